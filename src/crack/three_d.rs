//! 3D explicit cracks (001 §2.1): triangulated crack surfaces of massless crack particles,
//! the velocity field of every particle–node pair by the exact segment–triangle crossing
//! of [`crossing3`] (Task 1), crack motion in the centre-of-mass velocity and the two crack
//! surfaces moved in their own sides' fields (Task 7; 001 eqs. 11–12 in 3D), and the
//! checked-mode test that no particle crosses a crack. Contact is dimension-generic
//! ([`crate::contact`]); the node normal it uses is formed here.
//!
//! "In 3D CRAMP a crack is discretized into a set of triangular elements instead of line
//! segments, but otherwise the 3D algorithm is essentially the same as the 2D one" (001
//! §2.1): each function below is the 2D one of [`crate::crack`] with triangles for
//! segments.

use super::crossing3::{distance_2, projects_into, side_of_plane, Crossing3, Side3, SurfaceView, TriangleIndex};
use super::surface::TriangleSurface;
use super::{ContactDetection, ContactLaw};
use crate::check::CheckError;
use crate::dim::{GridGeometry, Space, Vector3, D3};
use crate::exact::{Accumulator, ExactSums, FastSum};
use crate::shape::ShapeKind;
use crate::simulation::Simulation;
use rayon::prelude::*;

/// One 3D crack: its surface (the vertices are the crack particles), the two crack
/// surfaces (the "above" and "below" positions of every crack particle), its contact law,
/// and its front.
#[derive(Clone, Debug, PartialEq)]
pub struct Crack3 {
    pub surface: TriangleSurface,
    /// Upper-surface position of each crack particle (moved in the "above" fields).
    pub above: Vec<Vector3>,
    /// Lower-surface position of each crack particle (moved in the "below" fields).
    pub below: Vec<Vector3>,
    pub contact: ContactLaw,
    pub v_sep: f64,
    pub v_contact: f64,
    pub detection: ContactDetection,
    /// Per triangle, which edges are on the surface's boundary; per vertex, whether it is.
    pub boundary_edge: Vec<[bool; 3]>,
    pub boundary_vertex: Vec<bool>,
    /// Crack-front edges: boundary edges with material beyond them (directed as in their
    /// triangle, so the surface is on their left seen from above).
    pub front: Vec<[u32; 2]>,
}

impl Crack3 {
    pub fn new(surface: TriangleSurface, contact: ContactLaw, v_sep: f64, v_contact: f64, front: Vec<[u32; 2]>) -> Crack3 {
        let (boundary_edge, boundary_vertex) = surface.boundary_flags();
        Crack3 {
            above: surface.vertices.clone(),
            below: surface.vertices.clone(),
            surface,
            contact,
            v_sep,
            v_contact,
            detection: ContactDetection::default(),
            boundary_edge,
            boundary_vertex,
            front,
        }
    }

    /// The view the crossing test reads.
    pub fn view(&self) -> SurfaceView<'_> {
        SurfaceView { points: &self.surface.vertices, triangles: &self.surface.triangles, boundary_edge: &self.boundary_edge, boundary_vertex: &self.boundary_vertex }
    }

    /// Crack-opening displacement at crack particle k: above − below.
    pub fn opening(&self, k: usize) -> Vector3 {
        self.above[k] - self.below[k]
    }
}

impl crate::contact::CrackFaces for Crack3 {
    fn law(&self) -> ContactLaw {
        self.contact
    }
    fn v_sep(&self) -> f64 {
        self.v_sep
    }
    fn v_contact(&self) -> f64 {
        self.v_contact
    }
    fn detection(&self) -> ContactDetection {
        self.detection
    }
}

/// The 3D crack machinery as the generic time step calls it.
impl crate::simulation::Dimension for D3 {
    type Crack = Crack3;
    type Growth = crate::fracture::growth3::Growth3;

    fn task1_cracks(sim: &mut Simulation<D3>) -> Result<(), CheckError> {
        assign_velocity_fields(sim)
    }
    fn finish_crack_nodes(sim: &mut Simulation<D3>) -> Result<(), CheckError> {
        finish_crack_nodes(sim)
    }
    fn contact_momenta(sim: &mut Simulation<D3>) -> Result<(), CheckError> {
        sim.apply_contact_to_momenta()
    }
    fn contact_updated_momenta(sim: &mut Simulation<D3>) -> Result<(), CheckError> {
        sim.apply_contact_to_updated_momenta()
    }
    /// The opening of the crack particles (above − below) interpolated at the point of
    /// the crack surface nearest the node (barycentric in its triangle), along −n.
    fn normal_gap(sim: &Simulation<D3>, c: usize, i: usize, n: Vector3) -> Option<f64> {
        let reach = 2.0 * sim.grid.h.max();
        let x = sim.grid.node_pos(i);
        let (t, w) = sim.scratch.crack_index3.get(c)?.nearest(&x, reach)?;
        let crack = &sim.cracks[c];
        let tri = crack.surface.triangles[t];
        let opening = (0..3).fold(Vector3::zeros(), |acc, j| acc + crack.opening(tri[j] as usize) * w[j]);
        Some(-opening.dot(&n))
    }
    fn task7_move_cracks(sim: &mut Simulation<D3>) {
        task7_move_cracks(sim)
    }
    fn grow_cracks(sim: &mut Simulation<D3>) -> Result<(), CheckError> {
        sim.grow_fronts().map_err(|error| CheckError::Growth { step: sim.step_count, error })
    }
    fn check_crack_sides(sim: &mut Simulation<D3>) -> Result<(), CheckError> {
        check_crack_sides(sim)
    }
    /// Per crack: the number of points, then every point, upper and lower surface point.
    fn crack_state_bits(cracks: &[Crack3]) -> Vec<u64> {
        let mut words = Vec::new();
        for c in cracks {
            words.push(c.surface.vertices.len() as u64);
            for pts in [&c.surface.vertices, &c.above, &c.below] {
                words.extend(pts.iter().flat_map(|q| [q.x.to_bits(), q.y.to_bits(), q.z.to_bits()]));
            }
        }
        words
    }
}

/// Bounding box of points.
fn bounds(points: &[Vector3]) -> (Vector3, Vector3) {
    points.iter().fold((Vector3::repeat(f64::INFINITY), Vector3::repeat(f64::NEG_INFINITY)), |(l, h), v| (l.inf(v), h.sup(v)))
}

/// Rebuild every crack's triangle index (buckets of one cell).
fn rebuild_indices(sim: &mut Simulation<D3>) {
    let h = sim.grid.min_h();
    let idx = &mut sim.scratch.crack_index3;
    idx.resize_with(sim.cracks.len(), Default::default);
    for (index, crack) in idx.iter_mut().zip(&sim.cracks) {
        index.rebuild(&crack.surface.vertices, &crack.surface.triangles, h);
    }
}

/// Task 1 with cracks: ν(p,i) for every pair by the exact crossing test, and the crack
/// that split each node (the 2D [`Simulation::assign_velocity_fields`] with triangles).
///
/// Screening, which changes no verdict (every pair gets [`Crossing3`]'s answer over all
/// triangles): a triangle can give a pair anything but a miss only if the segment from
/// particle to node meets the closed triangle ([`Crossing3::add`]), so only if the
/// triangle's bounding box meets the box B of the particle and all its nodes. A particle
/// whose reach h + l_p misses every crack's bounding box costs one box test per crack.
/// Near a crack, a triangle in an axis plane x_a = level whose plane has B on one side
/// (lo_a = level < hi_a or lo_a < level = hi_a; "one-sided") has every point of B, the
/// particle too, on that side or in the plane, so its only possible verdict is rule 3's
/// with the particle on that side: a node in the plane inside the closed triangle. Those
/// (node, triangle) pairs do not depend on the particle ([`crossing3::node_in_triangle`])
/// and are listed once per crack position ([`NodeOnIndex`]); of a node's, only the lowest
/// triangle with the particle off its plane counts (rule 4), with the particle's side of
/// its plane. The other triangles whose boxes meet B ("two-sided": oblique ones, and
/// axis-plane ones whose plane cuts B) take the general test: per B (the [`CellCache`];
/// consecutive particles of one cell often share B and their nodes) the bucket index lists
/// them with the exact side of their plane of every node where that is cheap (axis planes),
/// then per particle its exact side once, and each node whose side differs and whose
/// segment passes through the triangle's padded box. For an axis-plane triangle that is
/// two-sided too, a node in its plane can only get rule 3's verdict (the segment meets the
/// plane at the node alone), so it takes that from [`NodeOnIndex`] as above, and a node
/// strictly on the other side is tested only when the point where its segment meets the
/// plane lies in the padded box (the crossing points are computed once per particle and
/// plane, [`PlaneCrossings`]). When every triangle lies in an axis
/// plane and no plane cuts B ([`TriangleIndex::may_be_two_sided`]), there is no two-sided
/// triangle and the bucket query is skipped. The verdicts are accumulated per node in any
/// order ([`Crossing3`] does not depend on it), so the result is [`Crossing3`]'s over all
/// triangles, bit for bit the unscreened answer.
///
/// [`crossing3::node_in_triangle`]: super::crossing3::node_in_triangle
fn assign_velocity_fields(sim: &mut Simulation<D3>) -> Result<(), CheckError> {
    const STRIDE: usize = D3::MAX_NODES;
    rebuild_indices(sim);
    let grid = &sim.grid;
    let p = &sim.particles;
    let pairs = &mut sim.pairs;
    let scratch = &mut sim.scratch;
    let cracks = &sim.cracks;
    scratch.crack_node_on3.resize_with(cracks.len(), Default::default);
    for ((node_on, index), crack) in scratch.crack_node_on3.iter_mut().zip(&scratch.crack_index3).zip(cracks) {
        node_on.rebuild(grid, index, &crack.view());
    }
    let index = &scratch.crack_index3;
    let node_on = &scratch.crack_node_on3;
    scratch.pair_crack.resize(pairs.field.len(), 0);
    // As in 2D: a particle's nodes lie within h + l_p of it per axis (with round-off).
    let reach = (grid.h + p.lp.iter().fold(Vector3::zeros(), |a, l| a.sup(l))) * (1.0 + 1e-9);
    let (count, node) = (&pairs.count, &pairs.node);
    // One particle: its pairs' fields and cracks, and whether any pair is split.
    let one = |cache: &mut CellCache, nb: &mut NodeBox, i: usize, field: &mut [u8], pair_crack: &mut [u16]| -> bool {
        match <&mut [u8; STRIDE]>::try_from(&mut *field) {
            Ok(f) => *f = [0; STRIDE],
            Err(_) => field.fill(0),
        }
        let xp = p.x[i];
        if !index.iter().any(|index| index.box_meets_extent(&(xp - reach), &(xp + reach))) {
            return false;
        }
        let nodes = &node[i * STRIDE..i * STRIDE + count[i] as usize];
        // The nodes' positions and box (kept from the last particle with the same nodes).
        if nb.nodes != nodes {
            nb.nodes.clear();
            nb.nodes.extend_from_slice(nodes);
            (nb.lo, nb.hi) = (Vector3::repeat(f64::INFINITY), Vector3::repeat(f64::NEG_INFINITY));
            for (k, &ni) in nodes.iter().enumerate() {
                nb.x[k] = grid.node_pos(ni as usize);
                nb.lo = nb.lo.inf(&nb.x[k]);
                nb.hi = nb.hi.sup(&nb.x[k]);
            }
        }
        let (lo, hi) = (nb.lo.inf(&xp), nb.hi.sup(&xp));
        let xn = &nb.x[..nodes.len()];
        let mut split = false;
        for (c, crack) in cracks.iter().enumerate() {
            if !index[c].box_meets_extent(&lo, &hi) {
                continue;
            }
            let view = crack.view();
            // The two-sided triangles near B (none when no triangle plane can cut B).
            let near: &[NearTriangle] = if index[c].may_be_two_sided(&lo, &hi) {
                cache.prepare(c, &lo, &hi, nodes, xn, &index[c]);
                &cache.near
            } else {
                &[]
            };
            let holding = &node_on[c];
            if near.is_empty() && holding.is_empty() {
                continue;
            }
            // Two-sided triangles: the nodes on another side than the particle (all
            // nodes where their sides are not cached), with the particle's exact side.
            let all = (1u32 << xn.len()) - 1;
            let candidates = &mut cache.candidates;
            candidates.clear();
            let cross = &mut cache.cross;
            cross.plane = None;
            for e in near {
                let op = match e.axis {
                    Some((a, level, o)) => o * sign(xp[a] - level),
                    None => {
                        let v = view.triangles[e.t as usize].map(|q| &view.points[q as usize]);
                        side_of_plane(v[0], v[1], v[2], &xp)
                    }
                };
                // (An axis-plane triangle's nodes in its plane take rule 3's verdict from
                // [`NodeOnIndex`] below, two-sided or not: only the nodes strictly on the
                // other side can be crossed properly.)
                let other = match (e.axis.is_some(), op) {
                    (_, 0) => 0,
                    (false, _) => all,
                    (true, 1) => e.neg,
                    (true, _) => e.pos,
                };
                if other == 0 {
                    continue;
                }
                if let Some((a, level, _)) = e.axis {
                    // Skip the triangle when the crossing points of all the nodes on the
                    // other side miss its padded box.
                    if cross.plane != Some((a, level)) {
                        cross.set(a, level, &xp, xn);
                    }
                    let (b, c, [pl, ph]) = ((a + 1) % 3, (a + 2) % 3, &e.padded);
                    if cross.hi[0] < pl[b] || cross.lo[0] > ph[b] || cross.hi[1] < pl[c] || cross.lo[1] > ph[c] {
                        continue;
                    }
                }
                candidates.push(Candidate { padded: e.padded, t: e.t, op, other, pos: e.pos, axis: e.axis, ge: e.ge, le: e.le });
            }
            // Each candidate's verdicts for the nodes on its other side whose segment
            // from the particle meets its padded box (per axis from the box's distinct
            // node coordinates: the first test of [`TriangleIndex::segment_may_meet`],
            // exactly), accumulated per node (the verdict does not depend on the order).
            let pending = if candidates.is_empty() { 0 } else { (0..xn.len()).filter(|&k| field[k] == 0).fold(0u32, |m, k| m | 1 << k) };
            // (Default between uses: each written accumulator is taken below.)
            let accs = &mut cache.accs;
            let mut written = 0u32;
            for q in candidates.iter() {
                let mut m = q.other & pending;
                match q.axis {
                    // An axis-plane triangle x_a = level, node strictly on the other side:
                    // the segment meets the plane at one point X only, so it can meet the
                    // triangle only if X lies in its box. X is computed per node once per
                    // plane ([`PlaneCrossings`]), within a few ulps of the coordinates, far
                    // inside the padding (as for `segment_may_meet`), so no meeting segment
                    // is rejected.
                    Some((a, level, _)) => {
                        let (b, c) = ((a + 1) % 3, (a + 2) % 3);
                        if cross.plane != Some((a, level)) {
                            cross.set(a, level, &xp, xn);
                        }
                        while m != 0 {
                            let k = m.trailing_zeros() as usize;
                            m &= m - 1;
                            let xn = &xn[k];
                            let [xb, xc] = cross.x[k];
                            let [pl, ph] = &q.padded;
                            if xb >= pl[b] && xb <= ph[b] && xc >= pl[c] && xc <= ph[c] {
                                written |= 1 << k;
                                let on = if q.pos & 1 << k != 0 { 1 } else { -1 };
                                accs[k].add_with_sides(&view, q.t as usize, &xp, xn, q.op, on);
                            }
                        }
                    }
                    None => {
                        // The segment's box meets the padded box along axis a iff (x_p ≥ lo
                        // or x_n ≥ lo) and (x_p ≤ hi or x_n ≤ hi).
                        for a in 0..3 {
                            if xp[a] < q.padded[0][a] {
                                m &= q.ge[a];
                            }
                            if xp[a] > q.padded[1][a] {
                                m &= q.le[a];
                            }
                        }
                        while m != 0 {
                            let k = m.trailing_zeros() as usize;
                            m &= m - 1;
                            let xn = &xn[k];
                            let seg = [xp.inf(xn), xp.sup(xn)];
                            if TriangleIndex::segment_may_meet(&q.padded[0], &q.padded[1], &seg, &xp, xn) {
                                written |= 1 << k;
                                accs[k].add_with_side(&view, q.t as usize, &xp, xn, q.op);
                            }
                        }
                    }
                }
            }
            for (k, &ni) in nodes.iter().enumerate() {
                if field[k] != 0 {
                    continue;
                }
                // Axis-plane triangles: the lowest that holds the node in its plane and
                // closed area with the particle off its plane ([`NodeOnIndex`], in
                // increasing triangle index).
                let mut own = None;
                for t in holding.triangles_holding(ni) {
                    let Some((a, level, o)) = index[c].axis_plane(t as usize) else { continue };
                    let op = o * sign(xp[a] - level);
                    if op != 0 {
                        own = Some((t as usize, op));
                        break;
                    }
                }
                let side = if written & 1 << k != 0 {
                    let mut acc = std::mem::take(&mut accs[k]);
                    if let Some((t, op)) = own {
                        acc.add_node_on(t, op);
                    }
                    acc.side()
                } else {
                    // Rule 4 with the node on the surface and no proper crossing.
                    match own {
                        Some((_, 1)) => Side3::Above,
                        Some(_) => Side3::Below,
                        None => Side3::None,
                    }
                };
                if side != Side3::None {
                    field[k] = if side == Side3::Above { 1 } else { 2 };
                    pair_crack[k] = c as u16;
                    split = true;
                }
            }
        }
        split
    };
    // Chunks of particles (one closure call and one accumulator set per chunk).
    const CHUNK: usize = crate::step::PARTICLE_CHUNK;
    scratch.split.resize(pairs.field.len() / STRIDE, false);
    (pairs.field.par_chunks_mut(STRIDE * CHUNK), scratch.pair_crack.par_chunks_mut(STRIDE * CHUNK), scratch.split.par_chunks_mut(CHUNK))
        .into_par_iter()
        .enumerate()
        .for_each_init(<(CellCache, NodeBox)>::default, |(cache, nb), (chunk, (fields, pair_cracks, splits))| {
            for (j, ((field, pair_crack), split)) in fields.chunks_mut(STRIDE).zip(pair_cracks.chunks_mut(STRIDE)).zip(splits.iter_mut()).enumerate() {
                *split = one(cache, nb, chunk * CHUNK + j, field, pair_crack);
            }
        });
    super::record_node_cracks(sim).map_err(|(node, cracks)| too_many_fields(sim, node, cracks))
}

/// Per-thread scratch of Task 1: the two-sided triangles near the last box B of a particle
/// and its nodes (`key`: crack, corners of B, nodes; particles of one cell usually share
/// it), each with the nodes' sides of its plane; and the current particle's candidates.
#[derive(Default)]
struct CellCache {
    key: Option<(usize, Vector3, Vector3)>,
    nodes: Vec<u32>,
    /// Per axis, the distinct coordinates of the nodes, each with the nodes (bits) that
    /// have it (a comparison of a node's coordinate is made once per value).
    coords: [Vec<(f64, u32)>; 3],
    near: Vec<NearTriangle>,
    candidates: Vec<Candidate>,
    /// Per node position, the crossing verdicts of the current particle's candidates
    /// (default between particles).
    accs: [Crossing3; D3::MAX_NODES],
    /// The current particle's segments' crossing points with one axis plane.
    cross: PlaneCrossings,
}

/// Where the segments from the current particle to its nodes strictly on the other side
/// of the axis plane x_a = level (`plane`) meet that plane: per node position the two other
/// coordinates (axes a + 1, a + 2 mod 3) of the crossing point, and their box (`lo`, `hi`).
struct PlaneCrossings {
    plane: Option<(usize, f64)>,
    x: [[f64; 2]; D3::MAX_NODES],
    lo: [f64; 2],
    hi: [f64; 2],
}

impl Default for PlaneCrossings {
    fn default() -> Self {
        PlaneCrossings { plane: None, x: [[0.0; 2]; D3::MAX_NODES], lo: [f64::INFINITY; 2], hi: [f64::NEG_INFINITY; 2] }
    }
}

impl PlaneCrossings {
    /// The crossing points of the segments from particle `xp` to the nodes `xn` strictly on
    /// the other side of x_a = level.
    fn set(&mut self, a: usize, level: f64, xp: &Vector3, xn: &[Vector3]) {
        let (b, c) = ((a + 1) % 3, (a + 2) % 3);
        self.plane = Some((a, level));
        (self.lo, self.hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        let sp = sign(xp[a] - level);
        for (k, n) in xn.iter().enumerate() {
            if sp != 0 && sign(n[a] - level) == -sp {
                let s = (level - xp[a]) / (n[a] - xp[a]);
                let x = [xp[b] + s * (n[b] - xp[b]), xp[c] + s * (n[c] - xp[c])];
                for j in 0..2 {
                    self.lo[j] = self.lo[j].min(x[j]);
                    self.hi[j] = self.hi[j].max(x[j]);
                }
                self.x[k] = x;
            }
        }
    }
}

/// A two-sided triangle whose bounding box meets B (B not on one side of its plane): its
/// index, padded box ([`TriangleIndex::padded_box`]), and, for a triangle in an axis plane,
/// the nodes (bits by position in the particle's node list) above and below its plane.
struct NearTriangle {
    t: u32,
    padded: [Vector3; 2],
    pos: u32,
    neg: u32,
    /// For a triangle in an axis plane: the axis, the plane's level, and the sign of the
    /// normal's component along the axis (so a point's side is that sign times the sign
    /// of x_axis − level, exactly: the triple product reduces to that component).
    axis: Option<(usize, f64, i8)>,
    /// Per axis a, the nodes with x_a ≥ the padded box's lower bound, and ≤ its upper
    /// (oblique triangles only).
    ge: [u32; 3],
    le: [u32; 3],
}

/// Rule 3 for the triangles in axis planes, per grid node: every (node, triangle) with the
/// node in the triangle's plane and closed area, sorted (so each node's triangles are in
/// increasing index). Built when the crack's index was rebuilt (`generation`).
///
/// Why Task 1 may take a one-sided triangle's verdicts from here: for a box B of a
/// particle and its nodes and a triangle T in the axis plane x_a = level whose bounding box
/// meets B, B on one side of the plane (lo_a = level < hi_a or lo_a < level = hi_a) puts
/// every point of B, the particle too, on that side or in the plane, so the segment from
/// the particle to a node of B never crosses T properly (rule 2 needs strictly opposite
/// sides) and T's only possible verdict is rule 3's: the node in the plane and in the
/// closed triangle, the particle off the plane, with the particle's side. Such a node lies
/// in T's bounding box, so T meets B whatever B is, and [`crossing3::node_in_triangle`]
/// does not depend on the particle (any point off the plane gives its answer), so the
/// pairs can be listed once per crack position for all boxes. The same holds for a node in
/// the plane of a triangle whose plane cuts B (two-sided): a segment from a particle off
/// the plane meets the plane only at the node, so rule 3's verdict is again the only one.
/// Of a node's rule-3 verdicts only the lowest triangle counts ([`Crossing3::add_node_on`]),
/// so the scan stops at the first triangle with the particle off its plane.
///
/// [`crossing3::node_in_triangle`]: super::crossing3::node_in_triangle
#[derive(Clone, Debug, Default)]
pub struct NodeOnIndex {
    pairs: Vec<(u32, u32)>,
    /// Per grid node (bit i of word i / 64), whether it is in `pairs`; per word, how many
    /// set bits the words before it hold; and where each node's run of `pairs` starts (by
    /// the node's rank among the set bits; one more entry, the end).
    holds: Vec<u64>,
    rank: Vec<u32>,
    starts: Vec<u32>,
    generation: Option<u64>,
}

/// Per-thread scratch of Task 1: the last particle's nodes, their positions and box.
struct NodeBox {
    nodes: Vec<u32>,
    x: [Vector3; D3::MAX_NODES],
    lo: Vector3,
    hi: Vector3,
}

impl Default for NodeBox {
    fn default() -> Self {
        NodeBox { nodes: Vec::new(), x: [Vector3::zeros(); D3::MAX_NODES], lo: Vector3::repeat(f64::INFINITY), hi: Vector3::repeat(f64::NEG_INFINITY) }
    }
}

impl NodeOnIndex {
    /// List the pairs for the crack of `view` as `index` holds it, on `grid` (a no-op when
    /// the index has not been rebuilt since).
    fn rebuild(&mut self, grid: &crate::grid::Grid3, index: &TriangleIndex, view: &SurfaceView) {
        if self.generation == Some(index.generation()) {
            return;
        }
        self.generation = Some(index.generation());
        for &(i, _) in &self.pairs {
            self.holds[i as usize / 64] = 0;
        }
        self.holds.resize(crate::dim::GridGeometry::num_nodes(grid) / 64 + 1, 0);
        self.pairs.clear();
        // Node coordinates along axis c (as `node_pos` forms them: monotone in i).
        let coord = |c: usize, i: usize| grid.origin[c] + i as f64 * grid.h[c];
        for t in 0..view.triangles.len() {
            let Some((a, level, _)) = index.axis_plane(t) else { continue };
            let [tl, th] = index.aabb(t);
            // Per axis, the node indices whose coordinate lies in [tl, th] (level along a),
            // searched two indices beyond the rounded quotients and tested exactly.
            let mut range = [(0usize, 0usize); 3];
            let mut empty = false;
            for c in 0..3 {
                let (l, h) = if c == a { (level, level) } else { (tl[c], th[c]) };
                let q = |x: f64| (x - grid.origin[c]) / grid.h[c];
                // (Two indices of margin; `as` truncates the non-negative values.)
                let (f0, f1) = (q(l) - 2.0, q(h) + 2.0);
                if !(f1 >= 0.0 && f0 <= grid.n[c] as f64) {
                    empty = true;
                    break;
                }
                let (mut i0, mut i1) = (f0.max(0.0) as usize, f1.min(grid.n[c] as f64) as usize);
                while i0 <= i1 && coord(c, i0) < l {
                    i0 += 1;
                }
                while i1 >= i0 && coord(c, i1) > h {
                    if i1 == 0 {
                        empty = true;
                        break;
                    }
                    i1 -= 1;
                }
                if empty || i0 > i1 {
                    empty = true;
                    break;
                }
                range[c] = (i0, i1);
            }
            if empty {
                continue;
            }
            for iz in range[2].0..=range[2].1 {
                for iy in range[1].0..=range[1].1 {
                    for ix in range[0].0..=range[0].1 {
                        let x = Vector3::new(coord(0, ix), coord(1, iy), coord(2, iz));
                        debug_assert_eq!(x[a], level);
                        // A test point off the plane x_a = level.
                        let mut p = x;
                        p[a] += 1.0;
                        if p[a] == x[a] {
                            p[a] = x[a] * 2.0;
                        }
                        if super::crossing3::node_in_triangle(view, t, &p, &x) {
                            self.pairs.push((grid.node_index(ix, iy, iz) as u32, t as u32));
                        }
                    }
                }
            }
        }
        self.pairs.sort_unstable();
        self.starts.clear();
        for (j, &(i, _)) in self.pairs.iter().enumerate() {
            if j == 0 || self.pairs[j - 1].0 != i {
                self.starts.push(j as u32);
            }
            self.holds[i as usize / 64] |= 1 << (i % 64);
        }
        self.starts.push(self.pairs.len() as u32);
        self.rank.clear();
        let mut r = 0;
        for w in &self.holds {
            self.rank.push(r);
            r += w.count_ones();
        }
    }

    /// Whether the list is empty.
    #[inline]
    fn is_empty(&self) -> bool {
        self.pairs.is_empty()
    }

    /// The triangles holding node i (in its plane and closed area), in increasing index.
    #[inline]
    fn triangles_holding(&self, i: u32) -> impl Iterator<Item = u32> + '_ {
        let (w, b) = (i as usize / 64, i % 64);
        let run = match self.holds.get(w) {
            Some(&word) if word >> b & 1 != 0 => {
                let r = (self.rank[w] + (word & ((1u64 << b) - 1)).count_ones()) as usize;
                &self.pairs[self.starts[r] as usize..self.starts[r + 1] as usize]
            }
            _ => &[],
        };
        run.iter().map(|&(_, t)| t)
    }
}

impl CellCache {
    /// Make the cache hold the two-sided triangles near B = [lo, hi] of crack c with these
    /// nodes (the one-sided ones are [`NodeOnIndex`]'s).
    #[allow(clippy::too_many_arguments)]
    fn prepare(&mut self, c: usize, lo: &Vector3, hi: &Vector3, nodes: &[u32], xn: &[Vector3], index: &TriangleIndex) {
        if self.key == Some((c, *lo, *hi)) && self.nodes == nodes {
            return;
        }
        self.key = Some((c, *lo, *hi));
        self.nodes.clear();
        self.nodes.extend_from_slice(nodes);
        // The distinct node coordinates per axis, each with the nodes that have it.
        for (a, vals) in self.coords.iter_mut().enumerate() {
            vals.clear();
            for (k, x) in xn.iter().enumerate() {
                match vals.iter_mut().find(|(v, _)| *v == x[a]) {
                    Some((_, bits)) => *bits |= 1 << k,
                    None => vals.push((x[a], 1 << k)),
                }
            }
        }
        self.near.clear();
        let (near, coords) = (&mut self.near, &self.coords);
        index.near(lo, hi, |t| {
            let mut e = NearTriangle { t: t as u32, padded: index.padded_box(t), pos: 0, neg: 0, axis: None, ge: [0; 3], le: [0; 3] };
            // A triangle in an axis plane x_a = level is classified here (exactly and
            // cheaply); the others take the general test.
            if let Some((a, level, o)) = index.axis_plane(t) {
                // Every point x of B has the side o · sign(x_a − level): B on one side
                // leaves only rule 3, [`NodeOnIndex`]'s.
                if (lo[a] >= level && hi[a] > level) || (hi[a] <= level && lo[a] < level) {
                    return;
                }
                e.axis = Some((a, level, o));
                for &(x, bits) in &coords[a] {
                    match o * sign(x - level) {
                        1 => e.pos |= bits,
                        -1 => e.neg |= bits,
                        _ => {}
                    }
                }
                // (Its candidates test where the segments meet the plane instead of `ge`
                // and `le`.)
                near.push(e);
                return;
            }
            // Per axis, the nodes at or above the padded box's lower bound and at or below
            // its upper (for the candidates' segment-box test).
            let [pl, ph] = e.padded;
            for (c, vals) in coords.iter().enumerate() {
                for &(x, bits) in vals {
                    if x >= pl[c] {
                        e.ge[c] |= bits;
                    }
                    if x <= ph[c] {
                        e.le[c] |= bits;
                    }
                }
            }
            near.push(e);
        });
    }
}

/// The sign of x (0 for ±0).
#[inline]
fn sign(x: f64) -> i8 {
    (x > 0.0) as i8 - (x < 0.0) as i8
}

/// A two-sided triangle near a particle in Task 1: its padded bounding box, index, the
/// particle's exact side of its plane, and the nodes whose verdict it may give (`other`:
/// for an axis-plane triangle the nodes strictly on the other side, else all).
struct Candidate {
    padded: [Vector3; 2],
    t: u32,
    op: i8,
    other: u32,
    pos: u32,
    /// For an axis-plane triangle, as in [`NearTriangle`] (then `pos` holds the nodes
    /// above it).
    axis: Option<(usize, f64, i8)>,
    /// As in [`NearTriangle`].
    ge: [u32; 3],
    le: [u32; 3],
}

fn too_many_fields(sim: &Simulation<D3>, node: usize, cracks: Vec<usize>) -> CheckError {
    let x = sim.grid.node_pos(node);
    CheckError::TooManyFields3 { step: sim.step_count, ijk: sim.grid.node_ijk(node), x: vec![x.x, x.y, x.z], cracks }
}

/// +1 above, −1 below the crack near x, 0 unknown: the exact side of x relative to the
/// plane of the nearest triangle within `reach` onto whose closed area x projects
/// perpendicularly ([`TriangleIndex::nearest_projecting`]); unknown when there is none
/// (x beyond the front or an outer edge, at a convex kink between two triangles' ranges,
/// or far). The 2D `side_of` (the nearest segment whose closed interior x projects onto)
/// with triangles for segments, so that an extruded crack gives every node of the
/// extrusion its 2D side (case `cracks_2d_3d`). Used for the nodes in Task 7 and the
/// particles in the checked-mode crossing test.
fn side_of(crack: &Crack3, index: &TriangleIndex, x: &Vector3, reach: f64) -> i8 {
    side_and_triangle(crack, index, x, reach).0
}

/// [`side_of`] with the triangle it was read from (`u32::MAX` when unknown).
/// The first point of `xs` (in order) within `tol` of the triangle surface, with the
/// triangle it is near (the 3D form of [`super::first_particle_on`]: a scene whose crack
/// passes through a particle centre is refused, the particle being on neither side of it,
/// or on one by round-off only).
pub fn first_particle_on3(surface: &TriangleSurface, xs: &[Vector3], tol: f64) -> Option<(usize, usize)> {
    if surface.triangles.is_empty() {
        return None;
    }
    let (lo, hi) = bounds(&surface.vertices);
    let r = Vector3::repeat(tol);
    let (lo, hi) = (lo - r, hi + r);
    let mut index = TriangleIndex::default();
    // Buckets of the surface's own size: the query looks at the buckets within `tol`.
    let size = (hi - lo).max().max(tol);
    index.rebuild(&surface.vertices, &surface.triangles, size / 64.0);
    xs.iter().enumerate().find_map(|(p, x)| {
        if (0..3).any(|a| x[a] < lo[a] || x[a] > hi[a]) {
            return None;
        }
        index.nearest(x, tol).map(|(t, _)| (p, t))
    })
}

fn side_and_triangle(crack: &Crack3, index: &TriangleIndex, x: &Vector3, reach: f64) -> (i8, u32) {
    let Some(t) = index.nearest_projecting(x, reach) else { return (0, u32::MAX) };
    let [a, b, c] = crack.surface.triangles[t].map(|i| crack.surface.vertices[i as usize]);
    (side_of_plane(&a, &b, &c, x), t as u32)
}

/// After the Task 1 gather: every node has at most two fields (a node that one crack
/// splits three ways is first reduced to two, [`join_own_side`]); a node with two fields
/// gets the crack normal from above to below: the unit normal of the crack triangle nearest
/// the node (the 2D rule, nearest segment, with triangles; Nairn 2003 §2.2 saves the normal
/// of the crossed segment). Exact for planar cracks; on a curved crack the nearest triangle
/// is the best local plane the mesh offers, and unlike an average over crossed triangles
/// it does not depend on which particles happen to surround the node.
fn finish_crack_nodes(sim: &mut Simulation<D3>) -> Result<(), CheckError> {
    let reach = 2.0 * sim.grid.h.max();
    for a in 0..sim.nodes.active.len() {
        let i = sim.nodes.active[a] as usize;
        if sim.nodes.present[i] == 0b111 {
            join_own_side(sim, a, i)?;
        }
        let present = sim.nodes.present[i];
        if present.count_ones() == 2 {
            let c = sim.nodes.crack[i] as usize;
            let crack = &sim.cracks[c];
            let x = sim.grid.node_pos(i);
            let t = sim.scratch.crack_index3[c].nearest(&x, reach).map_or(0, |(t, _)| t);
            sim.nodes.normal[i] = -crack.surface.normal(t).normalize();
        }
    }
    Ok(())
}

/// A node that one crack splits three ways: some of its particles cross the crack to it
/// from above (field 1), some from below (field 2), and the rest reach it uncrossed (field
/// 0). Nairn 2003 allows two fields, "one for particles on one side of the crack and one
/// for particles on the other side", and says a third arises only "in unusual conditions";
/// it happens at a node just ahead of a warped front (issue 17, the corner-crack rod at
/// step 94): each part of the front grew level at its own height, so the surface's height
/// varies along the front by more than the node's distance from it within the node's
/// reach, and the node lies below the surface's extension on one side of it and above on
/// the other; a particle above the surface on the first side and one below it on the second
/// both see the surface between themselves and the node.
///
/// Rule: the node's own side is its exact side of the plane of the crack triangle nearest
/// it ([`TriangleIndex::nearest`], as for its normal); the particles that crossed to it from
/// that side are on the node's side of the crack where the node is, so they join field 0
/// (the node's own material); the particles from the other side keep their field. A node
/// in that plane is on neither side and joins both into field 0 (a node in the plane of a
/// flat crack beyond its front is crossed by no line). This is CRAMP's rule for a single
/// crack as NairnMPM implements it — a crossing from the side opposite the node's crossing
/// field goes to field 0 — with the side chosen by the geometry instead of by which
/// particle came first, so the result does not depend on particle order or threads. Only
/// these nodes change (a node with at most two fields is as before), and the checked-mode
/// crossing test reads particles' sides from the surface, not from the fields, so it still
/// catches a particle crossing the crack.
fn join_own_side(sim: &mut Simulation<D3>, a: usize, i: usize) -> Result<(), CheckError> {
    let c = sim.nodes.crack[i] as usize;
    let x = sim.grid.node_pos(i);
    // A crossed triangle meets a segment from the node to one of its particles, so it lies
    // within |h + l_p| ≤ (3/2)√3 h < 3 h of the node when l_p ≤ h/2 (a particle or more per
    // cell); a node with none within 3 h keeps the error.
    let reach = 3.0 * sim.grid.h.max();
    let Some((t, _)) = sim.scratch.crack_index3.get(c).and_then(|index| index.nearest(&x, reach)) else {
        return Err(too_many_fields(sim, i, vec![c]));
    };
    let surface = &sim.cracks[c].surface;
    let [p, q, r] = surface.triangles[t].map(|k| surface.vertices[k as usize]);
    let join = match side_of_plane(&p, &q, &r, &x) {
        // Node above: the particles above the crack (field 1) are on its side.
        1 => 0b010,
        -1 => 0b100,
        _ => 0b110,
    };
    sim.join_fields_into_zero(a, join);
    Ok(())
}

/// Centre-of-mass velocity of node i over its fields (eq. 32), None without mass.
fn centre_of_mass_velocity(sim: &Simulation<D3>, i: usize) -> Option<Vector3> {
    let present = sim.nodes.present[i];
    if present == 0 {
        return None;
    }
    fn sums<A: Accumulator<4>>(nodes: &crate::grid::Nodes<Vector3>, present: u8, i: usize) -> Option<[f64; 4]> {
        let mut a = A::default();
        for (f, fa) in nodes.fields.iter().enumerate() {
            if present & (1 << f) != 0 {
                a.add([fa.mom[i].x, fa.mom[i].y, fa.mom[i].z, fa.mass[i]]);
            }
        }
        a.certified()
    }
    let [px, py, pz, m] = sums::<FastSum<4>>(&sim.nodes, present, i).or_else(|| sums::<ExactSums<4>>(&sim.nodes, present, i)).expect("exact sums certify");
    Some(Vector3::new(px, py, pz) / m)
}

/// Velocity at x from the nodes' fields chosen by `field(i)`, with the linear shape
/// functions renormalised over the nodes that have one (001's N*); None if none has.
#[inline]
fn field_velocity(sim: &Simulation<D3>, x: &Vector3, field: impl Fn(usize) -> Option<Vector3>) -> Option<Vector3> {
    let mut node = [0u32; D3::MAX_NODES];
    let mut s = [0.0; D3::MAX_NODES];
    let mut g = [Vector3::zeros(); D3::MAX_NODES];
    let n = D3::weights_into(&sim.grid, ShapeKind::Linear, x, &Vector3::zeros(), &mut node, &mut s, &mut g);
    weighted_velocity(&s[..n], |k| field(node[k] as usize))
}

/// [`field_velocity`] from the weights `s` of its nodes (`field(k)` for the k-th).
#[inline(always)]
fn weighted_velocity(s: &[f64], field: impl Fn(usize) -> Option<Vector3>) -> Option<Vector3> {
    #[inline(always)]
    fn sums<A: Accumulator<4>>(s: &[f64], field: &impl Fn(usize) -> Option<Vector3>) -> Option<[f64; 4]> {
        let mut a = A::default();
        for (k, &s) in s.iter().enumerate() {
            if let Some(v) = field(k) {
                a.add([s * v.x, s * v.y, s * v.z, s]);
            }
        }
        a.certified()
    }
    let [sx, sy, sz, ws] = sums::<FastSum<4>>(s, &field).or_else(|| sums::<ExactSums<4>>(s, &field)).expect("exact sums certify");
    (ws > 0.0).then(|| Vector3::new(sx, sy, sz) / ws)
}

/// The linear weights of one of Task 7's points: its nodes' positions in the touched list
/// and their weights (`n` = [`WEIGHTS_UNKNOWN`] when it has more than 8 nodes: recomputed).
#[derive(Clone, Copy, Debug)]
pub struct PointWeights3 {
    n: u8,
    slot: [u32; 8],
    s: [f64; 8],
}

const WEIGHTS_UNKNOWN: u8 = u8::MAX;

/// A node that Task 7's points touch: its index, whether an upper- or lower-surface point
/// touches it, and the velocities the three surfaces read there (the above side's field,
/// the below side's, and the centre of mass; None where the node offers none), formed once
/// per node and step instead of once per point (the same operations on the same values).
#[derive(Clone, Copy, Debug)]
pub struct Touched3 {
    i: u32,
    surface: bool,
    v: [Option<Vector3>; 3],
}

/// Task 7 in 3D: every crack particle moves in the centre-of-mass velocity of its nodes
/// (eq. 32), each crack-surface point in the velocity field of its own side (001 eqs.
/// 11–12; [`super::side_field`] chooses the field, as in 2D).
fn task7_move_cracks(sim: &mut Simulation<D3>) {
    /// `slot` mark of a node no crack point touches.
    const UNSEEN: u32 = u32::MAX;
    let dt = sim.options.dt;
    let reach = 2.0 * sim.grid.h.max();
    rebuild_indices(sim);
    let mut cracks = std::mem::take(&mut sim.cracks);
    let mut slot = std::mem::take(&mut sim.scratch.node_slot3);
    let mut touched = std::mem::take(&mut sim.scratch.touched3);
    let mut weights = std::mem::take(&mut sim.scratch.weights3);
    let num_nodes = sim.nodes.present.len();
    if slot.len() != num_nodes {
        slot.clear();
        slot.resize(num_nodes, UNSEEN);
    }
    let this: &Simulation<D3> = sim;
    const POINT_CHUNK: usize = 32;
    for (c, crack) in cracks.iter_mut().enumerate() {
        let index = &this.scratch.crack_index3[c];
        // The nodes the crack's points touch, each once (`slot`: its position in `touched`).
        // Each point's weights are kept for its motion below.
        touched.clear();
        weights.clear();
        let (mut node, mut s27) = ([0u32; D3::MAX_NODES], [0.0; D3::MAX_NODES]);
        let surface_points = crack.above.len() + crack.below.len();
        for (k, x) in crack.above.iter().chain(&crack.below).chain(&crack.surface.vertices).enumerate() {
            // (`field_velocity`'s nodes and weights.)
            let n = crate::shape::linear_weights_3d(&this.grid, x, &mut node, &mut s27);
            let mut w = PointWeights3 { n: if n <= 8 { n as u8 } else { WEIGHTS_UNKNOWN }, slot: [0; 8], s: [0.0; 8] };
            for (m, &i) in node[..n].iter().enumerate() {
                let j = &mut slot[i as usize];
                if *j == UNSEEN {
                    *j = touched.len() as u32;
                    touched.push(Touched3 { i, surface: false, v: [None; 3] });
                }
                touched[*j as usize].surface |= k < surface_points;
                if m < 8 {
                    (w.slot[m], w.s[m]) = (*j, s27[m]);
                }
            }
            weights.push(w);
        }
        {
            let shape: &Crack3 = &*crack;
            let nodes = &this.nodes;
            touched.par_iter_mut().for_each(|t| {
                let i = t.i as usize;
                let (present, node_crack) = (nodes.present[i], nodes.crack[i]);
                let vel = |f: usize| nodes.fields[f].mom[i] / nodes.fields[f].mass[i];
                if t.surface {
                    // The node's geometric side, only where [`super::side_field`] asks for
                    // it (nodes whose fields do not tell the side; it asks whenever it calls
                    // its closure, whichever surface).
                    let mut asks = false;
                    super::side_field(present, node_crack, c, true, || {
                        asks = true;
                        0
                    });
                    let side = if asks { side_of(shape, index, &this.grid.node_pos(i), reach) } else { 0 };
                    t.v[0] = super::side_field(present, node_crack, c, true, || side).map(vel);
                    t.v[1] = super::side_field(present, node_crack, c, false, || side).map(vel);
                }
                t.v[2] = centre_of_mass_velocity(this, i);
            });
        }
        {
            let (slot, touched) = (&slot, &touched);
            // Each point moves in its own surface's velocities (the nodes' fields and sides
            // were fixed above, so the points move independently, in place): each surface
            // point in its side's fields, each crack particle in the centre-of-mass
            // velocity; one without material around it (in a crack open by more than a
            // cell) moves with its two surface points, so that it stays between them (as in
            // 2D, `crate::crack`'s Task 7).
            let (na, nb) = (crack.above.len(), crack.below.len());
            let (wa, rest) = weights.split_at(na);
            let (wb, wv) = rest.split_at(nb);
            let vel = |x: &Vector3, w: &PointWeights3, which: usize| -> Option<Vector3> {
                if w.n == WEIGHTS_UNKNOWN {
                    field_velocity(this, x, |i| touched[slot[i] as usize].v[which])
                } else {
                    weighted_velocity(&w.s[..w.n as usize], |k| touched[w.slot[k] as usize].v[which])
                }
            };
            let Crack3 { surface, above, below, .. } = &mut *crack;
            (surface.vertices.par_iter_mut(), above.par_iter_mut(), below.par_iter_mut(), wv.par_iter(), wa.par_iter(), wb.par_iter()).into_par_iter().with_min_len(POINT_CHUNK).for_each(
                |(x, a, b, w_x, w_a, w_b)| {
                    let va = vel(a, w_a, 0);
                    let vb = vel(b, w_b, 1);
                    let v = vel(x, w_x, 2).unwrap_or_else(|| match (va, vb) {
                        (Some(va), Some(vb)) => (va + vb) * 0.5,
                        (Some(v), None) | (None, Some(v)) => v,
                        (None, None) => Vector3::zeros(),
                    });
                    *a += va.unwrap_or_else(Vector3::zeros) * dt;
                    *b += vb.unwrap_or_else(Vector3::zeros) * dt;
                    *x += v * dt;
                },
            );
        }
        for t in &touched {
            slot[t.i as usize] = UNSEEN;
        }
    }
    sim.cracks = cracks;
    sim.scratch.node_slot3 = slot;
    sim.scratch.touched3 = touched;
    sim.scratch.weights3 = weights;
}

/// Checked mode: no particle near a crack crosses it (the 2D check with triangles). A
/// particle's side is known when it projects perpendicularly onto a triangle within two
/// cells ([`side_of`]); passing round the front goes through "unknown". A side is compared
/// with the one read before from the same part of the surface: the same triangle or one
/// sharing a corner with it (a particle moves a small fraction of a triangle per step),
/// made before the last check. When the nearest triangle is another part of the surface,
/// or was made by growth since the last check, the particle is checked
/// against the plane of the triangle it was read from, as long as it still projects onto
/// that triangle within reach (so a particle that crosses one sheet toward another, and
/// comes out on the same side of the other, is caught), and then takes its side from the
/// new one: a crack with two
/// sheets over one another — two branches passing each other, a terrace of a growing
/// front — has material between them that is above one sheet and below the other, and
/// its side "flipped" whenever the nearer sheet changed (case `tube_crack`; stops 34–39
/// reported such flips as crossings). A new triangle may put a particle that has not moved
/// on the other side from the triangle beside it: a front that kinks steeply folds its
/// new strip round the particles next to it (case `tube_crack`, step 615: a node 0.35 mm
/// from a particle moved 0.7 mm down and inward, θ = −23°, where the branch's K_II/K_I
/// alternated ±0.1 … 0.3 from check to check); the crack grew past the particle, which did
/// not cross it, and a particle that then moves through the new triangle is caught at the
/// next check.
fn check_crack_sides(sim: &mut Simulation<D3>) -> Result<(), CheckError> {
    rebuild_indices(sim);
    let nc = sim.cracks.len();
    let reach = 2.0 * sim.grid.h.max();
    let p = &sim.particles;
    if sim.crack_side.len() != p.len() * nc || sim.crack_side_triangle.len() != p.len() * nc || sim.crack_side_seen.len() != nc {
        sim.crack_side = vec![0; p.len() * nc];
        sim.crack_side_triangle = vec![u32::MAX; p.len() * nc];
        sim.crack_side_seen = vec![0; nc];
    }
    for (c, crack) in sim.cracks.iter().enumerate() {
        let index = &sim.scratch.crack_index3[c];
        let (lo, hi) = bounds(&crack.surface.vertices);
        let r = Vector3::repeat(reach);
        let (lo, hi) = (lo - r, hi + r);
        let sides: Vec<(i8, u32)> = (0..p.len())
            .into_par_iter()
            .with_min_len(crate::step::PARTICLE_CHUNK)
            .map(|i| {
                let x = p.x[i];
                if (0..3).any(|a| x[a] < lo[a] || x[a] > hi[a]) {
                    (0, u32::MAX)
                } else {
                    side_and_triangle(crack, index, &x, reach)
                }
            })
            .collect();
        let corners = |t: u32| crack.surface.triangles[t as usize];
        for (i, (side, t)) in sides.into_iter().enumerate() {
            let slot = p.id[i] as usize * nc + c;
            let (before, t_before) = (sim.crack_side[slot], sim.crack_side_triangle[slot]);
            if before != 0 && side != 0 {
                let (old, new) = (corners(t_before), corners(t));
                let made_before = (t as usize) < sim.crack_side_seen[c];
                let crossed = if made_before && old.iter().any(|v| new.contains(v)) {
                    side != before
                } else {
                    let v = old.map(|k| crack.surface.vertices[k as usize]);
                    let x = p.x[i];
                    projects_into(&x, &v) && distance_2(&x, &v) < reach * reach && side_of_plane(&v[0], &v[1], &v[2], &x) != before
                };
                if crossed {
                    return Err(CheckError::CrackCrossing { step: sim.step_count, particle: i, id: p.id[i], crack: c, before, after: side });
                }
            }
            sim.crack_side[slot] = side;
            sim.crack_side_triangle[slot] = t;
        }
        sim.crack_side_seen[c] = crack.surface.triangles.len();
    }
    Ok(())
}

/// The 3D crack stage of Task 1 alone, for `benches/step.rs`.
#[doc(hidden)]
impl Simulation<D3> {
    /// The segment–surface field assignment of Task 1 (cracks only).
    pub fn bench_crack_fields(&mut self) -> Result<(), CheckError> {
        assign_velocity_fields(self)
    }
}

#[cfg(test)]
mod tests {
    use crate::check::CheckError;
    use crate::dim::Vector3;
    use crate::scene3d::Scene3;

    /// A block with one crack of two parallel sheets, z = 1.6 and z = 2.6 (a mesh of two
    /// disjoint squares reaching past the block), and one particle moved by hand between
    /// checks (`check_crack_sides`). Between the sheets a particle is above the lower and
    /// below the upper: when the nearer sheet changes, its side as read from the nearest
    /// triangle flips without any crossing, and the check must not stop. Crossing either
    /// sheet must stop it, also when the particle then lies nearer the other sheet on the
    /// side it started on.
    fn two_sheets() -> crate::simulation::Simulation<crate::dim::D3> {
        let sheet = |z: f64| [[-1.0, -1.0, z], [5.0, -1.0, z], [5.0, 5.0, z], [-1.0, 5.0, z]];
        let v: Vec<String> = sheet(1.6).iter().chain(sheet(2.6).iter()).map(|p| format!("[{}, {}, {}]", p[0], p[1], p[2])).collect();
        let text = format!(
            "[grid]\norigin = [-2.0, -2.0, -2.0]\nsize = [8.0, 8.0, 8.0]\ncell = [1.0, 1.0, 1.0]\n\
             [solver]\nend_time = 1.0\nparticles_per_cell = 2\nchecked = true\n\
             [[materials]]\nname = \"m\"\nE = 1.0\nnu = 0.3\nrho = 1.0\n\
             [[bodies]]\nmaterial = \"m\"\nshape = {{ box = {{ min = [0.0, 0.0, 0.0], max = [4.0, 4.0, 4.0] }} }}\n\
             [[cracks]]\nsurface = {{ mesh = {{ vertices = [{}], triangles = [[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7]] }} }}\n",
            v.join(", ")
        );
        let mut sim = Scene3::from_toml(&text, "two_sheets", None).expect("scene").build().expect("simulation");
        // Particle 0 (id 0, one crack: slot 0) is moved by hand: forget its recorded side.
        assert_eq!(sim.particles.id[0], 0);
        sim.crack_side[0] = 0;
        sim
    }

    /// Put particle 0 at height z (x, y mid-block) and run the checked-mode side test.
    fn move_and_check(sim: &mut crate::simulation::Simulation<crate::dim::D3>, z: f64) -> Result<(), CheckError> {
        sim.particles.x[0] = Vector3::new(2.25, 1.75, z);
        super::check_crack_sides(sim)
    }

    #[test]
    fn a_particle_between_two_sheets_of_one_crack_does_not_cross_when_the_nearer_changes() {
        let mut sim = two_sheets();
        for z in [2.0, 2.2, 2.0, 2.3, 1.9] {
            move_and_check(&mut sim, z).unwrap_or_else(|e| panic!("z = {z}: {e}"));
        }
    }

    #[test]
    fn crossing_a_sheet_is_caught_also_toward_the_other_sheet() {
        // Through the upper sheet (the nearest triangle the same before and after).
        let mut sim = two_sheets();
        move_and_check(&mut sim, 2.4).unwrap();
        assert!(matches!(move_and_check(&mut sim, 2.7), Err(CheckError::CrackCrossing { before: -1, after: 1, .. })));
        // Through the lower sheet from below it to between the sheets, nearer the upper one:
        // below the upper sheet is the side it had below the lower one, but the lower
        // sheet's plane (the triangle its side was read from) was crossed.
        let mut sim = two_sheets();
        move_and_check(&mut sim, 1.4).unwrap();
        assert!(matches!(move_and_check(&mut sim, 2.2), Err(CheckError::CrackCrossing { before: -1, after: -1, .. })));
    }

    /// Growth folds a new triangle round a particle that does not move (a steeply kinked
    /// front, case `tube_crack` step 615): the new triangle shares corners with the one the
    /// particle's side was read from and puts it on the other side. The particle did not
    /// cross the crack; moving through the new triangle afterwards is a crossing.
    #[test]
    fn a_new_triangle_folded_round_a_particle_is_not_a_crossing_but_moving_through_it_is() {
        let mut sim = two_sheets();
        move_and_check(&mut sim, 2.45).unwrap();
        let below_sheet = sim.crack_side[0];
        // New triangle on the upper sheet's edge y = -1 (corners 4, 5), dipping to z = 2.3
        // at y = 3: 0.056 under the particle, nearer than the sheet (0.15 above it).
        let c = &mut sim.cracks[0];
        let x = Vector3::new(2.25, 3.0, 2.3);
        c.surface.vertices.push(x);
        c.above.push(x);
        c.below.push(x);
        c.surface.triangles.push([4, 5, 8]);
        move_and_check(&mut sim, 2.45).unwrap_or_else(|e| panic!("a particle the crack grew past: {e}"));
        assert_eq!(sim.crack_side[0], -below_sheet, "read from the new triangle, the side is the other");
        assert!(matches!(move_and_check(&mut sim, 2.35), Err(CheckError::CrackCrossing { before: 1, after: -1, .. }) | Err(CheckError::CrackCrossing { before: -1, after: 1, .. })));
    }
}
