//! Stability stress tests: the CFL sweep (case `cfl_sweep`, scene
//! `verification/cfl_block.toml`) and large deformation (case `squashed_disk`, scene
//! `verification/squashed_disk.toml`).
//!
//! **CFL sweep.** For each update scheme, bisect the largest time step, as a fraction of
//! h/c_d, for which the free elastic block runs a fixed number of steps without the
//! checked mode stopping it; then run just past that limit and require the run to stop
//! with the checked mode's `Unstable` error (energy above 100× its initial scale) rather
//! than a non-finite value or a silent blow-up. Explicit time integration is stable only
//! up to a critical step Δt ≤ 2/ω_max (Belytschko, Liu & Moran, *Nonlinear Finite
//! Elements*, 2000, §6.2); the default fraction 0.5 must lie below the measured limit of
//! every scheme. The measured limits (over a finite number of steps) are recorded, not
//! compared with a closed form: MUSL, USF and USAVG re-project the updated particle
//! velocities, which damps the grid's highest modes, and run stably past h/c_d.
//!
//! The block's initial velocity is odd about its centre, so it does not drift: a
//! drifting block leaves the grid after a number of steps that shrinks with Δt, and that
//! stop (`OutsideGrid`) would masquerade as the stability limit.
//!
//! **Squashed disk.** An elastic disk is squashed to half its height between two heavy,
//! stiff platens moving toward each other (no boundary conditions, so total momentum is
//! conserved exactly, a check that holds at any deformation). Particles cross many cells;
//! linear shape functions then produce cell-crossing noise (their gradients jump as a
//! particle changes cell; Bardenhagen & Kober 2004), uGIMP much less. The noise is
//! measured as the RMS second difference of the disk's strain-energy history (per step),
//! relative to its largest value: a smooth history has second differences O(Δt²).

use super::{scheme_name, SCHEMES};
use crate::check::CheckError;
use crate::report::plot::{PlotSpec, Series};
use crate::shape::ShapeKind;
use crate::simulation::{Scheme, Simulation};
use crate::verify::scene_file::SceneFile;
use crate::verify::{CaseOutput, Plot, Variant};
use anyhow::Context;


/// How a run at a given time-step fraction ended.
#[derive(Clone, Debug, PartialEq)]
pub struct StepOutcome {
    /// `None` if all steps ran.
    pub error: Option<CheckError>,
    pub steps: u64,
    /// max (KE + SE) / (KE + SE)(0) over the run.
    pub max_energy_ratio: f64,
}

/// Run the CFL block with `scheme` at Δt = `fraction` · h/c_d for up to `max_steps`.
pub fn run_block(scheme: Scheme, fraction: f64, max_steps: u64) -> anyhow::Result<StepOutcome> {
    let file = SceneFile::new("cfl_block.toml");
    let base = file.clone().load()?;
    let dt = fraction * Simulation::cfl_dt(&base.grid(), &base.materials());
    let scene = file
        .set("solver.scheme", scheme_name(scheme))
        .set("solver.checked", true)
        .set("solver.dt", format!("{dt:?}"))
        .set("solver.end_time", format!("{:?}", max_steps as f64 * dt))
        .load()?;
    let mut sim = scene.build()?;
    anyhow::ensure!(sim.options.dt == dt, "time step {} vs {dt}", sim.options.dt);
    let e0 = {
        let e = sim.energies();
        e.kinetic + e.strain
    };
    let mut out = StepOutcome { error: None, steps: 0, max_energy_ratio: 1.0 };
    for _ in 0..max_steps {
        if let Err(e) = sim.step() {
            out.error = Some(e);
            break;
        }
        let e = sim.energies();
        out.max_energy_ratio = out.max_energy_ratio.max((e.kinetic + e.strain) / e0);
    }
    out.steps = sim.step_count;
    Ok(out)
}

/// Largest stable fraction, smallest unstable fraction, every evaluated (fraction, outcome).
pub type Bisection = (f64, f64, Vec<(f64, StepOutcome)>);

/// Bisect the largest stable fraction of h/c_d in [0.5, 3] to within `tol`.
pub fn largest_stable_fraction(scheme: Scheme, max_steps: u64, tol: f64) -> anyhow::Result<Bisection> {
    let (mut lo, mut hi) = (0.5, 3.0);
    let mut seen = Vec::new();
    for f in [lo, hi] {
        seen.push((f, run_block(scheme, f, max_steps)?));
    }
    anyhow::ensure!(
        seen[0].1.error.is_none(),
        "{}: unstable already at 0.5 h/c_d: {:?}",
        scheme_name(scheme),
        seen[0].1.error
    );
    anyhow::ensure!(seen[1].1.error.is_some(), "{}: still running at 3 h/c_d", scheme_name(scheme));
    while hi - lo > tol {
        let mid = 0.5 * (lo + hi);
        let r = run_block(scheme, mid, max_steps)?;
        if r.error.is_none() {
            lo = mid;
        } else {
            hi = mid;
        }
        seen.push((mid, r));
    }
    seen.sort_by(|a, b| a.0.total_cmp(&b.0));
    Ok((lo, hi, seen))
}

/// Case `cfl_sweep`.
pub fn run_cfl_sweep(variant: Variant) -> anyhow::Result<CaseOutput> {
    let (steps, tol) = match variant {
        Variant::Quick => (2000, 0.02),
        Variant::Full => (20000, 0.005),
    };
    let mut out = CaseOutput::default();
    let mut series = Vec::new();
    for scheme in SCHEMES {
        let name = scheme_name(scheme);
        let (lo, hi, seen) = largest_stable_fraction(scheme, steps, tol)?;
        out.measure("default_is_stable", name, lo, f64::NAN);
        // Just past the limit: the smallest unstable fraction found.
        let past = seen.iter().find(|s| s.0 == hi).map(|s| s.1.clone()).context("the bisection evaluated hi")?;
        let unstable = matches!(past.error, Some(CheckError::Unstable { .. }));
        out.measure("stops_unstable", &format!("{name}, just past the limit"), if unstable { 1.0 } else { 0.0 }, 1.0);
        let far = run_block(scheme, 3.0, steps)?;
        let far_unstable = matches!(far.error, Some(CheckError::Unstable { .. }));
        out.measure("stops_unstable", &format!("{name}, at 3 h/c_d"), if far_unstable { 1.0 } else { 0.0 }, 1.0);
        out.note(format!(
            "{name}: stable for {steps} steps at {lo:.3} h/c_d; at {hi:.3} stopped after {} steps: {}; at 3 h/c_d after {} steps: {}",
            past.steps,
            past.error.map(|e| e.to_string()).unwrap_or_else(|| "not stopped".into()),
            far.steps,
            far.error.map(|e| e.to_string()).unwrap_or_else(|| "not stopped".into()),
        ));
        let pts: Vec<(f64, f64)> = seen.iter().map(|(f, o)| (*f, o.steps as f64 / steps as f64)).collect();
        series.push(Series::line(name, pts).with_markers());
    }
    out.figure(
        "cfl_sweep.png",
        &format!(
            "Fraction of the {steps}-step trial the free block ran before the checked mode stopped it (with `Unstable`), \
             against the time step as a fraction of h/c_d, per update scheme, at the fractions the bisection evaluated. \
             1 = ran to the end (stable)."
        ),
        PlotSpec::new("CFL sweep: how long a run survives vs time step", "Δt / (h / c_d)", "steps run / steps of the trial")
            .with_legend(crate::report::plot::LegendPosition::UpperRight),
        Plot::Lines(series),
    );
    Ok(out)
}

/// What the squashed-disk run measured.
#[derive(Clone, Debug)]
pub struct SquashRun {
    pub shape: ShapeKind,
    pub error: Option<String>,
    /// Final disk height / initial diameter.
    pub height_ratio: f64,
    pub max_dp: f64,
    /// RMS second difference of the disk's strain energy per step / its maximum.
    pub noise: f64,
    pub max_energy_error: f64,
    pub strain_energy: Vec<(f64, f64)>,
    pub wall_s: f64,
    /// The disk's particles at the end: (x, y, σyy).
    pub final_particles: Vec<(f64, f64, f64)>,
}

/// Squash the disk of `verification/squashed_disk.toml` with the given shape functions and cell size.
pub fn run_squash(shape: ShapeKind, cell: f64) -> anyhow::Result<SquashRun> {
    let scene = SceneFile::new("squashed_disk.toml")
        .set("solver.shape", super::vibrating_bar::shape_name(shape))
        .set("grid.cell", format!("[{cell}, {cell}]"))
        .load()?;
    let mut sim = scene.build()?;
    let disk = |s: &Simulation| (0..s.particles.len()).filter(|&i| s.particles.body[i] == 0).collect::<Vec<_>>();
    let ids = disk(&sim);
    let height = |s: &Simulation| {
        let ys = ids.iter().map(|&i| s.particles.x[i].y);
        ys.clone().fold(f64::NEG_INFINITY, f64::max) - ys.fold(f64::INFINITY, f64::min)
    };
    let h0 = height(&sim);
    let disk_se = |s: &Simulation| {
        let p = &s.particles;
        super::csum(ids.iter().map(|&i| {
            let m = &s.materials[p.material[i] as usize];
            p.vol0[i] * crate::material::Constitutive::energy_density(m, &p.strain[i], &p.stress[i])
        }))
    };
    let p0 = sim.total_momentum();
    let e0 = sim.energies().total();
    let (mut max_dp, mut max_de) = (0.0f64, 0.0f64);
    let mut se = vec![(0.0, disk_se(&sim))];
    let t0 = std::time::Instant::now();
    let r = sim.run_until(scene.solver.end_time, |s| {
        let p = &s.particles;
        let scale = crate::exact::sum_iter((0..p.len()).map(|i| p.mass[i] * (p.v[i].x.abs() + p.v[i].y.abs())));
        max_dp = max_dp.max((s.total_momentum() - p0).norm() / scale);
        max_de = max_de.max(((s.energies().total() - e0) / e0).abs());
        se.push((s.time, disk_se(s)));
    });
    let wall_s = t0.elapsed().as_secs_f64();
    let se_max = se.iter().map(|p| p.1).fold(0.0, f64::max);
    let d2: Vec<f64> = se.windows(3).map(|w| w[0].1 - 2.0 * w[1].1 + w[2].1).collect();
    let noise = (d2.iter().map(|x| x * x).sum::<f64>() / d2.len().max(1) as f64).sqrt() / se_max;
    Ok(SquashRun {
        shape,
        error: r.err().map(|e| e.to_string()),
        height_ratio: height(&sim) / h0,
        max_dp,
        noise,
        max_energy_error: max_de,
        strain_energy: se,
        wall_s,
        final_particles: ids
            .iter()
            .map(|&i| (sim.particles.x[i].x, sim.particles.x[i].y, sim.particles.stress[i].yy))
            .collect(),
    })
}

/// Case `squashed_disk` (full suite only).
pub fn run_squashed_disk(variant: Variant) -> anyhow::Result<CaseOutput> {
    anyhow::ensure!(variant == Variant::Full, "squashed_disk has no quick variant");
    let mut out = CaseOutput::default();
    let scene = SceneFile::new("squashed_disk.toml").load()?;
    let cell = scene.grid.cell[0];
    let mut runs = Vec::new();
    for shape in [ShapeKind::Ugimp, ShapeKind::Linear] {
        let r = run_squash(shape, cell)?;
        let name = match shape {
            ShapeKind::Ugimp => "uGIMP",
            ShapeKind::Linear => "linear",
        };
        out.note(format!(
            "{name}: final height / diameter {:.3}; max |ΔP|/Σm|v| {:.2e}; max |ΔE|/E0 {:.2e}; noise {:.3e}; {:.1} s{}",
            r.height_ratio,
            r.max_dp,
            r.max_energy_error,
            r.noise,
            r.wall_s,
            r.error.as_ref().map(|e| format!("; stopped: {e}")).unwrap_or_default()
        ));
        if shape == ShapeKind::Ugimp {
            out.measure("completed", name, if r.error.is_none() { 1.0 } else { 0.0 }, 1.0);
            out.measure("squashed", name, r.height_ratio, 0.5);
        }
        if r.error.is_none() {
            out.measure("momentum", name, r.max_dp, 0.0);
        }
        runs.push((name, r));
    }
    out.measure("gimp_quieter", "uGIMP / linear", runs[0].1.noise / runs[1].1.noise, f64::NAN);
    for (name, r) in &runs {
        out.figure(
            &format!("squashed_disk_{}.png", name.to_lowercase()),
            &format!(
                "The disk at the end of the squash with {name} shape functions, particles coloured by σyy \
                 (the platens are not drawn). Compare the smoothness of the two fields: the noise of linear shape \
                 functions comes from particles crossing cell boundaries."
            ),
            PlotSpec::new(&format!("Squashed disk, {name}: σyy at t = {:.2}", scene.solver.end_time), "x", "y")
                .with_size(800, 600),
            Plot::Particles { particles: r.final_particles.clone(), lines: Vec::new(), value_label: "σyy".into() },
        );
    }
    out.figure(
        "squashed_disk_strain_energy.png",
        "Strain energy of the disk while it is squashed to half its height, uGIMP against linear shape functions: \
         the linear history carries the cell-crossing noise.",
        PlotSpec::new("Squashed disk: strain energy, uGIMP vs linear", "time t", "strain energy of the disk"),
        Plot::Lines(runs.iter().map(|(n, r)| Series::line(n, r.strain_energy.clone())).collect()),
    );
    Ok(out)
}
