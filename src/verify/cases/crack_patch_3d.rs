//! The 3D crack-patch test (Nairn 2003 §3.1, Fig. 1, extruded; issue 15): case
//! `crack_patch_3d`, scenes `verification/crack_patch_3d_full.toml` and
//! `crack_patch_3d_half.toml`.
//!
//! A 3D DCB (the 2D crack-patch beam given a width of two cells, free side faces) with a
//! triangulated crack surface on its mid-plane y = 0, analysed in full, must give for every
//! particle of its top half exactly the bits of the top half alone with v_y = 0 on the
//! mid-plane nodes of the uncracked ligament; the bottom half must be the exact mirror of
//! the top (y ↦ −y). Reference: the symmetry-constrained half model, which needs no crack
//! code. Tolerance: none (`f64::to_bits` equality of x, v, σ, ε of every particle at every
//! compared step), fair for the reasons of the 2D case: correctly rounded grid sums, a grid
//! symmetric about the grid plane y = 0 with exact coordinates, the exact crossing test of
//! `crack::crossing3` (the crack's triangles lie in y = 0 exactly; the mid-plane nodes lie
//! on the crack and take the particles' own sides), and two independent fields on every
//! split node. Negative control: the crack removed, the comparison must differ.

use crate::dim::{SymOps, D3};
use crate::scene3d::{Scene3, Selection3};
use crate::simulation::Simulation;
use crate::verify::scene_file::SceneFile;
use crate::verify::{CaseOutput, Variant};
use anyhow::{bail, Context};
use std::collections::HashMap;

/// Crack front x of the scenes.
const FRONT_X: f64 = 50.0;

/// The full (with or without its crack) and half scenes at cell size `h` (2 mm in the
/// files), ending at `end`: the scene files with overrides. For other h the grid moves as
/// in the 2D case: nodes at x0 + k h (and z0 + k h) with the front strictly inside a cell,
/// exact binary coordinates, and the half model's symmetry nodes from the first node
/// beyond the front.
pub fn scenes(h: f64, crack: bool, end: f64) -> anyhow::Result<(Scene3, Scene3)> {
    let (mut full, mut half) = (SceneFile::new("crack_patch_3d_full.toml"), SceneFile::new("crack_patch_3d_half.toml"));
    if !crack {
        full = full.set("cracks", "[]");
    }
    full = full.set("solver.end_time", end);
    half = half.set("solver.end_time", end);
    let file_h = half.clone().load3()?.grid.cell[0];
    if h != file_h {
        let (x0, z0) = (-3.0 - h / 2.0, -3.0 - h / 2.0);
        let grid = |f: SceneFile| -> anyhow::Result<SceneFile> {
            let g = f.clone().load3()?.grid;
            Ok(f.set("grid.cell", format!("[{h}, {h}, {h}]")).set("grid.origin", format!("[{x0}, {}, {z0}]", g.origin[1])).set("grid.size", format!("[{}, {}, {}]", 106.0 + h, g.size[1], 10.0 + h)))
        };
        full = grid(full)?;
        half = grid(half)?;
        let nodes_past_front = ((FRONT_X - x0) / h).floor() + 1.0;
        let Selection3::Box { min, max } = half.clone().load3()?.boundary[0].nodes else {
            bail!("the half model's symmetry condition must be a box");
        };
        half = half.set("boundary.0.nodes.box.min", format!("[{}, {}, {z0}]", x0 + nodes_past_front * h, min[1])).set("boundary.0.nodes.box.max", format!("[{}, {}, {}]", max[0], max[1], z0 + 10.0 + h));
    }
    Ok((full.load3()?, half.load3()?))
}

type Key = (u64, u64, u64);

fn key(x: f64, y: f64, z: f64) -> Key {
    (x.to_bits(), y.to_bits(), z.to_bits())
}

/// Compare the full model's top half with the half model and its bottom half with the
/// mirror of the top: the number of values whose bits differ, and the first.
pub fn differing_bits(full: &Simulation<D3>, half: &Simulation<D3>) -> anyhow::Result<(u64, Option<String>)> {
    let hp = &half.particles;
    let idx: HashMap<Key, usize> = (0..hp.len()).map(|i| (key(hp.x0[i].x, hp.x0[i].y, hp.x0[i].z), i)).collect();
    let fp = &full.particles;
    let fidx: HashMap<Key, usize> = (0..fp.len()).map(|i| (key(fp.x0[i].x, fp.x0[i].y, fp.x0[i].z), i)).collect();
    let (mut count, mut first) = (0u64, None);
    let names = ["x", "y", "z"];
    let tnames = ["xx", "yy", "zz", "xy", "xz", "yz"];
    for i in 0..fp.len() {
        let x0 = fp.x0[i];
        // (what, value, reference) per component; the mirror flips y, and the yz, xy shears.
        let mut pairs: Vec<(String, f64, f64)> = Vec::with_capacity(18);
        if x0.y > 0.0 {
            let j = *idx.get(&key(x0.x, x0.y, x0.z)).with_context(|| format!("the half model has no particle at {x0:?}"))?;
            for c in 0..3 {
                pairs.push((format!("x.{}", names[c]), fp.x[i][c], hp.x[j][c]));
                pairs.push((format!("v.{}", names[c]), fp.v[i][c], hp.v[j][c]));
            }
            let (a, b) = (fp.stress[i].components(), hp.stress[j].components());
            let (ea, eb) = (fp.strain[i].components(), hp.strain[j].components());
            for k in 0..6 {
                pairs.push((format!("σ.{}", tnames[k]), a[k], b[k]));
                pairs.push((format!("ε.{}", tnames[k]), ea[k], eb[k]));
            }
            for (what, a, b) in pairs {
                if a.to_bits() != b.to_bits() {
                    count += 1;
                    first.get_or_insert_with(|| format!("top particle at {x0:?}: {what} full {a:e} vs half {b:e}"));
                }
            }
        } else {
            let m = *fidx.get(&key(x0.x, -x0.y, x0.z)).with_context(|| format!("the full model has no mirror of {x0:?}"))?;
            let flip = |c: usize| if c == 1 { -1.0 } else { 1.0 };
            for c in 0..3 {
                pairs.push((format!("x.{}", names[c]), fp.x[i][c], flip(c) * fp.x[m][c]));
                pairs.push((format!("v.{}", names[c]), fp.v[i][c], flip(c) * fp.v[m][c]));
            }
            let (a, b) = (fp.stress[i].components(), fp.stress[m].components());
            let (ea, eb) = (fp.strain[i].components(), fp.strain[m].components());
            // Sym3 components (xx, yy, zz, xy, xz, yz): xy and yz change sign under y ↦ −y.
            let tflip = [1.0, 1.0, 1.0, -1.0, 1.0, -1.0];
            for k in 0..6 {
                pairs.push((format!("σ.{}", tnames[k]), a[k], tflip[k] * b[k]));
                pairs.push((format!("ε.{}", tnames[k]), ea[k], tflip[k] * eb[k]));
            }
            for (what, a, b) in pairs {
                // The sign of a mirrored zero is not a value: zeros compare equal.
                if (a + 0.0).to_bits() != (b + 0.0).to_bits() {
                    count += 1;
                    first.get_or_insert_with(|| format!("bottom particle at {x0:?}: {what} {a:e} is not the mirror {b:e}"));
                }
            }
        }
    }
    Ok((count, first))
}

/// Compare every this many steps.
pub const COMPARE_EVERY: u64 = 10;

/// Run both models to their end time comparing every [`COMPARE_EVERY`] steps: (compared
/// steps, differing values, first difference). With `stop_early` the run ends at the first
/// compared step with a difference.
pub fn run_and_compare(full: &Scene3, half: &Scene3, stop_early: bool) -> anyhow::Result<(usize, u64, Option<String>)> {
    let (mut f, mut h) = (full.build()?, half.build()?);
    if f.options.dt.to_bits() != h.options.dt.to_bits() {
        bail!("the full and half models have different time steps");
    }
    if f.particles.len() != 2 * h.particles.len() {
        bail!("the full model has {} particles, not twice the half model's {}", f.particles.len(), h.particles.len());
    }
    let (mut compared, mut differing, mut first) = (0usize, 0u64, None);
    while f.time + 0.5 * f.options.dt < full.solver.end_time {
        f.step().context("full model")?;
        h.step().context("half model")?;
        if f.step_count % COMPARE_EVERY == 0 {
            let (n, d) = differing_bits(&f, &h)?;
            compared += 1;
            differing += n;
            if let (None, Some(m)) = (&first, d) {
                first = Some(format!("step {}: {m}", f.step_count));
            }
            if stop_early && n > 0 {
                break;
            }
        }
    }
    Ok((compared, differing, first))
}

/// Case `crack_patch_3d`.
pub fn run(variant: Variant) -> anyhow::Result<CaseOutput> {
    // Quick: 2 mm cells to t = 40 (about 330 steps, a quarter of the first opening);
    // full: the whole loading of the scene files (t = 120) and 1 mm cells to t = 40.
    let runs: &[(f64, f64)] = match variant {
        Variant::Quick => &[(2.0, 40.0)],
        Variant::Full => &[(2.0, 120.0), (1.0, 40.0)],
    };
    let mut out = CaseOutput::default();
    let (mut compared, mut differing) = (0usize, 0u64);
    for &(h, end) in runs {
        let (full, half) = scenes(h, true, end)?;
        let np = full.build()?.particles.len();
        let (c, d, first) = run_and_compare(&full, &half, false)?;
        compared += c;
        differing += d;
        out.note(format!(
            "h = {h} mm, t = {end}: compared {c} steps (every {COMPARE_EVERY}th) of {np} particles; {d} differing values{}",
            first.map(|f| format!("; first: {f}")).unwrap_or_default()
        ));
    }
    out.measure("differing_bits", "explicit crack surface vs half model", differing as f64, 0.0);
    out.measure("compared_steps", "", compared as f64, f64::NAN);
    let (bonded, half) = scenes(2.0, false, 10.0)?;
    let (_, n, first) = run_and_compare(&bonded, &half, true)?;
    out.measure("negative_control", "crack removed (bonded beam)", n as f64, f64::NAN);
    out.note(format!("Negative control (crack removed): {n} differing values by t = 10; first: {}", first.unwrap_or_default()));
    Ok(out)
}
