//! Path independence of the 3D front J (issue 16, verification item 6): J₁ at the front
//! nodes of the extruded SENT slab of `front_j_slab` (rollers on both z faces: exactly
//! plane strain, 3d-references.md §4.1) against the radius of the circular contour
//! ([`crate::fracture::front3`]), with and without the volume term, at the damped static
//! state and early in an undamped step-load run.
//!
//! * Crack length a = 10 mm (a/W = 0.5, tip mid-cell) so that circles of up to 4 cells at
//!   2 mm cells stay inside the plate (a circle that leaves the body misses the free edge's
//!   W n₁ term and is not a J contour).
//! * Static: the scene as `front_j_slab` runs it (ramp 0.25 ms, κ = 60 ms⁻¹ to 0.6 ms).
//!   J is path independent in elastostatics (Rice 1968); the volume term holds the residual
//!   inertia only.
//! * Dynamic: the same plate, loads applied as a step at t = 0, no damping; J evaluated
//!   at several times after the step wave reaches the crack plane (t₀ = (H − h/4)/c_d).
//!   The two-term J (line + volume, 004 eqs. 8, 12–13) is path independent for any
//!   elastodynamic field (Nishioka 1995); the line term alone is not (004 §4.3), and the
//!   difference is largest early, while the wave passes the tip.
//! * Independent magnitude check: the 2D run of the same scene (the extrusion reproduces
//!   it to round-off, case `cracks_2d_3d`) evaluated with the 2D code's rectangular
//!   contours and their area term ([`Simulation::tip_fracture`], verified against Freund
//!   in `chen_early_time`): a different contour shape and an independent implementation of
//!   the inertial term.
//! * Face nodes (z = 0 and z = B, on the roller planes) must give the interior value: the
//!   field is uniform in z.
//!
//! Tolerances and why each is fair: `verification/cases.toml`, case `front_j_path`.

use crate::fracture::front3::{FrontRequest, FrontResult};
use crate::fracture::jintegral::{CodMethod, TipEnd};
use crate::report::plot::{PlotSpec, Series};
use crate::verify::cases::front3::slab_scenes_at;
use crate::verify::{CaseOutput, Plot, Variant};
use anyhow::Context;
use std::time::Instant;

/// Crack length (mm) of the path-independence slab.
pub const A: f64 = 10.0;
/// Contour radii, in cells.
pub const RADII: [f64; 6] = [1.5, 2.0, 2.5, 3.0, 3.5, 4.0];
/// Rectangular 2D contours (cells from the tip node) of the 2D magnitude check.
pub const RECT: [usize; 3] = [2, 3, 4];
/// Evaluation times of the dynamic run after the wave's arrival at the crack plane (ms).
pub const AFTER_ARRIVAL: [f64; 4] = [0.005, 0.010, 0.015, 0.020];

/// J at one time: per radius (cells) the front nodes (line term and line + volume), and
/// the 2D rectangular contours (line, line + area).
#[derive(Clone, Debug)]
pub struct PathEval {
    pub t: f64,
    pub per_radius: Vec<(f64, Vec<FrontResult>)>,
    pub rect: Vec<(usize, f64, f64)>,
}

impl PathEval {
    /// The front node nearest mid-width (an interior node).
    pub fn mid(&self, b: f64) -> usize {
        let f = &self.per_radius[0].1;
        (0..f.len()).min_by(|&i, &k| (f[i].x.z - 0.5 * b).abs().total_cmp(&(f[k].x.z - 0.5 * b).abs())).expect("front nodes")
    }
    /// (radius in cells, J₁ line, J₁ line + volume) at node `n`.
    pub fn curve(&self, n: usize) -> Vec<(f64, f64, f64)> {
        self.per_radius.iter().map(|(r, f)| (*r, f[n].j1_line, f[n].j1)).collect()
    }
    /// At node `n`: its [`Self::curve`], the spreads over the radii of line + volume and
    /// of the line term alone, the mean J₁ (line + volume) over the radii, and the mean 2D
    /// rectangle J (line + area), the magnitude reference.
    pub fn summary(&self, n: usize) -> PathSummary {
        let curve = self.curve(n);
        PathSummary {
            spread_full: spread(curve.iter().map(|x| x.2)),
            spread_line: spread(curve.iter().map(|x| x.1)),
            j_ref: self.rect.iter().map(|x| x.2).sum::<f64>() / self.rect.len() as f64,
            mean_full: curve.iter().map(|x| x.2).sum::<f64>() / curve.len() as f64,
            curve,
        }
    }
}

/// [`PathEval::summary`].
pub struct PathSummary {
    pub curve: Vec<(f64, f64, f64)>,
    pub spread_full: f64,
    pub spread_line: f64,
    pub j_ref: f64,
    pub mean_full: f64,
}

/// (max − min)/mean of a set of values.
pub fn spread(v: impl Iterator<Item = f64> + Clone) -> f64 {
    let n = v.clone().count() as f64;
    let (lo, hi) = v.clone().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| (a.min(x), b.max(x)));
    (hi - lo) / (v.sum::<f64>() / n)
}

/// What one slab run (static or dynamic) measured.
#[derive(Clone, Debug)]
pub struct PathRun {
    pub h: f64,
    pub width: f64,
    pub evals: Vec<PathEval>,
    pub t_arrival: f64,
    pub particles: usize,
    pub steps: u64,
    pub seconds: f64,
}

/// Run the slab at cell size h, static (`dynamic` false: the scene's ramp and damping, J
/// at the end) or dynamic (step load, undamped, J at [`AFTER_ARRIVAL`]).
pub fn path_run(h: f64, dynamic: bool) -> anyhow::Result<PathRun> {
    let (mut f2, mut f3) = slab_scenes_at(h, A);
    let s2 = f2.clone().load()?;
    let m = &s2.materials[0];
    let (e, nu, rho) = (m.e, m.nu, m.rho);
    let c_d = (e * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu)) / rho).sqrt();
    // Loaded particles' layer: its centre is h/4 inside the end y = ±20.
    let t_arrival = (20.0 - 0.25 * h) / c_d;
    let times: Vec<f64> = if dynamic { AFTER_ARRIVAL.iter().map(|dt| t_arrival + dt).collect() } else { vec![s2.solver.end_time] };
    if dynamic {
        let end = times[times.len() - 1];
        for k in 0..2 {
            f2 = f2.set(&format!("loads.{k}.ramp"), "0.0");
            f3 = f3.set(&format!("loads.{k}.ramp"), "0.0");
        }
        f2 = f2.set("solver.damping", "0.0").set("solver.end_time", format!("{end:?}"));
        f3 = f3.set("solver.damping", "0.0").set("solver.end_time", format!("{end:?}"));
    }
    let (s2, s3) = (f2.load()?, f3.load3()?);
    let mut a = s2.build()?;
    let t = Instant::now();
    let mut b = s3.build()?;
    let req = s3.front_requests(&b.cracks)?.remove(0).context("the 3D slab asks for J")?;
    let mut evals = Vec::new();
    for &time in &times {
        a.run_until(time, |_| {})?;
        b.run_until(time, |_| {})?;
        let per_radius = RADII.iter().map(|&rc| (rc, b.front_fracture(0, &FrontRequest { radius: rc * h, volume_term: true, ..req.clone() }))).collect();
        let mut rect = Vec::new();
        for &c in &RECT {
            let line = a.tip_fracture(0, TipEnd::End, c, false, CodMethod::NextToTip, 0.0)?.j1;
            let full = a.tip_fracture(0, TipEnd::End, c, true, CodMethod::NextToTip, 0.0)?.j1;
            rect.push((c, line, full));
        }
        evals.push(PathEval { t: b.time, per_radius, rect });
    }
    Ok(PathRun { h, width: 2.0 * h, evals, t_arrival, particles: b.particles.len(), steps: b.step_count, seconds: t.elapsed().as_secs_f64() })
}

/// Case `front_j_path`.
pub fn run(variant: Variant) -> anyhow::Result<CaseOutput> {
    let hs: &[f64] = match variant {
        Variant::Quick => &[2.0],
        Variant::Full => &[2.0, 1.0],
    };
    let finest = hs[hs.len() - 1];
    let mut out = CaseOutput::default();
    let mut static_curves = Vec::new();
    let mut dyn_curves = Vec::new();
    for &h in hs {
        let label = format!("h = {h} mm");
        // Static.
        let r = path_run(h, false)?;
        let ev = &r.evals[0];
        let n = ev.mid(r.width);
        let PathSummary { curve: c, spread_full: s_full, spread_line: s_line, j_ref, mean_full } = ev.summary(n);
        out.measure("static_spread", &label, s_full, 0.0);
        out.measure("static_vs_2d", &label, mean_full, j_ref);
        out.note(format!(
            "Static, {label} ({} particles × {} steps, {:.1} s): mid-width node z = {}: J₁ against r (cells) line / line + volume: {}; \
             spread (max − min)/mean line {:.3} %, line + volume {:.3} %; 2D rectangular contours {:?} cells, line / line + area: {}.",
            r.particles,
            r.steps,
            r.seconds,
            ev.per_radius[0].1[n].x.z,
            c.iter().map(|x| format!("{}: {:.5e} / {:.5e}", x.0, x.1, x.2)).collect::<Vec<_>>().join(", "),
            100.0 * s_line,
            100.0 * s_full,
            RECT,
            ev.rect.iter().map(|x| format!("{:.5e} / {:.5e}", x.1, x.2)).collect::<Vec<_>>().join(", "),
        ));
        static_curves.push(Series::line(&format!("{label}, line + volume"), c.iter().map(|x| (x.0, x.2 / j_ref)).collect()).with_markers());
        static_curves.push(Series::line(&format!("{label}, line only"), c.iter().map(|x| (x.0, x.1 / j_ref)).collect()).with_markers());

        // Dynamic.
        let d = path_run(h, true)?;
        let (mut worst_full, mut most_line, mut worst_2d, mut worst_face): (f64, f64, f64, f64) = (0.0, 0.0, 0.0, 0.0);
        for ev in &d.evals {
            let n = ev.mid(d.width);
            let PathSummary { curve: c, spread_full: s_full, spread_line: s_line, j_ref, mean_full } = ev.summary(n);
            worst_full = worst_full.max(s_full);
            most_line = most_line.max(s_line);
            worst_2d = worst_2d.max((mean_full / j_ref - 1.0).abs());
            // Face nodes against the interior node: volume terms per unit length.
            for (_, f) in &ev.per_radius {
                let vi = f[n].j1 - f[n].j1_line;
                for g in f {
                    worst_face = worst_face.max(((g.j1 - g.j1_line) - vi).abs() / vi.abs());
                }
            }
            let tl = format!("{label}, t − t₀ = {:.0} µs", 1e3 * (ev.t - d.t_arrival));
            out.note(format!(
                "Dynamic, {tl}: J₁ against r (cells) line / line + volume: {}; spread line {:.1} %, line + volume {:.2} %; 2D rectangles \
                 {:?} line / line + area: {}; volume term per node at r = 2 cells (z: J₁ − J₁,line): {}.",
                c.iter().map(|x| format!("{}: {:.4e} / {:.4e}", x.0, x.1, x.2)).collect::<Vec<_>>().join(", "),
                100.0 * s_line,
                100.0 * s_full,
                RECT,
                ev.rect.iter().map(|x| format!("{:.4e} / {:.4e}", x.1, x.2)).collect::<Vec<_>>().join(", "),
                ev.per_radius[1].1.iter().map(|g| format!("{}: {:.4e}", g.x.z, g.j1 - g.j1_line)).collect::<Vec<_>>().join(", "),
            ));
            if h == finest {
                dyn_curves.push(Series::line(&format!("{tl}, line + volume"), c.iter().map(|x| (x.0, x.2 / j_ref)).collect()).with_markers());
                dyn_curves.push(Series::line(&format!("{tl}, line only"), c.iter().map(|x| (x.0, x.1 / j_ref)).collect()));
            }
        }
        out.measure("dynamic_spread", &label, worst_full, 0.0);
        out.measure("dynamic_line_spread", &label, most_line, f64::NAN);
        out.measure("dynamic_vs_2d", &label, worst_2d, 0.0);
        out.measure("face_nodes", &label, worst_face, 0.0);
        out.note(format!(
            "Dynamic, {label}: wave at the crack plane t₀ = {:.4} ms; {} particles × {} steps, {:.1} s. Over the evaluation times: largest \
             spread of J₁ (line + volume) {:.2} %, largest spread of the line term alone {:.1} %, largest |mean J₁ / 2D rectangles with \
             area term − 1| {:.2} %, largest |volume term at a node / at mid-width − 1| {:.1e}.",
            d.t_arrival,
            d.particles,
            d.steps,
            d.seconds,
            100.0 * worst_full,
            100.0 * most_line,
            100.0 * worst_2d,
            worst_face
        ));
    }
    static_curves.push(Series::reference("path independent", vec![(RADII[0], 1.0), (RADII[RADII.len() - 1], 1.0)]));
    dyn_curves.push(Series::reference("path independent", vec![(RADII[0], 1.0), (RADII[RADII.len() - 1], 1.0)]));
    out.figure(
        "front_j_path_static.png",
        "Extruded SENT slab (a = 10 mm, plane strain by rollers), damped static state: J₁ at the mid-width front node against the \
         circle's radius, line term alone and with the volume term, over the mean J of the 2D run's rectangular 2×2–4×4 contours \
         (with area term).",
        PlotSpec::new("3D front J: path independence, static", "contour radius (cells)", "J₁ / J₁(2D rectangles)"),
        Plot::Lines(static_curves),
    );
    out.figure(
        "front_j_path_dynamic.png",
        &format!(
            "The same slab under a step load, undamped, h = {finest} mm: J₁ at the mid-width front node against the circle's radius at \
             several times after the wave reaches the crack plane, line term alone (not path independent in dynamics) and with the \
             volume term, over the mean of the 2D rectangles with area term at the same time."
        ),
        PlotSpec::new("3D front J: path independence, dynamic", "contour radius (cells)", "J₁ / J₁(2D rectangles, area term)"),
        Plot::Lines(dyn_curves),
    );
    Ok(out)
}
