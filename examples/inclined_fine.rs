//! Experiment (issue 16 item 4): the inclined penny of `front_j_inclined` at a/h = N
//! (default 10), its crack plane moved to stay midway between particle planes.
//! `cargo run --release --example inclined_fine -- A_CELLS CENTER_Z [STEPS_ONLY]`
use cramp::verify::cases::front3::{inclined, inclined_scene, InclinedGeometry};

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    let a_cells: f64 = args.get(1).map_or(Ok(10.0), |s| s.parse())?;
    let cz: f64 = args.get(2).map_or(Ok(0.25), |s| s.parse())?;
    let g = 45f64.to_radians();
    let file = inclined_scene(a_cells).set("cracks.0.surface.disc.center", format!("[0.0, 0.0, {cz:?}]")).set("solver.checked", "false").set("solver.damping_on", if std::env::var("GRID_DAMPING").is_ok() { "\"grid\"" } else { "\"particles\"" });
    if args.get(3).is_some() {
        let s = file.load3()?;
        let mut sim = s.build()?;
        sim.options.checked = false;
        let t = std::time::Instant::now();
        for _ in 0..10 { sim.step()?; }
        println!("{} particles, dt {}, end {}, 10 steps {:.2} s", sim.particles.len(), sim.options.dt, s.solver.end_time, t.elapsed().as_secs_f64());
        return Ok(());
    }
    let geom = InclinedGeometry { centre: cramp::dim::Vector3::new(0.0, 0.0, cz), ..InclinedGeometry::oblique() };
    let r = inclined(file, geom)?;
    let n = r.front.len() as f64;
    let amp = {
        let a = cramp::verify::cases::front3::kassir_sih(r.sigma, 10.0, g, r.nu, 0.0);
        let b = cramp::verify::cases::front3::kassir_sih(r.sigma, 10.0, g, r.nu, 0.5 * std::f64::consts::PI);
        [a[0], a[1], b[2]]
    };
    let amp_fit = |k: &dyn Fn(usize) -> f64, f: &dyn Fn(f64) -> f64| {
        let num: f64 = (0..r.theta.len()).map(|i| k(i) * f(r.theta[i])).sum();
        let den: f64 = r.theta.iter().map(|&t| f(t) * f(t)).sum();
        num / den
    };
    for (name, ks) in [("domain", r.front_domain.iter().map(|f| f.k).collect::<Vec<_>>()), ("interaction", r.front_interaction.iter().map(|f| f.k).collect()), ("contour", r.front.iter().map(|f| f.k).collect()), ("r->0", r.k0.clone())] {
        let k1 = ks.iter().map(|k| k[0]).sum::<f64>() / n;
        let k2 = amp_fit(&|i| ks[i][1], &|t| t.cos());
        let k3 = amp_fit(&|i| ks[i][2], &|t| t.sin());
        println!("{name}: K_I avg {:+.2} %, K_II amp {:+.2} %, K_III amp {:+.2} %", 100.0 * (k1 / amp[0] - 1.0), 100.0 * (k2 / amp[1] - 1.0), 100.0 * (k3 / amp[2] - 1.0));
    }
    let g_of = |k: &[f64; 3]| (1.0 - r.nu * r.nu) * (k[0] * k[0] + k[1] * k[1]) / r.e + (1.0 + r.nu) * k[2] * k[2] / r.e;
    let gref = r.k_ref.iter().map(g_of).sum::<f64>() / n;
    println!("J1/G domain {:.4}, r->0 {:.4}; settled {:+.2e}; KE/SE {:.2e} near {:.2e}; {} particles x {} steps {:.0} s; front {} nodes", r.front_domain.iter().map(|f| f.j1).sum::<f64>() / n / gref, r.j0.iter().sum::<f64>() / n / gref, r.settled, r.kinetic_ratio, r.kinetic_ratio_near, r.particles, r.steps, r.seconds, r.front.len());
    for (i, f) in r.front_domain.iter().enumerate() {
        println!("node {i} theta {:.1} K {:?} interaction {:?} ref {:?}", r.theta[i].to_degrees(), f.k, r.front_interaction[i].k, r.k_ref[i]);
    }
    Ok(())
}
