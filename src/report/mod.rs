//! Reports: plots and the index.
pub mod plot;
