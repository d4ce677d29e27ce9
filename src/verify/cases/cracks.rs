//! Crack cases with contact (Nairn 2003 §2.2 and §3.2).
//!
//! * `cracked_disks`: the colliding cracked disks of Nairn 2003 §3.2 (Fig. 3),
//!   `verification/cracked_disks.toml`; the references and why each tolerance is fair are
//!   in `tests/cracked_disks.rs` and the manifest.
//! * `crack_friction`: Coulomb friction on crack faces against the closed form of a block
//!   sliding on a fixed base under a ramped load (`tests/crack_friction.rs` has the closed
//!   form and the error budget).
//!
//! The tests call these functions; the tolerances live in `verification/cases.toml`.

use crate::check::CheckError;
use crate::crack::ContactLaw;
use crate::report::plot::{LegendPosition, PlotSpec, Series};
use crate::scene::Scene;
use crate::simulation::Simulation;
use crate::verify::scene_file::SceneFile;
use crate::verify::{CaseOutput, Plot, Variant};

// ---------------------------------------------------------------------------------------
// Colliding cracked disks
// ---------------------------------------------------------------------------------------


/// Crack half-length and disk diameter (mm).
const DISK_A: f64 = 5.0;
const DISK_D: f64 = 30.0;
/// Crack indices in the scene: horizontal in the left disk, vertical in the right one.
pub const HORIZONTAL: usize = 0;
pub const VERTICAL: usize = 1;
/// The snapshot times of the paper's Fig. 3 (ms) that the case draws.
const FRAMES: [f64; 2] = [20.0, 45.0];

/// The cracked disks at cell size `h` = 1/2ⁿ mm (1 mm: the file as is). For finer cells
/// the grid moves by (1 − h)/2 in x and y so that the crack tips and disk centres stay
/// inside cells and each crack between two particle rows/columns, and it stays mirror
/// symmetric about x = 0 (zero total momentum to the bit).
pub fn cracked_disks_scene(h: f64) -> anyhow::Result<Scene> {
    let file = SceneFile::new("cracked_disks.toml");
    let g = file.clone().load()?.grid;
    anyhow::ensure!(h > 0.0 && (1.0 / h).log2().fract() == 0.0, "h = {h} mm must be 1/2ⁿ");
    if h == g.cell[0] {
        return file.load();
    }
    let s = 0.5 * (1.0 - h);
    file.set("grid.cell", format!("[{h}, {h}]"))
        .set("grid.origin", format!("[{}, {}]", g.origin[0] - s, g.origin[1] - s))
        .set("grid.size", format!("[{}, {}]", g.size[0] + 2.0 * s, g.size[1] + 2.0 * s))
        .load()
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
fn j_min_near(s: &Simulation, c: usize, h: f64) -> f64 {
    let e = s.cracks[c].extent;
    let p = &s.particles;
    (0..p.len())
        .filter(|&i| {
            let x = p.x[i];
            x.x >= e.min.x - h && x.x <= e.max.x + h && x.y >= e.min.y - h && x.y <= e.max.y + h
        })
        .map(|i| (1.0 + p.strain[i].xx) * (1.0 + p.strain[i].yy))
        .fold(f64::INFINITY, f64::min)
}

/// x momentum of the left disk (body 0).
fn left_momentum(s: &Simulation) -> f64 {
    let p = &s.particles;
    crate::exact::sum_iter((0..p.len()).filter(|&i| p.body[i] == 0).map(|i| p.mass[i] * p.v[i].x))
}

/// A particle snapshot: (x, y, σyy) per particle and the crack surfaces (above and below
/// of each crack) as polylines.
#[derive(Clone, Debug)]
pub struct Snapshot {
    pub time: f64,
    pub particles: Vec<(f64, f64, f64)>,
    pub surfaces: Vec<Vec<(f64, f64)>>,
}

fn snapshot(s: &Simulation) -> Snapshot {
    let p = &s.particles;
    let pts = |v: &[crate::dim::Vector]| v.iter().map(|x| (x.x, x.y)).collect::<Vec<_>>();
    Snapshot {
        time: s.time,
        particles: (0..p.len()).map(|i| (p.x[i].x, p.x[i].y, p.stress[i].yy)).collect(),
        surfaces: s.cracks.iter().flat_map(|c| [pts(&c.above), pts(&c.below)]).collect(),
    }
}

/// What the cracked-disk run measured (see `tests/cracked_disks.rs` for each quantity).
#[derive(Clone, Debug)]
pub struct DiskRun {
    pub h: f64,
    pub steps: u64,
    /// The checked run's error, if it stopped.
    pub error: Option<String>,
    /// Largest |P(t) − P(0)| / Σ m|v|₁ over the steps.
    pub max_dp: f64,
    /// Largest |E(t) − E(0)| / E(0) (kinetic + strain; contact is inelastic: not checked).
    pub max_de: f64,
    /// Centre openings (horizontal, vertical) at 20, 32 and 45 ms.
    pub frames: Vec<(f64, f64, f64)>,
    /// Peak centre opening of the horizontal crack and its time.
    pub h_peak: (f64, f64),
    /// Smallest opening of the horizontal crack over the run (value, time, point).
    pub h_min: (f64, f64, usize),
    /// Largest |opening| of the vertical crack up to 20 ms (value, time, point).
    pub v_abs_to_20: (f64, f64, usize),
    /// Smallest opening of the vertical crack over the run (value, time, point).
    pub v_min: (f64, f64, usize),
    /// Smallest J next to each crack over the run.
    pub j_min: [f64; 2],
    /// Resolution of the volume criterion for the vertical crack, h·max(0, V_sep/J_min − 1).
    pub d_res: f64,
    /// Peak contact force −dP_left/dt (smoothed over ±0.5 ms), the quasi-static Griffith
    /// opening from it and measured peak / estimate.
    pub f_peak: f64,
    pub griffith: f64,
    pub griffith_ratio: f64,
    /// Negative control: the error of the 13 ms state continued without contact on the
    /// vertical crack, and its smallest opening by 20 ms (continued unchecked).
    pub negative_error: Option<CheckError>,
    pub negative_min_opening: f64,
    /// (t, horizontal centre opening, vertical centre opening) every step.
    pub openings: Vec<(f64, f64, f64)>,
    pub snapshots: Vec<Snapshot>,
    pub wall_s: f64,
}

/// Run the cracked disks at cell size `h` (checked) with every measurement of the case.
pub fn run_cracked_disks(h: f64) -> anyhow::Result<DiskRun> {
    let scene = cracked_disks_scene(h)?;
    let v_sep = scene.cracks[VERTICAL].v_sep;
    let e = scene.materials[0].e;
    let mut sim = scene.build()?;
    anyhow::ensure!(sim.options.checked, "the cracked-disk scene must run checked");
    let p0 = sim.total_momentum();
    anyhow::ensure!((p0.x, p0.y) == (0.0, 0.0), "mirror-image disks must have zero momentum, got {p0:?}");
    let started = std::time::Instant::now();
    let e0 = sim.energies().total();
    let dt = sim.options.dt;
    let mut r = DiskRun {
        h,
        steps: 0,
        error: None,
        max_dp: 0.0,
        max_de: 0.0,
        frames: Vec::new(),
        h_peak: (f64::NEG_INFINITY, 0.0),
        h_min: (f64::INFINITY, 0.0, 0),
        v_abs_to_20: (0.0, 0.0, 0),
        v_min: (f64::INFINITY, 0.0, 0),
        j_min: [f64::INFINITY; 2],
        d_res: f64::NAN,
        f_peak: 0.0,
        griffith: f64::NAN,
        griffith_ratio: f64::NAN,
        negative_error: None,
        negative_min_opening: f64::NAN,
        openings: vec![(0.0, centre_opening(&sim, HORIZONTAL), centre_opening(&sim, VERTICAL))],
        snapshots: Vec::new(),
        wall_s: 0.0,
    };
    let mut hist: Vec<(f64, f64)> = Vec::new(); // (t, P_left)
    let mut negative: Option<Simulation> = None;
    let result = sim.run_until(scene.solver.end_time, |s| {
        let p = &s.particles;
        let scale = crate::exact::sum_iter((0..p.len()).map(|i| p.mass[i] * p.v[i].abs().sum()));
        r.max_dp = r.max_dp.max((s.total_momentum() - p0).norm() / scale);
        r.max_de = r.max_de.max((s.energies().total() - e0).abs() / e0);
        hist.push((s.time, left_momentum(s)));
        for (c, j) in r.j_min.iter_mut().enumerate() {
            *j = j.min(j_min_near(s, c, h));
        }
        let ((vlo, vk), (vhi, vhk)) = opening_range(s, VERTICAL);
        if vlo < r.v_min.0 {
            r.v_min = (vlo, s.time, vk);
        }
        if s.time <= 20.0 + 0.5 * dt {
            let (a, k) = if vhi.abs() > vlo.abs() { (vhi.abs(), vhk) } else { (vlo.abs(), vk) };
            if a > r.v_abs_to_20.0 {
                r.v_abs_to_20 = (a, s.time, k);
            }
        }
        let ((hlo, hk), _) = opening_range(s, HORIZONTAL);
        if hlo < r.h_min.0 {
            r.h_min = (hlo, s.time, hk);
        }
        let hc = centre_opening(s, HORIZONTAL);
        let vc = centre_opening(s, VERTICAL);
        if hc > r.h_peak.0 {
            r.h_peak = (hc, s.time);
        }
        r.openings.push((s.time, hc, vc));
        for tf in [20.0, 32.0, 45.0] {
            if (s.time - tf).abs() <= 0.5 * dt {
                r.frames.push((tf, hc, vc));
            }
        }
        if FRAMES.iter().any(|&tf| (s.time - tf).abs() <= 0.5 * dt) {
            r.snapshots.push(snapshot(s));
        }
        // Just before the disks touch: keep a copy for the negative control.
        if negative.is_none() && s.time >= 13.0 {
            negative = Some(s.clone());
        }
    });
    r.steps = sim.step_count;
    r.wall_s = started.elapsed().as_secs_f64();
    if let Err(e) = result {
        r.error = Some(e.to_string());
        return Ok(r);
    }
    r.d_res = h * (v_sep / r.j_min[VERTICAL] - 1.0).max(0.0);
    // Quasi-static order of magnitude of the opening: Brazilian-disk stress at the centre
    // from the peak contact force, Griffith centre opening in plane stress.
    let w = (0.5 / dt).round() as usize;
    for i in w..hist.len().saturating_sub(w) {
        r.f_peak = r.f_peak.max((hist[i - w].1 - hist[i + w].1) / (hist[i + w].0 - hist[i - w].0));
    }
    let sigma = 2.0 * r.f_peak / (std::f64::consts::PI * DISK_D * scene.bodies[0].thickness);
    r.griffith = 4.0 * sigma * DISK_A / e;
    r.griffith_ratio = r.h_peak.0 / r.griffith;
    // Negative control: no contact on the vertical crack from 13 ms.
    let mut neg = negative.ok_or_else(|| anyhow::anyhow!("the run never reached 13 ms"))?;
    neg.cracks[VERTICAL].contact = ContactLaw::None;
    r.negative_error = neg.run_until(20.0, |_| {}).err();
    neg.options.checked = false;
    let mut neg_min = f64::INFINITY;
    neg.run_until(20.0, |s| neg_min = neg_min.min(opening_range(s, VERTICAL).0 .0))?;
    r.negative_min_opening = neg_min;
    Ok(r)
}

/// Case `cracked_disks`: 1 mm cells (the scene file) in both suites. At 0.5 mm
/// ([`cracked_disks_scene`]`(0.5)`) the checked run completes (it used to stop: its
/// horizontal crack opens by 3.6 cells, the crack particles in the gap had no centre-of-mass
/// velocity and stayed behind the material until the crack folded — a third field at step
/// 1168 with the volume detection, a particle crossing at step 839 with the opening
/// detection, which read the opening of another part of the crack; Task 7 now moves such a
/// crack particle with its two surfaces, `crate::crack`), and every check passes but
/// `resolution` (0.19 h > 0.1 h: the material next to the vertical crack is compressed to
/// J = 0.756) — see the manifest.
pub fn run_disks(_variant: Variant) -> anyhow::Result<CaseOutput> {
    let mut out = CaseOutput::default();
    let sizes: &[f64] = &[1.0];
    for &h in sizes {
        let r = run_cracked_disks(h)?;
        let label = format!("h = {h} mm");
        out.measure("completed", &label, if r.error.is_none() { 1.0 } else { 0.0 }, 1.0);
        if let Some(e) = &r.error {
            out.note(format!("h = {h} mm: the checked run stopped: {e}"));
            continue;
        }
        out.measure("momentum", &label, r.max_dp, 0.0);
        let f20 = r.frames.iter().find(|f| f.0 == 20.0).map(|f| f.1).unwrap_or(f64::NAN);
        out.measure("horizontal_opens", &label, f20 / h, f64::NAN);
        out.measure("vertical_closed", &label, r.v_abs_to_20.0 / h, f64::NAN);
        out.measure("resolution", &label, r.d_res / h, f64::NAN);
        let overlap = (-r.v_min.0).max(0.0);
        out.measure("no_interpenetration", &label, if overlap == 0.0 { 0.0 } else { overlap / r.d_res }, f64::NAN);
        out.measure("griffith_order", &label, r.griffith_ratio.log2().abs(), f64::NAN);
        out.note(format!(
            "h = {h} mm: vertical crack largest |opening| to 20 ms {:.4} mm at {:.2} ms (crack point {}); J_min next to it \
             {:.3} → δ_res = {:.4} mm; largest overlap over the run {overlap:.4} mm at {:.2} ms (point {}); horizontal crack \
             peak centre opening {:.3} mm at {:.2} ms against the Griffith estimate {:.3} mm from the peak contact force \
             {:.4} N: ratio {:.3}",
            r.v_abs_to_20.0,
            r.v_abs_to_20.1,
            r.v_abs_to_20.2,
            r.j_min[VERTICAL],
            r.d_res,
            r.v_min.1,
            r.v_min.2,
            r.h_peak.0,
            r.h_peak.1,
            r.griffith,
            r.f_peak,
            r.griffith_ratio
        ));
        let crossed = matches!(r.negative_error, Some(CheckError::CrackCrossing { crack: VERTICAL, .. }));
        out.measure("negative_control_stops", &label, if crossed { 1.0 } else { 0.0 }, 1.0);
        out.measure("negative_control_overlap", &label, r.negative_min_opening, f64::NAN);
        out.note(format!(
            "h = {h} mm: {} steps in {:.1} s (checked); Fig. 3 frames (t, horizontal, vertical centre opening, mm): {}; \
             smallest horizontal opening {:.3} mm at {:.2} ms (point {}: reclosing with the material next to it at \
             J = {:.3} < V_sep, and the tip points' surface-tracking drift; not checked); max |E − E0|/E0 {:.2e} (contact is \
             inelastic, not checked); negative control: {}",
            r.steps,
            r.wall_s,
            r.frames.iter().map(|f| format!("({}, {:.3}, {:.3})", f.0, f.1, f.2)).collect::<Vec<_>>().join(", "),
            r.h_min.0,
            r.h_min.1,
            r.h_min.2,
            r.j_min[HORIZONTAL],
            r.max_de,
            r.negative_error.as_ref().map(|e| e.to_string()).unwrap_or_else(|| "did not stop".into())
        ));
        let tag = crate::report::plot::format_sig(h, 3).replace('.', "p");
        out.figure(
            &format!("cracked_disks_openings_h{tag}.png"),
            &format!(
                "Centre opening of the two cracks (above − below surface, normal to the crack) against time, {h} mm cells: \
                 the disks meet at ≈ 14 ms; the diametral compression opens the horizontal crack of the left disk while \
                 contact holds the vertical crack of the right disk closed (Nairn 2003 §3.2, Fig. 3)."
            ),
            PlotSpec::new("Colliding cracked disks: crack openings", "time (ms)", "centre opening (mm)")
                .with_legend(LegendPosition::UpperLeft),
            Plot::Lines(vec![
                Series::line("horizontal crack (left disk)", r.openings.iter().map(|o| (o.0, o.1)).collect()),
                Series::line("vertical crack (right disk)", r.openings.iter().map(|o| (o.0, o.2)).collect()),
            ]),
        );
        let mut csv = String::from("t_ms,horizontal_centre_opening_mm,vertical_centre_opening_mm\n");
        for o in &r.openings {
            csv += &format!("{:e},{:e},{:e}\n", o.0, o.1, o.2);
        }
        out.data(&format!("cracked_disks_openings_h{tag}.csv"), &format!("the opening histories at h = {h} mm"), csv);
        for snap in &r.snapshots {
            out.figure(
                &format!("cracked_disks_h{tag}_t{:.0}.png", snap.time),
                &format!(
                    "The disks at t = {:.1} ms ({h} mm cells), particles coloured by σyy (MPa), both surfaces of each crack \
                     drawn in black (Nairn 2003 Fig. 3{}).",
                    snap.time,
                    if (snap.time - 20.0).abs() < 0.1 { "b: soon after contact the horizontal crack is open, the vertical one closed" } else { "" }
                ),
                PlotSpec::new(&format!("Colliding cracked disks at t = {:.1} ms", snap.time), "x (mm)", "y (mm)").with_size(1000, 500),
                Plot::Particles { particles: snap.particles.clone(), lines: snap.surfaces.clone(), value_label: "σyy (MPa)".into() },
            );
        }
    }
    Ok(out)
}

// ---------------------------------------------------------------------------------------
// Friction on crack faces
// ---------------------------------------------------------------------------------------

/// Normal load (N), ramp time and end time (ms) of the friction block.
pub const FRICTION_N: f64 = 0.01;
pub const FRICTION_RAMP: f64 = 10.0;
pub const FRICTION_END: f64 = 20.0;

/// A 20 × 4 mm block pressed onto a fixed 36 × 4 mm base across a horizontal crack on
/// y = 0 and pushed sideways: total `force` (x, y) on the block's particles, ramped over
/// `ramp`; the crack's `contact` law as TOML (e.g. `"none"` or
/// `{ friction = { mu = 0.3 } }`). E = 0.1 MPa, ν = 0.33, ρ = 1.5 g/cm³, plane stress,
/// cells of `h` mm, uGIMP, USAVG, checked (units mm, g, ms). The crack runs beyond both
/// blocks (x from −9.5 to 29.5); the base is held by its node rows y ≤ −3.
/// `verification/crack_friction.toml` with overrides.
pub fn block_on_crack(h: f64, force: [f64; 2], ramp: f64, end_time: f64, contact: &str) -> SceneFile {
    SceneFile::new("crack_friction.toml")
        .set("grid.cell", format!("[{h:?}, {h:?}]"))
        .set("solver.end_time", end_time)
        .set("loads.0.force", format!("[{}, {}]", force[0], force[1]))
        .set("loads.0.ramp", ramp)
        .set("cracks.0.contact", contact)
}

/// Closed-form velocity and displacement of the block for acceleration `a` under the ramp.
pub fn friction_closed_form(a: f64, t: f64) -> (f64, f64) {
    if t <= FRICTION_RAMP {
        (a * t * t / (2.0 * FRICTION_RAMP), a * t * t * t / (6.0 * FRICTION_RAMP))
    } else {
        (a * (t - FRICTION_RAMP / 2.0), a * (FRICTION_RAMP * FRICTION_RAMP / 6.0 + t * (t - FRICTION_RAMP) / 2.0))
    }
}

/// Mass, momentum and centre of mass of the top block (body 0).
fn top_block(s: &Simulation) -> (f64, f64, f64, f64) {
    let p = &s.particles;
    let top: Vec<usize> = (0..p.len()).filter(|&i| p.body[i] == 0).collect();
    let m = crate::exact::sum_iter(top.iter().map(|&i| p.mass[i]));
    let px = crate::exact::sum_iter(top.iter().map(|&i| p.mass[i] * p.v[i].x));
    let py = crate::exact::sum_iter(top.iter().map(|&i| p.mass[i] * p.v[i].y));
    let mx = crate::exact::sum_iter(top.iter().map(|&i| p.mass[i] * p.x[i].x));
    (m, px, py, mx / m)
}

/// One friction run.
#[derive(Clone, Debug)]
pub struct FrictionRun {
    pub mu: f64,
    pub f: f64,
    /// Top block mass and its closed-form acceleration (F − μN)/m.
    pub m: f64,
    pub a: f64,
    /// Worst |v̄ − v_exact| / v_exact over the steps with t ≥ T_r (sliding cases).
    pub worst_v: f64,
    /// Largest |P_y|/m of the top block.
    pub max_vy: f64,
    /// Largest |slip| at the crack particle under the block's middle.
    pub max_slip: f64,
    /// Largest |centre-of-mass displacement| of the top block.
    pub max_dx: f64,
    /// Final time, slip, centre-of-mass displacement and v̄.
    pub t: f64,
    pub slip: f64,
    pub dx: f64,
    pub v: f64,
    /// (t, v̄) every step.
    pub velocity: Vec<(f64, f64)>,
    pub steps: u64,
    pub wall_s: f64,
}

impl FrictionRun {
    /// A run of coefficient `mu` and force `f` on a block of mass `m` (closed-form
    /// acceleration `a`) before its first step.
    pub fn new(mu: f64, f: f64, m: f64, a: f64) -> FrictionRun {
        FrictionRun { mu, f, m, a, worst_v: 0.0, max_vy: 0.0, max_slip: 0.0, max_dx: 0.0, t: 0.0, slip: 0.0, dx: 0.0, v: 0.0, velocity: vec![(0.0, 0.0)], steps: 0, wall_s: 0.0 }
    }
}

/// The block on a crack with Coulomb coefficient `mu` and tangential force `f` (N), cells of `h` mm.
pub fn run_friction_block(h: f64, mu: f64, f: f64) -> anyhow::Result<FrictionRun> {
    let started = std::time::Instant::now();
    let mut sim = block_on_crack(h, [f, -FRICTION_N], FRICTION_RAMP, FRICTION_END, &format!("{{ friction = {{ mu = {mu} }} }}")).load()?.build()?;
    // The crack particle under the middle of the block (x = 9.5 at 1 mm cells).
    let mid = (0..sim.cracks[0].points.len())
        .min_by(|&i, &j| {
            let d = |k: usize| (sim.cracks[0].points[k].x - 9.5).abs();
            d(i).total_cmp(&d(j))
        })
        .ok_or_else(|| anyhow::anyhow!("the crack has no points"))?;
    anyhow::ensure!(sim.cracks[0].points[mid].x == 9.5, "no crack particle at x = 9.5");
    let (m, _, _, x0) = top_block(&sim);
    let a = (f - mu * FRICTION_N) / m;
    let mut r = FrictionRun::new(mu, f, m, a);
    sim.run_until(FRICTION_END, |s| {
        let (_, px, py, xc) = top_block(s);
        let slip = s.cracks[0].opening_nt(mid).1;
        r.max_vy = r.max_vy.max(py.abs() / m);
        r.max_slip = r.max_slip.max(slip.abs());
        r.max_dx = r.max_dx.max((xc - x0).abs());
        if s.time >= FRICTION_RAMP && a > 0.0 {
            let (v_exact, _) = friction_closed_form(a, s.time);
            r.worst_v = r.worst_v.max((px / m - v_exact).abs() / v_exact);
        }
        (r.t, r.slip, r.dx, r.v) = (s.time, slip, xc - x0, px / m);
        r.velocity.push((s.time, px / m));
    })
    .map_err(|e| anyhow::anyhow!("μ = {mu}, F = {f}: {e}"))?;
    r.steps = sim.step_count;
    r.wall_s = started.elapsed().as_secs_f64();
    Ok(r)
}

/// The three runs of the case: sliding (μ = 0.3, F = 2μN), frictionless (F = 0.6 N_load)
/// and sticking (μ = 0.3, F = μN/2).
pub fn friction_runs(h: f64) -> anyhow::Result<[FrictionRun; 3]> {
    let mu = 0.3;
    Ok([
        run_friction_block(h, mu, 2.0 * mu * FRICTION_N)?,
        run_friction_block(h, 0.0, 0.6 * FRICTION_N)?,
        run_friction_block(h, mu, 0.5 * mu * FRICTION_N)?,
    ])
}

/// Case `crack_friction`: 1 mm cells, and 0.5 mm in the full suite.
pub fn run_friction(variant: Variant) -> anyhow::Result<CaseOutput> {
    let hs: &[f64] = match variant {
        Variant::Quick => &[1.0],
        Variant::Full => &[1.0, 0.5],
    };
    let mut out = CaseOutput::default();
    for &h in hs {
        let [sliding, frictionless, stick] = friction_runs(h)?;
        for (name, r) in [("sliding, μ = 0.3, F = 2μN", &sliding), ("frictionless, F = 0.6 N", &frictionless)] {
            let l = format!("h = {h} mm, {name}");
            let (_, x_exact) = friction_closed_form(r.a, r.t);
            out.measure("velocity", &l, r.worst_v, 0.0);
            out.measure("displacement", &l, r.dx, x_exact);
            out.measure("slip", &l, r.slip, x_exact);
            out.note(format!(
                "{l}: {} steps, {:.2} s; v̄(t_end) = {:.6} mm/ms vs {:.6}; max |P_y|/m {:.2e} mm/ms",
                r.steps,
                r.wall_s,
                r.v,
                friction_closed_form(r.a, r.t).0,
                r.max_vy
            ));
        }
        let (_, x_free) = friction_closed_form(stick.f / stick.m, stick.t);
        let l = format!("h = {h} mm, stick, μ = 0.3, F = μN/2");
        out.measure("stick_slip", &l, stick.max_slip / x_free, 0.0);
        out.measure("stick_motion", &l, stick.max_dx / x_free, 0.0);
        out.note(format!(
            "{l}: max |slip| {:.3e} mm, max |x̄ − x̄0| {:.3e} mm, free-sliding distance {x_free:.4} mm; final v̄ {:+.2e} mm/ms",
            stick.max_slip, stick.max_dx, stick.v
        ));
        let exact = |a: f64, r: &FrictionRun| r.velocity.iter().map(|p| (p.0, friction_closed_form(a, p.0).0)).collect::<Vec<_>>();
        let tag = crate::report::plot::format_sig(h, 3).replace('.', "p");
        out.figure(
            &format!("crack_friction_h{tag}.png"),
            &format!(
                "Mean velocity of the block sliding on a crack face against the closed form ({h} mm cells): the load (F, −N) \
                 is ramped over 10 ms; sliding with μ = 0.3 at F = 2μN, frictionless, and sticking at F = μN/2 \
                 (closed forms dashed; the stuck block's exact velocity is 0)."
            ),
            PlotSpec::new("Crack-face friction: block velocity", "time (ms)", "mean velocity of the block (mm/ms)")
                .with_legend(LegendPosition::UpperLeft),
            Plot::Lines(vec![
                Series::line("MPM, frictionless", frictionless.velocity.clone()),
                Series::reference("F/m", exact(frictionless.a, &frictionless)),
                Series::line("MPM, μ = 0.3, F = 2μN", sliding.velocity.clone()),
                Series::reference("(F − μN)/m", exact(sliding.a, &sliding)),
                Series::line("MPM, μ = 0.3, F = μN/2 (sticks)", stick.velocity.clone()),
            ]),
        );
    }
    Ok(out)
}
