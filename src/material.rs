//! Constitutive laws. Only isotropic linear elasticity today, behind the
//! [`Constitutive`] trait so other laws can follow without touching the time step.

use crate::dim::{Sym, Sym3};
use serde::{Deserialize, Serialize};

/// The 2D idealisation of the third direction.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PlaneState {
    /// σzz = 0, εzz free.
    PlaneStress,
    /// εzz = 0, σzz = ν(σxx + σyy).
    PlaneStrain,
}

/// A small-strain constitutive update: given the strain increment, update stress and strain.
pub trait Constitutive {
    /// Mass density in the undeformed state.
    fn density(&self) -> f64;
    /// Dilatational wave speed, used for the CFL time step.
    fn wave_speed(&self) -> f64;
    /// Add the in-plane strain increment `de` (zz ignored on input) to `strain` and update `stress`.
    fn update(&self, de: &Sym, strain: &mut Sym, stress: &mut Sym);
    /// Strain energy density ½ σ:ε for the current state (per unit undeformed volume).
    fn energy_density(&self, strain: &Sym, stress: &Sym) -> f64 {
        0.5 * stress.ddot(strain)
    }
}

/// Isotropic linear elastic solid (E, ν, ρ) in plane stress or plane strain.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct LinearElastic {
    /// Young's modulus.
    pub e: f64,
    /// Poisson's ratio.
    pub nu: f64,
    /// Density.
    pub rho: f64,
    pub state: PlaneState,
}

impl LinearElastic {
    /// Shear modulus μ = E / (2(1+ν)).
    pub fn shear_modulus(&self) -> f64 {
        self.e / (2.0 * (1.0 + self.nu))
    }

    /// In-plane Lamé λ: plane strain Eν/((1+ν)(1−2ν)); plane stress (λ*) Eν/(1−ν²).
    pub fn lambda(&self) -> f64 {
        match self.state {
            PlaneState::PlaneStrain => self.e * self.nu / ((1.0 + self.nu) * (1.0 - 2.0 * self.nu)),
            PlaneState::PlaneStress => self.e * self.nu / (1.0 - self.nu * self.nu),
        }
    }

    /// Kolosov constant κ: 3−4ν (plane strain), (3−ν)/(1+ν) (plane stress).
    pub fn kappa(&self) -> f64 {
        match self.state {
            PlaneState::PlaneStrain => 3.0 - 4.0 * self.nu,
            PlaneState::PlaneStress => (3.0 - self.nu) / (1.0 + self.nu),
        }
    }

    /// Effective modulus E' for J = K²/E': E/(1−ν²) (plane strain), E (plane stress).
    pub fn e_prime(&self) -> f64 {
        match self.state {
            PlaneState::PlaneStrain => self.e / (1.0 - self.nu * self.nu),
            PlaneState::PlaneStress => self.e,
        }
    }

    /// Shear wave speed c_s = sqrt(μ/ρ).
    pub fn shear_wave_speed(&self) -> f64 {
        (self.shear_modulus() / self.rho).sqrt()
    }

    /// Lamé λ of the 3D solid, Eν/((1+ν)(1−2ν)) (the plane-strain λ).
    pub fn lambda_3d(&self) -> f64 {
        self.e * self.nu / ((1.0 + self.nu) * (1.0 - 2.0 * self.nu))
    }

    /// A material of a 3D scene: there is no plane state, and λ, the dilatational wave
    /// speed c_d = √((λ+2μ)/ρ) and E' are those of the 3D solid, which are the
    /// plane-strain ones; so it is stored as plane strain.
    pub fn solid(e: f64, nu: f64, rho: f64) -> Self {
        LinearElastic { e, nu, rho, state: PlaneState::PlaneStrain }
    }

    /// Hooke's law in increments in 3D: dσ = λ tr(dε) I + 2μ dε (tensor shear). Like the
    /// 2D update, each component is a fixed expression of the same operands, so a
    /// mirrored increment gives a mirrored stress to the bit, and an increment with no z
    /// components gives the plane-strain update's operations on the in-plane components.
    pub fn update_3d(&self, de: &Sym3, strain: &mut Sym3, stress: &mut Sym3) {
        let l = self.lambda_3d();
        let m = self.shear_modulus();
        let tr = de.xx + de.yy + de.zz;
        strain.xx += de.xx;
        strain.yy += de.yy;
        strain.zz += de.zz;
        strain.xy += de.xy;
        strain.xz += de.xz;
        strain.yz += de.yz;
        stress.xx += l * tr + 2.0 * m * de.xx;
        stress.yy += l * tr + 2.0 * m * de.yy;
        stress.zz += l * tr + 2.0 * m * de.zz;
        stress.xy += 2.0 * m * de.xy;
        stress.xz += 2.0 * m * de.xz;
        stress.yz += 2.0 * m * de.yz;
    }

    /// In-plane constitutive matrix in Voigt form [xx, yy, γxy] (engineering shear).
    pub fn d_matrix(&self) -> nalgebra::Matrix3<f64> {
        let l = self.lambda();
        let m = self.shear_modulus();
        nalgebra::Matrix3::new(l + 2.0 * m, l, 0.0, l, l + 2.0 * m, 0.0, 0.0, 0.0, m)
    }
}

impl Constitutive for LinearElastic {
    fn density(&self) -> f64 {
        self.rho
    }

    /// c_d = sqrt((λ + 2μ)/ρ) with the in-plane λ of the plane state (references §7).
    fn wave_speed(&self) -> f64 {
        ((self.lambda() + 2.0 * self.shear_modulus()) / self.rho).sqrt()
    }

    /// Hooke's law in increments. Written so that a mirrored strain increment
    /// (εxy → −εxy) gives a mirrored stress to the bit: every component is a fixed
    /// expression of the same operands, no fused or reordered sums.
    fn update(&self, de: &Sym, strain: &mut Sym, stress: &mut Sym) {
        let l = self.lambda();
        let m = self.shear_modulus();
        let tr = de.xx + de.yy;
        let dsxx = l * tr + 2.0 * m * de.xx;
        let dsyy = l * tr + 2.0 * m * de.yy;
        let dsxy = 2.0 * m * de.xy;
        let (dszz, dezz) = match self.state {
            PlaneState::PlaneStrain => (self.nu * (dsxx + dsyy), 0.0),
            // σzz = 0: εzz = −ν/(1−ν) (εxx + εyy)
            PlaneState::PlaneStress => (0.0, -self.nu / (1.0 - self.nu) * tr),
        };
        strain.xx += de.xx;
        strain.yy += de.yy;
        strain.xy += de.xy;
        strain.zz += dezz;
        stress.xx += dsxx;
        stress.yy += dsyy;
        stress.xy += dsxy;
        stress.zz += dszz;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plane_strain_uniaxial_strain_matches_hooke() {
        let m = LinearElastic { e: 200.0, nu: 0.3, rho: 1.0, state: PlaneState::PlaneStrain };
        let (mut e, mut s) = (Sym::ZERO, Sym::ZERO);
        m.update(&Sym { xx: 1e-3, ..Sym::ZERO }, &mut e, &mut s);
        let c11 = 200.0 * 0.7 / (1.3 * 0.4);
        assert!((s.xx - c11 * 1e-3).abs() < 1e-12);
        assert!((s.zz - 0.3 * (s.xx + s.yy)).abs() < 1e-12);
    }

    #[test]
    fn three_d_uniaxial_stress_has_poisson_contraction_only() {
        let m = LinearElastic::solid(200.0, 0.3, 1.0);
        let (mut e, mut s) = (Sym3::ZERO, Sym3::ZERO);
        // εxx = σ/E, εyy = εzz = −νσ/E with σ = 0.2: σyy = σzz = 0, σxx = 0.2.
        m.update_3d(&Sym3 { xx: 1e-3, yy: -0.3e-3, zz: -0.3e-3, ..Sym3::ZERO }, &mut e, &mut s);
        assert!((s.xx - 0.2).abs() < 1e-14 && s.yy.abs() < 1e-15 && s.zz.abs() < 1e-15);
        m.update_3d(&Sym3 { yz: 1e-3, ..Sym3::ZERO }, &mut e, &mut s);
        assert!((s.yz - 2e-3 * m.shear_modulus()).abs() < 1e-15);
    }

    #[test]
    fn plane_stress_uniaxial_stress_has_no_lateral_stress() {
        let m = LinearElastic { e: 100.0, nu: 0.25, rho: 1.0, state: PlaneState::PlaneStress };
        let (mut e, mut s) = (Sym::ZERO, Sym::ZERO);
        // uniaxial stress state: εyy = −ν εxx
        m.update(&Sym { xx: 1e-3, yy: -0.25e-3, ..Sym::ZERO }, &mut e, &mut s);
        assert!((s.xx - 0.1).abs() < 1e-12 && s.yy.abs() < 1e-14 && s.zz == 0.0);
    }
}
