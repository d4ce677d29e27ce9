//! Model, boundary conditions, sparse assembly, Cholesky solve and stress recovery.
//!
//! The discrete problem is K u = f (Hughes 2000 §1.14, §3.9). Prescribed DOFs are
//! eliminated: with free (f) and prescribed (p) partitions,
//! K_ff u_f = f_f − K_fp u_p, solved by a sparse Cholesky factorisation of K_ff
//! (only its lower triangle is stored). Reactions are recovered afterwards as
//! r = f_int(u) − f_ext at every DOF.

use super::element::{self, GAUSS};
use super::mesh::Mesh;
use super::{FeaError, Result};
use crate::dim::{Sym, Sym3, Vector};
use crate::material::{LinearElastic, PlaneState};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::{factorize_symbolic_cholesky, LltRef, SymbolicCholesky, SymmetricOrdering};
use faer::sparse::{SparseColMat, Triplet};
use faer::{Conj, Mat, Side};
use nalgebra::{Matrix3, SMatrix, Vector3};

/// Material and thickness of a group of elements, with the D matrix of its plane state.
#[derive(Clone, Debug)]
pub struct ElementProperties {
    pub material: LinearElastic,
    /// Out-of-plane thickness t (multiplies every area integral and every traction).
    pub thickness: f64,
    /// D of the material's plane state (Voigt, engineering shear).
    d: Matrix3<f64>,
}

impl ElementProperties {
    /// Properties of `material` at `thickness` (not validated; [`Model::with_groups`] validates).
    pub fn new(material: LinearElastic, thickness: f64) -> ElementProperties {
        ElementProperties { material, thickness, d: material.d_matrix() }
    }

    /// D of the plane state (Voigt, engineering shear).
    pub fn d_matrix(&self) -> &Matrix3<f64> {
        &self.d
    }

    /// Full stress tensor (with σzz) from the Voigt strain.
    pub fn stress_from_strain(&self, eps: &Vector3<f64>) -> Sym {
        let s = self.d * eps;
        let zz = match self.material.state {
            PlaneState::PlaneStrain => self.material.nu * (s[0] + s[1]),
            PlaneState::PlaneStress => 0.0,
        };
        Sym { xx: s[0], yy: s[1], zz, xy: s[2] }
    }

    /// Full strain tensor (tensor shear, with εzz) from the Voigt strain.
    pub fn strain_tensor(&self, eps: &Vector3<f64>) -> Sym {
        let nu = self.material.nu;
        let zz = match self.material.state {
            PlaneState::PlaneStrain => 0.0,
            PlaneState::PlaneStress => -nu / (1.0 - nu) * (eps[0] + eps[1]),
        };
        Sym { xx: eps[0], yy: eps[1], zz, xy: 0.5 * eps[2] }
    }
}

/// Mesh, materials and thicknesses: everything that defines K.
///
/// Element `e` uses `properties[group(e)]`; [`Model::new`] makes one group for the
/// whole mesh, [`Model::with_groups`] one per body of a scene.
#[derive(Clone, Debug)]
pub struct Model<'m> {
    pub mesh: &'m Mesh,
    pub properties: Vec<ElementProperties>,
    /// Group of every element (empty: all elements in group 0).
    element_group: Vec<usize>,
}

fn check_properties(material: &LinearElastic, thickness: f64, what: &str) -> Result<()> {
    if !(material.e > 0.0 && material.e.is_finite()) {
        return Err(FeaError::InvalidInput(format!(
            "{what}Young's modulus E = {} must be positive and finite",
            material.e
        )));
    }
    let nu_max = match material.state {
        PlaneState::PlaneStrain => 0.5,
        PlaneState::PlaneStress => 1.0,
    };
    if !(material.nu > -1.0 && material.nu < nu_max) {
        return Err(FeaError::InvalidInput(format!(
            "{what}Poisson's ratio ν = {} must lie in (−1, {nu_max}) for {:?}",
            material.nu, material.state
        )));
    }
    if !(thickness > 0.0 && thickness.is_finite()) {
        return Err(FeaError::InvalidInput(format!("{what}thickness {thickness} must be positive and finite")));
    }
    Ok(())
}

/// Checks shared by the Q4 and the hex8 models: every group's material (and thickness),
/// a non-empty mesh, and one valid group index per element (or none: all in group 0).
pub(crate) fn check_groups(groups: &[(LinearElastic, f64)], element_group: &[usize], n_elements: usize) -> Result<()> {
    if groups.is_empty() {
        return Err(FeaError::InvalidInput("no material given".into()));
    }
    let multi = groups.len() > 1;
    for (k, (m, t)) in groups.iter().enumerate() {
        let what = if multi { format!("element group {k}: ") } else { String::new() };
        check_properties(m, *t, &what)?;
    }
    if n_elements == 0 {
        return Err(FeaError::InvalidInput("the mesh has no elements".into()));
    }
    if !element_group.is_empty() && element_group.len() != n_elements {
        return Err(FeaError::InvalidInput(format!(
            "{} element groups given for {} elements",
            element_group.len(),
            n_elements
        )));
    }
    if let Some(e) = element_group.iter().position(|&g| g >= groups.len()) {
        return Err(FeaError::InvalidInput(format!(
            "element {e} is in group {}, but there are {} groups",
            element_group[e],
            groups.len()
        )));
    }
    Ok(())
}

impl<'m> Model<'m> {
    /// One material and thickness for every element. Validates the material, the
    /// thickness and every element (det J > 0 at all Gauss points).
    pub fn new(mesh: &'m Mesh, material: LinearElastic, thickness: f64) -> Result<Model<'m>> {
        Model::with_groups(mesh, vec![(material, thickness)], Vec::new())
    }

    /// Element `e` gets material and thickness `groups[element_group[e]]`
    /// (`element_group` empty: every element in group 0).
    pub fn with_groups(
        mesh: &'m Mesh,
        groups: Vec<(LinearElastic, f64)>,
        element_group: Vec<usize>,
    ) -> Result<Model<'m>> {
        check_groups(&groups, &element_group, mesh.elements.len())?;
        for e in 0..mesh.elements.len() {
            let x = mesh.element_coords(e);
            for (g, [xi, eta]) in GAUSS.iter().enumerate() {
                element::point_data(&x, *xi, *eta).map_err(|det_j| FeaError::BadElement {
                    element: e,
                    gauss: g,
                    det_j,
                })?;
            }
        }
        let properties = groups
            .into_iter()
            .map(|(material, thickness)| ElementProperties::new(material, thickness))
            .collect();
        Ok(Model { mesh, properties, element_group })
    }

    /// Group of element `e`.
    pub fn group(&self, e: usize) -> usize {
        if self.element_group.is_empty() {
            0
        } else {
            self.element_group[e]
        }
    }

    /// Material, thickness and D of element `e`.
    pub fn element(&self, e: usize) -> &ElementProperties {
        &self.properties[self.group(e)]
    }
}

/// Prescribed displacements and external nodal forces, per DOF (`dim` per node: node `a`
/// has DOFs `dim·a + c`, c = 0 (x), 1 (y), 2 (z)). Shared by the Q4 (2D) and hex8 (3D) models.
#[derive(Clone, Debug)]
pub struct BoundaryConditions {
    dim: usize,
    prescribed: Vec<Option<f64>>,
    force: Vec<f64>,
}

impl BoundaryConditions {
    /// No constraints, no loads, for a 2D (Q4) mesh.
    pub fn new(mesh: &Mesh) -> BoundaryConditions {
        BoundaryConditions::for_nodes(mesh.n_nodes(), 2)
    }

    /// No constraints, no loads, for `n_nodes` nodes with `dim` DOFs each.
    pub fn for_nodes(n_nodes: usize, dim: usize) -> BoundaryConditions {
        BoundaryConditions { dim, prescribed: vec![None; dim * n_nodes], force: vec![0.0; dim * n_nodes] }
    }

    /// DOFs per node (2 or 3).
    pub fn dim(&self) -> usize {
        self.dim
    }

    fn check_node(&self, node: usize) -> Result<()> {
        let n_nodes = self.force.len() / self.dim;
        if node < n_nodes {
            Ok(())
        } else {
            Err(FeaError::NodeOutOfRange { node, n_nodes })
        }
    }

    /// Prescribe component `comp` (0 = x, 1 = y, 2 = z in 3D) of the displacement of `node`. A later call overrides.
    pub fn prescribe(&mut self, node: usize, comp: usize, value: f64) -> Result<()> {
        self.check_node(node)?;
        if comp >= self.dim {
            let names = if self.dim == 2 { "0 = x, 1 = y" } else { "0 = x, 1 = y, 2 = z" };
            return Err(FeaError::InvalidInput(format!("displacement component {comp} (use {names})")));
        }
        if !value.is_finite() {
            return Err(FeaError::InvalidInput(format!("prescribed value {value} at node {node} is not finite")));
        }
        self.prescribed[self.dim * node + comp] = Some(value);
        Ok(())
    }

    /// Prescribe both displacement components of `node`.
    pub fn prescribe_node(&mut self, node: usize, u: Vector) -> Result<()> {
        self.prescribe(node, 0, u.x)?;
        self.prescribe(node, 1, u.y)
    }

    /// Add a point force (total force, not per unit thickness) at `node`.
    pub fn point_load(&mut self, node: usize, f: Vector) -> Result<()> {
        self.add_load(node, f.as_slice())
    }

    /// Add a point force with one component per DOF of the node (2 or 3).
    pub fn add_load(&mut self, node: usize, f: &[f64]) -> Result<()> {
        self.check_node(node)?;
        if f.len() != self.dim {
            return Err(FeaError::InvalidInput(format!("a point load at node {node} has {} components, not {}", f.len(), self.dim)));
        }
        if f.iter().any(|v| !v.is_finite()) {
            return Err(FeaError::InvalidInput(format!("point load at node {node} is not finite")));
        }
        for (c, v) in f.iter().enumerate() {
            self.force[self.dim * node + c] += v;
        }
        Ok(())
    }

    /// Add the consistent nodal forces of a traction τ(x) (force per unit area of the
    /// face, i.e. per unit length per unit thickness) on the element edge from node `a`
    /// to node `b`: f_a = t ∫ N_a τ ds, f_b = t ∫ N_b τ ds with the linear edge shape
    /// functions (Cook et al. 2002, consistent loads). Integrated with 3-point
    /// Gauss–Legendre, exact for tractions that are polynomials of degree ≤ 4 along the edge.
    ///
    /// The edge must belong to an element (checked by a scan over the elements); the
    /// thickness is that element's.
    pub fn edge_traction(
        &mut self,
        model: &Model,
        a: usize,
        b: usize,
        traction: impl Fn(Vector) -> Vector,
    ) -> Result<()> {
        let mesh = model.mesh;
        mesh.check_node(a)?;
        mesh.check_node(b)?;
        let owner = mesh
            .elements
            .iter()
            .position(|c| (0..4).any(|k| (c[k] == a && c[(k + 1) % 4] == b) || (c[k] == b && c[(k + 1) % 4] == a)));
        let Some(owner) = owner else {
            return Err(FeaError::NotAnEdge { a, b });
        };
        let thickness = model.element(owner).thickness;
        let (xa, xb) = (mesh.nodes[a], mesh.nodes[b]);
        let len = (xb - xa).norm();
        // 3-point Gauss–Legendre on s ∈ [0, 1].
        let r = 0.5 * (0.6f64).sqrt();
        let pts = [(0.5 - r, 5.0 / 18.0), (0.5, 8.0 / 18.0), (0.5 + r, 5.0 / 18.0)];
        let (mut fa, mut fb) = (Vector::zeros(), Vector::zeros());
        for (s, w) in pts {
            let tau = traction(xa + (xb - xa) * s);
            if !(tau.x.is_finite() && tau.y.is_finite()) {
                return Err(FeaError::InvalidInput(format!("traction on edge {a}–{b} is not finite")));
            }
            fa += tau * ((1.0 - s) * w * len * thickness);
            fb += tau * (s * w * len * thickness);
        }
        self.point_load(a, fa)?;
        self.point_load(b, fb)
    }

    pub fn prescribed(&self) -> &[Option<f64>] {
        &self.prescribed
    }

    pub fn forces(&self) -> &[f64] {
        &self.force
    }
}

/// The assembled, reduced linear system K_ff u_f = f_f − K_fp u_p.
pub struct System {
    /// DOFs per node (2 or 3).
    pub dim: usize,
    /// Equation number of each DOF; `usize::MAX` for a prescribed DOF.
    pub eq: Vec<usize>,
    /// Full DOF vector holding the prescribed values (0 at free DOFs).
    pub u_prescribed: Vec<f64>,
    /// Lower triangle of K_ff.
    pub k: SparseColMat<usize, f64>,
    /// f_f − K_fp u_p.
    pub rhs: Vec<f64>,
    /// Fill-reducing elimination order of the equations (`ordering[k]` is eliminated
    /// k-th), or `None` for faer's approximate minimum degree. 3D meshes set it by nested
    /// dissection ([`super::ordering`], [`System::order_by_nodes`]); 2D keeps AMD.
    pub ordering: Option<Vec<usize>>,
}

/// Assemble the reduced system (see the module doc).
pub fn assemble(model: &Model, bcs: &BoundaryConditions) -> Result<System> {
    let mesh = model.mesh;
    assemble_reduced(bcs, mesh.n_dofs(), mesh.elements.len(), |e| {
        let props = model.element(e);
        let ke = element::stiffness(&mesh.element_coords(e), &props.d, props.thickness)
            .map_err(|(gauss, det_j)| FeaError::BadElement { element: e, gauss, det_j })?;
        let conn = mesh.elements[e];
        Ok((std::array::from_fn(|k| 2 * conn[k / 2] + k % 2), ke))
    })
}

/// The reduced system K_ff u_f = f_f − K_fp u_p for any element with `N` DOFs (Q4: 8,
/// hex8: 24): `element(e)` gives the global DOFs and the stiffness of element `e`.
/// Free DOFs are numbered in DOF order; only the lower triangle of K_ff is kept
/// (duplicate triplets are summed by faer).
pub(crate) fn assemble_reduced<const N: usize>(
    bcs: &BoundaryConditions,
    n_dofs: usize,
    n_elements: usize,
    mut element: impl FnMut(usize) -> Result<([usize; N], SMatrix<f64, N, N>)>,
) -> Result<System> {
    if bcs.prescribed.len() != n_dofs {
        return Err(FeaError::InvalidInput(format!(
            "boundary conditions are for {} DOFs, the mesh has {n_dofs}",
            bcs.prescribed.len()
        )));
    }
    let mut eq = vec![usize::MAX; n_dofs];
    let mut u_prescribed = vec![0.0; n_dofs];
    let mut n_eq = 0;
    for (dof, p) in bcs.prescribed.iter().enumerate() {
        match p {
            Some(v) => u_prescribed[dof] = *v,
            None => {
                eq[dof] = n_eq;
                n_eq += 1;
            }
        }
    }
    if n_eq == 0 {
        return Err(FeaError::NoFreeDofs);
    }
    let mut rhs: Vec<f64> = (0..n_dofs).filter(|&d| eq[d] != usize::MAX).map(|d| bcs.force[d]).collect();
    let mut triplets = Vec::with_capacity(N * (N + 1) / 2 * n_elements);
    for e in 0..n_elements {
        let (dofs, ke) = element(e)?;
        for r in 0..N {
            let row = eq[dofs[r]];
            if row == usize::MAX {
                continue;
            }
            for c in 0..N {
                let col = eq[dofs[c]];
                if col == usize::MAX {
                    rhs[row] -= ke[(r, c)] * u_prescribed[dofs[c]];
                } else if row >= col {
                    triplets.push(Triplet::new(row, col, ke[(r, c)]));
                }
            }
        }
    }
    let k = SparseColMat::<usize, f64>::try_new_from_triplets(n_eq, n_eq, &triplets)
        .map_err(|e| FeaError::Solver(format!("building the sparse matrix: {e:?}")))?;
    Ok(System { dim: bcs.dim, eq, u_prescribed, k, rhs, ordering: None })
}

/// A sparse Cholesky factorisation of K_ff (faer's supernodal or simplicial LLᵀ, with the
/// system's fill-reducing ordering).
pub struct Factorization {
    symbolic: SymbolicCholesky<usize>,
    values: Vec<f64>,
}

impl System {
    pub fn n_equations(&self) -> usize {
        self.rhs.len()
    }

    /// Eliminate the equations node by node in `node_order` (each node's free DOFs in
    /// x, y, z order): the fill-reducing ordering of the factorisation.
    pub fn order_by_nodes(&mut self, node_order: &[usize]) {
        let (dim, eq) = (self.dim, &self.eq);
        let order: Vec<usize> = node_order
            .iter()
            .flat_map(|&a| (0..dim).map(move |c| dim * a + c))
            .map(|dof| eq[dof])
            .filter(|&e| e != usize::MAX)
            .collect();
        debug_assert_eq!(order.len(), self.n_equations());
        self.ordering = Some(order);
    }

    /// Symbolic and numeric Cholesky factorisation of K_ff.
    pub fn factorize(&self) -> Result<Factorization> {
        let n = self.n_equations();
        let inverse: Vec<usize>;
        let ordering = match &self.ordering {
            None => SymmetricOrdering::Amd,
            Some(fwd) => {
                if fwd.len() != n {
                    return Err(FeaError::Solver(format!("the ordering has {} equations, K_ff {n}", fwd.len())));
                }
                let mut inv = vec![usize::MAX; n];
                for (new, &old) in fwd.iter().enumerate() {
                    inv[old] = new;
                }
                if inv.contains(&usize::MAX) {
                    return Err(FeaError::Solver("the ordering is not a permutation of the equations".into()));
                }
                inverse = inv;
                SymmetricOrdering::Custom(PermRef::new_checked(fwd, &inverse, n))
            }
        };
        let symbolic = factorize_symbolic_cholesky(self.k.symbolic(), Side::Lower, ordering, Default::default())
            .map_err(|e| FeaError::Solver(format!("symbolic Cholesky: {e:?}")))?;
        let mut values = Vec::new();
        values
            .try_reserve_exact(symbolic.len_val())
            .map_err(|_| FeaError::Solver(format!("out of memory for the Cholesky factor ({} values)", symbolic.len_val())))?;
        values.resize(symbolic.len_val(), 0.0);
        let par = faer::get_global_parallelism();
        let mut mem = MemBuffer::try_new(symbolic.factorize_numeric_llt_scratch::<f64>(par, Default::default()))
            .map_err(|_| FeaError::Solver("out of memory for the Cholesky workspace".into()))?;
        symbolic
            .factorize_numeric_llt::<f64>(
                &mut values,
                self.k.as_ref(),
                Side::Lower,
                Default::default(),
                par,
                MemStack::new(&mut mem),
                Default::default(),
            )
            .map_err(|n| FeaError::NotPositiveDefinite(format!("{n:?}")))?;
        Ok(Factorization { symbolic, values })
    }

    /// Every DOF's value: the free-DOF solution with the prescribed values filled in.
    pub fn dof_values(&self, u_free: &[f64]) -> Vec<f64> {
        (0..self.eq.len()).map(|d| if self.eq[d] == usize::MAX { self.u_prescribed[d] } else { u_free[self.eq[d]] }).collect()
    }

    /// Expand the free-DOF solution into nodal displacement vectors (2D).
    pub fn full_displacements(&self, u_free: &[f64]) -> Vec<Vector> {
        self.dof_values(u_free).chunks_exact(2).map(|u| Vector::new(u[0], u[1])).collect()
    }

    /// Factorise and solve, with the messages of a scene run: a matrix that is not
    /// positive definite names the supports to check, a non-finite solution is refused.
    /// Returns every DOF's value.
    pub fn factorize_and_solve(&self) -> Result<Vec<f64>> {
        let (conds, dofs) =
            if self.dim == 2 { ("vx = 0 / vy = 0", "x and y") } else { ("vx = 0 / vy = 0 / vz = 0", "x, y and z") };
        let factor = self.factorize().map_err(|e| match e {
            FeaError::NotPositiveDefinite(m) => FeaError::NotPositiveDefinite(format!(
                "{m}; check that the scene's [[boundary]] conditions ({conds}) fix every piece against \
                 translation in {dofs} and rotation"
            )),
            other => other,
        })?;
        let u_free = factor.solve(&self.rhs);
        if u_free.iter().any(|v| !v.is_finite()) {
            return Err(FeaError::NotPositiveDefinite("the solution is not finite".into()));
        }
        Ok(self.dof_values(&u_free))
    }
}

impl Factorization {
    /// Entries of the Cholesky factor L (its memory is 8 bytes each).
    pub fn factor_entries(&self) -> usize {
        self.values.len()
    }

    /// Solve K_ff x = rhs.
    pub fn solve(&self, rhs: &[f64]) -> Vec<f64> {
        let mut b = Mat::<f64>::from_fn(rhs.len(), 1, |i, _| rhs[i]);
        let par = faer::get_global_parallelism();
        let mut mem = MemBuffer::new(self.symbolic.solve_in_place_scratch::<f64>(1, par));
        LltRef::new(&self.symbolic, &self.values).solve_in_place_with_conj(Conj::No, b.as_mut(), par, MemStack::new(&mut mem));
        (0..rhs.len()).map(|i| b[(i, 0)]).collect()
    }
}

/// The solved state: displacements, Gauss-point and nodal stresses, reactions.
#[derive(Clone, Debug)]
pub struct Solution {
    /// Displacement of every node.
    pub displacement: Vec<Vector>,
    /// Strain (tensor shear, with εzz) at the 2×2 Gauss points of every element, in [`GAUSS`] order.
    pub gauss_strain: Vec<[Sym; 4]>,
    /// Stress (with σzz) at the Gauss points of every element.
    pub gauss_stress: Vec<[Sym; 4]>,
    /// Nodal-averaged stress: Gauss values extrapolated to the corners of each element,
    /// then averaged over the elements sharing the node (see [`nodal_average`]).
    pub nodal_stress: Vec<Sym>,
    /// r = f_int(u) − f_ext per node: the reaction at prescribed DOFs, the (round-off) residual elsewhere.
    pub reaction: Vec<Vector>,
}

/// Assemble, factorise, solve and recover stresses.
pub fn solve(model: &Model, bcs: &BoundaryConditions) -> Result<Solution> {
    let system = assemble(model, bcs)?;
    let factor = system.factorize()?;
    let u_free = factor.solve(&system.rhs);
    if u_free.iter().any(|v| !v.is_finite()) {
        return Err(FeaError::NotPositiveDefinite("the solution is not finite".into()));
    }
    Ok(postprocess(model, bcs, system.full_displacements(&u_free)))
}

/// Stresses, strains and reactions for given nodal displacements.
pub fn postprocess(model: &Model, bcs: &BoundaryConditions, displacement: Vec<Vector>) -> Solution {
    let mesh = model.mesh;
    let n_el = mesh.elements.len();
    let mut gauss_strain = Vec::with_capacity(n_el);
    let mut gauss_stress = Vec::with_capacity(n_el);
    let mut f_int = vec![Vector::zeros(); mesh.n_nodes()];
    for (e, conn) in mesh.elements.iter().enumerate() {
        let x = mesh.element_coords(e);
        let props = model.element(e);
        let u = conn.map(|a| displacement[a]);
        let mut eps_g = [Sym::ZERO; 4];
        let mut sig_g = [Sym::ZERO; 4];
        for (g, [xi, eta]) in GAUSS.iter().enumerate() {
            // The model validated every element, so det J > 0 here.
            let Ok(p) = element::point_data(&x, *xi, *eta) else { continue };
            let eps = element::strain(&p.grad_n, &u);
            let sig = props.d * eps;
            eps_g[g] = props.strain_tensor(&eps);
            sig_g[g] = props.stress_from_strain(&eps);
            let b: SMatrix<f64, 3, 8> = element::b_matrix(&p.grad_n);
            let fe = b.transpose() * sig * (p.det_j * props.thickness);
            for k in 0..4 {
                f_int[conn[k]] += Vector::new(fe[2 * k], fe[2 * k + 1]);
            }
        }
        gauss_strain.push(eps_g);
        gauss_stress.push(sig_g);
    }
    let reaction =
        f_int.iter().enumerate().map(|(a, f)| f - Vector::new(bcs.force[2 * a], bcs.force[2 * a + 1])).collect();
    let nodal_stress = nodal_average(mesh, &gauss_stress);
    Solution { displacement, gauss_strain, gauss_stress, nodal_stress, reaction }
}

/// Nodal averaging of Gauss-point values: in each element the 2×2 Gauss values are
/// extrapolated bilinearly to the corners (the Gauss points form a "sub-element" with
/// natural coordinates ξ' = √3 ξ, so corner a gets Σ_g N_g(√3 ξ_a, √3 η_a) σ_g;
/// Cook et al. 2002, stress extrapolation), then each node takes the plain mean over
/// its elements. Exact for any field that is bilinear in (ξ, η) inside an element, in
/// particular for constant stress.
pub fn nodal_average(mesh: &Mesh, gauss: &[[Sym; 4]]) -> Vec<Sym> {
    let s3 = 3.0f64.sqrt();
    let weights = element::CORNERS.map(|[xi, eta]| element::shape(s3 * xi, s3 * eta));
    extrapolate_and_average(mesh.n_nodes(), &mesh.elements, gauss, &weights)
}

/// A tensor that can be averaged (2D [`Sym`], 3D [`Sym3`]).
pub(crate) trait Averaged: Copy {
    const ZERO: Self;
    fn add(&self, b: &Self) -> Self;
    fn scale(&self, s: f64) -> Self;
}

impl Averaged for Sym {
    const ZERO: Sym = Sym::ZERO;
    fn add(&self, b: &Sym) -> Sym {
        Sym::add(self, b)
    }
    fn scale(&self, s: f64) -> Sym {
        Sym::scale(self, s)
    }
}

impl Averaged for Sym3 {
    const ZERO: Sym3 = Sym3::ZERO;
    fn add(&self, b: &Sym3) -> Sym3 {
        Sym3 {
            xx: self.xx + b.xx,
            yy: self.yy + b.yy,
            zz: self.zz + b.zz,
            xy: self.xy + b.xy,
            xz: self.xz + b.xz,
            yz: self.yz + b.yz,
        }
    }
    fn scale(&self, s: f64) -> Sym3 {
        Sym3 { xx: self.xx * s, yy: self.yy * s, zz: self.zz * s, xy: self.xy * s, xz: self.xz * s, yz: self.yz * s }
    }
}

/// Gauss values extrapolated to the corners of each element (corner k gets
/// Σ_g `weights[k][g]` value_g), then the plain mean over the elements at each node
/// (see [`nodal_average`]; the hex8 uses the same rule with its 2×2×2 points).
pub(crate) fn extrapolate_and_average<T: Averaged, const N: usize>(
    n_nodes: usize,
    elements: &[[usize; N]],
    gauss: &[[T; N]],
    weights: &[[f64; N]; N],
) -> Vec<T> {
    let mut sum = vec![T::ZERO; n_nodes];
    let mut count = vec![0u32; n_nodes];
    for (conn, g) in elements.iter().zip(gauss) {
        for (k, &a) in conn.iter().enumerate() {
            let v = (0..N).fold(T::ZERO, |s, q| s.add(&g[q].scale(weights[k][q])));
            sum[a] = sum[a].add(&v);
            count[a] += 1;
        }
    }
    sum.iter().zip(&count).map(|(s, &c)| if c > 0 { s.scale(1.0 / c as f64) } else { T::ZERO }).collect()
}
