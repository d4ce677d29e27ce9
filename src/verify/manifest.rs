//! The case manifest, `verification/cases.toml`, compiled into the binary so `cramp
//! verify` works from any directory. See the file itself for the format; every field
//! is required except where noted, and unknown fields are rejected.

use anyhow::Context;
use serde::{Deserialize, Serialize};
use std::sync::OnceLock;

/// The manifest text.
pub const TEXT: &str = include_str!("../../verification/cases.toml");

/// How a measured value is compared with its reference.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CompareKind {
    /// |value − reference| ≤ tolerance · |reference|.
    Relative,
    /// |value − reference| ≤ tolerance.
    Absolute,
    /// value ≤ tolerance (a bound; the reference column shows the theoretical value).
    AtMost,
    /// value ≥ tolerance.
    AtLeast,
}

impl CompareKind {
    /// How the tolerance reads in the tables, e.g. "≤ 5e-3 rel".
    pub fn describe(&self, tol: f64) -> String {
        let t = super::report::num(tol);
        match self {
            CompareKind::Relative => format!("≤ {t} rel"),
            CompareKind::Absolute => format!("≤ {t} abs"),
            CompareKind::AtMost => format!("value ≤ {t}"),
            CompareKind::AtLeast => format!("value ≥ {t}"),
        }
    }

    /// Whether the error column means anything (bounds compare the value itself).
    pub fn has_error(&self) -> bool {
        matches!(self, CompareKind::Relative | CompareKind::Absolute)
    }
}

/// One compared quantity of a case.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Check {
    /// Identifier the case function uses in its measurements.
    pub id: String,
    /// What is compared, in words (shown in the table).
    pub quantity: String,
    pub compare: CompareKind,
    pub tolerance: f64,
    /// Why the tolerance is fair: the size of the expected error and what a bug would give.
    pub why: String,
    /// Significant digits kept in the golden snapshot (default 4; 0 keeps only pass/fail,
    /// for round-off-level quantities).
    #[serde(default = "default_digits")]
    pub golden_digits: u32,
}

fn default_digits() -> u32 {
    4
}

/// One case.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CaseEntry {
    pub name: String,
    pub title: String,
    /// What the case checks, in a paragraph.
    pub what: String,
    /// The independent reference (closed form, conservation law, data) in words.
    pub reference: String,
    /// Where the reference comes from.
    pub citation: String,
    /// Scene files in `verification/` (empty for FE-only cases).
    #[serde(default)]
    pub scenes: Vec<String>,
    /// What the quick variant runs; absent: the case is in the full suite only.
    pub quick: Option<String>,
    /// What the full variant runs.
    pub full: String,
    #[serde(rename = "check")]
    pub checks: Vec<Check>,
}

/// The whole manifest.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Manifest {
    #[serde(rename = "case")]
    pub cases: Vec<CaseEntry>,
}

impl Manifest {
    /// Parse manifest text.
    pub fn parse(text: &str) -> anyhow::Result<Manifest> {
        let m: Manifest = toml::from_str(text).context("verification/cases.toml is not a valid manifest")?;
        for c in &m.cases {
            anyhow::ensure!(!c.checks.is_empty(), "manifest case '{}' has no [[case.check]]", c.name);
            for k in &c.checks {
                anyhow::ensure!(
                    k.tolerance.is_finite(),
                    "manifest case '{}' check '{}': tolerance must be finite",
                    c.name,
                    k.id
                );
            }
        }
        Ok(m)
    }

    /// The compiled-in manifest, parsed once.
    pub fn get() -> anyhow::Result<&'static Manifest> {
        static M: OnceLock<Result<Manifest, String>> = OnceLock::new();
        M.get_or_init(|| Manifest::parse(TEXT).map_err(|e| format!("{e:#}")))
            .as_ref()
            .map_err(|e| anyhow::anyhow!(e.clone()))
    }

    pub fn case(&self, name: &str) -> Option<&CaseEntry> {
        self.cases.iter().find(|c| c.name == name)
    }
}
