//! `crestline.curvature`: the command-line tool's `curvature`, on arrays.

use crestline::curvature::{CurvatureOptions, Estimator, estimate};
use numpy::PyArray1;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::arrays::{count, vectors_array};
use crate::error::{choose, to_py_err};
use crate::extract::ESTIMATORS;
use crate::mesh::{mesh_from_arrays, per_given_vertex};

/// Principal curvatures, directions and extremalities of every vertex of the mesh
/// `(vertices, faces)` (array-likes as for `extract`).
///
/// Options, with the defaults of `crestline curvature`: `estimator` "jet-fit" (default;
/// "cubic-fit" when `rings` is given), "shape-operator" or "cubic-fit"; `rings`, the k-ring of
/// the cubic fit (1 to 8, default 1);
/// `radius`, the jet fit's disc radius in sample spacings (default 2.5); `degree`, the jet
/// fit's polynomial degree (3 or 4, default 4; 4 lets the fit choose on noisy meshes);
/// `no_noise_adaptation`, keep the jet fit's radius fixed on noisy meshes;
/// `keep_orientation` and `no_weld`, as for `extract`. An option of another estimator than
/// the one that runs is a `ValueError`, as on the command line.
///
/// Returns a dict of numpy arrays indexed like the vertices: "k_max", "k_min", "e_max",
/// "e_min" (n,) and "dir_max", "dir_min", "normals" (n, 3). Signs: a sphere of radius r
/// has k = 1/r with outward normals; `k_max >= k_min`. Raises `TypeError` and `ValueError`
/// as `extract` does (a negative `rings` or `degree` is a `ValueError`).
#[pyfunction]
#[pyo3(signature = (
    vertices, faces, estimator = None, *, rings = None, radius = None, degree = None,
    no_noise_adaptation = false, keep_orientation = false, no_weld = false,
))]
pub fn curvature<'py>(
    py: Python<'py>,
    vertices: &Bound<'py, PyAny>,
    faces: &Bound<'py, PyAny>,
    estimator: Option<&str>,
    rings: Option<&Bound<'py, PyAny>>,
    radius: Option<f64>,
    degree: Option<&Bound<'py, PyAny>>,
    no_noise_adaptation: bool,
    keep_orientation: bool,
    no_weld: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let rings = rings.map(|k| count(k, "rings")).transpose()?;
    let degree = degree.map(|d| count(d, "degree")).transpose()?;
    let (mesh, weld) = mesh_from_arrays(vertices, faces, keep_orientation, no_weld)?;
    let estimator = match (estimator, rings) {
        (Some(name), _) => choose("estimator", name, &ESTIMATORS)?,
        (None, Some(_)) => Estimator::CubicFit,
        (None, None) => Estimator::JetFit,
    };
    let mut unused = Vec::new();
    if estimator != Estimator::CubicFit && rings.is_some() {
        unused.push("rings");
    }
    if estimator != Estimator::JetFit {
        for (given, name) in [
            (radius.is_some(), "radius"),
            (degree.is_some(), "degree"),
            (no_noise_adaptation, "no_noise_adaptation"),
        ] {
            if given {
                unused.push(name);
            }
        }
    }
    if !unused.is_empty() {
        let name = ESTIMATORS
            .iter()
            .find(|(_, e)| *e == estimator)
            .map_or("?", |(name, _)| *name);
        return Err(PyValueError::new_err(format!(
            "options that estimator '{name}' would not use: {}",
            unused.join(", ")
        )));
    }
    let mut options = CurvatureOptions::default().with_estimator(estimator);
    options.cubic_fit.rings = rings.unwrap_or(options.cubic_fit.rings);
    let jet_fit = &mut options.jet_fit;
    jet_fit.radius = radius.unwrap_or(jet_fit.radius);
    jet_fit.degree = degree.unwrap_or(jet_fit.degree);
    jet_fit.adapt_to_noise = !no_noise_adaptation;
    let c = py.detach(|| estimate(&mesh, &options)).map_err(to_py_err)?;
    let fields = PyDict::new(py);
    for (name, values) in [
        ("k_max", c.k_max),
        ("k_min", c.k_min),
        ("e_max", c.e_max),
        ("e_min", c.e_min),
    ] {
        let values = per_given_vertex(&weld, &values)?;
        fields.set_item(name, PyArray1::from_vec(py, values))?;
    }
    for (name, vectors) in [
        ("dir_max", &c.dir_max),
        ("dir_min", &c.dir_min),
        ("normals", &c.normals),
    ] {
        fields.set_item(name, vectors_array(py, &per_given_vertex(&weld, vectors)?)?)?;
    }
    Ok(fields)
}
