//! Thread-count independence in 3D (issue 14). Reference: cramp's design contract
//! (src/exact.rs, src/step.rs), as in tests/threads.rs: every particle→node and
//! node→particle sum is correctly rounded, and the parallel loops only split independent
//! per-node and per-particle work, so any number of threads must give the bits of one.
//! Tolerance: none (`f64::to_bits` equality).
//!
//! Scene: the loaded 3D scene `common::LOADED_3D` (two bodies, rollers on a node plane and
//! a node box, a ramped load, a body force, grid damping) refined to cells of 1/16 with
//! the box widened to 0.75 × 0.25 × 0.75, 5,700 particles: enough for the particle→node
//! pair lists to be built in 2 chunks (one per 4096 particles, at most one per thread)
//! and for the particle loops to split into many tasks. Checked mode on, 30 steps,
//! run in a 1-, a 2- and a 3-thread rayon pool (3 splits the work unevenly); then every
//! particle's position, velocity, stress, strain and displacement gradient and the
//! energies and total momentum are compared. The same comparison between the AVX2 and
//! the baseline copies of the hot loops (src/simd.rs), which the 3D step uses too.
//! Both comparisons sit in one `#[test]` so that switching the AVX2 copies off cannot
//! overlap the thread-count runs.

mod common;

use common::{global_bits_3d, particle_bits_3d};

const STEPS: usize = 30;

/// All bits of a run of the loaded 3D scene in a pool of `threads` (particles in build order).
fn bits_in_pool(threads: usize) -> Vec<u64> {
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
    pool.install(|| {
        assert_eq!(rayon::current_num_threads(), threads);
        let mut sim = common::build_3d(&common::loaded_3d_fine());
        assert!(sim.options.checked && sim.particles.len() > 4096, "{} particles", sim.particles.len());
        for _ in 0..STEPS {
            sim.step().unwrap_or_else(|e| panic!("{threads} threads: {e}"));
        }
        let e = sim.energies();
        assert!(e.strain > 0.0 && e.external_work != 0.0 && e.damping > 0.0, "{e:?}");
        let mut out: Vec<u64> = (0..sim.particles.len()).flat_map(|k| particle_bits_3d(&sim, k)).collect();
        out.extend(global_bits_3d(&sim));
        out
    })
}

fn first_difference(a: &[u64], b: &[u64]) -> Option<usize> {
    assert_eq!(a.len(), b.len());
    a.iter().zip(b).position(|(x, y)| x != y)
}

#[test]
fn one_two_and_three_threads_and_avx2_give_identical_bits_in_3d() {
    let reference = bits_in_pool(1);
    for threads in [2, 3] {
        let d = first_difference(&reference, &bits_in_pool(threads));
        assert_eq!(d, None, "{threads} threads differ from 1 at value {d:?}");
    }
    let avx2_available = cramp::simd::enabled();
    cramp::simd::set_enabled(false);
    assert!(!cramp::simd::enabled());
    let baseline = bits_in_pool(2);
    cramp::simd::set_enabled(true);
    if !avx2_available {
        println!("this CPU has no AVX2 (or CRAMP_SIMD=off): only the baseline code ran");
    }
    let d = first_difference(&reference, &baseline);
    assert_eq!(d, None, "baseline code differs from {} at value {d:?}", if avx2_available { "AVX2" } else { "baseline" });
}
