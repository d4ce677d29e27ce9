//! 3D crack growth (issue 17; [`crate::fracture::growth3`]) against independent references.
//! `tests/growth3.rs` calls these functions.
//!
//! * `front_growth_slab` (issue 17 verification item 2): the SENT plate of `front_j_slab`
//!   (W = 20 mm, a = 6 mm, plane strain, ramped damped end traction 1 MPa, h = 2 mm) with
//!   K_Ic = 6 MPa√mm (maximum hoop stress) and increments of half a cell, grown in 2D
//!   (`front_growth_2d.toml`) and extruded over two cells in z with rollers on both z faces
//!   (`front_growth_3d.toml`). Reference: the 2D run, whose tip uses the same J (the 3D
//!   front contour on the 2D nodal values, `fracture.circle`), the same speed estimate, the
//!   same split (the 3D one reduces to 2D's with no mode III) and the same criterion code.
//!   The extruded run reproduces the 2D fields to round-off (`front_j_slab`,
//!   `cracks_2d_3d`); the new triangles of each increment cover exactly the rectangle the
//!   2D segment sweeps, so every front node must advance at the steps the 2D tip does, by
//!   the same increments.
//!
//! Status (measured, h = 2 mm, 2 shared cores): 14 increments at the same 14 checks in 2D
//! and at all 5 front nodes, advance equal within 8.9e−16 increments, J₁ at the growth
//! events within one ulp, the front straight to the bit; the crack reaches the far edge at
//! 0.33 ms and every node stops there at the same check as the 2D tip. 3D run 3,200
//! particles × 464 steps, about 12 s alone.
//! * `front_growth_penny` (full suite; issue 17 verification item 1): the penny of
//!   `front_j_penny` (a/h = 5) with K_Ic = 3 MPa√mm and max_speed 40 mm/ms. Measured:
//!   planar to the bit, 349 node moves from 0.2215 ms to the cylinder's surface. The
//!   radius spread while the whole front grows is checked as a staircase of at most one
//!   whole increment between move counts (measured 1) plus a shape, radius less own
//!   advance, within the elastic displacement σr/E = 0.02 increments (measured 0.0061);
//!   the raw spread, 1.0028 increments, is reported (one whole increment whenever nodes
//!   move out of phase, so any drift exceeds a bound of exactly one; it was 1.16 before
//!   the growth frame fix and 1.0148 before the disc mesh fix; cases.toml).
//!   12,640 particles × 696 steps, 38–85 s on 2 shared cores.
//! * `front_growth_ellipse` (full; item 5): an elliptical crack b/a = 0.625 starts at the
//!   minor-axis ends and its aspect ratio rises (Irwin's K; cases.toml).
//! * `front_growth_inclined` (full; item 3): the inclined penny of `front_j_inclined` (γ = 45°)
//!   with K_Ic = 2.5 MPa√mm: the first increments of the two mirror-plane nodes (pure I + II)
//!   against the maximum hoop stress angle from Kassir & Sih's K's (−55.475°), the angle from the
//!   node's own K's, the growth frame there, the onset time on the ramp and the turn of the new
//!   surface toward the plane normal to the load (cases.toml). Measured: −56.90°, +56.48°; the
//!   other nodes' first increments 56.0–58.5° from the plane (with the growth frame's normal
//!   leaving out a leading neighbour's triangles; 56–67° before); the surface near the mirror
//!   plane tilts −15° (past the load-normal plane: later increments zigzag ±10–25°, reading the
//!   opening across the node's own kink). 200,960 particles × 348 steps, 3–5 min.
//! * `dcb_growth_3d` (full; item 4): the DCB of `dcb_growth`, 4 mm wide with free faces,
//!   restarts against corrected beam theory with the 3D front's plane-strain G_c.

use crate::fracture::growth3::NodeRecord;
use crate::report::plot::{PlotSpec, Series};
use crate::verify::scene_file::SceneFile;
use crate::verify::{CaseOutput, Plot, Variant};
use std::collections::BTreeMap;
use std::time::Instant;

/// What one slab growth comparison measured.
#[derive(Clone, Debug)]
pub struct SlabGrowth {
    /// 2D growth rows: (step, time, advance after the check, J₁, K_I, grew).
    pub rows_2d: Vec<(u64, f64, f64, f64, f64, bool)>,
    /// 3D growth rows.
    pub rows_3d: Vec<NodeRecord>,
    pub seconds_2d: f64,
    pub seconds_3d: f64,
    pub particles_3d: usize,
    pub steps: u64,
    /// Crack-surface triangles and vertices at the end.
    pub triangles: usize,
    pub vertices: usize,
    pub front_edges: usize,
}

/// Run the 2D and the extruded growth scenes (with overrides, e.g. the end time).
pub fn slab_growth(overrides: &[(&str, &str)]) -> anyhow::Result<SlabGrowth> {
    let mut f2 = SceneFile::new("front_growth_2d.toml");
    let mut f3 = SceneFile::new("front_growth_3d.toml");
    for (k, v) in overrides {
        f2 = f2.set(k, v);
        f3 = f3.set(k, v);
    }
    let (s2, s3) = (f2.load()?, f3.load3()?);
    let t = Instant::now();
    let mut a = s2.build()?;
    a.run_until(s2.solver.end_time, |_| {})?;
    let seconds_2d = t.elapsed().as_secs_f64();
    let g = a.growth.as_ref().ok_or_else(|| anyhow::anyhow!("the 2D scene does not grow"))?;
    let initial = g.cracks[0].initial_length;
    let rows_2d = g.records.iter().map(|r| (r.step, r.fracture.time, r.length - initial, r.fracture.j1, r.fracture.k1, r.grew)).collect();
    let t = Instant::now();
    let mut b = s3.build()?;
    b.run_until(s3.solver.end_time, |_| {})?;
    let seconds_3d = t.elapsed().as_secs_f64();
    let g3 = b.growth.as_ref().ok_or_else(|| anyhow::anyhow!("the 3D scene does not grow"))?;
    Ok(SlabGrowth {
        rows_2d,
        rows_3d: g3.records.clone(),
        seconds_2d,
        seconds_3d,
        particles_3d: b.particles.len(),
        steps: b.step_count,
        triangles: b.cracks[0].surface.triangles.len(),
        vertices: b.cracks[0].surface.vertices.len(),
        front_edges: b.cracks[0].front.len(),
    })
}

/// The comparison's figures.
#[derive(Clone, Debug, Default)]
pub struct SlabComparison {
    /// Checks in 2D and the 3D checks that have a 2D check at the same step.
    pub checks: usize,
    /// Increments of the 2D tip.
    pub increments: usize,
    /// Largest |advance(3D node) − advance(2D tip)| after any check, in increments.
    pub advance_diff: f64,
    /// Checks at which some node grew and the 2D tip did not, or the reverse.
    pub event_mismatches: usize,
    /// Largest |J₁(3D node)/J₁(2D) − 1| at the 3D growth events.
    pub j_diff: f64,
    /// Largest |K_I(3D node)/K_I(2D) − 1| at the 3D growth events.
    pub k_diff: f64,
    /// Largest spread of the front nodes' x after any check (the front straight).
    pub front_spread: f64,
    /// Largest max(|K_II|, |K_III|)/K_I at any 3D row.
    pub mixed: f64,
    pub nodes: usize,
}

/// Compare the 3D rows with the 2D rows step by step (`da` the increment length).
pub fn compare(r: &SlabGrowth, da: f64) -> SlabComparison {
    let by_step: BTreeMap<u64, &(u64, f64, f64, f64, f64, bool)> = r.rows_2d.iter().map(|row| (row.0, row)).collect();
    let mut out = SlabComparison { increments: r.rows_2d.iter().filter(|x| x.5).count(), ..Default::default() };
    let mut steps: BTreeMap<u64, Vec<&NodeRecord>> = BTreeMap::new();
    for row in &r.rows_3d {
        steps.entry(row.step).or_default().push(row);
    }
    out.nodes = r.rows_3d.iter().map(|x| x.label).max().map_or(0, |m| m as usize + 1);
    for (step, rows) in &steps {
        let Some(two) = by_step.get(step) else { continue };
        out.checks += 1;
        let grew3 = rows.iter().any(|x| x.grew);
        if grew3 != two.5 || rows.iter().any(|x| x.grew != two.5) {
            out.event_mismatches += 1;
        }
        for x in rows {
            out.advance_diff = out.advance_diff.max((x.advance - two.2).abs() / da);
            if x.grew {
                out.j_diff = out.j_diff.max((x.j1 / two.3 - 1.0).abs());
                out.k_diff = out.k_diff.max((x.k[0] / two.4 - 1.0).abs());
            }
            if x.k[0] > 0.0 {
                out.mixed = out.mixed.max(x.k[1].abs().max(x.k[2].abs()) / x.k[0]);
            }
        }
        let (lo, hi) = rows.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), x| (l.min(x.x.x), h.max(x.x.x)));
        out.front_spread = out.front_spread.max(hi - lo);
    }
    out
}

/// Case `front_growth_slab`.
pub fn run_slab(_variant: Variant) -> anyhow::Result<CaseOutput> {
    let r = slab_growth(&[])?;
    let da = 1.0;
    let c = compare(&r, da);
    let mut out = CaseOutput::default();
    out.measure("advance_vs_2d", "h = 2 mm", c.advance_diff, 0.0);
    out.measure("j_at_growth_vs_2d", "h = 2 mm", c.j_diff, 0.0);
    out.measure("events_vs_2d", "h = 2 mm", c.event_mismatches as f64, 0.0);
    out.measure("front_straight", "h = 2 mm", c.front_spread, 0.0);
    out.measure("increments", "h = 2 mm", c.increments as f64, 0.0);
    out.note(format!(
        "{} growth checks compared ({} front nodes); the 2D tip made {} increments of {da} mm. Largest |a₃D − a₂D| = {:.3e} increments, \
         growth events at different steps: {}, largest |J₁/J₁,2D − 1| at 3D growth events {:.2e}, |K_I/K_I,2D − 1| {:.2e}, \
         front spread in x {:.2e} mm, max(|K_II|, |K_III|)/K_I = {:.2e}. End: {} crack triangles, {} crack particles, {} front edges. \
         Runs: 2D {:.1} s, 3D {} particles × {} steps {:.1} s.",
        c.checks,
        c.nodes,
        c.increments,
        c.advance_diff,
        c.event_mismatches,
        c.j_diff,
        c.k_diff,
        c.front_spread,
        c.mixed,
        r.triangles,
        r.vertices,
        r.front_edges,
        r.seconds_2d,
        r.particles_3d,
        r.steps,
        r.seconds_3d
    ));
    // The 2D tip's x after each check against the 3D front nodes' x after each check.
    let series2: Vec<(f64, f64)> = r.rows_2d.iter().map(|x| (x.1, 6.0 + x.2)).collect();
    let mut series = vec![Series::reference("2D tip", series2)];
    let labels: std::collections::BTreeSet<u32> = r.rows_3d.iter().map(|x| x.label).collect();
    for l in labels {
        let pts: Vec<(f64, f64)> = r.rows_3d.iter().filter(|x| x.label == l).map(|x| (x.time, 6.0 + x.advance)).collect();
        series.push(Series::line(&format!("3D front node {l}"), pts));
    }
    out.figure(
        "front_growth_slab.png",
        "Crack tip position against time: the 2D tip (dashed) and every 3D front node (6 mm + its advance) after each growth check.",
        PlotSpec::new("Extruded SENT: crack growth in 2D and 3D", "time (ms)", "crack tip x (mm)"),
        Plot::Lines(series),
    );
    Ok(out)
}

/// Load a 3D verification scene with overrides, build it and run it to its end time
/// (unchecked if asked): the scene, the finished simulation and the wall time in seconds.
fn run_scene3(file: &str, overrides: &[(&str, &str)], unchecked: bool) -> anyhow::Result<(crate::scene3d::Scene3, crate::simulation::Simulation<crate::dim::D3>, f64)> {
    let mut f = SceneFile::new(file);
    for (k, v) in overrides {
        f = f.set(k, v);
    }
    let mut s = f.load3()?;
    if unchecked {
        s.solver.checked = false;
    }
    let t = Instant::now();
    let mut sim = s.build()?;
    sim.run_until(s.solver.end_time, |_| {})?;
    Ok((s, sim, t.elapsed().as_secs_f64()))
}

/// What the growing penny measured.
#[derive(Clone, Debug, Default)]
pub struct PennyGrowth {
    /// Largest |z| of any crack particle at the end (mm).
    pub z_max: f64,
    /// Largest spread (max − min) of the front nodes' distance from the axis at any check,
    /// nodes on the grid's symmetry planes included (mm).
    pub radius_spread: f64,
    /// Largest difference of two front nodes' move counts at a check while all grow.
    pub staircase: f64,
    /// Largest spread (mm) at a check while all grow of each node's radius less its own
    /// advance before the check: the front's shape apart from its whole increments.
    pub residual: f64,
    /// Per front node label: its advance at the end.
    pub advances: Vec<f64>,
    /// Radius range of the front at the end.
    pub r_min: f64,
    pub r_max: f64,
    pub increments: usize,
    pub first_growth: f64,
    pub front_edges: usize,
    pub splits: usize,
    pub seconds: f64,
    pub particles: usize,
    pub steps: u64,
}

/// The penny's growth increment (mm): half a cell of 2 mm (`front_penny_growth_3d.toml`).
pub const PENNY_INCREMENT: f64 = 1.0;

/// Run `front_penny_growth_3d.toml` (with overrides).
pub fn penny_growth(overrides: &[(&str, &str)]) -> anyhow::Result<PennyGrowth> {
    let (_, sim, seconds) = run_scene3("front_penny_growth_3d.toml", overrides, false)?;
    let g = sim.growth.as_ref().ok_or_else(|| anyhow::anyhow!("the penny does not grow"))?;
    let crack = &sim.cracks[0];
    let z_max = crack.surface.vertices.iter().map(|v| v.z.abs()).fold(0.0, f64::max);
    let mut by_step: BTreeMap<u64, Vec<&NodeRecord>> = BTreeMap::new();
    for r in &g.records {
        by_step.entry(r.step).or_default().push(r);
    }
    let radius = |x: &crate::dim::Vector3| (x.x * x.x + x.y * x.y).sqrt();
    let mut radius_spread: f64 = 0.0;
    let (mut staircase, mut residual): (f64, f64) = (0.0, 0.0);
    // Every move before any node stops is one whole increment (trimming only acts at the
    // surface), so a node's advance before the check is its advance after it less one
    // increment if it grew; a split node carries a copy of its parent's advance.
    let da = PENNY_INCREMENT;
    for rows in by_step.values() {
        // Only checks before any node stopped at the cylinder's surface: there the front
        // is trimmed, not grown.
        if rows.iter().any(|r| r.status != crate::fracture::growth3::NodeStatus::Growing) {
            break;
        }
        let (lo, hi) = rows.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), r| (l.min(radius(&r.x)), h.max(radius(&r.x))));
        radius_spread = radius_spread.max(hi - lo);
        let before = |r: &NodeRecord| r.advance - if r.grew { da } else { 0.0 };
        let spread = |f: &dyn Fn(&NodeRecord) -> f64| {
            let (lo, hi) = rows.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), r| (l.min(f(r)), h.max(f(r))));
            hi - lo
        };
        staircase = staircase.max(spread(&|r| (before(r) / da).round()));
        residual = residual.max(spread(&|r| radius(&r.x) - before(r)));
    }
    let mut last: BTreeMap<u32, f64> = BTreeMap::new();
    for r in &g.records {
        last.insert(r.label, r.advance);
    }
    let front: Vec<f64> = crack.front.iter().flatten().map(|&v| radius(&crack.surface.vertices[v as usize])).collect();
    Ok(PennyGrowth {
        z_max,
        radius_spread,
        staircase,
        residual,
        advances: last.values().copied().collect(),
        r_min: front.iter().copied().fold(f64::INFINITY, f64::min),
        r_max: front.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        increments: g.records.iter().filter(|r| r.grew).count(),
        first_growth: g.records.iter().find(|r| r.grew).map_or(f64::NAN, |r| r.time),
        front_edges: crack.front.len(),
        splits: g.cracks[0].splits,
        seconds,
        particles: sim.particles.len(),
        steps: sim.step_count,
    })
}

/// The penny's quasi-static onset time (ms) on its linear ramp (`front_penny_growth_3d.toml`:
/// end stress 1 MPa at 0.3 ms, K_Ic = 3 MPa√mm, a = 10 mm): K_I = 2σ√(a/π) × 1.1134 (Sneddon
/// with the finite-cylinder factor of 3d-references.md §1.2 at a/R = 1/2, H/R = 1, as
/// `front_j_penny`) reaches K_Ic at σ_c = 0.7551 MPa, t = 0.3 σ_c = 0.2265 ms.
pub fn penny_onset() -> f64 {
    let (a, kic, factor, ramp, stress) = (10.0_f64, 3.0, 1.1134, 0.3, 1.0);
    let sigma_c = kic / (2.0 * (a / std::f64::consts::PI).sqrt() * factor);
    ramp * sigma_c / stress
}

/// Case `front_growth_penny` (full suite only).
pub fn run_penny(_variant: Variant) -> anyhow::Result<CaseOutput> {
    let p = penny_growth(&[])?;
    let da = PENNY_INCREMENT;
    let mut out = CaseOutput::default();
    out.measure("planar", "a/h = 5", p.z_max, 0.0);
    out.measure("staircase", "a/h = 5", p.staircase, 0.0);
    out.measure("circular", "a/h = 5", p.residual / da, 0.0);
    out.measure("grown", "a/h = 5", p.increments as f64, 0.0);
    out.measure("onset", "a/h = 5", p.first_growth, penny_onset());
    let (amin, amax) = p.advances.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &a| (l.min(a), h.max(a)));
    out.note(format!(
        "Largest |z| of a crack particle {:.2e} mm; largest spread of the front nodes' radii at a check while all grew {:.4} mm \
         ({:.4} increments = at most {} whole increments of staircase + {:.4} mm of shape); {} node moves from t = {:.4} ms; node advances at the end {amin:.3}–{amax:.3} mm; front radius at the end \
         {:.3}–{:.3} mm, {} front edges after {} splits. Run {} particles × {} steps {:.1} s.",
        p.z_max,
        p.radius_spread,
        p.radius_spread / da,
        p.staircase,
        p.residual,
        p.increments,
        p.first_growth,
        p.r_min,
        p.r_max,
        p.front_edges,
        p.splits,
        p.particles,
        p.steps,
        p.seconds
    ));
    Ok(out)
}

/// The elliptical crack's semi-axes (mm) in `front_ellipse_growth_3d.toml`: a along x, b along y.
pub const ELLIPSE_A: f64 = 16.0;
pub const ELLIPSE_B: f64 = 10.0;

/// Irwin's shape of K_I along an elliptical front (3d-references.md §3):
/// K_I(φ)/K_I(90°) = [sin²φ + (b/a)² cos²φ]^{1/4}, φ the parametric angle.
pub fn irwin_shape(phi: f64, a: f64, b: f64) -> f64 {
    (phi.sin().powi(2) + (b / a).powi(2) * phi.cos().powi(2)).powf(0.25)
}

/// What the growing ellipse measured.
#[derive(Clone, Debug, Default)]
pub struct EllipseGrowth {
    /// Parametric angles (degrees) of the nodes that grew at the first check where any grew.
    pub first_grown: Vec<f64>,
    pub first_growth: f64,
    /// Smallest [(b + advance at the minor-axis end)/(a + advance at the major-axis end)]/(b/a)
    /// over the checks while every node grows.
    pub ratio_min: f64,
    /// The same ratio at the last such check.
    pub ratio_last: f64,
    /// At the last check before the first growth: (φ in degrees, K_I/K_I(minor-axis end), Irwin's shape).
    pub shape: Vec<(f64, f64, f64)>,
    pub increments: usize,
    pub seconds: f64,
    pub particles: usize,
    pub steps: u64,
}

/// Run `front_ellipse_growth_3d.toml` (with overrides).
pub fn ellipse_growth(overrides: &[(&str, &str)]) -> anyhow::Result<EllipseGrowth> {
    let (a, b) = (ELLIPSE_A, ELLIPSE_B);
    let (_, sim, seconds) = run_scene3("front_ellipse_growth_3d.toml", overrides, false)?;
    let g = sim.growth.as_ref().ok_or_else(|| anyhow::anyhow!("the ellipse does not grow"))?;
    let mut by_step: BTreeMap<u64, Vec<&NodeRecord>> = BTreeMap::new();
    for r in &g.records {
        by_step.entry(r.step).or_default().push(r);
    }
    // Parametric angle of a point near the initial front (its drift with the material is
    // ~1e−3 mm, far below what the checks resolve).
    let phi = |x: &crate::dim::Vector3| (x.y / b).atan2(x.x / a);
    let mut out = EllipseGrowth { ratio_min: f64::INFINITY, seconds, particles: sim.particles.len(), steps: sim.step_count, ..Default::default() };
    let mut previous: Option<&Vec<&NodeRecord>> = None;
    for rows in by_step.values() {
        let grown: Vec<f64> = rows.iter().filter(|r| r.grew).map(|r| phi(&r.x).to_degrees()).collect();
        if !grown.is_empty() && out.first_grown.is_empty() {
            out.first_grown = grown;
            out.first_growth = rows[0].time;
            if let Some(prev) = previous {
                // The end nodes on the symmetry planes: x = 0 (minor axis) and y = 0 (major axis).
                let minor = prev.iter().min_by(|p, q| p.x.x.abs().total_cmp(&q.x.x.abs())).expect("front nodes");
                let mut shape: Vec<(f64, f64, f64)> = prev.iter().map(|r| (phi(&r.x).to_degrees(), r.k[0] / minor.k[0], irwin_shape(phi(&r.x), a, b))).collect();
                shape.sort_by(|p, q| p.0.total_cmp(&q.0));
                out.shape = shape;
            }
        }
        if rows.iter().any(|r| r.status != crate::fracture::growth3::NodeStatus::Growing) {
            break;
        }
        let minor = rows.iter().min_by(|p, q| p.x.x.abs().total_cmp(&q.x.x.abs())).expect("front nodes");
        let major = rows.iter().min_by(|p, q| p.x.y.abs().total_cmp(&q.x.y.abs())).expect("front nodes");
        let ratio = (b + minor.advance) / (a + major.advance) / (b / a);
        out.ratio_min = out.ratio_min.min(ratio);
        out.ratio_last = ratio;
        previous = Some(rows);
    }
    out.increments = g.records.iter().filter(|r| r.grew).count();
    Ok(out)
}

/// Case `front_growth_ellipse` (full suite only; issue 17 verification item 5).
pub fn run_ellipse(_variant: Variant) -> anyhow::Result<CaseOutput> {
    let e = ellipse_growth(&[])?;
    let mut out = CaseOutput::default();
    let label = "b/a = 0.625, b/h = 5";
    let from_minor = e.first_grown.iter().map(|p| 90.0 - p.abs()).fold(f64::NAN, f64::max);
    out.measure("minor_axis_first", label, from_minor, 0.0);
    out.measure("aspect_ratio", label, e.ratio_min, 1.0);
    out.measure("grown", label, e.increments as f64, 0.0);
    let worst = e.shape.iter().map(|s| (s.1 / s.2 - 1.0).abs()).fold(0.0, f64::max);
    out.note(format!(
        "First growth at t = {:.4} ms at parametric angles {:?}° (90° = minor-axis end); (b + Δb)/(a + Δa) over b/a: smallest {:.4}, \
         at the last check while the whole front grew {:.4}; {} node moves. K_I along the front at the last check before the first \
         growth, over its value at the minor-axis end, against Irwin's [sin²φ + (b/a)² cos²φ]^{{1/4}}: largest deviation {:.1} % \
         (not a check: the finite body, a/R = 0.5, raises K more at the major-axis end, and the planar circle's curvature bias, \
         ≈ +0.4 r/ρ in J (3d-references.md §1.5), is largest there, ρ = b²/a = 6.25 mm). Per node (φ°, ratio, Irwin): {}. \
         Run {} particles × {} steps, {:.1} s.",
        e.first_growth,
        e.first_grown.iter().map(|p| (p * 10.0).round() / 10.0).collect::<Vec<_>>(),
        e.ratio_min,
        e.ratio_last,
        e.increments,
        100.0 * worst,
        e.shape.iter().map(|s| format!("({:.1}, {:.4}, {:.4})", s.0, s.1, s.2)).collect::<Vec<_>>().join(", "),
        e.particles,
        e.steps,
        e.seconds
    ));
    out.figure(
        "front_growth_ellipse_shape.png",
        "Elliptical crack (a = 16, b = 10 mm, h = 2 mm) just before growth starts: K_I at each front node over K_I at the minor-axis end, \
         against the parametric angle φ, with Irwin's infinite-body shape. The growth starts where K_I is largest.",
        PlotSpec::new("Elliptical crack: K_I along the front before growth", "parametric angle φ (degrees)", "K_I / K_I(90°)"),
        Plot::Lines(vec![
            Series::line("MPM front nodes", e.shape.iter().map(|s| (s.0, s.1)).collect()),
            Series::reference("Irwin (infinite body)", e.shape.iter().map(|s| (s.0, s.2)).collect()),
        ]),
    );
    Ok(out)
}

/// Width of the 3D DCB of `dcb_growth_3d.toml` (mm; free side faces) and its load line x.
pub const DCB3_WIDTH: f64 = 4.0;
pub const DCB3_LOAD_LINE: f64 = 99.5;

/// Corrected beam theory for the 3D DCB with the 3D front's plane-strain K:
/// G = (3/16) δ² E h³/(a + χh)⁴ = G_c = K_Ic²(1 − ν²)/E at
/// a + χh = (3E²h³δ²/(16 K_Ic²(1 − ν²)))^{1/4} (the 2D case's
/// [`crate::verify::cases::growth::dcb_effective_length`] with plane-strain G_c).
pub fn dcb3_effective_length(delta: f64) -> f64 {
    use crate::verify::cases::fracture::{ARM, E_BEAM};
    use crate::verify::cases::growth::KIC_DCB;
    let nu: f64 = 0.33;
    (3.0 * E_BEAM * E_BEAM * ARM.powi(3) * delta * delta / (16.0 * KIC_DCB * KIC_DCB * (1.0 - nu * nu))).powf(0.25)
}

/// What the 3D DCB growth run measured.
#[derive(Clone, Debug, Default)]
pub struct Dcb3Growth {
    /// Starts from rest of the mid-width front node: (time ms, a from the load line, beam-theory a).
    pub restarts: Vec<(f64, f64, f64)>,
    /// Largest spread of the front nodes' x inside the body at a check, in increments.
    pub front_spread: f64,
    /// Mid-width node's crack length after each check: (time, a).
    pub history: Vec<(f64, f64)>,
    pub increments: usize,
    pub seconds: f64,
    pub particles: usize,
    pub steps: u64,
}

/// Run `dcb_growth_3d.toml` (with overrides; unchecked, as the 2D growth cases).
pub fn dcb3_growth(overrides: &[(&str, &str)]) -> anyhow::Result<Dcb3Growth> {
    use crate::verify::cases::growth::V_DCB;
    let (s, sim, seconds) = run_scene3("dcb_growth_3d.toml", overrides, true)?;
    let g = sim.growth.as_ref().ok_or_else(|| anyhow::anyhow!("the DCB does not grow"))?;
    let mid = g.records.iter().min_by(|p, q| (p.x.z - 0.5 * DCB3_WIDTH).abs().total_cmp(&(q.x.z - 0.5 * DCB3_WIDTH).abs())).map(|r| r.label).ok_or_else(|| anyhow::anyhow!("no front records"))?;
    let mut out = Dcb3Growth { seconds, particles: sim.particles.len(), steps: sim.step_count, ..Default::default() };
    let mut last: Option<f64> = None;
    let mut by_step: BTreeMap<u64, Vec<&NodeRecord>> = BTreeMap::new();
    for r in &g.records {
        by_step.entry(r.step).or_default().push(r);
        if r.label != mid {
            continue;
        }
        out.history.push((r.time, DCB3_LOAD_LINE - r.x.x));
        if r.grew {
            if last.is_none_or(|l| r.time - l >= 1.0) {
                out.restarts.push((r.time, DCB3_LOAD_LINE - r.x.x, dcb3_effective_length(2.0 * V_DCB * r.time) - crate::verify::cases::fracture::CHI * crate::verify::cases::fracture::ARM));
            }
            last = Some(r.time);
        }
    }
    let da = 0.5 * s.grid.cell[0];
    for rows in by_step.values() {
        let inside: Vec<f64> = rows.iter().filter(|r| (0.0..=DCB3_WIDTH).contains(&r.x.z)).map(|r| r.x.x).collect();
        let (lo, hi) = inside.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &x| (l.min(x), h.max(x)));
        if hi >= lo {
            out.front_spread = out.front_spread.max((hi - lo) / da);
        }
    }
    out.increments = g.records.iter().filter(|r| r.grew).count();
    Ok(out)
}

/// Case `dcb_growth_3d` (full suite only; issue 17 verification item 4).
pub fn run_dcb3(_variant: Variant) -> anyhow::Result<CaseOutput> {
    use crate::verify::cases::fracture::{ARM, CHI};
    let d = dcb3_growth(&[])?;
    let mut out = CaseOutput::default();
    out.measure("restarts", "h = 2 mm, B = 4 mm", d.restarts.len() as f64, 0.0);
    for &(t, a, a_ref) in &d.restarts {
        out.measure("restart_length", &format!("h = 2 mm, mid-width node, t = {t:.2} ms"), a + CHI * ARM, a_ref + CHI * ARM);
    }
    out.measure("front_straight", "h = 2 mm, B = 4 mm", d.front_spread, 0.0);
    out.note(format!(
        "Mid-width front node: starts from rest (t ms, a, beam theory with plane-strain G_c) {}; largest spread of the front's x inside \
         the body at a check {:.3} increments; {} node moves. Run {} particles × {} steps, {:.1} s (unchecked).",
        d.restarts.iter().map(|(t, a, b)| format!("({t:.2}, {a:.2}, {b:.2})")).collect::<Vec<_>>().join(", "),
        d.front_spread,
        d.increments,
        d.particles,
        d.steps,
        d.seconds
    ));
    let a0 = DCB3_LOAD_LINE - 50.0;
    let theory: Vec<(f64, f64)> = (0..=200).map(|k| 0.1 * k as f64).map(|t| (t, (dcb3_effective_length(2.0 * crate::verify::cases::growth::V_DCB * t) - CHI * ARM).max(a0))).collect();
    out.figure(
        "dcb_growth_3d.png",
        "Displacement-controlled DCB, 4 mm wide with free faces (3D, h = 2 mm): crack length of the mid-width front node from the load line \
         versus time, against corrected beam theory with the plane-strain G_c of the 3D front.",
        PlotSpec::new("3D DCB under opening control: crack length", "time (ms)", "crack length a (mm)"),
        Plot::Lines(vec![Series::line("MPM, mid-width front node", d.history.clone()), Series::reference("corrected beam theory, G = G_c", theory)]),
    );
    Ok(out)
}

/// Kink angle of the maximum hoop stress criterion in the closed form of 3d-references.md §2
/// (Erdogan & Sih 1963; 001 eq. 20): θ₀ = 2 arctan[(1 − √(1 + 8r²))/(4r)], r = K_II/K_I
/// (radians, from x1 toward x2; 0 for K_II = 0, ∓70.53° for K_I ≤ 0). Written independently of
/// [`crate::fracture::criteria::hoop_stress_angle`], which takes the algebraically equal root
/// 2 arctan(−2K_II/(K_I + √(K_I² + 8K_II²))).
pub fn mts_kink(k1: f64, k2: f64) -> f64 {
    if k2 == 0.0 {
        return 0.0;
    }
    if k1 <= 0.0 {
        return -k2.signum() * 2.0 * (8.0f64.sqrt() / 4.0).atan();
    }
    let r = k2 / k1;
    2.0 * ((1.0 - (1.0 + 8.0 * r * r).sqrt()) / (4.0 * r)).atan()
}

/// K_eq of the maximum hoop stress criterion along θ (Erdogan & Sih 1963; 001 eq. 19):
/// cos(θ/2)[K_I cos²(θ/2) − (3/2)K_II sin θ].
pub fn mts_keq(k1: f64, k2: f64, theta: f64) -> f64 {
    let c = (0.5 * theta).cos();
    c * (k1 * c * c - 1.5 * k2 * theta.sin())
}

/// One front node's first increment on the inclined penny.
#[derive(Clone, Debug)]
pub struct FirstKink {
    pub label: u32,
    pub time: f64,
    /// Front angle θ of the node (degrees, from s, positive about n; 0 … −180 on y ≥ 0).
    pub theta_node: f64,
    /// θ_c of the criterion (degrees) and the closed form on the same row's K_I, K_II.
    pub theta_c: f64,
    pub theta_c_from_k: f64,
    /// The recorded direction of growth's angle from the original crack plane (degrees, from
    /// the in-plane radial direction toward n).
    pub psi: f64,
    /// Kassir & Sih's MTS angle at θ_node (degrees).
    pub theta_c_ref: f64,
    pub k: [f64; 3],
    pub k_eq: f64,
}

/// What the growing inclined penny measured.
#[derive(Clone, Debug, Default)]
pub struct InclinedGrowth {
    /// Remote stress σ = F/(loaded particles × h²/4) and Kassir & Sih at θ = 0 (K_I, K_II amplitude).
    pub sigma: f64,
    pub k_ref: [f64; 3],
    /// MTS kink and K_eq at θ = 0 from Kassir & Sih (degrees; MPa√mm at σ).
    pub kink_ref: f64,
    pub keq_ref: f64,
    pub onset_ref: f64,
    pub onset: f64,
    /// First increment of every node that grew, in label order.
    pub first: Vec<FirstKink>,
    /// The first increments of the two mirror-plane nodes (θ = 0 first, then θ = −180°).
    pub mirror: Vec<FirstKink>,
    /// Each mirror-plane node's increments: (θ_c, ψ from the original plane) in degrees, sign as recorded.
    pub mirror_sequence: Vec<(f64, Vec<(f64, f64)>)>,
    /// Largest |θ_c − θ₀(K_I, K_II)| over every increment (degrees).
    pub kink_from_k: f64,
    /// Largest angle from the mirror plane among the nodes that grew at the first check where any grew.
    pub first_from_mirror: f64,
    pub first_labels: Vec<(u32, f64)>,
    /// Tilt atan2(n_x, n_z) of the new surface within a cell of y = 0 (degrees): x < 0 (θ = 0) and x > 0
    /// (θ = −180°), and the triangles' count on each side.
    pub tilt: [f64; 2],
    pub tilt_triangles: [usize; 2],
    /// Nodes within 15° of θ = −90°: largest K_eq over all their checks, largest |K_III/K_I|, moves.
    pub mode3_keq_max: f64,
    pub mode3_ratio: f64,
    pub mode3_moves: usize,
    pub mode3_nodes: usize,
    pub kic: f64,
    pub nu: f64,
    pub ramp: f64,
    /// Nodes that ever grew, node moves, statuses other than growing at the end.
    pub grown_nodes: usize,
    pub increments: usize,
    pub stopped: usize,
    pub front_edges: usize,
    pub seconds: f64,
    pub particles: usize,
    pub steps: u64,
}

/// Run `front_inclined_growth_3d.toml` (with overrides).
pub fn inclined_growth(overrides: &[(&str, &str)]) -> anyhow::Result<InclinedGrowth> {
    use crate::verify::cases::front3::{kassir_sih, InclinedGeometry, INCL_A, INCL_GAMMA_DEG};
    let file = "front_inclined_growth_3d.toml";
    let (s, sim, seconds) = run_scene3(file, overrides, false)?;
    let g = sim.growth.as_ref().ok_or_else(|| anyhow::anyhow!("the inclined penny does not grow"))?;
    let geom = InclinedGeometry::oblique();
    let h = s.grid.cell[0];
    // The crack as built (before any growth): the new surface is every triangle with a vertex
    // beyond its vertices (new crack particles are appended, src/crack/advance3.rs).
    let meshes: Vec<Option<crate::stl::ClosedMesh>> = s.bodies.iter().map(|_| None).collect();
    let initial_vertices = s.crack_surfaces(&s.grid(), &meshes)?[0].surface.vertices.len();
    let mat = &sim.materials[0];
    let nu = mat.nu;
    let kic = s.materials[0].toughness.as_ref().map(|t| t.kic).ok_or_else(|| anyhow::anyhow!("no toughness"))?;
    let loaded = sim.particles.load.iter().filter(|&&l| l == 0).count();
    let force = s.loads[0].force.ok_or_else(|| anyhow::anyhow!("the top load is a force"))?[2];
    let ramp = s.loads[0].ramp;
    let sigma = force / (loaded as f64 * 0.25 * h * h);
    let gamma = INCL_GAMMA_DEG.to_radians();
    let k_ref = kassir_sih(sigma, INCL_A, gamma, nu, 0.0);
    let kink = mts_kink(k_ref[0], k_ref[1]);
    let keq_ref = mts_keq(k_ref[0], k_ref[1], kink);
    let mut out = InclinedGrowth {
        sigma,
        k_ref,
        kink_ref: kink.to_degrees(),
        keq_ref,
        onset_ref: ramp * kic / keq_ref,
        onset: f64::NAN,
        kink_from_k: 0.0,
        first_from_mirror: f64::NAN,
        kic,
        nu,
        ramp,
        seconds,
        particles: sim.particles.len(),
        steps: sim.step_count,
        front_edges: sim.cracks[0].front.len(),
        ..Default::default()
    };
    let from_mirror = |th: f64| th.abs().min(180.0 - th.abs());
    let mut by_step: BTreeMap<u64, Vec<&NodeRecord>> = BTreeMap::new();
    for r in &g.records {
        by_step.entry(r.step).or_default().push(r);
    }
    for rows in by_step.values() {
        let grown: Vec<&&NodeRecord> = rows.iter().filter(|r| r.grew).collect();
        if !grown.is_empty() {
            out.onset = rows[0].time;
            out.first_labels = grown.iter().map(|r| (r.label, geom.theta(&r.x).to_degrees())).collect();
            out.first_from_mirror = out.first_labels.iter().map(|&(_, t)| from_mirror(t)).fold(f64::NAN, f64::max);
            break;
        }
    }
    // Mirror-plane nodes: on y = 0 at their first record.
    let mut first_row: BTreeMap<u32, &NodeRecord> = BTreeMap::new();
    let mut first_grew: BTreeMap<u32, &NodeRecord> = BTreeMap::new();
    let mut sequences: BTreeMap<u32, Vec<(f64, f64)>> = BTreeMap::new();
    let mut mode3_labels = std::collections::BTreeSet::new();
    for r in &g.records {
        first_row.entry(r.label).or_insert(r);
        if r.grew {
            first_grew.entry(r.label).or_insert(r);
            let d = first_row[&r.label].x - geom.centre;
            let er = (d - geom.n * d.dot(&geom.n)).normalize();
            sequences.entry(r.label).or_default().push((r.theta.to_degrees(), r.heading.dot(&geom.n).atan2(r.heading.dot(&er)).to_degrees()));
            let from_k = mts_kink(r.k[0], r.k[1]);
            out.kink_from_k = out.kink_from_k.max((r.theta - from_k).to_degrees().abs());
        }
        let th = geom.theta(&first_row[&r.label].x).to_degrees();
        if (th + 90.0).abs() <= 15.0 {
            mode3_labels.insert(r.label);
            if r.k_eq.is_finite() {
                out.mode3_keq_max = out.mode3_keq_max.max(r.k_eq);
            }
            if r.k[0] > 0.0 {
                out.mode3_ratio = out.mode3_ratio.max((r.k[2] / r.k[0]).abs());
            }
            out.mode3_moves += r.grew as usize;
        }
    }
    out.mode3_nodes = mode3_labels.len();
    let first_of = |r: &NodeRecord| {
        let th = geom.theta(&r.x);
        let d = r.x - geom.centre;
        let er = (d - geom.n * d.dot(&geom.n)).normalize();
        let kr = kassir_sih(sigma, INCL_A, gamma, nu, th);
        FirstKink {
            label: r.label,
            time: r.time,
            theta_node: th.to_degrees(),
            theta_c: r.theta.to_degrees(),
            theta_c_from_k: mts_kink(r.k[0], r.k[1]).to_degrees(),
            psi: r.heading.dot(&geom.n).atan2(r.heading.dot(&er)).to_degrees(),
            theta_c_ref: mts_kink(kr[0], kr[1]).to_degrees(),
            k: r.k,
            k_eq: r.k_eq,
        }
    };
    out.first = first_grew.values().map(|r| first_of(r)).collect();
    let on_mirror = |l: u32| first_row[&l].x.y.abs() <= 1e-9 * INCL_A;
    let mut mirror: Vec<FirstKink> = first_grew.values().filter(|r| on_mirror(r.label)).map(|r| first_of(r)).collect();
    mirror.sort_by(|p, q| p.theta_node.abs().total_cmp(&q.theta_node.abs()));
    out.mirror_sequence = mirror.iter().map(|m| (m.theta_node, sequences[&m.label].clone())).collect();
    out.mirror = mirror;
    out.grown_nodes = first_grew.len();
    out.increments = g.records.iter().filter(|r| r.grew).count();
    let mut last: BTreeMap<u32, &NodeRecord> = BTreeMap::new();
    for r in &g.records {
        last.insert(r.label, r);
    }
    out.stopped = last.values().filter(|r| r.status != crate::fracture::growth3::NodeStatus::Growing).count();
    // The new surface near the mirror plane: area-weighted mean normal per side.
    let crack = &sim.cracks[0];
    let pts = &crack.surface.vertices;
    let mut sums = [crate::dim::Vector3::zeros(); 2];
    for t in &crack.surface.triangles {
        if t.iter().all(|&v| (v as usize) < initial_vertices) {
            continue;
        }
        let [a, b, c] = t.map(|v| pts[v as usize]);
        let centroid = (a + b + c) / 3.0;
        if centroid.y.abs() > h {
            continue;
        }
        let side = usize::from(centroid.x > 0.0);
        sums[side] += (b - a).cross(&(c - a));
        out.tilt_triangles[side] += 1;
    }
    for side in 0..2 {
        let n = if sums[side].z < 0.0 { -sums[side] } else { sums[side] };
        out.tilt[side] = n.x.atan2(n.z).to_degrees();
    }
    Ok(out)
}

/// Case `front_growth_inclined` (full suite only; issue 17 verification item 3).
pub fn run_inclined(_variant: Variant) -> anyhow::Result<CaseOutput> {
    let r = inclined_growth(&[])?;
    let mut out = CaseOutput::default();
    let label = "γ = 45°, a/h = 5";
    // θ = 0 as is, θ = −180° sign-reversed (the rotation about y maps it onto θ = 0).
    let kinks: Vec<f64> = r.mirror.iter().map(|m| if m.theta_node.abs() < 90.0 { m.theta_c } else { -m.theta_c }).collect();
    let worst = kinks.iter().copied().max_by(|p, q| (p - r.kink_ref).abs().total_cmp(&(q - r.kink_ref).abs())).unwrap_or(f64::NAN);
    if r.mirror.len() == 2 {
        out.measure("kink_theta0", label, worst, r.kink_ref);
        let frame = r.mirror.iter().map(|m| (m.psi - m.theta_c).abs()).fold(0.0, f64::max);
        out.measure("kink_frame", label, frame, 0.0);
    } else {
        // Both mirror-plane nodes must have grown for the kink checks to mean anything.
        out.measure("kink_theta0", label, f64::NAN, r.kink_ref);
        out.measure("kink_frame", label, f64::NAN, 0.0);
    }
    out.measure("kink_from_k", label, if r.increments > 0 { r.kink_from_k } else { f64::NAN }, 0.0);
    out.measure("theta0_first", label, r.first_from_mirror, 0.0);
    out.measure("onset", label, r.onset, r.onset_ref);
    let tilt = if r.tilt_triangles.iter().all(|&n| n > 0) { r.tilt[0].abs().max(r.tilt[1].abs()) } else { f64::NAN };
    out.measure("turns_to_load_normal", label, tilt, 0.0);
    out.measure("grown", label, r.increments as f64, 0.0);
    out.note(format!(
        "σ = {:.6} MPa; Kassir & Sih at θ = 0: K_I = {:.4}, K_II = {:.4} MPa√mm (r = {:.5}); MTS kink {:.3}°, K_eq = {:.4}; K_Ic = {} → onset \
         {:.4} ms on the {} ms ramp (quasi-static). Measured onset {:.4} ms ({:+.1} %), first nodes (label, θ°) {:?}.",
        r.sigma,
        r.k_ref[0],
        r.k_ref[1],
        r.k_ref[1] / r.k_ref[0],
        r.kink_ref,
        r.keq_ref,
        r.kic,
        r.onset_ref,
        r.ramp,
        r.onset,
        100.0 * (r.onset / r.onset_ref - 1.0),
        r.first_labels.iter().map(|(l, t)| (*l, (t * 10.0).round() / 10.0)).collect::<Vec<_>>()
    ));
    for m in &r.mirror {
        out.note(format!(
            "Mirror-plane node {} (θ = {:.1}°): first increment at t = {:.4} ms, K_I = {:.5}, K_II = {:.5}, K_III = {:.3e} (K_II/K_I = {:.4}, \
             {:+.1} % from Kassir & Sih's {:.4}), K_eq = {:.4}; θ_c = {:.3}° (closed form on these K's {:.3}°, on Kassir & Sih's {:.3}°); \
             direction {:.3}° from the original plane.",
            m.label,
            m.theta_node,
            m.time,
            m.k[0],
            m.k[1],
            m.k[2],
            m.k[1] / m.k[0],
            100.0 * ((m.k[1] / m.k[0]).abs() / (r.k_ref[1] / r.k_ref[0]) - 1.0),
            r.k_ref[1] / r.k_ref[0],
            m.k_eq,
            m.theta_c,
            m.theta_c_from_k,
            m.theta_c_ref,
            m.psi
        ));
    }
    {
        // The other nodes near the mirror plane: those that moved at the same check as their side's
        // mirror-plane node (an untouched front) and those that moved after a neighbour had (their
        // frames tilted by its new triangles).
        let from_mirror = |k: &FirstKink| k.theta_node.abs().min(180.0 - k.theta_node.abs());
        let mirror_time = |k: &FirstKink| r.mirror.iter().find(|m| (m.theta_node < -90.0) == (k.theta_node < -90.0)).map_or(f64::NAN, |m| m.time);
        let near: Vec<&FirstKink> = r.first.iter().filter(|k| from_mirror(k) <= 25.0 && from_mirror(k) > 1e-6).collect();
        let range = |with: bool, f: &dyn Fn(&FirstKink) -> f64| {
            near.iter().filter(|k| (k.time == mirror_time(k)) == with).map(|k| f(k)).fold((0usize, f64::INFINITY, f64::NEG_INFINITY), |(n, l, h), v| (n + 1, l.min(v), h.max(v)))
        };
        let fmt = |with: bool| {
            let (n, tl, th) = range(with, &|k| k.theta_c.abs());
            let (_, pl, ph) = range(with, &|k| k.psi.abs());
            let (_, rl, rh) = range(with, &|k| k.theta_c_ref.abs());
            format!("{n} nodes: |θ_c| {tl:.1}–{th:.1}° in their frames, |ψ| {pl:.1}–{ph:.1}° from the original plane, Kassir & Sih's MTS {rl:.1}–{rh:.1}°")
        };
        out.note(format!(
            "The other nodes within 25° of the mirror plane. Moved at the same check as their side's mirror-plane node: {}. Moved after a \
             neighbour had: {}. The frame's normal leaves out the triangles that hold a leading neighbour (src/fracture/growth3.rs \
             growth_normals); with them (the mean over every triangle at the node) the second group's frames were tilted ≈ 14° toward \
             the neighbour's kink and their directions over-turned to 56–67° from the plane (θ_c 29.7–56.8° in the tilted frames).",
            fmt(true),
            fmt(false)
        ));
    }
    for (th, seq) in &r.mirror_sequence {
        out.note(format!(
            "Mirror-plane node at θ = {th:.1}°: its successive increments (θ_c in its frame, ψ from the original plane) {}.",
            seq.iter().map(|(t, p)| format!("({t:.2}°, {p:.2}°)")).collect::<Vec<_>>().join(", ")
        ));
    }
    out.note(format!(
        "New surface within one cell of y = 0 at the end: tilt atan2(n_x, n_z) = {:.2}° on the θ = 0 side ({} triangles), {:.2}° on the \
         θ = −180° side ({} triangles); the original crack 45°, the first MTS increment −10.47° (Kassir & Sih). {} node moves by {} nodes, \
         {} nodes stopped; {} front edges at the end. Nodes within 15° of θ = −90° (K_III-dominated, {} nodes): largest K_eq {:.4} against \
         K_Ic = {} (K_eq = K_I there: the criterion leaves K_III out, docs/scene.md), largest |K_III/K_I| {:.3}, {} moves — no twist is \
         modelled (Kassir & Sih's twist angle there 38.1°, 3d-references.md §2). Run {} particles × {} steps, {:.1} s.",
        r.tilt[0],
        r.tilt_triangles[0],
        r.tilt[1],
        r.tilt_triangles[1],
        r.increments,
        r.grown_nodes,
        r.stopped,
        r.front_edges,
        r.mode3_nodes,
        r.mode3_keq_max,
        r.kic,
        r.mode3_ratio,
        r.mode3_moves,
        r.particles,
        r.steps,
        r.seconds
    ));
    let mut csv = String::from("label,time,theta_node_deg,k1,k2,k3,k_eq,theta_c_deg,theta_c_from_k_deg,theta_c_kassir_sih_deg,direction_from_plane_deg\n");
    for f in &r.first {
        csv.push_str(&format!("{},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e}\n", f.label, f.time, f.theta_node, f.k[0], f.k[1], f.k[2], f.k_eq, f.theta_c, f.theta_c_from_k, f.theta_c_ref, f.psi));
    }
    out.data("front_growth_inclined_first.csv", "Inclined penny: the first increment of every front node that grew — θ, K's, K_eq, θ_c, the closed form on the node's K's and on Kassir & Sih's, the direction's angle from the original plane.", csv);
    let mut first = r.first.clone();
    first.sort_by(|p, q| p.theta_node.total_cmp(&q.theta_node));
    // The nodes near θ = −90° do not grow: one curve per side, no line across the gap.
    let side = |far: bool, f: &dyn Fn(&FirstKink) -> f64| first.iter().filter(|k| (k.theta_node < -90.0) == far).map(|k| (k.theta_node, f(k))).collect::<Vec<_>>();
    let nu = r.nu;
    let reference: Vec<(f64, f64)> = (0..=180)
        .map(|k| -(k as f64))
        .map(|t| {
            let k = crate::verify::cases::front3::kassir_sih(r.sigma, crate::verify::cases::front3::INCL_A, crate::verify::cases::front3::INCL_GAMMA_DEG.to_radians(), nu, t.to_radians());
            (t, mts_kink(k[0], k[1]).to_degrees())
        })
        .collect();
    out.figure(
        "front_growth_inclined_kink.png",
        "Inclined penny crack (γ = 45°, a = 10 mm, h = 2 mm, half model): the first increment of every front node that grew, against the \
         front angle θ (0 and −180° on the mirror plane: pure I + II; the nodes within about 60° of θ = −90° did not grow): θ_c in the node's \
         growth frame and ψ, the direction's angle from the original crack plane, with the maximum hoop stress angle from Kassir & Sih's \
         K_I, K_II (K_III not used by the criterion). The mirror-plane nodes grew first, on an untouched front; ψ and θ_c coincide \
         where the node's frame lies in the original plane (its normal leaves out a leading neighbour's kinked triangles).",
        PlotSpec::new("Inclined penny: first-increment kink angle along the front", "front angle θ (degrees)", "angle (degrees)"),
        Plot::Lines(vec![
            Series::line("θ_c (node's frame), θ < −90°", side(true, &|k| k.theta_c)).with_markers(),
            Series::line("θ_c (node's frame), θ > −90°", side(false, &|k| k.theta_c)).with_markers(),
            Series::line("ψ (from the original plane), θ < −90°", side(true, &|k| k.psi)).with_markers(),
            Series::line("ψ (from the original plane), θ > −90°", side(false, &|k| k.psi)).with_markers(),
            Series::reference("MTS on Kassir & Sih's K's", reference),
        ]),
    );
    Ok(out)
}
