//! Python bindings of crestline: feature lines (ridges, valleys) of triangle meshes, numpy
//! arrays in and numpy arrays out.
//!
//! Built by maturin into the extension module `crestline._crestline`, which the package
//! `crestline` (`python/crestline/__init__.py`) re-exports. One file per part of the library
//! it binds: [`mesh`] (reading files, arrays to meshes), [`extract`], [`lines`] (the results),
//! [`curvature`], [`simplify`] (with the feature distance), [`render`]; [`arrays`] converts
//! numpy arrays and [`error`] turns the library's errors into Python exceptions.
//!
//! Every function takes the arrays with the GIL held (reading them is a copy) and releases
//! it for the work. Names and defaults are those of the command-line tool.

// The functions take the command-line tool's options as keyword arguments, one argument each.
#![allow(clippy::too_many_arguments)]

pub mod arrays;
pub mod curvature;
pub mod error;
pub mod extract;
pub mod lines;
pub mod mesh;
pub mod render;
pub mod simplify;

use pyo3::prelude::*;

/// Feature lines (ridges, valleys) of triangle meshes: numpy arrays in, numpy arrays out.
#[pymodule(name = "_crestline")]
fn crestline_module(module: &Bound<'_, PyModule>) -> PyResult<()> {
    module.add("__version__", env!("CARGO_PKG_VERSION"))?;
    module.add_class::<lines::Lines>()?;
    module.add_class::<lines::Line>()?;
    module.add_function(wrap_pyfunction!(mesh::read_mesh, module)?)?;
    module.add_function(wrap_pyfunction!(lines::read_lines, module)?)?;
    module.add_function(wrap_pyfunction!(extract::extract, module)?)?;
    module.add_function(wrap_pyfunction!(curvature::curvature, module)?)?;
    module.add_function(wrap_pyfunction!(simplify::simplify, module)?)?;
    module.add_function(wrap_pyfunction!(simplify::feature_distance, module)?)?;
    module.add_function(wrap_pyfunction!(render::render, module)?)?;
    Ok(())
}
