//! Feature lines as Python objects: `Lines` (all of them, with flat arrays and `write`) and
//! `Line` (one polyline).

use std::path::PathBuf;

use crestline::extract::ExtractStats;
use crestline::io::PlyEncoding;
use crestline::io::lines::{LinesFormat, write_lines};
use crestline::lines::{FeatureLine, FeatureLines};
use numpy::{PyArray1, PyArray2};
use pyo3::exceptions::PyIndexError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::arrays::vectors_array;
use crate::error::{choose, to_py_err};

/// Feature lines found on a mesh (or read from a file).
///
/// `len(lines)`, `lines[i]` and `for line in lines` give `Line` objects. All lines at once:
/// `points` (every point, (N, 3)) with `offsets` (line i is `points[offsets[i]:offsets[i+1]]`),
/// and per line `kinds`, `lengths`, `strengths`, `curvature_integrals`, `closed`.
/// `write(path)` saves them as the command-line tool does (OBJ, PLY or JSON).
#[pyclass(module = "crestline", frozen)]
pub struct Lines {
    lines: FeatureLines,
    stats: Option<ExtractStats>,
}

impl Lines {
    /// Wraps the lines of an extraction and its figures.
    pub fn new(lines: FeatureLines, stats: Option<ExtractStats>) -> Self {
        Lines { lines, stats }
    }

    /// The library's lines.
    pub fn feature_lines(&self) -> &FeatureLines {
        &self.lines
    }

    fn per_line<'py, T: numpy::Element>(
        &self,
        py: Python<'py>,
        value: impl Fn(&FeatureLine) -> T,
    ) -> Bound<'py, PyArray1<T>> {
        PyArray1::from_vec(py, self.lines.lines.iter().map(value).collect())
    }
}

#[pymethods]
impl Lines {
    fn __len__(&self) -> usize {
        self.lines.lines.len()
    }

    fn __getitem__(&self, py: Python<'_>, index: isize) -> PyResult<Line> {
        let n = self.lines.lines.len();
        let i = if index < 0 { index + n as isize } else { index };
        let line = usize::try_from(i)
            .ok()
            .and_then(|i| self.lines.lines.get(i))
            .ok_or_else(|| PyIndexError::new_err(format!("line {index} of {n}")))?;
        Line::of(py, line)
    }

    fn __iter__(slf: Bound<'_, Self>) -> PyResult<Bound<'_, PyAny>> {
        let py = slf.py();
        let lines = slf
            .get()
            .lines
            .lines
            .iter()
            .map(|l| Line::of(py, l))
            .collect::<PyResult<Vec<Line>>>()?;
        lines.into_pyobject(py)?.try_iter().map(Bound::into_any)
    }

    fn __repr__(&self) -> String {
        let mut counts: Vec<(&str, usize)> = Vec::new();
        for line in &self.lines.lines {
            match counts.iter_mut().find(|(k, _)| *k == line.kind_name()) {
                Some((_, n)) => *n += 1,
                None => counts.push((line.kind_name(), 1)),
            }
        }
        let counts: Vec<String> = counts.iter().map(|(k, n)| format!("{n} {k}")).collect();
        format!(
            "<crestline.Lines: {} lines ({}), total length {:.6}>",
            self.lines.lines.len(),
            counts.join(", "),
            self.lines.total_length()
        )
    }

    /// Every point of every line, line after line, as an (N, 3) float64 array.
    #[getter]
    fn points<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let points: Vec<crestline::Vec3> = self
            .lines
            .lines
            .iter()
            .flat_map(|l| l.points.iter().copied())
            .collect();
        vectors_array(py, &points)
    }

    /// Where each line starts in `points`, and at the end the number of points: an int64
    /// array of `len(lines) + 1` values.
    #[getter]
    fn offsets<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<i64>> {
        let offsets = std::iter::once(0)
            .chain(self.lines.lines.iter().scan(0i64, |end, l| {
                *end += l.points.len() as i64;
                Some(*end)
            }))
            .collect();
        PyArray1::from_vec(py, offsets)
    }

    /// The kind of each line ("ridge", "valley", ...), as a list of strings.
    #[getter]
    fn kinds(&self) -> Vec<&'static str> {
        self.lines.lines.iter().map(|l| l.kind_name()).collect()
    }

    /// The length of each line in model units (float64 array).
    #[getter]
    fn lengths<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.per_line(py, |l| l.length)
    }

    /// The strength T of each line (YBS eq. 5; float64 array, 0 for lines read from OBJ).
    #[getter]
    fn strengths<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.per_line(py, |l| l.strength)
    }

    /// The integral of |k| along each line (float64 array, 0 for lines read from OBJ).
    #[getter]
    fn curvature_integrals<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.per_line(py, |l| l.curvature_integral)
    }

    /// Whether each line is closed (bool array).
    #[getter]
    fn closed<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<bool>> {
        self.per_line(py, |l| l.closed)
    }

    /// The sum of the lengths.
    #[getter]
    fn total_length(&self) -> f64 {
        self.lines.total_length()
    }

    /// Figures about the extraction, as `crestline extract --stats json` prints them
    /// (triangles, singular triangles per family, lines traced and kept, threshold, seconds
    /// per stage; `jet_fit`: the sample spacing, the radius in spacings, the noise level and
    /// its standard deviation in spacings and the quartic weight the fit chose, `None` for
    /// the other estimators); `None` for lines read from a file.
    #[getter]
    fn stats<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        self.stats.as_ref().map(|s| stats_dict(py, s)).transpose()
    }

    /// Writes the lines to `path` as the command-line tool does: OBJ (`o ridges` / `o
    /// valleys` groups of `l` polylines), PLY (binary; vertices and edges with a kind) or
    /// JSON (every attribute of every line). `format` ("obj", "ply" or "json") overrides
    /// the extension.
    #[pyo3(signature = (path, format = None))]
    fn write(&self, py: Python<'_>, path: PathBuf, format: Option<&str>) -> PyResult<()> {
        let format = format
            .map(|name| choose("format", name, &LINES_FORMATS))
            .transpose()?;
        py.detach(|| write_lines(&path, &self.lines, format, PlyEncoding::BinaryLittleEndian))
            .map_err(to_py_err)
    }
}

/// The feature-line formats by the names of `--format`.
const LINES_FORMATS: [(&str, LinesFormat); 3] = [
    ("obj", LinesFormat::Obj),
    ("ply", LinesFormat::Ply),
    ("json", LinesFormat::Json),
];

fn stats_dict<'py>(py: Python<'py>, s: &ExtractStats) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("triangles", s.triangles)?;
    d.set_item("singular_max", s.trace.singular_max)?;
    d.set_item("singular_min", s.trace.singular_min)?;
    d.set_item("fallback_vertices", s.fallback_vertices)?;
    d.set_item("lines_traced", s.lines_traced)?;
    d.set_item("lines", s.lines)?;
    d.set_item("ridges", s.ridges)?;
    d.set_item("valleys", s.valleys)?;
    d.set_item("total_length", s.total_length)?;
    d.set_item("threshold", s.threshold)?;
    d.set_item("threshold_auto", s.threshold_is_auto)?;
    d.set_item("gaps_jumped", s.gaps_jumped)?;
    let jet_fit = match s.jet_fit {
        Some(j) => {
            let fit = PyDict::new(py);
            fit.set_item("spacing", j.spacing)?;
            fit.set_item("radius_spacings", j.radius)?;
            fit.set_item("noise_spacings", j.noise)?;
            fit.set_item("noise_sigma_spacings", j.sigma)?;
            fit.set_item("quartic_weight", j.quartic_weight)?;
            Some(fit)
        }
        None => None,
    };
    d.set_item("jet_fit", jet_fit)?;
    let seconds = PyDict::new(py);
    for (stage, time) in &s.stage_times {
        seconds.set_item(stage.name(), time.as_secs_f64())?;
    }
    d.set_item("stage_seconds", seconds)?;
    Ok(d)
}

/// One feature line: `kind` ("ridge", "valley", ...), `points` ((k, 3) float64), `closed`
/// (the last point joins the first, which is not repeated), `length`, `strength` (T) and
/// `curvature_integral`.
#[pyclass(module = "crestline", frozen, get_all)]
pub struct Line {
    kind: &'static str,
    points: Py<PyArray2<f64>>,
    closed: bool,
    length: f64,
    strength: f64,
    curvature_integral: f64,
}

impl Line {
    fn of(py: Python<'_>, line: &FeatureLine) -> PyResult<Line> {
        Ok(Line {
            kind: line.kind_name(),
            points: vectors_array(py, &line.points)?.unbind(),
            closed: line.closed,
            length: line.length,
            strength: line.strength,
            curvature_integral: line.curvature_integral,
        })
    }
}

#[pymethods]
impl Line {
    fn __repr__(&self) -> String {
        format!(
            "<crestline.Line: {}{}, length {:.6}, strength {:.4}>",
            self.kind,
            if self.closed { ", closed" } else { "" },
            self.length,
            self.strength
        )
    }
}

/// Reads feature lines from a file `Lines.write` or `crestline extract` wrote: OBJ, PLY or
/// JSON, chosen by the extension, with kinds (crease kinds too) and strengths.
#[pyfunction]
pub fn read_lines(py: Python<'_>, path: PathBuf) -> PyResult<Lines> {
    let lines = py
        .detach(|| crestline::io::lines::read_lines(&path, None))
        .map_err(to_py_err)?;
    Ok(Lines::new(lines, None))
}
