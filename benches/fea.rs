//! Timing of the static Q4 FEA: assembly, Cholesky factorisation (symbolic + numeric)
//! and triangular solves, on a plain n × n square mesh (bottom edge clamped, uniform
//! traction on the top edge, plane strain).
//!
//! * ~1e5 DOFs (224 × 224 cells, 100 800 free DOFs): criterion, 10 samples.
//! * ~1e6 DOFs (707 × 707 cells, 1 001 112 free DOFs): criterion, 10 samples (the
//!   factorisation takes ~7 s per iteration on the shared 2-core machine, so the group
//!   runs ~2–3 minutes). Set CRAMP_FEA_BENCH_1E6=0 to skip it.

use cramp::dim::Vector;
use cramp::fea::{self, BoundaryConditions, Grid, GridMesh, Model};
use cramp::material::{LinearElastic, PlaneState};
use criterion::{criterion_group, criterion_main, Criterion};
use std::hint::black_box;
use std::time::{Duration, Instant};

fn problem(n: usize) -> (GridMesh, LinearElastic) {
    let grid = Grid::new(Vector::zeros(), Vector::new(1.0, 1.0), n, n).unwrap();
    let gm = GridMesh::from_grid(grid, |_, _, _| true).unwrap();
    (gm, LinearElastic { e: 1000.0, nu: 0.3, rho: 1.0, state: PlaneState::PlaneStrain })
}

fn bcs(gm: &GridMesh, model: &Model) -> BoundaryConditions {
    let mut b = BoundaryConditions::new(&gm.mesh);
    let n = gm.grid.ny;
    for a in 0..gm.mesh.n_nodes() {
        if gm.node_grid[a][1] == 0 {
            b.prescribe_node(a, Vector::zeros()).unwrap();
        }
    }
    let mut top: Vec<usize> = (0..gm.mesh.n_nodes()).filter(|&a| gm.node_grid[a][1] == n).collect();
    top.sort_by_key(|&a| gm.node_grid[a][0]);
    for w in top.windows(2) {
        b.edge_traction(model, w[0], w[1], |_| Vector::new(0.0, 1.0)).unwrap();
    }
    b
}

fn bench_1e5(c: &mut Criterion) {
    let (gm, mat) = problem(224);
    let model = Model::new(&gm.mesh, mat, 1.0).unwrap();
    let b = bcs(&gm, &model);
    let sys = fea::assemble(&model, &b).unwrap();
    println!("1e5 case: {} equations, {} stored nonzeros (lower K_ff)", sys.n_equations(), sys.k.compute_nnz());
    let fac = sys.factorize().unwrap();
    let mut g = c.benchmark_group("fea_1e5_dofs");
    g.sample_size(10).measurement_time(Duration::from_secs(5)).warm_up_time(Duration::from_secs(1));
    g.bench_function("assemble", |bch| bch.iter(|| black_box(fea::assemble(&model, &b).unwrap())));
    g.bench_function("factorize", |bch| bch.iter(|| black_box(sys.factorize().unwrap())));
    g.bench_function("solve", |bch| bch.iter(|| black_box(fac.solve(&sys.rhs))));
    g.finish();
}

fn bench_1e6(c: &mut Criterion) {
    if std::env::var("CRAMP_FEA_BENCH_1E6").as_deref() == Ok("0") {
        return;
    }
    let (gm, mat) = problem(707);
    let model = Model::new(&gm.mesh, mat, 1.0).unwrap();
    let b = bcs(&gm, &model);
    let t = Instant::now();
    let sys = fea::assemble(&model, &b).unwrap();
    let t_asm = t.elapsed();
    let t = Instant::now();
    let fac = sys.factorize().unwrap();
    let t_fac = t.elapsed();
    println!(
        "1e6 case: {} equations, {} stored nonzeros (lower K_ff); first run: assemble {:.2} s, factorize {:.2} s",
        sys.n_equations(),
        sys.k.compute_nnz(),
        t_asm.as_secs_f64(),
        t_fac.as_secs_f64()
    );
    let mut g = c.benchmark_group("fea_1e6_dofs");
    g.sample_size(10).measurement_time(Duration::from_secs(20)).warm_up_time(Duration::from_millis(1));
    g.bench_function("assemble", |bch| bch.iter(|| black_box(fea::assemble(&model, &b).unwrap())));
    g.bench_function("factorize", |bch| bch.iter(|| black_box(sys.factorize().unwrap())));
    g.bench_function("solve", |bch| bch.iter(|| black_box(fac.solve(&sys.rhs))));
    g.finish();
}

criterion_group!(benches, bench_1e5, bench_1e6);
criterion_main!(benches);
