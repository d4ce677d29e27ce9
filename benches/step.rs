//! Timing of the MPM step on the performance scene of issue 6, the DCB of
//! verification/dcb_perf.toml (9600 particles, 1 mm cells, uGIMP, USAVG, with the crack),
//! and its crack-free twin verification/dcb_perf_half.toml (4800 particles): the whole
//! step with and without the crack (crack overhead per particle-step), particle-to-grid,
//! grid update, grid-to-particle, crack field assignment, contact, and exact vs naive
//! summation of the same nodal terms. Throughput is in particles (= particle-steps for a
//! whole step) or terms per second.
//!
//! Quick by design (10 samples, 0.3 s warm-up, 1 s measurement, no plots): run
//! `RAYON_NUM_THREADS=1 cargo bench --bench step` for the single-core figures; the
//! `whole_step_2_threads` group uses its own 2-thread pool. The states are those after
//! 200 steps (0.076 ms, the stress waves have crossed the beam), checked mode off.
//! Wall-clock figures on a shared machine are noisy; compare with callgrind counts.
//!
//! Measured 2026-11 (2-core machine shared with other jobs, load 1–4), 1 thread: whole
//! step 3.9 ms on the DCB (2.5 M particle-steps/s) and 2.4 ms on the twin; node sums of
//! the Task 1 terms: naive 3.2 G terms/s, certified fast 0.46 G/s, exact fixed point
//! 0.087 G/s. The 2-thread group needs an idle second core to mean anything.
//!
//! Measured 2026-12-01 (idle 2-core VM, `RAYON_NUM_THREADS=1`): whole step 2.57 ms on the
//! DCB (3.74 M particle-steps/s) and 1.20 ms on the twin (4.00 M/s per particle-step, so
//! the crack costs 7 % against the twin); 2-thread pool 1.149 ms (8.35 M/s) and 0.487 ms;
//! stages on the DCB: particle-to-grid 1.07 ms, grid update 0.43 ms, grid-to-particle
//! 0.62 ms, crack field assignment 0.20 ms, contact pass 1.4 µs; J at the tip (outside the
//! step): 2×2 line term 114 µs, two-term 140 µs, the COD fit adds < 1 µs.

use cramp::exact::{Accumulator, ExactSum, FastSum};
use cramp::fracture::jintegral::{CodMethod, TipEnd};
use cramp::scene::Scene;
use cramp::shape::MAX_NODES;
use cramp::simulation::Simulation;
use criterion::{criterion_group, criterion_main, BatchSize, Criterion, Throughput};
use std::hint::black_box;
use std::time::Duration;

fn warm(file: &str) -> Simulation {
    let path = format!("{}/verification/{file}", env!("CARGO_MANIFEST_DIR"));
    let mut sim = Scene::from_file(std::path::Path::new(&path)).unwrap().build().unwrap();
    sim.options.checked = false;
    for _ in 0..200 {
        sim.step().unwrap();
    }
    sim
}

fn quick<'a>(c: &'a mut Criterion, name: &str) -> criterion::BenchmarkGroup<'a, criterion::measurement::WallTime> {
    let mut g = c.benchmark_group(name);
    g.sample_size(10).warm_up_time(Duration::from_millis(300)).measurement_time(Duration::from_secs(1));
    g
}

fn bench_step(c: &mut Criterion) {
    let cracked = warm("dcb_perf.toml");
    let half = warm("dcb_perf_half.toml");
    println!(
        "threads {}, DCB {} particles, twin {} particles, {} / {} active nodes",
        rayon::current_num_threads(),
        cracked.particles.len(),
        half.particles.len(),
        cracked.nodes.active.len(),
        half.nodes.active.len()
    );

    let mut g = quick(c, "whole_step");
    for (name, sim) in [("dcb_crack", &cracked), ("dcb_half_no_crack", &half)] {
        g.throughput(Throughput::Elements(sim.particles.len() as u64));
        let mut s = sim.clone();
        g.bench_function(name, |b| b.iter(|| s.step().unwrap()));
    }
    g.finish();

    let pool = rayon::ThreadPoolBuilder::new().num_threads(2).build().unwrap();
    let mut g = quick(c, "whole_step_2_threads");
    for (name, sim) in [("dcb_crack", &cracked), ("dcb_half_no_crack", &half)] {
        g.throughput(Throughput::Elements(sim.particles.len() as u64));
        let mut s = sim.clone();
        g.bench_function(name, |b| b.iter(|| pool.install(|| s.step().unwrap())));
    }
    g.finish();

    let mut g = quick(c, "stages");
    g.throughput(Throughput::Elements(cracked.particles.len() as u64));
    let mut s = cracked.clone();
    g.bench_function("particle_to_grid", |b| b.iter(|| s.bench_particle_to_grid().unwrap()));
    let mut s = cracked.clone();
    s.bench_particle_to_grid().unwrap();
    // The grid update changes the nodal momenta it reads, so start each run from a copy.
    g.bench_function("grid_update", |b| b.iter_batched_ref(|| s.clone(), |s| s.bench_grid_update().unwrap(), BatchSize::LargeInput));
    let mut s = cracked.clone();
    g.bench_function("grid_to_particle", |b| b.iter(|| s.bench_grid_to_particle()));
    let mut s = cracked.clone();
    g.bench_function("crack_field_assignment", |b| b.iter(|| s.bench_crack_fields().unwrap()));
    let mut s = cracked.clone();
    g.bench_function("contact_pass", |b| b.iter(|| s.bench_contact()));
    g.finish();

    // J and K at the tip (outside the time step: at the history interval, when asked):
    // the 2×2 line contour, the two-term J, and the COD fit.
    let mut g = quick(c, "j_integral");
    for (name, n, area, cod) in [("line_2x2", 2, false, CodMethod::NextToTip), ("two_term_2x2", 2, true, CodMethod::NextToTip), ("line_2x2_cod_fit", 2, false, CodMethod::Fit)] {
        g.bench_function(name, |b| b.iter(|| black_box(cracked.tip_fracture(0, TipEnd::End, n, area, cod, 0.0).unwrap())));
    }
    g.finish();

    // Exact vs naive summation on the terms of Task 1 (m v_x S per pair, by node).
    let (p, pairs) = (&cracked.particles, &cracked.pairs);
    let terms: Vec<Vec<f64>> = cracked
        .nodes
        .active
        .iter()
        .map(|&n| {
            pairs
                .of_node(n as usize)
                .iter()
                .map(|&item| {
                    let (item, pp) = (item as usize, item as usize / MAX_NODES);
                    p.mass[pp] * p.v[pp].x * pairs.s[item]
                })
                .collect()
        })
        .collect();
    let count: usize = terms.iter().map(Vec::len).sum();
    let mut g = quick(c, "node_sums");
    g.throughput(Throughput::Elements(count as u64));
    g.bench_function("naive_f64", |b| b.iter(|| terms.iter().map(|t| t.iter().sum::<f64>()).fold(0.0, |a, x| a + black_box(x))));
    g.bench_function("fast_certified", |b| {
        b.iter(|| {
            terms.iter().fold(0.0, |a, t| {
                let mut f = FastSum::<1>::default();
                t.iter().for_each(|&x| f.add([x]));
                a + black_box(f.certified().map_or(f64::NAN, |v| v[0]))
            })
        })
    });
    g.bench_function("exact_fixed_point", |b| {
        b.iter(|| {
            terms.iter().fold(0.0, |a, t| {
                let mut s = ExactSum::new();
                t.iter().for_each(|&x| s.add(x));
                a + black_box(s.value())
            })
        })
    });
    g.finish();
}

/// The 3D performance scene (verification/dcb_perf_3d.toml: 28,800 particles, 2 mm
/// cells, uGIMP, USAVG, crack-free) after 50 steps, checked mode off: the whole step on 1
/// and 2 threads, and its stages. Throughput in particle-steps per second.
fn bench_step_3d(c: &mut Criterion) {
    let path = format!("{}/verification/dcb_perf_3d.toml", env!("CARGO_MANIFEST_DIR"));
    let scene = cramp::scene3d::Scene3::from_file(std::path::Path::new(&path)).unwrap();
    let mut sim = scene.build().unwrap();
    sim.options.checked = false;
    for _ in 0..50 {
        sim.step().unwrap();
    }
    println!("3D: threads {}, {} particles, {} active nodes of {}", rayon::current_num_threads(), sim.particles.len(), sim.nodes.active.len(), cramp::dim::GridGeometry::num_nodes(&sim.grid));
    let mut g = quick(c, "whole_step_3d");
    g.throughput(Throughput::Elements(sim.particles.len() as u64));
    let mut s = sim.clone();
    g.bench_function("dcb_3d", |b| b.iter(|| s.step().unwrap()));
    let pool = rayon::ThreadPoolBuilder::new().num_threads(2).build().unwrap();
    let mut s = sim.clone();
    g.bench_function("dcb_3d_2_threads", |b| b.iter(|| pool.install(|| s.step().unwrap())));
    g.finish();
    let mut g = quick(c, "stages_3d");
    g.throughput(Throughput::Elements(sim.particles.len() as u64));
    let mut s = sim.clone();
    g.bench_function("particle_to_grid", |b| b.iter(|| s.bench_particle_to_grid().unwrap()));
    let mut s = sim.clone();
    s.bench_particle_to_grid().unwrap();
    g.bench_function("grid_update", |b| b.iter_batched_ref(|| s.clone(), |s| s.bench_grid_update().unwrap(), BatchSize::LargeInput));
    let mut s = sim.clone();
    g.bench_function("grid_to_particle", |b| b.iter(|| s.bench_grid_to_particle()));
    g.finish();
}

/// The 3D crack overhead (issue 15): dcb_perf_3d.toml with the 2D performance DCB's crack
/// extruded — a rectangle on the grid plane y = 0 from x = 50 past the loaded end and both
/// side faces (front x = 50 across the width), contact "none" as in dcb_perf.toml — against
/// the same scene without it, the whole step after 50 steps, checked mode off (run with
/// `RAYON_NUM_THREADS=1`); and the segment–surface field assignment of Task 1 alone, with
/// throughput in particle–node pairs.
///
/// The crack overhead is the ratio of the two `whole_step_3d_crack` throughputs (same
/// particles, so particle-steps per second), as the 2D DCB against its twin.
///
/// Measured 2026-12-02 (callgrind, `examples/steps3d`, 1 thread, instructions per step as
/// the difference of 6- and 2-step runs; host load 7–12, so no wall times): 598 M with
/// the crack against 222 M without, 2.69× (the target is ≤ 1.10×); the lead's
/// main before the 2D ↔ 3D fixes: 601 M. Most of the difference was Task 1's crossing
/// tests (bucket queries, `triangle_verdict`, exact orient3d), then Task 7's node sides
/// and the per-step rebuilds of the triangle index and R*-tree. Branch crk (same bits):
/// 556 M → 315 M at steps 2–6 (1.42×): Task 1 ≈ 292 M → ≈ 67 M, Task 7 ≈ 27 M → ≈ 16.5 M,
/// rebuilds 11.3 M → 5.8 M (README, Performance).
/// Branch ovh2 (same bits): 287.5 M → 268.1 M (1.21×; README, Performance).
/// Branch ovh3 (same bits): 268.1 M → 241.6 M at steps 2–6 (1.094× of 220.9 M); at steps
/// 100–104 550.0 → 553.7 M against 395.2 M (1.40×; README, Performance).
/// Branch ovh4 (`scripts/window3d.sh`, instructions over the window only): steps 101–104
/// 554.1 M against 395.1 M (1.40×) → 433.9 M against 399.4 M (1.086×), steps 3–6 244.9 M
/// against 223.9 M (1.094×): the crack now stays on y = 0 (the mirror-symmetric shape
/// functions of `shape::axis_weights`, which move bits), and Task 1 handles the boxes its
/// plane cuts cheaply (same bits; README, Performance).
fn bench_crack_3d(c: &mut Criterion) {
    let path = format!("{}/verification/dcb_perf_3d.toml", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap();
    let crack = "\n[[cracks]]\nsurface = { polygon = { points = [[50.0, 0.0, -1.0], [50.0, 0.0, 13.0], [102.0, 0.0, 13.0], [102.0, 0.0, -1.0]] } }\ncontact = \"none\"\n";
    let warm3 = |text: &str| {
        let mut sim = cramp::scene3d::Scene3::from_toml(text, "dcb_perf_3d", None).unwrap().build().unwrap();
        sim.options.checked = false;
        for _ in 0..50 {
            sim.step().unwrap();
        }
        sim
    };
    let (cracked, plain) = (warm3(&format!("{text}{crack}")), warm3(&text));
    let pairs: u64 = cracked.pairs.count.iter().map(|&n| n as u64).sum();
    println!("3D crack: threads {}, {} particles, {} pairs, {} crack triangles", rayon::current_num_threads(), cracked.particles.len(), pairs, cracked.cracks[0].surface.triangles.len());
    let mut g = quick(c, "whole_step_3d_crack");
    g.throughput(Throughput::Elements(cracked.particles.len() as u64));
    for (name, sim) in [("dcb_3d_crack", &cracked), ("dcb_3d_no_crack", &plain)] {
        let mut s = sim.clone();
        g.bench_function(name, |b| b.iter(|| s.step().unwrap()));
    }
    g.finish();
    let mut g = quick(c, "crack_fields_3d");
    g.throughput(Throughput::Elements(pairs));
    let mut s = cracked.clone();
    g.bench_function("field_assignment", |b| b.iter(|| s.bench_crack_fields().unwrap()));
    g.finish();
}

criterion_group!(benches, bench_step, bench_step_3d, bench_crack_3d);
criterion_main!(benches);
