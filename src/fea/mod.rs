//! # Static Q4 finite elements — the independent second opinion for the MPM solver
//!
//! A plain, textbook, small-strain linear-elastic finite-element solver in 2D
//! (plane stress or plane strain) with 4-noded bilinear quadrilaterals (Q4),
//! 2×2 Gauss quadrature, Dirichlet conditions by elimination and a sparse
//! Cholesky solve (faer). Cracks are *meshed*: nodes along a crack that lies on
//! element edges are duplicated so the two faces separate. The energy release
//! rate J is computed with the equivalent domain integral and K_I, K_II with the
//! interaction integral.
//!
//! Nairn (2003) §3.1 compares CRAMP with "the same grid of rectangular 4-noded
//! elements" used as an FEA mesh; [`mesh::GridMesh`] builds exactly that mesh
//! from the MPM background grid and a cell-occupancy predicate.
//!
//! Read top-down:
//!
//! * [`mesh`] — node/element arrays; the structured mesh taken from a background grid.
//! * [`crack`] — cutting cracks along grid lines (node duplication), crack tips.
//! * [`element`] — Q4 shape functions, Gauss rule, B matrix, element stiffness.
//! * [`solve`] — model, boundary conditions, sparse assembly, Cholesky, stresses.
//! * [`jintegral`] — J (domain integral), K_I and K_II (interaction integral, COD split).
//! * [`output`] — nodal result tables, line probes, legacy VTK text.
//! * [`scene`] — a scene file mapped onto the FEA (mesh, supports, loads, cracks), so one
//!   scene runs both ways; [`run`] — `cramp fea`: solve, J/K per tip, files.
//!
//! In 3D (a [`crate::scene3d::Scene3`]) the same pipeline runs with trilinear hexahedra:
//!
//! * [`hex8`] — element (2×2×2 Gauss, D from the MPM's `update_3d`); [`mesh3`] — the grid
//!   mesh of the 3D material cells; [`solve3`] — model, assembly into the shared reduced
//!   system (`solve::assemble_reduced`) eliminated in nested-dissection order
//!   ([`ordering`]), stresses; [`crack3`] — planar cracks on grid
//!   planes (node duplication) and J, K_I, K_II, K_III per front node (3D EDI);
//!   [`scene3`] — the scene mapping; [`output3`], [`run3`] — `cramp fea` files.
//!
//! Units are whatever the caller uses consistently (the tests use mm, N, MPa).
//!
//! References used throughout:
//! * T. J. R. Hughes, *The Finite Element Method*, Dover 2000, §3.2–3.9 (Q4, B matrix, Gauss).
//! * R. D. Cook, D. S. Malkus, M. E. Plesha, R. J. Witt, *Concepts and Applications of
//!   Finite Element Analysis*, 4th ed., Wiley 2002 (isoparametric Q4, stress extrapolation,
//!   consistent nodal loads, patch test).
//! * C. F. Shih, B. Moran, T. Nakamura, "Energy release rate along a three-dimensional
//!   crack front in a thermally stressed body", Int. J. Fract. 30 (1986) 79–102 (EDI).
//! * T. L. Anderson, *Fracture Mechanics*, 3rd ed., CRC 2005, §2.6 (near-tip fields,
//!   Tables 2.1–2.2), §7.4 (domain integral, interaction integral).
//! * J. A. Nairn, "Material point method calculations with explicit cracks",
//!   CMES 4 (2003) 649–663.

pub mod compare;
pub mod compare3;
pub mod crack;
pub mod crack3;
pub mod element;
pub mod hex8;
pub mod jintegral;
pub mod mesh;
pub mod mesh3;
pub mod ordering;
pub mod output;
pub mod output3;
pub mod penny;
pub mod run;
pub mod run3;
pub mod scene;
pub mod scene3;
pub mod solve;
pub mod solve3;

pub use crack::{CrackTip, MeshedCrack};
pub use jintegral::{j_integral, JResult};
pub use mesh::{Grid, GridMesh, Mesh};
pub use output::{nodal_results, probe_line, write_vtk, NodalResults, ProbeSample};
pub use solve::{assemble, solve, BoundaryConditions, ElementProperties, Factorization, Model, Solution, System};

/// Everything that can go wrong in the FEA. Every variant says what is wrong
/// and where (indices, coordinates), so that a bad scene is fixable from the message.
#[derive(Debug, thiserror::Error)]
pub enum FeaError {
    #[error("invalid grid: {0}")]
    InvalidGrid(String),

    #[error("invalid input: {0}")]
    InvalidInput(String),

    #[error(transparent)]
    Scene(#[from] crate::scene::SceneError),

    #[error("scene field `{field}`: {message}")]
    SceneField { field: String, message: String },

    #[error("element {element} refers to node {node}, but the mesh has {n_nodes} nodes")]
    ElementNodeOutOfRange { element: usize, node: usize, n_nodes: usize },

    #[error("node {node} is out of range: the mesh has {n_nodes} nodes")]
    NodeOutOfRange { node: usize, n_nodes: usize },

    #[error(
        "element {element} is inverted or degenerate: Jacobian determinant {det_j:e} at Gauss point {gauss} \
         (nodes must be counter-clockwise and the quadrilateral convex)"
    )]
    BadElement { element: usize, gauss: usize, det_j: f64 },

    #[error("nodes {a} and {b} are not the two ends of an element edge, so no edge traction can be applied there")]
    NotAnEdge { a: usize, b: usize },

    #[error("crack {crack} has {n_points} point(s); a crack polyline needs at least two")]
    CrackTooShort { crack: usize, n_points: usize },

    #[error(
        "crack {crack}, segment {segment} from ({x0}, {y0}) to ({x1}, {y1}) is not supported: {reason}. \
         The FEA only cuts cracks along grid lines (element edges) with end points on grid nodes"
    )]
    CrackOffGrid { crack: usize, segment: usize, x0: f64, y0: f64, x1: f64, y1: f64, reason: String },

    #[error("J domain of {cells} cell(s) around the crack tip at ({x}, {y}) leaves the body (cell ({i}, {j}) is empty or outside the grid); use a smaller domain")]
    JDomainLeavesBody { cells: usize, x: f64, y: f64, i: isize, j: isize },

    #[error("crack tip at ({x}, {y}): {reason}")]
    BadTip { x: f64, y: f64, reason: String },

    #[error("there are no free degrees of freedom: every DOF is prescribed")]
    NoFreeDofs,

    #[error(
        "the stiffness matrix is not positive definite ({0}); most likely the Dirichlet conditions do not \
         remove all rigid-body motions (of every disconnected piece), or a material parameter is invalid"
    )]
    NotPositiveDefinite(String),

    #[error("sparse solver failure: {0}")]
    Solver(String),
}

/// Result type of the FEA module.
pub type Result<T> = std::result::Result<T, FeaError>;
