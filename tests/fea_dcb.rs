//! Double cantilever beam (DCB) of Guo & Nairn (2004) §4.1, solved statically.
//!
//! 100 × 24 × 1 mm, crack on the mid-plane y = 12 from the loaded end x = 0 to a = 50 mm,
//! E = 2300 MPa, ν = 0.33, plane stress. Right end x = 100 clamped (u = v = 0 at every
//! node). P = 1 N per arm at x = 0: +y on the top-left corner node (0, 24), −y on the
//! bottom-left corner node (0, 0); the load line is x = 0, so the crack length measured
//! from it is a = 50 mm. Units mm, N, MPa (K in MPa√mm).
//!
//! Reference: corrected beam theory for a DCB with arms of thickness h (Williams 1989;
//! Anderson 2005 §2.7 for the uncorrected form), per unit thickness,
//!
//! K_I = 2√3 P (a + χ h) / h^{3/2},  h = 12 mm, χ = 0.6688 (ν = 0.33),
//!
//! K_I,ref = 4.8355 MPa√mm. The root-rotation correction χ is itself an approximation
//! (values 0.64–0.67 in the literature move K by < 0.7 %), and the clamp at x = 100 is
//! 50 mm = 2.1 H from the tip, where beam theory assumes an infinite uncracked ligament.
//! Hence the 2 % tolerance on K_I at 1 mm elements. By symmetry of the geometry and the
//! loads about y = 12 the exact K_II is 0; |K_II| ≤ 1 % of K_I is asserted.
//!
//! Domain independence: two domains of about 4 and 8 mm half-width must give J (and K_I
//! from the interaction integral) within 0.5 % of each other at 1 mm and 0.5 mm elements
//! (the EDI is exactly path independent for the exact field; the difference is
//! discretisation error, measured ≤ 0.15 %).

use cramp::dim::Vector;
use cramp::fea::{self, BoundaryConditions, Grid, GridMesh, JResult, Model};
use cramp::material::{LinearElastic, PlaneState};

const E: f64 = 2300.0;
const NU: f64 = 0.33;

fn k_ref() -> f64 {
    let (p, a, h, chi) = (1.0, 50.0, 12.0, 0.6688);
    2.0 * 3f64.sqrt() * p * (a + chi * h) / h.powf(1.5)
}

/// Solve the DCB with element size `h` (optionally rotated by +90° about the origin,
/// to exercise a crack that is not along +x) and return J/K for the given domains (in mm).
fn dcb(h: f64, rotated: bool, domains_mm: &[f64]) -> Vec<JResult> {
    let (nx, ny) = ((100.0 / h).round() as usize, (24.0 / h).round() as usize);
    let mat = LinearElastic { e: E, nu: NU, rho: 1.0e-9, state: PlaneState::PlaneStress };
    // Rotation by +90°: (x, y) → (−y, x). The rotated body occupies [−24, 0] × [0, 100].
    let rot = |p: Vector| if rotated { Vector::new(-p.y, p.x) } else { p };
    let grid = if rotated {
        Grid::new(Vector::new(-24.0, 0.0), Vector::new(h, h), ny, nx).unwrap()
    } else {
        Grid::new(Vector::new(0.0, 0.0), Vector::new(h, h), nx, ny).unwrap()
    };
    let mut gm = GridMesh::from_grid(grid, |_, _, _| true).unwrap();
    let cracks = gm.cut_cracks(&[vec![rot(Vector::new(0.0, 12.0)), rot(Vector::new(50.0, 12.0))]]).unwrap();
    assert!(cracks[0].tips[0].is_none(), "the mouth at the loaded end is not a tip");
    let tip = cracks[0].tips[1].expect("the crack tip at x = 50");
    assert!((tip.position - rot(Vector::new(50.0, 12.0))).norm() < 1e-12);

    let model = Model::new(&gm.mesh, mat, 1.0).unwrap();
    let mut bcs = BoundaryConditions::new(&gm.mesh);
    let node_at = |p: Vector| {
        let (i, j) = gm.grid.snap_to_node(rot(p), 1e-9).unwrap();
        let n = gm.nodes_at(i, j);
        assert_eq!(n.len(), 1);
        n[0]
    };
    bcs.point_load(node_at(Vector::new(0.0, 24.0)), rot(Vector::new(0.0, 1.0))).unwrap();
    bcs.point_load(node_at(Vector::new(0.0, 0.0)), rot(Vector::new(0.0, -1.0))).unwrap();
    for a in 0..gm.mesh.n_nodes() {
        let p = gm.mesh.nodes[a];
        let x_orig = if rotated { p.y } else { p.x };
        if (x_orig - 100.0).abs() < 1e-9 {
            bcs.prescribe_node(a, Vector::zeros()).unwrap();
        }
    }
    let sol = fea::solve(&model, &bcs).unwrap();
    // Equilibrium of the whole specimen: the clamp reactions balance the (self-equilibrated) loads.
    let total: Vector = sol.reaction.iter().sum();
    assert!(total.norm() < 1e-9, "net reaction {total:?}");
    domains_mm.iter().map(|&d| fea::j_integral(&gm, &model, &sol, &tip, (d / h).round() as usize).unwrap()).collect()
}

fn report(h: f64, r: &JResult) {
    let kr = k_ref();
    println!(
        "h = {h:>4} mm, domain {:>2} cells: J = {:.6e} N/mm, K_I(int) = {:.5} ({:+.3} %), K_II(int) = {:+.2e}, \
         sqrt(E'J) = {:.5} ({:+.3} %), K_I(COD) = {:.5}, K_II(COD) = {:+.2e}, J vs (K_I²+K_II²)/E' {:+.2e}",
        r.cells,
        r.j,
        r.k1,
        100.0 * (r.k1 - kr) / kr,
        r.k2,
        r.k_from_j,
        100.0 * (r.k_from_j - kr) / kr,
        r.k1_cod,
        r.k2_cod,
        (r.j - (r.k1 * r.k1 + r.k2 * r.k2) / E) / r.j
    );
}

#[test]
fn dcb_stress_intensity_matches_corrected_beam_theory() {
    let kr = k_ref();
    println!("K_I reference (corrected beam theory, χ = 0.6688): {kr:.5} MPa√mm");
    let mut k_int = Vec::new();
    for h in [2.0, 1.0, 0.5] {
        let rs = dcb(h, false, &[4.0, 8.0]);
        for r in &rs {
            report(h, r);
        }
        k_int.push(rs[1].k1);
        if h > 1.0 {
            continue;
        }
        for r in &rs {
            // K from the EDI (J), 2 % against corrected beam theory (see the module doc).
            assert!(((r.k_from_j - kr) / kr).abs() < 0.02, "sqrt(E'J) {} vs {kr}", r.k_from_j);
            assert!(((r.k1_cod - kr) / kr).abs() < 0.02, "K_I(J, COD split) {} vs {kr}", r.k1_cod);
            assert!(r.k2.abs() <= 0.01 * r.k1, "K_II(int) {}", r.k2);
            assert!(r.k2_cod.abs() <= 0.01 * r.k1_cod, "K_II(COD) {}", r.k2_cod);
        }
        // Domain independence of J and of the interaction integral (measured ≤ 0.15 %).
        assert!(((rs[0].j - rs[1].j) / rs[1].j).abs() < 5e-3, "domains: J {} vs {}", rs[0].j, rs[1].j);
        assert!(((rs[0].k1 - rs[1].k1) / rs[1].k1).abs() < 5e-3, "domains: K_I {} vs {}", rs[0].k1, rs[1].k1);
    }
    // The interaction integral carries a larger first-order discretisation error in this
    // load-controlled, bending-dominated specimen (−3.8 % at 1 mm, −1.9 % at 0.5 mm): with
    // uniform Q4 and no singular elements, extracted K converges as O(h) (energy-like
    // quantity, r^½ singularity; Babuška & Miller 1984, Strang & Fix 1973 ch. 8), and the
    // constant of J happens to be much smaller here. Checked as a convergence statement
    // instead of a fixed tolerance: observed order from h = 2, 1, 0.5 mm in [0.8, 1.2],
    // and the Richardson limit 2 K(0.5) − K(1) within the same 2 % of beam theory.
    let order = ((k_int[1] - k_int[0]) / (k_int[2] - k_int[1])).log2();
    let k_rich = 2.0 * k_int[2] - k_int[1];
    println!(
        "interaction-integral K_I: observed order {order:.3}, Richardson limit {k_rich:.5} ({:+.3} % vs beam theory)",
        100.0 * (k_rich - kr) / kr
    );
    assert!((0.8..=1.2).contains(&order), "observed order {order}");
    assert!(((k_rich - kr) / kr).abs() < 0.02);
}

/// The same DCB rotated by +90° (crack along +y) must give the same J and K to round-off:
/// the mesh is the rotated image of the original, so any difference would be an error
/// in the crack-tip frame of the J / interaction integrals. Tolerance 1e-9 relative
/// (the solves differ only in round-off; ~1e-12 expected).
#[test]
fn dcb_rotated_by_90_degrees_gives_the_same_k() {
    let a = dcb(2.0, false, &[4.0, 8.0]);
    let b = dcb(2.0, true, &[4.0, 8.0]);
    for (r, s) in a.iter().zip(&b) {
        println!("unrotated J {:.12e} K_I {:.12}, rotated J {:.12e} K_I {:.12}", r.j, r.k1, s.j, s.k1);
        assert!(((r.j - s.j) / r.j).abs() < 1e-9);
        assert!(((r.k1 - s.k1) / r.k1).abs() < 1e-9);
        assert!((r.k2 - s.k2).abs() < 1e-9 * r.k1);
        assert!(((r.cod - s.cod).norm()) < 1e-9 * r.cod.norm());
    }
}

/// The same specimen from the verification scene `verification/dcb_static.toml`, mapped
/// onto the FEA exactly as `cramp fea` maps it (`cramp::fea::scene`): the mesh is the
/// scene grid's material cells (1 mm), the clamp is the scene's `[[boundary]]` on x ≤ 0,
/// the loads are the MPM particle loads lumped with the Q4 shape functions, and the crack
/// `[[102, 12], [49.5, 12]]` is meshed to the first node beyond its end, x = 49.
///
/// Reference: corrected beam theory as in the module doc, K_I = 2√3 P (a + χh)/h^{3/2} with
/// χ = 0.6688 (Williams 1989 for ν = 0.33, references §1(a)), h = 12 mm, and P and a taken
/// from the model itself: P = the resultant of the nodal loads on the upper arm (1 N) and
/// a = (load line) − (meshed tip), the load line being the x of that resultant, i.e. the
/// moment arm of the load about the tip section that beam theory uses (99 − 49 = 50 mm by
/// construction of the scene, asserted). Tolerance 2 % on √(E′J) from the equivalent
/// domain integral and on the COD-split K_I (χ uncertainty < 0.7 %, finite ligament and
/// 1 mm elements; see the module doc), domains of 4 and 8 cells; |K_II| ≤ 1 % of K_I by
/// symmetry. The loads are distributed over the last 2 mm of each arm instead of a corner
/// point, which changes nothing in beam theory beyond the moment arm.
#[test]
fn dcb_static_scene_file_matches_corrected_beam_theory() {
    use cramp::fea::scene::SceneFea;
    use cramp::scene::Scene;
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("verification/dcb_static.toml");
    let scene = Scene::from_file(&path).unwrap();
    let fea = SceneFea::from_scene(&scene).unwrap();
    let an = fea.analyse().unwrap();
    for n in &fea.notes {
        println!("note: {n}");
    }
    assert!(fea.auto_supports.is_empty(), "the scene's clamp must support the specimen");
    let [tip] = an.tips.as_slice() else { panic!("expected one crack tip, got {}", an.tips.len()) };
    assert!((tip.tip.position - Vector::new(49.0, 12.0)).norm() < 1e-12, "meshed tip {:?}", tip.tip.position);
    assert_eq!(tip.tip.direction, Vector::new(-1.0, 0.0));

    // Load P and load line of the upper arm from the nodal loads on the nodes of its
    // elements (crack-face copies included).
    let gm = &fea.grid_mesh;
    let mesh = &gm.mesh;
    let f = fea.bcs.forces();
    let mut upper = vec![false; mesh.n_nodes()];
    for (e, conn) in mesh.elements.iter().enumerate() {
        let [i, j] = gm.element_cell[e];
        if gm.grid.cell_center(i, j).y > 12.0 {
            conn.iter().for_each(|&a| upper[a] = true);
        }
    }
    let (mut p, mut moment) = (0.0, 0.0);
    for a in (0..mesh.n_nodes()).filter(|&a| upper[a]) {
        p += f[2 * a + 1];
        moment += mesh.nodes[a].x * f[2 * a + 1];
    }
    let load_line = moment / p;
    let a = load_line - tip.tip.position.x;
    println!("P = {p} N, load line x = {load_line} mm, a = {a} mm");
    assert!((p - 1.0).abs() < 1e-12 && (a - 50.0).abs() < 1e-9);
    let (h, chi) = (12.0, 0.6688);
    let kr = 2.0 * 3f64.sqrt() * p * (a + chi * h) / f64::powf(h, 1.5);
    println!("K_I reference (corrected beam theory, χ = 0.6688): {kr:.5} MPa√mm");
    // Equilibrium: the clamp reactions balance the (self-equilibrated) loads.
    let total: Vector = an.solution.reaction.iter().sum();
    assert!(total.norm() < 1e-9, "net reaction {total:?}");
    for cells in [4usize, 8] {
        let r = tip.domains.iter().find(|r| r.cells == cells).expect("domain fits");
        report(1.0, r);
        assert!(((r.k_from_j - kr) / kr).abs() < 0.02, "sqrt(E'J) {} vs {kr}", r.k_from_j);
        assert!(((r.k1_cod - kr) / kr).abs() < 0.02, "K_I(J, COD split) {} vs {kr}", r.k1_cod);
        assert!(r.k2.abs() <= 0.01 * r.k1, "K_II(int) {}", r.k2);
    }
}
