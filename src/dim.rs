//! The one place that knows the spatial dimension.
//!
//! cramp is 2D today (Nairn 2003; Guo & Nairn 2004). Everything that depends on the
//! dimension goes through these aliases and the [`Sym`] tensor, so that a 3D build
//! (Guo & Nairn, 001 §2–3) changes this file, the shape functions and the crack
//! geometry, not the algorithm.

/// Number of spatial dimensions.
pub const DIM: usize = 2;

/// A position, velocity, momentum or force.
pub type Vector = nalgebra::Vector2<f64>;

/// A general second-order tensor (velocity gradient, deformation gradient).
pub type Tensor = nalgebra::Matrix2<f64>;

/// A symmetric second-order tensor with the out-of-plane normal component kept,
/// so plane strain (σzz ≠ 0) and plane stress (εzz ≠ 0) are both represented.
/// Shear is the tensor component (εxy, not the engineering γxy).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Sym {
    pub xx: f64,
    pub yy: f64,
    pub zz: f64,
    pub xy: f64,
}

impl Sym {
    pub const ZERO: Sym = Sym { xx: 0.0, yy: 0.0, zz: 0.0, xy: 0.0 };

    /// Symmetric part of an in-plane tensor (zz = 0).
    pub fn sym_part(t: &Tensor) -> Sym {
        Sym { xx: t[(0, 0)], yy: t[(1, 1)], zz: 0.0, xy: 0.5 * (t[(0, 1)] + t[(1, 0)]) }
    }

    /// Double contraction a : b (shear counted twice).
    pub fn ddot(&self, b: &Sym) -> f64 {
        self.xx * b.xx + self.yy * b.yy + self.zz * b.zz + 2.0 * (self.xy * b.xy)
    }

    pub fn add(&self, b: &Sym) -> Sym {
        Sym { xx: self.xx + b.xx, yy: self.yy + b.yy, zz: self.zz + b.zz, xy: self.xy + b.xy }
    }

    pub fn scale(&self, s: f64) -> Sym {
        Sym { xx: self.xx * s, yy: self.yy * s, zz: self.zz * s, xy: self.xy * s }
    }

    /// In-plane traction-like product σ·g for a vector g.
    pub fn dot_vec(&self, g: &Vector) -> Vector {
        Vector::new(self.xx * g.x + self.xy * g.y, self.xy * g.x + self.yy * g.y)
    }

    pub fn is_finite(&self) -> bool {
        self.xx.is_finite() && self.yy.is_finite() && self.zz.is_finite() && self.xy.is_finite()
    }
}
