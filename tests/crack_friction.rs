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
//! 0.27 %, displacement +0.62 %, slip +0.08 % at 20 ms; frictionless, worst velocity error
//! 0.56 %; stick, slip 2.6e-5 and centre-of-mass motion 0.74 % of the free-sliding distance.
//! For the stick case the scale is the motion the same F would give without friction,
//! x_free = (F/m)(T_r²/6 + t(t − T_r)/2): slip and centre-of-mass displacement must stay
//! below 2 % of it (the elastic shear of the blocks under the friction traction moves
//! the centre of mass by ≈ 0.01 mm ≈ 0.7 % of x_free; slip is not elastic and stays ~0).
//!
//! Cost: three runs of ≈ 350 steps, 896 particles: ≈ 2 s each (release, loaded machine).

mod common;

use cramp::scene::Scene;
use cramp::simulation::Simulation;

const N: f64 = 0.01; // normal load, N
const RAMP: f64 = 10.0; // ms
const END: f64 = 20.0; // ms
const MID_POINT: usize = 19; // crack particle at x = 9.5, under the middle of the block

fn scene(mu: f64, f: f64) -> Scene {
    let text = common::block_on_crack([f, -N], RAMP, END, &format!("{{ friction = {{ mu = {mu} }} }}"));
    Scene::from_toml(&text, "crack friction").unwrap()
}

/// Mass, momentum and centre of mass of the top block (body 0).
fn top_block(s: &Simulation) -> (f64, f64, f64, f64) {
    let p = &s.particles;
    let top: Vec<usize> = (0..p.len()).filter(|&i| p.body[i] == 0).collect();
    let m = cramp::exact::sum_iter(top.iter().map(|&i| p.mass[i]));
    let px = cramp::exact::sum_iter(top.iter().map(|&i| p.mass[i] * p.v[i].x));
    let py = cramp::exact::sum_iter(top.iter().map(|&i| p.mass[i] * p.v[i].y));
    let mx = cramp::exact::sum_iter(top.iter().map(|&i| p.mass[i] * p.x[i].x));
    (m, px, py, mx / m)
}

/// Closed-form velocity and displacement for acceleration `a` under the ramp.
fn closed_form(a: f64, t: f64) -> (f64, f64) {
    if t <= RAMP {
        (a * t * t / (2.0 * RAMP), a * t * t * t / (6.0 * RAMP))
    } else {
        (a * (t - RAMP / 2.0), a * (RAMP * RAMP / 6.0 + t * (t - RAMP) / 2.0))
    }
}

struct Run {
    m: f64,
    /// Worst |v̄ − v_exact| / v_exact over the steps with t ≥ T_r (sliding cases).
    worst_v: f64,
    /// Largest |P_y|/m of the top block.
    max_vy: f64,
    /// Largest |slip| at the middle crack particle.
    max_slip: f64,
    /// Largest |centre-of-mass displacement| of the top block.
    max_dx: f64,
    /// Final time, slip, centre-of-mass displacement and v̄.
    t: f64,
    slip: f64,
    dx: f64,
    v: f64,
}

fn run(mu: f64, f: f64) -> Run {
    let started = std::time::Instant::now();
    let mut sim = scene(mu, f).build().unwrap();
    let (m, _, _, x0) = top_block(&sim);
    let a = (f - mu * N) / m;
    let mut r = Run { m, worst_v: 0.0, max_vy: 0.0, max_slip: 0.0, max_dx: 0.0, t: 0.0, slip: 0.0, dx: 0.0, v: 0.0 };
    sim.run_until(END, |s| {
        let (_, px, py, xc) = top_block(s);
        let slip = s.cracks[0].opening_nt(MID_POINT).1;
        r.max_vy = r.max_vy.max(py.abs() / m);
        r.max_slip = r.max_slip.max(slip.abs());
        r.max_dx = r.max_dx.max((xc - x0).abs());
        if s.time >= RAMP && a > 0.0 {
            let (v_exact, _) = closed_form(a, s.time);
            r.worst_v = r.worst_v.max((px / m - v_exact).abs() / v_exact);
        }
        (r.t, r.slip, r.dx, r.v) = (s.time, slip, xc - x0, px / m);
    })
    .unwrap_or_else(|e| panic!("μ = {mu}, F = {f}: {e}"));
    println!(
        "μ = {mu}, F = {f} N, N = {N} N, m = {m:.6} g: {} steps in {:.2} s",
        sim.step_count,
        started.elapsed().as_secs_f64()
    );
    r
}

#[test]
fn block_sliding_on_a_crack_face_follows_f_minus_mu_n_over_m() {
    let mu = 0.3;
    let f = 2.0 * mu * N;
    let r = run(mu, f);
    let a = (f - mu * N) / r.m;
    let (v_exact, x_exact) = closed_form(a, r.t);
    println!(
        "sliding: v̄(t_end) = {:.6} vs {v_exact:.6} mm/ms; worst |Δv|/v for t ≥ T_r {:.3e}; x̄ = {:.5} vs {x_exact:.5} mm ({:+.3e}); slip {:.5} mm ({:+.3e}); max |P_y|/m {:.2e}",
        r.v,
        r.worst_v,
        r.dx,
        (r.dx - x_exact) / x_exact,
        r.slip,
        (r.slip - x_exact) / x_exact,
        r.max_vy
    );
    assert!(r.worst_v <= 0.02, "velocity off the closed form by {:.3} %", 100.0 * r.worst_v);
    assert!(((r.dx - x_exact) / x_exact).abs() <= 0.02, "displacement {} vs {x_exact}", r.dx);
    assert!(((r.slip - x_exact) / x_exact).abs() <= 0.02, "slip {} vs {x_exact}", r.slip);
}

#[test]
fn frictionless_crack_face_slides_at_f_over_m() {
    let f = 0.6 * N;
    let r = run(0.0, f);
    let (v_exact, x_exact) = closed_form(f / r.m, r.t);
    println!(
        "frictionless: v̄(t_end) = {:.6} vs {v_exact:.6} mm/ms; worst |Δv|/v for t ≥ T_r {:.3e}; x̄ = {:.5} vs {x_exact:.5} mm; slip {:.5} mm",
        r.v, r.worst_v, r.dx, r.slip
    );
    assert!(r.worst_v <= 0.02, "velocity off the closed form by {:.3} %", 100.0 * r.worst_v);
    assert!(((r.dx - x_exact) / x_exact).abs() <= 0.02, "displacement {} vs {x_exact}", r.dx);
    assert!(((r.slip - x_exact) / x_exact).abs() <= 0.02, "slip {} vs {x_exact}", r.slip);
}

#[test]
fn block_sticks_on_a_crack_face_when_f_is_below_mu_n() {
    let mu = 0.3;
    let f = 0.5 * mu * N;
    let r = run(mu, f);
    let (_, x_free) = closed_form(f / r.m, r.t);
    println!(
        "stick: max |slip| {:.3e} mm, max |x̄ − x̄0| {:.3e} mm, free-sliding distance {x_free:.4} mm: ratios {:.2e}, {:.2e}; final v̄ {:+.2e} mm/ms",
        r.max_slip,
        r.max_dx,
        r.max_slip / x_free,
        r.max_dx / x_free,
        r.v
    );
    assert!(r.max_slip <= 0.02 * x_free, "the block slid: slip {} mm", r.max_slip);
    assert!(r.max_dx <= 0.02 * x_free, "the block moved: {} mm", r.max_dx);
}
