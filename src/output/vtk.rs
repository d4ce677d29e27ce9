//! Legacy VTK files (ASCII) for ParaView, and a reader for the files written here.
//!
//! Two kinds of file are written, both `DATASET POLYDATA` in the legacy format
//! (`# vtk DataFile Version 3.0`, which every ParaView version opens):
//!
//! * [`write_points`] — material points as `VERTICES` cells (one vertex per point,
//!   z = 0) with named `POINT_DATA` arrays: scalars, vectors and symmetric tensors.
//! * [`write_polylines`] — crack paths as `LINES` cells with named `CELL_DATA`
//!   scalars (one value per line).
//!
//! [`read_points`] reads back a file written by [`write_points`], and
//! [`read_points_3d`] one written by [`write_points_3d`]; `cramp compare` uses them
//! to diff two runs field by field.
//!
//! ## The reader is told the dimension
//!
//! A legacy VTK file always holds three coordinates per point, so the file alone
//! does not say whether it is 2D or 3D. The caller says so: [`read_points`] reads a
//! 2D file and rejects any non-zero out-of-plane component (z of a point or vector,
//! xz/yz/zx/zy of a tensor) as a malformed file, with the line; [`read_points_3d`]
//! reads every component as written, into [`PointArray::Vector3`] and
//! [`PointArray::Tensor3`]. `cramp compare` takes the dimension of a run from its
//! `history.csv` (a `momentum_z` column means 3D, see `docs/compare.md`).
//!
//! ## Numbers are written exactly
//!
//! Every `f64` is written with Rust's `{:e}` format: the shortest decimal string
//! that parses back to the *same bits* (e.g. `1e-1`, `-0e0`, `5e-324`). A snapshot
//! read back with [`read_points`] is therefore bit-identical to what was written,
//! so comparing two runs compares the runs, not the printing.
//!
//! ## Non-finite values are rejected
//!
//! ParaView's legacy ASCII reader parses numbers with C++ streams, which do not
//! accept `nan` or `inf`; a file containing them does not open. A NaN in a
//! snapshot of a reference code is a bug to surface, not data to plot, so the
//! writers return an [`std::io::ErrorKind::InvalidInput`] error naming the array
//! and the entry, and create no file. The check runs before the file is opened.
//! The reader, symmetrically, refuses `nan`/`inf` tokens.
//!
//! ## Names
//!
//! Legacy VTK array names cannot contain whitespace, and the title is one line of
//! at most 255 characters; both are checked. Array names must be unique within a
//! file, since the reader (and `cramp compare`) look arrays up by name.

use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::Path;

use anyhow::{anyhow, bail, Context};

use crate::dim::{Sym, Sym3, Vector, Vector3};

/// The first line of every file: the legacy format version ParaView reads.
const VTK_HEADER: &str = "# vtk DataFile Version 3.0";

/// Longest title the legacy format allows (the line is read into a 256-byte buffer).
const MAX_TITLE_LEN: usize = 255;

// ---------------------------------------------------------------------------
// Data passed to the writer, and read back by the reader
// ---------------------------------------------------------------------------

/// One named per-point array to write, borrowed from the caller.
#[derive(Clone, Copy, Debug)]
pub enum PointData<'a> {
    /// One number per point (`SCALARS name double 1`).
    Scalar(&'a [f64]),
    /// One in-plane vector per point (`VECTORS`, written with z = 0).
    Vector(&'a [Vector]),
    /// One symmetric tensor per point (`TENSORS`, written as the full 3×3 matrix
    /// `[[xx, xy, 0], [xy, yy, 0], [0, 0, zz]]`).
    Tensor(&'a [Sym]),
    /// One 3D vector per point (3D scenes).
    Vector3(&'a [Vector3]),
    /// One 3D symmetric tensor per point (3D scenes).
    Tensor3(&'a [Sym3]),
}

impl PointData<'_> {
    fn len(&self) -> usize {
        match self {
            PointData::Scalar(v) => v.len(),
            PointData::Vector(v) => v.len(),
            PointData::Tensor(v) => v.len(),
            PointData::Vector3(v) => v.len(),
            PointData::Tensor3(v) => v.len(),
        }
    }

    /// The first non-finite entry, as (point index, component name), if any.
    fn first_non_finite(&self) -> Option<(usize, &'static str)> {
        match self {
            PointData::Scalar(v) => v.iter().position(|x| !x.is_finite()).map(|i| (i, "value")),
            PointData::Vector(v) => v
                .iter()
                .enumerate()
                .find_map(|(i, a)| first_bad(&[("x", a.x), ("y", a.y)]).map(|c| (i, c))),
            PointData::Tensor(v) => v.iter().enumerate().find_map(|(i, s)| {
                first_bad(&[("xx", s.xx), ("yy", s.yy), ("zz", s.zz), ("xy", s.xy)]).map(|c| (i, c))
            }),
            PointData::Vector3(v) => v.iter().enumerate().find_map(|(i, a)| first_bad(&[("x", a.x), ("y", a.y), ("z", a.z)]).map(|c| (i, c))),
            PointData::Tensor3(v) => v.iter().enumerate().find_map(|(i, s)| {
                first_bad(&[("xx", s.xx), ("yy", s.yy), ("zz", s.zz), ("xy", s.xy), ("xz", s.xz), ("yz", s.yz)]).map(|c| (i, c))
            }),
        }
    }
}

/// One named per-point array read back from a file, owned.
#[derive(Clone, Debug, PartialEq)]
pub enum PointArray {
    Scalar(Vec<f64>),
    Vector(Vec<Vector>),
    Tensor(Vec<Sym>),
    /// A vector array of a 3D file ([`read_points_3d`]).
    Vector3(Vec<Vector3>),
    /// A tensor array of a 3D file ([`read_points_3d`]).
    Tensor3(Vec<Sym3>),
}

impl PointArray {
    /// Borrow as the writer's [`PointData`], e.g. to write a snapshot back out.
    pub fn as_point_data(&self) -> PointData<'_> {
        match self {
            PointArray::Scalar(v) => PointData::Scalar(v),
            PointArray::Vector(v) => PointData::Vector(v),
            PointArray::Tensor(v) => PointData::Tensor(v),
            PointArray::Vector3(v) => PointData::Vector3(v),
            PointArray::Tensor3(v) => PointData::Tensor3(v),
        }
    }
}

/// The content of a file written by [`write_points`] (`P = Vector`) or
/// [`write_points_3d`] (`P = Vector3`).
#[derive(Clone, Debug, PartialEq)]
pub struct PointSnapshot<P = Vector> {
    pub title: String,
    pub positions: Vec<P>,
    /// The arrays in file order, with their names.
    pub arrays: Vec<(String, PointArray)>,
}

impl<P> PointSnapshot<P> {
    /// The array with this name, if present.
    pub fn array(&self, name: &str) -> Option<&PointArray> {
        self.arrays.iter().find(|(n, _)| n == name).map(|(_, a)| a)
    }
}

// ---------------------------------------------------------------------------
// Writers
// ---------------------------------------------------------------------------

/// Write material points as a legacy VTK POLYDATA file of vertex cells with
/// named point arrays. Every array must have one entry per position.
///
/// Errors (`InvalidInput`, no file created): a length mismatch, a non-finite
/// number, a bad title or array name, or a duplicate array name.
pub fn write_points(
    path: impl AsRef<Path>,
    title: &str,
    positions: &[Vector],
    data: &[(&str, PointData)],
) -> io::Result<()> {
    let xyz: Vec<[f64; 3]> = positions.iter().map(|p| [p.x, p.y, 0.0]).collect();
    write_points_xyz(path, title, &xyz, data)
}

/// [`write_points`] for 3D positions (3D scenes).
pub fn write_points_3d(path: impl AsRef<Path>, title: &str, positions: &[Vector3], data: &[(&str, PointData)]) -> io::Result<()> {
    let xyz: Vec<[f64; 3]> = positions.iter().map(|p| [p.x, p.y, p.z]).collect();
    write_points_xyz(path, title, &xyz, data)
}

fn write_points_xyz(path: impl AsRef<Path>, title: &str, positions: &[[f64; 3]], data: &[(&str, PointData)]) -> io::Result<()> {
    // 1. Validate everything before touching the file system.
    check_title(title)?;
    check_positions(positions)?;
    let n = positions.len();
    check_names(data.iter().map(|(name, _)| *name))?;
    for (name, array) in data {
        if array.len() != n {
            return Err(invalid(format!(
                "point array '{name}' has {} entries for {n} points",
                array.len()
            )));
        }
        if let Some((i, component)) = array.first_non_finite() {
            return Err(invalid(format!(
                "point array '{name}' has a non-finite {component} at point {i}; \
                 legacy VTK ASCII cannot hold NaN or inf"
            )));
        }
    }

    // 2. Header, points, one vertex cell per point.
    let mut w = BufWriter::new(File::create(path)?);
    write_header_and_points(&mut w, title, positions)?;
    writeln!(w, "VERTICES {n} {}", 2 * n)?;
    for i in 0..n {
        writeln!(w, "1 {i}")?;
    }

    // 3. The point arrays.
    if !data.is_empty() {
        writeln!(w, "POINT_DATA {n}")?;
    }
    for (name, array) in data {
        match array {
            PointData::Scalar(values) => {
                writeln!(w, "SCALARS {name} double 1")?;
                writeln!(w, "LOOKUP_TABLE default")?;
                for &x in values.iter() {
                    writeln!(w, "{x:e}")?;
                }
            }
            PointData::Vector(vectors) => {
                writeln!(w, "VECTORS {name} double")?;
                for v in vectors.iter() {
                    writeln!(w, "{:e} {:e} 0e0", v.x, v.y)?;
                }
            }
            PointData::Tensor(tensors) => {
                writeln!(w, "TENSORS {name} double")?;
                for s in tensors.iter() {
                    writeln!(w, "{:e} {:e} 0e0", s.xx, s.xy)?;
                    writeln!(w, "{:e} {:e} 0e0", s.xy, s.yy)?;
                    writeln!(w, "0e0 0e0 {:e}", s.zz)?;
                    writeln!(w)?; // blank line between tensors, for the human reader
                }
            }
            PointData::Vector3(vectors) => {
                writeln!(w, "VECTORS {name} double")?;
                for v in vectors.iter() {
                    writeln!(w, "{:e} {:e} {:e}", v.x, v.y, v.z)?;
                }
            }
            PointData::Tensor3(tensors) => {
                writeln!(w, "TENSORS {name} double")?;
                for s in tensors.iter() {
                    writeln!(w, "{:e} {:e} {:e}", s.xx, s.xy, s.xz)?;
                    writeln!(w, "{:e} {:e} {:e}", s.xy, s.yy, s.yz)?;
                    writeln!(w, "{:e} {:e} {:e}", s.xz, s.yz, s.zz)?;
                    writeln!(w)?;
                }
            }
        }
    }
    w.flush()
}

/// Write polylines (crack paths) as a legacy VTK POLYDATA file of `LINES` cells,
/// with named per-line scalars (`CELL_DATA`), one value per line.
///
/// Errors (`InvalidInput`, no file created): a line with fewer than 2 points,
/// a length mismatch, a non-finite number, a bad title or name.
pub fn write_polylines(
    path: impl AsRef<Path>,
    title: &str,
    lines: &[Vec<Vector>],
    cell_scalars: &[(&str, &[f64])],
) -> io::Result<()> {
    // 1. Validate.
    check_title(title)?;
    if let Some(k) = lines.iter().position(|line| line.len() < 2) {
        return Err(invalid(format!("polyline {k} has fewer than 2 points")));
    }
    let points: Vec<[f64; 3]> = lines.iter().flatten().map(|p| [p.x, p.y, 0.0]).collect();
    check_positions(&points)?;
    check_names(cell_scalars.iter().map(|(name, _)| *name))?;
    for (name, values) in cell_scalars {
        if values.len() != lines.len() {
            return Err(invalid(format!(
                "cell array '{name}' has {} entries for {} lines",
                values.len(),
                lines.len()
            )));
        }
        if let Some(i) = values.iter().position(|x| !x.is_finite()) {
            return Err(invalid(format!(
                "cell array '{name}' has a non-finite value at line {i}"
            )));
        }
    }

    // 2. Header and the concatenated points of all lines.
    let mut w = BufWriter::new(File::create(path)?);
    write_header_and_points(&mut w, title, &points)?;

    // 3. One LINES cell per polyline: "count i0 i1 ...", indices into the points.
    let list_size: usize = lines.iter().map(|line| 1 + line.len()).sum();
    writeln!(w, "LINES {} {list_size}", lines.len())?;
    let mut first = 0;
    for line in lines {
        write!(w, "{}", line.len())?;
        for i in first..first + line.len() {
            write!(w, " {i}")?;
        }
        writeln!(w)?;
        first += line.len();
    }

    // 4. Per-line scalars.
    if !cell_scalars.is_empty() {
        writeln!(w, "CELL_DATA {}", lines.len())?;
    }
    for (name, values) in cell_scalars {
        writeln!(w, "SCALARS {name} double 1")?;
        writeln!(w, "LOOKUP_TABLE default")?;
        for &x in values.iter() {
            writeln!(w, "{x:e}")?;
        }
    }
    w.flush()
}

/// Write triangle meshes (3D crack surfaces) as a legacy VTK POLYDATA file of
/// `POLYGONS` cells, with named per-point vectors (`POINT_DATA`) and per-triangle scalars
/// (`CELL_DATA`). `triangles` index `points`.
///
/// Errors (`InvalidInput`, no file created): an index out of range, a length mismatch,
/// a non-finite number, a bad title or name.
pub fn write_triangles(
    path: impl AsRef<Path>,
    title: &str,
    points: &[Vector3],
    triangles: &[[u32; 3]],
    point_vectors: &[(&str, &[Vector3])],
    cell_scalars: &[(&str, &[f64])],
) -> io::Result<()> {
    check_title(title)?;
    let pts: Vec<[f64; 3]> = points.iter().map(|p| [p.x, p.y, p.z]).collect();
    check_positions(&pts)?;
    if let Some(k) = triangles.iter().position(|t| t.iter().any(|&i| i as usize >= points.len())) {
        return Err(invalid(format!("triangle {k} names a point that does not exist")));
    }
    check_names(point_vectors.iter().map(|(n, _)| *n).chain(cell_scalars.iter().map(|(n, _)| *n)))?;
    for (name, values) in point_vectors {
        if values.len() != points.len() {
            return Err(invalid(format!("point array '{name}' has {} entries for {} points", values.len(), points.len())));
        }
        if let Some(i) = values.iter().position(|v| !v.iter().all(|c| c.is_finite())) {
            return Err(invalid(format!("point array '{name}' has a non-finite value at point {i}")));
        }
    }
    for (name, values) in cell_scalars {
        if values.len() != triangles.len() {
            return Err(invalid(format!("cell array '{name}' has {} entries for {} triangles", values.len(), triangles.len())));
        }
        if let Some(i) = values.iter().position(|x| !x.is_finite()) {
            return Err(invalid(format!("cell array '{name}' has a non-finite value at triangle {i}")));
        }
    }
    let mut w = BufWriter::new(File::create(path)?);
    write_header_and_points(&mut w, title, &pts)?;
    writeln!(w, "POLYGONS {} {}", triangles.len(), 4 * triangles.len())?;
    for t in triangles {
        writeln!(w, "3 {} {} {}", t[0], t[1], t[2])?;
    }
    if !point_vectors.is_empty() {
        writeln!(w, "POINT_DATA {}", points.len())?;
    }
    for (name, values) in point_vectors {
        writeln!(w, "VECTORS {name} double")?;
        for v in values.iter() {
            writeln!(w, "{:e} {:e} {:e}", v.x, v.y, v.z)?;
        }
    }
    if !cell_scalars.is_empty() {
        writeln!(w, "CELL_DATA {}", triangles.len())?;
    }
    for (name, values) in cell_scalars {
        writeln!(w, "SCALARS {name} double 1")?;
        writeln!(w, "LOOKUP_TABLE default")?;
        for &x in values.iter() {
            writeln!(w, "{x:e}")?;
        }
    }
    w.flush()
}

/// The part shared by both writers: the four header lines and the POINTS block.
fn write_header_and_points(w: &mut impl Write, title: &str, points: &[[f64; 3]]) -> io::Result<()> {
    writeln!(w, "{VTK_HEADER}")?;
    writeln!(w, "{title}")?;
    writeln!(w, "ASCII")?;
    writeln!(w, "DATASET POLYDATA")?;
    writeln!(w, "POINTS {} double", points.len())?;
    for p in points {
        writeln!(w, "{:e} {:e} {:e}", p[0], p[1], p[2])?;
    }
    Ok(())
}

// --- Input checks shared by the writers --------------------------------------

fn invalid(message: String) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidInput, message)
}

fn first_bad(components: &[(&'static str, f64)]) -> Option<&'static str> {
    components
        .iter()
        .find(|(_, x)| !x.is_finite())
        .map(|(c, _)| *c)
}

fn check_title(title: &str) -> io::Result<()> {
    if title.contains(['\n', '\r']) {
        return Err(invalid("VTK title must be a single line".into()));
    }
    if title.len() > MAX_TITLE_LEN {
        return Err(invalid(format!(
            "VTK title is longer than {MAX_TITLE_LEN} bytes"
        )));
    }
    Ok(())
}

fn check_positions(points: &[[f64; 3]]) -> io::Result<()> {
    match points.iter().position(|p| !p.iter().all(|c| c.is_finite())) {
        Some(i) => Err(invalid(format!("point {i} has a non-finite coordinate"))),
        None => Ok(()),
    }
}

fn check_names<'n>(names: impl Iterator<Item = &'n str>) -> io::Result<()> {
    let mut seen: Vec<&str> = Vec::new();
    for name in names {
        if name.is_empty() || name.chars().any(char::is_whitespace) {
            return Err(invalid(format!(
                "VTK array name '{name}' is empty or contains whitespace"
            )));
        }
        if seen.contains(&name) {
            return Err(invalid(format!("VTK array name '{name}' is used twice")));
        }
        seen.push(name);
    }
    Ok(())
}

// ---------------------------------------------------------------------------
// Reader
// ---------------------------------------------------------------------------

/// Read a file written by [`write_points`]: title, positions and named arrays,
/// bit-identical to what was written.
///
/// This is not a general VTK reader: it accepts exactly the layout the writer
/// produces (POLYDATA, one vertex per point in order, z = 0, symmetric tensors
/// with zero out-of-plane shear) and reports anything else as an error, with
/// the line number.
pub fn read_points(path: impl AsRef<Path>) -> anyhow::Result<PointSnapshot> {
    let path = path.as_ref();
    let text = std::fs::read_to_string(path)
        .with_context(|| format!("reading VTK file {}", path.display()))?;
    parse_points(&text).with_context(|| format!("parsing VTK file {}", path.display()))
}

/// [`read_points`] on text already in memory.
pub fn parse_points(text: &str) -> anyhow::Result<PointSnapshot> {
    let (title, xyz, arrays) = parse_points_xyz(text, false)?;
    let positions = xyz.iter().map(|p| Vector::new(p[0], p[1])).collect();
    Ok(PointSnapshot { title, positions, arrays })
}

/// Read a file written by [`write_points_3d`]: every coordinate and component as
/// written, bit-identical; vectors as [`PointArray::Vector3`], tensors as
/// [`PointArray::Tensor3`] (checked symmetric). Otherwise as strict as [`read_points`].
pub fn read_points_3d(path: impl AsRef<Path>) -> anyhow::Result<PointSnapshot<Vector3>> {
    let path = path.as_ref();
    let text = std::fs::read_to_string(path)
        .with_context(|| format!("reading VTK file {}", path.display()))?;
    parse_points_3d(&text).with_context(|| format!("parsing VTK file {}", path.display()))
}

/// [`read_points_3d`] on text already in memory.
pub fn parse_points_3d(text: &str) -> anyhow::Result<PointSnapshot<Vector3>> {
    let (title, xyz, arrays) = parse_points_xyz(text, true)?;
    let positions = xyz.iter().map(|p| Vector3::new(p[0], p[1], p[2])).collect();
    Ok(PointSnapshot { title, positions, arrays })
}

/// The parser behind [`parse_points`] (`three_d = false`: out-of-plane components
/// must be 0, arrays are 2D) and [`parse_points_3d`]: title, (x, y, z) of each
/// point, and the arrays.
#[allow(clippy::type_complexity)]
fn parse_points_xyz(text: &str, three_d: bool) -> anyhow::Result<(String, Vec<[f64; 3]>, Vec<(String, PointArray)>)> {
    // 1. The four header lines.
    let mut lines = text.lines();
    let mut header_line = |expected: Option<&str>| -> anyhow::Result<String> {
        let line = lines
            .next()
            .ok_or_else(|| anyhow!("file ends inside the header"))?;
        if let Some(expected) = expected {
            if line.trim() != expected {
                bail!("expected header line '{expected}', found '{line}'");
            }
        }
        Ok(line.to_string())
    };
    header_line(Some(VTK_HEADER))?;
    let title = header_line(None)?;
    header_line(Some("ASCII"))?;
    header_line(Some("DATASET POLYDATA"))?;

    // 2. The rest is a stream of whitespace-separated tokens.
    let body_start_line = 5;
    let mut tokens = Tokens::new(lines, body_start_line);

    // POINTS n double, then n (x, y, z) triples, z = 0 in 2D.
    tokens.expect("POINTS")?;
    let n: usize = tokens.parse()?;
    tokens.expect("double")?;
    // Every point takes at least 3 coordinates and 2 vertex tokens: a count the file
    // cannot hold is an error here, not an allocation of its size.
    if n > tokens.remaining() / 5 {
        bail!("line {}: POINTS announces {n} points but the file holds only {} more tokens", tokens.line, tokens.remaining());
    }
    let mut positions = Vec::with_capacity(n);
    for _ in 0..n {
        let (x, y) = (tokens.float()?, tokens.float()?);
        let z = if three_d { tokens.float()? } else { tokens.expect_zero()? };
        positions.push([x, y, z]);
    }

    // VERTICES n 2n, then "1 i" for i in 0..n.
    tokens.expect("VERTICES")?;
    tokens.expect_usize(n)?;
    tokens.expect_usize(2 * n)?;
    for i in 0..n {
        tokens.expect_usize(1)?;
        tokens.expect_usize(i)?;
    }

    // Optional POINT_DATA n, then the arrays until the end of the file.
    let mut arrays: Vec<(String, PointArray)> = Vec::new();
    if tokens.peek().is_some() {
        tokens.expect("POINT_DATA")?;
        tokens.expect_usize(n)?;
    }
    while let Some(keyword) = tokens.next_token() {
        let name = tokens.word()?.to_string();
        tokens.expect("double")?;
        let array = match keyword {
            "SCALARS" => {
                tokens.expect_usize(1)?;
                tokens.expect("LOOKUP_TABLE")?;
                tokens.expect("default")?;
                PointArray::Scalar((0..n).map(|_| tokens.float()).collect::<Result<_, _>>()?)
            }
            "VECTORS" if three_d => {
                PointArray::Vector3((0..n).map(|_| tokens.vector3()).collect::<Result<_, _>>()?)
            }
            "VECTORS" => {
                PointArray::Vector((0..n).map(|_| tokens.vector()).collect::<Result<_, _>>()?)
            }
            "TENSORS" if three_d => {
                PointArray::Tensor3((0..n).map(|_| tokens.tensor3()).collect::<Result<_, _>>()?)
            }
            "TENSORS" => {
                PointArray::Tensor((0..n).map(|_| tokens.tensor()).collect::<Result<_, _>>()?)
            }
            other => bail!("line {}: unknown array kind '{other}'", tokens.line),
        };
        if arrays.iter().any(|(n, _)| *n == name) {
            bail!("array name '{name}' appears twice");
        }
        arrays.push((name, array));
    }

    Ok((title, positions, arrays))
}

/// Whitespace-separated tokens with the line they come from, for error messages.
struct Tokens<'t> {
    tokens: std::iter::Peekable<std::vec::IntoIter<(usize, &'t str)>>,
    /// Line of the last token taken.
    line: usize,
}

impl<'t> Tokens<'t> {
    fn new(lines: impl Iterator<Item = &'t str>, first_line: usize) -> Self {
        let tokens: Vec<(usize, &str)> = lines
            .enumerate()
            .flat_map(|(k, line)| line.split_whitespace().map(move |t| (first_line + k, t)))
            .collect();
        Tokens {
            tokens: tokens.into_iter().peekable(),
            line: first_line,
        }
    }

    /// Tokens not yet taken.
    fn remaining(&self) -> usize {
        self.tokens.len()
    }

    fn peek(&mut self) -> Option<&'t str> {
        self.tokens.peek().map(|&(_, t)| t)
    }

    fn next_token(&mut self) -> Option<&'t str> {
        let (line, token) = self.tokens.next()?;
        self.line = line;
        Some(token)
    }

    fn word(&mut self) -> anyhow::Result<&'t str> {
        self.next_token()
            .ok_or_else(|| anyhow!("unexpected end of file after line {}", self.line))
    }

    fn expect(&mut self, expected: &str) -> anyhow::Result<()> {
        let token = self.word()?;
        if token != expected {
            bail!("line {}: expected '{expected}', found '{token}'", self.line);
        }
        Ok(())
    }

    fn parse<T: std::str::FromStr>(&mut self) -> anyhow::Result<T> {
        let token = self.word()?;
        token.parse().map_err(|_| {
            anyhow!(
                "line {}: cannot parse '{token}' as {}",
                self.line,
                std::any::type_name::<T>()
            )
        })
    }

    /// A finite number (the writer never writes NaN or inf, see the module docs).
    fn float(&mut self) -> anyhow::Result<f64> {
        let x: f64 = self.parse()?;
        if !x.is_finite() {
            bail!(
                "line {}: non-finite number {x}; cramp never writes NaN or inf",
                self.line
            );
        }
        Ok(x)
    }

    fn expect_usize(&mut self, expected: usize) -> anyhow::Result<()> {
        let found: usize = self.parse()?;
        if found != expected {
            bail!("line {}: expected {expected}, found {found}", self.line);
        }
        Ok(())
    }

    /// A component the writer always writes as zero (z of a point or vector,
    /// out-of-plane shear of a tensor in a 2D file); returns it (±0).
    fn expect_zero(&mut self) -> anyhow::Result<f64> {
        let x = self.float()?;
        if x != 0.0 {
            bail!(
                "line {}: expected an out-of-plane 0, found {x:e}",
                self.line
            );
        }
        Ok(x)
    }

    fn vector(&mut self) -> anyhow::Result<Vector> {
        let (x, y) = (self.float()?, self.float()?);
        self.expect_zero()?;
        Ok(Vector::new(x, y))
    }

    /// A 3×3 tensor written as `[[xx, xy, 0], [xy, yy, 0], [0, 0, zz]]`.
    fn tensor(&mut self) -> anyhow::Result<Sym> {
        let (xx, xy) = (self.float()?, self.float()?);
        self.expect_zero()?;
        let (yx, yy) = (self.float()?, self.float()?);
        self.expect_zero()?;
        self.expect_zero()?;
        self.expect_zero()?;
        let zz = self.float()?;
        if xy.to_bits() != yx.to_bits() {
            bail!(
                "line {}: tensor is not symmetric (xy = {xy:e}, yx = {yx:e})",
                self.line
            );
        }
        Ok(Sym { xx, yy, zz, xy })
    }

    fn vector3(&mut self) -> anyhow::Result<Vector3> {
        Ok(Vector3::new(self.float()?, self.float()?, self.float()?))
    }

    /// A 3×3 tensor written as `[[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]]`; the
    /// mirrored entries must have the same bits.
    fn tensor3(&mut self) -> anyhow::Result<Sym3> {
        let mut m = [[0.0; 3]; 3];
        for row in m.iter_mut() {
            for x in row.iter_mut() {
                *x = self.float()?;
            }
        }
        for (name, (i, j)) in [("xy", (0, 1)), ("xz", (0, 2)), ("yz", (1, 2))] {
            let (a, b) = (m[i][j], m[j][i]);
            if a.to_bits() != b.to_bits() {
                let mirrored: String = name.chars().rev().collect();
                bail!(
                    "line {}: tensor is not symmetric ({name} = {a:e}, {mirrored} = {b:e})",
                    self.line
                );
            }
        }
        Ok(Sym3 { xx: m[0][0], yy: m[1][1], zz: m[2][2], xy: m[0][1], xz: m[0][2], yz: m[1][2] })
    }
}

// ---------------------------------------------------------------------------
// Tests
// ---------------------------------------------------------------------------

#[cfg(test)]
mod tests {
    use super::*;

    /// A fresh empty directory under the system temp dir, unique per test.
    fn temp_dir(test: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("cramp-vtk-{test}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    /// Awkward numbers: non-representable decimals, signed zero, subnormal,
    /// extremes, and values whose shortest repr needs all 17 digits.
    fn awkward() -> Vec<f64> {
        vec![
            0.1 + 0.2,
            -0.0,
            f64::MIN_POSITIVE / 3.0, // subnormal
            5e-324,                  // smallest subnormal
            f64::MAX,
            -f64::MIN_POSITIVE,
            1.0 / 3.0,
            std::f64::consts::PI * 1e200,
            123456789.0,
        ]
    }

    fn bits(xs: &[f64]) -> Vec<u64> {
        xs.iter().map(|x| x.to_bits()).collect()
    }

    #[test]
    fn small_file_has_the_expected_structure() {
        let dir = temp_dir("structure");
        let path = dir.join("p.vtk");
        let pos = [Vector::new(0.0, 0.5), Vector::new(1.5, -2.0)];
        let mass = [1.0, 2.0];
        let vel = [Vector::new(0.25, 0.0), Vector::new(-1.0, 3.0)];
        let stress = [
            Sym {
                xx: 1.0,
                yy: 2.0,
                zz: 3.0,
                xy: 4.0,
            },
            Sym {
                xx: -1.0,
                yy: 0.0,
                zz: 0.5,
                xy: 0.0,
            },
        ];
        write_points(
            &path,
            "cramp test step 7",
            &pos,
            &[
                ("mass", PointData::Scalar(&mass)),
                ("velocity", PointData::Vector(&vel)),
                ("stress", PointData::Tensor(&stress)),
            ],
        )
        .unwrap();

        let text = std::fs::read_to_string(&path).unwrap();
        let expected = "\
# vtk DataFile Version 3.0
cramp test step 7
ASCII
DATASET POLYDATA
POINTS 2 double
0e0 5e-1 0e0
1.5e0 -2e0 0e0
VERTICES 2 4
1 0
1 1
POINT_DATA 2
SCALARS mass double 1
LOOKUP_TABLE default
1e0
2e0
VECTORS velocity double
2.5e-1 0e0 0e0
-1e0 3e0 0e0
TENSORS stress double
1e0 4e0 0e0
4e0 2e0 0e0
0e0 0e0 3e0

-1e0 0e0 0e0
0e0 0e0 0e0
0e0 0e0 5e-1

";
        assert_eq!(text, expected);
    }

    #[test]
    fn round_trip_is_bit_exact() {
        let dir = temp_dir("roundtrip");
        let path = dir.join("p.vtk");
        let a = awkward();
        let n = a.len();
        let pos: Vec<Vector> = (0..n).map(|i| Vector::new(a[i], a[(i + 1) % n])).collect();
        let scalar: Vec<f64> = a.iter().rev().copied().collect();
        let vel: Vec<Vector> = (0..n).map(|i| Vector::new(a[(i + 2) % n], -a[i])).collect();
        let sym: Vec<Sym> = (0..n)
            .map(|i| Sym {
                xx: a[i],
                yy: a[(i + 3) % n],
                zz: a[(i + 4) % n],
                xy: a[(i + 5) % n],
            })
            .collect();
        write_points(
            &path,
            "round trip",
            &pos,
            &[
                ("s", PointData::Scalar(&scalar)),
                ("v", PointData::Vector(&vel)),
                ("sigma", PointData::Tensor(&sym)),
            ],
        )
        .unwrap();

        let snap = read_points(&path).unwrap();
        assert_eq!(snap.title, "round trip");
        let pos_bits = |p: &[Vector]| {
            p.iter()
                .flat_map(|v| [v.x.to_bits(), v.y.to_bits()])
                .collect::<Vec<_>>()
        };
        assert_eq!(pos_bits(&snap.positions), pos_bits(&pos));
        assert_eq!(snap.arrays.len(), 3);
        match snap.array("s").unwrap() {
            PointArray::Scalar(s) => assert_eq!(bits(s), bits(&scalar)),
            other => panic!("wrong kind {other:?}"),
        }
        match snap.array("v").unwrap() {
            PointArray::Vector(v) => assert_eq!(pos_bits(v), pos_bits(&vel)),
            other => panic!("wrong kind {other:?}"),
        }
        match snap.array("sigma").unwrap() {
            PointArray::Tensor(t) => {
                let sym_bits = |t: &[Sym]| {
                    t.iter()
                        .flat_map(|s| bits(&[s.xx, s.yy, s.zz, s.xy]))
                        .collect::<Vec<_>>()
                };
                assert_eq!(sym_bits(t), sym_bits(&sym));
            }
            other => panic!("wrong kind {other:?}"),
        }

        // Writing the snapshot back out gives a byte-identical file.
        let path2 = dir.join("p2.vtk");
        let data: Vec<(&str, PointData)> = snap
            .arrays
            .iter()
            .map(|(n, a)| (n.as_str(), a.as_point_data()))
            .collect();
        write_points(&path2, &snap.title, &snap.positions, &data).unwrap();
        assert_eq!(
            std::fs::read(&path).unwrap(),
            std::fs::read(&path2).unwrap()
        );
    }

    #[test]
    fn points_without_arrays_and_empty_files_round_trip() {
        let dir = temp_dir("empty");
        let path = dir.join("none.vtk");
        write_points(&path, "", &[Vector::new(1.0, 2.0)], &[]).unwrap();
        let snap = read_points(&path).unwrap();
        assert_eq!(snap.positions, vec![Vector::new(1.0, 2.0)]);
        assert!(snap.arrays.is_empty());

        let path = dir.join("zero.vtk");
        write_points(&path, "no points", &[], &[("m", PointData::Scalar(&[]))]).unwrap();
        let snap = read_points(&path).unwrap();
        assert!(snap.positions.is_empty());
        assert_eq!(snap.array("m"), Some(&PointArray::Scalar(vec![])));
    }

    #[test]
    fn non_finite_values_are_rejected_and_no_file_is_created() {
        let dir = temp_dir("nonfinite");
        let pos = [Vector::new(0.0, 0.0), Vector::new(1.0, 0.0)];
        let inf_vectors = [Vector::new(0.0, f64::INFINITY), Vector::zeros()];
        let cases: Vec<(&str, PointData)> = vec![
            ("nan_scalar", PointData::Scalar(&[1.0, f64::NAN])),
            ("inf_vector", PointData::Vector(&inf_vectors)),
        ];
        for (name, data) in cases {
            let path = dir.join(format!("{name}.vtk"));
            let err = write_points(&path, "t", &pos, &[(name, data)]).unwrap_err();
            assert_eq!(err.kind(), io::ErrorKind::InvalidInput);
            assert!(err.to_string().contains(name), "{err}");
            assert!(!path.exists());
        }
        let tensor = [
            Sym::ZERO,
            Sym {
                zz: f64::NEG_INFINITY,
                ..Sym::ZERO
            },
        ];
        let err = write_points(
            dir.join("t.vtk"),
            "t",
            &pos,
            &[("sig", PointData::Tensor(&tensor))],
        )
        .unwrap_err();
        assert!(err.to_string().contains("zz at point 1"), "{err}");

        let bad_pos = [Vector::new(f64::NAN, 0.0)];
        assert!(write_points(dir.join("p.vtk"), "t", &bad_pos, &[]).is_err());
        assert!(write_polylines(
            dir.join("l.vtk"),
            "t",
            &[bad_pos.to_vec(), pos.to_vec()],
            &[]
        )
        .is_err());
    }

    #[test]
    fn bad_inputs_are_rejected() {
        let dir = temp_dir("bad");
        let pos = [Vector::new(0.0, 0.0)];
        let path = dir.join("x.vtk");
        let one = [1.0];
        // Wrong length, bad names, duplicate names, multi-line title.
        assert!(write_points(&path, "t", &pos, &[("m", PointData::Scalar(&[1.0, 2.0]))]).is_err());
        assert!(write_points(&path, "t", &pos, &[("two words", PointData::Scalar(&one))]).is_err());
        assert!(write_points(&path, "t", &pos, &[("", PointData::Scalar(&one))]).is_err());
        let dup = [
            ("m", PointData::Scalar(&one)),
            ("m", PointData::Scalar(&one)),
        ];
        assert!(write_points(&path, "t", &pos, &dup).is_err());
        assert!(write_points(&path, "a\nb", &pos, &[]).is_err());
        assert!(!path.exists());
    }

    #[test]
    fn reader_rejects_files_it_did_not_write() {
        let good = "# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\nPOINTS 1 double\n1e0 2e0 0e0\nVERTICES 1 2\n1 0\n";
        assert!(parse_points(good).is_ok());
        let binary = good.replace("ASCII", "BINARY");
        assert!(parse_points(&binary).is_err());
        let three_d = good.replace("1e0 2e0 0e0", "1e0 2e0 1e0");
        let err = parse_points(&three_d).unwrap_err();
        assert!(err.to_string().contains("line 6"), "{err}");
        let truncated = good.replace("1 0\n", "");
        assert!(parse_points(&truncated).is_err());
        // The writer never writes NaN or inf, so the reader refuses them too.
        for bad in ["NaN", "nan", "inf", "-infinity"] {
            let text = good.replace("1e0 2e0", &format!("{bad} 2e0"));
            let err = parse_points(&text).unwrap_err();
            assert!(err.to_string().contains("non-finite"), "{err}");
        }
    }

    #[test]
    fn round_trip_3d_is_bit_exact() {
        let dir = temp_dir("roundtrip3d");
        let path = dir.join("p.vtk");
        let a = awkward();
        let n = a.len();
        let at = |i: usize| a[i % n];
        let pos: Vec<Vector3> = (0..n).map(|i| Vector3::new(at(i), at(i + 1), at(i + 2))).collect();
        let vel: Vec<Vector3> = (0..n).map(|i| Vector3::new(at(i + 3), -at(i), at(i + 7))).collect();
        let sym: Vec<Sym3> = (0..n)
            .map(|i| Sym3 { xx: at(i), yy: at(i + 1), zz: at(i + 2), xy: at(i + 3), xz: at(i + 4), yz: at(i + 5) })
            .collect();
        let id: Vec<f64> = (0..n).map(|i| i as f64).collect();
        let data = [("id", PointData::Scalar(&id)), ("v", PointData::Vector3(&vel)), ("sigma", PointData::Tensor3(&sym))];
        write_points_3d(&path, "round trip 3d", &pos, &data).unwrap();

        let snap = read_points_3d(&path).unwrap();
        let v_bits = |p: &[Vector3]| p.iter().flat_map(|v| bits(&[v.x, v.y, v.z])).collect::<Vec<_>>();
        assert_eq!(v_bits(&snap.positions), v_bits(&pos));
        assert_eq!(snap.array("id"), Some(&PointArray::Scalar(id.clone())));
        match snap.array("v").unwrap() {
            PointArray::Vector3(v) => assert_eq!(v_bits(v), v_bits(&vel)),
            other => panic!("wrong kind {other:?}"),
        }
        match snap.array("sigma").unwrap() {
            PointArray::Tensor3(t) => {
                let s_bits = |t: &[Sym3]| t.iter().flat_map(|s| bits(&[s.xx, s.yy, s.zz, s.xy, s.xz, s.yz])).collect::<Vec<_>>();
                assert_eq!(s_bits(t), s_bits(&sym));
            }
            other => panic!("wrong kind {other:?}"),
        }
        // Written back out: the same bytes.
        let path2 = dir.join("p2.vtk");
        let data: Vec<(&str, PointData)> = snap.arrays.iter().map(|(n, a)| (n.as_str(), a.as_point_data())).collect();
        write_points_3d(&path2, &snap.title, &snap.positions, &data).unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), std::fs::read(&path2).unwrap());

        // The 2D reader refuses the 3D file (a non-zero z), naming the line.
        let err = read_points(&path).unwrap_err();
        assert!(format!("{err:#}").contains("expected an out-of-plane 0"), "{err:#}");
    }

    #[test]
    fn reader_3d_rejects_files_it_did_not_write() {
        let good = "# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\nPOINTS 1 double\n1e0 2e0 3e0\nVERTICES 1 2\n1 0\nPOINT_DATA 1\nTENSORS s double\n1e0 2e0 3e0\n2e0 4e0 5e0\n3e0 5e0 6e0\n";
        let snap = parse_points_3d(good).unwrap();
        assert_eq!(snap.positions, vec![Vector3::new(1.0, 2.0, 3.0)]);
        let expected = Sym3 { xx: 1.0, yy: 4.0, zz: 6.0, xy: 2.0, xz: 3.0, yz: 5.0 };
        assert_eq!(snap.array("s"), Some(&PointArray::Tensor3(vec![expected])));
        // Each pair of mirrored entries is checked, and named.
        for (old, new, name) in [("2e0 4e0 5e0", "2.5e0 4e0 5e0", "xy"), ("3e0 5e0 6e0", "3.5e0 5e0 6e0", "xz"), ("3e0 5e0 6e0", "3e0 5.5e0 6e0", "yz")] {
            let err = parse_points_3d(&good.replace(old, new)).unwrap_err().to_string();
            assert!(err.contains("not symmetric") && err.contains(&format!("({name} = ")), "{err}");
        }
        let err = parse_points_3d(&good.replace("1e0 2e0 3e0\nVERTICES", "1e0 2e0 inf\nVERTICES")).unwrap_err();
        assert!(err.to_string().contains("non-finite") && err.to_string().contains("line 6"), "{err}");
        let err = parse_points_3d(&good.replace("POINTS 1", "POINTS 1000000000000")).unwrap_err();
        assert!(err.to_string().contains("POINTS announces"), "{err}");
        assert!(parse_points_3d(&good.replace("6e0\n", "")).is_err());
        // A 2D file is a 3D file with zero out-of-plane components.
        let two_d = "# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\nPOINTS 1 double\n1e0 2e0 0e0\nVERTICES 1 2\n1 0\n";
        assert_eq!(parse_points_3d(two_d).unwrap().positions, vec![Vector3::new(1.0, 2.0, 0.0)]);
    }

    #[test]
    fn polylines_have_the_expected_structure() {
        let dir = temp_dir("lines");
        let path = dir.join("cracks.vtk");
        let lines = vec![
            vec![
                Vector::new(0.0, 0.0),
                Vector::new(1.0, 0.0),
                Vector::new(1.5, 0.25),
            ],
            vec![Vector::new(2.0, 1.0), Vector::new(2.0, 2.0)],
        ];
        let k1 = [1.25, -0.5];
        write_polylines(&path, "cracks", &lines, &[("KI", &k1)]).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        let expected = "\
# vtk DataFile Version 3.0
cracks
ASCII
DATASET POLYDATA
POINTS 5 double
0e0 0e0 0e0
1e0 0e0 0e0
1.5e0 2.5e-1 0e0
2e0 1e0 0e0
2e0 2e0 0e0
LINES 2 7
3 0 1 2
2 3 4
CELL_DATA 2
SCALARS KI double 1
LOOKUP_TABLE default
1.25e0
-5e-1
";
        assert_eq!(text, expected);

        // Degenerate lines and mismatched lengths are rejected.
        assert!(write_polylines(&path, "t", &[vec![Vector::zeros()]], &[]).is_err());
        assert!(write_polylines(&path, "t", &lines, &[("KI", &[1.0])]).is_err());
        assert!(write_polylines(&path, "t", &lines, &[("KI", &[1.0, f64::NAN])]).is_err());
    }
}
