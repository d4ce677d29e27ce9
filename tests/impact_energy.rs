//! Transverse impact energy balance, after Nairn 2003 §3.4 (Delrin beam, E = 2900 MPa,
//! ν = 0.33, ρ = 1.5 g/cm³, impactor 10× stiffer and denser, 2.43 m/s; units mm, g, ms
//! so MPa, N, and mm/ms = m/s).
//!
//! Scene (an equivalent of the paper's problem at test cost: 2 mm cells, 580
//! particles, 1.2 ms; the same scene at 1 mm is `verification/delrin_impact.toml`, about
//! 75 s for the four schemes): an 88 × 6 mm Delrin beam, free (no supports: the
//! paper's support material has no cramp equivalent, and fixed-velocity nodes are not
//! energy-neutral in MPM), hit at midspan by
//! a disk (radius 4 mm, E = 29000, ρ = 1.5e-2) at 2.43 mm/ms, through the shared velocity
//! field (MPM's default no-slip contact). No loads, gravity or damping, so the exact
//! solution conserves KE + SE and momentum.
//!
//! Assertions and why they are fair:
//! * USAVG keeps the total energy within ±0.5 % of E0 over the whole run (the paper
//!   reports ±0.18 % for its impact with USAVG; 0.5 % is the brief's bound and leaves
//!   room for our coarse 2 mm grid).
//! * total momentum is conserved to 1e-12 Σm|v| (conservation law; MPM sums are exact, the test sums are compensated).
//! * the impact really happened: the disk's kinetic energy dropped by more than half
//!   (a momentum/energy exchange with the beam), otherwise the energy check is empty.
//! The USL, MUSL and USF figures are printed for the report, not asserted: the paper's
//! observations (USL poor/unstable, MUSL slowly dissipating, USF slowly gaining) are
//! qualitative.
//!
//! The run is checked (every invariant every step). Energies and momenta are summed here
//! with Neumaier-compensated sums (relative error ~1e-16, ample for a 0.5 % energy bound
//! and a 1e-12 momentum bound); this scene first exposed, and now guards, the ExactSum
//! fix for terms spread over hundreds of binades (velocities decaying ahead of the wave).

use cramp::material::Constitutive;
use cramp::scene::Scene;
use cramp::simulation::Simulation;

/// Neumaier-compensated sum.
fn csum(terms: impl Iterator<Item = f64>) -> f64 {
    let (mut s, mut c) = (0.0f64, 0.0f64);
    for x in terms {
        let t = s + x;
        c += if s.abs() >= x.abs() { (s - t) + x } else { (x - t) + s };
        s = t;
    }
    s + c
}

/// Kinetic + strain energy (no loads, body forces or damping in this scene).
fn total_energy(s: &Simulation) -> f64 {
    let p = &s.particles;
    csum((0..p.len()).map(|i| {
        let m = &s.materials[p.material[i] as usize];
        0.5 * p.mass[i] * p.v[i].norm_squared() + p.vol0[i] * m.energy_density(&p.strain[i], &p.stress[i])
    }))
}

fn momentum(s: &Simulation) -> nalgebra::Vector2<f64> {
    let p = &s.particles;
    nalgebra::Vector2::new(csum((0..p.len()).map(|i| p.mass[i] * p.v[i].x)), csum((0..p.len()).map(|i| p.mass[i] * p.v[i].y)))
}

fn impact_scene(scheme: &str, end_time: f64, h: f64) -> Scene {
    let text = format!(
        r#"
title = "Delrin beam transverse impact (after Nairn 2003 §3.4), free beam"
[grid]
origin = [-4.0, -8.0]
size = [96.0, 28.0]
cell = [{h}, {h}]

[solver]
scheme = "{scheme}"
shape = "ugimp"
cfl = 0.5
end_time = {end_time}
particles_per_cell = 2

[[materials]]
name = "delrin"
E = 2900.0
nu = 0.33
rho = 1.5e-3
state = "plane_stress"

[[materials]]
name = "impactor"
E = 29000.0
nu = 0.33
rho = 1.5e-2
state = "plane_stress"

[[bodies]]
material = "delrin"
shape = {{ rectangle = {{ min = [0.0, 0.0], max = [88.0, 6.0] }} }}

[[bodies]]
material = "impactor"
shape = {{ disk = {{ center = [44.0, 11.0], radius = 4.0 }} }}
velocity = [0.0, -2.43]
"#
    );
    Scene::from_toml(&text, "impact").unwrap()
}

#[test]
fn usavg_conserves_energy_through_transverse_impact() {
    let end = 1.2;
    let mut figures = Vec::new();
    for scheme in ["usavg", "musl", "usf", "usl"] {
        let scene = impact_scene(scheme, end, 2.0);
        let mut sim = scene.build().unwrap();
        sim.options.checked = true;
        let e0 = total_energy(&sim);
        let p0 = momentum(&sim);
        let disk_ke = |s: &Simulation| -> f64 {
            let p = &s.particles;
            (0..p.len()).filter(|&i| p.body[i] == 1).map(|i| 0.5 * p.mass[i] * p.v[i].norm_squared()).sum()
        };
        let kd0 = disk_ke(&sim);
        let (mut emin, mut emax, mut max_dp, mut kd_min) = (0.0f64, 0.0f64, 0.0f64, f64::INFINITY);
        let t0 = std::time::Instant::now();
        let r = sim.run_until(end, |s| {
            let d = (total_energy(s) - e0) / e0;
            emin = emin.min(d);
            emax = emax.max(d);
            let p = &s.particles;
            let scale: f64 = (0..p.len()).map(|i| p.mass[i] * (p.v[i].x.abs() + p.v[i].y.abs())).sum();
            max_dp = max_dp.max((momentum(s) - p0).norm() / scale);
            kd_min = kd_min.min(disk_ke(s));
        });
        let fin = (total_energy(&sim) - e0) / e0;
        println!(
            "{scheme:>5}: {:?} t = {:.3} ms, {} steps, {} particles, {:.1} s; ΔE/E0 in [{emin:+.3e}, {emax:+.3e}], final {fin:+.3e}; max |ΔP|/Σm|v| {max_dp:.2e}; disk KE min/KE0 {:.3}",
            r.as_ref().err(),
            sim.time,
            sim.step_count,
            sim.particles.len(),
            t0.elapsed().as_secs_f64(),
            kd_min / kd0
        );
        figures.push((scheme, r.is_ok(), emin, emax, max_dp, kd_min / kd0));
    }
    let (_, ok, emin, emax, dp, kd) = figures[0];
    assert!(ok);
    assert!(emin > -5e-3 && emax < 5e-3, "usavg energy range [{emin}, {emax}]");
    assert!(dp < 1e-12);
    assert!(kd < 0.5, "the disk did not hit the beam: min KE ratio {kd}");
}
