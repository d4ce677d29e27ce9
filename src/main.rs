//! The `cramp` command.

use clap::{Parser, Subcommand};
use cramp::output::{prepare_out_dir, run_scene, RunOptions, RunStatus};
use cramp::scene::{Scene, DEFAULT_SCENE};
use cramp::scene3d::{AnyScene, Scene3};
use cramp::scene_override::Override;
use cramp::verify::{self, compare, Variant};
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::AtomicBool;
use std::sync::Arc;

#[derive(Parser)]
#[command(
    name = "cramp",
    version,
    about = "Reference MPM with explicit cracks (CRAMP): run scenes, verify, compare",
    long_about = "Reference MPM with explicit cracks (CRAMP): run scenes, verify, compare.\n\n\
                  Without a command, runs the quick verification suite into reports/ (as `cramp verify --quick`)."
)]
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
        /// Worker threads, 1 to 1024 (default: all cores, or RAYON_NUM_THREADS). Results
        /// are bit-identical for any number; more than the cores only adds overhead.
        #[arg(long, value_parser = clap::value_parser!(u32).range(1..=MAX_THREADS as i64))]
        threads: Option<u32>,
        /// If the output directory holds an earlier run's files, delete those (cramp's own
        /// files only) instead of refusing to run.
        #[arg(long)]
        force: bool,
        /// Override a scene field, PATH=VALUE with a dotted path and a TOML value
        /// (`--set grid.cell=[0.5,0.5] --set cracks.0.contact=none`); repeatable. See docs/scene.md.
        #[arg(long = "set", value_name = "PATH=VALUE")]
        set: Vec<String>,
    },
    /// Run the verification cases: a table on stdout, reports/index.md with plots,
    /// reports/results.json; exit status 1 if any case fails.
    Verify {
        /// The quick suite (coarse cells, minutes) instead of the full one.
        #[arg(long)]
        quick: bool,
        /// Report directory.
        #[arg(long, default_value = "reports")]
        out: PathBuf,
        /// List the cases with their titles and exit.
        #[arg(long)]
        list: bool,
        /// Run the cases and write every scene they ran, overrides applied, into DIR
        /// (DIR/<case>/NN_<file>__<variant>.toml and DIR/index.csv), so that `cramp run`
        /// (or another code) runs exactly the same inputs. See docs/compare.md.
        #[arg(long, value_name = "DIR")]
        export: Option<PathBuf>,
        /// Cases to run (default: every case of the suite).
        cases: Vec<String>,
    },
    /// Compare two runs' history.csv and particle snapshots field by field; exit status 0
    /// iff every value agrees, |a − b| ≤ atol + rtol·|b| (default: bit-identical). See docs/compare.md.
    Compare {
        /// The run to check (directory with history.csv and *.vtk).
        run_a: PathBuf,
        /// The reference run.
        run_b: PathBuf,
        /// Relative tolerance.
        #[arg(long, default_value_t = 0.0)]
        rtol: f64,
        /// Absolute tolerance.
        #[arg(long, default_value_t = 0.0)]
        atol: f64,
    },
    /// Run the embedded demo scene (two colliding disks) into out/demo/ (replacing an
    /// earlier demo run there).
    Demo,
    /// Solve a scene statically: Q4 elements (2D) or hex8 (3D scene); fea.vtk, fea_gauss.vtk,
    /// fea_nodes.csv, probe CSVs and fea_summary.json (J, K per crack tip in 2D) in --out.
    Fea {
        /// Scene file (TOML).
        scene: PathBuf,
        /// Output directory (default: out/<scene name>-fea).
        #[arg(long)]
        out: Option<PathBuf>,
        /// If the output directory holds an earlier run's files, delete those (cramp's own
        /// files only) instead of refusing to run.
        #[arg(long)]
        force: bool,
        /// Override a scene field, PATH=VALUE (as for `cramp run`); repeatable.
        #[arg(long = "set", value_name = "PATH=VALUE")]
        set: Vec<String>,
    },
}

/// Print to stdout. A closed stdout (`cramp run … | head -1`) loses the text, which nobody
/// reads, rather than panicking as `print!` does.
macro_rules! out {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = write!(std::io::stdout(), $($arg)*);
    }};
}

/// [`out!`] with a newline.
macro_rules! outln {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stdout(), $($arg)*);
    }};
}

/// Exit status of `cramp compare` when the runs cannot be compared (bad input).
const EXIT_BAD_INPUT: u8 = 2;

/// Exit status of a run stopped by SIGINT or SIGTERM (128 + SIGINT, the shell's convention).
const EXIT_INTERRUPTED: u8 = 130;

/// Upper bound of `--threads`: more OS threads than this only costs memory and start-up.
const MAX_THREADS: u32 = 1024;

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Some(Command::Run { scene, out, unchecked, threads, force, set }) => set_threads(threads).and_then(|()| run(scene, out, unchecked, force, &set)),
        Some(Command::Fea { scene, out, force, set }) => fea(scene, out, force, &set).map(|()| ExitCode::SUCCESS),
        Some(Command::Demo) => run_demo(),
        Some(Command::Verify { quick, out, list, export, cases }) => {
            let variant = if quick { Variant::Quick } else { Variant::Full };
            if list {
                list_cases()
            } else if let Some(dir) = export {
                export_scenes(variant, &dir, &cases)
            } else {
                run_verify(variant, &out, &cases)
            }
        }
        Some(Command::Compare { run_a, run_b, rtol, atol }) => match compare::compare_runs(&run_a, &run_b, compare::Tolerance { rtol, atol }) {
            Ok(c) => {
                out!("{}", c.render());
                Ok(if c.agree() { ExitCode::SUCCESS } else { ExitCode::FAILURE })
            }
            Err(e) => {
                eprintln!("error: cannot compare the runs: {e:#}");
                return ExitCode::from(EXIT_BAD_INPUT);
            }
        },
        None => {
            eprintln!("cramp: no command given; running the quick verification suite (`cramp verify --quick`). See `cramp --help`.");
            run_verify(Variant::Quick, Path::new("reports"), &[])
        }
    };
    match result {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}

fn list_cases() -> anyhow::Result<ExitCode> {
    let m = verify::manifest::Manifest::get()?;
    for name in verify::case_names() {
        let c = m.case(name);
        let suite = if c.map(|c| c.quick.is_some()).unwrap_or(false) { "quick+full" } else { "full only " };
        outln!("{name:<18} {suite}  {}", c.map(|c| c.title.as_str()).unwrap_or("(no manifest entry)"));
    }
    Ok(ExitCode::SUCCESS)
}

/// Run the cases and write every scene they ran into `dir`.
fn export_scenes(variant: Variant, dir: &Path, names: &[String]) -> anyhow::Result<ExitCode> {
    let cases = verify::select(names, variant)?;
    let mut results = Vec::new();
    for case in &cases {
        eprint!("{:<18} ... ", case.name);
        let r = verify::run_case(case, variant);
        eprintln!("{} simulation(s) ({:.1} s)", r.simulations.len(), r.wall_s);
        results.push(r);
    }
    let written = verify::scene_file::export(dir, &results)?;
    outln!("{} scene file(s) in {} (index: {})", written.len(), dir.display(), dir.join("index.csv").display());
    Ok(ExitCode::SUCCESS)
}

/// Run the cases, print the table, write the report; exit status 1 if any case failed.
fn run_verify(variant: Variant, out: &Path, names: &[String]) -> anyhow::Result<ExitCode> {
    let cases = verify::select(names, variant)?;
    let start = std::time::Instant::now();
    let mut results = Vec::new();
    for case in &cases {
        eprint!("{:<18} ... ", case.name);
        let r = verify::run_case(case, variant);
        eprintln!("{} ({:.1} s)", if r.passed { "pass" } else { "FAIL" }, r.wall_s);
        results.push(r);
    }
    let total = start.elapsed().as_secs_f64();
    outln!("{}", verify::report::text_table(&results));
    let problems = verify::report::write_report(out, &results, variant, total)?;
    for p in &problems {
        eprintln!("warning: {p}");
    }
    let failed: Vec<&str> = results.iter().filter(|r| !r.passed).map(|r| r.name.as_str()).collect();
    outln!(
        "{} of {} cases passed in {total:.1} s; report in {}",
        results.len() - failed.len(),
        results.len(),
        out.join("index.md").display()
    );
    if failed.is_empty() {
        Ok(ExitCode::SUCCESS)
    } else {
        outln!("FAILED: {}", failed.join(", "));
        Ok(ExitCode::FAILURE)
    }
}

/// Size the global thread pool (before any parallel work).
fn set_threads(threads: Option<u32>) -> anyhow::Result<()> {
    if let Some(n) = threads {
        let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
        if n as usize > cores {
            eprintln!("warning: --threads {n} is more than the {cores} core(s) of this machine: the results are the same, the run slower");
        }
        rayon::ThreadPoolBuilder::new().num_threads(n as usize).build_global()?;
    }
    Ok(())
}

/// Read a scene file with `--set` overrides.
fn read_scene(path: &Path, set: &[String]) -> anyhow::Result<AnyScene> {
    let overrides = set.iter().map(|s| Override::parse(s)).collect::<Result<Vec<_>, _>>()?;
    Ok(cramp::scene_override::scene_file_with(path, &overrides)?)
}

fn run(scene_path: PathBuf, out: Option<PathBuf>, unchecked: bool, force: bool, set: &[String]) -> anyhow::Result<ExitCode> {
    let stem = scene_path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_else(|| "run".into());
    let out = out.unwrap_or_else(|| PathBuf::from("out").join(stem));
    match read_scene(&scene_path, set)? {
        AnyScene::D2(scene) => execute(&scene, out, unchecked, force),
        AnyScene::D3(scene) => execute_3d(&scene, out, unchecked, force),
    }
}

fn fea(scene_path: PathBuf, out: Option<PathBuf>, force: bool, set: &[String]) -> anyhow::Result<()> {
    let scene = read_scene(&scene_path, set)?;
    let stem = scene_path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_else(|| "run".into());
    let out = out.unwrap_or_else(|| PathBuf::from("out").join(format!("{stem}-fea")));
    prepare_out_dir(&out, force)?;
    match scene {
        AnyScene::D2(scene) => out!("{}", cramp::fea::run::run_fea(&scene, Some(&out))?.text()),
        AnyScene::D3(scene) => out!("{}", cramp::fea::run3::run_fea_3d(&scene, Some(&out))?.text()),
    }
    Ok(())
}

fn run_demo() -> anyhow::Result<ExitCode> {
    let scene = Scene::from_toml(DEFAULT_SCENE, "embedded demo scene")?;
    eprintln!("cramp: running the embedded demo scene ({}).", scene.title);
    execute(&scene, PathBuf::from("out/demo"), false, true)
}

/// The first SIGINT or SIGTERM (or SIGQUIT) sets the returned flag, which stops the run at
/// the end of its current step; a second one ends the process at once (exit status 130).
///
/// signal-hook (rather than ctrlc) because its `flag` module is exactly this pattern — an
/// `AtomicBool` the handler sets, polled between steps, with no thread and no handler code
/// of ours running in signal context — and `register_conditional_shutdown` gives the
/// "second signal exits" behaviour without extra state; it is the crate tokio and ctrlc's
/// peers build on, and adds one small dependency (signal-hook-registry).
fn stop_on_signals() -> anyhow::Result<Arc<AtomicBool>> {
    let stop = Arc::new(AtomicBool::new(false));
    for &signal in signal_hook::consts::TERM_SIGNALS {
        // The shutdown is registered first so that it acts only once `stop` is already set.
        signal_hook::flag::register_conditional_shutdown(signal, EXIT_INTERRUPTED as i32, Arc::clone(&stop))?;
        signal_hook::flag::register(signal, Arc::clone(&stop))?;
    }
    Ok(stop)
}

fn execute(scene: &Scene, out: PathBuf, unchecked: bool, force: bool) -> anyhow::Result<ExitCode> {
    for w in cramp::output::output_intervals(scene, scene.time_step()).warnings.into_iter().chain(scene.warnings()) {
        eprintln!("warning: {w}");
    }
    let opts = RunOptions {
        out_dir: Some(out.clone()),
        progress: std::io::stderr().is_terminal(),
        checked: unchecked.then_some(false),
        force,
        stop: Some(stop_on_signals()?),
    };

    let r = run_scene(scene, &opts)?;
    let s = &r.summary;
    let e = &s.final_energies;
    outln!(
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
    outln!(
        "final energies: kinetic {:.6e}, strain {:.6e}, external work {:.6e}, boundary work {:.6e}, damping {:.6e}, total {:.6e}",
        e.kinetic, e.strain, e.external_work, e.boundary_work, e.damping, e.total
    );
    outln!("outputs in {}", out.display());
    if s.status == RunStatus::Interrupted {
        eprintln!(
            "cramp: interrupted after step {} (t = {:e}); the outputs up to then and summary.json (status \"interrupted\") are in {}",
            s.steps,
            s.end_time,
            out.display()
        );
        return Ok(ExitCode::from(EXIT_INTERRUPTED));
    }
    Ok(ExitCode::SUCCESS)
}

fn execute_3d(scene: &Scene3, out: PathBuf, unchecked: bool, force: bool) -> anyhow::Result<ExitCode> {
    for w in scene.warnings() {
        eprintln!("warning: {w}");
    }
    let opts = RunOptions {
        out_dir: Some(out.clone()),
        progress: std::io::stderr().is_terminal(),
        checked: unchecked.then_some(false),
        force,
        stop: Some(stop_on_signals()?),
    };
    let r = cramp::output::three_d::run_scene_3d(scene, &opts)?;
    let s = &r.summary;
    let e = &s.final_energies;
    outln!(
        "{} (3D): {} particles, {} nodes, {} steps of dt = {:.4e} to t = {:.4e} in {:.3} s ({:.3e} particle-steps/s, {} thread{}{})",
        if scene.title.is_empty() { "scene" } else { &scene.title },
        s.particles,
        s.nodes,
        s.steps,
        s.dt,
        s.end_time,
        s.wall_time_s,
        s.particle_steps_per_second,
        s.threads,
        if s.threads == 1 { "" } else { "s" },
        if s.checked { ", checked" } else { "" }
    );
    outln!(
        "final energies: kinetic {:.6e}, strain {:.6e}, external work {:.6e}, boundary work {:.6e}, damping {:.6e}, total {:.6e}",
        e.kinetic, e.strain, e.external_work, e.boundary_work, e.damping, e.total
    );
    outln!("outputs in {}", out.display());
    if s.status == RunStatus::Interrupted {
        eprintln!("cramp: interrupted after step {} (t = {:e}); outputs and summary.json (status \"interrupted\") are in {}", s.steps, s.end_time, out.display());
        return Ok(ExitCode::from(EXIT_INTERRUPTED));
    }
    Ok(ExitCode::SUCCESS)
}
