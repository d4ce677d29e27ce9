//! The dynamic J-integral at a crack tip and its partition into K_I and K_II
//! (Guo & Nairn 2004 §3).
//!
//! * **Contour** (004 Fig. 3): the rectangle of grid lines n cells from the node nearest
//!   the tip (default n = 2, a "2×2" path), traversed counter-clockwise. It is cut where
//!   it crosses the crack; the cut gets two points, one per crack face, whose values are
//!   interpolated between the two neighbouring perimeter nodes in the velocity field of
//!   that face. The contour starts on the lower face (θ = −π in crack-tip coordinates)
//!   and ends on the upper face (θ = +π); perimeter nodes in the first half use the
//!   lower face's field where they have two, those in the second half the upper face's.
//! * **Line term** (eqs. 12–13): F_m = (W + K) n_m − (σ·n)·∂u/∂x_m at the contour points
//!   from the per-field nodal values of eq. 11 ([`crate::fracture::nodal`]), integrated
//!   segment by segment with the trapezoidal ("midpoint") rule of eq. 12, n being the
//!   segment's outward normal.
//! * **Area term** (eq. 8, on request): ∫_A (ρ ü·∂u/∂x_m − ρ u̇·∂u̇/∂x_m) dA over the
//!   particles inside the rectangle as equally weighted points (ρA = m/thickness), with
//!   velocity, acceleration and velocity gradient interpolated from the nodal fields of
//!   each particle's own pairs (the grid velocity, not the particle's own, which carries
//!   undamped components the grid cannot see — see [`NodalState::kinetic_energy`]). The
//!   two-term J is path independent; the line term alone is only in the limit of a small
//!   contour.
//! * **Which acceleration** (issue 22): eq. 8 follows from the divergence theorem with
//!   ∇·σ = ρü, i.e. without body forces, loads or damping. With them, eq. 1 of 004 gives
//!   ∇·σ = ρü − B + d_k u̇ (B the body force per volume, d_k the damping), and the same
//!   derivation gives J = line term + ∫_A ((∇·σ)·∂u/∂x_m − ρ u̇·∂u̇/∂x_m) dA: the
//!   "acceleration" of the area term is (∇·σ)/ρ = ü − B/ρ + (d_k/ρ) u̇, which carries the
//!   J-integral's body-force term −∫ B·∂u/∂x_m dA and its damping term. On the grid it is
//!   the total force of eq. 2 less the loads and body forces (eq. 5's first part, eq. 6's
//!   body force) and less the damping force −κp: (f^tot − f^ext + κp)/M^L
//!   ([`area_acceleration`]). With f^tot itself a body resting under gravity has no area
//!   term at all, and its J depends on the contour (tests/j_body_force.rs: 12 % over the
//!   2×2 … 6×6 contours, 0.9 % with the body-force term).
//! * **Crack-face contact** stays in that acceleration, as before. Strictly, (∇·σ)/ρ is
//!   f^int/M^L and the contact impulses are crack-face tractions, which add a face term
//!   −∫_faces t·∂u/∂x_m ds to J; taking f^int alone would include it. On the stationary
//!   cases it changes nothing measurable, but on the growing PMMA beam (case pmma_tpb,
//!   frictionless faces) it moves the crack's advance at 300 µs from 24 to 34 mm (4 mm
//!   cells) and 18 to 37 mm (2 mm): what contact does at a growing tip is issue 20's
//!   energy-balance question, and is left to it.
//! * **Crack-tip coordinates**: x₁′ along the last crack segment, pointing out of the tip;
//!   x₂′ its counter-clockwise normal. J₁ = J·e₁′ is the energy release rate G for growth
//!   straight ahead (eq. 10); J₂ = J·e₂′.
//! * **K_I, K_II** (eqs. 14–15 with the speed factors of [`crate::fracture::speed`]): G
//!   split by the crack-opening displacements δ_I (normal) and δ_II (sliding) of the
//!   tracked crack surfaces (001 eqs. 11–12); δ is the upper (+x₂′) face's position minus
//!   the lower face's, at the crack particle next to the tip as the paper does
//!   ([`CodMethod::NextToTip`], the default), or the leading √r term of a least-squares
//!   fit over the crack particles 1.5–8 cells behind the tip ([`CodMethod::Fit`]). Why
//!   both: on the split beams of 004 §4.1 the surfaces more than a cell behind the tip are
//!   the superposition of the mode I and mode II solutions to ~1 %, those within a cell
//!   are not (δ_II 18 % off at 2 mm), because there the few particle–node pairs around
//!   the tip fall into fields differently as the crack moves off the grid line; the
//!   fitted split is within 1 % of beam theory at 2 and 1 mm where the next-to-tip one is
//!   8–18 % off (issue 4 note; case split_beams_k). The fit is verified for stationary
//!   cracks only.
//!
//! Which crack surface is "upper": a crack's `above` surface is to the left of the
//! polyline's direction of travel (first point to last). At the last point (the "end"
//! tip) e₁′ is that direction, so the upper face is `above`; at the first point (the
//! "start" tip) e₁′ is reversed and the upper face is `below`.

use crate::dim::{Sym, Tensor, Vector};
use crate::exact::ExactSum;
use crate::fracture::nodal::NodalState;
use crate::fracture::speed::{speed_factors_for, SpeedError};
use crate::material::LinearElastic;
use crate::shape::MAX_NODES;
use crate::simulation::Simulation;
use serde::{Deserialize, Serialize};
use thiserror::Error;

/// Which end of a crack polyline is a tip.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum TipEnd {
    /// The first crack particle.
    Start,
    /// The last crack particle.
    End,
}

/// What a scene asks to be computed at the tips of one crack.
#[derive(Clone, Debug, PartialEq)]
pub struct JRequest {
    pub tips: Vec<TipEnd>,
    /// Half-size n of the n×n-cell rectangular contour.
    pub contour: usize,
    /// Include the area term of eq. 8 (two-term J).
    pub area_term: bool,
    /// How δ_I, δ_II are read from the tracked crack surfaces.
    pub cod: CodMethod,
    /// Radius (length) of a circular contour instead of the rectangle (line term only;
    /// [`Simulation::tip_fracture_request`]).
    pub circle: Option<f64>,
}

/// How the crack-opening displacements that split G into K_I and K_II (eqs. 14–15) are
/// read from the tracked crack surfaces.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CodMethod {
    /// The crack particle next to the tip (Guo & Nairn 2004 §3), as the paper does.
    /// Biased in mixed mode on a stationary crack (δ_II 18 % low in the 2 mm mixed split
    /// beam): the surfaces within about a cell of the tip are set by how the few
    /// particle–node pairs around the tip happen to fall into fields as the crack moves
    /// off the grid line, and are not the superposition of the mode I and mode II
    /// solutions there (issue 4 note).
    #[default]
    NextToTip,
    /// Least-squares fit of the near-tip expansion of the opening over the crack
    /// particles [`FIT_FROM`]–[`FIT_TO`] cells behind the tip (arc length, at most half
    /// the crack's length): each component δ(r) = a₁ r^½ + a₃ r^{3/2} + a₅ r^{5/2} (the
    /// crack-face displacement jump of the Williams expansion has only odd powers of √r:
    /// the r¹ terms, T-stress and rigid rotation, move both faces alike), resolved in the
    /// local crack direction; δ is a₁√h, the leading term one cell behind the tip.
    /// Beyond a cell from the tip the surfaces superpose to ~1 %, and the fitted split is
    /// within 1 % of beam theory on the split beams at 2 and 1 mm (case split_beams_k).
    /// Verified for stationary cracks whose fit window (8 cells) is small next to the
    /// body; not for growing cracks, whose surfaces behind the tip were laid down during
    /// growth (on the off-centre PMMA beam at 4 mm, 8 cells = 32 mm, it turns the crack
    /// less than the next-to-tip split). With fewer than three crack particles in the
    /// window, the next-to-tip value is used.
    Fit,
    /// No opening: G = J₁ split in the ratio K_I : K_II of the **interaction integral** on
    /// the same cut contour (Yau, Wang & Corten 1980; Anderson 2005 §7.4.3), the field's
    /// mutual J with the Williams fields of unit K_I and K_II in the tip's frame
    /// ([`interaction_k`]). The magnitude stays J's (the energy the discrete crack releases;
    /// the interaction integral's own K_I is less accurate near a coarse contour: +1.3 to
    /// +5 % against √(E′J) on the 2 mm DCB, as the static FEA's doc finds for Q4 meshes).
    /// It reads stresses and displacement gradients on the contour, two or more cells from
    /// the tip, not the crack surfaces next to it, so it does not see how the few
    /// particle–node pairs at the tip fall into fields (issue 20: a stationary mode I
    /// crack turned 45° on the grid gave K_II = 0.21 K_I from the opening).
    ///
    /// **Frame: the chord.** The auxiliary crack runs straight back from the tip along
    /// −e₁′ and must leave the contour where the real crack does (the integral's path
    /// independence needs traction-free faces on both fields between the contour and the
    /// tip), so e₁′ is the chord from the contour's cut on the crack to the tip, not the
    /// last segment: equal for a straight crack, but a growing crack's last segment (an
    /// increment of ½ cell) is far shorter than the contour, and split in its frame the
    /// contour reads the older crack's direction as a K_II that turns the next increment
    /// back past the path — the crack zigzags (mode II plate with cohesive segments,
    /// 5-cell contour: θ_c alternating ±50°; in the chord frame within a few degrees
    /// once the branch is longer than the contour; case growth_j). Growth then turns
    /// θ_c from the chord too, i.e. a kinked path is followed at the contour's scale.
    ///
    /// Static form: the ratio has no inertial term (with `area_term` the magnitude J keeps
    /// its own; `cramp run` warns). Refused with `circle` (no rectangular contour) and
    /// with growth's `speed_correction` (the speed factors convert openings, not K's).
    /// The δ_I, δ_II written beside it are the next-to-tip ones, in the chord frame.
    Interaction,
}

/// The COD fit window of [`CodMethod::Fit`], in cells behind the tip.
pub const FIT_FROM: f64 = 1.5;
pub const FIT_TO: f64 = 8.0;

/// Fracture parameters at one crack tip at one time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TipResult {
    pub time: f64,
    pub crack: usize,
    pub end: TipEnd,
    /// Tip position.
    pub tip: Vector,
    /// Unit vector e₁′ along the last segment, out of the tip.
    pub direction: Vector,
    /// J in crack-tip coordinates: the line term plus, when requested, the area term.
    pub j1: f64,
    pub j2: f64,
    /// The line term alone (eq. 7 on the finite contour).
    pub j1_line: f64,
    pub j2_line: f64,
    /// Crack-opening displacements (normal, sliding) of the upper face relative to the
    /// lower: at the crack particle next to the tip, or the fitted leading term one cell
    /// behind it ([`CodMethod`]).
    pub delta_i: f64,
    pub delta_ii: f64,
    /// Stress intensity factors from G = J₁ split by δ_I/δ_II (eqs. 14–15).
    pub k1: f64,
    pub k2: f64,
}

/// Why J could not be evaluated at a tip. Each names the crack, the tip and the cause.
#[derive(Clone, Debug, PartialEq, Error)]
pub enum FractureError {
    #[error("crack {crack} ({end:?} tip at ({x}, {y})): the {n}×{n} J contour around node ({ix}, {iy}) does not fit in the grid ({nx}×{ny} cells); use a smaller contour or a larger grid")]
    ContourOutsideGrid { crack: usize, end: TipEnd, x: f64, y: f64, n: usize, ix: i64, iy: i64, nx: usize, ny: usize },
    #[error("crack {crack} ({end:?} tip at ({x}, {y})): the J contour crosses the crack {crossings} times (need exactly once); the crack curves back through the contour or the tip is outside it — use a smaller contour")]
    Crossings { crack: usize, end: TipEnd, x: f64, y: f64, crossings: usize },
    #[error("crack {crack}: no particle to take the material of the tip from")]
    NoMaterial { crack: usize },
    #[error("crack {crack} ({end:?} tip): crack-speed factors: {source}")]
    Speed { crack: usize, end: TipEnd, source: SpeedError },
}

impl FractureError {
    /// The scene index of the crack the error is about.
    pub fn crack(&self) -> usize {
        match self {
            FractureError::ContourOutsideGrid { crack, .. }
            | FractureError::Crossings { crack, .. }
            | FractureError::NoMaterial { crack }
            | FractureError::Speed { crack, .. } => *crack,
        }
    }
}

/// One point of the cut contour: position and the nodal state of the field used there.
#[derive(Clone, Copy, Debug)]
struct ContourPoint {
    x: Vector,
    state: NodalState,
}

/// Preferred order of velocity fields for the material on one face: the `above` face is
/// field 1 where a node has it (particles above, seen across the crack), else field 0
/// (the node is on that side); symmetrically for `below` (Nairn 2003 §2.1).
fn face_fields(above: bool) -> [usize; 3] {
    if above {
        [1, 0, 2]
    } else {
        [2, 0, 1]
    }
}

fn state_on_face(states: &[Option<NodalState>; 3], above: bool) -> NodalState {
    face_fields(above).iter().find_map(|&f| states[f]).unwrap_or_default()
}

fn lerp(a: &NodalState, b: &NodalState, t: f64) -> NodalState {
    let l = |u: f64, v: f64| u + t * (v - u);
    NodalState {
        stress: Sym {
            xx: l(a.stress.xx, b.stress.xx),
            yy: l(a.stress.yy, b.stress.yy),
            zz: l(a.stress.zz, b.stress.zz),
            xy: l(a.stress.xy, b.stress.xy),
        },
        grad_u: a.grad_u + (b.grad_u - a.grad_u) * t,
        strain_energy: l(a.strain_energy, b.strain_energy),
        kinetic_energy: l(a.kinetic_energy, b.kinetic_energy),
        displacement: a.displacement + (b.displacement - a.displacement) * t,
        velocity: a.velocity + (b.velocity - a.velocity) * t,
        acceleration: a.acceleration + (b.acceleration - a.acceleration) * t,
    }
}

/// Eq. 13: the integrand vector (F₁, F₂) at a contour point for outward normal `n`.
fn integrand(s: &NodalState, n: Vector) -> Vector {
    let traction = s.stress.dot_vec(&n);
    let energy = s.strain_energy + s.kinetic_energy;
    // Σ_i t_i ∂u_i/∂x_m = (grad_uᵀ t)_m
    n * energy - s.grad_u.transpose() * traction
}

/// The unit chord from `cut` (where a contour meets the crack) to the tip; None if they
/// coincide.
fn chord_direction(tip: Vector, cut: Vector) -> Option<Vector> {
    let v = tip - cut;
    (v.norm() > 0.0).then(|| v.normalize())
}

/// K_I, K_II by the interaction integral ([`CodMethod::Interaction`]) on the cut contour
/// `pts` (counter-clockwise from the lower face to the upper one), tip frame (e₁′ = `d`,
/// e₂′ = `e2`): for each mode m the mutual J of the field and the Williams field of unit
/// K_m ([`crate::fracture::williams::williams_aux`]),
///
/// I_m = ∮ (W⁽ᵐ⁾ n₁ − σ_ij n_j ∂u⁽ᵐ⁾_i/∂x₁ − σ⁽ᵐ⁾_ij n_j ∂u_i/∂x₁) ds,  W⁽ᵐ⁾ = σ⁽ᵐ⁾_ij ε_ij,
///
/// in tip coordinates, with the trapezoidal rule per segment as the line term of J
/// (eq. 12), and K_m = E′ I_m / 2. The face points are at θ = −π (first) and +π (last),
/// and so is a perimeter node on the crack line behind the tip (a crack along a node row
/// passes through one), by the half of the path it belongs to.
/// Static form (no kinetic or inertial terms); the faces are traction-free in both fields.
fn interaction_k(pts: &[ContourPoint], tip: Vector, d: Vector, e2: Vector, mat: &LinearElastic) -> (f64, f64) {
    let (mu, kappa) = (mat.shear_modulus(), mat.kappa());
    let q = nalgebra::Matrix2::new(d.x, d.y, e2.x, e2.y);
    let last = pts.len() - 1;
    // Per point: local stress (σ11, σ22, σ12), local ∇u, and the auxiliary fields of both modes.
    let local: Vec<_> = pts
        .iter()
        .enumerate()
        .map(|(k, p)| {
            let xl = q * (p.x - tip);
            // On the crack line behind the tip (the cut points, and a perimeter node the
            // crack passes through) θ is ±π by the face the point stands for — the first
            // half of the path is the lower face — not by the sign of a round-off y.
            let on_faces = xl.x < 0.0 && xl.y.abs() <= 1e-9 * xl.x.abs();
            let theta = match k {
                0 => -std::f64::consts::PI,
                _ if k == last => std::f64::consts::PI,
                _ if on_faces && 2 * k < pts.len() => -std::f64::consts::PI,
                _ if on_faces => std::f64::consts::PI,
                _ => xl.y.atan2(xl.x),
            };
            let s = &p.state.stress;
            let sig = q * nalgebra::Matrix2::new(s.xx, s.xy, s.xy, s.yy) * q.transpose();
            let grad = q * p.state.grad_u * q.transpose();
            let aux = [1u8, 2].map(|m| crate::fracture::williams::williams_aux(m, xl.norm(), theta, mu, kappa));
            (sig, grad, aux)
        })
        .collect();
    let integrand = |k: usize, n: Vector, m: usize| {
        let (sig, grad, aux) = &local[k];
        let (sa, du_aux) = aux[m];
        let (e11, e22, e12) = (grad[(0, 0)], grad[(1, 1)], 0.5 * (grad[(0, 1)] + grad[(1, 0)]));
        let w = sa[0] * e11 + sa[1] * e22 + 2.0 * sa[2] * e12;
        let t = sig * n;
        let t_aux = Vector::new(sa[0] * n.x + sa[2] * n.y, sa[2] * n.x + sa[1] * n.y);
        w * n.x - (t.x * du_aux[0] + t.y * du_aux[1]) - (t_aux.x * grad[(0, 0)] + t_aux.y * grad[(1, 0)])
    };
    let mut sums = [ExactSum::new(), ExactSum::new()];
    for k in 0..last {
        let seg = pts[k + 1].x - pts[k].x;
        let len = seg.norm();
        if len == 0.0 {
            continue;
        }
        let n = q * (Vector::new(seg.y, -seg.x) / len);
        for (m, sum) in sums.iter_mut().enumerate() {
            sum.add(0.5 * len * (integrand(k, n, m) + integrand(k + 1, n, m)));
        }
    }
    let e_prime = mat.e_prime();
    (0.5 * e_prime * sums[0].value(), 0.5 * e_prime * sums[1].value())
}

impl TipResult {
    /// The row of a tip where J could not be evaluated: position known, the rest NaN.
    pub fn unavailable(time: f64, crack: usize, end: TipEnd, tip: Vector) -> Self {
        let nan = f64::NAN;
        let n = Vector::new(nan, nan);
        TipResult { time, crack, end, tip, direction: n, j1: nan, j2: nan, j1_line: nan, j2_line: nan, delta_i: nan, delta_ii: nan, k1: nan, k2: nan }
    }

    pub const HEADER: &'static str = "time,crack,tip,x,y,dir_x,dir_y,j1,j2,j1_line,j2_line,delta_i,delta_ii,k1,k2";

    /// One row of cracks.csv (`{:e}` round-trips f64 exactly).
    pub fn csv(&self) -> String {
        let end = match self.end {
            TipEnd::Start => "start",
            TipEnd::End => "end",
        };
        format!(
            "{:e},{},{},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e}",
            self.time, self.crack, end, self.tip.x, self.tip.y, self.direction.x, self.direction.y, self.j1, self.j2, self.j1_line, self.j2_line, self.delta_i, self.delta_ii, self.k1, self.k2
        )
    }
}

impl Simulation {
    /// J, K at one tip of crack `c` after the last completed step, with the crack moving at
    /// `speed` (0 for a stationary crack).
    pub fn tip_fracture(&self, c: usize, end: TipEnd, contour: usize, area_term: bool, cod: CodMethod, speed: f64) -> Result<TipResult, FractureError> {
        let (tip, d, e2, _) = self.tip_frame(c, end);
        // The face at θ = +π (upper, +x₂′): `above` at the end tip, `below` at the start tip.
        let upper_is_above = end == TipEnd::End;

        let path = self.contour_nodes(c, end, tip, d + e2, contour)?;
        let pts = self.cut_contour(c, end, tip, &path, upper_is_above)?;

        // Line term, eq. 12: trapezoidal rule per segment with the segment's outward normal.
        let mut jx = ExactSum::new();
        let mut jy = ExactSum::new();
        for w in pts.windows(2) {
            let seg = w[1].x - w[0].x;
            let len = seg.norm();
            if len == 0.0 {
                continue;
            }
            let n = Vector::new(seg.y, -seg.x) / len;
            let f = (integrand(&w[0].state, n) + integrand(&w[1].state, n)) * (0.5 * len);
            jx.add(f.x);
            jy.add(f.y);
        }
        let j_line = Vector::new(jx.value(), jy.value());
        let j_area = if area_term { self.area_term(&path) } else { Vector::zeros() };
        self.tip_result(c, end, j_line, j_area, cod, speed, Some(&pts))
    }

    /// The tip of crack c at `end`, its unit direction e₁′ (along the last segment, out of
    /// the tip), e₂′ (e₁′ turned 90° counter-clockwise) and the index of the crack particle
    /// next to it.
    fn tip_frame(&self, c: usize, end: TipEnd) -> (Vector, Vector, Vector, usize) {
        let crack = &self.cracks[c];
        let np = crack.points.len();
        let (tip, prev, next_to_tip) = match end {
            TipEnd::End => (crack.points[np - 1], crack.points[np - 2], np - 2),
            TipEnd::Start => (crack.points[0], crack.points[1], 1),
        };
        let d = (tip - prev).normalize();
        (tip, d, Vector::new(-d.y, d.x), next_to_tip)
    }

    /// The row of a tip from its J (line term and area term, global components): J₁, J₂
    /// in the tip's frame, the crack-opening displacements and the K split (eqs. 14–15).
    /// With [`CodMethod::Interaction`] and the cut contour `pts`, G is split in the
    /// interaction integral's K_I : K_II ratio (the magnitude stays J's, the energy the
    /// discrete crack releases); without `pts` (the circle) by the opening next to the tip.
    #[allow(clippy::too_many_arguments)]
    fn tip_result(&self, c: usize, end: TipEnd, j_line: Vector, j_area: Vector, cod: CodMethod, speed: f64, pts: Option<&[ContourPoint]>) -> Result<TipResult, FractureError> {
        let crack = &self.cracks[c];
        let (tip, d_segment, _, next_to_tip) = self.tip_frame(c, end);
        // The interaction integral's frame is the chord from the contour's cut on the
        // crack to the tip (CodMethod::Interaction); the others keep the last segment's.
        let d = match (cod, pts) {
            (CodMethod::Interaction, Some(pts)) => chord_direction(tip, pts[0].x).unwrap_or(d_segment),
            _ => d_segment,
        };
        let e2 = Vector::new(-d.y, d.x);
        let upper_is_above = end == TipEnd::End;
        let j = j_line + j_area;

        // Crack-opening displacements: fitted behind the tip, or at the crack particle
        // next to it.
        let fitted = match cod {
            CodMethod::Fit => self.fitted_opening(c, end),
            CodMethod::NextToTip | CodMethod::Interaction => None,
        };
        let (delta_i, delta_ii) = fitted.unwrap_or_else(|| {
            let opening = crack.opening(next_to_tip);
            let delta = if upper_is_above { opening } else { -opening };
            (delta.dot(&e2), delta.dot(&d))
        });

        let mat = self.material_near(tip).ok_or(FractureError::NoMaterial { crack: c })?;
        let sf = speed_factors_for(mat, speed).map_err(|source| FractureError::Speed { crack: c, end, source })?;
        let g = j.dot(&d);
        let (s1, s2) = match (cod, pts) {
            (CodMethod::Interaction, Some(pts)) => interaction_k(pts, tip, d, e2, mat),
            _ => (delta_i, delta_ii),
        };
        let (k1, k2) = partition_k(g, s1, s2, mat.shear_modulus(), sf.beta_d, sf.beta_s, sf.a_i, sf.a_ii);
        Ok(TipResult {
            time: self.time,
            crack: c,
            end,
            tip,
            direction: d,
            j1: g,
            j2: j.dot(&e2),
            j1_line: j_line.dot(&d),
            j2_line: j_line.dot(&e2),
            delta_i,
            delta_ii,
            k1,
            k2,
        })
    }

    /// [`CodMethod::Fit`]: the leading terms a₁√h of the least-squares fits of the
    /// opening's normal and sliding components to a₁ r^½ + a₃ r^{3/2} + a₅ r^{5/2} over
    /// the crack particles whose arc length r from the tip lies in
    /// [[`FIT_FROM`] h, [`FIT_TO`] h] and within half the crack's length, each
    /// resolved along its local tangent (pointing toward the tip) and normal. None if
    /// fewer than three particles are in the window or the fit is singular.
    fn fitted_opening(&self, c: usize, end: TipEnd) -> Option<(f64, f64)> {
        let crack = &self.cracks[c];
        let np = crack.points.len();
        let h = self.grid.h.x.max(self.grid.h.y);
        // The k-th crack particle counting from the tip.
        let from_tip = |k: usize| match end {
            TipEnd::End => np - 1 - k,
            TipEnd::Start => k,
        };
        let length: f64 = crack.points.windows(2).map(|w| (w[1] - w[0]).norm()).sum();
        let (r_from, r_to) = (FIT_FROM * h, (FIT_TO * h).min(0.5 * length));
        // Normal equations of the three-term fit in ρ = r/h, for both components at once.
        let mut ata = nalgebra::Matrix3::<f64>::zeros();
        let mut atb = nalgebra::Matrix3x2::<f64>::zeros();
        let (mut r, mut n) = (0.0, 0);
        for j in 1..np {
            let (prev, k) = (from_tip(j - 1), from_tip(j));
            r += (crack.points[k] - crack.points[prev]).norm();
            if r > r_to {
                break;
            }
            if r < r_from {
                continue;
            }
            // Local tip coordinates at k: e₁ toward the tip along the crack, e₂ to the
            // upper face; δ = upper − lower.
            let t = crack.tangent(k)?;
            let (d, delta) = match end {
                TipEnd::End => (t, crack.opening(k)),
                TipEnd::Start => (-t, -crack.opening(k)),
            };
            let e2 = Vector::new(-d.y, d.x);
            let rho = r / h;
            let basis = nalgebra::Vector3::new(rho.sqrt(), rho.powf(1.5), rho.powf(2.5));
            ata += basis * basis.transpose();
            atb += basis * nalgebra::RowVector2::new(delta.dot(&e2), delta.dot(&d));
            n += 1;
        }
        if n < 3 {
            return None;
        }
        let a = ata.cholesky()?.solve(&atb);
        Some((a[(0, 0)], a[(0, 1)]))
    }

    /// The perimeter nodes of the n×n contour around the node nearest `tip`,
    /// counter-clockwise from the lower-left corner.
    ///
    /// A tip exactly midway between two node lines is a tie; it is broken toward the tip's
    /// own e₁′ + e₂′ (`bias`), so the choice turns with the crack: two tips related by a
    /// rotation of the scene get rotated contours, and symmetric problems stay symmetric.
    fn contour_nodes(&self, c: usize, end: TipEnd, tip: Vector, bias: Vector, n: usize) -> Result<Vec<usize>, FractureError> {
        let g = &self.grid;
        let nearest = |u: f64, b: f64| {
            if u - u.floor() == 0.5 && b != 0.0 {
                if b > 0.0 {
                    u.ceil()
                } else {
                    u.floor()
                }
            } else {
                u.round()
            }
        };
        let ix = nearest((tip.x - g.origin.x) / g.h.x, bias.x) as i64;
        let iy = nearest((tip.y - g.origin.y) / g.h.y, bias.y) as i64;
        let ni = n as i64;
        if n == 0 || ix - ni < 0 || iy - ni < 0 || ix + ni > g.nx as i64 || iy + ni > g.ny as i64 {
            return Err(FractureError::ContourOutsideGrid { crack: c, end, x: tip.x, y: tip.y, n, ix, iy, nx: g.nx, ny: g.ny });
        }
        let (x0, x1, y0, y1) = ((ix - ni) as usize, (ix + ni) as usize, (iy - ni) as usize, (iy + ni) as usize);
        let mut path = Vec::with_capacity(8 * n);
        path.extend((x0..x1).map(|x| g.node_index(x, y0)));
        path.extend((y0..y1).map(|y| g.node_index(x1, y)));
        path.extend((x0 + 1..=x1).rev().map(|x| g.node_index(x, y1)));
        path.extend((y0 + 1..=y1).rev().map(|y| g.node_index(x0, y)));
        Ok(path)
    }

    /// Cut the closed perimeter where it crosses crack `c` and return the open contour
    /// from the lower face round to the upper face, with each point's nodal state.
    fn cut_contour(&self, c: usize, end: TipEnd, tip: Vector, path: &[usize], upper_is_above: bool) -> Result<Vec<ContourPoint>, FractureError> {
        let m = path.len();
        let pos = |k: usize| self.grid.node_pos(path[k % m]);
        // Every crossing as (perimeter segment j, parameter t in [0, 1)), a crossing at a
        // node counted once (t = 1 is the next segment's t = 0), and so is a crack
        // particle lying on the perimeter, which both of its segments meet: hits closer
        // than 1e-9 of a perimeter segment are one crossing.
        let mut hits: Vec<(usize, f64)> = Vec::new();
        let same = |a: (usize, f64), b: (usize, f64)| {
            let d = (a.0 as f64 + a.1 - b.0 as f64 - b.1).abs();
            d.min(m as f64 - d) < 1e-9
        };
        for j in 0..m {
            for s in self.cracks[c].points.windows(2) {
                if let Some((t, _)) = crate::crack::geometry::segment_intersection(pos(j), pos(j + 1), s[0], s[1]) {
                    let hit = if t >= 1.0 { ((j + 1) % m, 0.0) } else { (j, t) };
                    if !hits.iter().any(|&h| same(h, hit)) {
                        hits.push(hit);
                    }
                }
            }
        }
        if hits.len() != 1 {
            return Err(FractureError::Crossings { crack: c, end, x: tip.x, y: tip.y, crossings: hits.len() });
        }
        let (j, t) = hits[0];
        let lower_above = !upper_is_above;
        let states: Vec<[Option<NodalState>; 3]> = (0..m).map(|k| self.nodal_state(path[k])).collect();
        let cut = |above: bool| ContourPoint {
            x: pos(j) + (pos(j + 1) - pos(j)) * t,
            state: lerp(&state_on_face(&states[j], above), &state_on_face(&states[(j + 1) % m], above), t),
        };
        let mut pts = Vec::with_capacity(m + 2);
        pts.push(cut(lower_above));
        for k in 1..=m {
            let node = (j + k) % m;
            // First half of the nodes: the lower face's field; second half: the upper face's.
            let above = if 2 * (k - 1) < m { lower_above } else { upper_is_above };
            pts.push(ContourPoint { x: pos(node), state: state_on_face(&states[node], above) });
        }
        pts.push(cut(upper_is_above));
        Ok(pts)
    }

    /// Area term of eq. 8 over the particles inside the contour's rectangle, in global
    /// coordinates: Σ_p (m_p/B) [a_p·∂u/∂x_m − v_p·∂v/∂x_m], with v_p, a_p and ∂v/∂x from
    /// the nodal fields of the particle's own pairs, a the acceleration without loads,
    /// body forces and damping ([`area_acceleration`]; the module doc: the body-force and
    /// damping terms of J).
    fn area_term(&self, path: &[usize]) -> Vector {
        let g = &self.grid;
        let (mut lo, mut hi) = (g.node_pos(path[0]), g.node_pos(path[0]));
        for &i in path {
            let x = g.node_pos(i);
            lo = lo.inf(&x);
            hi = hi.sup(&x);
        }
        let p = &self.particles;
        let pairs = &self.pairs;
        let nodes = &self.nodes;
        let mut sx = ExactSum::new();
        let mut sy = ExactSum::new();
        let mut acc = [ExactSum::new(), ExactSum::new(), ExactSum::new(), ExactSum::new()];
        let mut grad = [ExactSum::new(), ExactSum::new(), ExactSum::new(), ExactSum::new()];
        for i in 0..p.len() {
            let x = p.x[i];
            if x.x < lo.x || x.x > hi.x || x.y < lo.y || x.y > hi.y {
                continue;
            }
            acc.iter_mut().chain(grad.iter_mut()).for_each(ExactSum::clear);
            let base = i * MAX_NODES;
            for k in base..base + pairs.count[i] as usize {
                let fa = &nodes.fields[pairs.field[k] as usize];
                let node = pairs.node[k] as usize;
                let m = fa.mass[node];
                let (mut v, mut a) = (fa.mom[node] / m, area_acceleration(fa, node, self.options.damping));
                if pairs.frac[k] != 1.0 {
                    // A pair in a crack-tip zone: its two fields in their shares (crack::tip_zone).
                    let (w, fb) = (pairs.frac[k], &nodes.fields[0]);
                    v = v * w + fb.mom[node] / fb.mass[node] * (1.0 - w);
                    a = a * w + area_acceleration(fb, node, self.options.damping) * (1.0 - w);
                }
                let (s, gr) = (pairs.s[k], pairs.g[k]);
                acc[0].add(s * a.x);
                acc[1].add(s * a.y);
                acc[2].add(s * v.x);
                acc[3].add(s * v.y);
                grad[0].add(v.x * gr.x);
                grad[1].add(v.x * gr.y);
                grad[2].add(v.y * gr.x);
                grad[3].add(v.y * gr.y);
            }
            let a = Vector::new(acc[0].value(), acc[1].value());
            let v = Vector::new(acc[2].value(), acc[3].value());
            let grad_v = Tensor::new(grad[0].value(), grad[1].value(), grad[2].value(), grad[3].value());
            let w = p.mass[i] / self.thickness[p.body[i] as usize];
            let f = (p.grad_u[i].transpose() * a - grad_v.transpose() * v) * w;
            sx.add(f.x);
            sy.add(f.y);
        }
        Vector::new(sx.value(), sy.value())
    }

    /// The material of the particle nearest to `x` (ties: lowest id).
    fn material_near(&self, x: Vector) -> Option<&LinearElastic> {
        let p = &self.particles;
        (0..p.len())
            .min_by(|&a, &b| (p.x[a] - x).norm_squared().total_cmp(&(p.x[b] - x).norm_squared()).then(p.id[a].cmp(&p.id[b])))
            .map(|i| &self.materials[p.material[i] as usize])
    }

    /// J, K at one tip as `req` asks: the rectangular contour of [`Simulation::tip_fracture`],
    /// or, with `req.circle`, the line term on the circle of that radius
    /// ([`Simulation::circle_j_2d`], the 3D front contour) with the same opening and split.
    pub fn tip_fracture_request(&self, c: usize, end: TipEnd, req: &JRequest, speed: f64) -> Result<TipResult, FractureError> {
        let Some(radius) = req.circle else { return self.tip_fracture(c, end, req.contour, req.area_term, req.cod, speed) };
        let (_, d, e2, _) = self.tip_frame(c, end);
        let (j1, j2) = self.circle_j_2d(c, end, radius, 16);
        self.tip_result(c, end, d * j1 + e2 * j2, Vector::zeros(), req.cod, speed, None)
    }

    /// Fracture parameters at every requested tip (`requests[c]` for crack c), with each
    /// growing tip's current speed estimate in the K partition when its crack's
    /// `speed_correction` asks for it (0 otherwise, and for a stationary crack).
    pub fn fracture_parameters(&self, requests: &[Option<JRequest>]) -> Result<Vec<TipResult>, FractureError> {
        let mut out = Vec::new();
        for (c, r) in requests.iter().enumerate() {
            if let Some(r) = r {
                for &end in &r.tips {
                    let speed = self.growth.as_ref().map_or(0.0, |g| g.tip_k_speed(c, end, self.time));
                    let grows = self.growth.as_ref().is_some_and(|g| g.grows(c));
                    match self.tip_fracture_request(c, end, r, speed) {
                        Ok(t) => out.push(t),
                        // A growing crack may curve through its contour or reach the grid's
                        // edge: a row of NaN then (growth.csv says why); a stationary one
                        // whose contour fails is an error in the scene.
                        Err(FractureError::ContourOutsideGrid { .. } | FractureError::Crossings { .. }) if grows => {
                            out.push(TipResult::unavailable(self.time, c, end, self.tip_of(c, end)));
                        }
                        Err(e) => return Err(e),
                    }
                }
            }
        }
        Ok(out)
    }
}

/// The acceleration of the J-integral's area term at one field of one node: the total
/// force of the last step (eq. 2, after contact) less the loads and body forces and less
/// the damping force −κp, over the mass — (∇·σ)/ρ plus the crack-face contact (module
/// doc, "Which acceleration").
pub fn area_acceleration<V: crate::dim::VectorOps>(fa: &crate::grid::FieldArrays<V>, node: usize, kappa: f64) -> V {
    (fa.ftot[node] - fa.fext[node] + fa.mom[node] * kappa) / fa.mass[node]
}

/// Eqs. 14–15 of Guo & Nairn 2004 (β labels as in [`crate::fracture::speed`]: the
/// paper's β_I is β_d and β_II is β_s):
/// K_I = δ_I √(2μGβ_s / (A_I (δ_I²β_s + δ_II²β_d))), K_II = δ_II √(2μGβ_d / (A_II (δ_I²β_s + δ_II²β_d))),
/// so that G = (A_I K_I² + A_II K_II²)/(2μ) and, for a stationary crack,
/// K_I = (δ_I/δ)√(E′G) (eq. 21). A closed crack (δ = 0) or G ≤ 0 gives K = 0: the split is
/// undefined there, and J itself is reported alongside.
#[allow(clippy::too_many_arguments, clippy::neg_cmp_op_on_partial_ord)]
pub fn partition_k(g: f64, delta_i: f64, delta_ii: f64, mu: f64, beta_d: f64, beta_s: f64, a_i: f64, a_ii: f64) -> (f64, f64) {
    let denom = delta_i * delta_i * beta_s + delta_ii * delta_ii * beta_d;
    if !(g > 0.0) || !(denom > 0.0) {
        return (0.0, 0.0);
    }
    let k1 = delta_i * (2.0 * mu * g * beta_s / (a_i * denom)).sqrt();
    let k2 = delta_ii * (2.0 * mu * g * beta_d / (a_ii * denom)).sqrt();
    (k1, k2)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::PlaneState;

    /// The exact Williams field K_I = 1.3, K_II = −0.4 in a frame turned by 30°, sampled on
    /// a square contour of half-size 2 around the tip cut by the crack on the left:
    /// the interaction integral returns both K to the trapezoidal rule's error.
    #[test]
    fn interaction_integral_recovers_a_williams_field() {
        use crate::fracture::williams::{williams_aux, williams_displacement};
        let m = LinearElastic { e: 1000.0, nu: 0.3, rho: 1e-3, state: PlaneState::PlaneStrain };
        let (mu, kappa) = (m.shear_modulus(), m.kappa());
        let (k1, k2) = (1.3, -0.4);
        let (sa, ca) = 30f64.to_radians().sin_cos();
        let (d, e2, tip) = (Vector::new(ca, sa), Vector::new(-sa, ca), Vector::new(0.7, -0.2));
        let q = nalgebra::Matrix2::new(d.x, d.y, e2.x, e2.y);
        // Local field at local point xl (θ given so the faces are ±π exactly).
        let u_local = |xl: Vector, theta: f64| williams_displacement(1, xl.norm(), theta, mu, kappa) * k1 + williams_displacement(2, xl.norm(), theta, mu, kappa) * k2;
        let state = |xl: Vector, theta: f64| {
            let (s1, _) = williams_aux(1, xl.norm(), theta, mu, kappa);
            let (s2, _) = williams_aux(2, xl.norm(), theta, mu, kappa);
            let sl = nalgebra::Matrix2::new(k1 * s1[0] + k2 * s2[0], k1 * s1[2] + k2 * s2[2], k1 * s1[2] + k2 * s2[2], k1 * s1[1] + k2 * s2[1]);
            // ∇u by central differences in the local frame, columns ∂/∂x1, ∂/∂x2.
            let hfd = 1e-6;
            let th = |x: Vector| if (theta.abs() - std::f64::consts::PI).abs() < 1e-12 { theta } else { x.y.atan2(x.x) };
            let dx = |e: Vector| (u_local(xl + e * hfd, th(xl + e * hfd)) - u_local(xl - e * hfd, th(xl - e * hfd))) / (2.0 * hfd);
            let (c1, c2) = (dx(Vector::new(1.0, 0.0)), dx(Vector::new(0.0, 1.0)));
            let gl = nalgebra::Matrix2::new(c1.x, c2.x, c1.y, c2.y);
            let sg = q.transpose() * sl * q;
            NodalState { stress: Sym { xx: sg[(0, 0)], yy: sg[(1, 1)], zz: 0.0, xy: sg[(0, 1)] }, grad_u: q.transpose() * gl * q, ..Default::default() }
        };
        // Counter-clockwise in the local frame from the lower face (−2, 0⁻) to the upper one.
        let n = 400;
        let corners = [Vector::new(-2.0, 0.0), Vector::new(-2.0, -2.0), Vector::new(2.0, -2.0), Vector::new(2.0, 2.0), Vector::new(-2.0, 2.0), Vector::new(-2.0, 0.0)];
        let mut pts = Vec::new();
        for (w, side) in corners.windows(2).enumerate() {
            let steps = if w == 0 || w == 4 { n / 2 } else { n };
            for k in 0..steps + usize::from(w == 4) {
                let xl = side[0] + (side[1] - side[0]) * (k as f64 / steps as f64);
                let theta = if pts.is_empty() { -std::f64::consts::PI } else if w == 4 && k == steps { std::f64::consts::PI } else { xl.y.atan2(xl.x) };
                pts.push(ContourPoint { x: tip + q.transpose() * xl, state: state(xl, theta) });
            }
        }
        let (i1, i2) = interaction_k(&pts, tip, d, e2, &m);
        assert!((i1 - k1).abs() < 2e-3 * k1.abs() && (i2 - k2).abs() < 2e-3 * k1.abs(), "K_I {i1} (exact {k1}), K_II {i2} (exact {k2})");
    }

    #[test]
    fn stationary_partition_reduces_to_eq_21() {
        // Plane stress: K = (δ/|δ|)√(EG) for each mode.
        let m = LinearElastic { e: 2300.0, nu: 0.33, rho: 1.5e-3, state: PlaneState::PlaneStress };
        let sf = speed_factors_for(&m, 0.0).unwrap();
        let (g, di, dii) = (0.01, 3.0e-3, 4.0e-3);
        let (k1, k2) = partition_k(g, di, dii, m.shear_modulus(), sf.beta_d, sf.beta_s, sf.a_i, sf.a_ii);
        let k = (m.e * g).sqrt();
        approx::assert_relative_eq!(k1, 0.6 * k, max_relative = 1e-14);
        approx::assert_relative_eq!(k2, 0.8 * k, max_relative = 1e-14);
    }

    #[test]
    fn moving_partition_returns_g() {
        // G = (A_I K_I² + A_II K_II²)/(2μ) for any speed below c_R (references §7).
        let m = LinearElastic { e: 2940.0, nu: 0.3, rho: 1.19e-3, state: PlaneState::PlaneStrain };
        let sf = speed_factors_for(&m, 0.4 * m.shear_wave_speed()).unwrap();
        let (g, di, dii) = (0.02, 1.0e-3, -2.5e-4);
        let (k1, k2) = partition_k(g, di, dii, m.shear_modulus(), sf.beta_d, sf.beta_s, sf.a_i, sf.a_ii);
        approx::assert_relative_eq!(sf.energy_release_rate(k1, k2, m.shear_modulus()), g, max_relative = 1e-14);
        assert!(k1 > 0.0 && k2 < 0.0);
    }

    #[test]
    fn closed_crack_or_negative_g_gives_zero_k() {
        assert_eq!(partition_k(1.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0, 1.0), (0.0, 0.0));
        assert_eq!(partition_k(-1e-20, 1.0, 0.0, 1.0, 1.0, 1.0, 1.0, 1.0), (0.0, 0.0));
    }
}
