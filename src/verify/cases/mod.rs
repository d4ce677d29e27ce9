//! The case functions. Each module holds the library code of one family of cases (the
//! tests in `tests/` call the same functions, so nothing is computed twice); the
//! registry maps the manifest's case names to them.

pub mod boundary;
pub mod chen;
pub mod colliding_disks;
pub mod crack_patch;
pub mod crack_patch_3d;
pub mod crack_friction_3d;
pub mod cracks;
pub mod cracks_3d;
pub mod fea;
pub mod fea3d;
pub mod fracture;
pub mod front3;
pub mod front_dcb;
pub mod front_dynamic;
pub mod front_path;
pub mod growth;
pub mod growth3;
pub mod growth3_examples;
pub mod growth_strip;
pub mod impact;
pub mod plates;
pub mod stability;
pub mod three_d;
pub mod rotation;
pub mod translation;
pub mod vibrating_bar;

use super::Case;
use crate::simulation::Scheme;

/// Every case, in the order of the report. A name here must have a `[[case]]` in
/// `verification/cases.toml` (a unit test checks both directions).
pub const REGISTRY: &[Case] = &[
    Case { name: "vibrating_bar", run: vibrating_bar::run },
    Case { name: "bar_convergence", run: vibrating_bar::run_convergence },
    Case { name: "impact_energy", run: impact::run },
    Case { name: "colliding_disks", run: colliding_disks::run },
    Case { name: "crack_patch", run: crack_patch::run },
    Case { name: "crack_patch_3d", run: crack_patch_3d::run },
    Case { name: "cracked_disks", run: cracks::run_disks },
    Case { name: "crack_friction", run: cracks::run_friction },
    Case { name: "crack_friction_3d", run: crack_friction_3d::run },
    Case { name: "fea_patch", run: fea::run_patch },
    Case { name: "fea_cantilever", run: fea::run_cantilever },
    Case { name: "fea_dcb", run: fea::run_dcb },
    Case { name: "cfl_sweep", run: stability::run_cfl_sweep },
    Case { name: "chen_early_time", run: fracture::run },
    Case { name: "chen_late_time", run: chen::run },
    Case { name: "dcb_k", run: fracture::run_dcb },
    Case { name: "split_beams_k", run: fracture::run_split_beams },
    Case { name: "pmma_tpb", run: growth::run_tpb },
    Case { name: "pmma_tpb_choices", run: growth::run_tpb_choices },
    Case { name: "pmma_tpb_offcentre", run: growth::run_offcentre },
    Case { name: "mode_ii_kink", run: growth::run_mode_ii },
    Case { name: "dcb_growth", run: growth::run_dcb_growth },
    Case { name: "growth_j", run: growth::run_growth_j },
    Case { name: "growth_strip", run: growth_strip::run },
    Case { name: "growth_strip_j", run: growth_strip::run_j },
    Case { name: "plates_k", run: plates::run },
    Case { name: "tip_translation", run: translation::run },
    Case { name: "crack_rotation", run: rotation::run },
    Case { name: "mpm_vs_fea", run: fea::run_mpm_vs_fea },
    Case { name: "fea_penny_3d", run: fea3d::run_penny },
    Case { name: "fea_dcb_3d", run: fea3d::run_dcb3 },
    Case { name: "mpm_vs_fea_3d", run: fea3d::run_mpm_vs_fea_3d },
    Case { name: "boundary_motion", run: boundary::run },
    Case { name: "bar_3d", run: three_d::run_bar },
    Case { name: "spheres_3d", run: three_d::run_spheres },
    Case { name: "block_3d", run: three_d::run_block },
    Case { name: "extrusion_2d_3d", run: three_d::run_extrusion },
    Case { name: "cracks_2d_3d", run: cracks_3d::run_2d_3d },
    Case { name: "front_j_slab", run: front3::run_slab },
    Case { name: "front_j_penny", run: front3::run_penny },
    Case { name: "front_j_inclined", run: front3::run_inclined },
    Case { name: "front_growth_slab", run: growth3::run_slab },
    Case { name: "front_growth_penny", run: growth3::run_penny },
    Case { name: "front_growth_ellipse", run: growth3::run_ellipse },
    Case { name: "front_growth_inclined", run: growth3::run_inclined },
    Case { name: "dcb_growth_3d", run: growth3::run_dcb3 },
    Case { name: "corner_crack_rod", run: growth3_examples::run_rod },
    Case { name: "tube_crack", run: growth3_examples::run_tube },
    Case { name: "front_j_path", run: front_path::run },
    Case { name: "front_j_dcb", run: front_dcb::run },
    Case { name: "front_k_dynamic", run: front_dynamic::run },
    Case { name: "cracked_spheres_3d", run: cracks_3d::run_spheres },
    Case { name: "bar_long", run: vibrating_bar::run_long },
    Case { name: "dcb_long", run: fracture::run_dcb_long },
    Case { name: "squashed_disk", run: stability::run_squashed_disk },
];

/// The four update schemes, in the order of Nairn 2003 §2.3.
pub const SCHEMES: [Scheme; 4] = [Scheme::Usl, Scheme::Musl, Scheme::Usf, Scheme::Usavg];

/// The scheme's name as in scene files.
pub fn scheme_name(s: Scheme) -> &'static str {
    match s {
        Scheme::Usl => "usl",
        Scheme::Musl => "musl",
        Scheme::Usf => "usf",
        Scheme::Usavg => "usavg",
    }
}

/// Neumaier-compensated sum (relative error ~1e-16 for the sums of the cases, far below
/// any tolerance; cheaper than the correctly rounded sums of the solver).
pub fn csum(terms: impl Iterator<Item = f64>) -> f64 {
    let (mut s, mut c) = (0.0f64, 0.0f64);
    for x in terms {
        let t = s + x;
        c += if s.abs() >= x.abs() { (s - t) + x } else { (x - t) + s };
        s = t;
    }
    s + c
}
