//! Result tables, line probes and legacy-VTK text for the FEA. Nothing here opens a
//! file: [`write_vtk`] writes to any `std::io::Write` the caller provides.

use super::element;
use super::mesh::Mesh;
use super::solve::Solution;
use crate::dim::{Sym, Vector};
use nalgebra::SVector;
use std::io::{self, Write};

/// Per-node results, flat and indexed by mesh node.
#[derive(Clone, Debug, PartialEq)]
pub struct NodalResults {
    pub position: Vec<Vector>,
    pub displacement: Vec<Vector>,
    /// Nodal-averaged stress (σxx, σyy, σxy, σzz; σzz ≠ 0 in plane strain).
    pub stress: Vec<Sym>,
}

/// Nodal positions, displacements and averaged stresses.
pub fn nodal_results(mesh: &Mesh, sol: &Solution) -> NodalResults {
    NodalResults {
        position: mesh.nodes.clone(),
        displacement: sol.displacement.clone(),
        stress: sol.nodal_stress.clone(),
    }
}

/// One sample of [`probe_line`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProbeSample<V = Vector, S = Sym> {
    pub position: V,
    /// Element that contains the point (the first found, on a shared edge or a crack face).
    pub element: Option<usize>,
    /// Stress interpolated bilinearly (element shape functions) from the nodal-averaged
    /// stresses of the containing element; `None` outside the mesh.
    pub stress: Option<S>,
}

/// Sample the stress at `n` equally spaced points from `from` to `to` (both included;
/// `n = 1` gives `from`). Each point is located by a bounding-box test and the inverse
/// isoparametric map; the cost is O(n × elements), meant for a few hundred points.
pub fn probe_line(mesh: &Mesh, sol: &Solution, from: Vector, to: Vector, n: usize) -> Vec<ProbeSample> {
    let samples = sample_line(mesh.elements.len(), |e| mesh.element_coords(e), from, to, n, |e, x, p| {
        let [xi, eta] = element::map_to_natural(x, p, 1e-10)?;
        let nf = element::shape(xi, eta);
        let conn = mesh.elements[e];
        Some((0..4).fold(Sym::ZERO, |acc, a| acc.add(&sol.nodal_stress[conn[a]].scale(nf[a]))))
    });
    samples
        .into_iter()
        .map(|(position, hit)| ProbeSample { position, element: hit.map(|h| h.0), stress: hit.map(|h| h.1) })
        .collect()
}

/// `n` equally spaced points from `from` to `to` (both included; `n = 1` gives `from`),
/// each with the first element (in mesh order) whose bounding box holds it and for which
/// `locate(e, corners, point)` finds a value. Shared by the Q4 and hex8 probes.
pub(crate) fn sample_line<const D: usize, const N: usize, S>(
    n_elements: usize,
    coords: impl Fn(usize) -> [SVector<f64, D>; N],
    from: SVector<f64, D>,
    to: SVector<f64, D>,
    n: usize,
    locate: impl Fn(usize, &[SVector<f64, D>; N], SVector<f64, D>) -> Option<S>,
) -> Vec<(SVector<f64, D>, Option<(usize, S)>)> {
    let boxes: Vec<(SVector<f64, D>, SVector<f64, D>)> = (0..n_elements)
        .map(|e| {
            let x = coords(e);
            let lo = x.iter().fold(SVector::<f64, D>::repeat(f64::INFINITY), |m, p| m.inf(p));
            let hi = x.iter().fold(SVector::<f64, D>::repeat(f64::NEG_INFINITY), |m, p| m.sup(p));
            (lo, hi)
        })
        .collect();
    (0..n)
        .map(|k| {
            let s = if n > 1 { k as f64 / (n - 1) as f64 } else { 0.0 };
            let p = from + (to - from) * s;
            let hit = boxes.iter().enumerate().find_map(|(e, (lo, hi))| {
                let pad = 1e-12 * (hi - lo).norm();
                if (0..D).any(|c| p[c] < lo[c] - pad || p[c] > hi[c] + pad) {
                    return None;
                }
                locate(e, &coords(e), p).map(|v| (e, v))
            });
            (p, hit)
        })
        .collect()
}

/// The lines of a legacy ASCII VTK unstructured grid up to `POINTS n double` (the title
/// is one line of at most 255 characters; empty: "cramp FEA"). Shared by the Q4 and hex8 writers.
pub(crate) fn vtk_header<W: Write>(out: &mut W, title: &str, n_points: usize) -> io::Result<()> {
    let title: String = title.chars().filter(|c| *c != '\n' && *c != '\r').take(255).collect();
    writeln!(out, "# vtk DataFile Version 3.0")?;
    writeln!(out, "{}", if title.is_empty() { "cramp FEA" } else { &title })?;
    writeln!(out, "ASCII")?;
    writeln!(out, "DATASET UNSTRUCTURED_GRID")?;
    writeln!(out, "POINTS {n_points} double")
}

fn tensor_row(s: &Sym) -> String {
    format!("{:e} {:e} 0 {:e} {:e} 0 0 0 {:e}", s.xx, s.xy, s.xy, s.yy, s.zz)
}

/// Write the mesh and solution as a legacy ASCII VTK file (format "vtk DataFile Version 3.0",
/// DATASET UNSTRUCTURED_GRID, one VTK_QUAD (type 9) per element; z = 0).
///
/// * POINT_DATA: `displacement` (VECTORS) and `stress` (TENSORS, nodal-averaged, σzz included).
/// * CELL_DATA: `stress` (TENSORS, mean of the four Gauss-point stresses).
///
/// Crack-face copies of a node are separate points at the same position, so "Warp By
/// Vector" on the displacement opens the crack in ParaView. Non-finite numbers are
/// written as they are (`NaN`, `inf`), which the VTK reader accepts.
pub fn write_vtk<W: Write>(out: &mut W, mesh: &Mesh, sol: &Solution, title: &str) -> io::Result<()> {
    if sol.displacement.len() != mesh.n_nodes() || sol.gauss_stress.len() != mesh.elements.len() {
        return Err(io::Error::new(io::ErrorKind::InvalidInput, "the solution does not belong to this mesh"));
    }
    vtk_header(out, title, mesh.n_nodes())?;
    for p in &mesh.nodes {
        writeln!(out, "{:e} {:e} 0", p.x, p.y)?;
    }
    let n_el = mesh.elements.len();
    writeln!(out, "CELLS {} {}", n_el, 5 * n_el)?;
    for c in &mesh.elements {
        writeln!(out, "4 {} {} {} {}", c[0], c[1], c[2], c[3])?;
    }
    writeln!(out, "CELL_TYPES {n_el}")?;
    for _ in 0..n_el {
        writeln!(out, "9")?;
    }
    writeln!(out, "POINT_DATA {}", mesh.n_nodes())?;
    writeln!(out, "VECTORS displacement double")?;
    for u in &sol.displacement {
        writeln!(out, "{:e} {:e} 0", u.x, u.y)?;
    }
    writeln!(out, "TENSORS stress double")?;
    for s in &sol.nodal_stress {
        writeln!(out, "{}", tensor_row(s))?;
    }
    writeln!(out, "CELL_DATA {n_el}")?;
    writeln!(out, "TENSORS stress double")?;
    for g in &sol.gauss_stress {
        let mean = g.iter().fold(Sym::ZERO, |a, s| a.add(s)).scale(0.25);
        writeln!(out, "{}", tensor_row(&mean))?;
    }
    Ok(())
}
