//! Simplification of long narrow open strips, where every collapse along the strip costs
//! nothing: the work must grow with the size of the strip, not with its square (see the
//! module docs of `crestline::simplify`, "Valence"). Counts, never wall time, are asserted.

// Test code: stopping loudly on the first surprise is the point.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use crestline::TriMesh;
use crestline::lines::FeatureLines;
use crestline::simplify::{Simplified, SimplifyOptions, Target, simplify};

/// A grid of `rows` × `columns` vertices, `columns` along x, each row at the point `section(j)`
/// of the cross-section (y, z): an open strip of `2 (rows - 1) (columns - 1)` triangles.
fn strip(rows: usize, columns: usize, section: impl Fn(usize) -> [f64; 2]) -> TriMesh {
    let mut positions = Vec::with_capacity(rows * columns);
    for i in 0..columns {
        for j in 0..rows {
            let [y, z] = section(j);
            positions.push([0.1 * i as f64, y, z]);
        }
    }
    let mut faces = Vec::new();
    for i in 0..columns - 1 {
        for j in 0..rows - 1 {
            let a = (i * rows + j) as u32;
            let (b, c) = (a + 1, a + rows as u32);
            faces.push([a, c, b]);
            faces.push([b, c, c + 1]);
        }
    }
    TriMesh::from_arrays(positions, faces).unwrap()
}

/// A flat straight strip two vertices wide with `faces` triangles.
fn flat_strip(faces: usize) -> TriMesh {
    strip(2, faces / 2 + 1, |j| [0.1 * j as f64, 0.0])
}

/// A straight half-pipe four vertices wide (the cross-section an arc, the rows straight lines)
/// with `faces` triangles.
fn half_pipe(faces: usize) -> TriMesh {
    strip(4, faces / 6 + 1, |j| {
        let a = (j as f64 / 3.0 - 0.5) * 1.2;
        [0.2 * a.sin(), -0.2 * a.cos()]
    })
}

fn max_degree(mesh: &TriMesh) -> usize {
    let mut neighbours = vec![Vec::new(); mesh.num_vertices()];
    for t in mesh.faces() {
        for k in 0..3 {
            let (a, b) = (t[k] as usize, t[(k + 1) % 3]);
            neighbours[a].push(b);
            neighbours[b as usize].push(t[k]);
        }
    }
    neighbours
        .iter_mut()
        .map(|n| {
            n.sort_unstable();
            n.dedup();
            n.len()
        })
        .max()
        .unwrap_or(0)
}

fn to_tenth(mesh: &TriMesh, eta: f64) -> Simplified {
    let options = SimplifyOptions::default()
        .with_target(Target::Ratio(0.1))
        .with_eta(eta);
    simplify(mesh, &FeatureLines::default(), &options).unwrap()
}

#[test]
fn straight_strips_take_work_proportional_to_their_size() {
    // Before the valence bound one vertex swallowed its whole row (a fan of all the triangles
    // left), and each collapse into it planned all its edges anew: 2 million candidates for
    // the flat strip of 4,000 triangles (500 per triangle), 8 million for 8,000. With the
    // bound (`MAX_VALENCE`, 128) a collapse plans at most 128 candidates, in practice far
    // fewer: at most 33 per input triangle here, whether fans (up to the bound) form or not,
    // which depends on how rounding orders the ties between collapses that cost nothing.
    // The bounds are spelled out rather than taken from `MAX_VALENCE`, so that raising it
    // far enough to turn it off fails the test.
    for (name, make) in [
        ("flat strip", flat_strip as fn(usize) -> TriMesh),
        ("half-pipe", half_pipe),
    ] {
        for eta in [0.0, 1.0] {
            for faces in [4_000, 16_000] {
                let mesh = make(faces);
                let r = to_tenth(&mesh, eta);
                let degree = max_degree(&r.mesh);
                eprintln!(
                    "{name}, eta {eta}: {} -> {} faces, {} collapses, {} passes, \
                     {} candidates, largest degree {degree}, {:?}",
                    r.faces_before, r.faces_after, r.collapses, r.passes, r.candidates, r.rejected
                );
                assert!(r.target_reached, "{name} {faces}");
                assert!(r.passes <= 2, "{name} {faces}: {} passes", r.passes);
                assert!(
                    r.candidates <= 64 * r.faces_before,
                    "{name}, eta {eta}, {faces}: {} candidates",
                    r.candidates
                );
                assert!(degree <= 128, "{name} {faces}: degree {degree}");
            }
        }
    }
}
