//! A grid node just ahead of a warped crack front (issue 17): the reproduction of the
//! corner-crack rod's stop at step 94 ("a node needs three velocity fields") in a small
//! scene, and the rule that resolves it (`join_own_side` in src/crack/three_d.rs).
//!
//! The rod's surface near the stop (read from its crack VTK at t = 15.975 µs): each part
//! of the front grew level at its own height, so along the front (y) the surface steps down
//! from z ≈ −5.6 (y < 5) to z ≈ −6.3 (y > 6.5) within one cell, and the front lies 0.6 mm
//! short of the grid node (30, 6, −6). The node is below the surface's level on one side
//! and above it on the other: a particle above the high part (y = 4.5, z = −5.5) and one
//! below the low part (y = 6.5, z = −6.5) both see the surface between themselves and the
//! node. Here the same step, in a 16 × 12 × 12 mm block with the rod's 2 mm cells and 2
//! particles per cell, the crack a ruled surface z = g(y) from the face x = 20 to the front
//! x = 29.4: g = −5.6 for y ≤ 5, −6.3 for y ≥ 6.5, linear between.

mod common;

use common::{global_bits_3d, lcg_permutation, particle_bits_3d};
use cramp::crack::crossing3::{crossing, Side3};
use cramp::dim::{GridGeometry, Space, Vector3, D3};
use cramp::simulation::Simulation;

/// The warped crack as a mesh: columns at x = 20, 22, …, 28, 29.4 (the front), rows at
/// the profile's y, z = g(y); normals up (+z is "above").
fn scene(checked: bool, pull: f64) -> String {
    let xs = [20.0, 22.0, 24.0, 26.0, 28.0, 29.4];
    let profile = [(0.0, -5.6), (2.5, -5.6), (5.0, -5.6), (6.5, -6.3), (9.0, -6.3), (12.0, -6.3)];
    let ny = profile.len();
    let mut vertices = Vec::new();
    for x in xs {
        for (y, z) in profile {
            vertices.push(format!("[{x}, {y}, {z}]"));
        }
    }
    let mut triangles = Vec::new();
    for i in 0..xs.len() - 1 {
        for j in 0..ny - 1 {
            let (a, b, c, d) = (i * ny + j, (i + 1) * ny + j, (i + 1) * ny + j + 1, i * ny + j + 1);
            triangles.push(format!("[{a}, {b}, {c}]"));
            triangles.push(format!("[{a}, {c}, {d}]"));
        }
    }
    format!(
        r#"
[grid]
origin = [16.0, -4.0, -16.0]
size = [24.0, 20.0, 20.0]
cell = [2.0, 2.0, 2.0]

[solver]
end_time = 0.001
particles_per_cell = 2
checked = {checked}

[[materials]]
name = "steel"
E = 200000.0
nu = 0.298
rho = 7.9e-3

[[bodies]]
material = "steel"
shape = {{ box = {{ min = [20.0, 0.0, -12.0], max = [36.0, 12.0, 0.0] }} }}

[[loads]]
particles = {{ box = {{ min = [19.0, -1.0, -0.5], max = [37.0, 13.0, 0.0] }} }}
normal = [0.0, 0.0, 1.0]
traction = [0.0, 0.0, {pull}]

[[loads]]
particles = {{ box = {{ min = [19.0, -1.0, -12.0], max = [37.0, 13.0, -11.5] }} }}
normal = [0.0, 0.0, 1.0]
traction = [0.0, 0.0, {neg}]

[[cracks]]
surface = {{ mesh = {{ vertices = [{v}], triangles = [{t}] }} }}
contact = "frictionless"
"#,
        neg = -pull,
        v = vertices.join(", "),
        t = triangles.join(", ")
    )
}

fn build(text: &str) -> Simulation<D3> {
    cramp::scene3d::Scene3::from_toml(text, "warped front", None).unwrap().build().unwrap()
}

/// The crossing test's verdict for every pair (particle, node) of the particles' current
/// positions, over all triangles: field 0 none, 1 above, 2 below (what Task 1 assigns
/// before any node rule).
fn verdicts(sim: &Simulation<D3>) -> Vec<u8> {
    let crack = &sim.cracks[0];
    let view = crack.view();
    let nt = crack.surface.triangles.len();
    (0..sim.pairs.field.len())
        .map(|k| {
            let p = k / D3::MAX_NODES;
            if k % D3::MAX_NODES >= sim.pairs.count[p] as usize {
                return 0;
            }
            let n = sim.grid.node_pos(sim.pairs.node[k] as usize);
            match crossing(&view, 0..nt, &sim.particles.x[p], &n) {
                Side3::None => 0,
                Side3::Above => 1,
                Side3::Below => 2,
            }
        })
        .collect()
}

fn node_at(sim: &Simulation<D3>, x: Vector3) -> usize {
    (0..sim.grid.num_nodes()).find(|&i| sim.grid.node_pos(i) == x).expect("a grid node there")
}

/// The pairs of node `i` (pair indices), with the crossing verdicts `v`: the set of verdicts.
fn kinds(sim: &Simulation<D3>, v: &[u8], i: usize) -> u8 {
    (0..v.len()).filter(|&k| k % D3::MAX_NODES < sim.pairs.count[k / D3::MAX_NODES] as usize && sim.pairs.node[k] as usize == i).fold(0, |m, k| m | 1 << v[k])
}

/// Reproduction and rule. The crossing test alone gives node (30, 6, −6) particles from
/// above (1), from below (2) and uncrossed (0) — CRAMP's two fields per node cannot hold it
/// (before the rule the first step stopped with "needs more than two velocity fields").
/// The node is above the plane of its nearest triangle (the ramp's, z = −6.067 at y = 6),
/// so the particles that crossed from above are on its side and join field 0; those from
/// below keep field 2. Every other pair keeps its crossing verdict.
#[test]
fn node_ahead_of_a_warped_front_takes_its_own_side() {
    let mut sim = build(&scene(true, 0.0));
    let node = node_at(&sim, Vector3::new(30.0, 6.0, -6.0));
    sim.step().expect("the step runs (the node's particles from above join field 0)");
    // No load, no velocity: nothing moved, so the verdicts are those of the step's Task 1.
    let v = verdicts(&sim);
    assert_eq!(kinds(&sim, &v, node), 0b111, "the crossing test alone gives the node three fields");
    let mut changed = 0;
    for k in 0..v.len() {
        let p = k / D3::MAX_NODES;
        if k % D3::MAX_NODES >= sim.pairs.count[p] as usize {
            continue;
        }
        let f = sim.pairs.field[k];
        if sim.pairs.node[k] as usize == node && v[k] == 1 {
            assert_eq!(f, 0, "particle {p} at {:?}: from above, on the node's side", sim.particles.x[p]);
            changed += 1;
        } else {
            assert_eq!(f, v[k], "pair {k}: particle {:?}, node {:?}", sim.particles.x[p], sim.grid.node_pos(sim.pairs.node[k] as usize));
        }
    }
    assert!(changed >= 1);
    assert_eq!(sim.nodes.present[node], 0b101, "fields 0 and 2 (below) at the node");
    // Its normal: the nearest triangle's (the ramp's), from above to below.
    let n = sim.nodes.normal[node];
    let ramp = Vector3::new(0.0, 0.7, 1.5).normalize();
    assert!((n + ramp).norm() < 1e-12, "{n:?}");
    // No other node of this scene needs the rule.
    for i in 0..sim.grid.num_nodes() {
        if i != node && sim.nodes.present.get(i).is_some_and(|&p| p != 0) {
            assert_ne!(kinds(&sim, &v, i), 0b111, "node {:?}", sim.grid.node_pos(i));
        }
    }
}

/// The same node mirrored (z ↦ −12 − z, the node on the mirror plane z = −6): a mirror
/// flips every exact side (of the node and of every particle), so the node is now below
/// the plane of its nearest triangle and keeps field 1, and its particles that crossed
/// from below join field 0 — the rule follows the geometry, not a field number.
#[test]
fn mirrored_node_keeps_the_mirrored_field() {
    let text = scene(true, 0.0);
    // The box [−12, 0], the particles and the node map onto themselves.
    let mirrored = mirror_z(&text);
    let mut sim = build(&mirrored);
    let node = node_at(&sim, Vector3::new(30.0, 6.0, -6.0));
    sim.step().expect("the mirrored step runs");
    let v = verdicts(&sim);
    assert_eq!(kinds(&sim, &v, node), 0b111);
    assert_eq!(sim.nodes.present[node], 0b011, "fields 0 and 1 at the mirrored node");
}

/// z ↦ −12 − z in the crack's vertices of [`scene`]'s text (the rest is symmetric).
fn mirror_z(text: &str) -> String {
    let start = text.find("vertices = [").unwrap() + "vertices = [".len();
    let end = start + text[start..].find("], triangles").unwrap();
    let vs: Vec<String> = text[start..end]
        .split("], [")
        .map(|v| {
            let c: Vec<f64> = v.trim_matches(|ch| ch == '[' || ch == ']').split(',').map(|x| x.trim().parse().unwrap()).collect();
            format!("[{}, {}, {}]", c[0], c[1], -12.0 - c[2])
        })
        .collect();
    format!("{}{}{}", &text[..start], vs.join(", "), &text[end..])
}

/// Under a tensile step in checked mode (the crossing check every step) the scene runs
/// 100 steps (17 µs, the rule in force from the first): no particle crosses the crack,
/// no node needs a third field, and the crack opens.
#[test]
fn warped_front_runs_under_load_in_checked_mode() {
    let mut sim = build(&scene(true, 200.0));
    for _ in 0..100 {
        sim.step().expect("checked step");
    }
    let crack = &sim.cracks[0];
    let open = (0..crack.surface.vertices.len()).map(|k| crack.opening(k).z).fold(f64::NEG_INFINITY, f64::max);
    assert!(open > 0.0, "the crack opens ({open})");
}

/// The rule is a function of the node and the surface, and the node's sums are gathered
/// again with correctly rounded sums: 40 loaded steps give the same bits of every particle
/// (by id), the energies and momentum, and every crack point and surface with the
/// particles shuffled and with 1 or 2 threads.
#[test]
fn warped_front_is_bit_identical_for_any_particle_order_and_thread_count() {
    const STEPS: usize = 40;
    let bits = |mut sim: Simulation<D3>| -> Vec<u64> {
        for _ in 0..STEPS {
            sim.step().expect("step");
        }
        let mut idx = vec![usize::MAX; sim.particles.len()];
        for (k, &id) in sim.particles.id.iter().enumerate() {
            idx[id as usize] = k;
        }
        let mut out: Vec<u64> = idx.iter().flat_map(|&k| particle_bits_3d(&sim, k)).collect();
        out.extend(global_bits_3d(&sim));
        let c = &sim.cracks[0];
        for set in [&c.surface.vertices, &c.above, &c.below] {
            out.extend(set.iter().flat_map(|v| [v.x, v.y, v.z].map(f64::to_bits)));
        }
        out
    };
    let text = scene(true, 200.0);
    let a = bits(build(&text));
    let mut shuffled = build(&text);
    shuffled.particles.permute(&lcg_permutation(shuffled.particles.len(), 2121));
    assert!(a == bits(shuffled), "the shuffled run differs");
    let in_pool = |threads: usize| rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap().install(|| bits(build(&text)));
    assert!(in_pool(1) == in_pool(2), "2 threads differ from 1");
    assert!(a == in_pool(1), "the pooled run differs from the plain one");
}
