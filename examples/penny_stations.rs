//! Per-station G along the FEA penny front against Sneddon × the cylinder factor
//! (issue 18 item 3): `cargo run --release --example penny_stations -- A_CELLS [STEP_DEG]`.
use cramp::verify::cases::fea3d::penny;

fn main() -> anyhow::Result<()> {
    let mut args = std::env::args().skip(1);
    let a_cells: f64 = args.next().unwrap_or_else(|| "12.5".into()).parse()?;
    let step: f64 = args.next().unwrap_or_else(|| "22.5".into()).parse()?;
    let p = penny(a_cells, step, &[2, 3])?;
    println!("a/h = {a_cells}: {} equations, FEA {:.1} s", p.equations, p.fea_seconds);
    for s in p.stations.iter().chain(&p.average) {
        println!(
            "cells {} theta {:6.2} deg: a_eff/a {:.4}  G/G_ref(a_eff) {:.4}",
            s.cells,
            s.theta.to_degrees(),
            s.a_eff / 10.0,
            s.g / p.g_ref(s.a_eff)
        );
    }
    Ok(())
}
