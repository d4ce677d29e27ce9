//! The two 3D crack-growth examples of paper 001 §3.3 (issue 17, "the paper's two
//! examples"; geometry decoded in shared/reference/3d-references.md §7.5), full suite only:
//!
//! * `corner_crack_rod`: `corner_crack_rod_3d.toml`, the inclined quarter-penny corner crack
//!   in the 50 × 50 × 100 mm steel rod under a 400 MPa step (250,000 particles, 233 steps).
//! * `tube_crack`: `tube_crack_3d.toml`, the 45° through-wall crack in the R 50/40 tube
//!   (848,000 particles, about 870 steps).
//!
//! The paper gives no numbers for either, only what the pictures show (001 §3.3): the front
//! turns at once from mixed mode to mode I dominated growth; the rod's front first grows in
//! length and shrinks after it passes the section's diagonal; the front interacts with the
//! edges and the growth runs until the whole front has reached them; the tube's two ends
//! turn to mode I and run round the circumference on offset paths that do not meet. Each is
//! made a measured check here (cases.toml says against what and why), with the run's time,
//! peak memory and front-node counts in the notes and pictures of the crack surface at
//! several times (an oblique projection coloured by the surface's tilt from the load axis,
//! [`crate::report::surface3`]).
//!
//! The initial mixity is also compared, as an orientation figure only, with the closed form
//! of an inclined penny in an infinite body at the same angle (3d-references.md §2, γ =
//! 39.23°: K_II/K_I = 2 tan γ/(2 − ν) = 0.959 at the point of pure I + II, where the maximum
//! hoop stress criterion kinks by 52.49°): a corner crack in a finite rod under a step wave
//! is not that crack, so the figures are reported, not checked.

use crate::dim::Vector3;
use crate::fracture::growth3::{front_degree, NodeRecord, NodeStatus};
use crate::report::plot::{PlotSpec, Series};
use crate::report::surface3::{SurfacePanel, View};
use crate::verify::scene_file::SceneFile;
use crate::verify::{CaseOutput, Plot, Variant};
use std::collections::{BTreeMap, BTreeSet};
use std::time::Instant;

/// The crack surface at one time.
#[derive(Clone, Debug)]
pub struct Snapshot {
    pub time: f64,
    pub step: u64,
    pub triangles: Vec<[[f64; 3]; 3]>,
    pub front: Vec<[[f64; 3]; 2]>,
}

/// One step's front: time, total length of the front edges, front nodes, front edges.
#[derive(Clone, Copy, Debug)]
pub struct FrontState {
    pub time: f64,
    pub length: f64,
    pub nodes: usize,
    pub edges: usize,
    /// Mean position along the faces of the front's ends (degree-1 nodes), NaN without.
    pub ends: f64,
}

/// What one example run measured.
#[derive(Clone, Debug)]
pub struct ExampleRun {
    pub records: Vec<NodeRecord>,
    pub snapshots: Vec<Snapshot>,
    pub fronts: Vec<FrontState>,
    pub seconds: f64,
    pub peak_memory: Option<u64>,
    pub particles: usize,
    pub steps: u64,
    pub time: f64,
    pub end_time: f64,
    /// The error that stopped the run before its end time, if any.
    pub error: Option<String>,
    pub initial_vertices: usize,
    pub initial_triangles: usize,
    /// Crack-surface triangles (at the end) with a vertex made by growth, as triangles.
    pub grown: Vec<[Vector3; 3]>,
    pub vertices: usize,
    pub triangles: usize,
    pub front_edges: usize,
    pub splits: usize,
    pub merges: usize,
    pub pruned: usize,
    /// Moves refused for folding the new strip (retried) and nodes stopped within reach of
    /// the boundary (growth3 module doc, items 5–6).
    pub folded: usize,
    pub near_edge: usize,
    /// Front nodes taken off the front by the notch rule (growth3 module doc, item 7).
    pub filled: usize,
    /// Stopped nodes left as a front end on a free face that grew on (growth3 module doc,
    /// item 5, "ends at a face").
    pub handed: usize,
    /// New crack particles moved to clear a particle centre, and (particle, triangle) pairs
    /// left within half the clearance (advance3 module doc, "clearance").
    pub cleared: usize,
    pub unclear: usize,
    /// Largest distance outside the specimen of a crack particle made by growth, over all steps.
    pub max_outside: f64,
    /// Largest distance outside the material (the union of the particles' uGIMP cuboids,
    /// where they are at that step) of a crack particle made by growth, over all steps
    /// ([`outside_material`]).
    pub max_outside_material: f64,
    pub increment: f64,
}

/// Run an example scene (with overrides), recording the crack surface at `snapshot_every`
/// (time) and the front after every step; `outside(x)` is the distance of x outside the
/// specimen (0 inside); `along_face(x)` the position of a front end along its face.
pub fn run_example(
    file: &str,
    overrides: &[(&str, &str)],
    snapshot_every: f64,
    outside: impl Fn(&Vector3) -> f64,
    along_face: impl Fn(&Vector3) -> f64,
) -> anyhow::Result<ExampleRun> {
    let mut f = SceneFile::new(file);
    for (k, v) in overrides {
        f = f.set(k, v);
    }
    let s = f.load3()?;
    let increment = s.cracks[0].fracture.as_ref().and_then(|fr| fr.growth.as_ref()).map_or(0.5, |g| g.increment) * s.grid.cell.iter().fold(f64::INFINITY, |a, &b| a.min(b));
    let t0 = Instant::now();
    let mut sim = s.build()?;
    let initial_vertices = sim.cracks[0].surface.vertices.len();
    let initial_triangles = sim.cracks[0].surface.triangles.len();
    let snap = |sim: &crate::simulation::Simulation<crate::dim::D3>| {
        let c = &sim.cracks[0];
        let v = &c.surface.vertices;
        let p = |i: u32| -> [f64; 3] { v[i as usize].into() };
        Snapshot {
            time: sim.time,
            step: sim.step_count,
            triangles: c.surface.triangles.iter().map(|t| t.map(p)).collect(),
            front: c.front.iter().map(|e| e.map(p)).collect(),
        }
    };
    let mut snapshots = vec![snap(&sim)];
    let mut fronts = Vec::new();
    let mut max_outside: f64 = 0.0;
    let mut max_outside_material: f64 = 0.0;
    let mut next_snapshot = snapshot_every;
    let front_state = |sim: &crate::simulation::Simulation<crate::dim::D3>| {
        let c = &sim.cracks[0];
        let v = &c.surface.vertices;
        let length = c.front.iter().map(|&[a, b]| (v[a as usize] - v[b as usize]).norm()).sum::<f64>() + 0.0;
        let deg = front_degree(c);
        let ends: Vec<f64> = deg.iter().filter(|(_, &d)| d == 1).map(|(&k, _)| along_face(&v[k as usize])).collect();
        FrontState {
            time: sim.time,
            length,
            nodes: deg.len(),
            edges: c.front.len(),
            ends: if ends.is_empty() { f64::NAN } else { ends.iter().sum::<f64>() / ends.len() as f64 },
        }
    };
    fronts.push(front_state(&sim));
    let result = sim.run_until(s.solver.end_time, |sim| {
        fronts.push(front_state(sim));
        let v = &sim.cracks[0].surface.vertices;
        let grown = &v[initial_vertices.min(v.len())..];
        for x in grown {
            max_outside = max_outside.max(outside(x));
        }
        let h = crate::dim::GridGeometry::min_h(&sim.grid);
        max_outside_material = max_outside_material.max(outside_material(&sim.particles.x, &sim.particles.lp, grown, h));
        if sim.time >= next_snapshot - 1e-9 * snapshot_every {
            snapshots.push(snap(sim));
            next_snapshot += snapshot_every;
        }
    });
    let seconds = t0.elapsed().as_secs_f64();
    let error = result.err().map(|e| e.to_string());
    if snapshots.last().map(|x| x.step) != Some(sim.step_count) {
        snapshots.push(snap(&sim));
    }
    let g = sim.growth.as_ref().ok_or_else(|| anyhow::anyhow!("{file}: the crack does not grow"))?;
    let c = &sim.cracks[0];
    let v = &c.surface.vertices;
    let grown = c.surface.triangles.iter().filter(|t| t.iter().any(|&i| i as usize >= initial_vertices)).map(|t| t.map(|i| v[i as usize])).collect();
    Ok(ExampleRun {
        records: g.records.clone(),
        snapshots,
        fronts,
        seconds,
        peak_memory: crate::fea::run3::peak_memory_bytes(),
        particles: sim.particles.len(),
        steps: sim.step_count,
        time: sim.time,
        end_time: s.solver.end_time,
        error,
        initial_vertices,
        initial_triangles,
        grown,
        vertices: v.len(),
        triangles: c.surface.triangles.len(),
        front_edges: c.front.len(),
        splits: g.cracks[0].splits,
        merges: g.cracks[0].merges,
        pruned: g.cracks[0].pruned,
        folded: g.cracks[0].folded,
        near_edge: g.cracks[0].near_edge,
        filled: g.cracks[0].filled,
        handed: g.cracks[0].handed,
        cleared: g.cracks[0].cleared,
        unclear: g.cracks[0].unclear,
        max_outside,
        max_outside_material,
        increment,
    })
}

/// The largest distance from one of `points` to the material: the union of the particles'
/// cuboids (centre `x`, half-widths `lp`: the particle domains of uGIMP) — 0 for a point
/// in a particle's cuboid, `h` (the cap) for one with no particle within a cell. The
/// material where it is at that step, so a crack particle carried with a wall that has
/// moved counts as inside it.
pub fn outside_material(x: &[Vector3], lp: &[Vector3], points: &[Vector3], h: f64) -> f64 {
    if points.is_empty() {
        return 0.0;
    }
    let (lo, hi) = points.iter().fold((Vector3::repeat(f64::INFINITY), Vector3::repeat(f64::NEG_INFINITY)), |(l, u), p| (l.inf(p), u.sup(p)));
    let pad = Vector3::repeat(2.0 * h);
    let (lo, hi) = (lo - pad, hi + pad);
    let cell = |p: &Vector3| ((p.x / h).floor() as i64, (p.y / h).floor() as i64, (p.z / h).floor() as i64);
    let mut buckets: std::collections::HashMap<(i64, i64, i64), Vec<u32>> = std::collections::HashMap::new();
    for (i, p) in x.iter().enumerate() {
        if (0..3).all(|a| p[a] >= lo[a] && p[a] <= hi[a]) {
            buckets.entry(cell(p)).or_default().push(i as u32);
        }
    }
    let mut worst: f64 = 0.0;
    for q in points {
        let (cx, cy, cz) = cell(q);
        let mut best = h;
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    for &i in buckets.get(&(cx + dx, cy + dy, cz + dz)).map_or(&[][..], |v| &v[..]) {
                        let (c, l) = (x[i as usize], lp[i as usize]);
                        let d = Vector3::new(((q.x - c.x).abs() - l.x).max(0.0), ((q.y - c.y).abs() - l.y).max(0.0), ((q.z - c.z).abs() - l.z).max(0.0));
                        best = best.min(d.norm());
                    }
                }
            }
        }
        worst = worst.max(best);
    }
    worst
}

/// Median of the values (NaN when empty).
pub fn median(mut v: Vec<f64>) -> f64 {
    v.retain(|x| x.is_finite());
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

/// Mixity figures of a run.
#[derive(Clone, Debug, Default)]
pub struct Mixity {
    /// The first check at which a node grew.
    pub onset_step: u64,
    pub onset_time: f64,
    /// Median |K_II|/K_I over the front at that check.
    pub onset: f64,
    /// Median |K_II|/K_I over all rows of nodes that have advanced at least `late_after`
    /// increments.
    pub late: f64,
    pub late_rows: usize,
    /// Per check: (time, median |K_II|/K_I over the front).
    pub curve: Vec<(f64, f64)>,
}

/// |K_II|/K_I at the onset check and late in the growth (nodes advanced by at least
/// `late_after` increments of length `da`).
pub fn mixity(records: &[NodeRecord], da: f64, late_after: f64) -> Mixity {
    let ratio = |r: &NodeRecord| if r.k[0] > 0.0 { r.k[1].abs() / r.k[0] } else { f64::NAN };
    let mut by_step: BTreeMap<u64, Vec<&NodeRecord>> = BTreeMap::new();
    for r in records {
        by_step.entry(r.step).or_default().push(r);
    }
    let mut m = Mixity { onset: f64::NAN, late: f64::NAN, onset_time: f64::NAN, ..Default::default() };
    for (step, rows) in &by_step {
        let med = median(rows.iter().map(|r| ratio(r)).collect());
        if med.is_finite() {
            m.curve.push((rows[0].time, med));
        }
        if m.onset.is_nan() && rows.iter().any(|r| r.grew) {
            m.onset_step = *step;
            m.onset_time = rows[0].time;
            m.onset = med;
        }
    }
    let late: Vec<f64> = records.iter().filter(|r| r.advance >= late_after * da - 1e-9 * da && r.step > m.onset_step).map(ratio).collect();
    m.late_rows = late.iter().filter(|x| x.is_finite()).count();
    m.late = median(late);
    m
}

/// The last check's front nodes with their angles round an axis (degrees, `angle(x)` in
/// (−180°, 180°]) unwrapped continuously from the first check: each row's angle is taken
/// within 180° of the unwrapped angle the same node (same `label`) had at the previous
/// check, or, for a node new at this check (a split point), of that of the previous
/// check's node nearest to it. A branch running round a tube then keeps counting past
/// 180° (case `tube_crack`: its two ends run in opposite senses from the crack's middle,
/// so a node's branch is the sign of its unwrapped angle). Between two checks a node moves
/// at most a few increments (one half cell each, about 1.3° round the tube), so the
/// unwrapping is unambiguous; a split point lies on an edge of its own branch, within
/// one edge length of the nearest previous node, while the other branch is 4 or more
/// cells away in z where the two pass each other. Returns (index into `records`,
/// unwrapped angle).
pub fn unwrapped_angles(records: &[NodeRecord], angle: impl Fn(&Vector3) -> f64) -> Vec<(usize, f64)> {
    let all = unwrapped_angles_all(records, angle);
    let last = all.iter().map(|&(i, _)| records[i].step).max();
    all.into_iter().filter(|&(i, _)| Some(records[i].step) == last).collect()
}

/// [`unwrapped_angles`] for the front nodes of every check, in the order of `records`'
/// checks.
pub fn unwrapped_angles_all(records: &[NodeRecord], angle: impl Fn(&Vector3) -> f64) -> Vec<(usize, f64)> {
    let wrap = |d: f64| d - 360.0 * (d / 360.0).round();
    let mut by_step: BTreeMap<u64, Vec<usize>> = BTreeMap::new();
    for (i, r) in records.iter().enumerate() {
        by_step.entry(r.step).or_default().push(i);
    }
    let mut prev: Vec<(usize, f64)> = Vec::new();
    let mut all = Vec::with_capacity(records.len());
    for rows in by_step.values() {
        let mut cur = Vec::with_capacity(rows.len());
        for &i in rows {
            let r = &records[i];
            let base = prev.iter().find(|&&(j, _)| records[j].label == r.label).or_else(|| {
                prev.iter().min_by(|a, b| (records[a.0].x - r.x).norm().total_cmp(&(records[b.0].x - r.x).norm()))
            });
            let a = angle(&r.x);
            cur.push((i, match base {
                Some(&(_, b)) => b + wrap(a - b),
                None => a,
            }));
        }
        all.extend(cur.iter().copied());
        prev = cur;
    }
    all
}

/// A branch's end (case `tube_crack`): the front nodes of the branch (the sign `sign` of
/// the unwrapped angle) at the last check at which it had any — a branch whose front has
/// all been stopped and pruned keeps where it was last seen — with their travel |angle|.
/// Empty if the branch never had a node.
pub fn branch_end(records: &[NodeRecord], all: &[(usize, f64)], sign: f64) -> Vec<(usize, f64)> {
    let mine: Vec<(usize, f64)> = all.iter().copied().filter(|&(_, a)| a * sign > 0.0).collect();
    let last = mine.iter().map(|&(i, _)| records[i].step).max();
    mine.into_iter().filter(|&(i, _)| Some(records[i].step) == last).map(|(i, a)| (i, a * sign)).collect()
}

/// Area-weighted mean unit normal of triangles (each turned into the hemisphere of `axis`)
/// and its angle to `axis` in degrees; NaN without area.
pub fn mean_tilt(tris: &[[Vector3; 3]], axis: Vector3) -> f64 {
    let mut sum = Vector3::zeros();
    for t in tris {
        let n = (t[1] - t[0]).cross(&(t[2] - t[0]));
        sum += if n.dot(&axis) < 0.0 { -n } else { n };
    }
    match sum.try_normalize(1e-300) {
        Some(n) => n.dot(&axis.normalize()).clamp(-1.0, 1.0).acos().to_degrees(),
        None => f64::NAN,
    }
}

fn box_edges(lo: [f64; 3], hi: [f64; 3]) -> Vec<[[f64; 3]; 2]> {
    let c = |i: usize| [if i & 1 == 0 { lo[0] } else { hi[0] }, if i & 2 == 0 { lo[1] } else { hi[1] }, if i & 4 == 0 { lo[2] } else { hi[2] }];
    let mut out = Vec::new();
    for i in 0..8 {
        for b in [1, 2, 4] {
            if i & b == 0 {
                out.push([c(i), c(i | b)]);
            }
        }
    }
    out
}

fn mb(bytes: Option<u64>) -> String {
    bytes.map_or("unknown".into(), |b| format!("{:.0} MB", b as f64 / 1e6))
}

/// Pick about `n` snapshots spread over the run (always the first and the last).
/// Six snapshots spread over the run as picture panels with the scene's `edges` in grey,
/// captioned with the time (and the step, when `with_step`).
fn surface_panels(snapshots: &[Snapshot], edges: &[[[f64; 3]; 2]], with_step: bool) -> Vec<SurfacePanel> {
    spread(snapshots, 6)
        .into_iter()
        .map(|s| SurfacePanel {
            caption: if with_step { format!("t = {:.1} µs, step {}", s.time * 1e3, s.step) } else { format!("t = {:.1} µs", s.time * 1e3) },
            triangles: s.triangles,
            edges: edges.to_vec(),
            front: s.front,
        })
        .collect()
}

fn spread<T: Clone>(v: &[T], n: usize) -> Vec<T> {
    if v.len() <= n {
        return v.to_vec();
    }
    let mut idx: BTreeSet<usize> = (0..n).map(|k| (k * (v.len() - 1) + (n - 1) / 2) / (n - 1)).collect();
    idx.insert(0);
    idx.insert(v.len() - 1);
    idx.into_iter().map(|k| v[k].clone()).collect()
}

/// Case `corner_crack_rod` (full suite only).
pub fn run_rod(_variant: Variant) -> anyhow::Result<CaseOutput> {
    let (lo, hi) = (Vector3::new(0.0, 0.0, -50.0), Vector3::new(50.0, 50.0, 50.0));
    let outside = move |x: &Vector3| (0..3).map(|a| (lo[a] - x[a]).max(x[a] - hi[a])).fold(0.0, f64::max);
    // A front end on the face y = 0 is at x along it, on x = 0 at y: its distance from
    // the rod's edge x = y = 0 along the face.
    let along = |x: &Vector3| if x.y.abs() < x.x.abs() { x.x } else { x.y };
    let r = run_example("corner_crack_rod_3d.toml", &[], 0.005, outside, along)?;
    let da = r.increment;
    let mut out = CaseOutput::default();
    let completed = r.error.is_none();
    out.measure("completes", "h = 2 mm", if completed { 1.0 } else { 0.0 }, 1.0);
    // Mixed mode to mode I.
    let m = mixity(&r.records, da, 3.0);
    out.measure("mixity_falls", "h = 2 mm", m.late / m.onset, 0.0);
    let tilt = mean_tilt(&r.grown, Vector3::z());
    out.measure("surface_turns", "h = 2 mm", tilt, 0.0);
    // Front length.
    let l0 = r.fronts[0].length;
    let (imax, lmax) = r.fronts.iter().enumerate().fold((0, f64::NEG_INFINITY), |(bi, bl), (i, f)| if f.length > bl { (i, f.length) } else { (bi, bl) });
    let fmax = r.fronts[imax];
    let lend = r.fronts.last().map_or(f64::NAN, |f| f.length);
    out.measure("front_grows", "h = 2 mm", lmax / l0, 1.0);
    out.measure("front_shrinks", "h = 2 mm", lend / lmax, 1.0);
    out.measure("peak_at_diagonal", "h = 2 mm", fmax.ends, 50.0);
    out.measure("inside", "h = 2 mm", r.max_outside_material, 0.0);
    out.measure("front_left", "h = 2 mm", r.front_edges as f64, 0.0);
    // Orientation: the onset check's node nearest the plane x = y (the point of pure I + II).
    let onset_rows: Vec<&NodeRecord> = r.records.iter().filter(|x| x.step == m.onset_step).collect();
    let mid = onset_rows.iter().min_by(|a, b| (a.x.x - a.x.y).abs().total_cmp(&(b.x.x - b.x.y).abs()));
    let nu = 0.298;
    let gamma = (1.0f64 / (1.0 + 2.0 / 3.0f64).sqrt()).acos();
    let closed = 2.0 * gamma.tan() / (2.0 - nu);
    let closed_kink = {
        // Maximum hoop stress for K_II/K_I = closed: θ = 2 atan((1 − √(1 + 8 r²))/(4 r)).
        let q = closed;
        (2.0 * ((1.0 - (1.0 + 8.0 * q * q).sqrt()) / (4.0 * q)).atan()).to_degrees()
    };
    let statuses: BTreeMap<&str, usize> = {
        let last_step = r.records.last().map_or(0, |x| x.step);
        let mut s = BTreeMap::new();
        for x in r.records.iter().filter(|x| x.step == last_step) {
            *s.entry(x.status.label()).or_insert(0) += 1;
        }
        s
    };
    let moves = r.records.iter().filter(|x| x.grew).count();
    let max_nodes = r.fronts.iter().map(|f| f.nodes).max().unwrap_or(0);
    out.note(format!(
        "Run: {} particles, {} steps to t = {:.4} ms of {:.4} ms in {:.0} s (peak resident memory of the process {}){}. \
         Growth from t = {:.4} ms (check at step {}): {} node moves; front nodes {} at the start, at most {}, {} at the end \
         ({} front edges; {} splits, {} merges, {} edges pruned at the boundary, {} nodes stopped within reach of it, {} moves \
         refused for folding the new strip and retried, {} nodes at the apex of a tongue of material filled, {} stopped nodes left as a front end on a free face that grew on, {} new crack particles moved to clear a particle centre ({} particle–triangle pairs left within half the clearance); node status at the last check {:?}). \
         Crack surface {} → {} triangles, {} → {} crack particles.",
        r.particles,
        r.steps,
        r.time,
        r.end_time,
        r.seconds,
        mb(r.peak_memory),
        r.error.as_ref().map_or(String::new(), |e| format!("; **stopped by an error**: {e}")),
        m.onset_time,
        m.onset_step,
        moves,
        r.fronts[0].nodes,
        max_nodes,
        r.fronts.last().map_or(0, |f| f.nodes),
        r.front_edges,
        r.splits,
        r.merges,
        r.pruned,
        r.near_edge,
        r.folded,
        r.filled,
        r.handed,
        r.cleared,
        r.unclear,
        statuses,
        r.initial_triangles,
        r.triangles,
        r.initial_vertices,
        r.vertices
    ));
    out.note(format!(
        "Mixity: median |K_II|/K_I over the front {:.3} at the onset check, {:.3} over the {} rows of nodes advanced ≥ 3 increments (ratio {:.3}). \
         Grown surface: area-weighted mean normal at {:.1}° from the load axis (the initial plane: 39.23°). \
         Front length {:.2} mm at the start, largest {:.2} mm at t = {:.4} ms (front ends then {:.2} mm along their faces from the rod's edge; \
         the section's diagonal ends at 50 mm), {:.2} mm at the end. Largest distance of a grown crack particle outside the rod's undeformed faces {:.3e} mm (the check `inside` measures it from the material where it is: {:.3e} mm).",
        m.onset,
        m.late,
        m.late_rows,
        m.late / m.onset,
        tilt,
        l0,
        lmax,
        fmax.time,
        fmax.ends,
        lend,
        r.max_outside,
        r.max_outside_material
    ));
    if let Some(x) = mid {
        out.note(format!(
            "Orientation only (not checked): at the onset check the front node nearest the plane x = y, ({:.2}, {:.2}, {:.2}), has \
             K_I = {:.1}, K_II = {:.1}, K_III = {:.1} MPa√mm, |K_II|/K_I = {:.3} and kinks by {:.1}° (θ_c); an inclined penny in an infinite body \
             at γ = 39.23° (3d-references.md §2) has |K_II|/K_I = 2 tan γ/(2 − ν) = {:.3} and a maximum-hoop-stress kink of {:.1}° at its \
             point of pure I + II. The corner crack in the rod under a step wave is not that crack (finite body, free faces, dynamic \
             loading 1–2 µs after the wave's arrival), so the figures only place the measurement.",
            x.x.x,
            x.x.y,
            x.x.z,
            x.k[0],
            x.k[1],
            x.k[2],
            x.k[1].abs() / x.k[0],
            x.theta.to_degrees(),
            closed,
            closed_kink
        ));
    }
    // Pictures of the crack surface.
    let edges = box_edges([0.0, 0.0, -25.0], [50.0, 50.0, 25.0]);
    let panels = surface_panels(&r.snapshots, &edges, true);
    let view = View { azimuth: -60.0, elevation: 15.0, axis: [0.0, 0.0, 1.0], max_tilt: 45.0 };
    let mut spec = PlotSpec::new("Corner crack in the rod: crack surface (middle 50 mm of the rod; front in black)", "", "");
    spec.size = (1500, 900);
    out.figure(
        "corner_crack_rod_surfaces.png",
        "The crack surface at several times, seen from (cos −60°, sin −60°, tan 15°) (the face y = 0 in front), coloured by the tilt \
         of each triangle from the plane normal to the load (red 0°, blue ≥ 45°; the initial crack is at 39°), the front in black, \
         the middle 50 mm of the rod in grey.",
        spec,
        Plot::Surfaces { panels, view, columns: 3 },
    );
    let plan = surface_panels(&r.snapshots, &box_edges([0.0, 0.0, 0.0], [50.0, 50.0, 0.0]), false);
    let mut spec = PlotSpec::new("Corner crack in the rod: plan view (section 50 × 50 mm; front in black)", "", "");
    spec.size = (1500, 1100);
    out.figure(
        "corner_crack_rod_plan.png",
        "The same surfaces seen from above (+z): the front sweeping the square section from its corner at the lower left; the \
         diagonal x + y = 50 mm runs between the lower-right and upper-left corners.",
        spec,
        Plot::Surfaces { panels: plan, view: View { azimuth: -90.0, elevation: 90.0, axis: [0.0, 0.0, 1.0], max_tilt: 45.0 }, columns: 3 },
    );
    out.figure(
        "corner_crack_rod_mixity.png",
        "Median |K_II|/K_I over the front at every growth check.",
        PlotSpec::new("Corner crack: mixity along the front", "time (ms)", "median |K_II|/K_I"),
        Plot::Lines(vec![Series::line("median over the front", m.curve.clone())]),
    );
    out.figure(
        "corner_crack_rod_front.png",
        "Front length (sum of the front edges) and the number of front nodes after every step.",
        PlotSpec::new("Corner crack: front length and front nodes", "time (ms)", "length (mm) / nodes"),
        Plot::Lines(vec![
            Series::line("front length (mm)", r.fronts.iter().map(|f| (f.time, f.length)).collect()),
            Series::line("front nodes", r.fronts.iter().map(|f| (f.time, f.nodes as f64)).collect()),
        ]),
    );
    Ok(out)
}

/// Case `tube_crack` (full suite only).
pub fn run_tube(_variant: Variant) -> anyhow::Result<CaseOutput> {
    let outside = |x: &Vector3| {
        let rr = (x.x * x.x + x.y * x.y).sqrt();
        (rr - 50.0).max(40.0 - rr).max(x.z.abs() - 150.0).max(0.0)
    };
    // Angle round the tube from the crack's middle (−y), degrees.
    let angle = |x: &Vector3| x.x.atan2(-x.y).to_degrees();
    let r = run_example("tube_crack_3d.toml", &[], 0.025, outside, angle)?;
    let da = r.increment;
    let mut out = CaseOutput::default();
    out.measure("completes", "h = 2 mm", if r.error.is_none() { 1.0 } else { 0.0 }, 1.0);
    let m = mixity(&r.records, da, 3.0);
    out.measure("mixity_falls", "h = 2 mm", m.late / m.onset, 0.0);
    let tilt = mean_tilt(&r.grown, Vector3::z());
    out.measure("surface_turns", "h = 2 mm", tilt, 0.0);
    // Each end's travel round the tube and the axial offset of the two paths.
    // Branches by the sign of the angle unwrapped over the checks (cases.toml, runs_round).
    // Each branch at the last check at which it had front nodes (a branch whose whole
    // front was stopped and pruned is measured where it was last seen).
    let all = unwrapped_angles_all(&r.records, angle);
    let ends = [1.0, -1.0].map(|sign| branch_end(&r.records, &all, sign));
    let [plus, minus] = ends.map(|e| e.into_iter().map(|(i, a)| (&r.records[i], a)).collect::<Vec<(&NodeRecord, f64)>>());
    let travel = |v: &[(&NodeRecord, f64)]| v.iter().map(|x| x.1).reduce(f64::min).unwrap_or(f64::NAN);
    let (tp, tm) = (travel(&plus), travel(&minus));
    let last_seen = |v: &[(&NodeRecord, f64)]| v.first().map_or(f64::NAN, |x| x.0.time * 1e3);
    // NaN (a branch with no node at all) fails the check: f64::min would drop it.
    out.measure("runs_round", "h = 2 mm", if tp.is_nan() || tm.is_nan() { f64::NAN } else { tp.min(tm) }, 0.0);
    let zmean = |v: &[(&NodeRecord, f64)]| v.iter().map(|x| x.0.x.z).sum::<f64>() / v.len() as f64;
    let offset = (zmean(&plus) - zmean(&minus)).abs();
    out.measure("paths_offset", "h = 2 mm", offset, 0.0);
    out.measure("inside", "h = 2 mm", r.max_outside_material, 0.0);
    let refused = r.records.iter().filter(|x| x.status == NodeStatus::AtCrack).count();
    out.note(format!(
        "Run: {} particles, {} steps to t = {:.4} ms of {:.4} ms in {:.0} s (peak resident memory of the process {}){}. Growth from \
         t = {:.4} ms; front nodes {} at the start, at most {}, {} at the end; {} splits, {} merges, {} edges pruned; {} rows refused \
         at a crack; {} stopped nodes handed the front's end on a face; {} new crack particles moved to clear a particle centre ({} particle–triangle pairs left within half the clearance). Median |K_II|/K_I {:.3} at onset, {:.3} late; grown surface's mean normal {:.1}° from the axis (initial 45°). \
         Ends (branches by their angle unwrapped over the checks, each at the last check at which it had front nodes: t = {:.1} and {:.1} µs): the +x branch's least travel {:.1}°, the −x branch's {:.1}° round the tube from the crack's middle, mean z {:.2} and {:.2} mm. Largest distance of a grown crack particle outside the undeformed wall (r = 40, 50 mm) {:.3} mm (the check `inside` measures it from the material where it is).",
        r.particles,
        r.steps,
        r.time,
        r.end_time,
        r.seconds,
        mb(r.peak_memory),
        r.error.as_ref().map_or(String::new(), |e| format!("; **stopped by an error**: {e}")),
        m.onset_time,
        r.fronts[0].nodes,
        r.fronts.iter().map(|f| f.nodes).max().unwrap_or(0),
        r.fronts.last().map_or(0, |f| f.nodes),
        r.splits,
        r.merges,
        r.pruned,
        refused,
        r.handed,
        r.cleared,
        r.unclear,
        m.onset,
        m.late,
        tilt,
        last_seen(&plus),
        last_seen(&minus),
        tp,
        tm,
        if plus.is_empty() { f64::NAN } else { zmean(&plus) },
        if minus.is_empty() { f64::NAN } else { zmean(&minus) },
        r.max_outside,
    ));
    let edges: Vec<[[f64; 3]; 2]> = {
        let mut e = Vec::new();
        for (rad, z) in [(50.0, -25.0), (50.0, 25.0), (40.0, -25.0), (40.0, 25.0)] {
            for k in 0..48 {
                let (a, b) = (k as f64 * std::f64::consts::TAU / 48.0, (k + 1) as f64 * std::f64::consts::TAU / 48.0);
                e.push([[rad * a.cos(), rad * a.sin(), z], [rad * b.cos(), rad * b.sin(), z]]);
            }
        }
        e
    };
    let panels = surface_panels(&r.snapshots, &edges, true);
    let view = View { azimuth: -90.0, elevation: 10.0, axis: [0.0, 0.0, 1.0], max_tilt: 45.0 };
    let mut spec = PlotSpec::new("Tube: crack surface (tube rings at z = ±25 mm in grey; front in black)", "", "");
    spec.size = (1500, 900);
    out.figure(
        "tube_crack_surfaces.png",
        "The crack surface at several times, seen from −y (the crack's side), coloured by the tilt from the plane normal to the load \
         (red 0°, blue ≥ 45°; the initial crack is at 45°).",
        spec,
        Plot::Surfaces { panels, view, columns: 3 },
    );
    out.figure(
        "tube_crack_mixity.png",
        "Median |K_II|/K_I over the front at every growth check.",
        PlotSpec::new("Tube: mixity along the front", "time (ms)", "median |K_II|/K_I"),
        Plot::Lines(vec![Series::line("median over the front", m.curve.clone())]),
    );
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Distance to the union of particle cuboids: 0 inside one, the gap beyond a face or
    /// edge, the cap `h` with no particle within a cell.
    #[test]
    fn outside_material_measures_from_the_particle_cuboids() {
        let lp = [Vector3::repeat(0.5); 2];
        let x = [Vector3::new(0.5, 0.5, 0.5), Vector3::new(1.5, 0.5, 0.5)];
        let d = |p: Vector3| outside_material(&x, &lp, &[p], 2.0);
        assert_eq!(d(Vector3::new(1.9, 0.2, 0.9)), 0.0);
        assert!((d(Vector3::new(2.3, 0.5, 0.5)) - 0.3).abs() < 1e-12);
        assert!((d(Vector3::new(2.3, 1.4, 0.5)) - 0.5).abs() < 1e-12);
        assert_eq!(d(Vector3::new(9.0, 9.0, 9.0)), 2.0);
        // The largest over the points.
        assert!((outside_material(&x, &lp, &[Vector3::new(1.0, 0.5, 0.5), Vector3::new(-0.25, 0.5, 0.5)], 2.0) - 0.25).abs() < 1e-12);
    }
}
