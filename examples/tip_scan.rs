//! Experiment (issue 22 item 1): SENT K_I/K_Tada(a) − 1 with the tip at a = 6 + f·h and
//! the crack line at y = 0 with the grid shifted by dy·h in y, ppc particles per cell.
//! `cargo run --release --example tip_scan -- h ppc dy [f...]`; also prints J/J_Tada on the
//! 2×2 and 3×3 contours, the settled strain energy U (for a static crack without contact a
//! function of which pairs are cut only) and T/U (whether the run reached its static state).
use cramp::fracture::jintegral::{CodMethod, TipEnd};
use cramp::verify::cases::plates::PlateKind;

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    let h: f64 = args.get(1).map_or(Ok(1.0), |s| s.parse())?;
    let ppc: usize = args.get(2).map_or(Ok(2), |s| s.parse())?;
    let dy: f64 = args.get(3).map_or(Ok(0.5), |s| s.parse())?;
    let fs: Vec<f64> = if args.len() > 4 { args[4..].iter().map(|s| s.parse().unwrap()).collect() } else { vec![0.1, 0.25, 0.4, 0.5, 0.6, 0.75, 0.9] };
    let extra: Vec<(String, String)> = std::env::var("SETS").ok().map(|s| s.split(';').filter(|x| !x.is_empty()).map(|kv| { let (k, v) = kv.split_once('=').unwrap(); (k.to_string(), v.to_string()) }).collect()).unwrap_or_default();
    let mut errs = Vec::new();
    for f in fs {
        let a = 6.0 + f * h;
        let mut file = PlateKind::Sent.scene_file(h, a, 0.0);
        let y0 = -20.0 - 2.0 * h;
        file = file.set("grid.origin", format!("[{}, {}]", -2.0 * h, y0 - dy * h)).set("grid.size", format!("[{}, {}]", 20.0 + 4.0 * h, 41.0 + 4.0 * h)).set("solver.particles_per_cell", format!("{ppc}"));
        for (k, v) in &extra { file = file.set(k, v.clone()); }
        let scene = file.load()?;
        let mut sim = scene.build()?;
        sim.run_until(scene.solver.end_time, |_| {})?;
        let mut row = Vec::new();
        let mut jr = Vec::new();
        // E′ of the plate's material (E = 1000 MPa, ν = 0.3, plane strain).
        let e_prime = 1000.0 / (1.0 - 0.3 * 0.3);
        for n in [2, 3] {
            let r = sim.tip_fracture(0, TipEnd::End, n, false, CodMethod::NextToTip, 0.0)?;
            row.push(r.k1 / PlateKind::Sent.k_ref(a) - 1.0);
            jr.push(r.j1 * e_prime / PlateKind::Sent.k_ref(a).powi(2));
        }
        let e = sim.energies();
        println!("h {h} ppc {ppc} dy {dy} f {f:.3}: J/J_Tada 2x2 {:.4}  3x3 {:.4}  U {:.9e}  T/U {:.1e}", jr[0], jr[1], e.strain, e.kinetic / e.strain);
        errs.push(row[0]);
        println!("h {h} ppc {ppc} dy {dy} f {f:.3}: K err 2x2 {:+.2}%  3x3 {:+.2}%", 100.0 * row[0], 100.0 * row[1]);
    }
    let (mn, mx) = errs.iter().fold((f64::MAX, f64::MIN), |(a, b), &e| (a.min(e), b.max(e)));
    println!("h {h} ppc {ppc} dy {dy}: min {:+.2}% max {:+.2}% spread {:.2}%", 100.0 * mn, 100.0 * mx, 100.0 * (mx - mn));
    Ok(())
}
