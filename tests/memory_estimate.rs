//! The memory estimate a scene is checked against before it is built
//! (`Scene::memory_estimate`, src/budget.rs) bounds what building and stepping the scene
//! really allocates, and is not wildly above it.
//!
//! Reference: the peak of live heap bytes, measured by a counting global allocator while
//! the scene is built and run for a few steps (every per-step buffer has grown by then).
//! Tolerance: the estimate must be at least the peak (it is used to refuse scenes that
//! do not fit, so it must not undercount) and at most 3× the peak (the particle count is
//! bounded by the bodies' boxes, which a disk overfills by 4/π, and the per-item sizes are
//! rounded up). One #[test], so no other test allocates during a measurement.

use cramp::scene::Scene;
use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

struct Peak;

static LIVE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Peak {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let p = System.alloc(layout);
        if !p.is_null() {
            let live = LIVE.fetch_add(layout.size(), Ordering::Relaxed) + layout.size();
            PEAK.fetch_max(live, Ordering::Relaxed);
        }
        p
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        System.dealloc(ptr, layout);
        LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let p = System.realloc(ptr, layout, new_size);
        if !p.is_null() {
            let live = LIVE.fetch_add(new_size, Ordering::Relaxed) + new_size;
            PEAK.fetch_max(live, Ordering::Relaxed);
            LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
        }
        p
    }
}

#[global_allocator]
static GLOBAL: Peak = Peak;

#[test]
fn the_estimate_bounds_the_peak_memory_of_build_and_steps() {
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("verification");
    let mut scenes: Vec<(String, Scene)> =
        ["vibrating_bar", "demo", "crack_patch_full", "cracked_disks", "dcb_perf", "squashed_disk", "delrin_impact"]
            .iter()
            .map(|name| (name.to_string(), Scene::from_file(&dir.join(format!("{name}.toml"))).unwrap()))
            .collect();
    // A large grid around a small body (the nodes dominate), with and without a crack.
    let sparse = |crack: &str| {
        format!(
            "[grid]\norigin = [0.0, 0.0]\nsize = [400.0, 300.0]\ncell = [1.0, 1.0]\n[solver]\nend_time = 1.0\n\
             [[materials]]\nname = \"m\"\nE = 1000.0\nnu = 0.3\nrho = 1.0\nstate = \"plane_strain\"\n\
             [[bodies]]\nmaterial = \"m\"\nshape = {{ rectangle = {{ min = [100.0, 100.0], max = [120.0, 110.0] }} }}\nvelocity = [1.0, 0.0]\n{crack}"
        )
    };
    scenes.push(("sparse grid".into(), Scene::from_toml(&sparse(""), "sparse").unwrap()));
    scenes.push((
        "sparse grid, crack".into(),
        Scene::from_toml(&sparse("[[cracks]]\npoints = [[90.0, 105.0], [110.0, 105.0]]\n"), "sparse").unwrap(),
    ));
    for (name, scene) in scenes {
        let estimate = scene.memory_estimate();
        let peak = pool.install(|| {
            let base = LIVE.load(Ordering::Relaxed);
            PEAK.store(base, Ordering::Relaxed);
            let mut sim = scene.build().unwrap();
            for _ in 0..3 {
                sim.step().unwrap();
            }
            let peak = PEAK.load(Ordering::Relaxed) - base;
            drop(sim);
            peak as f64
        });
        println!(
            "{name:<18} {:>8.0} nodes {:>8} particles (bound {:>8.0}): peak {:>11.0} B, estimate {:>11.0} B, ratio {:.2}",
            estimate.nodes,
            scene.build().unwrap().particles.len(),
            estimate.particles,
            peak,
            estimate.bytes,
            estimate.bytes / peak
        );
        assert!(estimate.bytes >= peak, "{name}: estimate {} below the peak {peak}", estimate.bytes);
        assert!(estimate.bytes <= 3.0 * peak, "{name}: estimate {} above 3× the peak {peak}", estimate.bytes);
    }
}
