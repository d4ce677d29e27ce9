//! 3D scene files: the same TOML language as 2D ([`crate::scene`]) with three-component
//! vectors, 3D bodies (box, sphere, cylinder, tube, extruded polygon, closed STL surface),
//! 3D node and particle selections (box, plane, line), and no plane state. A scene is 3D
//! when its `grid.cell` has three components ([`Dimension`] of a scene file, decided by
//! [`detect_dimension`]); `cramp run`, `verify` and `compare` take either.
//!
//! Cracks in 3D are triangulated surfaces (001 §2.1; [`crate::crack::three_d`]): a
//! polygon, disc, ellipse (each optionally clipped to the bodies' bounding box: a corner
//! crack), a list of vertices and triangles, or an STL file ([`CrackSpec3`]).
//!
//! Every vector of a scene must have the scene's number of components: a 2-component
//! vector in a 3D scene, or a 3-component one in a 2D scene, is an error naming the field
//! ([`check_vector_lengths`]), so no component is ever silently dropped.

use crate::dim::{Vector, Vector3, D3};
use crate::grid::Grid3;
use crate::material::LinearElastic;
use crate::motion::{BoundaryFields, BoundaryFn, Component, LoadVariation, LoadedParticle, MotionBuilder, TimeSpec, WilliamsSpec};
use crate::particles::{Particles, NO_LOAD};
use crate::scene::{Lattice, OutputSpec, SceneError, SolverSpec};

use crate::simulation::{cfl_time_step, Load, NodeBcs, Options, Simulation};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

fn invalid(field: impl Into<String>, message: impl Into<String>) -> SceneError {
    SceneError::Invalid { field: field.into(), message: message.into() }
}

/// Most particles a 3D scene may hold: a particle's arrays take about 330 bytes and its
/// 27 uGIMP node pairs (`Pairs`: node, weight, gradient, field, item, slot) about 1.2 kB,
/// so this many fill 16 GiB (the limit `validate` puts on the grid's arrays). Checked
/// while the bodies are filled, before the particle arrays grow.
const MAX_PARTICLES: usize = (16 << 30) / 1500;

/// A 3D scene.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Scene3 {
    #[serde(default)]
    pub title: String,
    pub grid: GridSpec3,
    pub solver: SolverSpec,
    #[serde(default)]
    pub output: OutputSpec,
    pub materials: Vec<MaterialSpec3>,
    pub bodies: Vec<BodySpec3>,
    #[serde(default)]
    pub boundary: Vec<BoundarySpec3>,
    #[serde(default)]
    pub loads: Vec<LoadSpec3>,
    /// Explicit cracks: triangulated surfaces.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub cracks: Vec<CrackSpec3>,
    /// The directory of the scene file, for relative STL paths (not a scene field).
    #[serde(skip)]
    pub base_dir: Option<PathBuf>,
    /// Line probes: stresses sampled along segments (written by `cramp fea`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub probes: Vec<ProbeSpec3>,
}

/// A line probe: `points` equally spaced samples from `from` to `to` (both included).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ProbeSpec3 {
    /// Name, used in the file name `probe_<name>.csv`: letters, digits, `_` and `-`.
    pub name: String,
    pub from: [f64; 3],
    pub to: [f64; 3],
    /// Number of sample points, both ends included (2 to 100000).
    pub points: usize,
}

#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct GridSpec3 {
    /// Corner of least coordinates.
    pub origin: [f64; 3],
    /// Extent in x, y, z (a whole number of cells each).
    pub size: [f64; 3],
    /// Cell size in x, y, z.
    pub cell: [f64; 3],
}

/// An isotropic linear elastic solid. There is no `state` in 3D.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct MaterialSpec3 {
    pub name: String,
    #[serde(rename = "E")]
    pub e: f64,
    pub nu: f64,
    pub rho: f64,
    /// Refused with a clear error: plane stress / plane strain mean nothing in 3D.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub state: Option<toml::Value>,
    /// Fracture toughness and growth criterion (001 §2.3.1), as in 2D; applied at each
    /// front node in its (x1, x2) plane ([`crate::fracture::growth3`]). Omitted: the
    /// material never fractures.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub toughness: Option<crate::scene::ToughnessSpec>,
}

/// The solid a body fills (its particles are the lattice points inside it).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, rename_all = "snake_case")]
pub enum Solid {
    /// Axis-aligned box, inclusive.
    Box { min: [f64; 3], max: [f64; 3] },
    Sphere { center: [f64; 3], radius: f64 },
    /// Circular cylinder from the centre of one end face to the other.
    Cylinder { from: [f64; 3], to: [f64; 3], radius: f64 },
    /// Hollow cylinder: inner_radius ≤ distance from the axis ≤ radius.
    Tube { from: [f64; 3], to: [f64; 3], radius: f64, inner_radius: f64 },
    /// A 2D polygon (in the plane of the two other axes, in the order y–z for axis x,
    /// z–x for y, x–y for z) swept along `axis` from `from` to `to`.
    Extrusion { points: Vec<[f64; 2]>, axis: Axis, from: f64, to: f64 },
    /// A closed, consistently oriented triangulated surface (binary or ASCII STL).
    Stl { file: String },
}

#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum Axis {
    X,
    Y,
    Z,
}

impl Axis {
    fn index(self) -> usize {
        match self {
            Axis::X => 0,
            Axis::Y => 1,
            Axis::Z => 2,
        }
    }
}

#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SineVelocity3 {
    pub amplitude: [f64; 3],
    pub k: [f64; 3],
    #[serde(default)]
    pub origin: [f64; 3],
}

#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct BodySpec3 {
    pub material: String,
    pub shape: Solid,
    #[serde(default)]
    pub velocity: [f64; 3],
    pub velocity_sine: Option<SineVelocity3>,
    #[serde(default)]
    pub body_force: [f64; 3],
}

/// Grid nodes or particles to act on.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, rename_all = "snake_case")]
pub enum Selection3 {
    /// Axis-aligned box, inclusive (to round-off).
    Box { min: [f64; 3], max: [f64; 3] },
    /// Points within `tolerance` (default a quarter of the smallest cell) of the plane
    /// through `point` with normal `normal`.
    Plane { point: [f64; 3], normal: [f64; 3], tolerance: Option<f64> },
    /// Points within a quarter cell of the segment.
    Line { from: [f64; 3], to: [f64; 3] },
    /// Points within `tolerance` (default a quarter of the smallest cell) of the plane
    /// through `center` with normal `normal` whose distance from `center` lies in
    /// [inner_radius, outer_radius] (inclusive to round-off): e.g. the ligament of a penny
    /// crack's symmetry plane, the plane outside the crack disc.
    Annulus { center: [f64; 3], normal: [f64; 3], inner_radius: f64, outer_radius: f64, tolerance: Option<f64> },
}

#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct BoundarySpec3 {
    pub nodes: Selection3,
    /// Prescribed velocity components: numbers or expressions of x, y, z, t.
    pub vx: Option<Component>,
    pub vy: Option<Component>,
    pub vz: Option<Component>,
    /// Prescribed displacement components (the nodes move by u(x, t) − u(x, 0)).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ux: Option<Component>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub uy: Option<Component>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub uz: Option<Component>,
    /// Williams crack-tip displacement (x, y) of a straight front parallel to z, plane strain.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub williams: Option<WilliamsSpec>,
    /// Time function multiplying every prescribed component.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub time: Option<TimeSpec>,
}

/// A 3D crack (001 §2.1): a triangulated surface of massless crack particles.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct CrackSpec3 {
    pub surface: CrackSurface,
    /// Keep only the part inside the bounding box of the bodies (a corner or edge crack
    /// from a disc, ellipse or convex polygon). Default false.
    #[serde(default)]
    pub clip_to_bodies: bool,
    /// Longest triangle edge of a meshed surface (polygon, disc, ellipse); default half the
    /// smallest cell (Nairn 2003 §2.1 spaces crack particles at half a cell).
    pub edge: Option<f64>,
    /// Contact law (default frictionless), as in 2D.
    #[serde(default = "crate::scene::default_contact")]
    pub contact: crate::scene::ContactSpec,
    #[serde(default = "crate::scene::default_vsep")]
    pub v_sep: f64,
    #[serde(default = "crate::scene::default_vcontact")]
    pub v_contact: f64,
    /// How contact is detected, as in 2D: "opening" (default), "volume" or "displacement".
    #[serde(default)]
    pub detection: crate::crack::ContactDetection,
    /// J, K_I, K_II, K_III at the crack's front nodes ([`crate::fracture::front3`]),
    /// written to cracks.csv at the history interval. Omitted: not computed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fracture: Option<FractureSpec3>,
}

/// `cracks[].fracture` of a 3D crack: where and how J and K are evaluated along the front
/// (paper 001 §2.2, Fig. 2; [`crate::fracture::front3`]).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct FractureSpec3 {
    /// Which front nodes: "all" (default) or `{ box = { min, max } }`, those in a box.
    #[serde(default)]
    pub nodes: FrontNodesSpec,
    /// Radius of the circular contour in the (x1, x2) plane, in cells (the smallest cell
    /// size); default 2.
    #[serde(default = "default_front_radius")]
    pub radius: f64,
    /// Trapezoid intervals on the circle, face to face (default 16: exact for the K fields).
    #[serde(default = "default_front_intervals")]
    pub intervals: usize,
    /// Add the volume term over the particles in the short cylinder (default false).
    #[serde(default)]
    pub volume_term: bool,
    /// Distance behind the front, in cells, at which the crack opening that splits J into
    /// K_I, K_II, K_III is read (default 1).
    #[serde(default = "default_cod_behind")]
    pub cod_behind: f64,
    /// Half-length, in cells, of the hat weight along the front over which the openings
    /// of the neighbouring front nodes are averaged before the split (default 0: each
    /// node's own opening; [`crate::fracture::front3::average_openings`]).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub cod_along: f64,
    /// How J₁ is evaluated: "contour" (default; the paper's circle of `radius`, 001 Fig. 2)
    /// or "domain" (the equivalent domain integral over the particles, with the weight
    /// q = 1 within `radius − ramp` cells of the front line, falling to 0 at `radius`, and a
    /// weight ψ = cos²(πs/2L) of half-length L = `along` cells along the front;
    /// [`crate::fracture::front3`]).
    #[serde(default)]
    pub method: FrontMethod,
    /// How K_I, K_II, K_III are taken from the fields: "opening" (default; J₁ split by the
    /// crack opening `cod_behind` cells behind the node, 004 eqs. 14–15 with mode III) or
    /// "interaction" (domain integral only: the interaction integral over the same domain
    /// with the unit-K fields of each mode, static; [`crate::fracture::front3::aux_fields`]).
    #[serde(default)]
    pub split: FrontSplit,
    /// Domain integral only: width of q's fall to 0, in cells (default 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ramp: Option<f64>,
    /// Domain integral only: half-length L of q's weight ψ = cos²(πs/2L) along the front, in
    /// cells (default [`DEFAULT_ALONG`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub along: Option<f64>,
    /// Domain integral only: the model's symmetry planes, `[{ axis = "x", at = 0.0 }, ...]`
    /// (at most one per axis): the particles' mirror images in them complete a domain that
    /// such a plane cuts ([`crate::fracture::front3::mirror_images`]). The material must lie
    /// on one side of each, and the scene must be symmetric about it (rollers on the plane).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub mirrors: Vec<MirrorSpec>,
    /// Let the front grow (001 §2.3.2; [`crate::fracture::growth3`]): the 2D table
    /// `{ increment, every, max_speed, speed_correction, speed_window }`. Omitted: the crack is stationary.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub growth: Option<crate::scene::GrowthSpec>,
}

impl FractureSpec3 {
    /// The domain integral's ramp width in cells (`ramp`, default 1).
    pub fn domain_ramp(&self) -> f64 {
        self.ramp.unwrap_or(1.0)
    }

    /// The domain integral's half-length along the front in cells (`along`, default [`DEFAULT_ALONG`]).
    pub fn domain_along(&self) -> f64 {
        self.along.unwrap_or(DEFAULT_ALONG)
    }
}

fn default_front_radius() -> f64 {
    2.0
}
fn default_front_intervals() -> usize {
    16
}
fn is_zero(x: &f64) -> bool {
    *x == 0.0
}
fn default_cod_behind() -> f64 {
    1.0
}
/// Default half-length of the domain integral's weight along a 3D front, in cells: a ψ
/// shorter than two cells reads the particles' sawtooth within a cell (docs/scene.md, the
/// measured figures: cos² with L = 1 cell per node −25 … +15 % on the a/h = 5 penny, L = 2
/// cells −5.3 … +6.2 %).
pub const DEFAULT_ALONG: f64 = 2.0;

/// `cracks[].fracture.method` of a 3D crack.
#[derive(Clone, Copy, Debug, Default, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum FrontMethod {
    /// The circular contour of 001 Fig. 2 (line term, volume term on request).
    #[default]
    Contour,
    /// The equivalent domain integral over the particles (includes the inertia terms and
    /// the variation along the front that the planar contour leaves out).
    Domain,
}

/// One of `cracks[].fracture.mirrors`: the symmetry plane x_axis = at.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct MirrorSpec {
    /// "x", "y" or "z".
    pub axis: String,
    pub at: f64,
}

impl MirrorSpec {
    /// The axis index (0–2), None for anything but "x", "y", "z".
    pub fn axis_index(&self) -> Option<usize> {
        ["x", "y", "z"].iter().position(|a| *a == self.axis)
    }
}

/// `cracks[].fracture.split` of a 3D crack.
#[derive(Clone, Copy, Debug, Default, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum FrontSplit {
    /// J₁ split by the crack opening behind the node.
    #[default]
    Opening,
    /// The interaction integral over the domain (method = "domain").
    Interaction,
}

/// The front nodes a `fracture` table asks for.
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, rename_all = "snake_case")]
pub enum FrontNodesSpec {
    /// Every crack particle on the front (inside the material).
    #[default]
    All,
    /// The front nodes inside a box (bounds included).
    Box { min: [f64; 3], max: [f64; 3] },
}

/// The shape of a 3D crack surface. Its normals (the "above" side) follow the right-hand
/// rule of a polygon's points, the given `normal`, or the triangles' corner order.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, rename_all = "snake_case")]
pub enum CrackSurface {
    /// A planar polygon (a rectangle is one), points in order.
    Polygon { points: Vec<[f64; 3]> },
    /// A disc (penny crack).
    Disc { center: [f64; 3], normal: [f64; 3], radius: f64 },
    /// An ellipse with semi-axis `a` along `axis` (projected on the plane) and `b` across.
    Ellipse { center: [f64; 3], normal: [f64; 3], axis: [f64; 3], a: f64, b: f64 },
    /// Vertices and triangles (corner indices from 0), used as given.
    Mesh { vertices: Vec<[f64; 3]>, triangles: Vec<[u32; 3]> },
    /// A triangulated surface from an STL file (binary or ASCII), used as given.
    Stl { file: String },
}

#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct LoadSpec3 {
    pub particles: Selection3,
    /// Total force, shared equally by the selected particles (or give `traction`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub force: Option<[f64; 3]>,
    /// Force per unit area, numbers or expressions of x, y, z, t, distributed by each
    /// particle's share of the face.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub traction: Option<[Component; 3]>,
    /// Outward normal of the loaded face (a traction on a `box`; a `plane` gives it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub normal: Option<[f64; 3]>,
    #[serde(default)]
    pub ramp: f64,
    /// Time function multiplying the force or traction (instead of `ramp`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub time: Option<TimeSpec>,
}

/// A polygon's points in the order whose right-hand normal agrees with n.
fn orient(mut poly: Vec<Vector3>, n: Vector3) -> Vec<Vector3> {
    if crate::crack::surface::newell_normal(&poly).dot(&n) < 0.0 {
        poly.reverse();
    }
    poly
}

fn v3(a: [f64; 3]) -> Vector3 {
    Vector3::new(a[0], a[1], a[2])
}

fn finite(field: &str, x: f64) -> Result<(), SceneError> {
    if x.is_finite() {
        Ok(())
    } else {
        Err(invalid(field, format!("must be a finite number, got {x}")))
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

fn finite3(field: &str, a: &[f64; 3]) -> Result<(), SceneError> {
    for (c, x) in a.iter().enumerate() {
        finite(&format!("{field}[{c}]"), *x)?;
    }
    Ok(())
}

/// The dimension of a scene file, from its `grid.cell` (or `grid.origin`).
pub fn detect_dimension(value: &toml::Value) -> Result<usize, String> {
    let grid = value.get("grid").ok_or("missing table [grid]")?;
    for key in ["cell", "origin", "size"] {
        if let Some(a) = grid.get(key).and_then(|v| v.as_array()) {
            return match a.len() {
                2 => Ok(2),
                3 => Ok(3),
                n => Err(format!("scene field `grid.{key}`: has {n} components; a scene is 2D (2 components) or 3D (3)")),
            };
        }
    }
    Err("scene field `grid.cell`: missing (it has 2 components in a 2D scene, 3 in a 3D one)".into())
}

/// Every array of numbers in the scene must have `dim` components, except the 2D
/// points of a 3D extrusion's polygon; the error names the field. (Arrays of arrays —
/// polygon and crack points — are checked element by element.)
pub fn check_vector_lengths(value: &toml::Value, dim: usize) -> Result<(), SceneError> {
    fn walk(v: &toml::Value, path: &str, dim: usize) -> Result<(), SceneError> {
        match v {
            toml::Value::Table(t) => {
                for (k, x) in t {
                    let p = if path.is_empty() { k.clone() } else { format!("{path}.{k}") };
                    walk(x, &p, dim)?;
                }
                Ok(())
            }
            toml::Value::Array(a) if !a.is_empty() && a.iter().all(|x| x.is_integer() || x.is_float()) => {
                // In 3D, extrusion polygons are 2D points (`...extrusion.points[i]`).
                let want = if dim == 3 && path.contains(".extrusion.points[") { 2 } else { dim };
                if a.len() != want {
                    let what = if want == 2 && dim == 3 { "an extrusion's polygon points have 2 components".to_string() } else { format!("this is a {dim}D scene (grid.cell has {dim} components), so vectors take {dim}") };
                    return Err(invalid(path, format!("has {} components; {what}", a.len())));
                }
                Ok(())
            }
            toml::Value::Array(a) => {
                for (i, x) in a.iter().enumerate() {
                    walk(x, &format!("{path}[{i}]"), dim)?;
                }
                Ok(())
            }
            _ => Ok(()),
        }
    }
    walk(value, "", dim)
}

impl Solid {
    /// Is x inside (boundary included, decided in floating point as written here; a
    /// lattice point exactly on a curved surface may fall either way by round-off).
    pub fn contains(&self, x: &Vector3, mesh: Option<&crate::stl::ClosedMesh>) -> bool {
        match self {
            Solid::Box { min, max } => (0..3).all(|c| x[c] >= min[c] && x[c] <= max[c]),
            Solid::Sphere { center, radius } => (x - v3(*center)).norm_squared() <= radius * radius,
            Solid::Cylinder { from, to, radius } => radial(x, from, to).is_some_and(|r2| r2 <= radius * radius),
            Solid::Tube { from, to, radius, inner_radius } => radial(x, from, to).is_some_and(|r2| r2 <= radius * radius && r2 >= inner_radius * inner_radius),
            Solid::Extrusion { points, axis, from, to } => {
                let a = axis.index();
                let (lo, hi) = if from <= to { (*from, *to) } else { (*to, *from) };
                if x[a] < lo || x[a] > hi {
                    return false;
                }
                let (u, w) = ((a + 1) % 3, (a + 2) % 3);
                let polygon = crate::scene::ShapeSpec::Polygon { points: points.clone() };
                polygon.contains(&Vector::new(x[u], x[w]))
            }
            Solid::Stl { .. } => mesh.is_some_and(|m| m.contains(x)),
        }
    }

    /// Axis-aligned bounding box.
    fn bounds(&self, mesh: Option<&crate::stl::ClosedMesh>) -> (Vector3, Vector3) {
        match self {
            Solid::Box { min, max } => (v3(*min), v3(*max)),
            Solid::Sphere { center, radius } => (v3(*center) - Vector3::repeat(*radius), v3(*center) + Vector3::repeat(*radius)),
            Solid::Cylinder { from, to, radius } | Solid::Tube { from, to, radius, .. } => {
                // The end discs reach radius·√(1 − d_c²) from their centres along axis c, d
                // the unit axis (0 along an axis-aligned cylinder's own axis); radius in
                // every direction if the axis has no length.
                let (a, b) = (v3(*from), v3(*to));
                let r = match (b - a).try_normalize(0.0) {
                    Some(d) => Vector3::from_fn(|c, _| radius * (1.0 - d[c] * d[c]).max(0.0).sqrt()),
                    None => Vector3::repeat(*radius),
                };
                (a.inf(&b) - r, a.sup(&b) + r)
            }
            Solid::Extrusion { points, axis, from, to } => {
                let a = axis.index();
                let (u, w) = ((a + 1) % 3, (a + 2) % 3);
                let mut lo = Vector3::repeat(f64::INFINITY);
                let mut hi = Vector3::repeat(f64::NEG_INFINITY);
                for p in points {
                    lo[u] = lo[u].min(p[0]);
                    hi[u] = hi[u].max(p[0]);
                    lo[w] = lo[w].min(p[1]);
                    hi[w] = hi[w].max(p[1]);
                }
                lo[a] = from.min(*to);
                hi[a] = from.max(*to);
                (lo, hi)
            }
            Solid::Stl { .. } => mesh.map(|m| m.bounds()).unwrap_or((Vector3::zeros(), Vector3::zeros())),
        }
    }
}

/// Squared distance of x from the axis from→to, if its projection lies between the ends.
/// For an axis along a coordinate direction it is the sum of the two other squared
/// offsets, computed as the 2D disk test computes it, so a cylinder along z holds exactly
/// the lattice points of the 2D disk it extrudes.
fn radial(x: &Vector3, from: &[f64; 3], to: &[f64; 3]) -> Option<f64> {
    let (a, b) = (v3(*from), v3(*to));
    let d = b - a;
    let r = x - a;
    let axial: Vec<usize> = (0..3).filter(|&c| d[c] != 0.0).collect();
    if let [k] = axial[..] {
        let (lo, hi) = (a[k].min(b[k]), a[k].max(b[k]));
        if x[k] < lo || x[k] > hi {
            return None;
        }
        let (u, w) = ((k + 1) % 3, (k + 2) % 3);
        let (u, w) = (u.min(w), u.max(w));
        return Some(r[u] * r[u] + r[w] * r[w]);
    }
    let t = r.dot(&d);
    let l2 = d.norm_squared();
    if t < 0.0 || t > l2 {
        return None;
    }
    Some((r - d * (t / l2)).norm_squared())
}

impl Selection3 {
    pub(crate) fn tolerance(&self, h: f64) -> f64 {
        match self {
            Selection3::Box { .. } => 1e-9 * h,
            Selection3::Plane { tolerance, .. } | Selection3::Annulus { tolerance, .. } => tolerance.unwrap_or(0.25 * h),
            Selection3::Line { .. } => 0.25 * h,
        }
    }

    pub(crate) fn contains(&self, x: &Vector3, tol: f64) -> bool {
        match self {
            Selection3::Box { min, max } => (0..3).all(|c| x[c] >= min[c] - tol && x[c] <= max[c] + tol),
            Selection3::Plane { point, normal, .. } => {
                let n = v3(*normal);
                ((x - v3(*point)).dot(&n) / n.norm()).abs() <= tol
            }
            Selection3::Line { from, to } => {
                let (a, b) = (v3(*from), v3(*to));
                let d = b - a;
                let l2 = d.norm_squared();
                let t = if l2 > 0.0 { ((x - a).dot(&d) / l2).clamp(0.0, 1.0) } else { 0.0 };
                (x - (a + d * t)).norm() <= tol
            }
            Selection3::Annulus { center, normal, inner_radius, outer_radius, .. } => {
                let n = v3(*normal) / v3(*normal).norm();
                let d = x - v3(*center);
                let along = d.dot(&n);
                let rho = (d - n * along).norm();
                let round_off = 1e-9 * outer_radius.abs().max(1.0);
                along.abs() <= tol && rho >= inner_radius - round_off && rho <= outer_radius + round_off
            }
        }
    }

    fn validate(&self, field: &str) -> Result<(), SceneError> {
        match self {
            Selection3::Box { min, max } => {
                finite3(&format!("{field}.box.min"), min)?;
                finite3(&format!("{field}.box.max"), max)?;
                if (0..3).any(|c| max[c] < min[c]) {
                    return Err(invalid(format!("{field}.box"), format!("max {max:?} is below min {min:?} in some direction")));
                }
            }
            Selection3::Plane { point, normal, tolerance } => {
                finite3(&format!("{field}.plane.point"), point)?;
                finite3(&format!("{field}.plane.normal"), normal)?;
                if v3(*normal).norm() == 0.0 {
                    return Err(invalid(format!("{field}.plane.normal"), "is the zero vector"));
                }
                if let Some(t) = tolerance {
                    positive(&format!("{field}.plane.tolerance"), *t)?;
                }
            }
            Selection3::Line { from, to } => {
                finite3(&format!("{field}.line.from"), from)?;
                finite3(&format!("{field}.line.to"), to)?;
            }
            Selection3::Annulus { center, normal, inner_radius, outer_radius, tolerance } => {
                finite3(&format!("{field}.annulus.center"), center)?;
                finite3(&format!("{field}.annulus.normal"), normal)?;
                if v3(*normal).norm() == 0.0 {
                    return Err(invalid(format!("{field}.annulus.normal"), "is the zero vector"));
                }
                if !(inner_radius.is_finite() && *inner_radius >= 0.0) {
                    return Err(invalid(format!("{field}.annulus.inner_radius"), format!("must be a finite number ≥ 0, got {inner_radius}")));
                }
                if !(outer_radius.is_finite() && outer_radius > inner_radius) {
                    return Err(invalid(format!("{field}.annulus.outer_radius"), format!("must be finite and above inner_radius ({inner_radius}), got {outer_radius}")));
                }
                if let Some(t) = tolerance {
                    positive(&format!("{field}.annulus.tolerance"), *t)?;
                }
            }
        }
        Ok(())
    }
}

impl Scene3 {
    /// Parse and validate TOML text; `origin` names the source in errors, `base_dir` is
    /// where relative STL paths are resolved.
    pub fn from_toml(text: &str, origin: &str, base_dir: Option<&Path>) -> Result<Scene3, SceneError> {
        let parse_err = |message: String| SceneError::Parse { path: origin.to_string(), message };
        let value: toml::Value = toml::from_str(text).map_err(|e| parse_err(e.to_string()))?;
        check_vector_lengths(&value, 3)?;
        let mut scene: Scene3 = toml::from_str(text).map_err(|e| parse_err(e.to_string()))?;
        scene.base_dir = base_dir.map(Path::to_path_buf);
        scene.validate()?;
        Ok(scene)
    }

    pub fn from_file(path: &Path) -> Result<Scene3, SceneError> {
        let text = std::fs::read_to_string(path).map_err(|e| SceneError::Io { path: path.display().to_string(), source: e })?;
        Scene3::from_toml(&text, &path.display().to_string(), path.parent())
    }

    /// Check every value for physical sense; the error names the field.
    pub fn validate(&self) -> Result<(), SceneError> {
        let g = &self.grid;
        let mut nodes = 1.0f64;
        for c in 0..3 {
            finite(&format!("grid.origin[{c}]"), g.origin[c])?;
            positive(&format!("grid.size[{c}]"), g.size[c])?;
            positive(&format!("grid.cell[{c}]"), g.cell[c])?;
            let n = g.size[c] / g.cell[c];
            if (n - n.round()).abs() > 1e-9 * n.max(1.0) || n.round() < 1.0 {
                return Err(invalid(format!("grid.size[{c}]"), format!("{} is not a whole number of cells of size {} (got {n} cells)", g.size[c], g.cell[c])));
            }
            nodes *= n.round() + 1.0;
        }
        // Nodal arrays of one velocity field take ~170 bytes per node (7 vectors and a
        // mass); refuse a grid whose arrays alone would not fit in 16 GiB.
        let bytes = nodes * 200.0;
        if bytes > 16.0 * (1u64 << 30) as f64 {
            return Err(invalid("grid.size", format!("{nodes:.3e} nodes would need about {:.0} GiB for the nodal arrays alone; use fewer or larger cells", bytes / (1u64 << 30) as f64)));
        }
        crate::scene::validate_solver(&self.solver, &self.output)?;
        self.validate_cracks()?;
        if self.materials.is_empty() {
            return Err(invalid("materials", "at least one material is required"));
        }
        for (i, m) in self.materials.iter().enumerate() {
            let f = |n: &str| format!("materials[{i}].{n}");
            if m.state.is_some() {
                return Err(invalid(f("state"), "plane_stress / plane_strain mean nothing in a 3D scene (the solid is 3D); remove the field"));
            }
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
                if t.criterion == crate::fracture::growth::Criterion::MinStrainEnergy && m.nu < 0.0 {
                    return Err(invalid(f("toughness.criterion"), format!("min_strain_energy needs 0 ≤ ν (κ = 3 − 4ν in (1, 3]), got ν = {}", m.nu)));
                }
            }
        }
        if self.bodies.is_empty() {
            return Err(invalid("bodies", "at least one body is required"));
        }
        for (i, b) in self.bodies.iter().enumerate() {
            let f = |n: &str| format!("bodies[{i}].{n}");
            if !self.materials.iter().any(|m| m.name == b.material) {
                return Err(invalid(f("material"), format!("no material named '{}'", b.material)));
            }
            finite3(&f("velocity"), &b.velocity)?;
            finite3(&f("body_force"), &b.body_force)?;
            if let Some(sv) = &b.velocity_sine {
                finite3(&f("velocity_sine.amplitude"), &sv.amplitude)?;
                finite3(&f("velocity_sine.k"), &sv.k)?;
                finite3(&f("velocity_sine.origin"), &sv.origin)?;
            }
            match &b.shape {
                Solid::Box { min, max } => {
                    finite3(&f("shape.box.min"), min)?;
                    finite3(&f("shape.box.max"), max)?;
                    if !(0..3).all(|c| max[c] > min[c]) {
                        return Err(invalid(f("shape.box"), format!("max {max:?} must exceed min {min:?} in every direction")));
                    }
                }
                Solid::Sphere { center, radius } => {
                    finite3(&f("shape.sphere.center"), center)?;
                    positive(&f("shape.sphere.radius"), *radius)?;
                }
                Solid::Cylinder { from, to, radius } | Solid::Tube { from, to, radius, .. } => {
                    let kind = if matches!(b.shape, Solid::Cylinder { .. }) { "cylinder" } else { "tube" };
                    finite3(&f(&format!("shape.{kind}.from")), from)?;
                    finite3(&f(&format!("shape.{kind}.to")), to)?;
                    positive(&f(&format!("shape.{kind}.radius")), *radius)?;
                    if from == to {
                        return Err(invalid(f(&format!("shape.{kind}.to")), "equals `from`: the axis has zero length"));
                    }
                    if let Solid::Tube { inner_radius, .. } = &b.shape {
                        positive(&f("shape.tube.inner_radius"), *inner_radius)?;
                        if inner_radius >= radius {
                            return Err(invalid(f("shape.tube.inner_radius"), format!("must be below radius {radius}, got {inner_radius}")));
                        }
                    }
                }
                Solid::Extrusion { points, from, to, .. } => {
                    if points.len() < 3 {
                        return Err(invalid(f("shape.extrusion.points"), format!("a polygon needs at least 3 points, got {}", points.len())));
                    }
                    for (k, p) in points.iter().enumerate() {
                        finite(&f(&format!("shape.extrusion.points[{k}][0]")), p[0])?;
                        finite(&f(&format!("shape.extrusion.points[{k}][1]")), p[1])?;
                    }
                    finite(&f("shape.extrusion.from"), *from)?;
                    finite(&f("shape.extrusion.to"), *to)?;
                    if from == to {
                        return Err(invalid(f("shape.extrusion.to"), "equals `from`: the extrusion has zero length"));
                    }
                }
                Solid::Stl { file } => {
                    if file.is_empty() {
                        return Err(invalid(f("shape.stl.file"), "is empty"));
                    }
                }
            }
        }
        for (i, b) in self.boundary.iter().enumerate() {
            b.nodes.validate(&format!("boundary[{i}].nodes"))?;
            self.boundary_fn(i)?;
        }
        for (i, l) in self.loads.iter().enumerate() {
            l.particles.validate(&format!("loads[{i}].particles"))?;
            self.load_normal(i)?;
        }
        let (lo, hi) = (self.grid.origin, std::array::from_fn::<f64, 3, _>(|c| self.grid.origin[c] + self.grid.size[c]));
        for (i, p) in self.probes.iter().enumerate() {
            let before: Vec<&str> = self.probes[..i].iter().map(|o| o.name.as_str()).collect();
            let h = self.grid.cell.iter().fold(f64::INFINITY, |m, &c| m.min(c));
            crate::scene::validate_probe(i, &p.name, &before, &p.from, &p.to, p.points, &lo, &hi, h)?;
        }
        let speeds: Vec<f64> = self.materials().iter().map(crate::material::Constitutive::wave_speed).collect();
        let mats: Vec<(f64, f64)> = self.materials.iter().map(|m| (m.e, m.rho)).collect();
        crate::scene::validate_time_step(&self.solver, self.time_step(), &speeds, &mats)
    }

    /// `boundary[i]` compiled ([`BoundaryFn`]): the error names the field.
    pub fn boundary_fn(&self, i: usize) -> Result<BoundaryFn, SceneError> {
        let b = &self.boundary[i];
        let field = format!("boundary[{i}]");
        let mat = match &b.williams {
            Some(w) => {
                let names: Vec<&str> = self.materials.iter().map(|m| m.name.as_str()).collect();
                Some(crate::motion::williams_material(&format!("{field}.williams"), w, &names, &self.materials(), 3).map_err(|(f, m)| invalid(f, m))?)
            }
            None => None,
        };
        let fields = BoundaryFields {
            field,
            velocity: vec![b.vx.as_ref(), b.vy.as_ref(), b.vz.as_ref()],
            displacement: vec![b.ux.as_ref(), b.uy.as_ref(), b.uz.as_ref()],
            time: b.time.as_ref(),
            williams: b.williams.as_ref(),
        };
        BoundaryFn::new(&fields, 3, mat).map_err(|(f, m)| invalid(f, m))
    }

    /// Check `loads[i]` ([`crate::motion::validate_load`]) and return a traction's unit
    /// outward normal: `normal`, or that of a `plane` selection.
    pub fn load_normal(&self, i: usize) -> Result<Option<Vec<f64>>, SceneError> {
        let l = &self.loads[i];
        let implied = match &l.particles {
            Selection3::Plane { normal, .. } => Some(normal.to_vec()),
            _ => None,
        };
        crate::motion::validate_load(&format!("loads[{i}]"), l.force.as_ref().map(|f| &f[..]), l.traction.as_ref().map(|t| &t[..]), l.normal.as_ref().map(|n| &n[..]), l.ramp, l.time.as_ref(), implied, 3)
            .map_err(|(f, m)| invalid(f, m))
    }

    /// Warnings (see [`crate::scene::Scene::warnings`]): displacements that do not change in time.
    pub fn warnings(&self) -> Vec<String> {
        (0..self.boundary.len()).filter_map(|i| self.boundary_fn(i).ok().map(|b| b.warnings(&format!("boundary[{i}]")))).flatten().collect()
    }

    pub fn grid(&self) -> Grid3 {
        let g = &self.grid;
        Grid3 { origin: v3(g.origin), h: v3(g.cell), n: std::array::from_fn(|c| (g.size[c] / g.cell[c]).round() as usize) }
    }

    pub fn materials(&self) -> Vec<LinearElastic> {
        self.materials.iter().map(|m| LinearElastic::solid(m.e, m.nu, m.rho)).collect()
    }

    /// The time step: explicit `dt`, or `cfl` (default 0.5) × smallest cell / c_d (3D).
    pub fn time_step(&self) -> f64 {
        match self.solver.dt {
            Some(dt) => dt,
            None => self.solver.cfl.unwrap_or(0.5) * cfl_time_step(&self.grid(), &self.materials()),
        }
    }

    /// History interval (default end_time / 100).
    pub fn history_interval(&self) -> f64 {
        self.output.history_interval.unwrap_or(self.solver.end_time / 100.0)
    }

    /// Fill the bodies with particles (n³ per cell on the regular sub-lattice, first
    /// body wins; only the cells of each body's bounding box are visited, so the cost
    /// scales with the material, not the grid), resolve loads and boundary conditions,
    /// and assemble the simulation.
    pub fn build(&self) -> Result<Simulation<D3>, SceneError> {
        let sim = self.build_simulation()?;
        crate::fingerprint::on_build(&sim, || toml::to_string(self).ok());
        Ok(sim)
    }

    fn build_simulation(&self) -> Result<Simulation<D3>, SceneError> {
        let grid = self.grid();
        let mats = self.materials();
        let n = self.solver.particles_per_cell;
        let meshes = self.load_meshes()?;
        let (lo, hi) = (grid.origin, crate::dim::GridGeometry::max_corner(&grid));
        for (k, body) in self.bodies.iter().enumerate() {
            let (a, b) = body.shape.bounds(meshes[k].as_ref());
            if (0..3).any(|c| a[c] < lo[c] || b[c] > hi[c]) {
                return Err(invalid(
                    format!("bodies[{k}].shape"),
                    format!("extends outside the grid [{}, {}] × [{}, {}] × [{}, {}] (its box is {:?} to {:?})", lo.x, hi.x, lo.y, hi.y, lo.z, hi.z, [a.x, a.y, a.z], [b.x, b.y, b.z]),
                ));
            }
        }
        let sub = grid.h / n as f64;
        let lp = sub * 0.5;
        let mut particles: Particles<D3> = Particles::default();
        let mut owner: Vec<Vec<Vector3>> = vec![Vec::new(); self.bodies.len()];
        // Cells in z, y, x order; sub-particles within a cell in the same order.
        let (mut clo, mut chi) = ([usize::MAX; 3], [0usize; 3]);
        for (k, body) in self.bodies.iter().enumerate() {
            let (a, b) = body.shape.bounds(meshes[k].as_ref());
            for c in 0..3 {
                let i0 = ((a[c] - grid.origin[c]) / grid.h[c]).floor().max(0.0) as usize;
                let i1 = (((b[c] - grid.origin[c]) / grid.h[c]).ceil() as usize).min(grid.n[c]);
                clo[c] = clo[c].min(i0);
                chi[c] = chi[c].max(i1);
            }
        }
        let mut filled = 0usize;
        // The lattices to fill: the grid's, shared by every body (each point to the first body
        // holding it), or each body's own from its box's lower corner (`solver.lattice`).
        let lattices: Vec<(Option<usize>, Vector3, [usize; 3], [usize; 3])> = match self.solver.lattice {
            Lattice::Grid => vec![(None, grid.origin, clo, chi)],
            Lattice::Body => (0..self.bodies.len())
                .map(|k| {
                    let (a, b) = self.bodies[k].shape.bounds(meshes[k].as_ref());
                    (Some(k), a, [0; 3], [0, 1, 2].map(|c| ((b[c] - a[c]) / grid.h[c]).ceil() as usize + 1))
                })
                .collect(),
        };
        for (only, anchor, clo, chi) in lattices {
            for iz in clo[2]..chi[2] {
                for iy in clo[1]..chi[1] {
                    for ix in clo[0]..chi[0] {
                        for cz in 0..n {
                            for cy in 0..n {
                                for cx in 0..n {
                                    let frac = |i: usize, c: usize| i as f64 + (c as f64 + 0.5) / n as f64;
                                    let x = Vector3::new(anchor.x + grid.h.x * frac(ix, cx), anchor.y + grid.h.y * frac(iy, cy), anchor.z + grid.h.z * frac(iz, cz));
                                    // On a body's own lattice, its points that no earlier body holds.
                                    let last = only.map_or(self.bodies.len(), |o| o + 1);
                                    let first = self.bodies[..last].iter().enumerate().position(|(k, body)| body.shape.contains(&x, meshes[k].as_ref()));
                                    let Some(k) = first.filter(|&k| only.is_none_or(|o| o == k)) else { continue };
                                    owner[k].push(x);
                                    filled += 1;
                                    if filled > MAX_PARTICLES {
                                        return Err(invalid(
                                            "bodies",
                                            format!("hold more than {MAX_PARTICLES} particles ({n}³ per cell), which with their node pairs would need more than 16 GiB; use larger cells or fewer particles per cell"),
                                        ));
                                    }
                                }
                            }
                        }
                    }
                }
            }
        }
        for (k, body) in self.bodies.iter().enumerate() {
            if owner[k].is_empty() {
                return Err(invalid(format!("bodies[{k}].shape"), "contains no particle positions (the body is smaller than the particle spacing, or hidden by earlier bodies)"));
            }
            let mi = self.materials.iter().position(|m| m.name == body.material).unwrap_or(0);
            let vol0 = sub.x * sub.y * sub.z;
            let mass = mats[mi].rho * vol0;
            for x in &owner[k] {
                let mut vel = v3(body.velocity);
                if let Some(sv) = &body.velocity_sine {
                    let phase = v3(sv.k).dot(&(x - v3(sv.origin)));
                    vel += v3(sv.amplitude) * phase.sin();
                }
                particles.push(*x, vel, mass, vol0, lp, mi as u16, k as u16);
            }
        }
        if particles.len() > u32::MAX as usize / 27 {
            return Err(invalid("solver.particles_per_cell", format!("{} particles are more than the pair index can address", particles.len())));
        }
        let hmin = crate::dim::GridGeometry::min_h(&grid);
        let mut loads = Vec::new();
        for (li, l) in self.loads.iter().enumerate() {
            let tol = l.particles.tolerance(hmin);
            let sel: Vec<usize> = (0..particles.len()).filter(|&p| l.particles.contains(&particles.x[p], tol)).collect();
            if sel.is_empty() {
                return Err(invalid(format!("loads[{li}].particles"), "selects no particles"));
            }
            for &p in &sel {
                if particles.load[p] != NO_LOAD {
                    let x = particles.x[p];
                    return Err(invalid(format!("loads[{li}].particles"), format!("selects the particle at ({}, {}, {}), already loaded by loads[{}]", x.x, x.y, x.z, particles.load[p])));
                }
                particles.load[p] = li as u16;
            }
            let normal = self.load_normal(li)?.unwrap_or_default();
            let loaded: Vec<LoadedParticle<Vector3>> = sel.iter().map(|&p| LoadedParticle { id: particles.id[p], x0: particles.x0[p], lp: particles.lp[p], thickness: 1.0 }).collect();
            let varying = LoadVariation::new(&format!("loads[{li}]"), l.time.as_ref(), l.traction.as_ref().map(|t| &t[..]), &normal, &loaded, particles.len()).map_err(|(f, m)| invalid(f, m))?;
            let force = l.force.map_or(Vector3::zeros(), v3);
            loads.push(Load { force_per_particle: force / sel.len() as f64, ramp: l.ramp, varying: varying.map(Box::new) });
        }
        let nn = crate::dim::GridGeometry::num_nodes(&grid);
        let mut bcs = NodeBcs::new(nn);
        let mut motion = MotionBuilder::default();
        for (bi, b) in self.boundary.iter().enumerate() {
            let tol = b.nodes.tolerance(hmin);
            let compiled = self.boundary_fn(bi)?;
            let field = format!("boundary[{bi}]");
            let mut any = false;
            for i in 0..nn {
                let x = crate::dim::GridGeometry::node_pos(&grid, i);
                if b.nodes.contains(&x, tol) {
                    any = true;
                    motion.add(&mut bcs, bi, &field, &compiled, i, &[x.x, x.y, x.z]).map_err(|(f, m)| invalid(f, m))?;
                }
            }
            if !any {
                return Err(invalid(format!("boundary[{bi}].nodes"), "selects no grid nodes"));
            }
        }
        motion.finish(&mut bcs);
        bcs.finish();
        let options = Options {
            scheme: self.solver.scheme,
            shape: self.solver.shape,
            dt: self.time_step(),
            damping: self.solver.damping,
            damping_on: self.solver.damping_on,
            checked: self.solver.checked,
            crack_method: self.solver.crack_method,
            tip_zone: 0.0,
        };
        let body_force = self.bodies.iter().map(|b| v3(b.body_force)).collect();
        let thickness = vec![1.0; self.bodies.len()];
        let cracks = self.crack_surfaces(&grid, &meshes)?;
        for (c, crack) in cracks.iter().enumerate() {
            if let Some((p, t)) = crate::crack::three_d::first_particle_on3(&crack.surface, &particles.x, 1e-9 * hmin) {
                let x = particles.x[p];
                return Err(invalid(
                    format!("cracks[{c}].surface"),
                    format!(
                        "the crack passes through the particle at ({:e}, {:e}, {:e}) of bodies[{}] (crack triangle {t}; within round-off), which is then on \
                         neither side of it (or on one by round-off only); move the crack off the planes of particles ({}",
                        x.x, x.y, x.z, particles.body[p], self.solver.lattice.particle_planes(n)
                    ),
                ));
            }
        }
        let requests = self.front_requests(&cracks)?;
        // A mirror plane bounds the material: every particle's domain on one side of it.
        for (c, req) in requests.iter().enumerate() {
            for (j, &(a, at)) in req.iter().flat_map(|r| r.mirrors.iter()).enumerate() {
                let hair = 1e-9 * self.grid.cell[a];
                let below = (0..particles.len()).find(|&p| particles.x[p][a] - particles.lp[p][a] < at - hair);
                let above = (0..particles.len()).find(|&p| particles.x[p][a] + particles.lp[p][a] > at + hair);
                if let (Some(p), Some(q)) = (below, above) {
                    return Err(invalid(
                        format!("cracks[{c}].fracture.mirrors[{j}]"),
                        format!("the material lies on both sides of the plane {} = {at} (particles at {:?} and {:?}): a mirror plane is a symmetry plane on the model's boundary", ["x", "y", "z"][a], particles.x[p].as_slice(), particles.x[q].as_slice()),
                    ));
                }
            }
        }
        let mut sim = Simulation::new(grid, particles, mats, body_force, thickness, loads, bcs, cracks, options);
        sim.growth = self.growth3(&sim, &requests);
        Ok(sim)
    }

    /// Crack-growth state for the cracks whose `fracture.growth` is set (None if none is).
    fn growth3(&self, sim: &Simulation<D3>, requests: &[Option<crate::fracture::front3::FrontRequest>]) -> Option<crate::fracture::growth3::Growth3> {
        let growing: Vec<_> = self
            .cracks
            .iter()
            .enumerate()
            .filter_map(|(c, spec)| {
                let g = spec.fracture.as_ref()?.growth.as_ref()?;
                let settings = crate::fracture::growth::GrowthSettings { increment: g.increment, every: g.every, max_speed: g.max_speed, speed_correction: g.speed_correction, speed_window: g.speed_window, release: None, cohesive: None };
                Some((c, requests[c].clone()?, settings))
            })
            .collect();
        if growing.is_empty() {
            return None;
        }
        let toughness = self.materials.iter().map(|m| m.toughness.as_ref().map(|t| crate::fracture::growth::Toughness { criterion: t.criterion, kic: t.kic })).collect();
        Some(crate::fracture::growth3::Growth3::new(sim, toughness, growing))
    }

    /// Check the crack fields that need no meshing (the rest is checked by
    /// [`Scene3::crack_surfaces`] when the scene is built).
    fn validate_cracks(&self) -> Result<(), SceneError> {
        for (i, c) in self.cracks.iter().enumerate() {
            let f = |n: &str| format!("cracks[{i}].{n}");
            if let Some(fr) = &c.fracture {
                positive(&f("fracture.radius"), fr.radius)?;
                let cells = self.grid.size.iter().zip(&self.grid.cell).map(|(s, h)| s / h).fold(0.0, f64::max);
                if fr.radius > cells {
                    return Err(invalid(f("fracture.radius"), format!("{} cells is more than the grid has ({cells} cells a side)", fr.radius)));
                }
                if !(2..=4096).contains(&fr.intervals) {
                    return Err(invalid(f("fracture.intervals"), format!("must be 2 to 4096, got {}", fr.intervals)));
                }
                positive(&f("fracture.cod_behind"), fr.cod_behind)?;
                if !(fr.cod_along >= 0.0 && fr.cod_along <= 64.0) {
                    return Err(invalid(f("fracture.cod_along"), format!("must be in [0, 64] cells (half-length along the front of the openings' average; 0: each node's own), got {}", fr.cod_along)));
                }
                if let Some(along) = fr.along {
                    positive(&f("fracture.along"), along)?;
                }
                if let Some(ramp) = fr.ramp {
                    positive(&f("fracture.ramp"), ramp)?;
                }
                if fr.split == FrontSplit::Interaction && fr.method != FrontMethod::Domain {
                    return Err(invalid(f("fracture.split"), "\"interaction\" is an integral over the domain: set method = \"domain\"".to_string()));
                }
                if fr.split == FrontSplit::Interaction && fr.growth.is_some() {
                    return Err(invalid(f("fracture.split"), "\"interaction\" is the static interaction integral (no inertia or crack-speed terms): a growing front splits by the opening".to_string()));
                }
                for (j, m) in fr.mirrors.iter().enumerate() {
                    let field = f(&format!("fracture.mirrors[{j}]"));
                    let Some(a) = m.axis_index() else {
                        return Err(invalid(format!("{field}.axis"), format!("must be \"x\", \"y\" or \"z\", got {:?}", m.axis)));
                    };
                    if fr.mirrors[..j].iter().any(|o| o.axis == m.axis) {
                        return Err(invalid(format!("{field}.axis"), format!("a second mirror plane normal to {}: at most one per axis", m.axis)));
                    }
                    let (lo, hi) = (self.grid.origin[a], self.grid.origin[a] + self.grid.size[a]);
                    if !(m.at >= lo && m.at <= hi) {
                        return Err(invalid(format!("{field}.at"), format!("{} is not in the grid's [{lo}, {hi}] along {}", m.at, m.axis)));
                    }
                    if fr.method != FrontMethod::Domain {
                        return Err(invalid(format!("{field}"), "mirror images complete the domain integral: set method = \"domain\"".to_string()));
                    }
                }
                if fr.method == FrontMethod::Domain && fr.domain_ramp() > fr.radius {
                    return Err(invalid(f("fracture.ramp"), format!("{} cells is more than the domain's radius ({} cells)", fr.domain_ramp(), fr.radius)));
                }
                if fr.method == FrontMethod::Contour && (fr.ramp.is_some() || fr.along.is_some()) {
                    return Err(invalid(f("fracture.method"), "`ramp` and `along` shape the domain integral: set method = \"domain\" or leave them out".to_string()));
                }
                if let Some(gr) = &fr.growth {
                    gr.validate(&f("fracture.growth"), self.materials.iter().any(|m| m.toughness.is_some()))?;
                    if gr.release.is_some() {
                        return Err(invalid(f("fracture.growth.release"), "the gradual release of new segments is 2D only (a 3D front releases its triangles at once)"));
                    }
                    if gr.cohesive.is_some() {
                        return Err(invalid(f("fracture.growth.cohesive"), "cohesive new segments are 2D only (a 3D front releases its triangles at once)"));
                    }
                }
                if let FrontNodesSpec::Box { min, max } = &fr.nodes {
                    finite3(&f("fracture.nodes.box.min"), min)?;
                    finite3(&f("fracture.nodes.box.max"), max)?;
                    if (0..3).any(|a| min[a] > max[a]) {
                        return Err(invalid(f("fracture.nodes.box"), format!("min {min:?} exceeds max {max:?}")));
                    }
                }
            }
            if let crate::scene::ContactSpec::Friction { mu } = c.contact {
                if !(mu >= 0.0 && mu.is_finite()) {
                    return Err(invalid(f("contact.friction.mu"), format!("must be zero or positive, got {mu}")));
                }
            }
            positive(&f("v_sep"), c.v_sep)?;
            if !(c.v_contact >= c.v_sep && c.v_contact.is_finite()) {
                return Err(invalid(f("v_contact"), format!("must be finite and at least v_sep = {}, got {}", c.v_sep, c.v_contact)));
            }
            if let Some(e) = c.edge {
                positive(&f("edge"), e)?;
                if e < 1e-3 * self.grid.cell.iter().fold(f64::INFINITY, |a, &b| a.min(b)) {
                    return Err(invalid(f("edge"), format!("{e} is below a thousandth of a cell: the surface would have millions of triangles")));
                }
            }
            if self.solver.tip_zone != 0.0 {
                return Err(invalid("solver.tip_zone", "the crack-tip zone is 2D only (3D fronts use CRAMP's pairs)"));
            }
            if self.solver.crack_method != crate::crack::CrackMethod::VelocityFields {
                return Err(invalid("solver.crack_method", "3D cracks use CRAMP's velocity fields only"));
            }
            match &c.surface {
                CrackSurface::Polygon { points } => {
                    for (k, p) in points.iter().enumerate() {
                        finite3(&f(&format!("surface.polygon.points[{k}]")), p)?;
                    }
                }
                CrackSurface::Disc { center, normal, radius } => {
                    finite3(&f("surface.disc.center"), center)?;
                    finite3(&f("surface.disc.normal"), normal)?;
                    positive(&f("surface.disc.radius"), *radius)?;
                    if v3(*normal).norm() == 0.0 {
                        return Err(invalid(f("surface.disc.normal"), "must not be zero"));
                    }
                }
                CrackSurface::Ellipse { center, normal, axis, a, b } => {
                    finite3(&f("surface.ellipse.center"), center)?;
                    finite3(&f("surface.ellipse.normal"), normal)?;
                    finite3(&f("surface.ellipse.axis"), axis)?;
                    positive(&f("surface.ellipse.a"), *a)?;
                    positive(&f("surface.ellipse.b"), *b)?;
                    if v3(*normal).norm() == 0.0 {
                        return Err(invalid(f("surface.ellipse.normal"), "must not be zero"));
                    }
                }
                CrackSurface::Mesh { vertices, .. } => {
                    for (k, p) in vertices.iter().enumerate() {
                        finite3(&f(&format!("surface.mesh.vertices[{k}]")), p)?;
                    }
                }
                CrackSurface::Stl { .. } => {}
            }
            if c.clip_to_bodies && matches!(c.surface, CrackSurface::Mesh { .. } | CrackSurface::Stl { .. }) {
                return Err(invalid(f("clip_to_bodies"), "clips planar shapes (polygon, disc, ellipse) only; a mesh is used as given"));
            }
        }
        Ok(())
    }

    /// Mesh every crack surface and find its front: the boundary edges with material
    /// beyond them (the point half a cell past the edge's midpoint, in the triangle's plane,
    /// lies in a body). Errors name the crack: a mesh that is not consistently oriented, a
    /// crack point outside the grid, a clip that leaves nothing.
    pub fn crack_surfaces(&self, grid: &Grid3, meshes: &[Option<crate::stl::ClosedMesh>]) -> Result<Vec<crate::crack::three_d::Crack3>, SceneError> {
        use crate::crack::surface::{clip_to_box, ellipse_boundary, planar_polygon, TriangleSurface};
        let hmin = crate::dim::GridGeometry::min_h(grid);
        let (glo, ghi) = (grid.origin, crate::dim::GridGeometry::max_corner(grid));
        let (blo, bhi) = self.bodies.iter().enumerate().fold((Vector3::repeat(f64::INFINITY), Vector3::repeat(f64::NEG_INFINITY)), |(l, h), (k, b)| {
            let (a, c) = b.shape.bounds(meshes[k].as_ref());
            (l.inf(&a), h.sup(&c))
        });
        let mut out = Vec::new();
        for (i, c) in self.cracks.iter().enumerate() {
            let f = |n: &str| format!("cracks[{i}].{n}");
            let edge = c.edge.unwrap_or(0.5 * hmin);
            let clip = |poly: Vec<Vector3>, field: &str| -> Result<Vec<Vector3>, SceneError> {
                if !c.clip_to_bodies {
                    return Ok(poly);
                }
                let clipped = clip_to_box(&poly, blo, bhi);
                if clipped.len() < 3 {
                    return Err(invalid(f(field), "no part of it lies inside the bodies' bounding box (clip_to_bodies)"));
                }
                Ok(clipped)
            };
            let surface = match &c.surface {
                CrackSurface::Polygon { points } => {
                    let poly = clip(points.iter().map(|p| v3(*p)).collect(), "surface.polygon")?;
                    planar_polygon(&poly, edge).map_err(|e| invalid(f("surface.polygon"), e))?
                }
                CrackSurface::Disc { center, normal, radius } => {
                    let n = v3(*normal);
                    let axis = if n.x.abs() <= n.y.abs() && n.x.abs() <= n.z.abs() { Vector3::x() } else if n.y.abs() <= n.z.abs() { Vector3::y() } else { Vector3::z() };
                    let b = ellipse_boundary(v3(*center), n, axis, *radius, *radius, edge).map_err(|e| invalid(f("surface.disc"), e))?;
                    planar_polygon(&orient(clip(b, "surface.disc")?, n), edge).map_err(|e| invalid(f("surface.disc"), e))?
                }
                CrackSurface::Ellipse { center, normal, axis, a, b } => {
                    let n = v3(*normal);
                    let bnd = ellipse_boundary(v3(*center), n, v3(*axis), *a, *b, edge).map_err(|e| invalid(f("surface.ellipse"), e))?;
                    planar_polygon(&orient(clip(bnd, "surface.ellipse")?, n), edge).map_err(|e| invalid(f("surface.ellipse"), e))?
                }
                CrackSurface::Mesh { vertices, triangles } => {
                    let s = TriangleSurface::new(vertices.iter().map(|p| v3(*p)).collect(), triangles.clone()).map_err(|e| invalid(f("surface.mesh"), e))?;
                    s.check_crack().map_err(|e| invalid(f("surface.mesh"), e))?;
                    s
                }
                CrackSurface::Stl { file } => {
                    let path = match &self.base_dir {
                        Some(d) if Path::new(file).is_relative() => d.join(file),
                        _ => PathBuf::from(file),
                    };
                    let (v, t) = crate::stl::read_triangles(&path).map_err(|e| invalid(f("surface.stl.file"), format!("{}: {e}", path.display())))?;
                    let s = TriangleSurface::new(v, t).map_err(|e| invalid(f("surface.stl.file"), format!("{}: {e}", path.display())))?;
                    s.check_crack().map_err(|e| invalid(f("surface.stl.file"), format!("{}: {e}", path.display())))?;
                    s
                }
            };
            if let Some((k, v)) = surface.vertices.iter().enumerate().find(|(_, v)| (0..3).any(|a| v[a] < glo[a] || v[a] > ghi[a])) {
                return Err(invalid(f("surface"), format!("crack point {k} at ({}, {}, {}) lies outside the grid", v.x, v.y, v.z)));
            }
            // The front: boundary edges with material beyond them: the point half a cell
            // beyond the edge's midpoint, or the point a thousandth of a cell beyond it, lies
            // in a body. The second test keeps the last edge of a front that ends on a free
            // face: on an inclined crack (the corner crack of corner_crack_rod_3d.toml) the
            // in-plane outward direction of that short edge leaves the body through the
            // face within half a cell, and without it the front ended one edge short of
            // the face, leaving an uncracked strip along the face (a grid node on the face
            // then saw particles above, below and beside the crack: three velocity fields).
            // Mouth edges lying in a face or outside the bodies fail both tests.
            let inside = |x: &Vector3| self.bodies.iter().enumerate().any(|(k, b)| b.shape.contains(x, meshes[k].as_ref()));
            let front = surface
                .boundary_edges()
                .into_iter()
                .filter(|&(a, b, t)| {
                    let (pa, pb) = (surface.vertices[a as usize], surface.vertices[b as usize]);
                    let out = (pb - pa).cross(&surface.normal(t)).normalize();
                    let mid = (pa + pb) * 0.5;
                    inside(&(mid + out * (0.5 * hmin))) || inside(&(mid + out * (1e-3 * hmin)))
                })
                .map(|(a, b, _)| [a, b])
                .collect();
            let mut crack = crate::crack::three_d::Crack3::new(surface, c.contact.law(), c.v_sep, c.v_contact, front);
            crack.detection = c.detection;
            out.push(crack);
        }
        Ok(out)
    }

    /// Per crack, the J/K request of its `fracture` table (None: not computed), with the
    /// front nodes resolved on the built cracks: the vertices of the front edges that lie
    /// in a body (within 1e−6 of a cell of one: nodes on a body's face count) and in the
    /// table's box. An error names the table when it selects no front node.
    pub fn front_requests(&self, cracks: &[crate::crack::three_d::Crack3]) -> Result<Vec<Option<crate::fracture::front3::FrontRequest>>, SceneError> {
        let h = self.grid.cell.iter().fold(f64::INFINITY, |a, &b| a.min(b));
        let mut meshes = None;
        let mut out = Vec::with_capacity(self.cracks.len());
        for (i, (spec, crack)) in self.cracks.iter().zip(cracks).enumerate() {
            let Some(fr) = &spec.fracture else {
                out.push(None);
                continue;
            };
            if meshes.is_none() {
                meshes = Some(self.load_meshes()?);
            }
            let meshes = meshes.as_ref().expect("loaded");
            let inside = |x: &Vector3| {
                let hair = 1e-6 * h;
                std::iter::once(*x).chain((0..6).map(|k| { let mut y = *x; y[k / 2] += if k % 2 == 0 { hair } else { -hair }; y })).any(|y| self.bodies.iter().enumerate().any(|(k, b)| b.shape.contains(&y, meshes[k].as_ref())))
            };
            let in_box = |x: &Vector3| match &fr.nodes {
                FrontNodesSpec::All => true,
                FrontNodesSpec::Box { min, max } => (0..3).all(|a| x[a] >= min[a] && x[a] <= max[a]),
            };
            let mut nodes: Vec<u32> = crack.front.iter().flatten().copied().filter(|&v| {
                let x = crack.surface.vertices[v as usize];
                inside(&x) && in_box(&x)
            }).collect();
            nodes.sort_unstable();
            nodes.dedup();
            if nodes.is_empty() {
                return Err(invalid(format!("cracks[{i}].fracture.nodes"), format!("selects no front node (the crack has {} front edges)", crack.front.len())));
            }
            let domain = (fr.method == FrontMethod::Domain).then(|| crate::fracture::front3::DomainShape { inner: (fr.radius - fr.domain_ramp()) * h, outer: fr.radius * h, along: fr.domain_along() * h });
            out.push(Some(crate::fracture::front3::FrontRequest { nodes, radius: fr.radius * h, intervals: fr.intervals, volume_term: fr.volume_term, cod_behind: fr.cod_behind * h, cod_along: fr.cod_along * h, tangents: Default::default(), normals: Default::default(), domain, interaction: fr.split == FrontSplit::Interaction, mirrors: fr.mirrors.iter().filter_map(|m| m.axis_index().map(|a| (a, m.at))).collect() }));
        }
        Ok(out)
    }

    /// Read every STL body's surface (None for the other solids).
    fn load_meshes(&self) -> Result<Vec<Option<crate::stl::ClosedMesh>>, SceneError> {
        self.bodies
            .iter()
            .enumerate()
            .map(|(k, b)| match &b.shape {
                Solid::Stl { file } => {
                    let path = match &self.base_dir {
                        Some(d) if Path::new(file).is_relative() => d.join(file),
                        _ => PathBuf::from(file),
                    };
                    crate::stl::ClosedMesh::read(&path).map(Some).map_err(|e| invalid(format!("bodies[{k}].shape.stl.file"), format!("{}: {e}", path.display())))
                }
                _ => Ok(None),
            })
            .collect()
    }
}

/// A scene file of either dimension.
#[derive(Clone, Debug)]
pub enum AnyScene {
    D2(crate::scene::Scene),
    D3(Scene3),
}

impl AnyScene {
    /// Read a scene file, deciding its dimension from `grid.cell`.
    pub fn from_file(path: &Path) -> Result<AnyScene, SceneError> {
        let text = std::fs::read_to_string(path).map_err(|e| SceneError::Io { path: path.display().to_string(), source: e })?;
        AnyScene::from_toml(&text, &path.display().to_string(), path.parent())
    }

    pub fn from_toml(text: &str, origin: &str, base_dir: Option<&Path>) -> Result<AnyScene, SceneError> {
        let value: toml::Value = toml::from_str(text).map_err(|e| SceneError::Parse { path: origin.to_string(), message: e.to_string() })?;
        match detect_dimension(&value).map_err(|m| SceneError::Parse { path: origin.to_string(), message: m })? {
            3 => Ok(AnyScene::D3(Scene3::from_toml(text, origin, base_dir)?)),
            _ => {
                check_vector_lengths(&value, 2)?;
                Ok(AnyScene::D2(crate::scene::Scene::from_toml(text, origin)?))
            }
        }
    }
}

