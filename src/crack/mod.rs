//! Explicit cracks: geometry, line crossing, velocity fields, surfaces (Nairn 2003 §2).
pub mod geometry;
