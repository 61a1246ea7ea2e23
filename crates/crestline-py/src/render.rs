//! `crestline.render`: the command-line tool's `render`, on arrays.

use std::path::PathBuf;

use crestline::render::{
    ColorMapChoice, FieldRange, RenderOptions, UpAxis, render_png, write_picture,
};
use pyo3::prelude::*;
use pyo3::types::PyBytes;

use crate::arrays::{counts, numbers, per_vertex};
use crate::error::{choose, to_py_err};
use crate::lines::Lines;
use crate::mesh::mesh_from_arrays;

/// Draws the mesh `(vertices, faces)`, its `lines` (a `Lines`; ridges red, valleys blue)
/// and a per-vertex `field` (an (n,) array-like, for example `curvature(...)["k_max"]`).
///
/// Without `path` returns the PNG file's bytes; with `path` writes a PNG, SVG (raster mesh,
/// vector lines) or HTML (the self-contained WebGL viewer) picture, chosen by the extension,
/// and returns None. Options, with the defaults of `crestline render`: `view` (azimuth,
/// elevation) in degrees (30, 20); `size` (width, height) in pixels (1024, 1024), both any
/// sequence of two numbers (a tuple, a list, a numpy array); `up`
/// "auto" (guessed from the mesh: "z" when it stands on a flat base along Z, else "y"), "y"
/// or "z"; `colormap` "auto", "viridis" or "diverging"; `field_range` the field values at the
/// ends of the colour map, a percentile p (the p-th to (100-p)-th percentiles, 0 for the whole
/// range; 2) or (min, max); `line_width` in pixels (2.5);
/// `no_ridges`, `no_valleys`, `no_legend`; `legend_title` (default: none); `wireframe`
/// draws the mesh's edges, hidden ones hidden (PNG and SVG; default False).
#[pyfunction]
#[pyo3(signature = (
    vertices, faces, lines = None, field = None, path = None, *, view = None, size = None,
    up = "auto", colormap = "auto", field_range = None, line_width = None, no_ridges = false, no_valleys = false,
    no_legend = false, legend_title = None, wireframe = false,
))]
pub fn render<'py>(
    py: Python<'py>,
    vertices: &Bound<'py, PyAny>,
    faces: &Bound<'py, PyAny>,
    lines: Option<Bound<'py, Lines>>,
    field: Option<&Bound<'py, PyAny>>,
    path: Option<PathBuf>,
    view: Option<&Bound<'py, PyAny>>,
    size: Option<&Bound<'py, PyAny>>,
    up: &str,
    colormap: &str,
    field_range: Option<&Bound<'py, PyAny>>,
    line_width: Option<f64>,
    no_ridges: bool,
    no_valleys: bool,
    no_legend: bool,
    legend_title: Option<String>,
    wireframe: bool,
) -> PyResult<Option<Bound<'py, PyBytes>>> {
    // The picture shows the mesh as given, neither welded nor turned (a field is one value
    // per vertex given).
    let (mesh, _) = mesh_from_arrays(vertices, faces, true, true)?;
    let field = field
        .map(|f| per_vertex(f, mesh.num_vertices(), "field"))
        .transpose()?;
    let mut options = RenderOptions::default();
    if let Some(view) = view {
        let [azimuth, elevation] = numbers(view, "view", "(azimuth, elevation)")?;
        options = options.with_view(azimuth, elevation);
    }
    if let Some(size) = size {
        let [width, height] = counts::<u32, 2>(size, "size", "(width, height)")?;
        options = options.with_size(width, height);
    }
    options.up = choose(
        "up",
        up,
        &[("auto", UpAxis::Auto), ("y", UpAxis::Y), ("z", UpAxis::Z)],
    )?;
    options.color_map = choose(
        "colormap",
        colormap,
        &[
            ("auto", ColorMapChoice::Auto),
            ("viridis", ColorMapChoice::Viridis),
            ("diverging", ColorMapChoice::Diverging),
        ],
    )?;
    if let Some(range) = field_range {
        options.field_range = field_range_from(range)?;
    }
    options.line_width = line_width.unwrap_or(options.line_width);
    options.show_ridges = !no_ridges;
    options.show_valleys = !no_valleys;
    options.legend = !no_legend;
    options.legend_title = legend_title.unwrap_or_default();
    options.wireframe = wireframe;
    let lines = lines.as_ref().map(|l| l.get().feature_lines());
    let field = field.as_deref();
    match path {
        Some(path) => {
            // Before the rendering, not after it.
            crestline::io::check_output_folder(&path).map_err(to_py_err)?;
            py.detach(|| write_picture(&path, &mesh, lines, field, &options))
                .map_err(to_py_err)?;
            Ok(None)
        }
        None => {
            let png = py
                .detach(|| render_png(&mesh, lines, field, &options))
                .map_err(to_py_err)?;
            Ok(Some(PyBytes::new(py, &png)))
        }
    }
}

/// `field_range` as the library's: a number is a percentile, a sequence of two the end
/// values (both checked with the other options).
fn field_range_from(value: &Bound<'_, PyAny>) -> PyResult<FieldRange> {
    if let Ok(p) = value.extract::<f64>() {
        return Ok(FieldRange::Percentile(p));
    }
    let [min, max] = numbers(
        value,
        "field_range",
        "(min, max), or a percentile (a number from 0 to below 50)",
    )?;
    Ok(FieldRange::Fixed { min, max })
}
