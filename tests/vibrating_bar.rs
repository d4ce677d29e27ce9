//! Single-mode vibrating bar (references §5.1, [EXACT]).
//!
//! Bar 0 ≤ x ≤ L, u = 0 at x = 0 (vx fixed on the x = 0 node line), free at x = L,
//! rollers (vy = 0) on the node lines of and beyond the long sides, so the exact
//! solution is 1D with wave speed c = c_d = sqrt((λ+2μ)/ρ) (plane strain λ here):
//! v(x,t) = v0 cos(ωt) sin(βx), β = π/(2L), ω = βc, T = 4L/c, and
//! v_cm(t) = (2 v0/π) cos(ωt).
//!
//! Assertions and why they are fair:
//! * period from the zero crossings of v_cm within 0.5 % of 4L/c for every scheme. The
//!   discretisation error of the frequency is O((βh)²/24 + (ωΔt)²/24) ≈ 2e-4 at
//!   L/h = 25 with 200 steps per period, so 0.5 % (as the brief asks) leaves room but
//!   would catch a wrong wave speed (e.g. plane stress vs strain is 11 %, rollers
//!   missing, i.e. c = sqrt(E/ρ)-like speeds, ≥ 5 %) or a wrong time step.
//! * the discrete initial kinetic energy equals ½ Σ m_p v_p² and is within 0.5 % of the
//!   continuum ρ v0² L H / 4 (midpoint quadrature of sin² with 50 points: error ≈ 1e-4).
//! * energy: KE is measured from the particle velocities at t_n and SE from stresses
//!   that MUSL and USF update half a step out of phase with them; on a single mode
//!   ω these schemes are symplectic Euler, whose energy H = ½(p² + ω²q²) oscillates
//!   about a conserved modified energy with relative amplitude ωΔt/2 (no secular
//!   drift). USAVG updates half the strain before and half after the momentum update
//!   (velocity Verlet-like), amplitude (ωΔt)²/4. We assert: USAVG has the smallest
//!   max |ΔE|/E0 of the four (Nairn 2003 §3.4), USAVG within ±0.5 % of E0 (the paper's
//!   impact stayed within ±0.18 %) and ≤ 1.2 (ωΔt)²/4, MUSL and USF within ±15 % of
//!   ωΔt/2, and the secular drift (energy at the v_cm zero crossings, where the
//!   oscillating part vanishes) below 0.1 % per period for MUSL/USF/USAVG.
//!
//! USL finding (not a bug in cramp, the instability of Nairn 2003 eq. 21): with only
//! the x = 0 node line fixed, the uGIMP particle next to the fixed end moves
//! infinitesimally into the support of the exterior node x = −h whenever it moves
//! left; that node then has a vanishing mass m ~ d² but a force ~ d, so USL (which
//! takes strain rates from p′/m of Task 4) applies a finite strain increment and loses
//! ≈ 1.7 % of the energy per period (more per unit time for smaller Δt: it is a per-step
//! kick) with a ≈ 2 % period error. Fixing vx on the exterior nodes x ≤ 0 as well
//! (equally valid for u(0) = 0) removes it; there USL behaves like MUSL and its period is
//! asserted too. With linear shape functions the effect is absent.

use cramp::material::Constitutive;
use cramp::scene::Scene;

const L: f64 = 25.0;
const H: f64 = 2.0;
const E: f64 = 100.0;
const NU: f64 = 0.3;
const RHO: f64 = 1.0;
const V0: f64 = 0.01;
const PERIODS: f64 = 4.0;

/// `fix_exterior`: fix vx on every node with x ≤ 0 instead of only the x = 0 line.
fn bar_scene(scheme: &str, end_time: f64, fix_exterior: bool) -> Scene {
    let beta = std::f64::consts::PI / (2.0 * L);
    let xmin_fixed = if fix_exterior { -2.0 } else { 0.0 };
    let text = format!(
        r#"
title = "vibrating bar"
[grid]
origin = [-2.0, -2.0]
size = [30.0, 6.0]
cell = [1.0, 1.0]

[solver]
scheme = "{scheme}"
shape = "ugimp"
cfl = 0.5
end_time = {end_time}
particles_per_cell = 2

[[materials]]
name = "m"
E = {E}
nu = {NU}
rho = {RHO}
state = "plane_strain"

[[bodies]]
material = "m"
shape = {{ rectangle = {{ min = [0.0, 0.0], max = [{L}, {H}] }} }}
velocity_sine = {{ amplitude = [{V0}, 0.0], k = [{beta}, 0.0] }}

# u = 0 at x = 0
[[boundary]]
nodes = {{ region = {{ min = [{xmin_fixed}, -2.0], max = [0.0, 4.0] }} }}
vx = 0.0

# rollers on and beyond the long sides
[[boundary]]
nodes = {{ region = {{ min = [-2.0, -2.0], max = [28.0, 0.0] }} }}
vy = 0.0

[[boundary]]
nodes = {{ region = {{ min = [-2.0, 2.0], max = [28.0, 4.0] }} }}
vy = 0.0
"#
    );
    Scene::from_toml(&text, "vibrating_bar").expect("valid scene")
}

fn exact_wave_speed() -> f64 {
    // Plane strain c_d² = E(1−ν)/(ρ(1+ν)(1−2ν)), written independently of material.rs.
    (E * (1.0 - NU) / (RHO * (1.0 + NU) * (1.0 - 2.0 * NU))).sqrt()
}

struct BarRun {
    period: f64,
    max_rel_drift: f64,
    /// Relative energy change per period at the v_cm zero crossings (least squares slope).
    secular_per_period: f64,
    dt: f64,
}

fn run_bar(scheme: &str, fix_exterior: bool) -> BarRun {
    let c = exact_wave_speed();
    let t_exact = 4.0 * L / c;
    let scene = bar_scene(scheme, PERIODS * t_exact, fix_exterior);
    let mut sim = scene.build().unwrap();
    let mass: f64 = sim.particles.mass.iter().sum();
    let e0 = sim.energies().total();
    let mut prev = (0.0, sim.total_momentum().x / mass, e0);
    let mut crossings = Vec::new();
    let mut max_drift: f64 = 0.0;
    sim.run_until(scene.solver.end_time, |s| {
        let v = s.total_momentum().x / mass;
        let t = s.time;
        let e = s.energies().total();
        if prev.1 > 0.0 && v <= 0.0 || prev.1 < 0.0 && v >= 0.0 {
            // Linear interpolation of the zero crossing and of the energy there.
            let f = prev.1 / (prev.1 - v);
            crossings.push((prev.0 + (t - prev.0) * f, prev.2 + (e - prev.2) * f));
        }
        prev = (t, v, e);
        max_drift = max_drift.max(((e - e0) / e0).abs());
    })
    .expect("run");
    assert!(crossings.len() >= 4, "{scheme}: too few zero crossings: {crossings:?}");
    // Crossings are half a period apart: least-squares slope of t_k against k.
    let n = crossings.len() as f64;
    let slope = |y: &dyn Fn(usize) -> f64, x: &dyn Fn(usize) -> f64| {
        let (mx, my) = ((0..crossings.len()).map(x).sum::<f64>() / n, (0..crossings.len()).map(y).sum::<f64>() / n);
        let sxy: f64 = (0..crossings.len()).map(|k| (x(k) - mx) * (y(k) - my)).sum();
        let sxx: f64 = (0..crossings.len()).map(|k| (x(k) - mx).powi(2)).sum();
        sxy / sxx
    };
    let period = 2.0 * slope(&|k| crossings[k].0, &|k| k as f64);
    let secular_per_period = slope(&|k| (crossings[k].1 - e0) / e0, &|k| crossings[k].0) * period;
    BarRun { period, max_rel_drift: max_drift, secular_per_period, dt: sim.options.dt }
}

#[test]
fn wave_speed_of_material_is_plane_strain_dilatational() {
    let scene = bar_scene("usavg", 1.0, false);
    let m = scene.materials()[0];
    let c = exact_wave_speed();
    assert!((m.wave_speed() - c).abs() <= 1e-14 * c, "{} vs {}", m.wave_speed(), c);
}

#[test]
fn initial_kinetic_energy_matches_single_mode() {
    let scene = bar_scene("usavg", 1.0, false);
    let sim = scene.build().unwrap();
    let e = sim.energies();
    let exact = RHO * V0 * V0 * L * H / 4.0;
    println!("KE0 = {:.9e}, continuum ρv0²LH/4 = {exact:.9e}", e.kinetic);
    assert!(((e.kinetic - exact) / exact).abs() < 5e-3, "KE0 {} vs {exact}", e.kinetic);
    assert_eq!(e.strain, 0.0);
}

fn check_schemes(fix_exterior: bool, schemes: &[&str]) -> Vec<(String, BarRun)> {
    let c = exact_wave_speed();
    let t_exact = 4.0 * L / c;
    let mut out = Vec::new();
    for scheme in ["usl", "musl", "usf", "usavg"] {
        let r = run_bar(scheme, fix_exterior);
        let err = (r.period - t_exact) / t_exact;
        println!(
            "exterior fixed = {fix_exterior:5}, {scheme:>5}: T = {:.6} (4L/c = {:.6}, rel err {:+.3e}); max |ΔE|/E0 = {:.3e}; secular ΔE/E0 per period = {:+.3e}",
            r.period, t_exact, err, r.max_rel_drift, r.secular_per_period
        );
        if schemes.contains(&scheme) {
            assert!(err.abs() < 5e-3, "{scheme}: period {} vs 4L/c = {t_exact}", r.period);
        }
        out.push((scheme.to_string(), r));
    }
    out
}

/// The setup of the brief: vx fixed on the x = 0 node line only.
#[test]
fn period_is_four_l_over_c_and_usavg_conserves_energy_best() {
    let runs = check_schemes(false, &["musl", "usf", "usavg"]);
    let c = exact_wave_speed();
    let omega = 2.0 * std::f64::consts::PI * c / (4.0 * L);
    let (_, usavg) = &runs[3];
    let wdt = omega * usavg.dt;
    println!("ωΔt/2 = {:.4e}, (ωΔt)²/4 = {:.4e}", wdt / 2.0, wdt * wdt / 4.0);
    for (s, r) in &runs[..3] {
        assert!(usavg.max_rel_drift < r.max_rel_drift, "usavg {} not better than {s} {}", usavg.max_rel_drift, r.max_rel_drift);
    }
    assert!(usavg.max_rel_drift < 5e-3);
    assert!(usavg.max_rel_drift <= 1.2 * wdt * wdt / 4.0, "usavg {} vs (ωΔt)²/4 = {}", usavg.max_rel_drift, wdt * wdt / 4.0);
    for (s, r) in &runs[1..3] {
        let ratio = r.max_rel_drift / (wdt / 2.0);
        assert!((0.85..1.15).contains(&ratio), "{s}: max |ΔE|/E0 = {} vs ωΔt/2 = {}", r.max_rel_drift, wdt / 2.0);
    }
    for (s, r) in &runs[1..] {
        assert!(r.secular_per_period.abs() < 1e-3, "{s}: secular drift {} per period", r.secular_per_period);
    }
}

/// vx fixed on all nodes x ≤ 0: the vanishing-mass exterior node is gone and USL
/// behaves like the others (see the module comment).
#[test]
fn usl_period_is_right_when_exterior_nodes_are_fixed() {
    let runs = check_schemes(true, &["usl", "musl", "usf", "usavg"]);
    let c = exact_wave_speed();
    let omega = 2.0 * std::f64::consts::PI * c / (4.0 * L);
    let wdt = omega * runs[0].1.dt;
    for (s, r) in &runs[..3] {
        let ratio = r.max_rel_drift / (wdt / 2.0);
        assert!((0.85..1.15).contains(&ratio), "{s}: max |ΔE|/E0 = {} vs ωΔt/2 = {}", r.max_rel_drift, wdt / 2.0);
    }
    for (s, r) in &runs {
        assert!(r.secular_per_period.abs() < 1e-3, "{s}: secular drift {} per period", r.secular_per_period);
    }
}
