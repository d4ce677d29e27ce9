//! The scenes of the verification cases: every scene a case runs is a file in
//! `verification/` plus overrides ([`crate::scene_override`]), and `cramp verify --export
//! DIR` writes each of them, overrides applied, so that `cramp run` (or a faster code)
//! runs exactly what the case ran.
//!
//! A case names a scene with [`SceneFile::new`]`("dcb.toml")` and its variant with
//! [`SceneFile::set`] (`.set("grid.cell", format!("[{h}, {h}]"))`, the same syntax as
//! `cramp run --set`), then [`SceneFile::load`]s it. While a case runs under
//! [`super::run_case`], every simulation built from a loaded scene remembers the file and
//! overrides ([`crate::fingerprint::SceneSource`]); a scene changed in Rust after loading
//! is recorded without a file, and `tests/golden.rs` fails on it.

use crate::fingerprint::SceneSource;
use crate::scene::Scene;
use crate::scene3d::{AnyScene, Scene3};
use crate::scene_override::{self, Override};
use anyhow::{anyhow, Context};
use std::path::{Path, PathBuf};

/// Every scene file of `verification/`, compiled in so that `cramp verify` works from any
/// directory (a unit test checks the list against the directory).
pub const FILES: &[(&str, &str)] = &[
    ("block_tension_3d.toml", include_str!("../../verification/block_tension_3d.toml")),
    ("cct_plate.toml", include_str!("../../verification/cct_plate.toml")),
    ("cfl_block.toml", include_str!("../../verification/cfl_block.toml")),
    ("chen_cct.toml", include_str!("../../verification/chen_cct.toml")),
    ("chen_cct_3d.toml", include_str!("../../verification/chen_cct_3d.toml")),
    ("colliding_spheres_3d.toml", include_str!("../../verification/colliding_spheres_3d.toml")),
    ("crack_friction.toml", include_str!("../../verification/crack_friction.toml")),
    ("crack_friction_3d.toml", include_str!("../../verification/crack_friction_3d.toml")),
    ("crack_patch_3d_full.toml", include_str!("../../verification/crack_patch_3d_full.toml")),
    ("crack_patch_3d_half.toml", include_str!("../../verification/crack_patch_3d_half.toml")),
    ("crack_patch_full.toml", include_str!("../../verification/crack_patch_full.toml")),
    ("crack_patch_half.toml", include_str!("../../verification/crack_patch_half.toml")),
    ("cracked_disks.toml", include_str!("../../verification/cracked_disks.toml")),
    ("cracked_spheres_3d.toml", include_str!("../../verification/cracked_spheres_3d.toml")),
    ("cracks_2d_3d_dcb_2d.toml", include_str!("../../verification/cracks_2d_3d_dcb_2d.toml")),
    ("cracks_2d_3d_dcb_3d.toml", include_str!("../../verification/cracks_2d_3d_dcb_3d.toml")),
    ("cracks_2d_3d_disks_2d.toml", include_str!("../../verification/cracks_2d_3d_disks_2d.toml")),
    ("cracks_2d_3d_disks_3d.toml", include_str!("../../verification/cracks_2d_3d_disks_3d.toml")),
    ("dcb_growth.toml", include_str!("../../verification/dcb_growth.toml")),
    ("dcb_nairn2003.toml", include_str!("../../verification/dcb_nairn2003.toml")),
    ("dcb_perf.toml", include_str!("../../verification/dcb_perf.toml")),
    ("dcb_perf_3d.toml", include_str!("../../verification/dcb_perf_3d.toml")),
    ("dcb_perf_half.toml", include_str!("../../verification/dcb_perf_half.toml")),
    ("dcb_static.toml", include_str!("../../verification/dcb_static.toml")),
    ("delrin_impact.toml", include_str!("../../verification/delrin_impact.toml")),
    ("demo.toml", include_str!("../../verification/demo.toml")),
    ("extrusion_impact_2d.toml", include_str!("../../verification/extrusion_impact_2d.toml")),
    ("extrusion_impact_3d.toml", include_str!("../../verification/extrusion_impact_3d.toml")),
    ("fea_beam_3d.toml", include_str!("../../verification/fea_beam_3d.toml")),
    ("fea_crack_extrusion_2d.toml", include_str!("../../verification/fea_crack_extrusion_2d.toml")),
    ("fea_crack_extrusion_3d.toml", include_str!("../../verification/fea_crack_extrusion_3d.toml")),
    ("fea_dcb_3d.toml", include_str!("../../verification/fea_dcb_3d.toml")),
    ("fea_extrusion_2d.toml", include_str!("../../verification/fea_extrusion_2d.toml")),
    ("fea_extrusion_3d.toml", include_str!("../../verification/fea_extrusion_3d.toml")),
    ("fea_penny_3d.toml", include_str!("../../verification/fea_penny_3d.toml")),
    ("front_penny_3d.toml", include_str!("../../verification/front_penny_3d.toml")),
    ("front_inclined_3d.toml", include_str!("../../verification/front_inclined_3d.toml")),
    ("front_inclined_aligned_3d.toml", include_str!("../../verification/front_inclined_aligned_3d.toml")),
    ("front_penny_growth_3d.toml", include_str!("../../verification/front_penny_growth_3d.toml")),
    ("front_ellipse_growth_3d.toml", include_str!("../../verification/front_ellipse_growth_3d.toml")),
    ("front_inclined_growth_3d.toml", include_str!("../../verification/front_inclined_growth_3d.toml")),
    ("dcb_growth_3d.toml", include_str!("../../verification/dcb_growth_3d.toml")),
    ("corner_crack_rod_3d.toml", include_str!("../../verification/corner_crack_rod_3d.toml")),
    ("tube_crack_3d.toml", include_str!("../../verification/tube_crack_3d.toml")),
    ("front_growth_2d.toml", include_str!("../../verification/front_growth_2d.toml")),
    ("front_growth_3d.toml", include_str!("../../verification/front_growth_3d.toml")),
    ("front_sent_2d.toml", include_str!("../../verification/front_sent_2d.toml")),
    ("front_sent_3d.toml", include_str!("../../verification/front_sent_3d.toml")),
    ("front_oblique_2d.toml", include_str!("../../verification/front_oblique_2d.toml")),
    ("front_oblique_3d.toml", include_str!("../../verification/front_oblique_3d.toml")),
    ("front_sh_3d.toml", include_str!("../../verification/front_sh_3d.toml")),
    ("front_sh_ramp_3d.toml", include_str!("../../verification/front_sh_ramp_3d.toml")),
    ("growth_strip.toml", include_str!("../../verification/growth_strip.toml")),
    ("hanging_sent.toml", include_str!("../../verification/hanging_sent.toml")),
    ("mode_ii_kink.toml", include_str!("../../verification/mode_ii_kink.toml")),
    ("mpm_vs_fea_3d.toml", include_str!("../../verification/mpm_vs_fea_3d.toml")),
    ("patch_displacement.toml", include_str!("../../verification/patch_displacement.toml")),
    ("patch_displacement_3d.toml", include_str!("../../verification/patch_displacement_3d.toml")),
    ("pmma_tpb.toml", include_str!("../../verification/pmma_tpb.toml")),
    ("ramp_hold_plate.toml", include_str!("../../verification/ramp_hold_plate.toml")),
    ("sent_plate.toml", include_str!("../../verification/sent_plate.toml")),
    ("split_beam.toml", include_str!("../../verification/split_beam.toml")),
    ("squashed_disk.toml", include_str!("../../verification/squashed_disk.toml")),
    ("traction_bending.toml", include_str!("../../verification/traction_bending.toml")),
    ("vibrating_bar.toml", include_str!("../../verification/vibrating_bar.toml")),
    ("vibrating_bar_3d.toml", include_str!("../../verification/vibrating_bar_3d.toml")),
];

/// A scene file of `verification/` and overrides: one variant of a case's scene.
#[derive(Clone, Debug)]
pub struct SceneFile {
    file: &'static str,
    text: &'static str,
    sets: Vec<String>,
}

impl SceneFile {
    /// A file of [`FILES`] (a name not there is a programming error of the case).
    pub fn new(file: &str) -> SceneFile {
        let &(file, text) = FILES.iter().find(|(f, _)| *f == file).unwrap_or_else(|| panic!("verification/{file} is not in verify::scene_file::FILES"));
        SceneFile { file, text, sets: Vec::new() }
    }

    /// Override `path` with `value`, written as TOML (`--set path=value`).
    pub fn set(mut self, path: &str, value: impl std::fmt::Display) -> SceneFile {
        self.sets.push(format!("{path}={value}"));
        self
    }

    /// The scene as TOML text with the overrides applied (comments dropped).
    pub fn to_toml(&self) -> anyhow::Result<String> {
        Ok(self.read()?.1.text)
    }

    fn read(&self) -> anyhow::Result<(AnyScene, SceneSource)> {
        let overrides = self.sets.iter().map(|s| Override::parse(s)).collect::<Result<Vec<_>, _>>()?;
        let origin = format!("verification/{}", self.file);
        let base = Path::new(env!("CARGO_MANIFEST_DIR")).join("verification");
        let scene = scene_override::scene_with(self.text, &origin, Some(&base), &overrides)?;
        // The file as is (with its comments) when nothing is overridden.
        let text = if overrides.is_empty() { self.text.to_string() } else { scene_override::apply_all(self.text, &origin, &overrides)? };
        let source = SceneSource { file: Some(self.file.to_string()), overrides: overrides.iter().map(|o| o.arg.clone()).collect(), text };
        Ok((scene, source))
    }

    /// Read the 2D scene with the overrides applied (validated as a file is).
    pub fn load(&self) -> anyhow::Result<Scene> {
        match self.read()? {
            (AnyScene::D2(s), source) => noted(s, source),
            (AnyScene::D3(_), _) => Err(anyhow!("verification/{} is a 3D scene", self.file)),
        }
    }

    /// Read the 3D scene with the overrides applied.
    pub fn load3(&self) -> anyhow::Result<Scene3> {
        match self.read()? {
            (AnyScene::D3(s), source) => noted(s, source),
            (AnyScene::D2(_), _) => Err(anyhow!("verification/{} is a 2D scene", self.file)),
        }
    }
}

/// Tell a running recording where a scene came from (see the module documentation).
fn noted<T: serde::Serialize>(scene: T, source: SceneSource) -> anyhow::Result<T> {
    crate::fingerprint::note_loaded(toml::to_string(&scene)?, source);
    Ok(scene)
}

/// One exported scene: the file written and what it reproduces.
#[derive(Clone, Debug)]
pub struct Exported {
    pub case: String,
    /// Position among the case's simulations (the order of its fingerprints).
    pub index: usize,
    /// The scene file written; None for a simulation that no scene describes (a copy of
    /// a simulation changed in Rust, listed in index.csv with the reason).
    pub path: Option<PathBuf>,
    /// The case's fingerprint of this simulation's final state.
    pub fingerprint: u64,
    /// Whether the scene came from a file of `verification/` (false: built in Rust).
    pub from_file: bool,
    /// Whether the case only built the simulation (never stepped it: an initial state, or
    /// the particle fill of `cramp fea`): its fingerprint is that of the built scene.
    pub built_only: bool,
    /// Particle-steps the case spent on it (particles × steps): the cost of running it again.
    pub work: u64,
    /// Its state after its first [`crate::fingerprint::EARLY_STEPS`] steps, if it got there.
    pub early: Option<crate::fingerprint::Early>,
}

/// A file-name-safe summary of overrides: `cell-0.5-0.5_shape-linear`.
fn variant_name(overrides: &[String]) -> String {
    let mut parts = Vec::new();
    for o in overrides {
        let (path, value) = o.split_once('=').unwrap_or((o, ""));
        let key = path.rsplit('.').next().unwrap_or(path);
        let value: String = value.chars().map(|c| if c.is_ascii_alphanumeric() || c == '.' || c == '-' { c } else { ' ' }).collect();
        let value = value.split_whitespace().collect::<Vec<_>>().join("-");
        parts.push(if value.is_empty() { key.to_string() } else { format!("{key}-{value}") });
    }
    let mut name = parts.join("_");
    if name.len() > 80 {
        let cut = (0..=80).rev().find(|&i| name.is_char_boundary(i)).unwrap_or(0);
        name.truncate(cut);
    }
    name
}

/// The overrides that make a simulation's scene run as the case ran it: `solver.checked`
/// as the case had it, and `solver.end_time` where the case stopped the run itself
/// before (or after) the scene's end time. A run that failed mid-step keeps the scene's
/// end time (`cramp run` fails at the same step).
fn run_overrides(sim: &crate::fingerprint::Recorded, text: &str) -> anyhow::Result<Vec<Override>> {
    let table: toml::Table = text.parse()?;
    let solver = table.get("solver");
    let mut out = Vec::new();
    let scene_checked = solver.and_then(|s| s.get("checked")).and_then(|c| c.as_bool()).unwrap_or(true);
    if scene_checked != sim.checked {
        out.push(Override::new("solver.checked", sim.checked)?);
    }
    let end = solver.and_then(|s| s.get("end_time")).and_then(|e| e.as_float().or(e.as_integer().map(|i| i as f64)));
    if sim.steps > 0 && sim.last_step_completed() && end.is_none_or(|e| (e - sim.time).abs() > 0.5 * sim.dt) {
        out.push(Override::new("solver.end_time", format!("{:?}", sim.time))?);
    }
    Ok(out)
}

/// Write every simulation of the results as a scene file `DIR/<case>/NN_<file>[__<variant>].toml`
/// (overrides applied, `solver.checked` and `solver.end_time` as the case ran it; see
/// [`run_overrides`]), and `DIR/index.csv` (`case,index,file,fingerprint,from_file,built_only,note`).
pub fn export(dir: &Path, results: &[super::CaseResult]) -> anyhow::Result<Vec<Exported>> {
    let mut out = Vec::new();
    for r in results {
        let case_dir = dir.join(&r.name);
        std::fs::create_dir_all(&case_dir).with_context(|| format!("cannot create {}", case_dir.display()))?;
        for (k, sim) in r.simulations.iter().enumerate() {
            let built_only = sim.steps == 0;
            let work = sim.particles as u64 * sim.steps;
            let Some(src) = &sim.scene else {
                out.push(Exported { case: r.name.clone(), index: k, path: None, fingerprint: sim.fingerprint, from_file: false, built_only, work, early: sim.early });
                continue;
            };
            let stem = src.file.as_deref().map_or("built_in_rust", |f| f.trim_end_matches(".toml"));
            let extra = run_overrides(sim, &src.text)?;
            let text = if extra.is_empty() { src.text.clone() } else { scene_override::apply_all(&src.text, "export", &extra)? };
            let overrides: Vec<String> = src.overrides.iter().cloned().chain(extra.iter().map(|o| o.arg.clone())).collect();
            let variant = variant_name(&overrides);
            let name = if variant.is_empty() { format!("{k:02}_{stem}.toml") } else { format!("{k:02}_{stem}__{variant}.toml") };
            let source = match &src.file {
                Some(f) => format!("# verification/{f}{}\n", overrides.iter().map(|o| format!(" \\\n#   --set '{o}'")).collect::<String>()),
                None => "# a scene built in Rust, not from a file of verification/\n".to_string(),
            };
            let note = if built_only { "# The case only built this scene (its initial state, or the particle fill of `cramp fea`); it never stepped it.\n" } else { "" };
            let header = format!(
                "# Simulation {k} of verification case `{}` ({:?}), exported by `cramp verify --export`:\n{source}{note}# The case's bit fingerprint of the final state: {:016x} (src/fingerprint.rs).\n\n",
                r.name, r.variant, sim.fingerprint
            );
            let path = case_dir.join(name);
            std::fs::write(&path, format!("{header}{text}")).with_context(|| format!("cannot write {}", path.display()))?;
            out.push(Exported { case: r.name.clone(), index: k, path: Some(path), fingerprint: sim.fingerprint, from_file: src.file.is_some(), built_only, work, early: sim.early });
        }
    }
    let mut index = String::from("case,index,file,fingerprint,from_file,built_only,note\n");
    for e in &out {
        let (file, note) = match &e.path {
            Some(p) => (p.strip_prefix(dir).unwrap_or(p).display().to_string(), ""),
            None => (String::new(), "a copy of a simulation changed in Rust: no scene describes it"),
        };
        index.push_str(&format!("{},{},{file},{:016x},{},{},{note}\n", e.case, e.index, e.fingerprint, e.from_file, e.built_only));
    }
    std::fs::write(dir.join("index.csv"), index).with_context(|| format!("cannot write {}", dir.join("index.csv").display()))?;
    Ok(out)
}

/// How far [`run_fingerprint`] runs an exported scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Reproduce {
    /// Build it only (the case never stepped it).
    Built,
    /// Run it to the end time written in the file.
    Full,
    /// Run it to this end time instead (`cramp run --set solver.end_time=T`).
    Until(f64),
}

/// Run an exported scene as `cramp run` does (no output files) and return the
/// fingerprint of the simulation's final state, also when the run stops with an error
/// (a case may run a scene until a check fails). With [`Reproduce::Built`], the
/// fingerprint of the scene as built (the simulation was never stepped).
pub fn run_fingerprint(path: &Path, how: Reproduce) -> anyhow::Result<u64> {
    let mut scene = AnyScene::from_file(path)?;
    if how == Reproduce::Built {
        return Ok(match &scene {
            AnyScene::D2(s) => crate::fingerprint::fingerprint(&s.build()?),
            AnyScene::D3(s) => crate::fingerprint::fingerprint(&s.build()?),
        });
    }
    // Only the end moves: the history rows stay where the full run has them.
    if let Reproduce::Until(t) = how {
        match &mut scene {
            AnyScene::D2(s) => {
                s.output.history_interval.get_or_insert(s.solver.end_time / 100.0);
                s.solver.end_time = t;
            }
            AnyScene::D3(s) => {
                s.output.history_interval.get_or_insert(s.solver.end_time / 100.0);
                s.solver.end_time = t;
            }
        }
    }
    let recorder = crate::fingerprint::Recorder::start();
    let opts = crate::output::RunOptions::default();
    let _ = match &scene {
        AnyScene::D2(s) => crate::output::run_scene(s, &opts).map(drop),
        AnyScene::D3(s) => crate::output::three_d::run_scene_3d(s, &opts).map(drop),
    };
    let recorded = recorder.finish();
    anyhow::ensure!(recorded.len() == 1, "{}: {} simulations ran, expected 1", path.display(), recorded.len());
    Ok(recorded[0].fingerprint)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_scene_file_is_compiled_in() {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("verification");
        for entry in std::fs::read_dir(&dir).unwrap() {
            let name = entry.unwrap().file_name().to_string_lossy().into_owned();
            if name.ends_with(".toml") && name != "cases.toml" {
                let text = FILES.iter().find(|(f, _)| *f == name).unwrap_or_else(|| panic!("verification/{name} is not in FILES")).1;
                assert_eq!(text, std::fs::read_to_string(dir.join(&name)).unwrap());
            }
        }
    }
}
