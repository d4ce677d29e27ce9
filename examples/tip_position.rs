//! Where the crack tip sits in its cell (issue 22 item 1, measurement only): the static
//! SENT plate of case `plates_k` (W = 20 mm, 2×2 particles per cell, ramped and damped
//! tension, K_I from the 2×2-contour J) with the tip at a = 6 + f·h for fractions f of a
//! cell, the crack on a grid line and mid-cell, K_I (2×2, 3×3 and 4×4 contours) against
//! Tada's K for the same a.
//! The grid and the particles stay put; only the crack moves, so the body is discretised
//! the same in every run (shifting the whole scene instead also changes which particle
//! rows fall inside the body at f = 0.25, 0.75 with 2×2 particles, which is a separate
//! effect).
//!
//! `cargo run --release --example tip_position [h]` (default h = 1 mm; ~3 s per run).

use cramp::fracture::jintegral::{CodMethod, TipEnd};
use cramp::verify::cases::plates::PlateKind;

fn main() -> anyhow::Result<()> {
    let h: f64 = std::env::args().nth(1).map_or(Ok(1.0), |s| s.parse())?;
    println!("SENT, h = {h} mm: K_I / K_Tada(a) − 1 for the tip at a = 6 + f·h");
    println!("{:>6}   {:>26}   {:>26}", "f", "grid line: 2×2, 3×3, 4×4", "mid-cell: 2×2, 3×3, 4×4");
    for f in [0.1, 0.25, 0.4, 0.5, 0.6, 0.75, 0.9] {
        let a = 6.0 + f * h;
        let mut row = Vec::new();
        for mid_cell in [false, true] {
            let mut file = PlateKind::Sent.scene_file(h, a, 0.0);
            if mid_cell {
                // The grid half a cell lower: y = 0 (the crack) between node rows; the
                // body's edges y = ±20 then lie mid-cell too, and the 2×2 particles still
                // fill it exactly.
                let y0 = -20.0 - 2.0 * h;
                file = file.set("grid.origin", format!("[{}, {}]", -2.0 * h, y0 - 0.5 * h)).set("grid.size", format!("[{}, {}]", 20.0 + 4.0 * h, 41.0 + 4.0 * h));
            }
            let scene = file.load()?;
            let mut sim = scene.build()?;
            sim.run_until(scene.solver.end_time, |_| {})?;
            for n in [2, 3, 4] {
                let k = sim.tip_fracture(0, TipEnd::End, n, false, CodMethod::NextToTip, 0.0)?.k1;
                row.push(k / PlateKind::Sent.k_ref(a) - 1.0);
            }
        }
        let pct = |v: &[f64]| v.iter().map(|e| format!("{:+.2}%", 100.0 * e)).collect::<Vec<_>>().join(" ");
        println!("{f:>6}   {:>26}   {:>26}", pct(&row[..3]), pct(&row[3..]));
    }
    Ok(())
}
