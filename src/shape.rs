//! Shape functions: classic bilinear MPM and uGIMP (undeformed-domain GIMP,
//! Bardenhagen & Kober 2004). Eq. 24 of Nairn 2003: S_{i,p} = N_i(x_p), G_{i,p} = ∇N_i(x_p).
//!
//! Both are tensor products of 1D functions of the signed distance ξ = x_p − x_i, and
//! both are written as functions of |ξ| with the sign applied to the gradient only, so a
//! particle mirrored about a grid line gets mirrored weights to the bit.

use crate::dim::Vector;
use crate::grid::Grid;
use serde::{Deserialize, Serialize};

/// Which shape functions the scene uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ShapeKind {
    /// Bilinear shape functions of the cell that holds the particle (4 nodes in 2D).
    Linear,
    /// uGIMP: the particle's undeformed domain (half-width l_p per direction) convolved
    /// with the bilinear functions (up to 3×3 nodes in 2D).
    Ugimp,
}

/// Most nodes a particle can touch: 3 per direction for uGIMP.
pub const MAX_NODES: usize = 9;

/// The nodes a particle interacts with, their weights S and gradients G.
#[derive(Clone, Copy, Debug)]
pub struct Weights {
    pub n: usize,
    pub node: [u32; MAX_NODES],
    pub s: [f64; MAX_NODES],
    pub g: [Vector; MAX_NODES],
}

/// 1D linear hat: value and derivative at signed distance xi, cell size h. At the kink
/// (a particle exactly on the node) the derivative is the average of the one-sided
/// ones, 0, so the gradients still sum to zero over the nodes with non-zero weight
/// (the neighbours, at distance h, have zero weight and are dropped) and a mirrored
/// particle still gets mirrored bits.
#[inline]
fn linear_1d(xi: f64, h: f64) -> (f64, f64) {
    let a = xi.abs();
    if a >= h {
        return (0.0, 0.0);
    }
    if a == 0.0 {
        return (1.0, 0.0);
    }
    let sgn = if xi < 0.0 { -1.0 } else { 1.0 };
    (1.0 - a / h, -sgn / h)
}

/// 1D uGIMP function (Bardenhagen & Kober 2004, eq. for the constant particle
/// characteristic function of half-width lp ≤ h/2 convolved with the hat).
#[inline]
fn ugimp_1d(xi: f64, h: f64, lp: f64) -> (f64, f64) {
    let a = xi.abs();
    let sgn = if xi < 0.0 { -1.0 } else { 1.0 };
    if a < lp {
        (1.0 - (a * a + lp * lp) / (2.0 * h * lp), -xi / (h * lp))
    } else if a <= h - lp {
        (1.0 - a / h, -sgn / h)
    } else if a < h + lp {
        let d = h + lp - a;
        (d * d / (4.0 * h * lp), -sgn * d / (2.0 * h * lp))
    } else {
        (0.0, 0.0)
    }
}

/// Range of node indices (along one axis) whose support can contain coordinate `x`:
/// returns (first index, count). `reach` is the support half-width minus the cell size
/// (0 for linear, lp for uGIMP).
#[inline]
fn node_range(x: f64, x0: f64, h: f64, reach: f64, n_cells: usize) -> (isize, usize) {
    let lo = floor_to_isize((x - reach - x0) / h);
    let hi = floor_to_isize((x + reach - x0) / h) + 1;
    let lo = lo.max(0);
    let hi = hi.min(n_cells as isize);
    (lo, (hi - lo + 1).max(0) as usize)
}

/// ⌊v⌋ as an integer, the same as `v.floor() as isize` for every v (NaN gives 0, and
/// values beyond ±2^63 saturate, as the cast does), without the call to libm's software
/// `floor` that the baseline x86-64 target needs: truncate, then step down for a negative
/// non-integer.
#[inline]
fn floor_to_isize(v: f64) -> isize {
    let t = v as isize;
    if (t as f64) > v && t != isize::MIN {
        t - 1
    } else {
        t
    }
}

/// The non-zero 1D weights (value, derivative) along one axis and their node indices;
/// returns how many.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn axis_weights(
    kind: ShapeKind,
    x: f64,
    x0: f64,
    h: f64,
    reach: f64,
    lp: f64,
    n_cells: usize,
    out: &mut [(f64, f64); 3],
    idx: &mut [usize; 3],
) -> usize {
    let (i0, count) = node_range(x, x0, h, reach, n_cells);
    let mut k = 0;
    for a in 0..count.min(3) {
        let i = (i0 as usize) + a;
        let xi = x - (x0 + i as f64 * h);
        let v = match kind {
            ShapeKind::Linear => linear_1d(xi, h),
            ShapeKind::Ugimp => ugimp_1d(xi, h, lp),
        };
        if v.0 != 0.0 {
            out[k] = v;
            idx[k] = i;
            k += 1;
        }
    }
    k
}

/// Weights of particle at `x` (half-widths `lp` for uGIMP). Nodes with zero weight
/// are dropped. Caller guarantees the particle is inside the grid (checked mode does).
pub fn weights(grid: &Grid, kind: ShapeKind, x: &Vector, lp: &Vector) -> Weights {
    let mut w = Weights { n: 0, node: [0; MAX_NODES], s: [0.0; MAX_NODES], g: [Vector::zeros(); MAX_NODES] };
    w.n = weights_into(grid, kind, x, lp, &mut w.node, &mut w.s, &mut w.g);
    w
}

/// [`weights`] written straight into the first entries of `node`, `s` and `g` (the
/// particle's stride of the pair arrays); returns how many.
#[inline(always)]
pub fn weights_into(
    grid: &Grid,
    kind: ShapeKind,
    x: &Vector,
    lp: &Vector,
    node: &mut [u32; MAX_NODES],
    s: &mut [f64; MAX_NODES],
    g: &mut [Vector; MAX_NODES],
) -> usize {
    let (rx, ry) = match kind {
        ShapeKind::Linear => (0.0, 0.0),
        ShapeKind::Ugimp => (lp.x, lp.y),
    };
    let mut sx = [(0.0, 0.0); 3];
    let mut sy = [(0.0, 0.0); 3];
    let mut nx_idx = [0usize; 3];
    let mut ny_idx = [0usize; 3];
    let kx = axis_weights(kind, x.x, grid.origin.x, grid.h.x, rx, lp.x, grid.nx, &mut sx, &mut nx_idx);
    let ky = axis_weights(kind, x.y, grid.origin.y, grid.h.y, ry, lp.y, grid.ny, &mut sy, &mut ny_idx);
    let mut k = 0;
    for b in 0..ky {
        for a in 0..kx {
            node[k] = grid.node_index(nx_idx[a], ny_idx[b]) as u32;
            s[k] = sx[a].0 * sy[b].0;
            g[k] = Vector::new(sx[a].1 * sy[b].0, sx[a].0 * sy[b].1);
            k += 1;
        }
    }
    k
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid() -> Grid {
        Grid { origin: Vector::new(-2.0, -3.0), h: Vector::new(0.5, 0.25), nx: 20, ny: 40 }
    }

    #[test]
    fn partition_of_unity_and_zero_gradient_sum() {
        let g = grid();
        let lp = Vector::new(0.125, 0.0625);
        for kind in [ShapeKind::Linear, ShapeKind::Ugimp] {
            for k in 0..500 {
                let x = Vector::new(-1.0 + 0.0137 * k as f64, -2.0 + 0.0091 * k as f64);
                let w = weights(&g, kind, &x, &lp);
                let s: f64 = w.s[..w.n].iter().sum();
                let gs: Vector = w.g[..w.n].iter().sum();
                assert!((s - 1.0).abs() < 1e-14, "{kind:?} at {x:?}: ΣS = {s}");
                assert!(gs.norm() < 1e-12, "{kind:?} at {x:?}: ΣG = {gs:?}");
            }
        }
    }

    #[test]
    fn gradient_matches_finite_difference() {
        let g = grid();
        let lp = Vector::new(0.125, 0.0625);
        let x = Vector::new(0.3311, 0.1093);
        for kind in [ShapeKind::Linear, ShapeKind::Ugimp] {
            let w = weights(&g, kind, &x, &lp);
            let e = 1e-7;
            for k in 0..w.n {
                let node = w.node[k];
                let val = |p: Vector| {
                    let ww = weights(&g, kind, &p, &lp);
                    (0..ww.n).find(|&j| ww.node[j] == node).map(|j| ww.s[j]).unwrap_or(0.0)
                };
                let dx = (val(x + Vector::new(e, 0.0)) - val(x - Vector::new(e, 0.0))) / (2.0 * e);
                let dy = (val(x + Vector::new(0.0, e)) - val(x - Vector::new(0.0, e))) / (2.0 * e);
                assert!((dx - w.g[k].x).abs() < 1e-6 && (dy - w.g[k].y).abs() < 1e-6);
            }
        }
    }

    #[test]
    fn integer_floor_matches_floor() {
        let cases = [0.0, -0.0, 0.5, -0.5, 1.0, -1.0, 2.9999999999999996, -2.0000000000000004, 1e15 + 0.5, -1e15 - 0.5, 4503599627370497.0, -7.25, 1e-300, -1e-300];
        for v in cases {
            assert_eq!(floor_to_isize(v), v.floor() as isize, "{v}");
        }
        assert_eq!(floor_to_isize(f64::NAN), f64::NAN.floor() as isize);
        assert_eq!(floor_to_isize(1e300), 1e300f64.floor() as isize);
        assert_eq!(floor_to_isize(-1e300), (-1e300f64).floor() as isize);
    }

    #[test]
    fn mirrored_particle_gets_mirrored_weights_bitwise() {
        // Grid symmetric about y = 0 (a grid line).
        let g = Grid { origin: Vector::new(0.0, -4.0), h: Vector::new(1.0, 1.0), nx: 8, ny: 8 };
        let lp = Vector::new(0.25, 0.25);
        for kind in [ShapeKind::Linear, ShapeKind::Ugimp] {
            let a = weights(&g, kind, &Vector::new(3.3, 0.37), &lp);
            let b = weights(&g, kind, &Vector::new(3.3, -0.37), &lp);
            assert_eq!(a.n, b.n);
            for k in 0..a.n {
                let p = g.node_pos(a.node[k] as usize);
                let j = (0..b.n).find(|&j| g.node_pos(b.node[j] as usize) == Vector::new(p.x, -p.y)).unwrap();
                assert_eq!(a.s[k].to_bits(), b.s[j].to_bits());
                assert_eq!(a.g[k].x.to_bits(), b.g[j].x.to_bits());
                assert_eq!(a.g[k].y.to_bits(), (-b.g[j].y).to_bits());
            }
        }
    }
}
