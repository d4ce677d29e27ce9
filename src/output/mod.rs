//! Outputs of a run: `history.csv` (energies at the history interval), `summary.json`
//! (scene echo, step count, time step, wall time, throughput, final energies) and VTK
//! particle snapshots at the archive interval. Physics stays out of here: this module
//! only reads a [`Simulation`].

pub mod vtk;

use crate::dim::Vector;
use crate::fracture::growth::GrowthRecord;
use crate::fracture::jintegral::{FractureError, TipResult};
use crate::scene::Scene;
use crate::simulation::{Energies, Simulation};
use anyhow::Context;
use serde::{Deserialize, Serialize};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// One row of history.csv.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct HistoryRow {
    pub time: f64,
    pub kinetic: f64,
    pub strain: f64,
    pub external_work: f64,
    pub damping: f64,
    /// kinetic + strain + damping − external_work.
    pub total: f64,
    /// Total particle momentum.
    pub momentum_x: f64,
    pub momentum_y: f64,
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
        }
    }

    pub const HEADER: &'static str = "time,kinetic,strain,external_work,damping,total,momentum_x,momentum_y";

    pub fn csv(&self) -> String {
        // `{:e}` of f64 round-trips exactly.
        format!(
            "{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e}",
            self.time, self.kinetic, self.strain, self.external_work, self.damping, self.total, self.momentum_x, self.momentum_y
        )
    }
}

/// summary.json.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Summary {
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
    pub final_energies: HistoryRow,
    /// Growing cracks at the end of the run: length, tip states, split time.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub growth: Vec<CrackGrowthSummary>,
}

/// How to run a scene.
#[derive(Clone, Debug, Default)]
pub struct RunOptions {
    /// Write outputs here (None: in memory only).
    pub out_dir: Option<PathBuf>,
    /// Show a progress bar (only drawn on a terminal).
    pub progress: bool,
    /// Override the scene's `solver.checked`.
    pub checked: Option<bool>,
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

/// Run an already built simulation (tests use this to alter a scene's state first).
pub fn run_simulation(scene: &Scene, mut sim: Simulation, opts: &RunOptions) -> anyhow::Result<RunResult> {
    if let Some(dir) = &opts.out_dir {
        std::fs::create_dir_all(dir).with_context(|| format!("cannot create output directory {}", dir.display()))?;
    }
    let end = scene.solver.end_time;
    let dt = sim.options.dt;
    let hist_dt = scene.history_interval();
    let arch_dt = scene.output.archive_interval;
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

    let requests = scene.fracture_requests();
    let wants_j = requests.iter().any(Option::is_some);
    let mut history = vec![HistoryRow::of(&sim)];
    let mut tips: Vec<TipResult> = Vec::new();
    let mut fracture_error: Option<FractureError> = None;
    let mut next_hist = hist_dt;
    let mut archive_index = 0usize;
    let mut next_arch = arch_dt.unwrap_or(f64::INFINITY);
    if let (Some(dir), Some(_)) = (&opts.out_dir, arch_dt) {
        write_snapshots(&sim, dir, archive_index)?;
        archive_index += 1;
    }
    let start = Instant::now();
    let mut io_error: Option<anyhow::Error> = None;
    let half = 0.5 * dt;
    let run = sim.run_until(end, |s| {
        bar.inc(1);
        if s.time + half >= next_hist {
            history.push(HistoryRow::of(s));
            if wants_j && fracture_error.is_none() {
                match s.fracture_parameters(&requests) {
                    Ok(t) => tips.extend(t),
                    Err(e) => fracture_error = Some(e),
                }
            }
            while next_hist <= s.time + half {
                next_hist += hist_dt;
            }
        }
        if s.time + half >= next_arch {
            if let Some(dir) = &opts.out_dir {
                if let Err(e) = write_snapshots(s, dir, archive_index) {
                    io_error.get_or_insert(e);
                }
            }
            archive_index += 1;
            while next_arch <= s.time + half {
                next_arch += arch_dt.unwrap_or(f64::INFINITY);
            }
        }
    });
    if let Err(e) = run {
        // What was computed up to the failure is written, so the run can be examined.
        if let Some(dir) = &opts.out_dir {
            history.push(HistoryRow::of(&sim));
            write_tables(dir, &sim, &history, wants_j.then_some(&tips[..]))?;
        }
        return Err(anyhow::anyhow!(e));
    }
    let wall = start.elapsed().as_secs_f64();
    bar.finish_and_clear();
    if let Some(e) = io_error {
        return Err(e);
    }
    if let Some(e) = fracture_error {
        return Err(anyhow::anyhow!(e));
    }
    if history.last().map(|h| h.time) != Some(sim.time) {
        history.push(HistoryRow::of(&sim));
        if wants_j && sim.step_count > 0 {
            tips.extend(sim.fracture_parameters(&requests)?);
        }
    }
    let summary = Summary {
        scene: scene.clone(),
        steps: sim.step_count,
        dt,
        end_time: sim.time,
        particles: sim.particles.len(),
        nodes: sim.grid.num_nodes(),
        wall_time_s: wall,
        particle_steps_per_second: sim.particles.len() as f64 * sim.step_count as f64 / wall.max(1e-12),
        threads: rayon::current_num_threads(),
        checked: sim.options.checked,
        final_energies: *history.last().expect("history has the initial row"),
        growth: CrackGrowthSummary::of(&sim),
    };
    if let Some(dir) = &opts.out_dir {
        write_tables(dir, &sim, &history, wants_j.then_some(&tips[..]))?;
        let json = serde_json::to_string_pretty(&summary)?;
        std::fs::write(dir.join("summary.json"), json).with_context(|| format!("cannot write {}", dir.join("summary.json").display()))?;
    }
    Ok(RunResult { history, tips, summary, sim })
}

/// The CSV tables of a run: history.csv, cracks.csv (when J is requested: `tips`),
/// growth.csv and crack_paths.csv (growing cracks).
fn write_tables(dir: &Path, sim: &Simulation, history: &[HistoryRow], tips: Option<&[TipResult]>) -> anyhow::Result<()> {
    write_history(&dir.join("history.csv"), history)?;
    if let Some(tips) = tips {
        write_tips(&dir.join("cracks.csv"), tips)?;
    }
    if let Some(g) = &sim.growth {
        write_rows(&dir.join("growth.csv"), GrowthRecord::HEADER, g.records.iter().map(GrowthRecord::csv))?;
        write_crack_paths(&dir.join("crack_paths.csv"), sim)?;
    }
    Ok(())
}

/// Write cracks.csv: one row per requested crack tip per history time.
pub fn write_tips(path: &Path, rows: &[TipResult]) -> anyhow::Result<()> {
    write_rows(path, TipResult::HEADER, rows.iter().map(TipResult::csv))
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

/// Write history.csv.
pub fn write_history(path: &Path, rows: &[HistoryRow]) -> anyhow::Result<()> {
    write_rows(path, HistoryRow::HEADER, rows.iter().map(HistoryRow::csv))
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
    vtk::write_polylines(
        path,
        &format!("cramp cracks t={:e}", sim.time),
        &lines,
        &[("crack", &crack), ("surface", &surface)],
    )
    .with_context(|| format!("cannot write crack snapshot {}", path.display()))
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
    vtk::write_points(
        path,
        &format!("cramp particles t={:e}", sim.time),
        &pos,
        &[
            ("id", PointData::Scalar(&id)),
            ("displacement", PointData::Vector(&disp)),
            ("velocity", PointData::Vector(&vel)),
            ("stress", PointData::Tensor(&stress)),
            ("strain", PointData::Tensor(&strain)),
            ("material", PointData::Scalar(&mat)),
        ],
    )
    .with_context(|| format!("cannot write snapshot {}", path.display()))
}
