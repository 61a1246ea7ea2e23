//! Parsing speed of the mesh readers, from memory (the file is read once, outside the
//! timing), in bytes of file per second.
//!
//! `parse` is the reader alone (positions and triangles); `read` adds building the
//! [`crestline::TriMesh`] and its connectivity, for scale.
//!
//! Run: `cargo bench -p crestline --bench io`. Needs the meshes in `shared/data/meshes`.

// Test code: stopping loudly on the first surprise is the point.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::hint::black_box;
use std::path::{Path, PathBuf};
use std::time::Duration;

use crestline::io::{Format, parse_mesh_bytes, read_mesh_bytes};
use criterion::{Criterion, Throughput, criterion_group, criterion_main};

fn meshes_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data/meshes")
}

const FILES: [(&str, Format); 3] = [
    ("horse.ply", Format::Ply),
    ("igea.ply", Format::Ply),
    ("stanford-bunny.obj", Format::Obj),
];

fn load(name: &str) -> Vec<u8> {
    let path = meshes_dir().join(name);
    match std::fs::read(&path) {
        Ok(bytes) => bytes,
        Err(e) => panic!(
            "cannot read {} ({e}): the benches need shared/data/meshes",
            path.display()
        ),
    }
}

/// One benchmark per shared file in `group`, running `f` on the file's bytes.
fn bench_files<T>(
    c: &mut Criterion,
    group: &str,
    samples: usize,
    f: impl Fn(&[u8], Format, &Path) -> T,
) {
    let mut group = c.benchmark_group(group);
    group
        .sample_size(samples)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2));
    for (name, format) in FILES {
        let bytes = load(name);
        group.throughput(Throughput::Bytes(bytes.len() as u64));
        group.bench_function(name, |b| {
            b.iter(|| f(black_box(&bytes), format, Path::new(name)))
        });
    }
    group.finish();
}

fn parse(c: &mut Criterion) {
    bench_files(c, "parse", 20, parse_mesh_bytes);
}

fn read(c: &mut Criterion) {
    bench_files(c, "read", 10, read_mesh_bytes);
}

criterion_group!(benches, parse, read);
criterion_main!(benches);
