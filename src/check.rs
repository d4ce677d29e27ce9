//! The checked mode: invariants asserted every step. A violation stops the run with an
//! error that names the step, the particle or node, and the values involved.
//!
//! Some checks are always on because continuing would be meaningless or unsafe (a
//! particle outside the grid, a non-finite value in a step that would propagate); the
//! rest run when `checked` is set (the default in tests and verification runs).

use crate::dim::VectorOps;
use thiserror::Error;

/// Tolerance on the shape-function partition of unity |ΣS − 1| (a few ulps of summing ≤ 9
/// products of numbers ≤ 1).
pub const PARTITION_TOL: f64 = 1e-13;

/// Relative tolerance on total mass (grid vs particles): partition-of-unity round-off.
pub const MASS_TOL: f64 = 1e-12;

/// Relative tolerance on momentum conservation (Σ f_int = 0 up to partition-of-unity round-off).
pub const MOMENTUM_TOL: f64 = 1e-10;

#[derive(Debug, Error, Clone, PartialEq)]
pub enum CheckError {
    #[error("step {step}: particle {particle} (id {id}) at {} is outside the grid {} (uGIMP needs its domain half-width inside too)", fmt_point(x, 6), fmt_box(lo, hi))]
    OutsideGrid { step: u64, particle: usize, id: u32, x: Vec<f64>, lo: Vec<f64>, hi: Vec<f64> },
    #[error("step {step}: partition of unity fails at particle {particle} (id {id}): ΣS = {sum_s:.17e}, ΣG = {}", fmt_point(g, 3))]
    PartitionOfUnity { step: u64, particle: usize, id: u32, sum_s: f64, g: Vec<f64> },
    #[error("step {step}: node {node} field {field} is in use with non-positive mass {mass:e}")]
    NodalMass { step: u64, node: usize, field: usize, mass: f64 },
    #[error("step {step}: total mass on the grid {grid:.17e} differs from the particles' {particles:.17e}")]
    TotalMass { step: u64, grid: f64, particles: f64 },
    #[error("step {step}: momentum not conserved in {stage}: before {}, after {}, tolerance {tol:.3e}", fmt_point(before, 9), fmt_point(after, 9))]
    Momentum { step: u64, stage: &'static str, before: Vec<f64>, after: Vec<f64>, tol: f64 },
    #[error("step {step}: non-finite {what} at particle {particle} (id {id}): {value}")]
    NonFiniteParticle { step: u64, particle: usize, id: u32, what: &'static str, value: String },
    #[error("step {step}: non-finite {what} at node {node} field {field}: {value}")]
    NonFiniteNode { step: u64, node: usize, field: usize, what: &'static str, value: String },
    #[error("step {step}: particle {particle} (id {id}) crossed crack {crack}: it was on side {before} and is now on side {after}")]
    CrackCrossing { step: u64, particle: usize, id: u32, crack: usize, before: i8, after: i8 },
    #[error("step {step}: grid node (i, j) = ({i}, {j}) at ({x}, {y}) needs more than two velocity fields (cracks {cracks:?}); CRAMP allows at most two")]
    TooManyFields { step: u64, i: usize, j: usize, x: f64, y: f64, cracks: Vec<usize> },
    #[error("step {step}: grid node (i, j, k) = ({}, {}, {}) at {} needs more than two velocity fields (cracks {cracks:?}); CRAMP allows at most two", ijk[0], ijk[1], ijk[2], fmt_point(x, 6))]
    TooManyFields3 { step: u64, ijk: [usize; 3], x: Vec<f64>, cracks: Vec<usize> },
    #[error("step {step}: particle {particle} (id {id}) sees no grid node that a crack does not hide (node visibility); it lies on a crack")]
    NoVisibleNode { step: u64, particle: usize, id: u32 },
    #[error("step {step}: contact at node {node} changed its total momentum from {} to {} (tolerance {tol:.3e})", fmt_point(before, 17), fmt_point(after, 17))]
    ContactMomentum { step: u64, node: usize, before: Vec<f64>, after: Vec<f64>, tol: f64 },
    #[error("step {step}: crack growth: {error}")]
    Growth { step: u64, error: crate::fracture::growth::GrowthError },
    #[error("step {step}: energy grew without bound (total {total:.6e} vs initial scale {scale:.6e}): the time step is probably above the stability limit; reduce `solver.cfl` or `solver.dt`")]
    Unstable { step: u64, total: f64, scale: f64 },
}

/// Format a vector for error messages: `(1e0, 2.5e-1)`.
pub fn fmt_vec<V: VectorOps>(v: &V) -> String {
    let parts: Vec<String> = (0..V::DIM).map(|c| format!("{:e}", v[c])).collect();
    format!("({})", parts.join(", "))
}

/// The components of a vector, for the errors that carry them.
pub fn components<V: VectorOps>(v: &V) -> Vec<f64> {
    (0..V::DIM).map(|c| v[c]).collect()
}

/// `(x, y[, z])` in scientific notation with `digits` after the point.
pub fn fmt_point(x: &[f64], digits: usize) -> String {
    let parts: Vec<String> = x.iter().map(|c| format!("{c:.digits$e}")).collect();
    format!("({})", parts.join(", "))
}

/// `[x0, x1] × [y0, y1][ × [z0, z1]]`.
pub fn fmt_box(lo: &[f64], hi: &[f64]) -> String {
    lo.iter().zip(hi).map(|(a, b)| format!("[{a}, {b}]")).collect::<Vec<_>>().join(" × ")
}
