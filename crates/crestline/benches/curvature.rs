//! Throughput of the curvature estimators (rayon-parallel), in vertices per second.
//!
//! ```sh
//! cargo bench -p crestline --bench curvature
//! ```
//!
//! Meshes: a generated torus of 100,000 vertices (valence 6), and the real meshes igea.ply
//! and stanford-bunny.obj from `../shared/data/meshes` when the I/O module can read them
//! (they are skipped with a note otherwise).

mod common;

use crestline::TriMesh;
use crestline::curvature::{
    CubicFitOptions, JetFitOptions, ShapeOperatorOptions, cubic_fit, jet_fit, shape_operator,
};
use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};

fn meshes() -> Vec<(String, TriMesh)> {
    common::torus_and_shared_meshes(&["igea.ply", "stanford-bunny.obj"])
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("curvature");
    group.sample_size(10);
    for (name, mesh) in meshes() {
        group.throughput(Throughput::Elements(mesh.num_vertices() as u64));
        group.bench_with_input(BenchmarkId::new("shape_operator", &name), &mesh, |b, m| {
            b.iter(|| shape_operator(m, &ShapeOperatorOptions::DEFAULT))
        });
        // The default estimator of `extract` (igea is noisy: cubic fits over wider discs).
        group.bench_with_input(BenchmarkId::new("jet_fit", &name), &mesh, |b, m| {
            b.iter(|| jet_fit(m, &JetFitOptions::DEFAULT))
        });
        for rings in [1, 2] {
            let options = CubicFitOptions::DEFAULT.with_rings(rings);
            group.bench_with_input(
                BenchmarkId::new(format!("cubic_fit_k{rings}"), &name),
                &mesh,
                |b, m| b.iter(|| cubic_fit(m, &options)),
            );
        }
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
