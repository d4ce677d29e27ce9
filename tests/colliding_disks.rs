//! Two colliding elastic disks (Sulsky, Chen & Schreyer 1994; references §5.3, the
//! demo scene `verification/demo.toml`).
//!
//! References and tolerances:
//! * Total linear momentum is a conservation law of MPM without boundary conditions,
//!   loads or damping (Σ_i f_int,i = 0 by the partition of unity). cramp sums exactly,
//!   so we require |P(t) − P(0)| ≤ 1e-12 Σ_p m_p |v_p|₁ at every step (round-off of the
//!   partition of unity and of the velocity updates; the checked mode uses 1e-10 per
//!   step). P(0) itself is ρ(A₁ − A₂)·v: it is zero only if both disks get the same
//!   particles, which the point-symmetric scene does to the bit (asserted).
//! * KE(0) = ½ M |v|² with M = Σ m_p the discrete particle mass (not ρπr²): every
//!   particle has |v|² = 0.02, so the two agree to a few ulps (1e-14 relative).
//! * M → ρπr² as particles refine: the particle area is (number of lattice points in the
//!   disk) × s², whose error is bounded by the area of the annulus of half-width s/√2
//!   (Gauss circle argument: every cell whose centre is counted lies within r + s/√2,
//!   every uncounted one outside r − s/√2), i.e. |M − ρπr²| ≤ ρ·4πr·s/√2. We assert
//!   that bound for particles_per_cell = 1..8 and that the error at 8 is smaller than at 1.
//! * Energy through the impact: no exact post-impact value exists (Sulsky et al. show it
//!   qualitatively). With USAVG we require the total KE + SE to stay within ±1 % of E0
//!   through the collision and rebound — a fairness argument from Nairn 2003 §3.4 (USAVG
//!   within ±0.18 % for an impact) with margin for this coarse 20×20 grid — and the
//!   other schemes' figures are printed, not asserted. After the rebound we check the
//!   disks have separated (the velocities reversed) and the KE
//!   has recovered to more than half of KE(0) (the remainder is in the disks' vibration).

use cramp::scene::{Scene, DEFAULT_SCENE};

fn demo(scheme: &str, ppc: usize, end_time: f64) -> Scene {
    let mut s = Scene::from_toml(DEFAULT_SCENE, "demo").unwrap();
    s.solver.scheme = match scheme {
        "usl" => cramp::simulation::Scheme::Usl,
        "musl" => cramp::simulation::Scheme::Musl,
        "usf" => cramp::simulation::Scheme::Usf,
        _ => cramp::simulation::Scheme::Usavg,
    };
    s.solver.particles_per_cell = ppc;
    s.solver.end_time = end_time;
    s.validate().unwrap();
    s
}

const RHO: f64 = 1000.0;
const R: f64 = 0.2;

#[test]
fn demo_scene_is_the_sulsky_setup() {
    let s = Scene::from_toml(DEFAULT_SCENE, "demo").unwrap();
    assert_eq!(s.bodies.len(), 2);
    assert_eq!(s.materials[0].e, 1000.0);
    assert_eq!(s.materials[0].rho, RHO);
    assert_eq!(s.grid.cell, [0.05, 0.05]);
}

#[test]
fn initial_kinetic_energy_is_half_m_v_squared() {
    let sim = demo("usavg", 2, 3.0).build().unwrap();
    let p = &sim.particles;
    let m: f64 = cramp::exact::sum(&p.mass);
    let ke = sim.energies().kinetic;
    let exact = 0.5 * m * 0.02;
    println!("M = {m:.12e}, KE0 = {ke:.12e}, ½M|v|² = {exact:.12e}, ρπr²·2 = {:.6e}", 2.0 * RHO * std::f64::consts::PI * R * R);
    assert!(((ke - exact) / exact).abs() < 1e-14);
    // Both disks get the same number of particles (the scene is point symmetric).
    let n0 = p.body.iter().filter(|&&b| b == 0).count();
    assert_eq!(n0 * 2, p.len());
    assert_eq!(sim.total_momentum(), nalgebra::Vector2::zeros());
}

#[test]
fn particle_mass_converges_to_rho_pi_r_squared() {
    let exact = RHO * std::f64::consts::PI * R * R;
    let mut errs = Vec::new();
    for ppc in 1..=8 {
        let sim = demo("usavg", ppc, 3.0).build().unwrap();
        let p = &sim.particles;
        let m0: f64 = (0..p.len()).filter(|&i| p.body[i] == 0).map(|i| p.mass[i]).sum();
        let s = 0.05 / ppc as f64;
        let bound = RHO * 4.0 * std::f64::consts::PI * R * s / std::f64::consts::SQRT_2;
        let err = (m0 - exact) / exact;
        println!("ppc {ppc}: spacing {s:.5}, disk mass {m0:.6} vs ρπr² {exact:.6}: rel err {err:+.3e} (bound {:.3e})", bound / exact);
        assert!((m0 - exact).abs() <= bound);
        errs.push(err.abs());
    }
    assert!(errs[7] < errs[0], "{errs:?}");
}

/// Runs to t = 3 like the demo: by t ≈ 4 the rebounding disks, tangent to the grid edges
/// at t = 0, reach the corners again and leave the grid (USL stops there with OutsideGrid).
#[test]
fn momentum_is_conserved_and_energy_recovered() {
    for scheme in ["usl", "musl", "usf", "usavg"] {
        let scene = demo(scheme, 2, 3.0);
        let mut sim = scene.build().unwrap();
        let p0 = sim.total_momentum();
        let e0 = sim.energies().total();
        let ke0 = sim.energies().kinetic;
        let mut max_dp: f64 = 0.0;
        let mut max_de: f64 = 0.0;
        let mut min_ke = f64::INFINITY;
        let mut t_min = 0.0;
        let r = sim.run_until(scene.solver.end_time, |s| {
            let p = &s.particles;
            let scale: f64 = (0..p.len()).map(|i| p.mass[i] * (p.v[i].x.abs() + p.v[i].y.abs())).sum();
            let dp = (s.total_momentum() - p0).norm() / scale;
            max_dp = max_dp.max(dp);
            let e = s.energies();
            max_de = max_de.max(((e.total() - e0) / e0).abs());
            if e.kinetic < min_ke {
                min_ke = e.kinetic;
                t_min = s.time;
            }
        });
        let e = sim.energies();
        // Centre-of-mass velocity of disk 0.
        let p = &sim.particles;
        let (mut m, mut mv) = (0.0, nalgebra::Vector2::zeros());
        for i in 0..p.len() {
            if p.body[i] == 0 {
                m += p.mass[i];
                mv += p.v[i] * p.mass[i];
            }
        }
        let v0 = mv / m;
        println!(
            "{scheme:>5}: {:?}; max |ΔP|/Σm|v| = {max_dp:.3e}; max |ΔE|/E0 = {max_de:.3e}; KE min {:.4} at t = {t_min:.3}; KE(3)/KE0 = {:.4}; final ΔE/E0 = {:+.3e}; disk-0 v_cm = ({:+.4}, {:+.4})",
            r.as_ref().err(),
            min_ke / ke0,
            e.kinetic / ke0,
            (e.total() - e0) / e0,
            v0.x,
            v0.y
        );
        r.unwrap();
        assert!(max_dp <= 1e-12, "{scheme}: momentum error {max_dp:e}");
        if scheme == "usavg" {
            assert!(max_de < 1e-2, "usavg energy error {max_de}");
            assert!(v0.x < 0.0 && v0.y < 0.0, "disk 0 has not rebounded: {v0:?}");
            assert!(e.kinetic > 0.5 * ke0);
        }
    }
}
