//! Reading and writing meshes: one front door over one file per format.
//!
//! PLACEHOLDER: the I/O module is being written; only the API shape is fixed here.

use std::path::Path;

use crate::error::{Error, Result};
use crate::mesh::TriMesh;

/// A mesh file format.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// Wavefront OBJ.
    Obj,
    /// Stanford PLY (ascii or binary).
    Ply,
    /// Object File Format.
    Off,
    /// STL (ascii or binary).
    Stl,
}

/// Reads a mesh, choosing the format by extension unless `format` is given.
///
/// # Errors
/// I/O and parse errors naming the file and position.
pub fn read_mesh(path: &Path, format: Option<Format>) -> Result<TriMesh> {
    let _ = format;
    Err(Error::InvalidInput(format!(
        "{}: reading is not available yet",
        path.display()
    )))
}
