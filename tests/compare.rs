//! `cramp compare`: identical runs agree bit for bit; a perturbed copy disagrees and the
//! report names the field, the file and the particle; structural mismatches (particle
//! sets, missing files, malformed CSV) are clear errors with exit status 2, never panics.

use cramp::output::vtk::{self, PointArray};
use cramp::output::{run_scene, RunOptions};
use cramp::scene::{Scene, DEFAULT_SCENE};
use cramp::verify::compare::{compare_runs, Tolerance};
use std::path::{Path, PathBuf};
use std::process::Command;

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("cramp-compare-test-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The demo scene, shortened: 3 snapshots, 11 history rows.
fn run_demo(dir: &Path) {
    let mut scene = Scene::from_toml(DEFAULT_SCENE, "demo").unwrap();
    scene.solver.end_time = 0.5;
    scene.output.archive_interval = Some(0.25);
    run_scene(
        &scene,
        &RunOptions { out_dir: Some(dir.to_path_buf()), progress: false, checked: Some(true), ..Default::default() },
    )
    .unwrap();
}

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let e = e.unwrap();
        std::fs::copy(e.path(), to.join(e.file_name())).unwrap();
    }
}

fn cramp(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_cramp")).args(args).output().unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// Rewrite one snapshot of a run with `edit` applied to its arrays.
fn edit_snapshot(path: &Path, edit: impl FnOnce(&mut Vec<cramp::dim::Vector>, &mut Vec<(String, PointArray)>)) {
    let mut s = vtk::read_points(path).unwrap();
    edit(&mut s.positions, &mut s.arrays);
    let data: Vec<(&str, vtk::PointData)> = s.arrays.iter().map(|(n, a)| (n.as_str(), a.as_point_data())).collect();
    vtk::write_points(path, &s.title, &s.positions, &data).unwrap();
}

#[test]
fn identical_runs_agree_and_a_perturbed_copy_disagrees_at_the_right_place() {
    let root = scratch("agree");
    let (a, b) = (root.join("a"), root.join("b"));
    run_demo(&a);
    run_demo(&b);
    let c = compare_runs(&a, &b, Tolerance::default()).unwrap();
    println!("{}", c.render());
    assert!(c.agree(), "two runs of the same scene differ:\n{}", c.render());
    assert_eq!(c.snapshots, ["particles_00000.vtk", "particles_00001.vtk", "particles_00002.vtk"]);
    assert!(
        c.fields.iter().any(|f| f.field == "particles.stress.xy")
            && c.fields.iter().any(|f| f.field == "history.kinetic")
    );
    let (code, stdout, _) = cramp(&["compare", a.to_str().unwrap(), b.to_str().unwrap()]);
    assert_eq!(code, 0, "{stdout}");
    assert!(stdout.contains("AGREE"), "{stdout}");

    // Perturb the x velocity of particle id 17 in the second snapshot by one part in 1e9.
    let p = root.join("p");
    copy_dir(&b, &p);
    edit_snapshot(&p.join("particles_00001.vtk"), |_, arrays| {
        let ids = match &arrays.iter().find(|(n, _)| n == "id").unwrap().1 {
            PointArray::Scalar(v) => v.clone(),
            _ => unreachable!(),
        };
        let k = ids.iter().position(|&x| x == 17.0).unwrap();
        if let Some((_, PointArray::Vector(v))) = arrays.iter_mut().find(|(n, _)| n == "velocity") {
            v[k].x *= 1.0 + 1e-9;
        }
    });
    let c = compare_runs(&p, &b, Tolerance::default()).unwrap();
    println!("{}", c.render());
    assert!(!c.agree());
    assert_eq!(c.violations(), 1);
    let f = c.fields.iter().find(|f| f.violations > 0).unwrap();
    assert_eq!(f.field, "particles.velocity.x");
    assert!(f.max_abs_at.starts_with("particles_00001.vtk particle id 17 "), "{}", f.max_abs_at);
    assert!((f.max_rel - 1e-9).abs() < 1e-12, "{}", f.max_rel);
    let (code, stdout, _) = cramp(&["compare", p.to_str().unwrap(), b.to_str().unwrap()]);
    assert_eq!(code, 1, "{stdout}");
    assert!(stdout.contains("DISAGREE: 1 of") && stdout.contains("particle id 17"), "{stdout}");
    // Within a relative tolerance of 1e-8 the copy agrees.
    let (code, stdout, _) = cramp(&["compare", p.to_str().unwrap(), b.to_str().unwrap(), "--rtol", "1e-8"]);
    assert_eq!(code, 0, "{stdout}");

    // A perturbed history value is located by row and time.
    let h = root.join("h");
    copy_dir(&b, &h);
    let text = std::fs::read_to_string(h.join("history.csv")).unwrap();
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    let mut cells: Vec<String> = lines[3].split(',').map(String::from).collect();
    cells[1] = format!("{:e}", cells[1].parse::<f64>().unwrap() + 1e-3);
    lines[3] = cells.join(",");
    std::fs::write(h.join("history.csv"), lines.join("\n") + "\n").unwrap();
    let c = compare_runs(&h, &b, Tolerance { rtol: 0.0, atol: 1e-6 }).unwrap();
    let f = c.fields.iter().find(|f| f.violations > 0).unwrap();
    assert_eq!(f.field, "history.kinetic");
    assert!(f.worst_at.starts_with("history.csv row 3 (t = "), "{}", f.worst_at);
    let _ = std::fs::remove_dir_all(&root);
}

#[test]
fn structural_mismatches_are_clear_errors() {
    let root = scratch("errors");
    let b = root.join("b");
    run_demo(&b);

    // A particle missing from one snapshot.
    let m = root.join("m");
    copy_dir(&b, &m);
    edit_snapshot(&m.join("particles_00002.vtk"), |pos, arrays| {
        pos.pop();
        for (_, a) in arrays.iter_mut() {
            match a {
                PointArray::Scalar(v) => drop(v.pop()),
                PointArray::Vector(v) => drop(v.pop()),
                PointArray::Tensor(v) => drop(v.pop()),
            }
        }
    });
    let e = format!("{:#}", compare_runs(&m, &b, Tolerance::default()).unwrap_err());
    assert!(e.contains("particles_00002.vtk: the particle sets differ") && e.contains("only in"), "{e}");
    let (code, _, stderr) = cramp(&["compare", m.to_str().unwrap(), b.to_str().unwrap()]);
    assert_eq!(code, 2, "{stderr}");
    assert!(stderr.contains("particle sets differ"), "{stderr}");

    // A missing snapshot file.
    let s = root.join("s");
    copy_dir(&b, &s);
    std::fs::remove_file(s.join("particles_00001.vtk")).unwrap();
    let e = format!("{:#}", compare_runs(&s, &b, Tolerance::default()).unwrap_err());
    assert!(e.contains("different VTK files") && e.contains("particles_00001.vtk"), "{e}");

    // A malformed history.csv names the file, line and column.
    let c = root.join("c");
    copy_dir(&b, &c);
    let text = std::fs::read_to_string(c.join("history.csv")).unwrap().replacen("e-", "x-", 1);
    std::fs::write(c.join("history.csv"), text).unwrap();
    let e = format!("{:#}", compare_runs(&c, &b, Tolerance::default()).unwrap_err());
    assert!(e.contains("history.csv line 3, column 'time'") && e.contains("is not a number"), "{e}");

    // A missing run directory.
    let e = format!("{:#}", compare_runs(&root.join("nope"), &b, Tolerance::default()).unwrap_err());
    assert!(e.contains("nope") && e.contains("does not exist"), "{e}");
    let (code, _, stderr) = cramp(&["compare", root.join("nope").to_str().unwrap(), b.to_str().unwrap()]);
    assert_eq!(code, 2, "{stderr}");
    let _ = std::fs::remove_dir_all(&root);
}

/// A cracked scene: the particle snapshots are compared, the crack polylines are listed
/// as not compared.
#[test]
fn crack_polylines_are_listed_not_compared() {
    let root = scratch("cracks");
    let mut scene = Scene::from_toml(cramp::verify::cases::crack_patch::FULL, "crack_patch_full").unwrap();
    scene.solver.end_time = 3.0;
    scene.output.archive_interval = Some(1.5);
    for d in ["a", "b"] {
        run_scene(
            &scene,
            &RunOptions { out_dir: Some(root.join(d)), progress: false, checked: Some(true), ..Default::default() },
        )
        .unwrap();
    }
    let c = compare_runs(&root.join("a"), &root.join("b"), Tolerance::default()).unwrap();
    assert!(c.agree(), "{}", c.render());
    assert_eq!(c.snapshots.len(), 3);
    assert_eq!(c.not_compared, ["cracks_00000.vtk", "cracks_00001.vtk", "cracks_00002.vtk"]);
    assert!(c.render().contains("not compared: 3 file(s)"));
    let _ = std::fs::remove_dir_all(&root);
}

#[test]
fn verify_rejects_unknown_cases_with_the_list() {
    let (code, stdout, stderr) = cramp(&[
        "verify",
        "--quick",
        "--out",
        std::env::temp_dir().join("cramp-verify-unknown").to_str().unwrap(),
        "no_such_case",
    ]);
    assert_ne!(code, 0, "{stdout}");
    assert!(stderr.contains("unknown verification case 'no_such_case'") && stderr.contains("fea_patch"), "{stderr}");
}

#[test]
fn verify_runs_a_case_and_writes_the_report() {
    let out = scratch("report");
    let (code, stdout, stderr) =
        cramp(&["verify", "--quick", "--out", out.to_str().unwrap(), "fea_patch", "fea_cantilever"]);
    assert_eq!(code, 0, "{stdout}\n{stderr}");
    assert!(stdout.contains("fea_cantilever") && stdout.contains("2 of 2 cases passed"), "{stdout}");
    let index = std::fs::read_to_string(out.join("index.md")).unwrap();
    assert!(index.contains("## fea_patch") && index.contains("fea_cantilever_convergence.png"));
    assert!(out.join("fea_cantilever_convergence.png").is_file());
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("results.json")).unwrap()).unwrap();
    assert_eq!(json["passed"], true);
    assert_eq!(json["cases"].as_array().unwrap().len(), 2);
    let _ = std::fs::remove_dir_all(&out);
}

/// A snapshot whose header announces more points than the file holds (`POINTS 1e12`, or
/// 10¹² written out) is an error naming the file and line, not an allocation of that
/// size; `cramp compare` exits 2.
#[test]
fn absurd_snapshot_sizes_are_errors_not_allocations() {
    let root = scratch("absurd");
    let b = root.join("b");
    run_demo(&b);
    for count in ["1e12", "1000000000000", "18446744073709551615", "-3"] {
        let a = root.join("a");
        let _ = std::fs::remove_dir_all(&a);
        copy_dir(&b, &a);
        let path = a.join("particles_00001.vtk");
        let text = std::fs::read_to_string(&path).unwrap();
        let header = text.lines().find(|l| l.starts_with("POINTS ")).unwrap().to_string();
        std::fs::write(&path, text.replacen(&header, &format!("POINTS {count} double"), 1)).unwrap();
        let e = format!("{:#}", compare_runs(&a, &b, Tolerance::default()).unwrap_err());
        assert!(e.contains("particles_00001.vtk") && e.contains("line 5"), "{count}: {e}");
        let (code, _, stderr) = cramp(&["compare", a.to_str().unwrap(), b.to_str().unwrap()]);
        assert_eq!(code, 2, "{count}: {stderr}");
    }
    let _ = std::fs::remove_dir_all(&root);
}

/// Text columns (cracks.csv `tip`) are compared as text: two runs of a scene computing J
/// agree, and a changed tip name is one violation located by row, time and tip.
#[test]
fn text_columns_compare_as_text() {
    let root = scratch("text");
    let mut scene = Scene::from_toml(cramp::verify::cases::crack_patch::FULL, "crack_patch_full").unwrap();
    scene.cracks[0].fracture = Some(toml::from_str("tips = \"end\"").unwrap());
    scene.solver.end_time = 1.0;
    for d in ["a", "b"] {
        run_scene(&scene, &RunOptions { out_dir: Some(root.join(d)), checked: Some(true), ..Default::default() })
            .unwrap();
    }
    let (a, b) = (root.join("a"), root.join("b"));
    let (code, stdout, stderr) = cramp(&["compare", a.to_str().unwrap(), b.to_str().unwrap()]);
    assert_eq!(code, 0, "{stdout}{stderr}");
    assert!(stdout.contains("cracks.tip\t") && stdout.contains("\ttext\t"), "{stdout}");
    let text = std::fs::read_to_string(a.join("cracks.csv")).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    let changed = lines[2].replacen(",end,", ",start,", 1);
    std::fs::write(a.join("cracks.csv"), text.replacen(lines[2], &changed, 1)).unwrap();
    let c = compare_runs(&a, &b, Tolerance { rtol: 1.0, atol: 1.0 }).unwrap();
    let f = c.fields.iter().find(|f| f.violations > 0).unwrap();
    assert_eq!((f.field.as_str(), f.violations, c.violations()), ("cracks.tip", 1, 1));
    assert!(
        f.worst_at.starts_with("cracks.csv row 2 (t = ")
            && f.worst_at.contains("tip = end")
            && f.worst_at.ends_with("(a = 'start', b = 'end')"),
        "{}",
        f.worst_at
    );
    let _ = std::fs::remove_dir_all(&root);
}
