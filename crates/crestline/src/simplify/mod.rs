//! Crest-line-guided mesh simplification: weighted quadric-error edge collapse.
//!
//! YBS 2005, section "Crest Lines and Mesh Simplification", following Kho and Garland
//! ("User-guided simplification", I3D 2003): each triangle `T_j` gets the Garland–Heckbert
//! quadric `Q(T_j)` (M. Garland, P. Heckbert, "Surface simplification using quadric error
//! metrics", SIGGRAPH 1997) scaled by `w_j = 1 / F(d_j)`, where `d_j` is the geodesic distance
//! from the triangle to the nearest crest line ([`crate::distance`]) and eq. 7 reads
//!
//! ```text
//! F(d) = (d / max(d) + ε)^η
//! ```
//!
//! Triangles near the lines weigh up to `ε^-η` times more, so the decimation spends its error
//! budget far from them and keeps the mesh dense along them. `η = 0` is plain QEM.
//!
//! [`simplify`] runs the public steps in order: [`crate::distance::feature_distance`] →
//! [`feature_weights`] → [`crease_edges`] → [`decimate_constrained`].
//!
//! **Creases** (lines with [`crate::lines::FeatureLine::crease`] set, issue 20) are
//! constraints, handled like boundaries: a vertex on a crease never moves; an edge from it to a
//! vertex off the creases collapses onto it; an edge between two crease vertices collapses
//! only along a crease, onto one of its ends; and corners (a crease vertex with one or three
//! or more crease edges) are never removed. Every vertex of the result on a crease is a
//! crease vertex of the input at exactly its place, so the sharp edges of a CAD part are kept
//! however far the rest is simplified (a curved crease loses vertices, as a boundary does).
//! Crease points are found on the mesh by their locations, or, for lines read from a file, by
//! their positions (mesh vertices within 1e-9 of the diagonal).
//!
//! ## The decimation
//! - **Quadrics.** Each triangle contributes `w · area · (plane quadric)` to its three
//!   corners (area weighting makes the result independent of how finely a region was
//!   tessellated). Each boundary edge adds a plane through it, perpendicular to its
//!   triangle, weighted by `boundary_weight · w · length²`, so that eating into the boundary's
//!   outline costs like eating into the surface.
//! - **Placement.** The minimiser of the summed quadric (a 3 × 3 solve); when that system is
//!   ill-conditioned (flat or cylindrical neighbourhoods, where the minimiser is a line or a
//!   plane) or the minimiser lands more than two edge lengths from the edge's midpoint, the
//!   best of the two end points and the midpoint. Boundary vertices never leave their place:
//!   an edge with one boundary end point collapses onto that end point, and an edge between
//!   two boundary vertices must be a boundary edge and collapses onto one of its end points.
//!   Every boundary vertex of the result is therefore a boundary vertex of the input, at
//!   exactly its input position.
//! - **Order.** A heap of candidate collapses keyed by cost, with lazy deletion: each entry
//!   carries the version stamps of its two end points, and a collapse bumps the stamp of the
//!   vertex it keeps (and queues that vertex's edges anew), so stale entries are skipped when
//!   popped. About nine in ten popped entries are stale, so the queue is built for few cache
//!   misses: 16-byte entries (costs as `f32`, computed in `f64` in coordinates
//!   normalised to a unit bounding-box diagonal), a four-ary heap holding only the cheapest
//!   candidates, and an unordered overflow purged of stale entries whenever the heap is
//!   refilled from it (`CandidateQueue`). When the queue runs dry before the target (all
//!   remaining candidates were refused), another pass re-evaluates every remaining edge;
//!   passes stop when one makes no collapse.
//! - **Validity.** A collapse of edge `u v` is refused when it would break the link condition
//!   (the common neighbours of `u` and `v` must be exactly the apexes of the triangles on
//!   `u v`, where a boundary counts as joined to one extra vertex; plus the checks that keep a
//!   tetrahedron and a lone triangle from folding flat), so manifold neighbourhoods stay
//!   manifold and the topology (components, Euler characteristic, boundary loops) is kept;
//!   when a moved triangle's normal would turn by more than `max_normal_rotation` (flips) or
//!   its area would vanish; and when either end point is a non-manifold vertex of the input
//!   (those, and so the non-manifold edges between them, are left alone).
//! - **Valence.** A collapse is refused when the vertex it keeps would get more than
//!   [`MAX_VALENCE`] (128) neighbours and more than either end point has now. Where costs
//!   tie (flat or straight stretches, where collapses cost nothing), the vertex just kept
//!   can win again and again: on a long straight strip one vertex swallowed its whole row,
//!   a fan of all the triangles left, and since each collapse into it plans all its edges
//!   anew the time grew with the square of the strip (a flat strip of 4,000 triangles took
//!   3 s, one of 64,000 did not finish in 9 minutes). The bound changes no result on the
//!   meshes of `shared/data/meshes` (to 10 %, 3 % and 2 %); the fans of an input (CAD caps)
//!   may still shrink.
//! - **Connectivity.** The [`TriMesh`] is immutable, so the collapses run on a light mutable
//!   copy (triangle list with alive flags, per-vertex triangle lists); the survivors are then
//!   compacted into a new [`TriMesh`].
//!
//! Cost: O(E log E) for the queue, with constant work per collapse, since the collapses keep
//! the degrees bounded (beyond those of the input). About 1 s for 270K triangles to 10 % on
//! one core (`BENCHMARKS.md`).
//!
//! ## Known limits
//! - The requested face count is met to within one face: interior collapses remove two
//!   triangles, boundary collapses one. It may not be met at all when every remaining collapse
//!   is refused ([`Simplified::target_reached`] says so).
//! - Unreferenced input vertices are dropped from the result.
//! - Quadrics measure distance to the planes of the original triangles, not to the surface;
//!   like all QEM variants this is an estimate of the Hausdorff error, not a bound.
//! - The normal check compares each moved triangle with its current normal, not its
//!   original one, so rotations can add up over many collapses (in practice only on
//!   coarse results of small or non-manifold meshes, with sheets close together).
//! - Non-manifold vertices stay, with every edge at them, which can stop a mesh with many
//!   of them short of the target.
//! - A candidate refused for a flip is not retried with another placement; it comes back
//!   only when a neighbouring collapse re-queues it.

mod decimator;
mod quadric;
mod queue;

use crate::distance::{DistanceOptions, FeatureDistance, feature_distance};
use crate::error::{Error, Result};
use crate::lines::{FeatureLines, SurfacePoint};
use crate::mesh::{TriMesh, mean_edge_length};

use decimator::Decimator;

/// Most neighbours a collapse may give the vertex it keeps, unless one of the two end points
/// has more already (see the module docs, "Valence").
pub const MAX_VALENCE: usize = 128;

/// How many triangles the simplified mesh should have.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Target {
    /// A fraction in (0, 1] of the input's triangles.
    Ratio(f64),
    /// An absolute number of triangles.
    Faces(usize),
}

impl Target {
    /// The triangle count this target asks of a mesh with `faces` triangles (never more than
    /// `faces`).
    pub fn faces_for(&self, faces: usize) -> usize {
        match *self {
            Target::Ratio(r) => ((faces as f64 * r).round() as usize).min(faces),
            Target::Faces(n) => n.min(faces),
        }
    }
}

impl Default for Target {
    fn default() -> Self {
        Target::Ratio(0.1)
    }
}

/// Options of [`simplify`] and [`decimate`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SimplifyOptions {
    /// How far to simplify. Default: `Target::Ratio(0.1)` (keep 10 % of the triangles).
    pub target: Target,
    /// Influence η of the feature lines in eq. 7; `0` is plain QEM and ignores the lines.
    /// Not used by [`decimate`], which takes the weights directly. Default: `1.0`.
    pub eta: f64,
    /// Regularisation ε of eq. 7; weights range from `(1 + ε)^-η` far from the lines to
    /// `ε^-η` on them. Not used by [`decimate`]. Default: `0.1` (the paper's value).
    pub eps: f64,
    /// Weight of the boundary-preserving planes relative to the surface quadrics.
    /// Default: `10.0`.
    pub boundary_weight: f64,
    /// Largest rotation, in degrees, a collapse may give the normal of a triangle it moves;
    /// guards against flipped and folded triangles. Default: `60.0`.
    pub max_normal_rotation: f64,
    /// How the feature distance is computed. Not used by [`decimate`].
    /// Default: [`DistanceOptions::DEFAULT`].
    pub distance: DistanceOptions,
    /// Keep the vertices of crease lines where they are (see the module docs). Not used by
    /// [`decimate`]. Default: `true`.
    pub keep_creases: bool,
}

impl SimplifyOptions {
    /// The default options as a constant.
    pub const DEFAULT: Self = SimplifyOptions {
        target: Target::Ratio(0.1),
        eta: 1.0,
        eps: 0.1,
        boundary_weight: 10.0,
        max_normal_rotation: 60.0,
        distance: DistanceOptions::DEFAULT,
        keep_creases: true,
    };

    /// Sets [`SimplifyOptions::target`].
    pub fn with_target(mut self, target: Target) -> Self {
        self.target = target;
        self
    }

    /// `Ok` when [`SimplifyOptions::eta`] is finite and ≥ 0 and [`SimplifyOptions::eps`]
    /// finite and > 0: what [`simplify`] checks of the weights first, for callers that do
    /// other work (extracting the lines) before it.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] naming the value out of range.
    pub fn check_weights(&self) -> Result<()> {
        if !(self.eta.is_finite() && self.eta >= 0.0) {
            return Err(Error::InvalidInput(format!(
                "eta must be a finite number >= 0, got {}",
                self.eta
            )));
        }
        if !(self.eps.is_finite() && self.eps > 0.0) {
            return Err(Error::InvalidInput(format!(
                "eps must be a finite number > 0, got {}",
                self.eps
            )));
        }
        Ok(())
    }

    /// Sets [`SimplifyOptions::eta`].
    pub fn with_eta(mut self, eta: f64) -> Self {
        self.eta = eta;
        self
    }

    /// Sets [`SimplifyOptions::eps`].
    pub fn with_eps(mut self, eps: f64) -> Self {
        self.eps = eps;
        self
    }

    /// Sets [`SimplifyOptions::boundary_weight`].
    pub fn with_boundary_weight(mut self, weight: f64) -> Self {
        self.boundary_weight = weight;
        self
    }

    /// Sets [`SimplifyOptions::max_normal_rotation`] (degrees).
    pub fn with_max_normal_rotation(mut self, degrees: f64) -> Self {
        self.max_normal_rotation = degrees;
        self
    }

    /// Sets [`SimplifyOptions::distance`].
    pub fn with_distance(mut self, distance: DistanceOptions) -> Self {
        self.distance = distance;
        self
    }
}

impl Default for SimplifyOptions {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// Candidate collapses refused, by reason. A candidate is counted each time it is examined
/// and refused (when it is queued and again when it is popped), so these are event counts,
/// not edge counts.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Rejections {
    /// An end point is a non-manifold vertex of the input.
    pub non_manifold: usize,
    /// An edge joining two boundary vertices that is not itself a boundary edge.
    pub boundary: usize,
    /// The link condition failed (the collapse would change the topology).
    pub link: usize,
    /// A moved triangle's normal would turn by more than the allowed angle.
    pub flip: usize,
    /// A moved triangle would lose (almost) all its area.
    pub degenerate: usize,
    /// The collapse would move or remove a crease vertex the constraints keep (see the module
    /// docs on creases).
    pub fixed: usize,
    /// The kept vertex would get more neighbours than the decimation allows (see the module
    /// docs, "Valence").
    pub valence: usize,
}

impl Rejections {
    /// The sum over all reasons.
    pub fn total(&self) -> usize {
        self.non_manifold
            + self.boundary
            + self.link
            + self.flip
            + self.degenerate
            + self.fixed
            + self.valence
    }
}

/// The result of [`simplify`] or [`decimate`].
#[derive(Debug, Clone)]
pub struct Simplified {
    /// The simplified mesh (unreferenced vertices dropped).
    pub mesh: TriMesh,
    /// Triangles of the input.
    pub faces_before: usize,
    /// Triangles of the result.
    pub faces_after: usize,
    /// The triangle count that was asked for.
    pub target_faces: usize,
    /// True when `faces_after <= target_faces`: the target was met (the result then has
    /// `target_faces` or `target_faces - 1` triangles, see the module docs).
    pub target_reached: bool,
    /// Edge collapses performed.
    pub collapses: usize,
    /// Refused candidates, by reason.
    pub rejected: Rejections,
    /// Passes over the candidate heap (more than one when the first ran dry).
    pub passes: usize,
    /// Candidate collapses planned: every edge once per pass, and the edges of the kept vertex
    /// after each collapse. The work of the decimation; a few per input triangle when the
    /// degrees stay bounded (see the module docs, "Valence").
    pub candidates: usize,
}

/// Crest-line-guided simplification (YBS 2005 eq. 7 weights on Garland–Heckbert quadrics).
///
/// Computes the feature distance of `lines` on `mesh`, turns it into per-triangle weights and
/// decimates. With `options.eta == 0` the lines are not looked at (plain QEM).
///
/// # Errors
/// [`Error::InvalidInput`] for options out of range (see [`decimate`]; also `eta` negative or
/// not finite, `eps` not positive) and for lines [`feature_distance`] rejects.
pub fn simplify(
    mesh: &TriMesh,
    lines: &FeatureLines,
    options: &SimplifyOptions,
) -> Result<Simplified> {
    options.check_weights()?;
    let weights = if options.eta == 0.0 {
        vec![1.0; mesh.num_faces()]
    } else {
        let distance = feature_distance(mesh, lines, &options.distance)?;
        feature_weights(&distance, options.eta, options.eps)
    };
    let creases = if options.keep_creases {
        crease_edges(mesh, lines)
    } else {
        Vec::new()
    };
    decimate_constrained(mesh, &weights, options, &creases)
}

/// The mesh edges of the crease lines of `lines` (points matched to vertices by their
/// locations, or else by position within 1e-9 of the diagonal; consecutive points on two
/// vertices joined by an edge make a crease edge). Empty without creases.
pub fn crease_edges(mesh: &TriMesh, lines: &FeatureLines) -> Vec<[u32; 2]> {
    let n = mesh.num_vertices();
    let mut edges = Vec::new();
    let creases: Vec<_> = lines.lines.iter().filter(|l| l.crease).collect();
    if creases.is_empty() {
        return edges;
    }
    let tolerance = 1e-9 * mesh.bounding_box().diagonal();
    let mut grid = None;
    for line in creases {
        let vertices: Vec<Option<u32>> = line
            .points
            .iter()
            .enumerate()
            .map(|(k, p)| {
                if let Some(SurfacePoint::Vertex(v)) = line.locations.get(k)
                    && (*v as usize) < n
                {
                    return Some(*v);
                }
                let grid = grid.get_or_insert_with(|| {
                    crate::spatial::PointGrid::new(mesh.positions(), mean_edge_length(mesh))
                });
                grid.nearest_within(*p, tolerance)
            })
            .collect();
        let m = vertices.len();
        let segments = if line.closed { m } else { m.saturating_sub(1) };
        for k in 0..segments {
            if let (Some(a), Some(b)) = (vertices[k], vertices[(k + 1) % m])
                && mesh.topology().edge_between(a, b).is_some()
            {
                edges.push([a, b]);
            }
        }
    }
    edges
}

/// Per-triangle weights `w = 1 / F(d)` with `F(d) = (d / max(d) + eps)^eta` (YBS eq. 7).
///
/// Triangles at `+∞` (no line on their component) count as `d = max(d)`, the farthest any
/// triangle is; when no triangle has a finite distance every weight is `(1 + eps)^-eta`.
pub fn feature_weights(distance: &FeatureDistance, eta: f64, eps: f64) -> Vec<f64> {
    let max = distance.max;
    distance
        .face
        .iter()
        .map(|&d| {
            let relative = if !d.is_finite() {
                1.0
            } else if max > 0.0 {
                (d / max).clamp(0.0, 1.0)
            } else {
                0.0
            };
            1.0 / (relative + eps).powf(eta)
        })
        .collect()
}

/// Weighted quadric-error edge-collapse decimation of `mesh` to `options.target`.
///
/// `face_weights` scales each triangle's quadric (one weight per triangle, finite and
/// positive); all ones is plain QEM. `eta`, `eps` and `distance` of the options are not used.
///
/// # Errors
/// [`Error::InvalidInput`] when the weights do not match the triangles or are not finite and
/// positive, a ratio target is outside (0, 1], `boundary_weight` is negative or not finite, or
/// `max_normal_rotation` is outside (0, 180].
pub fn decimate(
    mesh: &TriMesh,
    face_weights: &[f64],
    options: &SimplifyOptions,
) -> Result<Simplified> {
    decimate_constrained(mesh, face_weights, options, &[])
}

/// [`decimate`] with the mesh edges `creases` as constraints (see the module docs).
///
/// # Errors
/// As [`decimate`]; [`Error::InvalidInput`] when a crease edge names a vertex the mesh does
/// not have.
pub fn decimate_constrained(
    mesh: &TriMesh,
    face_weights: &[f64],
    options: &SimplifyOptions,
    creases: &[[u32; 2]],
) -> Result<Simplified> {
    validate(mesh, face_weights, options)?;
    let n = mesh.num_vertices();
    if let Some(e) = creases.iter().find(|e| e.iter().any(|&v| v as usize >= n)) {
        return Err(Error::InvalidInput(format!(
            "crease edge {} {} names a vertex beyond the {n} there are",
            e[0], e[1]
        )));
    }
    let faces_before = mesh.num_faces();
    let target_faces = options.target.faces_for(faces_before);
    let mut decimator = Decimator::new(mesh, face_weights, options);
    decimator.constrain(creases);
    let mut passes = 0;
    while decimator.live_faces > target_faces {
        passes += 1;
        let made = decimator.run_pass(target_faces);
        if made == 0 {
            break;
        }
    }
    let collapses = decimator.collapses;
    let rejected = decimator.rejected;
    let candidates = decimator.candidates;
    let mesh = decimator.into_mesh()?;
    let faces_after = mesh.num_faces();
    Ok(Simplified {
        mesh,
        faces_before,
        faces_after,
        target_faces,
        target_reached: faces_after <= target_faces,
        collapses,
        rejected,
        passes,
        candidates,
    })
}

fn validate(mesh: &TriMesh, face_weights: &[f64], options: &SimplifyOptions) -> Result<()> {
    if face_weights.len() != mesh.num_faces() {
        return Err(Error::InvalidInput(format!(
            "{} weights for {} triangles",
            face_weights.len(),
            mesh.num_faces()
        )));
    }
    if let Some(f) = face_weights
        .iter()
        .position(|w| !(w.is_finite() && *w > 0.0))
    {
        return Err(Error::InvalidInput(format!(
            "weight of triangle {f} is {}, not a finite positive number",
            face_weights[f]
        )));
    }
    if let Target::Ratio(r) = options.target
        && !(r > 0.0 && r <= 1.0)
    {
        return Err(Error::InvalidInput(format!(
            "target ratio must be in (0, 1], got {r}"
        )));
    }
    if !(options.boundary_weight.is_finite() && options.boundary_weight >= 0.0) {
        return Err(Error::InvalidInput(format!(
            "boundary weight must be a finite number >= 0, got {}",
            options.boundary_weight
        )));
    }
    let a = options.max_normal_rotation;
    if !(a > 0.0 && a <= 180.0) {
        return Err(Error::InvalidInput(format!(
            "max normal rotation must be in (0, 180] degrees, got {a}"
        )));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::Vec3;
    use crate::shapes;

    fn options(target: Target) -> SimplifyOptions {
        SimplifyOptions::default().with_target(target)
    }

    #[test]
    fn weights_follow_eq_7() {
        let d = FeatureDistance {
            face: vec![0.0, 1.0, 2.0, f64::INFINITY],
            max: 2.0,
            ..Default::default()
        };
        let w = feature_weights(&d, 2.0, 0.1);
        let expect = [1.0 / 0.01, 1.0 / 0.36, 1.0 / 1.21, 1.0 / 1.21];
        for (a, b) in w.iter().zip(expect) {
            assert!((a - b).abs() < 1e-9 * b, "{a} {b}");
        }
        assert!(feature_weights(&d, 0.0, 0.1).iter().all(|&x| x == 1.0));
    }

    #[test]
    fn tetrahedron_cannot_collapse() {
        let m = crate::shapes::tetrahedron();
        let r = decimate(&m, &[1.0; 4], &options(Target::Faces(2))).unwrap();
        assert_eq!(r.faces_after, 4);
        assert!(!r.target_reached);
        assert_eq!(r.collapses, 0);
        assert!(r.rejected.link > 0);
    }

    #[test]
    fn lone_triangle_is_kept() {
        let m = TriMesh::from_arrays(
            vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            vec![[0, 1, 2]],
        )
        .unwrap();
        let r = decimate(&m, &[1.0], &options(Target::Faces(0))).unwrap();
        assert_eq!(r.faces_after, 1);
    }

    #[test]
    fn flat_square_keeps_its_corners() {
        // A 4 × 4 grid on the unit square: the interior and the edges' middles can go, the
        // four corners are the only boundary vertices that cost nothing to keep.
        let m = shapes::height_field(|_, _| 0.0, [0.0, 1.0], [0.0, 1.0], 4, 4);
        let r = decimate(&m, &vec![1.0; m.num_faces()], &options(Target::Faces(2))).unwrap();
        assert_eq!(r.faces_after, 2, "{:?}", r.rejected);
        let mut corners: Vec<[f64; 3]> =
            r.mesh.positions().iter().map(|p| [p.x, p.y, p.z]).collect();
        corners.sort_by(|a, b| a.partial_cmp(b).unwrap());
        assert_eq!(
            corners,
            vec![
                [0.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [1.0, 0.0, 0.0],
                [1.0, 1.0, 0.0]
            ]
        );
    }

    #[test]
    fn bowtie_vertex_is_left_alone() {
        // Two icospheres touching at one shared vertex: that vertex is non-manifold.
        let a = shapes::icosphere(1.0, 2);
        let top = a
            .positions()
            .iter()
            .enumerate()
            .max_by(|x, y| x.1.z.total_cmp(&y.1.z))
            .unwrap()
            .0 as u32;
        let mut positions = a.positions().to_vec();
        let mut faces = a.faces().to_vec();
        let off = positions.len() as u32;
        // Mirror across the plane z = z(top), which maps `top` to itself; weld the copy's
        // `top + off` to `top` and flip the copy's winding, which the mirror reversed.
        let z = a.position(top).z;
        positions.extend(
            a.positions()
                .iter()
                .map(|p| Vec3::new(p.x, p.y, 2.0 * z - p.z)),
        );
        faces.extend(a.faces().iter().map(|t| {
            let t = t.map(|v| if v == top { top } else { v + off });
            [t[0], t[2], t[1]]
        }));
        let m = TriMesh::new(positions, faces).unwrap();
        assert_eq!(m.info().non_manifold_vertices, 1);
        let r = decimate(&m, &vec![1.0; m.num_faces()], &options(Target::Ratio(0.2))).unwrap();
        let info = r.mesh.info();
        assert_eq!(info.non_manifold_vertices, 1, "{info}");
        assert_eq!(info.non_manifold_edges, 0);
        assert!(r.rejected.non_manifold > 0);
        assert!(r.target_reached);
    }

    #[test]
    fn options_are_checked() {
        let m = shapes::icosphere(1.0, 1);
        let w = vec![1.0; m.num_faces()];
        let lines = FeatureLines::default();
        for bad in [
            options(Target::Ratio(0.0)),
            options(Target::Ratio(1.5)),
            SimplifyOptions::default().with_max_normal_rotation(0.0),
            SimplifyOptions::default().with_boundary_weight(f64::NAN),
        ] {
            assert!(decimate(&m, &w, &bad).is_err(), "{bad:?}");
        }
        assert!(decimate(&m, &w[1..], &SimplifyOptions::default()).is_err());
        let mut negative = w.clone();
        negative[3] = -1.0;
        assert!(decimate(&m, &negative, &SimplifyOptions::default()).is_err());
        for bad in [
            SimplifyOptions::default().with_eta(-1.0),
            SimplifyOptions::default().with_eps(0.0),
        ] {
            assert!(simplify(&m, &lines, &bad).is_err(), "{bad:?}");
        }
    }
}
