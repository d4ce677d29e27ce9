//! Case `growth_strip` (issue 20 item 2): a crack driven at a prescribed speed along the
//! mid-line of a long pre-strained strip between fixed grips, where the energy released
//! per unit of growth is known exactly.
//!
//! **Reference** (Freund, *Dynamic Fracture Mechanics* 1990, §4.3 and §6.4: steady crack
//! growth in a strip). A strip −H ≤ y ≤ H, its edges held by grips at u = (0, ±δ), a crack
//! along y = 0. Far ahead of the tip the strip is in uniaxial strain ε_yy = δ/H (plane
//! strain, ε_xx = 0: the grips hold u_x = 0), with strain-energy density
//! W0 = ½ M ε², M = λ + 2μ = E(1 − ν)/((1 + ν)(1 − 2ν)). Far behind it each half is
//! displaced rigidly by its grip: unstrained and at rest. In a steady state the fields
//! near the tip translate with it, so the energy inside a large rectangle that moves with
//! the tip (from far behind to far ahead, grip to grip) does not change. Energy enters it
//! only by convection through its front (the strip ahead, 2H·W0 per unit length, crossing
//! at speed v); none leaves through its back (no energy far behind), and the grips do no
//! work (they do not move). So the energy flux into the tip is G·v = 2H·W0·v:
//!
//!   G = 2H·W0 per unit thickness, for every speed 0 ≤ v < c_R,
//!
//! and the same for a long stationary crack (the static energy balance of extending it by
//! da: a column of the strained strip becomes two unloaded halves). Below c_R no mode of
//! the half strips (a layer clamped on one face, free on the other) has a phase speed
//! equal to v, so the continuum steady state leaves no waves behind.
//!
//! **What the MPM does with that energy.** The growth algorithm of Guo & Nairn (001
//! §2.3.2) adds a crack particle h/2 ahead of the tip at once; nothing takes up fracture
//! energy. The energy the far field gives up therefore stays in the body: the total
//! W_ext − U − T − D stays constant to the scheme's error, and the released 2H·W0 per unit
//! of growth is left behind as oscillations of the two halves, about half kinetic and half
//! strain energy (the virial theorem for small oscillations). The "energy released" from
//! the run's own global balance, G = (dW_ext − dU − dT − dD)/dA, is therefore zero by
//! construction, and −dU/dA alone is about ½·2H·W0: it cannot measure G in an MPM without
//! a fracture-energy sink. The strip measures it instead against 2H·W0.
//!
//! **What the two-term J does** (measured, the case's notes and figure): the stationary
//! control is within 2 %; a growing tip's J rises after each increment from ~0.3·2H·W0 to
//! about 2H·W0 before the next one (the freshly added segment is released at once, and the
//! new tip's field builds up over a few h/c_d, like a suddenly extended crack), so its
//! mean over steady growth falls with speed — 0.71, 0.54, 0.38 × 2H·W0 at 0.2, 0.4,
//! 0.6 c_R — independently of the cell size and of the contour. Case `growth_strip_j`
//! holds that mean to the reference and fails (issue 20).
//!
//! **Crack-face contact.** The scene's faces are frictionless with the opening detection
//! (the default), which never acts on the open flanks. With the volume detection every
//! approach of the oscillating flanks counts as contact, and with USAVG the energy grows
//! (2.1 × the released energy at 0.4 c_R; `growth_strip_j` holds it to the balance and
//! fails): the stress updates use momenta contacted at other points of the step than the
//! ones that move the particles (docs/verification.md, "The energy released by a growing
//! crack").

use crate::fracture::growth::GrowthRecord;
use crate::fracture::jintegral::TipEnd;
use crate::fracture::speed::rayleigh_speed_for;
use crate::material::{Constitutive, LinearElastic, PlaneState};
use crate::output::{HistoryRow, RunResult};
use crate::report::plot::{PlotSpec, Series};
use crate::verify::cases::growth::{records, run_growth_file};
use crate::verify::scene_file::SceneFile;
use crate::verify::{CaseOutput, Plot, Variant};

/// The strip's material (verification/growth_strip.toml).
pub const MATERIAL: LinearElastic = LinearElastic { e: 1000.0, nu: 0.3, rho: 1.0e-3, state: PlaneState::PlaneStrain };
/// Strain ε_yy = δ/H the grips impose.
pub const STRAIN: f64 = 1.0e-3;
/// CFL number of the scene: 0.2, 0.4 and 0.6 c_R are 12, 6 and 4 steps per increment.
pub const CFL: f64 = 0.42;
/// Growth increment as a fraction of the cell.
pub const INCREMENT: f64 = 0.5;
/// Start of the window of steady growth (ms): after the ramp (0.088 ms) and the start-up.
pub const WINDOW_FROM: f64 = 0.12;

/// Half-height of the strip at cell size `h`: y = 0 is a cell centre (the crack runs
/// mid-cell) and y = ±H grid lines: H = 8 + h/2.
pub fn half_height(h: f64) -> f64 {
    8.0 + 0.5 * h
}

/// 2H·W0, the energy released per unit of growth (and per unit thickness).
pub fn energy_release_rate(h: f64) -> f64 {
    let m = &MATERIAL;
    let modulus = m.e * (1.0 - m.nu) / ((1.0 + m.nu) * (1.0 - 2.0 * m.nu));
    2.0 * half_height(h) * 0.5 * modulus * STRAIN * STRAIN
}

/// How the crack faces meet.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Faces {
    /// Frictionless, detected by the tracked opening (the default of `[[cracks]]`).
    Opening,
    /// Frictionless, detected by the relative nodal volume (the negative control).
    Volume,
}

/// The strip at cell size `h`, length `length`, run to `end_time`, with the crack driven
/// at `speed` × c_R (None: the stationary control) and faces `faces`:
/// `verification/growth_strip.toml` with overrides.
pub fn strip(h: f64, length: f64, speed: Option<f64>, faces: Faces, end_time: f64) -> SceneFile {
    let hh = half_height(h);
    let (oy, x1) = (-hh - 2.0, length + 2.0);
    let c_d = MATERIAL.wave_speed();
    let mut f = SceneFile::new("growth_strip.toml")
        .set("grid.origin", format!("[-2.0, {oy}]"))
        .set("grid.size", format!("[{}, {}]", length + 4.0, 2.0 * hh + 4.0))
        .set("grid.cell", format!("[{h}, {h}]"))
        .set("solver.end_time", end_time)
        .set("bodies.0.shape.rectangle", format!("{{ min = [0.0, {}], max = [{length}, {hh}] }}", -hh))
        .set("boundary.0.nodes.region", format!("{{ min = [-2.0, {hh}], max = [{x1}, {}] }}", -oy))
        .set("boundary.0.uy", STRAIN * hh)
        .set("boundary.0.time.ramp", 12.0 * hh / c_d)
        .set("boundary.1.nodes.region", format!("{{ min = [-2.0, {oy}], max = [{x1}, {}] }}", -hh))
        .set("boundary.1.uy", -STRAIN * hh)
        .set("boundary.1.time.ramp", 12.0 * hh / c_d)
        .set("boundary.2.nodes.region", format!("{{ min = [{length}, {oy}], max = [{x1}, {}] }}", -oy))
        .set("cracks.0.points", format!("[[-1.0, 0.0], [{}, 0.0]]", 40.0 + 0.5 * h));
    if faces == Faces::Volume {
        f = f.set("cracks.0.detection", "\"volume\"");
    }
    match speed {
        Some(s) => f.set("cracks.0.fracture.growth.max_speed", max_speed(h, s)),
        None => f.set("cracks.0.fracture", "{ tips = \"end\", contour = 2, area_term = true }"),
    }
}

/// `max_speed` that lets an increment h/2 every n steps, n the whole number nearest to
/// (h/2)/(fraction·c_R·Δt), and refuses one every n − 1 steps.
pub fn max_speed(h: f64, fraction: f64) -> f64 {
    let c_r = rayleigh_speed_for(&MATERIAL).expect("valid wave speeds");
    let (da, dt) = (INCREMENT * h, CFL * h / MATERIAL.wave_speed());
    let n = (da / (fraction * c_r * dt)).round();
    1.001 * da / (n * dt)
}

/// What one growing run measured over the window of steady growth, each energy per
/// 2H·W0 and per unit of growth.
#[derive(Clone, Copy, Debug)]
pub struct Steady {
    /// Mean crack speed over the window, as a fraction of c_R.
    pub speed: f64,
    /// Mean two-term J over every check in the window.
    pub j_mean: f64,
    /// Mean J at the checks that added an increment (J just before it).
    pub j_before_increment: f64,
    /// Change of W_ext − U − T − D ("created" energy; −1 would be a sink of 2H·W0).
    pub balance: f64,
    /// −ΔU: the share of the released energy that left the strain energy.
    pub strain_released: f64,
    /// ΔT.
    pub kinetic_gained: f64,
    /// Increments in the window.
    pub increments: usize,
}

fn history_at(h: &[HistoryRow], t: f64) -> &HistoryRow {
    h.iter().min_by(|a, b| (a.time - t).abs().total_cmp(&(b.time - t).abs())).expect("a history")
}

/// [`Steady`] of run `r` at cell size `h` over [`WINDOW_FROM`, `to`]; the energies are per
/// the advance the prescribed speed `fraction`·c_R would give (a crack that stops
/// still counts the energy it should have released).
pub fn steady(r: &RunResult, h: f64, fraction: f64, to: f64) -> Steady {
    let g0 = energy_release_rate(h);
    let c_r = rayleigh_speed_for(&MATERIAL).expect("valid wave speeds");
    let recs: Vec<GrowthRecord> = records(r, TipEnd::End).into_iter().filter(|x| x.fracture.j1.is_finite() && (WINDOW_FROM..=to).contains(&x.fracture.time)).collect();
    let mean = |v: &[f64]| if v.is_empty() { f64::NAN } else { v.iter().sum::<f64>() / v.len() as f64 };
    let j_mean = mean(&recs.iter().map(|x| x.fracture.j1 / g0).collect::<Vec<_>>());
    let grew: Vec<&GrowthRecord> = recs.iter().filter(|x| x.grew).collect();
    let j_before_increment = mean(&grew.iter().map(|x| x.fracture.j1 / g0).collect::<Vec<_>>());
    let speed = match (grew.first(), grew.last()) {
        (Some(a), Some(b)) if b.fracture.time > a.fracture.time => (b.length - a.length) / (b.fracture.time - a.fracture.time) / c_r,
        _ => 0.0,
    };
    let (a, b) = (history_at(&r.history, WINDOW_FROM), history_at(&r.history, to));
    let released = g0 * fraction * c_r * (b.time - a.time);
    Steady {
        speed,
        j_mean,
        j_before_increment,
        balance: (b.total - a.total) / released,
        strain_released: (a.strain - b.strain) / released,
        kinetic_gained: (b.kinetic - a.kinetic) / released,
        increments: grew.len(),
    }
}

/// J/g0 of a growing tip averaged over bins of `width` ms, as (µs, mean): the every-step J
/// swings through each increment's cycle, its bin mean shows the trend.
pub fn binned(recs: &[GrowthRecord], g0: f64, width: f64) -> Vec<(f64, f64)> {
    let mut out: Vec<(f64, f64, usize)> = Vec::new();
    for x in recs.iter().filter(|x| x.fracture.j1.is_finite()) {
        let k = (x.fracture.time / width).floor();
        match out.last_mut() {
            Some(b) if b.0 == k => {
                b.1 += x.fracture.j1 / g0;
                b.2 += 1;
            }
            _ => out.push((k, x.fracture.j1 / g0, 1)),
        }
    }
    out.into_iter().map(|(k, s, n)| (1e3 * (k + 0.5) * width, s / n as f64)).collect()
}

/// One growing run: its [`Steady`] over the window, the note, and the binned J series.
fn growing(h: f64, length: f64, fraction: f64, faces: Faces, end: f64) -> anyhow::Result<(Steady, String, Series)> {
    growing_file(strip(h, length, Some(fraction), faces, end), h, fraction, end, label(h, fraction, faces))
}

/// The strip of [`strip`] (opening-detected contact) with each new segment released
/// gradually ([`crate::fracture::release`], default length and damping) and the J contour
/// at [`RELEASE_CONTOUR`] cells, which encloses most of the held faces.
pub fn strip_released(h: f64, length: f64, fraction: f64, end: f64) -> SceneFile {
    strip(h, length, Some(fraction), Faces::Opening, end).set("cracks.0.fracture.contour", RELEASE_CONTOUR).set("cracks.0.fracture.growth.release", "{}")
}

/// Half-width (cells) of the J contour of the released runs: the default release length
/// (4 cells) plus one.
pub const RELEASE_CONTOUR: usize = 5;

fn growing_released(h: f64, length: f64, fraction: f64, end: f64) -> anyhow::Result<(Steady, String, Series)> {
    growing_file(strip_released(h, length, fraction, end), h, fraction, end, format!("h = {h} mm, v = {fraction} c_R, released over 4 cells"))
}

fn growing_file(file: SceneFile, h: f64, fraction: f64, end: f64, label: String) -> anyhow::Result<(Steady, String, Series)> {
    let (r, wall) = run_growth_file(&file, false)?;
    let to = end - 0.005;
    let s = steady(&r, h, fraction, to);
    let note = format!(
        "{label}: speed {:.3} c_R over {} increments in {WINDOW_FROM}–{to} ms; J/(2H·W0): mean {:.3}, just before an increment {:.3}; per 2H·W0 and unit of the prescribed growth: Δ(W − U − T − D) {:+.4}, −ΔU {:.3}, ΔT {:.3}; {wall:.1} s wall (unchecked)",
        s.speed, s.increments, s.j_mean, s.j_before_increment, s.balance, s.strain_released, s.kinetic_gained
    );
    let series = Series::line(&label, binned(&records(&r, TipEnd::End), energy_release_rate(h), 0.005));
    Ok((s, note, series))
}

fn label(h: f64, fraction: f64, faces: Faces) -> String {
    format!("h = {h} mm, v = {fraction} c_R{}", if faces == Faces::Volume { ", volume-detected contact" } else { "" })
}

/// The strip's length and end time per variant: the window ends before the first wave
/// from the crack's start (at ~0.025 ms, x ≈ 40) is back from the far end at the c_d
/// front, 0.025 + 2(L − 40)/(c_d + v) ms.
fn strip_size(variant: Variant) -> (f64, f64) {
    match variant {
        Variant::Quick => (200.0, 0.235),
        Variant::Full => (300.0, 0.33),
    }
}

fn j_figure(out: &mut CaseOutput, file: &str, mut series: Vec<Series>, end: f64) {
    series.push(Series::reference("2H·W0", vec![(0.0, 1.0), (1e3 * end, 1.0)]));
    out.figure(
        file,
        "Pre-strained strip between fixed grips: two-term J/(2H·W0) at the crack tip versus time, stationary (every history row) and driven at prescribed speeds (mean over 5 µs bins of the every-step J, which rises after each increment and drops at the next)",
        PlotSpec::new("Strip with fixed grips: J / 2H·W0", "time (µs)", "J / (2H·W0)"),
        Plot::Lines(series),
    );
}

/// Case `growth_strip`: the stationary control, and the energy of growing runs (frictionless
/// faces, opening detection): quick h = 1 mm, L = 200 mm, v = 0.4 c_R; full L = 300 mm,
/// 0.2, 0.4, 0.6 c_R at h = 1 mm and 0.4 c_R at h = 0.5 mm.
pub fn run(variant: Variant) -> anyhow::Result<CaseOutput> {
    let (length, end) = strip_size(variant);
    let runs: &[(f64, f64)] = match variant {
        Variant::Quick => &[(1.0, 0.4)],
        Variant::Full => &[(1.0, 0.2), (1.0, 0.4), (1.0, 0.6), (0.5, 0.4)],
    };
    let mut out = CaseOutput::default();
    let mut series = Vec::new();

    // The stationary control: J after the ramp, averaged over the residual ringing.
    let (r, wall) = run_growth_file(&strip(1.0, length, None, Faces::Opening, 0.2), false)?;
    let g0 = energy_release_rate(1.0);
    let js: Vec<(f64, f64)> = r.tips.iter().filter(|x| x.time >= 0.1).map(|x| (1e3 * x.time, x.j1 / g0)).collect();
    let j_stat = js.iter().map(|p| p.1).sum::<f64>() / js.len() as f64;
    let (lo, hi) = js.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(l, u), p| (l.min(p.1), u.max(p.1)));
    out.measure("stationary_j", "h = 1 mm, 0.1–0.2 ms", j_stat, 1.0);
    out.note(format!("stationary crack, h = 1 mm: J/(2H·W0) = {j_stat:.4} (mean of {} rows after the ramp, range {lo:.3}–{hi:.3}: the ramp's residual ringing); {wall:.1} s wall", js.len()));
    series.push(Series::line("stationary, h = 1 mm", r.tips.iter().map(|x| (1e3 * x.time, x.j1 / g0)).collect()));

    for &(h, fraction) in runs {
        let (s, note, line) = growing(h, length, fraction, Faces::Opening, end)?;
        let label = label(h, fraction, Faces::Opening);
        out.measure("energy_balance", &label, s.balance.abs(), 0.0);
        out.measure("wake_strain_share", &label, s.strain_released, 0.5);
        out.note(note);
        series.push(line);
    }
    // One run with each new segment released gradually (growth_strip_j has all four).
    let (s, note, line) = growing_released(1.0, length, 0.4, end)?;
    out.measure("released_j", "h = 1 mm, v = 0.4 c_R", s.j_mean, 1.0);
    out.measure("released_j_is_g", "h = 1 mm, v = 0.4 c_R", s.j_mean, -s.balance);
    out.note(note);
    series.push(line);
    j_figure(&mut out, "growth_strip_j.png", series, end);
    Ok(out)
}

/// Case `growth_strip_j` (full suite only; FAILS today, issue 20): the mean two-term J of
/// the moving tip against 2H·W0 at 0.2, 0.4, 0.6 c_R (h = 1 mm) and 0.4 c_R (h = 0.5 mm);
/// the energy balance of the growing crack with frictionless contact at 0.4 c_R, h = 1 mm,
/// detected as by default (the tracked opening), and with the relative nodal volume as the
/// negative control, which must be seen to create energy.
pub fn run_j(variant: Variant) -> anyhow::Result<CaseOutput> {
    anyhow::ensure!(variant == Variant::Full, "growth_strip_j has no quick variant");
    let (length, end) = strip_size(variant);
    let mut out = CaseOutput::default();
    let mut series = Vec::new();
    for (h, fraction, faces) in [(1.0, 0.2, Faces::Opening), (1.0, 0.4, Faces::Opening), (1.0, 0.6, Faces::Opening), (0.5, 0.4, Faces::Opening), (1.0, 0.4, Faces::Volume)] {
        let (s, note, line) = growing(h, length, fraction, faces, end)?;
        let label = label(h, fraction, faces);
        match faces {
            Faces::Opening => {
                out.measure("growing_j", &label, s.j_mean, 1.0);
                if (h, fraction) == (1.0, 0.4) {
                    out.measure("contact_energy", &label, s.balance.abs(), 0.0);
                }
            }
            Faces::Volume => out.measure("contact_energy_volume", &label, s.balance, 0.0),
        }
        out.note(note);
        series.push(line);
    }
    // The same runs with each new segment released gradually (issue 20 item 2): J against
    // 2H·W0 and against the run's own energy balance, G = −Δ(W − U − T − D)/Δa.
    for (h, fraction) in [(1.0, 0.2), (1.0, 0.4), (1.0, 0.6), (0.5, 0.4)] {
        let (s, note, line) = growing_released(h, length, fraction, end)?;
        let label = format!("h = {h} mm, v = {fraction} c_R");
        out.measure("released_j", &label, s.j_mean, 1.0);
        out.measure("released_j_is_g", &label, s.j_mean, -s.balance);
        out.note(note);
        series.push(line);
    }
    j_figure(&mut out, "growth_strip_j_moving.png", series, end);
    Ok(out)
}
