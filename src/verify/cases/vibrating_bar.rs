//! Single-mode vibrating bar (references §5.1, closed form): cases `vibrating_bar`,
//! `bar_convergence` and `bar_long`; scene `verification/vibrating_bar.toml`.
//!
//! Bar 0 ≤ x ≤ L, u = 0 at x = 0 (vx fixed on the x = 0 node line), free at x = L,
//! rollers (vy = 0) on the node lines of and beyond the long sides, so the exact
//! solution is 1D with wave speed c = c_d = √((λ+2μ)/ρ) (plane strain λ here):
//! v(x,t) = v0 cos(ωt) sin(βx), β = π/(2L), ω = βc, T = 4L/c, and
//! v_cm(t) = (2 v0/π) cos(ωt).
//!
//! Energy: KE is measured from the particle velocities at t_n and SE from stresses
//! that MUSL and USF update half a step out of phase with them; on a single mode ω these
//! schemes are symplectic Euler, whose energy H = ½(p² + ω²q²) oscillates about a
//! conserved modified energy with relative amplitude ωΔt/2 (no secular drift). USAVG
//! updates half the strain before and half after the momentum update (velocity
//! Verlet-like), amplitude (ωΔt)²/4 (Nairn 2003 §2.3, §3.4).
//!
//! USL finding (not a bug in cramp, the instability of Nairn 2003 eq. 21): with only the
//! x = 0 node line fixed, the uGIMP particle next to the fixed end moves infinitesimally
//! into the support of the exterior node x = −h whenever it moves left; that node then
//! has a vanishing mass m ~ d² but a force ~ d, so USL (which takes strain rates from
//! p′/m of Task 4) applies a finite strain increment and loses ≈ 1.7 % of the energy per
//! period with a ≈ 2 % period error. Fixing vx on the exterior nodes x ≤ 0 as well
//! (equally valid for u(0) = 0) removes it; there USL behaves like MUSL and its period is
//! checked too. With linear shape functions the effect is absent.

use super::{scheme_name, SCHEMES};
use crate::report::plot::{PlotSpec, Series};
use crate::scene::{Scene, ShapeSpec};
use crate::shape::ShapeKind;
use crate::simulation::Scheme;
use crate::verify::scene_file::SceneFile;
use crate::verify::{CaseOutput, Plot, SweepPoint, Variant};
use anyhow::{bail, Context};
use std::f64::consts::PI;
use std::time::Instant;

/// The scene file.
pub const SCENE: &str = include_str!("../../../verification/vibrating_bar.toml");

/// The bar's physical parameters, read from the scene.
#[derive(Clone, Copy, Debug)]
pub struct Bar {
    pub length: f64,
    pub height: f64,
    pub e: f64,
    pub nu: f64,
    pub rho: f64,
    pub v0: f64,
}

impl Bar {
    pub fn of(scene: &Scene) -> anyhow::Result<Bar> {
        let (Some(body), Some(mat)) = (scene.bodies.first(), scene.materials.first()) else {
            bail!("the bar scene needs a body and a material");
        };
        let ShapeSpec::Rectangle { min, max } = body.shape else {
            bail!("the bar scene's body must be a rectangle");
        };
        let v0 = body.velocity_sine.as_ref().map(|s| s.amplitude[0]).context("the bar scene needs velocity_sine")?;
        Ok(Bar { length: max[0] - min[0], height: max[1] - min[1], e: mat.e, nu: mat.nu, rho: mat.rho, v0 })
    }

    /// Plane-strain dilatational wave speed c_d² = E(1−ν)/(ρ(1+ν)(1−2ν)), written
    /// independently of `material.rs`.
    pub fn wave_speed(&self) -> f64 {
        (self.e * (1.0 - self.nu) / (self.rho * (1.0 + self.nu) * (1.0 - 2.0 * self.nu))).sqrt()
    }

    /// The exact period 4L/c_d.
    pub fn period(&self) -> f64 {
        4.0 * self.length / self.wave_speed()
    }

    pub fn omega(&self) -> f64 {
        2.0 * PI / self.period()
    }

    /// Continuum initial kinetic energy ρ v0² L H / 4 (unit thickness).
    pub fn kinetic_energy(&self) -> f64 {
        self.rho * self.v0 * self.v0 * self.length * self.height / 4.0
    }
}

/// One configuration of the bar.
#[derive(Clone, Copy, Debug)]
pub struct BarConfig {
    pub scheme: Scheme,
    pub shape: ShapeKind,
    pub cell: f64,
    pub ppc: usize,
    /// Fix vx on every node with x ≤ 0 instead of only the x = 0 line.
    pub fix_exterior: bool,
    pub periods: f64,
    pub checked: bool,
}

impl BarConfig {
    /// The scene file's configuration with the given scheme, 4 periods, checked.
    pub fn base(scheme: Scheme) -> Self {
        BarConfig {
            scheme,
            shape: ShapeKind::Ugimp,
            cell: 1.0,
            ppc: 2,
            fix_exterior: false,
            periods: 4.0,
            checked: true,
        }
    }
}

/// The bar scene for a configuration: the scene file with k = π/(2L) set exactly, the
/// end time a whole number of exact periods, and the cell size, scheme, shape and
/// particles per cell of `cfg`.
pub fn bar_scene(cfg: &BarConfig) -> anyhow::Result<Scene> {
    let file = SceneFile::new("vibrating_bar.toml");
    let base = file.clone().load()?;
    let bar = Bar::of(&base)?;
    let mut file = file
        .set("bodies.0.velocity_sine.k", format!("[{}, 0.0]", PI / (2.0 * bar.length)))
        .set("solver.scheme", scheme_name(cfg.scheme))
        .set("solver.shape", shape_name(cfg.shape))
        .set("solver.particles_per_cell", cfg.ppc)
        .set("solver.end_time", cfg.periods * bar.period())
        .set("solver.checked", cfg.checked)
        .set("grid.cell", format!("[{}, {}]", cfg.cell, cfg.cell));
    if cfg.fix_exterior {
        let g = &base.grid;
        file = file.set("boundary.0.nodes", format!("{{ region = {{ min = [{}, {}], max = [0.0, {}] }} }}", g.origin[0], g.origin[1], g.origin[1] + g.size[1]));
    }
    file.load()
}

/// The shape functions' name as in scene files.
pub fn shape_name(s: ShapeKind) -> &'static str {
    match s {
        ShapeKind::Linear => "linear",
        ShapeKind::Ugimp => "ugimp",
    }
}

/// What one run of the bar measured.
#[derive(Clone, Debug)]
pub struct BarRun {
    /// Period from the zero crossings of v_cm (least squares over all crossings).
    pub period: f64,
    /// max |E(t) − E0| / E0 over the run.
    pub max_rel_drift: f64,
    /// Relative energy change per period at the v_cm zero crossings, where the
    /// oscillating part of the energy error vanishes (least-squares slope).
    pub secular_per_period: f64,
    /// max |v_cm − (2v0/π) cos ωt| / (2v0/π) over the run.
    pub vcm_error: f64,
    pub dt: f64,
    pub steps: u64,
    /// Wall time of the time loop.
    pub wall_s: f64,
    /// (t, (E − E0)/E0), at most ~800 points: per block of steps the one with the
    /// largest |E − E0| (so subsampling cannot hide the oscillation band).
    pub energy_history: Vec<(f64, f64)>,
    /// (t, v_cm), subsampled likewise.
    pub vcm_history: Vec<(f64, f64)>,
}

/// Least-squares slope of y against x.
fn slope(x: &[f64], y: &[f64]) -> f64 {
    let n = x.len() as f64;
    let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let sxy: f64 = x.iter().zip(y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let sxx: f64 = x.iter().map(|a| (a - mx).powi(2)).sum();
    sxy / sxx
}

/// Run the bar to the scene's end time and measure period, energy and v_cm error.
pub fn run_bar(scene: &Scene) -> anyhow::Result<BarRun> {
    let bar = Bar::of(scene)?;
    run_bar_sim(scene.build()?, scene.solver.end_time, bar.v0, bar.omega())
}

/// [`run_bar`] on a built simulation of either dimension: run to `end_time` and measure
/// the period of the centre-of-mass velocity (x component), the energy error and the
/// error of v_cm against (2 v0/π) cos ωt.
pub fn run_bar_sim<S: crate::simulation::Dimension>(mut sim: crate::simulation::Simulation<S>, end_time: f64, v0: f64, omega: f64) -> anyhow::Result<BarRun> {
    let mass: f64 = crate::exact::sum(&sim.particles.mass);
    let e0 = sim.energies().total();
    let amp = 2.0 * v0 / PI;
    let total_steps = (end_time / sim.options.dt).ceil().max(1.0) as u64;
    let every = (total_steps / 800).max(1);
    let mut prev = (0.0, sim.total_momentum()[0] / mass, e0);
    let mut crossings: Vec<(f64, f64)> = Vec::new();
    let (mut max_drift, mut vcm_error) = (0.0f64, ((prev.1 - amp) / amp).abs());
    let mut energy_history = vec![(0.0, 0.0)];
    let mut bucket: (f64, f64) = (0.0, 0.0);
    let mut vcm_history = vec![(0.0, prev.1)];
    let start = Instant::now();
    sim.run_until(end_time, |s| {
        let v = s.total_momentum()[0] / mass;
        let t = s.time;
        let e = s.energies().total();
        if prev.1 > 0.0 && v <= 0.0 || prev.1 < 0.0 && v >= 0.0 {
            // Linear interpolation of the zero crossing and of the energy there.
            let f = prev.1 / (prev.1 - v);
            crossings.push((prev.0 + (t - prev.0) * f, prev.2 + (e - prev.2) * f));
        }
        prev = (t, v, e);
        max_drift = max_drift.max(((e - e0) / e0).abs());
        vcm_error = vcm_error.max(((v - amp * (omega * t).cos()) / amp).abs());
        let de = (e - e0) / e0;
        if de.abs() >= bucket.1.abs() {
            bucket = (t, de);
        }
        if s.step_count % every == 0 {
            energy_history.push(bucket);
            bucket = (t, 0.0);
            vcm_history.push((t, v));
        }
    })?;
    let wall_s = start.elapsed().as_secs_f64();
    if crossings.len() < 4 {
        bail!("too few zero crossings of v_cm ({}) to measure the period", crossings.len());
    }
    // Crossings are half a period apart: least-squares slope of t_k against k.
    let k: Vec<f64> = (0..crossings.len()).map(|k| k as f64).collect();
    let t: Vec<f64> = crossings.iter().map(|c| c.0).collect();
    let de: Vec<f64> = crossings.iter().map(|c| (c.1 - e0) / e0).collect();
    let period = 2.0 * slope(&k, &t);
    let secular_per_period = slope(&t, &de) * period;
    Ok(BarRun {
        period,
        max_rel_drift: max_drift,
        secular_per_period,
        vcm_error,
        dt: sim.options.dt,
        steps: sim.step_count,
        wall_s,
        energy_history,
        vcm_history,
    })
}

/// Case `vibrating_bar`: period against 4L/c_d and the energy behaviour of each scheme.
pub fn run(variant: Variant) -> anyhow::Result<CaseOutput> {
    let cell = match variant {
        Variant::Quick => 1.0,
        Variant::Full => 0.5,
    };
    let mut out = CaseOutput::default();
    let base = Scene::from_toml(SCENE, "verification/vibrating_bar.toml")?;
    let bar = Bar::of(&base)?;
    let t_exact = bar.period();

    // Initial kinetic energy: discrete vs continuum (midpoint quadrature of sin²).
    let sim = bar_scene(&BarConfig { cell, ..BarConfig::base(Scheme::Usavg) })?.build()?;
    out.measure("initial_ke", "", sim.energies().kinetic, bar.kinetic_energy());

    let mut runs = Vec::new();
    for fix_exterior in [false, true] {
        for scheme in SCHEMES {
            let cfg = BarConfig { cell, fix_exterior, ..BarConfig::base(scheme) };
            let r = run_bar(&bar_scene(&cfg)?)
                .with_context(|| format!("{} (exterior fixed: {fix_exterior})", scheme_name(scheme)))?;
            runs.push((scheme, fix_exterior, r));
        }
    }
    let wdt = bar.omega() * runs[0].2.dt;
    let find =
        |s: Scheme, fx: bool| runs.iter().find(|r| r.0 == s && r.1 == fx).map(|r| &r.2).expect("every scheme ran");
    for (scheme, fx, r) in &runs {
        let name = scheme_name(*scheme);
        let label = if *fx { format!("{name}, x ≤ 0 fixed") } else { name.to_string() };
        // USL with only the x = 0 line fixed has the vanishing-mass exterior node (module doc).
        let vanishing_mass_node = *scheme == Scheme::Usl && !fx;
        if !vanishing_mass_node {
            out.measure("period", &label, r.period, t_exact);
            out.measure("secular_drift", &label, r.secular_per_period, 0.0);
        }
        if matches!(scheme, Scheme::Usl | Scheme::Musl | Scheme::Usf) && !vanishing_mass_node {
            out.measure("symplectic_euler_amplitude", &label, r.max_rel_drift / (wdt / 2.0), 1.0);
        }
    }
    let usavg = find(Scheme::Usavg, false);
    out.measure("usavg_amplitude", "", usavg.max_rel_drift / (wdt * wdt / 4.0), 1.0);
    out.measure("usavg_energy", "", usavg.max_rel_drift, 0.0);
    let best_other = [Scheme::Usl, Scheme::Musl, Scheme::Usf]
        .iter()
        .map(|&s| find(s, false).max_rel_drift)
        .fold(f64::INFINITY, f64::min);
    out.measure("usavg_best", "", usavg.max_rel_drift / best_other, f64::NAN);

    let usl = find(Scheme::Usl, false);
    out.note(format!(
        "USL with only the x = 0 node line fixed (the scene as written): period error {:+.2} %, max |ΔE|/E0 = {:.2e}, \
         secular drift {:+.2e} per period — the vanishing-mass exterior node of Nairn 2003 eq. 21 (see the case source); \
         with every node x ≤ 0 fixed USL is checked like the others.",
        100.0 * (usl.period - t_exact) / t_exact,
        usl.max_rel_drift,
        usl.secular_per_period
    ));
    out.note(format!(
        "Δt = {:.4e}, ωΔt/2 = {:.3e}, (ωΔt)²/4 = {:.3e}, exact period 4L/c_d = {t_exact:.6}.",
        runs[0].2.dt,
        wdt / 2.0,
        wdt * wdt / 4.0
    ));

    let series: Vec<Series> =
        SCHEMES.iter().map(|&s| Series::line(scheme_name(s), find(s, true).energy_history.clone())).collect();
    out.figure(
        "vibrating_bar_energy.png",
        "Relative total-energy error (E − E0)/E0 of the vibrating bar per update scheme (every node x ≤ 0 fixed). \
         MUSL, USF and USL oscillate with amplitude ωΔt/2, USAVG with (ωΔt)²/4; none drifts.",
        PlotSpec::new("Vibrating bar: energy error per update scheme", "time t", "(E − E0) / E0"),
        Plot::Lines(series),
    );
    let series: Vec<Series> = [Scheme::Musl, Scheme::Usavg]
        .iter()
        .map(|&s| Series::line(scheme_name(s), find(s, false).energy_history.clone()))
        .collect();
    out.figure(
        "vibrating_bar_energy_zoom.png",
        "The same for MUSL and USAVG with only the x = 0 line fixed (the scene file as written).",
        PlotSpec::new("Vibrating bar: MUSL vs USAVG energy error", "time t", "(E − E0) / E0"),
        Plot::Lines(series),
    );
    let amp = 2.0 * bar.v0 / PI;
    let exact: Vec<(f64, f64)> =
        (0..=400).map(|i| i as f64 * 4.0 * t_exact / 400.0).map(|t| (t, amp * (bar.omega() * t).cos())).collect();
    out.figure(
        "vibrating_bar_vcm.png",
        "Centre-of-mass velocity of the bar (USAVG) against the closed form (2v0/π) cos(ωt), ω = πc_d/(2L).",
        PlotSpec::new("Vibrating bar: centre-of-mass velocity", "time t", "v_cm"),
        Plot::Lines(vec![
            Series::line("cramp, USAVG", usavg.vcm_history.clone()),
            Series::reference("exact (2v0/π) cos ωt", exact),
        ]),
    );
    Ok(out)
}

/// Case `bar_convergence`: period error versus cell size (USAVG, uGIMP, 2 particles per
/// cell), and run time versus error over cell sizes, particles per cell, shape
/// functions and schemes.
pub fn run_convergence(variant: Variant) -> anyhow::Result<CaseOutput> {
    let (cells, periods): (&[f64], f64) = match variant {
        Variant::Quick => (&[1.0, 0.5, 0.25], 2.0),
        Variant::Full => (&[1.0, 0.5, 0.25, 0.125], 2.0),
    };
    let mut out = CaseOutput::default();
    let bar = Bar::of(&Scene::from_toml(SCENE, "verification/vibrating_bar.toml")?)?;
    let t_exact = bar.period();
    // u(0) = 0 on every node x ≤ 0: with only the x = 0 line fixed, the vanishing-mass
    // exterior node (module doc) adds a boundary error that converges more slowly
    // (measured in the full variant and reported as a note).
    let mut points = Vec::new();
    for &cell in cells {
        let cfg = BarConfig { cell, periods, checked: false, fix_exterior: true, ..BarConfig::base(Scheme::Usavg) };
        let r = run_bar(&bar_scene(&cfg)?)?;
        let err = ((r.period - t_exact) / t_exact).abs();
        out.measure("period_error", &format!("h = {cell}"), err, 0.0);
        points.push((cell, err));
        out.note(format!(
            "h = {cell}: period {:.8} (exact {t_exact:.8}), |error| {err:.3e}, {} steps, {:.2} s",
            r.period, r.steps, r.wall_s
        ));
    }
    let order = crate::report::plot::fit_order(&points);
    out.measure("order", "", order, 2.0);
    if variant == Variant::Full {
        let mut line_only = Vec::new();
        for &cell in cells {
            let cfg = BarConfig { cell, periods, checked: false, ..BarConfig::base(Scheme::Usavg) };
            let r = run_bar(&bar_scene(&cfg)?)?;
            line_only.push((cell, ((r.period - t_exact) / t_exact).abs()));
        }
        out.note(format!(
            "With only the x = 0 node line fixed (the scene file as written) the period errors are {} at h = {:?}: fitted order {:.2}, \
             the exterior node's boundary error (see vibrating_bar) converging more slowly than the interior O(h²).",
            line_only.iter().map(|p| format!("{:.2e}", p.1)).collect::<Vec<_>>().join(", "),
            cells,
            crate::report::plot::fit_order(&line_only)
        ));
    }
    out.figure(
        "bar_convergence.png",
        "Relative period error of the vibrating bar against cell size h (USAVG, uGIMP, 2×2 particles per cell, Δt = 0.5 h/c_d, \
         every node x ≤ 0 fixed), with the least-squares power law.",
        PlotSpec::new("Vibrating bar: period error vs cell size", "cell size h", "|T − 4L/c_d| / (4L/c_d)"),
        Plot::Convergence { points, label: "USAVG, uGIMP, ppc 2".into() },
    );

    // Cost versus accuracy.
    let (sweep_cells, ppcs, shapes, schemes): (&[f64], &[usize], &[ShapeKind], &[Scheme]) = match variant {
        Variant::Quick => (&[1.0, 0.5], &[1, 2], &[ShapeKind::Linear, ShapeKind::Ugimp], &[Scheme::Usavg]),
        Variant::Full => {
            (&[1.0, 0.5, 0.25], &[1, 2, 3], &[ShapeKind::Linear, ShapeKind::Ugimp], &[Scheme::Musl, Scheme::Usavg])
        }
    };
    let mut pareto = Vec::new();
    for &cell in sweep_cells {
        for &ppc in ppcs {
            for &shape in shapes {
                for &scheme in schemes {
                    let cfg = BarConfig { scheme, shape, cell, ppc, fix_exterior: true, periods, checked: false };
                    let r = run_bar(&bar_scene(&cfg)?)?;
                    let shape_name = match shape {
                        ShapeKind::Linear => "lin",
                        ShapeKind::Ugimp => "gimp",
                    };
                    let config = format!("h={cell} ppc={ppc} {shape_name} {}", scheme_name(scheme));
                    let err = ((r.period - t_exact) / t_exact).abs();
                    pareto.push((r.wall_s.max(1e-6), err, config.clone()));
                    out.sweep.push(SweepPoint { config, wall_s: r.wall_s, error: err });
                }
            }
        }
    }
    // With many runs, label only the front (the table in the report lists every run).
    if pareto.len() > 12 {
        let front = crate::report::plot::pareto_front(&pareto);
        for (i, p) in pareto.iter_mut().enumerate() {
            if !front.contains(&i) {
                p.2.clear();
            }
        }
    }
    out.figure(
        "bar_pareto.png",
        "Run time (time loop, unchecked) against the relative period error, over cell size, particles per cell (per \
         direction), shape functions and update scheme; every node x ≤ 0 fixed. \
         Circled in red: the Pareto front (no run is both faster and more accurate); with many runs only the front is \
         labelled, and the table below lists every run.",
        PlotSpec::new("Vibrating bar: run time vs period error", "wall time of the run (s)", "|T − 4L/c_d| / (4L/c_d)"),
        Plot::Pareto(pareto),
    );
    Ok(out)
}

/// Case `bar_long`: 10⁵ steps of the bar; the energy of USAVG and MUSL stays in the
/// oscillation band of their integrators, without secular drift.
pub fn run_long(variant: Variant) -> anyhow::Result<CaseOutput> {
    if variant == Variant::Quick {
        bail!("bar_long has no quick variant");
    }
    let mut out = CaseOutput::default();
    let steps = 100_000.0;
    for scheme in [Scheme::Usavg, Scheme::Musl] {
        let mut cfg = BarConfig { fix_exterior: true, checked: false, ..BarConfig::base(scheme) };
        let probe = bar_scene(&cfg)?;
        let bar = Bar::of(&probe)?;
        cfg.periods = steps * probe.time_step() / bar.period();
        let r = run_bar(&bar_scene(&cfg)?)?;
        let wdt = bar.omega() * r.dt;
        let name = scheme_name(scheme);
        match scheme {
            Scheme::Usavg => out.measure("usavg_amplitude", name, r.max_rel_drift / (wdt * wdt / 4.0), 1.0),
            _ => out.measure("musl_amplitude", name, r.max_rel_drift / (wdt / 2.0), 1.0),
        }
        out.measure("total_drift", name, r.secular_per_period * cfg.periods, 0.0);
        out.note(format!(
            "{name}: {} steps ({:.0} periods), max |ΔE|/E0 = {:.3e}, secular drift {:+.3e} per period, {:.1} s",
            r.steps, cfg.periods, r.max_rel_drift, r.secular_per_period, r.wall_s
        ));
        out.figure(
            &format!("bar_long_{name}.png"),
            &format!("(E − E0)/E0 of the vibrating bar over 10⁵ steps, {name} (subsampled)."),
            PlotSpec::new(&format!("Vibrating bar, 10⁵ steps: energy error, {name}"), "time t", "(E − E0) / E0"),
            Plot::Lines(vec![Series::line(name, r.energy_history.clone())]),
        );
    }
    Ok(out)
}
