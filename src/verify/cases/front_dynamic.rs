//! Dynamic K at straight 3D fronts (issue 16, verification item 5), case `front_k_dynamic`:
//! two stationary through-cracks whose fronts see a plane step wave, each in a slab made
//! exactly two-dimensional by its z-face supports, J₁ on the front circle with the volume
//! term (the two-term dynamic J, 004 eqs. 8, 12–13) at the mid-thickness front node.
//!
//! * **Mode I** (`verification/chen_cct_3d.toml`): Chen's plate of `chen_early_time`
//!   extruded two cells with rollers on the z faces (plane strain, 3d-references.md §4.1).
//!   Reference: Freund's semi-infinite crack under a suddenly applied crack-face pressure
//!   p = 2σ₀ (the two step waves superpose on the crack plane) until the far tip's wave
//!   arrives, t₀ + 2a/c_d ([`crate::verify::cases::fracture::freund`]); second reference:
//!   the 2D run of chen_cct.toml with its 2×2 rectangular contour and area term, the
//!   chen_early_time evaluation (the extrusion reproduces the 2D run, case `cracks_2d_3d`).
//! * **Mode III** (`verification/front_sh_3d.toml`): an edge crack in a plate whose z-face
//!   nodes are held in x and y and free in z, which the antiplane field satisfies exactly;
//!   antiplane shear τ applied suddenly on both ends sends two SH step waves that load the
//!   crack faces with p = 2τ at t₀. Reference (3d-references.md §6.1; Freund 1990 ch. 2):
//!   K_III(t) = 2p√(2c_s(t − t₀)/π) until the front's diffracted wave returns from the
//!   nearest edge, t − t₀ < 2 × 4.875 mm / c_s. K_III from J₁ = (1 + ν)K_III²/E (pure
//!   mode III; the COD split's K_I and K_II are reported as the mode-mixity check).
//!
//! Both are compared from seven cells of wave travel after arrival (t − t₀ ≥ 7h/c, the
//! start chen_early_time uses: the discrete step front is smeared over ~6 cells) to the end
//! of the exact window. Tolerances and why: `verification/cases.toml`, `front_k_dynamic`.

use crate::fracture::front3::FrontResult;
use crate::report::plot::{PlotSpec, Series};
use crate::verify::cases::fracture::{self, freund};
use crate::verify::scene_file::SceneFile;
use crate::verify::{CaseOutput, Plot, Variant};
use anyhow::Context;
use std::time::Instant;

/// Cell size of both slabs (mm) and their thickness (two cells).
pub const H: f64 = 0.25;
pub const B: f64 = 0.5;
/// Antiplane shear on the SH plate's ends (TPa: 100 MPa), its half-height and the
/// distance from the front to the nearest edge (mm).
pub const TAU: f64 = 1.0e-4;
pub const SH_HALF_HEIGHT: f64 = 5.0;
pub const SH_EDGE: f64 = 4.875;
/// Rise time of the ramped SH load (`front_sh_ramp_3d.toml`, µs): about 7.8 cells of
/// shear-wave travel at h = 0.25 mm, longer than the ≈ 0.5 µs period of the discrete step
/// front's ringing, so the grid carries the whole wave.
pub const SH_RAMP: f64 = 0.5;
/// Sampling interval (µs).
pub const DT_SAMPLE: f64 = 0.05;

/// One sample of a 3D run at the mid-thickness front node: time, J₁ (line + volume), J₁
/// (line alone), the COD split's (K_I, K_II, K_III), and the largest relative difference
/// of J₁ over the front nodes from the mid node's.
#[derive(Clone, Copy, Debug)]
pub struct FrontSample {
    pub t: f64,
    pub j1: f64,
    pub j1_line: f64,
    pub k: [f64; 3],
    pub along_front: f64,
}

/// Run a 3D scene to `end`, sampling the front every [`DT_SAMPLE`]; with the run's
/// particle count, steps and seconds.
pub fn sample_front(file: &SceneFile, end: f64) -> anyhow::Result<(Vec<FrontSample>, usize, u64, f64)> {
    let s = file.load3()?;
    let t = Instant::now();
    let mut sim = s.build()?;
    let req = s.front_requests(&sim.cracks)?.remove(0).context("the scene asks for J at its front")?;
    let mut out = Vec::new();
    let mut next = DT_SAMPLE;
    while sim.time + 0.5 * sim.options.dt < end {
        sim.run_until(next.min(end), |_| {})?;
        next += DT_SAMPLE;
        let front = sim.front_fracture(0, &req);
        let mid = mid_node(&front);
        let f = &front[mid];
        let along = front.iter().map(|g| (g.j1 / f.j1 - 1.0).abs()).fold(0.0, f64::max);
        out.push(FrontSample { t: sim.time, j1: f.j1, j1_line: f.j1_line, k: f.k, along_front: along });
    }
    Ok((out, sim.particles.len(), sim.step_count, t.elapsed().as_secs_f64()))
}

/// The front node nearest mid-thickness.
fn mid_node(front: &[FrontResult]) -> usize {
    (0..front.len()).min_by(|&i, &k| (front[i].x.z - 0.5 * B).abs().total_cmp(&(front[k].x.z - 0.5 * B).abs())).expect("front nodes")
}

/// The closed-form K_III(t) = 2p√(2c_s(t − t₀)/π), p = 2τ (TPa√mm; 0 before t₀).
pub fn k3_sh(cs: f64, t: f64, t0: f64) -> f64 {
    if t <= t0 {
        return 0.0;
    }
    2.0 * (2.0 * TAU) * (2.0 * cs * (t - t0) / std::f64::consts::PI).sqrt()
}

/// K_III(t) for the ramped load p(t) = 2τ min((t − t₀)/T, 1): the step response
/// [`k3_sh`] superposed over the ramp (Duhamel), K(t) = 2p√(2c_s/π) (2/3T)
/// [(t − t₀)^{3/2} − (t − t₀ − T)_+^{3/2}] (TPa√mm; 0 before t₀).
pub fn k3_sh_ramp(cs: f64, t: f64, t0: f64, rise: f64) -> f64 {
    if t <= t0 {
        return 0.0;
    }
    let s = t - t0;
    let late = (s - rise).max(0.0);
    2.0 * (2.0 * TAU) * (2.0 * cs / std::f64::consts::PI).sqrt() * 2.0 / (3.0 * rise) * (s.powf(1.5) - late.powf(1.5))
}

/// Case `front_k_dynamic` (full suite only).
pub fn run(_variant: Variant) -> anyhow::Result<CaseOutput> {
    let mut out = CaseOutput::default();
    let (e, nu, rho) = (fracture::E, fracture::NU, fracture::RHO);
    let mu = e / (2.0 * (1.0 + nu));
    let cs = (mu / rho).sqrt();
    let cd = (e * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu)) / rho).sqrt();
    let label = format!("h = {H} mm");

    // Mode I: Chen's plate extruded, against Freund and the 2D run.
    let t0 = 20.0 / cd;
    let t_end = t0 + 2.0 * fracture::A / cd;
    let (s3, n3, steps3, sec3) = sample_front(&SceneFile::new("chen_cct_3d.toml"), 3.45)?;
    let (s2, _, _) = fracture::run_chen(H, 3.45)?;
    let k0 = fracture::SIGMA * (std::f64::consts::PI * fracture::A).sqrt();
    let ep = e / (1.0 - nu * nu);
    let k_of = |j: f64| (ep * j.max(0.0)).sqrt() / k0;
    let (mut k_err, mut k_err_t, mut vs_2d, mut vs_2d_t, mut along) = (0.0f64, 0.0, 0.0f64, 0.0, 0.0f64);
    let mut rows = Vec::new();
    for (a, b) in s3.iter().zip(&s2) {
        anyhow::ensure!((a.t - b.t).abs() < 1e-9, "3D and 2D samples at different times ({} vs {} µs)", a.t, b.t);
        let k3 = k_of(a.j1);
        if a.t >= t0 + 7.0 * H / cd && a.t <= t_end {
            let err = (k3 - freund(2.0, cd, a.t, t0)).abs();
            if err > k_err {
                (k_err, k_err_t) = (err, a.t);
            }
            let d = (k3 / b.k2 - 1.0).abs();
            if d > vs_2d {
                (vs_2d, vs_2d_t) = (d, a.t);
            }
            along = along.max(a.along_front);
        }
        rows.push((a.t, k3, k_of(a.j1_line), b.k2, freund(2.0, cd, a.t, t0)));
    }
    out.measure("mode_i_freund", &format!("{label}, worst at {k_err_t:.3} µs"), k_err, 0.0);
    out.measure("mode_i_vs_2d", &format!("{label}, worst at {vs_2d_t:.3} µs"), vs_2d, 0.0);
    out.note(format!(
        "Mode I (Chen's plate extruded, {n3} particles × {steps3} steps, {sec3:.1} s): c_d = {cd:.4} mm/µs, t₀ = {t0:.4} µs, window \
         {:.3}–{t_end:.3} µs. Largest |K_I/σ₀√(πa) − Freund(p = 2σ₀)| = {k_err:.4} at {k_err_t:.3} µs; largest |K_I,3D/K_I,2D(2×2) − 1| \
         = {:.2} % at {vs_2d_t:.3} µs; J₁ along the front within {along:.1e} of the mid node. Samples (t, K 3D two-term, K 3D line only, \
         K 2D 2×2, Freund): {}.",
        t0 + 7.0 * H / cd,
        100.0 * vs_2d,
        rows.iter().filter(|r| r.0 >= t0 - 0.3).map(|r| format!("({:.2}, {:.3}, {:.3}, {:.3}, {:.3})", r.0, r.1, r.2, r.3, r.4)).collect::<Vec<_>>().join(", ")
    ));
    out.figure(
        "front_k_dynamic_mode_i.png",
        "Chen's plate extruded two cells with rollers on its z faces (plane strain), h = 0.25 mm: K_I(t)/σ₀√(πa) at the mid-thickness \
         front node from the 3D circle's J₁ (r = 2 cells) with and without the volume term, the 2D run's 2×2 rectangle with area term, \
         and Freund's exact response to p = 2σ₀ (valid to t₀ + 2a/c_d).",
        PlotSpec::new("3D front under a step wave: K_I(t)", "t (µs)", "K_I / σ₀√(πa)"),
        Plot::Lines(vec![
            Series::line("3D front, line + volume", rows.iter().map(|r| (r.0, r.1)).collect()),
            Series::line("3D front, line only", rows.iter().map(|r| (r.0, r.2)).collect()),
            Series::line("2D, 2×2 contour + area", rows.iter().map(|r| (r.0, r.3)).collect()),
            Series::line("Freund, p = 2σ₀ (exact)", rows.iter().filter(|r| r.0 <= t_end).map(|r| (r.0, r.4)).collect()),
        ]),
    );

    // Mode III: the SH step wave.
    let t0 = SH_HALF_HEIGHT / cs;
    let t_end = t0 + 2.0 * SH_EDGE / cs;
    let (s, n, steps, sec) = sample_front(&SceneFile::new("front_sh_3d.toml"), 3.7)?;
    let k3_of = |j: f64| (e * j.max(0.0) / (1.0 + nu)).sqrt();
    let (mut worst, mut worst_t, mut mix, mut line_dev, mut along) = (0.0f64, 0.0, 0.0f64, 0.0f64, 0.0f64);
    for x in &s {
        if x.t >= t0 + 7.0 * H / cs && x.t <= t_end {
            let kr = k3_sh(cs, x.t, t0);
            let d = (k3_of(x.j1) / kr - 1.0).abs();
            if d > worst {
                (worst, worst_t) = (d, x.t);
            }
            mix = mix.max(x.k[0].abs().max(x.k[1].abs()) / x.k[2].abs());
            line_dev = line_dev.max((k3_of(x.j1_line) / k3_of(x.j1) - 1.0).abs());
            along = along.max(x.along_front);
        }
    }
    out.measure("mode_iii_sh", &format!("{label}, worst at {worst_t:.3} µs"), worst, 0.0);
    // The same plate with the shear ramped over SH_RAMP: the window starts when the ramp
    // has fully arrived at the crack plane.
    let (r, nr, stepsr, secr) = sample_front(&SceneFile::new("front_sh_ramp_3d.toml"), 3.7)?;
    let (mut worst_r, mut worst_rt) = (0.0f64, 0.0);
    for x in &r {
        if x.t >= t0 + SH_RAMP && x.t <= t_end {
            let d = (k3_of(x.j1) / k3_sh_ramp(cs, x.t, t0, SH_RAMP) - 1.0).abs();
            if d > worst_r {
                (worst_r, worst_rt) = (d, x.t);
            }
        }
    }
    out.measure("mode_iii_sh_ramp", &format!("{label}, T = {SH_RAMP} µs, worst at {worst_rt:.3} µs"), worst_r, 0.0);
    out.measure("mode_iii_mixity", &label, mix, 0.0);
    out.measure("mode_iii_line_control", &label, line_dev, f64::NAN);
    out.note(format!(
        "Mode III (SH step wave, {n} particles × {steps} steps, {sec:.1} s): c_s = {cs:.4} mm/µs, t₀ = {t0:.4} µs, window {:.3}–{t_end:.3} µs. \
         Largest |K_III/2p√(2c_s(t − t₀)/π) − 1| = {:.2} % at {worst_t:.3} µs (K_III from J₁ = (1 + ν)K_III²/E); largest \
         max(|K_I|, |K_II|)/|K_III| of the COD split {mix:.2e}; the line term alone is up to {:.1} % off the two-term K; J₁ along the \
         front within {along:.1e} of the mid node. Samples (t, K_III two-term, K_III line only, COD split K_III, exact) in TPa√mm: {}.",
        t0 + 7.0 * H / cs,
        100.0 * worst,
        100.0 * line_dev,
        s.iter().filter(|x| x.t >= t0 - 0.3).map(|x| format!("({:.2}, {:.4e}, {:.4e}, {:.4e}, {:.4e})", x.t, k3_of(x.j1), k3_of(x.j1_line), x.k[2], k3_sh(cs, x.t, t0))).collect::<Vec<_>>().join(", ")
    ));
    out.note(format!(
        "Mode III, ramped (front_sh_ramp_3d.toml, rise T = {SH_RAMP} µs, {nr} particles × {stepsr} steps, {secr:.1} s): window {:.3}–{t_end:.3} µs; \
         largest |K_III/K_ramp − 1| = {:.2} % at {worst_rt:.3} µs. Samples (t, K_III two-term, exact ramp response) in TPa√mm: {}.",
        t0 + SH_RAMP,
        100.0 * worst_r,
        r.iter().filter(|x| x.t >= t0 - 0.3).map(|x| format!("({:.2}, {:.4e}, {:.4e})", x.t, k3_of(x.j1), k3_sh_ramp(cs, x.t, t0, SH_RAMP))).collect::<Vec<_>>().join(", ")
    ));
    out.figure(
        "front_k_dynamic_mode_iii.png",
        "Edge crack under an SH step wave (z faces held in x and y: exactly antiplane), h = 0.25 mm: K_III(t) at the mid-thickness front \
         node from the circle's J₁ (r = 2 cells) with and without the volume term, and from the COD split, against the exact \
         2p√(2c_s(t − t₀)/π), p = 2τ (valid until the front's diffracted wave returns from the nearest edge).",
        PlotSpec::new("3D front under an SH step wave: K_III(t)", "t (µs)", "K_III (TPa√mm)"),
        Plot::Lines(vec![
            Series::line("3D front, line + volume", s.iter().map(|x| (x.t, k3_of(x.j1))).collect()),
            Series::line("3D front, line only", s.iter().map(|x| (x.t, k3_of(x.j1_line))).collect()),
            Series::line("COD split K_III", s.iter().map(|x| (x.t, x.k[2])).collect()),
            Series::line("exact (Freund)", s.iter().filter(|x| x.t <= t_end).map(|x| (x.t, k3_sh(cs, x.t, t0))).collect()),
            Series::line("ramped load, line + volume", r.iter().map(|x| (x.t, k3_of(x.j1))).collect()),
            Series::line("ramped load, exact", r.iter().filter(|x| x.t <= t_end).map(|x| (x.t, k3_sh_ramp(cs, x.t, t0, SH_RAMP))).collect()),
        ]),
    );
    Ok(out)
}
