//! Helpers shared by several test files (each file under tests/ is its own crate; this
//! module is included with `mod common;`).

use cramp::verify::{self, Variant};

/// The block-on-a-crack scene of the `crack_friction` case at 1 mm cells
/// ([`cramp::verify::cases::cracks::block_on_crack`]): a 20 × 4 mm block pressed onto a
/// fixed 36 × 4 mm base across a horizontal crack on y = 0, total `force` (x, y) on the
/// block's particles ramped over `ramp`, the crack's `contact` law as TOML.
#[allow(dead_code)]
pub fn block_on_crack(force: [f64; 2], ramp: f64, end_time: f64, contact: &str) -> String {
    cramp::verify::cases::cracks::block_on_crack(1.0, force, ramp, end_time, contact)
}

/// Run a verification case of `verification/cases.toml` through the library (as `cramp
/// verify` does), print its table and notes, write its report section (figures and data
/// files) to target/tmp/<case>/, and assert that it passed. The tolerances are the
/// manifest's.
#[allow(dead_code)]
pub fn verify_case(name: &str, variant: Variant) -> verify::CaseResult {
    let case = verify::select(&[name.to_string()], variant).expect("a registered case").remove(0);
    let result = verify::run_case(&case, variant);
    println!("{}", verify::report::text_table(std::slice::from_ref(&result)));
    for n in &result.notes {
        println!("{n}");
    }
    let out = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let problems = verify::report::write_report(&out, std::slice::from_ref(&result), variant, result.wall_s).unwrap();
    println!("report with figures and data in {}", out.display());
    assert!(problems.is_empty(), "{problems:?}");
    assert!(result.passed, "verification case {name} failed: {:?}", result.errors);
    result
}
