//! Steps 4 and 5 of [`find_creases`](super::find_creases): crease edges chained into curves
//! from corner to corner, stray curves dropped; and the cone points that the merge needs (the
//! sides of crease vertices, which the curvature fits need too, are
//! [`crate::mesh::widest_side`]).

use rayon::prelude::*;

use super::{CreaseCurve, MAX_FACET_TURN};
use crate::lines::assemble::chain_links;
use crate::mesh::{TriMesh, corner_angle};
use crate::slices::union_find_root;

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
    let mut owner = std::collections::HashMap::new();
    for (i, c) in curves.iter().enumerate() {
        for &v in &c.vertices {
            if let Some(&j) = owner.get(&v) {
                let (ri, rj) = (
                    union_find_root(&mut parent, i),
                    union_find_root(&mut parent, j),
                );
                parent[ri] = rj;
            } else {
                owner.insert(v, i);
            }
        }
    }
    let mut total = vec![0.0; curves.len()];
    for (i, c) in curves.iter().enumerate() {
        total[union_find_root(&mut parent, i)] += c.length;
    }
    let keep: Vec<bool> = (0..curves.len())
        .map(|i| total[union_find_root(&mut parent, i)] >= min_length)
        .collect();
    let before = curves.len();
    let mut k = 0;
    curves.retain(|_| {
        k += 1;
        keep[k - 1]
    });
    before - curves.len()
}
