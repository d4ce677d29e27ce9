//! Bad 3D scenes are rejected with an error that names the offending field and says what
//! is wrong (the scene contract of src/scene3d.rs and src/stl.rs, issue 14: every vector
//! has the scene's number of components, STL bodies are closed and consistently oriented
//! surfaces, nothing is silently dropped or defaulted). Reference: the schema itself; no
//! tolerance involved. As in tests/bad_scenes.rs each case starts from a valid base scene
//! and changes one thing, so the error can only come from that change (the base scene is
//! checked to build), and the whole path a file takes is exercised:
//! `AnyScene::from_toml` (dimension, vector lengths, parsing, validation) then `build`
//! (STL files, the grid's extent, the selections).
//!
//! The `cramp` binary must turn the same errors into a non-zero exit status and a message
//! on stderr naming the field, without panicking; `cramp fea` refuses a 3D scene.

mod common;

use cramp::scene::SceneError;
use cramp::scene3d::AnyScene;
use std::path::Path;
use std::process::Command;

const BASE: &str = r#"
title = "base 3D"
[grid]
origin = [0.0, 0.0, 0.0]
size = [1.0, 1.0, 1.0]
cell = [0.125, 0.125, 0.125]

[solver]
end_time = 0.01

[[materials]]
name = "steel"
E = 1000.0
nu = 0.3
rho = 1.0

[[bodies]]
material = "steel"
shape = { box = { min = [0.25, 0.25, 0.25], max = [0.75, 0.5, 0.75] } }
velocity = [0.0, 0.0, 0.0]

[[boundary]]
nodes = { plane = { point = [0.0, 0.25, 0.0], normal = [0.0, 1.0, 0.0] } }
vy = 0.0

[[loads]]
particles = { box = { min = [0.25, 0.45, 0.25], max = [0.75, 0.5, 0.75] } }
force = [0.0, -1.0, 0.0]
"#;

const BOX_SHAPE: &str = "shape = { box = { min = [0.25, 0.25, 0.25], max = [0.75, 0.5, 0.75] } }";

/// Replace `from` (which must occur exactly once) by `to` in the base scene.
fn edit(from: &str, to: &str) -> String {
    assert_eq!(BASE.matches(from).count(), 1, "edit anchor {from:?} must occur once");
    BASE.replace(from, to)
}

/// The base scene with body 0's shape replaced.
fn with_shape(shape: &str) -> String {
    edit(BOX_SHAPE, &format!("shape = {shape}"))
}

/// Parse, validate and build (2D or 3D, as `cramp run` does); the first error.
fn error_of(text: &str, base_dir: Option<&Path>) -> SceneError {
    let built = AnyScene::from_toml(text, "bad3d.toml", base_dir).and_then(|s| match s {
        AnyScene::D2(s) => s.build().map(|_| ()),
        AnyScene::D3(s) => s.build().map(|_| ()),
    });
    match built {
        Err(e) => e,
        Ok(()) => panic!("scene was accepted:\n{text}"),
    }
}

/// The error is `SceneError::Invalid` for `field`, and its message contains every needle.
fn expect_invalid(text: &str, base_dir: Option<&Path>, field: &str, needles: &[&str]) {
    println!("{}", error_of(text, base_dir));
    match error_of(text, base_dir) {
        SceneError::Invalid { field: f, message } => {
            assert_eq!(f, field, "wrong field named; message: {message}");
            for n in needles {
                assert!(message.contains(n), "error for `{field}` does not contain {n:?}: {message}");
            }
        }
        e => panic!("expected an invalid `{field}`, got: {e}"),
    }
}

/// The error (of any kind) contains every needle.
fn expect_message(text: &str, needles: &[&str]) {
    let msg = error_of(text, None).to_string();
    for n in needles {
        assert!(msg.contains(n), "error message does not contain {n:?}:\n{msg}");
    }
}

#[test]
fn base_scene_is_valid_and_3d() {
    let Ok(AnyScene::D3(s)) = AnyScene::from_toml(BASE, "base", None) else { panic!("the base scene is a valid 3D scene") };
    let sim = s.build().unwrap();
    assert_eq!(sim.particles.len(), (4 * 2 * 4) * 8); // cells of the box × 2³ particles
}

// ---- vectors of the wrong length, non-finite numbers -----------------------------------

#[test]
fn vector_with_two_components_in_a_3d_scene() {
    let t = edit("velocity = [0.0, 0.0, 0.0]", "velocity = [1.0, 2.0]");
    expect_invalid(&t, None, "bodies[0].velocity", &["has 2 components", "3D scene", "take 3"]);
    let t = edit("force = [0.0, -1.0, 0.0]", "force = [0.0, -1.0, 0.0, 0.0]");
    expect_invalid(&t, None, "loads[0].force", &["has 4 components"]);
}

#[test]
fn vector_with_three_components_in_a_2d_scene() {
    let two_d = "[grid]\norigin = [0.0, 0.0]\nsize = [1.0, 1.0]\ncell = [0.125, 0.125]\n[solver]\nend_time = 0.01\n\
                 [[materials]]\nname = \"m\"\nE = 1000.0\nnu = 0.3\nrho = 1.0\nstate = \"plane_strain\"\n\
                 [[bodies]]\nmaterial = \"m\"\nshape = { rectangle = { min = [0.25, 0.25], max = [0.75, 0.5] } }\nvelocity = [0.0, 0.0]\n";
    assert!(matches!(AnyScene::from_toml(two_d, "2d", None), Ok(AnyScene::D2(_))));
    let t = two_d.replace("velocity = [0.0, 0.0]", "velocity = [0.0, 0.0, 0.0]");
    expect_invalid(&t, None, "bodies[0].velocity", &["has 3 components", "2D scene", "take 2"]);
}

#[test]
fn grid_with_four_components_or_fractional_cells() {
    let t = edit("cell = [0.125, 0.125, 0.125]", "cell = [0.125, 0.125, 0.125, 0.125]");
    expect_message(&t, &["grid.cell", "4 components"]);
    let t = edit("size = [1.0, 1.0, 1.0]", "size = [1.0, 1.0, 1.05]");
    expect_invalid(&t, None, "grid.size[2]", &["not a whole number of cells"]);
}

#[test]
fn extrusion_polygon_point_with_three_components() {
    let t = with_shape("{ extrusion = { points = [[0.3, 0.3, 0.3], [0.6, 0.3], [0.5, 0.6]], axis = \"z\", from = 0.25, to = 0.75 } }");
    expect_invalid(&t, None, "bodies[0].shape.extrusion.points[0]", &["has 3 components", "2 components"]);
}

#[test]
fn nan_in_a_vector() {
    let t = edit("velocity = [0.0, 0.0, 0.0]", "velocity = [0.0, nan, 0.0]");
    expect_invalid(&t, None, "bodies[0].velocity[1]", &["finite", "NaN"]);
    let t = edit("force = [0.0, -1.0, 0.0]", "force = [0.0, -inf, 0.0]");
    expect_invalid(&t, None, "loads[0].force[1]", &["finite"]);
}

// ---- materials and cracks -------------------------------------------------------------

#[test]
fn plane_state_in_a_3d_material() {
    let t = edit("rho = 1.0", "rho = 1.0\nstate = \"plane_strain\"");
    expect_invalid(&t, None, "materials[0].state", &["mean nothing in a 3D scene"]);
}

#[test]
fn poisson_ratio_one_half_in_3d() {
    let t = edit("nu = 0.3", "nu = 0.5");
    expect_invalid(&t, None, "materials[0].nu", &["(−1, 0.5)", "0.5"]);
}

#[test]
fn a_2d_crack_polyline_in_a_3d_scene() {
    let t = format!("{BASE}\n[[cracks]]\npoints = [[0.3, 0.4, 0.5], [0.6, 0.4, 0.5]]\n");
    expect_message(&t, &["points", "surface"]);
}

// ---- 3D cracks (issue 15, verification 6) ----------------------------------------------

/// The base scene with one `[[cracks]]` table of the given body.
fn with_crack(body: &str) -> String {
    format!("{BASE}\n[[cracks]]\n{body}\n")
}

/// A valid crack: a rectangle on y = 0.4 through the body, past its sides.
const GOOD_CRACK: &str = "surface = { polygon = { points = [[0.2, 0.4, 0.2], [0.2, 0.4, 0.8], [0.8, 0.4, 0.8], [0.8, 0.4, 0.2]] } }";

#[test]
fn base_scene_with_a_crack_builds() {
    let Ok(AnyScene::D3(s)) = AnyScene::from_toml(&with_crack(GOOD_CRACK), "crack", None) else { panic!("a valid 3D scene") };
    s.build().expect("the cracked base scene builds");
}

#[test]
fn crack_mesh_inconsistently_oriented_names_the_triangle() {
    let t = with_crack("surface = { mesh = { vertices = [[0.2, 0.4, 0.2], [0.2, 0.4, 0.8], [0.8, 0.4, 0.8], [0.8, 0.4, 0.2]], triangles = [[0, 1, 2], [0, 3, 2]] } }");
    expect_invalid(&t, None, "cracks[0].surface.mesh", &["triangle 1", "triangle 0", "not consistently oriented"]);
}

#[test]
fn self_intersecting_crack_mesh_names_both_triangles() {
    // A horizontal triangle and a vertical one through it (no shared corner).
    let t = with_crack(
        "surface = { mesh = { vertices = [[0.3, 0.4, 0.3], [0.5, 0.4, 0.7], [0.7, 0.4, 0.3], \
         [0.5, 0.3, 0.5], [0.4, 0.5, 0.5], [0.6, 0.5, 0.5]], triangles = [[0, 1, 2], [3, 4, 5]] } }",
    );
    expect_invalid(&t, None, "cracks[0].surface.mesh", &["triangles 0 and 1 intersect", "must not cut itself"]);
    // Coplanar overlap: two triangles of the same plane, one across the other.
    let t = with_crack(
        "surface = { mesh = { vertices = [[0.3, 0.4, 0.3], [0.5, 0.4, 0.7], [0.7, 0.4, 0.3], \
         [0.3, 0.4, 0.5], [0.5, 0.4, 0.35], [0.7, 0.4, 0.5]], triangles = [[0, 1, 2], [3, 4, 5]] } }",
    );
    expect_invalid(&t, None, "cracks[0].surface.mesh", &["triangles 0 and 1 intersect"]);
}

#[test]
fn closed_crack_mesh_is_refused_and_says_why() {
    // A tetrahedron, consistently oriented (outward normals): closed, so no front.
    let t = with_crack(
        "surface = { mesh = { vertices = [[0.3, 0.3, 0.3], [0.6, 0.3, 0.3], [0.3, 0.45, 0.3], [0.3, 0.3, 0.6]], \
         triangles = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]] } }",
    );
    expect_invalid(&t, None, "cracks[0].surface.mesh", &["closed surface", "no front", "its own body"]);
}

/// A crack through particle centres (within round-off) is refused as in 2D: each such
/// particle is on neither side of it. The base scene has 2 × 2 × 2 particles per 0.125
/// cell, at 0.03125 + k · 0.0625.
#[test]
fn crack_through_particle_centres_is_refused() {
    let t = with_crack("surface = { polygon = { points = [[0.2, 0.40625, 0.2], [0.2, 0.40625, 0.8], [0.8, 0.40625, 0.8], [0.8, 0.40625, 0.2]] } }");
    expect_invalid(&t, None, "cracks[0].surface", &["passes through the particle", "neither side", "grid plane"]);
    // An oblique triangle whose centroid is the particle centre (0.46875, 0.46875, 0.46875).
    let t = with_crack(
        "surface = { mesh = { vertices = [[0.31875, 0.41875, 0.36875], [0.61875, 0.46875, 0.36875], [0.46875, 0.51875, 0.66875]], triangles = [[0, 1, 2]] } }",
    );
    expect_invalid(&t, None, "cracks[0].surface", &["passes through the particle", "crack triangle 0"]);
    // A hair off the same centres builds.
    let t = with_crack("surface = { polygon = { points = [[0.2, 0.4063, 0.2], [0.2, 0.4063, 0.8], [0.8, 0.4063, 0.8], [0.8, 0.4063, 0.2]] } }");
    let Ok(AnyScene::D3(s)) = AnyScene::from_toml(&t, "crack", None) else { panic!("a valid 3D scene") };
    s.build().expect("a crack off the particle centres builds");
}

/// Every 3D scene file of verification/ builds (so a new scene check cannot leave a
/// verification scene refused until the full suite reaches it).
#[test]
fn every_3d_verification_scene_builds() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("verification");
    let mut built = 0;
    for (name, text) in cramp::verify::scene_file::FILES {
        if let AnyScene::D3(s) = AnyScene::from_toml(text, name, Some(&dir)).unwrap_or_else(|e| panic!("{name}: {e}")) {
            s.build().unwrap_or_else(|e| panic!("{name}: {e}"));
            built += 1;
        }
    }
    assert!(built >= 30, "only {built} 3D scenes");
}

#[test]
fn crack_point_outside_the_grid() {
    let t = with_crack("surface = { polygon = { points = [[0.2, 0.4, 0.2], [0.2, 0.4, 0.8], [1.5, 0.4, 0.8], [0.8, 0.4, 0.2]] } }");
    expect_invalid(&t, None, "cracks[0].surface", &["crack point", "outside the grid"]);
}

#[test]
fn bad_crack_numbers() {
    expect_invalid(&with_crack(&format!("{GOOD_CRACK}\nedge = 0.0")), None, "cracks[0].edge", &[]);
    expect_invalid(&with_crack(&format!("{GOOD_CRACK}\nedge = -0.1")), None, "cracks[0].edge", &[]);
    let disc = |c: &str, n: &str, r: &str| with_crack(&format!("surface = {{ disc = {{ center = {c}, normal = {n}, radius = {r} }} }}"));
    expect_invalid(&disc("[0.5, 0.4, 0.5]", "[0.0, 1.0, 0.0]", "0.0"), None, "cracks[0].surface.disc.radius", &[]);
    expect_invalid(&disc("[0.5, 0.4, 0.5]", "[0.0, 1.0, 0.0]", "-0.2"), None, "cracks[0].surface.disc.radius", &[]);
    expect_invalid(&disc("[0.5, 0.4, 0.5]", "[0.0, 0.0, 0.0]", "0.2"), None, "cracks[0].surface.disc.normal", &["zero"]);
    expect_invalid(&disc("[0.5, nan, 0.5]", "[0.0, 1.0, 0.0]", "0.2"), None, "cracks[0].surface.disc.center[1]", &["finite"]);
    let t = with_crack("surface = { ellipse = { center = [0.5, 0.4, 0.5], normal = [0.0, 0.0, 0.0], axis = [1.0, 0.0, 0.0], a = 0.2, b = 0.1 } }");
    expect_invalid(&t, None, "cracks[0].surface.ellipse.normal", &["zero"]);
    let t = with_crack("surface = { ellipse = { center = [0.5, 0.4, 0.5], normal = [0.0, 1.0, 0.0], axis = [1.0, 0.0, 0.0], a = 0.2, b = 0.0 } }");
    expect_invalid(&t, None, "cracks[0].surface.ellipse.b", &[]);
}

#[test]
fn bad_fracture_tables_and_unknown_detection_are_refused_in_3d() {
    // The 2D table's fields are not the 3D one's.
    expect_message(&with_crack(&format!("{GOOD_CRACK}\nfracture = {{ contour = 2 }}")), &["contour"]);
    let fr = |t: &str| with_crack(&format!("{GOOD_CRACK}\nfracture = {{ {t} }}"));
    expect_invalid(&fr("radius = 0.0"), None, "cracks[0].fracture.radius", &[]);
    expect_invalid(&fr("radius = 1000.0"), None, "cracks[0].fracture.radius", &["cells"]);
    expect_invalid(&fr("intervals = 1"), None, "cracks[0].fracture.intervals", &["2 to 4096"]);
    expect_invalid(&fr("cod_behind = -1.0"), None, "cracks[0].fracture.cod_behind", &[]);
    expect_invalid(&fr("cod_along = -1.0"), None, "cracks[0].fracture.cod_along", &["[0, 64] cells", "-1"]);
    expect_invalid(&fr("cod_along = 100.0"), None, "cracks[0].fracture.cod_along", &["[0, 64] cells", "100"]);
    expect_invalid(&fr("cod_along = nan"), None, "cracks[0].fracture.cod_along", &["[0, 64] cells"]);
    expect_invalid(&fr("method = \"domain\", radius = 2.0, ramp = 3.0"), None, "cracks[0].fracture.ramp", &["radius"]);
    expect_invalid(&fr("method = \"domain\", along = 0.0"), None, "cracks[0].fracture.along", &[]);
    expect_invalid(&fr("along = 2.0"), None, "cracks[0].fracture.method", &["domain"]);
    expect_invalid(&fr("ramp = 1.0"), None, "cracks[0].fracture.method", &["domain"]);
    expect_message(&fr("method = \"ring\""), &["method"]);
    // The interaction integral is a domain integral, and static.
    expect_invalid(&fr("split = \"interaction\""), None, "cracks[0].fracture.split", &["domain"]);
    expect_message(&fr("split = \"cod\""), &["split", "opening", "interaction"]);
    expect_invalid(&fr("nodes = { box = { min = [0.0, 0.0, 0.0], max = [1.0, -1.0, 1.0] } }"), None, "cracks[0].fracture.nodes.box", &["exceeds"]);
    // GOOD_CRACK reaches past the body on every side: it has no front in the material.
    expect_invalid(&fr(""), None, "cracks[0].fracture.nodes", &["no front node"]);
    // The three detections exist in 3D ("opening", the default, "volume", "displacement"); others do not.
    expect_message(&with_crack(&format!("{GOOD_CRACK}\ndetection = \"gap\"")), &["gap", "volume", "opening"]);
    // The gradual release of new segments is 2D only.
    let tough = fr("growth = { release = {} }").replacen("rho = 1.0", "rho = 1.0\ntoughness = { criterion = \"max_hoop_stress\", kic = 1.0 }", 1);
    expect_invalid(&tough, None, "cracks[0].fracture.growth.release", &["2D only"]);
    let cohesive = tough.replace("release = {}", "cohesive = { strength = 1.0 }");
    expect_invalid(&cohesive, None, "cracks[0].fracture.growth.cohesive", &["2D only"]);
    let growing = tough.replace("growth = { release = {} }", "method = \"domain\", split = \"interaction\", growth = {}");
    expect_invalid(&growing, None, "cracks[0].fracture.split", &["growing front"]);
    // Mirror planes: an axis by name, one per axis, in the grid, for the domain integral.
    let dom = |m: &str| fr(&format!("method = \"domain\", mirrors = [{m}]"));
    expect_invalid(&dom("{ axis = \"w\", at = 0.0 }"), None, "cracks[0].fracture.mirrors[0].axis", &["\"x\", \"y\" or \"z\"", "\"w\""]);
    expect_invalid(&dom("{ axis = \"y\", at = 0.0 }, { axis = \"y\", at = 0.5 }"), None, "cracks[0].fracture.mirrors[1].axis", &["at most one per axis"]);
    expect_invalid(&dom("{ axis = \"x\", at = 99.0 }"), None, "cracks[0].fracture.mirrors[0].at", &["not in the grid"]);
    expect_invalid(&fr("mirrors = [{ axis = \"x\", at = 0.0 }]"), None, "cracks[0].fracture.mirrors[0]", &["method = \"domain\""]);
    expect_message(&dom("{ axis = \"x\" }"), &["at"]);
}

#[test]
fn unreadable_or_closed_stl_crack_files() {
    let dir = common::temp_dir("three_d_bad_stl_crack");
    let field = "cracks[0].surface.stl.file";
    expect_invalid(&with_crack("surface = { stl = { file = \"nowhere.stl\" } }"), Some(&dir), field, &["nowhere.stl", "cannot open"]);
    std::fs::write(dir.join("garbage.stl"), b"this is not an STL file at all").unwrap();
    expect_invalid(&with_crack("surface = { stl = { file = \"garbage.stl\" } }"), Some(&dir), field, &["garbage.stl"]);
    // A closed box as a crack: refused, with the reason.
    write_both(&dir, "closed", &common::box_triangles([0.3, 0.3, 0.3], [0.6, 0.45, 0.6]));
    for file in ["closed.stl", "closed_bin.stl"] {
        expect_invalid(&with_crack(&format!("surface = {{ stl = {{ file = \"{file}\" }} }}")), Some(&dir), field, &[file, "closed surface", "no front"]);
    }
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn two_cracks_splitting_one_node_stop_the_run_naming_the_node() {
    // Two parallel cracks 0.03 apart inside one cell: a node beside both sees three
    // kinds of particles (below both, between, above both), so needs three fields.
    let crack = |y: f64| format!("surface = {{ polygon = {{ points = [[0.2, {y}, 0.2], [0.2, {y}, 0.8], [0.8, {y}, 0.8], [0.8, {y}, 0.2]] }} }}");
    let t = format!("{BASE}\n[[cracks]]\n{}\n[[cracks]]\n{}\n", crack(0.33), crack(0.36));
    let Ok(AnyScene::D3(s)) = AnyScene::from_toml(&t, "two cracks", None) else { panic!("a valid 3D scene") };
    let mut sim = s.build().expect("builds");
    let err = sim.step().expect_err("a node needs three fields").to_string();
    println!("{err}");
    for n in ["grid node (i, j, k) = (", ") at (", "more than two velocity fields", "cracks [0, 1]"] {
        assert!(err.contains(n), "error does not contain {n:?}: {err}");
    }
}

// ---- solids ---------------------------------------------------------------------------

#[test]
fn cylinder_with_a_zero_length_axis() {
    let t = with_shape("{ cylinder = { from = [0.5, 0.4, 0.5], to = [0.5, 0.4, 0.5], radius = 0.1 } }");
    expect_invalid(&t, None, "bodies[0].shape.cylinder.to", &["zero length"]);
}

#[test]
fn tube_inner_radius_not_below_radius() {
    for inner in ["0.2", "0.3"] {
        let t = with_shape(&format!("{{ tube = {{ from = [0.5, 0.3, 0.5], to = [0.5, 0.6, 0.5], radius = 0.2, inner_radius = {inner} }} }}"));
        expect_invalid(&t, None, "bodies[0].shape.tube.inner_radius", &["must be below radius 0.2", inner]);
    }
}

#[test]
fn sphere_of_zero_radius_and_body_without_particles() {
    let t = with_shape("{ sphere = { center = [0.5, 0.4, 0.5], radius = 0.0 } }");
    expect_invalid(&t, None, "bodies[0].shape.sphere.radius", &["must be positive"]);
    // A sphere between the particle positions (spacing 1/16, positions at odd multiples of 1/32).
    let t = with_shape("{ sphere = { center = [0.5, 0.4375, 0.5], radius = 0.01 } }");
    expect_invalid(&t, None, "bodies[0].shape", &["contains no particle positions"]);
}

#[test]
fn solid_of_a_2d_kind() {
    let t = with_shape("{ disk = { center = [0.5, 0.4, 0.5], radius = 0.1 } }");
    expect_message(&t, &["unknown variant `disk`", "sphere"]);
}

#[test]
fn body_outside_the_grid() {
    let t = with_shape("{ sphere = { center = [0.5, 0.4, 0.9], radius = 0.2 } }");
    expect_invalid(&t, None, "bodies[0].shape", &["extends outside the grid", "1.1"]);
}

// ---- selections, boundary conditions and loads -----------------------------------------

#[test]
fn plane_selection_with_a_zero_normal() {
    let t = edit("normal = [0.0, 1.0, 0.0]", "normal = [0.0, 0.0, 0.0]");
    expect_invalid(&t, None, "boundary[0].nodes.plane.normal", &["zero vector"]);
}

#[test]
fn boundary_that_fixes_nothing() {
    let t = edit("vy = 0.0\n", "");
    expect_invalid(&t, None, "boundary[0]", &["fixes nothing", "vx, vy, vz, ux, uy, uz or williams"]);
}

#[test]
fn boundary_selecting_no_nodes() {
    // Nodes lie on multiples of 1/8; y = 0.3 is 0.05 from the nearest, beyond h/4.
    let t = edit("point = [0.0, 0.25, 0.0]", "point = [0.0, 0.3, 0.0]");
    expect_invalid(&t, None, "boundary[0].nodes", &["selects no grid nodes"]);
    let t = edit("nodes = { plane = { point = [0.0, 0.25, 0.0], normal = [0.0, 1.0, 0.0] } }", "nodes = { line = { from = [0.06, 0.06, 0.06], to = [0.07, 0.06, 0.06] } }");
    expect_invalid(&t, None, "boundary[0].nodes", &["selects no grid nodes"]);
}

#[test]
fn selection_box_upside_down() {
    let t = edit("min = [0.25, 0.45, 0.25], max = [0.75, 0.5, 0.75]", "min = [0.75, 0.45, 0.25], max = [0.25, 0.5, 0.75]");
    expect_invalid(&t, None, "loads[0].particles.box", &["below min"]);
}

#[test]
fn load_selecting_no_particles_or_loaded_twice() {
    let t = edit("min = [0.25, 0.45, 0.25], max = [0.75, 0.5, 0.75]", "min = [0.8, 0.8, 0.8], max = [0.9, 0.9, 0.9]");
    expect_invalid(&t, None, "loads[0].particles", &["selects no particles"]);
    let t = format!("{BASE}\n[[loads]]\nparticles = {{ plane = {{ point = [0.0, 0.46875, 0.0], normal = [0.0, 1.0, 0.0] }} }}\nforce = [1.0, 0.0, 0.0]\n");
    expect_invalid(&t, None, "loads[1].particles", &["selects the particle at (0.28125, 0.46875, 0.28125), already loaded by loads[0]"]);
}

// ---- size -----------------------------------------------------------------------------

#[test]
fn grid_too_large() {
    let t = edit("size = [1.0, 1.0, 1.0]", "size = [1000.0, 1000.0, 1000.0]");
    expect_invalid(&t, None, "grid.size", &["GiB", "use fewer or larger cells"]);
}

/// A grid whose nodal arrays are allowed (200³ cells, about 1.5 GiB by the estimate of
/// `validate`, never allocated here) but whose one body holds 8 × 200³ = 64 million
/// particles: refused while filling, after 11.5 million particle positions (about
/// 270 MB), not after building 100 GB of particles and pairs.
#[test]
fn too_many_particles() {
    let t = edit("cell = [0.125, 0.125, 0.125]", "cell = [0.005, 0.005, 0.005]");
    let t = t.replace(BOX_SHAPE, "shape = { box = { min = [0.0, 0.0, 0.0], max = [1.0, 1.0, 1.0] } }");
    expect_invalid(&t, None, "bodies", &["hold more than 11453246 particles (2³ per cell)", "16 GiB", "use larger cells or fewer particles per cell"]);
}

// ---- STL bodies -----------------------------------------------------------------------

/// The base scene with body 0 an STL solid read from `file` (relative to the scene's directory).
fn stl_scene(file: &str) -> String {
    with_shape(&format!("{{ stl = {{ file = \"{file}\" }} }}"))
}

/// Write the triangles as `<name>.stl` in ASCII and `<name>_bin.stl` in binary.
fn write_both(dir: &Path, name: &str, triangles: &[[[f32; 3]; 3]]) {
    std::fs::write(dir.join(format!("{name}.stl")), common::ascii_stl(triangles)).unwrap();
    std::fs::write(dir.join(format!("{name}_bin.stl")), common::binary_stl(triangles)).unwrap();
}

#[test]
fn stl_files_that_are_missing_open_misoriented_or_not_stl() {
    let dir = common::temp_dir("three_d_bad_stl");
    let cube = common::box_triangles([0.25, 0.25, 0.25], [0.75, 0.5, 0.75]);
    write_both(&dir, "cube", &cube);
    for file in ["cube.stl", "cube_bin.stl"] {
        let Ok(AnyScene::D3(s)) = AnyScene::from_toml(&stl_scene(file), "stl", Some(&dir)) else { panic!("{file}: a valid scene") };
        s.build().unwrap_or_else(|e| panic!("{file}: the closed cube must build: {e}"));
    }
    let field = "bodies[0].shape.stl.file";

    // Missing file: the error names the resolved path.
    expect_invalid(&stl_scene("nowhere.stl"), Some(&dir), field, &["nowhere.stl", "cannot open"]);

    // Open: the last triangle missing; the open edge is named by its end points.
    let mut open = cube.clone();
    open.pop();
    write_both(&dir, "open", &open);
    for file in ["open.stl", "open_bin.stl"] {
        expect_invalid(&stl_scene(file), Some(&dir), field, &[file, "is not closed: the edge from (", "belongs to triangle"]);
    }

    // Inconsistently oriented: one triangle turned inside out.
    let mut flipped = cube.clone();
    flipped[5].swap(1, 2);
    write_both(&dir, "flipped", &flipped);
    for file in ["flipped.stl", "flipped_bin.stl"] {
        expect_invalid(&stl_scene(file), Some(&dir), field, &[file, "not consistently oriented"]);
    }

    // A degenerate triangle (two equal corners) in place of one face triangle.
    let mut degenerate = cube.clone();
    degenerate[0][1] = degenerate[0][0];
    write_both(&dir, "degenerate", &degenerate);
    expect_invalid(&stl_scene("degenerate.stl"), Some(&dir), field, &["triangle 0 is degenerate (two equal corners"]);

    // A vertex with a non-finite coordinate (binary STL stores any f32; ASCII ones are
    // refused by the reader). The vertex is shared by all its triangles, so the surface
    // is still closed: the coordinate itself must be refused.
    for (name, bad) in [("nan", f32::NAN), ("inf", f32::INFINITY)] {
        let mut t = cube.clone();
        t.iter_mut().flatten().filter(|v| **v == [0.75, 0.5, 0.75]).for_each(|v| v[0] = bad);
        std::fs::write(dir.join(format!("{name}.stl")), common::binary_stl(&t)).unwrap();
        expect_invalid(&stl_scene(&format!("{name}.stl")), Some(&dir), field, &["has a vertex with a non-finite coordinate", &format!("({bad}, 0.5, 0.75)")]);
    }

    // A truncated binary file: the sizes are in the message.
    let mut truncated = common::binary_stl(&cube);
    truncated.truncate(84 + 50 * 5);
    std::fs::write(dir.join("truncated.stl"), truncated).unwrap();
    expect_invalid(&stl_scene("truncated.stl"), Some(&dir), field, &["not a readable STL file", "this file has 334 bytes", "its triangle count needs 684 bytes"]);

    // Fewer than 4 triangles.
    write_both(&dir, "three", &cube[..3]);
    expect_invalid(&stl_scene("three_bin.stl"), Some(&dir), field, &["has 3 triangles", "at least 4"]);

    // Not an STL file at all, and an empty file.
    std::fs::write(dir.join("text.stl"), "this is not a mesh\n").unwrap();
    expect_invalid(&stl_scene("text.stl"), Some(&dir), field, &["text.stl", "not a readable STL file"]);
    std::fs::write(dir.join("empty.stl"), "").unwrap();
    expect_invalid(&stl_scene("empty.stl"), Some(&dir), field, &["empty.stl", "not a readable STL file"]);

    // A closed STL outside the grid.
    write_both(&dir, "far", &common::box_triangles([0.5, 0.5, 0.5], [1.5, 0.75, 0.75]));
    expect_invalid(&stl_scene("far_bin.stl"), Some(&dir), "bodies[0].shape", &["extends outside the grid"]);
    std::fs::remove_dir_all(dir).ok();
}

// ---- the binary -----------------------------------------------------------------------

/// Run `cramp <command> <scene>` on a scene written to a temporary directory.
fn run_binary(command: &str, scene_text: &str, name: &str) -> (std::process::ExitStatus, String, std::path::PathBuf) {
    let dir = common::temp_dir(&format!("three_d_bad_{name}"));
    let scene = dir.join(format!("{name}.toml"));
    std::fs::write(&scene, scene_text).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_cramp")).arg(command).arg(&scene).arg("--out").arg(dir.join("out")).output().expect("run cramp");
    (out.status, String::from_utf8_lossy(&out.stderr).into_owned(), dir)
}

#[test]
fn binary_reports_bad_3d_scenes_without_panicking() {
    let cases: Vec<(&str, &str, String, Vec<&str>)> = vec![
        ("run", "two_components", edit("velocity = [0.0, 0.0, 0.0]", "velocity = [1.0, 2.0]"), vec!["bodies[0].velocity", "has 2 components"]),
        ("run", "state", edit("rho = 1.0", "rho = 1.0\nstate = \"plane_stress\""), vec!["materials[0].state"]),
        ("run", "closed_crack", with_crack("surface = { mesh = { vertices = [[0.3, 0.3, 0.3], [0.6, 0.3, 0.3], [0.3, 0.45, 0.3], [0.3, 0.3, 0.6]], triangles = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]] } }"), vec!["cracks[0].surface.mesh", "closed surface"]),
        ("run", "cracks", format!("{BASE}\n[[cracks]]\npoints = [[0.3, 0.4, 0.5], [0.6, 0.4, 0.5]]\n"), vec!["points", "surface"]),
        ("run", "missing_stl", stl_scene("missing.stl"), vec!["bodies[0].shape.stl.file", "missing.stl", "cannot open"]),
        ("run", "outside", with_shape("{ sphere = { center = [0.5, 0.4, 0.9], radius = 0.2 } }"), vec!["bodies[0].shape", "outside the grid"]),
        ("fea", "fea_3d_free", edit("force = [0.0, -1.0, 0.0]", "force = [0.5, -1.0, 0.0]"), vec!["scene field `boundary`", "not held against rigid motion", "translation in x", "its loads do work on it"]),
    ];
    for (command, name, text, needles) in &cases {
        let (status, stderr, dir) = run_binary(command, text, name);
        assert!(!status.success(), "{name}: cramp {command} succeeded");
        assert!(!stderr.contains("panicked"), "{name}: cramp panicked:\n{stderr}");
        for n in needles {
            assert!(stderr.contains(n), "{name}: stderr does not contain {n:?}:\n{stderr}");
        }
        std::fs::remove_dir_all(dir).ok();
    }
}

#[test]
fn binary_runs_the_base_3d_scene() {
    let (status, stderr, dir) = run_binary("run", BASE, "good");
    assert!(status.success(), "{stderr}");
    assert!(dir.join("out").join("summary.json").exists());
    std::fs::remove_dir_all(dir).ok();
}


/// The time-step checks 2D and 3D share (scene::validate_time_step): a run of no step, a
/// run beyond solver.max_steps, and explicit damping with κ·dt ≥ 1 are errors naming the
/// field, in a 3D scene as in 2D.
#[test]
fn time_step_that_cannot_run_is_named_in_3d() {
    let base = BASE.to_string();
    let end = base.lines().find(|l| l.trim_start().starts_with("end_time")).expect("the base scene has an end_time").to_string();
    expect_invalid(&base.replace(&end, "end_time = 1e-12"), None, "solver.end_time", &["no step"]);
    expect_invalid(&base.replace(&end, "end_time = 1e9"), None, "solver.end_time", &["solver.max_steps"]);
    expect_invalid(&base.replace(&end, &format!("{end}\ndamping = 1e12")), None, "solver.damping", &["κ·dt"]);
}
