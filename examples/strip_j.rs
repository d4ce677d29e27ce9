//! Experiment (issue 20 item 2): the two-term J of a crack driven at a prescribed speed
//! through the pre-strained strip of `growth_strip` (L = 200 mm to 0.235 ms), against
//! 2H·W0, with a chosen growth increment and extra scene settings.
//! `SETS="solver.tip_zone=1" cargo run --release --example strip_j -- h fraction increment`
use cramp::fracture::speed::rayleigh_speed_for;
use cramp::material::Constitutive;
use cramp::verify::cases::growth::run_growth_file;
use cramp::verify::cases::growth_strip::{self as gs, Faces};

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    let h: f64 = args.get(1).map_or(Ok(1.0), |s| s.parse())?;
    let fraction: f64 = args.get(2).map_or(Ok(0.4), |s| s.parse())?;
    let inc: f64 = args.get(3).map_or(Ok(0.5), |s| s.parse())?;
    let extra: Vec<(String, String)> = std::env::var("SETS").ok().map(|s| s.split(';').filter(|x| !x.is_empty()).map(|kv| { let (k, v) = kv.split_once('=').unwrap(); (k.to_string(), v.to_string()) }).collect()).unwrap_or_default();
    let c_r = rayleigh_speed_for(&gs::MATERIAL).expect("wave speeds");
    let (da, dt) = (inc * h, gs::CFL * h / gs::MATERIAL.wave_speed());
    let n = (da / (fraction * c_r * dt)).round().max(1.0);
    let vmax = 1.001 * da / (n * dt);
    let end = 0.235;
    let mut file = gs::strip(h, 200.0, Some(fraction), Faces::Opening, end).set("cracks.0.fracture.growth.increment", inc).set("cracks.0.fracture.growth.max_speed", vmax);
    for (k, v) in &extra {
        file = file.set(k, v.clone());
    }
    let (r, wall) = run_growth_file(&file, false)?;
    let s = gs::steady(&r, h, fraction, end - 0.005);
    println!(
        "h {h} v {fraction} c_R inc {inc} ({n} steps each) {:?}: speed {:.3} c_R, {} increments; J/(2H·W0) mean {:.3}, before increment {:.3}; balance {:+.4}, −ΔU {:.3}, ΔT {:.3}; {wall:.1} s",
        extra, s.speed, s.increments, s.j_mean, s.j_before_increment, s.balance, s.strain_released, s.kinetic_gained
    );
    Ok(())
}
