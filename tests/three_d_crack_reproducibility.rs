//! Bit identity with 3D cracks and active contact (issue 15, verification 5). Reference:
//! cramp's design contract (src/exact.rs, src/step.rs; tests/three_d_reproducibility.rs
//! and tests/three_d_threads.rs for the crack-free step): the field of every
//! particle–node pair is an exact function of the pair (`crack::crossing3`), nodal sums
//! are correctly rounded, contact acts per node, and the crack points move by per-point
//! interpolation — so neither the particle order nor the thread count may change a bit.
//! Tolerance: none (`f64::to_bits` equality of every particle's x, v, σ, ε, ∇u, the
//! energies and total momentum, and every crack point and both crack surfaces).
//!
//! Scene: `verification/crack_friction_3d.toml` (a block cut by an inclined crack plane,
//! the part above pressed onto the part below with Coulomb friction μ = 0.3 and pushed
//! along the plane), checked mode. Contact acts from the first step (the load presses
//! the faces together); the run with contact = "none" must differ, which shows it does.

mod common;

use common::{global_bits_3d, lcg_permutation, particle_bits_3d};
use cramp::dim::D3;
use cramp::scene::ContactSpec;
use cramp::simulation::Simulation;
use cramp::verify::cases::crack_friction_3d::{scene, MU, NORMAL_LOAD};

/// The sliding run of the case at cells of `h` mm, with the crack's contact law.
fn build(h: f64, contact: ContactSpec) -> Simulation<D3> {
    let mut s = scene(h, MU, 2.0 * MU * NORMAL_LOAD).expect("scene");
    s.cracks[0].contact = contact;
    let sim = s.build().expect("build");
    assert!(sim.options.checked);
    sim
}

/// Bits of every particle (by id), the globals, and the crack points and surfaces.
fn bits(sim: &Simulation<D3>) -> Vec<u64> {
    let mut idx = vec![usize::MAX; sim.particles.len()];
    for (k, &id) in sim.particles.id.iter().enumerate() {
        idx[id as usize] = k;
    }
    let mut out: Vec<u64> = idx.iter().flat_map(|&k| particle_bits_3d(sim, k)).collect();
    out.extend(global_bits_3d(sim));
    let c = &sim.cracks[0];
    for set in [&c.surface.vertices, &c.above, &c.below] {
        out.extend(set.iter().flat_map(|v| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>()));
    }
    out
}

fn run(mut sim: Simulation<D3>, steps: usize) -> Vec<u64> {
    for _ in 0..steps {
        sim.step().expect("step");
    }
    bits(&sim)
}

fn first_difference(a: &[u64], b: &[u64]) -> Option<usize> {
    assert_eq!(a.len(), b.len());
    a.iter().zip(b).position(|(x, y)| x != y)
}

#[test]
fn shuffled_particles_give_identical_bits_with_a_crack_in_contact() {
    const STEPS: usize = 40;
    let friction = ContactSpec::Friction { mu: MU };
    let a = build(1.0, friction.clone());
    let mut b = a.clone();
    let perm = lcg_permutation(b.particles.len(), 1515);
    assert!(perm.iter().enumerate().any(|(k, &p)| k != p));
    b.particles.permute(&perm);
    let (ra, rb) = (run(a, STEPS), run(b, STEPS));
    let d = first_difference(&ra, &rb);
    assert_eq!(d, None, "the shuffled run differs at value {d:?}");
    // Contact acted: without it the faces interpenetrate and every bit moves.
    let none = run(build(1.0, ContactSpec::None), STEPS);
    assert!(first_difference(&ra, &none).is_some(), "contact changed nothing");
}

#[test]
fn one_and_two_threads_give_identical_bits_with_a_crack_in_contact() {
    // 0.5 mm cells: 23,040 particles, so the pair lists are built in several chunks.
    const STEPS: usize = 8;
    let in_pool = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| {
            let sim = build(0.5, ContactSpec::Friction { mu: MU });
            assert!(sim.particles.len() > 4 * 4096, "{} particles", sim.particles.len());
            run(sim, STEPS)
        })
    };
    let one = in_pool(1);
    let d = first_difference(&one, &in_pool(2));
    assert_eq!(d, None, "2 threads differ from 1 at value {d:?}");
}

/// Bit identity with a growing 3D crack (issue 17): the extruded SENT of case
/// `front_growth_slab` with K_Ic lowered to 0.5 MPa√mm so the front starts to grow near
/// step 60 and makes several increments by step 85. Shuffled particles, and 1 against 2
/// threads, must give the same bits of every particle, every crack point and surface, and
/// every growth record (node, position, J, K, direction, advance).
#[test]
fn growing_front_is_bit_identical_for_any_particle_order_and_thread_count() {
    use cramp::verify::scene_file::SceneFile;
    const STEPS: usize = 85;
    let build = || SceneFile::new("front_growth_3d.toml").set("materials.0.toughness.kic", "0.5").load3().unwrap().build().unwrap();
    let growth_bits = |sim: &Simulation<D3>| -> Vec<u64> {
        let g = sim.growth.as_ref().expect("the scene grows");
        g.records
            .iter()
            .flat_map(|r| {
                let mut w = vec![r.step, r.label as u64, r.vertex as u64, r.grew as u64];
                w.extend([r.x.x, r.x.y, r.x.z, r.advance, r.speed, r.j1, r.j2, r.k[0], r.k[1], r.k[2], r.theta, r.k_eq, r.heading.x, r.heading.y, r.heading.z].map(f64::to_bits));
                w
            })
            .collect()
    };
    let run_all = |mut sim: Simulation<D3>| -> (Vec<u64>, Vec<u64>, usize) {
        for _ in 0..STEPS {
            sim.step().expect("step");
        }
        let grew = sim.growth.as_ref().unwrap().records.iter().filter(|r| r.grew).count();
        (bits(&sim), growth_bits(&sim), grew)
    };
    let a = build();
    let mut b = a.clone();
    let perm = lcg_permutation(b.particles.len(), 1717);
    b.particles.permute(&perm);
    let (ra, ga, grew) = run_all(a);
    assert!(grew >= 10, "only {grew} node moves: the test would not exercise growth");
    let (rb, gb, _) = run_all(b);
    assert_eq!(first_difference(&ra, &rb), None, "the shuffled run's state differs");
    assert_eq!(first_difference(&ga, &gb), None, "the shuffled run's growth records differ");
    let in_pool = |threads: usize| rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap().install(|| run_all(build()));
    let (r1, g1, _) = in_pool(1);
    let (r2, g2, _) = in_pool(2);
    assert_eq!(first_difference(&r1, &r2), None, "2 threads differ from 1 (state)");
    assert_eq!(first_difference(&g1, &g2), None, "2 threads differ from 1 (growth records)");
    assert_eq!(first_difference(&ra, &r1), None, "the pooled run differs from the plain one");
}
