//! Throughput of the two curvature estimators (rayon-parallel), in vertices per second.
//!
//! ```sh
//! cargo bench -p crestline --bench curvature
//! ```
//!
//! Meshes: a generated torus of 100,000 vertices (valence 6), and the real meshes igea.ply
//! and stanford-bunny.obj from `../shared/data/meshes` when the I/O module can read them
//! (they are skipped with a note otherwise).

use std::path::PathBuf;

use crestline::TriMesh;
use crestline::curvature::{CubicFitOptions, ShapeOperatorOptions, cubic_fit, shape_operator};
use crestline::shapes::{self, GridPattern};
use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};

fn meshes() -> Vec<(String, TriMesh)> {
    let mut out = vec![(
        "torus-100k".to_string(),
        shapes::torus_with(3.0, 1.0, 400, 250, GridPattern::Uniform),
    )];
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data/meshes");
    for name in ["igea.ply", "stanford-bunny.obj"] {
        match crestline::io::read_mesh(&dir.join(name), None) {
            Ok(m) => out.push((name.to_string(), m)),
            Err(e) => eprintln!("skipping {name}: {e}"),
        }
    }
    out
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("curvature");
    group.sample_size(10);
    for (name, mesh) in meshes() {
        group.throughput(Throughput::Elements(mesh.num_vertices() as u64));
        group.bench_with_input(BenchmarkId::new("shape_operator", &name), &mesh, |b, m| {
            b.iter(|| shape_operator(m, &ShapeOperatorOptions::DEFAULT))
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
