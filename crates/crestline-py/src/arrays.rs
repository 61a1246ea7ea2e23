//! numpy arrays in and out, and the other arguments made of numbers: counts, short sequences.
//!
//! Inputs are read where they lie: a float64 or float32 array of vertices, or an int64,
//! int32, uint32 or uint64 array of faces, C-ordered or not (a slice, a transpose, a
//! `trimesh.Trimesh`'s tracked arrays), is copied once, straight into the mesh's own storage.
//! Anything else array-like (lists, other dtypes) goes through `numpy.asarray` first.
//! Outputs are numpy arrays that take over the library's buffers where the layout allows.
//!
//! Wrong types raise `TypeError`, wrong values `ValueError` (see [`crate::error`]): no array
//! at all (a string, `None`, a number where rows are needed) or values of the wrong kind
//! (floats, booleans, strings or dates where vertex indices are needed; strings or complex
//! numbers where coordinates are) is a `TypeError`; a wrong shape, a ragged list, a
//! non-finite coordinate or an index out of range is a `ValueError`. An empty array is no
//! rows, whatever its dtype (numpy makes `[]` float64). Counts ([`count`]) and short
//! sequences of numbers ([`numbers`], [`counts`], [`rows_of_numbers`]) follow the same rule.

use crestline::Vec3;
use numpy::ndarray::ArrayView2;
use numpy::{
    Element, PyArray1, PyArray2, PyArrayDescrMethods, PyArrayMethods, PyUntypedArray,
    PyUntypedArrayMethods,
};
use pyo3::exceptions::{PyOverflowError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyString};

use crate::error::{invalid, type_name, wrong_type};

/// The positions of an `(n, 3)` array-like of coordinates named `what` in messages.
///
/// # Errors
/// `TypeError` for no array or values that are not real numbers, `ValueError` for another
/// shape. Finiteness is checked by the mesh.
pub fn positions(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<Vec<Vec3>> {
    if let Ok(array) = obj.cast::<PyArray2<f64>>() {
        return rows(array, what, |x| x);
    }
    if let Ok(array) = obj.cast::<PyArray2<f32>>() {
        return rows(array, what, f64::from);
    }
    let array = as_numpy(obj, Values::Real, what)?;
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
/// `TypeError` for no array or a dtype that is not integer, `ValueError` for another shape
/// or an index out of range.
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
    let array = as_numpy(obj, Values::Index, what)?;
    if is_empty_list(&array) {
        return Ok(Vec::new());
    }
    check_rows_of_three(&array, what)?;
    index_rows(array.cast::<PyArray2<i64>>()?, what)
}

/// One value per vertex (`n` of them) from a 1-d array-like named `what` in messages.
///
/// # Errors
/// `TypeError` for no array or values that are not real numbers, `ValueError` for another
/// shape or length.
pub fn per_vertex(obj: &Bound<'_, PyAny>, n: usize, what: &str) -> PyResult<Vec<f64>> {
    let array = as_numpy(obj, Values::Real, what)?;
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

/// What the values of an array must be.
#[derive(Clone, Copy)]
enum Values {
    /// Coordinates and values per vertex: real numbers (integers and booleans too), read as
    /// float64.
    Real,
    /// Vertex indices: integers of any width and sign, read as int64 (a uint64 beyond turns
    /// negative and is refused with the other indices out of range).
    Index,
}

impl Values {
    /// The dtype the values are read as.
    fn dtype(self) -> &'static str {
        match self {
            Values::Real => "float64",
            Values::Index => "int64",
        }
    }

    /// Whether numpy's dtype kind (`f`, `i`, `u`, `b`, `c`, `U`, `O`, ...) holds such values.
    fn accepts(self, kind: u8) -> bool {
        match self {
            Values::Real => matches!(kind, b'f' | b'i' | b'u' | b'b'),
            Values::Index => matches!(kind, b'i' | b'u'),
        }
    }

    /// What the values must be, for messages.
    fn meaning(self) -> &'static str {
        match self {
            Values::Real => "real numbers",
            Values::Index => "integer vertex indices",
        }
    }
}

/// `obj` as a numpy array of the dtype `values` are read as, named `what` in messages.
///
/// An object array (numbers as Python objects) is read by its elements; an empty array is
/// no values whatever its dtype.
///
/// # Errors
/// `TypeError` for no array (a 0-d one: a string, `None`, a number) or values that are not
/// `values`, `ValueError` for a ragged list.
fn as_numpy<'py>(
    obj: &Bound<'py, PyAny>,
    values: Values,
    what: &str,
) -> PyResult<Bound<'py, PyUntypedArray>> {
    let numpy = obj.py().import("numpy")?;
    let mut array = asarray(&numpy, obj, what)?;
    if array.ndim() == 0 {
        return Err(wrong_type(format!(
            "{what} must be an array-like, got {}",
            type_name(obj)
        )));
    }
    if array.dtype().kind() == b'O' {
        array = asarray(&numpy, &array.call_method0("tolist")?, what)?;
    }
    if array.is_empty() {
        let empty = numpy.call_method1("zeros", (array.shape().to_vec(), values.dtype()))?;
        return Ok(empty.cast_into::<PyUntypedArray>()?);
    }
    if !values.accepts(array.dtype().kind()) {
        return Err(wrong_type(format!(
            "{what} must hold {}, got dtype {}",
            values.meaning(),
            array.dtype()
        )));
    }
    let array = numpy.call_method1("asarray", (array, values.dtype()))?;
    Ok(array.cast_into::<PyUntypedArray>()?)
}

/// `numpy.asarray(obj)`; numpy's refusal named after `what`, its type kept (`ValueError`
/// for a ragged list, `TypeError` for an object it cannot make an array of).
fn asarray<'py>(
    numpy: &Bound<'py, PyModule>,
    obj: &Bound<'py, PyAny>,
    what: &str,
) -> PyResult<Bound<'py, PyUntypedArray>> {
    let py = obj.py();
    let array = numpy.call_method1("asarray", (obj,)).map_err(|e| {
        let message = format!("{what} is not an array of numbers: {e}");
        if e.is_instance_of::<PyTypeError>(py) {
            wrong_type(message)
        } else if e.is_instance_of::<PyValueError>(py) {
            invalid(message)
        } else {
            e
        }
    })?;
    Ok(array.cast_into::<PyUntypedArray>()?)
}

/// An empty list or tuple becomes an array of shape (0,): no rows.
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

/// Unsigned integer types a count can be read as.
pub trait Unsigned: TryFrom<i128> + Copy + Default {
    /// The largest value, for messages.
    const LARGEST: u128;
}

impl Unsigned for usize {
    const LARGEST: u128 = usize::MAX as u128;
}

impl Unsigned for u32 {
    const LARGEST: u128 = u32::MAX as u128;
}

/// A count or size named `what` in messages: a non-negative integer (a Python int, a numpy
/// integer, anything with `__index__`) that fits `T`.
///
/// # Errors
/// `TypeError` for anything but an integer (a float too), `ValueError` for a negative
/// integer or one beyond `T`.
pub fn count<T: Unsigned>(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<T> {
    let py = obj.py();
    let too_large = || {
        invalid(format!(
            "{what} must be an integer from 0 to {}, got {obj}",
            T::LARGEST
        ))
    };
    let value: i128 = match obj.extract() {
        Ok(value) => value,
        Err(e) if e.is_instance_of::<PyOverflowError>(py) => return Err(too_large()),
        Err(e) if e.is_instance_of::<PyTypeError>(py) => {
            return Err(wrong_type(format!(
                "{what} must be a non-negative integer, got {}",
                type_name(obj)
            )));
        }
        Err(e) => return Err(e),
    };
    if value < 0 {
        return Err(invalid(format!(
            "{what} must be a non-negative integer, got {value}"
        )));
    }
    T::try_from(value).map_err(|_| too_large())
}

/// `N` numbers from a sequence (tuple, list, numpy array, any iterable but a string) named
/// `what` in messages; `names` says what they are, as `"(azimuth, elevation)"`.
///
/// # Errors
/// `TypeError` for no sequence or an item that is not a number, `ValueError` for another
/// length.
pub fn numbers<const N: usize>(
    obj: &Bound<'_, PyAny>,
    what: &str,
    names: &str,
) -> PyResult<[f64; N]> {
    let py = obj.py();
    let mut values = [0.0; N];
    for (i, (value, item)) in values
        .iter_mut()
        .zip(items(obj, N, what, names)?)
        .enumerate()
    {
        *value = item.extract::<f64>().map_err(|e| {
            if e.is_instance_of::<PyTypeError>(py) {
                wrong_type(format!(
                    "{what}[{i}] must be a number, got {}",
                    type_name(&item)
                ))
            } else {
                invalid(format!("{what}[{i}]: {e}"))
            }
        })?;
    }
    Ok(values)
}

/// `N` counts (see [`count`]) from a sequence as for [`numbers`].
///
/// # Errors
/// As [`numbers`] and [`count`], naming the item (`size[0]`).
pub fn counts<T: Unsigned, const N: usize>(
    obj: &Bound<'_, PyAny>,
    what: &str,
    names: &str,
) -> PyResult<[T; N]> {
    let mut values = [T::default(); N];
    for (i, (value, item)) in values
        .iter_mut()
        .zip(items(obj, N, what, names)?)
        .enumerate()
    {
        *value = count(&item, &format!("{what}[{i}]"))?;
    }
    Ok(values)
}

/// Rows of `N` numbers (see [`numbers`]) from a sequence of sequences (a list of tuples, a
/// `(k, N)` numpy array) named `what` in messages.
///
/// # Errors
/// As [`numbers`], naming the row (`mask_spheres[1]`).
pub fn rows_of_numbers<const N: usize>(
    obj: &Bound<'_, PyAny>,
    what: &str,
    names: &str,
) -> PyResult<Vec<[f64; N]>> {
    let rows = iterate(obj, &format!("{what} must be a sequence of {names} rows"))?;
    rows.iter()
        .enumerate()
        .map(|(i, row)| numbers(row, &format!("{what}[{i}]"), names))
        .collect()
}

/// The `n` items of a sequence named `what`, holding `names`.
fn items<'py>(
    obj: &Bound<'py, PyAny>,
    n: usize,
    what: &str,
    names: &str,
) -> PyResult<Vec<Bound<'py, PyAny>>> {
    let items = iterate(
        obj,
        &format!("{what} must be a sequence of {n} numbers {names}"),
    )?;
    if items.len() != n {
        return Err(invalid(format!(
            "{what} must have {n} values {names}, got {}",
            items.len()
        )));
    }
    Ok(items)
}

/// The items of any iterable but a string or bytes; otherwise a `TypeError` saying `expected`.
fn iterate<'py>(obj: &Bound<'py, PyAny>, expected: &str) -> PyResult<Vec<Bound<'py, PyAny>>> {
    let refused = || wrong_type(format!("{expected}, got {}", type_name(obj)));
    if obj.is_instance_of::<PyString>() || obj.is_instance_of::<PyBytes>() {
        return Err(refused());
    }
    obj.try_iter().map_err(|_| refused())?.collect()
}
