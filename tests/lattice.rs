//! `solver.lattice = "body"` (issue 22 item 1): a body's particles are anchored to the body,
//! so moving the whole scene on the grid by a fraction of a cell moves the particles with
//! it, and a box whose sides are whole multiples of the particle spacing is tiled exactly.
//! References: exact geometry (the particle count of a tiled box, its mass ρ·A·t, the
//! particles' places relative to the body to round-off of the shifted coordinates), and
//! the default lattice as the negative control (a box edge on a particle column keeps the
//! column: one more column of particles).

use cramp::scene::{Scene, SceneError};
use cramp::scene3d::Scene3;

/// A 2D scene: a 6 × 4 box at (x0, y0) on a grid of 1-cells with 2 × 2 particles per cell,
/// with the given `solver.lattice` line (or none).
fn scene_2d(x0: f64, y0: f64, lattice: &str) -> String {
    format!(
        r#"
[grid]
origin = [-3.0, -3.0]
size = [14.0, 12.0]
cell = [1.0, 1.0]

[solver]
end_time = 0.01
particles_per_cell = 2
{lattice}

[[materials]]
name = "m"
E = 1000.0
nu = 0.3
rho = 2.0
state = "plane_strain"

[[bodies]]
material = "m"
shape = {{ rectangle = {{ min = [{x0}, {y0}], max = [{}, {}] }} }}
"#,
        x0 + 6.0,
        y0 + 4.0
    )
}

fn particles_2d(text: &str) -> Vec<[f64; 3]> {
    let sim = Scene::from_toml(text, "lattice.toml").unwrap().build().unwrap();
    (0..sim.particles.len()).map(|p| [sim.particles.x[p].x, sim.particles.x[p].y, sim.particles.mass[p]]).collect()
}

#[test]
fn body_lattice_moves_with_the_body_in_2d() {
    let base = particles_2d(&scene_2d(0.0, 0.0, "lattice = \"body\""));
    // 6 × 4 cells of 2 × 2 particles: the box tiled, no row on its edges.
    assert_eq!(base.len(), 12 * 8);
    let mass: f64 = base.iter().map(|p| p[2]).sum();
    assert!((mass - 2.0 * 24.0).abs() < 1e-12, "mass {mass} against ρ·A = 48");
    for (dx, dy) in [(0.1, 0.0), (0.25, 0.0), (0.5, 0.75), (0.9, 0.25), (0.37, 0.61)] {
        let moved = particles_2d(&scene_2d(dx, dy, "lattice = \"body\""));
        assert_eq!(moved.len(), base.len(), "shift ({dx}, {dy})");
        for (a, b) in base.iter().zip(&moved) {
            assert!((b[0] - dx - a[0]).abs() < 1e-12 && (b[1] - dy - a[1]).abs() < 1e-12, "shift ({dx}, {dy}): particle at {a:?} went to {b:?}");
            assert_eq!(a[2], b[2]);
        }
    }
    // Negative control: on the grid's lattice a shift of 0.25 cell puts the box's edges
    // on particle columns and rows, which the inclusive fill keeps.
    let grid = particles_2d(&scene_2d(0.25, 0.25, ""));
    assert_eq!(grid.len(), 13 * 9, "the grid lattice gains a column and a row");
    // And unshifted, the two lattices are the same places.
    let on_grid = particles_2d(&scene_2d(0.0, 0.0, ""));
    assert_eq!(on_grid.len(), base.len());
}

#[test]
fn body_lattice_moves_with_the_body_in_3d() {
    let text = |x0: f64, lattice: &str| {
        format!(
            r#"
[grid]
origin = [-2.0, -2.0, -2.0]
size = [8.0, 7.0, 7.0]
cell = [1.0, 1.0, 1.0]

[solver]
end_time = 0.01
particles_per_cell = 2
{lattice}

[[materials]]
name = "m"
E = 1000.0
nu = 0.3
rho = 1.0

[[bodies]]
material = "m"
shape = {{ box = {{ min = [{x0}, 0.0, 0.0], max = [{}, 2.0, 3.0] }} }}
"#,
            x0 + 3.0
        )
    };
    let count = |t: &str| Scene3::from_toml(t, "lattice3.toml", None).unwrap().build().unwrap().particles.len();
    assert_eq!(count(&text(0.0, "lattice = \"body\"")), 6 * 4 * 6);
    assert_eq!(count(&text(0.25, "lattice = \"body\"")), 6 * 4 * 6);
    assert_eq!(count(&text(0.25, "")), 7 * 4 * 6, "negative control: the grid lattice gains a layer");
}

#[test]
fn bad_lattice_is_named() {
    let e = Scene::from_toml(&scene_2d(0.0, 0.0, "lattice = \"cells\""), "bad.toml").unwrap_err();
    let msg = e.to_string();
    assert!(matches!(e, SceneError::Parse { .. }), "{msg}");
    assert!(msg.contains("bad.toml") && msg.contains("lattice") && msg.contains("cells"), "{msg}");
}

#[test]
fn first_body_wins_on_the_bodies_lattices() {
    // A 2 × 2 inclusion listed first inside a 6 × 4 plate, both on their own lattices: the
    // inclusion keeps its 4 × 4 particles, the plate its own points outside the inclusion
    // (96 − 16 = 80: the two lattices coincide here, both corners being whole spacings
    // apart), and no two particles share a place.
    let text = scene_2d(0.0, 0.0, "lattice = \"body\"").replace(
        "[[bodies]]",
        "[[bodies]]\nmaterial = \"m\"\nshape = { rectangle = { min = [2.0, 1.0], max = [4.0, 3.0] } }\n\n[[bodies]]",
    );
    let sim = Scene::from_toml(&text, "lattice.toml").unwrap().build().unwrap();
    let body = |k: u16| (0..sim.particles.len()).filter(|&p| sim.particles.body[p] == k).count();
    assert_eq!((body(0), body(1)), (16, 80));
    let mut places: Vec<(i64, i64)> = (0..sim.particles.len()).map(|p| ((sim.particles.x[p].x * 1e6).round() as i64, (sim.particles.x[p].y * 1e6).round() as i64)).collect();
    places.sort_unstable();
    places.dedup();
    assert_eq!(places.len(), 96);
}

#[test]
fn the_fea_refuses_the_bodies_lattice() {
    let scene = Scene::from_toml(&scene_2d(0.0, 0.0, "lattice = \"body\""), "lattice.toml").unwrap();
    let e = cramp::fea::scene::SceneFea::from_scene(&scene).err().expect("refused");
    assert!(e.to_string().contains("solver.lattice"), "{e}");
}
