//! Steps 4 and 5 of [`find_creases`](super::find_creases): crease edges chained into curves
//! from corner to corner, stray curves dropped; and the sides and cone points of crease
//! vertices that the curvature fits need.

use rayon::prelude::*;

use super::{CreaseCurve, MAX_FACET_TURN};
use crate::lines::assemble::chain_links;
use crate::mesh::{TriMesh, Vec3};

/// Relative difference below which two sides' angles (or areas) at a crease vertex count as
/// equal in [`widest_side`]: far above rounding (1e-16 of a sum of a few angles; a translation
/// by 1e4 of a unit model shifts positions by 1e-12 of their size) and far below any real
/// difference of a mesh.
pub const SIDE_TIE: f64 = 1e-9;

/// The faces at vertex `v` on its widest side: the faces around v joined across edges at v
/// that are not flagged in `crease_edges` (per edge), grouped into sides, and of those the one
/// with the largest total angle at v (ties up to [`SIDE_TIE`]: the larger area, then the side
/// whose centroid comes first in (x, y, z) order). All faces of v when no crease
/// edge meets it. A vertex on a crease is a sample of every side; its own fit and fields
/// describe this one (see [`crate::curvature::jet_fit`](mod@crate::curvature::jet_fit)).
pub fn widest_side(mesh: &TriMesh, v: u32, crease_edges: &[bool]) -> Vec<u32> {
    let topo = mesh.topology();
    let faces = topo.vertex_faces(v);
    // Union-find over the (few) faces at v.
    let mut side: Vec<usize> = (0..faces.len()).collect();
    fn root(side: &mut [usize], mut i: usize) -> usize {
        while side[i] != i {
            side[i] = side[side[i]];
            i = side[i];
        }
        i
    }
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
                    let (ri, rj) = (root(&mut side, i), root(&mut side, j));
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
    for (i, &f) in faces.iter().enumerate() {
        let r = root(&mut side, i);
        let [a, b, c] = mesh.triangle(f as usize);
        total[r] += corner_angle(mesh, f, v);
        area[r] += 0.5 * (b - a).cross(&(c - a)).norm();
        centroid[r] += ((a - p) + (b - p) + (c - p)) / 3.0;
    }
    let roots: Vec<usize> = (0..faces.len())
        .filter(|&i| root(&mut side, i) == i)
        .collect();
    let widest = roots.iter().map(|&r| total[r]).fold(0.0, f64::max);
    // Angles equal up to rounding (a vertex on a straight crease between two flat sides has π
    // on each) are a tie: rounding changes with a translation and with the order of the faces,
    // and the choice must not. Ties go to the larger area (again up to rounding), then to the
    // side whose centroid comes first in (x, y, z) order.
    let tied = |x: f64, y: f64| (x - y).abs() <= SIDE_TIE * x.abs().max(y.abs());
    let Some(best) = roots
        .iter()
        .copied()
        .filter(|&r| tied(total[r], widest))
        .max_by(|&a, &b| {
            let by_area = if tied(area[a], area[b]) {
                std::cmp::Ordering::Equal
            } else {
                area[a].total_cmp(&area[b])
            };
            by_area.then_with(|| {
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
        .filter(|&i| root(&mut side, i) == best)
        .map(|i| faces[i])
        .collect()
}

/// The angle of triangle `f` at its corner `v` (0 for a triangle that repeats `v`).
fn corner_angle(mesh: &TriMesh, f: u32, v: u32) -> f64 {
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

/// Cone points: interior vertices whose angle deficit `2π − Σ angles` exceeds
/// [`MAX_FACET_TURN`] in magnitude and that no crease edge meets. A tessellation of a smooth
/// surface spreads its Gaussian curvature over many vertices; a cone's tip holds it all in one
/// (2.8 rad on a cone of half-angle 34°). Crest lines near one come from fits that straddle
/// the tip ([`crate::lines::merge`] cuts them).
pub fn cone_points(mesh: &TriMesh, crease_edges: &[bool]) -> Vec<u32> {
    let topo = mesh.topology();
    (0..mesh.num_vertices() as u32)
        .into_par_iter()
        .filter(|&v| {
            let edges = topo.vertex_edges(v);
            if edges.is_empty()
                || topo.vertex_kind(v) != crate::mesh::VertexKind::Interior
                || edges
                    .iter()
                    .any(|&e| crease_edges.get(e as usize).copied().unwrap_or(false))
            {
                return false;
            }
            let total: f64 = topo
                .vertex_faces(v)
                .iter()
                .map(|&f| corner_angle(mesh, f, v))
                .sum();
            (std::f64::consts::TAU - total).abs() > MAX_FACET_TURN.to_radians()
        })
        .collect()
}

/// Chains the edges flagged in `is_crease` into curves (see the module docs, step 4).
/// `angles` are those of [`dihedral_angles`](super::dihedral_angles); `corner_angle` in degrees.
pub fn chain_crease_edges(
    mesh: &TriMesh,
    is_crease: &[bool],
    angles: &[f64],
    corner_angle: f64,
) -> Vec<CreaseCurve> {
    let topo = mesh.topology();
    let links: Vec<(usize, usize)> = topo
        .edges()
        .iter()
        .zip(is_crease)
        .filter(|(_, c)| **c)
        .map(|(&[a, b], _)| (a as usize, b as usize))
        .collect();
    let convex_of = |a: u32, b: u32| {
        topo.edge_between(a, b)
            .is_some_and(|e| angles[e as usize] > 0.0)
    };
    let cos_corner = corner_angle.to_radians().cos();
    // A corner at `v` between the edges u–v and v–w.
    let is_corner = |u: u32, v: u32, w: u32| {
        let (p, q, r) = (mesh.position(u), mesh.position(v), mesh.position(w));
        let turn = match ((q - p).try_normalize(0.0), (r - q).try_normalize(0.0)) {
            (Some(d0), Some(d1)) => d0.dot(&d1) < cos_corner,
            _ => false,
        };
        turn || convex_of(u, v) != convex_of(v, w)
    };
    let mut curves = Vec::new();
    for (path, closed) in chain_links(mesh.num_vertices(), &links) {
        let path: Vec<u32> = path.into_iter().map(|v| v as u32).collect();
        let n = path.len();
        if closed {
            let corners: Vec<usize> = (0..n)
                .filter(|&k| is_corner(path[(k + n - 1) % n], path[k], path[(k + 1) % n]))
                .collect();
            if corners.is_empty() {
                curves.push(build_curve(mesh, angles, path, true));
                continue;
            }
            // Rotate to start at a corner and cut there and at every other corner.
            let mut rotated: Vec<u32> = path[corners[0]..].to_vec();
            rotated.extend_from_slice(&path[..=corners[0]]);
            let cuts: Vec<usize> = corners
                .iter()
                .map(|&k| (k + n - corners[0]) % n)
                .chain([n])
                .collect();
            for pair in cuts.windows(2) {
                let piece = rotated[pair[0]..=pair[1]].to_vec();
                curves.push(build_curve(mesh, angles, piece, false));
            }
        } else {
            let mut start = 0;
            for k in 1..n.saturating_sub(1) {
                if is_corner(path[k - 1], path[k], path[k + 1]) {
                    curves.push(build_curve(mesh, angles, path[start..=k].to_vec(), false));
                    start = k;
                }
            }
            if n >= 2 {
                curves.push(build_curve(mesh, angles, path[start..].to_vec(), false));
            }
        }
    }
    curves
}

fn build_curve(mesh: &TriMesh, angles: &[f64], vertices: Vec<u32>, closed: bool) -> CreaseCurve {
    let topo = mesh.topology();
    let (mut length, mut turning, mut signed) = (0.0, 0.0, 0.0);
    let n = vertices.len();
    let segments = if closed { n } else { n.saturating_sub(1) };
    for k in 0..segments {
        let (a, b) = (vertices[k], vertices[(k + 1) % n]);
        let l = (mesh.position(b) - mesh.position(a)).norm();
        let theta = topo.edge_between(a, b).map_or(0.0, |e| angles[e as usize]);
        if theta.is_finite() {
            length += l;
            turning += theta.abs() * l;
            signed += theta * l;
        }
    }
    CreaseCurve {
        vertices,
        closed,
        convex: signed >= 0.0,
        length,
        turning,
    }
}

/// Drops the curves whose connected set of curves (curves sharing a vertex) is shorter than
/// `min_length` (model units). Returns the number of curves dropped.
pub fn drop_stray_curves(curves: &mut Vec<CreaseCurve>, min_length: f64) -> usize {
    // Union-find over the curves, joined through shared vertices.
    let mut parent: Vec<usize> = (0..curves.len()).collect();
    fn root(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    let mut owner = std::collections::HashMap::new();
    for (i, c) in curves.iter().enumerate() {
        for &v in &c.vertices {
            if let Some(&j) = owner.get(&v) {
                let (ri, rj) = (root(&mut parent, i), root(&mut parent, j));
                parent[ri] = rj;
            } else {
                owner.insert(v, i);
            }
        }
    }
    let mut total = vec![0.0; curves.len()];
    for (i, c) in curves.iter().enumerate() {
        total[root(&mut parent, i)] += c.length;
    }
    let keep: Vec<bool> = (0..curves.len())
        .map(|i| total[root(&mut parent, i)] >= min_length)
        .collect();
    let before = curves.len();
    let mut k = 0;
    curves.retain(|_| {
        k += 1;
        keep[k - 1]
    });
    before - curves.len()
}
