//! Crack propagation (Guo & Nairn 001 §2.3; issue 7), coarse versions of the `cramp
//! verify` cases of src/verify/cases/growth.rs (which give the references, set-ups and
//! the reasons for each tolerance; verification/cases.toml states them), run here with
//! the checked mode on, plus the growth invariants.
//!
//! * The impacted PMMA three-point bend (001 §3.1) grows straight up at 4 and 2 mm, and
//!   the two crack-length histories agree within one growth increment on average.
//! * Off centre (001 §3.2) the crack turns toward the impact point, by both criteria,
//!   and the two paths agree within 3 mm.
//! * A centre crack under pure shear kinks at the pure-mode-II hoop-stress angle.
//! * A crack that reaches the far edge stops there, the body is recorded as cut through,
//!   and the run goes on with the two pieces apart and no particle crossing the crack.
//! * Growth is bit-reproducible under a permutation of the particles.

use cramp::fracture::growth::{is_simple_polyline, TipStatus};
use cramp::fracture::jintegral::TipEnd;
use cramp::verify::cases::growth::{depth_history, initiation, mean_difference, mode_ii_kink, path, path_shape_difference, records, run_growth, run_growth_file, three_point_bend, tip_asymmetry};

#[test]
fn pmma_beam_crack_grows_straight_and_converges() {
    let end = 0.3;
    let mut hist = Vec::new();
    for h in [4.0, 2.0] {
        let (r, wall) = run_growth_file(&three_point_bend(h, 0.0, "min_strain_energy", end), true).unwrap();
        let recs = records(&r, TipEnd::End);
        let drift = recs.iter().map(|x| x.fracture.tip.x.abs()).fold(0.0, f64::max);
        let a = depth_history(&recs);
        let a_end = a.last().unwrap().1;
        println!("h = {h}: initiation {:.1} µs, a(300 µs) = {a_end:.1} mm, max |x_tip| {drift:.2e} mm, {wall:.1} s", initiation(&recs).unwrap());
        // Mirror symmetry: the tip stays on x = 0 up to round-off (manifest: 1e-6 mm).
        assert!(drift <= 1e-6, "tip left the symmetry plane by {drift} mm");
        assert!(a_end - 50.0 >= 10.0, "crack grew only {} mm", a_end - 50.0);
        // Invariant: the crack stays a simple polyline.
        assert!(is_simple_polyline(&r.sim.cracks[0].points));
        hist.push(a);
    }
    let d = mean_difference(&hist[0], &hist[1], 1e3 * end);
    println!("mean |a_4 − a_2| = {d:.3} mm");
    // Within one growth increment of the coarser grid (h/2 = 2 mm) on average.
    assert!(d <= 2.0, "crack-length histories differ by {d} mm on average");
}

#[test]
fn off_centre_impact_turns_the_crack_toward_the_impact_point() {
    let mut paths = Vec::new();
    for crit in ["max_hoop_stress", "min_strain_energy"] {
        let (r, _) = run_growth_file(&three_point_bend(4.0, 0.1, crit, 0.21), true).unwrap();
        let p = path(&r);
        let tip = *p.last().unwrap();
        println!("{crit}: tip at ({:.2}, {:.2})", tip.0, tip.1);
        assert!(tip.0 >= 5.0, "{crit}: the crack did not turn toward x = +20 mm: tip {tip:?}");
        paths.push(p);
    }
    let (d, dl) = path_shape_difference(&paths[0], &paths[1]);
    println!("paths apart by at most {d:.2} mm over their common length; lengths differ by {dl:.2} mm");
    assert!(d <= 3.0, "criteria disagree by {d} mm");
    for p in &paths {
        let pts: Vec<_> = p.iter().map(|&(x, y)| cramp::dim::Vector::new(x, y)).collect();
        assert!(is_simple_polyline(&pts), "the path crosses itself");
    }
}

#[test]
fn pure_mode_ii_tips_kink_at_the_hoop_stress_angle() {
    let (kinks, r, wall) = mode_ii_kink(1.0, 0.4, true).unwrap();
    println!("first kinks (θ°, K_I/K_II): {kinks:?}, {wall:.1} s");
    let pure = -2.0 * (1.0 / 2f64.sqrt()).atan().to_degrees(); // −70.53°
    for (theta, ratio) in kinks {
        assert!((theta - pure).abs() <= 3.0, "kink {theta}° vs {pure}°");
        assert!(ratio.abs() <= 0.16, "K_I/K_II = {ratio}");
    }
    assert!(tip_asymmetry(&r) <= 0.1, "tips kink differently: {kinks:?}");
}

/// A 20 × 40 mm strip with a 6 mm edge crack (mouth outside the left edge), pulled by
/// ramped end forces; K_Ic is low, so the crack runs through to the right edge.
const STRIP: &str = r#"
title = "edge-cracked strip pulled apart"
[grid]
origin = [-4.5, -34.5]
size = [29.0, 69.0]
cell = [1.0, 1.0]
[solver]
end_time = 0.4
[output]
history_interval = 0.02
[[materials]]
name = "solid"
E = 1000.0
nu = 0.3
rho = 1.0e-3
state = "plane_strain"
toughness = { criterion = "max_hoop_stress", kic = 3.0 }
[[bodies]]
material = "solid"
shape = { rectangle = { min = [0.0, -20.0], max = [20.0, 20.0] } }
[[loads]]
particles = { region = { min = [0.0, 19.5], max = [20.0, 20.0] } }
force = [0.0, 20.0]
ramp = 0.2
[[loads]]
particles = { region = { min = [0.0, -20.0], max = [20.0, -19.5] } }
force = [0.0, -20.0]
ramp = 0.2
[[cracks]]
points = [[-1.0, 0.0], [6.0, 0.0]]
fracture = { tips = "end", contour = 2, growth = { increment = 0.5 } }
"#;

#[test]
fn a_crack_reaching_the_edge_stops_and_the_body_splits() {
    let (r, _) = run_growth(STRIP, true).unwrap();
    let g = r.sim.growth.as_ref().unwrap();
    let cg = &g.cracks[0];
    let tip = *path(&r).last().unwrap();
    println!("tip {tip:?}, status {:?}, split at {:?}, length {:.3}", cg.tips[0].status, cg.split, cg.length());
    assert_eq!(cg.tips[0].status, TipStatus::AtEdge);
    // Trimmed at the material boundary (x = 20), not beyond it, not short of it by more
    // than the boundary's resolution (a quarter cell).
    assert!(tip.0 <= 20.0 + 1e-9 && tip.0 >= 19.75, "tip {tip:?}");
    let split = cg.split.expect("the crack cut the strip through");
    assert!(split < 0.4);
    // The run went on (checked mode: no particle crossed the crack) and the pieces moved
    // apart: every particle above the crack moves up, every one below moves down.
    assert!(r.sim.time > 0.39);
    let p = &r.sim.particles;
    let (mut up, mut down) = (f64::INFINITY, f64::NEG_INFINITY);
    for i in 0..p.len() {
        let dy = p.x[i].y - p.x0[i].y;
        if p.x0[i].y > 0.0 { up = up.min(dy) } else { down = down.max(dy) }
    }
    println!("smallest upward displacement above {up:.3}, largest below {down:.3}");
    assert!(up > 0.0 && down < 0.0);
    // After the split, nothing more is added.
    assert!(g.records.iter().filter(|x| x.fracture.time > split).all(|x| !x.grew));
}

#[test]
fn growth_is_identical_after_shuffling_particles() {
    shuffled_growth_is_identical(three_point_bend(4.0, 0.1, "max_hoop_stress", 0.17).load().unwrap());
}

/// The same with each new segment released gradually (`growth.release`, issue 20), and
/// on one thread against the default pool: the holding forces act at nodes chosen by
/// crack geometry alone, serially.
#[test]
fn released_growth_is_identical_after_shuffling_particles_and_on_one_thread() {
    identical_after_shuffling_and_on_one_thread("cracks.0.fracture.growth.release", "{}");
}

/// The same with cohesive new segments (`growth.cohesive`, issue 20): the tractions are
/// spread from the crack particles, in order, serially.
#[test]
fn cohesive_growth_is_identical_after_shuffling_particles_and_on_one_thread() {
    identical_after_shuffling_and_on_one_thread("cracks.0.fracture.growth.cohesive", "{ strength = 20.0 }");
}

/// The off-centre PMMA beam at 4 mm with `key = value` grows to the same bits after
/// shuffling its particles and on one thread against the default pool.
fn identical_after_shuffling_and_on_one_thread(key: &str, value: &str) {
    let scene = three_point_bend(4.0, 0.1, "max_hoop_stress", 0.17).set(key, value).load().unwrap();
    let (pa, ra) = shuffled_growth_is_identical(scene.clone());
    let mut one = scene.build().unwrap();
    rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap().install(|| one.run_until(0.17, |_| {})).unwrap();
    assert_eq!((pa, ra), growth_bits(&one));
}

fn growth_bits(s: &cramp::simulation::Simulation) -> (Vec<u64>, Vec<u64>) {
    let c = &s.cracks[0];
    let g = s.growth.as_ref().unwrap();
    let pts: Vec<u64> = c.points.iter().chain(&c.above).chain(&c.below).flat_map(|p| [p.x.to_bits(), p.y.to_bits()]).collect();
    let recs: Vec<u64> = g.records.iter().flat_map(|r| [r.fracture.j1.to_bits(), r.fracture.k1.to_bits(), r.fracture.k2.to_bits(), r.theta.to_bits(), r.speed.to_bits()]).collect();
    (pts, recs)
}

/// Run `scene` to 0.17 ms as built and with its particles permuted; the crack and every
/// growth record must agree to the bit. Returns the bits.
fn shuffled_growth_is_identical(scene: cramp::scene::Scene) -> (Vec<u64>, Vec<u64>) {
    let mut a = scene.build().unwrap();
    let mut b = a.clone();
    let n = b.particles.len();
    // k ↦ 7919k + 13 mod n is a permutation when gcd(7919, n) = 1 (7919 is prime).
    assert!(!n.is_multiple_of(7919));
    let perm: Vec<usize> = (0..n).map(|k| (k * 7919 + 13) % n).collect();
    b.particles.permute(&perm);
    a.run_until(0.17, |_| {}).unwrap();
    b.run_until(0.17, |_| {}).unwrap();
    let (pa, ra) = growth_bits(&a);
    assert!(a.growth.as_ref().unwrap().records.iter().filter(|r| r.grew).count() >= 3, "the crack must have grown");
    assert_eq!((pa.clone(), ra.clone()), growth_bits(&b));
    (pa, ra)
}

/// A centre crack on the grid line y = 0 (h = 1) whose end has just kinked by −60°
/// (its last segment, half a cell long), in a plate under shear plus tension (τ = σ =
/// 1 MPa, ramped, damped). The nodes on y = 0 next to the kink lie on the crack; before
/// issue 22 the material beyond the kinked segment got field 0 there, next to fields 1
/// and 2, and the run stopped at step 1 with a third velocity field.
const KINKED_NOTCH: &str = r#"
title = "notch on a grid line, kinked by -60 degrees"
[grid]
origin = [-24.0, -24.0]
size = [48.0, 48.0]
cell = [1.0, 1.0]
[solver]
end_time = 0.5
damping = 10.0
[output]
history_interval = 0.05
[[materials]]
name = "solid"
E = 1000.0
nu = 0.3
rho = 1.0e-3
state = "plane_strain"
toughness = { criterion = "max_hoop_stress", kic = 3.66 }
[[bodies]]
material = "solid"
shape = { rectangle = { min = [-20.0, -20.0], max = [20.0, 20.0] } }
[[loads]]
particles = { region = { min = [-19.5, 19.5], max = [19.5, 20.0] } }
force = [40.0, 40.0]
ramp = 0.5
[[loads]]
particles = { region = { min = [-19.5, -20.0], max = [19.5, -19.5] } }
force = [-40.0, -40.0]
ramp = 0.5
[[loads]]
particles = { region = { min = [19.5, -20.0], max = [20.0, 20.0] } }
force = [0.0, 40.0]
ramp = 0.5
[[loads]]
particles = { region = { min = [-20.0, -20.0], max = [-19.5, 20.0] } }
force = [0.0, -40.0]
ramp = 0.5
[[cracks]]
points = [[-5.5, 0.0], [5.5, 0.0], [5.75, -0.4330127018922193]]
fracture = { tips = "end", contour = 2, area_term = true, growth = { increment = 0.5 } }
"#;

#[test]
fn a_notch_kinked_on_a_grid_line_grows_on_with_two_fields() {
    let (r, wall) = run_growth(KINKED_NOTCH, true).unwrap();
    let recs = records(&r, TipEnd::End);
    let grew = recs.iter().filter(|x| x.grew).count();
    let tip = *path(&r).last().unwrap();
    println!("{grew} increments, tip at ({:.2}, {:.2}), {wall:.1} s", tip.0, tip.1);
    // Checked to the end (≤ 2 fields at every node, no particle crossing the crack), and
    // the crack went on growing from the kink.
    assert!(r.sim.time > 0.49);
    assert!(grew >= 5, "only {grew} increments");
    assert!(is_simple_polyline(&r.sim.cracks[0].points));
}

/// Two cracks 0.8 cell apart (off the particle rows, which a scene may not put a crack on)
/// split the nodes between them twice: the error names the node by its grid indices and
/// position.
#[test]
fn a_node_needing_a_third_field_is_named_by_indices_and_position() {
    let text = KINKED_NOTCH.replace(
        "[[cracks]]\npoints = [[-5.5, 0.0], [5.5, 0.0], [5.75, -0.4330127018922193]]",
        "[[cracks]]\npoints = [[-5.5, 0.4], [5.5, 0.4]]\n[[cracks]]\npoints = [[-5.5, -0.4], [5.5, -0.4]]",
    );
    let err = run_growth(&text, true).err().expect("two cracks through one node's cell must stop the run");
    let msg = format!("{err:#}");
    println!("{msg}");
    assert!(msg.contains("grid node (i, j) = (") && msg.contains(", 24) at (") && msg.contains(", 0)"), "{msg}");
}
