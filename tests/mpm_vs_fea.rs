//! MPM versus FEA on the double cantilever beam of Nairn 2003 §3.1 (Fig. 2): σxx along the
//! mid-plane from the damped MPM run and from the static FEA of the same scene
//! (`verification/dcb_nairn2003.toml`; issue 5, verification 4).
//!
//! Scene: 100 × 36 × 1 mm, crack 50 mm from the loaded end on the mid-plane, E = 0.1 MPa,
//! ν = 0.33, ρ = 1.5 g/cm³, plane stress, 0.4 mN per arm, free body. 2 mm cells, 2 × 2
//! particles per cell, linear shape functions, USAVG; damping κ = 0.08 /ms ≈ 2ω₁
//! (critical; ω₁ = 0.0399 /ms from the Rayleigh quotient of the static deflection) and
//! 240 ms ≈ 9.4/ω₁, by which the transient has decayed to ~1e-3 of the static response
//! (the paper gives none of these three; see the scene file). 2076 steps, ~4 s release
//! on the shared 2-core machine.
//!
//! Compared at every grid node on the mid-plane y = 0 in the body (x = 0, 2, …, 100): on
//! the crack faces the upper face (MPM field of the particles above, FEA node copy of
//! the elements above), in the ligament the single field/node. The crack-tip node x = 50
//! (first unsplit node; singular) is reported but excluded.
//!
//! MPM value: particle stresses extrapolated to the node by Guo & Nairn 2004 eq. 11 (the
//! mass-weighted shape-function average per velocity field, "the same methods used to
//! extrapolate momenta to the grid", Nairn 2003 §3.1). FEA value: the **same** extrapolation
//! applied to the FEA stress field — σ_FEA evaluated at the initial positions of exactly
//! the particles the MPM value averages, with the same weights m_p N_{i,p}. Both sides are
//! then the same linear functional of their stress fields, so the comparison tests the
//! solutions, not two different stress-recovery schemes.
//!
//! Criterion (issue 5): |σxx,MPM − σxx,FEA| ≤ 5 % of the peak |σxx| (of this FEA curve,
//! over the compared nodes, crack tip included — the curve's peak is at the tip, as in
//! Fig. 2) at every node except the crack-tip node. The 5 % is the issue's; it covers the two
//! discretisations' differences (MPM particles at ±h/4 vs Gauss points at ±h/(2√3) and
//! the residual transient). Measured: 1.05 % (at x = 8).
//!
//! Negative control: the same MPM run against the FEA of the specimen with the crack one
//! cell (2 mm) shorter must exceed the 5 %.
//!
//! Also asserted: the MPM has reached the static state — its strain energy within 1 % of
//! the FEA's ½ fᵀu (measured +0.14 %; the discrete stiffnesses differ slightly, the
//! residual transient is ~0.1 %).
//!
//! Reported, not asserted: the FEA's own nodal-averaged stress (Gauss values extrapolated
//! to the corners and averaged, Cook et al. 2002). Against it the MPM eq.-11 values differ
//! by up to 11.7 % of the peak at the first ligament node ahead of the tip (x = 52) and
//! 4.8 % at x = 54, and are ~8 % low along the crack faces (3.4 % of the peak). The cause
//! is the recovery, not the solution: eq. 11 averages the particles within one cell of
//! the node, which smooths the r^(−1/2) field next to the tip (at x = 52 it is 16 % below
//! a 0.25 mm FEA, while the 2 mm nodal average is within 1 %) and, on a free face, gives
//! the stress at the particles' mass-weighted mean depth 3h/8 = 0.75 mm inside the 18 mm
//! arm, where the bending stress is 1 − 0.75/9 = 92 % of the face value. The CSV and the plot (target/tmp/mpm_vs_fea/) carry
//! all three curves.
//!
//! The run, the comparison and the negative control are the library case `mpm_vs_fea`
//! (`src/verify/cases/fea.rs`; its full variant adds 1 mm cells: 0.93 % at x = 48, strain
//! energy −0.66 %, negative control 17.5 %); the tolerances are in
//! `verification/cases.toml`. This test runs the quick case and writes its report section
//! (plot and CSV) to target/tmp/mpm_vs_fea/.

mod common;

use cramp::fea::compare::DCB_NAIRN2003_SCENE;
use cramp::verify::Variant;

#[test]
fn damped_mpm_dcb_matches_static_fea_along_the_mid_plane() {
    // The embedded scene is the verification file, unchanged.
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("verification/dcb_nairn2003.toml");
    assert_eq!(std::fs::read_to_string(path).unwrap(), DCB_NAIRN2003_SCENE);
    common::verify_case("mpm_vs_fea", Variant::Quick);
}
