//! Single-mode vibrating bar (references §5.1, closed form). The verification case —
//! period against 4L/c_d and the energy behaviour of every update scheme — is
//! `cramp::verify::cases::vibrating_bar` (cases `vibrating_bar`, `bar_convergence`,
//! `bar_long` of `verification/cases.toml`), run by `tests/golden.rs` and `cramp verify`.
//! This file checks the reference itself.

use cramp::material::Constitutive;
use cramp::scene::Scene;
use cramp::verify::cases::vibrating_bar::{bar_scene, Bar, BarConfig};

/// The closed form's wave speed (written independently in the case) is what the
/// material law uses: plane strain c_d, to 1e-14.
#[test]
fn wave_speed_of_material_is_plane_strain_dilatational() {
    let scene = bar_scene(&BarConfig::base(cramp::simulation::Scheme::Usavg)).unwrap();
    let m = scene.materials()[0];
    let c = Bar::of(&scene).unwrap().wave_speed();
    assert!((m.wave_speed() - c).abs() <= 1e-14 * c, "{} vs {}", m.wave_speed(), c);
}

/// The scene file's rounded k and end time are what `bar_scene` sets exactly.
#[test]
fn scene_file_matches_the_exact_mode() {
    let file = Scene::from_toml(cramp::verify::cases::vibrating_bar::SCENE, "vibrating_bar.toml").unwrap();
    let exact = bar_scene(&BarConfig::base(cramp::simulation::Scheme::Usavg)).unwrap();
    let (k_file, k) =
        (file.bodies[0].velocity_sine.as_ref().unwrap().k[0], exact.bodies[0].velocity_sine.as_ref().unwrap().k[0]);
    assert!((k_file - k).abs() <= 1e-15 * k);
    assert!((file.solver.end_time - exact.solver.end_time).abs() < 1e-5);
}
