//! Helpers shared by the CLI test modules: running the `crestline` binary Cargo built for the
//! tests, and (from the library's tests, `files`) the shared mesh folder and a folder's
//! listing.

// Each test module uses a subset of these helpers.
#![allow(dead_code, clippy::expect_used)]

use std::ffi::OsStr;
use std::path::Path;
use std::process::{Command, Output};

#[path = "../../../crestline/tests/suite/files.rs"]
mod files;
pub use files::{listing, shared_meshes_dir};

/// Runs `crestline` with `args` and returns what it did (whatever its exit code).
pub fn crestline(args: &[&str]) -> Output {
    run(args)
}

/// Runs `crestline` with `args`, checks that it succeeded and returns what it did.
#[track_caller]
pub fn crestline_ok<I: IntoIterator<Item = S>, S: AsRef<OsStr>>(args: I) -> Output {
    let out = run(args);
    assert!(out.status.success(), "{}", stderr(&out));
    out
}

fn run<I: IntoIterator<Item = S>, S: AsRef<OsStr>>(args: I) -> Output {
    Command::new(env!("CARGO_BIN_EXE_crestline"))
        .args(args)
        .output()
        .expect("the crestline binary runs")
}

/// A run's standard error as text.
pub fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// Checks that the run succeeded without a panic and returns it.
pub fn ok(out: Output) -> Output {
    assert!(out.status.success(), "failed: {}", stderr(&out));
    assert!(!stderr(&out).contains("panicked"));
    out
}

/// Checks that the run failed cleanly and returns its stderr.
pub fn fails(out: Output) -> String {
    let err = stderr(&out);
    assert!(!out.status.success(), "should fail; stderr: {err}");
    assert!(!err.contains("panicked"), "panicked: {err}");
    err
}

/// A path as an argument.
pub fn s(p: &Path) -> &str {
    p.to_str().expect("a UTF-8 path")
}

/// Writes to `path` (OBJ) a unit icosphere of `levels` subdivisions with the vertices
/// `spikes` moved three mean edges out along their normals; returns its positions.
pub fn write_spiky_sphere(path: &Path, levels: u32, spikes: &[usize]) -> Vec<crestline::Vec3> {
    let sphere = crestline::shapes::icosphere(1.0, levels);
    let normals = crestline::mesh::vertex_normals_area(&sphere);
    let edge = crestline::mesh::mean_edge_length(&sphere);
    let mut positions = sphere.positions().to_vec();
    for &v in spikes {
        positions[v] += normals[v] * 3.0 * edge;
    }
    let spiky = sphere
        .with_positions(positions.clone())
        .expect("finite positions");
    let options = crestline::io::WriteOptions::default();
    crestline::io::write_mesh(path, &spiky, crestline::io::Format::Obj, &options)
        .expect("the spiky sphere written");
    positions
}
