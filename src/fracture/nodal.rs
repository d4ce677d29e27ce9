//! Particle quantities extrapolated to the grid, per velocity field: eq. 11 of Guo &
//! Nairn (2004),
//!
//! f_{i,k} = Σ_p m_p f_p N_{i,p} δ_{k,ν(p,i)} / M^L_{i,k}   (k = 0, 1, 2),
//!
//! the mass-weighted average of f over the particles that field k of node i sees. The
//! J-integral contour (eqs. 12–13) reads stress, strain-energy density, kinetic-energy
//! density and displacement gradient from these values; the MPM-versus-FEA comparison
//! reads nodal stress.
//!
//! The shape functions, fields and lumped masses are those of the last completed step
//! (Task 0 and Task 1, evaluated at the positions at the start of that step); the
//! particle values are the current ones. Sums are exact, so the nodal values do not
//! depend on particle order and are mirror-exact like the step itself.

use crate::dim::{Sym, Tensor, Vector};
use crate::exact::ExactSum;
use crate::material::Constitutive;
use crate::shape::MAX_NODES;
use crate::simulation::Simulation;

/// The extrapolated state of one velocity field of one node.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct NodalState {
    /// Cauchy stress.
    pub stress: Sym,
    /// Displacement gradient ∂u_a/∂x_b (row a, column b).
    pub grad_u: Tensor,
    /// Strain-energy density W (per unit undeformed volume), eq. 9.
    pub strain_energy: f64,
    /// Kinetic-energy density ½ρ|v|² (eq. 9) from this field's nodal velocity and the
    /// extrapolated (initial) density. The paper extrapolates the particles' ½ρv²
    /// instead; the two agree for a smooth velocity field, but particle velocities also
    /// carry components the grid cannot represent (the null space of the particle-to-grid
    /// map, which FLIP-type updates never damp: after a sudden load they persist through
    /// any amount of damping), and those would add spurious kinetic energy to J.
    pub kinetic_energy: f64,
    /// Displacement u = x − x₀.
    pub displacement: Vector,
    /// Nodal velocity of this field (momentum over mass).
    pub velocity: Vector,
    /// The acceleration the J-integral needs: this field's acceleration in the last step
    /// less the loads, body forces and damping
    /// ([`crate::fracture::jintegral::area_acceleration`], "Which acceleration").
    pub acceleration: Vector,
}

/// Number of scalar quantities gathered per field: 4 stress + 4 gradient + W + ρ + 2 displacement.
const NQ: usize = 12;

impl Simulation {
    /// Eq. 11 at one node: the extrapolated state of each field present there
    /// (`None` for absent fields). Fields are 0, 1 (above), 2 (below) as in Task 1.
    pub fn nodal_state(&self, node: usize) -> [Option<NodalState>; 3] {
        let nodes = &self.nodes;
        let pairs = &self.pairs;
        let p = &self.particles;
        let nf = nodes.fields.len();
        let mut out = [None; 3];
        if node >= nodes.present.len() || nodes.present[node] == 0 {
            return out;
        }
        let mut acc: [[ExactSum; NQ]; 3] = Default::default();
        for &item in pairs.of_node(node) {
            let item = item as usize;
            let pp = item / MAX_NODES;
            let f = pairs.field[item] as usize;
            let w = p.mass[pp] * pairs.s[item];
            let s = &p.stress[pp];
            let g = &p.grad_u[pp];
            let mat = &self.materials[p.material[pp] as usize];
            let rho = p.mass[pp] / p.vol0[pp];
            let q: [f64; NQ] = [
                s.xx,
                s.yy,
                s.zz,
                s.xy,
                g[(0, 0)],
                g[(0, 1)],
                g[(1, 0)],
                g[(1, 1)],
                mat.energy_density(&p.strain[pp], s),
                rho,
                p.x[pp].x - p.x0[pp].x,
                p.x[pp].y - p.x0[pp].y,
            ];
            // A pair in a crack-tip zone is shared with field 0 (crack::tip_zone).
            let share = pairs.frac[item];
            if share != 1.0 {
                for (a, v) in acc[0].iter_mut().zip(q) {
                    a.add(w * (1.0 - share) * v);
                }
            }
            let w = if share != 1.0 { w * share } else { w };
            for (a, v) in acc[f].iter_mut().zip(q) {
                a.add(w * v);
            }
        }
        for f in 0..nf {
            if !nodes.has_field(node, f) {
                continue;
            }
            let fa = &nodes.fields[f];
            let m = fa.mass[node];
            let v: [f64; NQ] = std::array::from_fn(|k| acc[f][k].value() / m);
            let velocity = fa.mom[node] / m;
            out[f] = Some(NodalState {
                stress: Sym { xx: v[0], yy: v[1], zz: v[2], xy: v[3] },
                grad_u: Tensor::new(v[4], v[5], v[6], v[7]),
                strain_energy: v[8],
                kinetic_energy: 0.5 * v[9] * velocity.norm_squared(),
                displacement: Vector::new(v[10], v[11]),
                velocity,
                acceleration: crate::fracture::jintegral::area_acceleration(fa, node, self.options.damping),
            });
        }
        out
    }

    /// Eq. 11 on every node in use: `(node, field, state)` in ascending node order.
    pub fn nodal_states(&self) -> Vec<(usize, usize, NodalState)> {
        let mut out = Vec::new();
        for &node in &self.nodes.active {
            for (f, s) in self.nodal_state(node as usize).into_iter().enumerate() {
                if let Some(s) = s {
                    out.push((node as usize, f, s));
                }
            }
        }
        out
    }
}
