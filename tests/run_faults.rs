//! A run keeps its results when it fails, is interrupted or killed, and never mixes its
//! files with an earlier run's (issue 19).
//!
//! Reference: the output contract of src/output/mod.rs — history.csv (and cracks.csv,
//! growth.csv) hold one complete row per history time up to the last completed step;
//! summary.json says `completed`, `failed` (with the error) or `interrupted`, with the last
//! step and its time; snapshots are complete files or absent; a directory holding an
//! earlier run's files is refused unless --force. Exact checks, no tolerance.

use cramp::output::vtk;
use cramp::output::{run_scene, RunOptions, RunStatus};
use cramp::scene::Scene;
use cramp::verify::compare::{compare_runs, read_csv, Tolerance};
use std::path::{Path, PathBuf};
use std::process::{Child, Command};
use std::sync::atomic::AtomicBool;
use std::sync::Arc;
use std::time::{Duration, Instant};

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("cramp-run-faults-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A block flying at the grid's right edge: the always-on check stops it with "outside
/// the grid" at a step fixed by the speed; a history row and a snapshot every step.
const FLYING: &str = r#"
title = "a block leaving the grid"
[grid]
origin = [0.0, 0.0]
size = [1.0, 1.0]
cell = [0.1, 0.1]
[solver]
dt = 1e-3
end_time = 1.0
[output]
history_interval = 1e-3
archive_interval = 1e-3
[[materials]]
name = "m"
E = 1000.0
nu = 0.3
rho = 1.0
state = "plane_strain"
[[bodies]]
material = "m"
shape = { rectangle = { min = [0.5, 0.4], max = [0.7, 0.6] } }
velocity = [10.0, 0.0]
"#;

fn summary(dir: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap()
}

/// Every file of a run directory is complete: every CSV row parses, every snapshot reads.
fn assert_consistent(dir: &Path) -> usize {
    let history = read_csv(&dir.join("history.csv")).unwrap();
    for (r, row) in history.rows.iter().enumerate() {
        for cell in row {
            cell.parse::<f64>().unwrap_or_else(|_| panic!("history.csv row {}: '{cell}'", r + 1));
        }
    }
    for e in std::fs::read_dir(dir).unwrap() {
        let name = e.unwrap().file_name().to_string_lossy().into_owned();
        if name.starts_with("particles_") && name.ends_with(".vtk") {
            vtk::read_points(dir.join(&name)).unwrap_or_else(|e| panic!("{name}: {e:#}"));
        }
    }
    history.rows.len()
}

#[test]
fn an_error_at_step_n_leaves_the_history_up_to_n_and_a_summary_saying_so() {
    let dir = scratch("failed");
    let out = dir.join("out");
    let scene = Scene::from_toml(FLYING, "flying").unwrap();
    let e = format!(
        "{:#}",
        run_scene(&scene, &RunOptions { out_dir: Some(out.clone()), ..Default::default() }).unwrap_err()
    );
    // "… step N: particle … is outside the grid"
    let n: u64 = e
        .split("step ")
        .nth(2)
        .and_then(|t| t.split(':').next())
        .and_then(|t| t.parse().ok())
        .unwrap_or_else(|| panic!("{e}"));
    assert!(
        e.contains("is outside the grid")
            && e.contains(&format!("the run stopped after step {}", n - 1))
            && e.contains("status \"failed\""),
        "{e}"
    );
    assert!(n > 5, "{e}");
    let s = summary(&out);
    assert_eq!(s["status"], "failed");
    assert!(s["error"].as_str().unwrap().contains("outside the grid"), "{s}");
    assert_eq!(s["steps"].as_u64(), Some(n - 1));
    // One row at t = 0 and one per completed step, the last at the summary's time.
    let rows = assert_consistent(&out);
    assert_eq!(rows as u64, n);
    let history = read_csv(&out.join("history.csv")).unwrap();
    assert_eq!(history.rows.last().unwrap()[0].parse::<f64>().unwrap(), s["end_time"].as_f64().unwrap());
    assert_eq!(s["final_energies"]["time"], s["end_time"]);
    // A snapshot per completed step, and the binary exits 1 with the same story.
    assert!(
        out.join(format!("particles_{:05}.vtk", n - 1)).exists() && !out.join(format!("particles_{n:05}.vtk")).exists()
    );
    let scene_file = dir.join("flying.toml");
    std::fs::write(&scene_file, FLYING).unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_cramp"))
        .args(["run", scene_file.to_str().unwrap(), "--out", dir.join("bin").to_str().unwrap()])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains(&format!("the run stopped after step {}", n - 1)) && stderr.contains("outside the grid"),
        "{stderr}"
    );
    assert_eq!(summary(&dir.join("bin"))["status"], "failed");
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn a_stop_request_ends_the_run_at_the_end_of_a_step() {
    let dir = scratch("stop");
    let mut scene = Scene::from_toml(FLYING, "flying").unwrap();
    scene.bodies[0].velocity = [0.0, 0.0];
    let stop = Arc::new(AtomicBool::new(true));
    let r = run_scene(&scene, &RunOptions { out_dir: Some(dir.join("out")), stop: Some(stop), ..Default::default() })
        .unwrap();
    assert_eq!((r.summary.status, r.summary.steps), (RunStatus::Interrupted, 1));
    let s = summary(&dir.join("out"));
    assert_eq!((s["status"].as_str(), s["steps"].as_u64()), (Some("interrupted"), Some(1)));
    assert_eq!(assert_consistent(&dir.join("out")), 2);
    std::fs::remove_dir_all(dir).ok();
}

/// The performance DCB (2623 steps, J every 0.25 ms) with a snapshot every 0.01 ms, on one
/// thread, so it runs long enough to be signalled midway.
fn long_run(dir: &Path, name: &str) -> (Child, PathBuf) {
    let text = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("verification/dcb_perf.toml"))
        .unwrap()
        .replace("archive_interval = 0.25", "archive_interval = 0.01")
        .replace("history_interval = 0.25", "history_interval = 0.005");
    assert!(text.contains("archive_interval = 0.01") && text.contains("history_interval = 0.005"));
    let scene = dir.join(format!("{name}.toml"));
    std::fs::write(&scene, text).unwrap();
    let out = dir.join(name);
    let child = Command::new(env!("CARGO_BIN_EXE_cramp"))
        .args(["run", scene.to_str().unwrap(), "--out", out.to_str().unwrap(), "--threads", "1", "--unchecked"])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    (child, out)
}

/// Wait until the run has written `rows` history rows.
fn wait_for_rows(out: &Path, rows: usize) {
    let start = Instant::now();
    while std::fs::read_to_string(out.join("history.csv")).map_or(0, |t| t.lines().count()) < rows + 1 {
        assert!(start.elapsed() < Duration::from_secs(60), "the run wrote no {rows} rows in 60 s");
        std::thread::sleep(Duration::from_millis(20));
    }
}

fn signal(child: &Child, name: &str) {
    let ok = Command::new("kill").args([&format!("-{name}"), &child.id().to_string()]).status().unwrap();
    assert!(ok.success());
}

#[test]
fn sigterm_and_sigint_stop_the_run_with_consistent_files() {
    let dir = scratch("signals");
    for sig in ["TERM", "INT"] {
        let (mut child, out) = long_run(&dir, &format!("sig{sig}"));
        wait_for_rows(&out, 5);
        signal(&child, sig);
        let status = child.wait().unwrap();
        let mut stderr = String::new();
        std::io::Read::read_to_string(child.stderr.as_mut().unwrap(), &mut stderr).unwrap();
        assert_eq!(status.code(), Some(130), "SIG{sig}: {stderr}");
        assert!(stderr.contains("interrupted after step"), "{stderr}");
        let s = summary(&out);
        assert_eq!(s["status"], "interrupted", "SIG{sig}");
        let steps = s["steps"].as_u64().unwrap();
        assert!(steps > 0 && steps < 2623, "{steps}");
        let rows = assert_consistent(&out);
        let history = read_csv(&out.join("history.csv")).unwrap();
        assert_eq!(history.rows.last().unwrap()[0].parse::<f64>().unwrap(), s["end_time"].as_f64().unwrap());
        assert!(rows >= 5);
        // cracks.csv has a complete row per history row after the first, and the whole
        // directory reads (compare against itself agrees); no temporary file is left.
        let cracks = read_csv(&out.join("cracks.csv")).unwrap();
        assert_eq!(cracks.rows.len(), rows - 1);
        assert!(compare_runs(&out, &out, Tolerance::default()).unwrap().agree());
        let names: Vec<String> =
            std::fs::read_dir(&out).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
        assert!(!names.iter().any(|n| n.ends_with(".tmp")), "{names:?}");
    }
    std::fs::remove_dir_all(dir).ok();
}

/// SIGKILL gives no chance to write a summary, but every row and snapshot written is
/// complete (rows are written whole, snapshots by rename).
#[test]
fn a_killed_run_leaves_complete_rows_and_snapshots() {
    let dir = scratch("kill");
    let (mut child, out) = long_run(&dir, "killed");
    wait_for_rows(&out, 5);
    signal(&child, "KILL");
    child.wait().unwrap();
    assert!(!out.join("summary.json").exists());
    assert!(assert_consistent(&out) >= 5);
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn a_rerun_into_an_old_directory_is_refused_unless_forced() {
    let dir = scratch("rerun");
    let scene = dir.join("s.toml");
    let mut text = FLYING.replace("velocity = [10.0, 0.0]", "").replace("end_time = 1.0", "end_time = 0.01");
    std::fs::write(&scene, &text).unwrap();
    let out = dir.join("out");
    let run = |extra: &[&str]| {
        let o = Command::new(env!("CARGO_BIN_EXE_cramp"))
            .args(["run", scene.to_str().unwrap(), "--out", out.to_str().unwrap()])
            .args(extra)
            .output()
            .unwrap();
        (o.status.code(), String::from_utf8_lossy(&o.stderr).into_owned())
    };
    assert_eq!(run(&[]).0, Some(0));
    std::fs::write(out.join("notes.txt"), "mine").unwrap();
    let before = std::fs::read_to_string(out.join("history.csv")).unwrap();
    let (code, stderr) = run(&[]);
    assert_eq!(code, Some(1), "{stderr}");
    assert!(stderr.contains("already holds the results of a run") && stderr.contains("--force"), "{stderr}");
    assert_eq!(std::fs::read_to_string(out.join("history.csv")).unwrap(), before);
    // A shorter rerun with --force leaves none of the old snapshots beside its own, and
    // keeps the user's file.
    text = text.replace("end_time = 0.01", "end_time = 0.005");
    std::fs::write(&scene, &text).unwrap();
    let (code, stderr) = run(&["--force"]);
    assert_eq!(code, Some(0), "{stderr}");
    assert!(out.join("particles_00005.vtk").exists() && !out.join("particles_00006.vtk").exists());
    assert_eq!(std::fs::read_to_string(out.join("notes.txt")).unwrap(), "mine");
    assert_eq!(summary(&out)["steps"].as_u64(), Some(5));
    // The same for `cramp fea`.
    let fea = |extra: &[&str]| {
        Command::new(env!("CARGO_BIN_EXE_cramp"))
            .args(["fea", scene.to_str().unwrap(), "--out", dir.join("fea").to_str().unwrap()])
            .args(extra)
            .output()
            .unwrap()
            .status
            .code()
    };
    let fixed = text.replace(
        "[[bodies]]",
        "[[boundary]]\nnodes = { line = { from = [0.5, 0.4], to = [0.7, 0.4] } }\nvx = 0.0\nvy = 0.0\n\n[[bodies]]",
    );
    std::fs::write(&scene, fixed).unwrap();
    assert_eq!(fea(&[]), Some(0));
    assert_eq!(fea(&[]), Some(1));
    assert_eq!(fea(&["--force"]), Some(0));
    std::fs::remove_dir_all(dir).ok();
}

/// A closed stdout (`cramp run … | head -1`) is not a panic: the run finishes, exit 0.
#[test]
fn a_closed_stdout_is_not_a_panic() {
    let dir = scratch("pipe");
    let scene = dir.join("s.toml");
    std::fs::write(&scene, FLYING.replace("velocity = [10.0, 0.0]", "").replace("end_time = 1.0", "end_time = 0.005"))
        .unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_cramp"))
        .args(["run", scene.to_str().unwrap(), "--out", dir.join("out").to_str().unwrap()])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let status = child.wait().unwrap();
    let mut stderr = String::new();
    std::io::Read::read_to_string(child.stderr.as_mut().unwrap(), &mut stderr).unwrap();
    assert!(status.success() && !stderr.contains("panicked"), "{status}: {stderr}");
    assert_eq!(summary(&dir.join("out"))["status"], "completed");
    std::fs::remove_dir_all(dir).ok();
}
