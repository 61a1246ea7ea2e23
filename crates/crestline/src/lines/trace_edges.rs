//! Edge-based crest-line tracing, as YBS 2005 ("Tracing and Thresholding Crest Lines") use it
//! after Ohtake, Belyaev and Seidel 2004 (sec. 3, "Tracing ridges").
//!
//! Every edge `pq` is inspected on its own: with `dir(q)` flipped to agree with `dir(p)` (and
//! `e(q)` with it), the extremality changes sign along the edge, the crossing is a maximum of
//! `k_max` (ridges) or a minimum of `k_min` (valleys), and the curvature condition holds there
//! (`k_max > |k_min|`, resp. `k_min < −|k_max|`). The crossing point is the linear
//! interpolation of `e`'s zero.
//!
//! Ohtake et al. state the extremum test per end point, `e(v_i) ⟨v_j − v_i, dir(v_i)⟩ > 0`
//! "with i = 1 or 2", and the curvature condition at both end points. Here the two end
//! terms are summed, `e(p) ⟨q − p, dir(p)⟩ + e(q) ⟨p − q, dir(q)⟩ > 0` (`e` falls along the
//! direction: a maximum; `< 0` a minimum), and the curvature condition is read at the
//! crossing from the interpolated curvatures. Measured on the ellipsoid (5K and 20K faces, k =
//! 1 and 3, without extremality smoothing) and the torus of `tests/extract_ybs.rs`, the per-end
//! "or" and "and" readings and the end-point curvature condition give the same number of
//! pieces, the same largest distance from the exact crest line and the same coverage.
//!
//! Inside each triangle, two crest points on its edges are joined; three are joined to the
//! centroid of the three points (Ohtake et al.; [`place_junctions`] moves the junction there
//! after assembly); one is a line end. Unlike HPW's tracing, no triangle is singular here: the
//! orientation is per edge, which is what makes YBS's gap jumping ([`super::gap`]) necessary.
//!
//! **Limits.** Tracing cannot repair wrong extremalities. The cubic fit's `e` has errors that
//! grow like 1/h where the mesh is irregular (see [`crate::curvature::cubic_fit`](mod@crate::curvature::cubic_fit)); on the
//! icosphere-based ellipsoid its 1-ring `e` has the wrong sign on whole rows of vertices along
//! the icosahedron's seams (72 vertices with |e| > 1 at 20K faces), which cuts the equator
//! into pieces and bends them along the seams. That is why the YBS pipeline smooths the
//! extremalities first by default ([`crate::extract`]).

use rayon::prelude::*;

use crate::mesh::{TriMesh, Vec3};

use super::assemble::measure_line;
use super::trace::{Family, FamilySegments, Node, node_position};
use super::{FeatureLine, LineKind, SurfacePoint};

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
    // A maximum of k_max (ridges) or a minimum of k_min (valleys) along the edge.
    let extremum = match family.kind {
        LineKind::Ridge => slope > 0.0,
        LineKind::Valley => slope < 0.0,
    };
    extremum && family.kind.dominates(k, k_other)
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

/// Moves the junction of every triangle with three crest edges from the face's barycentre
/// (where [`super::assemble::assemble_lines`] puts a face node) to the centroid of its three
/// crest points, as Ohtake et al. connect them, and re-measures the lines that changed.
pub fn place_junctions(mesh: &TriMesh, family: &Family<'_>, lines: &mut [FeatureLine]) {
    let topo = mesh.topology();
    for line in lines.iter_mut() {
        let mut moved = false;
        for (point, location) in line.points.iter_mut().zip(&line.locations) {
            if let SurfacePoint::Face { face } = *location {
                *point = topo
                    .face_edges(face)
                    .iter()
                    .map(|&e| node_position(mesh, family, Node::Edge(e)))
                    .sum::<Vec3>()
                    / 3.0;
                moved = true;
            }
        }
        if moved {
            measure_line(mesh, family, line);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A strip along x with e_max = 0.5 - y along dir_max = +y: k_max decreases past y = 0.5
    /// after increasing before, a maximum (ridge) on y = 0.5.
    fn strip(e_sign: f64) -> (TriMesh, Vec<f64>, Vec<Vec3>) {
        let m = crate::shapes::quad_strip(4);
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
                e_noise: 0.0,
                e_alternative: &[],
            };
            let segs = trace_crest_edges(&m, &fam);
            assert_eq!(!segs.segments.is_empty(), expect, "sign {sign}");
            if expect {
                assert_eq!(segs.segments.len(), 8);
            }
        }
    }
}
