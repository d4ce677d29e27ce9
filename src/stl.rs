//! Closed triangulated surfaces read from STL files (binary or ASCII, with the `stl_io`
//! crate), for 3D bodies, and the exact point-in-solid test that fills them.
//!
//! **Closed**: every edge is shared by exactly two triangles that traverse it in opposite
//! directions (a closed, consistently oriented 2-manifold); otherwise the file is refused
//! with the offending edge named by its end points. `stl_io` merges vertices with equal
//! coordinates, so "shared" means the same coordinates to the bit.
//!
//! **Inside**: ray parity along +z, decided with Shewchuk's exact predicates (`robust`
//! crate, `orient2d` / `orient3d`): a triangle is crossed when the point's (x, y) lies
//! strictly inside the triangle's projection and the triangle's plane is above the point.
//! A point exactly on the surface is inside. When the ray meets an edge or vertex of the
//! projection exactly (a zero `orient2d`), the count is redone along +x, then +y. If all
//! three rays are degenerate (a point on three special lines at once: rare for a general
//! surface, but every point on an edge of an axis-aligned box meets an edge-on face along
//! each axis), an exact test decides whether the point lies on a triangle (inside);
//! otherwise the generalized winding number in floating point decides (≥ ½ is inside).
//! Every decision is therefore exact except in that last, documented case.

use crate::dim::Vector3;
use robust::{orient2d, orient3d, Coord, Coord3D};
use std::collections::HashMap;
use std::path::Path;

/// A closed, consistently oriented triangle mesh.
#[derive(Clone, Debug, PartialEq)]
pub struct ClosedMesh {
    pub vertices: Vec<Vector3>,
    pub triangles: Vec<[usize; 3]>,
}

/// Read the vertices and triangles of an STL file (binary or ASCII; `stl_io` merges
/// vertices with equal coordinates), for closed bodies and open crack surfaces alike.
pub fn read_triangles(path: &Path) -> Result<(Vec<Vector3>, Vec<[u32; 3]>), String> {
    let mut bytes = std::fs::read(path).map_err(|e| format!("cannot open: {e}"))?;
    // The size a binary file with this header's triangle count has.
    let binary_size = bytes.get(80..84).map(|c| 84 + 50 * u32::from_le_bytes([c[0], c[1], c[2], c[3]]) as u64);
    let size = bytes.len() as u64;
    if binary_size == Some(size) && bytes.starts_with(b"solid") {
        // A binary file whose free-form header begins with "solid" (some exporters
        // write that): blank the word so the reader does not take it for ASCII.
        bytes[..5].fill(b' ');
    }
    let mesh = stl_io::read_stl(&mut std::io::Cursor::new(bytes)).map_err(|e| {
        let binary = binary_size.map(|b| format!("; read as binary, its triangle count needs {b} bytes")).unwrap_or_default();
        format!("not a readable STL file ({e}): an ASCII STL starts with `solid `, a binary STL has an 80-byte header, a 4-byte triangle count and 50 bytes per triangle; this file has {size} bytes{binary}")
    })?;
    let vertices: Vec<Vector3> = mesh.vertices.iter().map(|v| Vector3::new(v[0] as f64, v[1] as f64, v[2] as f64)).collect();
    let triangles: Vec<[u32; 3]> = mesh.faces.iter().map(|f| f.vertices.map(|i| i as u32)).collect();
    Ok((vertices, triangles))
}

impl ClosedMesh {
    /// Read an STL file (binary or ASCII) and check that it is closed.
    pub fn read(path: &Path) -> Result<ClosedMesh, String> {
        let (vertices, triangles) = read_triangles(path)?;
        ClosedMesh::new(vertices, triangles.into_iter().map(|t| t.map(|i| i as usize)).collect())
    }



    /// Check closure and orientation (see the module documentation).
    pub fn new(vertices: Vec<Vector3>, triangles: Vec<[usize; 3]>) -> Result<ClosedMesh, String> {
        if let Some(v) = vertices.iter().find(|v| !v.iter().all(|c| c.is_finite())) {
            return Err(format!("has a vertex with a non-finite coordinate, ({}, {}, {})", v.x, v.y, v.z));
        }
        if triangles.len() < 4 {
            return Err(format!("has {} triangles; a closed surface needs at least 4", triangles.len()));
        }
        let fmt = |i: usize| {
            let v = vertices[i];
            format!("({}, {}, {})", v.x, v.y, v.z)
        };
        let mut directed: HashMap<(usize, usize), usize> = HashMap::new();
        for (t, tri) in triangles.iter().enumerate() {
            if tri.iter().any(|&i| i >= vertices.len()) {
                return Err(format!("triangle {t} names a vertex that does not exist"));
            }
            if tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2] {
                return Err(format!("triangle {t} is degenerate (two equal corners at {})", fmt(tri[0])));
            }
            for k in 0..3 {
                let e = (tri[k], tri[(k + 1) % 3]);
                if let Some(other) = directed.insert(e, t) {
                    return Err(format!(
                        "the edge from {} to {} is traversed in the same direction by triangles {other} and {t}: the surface is not consistently oriented (or not a manifold)",
                        fmt(e.0),
                        fmt(e.1)
                    ));
                }
            }
        }
        // Deterministic report: the lowest triangle index with an open edge.
        let mut open: Vec<(usize, (usize, usize))> = directed.iter().filter(|(e, _)| !directed.contains_key(&(e.1, e.0))).map(|(e, t)| (*t, *e)).collect();
        open.sort_unstable();
        if let Some((t, e)) = open.first() {
            return Err(format!("is not closed: the edge from {} to {} belongs to triangle {t} only", fmt(e.0), fmt(e.1)));
        }
        Ok(ClosedMesh { vertices, triangles })
    }

    /// Axis-aligned bounding box.
    pub fn bounds(&self) -> (Vector3, Vector3) {
        let mut lo = Vector3::repeat(f64::INFINITY);
        let mut hi = Vector3::repeat(f64::NEG_INFINITY);
        for v in &self.vertices {
            lo = lo.inf(v);
            hi = hi.sup(v);
        }
        (lo, hi)
    }

    /// Is x inside the closed surface (or on it)?
    pub fn contains(&self, x: &Vector3) -> bool {
        for axis in [2, 0, 1] {
            match self.ray_parity(x, axis) {
                Ray::Inside => return true,
                Ray::Outside => return false,
                Ray::Degenerate => {}
            }
        }
        self.on_surface(x) || self.winding_number(x) >= 0.5
    }

    /// Does x lie exactly on one of the triangles (boundary included)? Exact: x is in the
    /// triangle's plane (`orient3d` zero) and inside or on the edges of its projection
    /// along an axis the triangle is not parallel to.
    fn on_surface(&self, x: &Vector3) -> bool {
        let c3 = |p: &Vector3| Coord3D { x: p.x, y: p.y, z: p.z };
        self.triangles.iter().any(|tri| {
            let [a, b, c] = tri.map(|i| &self.vertices[i]);
            if (0..3).any(|k| x[k] < a[k].min(b[k]).min(c[k]) || x[k] > a[k].max(b[k]).max(c[k])) {
                return false;
            }
            if orient3d(c3(a), c3(b), c3(c), c3(x)) != 0.0 {
                return false;
            }
            (0..3).find_map(|axis| {
                let (u, w) = ((axis + 1) % 3, (axis + 2) % 3);
                let c2 = |p: &Vector3| Coord { x: p[u], y: p[w] };
                let area = orient2d(c2(a), c2(b), c2(c));
                (area != 0.0).then(|| {
                    let o = [orient2d(c2(a), c2(b), c2(x)), orient2d(c2(b), c2(c), c2(x)), orient2d(c2(c), c2(a), c2(x))];
                    o.iter().all(|&v| if area > 0.0 { v >= 0.0 } else { v <= 0.0 })
                })
            })
            .unwrap_or(false)
        })
    }

    /// Parity of the crossings of the ray from x along +axis.
    fn ray_parity(&self, x: &Vector3, axis: usize) -> Ray {
        // Coordinates permuted so that the ray runs along the third one.
        let (u, w) = ((axis + 1) % 3, (axis + 2) % 3);
        let c2 = |p: &Vector3| Coord { x: p[u], y: p[w] };
        let c3 = |p: &Vector3| Coord3D { x: p[u], y: p[w], z: p[axis] };
        let mut inside = false;
        for tri in &self.triangles {
            let [a, b, c] = tri.map(|i| &self.vertices[i]);
            // Quick reject on the projected bounding box and on the ray's half-line.
            let (umin, umax) = (a[u].min(b[u]).min(c[u]), a[u].max(b[u]).max(c[u]));
            let (wmin, wmax) = (a[w].min(b[w]).min(c[w]), a[w].max(b[w]).max(c[w]));
            if x[u] < umin || x[u] > umax || x[w] < wmin || x[w] > wmax || x[axis] > a[axis].max(b[axis]).max(c[axis]) {
                continue;
            }
            let p = c2(x);
            let o = [orient2d(c2(a), c2(b), p), orient2d(c2(b), c2(c), p), orient2d(c2(c), c2(a), p)];
            let pos = o.iter().filter(|&&v| v > 0.0).count();
            let neg = o.iter().filter(|&&v| v < 0.0).count();
            if pos > 0 && neg > 0 {
                continue; // the ray misses this triangle's projection
            }
            if pos + neg < 3 {
                // x projects onto an edge or vertex of this triangle's projection (or the
                // triangle is seen edge-on): this ray is degenerate, try another.
                return Ray::Degenerate;
            }
            let side = orient3d(c3(a), c3(b), c3(c), c3(x));
            if side == 0.0 {
                return Ray::Inside; // on the surface
            }
            // Projection strictly contains x: crossed iff the plane is above x (see orient3d's sign convention).
            if (side > 0.0) == (pos == 3) {
                inside = !inside;
            }
        }
        if inside {
            Ray::Inside
        } else {
            Ray::Outside
        }
    }

    /// Generalized winding number (Van Oosterom & Strackee solid angles / 4π).
    fn winding_number(&self, x: &Vector3) -> f64 {
        let mut total = 0.0;
        for tri in &self.triangles {
            let [a, b, c] = tri.map(|i| self.vertices[i] - x);
            let (la, lb, lc) = (a.norm(), b.norm(), c.norm());
            let num = a.dot(&b.cross(&c));
            let den = la * lb * lc + a.dot(&b) * lc + b.dot(&c) * la + c.dot(&a) * lb;
            total += 2.0 * num.atan2(den);
        }
        (total / (4.0 * std::f64::consts::PI)).abs()
    }
}

enum Ray {
    Inside,
    Outside,
    Degenerate,
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The unit cube [0,1]³ as 12 outward-oriented triangles.
    pub fn cube() -> ClosedMesh {
        let v: Vec<Vector3> = (0..8).map(|i| Vector3::new((i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64)).collect();
        let quads = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
        let t = quads.iter().flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]]).collect();
        ClosedMesh::new(v, t).unwrap()
    }

    #[test]
    fn cube_inside_outside_and_degenerate_rays() {
        let m = cube();
        assert!(m.contains(&Vector3::new(0.3, 0.4, 0.5)));
        assert!(!m.contains(&Vector3::new(1.3, 0.4, 0.5)));
        assert!(!m.contains(&Vector3::new(0.3, 0.4, -0.5)));
        // Rays through the diagonal edges of the face triangulation (x = y): degenerate
        // along z, decided along x.
        assert!(m.contains(&Vector3::new(0.5, 0.5, 0.5)));
        assert!(!m.contains(&Vector3::new(0.5, 0.5, 1.5)));
        // On the surface: inside.
        assert!(m.contains(&Vector3::new(0.25, 0.75, 1.0)));
        // On an edge and at a corner every ray is degenerate (an edge-on face along each
        // axis); the exact on-surface test decides, not the winding number (¼ and ⅛ there).
        assert!(m.contains(&Vector3::new(0.0, 0.0, 0.5)));
        assert!(m.contains(&Vector3::new(1.0, 1.0, 1.0)));
        assert!(!m.contains(&Vector3::new(1.0, 1.0, 1.5)));
    }

    #[test]
    fn open_and_misoriented_surfaces_are_refused() {
        let m = cube();
        let mut open = m.triangles.clone();
        open.pop();
        let e = ClosedMesh::new(m.vertices.clone(), open).unwrap_err();
        assert!(e.contains("is not closed: the edge from"), "{e}");
        let mut flipped = m.triangles.clone();
        flipped[0].swap(1, 2);
        let e = ClosedMesh::new(m.vertices.clone(), flipped).unwrap_err();
        assert!(e.contains("not consistently oriented"), "{e}");
    }
}
