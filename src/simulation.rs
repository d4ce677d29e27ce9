//! The state of a run — grid, particles, materials, boundary conditions, loads,
//! cracks — and the time loop around [`crate::step`].

use crate::check::CheckError;
use crate::crack::CrackMethod;
use crate::dim::{GridGeometry, Space, SymOps, Vector, VectorOps, D2};
use crate::exact;
use crate::grid::Nodes;
use crate::material::{Constitutive, LinearElastic};

use crate::particles::{Particles, NO_LOAD};
use crate::shape::ShapeKind;
use serde::{Deserialize, Serialize};
use std::fmt::Debug;

/// A dimension as the time step sees it: [`Space`] (vectors, tensors, grid, shape
/// functions) and its crack machinery — line crossing, contact, crack motion and growth
/// in 2D (polylines, [`crate::crack`]), triangulated crack surfaces in 3D
/// ([`crate::crack::three_d`], growth in [`crate::fracture::growth3`]). The step calls these once per step
/// and only in scenes with cracks; the per-particle and per-node loops inside them are
/// each dimension's own.
pub trait Dimension: Space {
    /// One crack of this dimension.
    type Crack: Clone + Debug + Send + Sync + crate::contact::CrackFaces;
    /// Crack growth state (001 §2.3).
    type Growth: Clone + Debug + Send + Sync;
    /// Task 1 with cracks: velocity field of every particle–node pair (line crossing).
    fn task1_cracks(sim: &mut Simulation<Self>) -> Result<(), CheckError>;
    /// Task 1 with cracks, after the gathers: nodal normals, field counts.
    fn finish_crack_nodes(sim: &mut Simulation<Self>) -> Result<(), CheckError>;
    /// Contact on the momenta of Task 1 / Task 6c (Nairn 2003 eqs. 13–19).
    fn contact_momenta(sim: &mut Simulation<Self>) -> Result<(), CheckError>;
    /// Contact on the momenta updated in Task 4, forces back-computed.
    fn contact_updated_momenta(sim: &mut Simulation<Self>) -> Result<(), CheckError>;
    /// Normal opening of crack c's tracked surfaces at node i along the node's crack
    /// normal `n` (from above to below; contact detection by opening): positive when the
    /// faces are apart, None without a crack segment near it.
    fn normal_gap(sim: &Simulation<Self>, c: usize, i: usize, n: Self::Vector) -> Option<f64>;
    /// Task 7: move the cracks in the centre-of-mass velocity field.
    fn task7_move_cracks(sim: &mut Simulation<Self>);
    /// Hold the faces of new crack segments still in release on the forces of Task 3
    /// ([`crate::fracture::release`]; 2D only).
    fn hold_released(_sim: &mut Simulation<Self>) {}
    /// Add the tractions of cohesive crack segments to Task 3's forces
    /// ([`crate::fracture::cohesive`]; 2D only).
    fn apply_cohesive(_sim: &mut Simulation<Self>) {}
    /// Crack propagation at the end of a step (only when the scene lets cracks grow).
    fn grow_cracks(sim: &mut Simulation<Self>) -> Result<(), CheckError>;
    /// Checked mode: no particle crossed a crack.
    fn check_crack_sides(sim: &mut Simulation<Self>) -> Result<(), CheckError>;
    /// The exact state of the cracks as 64-bit words (for [`crate::fingerprint`]).
    fn crack_state_bits(cracks: &[Self::Crack]) -> Vec<u64>;
}

/// The four ways to order the stress update within a step (Nairn 2003 §2.3 and appendix).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Scheme {
    /// Update stress last, from the momenta after Task 4 (Sulsky, Chen & Schreyer 1994).
    Usl,
    /// Modified USL: re-extrapolate the new particle momenta first (Sulsky, Zhou & Schreyer 1995).
    Musl,
    /// Update stress first, from the momenta of Task 1 (Bardenhagen 2002).
    Usf,
    /// Average of USF and MUSL, each with half the time step (Nairn 2003).
    Usavg,
}

/// What the damping term ∫ ρ κ u̇·δu dV of Guo & Nairn 2004 eq. 1 acts on.
///
/// Both choices put the same force −κp on every node (eq. 28), so the grid momenta and
/// the static state are the same. They differ in the particle velocity update of Task 5:
/// with `Grid` a particle is damped by −κ Σ S v_i, the grid's view of its velocity, and
/// the part of the particle velocities the grid cannot see (FLIP's null space) is never
/// damped; with `Particles` it is damped by −κ v_p, so everything decays as e^{−κt}.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum DampingOn {
    /// −κp on the nodes only (Nairn 2003 eq. 28; NairnMPM's grid damping).
    #[default]
    Grid,
    /// The same nodal force, and each particle's velocity damped by −κ v_p rather than
    /// −κ Σ S v_i (NairnMPM's particle damping at the same κ).
    Particles,
}

/// Solver options of a scene.
#[derive(Clone, Debug, PartialEq)]
pub struct Options {
    pub scheme: Scheme,
    pub shape: ShapeKind,
    /// Time step.
    pub dt: f64,
    /// Damping coefficient κ of eq. 28 (1/time).
    pub damping: f64,
    /// What the damping κ acts on: the grid momenta only (the papers' eq. 28) or the
    /// particle velocities as well.
    pub damping_on: DampingOn,
    /// Run the invariant checks every step.
    pub checked: bool,
    /// How cracks act on the particle–node pairs (CRAMP velocity fields by default).
    pub crack_method: CrackMethod,
    /// Length of the crack-tip zone ([`crate::crack::tip_zone`]; 2D), 0 for none (the
    /// papers' all-or-nothing pairs).
    pub tip_zone: f64,
}

/// A load on a set of particles: the same force on each, ramped linearly from zero over
/// `ramp` (applied in full at t = 0 when `ramp` is 0); or, with `varying`, a force that
/// follows a time function or differs from particle to particle (a traction,
/// [`crate::motion::LoadVariation`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Load<V = Vector> {
    pub force_per_particle: V,
    pub ramp: f64,
    pub varying: Option<Box<crate::motion::LoadVariation<V>>>,
}

impl<V: VectorOps> Load<V> {
    /// The same force on each particle, ramped over `ramp`.
    pub fn uniform(force_per_particle: V, ramp: f64) -> Self {
        Load { force_per_particle, ramp, varying: None }
    }

    /// The force per particle of a uniform load at time t.
    pub fn at(&self, t: f64) -> V {
        if self.ramp > 0.0 && t < self.ramp {
            self.force_per_particle * (t / self.ramp)
        } else {
            self.force_per_particle
        }
    }

    /// The force on the particle with id `id` and initial position `x0` at time t.
    #[inline]
    pub fn force_on(&self, t: f64, id: u32, x0: &V) -> V {
        match &self.varying {
            None => self.at(t),
            Some(v) => v.force(self.force_per_particle, t, id as usize, x0),
        }
    }
}

/// Velocity boundary conditions resolved onto nodes: bit c fixes component c (x, y, z).
#[derive(Clone, Debug, Default)]
pub struct NodeBcs<V = Vector> {
    pub mask: Vec<u8>,
    pub vel: Vec<V>,
    /// Nodes with any condition, ascending.
    pub nodes: Vec<u32>,
    /// The node components whose prescribed velocity changes in time (`vel` is rewritten
    /// for them every step; empty for constant velocities).
    pub motion: crate::motion::BoundaryMotion,
}

impl<V: VectorOps> NodeBcs<V> {
    pub fn new(num_nodes: usize) -> Self {
        NodeBcs { mask: vec![0; num_nodes], vel: vec![V::zeros(); num_nodes], nodes: Vec::new(), motion: Default::default() }
    }

    /// Fix component `c` (0 = x, 1 = y, 2 = z) of node `i` to velocity `v`.
    pub fn fix(&mut self, i: usize, c: usize, v: f64) {
        if self.mask[i] == 0 {
            self.nodes.push(i as u32);
        }
        self.mask[i] |= 1 << c;
        self.vel[i][c] = v;
    }

    pub fn finish(&mut self) {
        self.nodes.sort_unstable();
    }

    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }
}

/// Energies of the run (all extensive: they include the thickness).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Energies {
    pub kinetic: f64,
    pub strain: f64,
    /// Work done on the body by particle loads and body forces since t = 0.
    pub external_work: f64,
    /// Energy removed by the damping term −κp of eq. 28 since t = 0.
    pub damping: f64,
    /// Work done on the body by the velocity boundary conditions since t = 0: at every
    /// node component held at a non-zero velocity v_c, the reaction (the force Task 3
    /// removes there) times v_c Δt. Zero when every condition holds its nodes still.
    pub boundary_work: f64,
}

impl Energies {
    /// Kinetic + strain + damped − external work − boundary work: constant for an exact
    /// integrator. (The boundary work is +0 in a scene whose conditions hold their nodes
    /// still, so there the total has the same bits as without it.)
    pub fn total(&self) -> f64 {
        self.kinetic + self.strain + self.damping - self.external_work - self.boundary_work
    }
}

/// Per-particle/node pair data of the current step, laid out flat with stride
/// [`Space::MAX_NODES`] per particle (9 in 2D, 27 in 3D), and the node → pair incidence
/// (CSR) that turns every particle-to-grid sum into a gather over a node's pairs.
#[derive(Clone, Debug, Default)]
pub struct Pairs<S: Space = D2> {
    pub count: Vec<u8>,
    pub node: Vec<u32>,
    pub s: Vec<f64>,
    pub g: Vec<S::Vector>,
    /// Velocity field ν(p,i) ∈ {0,1,2} (eq. 2); all 0 without cracks.
    pub field: Vec<u8>,
    /// Share of the particle in field `field` at this node: 1 except for pairs in a
    /// crack-tip zone ([`crate::crack::tip_zone`], 2D), whose remaining 1 − share is in
    /// field 0.
    pub frac: Vec<f64>,
    /// Compact index of each node active this step (u32::MAX: not active); reset on the
    /// active nodes only, so its upkeep scales with the material, not the grid.
    pub slot: Vec<u32>,
    /// CSR over the active nodes in ascending order: the pairs of the active node with
    /// compact index a are `items[start[a]..start[a+1]]` (pair index p·MAX_NODES + k).
    pub start: Vec<u32>,
    pub items: Vec<u32>,
}

impl<S: Space> Pairs<S> {
    pub fn with_capacity(np: usize, nn: usize) -> Self {
        let stride = S::MAX_NODES;
        Pairs {
            count: vec![0; np],
            node: vec![0; np * stride],
            s: vec![0.0; np * stride],
            g: vec![S::Vector::zeros(); np * stride],
            field: vec![0; np * stride],
            frac: vec![1.0; np * stride],
            slot: vec![u32::MAX; nn],
            start: Vec::new(),
            items: Vec::with_capacity(np * stride),
        }
    }

    /// Pair indices of node `i` (after the CSR build of Task 1).
    #[inline]
    pub fn of_node(&self, i: usize) -> &[u32] {
        match self.slot.get(i) {
            Some(&a) if a != u32::MAX => &self.items[self.start[a as usize] as usize..self.start[a as usize + 1] as usize],
            _ => &[],
        }
    }

    /// Pair indices of the active node at position `a` of the ascending active list
    /// (`nodes.active[a]`): the gathers run over the active nodes in order, so they index
    /// `start` directly instead of looking the node up in `slot`.
    #[inline]
    pub fn of_active(&self, a: usize) -> &[u32] {
        &self.items[self.start[a] as usize..self.start[a + 1] as usize]
    }

    /// Pair indices of particle `p`.
    #[inline]
    pub fn of_particle(&self, p: usize) -> std::ops::Range<usize> {
        let base = p * S::MAX_NODES;
        base..base + self.count[p] as usize
    }
}

/// One MPM analysis: everything the time step reads and writes. Generic over the
/// dimension (`Simulation` alone is 2D; `Simulation<D3>` is 3D).
#[derive(Clone, Debug)]
pub struct Simulation<S: Dimension = D2> {
    pub grid: S::Grid,
    pub particles: Particles<S>,
    pub materials: Vec<LinearElastic>,
    /// Body force (acceleration) per body.
    pub body_force: Vec<S::Vector>,
    /// Thickness per body (2D; 1 in 3D), so particle areas can be recovered for contact volumes.
    pub thickness: Vec<f64>,
    pub loads: Vec<Load<S::Vector>>,
    pub bcs: NodeBcs<S::Vector>,
    pub cracks: Vec<S::Crack>,
    pub options: Options,
    pub nodes: Nodes<S::Vector>,
    pub pairs: Pairs<S>,
    /// Buffers of the parallel gathers, kept across steps.
    pub scratch: crate::step::Scratch<S>,
    pub time: f64,
    pub step_count: u64,
    /// Accumulated external work and damping (kinetic and strain are computed on demand).
    pub work: Energies,
    /// Total particle momentum at the start of the current step (checked mode).
    pub(crate) momentum_ref: S::Vector,
    /// Whether momentum must be conserved: no loads, body forces, boundary conditions or damping.
    pub(crate) momentum_conserving: bool,
    /// Total energy scale at t = 0 for the instability check.
    pub(crate) energy_scale: f64,
    /// Side (+1 above, −1 below, 0 unknown) of each particle relative to each crack,
    /// index id·ncracks + c with the particle's id (checked mode, cracks only).
    pub(crate) crack_side: Vec<i8>,
    /// 3D: the crack triangle each particle's known side was read from (same index as
    /// `crack_side`; checked mode, cracks only; empty in 2D).
    pub(crate) crack_side_triangle: Vec<u32>,
    /// 3D: each crack's triangle count at the last side check (checked mode; triangles are
    /// only ever appended, so those at or past it were made since by growth).
    pub(crate) crack_side_seen: Vec<usize>,
    /// Crack growth (001 §2.3), when a scene lets a crack grow; None otherwise.
    pub growth: Option<S::Growth>,
}

/// Largest stable time step estimate: the smallest cell dimension over the fastest
/// dilatational wave speed c_d = √((λ+2μ)/ρ) (plane strain/stress λ in 2D, the 3D λ in 3D).
pub fn cfl_time_step<V, G: GridGeometry<V>>(grid: &G, materials: &[LinearElastic]) -> f64 {
    let c = materials.iter().map(|m| m.wave_speed()).fold(0.0, f64::max);
    grid.min_h() / c
}

impl Simulation {
    /// [`cfl_time_step`] of a 2D grid.
    pub fn cfl_dt(grid: &crate::grid::Grid, materials: &[LinearElastic]) -> f64 {
        cfl_time_step(grid, materials)
    }
}

/// A verification case records the fingerprint of every simulation it ran
/// ([`crate::fingerprint`]); nothing happens outside a case.
impl<S: Dimension> Drop for Simulation<S> {
    fn drop(&mut self) {
        crate::fingerprint::on_drop(self);
    }
}

impl<S: Dimension> Simulation<S> {
    /// Assemble a simulation; `dt` and everything else come resolved from the scene.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        grid: S::Grid,
        particles: Particles<S>,
        materials: Vec<LinearElastic>,
        body_force: Vec<S::Vector>,
        thickness: Vec<f64>,
        loads: Vec<Load<S::Vector>>,
        bcs: NodeBcs<S::Vector>,
        cracks: Vec<S::Crack>,
        options: Options,
    ) -> Self {
        let nn = grid.num_nodes();
        let np = particles.len();
        let momentum_conserving = loads.is_empty()
            && body_force.iter().all(|b| *b == S::Vector::zeros())
            && bcs.is_empty()
            && options.damping == 0.0;
        let nodes = Nodes::new(nn, !cracks.is_empty());
        let mut sim = Simulation {
            grid,
            particles,
            materials,
            body_force,
            thickness,
            loads,
            bcs,
            cracks,
            options,
            nodes,
            pairs: Pairs::with_capacity(np, nn),
            scratch: Default::default(),
            time: 0.0,
            step_count: 0,
            work: Energies::default(),
            momentum_ref: S::Vector::zeros(),
            momentum_conserving,
            energy_scale: 0.0,
            crack_side: Vec::new(),
            crack_side_triangle: Vec::new(),
            crack_side_seen: Vec::new(),
            growth: None,
        };
        let e = sim.energies();
        sim.energy_scale = e.kinetic + e.strain;
        if sim.has_cracks() && sim.options.checked {
            // Record every particle's side of every crack before the first step.
            let _ = S::check_crack_sides(&mut sim);
        }
        sim
    }

    pub fn has_cracks(&self) -> bool {
        !self.cracks.is_empty()
    }


    /// Total particle momentum, summed exactly.
    pub fn total_momentum(&self) -> S::Vector {
        let p = &self.particles;
        S::Vector::from_fn(|c| exact::sum_fast((0..p.len()).map(|i| p.mass[i] * p.v[i][c])))
    }

    /// Kinetic and strain energy now, with the accumulated external work and damping.
    /// Sums are exact, so the values do not depend on particle order.
    pub fn energies(&self) -> Energies {
        let p = &self.particles;
        let kinetic = exact::sum_fast((0..p.len()).map(|i| 0.5 * p.mass[i] * p.v[i].norm_squared()));
        // ½ σ:ε per unit undeformed volume (the linear-elastic energy density).
        let strain = exact::sum_fast((0..p.len()).map(|i| p.vol0[i] * (0.5 * p.stress[i].ddot(&p.strain[i]))));
        Energies { kinetic, strain, ..self.work }
    }

    /// Set each particle's applied force for time t, and the velocities of the boundary
    /// conditions that change in time for the step from t to t + Δt
    /// ([`crate::motion::BoundaryMotion`]).
    pub(crate) fn apply_loads(&mut self, t: f64) {
        if !self.bcs.motion.is_empty() {
            self.bcs.motion.update(t, self.options.dt, &mut self.bcs.vel);
        }
        if self.loads.is_empty() {
            return;
        }
        let p = &mut self.particles;
        for i in 0..p.len() {
            let l = p.load[i];
            p.force[i] = if l == NO_LOAD { S::Vector::zeros() } else { self.loads[l as usize].force_on(t, p.id[i], &p.x0[i]) };
        }
    }

    /// Advance until `end_time`, calling `observe` after every step.
    pub fn run_until<F>(&mut self, end_time: f64, mut observe: F) -> Result<(), CheckError>
    where
        F: FnMut(&Simulation<S>),
    {
        self.run_until_stopped(end_time, |s| {
            observe(s);
            std::ops::ControlFlow::Continue(())
        })
        .map(|_| ())
    }

    /// Advance until `end_time` or until `observe`, called after every step, breaks;
    /// returns whether it broke before the end time.
    pub fn run_until_stopped<F>(&mut self, end_time: f64, mut observe: F) -> Result<bool, CheckError>
    where
        F: FnMut(&Simulation<S>) -> std::ops::ControlFlow<()>,
    {
        // Stop within half a step of the end time so round-off in t does not add a step.
        while self.time + 0.5 * self.options.dt < end_time {
            self.step()?;
            if observe(self).is_break() {
                return Ok(self.time + 0.5 * self.options.dt < end_time);
            }
        }
        Ok(false)
    }
}
