//! Material points, stored as a struct of arrays for the hot loops (Nairn 2003,
//! appendix Task 0: position, velocity, stress, strain, mass, density, thickness).

use crate::dim::{Space, SymOps, TensorOps, VectorOps, D2};

/// All material points of a scene. Index `p` addresses the same particle in every array.
/// Generic over the dimension `S` (2D by default).
#[derive(Clone, Debug, Default)]
pub struct Particles<S: Space = D2> {
    /// Stable identifier, unchanged when particles are reordered (outputs are sorted by it).
    pub id: Vec<u32>,
    /// Current position x_p.
    pub x: Vec<S::Vector>,
    /// Initial position, for displacements.
    pub x0: Vec<S::Vector>,
    /// Velocity v_p.
    pub v: Vec<S::Vector>,
    /// Mass m_p (density × area × thickness).
    pub mass: Vec<f64>,
    /// Undeformed volume m_p/ρ_p (area × thickness).
    pub vol0: Vec<f64>,
    /// Half-widths of the undeformed particle domain (uGIMP).
    pub lp: Vec<S::Vector>,
    /// Cauchy stress (small strain: the specific stress of the paper times ρ_p).
    pub stress: Vec<S::Sym>,
    /// Small strain, accumulated from the increments of eq. 35.
    pub strain: Vec<S::Sym>,
    /// Displacement gradient ∂u_a/∂x_b, accumulated from the velocity gradient (eq. 36).
    /// Its off-diagonal terms are the ∂u₁/∂y and ∂u₂/∂x that the J-integral needs separately.
    pub grad_u: Vec<S::Tensor>,
    /// Index into the scene's materials.
    pub material: Vec<u16>,
    /// Index into the scene's bodies.
    pub body: Vec<u16>,
    /// Applied point force f_p at the current time (set from the scene's loads each step).
    pub force: Vec<S::Vector>,
    /// Index of the load that acts on this particle, or [`NO_LOAD`].
    pub load: Vec<u16>,
}

/// Marker for a particle without an applied load.
pub const NO_LOAD: u16 = u16::MAX;

impl<S: Space> Particles<S> {
    pub fn len(&self) -> usize {
        self.x.len()
    }

    pub fn is_empty(&self) -> bool {
        self.x.is_empty()
    }

    /// Append one particle at rest with zero stress.
    #[allow(clippy::too_many_arguments)]
    pub fn push(&mut self, x: S::Vector, v: S::Vector, mass: f64, vol0: f64, lp: S::Vector, material: u16, body: u16) {
        self.id.push(self.x.len() as u32);
        self.x.push(x);
        self.x0.push(x);
        self.v.push(v);
        self.mass.push(mass);
        self.vol0.push(vol0);
        self.lp.push(lp);
        self.stress.push(S::Sym::ZERO);
        self.strain.push(S::Sym::ZERO);
        self.grad_u.push(S::Tensor::zeros());
        self.material.push(material);
        self.body.push(body);
        self.force.push(S::Vector::zeros());
        self.load.push(NO_LOAD);
    }

    /// Current volume by eq. 25 of Nairn 2003: V = (1+εxx)(1+εyy) m/(ρ t) in 2D (times t
    /// here, since vol0 already includes the thickness), (1+εxx)(1+εyy)(1+εzz) m/ρ in 3D.
    /// Used for the contact volumes (eq. 27).
    #[inline]
    pub fn volume(&self, p: usize) -> f64 {
        S::volume(&self.strain[p], self.vol0[p])
    }

    /// Reorder all arrays by `perm` (new index k takes old particle perm[k]). Used by the
    /// shuffle test that proves results do not depend on particle order.
    pub fn permute(&mut self, perm: &[usize]) {
        fn apply<T: Clone>(v: &mut [T], perm: &[usize]) {
            let old = v.to_vec();
            for (k, &p) in perm.iter().enumerate() {
                v[k] = old[p].clone();
            }
        }
        apply(&mut self.id, perm);
        apply(&mut self.x, perm);
        apply(&mut self.x0, perm);
        apply(&mut self.v, perm);
        apply(&mut self.mass, perm);
        apply(&mut self.vol0, perm);
        apply(&mut self.lp, perm);
        apply(&mut self.stress, perm);
        apply(&mut self.strain, perm);
        apply(&mut self.grad_u, perm);
        apply(&mut self.material, perm);
        apply(&mut self.body, perm);
        apply(&mut self.force, perm);
        apply(&mut self.load, perm);
    }
}
