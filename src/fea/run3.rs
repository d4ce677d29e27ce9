//! `cramp fea SCENE` for a 3D scene: map ([`super::scene3`]), solve, and write the files
//! of the 2D run ([`super::run`]) in their 3D form:
//!
//! * `fea.vtk` — hexahedra (legacy VTK) with nodal displacement, nodal-averaged stress and
//!   the element-mean stress;
//! * `fea_gauss.vtk` — the 2×2×2 Gauss points of every element with stress, strain and
//!   element number;
//! * `fea_nodes.csv` — `node,i,j,k,x,y,z,ux,uy,uz,sxx,syy,szz,sxy,sxz,syz`;
//! * `probe_<name>.csv` per `[[probes]]` entry — `s,x,y,z,sxx,syy,szz,sxy,sxz,syz`
//!   (empty fields outside the mesh);
//! * `fea_front.csv` (when the scene has meshed cracks) — `crack,node,i,j,k,x,y,z,cells,J,K_I,K_II,K_III`
//!   per front node and domain;
//! * `fea_summary.json` — mesh and system size, notes, load resultant, supports, strain
//!   energy, probes, and the times of assembly, factorisation + solve and stress recovery
//!   with the peak resident memory of the process.

use super::output3::{probe_line_3d, write_vtk_3d};
use super::run::{write_file, write_probe, ProbeSummary};
use super::scene3::{FeaAnalysis3, FrontResult, SceneFea3};
use super::hex8::{self, GAUSS};
use crate::dim::Vector3;
use crate::output::vtk::{write_points_3d, PointData};
use crate::scene3d::Scene3;
use anyhow::Context;
use serde::Serialize;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// fea_summary.json of a 3D scene.
#[derive(Clone, Debug, Serialize)]
pub struct FeaSummary3 {
    pub title: String,
    pub scene: Scene3,
    pub analysis: String,
    pub elements: usize,
    pub nodes: usize,
    pub equations: usize,
    /// Non-zeros of the stored lower triangle of K_ff.
    pub matrix_nonzeros: usize,
    pub particles: usize,
    pub loaded_particles: usize,
    pub load_resultant: [f64; 3],
    pub prescribed_dofs: usize,
    pub automatic_supports: usize,
    pub max_reaction_at_automatic_supports: f64,
    pub strain_energy: f64,
    pub notes: Vec<String>,
    pub probes: Vec<ProbeSummary>,
    /// Per front node of every meshed crack: J (3D equivalent domain integral), K_I, K_II,
    /// K_III (plane strain inside, COD mode split) for domains of 1 to 8 cells.
    pub front: Vec<FrontResult>,
    pub wall_time_s: f64,
    pub assembly_time_s: f64,
    /// Symbolic + numeric Cholesky and the solve.
    pub solve_time_s: f64,
    pub stress_time_s: f64,
    pub j_time_s: f64,
    /// Peak resident set of the process so far (Linux VmHWM), if known.
    pub peak_memory_bytes: Option<u64>,
}

/// Everything `cramp fea` produced for a 3D scene, in memory.
pub struct FeaReport3 {
    pub mapping: SceneFea3,
    pub analysis: FeaAnalysis3,
    pub summary: FeaSummary3,
    pub out_dir: Option<PathBuf>,
}

/// Peak resident set size of this process (VmHWM of /proc/self/status), if readable.
pub fn peak_memory_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}

/// Map, solve and (if `out_dir` is given) write the files listed in the module doc.
pub fn run_fea_3d(scene: &Scene3, out_dir: Option<&Path>) -> anyhow::Result<FeaReport3> {
    let start = Instant::now();
    let mapping = SceneFea3::from_scene(scene)?;
    let analysis = mapping.analyse()?;
    let mesh = &mapping.grid_mesh.mesh;
    let sol = &analysis.solution;
    if let Some(dir) = out_dir {
        std::fs::create_dir_all(dir).with_context(|| format!("cannot create output directory {}", dir.display()))?;
    }
    let mut probes = Vec::new();
    for spec in &scene.probes {
        let (from, to) = (Vector3::from(spec.from), Vector3::from(spec.to));
        let samples = probe_line_3d(mesh, sol, from, to, spec.points);
        let rows = samples.iter().map(|s| {
            let p = s.position;
            ([(p - from).norm(), p.x, p.y, p.z], s.stress.map(|t| [t.xx, t.yy, t.zz, t.xy, t.xz, t.yz]))
        });
        probes.push(write_probe(out_dir, &spec.name, "s,x,y,z,sxx,syy,szz,sxy,sxz,syz", rows)?);
    }
    let summary = FeaSummary3 {
        title: scene.title.clone(),
        scene: scene.clone(),
        analysis: "static, linear elastic, small strain; trilinear hexahedra (hex8) on the scene grid, 2×2×2 Gauss \
                   points; sparse Cholesky (faer)"
            .into(),
        elements: mesh.elements.len(),
        nodes: mesh.n_nodes(),
        equations: analysis.equations,
        matrix_nonzeros: analysis.matrix_nonzeros,
        particles: mapping.n_particles,
        loaded_particles: mapping.n_loaded_particles,
        load_resultant: mapping.load_resultant.into(),
        prescribed_dofs: mapping.bcs.prescribed().iter().filter(|p| p.is_some()).count(),
        automatic_supports: mapping.auto_supports.len(),
        max_reaction_at_automatic_supports: analysis.max_auto_reaction,
        strain_energy: analysis.strain_energy,
        notes: mapping.notes.clone(),
        probes,
        front: analysis.front.clone(),
        wall_time_s: start.elapsed().as_secs_f64(),
        assembly_time_s: analysis.assembly_seconds,
        solve_time_s: analysis.solve_seconds,
        stress_time_s: analysis.stress_seconds,
        j_time_s: analysis.j_seconds,
        peak_memory_bytes: peak_memory_bytes(),
    };
    if let Some(dir) = out_dir {
        let title = if scene.title.is_empty() { "cramp FEA".to_string() } else { format!("cramp FEA: {}", scene.title) };
        let mut vtk = Vec::new();
        write_vtk_3d(&mut vtk, mesh, sol, &title)?;
        write_file(&dir.join("fea.vtk"), &vtk)?;

        let n_gauss = 8 * mesh.elements.len();
        let (mut pos, mut elem) = (Vec::with_capacity(n_gauss), Vec::with_capacity(n_gauss));
        for e in 0..mesh.elements.len() {
            let x = mesh.element_coords(e);
            for xi in GAUSS {
                pos.push(hex8::map_to_physical(&x, xi));
                elem.push(e as f64);
            }
        }
        let stress: Vec<_> = sol.gauss_stress.iter().flatten().copied().collect();
        let strain: Vec<_> = sol.gauss_strain.iter().flatten().copied().collect();
        let gauss_data: [(&str, PointData); 3] = [
            ("stress", PointData::Tensor3(&stress)),
            ("strain", PointData::Tensor3(&strain)),
            ("element", PointData::Scalar(&elem)),
        ];
        write_points_3d(dir.join("fea_gauss.vtk"), &format!("{title}, Gauss points"), &pos, &gauss_data)
            .with_context(|| format!("cannot write {}", dir.join("fea_gauss.vtk").display()))?;

        let mut csv = String::from("node,i,j,k,x,y,z,ux,uy,uz,sxx,syy,szz,sxy,sxz,syz\n");
        for a in 0..mesh.n_nodes() {
            let [i, j, k] = mapping.grid_mesh.node_grid[a];
            let (x, u, s) = (mesh.nodes[a], sol.displacement[a], sol.nodal_stress[a]);
            let _ = writeln!(
                csv,
                "{a},{i},{j},{k},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e}",
                x.x, x.y, x.z, u.x, u.y, u.z, s.xx, s.yy, s.zz, s.xy, s.xz, s.yz
            );
        }
        write_file(&dir.join("fea_nodes.csv"), csv.as_bytes())?;
        if !analysis.front.is_empty() {
            let mut csv = String::from("crack,node,i,j,k,x,y,z,cells,J,K_I,K_II,K_III\n");
            for f in &analysis.front {
                let [i, j, k] = f.grid_node;
                let [x, y, z] = f.position;
                for d in &f.domains {
                    let _ = writeln!(
                        csv,
                        "{},{},{i},{j},{k},{x:e},{y:e},{z:e},{},{:e},{:e},{:e},{:e}",
                        f.crack, f.node, d.cells, d.j, d.k_i, d.k_ii, d.k_iii
                    );
                }
            }
            write_file(&dir.join("fea_front.csv"), csv.as_bytes())?;
        }
        write_file(&dir.join("fea_summary.json"), serde_json::to_string_pretty(&summary)?.as_bytes())?;
    }
    Ok(FeaReport3 { mapping, analysis, summary, out_dir: out_dir.map(Path::to_path_buf) })
}

impl FeaReport3 {
    /// A few lines for the terminal.
    pub fn text(&self) -> String {
        let s = &self.summary;
        let mut t = String::new();
        let title = if s.title.is_empty() { "scene" } else { &s.title };
        let _ = writeln!(
            t,
            "{title}: static 3D FEA, {} hex8 elements, {} nodes, {} equations ({} stored non-zeros); assembly {:.3} s, \
             Cholesky + solve {:.3} s",
            s.elements, s.nodes, s.equations, s.matrix_nonzeros, s.assembly_time_s, s.solve_time_s
        );
        let _ = writeln!(
            t,
            "load resultant ({:e}, {:e}, {:e}) from {} particles; strain energy {:.6e}",
            s.load_resultant[0], s.load_resultant[1], s.load_resultant[2], s.loaded_particles, s.strain_energy
        );
        if let Some(m) = s.peak_memory_bytes {
            let _ = writeln!(t, "peak memory {:.1} MiB", m as f64 / (1 << 20) as f64);
        }
        for n in &s.notes {
            let _ = writeln!(t, "note: {n}");
        }
        for f in &s.front {
            let [x, y, z] = f.position;
            match f.domains.last() {
                Some(d) => {
                    let _ = writeln!(
                        t,
                        "crack {} front node ({x}, {y}, {z}): J = {:.6e}, K_I = {:.6e}, K_II = {:+.3e}, K_III = {:+.3e} ({} cells)",
                        f.crack, d.j, d.k_i, d.k_ii, d.k_iii, d.cells
                    );
                }
                None => {
                    let _ = writeln!(t, "crack {} front node ({x}, {y}, {z}): {}", f.crack, f.skipped.as_deref().unwrap_or(""));
                }
            }
        }
        if let Some(dir) = &self.out_dir {
            let _ = writeln!(t, "outputs in {}", dir.display());
        }
        t
    }
}
