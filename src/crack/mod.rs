//! Explicit cracks (Nairn 2003 §2): massless crack particles joined into polylines,
//! the line-crossing test that assigns each particle–node pair its velocity field
//! (Task 1), crack motion in the centre-of-mass velocity (Task 7), and the crack
//! surfaces, each moved in the velocity field of its own side (004 §2.1; 001 eqs. 11–12),
//! whose separation gives the crack-opening displacements.

pub mod advance3;
pub mod crossing3;
pub mod geometry;
pub mod surface;
pub mod three_d;
pub mod tip_zone;
mod visibility;

use crate::check::CheckError;
use crate::dim::Vector;
use crate::exact::{Accumulator, ExactSums, FastSum};
use crate::shape::{self, ShapeKind, MAX_NODES};
use crate::simulation::Simulation;
use geometry::{Extent, Side};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// How the two faces of a crack interact where they touch (Nairn 2003 §2.2).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub enum ContactLaw {
    /// Faces never interact (they may interpenetrate).
    None,
    /// Stick: both fields take the centre-of-mass momentum (eq. 13).
    Stick,
    /// Frictional sliding with coefficient μ (eqs. 14–19); μ = 0 is frictionless.
    Friction(f64),
}

/// How a node with two fields decides that the crack faces there are in contact.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ContactDetection {
    /// The relative nodal volume (Nairn 2003 eqs. 8–12): below `v_sep` apart, above
    /// `v_contact` in contact, in between in contact when approaching. It cannot see a gap
    /// smaller than a fraction of a cell: approaching faces a little apart get the impulse
    /// and separating ones do not, so under sliding the faces ratchet open (pure mode II
    /// split beam at 2 mm: δ_I/δ_II = +1.5 %, K_I/K_II = +1.5 %; issue 22), and on a
    /// growing crack every approach of the freshly opened flanks counts as contact, which
    /// with USAVG and MUSL creates energy (issue 20; docs/verification.md, `growth_strip`).
    Volume,
    /// The normal opening of the tracked crack surfaces at the node (the displacement-based
    /// detection 004 §2.2 reports trying; the default): contact only where the faces would
    /// meet within the step, gap − Δt (v_a − v_b)·n̂ ≤ 0, and then the approach is removed
    /// only beyond what closes the gap, so faces close onto each other without overlapping
    /// or being pushed apart. In 2D the gap is read from the two surfaces' points nearest
    /// the node ([`Crack::normal_opening_near`]); in 3D from the crack particles' openings
    /// interpolated at the point of the crack nearest the node.
    #[default]
    Opening,
    /// NairnMPM's default (its `CrackSurfaceContact::GetDeltaMomentum` with
    /// `MaterialSeparation` by displacements): the normal difference of the two fields'
    /// mass-weighted mean particle displacements at the node, (ū_b − ū_a)·n̂, less
    /// Δt (v_a − v_b)·n̂ on the momenta after the forces; contact when it is negative and
    /// the fields approach, and then the whole normal approach is removed. A comparison
    /// option (issue 20 item 3, case `pmma_tpb_choices`): it does not see the faces, and
    /// the displacement difference at a node whose fields were one material before a
    /// growing crack reached it starts from the strain across the node, not from zero.
    /// Nodes where one field holds all but 10⁻⁶ of the mass are skipped, as NairnMPM does.
    /// After the particles have moved (Task 6c) their displacements are already those at
    /// the step's end, where NairnMPM adds Δt Δv to the start-of-step ones: the same to
    /// first order.
    Displacement,
}

/// How particle–node pairs near a crack are treated in Task 1.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CrackMethod {
    /// CRAMP (Nairn 2003 §2.1): a pair whose line crosses a crack uses the node's
    /// velocity field of the particle's side (fields 1 and 2), so a crack node carries two
    /// independent fields; crack contact acts between them. Passes the crack-patch test.
    #[default]
    VelocityFields,
    /// Node visibility (Belytschko, Lu & Gu 1994), the alternative Nairn 2003 §3.1 compares
    /// CRAMP with: a node whose line to the particle crosses a crack does not influence
    /// that particle; the shape functions are renormalized over the visible nodes. One
    /// velocity field per node, hence no crack contact and no crack-surface tracking.
    /// Does not pass the crack-patch test (the paper, §3.1).
    Visibility,
}

/// One crack: its crack particles in order along the polyline, its contact law, and the
/// positions of its two surfaces at every crack particle.
#[derive(Clone, Debug, PartialEq)]
pub struct Crack {
    /// Crack particles (moved in the centre-of-mass velocity, Task 7).
    pub points: Vec<Vector>,
    pub contact: ContactLaw,
    /// Relative nodal volume below which the faces are separated (eq. 10).
    pub v_sep: f64,
    /// Relative nodal volume above which the faces are in contact.
    pub v_contact: f64,
    /// How contact is detected (set after [`Crack::new`]; default the surfaces' opening).
    pub detection: ContactDetection,
    /// Bounding box of `points` (Subtask 1 of the line-crossing algorithm).
    pub extent: Extent,
    /// Upper-surface position of each crack particle (moved in the "above" field).
    pub above: Vec<Vector>,
    /// Lower-surface position of each crack particle (moved in the "below" field).
    pub below: Vec<Vector>,
}

impl Crack {
    pub fn new(points: Vec<Vector>, contact: ContactLaw, v_sep: f64, v_contact: f64) -> Self {
        let extent = Extent::of(&points);
        Crack { above: points.clone(), below: points.clone(), points, contact, v_sep, v_contact, detection: ContactDetection::default(), extent }
    }

    /// Normal gap between the tracked crack surfaces at `x` (a node), along `n_above`
    /// (the unit normal pointing to the "above" side): (x_a − x_b)·n̂ with x_a, x_b the
    /// points of the above and below surface polylines nearest `x`. Positive when the
    /// faces are apart. Each surface's nearest point is found by walking its polyline from
    /// the segment of the crack (`index`, within `reach`) nearest `x`, for as long as the
    /// distance decreases: the surfaces are read where they are, not at the crack particle
    /// of the same index, which may lie elsewhere along the crack (a crack particle moves
    /// in the centre-of-mass velocity, each surface in its own side's). None without a
    /// crack segment within `reach`.
    pub fn normal_opening_near(&self, index: &geometry::SegmentIndex, x: Vector, reach: f64, n_above: Vector) -> Option<f64> {
        let r = Vector::new(reach, reach);
        let mut best: Option<(f64, usize)> = None;
        for i in index.near(x - r, x + r) {
            let (dist, _) = nearest_on_segment(self.points[i], self.points[i + 1], x);
            if dist <= reach * reach && best.is_none_or(|(bd, _)| dist < bd) {
                best = Some((dist, i));
            }
        }
        let (_, k) = best?;
        let xa = nearest_on_polyline(&self.above, k, x);
        let xb = nearest_on_polyline(&self.below, k, x);
        Some((xa - xb).dot(&n_above))
    }

    /// Crack-opening displacement at crack particle k: above − below.
    pub fn opening(&self, k: usize) -> Vector {
        self.above[k] - self.below[k]
    }

    /// Unit tangent of the crack at crack particle k, along the crack's direction (from
    /// its first point to its last): the chord from point k−1 to point k+1 (one-sided at
    /// the tips). `None` for a degenerate chord.
    pub fn tangent(&self, k: usize) -> Option<Vector> {
        let n = self.points.len();
        let (a, b) = (self.points[k.saturating_sub(1)], self.points[(k + 1).min(n - 1)]);
        let d = b - a;
        let l = d.norm();
        (l > 0.0).then(|| d / l)
    }

    /// Crack-opening displacement at crack particle k in local components
    /// `(normal, tangential)`: the normal component is (above − below)·n̂ with n̂ the unit
    /// normal pointing to the "above" side (left of the crack's direction), so it is
    /// positive when the faces are apart and negative when they interpenetrate; the
    /// tangential component is the slip of the above face relative to the below face
    /// along [`Crack::tangent`]. (Nairn 2003 §2.2 normal convention; surfaces as in
    /// 004 §2.1.) `(0, 0)` at a degenerate chord.
    pub fn opening_nt(&self, k: usize) -> (f64, f64) {
        let Some(t) = self.tangent(k) else { return (0.0, 0.0) };
        let n_above = Vector::new(-t.y, t.x);
        let d = self.opening(k);
        (d.dot(&n_above), d.dot(&t))
    }
}

impl crate::contact::CrackFaces for Crack {
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

/// The field of a node that holds the material on one side (`above`) of crack `c`, or
/// None if the node has none — ν(s,i) of 001 eq. 12 for a crack-surface point s on that
/// side (2D and 3D). Field 0 holds the material on the node's own side, field 1 (2) the
/// material above (below) the crack seen across it (Nairn 2003 §2.1). The node's own side
/// follows from its fields (`present`) when the crack split it ({0,1}: below; {0,2}:
/// above; {1,2}: on the crack) and from the geometry otherwise (`geometric_side`: +1
/// above, −1 below, 0 unknown); a node whose side is unknown (ahead of a tip, or far)
/// gives field 0. A node split by another crack (`node_crack` ≠ c) gives none: its fields
/// say nothing about this crack.
pub(crate) fn side_field(present: u8, node_crack: u16, c: usize, above: bool, geometric_side: impl FnOnce() -> i8) -> Option<usize> {
    let has = |f: usize| present & (1 << f) != 0;
    let across = if above { 1 } else { 2 };
    if present == 0 {
        return None;
    }
    if present.count_ones() >= 2 && node_crack as usize != c {
        return None;
    }
    let node_above = match (has(0), has(1), has(2)) {
        (true, true, false) => Some(false),
        (true, false, true) => Some(true),
        (false, true, true) | (true, true, true) => return Some(across),
        (false, true, false) => Some(false),
        (false, false, true) => Some(true),
        _ => match geometric_side() {
            1 => Some(true),
            -1 => Some(false),
            _ => None,
        },
    };
    let f = match node_above {
        Some(a) if a == above => 0,
        Some(_) => across,
        None => 0,
    };
    has(f).then_some(f)
}

/// Crack particles along the polyline through `vertices`: every segment is divided
/// evenly so that neighbouring crack particles are at most `max_spacing` apart. The
/// scene's vertices are kept exactly. Crack particles move independently (Task 7), so
/// their spacing is the resolution of the crack's shape and of its surfaces; half a cell
/// is the usual choice (Nairn 2003 §2.1; the crack-opening displacement for K is read
/// at the crack particle next to the tip, 004 §3).
pub fn subdivide(vertices: &[Vector], max_spacing: f64) -> Vec<Vector> {
    let mut out = Vec::with_capacity(vertices.len());
    if let Some(first) = vertices.first() {
        out.push(*first);
    }
    for s in vertices.windows(2) {
        let d = s[1] - s[0];
        let n = (d.norm() / max_spacing).ceil().max(1.0) as usize;
        for k in 1..n {
            out.push(s[0] + d * (k as f64 / n as f64));
        }
        out.push(s[1]);
    }
    out
}

/// The first point of `xs` (in order) within `tol` of the polyline `points`, with the
/// segment it is near.
pub fn first_particle_on(points: &[Vector], xs: &[Vector], tol: f64) -> Option<(usize, usize)> {
    let index = geometry::SegmentIndex::of(points);
    let r = Vector::new(tol, tol);
    xs.iter().enumerate().find_map(|(p, &x)| {
        index
            .near(x - r, x + r)
            .find(|&s| {
                let (a, d) = (points[s], points[s + 1] - points[s]);
                let t = ((x - a).dot(&d) / d.norm_squared()).clamp(0.0, 1.0);
                (x - (a + d * t)).norm() <= tol
            })
            .map(|s| (p, s))
    })
}

/// After the field assignment of Task 1 (2D or 3D): the crack that split each node, in
/// particle order, so a conflict is reported for the same pair as a serial loop would. Two
/// different cracks at one node: Err((node, [first crack, second crack])).
pub(crate) fn record_node_cracks<S: crate::simulation::Dimension>(sim: &mut Simulation<S>) -> Result<(), (usize, Vec<usize>)> {
    let (pairs, scratch) = (&sim.pairs, &sim.scratch);
    let node_crack = &mut sim.nodes.crack;
    node_crack.fill(u16::MAX);
    for i in (0..sim.particles.len()).filter(|&i| scratch.split[i]) {
        for k in pairs.of_particle(i) {
            if pairs.field[k] == 0 {
                continue;
            }
            let (node, c) = (pairs.node[k] as usize, scratch.pair_crack[k]);
            let nc = node_crack[node];
            if nc != u16::MAX && nc != c {
                return Err((node, vec![nc as usize, c as usize]));
            }
            node_crack[node] = c;
        }
    }
    Ok(())
}

/// How near (in cells) the line of a crack a node must be to count as on it for the
/// crack-tip zone ([`tip_zone::on_line`]): crack points moving in the centre-of-mass
/// velocity leave a crack laid along a node row by round-off (~10⁻⁶ of a cell in the
/// static plates), which must not change how the zone treats its nodes.
const ON_LINE: f64 = 1e-3;

/// Velocity field index for a crossing result (eq. 2): 0 none, 1 above, 2 below.
#[inline]
fn field_of(side: Side) -> u8 {
    match side {
        Side::None => 0,
        Side::Above => 1,
        Side::Below => 2,
    }
}

/// The 2D crack machinery as the generic time step calls it (polylines; Nairn 2003).
impl crate::simulation::Dimension for crate::dim::D2 {
    type Crack = Crack;
    type Growth = crate::fracture::growth::Growth;

    fn task1_cracks(sim: &mut Simulation) -> Result<(), CheckError> {
        sim.task1_cracks()
    }
    fn finish_crack_nodes(sim: &mut Simulation) -> Result<(), CheckError> {
        sim.finish_crack_nodes()
    }
    fn contact_momenta(sim: &mut Simulation) -> Result<(), CheckError> {
        sim.apply_contact_to_momenta()
    }
    fn contact_updated_momenta(sim: &mut Simulation) -> Result<(), CheckError> {
        sim.apply_contact_to_updated_momenta()
    }
    fn normal_gap(sim: &Simulation, c: usize, i: usize, n: Vector) -> Option<f64> {
        let reach = 2.0 * sim.grid.h.x.max(sim.grid.h.y);
        let x = sim.grid.node_pos(i);
        sim.scratch.crack_index.get(c).and_then(|index| sim.cracks[c].normal_opening_near(index, x, reach, -n))
    }
    fn task7_move_cracks(sim: &mut Simulation) {
        sim.task7_move_cracks()
    }
    fn hold_released(sim: &mut Simulation) {
        sim.hold_released()
    }
    fn apply_cohesive(sim: &mut Simulation) {
        sim.apply_cohesive()
    }
    fn grow_cracks(sim: &mut Simulation) -> Result<(), CheckError> {
        sim.grow_cracks().map_err(|error| CheckError::Growth { step: sim.step_count, error })
    }
    fn check_crack_sides(sim: &mut Simulation) -> Result<(), CheckError> {
        sim.check_crack_sides()
    }
    /// Per crack: the number of points, then every point, upper and lower surface point.
    fn crack_state_bits(cracks: &[Crack]) -> Vec<u64> {
        let mut words = Vec::new();
        for c in cracks {
            words.push(c.points.len() as u64);
            for pts in [&c.points, &c.above, &c.below] {
                words.extend(pts.iter().flat_map(|q| [q.x.to_bits(), q.y.to_bits()]));
            }
        }
        words
    }
}

impl Simulation {
    /// Task 1 with cracks, by the scene's [`CrackMethod`]: CRAMP's velocity fields
    /// ([`Simulation::assign_velocity_fields`]) or node visibility
    /// ([`Simulation::assign_visible_nodes`]).
    pub(crate) fn task1_cracks(&mut self) -> Result<(), CheckError> {
        match self.options.crack_method {
            CrackMethod::VelocityFields => self.assign_velocity_fields(),
            CrackMethod::Visibility => self.assign_visible_nodes(),
        }
    }

    /// Task 1 with cracks: ν(p,i) for every pair by the line-crossing algorithm, and the
    /// crack that split each node. A node split by two different cracks, or needing
    /// fields 0, 1 and 2 at once, stops the run: CRAMP allows two fields per node.
    ///
    /// The gathers rely on this: a pair gets a field other than 0 only at a node whose
    /// crack is recorded in `nodes.crack` (see `step::is_split`).
    ///
    /// In parallel over particles (each writes only its own pairs' fields, and the crack
    /// each crossed), then the nodes' cracks are recorded serially in particle order, so
    /// a conflict is reported for the same pair as a serial loop would. Each crossing test
    /// looks only at the segments near the particle–node rectangle
    /// ([`geometry::SegmentIndex`]; same result as testing every segment).
    pub(crate) fn assign_velocity_fields(&mut self) -> Result<(), CheckError> {
        let grid = &self.grid;
        let p = &self.particles;
        let pairs = &mut self.pairs;
        let scratch = &mut self.scratch;
        let cracks = &self.cracks;
        scratch.crack_index.resize_with(cracks.len(), Default::default);
        for (index, crack) in scratch.crack_index.iter_mut().zip(cracks) {
            index.rebuild(&crack.points);
        }
        let index = &scratch.crack_index;
        scratch.pair_crack.resize(pairs.field.len(), 0);
        // The crack-tip zones of this step (none unless `solver.tip_zone` is set).
        let z = self.options.tip_zone;
        let walk = 3.0 * grid.h.x.max(grid.h.y);
        tip_zone::zones(&mut scratch.tip_zones, cracks, z, walk, &p.x, &p.lp);
        let zones = &scratch.tip_zones;
        let tol = ON_LINE * grid.h.x.min(grid.h.y);
        // A particle's nodes lie within h + l_p of it per axis: a node has a weight only if
        // the rounded distance fl(x_p − x_n) is below h + l_p, and the rounding is at most
        // a relative 2^−53; the factor 1 + 10⁻⁹ covers it (and the rounding of the bound).
        let reach = (grid.h + p.lp.iter().fold(Vector::zeros(), |a, l| a.sup(l))) * (1.0 + 1e-9);
        let (count, node) = (&pairs.count, &pairs.node);
        (pairs.field.par_chunks_mut(MAX_NODES), scratch.pair_crack.par_chunks_mut(MAX_NODES), pairs.frac.par_chunks_mut(MAX_NODES))
            .into_par_iter()
            .with_min_len(crate::step::PARTICLE_CHUNK)
            .enumerate()
            .map(|(i, (field, pair_crack, frac))| {
                let field: &mut [u8; MAX_NODES] = field.try_into().expect("a stride of the pair arrays");
                let n = count[i] as usize;
                let xp = p.x[i];
                // Screening by crack extent, per particle: if the box around the particle that
                // holds all its nodes misses every crack's bounding box, so does every
                // particle–node rectangle of Subtask 1, and all its pairs are in field 0.
                if cracks.iter().all(|c| !near_extent(&c.extent, xp, reach)) {
                    // The whole stride (a fixed length: no call to memset).
                    field.fill(0);
                    if z > 0.0 {
                        frac.fill(1.0);
                    }
                    return false;
                }
                // The tip zones within reach of this particle's nodes.
                let near_zone = |zn: &tip_zone::TipZone| (zn.tip - xp).abs().iter().zip(reach.iter()).all(|(d, r)| *d <= r + z);
                let mut split = false;
                for k in 0..n {
                    let xn = grid.node_pos(node[i * MAX_NODES + k] as usize);
                    field[k] = 0;
                    if z > 0.0 {
                        frac[k] = 1.0;
                        // A node on the crack's line near a tip: shares by the particle's place.
                        if let Some((zn, (side, phi))) = zones.iter().filter(|zn| near_zone(zn)).find_map(|zn| tip_zone::on_line(zn, &cracks[zn.crack].points, xp, xn, z, tol).map(|r| (zn, r))) {
                            if side != Side::None {
                                field[k] = field_of(side);
                                frac[k] = phi;
                                pair_crack[k] = zn.crack as u16;
                                split = true;
                            }
                            continue;
                        }
                    }
                    for (c, crack) in cracks.iter().enumerate() {
                        let x = geometry::crossing_detail_indexed(&crack.points, &crack.extent, &index[c], xp, xn);
                        let side = x.map_or(Side::None, |x| x.side);
                        if side != Side::None {
                            field[k] = field_of(side);
                            pair_crack[k] = c as u16;
                            split = true;
                            // Within a tip zone, part of the particle stays in field 0.
                            if let Some(x) = x {
                                for zn in zones.iter().filter(|zn| zn.crack == c && near_zone(zn)) {
                                    if let Some(phi) = tip_zone::share(zn, &crack.points, &x, xp, xn, z) {
                                        frac[k] = frac[k].min(phi);
                                    }
                                }
                                // A share of nothing (the line through the tip): field 0.
                                if frac[k] == 0.0 {
                                    field[k] = 0;
                                    frac[k] = 1.0;
                                }
                            }
                            break;
                        }
                    }
                }
                split
            })
            .collect_into_vec(&mut scratch.split);
        record_node_cracks(self).map_err(|(node, cracks)| self.too_many_fields(node, cracks))?;
        Ok(())
    }

    /// The error for a node that would need a third velocity field, naming it by its
    /// grid indices and position.
    fn too_many_fields(&self, node: usize, cracks: Vec<usize>) -> CheckError {
        let (i, j) = self.grid.node_ij(node);
        let x = self.grid.node_pos(node);
        CheckError::TooManyFields { step: self.step_count, i, j, x: x.x, y: x.y, cracks }
    }

    /// After the Task 1 gather: every node has at most two fields (three — the two faces
    /// and the joined material — for a node on a crack's line inside a crack-tip zone,
    /// [`tip_zone::on_line`]), and a node with two or more fields gets the crack normal of
    /// the crack that split it (the normal of the segment nearest the node, directed from
    /// above to below, §2.2).
    pub(crate) fn finish_crack_nodes(&mut self) -> Result<(), CheckError> {
        for &node in &self.nodes.active {
            let i = node as usize;
            let present = self.nodes.present[i];
            if present == 0b111 && !(self.options.tip_zone > 0.0 && tip_zone::node_on_line(&self.scratch.tip_zones, &self.cracks, self.grid.node_pos(i), ON_LINE * self.grid.h.x.min(self.grid.h.y))) {
                let c = self.nodes.crack[i] as usize;
                return Err(self.too_many_fields(i, vec![c]));
            }
            if present.count_ones() >= 2 {
                let c = self.nodes.crack[i] as usize;
                let reach = 2.0 * self.grid.h.x.max(self.grid.h.y);
                let points = &self.cracks[c].points;
                let x = self.grid.node_pos(i);
                self.nodes.normal[i] = match self.scratch.crack_index.get(c) {
                    Some(index) => nearest_segment_normal(points, index, x, reach),
                    None => nearest_of(points, 0..points.len().saturating_sub(1), x).1,
                };
            }
        }
        Ok(())
    }

    /// Task 7: move every crack particle in the centre-of-mass velocity of its nodes
    /// (eq. 32), and each crack surface point in the velocity field of its own side
    /// (001 eqs. 11–12): the field ν(s,i) of surface point s at node i is the one holding
    /// the material on that side of the crack there ([`Simulation::surface_field`]), and
    /// nodes without it are inactive for that surface, with the linear shape functions
    /// renormalised over the active ones (001's N*). Crack particles are massless points,
    /// hence linear (not GIMP) shape functions; nodes without mass are inactive too.
    pub(crate) fn task7_move_cracks(&mut self) {
        let dt = self.options.dt;
        let zero = Vector::zeros();
        let reach = 2.0 * self.grid.h.x.max(self.grid.h.y);
        // Moved in place: the cracks are taken out while the grid and nodes are read.
        let mut cracks = std::mem::take(&mut self.cracks);
        let mut indices = std::mem::take(&mut self.scratch.crack_index);
        let mut old = std::mem::take(&mut self.scratch.crack_points);
        indices.resize_with(cracks.len(), Default::default);
        let this: &Simulation = self;
        // Velocity at x from the nodes' fields chosen by `field(i)`, renormalised; None
        // where no node around x has the field.
        let velocity = |x: &Vector, field: &dyn Fn(usize) -> Option<Vector>| -> Option<Vector> {
            let w = shape::weights(&this.grid, ShapeKind::Linear, x, &zero);
            // Σ S v (x, y) and Σ S over the nodes with the field, correctly rounded.
            let [sx, sy, ws] = weighted_sum::<FastSum<3>>(&w, field).or_else(|| weighted_sum::<ExactSums<3>>(&w, field)).expect("exact sums certify");
            (ws > 0.0).then(|| Vector::new(sx, sy) / ws)
        };
        let cm = |i: usize| this.centre_of_mass_velocity(i);
        // Every point moves independently of the others, so the points are updated in
        // parallel (the bits do not depend on how they are split).
        const POINT_CHUNK: usize = 32;
        for (c, crack) in cracks.iter_mut().enumerate() {
            let Crack { points, above, below, .. } = &mut *crack;
            // The surfaces' fields are found against the crack before it moves.
            old.clear();
            old.extend_from_slice(points);
            let index = &mut indices[c];
            index.rebuild(&old);
            let (before, index) = (&old[..], &*index);
            let side = |i: usize, above: bool| this.surface_field(c, before, index, i, above, reach).map(|f| this.nodes.fields[f].mom[i] / this.nodes.fields[f].mass[i]);
            (points.par_iter_mut(), above.par_iter_mut(), below.par_iter_mut()).into_par_iter().with_min_len(POINT_CHUNK).for_each(|(x, a, b)| {
                let va = velocity(a, &|i| side(i, true));
                let vb = velocity(b, &|i| side(i, false));
                // A crack particle with no material around it (in a crack open by more
                // than a cell) has no centre-of-mass velocity: it moves with its two
                // surfaces, so that it stays between them. Left in place, it would lag the
                // material it belongs to (1.4 mm in the cracked disks at 0.5 mm), the
                // crack would fold, and the opening read at a node would be that of
                // another part of the crack.
                let v = velocity(x, &cm).unwrap_or_else(|| match (va, vb) {
                    (Some(va), Some(vb)) => (va + vb) * 0.5,
                    (Some(v), None) | (None, Some(v)) => v,
                    (None, None) => zero,
                });
                *a += va.unwrap_or(zero) * dt;
                *b += vb.unwrap_or(zero) * dt;
                *x += v * dt;
            });
            crack.extent = Extent::of(&crack.points);
        }
        self.cracks = cracks;
        self.scratch.crack_index = indices;
        self.scratch.crack_points = old;
    }

    /// Centre-of-mass velocity of node i over its fields (eq. 32), None without mass.
    fn centre_of_mass_velocity(&self, i: usize) -> Option<Vector> {
        let present = self.nodes.present[i];
        if present == 0 {
            return None;
        }
        // Σ p (x, y) and Σ m over the fields present, correctly rounded.
        fn sums<A: Accumulator<3>>(nodes: &crate::grid::Nodes, present: u8, i: usize) -> Option<[f64; 3]> {
            let mut a = A::default();
            for (f, fa) in nodes.fields.iter().enumerate() {
                if present & (1 << f) != 0 {
                    a.add([fa.mom[i].x, fa.mom[i].y, fa.mass[i]]);
                }
            }
            a.certified()
        }
        let [px, py, m] = sums::<FastSum<3>>(&self.nodes, present, i).or_else(|| sums::<ExactSums<3>>(&self.nodes, present, i)).expect("exact sums certify");
        Some(Vector::new(px, py) / m)
    }

    /// The field of node i that holds the material on one side (`above`) of crack `c`,
    /// or None if the node has none — ν(s,i) of 001 eq. 12 for a surface point s on that
    /// side. Field 0 holds the material on the node's own side, field 1 (2) the material
    /// above (below) the crack seen across it (Nairn 2003 §2.1). The node's own side
    /// follows from its fields when the crack split it ({0,1}: below; {0,2}: above;
    /// {1,2}, or {0,1,2} in a crack-tip zone: on the crack) and from the geometry otherwise; a node whose side is
    /// unknown (ahead of a tip, or far) gives field 0.
    pub(crate) fn surface_field(&self, c: usize, points: &[Vector], index: &geometry::SegmentIndex, i: usize, above: bool, reach: f64) -> Option<usize> {
        side_field(self.nodes.present[i], self.nodes.crack[i], c, above, || side_of(points, index, self.grid.node_pos(i), reach))
    }

    /// Checked mode: no particle near a crack changes side. A particle's side is known
    /// when its projection on the crack falls inside a segment within two cells of it;
    /// passing round a tip goes through "unknown" and resets the record. The record is
    /// kept by particle id, not by storage index, so reordering the particles between
    /// steps (`Particles::permute`) cannot make it compare two different particles.
    pub(crate) fn check_crack_sides(&mut self) -> Result<(), CheckError> {
        let nc = self.cracks.len();
        let reach = 2.0 * self.grid.h.x.max(self.grid.h.y);
        let p = &self.particles;
        if self.crack_side.len() != p.len() * nc {
            self.crack_side = vec![0; p.len() * nc];
        }
        let mut index = std::mem::take(&mut self.scratch.crack_index);
        index.resize_with(nc, Default::default);
        for (c, crack) in self.cracks.iter().enumerate() {
            let index = &mut index[c];
            index.rebuild(&crack.points);
            let mut ext = crack.extent;
            ext.min -= Vector::new(reach, reach);
            ext.max += Vector::new(reach, reach);
            for i in 0..p.len() {
                let x = p.x[i];
                let slot = p.id[i] as usize * nc + c;
                let side = if x.x < ext.min.x || x.x > ext.max.x || x.y < ext.min.y || x.y > ext.max.y {
                    0
                } else {
                    side_of(&crack.points, index, x, reach)
                };
                let before = self.crack_side[slot];
                if before != 0 && side != 0 && side != before {
                    return Err(CheckError::CrackCrossing { step: self.step_count, particle: i, id: p.id[i], crack: c, before, after: side });
                }
                self.crack_side[slot] = side;
            }
        }
        self.scratch.crack_index = index;
        Ok(())
    }
}

/// Σ S_k v_k (x and y) and Σ S_k over the nodes k of `w` where `field` gives a velocity.
fn weighted_sum<A: Accumulator<3>>(w: &shape::Weights, field: &dyn Fn(usize) -> Option<Vector>) -> Option<[f64; 3]> {
    let mut a = A::default();
    for k in 0..w.n {
        if let Some(v) = field(w.node[k] as usize) {
            a.add([w.s[k] * v.x, w.s[k] * v.y, w.s[k]]);
        }
    }
    a.certified()
}

/// Does the closed box `x ± reach` meet the closed extent?
#[inline]
fn near_extent(e: &Extent, x: Vector, reach: Vector) -> bool {
    x.x + reach.x >= e.min.x && x.x - reach.x <= e.max.x && x.y + reach.y >= e.min.y && x.y - reach.y <= e.max.y
}

/// +1 if `x` is left of (above) the nearest segment whose interior it projects onto
/// within `reach`, −1 if right of (below), 0 if unknown (beyond the tips or far).
///
/// Only the segments `index` (of `points`) finds within 2·reach of `x` are looked at: a
/// segment whose box is farther than that cannot be within `reach` (its computed
/// distance errs by round-off only), and the others are taken in the same order, so the
/// result is that of scanning every segment.
fn side_of(points: &[Vector], index: &geometry::SegmentIndex, x: Vector, reach: f64) -> i8 {
    let mut best = (f64::INFINITY, 0i8);
    let r = Vector::new(2.0 * reach, 2.0 * reach);
    for i in index.near(x - r, x + r) {
        let s = [points[i], points[i + 1]];
        let d = s[1] - s[0];
        let l2 = d.norm_squared();
        if l2 == 0.0 {
            continue;
        }
        let t = (x - s[0]).dot(&d) / l2;
        if !(0.0..=1.0).contains(&t) {
            continue;
        }
        let area = geometry::signed_area(s[0], s[1], x);
        let dist = area.abs() / l2.sqrt();
        if dist < reach && dist < best.0 {
            best = (dist, if area > 0.0 { 1 } else if area < 0.0 { -1 } else { 0 });
        }
    }
    best.1
}

/// Normal (above → below) of the crack segment nearest to `x`.
///
/// The segments `index` finds within `reach` of `x` are looked at first (in crack order,
/// as a scan of all would); if the nearest of them is closer than reach/2, no segment
/// outside that box (farther than `reach`, whose computed distance errs by round-off only)
/// can be nearer, and the result is that of the full scan, which runs otherwise.
fn nearest_segment_normal(points: &[Vector], index: &geometry::SegmentIndex, x: Vector, reach: f64) -> Vector {
    let r = Vector::new(reach, reach);
    let near = nearest_of(points, index.near(x - r, x + r), x);
    if near.0 < 0.25 * reach * reach {
        return near.1;
    }
    nearest_of(points, 0..points.len().saturating_sub(1), x).1
}

/// (squared distance, point) of the point of segment [a, b] nearest `x`.
pub(crate) fn nearest_on_segment(a: Vector, b: Vector, x: Vector) -> (f64, Vector) {
    let d = b - a;
    let l2 = d.norm_squared();
    let t = if l2 > 0.0 { ((x - a).dot(&d) / l2).clamp(0.0, 1.0) } else { 0.0 };
    let p = a + d * t;
    ((x - p).norm_squared(), p)
}

/// The point of polyline `pts` nearest `x`, by a walk over its segments from segment
/// `start` in the direction the distance decreases (the local minimum nearest `start`).
fn nearest_on_polyline(pts: &[Vector], start: usize, x: Vector) -> Vector {
    let seg = |i: usize| nearest_on_segment(pts[i], pts[i + 1], x);
    let (mut d, mut p) = seg(start);
    let mut i = start;
    while i > 0 {
        let (d2, p2) = seg(i - 1);
        if d2 >= d {
            break;
        }
        (d, p, i) = (d2, p2, i - 1);
    }
    let mut i = start;
    while i + 2 < pts.len() {
        let (d2, p2) = seg(i + 1);
        if d2 >= d {
            break;
        }
        (d, p, i) = (d2, p2, i + 1);
    }
    p
}

/// (squared distance, normal) of the segment nearest `x` among `segs`, ascending; the
/// first of equally near ones.
fn nearest_of(points: &[Vector], segs: impl Iterator<Item = usize>, x: Vector) -> (f64, Vector) {
    let mut best = (f64::INFINITY, Vector::new(0.0, -1.0));
    for i in segs {
        let s = [points[i], points[i + 1]];
        let d = s[1] - s[0];
        let l2 = d.norm_squared();
        if l2 == 0.0 {
            continue;
        }
        let t = ((x - s[0]).dot(&d) / l2).clamp(0.0, 1.0);
        let dist = (x - (s[0] + d * t)).norm_squared();
        if dist < best.0 {
            if let Some(n) = geometry::segment_normal(s[0], s[1]) {
                best = (dist, n);
            }
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `side_of` over every segment, as it was before the segment index.
    fn side_of_all(points: &[Vector], x: Vector, reach: f64) -> i8 {
        let mut best = (f64::INFINITY, 0i8);
        for s in points.windows(2) {
            let d = s[1] - s[0];
            let l2 = d.norm_squared();
            if l2 == 0.0 {
                continue;
            }
            let t = (x - s[0]).dot(&d) / l2;
            if !(0.0..=1.0).contains(&t) {
                continue;
            }
            let area = geometry::signed_area(s[0], s[1], x);
            let dist = area.abs() / l2.sqrt();
            if dist < reach && dist < best.0 {
                best = (dist, if area > 0.0 { 1 } else if area < 0.0 { -1 } else { 0 });
            }
        }
        best.1
    }

    /// Random polylines (short and long, on a half-unit lattice every other trial, where
    /// points on lines and ties are frequent) with their index, and query points and
    /// reaches; `check` compares an indexed result with the full scan.
    fn random_queries(seed: u64, trials: usize, mut check: impl FnMut(&[Vector], &geometry::SegmentIndex, Vector, f64)) {
        let mut state = seed;
        let mut unit = move || {
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        for trial in 0..trials {
            let n = 2 + (unit() * if trial % 10 == 0 { 300.0 } else { 12.0 }) as usize;
            let lattice = trial % 2 == 0;
            let pt = |u: &mut dyn FnMut() -> f64| {
                if lattice {
                    Vector::new((u() * 9.0).floor() * 0.5, (u() * 9.0).floor() * 0.5)
                } else {
                    Vector::new(u() * 4.0, u() * 4.0)
                }
            };
            let points: Vec<Vector> = (0..n).map(|_| pt(&mut unit)).collect();
            let index = geometry::SegmentIndex::of(&points);
            for _ in 0..20 {
                let x = pt(&mut unit);
                let reach = 0.05 + unit();
                check(&points, &index, x, reach);
            }
        }
    }

    #[test]
    fn indexed_nearest_normal_equals_the_full_scan() {
        random_queries(999, 3000, |points, index, x, reach| {
            let all = nearest_of(points, 0..points.len() - 1, x).1;
            assert_eq!(nearest_segment_normal(points, index, x, reach), all, "{points:?} {x:?} {reach}");
        });
    }

    #[test]
    fn indexed_side_of_equals_the_full_scan() {
        random_queries(12345, 5000, |points, index, x, reach| {
            assert_eq!(side_of(points, index, x, reach), side_of_all(points, x, reach), "{points:?} {x:?} {reach}");
        });
    }
}
