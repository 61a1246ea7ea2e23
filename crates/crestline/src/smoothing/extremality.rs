//! Sign-aware implicit smoothing of extremalities (HPW 2005, sec. 5.1, and the
//! inhomogeneous smoothing of sec. 6).
//!
//! Extremalities are not functions on the surface: each is defined up to the sign of its
//! principal direction. HPW smooth them with the modified Laplacian
//! `Δe(p) = Σ_q w_pq (σ_pq e(q) − e(p))`, `σ_pq = sign⟨dir(p), dir(q)⟩`, which works on the
//! whole mesh (singular triangles included). Here each step is implicit,
//! `(M + t L_σ) e' = M e` ([`super::system`], solved through [`super::DiffusionOperator`]);
//! the two families share the weights, differ in their signs, and are solved together (by
//! default with conjugate gradients in mixed precision, [`super::mixed_precision`]); smoothed
//! along their lines (below) each family has weights and an operator of its own, and the two
//! are solved side by side.
//!
//! The result does not depend on the initial choice of signs: flipping `dir(p)` flips `e(p)`
//! and every `σ_pq` at `p`, i.e. conjugates the system by a diagonal ±1 matrix.
//!
//! Inhomogeneous smoothing: per-vertex factors `f` scale the diffusion locally, the weight of
//! edge pq becoming `w_pq (f_p + f_q) / 2` ([`DiffusionMask`] builds them from regions).
//!
//! **Crease-aware diffusion** (a deviation, on by default; [`ExtremalitySmoothing::crease_angle`]).
//! A sharp crease of a CAD model is a jump of the principal curvature over one ring: the
//! extremality there is a pair of opposite spikes, one each side, and its zero sits on the
//! crease only as long as the two spikes balance. Plain diffusion mixes spikes with the
//! extremalities of the flat and curved faces on either side, which are not symmetric, and the
//! zero drifts off the crease (on fandisk, 3 steps lose 38% of the crease edges). Damping the
//! diffusion across edges where the curvature jumps keeps each side's profile and still
//! smooths along the crease; on smooth (also noisy scanned) surfaces the jumps are small and
//! the smoothing is HPW's. It is an automatic instance of the paper's inhomogeneous smoothing.
//!
//! **Twicing** (a deviation, on by default; [`ExtremalitySmoothing::twicing`]). Diffusion moves
//! the zeros of a field that bends: near a crossing `e ≈ a u + b u²`, one unit of time moves
//! the zero by about `2b / a` (the Laplacian over the gradient), whatever the noise. On the
//! public bumpy sphere the crest lines of its bumps bend and lie close together, and two plain
//! steps moved them by about a spacing on the *clean* mesh (score.py: the share of the lines
//! within half the tolerance of an exact crest line fell from 0.95 to 0.48). Tukey's twicing
//! (*Exploratory Data Analysis*, 1977), also Richardson extrapolation in the diffusion time,
//! smooths the residual and adds it back: `2 S e − S (S e)`, whose bias is of second order in
//! the time instead of first (0.48 → 0.88 there). Its noise is that of `S` at about half the
//! time (for heat kernels in the plane, variance `0.229 / (π t)` against `0.125 / (π t)` for
//! plain smoothing at t), so S runs the steps at twice the time step: the noise taken out is
//! about that of the plain smoothing with the options given (for the implicit steps and white
//! noise, variance +1.5% at the default 2 steps, +18% at 1 step, −2% at 3), the drift of the
//! zeros is gone. It costs
//! twice the steps. Measured (score.py, HPW, default settings; noisy cases only, since clean
//! meshes are not smoothed): bumpy/noisy20k 0.400 → 0.466, ridge/noisy20k 0.976 → 0.966, the
//! other public noisy cases within 0.002; on noisy cases made like them (not in `../shared`)
//! bumpy +0.01 to +0.07, an irregular noisy ellipsoid 0.874 → 0.897, the rest within 0.01.
//!
//! **Along the lines** (a deviation, [`ExtremalitySmoothing::along_lines`]; off by default,
//! on for white noise in [`crate::extract`]). A zero of e moves across its line only by what
//! the smoothing mixes in from across it; along the line, e is near zero on both sides. Each
//! family can therefore be smoothed faster along its own lines than across them: the ridges'
//! e_max along the min directions, the valleys' e_min along the max directions. The operator
//! is the linear finite-element diffusion with the tensor `P + θ (a − 1) T` per face
//! ([`super::along_line_weights`]): across the lines HPW's, along them up to `a` times faster
//! where the triangles have edges along the lines. (With θ = 1 everywhere, a face whose edges
//! cross the lines at an angle gets negative weights; clamped, they diffused across the lines
//! up to `a` times faster too, a spread that depended on the triangulation.) The noise the
//! jet fit leaves in e is correlated over its disc, so a weak crest's zero wanders over a
//! disc's length; isotropic smoothing long enough to take that out also mixes neighbouring
//! crests (public `bumpy/noisy20k`, four times the time: 0.867 → 0.688). Along the lines, at
//! `a` = 3: 0.860, the noisy ridge 0.962 → 0.966, the noisy ellipsoid 0.991 → 1.000; on 80
//! noisy surfaces made like the public ones 0.898 → 0.907 (BENCHMARKS.md). It costs one
//! operator per family, solved side by side.
//!
//! Time step: `t = time_step · h²` with `h` the mean edge length, so the same options behave
//! the same on meshes of any scale; one step diffuses over roughly `sqrt(time_step)` rings.

use rayon::prelude::*;

use crate::curvature::Curvature;
use crate::error::{Error, Result};
use crate::mesh::{TriMesh, Vec3, mean_edge_length};

use super::{
    DiffusionOperator, LinearSolver, along_line_weights, cotan_weights_and_mass, lumped_mass,
};

/// Options of [`smooth_extremalities`].
#[derive(Debug, Clone, PartialEq)]
pub struct ExtremalitySmoothing {
    /// Number of implicit steps. HPW needed at most 5 on their models.
    /// Default: 2 (with crease-aware diffusion: fandisk keeps 98% of its crease length, 96.7%
    /// after 3 steps; the bunny gives 207 lines, 134 after 3 steps).
    pub steps: usize,
    /// Step size relative to the squared mean edge length.
    /// Default: 1.0.
    pub time_step: f64,
    /// Per-vertex diffusion factors (1 = normal, 0 = none, >1 = more); `None` for
    /// homogeneous smoothing. Default: `None`.
    pub diffusion: Option<Vec<f64>>,
    /// Crease-aware diffusion (radians; 0 turns it off, which is HPW's smoothing): the weight
    /// of edge pq is divided by `1 + (J_pq / crease_angle)²` with
    /// `J_pq = |pq| · max(|Δk_max|, |Δk_min|)`, the jump of the principal curvatures across
    /// the edge times its length — about the dihedral angle a sharp crease puts between the
    /// two vertices, and O(h²) on a smooth surface. See the module docs.
    ///
    /// Default: [`DEFAULT_CREASE_ANGLE`].
    pub crease_angle: f64,
    /// The linear solver of the implicit steps.
    /// Default: [`LinearSolver::DEFAULT`] (Jacobi-preconditioned conjugate gradients,
    /// relative tolerance 1e-5).
    pub solver: LinearSolver,
    /// Twicing (see the module docs): the extremalities become `2 S e − S (S e)`, S being
    /// [`ExtremalitySmoothing::steps`] steps of twice [`ExtremalitySmoothing::time_step`]. About
    /// the noise of plain smoothing with the options as given (at 2 steps or more; one step
    /// lets about 9% more through), without its drift of the zeros; twice the steps. Applied
    /// by [`smooth_extremalities`] and [`smooth_extremalities_split`];
    /// [`ExtremalitySmoother`]'s steps are plain. `false` is HPW's plain smoothing.
    /// Default: true.
    pub twicing: bool,
    /// Also measure the smoothing's drift: what applying the smoothing once more (with
    /// these options) changes the smoothed extremalities and their simulated noise by, kept
    /// in [`Curvature::smoothing_drift`] and [`Curvature::smoothing_drift_noise`] for
    /// [`crate::lines::debias`]. Costs the steps once more (twice with twicing) on the
    /// extremalities and on their simulated noise, both solved to [`DRIFT_TOLERANCE`].
    /// [`crate::extract`] turns it on when it will move the lines back and the jet fit found
    /// the noise white ([`crate::lines::debias`], *Smoothing drift*). Off, the drift
    /// fields are emptied (a drift measured by an earlier smoothing would be stale).
    ///
    /// Default: false.
    pub measure_drift: bool,
    /// How many times faster, at most, each family diffuses along its own lines than across
    /// them (see the module docs, *Along the lines*): the ridges (max family) run along the
    /// min directions, the valleys along the max directions; across them the diffusion stays
    /// HPW's. 1 is HPW's isotropic smoothing; more than 1 takes out more of the noise without
    /// moving the zeros across, and costs one operator per family. [`crate::extract`] uses
    /// [`crate::extract::ExtractOptions::white_noise_along_lines`] instead where the jet fit
    /// finds the noise white.
    ///
    /// Default: 1.
    pub along_lines: f64,
}

/// Default of [`ExtremalitySmoothing::crease_angle`]: 0.3 rad (about 17°). Measured on fandisk
/// (3 steps): 90% of its crease edges covered, against 62% with plain smoothing; on the bunny
/// 134 lines instead of 101, none of them spurious to the eye.
pub const DEFAULT_CREASE_ANGLE: f64 = 0.3;

impl Default for ExtremalitySmoothing {
    fn default() -> Self {
        ExtremalitySmoothing {
            steps: 2,
            time_step: 1.0,
            diffusion: None,
            crease_angle: DEFAULT_CREASE_ANGLE,
            solver: LinearSolver::DEFAULT,
            twicing: true,
            measure_drift: false,
            along_lines: 1.0,
        }
    }
}

impl ExtremalitySmoothing {
    /// The options of the operator S the steps apply: with twicing, twice the time step.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] for a time step that is not a non-negative number (checked
    /// before it is doubled, so that the message shows the value given).
    fn operator(&self) -> Result<std::borrow::Cow<'_, Self>> {
        if !(self.time_step.is_finite() && self.time_step >= 0.0) {
            return Err(Error::InvalidInput(format!(
                "time step must be a non-negative number, got {}",
                self.time_step
            )));
        }
        Ok(if self.twicing {
            std::borrow::Cow::Owned(ExtremalitySmoothing {
                time_step: 2.0 * self.time_step,
                ..self.clone()
            })
        } else {
            std::borrow::Cow::Borrowed(self)
        })
    }
}

/// Regions that scale the smoothing locally, turned into per-vertex factors by
/// [`DiffusionMask::factors`]. Where regions overlap, the last one listed wins.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct DiffusionMask {
    /// The regions, in order.
    pub regions: Vec<MaskRegion>,
}

/// One region of a [`DiffusionMask`] with its factor.
#[derive(Debug, Clone, PartialEq)]
pub enum MaskRegion {
    /// Vertices within `radius` of `center`.
    Sphere {
        /// Centre.
        center: Vec3,
        /// Radius.
        radius: f64,
        /// Diffusion factor inside.
        factor: f64,
    },
    /// Vertices inside the axis-aligned box.
    Box {
        /// Smallest corner.
        min: Vec3,
        /// Largest corner.
        max: Vec3,
        /// Diffusion factor inside.
        factor: f64,
    },
}

impl DiffusionMask {
    /// `factors` (per vertex; `None` for 1 everywhere) times the regions' factors where they
    /// contain the vertex: the regions' factors alone without `factors`, `factors` unchanged
    /// without regions. For [`ExtremalitySmoothing::diffusion`]: a file's factors with
    /// regions on top.
    pub fn apply(&self, mesh: &TriMesh, factors: Option<Vec<f64>>) -> Option<Vec<f64>> {
        if self.regions.is_empty() {
            return factors;
        }
        let scale = self.factors(mesh);
        Some(match factors {
            Some(f) => f.iter().zip(&scale).map(|(a, b)| a * b).collect(),
            None => scale,
        })
    }

    /// Per-vertex factors: 1 outside every region.
    pub fn factors(&self, mesh: &TriMesh) -> Vec<f64> {
        mesh.positions()
            .iter()
            .map(|p| {
                self.regions
                    .iter()
                    .rev()
                    .find_map(|r| match *r {
                        MaskRegion::Sphere {
                            center,
                            radius,
                            factor,
                        } => ((p - center).norm() <= radius).then_some(factor),
                        MaskRegion::Box { min, max, factor } => {
                            ((0..3).all(|k| p[k] >= min[k] && p[k] <= max[k])).then_some(factor)
                        }
                    })
                    .unwrap_or(1.0)
            })
            .collect()
    }
}

/// What crease-aware diffusion divides the weight of edge `[a, b]` by: `1 + (J / crease_angle)²`
/// with `J = |pq| · max(|Δk_max|, |Δk_min|)` (1 when `J / crease_angle` is not finite).
#[inline]
fn crease_divisor(
    mesh: &TriMesh,
    curvature: &Curvature,
    crease_angle: f64,
    [a, b]: [u32; 2],
) -> f64 {
    let length = (mesh.position(a) - mesh.position(b)).norm();
    let (k_max, k_min) = (&curvature.k_max, &curvature.k_min);
    let (a, b) = (a as usize, b as usize);
    let jump = (k_max[a] - k_max[b]).abs().max((k_min[a] - k_min[b]).abs()) * length;
    let x = jump / crease_angle;
    if x.is_finite() { 1.0 + x * x } else { 1.0 }
}

/// Smooths `curvature.e_max` and `curvature.e_min` in place, keeping them consistent with
/// the stored directions.
///
/// # Errors
/// [`Error::InvalidInput`] for negative or non-finite options or factors of the wrong length;
/// [`Error::Solver`] if a factorisation fails or the iterative solver does not converge.
pub fn smooth_extremalities(
    mesh: &TriMesh,
    curvature: &mut Curvature,
    options: &ExtremalitySmoothing,
) -> Result<()> {
    if options.steps == 0 || mesh.num_faces() == 0 {
        return Ok(());
    }
    let smoother = ExtremalitySmoother::new(mesh, curvature, &*options.operator()?)?;
    run_steps(&smoother, curvature, options)
}

/// [`smooth_extremalities`] without diffusion across `creases` (per edge of
/// [`crate::mesh::Topology::edges`], true for a crease edge): every edge at a vertex on a
/// crease gets weight 0, so the two sides of a crease do not exchange values through it
/// (a crease vertex keeps its own, one-sided estimate).
///
/// # Errors
/// As [`smooth_extremalities`]; [`Error::InvalidInput`] when `creases` does not have one entry
/// per edge.
pub fn smooth_extremalities_split(
    mesh: &TriMesh,
    curvature: &mut Curvature,
    options: &ExtremalitySmoothing,
    creases: &[bool],
) -> Result<()> {
    if options.steps == 0 || mesh.num_faces() == 0 {
        return Ok(());
    }
    let smoother =
        ExtremalitySmoother::new_split(mesh, curvature, &*options.operator()?, Some(creases))?;
    run_steps(&smoother, curvature, options)
}

/// The steps of `options` on the extremalities, the second model's and the simulated noise
/// (all linear in the values, so smoothed alike), with twicing when asked.
fn run_steps(
    smoother: &ExtremalitySmoother<'_>,
    curvature: &mut Curvature,
    options: &ExtremalitySmoothing,
) -> Result<()> {
    let smooth = |a: &mut Vec<f64>, b: &mut Vec<f64>, tolerance: f64| -> Result<()> {
        smoother.steps_within(a, b, options.steps, tolerance)?;
        if options.twicing {
            // 2 S e − S (S e): the residual e − S e smoothed and added back.
            let (mut a2, mut b2) = (a.clone(), b.clone());
            smoother.steps_within(&mut a2, &mut b2, options.steps, tolerance)?;
            for (once, twice) in a.iter_mut().zip(&a2).chain(b.iter_mut().zip(&b2)) {
                *once = 2.0 * *once - twice;
            }
        }
        Ok(())
    };
    smooth(&mut curvature.e_max, &mut curvature.e_min, 0.0)?;
    // The second model's extremalities lie along the same directions: smoothed alike, so
    // that the crossings of the two are compared after the same steps.
    if curvature.has_alternative_extremalities() {
        let [a, b] = &mut curvature.alternative_extremalities;
        smooth(a, b, 0.0)?;
    }
    // Of the simulated noise only the median magnitude is read
    // ([`Curvature::set_simulated_noise`]): solved to [`NOISE_TOLERANCE`].
    if curvature.extremality_noise > 0.0 {
        let [mut a, mut b] = std::mem::take(&mut curvature.simulated_noise);
        smooth(&mut a, &mut b, NOISE_TOLERANCE)?;
        curvature.set_simulated_noise([a, b]);
    }
    if options.measure_drift {
        // What the smoothing, applied again, changes the smoothed fields by.
        let drift = |[a, b]: [&Vec<f64>; 2], tolerance: f64| -> Result<[Vec<f64>; 2]> {
            let (mut a2, mut b2) = (a.clone(), b.clone());
            smooth(&mut a2, &mut b2, tolerance)?;
            for (again, once) in a2.iter_mut().zip(a).chain(b2.iter_mut().zip(b)) {
                *again -= once;
            }
            Ok([a2, b2])
        };
        curvature.smoothing_drift = drift([&curvature.e_max, &curvature.e_min], DRIFT_TOLERANCE)?;
        curvature.smoothing_drift_noise = if curvature.extremality_noise > 0.0 {
            let [a, b] = &curvature.simulated_noise;
            drift([a, b], DRIFT_TOLERANCE)?
        } else {
            Default::default()
        };
    } else {
        curvature.smoothing_drift = Default::default();
        curvature.smoothing_drift_noise = Default::default();
    }
    Ok(())
}

/// The relative residual to which [`ExtremalitySmoothing::measure_drift`]'s steps are solved.
/// The drift is a correction, a few percent of the smoothed field where lines run: measured on
/// the public noisy bumps, ridge and ovoid, solving to 1e-3 instead of the solver's own 1e-5
/// changes it by 0.2 to 0.4% of its RMS and the corrected lines' points by at most 6e-5 model
/// units (igea 2e-5, of a diagonal of 0.16, when the drift was measured on scans too), for 40%
/// of its cost (igea's smoothing stage 0.41 → 0.65 s at 1e-5, 0.56 s at 1e-3).
pub const DRIFT_TOLERANCE: f64 = 1e-3;

/// The relative residual to which the steps on the simulated noise are solved (where the
/// solver's own tolerance is not looser). Its median magnitude is read, which moves by
/// about as much: measured on igea and horse ×16, the extremality noise moves by 1e-4 of
/// itself against the default 1e-5 and the lines' points stay the same, for 43 and 48% fewer
/// iterations on those fields (16 and 20% fewer in all). On white noise its slopes across
/// edges are read too ([`crate::lines::located`]): on `bumpy/noisy20k` the same 24 lines are
/// dropped at 1e-3 as at 1e-5 (the strengths of the others move in the fifth digit).
pub const NOISE_TOLERANCE: f64 = 1e-3;

/// The smoothing operator of both families, for repeated steps.
#[derive(Debug)]
pub struct ExtremalitySmoother<'m> {
    /// Both families' operator, or the max family's when they diffuse along their own lines.
    operator: DiffusionOperator<'m>,
    /// The min family's operator when it differs from the max family's.
    min_operator: Option<DiffusionOperator<'m>>,
}

impl<'m> ExtremalitySmoother<'m> {
    /// Builds the operator once (and factorises it, for [`LinearSolver::Cholesky`]).
    ///
    /// # Errors
    /// As [`smooth_extremalities`].
    pub fn new(
        mesh: &'m TriMesh,
        curvature: &Curvature,
        options: &ExtremalitySmoothing,
    ) -> Result<Self> {
        Self::new_split(mesh, curvature, options, None)
    }

    /// [`ExtremalitySmoother::new`] without diffusion across `creases` (see
    /// [`smooth_extremalities_split`]).
    ///
    /// # Errors
    /// As [`smooth_extremalities_split`].
    pub fn new_split(
        mesh: &'m TriMesh,
        curvature: &Curvature,
        options: &ExtremalitySmoothing,
        creases: Option<&[bool]>,
    ) -> Result<Self> {
        if !(options.time_step.is_finite() && options.time_step >= 0.0) {
            return Err(Error::InvalidInput(format!(
                "time step must be a non-negative number, got {}",
                options.time_step
            )));
        }
        if !(options.along_lines.is_finite() && options.along_lines > 0.0) {
            return Err(Error::InvalidInput(format!(
                "the diffusion along the lines must be a positive factor, got {}",
                options.along_lines
            )));
        }
        if !(options.crease_angle.is_finite() && options.crease_angle >= 0.0) {
            return Err(Error::InvalidInput(format!(
                "crease angle must be a non-negative number of radians, got {}",
                options.crease_angle
            )));
        }
        let n = mesh.num_vertices();
        if curvature.dir_max.len() != n || curvature.dir_min.len() != n {
            return Err(Error::InvalidInput(
                "curvature fields do not match the mesh".into(),
            ));
        }
        let factors = match &options.diffusion {
            Some(f) if f.len() != n || f.iter().any(|x| !(x.is_finite() && *x >= 0.0)) => {
                return Err(Error::InvalidInput(format!(
                    "diffusion factors: need {n} non-negative numbers, got {} values",
                    f.len()
                )));
            }
            other => other.as_deref(),
        };
        let edges = mesh.topology().edges();
        let on_crease = match creases {
            Some(flags) if flags.len() != edges.len() => {
                return Err(Error::InvalidInput(format!(
                    "crease flags: need one per edge ({}), got {}",
                    edges.len(),
                    flags.len()
                )));
            }
            Some(flags) => Some(mesh.topology().vertices_of_edges(flags)),
            None => None,
        };
        let (dir_max, dir_min) = (&curvature.dir_max, &curvature.dir_min);
        // Along their own lines each family has its weights: ridges run along dir_min.
        let (mut weights, mass, min_weights) = if options.along_lines == 1.0 {
            let (weights, mass) = cotan_weights_and_mass(mesh, mesh.positions());
            (weights, mass, None)
        } else {
            let (max, min) = rayon::join(
                || along_line_weights(mesh, dir_min, options.along_lines),
                || along_line_weights(mesh, dir_max, options.along_lines),
            );
            (max, lumped_mass(mesh, mesh.positions()), Some(min))
        };
        // The local factors and the crease attenuation, per edge.
        let scale = |w: &mut f64, [a, b]: [u32; 2]| {
            if let Some(f) = factors {
                *w *= 0.5 * (f[a as usize] + f[b as usize]);
            }
            if on_crease
                .as_ref()
                .is_some_and(|on| on[a as usize] || on[b as usize])
            {
                *w = 0.0;
            }
            if options.crease_angle > 0.0 && *w != 0.0 {
                *w /= crease_divisor(mesh, curvature, options.crease_angle, [a, b]);
            }
        };
        // One pass over the edges: the weights scaled and both families' signs
        // σ_pq = sign⟨dir(p), dir(q)⟩.
        let mut max_flips = vec![false; edges.len()];
        let mut min_flips = vec![false; edges.len()];
        weights
            .par_iter_mut()
            .zip(max_flips.par_iter_mut().zip(min_flips.par_iter_mut()))
            .zip(edges)
            .for_each(|((w, (max_flip, min_flip)), &[a, b])| {
                scale(w, [a, b]);
                let (a, b) = (a as usize, b as usize);
                *max_flip = dir_max[a].dot(&dir_max[b]) < 0.0;
                *min_flip = dir_min[a].dot(&dir_min[b]) < 0.0;
            });
        let h = mean_edge_length(mesh);
        let time = options.time_step * h * h;
        match min_weights {
            None => Ok(ExtremalitySmoother {
                operator: DiffusionOperator::new(
                    mesh,
                    weights,
                    mass,
                    time,
                    &[Some(&max_flips), Some(&min_flips)],
                    options.solver,
                )?,
                min_operator: None,
            }),
            Some(mut min_weights) => {
                min_weights
                    .par_iter_mut()
                    .zip(edges)
                    .for_each(|(w, &edge)| scale(w, edge));
                Ok(ExtremalitySmoother {
                    operator: DiffusionOperator::new(
                        mesh,
                        weights,
                        mass.clone(),
                        time,
                        &[Some(&max_flips)],
                        options.solver,
                    )?,
                    min_operator: Some(DiffusionOperator::new(
                        mesh,
                        min_weights,
                        mass,
                        time,
                        &[Some(&min_flips)],
                        options.solver,
                    )?),
                })
            }
        }
    }

    /// One implicit step of both families, in place. Returns the conjugate-gradient
    /// iterations (0 for Cholesky; the two families' sum when each has its operator).
    ///
    /// # Errors
    /// [`Error::InvalidInput`] when a field does not match the mesh; [`Error::Solver`] when
    /// conjugate gradients do not converge.
    pub fn step(&self, e_max: &mut [f64], e_min: &mut [f64]) -> Result<usize> {
        self.steps(e_max, e_min, 1)
    }

    /// `count` steps of both families, in place ([`ExtremalitySmoother::step`] repeated,
    /// sharing the solver's working memory). Returns the conjugate-gradient iterations.
    ///
    /// # Errors
    /// As [`ExtremalitySmoother::step`].
    pub fn steps(&self, e_max: &mut [f64], e_min: &mut [f64], count: usize) -> Result<usize> {
        self.steps_within(e_max, e_min, count, 0.0)
    }

    /// [`ExtremalitySmoother::steps`] solved to the relative residual `tolerance` where that
    /// is looser than the solver's own ([`DiffusionOperator::steps_within`]).
    ///
    /// # Errors
    /// As [`ExtremalitySmoother::step`].
    pub fn steps_within(
        &self,
        e_max: &mut [f64],
        e_min: &mut [f64],
        count: usize,
        tolerance: f64,
    ) -> Result<usize> {
        match &self.min_operator {
            None => self
                .operator
                .steps_within(&mut [e_max, e_min], count, tolerance),
            Some(min_operator) => {
                // The two families side by side.
                let (max, min) = rayon::join(
                    || self.operator.steps_within(&mut [e_max], count, tolerance),
                    || min_operator.steps_within(&mut [e_min], count, tolerance),
                );
                Ok(max? + min?)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes;
    use crate::smoothing::ConjugateGradientOptions;

    /// A synthetic field on a torus: directions along the tube circles, e a smooth function
    /// plus high-frequency noise.
    fn synthetic(mesh: &TriMesh) -> Curvature {
        let n = mesh.num_vertices();
        let mut c = Curvature {
            k_max: vec![1.0; n],
            k_min: vec![0.0; n],
            dir_max: Vec::with_capacity(n),
            dir_min: Vec::with_capacity(n),
            e_max: Vec::with_capacity(n),
            e_min: Vec::with_capacity(n),
            normals: vec![Vec3::z(); n],
            fallback_vertices: 0,
            extremality_noise: 0.0,
            simulated_noise: Default::default(),
            alternative_extremalities: Default::default(),
            one_sided: Vec::new(),
            smoothing_drift: Default::default(),
            smoothing_drift_noise: Default::default(),
            jet_fit: None,
        };
        for (i, p) in mesh.positions().iter().enumerate() {
            let around = Vec3::new(-p.y, p.x, 0.0).normalize();
            c.dir_min.push(around);
            c.dir_max.push(around.cross(&Vec3::z()));
            let noise = if i % 2 == 0 { 0.3 } else { -0.3 };
            c.e_max.push(p.x.sin() + noise);
            c.e_min.push(p.y.cos() - noise);
        }
        c
    }

    /// A flat square grid, directions along the axes, e_max a profile across x that bends
    /// (`u + 2u²`, u = x − 0.1: its zero at x = 0.1), plus alternating noise of `noise`.
    fn bent_profile(noise: f64) -> (TriMesh, Curvature) {
        let mesh = shapes::height_field(|_, _| 0.0, [-1.0, 1.0], [-1.0, 1.0], 40, 40);
        let n = mesh.num_vertices();
        let mut c = synthetic(&mesh);
        c.dir_max = vec![Vec3::x(); n];
        c.dir_min = vec![Vec3::y(); n];
        c.e_max = mesh
            .positions()
            .iter()
            .enumerate()
            .map(|(i, p)| {
                let u = p.x - 0.1;
                u + 2.0 * u * u + if i % 2 == 0 { noise } else { -noise }
            })
            .collect();
        c.e_min = vec![0.0; n];
        (mesh, c)
    }

    /// Where e_max crosses zero along the row y = 0, between x = −0.5 and 0.5.
    fn zero_on_the_middle_row(mesh: &TriMesh, e: &[f64]) -> f64 {
        let mut row = middle_row(mesh, e);
        row.retain(|(x, _)| x.abs() < 0.5);
        let k = row
            .windows(2)
            .position(|w| w[0].1 < 0.0 && w[1].1 >= 0.0)
            .unwrap();
        let ((x0, e0), (x1, e1)) = (row[k], row[k + 1]);
        x0 + (x1 - x0) * e0 / (e0 - e1)
    }

    /// The square [-1, 1]² of 40 × 40 cells in the plane z = 0, and its vertex nearest the
    /// origin.
    fn plane_and_centre(pattern: shapes::GridPattern) -> (TriMesh, usize) {
        let m = shapes::height_field_with(|_, _| 0.0, [-1.0, 1.0], [-1.0, 1.0], 40, 40, pattern);
        let centre = (0..m.num_vertices() as u32)
            .min_by(|&a, &b| m.position(a).norm().total_cmp(&m.position(b).norm()))
            .unwrap();
        (m, centre as usize)
    }

    /// Where the lines cross the triangles' edges at an angle, the diffusion across them stays
    /// HPW's (a face whose edges would need negative weights for the anisotropy diffuses as
    /// the cotan weights do), and along them it is never slower: a spike's second moment
    /// across the lines at factor 3 is that of factor 1, along them at least that.
    #[test]
    fn across_the_lines_the_spread_stays_hpws_at_any_angle() {
        for pattern in [
            shapes::GridPattern::Alternating,
            shapes::GridPattern::Uniform,
        ] {
            let (m, centre) = plane_and_centre(pattern);
            let nv = m.num_vertices();
            for degrees in [0.0_f64, 30.0, 45.0, 60.0, 90.0, 135.0] {
                let (sin, cos) = degrees.to_radians().sin_cos();
                // The ridges run along dir_min = s.
                let s = Vec3::new(cos, sin, 0.0);
                let mut c = synthetic(&m);
                c.k_max = vec![1.0; nv];
                c.dir_min = vec![s; nv];
                c.dir_max = vec![Vec3::new(-sin, cos, 0.0); nv];
                let spread = |along_lines: f64| {
                    let mut c = c.clone();
                    c.e_max = (0..nv)
                        .map(|i| if i == centre { 1.0 } else { 0.0 })
                        .collect();
                    c.e_min = c.e_max.clone();
                    let options = ExtremalitySmoothing {
                        twicing: false,
                        along_lines,
                        ..Default::default()
                    };
                    smooth_extremalities(&m, &mut c, &options).unwrap();
                    let (mut total, mut along, mut across) = (0.0, 0.0, 0.0);
                    for (e, p) in c.e_max.iter().zip(m.positions()) {
                        let d = p - m.position(centre as u32);
                        total += e;
                        along += e * d.dot(&s).powi(2);
                        across += e * (d.norm_squared() - d.dot(&s).powi(2));
                    }
                    (along / total, across / total)
                };
                let (along_1, across_1) = spread(1.0);
                let (along_3, across_3) = spread(3.0);
                let what = format!("{pattern:?} at {degrees}°");
                assert!(
                    (across_3 / across_1 - 1.0).abs() < 0.03,
                    "{what}: across {across_1} -> {across_3}"
                );
                assert!(
                    along_3 >= 0.99 * along_1,
                    "{what}: along {along_1} -> {along_3}"
                );
            }
        }
    }

    /// A unit spike diffuses `along_lines` times farther (in variance) along each family's
    /// lines than across: the ridges' field along the min directions (x), the valleys' along
    /// the max directions (y), whatever the directions' signs.
    #[test]
    fn spikes_spread_along_the_lines() {
        let (m, centre) = plane_and_centre(shapes::GridPattern::Alternating);
        let nv = m.num_vertices();
        let sign = |i: usize| if i % 3 == 0 { -1.0 } else { 1.0 };
        let mut c = synthetic(&m);
        c.k_max = vec![1.0; nv];
        c.dir_max = (0..nv).map(|i| Vec3::y() * sign(i)).collect();
        c.dir_min = (0..nv).map(|i| Vec3::x() * sign(i + 1)).collect();
        let spike = |i: usize| if i == centre { 1.0 } else { 0.0 };
        // Second moments along x and y of a field given along `signs`.
        let moments = |e: &[f64], signs: &dyn Fn(usize) -> f64| {
            let (mut total, mut xx, mut yy) = (0.0, 0.0, 0.0);
            for (i, p) in m.positions().iter().enumerate() {
                let v = e[i] * signs(i);
                total += v;
                xx += v * p.x * p.x;
                yy += v * p.y * p.y;
            }
            (xx / total, yy / total)
        };
        for along in [1.0, 3.0] {
            c.e_max = (0..nv).map(|i| spike(i) * sign(i)).collect();
            c.e_min = (0..nv).map(|i| spike(i) * sign(i + 1)).collect();
            let options = ExtremalitySmoothing {
                twicing: false,
                along_lines: along,
                ..Default::default()
            };
            smooth_extremalities(&m, &mut c, &options).unwrap();
            let (xx, yy) = moments(&c.e_max, &sign);
            assert!(
                (xx / yy / along - 1.0).abs() < 0.1,
                "ridges, {along}: {xx} along x, {yy} along y"
            );
            let (xx, yy) = moments(&c.e_min, &|i| sign(i + 1));
            assert!(
                (yy / xx / along - 1.0).abs() < 0.1,
                "valleys, {along}: {xx} along x, {yy} along y"
            );
        }
    }

    #[test]
    fn twicing_keeps_the_zero_where_it_is_and_removes_the_noise_as_well() {
        let spacing = 2.0 / 40.0;
        let smoothed = |noise: f64, twicing: bool| {
            let (mesh, mut c) = bent_profile(noise);
            let options = ExtremalitySmoothing {
                twicing,
                ..Default::default()
            };
            smooth_extremalities(&mesh, &mut c, &options).unwrap();
            (mesh, c.e_max)
        };
        let (mesh, plain) = smoothed(0.0, false);
        let (_, twiced) = smoothed(0.0, true);
        // Diffusion moves a bent profile's zero (by about time · Δe / |∇e|).
        let drift_plain = (zero_on_the_middle_row(&mesh, &plain) - 0.1).abs();
        let drift_twiced = (zero_on_the_middle_row(&mesh, &twiced) - 0.1).abs();
        assert!(drift_plain > 0.2 * spacing, "{drift_plain}");
        assert!(
            drift_twiced < 0.25 * drift_plain,
            "{drift_twiced} against {drift_plain}"
        );
        // The noise that is left is no more than plain smoothing leaves.
        let left = |with: &[f64], without: &[f64]| {
            let sum: f64 = with.iter().zip(without).map(|(a, b)| (a - b).powi(2)).sum();
            (sum / with.len() as f64).sqrt()
        };
        let plain_noise = left(&smoothed(0.3, false).1, &plain);
        let twiced_noise = left(&smoothed(0.3, true).1, &twiced);
        assert!(plain_noise < 0.3 * 0.5, "{plain_noise}");
        assert!(
            twiced_noise <= 1.1 * plain_noise,
            "{twiced_noise} against {plain_noise}"
        );
    }

    /// The vertices of the row y = 0 as (x, e), by x.
    fn middle_row(mesh: &TriMesh, e: &[f64]) -> Vec<(f64, f64)> {
        let mut row: Vec<(f64, f64)> = mesh
            .positions()
            .iter()
            .zip(e)
            .filter(|(p, _)| p.y.abs() < 1e-9)
            .map(|(p, &e)| (p.x, e))
            .collect();
        row.sort_by(|a, b| a.0.total_cmp(&b.0));
        row
    }

    /// e on the row y = 0 at x, linearly interpolated, and its slope there.
    fn on_the_middle_row(mesh: &TriMesh, e: &[f64], x: f64) -> (f64, f64) {
        let row = middle_row(mesh, e);
        let k = row.windows(2).position(|w| w[1].0 >= x).unwrap();
        let ((x0, e0), (x1, e1)) = (row[k], row[k + 1]);
        let slope = (e1 - e0) / (x1 - x0);
        (e0 + slope * (x - x0), slope)
    }

    /// Where the smoothed e_max crosses zero on the middle row, and where the measured drift
    /// puts the zero before smoothing (drift / slope further on).
    fn zero_moved_and_back(mesh: &TriMesh, c: &Curvature) -> (f64, f64) {
        let moved = zero_on_the_middle_row(mesh, &c.e_max);
        let (drift, _) = on_the_middle_row(mesh, &c.smoothing_drift[0], moved);
        let (_, slope) = on_the_middle_row(mesh, &c.e_max, moved);
        (moved, moved + drift / slope)
    }

    #[test]
    fn measured_drift_tells_how_far_the_smoothing_moved_the_zero() {
        // Profiles whose zero the smoothing moves: the bent one of `bent_profile` under
        // plain smoothing, and ones that bend (e = v + v² / 2, v = tanh(u / w)) under twicing,
        // whose first-order correction leaves part of the move. Applied to the smoothed
        // profile, whose bend the smoothing has already softened, the smoothing moves the zero
        // less than it moved the raw one's: where w is two spacings it finds about half the
        // move (measured: 0.1 → 0.0666, back to 0.0823); where w is ten spacings twicing moves
        // the zero a tenth of a spacing and the drift finds nearly all of it (the drift of
        // plain smoothing, twicing's first pass, would put it 0.4 spacings back).
        let spacing = 2.0 / 40.0;
        // (twicing, w, least move in spacings, share of the move left)
        let cases = [
            (false, None, 0.1, 0.1),
            (true, Some(2.0 * spacing), 0.1, 0.6),
            (true, Some(10.0 * spacing), 0.05, 0.25),
        ];
        let mut last = None;
        for (twicing, width, least, left) in cases {
            let (mesh, mut c) = bent_profile(0.0);
            if let Some(w) = width {
                for (e, p) in c.e_max.iter_mut().zip(mesh.positions()) {
                    let v = ((p.x - 0.1) / w).tanh();
                    *e = v + 0.5 * v * v;
                }
            }
            let options = ExtremalitySmoothing {
                twicing,
                measure_drift: true,
                ..Default::default()
            };
            smooth_extremalities(&mesh, &mut c, &options).unwrap();
            let (moved, back) = zero_moved_and_back(&mesh, &c);
            eprintln!("twicing {twicing}, w {width:?}: zero 0.1 -> {moved:.5}, back to {back:.5}");
            assert!((moved - 0.1).abs() > least * spacing, "{moved}");
            assert!(
                (back - 0.1).abs() < left * (moved - 0.1).abs(),
                "twicing {twicing}, w {width:?}: 0.1 -> {moved}, back to {back}"
            );
            last = Some((mesh, c, options));
        }
        let (mesh, mut c, options) = last.unwrap();
        // Measured only when asked, emptied otherwise (no stale drift), and for the simulated
        // noise where there is one.
        let n = mesh.num_vertices();
        assert!(c.smoothing_drift.iter().all(|d| d.len() == n));
        assert!(c.smoothing_drift_noise.iter().all(Vec::is_empty));
        smooth_extremalities(&mesh, &mut c, &ExtremalitySmoothing::default()).unwrap();
        assert!(c.smoothing_drift.iter().all(Vec::is_empty));
        c.set_simulated_noise([vec![0.1; n], vec![-0.1; n]]);
        smooth_extremalities(&mesh, &mut c, &options).unwrap();
        assert!(c.extremality_noise > 0.0);
        assert!(c.smoothing_drift_noise.iter().all(|d| d.len() == n));
    }

    #[test]
    fn several_steps_at_once_equal_single_steps() {
        let mesh = shapes::torus(3.0, 1.0, 40, 16);
        let base = synthetic(&mesh);
        for solver in [LinearSolver::DEFAULT, LinearSolver::Cholesky] {
            let options = ExtremalitySmoothing {
                solver,
                ..Default::default()
            };
            let smoother = ExtremalitySmoother::new(&mesh, &base, &options).unwrap();
            let (mut a, mut b) = (base.clone(), base.clone());
            let mut one_by_one = 0;
            for _ in 0..3 {
                one_by_one += smoother.step(&mut a.e_max, &mut a.e_min).unwrap();
            }
            let together = smoother.steps(&mut b.e_max, &mut b.e_min, 3).unwrap();
            assert_eq!(one_by_one, together);
            assert!(
                a.e_max
                    .iter()
                    .zip(&b.e_max)
                    .all(|(x, y)| x.to_bits() == y.to_bits())
            );
            assert!(
                a.e_min
                    .iter()
                    .zip(&b.e_min)
                    .all(|(x, y)| x.to_bits() == y.to_bits())
            );
            assert!(a.e_max.iter().zip(&base.e_max).any(|(x, y)| x != y));
        }
    }

    #[test]
    fn result_does_not_depend_on_the_initial_signs() {
        for solver in [LinearSolver::DEFAULT, LinearSolver::Cholesky] {
            signs_do_not_matter(solver);
        }
    }

    fn signs_do_not_matter(solver: LinearSolver) {
        let mesh = shapes::torus(3.0, 1.0, 40, 16);
        let base = synthetic(&mesh);
        let options = ExtremalitySmoothing {
            solver,
            ..Default::default()
        };
        let mut plain = base.clone();
        smooth_extremalities(&mesh, &mut plain, &options).unwrap();

        // Flip a pseudo-random subset of directions (and their extremalities).
        let mut flipped = base.clone();
        let flip: Vec<bool> = (0..mesh.num_vertices())
            .map(|i| (i * 7919 + 13) % 5 < 2)
            .collect();
        for (i, &f) in flip.iter().enumerate() {
            if f {
                flipped.dir_max[i] = -flipped.dir_max[i];
                flipped.e_max[i] = -flipped.e_max[i];
                flipped.dir_min[i] = -flipped.dir_min[i];
                flipped.e_min[i] = -flipped.e_min[i];
            }
        }
        smooth_extremalities(&mesh, &mut flipped, &options).unwrap();
        for (i, &f) in flip.iter().enumerate() {
            let s = if f { -1.0 } else { 1.0 };
            assert!((s * flipped.e_max[i] - plain.e_max[i]).abs() < 1e-9);
            assert!((s * flipped.e_min[i] - plain.e_min[i]).abs() < 1e-9);
        }
        // And smoothing did something: the alternating noise is damped.
        let roughness = |e: &[f64]| -> f64 {
            mesh.topology()
                .edges()
                .iter()
                .map(|&[a, b]| (e[a as usize] - e[b as usize]).powi(2))
                .sum()
        };
        assert!(roughness(&plain.e_max) < 0.2 * roughness(&base.e_max));
    }

    #[test]
    fn default_solver_agrees_with_cholesky() {
        // The default tolerance (relative residual per step) keeps the smoothed
        // extremalities within about that of the exact solves.
        let mesh = shapes::torus(3.0, 1.0, 40, 16);
        let base = synthetic(&mesh);
        let run = |solver| {
            let mut c = base.clone();
            let options = ExtremalitySmoothing {
                solver,
                ..Default::default()
            };
            smooth_extremalities(&mesh, &mut c, &options).unwrap();
            c
        };
        let (cg, exact) = (run(LinearSolver::DEFAULT), run(LinearSolver::Cholesky));
        for (x, y) in [(&cg.e_max, &exact.e_max), (&cg.e_min, &exact.e_min)] {
            let scale = y.iter().fold(0.0f64, |s, v| s.max(v.abs()));
            let worst = x
                .iter()
                .zip(y)
                .fold(0.0f64, |s, (a, b)| s.max((a - b).abs()));
            let tolerance = ConjugateGradientOptions::DEFAULT.tolerance;
            assert!(
                worst < 10.0 * tolerance * scale,
                "{worst:e} vs scale {scale}"
            );
        }
    }

    #[test]
    fn zero_factor_freezes_a_region() {
        let mesh = shapes::torus(3.0, 1.0, 40, 16);
        let base = synthetic(&mesh);
        let mask = DiffusionMask {
            regions: vec![MaskRegion::Box {
                min: Vec3::new(0.0, -10.0, -10.0),
                max: Vec3::new(10.0, 10.0, 10.0),
                factor: 0.0,
            }],
        };
        let factors = mask.factors(&mesh);
        // Plain smoothing keeps frozen values exactly; twicing combines two solves, each
        // exact there to the single precision of the default solver's updates.
        for (twicing, tolerance) in [(false, 1e-9), (true, 1e-6)] {
            let mut c = base.clone();
            let opts = ExtremalitySmoothing {
                diffusion: Some(factors.clone()),
                twicing,
                ..Default::default()
            };
            smooth_extremalities(&mesh, &mut c, &opts).unwrap();
            // Vertices whose whole ring is frozen keep their value.
            let topo = mesh.topology();
            let mut checked = 0;
            for v in 0..mesh.num_vertices() as u32 {
                if factors[v as usize] == 0.0
                    && topo.neighbors(v).all(|q| factors[q as usize] == 0.0)
                {
                    let (after, before) = (c.e_max[v as usize], base.e_max[v as usize]);
                    assert!((after - before).abs() < tolerance, "{after} {before}");
                    checked += 1;
                }
            }
            assert!(checked > 100);
            // Elsewhere values changed.
            let moved = (0..mesh.num_vertices())
                .filter(|&v| factors[v] == 1.0 && (c.e_max[v] - base.e_max[v]).abs() > 1e-3)
                .count();
            assert!(moved > 100);
        }
    }

    #[test]
    fn rejects_bad_options() {
        let mesh = shapes::torus(3.0, 1.0, 10, 6);
        let mut c = synthetic(&mesh);
        let bad = ExtremalitySmoothing {
            time_step: f64::NAN,
            ..Default::default()
        };
        assert!(smooth_extremalities(&mesh, &mut c, &bad).is_err());
        let bad = ExtremalitySmoothing {
            diffusion: Some(vec![1.0; 3]),
            ..Default::default()
        };
        assert!(smooth_extremalities(&mesh, &mut c, &bad).is_err());
    }
}
