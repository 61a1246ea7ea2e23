//! The feature-line pipelines, start to finish.
//!
//! [`extract`] runs the public steps of the chosen [`Method`] in order and nothing else:
//!
//! **HPW** (Hildebrandt, Polthier, Wardetzky 2005, Table 1):
//! 1. optional surface pre-smoothing ([`crate::smoothing::surface`]),
//! 2. discrete extremalities from the shape operator ([`crate::curvature`]),
//! 3. sign-aware extremality smoothing ([`crate::smoothing::extremality`]),
//! 4. tracing in regular triangles ([`crate::lines::trace`]),
//! 5. singular triangles ([`crate::lines::singular`]),
//! 6. polylines and threshold filtering ([`crate::lines::assemble`], [`crate::lines::filter`]),
//! 7. optional spatial fairing ([`crate::lines::fair`]).
//!
//! Between 6 and 7 ([`ExtractOptions::debias_lines`], on by default), on surfaces the jet
//! fit found noisy, the crest lines are moved across by the displacement the fit's widened
//! disc causes and, where the noise is white, by the drift the extremality smoothing
//! measured of itself ([`crate::lines::debias`]); so are the saliency method's, which are
//! crest lines too (linked crest points).
//!
//! Before the threshold of step 6 ([`ExtractOptions::drop_unlocated_lines`], on by default),
//! on surfaces whose noise the jet fit finds white, the HPW and YBS lines whose extremality
//! crosses zero less than twice as steeply as its estimation noise are dropped: the noise
//! moves them about, off the weak crests they follow ([`crate::lines::located`]), and the
//! ends of the others are cut where they do so.
//!
//! **Creases** (every method, [`ExtractOptions::creases`]): before step 1 the sharp creases of
//! the mesh are found ([`crate::lines::crease`]; none on meshes whose dihedral angles have no
//! gap, such as scans and smooth meshes). The curvature fits (jet fit) and the extremality
//! smoothing do not reach across them (nor across non-manifold edges: each sheet that meets
//! there is fitted on its own), and at the end they are merged with the crest lines
//! ([`crate::lines::merge`]): crest lines along a crease give way to it, crest lines ending
//! near one are joined to it.
//!
//! **YBS** (Yoshizawa, Belyaev, Seidel 2005): the enhanced cubic fit for curvature and
//! extremalities, edge-based tracing with gap jumping ([`crate::lines::trace_crest_lines`]),
//! filtering by the strength T.
//!
//! *Deliberate deviation:* by default YBS's extremalities get [`YBS_DEFAULT_SMOOTHING_STEPS`]
//! steps of HPW's sign-aware smoothing (step 3 above) before tracing; the paper does not
//! smooth them (`smoothing.steps = 0`, CLI `--smooth-steps 0`, is YBS as published). The
//! cubic fit's `e` has errors that grow like 1/h where the mesh is irregular (the Max normals
//! of the pre-smoothed mesh are only O(h) accurate there and the fit turns a normal error δn
//! into δn/h² in the cubic terms; see [`crate::curvature::cubic_fit`](mod@crate::curvature::cubic_fit)). On the
//! icosphere-based ellipsoid x²/9 + y²/4 + z² = 1 at 20K faces the 1-ring fit gets the sign of
//! e_max wrong on rows of vertices along the icosahedron's seams (72 vertices with |e| > 1;
//! none with exact normals), and no tracing rule can recover the crest line from that: the
//! published pipeline gives 48 pieces (8 kept), some bent 0.16 (2% of the diagonal) off the
//! equator along the seams, where the same tracing on the exact fields gives one closed line.
//! With two smoothing steps the traced equator is one closed line at 5K and 20K faces for
//! every k from 1 to 4, and the torus stays empty. Measured alternatives: larger k (the
//! paper's own remedy, k = 3 in its Fig. 5) passes at k = 3 with 4 pieces and a 0.069
//! deviation against a 0.075 tolerance, and fails at k = 2; one smoothing step leaves the
//! equator split around the valence-5 vertices. The price is the smoothing solves (twiced: twice the steps)
//! (`BENCHMARKS.md`, "Extremality smoothing solver"); T is measured on the smoothed fields,
//! as for HPW.
//!
//! **Default estimator of HPW and YBS: the jet fit** ([`crate::curvature::jet_fit`](mod@crate::curvature::jet_fit)).
//! *Deliberate deviation from all three papers.* The papers' estimators read one star (HPW's
//! shape operator) or a k-ring (YBS's cubic fit), so their errors depend on the
//! triangulation: on the irregular and marching-cubes cases of `../shared/quality` k is off
//! by 15 to 50% of max |k| and e by more than its own size, and the lines break into pieces.
//! The jet fit reads a disc of fixed radius in which every vertex counts by the area it stands
//! for, and measures the noise of the surface from its own residuals and widens the disc
//! with it (step 3 of issue 19: a scale that adapts to noise). The papers' estimators stay
//! one option away (`curvature.estimator`, CLI `--estimator shape-operator` / `cubic-fit`,
//! or `--rings k` for YBS's k-ring fit). With the jet fit, the extremality smoothing (step 3)
//! runs only on surfaces the fit found noisy ([`ExtractOptions::smooth_only_noisy`]), and the
//! strength T of each line is corrected for the part the remaining noise adds to it
//! ([`crate::lines::assemble`]). Figures before and after: `BENCHMARKS.md`, "Quality".
//! The saliency method uses it too: its feature points are crest points (see
//! [`crate::lines::link`]).
//!
//! *Orientation:* curvature signs follow the winding of the triangles, so a closed mesh wound
//! inward gives ridges as valleys and valleys as ridges, and a triangle wound against its
//! neighbours makes a fold of every edge it shares with them. By default [`extract`] first
//! reverses the triangles wound against the rest of their patch, then the closed components
//! that face inward ([`crate::mesh::orient_outward`];
//! [`ExtractOptions::orient_outward`], reported in [`ExtractStats::orientation`]), as the CLI
//! does for every command (unless `--keep-orientation`). Vertex and face indices stay as
//! they are, so the curvature fields and line locations refer to the mesh as given (their
//! positions to the repaired surface, below, where outliers moved).
//!
//! *Outliers:* next (unless [`ExtractOptions::repair_outliers`] is off), isolated outlier
//! vertices, the spikes scanners leave, are put back on the surface their neighbours describe
//! ([`crate::mesh::outliers`]); everything after runs on the repaired surface
//! ([`ExtractStats::outliers`]).
//!
//! **Saliency** (Mao, Wang, Zhou): curvature (jet fit by default), mesh saliency
//! ([`crate::saliency`]), an automatic threshold on it ([`crate::threshold`]) and the linking
//! rules ([`crate::lines::link`]).
//!
//! **Options** ([`ExtractOptions`], in `options.rs`): the method and its own steps' options
//! are one [`Pipeline`] ([`HpwOptions`], [`YbsOptions`], [`MwzOptions`]); the steps every
//! method runs (orientation, creases, pre-smoothing, curvature, extremality smoothing,
//! minimum length, fairing, merge) are shared. Every length is a fraction of the model size,
//! the bounding-box diagonal of the largest connected component ([`TriMesh::model_size`]: a
//! speck far away or a second part beside the first does not change the lines; see
//! [`ExtractOptions`] for the units of the filter widths).
//!
//! **Thresholds** ([`crate::threshold::Threshold`]): fixed, or the knee search of
//! [`crate::threshold`], a public step of its own ([`crate::threshold::choose_threshold`];
//! for lines [`crate::lines::filter::choose_line_threshold`]). It applies to the saliency
//! (Saliency, the paper's procedure) or to the strengths of the traced lines (HPW, YBS). For
//! lines the knee search has a floor: the search runs, on the log scale, over the lines that
//! pass both it and the minimum length, and can only raise it. The floor is what keeps shapes
//! without crest lines empty: T is dimensionless and the spurious lines of a sphere or a torus
//! stay below 1 (measured: ≤ 0.52 on `icosphere(2, 5)`, ≤ 0.45 on `torus(3, 1, 120, 40)` with
//! YBS), while among such lines a knee is easily found (their strengths span five orders of
//! magnitude). When the strengths have no knee (all lines alike: the 12 edges of a cube, or no
//! line above the floor) the floor stays. The saliency method splits a saliency that rises
//! without a knee in two ([`crate::threshold::NoKnee::Split`]) and keeps no point when it is
//! flat (or has fewer than 8 values), since a flat saliency curve means a shape without
//! salient parts (a sphere, a torus). Its ridge and valley points may each have a knee of
//! their own below that of all vertices ([`crate::saliency::family`]).

mod fields;
mod options;

use std::borrow::Cow;
use std::time::{Duration, Instant};

pub use fields::{SurfaceFields, surface_fields};
pub use options::{
    DEFAULT_MIN_LENGTH, ExtractOptions, HPW_DEFAULT_THRESHOLD, HpwOptions, MAX_SMOOTHING_STEPS,
    Method, MwzOptions, Pipeline, WHITE_NOISE_ALONG_LINES, YBS_DEFAULT_SMOOTHING_STEPS,
    YBS_DEFAULT_THRESHOLD, YbsOptions,
};

use crate::curvature::{self, Curvature, Estimator};
use crate::error::Result;
use crate::lines::crease::find_creases;
use crate::lines::debias::{DebiasReport, debias_crest_lines};
use crate::lines::fair::fair_lines;
use crate::lines::filter::{LineFilter, StrengthMeasure, choose_line_threshold, filter_lines};
use crate::lines::link::link_feature_points;
use crate::lines::located::{drop_unlocated_lines, slope_noises, trim_unlocated_ends};
use crate::lines::merge::merge_creases;
use crate::lines::{
    FeatureLines, LineKind, TraceReport, jump_crest_gaps, trace_crest_lines, trace_lines,
};
use crate::mesh::{
    Lattice, Orientation, OutlierRepair, TriMesh, find_lattice, orientation, repair_outliers,
    reverse_faces,
};
use crate::saliency::{family_thresholds, mesh_saliency};
use crate::smoothing::extremality::{smooth_extremalities, smooth_extremalities_split};
use crate::smoothing::surface::smooth_surface;
use crate::threshold::{ChosenThreshold, NoKnee};

/// The named stages, for progress reports and timings.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Stage {
    /// Isolated outlier vertices put back on the surface (before everything else).
    Outliers,
    /// Sharp creases (before step 1).
    Creases,
    /// Step 1.
    PreSmoothing,
    /// Step 2 (curvature and extremalities).
    Curvature,
    /// Step 3.
    ExtremalitySmoothing,
    /// Steps 4–6 before filtering (for Saliency: saliency and linking; for YBS: without gap
    /// jumping).
    Tracing,
    /// YBS's gap jumping.
    GapJumping,
    /// Step 6.
    Filtering,
    /// Crest lines moved by the jet fit's bias (noisy surfaces; [`crate::lines::debias`]).
    Debiasing,
    /// Step 7.
    Fairing,
    /// Crease curves merged with the crest lines.
    Merging,
}

impl Stage {
    /// A short human-readable name.
    pub fn name(self) -> &'static str {
        match self {
            Stage::Outliers => "outliers",
            Stage::Creases => "creases",
            Stage::PreSmoothing => "pre-smoothing",
            Stage::Curvature => "curvature",
            Stage::ExtremalitySmoothing => "extremality smoothing",
            Stage::Tracing => "tracing",
            Stage::GapJumping => "gap jumping",
            Stage::Filtering => "filtering",
            Stage::Debiasing => "debiasing",
            Stage::Fairing => "fairing",
            Stage::Merging => "merging",
        }
    }
}

/// Figures about one run.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ExtractStats {
    /// Triangles of the mesh.
    pub triangles: usize,
    /// Tracing figures (singular triangles per family and cases).
    pub trace: TraceReport,
    /// The isolated outlier vertices moved back onto their neighbours' surface
    /// ([`ExtractOptions::repair_outliers`]; none when that step did not run).
    pub outliers: OutlierRepair,
    /// The grid of a mesh left as marching cubes made it, every vertex on a grid edge
    /// ([`crate::mesh::find_lattice`]): the terraces of its interpolation are crest lines of
    /// the mesh and come out as lines (`BENCHMARKS.md`, "Open: raw marching cubes"). Said,
    /// not repaired.
    pub marching_cubes_grid: Option<Lattice>,
    /// Vertices whose curvature needed a fallback.
    pub fallback_vertices: usize,
    /// The jet fit's sample spacing, radius and measured noise level (`None` with the
    /// papers' estimators).
    pub jet_fit: Option<crate::curvature::JetFitReport>,
    /// Lines before filtering (after gap jumping).
    pub lines_traced: usize,
    /// Lines dropped before the strength threshold because the noise moves them about
    /// ([`crate::lines::located`]; 0 when that step did not run).
    pub lines_unlocated: usize,
    /// Lines whose ends the noise moves about were cut off before the strength threshold
    /// ([`crate::lines::located::trim_unlocated_ends`]; some may then be dropped by it; 0
    /// when that step did not run).
    pub lines_trimmed: usize,
    /// Lines kept.
    pub lines: usize,
    /// Crest lines of the ridge family kept (creases apart, as the JSON lines file counts
    /// them: `ridges`, `valleys`, `crease_ridges`, `crease_valleys`).
    pub ridges: usize,
    /// Crest lines of the valley family kept (creases apart).
    pub valleys: usize,
    /// Convex sharp creases kept (`crease-ridge` lines).
    pub crease_ridges: usize,
    /// Concave sharp creases kept (`crease-valley` lines).
    pub crease_valleys: usize,
    /// Total length of the lines kept.
    pub total_length: f64,
    /// The model size the relative lengths and strengths were measured against: the
    /// bounding-box diagonal of the largest connected component ([`TriMesh::model_size`]).
    pub scale: f64,
    /// Crease curves among the lines kept: `crease_ridges + crease_valleys`.
    pub creases: usize,
    /// Total length of the crease curves.
    pub crease_length: f64,
    /// The dihedral angle threshold of the creases (degrees); `None` when creases are off or
    /// the mesh has no gap in its dihedral angles (nor, when it is noisy, in those between
    /// filtered normals: see `crease_normals_filtered`).
    pub crease_threshold: Option<f64>,
    /// True when the crease threshold was found between filtered face normals: the mesh is
    /// noisy and its own dihedral angles had no gap ([`crate::lines::crease`], step 2b).
    pub crease_normals_filtered: bool,
    /// The strength threshold applied (for Saliency: the saliency threshold; infinite when
    /// the saliency is flat, so that no vertex is a feature point).
    pub threshold: f64,
    /// True when the threshold came from the automatic search: the knee, or the split of a
    /// saliency that rose without one (false when it was not asked for, or found nothing).
    pub threshold_is_auto: bool,
    /// True when the saliency had no knee and the threshold is its split
    /// ([`crate::threshold::NoKnee::Split`]).
    pub threshold_is_split: bool,
    /// Saliency: the thresholds of the ridge and the valley feature points
    /// ([`crate::saliency::family`]: `threshold`, or a family's own knee where it is lower).
    /// `None` for HPW and YBS.
    pub family_thresholds: Option<[f64; 2]>,
    /// Gaps jumped (YBS).
    pub gaps_jumped: usize,
    /// Line points moved by [`crate::lines::debias`] and their median move (all zero when it
    /// did not run).
    pub debias: DebiasReport,
    /// Wall time of each stage that ran, in order.
    pub stage_times: Vec<(Stage, Duration)>,
    /// The closed components found, the triangles rewound to agree with their neighbours and
    /// the components reversed because they faced inward (all zero when
    /// [`ExtractOptions::orient_outward`] is off).
    pub orientation: Orientation,
}

/// The result of [`extract`].
#[derive(Debug, Clone)]
pub struct Extraction {
    /// The lines kept.
    pub lines: FeatureLines,
    /// Curvature fields after extremality smoothing (on the repaired and the pre-smoothed
    /// surface, if any).
    pub curvature: Curvature,
    /// Figures about the run.
    pub stats: ExtractStats,
}

/// Finds the feature lines of `mesh`: ridges, valleys and sharp creases, by the pipeline of
/// `options.pipeline` (see the module docs for the steps), without progress reports.
///
/// The mesh is taken as given except that triangles wound against their neighbours and
/// closed components facing inward are reversed first ([`ExtractOptions::orient_outward`])
/// and isolated outlier vertices put back on the surface of their neighbours
/// ([`ExtractOptions::repair_outliers`]). Degenerate triangles, boundaries and non-manifold
/// edges are allowed.
///
/// ```
/// use crestline::extract::{ExtractOptions, Method, extract};
/// use crestline::lines::LineKind;
///
/// # fn main() -> crestline::Result<()> {
/// // An ellipsoid x²/9 + y²/4 + z² = 1 has one crest line, a ridge around its widest part.
/// let mesh = crestline::shapes::ellipsoid(3.0, 2.0, 1.0, 4);
/// let found = extract(&mesh, &ExtractOptions::for_method(Method::Hpw))?;
/// assert!(found.lines.of_kind(LineKind::Ridge).count() >= 1);
/// assert_eq!(found.stats.valleys, 0);
/// # Ok(())
/// # }
/// ```
///
/// # Errors
/// Invalid options, or a solver failure in a smoothing step.
pub fn extract(mesh: &TriMesh, options: &ExtractOptions) -> Result<Extraction> {
    extract_with_progress(mesh, options, &mut |_, _| {})
}

/// [`extract`], calling `progress(stage, None)` when a stage starts and
/// `progress(stage, Some(elapsed))` when it ends.
///
/// # Errors
/// As [`extract`].
pub fn extract_with_progress(
    mesh: &TriMesh,
    options: &ExtractOptions,
    progress: &mut dyn FnMut(Stage, Option<Duration>),
) -> Result<Extraction> {
    options.validate()?;
    mesh.check_coordinate_range()?;
    let mut stats = ExtractStats {
        triangles: mesh.num_faces(),
        marching_cubes_grid: find_lattice(mesh),
        ..Default::default()
    };
    let oriented = orient_if_inward(mesh, options, &mut stats);
    let mesh = oriented.as_ref().unwrap_or(mesh);
    let mut clock = StageClock {
        progress,
        times: Vec::new(),
    };

    let repaired;
    let mesh = if options.repair_outliers {
        let t = clock.begin(Stage::Outliers);
        let (moved, repair) = repair_outliers(mesh)?;
        stats.outliers = repair;
        repaired = moved;
        clock.end(Stage::Outliers, t);
        repaired.as_ref().unwrap_or(mesh)
    } else {
        mesh
    };

    let t = clock.begin(Stage::Creases);
    let creases = find_creases(mesh, &options.creases)?;
    stats.crease_threshold = creases.threshold;
    stats.crease_normals_filtered = creases.filtered;
    clock.end(Stage::Creases, t);
    let barriers = creases.barriers(mesh);
    let split = barriers.as_deref();

    let smoothed;
    let surface = if options.pre_smoothing.steps > 0 {
        let t = clock.begin(Stage::PreSmoothing);
        smoothed = smooth_surface(mesh, &options.pre_smoothing)?;
        clock.end(Stage::PreSmoothing, t);
        &smoothed
    } else {
        mesh
    };

    let t = clock.begin(Stage::Curvature);
    let mut curvature = curvature::estimate_split(surface, &options.curvature, split)?;
    stats.fallback_vertices = curvature.fallback_vertices;
    stats.jet_fit = curvature.jet_fit;
    clock.end(Stage::Curvature, t);

    let noise_measured = options.curvature.estimator == Estimator::JetFit;
    let skip = options.smooth_only_noisy && noise_measured && curvature.extremality_noise == 0.0;
    // The lines are moved back by the wide fit's bias when the fit found the surface noisy,
    // and by the smoothing's drift (measured by the smoothing) when that noise is white: where
    // the residual is mostly surface the fit does not follow (scans, subdivided models), the
    // drift is that detail, which the smoothing is there to take out (`lines::debias`).
    let debias = options.debias_lines && noise_measured && curvature.extremality_noise > 0.0;
    let white_noise = curvature.jet_fit.is_some_and(|r| r.white_noise());
    if options.smoothing.steps > 0 && !skip {
        let t = clock.begin(Stage::ExtremalitySmoothing);
        // On white noise: along the lines as the options say, and the drift measured when
        // the lines will be moved back by it.
        let mut smoothing = Cow::Borrowed(&options.smoothing);
        if white_noise {
            smoothing.to_mut().along_lines = options.white_noise_along_lines;
            smoothing.to_mut().measure_drift |= debias;
        }
        match split {
            Some(creases) => {
                smooth_extremalities_split(surface, &mut curvature, &smoothing, creases)?
            }
            None => smooth_extremalities(surface, &mut curvature, &smoothing)?,
        }
        clock.end(Stage::ExtremalitySmoothing, t);
    }

    let t = clock.begin(Stage::Tracing);
    let diagonal = mesh.model_size();
    stats.scale = diagonal;
    let mut traced = trace_by_method(surface, &curvature, &options.pipeline, &mut stats)?;
    clock.end(Stage::Tracing, t);
    if let Pipeline::Ybs(YbsOptions {
        gaps: Some(gaps), ..
    }) = &options.pipeline
    {
        let t = clock.begin(Stage::GapJumping);
        stats.gaps_jumped = jump_crest_gaps(surface, &curvature, &mut traced, gaps);
        clock.end(Stage::GapJumping, t);
    }
    stats.lines_traced = traced.lines.len();

    let t = clock.begin(Stage::Filtering);
    let crest_pipeline = !matches!(options.pipeline, Pipeline::Saliency(_));
    let locate = options.drop_unlocated_lines && white_noise && crest_pipeline;
    if let (true, Some(report)) = (locate, curvature.jet_fit) {
        let noise = slope_noises(surface, &curvature, split);
        stats.lines_unlocated = drop_unlocated_lines(surface, &curvature, noise, &mut traced);
        let window = report.radius * report.spacing;
        stats.lines_trimmed = trim_unlocated_ends(surface, &curvature, noise, window, &mut traced);
    }
    let filter = line_filter(&traced, options, diagonal, &mut stats);
    let mut lines = filter_lines(traced, &filter, diagonal);
    clock.end(Stage::Filtering, t);

    if debias && let Some(report) = curvature.jet_fit {
        let t = clock.begin(Stage::Debiasing);
        let radius = report.radius * report.spacing;
        stats.debias = debias_crest_lines(surface, &curvature, &mut lines, radius, split);
        clock.end(Stage::Debiasing, t);
    }

    if options.fairing.tolerance > 0.0 {
        let t = clock.begin(Stage::Fairing);
        fair_lines(&mut lines, &options.fairing, diagonal);
        clock.end(Stage::Fairing, t);
    }
    if !creases.is_empty() {
        let t = clock.begin(Stage::Merging);
        let fit_radius = curvature
            .jet_fit
            .map_or(0.0, |report| report.radius * report.spacing);
        lines = merge_creases(mesh, lines, &creases, &options.merge, fit_radius)?;
        clock.end(Stage::Merging, t);
    }
    stats.stage_times = clock.times;
    count_lines(&lines, &mut stats);
    let extraction = Extraction {
        lines,
        curvature,
        stats,
    };
    debug_assert!(
        extraction.check_finite().is_ok(),
        "{:?}",
        extraction.check_finite()
    );
    Ok(extraction)
}

/// The mesh with its triangles wound against their patch and its inward-facing closed
/// components reversed, or `None` when it needs no change (or `orient_outward` is off):
/// curvature signs follow the normals.
fn orient_if_inward(
    mesh: &TriMesh,
    options: &ExtractOptions,
    stats: &mut ExtractStats,
) -> Option<TriMesh> {
    if !options.orient_outward {
        return None;
    }
    // Classified once: the flags say what `orient_outward` would reverse.
    let (report, reverse) = orientation(mesh);
    stats.orientation = report;
    if report.inward == 0 && report.rewound_faces == 0 {
        return None;
    }
    Some(reverse_faces(mesh.clone(), &reverse))
}

/// Traces the candidate lines of the chosen method: HPW's regular and singular triangles,
/// YBS's edge-based crest lines, or the saliency method's linked feature points (whose
/// thresholds on the saliency are chosen here, [`family_thresholds`]).
fn trace_by_method(
    surface: &TriMesh,
    curvature: &Curvature,
    pipeline: &Pipeline,
    stats: &mut ExtractStats,
) -> Result<FeatureLines> {
    Ok(match pipeline {
        Pipeline::Hpw(_) => {
            let (traced, report) = trace_lines(surface, curvature);
            stats.trace = report;
            traced
        }
        Pipeline::Ybs(_) => trace_crest_lines(surface, curvature, None).0,
        Pipeline::Saliency(mwz) => {
            let saliency = mesh_saliency(surface, curvature, &mwz.saliency)?;
            // No knee: a rising curve is split in two; a flat one is a shape without salient
            // parts, no point.
            let no_knee = NoKnee::Split {
                flat: f64::INFINITY,
            };
            let chosen = family_thresholds(&saliency.saliency, curvature, &mwz.threshold, no_knee);
            record_threshold(chosen.all, stats);
            stats.family_thresholds = Some([chosen.ridge, chosen.valley]);
            link_feature_points(
                surface,
                curvature,
                &saliency.saliency,
                |kind| chosen.of(kind),
                &mwz.link,
            )
        }
    })
}

/// The line filter of step 6: the method's strength threshold (HPW and YBS: fixed, or the
/// knee of the traced lines' strengths, [`choose_line_threshold`]) and the minimum length.
/// The saliency method's threshold applies to points, before linking, and the linking applies
/// the strength floor ([`crate::lines::link::LinkOptions::min_strength`]): its lines are
/// filtered by length only.
fn line_filter(
    traced: &FeatureLines,
    options: &ExtractOptions,
    diagonal: f64,
    stats: &mut ExtractStats,
) -> LineFilter {
    let (measure, threshold) = match &options.pipeline {
        Pipeline::Hpw(o) => (o.measure, &o.threshold),
        Pipeline::Ybs(o) => (o.measure, &o.threshold),
        Pipeline::Saliency(_) => {
            return LineFilter {
                measure: StrengthMeasure::CurvatureIntegral,
                threshold: f64::NEG_INFINITY,
                min_length: options.min_length,
            };
        }
    };
    let mut filter = LineFilter {
        measure,
        threshold: threshold.floor(),
        min_length: options.min_length,
    };
    let chosen = choose_line_threshold(traced, &filter, diagonal, threshold);
    record_threshold(chosen, stats);
    filter.threshold = chosen.value;
    filter
}

fn record_threshold(chosen: ChosenThreshold, stats: &mut ExtractStats) {
    stats.threshold = chosen.value;
    stats.threshold_is_auto = chosen.from_knee;
    stats.threshold_is_split = chosen.from_split;
}

/// Fills the statistics' counts and lengths of the final lines.
fn count_lines(lines: &FeatureLines, stats: &mut ExtractStats) {
    let count = |kind: LineKind, crease: bool| {
        lines
            .lines
            .iter()
            .filter(|l| l.kind == kind && l.crease == crease)
            .count()
    };
    stats.lines = lines.lines.len();
    stats.ridges = count(LineKind::Ridge, false);
    stats.valleys = count(LineKind::Valley, false);
    stats.crease_ridges = count(LineKind::Ridge, true);
    stats.crease_valleys = count(LineKind::Valley, true);
    stats.total_length = lines.total_length();
    stats.creases = stats.crease_ridges + stats.crease_valleys;
    // A fold from +0: `sum` of no creases would be -0 (printed "-0.000000").
    stats.crease_length = lines.creases(true).fold(0.0, |total, l| total + l.length);
}

impl Extraction {
    /// Checks that every number of the result is finite: the lines' points, lengths,
    /// integrals and strengths, every curvature field and the lengths in the statistics
    /// (`stats.threshold` excepted: it is +∞ when the saliency is flat and the saliency method
    /// keeps no point). A NaN or an infinity would be a bug; [`extract`] checks this in debug
    /// builds, and the tests and fuzz targets call it.
    ///
    /// # Errors
    /// What the first non-finite value is, and where.
    pub fn check_finite(&self) -> std::result::Result<(), String> {
        let bad = |x: f64| !x.is_finite();
        for (i, l) in self.lines.lines.iter().enumerate() {
            if l.points.iter().any(|p| p.iter().any(|&c| bad(c))) {
                return Err(format!("line {i} has a non-finite point"));
            }
            for (name, x) in [
                ("length", l.length),
                ("curvature integral", l.curvature_integral),
                ("strength", l.strength),
            ] {
                if bad(x) {
                    return Err(format!("line {i} has a non-finite {name} ({x})"));
                }
            }
        }
        let c = &self.curvature;
        let scalars = [
            ("k_max", &c.k_max),
            ("k_min", &c.k_min),
            ("e_max", &c.e_max),
            ("e_min", &c.e_min),
        ];
        for (name, values) in scalars {
            if let Some(v) = values.iter().position(|&x| bad(x)) {
                return Err(format!("{name} of vertex {v} is {}", values[v]));
            }
        }
        let vectors = [
            ("dir_max", &c.dir_max),
            ("dir_min", &c.dir_min),
            ("normals", &c.normals),
        ];
        for (name, values) in vectors {
            if let Some(v) = values.iter().position(|p| p.iter().any(|&x| bad(x))) {
                return Err(format!("{name} of vertex {v} is not finite"));
            }
        }
        let s = &self.stats;
        for (name, x) in [
            ("total_length", s.total_length),
            ("crease_length", s.crease_length),
            ("extremality_noise", c.extremality_noise),
        ] {
            if bad(x) {
                return Err(format!("stats: {name} is {x}"));
            }
        }
        Ok(())
    }
}

/// Reports stage starts and ends and keeps the timings.
struct StageClock<'a> {
    progress: &'a mut dyn FnMut(Stage, Option<Duration>),
    times: Vec<(Stage, Duration)>,
}

impl StageClock<'_> {
    fn begin(&mut self, stage: Stage) -> Instant {
        (self.progress)(stage, None);
        Instant::now()
    }

    fn end(&mut self, stage: Stage, start: Instant) {
        let elapsed = start.elapsed();
        self.times.push((stage, elapsed));
        (self.progress)(stage, Some(elapsed));
    }
}
