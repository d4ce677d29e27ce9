//! Gradual release of a new crack segment (2D; issue 20 item 2): a modelling choice
//! beyond the papers, off by default (`cracks[].fracture.growth.release`).
//!
//! The papers' growth step (001 §2.3.2) adds a segment of one increment at once: the
//! material across it, which carried the crack-tip stresses, is freed in one step. With
//! nothing in the discrete crack to take up the energy the far field gives up, it stays in
//! the body as the freed faces' ringing, and the two-term J of a tip moving at a steady,
//! prescribed speed reads 0.71, 0.54, 0.38 × 2H·W0 at 0.2, 0.4, 0.6 c_R (case
//! `growth_strip_j`, the exact G of the pre-strained strip being 2H·W0): the run's own
//! energy balance releases nothing (W − U − T − D stays constant), so J of a growing crack
//! is not the energy the crack consumes. Dynamic finite-element crack propagation has the
//! same problem and the classical remedy, node release (Kobayashi, Mall, Urabe & Emery,
//! 1978; Rydholm, Fredriksson & Nilsson, 1978; Nishioka & Atluri, 1980): the faces of the
//! new segment are held by a closing force that vanishes over the time the tip takes to
//! cross it; the work of that force leaves the body and is the fracture energy.
//!
//! Here the faces of a segment are the two velocity fields of the nodes it splits. At
//! every node with two fields whose nearest crack segment is still in release, with
//! s ∈ [0, 1] the segment's released fraction (time since it was added over its release
//! time) and m_red = m_a m_b/(m_a + m_b), Task 3's forces of the two fields become
//!   f_a ← f_a − (1 − s) m_red [(f_a/m_a − f_b/m_b) + γ (v_a − v_b)],   f_b ← f_b + (…),
//! i.e. the fields' relative acceleration is scaled by s and their relative velocity is
//! damped at the rate (1 − s)γ: at s = 0 the node moves as uncracked material, at s = 1 as
//! the papers' free faces. The two forces are equal and opposite (momentum is conserved,
//! the node's total force unchanged); their work is negative (they oppose the opening),
//! so the run's energy balance W − U − T − D falls by the energy the crack consumed.
//!
//! Timing ([`ReleaseSettings::timing`]): a segment is released over the time the tip takes
//! to cross `length` cells at its speed estimate (this increment included), the speed
//! taken at least 0.2 c_R (a slow or first increment is released within 5·length cells
//! over c_R, so quasi-static growth is not held); γ = `damping` × c_d/h.
//!
//! Measured (`examples/strip_j.rs`, growth_strip at h = 1 mm, contour 5 cells, defaults
//! length 4, damping 1): J/(2H·W0) and the run's own G = −Δ(W − U − T − D)/(2H·W0 Δa) over
//! the steady window 0.971 / 0.938 at 0.2 c_R, 0.951 / 0.937 at 0.6 c_R (papers' sudden
//! release: J 0.71, 0.38, G ≈ 0). The contour must enclose most of the held faces (J of
//! a cohesive zone is its dissipation when the contour encloses it, Rice 1968): with the
//! 2-cell contour J reads 0.84–0.93. Case `growth_strip_j` has the checks.
use crate::simulation::Simulation;

/// Default cells the tip crosses while a segment is released.
pub const DEFAULT_LENGTH: f64 = 4.0;
/// Default damping of the held faces' relative velocity, in units of c_d/h.
pub const DEFAULT_DAMPING: f64 = 1.0;
/// The slowest tip speed a release is timed by, as a fraction of c_R.
pub const MIN_SPEED: f64 = 0.2;

/// `growth.release` of a crack.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ReleaseSettings {
    /// Cells the tip crosses while a new segment is released.
    pub length: f64,
    /// Damping of the held faces' relative velocity, in units of c_d/h.
    pub damping: f64,
}

impl ReleaseSettings {
    /// Release time and damping rate of a segment added by a tip of speed estimate
    /// `speed` (this increment included) on a grid of cell `h`, in a material of Rayleigh
    /// speed `c_r` and dilatational speed `c_d`.
    pub fn timing(&self, h: f64, speed: f64, c_r: f64, c_d: f64) -> (f64, f64) {
        let v = if speed.is_finite() { speed.max(MIN_SPEED * c_r) } else { c_r };
        (self.length * h / v, self.damping * c_d / h)
    }
}

/// A new crack segment whose faces are still held.
#[derive(Clone, Debug, PartialEq)]
pub struct Release {
    pub crack: usize,
    /// The segment's index in the crack's polyline (between points `segment` and
    /// `segment + 1`; kept current when points are inserted before it).
    pub segment: usize,
    /// When it was added, how long its release lasts, and the damping rate γ.
    pub t0: f64,
    pub duration: f64,
    pub rate: f64,
}

impl Release {
    /// Fraction released at time `t` (0 just after the segment is added, 1 once freed).
    pub fn fraction(&self, t: f64) -> f64 {
        if self.duration > 0.0 {
            ((t - self.t0) / self.duration).clamp(0.0, 1.0)
        } else {
            1.0
        }
    }
}

impl Simulation {
    /// Hold the faces of the segments still in release on the forces of Task 3 (module
    /// doc); the releases that have ended are dropped first. Serial over the active
    /// nodes; a node's segment is the nearest of its crack (the first of equals), so the
    /// result does not depend on particle order or threads.
    pub(crate) fn hold_released(&mut self) {
        let Some(growth) = self.growth.as_mut() else { return };
        let t = self.time;
        growth.releases.retain(|r| r.fraction(t) < 1.0);
        if growth.releases.is_empty() {
            return;
        }
        let growth = self.growth.take().expect("growth");
        let nodes = &mut self.nodes;
        for &node in &nodes.active {
            let i = node as usize;
            let (a, b) = match nodes.present[i] {
                0b011 => (0, 1),
                0b101 => (0, 2),
                0b110 => (1, 2),
                _ => continue,
            };
            let c = nodes.crack[i] as usize;
            if !growth.releases.iter().any(|r| r.crack == c) {
                continue;
            }
            let x = self.grid.node_pos(i);
            let points = &self.cracks[c].points;
            let mut best: Option<(f64, usize)> = None;
            for (k, s) in points.windows(2).enumerate() {
                let (d2, _) = crate::crack::nearest_on_segment(s[0], s[1], x);
                if best.is_none_or(|(bd, _)| d2 < bd) {
                    best = Some((d2, k));
                }
            }
            let Some((_, k)) = best else { continue };
            let Some(r) = growth.releases.iter().find(|r| r.crack == c && r.segment == k) else { continue };
            let hold = 1.0 - r.fraction(t);
            let (ma, mb) = (nodes.fields[a].mass[i], nodes.fields[b].mass[i]);
            let (fa, fb) = (nodes.fields[a].ftot[i], nodes.fields[b].ftot[i]);
            let dv = nodes.fields[a].mom[i] / ma - nodes.fields[b].mom[i] / mb;
            let df = (fa / ma - fb / mb + dv * r.rate) * (hold * ma * mb / (ma + mb));
            nodes.fields[a].ftot[i] = fa - df;
            nodes.fields[b].ftot[i] = fb + df;
        }
        self.growth = Some(growth);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn timing_floors_the_speed_and_scales_the_damping() {
        let r = ReleaseSettings { length: 4.0, damping: 1.0 };
        // A tip at 0.5 c_R crosses 4 cells of 2 mm in 8/(0.5 c_R).
        let (t, g) = r.timing(2.0, 50.0, 100.0, 200.0);
        assert!((t - 0.16).abs() < 1e-15 && (g - 100.0).abs() < 1e-12);
        // Slower than 0.2 c_R, or a first increment (no estimate): timed at 0.2 c_R.
        assert_eq!(r.timing(2.0, 1.0, 100.0, 200.0).0, r.timing(2.0, 0.0, 100.0, 200.0).0);
        assert!((r.timing(2.0, 0.0, 100.0, 200.0).0 - 0.4).abs() < 1e-15);
        let rel = Release { crack: 0, segment: 0, t0: 1.0, duration: 0.5, rate: 0.0 };
        assert_eq!((rel.fraction(0.5), rel.fraction(1.25), rel.fraction(2.0)), (0.0, 0.5, 1.0));
    }
}
