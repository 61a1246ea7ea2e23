//! Feature lines as Python objects: `Lines` (all of them, with flat arrays and `write`) and
//! `Line` (one polyline).
//!
//! Both pickle (and copy) by value: `Lines` with its lines' mesh locations, which
//! `feature_distance` and `simplify` use on the mesh they were traced on, and its `stats`.

use std::path::PathBuf;

use crestline::Vec3;
use crestline::extract::{ExtractStats, Extraction};
use crestline::io::PlyEncoding;
use crestline::io::lines::{LinesFormat, write_lines};
use crestline::lines::{FeatureLine, FeatureLines, LineKind, SurfacePoint};
use numpy::{Element, PyArray1, PyArray2, PyArrayMethods};
use pyo3::exceptions::{PyIndexError, PyOverflowError, PyTypeError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PySlice, PySliceMethods, PyType};

use crate::arrays::vectors_array;
use crate::error::{choose, invalid, to_py_err, type_name, wrong_type};

/// Feature lines found on a mesh (or read from a file).
///
/// `len(lines)`, `lines[i]` and `for line in lines` give `Line` objects; `lines[i:j]` (any
/// slice) gives a `Lines` of those lines. All lines at once: `points` (every point, (N, 3))
/// with `offsets` (line i is `points[offsets[i]:offsets[i+1]]`), and per line `kinds`,
/// `lengths`, `strengths`, `curvature_integrals`, `closed`. `write(path)` saves them as the
/// command-line tool does (OBJ, PLY or JSON). `pickle` and `copy` keep everything, the
/// lines' places on the mesh too.
#[pyclass(module = "crestline", frozen)]
pub struct Lines {
    lines: FeatureLines,
    /// The figures of the extraction as `stats` gives them (a copy each time); `None` for
    /// lines read from a file or sliced out of others.
    stats: Option<Py<PyDict>>,
}

impl Lines {
    /// The lines of an extraction, with its figures and the bounding-box `diagonal` of the
    /// mesh it ran on (a figure of `--stats json` too).
    ///
    /// # Errors
    /// When Python cannot build the figures' dict (out of memory).
    pub fn from_extraction(
        py: Python<'_>,
        extraction: Extraction,
        diagonal: f64,
    ) -> PyResult<Self> {
        Ok(Lines {
            stats: Some(stats_dict(py, &extraction.stats, diagonal)?.unbind()),
            lines: extraction.lines,
        })
    }

    /// Lines without figures (read from a file, or some of other lines).
    pub fn without_stats(lines: FeatureLines) -> Self {
        Lines { lines, stats: None }
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

    /// `lines[i]`: a `Line` (`i` negative counts from the end); `lines[i:j:k]`: a `Lines` of
    /// those lines, without `stats`.
    fn __getitem__<'py>(
        &self,
        py: Python<'py>,
        index: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let all = &self.lines.lines;
        if let Ok(slice) = index.cast::<PySlice>() {
            let picked = slice.indices(isize::try_from(all.len())?)?;
            let lines = (0..picked.slicelength)
                .filter_map(|k| isize::try_from(k).ok())
                .filter_map(|k| usize::try_from(picked.start + k * picked.step).ok())
                .filter_map(|i| all.get(i).cloned())
                .collect();
            let lines = Lines::without_stats(FeatureLines { lines });
            return Ok(Bound::new(py, lines)?.into_any());
        }
        let out_of_range = || PyIndexError::new_err(format!("line {index} of {}", all.len()));
        let i: isize = match index.extract() {
            Ok(i) => i,
            Err(e) if e.is_instance_of::<PyOverflowError>(py) => return Err(out_of_range()),
            Err(e) if e.is_instance_of::<PyTypeError>(py) => {
                return Err(wrong_type(format!(
                    "Lines indices must be integers or slices, not {}",
                    type_name(index)
                )));
            }
            Err(e) => return Err(e),
        };
        let from_start = if i < 0 {
            all.len().checked_sub(i.unsigned_abs())
        } else {
            usize::try_from(i).ok()
        };
        let line = from_start
            .and_then(|i| all.get(i))
            .ok_or_else(out_of_range)?;
        Ok(Bound::new(py, Line::of(py, line)?)?.into_any())
    }

    /// Pickling: the lines rebuilt by `Lines._from_state` from the dict of their arrays.
    fn __reduce__<'py>(
        slf: &Bound<'py, Self>,
    ) -> PyResult<(Bound<'py, PyAny>, (Bound<'py, PyDict>,))> {
        let rebuild = slf.get_type().getattr("_from_state")?;
        Ok((rebuild, (lines_state(slf.py(), slf.get())?,)))
    }

    /// The lines a `__reduce__` state describes (not for direct use).
    #[classmethod]
    fn _from_state(_cls: &Bound<'_, PyType>, state: &Bound<'_, PyDict>) -> PyResult<Self> {
        lines_from_state(state)
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

    /// Figures about the extraction, as `crestline extract --stats json` prints them but for
    /// the times of reading and writing files (triangles, singular triangles per family,
    /// lines traced and kept, `ridges` and `valleys` (crest lines only) and `crease_ridges`
    /// and `crease_valleys` (convex and concave creases), as the JSON lines file counts them,
    /// their total length, the sharp creases (`creases`, `crease_length`,
    /// `crease_threshold_degrees`: `None` when none were looked for or found;
    /// `crease_normals_filtered`: true when that threshold is between filtered normals, on a
    /// noisy mesh), the
    /// bounding-box `diagonal`, the model `scale` that relative lengths are fractions of (the
    /// diagonal of the largest connected component), threshold, seconds per stage; `jet_fit`: the sample spacing, the radius in spacings, the noise level and
    /// its standard deviation in spacings, the quartic weight the fit chose and
    /// `triangle_sampled_vertices`, the vertices fitted on the mesh's triangles (long thin
    /// triangles of CAD fans and strips), `None` for
    /// the other estimators); `None` for lines read from a file or sliced out of others. A
    /// copy each time.
    #[getter]
    fn stats<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyAny>>> {
        // A copy: changing the dict given does not change the lines' figures.
        let deepcopy = py.import("copy")?.getattr("deepcopy")?;
        self.stats
            .as_ref()
            .map(|s| deepcopy.call1((s,)))
            .transpose()
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

/// The figures of `--stats json` but for the times of reading and writing files.
fn stats_dict<'py>(
    py: Python<'py>,
    s: &ExtractStats,
    diagonal: f64,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("triangles", s.triangles)?;
    d.set_item("outliers_moved", s.outliers.vertices.len())?;
    d.set_item(
        "marching_cubes_grid",
        s.marching_cubes_grid.map(|grid| grid.spacing.to_vec()),
    )?;
    d.set_item("singular_max", s.trace.singular_max)?;
    d.set_item("singular_min", s.trace.singular_min)?;
    d.set_item("fallback_vertices", s.fallback_vertices)?;
    d.set_item("lines_traced", s.lines_traced)?;
    d.set_item("lines_unlocated", s.lines_unlocated)?;
    d.set_item("lines_trimmed", s.lines_trimmed)?;
    d.set_item("lines", s.lines)?;
    d.set_item("ridges", s.ridges)?;
    d.set_item("valleys", s.valleys)?;
    d.set_item("crease_ridges", s.crease_ridges)?;
    d.set_item("crease_valleys", s.crease_valleys)?;
    d.set_item("total_length", s.total_length)?;
    d.set_item("creases", s.creases)?;
    d.set_item("crease_length", s.crease_length)?;
    d.set_item("crease_threshold_degrees", s.crease_threshold)?;
    d.set_item("crease_normals_filtered", s.crease_normals_filtered)?;
    d.set_item("diagonal", diagonal)?;
    d.set_item("scale", s.scale)?;
    d.set_item("threshold", s.threshold)?;
    d.set_item("threshold_auto", s.threshold_is_auto)?;
    d.set_item("threshold_split", s.threshold_is_split)?;
    d.set_item("threshold_ridges", s.family_thresholds.map(|t| t[0]))?;
    d.set_item("threshold_valleys", s.family_thresholds.map(|t| t[1]))?;
    d.set_item("gaps_jumped", s.gaps_jumped)?;
    let jet_fit = match s.jet_fit {
        Some(j) => {
            let fit = PyDict::new(py);
            fit.set_item("spacing", j.spacing)?;
            fit.set_item("radius_spacings", j.radius)?;
            fit.set_item("noise_spacings", j.noise)?;
            fit.set_item("noise_sigma_spacings", j.sigma)?;
            fit.set_item("quartic_weight", j.quartic_weight)?;
            fit.set_item("noise_growth", j.noise_growth)?;
            fit.set_item("white_noise", j.white_noise())?;
            fit.set_item("triangle_sampled_vertices", j.triangle_sampled)?;
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

/// The attributes of a `Line` in the order `Line._from_fields` takes them.
type LineFields<'py> = (&'static str, Bound<'py, PyArray2<f64>>, bool, f64, f64, f64);

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

    /// Pickling: the line rebuilt by `Line._from_fields` from its attributes.
    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<(Bound<'py, PyAny>, LineFields<'py>)> {
        let line = slf.get();
        let rebuild = slf.get_type().getattr("_from_fields")?;
        let fields = (
            line.kind,
            line.points.bind(slf.py()).clone(),
            line.closed,
            line.length,
            line.strength,
            line.curvature_integral,
        );
        Ok((rebuild, fields))
    }

    /// The line of a `__reduce__`'s attributes (not for direct use).
    #[classmethod]
    fn _from_fields(
        _cls: &Bound<'_, PyType>,
        kind: &str,
        points: Bound<'_, PyArray2<f64>>,
        closed: bool,
        length: f64,
        strength: f64,
        curvature_integral: f64,
    ) -> PyResult<Self> {
        let (name, _, _) = kind_of_name(kind)?;
        Ok(Line {
            kind: name,
            points: points.unbind(),
            closed,
            length,
            strength,
            curvature_integral,
        })
    }
}

/// Reads feature lines from a file `Lines.write` or `crestline extract` wrote: OBJ, PLY or
/// JSON, with kinds (crease kinds too) and strengths. The format follows the extension
/// unless `format` names it: "obj", "ply" or "json", as for `Lines.write`.
///
/// Raises `ValueError` for a malformed file or an unknown format, `OSError` when it cannot
/// be read.
#[pyfunction]
#[pyo3(signature = (path, format = None))]
pub fn read_lines(py: Python<'_>, path: PathBuf, format: Option<&str>) -> PyResult<Lines> {
    let format = format
        .map(|name| choose("format", name, &LINES_FORMATS))
        .transpose()?;
    let lines = py
        .detach(|| crestline::io::lines::read_lines(&path, format))
        .map_err(to_py_err)?;
    Ok(Lines::without_stats(lines))
}

/// The kinds of lines by their names: family and whether a crease.
const KINDS: [(&str, LineKind, bool); 4] = [
    ("ridge", LineKind::Ridge, false),
    ("valley", LineKind::Valley, false),
    ("crease-ridge", LineKind::Ridge, true),
    ("crease-valley", LineKind::Valley, true),
];

fn kind_of_name(name: &str) -> PyResult<(&'static str, LineKind, bool)> {
    KINDS
        .iter()
        .find(|(known, _, _)| *known == name)
        .copied()
        .ok_or_else(|| invalid(format!("unknown kind of line '{name}'")))
}

/// The codes of the kinds of mesh locations in a pickled state.
const AT_VERTEX: u8 = 0;
const ON_EDGE: u8 = 1;
const IN_FACE: u8 = 2;

/// `lines` as a dict of arrays, for pickling: the attributes `Lines` gives (`kinds`,
/// `points`, `offsets`, `closed`, `lengths`, `strengths`, `curvature_integrals`), the mesh
/// locations of the points (`location_offsets` per line as `offsets`; per location its kind,
/// vertex, edge or face index and edge parameter) and `stats`.
fn lines_state<'py>(py: Python<'py>, lines: &Lines) -> PyResult<Bound<'py, PyDict>> {
    let all = &lines.lines.lines;
    let locations = all.iter().flat_map(|l| l.locations.iter());
    let location_kinds: Vec<u8> = locations
        .clone()
        .map(|at| match at {
            SurfacePoint::Vertex(_) => AT_VERTEX,
            SurfacePoint::Edge { .. } => ON_EDGE,
            SurfacePoint::Face { .. } => IN_FACE,
        })
        .collect();
    let location_indices: Vec<u32> = locations
        .clone()
        .map(|at| match *at {
            SurfacePoint::Vertex(v) => v,
            SurfacePoint::Edge { edge, .. } => edge,
            SurfacePoint::Face { face } => face,
        })
        .collect();
    let location_parameters: Vec<f64> = locations
        .map(|at| match *at {
            SurfacePoint::Edge { t, .. } => t,
            SurfacePoint::Vertex(_) | SurfacePoint::Face { .. } => 0.0,
        })
        .collect();
    let state = PyDict::new(py);
    state.set_item("kinds", lines.kinds())?;
    state.set_item("points", lines.points(py)?)?;
    state.set_item("offsets", lines.offsets(py))?;
    state.set_item("closed", lines.closed(py))?;
    state.set_item("lengths", lines.lengths(py))?;
    state.set_item("strengths", lines.strengths(py))?;
    state.set_item("curvature_integrals", lines.curvature_integrals(py))?;
    let location_offsets = ends(all.iter().map(|l| l.locations.len()));
    state.set_item("location_offsets", PyArray1::from_vec(py, location_offsets))?;
    state.set_item("location_kinds", PyArray1::from_vec(py, location_kinds))?;
    state.set_item("location_indices", PyArray1::from_vec(py, location_indices))?;
    state.set_item(
        "location_parameters",
        PyArray1::from_vec(py, location_parameters),
    )?;
    state.set_item("stats", lines.stats.as_ref())?;
    Ok(state)
}

/// Where each run of `lengths` starts, then where the last ends: `len + 1` values from 0.
fn ends(lengths: impl Iterator<Item = usize>) -> Vec<usize> {
    std::iter::once(0)
        .chain(lengths.scan(0, |end, n| {
            *end += n;
            Some(*end)
        }))
        .collect()
}

/// The lines of a dict [`lines_state`] made.
///
/// # Errors
/// `ValueError` for a dict it did not make (a key missing, arrays that do not agree).
fn lines_from_state(state: &Bound<'_, PyDict>) -> PyResult<Lines> {
    let kinds: Vec<String> = state_item(state, "kinds")?.extract()?;
    let points = state_column::<f64>(state, "points")?;
    let offsets = state_column::<usize>(state, "offsets")?;
    let closed = state_column::<bool>(state, "closed")?;
    let lengths = state_column::<f64>(state, "lengths")?;
    let strengths = state_column::<f64>(state, "strengths")?;
    let integrals = state_column::<f64>(state, "curvature_integrals")?;
    let location_offsets = state_column::<usize>(state, "location_offsets")?;
    let location_kinds = state_column::<u8>(state, "location_kinds")?;
    let location_indices = state_column::<u32>(state, "location_indices")?;
    let location_parameters = state_column::<f64>(state, "location_parameters")?;
    let n = kinds.len();
    let bad = || invalid("not the state of a crestline.Lines: its arrays do not agree");
    let ascending = |ends: &[usize]| ends.windows(2).all(|w| w[0] <= w[1]);
    let agree = [offsets.len(), location_offsets.len()] == [n + 1, n + 1]
        && ascending(&offsets)
        && ascending(&location_offsets)
        && [
            closed.len(),
            lengths.len(),
            strengths.len(),
            integrals.len(),
        ] == [n; 4]
        && offsets.last().map(|&end| 3 * end) == Some(points.len())
        && location_offsets.last() == Some(&location_kinds.len())
        && [location_indices.len(), location_parameters.len()] == [location_kinds.len(); 2];
    if !agree {
        return Err(bad());
    }
    let mut lines = Vec::with_capacity(n);
    for (i, name) in kinds.iter().enumerate() {
        let (_, kind, crease) = kind_of_name(name)?;
        let xyz = points
            .get(3 * offsets[i]..3 * offsets[i + 1])
            .ok_or_else(bad)?;
        let places = location_offsets[i]..location_offsets[i + 1];
        let locations = location_kinds
            .get(places.clone())
            .zip(location_indices.get(places.clone()))
            .zip(location_parameters.get(places))
            .ok_or_else(bad)?;
        let locations = locations
            .0
            .0
            .iter()
            .zip(locations.0.1)
            .zip(locations.1)
            .map(|((&at, &index), &t)| match at {
                AT_VERTEX => Ok(SurfacePoint::Vertex(index)),
                ON_EDGE => Ok(SurfacePoint::Edge { edge: index, t }),
                IN_FACE => Ok(SurfacePoint::Face { face: index }),
                _ => Err(bad()),
            })
            .collect::<PyResult<_>>()?;
        lines.push(FeatureLine {
            kind,
            points: xyz
                .chunks_exact(3)
                .map(|p| Vec3::new(p[0], p[1], p[2]))
                .collect(),
            locations,
            closed: closed[i],
            length: lengths[i],
            curvature_integral: integrals[i],
            strength: strengths[i],
            crease,
        });
    }
    let stats = state_item(state, "stats")?;
    let stats = if stats.is_none() {
        None
    } else {
        Some(stats.cast_into::<PyDict>()?.unbind())
    };
    Ok(Lines {
        lines: FeatureLines { lines },
        stats,
    })
}

fn state_item<'py>(state: &Bound<'py, PyDict>, key: &str) -> PyResult<Bound<'py, PyAny>> {
    state
        .get_item(key)?
        .ok_or_else(|| invalid(format!("not the state of a crestline.Lines: no '{key}'")))
}

/// The values of the array `state[key]`, flattened, as `T` (numpy converts them).
fn state_column<T: Element + Copy>(state: &Bound<'_, PyDict>, key: &str) -> PyResult<Vec<T>> {
    let py = state.py();
    let flat = py.import("numpy")?.call_method1(
        "ascontiguousarray",
        (
            state_item(state, key)?.call_method0("ravel")?,
            T::get_dtype(py),
        ),
    )?;
    Ok(flat.cast_into::<PyArray1<T>>()?.to_vec()?)
}
