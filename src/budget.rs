//! What a scene will cost before anything is allocated: the memory of its grid and
//! particles, checked against the machine's memory when the scene is built, so a typo in
//! a cell size is a clear error instead of a process that swaps or is killed.
//!
//! The estimate counts, per grid node, the nodal arrays of every velocity field (one, or
//! three with cracks) and the boundary-condition and incidence arrays; per particle, its
//! state, its particle–node pairs and the per-step buffers (including the gathers over
//! the nodes particles make active). The particle count is bounded from the bodies' bounding boxes (every sub-cell
//! centre in them), so the bound needs no particle fill. `tests/memory_estimate.rs`
//! checks the estimate against the peak memory of real builds and steps (the estimate is
//! at least the peak and less than three times it).

use crate::scene::{Scene, SceneError};

/// Bytes per grid node without cracks: one field's mass and six vectors (104 B), the
/// node flags, active list, boundary conditions and pair incidence (30 B), rounded up
/// (measured: 143 B per node on a large, mostly empty grid).
pub const BYTES_PER_NODE: f64 = 192.0;

/// Bytes per grid node with cracks: three velocity fields (312 B), the contact volume,
/// normal and crack index (26 B), the rest as without cracks, rounded up (measured:
/// 377 B per node).
pub const BYTES_PER_NODE_CRACKS: f64 = 512.0;

/// Bytes per particle: its state (≈ 200 B, up to twice that while the arrays grow by
/// doubling during the fill), up to 9 particle–node pairs with shape function,
/// gradient, node, field and incidence (≈ 300 B), and the per-step buffers (velocity
/// gradient, increments, crack pairs, ≈ 150 B; and the gathers' 232 B per node the
/// particles make active, at most one node per particle), rounded up.
pub const BYTES_PER_PARTICLE: f64 = 1024.0;

/// The memory a scene needs, estimated before building it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MemoryEstimate {
    pub cells: [f64; 2],
    pub nodes: f64,
    /// Upper bound on the particles: sub-cell centres inside the bodies' bounding boxes.
    pub particles: f64,
    pub bytes: f64,
}

/// The memory a scene may use: `CRAMP_MEMORY_LIMIT` (bytes, e.g. `8e9`) if set, else
/// the memory available now (Linux `/proc/meminfo`); None where neither is known.
pub fn memory_limit() -> Option<f64> {
    if let Some(v) = std::env::var_os("CRAMP_MEMORY_LIMIT") {
        return v.to_str().and_then(|s| s.trim().parse::<f64>().ok()).filter(|x| *x > 0.0);
    }
    let info = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = info.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024.0)
}

/// Bytes in a human unit.
fn human(bytes: f64) -> String {
    const UNITS: [&str; 5] = ["B", "kB", "MB", "GB", "TB"];
    let (mut x, mut u) = (bytes, 0);
    while x >= 1000.0 && u + 1 < UNITS.len() {
        x /= 1000.0;
        u += 1;
    }
    format!("{x:.1} {}", UNITS[u])
}

impl Scene {
    /// Estimate the memory of the grid and particles (call on a validated scene).
    pub fn memory_estimate(&self) -> MemoryEstimate {
        let g = &self.grid;
        let cells = [(g.size[0] / g.cell[0]).round(), (g.size[1] / g.cell[1]).round()];
        let nodes = (cells[0] + 1.0) * (cells[1] + 1.0);
        let n = self.solver.particles_per_cell as f64;
        let (lo, hi) = ([g.origin[0], g.origin[1]], [g.origin[0] + g.size[0], g.origin[1] + g.size[1]]);
        let particles: f64 = self
            .bodies
            .iter()
            .map(|b| {
                let (bmin, bmax) = b.shape.bounds();
                let extent =
                    |c: usize, a: f64, b: f64| ((b.min(hi[c]) - a.max(lo[c])) / g.cell[c] * n).max(0.0).floor() + 1.0;
                extent(0, bmin.x, bmax.x) * extent(1, bmin.y, bmax.y)
            })
            .sum();
        let per_node = if self.cracks.is_empty() { BYTES_PER_NODE } else { BYTES_PER_NODE_CRACKS };
        MemoryEstimate { cells, nodes, particles, bytes: nodes * per_node + particles * BYTES_PER_PARTICLE }
    }

    /// Refuse a scene whose estimated memory exceeds `limit` bytes (None: no check); the
    /// error names the grid and the estimate.
    pub fn check_memory(&self, limit: Option<f64>) -> Result<(), SceneError> {
        let Some(limit) = limit else { return Ok(()) };
        let e = self.memory_estimate();
        if e.bytes <= limit {
            return Ok(());
        }
        Err(SceneError::Invalid {
            field: "grid".into(),
            message: format!(
                "the scene needs about {} ({} × {} cells: {:.3e} nodes, up to {:.3e} particles), more than the {} of memory \
                 available; use larger cells or a smaller grid (CRAMP_MEMORY_LIMIT, in bytes, sets the limit)",
                human(e.bytes),
                e.cells[0],
                e.cells[1],
                e.nodes,
                e.particles,
                human(limit)
            ),
        })
    }
}
