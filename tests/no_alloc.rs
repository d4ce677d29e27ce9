//! No allocation inside the time step (issue 6: "Profile that scene and remove waste: …
//! no allocation inside the time step").
//!
//! Reference: the design contract of src/step.rs — every per-step buffer lives in the
//! simulation (`pairs`, `nodes`, `scratch`) and is reused, so once the buffers have grown
//! to the scene's size, `Simulation::step` calls the allocator zero times. Tolerance:
//! none (a count of 0).
//!
//! A counting global allocator (tests/common/counting_alloc.rs) wraps `std::alloc::System`
//! and counts `alloc`, `alloc_zeroed` and `realloc` calls while a flag is set. The scene is the performance
//! scene verification/dcb_perf.toml (9600 particles, a crack, uGIMP, USAVG, damping, end
//! loads), unchecked and checked; after a warm-up the next steps are counted, one
//! `sim.step()` at a time, inside a 1-thread and a 2-thread rayon pool (the whole loop
//! runs inside `install`, so no job is injected from outside the pool during the
//! count). Only `step()` is measured: J/K evaluation at history rows (`fracture_parameters`,
//! outside the step) may allocate, and the scene requests none.
//!
//! Found and fixed (issue 6): every allocation in the step came from the fallback of
//! `cramp::exact::ExactSum`, whose Shewchuk partials lived in a `Vec` — the exact redo
//! of a gather the certified fast sum declines (terms over more than 64 binades, as
//! ahead of a wave front: 13–49 calls per step unchecked), and in checked mode also the
//! partition-of-unity and total-mass sums (1865–2320 calls per step). The fallback is
//! now a fixed-size accumulator stored inline (same bits: both are correctly rounded).
//! Rayon allocated nothing in these steps, with 1 or 2 threads. (Counting every step of
//! the scene's 1 ms after the warm-up, 2600 steps, also gave 0 in all four runs.)
//!
//! Everything runs in one `#[test]` so no other test thread allocates during a count.
//! Set `CRAMP_ALLOC_TRACE=1` to print a backtrace of each counted allocation (the first
//! few), which names the allocating site.

#[path = "common/counting_alloc.rs"]
mod counting_alloc;

use counting_alloc::{count_each, print_allocation_sites, trace_if_requested};

const WARMUP: usize = 20;
const COUNTED: usize = 20;

fn scene(checked: bool) -> cramp::scene::Scene {
    scene_with_zone(checked, 0.0)
}

fn scene_with_zone(checked: bool, zone: f64) -> cramp::scene::Scene {
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/verification/dcb_perf.toml")).unwrap();
    let mut scene = cramp::scene::Scene::from_toml(&text, "verification/dcb_perf.toml").unwrap();
    scene.solver.checked = checked;
    scene.solver.tip_zone = zone;
    scene
}

/// Allocator calls of each of the counted steps, after the warm-up, in a pool of `threads`.
fn allocations_per_step(threads: usize, checked: bool) -> Vec<u64> {
    allocations_per_step_of(threads, scene(checked))
}

fn allocations_per_step_of(threads: usize, scene: cramp::scene::Scene) -> Vec<u64> {
    let checked = scene.solver.checked;
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
    pool.install(|| {
        assert_eq!(rayon::current_num_threads(), threads);
        let mut sim = scene.build().unwrap();
        assert_eq!(sim.particles.len(), 9600);
        assert!(sim.has_cracks() && sim.options.checked == checked && sim.options.damping > 0.0 && !sim.loads.is_empty());
        for _ in 0..WARMUP {
            sim.step().unwrap();
        }
        let counts = count_each(COUNTED, || sim.step());
        // The run did something: the arms are opening.
        let c = &sim.cracks[0];
        assert!(sim.energies().strain > 0.0 && (0..c.points.len()).any(|k| c.opening_nt(k).0 > 0.0));
        counts
    })
}

#[test]
fn the_time_step_does_not_allocate() {
    trace_if_requested();
    let mut failures = Vec::new();
    for checked in [false, true] {
        for threads in [1, 2] {
            let counts = allocations_per_step(threads, checked);
            let total: u64 = counts.iter().sum();
            eprintln!("checked = {checked}, {threads} thread(s): allocator calls per step {counts:?}");
            if total != 0 {
                failures.push(format!("checked = {checked}, {threads} thread(s): {total} allocator calls in {COUNTED} steps {counts:?}"));
            }
        }
    }
    // The same with a crack-tip zone (`solver.tip_zone = 1`, src/crack/tip_zone.rs): the
    // zones of each step reuse the last step's entries. In this test, not a second one:
    // the counting allocator is global, and tests of one binary run side by side.
    let counts = allocations_per_step_of(1, scene_with_zone(false, 1.0));
    let total: u64 = counts.iter().sum();
    eprintln!("tip zone, 1 thread: allocator calls per step {counts:?}");
    if total != 0 {
        failures.push(format!("tip zone, 1 thread: {total} allocator calls in {COUNTED} steps {counts:?}"));
    }
    print_allocation_sites();
    assert!(failures.is_empty(), "{failures:#?}");
}
