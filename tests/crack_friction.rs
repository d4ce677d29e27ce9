//! Coulomb friction on crack faces (Nairn 2003 §2.2, eqs. 14–19) against the closed form
//! of a block sliding on a fixed base.
//!
//! Scene (units mm, g, ms; E = 0.1 MPa, ν = 0.33, ρ = 1.5 g/cm³, plane stress, 1 mm cells,
//! 2×2 particles per cell, uGIMP, USAVG): a top block [0, 20] × [0, 4] rests on a bottom
//! block [−8, 28] × [−4, 0]; the interface y = 0 is a crack running through both ends
//! (x from −9.5 to 29.5, beyond both blocks), with `contact = { friction = { mu } }`. The
//! bottom block is held by its lowest node rows (y ≤ −3, vx = vy = 0), which no particle of
//! the top block ever touches. One load acts on every particle of the top block,
//! total force (F, −N)·λ(t), λ = min(t/T_r, 1), T_r = 10 ms: spread uniformly like a body
//! force, so it launches no stress wave from a loaded edge, and ramped so the normal load
//! is quasi-static (the block's vertical period, ≈ 4H/c ≈ 2 ms, is 1/5 of T_r).
//!
//! Closed form. Top block of mass m (the discrete Σ m_p). Quasi-statically the interface
//! carries the normal force Nλ(t), so Coulomb friction is at most μNλ(t).
//! * F > μN: Fλ > μNλ for every t > 0, so the block slides from the start and never
//!   sticks; m dv/dt = (F − μN)λ(t), a = (F − μN)/m:
//!   v(t) = a t²/(2T_r) for t ≤ T_r, a (t − T_r/2) after;
//!   x(t) = a t³/(6T_r) for t ≤ T_r, a (T_r²/6 + t (t − T_r)/2) after.
//! * F ≤ μN: static friction holds; no relative sliding at all (slip = 0).
//! * μ = 0 is the first case with a = F/m.
//!
//! Measured: v̄ = P_x/m of the top block's particles, its centre-of-mass displacement, and
//! the slip = tangential component of above − below of the tracked crack surfaces
//! (`Crack::opening_nt`) at the crack particle under the block's middle.
//!
//! Tolerance 2 % (relative), for every step with t ≥ T_r (before that v is small and
//! starts from 0). Error budget, each measured: (i) the vertical vibration that the ramp's
//! kink at t = 0 excites: the normal force is Nλ − m dv_y/dt, which shifts v by μ P_y/m
//! (|P_y|/m ≤ 5e-3 mm/ms, ≤ 1.2 % of v at t = T_r, less later); (ii) the load is applied
//! at the start of each step (a left Riemann sum of the ramp: relative error ≤ Δt/t ≈
//! 0.6 %); (iii) nodes where the local Coulomb test sticks (≈ 5 % of the contact events,
//! tiny-mass fields at the block's ends and on the node rows y = ±1 that uGIMP reaches
//! through the interface) and the slight tilt of the moving crack: together P_x + μP_y
//! deviates from ∫(F − μN) dt by 0.36 %. The centre-of-mass displacement also contains
//! the blocks' elastic shear (≈ 0.01 mm). Measured (t ≥ T_r): sliding, worst velocity error
//! 0.34 %, displacement +0.68 %, slip +0.14 % at 20 ms; frictionless, worst velocity error
//! 0.53 %; stick, slip 2.6e-5 and centre-of-mass motion 0.74 % of the free-sliding distance.
//! (0.5 mm cells, the case's full variant: 0.34 %, +0.47 %, −0.18 %; 0.27 %; 7.6e-6, 0.69 %.)
//! For the stick case the scale is the motion the same F would give without friction,
//! x_free = (F/m)(T_r²/6 + t(t − T_r)/2): slip and centre-of-mass displacement must stay
//! below 2 % of it (the elastic shear of the blocks under the friction traction moves
//! the centre of mass by ≈ 0.01 mm ≈ 0.7 % of x_free; slip is not elastic and stays ~0).
//!
//! The slip is read at the crack particle under the middle of the block, x = 9.5 mm (since
//! cracks are discretised to h/2 the index of that particle is looked up; a fixed index
//! read x = 0, the block's left end, before: slip +0.31 %, stick 2.0e-3).
//!
//! The runs and measurements are the library case `crack_friction`
//! (`src/verify/cases/cracks.rs`); the 2 % tolerances are in `verification/cases.toml`.
//! Cost: three runs of 346 steps, 896 particles: ≈ 0.5 s each (release, loaded machine).

mod common;

use cramp::verify::Variant;

#[test]
fn block_on_a_crack_face_slides_and_sticks_as_coulomb_friction_says() {
    common::verify_case("crack_friction", Variant::Quick);
}
