//! `cramp compare RUN_A RUN_B`: compare two runs field by field — the history
//! (`history.csv`, rows matched by index, columns by name) and every particle snapshot
//! (`*.vtk`, files matched by name, particles by their `id` array) — and report, per
//! field, the largest absolute and relative difference and where it is.
//!
//! Other CSV files (`cracks.csv`, `growth.csv`, …) are compared like the history when
//! present, columns of numbers within the tolerance and text columns (`tip`, `status`)
//! for equality; crack polylines (`cracks_*.vtk`) are listed but not compared yet.
//!
//! 2D and 3D runs are compared alike. A run is 3D when its `history.csv` has a
//! `momentum_z` column (both runs must have the same columns, so the same dimension);
//! its snapshots are then read with [`vtk::read_points_3d`] and compared in x, y, z and
//! all six tensor components, a 2D run's with [`vtk::read_points`] (which rejects a
//! non-zero out-of-plane component).
//!
//! A value agrees when |a − b| ≤ atol + rtol·|b| (b from RUN_B, the reference run). With
//! the defaults rtol = atol = 0 that is equality: bit-identical up to the sign of zero.
//! NaN never agrees. The two runs must have the same structure (history columns and row
//! count, snapshot files, arrays, particle ids); otherwise [`compare_runs`] returns an
//! error naming what differs. `docs/compare.md` documents the files a code must write to
//! be compared.

use crate::output::vtk::{self, PointArray};
use anyhow::{bail, Context};
use serde::Serialize;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// The agreement criterion |a − b| ≤ atol + rtol·|b|.
#[derive(Clone, Copy, Debug, Default, Serialize)]
pub struct Tolerance {
    pub rtol: f64,
    pub atol: f64,
}

impl Tolerance {
    pub fn agrees(&self, a: f64, b: f64) -> bool {
        (a - b).abs() <= self.atol + self.rtol * b.abs()
    }
}

/// The largest differences of one field over every file and entry compared.
#[derive(Clone, Debug, Serialize)]
pub struct FieldDiff {
    /// `history.<column>` or `particles.<array>[.<component>]`.
    pub field: String,
    /// A text column (e.g. `cracks.tip`), compared for equality: max_abs and max_rel are
    /// not used, max_abs_at is the first differing row.
    pub text: bool,
    pub compared: u64,
    /// Values outside the tolerance.
    pub violations: u64,
    pub max_abs: f64,
    /// Where the largest absolute difference is (file and row/time or particle id), with
    /// the two values; empty if all values are equal.
    pub max_abs_at: String,
    /// Largest |a − b| / |b| (infinite where b = 0 ≠ a).
    pub max_rel: f64,
    pub max_rel_at: String,
    /// The worst violation: the largest |a − b| − (atol + rtol·|b|).
    pub worst_at: String,
    #[serde(skip)]
    worst_excess: f64,
}

impl FieldDiff {
    fn new(field: String) -> Self {
        FieldDiff {
            field,
            text: false,
            compared: 0,
            violations: 0,
            max_abs: 0.0,
            max_abs_at: String::new(),
            max_rel: 0.0,
            max_rel_at: String::new(),
            worst_at: String::new(),
            worst_excess: f64::NEG_INFINITY,
        }
    }

    fn add(&mut self, a: f64, b: f64, tol: &Tolerance, at: &dyn Fn() -> String) {
        self.compared += 1;
        let d = (a - b).abs();
        let d = if d.is_nan() && !(a == b) { f64::INFINITY } else { d };
        if d > self.max_abs {
            self.max_abs = d;
            self.max_abs_at = format!("{} (a = {a:e}, b = {b:e})", at());
        }
        let rel = if d == 0.0 { 0.0 } else { d / b.abs() };
        if rel > self.max_rel {
            self.max_rel = rel;
            self.max_rel_at = format!("{} (a = {a:e}, b = {b:e})", at());
        }
        if !tol.agrees(a, b) {
            self.violations += 1;
            let excess = d - (tol.atol + tol.rtol * b.abs());
            if excess > self.worst_excess || self.worst_at.is_empty() {
                self.worst_excess = excess;
                self.worst_at = format!("{} (a = {a:e}, b = {b:e})", at());
            }
        }
    }

    /// Compare two cells of a text column: equal or a violation (the first one is reported).
    fn add_text(&mut self, a: &str, b: &str, at: &dyn Fn() -> String) {
        self.text = true;
        self.compared += 1;
        if a != b {
            self.violations += 1;
            if self.worst_at.is_empty() {
                self.worst_at = format!("{} (a = '{a}', b = '{b}')", at());
                self.max_abs_at = self.worst_at.clone();
            }
        }
    }
}

/// The result of comparing two runs.
#[derive(Clone, Debug, Serialize)]
pub struct Comparison {
    pub run_a: PathBuf,
    pub run_b: PathBuf,
    pub tolerance: Tolerance,
    pub history_rows: usize,
    /// The CSV files compared (history.csv and e.g. cracks.csv).
    pub csv_files: Vec<String>,
    pub snapshots: Vec<String>,
    /// Files present in both runs but not compared (crack polylines `cracks_*.vtk`).
    pub not_compared: Vec<String>,
    pub particles: usize,
    pub fields: Vec<FieldDiff>,
}

impl Comparison {
    /// Whether every compared value agrees.
    pub fn agree(&self) -> bool {
        self.fields.iter().all(|f| f.violations == 0)
    }

    pub fn violations(&self) -> u64 {
        self.fields.iter().map(|f| f.violations).sum()
    }

    pub fn compared(&self) -> u64 {
        self.fields.iter().map(|f| f.compared).sum()
    }

    /// The report printed by `cramp compare` (format documented in docs/compare.md).
    pub fn render(&self) -> String {
        let mut s = format!(
            "compare {} (a) against {} (b, reference): agree when |a - b| <= atol + rtol*|b|, rtol = {:e}, atol = {:e}\n",
            self.run_a.display(),
            self.run_b.display(),
            self.tolerance.rtol,
            self.tolerance.atol
        );
        s += &format!(
            "history.csv: {} rows; snapshots: {} file(s){}; {} particles in the last\n",
            self.history_rows,
            self.snapshots.len(),
            if self.snapshots.is_empty() {
                String::new()
            } else {
                format!(" ({} … {})", self.snapshots[0], self.snapshots[self.snapshots.len() - 1])
            },
            self.particles
        );
        if self.csv_files.len() > 1 {
            s += &format!(
                "also compared: {}\n",
                self.csv_files.iter().filter(|f| *f != "history.csv").cloned().collect::<Vec<_>>().join(", ")
            );
        }
        if !self.not_compared.is_empty() {
            s += &format!("not compared: {} file(s) ({} …)\n", self.not_compared.len(), self.not_compared[0]);
        }
        s += "field\tcompared\tviolations\tmax_abs\tmax_abs_at\tmax_rel\tmax_rel_at\n";
        let or_dash = |s: &str| if s.is_empty() { "-".to_string() } else { s.to_string() };
        for f in &self.fields {
            let (max_abs, max_rel) = if f.text {
                ("text".to_string(), "-".to_string())
            } else {
                (format!("{:e}", f.max_abs), format!("{:e}", f.max_rel))
            };
            s += &format!(
                "{}\t{}\t{}\t{max_abs}\t{}\t{max_rel}\t{}\n",
                f.field,
                f.compared,
                f.violations,
                or_dash(&f.max_abs_at),
                or_dash(&f.max_rel_at)
            );
        }
        for f in self.fields.iter().filter(|f| f.violations > 0) {
            s += &format!("worst violation of {}: {}\n", f.field, f.worst_at);
        }
        if self.agree() {
            s += &format!("AGREE: all {} values within tolerance\n", self.compared());
        } else {
            s += &format!(
                "DISAGREE: {} of {} values outside tolerance in {} field(s)\n",
                self.violations(),
                self.compared(),
                self.fields.iter().filter(|f| f.violations > 0).count()
            );
        }
        s
    }
}

/// A CSV file of a run: column names and each row's cells as written (trimmed).
#[derive(Clone, Debug, PartialEq)]
pub struct Csv {
    pub columns: Vec<String>,
    pub rows: Vec<Vec<String>>,
    /// Line number in the file of each row (from 1; the header is line 1).
    pub lines: Vec<usize>,
}

/// Read a CSV with a header line, every row with one cell per column; errors name the
/// file and line. Cells are kept as text: [`compare_runs`] decides per column whether it
/// holds numbers or text.
pub fn read_csv(path: &Path) -> anyhow::Result<Csv> {
    let text = std::fs::read_to_string(path).with_context(|| format!("cannot read {}", path.display()))?;
    let mut lines = text.lines().enumerate().filter(|(_, l)| !l.trim().is_empty());
    let Some((_, header)) = lines.next() else { bail!("{} is empty (expected a header line)", path.display()) };
    let columns: Vec<String> = header.split(',').map(|c| c.trim().to_string()).collect();
    if columns.iter().any(|c| c.is_empty()) {
        bail!("{} line 1: empty column name in the header '{header}'", path.display());
    }
    let (mut rows, mut numbers) = (Vec::new(), Vec::new());
    for (i, line) in lines {
        let cells: Vec<String> = line.split(',').map(|c| c.trim().to_string()).collect();
        if cells.len() != columns.len() {
            bail!("{} line {}: {} values for {} columns", path.display(), i + 1, cells.len(), columns.len());
        }
        rows.push(cells);
        numbers.push(i + 1);
    }
    Ok(Csv { columns, rows, lines: numbers })
}

/// The numbers of column `c`, or an error naming the file, line and column of a cell
/// that is not one.
fn numbers(csv: &Csv, c: usize, path: &Path) -> anyhow::Result<Vec<f64>> {
    csv.rows
        .iter()
        .enumerate()
        .map(|(r, row)| {
            row[c].parse::<f64>().with_context(|| {
                format!(
                    "{} line {}, column '{}': '{}' is not a number",
                    path.display(),
                    csv.lines[r],
                    csv.columns[c],
                    row[c]
                )
            })
        })
        .collect()
}

/// Columns that identify a row in the report's locations, besides `time`.
const KEY_COLUMNS: [&str; 2] = ["crack", "tip"];

/// The files of a run directory ending in `suffix`, sorted by name.
fn files_ending(dir: &Path, suffix: &str) -> anyhow::Result<Vec<String>> {
    let mut names = Vec::new();
    for entry in std::fs::read_dir(dir).with_context(|| format!("cannot list {}", dir.display()))? {
        let name = entry?.file_name().to_string_lossy().into_owned();
        if name.ends_with(suffix) {
            names.push(name);
        }
    }
    names.sort();
    Ok(names)
}

/// Whether a `.vtk` file name is a particle snapshot (`particles*.vtk`).
fn is_particle_snapshot(name: &str) -> bool {
    name.starts_with("particles") && name.ends_with(".vtk")
}

/// The same set of names in both runs, or an error listing the differences.
fn same_files(what: &str, a: &[String], b: &[String], ra: &str, rb: &str) -> anyhow::Result<()> {
    if a != b {
        let only_a: Vec<_> = a.iter().filter(|f| !b.contains(f)).cloned().collect();
        let only_b: Vec<_> = b.iter().filter(|f| !a.contains(f)).cloned().collect();
        bail!(
            "the runs have different {what}: only in {ra}: [{}]; only in {rb}: [{}]",
            only_a.join(", "),
            only_b.join(", ")
        );
    }
    Ok(())
}

/// Value of a component at point i.
type Component<'a> = Box<dyn Fn(usize) -> f64 + 'a>;

/// The scalar components of an array: (suffix, value of point i).
fn components(array: &PointArray) -> Vec<(&'static str, Component<'_>)> {
    match array {
        PointArray::Scalar(v) => vec![("", Box::new(move |i| v[i]))],
        PointArray::Vector(v) => vec![(".x", Box::new(move |i| v[i].x)), (".y", Box::new(move |i| v[i].y))],
        PointArray::Tensor(v) => vec![
            (".xx", Box::new(move |i| v[i].xx)),
            (".yy", Box::new(move |i| v[i].yy)),
            (".zz", Box::new(move |i| v[i].zz)),
            (".xy", Box::new(move |i| v[i].xy)),
        ],
        PointArray::Vector3(v) => vec![
            (".x", Box::new(move |i| v[i].x)),
            (".y", Box::new(move |i| v[i].y)),
            (".z", Box::new(move |i| v[i].z)),
        ],
        PointArray::Tensor3(v) => vec![
            (".xx", Box::new(move |i| v[i].xx)),
            (".yy", Box::new(move |i| v[i].yy)),
            (".zz", Box::new(move |i| v[i].zz)),
            (".xy", Box::new(move |i| v[i].xy)),
            (".xz", Box::new(move |i| v[i].xz)),
            (".yz", Box::new(move |i| v[i].yz)),
        ],
    }
}

fn kind(a: &PointArray) -> &'static str {
    match a {
        PointArray::Scalar(_) => "scalar",
        PointArray::Vector(_) | PointArray::Vector3(_) => "vector",
        PointArray::Tensor(_) | PointArray::Tensor3(_) => "tensor",
    }
}

/// A particle snapshot read in the run's dimension: the positions (as a vector array)
/// and the named arrays.
struct Snapshot {
    positions: PointArray,
    arrays: Vec<(String, PointArray)>,
}

impl Snapshot {
    fn read(path: &Path, three_d: bool) -> anyhow::Result<Self> {
        Ok(if three_d {
            let s = vtk::read_points_3d(path)?;
            Snapshot { positions: PointArray::Vector3(s.positions), arrays: s.arrays }
        } else {
            let s = vtk::read_points(path)?;
            Snapshot { positions: PointArray::Vector(s.positions), arrays: s.arrays }
        })
    }

    fn array(&self, name: &str) -> Option<&PointArray> {
        self.arrays.iter().find(|(n, _)| n == name).map(|(_, a)| a)
    }
}

/// Particle ids of a snapshot (the `id` array, integers), with a clear error otherwise.
fn ids(s: &Snapshot, file: &str, run: &str) -> anyhow::Result<Vec<u64>> {
    let Some(PointArray::Scalar(id)) = s.array("id") else {
        bail!("{run}/{file} has no scalar array 'id': particles cannot be matched");
    };
    id.iter()
        .map(|&x| {
            if x >= 0.0 && x.fract() == 0.0 && x < 9.0e15 {
                Ok(x as u64)
            } else {
                bail!("{run}/{file}: particle id {x} is not a non-negative integer")
            }
        })
        .collect()
}

/// Compare two run directories; see the module doc.
pub fn compare_runs(run_a: &Path, run_b: &Path, tol: Tolerance) -> anyhow::Result<Comparison> {
    if !(tol.rtol >= 0.0 && tol.atol >= 0.0) {
        bail!("--rtol and --atol must be zero or positive (got rtol = {}, atol = {})", tol.rtol, tol.atol);
    }
    for d in [run_a, run_b] {
        if !d.is_dir() {
            bail!("run directory {} does not exist (or is not a directory)", d.display());
        }
    }
    let (ra, rb) = (run_a.display().to_string(), run_b.display().to_string());
    let mut fields: Vec<FieldDiff> = Vec::new();
    let field = |name: String, fields: &mut Vec<FieldDiff>| -> usize {
        match fields.iter().position(|f| f.field == name) {
            Some(k) => k,
            None => {
                fields.push(FieldDiff::new(name));
                fields.len() - 1
            }
        }
    };

    // history.csv (required) and any other CSV (e.g. cracks.csv), matched by name.
    let (ca, cb) = (files_ending(run_a, ".csv")?, files_ending(run_b, ".csv")?);
    same_files("CSV files", &ca, &cb, &ra, &rb)?;
    if !ca.iter().any(|f| f == "history.csv") {
        bail!("{ra} has no history.csv (is it a run directory?)");
    }
    let (mut history_rows, mut three_d) = (0, false);
    for file in &ca {
        let (ha, hb) = (read_csv(&run_a.join(file))?, read_csv(&run_b.join(file))?);
        if ha.columns != hb.columns {
            bail!("{file} columns differ: {ra} has [{}], {rb} has [{}]", ha.columns.join(","), hb.columns.join(","));
        }
        if ha.rows.len() != hb.rows.len() {
            bail!("{file} has {} rows in {ra} but {} in {rb}", ha.rows.len(), hb.rows.len());
        }
        if file == "history.csv" {
            history_rows = ha.rows.len();
            three_d = ha.columns.iter().any(|c| c == "momentum_z");
        }
        let stem = file.trim_end_matches(".csv");
        let (pa, pb) = (run_a.join(file), run_b.join(file));
        let time = match hb.columns.iter().position(|c| c == "time") {
            Some(t) => numbers(&hb, t, &pb)?,
            None => Vec::new(),
        };
        let keys: Vec<usize> = KEY_COLUMNS.iter().filter_map(|k| hb.columns.iter().position(|c| c == k)).collect();
        let at = |r: usize| {
            let mut what: Vec<String> = time.get(r).map(|t| format!("t = {t:e}")).into_iter().collect();
            what.extend(keys.iter().map(|&k| format!("{} = {}", hb.columns[k], hb.rows[r][k])));
            if what.is_empty() {
                format!("{file} row {}", r + 1)
            } else {
                format!("{file} row {} ({})", r + 1, what.join(", "))
            }
        };
        for (c, name) in ha.columns.iter().enumerate() {
            let k = field(format!("{stem}.{name}"), &mut fields);
            // A column of numbers in the reference run is compared as numbers; one with
            // text in it (cramp's `tip`, `grew`, `status`) as text, cell by cell.
            match numbers(&hb, c, &pb) {
                Ok(b) => {
                    let a = numbers(&ha, c, &pa)?;
                    for (r, (&a, &b)) in a.iter().zip(&b).enumerate() {
                        fields[k].add(a, b, &tol, &|| at(r));
                    }
                }
                Err(_) => {
                    for (r, (a, b)) in ha.rows.iter().zip(&hb.rows).enumerate() {
                        fields[k].add_text(&a[c], &b[c], &|| at(r));
                    }
                }
            }
        }
    }

    // Particle snapshots; other VTK files (crack polylines) are listed as not compared.
    let (va, vb) = (files_ending(run_a, ".vtk")?, files_ending(run_b, ".vtk")?);
    same_files("VTK files", &va, &vb, &ra, &rb)?;
    let (fa, not_compared): (Vec<String>, Vec<String>) = va.into_iter().partition(|f| is_particle_snapshot(f));
    let mut particles = 0;
    for file in &fa {
        let (sa, sb) = (Snapshot::read(&run_a.join(file), three_d)?, Snapshot::read(&run_b.join(file), three_d)?);
        let (ia, ib) = (ids(&sa, file, &ra)?, ids(&sb, file, &rb)?);
        let index_b: HashMap<u64, usize> = ib.iter().enumerate().map(|(i, &id)| (id, i)).collect();
        let set_a: std::collections::HashSet<u64> = ia.iter().copied().collect();
        if index_b.len() != ib.len() {
            bail!("{rb}/{file}: particle ids are not unique");
        }
        if set_a.len() != ia.len() {
            bail!("{ra}/{file}: particle ids are not unique");
        }
        let only_a: Vec<u64> = ia.iter().filter(|id| !index_b.contains_key(id)).copied().collect();
        if !only_a.is_empty() || ia.len() != ib.len() {
            let only_b: Vec<u64> = ib.iter().filter(|id| !set_a.contains(id)).copied().collect();
            let show = |v: &[u64]| {
                v.iter().take(5).map(|x| x.to_string()).collect::<Vec<_>>().join(", ")
                    + if v.len() > 5 { ", …" } else { "" }
            };
            bail!(
                "{file}: the particle sets differ: {} particles in {ra}, {} in {rb}; {} ids only in {ra} [{}], {} only in {rb} [{}]",
                ia.len(),
                ib.len(),
                only_a.len(),
                show(&only_a),
                only_b.len(),
                show(&only_b)
            );
        }
        particles = ia.len();
        let names_a: Vec<&str> = sa.arrays.iter().map(|(n, _)| n.as_str()).collect();
        let names_b: Vec<&str> = sb.arrays.iter().map(|(n, _)| n.as_str()).collect();
        let mut sorted_a = names_a.clone();
        let mut sorted_b = names_b.clone();
        sorted_a.sort_unstable();
        sorted_b.sort_unstable();
        if sorted_a != sorted_b {
            bail!("{file}: the arrays differ: {ra} has [{}], {rb} has [{}]", names_a.join(", "), names_b.join(", "));
        }
        let mut pairs: Vec<(&str, &PointArray, &PointArray)> = vec![("position", &sa.positions, &sb.positions)];
        for (name, a) in &sa.arrays {
            let b = sb.array(name).expect("same array names");
            if kind(a) != kind(b) {
                bail!("{file}: array '{name}' is a {} in {ra} but a {} in {rb}", kind(a), kind(b));
            }
            pairs.push((name, a, b));
        }
        for (name, a, b) in pairs {
            for ((suffix, ga), (_, gb)) in components(a).into_iter().zip(components(b)) {
                let k = field(format!("particles.{name}{suffix}"), &mut fields);
                for (i, &id) in ia.iter().enumerate() {
                    let j = index_b[&id];
                    fields[k].add(ga(i), gb(j), &tol, &|| format!("{file} particle id {id}"));
                }
            }
        }
    }
    Ok(Comparison {
        run_a: run_a.to_path_buf(),
        run_b: run_b.to_path_buf(),
        tolerance: tol,
        history_rows,
        csv_files: ca,
        snapshots: fa,
        not_compared,
        particles,
        fields,
    })
}
