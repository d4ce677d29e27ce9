//! The MPM material boundary in 3D (001 §2.3.3, Fig. 4) and the trimming of a moving
//! crack-front node at it.
//!
//! "In MPM, a material body is discretized into a set of particles. Although this
//! discretization does not explicitly track locations of boundaries, we can determine them
//! approximately along the grid lines with the aid of the gradient of extrapolated nodal
//! volume. We call these approximate boundaries the MPM material boundaries ... if a newly
//! generated crack-front reaches the MPM material boundaries, it will get trimmed at the
//! MPM material boundaries." (001 §2.3.3)
//!
//! As in 2D ([`crate::fracture::growth`]), the boundary is where the **relative volume**
//! of the front's material, V(x) = Σ_p V_p N(x_p − x) / (h_x h_y h_z) with the trilinear
//! hat N, falls to [`BOUNDARY_VOLUME`] = ½: V is 1 inside a body filled with particles, ½ on
//! a flat face, ¼ along an edge, ⅛ at a corner and 0 outside — the volume a grid node at x
//! would receive. A front node's move from → to that ends where V < ½ is cut back to the
//! last point of the segment with V ≥ ½ (bisection, V is continuous) and the node stops
//! there ("edge"); a move that starts outside does not happen.
//!
//! The particles are binned by cell once per growth check (a sort of (cell, particle)
//! pairs, O(N log N), no array over the grid's cells), so a query reads the 3 × 3 × 3 cells
//! around x; the sum is exact ([`ExactSum`]), so V does not depend on particle order.
//! Cost: O(N log N) to build, O(27 log N + particles in 27 cells) per query.

use crate::dim::Vector3;
use crate::exact::ExactSum;
use crate::fracture::growth::{last_inside, BOUNDARY_VOLUME};
use crate::grid::Grid3;

/// Particles binned by grid cell, for relative-volume queries.
///
/// Sparse: the (cell, particle) pairs sorted by cell, so building it costs
/// O(N log N) in the particles and nothing per grid cell (a growth check on a 10⁷-node
/// grid does not touch 10⁷ counters), and a cell's particles are found by binary search.
pub struct MaterialBoundary3 {
    grid: Grid3,
    /// Cell index of each binned particle, ascending; `order[i]` is the particle of `cells[i]`.
    cells: Vec<u64>,
    order: Vec<u32>,
    x: Vec<Vector3>,
    volume: Vec<f64>,
    material: Vec<u16>,
}

impl MaterialBoundary3 {
    /// Bin particles (position, current volume, material) by the cell holding them;
    /// particles outside the grid are left out (they cannot be: the step stops first).
    pub fn new(grid: &Grid3, x: &[Vector3], volume: &[f64], material: &[u16]) -> MaterialBoundary3 {
        let cell_of = |p: &Vector3| -> Option<u64> {
            let mut c = [0u64; 3];
            for d in 0..3 {
                let f = ((p[d] - grid.origin[d]) / grid.h[d]).floor();
                if !(f >= 0.0 && f < grid.n[d] as f64) {
                    return None;
                }
                c[d] = f as u64;
            }
            Some((c[2] * grid.n[1] as u64 + c[1]) * grid.n[0] as u64 + c[0])
        };
        // (cell, particle) keys are distinct, so the sort's order is unique.
        let mut pairs: Vec<(u64, u32)> = x.iter().enumerate().filter_map(|(i, p)| cell_of(p).map(|c| (c, i as u32))).collect();
        pairs.sort_unstable();
        let (cells, order) = pairs.into_iter().unzip();
        MaterialBoundary3 { grid: grid.clone(), cells, order, x: x.to_vec(), volume: volume.to_vec(), material: material.to_vec() }
    }

    /// The particles binned in cell `c`.
    fn in_cell(&self, c: u64) -> &[u32] {
        let lo = self.cells.partition_point(|&k| k < c);
        let hi = lo + self.cells[lo..].partition_point(|&k| k <= c);
        &self.order[lo..hi]
    }

    /// Relative volume of material `mat` at `x` (module doc).
    pub fn relative_volume(&self, mat: usize, x: Vector3) -> f64 {
        let g = &self.grid;
        let h = g.h;
        let mut sum = ExactSum::new();
        let mut lo = [0usize; 3];
        let mut hi = [0usize; 3];
        for d in 0..3 {
            let f = ((x[d] - g.origin[d]) / h[d]).floor();
            lo[d] = (f - 1.0).clamp(0.0, g.n[d] as f64 - 1.0) as usize;
            hi[d] = (f + 1.0).clamp(0.0, g.n[d] as f64 - 1.0) as usize;
        }
        for k in lo[2]..=hi[2] {
            for j in lo[1]..=hi[1] {
                for i in lo[0]..=hi[0] {
                    let c = ((k * g.n[1] + j) * g.n[0] + i) as u64;
                    for &p in self.in_cell(c) {
                        let p = p as usize;
                        if self.material[p] as usize != mat {
                            continue;
                        }
                        let dx = self.x[p] - x;
                        let w = (0..3).map(|d| 1.0 - dx[d].abs() / h[d]).fold(1.0, |a, b| if b > 0.0 { a * b } else { 0.0 });
                        if w > 0.0 {
                            sum.add(w * self.volume[p]);
                        }
                    }
                }
            }
        }
        sum.value() / (h.x * h.y * h.z)
    }

    /// The move of a front node from `from` toward `to` in material `mat`, trimmed at the
    /// material boundary: `(target, at_edge)`. `target == from` when `from` is itself
    /// outside (relative volume below ½): no move.
    pub fn trim(&self, mat: usize, from: Vector3, to: Vector3) -> (Vector3, bool) {
        trim_by(from, to, |x| self.relative_volume(mat, x))
    }
}

/// A move from → to trimmed where the relative volume `v` falls below ½ (module doc):
/// `(target, at_edge)`, `target == from` when `from` is outside.
pub fn trim_by(from: Vector3, to: Vector3, v: impl Fn(Vector3) -> f64) -> (Vector3, bool) {
    let inside = |x: Vector3| v(x) >= BOUNDARY_VOLUME;
    if inside(to) {
        return (to, false);
    }
    if !inside(from) {
        return (from, true);
    }
    let lo = last_inside(|t| inside(from + (to - from) * t));
    (from + (to - from) * lo, true)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A box [0, 4]³ of 2×2×2 particles per unit cell (volume 1/8 each) in a grid from −2
    /// to 6: V = 1 inside, ½ on a face, ¼ on an edge, ⅛ at a corner, 0 outside; a move
    /// leaving through the face x = 4 is trimmed at it.
    #[test]
    fn box_relative_volume_and_trim() {
        let grid = Grid3 { origin: Vector3::repeat(-2.0), h: Vector3::repeat(1.0), n: [8, 8, 8] };
        let mut x = Vec::new();
        for k in 0..8 {
            for j in 0..8 {
                for i in 0..8 {
                    x.push(Vector3::new(0.25 + 0.5 * i as f64, 0.25 + 0.5 * j as f64, 0.25 + 0.5 * k as f64));
                }
            }
        }
        let vol = vec![0.125; x.len()];
        let mat = vec![0u16; x.len()];
        let b = MaterialBoundary3::new(&grid, &x, &vol, &mat);
        let v = |p: [f64; 3]| b.relative_volume(0, Vector3::from(p));
        assert_eq!(v([2.0, 2.0, 2.0]), 1.0);
        assert_eq!(v([4.0, 2.0, 2.0]), 0.5);
        assert_eq!(v([4.0, 4.0, 2.0]), 0.25);
        assert_eq!(v([4.0, 4.0, 4.0]), 0.125);
        assert_eq!(v([5.0, 2.0, 2.0]), 0.0);
        assert_eq!(b.relative_volume(1, Vector3::new(2.0, 2.0, 2.0)), 0.0, "another material");
        let (t, edge) = b.trim(0, Vector3::new(3.5, 2.0, 2.0), Vector3::new(4.5, 2.0, 2.0));
        assert!(edge && (t.x - 4.0).abs() < 1e-9 && t.y == 2.0, "trimmed to {t:?}");
        let (t, edge) = b.trim(0, Vector3::new(2.0, 2.0, 2.0), Vector3::new(2.5, 2.0, 2.0));
        assert!(!edge && t.x == 2.5);
        let (t, edge) = b.trim(0, Vector3::new(4.5, 2.0, 2.0), Vector3::new(5.0, 2.0, 2.0));
        assert!(edge && t.x == 4.5, "a move from outside does not happen");
    }
}
