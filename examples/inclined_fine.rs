//! Experiment (issue 16 item 4): the inclined penny of `front_j_inclined` at a/h = N
//! (default 10), its crack plane moved to stay midway between particle planes (centre z,
//! default 0.25 for a/h = 10), damping on the particles, unchecked. Prints the case's
//! summaries (front-average K_I, K_II and K_III amplitudes, worst node) per K estimate, and
//! each node. `cargo run --release --example inclined_fine -- A_CELLS CENTER_Z [STEPS_ONLY]`
use cramp::verify::cases::front3::{inclined, inclined_amplitudes, inclined_scene, inclined_summary, InclinedGeometry};

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    let a_cells: f64 = args.get(1).map_or(Ok(10.0), |s| s.parse())?;
    let cz: f64 = args.get(2).map_or(Ok(0.25), |s| s.parse())?;
    let file = inclined_scene(a_cells).set("cracks.0.surface.disc.center", format!("[0.0, 0.0, {cz:?}]")).set("solver.checked", "false");
    if args.get(3).is_some() {
        let s = file.load3()?;
        let mut sim = s.build()?;
        let t = std::time::Instant::now();
        for _ in 0..10 {
            sim.step()?;
        }
        println!("{} particles, dt {}, end {}, 10 steps {:.2} s", sim.particles.len(), sim.options.dt, s.solver.end_time, t.elapsed().as_secs_f64());
        return Ok(());
    }
    let geom = InclinedGeometry { centre: cramp::dim::Vector3::new(0.0, 0.0, cz), ..InclinedGeometry::oblique() };
    let r = inclined(file, geom)?;
    let amp = inclined_amplitudes(&r);
    let pct = |x: f64| 100.0 * (x - 1.0);
    for (name, ks) in [("domain", r.front_domain.iter().map(|f| f.k).collect::<Vec<_>>()), ("interaction", r.front_interaction.iter().map(|f| f.k).collect()), ("contour", r.front.iter().map(|f| f.k).collect()), ("r->0", r.k0.clone())] {
        let (s, w) = inclined_summary(&ks, &r.theta, &r.k_ref, amp);
        println!("{name}: K_I avg {:+.2} %, K_II amp {:+.2} %, K_III amp {:+.2} %; worst node / amplitude {:.1} %, {:.1} %, {:.1} %", pct(s[0]), pct(s[1]), pct(s[2]), 100.0 * w[0], 100.0 * w[1], 100.0 * w[2]);
    }
    let g_of = |k: &[f64; 3]| (1.0 - r.nu * r.nu) * (k[0] * k[0] + k[1] * k[1]) / r.e + (1.0 + r.nu) * k[2] * k[2] / r.e;
    let mean = |x: &mut dyn Iterator<Item = f64>| { let v: Vec<f64> = x.collect(); v.iter().sum::<f64>() / v.len() as f64 };
    println!("front-average J1 / G_ref: domain {:.4}", mean(&mut r.front_domain.iter().map(|f| f.j1)) / mean(&mut r.k_ref.iter().map(g_of)));
    println!("settled {:+.2e}; KE/SE {:.2e} near {:.2e}; {} particles x {} steps {:.0} s; front {} nodes", r.settled, r.kinetic_ratio, r.kinetic_ratio_near, r.particles, r.steps, r.seconds, r.front.len());
    for i in 0..r.front.len() {
        println!("node {i} theta {:.1} K {:?} interaction {:?} ref {:?}", r.theta[i].to_degrees(), r.front_domain[i].k, r.front_interaction[i].k, r.k_ref[i]);
    }
    Ok(())
}
