//! The bilinear isoparametric quadrilateral (Q4) with 2×2 Gauss quadrature
//! (Hughes 2000 §3.2 and §3.8; Cook et al. 2002 §6.3).
//!
//! Natural coordinates (ξ, η) ∈ [−1, 1]²; corner `a` at (ξ_a, η_a) =
//! (−1,−1), (1,−1), (1,1), (−1,1) (counter-clockwise);
//! N_a = ¼ (1 + ξ_a ξ)(1 + η_a η).
//! Strain in Voigt form ε = [εxx, εyy, γxy] = B u_e with u_e = [u1x, u1y, …, u4x, u4y].

use crate::dim::Vector;
use nalgebra::{Matrix2, Matrix3, SMatrix, Vector3};

/// Natural coordinates of the corners.
pub const CORNERS: [[f64; 2]; 4] = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]];

/// 1/√3, the 2-point Gauss–Legendre abscissa (weights 1).
pub const G: f64 = 0.577_350_269_189_625_8;

/// 2×2 Gauss points, point `g` next to corner `g`, all with weight 1
/// (exact for polynomials of degree ≤ 3 in each of ξ, η).
pub const GAUSS: [[f64; 2]; 4] = [[-G, -G], [G, -G], [G, G], [-G, G]];

/// Shape functions at (ξ, η).
pub fn shape(xi: f64, eta: f64) -> [f64; 4] {
    CORNERS.map(|[a, b]| 0.25 * (1.0 + a * xi) * (1.0 + b * eta))
}

/// Derivatives [∂N/∂ξ, ∂N/∂η] at (ξ, η).
pub fn shape_grad_natural(xi: f64, eta: f64) -> [[f64; 2]; 4] {
    CORNERS.map(|[a, b]| [0.25 * a * (1.0 + b * eta), 0.25 * b * (1.0 + a * xi)])
}

/// Shape functions, their spatial gradients and det J at one point of an element.
#[derive(Clone, Copy, Debug)]
pub struct PointData {
    pub n: [f64; 4],
    pub grad_n: [Vector; 4],
    pub det_j: f64,
}

/// Evaluate [`PointData`] at (ξ, η) for corner positions `x`.
/// Returns `Err(det J)` if det J ≤ 0 (inverted, degenerate or badly non-convex element).
pub fn point_data(x: &[Vector; 4], xi: f64, eta: f64) -> Result<PointData, f64> {
    let dn = shape_grad_natural(xi, eta);
    // Jacobian J_ij = ∂x_i/∂ξ_j.
    let mut jac = Matrix2::<f64>::zeros();
    for a in 0..4 {
        jac[(0, 0)] += x[a].x * dn[a][0];
        jac[(0, 1)] += x[a].x * dn[a][1];
        jac[(1, 0)] += x[a].y * dn[a][0];
        jac[(1, 1)] += x[a].y * dn[a][1];
    }
    let det_j = jac.determinant();
    // NaN (non-finite coordinates) is rejected too.
    if det_j.is_nan() || det_j <= 0.0 {
        return Err(det_j);
    }
    // ∇_x N = J^{-T} ∇_ξ N.
    let inv = Matrix2::new(jac[(1, 1)], -jac[(0, 1)], -jac[(1, 0)], jac[(0, 0)]) / det_j;
    let grad_n = dn
        .map(|[dxi, deta]| Vector::new(inv[(0, 0)] * dxi + inv[(1, 0)] * deta, inv[(0, 1)] * dxi + inv[(1, 1)] * deta));
    Ok(PointData { n: shape(xi, eta), grad_n, det_j })
}

/// Strain-displacement matrix B (3×8) from the shape-function gradients.
pub fn b_matrix(grad_n: &[Vector; 4]) -> SMatrix<f64, 3, 8> {
    let mut b = SMatrix::<f64, 3, 8>::zeros();
    for a in 0..4 {
        let g = grad_n[a];
        b[(0, 2 * a)] = g.x;
        b[(1, 2 * a + 1)] = g.y;
        b[(2, 2 * a)] = g.y;
        b[(2, 2 * a + 1)] = g.x;
    }
    b
}

/// Element stiffness K_e = Σ_g B_gᵀ D B_g det J_g t (unit weights).
/// `Err((gauss point, det J))` for a bad element.
pub fn stiffness(x: &[Vector; 4], d: &Matrix3<f64>, thickness: f64) -> Result<SMatrix<f64, 8, 8>, (usize, f64)> {
    let mut k = SMatrix::<f64, 8, 8>::zeros();
    for (g, [xi, eta]) in GAUSS.iter().enumerate() {
        let p = point_data(x, *xi, *eta).map_err(|det| (g, det))?;
        let b = b_matrix(&p.grad_n);
        k += b.transpose() * (d * b) * (p.det_j * thickness);
    }
    // Symmetrise exactly (the product above is symmetric only to round-off).
    Ok((k + k.transpose()) * 0.5)
}

/// Voigt strain [εxx, εyy, γxy] from the nodal displacements.
pub fn strain(grad_n: &[Vector; 4], u: &[Vector; 4]) -> Vector3<f64> {
    let mut e = Vector3::zeros();
    for a in 0..4 {
        e[0] += grad_n[a].x * u[a].x;
        e[1] += grad_n[a].y * u[a].y;
        e[2] += grad_n[a].y * u[a].x + grad_n[a].x * u[a].y;
    }
    e
}

/// Displacement gradient H_ij = ∂u_i/∂x_j.
pub fn displacement_gradient(grad_n: &[Vector; 4], u: &[Vector; 4]) -> Matrix2<f64> {
    let mut h = Matrix2::zeros();
    for a in 0..4 {
        h += u[a] * grad_n[a].transpose();
    }
    h
}

/// Map natural coordinates to x.
pub fn map_to_physical(x: &[Vector; 4], xi: f64, eta: f64) -> Vector {
    let n = shape(xi, eta);
    (0..4).fold(Vector::zeros(), |s, a| s + x[a] * n[a])
}

/// Inverse isoparametric map by Newton's method. Returns (ξ, η) if `p` is inside the
/// element (with tolerance `tol` in natural coordinates), `None` otherwise or if Newton fails.
pub fn map_to_natural(x: &[Vector; 4], p: Vector, tol: f64) -> Option<[f64; 2]> {
    let (mut xi, mut eta) = (0.0, 0.0);
    for _ in 0..30 {
        let r = map_to_physical(x, xi, eta) - p;
        let dn = shape_grad_natural(xi, eta);
        let mut jac = Matrix2::zeros();
        for a in 0..4 {
            jac[(0, 0)] += x[a].x * dn[a][0];
            jac[(0, 1)] += x[a].x * dn[a][1];
            jac[(1, 0)] += x[a].y * dn[a][0];
            jac[(1, 1)] += x[a].y * dn[a][1];
        }
        let step = jac.try_inverse()? * r;
        xi -= step.x;
        eta -= step.y;
        if !(xi.is_finite() && eta.is_finite()) || xi.abs() > 10.0 || eta.abs() > 10.0 {
            return None;
        }
        if step.norm() < 1e-14 {
            break;
        }
    }
    (xi.abs() <= 1.0 + tol && eta.abs() <= 1.0 + tol).then_some([xi.clamp(-1.0, 1.0), eta.clamp(-1.0, 1.0)])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shape_functions_partition_unity_and_reproduce_linear_fields() {
        let x = [Vector::new(0.0, 0.0), Vector::new(2.0, 0.3), Vector::new(1.7, 1.9), Vector::new(-0.2, 1.1)];
        for [xi, eta] in GAUSS {
            let p = point_data(&x, xi, eta).unwrap();
            let sum: f64 = p.n.iter().sum();
            assert!((sum - 1.0).abs() < 1e-15);
            // ∇(Σ N_a x_a) = I
            let mut h = Matrix2::zeros();
            for (xa, ga) in x.iter().zip(&p.grad_n) {
                h += xa * ga.transpose();
            }
            assert!((h - Matrix2::identity()).norm() < 1e-14);
        }
    }

    #[test]
    fn inverse_map_round_trips() {
        let x = [Vector::new(0.0, 0.0), Vector::new(2.0, 0.3), Vector::new(1.7, 1.9), Vector::new(-0.2, 1.1)];
        let p = map_to_physical(&x, 0.3, -0.6);
        let [xi, eta] = map_to_natural(&x, p, 1e-12).unwrap();
        assert!((xi - 0.3).abs() < 1e-12 && (eta + 0.6).abs() < 1e-12);
        assert!(map_to_natural(&x, Vector::new(5.0, 5.0), 1e-12).is_none());
    }

    #[test]
    fn clockwise_element_is_rejected() {
        let x = [Vector::new(0.0, 0.0), Vector::new(0.0, 1.0), Vector::new(1.0, 1.0), Vector::new(1.0, 0.0)];
        assert!(point_data(&x, 0.0, 0.0).is_err());
    }
}
