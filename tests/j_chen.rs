//! Chen's (1975) centre-cracked plate under a Heaviside tension (Guo & Nairn 2004 §4.2;
//! references §2(c) and verification/references-errata.md), through the library case
//! `chen_early_time` (src/verify/cases/fracture.rs has the scene and the reference).
//!
//! At 0.25 mm cells, the right half with rollers on the mirror plane and lateral edge:
//! 1. The stress the uncracked plate carries on the crack plane after t₀ is 2σ₀, not σ₀:
//!    the tension waves from the top and the bottom edge arrive together and superpose.
//!    Checked at the ligament node (8, 0), which no wave diffracted by the tip reaches
//!    before 3.49 µs: over 2.95–3.45 µs σ_yy/σ₀ rings about 2 (the discrete step front
//!    overshoots by up to 25 %, USAVG, no artificial viscosity), staying within 1.5–2.6
//!    with a mean within 10 % of 2 — unambiguously 2σ₀.
//! 2. Hence the crack faces are unloaded by p = 2σ₀, and Freund's formula with p = 2σ₀ is
//!    the exact K_I(t) for t₀ < t < 3.385 µs (the references print it with p = σ₀ — a
//!    factor of two too small for this symmetric load). Tolerance on K(t) − exact: 0.1
//!    for t ≥ t₀ + 0.25 µs at 0.25 mm: the smeared front delays and rings the rise by
//!    O(h/c_d); measured 0.083.
//! 3. Before the front arrives K_I is zero: |K| ≤ 0.05 up to t₀ − 0.2 µs (the step front
//!    is smeared over ~6 cells, 0.2 µs at this resolution).
//! 4. Path independence (004 §4.3): the two-term J on the 2×2 and 8×8 contours agree
//!    within 3 % once the tip is loaded, while the line term alone on the 8×8 contour
//!    falls more than 10 % short.

use cramp::verify::cases::fracture::{freund, run_chen, summarize};

#[test]
fn chen_early_time_k_follows_freund_with_the_superposed_wave() {
    let (s, cd, t0) = run_chen(0.25, 3.45).unwrap();
    for x in &s {
        println!(
            "t = {:.3} µs: K/σ√(πa) 2×2 {:.4}, 8×8 {:.4}, 8×8 line only {:.4}; Freund p = 2σ₀ {:.4} (p = σ₀ {:.4}); σyy(8,0)/σ₀ {:.4}",
            x.t, x.k2, x.k8, x.k8_line, freund(2.0, cd, x.t, t0), freund(1.0, cd, x.t, t0), x.syy_ligament
        );
    }
    let r = summarize(&s, cd, t0);
    println!("{r:?}");
    assert!((r.syy_mean - 2.0).abs() <= 0.1 * 2.0, "mean σyy/σ₀ on the ligament {}", r.syy_mean);
    assert!(r.syy_min >= 1.5 && r.syy_max <= 2.6, "σyy/σ₀ on the ligament leaves 2 ± 25 %: {r:?}");
    assert!(r.k_before <= 0.05, "K before the wave arrives: {}", r.k_before);
    assert!(r.k_error <= 0.1, "K vs exact: {} at {} µs", r.k_error, r.k_error_time);
    assert!(r.path_dependence <= 0.03, "two-term J path dependent: {}", r.path_dependence);
    assert!(r.line_deficit > 0.1, "the one-term J should drift on the large contour: {}", r.line_deficit);
}
