//! Feature distance: the geodesic distance from every vertex and triangle to the nearest
//! feature line.
//!
//! YBS 2005 (section "Crest Lines and Mesh Simplification") guides its simplification by the
//! geodesic distance `d` to the closest crest line point, which enters the weight of eq. 7,
//! `F(d) = (d / max(d) + ε)^η` (see [`crate::simplify`]). The paper computes a discrete `d_i`
//! per triangle with Floyd–Warshall over the triangle adjacency graph (centroid → edge midpoint
//! → centroid), which is cubic in the number of triangles. Here it takes O(n log n):
//!
//! 1. **Seeding.** Every vertex of a triangle the lines pass through gets its Euclidean
//!    distance to the nearest line segment. When a line carries
//!    [`locations`](crate::lines::FeatureLine::locations) (lines traced on this mesh), the
//!    triangles are those around the locations of each segment's two end points; otherwise
//!    (lines read from a file) points sampled along each segment are located on the mesh by a
//!    uniform grid of the triangles ([`FaceGrid`]), and the triangles around the corners of
//!    each located triangle are taken, so that slivers the line crosses between two samples
//!    are not missed. Seeding only the vertices next to the line matters: a vertex reached
//!    across the line by an edge gets an overestimate (the distance has a kink there).
//! 2. **Propagation.** Dijkstra's algorithm over the mesh edges from all seeds at once. With
//!    [`DistanceOptions::relax_across_triangles`] (the default) a settled vertex also updates
//!    the third corner of each triangle whose other corner is settled, by the planar-front
//!    update of the fast marching method on triangulated domains (R. Kimmel, J. A. Sethian,
//!    "Computing geodesic paths on manifolds", PNAS 1998): the distance is taken linear over
//!    the triangle with a unit gradient, which lets fronts cross triangles diagonally.
//! 3. **Per triangle.** The mean of the three corner values: the linear interpolant at the
//!    centroid, the point the paper's graph measures from.
//!
//! ## Known limits
//! - Edge-only Dijkstra overestimates geodesics: a path restricted to edges zig-zags, by up to
//!   ~8 % on a regular grid with diagonals (and more on poorly shaped meshes). The triangle
//!   update removes this for straight fronts (the distance to a straight line on a plane is
//!   reproduced exactly) and reduces it elsewhere, but the result is still a first-order
//!   approximation: near the end points of lines (circular fronts) it is off by O(h), and an
//!   update is only accepted when the front reaches the vertex from inside the triangle, so
//!   obtuse triangles fall back to edge updates. Seeds use Euclidean distance, which is below
//!   the geodesic one on curved surfaces (by O(h²) within the seeded triangles).
//! - The field is 1-Lipschitz along mesh edges (`|d(u) - d(v)| <= |u - v|`), never negative,
//!   and zero at mesh vertices that lie on a line.
//! - Vertices of components no line reaches, and unreferenced vertices, get `+∞`;
//!   [`FeatureDistance::max`] is the largest finite value. [`crate::simplify::feature_weights`]
//!   treats `+∞` as `max` (as far from the lines as anything gets).

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use crate::error::{Error, Result};
use crate::lines::{FeatureLine, FeatureLines, SurfacePoint};
use crate::mesh::{BoundingBox, TriMesh, Vec3, mean_edge_length};
use crate::spatial::{FaceGrid, closest_point_on_segment};

/// Options of [`feature_distance`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DistanceOptions {
    /// Also relax distances across triangles (planar-front update), not only along edges.
    /// Turning it off gives plain edge-graph Dijkstra, which overestimates. Default: `true`.
    pub relax_across_triangles: bool,
    /// Spacing of the points sampled along lines that carry no mesh locations, as a fraction
    /// of the mesh's mean edge length. Smaller values seed more triangles along the line.
    /// Default: `0.5`.
    pub sample_spacing: f64,
}

impl DistanceOptions {
    /// The default options as a constant.
    pub const DEFAULT: Self = DistanceOptions {
        relax_across_triangles: true,
        sample_spacing: 0.5,
    };

    /// Sets [`DistanceOptions::relax_across_triangles`].
    pub fn with_relax_across_triangles(mut self, relax: bool) -> Self {
        self.relax_across_triangles = relax;
        self
    }

    /// Sets [`DistanceOptions::sample_spacing`].
    pub fn with_sample_spacing(mut self, spacing: f64) -> Self {
        self.sample_spacing = spacing;
        self
    }
}

impl Default for DistanceOptions {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// The feature distance field (see the module docs).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FeatureDistance {
    /// Distance per vertex; `+∞` for vertices no line reaches (other components, unreferenced).
    pub vertex: Vec<f64>,
    /// Distance per triangle: the mean of its corners' values (`+∞` if one of them is).
    pub face: Vec<f64>,
    /// Largest finite value over vertices and triangles (0 when there is none).
    pub max: f64,
    /// Referenced vertices left at `+∞`.
    pub unreached_vertices: usize,
    /// Vertices that got a value directly from the lines.
    pub seeded_vertices: usize,
}

/// Geodesic distance from every vertex and triangle of `mesh` to the nearest of `lines`.
///
/// Lines without any point are ignored; with no line at all every value is `+∞`.
///
/// ```
/// use crestline::distance::{DistanceOptions, feature_distance};
///
/// # fn main() -> crestline::Result<()> {
/// // A box with curved faces and its 12 crease edges as lines.
/// let (mesh, creases) = crestline::shapes::pillow_box(1.0, 0.25, 8);
/// let d = feature_distance(&mesh, &creases, &DistanceOptions::default())?;
/// assert_eq!(d.vertex.len(), mesh.num_vertices());
/// assert_eq!(d.unreached_vertices, 0);
/// // Face centres are farthest from the edges, about a face's half width away.
/// assert!(d.max > 0.9 && d.max < 1.3, "{}", d.max);
/// # Ok(())
/// # }
/// ```
///
/// # Errors
/// [`Error::InvalidInput`] when a line point is not finite, a line's `locations` are neither
/// empty nor one per point, a location refers to an element the mesh does not have, a point
/// lies further than [`LINE_REACH`] diagonals outside the mesh's bounding box or from its
/// location on the mesh (lines of another mesh), or `options.sample_spacing` is not
/// positive.
pub fn feature_distance(
    mesh: &TriMesh,
    lines: &FeatureLines,
    options: &DistanceOptions,
) -> Result<FeatureDistance> {
    if !(options.sample_spacing.is_finite() && options.sample_spacing > 0.0) {
        return Err(Error::InvalidInput(format!(
            "sample spacing must be positive, got {}",
            options.sample_spacing
        )));
    }
    let seeds = seed_vertices(mesh, lines, options)?;
    let vertex = propagate_distances(mesh, &seeds, options.relax_across_triangles);
    Ok(summarize(mesh, vertex, seeds.len()))
}

/// Vertices near the lines with their Euclidean distance to the nearest segment (step 1 of
/// the module docs). A vertex appears at most once.
///
/// # Errors
/// As [`feature_distance`].
pub fn seed_vertices(
    mesh: &TriMesh,
    lines: &FeatureLines,
    options: &DistanceOptions,
) -> Result<Vec<(u32, f64)>> {
    let mut seed = vec![f64::INFINITY; mesh.num_vertices()];
    let mut grid: Option<FaceGrid<'_>> = None;
    let spacing = options.sample_spacing * mean_edge_length(mesh);
    let bounds = mesh.bounding_box();
    for (index, line) in lines.lines.iter().enumerate() {
        validate_line(mesh, &bounds, index, line)?;
        if line.points.is_empty() || mesh.num_faces() == 0 {
            continue;
        }
        let located = !line.locations.is_empty();
        let mut faces = Vec::new();
        for (p, q, i, j) in segments(line) {
            faces.clear();
            if located {
                faces_at(mesh, line.locations[i], &mut faces);
                faces_at(mesh, line.locations[j], &mut faces);
            } else {
                let grid = grid.get_or_insert_with(|| FaceGrid::new(mesh));
                let length = (q - p).norm();
                // At least the two end points; more where the segment is long against the
                // mesh, so that consecutive samples fall in touching triangles.
                let steps = if spacing > 0.0 {
                    (length / spacing).ceil().clamp(1.0, 1e7) as usize
                } else {
                    1
                };
                let topo = mesh.topology();
                for k in 0..=steps {
                    let x = p + (q - p) * (k as f64 / steps as f64);
                    if let Some(hit) = grid.closest_point(x) {
                        // The line may cross slivers between two samples; every triangle it
                        // crosses near a sample touches the located one at a corner.
                        for v in mesh.faces()[hit.face as usize] {
                            faces.extend_from_slice(topo.vertex_faces(v));
                        }
                    }
                }
                faces.sort_unstable();
                faces.dedup();
            }
            for &f in &faces {
                for v in mesh.faces()[f as usize] {
                    let d = point_segment_distance(mesh.position(v), p, q);
                    let s = &mut seed[v as usize];
                    *s = s.min(d);
                }
            }
        }
    }
    Ok(seed
        .iter()
        .enumerate()
        .filter(|(_, d)| d.is_finite())
        .map(|(v, &d)| (v as u32, d))
        .collect())
}

/// Shortest distances from `seeds` over the mesh (step 2 of the module docs): Dijkstra over
/// edges, plus the planar-front update across triangles when `relax_across_triangles`.
/// Vertices not reached get `+∞`.
pub fn propagate_distances(
    mesh: &TriMesh,
    seeds: &[(u32, f64)],
    relax_across_triangles: bool,
) -> Vec<f64> {
    let n = mesh.num_vertices();
    let topo = mesh.topology();
    let faces = mesh.faces();
    let pos = mesh.positions();
    let mut dist = vec![f64::INFINITY; n];
    let mut settled = vec![false; n];
    // Distances are never negative, and the bit patterns of non-negative f64 sort like their
    // values, so the heap can order plain integers.
    let mut heap: BinaryHeap<Reverse<(u64, u32)>> = BinaryHeap::with_capacity(seeds.len());
    for &(v, d) in seeds {
        let d = d.max(0.0);
        if (v as usize) < n && d < dist[v as usize] {
            dist[v as usize] = d;
            heap.push(Reverse((d.to_bits(), v)));
        }
    }
    let offer = |w: u32, d: f64, dist: &mut [f64], heap: &mut BinaryHeap<_>| {
        if d < dist[w as usize] {
            dist[w as usize] = d;
            heap.push(Reverse((d.to_bits(), w)));
        }
    };
    while let Some(Reverse((bits, v))) = heap.pop() {
        let d = f64::from_bits(bits);
        if settled[v as usize] || d > dist[v as usize] {
            continue;
        }
        settled[v as usize] = true;
        let p = pos[v as usize];
        for w in topo.neighbors(v) {
            if !settled[w as usize] {
                let dw = d + (pos[w as usize] - p).norm();
                offer(w, dw, &mut dist, &mut heap);
            }
        }
        if !relax_across_triangles {
            continue;
        }
        for &f in topo.vertex_faces(v) {
            let t = faces[f as usize];
            let c = t.iter().position(|&x| x == v).unwrap_or(0);
            let (a, b) = (t[(c + 1) % 3], t[(c + 2) % 3]);
            for (known, target) in [(a, b), (b, a)] {
                if settled[known as usize] && !settled[target as usize] {
                    let update = planar_front_update(
                        p,
                        d,
                        pos[known as usize],
                        dist[known as usize],
                        pos[target as usize],
                    );
                    if let Some(dt) = update {
                        offer(target, dt, &mut dist, &mut heap);
                    }
                }
            }
        }
    }
    dist
}

/// The distance at `c` of the linear field with unit gradient over triangle `a b c` that
/// takes the values `da` at `a` and `db` at `b`, when the front it describes reaches `c` from
/// inside the triangle (the upwind condition of fast marching); `None` otherwise.
fn planar_front_update(a: Vec3, da: f64, b: Vec3, db: f64, c: Vec3) -> Option<f64> {
    let (ea, eb) = (a - c, b - c);
    let (q11, q12, q22) = (ea.dot(&ea), ea.dot(&eb), eb.dot(&eb));
    let det = q11 * q22 - q12 * q12;
    if det <= 1e-12 * q11 * q22 {
        return None;
    }
    // With g = α ea + β eb the gradient: g·ea = da - t, g·eb = db - t and |g| = 1 give a
    // quadratic in t, the value at c; the larger root is the front arriving last.
    let qa = q11 - 2.0 * q12 + q22;
    let qb = 2.0 * (q12 * (da + db) - q22 * da - q11 * db);
    let qc = q22 * da * da - 2.0 * q12 * da * db + q11 * db * db - det;
    let disc = qb * qb - 4.0 * qa * qc;
    if disc < 0.0 || qa <= 0.0 {
        return None;
    }
    let t = (-qb + disc.sqrt()) / (2.0 * qa);
    let (r1, r2) = (da - t, db - t);
    let alpha = (q22 * r1 - q12 * r2) / det;
    let beta = (q11 * r2 - q12 * r1) / det;
    // The front comes from the side of edge a b: -g must lie in the cone of ea and eb. Keeping
    // t above both known values also keeps Dijkstra's settle order monotone.
    if alpha > 0.0 || beta > 0.0 || t < da.max(db) || !t.is_finite() {
        return None;
    }
    Some(t)
}

fn summarize(mesh: &TriMesh, vertex: Vec<f64>, seeded_vertices: usize) -> FeatureDistance {
    let face: Vec<f64> = mesh
        .faces()
        .iter()
        .map(|t| t.iter().map(|&v| vertex[v as usize]).sum::<f64>() / 3.0)
        .collect();
    let max = vertex
        .iter()
        .chain(&face)
        .filter(|d| d.is_finite())
        .fold(0.0f64, |m, &d| m.max(d));
    let topo = mesh.topology();
    let unreached_vertices = vertex
        .iter()
        .enumerate()
        .filter(|&(v, d)| !d.is_finite() && !topo.vertex_faces(v as u32).is_empty())
        .count();
    FeatureDistance {
        vertex,
        face,
        max,
        unreached_vertices,
        seeded_vertices,
    }
}

fn validate_line(
    mesh: &TriMesh,
    bounds: &BoundingBox,
    index: usize,
    line: &FeatureLine,
) -> Result<()> {
    if let Some(i) = line
        .points
        .iter()
        .position(|p| !p.iter().all(|c| c.is_finite()))
    {
        return Err(Error::InvalidInput(format!(
            "line {index}: point {i} has a non-finite coordinate"
        )));
    }
    // Lines of this mesh lie on it (fairing moves them by a fraction of a percent of the
    // diagonal): a point far outside its box belongs to another mesh, or to this one in
    // other units or another place.
    let diagonal = bounds.diagonal();
    let outside = |p: &[f64; 3]| -> f64 {
        let d: [f64; 3] =
            std::array::from_fn(|k| (bounds.min[k] - p[k]).max(p[k] - bounds.max[k]).max(0.0));
        // Scaled, so that a point at 1e308 does not overflow to infinity.
        let largest = d.iter().fold(0.0, |m: f64, &x| m.max(x));
        if largest > 0.0 {
            largest * d.iter().map(|x| (x / largest).powi(2)).sum::<f64>().sqrt()
        } else {
            0.0
        }
    };
    if let Some((i, d)) = line
        .points
        .iter()
        .map(|p| outside(&(*p).into()))
        .enumerate()
        .find(|&(_, d)| d.is_nan() || d > LINE_REACH * diagonal)
    {
        return Err(Error::InvalidInput(format!(
            "line {index}: point {i} is {d:.6e} outside the mesh's bounding box (diagonal \
             {diagonal:.6e}): the lines belong to another mesh"
        )));
    }
    if line.locations.is_empty() {
        return Ok(());
    }
    if line.locations.len() != line.points.len() {
        return Err(Error::InvalidInput(format!(
            "line {index}: {} locations for {} points",
            line.locations.len(),
            line.points.len()
        )));
    }
    let topo = mesh.topology();
    for (i, loc) in line.locations.iter().enumerate() {
        let ok = match *loc {
            SurfacePoint::Edge { edge, t } => (edge as usize) < topo.num_edges() && t.is_finite(),
            SurfacePoint::Face { face } => (face as usize) < mesh.num_faces(),
            SurfacePoint::Vertex(v) => (v as usize) < mesh.num_vertices(),
        };
        if !ok {
            return Err(Error::InvalidInput(format!(
                "line {index}: location {i} ({loc:?}) is not on this mesh"
            )));
        }
    }
    // Each point must be where its location is on this mesh.
    for (i, loc) in line.locations.iter().enumerate() {
        let point = line.points[i];
        let off = match *loc {
            SurfacePoint::Edge { edge, t } => {
                let [a, b] = topo.edge(edge).map(|v| mesh.position(v));
                (a + (b - a) * t - point).norm()
            }
            SurfacePoint::Face { face } => {
                let corners = mesh.triangle(face as usize);
                (crate::spatial::closest_point_on_triangle(point, corners) - point).norm()
            }
            SurfacePoint::Vertex(v) => (mesh.position(v) - point).norm(),
        };
        if off.is_nan() || off > LINE_REACH * diagonal {
            return Err(Error::InvalidInput(format!(
                "line {index}: point {i} is {off:.6e} from its place on this mesh ({}): the \
                 lines were traced on another mesh (or on this one welded or turned otherwise)",
                match *loc {
                    SurfacePoint::Edge { edge, .. } => format!("edge {edge}"),
                    SurfacePoint::Face { face } => format!("triangle {face}"),
                    SurfacePoint::Vertex(v) => format!("vertex {v}"),
                }
            )));
        }
    }
    Ok(())
}

/// How far (as a fraction of the mesh's bounding-box diagonal) a line point may lie outside
/// the mesh's box, or a traced point from its place on the mesh, before the lines are taken
/// for another mesh's. Fairing moves points by far less (its tolerance is a fraction of a
/// percent of the diagonal).
pub const LINE_REACH: f64 = 0.05;

/// The segments of a line as (start, end, start index, end index); a single point is a
/// segment of length zero and a closed line gets its closing segment.
fn segments(line: &FeatureLine) -> impl Iterator<Item = (Vec3, Vec3, usize, usize)> + '_ {
    let n = line.points.len();
    let count = match n {
        0 => 0,
        1 => 1,
        _ if line.closed && n > 2 => n,
        _ => n - 1,
    };
    (0..count).map(move |i| {
        let j = if n == 1 { 0 } else { (i + 1) % n };
        (line.points[i], line.points[j], i, j)
    })
}

/// Appends the triangles around a surface point (indices already validated).
fn faces_at(mesh: &TriMesh, location: SurfacePoint, out: &mut Vec<u32>) {
    let topo = mesh.topology();
    match location {
        SurfacePoint::Edge { edge, .. } => out.extend_from_slice(topo.edge_faces(edge)),
        SurfacePoint::Face { face } => out.push(face),
        SurfacePoint::Vertex(v) => out.extend_from_slice(topo.vertex_faces(v)),
    }
}

/// Euclidean distance from `x` to the segment `p q`.
pub fn point_segment_distance(x: Vec3, p: Vec3, q: Vec3) -> f64 {
    (x - closest_point_on_segment(x, p, q)).norm()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lines::LineKind;
    use crate::shapes;

    fn polyline(points: Vec<Vec3>, closed: bool) -> FeatureLines {
        let length = points.windows(2).map(|w| (w[1] - w[0]).norm()).sum();
        FeatureLines {
            lines: vec![FeatureLine {
                length,
                ..FeatureLine::new(LineKind::Ridge, points, closed)
            }],
        }
    }

    /// The flat strip [-2, 2] × [-1, 1] in the plane z = 0.
    fn strip(nx: usize, ny: usize) -> TriMesh {
        shapes::height_field(|_, _| 0.0, [-2.0, 2.0], [-1.0, 1.0], nx, ny)
    }

    #[test]
    fn straight_line_on_a_plane_gives_abs_y() {
        // y = 0.05 is not a grid row, so seeds come from located triangles, not vertices.
        let mesh = strip(40, 21);
        for relax in [true, false] {
            let lines = polyline(
                vec![Vec3::new(-2.0, 0.05, 0.0), Vec3::new(2.0, 0.05, 0.0)],
                false,
            );
            let opts = DistanceOptions::default().with_relax_across_triangles(relax);
            let d = feature_distance(&mesh, &lines, &opts).unwrap();
            for (v, p) in mesh.positions().iter().enumerate() {
                assert!(
                    (d.vertex[v] - (p.y - 0.05).abs()).abs() < 1e-12,
                    "relax {relax}: vertex {v} at ({}, {}): {}",
                    p.x,
                    p.y,
                    d.vertex[v]
                );
            }
            assert_eq!(d.unreached_vertices, 0);
            assert!((d.max - 1.05).abs() < 1e-12);
        }
    }

    #[test]
    fn slanted_line_is_exact_with_triangle_relaxation_only() {
        // On a convex planar domain the geodesic distance to a segment is the Euclidean one.
        let mesh = strip(40, 20);
        let (p, q) = (Vec3::new(-2.0, -0.6, 0.0), Vec3::new(2.0, 0.6, 0.0));
        let lines = polyline(vec![p, q], false);
        // Errors (min, max) where the nearest line point is well inside the segment (a
        // straight front) and near or at its ends (a circular front, or triangles that
        // depend on it).
        let errors = |relax: bool| {
            let opts = DistanceOptions::default().with_relax_across_triangles(relax);
            let d = feature_distance(&mesh, &lines, &opts).unwrap();
            let mut straight = (0.0f64, 0.0f64);
            let mut circular = (0.0f64, 0.0f64);
            for (v, x) in mesh.positions().iter().enumerate() {
                let e = d.vertex[v] - point_segment_distance(*x, p, q);
                let t = (x - p).dot(&(q - p)) / (q - p).norm_squared();
                let r = if (0.05..=0.95).contains(&t) {
                    &mut straight
                } else {
                    &mut circular
                };
                *r = (r.0.min(e), r.1.max(e));
            }
            (straight, circular)
        };
        let (straight, circular) = errors(true);
        assert!(straight.0 > -1e-9 && straight.1 < 1e-9, "{straight:?}");
        // First order at the ends: well under a tenth of the 0.1 grid spacing.
        assert!(circular.0 > -1e-9 && circular.1 < 0.01, "{circular:?}");
        let (straight, _) = errors(false);
        // Edge paths only: never below the truth, and clearly above it along the line.
        assert!(straight.0 > -1e-9 && straight.1 > 0.02, "{straight:?}");
    }

    #[test]
    fn circumferential_line_on_a_cylinder_gives_axial_distance() {
        let (radius, height, n) = (1.0, 3.0, 32);
        let mesh = shapes::cylinder(radius, height, n, 24);
        let z0 = 1.1;
        // The line's points lie on the vertical edges, its chords in the planar quads.
        let points = (0..n)
            .map(|i| {
                let a = std::f64::consts::TAU * i as f64 / n as f64;
                Vec3::new(radius * a.cos(), radius * a.sin(), z0)
            })
            .collect();
        let d = feature_distance(&mesh, &polyline(points, true), &Default::default()).unwrap();
        for (v, p) in mesh.positions().iter().enumerate() {
            assert!((d.vertex[v] - (p.z - z0).abs()).abs() < 1e-12, "{p}");
        }
    }

    #[test]
    fn located_line_is_zero_on_itself_and_grows_away_from_it() {
        let mesh = shapes::cylinder(1.0, 2.0, 16, 10);
        // Row 5 (z = 1) as a closed line of vertex locations.
        let ids: Vec<u32> = (0..16).map(|i| 5 * 16 + i).collect();
        let mut lines = polyline(ids.iter().map(|&v| mesh.position(v)).collect(), true);
        lines.lines[0].locations = ids.iter().map(|&v| SurfacePoint::Vertex(v)).collect();
        let d = feature_distance(&mesh, &lines, &Default::default()).unwrap();
        for &v in &ids {
            assert_eq!(d.vertex[v as usize], 0.0);
        }
        // Up each column from the line the distance strictly grows.
        for i in 0..16 {
            for j in 5..10 {
                let (lo, hi) = (j * 16 + i, (j + 1) * 16 + i);
                assert!(d.vertex[hi] > d.vertex[lo]);
            }
        }
        assert_eq!(d.seeded_vertices, 16 * 3);
    }

    #[test]
    fn field_is_lipschitz_along_edges() {
        let mesh = shapes::icosphere(1.0, 3);
        // A quarter of the equator.
        let arc = (0..=16)
            .map(|i| {
                let a = std::f64::consts::FRAC_PI_2 * i as f64 / 16.0;
                Vec3::new(a.cos(), a.sin(), 0.0)
            })
            .collect();
        let lines = polyline(arc, false);
        let d = feature_distance(&mesh, &lines, &Default::default()).unwrap();
        for &[a, b] in mesh.topology().edges() {
            let len = (mesh.position(a) - mesh.position(b)).norm();
            assert!((d.vertex[a as usize] - d.vertex[b as usize]).abs() <= len + 1e-12);
        }
        // The farthest point, opposite the arc's middle, is 3π/4 away on the unit sphere.
        let far = 0.75 * std::f64::consts::PI;
        assert!(d.max > far - 0.05 && d.max < far * 1.05, "{}", d.max);
    }

    #[test]
    fn unreached_components_are_infinite() {
        let a = shapes::icosphere(1.0, 1);
        let mut positions = a.positions().to_vec();
        let mut faces = a.faces().to_vec();
        let off = positions.len() as u32;
        positions.extend(a.positions().iter().map(|p| p + Vec3::new(5.0, 0.0, 0.0)));
        faces.extend(a.faces().iter().map(|t| t.map(|v| v + off)));
        let mesh = TriMesh::new(positions, faces).unwrap();
        let lines = polyline(vec![Vec3::new(0.0, 0.0, 1.0)], false);
        let d = feature_distance(&mesh, &lines, &Default::default()).unwrap();
        assert_eq!(d.unreached_vertices, a.num_vertices());
        assert!(d.vertex[off as usize].is_infinite());
        assert!(d.face[a.num_faces()].is_infinite());
        assert!(d.max.is_finite() && d.max > 0.0);
        let none = feature_distance(&mesh, &FeatureLines::default(), &Default::default()).unwrap();
        assert_eq!(none.max, 0.0);
        assert!(none.vertex.iter().all(|d| d.is_infinite()));
    }

    #[test]
    fn bad_locations_are_reported() {
        let mesh = strip(2, 2);
        let mut lines = polyline(vec![Vec3::zeros(), Vec3::x()], false);
        lines.lines[0].locations = vec![SurfacePoint::Vertex(0), SurfacePoint::Face { face: 99 }];
        let e = feature_distance(&mesh, &lines, &Default::default()).unwrap_err();
        assert!(e.to_string().contains("location 1"), "{e}");
        lines.lines[0].locations.pop();
        assert!(feature_distance(&mesh, &lines, &Default::default()).is_err());
    }

    #[test]
    fn lines_of_another_mesh_are_reported() {
        let mesh = shapes::icosphere(1.0, 2);
        // Far outside the mesh, up to the largest finite coordinates: an error at once
        // (sampling a segment 1e308 long ran for minutes).
        for far in [3.0, 1e6, 1e308] {
            let lines = polyline(
                vec![Vec3::new(0.0, 0.0, 1.0), Vec3::new(far, 0.0, 1.0)],
                false,
            );
            let e = feature_distance(&mesh, &lines, &Default::default()).unwrap_err();
            assert!(e.to_string().contains("another mesh"), "{e}");
            assert!(!e.to_string().contains("inf"), "{e}");
        }
        // Traced lines whose points are not where their locations are on this mesh: the
        // vertices moved (the same mesh elsewhere), or another mesh with as many elements.
        let on_vertex = |v: u32, at: Vec3| {
            let mut lines = polyline(vec![at, mesh.position(v)], false);
            lines.lines[0].locations = vec![SurfacePoint::Vertex(0), SurfacePoint::Vertex(v)];
            lines
        };
        let here = on_vertex(5, mesh.position(0));
        assert!(feature_distance(&mesh, &here, &Default::default()).is_ok());
        let there = on_vertex(5, mesh.position(7));
        let e = feature_distance(&mesh, &there, &Default::default()).unwrap_err();
        assert!(e.to_string().contains("traced on another mesh"), "{e}");
        // Points a little off (fairing) are fine.
        let faired = on_vertex(5, mesh.position(0) + Vec3::new(0.01, 0.0, 0.0));
        assert!(feature_distance(&mesh, &faired, &Default::default()).is_ok());
    }
}
