//! The one place where the library's errors become Python exceptions.
//!
//! Bad data or arguments (`InvalidInput`, a malformed file, a mesh the algorithm cannot work
//! on) raise `ValueError`; a file the system cannot read raises `OSError` (or its subclass
//! for the cause, such as `FileNotFoundError`); a numerical failure raises `RuntimeError`.
//!
//! The bindings' own checks follow Python's rule: an argument of the wrong type (a string
//! where an array is needed, floats where vertex indices are, a float where a count is)
//! raises `TypeError` ([`wrong_type`]); one of the right type with a wrong value (a wrong
//! shape, a negative count, an unknown name) raises `ValueError` ([`invalid`]). An output in
//! a folder that does not exist raises `FileNotFoundError` naming the folder (the library's
//! `Error::Io` of kind `NotFound`), as the command-line tool refuses it.

use crestline::Error;
use pyo3::exceptions::{
    PyFileNotFoundError, PyOSError, PyPermissionError, PyRuntimeError, PyTypeError, PyValueError,
};
use pyo3::prelude::*;
use pyo3::{PyErr, PyResult};

/// The Python exception for a library error, with the library's message.
pub fn to_py_err(error: Error) -> PyErr {
    let message = error.to_string();
    match error {
        Error::Io { cause, .. } => match cause.kind() {
            std::io::ErrorKind::NotFound => PyFileNotFoundError::new_err(message),
            std::io::ErrorKind::PermissionDenied => PyPermissionError::new_err(message),
            _ => PyOSError::new_err(message),
        },
        Error::Parse { .. } | Error::InvalidInput(_) | Error::Topology(_) => {
            PyValueError::new_err(message)
        }
        Error::Solver(_) => PyRuntimeError::new_err(message),
    }
}

/// A `ValueError` with `message`, for arguments the bindings check themselves.
pub fn invalid(message: impl Into<String>) -> PyErr {
    PyValueError::new_err(message.into())
}

/// A `TypeError` with `message`, for arguments of a type the bindings cannot use.
pub fn wrong_type(message: impl Into<String>) -> PyErr {
    PyTypeError::new_err(message.into())
}

/// The name of `obj`'s type, for messages (`"str"`, `"numpy.ndarray"`).
pub fn type_name(obj: &Bound<'_, PyAny>) -> String {
    obj.get_type()
        .fully_qualified_name()
        .map_or_else(|_| "?".to_owned(), |name| name.to_string())
}

/// The value the name `given` stands for among `choices` (case-insensitive, `_` for `-`);
/// otherwise a `ValueError` listing them, saying which argument (`what`) was wrong.
pub fn choose<T: Copy>(what: &str, given: &str, choices: &[(&str, T)]) -> PyResult<T> {
    let key = given.to_ascii_lowercase().replace('_', "-");
    choices
        .iter()
        .find(|(name, _)| *name == key)
        .map(|&(_, value)| value)
        .ok_or_else(|| {
            let names: Vec<String> = choices
                .iter()
                .map(|(name, _)| format!("'{name}'"))
                .collect();
            invalid(format!(
                "{what} must be one of {}, got '{given}'",
                names.join(", ")
            ))
        })
}

/// The name `value` has among `choices` (the inverse of [`choose`]), for messages.
pub fn name_of<T: PartialEq>(value: &T, choices: &[(&'static str, T)]) -> &'static str {
    choices
        .iter()
        .find(|(_, choice)| choice == value)
        .map_or("?", |(name, _)| *name)
}
