//! Shape functions: classic bilinear MPM and uGIMP (undeformed-domain GIMP,
//! Bardenhagen & Kober 2004). Eq. 24 of Nairn 2003: S_{i,p} = N_i(x_p), G_{i,p} = ∇N_i(x_p).
//!
//! Both are tensor products of 1D functions of the signed distance ξ = x_p − x_i, and
//! both are written as functions of |ξ| with the sign applied to the gradient only, so a
//! particle mirrored about a grid line gets mirrored weights to the bit; and the nodes
//! kept are those with a non-zero weight, decided the same way (`axis_weights`), so it gets
//! the mirrored nodes too.

use crate::dim::{Vector, Vector3};
use crate::grid::{Grid, Grid3};
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

/// Most nodes a particle can touch in 2D: 3 per direction for uGIMP
/// (`<D2 as Space>::MAX_NODES`).
pub const MAX_NODES: usize = 9;

/// Most nodes a particle can touch in 3D: 3 per direction for uGIMP.
pub const MAX_NODES_3D: usize = 27;

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

/// How near an integer a quotient of [`axis_weights`] must be for the neighbouring node to
/// be a candidate too.
pub(crate) const EDGE: f64 = 1e-6;

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
    // The nodes whose support can hold x: ⌊(x − reach − x0)/h⌋ … ⌊(x + reach − x0)/h⌋ + 1.
    // These quotients round differently for a particle and its mirror image about a grid
    // plane, so a node at the very edge of the support (|ξ| within round-off of h + reach,
    // weight ≈ 0 but not 0) could be found on one side and missed on the other. So when a
    // quotient lies within round-off of an integer, the neighbouring node is a candidate
    // too, and the weight functions, which decide from |ξ| alone and mirror exactly, keep
    // the nodes with a non-zero weight (at most 3: the support is at most 3h wide).
    let (ql, qh) = ((x - reach - x0) / h, (x + reach - x0) / h);
    let (lo, hi) = (floor_to_isize(ql), floor_to_isize(qh) + 1);
    // The quotients' round-off is a few ulps of n_cells, far below EDGE.
    let first = if ql - (lo as f64) < EDGE { lo - 1 } else { lo }.max(0);
    let last = if qh - ((hi - 1) as f64) > 1.0 - EDGE { hi + 1 } else { hi }.min(n_cells as isize);
    let mut k = 0;
    // An exclusive range: `first..=last` iterates with an extra exhaustion flag per step.
    for i in first..last + 1 {
        if k == 3 {
            break;
        }
        let i = i as usize;
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

/// The 3D weights (trilinear or uGIMP, the tensor product of the same 1D functions as
/// in 2D) written into the first entries of `node`, `s` and `g`; returns how many. Nodes
/// run x fastest, then y, then z. S = (Sx·Sy)·Sz and G = (S'x·Sy·Sz, Sx·S'y·Sz, Sx·Sy·S'z):
/// a fixed grouping, so a particle mirrored about a grid plane gets mirrored bits.
#[inline(always)]
pub fn weights_into_3d(
    grid: &Grid3,
    kind: ShapeKind,
    x: &Vector3,
    lp: &Vector3,
    node: &mut [u32; MAX_NODES_3D],
    s: &mut [f64; MAX_NODES_3D],
    g: &mut [Vector3; MAX_NODES_3D],
) -> usize {
    let reach = match kind {
        ShapeKind::Linear => Vector3::zeros(),
        ShapeKind::Ugimp => *lp,
    };
    let mut w = [[(0.0, 0.0); 3]; 3];
    let mut idx = [[0usize; 3]; 3];
    let mut k = [0usize; 3];
    for c in 0..3 {
        k[c] = axis_weights(kind, x[c], grid.origin[c], grid.h[c], reach[c], lp[c], grid.n[c], &mut w[c], &mut idx[c]);
    }
    tensor_product_3d(grid, &w, &idx, k, node, s, g)
}

/// The nodes, S and G of [`weights_into_3d`] from the 1D weights (value, derivative) `w`
/// and node indices `idx` per axis, `k` of each (the tensor product; shared with the AVX2
/// 1D weights of `gather3::weights_ugimp`, so both give the same bits).
#[inline(always)]
pub(crate) fn tensor_product_3d(
    grid: &Grid3,
    w: &[[(f64, f64); 3]; 3],
    idx: &[[usize; 3]; 3],
    k: [usize; 3],
    node: &mut [u32; MAX_NODES_3D],
    s: &mut [f64; MAX_NODES_3D],
    g: &mut [Vector3; MAX_NODES_3D],
) -> usize {
    // Node indices ix + (nx+1)·iy + (nx+1)(ny+1)·iz (`Grid3::node_index`), the row part
    // once per (y, z) row.
    let (sy_stride, sz_stride) = (grid.n[0] + 1, (grid.n[0] + 1) * (grid.n[1] + 1));
    let (kx, ky, kz) = (k[0].min(3), k[1].min(3), k[2].min(3));
    let mut n = 0;
    for cz in 0..kz {
        let (sz, dz) = w[2][cz];
        let zbase = idx[2][cz] * sz_stride;
        for b in 0..ky {
            let (sy, dy) = w[1][b];
            let base = zbase + idx[1][b] * sy_stride;
            for a in 0..kx {
                let (sx, dx) = w[0][a];
                let sxy = sx * sy;
                node[n] = (base + idx[0][a]) as u32;
                s[n] = sxy * sz;
                g[n] = Vector3::new((dx * sy) * sz, (sx * dy) * sz, sxy * dz);
                n += 1;
            }
        }
    }
    n
}

/// [`weights_into_3d`]'s nodes and values S of the linear shape functions, without the
/// gradients (the same operations on the same operands, so the same bits).
#[inline(always)]
pub fn linear_weights_3d(grid: &Grid3, x: &Vector3, node: &mut [u32; MAX_NODES_3D], s: &mut [f64; MAX_NODES_3D]) -> usize {
    let mut w = [[(0.0, 0.0); 3]; 3];
    let mut idx = [[0usize; 3]; 3];
    let mut k = [0usize; 3];
    for c in 0..3 {
        k[c] = axis_weights(ShapeKind::Linear, x[c], grid.origin[c], grid.h[c], 0.0, 0.0, grid.n[c], &mut w[c], &mut idx[c]);
    }
    let mut n = 0;
    for cz in 0..k[2] {
        let sz = w[2][cz].0;
        for b in 0..k[1] {
            let sy = w[1][b].0;
            for a in 0..k[0] {
                let sx = w[0][a].0;
                node[n] = grid.node_index(idx[0][a], idx[1][b], idx[2][cz]) as u32;
                s[n] = (sx * sy) * sz;
                n += 1;
            }
        }
    }
    n
}

/// [`weights_into_3d`] as a value (tests, J contours).
pub fn weights_3d(grid: &Grid3, kind: ShapeKind, x: &Vector3, lp: &Vector3) -> (usize, [u32; MAX_NODES_3D], [f64; MAX_NODES_3D], [Vector3; MAX_NODES_3D]) {
    let (mut node, mut s, mut g) = ([0; MAX_NODES_3D], [0.0; MAX_NODES_3D], [Vector3::zeros(); MAX_NODES_3D]);
    let n = weights_into_3d(grid, kind, x, lp, &mut node, &mut s, &mut g);
    (n, node, s, g)
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

    #[test]
    fn partition_of_unity_3d_and_extrusion_of_2d() {
        let g3 = Grid3 { origin: Vector3::new(-2.0, -3.0, 1.0), h: Vector3::new(0.5, 0.25, 0.4), n: [20, 40, 10] };
        let g2 = Grid { origin: Vector::new(-2.0, -3.0), h: Vector::new(0.5, 0.25), nx: 20, ny: 40 };
        let lp = Vector3::new(0.125, 0.0625, 0.1);
        for kind in [ShapeKind::Linear, ShapeKind::Ugimp] {
            for k in 0..400 {
                let x = Vector3::new(-1.0 + 0.0137 * k as f64, -2.0 + 0.0091 * k as f64, 2.0 + 0.0049 * k as f64);
                let (n, node, s, g) = weights_3d(&g3, kind, &x, &lp);
                let ss: f64 = s[..n].iter().sum();
                let gs: Vector3 = g[..n].iter().sum();
                assert!((ss - 1.0).abs() < 1e-14, "{kind:?} at {x:?}: ΣS = {ss}");
                assert!(gs.norm() < 1e-12, "{kind:?} at {x:?}: ΣG = {gs:?}");
                // Summed over z, the 3D weights are the 2D ones (tensor product).
                let w2 = weights(&g2, kind, &Vector::new(x.x, x.y), &Vector::new(lp.x, lp.y));
                for j in 0..w2.n {
                    let (ix, iy) = g2.node_ij(w2.node[j] as usize);
                    let col: f64 = (0..n).filter(|&m| {
                        let [a, b, _] = g3.node_ijk(node[m] as usize);
                        a == ix && b == iy
                    }).map(|m| s[m]).sum();
                    assert!((col - w2.s[j]).abs() < 1e-14);
                }
            }
        }
    }

    #[test]
    fn gradient_matches_finite_difference_3d() {
        let g3 = Grid3 { origin: Vector3::new(0.0, 0.0, 0.0), h: Vector3::new(0.5, 0.25, 0.4), n: [20, 40, 10] };
        let lp = Vector3::new(0.125, 0.0625, 0.1);
        let x = Vector3::new(3.3311, 2.1093, 1.777);
        for kind in [ShapeKind::Linear, ShapeKind::Ugimp] {
            let (n, node, _, g) = weights_3d(&g3, kind, &x, &lp);
            let e = 1e-7;
            for k in 0..n {
                let val = |p: Vector3| {
                    let (nn, nd, ss, _) = weights_3d(&g3, kind, &p, &lp);
                    (0..nn).find(|&j| nd[j] == node[k]).map(|j| ss[j]).unwrap_or(0.0)
                };
                for c in 0..3 {
                    let mut d = Vector3::zeros();
                    d[c] = e;
                    let fd = (val(x + d) - val(x - d)) / (2.0 * e);
                    assert!((fd - g[k][c]).abs() < 1e-6, "{kind:?} node {k} comp {c}: {fd} vs {}", g[k][c]);
                }
            }
        }
    }
}
