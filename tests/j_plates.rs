//! Static edge and centre cracks under slowly applied, damped tension, against Tada's
//! formulas (verification references §1(c), §1(d); Tada, Paris & Irwin 1973).
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
//! strain; units mm, g, ms. The load is ramped over `ramp` and damped.

use cramp::fracture::jintegral::TipEnd;
use cramp::scene::Scene;

fn tada_cct(alpha: f64) -> f64 {
    use std::f64::consts::PI;
    (1.0 - 0.025 * alpha.powi(2) + 0.06 * alpha.powi(4)) * (1.0 / (PI * alpha / 2.0).cos()).sqrt()
}

fn tada_sent(alpha: f64) -> f64 {
    use std::f64::consts::PI;
    let x = PI * alpha / 2.0;
    ((2.0 / (PI * alpha)) * x.tan()).sqrt() * (0.752 + 2.02 * alpha + 0.37 * (1.0 - x.sin()).powi(3)) / x.cos()
}

const SIGMA: f64 = 1.0;

/// `half_width`: x-extent of the modelled body from 0; `symmetric`: rollers at x = 0
/// (the CCT's mirror plane) and the crack from outside to x = a; otherwise the SENT,
/// whose edge crack runs from outside the left edge x = 0 to x = a.
#[allow(clippy::too_many_arguments)]
fn plate(h: f64, width: f64, half_height: f64, a: f64, symmetric: bool, ramp: f64, damping: f64, end: f64, shift: f64) -> String {
    let force = SIGMA * width;
    let mut s = format!(
        r#"
[grid]
origin = [{x0}, {y0}]
size = [{sx}, {sy}]
cell = [{h}, {h}]
[solver]
end_time = {end}
damping = {damping}
particles_per_cell = 2
[[materials]]
name = "m"
E = 1000.0
nu = 0.3
rho = 1.0e-3
state = "plane_strain"
[[bodies]]
material = "m"
shape = {{ rectangle = {{ min = [0.0, {ymin}], max = [{width}, {half_height}] }} }}
[[loads]]
particles = {{ region = {{ min = [0.0, {ytop}], max = [{width}, {half_height}] }} }}
force = [0.0, {force}]
ramp = {ramp}
[[loads]]
particles = {{ region = {{ min = [0.0, {ymin}], max = [{width}, {ybot}] }} }}
force = [0.0, {neg}]
ramp = {ramp}
[[cracks]]
points = [[{cx}, 0.0], [{a}, 0.0]]
contact = "none"
fracture = {{ tips = "end" }}
"#,
        x0 = -2.0 * h - shift * h,
        y0 = -half_height - 2.0 * h,
        sx = width + 4.0 * h,
        sy = 2.0 * half_height + 4.0 * h,
        ymin = -half_height,
        ytop = half_height - 0.5 * h,
        ybot = -half_height + 0.5 * h,
        neg = -force,
        cx = -h,
    );
    if symmetric {
        s += &format!("[[boundary]]\nnodes = {{ region = {{ min = [{}, {}], max = [0.0, {}] }} }}\nvx = 0.0\n", -3.0 * h, -half_height - 2.0 * h, half_height + 2.0 * h);
    }
    s
}

/// K_I (2×2 contour) after the load has been ramped and damped out; asserts it has
/// settled (the last two samples agree within 0.1 %).
fn k_static(text: &str) -> f64 {
    let scene = Scene::from_toml(text, "plate").unwrap();
    let mut sim = scene.build().unwrap();
    let end = scene.solver.end_time;
    let mut ks = Vec::new();
    for k in [0.8, 0.9, 1.0] {
        sim.run_until(k * end, |_| {}).unwrap();
        ks.push(sim.tip_fracture(0, TipEnd::End, 2, false, 0.0).unwrap().k1);
    }
    let n = ks.len();
    assert!((ks[n - 1] - ks[n - 2]).abs() <= 1e-3 * ks[n - 1], "not settled: {ks:?}");
    ks[n - 1]
}

/// The relative errors at h and h/2 must shrink at about first order (the crack tip is
/// resolved to a cell: the CRAMP displacement jump ends somewhere in the tip's cell),
/// and the Richardson extrapolation 2e(h/2) − e(h) must be within 2 % — the issue's
/// tolerance, which the handbook formulas (0.1 %, 0.5 %) and the finite plate height
/// leave room for. The raw errors are printed; 2 % at a single resolution needs
/// ~0.25 mm cells (`cramp verify`).
fn assert_first_order_convergence(name: &str, e: [f64; 2]) {
    let order = (e[0] / e[1]).log2();
    let extrapolated = 2.0 * e[1] - e[0];
    println!("{name}: errors {:+.2} % (h = 1 mm), {:+.2} % (h = 0.5 mm); observed order {order:.2}; Richardson {:+.2} %", 100.0 * e[0], 100.0 * e[1], 100.0 * extrapolated);
    assert!(e[1].abs() < e[0].abs(), "{name}: no convergence");
    assert!((0.5..=1.5).contains(&order), "{name}: observed order {order}");
    assert!(extrapolated.abs() <= 0.02, "{name}: extrapolated error {extrapolated}");
}

/// Centre-cracked plate, 2b = 20 mm, half-height 30 mm = 3b, a = 5 − h/2 (a/b ≈ 0.48):
/// the right half with rollers on the mirror plane x = 0 (a grid line), the tip in the
/// middle of a cell.
#[test]
fn centre_cracked_plate_k_converges_to_tada() {
    let b = 10.0;
    let mut e = [0.0; 2];
    for (k, h) in [1.0, 0.5].into_iter().enumerate() {
        let a = 5.0 - 0.5 * h;
        let k_ref = SIGMA * (std::f64::consts::PI * a).sqrt() * tada_cct(a / b);
        let kk = k_static(&plate(h, b, 30.0, a, true, 0.25, 60.0, 0.6, 0.0));
        e[k] = kk / k_ref - 1.0;
        println!("CCT h = {h}: a = {a}, K_I = {kk:.4}, Tada {k_ref:.4}");
    }
    assert_first_order_convergence("CCT", e);
}

/// Single-edge-notched plate, W = 20 mm, half-height 20 mm = W, a = 6 mm (a/W = 0.3),
/// uniform traction on both ends, the tip in the middle of a cell.
#[test]
fn single_edge_notched_plate_k_converges_to_tada() {
    let (a, w) = (6.0, 20.0);
    let k_ref = SIGMA * (std::f64::consts::PI * a).sqrt() * tada_sent(a / w);
    let mut e = [0.0; 2];
    for (k, h) in [1.0, 0.5].into_iter().enumerate() {
        let kk = k_static(&plate(h, w, 20.0, a, false, 0.25, 60.0, 0.6, 0.5));
        e[k] = kk / k_ref - 1.0;
        println!("SENT h = {h}: K_I = {kk:.4}, Tada {k_ref:.4}");
    }
    assert_first_order_convergence("SENT", e);
}
