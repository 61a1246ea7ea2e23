//! The extremality smoothing step (HPW sec. 5.1) with the default solver, Jacobi-preconditioned
//! conjugate gradients, next to symmetric Gauss–Seidel preconditioning and the sparse Cholesky
//! factorisation, in vertices per second.
//!
//! ```sh
//! cargo bench -p crestline --bench smoothing
//! ```
//!
//! Each iteration runs [`smooth_extremalities`] with the HPW defaults (2 implicit steps,
//! crease-aware weights, twiced since 2026-11-26: 4 solves per family) on a copy of the
//! shape-operator fields: building the operator and the steps, for both families. Meshes: igea.ply and stanford-bunny.obj from
//! `../shared/data/meshes` (skipped with a note when they cannot be read), and a generated
//! torus of 100,000 vertices.

mod common;

use crestline::TriMesh;
use crestline::curvature::{ShapeOperatorOptions, shape_operator};
use crestline::smoothing::ConjugateGradientOptions;
use crestline::smoothing::LinearSolver;
use crestline::smoothing::extremality::{ExtremalitySmoothing, smooth_extremalities};
use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};

fn meshes() -> Vec<(String, TriMesh)> {
    common::torus_and_shared_meshes(&["stanford-bunny.obj", "igea.ply"])
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("extremality_smoothing");
    group.sample_size(10);
    let solvers = [
        ("pcg_mixed_precision", LinearSolver::DEFAULT),
        (
            "pcg_plain",
            LinearSolver::PlainConjugateGradient(ConjugateGradientOptions::DEFAULT),
        ),
        ("cholesky", LinearSolver::Cholesky),
    ];
    for (name, mesh) in meshes() {
        let fields = shape_operator(&mesh, &ShapeOperatorOptions::DEFAULT);
        group.throughput(Throughput::Elements(mesh.num_vertices() as u64));
        for (solver_name, solver) in solvers {
            let options = ExtremalitySmoothing {
                solver,
                ..ExtremalitySmoothing::default()
            };
            group.bench_with_input(BenchmarkId::new(solver_name, &name), &mesh, |b, m| {
                b.iter_batched(
                    || fields.clone(),
                    |mut c| smooth_extremalities(m, &mut c, &options).map(|_| c),
                    criterion::BatchSize::LargeInput,
                )
            });
        }
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
