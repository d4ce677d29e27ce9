//! Colliding cracked disks (Nairn 2003 §3.2, Fig. 3): `verification/cracked_disks.toml`,
//! run to 45 ms in checked mode. Disks 30 mm across, 1 mm thick, central 10 mm cracks —
//! horizontal in the LEFT disk, vertical in the RIGHT disk (the paper's §3.2) — E = 0.1 MPa,
//! ν = 0.33, ρ = 1.5 g/cm³, each moving at 1 mm/ms toward the other, frictionless crack
//! faces with the paper's V_sep = 0.9, V_contact = 1.1. Units mm, g, ms (MPa, N).
//! 1 mm cells, 2×2 particles per cell (5,656 particles, 778 steps), uGIMP, USAVG.
//!
//! References, assertions and why the tolerances are fair:
//!
//! * **Checked mode** (no particle crosses its crack, no node needs three fields, mass,
//!   partition of unity, per-step momentum): the run must complete without a CheckError.
//! * **Momentum** (conservation law: no loads, boundary conditions or damping; contact
//!   impulses are ±Δp pairs, eqs. 13 and 17): |P(t) − P(0)| ≤ 1e-12 Σ_p m_p |v_p|₁ at
//!   every step, the bound of tests/colliding_disks.rs (round-off of the exact sums and of
//!   the partition of unity). P(0) = 0 to the bit: the disks are mirror images.
//! * **The paper's stated result at Fig. 3b** (t = 20 ms, "soon after contact"; our disks
//!   meet at ≈ 14 ms and are most compressed at ≈ 19 ms): the diametral compression opens
//!   the horizontal crack (mode I) — its centre opening (above − below surface, 001
//!   eqs. 11–12) must exceed one cell, h = 1 mm, i.e. be resolved and "well above zero"
//!   — while contact keeps the vertical crack closed: |normal opening| ≤ 0.05 h at every
//!   crack particle at every step up to 20 ms. 0.05 h is the contact-detection resolution
//!   (next item) and is 2 % of what the faces do without contact (negative control).
//! * **No interpenetration of the vertical crack, whole run**: normal opening ≥ −δ_res at
//!   every crack particle and step. δ_res is the resolution of the volume criterion
//!   (eqs. 8–10), computed in the test: with the faces closed and the material next to
//!   the crack at areal ratio J = (1+εxx)(1+εyy), an overlap δ raises the relative nodal
//!   volume to ≈ J(1 + δ/h), so contact is only guaranteed once J(1 + δ/h) ≥ V_sep;
//!   δ_res = h·max(0, V_sep/J_min − 1) with J_min the smallest J next to that crack over
//!   the run (measured 0.857 → 0.050 h). We also require δ_res ≤ 0.1 h so the check
//!   cannot become vacuous.
//! * **Negative control**: the same state at 13 ms (just before contact) continued with
//!   the vertical crack's contact switched off: checked mode must stop it with a crack
//!   crossing on that crack, and (continued unchecked to 20 ms) its faces must overlap
//!   by more than 0.5 mm (measured 2.51 mm, 50× δ_res): so it is contact that holds them.
//! * **Order of magnitude of the opening**: a quasi-static estimate from the measured
//!   peak contact force F (−dP_left/dt, smoothed over ±0.5 ms): the Brazilian-disk stress
//!   at the centre, normal to the loaded diameter, σ = 2F/(πDt), and the Griffith centre
//!   opening in plane stress, δ = 4σa/E (a = 5 mm). Measured peak opening / estimate must
//!   lie in [0.5, 2]: the estimate ignores dynamics (the load rises over ~5 ms, about one
//!   and a half wave transits of the disk; the dynamic amplification of an elastic system
//!   loaded from rest is between 1 and 2), the finite disk (a/R = 1/3 adds ~10 %) and the
//!   10 % strains; measured ratio 1.36 (peak force 0.340 N, estimate 1.44 mm, peak 1.97 mm).
//!
//! Findings printed for the report (not asserted: they depend on the grid and on V_sep):
//! the horizontal crack, when it recloses during the vibration after the impact, overlaps
//! by up to ≈ 0.12 mm (particle faces) because the material next to it is compressed to
//! J ≈ 0.78 < V_sep (δ_res ≈ 0.16 h there); with V_sep = 0.8 no overlap occurs but the
//! faces then stop ≈ 0.2 mm apart (contact detected too early) — the trade-off the paper
//! describes in §3.2. The surface points at and next to the crack tips move with the
//! fields of the nodes around the tip, which mix both faces, and drift (up to ~0.7 mm along
//! the crack); late in the run the horizontal crack's tip point shows a spurious overlap of
//! 0.64 mm where the particle faces overlap by at most 0.12 mm — a surface-tracking
//! artifact, not interpenetration. The vertical crack's points, tips included, all stay
//! within δ_res and are all checked. Kinetic + strain energy stays within 0.48 % of E(0)
//! (printed only: contact's equalisation of normal velocities is inelastic).
//!
//! The run and every measurement are the library case `cracked_disks`
//! (`src/verify/cases/cracks.rs`, which also draws the opening histories and particle
//! snapshots at 20 and 45 ms with the crack surfaces); the tolerances above are written
//! once, in `verification/cases.toml`. At 0.5 mm cells the checked run completes (it used
//! to stop, the crack particles in the wide-open horizontal crack lagging the material) but
//! the volume criterion's resolution bound is exceeded (see the manifest).
//!
//! Cost: ≈ 3 s release on the shared 2-core machine (the negative control ≈ 0.4 s).

mod common;

use cramp::verify::Variant;

#[test]
fn horizontal_crack_opens_on_impact_and_contact_keeps_the_vertical_crack_closed() {
    common::verify_case("cracked_disks", Variant::Quick);
}
