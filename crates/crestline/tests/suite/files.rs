//! File helpers shared by the library's integration tests and the command line's (which
//! include this file through `#[path]`): the shared data folders, and a folder's listing.

// Test helpers: failing loudly is the point.
#![allow(clippy::unwrap_used)]

use std::path::{Path, PathBuf};

/// A folder of the shared test data (`shared/<path>` beside the repository); panics when it
/// is missing.
pub fn shared_dir(path: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared")
        .join(path);
    assert!(
        dir.is_dir(),
        "the shared test data are missing: expected {} (see shared/data/README.md)",
        dir.display()
    );
    dir
}

/// The shared mesh folder (`shared/data/meshes` beside the repository).
pub fn shared_meshes_dir() -> PathBuf {
    shared_dir("data/meshes")
}

/// Files in `dir`, sorted.
pub fn listing(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}
