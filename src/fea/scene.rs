//! A scene file solved statically: the mapping from a [`Scene`] (the MPM input) onto
//! the Q4 FEA, so that one scene runs both ways (`cramp run` and `cramp fea`).
//!
//! The mapping reuses the MPM's own discretisation — [`Scene::build`] fills the bodies
//! with particles, selects the loaded particles and the constrained grid nodes — and
//! turns it into a finite-element model on the same grid (Nairn 2003 §3.1: "the same
//! grid of rectangular, 4-noded elements that was used for the MPM calculations"):
//!
//! * **Elements.** A grid cell becomes an element when it holds at least one particle
//!   of the MPM discretisation. The element takes the body (material, thickness) that
//!   owns most of the cell's particles (ties: the body listed first). For bodies whose
//!   edges lie on grid lines (every verification scene) the mesh is exactly the body;
//!   a cell only partly filled by particles (e.g. at a disk's edge) is meshed in full,
//!   and the summary counts such cells.
//! * **Supports.** `[[boundary]]` conditions act on grid nodes in both methods. Every
//!   constrained grid node's mesh nodes (all crack-face copies, as the MPM fixes every
//!   velocity field of a node) get the displacement the MPM gives that node by the end of
//!   the run ([`EndOfRun`]): 0 for a fixed velocity 0, v·NΔt for a constant velocity,
//!   and for prescribed motion what [`crate::motion::BoundaryMotion::displacement_at`]
//!   says. Grid nodes outside the material have no FEA counterpart and are skipped. Each
//!   connected piece of the mesh (elements joined through
//!   shared edges) must be held against the three rigid motions of the plane; if its
//!   supports leave one free (rollers only, a single pinned node) the error names the
//!   free translation or the centre of the free rotation. A piece without any support
//!   (a free body, like the DCB of Nairn 2003 §3.1) gets the minimal support that removes
//!   its rigid-body modes — one node fixed in x and y, the node farthest from it fixed
//!   across the line joining them — after checking that its loads are in equilibrium
//!   (net force and moment zero to 1e-9 of the load magnitude); the supports then carry
//!   no reaction and do not change the stresses, and the reported displacements have the
//!   piece's mean translation and rotation removed.
//! * **Loads.** The MPM spreads each loaded particle's force f_p to the nodes with its
//!   shape functions, S_ip f_p (Nairn 2003 eq. 28). The FEA lumps the same f_p onto the
//!   four nodes of the element that contains the particle with the Q4 shape functions,
//!   f_a += N_a(x_p) f_p. Because Σ_a N_a = 1 and Σ_a N_a x_a = x_p, every particle
//!   contributes the same force and the same moment as in the MPM. At the initial
//!   positions the nodal loads are in fact identical: linear MPM shape functions are the
//!   Q4 ones, N_a(x_p) = S_ip, and so are the uGIMP ones, because the particle domains of
//!   the regular fill tile the cells and the average of a bilinear function over a domain
//!   that does not straddle a node is its centre value (once the particles move, uGIMP
//!   spreads a particle's force up to one node wider). The full load is applied (a ramp
//!   only matters in time; a `time` function is taken at the end of the run). A
//!   `traction` becomes consistent nodal loads ∫ N_a t dΓ over each loaded particle's
//!   boundary face (Cook et al. 2002, consistent loads; [`GAUSS3`]). Body forces are the particle forces m_p b (eq. 28) lumped the same way;
//!   on a cell filled with n × n particles this is exactly the consistent nodal load
//!   ∫ N_a ρ b t dA (Cook et al. 2002, consistent loads).
//! * **Cracks** are meshed (nodes duplicated along the crack, [`GridMesh::cut_cracks`]).
//!   Every segment must lie on a grid line; interior vertices must be grid nodes. The
//!   MPM splits every grid node on the closed crack polyline into two velocity fields
//!   (the line-crossing test counts a node on the crack, including a node exactly at the
//!   tip; `crack::geometry::crossing_detail`), and leaves whole the first node beyond
//!   the tip. A crack end is therefore meshed at the **first grid node strictly beyond
//!   it** along its last segment: for a tip inside a cell (the placement docs/scene.md
//!   advises) that is the next node; for a tip exactly on a node, the node after it.
//!   The FEA crack then opens along exactly the element edges the MPM crack opens, and
//!   its tip is the first whole node — the node the MPM comparison excludes. The tip
//!   positions before and after meshing are reported. Crack-face contact is not
//!   modelled: the FEA faces are traction-free (check that they open).
//! * **Ignored by the static FEA** (reported as notes): damping, end time, time step,
//!   scheme, shape functions, initial velocities, load ramps, crack contact laws.
//!
//! References: Nairn (2003) §2, §3.1 and appendix; Cook, Malkus, Plesha & Witt (2002),
//! *Concepts and Applications of FEA*, consistent nodal loads and rigid-body modes.

use super::crack::{CrackTip, MeshedCrack};
use super::element;
use super::jintegral::{j_integral, JResult};

use super::mesh::{Grid, GridMesh};
use super::solve::{self, BoundaryConditions, Model, Solution};
use super::{FeaError, Result};
use crate::dim::Vector;
use crate::material::LinearElastic;
use crate::motion::{ComponentFn, TimeFn};
use crate::particles::NO_LOAD;
use crate::scene::Scene;
use std::collections::hash_map::Entry;
use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::time::Instant;

/// Relative tolerance (of the cell size) for "on a grid line" / "on a grid node".
const GRID_TOL: f64 = 1e-9;

/// Relative tolerance of the equilibrium check of an unsupported piece.
const EQUILIBRIUM_TOL: f64 = 1e-9;

/// One scene crack and its meshed counterpart.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneCrack {
    /// Index in the scene's `cracks`.
    pub index: usize,
    /// The polyline as written in the scene.
    pub scene_points: Vec<Vector>,
    /// The polyline as meshed (ends moved to the first grid node beyond them).
    pub meshed_points: Vec<Vector>,
    /// Tips found in the cut mesh (an end on the body boundary is a mouth, not a tip).
    pub meshed: MeshedCrack,
}

/// J and K at one crack tip for the domains that fit in the body.
#[derive(Clone, Debug, PartialEq)]
pub struct TipResult {
    /// Index of the scene crack.
    pub crack: usize,
    /// 0: the tip at the first point of the polyline, 1: at the last.
    pub end: usize,
    /// The end point as written in the scene.
    pub scene_position: Vector,
    /// The meshed tip (first grid node beyond the scene end point).
    pub tip: CrackTip,
    /// One result per domain size (cells = 1, 2, … up to [`MAX_J_CELLS`]) that fits.
    pub domains: Vec<JResult>,
    /// Why the larger domains were not evaluated (empty if all up to [`MAX_J_CELLS`] fit).
    pub skipped: Option<String>,
}

/// Largest J domain evaluated (q = 1 within this many cells of the tip).
pub const MAX_J_CELLS: usize = 8;

/// A solved scene.
#[derive(Clone, Debug)]
pub struct FeaAnalysis {
    pub solution: Solution,
    pub tips: Vec<TipResult>,
    /// Strain energy ½ uᵀKu: ½ fᵀu plus the work of the reactions at non-zero prescribed
    /// displacements.
    pub strain_energy: f64,
    /// Largest |reaction| at the automatic supports (0 in exact arithmetic).
    pub max_auto_reaction: f64,
    /// Number of equations (free DOFs).
    pub equations: usize,
    /// Wall times in seconds: assembly + factorisation + solve, and J.
    pub solve_seconds: f64,
    pub j_seconds: f64,
}

/// A support added to an unsupported piece of the mesh (see the module doc).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AutoSupport {
    pub node: usize,
    /// 0 = x, 1 = y.
    pub component: usize,
}

/// A scene mapped onto the FEA (see the module doc): mesh, element groups (one per
/// body), supports, nodal loads and meshed cracks, plus notes on what was ignored.
#[derive(Clone, Debug)]
pub struct SceneFea {
    pub grid_mesh: GridMesh,
    /// (material, thickness) of every scene body; element `e` uses `groups[element_body[e]]`.
    pub groups: Vec<(LinearElastic, f64)>,
    /// Body of every element.
    pub element_body: Vec<usize>,
    pub bcs: BoundaryConditions,
    pub cracks: Vec<SceneCrack>,
    pub auto_supports: Vec<AutoSupport>,
    /// Mesh nodes of every piece that got automatic supports.
    pub free_pieces: Vec<Vec<usize>>,
    /// Number of particles of the MPM discretisation and how many carry a load or body force.
    pub n_particles: usize,
    pub n_loaded_particles: usize,
    /// Sum of all nodal loads.
    pub load_resultant: Vector,
    /// Cells holding fewer than n × n particles (meshed in full) and cells holding particles of several bodies.
    pub partial_cells: usize,
    pub mixed_cells: usize,
    /// What the static FEA ignored or approximated, one sentence each.
    pub notes: Vec<String>,
}

fn scene_err(field: impl Into<String>, message: impl Into<String>) -> FeaError {
    FeaError::SceneField { field: field.into(), message: message.into() }
}

impl From<&crate::grid::Grid> for Grid {
    fn from(g: &crate::grid::Grid) -> Grid {
        Grid { origin: g.origin, h: g.h, nx: g.nx, ny: g.ny }
    }
}

/// Index of the first grid line strictly beyond coordinate `t` (in cells from the
/// origin) in direction `dir` (±1): the next one if `t` is a grid line itself.
fn next_line(t: f64, dir: f64) -> isize {
    let r = t.round();
    let on = (t - r).abs() <= GRID_TOL * t.abs().max(1.0);
    if dir > 0.0 {
        if on {
            r as isize + 1
        } else {
            t.ceil() as isize
        }
    } else if on {
        r as isize - 1
    } else {
        t.floor() as isize
    }
}

/// The polyline the FEA cuts for scene crack `c` (see the module doc).
fn meshed_polyline(grid: &Grid, c: usize, pts: &[Vector]) -> Result<Vec<Vector>> {
    if pts.len() < 2 {
        return Err(FeaError::CrackTooShort { crack: c, n_points: pts.len() });
    }
    let cells = |p: Vector| Vector::new((p.x - grid.origin.x) / grid.h.x, (p.y - grid.origin.y) / grid.h.y);
    let on_line = |t: f64| (t - t.round()).abs() <= GRID_TOL * t.abs().max(1.0);
    let off = |s: usize, reason: String| FeaError::CrackOffGrid {
        crack: c,
        segment: s,
        x0: pts[s].x,
        y0: pts[s].y,
        x1: pts[s + 1].x,
        y1: pts[s + 1].y,
        reason,
    };
    for s in 0..pts.len() - 1 {
        let (a, b) = (cells(pts[s]), cells(pts[s + 1]));
        let horizontal = (a.y - b.y).abs() <= GRID_TOL * a.y.abs().max(1.0);
        let vertical = (a.x - b.x).abs() <= GRID_TOL * a.x.abs().max(1.0);
        if horizontal && vertical {
            return Err(off(s, "the segment has zero length".into()));
        }
        if !horizontal && !vertical {
            return Err(off(
                s,
                "the segment is neither horizontal nor vertical, so it does not follow a grid line".into(),
            ));
        }
        let (coord, name) = if horizontal { (a.y, "y") } else { (a.x, "x") };
        if !on_line(coord) {
            return Err(off(s, format!("the segment lies between grid lines ({name} is not a multiple of the cell size from the grid origin)")));
        }
        for (k, p) in [(s, a), (s + 1, b)] {
            let inside = p.x >= -GRID_TOL
                && p.y >= -GRID_TOL
                && p.x <= grid.nx as f64 + GRID_TOL
                && p.y <= grid.ny as f64 + GRID_TOL;
            if !inside {
                return Err(off(s, format!("point {k} lies outside the grid")));
            }
        }
        if s > 0 && !(on_line(a.x) && on_line(a.y)) {
            return Err(off(
                s,
                format!("its start (crack point {s}) is a kink between two segments and must be a grid node"),
            ));
        }
    }
    let mut out = pts.to_vec();
    let n = pts.len();
    for (end, prev) in [(0usize, 1usize), (n - 1, n - 2)] {
        let (p, q) = (cells(pts[end]), cells(pts[prev]));
        let d = p - q;
        let moved = if d.x.abs() > d.y.abs() {
            let i = next_line(p.x, d.x.signum()).clamp(0, grid.nx as isize);
            grid.node_position(i as usize, p.y.round() as usize)
        } else {
            let j = next_line(p.y, d.y.signum()).clamp(0, grid.ny as isize);
            grid.node_position(p.x.round() as usize, j as usize)
        };
        out[end] = moved;
    }
    Ok(out)
}

/// A supported piece must be held against the three rigid motions of the plane: the
/// rigid modes (translations x, y and the rotation about `centre`, scaled by `size`)
/// restricted to the prescribed DOFs must have rank 3, i.e. their Gram matrix must have
/// no (relatively) zero eigenvalue. For a connected mesh of fully integrated Q4
/// elements the rigid modes are the whole null space of K, so this is exactly the
/// condition for K_ff to be positive definite (Cook et al. 2002, rigid-body modes).
fn check_rigid_modes(fixed: &[(usize, usize)], x: &[Vector], centre: Vector, size: f64, body: usize) -> Result<()> {
    let rows = fixed.iter().map(|&(a, c)| {
        let d = (x[a] - centre) / size;
        if c == 0 {
            [1.0, 0.0, -d.y]
        } else {
            [0.0, 1.0, d.x]
        }
    });
    let Some(v) = free_rigid_mode(rows) else { return Ok(()) };
    let (t, omega) = (Vector::new(v[0], v[1]), v[2] / size);
    let motion = if omega.abs() * size < 1e-6 * t.norm() {
        if t.y.abs() < 1e-6 * t.norm() {
            "translation in x".to_string()
        } else if t.x.abs() < 1e-6 * t.norm() {
            "translation in y".to_string()
        } else {
            format!("translation along ({:.4}, {:.4})", t.x / t.norm(), t.y / t.norm())
        }
    } else {
        let c = centre + Vector::new(-t.y, t.x) / omega;
        format!("rotation about ({:.6}, {:.6})", c.x, c.y)
    };
    Err(scene_err(
        "boundary",
        format!(
            "the piece of bodies[{body}] around ({:.6}, {:.6}) is not held against rigid motion: its supports (vx = 0 / \
             vy = 0 on {} node component(s)) leave a rigid {motion} free, so the static problem has no unique solution; \
             add [[boundary]] conditions that stop it",
            centre.x,
            centre.y,
            fixed.len()
        ),
    ))
}

/// The body owning every cell (`usize::MAX`: no particle), from the (cell, body) of every
/// particle: the body with most particles in the cell, ties to the body listed first. Also
/// counts the cells holding fewer than `ppc` particles and those holding several bodies.
/// Shared by the Q4 and hex8 scene mappings.
pub(super) fn cell_owners(
    n_cells: usize,
    n_bodies: usize,
    ppc: usize,
    particle_cells: impl Iterator<Item = (usize, usize)>,
) -> (Vec<usize>, usize, usize) {
    let mut counts: BTreeMap<usize, Vec<usize>> = BTreeMap::new();
    for (cell, body) in particle_cells {
        counts.entry(cell).or_insert_with(|| vec![0; n_bodies])[body] += 1;
    }
    let mut cell_body = vec![usize::MAX; n_cells];
    let (mut partial_cells, mut mixed_cells) = (0, 0);
    for (&cell, c) in &counts {
        let total: usize = c.iter().sum();
        // max_by_key keeps the last maximum; iterate in reverse so ties go to the first body.
        let body = (0..n_bodies).rev().max_by_key(|&b| c[b]).unwrap_or(0);
        cell_body[cell] = body;
        if total < ppc {
            partial_cells += 1;
        }
        if c.iter().filter(|&&v| v > 0).count() > 1 {
            mixed_cells += 1;
        }
    }
    (cell_body, partial_cells, mixed_cells)
}

/// Notes on what the static FEA ignores: initial velocities (`moving[k]` for body k) and
/// load ramps (`ramps[k]` of load k). Shared by the Q4 and hex8 mappings.
pub(super) fn motion_notes(notes: &mut Vec<String>, moving: impl Iterator<Item = bool>, ramps: impl Iterator<Item = f64>) {
    for (k, _) in moving.enumerate().filter(|(_, m)| *m) {
        notes.push(format!("bodies[{k}]: the initial velocity is ignored by the static FEA"));
    }
    for (k, ramp) in ramps.enumerate().filter(|(_, r)| *r > 0.0) {
        notes.push(format!("loads[{k}].ramp = {ramp}: the full load is applied (static)"));
    }
}

/// Notes on cells meshed in full although partly filled, and on cells shared by bodies
/// ([`cell_owners`]).
pub(super) fn cell_notes(notes: &mut Vec<String>, partial_cells: usize, ppc: usize, mixed_cells: usize) {
    if partial_cells > 0 {
        notes.push(format!(
            "{partial_cells} cell(s) hold fewer than {ppc} particles and are meshed in full: the FEA body is the union of \
             the cells that hold particles"
        ));
    }
    if mixed_cells > 0 {
        notes.push(format!(
            "{mixed_cells} cell(s) hold particles of several bodies; each element takes the body owning most of them"
        ));
    }
}

/// The eigenvector of the smallest eigenvalue of the Gram matrix Σ rowᵀ row of the rigid
/// modes restricted to the prescribed DOFs (one row per prescribed DOF), if that
/// eigenvalue is zero relative to the largest (1e-9): a rigid motion the supports leave
/// free. For a connected mesh of fully integrated elements the rigid modes are the whole
/// null space of K, so `None` is exactly the condition for K_ff to be positive definite.
pub(super) fn free_rigid_mode<const M: usize>(rows: impl Iterator<Item = [f64; M]>) -> Option<nalgebra::DVector<f64>> {
    let mut gram = nalgebra::DMatrix::<f64>::zeros(M, M);
    for row in rows {
        let row = nalgebra::DVector::from_column_slice(&row);
        gram += &row * row.transpose();
    }
    let eig = gram.symmetric_eigen();
    let (k, min) =
        eig.eigenvalues.iter().enumerate().fold((0, f64::INFINITY), |m, (k, &v)| if v < m.1 { (k, v) } else { m });
    if min > 1e-9 * eig.eigenvalues.iter().fold(0.0, |m: f64, &v| m.max(v)) {
        return None;
    }
    Some(eig.eigenvectors.column(k).into_owned())
}

/// The force on every particle that carries one: its share of a `[[loads]]` force plus
/// m_p b (Nairn 2003 eq. 28), as (particle, force), zero forces left out. Shared by 2D and 3D.
pub(super) fn particle_forces<S: crate::simulation::Dimension>(sim: &crate::simulation::Simulation<S>, t_end: f64) -> Vec<(usize, S::Vector)> {
    let p = &sim.particles;
    (0..p.len())
        .filter_map(|k| {
            let mut f = sim.body_force[p.body[k] as usize] * p.mass[k];
            if p.load[k] != NO_LOAD {
                let load = &sim.loads[p.load[k] as usize];
                match &load.varying {
                    None => f += load.force_per_particle,
                    // A total force with a time function: its value at the end of the run.
                    Some(v) if v.share.is_empty() => f += load.force_per_particle * v.time.at(t_end),
                    // A traction: consistent nodal loads instead (the scene mappings).
                    Some(_) => {}
                }
            }
            (f != <S::Vector as crate::dim::VectorOps>::zeros()).then_some((k, f))
        })
        .collect()
}

/// The end of the MPM run of a scene — its number of steps and time, t accumulated as
/// the time loop does — at which the static FEA takes the loads and the prescribed
/// displacements. Shared by 2D and 3D.
pub(super) struct EndOfRun {
    pub steps: u64,
    pub time: f64,
}

impl EndOfRun {
    pub fn of<S: crate::simulation::Dimension>(sim: &crate::simulation::Simulation<S>, end_time: f64) -> EndOfRun {
        let dt = sim.options.dt;
        let (mut steps, mut time) = (0u64, 0.0f64);
        // Simulation::run_until_stopped's loop (validation bounds the steps).
        while time + 0.5 * dt < end_time {
            time += dt;
            steps += 1;
        }
        EndOfRun { steps, time }
    }

    /// The displacement of component c of every constrained grid node at the end of the
    /// run: a fixed velocity v moves it by v × steps × Δt (0 for a support), a prescribed
    /// motion as [`crate::motion::BoundaryMotion::displacement_at`] says.
    pub fn node_displacements<S: crate::simulation::Dimension>(&self, sim: &crate::simulation::Simulation<S>) -> impl Fn(usize, usize) -> f64 {
        let motion = &sim.bcs.motion;
        let moved: HashMap<(usize, usize), f64> = motion.entries.iter().zip(motion.displacement_at(self.steps, sim.options.dt)).map(|(e, u)| ((e.node as usize, e.comp as usize), u)).collect();
        let vel: HashMap<(usize, usize), f64> = sim.bcs.nodes.iter().flat_map(|&g| (0..S::DIM).map(move |c| (g as usize, c))).map(|(g, c)| ((g, c), sim.bcs.vel[g][c])).collect();
        let travel = self.steps as f64 * sim.options.dt;
        move |g, c| match moved.get(&(g, c)) {
            Some(u) => *u,
            None => {
                let v = vel.get(&(g, c)).copied().unwrap_or(0.0);
                if v == 0.0 {
                    0.0
                } else {
                    v * travel
                }
            }
        }
    }
}

/// The grid axis a unit normal lies along, if it does.
pub(super) fn grid_axis(n: &[f64]) -> Option<usize> {
    n.iter().position(|v| v.abs() == 1.0)
}

/// The regular fill's particle lattice (sub-cell indices of every particle's initial
/// position), to find on which side a loaded particle's domain face is on the boundary.
pub(super) struct Lattice {
    origin: [f64; 3],
    cells: std::collections::HashSet<[i64; 3]>,
}

impl Lattice {
    pub fn new<S: crate::simulation::Dimension>(p: &crate::particles::Particles<S>, origin: &S::Vector) -> Lattice {
        let origin = std::array::from_fn(|c| if c < S::DIM { origin[c] } else { 0.0 });
        let mut l = Lattice { origin, cells: Default::default() };
        for k in 0..p.len() {
            let i = l.index::<S>(&p.x0[k], &p.lp[k]);
            l.cells.insert(i);
        }
        l
    }

    fn index<S: crate::simulation::Dimension>(&self, x: &S::Vector, lp: &S::Vector) -> [i64; 3] {
        std::array::from_fn(|c| if c < S::DIM { ((x[c] - self.origin[c]) / (2.0 * lp[c]) - 0.5).round() as i64 } else { 0 })
    }

    /// The side (+1 or −1 along `axis`) on which particle (x, lp)'s domain face is on the
    /// boundary: the side with no particle next to it (+1 if both have none or both have one).
    pub fn exposed_side<S: crate::simulation::Dimension>(&self, x: &S::Vector, lp: &S::Vector, axis: usize) -> f64 {
        let i = self.index::<S>(x, lp);
        let has = |d: i64| {
            let mut j = i;
            j[axis] += d;
            self.cells.contains(&j)
        };
        if !has(1) || has(-1) {
            1.0
        } else {
            -1.0
        }
    }
}

/// Three-point Gauss rule on [−1, 1] (points, weights): exact for polynomials of degree 5,
/// so a traction up to cubic times the linear shape functions is integrated exactly.
pub(super) const GAUSS3: [(f64, f64); 3] = [(-0.774_596_669_241_483_4, 5.0 / 9.0), (0.0, 8.0 / 9.0), (0.774_596_669_241_483_4, 5.0 / 9.0)];

/// The connected pieces of a mesh: elements joined through a shared side (`sides`: the
/// local node lists of an element's edges in 2D, faces in 3D; a shared corner or, in 3D,
/// edge is a hinge and does not join). Keyed by the first element of each piece, with
/// the piece's nodes. Union–find in element order, so the result is deterministic.
pub(super) fn connected_pieces<const N: usize, const K: usize>(
    elements: &[[usize; N]],
    sides: &[[usize; K]],
) -> BTreeMap<usize, BTreeSet<usize>> {
    let mut parent: Vec<usize> = (0..elements.len()).collect();
    let mut side_owner: HashMap<[usize; K], usize> = HashMap::new();
    for (e, conn) in elements.iter().enumerate() {
        for side in sides {
            let mut key = side.map(|k| conn[k]);
            key.sort_unstable();
            match side_owner.entry(key) {
                Entry::Occupied(o) => {
                    let (ra, rb) = (root(&mut parent, e), root(&mut parent, *o.get()));
                    if ra != rb {
                        parent[ra.max(rb)] = ra.min(rb);
                    }
                }
                Entry::Vacant(v) => {
                    v.insert(e);
                }
            }
        }
    }
    let mut pieces: BTreeMap<usize, BTreeSet<usize>> = BTreeMap::new();
    for (e, conn) in elements.iter().enumerate() {
        let r = root(&mut parent, e);
        pieces.entry(r).or_default().extend(conn.iter().copied());
    }
    pieces
}

/// Union–find root with path halving.
fn root(parent: &mut [usize], mut a: usize) -> usize {
    while parent[a] != a {
        parent[a] = parent[parent[a]];
        a = parent[a];
    }
    a
}

impl SceneFea {
    /// Map a scene onto the FEA (see the module doc). Errors name the scene field.
    pub fn from_scene(scene: &Scene) -> Result<SceneFea> {
        refuse_body_lattice(scene.solver.lattice)?;
        let sim = scene.build()?;
        let grid = Grid::from(&sim.grid);
        let p = &sim.particles;
        let n_bodies = scene.bodies.len();

        // Elements: cells holding particles; body by majority.
        let cell_of = |x: Vector| -> usize {
            let i = (((x.x - grid.origin.x) / grid.h.x).floor() as usize).min(grid.nx - 1);
            let j = (((x.y - grid.origin.y) / grid.h.y).floor() as usize).min(grid.ny - 1);
            grid.cell_index(i, j)
        };
        let ppc = scene.solver.particles_per_cell * scene.solver.particles_per_cell;
        let (cell_body, partial_cells, mixed_cells) = cell_owners(
            grid.nx * grid.ny,
            n_bodies,
            ppc,
            (0..p.len()).map(|k| (cell_of(p.x[k]), p.body[k] as usize)),
        );
        let mut grid_mesh = GridMesh::from_grid(grid, |i, j, _| cell_body[grid.cell_index(i, j)] != usize::MAX)?;
        let element_body: Vec<usize> =
            grid_mesh.element_cell.iter().map(|&[i, j]| cell_body[grid.cell_index(i, j)]).collect();
        let groups: Vec<(LinearElastic, f64)> = scene
            .bodies
            .iter()
            .map(|b| {
                let m = scene.materials.iter().position(|m| m.name == b.material).unwrap_or(0);
                (sim.materials[m], b.thickness)
            })
            .collect();

        // Cracks.
        let mut polylines = Vec::with_capacity(scene.cracks.len());
        for (c, spec) in scene.cracks.iter().enumerate() {
            let pts: Vec<Vector> = spec.points.iter().map(|q| Vector::new(q[0], q[1])).collect();
            polylines.push(meshed_polyline(&grid, c, &pts)?);
        }
        let meshed = grid_mesh.cut_cracks(&polylines)?;
        let cracks = meshed
            .into_iter()
            .enumerate()
            .map(|(c, m)| SceneCrack {
                index: c,
                scene_points: scene.cracks[c].points.iter().map(|q| Vector::new(q[0], q[1])).collect(),
                meshed_points: polylines[c].clone(),
                meshed: m,
            })
            .collect();

        let mesh = &grid_mesh.mesh;
        let mut bcs = BoundaryConditions::new(mesh);
        let mut notes = vec!["static, linear-elastic, small-strain analysis: solver.damping, solver.end_time, the \
                              time step, the scheme and the shape functions are not used"
            .to_string()];
        if !scene.cracks.is_empty() && scene.solver.crack_method == crate::crack::CrackMethod::Visibility {
            notes.push(
                "solver.crack_method = \"visibility\" is an MPM option: the FEA meshes the cracks (duplicated nodes), \
                 which is what the default velocity fields reproduce"
                    .to_string(),
            );
        }

        // Supports on every mesh node at a constrained grid node: the displacement the
        // MPM gives the grid node by the end of the run (0 for a fixed support).
        let end = EndOfRun::of(&sim, scene.solver.end_time);
        let prescribed = end.node_displacements(&sim);
        for &g in &sim.bcs.nodes {
            let g = g as usize;
            let (i, j) = sim.grid.node_ij(g);
            let mask = sim.bcs.mask[g];
            for a in grid_mesh.nodes_at(i, j) {
                for c in 0..2 {
                    if mask & (1 << c) != 0 {
                        bcs.prescribe(a, c, prescribed(g, c))?;
                    }
                }
            }
        }
        for (k, b) in scene.boundary.iter().enumerate() {
            let tol = b.nodes.tolerance(sim.grid.min_h());
            let hits = (0..mesh.n_nodes()).filter(|&a| b.nodes.contains(&mesh.nodes[a], tol)).count();
            if hits == 0 {
                notes.push(format!(
                    "boundary[{k}] selects only grid nodes outside the material: it has no effect on the FEA"
                ));
            }
        }

        // Loads and body forces, particle by particle.
        let mut n_loaded_particles = 0;
        let mut load_resultant = Vector::zeros();
        for (k, f) in particle_forces(&sim, end.time) {
            n_loaded_particles += 1;
            let cell = cell_of(p.x[k]);
            let (i, j) = (cell % grid.nx, cell / grid.nx);
            let Some(e) = grid_mesh.element_at(i as isize, j as isize) else {
                return Err(FeaError::InvalidInput(format!("loaded particle at {:?} is in no element", p.x[k])));
            };
            let c = grid.cell_center(i, j);
            let nf = element::shape(2.0 * (p.x[k].x - c.x) / grid.h.x, 2.0 * (p.x[k].y - c.y) / grid.h.y);
            for (a, &node) in mesh.elements[e].iter().enumerate() {
                bcs.point_load(node, f * nf[a])?;
            }
            load_resultant += f;
        }
        // Tractions as consistent nodal loads over each particle's face.
        let lattice = Lattice::new(p, &sim.grid.origin);
        for (li, l) in scene.loads.iter().enumerate() {
            let Some(traction) = &l.traction else { continue };
            let field = format!("loads[{li}]");
            let comps: Vec<ComponentFn> = traction.iter().enumerate().map(|(c, t)| ComponentFn::new(&format!("{field}.traction[{c}]"), t, 2)).collect::<std::result::Result<_, _>>().map_err(|(f, m)| scene_err(f, m))?;
            let time = TimeFn::new(&format!("{field}.time"), l.time.as_ref()).map_err(|(f, m)| scene_err(f, m))?;
            let normal = scene.load_normal(li)?.unwrap_or_default();
            let axis = grid_axis(&normal).ok_or_else(|| scene_err(format!("{field}.normal"), format!("{normal:?}: the FEA applies tractions on faces normal to a grid axis only")))?;
            for k in (0..p.len()).filter(|&k| p.load[k] == li as u16) {
                let (x0, lp) = (p.x0[k], p.lp[k]);
                let side = lattice.exposed_side::<crate::dim::D2>(&x0, &lp, axis);
                let across = 1 - axis;
                let thickness = scene.bodies[p.body[k] as usize].thickness;
                let cell = cell_of(x0);
                let (i, j) = (cell % grid.nx, cell / grid.nx);
                let e = grid_mesh.element_at(i as isize, j as isize).ok_or_else(|| FeaError::InvalidInput(format!("loaded particle at {x0:?} is in no element")))?;
                let c = grid.cell_center(i, j);
                for (s, w) in GAUSS3 {
                    let mut xf = x0;
                    xf[axis] += side * lp[axis];
                    xf[across] += s * lp[across];
                    let t = crate::motion::point(&[xf.x, xf.y], end.time);
                    let tr = Vector::new(comps[0].at(&t), comps[1].at(&t)) * (time.at(end.time) * w * lp[across] * thickness);
                    let nf = element::shape(2.0 * (xf.x - c.x) / grid.h.x, 2.0 * (xf.y - c.y) / grid.h.y);
                    for (a, &node) in mesh.elements[e].iter().enumerate() {
                        bcs.point_load(node, tr * nf[a])?;
                    }
                    load_resultant += tr;
                }
                n_loaded_particles += 1;
            }
        }

        // Pieces (elements joined through shared edges; a corner-only contact is a hinge):
        // supported ones must be held against every rigid motion, unsupported ones must be
        // in equilibrium and get the minimal support.
        let pieces = connected_pieces(&mesh.elements, &[[0, 1], [1, 2], [2, 3], [3, 0]]);
        let mut auto_supports = Vec::new();
        let mut free_pieces = Vec::new();
        let forces = bcs.forces().to_vec();
        for (&first_element, nodes) in &pieces {
            let nodes: Vec<usize> = nodes.iter().copied().collect();
            let body = element_body[first_element];
            let centre = nodes.iter().fold(Vector::zeros(), |s, &a| s + mesh.nodes[a]) / nodes.len() as f64;
            let size =
                nodes.iter().map(|&a| (mesh.nodes[a] - centre).norm()).fold(0.0, f64::max).max(grid.h.x.min(grid.h.y));
            let fixed: Vec<(usize, usize)> = nodes
                .iter()
                .flat_map(|&a| (0..2).map(move |c| (a, c)))
                .filter(|&(a, c)| bcs.prescribed()[2 * a + c].is_some())
                .collect();
            if !fixed.is_empty() {
                check_rigid_modes(&fixed, &mesh.nodes, centre, size, body)?;
                continue;
            }
            let x = |a: usize| mesh.nodes[a];
            let f = |a: usize| Vector::new(forces[2 * a], forces[2 * a + 1]);
            let magnitude: f64 = nodes.iter().map(|&a| f(a).norm()).sum();
            let net = nodes.iter().fold(Vector::zeros(), |s, &a| s + f(a));
            let moment: f64 = nodes.iter().map(|&a| (x(a) - centre).perp(&f(a))).sum();
            if net.norm() > EQUILIBRIUM_TOL * magnitude || moment.abs() > EQUILIBRIUM_TOL * magnitude * size {
                return Err(scene_err(
                    "boundary",
                    format!(
                        "the piece of bodies[{body}] around ({:.6}, {:.6}) has no support and its loads are not in equilibrium \
                         (net force ({:e}, {:e}), net moment {:e} about its centre): a static solution does not exist; \
                         add [[boundary]] conditions (vx = 0 / vy = 0) on it",
                        centre.x, centre.y, net.x, net.y, moment
                    ),
                ));
            }
            let a = nodes[0];
            let far = *nodes
                .iter()
                .max_by(|&&u, &&v| (x(u) - x(a)).norm().total_cmp(&(x(v) - x(a)).norm()).then(v.cmp(&u)))
                .unwrap_or(&a);
            let d = x(far) - x(a);
            let comp = if d.x.abs() >= d.y.abs() { 1 } else { 0 };
            for (node, component) in [(a, 0), (a, 1), (far, comp)] {
                bcs.prescribe(node, component, 0.0)?;
                auto_supports.push(AutoSupport { node, component });
            }
            free_pieces.push(nodes.clone());
            notes.push(format!(
                "the piece around ({:.6}, {:.6}) has no [[boundary]] support; its loads are in equilibrium, so the FEA \
                 removes its rigid-body modes by fixing node {a} at ({:.6}, {:.6}) in x and y and node {far} at \
                 ({:.6}, {:.6}) in {} (zero reactions, stresses unaffected); its displacements are reported with the mean \
                 translation and rotation of its nodes removed",
                centre.x,
                centre.y,
                x(a).x,
                x(a).y,
                x(far).x,
                x(far).y,
                if comp == 0 { "x" } else { "y" }
            ));
        }

        // Notes on the rest.
        motion_notes(
            &mut notes,
            scene.bodies.iter().map(|b| b.velocity != [0.0, 0.0] || b.velocity_sine.is_some()),
            scene.loads.iter().map(|l| l.ramp),
        );
        for (k, c) in scene.cracks.iter().enumerate() {
            if c.contact != crate::scene::ContactSpec::None {
                notes.push(format!(
                    "cracks[{k}].contact is not modelled: the FEA crack faces are traction-free and may overlap (check the opening)"
                ));
            }
        }
        cell_notes(&mut notes, partial_cells, ppc, mixed_cells);
        Ok(SceneFea {
            grid_mesh,
            groups,
            element_body,
            bcs,
            cracks,
            auto_supports,
            free_pieces,
            n_particles: p.len(),
            n_loaded_particles,
            load_resultant,
            partial_cells,
            mixed_cells,
            notes,
        })
    }

    /// The model: element groups = scene bodies.
    pub fn model(&self) -> Result<Model<'_>> {
        Model::with_groups(&self.grid_mesh.mesh, self.groups.clone(), self.element_body.clone())
    }

    /// Solve, recover stresses and evaluate J and K at every crack tip for domains of
    /// 1 to [`MAX_J_CELLS`] cells (as many as fit in the body; equivalent domain integral
    /// and interaction integral, [`super::jintegral`]).
    pub fn analyse(&self) -> Result<FeaAnalysis> {
        let model = self.model()?;
        let t0 = Instant::now();
        let system = solve::assemble(&model, &self.bcs)?;
        let equations = system.n_equations();
        let dofs = system.factorize_and_solve()?;
        let mut displacement: Vec<Vector> = dofs.chunks_exact(2).map(|u| Vector::new(u[0], u[1])).collect();
        let nodes = &self.grid_mesh.mesh.nodes;
        for piece in &self.free_pieces {
            // Remove the least-squares rigid motion ū + ω e_z × (x − x̄) (equal node weights):
            // the automatic supports fix an arbitrary one; this gauge keeps symmetric
            // problems symmetric. Rigid motion is strain-free in the Q4 (exactly
            // reproduced), so stresses and reactions do not change.
            let n = piece.len() as f64;
            let xm = piece.iter().fold(Vector::zeros(), |s, &a| s + nodes[a]) / n;
            let um = piece.iter().fold(Vector::zeros(), |s, &a| s + displacement[a]) / n;
            let (num, den) = piece.iter().fold((0.0, 0.0), |(p, q), &a| {
                let r = nodes[a] - xm;
                (p + r.perp(&(displacement[a] - um)), q + r.norm_squared())
            });
            let omega = if den > 0.0 { num / den } else { 0.0 };
            for &a in piece {
                let r = nodes[a] - xm;
                displacement[a] -= um + Vector::new(-r.y, r.x) * omega;
            }
        }
        let solution = solve::postprocess(&model, &self.bcs, displacement);
        let solve_seconds = t0.elapsed().as_secs_f64();
        let f = self.bcs.forces();
        // ½ uᵀ f_int: the loads' work, plus that of the reactions at non-zero prescribed
        // displacements (f_int = f_ext + reaction).
        let pre = self.bcs.prescribed();
        let strain_energy = 0.5
            * (solution.displacement.iter().enumerate().map(|(a, u)| u.x * f[2 * a] + u.y * f[2 * a + 1]).sum::<f64>()
                + (0..pre.len()).filter(|&d| pre[d].is_some_and(|v| v != 0.0)).map(|d| pre[d].unwrap_or(0.0) * solution.reaction[d / 2][d % 2]).sum::<f64>());
        let max_auto_reaction =
            self.auto_supports.iter().map(|s| solution.reaction[s.node][s.component].abs()).fold(0.0, f64::max);
        let t1 = Instant::now();
        let mut tips = Vec::new();
        for (crack, end, tip) in self.tips() {
            let pts = &self.cracks[crack].scene_points;
            let scene_position = if end == 0 { pts[0] } else { pts[pts.len() - 1] };
            let mut domains = Vec::new();
            let mut skipped = None;
            for cells in 1..=MAX_J_CELLS {
                match j_integral(&self.grid_mesh, &model, &solution, &tip, cells) {
                    Ok(r) => domains.push(r),
                    Err(e @ (FeaError::JDomainLeavesBody { .. } | FeaError::BadTip { .. })) => {
                        skipped = Some(format!("domains of {cells} to {MAX_J_CELLS} cells not evaluated: {e}"));
                        break;
                    }
                    Err(e) => return Err(e),
                }
            }
            tips.push(TipResult { crack, end, scene_position, tip, domains, skipped });
        }
        Ok(FeaAnalysis {
            solution,
            tips,
            strain_energy,
            max_auto_reaction,
            equations,
            solve_seconds,
            j_seconds: t1.elapsed().as_secs_f64(),
        })
    }

    /// Every crack tip of the mesh, in crack order (start before end).
    pub fn tips(&self) -> Vec<(usize, usize, CrackTip)> {
        let mut out = Vec::new();
        for c in &self.cracks {
            for (end, t) in c.meshed.tips.iter().enumerate() {
                if let Some(t) = t {
                    out.push((c.index, end, *t));
                }
            }
        }
        out
    }
}

/// `cramp fea` meshes the grid's cells as the grid's particle lattice fills them (a cell's
/// particles tile it): refused for `solver.lattice = "body"`, whose particles lie off the
/// cells' sub-cell centres, with an error naming the field.
pub(crate) fn refuse_body_lattice(lattice: crate::scene::Lattice) -> Result<()> {
    if lattice == crate::scene::Lattice::Body {
        return Err(FeaError::SceneField {
            field: "solver.lattice".into(),
            message: "\"body\" anchors the particles to the bodies, off the grid cells that `cramp fea` meshes; use the default \"grid\" for the FEA of a scene".into(),
        });
    }
    Ok(())
}
