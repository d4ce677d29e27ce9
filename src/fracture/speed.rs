//! Crack-speed factors for the dynamic J ↔ K relation of a moving crack tip
//! (paper 001 eqs. 14–18; Nishioka & Atluri 1983; Freund 1990), in the corrected form
//! of the verification references §7:
//!
//! * β_d = √(1 − v²/c_d²) (dilatational), β_s = √(1 − v²/c_s²) (shear);
//! * D = 4β_dβ_s − (1 + β_s²)² (the Rayleigh function, D = 0 at v = c_R);
//! * A_I = β_d(1 − β_s²)/D, A_II = β_s(1 − β_s²)/D;
//! * G = J = (A_I K_I² + A_II K_II²)/(2μ); A_I, A_II → (κ + 1)/4 as v → 0.
//!
//! Paper 001 eq. 16 prints β_I with c_s and β_II with c_d; used in its eq. 17 that
//! would put c_d into the (1 + β²)² term of the Rayleigh function, so the labels are
//! swapped there: β_I ≡ β_d, β_II ≡ β_s here.
//!
//! Evaluating D directly loses all precision at low speed (D = O(v²) is a difference
//! of O(1) terms), so D/q with q = v²/c_s², p = v²/c_d² is evaluated in the exact
//! rearrangement of references §7:
//!
//! D/q = [16(1 − c_s²/c_d²) + 16p − 24q + 8q² − q³] / [4β_dβ_s + (2 − q)²],
//!
//! (multiply D by its conjugate 4β_dβ_s + (1 + β_s²)² and use 1 + β_s² = 2 − q), so
//! A_I = β_d/(D/q), A_II = β_s/(D/q) are accurate to a few ulps at every speed below
//! c_R.

use crate::material::{Constitutive, LinearElastic};
use thiserror::Error;

/// Why the speed factors could not be evaluated.
#[derive(Clone, Copy, Debug, PartialEq, Error)]
pub enum SpeedError {
    /// c_d, c_s must be finite with 0 < c_s < c_d.
    #[error("invalid wave speeds c_d = {c_d}, c_s = {c_s} (need 0 < c_s < c_d)")]
    InvalidWaveSpeeds { c_d: f64, c_s: f64 },
    /// The crack speed must be finite and non-negative.
    #[error("invalid crack speed {v}")]
    InvalidSpeed { v: f64 },
    /// A_I, A_II diverge at the Rayleigh speed and are meaningless beyond it.
    #[error("crack speed {v} at or above the Rayleigh speed {c_r}")]
    AtOrAboveRayleigh { v: f64, c_r: f64 },
}

/// The speed factors of a crack moving at speed v (references §7).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpeedFactors {
    /// β_d = √(1 − v²/c_d²).
    pub beta_d: f64,
    /// β_s = √(1 − v²/c_s²).
    pub beta_s: f64,
    /// A_I = β_d(1 − β_s²)/D.
    pub a_i: f64,
    /// A_II = β_s(1 − β_s²)/D.
    pub a_ii: f64,
}

impl SpeedFactors {
    /// Energy release rate (dynamic J of a moving tip) from K_I, K_II:
    /// G = (A_I K_I² + A_II K_II²)/(2μ) (paper 001 eqs. 14–15 inverted; references §7).
    pub fn energy_release_rate(&self, k1: f64, k2: f64, mu: f64) -> f64 {
        (self.a_i * k1 * k1 + self.a_ii * k2 * k2) / (2.0 * mu)
    }
}

fn check_wave_speeds(c_d: f64, c_s: f64) -> Result<(), SpeedError> {
    if c_d.is_finite() && c_s.is_finite() && c_s > 0.0 && c_s < c_d {
        Ok(())
    } else {
        Err(SpeedError::InvalidWaveSpeeds { c_d, c_s })
    }
}

/// D/q, the Rayleigh function divided by q = v²/c_s², in the stable form of
/// references §7. Valid for 0 ≤ v ≤ c_s. Positive on [0, c_R), zero at c_R.
fn rayleigh_over_q(v: f64, c_d: f64, c_s: f64) -> f64 {
    let r = (c_s / c_d) * (c_s / c_d);
    let p = (v / c_d) * (v / c_d);
    let q = (v / c_s) * (v / c_s);
    let bd = (1.0 - p).max(0.0).sqrt();
    let bs = (1.0 - q).max(0.0).sqrt();
    let num = 16.0 * (1.0 - r) + 16.0 * p - 24.0 * q + 8.0 * q * q - q * q * q;
    let den = 4.0 * bd * bs + (2.0 - q) * (2.0 - q);
    num / den
}

/// The Rayleigh function D(v) = 4β_dβ_s − (1 + β_s²)², evaluated **directly**
/// (inaccurate at low speed: kept to document the pitfall of references §7).
pub fn rayleigh_function(v: f64, c_d: f64, c_s: f64) -> f64 {
    let bd = (1.0 - (v / c_d) * (v / c_d)).sqrt();
    let bs2 = 1.0 - (v / c_s) * (v / c_s);
    4.0 * bd * bs2.sqrt() - (1.0 + bs2) * (1.0 + bs2)
}

/// Rayleigh wave speed c_R: the root of D(v) = 0 in (0, c_s), by bisection on the
/// stable D/q (positive at 0, equal to −1 at c_s) down to adjacent floating-point
/// numbers. Errors for invalid wave speeds.
pub fn rayleigh_speed(c_d: f64, c_s: f64) -> Result<f64, SpeedError> {
    check_wave_speeds(c_d, c_s)?;
    let (mut lo, mut hi) = (0.0f64, c_s);
    for _ in 0..2000 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if rayleigh_over_q(mid, c_d, c_s) > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Ok(lo)
}

/// Crack-speed factors β_d, β_s, A_I, A_II at crack speed `v` (references §7; paper 001
/// eqs. 16–17 with the β labels corrected). At v = 0 the limit is returned exactly:
/// β = 1, A_I = A_II = 1/(2(1 − c_s²/c_d²)) = (κ + 1)/4. Errors for v < 0, non-finite
/// input, invalid wave speeds, and v ≥ c_R.
pub fn speed_factors(v: f64, c_d: f64, c_s: f64) -> Result<SpeedFactors, SpeedError> {
    check_wave_speeds(c_d, c_s)?;
    if !(v.is_finite() && v >= 0.0) {
        return Err(SpeedError::InvalidSpeed { v });
    }
    if v == 0.0 {
        let r = (c_s / c_d) * (c_s / c_d);
        let a = 1.0 / (2.0 * (1.0 - r));
        return Ok(SpeedFactors { beta_d: 1.0, beta_s: 1.0, a_i: a, a_ii: a });
    }
    let c_r = rayleigh_speed(c_d, c_s)?;
    let dq = rayleigh_over_q(v, c_d, c_s);
    // dq ≤ 0 (or NaN) can only happen within rounding of c_R
    if v >= c_r || dq.is_nan() || dq <= 0.0 {
        return Err(SpeedError::AtOrAboveRayleigh { v, c_r });
    }
    let beta_d = (1.0 - (v / c_d) * (v / c_d)).sqrt();
    let beta_s = (1.0 - (v / c_s) * (v / c_s)).sqrt();
    Ok(SpeedFactors { beta_d, beta_s, a_i: beta_d / dq, a_ii: beta_s / dq })
}

/// Wave speeds (c_d, c_s) of a material, consistent with its 2D state (references §7):
/// c_d = √((λ + 2μ)/ρ) with the in-plane λ (plane strain E(1−ν)/(ρ(1+ν)(1−2ν)), plane
/// stress E/(ρ(1−ν²)); paper 001 eq. 18: c_d² = ((κ+1)/(κ−1)) μ/ρ), c_s = √(μ/ρ).
pub fn wave_speeds(m: &LinearElastic) -> (f64, f64) {
    (m.wave_speed(), m.shear_wave_speed())
}

/// [`speed_factors`] with the wave speeds of `m` ([`wave_speeds`]).
pub fn speed_factors_for(m: &LinearElastic, v: f64) -> Result<SpeedFactors, SpeedError> {
    let (c_d, c_s) = wave_speeds(m);
    speed_factors(v, c_d, c_s)
}

/// Rayleigh speed of a material ([`rayleigh_speed`] with [`wave_speeds`]).
pub fn rayleigh_speed_for(m: &LinearElastic) -> Result<f64, SpeedError> {
    let (c_d, c_s) = wave_speeds(m);
    rayleigh_speed(c_d, c_s)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::PlaneState;

    fn mat(state: PlaneState) -> LinearElastic {
        // the Chen (1975) set of references §2(c); results depend on ν and state only
        LinearElastic { e: 199.4e9, nu: 0.3, rho: 5000.0, state }
    }

    /// References §7 table: v/c_R, plane strain A_I, A_II, plane stress A_I, A_II (ν = 0.3).
    const TABLE: [(f64, f64, f64, f64, f64); 10] = [
        (0.1, 0.704469, 0.702296, 0.774161, 0.772040),
        (0.2, 0.718365, 0.709394, 0.789497, 0.780730),
        (0.3, 0.743308, 0.721988, 0.817047, 0.796174),
        (0.4, 0.782603, 0.741485, 0.860502, 0.820141),
        (0.5, 0.842600, 0.770580, 0.926972, 0.856021),
        (0.6, 0.936165, 0.814715, 1.030902, 0.910663),
        (0.7, 1.093010, 0.886455, 1.205767, 0.999894),
        (0.8, 1.400449, 1.022841, 1.550365, 1.170416),
        (0.9, 2.284426, 1.405813, 2.549108, 1.652010),
        (0.95, 3.990653, 2.139879, 4.490205, 2.578898),
    ];

    /// The table is printed to 6 decimals: a correct value lies within 5e-7; 1e-6
    /// leaves a margin for the printed rounding only (tighter than the 1e-5 asked).
    const TABLE_TOL: f64 = 1e-6;

    #[test]
    fn speed_factors_match_reference_table() {
        for (k, state) in [PlaneState::PlaneStrain, PlaneState::PlaneStress].into_iter().enumerate() {
            let m = mat(state);
            let c_r = rayleigh_speed_for(&m).unwrap();
            for row in TABLE {
                let (want_i, want_ii) = if k == 0 { (row.1, row.2) } else { (row.3, row.4) };
                let f = speed_factors_for(&m, row.0 * c_r).unwrap();
                assert!((f.a_i - want_i).abs() < TABLE_TOL, "{state:?} v/c_R {}: A_I {}", row.0, f.a_i);
                assert!((f.a_ii - want_ii).abs() < TABLE_TOL, "{state:?} v/c_R {}: A_II {}", row.0, f.a_ii);
                // the stable form equals the textbook definition where the latter is accurate
                let d = rayleigh_function(row.0 * c_r, m.wave_speed(), m.shear_wave_speed());
                let one_minus_bs2 = 1.0 - f.beta_s * f.beta_s;
                assert!((f.beta_d * one_minus_bs2 / d - f.a_i).abs() < 1e-9 * f.a_i);
                assert!((f.beta_s * one_minus_bs2 / d - f.a_ii).abs() < 1e-9 * f.a_ii);
            }
        }
    }

    #[test]
    fn rayleigh_speed_ratios() {
        let ce = rayleigh_speed_for(&mat(PlaneState::PlaneStrain)).unwrap() / mat(PlaneState::PlaneStrain).shear_wave_speed();
        let cs = rayleigh_speed_for(&mat(PlaneState::PlaneStress)).unwrap() / mat(PlaneState::PlaneStress).shear_wave_speed();
        // references §7 (5 decimals)
        assert!((ce - 0.92741).abs() < 5e-6, "{ce}");
        assert!((cs - 0.91621).abs() < 5e-6, "{cs}");
        // references §2(c): Chen set, c_R = 3632.15 m/s (plane strain)
        let c_r = rayleigh_speed_for(&mat(PlaneState::PlaneStrain)).unwrap();
        assert!((c_r - 3632.15).abs() < 0.005, "{c_r}");
        // D vanishes there (stable form), and c_R < c_s < c_d
        let (c_d, c_s) = wave_speeds(&mat(PlaneState::PlaneStrain));
        assert!(rayleigh_over_q(c_r, c_d, c_s).abs() < 1e-12);
        assert!(c_r < c_s && c_s < c_d);
    }

    #[test]
    fn low_speed_limit_is_kappa_plus_one_over_four() {
        for state in [PlaneState::PlaneStrain, PlaneState::PlaneStress] {
            let m = mat(state);
            let lim = (m.kappa() + 1.0) / 4.0;
            let f0 = speed_factors_for(&m, 0.0).unwrap();
            assert_eq!((f0.beta_d, f0.beta_s), (1.0, 1.0));
            assert!((f0.a_i - lim).abs() < 1e-15 && f0.a_ii == f0.a_i, "{state:?}");
            let c_r = rayleigh_speed_for(&m).unwrap();
            for x in [1e-6, 1e-9, 1e-12] {
                let f = speed_factors_for(&m, x * c_r).unwrap();
                // the stable form is accurate; the deviation from the limit is O(x²)
                assert!((f.a_i - lim).abs() < 1e-9, "{state:?} {x}: {}", f.a_i);
                assert!((f.a_ii - lim).abs() < 1e-9, "{state:?} {x}: {}", f.a_ii);
            }
        }
        // plane strain ν = 0.3: 0.7 (to 1e-9 at v = 1e-6 c_R) — the direct formula is
        // visibly wrong there (the 0.700036 of references §7)
        let m = mat(PlaneState::PlaneStrain);
        let c_r = rayleigh_speed_for(&m).unwrap();
        let v = 1e-6 * c_r;
        assert!((speed_factors_for(&m, v).unwrap().a_i - 0.7).abs() < 1e-9);
        let (c_d, c_s) = wave_speeds(&m);
        let naive = (1.0 - (v / c_d).powi(2)).sqrt() * (v / c_s).powi(2) / rayleigh_function(v, c_d, c_s);
        assert!((naive - 0.7).abs() > 1e-6, "direct D unexpectedly accurate: {naive}");
        // Freund's normalisation A_I/(1−ν) → 1 in plane strain; G → (K_I² + K_II²)/E'
        let f = speed_factors_for(&m, 0.0).unwrap();
        assert!((f.a_i / (1.0 - m.nu) - 1.0).abs() < 1e-15);
        let g = f.energy_release_rate(2.0, 1.0, m.shear_modulus());
        assert!((g * m.e_prime() / 5.0 - 1.0).abs() < 1e-14, "{g}");
    }

    #[test]
    fn monotone_and_divergent_toward_rayleigh() {
        let m = mat(PlaneState::PlaneStrain);
        let c_r = rayleigh_speed_for(&m).unwrap();
        let mut prev = speed_factors_for(&m, 0.0).unwrap();
        for i in 1..1000 {
            let f = speed_factors_for(&m, c_r * i as f64 / 1000.0).unwrap();
            assert!(f.a_i >= prev.a_i && f.a_ii >= prev.a_ii && f.a_i >= f.a_ii);
            prev = f;
        }
        assert!(prev.a_i > 100.0);
    }

    #[test]
    fn errors_at_or_above_rayleigh_and_on_bad_input() {
        let m = mat(PlaneState::PlaneStress);
        let c_r = rayleigh_speed_for(&m).unwrap();
        assert!(matches!(speed_factors_for(&m, c_r), Err(SpeedError::AtOrAboveRayleigh { .. })));
        assert!(matches!(speed_factors_for(&m, 1.5 * c_r), Err(SpeedError::AtOrAboveRayleigh { .. })));
        assert!(matches!(speed_factors_for(&m, 1e9), Err(SpeedError::AtOrAboveRayleigh { .. })));
        assert!(speed_factors_for(&m, c_r * (1.0 - 1e-9)).is_ok());
        assert!(matches!(speed_factors_for(&m, -1.0), Err(SpeedError::InvalidSpeed { .. })));
        assert!(matches!(speed_factors_for(&m, f64::NAN), Err(SpeedError::InvalidSpeed { .. })));
        assert!(matches!(speed_factors(1.0, 1.0, 2.0), Err(SpeedError::InvalidWaveSpeeds { .. })));
        assert!(matches!(rayleigh_speed(1.0, 0.0), Err(SpeedError::InvalidWaveSpeeds { .. })));
        assert!(matches!(rayleigh_speed(f64::INFINITY, 1.0), Err(SpeedError::InvalidWaveSpeeds { .. })));
    }

    /// Paper 001 eq. 18 (c_d² = ((κ+1)/(κ−1)) μ/ρ) agrees with the material's c_d in both
    /// plane states.
    #[test]
    fn wave_speeds_consistent_with_paper_eq18() {
        for state in [PlaneState::PlaneStrain, PlaneState::PlaneStress] {
            let m = mat(state);
            let k = m.kappa();
            let cd2 = (k + 1.0) / (k - 1.0) * m.shear_modulus() / m.rho;
            let (c_d, c_s) = wave_speeds(&m);
            assert!((c_d * c_d / cd2 - 1.0).abs() < 1e-14, "{state:?}");
            assert!((c_s * c_s * m.rho / m.shear_modulus() - 1.0).abs() < 1e-14);
        }
        // references §2(c): c_d = 7326.98 m/s, c_s = 3916.43 m/s (plane strain)
        let (c_d, c_s) = wave_speeds(&mat(PlaneState::PlaneStrain));
        assert!((c_d - 7326.98).abs() < 0.005 && (c_s - 3916.43).abs() < 0.005);
    }
}
