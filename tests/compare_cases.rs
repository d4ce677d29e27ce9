//! `cramp compare` on the outputs of every scene the verification suite runs: each
//! verification/*.toml scene (2D and 3D; every case's scene is one of these files, issue 21),
//! shortened to a few steps with a row and a snapshot at most steps.
//!
//! Reference: equality. Two runs of the same scene are bit-identical (the solver's sums are
//! correctly rounded), so compare must report AGREE with zero tolerance over every file
//! the run wrote — history.csv, cracks.csv (whose `tip` column is text), growth.csv (`tip`,
//! `grew`, `status`, `j`), crack_paths.csv and the particle snapshots. A copy with exactly
//! one value changed must give exactly one violation, in that field. No tolerance is
//! involved.

use cramp::output::vtk::{self, PointArray};
use cramp::output::three_d::run_scene_3d;
use cramp::output::{run_scene, RunOptions};
use cramp::scene3d::AnyScene;
use cramp::verify::compare::{compare_runs, Tolerance};
use std::path::{Path, PathBuf};

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("cramp-compare-cases-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

/// Every scene of verification/ and those the quick cases build, by name.
fn scenes() -> Vec<(String, AnyScene)> {
    let mut out = Vec::new();
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("verification");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    for f in files {
        let name = f.file_stem().unwrap().to_string_lossy().into_owned();
        if name == "cases" {
            continue;
        }
        out.push((name, AnyScene::from_file(&f).unwrap()));
    }
    out
}

/// The scene cut to 6 steps, a history row every step and a snapshot every other step.
fn shortened(mut scene: AnyScene) -> AnyScene {
    let (dt, solver, output) = match &mut scene {
        AnyScene::D2(s) => (s.time_step(), &mut s.solver, &mut s.output),
        AnyScene::D3(s) => (s.time_step(), &mut s.solver, &mut s.output),
    };
    solver.end_time = 6.0 * dt;
    output.history_interval = Some(dt);
    output.archive_interval = Some(2.0 * dt);
    scene
}

fn run(scene: &AnyScene, dir: &Path) {
    let opts = RunOptions { out_dir: Some(dir.to_path_buf()), checked: Some(true), ..Default::default() };
    match scene {
        AnyScene::D2(s) => drop(run_scene(s, &opts).unwrap()),
        AnyScene::D3(s) => drop(run_scene_3d(s, &opts).unwrap()),
    }
}

/// The arrays of a snapshot as the writer takes them.
fn data(arrays: &[(String, PointArray)]) -> Vec<(&str, vtk::PointData<'_>)> {
    arrays.iter().map(|(n, a)| (n.as_str(), a.as_point_data())).collect()
}

/// The `stress` array of a snapshot, if any.
fn stress(arrays: &mut [(String, PointArray)]) -> Option<&mut PointArray> {
    arrays.iter_mut().find(|(n, _)| n == "stress").map(|(_, a)| a)
}

/// Change the middle particle's shear stress in a snapshot: xy in 2D, xz in 3D (a
/// component only a 3D file has). Returns the field compare must name.
fn perturb_stress(path: &Path, scene: &AnyScene) -> &'static str {
    match scene {
        AnyScene::D2(_) => {
            let mut s = vtk::read_points(path).unwrap();
            if let Some(PointArray::Tensor(t)) = stress(&mut s.arrays) {
                let k = t.len() / 2;
                t[k].xy = nudge(t[k].xy);
            }
            vtk::write_points(path, &s.title, &s.positions, &data(&s.arrays)).unwrap();
            "particles.stress.xy"
        }
        AnyScene::D3(_) => {
            let mut s = vtk::read_points_3d(path).unwrap();
            if let Some(PointArray::Tensor3(t)) = stress(&mut s.arrays) {
                let k = t.len() / 2;
                t[k].xz = nudge(t[k].xz);
            }
            vtk::write_points_3d(path, &s.title, &s.positions, &data(&s.arrays)).unwrap();
            "particles.stress.xz"
        }
    }
}

fn copy_dir(from: &Path, to: &Path) {
    let _ = std::fs::remove_dir_all(to);
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let e = e.unwrap();
        std::fs::copy(e.path(), to.join(e.file_name())).unwrap();
    }
}

/// Replace cell (row, column) of a CSV (row 0 is the header) and return the old cell.
fn edit_csv(path: &Path, row: usize, column: usize, edit: impl FnOnce(&str) -> String) -> String {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines: Vec<Vec<String>> = text.lines().map(|l| l.split(',').map(String::from).collect()).collect();
    let old = lines[row][column].clone();
    lines[row][column] = edit(&old);
    std::fs::write(path, lines.iter().map(|l| l.join(",")).collect::<Vec<_>>().join("\n") + "\n").unwrap();
    old
}

/// A different number that any tolerance of zero sees.
fn nudge(x: f64) -> f64 {
    if x == 0.0 {
        1e-300
    } else {
        x * (1.0 + 1e-12)
    }
}

/// Assert that comparing `p` (b with one change) against `b` finds exactly one violation, in `field`.
fn one_violation(p: &Path, b: &Path, field: &str, what: &str) {
    let c = compare_runs(p, b, Tolerance::default()).unwrap_or_else(|e| panic!("{what}: {e:#}"));
    let bad: Vec<&str> = c.fields.iter().filter(|f| f.violations > 0).map(|f| f.field.as_str()).collect();
    assert_eq!(c.violations(), 1, "{what}: {bad:?}\n{}", c.render());
    assert_eq!(bad, [field], "{what}\n{}", c.render());
}

#[test]
fn every_verification_scene_compares_equal_to_itself_and_finds_one_perturbed_value() {
    let (mut files_seen, mut perturbations) = (std::collections::BTreeSet::new(), 0);
    for (name, scene) in scenes() {
        let scene = shortened(scene);
        let root = scratch(&name);
        let (a, b, p) = (root.join("a"), root.join("b"), root.join("p"));
        run(&scene, &a);
        run(&scene, &b);
        let c = compare_runs(&a, &b, Tolerance::default()).unwrap_or_else(|e| panic!("{name}: {e:#}"));
        assert!(c.agree(), "{name}: two runs differ\n{}", c.render());
        assert!(c.history_rows >= 7 && !c.snapshots.is_empty(), "{name}\n{}", c.render());

        let mut names: Vec<String> =
            std::fs::read_dir(&b).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
        names.sort();
        for file in &names {
            files_seen.insert(if file.ends_with(".csv") {
                file.clone()
            } else {
                file.split('_').next().unwrap_or("").to_string()
            });
            if let Some(stem) = file.strip_suffix(".csv") {
                // The last numeric cell of the last row, and every text column once.
                let csv = cramp::verify::compare::read_csv(&b.join(file)).unwrap();
                let last = csv.rows.len();
                if last == 0 {
                    continue;
                }
                for (col, column) in csv.columns.iter().enumerate() {
                    let cell = &csv.rows[last - 1][col];
                    let is_text = csv.rows.iter().any(|r| r[col].parse::<f64>().is_err());
                    if !(is_text || col + 1 == csv.columns.len()) {
                        continue;
                    }
                    copy_dir(&b, &p);
                    edit_csv(&p.join(file), last, col, |old| {
                        if is_text {
                            format!("{old}x")
                        } else {
                            format!("{:e}", nudge(old.parse().unwrap()))
                        }
                    });
                    one_violation(
                        &p,
                        &b,
                        &format!("{stem}.{column}"),
                        &format!("{name}: {file} column {column} (was '{cell}')"),
                    );
                    perturbations += 1;
                }
            } else if Some(file) == names.iter().rfind(|f| f.starts_with("particles_")) {
                copy_dir(&b, &p);
                let field = perturb_stress(&p.join(file), &scene);
                one_violation(&p, &b, field, &format!("{name}: {file}"));
                perturbations += 1;
            }
        }
        let _ = std::fs::remove_dir_all(&root);
    }
    println!("{perturbations} single-value perturbations found, in files {files_seen:?}");
    for f in ["history.csv", "cracks.csv", "growth.csv", "crack_paths.csv"] {
        assert!(files_seen.contains(f), "no scene wrote {f}: {files_seen:?}");
    }
}
