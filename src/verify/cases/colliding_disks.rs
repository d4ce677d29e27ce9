//! Two colliding elastic disks (Sulsky, Chen & Schreyer 1994; references §5.3): case
//! `colliding_disks`, scene `verification/demo.toml` (the embedded demo scene).
//!
//! * Total linear momentum is a conservation law of MPM without boundary conditions,
//!   loads or damping (Σ_i f_int,i = 0 by the partition of unity). cramp sums exactly, so
//!   |P(t) − P(0)| ≤ 1e-12 Σ_p m_p |v_p|₁ at every step, for every scheme.
//! * KE(0) = ½ M |v|² with M = Σ m_p the discrete particle mass: every particle has
//!   |v|² = 0.02, so the two agree to a few ulps.
//! * Energy through the impact: no exact post-impact value exists (Sulsky et al. show it
//!   qualitatively). With USAVG the total KE + SE must stay within ±1 % of E0 through the
//!   collision and rebound (Nairn 2003 §3.4: USAVG within ±0.18 % for an impact; margin
//!   for this coarse 20×20 grid); the disks must have rebounded (disk 0's centre-of-mass
//!   velocity reversed) with KE back above half of KE(0).
//!
//! Runs to t = 3 like the demo: by t ≈ 4 the rebounding disks, tangent to the grid edges
//! at t = 0, reach the corners again and leave the grid.

use super::{scheme_name, SCHEMES};
use crate::report::plot::{PlotSpec, Series};
use crate::scene::Scene;
use crate::simulation::Scheme;
use crate::verify::scene_file::SceneFile;
use crate::verify::{CaseOutput, Plot, Variant};
use anyhow::Context;

/// The demo scene with a scheme, particles per cell and cell size.
pub fn disks_scene(scheme: Scheme, ppc: usize, cell: f64) -> anyhow::Result<Scene> {
    SceneFile::new("demo.toml")
        .set("solver.scheme", super::scheme_name(scheme))
        .set("solver.particles_per_cell", ppc)
        .set("grid.cell", format!("[{cell}, {cell}]"))
        .load()
}

/// What one run of the disks measured.
#[derive(Clone, Debug)]
pub struct DisksRun {
    pub scheme: Scheme,
    pub max_dp: f64,
    pub max_de: f64,
    pub ke0: f64,
    /// ½ M |v|² from the discrete mass.
    pub ke0_exact: f64,
    pub ke_final_ratio: f64,
    pub ke_min_ratio: f64,
    pub t_ke_min: f64,
    /// Disk 0's centre-of-mass velocity at the end.
    pub v_cm0: crate::dim::Vector,
    /// (t, KE), (t, SE), (t, (E − E0)/E0).
    pub kinetic: Vec<(f64, f64)>,
    pub strain: Vec<(f64, f64)>,
    pub energy_error: Vec<(f64, f64)>,
}

/// Run the disks to the scene's end time.
pub fn run_disks(scene: &Scene) -> anyhow::Result<DisksRun> {
    let mut sim = scene.build()?;
    let p0 = sim.total_momentum();
    let e = sim.energies();
    let (e0, ke0) = (e.total(), e.kinetic);
    let m = crate::exact::sum(&sim.particles.mass);
    let (mut max_dp, mut max_de, mut min_ke, mut t_min) = (0.0f64, 0.0f64, f64::INFINITY, 0.0);
    let (mut kinetic, mut strain, mut energy_error) = (vec![(0.0, ke0)], vec![(0.0, e.strain)], vec![(0.0, 0.0)]);
    sim.run_until(scene.solver.end_time, |s| {
        let p = &s.particles;
        let scale = crate::exact::sum_iter((0..p.len()).map(|i| p.mass[i] * (p.v[i].x.abs() + p.v[i].y.abs())));
        max_dp = max_dp.max((s.total_momentum() - p0).norm() / scale);
        let e = s.energies();
        max_de = max_de.max(((e.total() - e0) / e0).abs());
        if e.kinetic < min_ke {
            min_ke = e.kinetic;
            t_min = s.time;
        }
        kinetic.push((s.time, e.kinetic));
        strain.push((s.time, e.strain));
        energy_error.push((s.time, (e.total() - e0) / e0));
    })?;
    let p = &sim.particles;
    let (mut m0, mut mv) = (0.0, crate::dim::Vector::zeros());
    for i in (0..p.len()).filter(|&i| p.body[i] == 0) {
        m0 += p.mass[i];
        mv += p.v[i] * p.mass[i];
    }
    Ok(DisksRun {
        scheme: scene.solver.scheme,
        max_dp,
        max_de,
        ke0,
        ke0_exact: 0.5 * m * 0.02,
        ke_final_ratio: sim.energies().kinetic / ke0,
        ke_min_ratio: min_ke / ke0,
        t_ke_min: t_min,
        v_cm0: mv / m0,
        kinetic,
        strain,
        energy_error,
    })
}

/// Case `colliding_disks`.
pub fn run(variant: Variant) -> anyhow::Result<CaseOutput> {
    let (cell, ppc) = match variant {
        Variant::Quick => (0.05, 2),
        Variant::Full => (0.025, 2),
    };
    let mut out = CaseOutput::default();
    let mut runs = Vec::new();
    for scheme in SCHEMES {
        let r = run_disks(&disks_scene(scheme, ppc, cell)?).with_context(|| scheme_name(scheme))?;
        let name = scheme_name(scheme);
        out.measure("momentum", name, r.max_dp, 0.0);
        out.note(format!(
            "{name}: max |ΔP|/Σm|v| = {:.3e}; max |ΔE|/E0 = {:.3e}; KE min {:.4} KE0 at t = {:.3}; KE(end)/KE0 = {:.4}; \
             disk-0 v_cm = ({:+.4}, {:+.4})",
            r.max_dp, r.max_de, r.ke_min_ratio, r.t_ke_min, r.ke_final_ratio, r.v_cm0.x, r.v_cm0.y
        ));
        if scheme == Scheme::Usavg {
            out.measure("initial_ke", name, r.ke0, r.ke0_exact);
            out.measure("usavg_energy", name, r.max_de, 0.0);
            out.measure("rebound", name, r.v_cm0.x.max(r.v_cm0.y), f64::NAN);
            out.measure("ke_recovered", name, r.ke_final_ratio, f64::NAN);
        }
        runs.push(r);
    }
    let usavg = runs.iter().find(|r| r.scheme == Scheme::Usavg).context("usavg ran")?;
    out.figure(
        "colliding_disks_energies.png",
        "Kinetic, strain and total energy of the two colliding disks (USAVG): KE turns into SE during the contact and back.",
        PlotSpec::new("Colliding disks: energies (USAVG)", "time t", "energy"),
        Plot::Lines(vec![
            Series::line("kinetic", usavg.kinetic.clone()),
            Series::line("strain", usavg.strain.clone()),
            Series::line("kinetic + strain", usavg.kinetic.iter().zip(&usavg.strain).map(|(k, s)| (k.0, k.1 + s.1)).collect()),
        ]),
    );
    out.figure(
        "colliding_disks_energy_error.png",
        "Relative total-energy error of the colliding disks per update scheme.",
        PlotSpec::new("Colliding disks: energy error per update scheme", "time t", "(E − E0) / E0"),
        Plot::Lines(runs.iter().map(|r| Series::line(scheme_name(r.scheme), r.energy_error.clone())).collect()),
    );
    Ok(out)
}
