//! `cramp run --set PATH=VALUE` and `cramp verify --export` through the binary (issue 21).
//!
//! Reference: the file itself. A run with overrides is the run of the file with those
//! fields changed (the same particle count and history as the library's reading of the
//! overridden file); a bad override is refused with exit status 1 and a message naming the
//! `--set` (and, for a value that fails validation, the field, with the file's message).
//! `cramp verify --export` writes one scene per simulation and `cramp run` accepts each.

use cramp::scene3d::AnyScene;
use cramp::scene_override::{scene_file_with, Override};
use std::path::{Path, PathBuf};
use std::process::Command;

fn cramp(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_cramp")).args(args).output().unwrap();
    (out.status.code().unwrap_or(-1), String::from_utf8_lossy(&out.stdout).into_owned(), String::from_utf8_lossy(&out.stderr).into_owned())
}

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("cramp-overrides-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

fn scene(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("verification").join(name).display().to_string()
}

#[test]
fn run_with_overrides_is_the_run_of_the_changed_file() {
    let out = scratch("bar");
    let sets = ["solver.end_time=0.5", "grid.cell=[0.5,0.5]", "solver.shape=linear"];
    let file = scene("vibrating_bar.toml");
    let mut args = vec!["run", file.as_str(), "--out", out.to_str().unwrap()];
    for s in &sets {
        args.extend(["--set", s]);
    }
    let (code, stdout, stderr) = cramp(&args);
    assert_eq!(code, 0, "{stderr}");
    let overrides: Vec<Override> = sets.iter().map(|s| Override::parse(s).unwrap()).collect();
    let AnyScene::D2(s) = scene_file_with(Path::new(&scene("vibrating_bar.toml")), &overrides).unwrap() else { panic!("2D") };
    assert_eq!(s.grid.cell, [0.5, 0.5]);
    let n = s.build().unwrap().particles.len();
    assert!(stdout.contains(&format!("{n} particles")), "{stdout}");
    // The history is the library's run of the same overridden scene, to the bit.
    let lib = scratch("bar-lib");
    cramp::output::run_scene(&s, &cramp::output::RunOptions { out_dir: Some(lib.clone()), ..Default::default() }).unwrap();
    assert_eq!(std::fs::read_to_string(out.join("history.csv")).unwrap(), std::fs::read_to_string(lib.join("history.csv")).unwrap());
    let _ = std::fs::remove_dir_all(&out);
    let _ = std::fs::remove_dir_all(&lib);
}

#[test]
fn bad_overrides_are_refused_naming_the_flag() {
    let bar = scene("vibrating_bar.toml");
    let bar3 = scene("vibrating_bar_3d.toml");
    let cases: &[(&str, &str, &[&str])] = &[
        (&bar, "nonsense", &["`--set nonsense`", "expected PATH=VALUE"]),
        (&bar, "boundary.7.vx=0", &["`--set boundary.7.vx=0`", "index 7 is out of range"]),
        (&bar, "grid.cell.x=1", &["`--set grid.cell.x=1`", "must be an index"]),
        (&bar, "cracks.0.contact=none", &["`--set cracks.0.contact=none`", "no `cracks` to index"]),
        (&bar, "solver.cfl=[1, 2]", &["`--set solver.cfl=[1, 2]`", "invalid type"]),
        (&bar, "solver.speed=2", &["`--set solver.speed=2`", "unknown field `speed`"]),
        (&bar, "materials.0.nu=0.5", &["scene field `materials[0].nu`", "Poisson", "(set by `--set materials.0.nu=0.5`)"]),
        (&bar, "grid.cell=[-1.0, 1.0]", &["scene field `grid.cell[0]`", "(set by `--set grid.cell=[-1.0, 1.0]`)"]),
        // A 3D scene whose grid.cell is made 2D: the file's error (3-component vectors in a
        // 2D scene), naming the overrides the scene was read with.
        (&bar3, "grid.cell=[1.0, 1.0]", &["has 3 components", "grid.cell has 2 components", "(the scene read with `--set grid.cell=[1.0, 1.0]`)"]),
    ];
    for (file, set, expect) in cases {
        let out = scratch("bad");
        let (code, _, stderr) = cramp(&["run", file, "--set", set, "--out", out.to_str().unwrap()]);
        assert_eq!(code, 1, "--set {set}: {stderr}");
        for e in *expect {
            assert!(stderr.contains(e), "--set {set}: expected {e:?} in {stderr}");
        }
        assert!(!out.join("history.csv").exists(), "--set {set}: nothing may run");
    }
}

#[test]
fn exported_scenes_run() {
    let dir = scratch("export");
    let (code, stdout, stderr) = cramp(&["verify", "--quick", "--export", dir.to_str().unwrap(), "crack_friction"]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.contains("3 scene file(s)"), "{stdout}");
    let index = std::fs::read_to_string(dir.join("index.csv")).unwrap();
    let files: Vec<&str> = index.lines().skip(1).map(|l| l.split(',').nth(2).unwrap()).collect();
    assert_eq!(files.len(), 3, "{index}");
    for f in files {
        assert!(f.starts_with("crack_friction/") && f.contains("crack_friction__"), "{f}");
        let text = std::fs::read_to_string(dir.join(f)).unwrap();
        assert!(text.contains("# verification/crack_friction.toml") && text.contains("--set 'cracks.0.contact="), "{text}");
        let out = dir.join(format!("{f}.out"));
        let (code, _, stderr) = cramp(&["run", dir.join(f).to_str().unwrap(), "--out", out.to_str().unwrap()]);
        assert_eq!(code, 0, "{f}: {stderr}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
