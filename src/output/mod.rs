//! Outputs: VTK snapshots, history CSV, summary JSON.
pub mod vtk;
