//! Crack propagation in 2D (Guo & Nairn 001 §2.3): after each step (or every N steps)
//! the J-integral and K_I, K_II are evaluated at every growing tip; where the material's
//! criterion is met (001 eqs. 19–24, [`crate::fracture::criteria`]) a new crack particle
//! is added ahead of the tip in the direction θ_c, a fraction of a cell away (001 §2.3.2:
//! "we typically extend it half a grid cell length"), and becomes the new tip.
//!
//! What a tip may not do, and what happens instead:
//! * **leave the material** (001 §2.3.3): the material boundary is found from the grid —
//!   the relative nodal volume a node at the point would receive from the tip's material
//!   (eq. 27 of Nairn 2003 with linear shape functions) falls to ½ on a straight edge; a
//!   new segment reaching past it is trimmed there and the tip stops for good ("edge").
//! * **cross a crack** (its own or another): the segment is not added and the tip stops
//!   ("crack"). So every crack stays a simple polyline and never crosses another.
//! * **outrun the Rayleigh wave**: the energy flux into a tip vanishes as its speed
//!   approaches c_R (Freund 1990 §5.3; references §7: A_I, A_II → ∞), so an increment that
//!   would bring the tip-speed estimate to c_R or beyond waits; an optional `max_speed`
//!   limits it further.
//!
//! A crack whose two ends both lie on the material boundary has cut its body through:
//! the run records the time it split and goes on, the crack's contact law acting
//! between the pieces.
//!
//! Crack speed (in the Rayleigh limit above, and in the K partition factors of Guo &
//! Nairn 2004 eqs. 14–15 when `speed_correction` asks for them; the papers' runs use
//! their slow limit, 001 §3.1) is estimated from the tip's growth history: the advance
//! over the last `speed_window` increments (default [`SPEED_WINDOW`]) divided by the
//! time since the first of them, so a tip that stops slows down in the estimate.

use crate::crack::geometry::{segment_intersection, Extent};
use crate::dim::Vector;
use crate::exact::ExactSum;
use crate::fracture::criteria::{hoop_equivalent_k, hoop_stress_angle, sed_angle, sed_equivalent_k};
use crate::fracture::jintegral::{FractureError, JRequest, TipEnd, TipResult};
use crate::fracture::speed::rayleigh_speed_for;
use crate::simulation::Simulation;
use serde::{Deserialize, Serialize};

/// Number of past increments the crack-speed estimate spans by default (scene
/// `growth.speed_window`).
pub const SPEED_WINDOW: usize = 4;

/// Relative nodal volume at the material boundary (a straight edge: particles on one side).
pub const BOUNDARY_VOLUME: f64 = 0.5;

/// The boundary along a segment by bisection: the last parameter t ∈ [0, 1) found inside
/// (to 2⁻⁴⁰), given `inside(0)` and not `inside(1)` (the relative volume is continuous).
pub(crate) fn last_inside(inside: impl Fn(f64) -> bool) -> f64 {
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    for _ in 0..40 {
        let mid = 0.5 * (lo + hi);
        if inside(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    lo
}

/// A crack end with a relative volume below this is taken to be on the boundary when
/// deciding whether a crack has cut its body through (within about a quarter cell).
pub const NEAR_BOUNDARY_VOLUME: f64 = 0.75;

/// Crack-growth criterion of a material (001 §2.3.1).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Criterion {
    /// Maximum hoop stress (Erdogan & Sih 1963; 001 eqs. 19–20).
    MaxHoopStress,
    /// Minimum strain-energy density (Sih 1974; 001 eqs. 21–24).
    MinStrainEnergy,
}

/// A material's fracture toughness and the criterion it is applied with.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Toughness {
    pub criterion: Criterion,
    /// K_Ic, in the scene's stress × √length units.
    pub kic: f64,
}

impl Toughness {
    /// The direction θ_c the criterion gives for (K_I, K_II) and the equivalent K it
    /// compares with K_Ic (001 eqs. 19–24). A negative K_I (the faces overlap: the
    /// partition of eqs. 14–15 gives K_I the sign of δ_I) is taken as 0: faces in contact
    /// transmit pressure, not an opening singularity, so only K_II drives the tip. `None`
    /// for non-finite K.
    pub fn direction(&self, k1: f64, k2: f64, kappa: f64) -> Option<(f64, f64)> {
        if !(k1.is_finite() && k2.is_finite()) {
            return None;
        }
        let k1 = k1.max(0.0);
        match self.criterion {
            Criterion::MaxHoopStress => {
                let t = hoop_stress_angle(k1, k2);
                Some((t, hoop_equivalent_k(k1, k2, t)))
            }
            Criterion::MinStrainEnergy => sed_angle(k1, k2, kappa).map(|t| (t, sed_equivalent_k(k1, k2, kappa, t))),
        }
    }
}

/// How one crack grows (scene `cracks[].fracture.growth`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GrowthSettings {
    /// Length of each increment as a fraction of the cell size (default ½).
    pub increment: f64,
    /// Evaluate J/K and the criterion every this many steps (default 1).
    pub every: u64,
    /// Upper limit on the tip speed, if any.
    pub max_speed: Option<f64>,
    /// Whether K_I, K_II are split from J with the crack-speed factors of the tip's speed
    /// estimate (001 eqs. 14–17) or, as in the papers' runs (001 §3.1: "these
    /// simulations did not implement that adjustment"), with their slow limit
    /// A_I = A_II = (κ + 1)/4, β = 1 (default false).
    pub speed_correction: bool,
    /// Number of past increments the tip-speed estimate spans (default [`SPEED_WINDOW`]).
    pub speed_window: usize,
    /// Gradual release of new segments ([`crate::fracture::release`]); None: at once.
    pub release: Option<crate::fracture::release::ReleaseSettings>,
    /// Cohesive new segments and the zone's growth rule ([`crate::fracture::cohesive`]);
    /// None: free faces and the material's criterion, as the papers.
    pub cohesive: Option<crate::fracture::cohesive::CohesiveSettings>,
}

impl GrowthSettings {
    /// The crack speed the K partition takes for a tip whose speed estimate is `speed`:
    /// the estimate with `speed_correction`, 0 (the slow limit) without.
    pub fn k_speed(&self, speed: f64) -> f64 {
        if self.speed_correction {
            speed
        } else {
            0.0
        }
    }
}

/// Whether a tip can still grow.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TipStatus {
    Growing,
    /// Reached the material boundary (001 §2.3.3).
    AtEdge,
    /// Its next segment would have crossed crack `0` (the index).
    AtCrack(usize),
}

impl TipStatus {
    pub fn label(&self) -> String {
        match self {
            TipStatus::Growing => "growing".into(),
            TipStatus::AtEdge => "edge".into(),
            TipStatus::AtCrack(c) => format!("crack{c}"),
        }
    }
}

/// Growth state of one tip.
#[derive(Clone, Debug, PartialEq)]
pub struct TipGrowth {
    pub end: TipEnd,
    pub status: TipStatus,
    /// Total advance of this tip (sum of its increments).
    pub advance: f64,
    /// (time, advance after it) of every increment.
    pub events: Vec<(f64, f64)>,
}

impl TipGrowth {
    fn new(end: TipEnd) -> Self {
        TipGrowth { end, status: TipStatus::Growing, advance: 0.0, events: Vec::new() }
    }

    /// Tip-speed estimate at time `t`: the advance over the last `window` increments
    /// over the time since the first of them (0 before the second increment).
    pub fn speed(&self, t: f64, window: usize) -> f64 {
        self.speed_with(t, None, window)
    }

    /// The estimate if an increment of length `da` were added at `t`.
    fn speed_with(&self, t: f64, da: Option<f64>, window: usize) -> f64 {
        speed_estimate(&self.events, self.advance, t, da, window)
    }
}

/// The speed estimate of a growing tip or front node at time `t` from its increments
/// `events` ((time, advance after it)) and total `advance`, as if an increment of length
/// `da` were added at `t` when given: the advance over the last `window` (≥ 1)
/// increments over the time since the first of them (0 before the second increment).
pub fn speed_estimate(events: &[(f64, f64)], advance: f64, t: f64, da: Option<f64>, window: usize) -> f64 {
    let n = events.len() + da.is_some() as usize;
    if n < 2 {
        return 0.0;
    }
    let first = n.saturating_sub(window.max(1) + 1).min(events.len() - 1);
    let (t0, a0) = events[first];
    let a = advance + da.unwrap_or(0.0);
    if t > t0 {
        (a - a0) / (t - t0)
    } else {
        f64::INFINITY
    }
}

/// May an increment of length `da` be made at time `t`? The speed estimate with it must
/// stay below the Rayleigh speed `c_r` (the energy flux into a tip vanishes there, Freund
/// 1990 §5.3), and, with `max_speed`, `da` may not take less time than `da / max_speed`
/// since the last increment. `window` as in [`speed_estimate`].
pub fn speed_allows(events: &[(f64, f64)], advance: f64, t: f64, da: f64, c_r: f64, max_speed: Option<f64>, window: usize) -> bool {
    let new_speed = speed_estimate(events, advance, t, Some(da), window);
    let since_last = events.last().map_or(f64::INFINITY, |e| t - e.0);
    new_speed < c_r && max_speed.is_none_or(|vmax| da <= vmax * since_last)
}

/// Growth state of one crack.
#[derive(Clone, Debug, PartialEq)]
pub struct CrackGrowth {
    pub crack: usize,
    pub request: JRequest,
    pub settings: GrowthSettings,
    pub tips: Vec<TipGrowth>,
    /// Length of the crack polyline at the start of the run.
    pub initial_length: f64,
    /// Time at which the crack cut its body through, if it has.
    pub split: Option<f64>,
}

impl CrackGrowth {
    /// Tracked crack length: the initial length plus every tip's advance.
    pub fn length(&self) -> f64 {
        self.initial_length + self.tips.iter().map(|t| t.advance).sum::<f64>()
    }
}

/// One evaluation of the criterion at one tip (a row of growth.csv).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GrowthRecord {
    pub step: u64,
    pub fracture: TipResult,
    /// Tracked crack length after this evaluation.
    pub length: f64,
    /// Tip-speed estimate before this check (in the Rayleigh limit; in the K partition
    /// only with `speed_correction`).
    pub speed: f64,
    /// θ_c of the tip's material criterion, radians from the crack direction, counter-
    /// clockwise (toward the upper face); NaN for a material without a toughness.
    pub theta: f64,
    /// Equivalent K of the criterion along θ_c (NaN when θ_c is).
    pub k_eq: f64,
    /// Whether a crack particle was added.
    pub grew: bool,
    pub status: TipStatus,
    /// Whether J could be evaluated (the other fields are NaN when not).
    pub j: JStatus,
}

/// Whether J was evaluated at a growth check.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum JStatus {
    Ok,
    /// The contour does not fit in the grid.
    ContourOutsideGrid,
    /// The contour crosses the crack more than once (or not at all).
    ContourCrossings,
}

impl JStatus {
    pub fn label(&self) -> &'static str {
        match self {
            JStatus::Ok => "ok",
            JStatus::ContourOutsideGrid => "contour_outside_grid",
            JStatus::ContourCrossings => "contour_crossings",
        }
    }
}

impl GrowthRecord {
    pub const HEADER: &'static str = "time,step,crack,tip,x,y,length,speed,j1,k1,k2,theta_deg,k_eq,grew,status,j";

    /// The row of a check at which J could not be evaluated (`e`): NaN fracture values.
    fn without_j(sim: &Simulation, cg: &CrackGrowth, k: usize, speed: f64, tip: Vector, e: &FractureError) -> Self {
        let nan = f64::NAN;
        let fracture = TipResult::unavailable(sim.time, cg.crack, cg.tips[k].end, tip);
        let j = if matches!(e, FractureError::ContourOutsideGrid { .. }) { JStatus::ContourOutsideGrid } else { JStatus::ContourCrossings };
        GrowthRecord { step: sim.step_count, fracture, length: cg.length(), speed, theta: nan, k_eq: nan, grew: false, status: cg.tips[k].status, j }
    }

    pub fn csv(&self) -> String {
        let f = &self.fracture;
        let end = match f.end {
            TipEnd::Start => "start",
            TipEnd::End => "end",
        };
        format!(
            "{:e},{},{},{},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{},{},{}",
            f.time,
            self.step,
            f.crack,
            end,
            f.tip.x,
            f.tip.y,
            self.length,
            self.speed,
            f.j1,
            f.k1,
            f.k2,
            self.theta.to_degrees(),
            self.k_eq,
            self.grew as u8,
            self.status.label(),
            self.j.label()
        )
    }
}

/// Crack growth of a whole simulation: the toughness of each material (None: it does not
/// fracture) and the growing cracks.
#[derive(Clone, Debug, PartialEq)]
pub struct Growth {
    pub toughness: Vec<Option<Toughness>>,
    pub cracks: Vec<CrackGrowth>,
    /// Every evaluation so far, in order.
    pub records: Vec<GrowthRecord>,
    /// New segments whose faces are still held ([`crate::fracture::release`]).
    pub releases: Vec<crate::fracture::release::Release>,
    /// The cohesive segments of each crack that has them ([`crate::fracture::cohesive`]).
    pub cohesive: Vec<crate::fracture::cohesive::CohesiveZone>,
}

impl Growth {
    /// Growth state for the cracks `(index, request, settings)` of `sim`.
    pub fn new(sim: &Simulation, toughness: Vec<Option<Toughness>>, cracks: Vec<(usize, JRequest, GrowthSettings)>) -> Self {
        let cracks = cracks
            .into_iter()
            .map(|(c, request, settings)| {
                let pts = &sim.cracks[c].points;
                let initial_length = pts.windows(2).map(|s| (s[1] - s[0]).norm()).sum();
                let tips = request.tips.iter().map(|&e| TipGrowth::new(e)).collect();
                CrackGrowth { crack: c, request, settings, tips, initial_length, split: None }
            })
            .collect::<Vec<_>>();
        let cohesive = cracks
            .iter()
            .filter(|g| g.settings.cohesive.is_some())
            .map(|g| crate::fracture::cohesive::CohesiveZone::new(g.crack, sim.cracks[g.crack].points.len()))
            .collect();
        Growth { toughness, cracks, records: Vec::new(), releases: Vec::new(), cohesive }
    }

    /// Does crack `c` grow?
    pub fn grows(&self, c: usize) -> bool {
        self.cracks.iter().any(|g| g.crack == c)
    }

    /// Current speed estimate of tip `end` of crack `c` (0 if it does not grow).
    pub fn tip_speed(&self, c: usize, end: TipEnd, t: f64) -> f64 {
        self.cracks
            .iter()
            .filter(|g| g.crack == c)
            .flat_map(|g| g.tips.iter().map(move |tip| (tip, g.settings.speed_window)))
            .find(|(tip, _)| tip.end == end)
            .map_or(0.0, |(tip, w)| tip.speed(t, w))
    }

    /// The crack speed the K partition of tip `end` of crack `c` takes at `t`
    /// ([`GrowthSettings::k_speed`] of its speed estimate; 0 if it does not grow).
    pub fn tip_k_speed(&self, c: usize, end: TipEnd, t: f64) -> f64 {
        self.cracks.iter().find(|g| g.crack == c).map_or(0.0, |g| g.settings.k_speed(self.tip_speed(c, end, t)))
    }
}

/// Why a crack could not grow as asked (stops the run).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum GrowthError {
    #[error(transparent)]
    Fracture(#[from] FractureError),
    #[error("crack {crack}: no material particle near the {end:?} tip at ({x}, {y}) to take the toughness from")]
    NoMaterial { crack: usize, end: TipEnd, x: f64, y: f64 },
    #[error("crack {crack}: Rayleigh speed of the material at the {end:?} tip: {message}")]
    Rayleigh { crack: usize, end: TipEnd, message: String },
    #[error("crack {crack}: cohesive law of the material at the {end:?} tip: {message}")]
    Cohesive { crack: usize, end: TipEnd, message: String },
    /// 3D: a front node's evaluation failed ([`crate::fracture::growth3`]).
    #[error("crack {crack}, front node {node} at ({x}, {y}, {z}): {message}")]
    Front { crack: usize, node: u32, x: f64, y: f64, z: f64, message: String },
}

impl Simulation {
    /// Crack growth after a completed step (001 §2.3.2): at every growing tip whose crack
    /// is due this step, J and K (with the tip's speed estimate), the criterion of the
    /// material at the tip, and, when it is met, one new crack particle at the increment
    /// in direction θ_c (trimmed at the material boundary; refused across a crack).
    pub(crate) fn grow_cracks(&mut self) -> Result<(), GrowthError> {
        let Some(mut growth) = self.growth.take() else { return Ok(()) };
        let result = self.grow_cracks_with(&mut growth);
        self.growth = Some(growth);
        result
    }

    fn grow_cracks_with(&mut self, growth: &mut Growth) -> Result<(), GrowthError> {
        let h = self.grid.min_h();
        for cg in growth.cracks.iter_mut() {
            if !self.step_count.is_multiple_of(cg.settings.every) {
                continue;
            }
            let c = cg.crack;
            for k in 0..cg.tips.len() {
                let end = cg.tips[k].end;
                let speed = cg.tips[k].speed(self.time, cg.settings.speed_window);
                // A contour that no longer fits (near the grid's edge) or that the crack
                // crosses more than once (a curved crack near its tip) gives no J: the tip
                // does not grow at this evaluation, and the row says why.
                let fr = match self.tip_fracture_request(c, end, &cg.request, cg.settings.k_speed(speed)) {
                    Ok(fr) => fr,
                    Err(e @ (FractureError::ContourOutsideGrid { .. } | FractureError::Crossings { .. })) => {
                        let tip = self.tip_of(c, end);
                        growth.records.push(GrowthRecord::without_j(self, cg, k, speed, tip, &e));
                        continue;
                    }
                    Err(e) => return Err(e.into()),
                };
                let mat = self
                    .material_index_near(fr.tip)
                    .ok_or(GrowthError::NoMaterial { crack: c, end, x: fr.tip.x, y: fr.tip.y })?;
                let toughness = growth.toughness[mat];
                let kappa = self.materials[mat].kappa();
                let dir = toughness.and_then(|t| t.direction(fr.k1, fr.k2, kappa));
                let (theta, k_eq) = dir.unwrap_or((f64::NAN, f64::NAN));
                let mut grew = false;
                let meets = match cg.settings.cohesive {
                    // The zone's own rule (cohesive module doc): seed a first cohesive
                    // segment once the tip is loaded (K_eq > 0, so that θ_c is the load's);
                    // then advance when the crack particle behind the tip has reached the
                    // law's peak.
                    Some(_) => {
                        let zone = growth.cohesive.iter().find(|z| z.crack == c).expect("cohesive zone");
                        toughness.is_some() && dir.is_some() && zone.tip_ready(end == TipEnd::Start).unwrap_or(k_eq > 0.0)
                    }
                    None => matches!((toughness, dir), (Some(t), Some((_, keq))) if keq >= t.kic),
                };
                if cg.tips[k].status == TipStatus::Growing && meets {
                    let da = cg.settings.increment * h;
                    let c_r = rayleigh_speed_for(&self.materials[mat]).map_err(|e| GrowthError::Rayleigh { crack: c, end, message: e.to_string() })?;
                    let tip = &cg.tips[k];
                    if speed_allows(&tip.events, tip.advance, self.time, da, c_r, cg.settings.max_speed, cg.settings.speed_window) {
                        let (e1, e2) = (fr.direction, Vector::new(-fr.direction.y, fr.direction.x));
                        let heading = e1 * theta.cos() + e2 * theta.sin();
                        let (added, status) = self.extend_crack(c, end, mat, fr.tip, fr.tip + heading * da);
                        let tip = &mut cg.tips[k];
                        tip.status = status;
                        if added > 0.0 {
                            if end == TipEnd::Start {
                                growth.releases.iter_mut().filter(|r| r.crack == c).for_each(|r| r.segment += 1);
                            }
                            if let Some(cs) = cg.settings.cohesive {
                                let law = self.cohesive_law(mat, cs, toughness.expect("toughness").kic).map_err(|message| GrowthError::Cohesive { crack: c, end, message })?;
                                let thickness = self.thickness_near(fr.tip);
                                growth.cohesive.iter_mut().filter(|z| z.crack == c).for_each(|z| z.added(end == TipEnd::Start, law, thickness));
                            }
                            if let Some(rs) = cg.settings.release {
                                let segment = if end == TipEnd::Start { 0 } else { self.cracks[c].points.len() - 2 };
                                let speed = speed_estimate(&tip.events, tip.advance, self.time, Some(added), cg.settings.speed_window);
                                let (duration, rate) = rs.timing(h, speed, c_r, crate::material::Constitutive::wave_speed(&self.materials[mat]));
                                growth.releases.push(crate::fracture::release::Release { crack: c, segment, t0: self.time, duration, rate });
                            }
                            tip.advance += added;
                            tip.events.push((self.time, tip.advance));
                            grew = true;
                        }
                    }
                }
                growth.records.push(GrowthRecord {
                    step: self.step_count,
                    fracture: fr,
                    length: cg.length(),
                    speed,
                    theta,
                    k_eq,
                    grew,
                    status: cg.tips[k].status,
                    j: JStatus::Ok,
                });
            }
            if cg.split.is_none() && self.crack_cuts_through(cg) {
                cg.split = Some(self.time);
            }
        }
        Ok(())
    }

    /// Add the segment from the tip `from` of crack `c` toward `to`, trimmed at the
    /// boundary of material `mat` and refused if it would cross a crack. Returns the
    /// length added and the tip's new status.
    fn extend_crack(&mut self, c: usize, end: TipEnd, mat: usize, from: Vector, to: Vector) -> (f64, TipStatus) {
        // A crack, this one included, in the way?
        for (o, other) in self.cracks.iter().enumerate() {
            let n = other.points.len();
            for (s, seg) in other.points.windows(2).enumerate() {
                // The tip's own segment touches `from` by construction.
                let own = o == c && ((end == TipEnd::End && s == n - 2) || (end == TipEnd::Start && s == 0));
                if !own && segment_intersection(from, to, seg[0], seg[1]).is_some() {
                    return (0.0, TipStatus::AtCrack(o));
                }
            }
        }
        let mut target = to;
        let mut status = TipStatus::Growing;
        if self.relative_volume(mat, to) < BOUNDARY_VOLUME {
            status = TipStatus::AtEdge;
            if self.relative_volume(mat, from) < BOUNDARY_VOLUME {
                return (0.0, status);
            }
            // Bisect for the boundary along the segment (the relative volume is continuous).
            let lo = last_inside(|t| self.relative_volume(mat, from + (to - from) * t) >= BOUNDARY_VOLUME);
            target = from + (to - from) * lo;
        }
        let added = (target - from).norm();
        // Too short a segment would make a degenerate tip direction: stop there instead.
        if added < 1e-3 * self.grid.min_h() {
            return (0.0, status);
        }
        let crack = &mut self.cracks[c];
        match end {
            TipEnd::End => {
                crack.points.push(target);
                crack.above.push(target);
                crack.below.push(target);
            }
            TipEnd::Start => {
                crack.points.insert(0, target);
                crack.above.insert(0, target);
                crack.below.insert(0, target);
            }
        }
        crack.extent = Extent::of(&crack.points);
        (added, status)
    }

    /// Has crack `cg` cut its body through? Both ends on the material boundary: a tip
    /// stopped there, or a non-growing end within about a quarter cell of it.
    fn crack_cuts_through(&self, cg: &CrackGrowth) -> bool {
        let on_boundary = |end: TipEnd| {
            if let Some(t) = cg.tips.iter().find(|t| t.end == end) {
                return t.status == TipStatus::AtEdge;
            }
            let x = self.tip_of(cg.crack, end);
            match self.material_index_near(x) {
                Some(m) => self.relative_volume(m, x) < NEAR_BOUNDARY_VOLUME,
                None => true,
            }
        };
        on_boundary(TipEnd::Start) && on_boundary(TipEnd::End)
    }

    /// Relative volume of material `mat` at `x`: the volume a grid node at `x` would
    /// receive from the material's particles with linear shape functions (eq. 27 of
    /// Nairn 2003), over the cell area. 1 inside, ½ on a straight edge, 0 outside — the
    /// "MPM material boundary" of 001 §2.3.3. Exact sum: independent of particle order.
    pub fn relative_volume(&self, mat: usize, x: Vector) -> f64 {
        let p = &self.particles;
        let h = self.grid.h;
        let mut sum = ExactSum::new();
        for i in 0..p.len() {
            if p.material[i] as usize != mat {
                continue;
            }
            let d = p.x[i] - x;
            let (wx, wy) = (1.0 - d.x.abs() / h.x, 1.0 - d.y.abs() / h.y);
            if wx > 0.0 && wy > 0.0 {
                sum.add(wx * wy * self.particle_area(i));
            }
        }
        sum.value() / (h.x * h.y)
    }

    /// Current area of particle `i` (its volume over the body's thickness).
    fn particle_area(&self, i: usize) -> f64 {
        self.particles.volume(i) / self.thickness[self.particles.body[i] as usize]
    }

    /// Position of tip `end` of crack `c`.
    pub(crate) fn tip_of(&self, c: usize, end: TipEnd) -> Vector {
        let pts = &self.cracks[c].points;
        match end {
            TipEnd::Start => pts[0],
            TipEnd::End => pts[pts.len() - 1],
        }
    }

    /// The particle nearest to `x` (ties: lowest id), None without particles.
    fn nearest_particle(&self, x: Vector) -> Option<usize> {
        let p = &self.particles;
        (0..p.len()).min_by(|&a, &b| (p.x[a] - x).norm_squared().total_cmp(&(p.x[b] - x).norm_squared()).then(p.id[a].cmp(&p.id[b])))
    }

    /// Thickness of the body of the particle nearest `x` (ties: lowest id).
    pub fn thickness_near(&self, x: Vector) -> f64 {
        self.nearest_particle(x).map_or(1.0, |i| self.thickness[self.particles.body[i] as usize])
    }

    /// The cohesive law of material `mat` for `settings` with toughness `kic`:
    /// G_c = K_Ic²/E', rising stiffness ρ c_d²/h ([`crate::fracture::cohesive`]).
    pub fn cohesive_law(&self, mat: usize, settings: crate::fracture::cohesive::CohesiveSettings, kic: f64) -> Result<crate::fracture::cohesive::CohesiveLaw, String> {
        let m = &self.materials[mat];
        let c_d = crate::material::Constitutive::wave_speed(m);
        crate::fracture::cohesive::CohesiveLaw::new(settings.strength, kic * kic / m.e_prime(), m.rho * c_d * c_d, self.grid.min_h())
    }

    /// Index of the material of the particle nearest to `x` (ties: lowest id).
    pub fn material_index_near(&self, x: Vector) -> Option<usize> {
        self.nearest_particle(x).map(|i| self.particles.material[i] as usize)
    }
}

/// Is the polyline simple: do no two of its segments meet, other than neighbours at their
/// shared point? (The growth invariant: a new segment is refused where it would cross.)
pub fn is_simple_polyline(points: &[Vector]) -> bool {
    let n = points.len();
    for i in 0..n.saturating_sub(1) {
        for j in i + 2..n - 1 {
            if segment_intersection(points[i], points[i + 1], points[j], points[j + 1]).is_some() {
                return false;
            }
        }
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn speed_estimate_spans_the_window_and_decays_when_the_tip_stops() {
        let mut t = TipGrowth::new(TipEnd::End);
        let w = SPEED_WINDOW;
        assert_eq!(t.speed(1.0, w), 0.0);
        for k in 1..=6 {
            t.advance += 0.5;
            t.events.push((k as f64, t.advance));
        }
        // events at t = 1..6, 0.5 each: the window spans the last 4 increments → from t = 2.
        assert_eq!(t.speed(6.0, w), 2.0 / 4.0);
        assert_eq!(t.speed(10.0, w), 2.0 / 8.0);
        // a window of one increment: the last one, from t = 5
        assert_eq!(t.speed(6.0, 1), 0.5 / 1.0);
        // one more increment at t = 7 would give (3.5 − 1.5)/(7 − 3)
        assert_eq!(t.speed_with(7.0, Some(0.5), w), 2.0 / 4.0);
    }

    #[test]
    fn k_speed_is_the_estimate_only_with_speed_correction() {
        let mut g = GrowthSettings { increment: 0.5, every: 1, max_speed: None, speed_correction: false, speed_window: SPEED_WINDOW, release: None, cohesive: None };
        assert_eq!(g.k_speed(123.0), 0.0);
        g.speed_correction = true;
        assert_eq!(g.k_speed(123.0), 123.0);
    }

    #[test]
    fn simple_polyline_detects_a_crossing() {
        let v = |x: f64, y: f64| Vector::new(x, y);
        assert!(is_simple_polyline(&[v(0.0, 0.0), v(1.0, 0.0), v(1.0, 1.0), v(2.0, 1.0)]));
        assert!(!is_simple_polyline(&[v(0.0, 0.0), v(2.0, 0.0), v(2.0, 1.0), v(1.0, -1.0)]));
    }

    #[test]
    fn toughness_direction_is_each_criterion_and_none_when_closed() {
        let hoop = Toughness { criterion: Criterion::MaxHoopStress, kic: 1.0 };
        let (t, keq) = hoop.direction(0.0, 1.0, 1.8).unwrap();
        assert!((t.to_degrees() + 70.528779).abs() < 1e-5, "{}", t.to_degrees());
        assert!((keq - 2.0 / 3f64.sqrt()).abs() < 1e-12);
        let sed = Toughness { criterion: Criterion::MinStrainEnergy, kic: 1.0 };
        let (t, _) = sed.direction(0.0, 1.0, 1.8).unwrap();
        assert!((t.to_degrees() + 82.338).abs() < 1e-3, "{}", t.to_degrees());
        // Overlapping faces: K_I < 0 counts as 0.
        assert_eq!(hoop.direction(-1.0, 1.0, 1.8), hoop.direction(0.0, 1.0, 1.8));
        assert!(hoop.direction(f64::NAN, 1.0, 1.8).is_none());
    }
}
