//! Colliding cracked disks (Nairn 2003 §3.2, Fig. 3): `verification/cracked_disks.toml`,
//! run to 45 ms in checked mode. Disks 30 mm across, 1 mm thick, central 10 mm cracks —
//! horizontal in the LEFT disk, vertical in the RIGHT disk (the paper's §3.2) — E = 0.1 MPa,
//! ν = 0.33, ρ = 1.5 g/cm³, each moving at 1 mm/ms toward the other, frictionless crack
//! faces with the paper's V_sep = 0.9, V_contact = 1.1. Units mm, g, ms (MPa, N).
//! 1 mm cells, 2×2 particles per cell (5,656 particles, 778 steps), uGIMP, USAVG.
//!
//! References, assertions and why the tolerances are fair:
//!
//! * **Checked mode** (no particle crosses its crack, no node needs three fields, mass,
//!   partition of unity, per-step momentum): the run must complete without a CheckError.
//! * **Momentum** (conservation law: no loads, boundary conditions or damping; contact
//!   impulses are ±Δp pairs, eqs. 13 and 17): |P(t) − P(0)| ≤ 1e-12 Σ_p m_p |v_p|₁ at
//!   every step, the bound of tests/colliding_disks.rs (round-off of the exact sums and of
//!   the partition of unity). P(0) = 0 to the bit: the disks are mirror images.
//! * **The paper's stated result at Fig. 3b** (t = 20 ms, "soon after contact"; our disks
//!   meet at ≈ 14 ms and are most compressed at ≈ 19 ms): the diametral compression opens
//!   the horizontal crack (mode I) — its centre opening (above − below surface, 001
//!   eqs. 11–12) must exceed one cell, h = 1 mm, i.e. be resolved and "well above zero"
//!   — while contact keeps the vertical crack closed: |normal opening| ≤ 0.05 h at every
//!   crack particle at every step up to 20 ms. 0.05 h is the contact-detection resolution
//!   (next item) and is 2 % of what the faces do without contact (negative control).
//! * **No interpenetration of the vertical crack, whole run**: normal opening ≥ −δ_res at
//!   every crack particle and step. δ_res is the resolution of the volume criterion
//!   (eqs. 8–10), computed in the test: with the faces closed and the material next to
//!   the crack at areal ratio J = (1+εxx)(1+εyy), an overlap δ raises the relative nodal
//!   volume to ≈ J(1 + δ/h), so contact is only guaranteed once J(1 + δ/h) ≥ V_sep;
//!   δ_res = h·max(0, V_sep/J_min − 1) with J_min the smallest J next to that crack over
//!   the run (measured 0.857 → 0.050 h). We also require δ_res ≤ 0.1 h so the check
//!   cannot become vacuous.
//! * **Negative control**: the same state at 13 ms (just before contact) continued with
//!   the vertical crack's contact switched off: checked mode must stop it with a crack
//!   crossing on that crack, and (continued unchecked to 20 ms) its faces must overlap
//!   by more than 0.5 mm (measured 2.35 mm, 47× δ_res): so it is contact that holds them.
//! * **Order of magnitude of the opening**: a quasi-static estimate from the measured
//!   peak contact force F (−dP_left/dt, smoothed over ±0.5 ms): the Brazilian-disk stress
//!   at the centre, normal to the loaded diameter, σ = 2F/(πDt), and the Griffith centre
//!   opening in plane stress, δ = 4σa/E (a = 5 mm). Measured peak opening / estimate must
//!   lie in [0.5, 2]: the estimate ignores dynamics (the load rises over ~5 ms, about one
//!   and a half wave transits of the disk; the dynamic amplification of an elastic system
//!   loaded from rest is between 1 and 2), the finite disk (a/R = 1/3 adds ~10 %) and the
//!   10 % strains; measured ratio 1.36 (peak force 0.340 N, estimate 1.44 mm, peak 1.97 mm).
//!
//! Findings printed for the report (not asserted: they depend on the grid and on V_sep):
//! the horizontal crack, when it recloses during the vibration after the impact, overlaps
//! by up to ≈ 0.12 mm (particle faces) because the material next to it is compressed to
//! J ≈ 0.78 < V_sep (δ_res ≈ 0.16 h there); with V_sep = 0.8 no overlap occurs but the
//! faces then stop ≈ 0.2 mm apart (contact detected too early) — the trade-off the paper
//! describes in §3.2. The surface points at and next to the crack tips move with the
//! fields of the nodes around the tip, which mix both faces, and drift (up to ~0.7 mm along
//! the crack); late in the run the horizontal crack's tip point shows a spurious overlap of
//! 0.64 mm where the particle faces overlap by at most 0.12 mm — a surface-tracking
//! artifact, not interpenetration. The vertical crack's points, tips included, all stay
//! within δ_res and are all checked. Kinetic + strain energy stays within 0.48 % of E(0)
//! (printed only: contact's equalisation of normal velocities is inelastic).
//!
//! Cost: ≈ 20–35 s release on the shared 2-core machine (the negative control ≈ 4 s).

use cramp::crack::ContactLaw;
use cramp::scene::Scene;
use cramp::simulation::Simulation;
use std::path::Path;

const H: f64 = 1.0; // cell size, mm
const A: f64 = 5.0; // crack half-length, mm
const D: f64 = 30.0; // disk diameter, mm
const HORIZONTAL: usize = 0; // crack index in the scene (left disk)
const VERTICAL: usize = 1; // crack index in the scene (right disk)

fn scene() -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("verification/cracked_disks.toml");
    Scene::from_file(&path).unwrap()
}

/// Smallest and largest normal opening over a crack's particles, with their indices.
fn opening_range(s: &Simulation, c: usize) -> ((f64, usize), (f64, usize)) {
    let cr = &s.cracks[c];
    let mut lo = (f64::INFINITY, 0);
    let mut hi = (f64::NEG_INFINITY, 0);
    for k in 0..cr.points.len() {
        let n = cr.opening_nt(k).0;
        if n < lo.0 {
            lo = (n, k);
        }
        if n > hi.0 {
            hi = (n, k);
        }
    }
    (lo, hi)
}

/// Normal opening at the crack's middle particle (the crack centre).
fn centre_opening(s: &Simulation, c: usize) -> f64 {
    let cr = &s.cracks[c];
    cr.opening_nt(cr.points.len() / 2).0
}

/// Smallest areal ratio J = (1+εxx)(1+εyy) of the particles within one cell of a crack's
/// bounding box.
fn j_min_near(s: &Simulation, c: usize) -> f64 {
    let e = s.cracks[c].extent;
    let p = &s.particles;
    (0..p.len())
        .filter(|&i| {
            let x = p.x[i];
            x.x >= e.min.x - H && x.x <= e.max.x + H && x.y >= e.min.y - H && x.y <= e.max.y + H
        })
        .map(|i| (1.0 + p.strain[i].xx) * (1.0 + p.strain[i].yy))
        .fold(f64::INFINITY, f64::min)
}

/// x momentum of the left disk (body 0).
fn left_momentum(s: &Simulation) -> f64 {
    let p = &s.particles;
    cramp::exact::sum_iter((0..p.len()).filter(|&i| p.body[i] == 0).map(|i| p.mass[i] * p.v[i].x))
}

#[test]
fn horizontal_crack_opens_on_impact_and_contact_keeps_the_vertical_crack_closed() {
    let scene = scene();
    let v_sep = scene.cracks[VERTICAL].v_sep;
    let mut sim = scene.build().unwrap();
    assert!(sim.options.checked);
    let p0 = sim.total_momentum();
    assert_eq!((p0.x, p0.y), (0.0, 0.0), "mirror-image disks have zero momentum");
    let e = 0.1; // MPa
    assert_eq!(scene.materials[0].e, e);

    let started = std::time::Instant::now();
    let mut max_dp: f64 = 0.0;
    let e0 = sim.energies().total();
    let mut max_de: f64 = 0.0; // reported, not asserted: contact's velocity equalisation is inelastic
    let mut hist: Vec<(f64, f64)> = Vec::new(); // (t, P_left)
    let mut j_min = [f64::INFINITY; 2];
    let mut v_min_run = (f64::INFINITY, 0.0, 0usize); // vertical crack: smallest opening
    let mut v_abs_to_20 = (0.0f64, 0.0, 0usize); // vertical crack: largest |opening| to 20 ms
    let mut h_peak = (f64::NEG_INFINITY, 0.0); // horizontal crack centre: peak opening
    let mut h_min_run = (f64::INFINITY, 0.0, 0usize); // horizontal crack: smallest opening
    let mut frames: Vec<(f64, f64, f64)> = Vec::new(); // paper's frame times
    let frame_times = [20.0, 32.0, 45.0];
    let mut negative: Option<Simulation> = None;
    let dt = sim.options.dt;

    let r = sim.run_until(scene.solver.end_time, |s| {
        let p = &s.particles;
        let scale = cramp::exact::sum_iter((0..p.len()).map(|i| p.mass[i] * p.v[i].abs().sum()));
        max_dp = max_dp.max((s.total_momentum() - p0).norm() / scale);
        max_de = max_de.max((s.energies().total() - e0).abs() / e0);
        hist.push((s.time, left_momentum(s)));
        for (c, j) in j_min.iter_mut().enumerate() {
            *j = j.min(j_min_near(s, c));
        }
        let ((vlo, vk), (vhi, vhk)) = opening_range(s, VERTICAL);
        if vlo < v_min_run.0 {
            v_min_run = (vlo, s.time, vk);
        }
        if s.time <= 20.0 + 0.5 * dt {
            let (a, k) = if vhi.abs() > vlo.abs() { (vhi.abs(), vhk) } else { (vlo.abs(), vk) };
            if a > v_abs_to_20.0 {
                v_abs_to_20 = (a, s.time, k);
            }
        }
        let ((hlo, hk), _) = opening_range(s, HORIZONTAL);
        if hlo < h_min_run.0 {
            h_min_run = (hlo, s.time, hk);
        }
        let hc = centre_opening(s, HORIZONTAL);
        if hc > h_peak.0 {
            h_peak = (hc, s.time);
        }
        for &tf in &frame_times {
            if (s.time - tf).abs() <= 0.5 * dt {
                frames.push((tf, hc, centre_opening(s, VERTICAL)));
            }
        }
        // Just before the disks touch: keep a copy for the negative control.
        if negative.is_none() && s.time >= 13.0 {
            negative = Some(s.clone());
        }
    });
    let wall = started.elapsed().as_secs_f64();
    r.unwrap_or_else(|e| panic!("checked run failed: {e}"));

    // Momentum.
    println!("max |P(t) − P(0)| / Σ m|v|₁ over {} steps: {max_dp:.3e} (tolerance 1e-12)", sim.step_count);
    assert!(max_dp <= 1e-12, "momentum error {max_dp:e}");
    println!("max |E(t) − E(0)| / E(0) = {max_de:.3e} (kinetic + strain; not asserted)");

    // Fig. 3b: horizontal crack open, vertical crack closed.
    let f20 = frames.iter().find(|f| f.0 == 20.0).expect("a step at 20 ms");
    println!("Fig. 3 frames (t, horizontal centre COD, vertical centre COD) in mm: {frames:?}");
    println!(
        "horizontal crack: peak centre opening {:.4} mm at {:.2} ms; smallest opening over the run {:.4} mm at {:.2} ms (point {})",
        h_peak.0, h_peak.1, h_min_run.0, h_min_run.1, h_min_run.2
    );
    println!(
        "vertical crack: largest |opening| to 20 ms {:.4} mm at {:.2} ms (point {}); smallest opening over the run {:.4} mm at {:.2} ms (point {})",
        v_abs_to_20.0, v_abs_to_20.1, v_abs_to_20.2, v_min_run.0, v_min_run.1, v_min_run.2
    );
    assert!(f20.1 > H, "horizontal crack not open at 20 ms: {} mm", f20.1);
    assert!(v_abs_to_20.0 <= 0.05 * H, "vertical crack not held closed up to 20 ms: {v_abs_to_20:?}");

    // No interpenetration of the vertical crack beyond the volume criterion's resolution.
    let d_res = H * (v_sep / j_min[VERTICAL] - 1.0).max(0.0);
    println!(
        "J_min next to the cracks: horizontal {:.3}, vertical {:.3} → δ_res(vertical) = {d_res:.4} mm; (horizontal would be {:.4} mm)",
        j_min[HORIZONTAL],
        j_min[VERTICAL],
        H * (v_sep / j_min[HORIZONTAL] - 1.0).max(0.0)
    );
    assert!(d_res <= 0.1 * H, "resolution bound {d_res} too loose to mean anything");
    assert!(
        v_min_run.0 >= -d_res,
        "vertical crack faces overlap by {} mm > δ_res = {d_res} mm: {v_min_run:?}",
        -v_min_run.0
    );

    // Quasi-static order of magnitude of the opening.
    let w = (0.5 / dt).round() as usize;
    let mut f_peak: f64 = 0.0;
    for i in w..hist.len() - w {
        f_peak = f_peak.max((hist[i - w].1 - hist[i + w].1) / (hist[i + w].0 - hist[i - w].0));
    }
    let thickness = scene.bodies[0].thickness;
    let sigma = 2.0 * f_peak / (std::f64::consts::PI * D * thickness);
    let estimate = 4.0 * sigma * A / e;
    let ratio = h_peak.0 / estimate;
    println!("peak contact force {f_peak:.4} N → σ = {sigma:.4e} MPa → Griffith COD {estimate:.4} mm; measured/estimate = {ratio:.3}");
    assert!((0.5..=2.0).contains(&ratio), "peak opening {} mm vs quasi-static estimate {estimate} mm", h_peak.0);

    // Negative control: no contact on the vertical crack from 13 ms.
    let mut neg = negative.expect("state at 13 ms");
    neg.cracks[VERTICAL].contact = ContactLaw::None;
    let err = neg.run_until(20.0, |_| {}).expect_err("faces without contact must cross");
    println!("negative control (no contact on the vertical crack): {err}");
    assert!(matches!(err, cramp::check::CheckError::CrackCrossing { crack: VERTICAL, .. }), "{err}");
    neg.options.checked = false;
    let mut neg_min = f64::INFINITY;
    neg.run_until(20.0, |s| neg_min = neg_min.min(opening_range(s, VERTICAL).0 .0)).unwrap();
    println!("negative control: vertical crack opening down to {neg_min:.4} mm by 20 ms");
    assert!(neg_min < -0.5, "without contact the faces should overlap: {neg_min}");

    println!(
        "wall time {wall:.1} s for the checked run (+ negative control {:.1} s)",
        started.elapsed().as_secs_f64() - wall
    );
}
