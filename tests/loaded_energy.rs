//! Energy balance under applied loads: kinetic + strain + damped − external work = 0
//! (a conservation law; Nairn 2003 §2.3 discusses energy for the update schemes).
//!
//! A plate 10 × 60 mm (rollers on x = 0) pulled by a uniform tension ramped over 0.25 ms
//! on its top and bottom rows of particles, damped (κ = 60 ms⁻¹), USAVG. The external
//! work is Σ f_p·Δx_p, the work of the grid forces along the particles' grid-velocity
//! paths. Before this test existed, cramp integrated f_p·v_p with the particle
//! velocity: the FLIP update leaves components in v_p that the grid cannot see, and
//! under a load on one row of particles they correlate with the load — the "work" fell
//! to −0.018 while the strain energy rose to 0.27 (the checked mode then reported a
//! false `Unstable`). Tolerance 1 % of the work: the load is held constant within a step
//! (first-order in dt, ~0.5 % measured here) and USAVG's own energy error is ~10⁻⁴.

use cramp::scene::Scene;

mod common;
use common::{PLATE, PLATE_GRIPS};

#[test]
fn energy_balance_holds_under_a_ramped_load_with_damping() {
    let text = format!(
        r#"{PLATE}
[solver]
end_time = 0.3
damping = 60.0
particles_per_cell = 2
[[loads]]
particles = {{ region = {{ min = [0.0, 29.5], max = [10.0, 30.0] }} }}
force = [0.0, 10.0]
ramp = 0.25
[[loads]]
particles = {{ region = {{ min = [0.0, -30.0], max = [10.0, -29.5] }} }}
force = [0.0, -10.0]
ramp = 0.25
"#
    );
    let scene = Scene::from_toml(&text, "loaded plate").unwrap();
    let mut sim = scene.build().unwrap();
    let mut worst = 0.0f64;
    for k in 1..=6 {
        sim.run_until(0.05 * k as f64, |_| {}).unwrap();
        let e = sim.energies();
        let imbalance = e.kinetic + e.strain + e.damping - e.external_work;
        println!("t = {:.3}: KE {:.4e} SE {:.4e} damped {:.4e} work {:.4e} imbalance {:+.3e}", sim.time, e.kinetic, e.strain, e.damping, e.external_work, imbalance);
        assert!(e.external_work > 0.0);
        worst = worst.max(imbalance.abs() / e.external_work);
    }
    println!("largest |imbalance| / work: {worst:.3e}");
    assert!(worst <= 0.01, "energy imbalance {worst}");
}

/// The plate of the test above held by moving grips instead of loads: the nodes beyond
/// its top and bottom edges move apart at ±v from t = 0 (a step in velocity, damped). The
/// grips' work is the `boundary_work` of the energies (the reaction the held components
/// lose in Task 3 times v Δt); the conservation law is kinetic + strain + damped −
/// boundary work = 0 for every scheme. Tolerance 1 % of the work, as the loaded plate
/// above and for the same reason: the reaction is held constant within a step, an error
/// first order in Δt. That order is checked too: halving the time step (cfl 0.4 → 0.2)
/// must at least nearly halve the largest imbalance (ratio ≤ 0.65) for MUSL, USF and
/// USAVG. Measured: 3.4e−3 → 1.6e−3 (MUSL), 4.0e−3 → 2.1e−3 (USF), 6.0e−4 → 3.0e−4
/// (USAVG); USL 1.17e−3 → 1.27e−3, its own energy error (USL does not conserve energy,
/// Nairn 2003 §2.3), not first order in Δt, so USL has the 1 % bound only. Before
/// `boundary_work` existed the grips' work was nowhere in the history and the "total" of
/// a gripped run rose with the strain energy.
#[test]
fn energy_balance_holds_with_moving_grips_for_every_scheme() {
    for scheme in ["usl", "musl", "usf", "usavg"] {
        let worst = [0.4, 0.2].map(|cfl| gripped_plate_imbalance(scheme, cfl));
        println!("{scheme}: largest |imbalance| / grip work {:.3e} (cfl 0.4), {:.3e} (cfl 0.2)", worst[0], worst[1]);
        assert!(worst.iter().all(|w| *w <= 0.01), "{scheme}: energy imbalance {worst:?}");
        if scheme != "usl" {
            assert!(worst[1] <= 0.65 * worst[0], "{scheme}: imbalance not first order in dt: {worst:?}");
        }
    }
}

/// Largest |kinetic + strain + damped − boundary work| / boundary work of the gripped plate
/// at six times to 0.3 ms.
fn gripped_plate_imbalance(scheme: &str, cfl: f64) -> f64 {
    let text = format!(
        r#"{PLATE}
[solver]
end_time = 0.3
damping = 60.0
particles_per_cell = 2
scheme = "{scheme}"
cfl = {cfl}
{PLATE_GRIPS}"#
    );
    let scene = Scene::from_toml(&text, "gripped plate").unwrap();
    let mut sim = scene.build().unwrap();
    let mut worst = 0.0f64;
    for k in 1..=6 {
        sim.run_until(0.05 * k as f64, |_| {}).unwrap();
        let e = sim.energies();
        let imbalance = e.kinetic + e.strain + e.damping - e.boundary_work;
        println!("{scheme} cfl {cfl} t = {:.3}: KE {:.4e} SE {:.4e} damped {:.4e} grips {:.4e} imbalance {:+.3e}", sim.time, e.kinetic, e.strain, e.damping, e.boundary_work, imbalance);
        assert!(e.boundary_work > 0.0 && e.external_work == 0.0);
        assert_eq!(e.total().to_bits(), imbalance.to_bits());
        worst = worst.max(imbalance.abs() / e.boundary_work);
    }
    worst
}

/// The same law in 3D, with particle damping: the block of
/// verification/block_tension_3d.toml (rollers on its three faces through the origin)
/// stretched by its x = L node plane moving at v (instead of the particle load). One
/// solver for both dimensions: `boundary_work` is the same sum in 3D. Tolerance 1 % of
/// the grips' work, as the 2D tests (first order in Δt). Measured 7.3e−4 (at 0.5; the
/// imbalance stays at −3.5e−6 while the work grows to 0.136).
#[test]
fn energy_balance_holds_with_a_moving_grip_in_3d() {
    let text = r#"
[grid]
origin = [-2.0, -2.0, -2.0]
size = [16.0, 8.0, 8.0]
cell = [1.0, 1.0, 1.0]
[solver]
scheme = "usavg"
shape = "ugimp"
cfl = 0.5
end_time = 3.0
particles_per_cell = 2
damping = 8.0
damping_on = "particles"
[[materials]]
name = "m"
E = 1000.0
nu = 0.3
rho = 1.0
[[bodies]]
material = "m"
shape = { box = { min = [0.0, 0.0, 0.0], max = [10.0, 4.0, 4.0] } }
[[boundary]]
nodes = { box = { min = [-2.0, -2.0, -2.0], max = [0.0, 6.0, 6.0] } }
vx = 0.0
[[boundary]]
nodes = { box = { min = [-2.0, -2.0, -2.0], max = [14.0, 0.0, 6.0] } }
vy = 0.0
[[boundary]]
nodes = { box = { min = [-2.0, -2.0, -2.0], max = [14.0, 6.0, 0.0] } }
vz = 0.0
[[boundary]]
nodes = { box = { min = [10.0, -2.0, -2.0], max = [14.0, 6.0, 6.0] } }
vx = 0.004
"#;
    let mut sim = cramp::scene3d::Scene3::from_toml(text, "gripped block", None).unwrap().build().unwrap();
    let mut worst = 0.0f64;
    for k in 1..=6 {
        sim.run_until(0.5 * k as f64, |_| {}).unwrap();
        let e = sim.energies();
        let imbalance = e.kinetic + e.strain + e.damping - e.boundary_work;
        println!("3D t = {:.3}: KE {:.4e} SE {:.4e} damped {:.4e} grip {:.4e} imbalance {:+.3e}", sim.time, e.kinetic, e.strain, e.damping, e.boundary_work, imbalance);
        assert!(e.boundary_work > 0.0 && e.external_work == 0.0);
        worst = worst.max(imbalance.abs() / e.boundary_work);
    }
    println!("3D: largest |imbalance| / grip work: {worst:.3e}");
    assert!(worst <= 0.01, "3D energy imbalance {worst}");
}
