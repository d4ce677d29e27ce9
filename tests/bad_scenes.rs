//! Bad scenes are rejected with an error that names the offending field (the scene's
//! contract in src/scene.rs: parsing rejects unknown fields and wrong types with the
//! toml error naming the key; `validate` and `build` reject physically meaningless
//! values with the field's path). Reference: the schema itself; no tolerance involved.
//! Each case starts from a valid base scene and changes one thing, so the error can
//! only come from that change (the base scene is checked to build).
//!
//! The `cramp run` binary must turn the same errors into a non-zero exit status and a
//! message on stderr naming the field, without panicking.

use cramp::scene::{Scene, SceneError};
use std::path::PathBuf;
use std::process::Command;

const BASE: &str = r#"
title = "base"
[grid]
origin = [0.0, 0.0]
size = [1.0, 1.0]
cell = [0.1, 0.1]

[solver]
scheme = "usavg"
shape = "ugimp"
cfl = 0.5
end_time = 0.01
particles_per_cell = 2

[[materials]]
name = "steel"
E = 1000.0
nu = 0.3
rho = 1.0
state = "plane_strain"

[[bodies]]
material = "steel"
shape = { rectangle = { min = [0.2, 0.2], max = [0.8, 0.6] } }

[[boundary]]
nodes = { line = { from = [0.2, 0.2], to = [0.8, 0.2] } }
vy = 0.0

[[loads]]
particles = { region = { min = [0.2, 0.55], max = [0.8, 0.6] } }
force = [0.0, -1.0]
"#;

/// Replace `from` (which must occur exactly once) by `to` in the base scene.
fn edit(from: &str, to: &str) -> String {
    assert_eq!(BASE.matches(from).count(), 1, "edit anchor {from:?} must occur once");
    BASE.replace(from, to)
}

/// Parse, validate and build; return the first error.
fn error_of(text: &str) -> SceneError {
    match Scene::from_toml(text, "bad.toml") {
        Err(e) => e,
        Ok(s) => match s.build() {
            Err(e) => e,
            Ok(_) => panic!("scene was accepted:\n{text}"),
        },
    }
}

fn expect(text: &str, needles: &[&str]) {
    let e = error_of(text);
    let msg = e.to_string();
    for n in needles {
        assert!(msg.contains(n), "error message does not contain {n:?}:\n{msg}");
    }
}

fn invalid_field(text: &str) -> String {
    match error_of(text) {
        SceneError::Invalid { field, .. } => field,
        e => panic!("expected SceneError::Invalid, got {e}"),
    }
}

#[test]
fn base_scene_is_valid() {
    let s = Scene::from_toml(BASE, "base").unwrap();
    s.build().unwrap();
}

#[test]
fn unknown_field() {
    expect(&edit("cfl = 0.5", "cfl = 0.5\nsubsteps = 3"), &["bad.toml", "unknown field `substeps`"]);
    expect(&edit("nu = 0.3", "nu = 0.3\nyield = 3.0"), &["unknown field `yield`"]);
}

#[test]
fn wrong_type() {
    expect(&edit("E = 1000.0", "E = \"stiff\""), &["bad.toml", "E = \"stiff\"", "invalid type"]);
    expect(&edit("particles_per_cell = 2", "particles_per_cell = 2.5"), &["particles_per_cell"]);
    expect(&edit("scheme = \"usavg\"", "scheme = \"leapfrog\""), &["scheme", "leapfrog"]);
}

#[test]
fn missing_required_field() {
    expect(&edit("end_time = 0.01\n", ""), &["missing field `end_time`"]);
}

#[test]
fn negative_modulus() {
    assert_eq!(invalid_field(&edit("E = 1000.0", "E = -1000.0")), "materials[0].E");
    expect(&edit("E = 1000.0", "E = -1000.0"), &["scene field `materials[0].E`", "must be positive"]);
    assert_eq!(invalid_field(&edit("E = 1000.0", "E = nan")), "materials[0].E");
    assert_eq!(invalid_field(&edit("rho = 1.0", "rho = 0.0")), "materials[0].rho");
}

#[test]
fn poisson_ratio_at_or_above_one_half() {
    assert_eq!(invalid_field(&edit("nu = 0.3", "nu = 0.5")), "materials[0].nu");
    assert_eq!(invalid_field(&edit("nu = 0.3", "nu = 0.7")), "materials[0].nu");
    assert_eq!(invalid_field(&edit("nu = 0.3", "nu = -1.0")), "materials[0].nu");
}

#[test]
fn body_outside_grid() {
    let t = edit("min = [0.2, 0.2], max = [0.8, 0.6]", "min = [0.2, 0.2], max = [1.2, 0.6]");
    assert_eq!(invalid_field(&t), "bodies[0].shape");
    expect(&t, &["extends outside the grid"]);
    let t = edit("shape = { rectangle = { min = [0.2, 0.2], max = [0.8, 0.6] } }", "shape = { disk = { center = [0.5, 0.5], radius = 0.55 } }");
    assert_eq!(invalid_field(&t), "bodies[0].shape");
}

#[test]
fn empty_body() {
    // A sliver between two rows of particle positions (positions at 0.025 + 0.05 k).
    let t = edit("shape = { rectangle = { min = [0.2, 0.2], max = [0.8, 0.6] } }", "shape = { rectangle = { min = [0.2, 0.301], max = [0.8, 0.32] } }");
    // The load and boundary must not fail first: the body check comes before them.
    assert_eq!(invalid_field(&t), "bodies[0].shape");
    expect(&t, &["empty body"]);
    let t = edit("min = [0.2, 0.2], max = [0.8, 0.6]", "min = [0.2, 0.2], max = [0.2, 0.6]");
    assert_eq!(invalid_field(&t), "bodies[0].shape.rectangle");
}

#[test]
fn zero_cells_and_fractional_cells() {
    assert_eq!(invalid_field(&edit("cell = [0.1, 0.1]", "cell = [0.0, 0.1]")), "grid.cell[0]");
    assert_eq!(invalid_field(&edit("size = [1.0, 1.0]", "size = [1.0, 0.0]")), "grid.size[1]");
    let t = edit("cell = [0.1, 0.1]", "cell = [0.1, 0.3]");
    assert_eq!(invalid_field(&t), "grid.size[1]");
    expect(&t, &["not a whole number of cells"]);
    assert_eq!(invalid_field(&edit("cell = [0.1, 0.1]", "cell = [2.0, 0.1]")), "grid.size[0]");
}

#[test]
fn missing_file() {
    let path = PathBuf::from("/nonexistent/dir/scene.toml");
    let e = Scene::from_file(&path).unwrap_err();
    assert!(matches!(e, SceneError::Io { .. }), "{e:?}");
    assert!(e.to_string().contains("/nonexistent/dir/scene.toml"), "{e}");
}

#[test]
fn material_name_not_found() {
    let t = edit("material = \"steel\"", "material = \"stele\"");
    assert_eq!(invalid_field(&t), "bodies[0].material");
    expect(&t, &["no material named 'stele'"]);
    let t = edit("[[bodies]]", "[[materials]]\nname = \"steel\"\nE = 1.0\nnu = 0.2\nrho = 1.0\nstate = \"plane_stress\"\n\n[[bodies]]");
    assert_eq!(invalid_field(&t), "materials[1].name");
}

#[test]
fn bad_cfl_and_time_step() {
    // cfl up to the measured stability limit of the scheme (case cfl_sweep), named in the error.
    expect(&edit("cfl = 0.5", "cfl = 1.75"), &["solver.cfl", "at most 1.7", "USAVG", "cfl_sweep", "got 1.75"]);
    assert!(Scene::from_toml(&edit("cfl = 0.5", "cfl = 1.5"), "ok.toml").is_ok(), "USAVG is stable to 1.7");
    expect(&edit("scheme = \"usavg\"\nshape = \"ugimp\"\ncfl = 0.5", "scheme = \"usl\"\nshape = \"ugimp\"\ncfl = 0.65"), &["solver.cfl", "at most 0.6", "USL"]);
    assert_eq!(invalid_field(&edit("cfl = 0.5", "cfl = 0.0")), "solver.cfl");
    assert_eq!(invalid_field(&edit("cfl = 0.5", "cfl = -0.5")), "solver.cfl");
    assert_eq!(invalid_field(&edit("cfl = 0.5", "dt = -1e-3")), "solver.dt");
    assert_eq!(invalid_field(&edit("end_time = 0.01", "end_time = 0.0")), "solver.end_time");
    assert_eq!(invalid_field(&edit("particles_per_cell = 2", "particles_per_cell = 0")), "solver.particles_per_cell");
    assert_eq!(invalid_field(&edit("particles_per_cell = 2", "particles_per_cell = 9")), "solver.particles_per_cell");
    assert_eq!(invalid_field(&edit("cfl = 0.5", "cfl = 0.5\ndamping = -1.0")), "solver.damping");
}

#[test]
fn crack_with_one_point() {
    let t = format!("{BASE}\n[[cracks]]\npoints = [[0.5, 0.4]]\n");
    assert_eq!(invalid_field(&t), "cracks[0].points");
    let t = format!("{BASE}\n[[cracks]]\npoints = [[0.1, 0.4], [0.5, 0.4]]\nv_sep = 1.2\n");
    assert_eq!(invalid_field(&t), "cracks[0].v_sep");
    let t = format!("{BASE}\n[[cracks]]\npoints = [[0.1, 0.4], [0.5, 0.4]]\ncontact = {{ friction = {{ mu = -0.1 }} }}\n");
    assert_eq!(invalid_field(&t), "cracks[0].contact.friction.mu");
}

#[test]
fn crack_method_bad_value_or_visibility_with_contact() {
    // Not one of the two methods: the parse error names the key and the accepted values.
    expect(
        &edit("particles_per_cell = 2", "particles_per_cell = 2\ncrack_method = \"diffraction\""),
        &["bad.toml", "crack_method", "diffraction", "velocity_fields", "visibility"],
    );
    // Node visibility has one field per node and so no crack contact: contact must be "none".
    let vis = edit("particles_per_cell = 2", "particles_per_cell = 2\ncrack_method = \"visibility\"");
    let t = format!("{vis}\n[[cracks]]\npoints = [[0.1, 0.4], [0.5, 0.4]]\n");
    assert_eq!(invalid_field(&t), "cracks[0].contact"); // the default is frictionless
    let t = format!("{vis}\n[[cracks]]\npoints = [[0.1, 0.4], [0.5, 0.4]]\ncontact = \"none\"\n");
    Scene::from_toml(&t, "ok.toml").unwrap().build().unwrap();
}

#[test]
fn load_selecting_no_particles() {
    let t = edit("particles = { region = { min = [0.2, 0.55], max = [0.8, 0.6] } }", "particles = { region = { min = [0.85, 0.85], max = [0.9, 0.9] } }");
    assert_eq!(invalid_field(&t), "loads[0].particles");
    expect(&t, &["selects no particles"]);
    assert_eq!(invalid_field(&edit("force = [0.0, -1.0]", "force = [inf, -1.0]")), "loads[0].force[0]");
    assert_eq!(invalid_field(&edit("force = [0.0, -1.0]", "force = [0.0, -1.0]\nramp = -1.0")), "loads[0].ramp");
}

#[test]
fn overlapping_loads() {
    let t = format!("{BASE}\n[[loads]]\nparticles = {{ region = {{ min = [0.2, 0.2], max = [0.8, 0.6] }} }}\nforce = [1.0, 0.0]\n");
    assert_eq!(invalid_field(&t), "loads[1].particles");
}

#[test]
fn boundary_selecting_no_nodes_or_fixing_nothing() {
    // Between node lines (0.1 spacing, lines select within a quarter cell).
    let t = edit("nodes = { line = { from = [0.2, 0.2], to = [0.8, 0.2] } }", "nodes = { line = { from = [0.15, 0.15], to = [0.15, 0.15] } }");
    assert_eq!(invalid_field(&t), "boundary[0].nodes");
    expect(&t, &["selects no grid nodes"]);
    assert_eq!(invalid_field(&edit("vy = 0.0\n", "")), "boundary[0]");
}

#[test]
fn polygon_with_two_points() {
    let t = edit("shape = { rectangle = { min = [0.2, 0.2], max = [0.8, 0.6] } }", "shape = { polygon = { points = [[0.2, 0.2], [0.8, 0.6]] } }");
    assert_eq!(invalid_field(&t), "bodies[0].shape.polygon.points");
}

#[test]
fn no_materials_or_bodies() {
    let t = edit("[[bodies]]\nmaterial = \"steel\"\nshape = { rectangle = { min = [0.2, 0.2], max = [0.8, 0.6] } }\n", "bodies = []\n");
    // `bodies = []` after [[materials]] would belong to that table; put it at the top instead.
    let t = t.replace("bodies = []\n", "");
    let t = t.replacen("title = \"base\"", "title = \"base\"\nbodies = []", 1);
    assert_eq!(invalid_field(&t), "bodies");
}

// ---- the binary -------------------------------------------------------------------

fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("cramp-bad-scenes-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn run_binary(scene_text: Option<&str>, name: &str) -> (std::process::ExitStatus, String, PathBuf) {
    let dir = temp_dir(name);
    let scene = dir.join(format!("{name}.toml"));
    if let Some(t) = scene_text {
        std::fs::write(&scene, t).unwrap();
    }
    let out = Command::new(env!("CARGO_BIN_EXE_cramp"))
        .arg("run")
        .arg(&scene)
        .arg("--out")
        .arg(dir.join("out"))
        .output()
        .expect("run cramp");
    (out.status, String::from_utf8_lossy(&out.stderr).into_owned(), dir)
}

#[test]
fn binary_reports_bad_scenes_without_panicking() {
    let cases: Vec<(&str, String, Vec<&str>)> = vec![
        ("negative_modulus", edit("E = 1000.0", "E = -1000.0"), vec!["materials[0].E"]),
        ("unknown_field", edit("cfl = 0.5", "cfl = 0.5\nsubsteps = 3"), vec!["unknown field `substeps`"]),
        ("nu_half", edit("nu = 0.3", "nu = 0.5"), vec!["materials[0].nu"]),
        ("outside", edit("min = [0.2, 0.2], max = [0.8, 0.6]", "min = [0.2, 0.2], max = [1.2, 0.6]"), vec!["bodies[0].shape"]),
        (
            "no_nodes",
            edit("nodes = { line = { from = [0.2, 0.2], to = [0.8, 0.2] } }", "nodes = { line = { from = [0.15, 0.15], to = [0.15, 0.15] } }"),
            vec!["boundary[0].nodes"],
        ),
    ];
    for (name, text, needles) in &cases {
        let (status, stderr, dir) = run_binary(Some(text), name);
        assert!(!status.success(), "{name}: cramp run succeeded");
        assert!(!stderr.contains("panicked"), "{name}: cramp panicked:\n{stderr}");
        for n in needles {
            assert!(stderr.contains(n), "{name}: stderr does not name {n:?}:\n{stderr}");
        }
        std::fs::remove_dir_all(dir).ok();
    }
    let (status, stderr, dir) = run_binary(None, "missing_file");
    assert!(!status.success());
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(stderr.contains("missing_file.toml") && stderr.contains("cannot read scene file"), "{stderr}");
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn binary_runs_the_base_scene() {
    let (status, stderr, dir) = run_binary(Some(BASE), "good");
    assert!(status.success(), "{stderr}");
    assert!(dir.join("out").join("history.csv").exists());
    assert!(dir.join("out").join("summary.json").exists());
    std::fs::remove_dir_all(dir).ok();
}

/// The annotated example of docs/scene.md is a valid scene (keeps the docs honest).
#[test]
fn docs_example_scene_is_valid() {
    let doc = include_str!("../docs/scene.md");
    let example = doc.find("## Complete annotated example").expect("the complete example's section");
    let start = example + doc[example..].find("```toml").expect("example block") + "```toml".len();
    let end = start + doc[start..].find("```").expect("end of block");
    let s = Scene::from_toml(&doc[start..end], "docs/scene.md").unwrap();
    s.build().unwrap();
}

#[test]
fn crack_growth_settings_and_toughness() {
    let grow = |g: &str| format!("{BASE}\n[[cracks]]\npoints = [[0.1, 0.4], [0.5, 0.4]]\nfracture = {{ tips = \"end\", growth = {{ {g} }} }}\n");
    let tough = "state = \"plane_strain\"\ntoughness = { criterion = \"max_hoop_stress\", kic = 1.0 }";
    let with_toughness = |g: &str| grow(g).replacen("state = \"plane_strain\"", tough, 1);
    // a crack may grow, but no material has a toughness
    assert_eq!(invalid_field(&grow("")), "cracks[0].fracture.growth");
    assert!(with_toughness("").contains("toughness"));
    assert!(Scene::from_toml(&with_toughness(""), "ok").unwrap().build().is_ok());
    assert_eq!(invalid_field(&with_toughness("increment = 0.0")), "cracks[0].fracture.growth.increment");
    assert_eq!(invalid_field(&with_toughness("increment = 1.5")), "cracks[0].fracture.growth.increment");
    assert_eq!(invalid_field(&with_toughness("every = 0")), "cracks[0].fracture.growth.every");
    assert_eq!(invalid_field(&with_toughness("max_speed = -1.0")), "cracks[0].fracture.growth.max_speed");
    assert_eq!(invalid_field(&with_toughness("speed_window = 0")), "cracks[0].fracture.growth.speed_window");
    // speed_correction is a bool, speed_window a whole number: parse errors naming them
    expect(&with_toughness("speed_correction = 1"), &["speed_correction"]);
    expect(&with_toughness("speed_window = 2.5"), &["speed_window"]);
    assert!(Scene::from_toml(&with_toughness("speed_correction = true, speed_window = 2"), "ok").unwrap().build().is_ok());
    // the gradual release of new segments: its length and damping, each named
    assert!(Scene::from_toml(&with_toughness("release = {}"), "ok").unwrap().build().is_ok());
    assert!(Scene::from_toml(&with_toughness("release = { length = 2.5, damping = 0.0 }"), "ok").unwrap().build().is_ok());
    assert_eq!(invalid_field(&with_toughness("release = { length = 0.0 }")), "cracks[0].fracture.growth.release.length");
    assert_eq!(invalid_field(&with_toughness("release = { length = 1e9 }")), "cracks[0].fracture.growth.release.length");
    assert_eq!(invalid_field(&with_toughness("release = { damping = -1.0 }")), "cracks[0].fracture.growth.release.damping");
    expect(&with_toughness("release = { time = 1.0 }"), &["time"]);
    // cohesive new segments: a positive strength, required, not with `release`, and not
    // too strong for the cell (its rising part must end before half its final opening)
    assert!(Scene::from_toml(&with_toughness("cohesive = { strength = 0.001 }"), "ok").unwrap().build().is_ok());
    assert_eq!(invalid_field(&with_toughness("cohesive = { strength = 0.0 }")), "cracks[0].fracture.growth.cohesive.strength");
    assert_eq!(invalid_field(&with_toughness("cohesive = { strength = nan }")), "cracks[0].fracture.growth.cohesive.strength");
    expect(&with_toughness("cohesive = {}"), &["strength"]);
    expect(&with_toughness("cohesive = { strength = 1.0, sigma = 2.0 }"), &["sigma"]);
    assert_eq!(invalid_field(&with_toughness("cohesive = { strength = 0.001 }, release = {}")), "cracks[0].fracture.growth.cohesive");
    let strong = with_toughness("cohesive = { strength = 1e6 }");
    assert_eq!(invalid_field(&strong), "cracks[0].fracture.growth.cohesive.strength");
    expect(&strong, &["too strong for the cell"]);
    let bad_kic = with_toughness("").replace("kic = 1.0", "kic = -2.0");
    assert_eq!(invalid_field(&bad_kic), "materials[0].toughness.kic");
    // a toughness without its criterion, or an unknown criterion, is a parse error naming it
    expect(&with_toughness("").replace("criterion = \"max_hoop_stress\", ", ""), &["criterion"]);
    expect(&with_toughness("").replace("max_hoop_stress", "max_stress"), &["max_stress"]);
    let sed_negative_nu = with_toughness("").replace("max_hoop_stress", "min_strain_energy").replace("nu = 0.3", "nu = -0.2");
    assert_eq!(invalid_field(&sed_negative_nu), "materials[0].toughness.criterion");
}

// ---- every kind of bad scene (issue 19) ----------------------------------------------

/// One kind of bad scene: its name, the scene text, the field the error must name and a
/// phrase it must contain.
struct Bad {
    kind: &'static str,
    text: String,
    field: &'static str,
    says: &'static str,
}

fn bad(kind: &'static str, text: String, field: &'static str, says: &'static str) -> Bad {
    Bad { kind, text, field, says }
}

/// The base scene with a crack (TOML table body after `[[cracks]]`).
fn with_crack(crack: &str) -> String {
    format!("{BASE}\n[[cracks]]\n{crack}\n")
}

const TOUGH: &str = "state = \"plane_strain\"\ntoughness = { criterion = \"max_hoop_stress\", kic = 1.0 }";

/// Every kind of bad scene the issue lists, and more: each must be refused while
/// validating or building, with an error that names the field at fault and says why —
/// never a panic, a hang, a huge allocation or a misleading message from a later stage.
fn bad_scenes() -> Vec<Bad> {
    let rect = "shape = { rectangle = { min = [0.2, 0.2], max = [0.8, 0.6] } }";
    let shape = |s: &str| edit(rect, &format!("shape = {{ {s} }}"));
    let solver = |extra: &str| edit("particles_per_cell = 2", &format!("particles_per_cell = 2\n{extra}"));
    let body = |extra: &str| edit(rect, &format!("{rect}\n{extra}"));
    let crack = "points = [[0.1, 0.4], [0.5, 0.4]]";
    let growing = |g: &str| with_crack(&format!("{crack}\nfracture = {{ tips = \"end\", growth = {{ {g} }} }}")).replacen("state = \"plane_strain\"", TOUGH, 1);
    vec![
        // grid
        bad("grid origin NaN", edit("origin = [0.0, 0.0]", "origin = [nan, 0.0]"), "grid.origin[0]", "finite"),
        bad("grid size infinite", edit("size = [1.0, 1.0]", "size = [inf, 1.0]"), "grid.size[0]", "finite"),
        bad("grid cell negative", edit("cell = [0.1, 0.1]", "cell = [0.1, -0.1]"), "grid.cell[1]", "positive"),
        bad("grid cell subnormal", edit("cell = [0.1, 0.1]", "cell = [5e-324, 0.1]"), "grid.size[0]", ""),
        bad("grid of 1e7 × 1e7 cells", edit("size = [1.0, 1.0]", "size = [1e7, 1e7]").replace("cell = [0.1, 0.1]", "cell = [1.0, 1.0]"), "grid", "the scene needs about"),
        bad("grid of 1e8 cells a side", edit("cell = [0.1, 0.1]", "cell = [1e-8, 0.1]"), "grid.size[0]", "too many"),
        // solver
        bad("end_time shorter than a step", edit("end_time = 0.01", "end_time = 1e-9"), "solver.end_time", "no step"),
        bad("end_time of 1e12 steps", edit("end_time = 0.01", "end_time = 1e9"), "solver.end_time", "solver.max_steps"),
        bad("dt tiny", edit("cfl = 0.5", "dt = 1e-300"), "solver.end_time", "solver.max_steps"),
        bad("dt subnormal", edit("cfl = 0.5", "dt = 5e-324"), "solver.end_time", "solver.max_steps"),
        bad("dt infinite", edit("cfl = 0.5", "dt = inf"), "solver.dt", "finite"),
        bad("cfl NaN", edit("cfl = 0.5", "cfl = nan"), "solver.cfl", "finite"),
        bad("max_steps below the run", solver("max_steps = 3"), "solver.end_time", "solver.max_steps = 3"),
        bad("wave speed overflows", edit("E = 1000.0", "E = 1e300").replace("rho = 1.0", "rho = 1e-300"), "materials[0]", "wave speed"),
        bad("damping 1e300", solver("damping = 1e300"), "solver.damping", "κ·dt"),
        bad("damping NaN", solver("damping = nan"), "solver.damping", "finite"),
        bad("damping infinite", solver("damping = inf"), "solver.damping", "finite"),
        bad("particles_per_cell 100", edit("particles_per_cell = 2", "particles_per_cell = 100"), "solver.particles_per_cell", "1 to 8"),
        // output
        bad("history interval NaN", format!("{BASE}\n[output]\nhistory_interval = nan\n"), "output.history_interval", "finite"),
        bad("archive interval negative", format!("{BASE}\n[output]\narchive_interval = -1.0\n"), "output.archive_interval", "positive"),
        bad("archive interval infinite", format!("{BASE}\n[output]\narchive_interval = inf\n"), "output.archive_interval", "finite"),
        // materials
        bad("E NaN", edit("E = 1000.0", "E = nan"), "materials[0].E", "finite"),
        bad("nu infinite", edit("nu = 0.3", "nu = inf"), "materials[0].nu", "finite"),
        bad("rho negative", edit("rho = 1.0", "rho = -1.0"), "materials[0].rho", "positive"),
        bad("toughness kic infinite", growing("").replace("kic = 1.0", "kic = inf"), "materials[0].toughness.kic", "finite"),
        // bodies
        bad("velocity NaN", body("velocity = [nan, 0.0]"), "bodies[0].velocity[0]", "finite"),
        bad("velocity infinite", body("velocity = [0.0, -inf]"), "bodies[0].velocity[1]", "finite"),
        bad("body force infinite", body("body_force = [0.0, inf]"), "bodies[0].body_force[1]", "finite"),
        bad("velocity_sine amplitude NaN", body("velocity_sine = { amplitude = [nan, 0.0], k = [1.0, 0.0] }"), "bodies[0].velocity_sine.amplitude[0]", "finite"),
        bad("velocity_sine k infinite", body("velocity_sine = { amplitude = [1.0, 0.0], k = [inf, 0.0] }"), "bodies[0].velocity_sine.k[0]", "finite"),
        bad("velocity_sine origin NaN", body("velocity_sine = { amplitude = [1.0, 0.0], k = [1.0, 0.0], origin = [0.0, nan] }"), "bodies[0].velocity_sine.origin[1]", "finite"),
        bad("thickness zero", body("thickness = 0.0"), "bodies[0].thickness", "positive"),
        bad("rectangle corner NaN", shape("rectangle = { min = [nan, 0.2], max = [0.8, 0.6] }"), "bodies[0].shape.rectangle.min[0]", "finite"),
        bad("rectangle corner infinite", shape("rectangle = { min = [0.2, 0.2], max = [inf, 0.6] }"), "bodies[0].shape.rectangle.max[0]", "finite"),
        bad("disk centre NaN", shape("disk = { center = [nan, 0.5], radius = 0.2 }"), "bodies[0].shape.disk.center[0]", "finite"),
        bad("disk radius infinite", shape("disk = { center = [0.5, 0.5], radius = inf }"), "bodies[0].shape.disk.radius", "finite"),
        bad("polygon vertex NaN", shape("polygon = { points = [[0.2, 0.2], [nan, 0.2], [0.8, 0.6]] }"), "bodies[0].shape.polygon.points[1][0]", "finite"),
        bad("body entirely outside the grid", shape("disk = { center = [5.0, 5.0], radius = 0.2 }"), "bodies[0].shape", "entirely outside the grid"),
        bad("body partly outside the grid", shape("disk = { center = [0.9, 0.5], radius = 0.2 }"), "bodies[0].shape", "extends outside the grid"),
        // boundary conditions and loads
        bad("boundary vx NaN", edit("vy = 0.0", "vx = nan"), "boundary[0].vx", "finite"),
        bad("boundary vy infinite", edit("vy = 0.0", "vy = inf"), "boundary[0].vy", "finite"),
        bad("boundary line end NaN", edit("to = [0.8, 0.2]", "to = [nan, 0.2]"), "boundary[0].nodes.line.to[0]", "finite"),
        bad("load region corner NaN", edit("max = [0.8, 0.6] } }\nforce", "max = [0.8, nan] } }\nforce"), "loads[0].particles.region.max[1]", "finite"),
        bad("load force NaN", edit("force = [0.0, -1.0]", "force = [0.0, nan]"), "loads[0].force[1]", "finite"),
        bad("load ramp infinite", edit("force = [0.0, -1.0]", "force = [0.0, -1.0]\nramp = inf"), "loads[0].ramp", "finite"),
        // prescribed motion, tractions, time functions (issue 21)
        bad("boundary expression does not parse", edit("vy = 0.0", "vy = \"1e-3 * (x +\""), "boundary[0].vy", "does not parse"),
        bad("boundary expression unknown variable", edit("vy = 0.0", "uy = \"1e-3 * z\""), "boundary[0].uy", "unknown variable `z`"),
        bad("boundary expression unknown function", edit("vy = 0.0", "uy = \"sinus(x)\""), "boundary[0].uy", "not a known function"),
        bad("boundary expression not finite at t = 0", edit("vy = 0.0", "vy = \"1 / t\""), "boundary[0].vy", "at t = 0"),
        bad("boundary expression not finite at a node", edit("vy = 0.0", "uy = \"ln(x - 0.5)\"\ntime = { ramp = 1.0 }"), "boundary[0].uy", "at t = 0 at the node"),
        bad("boundary velocity and displacement", edit("vy = 0.0", "vy = 0.0\nuy = 1.0"), "boundary[0].uy", "velocity or a displacement"),
        bad("boundary time table not increasing", edit("vy = 0.0", "uy = 1.0\ntime = { table = [[0.0, 0.0], [0.0, 1.0]] }"), "boundary[0].time.table[1]", "does not increase"),
        bad("boundary time expression of x", edit("vy = 0.0", "uy = 1.0\ntime = \"x * t\""), "boundary[0].time", "unknown variable `x`"),
        bad("boundary time ramp negative", edit("vy = 0.0", "uy = 1.0\ntime = { ramp = -1.0 }"), "boundary[0].time.ramp", "positive"),
        bad("williams K not finite", edit("vy = 0.0", "williams = { k1 = nan, tip = [0.5, 0.4] }"), "boundary[0].williams.k1", "finite"),
        bad("williams tip of three components", edit("vy = 0.0", "williams = { k1 = 1.0, tip = [0.5, 0.4, 0.0] }"), "boundary[0].williams.tip", "components"),
        bad("williams unknown material", edit("vy = 0.0", "williams = { k1 = 1.0, tip = [0.5, 0.4], material = \"glass\" }"), "boundary[0].williams.material", "no material named"),
        bad("load force and traction", edit("force = [0.0, -1.0]", "force = [0.0, -1.0]\ntraction = [0.0, 1.0]\nnormal = [0.0, 1.0]"), "loads[0].traction", "not both"),
        bad("load neither force nor traction", edit("force = [0.0, -1.0]", "ramp = 1.0"), "loads[0].force", "missing"),
        bad("traction on a region without normal", edit("force = [0.0, -1.0]", "traction = [0.0, -1.0]"), "loads[0].normal", "missing"),
        bad("traction expression unknown variable", edit("force = [0.0, -1.0]", "traction = [0.0, \"-y * q\"]\nnormal = [0.0, 1.0]"), "loads[0].traction[1]", "unknown variable `q`"),
        bad("traction normal zero", edit("force = [0.0, -1.0]", "traction = [0.0, -1.0]\nnormal = [0.0, 0.0]"), "loads[0].normal", "non-zero"),
        bad("load ramp and time", edit("force = [0.0, -1.0]", "force = [0.0, -1.0]\nramp = 1.0\ntime = { ramp = 1.0 }"), "loads[0].time", "either"),
        // cracks
        bad("crack point NaN", with_crack("points = [[0.1, 0.4], [nan, 0.4]]"), "cracks[0].points[1][0]", "finite"),
        bad("crack point infinite", with_crack("points = [[0.1, 0.4], [inf, 0.4]]"), "cracks[0].points[1][0]", "finite"),
        bad("crack point 1e300", with_crack("points = [[0.1, 0.4], [1e300, 0.4]]"), "cracks[0].points[1]", "outside the grid"),
        bad("crack outside the grid", with_crack("points = [[0.1, 0.4], [0.5, -0.4]]"), "cracks[0].points[1]", "outside the grid"),
        bad("crack segment of zero length", with_crack("points = [[0.1, 0.4], [0.3, 0.4], [0.3, 0.4], [0.5, 0.4]]"), "cracks[0].points[2]", "must have a length"),
        bad("crack on a particle row", with_crack("points = [[0.1, 0.425], [0.5, 0.425]]"), "cracks[0].points", "passes through the particle"),
        bad("crack v_contact infinite", with_crack(&format!("{crack}\nv_contact = inf")), "cracks[0].v_contact", "finite"),
        bad("crack friction NaN", with_crack(&format!("{crack}\ncontact = {{ friction = {{ mu = nan }} }}")), "cracks[0].contact.friction.mu", "zero or positive"),
        bad("J contour outside the grid", with_crack(&format!("{crack}\nfracture = {{ tips = \"end\", contour = 8 }}")), "cracks[0].fracture", "geometry"),
        bad(
            "J contour crossing the crack twice",
            with_crack("points = [[0.1, 0.4], [0.5, 0.4], [0.5, 0.45], [0.35, 0.45]]\nfracture = { tips = \"end\", contour = 2 }"),
            "cracks[0].fracture",
            "crosses the crack",
        ),
        bad("growth increment NaN", growing("increment = nan"), "cracks[0].fracture.growth.increment", "(0, 1]"),
        bad("growth max_speed infinite", growing("max_speed = inf"), "cracks[0].fracture.growth.max_speed", "finite"),
        bad("growth speed_window zero", growing("speed_window = 0"), "cracks[0].fracture.growth.speed_window", "at least 1"),
        bad("tip zone negative", BASE.replace("particles_per_cell = 2", "particles_per_cell = 2\ntip_zone = -1.0"), "solver.tip_zone", "0 (none) to 4"),
        bad("tip zone NaN", BASE.replace("particles_per_cell = 2", "particles_per_cell = 2\ntip_zone = nan"), "solver.tip_zone", "finite"),
        bad(
            "tip zone with visibility",
            with_crack("points = [[0.1, 0.45], [0.5, 0.45]]").replace("particles_per_cell = 2", "particles_per_cell = 2\ntip_zone = 1.0\ncrack_method = \"visibility\""),
            "solver.tip_zone",
            "visibility",
        ),
        bad("probe end NaN", format!("{BASE}\n[[probes]]\nname = \"p\"\nfrom = [0.1, 0.1]\nto = [nan, 0.5]\npoints = 5\n"), "probes[0].to[0]", "finite"),
    ]
}

#[test]
fn every_kind_of_bad_scene_names_its_field() {
    let cases = bad_scenes();
    let mut kinds = std::collections::BTreeSet::new();
    for b in &cases {
        assert!(kinds.insert(b.kind), "duplicate kind {}", b.kind);
        let start = std::time::Instant::now();
        let e = error_of(&b.text);
        let msg = e.to_string();
        match &e {
            SceneError::Invalid { field, .. } => assert_eq!(field, b.field, "{}: {msg}", b.kind),
            e => panic!("{}: expected an invalid field, got {e}", b.kind),
        }
        assert!(msg.contains(b.says), "{}: the error does not say {:?}:\n{msg}", b.kind, b.says);
        assert!(start.elapsed().as_secs_f64() < 2.0, "{}: took {:?}", b.kind, start.elapsed());
    }
    println!("{} kinds of bad scene, each refused naming its field", cases.len());
    assert!(cases.len() >= 50, "{}", cases.len());
}

/// The memory estimate refuses a 10⁴ × 10⁴ grid (30 GB before) with a limit of a few
/// GB, naming the grid and the estimate, without filling a particle.
#[test]
fn memory_estimate_refuses_a_grid_beyond_the_limit() {
    let t = edit("size = [1.0, 1.0]", "size = [1e4, 1e4]").replace("cell = [0.1, 0.1]", "cell = [1.0, 1.0]");
    let s = Scene::from_toml(&t, "big").unwrap();
    let e = s.memory_estimate();
    assert_eq!(e.nodes, 10001.0 * 10001.0);
    let msg = s.check_memory(Some(4e9)).unwrap_err().to_string();
    assert!(msg.contains("scene field `grid`") && msg.contains("10000 × 10000 cells") && msg.contains("GB"), "{msg}");
    assert!(s.check_memory(Some(e.bytes * 1.01)).is_ok());
    assert!(s.check_memory(None).is_ok());
}

/// Run `cramp` with `args` and environment `env`; kill it and fail if it takes longer
/// than `limit_s` (a hang).
fn cramp_within(args: &[&str], env: &[(&str, &str)], limit_s: f64) -> (Option<i32>, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_cramp"))
        .args(args)
        .envs(env.iter().copied())
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let start = std::time::Instant::now();
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            let mut err = String::new();
            std::io::Read::read_to_string(child.stderr.as_mut().unwrap(), &mut err).unwrap();
            return (status.code(), err);
        }
        if start.elapsed().as_secs_f64() > limit_s {
            child.kill().ok();
            child.wait().ok();
            panic!("cramp {args:?} did not finish within {limit_s} s");
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
}

/// Through the binary: scenes that used to hang, spin or allocate without bound now end
/// at once with an error naming the field (in `run` and `fea`), and an output interval
/// below the time step is rounded up with a warning.
#[test]
fn binary_neither_hangs_nor_allocates_on_bad_scenes() {
    let dir = temp_dir("no_hang");
    let cases: Vec<(&str, &str, String, &str)> = vec![
        ("run", "huge_grid", edit("size = [1.0, 1.0]", "size = [1e7, 1e7]").replace("cell = [0.1, 0.1]", "cell = [1.0, 1.0]"), "scene field `grid`"),
        ("run", "big_grid", edit("size = [1.0, 1.0]", "size = [1e4, 1e4]").replace("cell = [0.1, 0.1]", "cell = [1.0, 1.0]"), "scene field `grid`"),
        ("run", "crack_inf", with_crack("points = [[0.1, 0.4], [inf, 0.4]]"), "cracks[0].points[1][0]"),
        ("fea", "crack_inf", with_crack("points = [[0.1, 0.4], [inf, 0.4]]"), "cracks[0].points[1][0]"),
        ("fea", "crack_1e300", with_crack("points = [[0.1, 0.4], [1e300, 0.4]]"), "cracks[0].points[1]"),
        ("run", "subnormal_dt", edit("cfl = 0.5", "dt = 5e-324"), "solver.max_steps"),
        ("run", "zero_steps", edit("end_time = 0.01", "end_time = 1e-12"), "solver.end_time"),
    ];
    for (command, name, text, needle) in &cases {
        let scene = dir.join(format!("{name}.toml"));
        std::fs::write(&scene, text).unwrap();
        let out = dir.join(format!("out-{command}-{name}"));
        let (code, stderr) = cramp_within(&[command, scene.to_str().unwrap(), "--out", out.to_str().unwrap()], &[("CRAMP_MEMORY_LIMIT", "4e9")], 20.0);
        assert_eq!(code, Some(1), "{command} {name}: {stderr}");
        assert!(stderr.contains(needle) && !stderr.contains("panicked"), "{command} {name}: {stderr}");
    }
    // An interval far below the time step: rounded up to one step, with a warning.
    let scene = dir.join("tiny_interval.toml");
    std::fs::write(&scene, format!("{BASE}\n[output]\nhistory_interval = 1e-300\narchive_interval = 1e-300\n")).unwrap();
    let out = dir.join("out-tiny");
    let (code, stderr) = cramp_within(&["run", scene.to_str().unwrap(), "--out", out.to_str().unwrap()], &[], 20.0);
    assert_eq!(code, Some(0), "{stderr}");
    assert!(stderr.contains("warning: output.history_interval = 1e-300 is shorter than the time step") && stderr.contains("output.archive_interval"), "{stderr}");
    let summary: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let steps = summary["steps"].as_u64().unwrap();
    assert_eq!(summary["warnings"].as_array().unwrap().len(), 2);
    assert_eq!(std::fs::read_to_string(out.join("history.csv")).unwrap().lines().count() as u64, steps + 2);
    // --threads beyond its bound is a usage error; above the cores, a warning.
    for n in ["0", "5000"] {
        let (code, stderr) = cramp_within(&["run", scene.to_str().unwrap(), "--threads", n], &[], 20.0);
        assert_eq!(code, Some(2), "--threads {n}: {stderr}");
        assert!(stderr.contains("--threads"), "{stderr}");
    }
    let (code, stderr) = cramp_within(&["run", scene.to_str().unwrap(), "--out", out.to_str().unwrap(), "--force", "--threads", "512"], &[], 20.0);
    assert_eq!(code, Some(0), "{stderr}");
    assert!(stderr.contains("warning: --threads 512 is more than the"), "{stderr}");
    std::fs::remove_dir_all(dir).ok();
}

/// Settings that are accepted but unverified for the case at hand are warned about
/// (`cramp run` prints them): the COD fit on a growing crack.
#[test]
fn cod_fit_on_a_growing_crack_warns() {
    let crack = |fracture: &str| format!("{BASE}\n[[cracks]]\npoints = [[0.1, 0.4], [0.5, 0.4]]\nfracture = {fracture}\n").replace("state = \"plane_strain\"", "state = \"plane_strain\"\ntoughness = { criterion = \"max_hoop_stress\", kic = 1.0 }");
    let warnings = |fracture: &str| Scene::from_toml(&crack(fracture), "w.toml").unwrap().warnings();
    let w = warnings(r#"{ tips = "end", cod = "fit", growth = { increment = 0.5 } }"#);
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(w[0].contains("cracks[0].fracture.cod") && w[0].contains("unverified"), "{w:?}");
    assert!(warnings(r#"{ tips = "end", cod = "fit" }"#).is_empty());
    assert!(warnings(r#"{ tips = "end", growth = { increment = 0.5 } }"#).is_empty());
}

/// `rotate` (src/scene_rotate.rs): what cannot be turned is named; a turned body that
/// leaves the grid is refused like any other; a polygon selection needs three points;
/// the interaction-integral split is refused where it does not apply.
#[test]
fn rotate_and_interaction_errors_name_the_field() {
    let turned = |text: &str, angle: f64| format!("rotate = {{ angle = {angle:?}, about = [0.5, 0.4] }}\n{text}");
    // The base scene's support is a roller (vy only).
    assert_eq!(invalid_field(&turned(BASE, 30.0)), "boundary[0].vy");
    expect(&turned(BASE, 30.0), &["one component", "vx", "vy"]);
    let clamp = edit("vy = 0.0", "vx = 0.0\nvy = 0.0");
    Scene::from_toml(&turned(&clamp, 30.0), "turned").unwrap().build().unwrap();
    let traction = clamp.replace("force = [0.0, -1.0]", "traction = [0.0, -1.0]\nnormal = [0.0, 1.0]");
    assert_eq!(invalid_field(&turned(&traction, 30.0)), "loads[0].traction");
    let expr = clamp.replace("vx = 0.0", "vx = \"0.1 * y\"");
    assert_eq!(invalid_field(&turned(&expr, 30.0)), "boundary[0].vx");
    assert_eq!(invalid_field(&format!("rotate = {{ angle = nan, about = [0.5, 0.4] }}\n{clamp}")), "rotate");
    // Turned by 90° about a far point, the body leaves the grid.
    let far = format!("rotate = {{ angle = 90.0, about = [2.0, 2.0] }}\n{clamp}");
    assert!(invalid_field(&far).starts_with("bodies[0]"), "{}", error_of(&far));
    let poly = clamp.replace("particles = { region = { min = [0.2, 0.55], max = [0.8, 0.6] } }", "particles = { polygon = { points = [[0.2, 0.55], [0.8, 0.55]] } }");
    assert_eq!(invalid_field(&poly), "loads[0].particles.polygon.points");
    let crack = "\n[[cracks]]\npoints = [[0.1, 0.4], [0.5, 0.4]]\nfracture = { tips = \"end\", cod = \"interaction\", area_term = true }\n";
    assert_eq!(invalid_field(&format!("{BASE}{crack}")), "cracks[0].fracture.cod");
}
