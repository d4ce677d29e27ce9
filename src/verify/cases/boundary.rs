//! Case `boundary_motion` (issue 21): prescribed boundary motion and tractions that vary
//! in space and time, each checked against an independent reference, in the MPM and in
//! the static FEA of the same scene file:
//!
//! 1. displacement patch test (`verification/patch_displacement.toml`): a linear
//!    displacement field prescribed on the boundary of a block gives the uniform strain
//!    and stress of Hooke's law inside (FEA to round-off; MPM damped to rest);
//! 2. pure bending (`traction_bending.toml`): end tractions t_x = ±σ0 y/c give
//!    σxx = σ0 y/c (Timoshenko & Goodier 1970 §21);
//! 3. ramp and hold (`ramp_hold_plate.toml`): an edge displacement ramped and held
//!    settles to the static FEA solution of the same scene.

use super::csum;
use crate::dim::Vector;
use crate::fea::scene::SceneFea;
use crate::scene::{Scene, ShapeSpec};
use crate::simulation::Simulation;
use crate::verify::scene_file::SceneFile;
use crate::verify::{CaseOutput, Variant};
use anyhow::bail;

/// Plane-strain Hooke's law written out (independently of `material.rs`): σ for the
/// tensor strain (εxx, εyy, εxy).
fn hooke_plane_strain(e: f64, nu: f64, exx: f64, eyy: f64, exy: f64) -> [f64; 3] {
    let lambda = e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
    let mu = e / (2.0 * (1.0 + nu));
    [(lambda + 2.0 * mu) * exx + lambda * eyy, lambda * exx + (lambda + 2.0 * mu) * eyy, 2.0 * mu * exy]
}

/// Run a scene to its end time, returning the simulation and KE/SE at the end.
fn settle(scene: &Scene) -> anyhow::Result<(Simulation, f64)> {
    let mut sim = scene.build()?;
    sim.run_until(scene.solver.end_time, |_| {})?;
    let e = sim.energies();
    Ok((sim, e.kinetic / e.strain))
}

/// The FEA displacement at point x (bilinear in its element), None outside the mesh.
fn fea_displacement(fea: &SceneFea, u: &[Vector], x: Vector) -> Option<Vector> {
    let g = &fea.grid_mesh.grid;
    let (fi, fj) = ((x.x - g.origin.x) / g.h.x, (x.y - g.origin.y) / g.h.y);
    let (i, j) = (fi.floor() as isize, fj.floor() as isize);
    let e = fea.grid_mesh.element_at(i, j)?;
    let n = crate::fea::element::shape(2.0 * (fi - i as f64) - 1.0, 2.0 * (fj - j as f64) - 1.0);
    Some(fea.grid_mesh.mesh.elements[e].iter().zip(n).fold(Vector::zeros(), |s, (&a, w)| s + u[a] * w))
}

/// Case `boundary_motion`.
pub fn run(variant: Variant) -> anyhow::Result<CaseOutput> {
    let mut out = CaseOutput::default();
    let refine = |f: SceneFile, h: f64| if variant == Variant::Full { f.set("grid.cell", format!("[{h}, {h}]")) } else { f };

    // 1. Displacement patch test.
    let scene = SceneFile::new("patch_displacement.toml").load()?;
    let m = &scene.materials[0];
    // u = (a x + b y, c x + d y), read from nothing but the file's numbers below.
    let (a, b, c, d) = (1e-5, 2e-6, 5e-6, -6e-6);
    let exact = hooke_plane_strain(m.e, m.nu, a, d, 0.5 * (b + c));
    let scale = exact.iter().fold(0.0f64, |s, v| s.max(v.abs()));
    let fea = SceneFea::from_scene(&scene)?;
    let sol = fea.analyse()?.solution;
    let fea_err = sol.gauss_stress.iter().flatten().map(|s| [s.xx - exact[0], s.yy - exact[1], s.xy - exact[2]].iter().fold(0.0f64, |m, v| m.max(v.abs()))).fold(0.0, f64::max) / scale;
    out.measure("fea_patch", "max |σ − σ_exact| / max|σ_exact| over Gauss points", fea_err, 0.0);
    let (sim, ke) = settle(&scene)?;
    let p = &sim.particles;
    let mpm_err = (0..p.len()).map(|i| [p.stress[i].xx - exact[0], p.stress[i].yy - exact[1], p.stress[i].xy - exact[2]].iter().fold(0.0f64, |m, v| m.max(v.abs()))).fold(0.0, f64::max) / scale;
    out.measure("mpm_patch", "max |σ − σ_exact| / max|σ_exact| over particles", mpm_err, 0.0);
    out.measure("settled", "patch", ke, 0.0);
    out.note(format!(
        "Patch test: exact σ = ({:.6e}, {:.6e}, {:.6e}) MPa; FEA max error {fea_err:.2e}, MPM max error {mpm_err:.2e} of max|σ| over {} particles (KE/SE = {ke:.1e}).",
        exact[0],
        exact[1],
        exact[2],
        p.len()
    ));
    drop(sim);

    // 1b. The same in 3D: u = A x.
    let scene = SceneFile::new("patch_displacement_3d.toml").load3()?;
    let m = &scene.materials[0];
    let a3 = [[1e-5, 2e-6, 0.0], [5e-6, -6e-6, 3e-6], [-2e-6, 1e-6, 4e-6]];
    let eps = |i: usize, j: usize| 0.5 * (a3[i][j] + a3[j][i]);
    let (lambda, mu) = (m.e * m.nu / ((1.0 + m.nu) * (1.0 - 2.0 * m.nu)), m.e / (2.0 * (1.0 + m.nu)));
    let tr = eps(0, 0) + eps(1, 1) + eps(2, 2);
    let sig = |i: usize, j: usize| if i == j { lambda * tr + 2.0 * mu * eps(i, j) } else { 2.0 * mu * eps(i, j) };
    let exact3 = [sig(0, 0), sig(1, 1), sig(2, 2), sig(0, 1), sig(0, 2), sig(1, 2)];
    let scale3 = exact3.iter().fold(0.0f64, |s, v| s.max(v.abs()));
    let err3 = |s: &crate::dim::Sym3| [s.xx, s.yy, s.zz, s.xy, s.xz, s.yz].iter().zip(&exact3).fold(0.0f64, |m, (v, e)| m.max((v - e).abs())) / scale3;
    let sol = crate::fea::scene3::SceneFea3::from_scene(&scene)?.analyse()?.solution;
    let fea_err3 = sol.gauss_stress.iter().flatten().map(err3).fold(0.0, f64::max);
    out.measure("fea_patch", "3D: max |σ − σ_exact| / max|σ_exact| over Gauss points", fea_err3, 0.0);
    let mut sim = scene.build()?;
    sim.run_until(scene.solver.end_time, |_| {})?;
    let mpm_err3 = sim.particles.stress.iter().map(err3).fold(0.0, f64::max);
    out.measure("mpm_patch", "3D: max |σ − σ_exact| / max|σ_exact| over particles", mpm_err3, 0.0);
    let e3 = sim.energies();
    out.measure("settled", "patch 3D", e3.kinetic / e3.strain, 0.0);
    out.note(format!("3D patch test: FEA max error {fea_err3:.2e}, MPM max error {mpm_err3:.2e} of max|σ| over {} particles.", sim.particles.len()));
    drop(sim);

    // 2. Pure bending by end tractions.
    let mut file = SceneFile::new("traction_bending.toml");
    if variant == Variant::Full {
        // The end columns of particles at h = 0.25 (2 per cell): x = 0.0625 and 15.9375.
        file = refine(file, 0.25);
        for (k, x) in [(0, 15.9375), (1, 0.0625)] {
            file = file.set(&format!("loads.{k}.particles.line.from.0"), x).set(&format!("loads.{k}.particles.line.to.0"), x);
        }
    }
    let scene = file.load()?;
    let (sigma0, half) = (1.0, 2.0);
    let ShapeSpec::Rectangle { min, max } = scene.bodies[0].shape else { bail!("the beam must be a rectangle") };
    let (x_lo, x_hi) = (min[0] + 0.25 * (max[0] - min[0]), min[0] + 0.75 * (max[0] - min[0]));
    let fea = SceneFea::from_scene(&scene)?;
    let sol = fea.analyse()?.solution;
    let g = fea.grid_mesh.grid;
    // Cell means: the mean over an element's Gauss points (over a cell's particles) against
    // the exact stress at the cell centre (the mean of a linear field over the cell). The
    // pointwise values carry the bilinear cell's parasitic bending stresses, ±3 % of σ0 here
    // at 8 cells through the depth (FEA at its Gauss points and MPM at its particles alike).
    let bending_error = |_x: f64, y: f64, s: [f64; 3]| (s[0] - sigma0 * y / half).abs().max(s[1].abs()).max(s[2].abs()) / sigma0;
    let mut fea_bend = 0.0f64;
    for (e, &[i, j]) in fea.grid_mesh.element_cell.iter().enumerate() {
        let centre = g.cell_center(i, j);
        if centre.x < x_lo || centre.x > x_hi {
            continue;
        }
        let mean = |f: &dyn Fn(&crate::dim::Sym) -> f64| sol.gauss_stress[e].iter().map(f).sum::<f64>() / 4.0;
        fea_bend = fea_bend.max(bending_error(centre.x, centre.y, [mean(&|s| s.xx), mean(&|s| s.yy), mean(&|s| s.xy)]));
    }
    out.measure("fea_bending", "max |σ − σ_exact| / σ0 over element means of the middle half", fea_bend, 0.0);
    let (sim, ke) = settle(&scene)?;
    let p = &sim.particles;
    let mut cells: std::collections::BTreeMap<(i64, i64), ([f64; 3], usize)> = Default::default();
    for i in (0..p.len()).filter(|&i| p.x0[i].x >= x_lo && p.x0[i].x <= x_hi) {
        let key = (((p.x0[i].x - g.origin.x) / g.h.x).floor() as i64, ((p.x0[i].y - g.origin.y) / g.h.y).floor() as i64);
        let c = cells.entry(key).or_insert(([0.0; 3], 0));
        for (k, v) in [p.stress[i].xx, p.stress[i].yy, p.stress[i].xy].into_iter().enumerate() {
            c.0[k] += v;
        }
        c.1 += 1;
    }
    let mpm_bend = cells
        .iter()
        .map(|(&(i, j), (s, n))| {
            let centre = g.cell_center(i as usize, j as usize);
            bending_error(centre.x, centre.y, s.map(|v| v / *n as f64))
        })
        .fold(0.0, f64::max);
    out.measure("mpm_bending", "max |σ − σ_exact| / σ0 over cell means of the middle half", mpm_bend, 0.0);
    out.measure("settled", "bending", ke, 0.0);
    out.note(format!("Pure bending: σxx = σ0 y/c with σ0 = {sigma0} MPa, c = {half} mm; over the cells of the middle half, FEA max error {fea_bend:.2e} σ0, MPM {mpm_bend:.2e} σ0 ({} cells; KE/SE = {ke:.1e}).", cells.len()));
    drop(sim);

    // 3. Ramp and hold vs the static FEA of the same scene.
    let scene = refine(SceneFile::new("ramp_hold_plate.toml"), 0.25).load()?;
    let fea = SceneFea::from_scene(&scene)?;
    let sol = fea.analyse()?.solution;
    let (sim, ke) = settle(&scene)?;
    let p = &sim.particles;
    let mut diffs = Vec::new();
    for i in 0..p.len() {
        let Some(uf) = fea_displacement(&fea, &sol.displacement, p.x0[i]) else { continue };
        diffs.push(((p.x[i] - p.x0[i] - uf).norm_squared(), uf.norm_squared()));
    }
    let rel = (csum(diffs.iter().map(|d| d.0)) / csum(diffs.iter().map(|d| d.1))).sqrt();
    out.measure("ramp_hold", "‖u_MPM − u_FEA‖ / ‖u_FEA‖ over particles", rel, 0.0);
    out.measure("settled", "ramp and hold", ke, 0.0);
    let (mpm_se, fea_se) = (sim.energies().strain, fea.analyse()?.strain_energy);
    out.measure("ramp_hold_energy", "MPM strain energy vs FEA ½uᵀKu", mpm_se, fea_se);
    out.note(format!("Ramp and hold: relative L2 difference of the particle displacements from the FEA's {rel:.2e}; strain energy MPM {mpm_se:.6e}, FEA {fea_se:.6e} (KE/SE = {ke:.1e})."));
    Ok(out)
}
