//! Chen's (1975) centre-cracked plate under a Heaviside tension (Guo & Nairn 2004 §4.2;
//! references §2(c)): plate 2b × 2h = 20 × 40 mm, crack 2a = 4.8 mm, E = 199.4 GPa,
//! ν = 0.3, ρ = 5000 kg/m³, σ₀ = 400 MPa on the edges parallel to the crack, plane strain.
//!
//! Units: mm, g, µs, so stresses are in TPa (1 TPa = 10⁶ MPa) and K in TPa·√mm.
//!
//! Reference (exact, references §2(c)): the P wave reaches the crack plane at
//! t₀ = h/c_d = 2.7296 µs, so K_I ≡ 0 before; for t₀ < t < t₀ + 2a/c_d = 3.385 µs the
//! tip responds as a semi-infinite crack (Freund; Thau & Lu 1971):
//! K_I/(σ√(πa)) = (2/(π(1−ν))) √(c_d (t − t₀)(1−2ν)/a).
//! That curve is exact only if no other wave reaches the tip before 3.385 µs, which
//! needs rollers on the lateral edges (free edges send a P wave from the loaded corners
//! at 2.920 µs), so the lateral edges have rollers here.
//!
//! The model is the right half (x ≥ 0) with the symmetry plane x = 0 on rollers; the
//! crack runs from outside the body to the tip at x = a.

use cramp::fracture::jintegral::TipEnd;
use cramp::material::Constitutive;
use cramp::scene::Scene;

const E: f64 = 0.1994;
const NU: f64 = 0.3;
const RHO: f64 = 5.0e-3;
const SIGMA: f64 = 4.0e-4;
const A: f64 = 2.4;

fn chen(h: f64, shape: &str, end_time: f64) -> String {
    // Total force on the top (and bottom) row of particles: σ₀ × half width × thickness.
    let force = SIGMA * 10.0;
    format!(
        r#"
title = "Chen CCT (half) h={h}"
[grid]
origin = [{x0}, -21.0]
size = [{sx}, 42.0]
cell = [{h}, {h}]
[solver]
end_time = {end_time}
shape = "{shape}"
particles_per_cell = 2
[[materials]]
name = "steel"
E = {E}
nu = {NU}
rho = {RHO}
state = "plane_strain"
[[bodies]]
material = "steel"
shape = {{ rectangle = {{ min = [0.0, -20.0], max = [10.0, 20.0] }} }}
[[boundary]]
nodes = {{ region = {{ min = [{x0}, -21.0], max = [0.0, 21.0] }} }}
vx = 0.0
[[boundary]]
nodes = {{ region = {{ min = [10.0, -21.0], max = [{x1}, 21.0] }} }}
vx = 0.0
[[loads]]
particles = {{ region = {{ min = [0.0, {ytop}], max = [10.0, 20.0] }} }}
force = [0.0, {force}]
[[loads]]
particles = {{ region = {{ min = [0.0, -20.0], max = [10.0, {ybot}] }} }}
force = [0.0, {neg}]
[[cracks]]
points = [[{cx}, 0.0], [{A}, 0.0]]
contact = "frictionless"
fracture = {{ tips = "end", area_term = true }}
"#,
        x0 = -2.0 * h,
        sx = 10.0 + 4.0 * h,
        x1 = 10.0 + 2.0 * h,
        ytop = 20.0 - 0.5 * h,
        ybot = -20.0 + 0.5 * h,
        neg = -force,
        cx = -h,
    )
}

/// Freund's semi-infinite-crack response to a crack-face pressure p applied suddenly at
/// t₀ (Freund 1990 §7.2; references §2(c)), normalised by σ₀√(πa):
/// K_I = 2p √(c_d (t − t₀)(1 − 2ν)/π) / (1 − ν).
fn freund(p_over_sigma: f64, cd: f64, t: f64, t0: f64) -> f64 {
    if t <= t0 {
        return 0.0;
    }
    p_over_sigma * 2.0 / (std::f64::consts::PI * (1.0 - NU)) * (cd * (t - t0) * (1.0 - 2.0 * NU) / A).sqrt()
}

struct Sample {
    t: f64,
    /// K_I/(σ₀√(πa)) from the two-term J on the 2×2 and 8×8 contours, and the line term alone on 8×8.
    k2: f64,
    k8: f64,
    k8_line: f64,
    /// σ_yy at the ligament node (8, 0), 5.6 mm ahead of the tip, over σ₀.
    syy_ligament: f64,
}

fn run_chen(h: f64, end: f64) -> (Vec<Sample>, f64, f64) {
    let scene = Scene::from_toml(&chen(h, "ugimp", end), "chen").unwrap();
    let mut sim = scene.build().unwrap();
    let cd = sim.materials[0].wave_speed();
    let t0 = 20.0 / cd;
    let k0 = SIGMA * (std::f64::consts::PI * A).sqrt();
    let ep = E / (1.0 - NU * NU);
    let k_of = |j: f64| (ep * j.max(0.0)).sqrt() / k0;
    let node = sim.grid.node_index((8.0 / h) as usize + 2, (21.0 / h).round() as usize);
    assert_eq!(sim.grid.node_pos(node), cramp::dim::Vector::new(8.0, 0.0));
    let mut out = Vec::new();
    let mut next: f64 = 0.05;
    while sim.time + 0.5 * sim.options.dt < end {
        sim.run_until(next.min(end), |_| {}).unwrap();
        next += 0.05;
        let j2 = sim.tip_fracture(0, TipEnd::End, 2, true, 0.0).unwrap();
        let j8 = sim.tip_fracture(0, TipEnd::End, 8, true, 0.0).unwrap();
        let syy = sim.nodal_state(node)[0].map(|s| s.stress.yy).unwrap_or(f64::NAN);
        out.push(Sample { t: sim.time, k2: k_of(j2.j1), k8: k_of(j8.j1), k8_line: k_of(j8.j1_line), syy_ligament: syy / SIGMA });
    }
    (out, cd, t0)
}

/// The early-time response at 0.25 mm cells (CI size; 0.125 mm in `cramp verify`).
///
/// 1. The stress the uncracked plate carries on the crack plane after t₀ is 2σ₀, not
///    σ₀: the tension waves from the top and the bottom edge arrive together and
///    superpose. Checked at the ligament node (8, 0), which no wave diffracted by the
///    tip reaches before t₀ + 5.6 mm/c_d = 3.49 µs: over 2.95–3.45 µs σ_yy/σ₀ rings
///    about 2 (the discrete step front overshoots by up to 25 % at this resolution,
///    USAVG, no artificial viscosity), staying within 1.5–2.6 with a mean within 10 %
///    of 2 — unambiguously 2σ₀, not σ₀.
/// 2. Hence the crack faces are unloaded by p = 2σ₀, and Freund's formula with p = 2σ₀
///    is the exact K_I(t) for t₀ < t < 3.385 µs. The references (§2(c)) print it with
///    p = σ₀ — a factor of two too small for this symmetric load; see
///    verification/references-errata.md. The measured curve follows 2σ₀ and not σ₀.
/// 3. Before the front arrives K_I is zero: |K| ≤ 0.05 up to t₀ − 0.2 µs (the discrete
///    step front is smeared over ~6 cells, 1.5 mm = 0.2 µs at this resolution).
/// 4. Tolerance on K(t) − exact: 0.1 for t ≥ t₀ + 0.25 µs at 0.25 mm. The smeared front
///    delays and rings the rise by O(h/c_d); 0.05 needs the 0.125 mm run of the full
///    suite.
/// 5. Path independence (004 §4.3): the two-term J on the 2×2 and 8×8 contours agree
///    within 3 % once the tip is loaded, while the line term alone on the 8×8 contour
///    (2 mm from the tip, enclosing the wave-loaded region) is more than 10 % low.
#[test]
fn chen_early_time_k_follows_freund_with_the_superposed_wave() {
    let (s, cd, t0) = run_chen(0.25, 3.45);
    let t_end = t0 + 2.0 * A / cd; // 3.385 µs: the far tip's diffracted wave arrives
    let mut worst = (0.0f64, 0.0f64);
    let mut line_gap = 0.0f64;
    for x in &s {
        let exact = freund(2.0, cd, x.t, t0);
        println!(
            "t = {:.3} µs: K/σ√(πa) 2×2 {:.4}, 8×8 {:.4}, 8×8 line only {:.4}; Freund p = 2σ₀ {:.4} (p = σ₀ {:.4}); σyy(8,0)/σ₀ {:.4}",
            x.t, x.k2, x.k8, x.k8_line, exact, freund(1.0, cd, x.t, t0), x.syy_ligament
        );
    }
    let ringing: Vec<f64> = s.iter().filter(|x| (2.95..=3.45).contains(&x.t)).map(|x| x.syy_ligament).collect();
    let mean = ringing.iter().sum::<f64>() / ringing.len() as f64;
    println!("σyy(8,0)/σ₀ over 2.95–3.45 µs: mean {mean:.4}, range {:.4}–{:.4}", ringing.iter().cloned().fold(f64::INFINITY, f64::min), ringing.iter().cloned().fold(0.0, f64::max));
    assert!((mean - 2.0).abs() <= 0.1 * 2.0, "mean σyy/σ₀ on the ligament {mean}");
    assert!(ringing.iter().all(|&r| (1.5..=2.6).contains(&r)), "σyy/σ₀ on the ligament leaves 2 ± 25 %: {ringing:?}");
    for x in &s {
        let exact = freund(2.0, cd, x.t, t0);
        if x.t <= t0 - 0.2 {
            assert!(x.k2.abs() <= 0.05, "K before the wave arrives: {} at {} µs", x.k2, x.t);
        }
        if x.t >= t0 + 0.25 && x.t <= t_end {
            let err = x.k2 - exact;
            if err.abs() > worst.0.abs() {
                worst = (err, x.t);
            }
            assert!(err.abs() <= 0.1, "K {} vs exact {exact} at {} µs", x.k2, x.t);
        }
        if x.t >= 3.0 {
            assert!((x.k8 - x.k2).abs() <= 0.03 * x.k2, "two-term J path dependent: 2×2 {} vs 8×8 {} at {}", x.k2, x.k8, x.t);
            line_gap = line_gap.max((x.k2 - x.k8_line) / x.k2);
        }
    }
    println!("largest |K − exact| for t₀+0.25 ≤ t ≤ 3.385 µs: {:.4} at {:.3} µs; largest line-term deficit on 8×8: {:.1} %", worst.0, worst.1, 100.0 * line_gap);
    assert!(line_gap > 0.1, "the one-term J should drift on the large contour");
}
