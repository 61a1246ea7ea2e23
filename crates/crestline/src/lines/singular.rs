//! Processing singular triangles (HPW 2005, sec. 4.2).
//!
//! Singular triangles carry no stable extremality, so lines are continued through them from
//! their regular neighbours: an edge of a singular triangle `T` is *marked* when the regular
//! triangle across it has a feature-segment end point on it. Then
//! - two marked edges (regular case): the two points are joined inside `T`;
//! - three marked edges (trisector case): the barycentre of `T` is joined to all three;
//! - one marked edge (start/end case): nothing is added, the line ends there.
//!
//! Edges with more than two faces (non-manifold) never mark: "the triangle across" is not
//! defined there.

use rayon::prelude::*;

use crate::mesh::TriMesh;

use super::trace::{FamilySegments, Node};

/// How many singular triangles fell in each case.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct SingularCases {
    /// Two marked edges: a segment was added.
    pub regular: usize,
    /// Three marked edges: barycentre and three segments.
    pub trisector: usize,
    /// One marked edge: a line ends here.
    pub start_end: usize,
}

/// Adds the segments through singular triangles to `segments` and returns the case counts.
/// The faces are examined in parallel; segments are appended in face order.
pub fn process_singular_triangles(mesh: &TriMesh, segments: &mut FamilySegments) -> SingularCases {
    let topo = mesh.topology();
    // Edge points that end a segment traced in a regular triangle.
    let mut marked_by_regular = vec![false; topo.num_edges()];
    for (seg, &f) in segments.segments.iter().zip(&segments.segment_faces) {
        if segments.regular[f as usize] {
            for node in seg {
                if let Node::Edge(e) = *node {
                    marked_by_regular[e as usize] = true;
                }
            }
        }
    }
    let regular = &segments.regular;
    // Per singular face with at least one marked edge: its marked edges.
    let marked: Vec<(u32, [u32; 3], usize)> = (0..mesh.num_faces() as u32)
        .into_par_iter()
        .filter(|&f| !regular[f as usize])
        .filter_map(|f| {
            let mut edges = [0u32; 3];
            let mut count = 0;
            for e in topo.face_edges(f) {
                if !marked_by_regular.get(e as usize).copied().unwrap_or(false) {
                    continue;
                }
                // The face across, when the edge has exactly two faces.
                let across_regular = match *topo.edge_faces(e) {
                    [a, b] => regular[if a == f { b } else { a } as usize],
                    _ => false,
                };
                if across_regular {
                    edges[count] = e;
                    count += 1;
                }
            }
            (count > 0).then_some((f, edges, count))
        })
        .collect();
    let mut cases = SingularCases::default();
    for (f, edges, count) in marked {
        match edges[..count] {
            [a, b] => {
                cases.regular += 1;
                segments.segments.push([Node::Edge(a), Node::Edge(b)]);
                segments.segment_faces.push(f);
            }
            [a, b, c] => {
                cases.trisector += 1;
                for e in [a, b, c] {
                    segments.segments.push([Node::Face(f), Node::Edge(e)]);
                    segments.segment_faces.push(f);
                }
            }
            _ => cases.start_end += 1,
        }
    }
    cases
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fan of four triangles around vertex 0: faces 0..4, face 1 singular.
    fn fan() -> TriMesh {
        let mut p = vec![[0.0, 0.0, 0.0]];
        for i in 0..6 {
            let a = i as f64 * std::f64::consts::TAU / 6.0;
            p.push([a.cos(), a.sin(), 0.0]);
        }
        let faces = (0..6).map(|i| [0, 1 + i, 1 + (i + 1) % 6]).collect();
        TriMesh::from_arrays(p, faces).unwrap()
    }

    #[test]
    fn cases_follow_the_number_of_marked_edges() {
        let m = fan();
        let topo = m.topology();
        // Face 1 is singular; segments in faces 0 and 2 end on its two spoke edges.
        let shared = |f: u32, g: u32| -> u32 {
            let fe = topo.face_edges(f);
            *fe.iter().find(|e| topo.face_edges(g).contains(e)).unwrap()
        };
        let mut s = FamilySegments {
            regular: vec![true, false, true, true, true, true],
            segments: vec![
                [Node::Edge(shared(0, 5)), Node::Edge(shared(0, 1))],
                [Node::Edge(shared(2, 1)), Node::Edge(shared(2, 3))],
            ],
            segment_faces: vec![0, 2],
        };
        let cases = process_singular_triangles(&m, &mut s);
        assert_eq!(cases.regular, 1);
        assert_eq!(s.segments.len(), 3);
        assert_eq!(
            s.segments[2],
            [Node::Edge(shared(0, 1)), Node::Edge(shared(2, 1))]
        );

        // Only one marked edge: nothing added.
        let mut s = FamilySegments {
            regular: vec![true, false, true, true, true, true],
            segments: vec![[Node::Edge(shared(0, 5)), Node::Edge(shared(0, 1))]],
            segment_faces: vec![0],
        };
        let cases = process_singular_triangles(&m, &mut s);
        assert_eq!(cases.start_end, 1);
        assert_eq!(s.segments.len(), 1);
    }

    #[test]
    fn trisector_adds_the_barycentre() {
        // A single triangle surrounded by three regular ones, each ending a line on it.
        let p = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [1.0, 1.0, 0.0],
            [-1.0, 0.5, 0.0],
            [0.5, -1.0, 0.0],
        ];
        let m = TriMesh::from_arrays(p, vec![[0, 1, 2], [1, 3, 2], [0, 2, 4], [0, 5, 1]]).unwrap();
        let fe = m.topology().face_edges(0);
        let mut s = FamilySegments {
            regular: vec![false, true, true, true],
            segments: fe.iter().map(|&e| [Node::Edge(e), Node::Edge(e)]).collect(),
            segment_faces: vec![1, 2, 3],
        };
        let cases = process_singular_triangles(&m, &mut s);
        assert_eq!(cases.trisector, 1);
        assert_eq!(
            s.segments
                .iter()
                .filter(|seg| seg[0] == Node::Face(0))
                .count(),
            3
        );
    }
}
