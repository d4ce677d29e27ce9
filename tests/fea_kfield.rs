//! Mixed-mode boundary-layer problem: the exact Williams near-tip displacement field
//! (Anderson 2005, Tables 2.1–2.2) with K_I = 1, K_II = 0.5 is prescribed on the outer
//! boundary of a 20 × 20 square with a straight crack from the left edge to the centre.
//! The exact solution inside is the same Williams field, so J = (K_I² + K_II²)/E′ and the
//! interaction integral must return K_I = 1, K_II = 0.5.
//!
//! Expected accuracy: uniform Q4 without singular elements resolves the r^½ singularity
//! poorly; extracted K (an energy-like functional) converges as O(h) (Babuška & Miller,
//! Int. J. Numer. Meth. Eng. 20 (1984) 1085; Strang & Fix 1973 ch. 8). Asserted: observed
//! order of the K_I and K_II errors in [0.9, 1.1] over h = 1, 0.5, 0.25, error < 1 % at
//! h = 0.25 (measured 0.49 %), and J·E′ = K_I² + K_II² to 2e-3 (J and the interaction
//! integral see the same discrete field; their mismatch is a higher-order discretisation
//! effect, measured ≤ 7e-4 at h = 1 and falling with h), domain independence to 0.1 %.
//! The crude COD mode split (first node pair behind the tip) is reported, only its sign checked.

use cramp::dim::Vector;
use cramp::fea::jintegral::williams_displacement;
use cramp::fea::{self, BoundaryConditions, Grid, GridMesh, JResult, Model};
use cramp::material::{LinearElastic, PlaneState};
use std::f64::consts::PI;

fn solve(h: f64, state: PlaneState) -> (Vec<JResult>, f64) {
    let n = (20.0 / h).round() as usize;
    let grid = Grid::new(Vector::new(-10.0, -10.0), Vector::new(h, h), n, n).unwrap();
    let mut gm = GridMesh::from_grid(grid, |_, _, _| true).unwrap();
    let cracks = gm.cut_cracks(&[vec![Vector::new(-10.0, 0.0), Vector::new(0.0, 0.0)]]).unwrap();
    let tip = cracks[0].tips[1].unwrap();
    let mat = LinearElastic { e: 2300.0, nu: 0.33, rho: 1.0, state };
    let (mu, kappa) = (mat.shear_modulus(), mat.kappa());
    let model = Model::new(&gm.mesh, mat, 1.0).unwrap();
    // Which face a crack-face node copy belongs to: the side of the elements using it.
    let mut upper_face = vec![false; gm.mesh.n_nodes()];
    for (e, conn) in gm.mesh.elements.iter().enumerate() {
        if gm.element_cell[e][1] as f64 * h - 10.0 >= 0.0 {
            for &a in conn {
                upper_face[a] = true;
            }
        }
    }
    let mut bcs = BoundaryConditions::new(&gm.mesh);
    for (a, (&p, &upper)) in gm.mesh.nodes.iter().zip(&upper_face).enumerate() {
        if p.x.abs() < 10.0 - 1e-9 && p.y.abs() < 10.0 - 1e-9 {
            continue;
        }
        let theta = if p.y == 0.0 && p.x < 0.0 {
            if upper {
                PI
            } else {
                -PI
            }
        } else {
            p.y.atan2(p.x)
        };
        let r = p.norm();
        let u = williams_displacement(1, r, theta, mu, kappa) + 0.5 * williams_displacement(2, r, theta, mu, kappa);
        bcs.prescribe_node(a, u).unwrap();
    }
    let sol = fea::solve(&model, &bcs).unwrap();
    let rs = [2.0, 4.0, 6.0]
        .iter()
        .map(|d| fea::j_integral(&gm, &model, &sol, &tip, (d / h).round() as usize).unwrap())
        .collect();
    (rs, mat.e_prime())
}

#[test]
fn williams_boundary_layer_gives_exact_mixed_mode_k() {
    for state in [PlaneState::PlaneStress, PlaneState::PlaneStrain] {
        let mut err1 = Vec::new();
        let mut err2 = Vec::new();
        for h in [1.0, 0.5, 0.25] {
            let (rs, ep) = solve(h, state);
            for r in &rs {
                println!(
                    "{state:?} h = {h}: domain {:>2} cells: K_I = {:.5}, K_II = {:.5}, J E' = {:.6} (exact 1.25), \
                     COD split K_I = {:.4}, K_II = {:.4}, J E' / (K_I² + K_II²) − 1 = {:+.2e}",
                    r.cells,
                    r.k1,
                    r.k2,
                    r.j * ep,
                    r.k1_cod,
                    r.k2_cod,
                    r.j * ep / (r.k1 * r.k1 + r.k2 * r.k2) - 1.0
                );
                assert!(((r.j * ep - (r.k1 * r.k1 + r.k2 * r.k2)) / (r.j * ep)).abs() < 2e-3);
                assert!(r.k1_cod > 0.0 && r.k2_cod > 0.0);
            }
            let last = rs[rs.len() - 1];
            for r in &rs {
                assert!(((r.k1 - last.k1) / last.k1).abs() < 1e-3 && ((r.k2 - last.k2) / last.k2).abs() < 1e-3);
            }
            err1.push((last.k1 - 1.0).abs());
            err2.push((last.k2 - 0.5).abs() / 0.5);
        }
        for errs in [&err1, &err2] {
            let orders: Vec<f64> = errs.windows(2).map(|w| (w[0] / w[1]).log2()).collect();
            println!("{state:?}: relative K errors {errs:?}, observed orders {orders:.3?}");
            for o in orders {
                assert!((0.9..=1.1).contains(&o), "order {o}");
            }
            assert!(errs[2] < 0.01);
        }
    }
}
