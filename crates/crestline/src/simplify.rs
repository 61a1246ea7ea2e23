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
//! - **Connectivity.** The [`TriMesh`] is immutable, so the collapses run on a light mutable
//!   copy (triangle list with alive flags, per-vertex triangle lists); the survivors are then
//!   compacted into a new [`TriMesh`].
//!
//! Cost: O(E log E) for the queue, with constant work per collapse on meshes of bounded
//! degree. About 1 s for 270K triangles to 10 % on one core (`BENCHMARKS.md`).
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

use rayon::prelude::*;

use crate::distance::{DistanceOptions, FeatureDistance, feature_distance};
use crate::error::{Error, Result};
use crate::lines::{FeatureLines, SurfacePoint};
use crate::mesh::{TriMesh, Vec3, VertexKind, mean_edge_length};

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
}

impl Rejections {
    /// The sum over all reasons.
    pub fn total(&self) -> usize {
        self.non_manifold + self.boundary + self.link + self.flip + self.degenerate + self.fixed
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
    if !(options.eta.is_finite() && options.eta >= 0.0) {
        return Err(Error::InvalidInput(format!(
            "eta must be a finite number >= 0, got {}",
            options.eta
        )));
    }
    if !(options.eps.is_finite() && options.eps > 0.0) {
        return Err(Error::InvalidInput(format!(
            "eps must be a finite number > 0, got {}",
            options.eps
        )));
    }
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

/// A symmetric 4 × 4 quadric `[A b; bᵀ c]`, stored as its upper triangle, whose value at `x`
/// is `xᵀAx + 2bᵀx + c`: a weighted sum of squared distances to planes.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
struct Quadric([f64; 10]);

impl Quadric {
    /// `weight` times the squared distance to the plane `n·x + d = 0` (`n` unit).
    fn plane(n: Vec3, d: f64, weight: f64) -> Self {
        let (a, b, c) = (n.x, n.y, n.z);
        Quadric(
            [
                a * a,
                a * b,
                a * c,
                a * d,
                b * b,
                b * c,
                b * d,
                c * c,
                c * d,
                d * d,
            ]
            .map(|x| x * weight),
        )
    }

    fn add(&mut self, other: &Quadric) {
        for (x, y) in self.0.iter_mut().zip(other.0) {
            *x += y;
        }
    }

    fn sum(&self, other: &Quadric) -> Quadric {
        let mut q = *self;
        q.add(other);
        q
    }

    fn value(&self, p: Vec3) -> f64 {
        let [a11, a12, a13, b1, a22, a23, b2, a33, b3, c] = self.0;
        let (x, y, z) = (p.x, p.y, p.z);
        x * (a11 * x + 2.0 * (a12 * y + a13 * z + b1))
            + y * (a22 * y + 2.0 * (a23 * z + b2))
            + z * (a33 * z + 2.0 * b3)
            + c
    }

    /// The point where the quadric is smallest, when `A` is well conditioned.
    fn minimizer(&self) -> Option<Vec3> {
        let [a11, a12, a13, b1, a22, a23, b2, a33, b3, _] = self.0;
        // Cofactors of the symmetric A (Cramer's rule).
        let c11 = a22 * a33 - a23 * a23;
        let c12 = a13 * a23 - a12 * a33;
        let c13 = a12 * a23 - a13 * a22;
        let c22 = a11 * a33 - a13 * a13;
        let c23 = a12 * a13 - a11 * a23;
        let c33 = a11 * a22 - a12 * a12;
        let det = a11 * c11 + a12 * c12 + a13 * c13;
        // For a positive semi-definite A, det / (trace/3)³ is the ratio of the geometric to
        // the arithmetic mean of the eigenvalues, cubed: near zero when one eigenvalue is
        // negligible against the others, i.e. the minimiser is not a point.
        let mean = (a11 + a22 + a33) / 3.0;
        if mean.is_nan() || mean <= 0.0 || det <= 1e-10 * mean * mean * mean {
            return None;
        }
        let x = -(c11 * b1 + c12 * b2 + c13 * b3) / det;
        let y = -(c12 * b1 + c22 * b2 + c23 * b3) / det;
        let z = -(c13 * b1 + c23 * b2 + c33 * b3) / det;
        let p = Vec3::new(x, y, z);
        p.iter().all(|c| c.is_finite()).then_some(p)
    }
}

/// Why a candidate collapse was refused.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Refusal {
    NonManifold,
    Boundary,
    Link,
    Flip,
    Degenerate,
    Fixed,
}

/// A planned collapse: `remove` merges into `keep`, which moves to `target`; `source` is the
/// input vertex whose position `target` is, or [`NEW_POSITION`].
#[derive(Debug, Clone, Copy)]
struct Plan {
    cost: f64,
    keep: u32,
    remove: u32,
    target: Vec3,
    source: u32,
}

/// The version of a vertex merged away.
const REMOVED: u32 = u32::MAX;

/// Marks a position computed by the decimation rather than taken from an input vertex.
const NEW_POSITION: u32 = u32::MAX;

/// A queued candidate, 16 bytes so that the heap stays compact: the cost as the bits of a
/// non-negative `f32` (which sort like the values; costs are computed in `f64` in normalised
/// coordinates, so `f32` keeps their order up to ties), the edge `u v`, and the sum of the
/// version stamps of `u` and `v` when it was queued. Stamps only grow, so an unchanged sum
/// means both are unchanged.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
struct Entry {
    cost: u32,
    u: u32,
    v: u32,
    stamp: u32,
}

/// The queue of candidate collapses: an exact min-priority queue with lazy deletion.
///
/// It is popped about ten times per collapse, mostly to discard stale entries, and on large
/// meshes all candidates together are far bigger than the caches, where every level of a
/// heap costs a cache miss. So only the cheapest candidates — those not above `threshold` —
/// live in a heap (four children per node: half the depth of a binary heap for about the
/// same cache lines per level); the others wait unordered in `overflow`. When the heap runs
/// dry, the overflow is purged of stale entries and its next [`REFILL`] cheapest move into
/// the heap. Pops come out in exactly the order of one big heap.
struct CandidateQueue {
    heap: Vec<Entry>,
    overflow: Vec<Entry>,
    /// Entries up to this one belong in the heap; `None` while the heap holds nothing yet.
    threshold: Option<Entry>,
}

/// How many candidates move from the overflow to the heap at a time (512 KB of entries).
const REFILL: usize = 32 * 1024;

impl CandidateQueue {
    fn from(entries: Vec<Entry>) -> Self {
        CandidateQueue {
            heap: Vec::new(),
            overflow: entries,
            threshold: None,
        }
    }

    fn push(&mut self, entry: Entry) {
        match self.threshold {
            Some(t) if entry <= t => self.push_heap(entry),
            _ => self.overflow.push(entry),
        }
    }

    /// The cheapest entry; `live` tells which overflow entries are still worth keeping when
    /// the heap is refilled (entries it rejects are dropped unseen).
    fn pop(&mut self, live: impl Fn(&Entry) -> bool) -> Option<Entry> {
        if self.heap.is_empty() {
            self.refill(live);
        }
        self.pop_heap()
    }

    fn refill(&mut self, live: impl Fn(&Entry) -> bool) {
        self.overflow.retain(|e| live(e));
        if self.overflow.is_empty() {
            return;
        }
        let m = REFILL.min(self.overflow.len());
        let (_, &mut pivot, _) = self.overflow.select_nth_unstable(m - 1);
        self.threshold = Some(pivot);
        self.heap.extend(self.overflow.drain(..m));
        // A sorted array is a valid heap.
        self.heap.sort_unstable();
    }

    fn push_heap(&mut self, entry: Entry) {
        let mut i = self.heap.len();
        self.heap.push(entry);
        while i > 0 {
            let parent = (i - 1) / 4;
            if self.heap[parent] <= entry {
                break;
            }
            self.heap[i] = self.heap[parent];
            i = parent;
        }
        self.heap[i] = entry;
    }

    fn pop_heap(&mut self) -> Option<Entry> {
        let last = self.heap.pop()?;
        let Some(&top) = self.heap.first() else {
            return Some(last);
        };
        // Sift the last entry down from the root along the smallest children.
        let n = self.heap.len();
        let mut i = 0;
        loop {
            let first = 4 * i + 1;
            if first >= n {
                break;
            }
            let mut child = first;
            for c in first + 1..(first + 4).min(n) {
                if self.heap[c] < self.heap[child] {
                    child = c;
                }
            }
            if self.heap[child] >= last {
                break;
            }
            self.heap[i] = self.heap[child];
            i = child;
        }
        self.heap[i] = last;
        Some(top)
    }
}

/// The mutable mesh the collapses run on, in coordinates centred on the bounding box and
/// scaled to a unit diagonal (which keeps the quadrics well conditioned however the input is
/// placed and sized, and the costs in the range of `f32`).
struct Decimator<'m> {
    input: &'m TriMesh,
    center: Vec3,
    scale: f64,
    positions: Vec<Vec3>,
    origin: Vec<u32>,
    faces: Vec<[u32; 3]>,
    face_alive: Vec<bool>,
    vertex_faces: Vec<Vec<u32>>,
    quadrics: Vec<Quadric>,
    boundary: Vec<bool>,
    locked: Vec<bool>,
    /// Crease corners, which no collapse may touch; empty without creases.
    fixed: Vec<bool>,
    /// Per vertex: its neighbours along creases (empty without creases).
    crease_neighbors: Vec<Vec<u32>>,
    /// Version stamp per vertex, bumped by every collapse that keeps the vertex;
    /// [`REMOVED`] once it is merged away (one array, so a liveness check reads two words).
    version: Vec<u32>,
    live_faces: usize,
    min_cos: f64,
    collapses: usize,
    rejected: Rejections,
    ring_u: Vec<u32>,
    ring_v: Vec<u32>,
}

impl<'m> Decimator<'m> {
    fn new(mesh: &'m TriMesh, face_weights: &[f64], options: &SimplifyOptions) -> Self {
        let topo = mesh.topology();
        let faces = mesh.faces().to_vec();
        let bbox = mesh.bounding_box();
        let center = bbox.center();
        let scale = match bbox.diagonal() {
            d if d > 0.0 && d.is_finite() => d,
            _ => 1.0,
        };
        let positions: Vec<Vec3> = mesh
            .positions()
            .iter()
            .map(|p| (p - center) / scale)
            .collect();
        let face_quadrics = face_quadrics(&positions, &faces, face_weights);
        let n = mesh.num_vertices();
        let mut quadrics: Vec<Quadric> = (0..n as u32)
            .into_par_iter()
            .map(|v| {
                let mut q = Quadric::default();
                for &f in topo.vertex_faces(v) {
                    q.add(&face_quadrics[f as usize]);
                }
                q
            })
            .collect();
        add_boundary_quadrics(
            mesh,
            &positions,
            face_weights,
            options.boundary_weight,
            &mut quadrics,
        );
        let kinds = topo.vertex_kinds();
        Decimator {
            input: mesh,
            center,
            scale,
            origin: (0..n as u32).collect(),
            positions,
            face_alive: vec![true; faces.len()],
            live_faces: faces.len(),
            faces,
            // Room for a few more triangles than now, which a vertex gains as it absorbs
            // its neighbours, saves most reallocations.
            vertex_faces: (0..n as u32)
                .map(|v| {
                    let faces = topo.vertex_faces(v);
                    let mut list = Vec::with_capacity(faces.len() + 4);
                    list.extend_from_slice(faces);
                    list
                })
                .collect(),
            quadrics,
            boundary: kinds.iter().map(|&k| k == VertexKind::Boundary).collect(),
            locked: kinds
                .iter()
                .map(|&k| k == VertexKind::NonManifold)
                .collect(),
            fixed: Vec::new(),
            crease_neighbors: Vec::new(),
            // Unreferenced vertices take part in nothing.
            version: kinds
                .iter()
                .map(|&k| {
                    if k == VertexKind::Unreferenced {
                        REMOVED
                    } else {
                        0
                    }
                })
                .collect(),
            min_cos: options.max_normal_rotation.to_radians().cos(),
            collapses: 0,
            rejected: Rejections::default(),
            ring_u: Vec::new(),
            ring_v: Vec::new(),
        }
    }

    /// Sets the crease constraints: neighbours along `creases`, corners fixed.
    fn constrain(&mut self, creases: &[[u32; 2]]) {
        if creases.is_empty() {
            return;
        }
        let n = self.positions.len();
        let mut neighbors = vec![Vec::new(); n];
        for &[a, b] in creases {
            if a != b && !neighbors[a as usize].contains(&b) {
                neighbors[a as usize].push(b);
                neighbors[b as usize].push(a);
            }
        }
        self.fixed = neighbors
            .iter()
            .map(|c| !c.is_empty() && c.len() != 2)
            .collect();
        self.crease_neighbors = neighbors;
    }

    /// Queues every current edge, then collapses the cheapest valid candidates until the
    /// target is met or the queue is empty. Returns the number of collapses made.
    fn run_pass(&mut self, target_faces: usize) -> usize {
        let mut heap = self.rank_edge_collapses();
        let before = self.collapses;
        while self.live_faces > target_faces {
            let Some(Entry { u, v, stamp, .. }) = heap.pop(|e| self.is_live(e)) else {
                break;
            };
            if !self.is_live(&Entry {
                cost: 0,
                u,
                v,
                stamp,
            }) {
                continue;
            }
            let checked = self
                .plan_collapse(u, v)
                .and_then(|plan| self.check_link_condition(u, v).map(|()| plan))
                .and_then(|plan| self.check_moved_faces(&plan).map(|()| plan));
            match checked {
                Ok(plan) => {
                    self.perform_collapse(&plan);
                    self.queue_edges_of(plan.keep, &mut heap);
                }
                Err(r) => self.count(r),
            }
        }
        self.collapses - before
    }

    /// All current edges with their planned collapse, as a heap.
    fn rank_edge_collapses(&mut self) -> CandidateQueue {
        let this = &*self;
        let planned: Vec<Result<Entry, Refusal>> = (0..this.positions.len() as u32)
            .into_par_iter()
            .filter(|&u| this.version[u as usize] != REMOVED)
            .flat_map_iter(|u| {
                let mut ring = Vec::new();
                this.collect_ring(u, &mut ring);
                ring.retain(|&w| w > u);
                ring.into_iter().map(move |w| this.entry(u, w))
            })
            .collect();
        let mut entries = Vec::with_capacity(planned.len());
        for p in planned {
            match p {
                Ok(e) => entries.push(e),
                Err(r) => self.count(r),
            }
        }
        CandidateQueue::from(entries)
    }

    fn entry(&self, u: u32, v: u32) -> Result<Entry, Refusal> {
        let plan = self.plan_collapse(u, v)?;
        Ok(Entry {
            cost: (plan.cost as f32).to_bits(),
            u,
            v,
            stamp: self.stamp(u, v),
        })
    }

    /// False for entries made stale by a collapse since they were queued.
    fn is_live(&self, e: &Entry) -> bool {
        let (vu, vv) = (self.version[e.u as usize], self.version[e.v as usize]);
        vu != REMOVED && vv != REMOVED && vu.wrapping_add(vv) == e.stamp
    }

    fn stamp(&self, u: u32, v: u32) -> u32 {
        self.version[u as usize].wrapping_add(self.version[v as usize])
    }

    fn queue_edges_of(&mut self, v: u32, heap: &mut CandidateQueue) {
        let mut ring = std::mem::take(&mut self.ring_u);
        self.collect_ring(v, &mut ring);
        for &w in &ring {
            match self.entry(v, w) {
                Ok(e) => heap.push(e),
                Err(r) => self.count(r),
            }
        }
        self.ring_u = ring;
    }

    fn count(&mut self, refusal: Refusal) {
        let r = &mut self.rejected;
        match refusal {
            Refusal::NonManifold => r.non_manifold += 1,
            Refusal::Boundary => r.boundary += 1,
            Refusal::Link => r.link += 1,
            Refusal::Flip => r.flip += 1,
            Refusal::Degenerate => r.degenerate += 1,
            Refusal::Fixed => r.fixed += 1,
        }
    }

    fn live_faces_of(&self, v: u32) -> impl Iterator<Item = u32> + '_ {
        self.vertex_faces[v as usize]
            .iter()
            .copied()
            .filter(|&f| self.face_alive[f as usize])
    }

    /// The neighbours of `v`, sorted, each once.
    fn collect_ring(&self, v: u32, ring: &mut Vec<u32>) {
        ring.clear();
        for f in self.live_faces_of(v) {
            ring.extend(self.faces[f as usize].iter().filter(|&&w| w != v));
        }
        ring.sort_unstable();
        ring.dedup();
    }

    /// Number of live triangles on edge `u v`.
    fn edge_face_count(&self, u: u32, v: u32) -> usize {
        self.live_faces_of(u)
            .filter(|&f| self.faces[f as usize].contains(&v))
            .count()
    }

    /// Where the merged vertex goes and at what cost (see the module docs on placement).
    fn plan_collapse(&self, u: u32, v: u32) -> Result<Plan, Refusal> {
        if self.locked[u as usize] || self.locked[v as usize] {
            return Err(Refusal::NonManifold);
        }
        let on_crease = |w: u32| {
            self.crease_neighbors
                .get(w as usize)
                .is_some_and(|c| !c.is_empty())
        };
        let q = self.quadrics[u as usize].sum(&self.quadrics[v as usize]);
        let (pu, pv) = (self.positions[u as usize], self.positions[v as usize]);
        let at = |keep: u32, remove: u32, target: Vec3, source: u32| Plan {
            cost: q.value(target).max(0.0),
            keep,
            remove,
            target,
            source,
        };
        let at_u = || at(u, v, pu, self.origin[u as usize]);
        let at_v = || at(v, u, pv, self.origin[v as usize]);
        let cheaper = |a: Plan, b: Plan| if b.cost < a.cost { b } else { a };
        if on_crease(u) || on_crease(v) {
            if self.boundary[u as usize] || self.boundary[v as usize] {
                return Err(Refusal::Fixed);
            }
            return match (on_crease(u), on_crease(v)) {
                (true, true) if self.crease_neighbors[u as usize].contains(&v) => {
                    // Corners are never removed.
                    match (self.fixed[v as usize], self.fixed[u as usize]) {
                        (false, false) => Ok(cheaper(at_u(), at_v())),
                        (false, true) => Ok(at_u()),
                        (true, false) => Ok(at_v()),
                        (true, true) => Err(Refusal::Fixed),
                    }
                }
                (true, true) => Err(Refusal::Fixed),
                (true, false) => Ok(at_u()),
                _ => Ok(at_v()),
            };
        }
        let plan = match (self.boundary[u as usize], self.boundary[v as usize]) {
            (true, true) => {
                if self.edge_face_count(u, v) != 1 {
                    return Err(Refusal::Boundary);
                }
                cheaper(at_u(), at_v())
            }
            (true, false) => at_u(),
            (false, true) => at_v(),
            (false, false) => {
                let mid = (pu + pv) * 0.5;
                let reach = 2.0 * (pu - pv).norm();
                match q.minimizer() {
                    Some(x) if (x - mid).norm() <= reach => at(v, u, x, NEW_POSITION),
                    _ => cheaper(cheaper(at_v(), at_u()), at(v, u, mid, NEW_POSITION)),
                }
            }
        };
        Ok(plan)
    }

    /// The link condition for collapsing edge `u v` on a surface with boundary (a boundary
    /// counts as joined to a virtual vertex): the common neighbours of `u` and `v` must be
    /// exactly the apexes of the triangles on `u v`, and no edge of both links may survive
    /// (which would fold a tetrahedron or a lone triangle flat).
    fn check_link_condition(&mut self, u: u32, v: u32) -> Result<(), Refusal> {
        let mut apexes = [0u32; 2];
        let mut count = 0;
        for f in self.live_faces_of(u) {
            let t = self.faces[f as usize];
            if t.contains(&v) {
                if count == 2 {
                    return Err(Refusal::Link);
                }
                apexes[count] = t.iter().copied().find(|&w| w != u && w != v).unwrap_or(u);
                count += 1;
            }
        }
        if count == 0 {
            return Err(Refusal::Link);
        }
        let (mut ring_u, mut ring_v) = (
            std::mem::take(&mut self.ring_u),
            std::mem::take(&mut self.ring_v),
        );
        self.collect_ring(u, &mut ring_u);
        self.collect_ring(v, &mut ring_v);
        let common = count_common(&ring_u, &ring_v);
        self.ring_u = ring_u;
        self.ring_v = ring_v;
        if common != count {
            return Err(Refusal::Link);
        }
        let has_face = |x: u32, a: u32, b: u32| {
            self.live_faces_of(x).any(|f| {
                let t = self.faces[f as usize];
                t.contains(&a) && t.contains(&b)
            })
        };
        match count {
            // Triangles u c d and v c d would both become x c d.
            2 => {
                let (c, d) = (apexes[0], apexes[1]);
                if has_face(u, c, d) && has_face(v, c, d) {
                    return Err(Refusal::Link);
                }
            }
            // u c and v c on the boundary too: the triangle hangs by c alone (or is alone).
            _ => {
                let c = apexes[0];
                if self.edge_face_count(u, c) == 1 && self.edge_face_count(v, c) == 1 {
                    return Err(Refusal::Link);
                }
            }
        }
        Ok(())
    }

    /// Refuses a collapse that turns a moved triangle by more than the allowed angle or
    /// leaves it without area.
    fn check_moved_faces(&self, plan: &Plan) -> Result<(), Refusal> {
        let (u, v) = (plan.keep, plan.remove);
        for x in [u, v] {
            for f in self.live_faces_of(x) {
                let t = self.faces[f as usize];
                if t.contains(&u) && t.contains(&v) {
                    continue;
                }
                let old = t.map(|w| self.positions[w as usize]);
                let new = t.map(|w| {
                    if w == u || w == v {
                        plan.target
                    } else {
                        self.positions[w as usize]
                    }
                });
                let n_old = (old[1] - old[0]).cross(&(old[2] - old[0]));
                let n_new = (new[1] - new[0]).cross(&(new[2] - new[0]));
                let longest = (new[1] - new[0])
                    .norm_squared()
                    .max((new[2] - new[1]).norm_squared())
                    .max((new[0] - new[2]).norm_squared());
                // Far above the 1e-13 at which TriMesh drops a triangle as degenerate.
                if n_new.norm() <= 1e-8 * longest {
                    return Err(Refusal::Degenerate);
                }
                if n_old.dot(&n_new) < self.min_cos * n_old.norm() * n_new.norm() {
                    return Err(Refusal::Flip);
                }
            }
        }
        Ok(())
    }

    fn perform_collapse(&mut self, plan: &Plan) {
        let (k, r) = (plan.keep as usize, plan.remove as usize);
        self.positions[k] = plan.target;
        self.origin[k] = plan.source;
        let qr = self.quadrics[r];
        self.quadrics[k].add(&qr);
        self.boundary[k] |= self.boundary[r];
        if let Some(moved) = self.crease_neighbors.get_mut(r).map(std::mem::take) {
            // Along a crease: r's other crease neighbours become k's.
            let (keep, remove) = (plan.keep, plan.remove);
            for w in moved {
                if w == keep {
                    continue;
                }
                for x in &mut self.crease_neighbors[w as usize] {
                    if *x == remove {
                        *x = keep;
                    }
                }
                self.crease_neighbors[k].push(w);
            }
            self.crease_neighbors[k].retain(|&x| x != remove);
        }
        self.version[r] = REMOVED;
        // Skipping the sentinel keeps a live vertex from ever looking removed.
        self.version[k] = (self.version[k] + 1) % REMOVED;
        let moved = std::mem::take(&mut self.vertex_faces[r]);
        for f in moved {
            if !self.face_alive[f as usize] {
                continue;
            }
            let t = &mut self.faces[f as usize];
            if t.contains(&plan.keep) {
                self.face_alive[f as usize] = false;
                self.live_faces -= 1;
                if let Some(&c) = t.iter().find(|&&w| w != plan.keep && w != plan.remove) {
                    let alive = &self.face_alive;
                    self.vertex_faces[c as usize].retain(|&g| alive[g as usize]);
                }
            } else {
                for w in t.iter_mut() {
                    if *w == plan.remove {
                        *w = plan.keep;
                    }
                }
                self.vertex_faces[k].push(f);
            }
        }
        let alive = &self.face_alive;
        self.vertex_faces[k].retain(|&g| alive[g as usize]);
        self.collapses += 1;
    }

    /// The live triangles over the surviving vertices, renumbered, back in input coordinates
    /// (vertices that kept or took an input vertex's place get its position bit for bit).
    fn into_mesh(self) -> Result<TriMesh> {
        let mut index = vec![u32::MAX; self.positions.len()];
        let mut positions = Vec::new();
        let mut faces = Vec::with_capacity(self.live_faces);
        for (f, t) in self.faces.iter().enumerate() {
            if !self.face_alive[f] {
                continue;
            }
            faces.push(t.map(|v| {
                let i = &mut index[v as usize];
                if *i == u32::MAX {
                    *i = positions.len() as u32;
                    positions.push(match self.origin[v as usize] {
                        NEW_POSITION => self.positions[v as usize] * self.scale + self.center,
                        o => self.input.position(o),
                    });
                }
                *i
            }));
        }
        TriMesh::new(positions, faces)
    }
}

/// Each triangle's `w · area · plane quadric`.
fn face_quadrics(positions: &[Vec3], faces: &[[u32; 3]], face_weights: &[f64]) -> Vec<Quadric> {
    faces
        .par_iter()
        .enumerate()
        .map(|(f, t)| {
            let [a, b, c] = t.map(|v| positions[v as usize]);
            let cross = (b - a).cross(&(c - a));
            let area = 0.5 * cross.norm();
            match cross.try_normalize(0.0) {
                Some(n) => Quadric::plane(n, -n.dot(&a), face_weights[f] * area),
                None => Quadric::default(),
            }
        })
        .collect()
}

/// Adds, for each boundary edge, the plane through it perpendicular to its triangle to both
/// end points, weighted by `boundary_weight · w · length²`.
fn add_boundary_quadrics(
    mesh: &TriMesh,
    positions: &[Vec3],
    face_weights: &[f64],
    boundary_weight: f64,
    quadrics: &mut [Quadric],
) {
    if boundary_weight == 0.0 {
        return;
    }
    let topo = mesh.topology();
    for e in 0..topo.num_edges() as u32 {
        let &[f] = topo.edge_faces(e) else {
            continue;
        };
        let [a, b] = topo.edge(e);
        let [p, q, r] = mesh.faces()[f as usize].map(|v| positions[v as usize]);
        let normal = (q - p).cross(&(r - p));
        let (pa, pb) = (positions[a as usize], positions[b as usize]);
        let edge = pb - pa;
        let Some(m) = edge.cross(&normal).try_normalize(0.0) else {
            continue;
        };
        let weight = boundary_weight * face_weights[f as usize] * edge.norm_squared();
        let plane = Quadric::plane(m, -m.dot(&pa), weight);
        quadrics[a as usize].add(&plane);
        quadrics[b as usize].add(&plane);
    }
}

/// Number of values in both sorted, deduplicated slices.
fn count_common(a: &[u32], b: &[u32]) -> usize {
    let (mut i, mut j, mut n) = (0, 0, 0);
    while i < a.len() && j < b.len() {
        match a[i].cmp(&b[j]) {
            std::cmp::Ordering::Less => i += 1,
            std::cmp::Ordering::Greater => j += 1,
            std::cmp::Ordering::Equal => {
                n += 1;
                i += 1;
                j += 1;
            }
        }
    }
    n
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes;

    fn options(target: Target) -> SimplifyOptions {
        SimplifyOptions::default().with_target(target)
    }

    #[test]
    fn queue_pops_in_order_across_refills() {
        let mut state = 7u64;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 40) as u32
        };
        let entry = |cost: u32, u: u32| Entry {
            cost,
            u,
            v: u + 1,
            stamp: 0,
        };
        // More than two refills' worth. Entries with u % 7 == 3 count as stale: the queue
        // drops them when they pass through a refill, which every initial entry does.
        // Pushed entries (some below, some above the threshold) are all live.
        let entries: Vec<Entry> = (0..3 * REFILL as u32).map(|i| entry(next(), i)).collect();
        let mut reference = std::collections::BinaryHeap::new();
        reference.extend(entries.iter().map(|&e| std::cmp::Reverse(e)));
        let mut queue = CandidateQueue::from(entries);
        let live = |e: &Entry| e.u % 7 != 3;
        let mut popped = 0;
        while let Some(e) = queue.pop(live) {
            let expected = loop {
                let std::cmp::Reverse(r) = reference.pop().unwrap();
                if live(&r) {
                    break r;
                }
            };
            assert_eq!(e, expected);
            popped += 1;
            if popped % 3 == 0 {
                let extra = entry(e.cost + next() % 5000, 7 * (1_000_000 + popped));
                queue.push(extra);
                reference.push(std::cmp::Reverse(extra));
            }
        }
        assert!(reference.iter().all(|r| !live(&r.0)));
        assert!(popped > 2 * REFILL as u32);
    }

    #[test]
    fn minimizer_is_the_corner_of_three_planes() {
        let mut q = Quadric::default();
        for (n, d) in [(Vec3::x(), -1.0), (Vec3::y(), -2.0), (Vec3::z(), 3.0)] {
            q.add(&Quadric::plane(n, d, 1.5));
        }
        let x = q.minimizer().unwrap();
        assert!((x - Vec3::new(1.0, 2.0, -3.0)).norm() < 1e-12);
        assert!(q.value(x).abs() < 1e-12);
        assert!((q.value(Vec3::new(1.0, 2.0, -1.0)) - 1.5 * 4.0).abs() < 1e-12);
        // Two planes meet in a line: no unique minimiser.
        let mut crease = Quadric::plane(Vec3::x(), 0.0, 1.0);
        crease.add(&Quadric::plane(Vec3::y(), 0.0, 1.0));
        assert_eq!(crease.minimizer(), None);
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
        let m = TriMesh::from_arrays(
            vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [0.0, 0.0, 1.0],
            ],
            vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
        )
        .unwrap();
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
