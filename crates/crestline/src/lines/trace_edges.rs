//! Edge-based crest-line tracing, as YBS 2005 ("Tracing and Thresholding Crest Lines") use it
//! after Ohtake, Belyaev and Seidel 2004.
//!
//! Every edge `pq` is inspected on its own: with `dir(q)` flipped to agree with `dir(p)`, the
//! extremality changes sign along the edge, the crossing is a maximum of `k_max` (ridges) or a
//! minimum of `k_min` (valleys), and the curvature condition holds there (`k_max > |k_min|`,
//! resp. `k_min < −|k_max|`, interpolated at the crossing). Whether the crossing is an
//! extremum is read from the signs of `e` against the edge direction projected on the
//! principal directions:
//! `e(p) ⟨q − p, dir(p)⟩ + e(q) ⟨p − q, dir(q)⟩ > 0` means `e` falls along the direction, i.e.
//! `de/dt < 0`, a maximum; `< 0` a minimum.
//!
//! Inside each triangle, two crest points on its edges are joined; three are joined to the
//! barycentre; one is a line end. Unlike HPW's tracing, no triangle is singular here: the
//! orientation is per edge, which is what makes YBS's gap jumping ([`super::gap`]) necessary.

use rayon::prelude::*;

use crate::mesh::TriMesh;

use super::LineKind;
use super::trace::{Family, FamilySegments, Node};

/// True when edge `e` carries a crest point of `family`.
pub fn is_crest_edge(mesh: &TriMesh, family: &Family<'_>, e: u32) -> bool {
    let [a, b] = mesh.topology().edge(e);
    let Some(t) = family.crossing(a, b) else {
        return false;
    };
    let s = family.relative_sign(a, b);
    let (pa, pb) = (mesh.position(a), mesh.position(b));
    let (da, db) = (family.dirs[a as usize], family.dirs[b as usize] * s);
    let (ea, eb) = (family.e[a as usize], family.e[b as usize] * s);
    let slope = ea * (pb - pa).dot(&da) + eb * (pa - pb).dot(&db);
    let lerp = |f: &[f64]| f[a as usize] * (1.0 - t) + f[b as usize] * t;
    let (k, k_other) = (lerp(family.k), lerp(family.k_other));
    match family.kind {
        LineKind::Ridge => slope > 0.0 && k > k_other.abs(),
        LineKind::Valley => slope < 0.0 && k < -k_other.abs(),
    }
}

/// Traces the crest segments of `family` edge by edge.
pub fn trace_crest_edges(mesh: &TriMesh, family: &Family<'_>) -> FamilySegments {
    let topo = mesh.topology();
    let crest: Vec<bool> = (0..topo.num_edges() as u32)
        .into_par_iter()
        .map(|e| is_crest_edge(mesh, family, e))
        .collect();
    let mut out = FamilySegments {
        regular: vec![true; mesh.num_faces()],
        ..Default::default()
    };
    for f in 0..mesh.num_faces() as u32 {
        let marked: Vec<u32> = topo
            .face_edges(f)
            .into_iter()
            .filter(|&e| crest[e as usize])
            .collect();
        match marked[..] {
            [a, b] => {
                out.segments.push([Node::Edge(a), Node::Edge(b)]);
                out.segment_faces.push(f);
            }
            [a, b, c] => {
                for e in [a, b, c] {
                    out.segments.push([Node::Face(f), Node::Edge(e)]);
                    out.segment_faces.push(f);
                }
            }
            _ => {}
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::Vec3;

    /// A strip along x with e_max = 0.5 - y along dir_max = +y: k_max decreases past y = 0.5
    /// after increasing before, a maximum (ridge) on y = 0.5.
    fn strip(e_sign: f64) -> (TriMesh, Vec<f64>, Vec<Vec3>) {
        let mut p = Vec::new();
        for i in 0..=4 {
            p.push([i as f64, 0.0, 0.0]);
            p.push([i as f64, 1.0, 0.0]);
        }
        let mut faces = Vec::new();
        for i in 0..4u32 {
            let (a, b, c, d) = (2 * i, 2 * i + 2, 2 * i + 3, 2 * i + 1);
            faces.extend([[a, b, c], [a, c, d]]);
        }
        let m = TriMesh::from_arrays(p, faces).unwrap();
        let e = m.positions().iter().map(|p| e_sign * (0.5 - p.y)).collect();
        // Alternate the direction signs: the tracing must not care.
        let dirs = (0..m.num_vertices())
            .map(|i| if i % 3 == 0 { -Vec3::y() } else { Vec3::y() })
            .collect::<Vec<_>>();
        let e = (0..m.num_vertices())
            .map(|i| if i % 3 == 0 { -1.0 } else { 1.0 })
            .zip::<Vec<f64>>(e)
            .map(|(s, v)| s * v)
            .collect();
        (m, e, dirs)
    }

    #[test]
    fn finds_the_maximum_and_rejects_the_minimum() {
        for (sign, expect) in [(1.0, true), (-1.0, false)] {
            let (m, e, dirs) = strip(sign);
            let n = m.num_vertices();
            let (k, k_other, zero) = (vec![1.0; n], vec![0.0; n], vec![0.0; n]);
            let fam = Family {
                kind: LineKind::Ridge,
                k: &k,
                k_other: &k_other,
                e: &e,
                e_other: &zero,
                dirs: &dirs,
            };
            let segs = trace_crest_edges(&m, &fam);
            assert_eq!(!segs.segments.is_empty(), expect, "sign {sign}");
            if expect {
                assert_eq!(segs.segments.len(), 8);
            }
        }
    }
}
