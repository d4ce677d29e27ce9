//! The crack-tip zone (`solver.tip_zone`, src/crack/tip_zone.rs; issue 22 item 1): with it,
//! K_I of a static crack no longer depends on where the tip sits in its cell.
//!
//! The static SENT plate of case `plates_k` (W = 20 mm, a ≈ 6 mm, h = 1 mm: 6 cells per
//! crack length, 2×2 particles per cell), its crack between node rows (the grid half a
//! cell lower), the tip at a = 6 + f·h for f = 0.1 … 0.9 with the grid and particles
//! fixed. Reference: Tada, Paris & Irwin's K_I(a) for each a (verification references
//! §1(d)). Measured with a one-cell zone: −2.6 … −0.5 % (spread 2.05 %; at h = 0.5 mm
//! −1.5 … −0.4 %, spread 1.1 %, first order in h); with CRAMP's all-or-nothing pairs
//! −0.4 … +6.5 % (spread 6.9 %; 3.6 % at h = 0.5 mm).
//! Tolerance 3 %: the zone's error at this resolution (2.6 %) plus room for the
//! contour's own ±0.3 % (2×2 against 3×3); the same check without the zone fails at
//! f = 0.25 (+6.5 %), the negative control below.

use cramp::fracture::jintegral::{CodMethod, TipEnd};
use cramp::verify::cases::plates::PlateKind;

fn k_error(f: f64, zone: f64) -> f64 {
    k_error_at(f, zone, 0.5)
}

/// K_I/K_Tada − 1 with the crack `dy` cells above a node row (0: on it, 0.5: mid-cell).
fn k_error_at(f: f64, zone: f64, dy: f64) -> f64 {
    let h = 1.0;
    let a = 6.0 + f * h;
    let file = PlateKind::Sent
        .scene_file(h, a, 0.0)
        .set("grid.origin", format!("[{}, {}]", -2.0 * h, -20.0 - (2.0 + dy) * h))
        .set("grid.size", format!("[{}, {}]", 20.0 + 4.0 * h, 41.0 + 4.0 * h))
        .set("solver.tip_zone", zone);
    let scene = file.load().expect("scene");
    let mut sim = scene.build().expect("build");
    sim.run_until(scene.solver.end_time, |_| {}).expect("run");
    let k = sim.tip_fracture(0, TipEnd::End, 2, false, CodMethod::NextToTip, 0.0).expect("J").k1;
    k / PlateKind::Sent.k_ref(a) - 1.0
}

#[test]
fn k_does_not_depend_on_the_tip_position_in_its_cell() {
    let errors: Vec<(f64, f64)> = [0.1, 0.25, 0.5, 0.75, 0.9].iter().map(|&f| (f, k_error(f, 1.0))).collect();
    for &(f, e) in &errors {
        println!("tip at 6 + {f} h: K_I / K_Tada − 1 = {:+.2} %", 100.0 * e);
    }
    for &(f, e) in &errors {
        assert!(e.abs() <= 0.03, "tip at 6 + {f} h: K_I off Tada by {:+.2} % (> 3 %)", 100.0 * e);
    }
    // Negative control: CRAMP's pairs at f = 0.25.
    let control = k_error(0.25, 0.0);
    println!("without the zone, f = 0.25: {:+.2} %", 100.0 * control);
    assert!(control.abs() > 0.03, "the check cannot tell the zone from none: {:+.2} %", 100.0 * control);
}

/// The same SENT with its crack along a node row (every verified 2D case has its crack on
/// a grid line). CRAMP's rule splits every particle of a node on the crack and none of a
/// node ahead of the tip, so the crack ends at a node: K_I +27.8 % (f = 0.05) … −3.4 %
/// (f = 0.95) without the zone. With a one-cell zone the nodes on the line share each
/// particle by its own place along the crack (tip_zone::on_line); measured over
/// f = 0.05 … 0.95 in steps of 0.05: −0.56 … +4.49 % (h = 1 mm; at h = 0.5 mm, seven
/// positions, −0.66 … +2.05 %). Tolerance 5 %: that error at this resolution plus the
/// contour's ±0.3 %; issue 22's goal of 1 % is not met (the module doc of
/// crack::tip_zone says what is left). Negative control: no zone at f = 0.05.
#[test]
fn crack_on_a_node_row_follows_its_tip() {
    let errors: Vec<(f64, f64)> = [0.05, 0.25, 0.4, 0.75, 0.95].iter().map(|&f| (f, k_error_at(f, 1.0, 0.0))).collect();
    for &(f, e) in &errors {
        println!("node row, tip at 6 + {f} h: K_I / K_Tada − 1 = {:+.2} %", 100.0 * e);
    }
    for &(f, e) in &errors {
        assert!(e.abs() <= 0.05, "node row, tip at 6 + {f} h: K_I off Tada by {:+.2} % (> 5 %)", 100.0 * e);
    }
    let control = k_error_at(0.05, 0.0, 0.0);
    println!("without the zone, f = 0.05: {:+.2} %", 100.0 * control);
    assert!(control.abs() > 0.05, "the check cannot tell the zone from none: {:+.2} %", 100.0 * control);
}
