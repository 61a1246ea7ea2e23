//! Crest-line-guided simplification of ~270K-triangle meshes to 10 %.
//!
//! - `pillow_box_270k`: the generated pillow box (`shapes::pillow_box(1, 0.25, 150)`,
//!   270,000 triangles) with its 12 exact crease lines; the feature distance alone, the whole
//!   of `simplify` with eta = 1, and plain QEM (eta = 0).
//! - `igea`: `../shared/data/meshes/igea.ply` (268,686 triangles) with the lines the default
//!   extraction finds (extracted once, outside the timing): `simplify` with eta = 1, and plain
//!   QEM. Skipped (with a note) when the file cannot be read.
//!
//! Run: `cargo bench -p crestline --bench simplify`. Figures go to `BENCHMARKS.md`.

mod common;

use std::hint::black_box;

use crestline::distance::{DistanceOptions, feature_distance};
use crestline::extract::{ExtractOptions, extract};
use crestline::lines::FeatureLines;
use crestline::shapes;
use crestline::simplify::{SimplifyOptions, Target, simplify};
use criterion::{Criterion, criterion_group, criterion_main};

fn pillow_box(c: &mut Criterion) {
    let (mesh, lines) = shapes::pillow_box(1.0, 0.25, 150);
    let to_tenth = SimplifyOptions::default().with_target(Target::Ratio(0.1));
    let mut group = c.benchmark_group("pillow_box_270k");
    group.sample_size(10);
    group.bench_function("feature_distance", |b| {
        b.iter(|| feature_distance(black_box(&mesh), &lines, &DistanceOptions::default()))
    });
    group.bench_function("simplify_eta1_to_10pct", |b| {
        b.iter(|| simplify(black_box(&mesh), &lines, &to_tenth))
    });
    group.bench_function("simplify_eta0_to_10pct", |b| {
        b.iter(|| simplify(black_box(&mesh), &lines, &to_tenth.with_eta(0.0)))
    });
    group.finish();
}

fn igea(c: &mut Criterion) {
    let Some((_, mesh)) = common::shared_meshes(&["igea.ply"]).pop() else {
        return;
    };
    let lines = match extract(&mesh, &ExtractOptions::default()) {
        Ok(e) => e.lines,
        Err(e) => {
            eprintln!("igea skipped: extraction failed: {e}");
            return;
        }
    };
    eprintln!("igea: {} lines extracted", lines.lines.len());
    let to_tenth = SimplifyOptions::default().with_target(Target::Ratio(0.1));
    let mut group = c.benchmark_group("igea");
    group.sample_size(10);
    group.bench_function("simplify_eta1_to_10pct", |b| {
        b.iter(|| simplify(black_box(&mesh), &lines, &to_tenth))
    });
    group.bench_function("simplify_eta0_to_10pct", |b| {
        b.iter(|| {
            simplify(
                black_box(&mesh),
                &FeatureLines::default(),
                &to_tenth.with_eta(0.0),
            )
        })
    });
    group.finish();
}

criterion_group!(benches, pillow_box, igea);
criterion_main!(benches);
