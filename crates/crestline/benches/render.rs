//! Rendering speed: a subdivided icosphere of 1.3 million faces at 1024x1024, with and
//! without a colour map and lines.
//!
//! Run: `cargo bench -p crestline --features render --bench render`

use std::hint::black_box;

use crestline::lines::{FeatureLine, FeatureLines, LineKind};
use crestline::render::{RenderOptions, render_image};
use crestline::{Vec3, shapes};
use criterion::{Criterion, criterion_group, criterion_main};

/// 64 circles of latitude on the unit sphere, ridges and valleys alternating, 512 points each.
fn latitude_lines() -> FeatureLines {
    let lines = (1..=64)
        .map(|i| {
            let z = -1.0 + 2.0 * f64::from(i) / 65.0;
            let r = (1.0 - z * z).sqrt();
            let kind = if i % 2 == 0 {
                LineKind::Ridge
            } else {
                LineKind::Valley
            };
            let points = (0..512)
                .map(|k| {
                    let a = std::f64::consts::TAU * f64::from(k) / 512.0;
                    Vec3::new(r * a.cos(), r * a.sin(), z)
                })
                .collect();
            FeatureLine::new(kind, points, true)
        })
        .collect();
    FeatureLines { lines }
}

fn bench_render(c: &mut Criterion) {
    let mesh = shapes::icosphere(1.0, 8);
    let lines = latitude_lines();
    let field: Vec<f64> = mesh.positions().iter().map(|p| p.x * p.y).collect();
    let opts = RenderOptions::default();
    let name = format!("icosphere {} faces 1024x1024", mesh.num_faces());
    let mut group = c.benchmark_group("render");
    group.sample_size(10);
    group.bench_function(format!("{name}: shaded"), |b| {
        b.iter(|| black_box(render_image(&mesh, None, None, &opts)))
    });
    group.bench_function(format!("{name}: shaded + field + legend"), |b| {
        b.iter(|| black_box(render_image(&mesh, None, Some(&field), &opts)))
    });
    group.bench_function(format!("{name}: shaded + 64 lines"), |b| {
        b.iter(|| black_box(render_image(&mesh, Some(&lines), None, &opts)))
    });
    group.finish();
}

criterion_group!(benches, bench_render);
criterion_main!(benches);
