//! Helpers shared by the integration tests: sampling a surface and measuring how far
//! the samples are from another surface; loading the shared meshes; small geometric checks.
//! Each test binary uses only some of them.
#![allow(dead_code)]

use crestline::spatial::FaceGrid;
use crestline::{TriMesh, Vec3};

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

/// The shared mesh folder (`../shared/data/meshes` beside the repository).
pub fn shared_meshes_dir() -> std::path::PathBuf {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data/meshes");
    assert!(
        dir.is_dir(),
        "the real test meshes are missing: expected them in {} (see shared/data/README.md)",
        dir.display()
    );
    dir
}

/// Loads one of the shared meshes by file name (panics with the reason when it cannot).
#[allow(clippy::panic)]
pub fn load_shared(name: &str) -> TriMesh {
    let path = shared_meshes_dir().join(name);
    crestline::io::read_mesh(&path, None).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
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
