//! Pure mode II with and without crack-face contact (issue 22 item 3, measurement): the
//! equal-shear split beam ("ENF") of case `split_beams_k` at cell size h, damped to rest,
//! K_I/K_II and the opening δ_I with `contact = "none"` and `"frictionless"` (detected by
//! the nodal volume and by the surfaces' opening).
//!
//! `cargo run --release --example mode_ii_contact [h]` (default 2 mm).

use cramp::verify::cases::fracture::{beam, split_contour, WHOLE_BEAM};

fn main() -> anyhow::Result<()> {
    let h: f64 = std::env::args().nth(1).map_or(Ok(2.0), |s| s.parse())?;
    for (contact, detection) in [("none", "volume"), ("frictionless", "volume"), ("frictionless", "opening")] {
        for cod in ["next_to_tip", "fit"] {
            let scene = beam(h, 1.0, 1.0, contact, split_contour(h), WHOLE_BEAM)
                .set("cracks.0.fracture.cod", format!("\"{cod}\""))
                .set("cracks.0.detection", format!("\"{detection}\""))
                .load()?;
            let r = cramp::output::run_scene(&scene, &cramp::output::RunOptions { checked: Some(false), ..Default::default() })?;
            let t = r.tips.last().expect("a cracks.csv row");
            println!("h = {h} mm, contact {contact:>12} ({detection:>7}), cod {cod:>11}: K_I/K_II = {:+.4}, K_II = {:.4}, δ_I = {:+.3e}, δ_II = {:+.3e}, J = {:.5e}", t.k1 / t.k2, t.k2, t.delta_i, t.delta_ii, t.j1);
        }
    }
    Ok(())
}
