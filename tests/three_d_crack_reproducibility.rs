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
