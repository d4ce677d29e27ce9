//! Dynamic stress intensity factor of Chen's centre-cracked plate (Guo & Nairn 2004
//! §4.2; references §2(c) with verification/references-errata.md): case
//! `chen_early_time`. Plate 2b × 2h = 20 × 40 mm, crack 2a = 4.8 mm, E = 199.4 GPa,
//! ν = 0.3, ρ = 5000 kg/m³, σ₀ = 400 MPa Heaviside on both edges parallel to the crack,
//! plane strain; units mm, g, µs (stresses in TPa). The right half is modelled, the
//! mirror plane x = 0 and the lateral edge on rollers (so the early-time curve is exact).
//!
//! Reference: the waves from the two loaded edges reach the crack plane together at
//! t₀ = h/c_d and superpose to 2σ₀, so until the far tip's diffracted wave arrives
//! (t₀ + 2a/c_d = 3.385 µs) K_I is Freund's semi-infinite-crack response to a crack-face
//! pressure p = 2σ₀: K_I/(σ₀√(πa)) = 2 · (2/(π(1−ν)))√(c_d (t − t₀)(1−2ν)/a).

use crate::fracture::jintegral::TipEnd;
use crate::material::Constitutive;
use crate::report::plot::{PlotSpec, Series};
use crate::scene::Scene;
use crate::verify::{CaseOutput, Plot, Variant};

const E: f64 = 0.1994;
const NU: f64 = 0.3;
const RHO: f64 = 5.0e-3;
const SIGMA: f64 = 4.0e-4;
const A: f64 = 2.4;

/// The half plate at cell size `h`, run to `end_time` µs, J requested at the tip.
pub fn chen_scene(h: f64, end_time: f64) -> anyhow::Result<Scene> {
    // Total force on the top (and bottom) row of particles: σ₀ × half width × thickness.
    let force = SIGMA * 10.0;
    let text = format!(
        r#"
title = "Chen CCT (right half, rollers) h = {h} mm"
[grid]
origin = [{x0}, -21.0]
size = [{sx}, 42.0]
cell = [{h}, {h}]
[solver]
end_time = {end_time}
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
    );
    Ok(Scene::from_toml(&text, "Chen CCT")?)
}

/// Freund's semi-infinite-crack response to a crack-face pressure p applied suddenly at
/// t₀ (Freund 1990 §7.2), normalised by σ₀√(πa): 2p√(c_d (t − t₀)(1 − 2ν)/π)/(1 − ν).
pub fn freund(p_over_sigma: f64, cd: f64, t: f64, t0: f64) -> f64 {
    if t <= t0 {
        return 0.0;
    }
    p_over_sigma * 2.0 / (std::f64::consts::PI * (1.0 - NU)) * (cd * (t - t0) * (1.0 - 2.0 * NU) / A).sqrt()
}

/// One sample of the run.
#[derive(Clone, Copy, Debug)]
pub struct ChenSample {
    pub t: f64,
    /// K_I/(σ₀√(πa)) from the two-term J on the 2×2 and 8×8 contours, and the line term alone on 8×8.
    pub k2: f64,
    pub k8: f64,
    pub k8_line: f64,
    /// σ_yy/σ₀ at the ligament node (8, 0), 5.6 mm ahead of the tip.
    pub syy_ligament: f64,
}

/// The run's samples every 0.05 µs, c_d and t₀.
pub fn run_chen(h: f64, end: f64) -> anyhow::Result<(Vec<ChenSample>, f64, f64)> {
    let mut sim = chen_scene(h, end)?.build()?;
    let cd = sim.materials[0].wave_speed();
    let t0 = 20.0 / cd;
    let k0 = SIGMA * (std::f64::consts::PI * A).sqrt();
    let ep = E / (1.0 - NU * NU);
    let k_of = |j: f64| (ep * j.max(0.0)).sqrt() / k0;
    let node = sim.grid.node_index((8.0 / h).round() as usize + 2, (21.0 / h).round() as usize);
    anyhow::ensure!(sim.grid.node_pos(node) == crate::dim::Vector::new(8.0, 0.0), "no grid node at (8, 0)");
    let mut out = Vec::new();
    let mut next: f64 = 0.05;
    while sim.time + 0.5 * sim.options.dt < end {
        sim.run_until(next.min(end), |_| {})?;
        next += 0.05;
        let j2 = sim.tip_fracture(0, TipEnd::End, 2, true, 0.0)?;
        let j8 = sim.tip_fracture(0, TipEnd::End, 8, true, 0.0)?;
        let syy = sim.nodal_state(node)[0].map(|s| s.stress.yy).unwrap_or(f64::NAN);
        out.push(ChenSample { t: sim.time, k2: k_of(j2.j1), k8: k_of(j8.j1), k8_line: k_of(j8.j1_line), syy_ligament: syy / SIGMA });
    }
    Ok((out, cd, t0))
}

/// The headline numbers of a run (see `verification/cases.toml`, case `chen_early_time`).
#[derive(Clone, Copy, Debug)]
pub struct ChenSummary {
    /// Largest |K − Freund(p = 2σ₀)| for t₀ + 0.25 µs ≤ t ≤ t₀ + 2a/c_d, and its time.
    pub k_error: f64,
    pub k_error_time: f64,
    /// Largest |K| up to t₀ − 0.2 µs.
    pub k_before: f64,
    /// Mean and range of σ_yy/σ₀ on the ligament over 2.95–3.45 µs.
    pub syy_mean: f64,
    pub syy_min: f64,
    pub syy_max: f64,
    /// Largest |K(8×8) − K(2×2)|/K(2×2) (two-term J) for t ≥ 3 µs.
    pub path_dependence: f64,
    /// Largest deficit of the line term alone on 8×8, (K(2×2) − K_line(8×8))/K(2×2), t ≥ 3 µs.
    pub line_deficit: f64,
}

pub fn summarize(s: &[ChenSample], cd: f64, t0: f64) -> ChenSummary {
    let t_end = t0 + 2.0 * A / cd;
    let mut sum = ChenSummary { k_error: 0.0, k_error_time: 0.0, k_before: 0.0, syy_mean: 0.0, syy_min: f64::INFINITY, syy_max: 0.0, path_dependence: 0.0, line_deficit: 0.0 };
    let mut n = 0;
    for x in s {
        if x.t <= t0 - 0.2 {
            sum.k_before = sum.k_before.max(x.k2.abs());
        }
        if x.t >= t0 + 0.25 && x.t <= t_end {
            let err = (x.k2 - freund(2.0, cd, x.t, t0)).abs();
            if err > sum.k_error {
                sum.k_error = err;
                sum.k_error_time = x.t;
            }
        }
        if (2.95..=3.45).contains(&x.t) {
            sum.syy_mean += x.syy_ligament;
            sum.syy_min = sum.syy_min.min(x.syy_ligament);
            sum.syy_max = sum.syy_max.max(x.syy_ligament);
            n += 1;
        }
        if x.t >= 3.0 {
            sum.path_dependence = sum.path_dependence.max((x.k8 - x.k2).abs() / x.k2);
            sum.line_deficit = sum.line_deficit.max((x.k2 - x.k8_line) / x.k2);
        }
    }
    sum.syy_mean /= n.max(1) as f64;
    sum
}

pub fn run(variant: Variant) -> anyhow::Result<CaseOutput> {
    let h = match variant {
        Variant::Quick => 0.25,
        Variant::Full => 0.125,
    };
    let (s, cd, t0) = run_chen(h, 3.45)?;
    let r = summarize(&s, cd, t0);
    let mut out = CaseOutput::default();
    out.measure("k_early", &format!("h = {h} mm, worst at {:.3} µs", r.k_error_time), r.k_error, 0.0);
    out.measure("k_before_arrival", &format!("h = {h} mm, t ≤ t₀ − 0.2 µs"), r.k_before, 0.0);
    out.measure("ligament_stress", &format!("h = {h} mm, mean over 2.95–3.45 µs (range {:.2}–{:.2})", r.syy_min, r.syy_max), r.syy_mean, 2.0);
    out.measure("path_independence", &format!("h = {h} mm, two-term J, 2×2 vs 8×8"), r.path_dependence, 0.0);
    out.measure("line_term_drifts", &format!("h = {h} mm, line term alone on 8×8"), r.line_deficit, 0.0);
    out.note(format!("c_d = {cd:.4} mm/µs, t₀ = {t0:.4} µs, t₀ + 2a/c_d = {:.4} µs", t0 + 2.0 * A / cd));
    let curve = |p: f64| s.iter().map(|x| (x.t, freund(p, cd, x.t, t0))).collect::<Vec<_>>();
    out.figure(
        "chen_early_time.png",
        "K_I(t)/σ₀√(πa) of Chen's plate: MPM (two-term J, 2×2 and 8×8 contours; line term alone on 8×8) against Freund's exact early-time response with p = 2σ₀ (valid to 3.385 µs) and the references' p = σ₀ curve",
        PlotSpec::new("Chen's centre crack: early-time K_I", "t (µs)", "K_I / σ₀√(πa)"),
        Plot::Lines(vec![
            Series::line("MPM, 2×2 contour", s.iter().map(|x| (x.t, x.k2)).collect()),
            Series::line("MPM, 8×8 contour", s.iter().map(|x| (x.t, x.k8)).collect()),
            Series::line("MPM, 8×8 line term only", s.iter().map(|x| (x.t, x.k8_line)).collect()),
            Series::line("Freund, p = 2σ₀ (exact)", curve(2.0)),
            Series::line("Freund, p = σ₀ (references as printed)", curve(1.0)),
        ]),
    );
    Ok(out)
}
