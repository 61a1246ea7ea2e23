//! Non-manifold edges, where three or more sheets of surface meet (a wall inside a box, parts
//! glued along an edge): each sheet is fitted on its own, so a T is not read as one bent
//! surface ([`crestline::lines::crease::Creases::barriers`]).

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::collections::HashMap;

use crestline::TriMesh;
use crestline::curvature::{CurvatureOptions, estimate_split};
use crestline::extract::{ExtractOptions, Method, extract};
use crestline::lines::crease::{CreaseOptions, find_creases};

/// The unit cube cut into `n` × `n` squares per face (two triangles each), wound outward,
/// with, when `wall` is set, the square x = 1/2 inside it on the same grid: its boundary is
/// 4 n edges of the cube's faces, each with three faces (`n` even).
fn cube_with_wall(n: u32, wall: bool) -> TriMesh {
    let mut index: HashMap<[u32; 3], u32> = HashMap::new();
    let mut positions = Vec::new();
    let mut faces = Vec::new();
    let mut vertex = |p: [u32; 3]| {
        *index.entry(p).or_insert_with(|| {
            positions.push(crestline::Vec3::new(
                p[0] as f64 / n as f64,
                p[1] as f64 / n as f64,
                p[2] as f64 / n as f64,
            ));
            (positions.len() - 1) as u32
        })
    };
    // Each sheet: a corner and two grid directions (axis, sign) whose cross product points
    // out of the cube.
    let mut sheets = vec![
        ([0, 0, 0], 1, 0),
        ([0, 0, n], 0, 1),
        ([0, 0, 0], 0, 2),
        ([0, n, 0], 2, 0),
        ([0, 0, 0], 2, 1),
        ([n, 0, 0], 1, 2),
    ];
    if wall {
        sheets.push(([n / 2, 0, 0], 1, 2));
    }
    for (origin, a, b) in sheets {
        for i in 0..n {
            for j in 0..n {
                let at = |di: u32, dj: u32| {
                    let mut p = origin;
                    p[a] += i + di;
                    p[b] += j + dj;
                    p
                };
                let q = [at(0, 0), at(1, 0), at(1, 1), at(0, 1)].map(&mut vertex);
                faces.push([q[0], q[1], q[2]]);
                faces.push([q[0], q[2], q[3]]);
            }
        }
    }
    TriMesh::new(positions, faces).unwrap()
}

#[test]
fn a_wall_inside_a_box_adds_no_crest_lines() {
    let boxed = cube_with_wall(20, false);
    let walled = cube_with_wall(20, true);
    let topo = walled.topology();
    let t_edges = (0..topo.num_edges() as u32)
        .filter(|&e| topo.edge_faces(e).len() == 3)
        .count();
    assert_eq!(t_edges, 80, "the wall meets the box along 4 × 20 edges");
    for method in [Method::Hpw, Method::Ybs, Method::Saliency] {
        let options = ExtractOptions::for_method(method);
        for (name, mesh) in [("box", &boxed), ("box with a wall", &walled)] {
            let found = extract(mesh, &options).unwrap();
            let s = &found.stats;
            assert_eq!(
                (s.ridges, s.valleys, s.crease_ridges, s.crease_valleys),
                (0, 0, 12, 0),
                "{method:?}, {name}: the 12 edges of the box and nothing else"
            );
            assert!((s.total_length - 12.0).abs() < 1e-9, "{method:?}, {name}");
        }
    }
}

#[test]
fn the_sheets_at_a_t_are_fitted_apart() {
    // Every sheet is planar: every vertex, those where the wall meets the box among them, has
    // zero curvature when the fits do not read across the T.
    let mesh = cube_with_wall(20, true);
    let creases = find_creases(&mesh, &CreaseOptions::DEFAULT).unwrap();
    let barriers = creases.barriers(&mesh).expect("creases and T edges");
    let topo = mesh.topology();
    for e in 0..topo.num_edges() as u32 {
        if topo.edge_faces(e).len() > 2 {
            assert!(barriers[e as usize], "T edge {e} is a barrier");
        }
    }
    let c = estimate_split(&mesh, &CurvatureOptions::default(), Some(&barriers)).unwrap();
    let worst = c
        .k_max
        .iter()
        .chain(&c.k_min)
        .fold(0.0f64, |m, k| m.max(k.abs()));
    assert!(worst < 1e-6, "largest |k| {worst} on planar sheets");
}
