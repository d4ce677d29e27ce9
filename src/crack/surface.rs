//! Triangulated crack surfaces of 3D scenes (001 §2.1: "each crack surface is described
//! by a collection of massless points connected by triangular elements").
//!
//! A [`TriangleSurface`] is a consistently oriented triangle mesh with every edge in at
//! most two triangles (an oriented 2-manifold with boundary). Its vertices are the crack
//! particles. "Above" is the side its normals point to: a triangle (a, b, c) has normal
//! (b − a) × (c − a), so a, b, c turn counter-clockwise seen from above. Velocity field 1
//! holds the material above, field 2 the material below (Nairn 2003 §2.1).
//!
//! The planar forms a 3D user writes — a polygon (a rectangle is one), a disc (penny), an
//! ellipse, and the part of a disc or ellipse inside a box (a quarter-penny corner crack)
//! — are meshed by [`planar_polygon`]: the boundary divided evenly into pieces no longer
//! than the requested edge, then a constrained Delaunay triangulation refined until every
//! edge is that short and no angle is below 25° (the `spade` crate, Ruppert-style
//! refinement). A crack whose plane is normal to a grid axis gets its plane coordinate
//! exactly (the crack-patch test puts the crack on a grid plane).

use crate::dim::Vector3;
use spade::{ConstrainedDelaunayTriangulation, Point2, RefinementParameters, Triangulation};
use std::collections::HashMap;

/// A consistently oriented triangle mesh (see the module documentation).
#[derive(Clone, Debug, PartialEq)]
pub struct TriangleSurface {
    pub vertices: Vec<Vector3>,
    pub triangles: Vec<[u32; 3]>,
}

impl TriangleSurface {
    /// Check the mesh: finite vertices, valid indices, no triangle of zero area, every
    /// directed edge in at most one triangle (consistent orientation) and every edge in at
    /// most two. The error names the triangle.
    pub fn new(vertices: Vec<Vector3>, triangles: Vec<[u32; 3]>) -> Result<TriangleSurface, String> {
        if let Some((i, v)) = vertices.iter().enumerate().find(|(_, v)| !v.iter().all(|c| c.is_finite())) {
            return Err(format!("vertex {i} has a non-finite coordinate, ({}, {}, {})", v.x, v.y, v.z));
        }
        if triangles.is_empty() {
            return Err("has no triangles".into());
        }
        let mut directed: HashMap<(u32, u32), usize> = HashMap::new();
        for (t, tri) in triangles.iter().enumerate() {
            if let Some(&i) = tri.iter().find(|&&i| i as usize >= vertices.len()) {
                return Err(format!("triangle {t} names vertex {i}, but there are {} vertices", vertices.len()));
            }
            let [a, b, c] = tri.map(|i| vertices[i as usize]);
            if (b - a).cross(&(c - a)) == Vector3::zeros() {
                return Err(format!("triangle {t} ({:?}) has zero area", tri));
            }
            for k in 0..3 {
                let e = (tri[k], tri[(k + 1) % 3]);
                if let Some(other) = directed.insert(e, t) {
                    return Err(format!(
                        "triangle {t} traverses its edge from vertex {} to vertex {} in the same direction as triangle {other}: the surface is not consistently oriented (or an edge has more than two triangles)",
                        e.0, e.1
                    ));
                }
            }
        }
        Ok(TriangleSurface { vertices, triangles })
    }

    /// Normal of triangle t, (b − a) × (c − a) (twice its area; points above).
    pub fn normal(&self, t: usize) -> Vector3 {
        let [a, b, c] = self.triangles[t].map(|i| self.vertices[i as usize]);
        (b - a).cross(&(c - a))
    }

    /// Boundary edges (in one triangle only), directed as in their triangle, with the
    /// triangle: (from, to, triangle), in triangle order.
    pub fn boundary_edges(&self) -> Vec<(u32, u32, usize)> {
        let mut directed: HashMap<(u32, u32), usize> = HashMap::with_capacity(3 * self.triangles.len());
        for (t, tri) in self.triangles.iter().enumerate() {
            for k in 0..3 {
                directed.insert((tri[k], tri[(k + 1) % 3]), t);
            }
        }
        let mut out = Vec::new();
        for (t, tri) in self.triangles.iter().enumerate() {
            for k in 0..3 {
                let (a, b) = (tri[k], tri[(k + 1) % 3]);
                if !directed.contains_key(&(b, a)) {
                    out.push((a, b, t));
                }
            }
        }
        out
    }

    /// Per triangle, which of its edges k (from corner k to corner k + 1) are boundary
    /// edges; per vertex, whether it lies on a boundary edge.
    pub fn boundary_flags(&self) -> (Vec<[bool; 3]>, Vec<bool>) {
        let mut edges = vec![[false; 3]; self.triangles.len()];
        let mut verts = vec![false; self.vertices.len()];
        for (a, b, t) in self.boundary_edges() {
            let tri = self.triangles[t];
            let k = (0..3).find(|&k| tri[k] == a && tri[(k + 1) % 3] == b).expect("edge of its triangle");
            edges[t][k] = true;
            verts[a as usize] = true;
            verts[b as usize] = true;
        }
        (edges, verts)
    }

    /// Axis-aligned bounding box of the vertices.
    pub fn bounds(&self) -> (Vector3, Vector3) {
        self.vertices.iter().fold((Vector3::repeat(f64::INFINITY), Vector3::repeat(f64::NEG_INFINITY)), |(lo, hi), v| (lo.inf(v), hi.sup(v)))
    }

    /// Longest edge.
    pub fn max_edge(&self) -> f64 {
        self.triangles
            .iter()
            .flat_map(|t| (0..3).map(move |k| (t[k], t[(k + 1) % 3])))
            .map(|(a, b)| (self.vertices[a as usize] - self.vertices[b as usize]).norm())
            .fold(0.0, f64::max)
    }
}

/// An orthonormal basis (u, v) of the plane with unit normal n, u × v = n, and the
/// coordinate axes used exactly when n is a coordinate axis.
struct PlaneBasis {
    u: Vector3,
    v: Vector3,
    n: Vector3,
    /// `Some(axis)` when n = ±e_axis: coordinates are then copied, not computed.
    axis: Option<usize>,
    /// The plane's coordinate along n (exact for an axis plane).
    offset: f64,
}

impl PlaneBasis {
    fn new(n: Vector3, point: Vector3) -> PlaneBasis {
        let n = n.normalize();
        let zeros = (0..3).filter(|&c| n[c] == 0.0).count();
        if zeros == 2 {
            let a = (0..3).find(|&c| n[c] != 0.0).unwrap();
            let n = Vector3::from_fn(|c, _| if c == a { n[a].signum() } else { 0.0 });
            // (u, v) cyclic after the axis, so u × v = +e_a; swapped for −e_a.
            let (mut u, mut v) = (Vector3::zeros(), Vector3::zeros());
            u[(a + 1) % 3] = 1.0;
            v[(a + 2) % 3] = 1.0;
            if n[a] < 0.0 {
                std::mem::swap(&mut u, &mut v);
            }
            return PlaneBasis { u, v, n, axis: Some(a), offset: point[a] };
        }
        let least = (0..3).min_by(|&a, &b| n[a].abs().total_cmp(&n[b].abs())).unwrap();
        let mut e = Vector3::zeros();
        e[least] = 1.0;
        let u = e.cross(&n).normalize();
        let v = n.cross(&u);
        PlaneBasis { u, v, n, axis: None, offset: n.dot(&point) }
    }

    fn to_plane(&self, x: &Vector3) -> [f64; 2] {
        match self.axis {
            Some(_) => [self.u.dot(x), self.v.dot(x)],
            None => [self.u.dot(x), self.v.dot(x)],
        }
    }

    fn to_space(&self, s: f64, t: f64) -> Vector3 {
        match self.axis {
            // Exact: each coordinate is s, t or the plane's offset.
            Some(a) => {
                let mut x = self.u * s + self.v * t;
                x[a] = self.offset;
                x
            }
            None => self.u * s + self.v * t + self.n * self.offset,
        }
    }
}

/// Newell's normal of a closed polygon (its direction follows the right-hand rule of the
/// point order; its length is twice the area).
pub fn newell_normal(points: &[Vector3]) -> Vector3 {
    let mut n = Vector3::zeros();
    for (k, a) in points.iter().enumerate() {
        let b = points[(k + 1) % points.len()];
        n += Vector3::new((a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y));
    }
    n
}

/// Mesh a planar polygon (points in order; its normal, hence "above", by the right-hand
/// rule) with every edge at most `max_edge` long. Errors: fewer than three points, points
/// off the polygon's plane, a self-intersecting boundary, a non-positive `max_edge`.
pub fn planar_polygon(points: &[Vector3], max_edge: f64) -> Result<TriangleSurface, String> {
    if points.len() < 3 {
        return Err(format!("a polygon needs at least 3 points, got {}", points.len()));
    }
    if !(max_edge > 0.0 && max_edge.is_finite()) {
        return Err(format!("the edge length must be positive and finite, got {max_edge}"));
    }
    let n = newell_normal(points);
    let size = points.iter().map(|p| (p - points[0]).norm()).fold(0.0, f64::max);
    if !(n.norm() > 1e-12 * size * size) {
        return Err("the polygon has zero area (its points are collinear or repeated)".into());
    }
    let basis = PlaneBasis::new(n, points[0]);
    for (k, p) in points.iter().enumerate() {
        let off = match basis.axis {
            Some(a) => p[a] - basis.offset,
            None => basis.n.dot(p) - basis.offset,
        };
        if off.abs() > 1e-9 * size {
            return Err(format!("point {k} ({}, {}, {}) is {off:e} off the plane of the polygon: a crack polygon must be planar", p.x, p.y, p.z));
        }
    }
    if let Some(surface) = parallelogram_lattice(points, max_edge) {
        return Ok(surface);
    }
    // Boundary in plane coordinates, each side divided evenly.
    let plane: Vec<[f64; 2]> = points.iter().map(|p| basis.to_plane(p)).collect();
    let mut boundary: Vec<[f64; 2]> = Vec::new();
    for k in 0..plane.len() {
        let (a, b) = (plane[k], plane[(k + 1) % plane.len()]);
        let len = ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)).sqrt();
        if len == 0.0 {
            return Err(format!("points {k} and {} coincide", (k + 1) % plane.len()));
        }
        let m = (len / max_edge).ceil().max(1.0) as usize;
        for j in 0..m {
            let f = j as f64 / m as f64;
            boundary.push([a[0] + f * (b[0] - a[0]), a[1] + f * (b[1] - a[1])]);
        }
    }
    check_simple(&plane)?;
    let nb = boundary.len();
    let vertices: Vec<Point2<f64>> = boundary.iter().map(|p| Point2::new(p[0], p[1])).collect();
    let edges: Vec<[usize; 2]> = (0..nb).map(|k| [k, (k + 1) % nb]).collect();
    let mut area = 0.4 * max_edge * max_edge;
    for _ in 0..12 {
        let mut cdt = ConstrainedDelaunayTriangulation::<Point2<f64>>::bulk_load_cdt(vertices.clone(), edges.clone()).map_err(|e| format!("cannot triangulate the polygon: {e:?}"))?;
        let result = cdt.refine(
            RefinementParameters::<f64>::new()
                .exclude_outer_faces(true)
                .keep_constraint_edges()
                .with_angle_limit(spade::AngleLimit::from_deg(25.0))
                .with_max_allowed_area(area)
                .with_max_additional_vertices(2_000_000),
        );
        let excluded: std::collections::HashSet<_> = result.excluded_faces.iter().copied().collect();
        let verts: Vec<Vector3> = cdt.vertices().map(|v| basis.to_space(v.position().x, v.position().y)).collect();
        let mut tris = Vec::new();
        for f in cdt.inner_faces() {
            if excluded.contains(&f.fix()) {
                continue;
            }
            let [a, b, c] = f.vertices().map(|v| v.fix().index() as u32);
            tris.push([a, b, c]); // counter-clockwise in (u, v): normal +n
        }
        let surface = TriangleSurface::new(verts, tris)?;
        if surface.max_edge() <= max_edge * (1.0 + 1e-12) {
            return Ok(drop_unused(surface));
        }
        area *= 0.5;
    }
    Err(format!("could not mesh the polygon with edges at most {max_edge}"))
}

/// A parallelogram (four points, opposite sides equal to 1e-12 of its size; a rectangle
/// is one) is meshed on a regular lattice: corners a, b, c, d, m × n cells of spacing at
/// most `max_edge`/√2 along a → b and a → d (so the diagonals are at most `max_edge`),
/// vertex (i, j) at a + (i/m)(b − a) + (j/n)(d − a), each cell split along its (i, j) →
/// (i+1, j+1) diagonal. Along an axis-aligned side this places the crack particles where
/// the 2D `crack::subdivide` places them for a spacing of `max_edge`/√2, and a crack
/// extruded from a 2D one is cut by every plane across the extrusion in the 2D polyline
/// (the 2D ↔ 3D comparisons rely on it). None for other polygons.
fn parallelogram_lattice(points: &[Vector3], max_edge: f64) -> Option<TriangleSurface> {
    let [a, b, c, d] = <[Vector3; 4]>::try_from(points).ok()?;
    let size = (c - a).norm().max((d - b).norm());
    if (c - b - (d - a)).norm() > 1e-12 * size {
        return None;
    }
    let spacing = max_edge / std::f64::consts::SQRT_2;
    let (ab, ad) = (b - a, d - a);
    let m = ((ab.norm() / spacing).ceil() as usize).max(1);
    let n = ((ad.norm() / spacing).ceil() as usize).max(1);
    let mut vertices = Vec::with_capacity((m + 1) * (n + 1));
    for j in 0..=n {
        for i in 0..=m {
            vertices.push(a + ab * (i as f64 / m as f64) + ad * (j as f64 / n as f64));
        }
    }
    let v = |i: usize, j: usize| (i + (m + 1) * j) as u32;
    let mut triangles = Vec::with_capacity(2 * m * n);
    for j in 0..n {
        for i in 0..m {
            triangles.push([v(i, j), v(i + 1, j), v(i + 1, j + 1)]);
            triangles.push([v(i, j), v(i + 1, j + 1), v(i, j + 1)]);
        }
    }
    TriangleSurface::new(vertices, triangles).ok()
}

/// Remove vertices no triangle uses (spade keeps none, but a refinement may), renumbering.
fn drop_unused(s: TriangleSurface) -> TriangleSurface {
    let mut used = vec![u32::MAX; s.vertices.len()];
    let mut vertices = Vec::with_capacity(s.vertices.len());
    let triangles = s
        .triangles
        .iter()
        .map(|t| {
            t.map(|i| {
                if used[i as usize] == u32::MAX {
                    used[i as usize] = vertices.len() as u32;
                    vertices.push(s.vertices[i as usize]);
                }
                used[i as usize]
            })
        })
        .collect();
    TriangleSurface { vertices, triangles }
}

/// A polygon (plane coordinates) whose sides do not meet except at shared corners.
fn check_simple(p: &[[f64; 2]]) -> Result<(), String> {
    use crate::crack::geometry::segment_intersection;
    use crate::dim::Vector;
    let n = p.len();
    let v = |k: usize| Vector::new(p[k % n][0], p[k % n][1]);
    for i in 0..n {
        for j in i + 1..n {
            if j == i + 1 || (i == 0 && j == n - 1) {
                continue;
            }
            if segment_intersection(v(i), v(i + 1), v(j), v(j + 1)).is_some() {
                return Err(format!("the polygon's sides {i} and {j} cross: a crack polygon must be simple"));
            }
        }
    }
    Ok(())
}

/// The boundary of an ellipse with semi-axes a (along `axis`, projected on the plane) and
/// b, centre `c`, unit normal n, as a polygon with sides at most `max_edge`. A disc is a = b.
pub fn ellipse_boundary(c: Vector3, n: Vector3, axis: Vector3, a: f64, b: f64, max_edge: f64) -> Result<Vec<Vector3>, String> {
    if !(a > 0.0 && b > 0.0 && a.is_finite() && b.is_finite()) {
        return Err(format!("the semi-axes must be positive, got a = {a}, b = {b}"));
    }
    let n = n.normalize();
    let u = (axis - n * axis.dot(&n)).try_normalize(1e-12).ok_or("the axis must not be parallel to the normal")?;
    let v = n.cross(&u);
    // A chord of angle 2π/m is at most max(a, b)·2π/m. A multiple of 4, so the boundary
    // has a vertex on each semi-axis and is symmetric about both.
    let m = ((2.0 * std::f64::consts::PI * a.max(b) / max_edge).ceil() as usize).max(12).next_multiple_of(4);
    Ok((0..m)
        .map(|k| {
            let th = 2.0 * std::f64::consts::PI * k as f64 / m as f64;
            c + u * (a * th.cos()) + v * (b * th.sin())
        })
        .collect())
}

/// Clip a convex or simple planar polygon to the box [lo, hi] (Sutherland–Hodgman: exact
/// for a convex polygon; a non-convex one may gain zero-width bridges, so only convex
/// shapes — discs, ellipses, rectangles — are clipped). Empty when nothing is inside.
pub fn clip_to_box(poly: &[Vector3], lo: Vector3, hi: Vector3) -> Vec<Vector3> {
    let mut out: Vec<Vector3> = poly.to_vec();
    for axis in 0..3 {
        for (bound, keep_below) in [(lo[axis], false), (hi[axis], true)] {
            let inside = |p: &Vector3| if keep_below { p[axis] <= bound } else { p[axis] >= bound };
            let input = std::mem::take(&mut out);
            for k in 0..input.len() {
                let (p, q) = (input[k], input[(k + 1) % input.len()]);
                match (inside(&p), inside(&q)) {
                    (true, true) => out.push(q),
                    (true, false) | (false, true) => {
                        let t = (bound - p[axis]) / (q[axis] - p[axis]);
                        let mut x = p + (q - p) * t;
                        x[axis] = bound;
                        out.push(x);
                        if inside(&q) {
                            out.push(q);
                        }
                    }
                    (false, false) => {}
                }
            }
            if out.is_empty() {
                return out;
            }
        }
    }
    // Remove repeated consecutive points the clipping may create.
    out.dedup();
    while out.len() > 1 && out.first() == out.last() {
        out.pop();
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rectangle_on_a_grid_plane_is_exact_and_oriented() {
        let pts = [Vector3::new(-2.0, 0.0, -3.0), Vector3::new(-2.0, 0.0, 5.0), Vector3::new(50.0, 0.0, 5.0), Vector3::new(50.0, 0.0, -3.0)];
        let s = planar_polygon(&pts, 1.0).unwrap();
        assert!(s.vertices.iter().all(|v| v.y == 0.0));
        assert!(s.max_edge() <= 1.0 + 1e-12);
        // right-hand rule: (-2,0,-3) → (-2,0,5) → (50,0,5) is +z then +x: z × x = +y
        for t in 0..s.triangles.len() {
            let n = s.normal(t);
            assert!(n.y > 0.0 && n.x == 0.0 && n.z == 0.0);
        }
        let area: f64 = (0..s.triangles.len()).map(|t| 0.5 * s.normal(t).norm()).sum();
        assert!((area - 52.0 * 8.0).abs() < 1e-9);
    }

    #[test]
    fn disc_and_its_quarter() {
        let bnd = ellipse_boundary(Vector3::zeros(), Vector3::z(), Vector3::x(), 5.0, 5.0, 0.5).unwrap();
        let s = planar_polygon(&bnd, 0.5).unwrap();
        let area: f64 = (0..s.triangles.len()).map(|t| 0.5 * s.normal(t).norm()).sum();
        assert!((area - std::f64::consts::PI * 25.0).abs() < 0.02 * 78.5);
        let q = clip_to_box(&bnd, Vector3::new(0.0, 0.0, -1.0), Vector3::new(10.0, 10.0, 1.0));
        let s = planar_polygon(&q, 0.5).unwrap();
        let qa: f64 = (0..s.triangles.len()).map(|t| 0.5 * s.normal(t).norm()).sum();
        assert!((qa - area / 4.0).abs() < 1e-6 * area);
        assert!(s.vertices.iter().all(|v| v.x >= 0.0 && v.y >= 0.0 && v.z == 0.0));
    }

    #[test]
    fn bad_meshes_are_named() {
        let v = vec![Vector3::zeros(), Vector3::x(), Vector3::y(), Vector3::new(1.0, 1.0, 0.0)];
        let e = TriangleSurface::new(v.clone(), vec![[0, 1, 2], [1, 3, 2], [1, 2, 3]]).unwrap_err();
        assert!(e.contains("triangle 2"), "{e}");
        assert!(TriangleSurface::new(v.clone(), vec![[0, 1, 2], [2, 1, 3]]).is_ok());
        let e = TriangleSurface::new(v.clone(), vec![[0, 1, 2], [1, 2, 3]]).unwrap_err();
        assert!(e.contains("triangle 1") && e.contains("consistently"), "{e}");
        let e = TriangleSurface::new(v.clone(), vec![[0, 1, 7]]).unwrap_err();
        assert!(e.contains("triangle 0"), "{e}");
        let e = TriangleSurface::new(vec![Vector3::zeros(), Vector3::x(), Vector3::x() * 2.0], vec![[0, 1, 2]]).unwrap_err();
        assert!(e.contains("zero area"), "{e}");
        let e = planar_polygon(&[Vector3::zeros(), Vector3::x(), Vector3::new(1.0, 1.0, 0.5), Vector3::y()], 0.5).unwrap_err();
        assert!(e.contains("planar"), "{e}");
        let e = planar_polygon(&[Vector3::zeros(), Vector3::new(2.0, 2.0, 0.0), Vector3::new(2.0, 0.0, 0.0), Vector3::y()], 0.5).unwrap_err();
        assert!(e.contains("cross"), "{e}");
    }
}
