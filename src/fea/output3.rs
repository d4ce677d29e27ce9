//! Line probes and legacy-VTK text for the hex8 FEA (the 3D form of [`super::output`]).

use super::hex8;
use super::mesh3::Mesh3;
use super::output::vtk_header;
use super::solve::Averaged;
use super::solve3::Solution3;
use crate::dim::{Sym3, Vector3};
use std::io::{self, Write};

/// One sample of [`probe_line_3d`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProbeSample3 {
    pub position: Vector3,
    /// Element that contains the point (the first found in mesh order on a shared face).
    pub element: Option<usize>,
    /// Stress interpolated trilinearly from the nodal-averaged stresses of the containing
    /// element; `None` outside the mesh.
    pub stress: Option<Sym3>,
}

/// Sample the stress at `n` equally spaced points from `from` to `to` (both included), as
/// [`super::output::probe_line`] does in 2D (bounding box, then the inverse map).
pub fn probe_line_3d(mesh: &Mesh3, sol: &Solution3, from: Vector3, to: Vector3, n: usize) -> Vec<ProbeSample3> {
    let boxes: Vec<(Vector3, Vector3)> = (0..mesh.elements.len())
        .map(|e| {
            let x = mesh.element_coords(e);
            let lo = x.iter().fold(Vector3::repeat(f64::INFINITY), |m, p| m.inf(p));
            let hi = x.iter().fold(Vector3::repeat(f64::NEG_INFINITY), |m, p| m.sup(p));
            (lo, hi)
        })
        .collect();
    (0..n)
        .map(|k| {
            let s = if n > 1 { k as f64 / (n - 1) as f64 } else { 0.0 };
            let p = from + (to - from) * s;
            let mut sample = ProbeSample3 { position: p, element: None, stress: None };
            for (e, (lo, hi)) in boxes.iter().enumerate() {
                let pad = 1e-12 * (hi - lo).norm();
                if (0..3).any(|c| p[c] < lo[c] - pad || p[c] > hi[c] + pad) {
                    continue;
                }
                if let Some(xi) = hex8::map_to_natural(&mesh.element_coords(e), p, 1e-10) {
                    let nf = hex8::shape(xi);
                    let conn = mesh.elements[e];
                    let st = (0..8).fold(Sym3::ZERO, |acc, a| acc.add(&sol.nodal_stress[conn[a]].scale(nf[a])));
                    sample.element = Some(e);
                    sample.stress = Some(st);
                    break;
                }
            }
            sample
        })
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
