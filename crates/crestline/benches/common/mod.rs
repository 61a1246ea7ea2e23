//! Meshes shared by the benches: a generated torus of 100,000 vertices (valence 6) and the
//! real meshes named, read from `../shared/data/meshes` (skipped with a note when they cannot
//! be read).

// Each bench uses a subset of these helpers.
#![allow(dead_code)]

use std::path::PathBuf;

use crestline::TriMesh;
use crestline::shapes::{self, GridPattern};

/// `torus-100k`: the generated torus of 100,000 vertices (valence 6), with its name.
pub fn torus_100k() -> (String, TriMesh) {
    (
        "torus-100k".to_string(),
        shapes::torus_with(3.0, 1.0, 400, 250, GridPattern::Uniform),
    )
}

/// The shared meshes `names` that could be read, with their names (the others are skipped
/// with a note).
pub fn shared_meshes(names: &[&str]) -> Vec<(String, TriMesh)> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data/meshes");
    let mut out = Vec::new();
    for &name in names {
        match crestline::io::read_mesh(&dir.join(name), None) {
            Ok(m) => out.push((name.to_string(), m)),
            Err(e) => eprintln!("skipping {name}: {e}"),
        }
    }
    out
}

/// `torus-100k` followed by the shared meshes `names` that could be read.
pub fn torus_and_shared_meshes(names: &[&str]) -> Vec<(String, TriMesh)> {
    let mut out = vec![torus_100k()];
    out.extend(shared_meshes(names));
    out
}
