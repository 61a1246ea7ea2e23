//! The one place where the library's errors become Python exceptions.
//!
//! Bad data or arguments (`InvalidInput`, a malformed file, a mesh the algorithm cannot work
//! on) raise `ValueError`; a file the system cannot read raises `OSError` (or its subclass
//! for the cause, such as `FileNotFoundError`); a numerical failure raises `RuntimeError`.

use crestline::Error;
use pyo3::PyErr;
use pyo3::exceptions::{
    PyFileNotFoundError, PyOSError, PyPermissionError, PyRuntimeError, PyValueError,
};

/// The Python exception for a library error, with the library's message.
pub fn to_py_err(error: Error) -> PyErr {
    let message = error.to_string();
    match error {
        Error::Io { source, .. } => match source.kind() {
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
