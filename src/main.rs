//! The `cramp` command.

use clap::{Parser, Subcommand};
use cramp::output::{run_scene, RunOptions};
use cramp::scene::{Scene, DEFAULT_SCENE};
use std::io::IsTerminal;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Parser)]
#[command(name = "cramp", version, about = "Reference MPM with explicit cracks (CRAMP): run scenes, verify, compare")]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand)]
enum Command {
    /// Run a scene: history.csv, summary.json and VTK snapshots in --out.
    Run {
        /// Scene file (TOML).
        scene: PathBuf,
        /// Output directory (default: out/<scene name>).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Switch the invariant checks off for speed (overrides solver.checked).
        #[arg(long)]
        unchecked: bool,
        /// Worker threads (default: all cores, or RAYON_NUM_THREADS). Results are
        /// bit-identical for any number.
        #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
        threads: Option<u32>,
    },
    /// Solve a scene statically with the Q4 FEA: fea.vtk, fea_gauss.vtk, fea_nodes.csv,
    /// probe CSVs and fea_summary.json (J, K per crack tip) in --out.
    Fea {
        /// Scene file (TOML).
        scene: PathBuf,
        /// Output directory (default: out/<scene name>-fea).
        #[arg(long)]
        out: Option<PathBuf>,
    },
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Some(Command::Run { scene, out, unchecked, threads }) => set_threads(threads).and_then(|()| run(scene, out, unchecked)),
        Some(Command::Fea { scene, out }) => fea(scene, out),
        None => run_default(),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}

/// Size the global thread pool (before any parallel work).
fn set_threads(threads: Option<u32>) -> anyhow::Result<()> {
    if let Some(n) = threads {
        rayon::ThreadPoolBuilder::new().num_threads(n as usize).build_global()?;
    }
    Ok(())
}

fn run(scene_path: PathBuf, out: Option<PathBuf>, unchecked: bool) -> anyhow::Result<()> {
    let scene = Scene::from_file(&scene_path)?;
    let stem = scene_path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_else(|| "run".into());
    let out = out.unwrap_or_else(|| PathBuf::from("out").join(stem));
    execute(&scene, out, unchecked)
}

fn fea(scene_path: PathBuf, out: Option<PathBuf>) -> anyhow::Result<()> {
    let scene = Scene::from_file(&scene_path)?;
    let stem = scene_path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_else(|| "run".into());
    let out = out.unwrap_or_else(|| PathBuf::from("out").join(format!("{stem}-fea")));
    print!("{}", cramp::fea::run::run_fea(&scene, Some(&out))?.text());
    Ok(())
}

fn run_default() -> anyhow::Result<()> {
    let scene = Scene::from_toml(DEFAULT_SCENE, "embedded demo scene")?;
    eprintln!("cramp: no command given; running the embedded demo scene ({}). See `cramp --help`.", scene.title);
    execute(&scene, PathBuf::from("out/demo"), false)
}

fn execute(scene: &Scene, out: PathBuf, unchecked: bool) -> anyhow::Result<()> {
    let opts = RunOptions { out_dir: Some(out.clone()), progress: std::io::stderr().is_terminal(), checked: unchecked.then_some(false) };
    let r = run_scene(scene, &opts)?;
    let s = &r.summary;
    let e = &s.final_energies;
    println!(
        "{}: {} particles, {} steps of dt = {:.4e} to t = {:.4e} in {:.3} s ({:.3e} particle-steps/s, {} thread{}{})",
        if scene.title.is_empty() { "scene" } else { &scene.title },
        s.particles,
        s.steps,
        s.dt,
        s.end_time,
        s.wall_time_s,
        s.particle_steps_per_second,
        s.threads,
        if s.threads == 1 { "" } else { "s" },
        if s.checked { ", checked" } else { "" }
    );
    println!(
        "final energies: kinetic {:.6e}, strain {:.6e}, external work {:.6e}, damping {:.6e}, total {:.6e}",
        e.kinetic, e.strain, e.external_work, e.damping, e.total
    );
    println!("outputs in {}", out.display());
    Ok(())
}
