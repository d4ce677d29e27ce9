//! Fill-reducing ordering of the 3D FEA (issue 18, speed and memory): the hex8 cube of
//! `benches/fea.rs` (n³ unit cells, bottom face clamped, unit z loads on the top face)
//! factorised with nested dissection (the default for 3D meshes, `fea::ordering`) or
//! faer's AMD, one ordering per process so that the peak resident memory is its own.
//!
//! `cargo run --release --example fea3d_ordering -- N [nd|amd]`
//! Prints equations, factor entries, times of assembly / factorisation / solve, the
//! residual |K u − f| / |f| and the peak memory (VmHWM).

use cramp::dim::Vector3;
use cramp::fea::mesh3::GridMesh3;
use cramp::fea::solve3::{assemble_3d, Model3};
use cramp::fea::BoundaryConditions;
use cramp::grid::Grid3;
use cramp::material::LinearElastic;
use std::time::Instant;

fn main() -> anyhow::Result<()> {
    let mut args = std::env::args().skip(1);
    let n: usize = args.next().ok_or_else(|| anyhow::anyhow!("usage: fea3d_ordering N [nd|amd]"))?.parse()?;
    let ordering = args.next().unwrap_or_else(|| "nd".into());
    let grid = Grid3 { origin: Vector3::zeros(), h: Vector3::repeat(1.0), n: [n, n, n] };
    let gm = GridMesh3::from_grid(grid, |_| true)?;
    let mut b = BoundaryConditions::for_nodes(gm.mesh.n_nodes(), 3);
    for (a, ijk) in gm.node_grid.iter().enumerate() {
        if ijk[2] == 0 {
            for c in 0..3 {
                b.prescribe(a, c, 0.0)?;
            }
        } else if ijk[2] == n {
            b.add_load(a, &[0.0, 0.0, 1.0])?;
        }
    }
    let model = Model3::new(&gm.mesh, LinearElastic::solid(1000.0, 0.3, 1.0))?;
    let t = Instant::now();
    let mut sys = assemble_3d(&model, &b)?;
    let t_asm = t.elapsed().as_secs_f64();
    match ordering.as_str() {
        "nd" => {}
        "amd" => sys.ordering = None,
        other => anyhow::bail!("ordering must be nd or amd, not {other:?}"),
    }
    let t = Instant::now();
    let fac = sys.factorize()?;
    let t_fac = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let u = fac.solve(&sys.rhs);
    let t_sol = t.elapsed().as_secs_f64();
    // Residual with the lower triangle: K u = L u + Lᵀ u − diag u.
    let k = sys.k.as_ref();
    let mut r: Vec<f64> = sys.rhs.iter().map(|f| -f).collect();
    for j in 0..k.ncols() {
        for (i, v) in k.row_idx_of_col(j).zip(k.val_of_col(j)) {
            r[i] += v * u[j];
            if i != j {
                r[j] += v * u[i];
            }
        }
    }
    let norm = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
    println!(
        "n = {n} ({ordering}): {} equations, {} factor entries ({:.2} GiB); assemble {t_asm:.2} s, factorise {t_fac:.2} s, \
         solve {t_sol:.3} s; |Ku − f|/|f| = {:.1e}; peak memory {:.2} GiB",
        sys.n_equations(),
        fac.factor_entries(),
        fac.factor_entries() as f64 * 8.0 / (1u64 << 30) as f64,
        norm(&r) / norm(&sys.rhs),
        cramp::fea::run3::peak_memory_bytes().unwrap_or(0) as f64 / (1u64 << 30) as f64
    );
    Ok(())
}
