//! J-integral and stress intensity factors on the split-beam specimens of Guo & Nairn
//! 2004 §4.1 (Fig. 4): 100 × 24 × 1 mm, crack on the mid-plane y = 12 from the loaded
//! end x = 100 to the tip at x = 50, E = 2300 MPa, ν = 0.33, ρ = 1.5 g/cm³, plane
//! stress, left edge clamped, end loads P_T (top arm) and P_B (bottom arm) applied at
//! t = 0 and held, damped so the run settles to the static solution. Units mm, g, ms
//! (N, MPa; K in MPa√mm; loads per unit thickness since the thickness is 1 mm).
//!
//! References (verification references §1(a), §1(b); Guo & Nairn 2004 eqs. 23–24):
//! * DCB, P_T = −P_B = P: corrected beam theory K_I = 2√3 P (a + χh)/h^{3/2}, h = 12 mm
//!   the arm thickness, χ = 0.6688 (Williams 1989 for ν = 0.33; Kanninen's 0.639 and
//!   the elasticity value 0.673 move K_I by −0.6 % / +0.1 %); K_II = 0 by symmetry.
//! * Equal-shear split beam ("ENF" in 004), P_T = P_B = P: K_II = 3Pa/h^{3/2} ·
//!   √(1 + (2(1+ν)/5)(h/a)²) (Carlsson et al. 1986 shear correction), K_I = 0 by
//!   antisymmetry. Crack-face contact is off ("none"): the exact faces slide without
//!   pressure, and the arms bend alike, so they do not interpenetrate.
//! * Mixed, P_T = P, P_B = 0 = ½(P, −P) + ½(P, P): K_I and K_II are half of the two
//!   above (superposition of the beam-theory values).
//!
//! Here a is measured from the load line — the column of loaded particles at
//! x = 100 − h/4 — to the tip: a = 50 − h/4.
//!
//! Set-up choices, each stated because each moves the result:
//! * The grid is shifted a quarter cell in x so the tip lies inside a cell, not on a
//!   node (see verification/references-errata.md: a tip on a node makes one arm one
//!   cell shorter once the crack leaves the grid line, +20 % in the mode II J at 2 mm).
//! * Damping: for the DCB's self-equilibrated loads κ = 5 ms⁻¹ on the grid to 3 ms; for
//!   the loads with a net force κ = 5 ms⁻¹ acting on the particle velocities too, to 4 ms
//!   (see [`ARMS`], [`WHOLE_BEAM`]: with the paper's grid damping alone, κ = 1 ms⁻¹ and
//!   12 ms, the grid-invisible particle velocities never decay and the crack surfaces
//!   keep drifting). The static reference does not depend on κ (the damping force
//!   vanishes at rest); each test checks that K has stopped changing.
//! * K_I/K_II of the mode II and mixed beams from the crack-opening displacements fitted
//!   1.5–8 cells behind the tip (`cod = "fit"`; [`CodMethod`]): the paper's next-to-tip
//!   value (the default) misplaces the mixed-mode split by 8–18 % (last test).
//! * CI resolution 2 mm cells, 2×2 particles per cell (the paper: "the mode I results
//!   converged for 2 × 2 mm cells, while the mode II results required smaller 1 × 1 mm
//!   cells"). The J contour is the paper's 2×2 for the DCB; for the two mode II cases it
//!   is 3×3: at 2 mm the 2×2 contour passes 4 mm from the tip, where the sliding field
//!   is resolved by two cells, and gives J 4–5 % below the larger contours, which agree
//!   with each other (measured; printed by the tests). The 1 mm runs with 2×2 contours
//!   are in the full verification suite.

use cramp::fracture::jintegral::{CodMethod, TipEnd, TipResult};
use cramp::output::{run_scene, RunOptions, RunResult};
use cramp::verify::cases::fracture::{a_of, beam, k_dcb, k_enf, split_beam, split_contour, Settle, ARMS, E_BEAM as E, WHOLE_BEAM};

fn run(h: f64, p_top: f64, p_bottom: f64, contact: &str, contour: usize, settle: Settle) -> RunResult {
    let scene = beam(h, p_top, p_bottom, contact, contour, settle).load().unwrap();
    run_scene(&scene, &RunOptions::default()).unwrap()
}

/// The static result: the last row of cracks.csv, after checking the run has settled
/// (K_I and K_II change by less than 0.2 % of |K| over the last 0.5 ms).
fn settled(r: &RunResult) -> TipResult {
    let n = r.tips.len();
    assert!(n >= 2, "cracks.csv rows: {n}");
    let (a, b) = (&r.tips[n - 2], &r.tips[n - 1]);
    let k = b.k1.hypot(b.k2);
    assert!((a.k1 - b.k1).abs() < 2e-3 * k && (a.k2 - b.k2).abs() < 2e-3 * k, "not settled: {a:?} → {b:?}");
    *b
}

/// J on the n×n contours, for the path-independence statement.
fn contours(r: &RunResult) -> Vec<f64> {
    (2..=4).map(|n| r.sim.tip_fracture(0, TipEnd::End, n, false, CodMethod::NextToTip, 0.0).unwrap().j1).collect()
}

#[test]
fn dcb_mode_i_k_matches_corrected_beam_theory_at_2mm() {
    let h = 2.0;
    let r = run(h, 1.0, -1.0, "none", 2, ARMS);
    let t = settled(&r);
    let k_ref = k_dcb(1.0, a_of(h));
    let err = (t.k1 - k_ref) / k_ref;
    let js = contours(&r);
    println!("DCB h = {h}: K_I = {:.4} vs {k_ref:.4} ({:+.2} %), K_II = {:.2e}, J(2×2, 3×3, 4×4) = {js:?}, √(E J) = {:.4}, wall {:.1} s", t.k1, 100.0 * err, t.k2, (E * t.j1).sqrt(), r.summary.wall_time_s);
    // 2 %: the and the paper's accuracy for converged mode I (beam theory itself,
    // through χ, is uncertain by ~0.7 %).
    assert!(err.abs() <= 0.02, "K_I error {err}");
    assert!(t.k2.abs() <= 0.01 * t.k1, "K_II {}", t.k2);
    // Static J is path independent: contours 2–4 cells agree within 0.5 %.
    for j in &js {
        assert!(((j - js[0]) / js[0]).abs() <= 5e-3, "J on the contours {js:?}");
    }
}

/// Equal-shear split beam ("ENF" of 004): K_II against eq. 24, K_I vanishing.
#[test]
fn split_beam_mode_ii_k_matches_beam_theory_at_2mm() {
    let h = 2.0;
    let r = split_beam(h, 1.0, 1.0).unwrap();
    let t = r.tip;
    let k_ref = k_enf(1.0, a_of(h));
    let err = (t.k2.abs() - k_ref) / k_ref;
    println!("ENF h = {h}: K_II = {:.4} vs {k_ref:.4} ({:+.2} %), K_I = {:.4}, settled to {:.1e}, wall {:.1} s", t.k2, 100.0 * err, t.k1, r.settled, r.wall);
    assert!(r.settled <= 2e-3, "not settled: K moved by {} of |K| in the last 0.5 ms", r.settled);
    // 3 %: the tolerance; beam theory with the shear correction is good to 1–3 %
    // for a/h ≈ 4 (references §1(b)).
    assert!(err.abs() <= 0.03, "K_II error {err}");
    // K_I vanishes by antisymmetry; the residual is a normal offset of the tracked
    // surfaces once the crack rises off the grid line with the arms: |K_I| ≤ 10 % of
    // |K_II| ("small"; measured 4.6 %).
    assert!(t.k1.abs() <= 0.1 * t.k2.abs(), "K_I {} should vanish by antisymmetry", t.k1);
}

/// Mixed mode, P_T = P, P_B = 0 = ½(P, −P) + ½(P, P): K_I and K_II are half the DCB's and
/// half the ENF's beam-theory values.
#[test]
fn mixed_mode_k_is_the_superposition_of_modes_i_and_ii_at_2mm() {
    let h = 2.0;
    let r = split_beam(h, 1.0, 0.0).unwrap();
    let t = r.tip;
    let (k1_ref, k2_ref) = (0.5 * k_dcb(1.0, a_of(h)), 0.5 * k_enf(1.0, a_of(h)));
    let (e1, e2) = ((t.k1 - k1_ref) / k1_ref, (t.k2.abs() - k2_ref) / k2_ref);
    println!("mixed h = {h}: K_I = {:.4} vs {k1_ref:.4} ({:+.2} %), K_II = {:.4} vs {k2_ref:.4} ({:+.2} %), settled to {:.1e}, wall {:.1} s", t.k1, 100.0 * e1, t.k2, 100.0 * e2, r.settled, r.wall);
    assert!(r.settled <= 2e-3, "not settled: K moved by {} of |K| in the last 0.5 ms", r.settled);
    assert!(e1.abs() <= 0.03 && e2.abs() <= 0.03, "K_I error {e1}, K_II error {e2}");
}

/// The paper's next-to-tip COD on the same mixed beam: J is the same, the split is not
/// (the surfaces within a cell of the tip do not superpose) — why the fit is the default.
#[test]
fn next_to_tip_cod_misplaces_the_mixed_mode_split_that_the_fit_gets() {
    let h = 2.0;
    // The default COD is the paper's next-to-tip value.
    let scene = beam(h, 1.0, 0.0, "none", split_contour(h), WHOLE_BEAM).load().unwrap();
    let r = run_scene(&scene, &RunOptions::default()).unwrap();
    let t = r.tips.last().unwrap();
    let k2_ref = 0.5 * k_enf(1.0, a_of(h));
    let e2 = (t.k2.abs() - k2_ref) / k2_ref;
    println!("mixed h = {h}, next-to-tip COD: K_I = {:.4}, K_II = {:.4} ({:+.2} %)", t.k1, t.k2, 100.0 * e2);
    assert!(e2 < -0.1, "the next-to-tip split was measured 18 % low in K_II; now {e2}");
}
