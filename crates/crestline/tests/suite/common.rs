//! Helpers shared by the integration tests: sampling a surface and measuring how far the
//! samples are from another surface (simplification); loading the shared meshes; distances
//! between points and polylines with the ellipsoid and torus checks of the extraction tests.

// Each test module uses a subset of these helpers.
#![allow(dead_code, clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use crestline::extract::{ExtractOptions, extract};
use crestline::lines::{FeatureLine, FeatureLines, LineKind};
use crestline::simplify::{Simplified, SimplifyOptions, Target, simplify};
use crestline::spatial::FaceGrid;
use crestline::{TriMesh, Vec3, shapes};

pub use super::files::{listing, shared_dir, shared_meshes_dir};

/// Points spread over each triangle of `mesh` accepted by `keep` (6 per triangle: the
/// centroid, three points towards the corners and three towards the edge midpoints).
pub fn samples(mesh: &TriMesh, keep: impl Fn(usize) -> bool) -> Vec<Vec3> {
    let bary = [
        [1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0],
        [0.7, 0.15, 0.15],
        [0.15, 0.7, 0.15],
        [0.15, 0.15, 0.7],
        [0.45, 0.45, 0.1],
        [0.1, 0.45, 0.45],
    ];
    (0..mesh.num_faces())
        .filter(|&f| keep(f))
        .flat_map(|f| {
            let [a, b, c] = mesh.triangle(f);
            bary.map(|[x, y, z]| a * x + b * y + c * z)
        })
        .collect()
}

/// Mean and largest distance from `points` to the surface of `mesh`.
pub fn distance_to(mesh: &TriMesh, points: &[Vec3]) -> (f64, f64) {
    let grid = FaceGrid::new(mesh);
    let d: Vec<f64> = points
        .iter()
        .map(|&p| {
            grid.closest_point(p)
                .map_or(f64::INFINITY, |hit| hit.distance)
        })
        .collect();
    let mean = d.iter().sum::<f64>() / d.len() as f64;
    (mean, d.iter().copied().fold(0.0, f64::max))
}

/// Loads one of the shared meshes by file name (panics with the reason when it cannot).
pub fn load_shared(name: &str) -> TriMesh {
    let path = shared_meshes_dir().join(name);
    crestline::io::read_mesh(&path, None).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// Interior edges whose two faces meet at a dihedral angle (between their normals) above
/// `degrees`: a CAD mesh's sharp creases.
pub fn sharp_edges(mesh: &TriMesh, degrees: f64) -> Vec<u32> {
    let normals = crestline::mesh::face_normals(mesh);
    let topo = mesh.topology();
    let cos = degrees.to_radians().cos();
    (0..topo.num_edges() as u32)
        .filter(|&e| match *topo.edge_faces(e) {
            [f, g] => normals[f as usize].dot(&normals[g as usize]) < cos,
            _ => false,
        })
        .collect()
}

/// `mesh` simplified to a tenth of its faces, the lines weighing `eta` (0: plain QEM).
pub fn simplify_to_tenth(mesh: &TriMesh, lines: &FeatureLines, eta: f64) -> Simplified {
    let options = SimplifyOptions::default()
        .with_target(Target::Ratio(0.1))
        .with_eta(eta);
    simplify(mesh, lines, &options).unwrap()
}

/// Distance from `p` to the segment `ab`.
pub fn point_segment_distance(p: Vec3, a: Vec3, b: Vec3) -> f64 {
    let ab = b - a;
    let len2 = ab.norm_squared();
    let t = if len2 > 0.0 {
        ((p - a).dot(&ab) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (a + ab * t - p).norm()
}

/// The segments of a polyline (closing the loop when `closed`).
pub fn polyline_segments(points: &[Vec3], closed: bool) -> Vec<(Vec3, Vec3)> {
    let n = points.len();
    let m = if closed && n > 2 {
        n
    } else {
        n.saturating_sub(1)
    };
    (0..m).map(|i| (points[i], points[(i + 1) % n])).collect()
}

/// A closed line of `kind`: the circle of `radius` around the z axis at height `z`, through
/// `n` points.
pub fn circle(kind: LineKind, radius: f64, z: f64, n: usize) -> FeatureLine {
    let points = (0..n)
        .map(|i| {
            let a = std::f64::consts::TAU * i as f64 / n as f64;
            Vec3::new(radius * a.cos(), radius * a.sin(), z)
        })
        .collect();
    FeatureLine::new(kind, points, true)
}

/// Points every `step` along each segment (midpoints of equal pieces), with the piece length.
pub fn weighted_samples(
    segments: impl IntoIterator<Item = [Vec3; 2]>,
    step: f64,
) -> Vec<(Vec3, f64)> {
    let mut out = Vec::new();
    for [a, b] in segments {
        let length = (b - a).norm();
        let n = (length / step).ceil().max(1.0) as usize;
        for i in 0..n {
            out.push((
                a + (b - a) * ((i as f64 + 0.5) / n as f64),
                length / n as f64,
            ));
        }
    }
    out
}

/// Distance from `p` to the nearest of `lines` (closed lines include their closing segment).
pub fn distance_to_lines(p: Vec3, lines: &FeatureLines) -> f64 {
    let mut best = f64::INFINITY;
    for l in &lines.lines {
        let n = l.points.len();
        let segs = if l.closed { n } else { n.saturating_sub(1) };
        for i in 0..segs {
            best = best.min(point_segment_distance(
                p,
                l.points[i],
                l.points[(i + 1) % n],
            ));
        }
        if n == 1 {
            best = best.min((l.points[0] - p).norm());
        }
    }
    best
}

/// Fraction of `samples` within `tol` of `lines`.
pub fn coverage(samples: &[Vec3], lines: &FeatureLines, tol: f64) -> f64 {
    let covered = samples
        .iter()
        .filter(|q| distance_to_lines(**q, lines) <= tol)
        .count();
    covered as f64 / samples.len() as f64
}

/// Semi-axes of the test ellipsoid x²/a² + y²/b² + z²/c² = 1 of the extraction tests.
///
/// Exact crest lines of a triaxial ellipsoid with a > b > c: ridges of an ellipsoid lie on its
/// three principal ellipses. On the equator z = 0 the principal direction of k_max is the z
/// direction (crossing the plane): at (a, 0, 0) k = a/c² across versus a/b² along, at
/// (0, b, 0) b/c² versus b/a². By the symmetry z → −z, e_max = 0 there, and k_max falls
/// towards the poles (to c/b² at (0, 0, c)): a maximum, so the whole equator is a ridge. On
/// the ellipses x = 0 and y = 0 the direction crossing the plane is the k_min direction near
/// their ends (e_min = 0, not a crest since k_min > 0), or a k_max *minimum* (at the poles).
/// Valleys need k_min < 0: none on a convex surface. So the only crest line is the equator
/// ellipse x²/a² + y²/b² = 1, z = 0.
pub const ELLIPSOID: [f64; 3] = [3.0, 2.0, 1.0];

/// `samples` points evenly spaced in parameter on the equator of [`ELLIPSOID`].
pub fn equator(samples: usize) -> Vec<Vec3> {
    let [a, b, _] = ELLIPSOID;
    (0..samples)
        .map(|i| {
            let t = i as f64 * std::f64::consts::TAU / samples as f64;
            Vec3::new(a * t.cos(), b * t.sin(), 0.0)
        })
        .collect()
}

/// Extracts lines from `mesh` (an [`ELLIPSOID`] mesh) with `options` and checks them against
/// the exact crest line: no valleys, every point within 1% of the bounding-box diagonal of
/// the equator, and at least 95% of the equator within that distance of a line. Returns the
/// lines for further checks.
pub fn check_ellipsoid(mesh: &TriMesh, options: &ExtractOptions, name: &str) -> FeatureLines {
    let diagonal = mesh.bounding_box().diagonal();
    let tol = 0.01 * diagonal;
    let lines = extract(mesh, options).unwrap().lines;
    assert!(
        lines.of_kind(LineKind::Valley).count() == 0,
        "{name}: valleys on a convex surface"
    );
    let exact = equator(20_000);
    for l in &lines.lines {
        for p in &l.points {
            let d = exact
                .iter()
                .map(|q| (q - p).norm())
                .fold(f64::INFINITY, f64::min);
            assert!(
                d <= tol,
                "{name}: ridge point {p:?} is {d:.4} from the equator (tol {tol:.4})"
            );
        }
    }
    let fraction = coverage(&equator(2000), &lines, tol);
    assert!(
        fraction >= 0.95,
        "{name}: ridges cover {:.1}% of the equator",
        100.0 * fraction
    );
    lines
}

/// Checks that `options` leave almost nothing on a torus (a Dupin cyclide: e = 0, no crest
/// lines): total length below 5% of the bounding-box diagonal.
pub fn check_torus_is_empty(options: &ExtractOptions, name: &str) {
    let mesh = shapes::torus(3.0, 1.0, 120, 40);
    let result = extract(&mesh, options).unwrap();
    let diagonal = mesh.bounding_box().diagonal();
    assert!(
        result.lines.total_length() < 0.05 * diagonal,
        "{name} torus: {} lines, total length {:.3} (diagonal {diagonal:.3})",
        result.lines.lines.len(),
        result.lines.total_length()
    );
}

/// A capsule: a cylinder of radius 1 and length 3 with hemispherical caps, meshed by rings
/// (96 vertices around, every other one moved on by half a step, so that the triangles are
/// uneven; 24 rings per cap, 40 along the cylinder), a ring on each seam. k_max = 1
/// everywhere and k_min steps from 0 to 1 at the seams: there is no crest line on it.
pub fn capsule() -> TriMesh {
    let (around, cap, along, h) = (96usize, 24usize, 40usize, 1.5);
    let mut rings: Vec<(f64, f64)> = Vec::new();
    for j in 1..=cap {
        let phi = -std::f64::consts::FRAC_PI_2 * (1.0 - j as f64 / cap as f64);
        rings.push((phi.cos(), -h + phi.sin()));
    }
    for j in 1..along {
        rings.push((1.0, -h + 2.0 * h * j as f64 / along as f64));
    }
    for j in 0..cap {
        let phi = std::f64::consts::FRAC_PI_2 * j as f64 / cap as f64;
        rings.push((phi.cos(), h + phi.sin()));
    }
    let mut positions = vec![[0.0, 0.0, -h - 1.0]];
    for &(r, z) in &rings {
        for i in 0..around {
            let turn = if i % 2 == 0 { 0.5 } else { 0.0 };
            let t = std::f64::consts::TAU * (i as f64 + turn) / around as f64;
            positions.push([r * t.cos(), r * t.sin(), z]);
        }
    }
    positions.push([0.0, 0.0, h + 1.0]);
    let n = around as u32;
    let ring = |j: usize, i: u32| 1 + j as u32 * n + i % n;
    let mut faces = Vec::new();
    for i in 0..n {
        faces.push([0, ring(0, i + 1), ring(0, i)]);
    }
    for j in 0..rings.len() - 1 {
        for i in 0..n {
            faces.push([ring(j, i), ring(j, i + 1), ring(j + 1, i + 1)]);
            faces.push([ring(j, i), ring(j + 1, i + 1), ring(j + 1, i)]);
        }
    }
    let top = positions.len() as u32 - 1;
    for i in 0..n {
        faces.push([ring(rings.len() - 1, i), ring(rings.len() - 1, i + 1), top]);
    }
    TriMesh::from_arrays(positions, faces).unwrap()
}

/// Runs `options` twice on `mesh`: the lines must be identical, not empty, and no polyline may
/// repeat a point.
pub fn check_deterministic_and_simple(mesh: &TriMesh, options: &ExtractOptions, name: &str) {
    let a = extract(mesh, options).unwrap();
    let b = extract(mesh, options).unwrap();
    assert_eq!(a.lines, b.lines, "{name}: not deterministic");
    assert!(!a.lines.lines.is_empty(), "{name}: no lines");
    for l in &a.lines.lines {
        let mut pts: Vec<[u64; 3]> = l
            .points
            .iter()
            .map(|p| [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()])
            .collect();
        pts.sort_unstable();
        let before = pts.len();
        pts.dedup();
        assert_eq!(before, pts.len(), "{name}: a polyline repeats a point");
    }
}
