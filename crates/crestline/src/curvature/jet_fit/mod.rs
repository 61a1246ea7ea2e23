//! Curvature, principal directions and extremalities from a polynomial fitted over a
//! geodesic disc: the osculating jets of Cazals and Pouget (*Estimating differential quantities
//! using polynomial fitting of osculating jets*, CAGD 22(2), 2005), with the neighbourhood and
//! the weights chosen by geometry rather than by the triangulation.
//!
//! **Why.** The papers' estimators read one star (HPW's shape operator) or a k-ring (YBS's
//! cubic fit). On irregular, marching-cubes and remeshed triangulations a star or a ring is a
//! lopsided, density-dependent sample of the surface: slivers and valence 3 to 13 put the
//! errors of k at tens of percent of max |k| and those of the extremalities (third
//! derivatives) far above the values themselves. A fit over a disc of fixed radius in which
//! every vertex counts in proportion to the area it stands for approximates an integral over
//! the disc, which does not depend on how the surface was sampled.
//!
//! **Steps**, per vertex p (in parallel):
//! 1. *Disc.* The vertices within Euclidean distance r of p that the mesh connects to p
//!    inside that ball (breadth-first over edges, so that a nearby sheet of another part is not
//!    taken); fewer than [`JetFitOptions::min_points`] → r grows by half, up to 4 times.
//! 2. *Weights.* `w_q = A_q (1 − |q − p|²/r²)²`, `A_q` the barycentric area of q (a third
//!    of its triangles' areas): the sum `Σ w_q f(q)` is a quadrature of `∫ K f dA`.
//! 3. *Fit.* In the tangent frame (x, y, n) of a first normal (the kernel-weighted area
//!    normals of the disc), the height of the samples is fitted by weighted least squares with
//!    a full bivariate polynomial of [`JetFitOptions::degree`] (3 or 4, constant and linear
//!    terms included: the vertex itself need not lie on the surface, as in scans).
//!    Coordinates are divided by r, so the normal equations are well scaled at every size.
//!    The fit's normal at the origin becomes the frame of a second fit, whose gradient at the
//!    origin is then zero to the fit's accuracy.
//!
//!    *Curved heights.* The heights of a sphere or a circular cylinder over its tangent
//!    plane are a series that converges only within its radius of curvature, slowly near
//!    it: on a disc not much smaller than that radius (a torus's tube under the wide discs
//!    of a noisy mesh, a coarse mesh) the polynomial's truncation is a bias of the
//!    extremalities (the noisy public torus kept a ridge of T = 1.6 around it, the CAD
//!    exports' tubes a bias of e of one sign). The second fit is also made of the curved
//!    heights `z + (c/2) z²`, c the dominant principal curvature (a sphere's curved heights
//!    are a quadratic), and the one of the two that leaves the smaller residual is kept
//!    (`Fit::curved`; on white noise the curved heights, below). The other stays as a
//!    second model of the surface ([`Curvature::alternative_extremalities`]): a crossing of
//!    e it does not have is not a crest. Measured (`score_fields.py`, public cases, mean e
//!    RMS): 0.020 → 0.013, the coarse torus `ring/reg5k` k 0.68% → 0.06% of max |k|, e
//!    0.088 → 0.025.
//!
//!    *On white noise the curved heights are kept wherever they are made*, whatever the
//!    residuals say ([`JetFitReport::white_noise`]: the public noisy cases, scans made
//!    alike, noisy CAD parts; of the shared meshes only the teapot, whose faceting passes
//!    for it). There the two residuals differ by the noise more than by the surface, and
//!    the choice was the noise's (an ellipsoid took the curved heights at 98% of its
//!    vertices clean and at 50% with noise of 0.1 spacings, the two choices agreeing at
//!    50.5% of them): the extremalities were a random mix of two models whose biases
//!    differ. On a torus, where e is zero and the equators are planes of symmetry, the
//!    mix's bias changed sign on the outer equator: six (YBS seven) of sixteen noisy tori
//!    made like the public one kept a ridge of 0.8 to 1.4 diagonals around it, none now
//!    (`tests/suite/quality_cases.rs`). Of the two models, the curved heights are exact on
//!    spheres and tubes, where the heights' series fails first, and under the wide discs of
//!    noisy meshes their zeros lie at least as close to the crests (the clean public meshes
//!    fitted with such a disc: the bumps' lines F1 0.846 against 0.821 with the heights,
//!    0.840 with the choice by residual; the others equal). Their sphere need reach over
//!    the disc only to within twice the noise (`1 + 2cP ≥ −4|c|σ` at every sample, P within
//!    2σ of the sphere's rim): where the disc is as wide as a tube (thin tubes, strong
//!    noise) the noise at its rim failed the exact test nearly everywhere and left the
//!    heights (tori of tube 0.2 under noise of 0.1 edges, the public one under 0.2: ridges
//!    of 0.7 to 2.6 diagonals along their outer side, none now; the teapot's faceting: the
//!    line along its spout), while a disc across a crease, whose other side turns away far
//!    beyond the noise, still fails it (a noisy part's edges traced as crest lines where
//!    the crease finder gives up: without the test at all, the noisy pipe elbow's F1 0.649
//!    → 0.190). The heights stay the second model. Clean meshes, CAD exports and scans
//!    whose residual is mostly surface keep the choice by residual. What it costs on noisy
//!    surfaces made alike: ellipsoids' lines wander a little more (F1 up to 0.03 lower;
//!    their heights' e is the steeper across the crests, 12% above the exact slope, which
//!    the same noise moves less), and a valley on the located filter's threshold
//!    (`lines::located`) falls under it on one noisy ridge (0.12). Measured in
//!    BENCHMARKS.md, *The fit's model on white noise*.
//! 4. *Differential quantities* of the second fit's graph h at the origin: with n outward, a
//!    convex surface has h ≈ −x²/(2ρ), so the Weingarten matrix is `W = −Hess h` (the metric
//!    is the identity to second order where the gradient vanishes). Its eigen-pairs are the
//!    principal curvatures and directions; the extremality along a principal direction t is
//!    `e = −D³h[t, t, t]` (the derivative of the eigenvalue of `−Hess h` along t; see
//!    [`crate::curvature::cubic_fit`](mod@crate::curvature::cubic_fit), step 5).
//!
//! **Degree.** Quartic on clean surfaces. On noisy ones the second fit blends the cubic and
//! the quartic of the same samples by their expected errors (`Blend`): the quartic's
//! Hessian is not biased by the surface's fourth-order terms, the cubic's carries less of
//! the noise. The weight weighs the cubic's bias, measured over a probe of the mesh, against
//! each disc's own extra noise, computed exactly. Measured (median quartic weight): the
//! noisy public cases (noise 0.1 spacings) 0 to 0.52; the noisy torus, whose tube is little
//! wider than the disc, 0.96; scans, whose "noise" of hundredths of a spacing is mostly the
//! truncation error of their sampling, and a CAD export taken for noisy, 0.99 to 1, less
//! only where a disc is one-sided (boundaries, creases). (The blend is of the heights' fits;
//! the curved heights of step 3 are made from the blended fit.)
//!
//! **Scale.** r is [`JetFitOptions::radius`] times the mesh's sample spacing
//! `h = sqrt(2 A / (√3 V))` (A the area, V the vertices in use): the edge length of a regular
//! triangulation with that density. Unlike the mean edge length, it is not changed by slivers
//! or by the long thin triangles of CAD fans. With [`JetFitOptions::adapt_to_noise`] the
//! radius grows with the noise level the fits themselves measure (see [`noise_radius`]).
//!
//! **Accuracy** (`bench/quality/run.sh`, `score_fields.py`, tables in `BENCHMARKS.md`): on the
//! public irregular and marching-cubes cases k is within a few percent of max |k| where the
//! papers' estimators are 15 to 50% off.
//!
//! **Fallbacks** (counted in [`Curvature::fallback_vertices`], never NaN): too few points for
//! the degree → the next lower degree (2: e = 0); fewer than three points or a singular
//! system → zero curvature in an arbitrary tangent frame.

mod polynomial;
mod surface;

use std::cell::RefCell;

use rayon::prelude::*;

use super::{Curvature, VertexEstimate, collect_estimates, tangent_frame};
use crate::error::{Error, Result};
use crate::mesh::{TriMesh, Vec3};
use polynomial::{Fit, solve};
use surface::{Scaled, SurfacePoint};

/// The largest [`JetFitOptions::radius`], in sample spacings: four times the default. A disc
/// gathers about 3.6 r² vertices and the time grows faster still (horse, 48k vertices: 1.3 s
/// at 2.5, 41 s at 10, 5 min at 20), while a disc wider than the features blurs them all; a
/// radius beyond the mesh (1e6) ran for minutes and found no lines. The noise adaptation
/// ([`noise_radius`]) still grows the radius given on noisy meshes.
pub const MAX_RADIUS: f64 = 10.0;

/// Options of [`jet_fit()`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JetFitOptions {
    /// Radius of the fitting disc, in units of the mesh's sample spacing (see the module
    /// docs). Larger radii average more (less noise, more blur of small features). Must be
    /// above 0 and at most [`MAX_RADIUS`].
    ///
    /// Default: 2.5.
    pub radius: f64,
    /// Degree of the fitted polynomial: 3 (cubic) or 4 (quartic). The quartic's second and
    /// third derivatives are not biased by the fourth-order terms of the surface: on the
    /// public clean cases of `../shared/quality` the worst RMS error of k is 0.3% of max |k|
    /// with quartics and 1.7% with cubics (`bench/quality/run.sh`, with the curved heights of
    /// the module docs; 0.8% and 7.7% without). Its five more
    /// coefficients carry more noise, though: when [`JetFitOptions::adapt_to_noise`] finds
    /// the surface noisy, 4 blends cubic and quartic by their expected errors, bias and
    /// noise together (measured on the mesh; see the module docs, *Degree*). 3 is cubic
    /// everywhere.
    ///
    /// Default: 4.
    pub degree: usize,
    /// Minimal number of vertices in a disc; smaller discs grow (boundary corners, coarse
    /// regions of adaptive meshes).
    ///
    /// Default: 24.
    pub min_points: usize,
    /// Grow the radius with the noise the fits' residuals measure: on white noise with its
    /// standard deviation ([`noise_radius`]), elsewhere with the residual itself. Clean meshes
    /// are not affected. (On white noise the fit keeps the curved heights, module docs step
    /// 3, with or without it.)
    ///
    /// Default: `true`.
    pub adapt_to_noise: bool,
}

impl JetFitOptions {
    /// The default options (see each field).
    pub const DEFAULT: Self = JetFitOptions {
        radius: 2.5,
        degree: 4,
        min_points: 24,
        adapt_to_noise: true,
    };

    /// Sets [`JetFitOptions::radius`].
    pub fn with_radius(mut self, radius: f64) -> Self {
        self.radius = radius;
        self
    }

    /// Sets [`JetFitOptions::degree`].
    pub fn with_degree(mut self, degree: usize) -> Self {
        self.degree = degree;
        self
    }

    /// Sets [`JetFitOptions::adapt_to_noise`].
    pub fn with_adapt_to_noise(mut self, adapt: bool) -> Self {
        self.adapt_to_noise = adapt;
        self
    }

    fn validate(&self) -> Result<()> {
        if !(self.radius.is_finite() && self.radius > 0.0 && self.radius <= MAX_RADIUS) {
            return Err(Error::InvalidInput(format!(
                "jet-fit radius must be above 0 and at most {MAX_RADIUS} (in sample spacings; \
                 larger discs blur every feature and take minutes), got {}",
                self.radius
            )));
        }
        if !(3..=4).contains(&self.degree) {
            return Err(Error::InvalidInput(format!(
                "jet-fit degree must be 3 or 4, got {}",
                self.degree
            )));
        }
        Ok(())
    }
}

impl Default for JetFitOptions {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// What [`jet_fit_report`] measured besides the fields.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JetFitReport {
    /// The mesh's sample spacing h (model units).
    pub spacing: f64,
    /// The fitting radius used, in units of h.
    pub radius: f64,
    /// Noise level: the median over vertices of the fits' weighted RMS residual, in units of
    /// h (below [`REFERENCE_NOISE`] on clean meshes, which keep the base radius). A residual
    /// of a fit with 15 coefficients is smaller than the noise that makes it, by a share that
    /// depends on the triangulation (see `sigma`). The radius is chosen by it where the noise
    /// is not white (scans, CAD exports: [`noise_radius`]).
    pub noise: f64,
    /// The standard deviation of the noise, in units of h: the median over the probe of the
    /// per-disc ratios of the fit's residual to the residual that white noise of unit standard
    /// deviation leaves in expectation (`Σ w − Σ w² mᵀ M⁻¹ m` of the weighted sum of squares: the
    /// fit takes up part of the noise). A median of square roots, it reads a little low: 0.095 to
    /// 0.098 for noise of 0.1 spacings, alike on regular and irregular meshes. On the public noisy
    /// cases, made with noise of 0.1 times the mean edge, it measures 0.096 to 0.118 where `noise`
    /// measures 0.075 to 0.090. On white noise the radius is chosen by it ([`noise_radius`]); it
    /// scales the simulated noise ([`crate::curvature::Curvature::extremality_noise`]) and weighs
    /// the quartic's extra noise.
    pub sigma: f64,
    /// The weight of the quartic against the cubic in the fits (see
    /// [`JetFitOptions::degree`]): 1 for quartics, 0 for cubics; on noisy meshes its median
    /// over the noise probe's vertices.
    pub quartic_weight: f64,
    /// On noisy meshes, the noise's standard deviation measured over discs of 5 sample
    /// spacings divided by the one measured over discs of 2.5 (the default radius; both on
    /// the same 2,000 or so probe vertices, whatever radius the fit itself uses): about 1 when
    /// the residual is white noise, which a wider fit leaves as it is, and more when part of
    /// it is surface the polynomial cannot follow, which grows with the disc
    /// ([`JetFitReport::white_noise`]). 0 where the fit found no noise (not measured).
    pub noise_growth: f64,
    /// Vertices whose disc was sampled on the mesh's triangles rather than at its vertices
    /// (long thin triangles: CAD fans and strips; see the module docs of
    /// `curvature/jet_fit/surface.rs`): slower, and measuring no noise (0 on scans and on
    /// regular, irregular and marching-cubes meshes).
    pub triangle_sampled: usize,
}

impl JetFitReport {
    /// Whether the measured noise is white noise: the fits' residual does not change when
    /// the disc doubles ([`JetFitReport::noise_growth`] within a factor
    /// [`WHITE_NOISE_GROWTH`] of 1).
    /// The simulated noise ([`Curvature::simulated_noise`]) is white noise of the measured
    /// level, so it describes the estimation noise of the extremalities only then; on
    /// scans and coarse models whose residual is mostly their sampling of the surface it
    /// overstates it (see [`crate::lines::located`]). On white noise the fit also keeps the
    /// curved heights wherever it makes them (module docs, step 3).
    pub fn white_noise(&self) -> bool {
        is_white_noise(self.noise_growth)
    }

    /// Whether the residual may as well be the fit's truncation error on a coarse clean mesh
    /// as the detail of a scan: measured (above [`REFERENCE_NOISE`]), not white, and below
    /// [`AMBIGUOUS_NOISE`]. Such a mesh is smoothed as a scan; the CLI says so, since on a
    /// clean mesh whose features are a few edges across the smoothing blurs them.
    pub fn may_be_truncation_error(&self) -> bool {
        self.noise > REFERENCE_NOISE && !self.white_noise() && self.noise < AMBIGUOUS_NOISE
    }
}

/// The residual (in sample spacings, [`JetFitReport::noise`]) below which a residual that is
/// not white may be either of two things nothing measured here tells apart
/// ([`JetFitReport::may_be_truncation_error`]). The truncation error of coarse clean meshes
/// whose features are two to four spacings across: 0.0005 to 0.0018 (a crater, elliptic bumps
/// on a sphere and an x⁶ superquadric of 5K faces, `bench/quality`), which the extremality
/// smoothing blurs (F1 0.908 and 0.484 smoothed, 1.000 and 0.927 not). And the detail a
/// subdivided scan carries: 0.0005 to 0.0026 (`crestline subdivide` of Igea, the horse and
/// Spot, one or two levels), which the smoothing is needed for (Igea ×4 unsmoothed: 62 → 96
/// diagonals of short lines across the face). Their noise growth overlaps too (3.5 against
/// 3.9 at the closest). Scans as given and faceted CAD exports measure 0.0057 and more.
/// Measured in BENCHMARKS.md, "Measured and not taken: coarse clean meshes left unsmoothed".
pub const AMBIGUOUS_NOISE: f64 = 0.003;

/// [`JetFitReport::white_noise`] for a [`JetFitReport::noise_growth`] of `growth`.
fn is_white_noise(growth: f64) -> bool {
    growth > 0.0 && (1.0 / WHITE_NOISE_GROWTH..=WHITE_NOISE_GROWTH).contains(&growth)
}

/// [`JetFitReport::white_noise`]'s bound on the change of the measured noise when the disc
/// doubles, either way. White noise leaves a residual that does not depend on the disc (the
/// noise estimate divides out what the fit takes up), while the truncation error of a
/// surface the polynomial does not follow grows with a power of the radius. Measured
/// (`crestline extract --stats`): the five public noisy cases and 46 made alike (0.05 to
/// 0.1 spacings of noise) 1.01 to 1.05; the shared meshes the fit finds noisy 1.39
/// (beetle), 1.59 (suzanne), 2.1 (horse, the bunny), 2.5 (igea), 3.2 (cow), 4.9 to 7.0
/// (spot, homer, the rocker arm); the teapot's faceting 1.01. The probes' radii are fixed
/// ([`JetFitReport::noise_growth`]): at the radius a user gives, discs of 1 and 2 spacings
/// are both grown to the fewest points a fit needs and read the same (the cow 1.05, the
/// horse 0.86).
pub const WHITE_NOISE_GROWTH: f64 = 1.1;

/// What the noise probe measured ([`Context::probe_noise`], model units).
struct NoiseProbe {
    /// The median weighted RMS residual of the fits ([`JetFitReport::noise`]).
    residual: f64,
    /// The standard deviation of the noise ([`JetFitReport::sigma`]).
    sigma: f64,
}

/// Curvature fields of `mesh` by jet fitting over geodesic discs (see the module docs).
///
/// # Errors
/// [`Error::InvalidInput`] for options out of range.
pub fn jet_fit(mesh: &TriMesh, options: &JetFitOptions) -> Result<Curvature> {
    jet_fit_report(mesh, options).map(|(c, _)| c)
}

/// [`jet_fit()`], also returning the spacing, the radius used and the measured noise level.
///
/// # Errors
/// As [`jet_fit()`].
pub fn jet_fit_report(
    mesh: &TriMesh,
    options: &JetFitOptions,
) -> Result<(Curvature, JetFitReport)> {
    jet_fit_split(mesh, options, None)
}

/// [`jet_fit_report`] with the discs split at `creases` (per edge of
/// [`crate::mesh::Topology::edges`], true for a crease; see the module docs, *Creases*).
///
/// # Errors
/// As [`jet_fit()`]; [`Error::InvalidInput`] when `creases` does not have one entry per edge.
pub fn jet_fit_split(
    mesh: &TriMesh,
    options: &JetFitOptions,
    creases: Option<&[bool]>,
) -> Result<(Curvature, JetFitReport)> {
    options.validate()?;
    let split = match creases {
        Some(edges) => Some(Split::new(mesh, edges)?),
        None => None,
    };
    let arrays = MeshArrays::new(mesh);
    let context = arrays.context(mesh, options, split.as_ref().filter(|s| s.any));
    let spacing = context.spacing;
    let probe = context.probe_noise(options.radius, PROBE_SAMPLES);
    let noise = probe.residual / spacing.max(f64::MIN_POSITIVE);
    let sigma = probe.sigma / spacing.max(f64::MIN_POSITIVE);
    let noisy = options.adapt_to_noise && noise > REFERENCE_NOISE;
    // White noise leaves the same residual over a wider disc; the surface's own truncation
    // error grows with it (`JetFitReport::white_noise`). At the default radius and twice it,
    // whatever radius the fit uses.
    let noise_growth = if noise > REFERENCE_NOISE {
        let narrow = JetFitOptions::DEFAULT.radius;
        let [narrow, wide] = [narrow, 2.0 * narrow]
            .map(|radius| context.probe_noise(radius, GROWTH_PROBE_SAMPLES).sigma);
        if narrow > 0.0 && wide.is_finite() {
            wide / narrow
        } else {
            0.0
        }
    } else {
        0.0
    };
    // By the noise's standard deviation where the noise is white; elsewhere (scans, CAD
    // exports) the residual is mostly surface the polynomial does not follow, of which the
    // fit takes up another share than of white noise, and the residual itself is the level.
    let radius = if !noisy {
        options.radius
    } else if is_white_noise(noise_growth) {
        noise_radius(options.radius, sigma)
    } else {
        widened(options.radius, noise / REFERENCE_NOISE)
    };
    // On noise the first fit, which only gives the frame, is cubic; the second blends the
    // cubic and the quartic by their expected errors (see `Blend`).
    let (blend, quartic_weight) = if noisy && options.degree == 4 {
        let (bias, weight) = context.cubic_bias(radius, probe.sigma);
        let blend = Blend {
            bias,
            sigma: probe.sigma,
        };
        (Some(blend), weight)
    } else {
        (None, if options.degree == 4 { 1.0 } else { 0.0 })
    };
    let fit_options = JetFitOptions {
        degree: if noisy { 3 } else { options.degree },
        ..*options
    };
    let context = Context {
        options: &fit_options,
        blend,
        keep_curved: is_white_noise(noise_growth).then_some(probe.sigma),
        ..context
    };
    let (mut curvature, mut simulated, alternative, triangle_sampled) = context.run(radius);
    curvature.alternative_extremalities = alternative;
    // The boundary's one-sided discs only: with the creases' too, the noise level and the
    // located filter, which read these flags, lost lines on noisy parts (BENCHMARKS.md,
    // "Lines beside creases left where the fit put them").
    curvature.one_sided = one_sided_vertices(mesh, radius * spacing, None);
    if noise > REFERENCE_NOISE {
        for x in simulated.iter_mut().flatten() {
            *x *= probe.sigma;
        }
        curvature.set_simulated_noise(simulated);
    }
    let report = JetFitReport {
        spacing,
        radius,
        noise,
        sigma,
        quartic_weight,
        noise_growth,
        triangle_sampled,
    };
    curvature.jet_fit = Some(report);
    Ok((curvature, report))
}

/// The fits' residual (in sample spacings, [`JetFitReport::noise`]) above which a mesh counts as
/// noisy and its disc widens ([`noise_radius`]: on white noise by the noise's standard deviation,
/// which on a mesh just above this level can leave the base radius; elsewhere by the residual).
/// Clean meshes measure below it: their residual is the quartic probe's truncation error (below
/// 0.0003 spacings on the public clean cases, bumps of 3 to 4 spacings included), and they keep the
/// base radius and report no noise. Truncation error is not told from noise here; the curved
/// heights (module docs, step 3) leave less of it on tubes: the coarsest public torus
/// (`ring/reg5k`) measured 0.0013 with the heights alone and was fitted as a noisy mesh, now it is
/// taken for clean. A coarser one (64 × 20 samples) still measures 0.0015 and gets a disc of 3.3
/// spacings (5.6 before), where the blend of cubic and quartic (module docs, *Degree*) finds the
/// cubic's bias far above the noise and fits quartics.
pub const REFERENCE_NOISE: f64 = 0.0005;

/// The noise's standard deviation (in sample spacings) that the fitting radius is referred
/// to ([`noise_radius`]): [`REFERENCE_NOISE`], a residual, on the scale of the standard
/// deviation. A fit's residual is the noise less what the fit takes up, 1/1.26 to 1/1.34 of
/// it on the regular public noisy meshes (`JetFitReport::sigma` over `noise`; 1/1.24 on the
/// regular height fields of `bench/quality/height_fields.py`, 1/1.48 on one) and 1/1.48 to
/// 1/1.56 on irregular ones made alike (`bench/quality/noisy_cases.py`), whose unequal
/// weights leave fewer samples in effect; at 1.3 times [`REFERENCE_NOISE`] the regular meshes
/// keep the radii they had when the radius was chosen by the residual.
pub const REFERENCE_SIGMA: f64 = 1.3 * REFERENCE_NOISE;

/// The radius (in sample spacings) for white noise of standard deviation σ (in sample
/// spacings, [`JetFitReport::sigma`]; until 2026-11-28 the argument was the residual,
/// [`JetFitReport::noise`], referred to [`REFERENCE_NOISE`], which now gives discs about 6%
/// narrower on regular meshes). The third derivatives of a least-squares fit over a disc of
/// radius ρ with ~ρ² samples carry noise of about σ / ρ⁴ (in units of 1/h²): the radius
/// `base (σ / σ_ref)^¼` keeps it at the level of a fit of radius `base` with noise σ_ref =
/// [`REFERENCE_SIGMA`]. With scan-like noise of 0.1 spacings the radius is about 3.5 times
/// the base (measured on the noisy public cases: smaller radii leave lines of noise, larger
/// ones blur bumps of a few spacings).
///
/// *Why σ and not the residual* (which chose the radius until 2026-11-28): the residual is
/// the noise less what the fit takes up, and the fit takes up more where the weights are
/// unequal (irregular meshes), so the same noise gave smaller discs there, whose
/// extremalities are noisier still (fewer samples in effect): 8.4 to 8.6 spacings on
/// irregular meshes with noise of 0.1 mean edges, 8.7 to 9.0 on regular ones. σ divides the
/// part the fit takes up out. Measured (HPW, `bench/quality/noisy_cases.py`, 20 irregular
/// meshes with noise of 0.1 mean edges): mean F1 0.872 → 0.890, none lower by more than
/// 0.001; the regular sets within 0.001.
///
/// *White noise only* ([`JetFitReport::white_noise`]). The share the fit takes up is that of
/// white noise; where the residual is mostly surface the polynomial does not follow (scans,
/// CAD exports) it is another, and σ overstates the level: on the export of a pocket plate
/// (`tests/data/cad`, fans of long thin triangles) σ read 2.4 times the residual and the
/// disc grew from 5.3 to 6.2 spacings, which traced two valleys on its flat faces. There the
/// residual stays the level, as before: `base (noise / REFERENCE_NOISE)^¼`.
pub fn noise_radius(base: f64, sigma: f64) -> f64 {
    widened(base, sigma / REFERENCE_SIGMA)
}

/// `base` times the fourth root of `ratio`, a noise level over its reference, when above 1.
fn widened(base: f64, ratio: f64) -> f64 {
    if ratio.is_finite() && ratio > 1.0 {
        base * ratio.powf(0.25)
    } else {
        base
    }
}

/// The sample spacing of a mesh: `sqrt(2 A / (√3 V))`, the edge length of a regular
/// triangulation with the same number of vertices per area (V counts the vertices that belong
/// to a triangle). Zero for a mesh without area.
pub fn sample_spacing(mesh: &TriMesh) -> f64 {
    let area: f64 = crate::mesh::face_areas(mesh).iter().sum();
    let topo = mesh.topology();
    let used = (0..mesh.num_vertices() as u32)
        .filter(|&v| !topo.vertex_faces(v).is_empty())
        .count();
    if used == 0 || area <= 0.0 {
        return 0.0;
    }
    (2.0 * area / (3f64.sqrt() * used as f64)).sqrt()
}

/// Where discs stop: the positions of the mesh's boundary vertices and of the vertices of the
/// `barriers` (per edge of [`crate::mesh::Topology::edges`]: the creases and non-manifold
/// edges the fit does not reach across, [`jet_fit_split`]).
pub fn disc_rims(mesh: &TriMesh, barriers: Option<&[bool]>) -> Vec<Vec3> {
    let topo = mesh.topology();
    let on_barrier = barriers.map_or_else(Vec::new, |edges| topo.vertices_of_edges(edges));
    (0..mesh.num_vertices() as u32)
        .filter(|&v| topo.is_boundary_vertex(v) || on_barrier.get(v as usize) == Some(&true))
        .map(|v| mesh.position(v))
        .collect()
}

/// Per vertex, whether a disc of `radius` (model units) around it reaches a boundary vertex
/// of the mesh or a vertex of the `barriers` ([`disc_rims`]): its fit is one-sided, with
/// another bias and more noise than a full disc's (beside a crease the fit stops at the
/// crease as it does at a boundary: on a noisy part's flat face the spread of e_min grew
/// fifteenfold towards a crease, the rounded box of `bench/quality/noisy_parts.py` under
/// noise of 0.05 of the mean edge). Empty when the mesh has neither (no vertex is).
pub fn one_sided_vertices(mesh: &TriMesh, radius: f64, barriers: Option<&[bool]>) -> Vec<bool> {
    let boundary = disc_rims(mesh, barriers);
    if boundary.is_empty() || !(radius.is_finite() && radius > 0.0) {
        return Vec::new();
    }
    let grid = crate::spatial::PointGrid::new(&boundary, radius);
    mesh.positions()
        .par_iter()
        .map(|&q| grid.nearest_within(q, radius).is_some())
        .collect()
}

/// Barycentric vertex areas: a third of the areas of each vertex's triangles.
pub fn vertex_areas(mesh: &TriMesh) -> Vec<f64> {
    let faces = crate::mesh::face_areas(mesh);
    crate::mesh::star_areas(mesh, &faces)
        .into_iter()
        .map(|a| a / 3.0)
        .collect()
}

fn median(values: &mut [f64]) -> f64 {
    if values.is_empty() {
        return 0.0;
    }
    let mid = values.len() / 2;
    values.select_nth_unstable_by(mid, f64::total_cmp);
    values[mid]
}

/// Per vertex, its neighbours in [`crate::mesh::Topology::vertex_edges`] order, in compressed
/// rows: the disc search reads them for every vertex of every disc, and looking each edge's
/// ends up in the topology cost about a tenth of the fit's time. The edges themselves are
/// read (from the topology, in the same order) only with creases: without them the search
/// reads 4 bytes per neighbour.
struct Neighbours {
    offsets: Vec<usize>,
    vertices: Vec<u32>,
}

impl Neighbours {
    fn new(mesh: &TriMesh) -> Self {
        let topo = mesh.topology();
        let n = mesh.num_vertices();
        let mut offsets = Vec::with_capacity(n + 1);
        let mut vertices = Vec::new();
        offsets.push(0);
        for a in 0..n as u32 {
            vertices.extend(topo.neighbors(a));
            offsets.push(vertices.len());
        }
        Neighbours { offsets, vertices }
    }

    /// The neighbours of `v`, the k-th across the k-th of its edges
    /// ([`crate::mesh::Topology::vertex_edges`]).
    fn of(&self, v: u32) -> &[u32] {
        &self.vertices[self.offsets[v as usize]..self.offsets[v as usize + 1]]
    }
}

/// About how many vertices the noise probe fits.
const PROBE_SAMPLES: usize = 20_000;

/// About how many vertices the probes of the noise's growth fit
/// ([`JetFitReport::noise_growth`]), the same at both radii (the wider disc holds four
/// times the samples). The median of the ratio needs far fewer than the level: its standard
/// error is a few thousandths here, where white noise and surface differ by 0.3 or more.
const GROWTH_PROBE_SAMPLES: usize = 2_000;

/// Per vertex, a pseudo-random key that depends on where the vertex is on the shape, not on
/// its index nor on the pose of the model: a hash of its valence and of its distance to the
/// centroid in units of the RMS distance, rounded to 2⁻¹². The noise probe fits the vertices
/// whose key is a multiple of its stride and the simulated noise is drawn from it, so that
/// reordering, turning, moving or scaling the mesh gives the same sample, the same radius and
/// the same noise level. The bins are coarse because one vertex more or less in the probe
/// moves the median, and with it every fit: moving a model of size 0.1 by 10⁴ leaves its
/// coordinates 10⁻¹¹ of its size off, which then crosses a bin about once in 10⁷ vertices.
fn probe_keys(mesh: &TriMesh) -> Vec<u64> {
    let positions = mesh.positions();
    let n = positions.len().max(1) as f64;
    let centroid = positions.iter().fold(Vec3::zeros(), |acc, p| acc + p) / n;
    let rms = (positions
        .iter()
        .map(|p| (p - centroid).norm_squared())
        .sum::<f64>()
        / n)
        .sqrt();
    let unit = if rms > 0.0 && rms.is_finite() {
        rms
    } else {
        1.0
    };
    let topo = mesh.topology();
    positions
        .iter()
        .enumerate()
        .map(|(v, p)| {
            let bin = ((p - centroid).norm() / unit * (1u64 << 12) as f64) as u64;
            let valence = topo.degree(v as u32) as u64;
            splitmix64(bin ^ splitmix64(valence))
        })
        .collect()
}

/// The splitmix64 finaliser: a well-mixed 64-bit hash of `z`.
fn splitmix64(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// What the fit of one vertex gives.
struct VertexFit {
    estimate: VertexEstimate,
    /// The fit's weighted RMS residual (model units) and the standard deviation of noise
    /// that would leave it (the residual over the one white noise of unit deviation leaves,
    /// `Fit::noise_residual`); both NaN on a fallback and on triangle samples.
    residual: [f64; 2],
    /// The extremalities of the fit to the simulated noise (0 on a fallback).
    noise: [f64; 2],
    /// The other model's extremalities along the estimate's directions (the estimate's own
    /// where there is none; [`Curvature::alternative_extremalities`]).
    alternative: [f64; 2],
    /// Whether the estimate is of a disc sampled on the triangles ([`surface`]).
    on_triangles: bool,
}

/// The per-vertex arrays a [`Context`] reads, made once per mesh.
struct MeshArrays {
    spacing: f64,
    areas: Vec<f64>,
    normals: Vec<Vec3>,
    keys: Vec<u64>,
    neighbours: Neighbours,
}

impl MeshArrays {
    fn new(mesh: &TriMesh) -> Self {
        MeshArrays {
            spacing: sample_spacing(mesh),
            areas: vertex_areas(mesh),
            normals: crate::mesh::vertex_normals_area(mesh),
            keys: probe_keys(mesh),
            neighbours: Neighbours::new(mesh),
        }
    }

    /// The context of fits with `options` (no residual, no blend; discs split at `split`).
    fn context<'a>(
        &'a self,
        mesh: &'a TriMesh,
        options: &'a JetFitOptions,
        split: Option<&'a Split<'a>>,
    ) -> Context<'a> {
        Context {
            mesh,
            areas: &self.areas,
            normals: &self.normals,
            spacing: self.spacing,
            options,
            split,
            residual: false,
            keys: &self.keys,
            neighbours: &self.neighbours,
            blend: None,
            keep_curved: None,
        }
    }
}

/// Everything a vertex's fit reads.
#[derive(Clone, Copy)]
struct Context<'a> {
    mesh: &'a TriMesh,
    areas: &'a [f64],
    normals: &'a [Vec3],
    spacing: f64,
    options: &'a JetFitOptions,
    /// Crease edges the discs do not cross; `None` when there are none.
    split: Option<&'a Split<'a>>,
    /// Whether the fits measure their residual (the noise probe; a second pass over the disc).
    residual: bool,
    /// Per vertex, its key ([`probe_keys`]).
    keys: &'a [u64],
    /// Per vertex, its neighbours and the edges to them.
    neighbours: &'a Neighbours,
    /// On noisy meshes: how the second fit blends cubic and quartic.
    blend: Option<Blend>,
    /// On white noise, the noise's standard deviation (model units): the curved heights are
    /// kept wherever they are made, not chosen by their residual (module docs, step 3).
    keep_curved: Option<f64>,
}

/// The blend of cubic and quartic in the second fit on noisy meshes. Both fits are
/// least-squares estimates from the same samples, the cubic nested in the quartic: the
/// quartic's Hessian H₄ is not biased by the surface's fourth-order terms and the cubic's
/// H₃ is, by b, while `H₄ − H₃` carries extra noise of variance ΔV, uncorrelated with H₃.
/// `H₃ + λ (H₄ − H₃)` has expected squared error `(1 − λ)² b² + var₃ + λ² ΔV`, least at
/// `λ = b² / (b² + ΔV)`. ΔV is computed exactly for each disc
/// ([`polynomial::Nested::extra_variance`]): large where the disc is one-sided (at
/// boundaries and creases, where the quartic extrapolates) and on small discs. b² is the
/// mesh's mean, measured by [`Context::cubic_bias`].
#[derive(Debug, Clone, Copy)]
struct Blend {
    /// b²: the mean squared bias of the cubic's Hessian (model units, 1/length²).
    bias: f64,
    /// The standard deviation of the noise (model units).
    sigma: f64,
}

impl Blend {
    /// λ for a disc of radius `r` whose fits' Hessians differ by extra noise variance
    /// `extra_variance` under unit noise (coefficient units).
    fn quartic_weight(&self, extra_variance: f64, r: f64) -> f64 {
        // Coefficients are in units of r, heights divided by r: the noise of the heights
        // is σ / r and the Hessian in model units is the coefficients' over r.
        let variance = extra_variance * (self.sigma / (r * r)).powi(2);
        if self.bias > 0.0 && variance.is_finite() {
            self.bias / (self.bias + variance)
        } else {
            0.0
        }
    }
}

/// Crease edges, the vertices on them and the widest side of each
/// ([`crate::mesh::widest_side`], found once: a disc that grows gathers it again).
struct Split<'a> {
    edges: &'a [bool],
    vertices: Vec<bool>,
    any: bool,
    /// The faces of vertex v's widest side are `side_faces[side_offsets[v]..side_offsets[v + 1]]`
    /// (none for a vertex off the creases; both empty without creases).
    side_offsets: Vec<u32>,
    side_faces: Vec<u32>,
}

impl<'a> Split<'a> {
    fn new(mesh: &TriMesh, edges: &'a [bool]) -> Result<Self> {
        let topo = mesh.topology();
        if edges.len() != topo.num_edges() {
            return Err(Error::InvalidInput(format!(
                "crease flags: need one per edge ({}), got {}",
                topo.num_edges(),
                edges.len()
            )));
        }
        let mut vertices = vec![false; mesh.num_vertices()];
        for (&[a, b], _) in topo.edges().iter().zip(edges).filter(|(_, c)| **c) {
            vertices[a as usize] = true;
            vertices[b as usize] = true;
        }
        let any = edges.iter().any(|&c| c);
        let (mut side_offsets, mut side_faces) = (Vec::new(), Vec::new());
        if any {
            let on_creases: Vec<u32> = (0..mesh.num_vertices() as u32)
                .filter(|&v| vertices[v as usize])
                .collect();
            let sides: Vec<Vec<u32>> = on_creases
                .par_iter()
                .map(|&v| crate::mesh::widest_side(mesh, v, edges))
                .collect();
            side_offsets = vec![0u32; mesh.num_vertices() + 1];
            let mut sides = on_creases.iter().zip(&sides).peekable();
            for v in 0..mesh.num_vertices() {
                let mut end = side_offsets[v];
                if let Some((_, side)) = sides.next_if(|(c, _)| **c as usize == v) {
                    side_faces.extend_from_slice(side);
                    end = side_faces.len() as u32;
                }
                side_offsets[v + 1] = end;
            }
        }
        Ok(Split {
            edges,
            vertices,
            any,
            side_offsets,
            side_faces,
        })
    }

    /// The faces of the widest side of crease vertex `v` ([`crate::mesh::widest_side`]).
    fn widest_side(&self, v: u32) -> &[u32] {
        let v = v as usize;
        &self.side_faces[self.side_offsets[v] as usize..self.side_offsets[v + 1] as usize]
    }
}

/// A sample in the fitting frame, divided by the radius, with its weight.
#[derive(Debug, Clone, Copy)]
struct Sample {
    x: f64,
    y: f64,
    z: f64,
    w: f64,
    /// The simulated noise of this sample's height (see [`simulated_noise`]).
    xi: f64,
}

/// Per-thread scratch: breadth-first marks and the disc.
#[derive(Default)]
struct Scratch {
    /// A byte per vertex ([`next_stamp`]).
    marks: Vec<u8>,
    stamp: u8,
    disc: Vec<u32>,
    /// The points the fit samples: the disc's vertices, or pieces of its triangles.
    points: Vec<SurfacePoint>,
    /// The points relative to the centre, scaled ([`Context::scale_points`]).
    scaled: Vec<Scaled>,
    samples: Vec<Sample>,
    /// Triangles of a disc sampled on its triangles ([`surface`]), with their own marks.
    faces: Vec<u32>,
    face_marks: Vec<u8>,
    face_stamp: u8,
    /// With creases: the area normal of the side of the disc's centre that the disc covers.
    side_normal: Vec3,
}

thread_local! {
    static SCRATCH: RefCell<Scratch> = RefCell::new(Scratch::default());
}

/// A fresh stamp for `marks` (resized to `n` entries), so that no entry equals it: the marks
/// of a breadth-first search are cleared by moving to the next stamp, and all of them every
/// 255 searches. A byte each: the searches read the marks of scattered vertices, which then
/// take a quarter of the cache that 32-bit stamps did.
fn next_stamp(marks: &mut Vec<u8>, stamp: &mut u8, n: usize) -> u8 {
    if marks.len() != n {
        *marks = vec![0; n];
        *stamp = 0;
    }
    *stamp = stamp.wrapping_add(1);
    if *stamp == 0 {
        marks.fill(0);
        *stamp = 1;
    }
    *stamp
}

impl Context<'_> {
    /// The vertices the probes fit: those whose key ([`probe_keys`]) is a multiple of a
    /// stride that leaves about `samples` of them.
    fn probe_vertices(&self, samples: usize) -> impl ParallelIterator<Item = u32> + '_ {
        let n = self.mesh.num_vertices();
        let stride = n.div_ceil(samples.max(1)).max(1) as u64;
        (0..n as u32)
            .into_par_iter()
            .filter(move |&v| self.keys[v as usize] % stride == 0)
    }

    /// The noise level of the surface: quartic fits with radius `radius` (in spacings) at
    /// about `samples` vertices spread over the mesh ([`PROBE_SAMPLES`] for the level the
    /// radius is chosen by). A quartic's residual on a smooth surface is its truncation
    /// error, orders of magnitude below any noise a scanner leaves.
    fn probe_noise(&self, radius: f64, samples: usize) -> NoiseProbe {
        let quartic = JetFitOptions {
            degree: 4,
            ..*self.options
        };
        let probe = Context {
            options: &quartic,
            residual: true,
            keep_curved: None,
            ..*self
        };
        let residuals: Vec<[f64; 2]> = self
            .probe_vertices(samples)
            .map(|v| {
                SCRATCH.with(|s| {
                    probe
                        .fit_vertex(v, radius * self.spacing, &mut s.borrow_mut())
                        .residual
                })
            })
            .filter(|r| r.iter().all(|x| x.is_finite()))
            .collect();
        let [residual, sigma] =
            [0, 1].map(|k| median(&mut residuals.iter().map(|r| r[k]).collect::<Vec<_>>()));
        NoiseProbe { residual, sigma }
    }

    /// The mean squared bias b² of the cubic's Hessian at radius `radius` (in spacings) on a
    /// surface with noise of standard deviation `sigma` (model units), and the median
    /// quartic weight ([`Blend`]) at the probe's vertices. At each, the cubic and the
    /// quartic are fitted to the same samples; as the fits are nested,
    /// `E|H₃ − H₄|² = b² + ΔV`, so the mean of `|H₃ − H₄|² − σ² ΔV` over the probe
    /// estimates b² (clamped at 0: no bias measured, cubics).
    fn cubic_bias(&self, radius: f64, sigma: f64) -> (f64, f64) {
        let probes: Vec<[f64; 3]> = self
            .probe_vertices(PROBE_SAMPLES)
            .filter_map(|v| {
                SCRATCH.with(|s| self.fit_both(v, radius * self.spacing, &mut s.borrow_mut()))
            })
            .filter(|probe| probe.iter().all(|x| x.is_finite()))
            .collect();
        let count = probes.len().max(1) as f64;
        let bias = (probes
            .iter()
            .map(|[d, dv, r]| d - dv * (sigma / (r * r)).powi(2))
            .sum::<f64>()
            / count)
            .max(0.0);
        let blend = Blend { bias, sigma };
        let mut weights: Vec<f64> = probes
            .iter()
            .map(|&[_, dv, r]| blend.quartic_weight(dv, r))
            .collect();
        (bias, median(&mut weights))
    }

    /// At vertex `v`: the squared (Frobenius) norm of the difference between the cubic's and
    /// the quartic's Hessians (model units) of one disc's samples (radius `radius`, model
    /// units), the variance of that difference under unit noise
    /// ([`polynomial::Nested::extra_variance`]) and the disc's radius. `None` where either
    /// fit fails or is ill-posed, or where the disc is sampled on triangles (the chord
    /// error of flat pieces is neither noise nor surface).
    fn fit_both(&self, v: u32, radius: f64, s: &mut Scratch) -> Option<[f64; 3]> {
        if self.mesh.topology().vertex_faces(v).is_empty() {
            return None;
        }
        let r = self.grow_disc(v, radius, s);
        if self.needs_triangle_samples(v, r, s) {
            return None;
        }
        let p = self.mesh.position(v);
        let normal = self.vertex_samples(p, r, s).try_normalize(1e-300)?;
        self.scale_points(p, r, s);
        self.frame_samples(normal, s);
        if s.samples.len() < 20 {
            return None;
        }
        let nested = polynomial::solve_nested(&s.samples)?;
        if nested.quartic.conditioning < ILL_POSED {
            return None;
        }
        let (h3, h4) = (nested.cubic.hessian(r), nested.quartic.hessian(r));
        let d = [h3[0] - h4[0], h3[1] - h4[1], h3[2] - h4[2]];
        let squared = d[0] * d[0] + 2.0 * d[1] * d[1] + d[2] * d[2];
        Some([squared, nested.extra_variance, r])
    }

    /// Fits every vertex with radius `radius` (in spacings); returns the fields, the
    /// extremalities the fits make of simulated white noise of unit standard deviation in
    /// the heights ([`simulated_noise`]) and the other model's extremalities
    /// ([`Curvature::alternative_extremalities`]).
    fn run(&self, radius: f64) -> (Curvature, [Vec<f64>; 2], [Vec<f64>; 2], usize) {
        let n = self.mesh.num_vertices();
        // Each part of the fits into its own array as they are made (one pass; an array of
        // whole `VertexFit`s is 168 bytes per vertex to fault in and read back).
        type Parts = (
            Vec<VertexEstimate>,
            ((Vec<f64>, Vec<f64>), ((Vec<f64>, Vec<f64>), Vec<bool>)),
        );
        let (estimates, ((noise_max, noise_min), ((other_max, other_min), on_triangles))): Parts =
            (0..n as u32)
                .into_par_iter()
                .map(|v| {
                    let fit = SCRATCH
                        .with(|s| self.fit_vertex(v, radius * self.spacing, &mut s.borrow_mut()));
                    // A fallback (or a sanitised estimate) has no second model: its own e.
                    let estimate = fit.estimate.sanitized();
                    let [other_max, other_min] = if estimate.fallback {
                        [estimate.e_max, estimate.e_min]
                    } else {
                        fit.alternative
                    };
                    let [noise_max, noise_min] = fit.noise;
                    (
                        estimate,
                        (
                            (noise_max, noise_min),
                            ((other_max, other_min), fit.on_triangles),
                        ),
                    )
                })
                .unzip();
        let on_triangles = on_triangles.par_iter().filter(|&&t| t).count();
        let (curvature, _) = collect_estimates(n, || (), |_, v| estimates[v as usize]);
        (
            curvature,
            [noise_max, noise_min],
            [other_max, other_min],
            on_triangles,
        )
    }

    /// The fit of vertex `v` ([`VertexFit`]).
    fn fit_vertex(&self, v: u32, radius: f64, s: &mut Scratch) -> VertexFit {
        let fallback = |normal| VertexFit {
            estimate: VertexEstimate::fallback(normal),
            residual: [f64::NAN; 2],
            noise: [0.0; 2],
            alternative: [0.0; 2],
            on_triangles: false,
        };
        let topo = self.mesh.topology();
        if topo.vertex_faces(v).is_empty() || radius.is_nan() || radius <= 0.0 {
            return fallback(Vec3::zeros());
        }
        let grown = self.grow_disc(v, radius, s);
        let mut on_triangles = self.needs_triangle_samples(v, grown, s);
        // A probe of the noise reads only the residual, which a disc sampled on its triangles
        // does not have (below): its fits are not made.
        if on_triangles && self.residual {
            return fallback(self.normals[v as usize]);
        }
        let p = self.mesh.position(v);
        let Some((mut n0, mut first, mut r)) =
            self.first_fit(v, p, [radius, grown], on_triangles, s)
        else {
            return fallback(self.normals[v as usize]);
        };
        // Vertices on too few rows for the polynomial across them (triangles several times
        // longer than wide): the surface between the rows is in the triangles.
        if !on_triangles
            && first
                .as_ref()
                .is_none_or(|fit| fit.conditioning < ILL_POSED)
        {
            on_triangles = true;
            if self.residual {
                return fallback(self.normals[v as usize]);
            }
            let Some(refit) = self.first_fit(v, p, [radius, grown], on_triangles, s) else {
                return fallback(self.normals[v as usize]);
            };
            (n0, first, r) = refit;
        }
        let Some(first) = first else {
            return fallback(n0);
        };
        // The fitted surface's normal at the origin: ∝ (−h_x, −h_y, 1) in the frame.
        let (u, w, _) = tangent_frame(n0);
        let n1 = (n0 - u * first.coef[1] - w * first.coef[2])
            .try_normalize(1e-300)
            .unwrap_or(n0);
        // Pieces of flat triangles are off a curved surface by the chord error, not by noise:
        // no residual measured there.
        let residual = self.residual && !on_triangles;
        // The same points as the first fit's (`first_fit` scaled them), in another frame.
        let Some(second) = self.fit_in_frame::<3>(n1, r, s, self.blend, residual) else {
            return fallback(n1);
        };
        let (second, other) = if on_triangles {
            (second, None)
        } else {
            second.curved(&s.samples, self.keep_curved.map(|sigma| sigma / r))
        };
        let (estimate, noise, alternative) = second.estimate(n1, r, other.as_ref());
        // Pieces of flat triangles are off a curved surface by the chord error, not by noise.
        let residual = if on_triangles {
            [f64::NAN; 2]
        } else {
            [
                second.residual * r,
                second.residual / second.noise_residual * r,
            ]
        };
        VertexFit {
            estimate,
            residual,
            noise,
            alternative,
            on_triangles,
        }
    }

    /// Gathers the disc of `v` with radius `radius` (model units), grown by half up to four
    /// times while it has fewer than [`JetFitOptions::min_points`] vertices; returns the
    /// radius of the disc gathered.
    fn grow_disc(&self, v: u32, radius: f64, s: &mut Scratch) -> f64 {
        let mut r = radius;
        for grown in 0..=MAX_GROWTH {
            self.gather_disc(v, r, s);
            if s.disc.len() >= self.options.min_points || grown == MAX_GROWTH {
                break;
            }
            r *= 1.5;
        }
        r
    }

    /// Samples the disc (at its vertices, with the radius `grown` of [`Self::grow_disc`], or
    /// on its triangles, [`Self::sample_triangle_disc`]) and fits it in the frame of the
    /// samples' kernel-weighted area normal: that normal, the fit of the heights alone
    /// (`None` when it cannot be solved) and the radius sampled; `None` when the normal
    /// vanishes.
    fn first_fit(
        &self,
        v: u32,
        p: Vec3,
        [radius, grown]: [f64; 2],
        on_triangles: bool,
        s: &mut Scratch,
    ) -> Option<(Vec3, Option<Fit>, f64)> {
        let (normal, r) = if on_triangles {
            self.sample_triangle_disc(v, radius, grown, s)
        } else {
            (self.vertex_samples(p, grown, s), grown)
        };
        let n0 = normal.try_normalize(1e-300)?;
        self.scale_points(p, r, s);
        // Only its coefficients are read: no residual, no other right-hand side.
        Some((n0, self.fit_in_frame::<1>(n0, r, s, None, false), r))
    }

    /// Puts the disc's vertices into `s.points` and returns the first normal: the
    /// kernel-weighted area normals of the disc. With creases, the normals of vertices on a
    /// crease mix both sides: the side's faces at the centre stand for them.
    fn vertex_samples(&self, p: Vec3, r: f64, s: &mut Scratch) -> Vec3 {
        let mut n0 = s.side_normal;
        s.points.clear();
        for &q in &s.disc {
            s.points.push(SurfacePoint {
                position: self.mesh.position(q),
                area: self.areas[q as usize],
                noise: simulated_noise(self.keys[q as usize]),
            });
            if self.split.is_some_and(|split| split.vertices[q as usize]) {
                continue;
            }
            let d2 = (self.mesh.position(q) - p).norm_squared() / (r * r);
            n0 += self.normals[q as usize] * self.areas[q as usize] * kernel(d2);
        }
        n0
    }

    /// Breadth-first from `v` over edges, keeping the vertices inside the ball of radius `r`.
    /// With creases the search neither crosses a crease edge nor goes on from a vertex on a
    /// crease (it is a sample of both sides, the end of the disc); a disc centred on a crease
    /// covers one side of it, the widest at v.
    fn gather_disc(&self, v: u32, r: f64, s: &mut Scratch) {
        let stamp = next_stamp(&mut s.marks, &mut s.stamp, self.mesh.num_vertices());
        let p = self.mesh.position(v);
        let r2 = r * r;
        s.disc.clear();
        s.disc.push(v);
        s.marks[v as usize] = stamp;
        s.side_normal = Vec3::zeros();
        let mut head = 0;
        if let Some(split) = self.split
            && split.vertices[v as usize]
        {
            self.seed_side(v, split, r2, s);
            head = 1;
        }
        let (marks, disc, positions) = (&mut s.marks, &mut s.disc, self.mesh.positions());
        while head < disc.len() {
            let a = disc[head];
            head += 1;
            if let Some(split) = self.split
                && split.vertices[a as usize]
                && a != v
            {
                continue;
            }
            let mut visit = |b: u32| {
                if marks[b as usize] != stamp {
                    marks[b as usize] = stamp;
                    if (positions[b as usize] - p).norm_squared() < r2 {
                        disc.push(b);
                    }
                }
            };
            let near = self.neighbours.of(a);
            match self.split {
                None => near.iter().for_each(|&b| visit(b)),
                Some(split) => {
                    let edges = self.mesh.topology().vertex_edges(a);
                    for (&b, &e) in near.iter().zip(edges) {
                        if !split.edges[e as usize] {
                            visit(b);
                        }
                    }
                }
            }
        }
    }

    /// Puts into the disc the vertices (within `r2` of v, squared) of the widest side of
    /// crease vertex `v` ([`crate::mesh::widest_side`]). Sets the side's area normal.
    fn seed_side(&self, v: u32, split: &Split<'_>, r2: f64, s: &mut Scratch) {
        let p = self.mesh.position(v);
        let stamp = s.stamp;
        for &f in split.widest_side(v) {
            let [a, b, c] = self.mesh.triangle(f as usize);
            s.side_normal += (b - a).cross(&(c - a)) / 6.0;
            for q in self.mesh.faces()[f as usize] {
                if s.marks[q as usize] != stamp && (self.mesh.position(q) - p).norm_squared() < r2 {
                    s.marks[q as usize] = stamp;
                    s.disc.push(q);
                }
            }
        }
    }

    /// The points of the disc (`s.points`) relative to `p`, divided by `r`, with their
    /// weights (`s.scaled`): what the samples of every frame share (the first fit and the
    /// second, in another frame, sample the same points).
    fn scale_points(&self, p: Vec3, r: f64, s: &mut Scratch) {
        s.scaled.clear();
        s.scaled
            .extend(s.points.iter().filter_map(|q| q.scaled(p, r)));
    }

    /// The scaled points of the disc (`s.scaled`, [`Self::scale_points`]) as samples in the
    /// tangent frame of `normal` (`s.samples`).
    fn frame_samples(&self, normal: Vec3, s: &mut Scratch) {
        let (u, w, n) = tangent_frame(normal);
        let frame = [u, w, n];
        s.samples.clear();
        s.samples.extend(s.scaled.iter().map(|q| q.sample(frame)));
    }

    /// Weighted least-squares fit of the disc's heights over the tangent plane of `normal`:
    /// the points as [`Self::scale_points`] left them, scaled by `r`.
    /// With `blend`, a blend of cubic and quartic ([`Blend`]) where the disc carries both.
    /// The residual is measured only when `residual` (the blend never measures it). `K` is
    /// 3 for a fit of the simulated noise and the squared heights too, 1 for the heights'
    /// coefficients alone ([`solve`]; without a blend).
    fn fit_in_frame<const K: usize>(
        &self,
        normal: Vec3,
        r: f64,
        s: &mut Scratch,
        blend: Option<Blend>,
        residual: bool,
    ) -> Option<Fit> {
        self.frame_samples(normal, s);
        let count = s.samples.len();
        if let Some(blend) = blend
            && count >= 20
            && let Some(nested) = polynomial::solve_nested(&s.samples)
        {
            let lambda = blend.quartic_weight(nested.extra_variance, r);
            return Some(Fit::blend(nested.cubic, nested.quartic, lambda));
        }
        // Degree by what the disc can carry: 15, 10 and 6 coefficients, with some surplus;
        // a lower one when the normal equations cannot be factored.
        let mut fit = None;
        if count >= 20 && self.options.degree >= 4 {
            fit = solve::<15, K>(&s.samples, 4, residual);
        }
        if fit.is_none() && count >= 13 {
            fit = solve::<10, K>(&s.samples, 3, residual);
        }
        if fit.is_none() && count >= 7 {
            fit = solve::<6, K>(&s.samples, 2, residual);
        }
        fit
    }
}

/// How many times a disc grows by half, at most, for want of vertices ([`Context::grow_disc`]).
/// (Until 2026-11-27 the radius grew once more after the last gather: the fit then weighed
/// the disc of 1.5⁴ radii with the kernel of 1.5⁵.)
const MAX_GROWTH: usize = 4;

/// [`polynomial::Fit::conditioning`] below which a disc sampled at its vertices is sampled
/// on its triangles instead.
const ILL_POSED: f64 = 1e-8;

/// The smooth compact kernel `(1 − d²)²` on the unit disc (`d2` = d²).
fn kernel(d2: f64) -> f64 {
    if d2 < 1.0 {
        let t = 1.0 - d2;
        t * t
    } else {
        0.0
    }
}

/// Simulated white noise of unit standard deviation in the height of the vertex with key
/// `key` ([`probe_keys`]): the same value in every disc that contains the vertex, so that the
/// fits turn it into noise of the extremalities with the spatial correlation real noise gets
/// (uniform on [−√3, √3]; keyed by position, so that reordering the mesh does not change it).
/// Vertices that share a key (same valence, same distance bin: a few per bin on large meshes,
/// spread over the shape) draw the same value.
pub(crate) fn simulated_noise(key: u64) -> f64 {
    let unit = (splitmix64(key ^ 0x5851_F42D_4C95_7F2D) >> 11) as f64 / (1u64 << 53) as f64;
    3f64.sqrt() * (2.0 * unit - 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes;

    #[test]
    fn sphere_has_curvature_one_over_radius_and_zero_extremality() {
        let mesh = shapes::icosphere(2.0, 4);
        let c = jet_fit(&mesh, &JetFitOptions::DEFAULT).unwrap();
        for v in 0..c.len() {
            assert!((c.k_max[v] - 0.5).abs() < 1e-3, "k_max {}", c.k_max[v]);
            assert!((c.k_min[v] - 0.5).abs() < 1e-3, "k_min {}", c.k_min[v]);
            assert!(c.e_max[v].abs() < 1e-2 && c.e_min[v].abs() < 1e-2);
        }
        assert_eq!(c.fallback_vertices, 0);
    }

    #[test]
    fn a_disc_short_of_vertices_is_weighed_at_the_radius_it_was_gathered_at() {
        // An octahedron has 6 vertices, fewer than a disc wants (24): every disc grows to its
        // largest and stays short. The radius returned is the one gathered, and the disc holds
        // exactly the vertices within it.
        let mesh = shapes::octahedron();
        let arrays = MeshArrays::new(&mesh);
        let context = arrays.context(&mesh, &JetFitOptions::DEFAULT, None);
        let mut s = Scratch::default();
        // A radius whose largest growth (1.5⁴ ≈ 5.06 times) reaches the four neighbours of a
        // vertex (at √2) but not the opposite one (at 2), and the next growth would.
        let radius = 1.6 / 1.5f64.powi(4);
        let r = context.grow_disc(0, radius, &mut s);
        let largest = (0..MAX_GROWTH).fold(radius, |r, _| r * 1.5);
        assert_eq!(r, largest);
        let p = mesh.position(0);
        let mut inside: Vec<u32> = (0..6)
            .filter(|&q| (mesh.position(q) - p).norm() < r)
            .collect();
        let mut disc = s.disc.clone();
        disc.sort_unstable();
        inside.sort_unstable();
        assert_eq!(disc, inside);
        assert_eq!(disc.len(), 5);
    }

    #[test]
    fn the_widest_sides_found_once_are_those_of_each_crease_vertex() {
        // A cube of bulging faces: creases along its edges, corners where three meet.
        let (mesh, _) = shapes::pillow_box(1.0, 0.2, 6);
        let angles = crate::lines::crease::dihedral_angles(&mesh);
        let edges: Vec<bool> = angles.iter().map(|&a| a > 0.5).collect();
        let split = Split::new(&mesh, &edges).unwrap();
        assert!(split.any);
        let mut on_creases = 0;
        for v in 0..mesh.num_vertices() as u32 {
            if split.vertices[v as usize] {
                on_creases += 1;
                assert_eq!(
                    split.widest_side(v),
                    crate::mesh::widest_side(&mesh, v, &edges)
                );
                assert!(!split.widest_side(v).is_empty());
            } else {
                assert!(split.widest_side(v).is_empty());
            }
        }
        assert!(on_creases > 0);
    }

    #[test]
    fn strips_of_long_triangles_are_sampled_on_the_triangles() {
        // An open cylinder as a CAD exporter writes it: one strip of triangles as long as the
        // cylinder, every vertex on one of the two rims. Sampled at the vertices, each disc
        // is a row along a rim and the fit is singular across it (k_min was 0.15, |e| 1e5).
        let strip = shapes::cylinder(1.0, 4.0, 128, 1);
        check_unit_cylinder(&strip);
        // The report counts them: every vertex here, none on a well-shaped sphere.
        let (_, report) = jet_fit_report(&strip, &JetFitOptions::DEFAULT).unwrap();
        assert_eq!(report.triangle_sampled, strip.num_vertices());
        let sphere = shapes::icosphere(1.0, 3);
        let (_, report) = jet_fit_report(&sphere, &JetFitOptions::DEFAULT).unwrap();
        assert_eq!(report.triangle_sampled, 0);
    }

    #[test]
    fn anisotropic_triangles_are_fitted_as_well_as_isotropic_ones() {
        // 12 rows of triangles 7 times longer than wide: at the fitting radius the next row is
        // at the rim of the disc (k_min was -1089 before strips were sampled on triangles, and
        // up to 0.21 at the open rims, where a disc holds two rows, before ill-posed fits
        // were sampled on triangles too).
        check_unit_cylinder(&shapes::cylinder(1.0, 4.0, 128, 12));
    }

    /// k_max within 0.03 of 1, |k_min| below 0.03 and |e| below 0.1 at every vertex.
    fn check_unit_cylinder(mesh: &TriMesh) {
        let c = jet_fit(mesh, &JetFitOptions::DEFAULT).unwrap();
        assert_eq!(c.fallback_vertices, 0);
        for v in 0..c.len() {
            assert!(
                (c.k_max[v] - 1.0).abs() < 0.03,
                "k_max {} at {v}",
                c.k_max[v]
            );
            assert!(c.k_min[v].abs() < 0.03, "k_min {} at {v}", c.k_min[v]);
            assert!(
                c.e_max[v].abs() < 0.1 && c.e_min[v].abs() < 0.1,
                "e {} {} at {v}",
                c.e_max[v],
                c.e_min[v]
            );
        }
    }

    /// `mesh` with its vertices moved along the radius by uniform noise of standard
    /// deviation `deviation` sample spacings.
    fn with_radial_noise(mesh: &TriMesh, deviation: f64) -> TriMesh {
        let spacing = sample_spacing(mesh);
        let positions = mesh
            .positions()
            .iter()
            .enumerate()
            .map(|(v, p)| {
                let u = (splitmix64(v as u64) >> 11) as f64 / (1u64 << 53) as f64;
                let q = p * (1.0 + deviation * spacing * 3f64.sqrt() * (2.0 * u - 1.0));
                [q.x, q.y, q.z]
            })
            .collect();
        TriMesh::from_arrays(positions, mesh.faces().to_vec()).unwrap()
    }

    #[test]
    fn noise_is_measured_with_its_standard_deviation() {
        // A sphere with its vertices moved along the normal by uniform noise of standard
        // deviation 0.1 spacings: the bare residual reads about three quarters of it (the
        // fit takes up part of the noise), the residual over its degrees of freedom all of
        // it. The sphere has no fourth-order terms for the quartic to win on: mostly cubic.
        let noisy = with_radial_noise(&shapes::icosphere(1.0, 5), 0.1);
        let (_, report) = jet_fit_report(&noisy, &JetFitOptions::DEFAULT).unwrap();
        // Measured: sigma 0.0988, noise 0.0829, weight 0.027.
        assert!((report.sigma - 0.1).abs() < 0.01, "sigma {}", report.sigma);
        assert!(report.noise < 0.09, "noise {}", report.noise);
        assert!(
            report.quartic_weight < 0.5,
            "weight {}",
            report.quartic_weight
        );
    }

    #[test]
    fn white_noise_is_told_from_surface_the_fit_cannot_follow() {
        // Noise added to a sphere is white: the same over twice the disc.
        let noisy = with_radial_noise(&shapes::icosphere(1.0, 5), 0.1);
        let (_, white) = jet_fit_report(&noisy, &JetFitOptions::DEFAULT).unwrap();
        // Measured: 1.003.
        assert!(white.white_noise(), "growth {}", white.noise_growth);
        assert!(
            (white.noise_growth - 1.0).abs() < 0.05,
            "growth {}",
            white.noise_growth
        );
        // A clean mesh measures no noise, nor its growth.
        let (_, report) =
            jet_fit_report(&shapes::icosphere(1.0, 5), &JetFitOptions::DEFAULT).unwrap();
        assert_eq!(report.noise_growth, 0.0);
        assert!(!report.white_noise());
        // Coarse meshes are taken for noisy by the residual their sampling leaves, which
        // grows with the disc: not white (measured: growth 23 and 2.5).
        for (name, mesh) in [
            ("coarse ellipsoid", shapes::ellipsoid(1.0, 0.5, 0.25, 3)),
            ("coarse waving surface", shapes::waving_surface(8.0, 24)),
        ] {
            let (_, report) = jet_fit_report(&mesh, &JetFitOptions::DEFAULT).unwrap();
            assert!(
                report.noise > REFERENCE_NOISE,
                "{name}: noise {}",
                report.noise
            );
            assert!(
                report.noise_growth > 2.0,
                "{name}: growth {}",
                report.noise_growth
            );
            assert!(!report.white_noise(), "{name}");
            // The probes' radii do not follow the fit's: with a radius of 1 (discs of 1 and 2
            // spacings are both grown to the fewest points a fit needs, and read alike: the
            // cow measured 1.05 so, the horse 0.86) the growth is the same.
            let small = JetFitOptions::DEFAULT.with_radius(1.0);
            let (_, at_one) = jet_fit_report(&mesh, &small).unwrap();
            assert_eq!(at_one.noise_growth, report.noise_growth, "{name}");
        }
        // Nor is a residual that falls when the disc doubles taken for white noise.
        let falling = JetFitReport {
            noise_growth: 0.85,
            ..white
        };
        assert!(!falling.white_noise());
    }

    #[test]
    fn a_low_residual_that_is_not_white_may_be_truncation_error() {
        let report = |noise, noise_growth| JetFitReport {
            spacing: 1.0,
            radius: 2.5,
            noise,
            sigma: noise,
            quartic_weight: 1.0,
            noise_growth,
            triangle_sampled: 0,
        };
        // The coarse crater of `bench/quality/height_fields.py` measured 0.0018 and 3.87.
        assert!(report(0.0018, 3.87).may_be_truncation_error());
        // White noise, a scan's level (Igea 0.0067), nothing measured.
        assert!(!report(0.0018, 1.02).may_be_truncation_error());
        assert!(!report(0.0067, 2.51).may_be_truncation_error());
        assert!(!report(0.0, 0.0).may_be_truncation_error());
    }

    #[test]
    fn noise_radius_grows_only_with_noise() {
        assert_eq!(noise_radius(2.5, REFERENCE_SIGMA), 2.5);
        assert_eq!(noise_radius(2.5, 0.5 * REFERENCE_SIGMA), 2.5);
        assert!((noise_radius(2.5, 16.0 * REFERENCE_SIGMA) - 5.0).abs() < 1e-12);
        assert_eq!(noise_radius(2.5, f64::NAN), 2.5);
    }

    #[test]
    fn rejects_bad_options() {
        let mesh = shapes::icosphere(1.0, 1);
        assert!(jet_fit(&mesh, &JetFitOptions::DEFAULT.with_degree(5)).is_err());
        assert!(jet_fit(&mesh, &JetFitOptions::DEFAULT.with_radius(-1.0)).is_err());
        assert!(jet_fit(&mesh, &JetFitOptions::DEFAULT.with_radius(f64::NAN)).is_err());
        assert!(
            jet_fit(
                &mesh,
                &JetFitOptions::DEFAULT.with_radius(MAX_RADIUS * 1.01)
            )
            .is_err()
        );
        assert!(jet_fit(&mesh, &JetFitOptions::DEFAULT.with_radius(MAX_RADIUS)).is_ok());
    }
}
