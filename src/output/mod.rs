//! Outputs of a run: `history.csv` (energies at the history interval), `summary.json`
//! (scene echo, step count, time step, wall time, throughput, final energies) and VTK
//! particle snapshots at the archive interval. Physics stays out of here: this module
//! only reads a [`Simulation`].

pub mod three_d;
pub mod vtk;

use crate::dim::Vector;
use crate::fracture::growth::GrowthRecord;
use crate::fracture::jintegral::TipResult;
use crate::scene::Scene;
use crate::simulation::{Energies, Simulation};
use anyhow::{bail, Context};
use serde::{Deserialize, Serialize};
use std::io::Write;
use std::ops::ControlFlow;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Instant;

/// One row of history.csv.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct HistoryRow {
    pub time: f64,
    pub kinetic: f64,
    pub strain: f64,
    pub external_work: f64,
    pub damping: f64,
    /// kinetic + strain + damping − external_work − boundary_work.
    pub total: f64,
    /// Total particle momentum.
    pub momentum_x: f64,
    pub momentum_y: f64,
    /// Work of the velocity boundary conditions that move their nodes (reaction · v_c Δt).
    #[serde(default)]
    pub boundary_work: f64,
}

impl HistoryRow {
    pub fn of(sim: &Simulation) -> Self {
        let e: Energies = sim.energies();
        let p = sim.total_momentum();
        HistoryRow {
            time: sim.time,
            kinetic: e.kinetic,
            strain: e.strain,
            external_work: e.external_work,
            damping: e.damping,
            total: e.total(),
            momentum_x: p.x,
            momentum_y: p.y,

            boundary_work: e.boundary_work,
        }
    }

    pub const HEADER: &'static str = "time,kinetic,strain,external_work,damping,total,momentum_x,momentum_y,boundary_work";

    pub fn csv(&self) -> String {
        // `{:e}` of f64 round-trips exactly.
        format!(
            "{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e}",
            self.time, self.kinetic, self.strain, self.external_work, self.damping, self.total, self.momentum_x, self.momentum_y, self.boundary_work
        )
    }
}

/// How a run ended (`status` in summary.json).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum RunStatus {
    /// Reached the end time.
    #[default]
    Completed,
    /// Stopped by an error (`error` in the summary): a failed check, a crack-tip
    /// evaluation or an output that could not be written.
    Failed,
    /// Stopped at the end of a step on request (SIGINT or SIGTERM to `cramp run`).
    Interrupted,
}

/// summary.json, written at the end of every run, completed or not.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Summary {
    /// How the run ended; `steps` and `end_time` are the last step completed and its time.
    #[serde(default)]
    pub status: RunStatus,
    /// The error that stopped a failed run.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
    /// What the run changed in the scene's request, e.g. an output interval below the
    /// time step rounded up to one step (also printed by `cramp run`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
    pub scene: Scene,
    pub steps: u64,
    pub dt: f64,
    pub end_time: f64,
    pub particles: usize,
    pub nodes: usize,
    pub wall_time_s: f64,
    /// Particles × steps / wall time of the time loop (outputs included).
    pub particle_steps_per_second: f64,
    /// Worker threads of the run (results do not depend on it).
    #[serde(default)]
    pub threads: usize,
    pub checked: bool,
    /// The last row of history.csv.
    pub final_energies: HistoryRow,
    /// Growing cracks at the end of the run: length, tip states, split time.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub growth: Vec<CrackGrowthSummary>,
}

/// How to run a scene.
#[derive(Clone, Debug, Default)]
pub struct RunOptions {
    /// Write outputs here (None: in memory only). A directory that already holds cramp's
    /// files is refused unless `force` is set ([`prepare_out_dir`]).
    pub out_dir: Option<PathBuf>,
    /// Show a progress bar (only drawn on a terminal).
    pub progress: bool,
    /// Override the scene's `solver.checked`.
    pub checked: Option<bool>,
    /// Delete cramp's own files from an existing `out_dir` first instead of refusing it.
    pub force: bool,
    /// When this flag becomes true (a SIGINT/SIGTERM handler sets it), the run stops at
    /// the end of the current step, writes its outputs and reports
    /// [`RunStatus::Interrupted`].
    pub stop: Option<Arc<AtomicBool>>,
}

/// What a run returns in memory.
#[derive(Clone, Debug)]
pub struct RunResult {
    pub history: Vec<HistoryRow>,
    /// J and K at every requested crack tip at each history time (cracks.csv).
    pub tips: Vec<TipResult>,
    pub summary: Summary,
    pub sim: Simulation,
}

/// Build and run a scene to its end time, recording history and writing outputs.
pub fn run_scene(scene: &Scene, opts: &RunOptions) -> anyhow::Result<RunResult> {
    let mut sim = scene.build()?;
    if let Some(c) = opts.checked {
        sim.options.checked = c;
    }
    run_simulation(scene, sim, opts)
}

/// The names of the files `cramp run` and `cramp fea` write into an output directory
/// (and the temporary files of an atomic write, `.NAME.tmp`).
pub fn is_cramp_output(name: &str) -> bool {
    let name = name.strip_prefix('.').and_then(|n| n.strip_suffix(".tmp")).unwrap_or(name);
    let numbered = |prefix: &str, ext: &str| name.strip_prefix(prefix).and_then(|r| r.strip_suffix(ext)).is_some_and(|k| !k.is_empty() && k.bytes().all(|b| b.is_ascii_digit()));
    matches!(
        name,
        "history.csv" | "summary.json" | "cracks.csv" | "growth.csv" | "crack_paths.csv" | "particles.pvd" | "fea.vtk" | "fea_gauss.vtk" | "fea_nodes.csv" | "fea_summary.json"
    ) || numbered("particles_", ".vtk")
        || numbered("cracks_", ".vtk")
        || numbered("front_", ".vtk")
        || (name.starts_with("probe_") && name.ends_with(".csv"))
}

/// Make `dir` ready for a run's outputs: create it if needed; if it already holds files
/// of an earlier cramp run (see [`is_cramp_output`]), refuse — so a run never leaves
/// another run's files beside its own — unless `force`, which deletes those files (and
/// only those) first.
pub fn prepare_out_dir(dir: &Path, force: bool) -> anyhow::Result<()> {
    if !dir.exists() {
        return std::fs::create_dir_all(dir).with_context(|| format!("cannot create output directory {}", dir.display()));
    }
    if !dir.is_dir() {
        bail!("output directory {} exists and is not a directory", dir.display());
    }
    let mut ours = Vec::new();
    for entry in std::fs::read_dir(dir).with_context(|| format!("cannot list output directory {}", dir.display()))? {
        let entry = entry?;
        let name = entry.file_name().to_string_lossy().into_owned();
        if is_cramp_output(&name) && entry.file_type()?.is_file() {
            ours.push(name);
        }
    }
    if ours.is_empty() {
        return Ok(());
    }
    ours.sort();
    if !force {
        bail!(
            "output directory {} already holds the results of a run ({} file(s): {}{}); choose another --out, \
             or pass --force to delete cramp's files there first",
            dir.display(),
            ours.len(),
            ours.iter().take(4).cloned().collect::<Vec<_>>().join(", "),
            if ours.len() > 4 { ", …" } else { "" }
        );
    }
    for name in &ours {
        std::fs::remove_file(dir.join(name)).with_context(|| format!("cannot delete {}", dir.join(name).display()))?;
    }
    Ok(())
}

/// A CSV file written as the run goes: the header at creation, then each row with one
/// `write` of the whole line, unbuffered, so a run that fails, is interrupted or is
/// killed leaves every row written before.
struct RowFile {
    file: std::fs::File,
    path: PathBuf,
}

impl RowFile {
    fn create(path: PathBuf, header: &str) -> anyhow::Result<Self> {
        let file = std::fs::File::create(&path).with_context(|| format!("cannot create {}", path.display()))?;
        let mut f = RowFile { file, path };
        f.row(header)?;
        Ok(f)
    }

    fn row(&mut self, line: &str) -> anyhow::Result<()> {
        self.file.write_all(format!("{line}\n").as_bytes()).with_context(|| format!("cannot write {}", self.path.display()))
    }
}

/// The files of a run directory that grow row by row (history.csv, cracks.csv,
/// growth.csv) and the snapshot counter.
struct Streams {
    dir: PathBuf,
    history: RowFile,
    cracks: Option<RowFile>,
    growth: Option<RowFile>,
    /// Growth records already in growth.csv.
    growth_rows: usize,
    /// Times of the snapshots written so far (particles.pvd lists them).
    archive_times: Vec<f64>,
}

impl Streams {
    fn open(dir: &Path, sim: &Simulation, wants_j: bool) -> anyhow::Result<Self> {
        Ok(Streams {
            dir: dir.to_path_buf(),
            history: RowFile::create(dir.join("history.csv"), HistoryRow::HEADER)?,
            cracks: if wants_j { Some(RowFile::create(dir.join("cracks.csv"), TipResult::HEADER)?) } else { None },
            growth: if sim.growth.is_some() { Some(RowFile::create(dir.join("growth.csv"), GrowthRecord::HEADER)?) } else { None },
            growth_rows: 0,
            archive_times: Vec::new(),
        })
    }

    fn history(&mut self, row: &HistoryRow) -> anyhow::Result<()> {
        self.history.row(&row.csv())
    }

    fn tips(&mut self, tips: &[TipResult]) -> anyhow::Result<()> {
        if let Some(f) = &mut self.cracks {
            for t in tips {
                f.row(&t.csv())?;
            }
        }
        Ok(())
    }

    /// Append the growth checks made since the last call.
    fn growth(&mut self, sim: &Simulation) -> anyhow::Result<()> {
        if let (Some(f), Some(g)) = (&mut self.growth, &sim.growth) {
            for r in &g.records[self.growth_rows..] {
                f.row(&r.csv())?;
            }
            self.growth_rows = g.records.len();
        }
        Ok(())
    }

    /// The snapshots of this time, and particles.pvd rewritten to list them (so a run
    /// stopped at any point leaves a collection of complete snapshots).
    fn snapshots(&mut self, sim: &Simulation) -> anyhow::Result<()> {
        write_snapshots(sim, &self.dir, self.archive_times.len())?;
        self.archive_times.push(sim.time);
        let files: Vec<(f64, String)> = self.archive_times.iter().enumerate().map(|(k, &t)| (t, format!("particles_{k:05}.vtk"))).collect();
        let pvd = self.dir.join("particles.pvd");
        write_atomically(&pvd, |tmp| write_pvd(tmp, &files))
    }
}

/// The history and archive intervals a run uses, each at least one time step, and the
/// warnings for a scene's interval that had to be rounded up.
#[derive(Clone, Debug, PartialEq)]
pub struct OutputIntervals {
    pub history: f64,
    pub archive: Option<f64>,
    pub warnings: Vec<String>,
}

/// Rows and snapshots are written at most once per step, so an interval shorter than the
/// time step `dt` means "every step": it is rounded up to `dt`, with a warning when the
/// scene gave it (silently for the default history interval, end_time / 100).
pub fn output_intervals(scene: &Scene, dt: f64) -> OutputIntervals {
    let mut warnings = Vec::new();
    let mut at_least_one_step = |field: &str, given: Option<f64>, default: f64| {
        let interval = given.unwrap_or(default);
        if interval >= dt {
            return interval;
        }
        if given.is_some() {
            warnings.push(format!("{field} = {interval:e} is shorter than the time step dt = {dt:e}: rounded up to one step"));
        }
        dt
    };
    let history = at_least_one_step("output.history_interval", scene.output.history_interval, scene.solver.end_time / 100.0);
    let archive = scene.output.archive_interval.map(|a| at_least_one_step("output.archive_interval", Some(a), a));
    OutputIntervals { history, archive, warnings }
}

/// Run an already built simulation (tests use this to alter a scene's state first).
///
/// With an output directory, history.csv, cracks.csv and growth.csv grow row by row as
/// the run goes, snapshots are written atomically, and summary.json is written at the end
/// whatever happens: `completed`, `interrupted` (`opts.stop` was set; returns `Ok`) or
/// `failed` with the error (returns the error, after writing every output up to the last
/// completed step).
pub fn run_simulation(scene: &Scene, mut sim: Simulation, opts: &RunOptions) -> anyhow::Result<RunResult> {
    let end = scene.solver.end_time;
    let dt = sim.options.dt;
    let OutputIntervals { history: hist_dt, archive: arch_dt, warnings } = output_intervals(scene, dt);
    let requests = scene.fracture_requests();
    let wants_j = requests.iter().any(Option::is_some);
    let mut streams = match &opts.out_dir {
        Some(dir) => {
            prepare_out_dir(dir, opts.force)?;
            Some(Streams::open(dir, &sim, wants_j)?)
        }
        None => None,
    };
    let total_steps = ((end / dt) - 0.5).ceil().max(0.0) as u64;
    let bar = if opts.progress {
        let b = indicatif::ProgressBar::new(total_steps);
        b.set_style(
            indicatif::ProgressStyle::with_template("{bar:40} {pos}/{len} steps  {elapsed_precise} (eta {eta})")
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        b
    } else {
        indicatif::ProgressBar::hidden()
    };

    let mut history = vec![HistoryRow::of(&sim)];
    let mut tips: Vec<TipResult> = Vec::new();
    let mut next_hist = hist_dt;
    let mut next_arch = arch_dt.unwrap_or(f64::INFINITY);
    // The first error of the observer (a crack-tip evaluation or an output), which stops the run.
    let mut observer_error: Option<anyhow::Error> = None;
    if let Some(out) = &mut streams {
        out.history(&history[0])?;
        if arch_dt.is_some() {
            out.snapshots(&sim)?;
        }
    }
    // The last step completed and its time (a failing step may have advanced the clock).
    let (mut done_steps, mut done_time) = (sim.step_count, sim.time);
    let start = Instant::now();
    let half = 0.5 * dt;
    let outcome = sim.run_until_stopped(end, |s| {
        bar.inc(1);
        (done_steps, done_time) = (s.step_count, s.time);
        let mut record = || -> anyhow::Result<()> {
            if s.time + half >= next_hist {
                let row = HistoryRow::of(s);
                history.push(row);
                let new_tips = if wants_j { s.fracture_parameters(&requests)? } else { Vec::new() };
                if let Some(out) = &mut streams {
                    out.history(&row)?;
                    out.tips(&new_tips)?;
                }
                tips.extend(new_tips);
                while next_hist <= s.time + half {
                    next_hist += hist_dt;
                }
            }
            if let Some(out) = &mut streams {
                out.growth(s)?;
            }
            if s.time + half >= next_arch {
                if let Some(out) = &mut streams {
                    out.snapshots(s)?;
                }
                while next_arch <= s.time + half {
                    next_arch += arch_dt.unwrap_or(f64::INFINITY);
                }
            }
            Ok(())
        };
        if let Err(e) = record() {
            observer_error = Some(e);
            return ControlFlow::Break(());
        }
        if opts.stop.as_ref().is_some_and(|f| f.load(Ordering::Relaxed)) {
            return ControlFlow::Break(());
        }
        ControlFlow::Continue(())
    });
    let wall = start.elapsed().as_secs_f64();
    bar.finish_and_clear();
    let (failure, stopped) = match outcome {
        Err(e) => (Some(anyhow::anyhow!(e)), false),
        Ok(stopped) => (observer_error, stopped),
    };
    let status = match (&failure, stopped) {
        (Some(_), _) => RunStatus::Failed,
        (None, true) => RunStatus::Interrupted,
        (None, false) => RunStatus::Completed,
    };
    // A run that stopped between history times ends with a row of its last state (unless
    // the state is that of a failed step).
    if status != RunStatus::Failed && history.last().map(|h| h.time) != Some(sim.time) {
        let row = HistoryRow::of(&sim);
        history.push(row);
        let new_tips = if wants_j && sim.step_count > 0 { sim.fracture_parameters(&requests)? } else { Vec::new() };
        if let Some(out) = &mut streams {
            out.history(&row)?;
            out.tips(&new_tips)?;
        }
        tips.extend(new_tips);
    }
    let summary = Summary {
        status,
        error: failure.as_ref().map(|e| format!("{e:#}")),
        warnings,
        scene: scene.clone(),
        steps: done_steps,
        dt,
        end_time: done_time,
        particles: sim.particles.len(),
        nodes: sim.grid.num_nodes(),
        wall_time_s: wall,
        particle_steps_per_second: sim.particles.len() as f64 * done_steps as f64 / wall.max(1e-12),
        threads: rayon::current_num_threads(),
        checked: sim.options.checked,
        final_energies: *history.last().expect("history has the initial row"),
        growth: CrackGrowthSummary::of(&sim),
    };
    if let (Some(out), Some(dir)) = (&mut streams, &opts.out_dir) {
        // The growth checks of a failed step are part of the record of how it failed.
        out.growth(&sim)?;
        if sim.growth.is_some() {
            write_crack_paths(&dir.join("crack_paths.csv"), &sim)?;
        }
        let json = serde_json::to_string_pretty(&summary)?;
        write_atomically(&dir.join("summary.json"), |tmp| std::fs::write(tmp, &json).map_err(Into::into))?;
    }
    if let Some(e) = failure {
        let at = format!("the run stopped after step {done_steps} (t = {done_time:e})");
        return Err(match &opts.out_dir {
            Some(dir) => e.context(format!("{at}; its outputs up to then and summary.json (status \"failed\") are in {}", dir.display())),
            None => e.context(at),
        });
    }
    Ok(RunResult { history, tips, summary, sim })
}

/// Write `path` through a temporary file in the same directory and a rename, so the file
/// is either absent, the previous version, or complete — never half-written.
pub fn write_atomically(path: &Path, write: impl FnOnce(&Path) -> anyhow::Result<()>) -> anyhow::Result<()> {
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let tmp = path.with_file_name(format!(".{name}.tmp"));
    if let Err(e) = write(&tmp) {
        let _ = std::fs::remove_file(&tmp);
        return Err(e);
    }
    std::fs::rename(&tmp, path).with_context(|| format!("cannot rename {} to {}", tmp.display(), path.display()))
}

/// Write a CSV file from its header and rows.
fn write_rows(path: &Path, header: &str, rows: impl Iterator<Item = String>) -> anyhow::Result<()> {
    let mut f = std::io::BufWriter::new(std::fs::File::create(path).with_context(|| format!("cannot create {}", path.display()))?);
    writeln!(f, "{header}")?;
    for r in rows {
        writeln!(f, "{r}")?;
    }
    Ok(())
}

/// crack_paths.csv: every crack's polyline at the end of the run (crack particles in
/// order; `crack,index,x,y`), the path a growing crack took.
pub fn write_crack_paths(path: &Path, sim: &Simulation) -> anyhow::Result<()> {
    let rows = sim.cracks.iter().enumerate().flat_map(|(c, cr)| cr.points.iter().enumerate().map(move |(k, p)| format!("{c},{k},{:e},{:e}", p.x, p.y)));
    write_rows(path, "crack,index,x,y", rows)
}

/// The end state of one growing crack (summary.json).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct CrackGrowthSummary {
    pub crack: usize,
    /// Tracked length: initial polyline length plus every increment.
    pub length: f64,
    /// Per growing tip: which end, its advance, and its status (growing, edge, crackN).
    pub tips: Vec<(String, f64, String)>,
    /// Time at which the crack cut its body through.
    pub split_time: Option<f64>,
}

impl CrackGrowthSummary {
    pub fn of(sim: &Simulation) -> Vec<CrackGrowthSummary> {
        let Some(g) = &sim.growth else { return Vec::new() };
        g.cracks
            .iter()
            .map(|cg| CrackGrowthSummary {
                crack: cg.crack,
                length: cg.length(),
                tips: cg.tips.iter().map(|t| (format!("{:?}", t.end).to_lowercase(), t.advance, t.status.label())).collect(),
                split_time: cg.split,
            })
            .collect()
    }
}

/// A ParaView collection (`.pvd`) listing snapshot files with their times, so ParaView
/// opens a run's snapshots as one time series (2D and 3D).
pub fn write_pvd(path: &Path, files: &[(f64, String)]) -> anyhow::Result<()> {
    let parts: Vec<(f64, usize, String)> = files.iter().map(|(t, n)| (*t, 0, n.clone())).collect();
    write_pvd_parts(path, &parts)
}

/// A ParaView collection of (time, part, file): several files per time are the parts of
/// one multiblock data set (3D runs: particles part 0, crack surfaces part 1).
pub fn write_pvd_parts(path: &Path, files: &[(f64, usize, String)]) -> anyhow::Result<()> {
    let mut f = std::io::BufWriter::new(std::fs::File::create(path).with_context(|| format!("cannot create {}", path.display()))?);
    writeln!(f, "<?xml version=\"1.0\"?>")?;
    writeln!(f, "<VTKFile type=\"Collection\" version=\"0.1\">")?;
    writeln!(f, "  <Collection>")?;
    for (t, part, name) in files {
        writeln!(f, "    <DataSet timestep=\"{t:e}\" part=\"{part}\" file=\"{name}\"/>")?;
    }
    writeln!(f, "  </Collection>")?;
    writeln!(f, "</VTKFile>")?;
    f.flush()?;
    Ok(())
}

/// The snapshots of one archive time: `particles_NNNNN.vtk` and, when the scene has
/// cracks, `cracks_NNNNN.vtk`.
fn write_snapshots(sim: &Simulation, dir: &Path, index: usize) -> anyhow::Result<()> {
    write_snapshot(sim, &dir.join(format!("particles_{index:05}.vtk")))?;
    if sim.has_cracks() {
        write_crack_snapshot(sim, &dir.join(format!("cracks_{index:05}.vtk")))?;
    }
    Ok(())
}

/// Crack snapshot in legacy VTK: for every crack, in scene order, three polylines — the
/// crack particles (moved in the centre-of-mass velocity, Nairn 2003 Task 7), its
/// "above" surface and its "below" surface (each moved in its own velocity field,
/// Nairn 2003/Guo & Nairn: the crack-opening displacement is above − below at each
/// crack particle). Cell scalars: `crack` (index in the scene) and `surface` (0 crack
/// particles, 1 above, 2 below). ParaView: colour by `surface`, filter by `crack`.
pub fn write_crack_snapshot(sim: &Simulation, path: &Path) -> anyhow::Result<()> {
    let mut lines = Vec::with_capacity(3 * sim.cracks.len());
    let mut crack = Vec::with_capacity(3 * sim.cracks.len());
    let mut surface = Vec::with_capacity(3 * sim.cracks.len());
    for (c, cr) in sim.cracks.iter().enumerate() {
        for (k, pts) in [&cr.points, &cr.above, &cr.below].into_iter().enumerate() {
            lines.push(pts.clone());
            crack.push(c as f64);
            surface.push(k as f64);
        }
    }
    write_atomically(path, |tmp| {
        vtk::write_polylines(tmp, &format!("cramp cracks t={:e}", sim.time), &lines, &[("crack", &crack), ("surface", &surface)])
            .with_context(|| format!("cannot write crack snapshot {}", path.display()))
    })
}

/// Particle snapshot in legacy VTK, particles sorted by id so the file does not depend
/// on the order particles are stored in.
pub fn write_snapshot(sim: &Simulation, path: &Path) -> anyhow::Result<()> {
    use vtk::PointData;
    let p = &sim.particles;
    let mut order: Vec<usize> = (0..p.len()).collect();
    order.sort_by_key(|&i| p.id[i]);
    let pos: Vec<Vector> = order.iter().map(|&i| p.x[i]).collect();
    let disp: Vec<Vector> = order.iter().map(|&i| p.x[i] - p.x0[i]).collect();
    let vel: Vec<Vector> = order.iter().map(|&i| p.v[i]).collect();
    let stress: Vec<_> = order.iter().map(|&i| p.stress[i]).collect();
    let strain: Vec<_> = order.iter().map(|&i| p.strain[i]).collect();
    let mat: Vec<f64> = order.iter().map(|&i| p.material[i] as f64).collect();
    let id: Vec<f64> = order.iter().map(|&i| p.id[i] as f64).collect();
    let data = [
        ("id", PointData::Scalar(&id)),
        ("displacement", PointData::Vector(&disp)),
        ("velocity", PointData::Vector(&vel)),
        ("stress", PointData::Tensor(&stress)),
        ("strain", PointData::Tensor(&strain)),
        ("material", PointData::Scalar(&mat)),
    ];
    write_atomically(path, |tmp| {
        vtk::write_points(tmp, &format!("cramp particles t={:e}", sim.time), &pos, &data).with_context(|| format!("cannot write snapshot {}", path.display()))
    })
}
