//! Run N unchecked steps of a 3D scene (for instruction counts under callgrind and quick
//! timings): `cargo run --release --example steps3d -- SCENE STEPS [THREADS]`.
//! Instructions per particle-step are the difference of two runs with different STEPS
//! divided by (difference of steps × particles): setup and the first steps cancel.
//! The state hash covers every bit of x, v, σ, ε and ∇u: equal hashes, equal bits.
#[path = "common/state_hash.rs"]
mod state_hash;

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    anyhow::ensure!(args.len() >= 3, "usage: steps3d SCENE STEPS [THREADS]");
    let steps: u64 = args[2].parse()?;
    if let Some(t) = args.get(3) {
        rayon::ThreadPoolBuilder::new().num_threads(t.parse()?).build_global()?;
    }
    let scene = cramp::scene3d::Scene3::from_file(std::path::Path::new(&args[1]))?;
    let mut sim = scene.build()?;
    sim.options.checked = false;
    let t = std::time::Instant::now();
    for _ in 0..steps {
        sim.step()?;
    }
    let wall = t.elapsed().as_secs_f64();
    let p = sim.total_momentum();
    let hash = state_hash::state_hash(&sim);
    println!("state hash {hash:016x}");
    let pairs: usize = sim.pairs.count.iter().map(|&c| c as usize).sum();
    println!("{:.2} pairs per particle, {} active nodes", pairs as f64 / sim.particles.len() as f64, sim.nodes.active.len());
    println!(
        "{} particles, {} steps, {:.3} s, {:.3} M particle-steps/s; t = {}, P = {:?}, |P| = {:e}, E = {:?}",
        sim.particles.len(),
        steps,
        wall,
        sim.particles.len() as f64 * steps as f64 / wall / 1e6,
        sim.time,
        p,
        p.norm(),
        sim.energies()
    );
    Ok(())
}
