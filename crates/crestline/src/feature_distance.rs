//! Distance from every vertex to the nearest feature line, measured along the surface.
//!
//! Method: the vertices within [`FeatureDistanceOptions::seed_radius`] mean edge lengths of a
//! line point are seeded with their straight distance to that point; Dijkstra's algorithm then
//! propagates along mesh edges (edge lengths as weights). The result is a graph geodesic: it
//! never crosses empty space between parts of the surface (unlike a Euclidean distance), and
//! it overestimates the true geodesic distance by the usual zig-zag factor of edge paths
//! (up to about 15% on regular triangulations, less along edges).
//!
//! Lines read from a file carry no surface locations, so seeding uses only point positions.
//! Lines are polylines whose points lie on edges of the mesh when traced on it, so every
//! line point has vertices within one edge length.
//!
//! Limits: vertices of components no line touches, and unreferenced vertices, get `+inf`.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use crate::lines::FeatureLines;
use crate::mesh::{TriMesh, mean_edge_length};
use crate::spatial::PointGrid;

/// Options of [`feature_distance`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FeatureDistanceOptions {
    /// Vertices within this many mean edge lengths of a line point start with their
    /// straight distance to it. Default: 1.5.
    pub seed_radius: f64,
}

impl Default for FeatureDistanceOptions {
    fn default() -> Self {
        FeatureDistanceOptions { seed_radius: 1.5 }
    }
}

/// A vertex waiting in Dijkstra's queue, ordered nearest first.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Queued {
    distance: f64,
    vertex: u32,
}

impl Eq for Queued {}

impl Ord for Queued {
    fn cmp(&self, other: &Self) -> Ordering {
        other
            .distance
            .total_cmp(&self.distance)
            .then(other.vertex.cmp(&self.vertex))
    }
}

impl PartialOrd for Queued {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

/// Distance along the surface from every vertex to the nearest point of `lines`; `+inf`
/// where no line is reachable.
pub fn feature_distance(
    mesh: &TriMesh,
    lines: &FeatureLines,
    options: &FeatureDistanceOptions,
) -> Vec<f64> {
    let n = mesh.num_vertices();
    let mut distance = vec![f64::INFINITY; n];
    let topo = mesh.topology();
    let edge = mean_edge_length(mesh);
    if edge <= 0.0 {
        return distance;
    }
    let radius = options.seed_radius.max(0.0) * edge;
    let grid = PointGrid::new(mesh.positions(), radius.max(edge));
    for p in lines.lines.iter().flat_map(|l| &l.points) {
        grid.for_each_within(*p, radius, |v, d2| {
            if !topo.vertex_faces(v).is_empty() {
                let d = d2.sqrt();
                if d < distance[v as usize] {
                    distance[v as usize] = d;
                }
            }
        });
    }
    let mut queue: BinaryHeap<Queued> = distance
        .iter()
        .enumerate()
        .filter(|(_, d)| d.is_finite())
        .map(|(v, &d)| Queued {
            distance: d,
            vertex: v as u32,
        })
        .collect();
    let positions = mesh.positions();
    while let Some(Queued {
        distance: d,
        vertex,
    }) = queue.pop()
    {
        if d > distance[vertex as usize] {
            continue;
        }
        let p = positions[vertex as usize];
        for w in topo.neighbors(vertex) {
            let through = d + (positions[w as usize] - p).norm();
            if through < distance[w as usize] {
                distance[w as usize] = through;
                queue.push(Queued {
                    distance: through,
                    vertex: w,
                });
            }
        }
    }
    distance
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lines::{FeatureLine, LineKind};
    use crate::mesh::Vec3;
    use crate::shapes;

    fn line(points: Vec<Vec3>) -> FeatureLines {
        FeatureLines {
            lines: vec![FeatureLine {
                kind: LineKind::Ridge,
                points,
                locations: vec![],
                closed: false,
                length: 0.0,
                curvature_integral: 0.0,
                strength: 0.0,
            }],
        }
    }

    #[test]
    fn distance_grows_away_from_a_line_on_a_plane() {
        // A 20x20 grid over [0, 2]², the line along x = 1.
        let mesh = shapes::height_field(|_, _| 0.0, [0.0, 2.0], [0.0, 2.0], 20, 20);
        let points = (0..=20)
            .map(|i| Vec3::new(1.0, f64::from(i) / 10.0, 0.0))
            .collect();
        let d = feature_distance(&mesh, &line(points), &FeatureDistanceOptions::default());
        for (v, p) in mesh.positions().iter().enumerate() {
            let exact = (p.x - 1.0).abs();
            // Along grid rows the edge path is straight: exact up to rounding.
            assert!(
                (d[v] - exact).abs() < 1e-9,
                "vertex {v} at {p}: {} vs {exact}",
                d[v]
            );
        }
    }

    #[test]
    fn unreachable_parts_and_empty_lines_give_infinity() {
        let mesh = shapes::icosphere(1.0, 1);
        let d = feature_distance(&mesh, &FeatureLines::default(), &Default::default());
        assert!(d.iter().all(|x| x.is_infinite()));
        let d = feature_distance(
            &mesh,
            &line(vec![Vec3::new(0.0, 0.0, 1.0)]),
            &Default::default(),
        );
        assert!(d.iter().all(|x| x.is_finite()));
        // The far pole is about half a great circle away.
        let far = d.iter().cloned().fold(0.0, f64::max);
        assert!(far > 2.8 && far < 3.6, "{far}");
    }
}
