//! The options of [`extract`](super::extract): one type per method (the [`Pipeline`]) and the
//! parts every method shares.

use crate::curvature::{CurvatureOptions, Estimator};
use crate::error::{Error, Result};
use crate::lines::crease::CreaseOptions;
use crate::lines::fair::Fairing;
pub use crate::lines::filter::HPW_DEFAULT_THRESHOLD;
use crate::lines::filter::StrengthMeasure;
use crate::lines::gap::GapJumping;
use crate::lines::link::LinkOptions;
use crate::lines::merge::MergeOptions;
use crate::saliency::SaliencyOptions;
use crate::smoothing::extremality::ExtremalitySmoothing;
use crate::smoothing::surface::SurfaceSmoothing;
use crate::threshold::{KneeSearch, Threshold};

/// Which paper's pipeline runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Method {
    /// Hildebrandt–Polthier–Wardetzky: shape operator, extremality smoothing.
    #[default]
    Hpw,
    /// Yoshizawa–Belyaev–Seidel: enhanced cubic fitting, strength T.
    Ybs,
    /// Mao–Wang–Zhou: mesh saliency with an automatic threshold, linked feature points.
    Saliency,
}

/// Default threshold of the YBS pipeline on T (dimensionless, as in the paper's figures):
/// the floor of its automatic threshold, and the threshold when the strengths have no knee.
pub const YBS_DEFAULT_THRESHOLD: f64 = 1.0;
/// Default minimum line length, as a fraction of the model size ([`crate::TriMesh::model_size`]).
pub const DEFAULT_MIN_LENGTH: f64 = 0.01;
/// Default number of sign-aware extremality smoothing steps of the YBS pipeline (the paper
/// has none; see the module docs of [`crate::extract`] for why and what it costs).
pub const YBS_DEFAULT_SMOOTHING_STEPS: usize = 2;
/// Default of [`ExtractOptions::white_noise_along_lines`]: on white noise the extremalities
/// diffuse up to three times faster along their lines than across (across as HPW smooth).
/// Measured, HPW, on 80 noisy surfaces made like the public ones (not in `../shared`: the
/// public five and six further height fields moved along their normals by 0.07, 0.1 and 0.15
/// of the mean edge, regular and irregular meshes, `bench/quality/noisy_cases.py`;
/// BENCHMARKS.md, *Smoothing along the lines on white noise*): mean F1 0.898 → 0.907, each
/// set's mean up (+0.002 to +0.023), 34 surfaces up and 7 down by more than 0.005, the most
/// on long weak crests (the public ridge and ellipsoid, MATLAB's peaks on irregular meshes);
/// crests that curve within a few spacings lose a little (a bumpy sphere −0.054, blobs
/// −0.027). 6 and 10 gain a little more (0.909, 0.911) and lose more often (11 down).
pub const WHITE_NOISE_ALONG_LINES: f64 = 3.0;

/// Options of the HPW pipeline's own steps: tracing in regular and singular triangles, then
/// the strength threshold (step 6).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HpwOptions {
    /// The threshold on the lines' strengths. Default: T ≥ [`HPW_DEFAULT_THRESHOLD`], fixed.
    ///
    /// Why fixed (measured on the shared meshes, table in BENCHMARKS.md): the knee cleans
    /// scans (igea 659 → 206 lines) but on CAD meshes it drops crease pieces (fandisk:
    /// T = 5.55, crease coverage 95.9% → 89.5%); [`HpwOptions::automatic`] for scans.
    pub threshold: Threshold,
    /// The strength the threshold applies to. Default: [`StrengthMeasure::Cyclideness`], T:
    /// the curvature integral of Ohtake et al. that HPW filter with cannot tell spurious lines
    /// on Dupin cyclides (a torus: ∫|k| ds is large along any line there) from crest lines,
    /// while T, built on the cyclideness, is ≈ 0 on them.
    pub measure: StrengthMeasure,
}

impl HpwOptions {
    /// The defaults.
    pub const DEFAULT: Self = HpwOptions {
        threshold: Threshold::Fixed(HPW_DEFAULT_THRESHOLD),
        measure: StrengthMeasure::Cyclideness,
    };

    /// The automatic threshold for line strengths: the knee of the strengths at or above
    /// [`HPW_DEFAULT_THRESHOLD`], which stays the threshold when they have no knee.
    pub fn automatic() -> Threshold {
        Threshold::Knee {
            floor: HPW_DEFAULT_THRESHOLD,
            search: KneeSearch::for_strengths(),
        }
    }
}

impl Default for HpwOptions {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// Options of the YBS pipeline's own steps: edge-based tracing, gap jumping and the strength
/// threshold.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct YbsOptions {
    /// The threshold on the lines' strengths. Default: the knee of the strengths at or above
    /// T = [`YBS_DEFAULT_THRESHOLD`] ([`YbsOptions::automatic`]).
    ///
    /// Why (measured on the shared meshes, table in BENCHMARKS.md): YBS's fixed T ≥ 1 keeps
    /// hundreds of weak lines on scanned meshes (igea 576 lines, 46 diagonals long) and a
    /// few on fandisk's flat faces; the knee keeps the salient ones (igea 137, 22 diagonals;
    /// fandisk's creases all kept) and keeps spheres and tori empty.
    pub threshold: Threshold,
    /// The strength the threshold applies to. Default: [`StrengthMeasure::Cyclideness`]
    /// (YBS eq. 5).
    pub measure: StrengthMeasure,
    /// Gap jumping; `None` turns it off. Default: YBS's angles ([`GapJumping::default`]).
    pub gaps: Option<GapJumping>,
}

impl YbsOptions {
    /// The automatic threshold for line strengths: the knee of the strengths at or above
    /// [`YBS_DEFAULT_THRESHOLD`], which stays the threshold when they have no knee.
    pub fn automatic() -> Threshold {
        Threshold::Knee {
            floor: YBS_DEFAULT_THRESHOLD,
            search: KneeSearch::for_strengths(),
        }
    }
}

impl Default for YbsOptions {
    fn default() -> Self {
        YbsOptions {
            threshold: Self::automatic(),
            measure: StrengthMeasure::Cyclideness,
            gaps: Some(GapJumping::default()),
        }
    }
}

/// Options of the saliency pipeline's own steps (Mao, Wang, Zhou): the saliency field, its
/// threshold and the linking of the feature points.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MwzOptions {
    /// The saliency field. Default: [`SaliencyOptions::default`].
    pub saliency: SaliencyOptions,
    /// The threshold on the saliency: vertices above it are feature points. Default: the knee
    /// of all the saliency values ([`MwzOptions::automatic`], the paper's procedure); when
    /// they rise without a knee, their split ([`crate::threshold::NoKnee::Split`]); when they
    /// are flat (or fewer than 8) no vertex is a feature point (a flat saliency curve means a
    /// shape without salient parts: a sphere, a torus).
    pub threshold: Threshold,
    /// Feature-point linking. Default: [`LinkOptions::default`].
    pub link: LinkOptions,
}

impl MwzOptions {
    /// The paper's automatic threshold: the knee of all the saliency values (no floor).
    pub fn automatic() -> Threshold {
        Threshold::Knee {
            floor: f64::NEG_INFINITY,
            search: KneeSearch::default(),
        }
    }
}

impl Default for MwzOptions {
    fn default() -> Self {
        MwzOptions {
            saliency: SaliencyOptions::default(),
            threshold: Self::automatic(),
            link: LinkOptions::default(),
        }
    }
}

/// The method that runs, with the options of its own steps.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Pipeline {
    /// Hildebrandt–Polthier–Wardetzky.
    Hpw(HpwOptions),
    /// Yoshizawa–Belyaev–Seidel.
    Ybs(YbsOptions),
    /// Mao–Wang–Zhou (mesh saliency).
    Saliency(MwzOptions),
}

impl Pipeline {
    /// The method's defaults.
    pub fn for_method(method: Method) -> Self {
        match method {
            Method::Hpw => Pipeline::Hpw(HpwOptions::default()),
            Method::Ybs => Pipeline::Ybs(YbsOptions::default()),
            Method::Saliency => Pipeline::Saliency(MwzOptions::default()),
        }
    }

    /// Which method this is.
    pub fn method(&self) -> Method {
        match self {
            Pipeline::Hpw(_) => Method::Hpw,
            Pipeline::Ybs(_) => Method::Ybs,
            Pipeline::Saliency(_) => Method::Saliency,
        }
    }

    /// The threshold of the method: on the lines' strengths (HPW, YBS) or on the saliency.
    pub fn threshold(&self) -> &Threshold {
        match self {
            Pipeline::Hpw(o) => &o.threshold,
            Pipeline::Ybs(o) => &o.threshold,
            Pipeline::Saliency(o) => &o.threshold,
        }
    }

    /// Sets the threshold of the method.
    pub fn set_threshold(&mut self, threshold: Threshold) {
        match self {
            Pipeline::Hpw(o) => o.threshold = threshold,
            Pipeline::Ybs(o) => o.threshold = threshold,
            Pipeline::Saliency(o) => o.threshold = threshold,
        }
    }

    /// The method's automatic threshold ([`HpwOptions::automatic`],
    /// [`YbsOptions::automatic`], [`MwzOptions::automatic`]).
    pub fn automatic_threshold(&self) -> Threshold {
        match self {
            Pipeline::Hpw(_) => HpwOptions::automatic(),
            Pipeline::Ybs(_) => YbsOptions::automatic(),
            Pipeline::Saliency(_) => MwzOptions::automatic(),
        }
    }
}

impl Default for Pipeline {
    fn default() -> Self {
        Pipeline::Hpw(HpwOptions::default())
    }
}

/// Options of [`extract`](super::extract): the method's own ([`Pipeline`]) and the steps every
/// method runs. Every field has a documented default; [`ExtractOptions::for_method`] gives the
/// defaults of each method.
///
/// **Units.** Every length of these options is a fraction of the model size: the
/// bounding-box diagonal of the mesh, or of its largest connected component when it has
/// several ([`crate::TriMesh::model_size`]; [`ExtractStats::scale`](super::ExtractStats::scale))
/// ([`ExtractOptions::min_length`], [`Fairing::tolerance`], the crease and merge distances of
/// [`CreaseOptions`] and [`MergeOptions`]), so that the same options mean the same on a model
/// in millimetres and in metres. Three scales are not lengths of the result but widths of
/// the estimators' filters, and follow the mesh's resolution instead: the smoothing step sizes
/// (squared mean edge lengths, [`ExtremalitySmoothing::time_step`],
/// [`SurfaceSmoothing::time_step`]), the jet fit's radius (sample spacings,
/// [`crate::curvature::JetFitOptions::radius`]) and the saliency's σ (mean edge lengths,
/// [`SaliencyOptions::lambda`]). Strengths (T, ∫|k| ds) and the saliency are dimensionless.
#[derive(Debug, Clone, PartialEq)]
pub struct ExtractOptions {
    /// The method and the options of its own steps. Default: [`Pipeline::Hpw`] with
    /// [`HpwOptions::DEFAULT`].
    pub pipeline: Pipeline,
    /// Reverse the triangles wound against their neighbours, then those of closed components
    /// that face inward (negative volume), before anything else, so that ridges are not taken
    /// for valleys nor edges for folds (see [`crate::extract`] and
    /// [`crate::mesh::orient_outward`]); `false` takes the winding as it is. Default: true.
    pub orient_outward: bool,
    /// Put isolated outlier vertices (spikes: single vertices far off the surface their
    /// neighbours describe, as scanners leave them) back on that surface before anything
    /// else but the orientation ([`crate::mesh::outliers`]): each would otherwise be ringed by
    /// creases and pull every fit around it into crest lines of its own. Vertices on a sharp
    /// feature or under white noise are not outliers by that test (of the shared meshes and
    /// the CAD parts, one vertex of the horse scan moves). The curvature fields and the lines are those of the repaired
    /// surface; [`crate::extract::ExtractStats::outliers`] says which vertices moved. `false`
    /// takes every vertex as it is. Default: true.
    pub repair_outliers: bool,
    /// Sharp creases ([`crate::lines::crease`]), found before anything else but the
    /// orientation and the outliers' repair: the curvature fits and the extremality smoothing do not reach across them, and
    /// they join the lines at the end. Default: [`CreaseOptions::default`] (threshold from the
    /// gap in the dihedral angles, or on a noisy mesh without one in the angles between
    /// filtered normals; none on meshes without such a gap) for every method.
    pub creases: CreaseOptions,
    /// Step 1: surface pre-smoothing. Default: off (0 steps).
    pub pre_smoothing: SurfaceSmoothing,
    /// Curvature estimation. Default: the jet fit ([`Estimator::JetFit`]) for every method,
    /// a deliberate deviation from the papers (see [`crate::extract`]).
    pub curvature: CurvatureOptions,
    /// Step 3: sign-aware extremality smoothing, for every method (the saliency method's
    /// feature points are crest points). Default: 2 steps of size 1 (relative), crease-aware,
    /// twiced ([`ExtremalitySmoothing::default`]); for YBS [`YBS_DEFAULT_SMOOTHING_STEPS`], a
    /// deviation from the paper (see [`crate::extract`]; 0 steps is YBS as published).
    pub smoothing: ExtremalitySmoothing,
    /// Run the extremality smoothing only when the curvature estimate found the surface
    /// noisy ([`crate::curvature::Curvature::extremality_noise`] > 0; only the jet fit
    /// measures noise, so the papers' estimators are always smoothed). On clean surfaces the
    /// jet fit has already averaged over a disc, and smoothing again moves the zeros of the
    /// extremalities of small features (measured on the public bumpy sphere: F1 0.92 → 0.22
    /// at 5K faces, 0.99 → 0.90 at 20K); on noisy ones it removes what noise the fit leaves.
    /// Default: true.
    pub smooth_only_noisy: bool,
    /// Where the jet fit finds the surface's noise white
    /// ([`crate::curvature::JetFitReport::white_noise`]; of the shared scans and models only
    /// the teapot), the extremality smoothing runs up to this many times faster along each
    /// family's lines than across them ([`ExtremalitySmoothing::along_lines`], which it
    /// replaces there): the fit leaves noise in the extremalities that is correlated over its
    /// disc, and a weak crest's zero wanders with it; averaging along the line takes more of it
    /// out without moving the zero across. 1 is HPW's isotropic smoothing. Elsewhere (scans
    /// whose residual is fine detail, clean meshes) the smoothing is as
    /// [`ExtractOptions::smoothing`] says: on igea, whose residual is not white, smoothing along
    /// the lines (a first version, which also diffused faster across them where the triangles
    /// do not follow the lines) dropped a fifth of the lines (480 → 376), two of the forehead's
    /// three ridges among them.
    ///
    /// Default: [`WHITE_NOISE_ALONG_LINES`].
    pub white_noise_along_lines: f64,
    /// Lines shorter than this fraction of the model size are dropped (HPW step 6,
    /// for every method). Default: [`DEFAULT_MIN_LENGTH`].
    pub min_length: f64,
    /// Move the crest lines across by the displacement the jet fit's disc causes
    /// ([`crate::lines::debias`]), when the fit found the surface noisy (its disc is then
    /// wide; on clean meshes nothing runs); every method's lines are crest lines (the
    /// saliency method's are linked crest points). Measured on the public `bumpy/noisy20k`:
    /// F1 0.466 → 0.710 (YBS 0.483 → 0.739, saliency 0.466 → 0.815), on four more noisy
    /// bumpy spheres +0.10 to +0.25.
    ///
    /// Default: true. On 24 further noisy surfaces made like the public ones (reg20k and
    /// irr20k moved along their normals, 0.07 and 0.1 of the mean edge) the bumpy spheres
    /// gain 0.15 to 0.28 and the others move by −0.026 to 0.000 (the ellipsoid's symmetric
    /// crest has no bias to remove, only the noise of its estimate; see the module docs of
    /// [`crate::lines::debias`]). False keeps the traced lines where the fit put them.
    pub debias_lines: bool,
    /// Before the strength threshold, drop the HPW and YBS lines whose extremality crosses
    /// zero less than twice as steeply as its estimation noise, and cut such ends off the
    /// others ([`crate::lines::located`]): lines the noise moves about, off the weak crests
    /// they follow. Runs only when the jet fit finds the surface's noise white
    /// ([`crate::curvature::JetFitReport::white_noise`]; of the shared scans and models only
    /// the teapot, whose lines along its base and handle stay). Measured on the public `bumpy/noisy20k`: HPW F1
    /// 0.710 → 0.806, YBS 0.739 → 0.811; the other public and CAD cases unchanged.
    ///
    /// Default: true. On 46 further noisy surfaces made like the public ones (against false)
    /// the ten bumpy spheres gain up to 0.12 but one (YBS: 0.715 → 0.713), the made-alike
    /// noisy torus's spurious rim shortens, two noisy ridges lose 0.021 and 0.001 (YBS), the
    /// others are unchanged. The cut lines are measured again, so YBS's automatic threshold
    /// (the knee of the strengths) sees their new strengths. False keeps every traced line,
    /// whole, for the strength threshold.
    pub drop_unlocated_lines: bool,
    /// Step 7: spatial fairing; its tolerance is a fraction of the model size.
    /// Default: off.
    pub fairing: Fairing,
    /// How crease curves and crest lines are merged ([`crate::lines::merge`]). Default:
    /// [`MergeOptions::default`].
    pub merge: MergeOptions,
}

impl ExtractOptions {
    /// The defaults of a method.
    pub fn for_method(method: Method) -> Self {
        let mut smoothing = ExtremalitySmoothing::default();
        if method == Method::Ybs {
            smoothing.steps = YBS_DEFAULT_SMOOTHING_STEPS;
        }
        ExtractOptions {
            pipeline: Pipeline::for_method(method),
            orient_outward: true,
            repair_outliers: true,
            creases: CreaseOptions::DEFAULT,
            pre_smoothing: SurfaceSmoothing::default(),
            curvature: CurvatureOptions::default().with_estimator(Estimator::JetFit),
            smoothing,
            smooth_only_noisy: true,
            white_noise_along_lines: WHITE_NOISE_ALONG_LINES,
            min_length: DEFAULT_MIN_LENGTH,
            debias_lines: true,
            drop_unlocated_lines: true,
            fairing: Fairing::default(),
            merge: MergeOptions::DEFAULT,
        }
    }

    /// Which method runs.
    pub fn method(&self) -> Method {
        self.pipeline.method()
    }

    /// These options with the method's threshold set to `threshold`.
    pub fn with_threshold(mut self, threshold: Threshold) -> Self {
        self.pipeline.set_threshold(threshold);
        self
    }

    /// These options with the method's automatic threshold
    /// ([`Pipeline::automatic_threshold`]).
    pub fn with_automatic_threshold(self) -> Self {
        let automatic = self.pipeline.automatic_threshold();
        self.with_threshold(automatic)
    }

    /// Checks the values that every run reads, whether or not the stage that uses them runs
    /// on a given mesh (the smoothing runs only on noisy meshes by default): a fixed
    /// threshold and a minimum length that are finite and not negative (a knee search's floor
    /// not NaN nor +∞), a fairing tolerance that is finite
    /// and not negative, a smoothing time step above 0 and at most 1e6 (beyond, one step
    /// would smooth across any mesh and the solver loses precision) and a crease angle from 0
    /// to π. [`extract()`](crate::extract::extract) checks them first.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] naming the first value out of range.
    pub fn validate(&self) -> Result<()> {
        let not_negative = |value: f64| value.is_finite() && value >= 0.0;
        // A knee search's floor may be −∞ (no floor, the saliency's).
        let (threshold, fine) = match *self.pipeline.threshold() {
            Threshold::Fixed(value) => (value, not_negative(value)),
            Threshold::Knee { floor, .. } => (floor, floor < f64::INFINITY),
        };
        let checks = [
            (fine, "threshold", threshold, "of at least 0"),
            (
                not_negative(self.min_length),
                "minimum line length",
                self.min_length,
                "of at least 0",
            ),
            (
                not_negative(self.fairing.tolerance),
                "fairing tolerance",
                self.fairing.tolerance,
                "of at least 0",
            ),
            (
                self.smoothing.time_step > 0.0
                    && self.smoothing.time_step <= MAX_SMOOTHING_TIME_STEP,
                "smoothing time step",
                self.smoothing.time_step,
                "above 0 and at most 1e6",
            ),
            (
                self.white_noise_along_lines > 0.0
                    && self.white_noise_along_lines <= MAX_ALONG_LINES,
                "smoothing factor along the lines on white noise",
                self.white_noise_along_lines,
                "above 0 and at most 1e6",
            ),
            (
                self.smoothing.along_lines > 0.0 && self.smoothing.along_lines <= MAX_ALONG_LINES,
                "smoothing factor along the lines (smoothing.along_lines)",
                self.smoothing.along_lines,
                "above 0 and at most 1e6",
            ),
        ];
        for (fine, what, value, range) in checks {
            if !fine {
                return Err(Error::InvalidInput(format!(
                    "{what} must be a finite number {range}, got {value}"
                )));
            }
        }
        for (steps, what, larger) in [
            (
                self.pre_smoothing.steps,
                "surface pre-smoothing steps",
                "the flow's time step",
            ),
            (
                self.smoothing.steps,
                "extremality smoothing steps",
                "the smoothing time step",
            ),
        ] {
            if steps > MAX_SMOOTHING_STEPS {
                return Err(Error::InvalidInput(format!(
                    "{what} must be at most {MAX_SMOOTHING_STEPS}, got {steps} (each step \
                     solves a system over the whole mesh; for more smoothing use fewer steps \
                     and a larger {larger})"
                )));
            }
        }
        let angle = self.smoothing.crease_angle;
        if !(angle.is_finite() && (0.0..=std::f64::consts::PI).contains(&angle)) {
            // Given in degrees and stored in radians: the round trip's last bits dropped
            // (-3, not -3.0000000000000004), unless that would hide the value (a tiny
            // negative angle, a huge one).
            let degrees = angle.to_degrees();
            let rounded = (degrees * 1e9).round() / 1e9;
            let shown = if rounded != 0.0 && rounded.is_finite() {
                rounded
            } else {
                degrees
            };
            return Err(Error::InvalidInput(format!(
                "crease angle must be from 0 to 180 degrees, got {shown} degrees"
            )));
        }
        Ok(())
    }
}

/// The most steps of surface pre-smoothing and of extremality smoothing
/// [`ExtractOptions::validate`] accepts. Each step solves a linear system over the whole
/// mesh (igea: about 0.1 s, horse ×16 about 0.4 s), so a thousand take minutes; any amount of
/// smoothing is reached with fewer steps of a larger time step. A count of 10⁹, given by
/// mistake, ran for ever, and from Python it cannot be interrupted within the stage.
pub const MAX_SMOOTHING_STEPS: usize = 1000;

/// The largest [`ExtremalitySmoothing::time_step`] [`ExtractOptions::validate`] accepts. One
/// step diffuses over about `sqrt(time_step)` rings: at 1e6 a thousand, beyond the extent of
/// any mesh, so larger steps only flatten the extremalities further (spot and horse had no
/// lines left from 1e4 and 1e6) while the implicit system loses the precision its solver
/// needs (conjugate gradients broke down at 1e15 on both, and 1e300 overflows).
const MAX_SMOOTHING_TIME_STEP: f64 = 1e6;

/// The largest factor of the smoothing along the lines
/// ([`ExtractOptions::white_noise_along_lines`]): far beyond any use, and well within the
/// weights' range.
const MAX_ALONG_LINES: f64 = 1e6;

impl Default for ExtractOptions {
    fn default() -> Self {
        Self::for_method(Method::Hpw)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_out_of_range_are_named_before_anything_runs() {
        assert!(ExtractOptions::default().validate().is_ok());
        for method in [Method::Hpw, Method::Ybs, Method::Saliency] {
            assert!(ExtractOptions::for_method(method).validate().is_ok());
        }
        type Spoil = fn(&mut ExtractOptions);
        let bad: [(Spoil, &str); 10] = [
            (|o| o.min_length = -0.1, "minimum line length"),
            (|o| o.min_length = f64::NAN, "minimum line length"),
            (|o| o.fairing.tolerance = f64::INFINITY, "fairing tolerance"),
            (|o| o.smoothing.time_step = 0.0, "smoothing time step"),
            (|o| o.smoothing.time_step = 1e9, "smoothing time step"),
            (|o| o.smoothing.crease_angle = 4.0, "crease angle"),
            (
                |o| o.pipeline.set_threshold(Threshold::Fixed(f64::NAN)),
                "threshold",
            ),
            (
                |o| o.pipeline.set_threshold(Threshold::Fixed(-1.0)),
                "threshold",
            ),
            (
                |o| o.pre_smoothing.steps = 1_000_000_000,
                "pre-smoothing steps must be at most 1000, got 1000000000",
            ),
            (
                |o| o.smoothing.steps = MAX_SMOOTHING_STEPS + 1,
                "extremality smoothing steps must be at most 1000",
            ),
        ];
        for (spoil, what) in bad {
            let mut options = ExtractOptions::default();
            spoil(&mut options);
            let e = options.validate().unwrap_err().to_string();
            assert!(e.contains(what), "{e}");
            // The mesh is never looked at: on a sphere, which is not smoothed either.
            let sphere = crate::shapes::icosphere(1.0, 2);
            assert!(
                crate::extract::extract(&sphere, &options).is_err(),
                "{what}"
            );
        }
        // The most steps are accepted.
        let mut options = ExtractOptions::default();
        options.pre_smoothing.steps = MAX_SMOOTHING_STEPS;
        options.smoothing.steps = MAX_SMOOTHING_STEPS;
        assert!(options.validate().is_ok());
        // An angle given in degrees is named as given.
        let mut options = ExtractOptions::default();
        options.smoothing.crease_angle = (-3.0f64).to_radians();
        let e = options.validate().unwrap_err().to_string();
        assert!(e.ends_with("got -3 degrees"), "{e}");
    }
}
