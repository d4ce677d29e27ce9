//! Fracture cases. `dcb_k`: K_I of the DCB of Guo & Nairn 2004 §4.1 against corrected beam
//! theory, with run time versus error across cell sizes. `dcb_long`: the same DCB with the paper's grid
//! damping over 10⁵ steps (energy balance, end state). `chen_early_time`: the dynamic
//! stress intensity factor of Chen's centre-cracked plate (Guo & Nairn 2004
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

use crate::fracture::jintegral::{CodMethod, TipEnd};
use crate::material::Constitutive;
use crate::report::plot::{PlotSpec, Series};
use crate::scene::Scene;
use crate::verify::scene_file::SceneFile;
use crate::verify::{CaseOutput, Plot, Variant};


/// Chen's plate material and load (units mm, g, µs; TPa): E, ν, ρ, σ₀ and the half crack length a.
pub const E: f64 = 0.1994;
pub const NU: f64 = 0.3;
pub const RHO: f64 = 5.0e-3;
pub const SIGMA: f64 = 4.0e-4;
pub const A: f64 = 2.4;

/// The half plate at cell size `h`, run to `end_time` µs, J requested at the tip:
/// `verification/chen_cct.toml` with the cell size's overrides.
pub fn chen_file(h: f64, end_time: f64) -> SceneFile {
    SceneFile::new("chen_cct.toml")
        .set("grid.origin", format!("[{}, -21.0]", -2.0 * h))
        .set("grid.size", format!("[{}, 42.0]", 10.0 + 4.0 * h))
        .set("grid.cell", format!("[{h}, {h}]"))
        .set("solver.end_time", end_time)
        .set("boundary.0.nodes.region.min", format!("[{}, -21.0]", -2.0 * h))
        .set("boundary.1.nodes.region.max", format!("[{}, 21.0]", 10.0 + 2.0 * h))
        .set("loads.0.particles.region.min", format!("[0.0, {}]", 20.0 - 0.5 * h))
        .set("loads.1.particles.region.max", format!("[10.0, {}]", -20.0 + 0.5 * h))
        .set("cracks.0.points", format!("[[{}, 0.0], [{A}, 0.0]]", -h))
}

/// [`chen_file`], read.
pub fn chen_scene(h: f64, end_time: f64) -> anyhow::Result<Scene> {
    chen_file(h, end_time).load()
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
    /// The 2×2 K_I with the sign of the crack opening (the COD partition's K_I): negative
    /// where the faces overlap, which a scene without crack contact allows.
    pub k2_signed: f64,
    pub k8: f64,
    pub k8_line: f64,
    /// σ_yy/σ₀ at the ligament node (8, 0), 5.6 mm ahead of the tip.
    pub syy_ligament: f64,
}

/// The run's samples every 0.05 µs, c_d and t₀.
pub fn run_chen(h: f64, end: f64) -> anyhow::Result<(Vec<ChenSample>, f64, f64)> {
    run_chen_scene(&chen_scene(h, end)?, end)
}

/// [`run_chen`] for a variant of [`chen_scene`] (another crack contact law, say).
pub fn run_chen_scene(scene: &Scene, end: f64) -> anyhow::Result<(Vec<ChenSample>, f64, f64)> {
    let h = scene.grid.cell[0];
    let mut sim = scene.build()?;
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
        let j2 = sim.tip_fracture(0, TipEnd::End, 2, true, CodMethod::NextToTip, 0.0)?;
        let j8 = sim.tip_fracture(0, TipEnd::End, 8, true, CodMethod::NextToTip, 0.0)?;
        let syy = sim.nodal_state(node)[0].map(|s| s.stress.yy).unwrap_or(f64::NAN);
        out.push(ChenSample { t: sim.time, k2: k_of(j2.j1), k2_signed: j2.k1 / k0, k8: k_of(j8.j1), k8_line: k_of(j8.j1_line), syy_ligament: syy / SIGMA });
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

// ---------------------------------------------------------------------------------------
// Split beams (Guo & Nairn 2004 §4.1): scenes and beam-theory references
// ---------------------------------------------------------------------------------------

/// Young's modulus of the split beams (MPa).
pub const E_BEAM: f64 = 2300.0;
pub const NU_BEAM: f64 = 0.33;
/// Arm thickness h (mm).
pub const ARM: f64 = 12.0;
/// Root-rotation correction χ of corrected beam theory (Williams 1989, ν = 0.33).
pub const CHI: f64 = 0.6688;

/// How long and how damped a run must be to settle to the static solution.
#[derive(Clone, Copy)]
pub struct Settle {
    pub damping: f64,
    /// `solver.damping_on`: "grid" or "particles".
    pub damping_on: &'static str,
    pub end_time: f64,
}

/// Self-equilibrated opening loads excite only the arms' bending (ω ≈ 6 ms⁻¹): κ = 5 ms⁻¹
/// is near critical and 3 ms is ample.
pub const ARMS: Settle = Settle { damping: 5.0, damping_on: "grid", end_time: 3.0 };
/// Loads with a net force also bend the whole beam, a cantilever 100 mm long and 24 mm
/// deep: uncracked ω₁ = 1.875²√(EI/ρAL⁴) ≈ 3.0 ms⁻¹; the cracked beam is softer (its
/// strain energy oscillates with a period of ≈ 2.6 ms in an underdamped run, ω ≈ 2.4
/// ms⁻¹), so κ = 5 ms⁻¹ is about critical for it as for the arms. The damping acts on the
/// particle velocities too (`damping_on = "particles"`): with grid damping alone the
/// particle-velocity components the grid cannot see keep a kinetic energy of ~1 % of the
/// strain energy indefinitely, and the crack surfaces, which integrate the face velocities,
/// drift with them (δ_II swung ±40 % at 12 ms with κ = 1 ms⁻¹; issue 4 note). Settled to
/// 0.1 % of K by 3 ms at 2 and 1 mm (measured).
pub const WHOLE_BEAM: Settle = Settle { damping: 5.0, damping_on: "particles", end_time: 4.0 };

/// The split beam of Guo & Nairn 2004 §4.1 (Fig. 4) at cell size h: `verification/split_beam.toml`
/// with overrides (end loads, crack contact law as TOML, e.g. `"none"`, J contour, damping).
pub fn beam(h: f64, p_top: f64, p_bottom: f64, contact: &str, contour: usize, settle: Settle) -> SceneFile {
    let Settle { damping, damping_on, end_time } = settle;
    let (ox, lx) = (-8.0 - 0.25 * h, 100.0 - 0.5 * h);
    SceneFile::new("split_beam.toml")
        .set("grid.origin", format!("[{ox}, -8.0]"))
        .set("grid.cell", format!("[{h}, {h}]"))
        .set("solver.end_time", end_time)
        .set("solver.damping", damping)
        .set("solver.damping_on", format!("\"{damping_on}\""))
        .set("boundary.0.nodes.region.min", format!("[{ox}, -8.0]"))
        .set("loads.0.particles.region.min", format!("[{lx}, 12.0]"))
        .set("loads.0.force", format!("[0.0, {p_top}]"))
        .set("loads.1.particles.region.min", format!("[{lx}, 0.0]"))
        .set("loads.1.force", format!("[0.0, {p_bottom}]"))
        .set("cracks.0.contact", format!("\"{contact}\""))
        .set("cracks.0.fracture.contour", contour)
}

/// Crack length from the load line (the loaded particle column at x = 100 − h/4).
pub fn a_of(h: f64) -> f64 {
    50.0 - 0.25 * h
}

/// Corrected beam theory for the DCB, P per arm.
pub fn k_dcb(p: f64, a: f64) -> f64 {
    2.0 * 3f64.sqrt() * p * (a + CHI * ARM) / ARM.powf(1.5)
}

/// Beam theory with shear correction for the equal-shear split beam, P per arm.
pub fn k_enf(p: f64, a: f64) -> f64 {
    3.0 * p * a / ARM.powf(1.5) * (1.0 + 2.0 * (1.0 + NU_BEAM) / 5.0 * (ARM / a).powi(2)).sqrt()
}


/// K_I of the DCB at cell size h after the damped run (last cracks.csv row), J on the
/// 2×2 and 4×4 contours, and the wall time.
pub fn dcb_k(h: f64) -> anyhow::Result<(f64, f64, f64, f64)> {
    let scene = beam(h, 1.0, -1.0, "none", 2, ARMS).load()?;
    let start = std::time::Instant::now();
    let r = crate::output::run_scene(&scene, &crate::output::RunOptions { checked: Some(false), ..Default::default() })?;
    let wall = start.elapsed().as_secs_f64();
    let t = r.tips.last().ok_or_else(|| anyhow::anyhow!("no cracks.csv rows"))?;
    let j4 = r.sim.tip_fracture(0, TipEnd::End, 4, false, CodMethod::NextToTip, 0.0)?.j1;
    Ok((t.k1, t.j1, j4, wall))
}

/// Case `dcb_k`: the quick variant runs 2 mm cells, the full one 4, 2 and 1 mm with the
/// run time against the error (Pareto plot).
pub fn run_dcb(variant: Variant) -> anyhow::Result<CaseOutput> {
    let sizes: &[f64] = match variant {
        Variant::Quick => &[2.0],
        Variant::Full => &[4.0, 2.0, 1.0, 0.5],
    };
    let mut out = CaseOutput::default();
    let mut pareto = Vec::new();
    let mut conv = Vec::new();
    for &h in sizes {
        let (k1, j2, j4, wall) = dcb_k(h)?;
        let k_ref = k_dcb(1.0, a_of(h));
        let err = (k1 - k_ref) / k_ref;
        // 4 mm cells leave three cells per arm: shown in the plots and notes for the
        // convergence and cost picture, not held to the 2 % of converged mode I.
        if h <= 2.0 {
            out.measure("k_i", &format!("h = {h} mm, 2×2 contour"), k1, k_ref);
            out.note(format!("h = {h} mm: {wall:.1} s wall (unchecked)"));
            out.measure("path_independence", &format!("h = {h} mm, J(4×4) vs J(2×2)"), j4, j2);
        } else {
            out.note(format!("h = {h} mm: K_I = {k1:.4} vs {k_ref:.4} ({:+.2} %), J(4×4)/J(2×2) − 1 = {:+.2} %, {wall:.1} s", 100.0 * err, 100.0 * (j4 / j2 - 1.0)));
        }
        pareto.push((wall, err.abs(), format!("h = {h} mm")));
        conv.push((h, err.abs()));
    }
    if pareto.len() > 1 {
        out.figure(
            "dcb_k_runtime.png",
            "DCB of Guo & Nairn 2004 §4.1: |K_I error| against corrected beam theory versus wall time (unchecked, all threads), per cell size",
            PlotSpec::new("DCB K_I: run time versus error", "wall time (s)", "|K_I − K_beam| / K_beam"),
            Plot::Pareto(pareto),
        );
        out.figure(
            "dcb_k_convergence.png",
            "DCB K_I error versus cell size (log–log, fitted order)",
            PlotSpec::new("DCB K_I convergence", "cell size h (mm)", "|K_I − K_beam| / K_beam"),
            Plot::Convergence { points: conv, label: "DCB K_I".into() },
        );
    }
    Ok(out)
}

/// A split beam run to its static state: the last cracks.csv row, how much K still moved
/// over the last history interval (relative to |K|), the K history and the wall time.
pub struct SplitBeam {
    pub tip: crate::fracture::jintegral::TipResult,
    pub settled: f64,
    pub history: Vec<crate::fracture::jintegral::TipResult>,
    pub wall: f64,
}

/// The J contour for the mode II beams: 3×3 at 2 mm (the 2×2 contour passes 4 mm from
/// the tip, where two cells resolve the sliding field, and gives J 4–5 % below the larger
/// contours, which agree with each other), 2×2 (the paper's) below.
pub fn split_contour(h: f64) -> usize {
    if h >= 2.0 {
        3
    } else {
        2
    }
}

/// The split beam with end loads P_T, P_B at cell size h, damped to its static state.
pub fn split_beam(h: f64, p_top: f64, p_bottom: f64) -> anyhow::Result<SplitBeam> {
    let scene = beam(h, p_top, p_bottom, "none", split_contour(h), WHOLE_BEAM).set("cracks.0.fracture.cod", "\"fit\"").load()?;
    let start = std::time::Instant::now();
    let r = crate::output::run_scene(&scene, &crate::output::RunOptions { checked: Some(false), ..Default::default() })?;
    let wall = start.elapsed().as_secs_f64();
    let n = r.tips.len();
    anyhow::ensure!(n >= 2, "split beam: {n} cracks.csv rows");
    let (a, b) = (r.tips[n - 2], r.tips[n - 1]);
    let settled = (a.k1 - b.k1).abs().max((a.k2 - b.k2).abs()) / b.k1.hypot(b.k2);
    Ok(SplitBeam { tip: b, settled, history: r.tips, wall })
}

/// Case `split_beams_k`: the equal-shear ("ENF", P_T = P_B) and mixed-mode (P_T = P,
/// P_B = 0) split beams of Guo & Nairn 2004 §4.1 against beam theory: K_II of eq. 24 for
/// the first, half the DCB's K_I and half the ENF's K_II for the second (superposition).
pub fn run_split_beams(variant: Variant) -> anyhow::Result<CaseOutput> {
    let sizes: &[f64] = match variant {
        Variant::Quick => &[2.0],
        Variant::Full => &[2.0, 1.0],
    };
    let mut out = CaseOutput::default();
    let mut last = None;
    for &h in sizes {
        let a = a_of(h);
        let enf = split_beam(h, 1.0, 1.0)?;
        let mixed = split_beam(h, 1.0, 0.0)?;
        let c = split_contour(h);
        out.measure("mode_ii_k2", &format!("h = {h} mm, {c}×{c} contour"), enf.tip.k2.abs(), k_enf(1.0, a));
        out.measure("mode_ii_k1", &format!("h = {h} mm"), (enf.tip.k1 / enf.tip.k2).abs(), 0.0);
        out.measure("mixed_k1", &format!("h = {h} mm, {c}×{c} contour"), mixed.tip.k1, 0.5 * k_dcb(1.0, a));
        out.measure("mixed_k2", &format!("h = {h} mm, {c}×{c} contour"), mixed.tip.k2.abs(), 0.5 * k_enf(1.0, a));
        out.measure("settled", &format!("h = {h} mm, both beams, last 0.5 ms"), enf.settled.max(mixed.settled), 0.0);
        out.note(format!(
            "h = {h} mm: ENF J = {:.5e}, δ_I/δ_II = {:+.4}; mixed J = {:.5e}, δ_II/δ_I = {:.4} (beam theory {:.4}); wall {:.1} s + {:.1} s (unchecked)",
            enf.tip.j1,
            enf.tip.delta_i / enf.tip.delta_ii,
            mixed.tip.j1,
            mixed.tip.delta_ii / mixed.tip.delta_i,
            k_enf(1.0, a) / k_dcb(1.0, a),
            enf.wall,
            mixed.wall
        ));
        last = Some((h, enf, mixed));
    }
    if let Some((h, enf, mixed)) = last {
        let a = a_of(h);
        let t_end = WHOLE_BEAM.end_time;
        let k = |r: &SplitBeam, f: fn(&crate::fracture::jintegral::TipResult) -> f64| r.history.iter().map(|t| (t.time, f(t))).collect::<Vec<_>>();
        let flat = |name: &str, v: f64| Series::line(name, vec![(0.0, v), (t_end, v)]);
        out.figure(
            "split_beams_k.png",
            &format!("K_I and K_II of the split beams at {h} mm cells, damped from the sudden end loads to the static state, against beam theory (ENF: eq. 24; mixed: half the DCB and ENF values)"),
            PlotSpec::new("Split beams: K against beam theory", "t (ms)", "K (MPa√mm)"),
            Plot::Lines(vec![
                Series::line("ENF K_II", k(&enf, |t| t.k2.abs())),
                Series::line("ENF K_I", k(&enf, |t| t.k1)),
                Series::line("mixed K_I", k(&mixed, |t| t.k1)),
                Series::line("mixed K_II", k(&mixed, |t| t.k2.abs())),
                flat("beam theory ENF K_II", k_enf(1.0, a)),
                flat("beam theory mixed K_I", 0.5 * k_dcb(1.0, a)),
                flat("beam theory mixed K_II", 0.5 * k_enf(1.0, a)),
            ]),
        );
    }
    Ok(out)
}

// ---------------------------------------------------------------------------------------
// Long run of the damped DCB (issue 6): energy balance over 10⁵ steps, static end state
// ---------------------------------------------------------------------------------------

/// Steps of the long DCB run.
pub const DCB_LONG_STEPS: u64 = 100_000;
/// K_I is evaluated every this many steps; the last `DCB_LONG_WINDOW` steps are the
/// window in which a static state must not change.
pub const DCB_LONG_K_EVERY: u64 = 100;
pub const DCB_LONG_WINDOW: u64 = 3000;
/// The damping of Guo & Nairn 2004 §4.1 (d_k = 1000 s⁻¹ = 1 ms⁻¹) on the grid, as the
/// paper and `verification/dcb_perf.toml` have it (the end time is set from the steps).
pub const PAPER_DAMPING: Settle = Settle { damping: 1.0, damping_on: "grid", end_time: 1.0 };
/// The same κ acting on the particle velocities too (`damping_on = "particles"`).
pub const PARTICLE_DAMPING: Settle = Settle { damping: 1.0, damping_on: "particles", end_time: 1.0 };

/// One sample of the long run.
#[derive(Clone, Copy, Debug)]
pub struct DcbLongSample {
    pub t: f64,
    pub e: crate::simulation::Energies,
    /// −½Δt Σ_p f_p·v_p: the first-order term the balance carries (see [`dcb_long`]).
    pub load_term: f64,
}

/// What the long DCB run measured.
#[derive(Clone, Debug)]
pub struct DcbLong {
    pub cell: f64,
    pub dt: f64,
    pub steps: u64,
    /// Wall time of the time loop (energies every step, J every `DCB_LONG_K_EVERY` steps).
    pub wall_s: f64,
    /// Every 100th step (and t = 0).
    pub history: Vec<DcbLongSample>,
    /// Largest |KE + SE + D − W| over the first and over the second half of the steps
    /// (after every step), with its time.
    pub max_total_first: (f64, f64),
    pub max_total_second: (f64, f64),
    /// Largest |total − total(middle step)| over the second half.
    pub max_change_second: f64,
    /// Largest |total − load term| over the run.
    pub max_residual: f64,
    /// Energies at the end.
    pub end: crate::simulation::Energies,
    /// Kinetic energy of the grid momenta after the last step, Σ|p_i|²/(2m_i) over every
    /// field: the part of the particles' kinetic energy the grid sees.
    pub grid_kinetic: f64,
    /// The crack tip every `DCB_LONG_K_EVERY` steps; the last is the cracks.csv row
    /// `cramp run` writes at the end.
    pub tips: Vec<crate::fracture::jintegral::TipResult>,
}

/// The DCB of Guo & Nairn 2004 §4.1 at cell size `h` with the damping `settle` (its end
/// time is replaced), run unchecked for `steps` steps, energies after every step.
///
/// The balance KE + SE + D − W is not zero but ≈ −½Δt Σ_p f_p·v_p: the kinetic energy is
/// read from the velocities at whole steps while the particles move with the updated
/// velocities, so for the load potential −f·x the scheme is symplectic Euler. For a mass
/// under a constant force (p' = p + Δt f, x' = x + Δt p'/m) the identity is exact:
/// ½(p'² − p²)/m − f·(x' − x) = −Δt² f²/(2m), which sums to −½Δt f·v(t). The term is
/// bounded by the load-point velocity and vanishes with it — no drift.
pub fn dcb_long(h: f64, steps: u64, settle: Settle) -> anyhow::Result<DcbLong> {
    let dt = beam(h, 1.0, -1.0, "none", 2, settle).load()?.time_step();
    let scene = beam(h, 1.0, -1.0, "none", 2, settle).set("solver.end_time", steps as f64 * dt).load()?;
    let requests = scene.fracture_requests();
    let mut sim = scene.build()?;
    sim.options.checked = false;
    anyhow::ensure!(sim.options.dt == dt, "time step {} vs {dt}", sim.options.dt);
    let load_term = |s: &crate::simulation::Simulation| {
        let p = &s.particles;
        -0.5 * dt * super::csum((0..p.len()).map(|i| p.force[i].dot(&p.v[i])))
    };
    let mut history = vec![DcbLongSample { t: 0.0, e: sim.energies(), load_term: 0.0 }];
    let (mut first, mut second, mut mid, mut change, mut residual) = ((0.0f64, 0.0), (0.0f64, 0.0), 0.0, 0.0f64, 0.0f64);
    let mut tips = Vec::new();
    let start = std::time::Instant::now();
    for k in 1..=steps {
        sim.step()?;
        let e = sim.energies();
        let (total, term) = (e.total(), load_term(&sim));
        let slot = if k <= steps / 2 { &mut first } else { &mut second };
        if total.abs() > slot.0 {
            *slot = (total.abs(), sim.time);
        }
        if k == steps / 2 {
            mid = total;
        } else if k > steps / 2 {
            change = change.max((total - mid).abs());
        }
        residual = residual.max((total - term).abs());
        if k % 100 == 0 {
            history.push(DcbLongSample { t: sim.time, e, load_term: term });
        }
        if k % DCB_LONG_K_EVERY == 0 || k == steps {
            tips.extend(sim.fracture_parameters(&requests)?);
        }
    }
    let wall_s = start.elapsed().as_secs_f64();
    let n = &sim.nodes;
    let grid_kinetic = crate::exact::sum_fast(n.present_fields().map(|(f, i)| 0.5 * n.fields[f].mom[i].norm_squared() / n.fields[f].mass[i]));
    anyhow::ensure!(tips.last().is_some_and(|t| t.time == sim.time), "no crack tip evaluated at the end");
    Ok(DcbLong {
        cell: h,
        dt,
        steps,
        wall_s,
        history,
        max_total_first: first,
        max_total_second: second,
        max_change_second: change,
        max_residual: residual,
        end: sim.energies(),
        grid_kinetic,
        tips,
    })
}

/// Case `dcb_long` (full suite only): the damped DCB over 10⁵ steps at 2 mm cells, twice:
/// with the paper's κ on the grid (energy balance; the arms never stop ringing, reported)
/// and with the same κ on the particle velocities too (energy balance and the static end
/// state).
pub fn run_dcb_long(variant: Variant) -> anyhow::Result<CaseOutput> {
    anyhow::ensure!(variant == Variant::Full, "dcb_long has no quick variant");
    let h = 2.0;
    let k_ref = k_dcb(1.0, a_of(h));
    let mut out = CaseOutput::default();
    let grid = dcb_long(h, DCB_LONG_STEPS, PAPER_DAMPING)?;
    let particles = dcb_long(h, DCB_LONG_STEPS, PARTICLE_DAMPING)?;
    // (K_I − K_beam)/K_beam range over the last window, and the last sample.
    let window = |r: &DcbLong| {
        let t_end = r.steps as f64 * r.dt;
        let ks: Vec<f64> = r.tips.iter().filter(|t| t.time >= t_end - (DCB_LONG_WINDOW as f64 - 0.5) * r.dt).map(|t| t.k1).collect();
        let range = ks.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &k| (a.min(k), b.max(k)));
        (range, ks.len())
    };
    for (r, label) in [(&grid, "κ on the grid"), (&particles, "κ on the particles")] {
        let w = r.end.external_work;
        let t_end = r.steps as f64 * r.dt;
        let (max_total, at) = if r.max_total_first.0 >= r.max_total_second.0 { r.max_total_first } else { r.max_total_second };
        out.measure("energy_balance", &format!("h = {h} mm, {label}, worst at t = {at:.2} ms"), max_total / w, 0.0);
        out.measure("balance_residual", &format!("h = {h} mm, {label}"), r.max_residual / w, 0.0);
        out.measure("bounded", &format!("h = {h} mm, {label}"), r.max_change_second / r.max_total_first.0, 0.0);
        out.measure("kinetic_residual", &format!("h = {h} mm, {label}, at the end"), r.end.kinetic / r.end.strain, 0.0);
        let last = r.tips.last().expect("dcb_long evaluates the tip at the end");
        let ((k_min, k_max), n) = window(r);
        out.note(format!(
            "{label}: {} steps of Δt = {:.4e} ms to t = {t_end:.2} ms, {:.1} s wall (unchecked, {} threads; energies every step, J every {DCB_LONG_K_EVERY} steps). \
             Energies at the end: KE {:.4e}, SE {:.6e}, D {:.6e}, W {:.6e} (SE/W = {:.5}). Balance: max |KE + SE + D − W| {:.3e} W at {:.2} ms in the first half, \
             {:.3e} at {:.2} ms in the second; without the load term −½Δt Σf·v at most {:.3e} W. K_I at the end {:.5} vs {k_ref:.5} ({:+.2} %); over the last \
             {DCB_LONG_WINDOW} steps ({n} samples) K_I/K_beam − 1 ranges {:+.2} … {:+.2} %. Particle KE/SE {:.3e}, grid KE/SE {:.3e}.",
            r.steps,
            r.dt,
            r.wall_s,
            rayon::current_num_threads(),
            r.end.kinetic,
            r.end.strain,
            r.end.damping,
            w,
            r.end.strain / w,
            r.max_total_first.0 / w,
            r.max_total_first.1,
            r.max_total_second.0,
            r.max_total_second.1,
            r.max_residual / w,
            last.k1,
            100.0 * (last.k1 / k_ref - 1.0),
            100.0 * (k_min / k_ref - 1.0),
            100.0 * (k_max / k_ref - 1.0),
            r.end.kinetic / r.end.strain,
            r.grid_kinetic / r.end.strain
        ));
    }
    // The static end state, on the run whose damping reaches it.
    let last = particles.tips.last().expect("dcb_long evaluates the tip at the end");
    out.measure("k_i", &format!("h = {h} mm, κ on the particles, 2×2 contour, t = {:.2} ms", last.time), last.k1, k_ref);
    let ((k_min, k_max), n) = window(&particles);
    out.measure("settled", &format!("h = {h} mm, κ on the particles, {n} samples over the last {DCB_LONG_WINDOW} steps"), (k_max - k_min) / k_ref, 0.0);
    let r = &grid;
    let w = r.end.external_work;
    let t_end = r.steps as f64 * r.dt;
    let series = |name: &str, f: fn(&DcbLongSample) -> f64| Series::line(name, r.history.iter().filter(|x| x.t > 0.0).map(|x| (x.t, f(x))).collect());
    out.figure(
        "dcb_long_energies.png",
        &format!(
            "Energies of the damped DCB (Guo & Nairn 2004 §4.1, {h} mm cells, κ = 1 ms⁻¹ on the grid) over 10⁵ steps, every 100th step, \
             logarithmic axis: W and SE settle near their static values (SE = W/2) and D takes the rest; KE falls to the part the grid \
             damping cannot reach (the FLIP null space) and stays there; the balance |KE + SE + D − W| falls with the motion of the loaded ends."
        ),
        PlotSpec::new("Damped DCB, 10⁵ steps: energies", "time t (ms)", "energy (N·mm)"),
        Plot::LogY(vec![
            series("external work W", |x| x.e.external_work),
            series("strain energy SE", |x| x.e.strain),
            series("damping D", |x| x.e.damping),
            series("kinetic energy KE", |x| x.e.kinetic),
            series("|KE + SE + D − W|", |x| x.e.total().abs()),
        ]),
    );
    out.figure(
        "dcb_long_balance.png",
        "The energy balance (KE + SE + D − W)/W of the damped DCB over the first 10 ms (every 100th step), and the first-order \
         load term −½Δt Σ_p f_p·v_p/W it follows (symplectic Euler for the load potential; see the case's notes). After 10 ms both stay at the 1e-5 level to the end.",
        PlotSpec::new("Damped DCB: energy balance and the load term", "time t (ms)", "energy / W"),
        Plot::Lines(vec![
            Series::line("(KE + SE + D − W)/W", r.history.iter().filter(|x| x.t <= 10.0).map(|x| (x.t, x.e.total() / w)).collect()),
            Series::reference("−½Δt Σ f·v / W", r.history.iter().filter(|x| x.t <= 10.0).map(|x| (x.t, x.load_term / w)).collect()),
        ]),
    );
    out.figure(
        "dcb_long_k.png",
        &format!(
            "K_I/K_beam − 1 of the damped DCB every {DCB_LONG_K_EVERY} steps from 10 ms on (2×2 contour; before, the transient swings by up to 8 %), \
             with the 2 % tolerance dashed: with the damping on the grid the arms keep ringing at about ±1 % in K to the end of the 10⁵ steps; \
             with the same κ on the particle velocities too the run settles."
        ),
        PlotSpec::new("Damped DCB, 10⁵ steps: K_I against corrected beam theory", "time t (ms)", "K_I / K_beam − 1"),
        Plot::Lines(vec![
            Series::line("MPM, κ on the grid", r.tips.iter().filter(|t| t.time >= 10.0).map(|t| (t.time, t.k1 / k_ref - 1.0)).collect()),
            Series::line("MPM, κ on the particles", particles.tips.iter().filter(|t| t.time >= 10.0).map(|t| (t.time, t.k1 / k_ref - 1.0)).collect()),
            Series::reference("+2 %", vec![(10.0, 0.02), (t_end, 0.02)]),
            Series::reference("−2 %", vec![(10.0, -0.02), (t_end, -0.02)]),
        ]),
    );
    Ok(out)
}
