//! The crack-patch test (Nairn 2003 §3.1, Fig. 1): case `crack_patch`, scenes
//! `verification/crack_patch_full.toml` and `crack_patch_half.toml`.
//!
//! An explicit-crack DCB analysed in full must give, for every particle of its top half,
//! exactly the same bits as the top half alone with the y-velocity fixed on the
//! mid-plane nodes of the uncracked ligament; the bottom half must be the exact mirror
//! of the top.
//!
//! Reference: the symmetry-constrained half model (an independent computation that needs
//! no crack code). Tolerance: none — `f64::to_bits` equality of position, velocity,
//! stress and strain of every particle at every compared step (every 10th). This is fair
//! because every grid sum is correctly rounded (order-independent), the grid is
//! symmetric about the grid line y = 0 with exactly representable coordinates, and the
//! crack fields give the mid-plane nodes two independent fields.
//!
//! The crack faces have no contact law: the half model's mid-plane face is free, so the
//! equivalent full model has none either. (With frictionless contact the grey-zone
//! velocity test of eq. 12 engages near the loaded end and the models differ, as they
//! should: the full model then enforces a constraint the half model does not.)
//!
//! Negative control: the same comparison with the crack removed from the full model must
//! find differing bits (the full model is then a bonded beam, not a DCB).

use crate::scene::{Scene, Selection};
use crate::simulation::Simulation;
use crate::verify::scene_file::SceneFile;
use crate::verify::{CaseOutput, Variant};
use anyhow::{bail, Context};
use std::collections::HashMap;


/// Crack tip x of the scenes.
const TIP_X: f64 = 50.0;

/// The full (with or without its crack) and half scenes at cell size `h` (2 mm in the
/// files). For other h the grid origin moves by h/4 per halving so the tip stays inside a
/// cell and the node coordinates stay exact in binary, and the half model's symmetry line
/// starts at the first node beyond the tip.
pub fn scenes(h: f64, crack: bool) -> anyhow::Result<(Scene, Scene)> {
    let (mut full, mut half) = (SceneFile::new("crack_patch_full.toml"), SceneFile::new("crack_patch_half.toml"));
    if !crack {
        full = full.set("cracks", "[]");
    }
    let file_h = half.clone().load()?.grid.cell[0];
    if h != file_h {
        // Nodes at x0 + k h with the tip strictly between two of them.
        let x0 = -3.0 - h / 2.0;
        let grid = |f: SceneFile| -> anyhow::Result<SceneFile> {
            let g = f.clone().load()?.grid;
            Ok(f.set("grid.cell", format!("[{h}, {h}]")).set("grid.origin", format!("[{x0}, {}]", g.origin[1])).set("grid.size", format!("[{}, {}]", 106.0 + h, g.size[1])))
        };
        full = grid(full)?;
        half = grid(half)?;
        let nodes_past_tip = ((TIP_X - x0) / h).floor() + 1.0;
        let first = x0 + nodes_past_tip * h;
        let Selection::Line { from, .. } = half.clone().load()?.boundary[0].nodes else {
            bail!("the half model's symmetry condition must be a line");
        };
        half = half.set("boundary.0.nodes.line.from", format!("[{first}, {}]", from[1]));
    }
    Ok((full.load()?, half.load()?))
}

/// Key a particle by the bits of its initial position.
pub fn key(x: f64, y: f64) -> (u64, u64) {
    (x.to_bits(), y.to_bits())
}

/// Compare the full model's top half with the half model and its bottom half with the
/// mirror of the top. Returns the number of values whose bits differ and a description
/// of the first.
pub fn differing_bits(full: &Simulation, half: &Simulation) -> anyhow::Result<(u64, Option<String>)> {
    let hp = &half.particles;
    let idx: HashMap<_, _> = (0..hp.len()).map(|i| (key(hp.x0[i].x, hp.x0[i].y), i)).collect();
    let fp = &full.particles;
    let fidx: HashMap<_, _> = (0..fp.len()).map(|i| (key(fp.x0[i].x, fp.x0[i].y), i)).collect();
    let (mut count, mut first) = (0u64, None);
    for i in 0..fp.len() {
        let x0 = fp.x0[i];
        if x0.y > 0.0 {
            let j = *idx.get(&key(x0.x, x0.y)).with_context(|| format!("the half model has no particle at {x0:?}"))?;
            let pairs = [
                ("x", fp.x[i].x, hp.x[j].x),
                ("y", fp.x[i].y, hp.x[j].y),
                ("vx", fp.v[i].x, hp.v[j].x),
                ("vy", fp.v[i].y, hp.v[j].y),
                ("sxx", fp.stress[i].xx, hp.stress[j].xx),
                ("syy", fp.stress[i].yy, hp.stress[j].yy),
                ("sxy", fp.stress[i].xy, hp.stress[j].xy),
                ("exx", fp.strain[i].xx, hp.strain[j].xx),
                ("eyy", fp.strain[i].yy, hp.strain[j].yy),
                ("exy", fp.strain[i].xy, hp.strain[j].xy),
            ];
            for (what, a, b) in pairs {
                if a.to_bits() != b.to_bits() {
                    count += 1;
                    first.get_or_insert_with(|| format!("top particle at {x0:?}: {what} full {a:e} vs half {b:e}"));
                }
            }
        } else {
            let m = *fidx.get(&key(x0.x, -x0.y)).with_context(|| format!("the full model has no mirror of {x0:?}"))?;
            let pairs = [
                ("x", fp.x[i].x, fp.x[m].x),
                ("y", fp.x[i].y, -fp.x[m].y),
                ("vx", fp.v[i].x, fp.v[m].x),
                ("vy", fp.v[i].y, -fp.v[m].y),
                ("sxx", fp.stress[i].xx, fp.stress[m].xx),
                ("syy", fp.stress[i].yy, fp.stress[m].yy),
                ("sxy", fp.stress[i].xy, -fp.stress[m].xy),
                ("exy", fp.strain[i].xy, -fp.strain[m].xy),
            ];
            for (what, a, b) in pairs {
                // A mirrored zero may carry either sign (0 − 0 = +0, −(+0) = −0): the sign
                // of zero is not a value, so zeros compare equal; all else by bits.
                if (a + 0.0).to_bits() != (b + 0.0).to_bits() {
                    count += 1;
                    first.get_or_insert_with(|| {
                        format!("bottom particle at {x0:?}: {what} {a:e} is not the mirror {b:e}")
                    });
                }
            }
        }
    }
    Ok((count, first))
}

/// Compare every this many steps.
pub const COMPARE_EVERY: u64 = 10;

/// The outcome of a crack-patch comparison.
#[derive(Clone, Debug)]
pub struct PatchComparison {
    /// Steps compared.
    pub compared: usize,
    /// Values (particle × field × compared step) whose bits differ.
    pub differing: u64,
    /// The first difference, with its step.
    pub first: Option<String>,
}

/// Run both models to `end`, comparing every [`COMPARE_EVERY`] steps. With `stop_early`
/// the run ends at the first compared step with a difference.
pub fn run_and_compare(full: &Scene, half: &Scene, end: f64, stop_early: bool) -> anyhow::Result<PatchComparison> {
    let (mut f, mut h) = (full.build()?, half.build()?);
    if f.options.dt.to_bits() != h.options.dt.to_bits() {
        bail!("the full and half models have different time steps");
    }
    if f.particles.len() != 2 * h.particles.len() {
        bail!("the full model has {} particles, not twice the half model's {}", f.particles.len(), h.particles.len());
    }
    let mut c = PatchComparison { compared: 0, differing: 0, first: None };
    while f.time + 0.5 * f.options.dt < end {
        f.step().context("full model")?;
        h.step().context("half model")?;
        if f.step_count % COMPARE_EVERY == 0 {
            let (n, first) = differing_bits(&f, &h)?;
            c.compared += 1;
            c.differing += n;
            if let (None, Some(m)) = (&c.first, first) {
                c.first = Some(format!("step {}: {m}", f.step_count));
            }
            if stop_early && n > 0 {
                break;
            }
        }
    }
    Ok(c)
}

/// Case `crack_patch`.
pub fn run(variant: Variant) -> anyhow::Result<CaseOutput> {
    let h = match variant {
        Variant::Quick => 2.0,
        Variant::Full => 1.0,
    };
    let mut out = CaseOutput::default();
    let (full, half) = scenes(h, true)?;
    let c = run_and_compare(&full, &half, full.solver.end_time, false)?;
    out.measure("differing_bits", "explicit crack vs half model", c.differing as f64, 0.0);
    out.measure("compared_steps", "", c.compared as f64, f64::NAN);
    out.note(format!(
        "h = {h} mm: compared {} steps (every {COMPARE_EVERY}th) of {} particles; {} differing values{}",
        c.compared,
        full.build()?.particles.len(),
        c.differing,
        c.first.map(|f| format!("; first: {f}")).unwrap_or_default()
    ));
    let (bonded, half) = scenes(h, false)?;
    let n = run_and_compare(&bonded, &half, 10.0, true)?;
    out.measure("negative_control", "crack removed (bonded beam)", n.differing as f64, f64::NAN);
    out.note(format!(
        "Negative control (crack removed): {} differing values by t = 10; first: {}",
        n.differing,
        n.first.unwrap_or_default()
    ));
    Ok(out)
}
