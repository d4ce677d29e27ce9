//! Line probes and legacy-VTK text for the hex8 FEA (the 3D form of [`super::output`]).

use super::hex8;
use super::mesh3::Mesh3;
use super::output::{sample_line, vtk_header};
use super::solve::Averaged;
use super::solve3::Solution3;
use crate::dim::{Sym3, Vector3};
use std::io::{self, Write};

/// One sample of [`probe_line_3d`] (fields as in 2D; trilinear interpolation).
pub type ProbeSample3 = super::output::ProbeSample<Vector3, Sym3>;

/// Sample the stress at `n` equally spaced points from `from` to `to` (both included), as
/// [`super::output::probe_line`] does in 2D (bounding box, then the inverse map).
pub fn probe_line_3d(mesh: &Mesh3, sol: &Solution3, from: Vector3, to: Vector3, n: usize) -> Vec<ProbeSample3> {
    let samples = sample_line(mesh.elements.len(), |e| mesh.element_coords(e), from, to, n, |e, x, p| {
        let nf = hex8::shape(hex8::map_to_natural(x, p, 1e-10)?);
        let conn = mesh.elements[e];
        Some((0..8).fold(Sym3::ZERO, |acc, a| acc.add(&sol.nodal_stress[conn[a]].scale(nf[a]))))
    });
    samples
        .into_iter()
        .map(|(position, hit)| ProbeSample3 { position, element: hit.map(|h| h.0), stress: hit.map(|h| h.1) })
        .collect()
}

fn tensor_row(s: &Sym3) -> String {
    format!("{:e} {:e} {:e} {:e} {:e} {:e} {:e} {:e} {:e}", s.xx, s.xy, s.xz, s.xy, s.yy, s.yz, s.xz, s.yz, s.zz)
}

/// Write the mesh and solution as a legacy ASCII VTK file (UNSTRUCTURED_GRID, one
/// VTK_HEXAHEDRON (type 12) per element), with POINT_DATA `displacement` and `stress`
/// (nodal-averaged) and CELL_DATA `stress` (mean of the eight Gauss-point stresses).
pub fn write_vtk_3d<W: Write>(out: &mut W, mesh: &Mesh3, sol: &Solution3, title: &str) -> io::Result<()> {
    if sol.displacement.len() != mesh.n_nodes() || sol.gauss_stress.len() != mesh.elements.len() {
        return Err(io::Error::new(io::ErrorKind::InvalidInput, "the solution does not belong to this mesh"));
    }
    vtk_header(out, title, mesh.n_nodes())?;
    for p in &mesh.nodes {
        writeln!(out, "{:e} {:e} {:e}", p.x, p.y, p.z)?;
    }
    let n_el = mesh.elements.len();
    writeln!(out, "CELLS {} {}", n_el, 9 * n_el)?;
    for c in &mesh.elements {
        writeln!(out, "8 {} {} {} {} {} {} {} {}", c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7])?;
    }
    writeln!(out, "CELL_TYPES {n_el}")?;
    for _ in 0..n_el {
        writeln!(out, "12")?;
    }
    writeln!(out, "POINT_DATA {}", mesh.n_nodes())?;
    writeln!(out, "VECTORS displacement double")?;
    for u in &sol.displacement {
        writeln!(out, "{:e} {:e} {:e}", u.x, u.y, u.z)?;
    }
    writeln!(out, "TENSORS stress double")?;
    for s in &sol.nodal_stress {
        writeln!(out, "{}", tensor_row(s))?;
    }
    writeln!(out, "CELL_DATA {n_el}")?;
    writeln!(out, "TENSORS stress double")?;
    for g in &sol.gauss_stress {
        let mean = g.iter().fold(Sym3::ZERO, |a, s| a.add(s)).scale(0.125);
        writeln!(out, "{}", tensor_row(&mean))?;
    }
    Ok(())
}
