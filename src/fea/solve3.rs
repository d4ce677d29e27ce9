//! The hex8 model: materials, assembly into the shared reduced system
//! ([`super::solve::assemble_reduced`]), solve and stress recovery — the 3D form of
//! [`super::solve`] (same elimination of prescribed DOFs, same faer sparse Cholesky,
//! same nodal averaging rule).

use super::hex8::{self, GAUSS};
use super::mesh3::Mesh3;
use super::ordering::nested_dissection;
use super::solve::{assemble_reduced, check_groups, extrapolate_and_average, BoundaryConditions, System};
use super::{FeaError, Result};
use crate::dim::{Sym3, Vector3};
use crate::material::LinearElastic;
use nalgebra::SMatrix;

/// Mesh and materials: everything that defines K. Element `e` uses
/// `materials[group(e)]` (one group per scene body).
#[derive(Clone, Debug)]
pub struct Model3<'m> {
    pub mesh: &'m Mesh3,
    pub materials: Vec<LinearElastic>,
    d: Vec<SMatrix<f64, 6, 6>>,
    element_group: Vec<usize>,
}

impl<'m> Model3<'m> {
    /// One material for every element. Validates the material and every element (det J > 0 at all Gauss points).
    pub fn new(mesh: &'m Mesh3, material: LinearElastic) -> Result<Model3<'m>> {
        Model3::with_groups(mesh, vec![material], Vec::new())
    }

    /// Element `e` gets `materials[element_group[e]]` (`element_group` empty: all in group 0).
    pub fn with_groups(mesh: &'m Mesh3, materials: Vec<LinearElastic>, element_group: Vec<usize>) -> Result<Model3<'m>> {
        let groups: Vec<(LinearElastic, f64)> = materials.iter().map(|m| (*m, 1.0)).collect();
        check_groups(&groups, &element_group, mesh.elements.len())?;
        for e in 0..mesh.elements.len() {
            let x = mesh.element_coords(e);
            for (g, xi) in GAUSS.iter().enumerate() {
                hex8::point_data(&x, *xi).map_err(|det_j| FeaError::BadElement { element: e, gauss: g, det_j })?;
            }
        }
        let d = materials.iter().map(hex8::d_matrix).collect();
        Ok(Model3 { mesh, materials, d, element_group })
    }

    /// Group of element `e`.
    pub fn group(&self, e: usize) -> usize {
        self.element_group.get(e).copied().unwrap_or(0)
    }

    /// Material of element `e`.
    pub fn material(&self, e: usize) -> &LinearElastic {
        &self.materials[self.group(e)]
    }
}

/// Assemble the reduced system K_ff u_f = f_f − K_fp u_p.
pub fn assemble_3d(model: &Model3, bcs: &BoundaryConditions) -> Result<System> {
    let mesh = model.mesh;
    if bcs.dim() != 3 {
        return Err(FeaError::InvalidInput("the boundary conditions of a 3D mesh need 3 DOFs per node".into()));
    }
    let mut system = assemble_reduced(bcs, mesh.n_dofs(), mesh.elements.len(), |e| {
        let ke = hex8::stiffness(&mesh.element_coords(e), &model.d[model.group(e)])
            .map_err(|(gauss, det_j)| FeaError::BadElement { element: e, gauss, det_j })?;
        let conn = mesh.elements[e];
        Ok((std::array::from_fn(|k| 3 * conn[k / 3] + k % 3), ke))
    })?;
    let pos: Vec<[f64; 3]> = mesh.nodes.iter().map(|x| [x.x, x.y, x.z]).collect();
    system.order_by_nodes(&nested_dissection(&pos, &mesh.elements));
    Ok(system)
}

/// The solved state: displacements, Gauss-point and nodal stresses, reactions.
#[derive(Clone, Debug)]
pub struct Solution3 {
    pub displacement: Vec<Vector3>,
    /// Strain (tensor shear) at the 2×2×2 Gauss points of every element, in [`GAUSS`] order.
    pub gauss_strain: Vec<[Sym3; 8]>,
    pub gauss_stress: Vec<[Sym3; 8]>,
    /// Gauss values extrapolated trilinearly to the corners, averaged over the elements at each node.
    pub nodal_stress: Vec<Sym3>,
    /// r = f_int(u) − f_ext per node: the reaction at prescribed DOFs, the (round-off) residual elsewhere.
    pub reaction: Vec<Vector3>,
}

/// Nodal displacements from every DOF's value.
pub fn nodal_vectors(dofs: &[f64]) -> Vec<Vector3> {
    dofs.chunks_exact(3).map(|u| Vector3::new(u[0], u[1], u[2])).collect()
}

/// Assemble, factorise, solve and recover stresses.
pub fn solve_3d(model: &Model3, bcs: &BoundaryConditions) -> Result<Solution3> {
    let system = assemble_3d(model, bcs)?;
    let factor = system.factorize()?;
    let u_free = factor.solve(&system.rhs);
    if u_free.iter().any(|v| !v.is_finite()) {
        return Err(FeaError::NotPositiveDefinite("the solution is not finite".into()));
    }
    Ok(postprocess_3d(model, bcs, nodal_vectors(&system.dof_values(&u_free))))
}

/// Stresses, strains and reactions for given nodal displacements.
pub fn postprocess_3d(model: &Model3, bcs: &BoundaryConditions, displacement: Vec<Vector3>) -> Solution3 {
    let mesh = model.mesh;
    let n_el = mesh.elements.len();
    let mut gauss_strain = Vec::with_capacity(n_el);
    let mut gauss_stress = Vec::with_capacity(n_el);
    let mut f_int = vec![Vector3::zeros(); mesh.n_nodes()];
    for (e, conn) in mesh.elements.iter().enumerate() {
        let x = mesh.element_coords(e);
        let material = model.material(e);
        let u = conn.map(|a| displacement[a]);
        let mut eps_g = [Sym3::ZERO; 8];
        let mut sig_g = [Sym3::ZERO; 8];
        for (g, xi) in GAUSS.iter().enumerate() {
            // The model validated every element, so det J > 0 here.
            let Ok(p) = hex8::point_data(&x, *xi) else { continue };
            eps_g[g] = hex8::strain(&p.grad_n, &u);
            sig_g[g] = hex8::stress(material, &eps_g[g]);
            let fe = hex8::b_matrix(&p.grad_n).transpose() * hex8::voigt_stress(&sig_g[g]) * p.det_j;
            for k in 0..8 {
                f_int[conn[k]] += Vector3::new(fe[3 * k], fe[3 * k + 1], fe[3 * k + 2]);
            }
        }
        gauss_strain.push(eps_g);
        gauss_stress.push(sig_g);
    }
    let f = bcs.forces();
    let reaction = f_int.iter().enumerate().map(|(a, r)| r - Vector3::new(f[3 * a], f[3 * a + 1], f[3 * a + 2])).collect();
    let nodal_stress = nodal_average_3d(mesh, &gauss_stress);
    Solution3 { displacement, gauss_strain, gauss_stress, nodal_stress, reaction }
}

/// Nodal averaging as in 2D ([`super::solve::nodal_average`]): the 2×2×2 Gauss points
/// form a sub-element with natural coordinates √3 ξ, so corner a gets
/// Σ_g N_g(√3 ξ_a) σ_g; exact for fields trilinear in ξ, in particular constant stress.
pub fn nodal_average_3d(mesh: &Mesh3, gauss: &[[Sym3; 8]]) -> Vec<Sym3> {
    let s3 = 3.0f64.sqrt();
    let weights = hex8::CORNERS.map(|c| hex8::shape(c.map(|v| s3 * v)));
    extrapolate_and_average(mesh.n_nodes(), &mesh.elements, gauss, &weights)
}
