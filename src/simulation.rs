//! The state of a run — grid, particles, materials, boundary conditions, loads,
//! cracks — and the time loop around [`crate::step`].

use crate::check::CheckError;
use crate::crack::{Crack, CrackMethod};
use crate::dim::Vector;
use crate::exact;
use crate::grid::{Grid, Nodes};
use crate::material::{Constitutive, LinearElastic};
use crate::particles::{Particles, NO_LOAD};
use crate::shape::{ShapeKind, MAX_NODES};
use serde::{Deserialize, Serialize};

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
}

/// A load on a set of particles: the same force on each, ramped linearly from zero over
/// `ramp` (applied in full at t = 0 when `ramp` is 0).
#[derive(Clone, Debug, PartialEq)]
pub struct Load {
    pub force_per_particle: Vector,
    pub ramp: f64,
}

impl Load {
    pub fn at(&self, t: f64) -> Vector {
        if self.ramp > 0.0 && t < self.ramp {
            self.force_per_particle * (t / self.ramp)
        } else {
            self.force_per_particle
        }
    }
}

/// Velocity boundary conditions resolved onto nodes: bit 0 fixes x, bit 1 fixes y.
#[derive(Clone, Debug, Default)]
pub struct NodeBcs {
    pub mask: Vec<u8>,
    pub vel: Vec<Vector>,
    /// Nodes with any condition, ascending.
    pub nodes: Vec<u32>,
}

impl NodeBcs {
    pub fn new(num_nodes: usize) -> Self {
        NodeBcs { mask: vec![0; num_nodes], vel: vec![Vector::zeros(); num_nodes], nodes: Vec::new() }
    }

    /// Fix component `c` (0 = x, 1 = y) of node `i` to velocity `v`.
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
}

impl Energies {
    /// Kinetic + strain + damped − external work: constant for an exact integrator.
    pub fn total(&self) -> f64 {
        self.kinetic + self.strain + self.damping - self.external_work
    }
}

/// Per-particle/node pair data of the current step, laid out flat with stride
/// [`MAX_NODES`] per particle, and the node → pair incidence (CSR) that turns every
/// particle-to-grid sum into a gather over a node's pairs.
#[derive(Clone, Debug, Default)]
pub struct Pairs {
    pub count: Vec<u8>,
    pub node: Vec<u32>,
    pub s: Vec<f64>,
    pub g: Vec<Vector>,
    /// Velocity field ν(p,i) ∈ {0,1,2} (eq. 2); all 0 without cracks.
    pub field: Vec<u8>,
    /// CSR over nodes: pairs of node i are `items[start[i]..start[i+1]]` (pair index p·MAX_NODES + k).
    pub start: Vec<u32>,
    pub items: Vec<u32>,
    /// Scratch cursor for filling `items` (kept to avoid allocating inside the step).
    pub fill: Vec<u32>,
}

impl Pairs {
    pub fn with_capacity(np: usize, nn: usize) -> Self {
        Pairs {
            count: vec![0; np],
            node: vec![0; np * MAX_NODES],
            s: vec![0.0; np * MAX_NODES],
            g: vec![Vector::zeros(); np * MAX_NODES],
            field: vec![0; np * MAX_NODES],
            start: vec![0; nn + 1],
            items: Vec::with_capacity(np * MAX_NODES),
            fill: Vec::with_capacity(nn),
        }
    }

    /// Pair indices of node `i` (after the CSR build of Task 1).
    #[inline]
    pub fn of_node(&self, i: usize) -> &[u32] {
        &self.items[self.start[i] as usize..self.start[i + 1] as usize]
    }

    /// Pair indices of particle `p`.
    #[inline]
    pub fn of_particle(&self, p: usize) -> std::ops::Range<usize> {
        let base = p * MAX_NODES;
        base..base + self.count[p] as usize
    }
}

/// One MPM analysis: everything the time step reads and writes.
#[derive(Clone, Debug)]
pub struct Simulation {
    pub grid: Grid,
    pub particles: Particles,
    pub materials: Vec<LinearElastic>,
    /// Body force (acceleration) per body.
    pub body_force: Vec<Vector>,
    /// Thickness per body (2D), so particle areas can be recovered for contact volumes.
    pub thickness: Vec<f64>,
    pub loads: Vec<Load>,
    pub bcs: NodeBcs,
    pub cracks: Vec<Crack>,
    pub options: Options,
    pub nodes: Nodes,
    pub pairs: Pairs,
    /// Buffers of the parallel gathers, kept across steps.
    pub scratch: crate::step::Scratch,
    pub time: f64,
    pub step_count: u64,
    /// Accumulated external work and damping (kinetic and strain are computed on demand).
    pub work: Energies,
    /// Total particle momentum at the start of the current step (checked mode).
    pub(crate) momentum_ref: Vector,
    /// Whether momentum must be conserved: no loads, body forces, boundary conditions or damping.
    pub(crate) momentum_conserving: bool,
    /// Total energy scale at t = 0 for the instability check.
    pub(crate) energy_scale: f64,
    /// Side (+1 above, −1 below, 0 unknown) of each particle relative to each crack,
    /// index id·ncracks + c with the particle's id (checked mode, cracks only).
    pub(crate) crack_side: Vec<i8>,
    /// Crack growth (001 §2.3), when a scene lets a crack grow; None otherwise.
    pub growth: Option<crate::fracture::growth::Growth>,
}

impl Simulation {
    /// Assemble a simulation; `dt` and everything else come resolved from the scene.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        grid: Grid,
        particles: Particles,
        materials: Vec<LinearElastic>,
        body_force: Vec<Vector>,
        thickness: Vec<f64>,
        loads: Vec<Load>,
        bcs: NodeBcs,
        cracks: Vec<Crack>,
        options: Options,
    ) -> Self {
        let nn = grid.num_nodes();
        let np = particles.len();
        let momentum_conserving = loads.is_empty()
            && body_force.iter().all(|b| *b == Vector::zeros())
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
            momentum_ref: Vector::zeros(),
            momentum_conserving,
            energy_scale: 0.0,
            crack_side: Vec::new(),
            growth: None,
        };
        let e = sim.energies();
        sim.energy_scale = e.kinetic + e.strain;
        if sim.has_cracks() && sim.options.checked {
            // Record every particle's side of every crack before the first step.
            let _ = sim.check_crack_sides();
        }
        sim
    }

    pub fn has_cracks(&self) -> bool {
        !self.cracks.is_empty()
    }

    /// Largest stable time step estimate: cell size over the fastest dilatational wave.
    pub fn cfl_dt(grid: &Grid, materials: &[LinearElastic]) -> f64 {
        let c = materials.iter().map(|m| m.wave_speed()).fold(0.0, f64::max);
        grid.min_h() / c
    }

    /// Total particle momentum, summed exactly.
    pub fn total_momentum(&self) -> Vector {
        let p = &self.particles;
        Vector::new(exact::sum_fast((0..p.len()).map(|i| p.mass[i] * p.v[i].x)), exact::sum_fast((0..p.len()).map(|i| p.mass[i] * p.v[i].y)))
    }

    /// Kinetic and strain energy now, with the accumulated external work and damping.
    /// Sums are exact, so the values do not depend on particle order.
    pub fn energies(&self) -> Energies {
        let p = &self.particles;
        let kinetic = exact::sum_fast((0..p.len()).map(|i| 0.5 * p.mass[i] * p.v[i].norm_squared()));
        let strain = exact::sum_fast((0..p.len()).map(|i| {
            let m = &self.materials[p.material[i] as usize];
            p.vol0[i] * m.energy_density(&p.strain[i], &p.stress[i])
        }));
        Energies { kinetic, strain, ..self.work }
    }

    /// Set each particle's applied force for time t.
    pub(crate) fn apply_loads(&mut self, t: f64) {
        if self.loads.is_empty() {
            return;
        }
        let p = &mut self.particles;
        for i in 0..p.len() {
            let l = p.load[i];
            p.force[i] = if l == NO_LOAD { Vector::zeros() } else { self.loads[l as usize].at(t) };
        }
    }

    /// Advance until `end_time`, calling `observe` after every step.
    pub fn run_until<F>(&mut self, end_time: f64, mut observe: F) -> Result<(), CheckError>
    where
        F: FnMut(&Simulation),
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
        F: FnMut(&Simulation) -> std::ops::ControlFlow<()>,
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
