//! Static edge and centre cracks under slowly applied, damped tension against Tada's
//! handbook formulas (verification references §1(c), §1(d); Tada, Paris & Irwin 1973):
//! case `plates_k`. `tests/j_plates.rs` calls these functions.
//!
//! K_I = σ√(πa) F(α), for a long plate under uniform remote tension σ (ends free to
//! rotate: traction loading):
//! * CCT (centre crack 2a, width 2b, α = a/b): F = (1 − 0.025α² + 0.06α⁴)√(sec(πα/2)),
//!   0.1 % for any α;
//! * SENT (edge crack a, width W, α = a/W): F = √((2/(πα)) tan(πα/2)) [0.752 + 2.02α +
//!   0.37(1 − sin(πα/2))³]/cos(πα/2), better than 0.5 %.
//!
//! The formulas are for long plates; the half-heights here are 3b (CCT) and W (SENT),
//! the references' minimum for the SENT (H/W ≥ 1 per half).
//! The static K does not depend on E, ν or ρ for traction loading (2D elasticity), so
//! a soft, light material settles fast: E = 1000 MPa, ν = 0.3, ρ = 10⁻³ g/mm³, plane
//! strain; units mm, g, ms. The load is ramped over 0.25 ms and damped (κ = 60 ms⁻¹) to
//! 0.6 ms; K_I from the 2×2 contour J split by the crack-opening displacements.
//!
//! The crack tip ends somewhere in its cell (the CRAMP displacement jump is resolved to a
//! cell), so K converges at first order in h: the case checks the observed order and the
//! Richardson extrapolation 2K(h/2) − K(h) against Tada.

use crate::fracture::jintegral::{CodMethod, TipEnd};
use crate::report::plot::PlotSpec;
use crate::scene::Scene;
use crate::verify::scene_file::SceneFile;
use crate::verify::{CaseOutput, Plot, Variant};
use std::f64::consts::PI;

/// Tada's geometry factor of the centre-cracked plate, α = a/b.
pub fn tada_cct(alpha: f64) -> f64 {
    (1.0 - 0.025 * alpha.powi(2) + 0.06 * alpha.powi(4)) * (1.0 / (PI * alpha / 2.0).cos()).sqrt()
}

/// Tada's geometry factor of the single-edge-notched plate, α = a/W.
pub fn tada_sent(alpha: f64) -> f64 {
    let x = PI * alpha / 2.0;
    ((2.0 / (PI * alpha)) * x.tan()).sqrt() * (0.752 + 2.02 * alpha + 0.37 * (1.0 - x.sin()).powi(3)) / x.cos()
}

/// Remote tension (MPa).
const SIGMA: f64 = 1.0;

/// The two plates.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PlateKind {
    /// Centre-cracked plate, 2b = 20 mm, half-height 30 mm = 3b, a = 5 − h/2 (a/b ≈ 0.48):
    /// the right half with rollers on the mirror plane x = 0 (a grid line), the tip in
    /// the middle of a cell.
    Cct,
    /// Single-edge-notched plate, W = 20 mm, half-height 20 mm = W, a = 6 mm (a/W = 0.3),
    /// uniform traction on both ends, the grid shifted half a cell so the tip is in the
    /// middle of a cell.
    Sent,
}

impl PlateKind {
    pub fn name(self) -> &'static str {
        match self {
            PlateKind::Cct => "CCT",
            PlateKind::Sent => "SENT",
        }
    }

    /// The scene file (`verification/cct_plate.toml`, `sent_plate.toml`).
    pub fn file(self) -> &'static str {
        match self {
            PlateKind::Cct => "cct_plate.toml",
            PlateKind::Sent => "sent_plate.toml",
        }
    }

    /// The case's crack length at cell size h: CCT a = 5 − h/2 (tip mid-cell), SENT 6 mm.
    pub fn crack_length(self, h: f64) -> f64 {
        match self {
            PlateKind::Cct => 5.0 - 0.5 * h,
            PlateKind::Sent => 6.0,
        }
    }

    /// The plate's scene at cell size h with the tip at x = a and the grid shifted by
    /// `shift` cells in −x, as overrides of its file: two cells of margin, the loaded
    /// particle rows the outermost half cell, the crack from one cell outside the body.
    pub fn scene_file(self, h: f64, a: f64, shift: f64) -> SceneFile {
        let (width, half_height) = match self {
            PlateKind::Cct => (10.0, 30.0),
            PlateKind::Sent => (20.0, 20.0),
        };
        let file = SceneFile::new(self.file())
            .set("grid.origin", format!("[{}, {}]", -2.0 * h - shift * h, -half_height - 2.0 * h))
            .set("grid.size", format!("[{}, {}]", width + 4.0 * h, 2.0 * half_height + 4.0 * h))
            .set("grid.cell", format!("[{h}, {h}]"))
            .set("loads.0.particles.region.min", format!("[0.0, {}]", half_height - 0.5 * h))
            .set("loads.1.particles.region.max", format!("[{width}, {}]", -half_height + 0.5 * h))
            .set("cracks.0.points", format!("[[{}, 0.0], [{a}, 0.0]]", -h));
        match self {
            // Rollers on the mirror plane x = 0 and the nodes beyond it.
            PlateKind::Cct => file.set("boundary.0.nodes.region", format!("{{ min = [{}, {}], max = [0.0, {}] }}", -3.0 * h, -half_height - 2.0 * h, half_height + 2.0 * h)),
            PlateKind::Sent => file,
        }
    }

    /// The case's scene at cell size h (the SENT's grid shifted half a cell so its tip is
    /// mid-cell) and the crack length a.
    pub fn scene(self, h: f64) -> anyhow::Result<(Scene, f64)> {
        let a = self.crack_length(h);
        let shift = match self {
            PlateKind::Cct => 0.0,
            PlateKind::Sent => 0.5,
        };
        Ok((self.scene_file(h, a, shift).load()?, a))
    }

    /// Tada's K_I for crack length a.
    pub fn k_ref(self, a: f64) -> f64 {
        SIGMA
            * (PI * a).sqrt()
            * match self {
                PlateKind::Cct => tada_cct(a / 10.0),
                PlateKind::Sent => tada_sent(a / 20.0),
            }
    }
}

/// One static plate run.
#[derive(Clone, Debug)]
pub struct PlateRun {
    pub kind: PlateKind,
    pub h: f64,
    pub a: f64,
    /// K_I (2×2 contour) at 0.8, 0.9 and 1.0 of the end time.
    pub k_samples: [f64; 3],
    /// Tada's K_I.
    pub k_ref: f64,
    pub particles: usize,
    pub steps: u64,
    pub wall_s: f64,
}

impl PlateRun {
    /// The final K_I.
    pub fn k(&self) -> f64 {
        self.k_samples[2]
    }
    /// K_I / K_Tada − 1.
    pub fn error(&self) -> f64 {
        self.k() / self.k_ref - 1.0
    }
}

/// Ramp, damp and sample K_I of one plate at cell size h.
pub fn plate_k(kind: PlateKind, h: f64) -> anyhow::Result<PlateRun> {
    let (scene, a) = kind.scene(h)?;
    let started = std::time::Instant::now();
    let mut sim = scene.build()?;
    let end = scene.solver.end_time;
    let mut k_samples = [0.0; 3];
    for (k, f) in [0.8, 0.9, 1.0].into_iter().enumerate() {
        sim.run_until(f * end, |_| {})?;
        k_samples[k] = sim.tip_fracture(0, TipEnd::End, 2, false, CodMethod::NextToTip, 0.0)?.k1;
    }
    Ok(PlateRun {
        kind,
        h,
        a,
        k_samples,
        k_ref: kind.k_ref(a),
        particles: sim.particles.len(),
        steps: sim.step_count,
        wall_s: started.elapsed().as_secs_f64(),
    })
}

/// The cell sizes of a variant per plate. The CCT's crack is 2 cells long at 2 mm, where
/// its error (−8.4 %) has the other sign than at 1 mm (+5.3 %): pre-asymptotic, so it
/// starts at 1 mm; the SENT is asymptotic from 2 mm (+13.0 %, +6.6 %: order 0.98).
pub fn cell_sizes(kind: PlateKind, variant: Variant) -> &'static [f64] {
    match (kind, variant) {
        (PlateKind::Cct, Variant::Quick) => &[1.0, 0.5],
        (PlateKind::Sent, Variant::Quick) => &[2.0, 1.0],
        (PlateKind::Cct, Variant::Full) => &[1.0, 0.5, 0.25],
        (PlateKind::Sent, Variant::Full) => &[2.0, 1.0, 0.5, 0.25],
    }
}

/// Case `plates_k`: both plates at the cell sizes of the variant ([`cell_sizes`]); per
/// plate the observed order and the Richardson limit of the two finest, the settling of
/// every run, and the convergence plot.
pub fn run(variant: Variant) -> anyhow::Result<CaseOutput> {
    let mut out = CaseOutput::default();
    let mut series = Vec::new();
    for kind in [PlateKind::Cct, PlateKind::Sent] {
        let hs = cell_sizes(kind, variant);
        let mut runs = Vec::new();
        for &h in hs {
            let r = plate_k(kind, h)?;
            let name = kind.name();
            out.measure("settled", &format!("{name}, h = {h} mm, K(0.9 t_end) vs K(t_end)"), r.k_samples[1], r.k());
            out.note(format!(
                "{name}, h = {h} mm: a = {} mm, K_I = {:.4} vs Tada {:.4} ({:+.2} %); {} particles, {} steps, {:.1} s",
                r.a,
                r.k(),
                r.k_ref,
                100.0 * r.error(),
                r.particles,
                r.steps,
                r.wall_s
            ));
            out.sweep.push(crate::verify::SweepPoint {
                config: format!("{name}, h = {h} mm"),
                wall_s: r.wall_s,
                error: r.error().abs(),
            });
            runs.push(r);
        }
        let n = runs.len();
        let (c, f) = (&runs[n - 2], &runs[n - 1]);
        let (ec, ef) = (c.error(), f.error());
        let pair = format!("{}, h = {} → {} mm", kind.name(), c.h, f.h);
        // Errors of opposite sign give NaN, which fails.
        out.measure("order", &pair, (ec / ef).log2(), 1.0);
        // Richardson for first order: e(0) ≈ 2e(h/2) − e(h). For the CCT a depends on h,
        // so the extrapolation is done on the relative errors (each against its own Tada K).
        out.measure("richardson", &format!("{pair}, 2e(h/2) − e(h)"), 1.0 + 2.0 * ef - ec, 1.0);
        series.push((kind, runs.iter().map(|r| (r.h, r.error().abs())).collect::<Vec<_>>()));
    }
    for (kind, points) in &series {
        out.figure(
            &format!("plates_k_{}_convergence.png", kind.name().to_lowercase()),
            &format!(
                "{}: |K_I/K_Tada − 1| against cell size (log–log, least-squares order); the tip ends somewhere in its cell, \
                 so first order is expected.",
                kind.name()
            ),
            PlotSpec::new(&format!("{}: K_I error vs cell size", kind.name()), "cell size h (mm)", "|K_I − K_Tada| / K_Tada"),
            Plot::Convergence { points: points.clone(), label: format!("{} K_I", kind.name()) },
        );
    }
    Ok(out)
}
