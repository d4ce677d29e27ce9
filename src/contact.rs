//! Crack-face contact at nodes with two velocity fields (Nairn 2003 §2.2, eqs. 8–19).
//!
//! Detection: the relative nodal volume V_rel = V_i / V_undeformed (eqs. 8–10). Below
//! `v_sep` the faces are separated; above `v_contact` they are in contact; in between,
//! they are in contact when approaching, (v_a − v_b)·n̂ > 0 with n̂ the crack normal from
//! above to below (eqs. 11–12).
//!
//! Response, as a momentum change Δp applied to the "above" field and −Δp to the
//! "below" one, so total momentum is conserved (to round-off):
//! * stick (eq. 13): Δp = (m_b p_a... ) — both fields move with the centre of mass;
//! * friction μ (eqs. 14–19): the normal relative velocity is removed, and the
//!   tangential one is reduced by at most μ times the normal impulse (Coulomb), or
//!   removed when that suffices (sticking by friction). μ = 0 is frictionless.
//!   An impulse can only push: frictional contact acts only when the faces approach.

use crate::crack::{ContactDetection, ContactLaw};
#[cfg(test)]
use crate::dim::Vector;
use crate::dim::{GridGeometry, VectorOps};
use crate::check::CheckError;
use crate::simulation::{Dimension, Simulation};

/// What contact needs to know of a crack, in 2D and 3D.
pub trait CrackFaces {
    /// The contact law of its faces.
    fn law(&self) -> ContactLaw;
    /// Relative nodal volume below which the faces are separated (eq. 10).
    fn v_sep(&self) -> f64;
    /// Relative nodal volume above which the faces are in contact.
    fn v_contact(&self) -> f64;
    /// How contact is detected.
    fn detection(&self) -> ContactDetection;
}

/// Which fields of a two-field node are "above" and "below" the crack: field 1 is the
/// particles above the crack relative to the node, field 2 below; field 0 is on the
/// node's own side, so it is below when the other is 1 and above when the other is 2.
/// A node on a crack's line inside a crack-tip zone holds all three (crack::tip_zone::
/// on_line): fields 1 and 2 are the two faces, field 0 the material joined across.
#[inline]
fn above_below(present: u8) -> Option<(usize, usize)> {
    match present {
        0b110 | 0b111 => Some((1, 2)),
        0b011 => Some((1, 0)),
        0b101 => Some((0, 2)),
        _ => None,
    }
}

/// The momentum change of the above field for a contact law, or None if no contact.
/// `dv` = v_a − v_b, `n` the normal from above to below, `mred` = m_a m_b/(m_a + m_b).
pub fn contact_impulse<V: VectorOps>(law: ContactLaw, dv: V, n: V, mred: f64, forced: bool) -> Option<V> {
    let dvn = dv.dot(&n);
    if !(forced || dvn > 0.0) {
        return None;
    }
    match law {
        ContactLaw::None => None,
        // Eq. 13: Δp_a = (m_a p_b − m_b p_a)/(m_a + m_b) = −m_red (v_a − v_b).
        ContactLaw::Stick => Some(-dv * mred),
        ContactLaw::Friction(mu) => {
            if dvn <= 0.0 {
                return None;
            }
            let normal = -n * (mred * dvn);
            let dvt = dv - n * dvn;
            let vt = dvt.norm();
            let tangential = if vt <= mu * dvn {
                -dvt * mred
            } else {
                -dvt * (mu * mred * dvn / vt)
            };
            Some(normal + tangential)
        }
    }
}

impl<S: Dimension> Simulation<S> {
    /// Contact on momenta extrapolated from the particles (Tasks 2 and 6c).
    pub(crate) fn apply_contact_to_momenta(&mut self) -> Result<(), CheckError> {
        self.contact_pass(false)
    }

    /// Contact on the momenta of Task 4, with the total forces back-computed so Task 5
    /// moves the particles consistently.
    pub(crate) fn apply_contact_to_updated_momenta(&mut self) -> Result<(), CheckError> {
        self.contact_pass(true)
    }

    /// One contact pass. Checked mode asserts that each node's total momentum is kept to
    /// round-off: Δp and −Δp are added to its two fields, so (p_a + Δp) + (p_b − Δp)
    /// differs from p_a + p_b by at most a few ulps of |p_a| + |p_b| + 2|Δp| (bound 4ε).
    fn contact_pass(&mut self, back_compute_forces: bool) -> Result<(), CheckError> {
        let dt = self.options.dt;
        let cell = self.grid.cell_measure();
        let mut nodes = std::mem::take(&mut self.nodes);
        for (a_idx, &node) in nodes.active.iter().enumerate() {
            let i = node as usize;
            let Some((a, b)) = above_below(nodes.present[i]) else { continue };
            let c = nodes.crack[i] as usize;
            let crack = &self.cracks[c];
            if crack.law() == ContactLaw::None {
                continue;
            }
            let (ma, mb) = (nodes.fields[a].mass[i], nodes.fields[b].mass[i]);
            let (pa, pb) = (nodes.fields[a].mom[i], nodes.fields[b].mom[i]);
            let dv = pa / ma - pb / mb;
            let mred = ma * mb / (ma + mb);
            let n = nodes.normal[i];
            let (dv, forced) = match crack.detection() {
                ContactDetection::Volume => {
                    let v_rel = nodes.volume[i] / cell * self.mirror_factor(a_idx, i);
                    if v_rel < crack.v_sep() {
                        continue;
                    }
                    (dv, v_rel > crack.v_contact())
                }
                ContactDetection::Opening => {
                    let Some(gap) = S::normal_gap(self, c, i, n) else {
                        continue;
                    };
                    // Apart through the whole step: no contact.
                    if gap - dt * dv.dot(&n) > 0.0 {
                        continue;
                    }
                    // Only the approach beyond what closes the gap is removed.
                    (dv - n * (gap.max(0.0) / dt), gap <= 0.0)
                }
                ContactDetection::Displacement => {
                    // Separating: no contact; nor (as NairnMPM) where one field holds
                    // almost all the node's mass.
                    let ratio = ma / (ma + mb);
                    if dv.dot(&n) <= 0.0 || !(1e-6..=0.999999).contains(&ratio) {
                        continue;
                    }
                    let (ua, ub) = self.field_displacements(a_idx, a, b);
                    let mut open = (ub - ua).dot(&n);
                    if back_compute_forces {
                        open -= dt * dv.dot(&n);
                    }
                    if open >= 0.0 {
                        continue;
                    }
                    (dv, false)
                }
            };
            let Some(dp) = contact_impulse(crack.law(), dv, n, mred, forced) else {
                continue;
            };
            nodes.fields[a].mom[i] = pa + dp;
            nodes.fields[b].mom[i] = pb - dp;
            if self.options.checked {
                let (before, after) = (pa + pb, nodes.fields[a].mom[i] + nodes.fields[b].mom[i]);
                let tol = 4.0 * f64::EPSILON * (pa.norm() + pb.norm() + 2.0 * dp.norm());
                if !((after - before).norm() <= tol) && before.is_finite() && after.is_finite() {
                    use crate::check::components;
                    self.nodes = nodes;
                    return Err(CheckError::ContactMomentum { step: self.step_count, node: i, before: components(&before), after: components(&after), tol });
                }
            }
            if back_compute_forces {
                nodes.fields[a].ftot[i] += dp / dt;
                nodes.fields[b].ftot[i] -= dp / dt;
            }
        }
        self.nodes = nodes;
        Ok(())
    }

    /// The mass-weighted mean particle displacement of fields `a` and `b` at active node
    /// `a_idx` (NairnMPM's displacement detection), each pair counted in its fields as the
    /// mass gather counts it (a share w < 1 of a crack-tip zone: w in its field, 1 − w in
    /// field 0). Exact sums, so the same bits for any particle order.
    fn field_displacements(&self, a_idx: usize, a: usize, b: usize) -> (S::Vector, S::Vector) {
        use crate::exact::{Accumulator, ExactSums};
        let (p, pairs) = (&self.particles, &self.pairs);
        let mut acc: [ExactSums<4>; crate::grid::MAX_FIELDS] = Default::default();
        for &item in pairs.of_active(a_idx) {
            let item = item as usize;
            let f = pairs.field[item] as usize;
            let pp = item / S::MAX_NODES;
            let u = p.x[pp] - p.x0[pp];
            let m = p.mass[pp] * pairs.s[item];
            let mut lanes = [0.0; 4];
            lanes[0] = m;
            for c in 0..S::DIM {
                lanes[c + 1] = m * u[c];
            }
            crate::step::add_shared(&mut acc, f, pairs.frac[item], lanes, S::DIM + 1);
        }
        let mean = |acc: &ExactSums<4>| {
            let l = acc.certified().expect("exact sums");
            debug_assert!(l[0] > 0.0, "a present field has mass");
            S::Vector::from_fn(|c| l[c + 1] / l[0])
        };
        (mean(&acc[a]), mean(&acc[b]))
    }

    /// The factor that makes the nodal volume of eq. 27 at a node on a boundary plane
    /// comparable with the cell volume of eq. 10: 2 for every axis c along which the node
    /// has a prescribed velocity (a wall, a roller, a clamp) and every particle it sees lies
    /// strictly on one side of its plane x_c = const; 1 otherwise.
    ///
    /// Why: V_rel = V_i / V_cell (Nairn 2003 eqs. 8–10) reads "how full of material is the
    /// node's support", and reaches 1 at an interior node of intact material. A node on a
    /// plane the material cannot cross has material on one side only, so its V_rel is at
    /// most 1/2 even with the crack closed and would never reach V_sep (0.9 in the paper):
    /// contact would never act there. A frictionless wall — in particular the roller
    /// (v_c = 0) that makes a 3D slab plane strain — is a symmetry plane, and the mirror
    /// image of the material beyond it adds the same volume again; so V_rel there is twice
    /// the one-sided ratio, and an extrusion in z with rollers on both z faces detects
    /// contact at its face nodes exactly as the interior ones and as the 2D run does
    /// (case `cracks_2d_3d`). Only nodes a crack splits, with contact on, and a
    /// prescribed component reach this test.
    fn mirror_factor(&self, a: usize, i: usize) -> f64 {
        let mask = self.bcs.mask.get(i).copied().unwrap_or(0);
        if mask == 0 {
            return 1.0;
        }
        let xn = self.grid.node_pos(i);
        let p = &self.particles;
        let mut factor = 1.0;
        for c in 0..S::DIM {
            if mask & (1 << c) == 0 {
                continue;
            }
            let (mut below, mut above) = (false, false);
            for &item in self.pairs.of_active(a) {
                let x = p.x[item as usize / S::MAX_NODES][c];
                below |= x <= xn[c];
                above |= x >= xn[c];
            }
            if below != above {
                factor *= 2.0;
            }
        }
        factor
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stick_gives_both_fields_the_centre_of_mass_velocity() {
        let (ma, mb) = (2.0, 3.0);
        let (va, vb) = (Vector::new(1.0, -2.0), Vector::new(-0.5, 1.0));
        let mred = ma * mb / (ma + mb);
        let dp = contact_impulse(ContactLaw::Stick, va - vb, Vector::new(0.0, -1.0), mred, false).unwrap();
        let vcm = (va * ma + vb * mb) / (ma + mb);
        assert!(((va * ma + dp) / ma - vcm).norm() < 1e-15);
        assert!(((vb * mb - dp) / mb - vcm).norm() < 1e-15);
    }

    #[test]
    fn frictionless_removes_only_the_normal_approach() {
        let n = Vector::new(0.0, -1.0);
        let dv = Vector::new(0.3, -1.0); // above moving down onto below, sliding in x
        let dp = contact_impulse(ContactLaw::Friction(0.0), dv, n, 1.0, false).unwrap();
        assert!((dp - Vector::new(0.0, 1.0)).norm() < 1e-15);
        // separating faces get no impulse
        assert!(contact_impulse(ContactLaw::Friction(0.0), -dv, n, 1.0, false).is_none());
    }

    #[test]
    fn coulomb_friction_limits_the_tangential_impulse() {
        let n = Vector::new(0.0, -1.0);
        let dv = Vector::new(2.0, -1.0);
        let dp = contact_impulse(ContactLaw::Friction(0.5), dv, n, 1.0, false).unwrap();
        // normal impulse 1, tangential at most 0.5, opposing the slip
        assert!((dp - Vector::new(-0.5, 1.0)).norm() < 1e-15);
        // enough friction: sticks
        let dp = contact_impulse(ContactLaw::Friction(5.0), dv, n, 1.0, false).unwrap();
        assert!((dp + dv).norm() < 1e-15);
    }
}
