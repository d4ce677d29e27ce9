//! The trilinear isoparametric hexahedron (hex8) with 2×2×2 Gauss quadrature
//! (Hughes 2000 §3.5 and §3.8; Cook et al. 2002 §6.4) — the 3D counterpart of
//! [`super::element`] (Q4).
//!
//! Natural coordinates (ξ, η, ζ) ∈ [−1, 1]³; corner `a` at (ξ_a, η_a, ζ_a) =
//! (−1,−1,−1), (1,−1,−1), (1,1,−1), (−1,1,−1), then the same four at ζ = +1 (the VTK
//! hexahedron order: the bottom face counter-clockwise seen from +z, then the top);
//! N_a = ⅛ (1 + ξ_a ξ)(1 + η_a η)(1 + ζ_a ζ).
//! Strain in Voigt form ε = [εxx, εyy, εzz, γxy, γyz, γxz] = B u_e with
//! u_e = [u1x, u1y, u1z, …, u8x, u8y, u8z] (engineering shear γ = 2ε).
//!
//! The material law is the MPM's own ([`LinearElastic::update_3d`]): D is built column by
//! column from it ([`d_matrix`]) and the stress of a strain is its update from zero
//! ([`stress`]), so the FEA and the MPM use one Hooke's law.

use crate::dim::{Sym3, Vector3};
use crate::material::LinearElastic;
use nalgebra::{Matrix3, SMatrix};

/// Natural coordinates of the corners.
pub const CORNERS: [[f64; 3]; 8] = [
    [-1.0, -1.0, -1.0],
    [1.0, -1.0, -1.0],
    [1.0, 1.0, -1.0],
    [-1.0, 1.0, -1.0],
    [-1.0, -1.0, 1.0],
    [1.0, -1.0, 1.0],
    [1.0, 1.0, 1.0],
    [-1.0, 1.0, 1.0],
];

/// 2×2×2 Gauss points, point `g` next to corner `g`, all with weight 1 (exact for
/// polynomials of degree ≤ 3 in each of ξ, η, ζ).
pub const GAUSS: [[f64; 3]; 8] = {
    let g = super::element::G;
    let mut p = [[0.0; 3]; 8];
    let mut a = 0;
    while a < 8 {
        p[a] = [g * CORNERS[a][0], g * CORNERS[a][1], g * CORNERS[a][2]];
        a += 1;
    }
    p
};

/// Shape functions at ξ = (ξ, η, ζ).
pub fn shape(xi: [f64; 3]) -> [f64; 8] {
    CORNERS.map(|c| 0.125 * (1.0 + c[0] * xi[0]) * (1.0 + c[1] * xi[1]) * (1.0 + c[2] * xi[2]))
}

/// Derivatives [∂N/∂ξ, ∂N/∂η, ∂N/∂ζ] at ξ.
pub fn shape_grad_natural(xi: [f64; 3]) -> [[f64; 3]; 8] {
    CORNERS.map(|c| {
        let f = [1.0 + c[0] * xi[0], 1.0 + c[1] * xi[1], 1.0 + c[2] * xi[2]];
        [0.125 * c[0] * f[1] * f[2], 0.125 * c[1] * f[0] * f[2], 0.125 * c[2] * f[0] * f[1]]
    })
}

/// Jacobian J_ij = ∂x_i/∂ξ_j.
fn jacobian(x: &[Vector3; 8], dn: &[[f64; 3]; 8]) -> Matrix3<f64> {
    let mut jac = Matrix3::zeros();
    for a in 0..8 {
        for i in 0..3 {
            for j in 0..3 {
                jac[(i, j)] += x[a][i] * dn[a][j];
            }
        }
    }
    jac
}

/// Shape functions, their spatial gradients and det J at one point of an element.
#[derive(Clone, Copy, Debug)]
pub struct PointData {
    pub n: [f64; 8],
    pub grad_n: [Vector3; 8],
    pub det_j: f64,
}

/// Evaluate [`PointData`] at ξ for corner positions `x`.
/// Returns `Err(det J)` if det J ≤ 0 (inverted, degenerate or badly distorted element).
pub fn point_data(x: &[Vector3; 8], xi: [f64; 3]) -> Result<PointData, f64> {
    let dn = shape_grad_natural(xi);
    let jac = jacobian(x, &dn);
    let det_j = jac.determinant();
    if det_j.is_nan() || det_j <= 0.0 {
        return Err(det_j);
    }
    let Some(inv) = jac.try_inverse() else { return Err(det_j) };
    // ∇_x N = J^{-T} ∇_ξ N.
    let grad_n = dn.map(|d| inv.transpose() * Vector3::new(d[0], d[1], d[2]));
    Ok(PointData { n: shape(xi), grad_n, det_j })
}

/// Strain-displacement matrix B (6×24) from the shape-function gradients.
pub fn b_matrix(grad_n: &[Vector3; 8]) -> SMatrix<f64, 6, 24> {
    let mut b = SMatrix::<f64, 6, 24>::zeros();
    for a in 0..8 {
        let g = grad_n[a];
        let (cx, cy, cz) = (3 * a, 3 * a + 1, 3 * a + 2);
        b[(0, cx)] = g.x;
        b[(1, cy)] = g.y;
        b[(2, cz)] = g.z;
        b[(3, cx)] = g.y;
        b[(3, cy)] = g.x;
        b[(4, cy)] = g.z;
        b[(4, cz)] = g.y;
        b[(5, cx)] = g.z;
        b[(5, cz)] = g.x;
    }
    b
}

/// Voigt strain [εxx, εyy, εzz, γxy, γyz, γxz] as a tensor (shear halved).
fn voigt_to_tensor(e: &[f64; 6]) -> Sym3 {
    Sym3 { xx: e[0], yy: e[1], zz: e[2], xy: 0.5 * e[3], yz: 0.5 * e[4], xz: 0.5 * e[5] }
}

/// Stress of the MPM's Hooke's law ([`LinearElastic::update_3d`]) for a total strain (tensor shear).
pub fn stress(material: &LinearElastic, strain: &Sym3) -> Sym3 {
    let (mut e, mut s) = (Sym3::ZERO, Sym3::ZERO);
    material.update_3d(strain, &mut e, &mut s);
    s
}

/// D (Voigt, engineering shear) with column k the stress of the unit Voigt strain k.
pub fn d_matrix(material: &LinearElastic) -> SMatrix<f64, 6, 6> {
    let mut d = SMatrix::<f64, 6, 6>::zeros();
    for k in 0..6 {
        let mut unit = [0.0; 6];
        unit[k] = 1.0;
        let s = stress(material, &voigt_to_tensor(&unit));
        for (r, v) in [s.xx, s.yy, s.zz, s.xy, s.yz, s.xz].into_iter().enumerate() {
            d[(r, k)] = v;
        }
    }
    d
}

/// Element stiffness K_e = Σ_g B_gᵀ D B_g det J_g (unit weights).
/// `Err((gauss point, det J))` for a bad element.
pub fn stiffness(x: &[Vector3; 8], d: &SMatrix<f64, 6, 6>) -> Result<SMatrix<f64, 24, 24>, (usize, f64)> {
    let mut k = SMatrix::<f64, 24, 24>::zeros();
    for (g, xi) in GAUSS.iter().enumerate() {
        let p = point_data(x, *xi).map_err(|det| (g, det))?;
        let b = b_matrix(&p.grad_n);
        k += b.transpose() * (d * b) * p.det_j;
    }
    // Symmetrise exactly (the product above is symmetric only to round-off).
    Ok((k + k.transpose()) * 0.5)
}

/// Displacement gradient H_ij = ∂u_i/∂x_j.
pub fn displacement_gradient(grad_n: &[Vector3; 8], u: &[Vector3; 8]) -> Matrix3<f64> {
    let mut h = Matrix3::zeros();
    for a in 0..8 {
        h += u[a] * grad_n[a].transpose();
    }
    h
}

/// Strain (tensor shear) from the nodal displacements.
pub fn strain(grad_n: &[Vector3; 8], u: &[Vector3; 8]) -> Sym3 {
    let h = displacement_gradient(grad_n, u);
    Sym3 {
        xx: h[(0, 0)],
        yy: h[(1, 1)],
        zz: h[(2, 2)],
        xy: 0.5 * (h[(0, 1)] + h[(1, 0)]),
        xz: 0.5 * (h[(0, 2)] + h[(2, 0)]),
        yz: 0.5 * (h[(1, 2)] + h[(2, 1)]),
    }
}

/// Voigt vector of a stress (for f = Bᵀσ).
pub fn voigt_stress(s: &Sym3) -> SMatrix<f64, 6, 1> {
    SMatrix::<f64, 6, 1>::from_column_slice(&[s.xx, s.yy, s.zz, s.xy, s.yz, s.xz])
}

/// Map natural coordinates to x.
pub fn map_to_physical(x: &[Vector3; 8], xi: [f64; 3]) -> Vector3 {
    let n = shape(xi);
    (0..8).fold(Vector3::zeros(), |s, a| s + x[a] * n[a])
}

/// Inverse isoparametric map by Newton's method. Returns ξ if `p` is inside the element
/// (with tolerance `tol` in natural coordinates), `None` otherwise or if Newton fails.
pub fn map_to_natural(x: &[Vector3; 8], p: Vector3, tol: f64) -> Option<[f64; 3]> {
    let mut xi = [0.0; 3];
    for _ in 0..30 {
        let r = map_to_physical(x, xi) - p;
        let step = jacobian(x, &shape_grad_natural(xi)).try_inverse()? * r;
        for c in 0..3 {
            xi[c] -= step[c];
        }
        if xi.iter().any(|v| !v.is_finite() || v.abs() > 10.0) {
            return None;
        }
        if step.norm() < 1e-14 {
            break;
        }
    }
    xi.iter().all(|v| v.abs() <= 1.0 + tol).then(|| xi.map(|v| v.clamp(-1.0, 1.0)))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn distorted() -> [Vector3; 8] {
        let mut x = CORNERS.map(|c| Vector3::new(c[0], c[1], c[2]));
        let shifts = [[0.1, -0.2, 0.05], [0.3, 0.1, -0.1], [-0.2, 0.25, 0.1], [0.05, -0.1, 0.2], [-0.1, 0.1, 0.3], [0.2, 0.0, -0.2], [0.1, 0.3, 0.15], [-0.3, -0.05, 0.1]];
        for (p, s) in x.iter_mut().zip(shifts) {
            *p += Vector3::new(s[0], s[1], s[2]);
        }
        x
    }

    #[test]
    fn shape_functions_partition_unity_and_reproduce_linear_fields() {
        let x = distorted();
        for xi in GAUSS {
            let p = point_data(&x, xi).unwrap();
            assert!((p.n.iter().sum::<f64>() - 1.0).abs() < 1e-15);
            let h = displacement_gradient(&p.grad_n, &x);
            assert!((h - Matrix3::identity()).norm() < 1e-14);
        }
    }

    #[test]
    fn d_matrix_is_the_isotropic_one() {
        let m = LinearElastic::solid(200.0, 0.3, 1.0);
        let d = d_matrix(&m);
        let (l, mu) = (m.lambda_3d(), m.shear_modulus());
        for i in 0..6 {
            for j in 0..6 {
                let want = if i < 3 && j < 3 { l + if i == j { 2.0 * mu } else { 0.0 } } else if i == j { mu } else { 0.0 };
                assert!((d[(i, j)] - want).abs() < 1e-12 * l, "D[{i}][{j}] = {} vs {want}", d[(i, j)]);
            }
        }
    }

    #[test]
    fn stiffness_has_six_rigid_modes_and_is_symmetric() {
        let x = distorted();
        let k = stiffness(&x, &d_matrix(&LinearElastic::solid(1.0, 0.25, 1.0))).unwrap();
        assert_eq!(k, k.transpose());
        let eig = k.symmetric_eigen();
        let max = eig.eigenvalues.max();
        let zero = eig.eigenvalues.iter().filter(|v| v.abs() < 1e-12 * max).count();
        assert_eq!(zero, 6, "eigenvalues {:?}", eig.eigenvalues);
    }

    #[test]
    fn inverse_map_round_trips() {
        let x = distorted();
        let p = map_to_physical(&x, [0.3, -0.6, 0.2]);
        let xi = map_to_natural(&x, p, 1e-12).unwrap();
        assert!((xi[0] - 0.3).abs() < 1e-12 && (xi[1] + 0.6).abs() < 1e-12 && (xi[2] - 0.2).abs() < 1e-12);
        assert!(map_to_natural(&x, Vector3::new(5.0, 5.0, 5.0), 1e-12).is_none());
    }

    #[test]
    fn mirrored_element_is_rejected() {
        let mut x = CORNERS.map(|c| Vector3::new(c[0], c[1], c[2]));
        x.swap(1, 3);
        x.swap(5, 7);
        assert!(point_data(&x, [0.0; 3]).is_err());
    }
}
