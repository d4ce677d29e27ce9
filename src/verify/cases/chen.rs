//! Case `chen_late_time`: Chen's dynamic centre-cracked plate (Guo & Nairn 2004 §4.2;
//! references §2(c) with verification/references-errata.md) run far past the early-time
//! window of `chen_early_time`, against the static K_I of the same half-plate scene from
//! cramp's static Q4 FEA. The scene, Freund's early-time curve and the sampling are those
//! of [`super::fracture`] ([`chen_file`], [`run_chen_scene`], [`freund`]).
//!
//! What the late-time curve must do. With rollers on both lateral edges the uncracked
//! plate is a 1D bar: the two step waves meet on the crack plane at t₀ = H/c_d and the
//! crack-plane stress is a square wave 0 ↔ 2σ₀ of period T = 4H/c_d = 10.92 µs (H = 20 mm)
//! with mean σ₀. The crack responds quasi-statically on that time scale (a/c_R ≈ 0.7 µs),
//! so K_I(t) swings between about 0 and 2K_s and, the system being linear and undamped,
//! its mean over whole periods is the static K_s. The crack softens the plate's breathing
//! mode: with the FEA's crack compliance ΔU/U₀ (static strain energy against the
//! uncracked σ₀²V/2M) and the mode's crack-plane stress twice its mean square, the
//! Rayleigh estimate of the period is T√(1 + 2ΔU/U₀) ≈ 11.5 µs (a note, not a check).
//! So the runs go to [`END`] = 40 µs, about three periods; 14 µs would hold one.
//!
//! Crack contact. The scene of `chen_early_time` has frictionless contact; here the crack
//! has none, so the problem is the linear one the static FEA solves (its faces are
//! traction-free and may overlap) and K_I is signed by the crack opening (negative while
//! the faces overlap in the unloading half-period). Frictionless contact does not work for
//! this problem at these cells: its detection (relative nodal volume ≥ v_sep = 0.9 and the
//! faces approaching, Nairn 2003 eqs. 8–12) cannot see openings of 0.02–0.05 mm in
//! 0.25 mm cells (the nodal volume barely changes), so every closing motion of the faces
//! at a crack node is stopped as if they touched. A damped run (κ = 0.3 µs⁻¹ on the
//! particles) of the frictionless scene settles at K_I/σ₀√(πa) = 1.38 on the 2×2 contour
//! (1.20 on 8×8: path dependent) with the opening held flat at 0.0255 mm over the inner
//! half of the crack, against 1.029 (2×2) and an elliptic opening (0.0184 mm at x = 0;
//! FEA on the same grid 0.0183 mm) without contact. The full variant runs the
//! frictionless scene too and reports its late-time mean (notes and plot).

use super::fracture::{chen_file, freund, run_chen_scene, ChenSample, A, E, NU, SIGMA};
use crate::report::plot::{PlotSpec, Series};
use crate::verify::{CaseOutput, Plot, Variant};
use std::f64::consts::PI;

/// End of the MPM runs (µs): about three breathing periods after the waves arrive.
pub const END: f64 = 40.0;

/// Cell size of the FEA reference (mm) and the coarser mesh it is compared with.
pub const FEA_H: f64 = 0.05;

/// Hysteresis of the crossing detection, in units of K_s: a crossing of K_s counts once
/// K_I has gone on to (1 ± BAND) K_s. K_I swings by about ±K_s about the mean; the
/// ringing on its flanks (up to 0.6 K_s peak to peak) must not count.
pub const BAND: f64 = 0.5;

/// Plate half-height H and half-width b (mm).
const H: f64 = 20.0;
const B: f64 = 10.0;

/// The static FEA of the half plate at cell size `h`.
#[derive(Clone, Debug)]
pub struct FeaStatic {
    pub h: f64,
    /// K_I/σ₀√(πa) = √(E′J)/σ₀√(πa), J from the equivalent domain integral on the largest domain (8 cells).
    pub k_j: f64,
    /// The same from the interaction integral (for context).
    pub k_interaction: f64,
    /// Strain energy (per unit thickness).
    pub strain_energy: f64,
    /// |y reaction| at the one support the static problem needs (see [`fea_static`]) over the end load.
    pub reaction: f64,
    pub wall_s: f64,
}

/// The scene of [`chen_file`] solved statically by the Q4 FEA on its own grid at cell
/// size `h`. Two changes, neither of which changes the static solution: the crack's tip
/// is moved from a to a − h/2, because the FEA meshes a crack end at the first grid node
/// beyond it (the node the MPM leaves whole), so the meshed tip is exactly at a = 2.4 mm
/// (needs a/h whole; checked); and the ligament's end node (b, 0), on the plate's mirror
/// plane y = 0, gets v_y = 0: rollers alone leave a rigid y translation free, which the
/// self-equilibrated, y-symmetric load does not excite (the support's reaction is
/// round-off; returned).
pub fn fea_static(h: f64) -> anyhow::Result<FeaStatic> {
    let scene = chen_file(h, 1.0)
        .set("cracks.0.points.1", format!("[{}, 0.0]", A - 0.5 * h))
        .set("boundary.2", format!("{{ nodes = {{ region = {{ min = [{}, {}], max = [{}, {}] }} }}, vy = 0.0 }}", B - 0.25 * h, -0.25 * h, B + 0.25 * h, 0.25 * h))
        .load()?;
    let started = std::time::Instant::now();
    let r = crate::fea::run::run_fea(&scene, None)?;
    let wall_s = started.elapsed().as_secs_f64();
    let tip = r.summary.tips.first().ok_or_else(|| anyhow::anyhow!("FEA of Chen's plate: no crack tip"))?;
    anyhow::ensure!((tip.meshed_position[0] - A).abs() <= 1e-9 * A && tip.meshed_position[1].abs() <= 1e-9, "FEA crack tip meshed at {:?}, not ({A}, 0)", tip.meshed_position);
    let d = tip.domains.last().ok_or_else(|| anyhow::anyhow!("FEA of Chen's plate: no J domain"))?;
    anyhow::ensure!(d.cells == crate::fea::scene::MAX_J_CELLS, "FEA J: largest domain {} cells", d.cells);
    let k0 = SIGMA * (PI * A).sqrt();
    let reaction = r.analysis.solution.reaction.iter().map(|f| f.y.abs()).fold(0.0, f64::max) / (SIGMA * B);
    Ok(FeaStatic { h, k_j: (E / (1.0 - NU * NU) * d.j).sqrt() / k0, k_interaction: d.k_i / k0, strain_energy: r.summary.strain_energy, reaction, wall_s })
}

/// The exact K_I/σ√(πa) of an infinite row of collinear cracks 2a at spacing 2b under
/// remote tension (Westergaard 1939; Irwin 1957; Koiter 1959; Tada, Paris & Irwin,
/// *The Stress Analysis of Cracks Handbook*): √((2b/πa) tan(πa/2b)). Its lines x = ±b
/// midway between cracks are symmetry lines, u_x = 0 and σ_xy = 0 (rollers), once the
/// uniform σ_xx that makes ε_xx = 0 at infinity is added (a stress parallel to the cracks
/// has no K): it is the infinitely high version of the half plate on rollers.
pub fn periodic_cracks(alpha: f64) -> f64 {
    ((2.0 / (PI * alpha)) * (PI * alpha / 2.0).tan()).sqrt()
}

/// A crossing of the static value: its time and direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Crossing {
    pub t: f64,
    pub up: bool,
}

/// Crossings of the level `ks` by the samples (t, K) with hysteresis [`BAND`]: the state
/// turns high when K > (1 + BAND) ks and low when K < (1 − BAND) ks (it starts low), and
/// each turn is timed at the last crossing of ks before it (linear between samples).
pub fn crossings(s: &[(f64, f64)], ks: f64) -> Vec<Crossing> {
    let mut out = Vec::new();
    let mut high = false;
    let mut last = f64::NAN;
    for w in s.windows(2) {
        let ((t0, k0), (t1, k1)) = (w[0], w[1]);
        if (k0 - ks) * (k1 - ks) < 0.0 || (k1 == ks && k0 != ks) {
            last = t0 + (ks - k0) / (k1 - k0) * (t1 - t0);
        }
        if !high && k1 > (1.0 + BAND) * ks {
            high = true;
            out.push(Crossing { t: last, up: true });
        } else if high && k1 < (1.0 - BAND) * ks {
            high = false;
            out.push(Crossing { t: last, up: false });
        }
    }
    out
}

/// Mean of the piecewise-linear K(t) through the samples over [a, b] (trapezoidal rule;
/// the ends interpolated). NaN unless a < b lie within the samples.
pub fn mean_over(s: &[(f64, f64)], a: f64, b: f64) -> f64 {
    let inside = match (s.first(), s.last()) {
        (Some(first), Some(last)) => first.0 <= a && a < b && b <= last.0,
        _ => false,
    };
    if !inside {
        return f64::NAN;
    }
    let at = |(t0, k0): (f64, f64), (t1, k1): (f64, f64), t: f64| k0 + (k1 - k0) * (t - t0) / (t1 - t0);
    let terms = s.windows(2).filter_map(|w| {
        let (lo, hi) = (w[0].0.max(a), w[1].0.min(b));
        (hi > lo).then(|| 0.5 * (at(w[0], w[1], lo) + at(w[0], w[1], hi)) * (hi - lo))
    });
    super::csum(terms) / (b - a)
}

/// The late-time figures of one run, K normalised by σ₀√(πa).
#[derive(Clone, Debug)]
pub struct LateSummary {
    pub crossings: Vec<Crossing>,
    /// First and last up-crossing of K_s: whole periods.
    pub window: (f64, f64),
    pub periods: usize,
    /// Mean of K over the window (NaN with fewer than two up-crossings).
    pub mean: f64,
    /// Per period: start, length, mean.
    pub period_means: Vec<(f64, f64, f64)>,
    /// The first peak (time, K): the largest K before the first down-crossing.
    pub peak: (f64, f64),
    /// Crossings (either way) after the first peak.
    pub crossings_after_peak: usize,
}

/// The late-time analysis of a K(t) curve against the static value `ks`.
pub fn summarize_late(s: &[(f64, f64)], ks: f64) -> LateSummary {
    let crossings = crossings(s, ks);
    let ups: Vec<f64> = crossings.iter().filter(|c| c.up).map(|c| c.t).collect();
    let first_down = crossings.iter().find(|c| !c.up).map(|c| c.t).unwrap_or(f64::INFINITY);
    let peak = s.iter().filter(|x| x.0 < first_down).fold((f64::NAN, f64::NEG_INFINITY), |p, &x| if x.1 > p.1 { x } else { p });
    let window = match (ups.first(), ups.last()) {
        (Some(&a), Some(&b)) if ups.len() >= 2 => (a, b),
        _ => (f64::NAN, f64::NAN),
    };
    LateSummary {
        window,
        periods: ups.len().saturating_sub(1),
        mean: mean_over(s, window.0, window.1),
        period_means: ups.windows(2).map(|w| (w[0], w[1] - w[0], mean_over(s, w[0], w[1]))).collect(),
        peak,
        crossings_after_peak: crossings.iter().filter(|c| c.t > peak.0).count(),
        crossings,
    }
}

/// Constrained (plane-strain, ε_xx = 0) modulus M of the uncracked bar.
fn bar_modulus() -> f64 {
    E * (1.0 - NU) / ((1.0 + NU) * (1.0 - 2.0 * NU))
}

/// One MPM run of the case.
struct Run {
    h: f64,
    contact: &'static str,
    samples: Vec<ChenSample>,
    cd: f64,
    t0: f64,
    late: LateSummary,
    wall_s: f64,
}

/// The MPM run at cell size h with the crack's `contact` law ("none", "frictionless").
fn mpm(h: f64, contact: &'static str, ks: f64) -> anyhow::Result<Run> {
    let name = contact;
    let scene = chen_file(h, END).set("cracks.0.contact", format!("\"{contact}\"")).load()?;
    let started = std::time::Instant::now();
    let (samples, cd, t0) = run_chen_scene(&scene, END)?;
    let wall_s = started.elapsed().as_secs_f64();
    let curve: Vec<(f64, f64)> = samples.iter().map(|x| (x.t, x.k2_signed)).collect();
    let late = summarize_late(&curve, ks);
    Ok(Run { h, contact: name, samples, cd, t0, late, wall_s })
}

fn describe(r: &Run, ks: f64) -> String {
    let l = &r.late;
    let periods = l.period_means.iter().map(|(t, p, m)| format!("{p:.2} µs from {t:.2} µs: mean {m:.4} = {:.3} K_s", m / ks)).collect::<Vec<_>>().join("; ");
    let times = l.crossings.iter().map(|c| format!("{}{:.2}", if c.up { "↑" } else { "↓" }, c.t)).collect::<Vec<_>>().join(" ");
    format!(
        "h = {} mm, crack contact {}: first peak K_I/σ₀√(πa) = {:.4} at {:.2} µs; crossings of K_s (µs) {times}; mean over {} whole period(s) {:.2}–{:.2} µs = {:.4} = {:.3} K_s; periods: {periods}; {:.1} s wall",
        r.h, r.contact, l.peak.1, l.peak.0, l.periods, l.window.0, l.window.1, l.mean, l.mean / ks, r.wall_s
    )
}

/// Case `chen_late_time`: quick 0.25 mm, full 0.25 and 0.125 mm (plus the frictionless
/// scene at 0.25 mm, reported); FEA at 0.1 and 0.05 mm (full: and 0.025 mm).
pub fn run(variant: Variant) -> anyhow::Result<CaseOutput> {
    let (cells, fea_cells): (&[f64], &[f64]) = match variant {
        Variant::Quick => (&[0.25], &[2.0 * FEA_H, FEA_H]),
        Variant::Full => (&[0.25, 0.125], &[2.0 * FEA_H, FEA_H, 0.5 * FEA_H]),
    };
    let mut out = CaseOutput::default();

    // The reference: static FEA of the same scene.
    let fea = fea_cells.iter().map(|&h| fea_static(h)).collect::<anyhow::Result<Vec<_>>>()?;
    let ks = fea.iter().find(|f| f.h == FEA_H).map(|f| f.k_j).ok_or_else(|| anyhow::anyhow!("no FEA at {FEA_H} mm"))?;
    for w in fea.windows(2) {
        out.measure("fea_converged", &format!("FEA h = {} vs {} mm, √(E′J), 8-cell domain", w[0].h, w[1].h), w[0].k_j, w[1].k_j);
    }
    let (c, f) = (&fea[fea.len() - 2], &fea[fea.len() - 1]);
    let richardson = 2.0 * f.k_j - c.k_j;
    let exact = periodic_cracks(A / B);
    out.measure("fea_vs_periodic_cracks", &format!("FEA 2K(h = {}) − K(h = {} mm)", f.h, c.h), richardson, exact);
    for x in &fea {
        out.note(format!(
            "FEA h = {} mm: K_I/σ₀√(πa) = {:.5} from J (interaction integral {:.5}); strain energy {:.6e}; |reaction| at the v_y = 0 node / end load {:.1e}; {:.1} s",
            x.h, x.k_j, x.k_interaction, x.strain_energy, x.reaction, x.wall_s
        ));
    }
    let tada = super::plates::tada_cct(A / B);
    out.note(format!(
        "Static value K_s = {ks:.4} (FEA, {FEA_H} mm). First-order Richardson limit {richardson:.4}; exact infinite row of collinear cracks (the rollers are its symmetry lines) {exact:.4}. \
         For context, Tada's centre-cracked strip with free edges, F({:.2}) = {tada:.4}: the free edges let the ligament contract and bend, the rollers hold them straight, so the roller plate's K is {:.1} % lower; the finite height (H = {H} mm = {:.1}a; the crack's disturbance decays like e^(−π|y|/b) = {:.0e} at the ends) changes it by less than the FEA's discretisation",
        A / B,
        100.0 * (1.0 - exact / tada),
        H / A,
        (-PI * H / B).exp()
    ));

    // The MPM runs.
    let mut runs = Vec::new();
    for &h in cells {
        runs.push(mpm(h, "none", ks)?);
    }
    for r in &runs {
        let l = &r.late;
        out.measure("k_late_mean", &format!("h = {} mm, {} whole period(s), {:.2}–{:.2} µs", r.h, l.periods, l.window.0, l.window.1), l.mean, ks);
        out.measure("oscillates", &format!("h = {} mm, crossings of K_s after the first peak ({:.2} µs)", r.h, l.peak.0), l.crossings_after_peak as f64, f64::NAN);
        out.note(describe(r, ks));
    }
    let (cd, t0) = (runs[0].cd, runs[0].t0);
    let fine = fea.iter().find(|f| f.h == FEA_H).expect("the reference mesh");
    let u0 = SIGMA * SIGMA * B * (2.0 * H - 0.5 * fine.h) / (2.0 * bar_modulus());
    let du = fine.strain_energy / u0 - 1.0;
    out.note(format!(
        "Breathing period of the uncracked bar T = 4H/c_d = {:.3} µs; with the crack, T√(1 + 2ΔU/U₀) = {:.3} µs (ΔU/U₀ = {:.4} from the FEA strain energy, U₀ = σ₀²V/2M over the loaded length); measured above",
        4.0 * H / cd,
        4.0 * H / cd * (1.0 + 2.0 * du).sqrt(),
        du
    ));
    if variant == Variant::Full {
        let r = mpm(0.25, "frictionless", ks)?;
        out.note(format!("Frictionless contact (reported, not checked; see the module doc: the relative-volume detection stops the faces' closing): {}", describe(&r, ks)));
        runs.push(r);
    }

    // The whole curve.
    let mut series: Vec<Series> = runs
        .iter()
        .map(|r| {
            let what = if r.contact == "none" { "signed by the opening" } else { "frictionless contact" };
            Series::line(&format!("MPM, h = {} mm, 2×2 contour ({what})", r.h), r.samples.iter().map(|x| (x.t, x.k2_signed)).collect())
        })
        .collect();
    series.push(Series::reference(&format!("static FEA of the same scene, {ks:.4}"), vec![(0.0, ks), (END, ks)]));
    let t_far = t0 + 2.0 * A / cd;
    let early: Vec<(f64, f64)> = runs[0].samples.iter().map(|x| x.t).filter(|&t| t <= t_far).chain([t_far]).map(|t| (t, freund(2.0, cd, t, t0))).collect();
    series.push(Series::line(&format!("Freund, p = 2σ₀ (exact to {t_far:.3} µs)"), early));
    out.figure(
        "chen_late_time.png",
        &format!(
            "K_I(t)/σ₀√(πa) of Chen's plate (right half, rollers on both lateral edges) to {END} µs: MPM, two-term J on the 2×2 contour with the sign of the crack opening, no crack contact; the static FEA of the same scene ({FEA_H} mm mesh); Freund's exact early-time response with p = 2σ₀"
        ),
        PlotSpec::new("Chen's centre crack: K_I(t) to late times", "t (µs)", "K_I / σ₀√(πa)"),
        Plot::Lines(series),
    );
    let mut csv = String::from("h_mm,contact,t_us,k_signed_2x2,k_2x2,k_8x8\n");
    for r in &runs {
        for x in &r.samples {
            csv += &format!("{},{},{:e},{:e},{:e},{:e}\n", r.h, r.contact, x.t, x.k2_signed, x.k2, x.k8);
        }
    }
    out.data("chen_late_time.csv", "the K_I(t)/σ₀√(πa) samples of the plot (every 0.05 µs), per run", csv);
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crossings_ignore_ringing_inside_the_band_and_time_the_last_crossing() {
        // Rise through 1 with a ring back below it (but not below 0.5), then a fall.
        let s = [(0.0, 0.0), (1.0, 1.2), (2.0, 0.8), (3.0, 1.6), (4.0, 2.0), (5.0, 0.9), (6.0, 1.1), (7.0, 0.2)];
        let c = crossings(&s, 1.0);
        assert_eq!(c.len(), 2);
        assert!(c[0].up && (c[0].t - 2.25).abs() < 1e-12, "{c:?}");
        assert!(!c[1].up && (c[1].t - (6.0 + 0.1 / 0.9)).abs() < 1e-12, "{c:?}");
    }

    #[test]
    fn mean_over_whole_periods_of_a_shifted_cosine_is_its_offset() {
        // 1 − cos(2πt/10) from rest to t = 40: up-crossings of 1 at 2.5, 12.5, 22.5, 32.5; first peak 2 at 5.
        let s: Vec<(f64, f64)> = (0..=4000).map(|i| 0.01 * i as f64).map(|t| (t, 1.0 - (2.0 * PI * t / 10.0).cos())).collect();
        assert!((mean_over(&s, 3.0, 23.0) - 1.0).abs() < 1e-6);
        let l = summarize_late(&s, 1.0);
        assert_eq!(l.periods, 3);
        assert_eq!(l.crossings_after_peak, 7); // ↓7.5 ↑12.5 ↓17.5 ↑22.5 ↓27.5 ↑32.5 ↓37.5
        assert!((l.window.0 - 2.5).abs() < 1e-4 && (l.window.1 - 32.5).abs() < 1e-4, "{l:?}");
        assert!((l.mean - 1.0).abs() < 1e-6 && (l.peak.0 - 5.0).abs() < 1e-9, "{l:?}");
    }

    #[test]
    fn periodic_cracks_match_the_references_tangent_column() {
        // references §1(c): Irwin's tangent formula, 1.0248 at a/b = 0.24.
        assert!((periodic_cracks(0.24) - 1.0248).abs() < 5e-5);
    }
}
