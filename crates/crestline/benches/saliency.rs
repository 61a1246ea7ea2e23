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

use std::path::PathBuf;

use crestline::TriMesh;
use crestline::curvature::{CurvatureOptions, Estimator, estimate};
use crestline::saliency::{SaliencyOptions, mesh_saliency};
use crestline::shapes::{self, GridPattern};
use crestline::threshold::{KneeSearch, seek_threshold};
use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};

fn meshes() -> Vec<(String, TriMesh)> {
    let mut out = Vec::new();
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data/meshes");
    for name in ["igea.ply", "fandisk.obj"] {
        match crestline::io::read_mesh(&dir.join(name), None) {
            Ok(m) => out.push((name.to_string(), m)),
            Err(e) => eprintln!("skipping {name}: {e}"),
        }
    }
    out.push((
        "torus-100k".to_string(),
        shapes::torus_with(3.0, 1.0, 400, 250, GridPattern::Uniform),
    ));
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
