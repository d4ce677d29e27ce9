//! Static edge and centre cracks under slowly applied, damped tension, against Tada's
//! formulas (verification references §1(c), §1(d); Tada, Paris & Irwin 1973).
//!
//! K_I = σ√(πa) F(α), for a long plate under uniform remote tension σ (ends free to
//! rotate: traction loading):
//! * CCT (centre crack 2a, width 2b, α = a/b): F = (1 − 0.025α² + 0.06α⁴)√(sec(πα/2)),
//!   0.1 % for any α;
//! * SENT (edge crack a, width W, α = a/W): F = √((2/(πα)) tan(πα/2)) [0.752 + 2.02α +
//!   0.37(1 − sin(πα/2))³]/cos(πα/2), better than 0.5 %.
//! The formulas are for long plates; the plates here are 3b (CCT) and 2W (SENT) high
//! per half, where the references put the length effect below the formulas' accuracy.
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
fn plate(h: f64, width: f64, half_height: f64, a: f64, symmetric: bool, ramp: f64, damping: f64, end: f64) -> String {
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
        x0 = -2.0 * h - 0.25 * h,
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

fn k_static(text: &str) -> (Vec<(f64, f64)>, f64) {
    let scene = Scene::from_toml(text, "plate").unwrap();
    let mut sim = scene.build().unwrap();
    let end = scene.solver.end_time;
    let mut out = Vec::new();
    let mut next = 0.1 * end;
    while sim.time + 0.5 * sim.options.dt < end {
        sim.run_until(next, |_| {}).unwrap();
        next += 0.1 * end;
        let t = sim.tip_fracture(0, TipEnd::End, 2, false, 0.0).unwrap();
        let t3 = sim.tip_fracture(0, TipEnd::End, 3, false, 0.0).unwrap();
        out.push((t.k1, t3.k1));
    }
    (out, sim.time)
}

#[test]
fn explore_plates() {
    let h: f64 = std::env::var("H").ok().and_then(|v| v.parse().ok()).unwrap_or(1.0);
    let (a, b) = (5.0, 10.0);
    let text = plate(h, b, 30.0, a, true, 0.25, 60.0, 0.6);
    let (k, _) = k_static(&text);
    let kref = SIGMA * (std::f64::consts::PI * a).sqrt() * tada_cct(a / b);
    for (k2, k3) in &k {
        println!("CCT h={h}: K(2x2)={k2:.4} ({:+.2}%) K(3x3)={k3:.4} ({:+.2}%)", 100.0 * (k2 / kref - 1.0), 100.0 * (k3 / kref - 1.0));
    }
    let (a, w) = (6.0, 20.0);
    let text = plate(h, w, 20.0, a, false, 0.25, 60.0, 0.6);
    let (k, _) = k_static(&text);
    let kref = SIGMA * (std::f64::consts::PI * a).sqrt() * tada_sent(a / w);
    for (k2, k3) in &k {
        println!("SENT h={h}: K(2x2)={k2:.4} ({:+.2}%) K(3x3)={k3:.4} ({:+.2}%)", 100.0 * (k2 / kref - 1.0), 100.0 * (k3 / kref - 1.0));
    }
    println!("F_cct(0.5) = {}, F_sent(0.3) = {}", tada_cct(0.5), tada_sent(0.3));
}

