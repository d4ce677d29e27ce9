//! Crack surfaces in 3D for the reports: a row of panels (one per time), each an oblique
//! parallel projection of the crack's triangles, filled and coloured by the tilt of each
//! triangle's normal from a reference axis (the load axis: 0° = the plane normal to the
//! load, mode I), lit by a fixed light so the facets read as a surface, drawn back to front
//! (painter's order), with line segments (the specimen's edges, the front) over or under
//! them. Drawn with plotters and the bundled font of [`super::plot`]: a person sees the
//! surface turn without opening ParaView (issue 17).

use super::plot::{register_bundled_font, FONT};
use anyhow::{ensure, Context, Result};
use plotters::prelude::*;
use std::path::Path;

/// One panel: a caption, the triangles (three corners each), and lines (pairs of points,
/// drawn in `line_color`, e.g. the specimen's edges) and the front (pairs, drawn in black,
/// thick, on top).
#[derive(Clone, Debug, Default)]
pub struct SurfacePanel {
    pub caption: String,
    pub triangles: Vec<[[f64; 3]; 3]>,
    pub edges: Vec<[[f64; 3]; 2]>,
    pub front: Vec<[[f64; 3]; 2]>,
}

/// The view: the eye's azimuth (degrees from +x toward +y) and elevation (degrees above
/// the x–y plane), and the axis the colour measures the tilt from (unit).
#[derive(Clone, Copy, Debug)]
pub struct View {
    pub azimuth: f64,
    pub elevation: f64,
    pub axis: [f64; 3],
    /// Tilt (degrees) at the blue end of the scale (0° is red).
    pub max_tilt: f64,
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// Red (tilt 0) to blue (tilt ≥ max) through yellow and green, scaled by the light.
fn tilt_colour(t: f64, light: f64) -> RGBColor {
    let t = t.clamp(0.0, 1.0);
    let stops = [(0.0, (200.0, 30.0, 30.0)), (0.33, (235.0, 190.0, 40.0)), (0.66, (60.0, 170.0, 90.0)), (1.0, (40.0, 80.0, 200.0))];
    let mut c = stops[3].1;
    for w in stops.windows(2) {
        if t <= w[1].0 {
            let s = (t - w[0].0) / (w[1].0 - w[0].0);
            c = (w[0].1 .0 + s * (w[1].1 .0 - w[0].1 .0), w[0].1 .1 + s * (w[1].1 .1 - w[0].1 .1), w[0].1 .2 + s * (w[1].1 .2 - w[0].1 .2));
            break;
        }
    }
    let k = (0.45 + 0.55 * light.clamp(0.0, 1.0)).min(1.0);
    RGBColor((c.0 * k).round() as u8, (c.1 * k).round() as u8, (c.2 * k).round() as u8)
}

/// Draw `panels` side by side (`columns` per row) into a PNG `width` pixels wide, each
/// panel on the same scale, with a title and a colour key of the tilt. Errors on no
/// panels or a non-finite point.
pub fn surface_panels(path: impl AsRef<Path>, title: &str, panels: &[SurfacePanel], view: View, columns: usize, width: u32) -> Result<()> {
    let path = path.as_ref();
    ensure!(!panels.is_empty(), "surface plot '{title}': no panels");
    let finite = |p: &[f64; 3]| p.iter().all(|v| v.is_finite());
    ensure!(
        panels.iter().all(|p| p.triangles.iter().flatten().all(finite) && p.edges.iter().flatten().all(finite) && p.front.iter().flatten().all(finite)),
        "surface plot '{title}': a non-finite point"
    );
    register_bundled_font()?;
    let (az, el) = (view.azimuth.to_radians(), view.elevation.to_radians());
    let eye = [el.cos() * az.cos(), el.cos() * az.sin(), el.sin()];
    let right = [-az.sin(), az.cos(), 0.0];
    let up = cross(eye, right);
    let project = |p: &[f64; 3]| (dot(*p, right), dot(*p, up));
    // One scale for every panel.
    let (mut x0, mut x1, mut y0, mut y1) = (f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY, f64::NEG_INFINITY);
    for p in panels {
        for q in p.triangles.iter().flatten().chain(p.edges.iter().flatten()).chain(p.front.iter().flatten()) {
            let (u, v) = project(q);
            x0 = x0.min(u);
            x1 = x1.max(u);
            y0 = y0.min(v);
            y1 = y1.max(v);
        }
    }
    ensure!(x0.is_finite() && x1 > x0 && y1 > y0, "surface plot '{title}': nothing to draw");
    let pad = 0.04 * (x1 - x0).max(y1 - y0);
    let (x0, x1, y0, y1) = (x0 - pad, x1 + pad, y0 - pad, y1 + pad);
    let columns = columns.clamp(1, panels.len());
    let rows = panels.len().div_ceil(columns);
    let (title_h, key_h, caption_h) = (40u32, 50u32, 28u32);
    let panel_w = (width / columns as u32).max(120);
    let panel_h = ((panel_w as f64 - 10.0) * (y1 - y0) / (x1 - x0)).round().clamp(80.0, 1600.0) as u32 + caption_h;
    let size = (panel_w * columns as u32, title_h + key_h + panel_h * rows as u32);
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    let root = BitMapBackend::new(path, size).into_drawing_area();
    root.fill(&WHITE)?;
    let (head, rest) = root.split_vertically(title_h);
    head.draw(&Text::new(title.to_string(), (10, 10), (FONT, 20).into_font()))?;
    let (body, key) = rest.split_vertically(panel_h * rows as u32);
    let light_dir = {
        let l = [eye[0] + 0.3 * up[0], eye[1] + 0.3 * up[1], eye[2] + 0.3 * up[2]];
        let n = dot(l, l).sqrt();
        [l[0] / n, l[1] / n, l[2] / n]
    };
    let areas = body.split_evenly((rows, columns));
    for (p, area) in panels.iter().zip(areas.iter()) {
        let mut chart = ChartBuilder::on(area).caption(&p.caption, (FONT, 15)).margin(5).build_cartesian_2d(x0..x1, y0..y1)?;
        let grey = RGBColor(150, 150, 150);
        // Specimen edges first (under the surface), then the triangles back to front.
        for e in &p.edges {
            chart.draw_series(std::iter::once(PathElement::new(vec![project(&e[0]), project(&e[1])], grey.stroke_width(1))))?;
        }
        let mut order: Vec<(f64, usize)> = p.triangles.iter().enumerate().map(|(k, t)| ((dot(t[0], eye) + dot(t[1], eye) + dot(t[2], eye)) / 3.0, k)).collect();
        order.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        let polys: Vec<Polygon<(f64, f64)>> = order
            .iter()
            .filter_map(|&(_, k)| {
                let t = &p.triangles[k];
                let n = cross(sub(t[1], t[0]), sub(t[2], t[0]));
                let nn = dot(n, n).sqrt();
                if nn == 0.0 {
                    return None;
                }
                let n = [n[0] / nn, n[1] / nn, n[2] / nn];
                let tilt = dot(n, view.axis).abs().min(1.0).acos().to_degrees();
                let light = dot(n, light_dir).abs();
                Some(Polygon::new(t.iter().map(project).collect::<Vec<_>>(), tilt_colour(tilt / view.max_tilt, light).filled()))
            })
            .collect();
        chart.draw_series(polys)?;
        for e in &p.front {
            chart.draw_series(std::iter::once(PathElement::new(vec![project(&e[0]), project(&e[1])], BLACK.stroke_width(2))))?;
        }
    }
    // Colour key.
    let n = 40;
    let (kw, kx) = ((size.0 as i32 - 40).min(500), 20);
    for i in 0..n {
        let t = i as f64 / (n - 1) as f64;
        let x = kx + (kw * i) / n;
        key.draw(&Rectangle::new([(x, 8), (x + kw / n + 1, 24)], tilt_colour(t, 1.0).filled()))?;
    }
    key.draw(&Text::new(
        format!("tilt of the surface's normal from the load axis: 0° (left, mode I plane) to {}° and more (right)", view.max_tilt),
        (kx, 30),
        (FONT, 13).into_font(),
    ))?;
    root.present().with_context(|| format!("writing {}", path.display()))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn draws_two_panels() {
        let dir = std::env::temp_dir().join(format!("cramp-surface3-{}", std::process::id()));
        let path = dir.join("s.png");
        let tri = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.5]];
        let p = SurfacePanel { caption: "t = 0".into(), triangles: vec![tri], edges: vec![[[0.0; 3], [1.0, 1.0, 1.0]]], front: vec![[tri[1], tri[2]]] };
        let view = View { azimuth: -45.0, elevation: 20.0, axis: [0.0, 0.0, 1.0], max_tilt: 45.0 };
        surface_panels(&path, "test", &[p.clone(), p], view, 2, 600).unwrap();
        assert!(std::fs::metadata(&path).unwrap().len() > 1000);
        let _ = std::fs::remove_dir_all(&dir);
        assert!(surface_panels(dir.join("e.png"), "empty", &[], view, 2, 600).is_err());
    }
}
