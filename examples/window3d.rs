//! Instruction counts of a window of steps late in a 3D run, under callgrind:
//! `window3d SCENE WARM STEPS` runs WARM unchecked steps on one thread, then (with
//! `GO_FILE` set) prints "ready" and waits for that file, runs STEPS more steps, prints
//! "done" and waits for `GO_FILE.done`, then prints the state hash of `steps3d`.
//! `scripts/window3d.sh` starts it under callgrind without instrumentation and switches
//! instrumentation on at "ready" and off at "done", so the warm-up runs at near native
//! speed and only the window is counted (rayon's worker thread included, which a
//! `--toggle-collect` on the calling function would miss).
#[path = "common/state_hash.rs"]
mod state_hash;
use std::io::Write;

#[inline(never)]
fn measured(sim: &mut cramp::simulation::Simulation<cramp::dim::D3>, steps: u64) -> anyhow::Result<()> {
    for _ in 0..steps {
        sim.step()?;
    }
    Ok(())
}

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    anyhow::ensure!(args.len() == 4, "usage: window3d SCENE WARM STEPS");
    let (warm, steps): (u64, u64) = (args[2].parse()?, args[3].parse()?);
    rayon::ThreadPoolBuilder::new().num_threads(1).build_global()?;
    let scene = cramp::scene3d::Scene3::from_file(std::path::Path::new(&args[1]))?;
    let mut sim = scene.build()?;
    sim.options.checked = false;
    for _ in 0..warm {
        sim.step()?;
    }
    if let Ok(go) = std::env::var("GO_FILE") {
        println!("ready");
        std::io::stdout().flush()?;
        while !std::path::Path::new(&go).exists() {
            std::thread::sleep(std::time::Duration::from_millis(100));
        }
    }
    measured(&mut sim, steps)?;
    if let Ok(go) = std::env::var("GO_FILE") {
        println!("done");
        std::io::stdout().flush()?;
        let done = format!("{go}.done");
        while !std::path::Path::new(&done).exists() {
            std::thread::sleep(std::time::Duration::from_millis(100));
        }
    }
    let hash = state_hash::state_hash(&sim);
    println!("state hash {hash:016x} after {} steps", warm + steps);
    Ok(())
}
