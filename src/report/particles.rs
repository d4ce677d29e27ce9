//! Particle snapshots for the reports: material points drawn as dots coloured by a
//! scalar (a stress component, say) on equal x and y scales, optionally with polylines
//! (cracks) drawn over them, and a colour bar. Drawn with plotters and the bundled font
//! of [`super::plot`].

use super::plot::{format_sig, register_bundled_font, FONT};
use anyhow::{ensure, Context, Result};
use plotters::prelude::*;
use std::path::Path;

/// A colour on a blue–white–red scale for t in [0, 1] (diverging, readable on white
/// dots' neighbours; 0.5 is light grey so that zero stress stands out in a symmetric range).
pub fn diverging(t: f64) -> RGBColor {
    let t = if t.is_finite() { t.clamp(0.0, 1.0) } else { 0.5 };
    let (lo, mid, hi) = ((59.0, 76.0, 192.0), (221.0, 221.0, 221.0), (180.0, 4.0, 38.0));
    let (a, b, s) = if t < 0.5 { (lo, mid, t / 0.5) } else { (mid, hi, (t - 0.5) / 0.5) };
    let mix = |x: f64, y: f64| (x + (y - x) * s).round() as u8;
    RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

/// Draw particles `(x, y, value)` coloured by value on a symmetric range ±max|value|
/// (blue negative, red positive), with `lines` (e.g. crack polylines) in black, into a
/// PNG of the given width; the height follows the data's aspect ratio. `value_label`
/// names the colour bar. Errors on no particles or a non-finite coordinate.
pub fn particle_plot(
    path: impl AsRef<Path>,
    title: &str,
    value_label: &str,
    particles: &[(f64, f64, f64)],
    lines: &[Vec<(f64, f64)>],
    width: u32,
) -> Result<()> {
    let path = path.as_ref();
    ensure!(!particles.is_empty(), "particle plot '{title}': no particles");
    ensure!(
        particles.iter().all(|p| p.0.is_finite() && p.1.is_finite()),
        "particle plot '{title}': a non-finite position"
    );
    register_bundled_font()?;
    let (mut x0, mut x1, mut y0, mut y1) = (f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY, f64::NEG_INFINITY);
    for p in particles.iter().map(|p| (p.0, p.1)).chain(lines.iter().flatten().copied()) {
        x0 = x0.min(p.0);
        x1 = x1.max(p.0);
        y0 = y0.min(p.1);
        y1 = y1.max(p.1);
    }
    let pad = 0.04 * (x1 - x0).max(y1 - y0).max(1e-12);
    let (x0, x1, y0, y1) = (x0 - pad, x1 + pad, y0 - pad, y1 + pad);
    let vmax = particles.iter().map(|p| p.2.abs()).filter(|v| v.is_finite()).fold(0.0, f64::max);
    // Plot area: width minus label areas and colour bar; height from the aspect ratio.
    let (left, bottom, bar, top) = (80u32, 55u32, 110u32, 50u32);
    let plot_w = width.saturating_sub(left + bar + 20).max(100);
    let plot_h = ((plot_w as f64) * (y1 - y0) / (x1 - x0)).round().clamp(100.0, 1400.0) as u32;
    let size = (width, plot_h + bottom + top + 20);
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    let root = BitMapBackend::new(path, size).into_drawing_area();
    root.fill(&WHITE)?;
    let (main, bar_area) = root.split_horizontally(size.0 - bar);
    let mut chart = ChartBuilder::on(&main)
        .caption(title, (FONT, 22))
        .margin(10)
        .x_label_area_size(bottom)
        .y_label_area_size(left)
        .build_cartesian_2d(x0..x1, y0..y1)?;
    chart
        .configure_mesh()
        .x_desc("x")
        .y_desc("y")
        .label_style((FONT, 14))
        .axis_desc_style((FONT, 16))
        .x_label_formatter(&|v| format_sig(*v, 3))
        .y_label_formatter(&|v| format_sig(*v, 3))
        .light_line_style(WHITE)
        .draw()?;
    let radius = ((plot_w as f64) / (particles.len() as f64).sqrt() / 3.0).clamp(1.0, 4.0) as i32;
    let scale = |v: f64| if vmax > 0.0 { 0.5 + 0.5 * v / vmax } else { 0.5 };
    chart.draw_series(particles.iter().map(|p| Circle::new((p.0, p.1), radius, diverging(scale(p.2)).filled())))?;
    for line in lines {
        chart.draw_series(LineSeries::new(line.iter().copied(), BLACK.stroke_width(2)))?;
    }
    // Colour bar: 100 bands from −vmax (bottom) to +vmax (top).
    let bar_area = bar_area.margin(top + 10, bottom + 10, 10, 10);
    let (bw, bh) = bar_area.dim_in_pixel();
    let bands = 100;
    for k in 0..bands {
        let t = k as f64 / (bands - 1) as f64;
        let y_top = bh as i32 - ((k + 1) as f64 * bh as f64 / bands as f64).round() as i32;
        let y_bot = bh as i32 - (k as f64 * bh as f64 / bands as f64).round() as i32;
        bar_area.draw(&Rectangle::new([(0, y_top), (22, y_bot)], diverging(t).filled()))?;
    }
    let font = (FONT, 14).into_font();
    bar_area.draw(&Text::new(format_sig(vmax, 3), (26, 0), font.clone()))?;
    bar_area.draw(&Text::new("0".to_string(), (26, bh as i32 / 2 - 7), font.clone()))?;
    bar_area.draw(&Text::new(format_sig(-vmax, 3), (26, bh as i32 - 14), font.clone()))?;
    let _ = bw;
    root.draw(&Text::new(
        value_label.to_string(),
        ((size.0 - bar + 5) as i32, (top - 15) as i32),
        (FONT, 15).into_font(),
    ))?;
    root.present().with_context(|| format!("writing {}", path.display()))
}
