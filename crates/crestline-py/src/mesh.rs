//! Meshes: read from a file as arrays, and built from arrays for the other functions.

use std::path::PathBuf;

use crestline::TriMesh;
use crestline::io::Format;
use crestline::mesh::Weld;
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;

use crate::arrays::{MeshArrays, points_array, positions, triangles, triangles_array};
use crate::error::{choose, to_py_err};

/// Reads a mesh file (OBJ, PLY, OFF or STL; the format follows the extension unless
/// `format` names it: "obj", "ply", "off" or "stl").
///
/// Returns `(vertices, faces)`: vertices as an (n, 3) float64 array and faces as an (m, 3)
/// int64 array, in file order (polygons are split into fans of triangles). Nothing is
/// dropped: degenerate triangles and unreferenced vertices are kept here, and skipped by the
/// functions that take the arrays, as the command-line tool does.
///
/// Raises `ValueError` for a malformed file (the message names the file and the line or byte
/// where it goes wrong), `OSError` when it cannot be read.
#[pyfunction]
#[pyo3(signature = (path, format = None))]
pub fn read_mesh<'py>(
    py: Python<'py>,
    path: PathBuf,
    format: Option<&str>,
) -> PyResult<MeshArrays<'py>> {
    let formats = Format::ALL.map(|f| (f.extension(), f));
    let format = format
        .map(|name| choose("format", name, &formats))
        .transpose()?;
    let data = py
        .detach(|| crestline::io::read_mesh_data(&path, format))
        .map_err(to_py_err)?;
    let faces = triangles_array(py, &data.faces)?;
    Ok((points_array(py, data.positions)?, faces))
}

/// The mesh of `vertices` and `faces` (array-likes), its vertices at one position welded
/// unless `no_weld` ([`crestline::mesh::weld_coincident`], as the command-line tool does) and
/// its triangles wound consistently and its closed surfaces turned outward unless
/// `keep_orientation` ([`crestline::mesh::orient_outward`]); with the weld, which
/// carries values per vertex between the arrays and the mesh. The arrays are read with the
/// GIL held; the mesh is built without it.
///
/// # Errors
/// `ValueError` for arrays of the wrong shape or type, non-finite coordinates and indices
/// out of range.
pub fn mesh_from_arrays(
    vertices: &Bound<'_, PyAny>,
    faces: &Bound<'_, PyAny>,
    keep_orientation: bool,
    no_weld: bool,
) -> PyResult<(TriMesh, Weld)> {
    let points = positions(vertices, "vertices")?;
    let triangles = triangles(faces, "faces")?;
    vertices
        .py()
        .detach(|| {
            let mesh = TriMesh::new(points, triangles)?;
            let (mesh, weld) = if no_weld {
                let weld = Weld::identity(mesh.num_vertices());
                (mesh, weld)
            } else {
                crestline::mesh::weld_coincident(mesh)?
            };
            if keep_orientation {
                Ok((mesh, weld))
            } else {
                crestline::mesh::orient_outward(mesh).map(|(mesh, _)| (mesh, weld))
            }
        })
        .map_err(to_py_err)
}

/// Values per vertex of the mesh built by [`mesh_from_arrays`], one per vertex of the arrays.
///
/// # Errors
/// `RuntimeError` unless there is one value per vertex of the mesh (a bug, not an input).
pub fn per_given_vertex<T: Copy>(weld: &Weld, values: &[T]) -> PyResult<Vec<T>> {
    weld.to_given(values).ok_or_else(|| {
        PyRuntimeError::new_err("internal error: not one value per vertex of the welded mesh")
    })
}
