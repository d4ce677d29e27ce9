//! `cramp fea SCENE [--out DIR]`: map a scene onto the FEA ([`super::scene`]), solve,
//! evaluate J and K at every crack tip, and write
//!
//! * `fea.vtk` — the mesh (legacy VTK, UNSTRUCTURED_GRID of quads) with nodal
//!   displacement, nodal-averaged stress and the element-mean stress; crack faces are
//!   separate points, so *Warp By Vector* opens the crack in ParaView;
//! * `fea_gauss.vtk` — the 2×2 Gauss points of every element (POLYDATA vertices) with
//!   their stress, strain and element number;
//! * `fea_nodes.csv` — `node,i,j,x,y,ux,uy,sxx,syy,sxy,szz` (nodal-averaged stress);
//! * `probe_<name>.csv` for every `[[probes]]` entry — `s,x,y,sxx,syy,sxy,szz` with the
//!   nodal-averaged stress interpolated in the containing element (empty fields where
//!   the point is outside the mesh; on an element edge the first element in mesh order,
//!   i.e. the lower/left one, is used);
//! * `fea_summary.json` — mesh size, notes on what the static FEA ignored, load
//!   resultant, supports, strain energy, and per crack tip J (equivalent domain integral),
//!   K_I and K_II (interaction integral), √(E′J) and the COD mode split for domains of
//!   1 to 8 cells.
//!
//! Numbers are written with Rust's shortest round-trip format (`{:e}`).

use super::element::{self, GAUSS};
use super::jintegral::JResult;
use super::output::{probe_line, write_vtk};
use super::scene::{FeaAnalysis, SceneFea, TipResult};
use crate::dim::{Sym, Vector};
use crate::output::vtk::{write_points, PointData};
use crate::scene::Scene;
use anyhow::Context;
use serde::Serialize;
use std::fmt::Write as _;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// J and K for one domain, as written to the summary.
#[derive(Clone, Debug, Serialize)]
pub struct DomainSummary {
    pub cells: usize,
    pub j: f64,
    pub k_i: f64,
    pub k_ii: f64,
    pub k_from_j: f64,
    pub k_i_cod: f64,
    pub k_ii_cod: f64,
    /// Crack-face displacement jump at the first node pair behind the tip (sliding, opening).
    pub cod: [f64; 2],
}

impl From<&JResult> for DomainSummary {
    fn from(r: &JResult) -> Self {
        DomainSummary {
            cells: r.cells,
            j: r.j,
            k_i: r.k1,
            k_ii: r.k2,
            k_from_j: r.k_from_j,
            k_i_cod: r.k1_cod,
            k_ii_cod: r.k2_cod,
            cod: [r.cod.x, r.cod.y],
        }
    }
}

/// One crack tip in the summary.
#[derive(Clone, Debug, Serialize)]
pub struct TipSummary {
    pub crack: usize,
    /// "start" or "end" of the polyline.
    pub end: String,
    pub scene_position: [f64; 2],
    pub meshed_position: [f64; 2],
    pub meshed_node: usize,
    pub direction: [f64; 2],
    pub domains: Vec<DomainSummary>,
    pub skipped: Option<String>,
}

/// One probe in the summary.
#[derive(Clone, Debug, Serialize)]
pub struct ProbeSummary {
    pub name: String,
    pub file: String,
    pub points: usize,
    pub outside_mesh: usize,
}

/// fea_summary.json.
#[derive(Clone, Debug, Serialize)]
pub struct FeaSummary {
    pub title: String,
    /// The scene as read.
    pub scene: Scene,
    pub analysis: String,
    pub elements: usize,
    pub nodes: usize,
    pub equations: usize,
    pub particles: usize,
    pub loaded_particles: usize,
    pub load_resultant: [f64; 2],
    pub prescribed_dofs: usize,
    pub automatic_supports: usize,
    pub max_reaction_at_automatic_supports: f64,
    pub strain_energy: f64,
    pub notes: Vec<String>,
    pub tips: Vec<TipSummary>,
    pub probes: Vec<ProbeSummary>,
    pub wall_time_s: f64,
    pub solve_time_s: f64,
    pub j_time_s: f64,
}

/// Everything `cramp fea` produced, in memory.
pub struct FeaReport {
    pub mapping: SceneFea,
    pub analysis: FeaAnalysis,
    pub summary: FeaSummary,
    pub out_dir: Option<PathBuf>,
}

fn tip_summary(t: &TipResult) -> TipSummary {
    TipSummary {
        crack: t.crack,
        end: if t.end == 0 { "start" } else { "end" }.into(),
        scene_position: [t.scene_position.x, t.scene_position.y],
        meshed_position: [t.tip.position.x, t.tip.position.y],
        meshed_node: t.tip.node,
        direction: [t.tip.direction.x, t.tip.direction.y],
        domains: t.domains.iter().map(DomainSummary::from).collect(),
        skipped: t.skipped.clone(),
    }
}

/// Map, solve and (if `out_dir` is given) write the files listed in the module doc.
pub fn run_fea(scene: &Scene, out_dir: Option<&Path>) -> anyhow::Result<FeaReport> {
    let start = Instant::now();
    let mapping = SceneFea::from_scene(scene)?;
    let analysis = mapping.analyse()?;
    let mesh = &mapping.grid_mesh.mesh;
    let sol = &analysis.solution;
    let mut probes = Vec::new();
    if let Some(dir) = out_dir {
        std::fs::create_dir_all(dir).with_context(|| format!("cannot create output directory {}", dir.display()))?;
    }
    for spec in &scene.probes {
        let from = Vector::new(spec.from[0], spec.from[1]);
        let to = Vector::new(spec.to[0], spec.to[1]);
        let samples = probe_line(mesh, sol, from, to, spec.points);
        let rows = samples.iter().map(|s| {
            let p = s.position;
            ([(p - from).norm(), p.x, p.y], s.stress.map(|st| [st.xx, st.yy, st.xy, st.zz]))
        });
        probes.push(write_probe(out_dir, &spec.name, "s,x,y,sxx,syy,sxy,szz", rows)?);
    }
    let summary = FeaSummary {
        title: scene.title.clone(),
        scene: scene.clone(),
        analysis: "static, linear elastic, small strain; Q4 elements on the scene grid, 2×2 Gauss points; \
                   sparse Cholesky (faer)"
            .into(),
        elements: mesh.elements.len(),
        nodes: mesh.n_nodes(),
        equations: analysis.equations,
        particles: mapping.n_particles,
        loaded_particles: mapping.n_loaded_particles,
        load_resultant: [mapping.load_resultant.x, mapping.load_resultant.y],
        prescribed_dofs: mapping.bcs.prescribed().iter().filter(|p| p.is_some()).count(),
        automatic_supports: mapping.auto_supports.len(),
        max_reaction_at_automatic_supports: analysis.max_auto_reaction,
        strain_energy: analysis.strain_energy,
        notes: mapping.notes.clone(),
        tips: analysis.tips.iter().map(tip_summary).collect(),
        probes,
        wall_time_s: start.elapsed().as_secs_f64(),
        solve_time_s: analysis.solve_seconds,
        j_time_s: analysis.j_seconds,
    };
    if let Some(dir) = out_dir {
        let mut vtk = Vec::new();
        let title =
            if scene.title.is_empty() { "cramp FEA".to_string() } else { format!("cramp FEA: {}", scene.title) };
        write_vtk(&mut vtk, mesh, sol, &title)?;
        write_file(&dir.join("fea.vtk"), &vtk)?;

        let mut pos = Vec::with_capacity(4 * mesh.elements.len());
        let mut stress = Vec::with_capacity(pos.capacity());
        let mut strain = Vec::with_capacity(pos.capacity());
        let mut elem = Vec::with_capacity(pos.capacity());
        for e in 0..mesh.elements.len() {
            let x = mesh.element_coords(e);
            for (g, [xi, eta]) in GAUSS.iter().enumerate() {
                pos.push(element::map_to_physical(&x, *xi, *eta));
                stress.push(sol.gauss_stress[e][g]);
                strain.push(sol.gauss_strain[e][g]);
                elem.push(e as f64);
            }
        }
        let gauss_data: [(&str, PointData); 3] = [
            ("stress", PointData::Tensor(&stress)),
            ("strain", PointData::Tensor(&strain)),
            ("element", PointData::Scalar(&elem)),
        ];
        write_points(dir.join("fea_gauss.vtk"), &format!("{title}, Gauss points"), &pos, &gauss_data)
            .with_context(|| format!("cannot write {}", dir.join("fea_gauss.vtk").display()))?;

        let mut csv = String::from("node,i,j,x,y,ux,uy,sxx,syy,sxy,szz\n");
        for a in 0..mesh.n_nodes() {
            let [i, j] = mapping.grid_mesh.node_grid[a];
            let (x, u, s): (Vector, Vector, Sym) = (mesh.nodes[a], sol.displacement[a], sol.nodal_stress[a]);
            let _ = writeln!(
                csv,
                "{a},{i},{j},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e}",
                x.x, x.y, u.x, u.y, s.xx, s.yy, s.xy, s.zz
            );
        }
        write_file(&dir.join("fea_nodes.csv"), csv.as_bytes())?;
        let json = serde_json::to_string_pretty(&summary)?;
        write_file(&dir.join("fea_summary.json"), json.as_bytes())?;
    }
    Ok(FeaReport { mapping, analysis, summary, out_dir: out_dir.map(Path::to_path_buf) })
}

/// `probe_<name>.csv` in `dir` (if given): the header, then per sample its leading
/// columns (distance from the start, coordinates) and its stress components, or empty
/// stress fields outside the mesh. Returns the probe's summary. Shared by 2D and 3D.
pub(super) fn write_probe<const A: usize, const B: usize>(
    dir: Option<&Path>,
    name: &str,
    header: &str,
    rows: impl Iterator<Item = ([f64; A], Option<[f64; B]>)>,
) -> anyhow::Result<ProbeSummary> {
    let file = format!("probe_{name}.csv");
    let (mut text, mut points, mut outside_mesh) = (format!("{header}\n"), 0, 0);
    for (lead, stress) in rows {
        points += 1;
        text.push_str(&lead.iter().map(|v| format!("{v:e}")).collect::<Vec<_>>().join(","));
        match stress {
            Some(st) => st.iter().for_each(|v| {
                let _ = write!(text, ",{v:e}");
            }),
            None => {
                outside_mesh += 1;
                text.push_str(&",".repeat(B));
            }
        }
        text.push('\n');
    }
    if let Some(dir) = dir {
        write_file(&dir.join(&file), text.as_bytes())?;
    }
    Ok(ProbeSummary { name: name.to_string(), file, points, outside_mesh })
}

pub(super) fn write_file(path: &Path, bytes: &[u8]) -> anyhow::Result<()> {
    let mut f = std::fs::File::create(path).with_context(|| format!("cannot create {}", path.display()))?;
    f.write_all(bytes).with_context(|| format!("cannot write {}", path.display()))
}

impl FeaReport {
    /// A few lines for the terminal: mesh, notes, J/K per tip.
    pub fn text(&self) -> String {
        let s = &self.summary;
        let mut t = String::new();
        let title = if s.title.is_empty() { "scene" } else { &s.title };
        let _ = writeln!(
            t,
            "{title}: static FEA, {} elements, {} nodes, {} equations, solved in {:.3} s",
            s.elements, s.nodes, s.equations, s.solve_time_s
        );
        let _ = writeln!(
            t,
            "load resultant ({:e}, {:e}) from {} particles; strain energy {:.6e}",
            s.load_resultant[0], s.load_resultant[1], s.loaded_particles, s.strain_energy
        );
        for n in &s.notes {
            let _ = writeln!(t, "note: {n}");
        }
        for tip in &s.tips {
            let _ = writeln!(
                t,
                "crack {} {}: scene tip ({}, {}), meshed at node ({}, {})",
                tip.crack,
                tip.end,
                tip.scene_position[0],
                tip.scene_position[1],
                tip.meshed_position[0],
                tip.meshed_position[1]
            );
            for d in &tip.domains {
                let _ = writeln!(
                    t,
                    "  domain {:>2} cells: J = {:.6e}, K_I = {:.6e}, K_II = {:+.3e}, sqrt(E'J) = {:.6e}",
                    d.cells, d.j, d.k_i, d.k_ii, d.k_from_j
                );
            }
            if let Some(sk) = &tip.skipped {
                let _ = writeln!(t, "  {sk}");
            }
        }
        if let Some(dir) = &self.out_dir {
            let _ = writeln!(t, "outputs in {}", dir.display());
        }
        t
    }
}
