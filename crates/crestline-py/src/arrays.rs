//! numpy arrays in and out.
//!
//! Inputs are read where they lie: a float64 or float32 array of vertices, or an int64,
//! int32, uint32 or uint64 array of faces, C-ordered or not (a slice, a transpose, a
//! `trimesh.Trimesh`'s tracked arrays), is copied once, straight into the mesh's own storage.
//! Anything else array-like (lists, other dtypes) goes through `numpy.asarray` first.
//! Outputs are numpy arrays that take over the library's buffers where the layout allows.

use crestline::Vec3;
use numpy::ndarray::ArrayView2;
use numpy::{
    Element, PyArray1, PyArray2, PyArrayDescrMethods, PyArrayMethods, PyUntypedArray,
    PyUntypedArrayMethods,
};
use pyo3::prelude::*;

use crate::error::invalid;

/// The positions of an `(n, 3)` array-like of coordinates named `what` in messages.
///
/// # Errors
/// `ValueError` for another shape or values that are not numbers. Finiteness is checked by
/// the mesh.
pub fn positions(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<Vec<Vec3>> {
    if let Ok(array) = obj.cast::<PyArray2<f64>>() {
        return rows(array, what, |x| x);
    }
    if let Ok(array) = obj.cast::<PyArray2<f32>>() {
        return rows(array, what, f64::from);
    }
    let array = as_numpy(obj, Some("float64"), what)?;
    if is_empty_list(&array) {
        return Ok(Vec::new());
    }
    check_rows_of_three(&array, what)?;
    rows(array.cast::<PyArray2<f64>>()?, what, |x| x)
}

/// The triangles of an `(m, 3)` array-like of vertex indices named `what` in messages.
/// Indices must be integers in `[0, 2^32)`; the mesh checks that they name vertices.
///
/// # Errors
/// `ValueError` for another shape, a dtype that is not integer, or an index out of range.
pub fn triangles(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<Vec<[u32; 3]>> {
    if let Ok(array) = obj.cast::<PyArray2<i64>>() {
        return index_rows(array, what);
    }
    if let Ok(array) = obj.cast::<PyArray2<i32>>() {
        return index_rows(array, what);
    }
    if let Ok(array) = obj.cast::<PyArray2<u32>>() {
        return index_rows(array, what);
    }
    if let Ok(array) = obj.cast::<PyArray2<u64>>() {
        return index_rows(array, what);
    }
    let array = as_numpy(obj, None, what)?;
    if is_empty_list(&array) {
        return Ok(Vec::new());
    }
    let kind = array.dtype().kind();
    if !(kind == b'i' || kind == b'u') {
        return Err(invalid(format!(
            "{what} must hold integer vertex indices, got dtype {}",
            array.dtype()
        )));
    }
    check_rows_of_three(&array, what)?;
    let array = array.call_method1("astype", ("int64",))?;
    index_rows(array.cast::<PyArray2<i64>>()?, what)
}

/// One value per vertex (`n` of them) from a 1-d array-like named `what` in messages.
///
/// # Errors
/// `ValueError` for another shape or length.
pub fn per_vertex(obj: &Bound<'_, PyAny>, n: usize, what: &str) -> PyResult<Vec<f64>> {
    let array = as_numpy(obj, Some("float64"), what)?;
    if array.shape() != [n] {
        return Err(invalid(format!(
            "{what} must have shape ({n},), one value per vertex, got {}",
            shape_text(array.shape())
        )));
    }
    let array = array.cast::<PyArray1<f64>>()?;
    let view = array
        .try_readonly()
        .map_err(|e| invalid(format!("{what}: {e}")))?;
    Ok(view.as_array().to_vec())
}

/// A mesh as numpy arrays: vertices `(n, 3)` float64 and faces `(m, 3)` int64.
pub type MeshArrays<'py> = (Bound<'py, PyArray2<f64>>, Bound<'py, PyArray2<i64>>);

/// An `(n, 3)` float64 array that takes over `points`' buffer.
pub fn points_array<'py>(
    py: Python<'py>,
    points: Vec<[f64; 3]>,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let n = points.len();
    PyArray1::from_vec(py, points.into_flattened()).reshape([n, 3])
}

/// An `(n, 3)` float64 array of vectors.
pub fn vectors_array<'py>(
    py: Python<'py>,
    vectors: &[Vec3],
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    points_array(py, vectors.iter().map(|v| [v.x, v.y, v.z]).collect())
}

/// An `(m, 3)` int64 array of triangles.
pub fn triangles_array<'py>(
    py: Python<'py>,
    triangles: &[[u32; 3]],
) -> PyResult<Bound<'py, PyArray2<i64>>> {
    let flat: Vec<i64> = triangles
        .as_flattened()
        .iter()
        .map(|&i| i64::from(i))
        .collect();
    PyArray1::from_vec(py, flat).reshape([triangles.len(), 3])
}

/// `numpy.asarray(obj, dtype)`, with a `ValueError` naming `what` when numpy refuses.
fn as_numpy<'py>(
    obj: &Bound<'py, PyAny>,
    dtype: Option<&str>,
    what: &str,
) -> PyResult<Bound<'py, PyUntypedArray>> {
    let numpy = obj.py().import("numpy")?;
    let array = numpy
        .call_method1("asarray", (obj, dtype))
        .map_err(|e| invalid(format!("{what} is not an array of numbers: {e}")))?;
    Ok(array.cast_into::<PyUntypedArray>()?)
}

/// An empty list or tuple becomes an array of shape (0,) (and dtype float64): no rows.
fn is_empty_list(array: &Bound<'_, PyUntypedArray>) -> bool {
    array.shape() == [0]
}

fn check_rows_of_three(array: &Bound<'_, PyUntypedArray>, what: &str) -> PyResult<()> {
    match array.shape() {
        [_, 3] => Ok(()),
        shape => Err(invalid(format!(
            "{what} must have shape (n, 3), got {}",
            shape_text(shape)
        ))),
    }
}

fn shape_text(shape: &[usize]) -> String {
    match shape {
        [n] => format!("({n},)"),
        _ => format!(
            "({})",
            shape
                .iter()
                .map(usize::to_string)
                .collect::<Vec<_>>()
                .join(", ")
        ),
    }
}

/// Reads a 2-d array of any layout row by row.
fn read_rows<T: Element + Copy, R>(
    array: &Bound<'_, PyArray2<T>>,
    what: &str,
    row: impl Fn(ArrayView2<'_, T>, usize) -> PyResult<R>,
) -> PyResult<Vec<R>> {
    let shape = array.shape();
    if shape.get(1) != Some(&3) {
        return Err(invalid(format!(
            "{what} must have shape (n, 3), got {}",
            shape_text(shape)
        )));
    }
    let view = array
        .try_readonly()
        .map_err(|e| invalid(format!("{what}: {e}")))?;
    let view = view.as_array();
    (0..view.nrows()).map(|i| row(view, i)).collect()
}

fn rows<T: Element + Copy>(
    array: &Bound<'_, PyArray2<T>>,
    what: &str,
    to_f64: impl Fn(T) -> f64,
) -> PyResult<Vec<Vec3>> {
    read_rows(array, what, |view, i| {
        Ok(Vec3::new(
            to_f64(view[[i, 0]]),
            to_f64(view[[i, 1]]),
            to_f64(view[[i, 2]]),
        ))
    })
}

fn index_rows<T>(array: &Bound<'_, PyArray2<T>>, what: &str) -> PyResult<Vec<[u32; 3]>>
where
    T: Element + Copy + std::fmt::Display + TryInto<u32>,
{
    read_rows(array, what, |view, i| {
        let index = |j: usize| {
            let value = view[[i, j]];
            value.try_into().map_err(|_| {
                invalid(format!(
                    "{what}: row {i} has index {value}, outside [0, 2^32)"
                ))
            })
        };
        Ok([index(0)?, index(1)?, index(2)?])
    })
}
