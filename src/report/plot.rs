//! PNG plots for the reports, drawn with `plotters` on its bitmap backend.
//!
//! Four kinds of plot, each a function taking plain data:
//!
//! * [`line_plot`] — named x–y series on linear axes, optionally with markers,
//!   and reference curves (exact solutions) drawn as dashed black lines;
//!   [`semilog_y_plot`] the same with a logarithmic y axis.
//! * [`loglog_convergence`] — error versus cell size on log–log axes, with the
//!   least-squares power law drawn and its order in the legend ([`fit_order`]).
//! * [`pareto_plot`] — run time versus error on log–log axes with the Pareto
//!   front (the runs no other run beats in both time and error) marked and
//!   connected ([`pareto_front`]).
//!
//! ## Fonts
//!
//! plotters draws text with `ab_glyph` from fonts registered at run time; there
//! is no system font lookup (CI machines may have none). The DejaVu Sans font in
//! `assets/DejaVuSans.ttf` is compiled into the binary with `include_bytes!` and
//! registered once, as family `"sans-serif"`, by [`register_bundled_font`], which
//! every plot function calls first. All text uses [`FONT`]. (Drawing text with
//! an unregistered family fails with `FontUnavailable`.)
//!
//! ## Tick labels
//!
//! Tick values are computed in floating point (`0.1 + 0.2 = 0.30000000000000004`),
//! so every axis gets a label formatter built on [`format_sig`]: a fixed number
//! of significant digits, trailing zeros trimmed, and `1e-3` style outside
//! `[0.01, 10000)`.
//!
//! ## Bad data is an error, not a gap
//!
//! A NaN or infinite value (or a non-positive one on a log axis) makes the plot
//! functions return an error naming the series and the point: in a reference
//! code such a value is a bug to surface, and silently dropping it would make a
//! plot look better than the run was.

use std::ops::Range;
use std::path::Path;
use std::sync::OnceLock;

use anyhow::{anyhow, ensure, Context, Result};
use plotters::coord::combinators::{BindKeyPoints, LogCoord, WithKeyPoints};
use plotters::coord::ranged1d::{Ranged, ValueFormatter};
use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;

/// The font family all text is drawn with; see [`register_bundled_font`].
pub const FONT: &str = "sans-serif";

/// Default image size in pixels.
pub const DEFAULT_SIZE: (u32, u32) = (900, 600);

// Text sizes in pixels.
const TITLE_SIZE: u32 = 26;
const AXIS_DESC_SIZE: u32 = 20;
const TICK_LABEL_SIZE: u32 = 16;
const LEGEND_SIZE: u32 = 17;
const POINT_LABEL_SIZE: u32 = 13;

/// Line colours for the series, in order (the "tab10" palette, without grey and
/// olive, which read poorly on white). Black is kept for reference curves.
const PALETTE: [RGBColor; 8] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(23, 190, 207),
];

// ---------------------------------------------------------------------------
// What to plot
// ---------------------------------------------------------------------------

/// Title, axis labels, size and optional fixed ranges of one plot.
#[derive(Clone, Debug)]
pub struct PlotSpec {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    /// Image size in pixels (width, height); [`DEFAULT_SIZE`] unless changed.
    pub size: (u32, u32),
    /// Fixed x range; `None` fits the data with a little padding.
    pub x_range: Option<(f64, f64)>,
    /// Fixed y range; `None` fits the data with a little padding.
    pub y_range: Option<(f64, f64)>,
    /// Where the legend goes; `None` uses the plot function's default.
    pub legend: Option<LegendPosition>,
}

impl PlotSpec {
    pub fn new(title: &str, x_label: &str, y_label: &str) -> Self {
        PlotSpec {
            title: title.to_string(),
            x_label: x_label.to_string(),
            y_label: y_label.to_string(),
            size: DEFAULT_SIZE,
            x_range: None,
            y_range: None,
            legend: None,
        }
    }

    pub fn with_size(mut self, width: u32, height: u32) -> Self {
        self.size = (width, height);
        self
    }

    pub fn with_x_range(mut self, lo: f64, hi: f64) -> Self {
        self.x_range = Some((lo, hi));
        self
    }

    pub fn with_y_range(mut self, lo: f64, hi: f64) -> Self {
        self.y_range = Some((lo, hi));
        self
    }

    pub fn with_legend(mut self, position: LegendPosition) -> Self {
        self.legend = Some(position);
        self
    }
}

/// Which corner of the plot the legend box goes in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LegendPosition {
    UpperLeft,
    UpperRight,
    LowerLeft,
    LowerRight,
}

impl LegendPosition {
    fn to_plotters(self) -> SeriesLabelPosition {
        match self {
            LegendPosition::UpperLeft => SeriesLabelPosition::UpperLeft,
            LegendPosition::UpperRight => SeriesLabelPosition::UpperRight,
            LegendPosition::LowerLeft => SeriesLabelPosition::LowerLeft,
            LegendPosition::LowerRight => SeriesLabelPosition::LowerRight,
        }
    }
}

/// One named curve of a [`line_plot`].
#[derive(Clone, Debug)]
pub struct Series {
    pub name: String,
    pub points: Vec<(f64, f64)>,
    /// Draw a marker at every point as well as the line.
    pub markers: bool,
    /// A reference curve (e.g. the exact solution): dashed black, no markers.
    pub reference: bool,
}

impl Series {
    /// A coloured line.
    pub fn line(name: &str, points: Vec<(f64, f64)>) -> Self {
        Series {
            name: name.to_string(),
            points,
            markers: false,
            reference: false,
        }
    }

    /// A dashed black reference curve.
    pub fn reference(name: &str, points: Vec<(f64, f64)>) -> Self {
        Series {
            name: name.to_string(),
            points,
            markers: false,
            reference: true,
        }
    }

    /// The same series with a marker at every point.
    pub fn with_markers(mut self) -> Self {
        self.markers = true;
        self
    }
}

// ---------------------------------------------------------------------------
// Numbers behind the plots
// ---------------------------------------------------------------------------

/// Order of convergence p of `error ≈ C h^p`: the least-squares slope of
/// log(error) against log(h), for points `(h, error)`.
///
/// Returns NaN if there are fewer than two points, any h or error is not
/// finite and positive, or all h are equal.
pub fn fit_order(points: &[(f64, f64)]) -> f64 {
    fit_power_law(points).map_or(f64::NAN, |(p, _)| p)
}

/// Least squares of `ln e = ln C + p ln h`; returns `(p, ln C)`.
fn fit_power_law(points: &[(f64, f64)]) -> Option<(f64, f64)> {
    let positive = |v: f64| v.is_finite() && v > 0.0;
    if points.len() < 2 || !points.iter().all(|&(h, e)| positive(h) && positive(e)) {
        return None;
    }
    let logs: Vec<(f64, f64)> = points.iter().map(|&(h, e)| (h.ln(), e.ln())).collect();
    let n = logs.len() as f64;
    let mean_x = logs.iter().map(|l| l.0).sum::<f64>() / n;
    let mean_y = logs.iter().map(|l| l.1).sum::<f64>() / n;
    // Centred sums: accurate even when all h are close to each other.
    let sxx: f64 = logs.iter().map(|&(x, _)| (x - mean_x).powi(2)).sum();
    let sxy: f64 = logs.iter().map(|&(x, y)| (x - mean_x) * (y - mean_y)).sum();
    if sxx == 0.0 {
        return None;
    }
    let p = sxy / sxx;
    Some((p, mean_y - p * mean_x))
}

/// Indices of the Pareto front of `(run time, error, label)` points: the points
/// no other point beats, i.e. no other point has time ≤ and error ≤ with at
/// least one strictly less. Sorted by increasing time (then error, then index),
/// which is the order to connect them in.
///
/// Points with a non-finite time or error are never on the front and never
/// dominate. Identical points do not dominate each other: both are on the front.
pub fn pareto_front<L>(points: &[(f64, f64, L)]) -> Vec<usize> {
    let finite = |i: usize| points[i].0.is_finite() && points[i].1.is_finite();
    let dominates = |j: usize, i: usize| {
        let (tj, ej, ti, ei) = (points[j].0, points[j].1, points[i].0, points[i].1);
        tj <= ti && ej <= ei && (tj < ti || ej < ei)
    };
    let mut front: Vec<usize> = (0..points.len())
        .filter(|&i| finite(i))
        .filter(|&i| !(0..points.len()).any(|j| finite(j) && dominates(j, i)))
        .collect();
    front.sort_by(|&a, &b| {
        (points[a].0, points[a].1)
            .partial_cmp(&(points[b].0, points[b].1))
            .unwrap()
            .then(a.cmp(&b))
    });
    front
}

/// `x` with `sig` significant digits, trailing zeros trimmed; scientific
/// (`1.5e-3`) when |x| < 0.01 or |x| ≥ 10000. `format_sig(0.1 + 0.2, 3) == "0.3"`.
pub fn format_sig(x: f64, sig: usize) -> String {
    if x == 0.0 {
        return "0".to_string();
    }
    if !x.is_finite() {
        return x.to_string();
    }
    let sig = sig.clamp(1, 17);
    let exponent = x.abs().log10().floor() as i32;
    if !(-2..4).contains(&exponent) {
        let s = format!("{:.*e}", sig - 1, x); // e.g. "1.500e-3"
        let (mantissa, exp) = s.split_once('e').expect("{:e} output has an exponent");
        format!("{}e{exp}", trim_zeros(mantissa))
    } else {
        let decimals = (sig as i32 - 1 - exponent).max(0) as usize;
        trim_zeros(&format!("{x:.decimals$}")).to_string()
    }
}

/// A tick label with 3 significant digits (see [`format_sig`]).
pub fn format_tick(x: f64) -> String {
    format_sig(x, 3)
}

/// "1.500" → "1.5", "2.000" → "2", "150" → "150".
fn trim_zeros(s: &str) -> &str {
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.')
    } else {
        s
    }
}

/// Label formatter for a linear axis over `range`: enough significant digits to
/// tell ticks apart (a narrow range far from zero needs more than 3), and
/// round-off next to zero (`5.55e-17`) shown as `0`.
fn linear_tick_formatter(range: &Range<f64>) -> impl Fn(&f64) -> String {
    let span = range.end - range.start;
    let magnitude = range.start.abs().max(range.end.abs());
    let extra = (magnitude.log10().floor() - span.log10().floor()).max(0.0) as usize;
    let sig = (2 + extra).clamp(3, 15);
    move |&x| {
        if x.abs() < span * 1e-9 {
            "0".to_string()
        } else {
            format_sig(x, sig)
        }
    }
}

// ---------------------------------------------------------------------------
// The plots
// ---------------------------------------------------------------------------

/// Named x–y series on linear axes. Reference series are dashed black; the
/// others take colours in order. The legend defaults to the upper right.
pub fn line_plot(path: impl AsRef<Path>, spec: &PlotSpec, series: &[Series]) -> Result<()> {
    ensure!(
        !series.is_empty(),
        "line plot '{}' has no series",
        spec.title
    );
    for s in series {
        check_points(&s.name, &s.points, Axes::Linear)?;
    }
    let all_points = || series.iter().flat_map(|s| s.points.iter());
    let x_range = linear_range(all_points().map(|p| p.0), spec.x_range)?;
    let y_range = linear_range(all_points().map(|p| p.1), spec.y_range)?;

    let root = open_canvas(path.as_ref(), spec)?;
    let mut chart =
        chart_builder(&root, spec).build_cartesian_2d(x_range.clone(), y_range.clone())?;
    draw_mesh(
        &mut chart,
        spec,
        &linear_tick_formatter(&x_range),
        &linear_tick_formatter(&y_range),
    )?;

    draw_series_and_legend(&mut chart, spec, series)?;
    root.present()
        .with_context(|| format!("writing {}", path.as_ref().display()))
}

/// Named x–y series on a linear x and a logarithmic y axis (every y must be positive),
/// for quantities spanning decades, such as energies that decay. Colours and legend as
/// [`line_plot`].
pub fn semilog_y_plot(path: impl AsRef<Path>, spec: &PlotSpec, series: &[Series]) -> Result<()> {
    ensure!(
        !series.is_empty(),
        "semilog plot '{}' has no series",
        spec.title
    );
    for s in series {
        check_points(&s.name, &s.points, Axes::LogY)?;
    }
    let all_points = || series.iter().flat_map(|s| s.points.iter());
    let x_range = linear_range(all_points().map(|p| p.0), spec.x_range)?;
    let y_range = log_range(all_points().map(|p| p.1), spec.y_range)?;

    let root = open_canvas(path.as_ref(), spec)?;
    let mut chart =
        chart_builder(&root, spec).build_cartesian_2d(x_range.clone(), log_axis(&y_range))?;
    draw_mesh(
        &mut chart,
        spec,
        &linear_tick_formatter(&x_range),
        &|y| format_tick(*y),
    )?;

    draw_series_and_legend(&mut chart, spec, series)?;
    root.present()
        .with_context(|| format!("writing {}", path.as_ref().display()))
}

/// Error versus cell size `(h, error)` on log–log axes, with the least-squares
/// power law `C h^p` drawn dashed over the data and "fitted order p = …" in the
/// legend (upper left by default). Needs at least two points with distinct h.
pub fn loglog_convergence(
    path: impl AsRef<Path>,
    spec: &PlotSpec,
    points: &[(f64, f64)],
    label: &str,
) -> Result<()> {
    check_points(label, points, Axes::LogLog)?;
    let (p, ln_c) = fit_power_law(points)
        .ok_or_else(|| anyhow!("'{label}': fitting an order needs two points with distinct h"))?;

    // The fitted line only needs its two ends: it is straight on log–log axes.
    let h_min = points.iter().map(|p| p.0).fold(f64::INFINITY, f64::min);
    let h_max = points.iter().map(|p| p.0).fold(f64::NEG_INFINITY, f64::max);
    let fit = |h: f64| (h, (ln_c + p * h.ln()).exp());
    let fitted = [fit(h_min), fit(h_max)];

    let ys = points.iter().chain(&fitted).map(|p| p.1);
    let x_range = log_range(points.iter().map(|p| p.0), spec.x_range)?;
    let y_range = log_range(ys, spec.y_range)?;

    let root = open_canvas(path.as_ref(), spec)?;
    let mut chart =
        chart_builder(&root, spec).build_cartesian_2d(log_axis(&x_range), log_axis(&y_range))?;
    draw_mesh(&mut chart, spec, &|x| format_tick(*x), &|y| format_tick(*y))?;

    let mut sorted = points.to_vec();
    sorted.sort_by(|a, b| a.0.total_cmp(&b.0));
    draw_line(&mut chart, label, &sorted, PALETTE[0], true)?;
    draw_dashed(
        &mut chart,
        &format!("fitted order p = {p:.2}"),
        &fitted,
        BLACK,
    )?;
    draw_legend(&mut chart, spec.legend.unwrap_or(LegendPosition::UpperLeft))?;
    root.present()
        .with_context(|| format!("writing {}", path.as_ref().display()))
}

/// Run time versus error `(time, error, label)` on log–log axes: every run as a
/// labelled point, the Pareto front ([`pareto_front`]) in red and connected.
/// The legend defaults to the upper right (where dominated runs are, if any).
pub fn pareto_plot(
    path: impl AsRef<Path>,
    spec: &PlotSpec,
    points: &[(f64, f64, String)],
) -> Result<()> {
    let xy: Vec<(f64, f64)> = points.iter().map(|p| (p.0, p.1)).collect();
    check_points("runs", &xy, Axes::LogLog)?;
    let front: Vec<(f64, f64)> = pareto_front(points).into_iter().map(|i| xy[i]).collect();

    let mut x_range = log_range(xy.iter().map(|p| p.0), spec.x_range)?;
    if spec.x_range.is_none() {
        // Room on the right for the label of the slowest run.
        x_range.end *= (x_range.end / x_range.start).powf(0.12);
    }
    let y_range = log_range(xy.iter().map(|p| p.1), spec.y_range)?;

    let root = open_canvas(path.as_ref(), spec)?;
    let mut chart =
        chart_builder(&root, spec).build_cartesian_2d(log_axis(&x_range), log_axis(&y_range))?;
    draw_mesh(&mut chart, spec, &|x| format_tick(*x), &|y| format_tick(*y))?;

    // All runs: a blue dot with its label beside it.
    let run_color = PALETTE[0];
    let label_font = (FONT, POINT_LABEL_SIZE)
        .into_font()
        .color(&RGBColor(60, 60, 60));
    chart
        .draw_series(points.iter().map(|(t, e, label)| {
            EmptyElement::at((*t, *e))
                + Circle::new((0, 0), 5, run_color.filled())
                + Text::new(label.clone(), (8, -16), label_font.clone())
        }))?
        .label("runs")
        .legend(move |(x, y)| Circle::new((x + 12, y), 5, run_color.filled()));

    // The front: a red line through red rings around its runs.
    let front_color = PALETTE[3];
    let front_style = front_color.stroke_width(2);
    chart
        .draw_series(LineSeries::new(front.iter().copied(), front_style))?
        .label("Pareto front (no run is faster and more accurate)")
        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], front_style));
    chart.draw_series(front.iter().map(|&p| Circle::new(p, 8, front_style)))?;

    draw_legend(
        &mut chart,
        spec.legend.unwrap_or(LegendPosition::UpperRight),
    )?;
    root.present()
        .with_context(|| format!("writing {}", path.as_ref().display()))
}

// ---------------------------------------------------------------------------
// Drawing helpers shared by the plots
// ---------------------------------------------------------------------------

/// The bundled font, compiled into the binary.
static DEJAVU_SANS: &[u8] = include_bytes!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/assets/DejaVuSans.ttf"
));

/// Register the bundled DejaVu Sans as the [`FONT`] family, once per process.
/// Every plot function calls it; calling it again is free.
pub fn register_bundled_font() -> Result<()> {
    static REGISTERED: OnceLock<std::result::Result<(), String>> = OnceLock::new();
    REGISTERED
        .get_or_init(|| {
            plotters::style::register_font(FONT, FontStyle::Normal, DEJAVU_SANS)
                .map_err(|_| "the bundled assets/DejaVuSans.ttf is not a valid font".to_string())
        })
        .clone()
        .map_err(|message| anyhow!(message))
}

type Canvas<'a> = DrawingArea<BitMapBackend<'a>, Shift>;

/// A chart drawn on a [`Canvas`]; X and Y are linear or logarithmic f64 axes.
type Chart<'a, 'b, X, Y> = ChartContext<'a, BitMapBackend<'b>, Cartesian2d<X, Y>>;

/// A white canvas of the spec's size that writes a PNG to `path` on `present()`.
fn open_canvas<'a>(path: &'a Path, spec: &PlotSpec) -> Result<Canvas<'a>> {
    register_bundled_font()?;
    let is_png = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("png"));
    ensure!(is_png, "plot file {} must end in .png", path.display());
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    let root = BitMapBackend::new(path, spec.size).into_drawing_area();
    root.fill(&WHITE)?;
    Ok(root)
}

/// Title and room for the tick labels and axis descriptions.
fn chart_builder<'a, 'b>(
    root: &'a Canvas<'b>,
    spec: &PlotSpec,
) -> ChartBuilder<'a, 'b, BitMapBackend<'b>> {
    let mut builder = ChartBuilder::on(root);
    builder
        .caption(&spec.title, (FONT, TITLE_SIZE))
        .margin(20)
        .x_label_area_size(60)
        .y_label_area_size(95);
    builder
}

/// Axes, tick labels, axis descriptions and a light grid.
fn draw_mesh<'a, 'b: 'a, X, Y>(
    chart: &mut Chart<'a, 'b, X, Y>,
    spec: &PlotSpec,
    x_format: &dyn Fn(&f64) -> String,
    y_format: &dyn Fn(&f64) -> String,
) -> Result<()>
where
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    chart
        .configure_mesh()
        .x_desc(&spec.x_label)
        .y_desc(&spec.y_label)
        // Ticks per axis from the image size, so small images are not crowded
        // (ignored by log axes, which have their own ticks).
        .x_labels((spec.size.0 / 90).clamp(3, 12) as usize)
        .y_labels((spec.size.1 / 55).clamp(3, 12) as usize)
        .x_label_formatter(x_format)
        .y_label_formatter(y_format)
        .label_style((FONT, TICK_LABEL_SIZE))
        .axis_desc_style((FONT, AXIS_DESC_SIZE))
        .bold_line_style(RGBColor(215, 215, 215))
        .light_line_style(RGBColor(242, 242, 242))
        .draw()?;
    Ok(())
}

/// A solid coloured line, optionally with a marker at each point, in the legend.
fn draw_line<'a, 'b: 'a, X, Y>(
    chart: &mut Chart<'a, 'b, X, Y>,
    name: &str,
    points: &[(f64, f64)],
    color: RGBColor,
    markers: bool,
) -> Result<()>
where
    X: Ranged<ValueType = f64>,
    Y: Ranged<ValueType = f64>,
{
    let style = color.stroke_width(2);
    chart
        .draw_series(LineSeries::new(points.iter().copied(), style))?
        .label(name)
        .legend(move |(x, y)| {
            EmptyElement::at((x, y))
                + PathElement::new(vec![(0, 0), (24, 0)], style)
                + Circle::new((12, 0), if markers { 4 } else { 0 }, color.filled())
        });
    if markers {
        chart.draw_series(points.iter().map(|&p| Circle::new(p, 4, color.filled())))?;
    }
    Ok(())
}

/// A dashed line (reference curves, fits), in the legend.
fn draw_dashed<'a, 'b: 'a, X, Y>(
    chart: &mut Chart<'a, 'b, X, Y>,
    name: &str,
    points: &[(f64, f64)],
    color: RGBColor,
) -> Result<()>
where
    X: Ranged<ValueType = f64>,
    Y: Ranged<ValueType = f64>,
{
    let style = color.stroke_width(2);
    chart
        .draw_series(DashedLineSeries::new(points.iter().copied(), 10, 6, style))?
        .label(name)
        .legend(move |(x, y)| DashedPathElement::new(vec![(x, y), (x + 24, y)], 7, 4, style));
    Ok(())
}

/// The series of a line plot, references dashed black and the others in palette
/// order, and the legend (upper right unless the spec says otherwise).
fn draw_series_and_legend<'a, 'b: 'a, X, Y>(chart: &mut Chart<'a, 'b, X, Y>, spec: &PlotSpec, series: &[Series]) -> Result<()>
where
    X: Ranged<ValueType = f64>,
    Y: Ranged<ValueType = f64>,
{
    let mut colors = PALETTE.iter().cycle();
    for s in series {
        if s.reference {
            draw_dashed(chart, &s.name, &s.points, BLACK)?;
        } else {
            let color = *colors.next().expect("cycle never ends");
            draw_line(chart, &s.name, &s.points, color, s.markers)?;
        }
    }
    draw_legend(chart, spec.legend.unwrap_or(LegendPosition::UpperRight))
}

/// The legend box: white, framed, over the plot.
fn draw_legend<'a, 'b: 'a, X, Y>(
    chart: &mut Chart<'a, 'b, X, Y>,
    position: LegendPosition,
) -> Result<()>
where
    X: Ranged<ValueType = f64>,
    Y: Ranged<ValueType = f64>,
{
    chart
        .configure_series_labels()
        .position(position.to_plotters())
        .margin(12)
        .legend_area_size(30)
        .label_font((FONT, LEGEND_SIZE))
        .background_style(WHITE.mix(0.9))
        .border_style(RGBColor(120, 120, 120))
        .draw()?;
    Ok(())
}

// --- Data checks and axis ranges -------------------------------------------

#[derive(Clone, Copy, PartialEq)]
enum Axes {
    Linear,
    LogLog,
    /// Linear x, logarithmic y.
    LogY,
}

/// Every point finite (and positive on log–log axes), and at least one point.
fn check_points(name: &str, points: &[(f64, f64)], axes: Axes) -> Result<()> {
    ensure!(!points.is_empty(), "series '{name}' has no points");
    for (i, &(x, y)) in points.iter().enumerate() {
        ensure!(
            x.is_finite() && y.is_finite(),
            "series '{name}' point {i} is not finite: ({x}, {y})"
        );
        if axes == Axes::LogLog {
            ensure!(
                x > 0.0 && y > 0.0,
                "series '{name}' point {i} is not positive on log axes: ({x}, {y})"
            );
        }
        if axes == Axes::LogY {
            ensure!(y > 0.0, "series '{name}' point {i} is not positive on a log y axis: ({x}, {y})");
        }
    }
    Ok(())
}

/// The fixed range if given, else the data range padded by 5 % on each side.
fn linear_range(
    values: impl Iterator<Item = f64>,
    fixed: Option<(f64, f64)>,
) -> Result<Range<f64>> {
    if let Some((lo, hi)) = fixed {
        ensure!(
            lo.is_finite() && hi.is_finite() && lo < hi,
            "bad fixed axis range [{lo}, {hi}]"
        );
        return Ok(lo..hi);
    }
    let (lo, hi) = min_max(values)?;
    let pad = if hi > lo {
        0.05 * (hi - lo)
    } else if lo != 0.0 {
        0.1 * lo.abs()
    } else {
        1.0
    };
    Ok(lo - pad..hi + pad)
}

/// The fixed range if given, else the data range padded by a factor on each side.
fn log_range(values: impl Iterator<Item = f64>, fixed: Option<(f64, f64)>) -> Result<Range<f64>> {
    if let Some((lo, hi)) = fixed {
        ensure!(
            lo > 0.0 && hi.is_finite() && lo < hi,
            "bad fixed log axis range [{lo}, {hi}]"
        );
        return Ok(lo..hi);
    }
    let (lo, hi) = min_max(values)?;
    let factor = (hi / lo).powf(0.06).max(1.3);
    Ok(lo / factor..hi * factor)
}

/// A logarithmic axis over `range` with ticks from [`log_ticks`].
///
/// plotters' own log ticks can repeat a decade (two "0.1" labels drawn on top of
/// each other) and leave a two-decade axis with only two labels, so the ticks
/// are chosen here.
fn log_axis(range: &Range<f64>) -> WithKeyPoints<LogCoord<f64>> {
    let (labelled, grid_only) = log_ticks(range.start, range.end);
    range
        .clone()
        .log_scale()
        .with_key_points(labelled)
        .with_light_points(grid_only)
}

/// Tick values for a log axis over `[lo, hi]`: (labelled ticks, unlabelled grid
/// lines). Ticks are m·10^k with the mantissas m chosen by how many decades the
/// axis spans: 1 only (every few decades on very long axes); 1, 2, 5; or 1…9.
/// Each tick is parsed from its decimal text, so it is the double nearest to
/// m·10^k (0.3, not 0.30000000000000004).
fn log_ticks(lo: f64, hi: f64) -> (Vec<f64>, Vec<f64>) {
    let decades = (hi / lo).log10();
    let (labelled_mantissas, decade_stride): (&[f64], i32) = if decades > 8.0 {
        (&[1.0], (decades / 8.0).ceil() as i32)
    } else if decades > 3.5 {
        (&[1.0], 1)
    } else if decades > 1.5 {
        (&[1.0, 2.0, 5.0], 1)
    } else if decades > 0.6 {
        (&[1.0, 2.0, 3.0, 5.0], 1)
    } else {
        (&[1.0, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0], 1)
    };
    let grid_mantissas: &[f64] = if decades > 3.5 {
        &[]
    } else {
        &[2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0]
    };

    let in_range = |x: &f64| (lo..=hi).contains(x);
    let value = |m: f64, k: i32| -> f64 { format!("{m}e{k}").parse().expect("a decimal literal") };
    let (k_lo, k_hi) = (lo.log10().floor() as i32, hi.log10().ceil() as i32);
    let mut labelled = Vec::new();
    let mut grid_only = Vec::new();
    for k in k_lo..=k_hi {
        for &m in labelled_mantissas {
            if m != 1.0 || k.rem_euclid(decade_stride) == 0 {
                labelled.push(value(m, k));
            }
        }
        for &m in grid_mantissas {
            if !labelled_mantissas.contains(&m) {
                grid_only.push(value(m, k));
            }
        }
    }
    labelled.retain(in_range);
    grid_only.retain(in_range);
    if labelled.len() < 2 {
        // A very narrow axis (e.g. 2.1 to 2.4): label its ends.
        labelled = vec![lo, hi];
    }
    (labelled, grid_only)
}

fn min_max(values: impl Iterator<Item = f64>) -> Result<(f64, f64)> {
    values
        .fold(None, |acc: Option<(f64, f64)>, v| match acc {
            None => Some((v, v)),
            Some((lo, hi)) => Some((lo.min(v), hi.max(v))),
        })
        .ok_or_else(|| anyhow!("no data to plot"))
}

// ---------------------------------------------------------------------------
// Tests
// ---------------------------------------------------------------------------

#[cfg(test)]
mod tests {
    use super::*;

    fn temp_dir(test: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("cramp-plot-{test}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    /// The PNG exists, starts with the PNG signature and is not a blank image.
    fn assert_png(path: &Path) {
        let bytes = std::fs::read(path).unwrap();
        assert!(
            bytes.starts_with(b"\x89PNG\r\n\x1a\n"),
            "{} is not a PNG",
            path.display()
        );
        assert!(
            bytes.len() > 15_000,
            "{} is only {} bytes",
            path.display(),
            bytes.len()
        );
    }

    #[test]
    fn fit_order_recovers_exact_power_laws() {
        for &(c, p) in &[
            (1.0, 1.0),
            (3.7, 2.0),
            (0.02, 1.5),
            (5.0, -0.5),
            (1e-3, 4.0),
        ] {
            let points: Vec<(f64, f64)> = [0.1, 0.05, 0.025, 0.0125, 0.00625]
                .iter()
                .map(|&h: &f64| (h, c * h.powf(p)))
                .collect();
            let fitted = fit_order(&points);
            assert!(
                (fitted - p).abs() < 1e-12,
                "c = {c}, p = {p}: fitted {fitted}"
            );
        }
        // Two points give the exact slope; irregular spacing too.
        let two = [(1.0, 2.0), (4.0, 32.0)];
        assert!((fit_order(&two) - 2.0).abs() < 1e-14);
    }

    #[test]
    fn fit_order_is_least_squares_on_noisy_data() {
        // ln e = 2 ln h + noise, noise symmetric about the line: slope exactly 2 by symmetry.
        let hs = [1.0f64, 2.0, 4.0, 8.0];
        let noise = [0.1, -0.1, -0.1, 0.1];
        let points: Vec<(f64, f64)> = hs
            .iter()
            .zip(noise)
            .map(|(&h, n)| (h, (2.0 * h.ln() + n).exp()))
            .collect();
        assert!((fit_order(&points) - 2.0).abs() < 1e-12);
    }

    #[test]
    fn fit_order_is_nan_when_undefined() {
        assert!(fit_order(&[]).is_nan());
        assert!(fit_order(&[(0.1, 1.0)]).is_nan());
        assert!(fit_order(&[(0.1, 1.0), (0.1, 2.0)]).is_nan());
        assert!(fit_order(&[(0.1, 1.0), (0.2, 0.0)]).is_nan());
        assert!(fit_order(&[(0.1, 1.0), (f64::NAN, 2.0)]).is_nan());
    }

    #[test]
    fn pareto_front_keeps_the_non_dominated_points() {
        let points = [
            (1.0, 10.0, "fast, coarse"), // 0: front (fastest)
            (2.0, 5.0, "a"),             // 1: front
            (3.0, 6.0, "b"),             // 2: dominated by 1
            (4.0, 1.0, "slow, fine"),    // 3: front (most accurate)
            (4.0, 2.0, "c"),             // 4: dominated by 3 (same time, more error)
            (0.5, 20.0, "fastest"),      // 5: front
            (2.0, 5.0, "a again"),       // 6: equal to 1: both on the front
            (f64::NAN, 0.1, "broken"),   // 7: non-finite: never on the front
            (10.0, 1.0, "slower, same"), // 8: dominated by 3 (same error, more time)
        ];
        assert_eq!(pareto_front(&points), vec![5, 0, 1, 6, 3]);
        assert!(pareto_front::<()>(&[]).is_empty());
        assert_eq!(pareto_front(&[(1.0, 1.0, ())]), vec![0]);
    }

    #[test]
    fn tick_labels_are_short() {
        assert_eq!(format_tick(0.1 + 0.2), "0.3");
        assert_eq!(format_tick(0.30000000000000004), "0.3");
        assert_eq!(format_tick(0.0), "0");
        assert_eq!(format_tick(1.0), "1");
        assert_eq!(format_tick(-2.5), "-2.5");
        assert_eq!(format_tick(100.0), "100");
        assert_eq!(format_tick(1234.0), "1234");
        assert_eq!(format_tick(0.0125), "0.0125");
        assert_eq!(format_tick(0.001), "1e-3");
        assert_eq!(format_tick(0.0015000000000000002), "1.5e-3");
        assert_eq!(format_tick(1e-10), "1e-10");
        assert_eq!(format_tick(25000.0), "2.5e4");
        assert_eq!(format_tick(9.9996), "10");
        assert_eq!(format_sig(1.00025, 5), "1.0003");
        // Linear axes: more digits for narrow ranges, round-off at zero is 0.
        let narrow = linear_tick_formatter(&(1.0..1.001));
        assert_eq!(narrow(&1.0002000000000002), "1.0002");
        let around_zero = linear_tick_formatter(&(-1.0..1.0));
        assert_eq!(around_zero(&5.551115123125783e-17), "0");
        assert_eq!(around_zero(&0.6000000000000001), "0.6");
    }

    #[test]
    fn log_ticks_are_exact_unique_and_readable() {
        let (labelled, grid) = log_ticks(0.0085, 0.13);
        assert_eq!(labelled, vec![0.01, 0.02, 0.03, 0.05, 0.1]);
        assert!(grid.contains(&0.04) && grid.contains(&0.09) && !grid.contains(&0.05));
        let (labelled, _) = log_ticks(1.2e-4, 1.1e-2);
        assert_eq!(labelled, vec![2e-4, 5e-4, 1e-3, 2e-3, 5e-3, 1e-2]);
        let (labelled, grid) = log_ticks(1e-12, 1.0);
        assert_eq!(labelled, vec![1e-12, 1e-10, 1e-8, 1e-6, 1e-4, 1e-2, 1.0]);
        assert!(grid.is_empty());
        let (labelled, _) = log_ticks(2.1, 2.4);
        assert_eq!(labelled, vec![2.1, 2.4]);
        let (labelled, _) = log_ticks(0.25, 0.7);
        assert_eq!(labelled, vec![0.25, 0.3, 0.4, 0.5, 0.6, 0.7]);
    }

    #[test]
    fn line_plot_renders() {
        let dir = temp_dir("line");
        let xs: Vec<f64> = (0..=50).map(|i| i as f64 * 0.02).collect();
        let exact: Vec<(f64, f64)> = xs
            .iter()
            .map(|&x| (x, (std::f64::consts::PI * x).sin()))
            .collect();
        let mpm: Vec<(f64, f64)> = xs
            .iter()
            .step_by(5)
            .map(|&x| (x, 0.97 * (std::f64::consts::PI * x).sin()))
            .collect();
        let fea: Vec<(f64, f64)> = xs
            .iter()
            .map(|&x| (x, 1.02 * (std::f64::consts::PI * x).sin() - 0.05))
            .collect();
        let spec = PlotSpec::new("Crack opening profile", "x / a", "opening / exact maximum");
        let path = dir.join("line.png");
        line_plot(
            &path,
            &spec,
            &[
                Series::reference("exact (Westergaard)", exact.clone()),
                Series::line("MPM, USAVG", mpm).with_markers(),
                Series::line("Q4 FEA", fea),
            ],
        )
        .unwrap();
        assert_png(&path);

        // A fixed y range, a custom size, and a constant series (zero span).
        let spec = PlotSpec::new("Fixed range", "t", "energy")
            .with_y_range(-2.0, 2.0)
            .with_size(600, 400);
        let flat = Series::line("flat", vec![(0.0, 1.0), (1.0, 1.0)]);
        line_plot(dir.join("fixed.png"), &spec, std::slice::from_ref(&flat)).unwrap();
        line_plot(
            dir.join("flat.png"),
            &PlotSpec::new("Flat", "t", "e"),
            &[flat],
        )
        .unwrap();
    }

    #[test]
    fn convergence_plot_renders() {
        let dir = temp_dir("convergence");
        let points: Vec<(f64, f64)> = [0.1, 0.05, 0.025, 0.0125]
            .iter()
            .map(|&h: &f64| (h, 0.8 * h.powf(1.98)))
            .collect();
        let spec = PlotSpec::new(
            "J-integral convergence",
            "cell size h",
            "relative error in J",
        );
        let path = dir.join("convergence.png");
        loglog_convergence(&path, &spec, &points, "MPM, GIMP").unwrap();
        assert_png(&path);
    }

    #[test]
    fn pareto_plot_renders() {
        let dir = temp_dir("pareto");
        let points = vec![
            (0.5, 2e-2, "h=1/16 linear".to_string()),
            (1.2, 4e-3, "h=1/32 GIMP".to_string()),
            (2.0, 9e-3, "h=1/32 linear".to_string()),
            (7.5, 1e-3, "h=1/64 GIMP".to_string()),
            (9.0, 3e-3, "h=1/64 linear".to_string()),
        ];
        let spec = PlotSpec::new(
            "Cost versus accuracy",
            "run time [s]",
            "relative error in K_I",
        );
        let path = dir.join("pareto.png");
        pareto_plot(&path, &spec, &points).unwrap();
        assert_png(&path);
    }

    #[test]
    fn bad_data_is_an_error() {
        let dir = temp_dir("bad");
        let spec = PlotSpec::new("t", "x", "y");
        let nan = Series::line("broken", vec![(0.0, 1.0), (1.0, f64::NAN)]);
        let err = line_plot(dir.join("nan.png"), &spec, &[nan]).unwrap_err();
        assert!(err.to_string().contains("broken"), "{err}");
        assert!(line_plot(dir.join("empty.png"), &spec, &[]).is_err());
        assert!(
            loglog_convergence(dir.join("zero.png"), &spec, &[(0.1, 0.0), (0.2, 1.0)], "e")
                .is_err()
        );
        assert!(loglog_convergence(dir.join("one.png"), &spec, &[(0.1, 1.0)], "e").is_err());
        let ok = Series::line("ok", vec![(0.0, 1.0), (1.0, 2.0)]);
        assert!(line_plot(dir.join("plot.svg"), &spec, &[ok]).is_err());
    }
}
