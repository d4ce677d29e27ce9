//! Coulomb friction on an inclined 3D crack face (issue 15, verification 4): case
//! `crack_friction_3d`, scene `verification/crack_friction_3d.toml`.
//!
//! The 3D twin of `crack_friction` (see its manifest entry for the error budget): a
//! cylindrical block on a wider cylindrical base across a crack plane whose normal
//! n = (−1, 2, −1)/√6 lies in no coordinate plane; the base is held, the block carries an
//! equal share per particle of the load F t − N n ramped over T_r = 10 ms (t the plane's direction of
//! steepest x). A rigid block on a Coulomb face moves along t with m dv/dt = (F − μN) λ(t)
//! (`cracks::friction_closed_form`), and does not move when F ≤ μN. Runs: sliding
//! (μ = 0.3, F = 2μN), frictionless (F = 0.6 N) and stuck (μ = 0.3, F = μN/2). The part
//! above is the block, body 0 (checked to lie above the plane), followed by id.

use super::cracks::{friction_closed_form, FrictionRun, FRICTION_END, FRICTION_RAMP};
use crate::dim::{Vector3, D3};
use crate::scene3d::{CrackSurface, Scene3, Solid};
use crate::verify::scene_file::SceneFile;
use crate::simulation::Simulation;
use crate::verify::{CaseOutput, Variant};
use anyhow::{ensure, Context};

/// Normal load (N) of the scene, and μ of its sliding run.
pub const NORMAL_LOAD: f64 = 0.008;
pub const MU: f64 = 0.3;

/// Unit normal of the crack plane ("above" is the block) and unit sliding direction.
pub fn plane_normal() -> Vector3 {
    Vector3::new(-1.0, 2.0, -1.0) / 6f64.sqrt()
}
pub fn sliding_direction() -> Vector3 {
    Vector3::new(5.0, 2.0, -1.0) / 30f64.sqrt()
}

/// The crack plane −x + 2y − z = c(h) = h/4 lies midway between particle layers for 2
/// particles per cell (−x + 2y − z is a multiple of h/2 at every particle); p0 = (0, c/2, 0)
/// is the centre of the block's face.
pub fn centre(h: f64) -> Vector3 {
    Vector3::new(0.0, h / 8.0, 0.0)
}

/// The scene file with cells of `h` mm, Coulomb coefficient `mu` and tangential force
/// `f`: `verification/crack_friction_3d.toml` (written for h = 1) with overrides placing
/// its geometry on the plane of [`centre`], so `cramp run` of the exported file reproduces
/// every run.
pub fn scene_file(h: f64, mu: f64, f: f64) -> SceneFile {
    let (n, t, p0) = (plane_normal(), sliding_direction(), centre(h));
    let v = |v: Vector3| format!("[{:?}, {:?}, {:?}]", v.x, v.y, v.z);
    SceneFile::new("crack_friction_3d.toml")
        .set("grid.cell", format!("[{h:?}, {h:?}, {h:?}]"))
        .set("bodies.0.shape.cylinder.from", v(p0))
        .set("bodies.0.shape.cylinder.to", v(p0 + n * 3.0))
        .set("bodies.1.shape.cylinder.from", v(p0 - n * 3.0))
        .set("bodies.1.shape.cylinder.to", v(p0))
        .set("boundary.0.nodes.plane.point", v(p0 + n * -11.5))
        .set("loads.0.particles.plane.point", v(p0 + n * 2.0))
        .set("loads.0.force", v(t * f - n * NORMAL_LOAD))
        .set("cracks.0.surface.disc.center", v(p0))
        .set("cracks.0.contact", if mu == 0.0 { "\"frictionless\"".to_string() } else { format!("{{ friction = {{ mu = {mu:?} }} }}") })
}

/// [`scene_file`], loaded and checked against the layout this case relies on.
pub fn scene(h: f64, mu: f64, f: f64) -> anyhow::Result<Scene3> {
    let s = scene_file(h, mu, f).load3()?;
    ensure!(s.loads.len() == 1 && s.cracks.len() == 1 && s.bodies.len() == 2 && s.boundary.len() == 1, "unexpected scene layout");
    ensure!(s.loads[0].ramp == FRICTION_RAMP && s.solver.end_time == FRICTION_END, "ramp and end time must be those of crack_friction");
    ensure!(matches!(s.bodies[0].shape, Solid::Cylinder { .. }) && matches!(s.cracks[0].surface, CrackSurface::Disc { .. }), "the bodies must be cylinders and the crack a disc");
    Ok(s)
}

/// The particle ids of the block (body 0), checked to lie above the crack plane and the
/// base's below, and the block's mass.
fn part_above(s: &Simulation<D3>, c: f64) -> anyhow::Result<(Vec<bool>, f64)> {
    let p = &s.particles;
    let n = Vector3::new(-1.0, 2.0, -1.0);
    let mut above = vec![false; p.len()];
    for i in 0..p.len() {
        let d = p.x[i].dot(&n) - c;
        ensure!((d > 0.0) == (p.body[i] == 0) && d.abs() > 1e-9, "particle {i} at signed distance {d} is on the wrong side of the crack");
        above[p.id[i] as usize] = p.body[i] == 0;
    }
    let m = crate::exact::sum_iter((0..p.len()).filter(|&i| above[p.id[i] as usize]).map(|i| p.mass[i]));
    Ok((above, m))
}

/// Momentum and mass-weighted position of the part above (exact sums).
fn momentum_above(s: &Simulation<D3>, above: &[bool]) -> (Vector3, Vector3) {
    let p = &s.particles;
    let sel: Vec<usize> = (0..p.len()).filter(|&i| above[p.id[i] as usize]).collect();
    let sum = |f: &dyn Fn(usize) -> Vector3| Vector3::from_fn(|c, _| crate::exact::sum_iter(sel.iter().map(|&i| f(i)[c])));
    (sum(&|i| p.v[i] * p.mass[i]), sum(&|i| p.x[i] * p.mass[i]))
}

/// One run: the part above's motion along t against the closed form.
pub fn run_block(h: f64, mu: f64, f: f64) -> anyhow::Result<FrictionRun> {
    let started = std::time::Instant::now();
    let mut sim = scene(h, mu, f)?.build()?;
    let (n, t) = (plane_normal(), sliding_direction());
    let (above, m) = part_above(&sim, h / 4.0)?;
    ensure!(above.iter().any(|&a| a), "no particle above the crack");
    // The crack point nearest the centre of the block's face.
    let centre = centre(h);
    let crack = &sim.cracks[0];
    let mid = (0..crack.surface.vertices.len())
        .min_by(|&i, &j| (crack.surface.vertices[i] - centre).norm().total_cmp(&(crack.surface.vertices[j] - centre).norm()))
        .context("the crack has no points")?;
    let (_, mx0) = momentum_above(&sim, &above);
    let a = (f - mu * NORMAL_LOAD) / m;
    let mut r = FrictionRun::new(mu, f, m, a);
    sim.run_until(FRICTION_END, |s| {
        let (p, mx) = momentum_above(s, &above);
        let (vt, vn) = (p.dot(&t) / m, p.dot(&n) / m);
        let dx = (mx - mx0).dot(&t) / m;
        let slip = s.cracks[0].opening(mid).dot(&t);
        r.max_vy = r.max_vy.max(vn.abs());
        r.max_slip = r.max_slip.max(slip.abs());
        r.max_dx = r.max_dx.max(((mx - mx0) / m).norm());
        if s.time >= FRICTION_RAMP && a > 0.0 {
            let (v_exact, _) = friction_closed_form(a, s.time);
            r.worst_v = r.worst_v.max((vt - v_exact).abs() / v_exact);
        }
        (r.t, r.slip, r.dx, r.v) = (s.time, slip, dx, vt);
        r.velocity.push((s.time, vt));
    })
    .map_err(|e| anyhow::anyhow!("μ = {mu}, F = {f}: {e}"))?;
    r.steps = sim.step_count;
    r.wall_s = started.elapsed().as_secs_f64();
    Ok(r)
}

/// Case `crack_friction_3d`: 1 mm cells, and 0.5 mm in the full suite.
pub fn run(variant: Variant) -> anyhow::Result<CaseOutput> {
    let hs: &[f64] = match variant {
        Variant::Quick => &[1.0],
        Variant::Full => &[1.0, 0.5],
    };
    let mut out = CaseOutput::default();
    for &h in hs {
        let sliding = run_block(h, MU, 2.0 * MU * NORMAL_LOAD)?;
        let frictionless = run_block(h, 0.0, 0.6 * NORMAL_LOAD)?;
        let stick = run_block(h, MU, 0.5 * MU * NORMAL_LOAD)?;
        for (name, r) in [("sliding, μ = 0.3, F = 2μN", &sliding), ("frictionless, F = 0.6 N", &frictionless)] {
            let l = format!("h = {h} mm, {name}");
            let (v_exact, x_exact) = friction_closed_form(r.a, r.t);
            out.measure("velocity", &l, r.worst_v, 0.0);
            out.measure("displacement", &l, r.dx, x_exact);
            out.measure("slip", &l, r.slip, x_exact);
            out.note(format!(
                "{l}: {} steps, {:.2} s; v̄·t(t_end) = {:.6} mm/ms vs {v_exact:.6}; max |P·n|/m {:.2e} mm/ms",
                r.steps, r.wall_s, r.v, r.max_vy
            ));
        }
        let (_, x_free) = friction_closed_form(stick.f / stick.m, stick.t);
        let l = format!("h = {h} mm, stick, μ = 0.3, F = μN/2");
        out.measure("stick_slip", &l, stick.max_slip / x_free, 0.0);
        out.measure("stick_motion", &l, stick.max_dx / x_free, 0.0);
        out.note(format!(
            "{l}: max |slip| {:.3e} mm, max |x̄ − x̄0| {:.3e} mm, free-sliding distance {x_free:.4} mm; final v̄·t {:+.2e} mm/ms; {} steps, {:.2} s",
            stick.max_slip, stick.max_dx, stick.v, stick.steps, stick.wall_s
        ));
    }
    Ok(out)
}
