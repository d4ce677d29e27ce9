//! Patch test (Irons; MacNeal & Harder, "A proposed standard set of problems to test
//! finite element accuracy", Finite Elem. Anal. Des. 1 (1985) 3–20, test 1 geometry).
//!
//! A 0.24 × 0.12 rectangle meshed with five distorted Q4 elements around an interior
//! quadrilateral. The linear field u = 1e-3 (x + y/2), v = 1e-3 (y + x/2) is prescribed
//! at the four boundary nodes; the interior nodes are free. A conforming Q4 mesh must
//! reproduce the linear field at the interior nodes and the constant strain
//! εxx = εyy = γxy = 1e-3 (hence constant stress D ε) everywhere.
//!
//! Tolerance 1e-10 relative: the only error is round-off of an 8-unknown solve with a
//! condition number ~1e2 and element integrals summed over a few terms, so ~1e-14 is
//! expected; 1e-10 catches any genuine inconsistency (a wrong B, Jacobian or quadrature
//! gives errors of order 1e-3 relative or more).
//!
//! The patch solves themselves are the verification case `fea_patch`
//! (`cramp::verify::cases::fea`, run by `tests/golden.rs` and `cramp verify`); this file
//! keeps the bad-input checks.

use cramp::dim::Vector;
use cramp::fea::{self, BoundaryConditions, Mesh, Model};
use cramp::material::{LinearElastic, PlaneState};
use cramp::verify::cases::fea::patch_mesh as patch;

/// Bad input gives errors, not panics.
#[test]
fn bad_input_is_reported() {
    // Clockwise element.
    let mesh = Mesh::new(
        vec![Vector::new(0.0, 0.0), Vector::new(0.0, 1.0), Vector::new(1.0, 1.0), Vector::new(1.0, 0.0)],
        vec![[0, 1, 2, 3]],
    )
    .unwrap();
    let mat = LinearElastic { e: 1.0, nu: 0.3, rho: 1.0, state: PlaneState::PlaneStress };
    let err = Model::new(&mesh, mat, 1.0).unwrap_err();
    assert!(matches!(err, fea::FeaError::BadElement { element: 0, .. }), "{err}");
    // Node out of range.
    assert!(Mesh::new(vec![Vector::zeros(); 3], vec![[0, 1, 2, 3]]).is_err());
    // Unconstrained body: Cholesky must fail cleanly.
    let mesh = patch();
    let model = Model::new(&mesh, mat, 1.0).unwrap();
    let mut bcs = BoundaryConditions::new(&mesh);
    bcs.point_load(2, Vector::new(1.0, 0.0)).unwrap();
    match fea::solve(&model, &bcs) {
        Err(e) => println!("unconstrained: {e}"),
        Ok(_) => panic!("an unconstrained patch must not solve"),
    }
    assert!(bcs.point_load(99, Vector::zeros()).is_err());
    assert!(matches!(bcs.edge_traction(&model, 0, 2, |_| Vector::zeros()), Err(fea::FeaError::NotAnEdge { .. })));
}
