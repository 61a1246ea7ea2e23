//! Isolated outlier vertices ("spikes"): single vertices far off the surface their neighbours
//! describe, as scanners leave them (a stray range sample, a bad stereo match), found and put
//! back on that surface before anything is estimated.
//!
//! **Why.** One such vertex is a cone of steep triangles: its edges pass any crease angle, so
//! the crease finder rings it with short creases, and every polynomial fit whose disc holds it
//! is pulled towards it, so its neighbourhood gets crest lines of its own. Measured on the
//! public clean cases with 0.5% of the vertices moved ±3 mean edges along their normals
//! (`bench/quality/spikes.py`): 13 diagonals of creases on the torus, HPW's F1 0.24 to 0.45
//! on the closed surfaces, 0.00 to 0.80 on the noisy ones. The noise measure of the
//! jet fit is a median (a few spikes do not move it), so the mesh passes for clean and nothing
//! widens or smooths the fits around them. None of the papers deals with outliers: they assume
//! a surface mesh, and the pre-smoothing of HPW spreads a spike over its neighbourhood rather
//! than removing it.
//!
//! **Test, per vertex v** with one fan of triangles (interior or on the boundary; in parallel;
//! non-manifold vertices are left alone):
//! 1. *Screen.* The ring of v (its neighbours, centroid c) spans a polygon whose area vector
//!    `n = Σ (a − c) × (b − c)` over v's triangles (v, a, b) does not depend on where v is. v
//!    is a candidate when its height over the ring's plane (through c, normal n) exceeds
//!    [`SCREEN_HEIGHT`] times the ring's mean radius ρ (a smooth surface sampled finely
//!    enough to be fitted, `k ρ < 1`, puts v within `k ρ² / 2 < ρ / 2` of the plane) and
//!    [`TYPICAL_HEIGHTS`] times the median of that height over the mesh's vertices: under
//!    white noise, whose heights are normal, that is 5.4 standard deviations, which one
//!    vertex in ten million passes. (The height itself, not in units of ρ: noise moves a
//!    vertex by the same amount whatever the size of its ring, and on irregular meshes small
//!    rings would pass for outliers.)
//! 2. *Leave-one-out fit.* The second ring of v (the third where the second holds fewer than
//!    12 vertices: at a boundary, around valence 3 or 4), v itself left out, is fitted by
//!    least squares with a quadratic height over the ring's plane (coordinates in units of
//!    ρ). v is an outlier when it lies off that quadratic by more than [`OUTLIER_RATIO`]
//!    times the samples' own residual (`√(Σ r² / (m − 6))` for m samples) and by more than
//!    [`SCREEN_HEIGHT`] ρ / 2, its foot within [`FOOT_REACH`] ρ of a sample (where the fit
//!    holds; at a boundary, or after a spike sideways, it can lie outside the ring). On a
//!    sharp feature the neighbours do not lie on one quadratic (a cube's corner: its three
//!    faces), and the residual is as large as v's distance; on a smooth surface or under
//!    white noise they do.
//!
//!    *Spikes side by side.* Another spike in the second ring inflates the residual and tilts
//!    the ring's plane (by 45° for a neighbour three ring radii up). The sample whose deleted
//!    residual (its distance from the fit of the others) is the largest is left out when it is
//!    an outlier of the others' fit by the same test, up to [`MAX_DROPPED`] of them. The fit's
//!    frame starts from the summed unit normals of the samples' triangles that do not have v
//!    as a corner (a spike beside v tilts only a few of them), and is set again on the fit
//!    above the ring's centre, with the fit's normal there, until it stays (at most
//!    [`MAX_REFRAMES`] fits; if it does not stay, v stays).
//!
//!    *Cone tips.* The tip of a real cone made of one vertex (a drill point, a countersink) is
//!    off its neighbours' quadratic too, by about the tip's curvature over the samples: it is an
//!    outlier only if it also departs, by the same test, from the fit of its sides by a cone
//!    about its foot (`c₀ + c₁x + c₂y + c₃r + c₄x² + c₅xy + c₆y²`, r the distance from the
//!    foot),
//!    which a spike on a smooth surface does and a cone's tip does not. Where the mesh is made
//!    in rings around v, its first two rings are two circles that any `c₀ + c r²` passes
//!    through exactly: the samples must lie at three distances at least from the ring's centre
//!    in its plane (a third ring is taken), or v is not tested (a CAD cone whose tip is joined straight to the rim of a
//!    flat fan).
//! 3. *Repair.* Each outlier moves along the normal onto the quadratic. The test runs again on
//!    the repaired mesh, up to [`MAX_ROUNDS`] times, for what the moves uncover.
//!
//! **Limits.** A cluster of spikes side by side (a blob of adjacent bad samples; three spikes
//! on one triangle already) tilts the ring's plane and fills the second ring with more than
//! the fit can leave out: it is a bump to this test, and it stays. On a mesh made
//! mostly of flat faces the median height is zero and only the first bound of the screen
//! holds; the fits decide. Measured (`BENCHMARKS.md`, "Stray vertices put back"): of the
//! shared meshes, the quality cases (clean, noisy and made alike) and the CAD parts, one
//! vertex moves, on the horse (a scan): a vertex of valence 4 that stands 0.7 edges above its
//! ring, its ring 0.35 edges below the plane of the three rings around it.

use rayon::prelude::*;

use super::{TriMesh, Vec3, VertexKind, tangent_frame};
use crate::error::Result;

/// The height over its ring's plane, in units of the ring's mean radius, above which a vertex
/// is tested (step 1 of the module docs); half of it is the least distance off its
/// neighbours' quadratic that makes it an outlier.
pub const SCREEN_HEIGHT: f64 = 0.5;

/// How many times the median distance of the mesh's vertices from their rings' planes a
/// vertex's must be to be tested (step 1 of the module docs).
pub const TYPICAL_HEIGHTS: f64 = 8.0;

/// How many times the neighbours' residual about their quadratic a vertex must lie off it to
/// be an outlier (step 2 of the module docs).
pub const OUTLIER_RATIO: f64 = 8.0;

/// Rounds of test and repair (step 3 of the module docs).
pub const MAX_ROUNDS: usize = 3;

/// The most samples of a second ring left out of its fit as outliers of the others (step 2
/// of the module docs).
pub const MAX_DROPPED: usize = 3;

/// The most fits of a vertex's second ring, each in the frame set on the one before, above
/// the ring's centre (step 2 of the module docs): the frame is set again at most
/// `MAX_REFRAMES − 1` times.
pub const MAX_REFRAMES: usize = 4;

/// The frame stays when the fit's normal turns from it by less than this cosine's angle
/// (about 1.1°).
const REFRAMED_COS: f64 = 0.9998;

/// How far from the nearest sample, in ring radii, v's foot may lie for the fit to be read
/// there.
pub const FOOT_REACH: f64 = 1.5;

/// The smallest ratio of the smallest to the largest diagonal entry of the Cholesky factor of
/// the quadratic's normal equations: below it (condition above about 1e12) the coefficients
/// are rounding, as when the samples lie on one circle.
const MIN_PIVOT_RATIO: f64 = 1e-6;

/// The fewest samples of the leave-one-out fit (six coefficients and six degrees of freedom
/// for the residual); a second ring with fewer grows to the third.
const MIN_SAMPLES: usize = 12;

/// The fewest degrees of freedom a fit leaves its residual (the cone's seven coefficients
/// leave five of [`MIN_SAMPLES`]); a fit with fewer, after samples were left out, is refused.
const MIN_DEGREES_OF_FREEDOM: usize = 5;

/// What [`repair_outliers`] did.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct OutlierRepair {
    /// The vertices moved onto their neighbours' surface, ascending.
    pub vertices: Vec<u32>,
    /// How far each moved, in the order of `vertices` (model units; from where it was to
    /// where it ends, when it moved in more than one round).
    pub distances: Vec<f64>,
}

/// The isolated outlier vertices of `mesh` and, for each, the position on its neighbours'
/// quadratic it moves to: one round of the test in the module docs.
pub fn find_outliers(mesh: &TriMesh) -> Vec<(u32, Vec3)> {
    let heights: Vec<Option<[f64; 2]>> = (0..mesh.num_vertices() as u32)
        .into_par_iter()
        .map(|v| ring_height(mesh, v))
        .collect();
    let mut all: Vec<f64> = heights.iter().flatten().map(|[h, _]| *h).collect();
    if all.is_empty() {
        return Vec::new();
    }
    let middle = all.len() / 2;
    let (_, &mut median, _) = all.select_nth_unstable_by(middle, f64::total_cmp);
    let typical = TYPICAL_HEIGHTS * median;
    heights
        .par_iter()
        .enumerate()
        .filter(|(_, h)| h.is_some_and(|[h, radius]| h > typical && h > SCREEN_HEIGHT * radius))
        .filter_map(|(v, _)| outlier_target(mesh, v as u32).map(|p| (v as u32, p)))
        .collect()
}

/// The distance of vertex `v` from its ring's plane and the ring's mean radius (step 1 of
/// the module docs); `None` for vertices that are not interior or on the boundary (one fan).
fn ring_height(mesh: &TriMesh, v: u32) -> Option<[f64; 2]> {
    if !matches!(
        mesh.topology().vertex_kind(v),
        VertexKind::Interior | VertexKind::Boundary
    ) {
        return None;
    }
    let (centre, normal, radius) = ring_plane(mesh, v)?;
    Some([(mesh.position(v) - centre).dot(&normal).abs(), radius])
}

/// `mesh` with its isolated outlier vertices moved onto the surface of their neighbours
/// (the module docs), or `None` when it has none; and what was moved.
///
/// # Errors
/// None in practice: the moved positions are finite (the error is that of
/// [`TriMesh::with_positions`]).
pub fn repair_outliers(mesh: &TriMesh) -> Result<(Option<TriMesh>, OutlierRepair)> {
    let mut repair = OutlierRepair::default();
    let mut repaired: Option<TriMesh> = None;
    for _ in 0..MAX_ROUNDS {
        let current = repaired.as_ref().unwrap_or(mesh);
        let found = find_outliers(current);
        if found.is_empty() {
            break;
        }
        let mut positions = current.positions().to_vec();
        for &(v, p) in &found {
            positions[v as usize] = p;
        }
        repaired = Some(current.with_positions(positions)?);
    }
    if let Some(moved) = &repaired {
        for (v, (a, b)) in mesh.positions().iter().zip(moved.positions()).enumerate() {
            if a != b {
                repair.vertices.push(v as u32);
                repair.distances.push((a - b).norm());
            }
        }
    }
    Ok((repaired, repair))
}

/// Where vertex `v`, a candidate of the screen, belongs when it is an outlier (step 2 of the
/// module docs).
fn outlier_target(mesh: &TriMesh, v: u32) -> Option<Vec3> {
    let p = mesh.position(v);
    let (centre, normal, radius) = ring_plane(mesh, v)?;
    let samples = neighbourhood(mesh, v, centre, normal)?;
    let positions: Vec<Vec3> = samples.iter().map(|&q| mesh.position(q)).collect();
    let normal = samples_normal(mesh, v, &samples).unwrap_or(normal);
    // A spike in the ring tilts the ring's plane (by 45° for a neighbour three ring radii
    // up, nearly on edge for one of twelve), and v's foot in a tilted frame lies far from the
    // ring, where the quadratic is an extrapolation. The fit starts from the triangles of the
    // samples (a spike beside v tilts only the few at it), and the frame is set again on the
    // fit above the ring's centre (inside the samples, where the fit is sound), with the fit's
    // normal there, until it stays.
    let (mut origin, mut normal) = (centre, normal);
    for _ in 0..MAX_REFRAMES {
        let (u, w, _) = tangent_frame(normal);
        let local = |q: Vec3| {
            let d = (q - origin) / radius;
            (d.dot(&u), d.dot(&w), d.dot(&normal))
        };
        let mut points: Vec<(f64, f64, f64)> = positions.iter().map(|&q| local(q)).collect();
        let quadratic = fit_without_outliers(Model::Quadratic, &mut points)?;
        let (x, y, z) = local(p);
        let (gx, gy) = quadratic.slope_at_origin();
        let turned = (normal - u * gx - w * gy).try_normalize(1e-300)?;
        if turned.dot(&normal) > REFRAMED_COS {
            // v's foot must lie among the samples, where the fit holds: within a ring radius
            // and a half of one of them (on a boundary, or after a sideways spike, it can
            // lie outside the ring).
            let near = points
                .iter()
                .any(|&(a, b, _)| (a - x).powi(2) + (b - y).powi(2) <= FOOT_REACH * FOOT_REACH);
            if !(near && quadratic.departs(x, y, z)) {
                return None;
            }
            // Nor the tip of a cone: the samples of its sides lie on a cone about v's foot
            // that v does not depart from.
            let mut sides: Vec<(f64, f64, f64)> = positions.iter().map(|&q| local(q)).collect();
            let cone = fit_without_outliers(Model::Cone { x0: x, y0: y }, &mut sides);
            if cone.is_some_and(|cone| !cone.departs(x, y, z)) {
                return None;
            }
            let off = z - quadratic.height(x, y);
            return Some(p - normal * (off * radius));
        }
        origin += normal * (quadratic.height(0.0, 0.0) * radius);
        normal = turned;
    }
    None
}

/// The fit of `points` by `model` with up to [`MAX_DROPPED`] of them left out, each an outlier of
/// the fit of the others by the test of the module docs: another spike in v's second ring.
/// The point tested is the one whose deleted residual (its distance from the fit of the
/// others, `r / (1 − h)` with h its leverage) is the largest; its plain residual need not be,
/// as a spike pulls the fit towards itself and tilts it away from the rest. Points left out
/// are removed from `points`.
fn fit_without_outliers(model: Model, points: &mut Vec<(f64, f64, f64)>) -> Option<Fit> {
    let mut fit = fit_model(model, points)?;
    for _ in 0..MAX_DROPPED {
        if points.len() <= MIN_SAMPLES {
            break;
        }
        let deleted = |k: usize| fit.deleted_residual(points[k]).abs();
        let worst = (0..points.len()).max_by(|&i, &j| deleted(i).total_cmp(&deleted(j)))?;
        let (x, y, z) = points.swap_remove(worst);
        match fit_model(model, points) {
            Some(without) if without.departs(x, y, z) => fit = without,
            _ => {
                points.push((x, y, z));
                break;
            }
        }
    }
    Some(fit)
}

/// The centroid of the ring of `v`, the unit area vector of the polygon the ring spans
/// (oriented by the winding of v's triangles) and the ring's mean radius; `None` when the
/// polygon has no area.
fn ring_plane(mesh: &TriMesh, v: u32) -> Option<(Vec3, Vec3, f64)> {
    let topo = mesh.topology();
    let faces = mesh.faces();
    // Two passes over the neighbours: this runs at every vertex, without an allocation.
    let count = topo.degree(v) as f64;
    let centre = topo.neighbors(v).map(|q| mesh.position(q)).sum::<Vec3>() / count;
    let radius = topo
        .neighbors(v)
        .map(|q| (mesh.position(q) - centre).norm())
        .sum::<f64>()
        / count;
    if radius.is_nan() || radius <= 0.0 {
        return None;
    }
    // In units of the radius, so that neither tiny nor huge models under- or overflow.
    let mut area = Vec3::zeros();
    for &f in topo.vertex_faces(v) {
        let tri = faces[f as usize];
        let at = tri.iter().position(|&q| q == v)?;
        let a = (mesh.position(tri[(at + 1) % 3]) - centre) / radius;
        let b = (mesh.position(tri[(at + 2) % 3]) - centre) / radius;
        area += a.cross(&b);
    }
    let normal = area.try_normalize(1e-12)?;
    Some((centre, normal, radius))
}

/// The normal the fit of `samples` starts from: the sum of the unit normals of their
/// triangles that do not have `v` as a corner, normalised. A spike beside v tilts only the
/// triangles at it (from the ring's plane, a pair of spikes 12 edges tall was never found:
/// the frame set again from nearly on edge did not settle).
fn samples_normal(mesh: &TriMesh, v: u32, samples: &[u32]) -> Option<Vec3> {
    let topo = mesh.topology();
    let mut faces: Vec<u32> = samples
        .iter()
        .flat_map(|&q| topo.vertex_faces(q).iter().copied())
        .collect();
    faces.sort_unstable();
    faces.dedup();
    let mut sum = Vec3::zeros();
    for f in faces {
        let corners = mesh.faces()[f as usize];
        if corners.contains(&v) {
            continue;
        }
        let [a, b, c] = corners.map(|q| mesh.position(q));
        if let Some(n) = (b - a).cross(&(c - a)).try_normalize(0.0) {
            sum += n;
        }
    }
    sum.try_normalize(1e-12)
}

/// The vertices one or two edges from `v`, without `v`; three edges where two give fewer
/// than [`MIN_SAMPLES`] (at a boundary, around a vertex of valence 3 or 4) or lie at fewer
/// than three distances from the ring's centre in its plane (`centre`, `normal`: see
/// [`distinct_distances`]). `None` when three edges do not either.
///
/// Samples at two distances are two circles about v where the mesh is made in rings around it
/// (a cone's tip meshed as a polar disc): `c₀ + c r²` passes through both exactly, whatever
/// the surface does between them, and the residual says nothing. A third distance tells a
/// cone from a paraboloid; a tip whose neighbourhood never has one (a CAD cone, its tip joined
/// straight to the rim of a flat fan) is not tested.
fn neighbourhood(mesh: &TriMesh, v: u32, centre: Vec3, normal: Vec3) -> Option<Vec<u32>> {
    let topo = mesh.topology();
    // Breadth-first by rings; `seen` (sorted) holds v and the rings so far.
    let mut seen: Vec<u32> = vec![v];
    let mut frontier: Vec<u32> = vec![v];
    let mut samples: Vec<u32> = Vec::new();
    for rings in 1..=3 {
        let mut next: Vec<u32> = frontier
            .iter()
            .flat_map(|&a| topo.neighbors(a))
            .filter(|q| seen.binary_search(q).is_err())
            .collect();
        next.sort_unstable();
        next.dedup();
        seen.extend(&next);
        seen.sort_unstable();
        samples.extend(&next);
        frontier = next;
        if rings >= 2
            && samples.len() >= MIN_SAMPLES
            && distinct_distances(mesh, centre, normal, &samples) >= 3
        {
            return Some(samples);
        }
    }
    None
}

/// How many distances from the line through `centre` along the unit `normal` the vertices
/// `samples` lie at, distances within a hundredth of the largest counting as one. From the
/// ring's centre in its plane, not from v: the distances from a tall spike bunch together
/// (from 10 edges up, all of its rings looked like one).
fn distinct_distances(mesh: &TriMesh, centre: Vec3, normal: Vec3, samples: &[u32]) -> usize {
    let mut distances: Vec<f64> = samples
        .iter()
        .map(|&q| {
            let d = mesh.position(q) - centre;
            (d - normal * d.dot(&normal)).norm()
        })
        .collect();
    distances.sort_unstable_by(f64::total_cmp);
    let tolerance = 0.01 * distances.last().copied().unwrap_or(0.0);
    1 + distances
        .windows(2)
        .filter(|w| w[1] - w[0] > tolerance)
        .count()
}

/// The height models of the leave-one-out fit.
#[derive(Debug, Clone, Copy)]
enum Model {
    /// `c₀ + c₁x + c₂y + c₃x² + c₄xy + c₅y²`: a smooth surface.
    Quadratic,
    /// `c₀ + c₁x + c₂y + c₃r + c₄x² + c₅xy + c₆y²`, r the distance from (x₀, y₀) in the
    /// plane: a cone with its tip above (x₀, y₀) (a drill point, a countersink) on a surface
    /// that bends, which a quadratic misses there by about its tip's curvature over the
    /// samples.
    Cone { x0: f64, y0: f64 },
}

impl Model {
    fn basis(self, x: f64, y: f64) -> nalgebra::DVector<f64> {
        match self {
            Model::Quadratic => {
                nalgebra::DVector::from_column_slice(&[1.0, x, y, x * x, x * y, y * y])
            }
            Model::Cone { x0, y0 } => nalgebra::DVector::from_column_slice(&[
                1.0,
                x,
                y,
                (x - x0).hypot(y - y0),
                x * x,
                x * y,
                y * y,
            ]),
        }
    }

    /// The number of coefficients.
    fn size(self) -> usize {
        match self {
            Model::Quadratic => 6,
            Model::Cone { .. } => 7,
        }
    }
}

/// A least-squares fit of the heights of samples by a [`Model`], and its residual.
struct Fit {
    model: Model,
    coefficients: nalgebra::DVector<f64>,
    residual: f64,
    /// The inverse of the normal equations' matrix, for the samples' leverages.
    inverse: nalgebra::DMatrix<f64>,
}

impl Fit {
    fn height(&self, x: f64, y: f64) -> f64 {
        self.coefficients.dot(&self.model.basis(x, y))
    }

    /// The gradient of the height at the origin (both models' linear terms).
    fn slope_at_origin(&self) -> (f64, f64) {
        (self.coefficients[1], self.coefficients[2])
    }

    /// The residual of a sample of the fit divided by `1 − h`, h its leverage: its distance
    /// from the fit of the other samples.
    fn deleted_residual(&self, (x, y, z): (f64, f64, f64)) -> f64 {
        let b = self.model.basis(x, y);
        let leverage = b.dot(&(&self.inverse * &b));
        (z - self.height(x, y)) / (1.0 - leverage).max(1e-12)
    }

    /// Whether the point at (x, y, z), not one of the samples, is an outlier of them (step 2
    /// of the module docs; lengths in units of the ring's radius).
    fn departs(&self, x: f64, y: f64, z: f64) -> bool {
        let off = (z - self.height(x, y)).abs();
        off > OUTLIER_RATIO * self.residual && off > 0.5 * SCREEN_HEIGHT
    }
}

/// Fits `z(x, y)` with `model` by the normal equations (coordinates are of order one: the
/// ring's radius is the unit); `None` when they are singular or ill-conditioned, or leave the
/// residual fewer than [`MIN_DEGREES_OF_FREEDOM`].
fn fit_model(model: Model, samples: &[(f64, f64, f64)]) -> Option<Fit> {
    let n = model.size();
    if samples.len() < n + MIN_DEGREES_OF_FREEDOM {
        return None;
    }
    let mut normal = nalgebra::DMatrix::<f64>::zeros(n, n);
    let mut rhs = nalgebra::DVector::<f64>::zeros(n);
    for &(x, y, z) in samples {
        let b = model.basis(x, y);
        normal += &b * b.transpose();
        rhs += &b * z;
    }
    let cholesky = normal.cholesky()?;
    let pivots = cholesky.l_dirty().diagonal();
    if pivots.min().is_nan() || pivots.min() <= MIN_PIVOT_RATIO * pivots.max() {
        return None;
    }
    let fitted = Fit {
        model,
        coefficients: cholesky.solve(&rhs),
        residual: 0.0,
        inverse: cholesky.inverse(),
    };
    let squares: f64 = samples
        .iter()
        .map(|&(x, y, z)| (z - fitted.height(x, y)).powi(2))
        .sum();
    Some(Fit {
        residual: (squares / (samples.len() - n) as f64).sqrt(),
        ..fitted
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes;

    /// `mesh` with vertex `v` moved by `amount` times the mean edge length along its normal.
    fn spiked(mesh: &TriMesh, vertices: &[u32], amount: f64) -> TriMesh {
        let normals = crate::mesh::vertex_normals_area(mesh);
        let edge = crate::mesh::mean_edge_length(mesh);
        let mut positions = mesh.positions().to_vec();
        for &v in vertices {
            positions[v as usize] += normals[v as usize] * amount * edge;
        }
        mesh.with_positions(positions).unwrap()
    }

    #[test]
    fn a_spike_on_a_sphere_goes_back_onto_it() {
        let sphere = shapes::icosphere(1.0, 4);
        // A tall spike as well: measured from v, the distances of its rings bunched into one.
        for amount in [3.0, -3.0, 1.0, 12.0, -20.0] {
            let mesh = spiked(&sphere, &[100], amount);
            let (repaired, repair) = repair_outliers(&mesh).unwrap();
            assert_eq!(repair.vertices, vec![100], "spike of {amount} edges");
            let p = repaired.unwrap().position(100);
            // Back on the unit sphere to within the quadratic's truncation.
            assert!((p.norm() - 1.0).abs() < 2e-3, "|p| = {}", p.norm());
        }
    }

    #[test]
    fn clean_and_sharp_shapes_have_no_outliers() {
        let cone = |slope: f64| move |x: f64, y: f64| -slope * x.hypot(y);
        let meshes = [
            ("sphere", shapes::icosphere(1.0, 3)),
            ("ellipsoid", shapes::ellipsoid(3.0, 2.0, 1.0, 4)),
            ("torus", shapes::torus(3.0, 1.0, 60, 20)),
            ("coarse torus", shapes::torus(3.0, 1.0, 24, 8)),
            ("pillow box", shapes::pillow_box(1.0, 0.2, 8).0),
            ("sharp pillow box", shapes::pillow_box(1.0, 0.0, 3).0),
            // Cone tips meshed in rings around them: the first two rings are circles, which
            // a quadratic passes through exactly (a drill point, a 90° countersink, a spike).
            ("drill point", shapes::disk(cone(0.6), 1.0, 10)),
            ("countersink", shapes::disk(cone(-1.0), 1.0, 10)),
            ("needle", shapes::disk(cone(3.0), 1.0, 10)),
            (
                "grid cone",
                shapes::height_field(cone(1.0), [-1.0, 1.0], [-1.0, 1.0], 20, 20),
            ),
            ("fan cone", fan_cone(24, 1.5)),
        ];
        for (name, mesh) in meshes {
            assert_eq!(find_outliers(&mesh), vec![], "{name}");
        }
    }

    /// A CAD-style cone: its tip joined straight to a rim of `n` vertices, the base a flat fan
    /// around its centre.
    fn fan_cone(n: u32, height: f64) -> TriMesh {
        let mut positions = vec![Vec3::new(0.0, 0.0, height), Vec3::zeros()];
        let mut faces = Vec::new();
        for i in 0..n {
            let angle = std::f64::consts::TAU * f64::from(i) / f64::from(n);
            positions.push(Vec3::new(angle.cos(), angle.sin(), 0.0));
            let (a, b) = (2 + i, 2 + (i + 1) % n);
            faces.push([0, a, b]);
            faces.push([1, b, a]);
        }
        TriMesh::new(positions, faces).unwrap()
    }

    #[test]
    fn a_spike_on_a_boundary_goes_back() {
        let plane = shapes::height_field(|x, y| 0.1 * x * y, [-1.0, 1.0], [-1.0, 1.0], 20, 20);
        // A vertex in the middle of the side y = -1.
        let v = (0..plane.num_vertices() as u32)
            .find(|&v| {
                let p = plane.position(v);
                (p.y + 1.0).abs() < 1e-12 && p.x.abs() < 1e-12
            })
            .unwrap();
        let mesh = spiked(&plane, &[v], 3.0);
        let (repaired, repair) = repair_outliers(&mesh).unwrap();
        assert_eq!(repair.vertices, vec![v]);
        let p = repaired.unwrap().position(v);
        assert!((p.z - 0.1 * p.x * p.y).abs() < 1e-3, "{p:?}");
    }

    #[test]
    fn a_spike_among_white_noise_is_found_and_the_noise_is_left() {
        let sphere = shapes::icosphere(1.0, 5);
        let normals = crate::mesh::vertex_normals_area(&sphere);
        let edge = crate::mesh::mean_edge_length(&sphere);
        // Deterministic noise of standard deviation about 0.15 edges (a sum of uniforms).
        let mut state = 12345u64;
        let mut uniform = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let mut positions = sphere.positions().to_vec();
        for (p, n) in positions.iter_mut().zip(&normals) {
            let noise: f64 = (0..12).map(|_| uniform()).sum();
            *p += n * noise * 0.15 * edge;
        }
        positions[7] += normals[7] * 4.0 * edge;
        let mesh = sphere.with_positions(positions).unwrap();
        let (_, repair) = repair_outliers(&mesh).unwrap();
        assert_eq!(repair.vertices, vec![7]);
    }

    #[test]
    fn two_spikes_side_by_side_are_both_found() {
        let sphere = shapes::icosphere(1.0, 4);
        let b = sphere.topology().neighbors(100).next().unwrap();
        // Tall ones too: one turns its neighbour's ring plane nearly on edge.
        for amount in [3.0, 12.0] {
            let mesh = spiked(&sphere, &[100, b], amount);
            let (_, repair) = repair_outliers(&mesh).unwrap();
            let mut expected = vec![100, b];
            expected.sort_unstable();
            assert_eq!(repair.vertices, expected, "spikes of {amount} edges");
        }
    }
}
