//! Outputs of a 3D run: `history.csv` (energies and the three momentum components at the
//! history interval), `summary.json`, VTK particle snapshots with 3D positions, vectors and
//! full symmetric tensors, and the ParaView collection `particles.pvd`.

use super::vtk::{self, PointData};
use super::{prepare_out_dir, write_atomically, write_pvd_parts, RunOptions, RunStatus};
use crate::dim::{Vector3, D3};
use crate::scene3d::Scene3;
use crate::simulation::{Energies, Simulation};
use anyhow::Context;
use serde::{Deserialize, Serialize};
use std::path::Path;
use std::time::Instant;

/// One row of a 3D history.csv.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct HistoryRow3 {
    pub time: f64,
    pub kinetic: f64,
    pub strain: f64,
    pub external_work: f64,
    pub damping: f64,
    /// kinetic + strain + damping − external_work − boundary_work.
    pub total: f64,
    pub momentum_x: f64,
    pub momentum_y: f64,
    pub momentum_z: f64,
    /// Work of the velocity boundary conditions that move their nodes (reaction · v_c Δt).
    #[serde(default)]
    pub boundary_work: f64,
}

impl HistoryRow3 {
    pub fn of(sim: &Simulation<D3>) -> Self {
        let e: Energies = sim.energies();
        let p = sim.total_momentum();
        HistoryRow3 {
            time: sim.time,
            kinetic: e.kinetic,
            strain: e.strain,
            external_work: e.external_work,
            damping: e.damping,
            total: e.total(),
            momentum_x: p.x,
            momentum_y: p.y,
            momentum_z: p.z,

            boundary_work: e.boundary_work,
        }
    }

    pub const HEADER: &'static str = "time,kinetic,strain,external_work,damping,total,momentum_x,momentum_y,momentum_z,boundary_work";

    pub fn csv(&self) -> String {
        format!(
            "{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e}",
            self.time, self.kinetic, self.strain, self.external_work, self.damping, self.total, self.momentum_x, self.momentum_y, self.momentum_z, self.boundary_work
        )
    }
}

/// summary.json of a 3D run.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Summary3 {
    /// How the run ended; `steps` and `end_time` are the last step completed and its time.
    pub status: RunStatus,
    /// The error that stopped a failed run.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
    pub scene: Scene3,
    pub dimension: usize,
    pub steps: u64,
    pub dt: f64,
    pub end_time: f64,
    pub particles: usize,
    pub nodes: usize,
    pub wall_time_s: f64,
    /// Particles × steps / wall time of the time loop (outputs included).
    pub particle_steps_per_second: f64,
    pub threads: usize,
    pub checked: bool,
    /// Bytes per particle of the particle arrays and of the pair arrays (27 pairs).
    pub bytes_per_particle: usize,
    /// Bytes per grid node of the nodal arrays (one velocity field).
    pub bytes_per_node: usize,
    pub final_energies: HistoryRow3,
}

/// What a 3D run returns in memory.
#[derive(Clone, Debug)]
pub struct RunResult3 {
    pub history: Vec<HistoryRow3>,
    /// J and K at the requested front nodes at each history time after t = 0 (cracks.csv).
    pub fronts: Vec<crate::fracture::front3::FrontResult>,
    pub summary: Summary3,
    pub sim: Simulation<D3>,
}

/// Memory of one particle: its state arrays and its stride of the pair arrays.
pub fn bytes_per_particle_3d() -> usize {
    let v = std::mem::size_of::<Vector3>();
    let state = 5 * v // x, x0, v, lp, force
        + 2 * std::mem::size_of::<crate::dim::Sym3>()
        + std::mem::size_of::<crate::dim::Tensor3>()
        + 2 * 8 // mass, vol0
        + 4 + 3 * 2; // id, material, body, load
    let pairs = 27 * (4 + 8 + v + 1 + 4) + 1; // node, s, g, field, CSR item; count
    state + pairs
}

/// Memory of one grid node with one velocity field: mass and six vectors, the present
/// bits, the compact CSR index and the touched mark, and the boundary-condition mask and
/// velocity.
pub fn bytes_per_node_3d() -> usize {
    let v = std::mem::size_of::<Vector3>();
    8 + 6 * v + 1 + 4 + 1 + 1 + v
}

/// Build and run a 3D scene to its end time, recording history and writing outputs.
pub fn run_scene_3d(scene: &Scene3, opts: &RunOptions) -> anyhow::Result<RunResult3> {
    let mut sim = scene.build()?;
    if let Some(c) = opts.checked {
        sim.options.checked = c;
    }
    run_simulation_3d(scene, sim, opts)
}

/// Run an already built 3D simulation. As in 2D: history.csv grows row by row as the run
/// goes, snapshots and particles.pvd are written atomically, and summary.json is written
/// however the run ends (completed, interrupted by the stop flag, or failed with the
/// error; a failed run still returns its error).
pub fn run_simulation_3d(scene: &Scene3, mut sim: Simulation<D3>, opts: &RunOptions) -> anyhow::Result<RunResult3> {
    if let Some(dir) = &opts.out_dir {
        prepare_out_dir(dir, opts.force)?;
    }
    let end = scene.solver.end_time;
    let dt = sim.options.dt;
    // Intervals below one step mean "every step" (the 2D runner warns about them).
    let hist_dt = scene.history_interval().max(dt);
    let arch_dt = scene.output.archive_interval.map(|a| a.max(dt));
    let total_steps = ((end / dt) - 0.5).ceil().max(0.0) as u64;
    let bar = if opts.progress { indicatif::ProgressBar::new(total_steps) } else { indicatif::ProgressBar::hidden() };
    let mut history = vec![HistoryRow3::of(&sim)];
    let mut rows = match &opts.out_dir {
        Some(dir) => Some(super::RowFile::create(dir.join("history.csv"), HistoryRow3::HEADER)?),
        None => None,
    };
    if let Some(f) = &mut rows {
        f.row(&history[0].csv())?;
    }
    // J and K along the fronts (cracks.csv), at the history times after t = 0 (the nodal
    // values of eq. 11 need a completed step).
    let requests = scene.front_requests(&sim.cracks)?;
    let wants_j = requests.iter().any(Option::is_some);
    // A growing crack is evaluated at its current front ([`Growth3::current_request`]).
    let live = |s: &Simulation<D3>| -> Vec<Option<crate::fracture::front3::FrontRequest>> {
        match &s.growth {
            None => requests.clone(),
            Some(g) => requests.iter().enumerate().map(|(c, r)| g.current_request(s, c).or_else(|| r.clone())).collect(),
        }
    };
    // growth.csv: one row per front node per growth check, appended after every step.
    let mut growth_rows = match (&opts.out_dir, &sim.growth) {
        (Some(dir), Some(_)) => Some((super::RowFile::create(dir.join("growth.csv"), crate::fracture::growth3::NodeRecord::HEADER)?, 0usize)),
        _ => None,
    };
    let mut write_growth = |s: &Simulation<D3>| -> anyhow::Result<()> {
        if let (Some((f, done)), Some(g)) = (&mut growth_rows, &s.growth) {
            for r in &g.records[*done..] {
                f.row(&r.csv())?;
            }
            *done = g.records.len();
        }
        Ok(())
    };
    let mut fronts = Vec::new();
    let mut front_rows = match &opts.out_dir {
        Some(dir) if wants_j => Some(super::RowFile::create(dir.join("cracks.csv"), crate::fracture::front3::FrontResult::HEADER)?),
        _ => None,
    };
    let mut record_fronts = |s: &Simulation<D3>, fronts: &mut Vec<crate::fracture::front3::FrontResult>| -> anyhow::Result<()> {
        if !wants_j || s.step_count == 0 {
            return Ok(());
        }
        let new = s.front_parameters(&live(s));
        if let Some(f) = &mut front_rows {
            for r in &new {
                f.row(&r.csv())?;
            }
        }
        fronts.extend(new);
        Ok(())
    };
    let mut next_hist = hist_dt;
    let mut snapshots: Vec<(f64, usize, String)> = Vec::new();
    let mut next_arch = arch_dt.unwrap_or(f64::INFINITY);
    let mut archived = 0usize;
    let mut archive = |s: &Simulation<D3>, snapshots: &mut Vec<(f64, usize, String)>| -> anyhow::Result<()> {
        if let Some(dir) = &opts.out_dir {
            let name = format!("particles_{archived:05}.vtk");
            write_atomically(&dir.join(&name), |tmp| write_snapshot_3d(s, tmp))?;
            snapshots.push((s.time, 0, name));
            if s.has_cracks() {
                let name = format!("cracks_{archived:05}.vtk");
                write_atomically(&dir.join(&name), |tmp| write_crack_snapshot_3d(s, tmp))?;
                snapshots.push((s.time, 1, name));
            }
            if wants_j && s.step_count > 0 {
                let name = format!("front_{archived:05}.vtk");
                let results = s.front_parameters(&live(s));
                write_atomically(&dir.join(&name), |tmp| write_front_snapshot_3d(&results, s.time, tmp))?;
                snapshots.push((s.time, 2, name));
            }
            archived += 1;
            write_atomically(&dir.join("particles.pvd"), |tmp| write_pvd_parts(tmp, snapshots))?;
        }
        Ok(())
    };
    if arch_dt.is_some() {
        archive(&sim, &mut snapshots)?;
    }
    let (mut done_steps, mut done_time) = (sim.step_count, sim.time);
    let mut observer_error: Option<anyhow::Error> = None;
    let start = Instant::now();
    let half = 0.5 * dt;
    let outcome = sim.run_until_stopped(end, |s| {
        bar.inc(1);
        (done_steps, done_time) = (s.step_count, s.time);
        let mut record = || -> anyhow::Result<()> {
            write_growth(s)?;
            if s.time + half >= next_hist {
                let row = HistoryRow3::of(s);
                history.push(row);
                if let Some(f) = &mut rows {
                    f.row(&row.csv())?;
                }
                record_fronts(s, &mut fronts)?;
                while next_hist <= s.time + half {
                    next_hist += hist_dt;
                }
            }
            if s.time + half >= next_arch {
                archive(s, &mut snapshots)?;
                while next_arch <= s.time + half {
                    next_arch += arch_dt.unwrap_or(f64::INFINITY);
                }
            }
            Ok(())
        };
        if let Err(e) = record() {
            observer_error = Some(e);
            return std::ops::ControlFlow::Break(());
        }
        if opts.stop.as_ref().is_some_and(|f| f.load(std::sync::atomic::Ordering::Relaxed)) {
            return std::ops::ControlFlow::Break(());
        }
        std::ops::ControlFlow::Continue(())
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
    if status != RunStatus::Failed && history.last().map(|h| h.time) != Some(sim.time) {
        let row = HistoryRow3::of(&sim);
        history.push(row);
        if let Some(f) = &mut rows {
            f.row(&row.csv())?;
        }
        record_fronts(&sim, &mut fronts)?;
    }
    // The growth checks of a failed step are part of the record of how it failed.
    write_growth(&sim)?;
    let summary = Summary3 {
        status,
        error: failure.as_ref().map(|e| format!("{e:#}")),
        scene: scene.clone(),
        dimension: 3,
        steps: done_steps,
        dt,
        end_time: done_time,
        particles: sim.particles.len(),
        nodes: crate::dim::GridGeometry::num_nodes(&sim.grid),
        wall_time_s: wall,
        particle_steps_per_second: sim.particles.len() as f64 * done_steps as f64 / wall.max(1e-12),
        threads: rayon::current_num_threads(),
        checked: sim.options.checked,
        bytes_per_particle: bytes_per_particle_3d(),
        bytes_per_node: bytes_per_node_3d(),
        final_energies: *history.last().expect("history has the initial row"),
    };
    if let Some(dir) = &opts.out_dir {
        let json = serde_json::to_string_pretty(&summary)?;
        write_atomically(&dir.join("summary.json"), |tmp| std::fs::write(tmp, &json).with_context(|| format!("cannot write {}", tmp.display())))?;
    }
    if let Some(e) = failure {
        let at = format!("the run stopped after step {done_steps} (t = {done_time:e})");
        return Err(match &opts.out_dir {
            Some(dir) => e.context(format!("{at}; its outputs up to then and summary.json (status \"failed\") are in {}", dir.display())),
            None => e.context(at),
        });
    }
    Ok(RunResult3 { history, fronts, summary, sim })
}

/// 3D particle snapshot in legacy VTK, particles sorted by id.
pub fn write_snapshot_3d(sim: &Simulation<D3>, path: &Path) -> anyhow::Result<()> {
    let p = &sim.particles;
    let mut order: Vec<usize> = (0..p.len()).collect();
    order.sort_by_key(|&i| p.id[i]);
    let pos: Vec<Vector3> = order.iter().map(|&i| p.x[i]).collect();
    let disp: Vec<Vector3> = order.iter().map(|&i| p.x[i] - p.x0[i]).collect();
    let vel: Vec<Vector3> = order.iter().map(|&i| p.v[i]).collect();
    let stress: Vec<_> = order.iter().map(|&i| p.stress[i]).collect();
    let strain: Vec<_> = order.iter().map(|&i| p.strain[i]).collect();
    let mat: Vec<f64> = order.iter().map(|&i| p.material[i] as f64).collect();
    let id: Vec<f64> = order.iter().map(|&i| p.id[i] as f64).collect();
    vtk::write_points_3d(
        path,
        &format!("cramp particles t={:e}", sim.time),
        &pos,
        &[
            ("id", PointData::Scalar(&id)),
            ("displacement", PointData::Vector3(&disp)),
            ("velocity", PointData::Vector3(&vel)),
            ("stress", PointData::Tensor3(&stress)),
            ("strain", PointData::Tensor3(&strain)),
            ("material", PointData::Scalar(&mat)),
        ],
    )
    .with_context(|| format!("cannot write snapshot {}", path.display()))
}

/// 3D crack snapshot in legacy VTK: for every crack, in scene order, three triangle meshes
/// — the crack particles (moved in the centre-of-mass velocity, Task 7), the "above"
/// surface and the "below" surface (each moved in its own side's fields, 001 eqs. 11–12).
/// Point vector `opening`: above − below at the crack particle (the crack-opening
/// displacement, the same on all three copies). Cell scalars `crack` (index in the scene)
/// and `surface` (0 crack particles, 1 above, 2 below).
pub fn write_crack_snapshot_3d(sim: &Simulation<D3>, path: &Path) -> anyhow::Result<()> {
    let (mut pts, mut tris, mut opening, mut crack, mut surface) = (Vec::new(), Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for (c, cr) in sim.cracks.iter().enumerate() {
        let open: Vec<Vector3> = (0..cr.above.len()).map(|k| cr.opening(k)).collect();
        for (k, set) in [&cr.surface.vertices, &cr.above, &cr.below].into_iter().enumerate() {
            let base = pts.len() as u32;
            pts.extend_from_slice(set);
            opening.extend_from_slice(&open);
            for t in &cr.surface.triangles {
                tris.push(t.map(|i| i + base));
                crack.push(c as f64);
                surface.push(k as f64);
            }
        }
    }
    vtk::write_triangles(path, &format!("cramp cracks t={:e}", sim.time), &pts, &tris, &[("opening", &opening)], &[("crack", &crack), ("surface", &surface)])
        .with_context(|| format!("cannot write crack snapshot {}", path.display()))
}

/// The front nodes with J and K (`fracture` tables) in legacy VTK, one vertex per node:
/// scalars `crack`, `node`, `j1`, `j2`, `k1`, `k2`, `k3` and `k_valid` (0 where the opening
/// behind the node could not be read; K written as 0 there, VTK holds no NaN), vectors
/// `e1`, `e2` (the local frame). Nodes without a frame are left out.
pub fn write_front_snapshot_3d(results: &[crate::fracture::front3::FrontResult], time: f64, path: &Path) -> anyhow::Result<()> {
    let r: Vec<_> = results.iter().filter(|f| f.frame.e1.iter().all(|c| c.is_finite()) && f.j1.is_finite()).collect();
    let pos: Vec<Vector3> = r.iter().map(|f| f.x).collect();
    let col = |g: &dyn Fn(&crate::fracture::front3::FrontResult) -> f64| -> Vec<f64> { r.iter().map(|f| g(f)).collect() };
    let valid = |f: &crate::fracture::front3::FrontResult| f.k.iter().all(|k| k.is_finite());
    let k = |a: usize| col(&|f| if valid(f) { f.k[a] } else { 0.0 });
    let (crack, node, j1, j2) = (col(&|f| f.crack as f64), col(&|f| f.node as f64), col(&|f| f.j1), col(&|f| f.j2));
    let (k1, k2, k3, kv) = (k(0), k(1), k(2), col(&|f| valid(f) as u8 as f64));
    let j2 = j2.into_iter().map(|x| if x.is_finite() { x } else { 0.0 }).collect::<Vec<_>>();
    let e1: Vec<Vector3> = r.iter().map(|f| f.frame.e1).collect();
    let e2: Vec<Vector3> = r.iter().map(|f| f.frame.e2).collect();
    vtk::write_points_3d(
        path,
        &format!("cramp crack fronts t={time:e}"),
        &pos,
        &[
            ("crack", PointData::Scalar(&crack)),
            ("node", PointData::Scalar(&node)),
            ("j1", PointData::Scalar(&j1)),
            ("j2", PointData::Scalar(&j2)),
            ("k1", PointData::Scalar(&k1)),
            ("k2", PointData::Scalar(&k2)),
            ("k3", PointData::Scalar(&k3)),
            ("k_valid", PointData::Scalar(&kv)),
            ("e1", PointData::Vector3(&e1)),
            ("e2", PointData::Vector3(&e2)),
        ],
    )
    .with_context(|| format!("cannot write front snapshot {}", path.display()))
}
