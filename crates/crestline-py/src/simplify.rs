//! `crestline.simplify` and `crestline.feature_distance`: the command-line tool's
//! `simplify` and `distance`, on arrays.

use crestline::TriMesh;
use crestline::distance::{DistanceOptions, feature_distance as run_feature_distance};
use crestline::extract::ExtractOptions;
use crestline::lines::FeatureLines;
use crestline::simplify::{SimplifyOptions, Target, simplify as run_simplify};
use numpy::PyArray1;
use pyo3::prelude::*;

use crate::arrays::{MeshArrays, count, triangles_array, vectors_array};
use crate::error::{invalid, to_py_err};
use crate::extract::extract_interruptibly;
use crate::lines::Lines;
use crate::mesh::{mesh_from_arrays, per_given_vertex};

/// Simplifies the mesh `(vertices, faces)` by quadric-error edge collapse, keeping it dense
/// near the feature lines (YBS 2005, eq. 7).
///
/// `lines`: the `Lines` that guide it; without them they are extracted with the default
/// method (as `crestline simplify` does), unless `eta` is 0. `ratio`: keep this fraction of
/// the triangles, in (0, 1] (default 0.1); `target_faces`: keep this many instead (the
/// command line's `--faces`). `eta`: influence of the lines, 0 for plain QEM (default 1);
/// `eps`: the regularisation epsilon of eq. 7 (default 0.1). `keep_orientation` and `no_weld`
/// as for `extract` (by default vertices at one position are made one first).
///
/// Returns `(vertices, faces)` of the simplified mesh as float64 and int64 arrays. Ctrl-C
/// interrupts the extraction of the lines (at its next stage), not the simplification.
#[pyfunction]
#[pyo3(signature = (
    vertices, faces, lines = None, *, ratio = None, target_faces = None, eta = None,
    eps = None, keep_orientation = false, no_weld = false,
))]
pub fn simplify<'py>(
    py: Python<'py>,
    vertices: &Bound<'py, PyAny>,
    faces: &Bound<'py, PyAny>,
    lines: Option<Bound<'py, Lines>>,
    ratio: Option<f64>,
    target_faces: Option<&Bound<'py, PyAny>>,
    eta: Option<f64>,
    eps: Option<f64>,
    keep_orientation: bool,
    no_weld: bool,
) -> PyResult<MeshArrays<'py>> {
    let target_faces = target_faces.map(|n| count(n, "target_faces")).transpose()?;
    let mut options = SimplifyOptions::default();
    options.target = match (ratio, target_faces) {
        (Some(_), Some(_)) => return Err(invalid("give ratio or target_faces, not both")),
        (Some(r), None) => Target::Ratio(r),
        (None, Some(n)) => Target::Faces(n),
        (None, None) => options.target,
    };
    options.eta = eta.unwrap_or(options.eta);
    options.eps = eps.unwrap_or(options.eps);
    // Before the lines are extracted.
    options.check_weights().map_err(to_py_err)?;
    let (mesh, _) = mesh_from_arrays(vertices, faces, keep_orientation, no_weld)?;
    let extracted;
    let lines = match lines.as_ref() {
        Some(lines) => lines.get().feature_lines(),
        None if options.eta == 0.0 => &FeatureLines::default(),
        None => {
            extracted = guiding_lines(py, &mesh)?;
            &extracted
        }
    };
    let simplified = py
        .detach(|| run_simplify(&mesh, lines, &options))
        .map_err(to_py_err)?;
    let mesh = simplified.mesh;
    Ok((
        vectors_array(py, mesh.positions())?,
        triangles_array(py, mesh.faces())?,
    ))
}

/// The geodesic distance from every vertex of `(vertices, faces)` to the nearest of `lines`
/// (extracted with the default method when not given, as `crestline distance` does).
///
/// `edges_only`: propagate along edges only (plain Dijkstra, which overestimates) instead
/// of also across triangles. `keep_orientation` and `no_weld` as for `extract` (vertices at
/// one position are one by default; each copy gets its distance). Returns an (n,) float64
/// array, one value per vertex given; vertices no line reaches (other components,
/// unreferenced vertices) get `inf`. Ctrl-C interrupts the extraction of the lines (at its
/// next stage), not the propagation.
#[pyfunction]
#[pyo3(signature = (
    vertices, faces, lines = None, *, edges_only = false, keep_orientation = false, no_weld = false,
))]
pub fn feature_distance<'py>(
    py: Python<'py>,
    vertices: &Bound<'py, PyAny>,
    faces: &Bound<'py, PyAny>,
    lines: Option<Bound<'py, Lines>>,
    edges_only: bool,
    keep_orientation: bool,
    no_weld: bool,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let (mesh, weld) = mesh_from_arrays(vertices, faces, keep_orientation, no_weld)?;
    let options = DistanceOptions::default().with_relax_across_triangles(!edges_only);
    let extracted;
    let lines = match lines.as_ref() {
        Some(lines) => lines.get().feature_lines(),
        None => {
            extracted = guiding_lines(py, &mesh)?;
            &extracted
        }
    };
    let distance = py
        .detach(|| run_feature_distance(&mesh, lines, &options))
        .map_err(to_py_err)?;
    Ok(PyArray1::from_vec(
        py,
        per_given_vertex(&weld, &distance.vertex)?,
    ))
}

/// The lines `simplify` and `feature_distance` use when none are given.
fn guiding_lines(py: Python<'_>, mesh: &TriMesh) -> PyResult<FeatureLines> {
    // `mesh_from_arrays` has oriented the mesh already, unless `keep_orientation`.
    let options = ExtractOptions {
        orient_outward: false,
        ..ExtractOptions::default()
    };
    Ok(extract_interruptibly(py, mesh, &options)?.lines)
}
