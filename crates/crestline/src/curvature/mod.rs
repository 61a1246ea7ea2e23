//! Per-vertex principal curvatures, principal directions and extremality coefficients.
//!
//! Two estimators fill the same [`Curvature`] result:
//! - [`Estimator::ShapeOperator`]: the discrete shape operator of HPW 2005 (sec. 3) with the
//!   discrete extremalities of its eq. 4 ([`shape_operator()`], [`extremality`]);
//! - [`Estimator::CubicFit`]: the enhanced adjacent-normal cubic fit of YBS 2005 (eq. 2) with
//!   the extremality of its eq. 3 ([`cubic_fit()`]).
//!
//! [`estimate`] dispatches on [`CurvatureOptions::estimator`]; both estimators run in parallel
//! with rayon and never fail on a mesh (boundaries, non-manifold parts, unreferenced vertices
//! and tiny components get documented fallbacks, counted in [`Curvature::fallback_vertices`]).
//!
//! ## Sign conventions
//! Normals point outward; curvature is positive where the surface bends away from the normal
//! (a sphere of radius r has k = 1/r everywhere); `k_max >= k_min`. `dir_max`/`dir_min` are
//! unit tangent vectors whose sign is arbitrary but fixed; `e_max`/`e_min` are the derivatives
//! of `k_max`/`k_min` along exactly the stored `dir_max`/`dir_min` (flip a direction and its
//! extremality flips sign with it). Ridges: `e_max = 0`, `de_max/dt_max < 0`,
//! `k_max > |k_min|`; valleys: `e_min = 0`, `de_min/dt_min > 0`, `k_min < -|k_max|`.
//!
//! Under a rigid motion the values are unchanged (directions rotate with the mesh); under a
//! uniform scaling by s, curvatures scale by 1/s and extremalities by 1/s².

pub mod cubic_fit;
pub mod extremality;
pub mod jet_fit;
pub mod shape_operator;

/// Moved to [`crate::mesh`] (the outlier repair there needs it); kept here, where the
/// estimators' frames are built.
pub use crate::mesh::tangent_frame;
pub use cubic_fit::{CubicFitOptions, cubic_fit};
pub use jet_fit::{JetFitOptions, JetFitReport, jet_fit, jet_fit_report, jet_fit_split};
pub use shape_operator::{PrincipalSelection, ShapeOperatorOptions, shape_operator};

use rayon::prelude::*;

use crate::error::Result;
use crate::mesh::{TriMesh, Vec3};

/// Which estimator computes the curvature.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Estimator {
    /// Discrete shape operator and discrete extremalities (HPW 2005, sec. 3, eq. 4).
    #[default]
    ShapeOperator,
    /// Enhanced adjacent-normal cubic fitting (YBS 2005, eqs. 2, 3).
    CubicFit,
    /// Weighted polynomial fit over a geodesic disc chosen by geometry (Cazals and Pouget
    /// 2005, with area weights): independent of the triangulation ([`jet_fit()`]).
    JetFit,
}

impl Estimator {
    /// The name the command-line tool and the Python package give it.
    pub fn name(self) -> &'static str {
        match self {
            Estimator::ShapeOperator => "shape-operator",
            Estimator::CubicFit => "cubic-fit",
            Estimator::JetFit => "jet-fit",
        }
    }
}

/// Per-vertex curvature fields, indexed like the mesh's vertices.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Curvature {
    /// Maximal principal curvature.
    pub k_max: Vec<f64>,
    /// Minimal principal curvature (`k_min <= k_max`).
    pub k_min: Vec<f64>,
    /// Unit principal direction of `k_max` (tangent; sign arbitrary but fixed).
    pub dir_max: Vec<Vec3>,
    /// Unit principal direction of `k_min`.
    pub dir_min: Vec<Vec3>,
    /// Extremality `e_max = d k_max / d dir_max`, consistent with the stored `dir_max`.
    pub e_max: Vec<f64>,
    /// Extremality `e_min = d k_min / d dir_min`, consistent with the stored `dir_min`.
    pub e_min: Vec<f64>,
    /// The unit normals the estimate used (outward).
    pub normals: Vec<Vec3>,
    /// Vertices that could not be estimated normally (too few neighbours, unreferenced,
    /// degenerate star) and got a fallback value; never NaN.
    pub fallback_vertices: usize,
    /// Standard deviation of the estimation noise of the extremalities, from
    /// [`Curvature::simulated_noise`] ([`Curvature::set_simulated_noise`]). 0 when the estimator does not measure noise (the shape
    /// operator, the cubic fit) or found the mesh clean. Line strengths count the cyclideness
    /// above this noise only ([`crate::lines::assemble::noise_free_share`]).
    pub extremality_noise: f64,
    /// What the estimator makes of white noise of the measured level in the vertex heights:
    /// per vertex, the `e_max` and `e_min` it would add. Smoothing steps smooth it with the
    /// extremalities, so that [`Curvature::extremality_noise`] follows them. Empty when
    /// `extremality_noise` is 0.
    pub simulated_noise: [Vec<f64>; 2],
    /// Per vertex, `e_max` and `e_min` along the same directions by a second model of the
    /// surface: the jet fit fits both the heights and the curved heights and keeps the
    /// better, or on white noise the curved heights ([`jet_fit`](mod@jet_fit), *Curved
    /// heights*); these are the other's. Where the disc determines the fit the two agree;
    /// where it does not (rows of a CAD export's strips) they can disagree in sign, and a
    /// zero of e that only one of them has is not a crest
    /// ([`crate::lines::assemble::is_resolved`]). Smoothed with the extremalities.
    /// Empty for the other estimators.
    pub alternative_extremalities: [Vec<f64>; 2],
    /// Per vertex, whether the jet fit's disc reached the mesh boundary: a one-sided fit, with
    /// another bias and more noise than a full disc's
    /// ([`jet_fit::one_sided_vertices`]).
    /// Empty for the other estimators and for meshes without a boundary.
    pub one_sided: Vec<bool>,
    /// Per vertex, what one more application of the extremality smoothing changes the
    /// smoothed `e_max` and `e_min` by, when the smoothing measured it
    /// ([`ExtremalitySmoothing::measure_drift`](crate::smoothing::extremality::ExtremalitySmoothing::measure_drift));
    /// empty otherwise. The smoothing moves the zeros of a field that bends on its own scale
    /// (twicing removes the first-order part of that move, not all of it); applied again
    /// to the smoothed field it moves them again, less far where the first pass softened the
    /// bend, so this change over the slope across a line is a lower estimate of how far the
    /// smoothing moved the line ([`crate::lines::debias`], *Smoothing drift*).
    pub smoothing_drift: [Vec<f64>; 2],
    /// The same for [`Curvature::simulated_noise`]: what the drift's estimate carries of the
    /// noise (empty unless both are there).
    pub smoothing_drift_noise: [Vec<f64>; 2],
    /// What the jet fit measured and chose (sample spacing, radius, noise level); `None` for
    /// the other estimators.
    pub jet_fit: Option<JetFitReport>,
}

impl Curvature {
    /// Number of vertices the fields describe.
    pub fn len(&self) -> usize {
        self.k_max.len()
    }

    /// True when there are no vertices.
    pub fn is_empty(&self) -> bool {
        self.k_max.is_empty()
    }

    /// Whether [`Curvature::alternative_extremalities`] holds a second model: both fields, one
    /// value per vertex.
    pub fn has_alternative_extremalities(&self) -> bool {
        let n = self.len();
        n > 0 && self.alternative_extremalities.iter().all(|e| e.len() == n)
    }

    /// Sets [`Curvature::simulated_noise`] and the noise level it implies: its median
    /// absolute value over both families divided by 0.6745 (the standard deviation, for
    /// normal noise), at the vertices whose disc is not [`Curvature::one_sided`], or at every
    /// vertex when fewer than [`MIN_NOISE_SAMPLES`] are left. The fits of
    /// one-sided discs, within the fit's radius of a boundary, have a larger noise; the
    /// median alone does not keep it out when they are many (the public noisy ridge, an open
    /// height field with a disc of 9 spacings: a third of its vertices, and a level of 0.99
    /// where the interior's is 0.82 and the error against the exact fields 0.8 to 1.06).
    pub fn set_simulated_noise(&mut self, simulated: [Vec<f64>; 2]) {
        let one_sided = &self.one_sided;
        let interior = |v: usize| !one_sided.get(v).copied().unwrap_or(false);
        let count = (0..self.len()).filter(|&v| interior(v)).count();
        let sample = |v: usize| count < MIN_NOISE_SAMPLES || interior(v);
        let mut magnitudes: Vec<f64> = simulated
            .iter()
            .flat_map(|family| family.iter().enumerate())
            .filter(|&(v, _)| sample(v))
            .map(|(_, x)| x.abs())
            .collect();
        self.extremality_noise = if magnitudes.is_empty() {
            0.0
        } else {
            let mid = magnitudes.len() / 2;
            magnitudes.select_nth_unstable_by(mid, f64::total_cmp);
            magnitudes[mid] / 0.6745
        };
        self.simulated_noise = simulated;
    }
}

/// The fewest vertices away from the boundary whose simulated noise
/// [`Curvature::set_simulated_noise`] takes the median of alone.
pub const MIN_NOISE_SAMPLES: usize = 64;

/// Options of [`estimate`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CurvatureOptions {
    /// Which estimator runs.
    ///
    /// Default: [`Estimator::JetFit`], the one estimator whose error does not depend on the
    /// triangulation; the papers' estimators stay selectable.
    pub estimator: Estimator,
    /// Options of the shape-operator estimator (used when `estimator` is
    /// [`Estimator::ShapeOperator`]).
    ///
    /// Default: [`ShapeOperatorOptions::DEFAULT`].
    pub shape_operator: ShapeOperatorOptions,
    /// Options of the cubic fit (used when `estimator` is [`Estimator::CubicFit`]); its
    /// `rings` is the k of the k-ring neighbourhood.
    ///
    /// Default: [`CubicFitOptions::DEFAULT`] (1-ring, YBS pre-smoothing on).
    pub cubic_fit: CubicFitOptions,
    /// Options of the jet fit (used when `estimator` is [`Estimator::JetFit`]).
    ///
    /// Default: [`JetFitOptions::DEFAULT`].
    pub jet_fit: JetFitOptions,
}

impl CurvatureOptions {
    /// The default options: jet fit; for the cubic fit, the 1-ring.
    pub const DEFAULT: Self = CurvatureOptions {
        estimator: Estimator::JetFit,
        shape_operator: ShapeOperatorOptions::DEFAULT,
        cubic_fit: CubicFitOptions::DEFAULT,
        jet_fit: JetFitOptions::DEFAULT,
    };

    /// Selects the estimator.
    pub fn with_estimator(mut self, estimator: Estimator) -> Self {
        self.estimator = estimator;
        self
    }

    /// Sets the k of the cubic fit's k-ring neighbourhood (YBS use 1 to 4).
    pub fn with_rings(mut self, rings: usize) -> Self {
        self.cubic_fit.rings = rings;
        self
    }
}

impl Default for CurvatureOptions {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// An option that belongs to one estimator: front ends that take every estimator's options
/// at once (the command-line tool, the Python binding) ask [`select_estimator`] which
/// estimator runs and which of the options given it would not use.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum EstimatorOption {
    /// The jet fit's radius ([`JetFitOptions::radius`]).
    Radius,
    /// The jet fit's degree ([`JetFitOptions::degree`]).
    Degree,
    /// The jet fit's radius kept fixed on noisy meshes ([`JetFitOptions::adapt_to_noise`]
    /// off).
    NoNoiseAdaptation,
    /// The cubic fit's k-ring ([`CubicFitOptions::rings`]); given alone (without an
    /// estimator), it selects the cubic fit.
    Rings,
    /// The neighbourhood's weight in the shape operator's principal directions
    /// ([`ShapeOperatorOptions::direction_support`]).
    DirectionSupport,
}

impl EstimatorOption {
    /// Every option, in the order [`select_estimator`] reports them.
    pub const ALL: [EstimatorOption; 5] = [
        EstimatorOption::Radius,
        EstimatorOption::Degree,
        EstimatorOption::NoNoiseAdaptation,
        EstimatorOption::Rings,
        EstimatorOption::DirectionSupport,
    ];

    /// The estimator that uses the option.
    pub fn estimator(self) -> Estimator {
        match self {
            EstimatorOption::Radius
            | EstimatorOption::Degree
            | EstimatorOption::NoNoiseAdaptation => Estimator::JetFit,
            EstimatorOption::Rings => Estimator::CubicFit,
            EstimatorOption::DirectionSupport => Estimator::ShapeOperator,
        }
    }
}

/// The result of [`select_estimator`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct EstimatorSelection {
    /// The estimator that runs.
    pub estimator: Estimator,
    /// The options given that it would not use, each with the estimator that would, in the
    /// order of [`EstimatorOption::ALL`]; empty when every option given applies.
    pub unused: Vec<(EstimatorOption, Estimator)>,
}

impl EstimatorSelection {
    /// One reason per unused option, `name` spelling the option as the front end takes it:
    /// `--radius (it applies to the jet-fit estimator; this run uses cubic-fit)`.
    pub fn reasons(&self, name: impl Fn(EstimatorOption) -> &'static str) -> Vec<String> {
        self.unused
            .iter()
            .map(|&(option, needs)| {
                format!(
                    "{} (it applies to the {} estimator; this run uses {})",
                    name(option),
                    needs.name(),
                    self.estimator.name()
                )
            })
            .collect()
    }
}

/// Which estimator runs when a front end is given the estimator `chosen` (if any) and the
/// options `given`: `chosen`, else the cubic fit when [`EstimatorOption::Rings`] is given,
/// else `default`; and the options given that belong to another estimator than that one.
///
/// ```
/// use crestline::curvature::{Estimator, EstimatorOption, select_estimator};
///
/// // `--rings 2` alone selects the cubic fit; `--radius` then has nothing to apply to.
/// let given = [EstimatorOption::Rings, EstimatorOption::Radius];
/// let selection = select_estimator(None, &given, Estimator::JetFit);
/// assert_eq!(selection.estimator, Estimator::CubicFit);
/// assert_eq!(selection.unused, [(EstimatorOption::Radius, Estimator::JetFit)]);
/// ```
pub fn select_estimator(
    chosen: Option<Estimator>,
    given: &[EstimatorOption],
    default: Estimator,
) -> EstimatorSelection {
    let estimator = match chosen {
        Some(e) => e,
        None if given.contains(&EstimatorOption::Rings) => Estimator::CubicFit,
        None => default,
    };
    let unused = EstimatorOption::ALL
        .into_iter()
        .filter(|option| given.contains(option) && option.estimator() != estimator)
        .map(|option| (option, option.estimator()))
        .collect();
    EstimatorSelection { estimator, unused }
}

/// Principal curvatures, directions, extremalities and normals of every vertex of `mesh`,
/// by the estimator `options` selects.
///
/// ```
/// use crestline::curvature::{CurvatureOptions, Estimator, estimate};
///
/// # fn main() -> crestline::Result<()> {
/// // A sphere of radius 2 bends by k = 1/2 in every direction.
/// let sphere = crestline::shapes::icosphere(2.0, 4);
/// let options = CurvatureOptions::default().with_estimator(Estimator::JetFit);
/// let c = estimate(&sphere, &options)?;
/// assert!(c.k_max.iter().chain(&c.k_min).all(|k| (k - 0.5).abs() < 0.01));
/// # Ok(())
/// # }
/// ```
///
/// # Errors
/// [`crate::Error::InvalidInput`] for options out of range (see [`CubicFitOptions`]; a
/// negative or non-finite [`ShapeOperatorOptions::direction_support`]). A mesh
/// never causes an error: vertices that cannot be estimated get a fallback value and are
/// counted in [`Curvature::fallback_vertices`].
pub fn estimate(mesh: &TriMesh, options: &CurvatureOptions) -> Result<Curvature> {
    estimate_split(mesh, options, None)
}

/// [`estimate`] with the neighbourhoods split at `creases` (per edge of
/// [`crate::mesh::Topology::edges`], true for a crease edge): the jet fit's discs do not
/// reach across a crease ([`jet_fit_split`]). The papers' estimators read one star or ring
/// and ignore `creases`.
///
/// # Errors
/// As [`estimate`]; [`crate::Error::InvalidInput`] when `creases` does not have one entry per
/// edge.
pub fn estimate_split(
    mesh: &TriMesh,
    options: &CurvatureOptions,
    creases: Option<&[bool]>,
) -> Result<Curvature> {
    mesh.check_coordinate_range()?;
    match options.estimator {
        Estimator::ShapeOperator => {
            let support = options.shape_operator.direction_support;
            if !(support.is_finite() && support >= 0.0) {
                return Err(crate::Error::InvalidInput(format!(
                    "direction support must be a non-negative number, got {support}"
                )));
            }
            Ok(shape_operator(mesh, &options.shape_operator))
        }
        Estimator::CubicFit => cubic_fit(mesh, &options.cubic_fit),
        Estimator::JetFit => jet_fit_split(mesh, &options.jet_fit, creases).map(|(c, _)| c),
    }
}

/// Eigen-decomposition of the symmetric 2×2 matrix `[[a, b], [b, c]]`: returns
/// `(λ_max, λ_min, t_max)` with `t_max` the unit eigenvector of `λ_max` (the one of `λ_min`
/// is `t_max` turned by +90°: `(-t_max[1], t_max[0])`).
///
/// Closed form rather than an iterative solver: it is exact to rounding, branch-light and
/// well conditioned (the eigenvector is built from the larger of two equivalent forms).
/// Plain square roots rather than `hypot` (a measurable cost in the per-vertex loops): entries
/// beyond ~1e154 overflow to infinity, which the estimators turn into their fallback value.
pub fn symmetric_eigen_2x2(a: f64, b: f64, c: f64) -> (f64, f64, [f64; 2]) {
    let mean = 0.5 * (a + c);
    let half_diff = 0.5 * (a - c);
    let radius = (half_diff * half_diff + b * b).sqrt();
    let (x, y) = if half_diff >= 0.0 {
        (radius + half_diff, b)
    } else {
        (b, radius - half_diff)
    };
    let norm = (x * x + y * y).sqrt();
    // An umbilic (radius = 0) has every direction principal: pick the first axis.
    let t = if norm > 0.0 && norm.is_finite() {
        [x / norm, y / norm]
    } else {
        [1.0, 0.0]
    };
    (mean + radius, mean - radius, t)
}

/// One vertex's estimate, before it is scattered into a [`Curvature`].
#[derive(Debug, Clone, Copy)]
pub(crate) struct VertexEstimate {
    pub k_max: f64,
    pub k_min: f64,
    pub dir_max: Vec3,
    pub dir_min: Vec3,
    pub e_max: f64,
    pub e_min: f64,
    pub normal: Vec3,
    pub fallback: bool,
}

impl VertexEstimate {
    /// The fallback value of a vertex with the given normal (zero normal: coordinate frame).
    pub fn fallback(normal: Vec3) -> Self {
        let (u, v, n) = tangent_frame(normal);
        VertexEstimate {
            k_max: 0.0,
            k_min: 0.0,
            dir_max: u,
            dir_min: v,
            e_max: 0.0,
            e_min: 0.0,
            normal: n,
            fallback: true,
        }
    }

    /// Replaces anything non-finite (overflow on absurd input) by the fallback value, so that
    /// the "never NaN" promise holds whatever the arithmetic did.
    pub fn sanitized(self) -> Self {
        let finite = [self.k_max, self.k_min, self.e_max, self.e_min]
            .iter()
            .all(|x| x.is_finite())
            && [self.dir_max, self.dir_min, self.normal]
                .iter()
                .all(|v| v.iter().all(|x| x.is_finite()));
        if finite {
            self
        } else {
            VertexEstimate::fallback(if self.normal.iter().all(|x| x.is_finite()) {
                self.normal
            } else {
                Vec3::zeros()
            })
        }
    }
}

/// `n` zero vectors, written by the worker threads: `vec![Vec3::zeros(); n]` fills on one
/// thread (the allocator cannot hand out zeroed pages for a type it does not know to be all
/// zero bits), 10 ms per array on a 1.5M-face mesh.
pub(crate) fn zero_vectors(n: usize) -> Vec<Vec3> {
    let mut v = Vec::with_capacity(n);
    v.par_extend(rayon::iter::repeat_n(Vec3::zeros(), n));
    v
}

/// Runs `estimate` for every vertex in parallel (with per-job scratch from `init`) and writes
/// the results straight into the arrays of a [`Curvature`]; also returns the per-vertex
/// fallback flags.
pub(crate) fn collect_estimates<T, I, F>(n: usize, init: I, estimate: F) -> (Curvature, Vec<bool>)
where
    I: Fn() -> T + Sync + Send,
    F: Fn(&mut T, u32) -> VertexEstimate + Sync + Send,
{
    collect_estimates_with_normals(zero_vectors(n), init, |scratch, v, _| estimate(scratch, v))
}

/// [`collect_estimates`] for an estimator that already has the vertex normals: `estimate`
/// gets vertex `v`'s entry of `normals`, whose storage becomes the result's normals (each
/// entry overwritten by the estimate's normal), so that no second array is allocated.
pub(crate) fn collect_estimates_with_normals<T, I, F>(
    normals: Vec<Vec3>,
    init: I,
    estimate: F,
) -> (Curvature, Vec<bool>)
where
    I: Fn() -> T + Sync + Send,
    F: Fn(&mut T, u32, Vec3) -> VertexEstimate + Sync + Send,
{
    let n = normals.len();
    let mut c = Curvature {
        k_max: vec![0.0; n],
        k_min: vec![0.0; n],
        dir_max: zero_vectors(n),
        dir_min: zero_vectors(n),
        e_max: vec![0.0; n],
        e_min: vec![0.0; n],
        normals,
        fallback_vertices: 0,
        extremality_noise: 0.0,
        simulated_noise: Default::default(),
        alternative_extremalities: Default::default(),
        one_sided: Vec::new(),
        smoothing_drift: Default::default(),
        smoothing_drift_noise: Default::default(),
        jet_fit: None,
    };
    let mut fallback = vec![false; n];
    (
        c.k_max.par_iter_mut(),
        c.k_min.par_iter_mut(),
        c.dir_max.par_iter_mut(),
        c.dir_min.par_iter_mut(),
        c.e_max.par_iter_mut(),
        c.e_min.par_iter_mut(),
        c.normals.par_iter_mut(),
        fallback.par_iter_mut(),
    )
        .into_par_iter()
        .enumerate()
        .for_each_init(
            init,
            |scratch, (v, (k_max, k_min, dir_max, dir_min, e_max, e_min, normal, fb))| {
                let est = estimate(scratch, v as u32, *normal);
                *k_max = est.k_max;
                *k_min = est.k_min;
                *dir_max = est.dir_max;
                *dir_min = est.dir_min;
                *e_max = est.e_max;
                *e_min = est.e_min;
                *normal = est.normal;
                *fb = est.fallback;
            },
        );
    c.fallback_vertices = fallback.iter().filter(|&&f| f).count();
    (c, fallback)
}

impl VertexEstimate {
    /// Writes the estimate into vertex `v` of `c` (the fallback count is not touched).
    pub fn store(&self, c: &mut Curvature, v: usize) {
        c.k_max[v] = self.k_max;
        c.k_min[v] = self.k_min;
        c.dir_max[v] = self.dir_max;
        c.dir_min[v] = self.dir_min;
        c.e_max[v] = self.e_max;
        c.e_min[v] = self.e_min;
        c.normals[v] = self.normal;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_noise_level_is_the_interior_s() {
        // 200 vertices, the first 120 one-sided with ten times the noise (of either sign):
        // the median over every vertex is 10, the interior's 1.
        let n = 200;
        let one_sided: Vec<bool> = (0..n).map(|v| v < 120).collect();
        let family: Vec<f64> = (0..n)
            .map(|v| if one_sided[v] { 10.0 } else { 1.0 })
            .enumerate()
            .map(|(v, x)| if v % 2 == 0 { -x } else { x })
            .collect();
        let mut c = Curvature {
            k_max: vec![0.0; n],
            one_sided,
            ..Curvature::default()
        };
        c.set_simulated_noise([family.clone(), family.clone()]);
        assert!((c.extremality_noise - 1.0 / 0.6745).abs() < 1e-12);
        // Without the flags, or with too few interior vertices left, every vertex counts.
        c.one_sided = Vec::new();
        c.set_simulated_noise([family.clone(), family.clone()]);
        assert!((c.extremality_noise - 10.0 / 0.6745).abs() < 1e-12);
        c.one_sided = (0..n).map(|v| v >= MIN_NOISE_SAMPLES / 2).collect();
        let family: Vec<f64> = (0..n)
            .map(|v| if c.one_sided[v] { 10.0 } else { 1.0 })
            .collect();
        c.set_simulated_noise([family.clone(), family]);
        assert!((c.extremality_noise - 10.0 / 0.6745).abs() < 1e-12);
    }

    #[test]
    fn eigen_2x2_matches_definition() {
        for &(a, b, c) in &[
            (2.0, 0.0, 1.0),
            (1.0, 0.0, 2.0),
            (0.3, -0.7, 1.1),
            (-1.0, 2.0, -1.0),
            (1.0, 1e-20, 1.0),
        ] {
            let (l1, l2, t) = symmetric_eigen_2x2(a, b, c);
            assert!(l1 >= l2);
            assert!((t[0].hypot(t[1]) - 1.0).abs() < 1e-14);
            // A t = λ t
            let at = [a * t[0] + b * t[1], b * t[0] + c * t[1]];
            assert!((at[0] - l1 * t[0]).abs() < 1e-12 && (at[1] - l1 * t[1]).abs() < 1e-12);
            assert!((l1 + l2 - (a + c)).abs() < 1e-12);
            assert!((l1 * l2 - (a * c - b * b)).abs() < 1e-12);
        }
        let (l1, l2, t) = symmetric_eigen_2x2(1.0, 0.0, 1.0);
        assert_eq!((l1, l2, t), (1.0, 1.0, [1.0, 0.0]));
    }

    #[test]
    fn tangent_frame_is_orthonormal_and_right_handed() {
        for n in [
            Vec3::z(),
            -Vec3::x(),
            Vec3::new(1.0, 2.0, -3.0).normalize(),
            Vec3::new(1e-9, 1.0, 0.0).normalize(),
        ] {
            let (u, v, m) = tangent_frame(n);
            assert!((u.norm() - 1.0).abs() < 1e-14 && (v.norm() - 1.0).abs() < 1e-14);
            assert!(u.dot(&n).abs() < 1e-14 && v.dot(&n).abs() < 1e-14 && u.dot(&v).abs() < 1e-14);
            assert!((u.cross(&v) - m).norm() < 1e-14);
        }
        assert_eq!(
            tangent_frame(Vec3::zeros()),
            (Vec3::x(), Vec3::y(), Vec3::z())
        );
    }

    #[test]
    fn rings_alone_select_the_cubic_fit_and_an_estimator_given_wins() {
        use EstimatorOption::*;
        let select =
            |chosen, given: &[EstimatorOption]| select_estimator(chosen, given, Estimator::JetFit);
        assert_eq!(select(None, &[]).estimator, Estimator::JetFit);
        assert_eq!(select(None, &[Rings]).estimator, Estimator::CubicFit);
        assert_eq!(select(None, &[Rings]).unused, []);
        let shape_operator = select(Some(Estimator::ShapeOperator), &[Rings, DirectionSupport]);
        assert_eq!(shape_operator.estimator, Estimator::ShapeOperator);
        assert_eq!(shape_operator.unused, [(Rings, Estimator::CubicFit)]);
        assert_eq!(
            shape_operator.reasons(|_| "--rings"),
            ["--rings (it applies to the cubic-fit estimator; this run uses shape-operator)"]
        );
        assert_eq!(
            select_estimator(None, &[], Estimator::ShapeOperator).estimator,
            Estimator::ShapeOperator
        );
    }

    #[test]
    fn options_of_another_estimator_are_reported_in_one_order_with_the_estimator_they_need() {
        use EstimatorOption::*;
        let every = EstimatorOption::ALL;
        let mut reversed = every;
        reversed.reverse();
        for given in [every, reversed] {
            let selection =
                select_estimator(Some(Estimator::ShapeOperator), &given, Estimator::JetFit);
            assert_eq!(
                selection.unused,
                [
                    (Radius, Estimator::JetFit),
                    (Degree, Estimator::JetFit),
                    (NoNoiseAdaptation, Estimator::JetFit),
                    (Rings, Estimator::CubicFit),
                ]
            );
        }
        let jet = select_estimator(
            None,
            &[Radius, Degree, NoNoiseAdaptation],
            Estimator::JetFit,
        );
        assert_eq!(jet.unused, []);
        for option in every {
            let selection =
                select_estimator(Some(option.estimator()), &[option], Estimator::JetFit);
            assert_eq!(selection.unused, [], "{option:?}");
        }
    }
}
