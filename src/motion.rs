//! Boundary motion and loads that vary in space and time (2D and 3D scenes).
//!
//! * `[[boundary]]` components `vx vy vz` (nodal velocity) and `ux uy uz` (nodal
//!   displacement) are a number or an expression of x, y, (z,) t ([`crate::expr`]);
//!   `williams` prescribes the displacement of the Williams crack-tip field (K_I, K_II,
//!   T-stress; [`williams_displacement`]); an optional `time` function ([`TimeSpec`]:
//!   ramp and hold, a table of (t, value), an expression of t) multiplies them.
//! * `[[loads]]` take a `traction` (force per unit area of the surface: in 2D the edge
//!   length × the body's thickness) instead of a total `force`, distributed by each
//!   particle's share of the boundary ([`face_share`]), and a `time` function.
//!
//! The MPM applies a prescribed nodal **velocity** v(x, t) at the middle of each step,
//! v(x_i, t + Δt/2), and a prescribed **displacement** u(x, t) as the velocity that moves
//! the node by the increment of u over the step, (u(x_i, t + Δt) − u(x_i, t))/Δt: the
//! nodes then move by u(x_i, t) − u(x_i, 0) exactly (a displacement that does not change
//! in time moves nothing). The static FEA (`cramp fea`) prescribes the displacement the
//! MPM's nodes have at the end of the run ([`BoundaryMotion::displacement_at`]).
//!
//! Cost: constant velocities keep the plain fixed-velocity path (no work per step, the
//! same bits as before). Otherwise each prescription is split once, when the scene is
//! built, into a spatial factor per node (constants, expressions without t, the Williams
//! field) and a time factor per step; only an expression that uses both position and t
//! is evaluated per node per step, as a precompiled `f64` program. A scene without such
//! prescriptions does no work for them at all.

use crate::expr::{Expr, T};
use crate::material::{LinearElastic, PlaneState};
use serde::{Deserialize, Serialize};

/// A prescribed component or traction component: a number, or an expression string.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(untagged)]
pub enum Component {
    Number(f64),
    Expr(String),
}

/// `time = { ramp = T }`: f = t/T for t < T, then 1 (ramp and hold).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct RampSpec {
    pub ramp: f64,
}

/// `time = { table = [[t0, f0], [t1, f1], …] }`: piecewise linear in t, held constant
/// before the first and after the last point.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct TableSpec {
    pub table: Vec<[f64; 2]>,
}

/// A time function f(t) multiplying a prescription or a load.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(untagged)]
pub enum TimeSpec {
    Ramp(RampSpec),
    Table(TableSpec),
    /// An expression of t alone.
    Expr(String),
}

/// `williams = { k1, k2, t_stress, tip, angle, material }`: the displacement of the
/// Williams crack-tip field (Anderson 2005, Table 2.2; T-stress term of Williams 1957).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct WilliamsSpec {
    /// K_I (stress × √length).
    pub k1: f64,
    /// K_II (default 0).
    #[serde(default)]
    pub k2: f64,
    /// T-stress, the uniform stress parallel to the crack (default 0).
    #[serde(default)]
    pub t_stress: f64,
    /// Crack tip (a 3D scene's field is the plane-strain one of a straight front parallel
    /// to z: the tip's z is not used).
    pub tip: Vec<f64>,
    /// Direction in which the crack would extend, degrees counter-clockwise from +x
    /// (default 0: the crack lies along −x from the tip).
    #[serde(default)]
    pub angle: f64,
    /// Material giving E and ν (and in 2D the plane state); default the scene's only material.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub material: Option<String>,
}

/// Compiled time function.
#[derive(Clone, Debug, PartialEq)]
pub enum TimeFn {
    One,
    Ramp(f64),
    Table(Vec<[f64; 2]>),
    Expr(Expr),
}

impl TimeFn {
    /// Compile a `time` field (`field` names it in errors): ramp ≥ 0 and finite, a table of
    /// at least one finite point with strictly increasing times, an expression of t only.
    pub fn new(field: &str, spec: Option<&TimeSpec>) -> Result<TimeFn, (String, String)> {
        let err = |f: &str, m: String| (f.to_string(), m);
        let f = match spec {
            None => return Ok(TimeFn::One),
            Some(TimeSpec::Ramp(r)) => {
                if !(r.ramp.is_finite() && r.ramp >= 0.0) {
                    return Err(err(&format!("{field}.ramp"), format!("must be zero or positive (and finite), got {}", r.ramp)));
                }
                TimeFn::Ramp(r.ramp)
            }
            Some(TimeSpec::Table(tb)) => {
                if tb.table.is_empty() {
                    return Err(err(&format!("{field}.table"), "needs at least one point [t, value]".into()));
                }
                for (k, p) in tb.table.iter().enumerate() {
                    if !(p[0].is_finite() && p[1].is_finite()) {
                        return Err(err(&format!("{field}.table[{k}]"), format!("must be finite, got {p:?}")));
                    }
                    if k > 0 && p[0] <= tb.table[k - 1][0] {
                        return Err(err(&format!("{field}.table[{k}]"), format!("time {} does not increase past {}", p[0], tb.table[k - 1][0])));
                    }
                }
                TimeFn::Table(tb.table.clone())
            }
            Some(TimeSpec::Expr(text)) => TimeFn::Expr(Expr::parse(text, &[T]).map_err(|m| err(field, m))?),
        };
        let v0 = f.at(0.0);
        if !v0.is_finite() {
            return Err(err(field, format!("is {v0} at t = 0 (must be a finite number)")));
        }
        Ok(f)
    }

    /// f(t).
    #[inline]
    pub fn at(&self, t: f64) -> f64 {
        match self {
            TimeFn::One => 1.0,
            TimeFn::Ramp(r) => {
                if *r > 0.0 && t < *r {
                    t / r
                } else {
                    1.0
                }
            }
            TimeFn::Table(pts) => {
                let k = pts.partition_point(|p| p[0] <= t);
                if k == 0 {
                    pts[0][1]
                } else if k == pts.len() {
                    pts[k - 1][1]
                } else {
                    let (a, b) = (pts[k - 1], pts[k]);
                    a[1] + (b[1] - a[1]) * ((t - a[0]) / (b[0] - a[0]))
                }
            }
            TimeFn::Expr(e) => e.eval(&[0.0, 0.0, 0.0, t]),
        }
    }
}

/// A compiled component: a constant or an expression of position and time.
#[derive(Clone, Debug, PartialEq)]
pub enum ComponentFn {
    Const(f64),
    Expr(Expr),
}

impl ComponentFn {
    /// Compile a component of a `dim`-D scene (variables x, y, t; or x, y, z, t).
    pub fn new(field: &str, c: &Component, dim: usize) -> Result<ComponentFn, (String, String)> {
        match c {
            Component::Number(v) => {
                if !v.is_finite() {
                    return Err((field.to_string(), format!("must be a finite number, got {v}")));
                }
                Ok(ComponentFn::Const(*v))
            }
            Component::Expr(text) => {
                let allowed: &[usize] = if dim == 3 { &[0, 1, 2, T] } else { &[0, 1, T] };
                Expr::parse(text, allowed).map(ComponentFn::Expr).map_err(|m| (field.to_string(), m))
            }
        }
    }

    /// The value at position and time `v` = [x, y, z, t].
    #[inline]
    pub fn at(&self, v: &[f64; 4]) -> f64 {
        match self {
            ComponentFn::Const(c) => *c,
            ComponentFn::Expr(e) => e.eval(v),
        }
    }

    /// Whether it changes with time.
    pub fn uses_t(&self) -> bool {
        matches!(self, ComponentFn::Expr(e) if e.uses(T))
    }
}

/// [x, y, z, t] from a point's components.
#[inline]
pub fn point(x: &[f64], t: f64) -> [f64; 4] {
    let mut v = [0.0, 0.0, 0.0, t];
    v[..x.len()].copy_from_slice(x);
    v
}

/// [x, y, z, t] from a vector of the scene's dimension.
#[inline]
pub fn vector_point<V: crate::dim::VectorOps>(x: &V, t: f64) -> [f64; 4] {
    let mut v = [0.0, 0.0, 0.0, t];
    for (c, slot) in v.iter_mut().enumerate().take(V::DIM) {
        *slot = x[c];
    }
    v
}

/// Williams displacement at point `x` (2 or 3 components; z unused): the K_I and K_II
/// near-tip terms (Anderson 2005 Table 2.2) and the T-stress term
/// u = T r/(8μ) ((κ+1) cos θ, (κ−3) sin θ) (the uniform σ_xx' = T), in the crack's frame
/// (x' along `angle`, θ from x', the faces at θ = ±π), rotated back to x, y.
pub fn williams_displacement(w: &WilliamsSpec, mat: &LinearElastic, x: &[f64]) -> [f64; 2] {
    let (mu, kappa) = (mat.shear_modulus(), mat.kappa());
    let (s, c) = w.angle.to_radians().sin_cos();
    let (dx, dy) = (x[0] - w.tip[0], x[1] - w.tip[1]);
    let (xl, yl) = (c * dx + s * dy, -s * dx + c * dy);
    let (r, theta) = (xl.hypot(yl), yl.atan2(xl));
    let u1 = crate::fracture::williams::williams_displacement(1, r, theta, mu, kappa);
    let u2 = crate::fracture::williams::williams_displacement(2, r, theta, mu, kappa);
    let (ct, st) = (theta.cos(), theta.sin());
    let tt = w.t_stress * r / (8.0 * mu);
    let ul = [w.k1 * u1.x + w.k2 * u2.x + tt * (kappa + 1.0) * ct, w.k1 * u1.y + w.k2 * u2.y + tt * (kappa - 3.0) * st];
    [c * ul[0] - s * ul[1], s * ul[0] + c * ul[1]]
}

/// The material of a `williams` field: named, or the scene's only one. A 3D scene's
/// field is plane strain.
pub fn williams_material(field: &str, w: &WilliamsSpec, names: &[&str], mats: &[LinearElastic], dim: usize) -> Result<LinearElastic, (String, String)> {
    let k = match &w.material {
        Some(name) => names.iter().position(|n| n == name).ok_or_else(|| (format!("{field}.material"), format!("no material named '{name}'")))?,
        None if names.len() == 1 => 0,
        None => return Err((format!("{field}.material"), format!("the scene has {} materials: name the one whose E and ν the field uses", names.len()))),
    };
    let mut m = mats[k];
    if dim == 3 {
        m.state = PlaneState::PlaneStrain;
    }
    Ok(m)
}

/// Checks of a `williams` table that need no material: finite K, T, angle; a tip of the
/// scene's dimension.
pub fn validate_williams(field: &str, w: &WilliamsSpec, dim: usize) -> Result<(), (String, String)> {
    for (k, v) in [("k1", w.k1), ("k2", w.k2), ("t_stress", w.t_stress), ("angle", w.angle)] {
        if !v.is_finite() {
            return Err((format!("{field}.{k}"), format!("must be a finite number, got {v}")));
        }
    }
    if w.tip.len() != dim {
        return Err((format!("{field}.tip"), format!("has {} components; this is a {dim}D scene", w.tip.len())));
    }
    if let Some(c) = w.tip.iter().position(|v| !v.is_finite()) {
        return Err((format!("{field}.tip[{c}]"), format!("must be a finite number, got {}", w.tip[c])));
    }
    Ok(())
}

/// What a `[[boundary]]` prescribes in one direction.
#[derive(Clone, Debug, PartialEq)]
pub enum Prescribed {
    /// Velocity v(x, t) = component(x, t) · f(t).
    Velocity(ComponentFn),
    /// Displacement u(x, t) = component(x, t) · f(t).
    Displacement(ComponentFn),
    /// Displacement of the Williams field (component c) · f(t).
    Williams(Box<(WilliamsSpec, LinearElastic)>),
}

/// One `[[boundary]]` compiled: per direction what it prescribes, and its time function.
#[derive(Clone, Debug, PartialEq)]
pub struct BoundaryFn {
    pub comps: Vec<Option<Prescribed>>,
    pub time: TimeFn,
}

/// The raw fields of one `[[boundary]]` (2D or 3D), for [`BoundaryFn::new`].
pub struct BoundaryFields<'a> {
    /// "boundary[i]".
    pub field: String,
    /// vx, vy(, vz).
    pub velocity: Vec<Option<&'a Component>>,
    /// ux, uy(, uz).
    pub displacement: Vec<Option<&'a Component>>,
    pub time: Option<&'a TimeSpec>,
    pub williams: Option<&'a WilliamsSpec>,
}

const AXES: [&str; 3] = ["x", "y", "z"];

impl BoundaryFn {
    /// Compile and check one `[[boundary]]`: at least one component, no direction given
    /// twice (a velocity and a displacement, or a displacement and `williams`), valid
    /// expressions and time function. `williams_mat` is the material of its `williams`.
    pub fn new(b: &BoundaryFields, dim: usize, williams_mat: Option<LinearElastic>) -> Result<BoundaryFn, (String, String)> {
        let f = &b.field;
        let mut comps: Vec<Option<Prescribed>> = vec![None; dim];
        for c in 0..dim {
            if let Some(v) = b.velocity[c] {
                comps[c] = Some(Prescribed::Velocity(ComponentFn::new(&format!("{f}.v{}", AXES[c]), v, dim)?));
            }
            if let Some(u) = b.displacement[c] {
                if comps[c].is_some() {
                    return Err((format!("{f}.u{}", AXES[c]), format!("prescribes the {} direction already given by v{}: give a velocity or a displacement", AXES[c], AXES[c])));
                }
                comps[c] = Some(Prescribed::Displacement(ComponentFn::new(&format!("{f}.u{}", AXES[c]), u, dim)?));
            }
        }
        if let Some(w) = b.williams {
            validate_williams(&format!("{f}.williams"), w, dim)?;
            let mat = williams_mat.ok_or_else(|| (format!("{f}.williams"), "no material".to_string()))?;
            for (c, slot) in comps.iter_mut().enumerate().take(2) {
                if slot.is_some() {
                    return Err((format!("{f}.williams"), format!("prescribes u{} (in-plane displacement), already given by v{0} or u{0}", AXES[c])));
                }
                *slot = Some(Prescribed::Williams(Box::new((w.clone(), mat))));
            }
        }
        if comps.iter().all(Option::is_none) {
            let names = if dim == 3 { "vx, vy, vz, ux, uy, uz or williams" } else { "vx, vy, ux, uy or williams" };
            return Err((f.clone(), format!("fixes nothing: give {names}")));
        }
        let time = TimeFn::new(&format!("{f}.time"), b.time)?;
        Ok(BoundaryFn { comps, time })
    }

    /// The fixed velocity of direction c if it is a constant in time (the plain
    /// fixed-velocity condition, with no per-step work); None if it varies or is absent.
    pub fn constant_velocity(&self, c: usize) -> Option<f64> {
        match (&self.comps[c], &self.time) {
            (Some(Prescribed::Velocity(ComponentFn::Const(v))), TimeFn::One) => Some(*v),
            _ => None,
        }
    }

    /// Warnings: a displacement that does not change in time moves nothing.
    pub fn warnings(&self, field: &str) -> Vec<String> {
        let mut out = Vec::new();
        for (c, p) in self.comps.iter().enumerate() {
            let still = match p {
                Some(Prescribed::Displacement(f)) => !f.uses_t() && self.time == TimeFn::One,
                Some(Prescribed::Williams(_)) => self.time == TimeFn::One && c == 0,
                _ => false,
            };
            if still {
                let what = if matches!(p, Some(Prescribed::Williams(_))) { "williams".to_string() } else { format!("u{}", AXES[c]) };
                out.push(format!(
                    "{field}.{what} does not change in time: the nodes move by u(x, t) − u(x, 0) = 0 and are held where they are; \
                     give a `time` function (e.g. time = {{ ramp = … }}) to apply it"
                ));
            }
        }
        out
    }
}

/// One node component whose prescribed velocity changes in time.
#[derive(Clone, Debug, PartialEq)]
pub struct MotionEntry {
    pub node: u32,
    pub comp: u8,
    /// Index into [`BoundaryMotion::sources`].
    pub source: u16,
    /// Spatial factor (the component at the node, t = 0; the Williams displacement);
    /// unused when the source's expression uses position and time.
    pub value: f64,
    /// Node position (for expressions of position and time).
    pub x: [f64; 4],
}

/// One prescription of one direction of one `[[boundary]]`.
#[derive(Clone, Debug, PartialEq)]
pub struct MotionSource {
    pub displacement: bool,
    pub time: TimeFn,
    /// An expression of t: its value multiplies the spatial factors (`per_node` false),
    /// or, if it uses position too, it is evaluated at every node (`per_node` true).
    pub temporal: Option<Expr>,
    pub per_node: bool,
}

impl MotionSource {
    /// g(t) = f(t) × the expression of t alone (1 without).
    #[inline]
    fn factor(&self, t: f64) -> f64 {
        let e = match &self.temporal {
            Some(e) if !self.per_node => e.eval(&[0.0, 0.0, 0.0, t]),
            _ => 1.0,
        };
        self.time.at(t) * e
    }

    /// Prescribed value (velocity or displacement) at node position x (with t set).
    #[inline]
    fn value(&self, entry: &MotionEntry, t: f64) -> f64 {
        if self.per_node {
            let mut v = entry.x;
            v[T] = t;
            self.temporal.as_ref().map_or(0.0, |e| e.eval(&v)) * self.time.at(t)
        } else {
            entry.value * self.factor(t)
        }
    }

    /// The velocity over the step from t to t + dt.
    #[inline]
    fn velocity(&self, entry: &MotionEntry, t: f64, dt: f64) -> f64 {
        if self.displacement {
            (self.value(entry, t + dt) - self.value(entry, t)) / dt
        } else {
            self.value(entry, t + 0.5 * dt)
        }
    }
}

/// The node components whose prescribed velocity changes in time (see the module doc),
/// sorted by node and component.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct BoundaryMotion {
    pub sources: Vec<MotionSource>,
    pub entries: Vec<MotionEntry>,
}

impl BoundaryMotion {
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// The source for direction c of a compiled boundary (None for a constant velocity or
    /// no prescription).
    pub fn source_of(b: &BoundaryFn, c: usize) -> Option<MotionSource> {
        let p = b.comps[c].as_ref()?;
        if b.constant_velocity(c).is_some() {
            return None;
        }
        let (displacement, f) = match p {
            Prescribed::Velocity(f) => (false, Some(f)),
            Prescribed::Displacement(f) => (true, Some(f)),
            Prescribed::Williams(_) => (true, None),
        };
        let temporal = match f {
            Some(ComponentFn::Expr(e)) if e.uses(T) => Some(e.clone()),
            _ => None,
        };
        let per_node = temporal.as_ref().is_some_and(Expr::uses_position);
        Some(MotionSource { displacement, time: b.time.clone(), temporal, per_node })
    }

    /// The spatial factor of direction c of `b` at node position `x` (2 or 3 components).
    pub fn spatial(b: &BoundaryFn, c: usize, x: &[f64]) -> f64 {
        match &b.comps[c] {
            Some(Prescribed::Velocity(f)) | Some(Prescribed::Displacement(f)) => {
                if f.uses_t() {
                    1.0
                } else {
                    f.at(&point(x, 0.0))
                }
            }
            Some(Prescribed::Williams(w)) => williams_displacement(&w.0, &w.1, x)[c],
            None => 0.0,
        }
    }

    /// Write the velocity of every entry for the step from t to t + dt into `vel`.
    pub fn update<V: crate::dim::VectorOps>(&self, t: f64, dt: f64, vel: &mut [V]) {
        for e in &self.entries {
            vel[e.node as usize][e.comp as usize] = self.sources[e.source as usize].velocity(e, t, dt);
        }
    }

    /// The displacement of every entry after `steps` steps of `dt` from t = 0, as the
    /// MPM's nodes move: u(t_N) − u(0) for a displacement, Σ v(t_n + Δt/2) Δt for a
    /// velocity (the FEA's prescribed displacements).
    pub fn displacement_at(&self, steps: u64, dt: f64) -> Vec<f64> {
        let t_end = steps as f64 * dt;
        // Σ factor(t_n + Δt/2) per source whose entries share it.
        let sums: Vec<f64> = self
            .sources
            .iter()
            .map(|s| if s.displacement || s.per_node { 0.0 } else { (0..steps).map(|n| s.factor((n as f64 + 0.5) * dt)).sum::<f64>() * dt })
            .collect();
        self.entries
            .iter()
            .map(|e| {
                let s = &self.sources[e.source as usize];
                if s.displacement {
                    s.value(e, t_end) - s.value(e, 0.0)
                } else if s.per_node {
                    (0..steps).map(|n| s.value(e, (n as f64 + 0.5) * dt)).sum::<f64>() * dt
                } else {
                    e.value * sums[e.source as usize]
                }
            })
            .collect()
    }
}

/// Resolves the scene's `[[boundary]]` onto nodes in order: a later condition overrides
/// an earlier one on the same node and direction, as for constant velocities.
#[derive(Default)]
pub struct MotionBuilder {
    sources: Vec<MotionSource>,
    /// (boundary index, direction) → source.
    source_of: std::collections::HashMap<(usize, usize), u16>,
    entries: std::collections::BTreeMap<(u32, u8), MotionEntry>,
}

impl MotionBuilder {
    /// Apply boundary `bi` (compiled `b`, field name `field` = "boundary[i]") to node
    /// `node` at position `x`: constant velocities go to `bcs` as before, the rest
    /// become motion entries. A prescription that is not finite at t = 0 at the node is
    /// an error naming the field and the node.
    pub fn add<V: crate::dim::VectorOps>(&mut self, bcs: &mut crate::simulation::NodeBcs<V>, bi: usize, field: &str, b: &BoundaryFn, node: usize, x: &[f64]) -> Result<(), (String, String)> {
        for c in 0..b.comps.len() {
            let Some(p) = &b.comps[c] else { continue };
            let key = (node as u32, c as u8);
            if let Some(v) = b.constant_velocity(c) {
                bcs.fix(node, c, v);
                self.entries.remove(&key);
                continue;
            }
            let Some(source) = BoundaryMotion::source_of(b, c) else { continue };
            let value = BoundaryMotion::spatial(b, c, x);
            let entry = MotionEntry { node: node as u32, comp: c as u8, source: 0, value, x: point(x, 0.0) };
            let at0 = source.value(&entry, 0.0);
            if !at0.is_finite() {
                let name = match p {
                    Prescribed::Velocity(_) => format!("v{}", AXES[c]),
                    Prescribed::Displacement(_) => format!("u{}", AXES[c]),
                    Prescribed::Williams(_) => "williams".to_string(),
                };
                return Err((format!("{field}.{name}"), format!("is {at0} at t = 0 at the node at {x:?} (must be a finite number)")));
            }
            let n = self.sources.len();
            let s = *self.source_of.entry((bi, c)).or_insert_with(|| n as u16);
            if s as usize == n {
                self.sources.push(source);
            }
            bcs.fix(node, c, 0.0);
            self.entries.insert(key, MotionEntry { source: s, ..entry });
        }
        Ok(())
    }

    /// The motion, into `bcs`.
    pub fn finish<V: crate::dim::VectorOps>(self, bcs: &mut crate::simulation::NodeBcs<V>) {
        bcs.motion = BoundaryMotion { sources: self.sources, entries: self.entries.into_values().collect() };
    }
}

/// The boundary measure a particle stands for on a face of outward normal `n` (unit):
/// the projection of its domain (half-widths `lp`) onto the face, Σ_c |n_c| × the
/// domain's extent across c (2D: |n_x|·2l_y + |n_y|·2l_x; 3D: |n_x|·4l_y l_z + …). The
/// domains of a regular fill tile the body, so on a flat grid-aligned face the shares
/// add up to the face's length (area).
pub fn face_share(lp: &[f64], n: &[f64]) -> f64 {
    let d = lp.len();
    (0..d)
        .map(|c| {
            let across: f64 = (0..d).filter(|&k| k != c).map(|k| 2.0 * lp[k]).product();
            n[c].abs() * across
        })
        .sum()
}

/// Check one `[[loads]]` (`field` = "loads[i]") beyond its selection: exactly one of
/// `force` and `traction`, finite numbers, not both `ramp` and `time`, a valid time
/// function and traction components; for a traction, the outward normal: `normal` if
/// given, else the one the selection implies (`implied`: a 2D line's perpendicular, a 3D
/// plane's normal). Returns the unit normal of a traction.
#[allow(clippy::too_many_arguments)]
pub fn validate_load(
    field: &str,
    force: Option<&[f64]>,
    traction: Option<&[Component]>,
    normal: Option<&[f64]>,
    ramp: f64,
    time: Option<&TimeSpec>,
    implied: Option<Vec<f64>>,
    dim: usize,
) -> Result<Option<Vec<f64>>, (String, String)> {
    let err = |f: String, m: String| Err((f, m));
    if !(ramp.is_finite() && ramp >= 0.0) {
        return err(format!("{field}.ramp"), format!("must be zero or positive (and finite), got {ramp}"));
    }
    if ramp > 0.0 && time.is_some() {
        return err(format!("{field}.time"), "give either `ramp` or `time` (time = { ramp = … } is the same ramp)".into());
    }
    TimeFn::new(&format!("{field}.time"), time)?;
    match (force, traction) {
        (Some(_), Some(_)) => return err(format!("{field}.traction"), "give either a total `force` or a `traction`, not both".into()),
        (None, None) => return err(format!("{field}.force"), "missing: give a total `force` or a `traction`".into()),
        (Some(f), None) => {
            if let Some(c) = f.iter().position(|v| !v.is_finite()) {
                return err(format!("{field}.force[{c}]"), format!("must be a finite number, got {}", f[c]));
            }
            if normal.is_some() {
                return err(format!("{field}.normal"), "is used by a `traction` only".into());
            }
            return Ok(None);
        }
        (None, Some(t)) => {
            for (c, comp) in t.iter().enumerate() {
                ComponentFn::new(&format!("{field}.traction[{c}]"), comp, dim)?;
            }
        }
    }
    let n = match (normal, implied) {
        (Some(n), _) => {
            if let Some(c) = n.iter().position(|v| !v.is_finite()) {
                return err(format!("{field}.normal[{c}]"), format!("must be a finite number, got {}", n[c]));
            }
            n.to_vec()
        }
        (None, Some(n)) => n,
        (None, None) => {
            let sel = if dim == 3 { "`box` or `line`" } else { "`region`" };
            return err(format!("{field}.normal"), format!("missing: a traction on a {sel} selection needs the boundary's outward normal"));
        }
    };
    let len = n.iter().map(|v| v * v).sum::<f64>().sqrt();
    if !(len > 0.0) {
        return err(format!("{field}.normal"), format!("must be a non-zero vector, got {n:?}"));
    }
    Ok(Some(n.iter().map(|v| v / len).collect()))
}

/// A `[[loads]]` whose force changes with time or from particle to particle.
#[derive(Clone, Debug, PartialEq)]
pub struct LoadVariation<V> {
    pub time: TimeFn,
    /// Traction loads: per particle id, its boundary share × thickness (0 for others);
    /// empty for a total `force`.
    pub share: Vec<f64>,
    /// Traction loads: per particle id, the force at time factor 1 from the components
    /// that do not change in time.
    pub fixed: Vec<V>,
    /// Traction components that change in time (component, expression).
    pub temporal: Vec<(usize, Expr)>,
}

/// One selected particle of a traction load.
pub struct LoadedParticle<V> {
    pub id: u32,
    pub x0: V,
    pub lp: V,
    /// The body's thickness (2D), 1 in 3D.
    pub thickness: f64,
}

impl<V: crate::dim::VectorOps> LoadVariation<V> {
    /// Compile `loads[i]` (`field`): its time function, and for a traction (`traction`,
    /// outward normal `normal`, unit) each particle's share and the force of the
    /// components that do not change in time. `n_ids` is the number of particles. None if
    /// the load is a plain uniform force (no time function, no traction).
    pub fn new(
        field: &str,
        time: Option<&TimeSpec>,
        traction: Option<&[Component]>,
        normal: &[f64],
        particles: &[LoadedParticle<V>],
        n_ids: usize,
    ) -> Result<Option<LoadVariation<V>>, (String, String)> {
        let time_fn = TimeFn::new(&format!("{field}.time"), time)?;
        let Some(traction) = traction else {
            return Ok((time_fn != TimeFn::One).then_some(LoadVariation { time: time_fn, share: Vec::new(), fixed: Vec::new(), temporal: Vec::new() }));
        };
        let comps = traction.iter().enumerate().map(|(c, t)| ComponentFn::new(&format!("{field}.traction[{c}]"), t, V::DIM)).collect::<Result<Vec<_>, _>>()?;
        let mut share = vec![0.0; n_ids];
        let mut fixed = vec![V::zeros(); n_ids];
        for p in particles {
            let lp: Vec<f64> = (0..V::DIM).map(|c| p.lp[c]).collect();
            let a = face_share(&lp, normal) * p.thickness;
            share[p.id as usize] = a;
            let x = vector_point(&p.x0, 0.0);
            for (c, f) in comps.iter().enumerate() {
                let v = f.at(&x);
                if !v.is_finite() {
                    return Err((format!("{field}.traction[{c}]"), format!("is {v} at t = 0 at the particle at {:?} (must be a finite number)", &x[..V::DIM])));
                }
                if !f.uses_t() {
                    fixed[p.id as usize][c] = v * a;
                }
            }
        }
        let temporal = comps
            .into_iter()
            .enumerate()
            .filter_map(|(c, f)| match f {
                ComponentFn::Expr(e) if e.uses(T) => Some((c, e)),
                _ => None,
            })
            .collect();
        Ok(Some(LoadVariation { time: time_fn, share, fixed, temporal }))
    }

    /// The traction at the initial position `x0` and time t (force per unit area), for
    /// the FEA's consistent loads: f(t) × the components.
    pub fn traction_at(traction: &[ComponentFn], time: &TimeFn, x: &[f64], t: f64) -> Vec<f64> {
        let v = point(x, t);
        traction.iter().map(|f| f.at(&v) * time.at(t)).collect()
    }

    /// The force on particle `id` (initial position `x0`) at time t; `uniform` is the
    /// load's force per particle (for a total `force`).
    #[inline]
    pub fn force(&self, uniform: V, t: f64, id: usize, x0: &V) -> V {
        let f = if self.share.is_empty() {
            uniform
        } else {
            let mut f = self.fixed[id];
            if !self.temporal.is_empty() {
                let v = vector_point(x0, t);
                for (c, e) in &self.temporal {
                    f[*c] += e.eval(&v) * self.share[id];
                }
            }
            f
        };
        f * self.time.at(t)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn time_functions() {
        let ramp = TimeFn::new("f", Some(&TimeSpec::Ramp(RampSpec { ramp: 2.0 }))).unwrap();
        assert_eq!((ramp.at(0.0), ramp.at(1.0), ramp.at(2.0), ramp.at(5.0)), (0.0, 0.5, 1.0, 1.0));
        let table = TimeFn::new("f", Some(&TimeSpec::Table(TableSpec { table: vec![[0.0, 0.0], [1.0, 2.0], [3.0, 2.0], [4.0, 0.0]] }))).unwrap();
        assert_eq!((table.at(-1.0), table.at(0.5), table.at(2.0), table.at(3.5), table.at(9.0)), (0.0, 1.0, 2.0, 1.0, 0.0));
        let e = TimeFn::new("f", Some(&TimeSpec::Expr("1 - exp(-t)".into()))).unwrap();
        assert_eq!(e.at(1.0), 1.0 - (-1.0f64).exp());
        let bad = |s: TimeSpec| TimeFn::new("loads[0].time", Some(&s)).unwrap_err();
        assert_eq!(bad(TimeSpec::Expr("x * t".into())).0, "loads[0].time");
        assert!(bad(TimeSpec::Expr("1 / t".into())).1.contains("at t = 0"));
        assert_eq!(bad(TimeSpec::Table(TableSpec { table: vec![[0.0, 0.0], [0.0, 1.0]] })).0, "loads[0].time.table[1]");
        assert_eq!(bad(TimeSpec::Ramp(RampSpec { ramp: -1.0 })).0, "loads[0].time.ramp");
    }

    #[test]
    fn williams_t_stress_and_rotation() {
        let m = LinearElastic { e: 1000.0, nu: 0.3, rho: 1.0, state: PlaneState::PlaneStrain };
        let w = WilliamsSpec { k1: 0.0, k2: 0.0, t_stress: 2.0, tip: vec![1.0, 1.0], angle: 0.0, material: None };
        // Uniform σxx = T in plane strain: εxx = (1−ν²)T/E, εyy = −ν(1+ν)T/E.
        let u = williams_displacement(&w, &m, &[2.0, 1.5]);
        assert!((u[0] - (1.0 - 0.09) * 2.0 / 1000.0).abs() < 1e-15 && (u[1] - (-0.3 * 1.3 * 2.0 / 1000.0 * 0.5)).abs() < 1e-15, "{u:?}");
        // Turning the crack by 90° turns the field: ahead of the tip along +y, mode I opens in x.
        let w = WilliamsSpec { k1: 1.0, t_stress: 0.0, angle: 90.0, ..w };
        let (a, b) = (williams_displacement(&w, &m, &[0.5, 0.0]), williams_displacement(&w, &m, &[1.5, 0.0]));
        assert!(a[0] < 0.0 && b[0] > 0.0 && (a[0] + b[0]).abs() < 1e-15 && (a[1] - b[1]).abs() < 1e-15, "{a:?} {b:?}");
    }

    #[test]
    fn shares_tile_the_face() {
        assert_eq!(face_share(&[0.25, 0.5], &[1.0, 0.0]), 1.0);
        assert_eq!(face_share(&[0.25, 0.5], &[0.0, -1.0]), 0.5);
        assert_eq!(face_share(&[0.25, 0.5, 1.0], &[0.0, 0.0, 1.0]), 0.5);
    }
}
