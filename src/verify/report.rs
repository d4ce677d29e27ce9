//! The outputs of `cramp verify`: the table on stdout, and in the report directory
//! `index.md` (a section per case with its reference, checks and figures),
//! `results.json` (machine-readable) and the PNG figures.

use super::manifest::Manifest;
use super::{CaseResult, Figure, Plot, Variant};
use crate::report::plot;
use anyhow::Context;
use serde::Serialize;
use std::fmt::Write as _;
use std::path::Path;

/// A number for the tables: 5 significant digits, trailing zeros trimmed, `—` for NaN.
pub fn num(x: f64) -> String {
    if x.is_nan() {
        "—".into()
    } else if x == 0.0 {
        "0".into()
    } else if x.abs() >= 1e-3 && x.abs() < 1e5 {
        plot::format_sig(x, 5)
    } else {
        // 4 decimals of mantissa, trailing zeros trimmed: 1e-12, 2.5e-16, 8.4538e-4.
        let s = format!("{x:.4e}");
        match s.split_once('e') {
            Some((m, e)) if m.contains('.') => format!("{}e{e}", m.trim_end_matches('0').trim_end_matches('.')),
            _ => s,
        }
    }
}

/// The table rows as strings: case, quantity, reference, result, error, tolerance, pass, wall time.
fn table_rows(results: &[CaseResult]) -> Vec<[String; 8]> {
    let mut rows = Vec::new();
    for r in results {
        let wall = format!("{:.2} s", r.wall_s);
        for (k, row) in r.rows.iter().enumerate() {
            let what = if row.label.is_empty() { row.check.clone() } else { format!("{} [{}]", row.check, row.label) };
            let tol = row.compare.describe(row.tolerance);
            let error = if row.compare.has_error() { num(row.error) } else { "—".into() };
            rows.push([
                if k == 0 { r.name.clone() } else { String::new() },
                what,
                num(row.reference),
                num(row.value),
                error,
                tol,
                if row.pass { "pass".into() } else { "FAIL".into() },
                if k == 0 { wall.clone() } else { String::new() },
            ]);
        }
        for e in &r.errors {
            rows.push([
                if r.rows.is_empty() { r.name.clone() } else { String::new() },
                format!("error: {e}"),
                String::new(),
                String::new(),
                String::new(),
                String::new(),
                "FAIL".into(),
                wall.clone(),
            ]);
        }
    }
    rows
}

const HEADER: [&str; 8] = ["case", "quantity", "reference", "result", "error", "tolerance", "pass/fail", "wall time"];

/// The plain-text table for the terminal.
pub fn text_table(results: &[CaseResult]) -> String {
    let rows = table_rows(results);
    let width = |c: usize| {
        rows.iter().map(|r| r[c].chars().count()).chain([HEADER[c].chars().count()]).max().unwrap_or(0).min(70)
    };
    let widths: Vec<usize> = (0..8).map(width).collect();
    let line = |cells: &[String]| {
        let mut s = String::new();
        for (c, cell) in cells.iter().enumerate() {
            let cell: String = if cell.chars().count() > widths[c] {
                cell.chars().take(widths[c] - 1).chain(['…']).collect()
            } else {
                cell.clone()
            };
            let pad = widths[c] - cell.chars().count();
            if (2..=4).contains(&c) {
                s += &format!("{}{}  ", " ".repeat(pad), cell);
            } else {
                s += &format!("{}{}  ", cell, " ".repeat(pad));
            }
        }
        s.trim_end().to_string() + "\n"
    };
    let mut out = line(&HEADER.map(String::from));
    out += &line(&widths.iter().map(|w| "-".repeat(*w)).collect::<Vec<_>>());
    for r in &rows {
        out += &line(r);
    }
    out
}

fn md_escape(s: &str) -> String {
    s.replace('|', "\\|")
}

/// Draw one figure into `dir`.
pub fn draw(dir: &Path, f: &Figure) -> anyhow::Result<()> {
    let path = dir.join(&f.file);
    match &f.plot {
        Plot::Lines(series) => plot::line_plot(&path, &f.spec, series),
        Plot::LogY(series) => plot::semilog_y_plot(&path, &f.spec, series),
        Plot::Convergence { points, label } => plot::loglog_convergence(&path, &f.spec, points, label),
        Plot::Pareto(points) => plot::pareto_plot(&path, &f.spec, points),
        Plot::Particles { particles, lines, value_label } => {
            crate::report::particles::particle_plot(&path, &f.spec.title, value_label, particles, lines, f.spec.size.0)
        }
        Plot::Surfaces { panels, view, columns } => crate::report::surface3::surface_panels(&path, &f.spec.title, panels, *view, *columns, f.spec.size.0),
    }
    .with_context(|| format!("drawing {}", path.display()))
}

#[derive(Serialize)]
struct ResultsJson<'a> {
    variant: Variant,
    passed: bool,
    total_wall_s: f64,
    cases: &'a [CaseResult],
}

/// Write index.md, results.json and the figures into `dir`. A figure that cannot be
/// drawn is reported in the index (and returned as an error list) but does not stop the
/// report.
pub fn write_report(
    dir: &Path,
    results: &[CaseResult],
    variant: Variant,
    total_wall_s: f64,
) -> anyhow::Result<Vec<String>> {
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create report directory {}", dir.display()))?;
    let manifest = Manifest::get()?;
    let passed = results.iter().all(|r| r.passed);
    let mut problems = Vec::new();
    let mut md = String::new();
    let variant_name = match variant {
        Variant::Quick => "quick",
        Variant::Full => "full",
    };
    writeln!(md, "# cramp verification report ({variant_name} suite)\n")?;
    writeln!(
        md,
        "{} of {} cases passed in {:.1} s. Generated by `cramp verify{}` (cramp {}); machine-readable results in \
         [`results.json`](results.json). Each case compares cramp with an independent reference; tolerances and why \
         they are fair come from `verification/cases.toml`.\n",
        results.iter().filter(|r| r.passed).count(),
        results.len(),
        total_wall_s,
        if variant == Variant::Quick { " --quick" } else { "" },
        env!("CARGO_PKG_VERSION")
    )?;
    writeln!(md, "| case | result | checks | wall time |\n|---|---|---|---|")?;
    for r in results {
        let title = manifest.case(&r.name).map(|c| c.title.as_str()).unwrap_or("");
        writeln!(
            md,
            "| [{}](#{}) — {} | {} | {}/{} | {:.2} s |",
            r.name,
            r.name.replace('_', "-"),
            md_escape(title),
            if r.passed { "pass" } else { "**FAIL**" },
            r.rows.iter().filter(|x| x.pass).count(),
            r.rows.len() + r.errors.len(),
            r.wall_s
        )?;
    }
    writeln!(md)?;
    for r in results {
        let Some(c) = manifest.case(&r.name) else { continue };
        writeln!(md, "## {}\n", r.name)?;
        writeln!(md, "**{}** — {}\n", md_escape(&c.title), if r.passed { "pass" } else { "**FAIL**" })?;
        writeln!(md, "{}\n", c.what)?;
        writeln!(md, "* Reference: {}", c.reference)?;
        writeln!(md, "* Citation: {}", c.citation)?;
        if !c.scenes.is_empty() {
            writeln!(
                md,
                "* Scenes: {}",
                c.scenes.iter().map(|s| format!("`verification/{s}`")).collect::<Vec<_>>().join(", ")
            )?;
        }
        let run = match variant {
            Variant::Quick => c.quick.as_deref().unwrap_or(""),
            Variant::Full => &c.full,
        };
        writeln!(md, "* This run ({variant_name}): {run}; wall time {:.2} s\n", r.wall_s)?;
        writeln!(md, "| quantity | reference | result | error | tolerance | |\n|---|---|---|---|---|---|")?;
        for row in &r.rows {
            let what =
                if row.label.is_empty() { row.quantity.clone() } else { format!("{} [{}]", row.quantity, row.label) };
            writeln!(
                md,
                "| {} | {} | {} | {} | {} | {} |",
                md_escape(&what),
                num(row.reference),
                num(row.value),
                if row.compare.has_error() { num(row.error) } else { "—".into() },
                row.compare.describe(row.tolerance),
                if row.pass { "pass" } else { "**FAIL**" }
            )?;
        }
        for e in &r.errors {
            writeln!(md, "| **error**: {} | | | | | **FAIL** |", md_escape(e))?;
        }
        writeln!(md, "\nWhy the tolerances are fair:\n")?;
        for k in &c.checks {
            writeln!(md, "* `{}` ({}): {}", k.id, k.compare.describe(k.tolerance), k.why)?;
        }
        writeln!(md)?;
        for f in &r.figures {
            match draw(dir, f) {
                Ok(()) => writeln!(md, "![{}]({})\n\n*{}*\n", md_escape(&f.spec.title), f.file, f.caption)?,
                Err(e) => {
                    let msg = format!("{}: figure {} not drawn: {e:#}", r.name, f.file);
                    writeln!(md, "**{}**\n", md_escape(&msg))?;
                    problems.push(msg);
                }
            }
        }
        for d in &r.data {
            let path = dir.join(&d.file);
            match std::fs::write(&path, &d.contents) {
                Ok(()) => writeln!(md, "Data: [`{}`]({}) — {}\n", d.file, d.file, d.caption)?,
                Err(e) => {
                    let msg = format!("{}: data file {} not written: {e}", r.name, d.file);
                    writeln!(md, "**{}**\n", md_escape(&msg))?;
                    problems.push(msg);
                }
            }
        }
        if !r.sweep.is_empty() {
            writeln!(md, "<details><summary>Run time and error per configuration</summary>\n")?;
            writeln!(md, "| configuration | wall time (s) | error |\n|---|---|---|")?;
            for s in &r.sweep {
                writeln!(md, "| {} | {:.3} | {} |", s.config, s.wall_s, num(s.error))?;
            }
            writeln!(md, "\n</details>\n")?;
        }
        if !r.notes.is_empty() {
            writeln!(md, "Notes:\n")?;
            for n in &r.notes {
                writeln!(md, "* {n}")?;
            }
            writeln!(md)?;
        }
    }
    let index = dir.join("index.md");
    std::fs::write(&index, md).with_context(|| format!("cannot write {}", index.display()))?;
    let json = serde_json::to_string_pretty(&ResultsJson { variant, passed, total_wall_s, cases: results })?;
    let path = dir.join("results.json");
    std::fs::write(&path, json).with_context(|| format!("cannot write {}", path.display()))?;
    Ok(problems)
}
