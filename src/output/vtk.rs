//! Legacy VTK writer (placeholder signature; the full writer lands from the output branch).
use crate::dim::{Sym, Vector};

pub enum PointData<'a> {
    Scalar(&'a [f64]),
    Vector(&'a [Vector]),
    Tensor(&'a [Sym]),
}

pub fn write_points(_path: &std::path::Path, _title: &str, _positions: &[Vector], _data: &[(&str, PointData)]) -> std::io::Result<()> {
    Ok(())
}
