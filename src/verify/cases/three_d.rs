//! 3D verification cases (issue 14; 001 §2.1: "otherwise the 3D algorithm is essentially
//! the same as the 2D one"): the vibrating bar in 3D per update scheme (`bar_3d`), two
//! colliding spheres (`spheres_3d`), a static block in uniaxial tension (`block_3d`), and
//! the consistency of a 2D plane-strain scene with its extrusion in z (`extrusion_2d_3d`).
//! Scenes: `verification/vibrating_bar_3d.toml`, `colliding_spheres_3d.toml`,
//! `block_tension_3d.toml`, `extrusion_impact_2d.toml` / `extrusion_impact_3d.toml`.

use super::vibrating_bar::{bar_scene, run_bar_sim, BarConfig};
use super::{csum, scheme_name, SCHEMES};
use crate::dim::{Vector3, D3};
use crate::report::plot::{PlotSpec, Series};
use crate::scene3d::{Scene3, Solid};
use crate::simulation::{Scheme, Simulation};
use crate::verify::scene_file::SceneFile;
use crate::verify::{CaseOutput, Plot, Variant};
use anyhow::{bail, Context};
use std::f64::consts::PI;


/// The 3D bar's dimensions and material, read from the scene.
struct Bar3 {
    length: f64,
    height: f64,
    width: f64,
    e: f64,
    nu: f64,
    rho: f64,
    v0: f64,
}

impl Bar3 {
    fn of(scene: &Scene3) -> anyhow::Result<Bar3> {
        let (Some(body), Some(mat)) = (scene.bodies.first(), scene.materials.first()) else {
            bail!("the 3D bar scene needs a body and a material");
        };
        let Solid::Box { min, max } = body.shape else {
            bail!("the 3D bar scene's body must be a box");
        };
        let v0 = body.velocity_sine.as_ref().map(|s| s.amplitude[0]).context("the 3D bar needs velocity_sine")?;
        Ok(Bar3 { length: max[0] - min[0], height: max[1] - min[1], width: max[2] - min[2], e: mat.e, nu: mat.nu, rho: mat.rho, v0 })
    }

    /// 3D dilatational wave speed c_d² = (λ + 2μ)/ρ = E(1−ν)/(ρ(1+ν)(1−2ν)), written
    /// independently of `material.rs`.
    fn wave_speed(&self) -> f64 {
        (self.e * (1.0 - self.nu) / (self.rho * (1.0 + self.nu) * (1.0 - 2.0 * self.nu))).sqrt()
    }

    fn period(&self) -> f64 {
        4.0 * self.length / self.wave_speed()
    }
}

/// The 3D bar scene with scheme, cell size and periods; k = π/(2L) exactly; vx fixed on
/// every node x ≤ 0 when `fix_exterior` (see the 2D case for why USL needs it).
fn bar3_scene(scheme: Scheme, cell: f64, periods: f64, fix_exterior: bool) -> anyhow::Result<Scene3> {
    let file = SceneFile::new("vibrating_bar_3d.toml");
    let base = file.clone().load3()?;
    let bar = Bar3::of(&base)?;
    let mut file = file
        .set("bodies.0.velocity_sine.k", format!("[{}, 0.0, 0.0]", PI / (2.0 * bar.length)))
        .set("solver.scheme", scheme_name(scheme))
        .set("solver.end_time", periods * bar.period())
        .set("grid.cell", format!("[{cell}, {cell}, {cell}]"));
    if fix_exterior {
        let (o, size) = (base.grid.origin, base.grid.size);
        file = file.set("boundary.0.nodes", format!("{{ box = {{ min = [{}, {}, {}], max = [0.0, {}, {}] }} }}", o[0], o[1], o[2], o[1] + size[1], o[2] + size[2]));
    }
    file.load3()
}

/// Case `bar_3d`: the single-mode bar in 3D, period and energy per scheme.
pub fn run_bar(variant: Variant) -> anyhow::Result<CaseOutput> {
    let cell = match variant {
        Variant::Quick => 1.0,
        Variant::Full => 0.5,
    };
    let mut out = CaseOutput::default();
    let base = SceneFile::new("vibrating_bar_3d.toml").load3()?;
    let bar = Bar3::of(&base)?;
    let t_exact = bar.period();
    let omega = 2.0 * PI / t_exact;
    let sim = bar3_scene(Scheme::Usavg, cell, 4.0, true)?.build()?;
    let ke0 = bar.rho * bar.v0 * bar.v0 * bar.length * bar.height * bar.width / 4.0;
    out.measure("initial_ke", "", sim.energies().kinetic, ke0);
    let mut usavg_history = Vec::new();
    for scheme in SCHEMES {
        let s = bar3_scene(scheme, cell, 4.0, true)?;
        let r = run_bar_sim(s.build()?, s.solver.end_time, bar.v0, omega).with_context(|| scheme_name(scheme))?;
        let wdt = omega * r.dt;
        let name = scheme_name(scheme);
        out.measure("period", name, r.period, t_exact);
        out.measure("secular_drift", name, r.secular_per_period, 0.0);
        match scheme {
            Scheme::Usavg => {
                out.measure("usavg_amplitude", name, r.max_rel_drift / (wdt * wdt / 4.0), 1.0);
                usavg_history = r.energy_history.clone();
            }
            _ => out.measure("symplectic_euler_amplitude", name, r.max_rel_drift / (wdt / 2.0), 1.0),
        }
        out.note(format!(
            "{name}: period {:.6} (exact 4L/c_d = {t_exact:.6}, {:+.3} %), max |ΔE|/E0 {:.3e}, secular {:+.2e} per period, {} steps, {:.2} s",
            r.period,
            100.0 * (r.period - t_exact) / t_exact,
            r.max_rel_drift,
            r.secular_per_period,
            r.steps,
            r.wall_s
        ));
    }
    out.figure(
        "bar_3d_energy.png",
        "Relative energy error (E − E0)/E0 of the 3D vibrating bar, USAVG (rollers on the four long faces, every node x ≤ 0 fixed).",
        PlotSpec::new("3D vibrating bar: energy error (USAVG)", "time t", "(E − E0) / E0"),
        Plot::Lines(vec![Series::line("usavg", usavg_history)]),
    );
    Ok(out)
}

/// Case `spheres_3d`: momentum conserved to round-off every step, energy of USAVG bounded
/// through collision and rebound, rebound.
pub fn run_spheres(variant: Variant) -> anyhow::Result<CaseOutput> {
    let mut scene = SceneFile::new("colliding_spheres_3d.toml");
    if variant == Variant::Full {
        scene = scene.set("grid.cell", "[0.025, 0.025, 0.025]");
    }
    let mut out = CaseOutput::default();
    let mut usavg_energy = Vec::new();
    for scheme in SCHEMES {
        let s = scene.clone().set("solver.scheme", scheme_name(scheme)).load3()?;
        let mut sim = s.build()?;
        let p = &sim.particles;
        let scale = csum((0..p.len()).map(|i| p.mass[i] * p.v[i].abs().sum()));
        let mass = csum(p.mass.iter().copied());
        let v2 = 3.0 * 0.1f64 * 0.1;
        if scheme == Scheme::Usavg {
            out.measure("initial_ke", "", sim.energies().kinetic, 0.5 * mass * v2);
        }
        let p0 = momentum3(&sim);
        let e0 = sim.energies().total();
        let (mut dp, mut de) = (0.0f64, 0.0f64);
        let mut hist = vec![(0.0, 0.0)];
        sim.run_until(s.solver.end_time, |s| {
            dp = dp.max((momentum3(s) - p0).norm() / scale);
            let e = (s.energies().total() - e0) / e0;
            de = de.max(e.abs());
            hist.push((s.time, e));
        })?;
        let name = scheme_name(scheme);
        out.measure("momentum", name, dp, 0.0);
        if scheme == Scheme::Usavg {
            out.measure("usavg_energy", "", de, 0.0);
            // Sphere 0's centre-of-mass velocity (initially +0.1 in every component).
            let p = &sim.particles;
            let m0 = csum((0..p.len()).filter(|&i| p.body[i] == 0).map(|i| p.mass[i]));
            let v0: Vec<f64> = (0..3).map(|c| csum((0..p.len()).filter(|&i| p.body[i] == 0).map(|i| p.mass[i] * p.v[i][c])) / m0).collect();
            out.measure("rebound", "", v0.iter().copied().fold(f64::NEG_INFINITY, f64::max), 0.0);
            let e = sim.energies();
            out.measure("ke_recovered", "", e.kinetic / (0.5 * mass * v2), f64::NAN);
            usavg_energy = hist;
        }
        out.note(format!("{name}: max |P − P0|/Σm|v| = {dp:.2e}, max |ΔE|/E0 = {de:.3e}, {} particles, {} steps", sim.particles.len(), sim.step_count));
    }
    out.figure(
        "spheres_3d_energy.png",
        "Relative energy error of the colliding spheres through collision and rebound (USAVG).",
        PlotSpec::new("Colliding spheres: energy error (USAVG)", "time t", "(E − E0) / E0"),
        Plot::Lines(vec![Series::line("usavg", usavg_energy)]),
    );
    Ok(out)
}

fn momentum3(s: &Simulation<D3>) -> Vector3 {
    let p = &s.particles;
    Vector3::from_fn(|c, _| csum((0..p.len()).map(|i| p.mass[i] * p.v[i][c])))
}

/// Case `block_3d`: a damped block in uniaxial tension settles to the closed form.
pub fn run_block(variant: Variant) -> anyhow::Result<CaseOutput> {
    let mut file = SceneFile::new("block_tension_3d.toml").set("solver.checked", false);
    if variant == Variant::Full {
        // The last particle layer of 0.5 mm cells with 2 particles per cell: x = 9.875.
        file = file.set("grid.cell", "[0.5, 0.5, 0.5]").set("loads.0.particles.plane.point.0", 9.875).set("loads.0.particles.plane.tolerance", 0.05);
    }
    let scene = file.load3()?;
    let mut sim = scene.build()?;
    let (e, nu) = (scene.materials[0].e, scene.materials[0].nu);
    let Solid::Box { min, max } = scene.bodies[0].shape else { bail!("the block must be a box") };
    let area = (max[1] - min[1]) * (max[2] - min[2]);
    let sigma = scene.loads[0].force.map_or(f64::NAN, |f| f[0]) / area;
    let mut hist = Vec::new();
    sim.run_until(scene.solver.end_time, |s| {
        let p = &s.particles;
        let vol = csum(p.vol0.iter().copied());
        hist.push((s.time, csum((0..p.len()).map(|i| p.vol0[i] * p.stress[i].xx)) / vol));
    })?;
    // Means over the middle half of the length (L/4 ≤ x0 ≤ 3L/4): away from the loaded
    // end layer (a load on particles, not a face traction) and from the symmetry face,
    // where by Saint-Venant the stress is the uniform F/A.
    let p = &sim.particles;
    let (a, b) = (min[0] + 0.25 * (max[0] - min[0]), min[0] + 0.75 * (max[0] - min[0]));
    let mid: Vec<usize> = (0..p.len()).filter(|&i| p.x0[i].x >= a && p.x0[i].x <= b).collect();
    let vol = csum(mid.iter().map(|&i| p.vol0[i]));
    let mean = |f: &dyn Fn(usize) -> f64| csum(mid.iter().map(|&i| p.vol0[i] * f(i))) / vol;
    let sxx = mean(&|i| p.stress[i].xx);
    let (exx, eyy, ezz) = (mean(&|i| p.strain[i].xx), mean(&|i| p.strain[i].yy), mean(&|i| p.strain[i].zz));
    out_block(sigma, e, nu, sxx, exx, eyy, ezz, sim.energies().kinetic / sim.energies().strain, hist)
}

#[allow(clippy::too_many_arguments)]
fn out_block(sigma: f64, e: f64, nu: f64, sxx: f64, exx: f64, eyy: f64, ezz: f64, ke_ratio: f64, hist: Vec<(f64, f64)>) -> anyhow::Result<CaseOutput> {
    let mut out = CaseOutput::default();
    out.measure("stress", "σxx", sxx, sigma);
    out.measure("strain", "εxx", exx, sigma / e);
    out.measure("poisson", "εyy", eyy, -nu * sigma / e);
    out.measure("poisson", "εzz", ezz, -nu * sigma / e);
    out.measure("settled", "", ke_ratio, 0.0);
    out.note(format!("volume means over L/4 ≤ x ≤ 3L/4 at the end: σxx = {sxx:.6e} (F/A = {sigma}), εxx = {exx:.6e}, εyy = {eyy:.6e}, εzz = {ezz:.6e}; KE/SE = {ke_ratio:.2e}"));
    out.figure(
        "block_3d_stress.png",
        "Volume mean of σxx over the whole damped 3D block against F/A (the load acts on the end layer of particles, at x = L − h/4, so the whole-body mean settles about h/(4L) below F/A; the checks use the middle half).",
        PlotSpec::new("3D block in tension: mean σxx", "time t", "mean σxx"),
        Plot::Lines(vec![Series::line("cramp", hist.clone()), Series::reference("F/A", vec![(0.0, sigma), (hist.last().map(|h| h.0).unwrap_or(1.0), sigma)])]),
    );
    Ok(out)
}

/// Case `extrusion_2d_3d`: a 2D plane-strain scene and its extrusion in z (rollers on
/// both z faces) give the same energies and particle fields, to round-off.
pub fn run_extrusion(variant: Variant) -> anyhow::Result<CaseOutput> {
    let mut out = CaseOutput::default();
    // 1. The vibrating bar (USAVG and MUSL), 2D vs 3D (width 2 = 2 cells).
    for scheme in [Scheme::Usavg, Scheme::Musl] {
        let cell = if variant == Variant::Full { 0.5 } else { 1.0 };
        let s2 = bar_scene(&BarConfig { scheme, cell, fix_exterior: true, periods: 2.0, ..BarConfig::base(scheme) })?;
        let s3 = bar3_scene(scheme, cell, 2.0, true)?;
        let width = match s3.bodies[0].shape {
            Solid::Box { min, max } => max[2] - min[2],
            _ => bail!("the 3D bar must be a box"),
        };
        let (mut s2b, mut s3b) = (s2.build()?, s3.build()?);
        compare_extrusion(&mut out, &format!("bar {}", scheme_name(scheme)), &mut s2b, &mut s3b, s2.solver.end_time, width, |_, _| {})?;
    }
    // 2. The Delrin impact in plane strain (two bodies, impact through the shared field).
    let s2 = SceneFile::new("extrusion_impact_2d.toml").load()?;
    let s3 = SceneFile::new("extrusion_impact_3d.toml").load3()?;
    let width = match s3.bodies[0].shape {
        Solid::Box { min, max } => max[2] - min[2],
        _ => bail!("the 3D beam must be a box"),
    };
    compare_extrusion(&mut out, "impact", &mut s2.build()?, &mut s3.build()?, s2.solver.end_time, width, |_, _| {})?;
    Ok(out)
}

/// Run both to `end` and compare energies at every step (3D = width × 2D) and the final
/// particle fields (every 3D particle against the 2D particle at the same x, y);
/// `after_step` sees both after every step (the crack cases compare their cracks there).
pub(crate) fn compare_extrusion(
    out: &mut CaseOutput,
    label: &str,
    s2: &mut Simulation,
    s3: &mut Simulation<D3>,
    end: f64,
    width: f64,
    mut after_step: impl FnMut(&Simulation, &Simulation<D3>),
) -> anyhow::Result<()> {
    if s2.options.dt != s3.options.dt {
        bail!("{label}: the 2D and 3D time steps differ ({} vs {}); the scenes do not match", s2.options.dt, s3.options.dt);
    }
    let mut de = 0.0f64;
    while s2.time + 0.5 * s2.options.dt < end {
        s2.step()?;
        s3.step()?;
        after_step(s2, s3);
        let (e2, e3) = (s2.energies(), s3.energies());
        for (a, b) in [(e2.kinetic, e3.kinetic), (e2.strain, e3.strain)] {
            let scale = (e2.kinetic + e2.strain) * width;
            de = de.max((a * width - b).abs() / scale);
        }
    }
    out.measure("energy", label, de, 0.0);
    // Particle fields: the 2D particle at each 3D particle's initial (x, y).
    let key = |x: f64, y: f64| (x.to_bits(), y.to_bits());
    let index: std::collections::HashMap<(u64, u64), usize> = (0..s2.particles.len()).map(|i| (key(s2.particles.x0[i].x, s2.particles.x0[i].y), i)).collect();
    let (p2, p3) = (&s2.particles, &s3.particles);
    let (mut dx, mut dv, mut ds, mut uz) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    let umax = (0..p2.len()).map(|i| (p2.x[i] - p2.x0[i]).norm()).fold(0.0, f64::max);
    let vmax = (0..p2.len()).map(|i| p2.v[i].norm()).fold(0.0, f64::max);
    let smax = (0..p2.len()).map(|i| p2.stress[i].xx.abs().max(p2.stress[i].yy.abs()).max(p2.stress[i].xy.abs())).fold(0.0, f64::max);
    for j in 0..p3.len() {
        let Some(&i) = index.get(&key(p3.x0[j].x, p3.x0[j].y)) else {
            bail!("{label}: 3D particle at {:?} has no 2D twin: the scenes are not an extrusion of each other", p3.x0[j]);
        };
        dx = dx.max(((p3.x[j].x - p2.x[i].x).abs()).max((p3.x[j].y - p2.x[i].y).abs()));
        dv = dv.max(((p3.v[j].x - p2.v[i].x).abs()).max((p3.v[j].y - p2.v[i].y).abs()));
        let (a, b) = (&p2.stress[i], &p3.stress[j]);
        ds = ds.max((a.xx - b.xx).abs().max((a.yy - b.yy).abs()).max((a.xy - b.xy).abs()).max((a.zz - b.zz).abs()));
        uz = uz.max((p3.x[j].z - p3.x0[j].z).abs().max(p3.v[j].z.abs() * end));
    }
    if p3.len() % p2.len() != 0 {
        bail!("{label}: {} 3D particles are not a whole number of layers of the {} 2D ones", p3.len(), p2.len());
    }
    out.measure("fields", &format!("{label}: position / max |u|"), dx / umax, 0.0);
    out.measure("fields", &format!("{label}: velocity / max |v|"), dv / vmax, 0.0);
    out.measure("fields", &format!("{label}: stress / max |σ|"), ds / smax, 0.0);
    out.measure("out_of_plane", label, uz / umax, 0.0);
    out.note(format!(
        "{label}: {} 2D and {} 3D particles ({} layers), {} steps; max energy difference {de:.2e} of the total; fields: position {:.2e}, velocity {:.2e}, stress {:.2e} (relative to their maxima); out-of-plane motion {:.2e}",
        p2.len(),
        p3.len(),
        p3.len() / p2.len(),
        s3.step_count,
        dx / umax,
        dv / vmax,
        ds / smax,
        uz / umax
    ));
    Ok(())
}
