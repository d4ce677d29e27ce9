//! The verification suite: named cases, each a scene (or a small FE model) plus a
//! manifest entry saying what it checks, against which independent reference, with
//! which tolerance and why that tolerance is fair.
//!
//! * The **manifest**, `verification/cases.toml`, is the human-readable half and the
//!   single source of every tolerance: one `[[case]]` table per case with its
//!   description, reference and citation, what the quick and full variants run, and one
//!   `[[case.check]]` per compared quantity (`compare` kind, `tolerance`, `why`).
//! * The **code** half is one function per case in [`cases`], `fn(Variant) ->
//!   anyhow::Result<CaseOutput>`: it runs the scene through the library and returns
//!   [`Measurement`]s (a value and its reference, tagged with the check id), plus
//!   optional figures, notes and run-time sweeps. It never decides pass or fail.
//! * [`run_case`] evaluates every measurement against its manifest check. A check with
//!   no measurement fails (an empty check would pass vacuously), and so does a
//!   measurement naming a check the manifest does not have.
//!
//! `cramp verify [--quick] [CASE…]` runs cases and writes `reports/` ([`report`]);
//! `tests/golden.rs` runs every quick case, asserts it passes and snapshots its headline
//! numbers ([`headline`]) into `golden/`. The golden snapshot only guards against
//! regressions; the reference is always the manifest's.
//!
//! ## Adding a case
//!
//! 1. Put its scene in `verification/` (if it is an MPM scene).
//! 2. Add a `[[case]]` table to `verification/cases.toml` with its checks.
//! 3. Write `src/verify/cases/<name>.rs` with `pub fn run(variant: Variant) ->
//!    anyhow::Result<CaseOutput>` returning one [`Measurement`] (or more, with labels)
//!    per check, and register it in [`cases::REGISTRY`].
//! 4. If it is in the quick suite, add a `golden_case!` line to `tests/golden.rs`, run
//!    `INSTA_UPDATE=always cargo test --release --test golden` once, and commit the new
//!    file in `golden/` with the reason in the commit message.
//!
//! `docs/verification.md` says the same with an example.

pub mod cases;
pub mod compare;
pub mod manifest;
pub mod report;
pub mod scene_file;

use crate::report::plot::{PlotSpec, Series};
use anyhow::{anyhow, bail};
use manifest::{Check, CompareKind, Manifest};
use serde::Serialize;
use std::time::Instant;

/// Which resolution of a case to run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Variant {
    /// Coarse, for CI and `cargo run --release` (the whole quick suite in minutes).
    Quick,
    /// Finer cells, more configurations, long runs.
    Full,
}

/// One measured quantity of a case, compared by the runner against its manifest check.
#[derive(Clone, Debug, Serialize)]
pub struct Measurement {
    /// The id of a `[[case.check]]` of the manifest.
    pub check: String,
    /// Which instance of the check (a scheme, a mesh, …); empty if there is one.
    pub label: String,
    pub value: f64,
    /// The independent reference value (a closed form, a conservation law's 0, a bound's
    /// theoretical value); for `at_most` / `at_least` checks the tolerance is the bound.
    pub reference: f64,
}

impl Measurement {
    pub fn new(check: &str, label: &str, value: f64, reference: f64) -> Self {
        Measurement { check: check.to_string(), label: label.to_string(), value, reference }
    }
}

/// The data of one figure of the report.
#[derive(Clone, Debug)]
pub enum Plot {
    /// Named x–y series on linear axes ([`crate::report::plot::line_plot`]).
    Lines(Vec<Series>),
    /// Named x–y series, linear x and logarithmic y (every y > 0;
    /// [`crate::report::plot::semilog_y_plot`]).
    LogY(Vec<Series>),
    /// Error versus cell size on log–log axes with the fitted order.
    Convergence { points: Vec<(f64, f64)>, label: String },
    /// Run time versus error with the Pareto front marked.
    Pareto(Vec<(f64, f64, String)>),
    /// A particle snapshot: (x, y, value) coloured by value, with polylines (cracks)
    /// over it ([`crate::report::particles::particle_plot`]; the spec's title and width are used).
    Particles { particles: Vec<(f64, f64, f64)>, lines: Vec<Vec<(f64, f64)>>, value_label: String },
    /// 3D crack surfaces, one panel per time, in an oblique projection coloured by the
    /// tilt from the view's axis ([`crate::report::surface3::surface_panels`]; the spec's
    /// title and width are used).
    Surfaces { panels: Vec<crate::report::surface3::SurfacePanel>, view: crate::report::surface3::View, columns: usize },
}

/// A figure: a PNG file name (within the report directory), a caption and its data.
#[derive(Clone, Debug)]
pub struct Figure {
    pub file: String,
    pub caption: String,
    pub spec: PlotSpec,
    pub plot: Plot,
}

/// One configuration of a cost–accuracy sweep: what was run, its wall time and error.
#[derive(Clone, Debug, Serialize)]
pub struct SweepPoint {
    pub config: String,
    pub wall_s: f64,
    pub error: f64,
}

/// A data file of the report (a CSV of a figure's numbers, say): its file name within
/// the report directory, a one-line description and its contents.
#[derive(Clone, Debug)]
pub struct DataFile {
    pub file: String,
    pub caption: String,
    pub contents: String,
}

/// What a case function returns: measurements (never pass/fail), figures, notes
/// (Markdown lines for the report), sweeps, data files.
#[derive(Clone, Debug, Default)]
pub struct CaseOutput {
    pub measurements: Vec<Measurement>,
    pub figures: Vec<Figure>,
    pub notes: Vec<String>,
    pub sweep: Vec<SweepPoint>,
    pub data: Vec<DataFile>,
}

impl CaseOutput {
    pub fn measure(&mut self, check: &str, label: &str, value: f64, reference: f64) {
        self.measurements.push(Measurement::new(check, label, value, reference));
    }
    pub fn note(&mut self, text: impl Into<String>) {
        self.notes.push(text.into());
    }
    pub fn figure(&mut self, file: &str, caption: &str, spec: PlotSpec, plot: Plot) {
        self.figures.push(Figure { file: file.to_string(), caption: caption.to_string(), spec, plot });
    }
    pub fn data(&mut self, file: &str, caption: &str, contents: String) {
        self.data.push(DataFile { file: file.to_string(), caption: caption.to_string(), contents });
    }
}

/// A case of the registry: its name (as in the manifest) and its function.
#[derive(Clone, Copy, Debug)]
pub struct Case {
    pub name: &'static str,
    pub run: fn(Variant) -> anyhow::Result<CaseOutput>,
}

/// One row of the results table: a measurement evaluated against its check.
#[derive(Clone, Debug, Serialize)]
pub struct Row {
    pub check: String,
    pub label: String,
    pub quantity: String,
    pub compare: CompareKind,
    pub value: f64,
    pub reference: f64,
    /// |value − reference| / |reference| (relative), |value − reference| (absolute), or
    /// the value itself (at_most / at_least).
    pub error: f64,
    pub tolerance: f64,
    pub pass: bool,
}

/// The outcome of running one case.
#[derive(Clone, Debug, Serialize)]
pub struct CaseResult {
    pub name: String,
    pub variant: Variant,
    pub passed: bool,
    pub wall_s: f64,
    /// Why the case failed to run (a simulation error, a check without measurement, …).
    pub errors: Vec<String>,
    pub rows: Vec<Row>,
    /// The bit fingerprint of every simulation the case ran, in order
    /// ([`crate::fingerprint`]).
    #[serde(skip)]
    pub fingerprints: Vec<u64>,
    /// Every simulation the case ran, in the same order: its scene (for `cramp verify
    /// --export`) and whether it ran checked.
    #[serde(skip)]
    pub simulations: Vec<crate::fingerprint::Recorded>,
    pub sweep: Vec<SweepPoint>,
    #[serde(skip)]
    pub figures: Vec<Figure>,
    #[serde(skip)]
    pub notes: Vec<String>,
    #[serde(skip)]
    pub data: Vec<DataFile>,
}

/// Evaluate a measurement against its check: (error, pass). NaN never passes.
pub fn evaluate(check: &Check, value: f64, reference: f64) -> (f64, bool) {
    let tol = check.tolerance;
    match check.compare {
        CompareKind::Relative => {
            let e = (value - reference).abs() / reference.abs();
            (e, e <= tol)
        }
        CompareKind::Absolute => {
            let e = (value - reference).abs();
            (e, e <= tol)
        }
        CompareKind::AtMost => (value, value <= tol),
        CompareKind::AtLeast => (value, value >= tol),
    }
}

/// The names of all registered cases, in registry order.
pub fn case_names() -> Vec<&'static str> {
    cases::REGISTRY.iter().map(|c| c.name).collect()
}

/// Resolve case names (empty: every case of the variant's suite). Unknown names, or a
/// full-only case asked for in the quick suite, are errors listing the valid names.
pub fn select(names: &[String], variant: Variant) -> anyhow::Result<Vec<Case>> {
    let manifest = Manifest::get()?;
    if names.is_empty() {
        return Ok(cases::REGISTRY
            .iter()
            .copied()
            .filter(|c| variant == Variant::Full || manifest.case(c.name).map(|m| m.quick.is_some()).unwrap_or(false))
            .collect());
    }
    let mut out = Vec::new();
    for n in names {
        let Some(case) = cases::REGISTRY.iter().find(|c| c.name == n) else {
            bail!("unknown verification case '{n}'; the cases are: {}", case_names().join(", "));
        };
        if variant == Variant::Quick && manifest.case(n).map(|m| m.quick.is_none()).unwrap_or(true) {
            bail!("case '{n}' is in the full suite only (it has no quick variant); run it without --quick");
        }
        out.push(*case);
    }
    Ok(out)
}

/// Run one case and evaluate its measurements against the manifest.
pub fn run_case(case: &Case, variant: Variant) -> CaseResult {
    let start = Instant::now();
    let recorder = crate::fingerprint::Recorder::start();
    let output = (case.run)(variant);
    let recorded = recorder.finish();
    let fingerprints = recorded.iter().map(|r| r.fingerprint).collect();
    let wall_s = start.elapsed().as_secs_f64();
    let mut result = CaseResult {
        name: case.name.to_string(),
        variant,
        passed: false,
        wall_s,
        errors: Vec::new(),
        rows: Vec::new(),
        fingerprints,
        simulations: recorded,
        sweep: Vec::new(),
        figures: Vec::new(),
        notes: Vec::new(),
        data: Vec::new(),
    };
    let manifest = match Manifest::get().and_then(|m| {
        m.case(case.name)
            .cloned()
            .ok_or_else(|| anyhow!("case '{}' has no [[case]] in verification/cases.toml", case.name))
    }) {
        Ok(m) => m,
        Err(e) => {
            result.errors.push(format!("{e:#}"));
            return result;
        }
    };
    let out = match output {
        Ok(o) => o,
        Err(e) => {
            result.errors.push(format!("the case did not run to completion: {e:#}"));
            return result;
        }
    };
    for m in &out.measurements {
        let Some(check) = manifest.checks.iter().find(|c| c.id == m.check) else {
            result
                .errors
                .push(format!("measurement '{}' names no check of case '{}' in the manifest", m.check, case.name));
            continue;
        };
        let (error, pass) = evaluate(check, m.value, m.reference);
        result.rows.push(Row {
            check: m.check.clone(),
            label: m.label.clone(),
            quantity: check.quantity.clone(),
            compare: check.compare,
            value: m.value,
            reference: m.reference,
            error,
            tolerance: check.tolerance,
            pass,
        });
    }
    for c in &manifest.checks {
        if !out.measurements.iter().any(|m| m.check == c.id) {
            result.errors.push(format!("check '{}' was not measured", c.id));
        }
    }
    result.passed = result.errors.is_empty() && result.rows.iter().all(|r| r.pass);
    result.figures = out.figures;
    result.notes = out.notes;
    result.sweep = out.sweep;
    result.data = out.data;
    result
}

/// Round to `digits` significant digits (0 keeps the value as is); used for the golden
/// snapshots so that round-off in the last bits does not make them brittle.
pub fn round_sig(x: f64, digits: u32) -> f64 {
    if x == 0.0 || !x.is_finite() || digits == 0 {
        return x;
    }
    let s = format!("{:.*e}", digits as usize - 1, x);
    s.parse().unwrap_or(x)
}

/// The headline numbers of a result for the golden snapshot: per row the check, label,
/// pass flag and the value rounded as the manifest's `golden_digits` says (checks with
/// `golden_digits = 0`, round-off-level quantities, keep only the pass flag). Wall times
/// are left out. The `fingerprint` is the hash of the exact final state of every
/// simulation the case ran ([`crate::fingerprint`]): any moved bit shows up there even
/// when the rounded values do not change.
pub fn headline(result: &CaseResult) -> anyhow::Result<serde_json::Value> {
    let manifest = Manifest::get()?;
    let case = manifest.case(&result.name).ok_or_else(|| anyhow!("no manifest entry for {}", result.name))?;
    let rows: Vec<serde_json::Value> = result
        .rows
        .iter()
        .map(|r| {
            let digits = case.checks.iter().find(|c| c.id == r.check).map(|c| c.golden_digits).unwrap_or(4);
            let mut v = serde_json::json!({ "check": r.check, "label": r.label, "pass": r.pass });
            if digits > 0 {
                v["value"] = serde_json::json!(round_sig(r.value, digits));
            }
            v
        })
        .collect();
    Ok(
        serde_json::json!({
            "case": result.name,
            "variant": result.variant,
            "passed": result.passed,
            "errors": result.errors,
            "rows": rows,
            "fingerprint": {
                "simulations": result.fingerprints.len(),
                "bits": format!("{:016x}", crate::fingerprint::combine(&result.fingerprints)),
            },
        }),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_registered_case_has_a_manifest_entry_and_back() {
        let m = Manifest::get().unwrap();
        for c in cases::REGISTRY {
            assert!(m.case(c.name).is_some(), "case '{}' has no [[case]] in verification/cases.toml", c.name);
        }
        for c in &m.cases {
            assert!(
                cases::REGISTRY.iter().any(|r| r.name == c.name),
                "manifest case '{}' is not in cases::REGISTRY",
                c.name
            );
            for s in &c.scenes {
                let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("verification").join(s);
                assert!(path.is_file(), "case '{}' names scene {s}, which is not in verification/", c.name);
            }
        }
    }

    /// Every scene the manifest lists is a valid scene that builds.
    #[test]
    fn manifest_scenes_build() {
        for c in &Manifest::get().unwrap().cases {
            for s in &c.scenes {
                let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("verification").join(s);
                match crate::scene3d::AnyScene::from_file(&path).unwrap_or_else(|e| panic!("{s}: {e}")) {
                    crate::scene3d::AnyScene::D2(scene) => drop(scene.build().unwrap_or_else(|e| panic!("{s}: {e}"))),
                    crate::scene3d::AnyScene::D3(scene) => drop(scene.build().unwrap_or_else(|e| panic!("{s}: {e}"))),
                }
            }
        }
    }

    #[test]
    fn evaluation_follows_the_compare_kind() {
        let check = |compare, tolerance| Check {
            id: "x".into(),
            quantity: String::new(),
            compare,
            tolerance,
            why: String::new(),
            golden_digits: 4,
        };
        assert!(evaluate(&check(CompareKind::Relative, 0.01), 1.005, 1.0).1);
        assert!(!evaluate(&check(CompareKind::Relative, 0.01), 1.02, 1.0).1);
        assert!(evaluate(&check(CompareKind::Absolute, 0.0), 0.0, 0.0).1);
        assert!(!evaluate(&check(CompareKind::Absolute, 0.0), 1e-300, 0.0).1);
        assert!(evaluate(&check(CompareKind::AtMost, 1.0), 1.0, f64::NAN).1);
        assert!(!evaluate(&check(CompareKind::AtLeast, 1.0), 0.5, f64::NAN).1);
        for kind in [CompareKind::Relative, CompareKind::Absolute, CompareKind::AtMost, CompareKind::AtLeast] {
            assert!(!evaluate(&check(kind, 1.0), f64::NAN, 1.0).1, "NaN passed a {kind:?} check");
        }
    }

    #[test]
    fn rounding_keeps_significant_digits() {
        assert_eq!(round_sig(0.000123456, 3), 0.000123);
        assert_eq!(round_sig(-98765.4, 2), -99000.0);
        assert_eq!(round_sig(0.0, 3), 0.0);
    }

    #[test]
    fn unknown_and_full_only_cases_are_clear_errors() {
        let e = select(&["nope".into()], Variant::Quick).unwrap_err().to_string();
        assert!(e.contains("unknown verification case 'nope'") && e.contains("vibrating_bar"), "{e}");
        let e = select(&["bar_long".into()], Variant::Quick).unwrap_err().to_string();
        assert!(e.contains("full suite only"), "{e}");
        assert!(select(&["bar_long".into()], Variant::Full).is_ok());
    }

    /// A case whose measurement names no check, or which leaves a check unmeasured, fails.
    #[test]
    fn unmeasured_and_unknown_checks_fail_the_case() {
        fn bogus(_: Variant) -> anyhow::Result<CaseOutput> {
            let mut o = CaseOutput::default();
            o.measure("no_such_check", "", 1.0, 1.0);
            Ok(o)
        }
        let r = run_case(&Case { name: "fea_patch", run: bogus }, Variant::Quick);
        assert!(!r.passed);
        assert!(r.errors.iter().any(|e| e.contains("no_such_check")));
        assert!(r.errors.iter().any(|e| e.contains("'displacement' was not measured")));
        fn failing(_: Variant) -> anyhow::Result<CaseOutput> {
            anyhow::bail!("simulated failure")
        }
        let r = run_case(&Case { name: "fea_patch", run: failing }, Variant::Quick);
        assert!(!r.passed && r.errors[0].contains("simulated failure"));
    }
}
