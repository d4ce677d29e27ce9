//! Timing of the static Q4 FEA: assembly, Cholesky factorisation (symbolic + numeric)
//! and triangular solves, on a plain n × n square mesh (bottom edge clamped, uniform
//! traction on the top edge, plane strain); and of the hex8 FEA on an n × n × n cube
//! (bottom face clamped, uniform load on the top face), with the peak memory.
//!
//! * 3D ~1e5 DOFs (32³ cells, 104 544 free DOFs, 4.0e6 stored non-zeros): criterion, 10
//!   samples; the group runs first so that its peak resident memory (VmHWM) is its own.
//!   The 3D system is eliminated in nested-dissection order (`fea::ordering`); with faer's
//!   AMD instead (`examples/fea3d_ordering.rs N amd`, one ordering per process):
//!
//!   | cube | equations | factor entries ND / AMD | factorise ND / AMD | peak memory ND / AMD |
//!   |---|---|---|---|---|
//!   | 20³ | 26,460 | 1.71e7 / 2.96e7 | 2.3 s / 6.5 s | 0.18 / 0.27 GiB |
//!   | 32³ | 104,544 | 1.17e8 / 2.15e8 | 27.6 s / 86.7 s | 1.04 / 1.78 GiB |
//!   | 45³ | 285,660 | 4.73e8 / — | 185 s / — | 3.98 GiB / — |
//!
//!   (shared 2-core machine, load 6–8; the residual |Ku − f|/|f| is 1e-13 either way).
//!   Factor entries grow like n^1.39 under ND (n^(4/3) in theory) against ~n^(5/3) under
//!   AMD (measured on the penny meshes: 4.5e4 equations 0.6 GiB, 1.4e5 3.3 GiB, 3.0e5 more
//!   than 12 GiB).
//! * 3D ~1e6 DOFs (69³ cells, ~1.0e6 free DOFs): not run by default. Extrapolated from the
//!   table, ND needs ~2.7e9 factor entries (~20 GiB) and ~40 min on the shared machine: at
//!   the edge of the development machine's 24 GiB (AMD ended near 5–7e5 equations).
//!   CRAMP_FEA3D_BENCH_1E6=1 runs it anyway.
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

/// The hex8 cube: n³ cells of unit size, bottom face clamped, unit nodal loads in z on the top face.
fn cube(n: usize) -> (cramp::fea::mesh3::GridMesh3, BoundaryConditions) {
    use cramp::dim::Vector3;
    use cramp::grid::Grid3;
    let grid = Grid3 { origin: Vector3::zeros(), h: Vector3::repeat(1.0), n: [n, n, n] };
    let gm = cramp::fea::mesh3::GridMesh3::from_grid(grid, |_| true).unwrap();
    let mut b = BoundaryConditions::for_nodes(gm.mesh.n_nodes(), 3);
    for (a, ijk) in gm.node_grid.iter().enumerate() {
        if ijk[2] == 0 {
            for c in 0..3 {
                b.prescribe(a, c, 0.0).unwrap();
            }
        } else if ijk[2] == n {
            b.add_load(a, &[0.0, 0.0, 1.0]).unwrap();
        }
    }
    (gm, b)
}

fn bench_3d(c: &mut Criterion, n: usize, group: &str) {
    use cramp::fea::solve3::{assemble_3d, Model3};
    let (gm, b) = cube(n);
    let model = Model3::new(&gm.mesh, LinearElastic::solid(1000.0, 0.3, 1.0)).unwrap();
    let t = Instant::now();
    let sys = assemble_3d(&model, &b).unwrap();
    let t_asm = t.elapsed();
    let t = Instant::now();
    let fac = sys.factorize().unwrap();
    let t_fac = t.elapsed();
    let t = Instant::now();
    black_box(fac.solve(&sys.rhs));
    println!(
        "{group}: {} equations, {} stored nonzeros (lower K_ff); first run: assemble {:.2} s, factorize {:.2} s, solve {:.3} s; \
         peak resident memory {:.2} GiB",
        sys.n_equations(),
        sys.k.compute_nnz(),
        t_asm.as_secs_f64(),
        t_fac.as_secs_f64(),
        t.elapsed().as_secs_f64(),
        cramp::fea::run3::peak_memory_bytes().unwrap_or(0) as f64 / (1u64 << 30) as f64
    );
    let mut g = c.benchmark_group(group);
    g.sample_size(10).measurement_time(Duration::from_secs(10)).warm_up_time(Duration::from_millis(1));
    g.bench_function("assemble", |bch| bch.iter(|| black_box(assemble_3d(&model, &b).unwrap())));
    g.bench_function("factorize", |bch| bch.iter(|| black_box(sys.factorize().unwrap())));
    g.bench_function("solve", |bch| bch.iter(|| black_box(fac.solve(&sys.rhs))));
    g.finish();
}

fn bench_3d_1e5(c: &mut Criterion) {
    bench_3d(c, 32, "fea3d_1e5_dofs");
}

fn bench_3d_1e6(c: &mut Criterion) {
    if std::env::var("CRAMP_FEA3D_BENCH_1E6").as_deref() == Ok("1") {
        bench_3d(c, 69, "fea3d_1e6_dofs");
    }
}

criterion_group!(benches, bench_3d_1e5, bench_3d_1e6, bench_1e5, bench_1e6);
criterion_main!(benches);
