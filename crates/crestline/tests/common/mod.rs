//! Helpers shared by the simplification tests: sampling a surface and measuring how far
//! the samples are from another surface.

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
