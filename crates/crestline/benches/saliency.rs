//! Mesh saliency (Mao et al. eqs. 5–8) and the knee search on its values.
//!
//! ```sh
//! cargo bench -p crestline --bench saliency
//! ```
//!
//! Meshes: igea.ply (134,345 vertices) and fandisk.obj from `../shared/data/meshes` (each is
//! skipped with a note when it cannot be read), and a generated torus of 100,000 vertices.
//! The curvature (cubic fit, as the saliency method uses) is computed once, outside the
//! timing.

mod common;

use crestline::TriMesh;
use crestline::curvature::{CurvatureOptions, Estimator, estimate};
use crestline::saliency::{SaliencyOptions, mesh_saliency};
use crestline::threshold::{KneeSearch, seek_threshold};
use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};

fn meshes() -> Vec<(String, TriMesh)> {
    let mut out = common::shared_meshes(&["igea.ply", "fandisk.obj"]);
    out.push(common::torus_100k());
    out
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("saliency");
    group.sample_size(10);
    let options = CurvatureOptions::default().with_estimator(Estimator::CubicFit);
    for (name, mesh) in meshes() {
        let Ok(curvature) = estimate(&mesh, &options) else {
            eprintln!("skipping {name}: no curvature");
            continue;
        };
        group.throughput(Throughput::Elements(mesh.num_vertices() as u64));
        group.bench_with_input(BenchmarkId::new("mesh_saliency", &name), &mesh, |b, m| {
            b.iter(|| mesh_saliency(m, &curvature, &SaliencyOptions::default()))
        });
        let Ok(s) = mesh_saliency(&mesh, &curvature, &SaliencyOptions::default()) else {
            continue;
        };
        group.bench_with_input(
            BenchmarkId::new("seek_threshold", &name),
            &s.saliency,
            |b, v| b.iter(|| seek_threshold(v, &KneeSearch::default())),
        );
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
