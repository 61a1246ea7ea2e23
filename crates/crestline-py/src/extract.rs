//! `crestline.extract`: the command-line tool's `extract`, on arrays.
//!
//! The extraction runs without the GIL and checks for signals when each stage starts and
//! ends ([`extract_interruptibly`]): Ctrl-C raises `KeyboardInterrupt` at the next stage
//! boundary instead of after the whole run.

use std::panic::{AssertUnwindSafe, catch_unwind, resume_unwind};

use crestline::extract::{ExtractOptions, Extraction, Method, Pipeline, extract_with_progress};
use crestline::lines::crease::CreaseAngle;
use crestline::mesh::Weld;
use crestline::smoothing::extremality::{DiffusionMask, MaskRegion};
use crestline::smoothing::surface::SurfaceSmoothing;
use crestline::threshold::Threshold;
use crestline::{TriMesh, Vec3};
use pyo3::prelude::*;

use crate::arrays::{count, per_vertex, rows_of_numbers};
use crate::curvature::EstimatorArguments;
use crate::error::{choose, invalid, name_of, to_py_err, type_name, wrong_type};
use crate::lines::Lines;
use crate::mesh::mesh_from_arrays;
use crestline::curvature::Estimator;

/// Finds the ridges and valleys of the mesh `(vertices, faces)`.
///
/// `vertices`: (n, 3) array-like of coordinates (float64, float32, ...); `faces`: (m, 3)
/// array-like of vertex indices (int64, int32, ...). A `trimesh.Trimesh`'s `.vertices` and
/// `.faces` work as they are. The options and their defaults are those of `crestline
/// extract`, each named as its flag with `-` written `_` (but for `mask_spheres` and
/// `mask_boxes`); `None` means the method's default:
///
/// - `method`: "hpw" (Hildebrandt-Polthier-Wardetzky 2005, default), "ybs"
///   (Yoshizawa-Belyaev-Seidel 2005) or "saliency" (Mao-Wang-Zhou).
/// - `threshold`: a number, or "auto" for the knee of the sorted strengths. HPW: the strength
///   T, default 1. YBS: default "auto" (above T = 1). Saliency: the saliency, default "auto".
/// - `min_length`: lines shorter than this fraction of the bounding-box diagonal (of the
///   largest part when the mesh has several) are dropped (default 0.01).
/// - `smooth_steps`, `smooth_time`: extremality smoothing steps (default 2 for HPW and YBS,
///   run when the curvature estimate finds the surface noisy; giving a number always runs
///   them; at most 1000) and step size relative to the squared mean edge length (default 1).
/// - `smooth_along`: on meshes whose noise the jet fit finds white, the extremality smoothing
///   runs up to this many times faster along the lines than across them (default 3; 1 is HPW's
///   isotropic smoothing); other meshes are smoothed isotropically.
/// - `crease_angle`: damp the smoothing across curvature jumps of about this angle, in
///   degrees (default 0.3 rad, about 17.2; 0 with `no_twicing` is HPW's plain smoothing).
/// - `creases`: sharp creases, traced as lines of their own and not smoothed or fitted
///   across: "auto" (default: the edges above the gap in the histogram of dihedral angles;
///   on a noisy mesh without one, the gap between face normals filtered within the faces;
///   none when there is no gap, as on scans of smooth shapes), "off", or a dihedral angle
///   in degrees.
/// - `fair`: spatial fairing, largest displacement as a fraction of the diagonal (off).
/// - `no_debias`: leave the crest lines where they are traced. By default, on
///   meshes the jet fit finds noisy, they are moved across by the displacement its widened
///   disc causes and, on white noise, by the drift the extremality smoothing measures of
///   itself.
/// - `keep_unlocated`: keep the lines the noise moves about, and their ends (HPW and YBS
///   with the jet fit only). By default, on meshes the jet fit finds white noise on, they
///   drop the lines whose extremality crosses zero less than twice as steeply as its
///   estimation noise, and cut such ends off the lines they keep.
/// - `keep_outliers`: take every vertex as it is. By default isolated outlier vertices
///   (spikes: single vertices far off the surface their neighbours describe, as scanners
///   leave them) are put back on that surface first, so that they are not ringed with
///   creases and crest lines; `stats["outliers_moved"]` counts them.
/// - `pre_smooth`: steps of implicit mean-curvature flow before anything else (off; at most
///   1000).
/// - `estimator`: "jet-fit" (default), "shape-operator" or "cubic-fit". The options of
///   one estimator given with another that runs are a `ValueError`, as on the command line:
/// - `radius`, `degree`, `no_noise_adaptation` (jet fit): radius of the disc in sample
///   spacings (default 2.5; grown on noisy meshes unless `no_noise_adaptation`) and degree
///   of the polynomial, 3 or 4 (default 4).
/// - `rings` (cubic fit): rings of YBS's cubic fit (1 to 8); selects the cubic fit unless
///   `estimator` says otherwise.
/// - `direction_support` (shape operator): neighbourhood weight in the principal directions
///   (default 0.5; 0 is the paper's operator).
/// - `mask`: one diffusion factor per vertex (inhomogeneous smoothing); `mask_spheres`:
///   `(x, y, z, r, factor)` rows (the command line's repeated `--mask-sphere`) and
///   `mask_boxes`: `(x0, y0, z0, x1, y1, z1, factor)` rows (`--mask-box`), tuples, lists,
///   or the rows of a numpy array, scale it inside them.
/// - `no_gaps`: turn off YBS's gap jumping (method "ybs" only).
/// - `keep_orientation`: keep the triangles' winding. By default triangles wound against
///   their neighbours, then closed surfaces facing inward, are reversed first (curvature
///   signs follow the normals).
/// - `no_twicing`: plain extremality smoothing, as HPW smooth (by default the residual the
///   smoothing removes is smoothed and added back: its noise reduction without the drift of
///   the zeros).
/// - `no_weld`: keep vertices at the same position apart. By default they are made one first
///   (patches exported side by side, seams split for texture or normals), as the
///   command-line tool does: otherwise the surface, its fits and its lines end at every seam.
///   Triangles that repeat the corners of another are dropped too.
///
/// Returns a `Lines`. Raises `TypeError` for arguments of the wrong type (a string or floats
/// where vertex indices are needed, a float where a count is), `ValueError` for bad values
/// (shape, NaN, index out of range, a negative count, a mesh without triangles) or options
/// (out of range, or unused by the method and estimator that run). The work releases the
/// GIL; Ctrl-C raises `KeyboardInterrupt` when the stage running ends.
#[pyfunction]
#[pyo3(signature = (
    vertices, faces, method = "hpw", *, threshold = None, min_length = None,
    smooth_steps = None, smooth_time = None, smooth_along = None, crease_angle = None,
    creases = None,
    direction_support = None, fair = None, pre_smooth = None, estimator = None,
    radius = None, degree = None, no_noise_adaptation = false, rings = None, mask = None,
    mask_spheres = None, mask_boxes = None, no_gaps = false, keep_orientation = false,
    no_weld = false, no_twicing = false, no_debias = false, keep_unlocated = false,
    keep_outliers = false,
))]
pub fn extract(
    py: Python<'_>,
    vertices: &Bound<'_, PyAny>,
    faces: &Bound<'_, PyAny>,
    method: &str,
    threshold: Option<&Bound<'_, PyAny>>,
    min_length: Option<f64>,
    smooth_steps: Option<&Bound<'_, PyAny>>,
    smooth_time: Option<f64>,
    smooth_along: Option<f64>,
    crease_angle: Option<f64>,
    creases: Option<&Bound<'_, PyAny>>,
    direction_support: Option<f64>,
    fair: Option<f64>,
    pre_smooth: Option<&Bound<'_, PyAny>>,
    estimator: Option<&str>,
    radius: Option<f64>,
    degree: Option<&Bound<'_, PyAny>>,
    no_noise_adaptation: bool,
    rings: Option<&Bound<'_, PyAny>>,
    mask: Option<&Bound<'_, PyAny>>,
    mask_spheres: Option<&Bound<'_, PyAny>>,
    mask_boxes: Option<&Bound<'_, PyAny>>,
    no_gaps: bool,
    keep_orientation: bool,
    no_weld: bool,
    no_twicing: bool,
    no_debias: bool,
    keep_unlocated: bool,
    keep_outliers: bool,
) -> PyResult<Lines> {
    let method = choose("method", method, &METHODS)?;
    let smooth_steps = smooth_steps.map(|n| count(n, "smooth_steps")).transpose()?;
    let pre_smooth = pre_smooth.map(|n| count(n, "pre_smooth")).transpose()?;
    let estimator = EstimatorArguments::new(
        estimator,
        rings,
        radius,
        degree,
        no_noise_adaptation,
        direction_support,
    )?;
    let creases = creases.map(crease_angle_of).transpose()?;
    let mask_spheres = mask_spheres
        .map(|s| rows_of_numbers::<5>(s, "mask_spheres", "(x, y, z, r, factor)"))
        .transpose()?;
    let mask_boxes = mask_boxes
        .map(|b| rows_of_numbers::<7>(b, "mask_boxes", "(x0, y0, z0, x1, y1, z1, factor)"))
        .transpose()?;
    refuse_negative_factors(mask_spheres.as_deref(), "mask_spheres")?;
    refuse_negative_radii(mask_spheres.as_deref())?;
    refuse_negative_factors(mask_boxes.as_deref(), "mask_boxes")?;
    let mut options = ExtractOptions::for_method(method);
    refuse_unused_options(
        method,
        &estimator,
        [no_gaps, no_debias, keep_unlocated, smooth_along.is_some()],
        &options,
    )?;
    // `mesh_from_arrays` orients the mesh, unless `keep_orientation`.
    options.orient_outward = false;
    if let Some(steps) = smooth_steps {
        options.smoothing.steps = steps;
    }
    // As on the command line: the library smooths clean meshes only when told to, and a
    // smoothing option given is that.
    let smoothing: Vec<&str> = [
        (smooth_time.is_some(), "smooth_time"),
        (no_twicing, "no_twicing"),
        (crease_angle.is_some(), "crease_angle"),
        (mask.is_some(), "mask"),
        (mask_spheres.is_some(), "mask_spheres"),
        (mask_boxes.is_some(), "mask_boxes"),
    ]
    .into_iter()
    .filter_map(|(given, name)| given.then_some(name))
    .collect();
    // `smooth_along` does not make clean meshes smoothed, but has nothing to shape at 0 steps.
    let refused: Vec<&str> = smoothing
        .iter()
        .copied()
        .chain(smooth_along.is_some().then_some("smooth_along"))
        .collect();
    if smooth_steps == Some(0) && !refused.is_empty() {
        return Err(invalid(format!(
            "{}: the extremality smoothing they set does not run with smooth_steps=0",
            refused.join(", ")
        )));
    }
    if smooth_steps.is_some() || !smoothing.is_empty() {
        options.smooth_only_noisy = false;
    }
    options.smoothing.time_step = smooth_time.unwrap_or(options.smoothing.time_step);
    options.smoothing.twicing = !no_twicing;
    options.white_noise_along_lines = smooth_along.unwrap_or(options.white_noise_along_lines);
    if let Some(degrees) = crease_angle {
        options.smoothing.crease_angle = degrees.to_radians();
    }
    if let Some(angle) = creases {
        options.creases.angle = angle;
    }
    apply_threshold(&mut options, threshold)?;
    options.min_length = min_length.unwrap_or(options.min_length);
    options.fairing.tolerance = fair.unwrap_or(options.fairing.tolerance);
    options.debias_lines = !no_debias;
    options.drop_unlocated_lines = !keep_unlocated;
    options.repair_outliers = !keep_outliers;
    if let Some(steps) = pre_smooth {
        options.pre_smoothing = SurfaceSmoothing {
            steps,
            ..SurfaceSmoothing::default()
        };
    }
    options.curvature = estimator.apply(options.curvature);
    if let (true, Pipeline::Ybs(ybs)) = (no_gaps, &mut options.pipeline) {
        ybs.gaps = None;
    }
    let (mesh, weld) = mesh_from_arrays(vertices, faces, keep_orientation, no_weld)?;
    if mesh.num_faces() == 0 {
        return Err(invalid(format!(
            "the mesh has no triangles ({} vertices, {} degenerate triangles dropped): \
             nothing to work on",
            weld.map.len(),
            mesh.degenerate_faces()
        )));
    }
    options.smoothing.diffusion = diffusion(
        &mesh,
        &weld,
        mask,
        &mask_spheres.unwrap_or_default(),
        &mask_boxes.unwrap_or_default(),
    )?;
    let diagonal = mesh.bounding_box().diagonal();
    let extraction = extract_interruptibly(py, &mesh, &options)?;
    Lines::from_extraction(py, extraction, diagonal)
}

/// Refuses the options that `method` and the estimator that runs would not use, as the
/// command-line tool does, naming the arguments: `no_gaps` but for YBS, `no_debias` and
/// `smooth_along` but with the jet fit, `keep_unlocated` but for HPW and YBS with the jet
/// fit, and the options of another estimator ([`EstimatorArguments::unused`]).
fn refuse_unused_options(
    method: Method,
    estimator: &EstimatorArguments,
    [no_gaps, no_debias, keep_unlocated, smooth_along]: [bool; 4],
    defaults: &ExtractOptions,
) -> PyResult<()> {
    let mut unused = Vec::new();
    if no_gaps && method != Method::Ybs {
        unused.push("no_gaps (gap jumping is part of method 'ybs' only)".to_owned());
    }
    unused.extend(estimator.unused(defaults.curvature.estimator));
    if no_debias && estimator.estimator(defaults.curvature.estimator) != Estimator::JetFit {
        unused.push(
            "no_debias (the lines are moved back by the jet fit's bias only; the papers' \
             estimators read no disc)"
                .to_owned(),
        );
    }
    if smooth_along && estimator.estimator(defaults.curvature.estimator) != Estimator::JetFit {
        unused.push(
            "smooth_along (only the jet fit tells white noise; the papers' estimators are \
             smoothed as HPW smooth)"
                .to_owned(),
        );
    }
    if keep_unlocated && method == Method::Saliency {
        unused.push(
            "keep_unlocated (HPW and YBS drop the lines the noise moves about; the saliency \
             method links feature points)"
                .to_owned(),
        );
    } else if keep_unlocated
        && estimator.estimator(defaults.curvature.estimator) != Estimator::JetFit
    {
        unused.push(
            "keep_unlocated (only the jet fit measures the noise; the papers' estimators \
             read no disc)"
                .to_owned(),
        );
    }
    if unused.is_empty() {
        return Ok(());
    }
    Err(invalid(format!(
        "options that method '{}' would not use: {}",
        name_of(&method, &METHODS),
        unused.join("; ")
    )))
}

/// [`crestline::extract::extract`] without the GIL, checking for signals when each stage
/// starts and ends: the exception of a Python signal handler (`KeyboardInterrupt` for
/// Ctrl-C) abandons the run there and is raised. A stage itself runs to its end.
///
/// # Errors
/// The library's error as a Python exception, or the signal handler's.
pub fn extract_interruptibly(
    py: Python<'_>,
    mesh: &TriMesh,
    options: &ExtractOptions,
) -> PyResult<Extraction> {
    /// What unwinds out of the library when a signal handler raised: `resume_unwind` runs
    /// no panic hook (nothing is printed) and only the frames of the run are left.
    struct Interrupted(PyErr);

    let outcome = py.detach(|| {
        catch_unwind(AssertUnwindSafe(|| {
            extract_with_progress(mesh, options, &mut |_, _| {
                if let Err(raised) = Python::attach(|py| py.check_signals()) {
                    resume_unwind(Box::new(Interrupted(raised)));
                }
            })
        }))
    });
    match outcome {
        Ok(extraction) => extraction.map_err(to_py_err),
        Err(payload) => match payload.downcast::<Interrupted>() {
            Ok(interrupted) => Err(interrupted.0),
            // A panic of the library: on to pyo3, which raises `PanicException`.
            Err(payload) => resume_unwind(payload),
        },
    }
}

/// The methods by their command-line names.
const METHODS: [(&str, Method); 3] = [
    ("hpw", Method::Hpw),
    ("ybs", Method::Ybs),
    ("saliency", Method::Saliency),
];

/// `threshold`: a number fixes it, "auto" asks for the knee search.
fn apply_threshold(
    options: &mut ExtractOptions,
    threshold: Option<&Bound<'_, PyAny>>,
) -> PyResult<()> {
    let Some(threshold) = threshold else {
        return Ok(());
    };
    if let Ok(text) = threshold.extract::<String>() {
        if text != "auto" {
            return Err(invalid(format!(
                "threshold takes a number or 'auto', got '{text}'"
            )));
        }
        options
            .pipeline
            .set_threshold(options.pipeline.automatic_threshold());
        return Ok(());
    }
    let value = threshold.extract().map_err(|_| {
        wrong_type(format!(
            "threshold takes a number or 'auto', got {}",
            type_name(threshold)
        ))
    })?;
    options.pipeline.set_threshold(Threshold::Fixed(value));
    Ok(())
}

/// `creases`: "auto", "off" or a dihedral angle in degrees strictly between 0 and 180, as
/// `--creases` takes it.
///
/// # Errors
/// `ValueError` for another string or an angle out of range, `TypeError` for anything else.
pub fn crease_angle_of(creases: &Bound<'_, PyAny>) -> PyResult<CreaseAngle> {
    let expected = "creases takes 'auto', 'off' or an angle in degrees between 0 and 180";
    if let Ok(text) = creases.extract::<String>() {
        return match text.as_str() {
            "auto" => Ok(CreaseAngle::Auto),
            "off" => Ok(CreaseAngle::Off),
            _ => Err(invalid(format!("{expected}, got '{text}'"))),
        };
    }
    let degrees: f64 = creases
        .extract()
        .map_err(|_| wrong_type(format!("{expected}, got {}", type_name(creases))))?;
    if degrees > 0.0 && degrees < 180.0 {
        Ok(CreaseAngle::Degrees(degrees))
    } else {
        Err(invalid(format!("{expected}, got {degrees}")))
    }
}

/// Refuses a region whose factor (its last number) is negative or not finite, before any
/// work (the command line refuses it as it parses `--mask-sphere` and `--mask-box`).
fn refuse_negative_factors<const N: usize>(rows: Option<&[[f64; N]]>, what: &str) -> PyResult<()> {
    for (i, row) in rows.unwrap_or_default().iter().enumerate() {
        let factor = row[N - 1];
        if !factor.is_finite() || factor < 0.0 {
            return Err(invalid(format!(
                "{what}[{i}]: factor {factor} must be a finite number >= 0"
            )));
        }
    }
    Ok(())
}

/// Refuses a sphere `(x, y, z, r, factor)` whose radius is negative or not finite, before any
/// work (as the command line's `--mask-sphere`).
fn refuse_negative_radii(spheres: Option<&[[f64; 5]]>) -> PyResult<()> {
    for (i, &[.., radius, _]) in spheres.unwrap_or_default().iter().enumerate() {
        if !(radius.is_finite() && radius >= 0.0) {
            return Err(invalid(format!(
                "mask_spheres[{i}]: radius {radius} must be a finite number >= 0"
            )));
        }
    }
    Ok(())
}

/// Per-vertex diffusion factors: `mask`, scaled inside the spheres and boxes.
fn diffusion(
    mesh: &TriMesh,
    weld: &Weld,
    mask: Option<&Bound<'_, PyAny>>,
    spheres: &[[f64; 5]],
    boxes: &[[f64; 7]],
) -> PyResult<Option<Vec<f64>>> {
    // One factor per vertex of the arrays; vertices welded into one take the least of theirs.
    let factors = mask
        .map(|m| per_vertex(m, weld.map.len(), "mask"))
        .transpose()?
        .map(|given| {
            weld.to_welded(&given, f64::min)
                .ok_or_else(|| invalid("mask must have one value per vertex"))
        })
        .transpose()?;
    let spheres = spheres
        .iter()
        .map(|&[x, y, z, radius, factor]| MaskRegion::Sphere {
            center: Vec3::new(x, y, z),
            radius,
            factor,
        });
    let boxes = boxes
        .iter()
        .map(|&[x0, y0, z0, x1, y1, z1, factor]| MaskRegion::Box {
            min: Vec3::new(x0, y0, z0),
            max: Vec3::new(x1, y1, z1),
            factor,
        });
    let regions = DiffusionMask {
        regions: spheres.chain(boxes).collect(),
    };
    Ok(regions.apply(mesh, factors))
}
