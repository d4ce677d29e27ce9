//! Reports: plots and the index.
pub mod particles;
pub mod plot;
pub mod surface3;
