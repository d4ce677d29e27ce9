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
                PointArray::Vector3(v) => drop(v.pop()),
                PointArray::Tensor3(v) => drop(v.pop()),
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
    let mut scene = Scene::from_toml(include_str!("../verification/crack_patch_full.toml"), "crack_patch_full").unwrap();
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
    let mut scene = Scene::from_toml(include_str!("../verification/crack_patch_full.toml"), "crack_patch_full").unwrap();
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

// ---------------------------------------------------------------------------
// 3D runs (issue 14)
// ---------------------------------------------------------------------------

/// The colliding-spheres scene, coarsened (cell 0.1: 560 particles) and shortened
/// (end time 0.2: 5 steps, 3 snapshots, 5 history rows).
fn run_spheres_3d(dir: &Path) {
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/verification/colliding_spheres_3d.toml")).unwrap();
    let mut scene = cramp::scene3d::Scene3::from_toml(&text, "spheres", None).unwrap();
    scene.grid.cell = [0.1; 3];
    scene.solver.end_time = 0.2;
    scene.output.history_interval = Some(0.05);
    scene.output.archive_interval = Some(0.1);
    cramp::output::three_d::run_scene_3d(&scene, &RunOptions { out_dir: Some(dir.to_path_buf()), ..Default::default() }).unwrap();
}

/// Rewrite one 3D snapshot of a run with `edit` applied to particle `id`'s position
/// and arrays (given as the particle's index in the file).
fn edit_snapshot_3d(path: &Path, edit: impl FnOnce(usize, &mut Vec<cramp::dim::Vector3>, &mut Vec<(String, PointArray)>)) {
    let mut s = vtk::read_points_3d(path).unwrap();
    let Some(PointArray::Scalar(ids)) = s.array("id") else { panic!("no id array") };
    let k = ids.iter().position(|&x| x == 17.0).unwrap();
    edit(k, &mut s.positions, &mut s.arrays);
    let data: Vec<(&str, vtk::PointData)> = s.arrays.iter().map(|(n, a)| (n.as_str(), a.as_point_data())).collect();
    vtk::write_points_3d(path, &s.title, &s.positions, &data).unwrap();
}

/// A value changed by one part in 1e9 (or by 1e-9 where it is 0).
fn nudge(x: f64) -> f64 {
    x + 1e-9 * x.abs().max(1.0)
}

/// The only field with violations of a comparison that has exactly one violation.
fn single_violation(c: &cramp::verify::compare::Comparison) -> &cramp::verify::compare::FieldDiff {
    assert_eq!(c.violations(), 1, "{}", c.render());
    c.fields.iter().find(|f| f.violations > 0).unwrap()
}

#[test]
fn three_d_runs_compare_in_every_component() {
    let root = scratch("3d");
    let (a, b) = (root.join("a"), root.join("b"));
    run_spheres_3d(&a);
    run_spheres_3d(&b);

    // Two runs of the same scene agree bit for bit, in every 3D component.
    let c = compare_runs(&a, &b, Tolerance::default()).unwrap();
    println!("{}", c.render());
    assert!(c.agree(), "{}", c.render());
    assert_eq!(c.snapshots, ["particles_00000.vtk", "particles_00001.vtk", "particles_00002.vtk"]);
    assert_eq!(c.history_rows, 5);
    let names: Vec<&str> = c.fields.iter().map(|f| f.field.as_str()).collect();
    for f in [
        "history.momentum_z",
        "particles.position.z",
        "particles.velocity.z",
        "particles.displacement.z",
        "particles.stress.xz",
        "particles.stress.yz",
        "particles.strain.xz",
        "particles.strain.yz",
    ] {
        assert!(names.contains(&f), "{f} missing from {names:?}");
    }
    // Every component of every particle of every snapshot is compared: 3 position, 3 × 2
    // vector and 6 × 2 tensor components and 2 scalars per particle, 10 history columns
    // (time, five energies, three momenta, and the boundary work).
    let particles: usize = c.particles;
    assert_eq!(c.compared() as usize, 3 * particles * (3 + 6 + 12 + 2) + 5 * 10);
    let (code, stdout, _) = cramp(&["compare", a.to_str().unwrap(), b.to_str().unwrap()]);
    assert_eq!(code, 0, "{stdout}");
    assert!(stdout.contains("particles.stress.xz\t"), "{stdout}");

    // One z coordinate moved: exactly one violation, in particles.position.z.
    let z = root.join("z");
    copy_dir(&b, &z);
    edit_snapshot_3d(&z.join("particles_00001.vtk"), |k, pos, _| pos[k].z = nudge(pos[k].z));
    let c = compare_runs(&z, &b, Tolerance::default()).unwrap();
    let f = single_violation(&c);
    assert_eq!(f.field, "particles.position.z");
    assert!(f.worst_at.starts_with("particles_00001.vtk particle id 17 "), "{}", f.worst_at);
    let (code, stdout, _) = cramp(&["compare", z.to_str().unwrap(), b.to_str().unwrap()]);
    assert_eq!(code, 1, "{stdout}");
    assert!(stdout.contains("worst violation of particles.position.z: particles_00001.vtk particle id 17"), "{stdout}");

    // One xz stress changed (both mirrored entries, so the tensor stays symmetric).
    let s = root.join("s");
    copy_dir(&b, &s);
    edit_snapshot_3d(&s.join("particles_00002.vtk"), |k, _, arrays| {
        let Some((_, PointArray::Tensor3(t))) = arrays.iter_mut().find(|(n, _)| n == "stress") else { panic!("no 3D stress") };
        t[k].xz = nudge(t[k].xz);
    });
    let c = compare_runs(&s, &b, Tolerance::default()).unwrap();
    let f = single_violation(&c);
    assert_eq!(f.field, "particles.stress.xz");
    assert!(f.worst_at.starts_with("particles_00002.vtk particle id 17 "), "{}", f.worst_at);

    // One momentum_z of the history changed.
    let h = root.join("h");
    copy_dir(&b, &h);
    let text = std::fs::read_to_string(h.join("history.csv")).unwrap();
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    let column = lines[0].split(',').position(|c| c == "momentum_z").unwrap();
    let mut cells: Vec<String> = lines[2].split(',').map(String::from).collect();
    cells[column] = format!("{:e}", nudge(cells[column].parse::<f64>().unwrap()));
    lines[2] = cells.join(",");
    std::fs::write(h.join("history.csv"), lines.join("\n") + "\n").unwrap();
    let c = compare_runs(&h, &b, Tolerance::default()).unwrap();
    let f = single_violation(&c);
    assert_eq!(f.field, "history.momentum_z");
    assert!(f.worst_at.starts_with("history.csv row 2 (t = "), "{}", f.worst_at);

    // A 2D run and a 3D run cannot be compared: their history columns differ.
    let d2 = root.join("d2");
    run_demo(&d2);
    let e = format!("{:#}", compare_runs(&d2, &b, Tolerance::default()).unwrap_err());
    assert!(e.contains("history.csv columns differ"), "{e}");

    // Without momentum_z the runs are declared 2D, and the 3D snapshots are refused as
    // malformed 2D files (the rule of docs/compare.md), not silently projected.
    for run in [&a, &b] {
        let text = std::fs::read_to_string(run.join("history.csv")).unwrap();
        let z = text.lines().next().unwrap().split(',').position(|c| c == "momentum_z").unwrap();
        let cut: Vec<String> = text.lines().map(|l| l.split(',').enumerate().filter(|(k, _)| *k != z).map(|(_, c)| c).collect::<Vec<_>>().join(",")).collect();
        std::fs::write(run.join("history.csv"), cut.join("\n") + "\n").unwrap();
    }
    let e = format!("{:#}", compare_runs(&a, &b, Tolerance::default()).unwrap_err());
    assert!(e.contains("particles_00000.vtk") && e.contains("expected an out-of-plane 0"), "{e}");
    let _ = std::fs::remove_dir_all(&root);
}
