//! Golden snapshots of the quick verification suite.
//!
//! Each test runs one quick case of `verification/cases.toml` through the library (as
//! `cramp verify --quick CASE` does), asserts that every check passes against its
//! independent reference, and then compares the case's headline numbers — each measured
//! value rounded to the manifest's `golden_digits` significant digits, round-off-level
//! values reduced to their pass flag, no wall times — with the snapshot in
//! `golden/<case>.snap`. The snapshot is never the reference: it only makes a change of
//! the numbers visible, so a regression fails CI. Changing a golden file needs a reason
//! in the commit message.
//!
//! Under CI (`CI=true`) a missing or changed snapshot fails and nothing is written.
//! Locally a change writes `golden/<case>.snap.new` (ignored by git) and fails; accept
//! with `cargo insta review` or `INSTA_UPDATE=always cargo test --release --test golden`.
//!
//! Then every simulation the case ran is exported as a scene file (`cramp verify --export`,
//! [`verify::scene_file::export`]) and run again as `cramp run` runs a file: its final
//! state must have the case's bit fingerprint (issue 21, Verification 3). Every exported
//! scene must come from a file of `verification/` with overrides, not from Rust. The case
//! itself runs once. A simulation of at most [`FULL_REPRODUCTION`] particle-steps is run
//! again to its end; a longer one only over its first [`cramp::fingerprint::EARLY_STEPS`] steps
//! (`cramp run --set solver.end_time=T`), against the case's fingerprint of that state,
//! so that CI does not pay for the expensive runs twice. That checks the file (every field
//! of the scene is in the first step's state) and the runner's stepping; what it leaves
//! to the full export (`cramp verify --quick --export DIR`, then `cramp run` of each file)
//! is a change of the run after that step made in Rust, which a case must not do.

use cramp::verify::scene_file::Reproduce;
use cramp::verify::{self, Variant};

fn golden(name: &str) {
    let case = verify::select(&[name.to_string()], Variant::Quick).expect("a registered quick case").remove(0);
    let result = verify::run_case(&case, Variant::Quick);
    println!("{}", verify::report::text_table(std::slice::from_ref(&result)));
    assert!(result.passed, "verification case {name} failed: {:?}", result.errors);
    let headline = verify::headline(&result).expect("headline numbers");
    insta::with_settings!({ snapshot_path => "../golden", prepend_module_to_snapshot => false, omit_expression => true }, {
        insta::assert_json_snapshot!(name, headline);
    });
    exported_scenes_reproduce(&result);
}

/// Simulations no scene file can describe, with the reason (issue 21 asks to name them).
const NOT_A_SCENE: &[(&str, usize, &str)] = &[(
    "cracked_disks",
    0,
    "the negative control: a copy of the run at 13 ms whose vertical crack's contact is switched off in Rust; \
     the scene language has no contact law that changes in time",
)];

/// Particle-steps up to which an exported simulation is reproduced to its end (a few
/// seconds of running); longer ones are reproduced over their first steps (module
/// documentation).
const FULL_REPRODUCTION: u64 = 4_000_000;

/// Export the case's scenes and run each: same fingerprint as in the case, to the bit.
fn exported_scenes_reproduce(result: &verify::CaseResult) {
    let dir = std::env::temp_dir().join(format!("cramp-golden-export-{}-{}", result.name, std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let exported = verify::scene_file::export(&dir, std::slice::from_ref(result)).expect("the case's scenes export");
    assert_eq!(exported.len(), result.fingerprints.len());
    let mut problems = Vec::new();
    for e in &exported {
        let Some(path) = &e.path else {
            if !NOT_A_SCENE.iter().any(|&(c, i, _)| c == result.name && i == e.index) {
                problems.push(format!("simulation {}: not built from a scene (a copy changed in Rust)", e.index));
            }
            continue;
        };
        if !e.from_file {
            problems.push(format!("simulation {}: scene built in Rust, not from a file of verification/ ({})", e.index, path.display()));
        }
        let (how, expected, what) = match e.early {
            _ if e.built_only => (Reproduce::Built, e.fingerprint, "as built"),
            Some(early) if e.work > FULL_REPRODUCTION => (Reproduce::Until(early.time), early.fingerprint, "after its first steps"),
            _ => (Reproduce::Full, e.fingerprint, "at its end"),
        };
        println!("simulation {} ({} particle-steps): cramp run of {} reproduces the case {what}", e.index, e.work, path.display());
        match verify::scene_file::run_fingerprint(path, how) {
            Ok(f) if f == expected => {}
            Ok(f) => problems.push(format!("simulation {}: cramp run of {} gives fingerprint {f:016x} {what}, the case {expected:016x}", e.index, path.display())),
            Err(err) => problems.push(format!("simulation {}: {} does not run: {err:#}", e.index, path.display())),
        }
    }
    assert!(problems.is_empty(), "case {}: exported scenes do not reproduce its runs:\n{}", result.name, problems.join("\n"));
    let _ = std::fs::remove_dir_all(&dir);
}

macro_rules! golden_case {
    ($($name:ident),* $(,)?) => {
        $(
            #[test]
            fn $name() {
                golden(stringify!($name));
            }
        )*
        /// Every case of the quick suite has a test here (and so a golden file).
        #[test]
        fn every_quick_case_has_a_golden_test() {
            let tested = [$(stringify!($name)),*];
            for case in verify::select(&[], Variant::Quick).unwrap() {
                assert!(tested.contains(&case.name), "quick case '{}' has no golden_case! entry in tests/golden.rs", case.name);
            }
        }
    };
}

golden_case!(
    vibrating_bar,
    bar_convergence,
    impact_energy,
    colliding_disks,
    crack_patch,
    crack_patch_3d,
    cracked_disks,
    crack_friction,
    fea_patch,
    fea_cantilever,
    fea_dcb,
    cfl_sweep,
    chen_early_time,
    chen_late_time,
    dcb_k,
    split_beams_k,
    pmma_tpb,
    pmma_tpb_offcentre,
    mode_ii_kink,
    dcb_growth,
    growth_strip,
    growth_j,
    plates_k,
    mpm_vs_fea,
    fea_penny_3d,
    fea_dcb_3d,
    mpm_vs_fea_3d,
    boundary_motion,
    bar_3d,
    spheres_3d,
    block_3d,
    extrusion_2d_3d,
    cracked_spheres_3d,
    crack_friction_3d,
    front_j_slab,
    front_j_penny,
    front_growth_slab
);
