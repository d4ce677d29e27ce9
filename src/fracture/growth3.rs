//! Crack propagation in 3D (Guo & Nairn 001 §2.3, Figs. 3–4; issue 17): the 2D driver of
//! [`crate::fracture::growth`] applied at every node of a crack front.
//!
//! Every `every` steps, for each growing crack (scene `cracks[].fracture.growth`, the 2D
//! table: `increment`, `every`, `max_speed`), at every current front node:
//!
//! 1. **J and K** ([`crate::fracture::front3`]): J₁, J₂ on the circle of the crack's
//!    `fracture` table in the node's (x1, x2) plane, and K_I, K_II, K_III from J₁ and the
//!    opening `cod_behind` behind the node, split with the node's speed factors
//!    ([`partition_k3_moving`]; the 2D split of 004 eqs. 14–15 plus mode III), the node's
//!    speed estimated from its own increments as a 2D tip's ([`speed_estimate`]).
//! 2. **Criterion** of the node's material (its `toughness`: maximum hoop stress or
//!    minimum strain-energy density with K_Ic; [`Toughness::direction`], the 2D code) from
//!    (K_I, K_II): the kink angle θ_c and K_eq. **K_III is left out** of both, as in the
//!    paper (001 §2.3.1 applies the 2D criteria at each front node): the node advances in its
//!    own (x1, x2) plane, so the new surface can kink about the front but never twists
//!    about x1; a front under mode III alone does not grow however large K_III is, and a
//!    mixed I/III front grows as if K_III were 0. K_III is reported in every row.
//! 3. **Move**: a node with K_eq ≥ K_Ic, still growing, whose speed estimate with the
//!    increment stays below the Rayleigh speed (and `max_speed`, [`speed_allows`]), moves
//!    `increment` smallest cells along x1 cos θ_c + x2 sin θ_c. **Growth frame**: x1 is
//!    normal to the front tangent at the node ([`Simulation::growth_tangents`]), the sum of
//!    the unit vectors toward its front neighbours as in [`crate::fracture::front3`], except
//!    that each front edge is taken at the lower of its two ends' advances: an end whose
//!    advance exceeds the other's by more than half its own last move counts at the crack
//!    particle it left at that move. Each node moves on its own
//!    criterion, so at any check some nodes of a uniformly growing front have made one
//!    increment more than their neighbours: a staircase of one increment, about the length
//!    of a front edge (both half a cell by default). Taken as the front's shape, it tilted
//!    x1 of a lagging node by up to 32° (case `front_growth_penny`: the node moved sideways
//!    and lost 1 − cos 32° = 0.15 of an increment of radius at its first move, 0.17 over
//!    its life; the front's radius spread was 1.16 increments). With the staircase removed,
//!    a circular front grows radially (tilts below 0.2°). A genuine difference of advance
//!    along the front (e.g. an elliptical crack's) is seen less one increment at most.
//!    x2 (the crack normal) is the mean of the unit normals of the node's triangles, by the
//!    same rule ([`Simulation::growth_normals`]): the triangles holding a neighbour that
//!    leads by more than half its last move are left out — made by that neighbour's move,
//!    they carry its kink, not the surface behind the node. With them, on the inclined
//!    penny (case `front_growth_inclined`, γ = 45°) a node beside a kinked neighbour had
//!    its frame tilted ≈ 14° toward the kink while the opening one cell behind it was still
//!    the flat crack's, and its first increment over-turned: 56–67° from the plane for
//!    Kassir & Sih's 54–55.5° (now 56.0–58.5°, as the nodes on an untouched front). J and K
//!    are evaluated in the same frame (the request's `tangents` and `normals`).
//! 4. **Symmetry planes**: a grid-node plane x_c = const, within two cells of the node,
//!    whose grid node nearest the node has a prescribed velocity component c (a roller or
//!    wall, read as a symmetry plane as contact's mirror rule does, [`crate::contact`]).
//!    A node lying exactly on one keeps its coordinate c (it moves within the plane, as
//!    its mirror image would); if it is a front end, its tangent is that of the front with
//!    its mirror image (the component normal to the plane), so x1 lies in the plane and the
//!    node moves a full increment (with the end edge's own normal it moved
//!    cos(φ/2) of one, φ the edge's angle at the centre of a penny); the material boundary
//!    near one counts the mirror image
//!    of the material across it ([`mirrored_volume`]; on the plane: twice the one-sided
//!    relative volume). A quarter penny on its two symmetry planes and an extruded crack
//!    between rollers then grow as the full body would (without the images the nodes a
//!    cell from a roller face see 7/8 of the material and stop short of the far edge).
//! 5. **Material boundary** (001 §2.3.3, Fig. 4; [`MaterialBoundary3`]): a move that ends
//!    where the relative volume of the node's material is below ½ is trimmed at the
//!    boundary and the node stops there for good (status `edge`, as a 2D tip); a node
//!    already outside does not move. Front edges with both ends stopped at the boundary
//!    leave the front ([`prune_front_where`]); the rest of the front goes on.
//!    **Free faces**: an end of an open front that is not on a symmetry plane lies where
//!    the crack's edge leaves the material, on a free face, where the relative volume is ½
//!    up to the strain: the test above would stop it at its first move (a stretched face
//!    has V a little below ½; measured on the extruded slab without rollers: both face
//!    nodes stopped at their first check, their neighbours were drawn to the faces and
//!    stopped too, and the crack did not get through). Such a node ([`free_face`]: the
//!    relative volume's gradient times the cell is at least [`FACE_GRADIENT`] = ¼; ¾ on a
//!    flat face, ⅛ one cell inside) moves along the face — its direction of growth
//!    projected on the plane normal to the outward normal n = −∇V/|∇V| ([`along_face`]),
//!    the gradient taken one cell behind the node along −x1 (at the node itself, a face
//!    ahead tilted n: on the slab the face nodes turned 21° into the body two cells before
//!    the far face and stopped 0.4 mm inside it) —
//!    and its boundary test counts the image of the material across that plane through
//!    the node, as on a symmetry plane: V(x) + V(x′) ≥ ½ with x′ the mirror image of x
//!    ([`reflect`]). So it still stops where the face meets another face (V = ¼ at a
//!    right-angled edge, 2V = ½) or leaves the material along it, and edges with both ends
//!    stopped are pruned as before. Nodes on symmetry planes and interior nodes are not
//!    affected.
//!    **Within reach of the boundary** ([`near_boundary`]): a growing node that does not
//!    meet its criterion at a check also stops for good at the boundary (status `edge`,
//!    where it is) when its relative volume, with the images
//!    above, is below [`NEAR_BOUNDARY_VOLUME`] = ¾ — the 2D driver's "on the boundary",
//!    within 0.29 of a cell of a flat face — and the point one increment ahead along its
//!    x1 (along the face for a front end on a free face) lies outside (V < ½): the
//!    boundary is the one ahead, and its next move would be trimmed there. Such a node
//!    cannot reach the boundary by the criterion: its contour (radius ≥ 1 cell) is cut by
//!    the free face, the missing part of the circle and the face's W n₁ term are not in
//!    J₁, and J₁ comes out small or negative (K = 0; measured on `corner_crack_rod`: 8
//!    nodes 0.03–0.19 mm short of the boundary of the far faces with J₁ = −0.5 … −30 N/mm
//!    never moved again, kept status `growing`, and their front edges were never pruned).
//!    The ligament it leaves, at most 0.29 cell, is below the resolution of the MPM
//!    material boundary itself (001 §2.3.3: "approximately along the grid lines").
//!    **Left behind at a free face**: a growing node with no energy release (J₁ ≤ 0, so
//!    K = 0 and it cannot meet its criterion) at [`DRY_CHECKS`] = 4 consecutive checks, at
//!    a free face ([`free_face`] at the node itself: within about ¾ cell of it), whose
//!    front neighbour has advanced more than [`LAG_INCREMENTS`] = 1.5 increments further
//!    (at least two moves ahead; one increment is the staircase of item 3), or all of whose
//!    front neighbours have stopped for good, also stops for good (status `edge`, counted
//!    with the nodes above) even when its x1 does not point at the face. (Without the
//!    second clause, measured: a front end on the inner face with J₁ < 0, whose only
//!    neighbour had been stopped by the first, kept a two-node piece of front 10° behind
//!    the rest for the whole run.) Measured on `tube_crack` (main 833f572): nodes 0.3–0.8 mm from the
//!    tube's inner face, their front tilted so that the contour circle (2 cells) was cut
//!    by the face, had J₁ = −66 … −21 N/mm (K = 0) and stayed `growing` 2–10 increments
//!    behind their neighbours for the rest of the run, their front edges never pruned;
//!    their neighbours' one-end triangles about them made fans of slivers (the sliver rule
//!    of [`crate::crack::advance3`] drops such edges once the node is stopped). Before the
//!    load arrives no node lags, so the rule cannot stop a front that has not yet grown.
//!    Only after J₁ ≤ 0 at 4 consecutive checks: at one check, a dip of the dynamic field
//!    stopped the whole inner part of a branch for good (case `tube_crack` with
//!    `cod_along = 2`, branch front: at step 264 the node 1.4 mm off the inner face had
//!    J₁ = −5.8 N/mm after 13, 27, 20, 2.5 at the checks before, and 54 and 106 at the two
//!    after, and its neighbour on the face −3.8 and −1.6; both stopped, the rest of the
//!    front went on with its end 1.4–7 mm off the inner face, drifted out through the wall
//!    and left it at 85° round the tube, while the other branch ran 173°). The nodes the
//!    rule was made for stayed at J₁ ≤ 0 for the rest of the run (below).
//!    Only with J₁ ≤ 0 (every such node in the tube runs had J₁ = −126 … −5 N/mm): a node
//!    with J₁ > 0 below K_Ic is slowing, not cut off from its energy — on the slab without
//!    rollers (tests/growth3.rs `free_face_fronts_grow_through_the_slab`) a face node
//!    lagging as the far face neared was stopped at x = 18.97, 1 mm short of it, when the
//!    rule did not ask for J₁ ≤ 0.
//!    **Back onto the boundary**: a front end on a free face whose move (along the face,
//!    its image counted) is not trimmed and ends outside the material by the direct
//!    relative volume (V < ½ with no face image) is brought back along −n onto the boundary
//!    (the last point with V ≥ ½ from one cell inside to the target, when that inner point
//!    is inside) when either (a) the node **starts** more than [`START_OUTSIDE`] = 0.02 cell
//!    beyond the boundary (the same distance, along n from one cell inside, measured at its
//!    position before the move), or (b) the pull-back exceeds [`PULL_BACK_MIN`] = 0.1 cell
//!    (a move along the tangent plane of a convex face). (a) is an end that was put or left
//!    outside the material: the tube's initial crack (its polygon reaches r = 50.35 for the
//!    outer radius 50, as the archived input; the boundary there is at r ≈ 50.25), or an
//!    end carried out by many moves each below (b) (a move of one increment, 1 mm, along
//!    the tangent plane at r = 50 ends 0.01 mm outside: the drift adds up, and (a) brings it
//!    back once it passes 0.02 cell). Measured on `tube_crack`: with (b) alone the outer
//!    ends' first moves (step 165) ended at r = 50.45, a pull-back of 0.2 mm = exactly
//!    0.1 cell that (b) does not make, and were carried with the bulging wall to 0.64 mm
//!    outside it (check `inside`, 0.5; main 833f572 without any pull-back: 0.89 mm).
//!    Why the thresholds: a front end on a stretched flat face has V a little below ½
//!    (measured on the slab without rollers, tests/growth3.rs
//!    `free_face_fronts_grow_through_the_slab`: V = 0.4968–0.4986 at its targets, 0.002–
//!    0.005 mm beyond the face), and brought back by so little inside its face its J₁ fell
//!    to 0.02 N/mm and it never moved again after its fifth move (why J₁ collapses for a
//!    node a few µm inside the face is not diagnosed); a pull-back limit of 0.02 cell
//!    (instead of (b)'s 0.1) broke the same test by the far edge (node 0 ended at
//!    x = 20.10). The start's distance tells an end that is outside from one that is on
//!    its face to the resolution of the MPM boundary: on the slab the face nodes start
//!    within 0.005 mm of the face for most of the run, and (a) first acts at step 325
//!    (x ≈ 15, start 0.05 mm = 0.025 cell beyond the face, target brought back to 0.009 mm
//!    inside it; the test passes). Never after a trimmed move (the node stops there):
//!    where the face meets another face (the slab's far edge) the direct V is ¼ and the
//!    pull-back along −n took a face node 0.6 mm off its face (with (a) on trimmed moves:
//!    1.5 mm, at step 334, start 0.15 mm "beyond" the face only because the far face was
//!    within a cell).
//!    **Ends at a face**: the front edge from a node stopped for good on a free face (its
//!    relative volume with the images below [`NEAR_BOUNDARY_VOLUME`] = ¾ and a face there,
//!    not on a symmetry plane) to the front's growing end on the same face (face normals
//!    within 45°, [`SAME_FACE_COS`]) has both ends at the boundary and leaves the front, as
//!    an edge with both ends stopped does; the stopped node, now the front's end on that
//!    face, grows on as a free-face end (status `growing` again: along the face, its image
//!    counted). A front that reaches a face is a crack that meets the face there, and its
//!    trace on the face extends as the front sweeps on. Not where the end is on another
//!    face (the front has reached the edge where two faces meet: the slab's far edge, where
//!    the node stopped on the far face has nowhere to grow), and not for edges pruned with
//!    both ends stopped. Measured on `tube_crack` (`cramp run` to 49 µs, stop
//!    39): the interior node next to the outer end, 0.13 cell inside the outer face, was
//!    trimmed at the face at step 225 and stopped for good, while the end beyond it ran on
//!    along the face; their edge, one end growing, was neither pruned nor dropped by the
//!    sliver rule, and the stopped node stayed on the front to the end of the run — a piece
//!    of front left at 29.7° round the tube while both branches ran past 190°.
//! 6. **New surface** ([`advance_front`], 001 Fig. 3): before it, the targets of the
//!    interior nodes of every run of consecutive moving front nodes are re-spaced along the
//!    new front to the arc-length fractions they had ([`respace_moves`]; the reason, a
//!    front sweeping round an axis whose nodes slide along it and crowd, is in the
//!    [`crate::crack::advance3`] module doc). Then one triangle per front edge with one
//!    end moving, four with both, five when the new edge exceeds twice its reference length
//!    (split, a new front node), one and a merged node when it falls below a quarter. A
//!    node whose new triangles would meet the existing surface of any crack is refused and
//!    stops for good (status `crack`), as a 2D tip. The new crack particles are first
//!    moved along the new triangles' normals, by at most 0.08 cell per round (3 rounds), so
//!    that no particle centre lies within [`CLEARANCE_CELLS`] = 2 % of a cell of the new
//!    surface ([`Clearance`]; why, and the tube's particle that was left on its crack, in
//!    the [`crate::crack::advance3`] module doc, "clearance"). A node whose new triangles meet only
//!    another new triangle of the same advance (the new strip folds over itself: its
//!    heading and a neighbour's converge or cross within one increment) is refused this
//!    time and **retried at its next check** (status `growing`): the fold says nothing
//!    about a crack in its way, and at the next check the node lags its neighbours by an
//!    increment, which the growth frame of item 3 sees through. Measured on
//!    `corner_crack_rod` before the split and merge rules of [`advance_front`] were
//!    made to measure across the moves and along the old edge: stopped for good, the 7
//!    nodes of the first fold (headings 55–57° off the front normal at the split points
//!    of a riser, all five meeting pairs new against new) lagged more at every check,
//!    their long front edges spanned the surface grown past them, and 15 nodes by the far
//!    corner ended `crack` with K_eq above K_Ic; retried instead (those rules not yet
//!    changed), 7 of them were refused at every retry, as the split points' headings
//!    stayed skewed. With the two rules the case has no fold at all (0 retries): the
//!    retry is the fallback for a fold they do not prevent.
//! 7. **Notch rule** ([`fill_notches`], not in the paper): after the advance, a front node
//!    at the apex of a tongue of material reaching back into the crack — the material
//!    between its two front edges making an angle below [`NOTCH_ANGLE_DEG`] = 45° — is cut
//!    off: the triangle (node, previous, next) joins the crack and the node leaves the
//!    front (most acute first, until none is left; the reason and the measured case are in
//!    the function's doc). Such a node cannot move: its growth tangent and heading are
//!    skewed by its nearly opposed front edges, and every triangle it would make runs
//!    through the crack beside it or stands on end.
//!
//! A new front node made by a split takes a copy of the growth history (advance, increment
//! times, status) of the lower-labelled end of its edge; merged nodes keep the history of
//! the lower-labelled one. Every front node has a stable `label` (initial front nodes in
//! vertex order, then new ones as they appear); `growth.csv` has one row per front node per
//! check. The body's crack triangle index and boundary flags are rebuilt by
//! [`advance_front`] and at the next Task 1.
//!
//! Everything is a deterministic function of the state: nodes in ascending vertex order,
//! exact sums in J and the relative volume, so a run is bit-identical for any particle
//! order and thread count (tests/three_d_crack_reproducibility.rs).

use crate::crack::advance3::{advance_front_stopped, fill_notches, fold_cos, has_notch, prune_front_where, respace_moves, Clearance, CLEARANCE_CELLS, CLEARANCE_MAX_SHIFT, NOTCH_ANGLE_DEG};
use crate::dim::{GridGeometry, Vector3, D3};
use crate::fracture::boundary3::{trim_by, MaterialBoundary3};
use crate::fracture::front3::{front_tangents, partition_k3_moving, FrontRequest};
use crate::fracture::growth::{speed_allows, Criterion, speed_estimate, GrowthError, GrowthSettings, Toughness, BOUNDARY_VOLUME, NEAR_BOUNDARY_VOLUME};
use crate::fracture::speed::{rayleigh_speed_for, speed_factors_for};
use crate::simulation::Simulation;
use std::collections::{BTreeMap, BTreeSet};

/// Whether a front node can still grow.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NodeStatus {
    Growing,
    /// Reached the material boundary (001 §2.3.3).
    AtEdge,
    /// Its new surface would have met a crack surface.
    AtCrack,
}

impl NodeStatus {
    pub fn label(&self) -> &'static str {
        match self {
            NodeStatus::Growing => "growing",
            NodeStatus::AtEdge => "edge",
            NodeStatus::AtCrack => "crack",
        }
    }
}

/// Growth state of one front node.
#[derive(Clone, Debug, PartialEq)]
pub struct NodeGrowth {
    /// Stable label (module doc).
    pub label: u32,
    pub status: NodeStatus,
    /// Total advance (sum of its moves).
    pub advance: f64,
    /// (time, advance after it) of every move.
    pub events: Vec<(f64, f64)>,
    /// The crack particle the node left at its last move (None before its first move and
    /// for a node made by a split): its position before that move, for the front tangent
    /// its neighbours see ([`Simulation::growth_tangents`]).
    pub from: Option<u32>,
    /// Consecutive checks, up to this one, at which the node's J₁ was not positive.
    pub dry: u32,
}

impl NodeGrowth {
    fn start(label: u32) -> NodeGrowth {
        NodeGrowth { label, status: NodeStatus::Growing, advance: 0.0, events: Vec::new(), from: None, dry: 0 }
    }

    /// The length of the node's last move (None before its first).
    pub fn last_step(&self) -> Option<f64> {
        let n = self.events.len();
        match n {
            0 => None,
            1 => Some(self.events[0].1),
            _ => Some(self.events[n - 1].1 - self.events[n - 2].1),
        }
    }
}

/// Growth state of one 3D crack.
#[derive(Clone, Debug, PartialEq)]
pub struct FrontGrowth {
    pub crack: usize,
    /// Contour, intervals, volume term and opening distance of the crack's `fracture`
    /// table (its `nodes` are replaced by the current front at every check).
    pub request: FrontRequest,
    pub settings: GrowthSettings,
    /// Reference length of each front edge (001 Fig. 3's "initial length").
    pub front_ref: Vec<f64>,
    /// The current front nodes by crack-particle index.
    pub nodes: BTreeMap<u32, NodeGrowth>,
    pub next_label: u32,
    /// Front edges split and merged, edges pruned so far.
    pub splits: usize,
    pub merges: usize,
    pub pruned: usize,
    /// Moves refused because the new strip folded over itself (retried, module doc item 6)
    /// and nodes stopped within reach of the boundary (item 5), so far.
    pub folded: usize,
    pub near_edge: usize,
    /// Front nodes taken off the front by the notch rule ([`fill_notches`]), so far.
    pub filled: usize,
    /// Stopped nodes that became a front end on a free face and grow on (item 5, "ends at
    /// a face"), so far.
    pub handed: usize,
    /// New crack particles moved to clear a particle centre, and (particle, triangle) pairs
    /// left within half the clearance (item 6, "clearance"), so far.
    pub cleared: usize,
    pub unclear: usize,
}

/// One evaluation at one front node (a row of the 3D growth.csv).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NodeRecord {
    pub time: f64,
    pub step: u64,
    pub crack: usize,
    pub label: u32,
    /// Crack-particle index of the node at the evaluation.
    pub vertex: u32,
    pub x: Vector3,
    /// The node's advance after this check and its speed estimate before it.
    pub advance: f64,
    pub speed: f64,
    pub j1: f64,
    pub j2: f64,
    pub k: [f64; 3],
    /// θ_c (radians from x1 toward x2) and K_eq of the criterion; NaN without toughness or K.
    pub theta: f64,
    pub k_eq: f64,
    /// Unit direction of growth x1 cos θ_c + x2 sin θ_c (global; NaN when θ_c is).
    pub heading: Vector3,
    pub grew: bool,
    pub status: NodeStatus,
}

impl NodeRecord {
    pub const HEADER: &'static str = "time,step,crack,node,vertex,x,y,z,advance,speed,j1,j2,k1,k2,k3,theta_deg,k_eq,dir_x,dir_y,dir_z,grew,status";

    pub fn csv(&self) -> String {
        let v = [
            self.x.x,
            self.x.y,
            self.x.z,
            self.advance,
            self.speed,
            self.j1,
            self.j2,
            self.k[0],
            self.k[1],
            self.k[2],
            self.theta.to_degrees(),
            self.k_eq,
            self.heading.x,
            self.heading.y,
            self.heading.z,
        ];
        let mut s = format!("{:e},{},{},{},{}", self.time, self.step, self.crack, self.label, self.vertex);
        for x in v {
            s.push_str(&format!(",{x:e}"));
        }
        s.push_str(&format!(",{},{}", self.grew as u8, self.status.label()));
        s
    }
}

/// Crack growth of a 3D simulation.
#[derive(Clone, Debug, PartialEq)]
pub struct Growth3 {
    /// Toughness of each material (None: it does not fracture).
    pub toughness: Vec<Option<Toughness>>,
    pub cracks: Vec<FrontGrowth>,
    /// Every evaluation so far, in order.
    pub records: Vec<NodeRecord>,
}

impl Growth3 {
    /// Growth state for the cracks `(index, request, settings)` of `sim`: the current front
    /// with its edges' lengths as reference lengths, nodes labelled in vertex order.
    pub fn new(sim: &Simulation<D3>, toughness: Vec<Option<Toughness>>, cracks: Vec<(usize, FrontRequest, GrowthSettings)>) -> Growth3 {
        let cracks = cracks
            .into_iter()
            .map(|(c, request, settings)| {
                let crack = &sim.cracks[c];
                let v = &crack.surface.vertices;
                let front_ref = crack.front.iter().map(|&[a, b]| (v[a as usize] - v[b as usize]).norm()).collect();
                let ids: BTreeSet<u32> = crack.front.iter().flatten().copied().collect();
                let nodes: BTreeMap<u32, NodeGrowth> =
                    ids.iter().enumerate().map(|(k, &v)| (v, NodeGrowth::start(k as u32))).collect();
                let next_label = nodes.len() as u32;
                FrontGrowth { crack: c, request, settings, front_ref, nodes, next_label, splits: 0, merges: 0, pruned: 0, folded: 0, near_edge: 0, filled: 0, handed: 0, cleared: 0, unclear: 0 }
            })
            .collect();
        Growth3 { toughness, cracks, records: Vec::new() }
    }

    /// The J/K request of crack `c` of `sim` at its current front, with the growth
    /// driver's front tangents (None if it does not grow).
    pub fn current_request(&self, sim: &Simulation<D3>, c: usize) -> Option<FrontRequest> {
        let g = self.cracks.iter().find(|g| g.crack == c)?;
        Some(sim.growth_request(g))
    }
}

impl Simulation<D3> {
    /// Crack growth after a completed step (module doc).
    pub(crate) fn grow_fronts(&mut self) -> Result<(), GrowthError> {
        let Some(mut growth) = self.growth.take() else { return Ok(()) };
        let result = self.grow_fronts_with(&mut growth);
        self.growth = Some(growth);
        result
    }

    fn grow_fronts_with(&mut self, growth: &mut Growth3) -> Result<(), GrowthError> {
        let h = self.grid.min_h();
        let mut boundary: Option<MaterialBoundary3> = None;
        let growth_hoop_only = growth.toughness.iter().flatten().all(|t| matches!(t.criterion, Criterion::MaxHoopStress));
        for fg in growth.cracks.iter_mut() {
            if !self.step_count.is_multiple_of(fg.settings.every) {
                continue;
            }
            let c = fg.crack;
            let req = self.growth_request(fg);
            let results = self.front_fracture(c, &req);
            let degree = front_degree(&self.cracks[c]);
            let da = fg.settings.increment * h;
            let mut moves: BTreeMap<u32, Vector3> = BTreeMap::new();
            let mut rows: Vec<NodeRecord> = Vec::with_capacity(results.len());
            for fr in &results {
                if let Some(n) = fg.nodes.get_mut(&fr.node) {
                    n.dry = if fr.j1 > 0.0 { 0 } else { n.dry + 1 };
                }
            }
            // A node is left behind when a front neighbour has advanced more than
            // LAG_INCREMENTS increments further, or when all its front neighbours have
            // stopped for good (module doc, item 5).
            let lags = |v: u32| {
                let own = fg.nodes[&v].advance;
                let nbrs: Vec<&NodeGrowth> = self.cracks[c].front.iter().filter(|e| e.contains(&v)).flatten().filter(|&&u| u != v).filter_map(|u| fg.nodes.get(u)).collect();
                nbrs.iter().any(|n| n.advance - own > LAG_INCREMENTS * da) || (!nbrs.is_empty() && nbrs.iter().all(|n| n.status != NodeStatus::Growing))
            };
            for fr in &results {
                let v = fr.node;
                let node = &fg.nodes[&v];
                let speed = speed_estimate(&node.events, node.advance, self.time, None, fg.settings.speed_window);
                let err = |message: String| GrowthError::Front { crack: c, node: v, x: fr.x.x, y: fr.x.y, z: fr.x.z, message };
                let mat = self.material_index_near3(&fr.x).ok_or_else(|| err("no material particle to take the toughness from".into()))?;
                let m = &self.materials[mat];
                let sf = speed_factors_for(m, fg.settings.k_speed(speed)).map_err(|e| err(format!("crack-speed factors: {e}")))?;
                let k = if fr.delta.iter().all(|d| d.is_finite()) && fr.j1.is_finite() { partition_k3_moving(fr.j1, fr.delta, m.shear_modulus(), &sf) } else { [f64::NAN; 3] };
                let toughness = growth.toughness[mat];
                let dir = toughness.and_then(|t| t.direction(k[0], k[1], m.kappa()));
                let (theta, k_eq) = dir.unwrap_or((f64::NAN, f64::NAN));
                let mut heading = fr.frame.e1 * theta.cos() + fr.frame.e2 * theta.sin();
                let meets = matches!((toughness, dir), (Some(t), Some((_, keq))) if keq >= t.kic);
                let mut status = node.status;
                if status == NodeStatus::Growing {
                    let planes = self.symmetry_planes(&fr.x);
                    let on_plane = on_symmetry_plane(&planes, &fr.x);
                    let b = boundary.get_or_insert_with(|| self.material_boundary3());
                    // A front end on a free face (module doc, item 5): along the face,
                    // the face's image counted in the boundary test (not when the
                    // direction is normal to the face: then the face stops it).
                    let face_normal = if !on_plane && degree.get(&v) == Some(&1) { free_face(b, mat, fr.x - fr.frame.e1 * h, &planes, h) } else { None };
                    let on_face = |dir: Vector3| face_normal.and_then(|n| along_face(dir, n).map(|d| (n, d)));
                    let (b, pl, x0) = (&*b, planes.as_slice(), fr.x);
                    let volume = |face: Option<(Vector3, Vector3)>| {
                        move |x: Vector3| match face {
                            Some((n, _)) => mirrored_volume(b, mat, x, pl) + mirrored_volume(b, mat, reflect(x, x0, n), pl),
                            None => mirrored_volume(b, mat, x, pl),
                        }
                    };
                    if meets {
                        let c_r = rayleigh_speed_for(m).map_err(|e| err(format!("Rayleigh speed: {e}")))?;
                        if speed_allows(&node.events, node.advance, self.time, da, c_r, fg.settings.max_speed, fg.settings.speed_window) {
                            let face = on_face(heading);
                            if let Some((_, d)) = face {
                                heading = d;
                            }
                            let mut to = fr.x + heading * da;
                            for &(a, p) in &planes {
                                if p == fr.x[a] {
                                    to[a] = p;
                                }
                            }
                            let (mut target, at_edge) = trim_by(fr.x, to, volume(face));
                            // A front end on a free face whose untrimmed move ends outside
                            // the material (with no image) is brought back along −n to the
                            // boundary when it started beyond it (by > START_OUTSIDE) or the
                            // pull-back exceeds PULL_BACK_MIN (module doc, item 5).
                            if let Some((n, _)) = face {
                                let direct = volume(None);
                                // A point beyond the boundary (along n): its point back on it.
                                let back_on = |x: Vector3| {
                                    let inner = x - n * h;
                                    (direct(x) < BOUNDARY_VOLUME && direct(inner) >= BOUNDARY_VOLUME).then(|| trim_by(inner, x, &direct).0)
                                };
                                let started_out = back_on(fr.x).is_some_and(|b| (b - fr.x).norm() > START_OUTSIDE * h);
                                if let Some(back) = back_on(target) {
                                    if !at_edge && (started_out || (back - target).norm() > PULL_BACK_MIN * h) {
                                        target = back;
                                    }
                                }
                            }
                            if at_edge {
                                status = NodeStatus::AtEdge;
                            }
                            // Too short a move would make a degenerate triangle: stop there instead.
                            if (target - fr.x).norm() >= 1e-3 * h {
                                moves.insert(v, target);
                            }
                        }
                    }
                    // A node that does not meet its criterion, within reach of the boundary
                    // ahead (module doc, item 5).
                    if !meets && status == NodeStatus::Growing {
                        let face = on_face(fr.frame.e1);
                        let ahead = face.map_or(fr.frame.e1, |(_, d)| d);
                        if near_boundary(volume(face), fr.x, ahead, da) {
                            status = NodeStatus::AtEdge;
                            fg.near_edge += 1;
                        } else if node.dry >= DRY_CHECKS && lags(v) && free_face(b, mat, fr.x, pl, h).is_some() {
                            // Left behind by the front at a free face (module doc, item 5).
                            status = NodeStatus::AtEdge;
                            fg.near_edge += 1;
                        }
                    }
                }
                rows.push(NodeRecord {
                    time: self.time,
                    step: self.step_count,
                    crack: c,
                    label: node.label,
                    vertex: v,
                    x: fr.x,
                    advance: node.advance,
                    speed,
                    j1: fr.j1,
                    j2: fr.j2,
                    k,
                    theta,
                    k_eq,
                    heading,
                    grew: false,
                    status,
                });
            }
            for r in &rows {
                fg.nodes.get_mut(&r.vertex).expect("front node").status = r.status;
            }
            if !moves.is_empty() {
                // Interior nodes of every run of moving nodes keep their arc-length
                // fractions along the front (module doc, item 6).
                respace_moves(&self.cracks[c], &mut moves, RESPACE_TOL * h);
                let others: Vec<&crate::crack::surface::TriangleSurface> = self.cracks.iter().enumerate().filter(|&(o, _)| o != c).map(|(_, k)| &k.surface).collect();
                let mut crack = self.cracks[c].clone();
                // Stopped for good and not moving (sliver rule of advance_front_stopped).
                let stopped: BTreeSet<u32> = rows.iter().filter(|r| r.status != NodeStatus::Growing && !moves.contains_key(&r.vertex)).map(|r| r.vertex).collect();
                // Fold test (advance3 module doc, "turn-over"): 80.5° when every material
                // with a toughness grows by maximum hoop stress, 90° otherwise.
                // The new surface keeps clear of particle centres (advance3 module doc,
                // "clearance"): those in the box of the front and the targets.
                let reach = Vector3::repeat((CLEARANCE_MAX_SHIFT + 1.0) * CLEARANCE_CELLS * h + da);
                let (lo, hi) = crack.front.iter().flatten().map(|&v| crack.surface.vertices[v as usize]).chain(moves.values().copied()).fold((Vector3::repeat(f64::INFINITY), Vector3::repeat(f64::NEG_INFINITY)), |(l, u), x| (l.inf(&x), u.sup(&x)));
                let (lo, hi) = (lo - reach, hi + reach);
                let near: Vec<Vector3> = self.particles.x.iter().filter(|x| (0..3).all(|a| x[a] >= lo[a] && x[a] <= hi[a])).copied().collect();
                let mut planes: Vec<(usize, f64)> = moves.values().flat_map(|x| self.symmetry_planes(x)).collect();
                planes.sort_by(|a, b| a.partial_cmp(b).expect("finite planes"));
                planes.dedup();
                let clearance = Clearance { points: &near, distance: CLEARANCE_CELLS * h, planes: &planes, ahead: da };
                let report = advance_front_stopped(&mut crack, &mut fg.front_ref, &moves, &others, &stopped, fold_cos(growth_hoop_only), &clearance);
                fg.pruned += report.dropped;
                fg.cleared += report.cleared;
                fg.unclear += report.unclear;
                self.cracks[c] = crack;
                fg.splits += report.splits;
                fg.merges += report.merges;
                // Folded moves are retried at the next check: the node keeps its status.
                fg.folded += report.folded.len();
                for v in &report.refused {
                    fg.nodes.get_mut(v).expect("front node").status = NodeStatus::AtCrack;
                    if let Some(r) = rows.iter_mut().find(|r| r.vertex == *v) {
                        r.status = NodeStatus::AtCrack;
                    }
                }
                // Carry each node's history to its new crack particle.
                let pts = &self.cracks[c].surface.vertices;
                let mut next: BTreeMap<u32, NodeGrowth> = BTreeMap::new();
                let moved: BTreeMap<u32, u32> = report.moved.iter().copied().collect();
                for (v, mut ng) in std::mem::take(&mut fg.nodes) {
                    let Some(&nv) = moved.get(&v) else {
                        next.insert(v, ng);
                        continue;
                    };
                    let step = (pts[nv as usize] - pts[v as usize]).norm();
                    ng.advance += step;
                    ng.events.push((self.time, ng.advance));
                    ng.from = Some(v);
                    if let Some(r) = rows.iter_mut().find(|r| r.vertex == v) {
                        r.grew = true;
                        r.advance = ng.advance;
                    }
                    match next.get(&nv) {
                        // Merged with a node of lower label: keep that one's history.
                        Some(other) if other.label < ng.label => {}
                        _ => {
                            next.insert(nv, ng);
                        }
                    }
                }
                // Split points: new front nodes with no history take a copy of the
                // lower-labelled end of their edge.
                let crack = &self.cracks[c];
                let fresh: BTreeSet<u32> = crack.front.iter().flatten().copied().filter(|v| !next.contains_key(v)).collect();
                for v in fresh {
                    let neighbour = crack.front.iter().filter(|e| e.contains(&v)).flatten().filter_map(|u| next.get(u)).min_by_key(|n| n.label);
                    let mut ng = neighbour.cloned().unwrap_or(NodeGrowth::start(0));
                    ng.label = fg.next_label;
                    ng.from = None;
                    fg.next_label += 1;
                    next.insert(v, ng);
                }
                fg.nodes = next;
            }
            // Tongues of material reaching back into the crack are cut at their apex
            // (notch rule, module doc item 7).
            if has_notch(&self.cracks[c], NOTCH_ANGLE_DEG.to_radians()) {
                let others: Vec<&crate::crack::surface::TriangleSurface> = self.cracks.iter().enumerate().filter(|&(o, _)| o != c).map(|(_, k)| &k.surface).collect();
                let mut crack = self.cracks[c].clone();
                let filled = fill_notches(&mut crack, &mut fg.front_ref, &others, NOTCH_ANGLE_DEG.to_radians());
                if !filled.is_empty() {
                    self.cracks[c] = crack;
                    fg.filled += filled.len();
                }
            }
            // Front edges with both ends at the boundary leave the front: both stopped
            // there, or one stopped on a free face and the other the front's end on the
            // same face; the stopped node, left as the front's end on that face, grows on
            // as a free-face end (module doc, item 5, "ends at a face").
            let stopped: BTreeSet<u32> = fg.nodes.iter().filter(|(_, n)| n.status == NodeStatus::AtEdge).map(|(&v, _)| v).collect();
            if !stopped.is_empty() {
                let b = boundary.get_or_insert_with(|| self.material_boundary3());
                let degree = front_degree(&self.cracks[c]);
                let face_at = |v: u32| self.free_face_normal(b, self.cracks[c].surface.vertices[v as usize], h);
                let face_ends: BTreeMap<u32, Vector3> = fg.nodes.iter().filter(|(v, n)| n.status == NodeStatus::Growing && degree.get(v) == Some(&1)).filter_map(|(&v, _)| face_at(v).map(|n| (v, n))).collect();
                let stopped_on_face: BTreeMap<u32, Vector3> = if face_ends.is_empty() { BTreeMap::new() } else { stopped.iter().filter_map(|&v| face_at(v).map(|n| (v, n))).collect() };
                let (leaves, handed) = edges_at_boundary(&self.cracks[c].front, &stopped, &stopped_on_face, &face_ends);
                let mut crack = self.cracks[c].clone();
                let dropped = prune_front_where(&mut crack, &mut fg.front_ref, |e| leaves.contains(e));
                if dropped > 0 {
                    self.cracks[c] = crack;
                    fg.pruned += dropped;
                    let after = front_degree(&self.cracks[c]);
                    for v in handed {
                        if after.get(&v) == Some(&1) {
                            fg.nodes.get_mut(&v).expect("front node").status = NodeStatus::Growing;
                            fg.handed += 1;
                        }
                    }
                }
            }
            let on_front: BTreeSet<u32> = self.cracks[c].front.iter().flatten().copied().collect();
            fg.nodes.retain(|v, _| on_front.contains(v));
            growth.records.extend(rows);
        }
        Ok(())
    }

    /// The J/K request of a growing crack: its current front nodes and their growth
    /// tangents ([`Simulation::growth_tangents`]).
    fn growth_request(&self, fg: &FrontGrowth) -> FrontRequest {
        FrontRequest { nodes: fg.nodes.keys().copied().collect(), tangents: self.growth_tangents(fg), normals: self.growth_normals(fg), ..fg.request.clone() }
    }

    /// The crack normals of a growing crack's front nodes where a front neighbour leads by
    /// more than half its own last move (the rule of [`Simulation::growth_tangents`]): the
    /// mean of the unit normals of the node's triangles without those that hold the leading
    /// neighbour's current crack particle. Such a triangle was made by the neighbour's move
    /// and carries its kink, not the surface behind the node (with it, a node beside a
    /// kinked neighbour had its frame tilted ≈ 14° toward the kink on the inclined penny,
    /// case `front_growth_inclined`, and its first increment over-turned).
    pub fn growth_normals(&self, fg: &FrontGrowth) -> BTreeMap<u32, Vector3> {
        let crack = &self.cracks[fg.crack];
        let s = &crack.surface;
        let leads = |a: &NodeGrowth, b: &NodeGrowth| matches!((a.from, a.last_step()), (Some(_), Some(step)) if a.advance - b.advance > 0.5 * step);
        let mut skip: BTreeMap<u32, Vec<u32>> = BTreeMap::new();
        for &[p, q] in &crack.front {
            if let (Some(np), Some(nq)) = (fg.nodes.get(&p), fg.nodes.get(&q)) {
                if leads(nq, np) {
                    skip.entry(p).or_default().push(q);
                }
                if leads(np, nq) {
                    skip.entry(q).or_default().push(p);
                }
            }
        }
        let mut out: BTreeMap<u32, Vector3> = BTreeMap::new();
        if skip.is_empty() {
            return out;
        }
        for (t, tri) in s.triangles.iter().enumerate() {
            for v in tri {
                if let Some(sk) = skip.get(v) {
                    if !tri.iter().any(|w| sk.contains(w)) {
                        *out.entry(*v).or_insert_with(Vector3::zeros) += s.normal(t);
                    }
                }
            }
        }
        out.retain(|_, n| n.norm() > 0.0);
        out
    }

    /// The front tangents of a growing crack where they differ from the front's own
    /// (module doc, items 3–4): the tangent at node P is the sum of the unit vectors toward
    /// its front neighbours, each edge with the end that leads the other by more than half
    /// its own last move taken at the crack particle it left at that move (the asynchronous
    /// staircase removed); a front end lying on a symmetry plane keeps only the tangent's
    /// component normal to the plane (the tangent of the front and its mirror image).
    pub fn growth_tangents(&self, fg: &FrontGrowth) -> BTreeMap<u32, Vector3> {
        let crack = &self.cracks[fg.crack];
        let pts = &crack.surface.vertices;
        let at = |v: u32| pts[v as usize];
        // The end that leads the other by more than half its own last move, at the crack
        // particle it left at that move.
        let behind = |a: &NodeGrowth, b: &NodeGrowth, v: u32| -> Vector3 {
            match (a.from, a.last_step()) {
                (Some(f), Some(step)) if a.advance - b.advance > 0.5 * step => at(f),
                _ => at(v),
            }
        };
        let span = |p: u32, q: u32| -> Vector3 {
            match (fg.nodes.get(&p), fg.nodes.get(&q)) {
                (Some(np), Some(nq)) => behind(nq, np, q) - behind(np, nq, p),
                _ => at(q) - at(p),
            }
        };
        let own = front_tangents(crack, |p, q| at(q) - at(p));
        let mut out = front_tangents(crack, span);
        let ends = front_degree(crack);
        for (v, t) in out.iter_mut() {
            if ends[v] != 1 {
                continue;
            }
            let x = pts[*v as usize];
            for (a, p) in self.symmetry_planes(&x) {
                if p == x[a] && t[a] != 0.0 {
                    let mut n = Vector3::zeros();
                    n[a] = t[a];
                    *t = n;
                }
            }
        }
        out.retain(|v, t| own.get(v) != Some(t));
        out
    }

    /// The material boundary of the current particles (relative volume, current volumes).
    fn material_boundary3(&self) -> MaterialBoundary3 {
        let p = &self.particles;
        let volume: Vec<f64> = (0..p.len()).map(|i| p.volume(i)).collect();
        MaterialBoundary3::new(&self.grid, &p.x, &volume, &p.material)
    }

    /// The outward normal of the free face on which crack particle position x lies (module
    /// doc, item 5, "ends at a face"), if it does: not on a symmetry plane, its relative
    /// volume (with the planes' images) below [`NEAR_BOUNDARY_VOLUME`] (the 2D driver's "on
    /// the boundary", within 0.29 cell of a flat face) and a face there ([`free_face`]).
    fn free_face_normal(&self, b: &MaterialBoundary3, x: Vector3, h: f64) -> Option<Vector3> {
        let planes = self.symmetry_planes(&x);
        if on_symmetry_plane(&planes, &x) {
            return None;
        }
        let mat = self.material_index_near3(&x)?;
        if mirrored_volume(b, mat, x, &planes) >= NEAR_BOUNDARY_VOLUME {
            return None;
        }
        free_face(b, mat, x, &planes, h)
    }

    /// The symmetry planes near x (module doc, item 4): per axis c, the node plane
    /// x_c = const nearest to x, within two cells, whose grid node nearest to x has a
    /// prescribed velocity component c (a wall or roller), as (c, coordinate).
    pub fn symmetry_planes(&self, x: &Vector3) -> Vec<(usize, f64)> {
        let g = &self.grid;
        let mut ijk = [0i64; 3];
        for a in 0..3 {
            ijk[a] = ((x[a] - g.origin[a]) / g.h[a]).round() as i64;
        }
        let mut out = Vec::new();
        for a in 0..3 {
            let f = (x[a] - g.origin[a]) / g.h[a];
            let mut best: Option<(f64, f64)> = None;
            for i in (f.floor() as i64 - 1)..=(f.ceil() as i64 + 1) {
                let mut n = ijk;
                n[a] = i;
                if (0..3).any(|b| n[b] < 0 || n[b] > g.n[b] as i64) {
                    continue;
                }
                let node = g.node_index(n[0] as usize, n[1] as usize, n[2] as usize);
                let p = g.node_pos(node)[a];
                let d = (p - x[a]).abs();
                if self.bcs.mask.get(node).is_some_and(|m| m & (1 << a) != 0) && d <= 2.0 * g.h[a] && best.is_none_or(|(bd, _)| d < bd) {
                    best = Some((d, p));
                }
            }
            if let Some((_, p)) = best {
                out.push((a, p));
            }
        }
        out
    }

    /// Index of the material at x: the scene's only material, else that of the nearest
    /// particle (ties: lowest id).
    pub fn material_index_near3(&self, x: &Vector3) -> Option<usize> {
        if self.materials.len() == 1 {
            return Some(0);
        }
        let p = &self.particles;
        (0..p.len())
            .min_by(|&a, &b| (p.x[a] - x).norm_squared().total_cmp(&(p.x[b] - x).norm_squared()).then(p.id[a].cmp(&p.id[b])))
            .map(|i| p.material[i] as usize)
    }
}

/// The relative volume of material `mat` at x with the mirror images of the material
/// across the symmetry `planes` (module doc, item 4): the sum of the direct relative
/// volume at every reflection of x across a subset of the planes (the hat is symmetric,
/// so an image particle near x is a particle near the reflected point). On a plane its
/// reflection is x itself: twice the one-sided value.
pub fn mirrored_volume(b: &MaterialBoundary3, mat: usize, x: Vector3, planes: &[(usize, f64)]) -> f64 {
    let mut sum = 0.0;
    for subset in 0..(1usize << planes.len()) {
        let mut y = x;
        for (k, &(a, p)) in planes.iter().enumerate() {
            if subset & (1 << k) != 0 {
                y[a] = 2.0 * p - y[a];
            }
        }
        sum += b.relative_volume(mat, y);
    }
    sum
}

/// The front edges that leave the front at the boundary (module doc, item 5), and the
/// stopped nodes handed the front's end on a face ("ends at a face"): an edge leaves when
/// both its ends are `stopped`, or when one end is stopped on a free face
/// (`stopped_on_face`, its outward normal) and the other is a growing front end on the
/// same face (`face_ends`, normals within 45°: [`SAME_FACE_COS`]); that stopped end is
/// handed the end.
pub fn edges_at_boundary(
    front: &[[u32; 2]],
    stopped: &BTreeSet<u32>,
    stopped_on_face: &BTreeMap<u32, Vector3>,
    face_ends: &BTreeMap<u32, Vector3>,
) -> (BTreeSet<[u32; 2]>, BTreeSet<u32>) {
    // The stopped end a of an edge (a, e) to a face end e on the same face.
    let beside = |a: u32, e: u32| matches!((stopped_on_face.get(&a), face_ends.get(&e)), (Some(na), Some(ne)) if na.dot(ne) >= SAME_FACE_COS);
    let (mut leaves, mut handed) = (BTreeSet::new(), BTreeSet::new());
    for e in front {
        let by = if beside(e[0], e[1]) {
            Some(e[0])
        } else if beside(e[1], e[0]) {
            Some(e[1])
        } else {
            None
        };
        if by.is_some() || (stopped.contains(&e[0]) && stopped.contains(&e[1])) {
            leaves.insert(*e);
        }
        handed.extend(by);
    }
    (leaves, handed)
}

/// Whether x lies on one of `planes` (axis, coordinate; [`Simulation::symmetry_planes`]).
pub fn on_symmetry_plane(planes: &[(usize, f64)], x: &Vector3) -> bool {
    planes.iter().any(|&(a, p)| p == x[a])
}

/// The number of front edges at each front node (1 at the ends of an open front).
pub fn front_degree(crack: &crate::crack::three_d::Crack3) -> BTreeMap<u32, usize> {
    let mut ends: BTreeMap<u32, usize> = BTreeMap::new();
    for e in &crack.front {
        for v in e {
            *ends.entry(*v).or_default() += 1;
        }
    }
    ends
}

/// The outward unit normal of the free face at x (module doc, item 5): minus the gradient
/// of the relative volume (with the symmetry planes' images), by central differences half
/// a cell either side along each axis; None where its magnitude times the cell is below
/// [`FACE_GRADIENT`] (x is not at a face: on a flat face it is ¾, one cell inside ⅛). The
/// driver asks at the point one cell behind a front end (along −x1, on the crack's side),
/// so that a face the node is approaching does not tilt the normal of the face it is on.
pub fn free_face(b: &MaterialBoundary3, mat: usize, x: Vector3, planes: &[(usize, f64)], h: f64) -> Option<Vector3> {
    let mut g = Vector3::zeros();
    for a in 0..3 {
        let mut e = Vector3::zeros();
        e[a] = 0.5 * h;
        g[a] = (mirrored_volume(b, mat, x + e, planes) - mirrored_volume(b, mat, x - e, planes)) / h;
    }
    if g.norm() * h < FACE_GRADIENT {
        return None;
    }
    Some(-g.normalize())
}

/// A front node lags when a front neighbour has advanced more than this many increments
/// further (module doc, item 5): one increment is the staircase of asynchronous moves
/// (item 3); one and a half is at least two moves behind.
pub const LAG_INCREMENTS: f64 = 1.5;

/// Consecutive checks with J₁ ≤ 0 before a node left behind at a free face stops for good
/// (module doc, item 5, "left behind at a free face").
pub const DRY_CHECKS: u32 = 4;

/// A free-face end is brought back onto the boundary (module doc, item 5, "back onto the
/// boundary") only when that moves it by more than this many cells.
pub const PULL_BACK_MIN: f64 = 0.1;

/// A free-face end that starts more than this many cells beyond the boundary (direct
/// relative volume, along the face's outward normal) is brought back onto it whatever its
/// move (module doc, item 5, "back onto the boundary").
pub const START_OUTSIDE: f64 = 0.02;

/// Re-spacing (module doc, item 6) changes a target only by more than this many cells:
/// below it the change is rounding (a front that keeps its spacing is left to the bit).
pub const RESPACE_TOL: f64 = 1e-6;

/// Two points are on the same free face (module doc, item 5, "ends at a face") when their
/// face normals make an angle below 45°: a face, not the edge where two faces meet.
pub const SAME_FACE_COS: f64 = std::f64::consts::FRAC_1_SQRT_2;

/// Relative-volume gradient (times the cell) above which a front end is on a free face.
pub const FACE_GRADIENT: f64 = 0.25;

/// The direction of growth `heading` projected on the face of outward normal n, unit;
/// None if the heading is (nearly) normal to the face.
pub fn along_face(heading: Vector3, n: Vector3) -> Option<Vector3> {
    (heading - n * heading.dot(&n)).try_normalize(1e-6)
}

/// Whether a front node at x that does not meet its criterion has reached the material
/// boundary ahead of it (module doc, item 5): its relative volume `volume(x)` (with the
/// images of its symmetry planes and free face) is below [`NEAR_BOUNDARY_VOLUME`] = ¾
/// (the 2D driver's "on the boundary": within 0.29 of a cell of a flat face, where
/// V = 1 − (1 − d/h)²/2), and the point one increment `da` ahead along `ahead` (its x1,
/// along the face for a front end on a free face) lies outside (V < ½), so the boundary
/// is the one ahead of it and its next move would be trimmed.
pub fn near_boundary(volume: impl Fn(Vector3) -> f64, x: Vector3, ahead: Vector3, da: f64) -> bool {
    volume(x) < NEAR_BOUNDARY_VOLUME && volume(x + ahead * da) < BOUNDARY_VOLUME
}

/// The mirror image of x across the plane through p with unit normal n.
pub fn reflect(x: Vector3, p: Vector3, n: Vector3) -> Vector3 {
    x - n * (2.0 * n.dot(&(x - p)))
}
