//! Meshed cracks: cut a [`GridMesh`] along crack polylines that follow grid lines.
//!
//! A crack is represented in the FEA the classical way: the nodes along the crack
//! are duplicated so the elements above and below use different nodes and the
//! faces open freely (traction-free crack faces, e.g. Cook et al. 2002, ch. 7 on
//! crack modelling). The crack-tip node is *not* duplicated, so the crack closes there.
//!
//! The rule used to split a grid node is purely topological, so it needs no
//! special cases for tips, mouths, kinks or crossings: the up to four material
//! cells around the node are grouped into classes that are connected through
//! un-cut edges ending at the node; every class gets its own copy of the node.
//! * At an interior crack tip only one cut edge ends at the node, the ring of cells
//!   is still connected → one class → not split (a tip).
//! * Along the crack two cut edges end at the node → two classes → split.
//! * At the mouth of an edge crack (node on the body boundary) one cut edge plus the
//!   missing cells outside the body separate the ring → split (a mouth, not a tip).

use super::mesh::GridMesh;
use super::{FeaError, Result};
use crate::dim::Vector;

/// A crack tip found in the cut mesh: an end point of a crack polyline whose node was not split.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CrackTip {
    /// Which crack (index into the list given to [`GridMesh::cut_cracks`]).
    pub crack: usize,
    /// The mesh node at the tip (not duplicated).
    pub node: usize,
    /// Grid node (i, j) of the tip.
    pub grid_node: [usize; 2],
    /// Tip position.
    pub position: Vector,
    /// Unit vector of the crack-tip x1 axis: along the last crack segment, pointing
    /// from the crack into the uncracked material. The x2 axis is x1 rotated +90°.
    pub direction: Vector,
}

/// What cutting one crack produced.
#[derive(Clone, Debug, PartialEq)]
pub struct MeshedCrack {
    /// The polyline as given.
    pub points: Vec<Vector>,
    /// Tips at the first and the last point; `None` where that end is a mouth on the
    /// body boundary (or meets another crack), i.e. where its node was split.
    pub tips: [Option<CrackTip>; 2],
}

/// Relative tolerance (in cell sizes) for a crack point to count as a grid node.
const SNAP_TOL: f64 = 1e-9;

impl GridMesh {
    /// Cut the given crack polylines into the mesh (see the module doc).
    ///
    /// Every segment must be horizontal or vertical, lie on a grid line and start and end
    /// on grid nodes; anything else is a [`FeaError::CrackOffGrid`] naming the segment.
    pub fn cut_cracks(&mut self, cracks: &[Vec<Vector>]) -> Result<Vec<MeshedCrack>> {
        let g = self.grid;
        // cut_h[i + j nx]: edge (i, j)–(i+1, j); cut_v[i + j (nx+1)]: edge (i, j)–(i, j+1).
        let mut cut_h = vec![false; g.nx * (g.ny + 1)];
        let mut cut_v = vec![false; (g.nx + 1) * g.ny];
        let mut ends = Vec::with_capacity(cracks.len());
        for (c, pts) in cracks.iter().enumerate() {
            if pts.len() < 2 {
                return Err(FeaError::CrackTooShort { crack: c, n_points: pts.len() });
            }
            let mut first_last = [[0usize; 2]; 2];
            for s in 0..pts.len() - 1 {
                let (p, q) = (pts[s], pts[s + 1]);
                let off = |reason: &str| FeaError::CrackOffGrid {
                    crack: c,
                    segment: s,
                    x0: p.x,
                    y0: p.y,
                    x1: q.x,
                    y1: q.y,
                    reason: reason.to_string(),
                };
                let a = g.snap_to_node(p, SNAP_TOL).ok_or_else(|| off("the start point is not a grid node"))?;
                let b = g.snap_to_node(q, SNAP_TOL).ok_or_else(|| off("the end point is not a grid node"))?;
                if a == b {
                    return Err(off("the segment has zero length"));
                }
                if a.1 == b.1 {
                    let j = a.1;
                    for i in a.0.min(b.0)..a.0.max(b.0) {
                        cut_h[i + j * g.nx] = true;
                    }
                } else if a.0 == b.0 {
                    let i = a.0;
                    for j in a.1.min(b.1)..a.1.max(b.1) {
                        cut_v[i + j * (g.nx + 1)] = true;
                    }
                } else {
                    return Err(off(
                        "the segment is neither horizontal nor vertical, so it does not follow a grid line",
                    ));
                }
                if s == 0 {
                    first_last[0] = [a.0, a.1];
                }
                first_last[1] = [b.0, b.1];
            }
            ends.push(first_last);
        }

        // Split every grid node touched by a cut edge.
        let mut split_count = vec![1usize; (g.nx + 1) * (g.ny + 1)];
        for j in 0..=g.ny {
            for i in 0..=g.nx {
                // The four edges ending at the node, in ring order between the cells
                // SW–SE (below), SE–NE (right), NE–NW (above), NW–SW (left).
                let below = j > 0 && cut_v[i + (j - 1) * (g.nx + 1)];
                let right = i < g.nx && cut_h[i + j * g.nx];
                let above = j < g.ny && cut_v[i + j * (g.nx + 1)];
                let left = i > 0 && cut_h[(i - 1) + j * g.nx];
                if !(below || right || above || left) {
                    continue;
                }
                let (ii, jj) = (i as isize, j as isize);
                // Cells in ring order with the local corner index of node (i, j) in each.
                let ring = [
                    (self.element_at(ii - 1, jj - 1), 2usize), // SW
                    (self.element_at(ii, jj - 1), 3),          // SE
                    (self.element_at(ii, jj), 0),              // NE
                    (self.element_at(ii - 1, jj), 1),          // NW
                ];
                let shared_cut = [below, right, above, left]; // between ring[k] and ring[k+1]
                                                              // Connected classes around the ring (at most 4 members: simple relabelling).
                let mut class = [usize::MAX; 4];
                let mut n_class = 0;
                // Start right after a break (a cut edge or a missing cell) so a class never wraps.
                let start = (0..4)
                    .find(|&k| shared_cut[(k + 3) % 4] || ring[(k + 3) % 4].0.is_none() || ring[k].0.is_none())
                    .unwrap_or(0);
                for step in 0..4 {
                    let k = (start + step) % 4;
                    if ring[k].0.is_none() {
                        continue;
                    }
                    let prev = (k + 3) % 4;
                    let joined = step > 0 && ring[prev].0.is_some() && !shared_cut[prev];
                    class[k] = if joined { class[prev] } else { n_class };
                    if !joined {
                        n_class += 1;
                    }
                }
                // A closed ring with no break and ≥1 cut edge cannot happen (a cut is a break),
                // but a ring whose only break is a single cut edge is one class: the tip case.
                if n_class <= 1 {
                    continue;
                }
                split_count[g.node_index(i, j)] = n_class;
                // Class 0 keeps the existing node; the others get fresh copies.
                let original = ring.iter().find_map(|&(e, corner)| e.map(|e| self.mesh.elements[e][corner]));
                let Some(original) = original else { continue };
                let mut copies = vec![original];
                for _ in 1..n_class {
                    copies.push(self.mesh.nodes.len());
                    self.mesh.nodes.push(g.node_position(i, j));
                    self.node_grid.push([i, j]);
                }
                for k in 0..4 {
                    if let (Some(e), corner) = ring[k] {
                        self.mesh.elements[e][corner] = copies[class[k]];
                    }
                }
            }
        }

        // Report tips: crack ends whose node was not split and is a mesh node.
        let mut out = Vec::with_capacity(cracks.len());
        for (c, pts) in cracks.iter().enumerate() {
            let mut tips = [None, None];
            for (end, tip) in tips.iter_mut().enumerate() {
                let [i, j] = ends[c][end];
                if split_count[g.node_index(i, j)] != 1 {
                    continue;
                }
                let nodes = self.nodes_at(i, j);
                if nodes.len() != 1 {
                    continue;
                }
                let (tip_pt, prev_pt) =
                    if end == 0 { (pts[0], pts[1]) } else { (pts[pts.len() - 1], pts[pts.len() - 2]) };
                let d = tip_pt - prev_pt;
                *tip = Some(CrackTip {
                    crack: c,
                    node: nodes[0],
                    grid_node: [i, j],
                    position: g.node_position(i, j),
                    direction: d / d.norm(),
                });
            }
            out.push(MeshedCrack { points: pts.clone(), tips });
        }
        Ok(out)
    }
}
