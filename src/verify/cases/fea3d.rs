//! The 3D static FEA (hex8) against references with cracks: cases `fea_penny_3d` (penny
//! crack, J along the front against Sneddon with the finite-cylinder factor),
//! `fea_dcb_3d` (J across the width of a 3D DCB) and `mpm_vs_fea_3d` (MPM against FEA
//! ahead of a 3D crack front). `tests/fea3d.rs` calls the same functions.

use crate::dim::Vector3;
use crate::fea::penny::{discrete_front, front_g, FrontStation};
use crate::fea::scene3::SceneFea3;
use crate::report::plot::{PlotSpec, Series};
use crate::verify::scene_file::SceneFile;
use crate::verify::{CaseOutput, Plot, Variant};
use anyhow::Context;

// ---------------------------------------------------------------------------------------
// Penny crack
// ---------------------------------------------------------------------------------------

/// Crack radius, cylinder radius and half-length of `verification/fea_penny_3d.toml` (mm).
pub const PENNY_A: f64 = 10.0;
pub const PENNY_R: f64 = 30.0;
pub const PENNY_H: f64 = 30.0;

/// K_I/K_∞ of a penny crack at mid-length of a solid cylinder with free lateral surface
/// and H/R = 1 (3d-references.md §1.2, axisymmetric FE computed there, ν = 0.3), linear
/// between the tabulated a/R (the table is smooth, ~(a/R)³: linear interpolation between
/// 0.30, 1/3 and 0.40 is within 0.05 % of it near a/R = 1/3).
pub fn penny_cylinder_factor(a_over_r: f64) -> f64 {
    const T: [(f64, f64); 7] =
        [(0.10, 1.0011), (0.20, 1.0085), (0.25, 1.0163), (0.30, 1.0273), (1.0 / 3.0, 1.0367), (0.40, 1.0612), (0.50, 1.1134)];
    let k = T.iter().position(|&(x, _)| x >= a_over_r).unwrap_or(T.len() - 1).clamp(1, T.len() - 1);
    let ((x0, y0), (x1, y1)) = (T[k - 1], T[k]);
    y0 + (y1 - y0) * (a_over_r - x0) / (x1 - x0)
}

/// The penny scene with a/h = `a_cells` (a half-integer, so that no node lies on r = a).
pub fn penny_scene(a_cells: f64) -> SceneFile {
    let h = PENNY_A / a_cells;
    let n = (PENNY_R / h).ceil() as usize + 4;
    SceneFile::new("fea_penny_3d.toml")
        .set("grid.cell", format!("[{h:?}, {h:?}, {h:?}]"))
        .set("grid.origin", format!("[{0:?}, {0:?}, {0:?}]", -2.0 * h))
        .set("grid.size", format!("[{0:?}, {0:?}, {0:?}]", n as f64 * h))
        .set("loads.0.particles", format!("{{ box = {{ min = [-1.0, -1.0, {:?}], max = [31.0, 31.0, 30.0] }} }}", PENNY_H - 0.5 * h))
}

/// One penny solve: the stations along the front and the whole-front average.
#[derive(Clone, Debug)]
pub struct Penny {
    pub a_cells: f64,
    pub h: f64,
    pub equations: usize,
    /// σ = F / meshed cross-section; the cylinder radius of that section.
    pub sigma: f64,
    pub r_eff: f64,
    pub e: f64,
    pub nu: f64,
    pub opening_area: f64,
    /// Per station, and the whole-front average (ψ ≡ 1), for each domain size.
    pub stations: Vec<FrontStation>,
    pub average: Vec<FrontStation>,
    pub fea_seconds: f64,
}

impl Penny {
    /// Sneddon's G for radius `a` with the finite-cylinder factor at a/R_eff.
    pub fn g_ref(&self, a: f64) -> f64 {
        let f = penny_cylinder_factor(a / self.r_eff);
        4.0 * (1.0 - self.nu * self.nu) * self.sigma * self.sigma * a / (std::f64::consts::PI * self.e) * f * f
    }
}

/// Solve the penny at a/h = `a_cells` and evaluate G at the stations every `step_deg`
/// degrees from 0 to 90 with hats of half-width `step_deg` (a partition of unity), for
/// domains of `cells` cells.
pub fn penny(a_cells: f64, step_deg: f64, cells: &[usize]) -> anyhow::Result<Penny> {
    let scene = penny_scene(a_cells).load3()?;
    let t = std::time::Instant::now();
    let fea = SceneFea3::from_scene(&scene)?;
    let an = fea.analyse()?;
    let center = Vector3::zeros();
    let front = discrete_front(&fea, center)?;
    let n = (90.0 / step_deg).round() as usize;
    let thetas: Vec<f64> = (0..=n).map(|k| (k as f64 * step_deg).to_radians()).collect();
    let (mut stations, mut average) = (Vec::new(), Vec::new());
    for &c in cells {
        stations.extend(front_g(&fea, &an, &front, center, PENNY_A, &thetas, step_deg.to_radians(), c)?);
        average.extend(front_g(&fea, &an, &front, center, PENNY_A, &[std::f64::consts::FRAC_PI_4], f64::INFINITY, c)?);
    }
    let m = &fea.materials[0];
    Ok(Penny {
        a_cells,
        h: fea.grid_mesh.grid.h.x,
        equations: an.equations,
        sigma: fea.load_resultant.z / front.section_area,
        r_eff: (4.0 * front.section_area / std::f64::consts::PI).sqrt(),
        e: m.e,
        nu: m.nu,
        opening_area: front.opening_area,
        stations,
        average,
        fea_seconds: t.elapsed().as_secs_f64(),
    })
}

/// Case `fea_penny_3d`.
pub fn run_penny(variant: Variant) -> anyhow::Result<CaseOutput> {
    let meshes: &[f64] = match variant {
        Variant::Quick => &[12.5],
        Variant::Full => &[4.5, 6.5, 8.5, 12.5],
    };
    let mut out = CaseOutput::default();
    let mut conv = Vec::new();
    let mut curves = Vec::new();
    for &m in meshes {
        let p = penny(m, 22.5, &[2, 3])?;
        let avg = |c: usize| p.average.iter().find(|s| s.cells == c).copied().context("average");
        let (a2, a3) = (avg(2)?, avg(3)?);
        let ratio = a3.g / p.g_ref(a3.a_eff);
        let label = format!("a/h = {m}");
        conv.push((p.h / PENNY_A, (ratio - 1.0).abs()));
        out.note(format!(
            "a/h = {m} (h = {:.4} mm, {} equations, {:.1} s): σ = F/section = {:.3} MPa, R_eff = {:.3} mm; opening region {:.2} mm² \
             (quarter disc {:.2}); whole-front average (3-cell domain): a_eff = {:.4} mm, G = {:.5e}, Sneddon × cylinder factor \
             {:.4} at a_eff/R_eff = {:.4}: {:.5e} ({:+.2} %); J̄ against Sneddon's for the nominal a = 10 (J̄ ∝ G a): {:+.2} %; 2-cell domain {:+.3} % from the 3-cell one",
            p.h,
            p.equations,
            p.fea_seconds,
            p.sigma,
            p.r_eff,
            p.opening_area,
            std::f64::consts::PI * PENNY_A * PENNY_A / 4.0,
            a3.a_eff,
            a3.g,
            penny_cylinder_factor(a3.a_eff / p.r_eff),
            a3.a_eff / p.r_eff,
            p.g_ref(a3.a_eff),
            100.0 * (ratio - 1.0),
            100.0 * (a3.g * a3.a_eff / (p.g_ref(PENNY_A) * PENNY_A) - 1.0),
            100.0 * (a2.g / a3.g - 1.0)
        ));
        let stations: Vec<&FrontStation> = p.stations.iter().filter(|s| s.cells == 3).collect();
        let mut line = Vec::new();
        let mut worst: f64 = 0.0;
        for s in &stations {
            let r = s.g / p.g_ref(s.a_eff);
            worst = worst.max((r - 1.0).abs());
            line.push((s.theta.to_degrees(), r));
        }
        out.note(format!(
            "a/h = {m}, stations every 22.5° (hats of ±22.5°, 3-cell domain): G/G_ref(a_eff) = {} — largest deviation {:.1} % (reported, not checked: the staircase front, docs/verification.md)",
            line.iter().map(|(t, r)| format!("{r:.3} at {t}°")).collect::<Vec<_>>().join(", "),
            100.0 * worst
        ));
        // Mirror symmetry of the model about the plane x = y: station θ and 90° − θ.
        let n = stations.len();
        let asym = (0..n).map(|k| (stations[k].g - stations[n - 1 - k].g).abs() / stations[k].g).fold(0.0, f64::max);
        // Stations with hats of ±Δ every Δ are a partition of unity: their J̄ add up to the average's.
        let partition = (stations.iter().map(|s| s.jbar).sum::<f64>() - a3.jbar).abs() / a3.jbar;
        if m >= 12.5 {
            out.measure("average_g", &label, a3.g, p.g_ref(a3.a_eff));
            out.measure("domain_independence", &label, a2.g, a3.g);
            out.measure("mirror_symmetry", &label, asym, 0.0);
            out.measure("partition", &label, partition, 0.0);
        }
        curves.push(Series::line(&format!("a/h = {m}"), line).with_markers());
    }
    curves.push(Series::reference("Sneddon × cylinder factor", vec![(0.0, 1.0), (90.0, 1.0)]));
    out.figure(
        "fea_penny_3d_front.png",
        "Penny crack (eighth model, hex8 FEA): G along the front from the 3D EDI with radial virtual extension and hats of ±22.5° in θ, \
         over Sneddon's G × the finite-cylinder factor at the staircase's ψ-weighted radius a_eff, per mesh. The whole-front \
         average is the checked value; the per-station scatter is the staircase front (see the case notes).",
        PlotSpec::new("Penny crack: G(θ)/G_ref along the front", "θ (degrees)", "G / G_ref(a_eff)"),
        Plot::Lines(curves),
    );
    if conv.len() > 1 {
        out.figure(
            "fea_penny_3d_convergence.png",
            "Penny crack: |front-average G / G_ref − 1| against h/a.",
            PlotSpec::new("Penny crack: front-average G error vs h/a", "h / a", "|G/G_ref − 1|"),
            Plot::Convergence { points: conv, label: "hex8, whole-front average".into() },
        );
    }
    Ok(out)
}

// ---------------------------------------------------------------------------------------
// 3D DCB
// ---------------------------------------------------------------------------------------

/// Width of `verification/fea_dcb_3d.toml` (mm) and the load per arm (N).
pub const DCB3_B: f64 = 12.0;
pub const DCB3_P: f64 = 12.0;

/// The 3D DCB at cell size `h` (dividing 2 mm) with the crack end moved by `da` cells
/// (0: the nodes x = 50 are the front). The crack keeps the triangulation this case has
/// always had (2 mm past the side faces, `edge` half a cell; the file's is the MPM
/// front of `front_j_dcb`): the FEA meshes the same nodes either way, and the golden
/// fingerprint of the built scenes stays.
pub fn dcb3_scene(h: f64, da: i32) -> SceneFile {
    let end = 50.0 - 0.5 * h + da as f64 * h;
    let crack = format!("[[-2.0, 12.0, -2.0], [-2.0, 12.0, 14.0], [{end:?}, 12.0, 14.0], [{end:?}, 12.0, -2.0]]");
    SceneFile::new("fea_dcb_3d.toml")
        .set("grid.cell", format!("[{h:?}, {h:?}, {h:?}]"))
        .set("grid.origin", format!("[{0:?}, {0:?}, {0:?}]", -2.0 * h))
        .set("grid.size", format!("[{:?}, {:?}, {:?}]", 100.0 + 4.0 * h, 24.0 + 4.0 * h, 12.0 + 4.0 * h))
        .set("loads.0.particles", format!("{{ box = {{ min = [0.0, 12.0, 0.0], max = [{:?}, 24.0, 12.0] }} }}", 0.5 * h))
        .set("loads.1.particles", format!("{{ box = {{ min = [0.0, 0.0, 0.0], max = [{:?}, 12.0, 12.0] }} }}", 0.5 * h))
        .set("cracks.0.surface.polygon.points", crack)
        .set("cracks.0.edge", format!("{:?}", 0.5 * h))
}

/// Corrected beam theory G per unit width of a DCB with load P/B per arm (Williams 1989,
/// χ = 0.6688 as in the 2D `dcb_k` case), E the Young's modulus (free anticlastic bending).
pub fn dcb3_g_beam(a: f64, e: f64) -> f64 {
    use super::fracture::{ARM, CHI};
    12.0 * (DCB3_P / DCB3_B).powi(2) * (a + CHI * ARM).powi(2) / (e * ARM.powi(3))
}

/// One 3D DCB solve set at cell size h.
#[derive(Clone, Debug)]
pub struct Dcb3 {
    pub h: f64,
    pub equations: usize,
    /// (z, J with the ≈ 4 mm domain, J with the ≈ 8 mm domain) per front node.
    pub front: Vec<(f64, f64, f64)>,
    /// ∫ J dz = Σ J_k ∫ψ_k dz (exact for the EDI: the hats are a partition of unity).
    pub j_width: f64,
    /// dU/da at fixed load by central differences of the FEA strain energy at a ± h.
    pub du_da: f64,
    pub e: f64,
    pub seconds: f64,
}

/// One hex8 solve of a 3D DCB scene at cell size h.
#[derive(Clone, Debug)]
pub struct Dcb3Solve {
    /// x of the front nodes (the first unsplit node plane).
    pub front_x: f64,
    /// (z, J with the ≈ 4 mm domain, J with the ≈ 8 mm domain) per front node.
    pub front: Vec<(f64, f64, f64)>,
    pub strain_energy: f64,
    pub equations: usize,
    pub e: f64,
}

/// Solve a 3D DCB scene (a straight front along z on one node plane x) with hex8 and
/// read J at its front nodes.
pub fn dcb3_solve(file: &SceneFile, h: f64) -> anyhow::Result<Dcb3Solve> {
    dcb3_solve_domains(file, [(4.0 / h).round() as usize, (8.0 / h).round() as usize])
}

/// [`dcb3_solve`] with J read from domains of `cells[0]` and `cells[1]` cells (at most
/// 8 each, the FEA's largest).
pub fn dcb3_solve_domains(file: &SceneFile, cells: [usize; 2]) -> anyhow::Result<Dcb3Solve> {
    let fea = SceneFea3::from_scene(&file.load3()?)?;
    let an = fea.analyse()?;
    let [c1, c2] = cells;
    let front_x = an.front.first().context("no front node")?.position[0];
    let mut front = Vec::new();
    for f in &an.front {
        anyhow::ensure!(f.position[0] == front_x, "front node at x = {}, another at {front_x}", f.position[0]);
        let j = |c: usize| f.domains.iter().find(|d| d.cells == c).map(|d| d.j).with_context(|| format!("no {c}-cell J at z = {}: {:?}", f.position[2], f.skipped));
        front.push((f.position[2], j(c1)?, j(c2)?));
    }
    Ok(Dcb3Solve { front_x, front, strain_energy: an.strain_energy, equations: an.equations, e: fea.materials[0].e })
}

pub fn dcb3(h: f64) -> anyhow::Result<Dcb3> {
    let t = std::time::Instant::now();
    let d = dcb3_solve(&dcb3_scene(h, 0), h)?;
    anyhow::ensure!(d.front_x == 50.0, "front at x = {}", d.front_x);
    let j_width = d.front.iter().map(|&(z, _, j)| j * if z == 0.0 || z == DCB3_B { 0.5 * h } else { h }).sum();
    let u_minus = dcb3_solve(&dcb3_scene(h, -1), h)?.strain_energy;
    let u_plus = dcb3_solve(&dcb3_scene(h, 1), h)?.strain_energy;
    Ok(Dcb3 {
        h,
        equations: d.equations,
        front: d.front,
        j_width,
        du_da: (u_plus - u_minus) / (2.0 * h),
        e: d.e,
        seconds: t.elapsed().as_secs_f64(),
    })
}

/// Case `fea_dcb_3d`.
pub fn run_dcb3(variant: Variant) -> anyhow::Result<CaseOutput> {
    let hs: &[f64] = match variant {
        Variant::Quick => &[2.0],
        Variant::Full => &[2.0, 1.0],
    };
    let mut out = CaseOutput::default();
    let mut series = Vec::new();
    for &h in hs {
        let d = dcb3(h)?;
        let a = super::fracture::a_of(h);
        let g_beam = dcb3_g_beam(a, d.e);
        let label = format!("h = {h} mm");
        let mid = d.front.iter().find(|f| f.0 == 0.5 * DCB3_B).context("no front node at mid-width")?;
        out.measure("energy_balance", &label, d.j_width, d.du_da);
        out.measure("mid_width_low", &label, mid.2 / g_beam, 1.0);
        out.measure("mid_width_high", &label, mid.2 / g_beam, 1.15);
        out.measure("domain_independence", &format!("{label}, mid-width"), mid.1, mid.2);
        let asym = d.front.iter().zip(d.front.iter().rev()).map(|(p, q)| (p.2 - q.2).abs() / mid.2).fold(0.0, f64::max);
        out.measure("width_symmetry", &label, asym, 0.0);
        out.note(format!(
            "h = {h} mm ({} equations, 3 solves, {:.1} s): a = {a} mm, beam theory G = {g_beam:.5e} N/mm (E; ×{:.4} with E/(1 − ν²)); \
             J at mid-width {:.5e} ({:.4} × beam), width average ∫J dz/B {:.5e} ({:.4} × beam), at the side faces {:.5e} ({:.4} × beam); \
             ∫J dz = {:.5e} N vs dU/da = {:.5e} N ({:+.2} %)",
            d.equations,
            d.seconds,
            1.0 / (1.0 - 0.33f64.powi(2)),
            mid.2,
            mid.2 / g_beam,
            d.j_width / DCB3_B,
            d.j_width / DCB3_B / g_beam,
            d.front[0].2,
            d.front[0].2 / g_beam,
            d.j_width,
            d.du_da,
            100.0 * (d.j_width / d.du_da - 1.0)
        ));
        series.push(Series::line(&format!("FEA J, h = {h} mm (≈ 8 mm domain)"), d.front.iter().map(|f| (f.0, f.2)).collect()).with_markers());
        if h == hs[hs.len() - 1] {
            series.push(Series::reference("corrected beam theory, E", vec![(0.0, g_beam), (DCB3_B, g_beam)]));
            let plate = g_beam / (1.0 - 0.33f64.powi(2));
            series.push(Series::reference("corrected beam theory, E/(1 − ν²)", vec![(0.0, plate), (DCB3_B, plate)]));
        }
    }
    out.note(
        "MPM J across the width of this scene file, plotted with the FEA's: case front_j_dcb (full suite; the MPM run is about \
         10⁸ particle-steps).",
    );
    out.figure(
        "fea_dcb_3d_width.png",
        "3D DCB with free sides (B = 12 mm = arm thickness): FEA J at the front nodes across the width, with corrected beam theory \
         (χ = 0.6688) for free (E) and suppressed (E/(1 − ν²)) anticlastic bending. The MPM J beside it: case front_j_dcb.",
        PlotSpec::new("3D DCB: J across the width", "z (mm)", "J (N/mm)"),
        Plot::Lines(series),
    );
    Ok(out)
}

// ---------------------------------------------------------------------------------------
// MPM against FEA in 3D
// ---------------------------------------------------------------------------------------

/// `verification/mpm_vs_fea_3d.toml`; `shorter` moves the crack end one cell towards the
/// loaded end (the negative control's FEA).
pub fn mpm_vs_fea_3d_scene(shorter: bool) -> SceneFile {
    let end = if shorter { 27.0 } else { 29.0 };
    SceneFile::new("mpm_vs_fea_3d.toml")
        .set("cracks.0.surface.polygon.points", format!("[[-2.0, 0.0, -1.0], [-2.0, 0.0, 5.0], [{end:?}, 0.0, 5.0], [{end:?}, 0.0, -1.0]]"))
}

/// The MPM run, the FEA of the same scene and of the crack one cell shorter, compared at
/// mid-width (z = 2).
pub struct MpmVsFea3 {
    pub comparison: crate::fea::compare3::LineComparison3,
    pub negative: crate::fea::compare3::LineComparison3,
    pub mpm_strain_energy: f64,
    pub mpm_kinetic: f64,
    pub fea_strain_energy: f64,
    pub steps: u64,
    pub mpm_seconds: f64,
    pub particles: usize,
}

pub fn mpm_vs_fea_3d() -> anyhow::Result<MpmVsFea3> {
    use crate::fea::compare3::compare_ahead_of_front;
    let scene = mpm_vs_fea_3d_scene(false).load3()?;
    let t = std::time::Instant::now();
    let mut sim = scene.build()?;
    sim.run_until(scene.solver.end_time, |_| {})?;
    let mpm_seconds = t.elapsed().as_secs_f64();
    let fea_at = |s: &crate::scene3d::Scene3| -> anyhow::Result<(SceneFea3, crate::fea::scene3::FeaAnalysis3)> {
        let fea = SceneFea3::from_scene(s)?;
        let an = fea.analyse()?;
        Ok((fea, an))
    };
    let mid = |fea: &SceneFea3, x: f64| -> anyhow::Result<usize> {
        fea.cracks[0].front.iter().position(|f| f.position.z == 2.0 && f.position.x == x).context("no front node at z = 2")
    };
    let (fea, an) = fea_at(&scene)?;
    let comparison = compare_ahead_of_front(&sim, &fea, &an.solution, 0, mid(&fea, 30.0)?)?;
    let (fea_s, an_s) = fea_at(&mpm_vs_fea_3d_scene(true).load3()?)?;
    let negative = compare_ahead_of_front(&sim, &fea_s, &an_s.solution, 0, mid(&fea_s, 28.0)?)?;
    let e = sim.energies();
    Ok(MpmVsFea3 {
        comparison,
        negative,
        mpm_strain_energy: e.strain,
        mpm_kinetic: e.kinetic,
        fea_strain_energy: an.strain_energy,
        steps: sim.step_count,
        mpm_seconds,
        particles: sim.particles.len(),
    })
}

/// Case `mpm_vs_fea_3d` (the scene file as is in both variants).
pub fn run_mpm_vs_fea_3d(_variant: Variant) -> anyhow::Result<CaseOutput> {
    let r = mpm_vs_fea_3d()?;
    let (c, n) = (&r.comparison, &r.negative);
    let mut out = CaseOutput::default();
    let at = |p: [f64; 3]| format!("worst at x = {}", p[0]);
    out.measure("syy_line", &at(c.max_diff_at), c.max_diff / c.peak, f64::NAN);
    out.measure("static_reached", "MPM ½Σσ:ε V vs FEA ½fᵀu", r.mpm_strain_energy, r.fea_strain_energy);
    out.measure("negative_control", &format!("FEA crack one cell shorter, {}", at(n.max_diff_at)), n.max_diff / n.peak, f64::NAN);
    out.note(format!(
        "MPM: {} particles, {} steps to t = 140 ms in {:.1} s (checked); kinetic energy {:.2e}, strain energy {:.5e} vs FEA {:.5e} \
         ({:+.3} %). σyy at the front node: MPM {:.4e}, FEA (eq. 11) {:.4e} ({:.1} % of the peak, excluded).",
        r.particles,
        r.steps,
        r.mpm_seconds,
        r.mpm_kinetic,
        r.mpm_strain_energy,
        r.fea_strain_energy,
        100.0 * (r.mpm_strain_energy / r.fea_strain_energy - 1.0),
        c.rows.iter().find(|x| x.is_front).map_or(f64::NAN, |x| x.mpm),
        c.rows.iter().find(|x| x.is_front).map_or(f64::NAN, |x| x.fea_eq11),
        100.0 * c.front_diff / c.peak
    ));
    let curve = |f: fn(&crate::fea::compare3::LineRow3) -> f64| c.rows.iter().map(|x| (x.position[0], f(x))).collect::<Vec<_>>();
    out.figure(
        "mpm_vs_fea_3d_line.png",
        "σyy along y = 0, z = 2 (mid-width) of the 3D DCB: the damped MPM's particle stresses extrapolated to the nodes (eq. 11), \
         the static hex8 FEA field averaged the same way (checked pairing) and its nodal average. Upper crack face for x < 30, \
         ligament beyond; the front node x = 30 is excluded from the check.",
        PlotSpec::new("3D DCB: σyy ahead of the front, MPM vs FEA", "x (mm)", "σyy (MPa)"),
        Plot::Lines(vec![
            Series::line("MPM (eq. 11)", curve(|x| x.mpm)).with_markers(),
            Series::line("FEA averaged like the MPM (eq. 11)", curve(|x| x.fea_eq11)).with_markers(),
            Series::line("FEA nodal-averaged", curve(|x| x.fea_nodal)).with_markers(),
        ]),
    );
    out.data("mpm_vs_fea_3d_line.csv", "σyy per node of the line: MPM (eq. 11), FEA eq. 11, FEA nodal", c.csv());
    Ok(out)
}
