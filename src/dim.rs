//! The spatial dimension: [`Space`], with [`D2`] and [`D3`].
//!
//! cramp is one solver for 2D and 3D scenes (001 §2.1: "in 3D CRAMP a crack is
//! discretized into a set of triangular elements instead of line segments, but otherwise
//! the 3D algorithm is essentially the same as the 2D one"). The time step, the grid's
//! nodal arrays, the particles and the checks are written once, generic over a marker
//! type `S: Space`; everything that differs between 2D and 3D is an associated type or
//! function of [`Space`]: the vector, tensor and symmetric-tensor types, the grid's
//! geometry, the shape-function stencil (9 or 27 uGIMP nodes), the particle volume of
//! eq. 25 and Hooke's law. Generic code is monomorphised per dimension, so the hot loops
//! contain no dimension branches and no trait objects.
//!
//! Why a marker type with associated types (like dimforge's parry/rapier `Real`/`Point`
//! aliases, or cb-geo/mpm's `Tdim` template parameter) rather than a `const D: usize`:
//! the per-dimension pieces that are not just "an array of length D" (the symmetric
//! tensor with its out-of-plane component in 2D, the grid, the summation lanes whose
//! count is D + 1 or D², the crack geometry) need a type to hang on, and stable Rust
//! cannot compute array lengths from a const parameter.
//!
//! The 2D aliases [`Vector`], [`Tensor`] and [`Sym`] are what the 2D-only modules (crack
//! line crossing, contact, J contour, growth, the Q4 FEA) use; they are `D2`'s types.

use crate::exact::Lanes;
use crate::grid::{Grid, Grid3};
use crate::material::LinearElastic;
use crate::shape::ShapeKind;
use std::fmt::Debug;
use std::ops::{Add, AddAssign, Div, Index, IndexMut, Mul, MulAssign, Neg, Sub, SubAssign};

/// Number of spatial dimensions of the 2D-only modules.
pub const DIM: usize = 2;

/// A 2D position, velocity, momentum or force.
pub type Vector = nalgebra::Vector2<f64>;

/// A general 2D second-order tensor (velocity gradient, displacement gradient).
pub type Tensor = nalgebra::Matrix2<f64>;

/// A 3D vector.
pub type Vector3 = nalgebra::Vector3<f64>;

/// A general 3D second-order tensor.
pub type Tensor3 = nalgebra::Matrix3<f64>;

/// The operations the generic solver needs of a vector (nalgebra's `Vector2`/`Vector3`).
pub trait VectorOps:
    Copy
    + Debug
    + PartialEq
    + Send
    + Sync
    + 'static
    + Add<Output = Self>
    + Sub<Output = Self>
    + Neg<Output = Self>
    + Mul<f64, Output = Self>
    + Div<f64, Output = Self>
    + AddAssign
    + SubAssign
    + MulAssign<f64>
    + Index<usize, Output = f64>
    + IndexMut<usize>
{
    /// Number of components.
    const DIM: usize;
    fn zeros() -> Self;
    fn dot(&self, b: &Self) -> f64;
    fn norm_squared(&self) -> f64;
    fn norm(&self) -> f64;
    /// Σ |components| (the scales of the momentum checks).
    fn abs_sum(&self) -> f64;
    fn is_finite(&self) -> bool;
    fn from_fn(f: impl FnMut(usize) -> f64) -> Self;
}

impl<const N: usize> VectorOps for nalgebra::SVector<f64, N> {
    const DIM: usize = N;
    #[inline(always)]
    fn zeros() -> Self {
        nalgebra::SVector::<f64, N>::zeros()
    }
    #[inline(always)]
    fn dot(&self, b: &Self) -> f64 {
        nalgebra::Matrix::dot(self, b)
    }
    #[inline(always)]
    fn norm_squared(&self) -> f64 {
        nalgebra::Matrix::norm_squared(self)
    }
    #[inline(always)]
    fn norm(&self) -> f64 {
        nalgebra::Matrix::norm(self)
    }
    #[inline(always)]
    fn abs_sum(&self) -> f64 {
        self.abs().sum()
    }
    #[inline(always)]
    fn is_finite(&self) -> bool {
        self.iter().all(|c| c.is_finite())
    }
    #[inline(always)]
    fn from_fn(mut f: impl FnMut(usize) -> f64) -> Self {
        nalgebra::SVector::<f64, N>::from_fn(|i, _| f(i))
    }
}

/// The operations the generic solver needs of a general tensor (velocity gradient).
pub trait TensorOps: Copy + Debug + PartialEq + Send + Sync + 'static + Mul<f64, Output = Self> + AddAssign {
    fn zeros() -> Self;
    /// Tensor from its components in row-major order, (a, b) = f(a, b).
    fn from_fn(f: impl FnMut(usize, usize) -> f64) -> Self;
    fn get(&self, a: usize, b: usize) -> f64;
}

impl<const N: usize> TensorOps for nalgebra::SMatrix<f64, N, N> {
    #[inline(always)]
    fn zeros() -> Self {
        nalgebra::SMatrix::<f64, N, N>::zeros()
    }
    #[inline(always)]
    fn from_fn(f: impl FnMut(usize, usize) -> f64) -> Self {
        nalgebra::SMatrix::<f64, N, N>::from_fn(f)
    }
    #[inline(always)]
    fn get(&self, a: usize, b: usize) -> f64 {
        self[(a, b)]
    }
}

/// A symmetric second-order tensor (stress, strain) of dimension `S`.
pub trait SymOps<V, T>: Copy + Debug + Default + PartialEq + Send + Sync + 'static {
    const ZERO: Self;
    /// Symmetric part of a tensor.
    fn sym_part(t: &T) -> Self;
    /// Double contraction a : b (shear counted twice).
    fn ddot(&self, b: &Self) -> f64;
    /// The traction-like product σ·g.
    fn dot_vec(&self, g: &V) -> V;
    fn is_finite(&self) -> bool;
    /// Every stored component, in a fixed order (fingerprints, outputs).
    fn components(&self) -> Vec<f64>;
}

/// A 2D symmetric second-order tensor with the out-of-plane normal component kept,
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

impl SymOps<Vector, Tensor> for Sym {
    const ZERO: Sym = Sym::ZERO;
    #[inline(always)]
    fn sym_part(t: &Tensor) -> Self {
        Sym::sym_part(t)
    }
    #[inline(always)]
    fn ddot(&self, b: &Self) -> f64 {
        Sym::ddot(self, b)
    }
    #[inline(always)]
    fn dot_vec(&self, g: &Vector) -> Vector {
        Sym::dot_vec(self, g)
    }
    fn is_finite(&self) -> bool {
        Sym::is_finite(self)
    }
    fn components(&self) -> Vec<f64> {
        vec![self.xx, self.yy, self.zz, self.xy]
    }
}

/// A 3D symmetric second-order tensor (tensor shear components, not engineering).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Sym3 {
    pub xx: f64,
    pub yy: f64,
    pub zz: f64,
    pub xy: f64,
    pub xz: f64,
    pub yz: f64,
}

impl Sym3 {
    pub const ZERO: Sym3 = Sym3 { xx: 0.0, yy: 0.0, zz: 0.0, xy: 0.0, xz: 0.0, yz: 0.0 };

    /// The full 3×3 matrix.
    pub fn to_tensor(&self) -> Tensor3 {
        Tensor3::new(self.xx, self.xy, self.xz, self.xy, self.yy, self.yz, self.xz, self.yz, self.zz)
    }
}

impl SymOps<Vector3, Tensor3> for Sym3 {
    const ZERO: Sym3 = Sym3::ZERO;
    #[inline(always)]
    fn sym_part(t: &Tensor3) -> Self {
        Sym3 {
            xx: t[(0, 0)],
            yy: t[(1, 1)],
            zz: t[(2, 2)],
            xy: 0.5 * (t[(0, 1)] + t[(1, 0)]),
            xz: 0.5 * (t[(0, 2)] + t[(2, 0)]),
            yz: 0.5 * (t[(1, 2)] + t[(2, 1)]),
        }
    }
    #[inline(always)]
    fn ddot(&self, b: &Self) -> f64 {
        self.xx * b.xx + self.yy * b.yy + self.zz * b.zz + 2.0 * (self.xy * b.xy + self.xz * b.xz + self.yz * b.yz)
    }
    #[inline(always)]
    fn dot_vec(&self, g: &Vector3) -> Vector3 {
        Vector3::new(
            self.xx * g.x + self.xy * g.y + self.xz * g.z,
            self.xy * g.x + self.yy * g.y + self.yz * g.z,
            self.xz * g.x + self.yz * g.y + self.zz * g.z,
        )
    }
    fn is_finite(&self) -> bool {
        self.components().iter().all(|c| c.is_finite())
    }
    fn components(&self) -> Vec<f64> {
        vec![self.xx, self.yy, self.zz, self.xy, self.xz, self.yz]
    }
}

/// The geometry of a regular background grid, as the generic solver sees it.
pub trait GridGeometry<V>: Clone + Debug + PartialEq + Send + Sync + 'static {
    fn num_nodes(&self) -> usize;
    /// Position of node i.
    fn node_pos(&self, i: usize) -> V;
    /// The node's integer coordinates (i, j) or (i, j, k), for messages.
    fn node_coords(&self, i: usize) -> Vec<usize>;
    fn origin(&self) -> V;
    /// The corner opposite the origin.
    fn max_corner(&self) -> V;
    /// Smallest cell dimension, for the CFL time step and the checks' scales.
    fn min_h(&self) -> f64;
    /// Cell area (2D) or volume (3D).
    fn cell_measure(&self) -> f64;
}

/// A spatial dimension: everything the generic solver needs to know about it.
pub trait Space: Copy + Clone + Debug + Default + PartialEq + Send + Sync + 'static {
    /// Number of spatial dimensions.
    const DIM: usize;
    /// Most nodes a particle can touch: 3 per direction for uGIMP (9 in 2D, 27 in 3D).
    const MAX_NODES: usize;
    /// Name in messages and outputs ("2D", "3D").
    const NAME: &'static str;
    type Vector: VectorOps;
    type Tensor: TensorOps;
    type Sym: SymOps<Self::Vector, Self::Tensor>;
    type Grid: GridGeometry<Self::Vector>;
    /// Summation lanes of one pair's contribution to a node's mass and momentum (1 + DIM).
    type MassLanes: Lanes;
    /// Lanes of a vector (DIM).
    type VecLanes: Lanes;
    /// Lanes of a general tensor: component (a, b) in lane a·[`Space::TENSOR_ROW`] + b.
    type TensorLanes: Lanes;
    /// Lanes per tensor row: DIM, or more when padding makes each row one whole vector
    /// register (3D: rows of 4, so every term is a broadcast times a 4-wide vector, with
    /// no shuffles; the pad lanes are never read).
    const TENSOR_ROW: usize;
    /// One term's tensor lanes before its components are written: 0, and 1.0 in the pad
    /// lanes (a sum of ones certifies at once, so the pads never send a gather to the
    /// slow certificate or the exact sum).
    const TENSOR_TERM: Self::TensorLanes;
    /// Lanes of a particle's velocity and acceleration increments (2·DIM).
    type IncLanes: Lanes;

    /// Shape-function weights and gradients of a particle (eq. 24) into the first entries
    /// of `node`, `s`, `g` (each of length [`Space::MAX_NODES`]); returns how many.
    fn weights_into(grid: &Self::Grid, kind: ShapeKind, x: &Self::Vector, lp: &Self::Vector, node: &mut [u32], s: &mut [f64], g: &mut [Self::Vector]) -> usize;

    /// Current particle volume from its strain (eq. 25 of Nairn 2003 with one factor per
    /// direction): V = Π(1 + ε_aa) V₀.
    fn volume(strain: &Self::Sym, vol0: f64) -> f64;

    /// Hooke's law in increments: add the strain increment to `strain`, update `stress`.
    fn hooke(m: &LinearElastic, de: &Self::Sym, strain: &mut Self::Sym, stress: &mut Self::Sym);
}

/// Two dimensions (Nairn 2003; Guo & Nairn 2004): plane stress or plane strain.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct D2;

/// Three dimensions (Guo & Nairn 001 §2–3).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct D3;

impl Space for D2 {
    const DIM: usize = 2;
    const MAX_NODES: usize = 9;
    const NAME: &'static str = "2D";
    type Vector = Vector;
    type Tensor = Tensor;
    type Sym = Sym;
    type Grid = Grid;
    type MassLanes = [f64; 3];
    type VecLanes = [f64; 2];
    type TensorLanes = [f64; 4];
    const TENSOR_ROW: usize = 2;
    const TENSOR_TERM: [f64; 4] = [0.0; 4];
    type IncLanes = [f64; 4];

    #[inline(always)]
    fn weights_into(grid: &Grid, kind: ShapeKind, x: &Vector, lp: &Vector, node: &mut [u32], s: &mut [f64], g: &mut [Vector]) -> usize {
        crate::shape::weights_into(grid, kind, x, lp, node.try_into().unwrap(), s.try_into().unwrap(), g.try_into().unwrap())
    }

    #[inline(always)]
    fn volume(strain: &Sym, vol0: f64) -> f64 {
        (1.0 + strain.xx) * (1.0 + strain.yy) * vol0
    }

    #[inline(always)]
    fn hooke(m: &LinearElastic, de: &Sym, strain: &mut Sym, stress: &mut Sym) {
        use crate::material::Constitutive;
        m.update(de, strain, stress)
    }
}

impl Space for D3 {
    const DIM: usize = 3;
    const MAX_NODES: usize = 27;
    const NAME: &'static str = "3D";
    type Vector = Vector3;
    type Tensor = Tensor3;
    type Sym = Sym3;
    type Grid = Grid3;
    type MassLanes = [f64; 4];
    type VecLanes = [f64; 3];
    type TensorLanes = [f64; 12];
    const TENSOR_ROW: usize = 4;
    const TENSOR_TERM: [f64; 12] = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0];
    type IncLanes = [f64; 6];

    #[inline(always)]
    fn weights_into(grid: &Grid3, kind: ShapeKind, x: &Vector3, lp: &Vector3, node: &mut [u32], s: &mut [f64], g: &mut [Vector3]) -> usize {
        crate::shape::weights_into_3d(grid, kind, x, lp, node.try_into().unwrap(), s.try_into().unwrap(), g.try_into().unwrap())
    }

    #[inline(always)]
    fn volume(strain: &Sym3, vol0: f64) -> f64 {
        (1.0 + strain.xx) * (1.0 + strain.yy) * (1.0 + strain.zz) * vol0
    }

    #[inline(always)]
    fn hooke(m: &LinearElastic, de: &Sym3, strain: &mut Sym3, stress: &mut Sym3) {
        m.update_3d(de, strain, stress)
    }
}
