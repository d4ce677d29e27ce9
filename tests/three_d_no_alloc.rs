//! No allocation inside the 3D time step (issue 14: the 3D step is the same generic code
//! as the 2D one, whose allocation-free step tests/no_alloc.rs guards, issue 6).
//!
//! Reference: the design contract of src/step.rs — every per-step buffer lives in the
//! simulation (`pairs`, `nodes`, `scratch`) and is reused, so once the buffers have grown
//! to the scene's size, `Simulation::step` calls the allocator zero times. Tolerance:
//! none (a count of 0).
//!
//! The counting global allocator of tests/no_alloc.rs (tests/common/counting_alloc.rs; a
//! global allocator needs its own test binary): it wraps `std::alloc::System` and counts `alloc`, `alloc_zeroed` and
//! `realloc` calls while a flag is set. The scene is `common::loaded_3d_fine()` (5,700
//! particles in two bodies, uGIMP's 27-node stencil, USAVG, rollers on a node plane and
//! a node box, a ramped load, a body force, grid damping; more than 4096 particles, so
//! 2 threads build the pair lists in 2 chunks), unchecked and checked; after a warm-up
//! the next steps are counted, one `sim.step()` at a time, inside a 1-thread and a
//! 2-thread rayon pool (the whole loop runs inside `install`). The same with damping on
//! the particles (one more sum over all particles), checked, 2 threads.
//!
//! Everything runs in one `#[test]` so no other test thread allocates during a count.
//! Set `CRAMP_ALLOC_TRACE=1` to print a backtrace of each counted allocation (the first
//! few), which names the allocating site.

mod common;

#[path = "common/counting_alloc.rs"]
mod counting_alloc;

use counting_alloc::{count_each, print_allocation_sites, trace_if_requested};

const WARMUP: usize = 10;
const COUNTED: usize = 10;

/// Allocator calls of each of the counted steps, after the warm-up, in a pool of `threads`.
fn allocations_per_step(threads: usize, checked: bool, damping_on: cramp::simulation::DampingOn) -> Vec<u64> {
    let mut scene = cramp::scene3d::Scene3::from_toml(&common::loaded_3d_fine(), "loaded 3D", None).unwrap();
    scene.solver.checked = checked;
    scene.solver.damping_on = damping_on;
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
    pool.install(|| {
        assert_eq!(rayon::current_num_threads(), threads);
        let mut sim = scene.build().unwrap();
        assert!(sim.particles.len() > 4096);
        assert!(sim.options.checked == checked && sim.options.damping > 0.0 && !sim.loads.is_empty());
        for _ in 0..WARMUP {
            sim.step().unwrap();
        }
        let counts = count_each(COUNTED, || sim.step());
        // The run did something.
        let e = sim.energies();
        assert!(e.strain > 0.0 && e.external_work != 0.0 && e.damping > 0.0, "{e:?}");
        counts
    })
}

#[test]
fn the_3d_time_step_does_not_allocate() {
    use cramp::simulation::DampingOn;
    trace_if_requested();
    let mut failures = Vec::new();
    let runs = [(false, 1, DampingOn::Grid), (false, 2, DampingOn::Grid), (true, 1, DampingOn::Grid), (true, 2, DampingOn::Grid), (true, 2, DampingOn::Particles)];
    for (checked, threads, damping_on) in runs {
        let counts = allocations_per_step(threads, checked, damping_on);
        let total: u64 = counts.iter().sum();
        let what = format!("checked = {checked}, {threads} thread(s), damping on {damping_on:?}");
        eprintln!("{what}: allocator calls per step {counts:?}");
        if total != 0 {
            failures.push(format!("{what}: {total} allocator calls in {COUNTED} steps {counts:?}"));
        }
    }
    print_allocation_sites();
    assert!(failures.is_empty(), "{failures:#?}");
}
