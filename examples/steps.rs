//! Run N unchecked steps of a scene (for instruction counts under callgrind and quick
//! timings): `cargo run --release --example steps -- SCENE STEPS [THREADS]`.
//! Instructions per particle-step are the difference of two runs with different STEPS
//! divided by (difference of steps × particles): setup and the first steps cancel.

#[path = "common/state_hash.rs"]
mod state_hash;

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    anyhow::ensure!(args.len() >= 3, "usage: steps SCENE STEPS [THREADS]");
    let steps: u64 = args[2].parse()?;
    if let Some(t) = args.get(3) {
        rayon::ThreadPoolBuilder::new().num_threads(t.parse()?).build_global()?;
    }
    let scene = cramp::scene::Scene::from_file(std::path::Path::new(&args[1]))?;
    let mut sim = scene.build()?;
    sim.options.checked = false;
    let t = std::time::Instant::now();
    for _ in 0..steps {
        sim.step()?;
    }
    let wall = t.elapsed().as_secs_f64();
    let p = sim.total_momentum();
    // FNV-1a over the bits of the particle state and the cracks: equal hashes, equal bits.
    let mut fnv = state_hash::Fnv::new();
    let mut eat = |x: f64| fnv.eat(x);
    let q = &sim.particles;
    for i in 0..q.len() {
        for x in [q.x[i].x, q.x[i].y, q.v[i].x, q.v[i].y, q.stress[i].xx, q.stress[i].yy, q.stress[i].xy, q.stress[i].zz, q.strain[i].xx, q.strain[i].yy, q.strain[i].zz, q.strain[i].xy] {
            eat(x);
        }
        for x in q.grad_u[i].iter() {
            eat(*x);
        }
    }
    for c in &sim.cracks {
        for v in c.points.iter().chain(&c.above).chain(&c.below) {
            eat(v.x);
            eat(v.y);
        }
    }
    println!("state hash {:016x}", fnv.0);
    println!(
        "{} particles, {} steps, {:.3} s, {:.3} M particle-steps/s; t = {}, P = ({:e}, {:e}), E = {:?}",
        sim.particles.len(),
        steps,
        wall,
        sim.particles.len() as f64 * steps as f64 / wall / 1e6,
        sim.time,
        p.x,
        p.y,
        sim.energies()
    );
    Ok(())
}
