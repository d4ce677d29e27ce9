//! MPM versus FEA on the same scene: σxx along the grid line of a crack (Nairn 2003
//! §3.1, Fig. 2: "the x direction stress along the mid-plane of the specimen").
//!
//! * **MPM**: the particle stresses of the damped run extrapolated to the grid nodes per
//!   velocity field, f_{i,k} = Σ_p m_p f_p N_{i,p} δ_{k,ν(p,i)} / M_{i,k} (Guo & Nairn 2004
//!   eq. 11; [`Simulation::nodal_state`]) — "by the same methods used to extrapolate
//!   momenta to the grid" (Nairn 2003 §3.1).
//! * **FEA**: the nodal-averaged stress of the static Q4 solution on the same grid
//!   ([`super::solve::nodal_average`]: Gauss values extrapolated bilinearly to the
//!   corners, averaged over the elements at the node).
//!
//! At a node on the crack faces both methods have two values (two velocity fields /
//! two node copies); the comparison takes the **upper face**, the side x2 > 0 of the
//! crack-tip frame (x1 along the crack towards the uncracked ligament, x2 = x1 rotated
//! +90°): in the MPM the field of the particles on that side (read from the particle–node
//! pairs of the last step), in the FEA the node copy used by the elements on that side.
//! Ahead of the tip there is a single field / node. The crack-tip node (the first node
//! the MPM does not split, where the FEA crack is meshed to end) is the singular point:
//! it is listed but excluded from the maximum difference.
//!
//! [`mpm_vs_fea`] runs both analyses from one scene and returns the table
//! ([`mpm_vs_fea_dcb`]: the verification DCB); the data can be written as CSV
//! ([`LineComparison::csv`]) and plotted ([`LineComparison::plot`]).

use super::scene::SceneFea;
use super::solve::{ElementProperties, Solution};
use crate::dim::{Sym, Vector};
use crate::output::{run_scene, RunOptions};
use crate::report::plot::{format_sig, line_plot, LegendPosition, PlotSpec, Series};
use crate::scene::Scene;
use crate::shape::MAX_NODES;
use crate::simulation::Simulation;
use anyhow::{bail, Context};
use serde::Serialize;
use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

/// One grid node on the crack line.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct LineRow {
    /// Coordinate along the line (x for a horizontal crack, y for a vertical one).
    pub s: f64,
    pub position: [f64; 2],
    pub grid_node: [usize; 2],
    /// MPM velocity field read (0 single, 1 above, 2 below).
    pub mpm_field: usize,
    pub mpm_sxx: f64,
    pub fea_sxx: f64,
    /// The FEA stress field sampled at the initial positions of the particles that the
    /// MPM value averages, and averaged with the same weights m_p N_{i,p} (eq. 11 applied
    /// to the FEA field): separates a difference of the stress fields from a difference
    /// of the two nodal recoveries.
    pub fea_sxx_eq11: f64,
    /// This is the crack-tip node (excluded from the maximum difference).
    pub is_tip: bool,
    /// The node is split (crack face) in the FEA.
    pub on_crack_face: bool,
}

/// σxx along a crack line from the MPM and the FEA, with the summary numbers.
#[derive(Clone, Debug, Serialize)]
pub struct LineComparison {
    pub title: String,
    pub rows: Vec<LineRow>,
    pub tip_position: [f64; 2],
    /// max |σxx| of the FEA over all rows (the crack-tip node included).
    pub peak: f64,
    /// max |σxx,MPM − σxx,FEA| over all rows except the crack-tip node, and where.
    pub max_diff: f64,
    pub max_diff_at: [f64; 2],
    /// The same at the crack-tip node (reported, not part of the criterion).
    pub tip_diff: f64,
    /// max |σxx| of the FEA field averaged like the MPM (eq. 11), crack tip included.
    pub peak_eq11: f64,
    /// max |σxx,MPM − σxx,FEA via eq. 11| except at the tip, and where.
    pub max_diff_eq11: f64,
    pub max_diff_eq11_at: [f64; 2],
    /// MPM run: end time, steps, wall time, final kinetic and strain energy.
    pub mpm_time: f64,
    pub mpm_steps: u64,
    pub mpm_wall_s: f64,
    pub mpm_kinetic: f64,
    pub mpm_strain_energy: f64,
    /// FEA strain energy ½ fᵀu and wall time.
    pub fea_strain_energy: f64,
    pub fea_wall_s: f64,
}

/// Compare σxx on the grid line of scene crack `crack` (its meshed tip must exist) for a
/// finished MPM run `sim` and the FEA solution `sol` of `fea` (same scene).
pub fn compare_on_crack_line(
    sim: &Simulation,
    fea: &SceneFea,
    sol: &Solution,
    crack: usize,
) -> anyhow::Result<LineComparison> {
    let Some(sc) = fea.cracks.get(crack) else { bail!("the scene has no crack {crack}") };
    let tips: Vec<_> = sc.meshed.tips.iter().flatten().collect();
    let [tip] = tips.as_slice() else {
        bail!("crack {crack} has {} tips in the mesh; the comparison needs exactly one (an edge crack)", tips.len())
    };
    let gm = &fea.grid_mesh;
    let g = &gm.grid;
    if sim.grid.nx != g.nx || sim.grid.ny != g.ny || sim.grid.origin != g.origin || sim.grid.h != g.h {
        bail!("the MPM run and the FEA are not on the same grid");
    }
    let e1 = tip.direction;
    let e2 = Vector::new(-e1.y, e1.x);
    let horizontal = e1.y == 0.0;
    let [it, jt] = tip.grid_node;
    let line_nodes: Vec<[usize; 2]> =
        if horizontal { (0..=g.nx).map(|i| [i, jt]).collect() } else { (0..=g.ny).map(|j| [it, j]).collect() };
    let pairs = &sim.pairs;
    let p = &sim.particles;
    let mut rows = Vec::new();
    for [i, j] in line_nodes {
        let copies = gm.nodes_at(i, j);
        if copies.is_empty() {
            continue;
        }
        let xn = g.node_position(i, j);
        // FEA: the copy used by an element on the upper side.
        let mut fea_node = copies[0];
        for (di, dj, corner) in [(0isize, 0isize, 0usize), (-1, 0, 1), (-1, -1, 2), (0, -1, 3)] {
            if let Some(e) = gm.element_at(i as isize + di, j as isize + dj) {
                let c = g.cell_center((i as isize + di) as usize, (j as isize + dj) as usize);
                if (c - xn).dot(&e2) > 0.0 {
                    fea_node = gm.mesh.elements[e][corner];
                }
            }
        }
        // MPM: the field the particles on the upper side use at this node.
        let node = sim.grid.node_index(i, j);
        let items = pairs.of_node(node);
        let field = items
            .iter()
            .find(|&&it| (p.x[it as usize / MAX_NODES] - xn).dot(&e2) > 0.0)
            .map(|&it| pairs.field[it as usize] as usize);
        let Some(field) = field else { continue };
        let Some(state) = sim.nodal_state(node)[field] else { continue };
        let (mut num, mut den) = (0.0, 0.0);
        for &item in items {
            let item = item as usize;
            if pairs.field[item] as usize != field {
                continue;
            }
            let pp = item / MAX_NODES;
            let w = p.mass[pp] * pairs.s[item];
            num += w * fea_stress_at(fea, sol, p.x0[pp]).map_or(f64::NAN, |s| s.xx);
            den += w;
        }
        rows.push(LineRow {
            s: if horizontal { xn.x } else { xn.y },
            position: [xn.x, xn.y],
            grid_node: [i, j],
            mpm_field: field,
            mpm_sxx: state.stress.xx,
            fea_sxx: sol.nodal_stress[fea_node].xx,
            fea_sxx_eq11: num / den,
            is_tip: [i, j] == tip.grid_node,
            on_crack_face: copies.len() > 1,
        });
    }
    if rows.is_empty() {
        bail!("no node of the crack line holds material in both analyses");
    }
    let peak = rows.iter().map(|r| r.fea_sxx.abs()).fold(0.0, f64::max);
    let (mut max_diff, mut max_diff_at, mut tip_diff) = (0.0, [f64::NAN; 2], 0.0);
    for r in &rows {
        let d = (r.mpm_sxx - r.fea_sxx).abs();
        if r.is_tip {
            tip_diff = d;
        } else if d > max_diff || max_diff_at[0].is_nan() {
            max_diff = d;
            max_diff_at = r.position;
        }
    }
    let peak_eq11 = rows.iter().map(|r| r.fea_sxx_eq11.abs()).fold(0.0, f64::max);
    let (mut max_diff_eq11, mut max_diff_eq11_at) = (0.0, [f64::NAN; 2]);
    for r in rows.iter().filter(|r| !r.is_tip) {
        let d = (r.mpm_sxx - r.fea_sxx_eq11).abs();
        if d > max_diff_eq11 || max_diff_eq11_at[0].is_nan() {
            max_diff_eq11 = d;
            max_diff_eq11_at = r.position;
        }
    }
    let e = sim.energies();
    Ok(LineComparison {
        title: String::new(),
        rows,
        tip_position: [tip.position.x, tip.position.y],
        peak,
        max_diff,
        max_diff_at,
        tip_diff,
        peak_eq11,
        max_diff_eq11,
        max_diff_eq11_at,
        mpm_time: sim.time,
        mpm_steps: sim.step_count,
        mpm_wall_s: 0.0,
        mpm_kinetic: e.kinetic,
        mpm_strain_energy: e.strain,
        fea_strain_energy: 0.0,
        fea_wall_s: 0.0,
    })
}

/// The FEA stress at a point inside the material, from the displacements of the element
/// (grid cell) that contains it (strain B(ξ, η) u_e, stress D ε).
pub fn fea_stress_at(fea: &SceneFea, sol: &Solution, x: Vector) -> Option<Sym> {
    let gm = &fea.grid_mesh;
    let g = &gm.grid;
    let fi = (x.x - g.origin.x) / g.h.x;
    let fj = (x.y - g.origin.y) / g.h.y;
    let e = gm.element_at(fi.floor() as isize, fj.floor() as isize)?;
    let [i, j] = gm.element_cell[e];
    let c = g.cell_center(i, j);
    let xe = gm.mesh.element_coords(e);
    let pd = super::element::point_data(&xe, 2.0 * (x.x - c.x) / g.h.x, 2.0 * (x.y - c.y) / g.h.y).ok()?;
    let u = gm.mesh.elements[e].map(|a| sol.displacement[a]);
    let eps = super::element::strain(&pd.grad_n, &u);
    let (material, thickness) = fea.groups[fea.element_body[e]];
    Some(ElementProperties::new(material, thickness).stress_from_strain(&eps))
}

/// Solve `scene` with the FEA and compare with the finished MPM run `sim` of the same
/// scene along the grid line of crack 0 (see the module doc).
pub fn compare_with_fea(sim: &Simulation, scene: &Scene) -> anyhow::Result<LineComparison> {
    let t0 = Instant::now();
    let fea = SceneFea::from_scene(scene)?;
    let analysis = fea.analyse()?;
    let mut c = compare_on_crack_line(sim, &fea, &analysis.solution, 0)?;
    c.title = scene.title.clone();
    c.fea_wall_s = t0.elapsed().as_secs_f64();
    c.fea_strain_energy = analysis.strain_energy;
    Ok(c)
}

/// Run the scene with the MPM to its end time (damped to the static state) and with the
/// FEA, and compare σxx on the grid line of crack 0 (see the module doc). `checked`
/// overrides the scene's `solver.checked`.
pub fn mpm_vs_fea(scene: &Scene, checked: Option<bool>) -> anyhow::Result<LineComparison> {
    let t1 = Instant::now();
    let run = run_scene(scene, &RunOptions { checked, ..Default::default() })?;
    let mpm_wall_s = t1.elapsed().as_secs_f64();
    let mut c = compare_with_fea(&run.sim, scene)?;
    c.mpm_wall_s = mpm_wall_s;
    Ok(c)
}

/// `verification/dcb_nairn2003.toml`, embedded: the DCB of Nairn 2003 §3.1.
pub const DCB_NAIRN2003_SCENE: &str = include_str!("../../verification/dcb_nairn2003.toml");

/// Nairn 2003 §3.1, Fig. 2: the damped MPM DCB against the static FEA of the same scene
/// ([`DCB_NAIRN2003_SCENE`], [`mpm_vs_fea`]); ~2100 MPM steps, ~30 s in release.
/// `tests/mpm_vs_fea.rs` states the criterion and the measured agreement.
pub fn mpm_vs_fea_dcb(checked: Option<bool>) -> anyhow::Result<LineComparison> {
    let scene = Scene::from_toml(DCB_NAIRN2003_SCENE, "verification/dcb_nairn2003.toml")?;
    mpm_vs_fea(&scene, checked)
}

impl LineComparison {
    /// `s,x,y,i,j,mpm_field,mpm_sxx,fea_sxx,diff,fea_sxx_eq11,is_tip,on_crack_face`.
    pub fn csv(&self) -> String {
        let mut t = String::from("s,x,y,i,j,mpm_field,mpm_sxx,fea_sxx,diff,fea_sxx_eq11,is_tip,on_crack_face\n");
        for r in &self.rows {
            let _ = writeln!(
                t,
                "{:e},{:e},{:e},{},{},{},{:e},{:e},{:e},{:e},{},{}",
                r.s,
                r.position[0],
                r.position[1],
                r.grid_node[0],
                r.grid_node[1],
                r.mpm_field,
                r.mpm_sxx,
                r.fea_sxx,
                r.mpm_sxx - r.fea_sxx,
                r.fea_sxx_eq11,
                r.is_tip,
                r.on_crack_face
            );
        }
        t
    }

    /// The curves on one PNG (markers at the nodes): the MPM, the FEA nodal-averaged
    /// stress, and the FEA field averaged like the MPM (eq. 11); the crack-tip node is
    /// named in the title.
    pub fn plot(&self, path: impl AsRef<Path>) -> anyhow::Result<()> {
        let (spec, series) = self.plot_data();
        line_plot(path.as_ref(), &spec, &series).with_context(|| format!("plotting {}", path.as_ref().display()))
    }

    /// The figure of [`LineComparison::plot`] as data (for the verification report).
    pub fn plot_data(&self) -> (PlotSpec, Vec<Series>) {
        let curve = |f: fn(&LineRow) -> f64| -> Vec<(f64, f64)> { self.rows.iter().map(|r| (r.s, f(r))).collect() };
        let title = format!(
            "σxx on the crack line: MPM vs FEA (tip node at {}, {})",
            self.tip_position[0], self.tip_position[1]
        );
        let spec = PlotSpec::new(&title, "position along the crack line", "σxx").with_legend(LegendPosition::UpperLeft);
        let series = vec![
            Series::line(
                &format!("MPM, damped to t = {} (eq. 11)", format_sig(self.mpm_time, 4)),
                curve(|r| r.mpm_sxx),
            )
            .with_markers(),
            Series::line("static FEA, nodal-averaged", curve(|r| r.fea_sxx)).with_markers(),
            Series::line("static FEA field averaged like the MPM (eq. 11)", curve(|r| r.fea_sxx_eq11)).with_markers(),
        ];
        (spec, series)
    }

    /// A few lines for logs and test output.
    pub fn text(&self) -> String {
        let pct = |d: f64, peak: f64| 100.0 * d / peak;
        format!(
            "MPM (eq. 11) vs FEA field averaged like the MPM (eq. 11): peak |σxx| {:.6e}, max difference away from the tip \
             {:.6e} = {:.2} % of the peak at ({}, {})\n\
             MPM (eq. 11) vs FEA nodal-averaged: peak |σxx| {:.6e}, max difference away from the tip {:.6e} = {:.2} % of \
             the peak at ({}, {}); at the tip node {:.6e} = {:.2} %\n\
             MPM: t = {} ({} steps, {:.1} s), kinetic energy {:.3e}, strain energy {:.6e}; FEA strain energy {:.6e} \
             ({:+.3} %), {:.3} s",
            self.peak_eq11,
            self.max_diff_eq11,
            pct(self.max_diff_eq11, self.peak_eq11),
            self.max_diff_eq11_at[0],
            self.max_diff_eq11_at[1],
            self.peak,
            self.max_diff,
            pct(self.max_diff, self.peak),
            self.max_diff_at[0],
            self.max_diff_at[1],
            self.tip_diff,
            pct(self.tip_diff, self.peak),
            self.mpm_time,
            self.mpm_steps,
            self.mpm_wall_s,
            self.mpm_kinetic,
            self.mpm_strain_energy,
            self.fea_strain_energy,
            100.0 * (self.mpm_strain_energy - self.fea_strain_energy) / self.fea_strain_energy,
            self.fea_wall_s
        )
    }
}
