//! `crestline.curvature`: the command-line tool's `curvature`, on arrays; and the estimator
//! options `curvature` and `extract` share ([`EstimatorArguments`]).

use crestline::curvature::cubic_fit::MAX_RINGS;
use crestline::curvature::{
    CurvatureOptions, Estimator, EstimatorOption, EstimatorSelection, select_estimator,
};
use crestline::extract::surface_fields;
use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::arrays::{count, vectors_array};
use crate::error::{choose, invalid, name_of, to_py_err};
use crate::extract::crease_angle_of;
use crate::mesh::{mesh_from_arrays, per_given_vertex};

/// Principal curvatures, directions and extremalities of every vertex of the mesh
/// `(vertices, faces)` (array-likes as for `extract`).
///
/// Options, with the defaults of `crestline curvature` (each named as its flag, `-` written
/// `_`): `estimator` "jet-fit" (default; "cubic-fit" when `rings` is given), "shape-operator"
/// or "cubic-fit"; `rings`, the k-ring of the cubic fit (1 to 8, default 1);
/// `radius`, the jet fit's disc radius in sample spacings (default 2.5); `degree`, the jet
/// fit's polynomial degree (3 or 4, default 4; 4 lets the fit choose on noisy meshes);
/// `no_noise_adaptation`, keep the jet fit's radius fixed on noisy meshes;
/// `direction_support`, the neighbourhood's weight in the shape operator's principal
/// directions (default 0.5; 0 is the paper's operator); `creases`, the sharp creases the jet
/// fit does not reach across (each side gets its own fit): "auto" (default: the edges above
/// the gap in the histogram of dihedral angles, none on scans), "off", or a dihedral angle
/// in degrees; `keep_outliers`, `keep_orientation` and `no_weld`, as for `extract` (isolated
/// outlier vertices are put back on their neighbours' surface before the estimation unless
/// `keep_outliers`; the fields are those of the surface so repaired). An option of another
/// estimator than the one that runs is a `ValueError`, as on the command line.
///
/// Returns a dict of numpy arrays indexed like the vertices: "k_max", "k_min", "e_max",
/// "e_min" (n,) and "dir_max", "dir_min", "normals" (n, 3), and "outliers" (n,), true at
/// the vertices put back (all false with `keep_outliers`). Signs: a sphere of radius r
/// has k = 1/r with outward normals; `k_max >= k_min`. Raises `TypeError` and `ValueError`
/// as `extract` does (a negative `rings` or `degree` is a `ValueError`).
#[pyfunction]
#[pyo3(signature = (
    vertices, faces, estimator = None, *, rings = None, radius = None, degree = None,
    no_noise_adaptation = false, direction_support = None, creases = None,
    keep_outliers = false, keep_orientation = false, no_weld = false,
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
    direction_support: Option<f64>,
    creases: Option<&Bound<'py, PyAny>>,
    keep_outliers: bool,
    keep_orientation: bool,
    no_weld: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let arguments = EstimatorArguments::new(
        estimator,
        rings,
        radius,
        degree,
        no_noise_adaptation,
        direction_support,
    )?;
    let creases = creases.map(crease_angle_of).transpose()?;
    let defaults = CurvatureOptions::default().with_estimator(Estimator::JetFit);
    let estimator = arguments.estimator(defaults.estimator);
    let mut unused = arguments.unused(defaults.estimator);
    if creases.is_some() && estimator != Estimator::JetFit {
        unused.push(format!(
            "creases (the estimation splits at creases with the jet-fit estimator only; this \
             run uses {})",
            name_of(&estimator, &ESTIMATORS)
        ));
    }
    if !unused.is_empty() {
        return Err(invalid(format!(
            "options that estimator '{}' would not use: {}",
            name_of(&estimator, &ESTIMATORS),
            unused.join("; ")
        )));
    }
    let options = arguments.apply(defaults);
    // Split at the creases (the jet fit only: `surface_fields`).
    let angle = creases.unwrap_or_default();
    let (mesh, weld) = mesh_from_arrays(vertices, faces, keep_orientation, no_weld)?;
    let estimated = py
        .detach(|| surface_fields(&mesh, &options, angle, !keep_outliers))
        .map_err(to_py_err)?;
    let mut moved = vec![false; mesh.num_vertices()];
    for &v in &estimated.outliers.vertices {
        moved[v as usize] = true;
    }
    let c = estimated.curvature;
    let fields = PyDict::new(py);
    fields.set_item(
        "outliers",
        PyArray1::from_vec(py, per_given_vertex(&weld, &moved)?),
    )?;
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

/// The estimators by their command-line names.
pub const ESTIMATORS: [(&str, Estimator); 3] = [
    ("jet-fit", Estimator::JetFit),
    ("shape-operator", Estimator::ShapeOperator),
    ("cubic-fit", Estimator::CubicFit),
];

/// The keyword of an estimator option.
fn keyword(option: EstimatorOption) -> &'static str {
    match option {
        EstimatorOption::Radius => "radius",
        EstimatorOption::Degree => "degree",
        EstimatorOption::NoNoiseAdaptation => "no_noise_adaptation",
        EstimatorOption::Rings => "rings",
        EstimatorOption::DirectionSupport => "direction_support",
    }
}

/// The curvature estimator and its options as `extract` and `curvature` take them (the
/// command-line tool's estimator flags): each means the same in both, and the options of an
/// estimator that does not run are refused ([`EstimatorArguments::unused`]).
pub struct EstimatorArguments {
    /// `estimator`, when given.
    pub estimator: Option<Estimator>,
    /// `rings` of the cubic fit, 1 to [`MAX_RINGS`].
    pub rings: Option<usize>,
    /// `radius` of the jet fit.
    pub radius: Option<f64>,
    /// `degree` of the jet fit.
    pub degree: Option<usize>,
    /// `no_noise_adaptation` of the jet fit.
    pub no_noise_adaptation: bool,
    /// `direction_support` of the shape operator.
    pub direction_support: Option<f64>,
}

impl EstimatorArguments {
    /// The arguments as Python gave them.
    ///
    /// # Errors
    /// `ValueError` for an unknown estimator or `rings` outside 1 to [`MAX_RINGS`];
    /// `TypeError` and `ValueError` for a `rings` or `degree` that is not a count.
    pub fn new(
        estimator: Option<&str>,
        rings: Option<&Bound<'_, PyAny>>,
        radius: Option<f64>,
        degree: Option<&Bound<'_, PyAny>>,
        no_noise_adaptation: bool,
        direction_support: Option<f64>,
    ) -> PyResult<Self> {
        let rings = rings.map(|k| count(k, "rings")).transpose()?;
        if let Some(k) = rings.filter(|k| !(1..=MAX_RINGS).contains(k)) {
            return Err(invalid(format!(
                "rings must be a whole number from 1 to {MAX_RINGS}, got {k}"
            )));
        }
        Ok(EstimatorArguments {
            estimator: estimator
                .map(|name| choose("estimator", name, &ESTIMATORS))
                .transpose()?,
            rings,
            radius,
            degree: degree.map(|d| count(d, "degree")).transpose()?,
            no_noise_adaptation,
            direction_support,
        })
    }

    /// The estimator options given, as the library names them.
    fn given(&self) -> Vec<EstimatorOption> {
        [
            (self.radius.is_some(), EstimatorOption::Radius),
            (self.degree.is_some(), EstimatorOption::Degree),
            (self.no_noise_adaptation, EstimatorOption::NoNoiseAdaptation),
            (self.rings.is_some(), EstimatorOption::Rings),
            (
                self.direction_support.is_some(),
                EstimatorOption::DirectionSupport,
            ),
        ]
        .into_iter()
        .filter_map(|(given, option)| given.then_some(option))
        .collect()
    }

    /// The estimator that runs and the options of another one
    /// ([`crestline::curvature::select_estimator`]).
    fn selection(&self, default: Estimator) -> EstimatorSelection {
        select_estimator(self.estimator, &self.given(), default)
    }

    /// The estimator that runs: `estimator`, else the cubic fit with `rings`, else `default`.
    pub fn estimator(&self, default: Estimator) -> Estimator {
        self.selection(default).estimator
    }

    /// The options given for another estimator than the one that runs, each with why.
    pub fn unused(&self, default: Estimator) -> Vec<String> {
        self.selection(default).reasons(keyword)
    }

    /// `options` with the estimator and the options given.
    pub fn apply(&self, options: CurvatureOptions) -> CurvatureOptions {
        let mut options = options.with_estimator(self.estimator(options.estimator));
        if let Some(k) = self.rings {
            options = options.with_rings(k);
        }
        if let Some(r) = self.radius {
            options.jet_fit = options.jet_fit.with_radius(r);
        }
        if let Some(d) = self.degree {
            options.jet_fit = options.jet_fit.with_degree(d);
        }
        if self.no_noise_adaptation {
            options.jet_fit = options.jet_fit.with_adapt_to_noise(false);
        }
        if let Some(support) = self.direction_support {
            options.shape_operator.direction_support = support;
        }
        options
    }
}
