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

use cramp::dim::Vector;
use cramp::fea::{self, BoundaryConditions, Mesh, Model};
use cramp::material::{LinearElastic, PlaneState};

fn patch() -> Mesh {
    let nodes = vec![
        Vector::new(0.0, 0.0),
        Vector::new(0.24, 0.0),
        Vector::new(0.24, 0.12),
        Vector::new(0.0, 0.12),
        Vector::new(0.04, 0.02),
        Vector::new(0.18, 0.03),
        Vector::new(0.16, 0.08),
        Vector::new(0.08, 0.08),
    ];
    let elements = vec![[4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [7, 6, 2, 3], [0, 4, 7, 3]];
    Mesh::new(nodes, elements).unwrap()
}

fn exact_u(x: Vector) -> Vector {
    1e-3 * Vector::new(x.x + 0.5 * x.y, x.y + 0.5 * x.x)
}

fn run(state: PlaneState) {
    let mesh = patch();
    let mat = LinearElastic { e: 1.0e6, nu: 0.25, rho: 1.0, state };
    let model = Model::new(&mesh, mat, 0.001).unwrap();
    let mut bcs = BoundaryConditions::new(&mesh);
    for a in 0..4 {
        bcs.prescribe_node(a, exact_u(mesh.nodes[a])).unwrap();
    }
    let sol = fea::solve(&model, &bcs).unwrap();

    let tol = 1e-10;
    for a in 0..mesh.n_nodes() {
        let err = (sol.displacement[a] - exact_u(mesh.nodes[a])).norm();
        assert!(err <= tol * 1e-3 * 0.24, "{state:?} node {a}: displacement error {err:e}");
    }
    // Exact stress: D [1e-3, 1e-3, 1e-3].
    let s = mat.d_matrix() * nalgebra::Vector3::new(1e-3, 1e-3, 1e-3);
    let zz = if state == PlaneState::PlaneStrain { mat.nu * (s[0] + s[1]) } else { 0.0 };
    let scale = s.norm();
    let check = |what: &str, t: &cramp::dim::Sym| {
        let err = [t.xx - s[0], t.yy - s[1], t.xy - s[2], t.zz - zz].iter().map(|v| v.abs()).fold(0.0, f64::max);
        assert!(err <= tol * scale, "{state:?} {what}: stress error {err:e} (scale {scale:e})");
    };
    let mut worst: f64 = 0.0;
    for (e, g) in sol.gauss_stress.iter().enumerate() {
        for (k, t) in g.iter().enumerate() {
            check(&format!("element {e} Gauss point {k}"), t);
            worst = worst.max((t.xx - s[0]).abs().max((t.yy - s[1]).abs()).max((t.xy - s[2]).abs()) / scale);
        }
    }
    for (a, t) in sol.nodal_stress.iter().enumerate() {
        check(&format!("node {a} (averaged)"), t);
    }
    // Interior nodes are free and unloaded: their residual must vanish; the boundary
    // reactions must be in equilibrium.
    for a in 4..8 {
        assert!(sol.reaction[a].norm() <= tol * scale * 0.001 * 0.24, "residual at node {a}");
    }
    let total: Vector = sol.reaction.iter().sum();
    assert!(total.norm() <= tol * scale * 0.001 * 0.24);
    println!("{state:?}: worst relative Gauss-stress error {worst:e}");
}

#[test]
fn patch_test_plane_stress() {
    run(PlaneState::PlaneStress);
}

#[test]
fn patch_test_plane_strain() {
    run(PlaneState::PlaneStrain);
}

/// Force-driven variant: the same patch, minimal supports, and the consistent nodal
/// forces of the constant traction σ·n on the boundary edges. Checks the edge-traction
/// integration against the same exact constant-stress state.
#[test]
fn patch_test_traction_driven() {
    let mesh = patch();
    let mat = LinearElastic { e: 1.0e6, nu: 0.25, rho: 1.0, state: PlaneState::PlaneStress };
    let model = Model::new(&mesh, mat, 0.001).unwrap();
    let s = mat.d_matrix() * nalgebra::Vector3::new(1e-3, 1e-3, 1e-3);
    let sig = nalgebra::Matrix2::new(s[0], s[2], s[2], s[1]);
    let mut bcs = BoundaryConditions::new(&mesh);
    // Boundary edges counter-clockwise, outward normal = (dy, −dx)/len.
    for (a, b) in [(0, 1), (1, 2), (2, 3), (3, 0)] {
        let d = mesh.nodes[b] - mesh.nodes[a];
        let normal = Vector::new(d.y, -d.x) / d.norm();
        bcs.edge_traction(&model, a, b, |_| sig * normal).unwrap();
    }
    // Remove rigid motion by pinning node 0 to the exact field and node 1's v.
    bcs.prescribe_node(0, exact_u(mesh.nodes[0])).unwrap();
    bcs.prescribe(1, 1, exact_u(mesh.nodes[1]).y).unwrap();
    let sol = fea::solve(&model, &bcs).unwrap();
    for (a, x) in mesh.nodes.iter().enumerate() {
        let err = (sol.displacement[a] - exact_u(*x)).norm();
        assert!(err <= 1e-10 * 1e-3 * 0.24, "node {a}: {err:e}");
    }
}

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
