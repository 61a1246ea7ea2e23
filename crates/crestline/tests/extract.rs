//! End-to-end properties of `extract` on analytic surfaces and real meshes.
//!
//! Exact crest lines of the triaxial ellipsoid x²/a² + y²/b² + z²/c² = 1 with a > b > c:
//! ridges of an ellipsoid lie on its three principal ellipses. On the equator z = 0 the
//! principal direction of k_max is the z direction (crossing the plane): at (a, 0, 0)
//! k = a/c² across versus a/b² along, at (0, b, 0) b/c² versus b/a². By the symmetry z → −z,
//! e_max = 0 there, and k_max falls towards the poles (to c/b² at (0, 0, c)): a maximum, so
//! the whole equator is a ridge. On the ellipses x = 0 and y = 0 the direction crossing the
//! plane is the k_min direction near their ends (e_min = 0, not a crest since k_min > 0), or a
//! k_max *minimum* (at the poles). Valleys need k_min < 0: none on a convex surface. So the
//! only crest line is the equator ellipse x²/a² + y²/b² = 1, z = 0.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use crestline::extract::{ExtractOptions, Method, extract};
use crestline::lines::{FeatureLines, LineKind};
use crestline::{TriMesh, Vec3, shapes};

const A: f64 = 3.0;
const B: f64 = 2.0;
const C: f64 = 1.0;

/// Dense samples of the equator ellipse.
fn equator(samples: usize) -> Vec<Vec3> {
    (0..samples)
        .map(|i| {
            let t = i as f64 * std::f64::consts::TAU / samples as f64;
            Vec3::new(A * t.cos(), B * t.sin(), 0.0)
        })
        .collect()
}

fn point_segment_distance(p: Vec3, a: Vec3, b: Vec3) -> f64 {
    let ab = b - a;
    let t = if ab.norm_squared() > 0.0 {
        ((p - a).dot(&ab) / ab.norm_squared()).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (a + ab * t - p).norm()
}

fn distance_to_lines(p: Vec3, lines: &FeatureLines) -> f64 {
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

fn check_ellipsoid(mesh: &TriMesh, method: Method) {
    let diagonal = mesh.bounding_box().diagonal();
    let tol = 0.01 * diagonal;
    let result = extract(mesh, &ExtractOptions::for_method(method)).unwrap();
    let lines = &result.lines;
    assert!(
        lines.of_kind(LineKind::Valley).count() == 0,
        "{method:?}: valleys on a convex surface"
    );
    // Every ridge point lies within 1% of the diagonal of the exact crest line.
    let exact = equator(20_000);
    for l in &lines.lines {
        for p in &l.points {
            let d = exact
                .iter()
                .map(|q| (q - p).norm())
                .fold(f64::INFINITY, f64::min);
            assert!(
                d <= tol,
                "{method:?}: ridge point {p:?} is {d:.4} from the equator (tol {tol:.4})"
            );
        }
    }
    // The ridges cover at least 95% of the crest line.
    let samples = equator(2000);
    let covered = samples
        .iter()
        .filter(|q| distance_to_lines(**q, lines) <= tol)
        .count();
    let fraction = covered as f64 / samples.len() as f64;
    assert!(
        fraction >= 0.95,
        "{method:?}: ridges cover {:.1}% of the equator",
        100.0 * fraction
    );
}

#[test]
fn hpw_finds_the_ellipsoid_crest_line_at_5k_and_20k_faces() {
    for subdivisions in [4, 5] {
        let mesh = shapes::ellipsoid(A, B, C, subdivisions);
        check_ellipsoid(&mesh, Method::Hpw);
    }
}

#[test]
fn torus_has_no_crest_lines_by_default() {
    let mesh = shapes::torus(3.0, 1.0, 120, 40);
    let result = extract(&mesh, &ExtractOptions::for_method(Method::Hpw)).unwrap();
    let diagonal = mesh.bounding_box().diagonal();
    assert!(
        result.lines.total_length() < 0.05 * diagonal,
        "torus: {} lines, total length {:.3} (diagonal {diagonal:.3})",
        result.lines.lines.len(),
        result.lines.total_length()
    );
}

#[test]
fn output_is_deterministic_and_polylines_are_simple() {
    let mesh = shapes::ellipsoid(A, B, C, 4);
    let options = ExtractOptions {
        filter: crestline::lines::filter::LineFilter {
            threshold: 0.0,
            min_length: 0.0,
            ..Default::default()
        },
        ..ExtractOptions::default()
    };
    let a = extract(&mesh, &options).unwrap();
    let b = extract(&mesh, &options).unwrap();
    assert_eq!(a.lines, b.lines);
    assert!(!a.lines.lines.is_empty());
    for l in &a.lines.lines {
        let mut pts: Vec<[u64; 3]> = l
            .points
            .iter()
            .map(|p| [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()])
            .collect();
        pts.sort_unstable();
        let before = pts.len();
        pts.dedup();
        assert_eq!(before, pts.len(), "a polyline repeats a point");
    }
}
