//! The Williams near-tip fields of unit K_I and K_II (Anderson 2005, Tables 2.1 and 2.2),
//! and of unit K_III (antiplane shear): the auxiliary state of the interaction integral (the
//! static FEA's K split, [`crate::fea::jintegral`], the MPM contour's `cod = "interaction"`,
//! [`crate::fracture::jintegral`], and the 3D domain's `split = "interaction"`,
//! [`crate::fracture::front3`]) and the displacement of the `williams` boundary condition
//! ([`crate::motion`]).

use crate::dim::Vector;
use std::f64::consts::PI;

/// Williams near-tip auxiliary field of unit K at a point (local polar r, θ):
/// stress [σ11, σ22, σ12] and the x1-derivative of the displacement [∂u1/∂x1, ∂u2/∂x1].
/// `mode` 1 or 2. Anderson (2005) Tables 2.1 and 2.2; μ shear modulus, κ Kolosov constant.
///
/// The displacements are u = √r f(θ) with f from the tables, so
/// ∂u/∂x1 = cos θ ∂u/∂r − (sin θ / r) ∂u/∂θ = (cos θ f/2 − sin θ f′) / √r.
pub fn williams_aux(mode: u8, r: f64, theta: f64, mu: f64, kappa: f64) -> ([f64; 3], [f64; 2]) {
    let (s, c) = (0.5 * theta).sin_cos();
    let (s3, c3) = (1.5 * theta).sin_cos();
    let a = 1.0 / (2.0 * PI * r).sqrt();
    let cc = 1.0 / (2.0 * mu * (2.0 * PI).sqrt());
    let (sig, f, fp) = if mode == 1 {
        (
            [a * c * (1.0 - s * s3), a * c * (1.0 + s * s3), a * c * s * c3],
            [cc * c * (kappa - 1.0 + 2.0 * s * s), cc * s * (kappa + 1.0 - 2.0 * c * c)],
            [
                cc * (-0.5 * s * (kappa - 1.0 + 2.0 * s * s) + 2.0 * s * c * c),
                cc * (0.5 * c * (kappa + 1.0 - 2.0 * c * c) + 2.0 * s * s * c),
            ],
        )
    } else {
        (
            [-a * s * (2.0 + c * c3), a * s * c * c3, a * c * (1.0 - s * s3)],
            [cc * s * (kappa + 1.0 + 2.0 * c * c), -cc * c * (kappa - 1.0 - 2.0 * s * s)],
            [
                cc * (0.5 * c * (kappa + 1.0 + 2.0 * c * c) - 2.0 * s * s * c),
                cc * (0.5 * s * (kappa - 1.0 - 2.0 * s * s) + 2.0 * s * c * c),
            ],
        )
    };
    let (st, ct) = theta.sin_cos();
    let sr = r.sqrt();
    let du1 = [(ct * 0.5 * f[0] - st * fp[0]) / sr, (ct * 0.5 * f[1] - st * fp[1]) / sr];
    (sig, du1)
}

/// Williams near-tip displacement of unit K (used to test [`williams_aux`]).
pub fn williams_displacement(mode: u8, r: f64, theta: f64, mu: f64, kappa: f64) -> Vector {
    let (s, c) = (0.5 * theta).sin_cos();
    let k = (r / (2.0 * PI)).sqrt() / (2.0 * mu);
    if mode == 1 {
        Vector::new(k * c * (kappa - 1.0 + 2.0 * s * s), k * s * (kappa + 1.0 - 2.0 * c * c))
    } else {
        Vector::new(k * s * (kappa + 1.0 + 2.0 * c * c), -k * c * (kappa - 1.0 - 2.0 * s * s))
    }
}


/// The mode III field of unit K_III at local polar (r, θ) (Anderson 2005, Table 2.2):
/// stress [σ13, σ23] = (−sin(θ/2), cos(θ/2))/√(2πr) and ∂u3/∂x1, with
/// u3 = (2/μ)√(r/2π) sin(θ/2), so ∂u3/∂x1 = (2/μ)(cos θ sin(θ/2)/2 − sin θ cos(θ/2)/2)/√(2πr).
pub fn williams_aux_iii(r: f64, theta: f64, mu: f64) -> ([f64; 2], f64) {
    let (s, c) = (0.5 * theta).sin_cos();
    let a = 1.0 / (2.0 * PI * r).sqrt();
    let (st, ct) = theta.sin_cos();
    ([-a * s, a * c], 2.0 / mu * a * (0.5 * ct * s - 0.5 * st * c))
}

/// The mode III displacement u3 of unit K_III (used to test [`williams_aux_iii`]).
pub fn williams_displacement_iii(r: f64, theta: f64, mu: f64) -> f64 {
    2.0 / mu * (r / (2.0 * PI)).sqrt() * (0.5 * theta).sin()
}
