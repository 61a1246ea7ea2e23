//! Loop subdivision: every triangle split into four, positions smoothed by Loop's masks.
//!
//! C. Loop, *Smooth subdivision surfaces based on triangles*, MS thesis, University of Utah,
//! 1987, with the crease rules of H. Hoppe et al., *Piecewise smooth surface reconstruction*,
//! SIGGRAPH 1994 (section 3.2) for boundaries and non-manifold edges. One level turns F faces,
//! E edges and V vertices into 4F faces, 2E + 3F edges and V + E vertices: vertex `v` keeps its
//! index and the new vertex of edge `e` is `V + e`.
//!
//! - New (odd) vertex of an edge ab: `3/8 (a + b) + 1/8 (c + d)` where c and d are the corners
//!   opposite ab, when ab has exactly two faces; the midpoint `(a + b) / 2` on a crease (a
//!   boundary edge, or an edge with three or more faces).
//! - Old (even) vertex v with n neighbours p_i and no crease edge: `(1 − n β) v + β Σ p_i` with
//!   `β = (5/8 − (3/8 + cos(2π/n)/4)²) / n` (Loop's weights). On a crease, that is with exactly
//!   two crease edges to a and b: `3/4 v + 1/8 (a + b)`, the cubic B-spline rule, so a boundary
//!   curve is refined from its own vertices only and stays a boundary. Corners stay where
//!   they are: vertices with one or more than two crease edges, vertices whose faces form
//!   several fans, and crease vertices where the crease turns by more than
//!   [`SubdivideOptions::corner_angle`].
//!
//! All masks have positive weights summing to one, so every new position is a convex
//! combination of old ones: a planar mesh stays in its plane and the result stays inside the
//! convex hull of the input. Unreferenced vertices are kept where they are.
//!
//! Limits: sharp interior edges (fandisk's creases) are smoothed like any other edge; only
//! boundaries and non-manifold edges are creases. Each level rebuilds the connectivity.

use std::f64::consts::TAU;

use rayon::prelude::*;

use super::{EdgeKind, TriMesh, Vec3, VertexKind};
use crate::error::{Error, Result};

/// Options of [`loop_subdivide`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SubdivideOptions {
    /// Number of subdivision levels; each multiplies the face count by 4. `0` returns the
    /// mesh unchanged. Default: `1`.
    pub levels: u32,
    /// A boundary (or non-manifold crease) vertex where the crease turns by more than this
    /// angle, in degrees, is a corner and does not move; `180` makes no such corners, `0`
    /// makes every bend one. Default: `60.0` (the corners of a square are kept, a boundary
    /// sampled at 10° or finer is smoothed).
    pub corner_angle: f64,
}

impl SubdivideOptions {
    /// The default options as a constant.
    pub const DEFAULT: Self = SubdivideOptions {
        levels: 1,
        corner_angle: 60.0,
    };

    /// Sets [`SubdivideOptions::levels`].
    pub fn with_levels(mut self, levels: u32) -> Self {
        self.levels = levels;
        self
    }

    /// Sets [`SubdivideOptions::corner_angle`] (degrees).
    pub fn with_corner_angle(mut self, degrees: f64) -> Self {
        self.corner_angle = degrees;
        self
    }
}

impl Default for SubdivideOptions {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// Largest face count a subdivided mesh may have: the connectivity packs a face index and a
/// corner slot into one `u32` (see `Topology::build`).
const MAX_FACES: usize = (u32::MAX >> 2) as usize;

/// Applies [`SubdivideOptions::levels`] levels of Loop subdivision to `mesh`.
///
/// ```
/// use crestline::mesh::{SubdivideOptions, loop_subdivide};
///
/// # fn main() -> crestline::Result<()> {
/// let coarse = crestline::shapes::icosphere(1.0, 1);
/// let fine = loop_subdivide(&coarse, &SubdivideOptions::default())?;
/// assert_eq!(fine.num_faces(), 4 * coarse.num_faces());
/// # Ok(())
/// # }
/// ```
///
/// # Errors
/// [`Error::InvalidInput`] when `corner_angle` is not in [0, 180] or when the result would
/// have more faces or vertices than crestline indexes (about 10^9 faces, 4·10^9 vertices);
/// the check is made before anything is allocated.
pub fn loop_subdivide(mesh: &TriMesh, options: &SubdivideOptions) -> Result<TriMesh> {
    if !(0.0..=180.0).contains(&options.corner_angle) {
        return Err(Error::InvalidInput(format!(
            "corner angle {} is not between 0 and 180 degrees",
            options.corner_angle
        )));
    }
    check_size(mesh, options.levels)?;
    // The crease at a vertex turns by more than the corner angle exactly when the cosine of the
    // angle between its two crease edges exceeds this.
    let corner_cos = -options.corner_angle.to_radians().cos();
    let mut current = mesh.clone();
    for _ in 0..options.levels {
        current = subdivide_once(&current, corner_cos)?;
    }
    Ok(current)
}

/// Predicts the counts after `levels` levels (V' = V + E, E' = 2E + 3F, F' = 4F) and refuses
/// results crestline cannot index.
fn check_size(mesh: &TriMesh, levels: u32) -> Result<()> {
    let (mut v, mut e, mut f) = (
        mesh.num_vertices() as u128,
        mesh.topology().num_edges() as u128,
        mesh.num_faces() as u128,
    );
    for _ in 0..levels {
        (v, e, f) = (v + e, 2 * e + 3 * f, 4 * f);
        if f > MAX_FACES as u128 || v > u32::MAX as u128 {
            return Err(Error::InvalidInput(format!(
                "{levels} levels of subdivision would make {f} faces and {v} vertices, more than \
                 the {MAX_FACES} faces and {} vertices crestline indexes",
                u32::MAX
            )));
        }
    }
    Ok(())
}

/// One level: old vertices moved, one new vertex per edge, four faces per face.
fn subdivide_once(mesh: &TriMesh, corner_cos: f64) -> Result<TriMesh> {
    let topology = mesh.topology();
    let num_vertices = mesh.num_vertices();
    let mut positions = Vec::with_capacity(num_vertices + topology.num_edges());
    positions.par_extend(
        (0..num_vertices as u32)
            .into_par_iter()
            .map(|v| even_position(mesh, v, corner_cos)),
    );
    positions.par_extend(
        (0..topology.num_edges() as u32)
            .into_par_iter()
            .map(|e| odd_position(mesh, e)),
    );
    // Fits in u32: check_size bounded V + E.
    let first_edge_vertex = num_vertices as u32;
    let faces: Vec<[u32; 3]> = mesh
        .faces()
        .par_iter()
        .enumerate()
        .flat_map_iter(|(f, &[a, b, c])| {
            // Slot s of a face joins corner s to corner s + 1.
            let [ab, bc, ca] = topology.face_edges(f as u32).map(|e| first_edge_vertex + e);
            [[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]
        })
        .collect();
    TriMesh::new(positions, faces)
}

/// New position of old vertex `v` (see the module docs for the rules).
fn even_position(mesh: &TriMesh, v: u32, corner_cos: f64) -> Vec3 {
    let topology = mesh.topology();
    let x = mesh.position(v);
    let mut crease_ends = [x; 2];
    let mut creases = 0;
    for &e in topology.vertex_edges(v) {
        if topology.edge_kind(e) != EdgeKind::Manifold {
            if creases < 2 {
                crease_ends[creases] = mesh.position(other_end(topology.edge(e), v));
            }
            creases += 1;
        }
    }
    match (creases, topology.vertex_kind(v)) {
        (0, VertexKind::Interior) => {
            let n = topology.degree(v) as f64;
            let sum: Vec3 = topology.neighbors(v).map(|u| mesh.position(u)).sum();
            let beta = loop_beta(n);
            x * (1.0 - n * beta) + sum * beta
        }
        (2, VertexKind::Boundary | VertexKind::NonManifold) => {
            let [a, b] = crease_ends;
            let (u, w) = (a - x, b - x);
            if u.dot(&w) > corner_cos * u.norm() * w.norm() {
                x
            } else {
                x * 0.75 + (a + b) * 0.125
            }
        }
        // Unreferenced vertices, corners of creases, several fans meeting at a vertex.
        _ => x,
    }
}

/// Loop's weight of each neighbour of a smooth vertex with `n` neighbours.
fn loop_beta(n: f64) -> f64 {
    let c = 0.375 + 0.25 * (TAU / n).cos();
    (0.625 - c * c) / n
}

/// Position of the new vertex on edge `e`.
fn odd_position(mesh: &TriMesh, e: u32) -> Vec3 {
    let topology = mesh.topology();
    let [a, b] = topology.edge(e);
    let (pa, pb) = (mesh.position(a), mesh.position(b));
    match *topology.edge_faces(e) {
        [f, g] => {
            let c = opposite_corner(mesh.faces()[f as usize], a, b);
            let d = opposite_corner(mesh.faces()[g as usize], a, b);
            (pa + pb) * 0.375 + (mesh.position(c) + mesh.position(d)) * 0.125
        }
        _ => (pa + pb) * 0.5,
    }
}

/// The corner of `face` that is neither `a` nor `b` (both are corners of it, and a kept face
/// has three distinct corners).
fn opposite_corner(face: [u32; 3], a: u32, b: u32) -> u32 {
    let sum: u64 = face.iter().map(|&i| u64::from(i)).sum();
    (sum - u64::from(a) - u64::from(b)) as u32
}

fn other_end([a, b]: [u32; 2], v: u32) -> u32 {
    if a == v { b } else { a }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes;

    fn subdivide(mesh: &TriMesh, levels: u32) -> TriMesh {
        loop_subdivide(mesh, &SubdivideOptions::DEFAULT.with_levels(levels)).unwrap()
    }

    fn assert_close(a: Vec3, b: Vec3, what: &str) {
        assert!((a - b).norm() < 1e-14, "{what}: {a:?} != {b:?}");
    }

    /// A regular tetrahedron centred at the origin, wound outward.
    fn tetrahedron() -> TriMesh {
        let p = vec![
            [1.0, 1.0, 1.0],
            [1.0, -1.0, -1.0],
            [-1.0, 1.0, -1.0],
            [-1.0, -1.0, 1.0],
        ];
        TriMesh::from_arrays(p, vec![[0, 1, 2], [0, 2, 3], [0, 3, 1], [1, 3, 2]]).unwrap()
    }

    #[test]
    fn tetrahedron_matches_the_masks_by_hand() {
        // n = 3: β = (5/8 − (3/8 − 1/8)²)/3 = 3/16, so v' = (7/16) v + (3/16)(−v) = v/4 (the
        // other three corners sum to −v). Edge ab: 3/8 (a + b) + 1/8 (c + d) with
        // c + d = −(a + b), so (a + b)/4.
        let mesh = tetrahedron();
        let out = subdivide(&mesh, 1);
        assert_eq!(out.num_vertices(), 4 + 6);
        assert_eq!(out.num_faces(), 16);
        for v in 0..4 {
            assert_close(out.position(v), mesh.position(v) / 4.0, "old vertex");
        }
        for (e, &[a, b]) in mesh.topology().edges().iter().enumerate() {
            let expected = (mesh.position(a) + mesh.position(b)) / 4.0;
            assert_close(out.position(4 + e as u32), expected, "edge vertex");
        }
    }

    #[test]
    fn closed_mesh_stays_closed_manifold_with_the_predicted_counts() {
        let mesh = shapes::icosphere(1.0, 2);
        let before = mesh.info();
        let once = subdivide(&mesh, 1);
        let info = once.info();
        assert_eq!(info.faces, 4 * before.faces);
        assert_eq!(info.vertices, before.vertices + before.edges);
        assert_eq!(info.edges, 2 * before.edges + 3 * before.faces);
        assert_eq!(info.degenerate_faces, 0);
        assert!(info.closed);
        assert_eq!(info.boundary_edges, 0);
        assert_eq!(info.non_manifold_edges, 0);
        assert_eq!(info.non_manifold_vertices, 0);
        assert_eq!(info.components, 1);
        assert_eq!(info.euler_characteristic, 2);
        let twice = subdivide(&mesh, 2);
        assert_eq!(twice.num_faces(), 16 * before.faces);
        assert!(twice.info().closed);
    }

    #[test]
    fn winding_follows_the_parent_faces() {
        // Every child of an outward face of the icosphere faces outward too.
        let out = subdivide(&shapes::icosphere(1.0, 1), 1);
        for f in 0..out.num_faces() {
            let [a, b, c] = out.triangle(f);
            let normal = (b - a).cross(&(c - a));
            assert!(normal.dot(&(a + b + c)) > 0.0, "face {f} points inward");
        }
    }

    #[test]
    fn result_lies_in_the_convex_hull() {
        // Every mask is a convex combination, so no point leaves the unit ball; the icosphere
        // (320 faces, vertices on the sphere) shrinks only a little.
        let out = subdivide(&shapes::icosphere(1.0, 2), 2);
        for &p in out.positions() {
            let r = p.norm();
            assert!(r <= 1.0 + 1e-12 && r > 0.95, "radius {r}");
        }
    }

    /// The unit square [−1, 1]² at z = 0 on an n × n grid.
    fn square(n: usize) -> TriMesh {
        shapes::height_field(|_, _| 0.0, [-1.0, 1.0], [-1.0, 1.0], n, n)
    }

    fn on_square_side(p: Vec3) -> bool {
        let close = |a: f64, b: f64| (a - b).abs() < 1e-15;
        close(p.x.abs(), 1.0) || close(p.y.abs(), 1.0)
    }

    #[test]
    fn flat_square_keeps_its_plane_boundary_and_corners() {
        let mesh = square(5);
        let before = mesh.info();
        let out = subdivide(&mesh, 2);
        let info = out.info();
        assert_eq!(info.boundary_loops, 1);
        assert_eq!(info.boundary_edges, 4 * before.boundary_edges);
        assert_eq!(info.faces, 16 * before.faces);
        let topology = out.topology();
        for (v, &p) in out.positions().iter().enumerate() {
            assert_eq!(p.z, 0.0, "vertex {v} left the plane");
            assert!(
                p.x.abs() <= 1.0 + 1e-15 && p.y.abs() <= 1.0 + 1e-15,
                "vertex {v} left the square"
            );
            if topology.is_boundary_vertex(v as u32) {
                assert!(on_square_side(p), "boundary vertex {v} at {p:?}");
            }
        }
        for corner in [[-1.0, -1.0], [1.0, -1.0], [-1.0, 1.0], [1.0, 1.0]] {
            let corner = Vec3::new(corner[0], corner[1], 0.0);
            assert!(out.positions().contains(&corner), "corner {corner:?} moved");
        }
    }

    #[test]
    fn without_corners_a_square_corner_follows_the_spline_rule() {
        let mesh = square(2);
        let options = SubdivideOptions::DEFAULT.with_corner_angle(180.0);
        let out = loop_subdivide(&mesh, &options).unwrap();
        let corner = Vec3::new(-1.0, -1.0, 0.0);
        let v = mesh.positions().iter().position(|&p| p == corner).unwrap() as u32;
        // Crease neighbours (0, −1) and (−1, 0): 3/4 (−1, −1) + 1/8 (−1, −1) = (−7/8, −7/8).
        assert_close(out.position(v), Vec3::new(-0.875, -0.875, 0.0), "corner");
    }

    #[test]
    fn non_manifold_edge_is_a_crease_and_unreferenced_vertices_stay() {
        // Three triangles on edge 0–1, and vertex 5 used by nothing.
        let p = vec![
            [0.0, 0.0, 0.0],
            [2.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [1.0, -1.0, 0.0],
            [1.0, 0.0, 1.0],
            [7.0, 7.0, 7.0],
        ];
        let mesh = TriMesh::from_arrays(p, vec![[0, 1, 2], [1, 0, 3], [0, 1, 4]]).unwrap();
        let out = subdivide(&mesh, 1);
        assert_eq!(out.num_vertices(), 6 + mesh.topology().num_edges());
        assert_eq!(out.num_faces(), 12);
        assert_eq!(out.position(5), Vec3::new(7.0, 7.0, 7.0));
        let topology = mesh.topology();
        let e = (0..topology.num_edges() as u32)
            .find(|&e| topology.edge(e) == [0, 1])
            .unwrap();
        assert_close(
            out.position(6 + e),
            Vec3::new(1.0, 0.0, 0.0),
            "crease midpoint",
        );
        // Vertices 0 and 1 touch the non-manifold edge and three boundary edges: corners.
        assert_eq!(out.position(0), Vec3::zeros());
        assert_eq!(out.position(1), Vec3::new(2.0, 0.0, 0.0));
        assert_eq!(out.info().non_manifold_edges, 2);
    }

    #[test]
    fn zero_levels_returns_the_mesh() {
        let mesh = tetrahedron();
        let out = subdivide(&mesh, 0);
        assert_eq!(out.positions(), mesh.positions());
        assert_eq!(out.faces(), mesh.faces());
    }

    #[test]
    fn refuses_bad_options_and_oversized_results() {
        let mesh = tetrahedron();
        for angle in [f64::NAN, -1.0, 181.0] {
            let options = SubdivideOptions::DEFAULT.with_corner_angle(angle);
            let e = loop_subdivide(&mesh, &options).unwrap_err();
            assert!(e.to_string().contains("corner angle"), "{e}");
        }
        let e = loop_subdivide(&mesh, &SubdivideOptions::DEFAULT.with_levels(15)).unwrap_err();
        assert!(e.to_string().contains("15 levels"), "{e}");
        // 4 · 4^14 = 2^30 faces is one too many; 13 levels fit.
        assert!(check_size(&mesh, 13).is_ok());
        assert!(check_size(&mesh, 14).is_err());
    }
}
