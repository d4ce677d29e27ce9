//! STL bodies fill exactly the particles of the equivalent analytic body (issue 14).
//! Reference: the `box` and `extrusion` solids of src/scene3d.rs, whose membership tests
//! are plain coordinate comparisons (and the 2D polygon test); the STL body decides
//! membership with ray parity and Shewchuk's exact predicates (src/stl.rs), a point on
//! the surface counting as inside, as the inclusive box does. Tolerance: none — the same
//! particle count, and the same positions, masses and volumes to the bit, in the same
//! order. The STL files are written here by hand (tests/common: binary and ASCII, f32
//! coordinates that are exact multiples of 1/32), independently of the reader.
//!
//! Cases, each in ASCII and binary STL:
//! * a cube [1/4, 3/4]³ (faces between particle planes; particles at x = y = z lie on
//!   the projections of a face diagonal along every axis, so all three rays are
//!   degenerate there and the winding-number fallback decides);
//! * a box whose six faces pass through particle planes (particles on faces, edges and
//!   corners: the exact on-surface rule);
//! * a non-convex L-shaped prism against the `extrusion` body of the same polygon.
//!
//! And `cramp run` takes a scene whose STL file is named relative to the scene file.

mod common;

use cramp::dim::D3;
use cramp::scene3d::Scene3;
use cramp::simulation::Simulation;
use std::path::Path;

const SCENE: &str = r#"
[grid]
origin = [0.0, 0.0, 0.0]
size = [1.0, 1.0, 1.0]
cell = [0.125, 0.125, 0.125]

[solver]
end_time = 0.01

[[materials]]
name = "m"
E = 1000.0
nu = 0.3
rho = 2.0

[[bodies]]
material = "m"
shape = SHAPE
velocity = [0.1, 0.0, -0.1]
"#;

fn build(shape: &str, dir: &Path) -> Simulation<D3> {
    let text = SCENE.replace("SHAPE", shape);
    Scene3::from_toml(&text, "stl test", Some(dir)).unwrap_or_else(|e| panic!("{shape}: {e}")).build().unwrap_or_else(|e| panic!("{shape}: {e}"))
}

/// Positions, velocities, masses and volumes as bits, in particle order.
fn fill_bits(sim: &Simulation<D3>) -> Vec<u64> {
    let p = &sim.particles;
    (0..p.len()).flat_map(|k| [p.x[k].x, p.x[k].y, p.x[k].z, p.v[k].x, p.v[k].y, p.v[k].z, p.mass[k], p.vol0[k]]).map(f64::to_bits).collect()
}

/// Write the triangles as ASCII and binary STL and check that both fill the particles of `analytic`.
fn assert_stl_fills_like(dir: &Path, name: &str, triangles: &[[[f32; 3]; 3]], analytic: &str, expected: usize) -> usize {
    std::fs::write(dir.join(format!("{name}.stl")), common::ascii_stl(triangles)).unwrap();
    std::fs::write(dir.join(format!("{name}_bin.stl")), common::binary_stl(triangles)).unwrap();
    let reference = build(analytic, dir);
    assert_eq!(reference.particles.len(), expected, "{analytic}");
    for file in [format!("{name}.stl"), format!("{name}_bin.stl")] {
        let stl = build(&format!("{{ stl = {{ file = \"{file}\" }} }}"), dir);
        assert_eq!(stl.particles.len(), reference.particles.len(), "{file}: particle count differs from {analytic}");
        assert!(fill_bits(&stl) == fill_bits(&reference), "{file}: particles differ from {analytic}");
    }
    expected
}

#[test]
fn stl_cube_and_box_fill_the_same_particles() {
    let dir = common::temp_dir("three_d_stl");
    // 4 × 4 × 4 cells, 8 particles each.
    let cube = common::box_triangles([0.25; 3], [0.75; 3]);
    assert_stl_fills_like(&dir, "cube", &cube, "{ box = { min = [0.25, 0.25, 0.25], max = [0.75, 0.75, 0.75] } }", 512);
    // Particles lie on odd multiples of 1/32: faces at 9/32 and 23/32 (x), 9/32 and 15/32
    // (y), 11/32 and 21/32 (z) pass through 8, 4 and 6 particle planes' worth:
    // (23 − 9)/2 + 1 = 8, (15 − 9)/2 + 1 = 4, (21 − 11)/2 + 1 = 6 particles per line.
    let on_faces = common::box_triangles([0.28125, 0.28125, 0.34375], [0.71875, 0.46875, 0.65625]);
    assert_stl_fills_like(&dir, "on_faces", &on_faces, "{ box = { min = [0.28125, 0.28125, 0.34375], max = [0.71875, 0.46875, 0.65625] } }", 8 * 4 * 6);
    std::fs::remove_dir_all(dir).ok();
}

/// The L-shaped polygon (counter-clockwise in x–y), its reflex corner at index 3.
const L_POLYGON: [[f32; 2]; 6] = [[0.25, 0.25], [0.75, 0.25], [0.75, 0.375], [0.5, 0.375], [0.5, 0.625], [0.25, 0.625]];

/// The closed, outward-oriented surface of the L polygon swept along z from z0 to z1:
/// caps fanned from the reflex corner (each fan triangle counter-clockwise, checked),
/// and two triangles per side wall.
fn l_prism(z0: f32, z1: f32) -> Vec<[[f32; 3]; 3]> {
    let p = |i: usize, z: f32| [L_POLYGON[i % 6][0], L_POLYGON[i % 6][1], z];
    let mut t = Vec::new();
    for (a, b) in [(4, 5), (5, 0), (0, 1), (1, 2)] {
        let [q, r, s] = [L_POLYGON[3], L_POLYGON[a], L_POLYGON[b]];
        assert!((r[0] - q[0]) * (s[1] - q[1]) - (r[1] - q[1]) * (s[0] - q[0]) > 0.0, "fan triangle must be counter-clockwise");
        t.push([p(3, z1), p(a, z1), p(b, z1)]); // top, normal +z
        t.push([p(3, z0), p(b, z0), p(a, z0)]); // bottom, normal −z
    }
    for i in 0..6 {
        t.push([p(i, z0), p(i + 1, z0), p(i + 1, z1)]);
        t.push([p(i, z0), p(i + 1, z1), p(i, z1)]);
    }
    t
}

#[test]
fn stl_l_prism_and_extrusion_fill_the_same_particles() {
    let dir = common::temp_dir("three_d_stl_l");
    let points: Vec<String> = L_POLYGON.iter().map(|q| format!("[{}, {}]", q[0], q[1])).collect();
    let extrusion = format!("{{ extrusion = {{ points = [{}], axis = \"z\", from = 0.25, to = 0.625 }} }}", points.join(", "));
    // The L covers 4 × 1 + 2 × 2 = 8 cells of 1/8 in x–y, over 3 cells in z; 8 particles each.
    assert_stl_fills_like(&dir, "l_prism", &l_prism(0.25, 0.625), &extrusion, 8 * 3 * 8);
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn cramp_run_reads_an_stl_body_relative_to_the_scene_file() {
    let dir = common::temp_dir("three_d_stl_run");
    std::fs::create_dir_all(dir.join("meshes")).unwrap();
    std::fs::write(dir.join("meshes").join("cube.stl"), common::binary_stl(&common::box_triangles([0.25; 3], [0.75; 3]))).unwrap();
    std::fs::write(dir.join("scene.toml"), SCENE.replace("SHAPE", "{ stl = { file = \"meshes/cube.stl\" } }")).unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_cramp")).arg("run").arg(dir.join("scene.toml")).arg("--out").arg(dir.join("out")).current_dir(std::env::temp_dir()).output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    let summary = std::fs::read_to_string(dir.join("out").join("summary.json")).unwrap();
    assert!(summary.contains("512"), "the summary should count 512 particles:\n{summary}");
    std::fs::remove_dir_all(dir).ok();
}
