//! Meshed planar cracks in the hex8 mesh (node duplication on a grid plane) and J, K_I,
//! K_II, K_III at the front nodes by the 3D equivalent domain integral — the 3D forms of
//! [`super::crack`] and [`super::jintegral`].
//!
//! **Cutting.** A crack is a triangulated surface (vertices and triangles, the layout of
//! the MPM's 3D crack surfaces). The FEA meshes a crack only if every triangle lies in one
//! grid plane (the plane x_a = origin_a + k·h_a for one axis a); anything else is an error
//! naming the triangle. Like the MPM, which gives two velocity fields to every grid node
//! on the closed crack surface, the FEA duplicates every grid node of that plane lying
//! inside or on a triangle (and with material on both sides): the elements on the + side
//! of the plane take the new copy. The first grid nodes beyond the crack's edge stay
//! whole: they are the **front nodes** (a node of the plane, not split, with a split
//! in-plane neighbour). So a crack edge inside a cell is meshed at the next grid line,
//! the 2D rule ([`super::scene`]).
//!
//! **J at a front node** (Shih, Moran & Nakamura 1986, eqs. 21–23; Anderson 2005
//! §7.4.2): with the local frame e1 (in the crack plane, normal to the front, into the
//! material), e2 (crack-plane normal), e3 = e1 × e2 along the front,
//!
//! J̄ = ∫_V (σ_ij ∂u_i/∂x1 − W δ_1j) ∂q/∂x_j dV,  J = J̄ / ∫ ψ ds,
//!
//! q = φ ψ at the grid nodes: φ = 1 within `n` cells of the front node in the (e1, e2)
//! plane (Chebyshev distance), 0 beyond; ψ = 1 − |Δ3|/h3 the hat function of the node
//! along the front (one cell each way, cut at the body surface), so ∫ψ ds = h3 inside and
//! h3/2 at a front node on a free surface. Only fronts running along a grid axis are
//! evaluated (e1 along a grid axis); a front node where the front turns is skipped with
//! the reason. No body force, crack-face traction or thermal strain in the domain.
//!
//! **K** (3d-references.md §0): inside a body the near-front field is plane strain plus
//! antiplane shear, J = (1 − ν²)(K_I² + K_II²)/E + (1 + ν)K_III²/E; the mode split uses the
//! crack-face displacement jump Δu at the split node one cell behind the front:
//! K_II/K_I = Δu1/Δu2, K_III/K_I = (1 − ν) Δu3/Δu2, sign of K_I from Δu2.

use super::hex8::{self, GAUSS};
use super::mesh3::GridMesh3;
use super::solve3::{Model3, Solution3};
use super::{FeaError, Result};
use crate::dim::Vector3;
use nalgebra::Matrix3;
use std::collections::BTreeSet;

/// Relative tolerance (of the cell size) for "on a grid plane" and "inside a triangle".
const TOL: f64 = 1e-9;

/// A front node of a meshed crack.
#[derive(Clone, Debug, PartialEq)]
pub struct FrontNode {
    /// The mesh node (not duplicated).
    pub node: usize,
    pub grid_node: [usize; 3],
    pub position: Vector3,
    /// e1: in the crack plane, from the crack into the material (unit), if the front runs
    /// along a grid axis here; `None` where it turns (the node is skipped for J).
    pub direction: Option<Vector3>,
}

/// What cutting one crack produced.
#[derive(Clone, Debug, PartialEq)]
pub struct MeshedCrack3 {
    /// Axis a of the crack plane and its grid-plane index k (x_a = origin_a + k h_a).
    pub axis: usize,
    pub plane: usize,
    /// Flat grid indices of the split nodes (sorted).
    pub split: Vec<usize>,
    /// Front nodes in grid order.
    pub front: Vec<FrontNode>,
}

/// J and K at one front node for one domain.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct FrontJ {
    pub cells: usize,
    pub j: f64,
    pub k_i: f64,
    pub k_ii: f64,
    pub k_iii: f64,
    /// Crack-face jump (+ face − − face) one cell behind the front in (e1, e2, e3).
    pub cod: [f64; 3],
}

fn off(crack: usize, t: usize, reason: impl Into<String>) -> FeaError {
    FeaError::InvalidInput(format!(
        "cracks[{crack}], triangle {t}: {}; the 3D FEA meshes only planar cracks whose triangles lie in one grid \
         plane (x, y or z a whole number of cells from the grid origin)",
        reason.into()
    ))
}

/// 2D point-in-triangle test (inclusive, tolerance `tol` in the barycentric coordinates).
fn in_triangle(p: [f64; 2], t: [[f64; 2]; 3], tol: f64) -> bool {
    let d = (t[1][0] - t[0][0]) * (t[2][1] - t[0][1]) - (t[2][0] - t[0][0]) * (t[1][1] - t[0][1]);
    if d == 0.0 {
        return false;
    }
    let l1 = ((t[1][0] - p[0]) * (t[2][1] - p[1]) - (t[2][0] - p[0]) * (t[1][1] - p[1])) / d;
    let l2 = ((t[2][0] - p[0]) * (t[0][1] - p[1]) - (t[0][0] - p[0]) * (t[2][1] - p[1])) / d;
    let l3 = 1.0 - l1 - l2;
    l1 >= -tol && l2 >= -tol && l3 >= -tol
}

impl GridMesh3 {
    /// The grid plane (axis, index) of crack `c`'s triangles, or an error naming the triangle.
    fn crack_plane(&self, c: usize, vertices: &[Vector3], triangles: &[[u32; 3]]) -> Result<(usize, usize)> {
        let g = &self.grid;
        let mut plane = None;
        for (t, tri) in triangles.iter().enumerate() {
            let p = tri.map(|v| vertices.get(v as usize).copied());
            let [Some(a), Some(b), Some(d)] = p else { return Err(off(c, t, "a vertex index is out of range")) };
            let axes: Vec<usize> = (0..3).filter(|&k| (a[k] - b[k]).abs() <= TOL * g.h[k] && (a[k] - d[k]).abs() <= TOL * g.h[k]).collect();
            let [axis] = axes[..] else {
                return Err(off(c, t, if axes.is_empty() { "it is not parallel to a coordinate plane" } else { "it has zero area" }));
            };
            let s = (a[axis] - g.origin[axis]) / g.h[axis];
            if (s - s.round()).abs() > TOL * s.abs().max(1.0) || s.round() < 0.0 || s.round() > g.n[axis] as f64 {
                return Err(off(c, t, format!("its plane {} = {} lies between grid planes", ["x", "y", "z"][axis], a[axis])));
            }
            let here = (axis, s.round() as usize);
            if *plane.get_or_insert(here) != here {
                return Err(off(c, t, "the crack is not planar: its triangles lie in different grid planes"));
            }
        }
        plane.ok_or_else(|| FeaError::InvalidInput(format!("cracks[{c}] has no triangles")))
    }

    /// Cut one planar crack (see the module doc): duplicate the split nodes for the
    /// elements on the + side and find the front nodes. Cracks are cut one after another.
    pub fn cut_planar_crack(&mut self, c: usize, vertices: &[Vector3], triangles: &[[u32; 3]]) -> Result<MeshedCrack3> {
        let (axis, k0) = self.crack_plane(c, vertices, triangles)?;
        let (u, w) = ((axis + 1) % 3, (axis + 2) % 3);
        let g = self.grid.clone();
        let tris: Vec<[[f64; 2]; 3]> = triangles.iter().map(|t| t.map(|v| [vertices[v as usize][u], vertices[v as usize][w]])).collect();
        // Grid node (plane coordinates iu, iw) → flat index, and the elements on each side.
        let node_at = |iu: usize, iw: usize| {
            let mut ijk = [0; 3];
            ijk[axis] = k0;
            ijk[u] = iu;
            ijk[w] = iw;
            g.node_index(ijk[0], ijk[1], ijk[2])
        };
        // Elements around grid node (iu, iw) on the − side (cell index k0 − 1) and + side (k0).
        let sides = |gm: &GridMesh3, iu: usize, iw: usize| -> [Vec<(usize, usize)>; 2] {
            let mut out = [Vec::new(), Vec::new()];
            for (side, dk) in [(0usize, -1isize), (1, 0)] {
                for du in [-1isize, 0] {
                    for dw in [-1isize, 0] {
                        let mut cell = [0isize; 3];
                        cell[axis] = k0 as isize + dk;
                        cell[u] = iu as isize + du;
                        cell[w] = iw as isize + dw;
                        if let Some(e) = gm.element_at(cell) {
                            // Corner of this cell at the node.
                            let mut off3 = [0usize; 3];
                            off3[axis] = (-dk) as usize;
                            off3[u] = (-du) as usize;
                            off3[w] = (-dw) as usize;
                            let corner = super::mesh3::CELL_CORNERS.iter().position(|o| *o == off3).unwrap_or(0);
                            out[side].push((e, corner));
                        }
                    }
                }
            }
            out
        };
        let (nu, nw) = (g.n[u], g.n[w]);
        let mut split = BTreeSet::new();
        for iw in 0..=nw {
            for iu in 0..=nu {
                let p = [g.origin[u] + iu as f64 * g.h[u], g.origin[w] + iw as f64 * g.h[w]];
                let tol = TOL;
                if !tris.iter().any(|t| in_triangle(p, *t, tol)) {
                    continue;
                }
                let [below, above] = sides(self, iu, iw);
                if below.is_empty() || above.is_empty() {
                    continue;
                }
                let a = self.grid_node[node_at(iu, iw)];
                let copy = self.mesh.nodes.len();
                self.mesh.nodes.push(self.mesh.nodes[a]);
                self.node_grid.push(self.node_grid[a]);
                for (e, corner) in above {
                    self.mesh.elements[e][corner] = copy;
                }
                self.copies.entry(node_at(iu, iw)).or_default().push(copy);
                split.insert((iu, iw));
            }
        }
        // Front nodes: in the plane, not split, material on both sides, a split 4-neighbour.
        let mut front = Vec::new();
        for iw in 0..=nw {
            for iu in 0..=nu {
                if split.contains(&(iu, iw)) {
                    continue;
                }
                let [below, above] = sides(self, iu, iw);
                if below.is_empty() || above.is_empty() {
                    continue;
                }
                let mut dir = Vector3::zeros();
                let mut any = false;
                for (du, dw) in [(-1isize, 0isize), (1, 0), (0, -1), (0, 1)] {
                    let (ju, jw) = (iu as isize + du, iw as isize + dw);
                    if ju >= 0 && jw >= 0 && split.contains(&(ju as usize, jw as usize)) {
                        any = true;
                        dir -= Vector3::ith(u, du as f64) + Vector3::ith(w, dw as f64);
                    }
                }
                if !any {
                    continue;
                }
                // Along a grid axis when the split neighbours lie on one side only.
                let aligned = (dir[u] == 0.0) != (dir[w] == 0.0) && dir.norm() == 1.0;
                let gi = node_at(iu, iw);
                let node = self.grid_node[gi];
                front.push(FrontNode {
                    node,
                    grid_node: g.node_ijk(gi),
                    position: self.mesh.nodes[node],
                    direction: aligned.then_some(dir),
                });
            }
        }
        Ok(MeshedCrack3 { axis, plane: k0, split: split.iter().map(|&(iu, iw)| node_at(iu, iw)).collect(), front })
    }
}

/// J, K_I, K_II, K_III at front node `f` of crack `crack` for a domain of `cells` cells
/// (see the module doc). Errors if the domain leaves the body or the front turns here.
pub fn j_front(gm: &GridMesh3, model: &Model3, sol: &Solution3, crack: &MeshedCrack3, f: &FrontNode, cells: usize) -> Result<FrontJ> {
    let bad = |reason: String| FeaError::BadTip { x: f.position.x, y: f.position.y, reason: format!("front node at z = {}: {reason}", f.position.z) };
    let e1 = f.direction.ok_or_else(|| bad("the meshed front turns here (not along a grid axis); J is not evaluated".into()))?;
    if cells == 0 {
        return Err(FeaError::InvalidInput("a J domain needs at least 1 cell".into()));
    }
    let axis = crack.axis;
    let e2 = Vector3::ith(axis, 1.0);
    let e3 = e1.cross(&e2);
    let a1 = (0..3).find(|&k| e1[k] != 0.0).unwrap_or(0);
    let a3 = 3 - axis - a1;
    let g = &gm.grid;
    let n = cells as isize;
    let fi = f.grid_node.map(|v| v as isize);
    // Cells of the domain: within n + 1 cells of the node in the (e1, e2) plane, one cell
    // each way along e3. A side along e3 with no material at all (a free surface through
    // the front node, or the grid's end) cuts the hat there; otherwise every cell must be
    // material of one group.
    let mut group = None;
    let mut cells_in = Vec::new();
    let mut psi_len = 0.0;
    for d3 in [-1isize, 0] {
        let side: Vec<Option<usize>> = (-n - 1..n + 1)
            .flat_map(|d1| (-n - 1..n + 1).map(move |d2| (d1, d2)))
            .map(|(d1, d2)| {
                let mut c = [0isize; 3];
                c[a1] = fi[a1] + d1;
                c[axis] = fi[axis] + d2;
                c[a3] = fi[a3] + d3;
                gm.element_at(c)
            })
            .collect();
        if side.iter().all(Option::is_none) {
            continue;
        }
        if side.iter().any(Option::is_none) {
            return Err(bad(format!("the J domain of {cells} cell(s) leaves the body; use a smaller domain")));
        }
        for e in side.into_iter().flatten() {
            let grp = model.group(e);
            if *group.get_or_insert(grp) != grp {
                return Err(bad(format!("the J domain of {cells} cell(s) crosses a material change")));
            }
            cells_in.push(e);
        }
        psi_len += 0.5 * g.h[a3];
    }
    if cells_in.is_empty() {
        return Err(bad("no material around this node".into()));
    }
    let material = model.material(cells_in[0]);
    let rot = Matrix3::from_rows(&[e1.transpose(), e2.transpose(), e3.transpose()]);
    let q_node = |a: usize| -> Vector3 {
        let d = gm.node_grid[a].map(|v| v as isize);
        let (d1, d2, d3) = (d[a1] - fi[a1], d[axis] - fi[axis], d[a3] - fi[a3]);
        if d1.abs().max(d2.abs()) <= n && d3.abs() == 0 {
            e1
        } else {
            Vector3::zeros()
        }
    };
    let jbar = domain_integral(gm, sol, &cells_in, q_node)?;
    let j = jbar / psi_len;
    // Crack-face jump one cell behind the front node.
    let mut behind = f.grid_node;
    behind[a1] = (fi[a1] - e1[a1] as isize) as usize;
    let gb = g.node_index(behind[0], behind[1], behind[2]);
    let lower = gm.grid_node[gb];
    let upper = gm.copies.get(&gb).and_then(|c| c.first().copied());
    let cod = match upper {
        Some(up) if lower != usize::MAX => rot * (sol.displacement[up] - sol.displacement[lower]),
        _ => return Err(bad("no split node one cell behind the front".into())),
    };
    let (e, nu) = (material.e, material.nu);
    let jp = j.max(0.0);
    let (r2, r3) = if cod.y != 0.0 { (cod.x / cod.y, (1.0 - nu) * cod.z / cod.y) } else { (0.0, 0.0) };
    let k_i = cod.y.signum() * (jp * e / ((1.0 - nu * nu) * (1.0 + r2 * r2) + (1.0 + nu) * r3 * r3)).sqrt();
    Ok(FrontJ { cells, j, k_i, k_ii: r2 * k_i, k_iii: r3 * k_i, cod: [cod.x, cod.y, cod.z] })
}

/// The 3D equivalent domain integral for a virtual crack extension given as a vector at
/// every mesh node (Shih, Moran & Nakamura 1986, eq. 21, with the extension direction
/// inside q; deLorenzi 1982): q interpolated with the hex8 shape functions,
///
/// J̄ = ∫_V (σ_ij ∂u_i/∂x_k − W δ_jk) ∂q_k/∂x_j dV,
///
/// summed with the 2×2×2 Gauss rule over `elements` (every element where q is not
/// identically 0 must be in the list). For the FE fields this is the derivative of the
/// discrete potential energy with respect to moving the nodes by q (deLorenzi's
/// equivalence), so J̄ = ∫ G(s) q(s)·ν(s) ds along the front when q vanishes on the outer
/// boundary of the domain, is tangent to every symmetry plane and the crack faces in the
/// domain carry no traction. No body force, crack-face traction or thermal strain.
pub fn domain_integral(gm: &GridMesh3, sol: &Solution3, elements: &[usize], q_node: impl Fn(usize) -> Vector3) -> Result<f64> {
    let mut jbar = 0.0;
    for &e in elements {
        let conn = gm.mesh.elements[e];
        let q = conn.map(&q_node);
        if q.iter().all(|v| *v == Vector3::zeros()) {
            continue;
        }
        let x = gm.mesh.element_coords(e);
        let u = conn.map(|a| sol.displacement[a]);
        for (gp, xi) in GAUSS.iter().enumerate() {
            let p = hex8::point_data(&x, *xi).map_err(|det_j| FeaError::BadElement { element: e, gauss: gp, det_j })?;
            // grad_q[(k, j)] = ∂q_k/∂x_j, h[(i, k)] = ∂u_i/∂x_k.
            let grad_q = (0..8).fold(Matrix3::zeros(), |s, a| s + q[a] * p.grad_n[a].transpose());
            let h = hex8::displacement_gradient(&p.grad_n, &u);
            let s = sol.gauss_stress[e][gp];
            let sig = s.to_tensor();
            let w = 0.5 * crate::dim::SymOps::ddot(&s, &sol.gauss_strain[e][gp]);
            // σ_ij u_i,k q_k,j = tr(σ H grad_q) (σ symmetric); W δ_jk q_k,j = W tr(grad_q).
            jbar += ((sig * h * grad_q).trace() - w * grad_q.trace()) * p.det_j;
        }
    }
    Ok(jbar)
}
