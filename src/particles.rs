//! Material points, stored as a struct of arrays for the hot loops (Nairn 2003,
//! appendix Task 0: position, velocity, stress, strain, mass, density, thickness).

use crate::dim::{Sym, Tensor, Vector};

/// All material points of a scene. Index `p` addresses the same particle in every array.
#[derive(Clone, Debug, Default)]
pub struct Particles {
    /// Stable identifier, unchanged when particles are reordered (outputs are sorted by it).
    pub id: Vec<u32>,
    /// Current position x_p.
    pub x: Vec<Vector>,
    /// Initial position, for displacements.
    pub x0: Vec<Vector>,
    /// Velocity v_p.
    pub v: Vec<Vector>,
    /// Mass m_p (density × area × thickness).
    pub mass: Vec<f64>,
    /// Undeformed volume m_p/ρ_p (area × thickness).
    pub vol0: Vec<f64>,
    /// Half-widths of the undeformed particle domain (uGIMP).
    pub lp: Vec<Vector>,
    /// Cauchy stress (small strain: the specific stress of the paper times ρ_p).
    pub stress: Vec<Sym>,
    /// Small strain, accumulated from the increments of eq. 35.
    pub strain: Vec<Sym>,
    /// Displacement gradient ∂u_a/∂x_b, accumulated from the velocity gradient (eq. 36).
    /// Its off-diagonal terms are the ∂u₁/∂y and ∂u₂/∂x that the J-integral needs separately.
    pub grad_u: Vec<Tensor>,
    /// Index into the scene's materials.
    pub material: Vec<u16>,
    /// Index into the scene's bodies.
    pub body: Vec<u16>,
    /// Applied point force f_p at the current time (set from the scene's loads each step).
    pub force: Vec<Vector>,
    /// Index of the load that acts on this particle, or [`NO_LOAD`].
    pub load: Vec<u16>,
}

/// Marker for a particle without an applied load.
pub const NO_LOAD: u16 = u16::MAX;

impl Particles {
    pub fn len(&self) -> usize {
        self.x.len()
    }

    pub fn is_empty(&self) -> bool {
        self.x.is_empty()
    }

    /// Append one particle at rest with zero stress.
    #[allow(clippy::too_many_arguments)]
    pub fn push(&mut self, x: Vector, v: Vector, mass: f64, vol0: f64, lp: Vector, material: u16, body: u16) {
        self.id.push(self.x.len() as u32);
        self.x.push(x);
        self.x0.push(x);
        self.v.push(v);
        self.mass.push(mass);
        self.vol0.push(vol0);
        self.lp.push(lp);
        self.stress.push(Sym::ZERO);
        self.strain.push(Sym::ZERO);
        self.grad_u.push(Tensor::zeros());
        self.material.push(material);
        self.body.push(body);
        self.force.push(Vector::zeros());
        self.load.push(NO_LOAD);
    }

    /// Current volume by eq. 25 of Nairn 2003: V = (1+εxx)(1+εyy) m/(ρ t) (times t here,
    /// since vol0 already includes the thickness). Used for the contact volumes (eq. 27).
    #[inline]
    pub fn volume(&self, p: usize) -> f64 {
        (1.0 + self.strain[p].xx) * (1.0 + self.strain[p].yy) * self.vol0[p]
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
