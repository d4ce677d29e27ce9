//! Cohesive new segments (2D; issue 20 item 2): a traction–separation law on the crack
//! segments that growth adds, a modelling choice beyond the papers, off by default
//! (`cracks[].fracture.growth.cohesive`).
//!
//! Why: the papers' growth step (001 §2.3.2) frees the material across a new segment at
//! once. Nothing in the discrete crack consumes energy, so the run's own energy balance
//! W_ext + W_b − U − T − D stays constant while the crack grows: the energy the far field
//! gives up rings in the freed faces, and the criterion's J is not the energy released
//! (case `growth_j`, papers' release: G ≈ −0.01 G_c). A timed release of the faces
//! ([`crate::fracture::release`]) consumes energy, but what it consumes is set by its
//! timing, not by the material: under a criterion it gave J/G − 1 = +57 … +88 % in the
//! DCB's bursts. A cohesive zone makes the energy consumed per unit of new crack the
//! material's G_c by construction, and the J-integral around a contour that encloses the
//! zone is the work of its tractions (Rice 1968, J = ∫₀^δ_t T dδ): J = G in steady growth.
//!
//! **Law** (triangular; Hillerborg, Modéer & Petersson 1976 for the softening, Camacho &
//! Ortiz 1996 for the effective opening and the explicit setting), on the effective opening
//! λ = √(⟨δ_n⟩² + δ_t²) (⟨δ_n⟩ the normal opening where positive, δ_t the sliding):
//!   T(δ) = k δ                                   0 ≤ δ ≤ δ_p   (rising, k = ρ c_d²/h)
//!   T(δ) = σ_c (δ_c − δ)/(δ_c − δ_p)              δ_p < δ < δ_c (softening)
//!   T(δ) = 0                                     δ ≥ δ_c       (free faces)
//! with σ_c the scene's `strength`, δ_p = σ_c/k and δ_c = 2 G_c/σ_c so that the area
//! under the law is G_c = K_Ic²/E' of the material (plane stress E' = E, plane strain
//! E/(1 − ν²)), in any mode under proportional opening. The traction is the secant
//! stiffness of the largest effective opening reached, s = T(λ_max)/λ_max (k on the
//! rising part), times the opening: T_n = s⟨δ_n⟩, T_t = s δ_t — the law unloads linearly
//! to the origin (damage: no healing), and a closed segment carries no normal traction
//! (closing faces are crack contact's business) but keeps its shear stiffness until it
//! has softened. The rising stiffness k = ρ c_d²/h (P-wave modulus
//! over one cell) is the stiffness of one cell of the material across the segment: a
//! segment before its peak is about as stiff as the material it replaced, and the pair of
//! fields it joins stays within the explicit step's stability limit at every CFL number
//! the solver accepts. The same k in sliding (stiffer than one cell's shear, μ/h, and as
//! stable) keeps a new segment from sliding before it softens: a free-sliding seed turned
//! the mode II kink of `mode_ii_kink` by a further −47° at its second check.
//!
//! **Where it acts.** Every crack particle (vertex) of a cohesive segment carries the
//! traction of its own opening (above − below in the crack's normal n̂ and tangent t̂ at
//! the particle; the tracked surfaces, 004 §2.1) over its tributary length w (half of each
//! neighbouring cohesive segment) times the body's thickness: a force F = (T_n n̂ + T_t t̂)
//! w t. Like a crack particle's contribution to anything on the grid, F goes to the nodes
//! of the cell holding the vertex with linear weights N_i, on the above field as −F N_i
//! and on the below field as +F N_i
//! (equal and opposite: momentum is conserved and every node's total force unchanged; a
//! node with a single field gets nothing). The forces are added to Task 3's before the
//! fixed directions are zeroed, so a held node keeps its condition and its reaction
//! includes them. Their work, −F (v_a − v_b)·n̂ summed, is the energy the zone consumes:
//! the run's balance falls by it.
//!
//! **When the tip advances.** With a cohesive law the crack's polyline tip is the leading
//! edge of the cohesive zone. At each growth evaluation a tip advances by the increment
//! when the crack particle one increment behind it (the previous tip) has reached the
//! law's peak (δ_max ≥ δ_p: the material there carried σ_c) — a strength criterion at
//! the zone's front, the zone's own, in place of K_eq ≥ K_Ic. A tip with no cohesive
//! segment yet is seeded with one at its first check with the tip loaded (K_eq > 0), in
//! the direction θ_c of that first load: the seed, before its peak, is about as stiff as
//! the material it replaced (a load whose mode mix turns later turns the following
//! segments, not the seed). The direction is the material criterion's θ_c
//! from K_I, K_II (001 eqs. 18–19) and the Rayleigh speed and `max_speed` still limit the
//! tip.
//!
//! **Resolution.** The zone, about E′G_c/σ_c² long, must span a few cells and lie inside
//! the J contour; σ_c is then a regularisation far below a real material's strength.
//! Measured (case `growth_j`; J/G − 1 per burst, G from the run's own balance): DCB
//! (quasi-static bursts) at σ_c = 3 MPa, 2 and 1 mm, within −0.4 … +4.8 %; PMMA beam
//! under impact at 2 mm, σ_c = 20 MPa (zone 1.8 cells) +16 %, at 1 mm −4.4 %; σ_c = 15
//! MPa (3.2 cells) at 2 mm −0.5 %. With a zone the DCB restarts about one zone length
//! shorter than corrected beam theory's LEFM length (the zone adds compliance).
use crate::crack::side_field;
use crate::dim::Vector;
use crate::shape::{self, ShapeKind};
use crate::simulation::Simulation;

/// `growth.cohesive` of a crack.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CohesiveSettings {
    /// Peak traction σ_c.
    pub strength: f64,
}

/// The triangular law of one material: peak σ_c at δ_p, zero at δ_c.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CohesiveLaw {
    pub strength: f64,
    pub delta_p: f64,
    pub delta_c: f64,
}

impl CohesiveLaw {
    /// The law of strength `strength` with toughness `g_c` (area under the law) on a
    /// material of P-wave modulus `m` (ρ c_d²) and a grid of cell `h`; Err when the
    /// rising part would reach past half of δ_c (the cell is too coarse for the zone).
    pub fn new(strength: f64, g_c: f64, m: f64, h: f64) -> Result<Self, String> {
        let delta_p = strength * h / m;
        let delta_c = 2.0 * g_c / strength;
        if !(delta_p <= 0.5 * delta_c) {
            return Err(format!(
                "too strong for the cell: the law's opening at its peak, σ_c h/(ρ c_d²) = {delta_p:.4e}, must be at most half its final opening 2 G_c/σ_c = {delta_c:.4e} \
                 (σ_c ≤ √(G_c ρ c_d²/h) = {:.4e}); lower the strength or refine the grid",
                (g_c * m / h).sqrt()
            ));
        }
        Ok(CohesiveLaw { strength, delta_p, delta_c })
    }

    /// The envelope T(δ) for δ ≥ 0 (module doc).
    fn envelope(&self, delta: f64) -> f64 {
        if delta <= self.delta_p {
            self.strength * delta / self.delta_p
        } else if delta < self.delta_c {
            self.strength * (self.delta_c - delta) / (self.delta_c - self.delta_p)
        } else {
            0.0
        }
    }

    /// Secant stiffness after the largest effective opening `lambda_max`: k while it is
    /// on the rising part (or unloaded), T(λ_max)/λ_max once softening, 0 once free.
    pub fn secant(&self, lambda_max: f64) -> f64 {
        if lambda_max <= self.delta_p {
            self.strength / self.delta_p
        } else {
            self.envelope(lambda_max) / lambda_max
        }
    }

    /// Normal traction at normal opening `delta` in pure mode I with largest opening so
    /// far `delta_max` ≥ `delta` (≥ 0 resists opening; 0 when closed or fully open).
    pub fn traction(&self, delta: f64, delta_max: f64) -> f64 {
        self.secant(delta_max.max(delta)) * delta.max(0.0)
    }
}

/// The cohesive segments of one crack.
#[derive(Clone, Debug, PartialEq)]
pub struct CohesiveZone {
    pub crack: usize,
    /// Per segment of the crack's polyline (points k, k+1): its law and thickness when
    /// growth added it, None for the segments of the initial crack.
    pub segments: Vec<Option<(CohesiveLaw, f64)>>,
    /// Per crack particle: the largest normal opening reached (0 until loaded).
    pub delta_max: Vec<f64>,
}

impl CohesiveZone {
    pub fn new(crack: usize, points: usize) -> Self {
        CohesiveZone { crack, segments: vec![None; points.saturating_sub(1)], delta_max: vec![0.0; points] }
    }

    /// A segment was added at the start (`at_start`) or the end of the polyline.
    pub fn added(&mut self, at_start: bool, law: CohesiveLaw, thickness: f64) {
        if at_start {
            self.segments.insert(0, Some((law, thickness)));
            self.delta_max.insert(0, 0.0);
        } else {
            self.segments.push(Some((law, thickness)));
            self.delta_max.push(0.0);
        }
    }

    /// Has the tip at the start (`at_start`) or end a cohesive segment, and has the crack
    /// particle one segment behind the tip reached the law's peak? None: no cohesive
    /// segment at that tip yet.
    pub fn tip_ready(&self, at_start: bool) -> Option<bool> {
        let n = self.segments.len();
        let (seg, behind) = if at_start { (0, 1) } else { (n.checked_sub(1)?, n.checked_sub(1)?) };
        let (law, _) = self.segments.get(seg).copied().flatten()?;
        Some(self.delta_max[behind] >= law.delta_p)
    }
}

impl Simulation {
    /// Add the cohesive tractions to Task 3's forces (module doc); first update each
    /// cohesive crack particle's largest opening. Serial over the crack particles in
    /// order: the sums do not depend on particle order or threads.
    pub(crate) fn apply_cohesive(&mut self) {
        let Some(growth) = self.growth.as_mut() else { return };
        if growth.cohesive.is_empty() {
            return;
        }
        let mut zones = std::mem::take(&mut growth.cohesive);
        let mut pairs: Vec<(usize, Vector, Vector)> = Vec::new();
        for zone in zones.iter_mut() {
            let c = zone.crack;
            let crack = &self.cracks[c];
            let n = crack.points.len();
            debug_assert_eq!(zone.segments.len() + 1, n, "crack {c}: the cohesive zone's segments follow the polyline");
            for k in 0..n {
                let left = if k > 0 { zone.segments[k - 1] } else { None };
                let right = if k + 1 < n { zone.segments[k] } else { None };
                if left.is_none() && right.is_none() {
                    continue;
                }
                let (dn, ds) = crack.opening_nt(k);
                let lambda = (dn.max(0.0) * dn.max(0.0) + ds * ds).sqrt();
                zone.delta_max[k] = zone.delta_max[k].max(lambda);
                let Some(t) = crack.tangent(k) else { continue };
                let n_above = Vector::new(-t.y, t.x);
                // Secant stiffness times tributary length and thickness, from each side's law.
                let mut stiffness = 0.0;
                if let Some((law, thick)) = left {
                    stiffness += law.secant(zone.delta_max[k]) * 0.5 * (crack.points[k] - crack.points[k - 1]).norm() * thick;
                }
                if let Some((law, thick)) = right {
                    stiffness += law.secant(zone.delta_max[k]) * 0.5 * (crack.points[k + 1] - crack.points[k]).norm() * thick;
                }
                let f = (n_above * dn.max(0.0) + t * ds) * stiffness;
                if f == Vector::zeros() {
                    continue;
                }
                pairs.push((c, crack.points[k], f));
            }
        }
        self.growth.as_mut().expect("growth").cohesive = zones;
        for (c, x, f) in pairs {
            self.spread_pair(c, x, f);
        }
    }

    /// Add −`f` N_i to the above field and +`f` N_i to the below field of the nodes
    /// around `x` (linear shape functions, as Task 7 reads the grid at a crack particle),
    /// where crack `c` split the node.
    fn spread_pair(&mut self, c: usize, x: Vector, f: Vector) {
        let w = shape::weights(&self.grid, ShapeKind::Linear, &x, &Vector::zeros());
        let nodes = &mut self.nodes;
        for (&node, &s) in w.node[..w.n].iter().zip(&w.s[..w.n]) {
            let i = node as usize;
            let (present, node_crack) = (nodes.present[i], nodes.crack[i]);
            let (Some(a), Some(b)) = (side_field(present, node_crack, c, true, || 0), side_field(present, node_crack, c, false, || 0)) else { continue };
            if a == b {
                continue;
            }
            nodes.fields[a].ftot[i] -= f * s;
            nodes.fields[b].ftot[i] += f * s;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_law_encloses_g_c_and_unloads_to_the_origin() {
        // σ_c = 2, G_c = 0.01, ρc_d² = 1000, h = 1: δ_p = 0.002, δ_c = 0.01.
        let law = CohesiveLaw::new(2.0, 0.01, 1000.0, 1.0).unwrap();
        assert!((law.delta_p - 0.002).abs() < 1e-15 && (law.delta_c - 0.01).abs() < 1e-15);
        // Area under the envelope (trapezoid rule is exact on the piecewise-linear law
        // with a node at δ_p).
        let n = 1000;
        let d = law.delta_c / n as f64;
        let area: f64 = (0..n).map(|i| 0.5 * d * (law.traction(i as f64 * d, i as f64 * d) + law.traction((i + 1) as f64 * d, (i + 1) as f64 * d))).sum();
        assert!((area - 0.01).abs() < 1e-12, "area {area}");
        assert_eq!(law.traction(law.delta_p, law.delta_p), 2.0);
        // Unloading from δ_max = 0.006 (T = 1) is linear to the origin; closed: nothing.
        assert!((law.traction(0.003, 0.006) - 0.5).abs() < 1e-12);
        assert_eq!(law.traction(-1e-3, 0.006), 0.0);
        assert_eq!(law.traction(0.02, 0.02), 0.0);
    }

    #[test]
    fn a_law_too_strong_for_the_cell_is_refused() {
        // δ_p = 0.02 > δ_c/2 = 0.005.
        let e = CohesiveLaw::new(20.0, 0.05, 1000.0, 1.0).unwrap_err();
        assert!(e.contains("too strong for the cell"), "{e}");
    }

    #[test]
    fn the_tip_is_ready_once_the_particle_behind_it_peaked() {
        let law = CohesiveLaw::new(2.0, 0.01, 1000.0, 1.0).unwrap();
        let mut z = CohesiveZone::new(0, 2);
        assert_eq!(z.tip_ready(false), None);
        z.added(false, law, 1.0);
        assert_eq!(z.tip_ready(false), Some(false));
        z.delta_max[1] = 0.002;
        assert_eq!(z.tip_ready(false), Some(true));
        assert_eq!(z.tip_ready(true), None);
    }
}
