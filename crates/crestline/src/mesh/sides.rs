//! The sides of a vertex's star cut by flagged edges (the creases of
//! [`crate::lines::crease`]): the curvature fits read one side of a crease vertex, the merge
//! of creases and crest lines another's lines.

use super::{TriMesh, Vec3};
use crate::slices::union_find_root;

/// Relative difference below which two sides' angles (or areas) at a crease vertex count as
/// equal in [`widest_side`]: far above rounding (1e-16 of a sum of a few angles; a translation
/// by 1e4 of a unit model shifts positions by 1e-12 of their size) and far below any real
/// difference of a mesh.
pub const SIDE_TIE: f64 = 1e-9;

/// The faces at vertex `v` on its widest side: the faces around v joined across edges at v
/// that are not flagged in `crease_edges` (per edge), grouped into sides, and of those the one
/// with the largest total angle at v (ties up to [`SIDE_TIE`]: the larger area, more faces,
/// the larger second moment of the face centroids, then the side whose centroid comes first
/// in (x, y, z) order). All faces of v when no crease
/// edge meets it. A vertex on a crease is a sample of every side; its own fit and fields
/// describe this one (see [`crate::curvature::jet_fit`](mod@crate::curvature::jet_fit)).
pub fn widest_side(mesh: &TriMesh, v: u32, crease_edges: &[bool]) -> Vec<u32> {
    let topo = mesh.topology();
    let faces = topo.vertex_faces(v);
    // Union-find over the (few) faces at v.
    let mut side: Vec<usize> = (0..faces.len()).collect();
    for (i, &f) in faces.iter().enumerate() {
        for e in topo.face_edges(f) {
            let Some(&flag) = crease_edges.get(e as usize) else {
                continue;
            };
            let [a, b] = topo.edge(e);
            if flag || (a != v && b != v) {
                continue;
            }
            for &g in topo.edge_faces(e) {
                if let Some(j) = faces.iter().position(|&h| h == g) {
                    let (ri, rj) = (union_find_root(&mut side, i), union_find_root(&mut side, j));
                    side[ri] = rj;
                }
            }
        }
    }
    // Per side: total angle at v, area, and the sum of its face centroids taken from v.
    let p = mesh.position(v);
    let mut total = vec![0.0; faces.len()];
    let mut area = vec![0.0; faces.len()];
    let mut centroid = vec![Vec3::zeros(); faces.len()];
    let mut count = vec![0usize; faces.len()];
    let mut moment = vec![0.0; faces.len()];
    for (i, &f) in faces.iter().enumerate() {
        let r = union_find_root(&mut side, i);
        let [a, b, c] = mesh.triangle(f as usize);
        total[r] += corner_angle(mesh, f, v);
        area[r] += 0.5 * (b - a).cross(&(c - a)).norm();
        let from_v = ((a - p) + (b - p) + (c - p)) / 3.0;
        centroid[r] += from_v;
        count[r] += 1;
        moment[r] += from_v.norm_squared();
    }
    let roots: Vec<usize> = (0..faces.len())
        .filter(|&i| union_find_root(&mut side, i) == i)
        .collect();
    let widest = roots.iter().map(|&r| total[r]).fold(0.0, f64::max);
    // Angles equal up to rounding (a vertex on a straight crease between two flat sides has π
    // on each) are a tie: rounding changes with a translation, a rotation and with the order
    // of the faces, and the choice must not. Ties go to the larger area, then to the side of
    // more faces, then to the larger second moment of the face centroids about v (each up to
    // rounding: all three are invariant under motions and reordering), and only then to the
    // side whose centroid comes first in (x, y, z) order.
    let tied = |x: f64, y: f64| (x - y).abs() <= SIDE_TIE * x.abs().max(y.abs());
    let by = |x: f64, y: f64| {
        if tied(x, y) {
            std::cmp::Ordering::Equal
        } else {
            x.total_cmp(&y)
        }
    };
    let Some(best) = roots
        .iter()
        .copied()
        .filter(|&r| tied(total[r], widest))
        .max_by(|&a, &b| {
            by(area[a], area[b])
                .then(count[a].cmp(&count[b]))
                .then(by(moment[a], moment[b]))
                .then_with(|| {
                    let (ca, cb) = (centroid[a], centroid[b]);
                    (cb.x.total_cmp(&ca.x))
                        .then(cb.y.total_cmp(&ca.y))
                        .then(cb.z.total_cmp(&ca.z))
                })
        })
    else {
        return Vec::new();
    };
    (0..faces.len())
        .filter(|&i| union_find_root(&mut side, i) == best)
        .map(|i| faces[i])
        .collect()
}

/// The angle of triangle `f` at its corner `v` (0 for a triangle that repeats `v`).
pub(crate) fn corner_angle(mesh: &TriMesh, f: u32, v: u32) -> f64 {
    let [a, b, c] = mesh.faces()[f as usize];
    let (q, r) = match v {
        _ if v == a => (b, c),
        _ if v == b => (c, a),
        _ if v == c => (a, b),
        _ => return 0.0,
    };
    if q == v || r == v {
        return 0.0;
    }
    let p = mesh.position(v);
    (mesh.position(q) - p).angle(&(mesh.position(r) - p))
}
