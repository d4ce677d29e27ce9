//! Advancing a 3D crack front: the new crack-surface triangles of 001 §2.3.2, Fig. 3.
//!
//! "If only one end of a crack segment propagates (such as segment AB), a single new crack
//! surface element will be created (such as ABB'). If both ends of a segment propagate
//! (such as segment BC), then four new crack surface elements are created (such as the four
//! elements within BCC'B'). If a new crack-front segment becomes too long after
//! propagation, say two times longer than the initial length, the segment will be broken
//! into two, and five new crack elements will be created (such as five elements within
//! CDD'C' with added point P1 along the long segment in the new crack front). If a
//! crack-front segment becomes too short after propagation, say less than 25% of the
//! initial length, the segment will be shrunk into a point, and only one new crack element
//! will be created (such as E'F' combining to P2)." (001 §2.3.2)
//!
//! The rules as implemented, for a front edge a→b (directed as in its triangle: the crack
//! surface on its left seen from above) whose ends move to a′, b′ (an end that does not
//! move keeps its crack particle):
//!
//! * **one end moves** (a): the triangle (b, a, a′); the front edge becomes a′→b.
//! * **both ends move**: the quadrilateral b, a, a′, b′ is cut into four triangles about
//!   its centre c = ((a + b) + (a′ + b′))/4, a new crack particle: (b, a, c), (a, a′, c),
//!   (a′, b′, c), (b′, b, c). Four triangles rather than two because a diagonal would pick
//!   one of two mirror-image cuts: the centre keeps a mirror-symmetric front symmetric to
//!   the bit (c and the midpoints below are symmetric in a ↔ b).
//! * **split**: if the new edge is longer than 2 L (L the edge's reference length)
//!   **across the moves** — its length normal to m = (a′ − a) + (b′ − b), the two ends'
//!   summed moves (|a′b′| itself when m is zero) — the midpoint p of a′b′ is added and the
//!   quadrilateral is cut into five: (b, a, c), (a, a′, c), (a′, p, c), (p, b′, c),
//!   (b′, b, c); the front edges a′→p and p→b′ each keep L. Across the moves, because a
//!   front that grows node by node is a staircase (growth3 module doc, item 3): an edge
//!   whose one end has made an increment more than the other (a riser) lies along the
//!   moves and is long without the front having stretched. Split at its midpoint, it
//!   gave a node halfway up the riser, whose front tangent (and so its direction of
//!   growth) pointed up the riser: measured on `corner_crack_rod`, headings 55° and 57°
//!   off the front normal at the two split points of a riser, 27° at their neighbours,
//!   and the new strip folded over itself. For an edge normal to its ends' moves (a
//!   front growing evenly, a penny's radial growth) it is |a′b′|, the paper's test.
//! * **merge**: if the new edge is shorter than L/4 **along the old edge** (both ends
//!   moved): (b′ − a′)·(b − a)/|b − a| < L/4, a′ and b′ become one crack particle at their
//!   midpoint m and the edge leaves one triangle (b, a, m) and no front edge; the
//!   neighbouring edges end at m. Measured along the old edge, so that a new edge that
//!   has turned over (its ends' moves crossed: the projection is negative however long
//!   |a′b′| is) is merged too — it has passed through zero length on the way, where the
//!   paper's rule ("less than 25 % of the initial length") would have shrunk it into a
//!   point; for a new edge parallel to the old one it is |a′b′| < L/4, the paper's test.
//!   (A short edge with one end moving is not merged: the moving end travels away from
//!   the other along the front normal.)
//! * **reference length** L: the edge's length when the crack was built; an edge made by
//!   moving or splitting inherits its parent's L, so "two times longer than the initial
//!   length" keeps meaning the initial discretisation wherever the front has gone.
//! * **no crossing**: a new triangle may not meet any existing triangle of any crack (or
//!   another new one) except at shared corners (exact test, [`triangles_meet`]). Every
//!   front node whose move makes such a triangle is refused (it stays where it is), and
//!   the advance is rebuilt without it until no triangle meets. The report tells the two
//!   kinds apart: a node whose new triangles meet the **existing** surface (of this crack
//!   or another) is `refused` — its move would cut a crack, and the driver stops it for
//!   good, as a 2D tip that would cross a crack; a node whose new triangles meet only
//!   **other new triangles** of the same advance is `folded` — its move and a
//!   neighbour's fold the new strip over itself (headings that converge or cross over a
//!   distance of one increment, e.g. on a one-increment staircase of the front), which
//!   says nothing about the crack it would meet, and the driver retries it at its next
//!   check, when the front's shape and the headings have changed.
//!
//! * **sliver** (not in the paper; issue 17, case `tube_crack`): a front edge b–a whose end
//!   b is stopped for good (at the material boundary or at a crack: the growth driver's
//!   `stopped` set) while a moves would make the one-end triangle (b, a, a′) again at every
//!   move of a, a fan about the fixed b. When that triangle's smallest angle is below
//!   [`SLIVER_ANGLE_DEG`] = 15° the edge leaves the front instead (no triangle; b–a stays a
//!   boundary edge of the surface that is not front, as a pruned edge of 001 §2.3.3) and
//!   a′ carries on from its other edge. Measured on `tube_crack` (main 833f572): a front
//!   end stopped on the tube's inner face and its moving neighbour made a fan of such
//!   triangles up to 11 mm long; one of them, corners nearly collinear (smallest angle
//!   5.6°, largest 157°), had a plane nearly normal to the crack's, and a particle 2.5 mm
//!   from it took its side from it and then "crossed" when a proper triangle came nearer
//!   (the run's stop at step 537). 15°: a one-end triangle of a front growing normally
//!   (edge ≈ ⅓ cell, move ½ cell at up to 45° to the edge) has its smallest angle above
//!   25°; a fan's triangles fall below 15° from the third or fourth on. Not applied to a
//!   moving node all of whose front edges would go (it would be left with no triangle).
//!
//! * **turn-over** (not in the paper; issue 17, case `tube_crack`): a new triangle whose
//!   normal points against that of the old triangle holding the front edge it is built on
//!   (n_new · n_old < 0: a dihedral angle above 90°, the new strip folded back over the
//!   surface behind it) is a fold, and its moved nodes are refused as `folded` (retried at
//!   their next check). No kink of either criterion comes near it (the maximum hoop stress
//!   kink is at most 70.5°), so it only catches a node whose move runs along or back
//!   across its front edge — on a jagged front, an edge lying along the direction of
//!   growth (a riser of the staircase) whose trailing end moves past the leading one.
//!   Measured on `tube_crack` (branch tube5, before this rule; crack surface at step 612):
//!   13 of 12,210 triangles faced the wrong way (n_z < 0 where the grown surface has
//!   n_z ≈ +1), in two groups: 6 at 75–78° round the tube on the +x branch (z ≈ 4.85,
//!   r = 41.4–42.2), by which 4 front nodes with K_eq = 1300–7000 (K_Ic = 632) had been
//!   refused at a crack and stayed to the end (the check `runs_round` read 78.1°), and 7 at
//!   163–171° on the −x branch (z ≈ −3.4 … −4.3), e.g. triangle (6395, 6393, 6393′) of a
//!   front edge running 1.2° round the tube (a riser) whose trailing end 6393 moved past
//!   6395: a particle 2.1–2.6 mm below took side +1 from that upside-down triangle and −1
//!   from a correct one made 0.6 mm away at the next check, and the crossing test stopped
//!   the run (step 615). The exact crossing test does not see it: the folded triangle
//!   lies beside the old ones, not through them.
//!
//!   **Widened to the criterion's reach** (branch tube6): when every material of the
//!   scene with a toughness grows by maximum hoop stress, the test is a dihedral above
//!   70.529° + 10° = 80.5° ([`fold_cos`]; 90° otherwise, and in [`advance_front`]).
//!   70.529° is the largest kink maximum hoop stress asks for (K_I = 0; 001 eq. 20). A
//!   one-end triangle (b, a, a′) whose move is kinked by θ from the old plane, with the
//!   front edge at ψ to the node's front tangent (the move normal to the tangent), has a
//!   dihedral atan(tan θ / cos ψ) with the old plane: 80.5° at θ = 70.5° needs ψ = 62°,
//!   a front turning by about 124° at that node, which a front that is one does not do;
//!   the four triangles of a quadrilateral, with the centre halfway, tilt less. So no
//!   move the criterion can ask for is refused, while a triangle standing nearly at right
//!   angles to the surface behind it — which the n·n_old < 0 test missed — is. Measured
//!   on `tube_crack` (branch tube5, with the 90° test): the 2 triangles left upside down,
//!   at 75–76° round the tube (made at step ≈ 329), stood nearly vertical, n = (−0.99,
//!   0.04, −0.07) (in the tube's wall, at about 90° to the surface behind them), and the
//!   piece of the +x branch's front beside them was refused at a crack at step 339 with
//!   K_eq = 3600–5400 (K_Ic = 632) and stuck there to the end (runs_round 77.0°). The
//!   minimum strain-energy density criterion kinks by up to acos((κ − 1)/6) (82.3° at
//!   ν = 0.3 in plane strain, 90° as ν → ½): no margin is left, and its test stays at 90°.
//!   Measured with it (branch tube6, `tube_crack` as a case and a `cramp run` to step 346):
//!   the piece is no longer refused at a crack but folded at every retry — two nodes at
//!   74.5° and 75.8° (K_eq 3850–7000) at the bottom of a slot in the front 6–8° long,
//!   whose front edges lie along the growth direction, so their tangents and headings are
//!   skewed 27–44° and their one-end triangles stand nearly vertical; runs_round 74.3°. The
//!   test changed how the piece is held, not that it is (a notch rule is left to do).
//!
//! * **re-spacing** (not in the paper's Fig. 3; issue 17, case `tube_crack`;
//!   [`respace_moves`], applied by the growth driver to the targets before this advance):
//!   along every run of at least three front nodes, consecutive on the front, that all
//!   move at this advance, the run's two end nodes keep their targets and each interior
//!   node is put on the polyline of the run's targets at the arc-length fraction it had
//!   along the run before the move. Every node moves the same increment along its own
//!   front normal (001 §2.3.2), so where the front sweeps round an axis (a through-wall
//!   front in a tube: the part at the inner radius gains angle faster than the part at
//!   the outer) the front tilts, its normal gains a component along the front, and the
//!   nodes slide along the front at every move: measured on `tube_crack` (branch tube3),
//!   mid-wall nodes moved outward through the wall (r = 43.2 → 45.0 mm over steps
//!   336–345), crowded at r = 45–47 mm, their headings crossed and their moves were
//!   refused at the surface just made. A node's place along the front is a matter of
//!   discretisation, not of mechanics: 3D front-tracking codes re-discretise the advanced
//!   front (FRANC3D fits a curve through the new front points and re-seeds nodes along it;
//!   not checked here against its documentation). Here only
//!   the interior nodes of a run are moved, along the new front (not across it: the front's
//!   shape is that of the targets), and only by more than a millionth of a cell (a
//!   straight or circular front growing uniformly keeps its spacing and is left to the
//!   bit). A node next to one that does not move is a run end: the staircase of
//!   asynchronous moves (growth3 module doc, item 3) is not resampled.
//!
//! * **notch** (not in the paper; issue 17, case `tube_crack`; [`fill_notches`], applied
//!   by the growth driver after each advance): a front node at the apex of a tongue of
//!   material reaching back into the crack (the material between its two front edges
//!   under [`NOTCH_ANGLE_DEG`] = 45°) is cut off with the triangle (node, previous, next)
//!   and leaves the front. Such an apex cannot move (its heading is skewed by its nearly
//!   opposed edges, and every triangle it would make is refused or a fold), and the rest
//!   of the front passes it by.
//!
//! * **clearance** (not in the paper; issue 17, case `tube_crack`; [`Clearance`], given by
//!   the growth driver): the new crack particles are moved along the normal of the new
//!   triangles, by at most [`CLEARANCE_MAX_SHIFT`] clearances per round, until no particle centre
//!   that projects onto a new triangle lies within the clearance of its plane (to a
//!   thousandth of it after three rounds: a shift tilts the triangle, which the next round
//!   takes up; a
//!   [`CLEARANCE_CELLS`] = 2 % of a cell in the driver). A particle's side of its crack is
//!   the side of its centre (Nairn 2003, Task 1), and the crack surface moves with the
//!   nodes' centre-of-mass velocity, not with the particles beside it: a particle that a
//!   new triangle passes through, or nearly, is on neither side to within that motion.
//!   Measured on `tube_crack` (stop 40, `cramp run` to the stop, surfaces every 2 µs): the
//!   −x branch, running round the tube nearly normal to its axis, settled at z ≈ −3.5 mm,
//!   a plane of particle centres (2 × 2 × 2 per 2 mm cell); a triangle made at ≈ 111 µs
//!   passed 0.010 mm (0.5 % of a cell) from particle 419468, which then lay 0.005–0.012 mm
//!   above the crack surface as the crack's faces opened and closed by 0.006–0.016 mm, and
//!   at 123.8 µs was 0.001 mm below it: it had changed fields and the checked mode stopped
//!   the run (step 721). 2 % of a cell is 7 times that drift and a twenty-fifth of the
//!   half-cell particle spacing; a move of this size is far below the discretisation of
//!   the front (increments of a fraction of a cell). The crossing tests below see the
//!   moved points. A particle ahead of the new front, up to one increment beyond a new
//!   triangle's front edge on that triangle's extended plane, is kept clear too: the next
//!   advance builds its triangles from that edge, and their corners there are old by then.
//!   Measured on `tube_crack` with the clearance only on the new triangles (`cramp run`
//!   to its stop at step 739, surfaces every 2 µs): particle 414033 projected onto a new
//!   triangle with 0.81 of its weight on the corner made one advance earlier (the new
//!   corners carried 0.19 < [`CLEARANCE_MIN_WEIGHT`], so it asked nothing), lay 0.0009 mm
//!   from it, drifted ±0.01 mm and changed side at 126.9 µs. A crack particle on a
//!   symmetry plane stays on it, and a new triangle whose new corners carry less than
//!   [`CLEARANCE_MIN_WEIGHT`] of the particle's projection (the particle next to the old
//!   front edge, kept clear of the last advance's extended plane) asks nothing. Shifts are chosen per crack particle as the largest asked for (ties to
//!   the larger vector, component by component), so the result does not depend on the
//!   order of the points.
//!
//! New crack particles start with both crack surfaces at their position (as a new 2D tip
//! particle does). Everything is a deterministic function of the inputs.

use super::surface::{triangles_meet, TriangleSurface};
use super::three_d::Crack3;
use crate::dim::Vector3;
use std::collections::{BTreeMap, BTreeSet};

/// Split a front edge whose new length exceeds this many reference lengths.
pub const SPLIT_RATIO: f64 = 2.0;
/// Merge a front edge whose new length is below this many reference lengths.
pub const MERGE_RATIO: f64 = 0.25;

/// The largest kink the maximum hoop stress criterion can ask for (degrees), at K_I = 0:
/// θ_c = −2 atan(1/√2) = −70.529° (001 eq. 20; [`crate::fracture::criteria::hoop_stress_angle`]).
pub const HOOP_MAX_KINK_DEG: f64 = 70.528779;
/// Margin (degrees) over a criterion's largest kink in the fold test (module doc,
/// "turn-over").
pub const FOLD_MARGIN_DEG: f64 = 10.0;

/// The fold test's cosine (module doc, "turn-over") for a crack whose nodes all grow by
/// the maximum hoop stress criterion (`hoop_only`): cos(70.529° + 10°); otherwise 0 (a
/// dihedral above 90° only: the minimum strain-energy density criterion kinks by up to
/// acos((κ − 1)/6), 79.7–82.3° at ν = 0.3 and up to 90° as ν → ½, leaving no margin).
pub fn fold_cos(hoop_only: bool) -> f64 {
    if hoop_only {
        (HOOP_MAX_KINK_DEG + FOLD_MARGIN_DEG).to_radians().cos()
    } else {
        0.0
    }
}

/// The new surface's least distance to particle centres, in cells (module doc,
/// "clearance"; the growth driver's value).
pub const CLEARANCE_CELLS: f64 = 0.02;
/// The largest shift of a new crack particle in one round, in clearances (module doc,
/// "clearance").
pub const CLEARANCE_MAX_SHIFT: f64 = 4.0;
/// The least share of a particle's projection on a new triangle that its new corners
/// must carry for the triangle to be moved (module doc, "clearance").
pub const CLEARANCE_MIN_WEIGHT: f64 = 0.25;
/// Rounds of shifts (each from the positions the last left).
const CLEARANCE_ROUNDS: usize = 3;

/// Points the new surface of an advance keeps clear of (module doc, "clearance").
#[derive(Clone, Copy, Debug)]
pub struct Clearance<'a> {
    /// Particle centres near the front (any order).
    pub points: &'a [Vector3],
    /// The least distance from a new triangle's plane to a point that projects onto it.
    pub distance: f64,
    /// Symmetry planes (axis, level): a new crack particle on one stays on it.
    pub planes: &'a [(usize, f64)],
    /// How far beyond the new front the new triangles' planes are kept clear too (the
    /// next advance builds there; the driver's increment).
    pub ahead: f64,
}

impl Clearance<'_> {
    /// No clearance (the new crack particles stay where the moves put them).
    pub const NONE: Clearance<'static> = Clearance { points: &[], distance: 0.0, planes: &[], ahead: 0.0 };
}

/// What one advance did.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct AdvanceReport {
    /// Crack particles added (moved front nodes, quadrilateral centres, split points).
    pub new_vertices: usize,
    pub new_triangles: usize,
    pub splits: usize,
    pub merges: usize,
    /// Front nodes whose move was refused because a new triangle would meet the existing
    /// surface of this crack or another (module doc, "no crossing").
    pub refused: Vec<u32>,
    /// Front nodes whose move was refused only because a new triangle would meet another
    /// new triangle of this advance (the new strip folding over itself).
    pub folded: Vec<u32>,
    /// (old front node, its new crack particle) for every node that moved (merged nodes
    /// share one new particle).
    pub moved: Vec<(u32, u32)>,
    /// Front edges from a stopped node dropped instead of a sliver triangle (module doc,
    /// "sliver").
    pub dropped: usize,
    /// New crack particles moved to clear a particle centre (module doc, "clearance").
    pub cleared: usize,
    /// (point, new triangle) pairs still within half the clearance after the shifts.
    pub unclear: usize,
}

/// The triangles and front of one advance, before it is applied.
struct Plan {
    vertices: Vec<Vector3>,
    moved: Vec<(u32, u32)>,
    triangles: Vec<[u32; 3]>,
    /// New front edges with their reference lengths, in the old front's order.
    front: Vec<([u32; 2], f64)>,
    /// For each new triangle, the moved front nodes it came from (for refusals).
    sources: Vec<Vec<u32>>,
    /// For each new triangle, the index of the old front edge it was built on.
    edges: Vec<usize>,
    splits: usize,
    merges: usize,
    dropped: usize,
}

/// Advance the front of `crack`: front node `v` moves to `moves[&v]` (nodes not in
/// `moves` stay). `front_ref[k]` is the reference length of `crack.front[k]`; both are
/// replaced by the new front. `others` are the other cracks' surfaces (no new triangle may
/// meet them). Returns what was done; the crack's boundary flags are recomputed.
/// The fold test is the turn-over at 90° (`fold_cos` 0).
pub fn advance_front(crack: &mut Crack3, front_ref: &mut Vec<f64>, moves: &BTreeMap<u32, Vector3>, others: &[&TriangleSurface]) -> AdvanceReport {
    advance_front_stopped(crack, front_ref, moves, others, &BTreeSet::new(), 0.0, &Clearance::NONE)
}

/// [`advance_front`] with the front nodes stopped for good (`stopped`, which do not move):
/// a front edge from a stopped node whose other end moves leaves the front instead of
/// making a sliver triangle (module doc, "sliver"); a new triangle whose unit normal
/// makes a cosine below `fold_cos` with that of the old triangle behind its front edge is
/// a fold (module doc, "turn-over"; [`fold_cos`]); the new crack particles keep
/// `clearance` from the points it lists (module doc, "clearance").
pub fn advance_front_stopped(
    crack: &mut Crack3,
    front_ref: &mut Vec<f64>,
    moves: &BTreeMap<u32, Vector3>,
    others: &[&TriangleSurface],
    stopped: &BTreeSet<u32>,
    fold_cos: f64,
    clearance: &Clearance,
) -> AdvanceReport {
    assert_eq!(front_ref.len(), crack.front.len(), "one reference length per front edge");
    let mut moves = moves.clone();
    let mut refused = Vec::new();
    let mut folded = Vec::new();
    let mut cleared;
    let plan = loop {
        let drop = slivers(crack, &moves, stopped);
        let mut plan = plan(crack, front_ref, &moves, &drop);
        cleared = clear_points(crack, &mut plan, clearance);
        let (existing, new) = crossing_sources(crack, &plan, others, fold_cos);
        if existing.is_empty() && new.is_empty() {
            break plan;
        }
        for v in new.difference(&existing) {
            moves.remove(v);
            folded.push(*v);
        }
        for v in existing {
            moves.remove(&v);
            refused.push(v);
        }
    };
    refused.sort_unstable();
    folded.sort_unstable();
    let report = AdvanceReport {
        new_vertices: plan.vertices.len(),
        new_triangles: plan.triangles.len(),
        splits: plan.splits,
        merges: plan.merges,
        refused,
        folded,
        moved: plan.moved.clone(),
        dropped: plan.dropped,
        cleared: cleared.0,
        unclear: cleared.1,
    };
    let s = &mut crack.surface;
    s.vertices.extend(&plan.vertices);
    crack.above.extend(&plan.vertices);
    crack.below.extend(&plan.vertices);
    s.triangles.extend(&plan.triangles);
    crack.front = plan.front.iter().map(|(e, _)| *e).collect();
    *front_ref = plan.front.iter().map(|(_, l)| *l).collect();
    let (edges, verts) = crack.surface.boundary_flags();
    crack.boundary_edge = edges;
    crack.boundary_vertex = verts;
    report
}

/// Move the new crack particles of `plan` along the new triangles' normals until no point
/// of `clearance` that projects onto a new triangle lies within `clearance.distance` of
/// its plane (module doc, "clearance"). Returns (crack particles moved, (point, triangle)
/// pairs still within half the distance).
fn clear_points(crack: &Crack3, plan: &mut Plan, clearance: &Clearance) -> (usize, usize) {
    let dist = clearance.distance;
    if clearance.points.is_empty() || dist <= 0.0 || plan.triangles.is_empty() {
        return (0, 0);
    }
    let pts = &crack.surface.vertices;
    let first_new = pts.len() as u32;
    let mut moved = BTreeSet::new();
    let mut unclear = 0;
    let sorted = |e: [u32; 2]| [e[0].min(e[1]), e[0].max(e[1])];
    let new_front: BTreeSet<[u32; 2]> = plan.front.iter().map(|(e, _)| sorted(*e)).collect();
    for round in 0..=CLEARANCE_ROUNDS {
        // Per new crack particle: the largest shift asked for (ties to the larger vector).
        let mut want: BTreeMap<u32, Vector3> = BTreeMap::new();
        let mut close = 0;
        let pos = |n: u32| if n < first_new { pts[n as usize] } else { plan.vertices[(n - first_new) as usize] };
        for tri in &plan.triangles {
            let t = tri.map(pos);
            let normal = (t[1] - t[0]).cross(&(t[2] - t[0]));
            let area2 = normal.norm();
            if area2 == 0.0 {
                continue;
            }
            let n = normal / area2;
            // The corner opposite the triangle's edge on the new front, if it has one, with
            // the least weight of that corner at a point up to `ahead` beyond the edge.
            let beyond = (0..3)
                .find(|&k| new_front.contains(&sorted([tri[(k + 1) % 3], tri[(k + 2) % 3]])))
                .map(|k| (k, -clearance.ahead * (t[(k + 2) % 3] - t[(k + 1) % 3]).norm() / area2));
            let (lo, hi) = bbox(&t);
            let pad = Vector3::repeat(dist + if beyond.is_some() { clearance.ahead } else { 0.0 });
            let (lo, hi) = (lo - pad, hi + pad);
            for x in clearance.points {
                if (0..3).any(|a| x[a] < lo[a] || x[a] > hi[a]) {
                    continue;
                }
                let d = (x - t[0]).dot(&n);
                if d.abs() >= dist {
                    continue;
                }
                // Barycentric weights of the projection (sub-triangle areas over the whole).
                let q = x - n * d;
                let w = [(t[1] - q).cross(&(t[2] - q)).dot(&n), (t[2] - q).cross(&(t[0] - q)).dot(&n), (t[0] - q).cross(&(t[1] - q)).dot(&n)].map(|a| a / area2);
                let on = w.iter().all(|&wi| wi >= 0.0);
                // Ahead of the new front: on the triangle's plane extended past its front
                // edge by up to `ahead` (the next advance's new surface starts there).
                let ahead = !on && beyond.is_some_and(|(c, least)| (0..3).all(|k| w[k] >= if k == c { least } else { 0.0 }));
                if !on && !ahead {
                    continue;
                }
                if on && d.abs() < 0.5 * dist {
                    close += 1;
                }
                let w_new: f64 = (0..3).filter(|&k| tri[k] >= first_new).map(|k| w[k]).sum();
                if round == CLEARANCE_ROUNDS || w_new < CLEARANCE_MIN_WEIGHT {
                    continue;
                }
                // Move the plane away from the point: to the −n side of a point on +n.
                let s = if d >= 0.0 { d - dist } else { dist + d };
                let shift = n * (s / w_new).clamp(-CLEARANCE_MAX_SHIFT * dist, CLEARANCE_MAX_SHIFT * dist);
                for &k in tri.iter().filter(|&&k| k >= first_new) {
                    let e = want.entry(k - first_new).or_insert(shift);
                    let larger = (shift.norm(), shift.x, shift.y, shift.z).partial_cmp(&(e.norm(), e.x, e.y, e.z)) == Some(std::cmp::Ordering::Greater);
                    if larger {
                        *e = shift;
                    }
                }
            }
        }
        unclear = close;
        if want.is_empty() {
            break;
        }
        for (k, mut shift) in want {
            let v = &mut plan.vertices[k as usize];
            for &(a, level) in clearance.planes {
                if v[a] == level {
                    shift[a] = 0.0;
                }
            }
            *v += shift;
            moved.insert(k);
        }
    }
    (moved.len(), unclear)
}

/// Drop from the front every edge `e` with `leaves(e)`, with its reference length; the
/// driver's test is "both ends at the boundary" (001 §2.3.3: "If both ends of a
/// crack-front segment are at or outside the MPM material boundary, that segment is beyond
/// the material ... Such segments will be eliminated as a crack-front"). Returns how many
/// were dropped.
pub fn prune_front_where(crack: &mut Crack3, front_ref: &mut Vec<f64>, leaves: impl Fn(&[u32; 2]) -> bool) -> usize {
    let keep: Vec<bool> = crack.front.iter().map(|e| !leaves(e)).collect();
    let before = crack.front.len();
    let mut k = 0;
    crack.front.retain(|_| {
        k += 1;
        keep[k - 1]
    });
    let mut k = 0;
    front_ref.retain(|_| {
        k += 1;
        keep[k - 1]
    });
    before - crack.front.len()
}

/// Build the new vertices, triangles and front for `moves` (no crossing test).
fn plan(crack: &Crack3, front_ref: &[f64], moves: &BTreeMap<u32, Vector3>, drop: &BTreeSet<usize>) -> Plan {
    let pts = &crack.surface.vertices;
    let first_new = pts.len() as u32;
    let mut vertices: Vec<Vector3> = Vec::new();
    let add = |vertices: &mut Vec<Vector3>, x: Vector3| {
        vertices.push(x);
        first_new + vertices.len() as u32 - 1
    };
    // One new crack particle per moved front node (shared by its two front edges).
    let mut moved: BTreeMap<u32, u32> = BTreeMap::new();
    for (&v, &x) in moves {
        moved.insert(v, add(&mut vertices, x));
    }
    // Merges: both ends moved and the new edge shorter than MERGE_RATIO·L along the old
    // one (a turned-over edge has a negative projection). A node in two
    // merges (two short edges in a row) joins both into one particle: union by the lower
    // new index, position the mean of the members' new positions.
    let mut parent: BTreeMap<u32, u32> = moved.values().map(|&n| (n, n)).collect();
    fn root(parent: &BTreeMap<u32, u32>, mut n: u32) -> u32 {
        while parent[&n] != n {
            n = parent[&n];
        }
        n
    }
    let mut merged_edge = vec![false; crack.front.len()];
    let mut merges = 0;
    for (k, &[a, b]) in crack.front.iter().enumerate() {
        if let (Some(&na), Some(&nb)) = (moved.get(&a), moved.get(&b)) {
            let (xa, xb) = (vertices[(na - first_new) as usize], vertices[(nb - first_new) as usize]);
            let old = pts[b as usize] - pts[a as usize];
            if (xb - xa).dot(&old) < MERGE_RATIO * front_ref[k] * old.norm() {
                let (ra, rb) = (root(&parent, na), root(&parent, nb));
                if ra != rb {
                    let (lo, hi) = (ra.min(rb), ra.max(rb));
                    parent.insert(hi, lo);
                }
                merged_edge[k] = true;
                merges += 1;
            }
        }
    }
    if merges > 0 {
        let mut groups: BTreeMap<u32, Vec<u32>> = BTreeMap::new();
        for &n in moved.values() {
            groups.entry(root(&parent, n)).or_default().push(n);
        }
        for (r, members) in &groups {
            if members.len() > 1 {
                // Pairwise midpoint for two members (symmetric in the pair), mean otherwise.
                let x = if members.len() == 2 {
                    (vertices[(members[0] - first_new) as usize] + vertices[(members[1] - first_new) as usize]) * 0.5
                } else {
                    members.iter().fold(Vector3::zeros(), |s, &n| s + vertices[(n - first_new) as usize]) / members.len() as f64
                };
                vertices[(r - first_new) as usize] = x;
            }
        }
        for n in moved.values_mut() {
            *n = root(&parent, *n);
        }
    }
    let pos = |vertices: &Vec<Vector3>, n: u32| if n < first_new { pts[n as usize] } else { vertices[(n - first_new) as usize] };
    let mut triangles = Vec::new();
    let mut sources = Vec::new();
    let mut edges = Vec::new();
    let mut front = Vec::new();
    let mut splits = 0;
    let mut dropped = 0;
    for (k, &[a, b]) in crack.front.iter().enumerate() {
        let l = front_ref[k];
        match (moved.get(&a).copied(), moved.get(&b).copied()) {
            (None, None) => front.push(([a, b], l)),
            (Some(_), None) | (None, Some(_)) if drop.contains(&k) => dropped += 1,
            (Some(na), None) => {
                triangles.push([b, a, na]);
                sources.push(vec![a]);
                edges.push(k);
                front.push(([na, b], l));
            }
            (None, Some(nb)) => {
                triangles.push([b, a, nb]);
                sources.push(vec![b]);
                edges.push(k);
                front.push(([a, nb], l));
            }
            (Some(na), Some(nb)) if merged_edge[k] || na == nb => {
                triangles.push([b, a, na]);
                sources.push(vec![a, b]);
                edges.push(k);
            }
            (Some(na), Some(nb)) => {
                let (xa, xb) = (pos(&vertices, na), pos(&vertices, nb));
                let c = add(&mut vertices, ((pts[a as usize] + pts[b as usize]) + (xa + xb)) * 0.25);
                let quad = if across_moves(xb - xa, (xa - pts[a as usize]) + (xb - pts[b as usize])) > SPLIT_RATIO * l {
                    splits += 1;
                    let p = add(&mut vertices, (xa + xb) * 0.5);
                    front.push(([na, p], l));
                    front.push(([p, nb], l));
                    vec![[b, a, c], [a, na, c], [na, p, c], [p, nb, c], [nb, b, c]]
                } else {
                    front.push(([na, nb], l));
                    vec![[b, a, c], [a, na, c], [na, nb, c], [nb, b, c]]
                };
                for t in quad {
                    triangles.push(t);
                    sources.push(vec![a, b]);
                    edges.push(k);
                }
            }
        }
    }
    Plan { vertices, moved: moved.into_iter().collect(), triangles, front, sources, edges, splits, merges, dropped }
}

/// Smallest angle of a one-end triangle (b, a, a′) from a stopped node b below which the
/// front edge b–a leaves the front instead (module doc, "sliver").
pub const SLIVER_ANGLE_DEG: f64 = 15.0;

/// The front edges (indices) whose one end is `stopped` and does not move while the other
/// moves, and whose one-end triangle would have an angle below [`SLIVER_ANGLE_DEG`]; not
/// those of a moving node all of whose front edges are such (it would be left with no
/// triangle).
fn slivers(crack: &Crack3, moves: &BTreeMap<u32, Vector3>, stopped: &BTreeSet<u32>) -> BTreeSet<usize> {
    let pts = &crack.surface.vertices;
    let mut out = BTreeSet::new();
    if stopped.is_empty() {
        return out;
    }
    let mut count: BTreeMap<u32, (usize, usize)> = BTreeMap::new();
    for &[a, b] in &crack.front {
        for v in [a, b] {
            count.entry(v).or_default().0 += 1;
        }
    }
    for (k, &[a, b]) in crack.front.iter().enumerate() {
        let (fixed, moving) = match (moves.get(&a), moves.get(&b)) {
            (Some(_), None) => (b, a),
            (None, Some(_)) => (a, b),
            _ => continue,
        };
        if !stopped.contains(&fixed) {
            continue;
        }
        let tri = [pts[fixed as usize], pts[moving as usize], moves[&moving]];
        if min_angle(&tri) < SLIVER_ANGLE_DEG.to_radians() {
            out.insert(k);
            count.entry(moving).or_default().1 += 1;
        }
    }
    let keep: BTreeSet<u32> = count.iter().filter(|(_, &(all, sl))| sl > 0 && sl == all).map(|(&v, _)| v).collect();
    if !keep.is_empty() {
        out.retain(|&k| !crack.front[k].iter().any(|v| keep.contains(v)));
    }
    out
}

/// The smallest interior angle (radians) of a triangle; 0 for a degenerate one.
pub fn min_angle(t: &[Vector3; 3]) -> f64 {
    let mut m = std::f64::consts::PI;
    for i in 0..3 {
        let (u, v) = (t[(i + 1) % 3] - t[i], t[(i + 2) % 3] - t[i]);
        let (lu, lv) = (u.norm(), v.norm());
        if lu == 0.0 || lv == 0.0 {
            return 0.0;
        }
        m = m.min(u.cross(&v).norm().atan2(u.dot(&v)));
    }
    m
}

/// The length of the new edge `e` = b′ − a′ normal to `m`, its ends' summed moves (module
/// doc, "split"); |e| when m is zero.
fn across_moves(e: Vector3, m: Vector3) -> f64 {
    match m.try_normalize(0.0) {
        Some(u) => (e - u * u.dot(&e)).norm(),
        None => e.norm(),
    }
}

/// Axis-aligned bounding box of a triangle.
fn bbox(t: &[Vector3; 3]) -> (Vector3, Vector3) {
    (t[0].inf(&t[1]).inf(&t[2]), t[0].sup(&t[1]).sup(&t[2]))
}

/// Whether two boxes overlap (closed).
fn overlap(a: &(Vector3, Vector3), b: &(Vector3, Vector3)) -> bool {
    (0..3).all(|d| a.0[d] <= b.1[d] && b.0[d] <= a.1[d])
}

/// The indices of the candidate triangles `new` (corners at `new_idx`, crack-particle
/// indices of `crack`, new ones past its end) that meet an existing triangle of `crack` not
/// sharing a corner index with them (a shared corner is adjacency) or any triangle of
/// `others` (no shared corners there).
fn meeting_surfaces(crack: &Crack3, new: &[[Vector3; 3]], new_idx: &[[u32; 3]], others: &[&TriangleSurface]) -> BTreeSet<usize> {
    let pts = &crack.surface.vertices;
    let new_boxes: Vec<_> = new.iter().map(bbox).collect();
    let mut meets = BTreeSet::new();
    for tri in &crack.surface.triangles {
        let old = tri.map(|n| pts[n as usize]);
        let ob = bbox(&old);
        for (i, nt) in new_idx.iter().enumerate() {
            if overlap(&ob, &new_boxes[i]) && !nt.iter().any(|n| tri.contains(n)) && triangles_meet(&new[i], &old) {
                meets.insert(i);
            }
        }
    }
    for s in others {
        for tri in &s.triangles {
            let old = tri.map(|n| s.vertices[n as usize]);
            let ob = bbox(&old);
            for i in 0..new.len() {
                if overlap(&ob, &new_boxes[i]) && triangles_meet(&new[i], &old) {
                    meets.insert(i);
                }
            }
        }
    }
    meets
}

/// The moved front nodes whose new triangles meet an existing triangle (of this crack or
/// `others`), and those whose new triangles meet another new triangle, other than at
/// shared corners: (existing, new).
fn crossing_sources(crack: &Crack3, plan: &Plan, others: &[&TriangleSurface], fold_cos: f64) -> (BTreeSet<u32>, BTreeSet<u32>) {
    let pts = &crack.surface.vertices;
    let first_new = pts.len() as u32;
    let pos = |n: u32| if n < first_new { pts[n as usize] } else { plan.vertices[(n - first_new) as usize] };
    let new_tris: Vec<[Vector3; 3]> = plan.triangles.iter().map(|t| t.map(pos)).collect();
    let new_boxes: Vec<_> = new_tris.iter().map(bbox).collect();
    let mut existing = BTreeSet::new();
    for i in meeting_surfaces(crack, &new_tris, &plan.triangles, others) {
        existing.extend(plan.sources[i].iter().copied());
    }
    // New triangles among themselves.
    let mut new = BTreeSet::new();
    let mut flag = |i: usize| new.extend(plan.sources[i].iter().copied());
    // Turned over (module doc, "turn-over"): a new triangle whose normal makes a dihedral
    // angle above acos(fold_cos) with that of the old triangle holding its front edge.
    let front_pairs: BTreeMap<[u32; 2], usize> = crack.front.iter().enumerate().map(|(k, &[a, b])| ([a.min(b), a.max(b)], k)).collect();
    let mut behind: BTreeMap<usize, usize> = BTreeMap::new();
    for (t, tri) in crack.surface.triangles.iter().enumerate() {
        for e in 0..3 {
            let (p, q) = (tri[e], tri[(e + 1) % 3]);
            if let Some(&k) = front_pairs.get(&[p.min(q), p.max(q)]) {
                behind.entry(k).or_insert(t);
            }
        }
    }
    for (i, nt) in new_tris.iter().enumerate() {
        if let Some(&t) = behind.get(&plan.edges[i]) {
            let n_new = (nt[1] - nt[0]).cross(&(nt[2] - nt[0]));
            let n_old = crack.surface.normal(t);
            if n_new.dot(&n_old) < fold_cos * n_new.norm() * n_old.norm() {
                flag(i);
            }
        }
    }
    for i in 0..plan.triangles.len() {
        for j in i + 1..plan.triangles.len() {
            if overlap(&new_boxes[i], &new_boxes[j])
                && !plan.triangles[i].iter().any(|n| plan.triangles[j].contains(n))
                && triangles_meet(&new_tris[i], &new_tris[j])
            {
                flag(i);
                flag(j);
            }
        }
    }
    (existing, new)
}

/// The largest material angle (degrees) at a front node that [`fill_notches`] fills.
pub const NOTCH_ANGLE_DEG: f64 = 45.0;

/// The material angle at front node `v` whose front edges are p→v and v→n (directed with
/// the crack on their left seen from above, `normal` the crack's normal there): 2π less the
/// angle the crack fills at v, the angle from n − v counter-clockwise about `normal` to
/// p − v (in [0, 2π)). π on a straight front, above π where v leads its neighbours (every
/// node of a convex front), below where it lags them.
pub fn material_angle(p: Vector3, v: Vector3, n: Vector3, normal: Vector3) -> f64 {
    let (a, b) = (p - v, n - v);
    let crack = normal.normalize().dot(&b.cross(&a)).atan2(b.dot(&a)).rem_euclid(std::f64::consts::TAU);
    std::f64::consts::TAU - crack
}

/// The front nodes (not in `skip`) at the apex of a tongue of material narrower than
/// `max_angle` ([`fill_notches`]), most acute first: (angle, node, incoming front edge,
/// outgoing front edge).
fn notches(crack: &Crack3, max_angle: f64, skip: &BTreeSet<u32>) -> Vec<(f64, u32, usize, usize)> {
    let pts = &crack.surface.vertices;
    let mut incoming: BTreeMap<u32, Vec<usize>> = BTreeMap::new();
    let mut outgoing: BTreeMap<u32, Vec<usize>> = BTreeMap::new();
    for (k, &[a, b]) in crack.front.iter().enumerate() {
        outgoing.entry(a).or_default().push(k);
        incoming.entry(b).or_default().push(k);
    }
    let mut normals: BTreeMap<u32, Vector3> = BTreeMap::new();
    for (t, tri) in crack.surface.triangles.iter().enumerate() {
        let n = crack.surface.normal(t);
        let len = n.norm();
        if len > 0.0 {
            for v in tri.iter().filter(|v| incoming.contains_key(v)) {
                *normals.entry(*v).or_insert_with(Vector3::zeros) += n / len;
            }
        }
    }
    let mut candidates: Vec<(f64, u32, usize, usize)> = Vec::new();
    for (&v, ins) in &incoming {
        let (Some(outs), Some(normal)) = (outgoing.get(&v), normals.get(&v)) else { continue };
        if ins.len() != 1 || outs.len() != 1 || skip.contains(&v) {
            continue;
        }
        let (ki, ko) = (ins[0], outs[0]);
        let (p, n) = (crack.front[ki][0], crack.front[ko][1]);
        if p == n {
            continue;
        }
        let angle = material_angle(pts[p as usize], pts[v as usize], pts[n as usize], *normal);
        if angle < max_angle {
            candidates.push((angle, v, ki, ko));
        }
    }
    candidates.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    candidates
}

/// Whether [`fill_notches`] has a node to look at (a tongue narrower than `max_angle`):
/// the driver asks before it copies the crack.
pub fn has_notch(crack: &Crack3, max_angle: f64) -> bool {
    !notches(crack, max_angle, &BTreeSet::new()).is_empty()
}

/// Notch rule (not in the paper; issue 17, case `tube_crack`): a front node v with one
/// front edge in, p→v, and one out, v→n, where the material between the two edges makes
/// an angle below `max_angle` (radians; [`material_angle`], the normal the mean unit
/// normal of v's triangles) is the apex of a tongue of material reaching back into the
/// crack. The triangle (v, p, n) is added to the crack, v leaves the front and p→n takes
/// the two edges' place (reference length the smaller of theirs). Most acute first (ties
/// by vertex index), repeated until no node qualifies; a fill is skipped when (v, p, n) is
/// degenerate, when p–n is already an edge of the surface, or when the triangle meets an
/// existing triangle of this crack (not sharing a corner) or of another crack. Returns the
/// nodes taken off the front, in the order filled.
///
/// Why: the tongue's apex cannot move. Its front tangent (the sum of the unit vectors
/// along its two edges, which nearly cancel) and so its heading are skewed, and every
/// triangle it would make runs through the crack beside it or stands on end (refused at a
/// crack, or as a fold); its neighbours then fan one-end triangles about it. Measured on
/// `tube_crack` (stop 38, main 05ab9c3, surface at step 618): front nodes 2843 (74.3°
/// round the tube, r = 42.4 mm) and 2858 (75.6°) of the +x branch, unmoved from step 330
/// to the end with K_eq = 3850–8000 (K_Ic = 632), at the apex of a ligament 2.4 mm high on
/// the inner face that the rest of the front had passed (material angles 5° and, once
/// 2843 is filled, 28°); the check `runs_round` read 74.3° for a branch that had run
/// 190° round. 45°: a front growing node by node is a staircase of one increment, and a
/// node lagging both neighbours by one increment at the default spacing (both half a cell)
/// has a material angle of 90°; a tongue under 45° is narrower than its own length over
/// the last cell, below what the grid resolves.
pub fn fill_notches(crack: &mut Crack3, front_ref: &mut Vec<f64>, others: &[&TriangleSurface], max_angle: f64) -> Vec<u32> {
    assert_eq!(front_ref.len(), crack.front.len(), "one reference length per front edge");
    let mut filled = Vec::new();
    let mut skip: BTreeSet<u32> = BTreeSet::new();
    loop {
        let candidates = notches(crack, max_angle, &skip);
        let Some(&(_, v, ki, ko)) = candidates.first() else { break };
        let pts = &crack.surface.vertices;
        let (p, n) = (crack.front[ki][0], crack.front[ko][1]);
        let tri = [v, p, n];
        let t = tri.map(|i| pts[i as usize]);
        let degenerate = (t[1] - t[0]).cross(&(t[2] - t[0])).norm() == 0.0;
        let has_edge = crack.surface.triangles.iter().any(|u| u.contains(&p) && u.contains(&n));
        if degenerate || has_edge || !meeting_surfaces(crack, &[t], &[tri], others).is_empty() {
            skip.insert(v);
            continue;
        }
        let reference = front_ref[ki].min(front_ref[ko]);
        crack.surface.triangles.push(tri);
        crack.front[ki] = [p, n];
        front_ref[ki] = reference;
        crack.front.remove(ko);
        front_ref.remove(ko);
        let (edges, verts) = crack.surface.boundary_flags();
        crack.boundary_edge = edges;
        crack.boundary_vertex = verts;
        filled.push(v);
    }
    filled
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::crack::ContactLaw;

    /// A rectangular crack in z = 0 from x = 0 to 1, y = −n/2 to n/2 (so that y → −y
    /// mirrors it exactly), as 2n triangles, with its front the edge x = 1 (directed so the
    /// surface is on its left seen from +z).
    fn strip(n: usize) -> (Crack3, Vec<f64>) {
        let mut v = Vec::new();
        for j in 0..=n {
            let y = j as f64 - 0.5 * n as f64;
            v.push(Vector3::new(0.0, y, 0.0));
            v.push(Vector3::new(1.0, y, 0.0));
        }
        let mut t = Vec::new();
        for j in 0..n as u32 {
            let (a0, a1, b0, b1) = (2 * j, 2 * j + 1, 2 * j + 2, 2 * j + 3);
            t.push([a0, a1, b1]);
            t.push([a0, b1, b0]);
        }
        let s = TriangleSurface::new(v, t).unwrap();
        let front: Vec<[u32; 2]> = (0..n as u32).map(|j| [2 * j + 1, 2 * j + 3]).collect();
        // Check the front direction against the boundary edges.
        let b = s.boundary_edges();
        for e in &front {
            assert!(b.iter().any(|&(x, y, _)| [x, y] == *e), "front edge {e:?} is not a directed boundary edge");
        }
        let refs = vec![1.0; front.len()];
        (Crack3::new(s, ContactLaw::None, 0.0, 0.0, front), refs)
    }

    /// Every front node of `c` moved to `to(its position)`.
    fn moves_of(c: &Crack3, to: impl Fn(Vector3) -> Vector3) -> BTreeMap<u32, Vector3> {
        c.front.iter().flatten().map(|&v| (v, to(c.surface.vertices[v as usize]))).collect()
    }

    fn area(s: &TriangleSurface) -> f64 {
        (0..s.triangles.len()).map(|t| s.normal(t).norm() * 0.5).sum()
    }

    fn check_valid(c: &Crack3) {
        TriangleSurface::new(c.surface.vertices.clone(), c.surface.triangles.clone()).expect("consistently oriented surface");
        c.surface.check_crack().expect("no self-intersection");
        let b = c.surface.boundary_edges();
        for e in &c.front {
            assert!(b.iter().any(|&(x, y, _)| [x, y] == *e), "front edge {e:?} is not a directed boundary edge");
        }
        for t in 0..c.surface.triangles.len() {
            assert!(c.surface.normal(t).z > 0.0, "triangle {t} faces down");
        }
    }

    /// Every front node moved by d along x: four triangles per segment, the new front the
    /// straight line x = 1 + d, the area grows by exactly n·d.
    #[test]
    fn straight_front_all_nodes_move() {
        let n = 4;
        let (mut c, mut refs) = strip(n);
        let a0 = area(&c.surface);
        let moves = moves_of(&c, |x| x + Vector3::new(0.5, 0.0, 0.0));
        let r = advance_front(&mut c, &mut refs, &moves, &[]);
        assert_eq!((r.new_vertices, r.new_triangles, r.splits, r.merges), (n + 1 + n, 4 * n, 0, 0));
        assert!(r.refused.is_empty());
        check_valid(&c);
        assert_eq!(c.front.len(), n);
        for e in &c.front {
            assert!(e.iter().all(|&v| c.surface.vertices[v as usize].x == 1.5));
        }
        assert!((area(&c.surface) - a0 - 0.5 * n as f64).abs() < 1e-12);
        assert_eq!(c.above.len(), c.surface.vertices.len());
        assert_eq!(refs, vec![1.0; n]);
        assert_eq!(r.moved.len(), n + 1);
        // The two end nodes stopped at a boundary, and one interior node: only the edges
        // with both ends stopped leave the front.
        let new_of = |old: u32| r.moved.iter().find(|m| m.0 == old).unwrap().1;
        let ends: std::collections::BTreeSet<u32> = [new_of(1), new_of(3), new_of(2 * n as u32 + 1)].into();
        assert_eq!(prune_front_where(&mut c, &mut refs, |e| ends.contains(&e[0]) && ends.contains(&e[1])), 1, "only the edge from node 1 to node 3 has both ends stopped");
        assert_eq!((c.front.len(), refs.len()), (n - 1, n - 1));
    }

    /// One end of a segment moves: one triangle (001 Fig. 3, ABB′).
    /// The signed distances from `x` to the planes of the triangles of `c` from `first` on
    /// that it projects onto.
    fn distances_to_new(c: &Crack3, first: usize, x: Vector3) -> Vec<f64> {
        let s = &c.surface;
        s.triangles[first..]
            .iter()
            .filter_map(|tri| {
                let t = tri.map(|k| s.vertices[k as usize]);
                let n = (t[1] - t[0]).cross(&(t[2] - t[0])).normalize();
                let d = (x - t[0]).dot(&n);
                let q = x - n * d;
                (0..3).all(|k| (t[(k + 1) % 3] - q).cross(&(t[(k + 2) % 3] - q)).dot(&n) >= 0.0).then_some(d)
            })
            .collect()
    }

    #[test]
    fn new_surface_clears_particle_centres() {
        // Particles just above and below the strip the front sweeps, one far off it and one
        // next to the old surface; the front moves by half a unit along x.
        let points = [Vector3::new(1.25, 0.3, 0.001), Vector3::new(1.3, -0.6, -0.005), Vector3::new(1.2, 0.1, 0.5), Vector3::new(0.5, 0.0, 0.001)];
        let dist = 0.02;
        let run = |points: &[Vector3], planes: &[(usize, f64)]| {
            let (mut c, mut refs) = strip(2);
            let first = c.surface.triangles.len();
            let moves = moves_of(&c, |x| x + Vector3::new(0.5, 0.0, 0.0));
            let r = advance_front_stopped(&mut c, &mut refs, &moves, &[], &BTreeSet::new(), 0.0, &Clearance { points, distance: dist, planes, ahead: 0.0 });
            check_valid(&c);
            (c, first, r)
        };
        let (c, first, r) = run(&points, &[]);
        // Without the clearance both particles lie within it.
        let (mut bare, mut refs) = strip(2);
        let moves = moves_of(&bare, |x| x + Vector3::new(0.5, 0.0, 0.0));
        advance_front(&mut bare, &mut refs, &moves, &[]);
        for x in &points[..2] {
            assert!(distances_to_new(&bare, first, *x).iter().any(|d| d.abs() < dist), "{x:?} is near the unmoved strip");
        }
        // With it, each keeps its side and the clearance (to 10⁻³ of it: a shift tilts the
        // triangle a little, which the next rounds take up), by a move of at most
        // CLEARANCE_MAX_SHIFT clearances.
        assert!(r.cleared > 0 && r.unclear == 0, "{r:?}");
        for (x, side) in [(points[0], 1.0), (points[1], -1.0)] {
            let d = distances_to_new(&c, first, x);
            assert!(!d.is_empty() && d.iter().all(|d| d * side >= dist * (1.0 - 1e-3)), "{x:?}: distances {d:?}");
        }
        let old = c.surface.vertices.len() - r.new_vertices;
        for (k, v) in c.surface.vertices[old..].iter().enumerate() {
            let m = bare.surface.vertices[old + k];
            assert!((v - m).norm() <= CLEARANCE_MAX_SHIFT * dist * (1.0 + 1e-12) , "crack particle {k} moved from {m:?} to {v:?}");
            assert_eq!(c.above[old + k], *v);
            assert_eq!(c.below[old + k], *v);
        }
        // The far particle and the one by the old surface ask nothing: alone, nothing moves.
        let (alone, _, r2) = run(&points[2..], &[]);
        assert_eq!((r2.cleared, alone.surface.vertices.clone()), (0, bare.surface.vertices.clone()));
        // The points' order does not matter, to the bit.
        let reversed: Vec<Vector3> = points.iter().rev().copied().collect();
        let (c2, _, _) = run(&reversed, &[]);
        assert_eq!(c2.surface.vertices, c.surface.vertices);
        // A crack particle on a symmetry plane stays on it: here the plane of the crack.
        let (pinned, _, _) = run(&points, &[(2, 0.0)]);
        assert!(pinned.surface.vertices.iter().all(|v| v.z == 0.0));
        // A particle a fifth of a unit ahead of the new front (x = 1.5), just below its
        // plane: left alone without `ahead`, kept clear of the extended plane with it.
        let x = Vector3::new(1.7, 0.4, -0.003);
        for (ahead, cleared) in [(0.0, false), (0.5, true)] {
            let (mut c, mut refs) = strip(2);
            let moves = moves_of(&c, |x| x + Vector3::new(0.5, 0.0, 0.0));
            let r = advance_front_stopped(&mut c, &mut refs, &moves, &[], &BTreeSet::new(), 0.0, &Clearance { points: &[x], distance: dist, planes: &[], ahead });
            assert_eq!(r.cleared > 0, cleared, "ahead {ahead}: {r:?}");
            // The extended plane of the triangles at the front, at the particle.
            let front_tris: Vec<f64> = c.surface.triangles[first..]
                .iter()
                .filter(|t| t.iter().filter(|&&k| c.front.iter().flatten().any(|&f| f == k)).count() == 2)
                .map(|t| {
                    let v = t.map(|k| c.surface.vertices[k as usize]);
                    let n = (v[1] - v[0]).cross(&(v[2] - v[0])).normalize();
                    (x - v[0]).dot(&n)
                })
                .collect();
            if cleared {
                assert!(front_tris.iter().all(|d| *d <= -dist * (1.0 - 1e-3)), "{front_tris:?}");
            }
        }
    }

    #[test]
    fn one_end_moves_one_triangle() {
        let (mut c, mut refs) = strip(2);
        let v = c.front[0][0];
        let moves = BTreeMap::from([(v, c.surface.vertices[v as usize] + Vector3::new(0.4, 0.0, 0.0))]);
        let r = advance_front(&mut c, &mut refs, &moves, &[]);
        assert_eq!((r.new_vertices, r.new_triangles), (1, 1));
        check_valid(&c);
        assert_eq!(c.front.len(), 2);
    }

    /// Notch rule: a front node left four increments behind both neighbours (spacing 1,
    /// material angle 2 atan(1/4) = 28°) is filled with the triangle (node, previous,
    /// next) and leaves the front; one left a single increment behind (90°) is not, nor is
    /// any node of a straight front.
    #[test]
    fn tongue_of_material_is_filled_at_its_apex() {
        let (mut c, mut refs) = strip(6);
        assert!(fill_notches(&mut c, &mut refs, &[], NOTCH_ANGLE_DEG.to_radians()).is_empty(), "a straight front has no notch");
        for (lag, fills) in [(4.0, true), (1.0, false)] {
            let (mut c, mut refs) = strip(6);
            let stay = 7; // the front node at y = 0
            let moves = moves_of(&c, |x| x + Vector3::new(lag, 0.0, 0.0)).into_iter().filter(|&(v, _)| v != stay).collect();
            let r = advance_front(&mut c, &mut refs, &moves, &[]);
            assert!(r.refused.is_empty() && r.folded.is_empty());
            let new_of = |v: u32| r.moved.iter().find(|m| m.0 == v).unwrap().1;
            let (p, n) = (new_of(5), new_of(9));
            let pts = &c.surface.vertices;
            let angle = material_angle(pts[p as usize], pts[stay as usize], pts[n as usize], Vector3::z());
            let triangles = c.surface.triangles.len();
            let filled = fill_notches(&mut c, &mut refs, &[], NOTCH_ANGLE_DEG.to_radians());
            check_valid(&c);
            assert_eq!(refs.len(), c.front.len());
            if fills {
                assert!((angle - 2.0 * 0.25f64.atan()).abs() < 1e-12, "angle {angle}");
                assert_eq!(filled, vec![stay]);
                assert_eq!(c.surface.triangles.len(), triangles + 1);
                assert!(c.front.contains(&[p, n]) && !c.front.iter().flatten().any(|&v| v == stay));
            } else {
                assert!(filled.is_empty(), "lag {lag}: filled {filled:?} at angle {angle}");
                assert_eq!(c.surface.triangles.len(), triangles);
            }
        }
    }

    /// The material angle: π on a straight front, above π at a node of a convex crack's
    /// front (a penny's) and where the node leads its neighbours.
    #[test]
    fn material_angle_of_straight_convex_and_leading_fronts() {
        let z = Vector3::z();
        let pi = std::f64::consts::PI;
        // Straight front along +y with the crack on its left (x < 1).
        let a = material_angle(Vector3::new(1.0, -1.0, 0.0), Vector3::new(1.0, 0.0, 0.0), Vector3::new(1.0, 1.0, 0.0), z);
        assert!((a - pi).abs() < 1e-15);
        // Penny of radius 1 about the origin, front counter-clockwise seen from +z.
        let at = |deg: f64| Vector3::new(deg.to_radians().cos(), deg.to_radians().sin(), 0.0);
        let a = material_angle(at(-10.0), at(0.0), at(10.0), z);
        assert!((a - (pi + 10f64.to_radians())).abs() < 1e-12, "{a}");
        // A node one unit ahead of neighbours one unit away: 90° of crack, 270° of material.
        let a = material_angle(Vector3::new(1.0, -1.0, 0.0), Vector3::new(2.0, 0.0, 0.0), Vector3::new(1.0, 1.0, 0.0), z);
        assert!((a - 1.5 * pi).abs() < 1e-12, "{a}");
    }

    /// Turn-over (module doc): a front end moved back behind its front edge and past its
    /// neighbour along it (lifted off the plane, so that its triangle meets no old one)
    /// would make a triangle facing against the surface behind it: refused as a fold.
    #[test]
    fn turned_over_triangle_is_a_fold() {
        let (mut c, mut refs) = strip(2);
        let [a, b] = c.front[0];
        let (xa, xb) = (c.surface.vertices[a as usize], c.surface.vertices[b as usize]);
        // Behind the front line x = 1, beyond b along the edge a → b, 0.02 above the plane.
        let to = xb + (xb - xa) * 0.5 + Vector3::new(-0.1, 0.0, 0.02);
        let moves = BTreeMap::from([(a, to)]);
        let r = advance_front(&mut c, &mut refs, &moves, &[]);
        assert_eq!((r.folded.clone(), r.refused.clone(), r.new_triangles), (vec![a], vec![], 0));
        check_valid(&c);
        // The same move ahead of the front line makes its triangle.
        let (mut c, mut refs) = strip(2);
        let moves = BTreeMap::from([(a, xb + (xb - xa) * 0.5 + Vector3::new(0.1, 0.0, 0.02))]);
        let r = advance_front(&mut c, &mut refs, &moves, &[]);
        assert_eq!((r.folded.len(), r.new_triangles), (0, 1));
    }

    /// A segment stretched past twice its reference length is split (five triangles, two
    /// front edges); one shrunk below a quarter is merged into a point (one triangle).
    #[test]
    fn split_and_merge() {
        let (mut c, mut refs) = strip(3);
        // Fan the middle segment's ends apart: y of its ends −0.8 and +0.8.
        let [a, b] = c.front[1];
        let xa = c.surface.vertices[a as usize];
        let xb = c.surface.vertices[b as usize];
        let moves = BTreeMap::from([(a, xa + Vector3::new(0.5, -0.8, 0.0)), (b, xb + Vector3::new(0.5, 0.8, 0.0))]);
        let r = advance_front(&mut c, &mut refs, &moves, &[]);
        assert_eq!(r.splits, 1);
        // Middle: 5 triangles; neighbours: one end moves, 1 triangle each.
        assert_eq!(r.new_triangles, 5 + 2);
        assert_eq!(c.front.len(), 4);
        check_valid(&c);

        let (mut c, mut refs) = strip(3);
        let [a, b] = c.front[1];
        let xa = c.surface.vertices[a as usize];
        let xb = c.surface.vertices[b as usize];
        let moves = BTreeMap::from([(a, xa + Vector3::new(0.5, 0.45, 0.0)), (b, xb + Vector3::new(0.5, -0.45, 0.0))]);
        let r = advance_front(&mut c, &mut refs, &moves, &[]);
        assert_eq!(r.merges, 1);
        // Middle: 1 triangle (b, a, m); neighbours 1 each.
        assert_eq!(r.new_triangles, 3);
        assert_eq!(c.front.len(), 2, "the merged edge left the front");
        let m = c.front[0][1];
        assert_eq!(c.front[1][0], m, "the neighbours meet at the merged point");
        assert_eq!(c.surface.vertices[m as usize], Vector3::new(1.5, 0.0, 0.0));
        check_valid(&c);
    }

    /// A second crack standing across x = 1.25, y ∈ [−1.5, −0.3], z ∈ [−1, 1] (two triangles).
    fn wall_across_lower_half() -> TriangleSurface {
        TriangleSurface::new(
            vec![Vector3::new(1.25, -1.5, -1.0), Vector3::new(1.25, -0.3, -1.0), Vector3::new(1.25, -0.3, 1.0), Vector3::new(1.25, -1.5, 1.0)],
            vec![[0, 1, 2], [0, 2, 3]],
        )
        .unwrap()
    }

    /// A move that would fold the new surface back across the crack is refused: that
    /// node stays, the rest advance.
    #[test]
    fn crossing_move_is_refused() {
        let (mut c, mut refs) = strip(2);
        // A second crack standing across x = 1.25, y ∈ [−1.5, −0.3], z ∈ [−1, 1]: the new
        // surface of the front edge y ∈ [−1, 0] would cut it, that of y ∈ [0, 1] not.
        let wall = wall_across_lower_half();
        let moves = moves_of(&c, |x| x + Vector3::new(0.5, 0.0, 0.0));
        let r = advance_front(&mut c, &mut refs, &moves, &[&wall]);
        assert_eq!(r.refused, vec![1, 3], "the nodes at y = −1 and 0 stay");
        assert_eq!(r.new_triangles, 1, "the edge y ∈ [0, 1] grows by one triangle (only its upper end moves)");
        check_valid(&c);
        for (t, tri) in c.surface.triangles.iter().enumerate() {
            assert!(!triangles_meet(&tri.map(|n| c.surface.vertices[n as usize]), &[wall.vertices[0], wall.vertices[1], wall.vertices[2]]), "triangle {t}");
            assert!(!triangles_meet(&tri.map(|n| c.surface.vertices[n as usize]), &[wall.vertices[0], wall.vertices[2], wall.vertices[3]]), "triangle {t}");
        }
    }

    /// Moves that fold the new strip over itself: every node of a 4-edge strip advances
    /// by 0.5 except node 5 (y = 0), which stays, and node 3 (y = −1), whose heading swings
    /// 68° up past it to (1.4, 0.95): the new triangle (1′, 3′, c) of edge 1→3 enters the
    /// triangle (7, 5, 7′) of edge 5→7 (none of the edges is short or turned over, so no
    /// merge applies). The new triangles meet each other, not the existing surface: the
    /// nodes are reported `folded` (the driver retries them), not `refused`, and the rest
    /// advance on a valid surface. The wall of `crossing_move_is_refused` gives `refused`
    /// only.
    #[test]
    fn folding_moves_are_told_from_crossing_ones() {
        let (mut c, mut refs) = strip(4);
        let mut moves = moves_of(&c, |x| x + Vector3::new(0.5, 0.0, 0.0));
        moves.remove(&5);
        moves.insert(3, Vector3::new(1.4, 0.95, 0.0));
        let r = advance_front(&mut c, &mut refs, &moves, &[]);
        assert!(r.refused.is_empty(), "refused {:?}", r.refused);
        assert!(r.folded.contains(&3) && r.folded.contains(&7), "folded {:?}", r.folded);
        assert!(r.moved.iter().any(|m| m.0 == 9), "node 9 advances: {:?}", r.moved);
        check_valid(&c);

        let (mut c, mut refs) = strip(2);
        let wall = wall_across_lower_half();
        let moves = moves_of(&c, |x| x + Vector3::new(0.5, 0.0, 0.0));
        let r = advance_front(&mut c, &mut refs, &moves, &[&wall]);
        assert_eq!((r.refused.clone(), r.folded.clone()), (vec![1, 3], vec![]));
    }

    /// A penny crack (closed front) grown radially by half its edge length 20 times (radius
    /// 3 → 8): the surface stays valid and closed-fronted, edges stretched past twice their
    /// reference length are split, and every front node stays within the sagitta of a split
    /// chord of the circle it should be on.
    #[test]
    fn penny_front_grows_radially_and_splits() {
        use crate::crack::surface::{ellipse_boundary, planar_polygon};
        let (r0, edge, step, n) = (3.0, 0.5, 0.25, 20);
        let z = Vector3::z();
        let s = planar_polygon(&ellipse_boundary(Vector3::zeros(), z, Vector3::x(), r0, r0, edge).unwrap(), edge).unwrap();
        let front: Vec<[u32; 2]> = s.boundary_edges().iter().map(|&(a, b, _)| [a, b]).collect();
        let mut refs: Vec<f64> = front.iter().map(|&[a, b]| (s.vertices[a as usize] - s.vertices[b as usize]).norm()).collect();
        let mut c = Crack3::new(s, ContactLaw::None, 0.0, 0.0, front);
        let n0 = c.front.len();
        let mut splits = 0;
        for k in 1..=n {
            let moves = moves_of(&c, |x| x + x.normalize() * step);
            let r = advance_front(&mut c, &mut refs, &moves, &[]);
            assert!(r.refused.is_empty(), "advance {k}: refused {:?}", r.refused);
            splits += r.splits;
            check_valid(&c);
            // Closed front: every front node starts one front edge and ends one.
            let mut starts: Vec<u32> = c.front.iter().map(|e| e[0]).collect();
            let mut ends: Vec<u32> = c.front.iter().map(|e| e[1]).collect();
            starts.sort_unstable();
            ends.sort_unstable();
            assert_eq!(starts, ends, "advance {k}: the front is not a closed loop");
        }
        let r_max = c.front.iter().flatten().map(|&v| c.surface.vertices[v as usize].norm()).fold(0.0, f64::max);
        let r_min = c.front.iter().flatten().map(|&v| c.surface.vertices[v as usize].norm()).fold(f64::INFINITY, f64::min);
        // Radius 3 → 8: edges of ~0.5 stretch past 1.0 near radius 6 and split. A split
        // point is a chord's midpoint, inside the circle by the sagitta (≈ 0.02 for a chord
        // of 1 at radius 6), and then moves radially like the rest.
        assert!((r_max - (r0 + n as f64 * step)).abs() < 1e-12, "r_max {r_max}");
        assert!(r_max - r_min < 0.05, "front radii spread {r_min}..{r_max}");
        assert!(splits >= n0 / 2, "{splits} splits of {n0} edges");
        assert_eq!(c.front.len(), n0 + splits);
        println!("penny: {n0} front edges, {splits} splits, radii {r_min}..{r_max}, {} triangles", c.surface.triangles.len());
    }

    /// Mirror symmetry: moves mirror-symmetric about y = 0 (the strip is) give new crack
    /// particles that are mirror images of each other to the bit.
    #[test]
    fn mirrored_front_gives_mirrored_points() {
        let n = 4;
        let (mut c, mut refs) = strip(n);
        let moves = moves_of(&c, |x| x + Vector3::new(0.3 + 0.1 * x.y * x.y, 0.07 * x.y * x.y.abs(), 0.0));
        advance_front(&mut c, &mut refs, &moves, &[]);
        check_valid(&c);
        for v in &c.surface.vertices {
            let m = Vector3::new(v.x, -v.y, v.z);
            assert!(c.surface.vertices.iter().any(|w| w.x.to_bits() == m.x.to_bits() && w.y == m.y && w.z.to_bits() == m.z.to_bits()), "mirror of {v:?} missing");
        }
    }
}

/// Re-space the moved nodes of a front along the advanced front (module doc, "re-spacing";
/// not in the paper's rules of Fig. 3): for every run of at least three front nodes that
/// are consecutive along the front and all move (`moves`), the run's two end nodes keep
/// their targets and every interior node is put on the polyline of the run's targets at
/// the arc-length fraction it had along the polyline of the run's current positions. A
/// node is only moved when that changes its target by more than `tol` (a front that keeps
/// its spacing, as a straight or circular front growing uniformly, is left as it was to
/// the bit). A closed front all of whose nodes move has no run ends and is left as it is.
/// Returns how many targets changed.
pub fn respace_moves(crack: &Crack3, moves: &mut BTreeMap<u32, Vector3>, tol: f64) -> usize {
    let pts = &crack.surface.vertices;
    let mut succ: BTreeMap<u32, Vec<u32>> = BTreeMap::new();
    let mut pred: BTreeMap<u32, Vec<u32>> = BTreeMap::new();
    for &[a, b] in &crack.front {
        succ.entry(a).or_default().push(b);
        pred.entry(b).or_default().push(a);
    }
    // A node with more than one front edge on a side is a branch point: the chains stop there.
    let simple = |v: u32| succ.get(&v).is_none_or(|s| s.len() == 1) && pred.get(&v).is_none_or(|p| p.len() == 1);
    let mut nodes: BTreeSet<u32> = crack.front.iter().flatten().copied().collect();
    let mut chains: Vec<(Vec<u32>, bool)> = Vec::new();
    // Open chains from their first node (no predecessor, or a branch point).
    let starts: Vec<u32> = nodes.iter().copied().filter(|&v| !pred.contains_key(&v) || !simple(v)).collect();
    for &s in &starts {
        nodes.remove(&s);
    }
    for s in starts {
        for &first in succ.get(&s).map(Vec::as_slice).unwrap_or(&[]) {
            let mut chain = vec![s];
            let mut n = first;
            loop {
                chain.push(n);
                if !simple(n) || !nodes.remove(&n) {
                    break;
                }
                let Some(&m) = succ.get(&n).and_then(|s| s.first()) else { break };
                n = m;
            }
            chains.push((chain, false));
        }
    }
    // Closed loops.
    while let Some(&s) = nodes.iter().next() {
        let mut chain = vec![s];
        nodes.remove(&s);
        let mut v = s;
        while let Some(&n) = succ.get(&v).and_then(|s| s.first()) {
            if !nodes.remove(&n) {
                break;
            }
            chain.push(n);
            v = n;
        }
        chains.push((chain, true));
    }
    let mut changed = 0;
    for (mut chain, closed) in chains {
        if closed {
            // Start the loop at a node that does not move, so that no run wraps round.
            let Some(k) = chain.iter().position(|v| !moves.contains_key(v)) else { continue };
            chain.rotate_left(k);
        }
        let mut i = 0;
        while i < chain.len() {
            if !moves.contains_key(&chain[i]) {
                i += 1;
                continue;
            }
            let mut j = i;
            while j + 1 < chain.len() && moves.contains_key(&chain[j + 1]) {
                j += 1;
            }
            if j >= i + 2 {
                let run = &chain[i..=j];
                let p: Vec<Vector3> = run.iter().map(|&v| pts[v as usize]).collect();
                let q: Vec<Vector3> = run.iter().map(|v| moves[v]).collect();
                let cum = |x: &[Vector3]| {
                    let mut c = vec![0.0];
                    for w in x.windows(2) {
                        c.push(c.last().unwrap() + (w[1] - w[0]).norm());
                    }
                    c
                };
                let (s, t) = (cum(&p), cum(&q));
                let (sl, tl) = (s[s.len() - 1], t[t.len() - 1]);
                if sl > 0.0 && tl > 0.0 {
                    let mut new = Vec::new();
                    for k in 1..run.len() - 1 {
                        let want = s[k] / sl * tl;
                        let seg = (1..t.len()).find(|&m| t[m] >= want).unwrap_or(t.len() - 1);
                        let len = t[seg] - t[seg - 1];
                        let u = if len > 0.0 { ((want - t[seg - 1]) / len).clamp(0.0, 1.0) } else { 0.0 };
                        let x = q[seg - 1] + (q[seg] - q[seg - 1]) * u;
                        if (x - q[k]).norm() > tol {
                            new.push((run[k], x));
                        }
                    }
                    changed += new.len();
                    moves.extend(new);
                }
            }
            i = j + 1;
        }
    }
    changed
}
