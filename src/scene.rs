//! Scene files (TOML): grid, materials, bodies, boundary conditions, loads, cracks,
//! solver options and outputs. Units are the user's, as long as they are consistent;
//! the examples use mm, g, ms (so forces in N and stresses in MPa), like the papers.
//!
//! Parsing rejects unknown fields and wrong types (the `toml` error names the key and
//! line); [`Scene::validate`] rejects physically meaningless values with the field's
//! path; [`Scene::build`] turns a valid scene into a [`Simulation`]. See
//! `docs/scene.md` for every field.

use crate::crack::{ContactLaw, Crack, CrackMethod};
use crate::fracture::growth::{Criterion, Growth, GrowthSettings, Toughness};
use crate::fracture::jintegral::{CodMethod, JRequest, TipEnd};
use crate::dim::Vector;
use crate::grid::Grid;
use crate::material::{LinearElastic, PlaneState};
use crate::motion::{BoundaryFields, BoundaryFn, Component, LoadVariation, LoadedParticle, MotionBuilder, TimeSpec, WilliamsSpec};
use crate::particles::{Particles, NO_LOAD};
use crate::shape::ShapeKind;
use crate::simulation::{DampingOn, Load, NodeBcs, Options, Scheme, Simulation};
use serde::{Deserialize, Serialize};
use std::path::Path;
use thiserror::Error;

#[derive(Debug, Error)]
pub enum SceneError {
    #[error("cannot read scene file {path}: {source}")]
    Io { path: String, source: std::io::Error },
    #[error("scene file {path} is not a valid scene:\n{message}")]
    Parse { path: String, message: String },
    #[error("scene field `{field}`: {message}")]
    Invalid { field: String, message: String },
    /// A bad `--set PATH=VALUE` ([`crate::scene_override`]).
    #[error("`--set {arg}`: {message}")]
    Override { arg: String, message: String },
}

fn invalid(field: impl Into<String>, message: impl Into<String>) -> SceneError {
    SceneError::Invalid { field: field.into(), message: message.into() }
}

#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// Free text shown in summaries.
    #[serde(default)]
    pub title: String,
    pub grid: GridSpec,
    pub solver: SolverSpec,
    #[serde(default)]
    pub output: OutputSpec,
    pub materials: Vec<MaterialSpec>,
    pub bodies: Vec<BodySpec>,
    #[serde(default)]
    pub boundary: Vec<BoundarySpec>,
    #[serde(default)]
    pub loads: Vec<LoadSpec>,
    #[serde(default)]
    pub cracks: Vec<CrackSpec>,
    /// Line probes: stresses sampled along segments (written by `cramp fea`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub probes: Vec<ProbeSpec>,
    /// Turn the whole scene about a point, the grid staying ([`crate::scene_rotate`]);
    /// applied when the file is read, so a built scene never has it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rotate: Option<crate::scene_rotate::RotateSpec>,
}

#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct GridSpec {
    /// Lower-left corner.
    pub origin: [f64; 2],
    /// Extent in x and y (must be a whole number of cells).
    pub size: [f64; 2],
    /// Cell size in x and y.
    pub cell: [f64; 2],
}

#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SolverSpec {
    /// usl, musl, usf or usavg (default usavg).
    #[serde(default = "default_scheme")]
    pub scheme: Scheme,
    /// linear or ugimp (default ugimp).
    #[serde(default = "default_shape")]
    pub shape: ShapeKind,
    /// Time step as a fraction of cell size / dilatational wave speed (default 0.5).
    pub cfl: Option<f64>,
    /// Explicit time step (overrides cfl).
    pub dt: Option<f64>,
    /// End time (required).
    pub end_time: f64,
    /// Damping coefficient κ of eq. 28, 1/time (default 0).
    #[serde(default)]
    pub damping: f64,
    /// What κ damps: "grid" (the nodal momenta, eq. 28; default) or "particles" (the
    /// same nodal force, and the particle velocities themselves in Task 5).
    #[serde(default)]
    pub damping_on: DampingOn,
    /// Particles per cell per direction (default 2).
    #[serde(default = "default_ppc")]
    pub particles_per_cell: usize,
    /// Where each body's particle lattice is anchored: "grid" (default: the grid's cells,
    /// particles at the same places in every cell) or "body" (the corner of the body's
    /// bounding box, so the particles move with the body when the scene moves on the grid).
    #[serde(default, skip_serializing_if = "Lattice::is_grid")]
    pub lattice: Lattice,
    /// Invariant checks every step (default true).
    #[serde(default = "default_true")]
    pub checked: bool,
    /// How cracks act: "velocity_fields" (CRAMP, default) or "visibility" (node
    /// visibility, the alternative Nairn 2003 §3.1 compares with).
    #[serde(default)]
    pub crack_method: CrackMethod,
    /// Length of the crack-tip zone in cells (2D; default 0, none): pairs meeting a crack
    /// less than this behind a tip are shared between fields (crack::tip_zone).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub tip_zone: f64,
    /// Largest number of time steps the run may take (default [`DEFAULT_MAX_STEPS`]): a
    /// scene needing more is refused, so a typo in end_time or dt cannot start a run of
    /// years. Raise it to allow a longer run.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_steps: Option<u64>,
}

fn is_zero(v: &f64) -> bool {
    *v == 0.0
}

/// Where a body's particle lattice (`particles_per_cell`ⁿ particles per cell-sized block,
/// at the centres of its sub-cells) is anchored: `solver.lattice`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Lattice {
    /// The grid's cells (Nairn 2003 and the papers' examples): a particle sits at the same
    /// place in every cell, and a body's edge that falls on a particle row keeps that row
    /// (the fill is inclusive), so the discrete body changes when the scene is moved on
    /// the grid by a fraction of a cell.
    #[default]
    Grid,
    /// The lower corner of the body's bounding box: the body's particles are the same
    /// relative to the body wherever it lies on the grid (a box whose sides are whole
    /// multiples of the particle spacing is tiled exactly, with no row on its edges), so
    /// translating a scene on the grid moves only the grid under the material (issue 22).
    /// Bodies that touch have their own anchors, so the spacing across their interface is
    /// not the lattice's unless their corners are whole spacings apart; a rotated scene is
    /// anchored at its new bounding box. Not for `cramp fea`, whose mesh is the grid's
    /// cells as the grid's lattice fills them.
    Body,
}

impl Lattice {
    fn is_grid(&self) -> bool {
        *self == Lattice::Grid
    }

    /// Where the particles lie in 2D, for error messages that advise moving a crack off them.
    pub fn particle_rows(self, n: usize) -> String {
        match self {
            Lattice::Grid => format!("they lie at the centres of the {n} × {n} sub-cells of each cell), e.g. onto a grid line"),
            Lattice::Body => format!("with solver.lattice = \"body\" they lie at the centres of the {n} × {n} sub-cells of cell-sized blocks laid from each body's lower corner), e.g. a whole number of particle spacings from the body's lower edge"),
        }
    }

    /// Where the particles lie in 3D (as [`Lattice::particle_rows`]).
    pub fn particle_planes(self, n: usize) -> String {
        match self {
            Lattice::Grid => format!("they lie at the centres of the {n} × {n} × {n} sub-cells of each cell), e.g. onto a grid plane"),
            Lattice::Body => format!("with solver.lattice = \"body\" they lie at the centres of the {n} × {n} × {n} sub-cells of cell-sized blocks laid from each body's lower corner), e.g. a whole number of particle spacings from the body's lower face"),
        }
    }
}

/// Default of `solver.max_steps`: 10⁸ steps (days of run time for a few thousand particles).
pub const DEFAULT_MAX_STEPS: u64 = 100_000_000;

/// The largest `solver.cfl` accepted for a scheme: the stability limit measured by the
/// case `cfl_sweep` on a vibrating elastic block with uGIMP (USL 0.60; MUSL and USAVG
/// 1.71, USF 1.73 over 2000 steps), rounded down to two digits.
pub fn stable_cfl(scheme: Scheme) -> f64 {
    match scheme {
        Scheme::Usl => 0.6,
        Scheme::Musl | Scheme::Usf | Scheme::Usavg => 1.7,
    }
}

fn default_scheme() -> Scheme {
    Scheme::Usavg
}
fn default_shape() -> ShapeKind {
    ShapeKind::Ugimp
}
fn default_ppc() -> usize {
    2
}
fn default_true() -> bool {
    true
}

#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, Default)]
#[serde(deny_unknown_fields)]
pub struct OutputSpec {
    /// Time between rows of history.csv (default: end_time / 100).
    pub history_interval: Option<f64>,
    /// Time between VTK particle snapshots (default: none).
    pub archive_interval: Option<f64>,
}

#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct MaterialSpec {
    pub name: String,
    /// Young's modulus.
    #[serde(rename = "E")]
    pub e: f64,
    /// Poisson's ratio.
    pub nu: f64,
    /// Density.
    pub rho: f64,
    /// plane_stress or plane_strain.
    pub state: PlaneState,
    /// Fracture toughness and growth criterion (001 §2.3.1). Omitted: the material never
    /// fractures (a growing crack stops where its tip is in this material).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub toughness: Option<ToughnessSpec>,
}

/// `materials[].toughness = { criterion = "max_hoop_stress" | "min_strain_energy", kic = … }`.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ToughnessSpec {
    /// Which criterion decides growth and its direction (required).
    pub criterion: Criterion,
    /// K_Ic in the scene's stress × √length units (required).
    pub kic: f64,
}

#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, rename_all = "snake_case")]
pub enum ShapeSpec {
    Rectangle { min: [f64; 2], max: [f64; 2] },
    Disk { center: [f64; 2], radius: f64 },
    Polygon { points: Vec<[f64; 2]> },
}

#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SineVelocity {
    /// Velocity amplitude vector.
    pub amplitude: [f64; 2],
    /// Wave vector k: v = amplitude · sin(k · (x − origin)).
    pub k: [f64; 2],
    #[serde(default)]
    pub origin: [f64; 2],
}

#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct BodySpec {
    /// Name of a material in `materials`.
    pub material: String,
    pub shape: ShapeSpec,
    /// Thickness (2D), default 1.
    #[serde(default = "default_one")]
    pub thickness: f64,
    /// Uniform initial velocity.
    #[serde(default)]
    pub velocity: [f64; 2],
    /// Optional single-mode initial velocity added to `velocity`.
    pub velocity_sine: Option<SineVelocity>,
    /// Body force per unit mass (acceleration), e.g. gravity.
    #[serde(default)]
    pub body_force: [f64; 2],
}

fn default_one() -> f64 {
    1.0
}

#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, rename_all = "snake_case")]
pub enum Selection {
    /// Axis-aligned box, inclusive.
    Region { min: [f64; 2], max: [f64; 2] },
    /// Points within a quarter cell of the segment.
    Line { from: [f64; 2], to: [f64; 2] },
    /// Points inside the polygon or on its edges (even–odd rule; what `rotate` makes of a region).
    Polygon { points: Vec<[f64; 2]> },
}

#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct BoundarySpec {
    /// Which grid nodes.
    pub nodes: Selection,
    /// Prescribed x velocity, if given: a number or an expression of x, y, t.
    pub vx: Option<Component>,
    /// Prescribed y velocity, if given.
    pub vy: Option<Component>,
    /// Prescribed x displacement (the nodes move by u(x, t) − u(x, 0)).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ux: Option<Component>,
    /// Prescribed y displacement.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub uy: Option<Component>,
    /// Displacement of the Williams crack-tip field (both in-plane directions).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub williams: Option<WilliamsSpec>,
    /// Time function multiplying every prescribed component (default 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub time: Option<TimeSpec>,
}

#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct LoadSpec {
    /// Which particles.
    pub particles: Selection,
    /// Total force, shared equally by the selected particles (or give `traction`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub force: Option<[f64; 2]>,
    /// Force per unit area of the boundary (edge length × thickness), numbers or
    /// expressions of x, y, t, distributed by each particle's share of the boundary.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub traction: Option<[Component; 2]>,
    /// Outward normal of the loaded boundary (a traction on a `region`; a `line` gives it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub normal: Option<[f64; 2]>,
    /// Ramp time: the force grows linearly from 0 over this time (default 0: a step load).
    #[serde(default)]
    pub ramp: f64,
    /// Time function multiplying the force or traction (instead of `ramp`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub time: Option<TimeSpec>,
}

#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, rename_all = "snake_case")]
pub enum ContactSpec {
    None,
    Stick,
    Frictionless,
    Friction { mu: f64 },
}

impl ContactSpec {
    /// The contact law it names.
    pub fn law(&self) -> ContactLaw {
        match *self {
            ContactSpec::None => ContactLaw::None,
            ContactSpec::Stick => ContactLaw::Stick,
            ContactSpec::Frictionless => ContactLaw::Friction(0.0),
            ContactSpec::Friction { mu } => ContactLaw::Friction(mu),
        }
    }
}

#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct CrackSpec {
    /// Crack particles in order (at least two).
    pub points: Vec<[f64; 2]>,
    /// Contact law (default frictionless).
    #[serde(default = "default_contact")]
    pub contact: ContactSpec,
    /// Relative volume below which faces are separated (default 0.9).
    #[serde(default = "default_vsep")]
    pub v_sep: f64,
    /// Relative volume above which faces are in contact (default 1.1).
    #[serde(default = "default_vcontact")]
    pub v_contact: f64,
    /// How contact is detected: "opening" (default; the tracked crack surfaces' normal
    /// opening), "volume" (Nairn 2003 eqs. 8–12, with v_sep and v_contact) or
    /// "displacement" (NairnMPM's: the two fields' mean particle displacements).
    #[serde(default)]
    pub detection: crate::crack::ContactDetection,
    /// J-integral and stress intensity factors at this crack's tips (Guo & Nairn 2004 §3),
    /// written to cracks.csv at the history interval. Omitted: not computed.
    #[serde(default)]
    pub fracture: Option<FractureSpec>,
}

/// Which crack ends are tips, and how J is evaluated there.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct FractureSpec {
    /// "start" (first point), "end" (last point) or "both".
    pub tips: TipsSpec,
    /// Half-size n of the n×n-cell rectangular J contour (default 2).
    #[serde(default = "default_contour")]
    pub contour: usize,
    /// Add the area term of eq. 8 (two-term, path-independent J; default false).
    #[serde(default)]
    pub area_term: bool,
    /// How δ_I, δ_II for the K split are read from the crack surfaces: "next_to_tip"
    /// (default; Guo & Nairn 2004 §3) or "fit" (verified for stationary cracks only).
    #[serde(default)]
    pub cod: CodMethod,
    /// J on the circle of this radius (in cells of the smallest cell size) around the
    /// tip — the 3D front contour, line term only ([`Simulation::circle_j_2d`]) — instead
    /// of the rectangle (`contour`, `area_term` unused). For comparing a 2D scene with its
    /// 3D extrusion (case `front_growth_slab`). Omitted: the rectangle.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub circle: Option<f64>,
    /// Let the tips grow (001 §2.3.2) by the toughness of the material they are in.
    /// Omitted: the crack is stationary.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub growth: Option<GrowthSpec>,
}

/// `cracks[].fracture.growth = { increment = 0.5, every = 1, max_speed = …, speed_correction = false, speed_window = 4 }`.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct GrowthSpec {
    /// Length of each new segment as a fraction of the cell size (default 0.5, 001 §2.3.2).
    #[serde(default = "default_increment")]
    pub increment: f64,
    /// Evaluate J, K and the criterion every this many steps (default 1).
    #[serde(default = "default_every")]
    pub every: u64,
    /// Optional upper limit on the tip speed (the Rayleigh speed always limits it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_speed: Option<f64>,
    /// Split K_I, K_II with the crack-speed factors of the tip's speed estimate (001 eqs.
    /// 14–17); default false: their slow limit, as the papers' runs (001 §3.1) and
    /// NairnMPM do.
    #[serde(default)]
    pub speed_correction: bool,
    /// Number of past increments the tip-speed estimate spans (default 4).
    #[serde(default = "default_speed_window")]
    pub speed_window: usize,
    /// Release each new segment gradually (2D; [`crate::fracture::release`]). Omitted: at
    /// once, as the papers (001 §2.3.2).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub release: Option<ReleaseSpec>,
    /// Cohesive new segments (2D; [`crate::fracture::cohesive`]): a triangular
    /// traction–separation law of area G_c = K_Ic²/E' and peak `strength`, and the zone's
    /// growth rule. Omitted: free faces and the material's criterion, as the papers.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cohesive: Option<CohesiveSpec>,
}

/// `cracks[].fracture.growth.cohesive = { strength = 3.5 }` (2D).
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct CohesiveSpec {
    /// Peak traction σ_c (stress units; required).
    pub strength: f64,
}

/// `cracks[].fracture.growth.release = { length = 4.0, damping = 1.0 }` (2D).
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ReleaseSpec {
    /// Cells the tip crosses while a new segment is released (default 4).
    #[serde(default = "default_release_length")]
    pub length: f64,
    /// Damping of the held faces' relative velocity, in units of c_d/h (default 1).
    #[serde(default = "default_release_damping")]
    pub damping: f64,
}

fn default_release_length() -> f64 {
    crate::fracture::release::DEFAULT_LENGTH
}
fn default_release_damping() -> f64 {
    crate::fracture::release::DEFAULT_DAMPING
}

impl GrowthSpec {
    /// Check the table `field` (`cracks[i].fracture.growth`) of a 2D or 3D scene; a
    /// growing crack needs a material with a `toughness`.
    pub(crate) fn validate(&self, field: &str, any_toughness: bool) -> Result<(), SceneError> {
        let f = |n: &str| format!("{field}.{n}");
        if !(self.increment > 0.0 && self.increment <= 1.0) {
            return Err(invalid(f("increment"), format!("must be in (0, 1] (a fraction of the cell size), got {}", self.increment)));
        }
        if self.every == 0 {
            return Err(invalid(f("every"), "must be at least 1 (steps between evaluations)"));
        }
        if let Some(vmax) = self.max_speed {
            positive(&f("max_speed"), vmax)?;
        }
        if self.speed_window == 0 {
            return Err(invalid(f("speed_window"), "must be at least 1 (increments the tip-speed estimate spans)"));
        }
        if let Some(r) = &self.release {
            if !(r.length > 0.0 && r.length <= 20.0) {
                return Err(invalid(f("release.length"), format!("must be in (0, 20] cells (the tip's travel while a new segment is released), got {}", r.length)));
            }
            if !(r.damping >= 0.0 && r.damping <= 10.0) {
                return Err(invalid(f("release.damping"), format!("must be in [0, 10] (units of c_d/h), got {}", r.damping)));
            }
        }
        if let Some(c) = &self.cohesive {
            positive(&f("cohesive.strength"), c.strength)?;
            if self.release.is_some() {
                return Err(invalid(f("cohesive"), "cannot be combined with `release` (choose one way for new segments to take up energy)"));
            }
        }
        if !any_toughness {
            return Err(invalid(field, "the crack may grow but no material has a `toughness` (criterion and kic)"));
        }
        Ok(())
    }
}

fn default_increment() -> f64 {
    0.5
}
fn default_every() -> u64 {
    1
}
fn default_speed_window() -> usize {
    crate::fracture::growth::SPEED_WINDOW
}

#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum TipsSpec {
    Start,
    End,
    Both,
}

fn default_contour() -> usize {
    2
}

/// A line probe: `points` equally spaced samples from `from` to `to` (both included).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ProbeSpec {
    /// Name, used in the file name `probe_<name>.csv`: letters, digits, `_` and `-`.
    pub name: String,
    /// Start point.
    pub from: [f64; 2],
    /// End point.
    pub to: [f64; 2],
    /// Number of sample points, both ends included (2 to 100000).
    pub points: usize,
}

pub(crate) fn default_contact() -> ContactSpec {
    ContactSpec::Frictionless
}
pub(crate) fn default_vsep() -> f64 {
    0.9
}
pub(crate) fn default_vcontact() -> f64 {
    1.1
}

fn v(a: [f64; 2]) -> Vector {
    Vector::new(a[0], a[1])
}

impl ShapeSpec {
    /// The axis-aligned bounding box (min, max) of the shape.
    pub fn bounds(&self) -> (Vector, Vector) {
        match self {
            ShapeSpec::Rectangle { min, max } => (v(*min), v(*max)),
            ShapeSpec::Disk { center, radius } => (v(*center) - Vector::new(*radius, *radius), v(*center) + Vector::new(*radius, *radius)),
            ShapeSpec::Polygon { points } => points.iter().fold(
                (Vector::new(f64::INFINITY, f64::INFINITY), Vector::new(f64::NEG_INFINITY, f64::NEG_INFINITY)),
                |(lo, hi), p| (lo.inf(&v(*p)), hi.sup(&v(*p))),
            ),
        }
    }

    pub fn contains(&self, x: &Vector) -> bool {
        match self {
            ShapeSpec::Rectangle { min, max } => x.x >= min[0] && x.x <= max[0] && x.y >= min[1] && x.y <= max[1],
            ShapeSpec::Disk { center, radius } => (x - v(*center)).norm_squared() <= radius * radius,
            ShapeSpec::Polygon { points } => polygon_contains(points, x),
        }
    }
}

/// Even–odd ray casting (a point exactly on an edge may fall either way).
fn polygon_contains(points: &[[f64; 2]], x: &Vector) -> bool {
    let mut inside = false;
    let n = points.len();
    for i in 0..n {
        let a = v(points[i]);
        let b = v(points[(i + 1) % n]);
        if (a.y > x.y) != (b.y > x.y) {
            let xc = a.x + (x.y - a.y) * (b.x - a.x) / (b.y - a.y);
            if x.x < xc {
                inside = !inside;
            }
        }
    }
    inside
}

impl Selection {
    /// Matching tolerance for a grid of cell size h: round-off for regions, a quarter
    /// cell for lines (so a line drawn along a row of nodes or particles selects it).
    pub(crate) fn tolerance(&self, h: f64) -> f64 {
        match self {
            Selection::Region { .. } | Selection::Polygon { .. } => 1e-9 * h,
            Selection::Line { .. } => 0.25 * h,
        }
    }

    pub(crate) fn contains(&self, x: &Vector, tol: f64) -> bool {
        match self {
            Selection::Region { min, max } => {
                x.x >= min[0] - tol && x.x <= max[0] + tol && x.y >= min[1] - tol && x.y <= max[1] + tol
            }
            Selection::Line { from, to } => {
                let a = v(*from);
                let b = v(*to);
                let d = b - a;
                let l2 = d.norm_squared();
                let t = if l2 > 0.0 { ((x - a).dot(&d) / l2).clamp(0.0, 1.0) } else { 0.0 };
                (x - (a + d * t)).norm() <= tol
            }
            Selection::Polygon { points } => {
                let n = points.len();
                let on_edge = (0..n).any(|i| Selection::Line { from: points[i], to: points[(i + 1) % n] }.contains(x, tol));
                on_edge || polygon_contains(points, x)
            }
        }
    }
}

fn finite(field: &str, x: f64) -> Result<(), SceneError> {
    if x.is_finite() {
        Ok(())
    } else {
        Err(invalid(field, format!("must be a finite number, got {x}")))
    }
}

/// Every component of a point or vector finite; the error names the component.
/// Checks of one line probe `probes[i]` (2D or 3D: `from`, `to`, `lo`, `hi` have the
/// scene's number of components): a file-name-safe name not used by an earlier probe
/// (`before`), finite end points inside the grid [lo, hi] (to 1e-9 of the cell `h`),
/// distinct ends, 2 to 100000 points.
#[allow(clippy::too_many_arguments)]
pub(crate) fn validate_probe(
    i: usize,
    name: &str,
    before: &[&str],
    from: &[f64],
    to: &[f64],
    points: usize,
    lo: &[f64],
    hi: &[f64],
    h: f64,
) -> Result<(), SceneError> {
    let f = |n: &str| format!("probes[{i}].{n}");
    if name.is_empty() || !name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-') {
        return Err(invalid(f("name"), format!("must be non-empty letters, digits, '_' or '-' (it names the file probe_<name>.csv), got '{name}'")));
    }
    if before.contains(&name) {
        return Err(invalid(f("name"), format!("duplicate probe name '{name}'")));
    }
    let box_text = (0..lo.len()).map(|c| format!("[{}, {}]", lo[c], hi[c])).collect::<Vec<_>>().join(" × ");
    for (key, x) in [("from", from), ("to", to)] {
        for (c, v) in x.iter().enumerate() {
            finite(&format!("{}[{c}]", f(key)), *v)?;
        }
        let tol = 1e-9 * h;
        if (0..x.len()).any(|c| x[c] < lo[c] - tol || x[c] > hi[c] + tol) {
            return Err(invalid(f(key), format!("{x:?} lies outside the grid {box_text}")));
        }
    }
    if from == to {
        return Err(invalid(f("to"), format!("equals `from` {from:?}: a probe line needs two different end points")));
    }
    if !(2..=100_000).contains(&points) {
        return Err(invalid(f("points"), format!("must be 2 to 100000 (both ends are sampled), got {points}")));
    }
    Ok(())
}

fn finite_all(field: &str, xs: &[f64]) -> Result<(), SceneError> {
    xs.iter().enumerate().try_for_each(|(c, &x)| finite(&format!("{field}[{c}]"), x))
}

/// Every point of a selection finite.
fn finite_selection(field: &str, sel: &Selection) -> Result<(), SceneError> {
    match sel {
        Selection::Region { min, max } => {
            finite_all(&format!("{field}.region.min"), min)?;
            finite_all(&format!("{field}.region.max"), max)
        }
        Selection::Line { from, to } => {
            finite_all(&format!("{field}.line.from"), from)?;
            finite_all(&format!("{field}.line.to"), to)
        }
        Selection::Polygon { points } => {
            if points.len() < 3 {
                return Err(invalid(format!("{field}.polygon.points"), format!("needs at least 3 points, got {}", points.len())));
            }
            points.iter().enumerate().try_for_each(|(k, p)| finite_all(&format!("{field}.polygon.points[{k}]"), p))
        }
    }
}

fn positive(field: &str, x: f64) -> Result<(), SceneError> {
    finite(field, x)?;
    if x > 0.0 {
        Ok(())
    } else {
        Err(invalid(field, format!("must be positive, got {x}")))
    }
}

/// The checks of `[solver]` and `[output]` that do not depend on the dimension (2D and 3D
/// scenes share them).
pub(crate) fn validate_solver(s: &SolverSpec, output: &OutputSpec) -> Result<(), SceneError> {
    positive("solver.end_time", s.end_time)?;
    if let Some(cfl) = s.cfl {
        positive("solver.cfl", cfl)?;
        let limit = stable_cfl(s.scheme);
        if cfl > limit {
            return Err(invalid(
                "solver.cfl",
                format!(
                    "must be at most {limit}, the measured stability limit of the {} scheme (case cfl_sweep; docs/scene.md), got {cfl}",
                    format!("{:?}", s.scheme).to_uppercase()
                ),
            ));
        }
    }
    if let Some(dt) = s.dt {
        positive("solver.dt", dt)?;
    }
    finite("solver.damping", s.damping)?;
    if s.damping < 0.0 {
        return Err(invalid("solver.damping", format!("must be zero or positive, got {}", s.damping)));
    }
    finite("solver.tip_zone", s.tip_zone)?;
    if !(0.0..=4.0).contains(&s.tip_zone) {
        return Err(invalid("solver.tip_zone", format!("must be 0 (none) to 4 cells, got {}", s.tip_zone)));
    }
    if s.particles_per_cell == 0 || s.particles_per_cell > 8 {
        return Err(invalid("solver.particles_per_cell", format!("must be 1 to 8, got {}", s.particles_per_cell)));
    }
    if let Some(h) = output.history_interval {
        positive("output.history_interval", h)?;
    }
    if let Some(a) = output.archive_interval {
        positive("output.archive_interval", a)?;
    }
    Ok(())
}

/// The time step must advance time and the run must end in a sane number of steps:
/// dt positive and finite (an overflowing wave speed gives 0), end_time at least half
/// a step (a run of 0 steps is a mistake), at most `solver.max_steps` steps, and the
/// explicit damping κΔt below 1 (above, −κp removes more than the momentum in one step).
/// `speeds` are the materials' dilatational wave speeds and `materials` their (E, ρ),
/// for the message when the time step is not a number.
pub(crate) fn validate_time_step(s: &SolverSpec, dt: f64, speeds: &[f64], materials: &[(f64, f64)]) -> Result<(), SceneError> {
    let dt_field = if s.dt.is_some() { "solver.dt" } else { "solver.cfl" };
    if !(dt > 0.0 && dt.is_finite()) {
        // The fastest material (a NaN speed, from inf/inf, sorts above every number).
        let (k, c) = speeds.iter().copied().enumerate().max_by(|a, b| a.1.total_cmp(&b.1)).unwrap_or((0, 0.0));
        let (e, rho) = materials.get(k).copied().unwrap_or((f64::NAN, f64::NAN));
        return Err(invalid(
            format!("materials[{k}]"),
            format!("E = {:e} and rho = {:e} give a dilatational wave speed of {c:e}, so the time step cfl × cell / c_d is {dt:e}; use values whose ratio is a finite number", e, rho),
        ));
    }
    let steps = (s.end_time / dt - 0.5).ceil();
    if steps < 1.0 {
        return Err(invalid("solver.end_time", format!("{:e} is shorter than half the time step dt = {dt:e}: the run would take no step", s.end_time)));
    }
    let max_steps = s.max_steps.unwrap_or(DEFAULT_MAX_STEPS);
    if steps > max_steps as f64 {
        return Err(invalid(
            "solver.end_time",
            format!(
                "{:e} takes {steps:e} steps of dt = {dt:e} ({dt_field}), more than solver.max_steps = {max_steps}; \
                 check end_time and the time step, or raise solver.max_steps to allow the run",
                s.end_time
            ),
        ));
    }
    if s.damping * dt >= 1.0 {
        return Err(invalid(
            "solver.damping",
            format!(
                "κ = {:e} with dt = {dt:e} gives κ·dt = {:e} ≥ 1: the explicit damping force −κp would remove more than \
                 the whole momentum in one step; use κ < 1/dt = {:e}",
                s.damping,
                s.damping * dt,
                1.0 / dt
            ),
        ));
    }
    Ok(())
}

impl Scene {
    /// Read and validate a scene file.
    pub fn from_file(path: &Path) -> Result<Scene, SceneError> {
        let text = std::fs::read_to_string(path).map_err(|e| SceneError::Io { path: path.display().to_string(), source: e })?;
        Scene::from_toml(&text, &path.display().to_string())
    }

    /// Parse and validate TOML text; `origin` names the source in errors.
    pub fn from_toml(text: &str, origin: &str) -> Result<Scene, SceneError> {
        let scene: Scene = toml::from_str(text).map_err(|e| SceneError::Parse { path: origin.to_string(), message: e.to_string() })?;
        let scene = crate::scene_rotate::apply(scene)?;
        scene.validate()?;
        Ok(scene)
    }

    /// Check every value for physical sense; the error names the field.
    pub fn validate(&self) -> Result<(), SceneError> {
        let g = &self.grid;
        for c in 0..2 {
            finite(&format!("grid.origin[{c}]"), g.origin[c])?;
            positive(&format!("grid.size[{c}]"), g.size[c])?;
            positive(&format!("grid.cell[{c}]"), g.cell[c])?;
            let n = g.size[c] / g.cell[c];
            if (n - n.round()).abs() > 1e-9 * n.max(1.0) || n.round() < 1.0 {
                return Err(invalid(format!("grid.size[{c}]"), format!("{} is not a whole number of cells of size {} (got {n} cells)", g.size[c], g.cell[c])));
            }
            if n.round() > 1e7 {
                return Err(invalid(format!("grid.size[{c}]"), format!("{n} cells is too many")));
            }
        }
        validate_solver(&self.solver, &self.output)?;
        if self.materials.is_empty() {
            return Err(invalid("materials", "at least one material is required"));
        }
        for (i, m) in self.materials.iter().enumerate() {
            let f = |n: &str| format!("materials[{i}].{n}");
            positive(&f("E"), m.e)?;
            positive(&f("rho"), m.rho)?;
            finite(&f("nu"), m.nu)?;
            if !(m.nu > -1.0 && m.nu < 0.5) {
                return Err(invalid(f("nu"), format!("Poisson's ratio must be in (−1, 0.5), got {}", m.nu)));
            }
            if self.materials[..i].iter().any(|o| o.name == m.name) {
                return Err(invalid(f("name"), format!("duplicate material name '{}'", m.name)));
            }
            if let Some(t) = &m.toughness {
                positive(&f("toughness.kic"), t.kic)?;
                if t.criterion == Criterion::MinStrainEnergy && m.nu < 0.0 {
                    return Err(invalid(f("toughness.criterion"), format!("min_strain_energy needs 0 ≤ ν (κ in (1, 3]), got ν = {}", m.nu)));
                }
            }
        }
        if self.bodies.is_empty() {
            return Err(invalid("bodies", "at least one body is required"));
        }
        let (lo, hi) = (v(g.origin), v(g.origin) + v(g.size));
        for (i, b) in self.bodies.iter().enumerate() {
            let f = |n: &str| format!("bodies[{i}].{n}");
            if !self.materials.iter().any(|m| m.name == b.material) {
                return Err(invalid(f("material"), format!("no material named '{}'", b.material)));
            }
            positive(&f("thickness"), b.thickness)?;
            match &b.shape {
                ShapeSpec::Rectangle { min, max } => {
                    finite_all(&f("shape.rectangle.min"), min)?;
                    finite_all(&f("shape.rectangle.max"), max)?;
                    if !(max[0] > min[0] && max[1] > min[1]) {
                        return Err(invalid(f("shape.rectangle"), format!("max {max:?} must exceed min {min:?} in both directions")));
                    }
                }
                ShapeSpec::Disk { center, radius } => {
                    finite_all(&f("shape.disk.center"), center)?;
                    positive(&f("shape.disk.radius"), *radius)?;
                }
                ShapeSpec::Polygon { points } => {
                    if points.len() < 3 {
                        return Err(invalid(f("shape.polygon.points"), format!("a polygon needs at least 3 points, got {}", points.len())));
                    }
                    for (k, q) in points.iter().enumerate() {
                        finite_all(&f(&format!("shape.polygon.points[{k}]")), q)?;
                    }
                }
            }
            let (bmin, bmax) = b.shape.bounds();
            if bmax.x < lo.x || bmax.y < lo.y || bmin.x > hi.x || bmin.y > hi.y {
                return Err(invalid(f("shape"), format!("lies entirely outside the grid [{}, {}] × [{}, {}]", lo.x, hi.x, lo.y, hi.y)));
            }
            finite_all(&f("velocity"), &b.velocity)?;
            finite_all(&f("body_force"), &b.body_force)?;
            if let Some(sv) = &b.velocity_sine {
                finite_all(&f("velocity_sine.amplitude"), &sv.amplitude)?;
                finite_all(&f("velocity_sine.k"), &sv.k)?;
                finite_all(&f("velocity_sine.origin"), &sv.origin)?;
            }
        }
        for (i, b) in self.boundary.iter().enumerate() {
            self.boundary_fn(i)?;
            finite_selection(&format!("boundary[{i}].nodes"), &b.nodes)?;
        }
        for (i, l) in self.loads.iter().enumerate() {
            finite_selection(&format!("loads[{i}].particles"), &l.particles)?;
            self.load_normal(i)?;
        }
        for (i, c) in self.cracks.iter().enumerate() {
            if c.points.len() < 2 {
                return Err(invalid(format!("cracks[{i}].points"), format!("a crack needs at least 2 points, got {}", c.points.len())));
            }
            let tol = 1e-9 * g.cell[0].min(g.cell[1]);
            for (k, q) in c.points.iter().enumerate() {
                let field = format!("cracks[{i}].points[{k}]");
                finite_all(&field, q)?;
                if q[0] < lo.x - tol || q[1] < lo.y - tol || q[0] > hi.x + tol || q[1] > hi.y + tol {
                    return Err(invalid(field, format!("{q:?} lies outside the grid [{}, {}] × [{}, {}]", lo.x, hi.x, lo.y, hi.y)));
                }
                if k > 0 && c.points[k - 1] == *q {
                    return Err(invalid(field, format!("repeats point {} {q:?}: a crack segment must have a length", k - 1)));
                }
            }
            finite(&format!("cracks[{i}].v_sep"), c.v_sep)?;
            finite(&format!("cracks[{i}].v_contact"), c.v_contact)?;
            if !(c.v_sep > 0.0 && c.v_sep < c.v_contact) {
                return Err(invalid(format!("cracks[{i}].v_sep"), format!("need 0 < v_sep < v_contact, got v_sep = {}, v_contact = {}", c.v_sep, c.v_contact)));
            }
            if let Some(fr) = &c.fracture {
                if let Some(r) = fr.circle {
                    positive(&format!("cracks[{i}].fracture.circle"), r)?;
                }
                if fr.cod == CodMethod::Interaction && (fr.circle.is_some() || fr.growth.as_ref().is_some_and(|g| g.speed_correction)) {
                    return Err(invalid(
                        format!("cracks[{i}].fracture.cod"),
                        "\"interaction\" is the interaction integral on the rectangular contour: not with `circle`, nor with growth's `speed_correction` (the speed factors convert crack openings, not the interaction integral's K's); use \"next_to_tip\" or \"fit\" there",
                    ));
                }
                if fr.contour == 0 {
                    return Err(invalid(format!("cracks[{i}].fracture.contour"), "must be at least 1 (cells from the node nearest the tip)"));
                }
                let cells = (g.size[0] / g.cell[0]).max(g.size[1] / g.cell[1]).round();
                if fr.contour as f64 > cells {
                    return Err(invalid(format!("cracks[{i}].fracture.contour"), format!("{} cells is more than the grid has ({cells} cells a side)", fr.contour)));
                }
                if let Some(gr) = &fr.growth {
                    gr.validate(&format!("cracks[{i}].fracture.growth"), self.materials.iter().any(|m| m.toughness.is_some()))?;
                }
            }
            if let ContactSpec::Friction { mu } = c.contact {
                if !(mu >= 0.0 && mu.is_finite()) {
                    return Err(invalid(format!("cracks[{i}].contact.friction.mu"), format!("must be zero or positive, got {mu}")));
                }
            }
            if self.solver.crack_method == CrackMethod::Visibility && self.solver.tip_zone != 0.0 {
                return Err(invalid("solver.tip_zone", "is a rule for CRAMP's velocity fields; crack_method = \"visibility\" has none (set tip_zone = 0)"));
            }
            if self.solver.crack_method == CrackMethod::Visibility && c.contact != ContactSpec::None {
                return Err(invalid(
                    format!("cracks[{i}].contact"),
                    "solver.crack_method = \"visibility\" has one velocity field per node and no crack contact; \
                     set contact = \"none\" (or use crack_method = \"velocity_fields\")",
                ));
            }
        }
        for (i, p) in self.probes.iter().enumerate() {
            let before: Vec<&str> = self.probes[..i].iter().map(|o| o.name.as_str()).collect();
            validate_probe(i, &p.name, &before, &p.from, &p.to, p.points, &[lo.x, lo.y], &[hi.x, hi.y], g.cell[0].min(g.cell[1]))?;
        }
        let speeds: Vec<f64> = self.materials().iter().map(crate::material::Constitutive::wave_speed).collect();
        let mats: Vec<(f64, f64)> = self.materials.iter().map(|m| (m.e, m.rho)).collect();
        validate_time_step(&self.solver, self.time_step(), &speeds, &mats)
    }

    /// `boundary[i]` compiled ([`BoundaryFn`]): the error names the field.
    pub fn boundary_fn(&self, i: usize) -> Result<BoundaryFn, SceneError> {
        let b = &self.boundary[i];
        let field = format!("boundary[{i}]");
        let mat = match &b.williams {
            Some(w) => {
                let names: Vec<&str> = self.materials.iter().map(|m| m.name.as_str()).collect();
                Some(crate::motion::williams_material(&format!("{field}.williams"), w, &names, &self.materials(), 2).map_err(|(f, m)| invalid(f, m))?)
            }
            None => None,
        };
        let fields = BoundaryFields { field, velocity: vec![b.vx.as_ref(), b.vy.as_ref()], displacement: vec![b.ux.as_ref(), b.uy.as_ref()], time: b.time.as_ref(), williams: b.williams.as_ref() };
        BoundaryFn::new(&fields, 2, mat).map_err(|(f, m)| invalid(f, m))
    }

    /// Check `loads[i]` ([`crate::motion::validate_load`]) and return a traction's unit
    /// outward normal: `normal`, or perpendicular to a `line` selection.
    pub fn load_normal(&self, i: usize) -> Result<Option<Vec<f64>>, SceneError> {
        let l = &self.loads[i];
        let implied = match l.particles {
            Selection::Line { from, to } if from != to => Some(vec![to[1] - from[1], from[0] - to[0]]),
            _ => None,
        };
        crate::motion::validate_load(&format!("loads[{i}]"), l.force.as_ref().map(|f| &f[..]), l.traction.as_ref().map(|t| &t[..]), l.normal.as_ref().map(|n| &n[..]), l.ramp, l.time.as_ref(), implied, 2)
            .map_err(|(f, m)| invalid(f, m))
    }

    pub fn grid(&self) -> Grid {
        let g = &self.grid;
        Grid {
            origin: v(g.origin),
            h: v(g.cell),
            nx: (g.size[0] / g.cell[0]).round() as usize,
            ny: (g.size[1] / g.cell[1]).round() as usize,
        }
    }

    pub fn materials(&self) -> Vec<LinearElastic> {
        self.materials.iter().map(|m| LinearElastic { e: m.e, nu: m.nu, rho: m.rho, state: m.state }).collect()
    }

    /// The time step: explicit `dt`, or `cfl` (default 0.5) × cell / c_d.
    pub fn time_step(&self) -> f64 {
        let mats = self.materials();
        match self.solver.dt {
            Some(dt) => dt,
            None => self.solver.cfl.unwrap_or(0.5) * Simulation::cfl_dt(&self.grid(), &mats),
        }
    }

    /// Fill the bodies with particles, resolve loads and boundary conditions onto
    /// particles and nodes, and assemble the simulation.
    pub fn build(&self) -> Result<Simulation, SceneError> {
        self.check_memory(crate::budget::memory_limit())?;
        let grid = self.grid();
        let mats = self.materials();
        let n = self.solver.particles_per_cell;
        let mut particles = Particles::default();
        let sub = Vector::new(grid.h.x / n as f64, grid.h.y / n as f64);
        let lp = sub * 0.5;
        // Cells in order, particles within a cell in order; a point claimed by an earlier
        // body is not filled again (first body wins). Only the cells the bodies' boxes
        // touch are visited.
        let mut owner: Vec<Vec<Vector>> = vec![Vec::new(); self.bodies.len()];
        // The lattices to fill: the grid's, shared by every body (each point to the first body
        // holding it), or each body's own from its box's lower corner (`solver.lattice`).
        type Fill = (Option<usize>, Vector, [(usize, usize); 2]);
        let lattices: Vec<Fill> = match self.solver.lattice {
            Lattice::Grid => vec![(None, grid.origin, self.body_cells(&grid))],
            Lattice::Body => (0..self.bodies.len())
                .map(|k| {
                    self.check_body_in_grid(k, &grid)?;
                    let (bmin, bmax) = self.bodies[k].shape.bounds();
                    Ok((Some(k), bmin, [0, 1].map(|c| (0, ((bmax[c] - bmin[c]) / grid.h[c]).ceil() as usize + 1))))
                })
                .collect::<Result<_, SceneError>>()?,
        };
        for (only, anchor, [(ix0, ix1), (iy0, iy1)]) in lattices {
            for iy in iy0..iy1 {
                for ix in ix0..ix1 {
                    for b in 0..n {
                        for a in 0..n {
                            let x = Vector::new(
                                anchor.x + grid.h.x * (ix as f64 + (a as f64 + 0.5) / n as f64),
                                anchor.y + grid.h.y * (iy as f64 + (b as f64 + 0.5) / n as f64),
                            );
                            // On a body's own lattice, its points that no earlier body holds.
                            let last = only.map_or(self.bodies.len(), |o| o + 1);
                            let first = self.bodies[..last].iter().position(|body| body.shape.contains(&x));
                            if let Some(k) = first.filter(|&k| only.is_none_or(|o| o == k)) {
                                owner[k].push(x);
                            }
                        }
                    }
                }
            }
        }
        for (k, body) in self.bodies.iter().enumerate() {
            if owner[k].is_empty() {
                return Err(invalid(format!("bodies[{k}].shape"), "contains no particle positions inside the grid (empty body)"));
            }
            let mi = self.materials.iter().position(|m| m.name == body.material).unwrap_or(0);
            let rho = mats[mi].rho;
            let area = sub.x * sub.y;
            let vol0 = area * body.thickness;
            for x in &owner[k] {
                let mut vel = v(body.velocity);
                if let Some(sv) = &body.velocity_sine {
                    let phase = v(sv.k).dot(&(x - v(sv.origin)));
                    vel += v(sv.amplitude) * phase.sin();
                }
                particles.push(*x, vel, rho * vol0, vol0, lp, mi as u16, k as u16);
            }
        }
        // Particles must lie inside the grid (with their uGIMP domain).
        for k in 0..self.bodies.len() {
            self.check_body_in_grid(k, &grid)?;
        }
        // Loads: the total force is shared by the selected particles.
        let mut loads = Vec::new();
        for (li, l) in self.loads.iter().enumerate() {
            let tol = l.particles.tolerance(grid.min_h());
            let sel: Vec<usize> = (0..particles.len()).filter(|&p| l.particles.contains(&particles.x[p], tol)).collect();
            if sel.is_empty() {
                return Err(invalid(format!("loads[{li}].particles"), "selects no particles"));
            }
            for &p in &sel {
                if particles.load[p] != NO_LOAD {
                    return Err(invalid(format!("loads[{li}].particles"), format!("selects particle at {:?} already loaded by loads[{}]", particles.x[p], particles.load[p])));
                }
                particles.load[p] = li as u16;
            }
            let normal = self.load_normal(li)?.unwrap_or_default();
            let loaded: Vec<LoadedParticle<Vector>> =
                sel.iter().map(|&p| LoadedParticle { id: particles.id[p], x0: particles.x0[p], lp: particles.lp[p], thickness: self.bodies[particles.body[p] as usize].thickness }).collect();
            let varying = LoadVariation::new(&format!("loads[{li}]"), l.time.as_ref(), l.traction.as_ref().map(|t| &t[..]), &normal, &loaded, particles.len()).map_err(|(f, m)| invalid(f, m))?;
            let force = l.force.map_or(Vector::zeros(), v);
            loads.push(Load { force_per_particle: force / sel.len() as f64, ramp: l.ramp, varying: varying.map(Box::new) });
        }
        // Boundary conditions on nodes.
        let mut bcs = NodeBcs::new(grid.num_nodes());
        let mut motion = MotionBuilder::default();
        for (bi, b) in self.boundary.iter().enumerate() {
            let ntol = b.nodes.tolerance(grid.min_h());
            let compiled = self.boundary_fn(bi)?;
            let field = format!("boundary[{bi}]");
            let mut any = false;
            for i in 0..grid.num_nodes() {
                let x = grid.node_pos(i);
                if b.nodes.contains(&x, ntol) {
                    any = true;
                    motion.add(&mut bcs, bi, &field, &compiled, i, &[x.x, x.y]).map_err(|(f, m)| invalid(f, m))?;
                }
            }
            if !any {
                return Err(invalid(format!("boundary[{bi}].nodes"), "selects no grid nodes"));
            }
        }
        motion.finish(&mut bcs);
        bcs.finish();
        let cracks = self
            .cracks
            .iter()
            .map(|c| {
                let law = c.contact.law();
                let vertices: Vec<Vector> = c.points.iter().map(|p| v(*p)).collect();
                let mut crack = Crack::new(crate::crack::subdivide(&vertices, 0.5 * grid.min_h()), law, c.v_sep, c.v_contact);
                crack.detection = c.detection;
                crack
            })
            .collect();
        let options = Options {
            scheme: self.solver.scheme,
            shape: self.solver.shape,
            dt: self.time_step(),
            damping: self.solver.damping,
            damping_on: self.solver.damping_on,
            checked: self.solver.checked,
            crack_method: self.solver.crack_method,
            tip_zone: self.solver.tip_zone * self.grid.cell[0].max(self.grid.cell[1]),
        };
        let body_force = self.bodies.iter().map(|b| v(b.body_force)).collect();
        let thickness = self.bodies.iter().map(|b| b.thickness).collect();
        let mut sim = Simulation::new(grid, particles, mats, body_force, thickness, loads, bcs, cracks, options);
        sim.growth = self.growth(&sim);
        self.check_cracks_against_particles(&sim)?;
        crate::fingerprint::on_build(&sim, || toml::to_string(self).ok());
        Ok(sim)
    }

    /// Body `k`'s bounding box lies inside the grid.
    fn check_body_in_grid(&self, k: usize, grid: &Grid) -> Result<(), SceneError> {
        let (lo, hi) = (grid.origin, grid.max_corner());
        let (bmin, bmax) = self.bodies[k].shape.bounds();
        if bmin.x < lo.x || bmin.y < lo.y || bmax.x > hi.x || bmax.y > hi.y {
            return Err(invalid(format!("bodies[{k}].shape"), format!("extends outside the grid [{}, {}] × [{}, {}]", lo.x, hi.x, lo.y, hi.y)));
        }
        Ok(())
    }

    /// Cell ranges [ix0, ix1) × [iy0, iy1) that hold every particle position of every body:
    /// the cells the bodies' bounding boxes touch, with a cell of margin for round-off.
    fn body_cells(&self, grid: &Grid) -> [(usize, usize); 2] {
        let (mut lo, mut hi) = (Vector::new(f64::INFINITY, f64::INFINITY), Vector::new(f64::NEG_INFINITY, f64::NEG_INFINITY));
        for b in &self.bodies {
            let (bmin, bmax) = b.shape.bounds();
            lo = lo.inf(&bmin);
            hi = hi.sup(&bmax);
        }
        let range = |lo: f64, hi: f64, origin: f64, h: f64, n: usize| {
            let first = ((lo - origin) / h).floor() - 1.0;
            let last = ((hi - origin) / h).floor() + 2.0;
            // NaN-free after validation; `as` saturates, and the clamps keep the range in the grid.
            ((first.max(0.0) as usize).min(n), (last.max(0.0) as usize).min(n))
        };
        [range(lo.x, hi.x, grid.origin.x, grid.h.x, grid.nx), range(lo.y, hi.y, grid.origin.y, grid.h.y, grid.ny)]
    }

    /// Errors a crack's geometry causes, reported as the scene's fault before the run
    /// instead of at some later step: a crack passing through a particle (exactly, or
    /// within 10⁻⁹ of a cell: the particle is on neither side, or on one by round-off, so
    /// the checked mode may see it "cross" the crack once it moves), and a crack whose `fracture` request cannot be evaluated where it lies (J
    /// contour outside the grid or crossing the crack more than once, no material at the tip).
    fn check_cracks_against_particles(&self, sim: &Simulation) -> Result<(), SceneError> {
        for (c, crack) in sim.cracks.iter().enumerate() {
            if let Some((p, seg)) = crate::crack::first_particle_on(&crack.points, &sim.particles.x, 1e-9 * sim.grid.min_h()) {
                let x = sim.particles.x[p];
                return Err(invalid(
                    format!("cracks[{c}].points"),
                    format!(
                        "the crack passes through the particle at ({:e}, {:e}) of bodies[{}] (crack segment {seg}; within round-off), which is \
                         then on neither side of it (or on one by round-off only); move the crack off the rows of particles ({}",
                        x.x, x.y, sim.particles.body[p], self.solver.lattice.particle_rows(self.solver.particles_per_cell)
                    ),
                ));
            }
        }
        for (c, spec) in self.cracks.iter().enumerate() {
            let Some(cs) = spec.fracture.as_ref().and_then(|f| f.growth.as_ref()).and_then(|g| g.cohesive) else { continue };
            for (m, mat) in self.materials.iter().enumerate() {
                let Some(t) = &mat.toughness else { continue };
                if let Err(e) = sim.cohesive_law(m, crate::fracture::cohesive::CohesiveSettings { strength: cs.strength }, t.kic) {
                    return Err(invalid(format!("cracks[{c}].fracture.growth.cohesive.strength"), format!("material {m} ({}): {e}", mat.name)));
                }
            }
        }
        if let Err(e) = sim.fracture_parameters(&self.fracture_requests()) {
            return Err(invalid(format!("cracks[{}].fracture", e.crack()), format!("the crack's geometry does not allow J and K at its tip: {e}")));
        }
        Ok(())
    }

    /// Crack-growth state for the cracks whose `fracture.growth` is set (None if none is).
    fn growth(&self, sim: &Simulation) -> Option<Growth> {
        let requests = self.fracture_requests();
        let growing: Vec<(usize, JRequest, GrowthSettings)> = self
            .cracks
            .iter()
            .enumerate()
            .filter_map(|(c, spec)| {
                let g = spec.fracture.as_ref()?.growth.as_ref()?;
                let release = g.release.map(|r| crate::fracture::release::ReleaseSettings { length: r.length, damping: r.damping });
                let settings = GrowthSettings { increment: g.increment, every: g.every, max_speed: g.max_speed, speed_correction: g.speed_correction, speed_window: g.speed_window, release, cohesive: g.cohesive.map(|c| crate::fracture::cohesive::CohesiveSettings { strength: c.strength }) };
                Some((c, requests[c].clone()?, settings))
            })
            .collect();
        if growing.is_empty() {
            return None;
        }
        let toughness = self.materials.iter().map(|m| m.toughness.as_ref().map(|t| Toughness { criterion: t.criterion, kic: t.kic })).collect();
        Some(Growth::new(sim, toughness, growing))
    }

    /// Settings that are accepted but unverified for the case at hand, one message each
    /// (`cramp run` prints them as warnings): the COD fit on a growing crack, whose
    /// surfaces behind the tip were laid down during growth (verified for stationary
    /// cracks only, case split_beams_k).
    pub fn warnings(&self) -> Vec<String> {
        let mut out = Vec::new();
        for i in 0..self.boundary.len() {
            if let Ok(b) = self.boundary_fn(i) {
                out.extend(b.warnings(&format!("boundary[{i}]")));
            }
        }
        if self.solver.tip_zone > 0.0 && self.cracks.iter().any(|c| c.fracture.is_some()) {
            out.push(
                "solver.tip_zone is experimental: J near a zone is verified (tests/tip_zone.rs), the K_I/K_II split by the crack opening is not — the surfaces move with fields that hold shares of particles (case tip_translation: the DCB with its crack 0.1 cell off a node row gives J −4 % but K_I −57 %); a field holding only a share of one particle cannot balance and pulls that particle, so at some tip positions a static run settles ~60 × slower than its damping (SENT, tip 0.55 of its cell: J +4 % from 0.6 to 6 ms; docs/scene.md)"
                    .to_string(),
            );
        }
        for (c, crack) in self.cracks.iter().enumerate() {
            if let Some(f) = &crack.fracture {
                if f.cod == CodMethod::Interaction && f.area_term {
                    out.push(format!(
                        "cracks[{c}].fracture.cod = \"interaction\" with area_term: the K_I : K_II ratio is the static interaction integral's (no inertial term; J, the magnitude, keeps it) — verified for stationary cracks under slow loading (case crack_rotation) and, as a growth direction, on growth_j's shear plate; not as K_II of a dynamically loaded crack"
                    ));
                }
                if f.cod == CodMethod::Fit && f.growth.is_some() {
                    out.push(format!(
                        "cracks[{c}].fracture.cod = \"fit\" on a growing crack is unverified (verified for stationary cracks only, case split_beams_k); \"next_to_tip\" is the papers' method for growth"
                    ));
                }
            }
        }
        out
    }

    /// Per crack, the J/K request of its `fracture` table (None: not computed).
    pub fn fracture_requests(&self) -> Vec<Option<JRequest>> {
        self.cracks
            .iter()
            .map(|c| {
                c.fracture.as_ref().map(|f| JRequest {
                    tips: match f.tips {
                        TipsSpec::Start => vec![TipEnd::Start],
                        TipsSpec::End => vec![TipEnd::End],
                        TipsSpec::Both => vec![TipEnd::Start, TipEnd::End],
                    },
                    contour: f.contour,
                    area_term: f.area_term,
                    cod: f.cod,
                    circle: f.circle.map(|r| r * self.grid.cell[0].min(self.grid.cell[1])),
                })
            })
            .collect()
    }
}

/// The embedded default scene (`cargo run --release` with no arguments).
pub const DEFAULT_SCENE: &str = include_str!("../verification/demo.toml");
