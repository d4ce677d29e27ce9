//! Thread-count independence. Reference: cramp's design contract (src/exact.rs,
//! src/step.rs): every particle→node and node→particle sum is correctly rounded, and the
//! parallel loops only split independent per-node and per-particle work, so any number
//! of threads must give the bits of one. Tolerance: none (`f64::to_bits` equality).
//!
//! Scene: the cracked DCB of verification/dcb_perf.toml (Guo & Nairn 2004 §4.1) at 2 mm
//! cells, with frictionless crack contact so the contact code runs too, checked mode on,
//! 300 steps (through the first stress waves, where the exact-sum fallback is used most).
//! Run in a 1-thread and in a 2-thread rayon pool (and a 3-thread one, which splits the
//! work unevenly), then compare every particle's position, velocity, stress, strain and
//! displacement gradient, the crack particles and surfaces, and the energies. The same
//! comparison between the AVX2 and the baseline copies of the hot loops (src/simd.rs).

use cramp::scene::Scene;
use cramp::simulation::Simulation;

const STEPS: usize = 300;

fn scene() -> Scene {
    let mut text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/verification/dcb_perf.toml")).unwrap();
    text = text.replace("cell = [1.0, 1.0]", "cell = [2.0, 2.0]").replace("origin = [-2.5, -14.0]", "origin = [-5.0, -14.0]");
    text = text.replace("size = [105.0, 28.0]", "size = [110.0, 28.0]").replace("contact = \"none\"", "contact = \"frictionless\"");
    // The clamp: the node columns x = -1 and x = 1 hold the end column of particles.
    text = text.replace("nodes = { region = { min = [-2.5, -14.0], max = [0.5, 14.0] } }", "nodes = { region = { min = [-5.0, -14.0], max = [1.0, 14.0] } }");
    text = text.replace("min = [99.5, 0.0], max = [100.0, 12.0]", "min = [99.0, 0.0], max = [100.0, 12.0]");
    text = text.replace("min = [99.5, -12.0], max = [100.0, 0.0]", "min = [99.0, -12.0], max = [100.0, 0.0]");
    Scene::from_toml(&text, "threads DCB").unwrap()
}

fn run_in_pool(threads: usize) -> Simulation {
    run_scene_in_pool(threads, scene())
}

fn run_scene_in_pool(threads: usize, scene: Scene) -> Simulation {
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
    pool.install(|| {
        assert_eq!(rayon::current_num_threads(), threads);
        let mut sim = scene.build().unwrap();
        assert!(sim.options.checked && sim.has_cracks());
        for _ in 0..STEPS {
            sim.step().unwrap_or_else(|e| panic!("{threads} threads: {e}"));
        }
        sim
    })
}

fn bits(sim: &Simulation) -> Vec<u64> {
    let p = &sim.particles;
    let mut out = Vec::new();
    for k in 0..p.len() {
        let (s, e, g) = (&p.stress[k], &p.strain[k], &p.grad_u[k]);
        out.extend([p.x[k].x, p.x[k].y, p.v[k].x, p.v[k].y, s.xx, s.yy, s.zz, s.xy, e.xx, e.yy, e.zz, e.xy, g[(0, 0)], g[(0, 1)], g[(1, 0)], g[(1, 1)]]);
    }
    for c in &sim.cracks {
        for k in 0..c.points.len() {
            out.extend([c.points[k].x, c.points[k].y, c.above[k].x, c.above[k].y, c.below[k].x, c.below[k].y]);
        }
    }
    let e = sim.energies();
    out.extend([e.kinetic, e.strain, e.external_work, e.damping]);
    out.into_iter().map(f64::to_bits).collect()
}

#[test]
fn one_two_and_three_threads_give_identical_bits() {
    let one = run_in_pool(1);
    let reference = bits(&one);
    // The run did something: the arms opened.
    let tip_opening = one.cracks[0].opening(0);
    assert!(tip_opening.y.abs() > 0.0 && one.energies().strain > 0.0, "{tip_opening:?}");
    for threads in [2, 3] {
        let other = bits(&run_in_pool(threads));
        let first_diff = reference.iter().zip(&other).position(|(a, b)| a != b);
        assert_eq!(first_diff, None, "{threads} threads differ from 1 at value {first_diff:?}");
        assert_eq!(reference.len(), other.len());
    }
}

/// The AVX2 copies of the hot loops (src/simd.rs) give the bits of the baseline code: the
/// same scene with them switched off and on. On a CPU without AVX2 both runs are
/// baseline and the test says so.
#[test]
fn avx2_and_baseline_code_give_identical_bits() {
    cramp::simd::set_enabled(false);
    assert!(!cramp::simd::enabled());
    let baseline = bits(&run_in_pool(2));
    cramp::simd::set_enabled(true);
    if !cramp::simd::enabled() {
        println!("this CPU has no AVX2: only the baseline code ran");
    }
    let wide = bits(&run_in_pool(2));
    let first_diff = baseline.iter().zip(&wide).position(|(a, b)| a != b);
    assert_eq!(first_diff, None, "AVX2 code differs from baseline at value {first_diff:?}");
    assert_eq!(baseline.len(), wide.len());
}

/// The same with the damping acting on the particle velocities (`damping_on =
/// "particles"`), whose extra dissipation is one more sum over all particles.
#[test]
fn particle_damping_gives_identical_bits_on_one_and_two_threads() {
    let with_particle_damping = || {
        let mut sc = scene();
        assert!(sc.solver.damping > 0.0);
        sc.solver.damping_on = cramp::simulation::DampingOn::Particles;
        sc
    };
    let one = bits(&run_scene_in_pool(1, with_particle_damping()));
    let two = bits(&run_scene_in_pool(2, with_particle_damping()));
    let first_diff = one.iter().zip(&two).position(|(a, b)| a != b);
    assert_eq!(first_diff, None, "2 threads differ from 1 at value {first_diff:?}");
    // And it is not the grid-damped run.
    assert_ne!(one, bits(&run_in_pool(1)));
}
