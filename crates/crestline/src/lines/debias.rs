//! Bias correction of crest-line positions on noisy surfaces: each point of a traced crest
//! line is moved across the line by the displacement the jet fit's disc is known to cause.
//!
//! **Why.** On noisy meshes the jet fit widens its disc with the noise
//! ([`crate::curvature::jet_fit`](mod@crate::curvature::jet_fit), *Scale*: about 9 sample
//! spacings at noise of 0.1 spacing). Its extremality is then a blurred one, and the zeros of
//! a blurred e sit beside the zeros of e wherever the profile of e across the line is not
//! symmetric. On the public `bumpy/noisy20k` case (ridges of Gaussian bumps, broad: k falls
//! by 20% within 4 spacings of the line) the traced lines were the right lines, displaced by a
//! median 1.08 tolerances, mostly by an offset that is constant along each line, not by
//! wiggles. No smaller disc helps: e is a third derivative across the line, so its noise
//! grows like σ / (W^3.5 L^0.5) for a window W wide and L long, and an elongated window
//! ("long along the line, narrow across") would need L ≈ 100 R to halve W at the same
//! noise (measured: a 12 × 5 spacing ellipse halves the bias of e near the bumps' ridges
//! on the clean mesh, RMS 1.18 → 0.56, and more than doubles its error on the noisy one,
//! 1.40 → 3.67). The bias itself, though, is known.
//!
//! **The bias of the fit.** A weighted least-squares polynomial of degree 3 or 4 with the
//! jet fit's weights `(1 − r²/R²)²` on a disc of radius R reproduces the polynomial terms it
//! has; its third derivatives at the centre are biased by the fifth-order terms only (the
//! fourth-order ones are even and the disc is symmetric). Projecting `t⁵` and `s²t³` on the
//! basis gives, for both degrees, `ê = e + β R² Δe + O(R⁴)` with β = 1/28 exactly (the
//! quadrature is in this module's tests). Where the fit's ê crosses zero, the exact e is
//! `−β R² Δe`, so the crest lies `δ = β R² Δe / ∂ₜe` further along t, the direction across
//! the line. Only the part across is used: `Δe ≈ ∂ₜₜe` (the part along the line,
//! `∂ₛₛe = −κ_g ∂ₜe` on a line of geodesic curvature κ_g, was measured to help on the ovoid
//! and the ridge and to hurt on the bumps, from the noise of κ_g). Checked on the clean
//! `bumpy/reg20k` traced with a fixed disc of 8.8 spacings: the offsets of the lines from the
//! exact ones regress on `∂ₜₜe / ∂ₜe` and κ_g with coefficients 2.52 and −2.45 (spacings²),
//! where β R² = 2.76.
//!
//! **Steps**, per crest line (creases are left alone):
//! 1. *Profile.* At each point p, with n the mean of the fit's normals near p, u the
//!    line's direction (a chord over one spacing each way) and v = n × u, the extremality of
//!    the line's family (`e_max` along `dir_max` for ridges, `e_min` along `dir_min` for
//!    valleys, signed to point along v) at the vertices within [`WINDOW`] R of p is fitted by
//!    least squares with `c₀ + c₁t + c₂t² + c₃s + c₄st + c₅s²` (t = (q − p)·v, s = (q − p)·u):
//!    `∂ₜe = c₁`, `∂ₜₜe = 2c₂`. Vertices within R of the mesh boundary, or of a crease (or
//!    non-manifold edge) the fit was split at, where its discs stop as at a boundary, are left
//!    out of the
//!    fit: their discs are one-sided, and their extremalities carry that disc's bias (of
//!    first order in R, from the even terms a symmetric disc cancels), not the `β R² Δe`
//!    this module corrects. Measured on the public noisy ridge (an open height field, R ≈ 9
//!    spacings): with them, the valleys' points between R and 1.7 R from the boundary (a
//!    third of them) moved 0.12 and 0.23 tolerances away from the exact lines on average,
//!    those farther in 0.01 and 0.09, and the two valleys, mirror images of each other, got
//!    `∂ₜₜe / ∂ₜe` of −0.04 and 3.6 per unit where the same fit on the clean mesh gives ±0.99;
//!    without them the correction falls below its noise there, as it should (the clean
//!    mesh's valleys, fitted with the same disc, sit within 0.02 tolerances of the exact ones).
//! 2. *Along the line.* The bias changes slowly along a line and the noise of these
//!    derivatives does not: `c₁` and `c₂` are averaged along the line with Gaussian weights
//!    of width R in arc length (the fit's own scale), and δ = β R² 2c̄₂ / c̄₁. A mean c̄₁ of the
//!    wrong sign for the family (a ridge's e decreases across it) leaves the point alone, and
//!    so does a crest sharper than the disc (*Sharp crests* below).
//! 3. *Shrinkage.* The extremalities carry a simulation of what the measured noise makes of
//!    them ([`Curvature::simulated_noise`]); the same fits and averages of it give the
//!    variances the noise leaves in c̄₁ and c̄₂ (their mean squares over the line), and δ is
//!    divided by `1 + var(c̄₂)/c̄₂² + var(c̄₁)/c̄₁²` (a Wiener factor), so that a correction
//!    not clearly above its own noise fades out. Measured in a prototype without it: the
//!    lines of the noisy ovoid and ridge, where the bias is small, lost 0.02 to 0.07 F1.
//! 4. *Move.* p + δ v, with |δ| (the smoothing's drift below included) at most
//!    [`MAX_SHIFT`] R, projected back onto the mesh (its location becomes the face it lands
//!    in). Points within R of the mesh boundary or of a crease the fit was split at stay (the
//!    disc is one-sided there and the bias is not the symmetric one: beside the creases of
//!    noisy parts, where the spread of e grows manyfold towards the crease, lines along a
//!    crease were moved off it by a spacing or two, out of the reach of
//!    [`super::merge`], and came back joined to it as combs of short valleys; the rounded
//!    box of `bench/quality/noisy_parts.py` under noise of 0.05 to 0.1 of the mean edge, F1 0.89 to
//!    0.94 → 0.93 to 0.97), and so do line ends shared with another line, so that
//!    lines that meet still meet. No segment of the moved line may keep less than half its
//!    length along the original one (`keep_unfolded`, on the targets before they are put
//!    back on the mesh): where a point that stays is beside one that moves far along the
//!    line, or a move towards the centre of the line's turn exceeds half its radius, the
//!    moves at both ends are halved until it does (each at most four times, then dropped),
//!    so that a line does not fold back on itself.
//!
//! **Smoothing drift.** The lines are traced on the smoothed extremalities
//! ([`crate::smoothing::extremality`]), and smoothing moves the zeros of a field that bends
//! on its own scale. Twicing removes the first-order part of that move, which is all of it
//! where e is a quadratic over the smoothing's reach, not where the crests bend within a few
//! spacings, as the public noisy sphere's bumps do. Measured on the clean `bumpy/reg20k`
//! traced with the noisy case's disc (`score.py "crestline extract {in} -o {out} -q --radius
//! 8.77 --no-noise-adaptation [--smooth-steps 0]"`): F1 0.903 without the smoothing, 0.826
//! with it. The smoothing's move is not known in closed form, but the smoothing can be
//! applied again: the change d it makes to the smoothed field ([`Curvature::smoothing_drift`],
//! measured by the smoothing when [`crate::extract`] is to move the lines and the fit found the
//! noise white, below) moves the traced zero again by `−d / ∂ₜe`, so the zero before smoothing
//! lies about `d / ∂ₜe` further along v. That is a lower estimate: applied to an already
//! smoothed profile, whose bend the first pass softened, the smoothing moves it less than it
//! moved the raw one (about half where the profile bends within two spacings; unit test in
//! `smoothing::extremality`). d is fitted as e is (step 1; its value at p), averaged alike
//! (step 2), and `c̄_d / c̄₁` is added to δ, shrunk by the positive part of `1 − var(c̄_d) /
//! c̄_d²` (the shrinkage of James and Stein's estimator, for this one value; the variance from
//! the drift of the simulated noise, [`Curvature::smoothing_drift_noise`], as in step 3; the
//! slope's is left to step 3's factor). The Wiener factor of step 3 let more noise through: on
//! noisy ovoids and ridges made like the public ones it cost up to 0.03 F1 where this costs up
//! to 0.021. Fitting the unsmoothed extremalities' profile instead of d finds all of the move,
//! with their noise (the noisy ridges made alike lost up to 0.058). Measured (`score.py`,
//! default settings): `bumpy/noisy20k` HPW 0.806 → 0.846, YBS 0.811 → 0.848, saliency 0.804 →
//! 0.842, `ridge/noisy20k` 0.969 → 0.963; 36 noisy surfaces made alike (the public reg20k and
//! irr20k moved along their exact normals by 0.05 to 0.1 of the mean edge, other seeds), HPW
//! mean 0.889 → 0.899: the bumpy spheres +0.024 to +0.084, the ovoids −0.029 to 0, the ridges
//! −0.021 to 0, the superquadrics unchanged (YBS alike); 56 noisy CAD parts made alike
//! (`score_cad.py`) −0.012 to +0.003 (the least, the rounded box, whose fillets' tangent seams
//! carry crest lines).
//! *Only on white noise* ([`crate::curvature::jet_fit::JetFitReport::white_noise`]): where the
//! fit's residual is mostly surface it does not follow (scans, subdivided models), the drift is
//! that surface's detail, which the smoothing is there to take out, and the lines it moves back
//! follow the detail: measured on every noisy mesh, the total turning of the lines of horse ×16
//! (Loop subdivision, whose curvature ripples at the scale of the coarse edges) grew by 34%,
//! igea's and the bunny's by 2%, and the drift cost horse ×16's smoothing 1.9 → 2.7 s. The
//! moves are kept from folding the line (step 4): with the drift on the shared scans their
//! corrected lines turned back at 1 to 4 segments (the bunny, igea, the horse, the rocker arm),
//! with the fit's bias alone at 1 and 2 (igea, the horse).
//!
//! **Measured** (`../shared/quality/score.py`, default HPW; YBS alike): `bumpy/noisy20k`
//! F1 0.466 → 0.710 (median distance of the ridges to the exact ones 1.08 → 0.72
//! tolerances), four more noisy bumpy spheres (noise 0.05 and 0.1 of the mean edge, other
//! seeds) +0.10 to +0.25; `ridge/noisy20k` 0.966 → 0.969 (0.952 before the vertices near
//! the boundary were left out of step 1); clean meshes unchanged (it does not run).
//! On 24 further noisy surfaces made alike (the public reg20k and irr20k of the bumpy sphere,
//! ovoid, ridge and superquadric moved along their exact normals by 0.07 and 0.1 of the
//! mean edge, three seeds; `score.py --cases`) the mean F1 goes 0.795 → 0.838: the bumpy
//! spheres +0.15 to +0.28, the others −0.026 to 0.000. The saliency method's lines (linked
//! crest points) alike: `bumpy/noisy20k` 0.466 → 0.815, the 24 made alike 0.700 → 0.750
//! (bumps +0.15 to +0.30, the others −0.012 to +0.001).
//! *Limit:* where the crest is symmetric (the ovoid's equator) there is no bias to remove and
//! the correction adds only the noise of its estimate: up to −0.026 F1 on a noise of 0.1 of
//! the mean edge.
//!
//! **Sharp crests.** The bias model is a Taylor expansion of a surface smooth over the disc.
//! A crease is not: the edge of a machined part under the noise of a scan (too noisy for
//! [`crate::lines::crease`] to find it) is traced as a crest of the widened fit, and the
//! formula, fed the fit's response to a kink, moved such lines by up to a third of the disc
//! (the rims of a pipe elbow onto its end faces). So at each point the mesh's own bend
//! across the line is measured from its vertex normals (their component across the line,
//! `g = n · v`, averaged over strips along the line, at distances r from it in the plane
//! across it): within a spacing of the line (the change of g between the strips at r ≈ ±h)
//! and farther out (from those strips to the ones at the window's edge, per side). Both are
//! averaged along the line as in step 2, and where the inner bend, of the family's sign, is
//! more than [`SHARPNESS`] times the outer one (either sign) the point stays: the surface
//! turns within a spacing of the line, not over the disc. Measured per line (median over its
//! points of the ratio of the two bends): the lines of the public and made-alike noisy
//! surfaces 0.9 to 2.2 (1.8% of their points above 2, most on the ridge's valleys and the
//! bumps' short valleys), the edges of noisy machined parts 2.2 to 400 or of opposite
//! signs, a few at 1.3 to 2 (the hex nut's 30° chamfers). Measured (`score_cad.py --cases`,
//! the eight public uniform parts with normal noise of 0.05 and 0.1 of the mean edge, made
//! here): HPW mean F1 0.666 → 0.798 (0.797 without the debias), YBS 0.671 → 0.807; the pipe
//! elbow at 0.1 0.000 → 0.717, the slotted plate at 0.05 0.044 → 0.719; the public noisy
//! cases unchanged, the 36 made alike unchanged but one (−0.004). On the shared scans the
//! debias ran on lines whose residual is surface the fit does not follow (not white noise);
//! it now leaves many of those points alone.
//!
//! [`crate::extract`] runs it on the jet fit's lines by default
//! ([`crate::extract::ExtractOptions::debias_lines`], CLI `--no-debias` to skip it) when the
//! fit found the surface noisy ([`crate::curvature::Curvature::extremality_noise`] > 0): on
//! clean meshes the disc is small (2.5 spacings), the bias negligible and the extremalities
//! are not smoothed.

use std::collections::HashMap;

use nalgebra::{Matrix6, Matrix6x4, Vector4, Vector6};
use rayon::prelude::*;

use super::assemble::integrate;
use super::{FeatureLine, FeatureLines, LineKind, SurfacePoint, arc_lengths};
use crate::curvature::Curvature;
use crate::curvature::jet_fit::{disc_rims, one_sided_vertices};
use crate::mesh::{TriMesh, Vec3, vertex_normals_area};
use crate::spatial::{FaceGrid, PointGrid};

/// The bias coefficient of the jet fit's third derivatives: `ê = e + β R² Δe` (see the
/// module docs), for the weights `(1 − r²/R²)²` and degree 3 or 4.
pub const FIT_BIAS: f64 = 1.0 / 28.0;

/// Radius of the window of step 1, as a fraction of the fit radius R. The fit's e is smooth
/// over about R; a quadratic across describes it over a part of that. Measured (a prototype
/// of this module) on the public noisy bumps at R ≈ 8.8 spacings: windows of 4, 6, 9 and 12
/// spacings gave F1 0.70, 0.73, 0.69, 0.62 (0.7 R ≈ 6 spacings); 9 and 12 were better on the
/// noisy ridge (0.954 against 0.940).
pub const WINDOW: f64 = 0.7;

/// Largest move, as a fraction of the fit radius R.
pub const MAX_SHIFT: f64 = 1.0 / 3.0;

/// A crest is sharper than the fit's disc, and left where the fit put it, where the mesh
/// bends across the line within a spacing of it more than this many times as much as from
/// there to the window's edge (both from its vertex normals, see the module docs, *Sharp
/// crests*). The bias model is a Taylor expansion of the surface over the disc; at a crease
/// (a CAD part's edge under noise, too noisy for [`crate::lines::crease`] to find) the
/// surface has none: it turns within a spacing and is flat beyond. Where the disc resolves
/// the crest the two bends are alike (a crest narrower than the window bends less farther
/// out); 2 says "the surface turns more than twice as fast at the line as around it".
pub const SHARPNESS: f64 = 2.0;

/// Halvings of a point's move, where it folds or pinches the line (step 4), before it is
/// dropped.
const FOLD_HALVINGS: u8 = 4;

/// Step 4's guard, on the points' targets (before they are put back on the mesh): shrinks the
/// moves of a line's points until every segment of the moved line keeps at least half the
/// original segment's length along it. Where neighbouring moves would fold the line back or
/// pinch it (a point that stays beside one that moves far along the line; a move towards the
/// centre of the line's turn by more than half its radius), the moves at both ends of the
/// segment are halved, each point's [`FOLD_HALVINGS`] times at most, and then dropped. A
/// move across a straight line beside one that stays is a spike, not a fold, and is kept.
/// Each round tests the segments next to the moves the last round changed (all of them at
/// first) and then shrinks, so that the result does not depend on the line's direction or,
/// for a closed line, its first point, and every point changes at most five times.
fn keep_unfolded(points: &[Vec3], closed: bool, moves: &mut [Vec3]) {
    let n = points.len();
    let segments = if closed { n } else { n.saturating_sub(1) };
    let mut halvings = vec![0u8; n];
    let mut test: Vec<usize> = (0..segments).collect();
    while !test.is_empty() {
        let mut shrink = Vec::new();
        for &k in &test {
            let j = (k + 1) % n;
            let original = points[j] - points[k];
            // Written alike from either end, so that a reversed line is tested alike.
            let moved = (points[j] + moves[j]) - (points[k] + moves[k]);
            if moved.dot(&original) < 0.5 * original.norm_squared() {
                shrink.extend([k, j]);
            }
        }
        shrink.sort_unstable();
        shrink.dedup();
        test.clear();
        for &i in &shrink {
            if halvings[i] < FOLD_HALVINGS {
                halvings[i] += 1;
                moves[i] *= 0.5;
            } else {
                moves[i] = Vec3::zeros();
            }
            // The segments on either side of point i.
            if closed || i > 0 {
                test.push((i + n - 1) % n);
            }
            if closed || i + 1 < n {
                test.push(i);
            }
        }
        test.sort_unstable();
        test.dedup();
    }
}

/// The fewest vertices a profile fit of step 1 takes.
const MIN_SAMPLES: usize = 10;

/// What [`debias_crest_lines`] did.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct DebiasReport {
    /// Points moved.
    pub moved: usize,
    /// The median distance they moved (model units); 0 when none moved.
    pub median_shift: f64,
    /// Of the points moved, those whose move includes the smoothing's drift (module docs,
    /// *Smoothing drift*; 0 unless the smoothing measured it).
    pub with_drift: usize,
}

/// Moves the points of the crest lines in `lines` across the lines by the bias of a jet fit
/// of radius `radius` (model units), estimated from `curvature`'s extremalities on `mesh`
/// (see the module docs), and updates the lengths. Creases, lines of fewer than three points
/// and a non-positive or non-finite radius are left as they are. `barriers` flags the edges
/// the fit was split at (creases, non-manifold edges; per edge of
/// [`crate::mesh::Topology::edges`]): within `radius` of them, as of the boundary, the discs
/// were one-sided.
pub fn debias_crest_lines(
    mesh: &TriMesh,
    curvature: &Curvature,
    lines: &mut FeatureLines,
    radius: f64,
    barriers: Option<&[bool]>,
) -> DebiasReport {
    if !(radius.is_finite() && radius > 0.0) || curvature.len() != mesh.num_vertices() {
        return DebiasReport::default();
    }
    let context = Context::new(mesh, curvature, radius, barriers);
    let shared = shared_ends(lines);
    // Each line reads only itself, the fields and the shared ends (taken before any move).
    // Per point moved: how far, and whether the drift was part of the move.
    let moves: Vec<(f64, bool)> = lines
        .lines
        .par_iter_mut()
        .filter(|l| !l.crease && l.points.len() >= 3)
        .flat_map_iter(|line| {
            let mut moves = Vec::new();
            context.debias_line(line, &shared, &mut moves);
            let zeros = vec![0.0; line.points.len()];
            line.length = integrate(&line.points, &zeros, &zeros, line.closed).0;
            moves
        })
        .collect();
    let mut shifts: Vec<f64> = moves.iter().map(|m| m.0).collect();
    shifts.sort_by(f64::total_cmp);
    DebiasReport {
        moved: shifts.len(),
        median_shift: shifts.get(shifts.len() / 2).copied().unwrap_or(0.0),
        with_drift: moves.iter().filter(|m| m.1).count(),
    }
}

/// The mesh, its fields and the grids the lines are corrected with.
struct Context<'a> {
    mesh: &'a TriMesh,
    curvature: &'a Curvature,
    radius: f64,
    /// The mesh's sample spacing: the unit of the tangent's chord.
    spacing: f64,
    vertices: PointGrid,
    /// The boundary's vertices and the creases' ([`disc_rims`]); `None` without either.
    rims: Option<PointGrid>,
    /// Per vertex: within R of the mesh boundary or of a crease, where the fit's disc is
    /// one-sided and its extremalities carry another bias than the symmetric disc's (empty
    /// on closed meshes without creases).
    one_sided: Vec<bool>,
    faces: FaceGrid<'a>,
    /// The mesh's area-weighted vertex normals (the one-ring's, not the fit's).
    mesh_normals: Vec<Vec3>,
}

/// One point's profile fit (step 1).
#[derive(Debug, Clone, Copy)]
struct Profile {
    /// Unit direction across the line (n × u).
    across: Vec3,
    /// ∂ₜe.
    slope: f64,
    /// ∂ₜₜe.
    bend: f64,
    /// ∂ₜₜ of the simulated noise of e ([`Curvature::simulated_noise`]): what noise of the
    /// measured level makes of `bend` (0 without a simulation).
    noise_bend: f64,
    /// The same for `slope`.
    noise_slope: f64,
    /// The smoothing's drift of e at p ([`Curvature::smoothing_drift`], the profile's value
    /// at t = s = 0; 0 without it).
    drift: f64,
    /// The same for the drift's noise ([`Curvature::smoothing_drift_noise`]).
    noise_drift: f64,
    /// The mesh's own curvature across the line within a spacing of it, and across the
    /// rest of the window (see [`SHARPNESS`], [`Context::sharpness`]); `None` when not
    /// measured.
    sharpness: Option<(f64, f64)>,
}

impl<'a> Context<'a> {
    fn new(
        mesh: &'a TriMesh,
        curvature: &'a Curvature,
        radius: f64,
        barriers: Option<&[bool]>,
    ) -> Self {
        let positions = mesh.positions();
        let window = WINDOW * radius;
        let rims = disc_rims(mesh, barriers);
        let rims = (!rims.is_empty()).then(|| PointGrid::new(&rims, radius));
        // The fit's own flags when it has them (the same radius in `extract`), which do not
        // mark the creases' one-sided discs.
        let one_sided = if barriers.is_none() && curvature.one_sided.len() == mesh.num_vertices() {
            curvature.one_sided.clone()
        } else {
            one_sided_vertices(mesh, radius, barriers)
        };
        let ((vertices, faces), mesh_normals) = rayon::join(
            || rayon::join(|| PointGrid::new(positions, window), || FaceGrid::new(mesh)),
            || vertex_normals_area(mesh),
        );
        Context {
            mesh_normals,
            mesh,
            curvature,
            radius,
            one_sided,
            spacing: curvature
                .jet_fit
                .map_or(radius / 8.0, |report| report.spacing),
            vertices,
            rims,
            faces,
        }
    }

    fn debias_line(
        &self,
        line: &mut FeatureLine,
        shared: &HashMap<[u64; 3], usize>,
        out: &mut Vec<(f64, bool)>,
    ) {
        let n = line.points.len();
        let arc = arc_lengths(&line.points, line.closed);
        let total = arc[n];
        let profiles: Vec<Option<Profile>> = (0..n)
            .map(|k| {
                let p = line.points[k];
                let near_rim = self
                    .rims
                    .as_ref()
                    .is_some_and(|b| b.nearest_within(p, self.radius).is_some());
                if near_rim {
                    return None;
                }
                let u = chord(&line.points, &arc, line.closed, k, self.spacing)?;
                self.profile(p, u, line.kind)
            })
            .collect();
        let sigma = self.radius;
        let scale = FIT_BIAS * self.radius * self.radius;
        let mut moved = line.points.clone();
        let mut locations = line.locations.clone();
        // Gaussian averages along the line (step 2) at every point.
        let pooled: Vec<Option<Pooled>> = (0..n)
            .map(|k| {
                profiles[k]?;
                let mut sum = Pooled::default();
                for (j, profile) in profiles.iter().enumerate() {
                    let Some(profile) = profile else { continue };
                    let mut d = (arc[j] - arc[k]).abs();
                    if line.closed {
                        d = d.min(total - d);
                    }
                    if d <= 3.0 * sigma {
                        sum.add((-0.5 * (d / sigma).powi(2)).exp(), profile);
                    }
                }
                Some(sum.mean())
            })
            .collect();
        // The variance the noise gives the mean ∂ₜₜe: the line's mean square of the
        // simulated noise's (step 3).
        let means = pooled.iter().flatten();
        let count = means.clone().count().max(1) as f64;
        let bend_variance = means.clone().map(|p| p.noise_bend.powi(2)).sum::<f64>() / count;
        let slope_variance = means.clone().map(|p| p.noise_slope.powi(2)).sum::<f64>() / count;
        let drift_variance = means.map(|p| p.noise_drift.powi(2)).sum::<f64>() / count;
        // A variance relative to a squared value; no variance is none relative to a zero value.
        let relative = |variance: f64, value: f64| {
            if variance > 0.0 {
                variance / (value * value)
            } else {
                0.0
            }
        };
        // Each point's move (zero where it stays), before the fold guard of step 4, and
        // whether the smoothing's drift is part of it.
        let mut moves = vec![Vec3::zeros(); n];
        let mut with_drift = vec![false; n];
        for k in 0..n {
            let (Some(here), Some(mean)) = (profiles[k], pooled[k]) else {
                continue;
            };
            let open_end = !line.closed && (k == 0 || k == n - 1);
            if open_end && shared.get(&key(line.points[k])).is_some_and(|&c| c > 1) {
                continue;
            }
            let is_crest = match line.kind {
                LineKind::Ridge => mean.slope < 0.0,
                LineKind::Valley => mean.slope > 0.0,
            };
            if !is_crest || mean.is_sharp(line.kind) {
                continue;
            }
            // Relative variance of the ratio bend / slope (to first order), and the Wiener
            // factor 1 / (1 + that).
            let ratio = relative(bend_variance, mean.bend) + relative(slope_variance, mean.slope);
            let mut shift = scale * mean.bend / mean.slope / (1.0 + ratio);
            // The smoothing's drift (module docs, *Smoothing drift*), where it stands clear of
            // its noise: shrunk by the positive part of 1 − var / drift² (James–Stein).
            if mean.drift != 0.0 {
                let shrink = (1.0 - relative(drift_variance, mean.drift)).max(0.0);
                shift += mean.drift / mean.slope * shrink;
                with_drift[k] = shrink > 0.0;
            }
            let limit = MAX_SHIFT * self.radius;
            let shift = shift.clamp(-limit, limit);
            let step = here.across * shift;
            if step.iter().all(|c| c.is_finite()) {
                moves[k] = step;
            }
        }
        keep_unfolded(&line.points, line.closed, &mut moves);
        for (k, step) in moves.iter().enumerate() {
            if *step == Vec3::zeros() {
                continue;
            }
            let Some(landing) = self.faces.closest_point(line.points[k] + step) else {
                continue;
            };
            out.push(((landing.point - line.points[k]).norm(), with_drift[k]));
            moved[k] = landing.point;
            if let Some(location) = locations.get_mut(k) {
                *location = SurfacePoint::Face { face: landing.face };
            }
        }
        line.points = moved;
        line.locations = locations;
    }

    /// Step 1 at `p`: the least-squares quadratic of the family's extremality across and
    /// along the line, or `None` when too few vertices are near or the system is singular.
    fn profile(&self, p: Vec3, u: Vec3, kind: LineKind) -> Option<Profile> {
        let c = self.curvature;
        let family = match kind {
            LineKind::Ridge => 0,
            LineKind::Valley => 1,
        };
        let (e, dir) = [(&c.e_max, &c.dir_max), (&c.e_min, &c.dir_min)][family];
        // The fields the profile fits besides e: its simulated noise, the smoothing's drift
        // and the drift's noise (each absent unless there is one value per vertex).
        let others = [
            &c.simulated_noise[family],
            &c.smoothing_drift[family],
            &c.smoothing_drift_noise[family],
        ]
        .map(|field| (field.len() == e.len()).then_some(field));
        let window = WINDOW * self.radius;
        let mut near = Vec::new();
        let mut normal = Vec3::zeros();
        self.vertices.for_each_within(p, window, |v, _| {
            if self.one_sided.get(v as usize).copied().unwrap_or(false) {
                return;
            }
            near.push(v as usize);
            normal += c.normals[v as usize];
        });
        if near.len() < MIN_SAMPLES || normal.norm() == 0.0 {
            return None;
        }
        let normal = normal.normalize();
        let along = (u - normal * u.dot(&normal)).try_normalize(1e-12)?;
        let across = normal.cross(&along);
        // Coordinates in units of the window, so the system is well scaled.
        let mut ata = Matrix6::<f64>::zeros();
        // Right-hand sides: e, then the `others` (zero where absent).
        let mut atb = Matrix6x4::<f64>::zeros();
        let positions = self.mesh.positions();
        for &v in &near {
            let d = (positions[v] - p) / window;
            let (t, s) = (d.dot(&across), d.dot(&along));
            let sign = if dir[v].dot(&across) < 0.0 { -1.0 } else { 1.0 };
            let row = Vector6::new(1.0, t, t * t, s, s * t, s * s);
            ata += row * row.transpose();
            let [noise, drift, drift_noise] = others.map(|f| f.map_or(0.0, |f| f[v]));
            let values = Vector4::new(e[v], noise, drift, drift_noise) * sign;
            atb += row * values.transpose();
        }
        let x = ata.cholesky()?.solve(&atb);
        let (coefficients, noise) = (x.column(0), x.column(1));
        Some(Profile {
            across,
            slope: coefficients[1] / window,
            bend: 2.0 * coefficients[2] / (window * window),
            noise_bend: 2.0 * noise[2] / (window * window),
            noise_slope: noise[1] / window,
            drift: x[(0, 2)],
            noise_drift: x[(0, 3)],
            sharpness: self.sharpness(p, &near, [normal, across, along]),
        })
    }

    /// The mesh's curvature across the line at `p`, within a spacing of it and over the rest
    /// of the window (see [`SHARPNESS`]), from the component across the line of the mesh's
    /// vertex normals, `g = n · across`, averaged over strips along the line (`|s| ≤ 2h`) at
    /// a distance r from it in the plane across it (signed by the side, the sign of t): inner
    /// strips at `h/2 ≤ |r| ≤ 3h/2` and outer strips at `5/7 ≤ |r| / window ≤ 1`. The inner
    /// curvature is the change of g between the two inner strips over the distance of their
    /// mean r; the outer one, per side, the change of g from the inner strip to the outer one
    /// over theirs, averaged over the sides that have both (a thin part may end within the
    /// window on one side). Vertices whose mesh normal faces away from `normal` (the far side
    /// of a thin part within the window) are left out. `None` when an inner strip is empty,
    /// neither side has its outer strip, or the window is too small for the strips to be
    /// apart (a disc of 3 spacings or less: the noise-adapted fit widens it on noisy meshes,
    /// but `--no-noise-adaptation` keeps 2.5).
    fn sharpness(
        &self,
        p: Vec3,
        near: &[usize],
        [normal, across, along]: [Vec3; 3],
    ) -> Option<(f64, f64)> {
        let h = self.spacing;
        let window = WINDOW * self.radius;
        let (inner, outer) = (0.5 * h..=1.5 * h, window * 5.0 / 7.0..=window);
        if *outer.start() <= *inner.end() {
            return None;
        }
        let positions = self.mesh.positions();
        // Per side (r < 0, r > 0) and strip (inner, outer): the sums of g and of r, and the
        // count.
        let mut strips = [[(0.0, 0.0, 0usize); 2]; 2];
        for &v in near {
            if self.mesh_normals[v].dot(&normal) <= 0.0 {
                continue;
            }
            let d = positions[v] - p;
            let (t, s) = (d.dot(&across), d.dot(&along));
            if s.abs() > 2.0 * h {
                continue;
            }
            // The distance from the line in the plane across it, signed by the side: the
            // across coordinate t shrinks on faces that slope away from the tangent plane (on
            // the faces of a right-angled edge t ≤ 0.71 r, and the outer strips would stay
            // empty).
            let r = (d.norm_squared() - s * s).max(0.0).sqrt().copysign(t);
            let strip = if inner.contains(&r.abs()) {
                0
            } else if outer.contains(&r.abs()) {
                1
            } else {
                continue;
            };
            let sum = &mut strips[usize::from(r > 0.0)][strip];
            sum.0 += self.mesh_normals[v].dot(&across);
            sum.1 += r;
            sum.2 += 1;
        }
        // The strip's mean g and mean r.
        let mean = |(g, r, count): (f64, f64, usize)| {
            (count > 0).then(|| (g / count as f64, r / count as f64))
        };
        let [below, above] = strips.map(|side| side.map(mean));
        let (below_in, above_in) = (below[0]?, above[0]?);
        // The change of g over the change of r between two strips' means.
        let bend = |(g0, r0): (f64, f64), (g1, r1): (f64, f64)| (g1 - g0) / (r1 - r0);
        let inner_curvature = bend(below_in, above_in);
        let sides: Vec<f64> = [
            below[1].map(|out| bend(out, below_in)),
            above[1].map(|out| bend(above_in, out)),
        ]
        .into_iter()
        .flatten()
        .collect();
        if sides.is_empty() {
            return None;
        }
        let outer_curvature = sides.iter().sum::<f64>() / sides.len() as f64;
        Some((inner_curvature, outer_curvature))
    }
}

/// Gaussian-weighted sums, then means, of the profiles along a line.
#[derive(Debug, Clone, Copy, Default)]
struct Pooled {
    weight: f64,
    slope: f64,
    bend: f64,
    noise_bend: f64,
    noise_slope: f64,
    drift: f64,
    noise_drift: f64,
    /// Weight of the profiles with a sharpness, and their weighted sums of the mesh's
    /// curvature across the line within a spacing of it and farther out (sums: only their
    /// ratio is read).
    sharp_weight: f64,
    inner_curvature: f64,
    outer_curvature: f64,
}

impl Pooled {
    fn add(&mut self, g: f64, profile: &Profile) {
        self.weight += g;
        self.slope += g * profile.slope;
        self.bend += g * profile.bend;
        self.noise_bend += g * profile.noise_bend;
        self.noise_slope += g * profile.noise_slope;
        self.drift += g * profile.drift;
        self.noise_drift += g * profile.noise_drift;
        if let Some((inner, outer)) = profile.sharpness {
            self.sharp_weight += g;
            self.inner_curvature += g * inner;
            self.outer_curvature += g * outer;
        }
    }

    fn mean(self) -> Self {
        let w = self.weight;
        Pooled {
            weight: w,
            slope: self.slope / w,
            bend: self.bend / w,
            noise_bend: self.noise_bend / w,
            noise_slope: self.noise_slope / w,
            drift: self.drift / w,
            noise_drift: self.noise_drift / w,
            ..self
        }
    }

    /// True when the crest is sharper than the fit's disc (see [`SHARPNESS`]): the mesh
    /// bends across the line (ridges: convex, valleys: concave) within a spacing of it more
    /// than [`SHARPNESS`] times as much as farther out, either way.
    fn is_sharp(&self, kind: LineKind) -> bool {
        let sign = match kind {
            LineKind::Ridge => 1.0,
            LineKind::Valley => -1.0,
        };
        let (inner, outer) = (sign * self.inner_curvature, sign * self.outer_curvature);
        self.sharp_weight > 0.0 && inner > SHARPNESS * outer.abs()
    }
}

/// The line's direction at point `k`: the chord between the points `reach` before and after
/// it in arc length (clamped to the ends of an open line, wrapped around a closed one).
fn chord(points: &[Vec3], arc: &[f64], closed: bool, k: usize, reach: f64) -> Option<Vec3> {
    let n = points.len();
    let total = arc[n];
    let at = |s: f64| -> Vec3 {
        let s = if closed {
            s.rem_euclid(total)
        } else {
            s.clamp(0.0, arc[n - 1])
        };
        // The segment holding s: arc[i] <= s <= arc[i + 1] (i = n - 1: the closing one).
        let i = arc[..n].partition_point(|&a| a <= s).saturating_sub(1);
        let (a, b) = (points[i], points[(i + 1) % n]);
        let length = arc[i + 1] - arc[i];
        let f = if length > 0.0 {
            (s - arc[i]) / length
        } else {
            0.0
        };
        a + (b - a) * f.clamp(0.0, 1.0)
    };
    (at(arc[k] + reach) - at(arc[k] - reach)).try_normalize(1e-300)
}

/// How many line ends sit at each position (bitwise), for ends shared by lines that meet.
fn shared_ends(lines: &FeatureLines) -> HashMap<[u64; 3], usize> {
    let mut ends = HashMap::new();
    for line in lines
        .lines
        .iter()
        .filter(|l| !l.closed && !l.points.is_empty())
    {
        let last = line.points.len() - 1;
        for p in [line.points[0], line.points[last]] {
            *ends.entry(key(p)).or_insert(0) += 1;
        }
    }
    ends
}

fn key(p: Vec3) -> [u64; 3] {
    [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// β = 1/28: the third derivative along t of a weighted least-squares quartic (and cubic)
    /// on the unit disc with weights (1 − r²)², fitted to t⁵ and to s²t³, by quadrature
    /// exact for these polynomials.
    #[test]
    fn fit_bias_is_one_twenty_eighth() {
        for degree in [3usize, 4] {
            let terms: Vec<(i32, i32)> = (0..=degree as i32)
                .flat_map(|i| (0..=degree as i32 - i).map(move |j| (i, j)))
                .collect();
            let m = terms.len();
            // Gauss–Legendre in r on [0, 1] (8 nodes), uniform in the angle (32 nodes).
            let (nodes, weights) = gauss_legendre_8();
            let mut ata = nalgebra::DMatrix::<f64>::zeros(m, m);
            let mut atb5 = nalgebra::DVector::<f64>::zeros(m);
            let mut atb23 = nalgebra::DVector::<f64>::zeros(m);
            for (x, wx) in nodes.iter().zip(&weights) {
                let r = 0.5 * (x + 1.0);
                for a in 0..32 {
                    let angle = a as f64 * std::f64::consts::TAU / 32.0;
                    let (s, t) = (r * angle.cos(), r * angle.sin());
                    let w = 0.5 * wx * r * (1.0 - r * r).powi(2);
                    let row = nalgebra::DVector::from_iterator(
                        m,
                        terms.iter().map(|&(i, j)| s.powi(i) * t.powi(j)),
                    );
                    ata += &row * row.transpose() * w;
                    atb5 += &row * (t.powi(5) * w);
                    atb23 += &row * (s * s * t.powi(3) * w);
                }
            }
            let t3 = terms.iter().position(|&ij| ij == (0, 3)).unwrap();
            let solve = |b: &nalgebra::DVector<f64>| ata.clone().cholesky().unwrap().solve(b);
            // ∂ₜ³ of the fit is 6 c₀₃; ∂ₜ⁵ t⁵ = 120 and ∂ₜ²(∂ₛ²∂ₜ³) s²t³ = 12 · 1... (Δe terms).
            let beta5 = 6.0 * solve(&atb5)[t3] / 120.0;
            let beta23 = 6.0 * solve(&atb23)[t3] / 12.0;
            assert!((beta5 - FIT_BIAS).abs() < 1e-9, "degree {degree}: {beta5}");
            assert!(
                (beta23 - FIT_BIAS).abs() < 1e-9,
                "degree {degree}: {beta23}"
            );
        }
    }

    /// The fields of a flat grid (normal z) whose valley family runs across x (k_min = −1,
    /// `dir_min` = x) with extremality `e_min`; the ridge family flat.
    fn valleys_along_y(e_min: Vec<f64>) -> Curvature {
        let n = e_min.len();
        Curvature {
            k_max: vec![0.0; n],
            k_min: vec![-1.0; n],
            dir_max: vec![Vec3::y(); n],
            dir_min: vec![Vec3::x(); n],
            e_max: vec![0.0; n],
            e_min,
            normals: vec![Vec3::z(); n],
            ..Curvature::default()
        }
    }

    /// The profile of step 1 leaves out the vertices whose fits were one-sided: on a flat
    /// open grid with e = t exactly, except near the boundary where it is far off, a point
    /// whose window reaches those vertices still gets ∂ₜe = 1 and ∂ₜₜe = 0.
    #[test]
    fn profile_leaves_out_one_sided_vertices() {
        let mesh = crate::shapes::height_field(|_, _| 0.0, [-2.0, 2.0], [-2.0, 2.0], 40, 40);
        let radius = 0.5;
        let positions = mesh.positions();
        let e: Vec<f64> = positions
            .iter()
            .map(|p| {
                let inside = p.x.abs() <= 2.0 - radius + 1e-9 && p.y.abs() <= 2.0 - radius + 1e-9;
                // Near the boundary: a bias that would bend the profile.
                if inside { p.x } else { p.x + 50.0 * p.x * p.x }
            })
            .collect();
        let curvature = valleys_along_y(e);
        let context = Context::new(&mesh, &curvature, radius, None);
        // 0.6 from the boundary at x = 2: its window (0.35) reaches vertices within R of it.
        let p = Vec3::new(1.4, 0.0, 0.0);
        let profile = context.profile(p, Vec3::y(), LineKind::Valley).unwrap();
        // e_min along dir_min = x, signed along the across direction: slope 1 in t.
        assert!((profile.slope - 1.0).abs() < 1e-9, "{profile:?}");
        assert!(profile.bend.abs() < 1e-6, "{profile:?}");
    }

    /// The same beside a crease the fit was split at (the grid's column at x = 1): the
    /// vertices within R of it are left out as the boundary's are.
    #[test]
    fn profile_leaves_out_the_vertices_beside_a_crease() {
        let mesh = crate::shapes::height_field(|_, _| 0.0, [-2.0, 2.0], [-2.0, 2.0], 40, 40);
        let radius = 0.5;
        let e: Vec<f64> = mesh
            .positions()
            .iter()
            .map(|p| {
                let d = p.x - 1.0;
                if d.abs() > radius + 1e-9 {
                    p.x
                } else {
                    p.x + 50.0 * d * d
                }
            })
            .collect();
        let curvature = valleys_along_y(e);
        let on = |v: u32| (mesh.position(v).x - 1.0).abs() < 1e-9;
        let crease: Vec<bool> = mesh
            .topology()
            .edges()
            .iter()
            .map(|&[a, b]| on(a) && on(b))
            .collect();
        // 0.6 from the crease: its window (0.35) reaches vertices within R of it.
        let p = Vec3::new(0.4, 0.0, 0.0);
        let profile = |barriers| {
            let context = Context::new(&mesh, &curvature, radius, barriers);
            context.profile(p, Vec3::y(), LineKind::Valley).unwrap()
        };
        let split = profile(Some(&crease));
        assert!((split.slope - 1.0).abs() < 1e-9, "{split:?}");
        assert!(split.bend.abs() < 1e-6, "{split:?}");
        // Without the crease those vertices bend the profile.
        assert!(profile(None).bend.abs() > 1.0, "{:?}", profile(None));
    }

    /// A straight valley on a flat grid, e_min = x (its zero at x = 0), after a smoothing
    /// whose drift field is 0.03 everywhere: applied once more, the smoothing would move the
    /// zero to x = −0.03, so it moved it there from x = 0.03, and the line goes back by
    /// drift / slope; less as the drift's noise grows, not at all once it is above the drift.
    #[test]
    fn lines_go_back_by_the_smoothing_drift_where_it_stands_clear_of_its_noise() {
        let mesh = crate::shapes::height_field(|_, _| 0.0, [-2.0, 2.0], [-2.0, 2.0], 40, 40);
        let n = mesh.num_vertices();
        let moved_to = |drift_noise: Option<f64>| {
            let curvature = Curvature {
                smoothing_drift: [vec![0.0; n], vec![0.03; n]],
                smoothing_drift_noise: match drift_noise {
                    Some(x) => [vec![0.0; n], vec![x; n]],
                    None => Default::default(),
                },
                ..valleys_along_y(mesh.positions().iter().map(|p| p.x).collect())
            };
            let points = (0..=40)
                .map(|k| Vec3::new(0.0, -1.0 + 0.05 * k as f64, 0.0))
                .collect();
            let mut lines = FeatureLines {
                lines: vec![FeatureLine::new(LineKind::Valley, points, false)],
            };
            let report = debias_crest_lines(&mesh, &curvature, &mut lines, 0.5, None);
            let xs: Vec<f64> = lines.lines[0].points.iter().map(|p| p.x).collect();
            (report.moved, xs)
        };
        let (moved, xs) = moved_to(None);
        assert_eq!(moved, 41);
        assert!(xs.iter().all(|x| (x - 0.03).abs() < 1e-9), "{xs:?}");
        // Noise of a third of the drift: shrunk by 1 − 1/9.
        let (_, xs) = moved_to(Some(0.01));
        let expected = 0.03 * (1.0 - 1.0 / 9.0);
        assert!(xs.iter().all(|x| (x - expected).abs() < 1e-9), "{xs:?}");
        // Noise above the drift: the line stays.
        let (_, xs) = moved_to(Some(0.05));
        assert!(xs.iter().all(|x| x.abs() < 1e-9), "{xs:?}");
    }

    /// The same valley beside a crease the fit was split at: within R of it the discs were
    /// one-sided, as at a boundary, and the line stays; a crease farther away changes nothing.
    #[test]
    fn lines_within_a_fit_radius_of_a_crease_stay() {
        let mesh = crate::shapes::height_field(|_, _| 0.0, [-2.0, 2.0], [-2.0, 2.0], 40, 40);
        let n = mesh.num_vertices();
        let curvature = Curvature {
            smoothing_drift: [vec![0.0; n], vec![0.03; n]],
            ..valleys_along_y(mesh.positions().iter().map(|p| p.x).collect())
        };
        // The edges along the grid's column at x = `at`.
        let crease_at = |at: f64| -> Vec<bool> {
            let on = |v: u32| (mesh.position(v).x - at).abs() < 1e-9;
            let topology = mesh.topology();
            topology
                .edges()
                .iter()
                .map(|&[a, b]| on(a) && on(b))
                .collect()
        };
        let moved_with = |barriers: Option<&[bool]>| {
            let points = (0..=40)
                .map(|k| Vec3::new(0.0, -1.0 + 0.05 * k as f64, 0.0))
                .collect();
            let mut lines = FeatureLines {
                lines: vec![FeatureLine::new(LineKind::Valley, points, false)],
            };
            debias_crest_lines(&mesh, &curvature, &mut lines, 0.5, barriers).moved
        };
        assert_eq!(moved_with(None), 41);
        assert_eq!(moved_with(Some(&crease_at(0.3))), 0);
        assert_eq!(moved_with(Some(&crease_at(-1.5))), 41);
    }

    /// A point that moves beside points that stay would fold the line (its moved segments
    /// turn back); its move is halved until the segments keep half their length along the
    /// originals. Moves that keep them are left as they are, and the result does not depend
    /// on the line's direction.
    #[test]
    fn moves_never_fold_a_line() {
        let points: Vec<Vec3> = (0..5)
            .map(|k| Vec3::new(0.1 * k as f64, 0.0, 0.0))
            .collect();
        // Across the line: kept whole.
        let mut moves = vec![Vec3::zeros(); 5];
        moves[2] = Vec3::new(0.0, 0.3, 0.0);
        keep_unfolded(&points, false, &mut moves);
        assert_eq!(moves[2], Vec3::new(0.0, 0.3, 0.0));
        // Along the line, past its neighbour (0.15 > 0.05, half a segment): 0.15 → 0.075 →
        // 0.0375, the first that keeps half of each segment (0.0625 ≥ 0.05).
        let mut moves = vec![Vec3::zeros(); 5];
        moves[2] = Vec3::new(0.15, 0.0, 0.0);
        keep_unfolded(&points, false, &mut moves);
        assert!((moves[2].x - 0.0375).abs() < 1e-12, "{moves:?}");
        assert!(
            moves
                .iter()
                .enumerate()
                .all(|(k, m)| k == 2 || *m == Vec3::zeros())
        );
        // Two neighbours moved towards each other until they would cross (on a closed line,
        // whose last segment joins the first point): both halved.
        let mut moves = vec![Vec3::zeros(); 5];
        moves[1] = Vec3::new(0.08, 0.0, 0.0);
        moves[2] = Vec3::new(-0.08, 0.0, 0.0);
        keep_unfolded(&points, true, &mut moves);
        let gap = (points[2] + moves[2] - points[1] - moves[1]).x;
        assert!(gap >= 0.05 - 1e-12, "{moves:?}");
        // A move that four halvings do not cure: dropped.
        let mut moves = vec![Vec3::zeros(); 5];
        moves[4] = Vec3::new(-10.0, 0.0, 0.0);
        keep_unfolded(&points, false, &mut moves);
        assert_eq!(moves[4], Vec3::zeros());
        // Folds that shrinking makes elsewhere: each round tests before it shrinks, so the
        // line and its reverse get the same moves (shrinking while testing gave 0.02, −0.005
        // one way and 0.04, −0.01 the other).
        let points: Vec<Vec3> = (0..6)
            .map(|k| Vec3::new(0.1 * k as f64, 0.0, 0.0))
            .collect();
        let given = [0.0, 0.08, -0.08, -0.15, 0.0, 0.0].map(|x| Vec3::new(x, 0.0, 0.0));
        let expected = [0.0, 0.02, -0.01, -0.0375, 0.0, 0.0];
        let mut moves = given.to_vec();
        keep_unfolded(&points, false, &mut moves);
        let reversed: Vec<Vec3> = points.iter().rev().copied().collect();
        let mut moves_reversed: Vec<Vec3> = given.iter().rev().copied().collect();
        keep_unfolded(&reversed, false, &mut moves_reversed);
        for (k, x) in expected.iter().enumerate() {
            assert!((moves[k].x - x).abs() < 1e-12, "{moves:?}");
            assert_eq!(moves_reversed[5 - k], moves[k], "{moves_reversed:?}");
        }
        // A closed square folded only across the segment that closes it (from its last point
        // to its first): tested when closed, not when open.
        let square =
            [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)].map(|(x, y)| Vec3::new(x, y, 0.0));
        let given = [
            Vec3::zeros(),
            Vec3::zeros(),
            Vec3::zeros(),
            Vec3::new(0.0, -1.2, 0.0),
        ];
        let mut moves = given.to_vec();
        keep_unfolded(&square, true, &mut moves);
        assert!((moves[3].y + 0.3).abs() < 1e-12, "{moves:?}");
        let mut moves = given.to_vec();
        keep_unfolded(&square, false, &mut moves);
        assert_eq!(moves, given.to_vec());
    }

    /// The pooled sharpness at the centre of a height field z = h(x) (lines along y) with a
    /// disc of 8 spacings.
    fn pooled_sharpness(h: impl Fn(f64) -> f64) -> Pooled {
        pooled_sharpness_with(h, 0.4).unwrap()
    }

    /// [`pooled_sharpness`] with a disc of `radius` (the spacing is 0.05); `None` when a
    /// point has no sharpness.
    fn pooled_sharpness_with(h: impl Fn(f64) -> f64, radius: f64) -> Option<Pooled> {
        // 80 intervals over [-2, 2]: a column of vertices at x = 0.
        let mesh = crate::shapes::height_field(|x, _| h(x), [-2.0, 2.0], [-2.0, 2.0], 80, 80);
        let n = mesh.num_vertices();
        let curvature = Curvature {
            normals: vec![Vec3::z(); n],
            jet_fit: Some(crate::curvature::jet_fit::JetFitReport {
                spacing: 0.05,
                radius: radius / 0.05,
                noise: 0.0,
                sigma: 0.0,
                quartic_weight: 1.0,
                noise_growth: 1.0,
                triangle_sampled: 0,
            }),
            ..Curvature::default()
        };
        let context = Context::new(&mesh, &curvature, radius, None);
        assert_eq!(context.spacing, 0.05);
        let mut pooled = Pooled::default();
        for y in [-0.3, -0.1, 0.0, 0.1, 0.3] {
            let p = Vec3::new(0.0, y, h(0.0));
            let mut near = Vec::new();
            context
                .vertices
                .for_each_within(p, WINDOW * radius, |v, _| near.push(v as usize));
            let sharpness = context.sharpness(p, &near, [Vec3::z(), Vec3::x(), Vec3::y()]);
            sharpness?;
            let profile = Profile {
                across: Vec3::x(),
                slope: 0.0,
                bend: 0.0,
                noise_bend: 0.0,
                noise_slope: 0.0,
                drift: 0.0,
                noise_drift: 0.0,
                sharpness,
            };
            pooled.add(1.0, &profile);
        }
        Some(pooled.mean())
    }

    /// A crease (two planes, the edge of a roof) is sharper than the disc; a crest the disc
    /// resolves (a parabolic cylinder, the same curvature everywhere) is not; a gaussian
    /// ridge as wide as the disc is not either; a valley's crease is sharp for valleys only.
    #[test]
    fn a_crease_is_sharper_than_the_disc_and_a_resolved_crest_is_not() {
        let roof = pooled_sharpness(|x: f64| -0.5 * x.abs());
        assert!(roof.is_sharp(LineKind::Ridge), "{roof:?}");
        assert!(!roof.is_sharp(LineKind::Valley), "{roof:?}");
        // The normals' component across: ±sin(atan 0.5) on the two planes, over the distance
        // between the vertices one spacing to either side in the plane across: 2h √1.25.
        let expected = 2.0 * (0.5f64).atan().sin() / (0.1 * 1.25f64.sqrt());
        // The pooled sums of five points of weight 1.
        assert_eq!(roof.sharp_weight, 5.0);
        assert!(
            (roof.inner_curvature / 5.0 - expected).abs() < 1e-9,
            "{roof:?}, expected {expected}"
        );
        assert!(roof.outer_curvature.abs() < 1e-9, "{roof:?}");
        let trough = pooled_sharpness(|x: f64| 0.5 * x.abs());
        assert!(trough.is_sharp(LineKind::Valley), "{trough:?}");
        assert!(!trough.is_sharp(LineKind::Ridge), "{trough:?}");
        let cylinder = pooled_sharpness(|x: f64| -0.5 * x * x);
        assert!(!cylinder.is_sharp(LineKind::Ridge), "{cylinder:?}");
        let ratio = cylinder.inner_curvature / cylinder.outer_curvature;
        assert!((0.9..1.2).contains(&ratio), "{cylinder:?}");
        let gaussian = pooled_sharpness(|x: f64| 0.3 * (-x * x / (2.0 * 0.4 * 0.4)).exp());
        assert!(!gaussian.is_sharp(LineKind::Ridge), "{gaussian:?}");
        // A right-angled edge: its faces slope away from the tangent plane by 45°, and the
        // outer strips are at their distance from the line, not at their tangent coordinate
        // (which reaches 0.71 of it: the strips would be empty).
        let right = pooled_sharpness(|x: f64| -x.abs());
        assert!(right.is_sharp(LineKind::Ridge), "{right:?}");
        assert!(right.outer_curvature.abs() < 1e-9, "{right:?}");
        // A disc of 2.94 spacings has outer strips (from 1.47 spacings: the vertices 2
        // spacings off the line of a flat roof are in them) that start inside the inner ones
        // (to 1.5): no sharpness, the debias runs as it did; 3.2 spacings has one.
        let flat_roof = |x: f64| -0.1 * x.abs();
        assert!(pooled_sharpness_with(flat_roof, 0.147).is_none());
        let small = pooled_sharpness_with(flat_roof, 0.16).unwrap();
        assert!(small.is_sharp(LineKind::Ridge), "{small:?}");
    }

    fn gauss_legendre_8() -> ([f64; 8], [f64; 8]) {
        let x = [
            -0.960_289_856_497_536_3,
            -0.796_666_477_413_626_7,
            -0.525_532_409_916_329,
            -0.183_434_642_495_649_8,
            0.183_434_642_495_649_8,
            0.525_532_409_916_329,
            0.796_666_477_413_626_7,
            0.960_289_856_497_536_3,
        ];
        let w = [
            0.101_228_536_290_376_3,
            0.222_381_034_453_374_5,
            0.313_706_645_877_887_3,
            0.362_683_783_378_362,
            0.362_683_783_378_362,
            0.313_706_645_877_887_3,
            0.222_381_034_453_374_5,
            0.101_228_536_290_376_3,
        ];
        (x, w)
    }
}
