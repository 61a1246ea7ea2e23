//! Tracing feature-line segments in regular triangles (HPW 2005, sec. 4.1, eqs. 5 and 6).
//!
//! A triangle is *regular* for a family (max or min) when the signs of the principal
//! directions at its corners can be chosen so that the three have mutually positive inner
//! products (HPW Definition 1); otherwise it is *singular* and left to
//! [`super::singular`]. In a regular triangle the consistently signed extremality is linear,
//! so its zero set is a segment between two edge points (HPW Lemma 1). That segment is a
//! feature-line segment when, with the same consistent signs,
//! - ridges (max family): `⟨∇e_max, Σ dir_max⟩ < 0` (eq. 5) and `|Σ k_max| > |Σ k_min|` (eq. 6);
//! - valleys (min family): `⟨∇e_min, Σ dir_min⟩ > 0` and `|Σ k_min| > |Σ k_max|`.
//!
//! Edge points are computed per edge, not per triangle: the crossing on edge `ab` depends only
//! on `e(a)`, `e(b)` and `sign⟨dir(a), dir(b)⟩`, so the two triangles of an edge produce the
//! same point and segments join into connected lines. A value of exactly zero counts as
//! positive (simulation of simplicity), so a zero set never passes through a vertex; crossing
//! parameters are kept a hair away from the endpoints so no two edge points coincide.

use rayon::prelude::*;

use crate::curvature::Curvature;
use crate::curvature::extremality::consistent_signs;
use crate::mesh::{TriMesh, Vec3};

use super::LineKind;

/// How far from an edge's endpoints a crossing point is kept (as a fraction of the edge).
const END_MARGIN: f64 = 1e-6;

/// A node of the segment graph: a point on an edge or the barycentre of a face.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Node {
    /// The zero crossing on edge `e` (an index into the mesh's edges).
    Edge(u32),
    /// The barycentre of face `f` (the trisector case of singular triangles).
    Face(u32),
}

/// The fields of one family (max → ridges, min → valleys).
#[derive(Debug, Clone, Copy)]
pub struct Family<'a> {
    /// Ridge for the max family, valley for the min family.
    pub kind: LineKind,
    /// Curvature of this family (`k_max` for ridges).
    pub k: &'a [f64],
    /// Curvature of the other family.
    pub k_other: &'a [f64],
    /// Extremality of this family, consistent with `dirs`.
    pub e: &'a [f64],
    /// Extremality of the other family (for the cyclideness).
    pub e_other: &'a [f64],
    /// Principal directions of this family.
    pub dirs: &'a [Vec3],
    /// Standard deviation of the extremalities' estimation noise
    /// ([`Curvature::extremality_noise`]), taken out of the cyclideness of lines
    /// ([`super::assemble::noise_free_share`]).
    pub e_noise: f64,
    /// This family's extremality by a second model of the surface, per vertex
    /// ([`Curvature::alternative_extremalities`]); empty when the estimator has one model.
    pub e_alternative: &'a [f64],
}

impl<'a> Family<'a> {
    /// The max family (ridges) or the min family (valleys) of `c`.
    pub fn of(c: &'a Curvature, kind: LineKind) -> Self {
        let alternative = |k: usize| -> &'a [f64] {
            if c.has_alternative_extremalities() {
                &c.alternative_extremalities[k]
            } else {
                &[]
            }
        };
        match kind {
            LineKind::Ridge => Family {
                kind,
                k: &c.k_max,
                k_other: &c.k_min,
                e: &c.e_max,
                e_other: &c.e_min,
                dirs: &c.dir_max,
                e_noise: c.extremality_noise,
                e_alternative: alternative(0),
            },
            LineKind::Valley => Family {
                kind,
                k: &c.k_min,
                k_other: &c.k_max,
                e: &c.e_min,
                e_other: &c.e_max,
                dirs: &c.dir_min,
                e_noise: c.extremality_noise,
                e_alternative: alternative(1),
            },
        }
    }

    /// Relative sign `sign⟨dir(a), dir(b)⟩` (zero counts as positive).
    #[inline]
    pub fn relative_sign(&self, a: u32, b: u32) -> f64 {
        if self.dirs[a as usize].dot(&self.dirs[b as usize]) < 0.0 {
            -1.0
        } else {
            1.0
        }
    }

    /// Parameter of the zero crossing on edge `a → b` (from `a`), if `e` changes sign.
    #[inline]
    pub fn crossing(&self, a: u32, b: u32) -> Option<f64> {
        let ea = self.e[a as usize];
        let eb = self.relative_sign(a, b) * self.e[b as usize];
        ((ea >= 0.0) != (eb >= 0.0)).then(|| (ea / (ea - eb)).clamp(END_MARGIN, 1.0 - END_MARGIN))
    }
}

/// Segments of one family: per-face regularity and the feature segments found.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FamilySegments {
    /// Per face: regular for this family.
    pub regular: Vec<bool>,
    /// Segments between nodes, in face order.
    pub segments: Vec<[Node; 2]>,
    /// The face each segment lies in.
    pub segment_faces: Vec<u32>,
}

impl FamilySegments {
    /// Number of singular faces.
    pub fn singular_count(&self) -> usize {
        self.regular.iter().filter(|r| !**r).count()
    }
}

/// Traces the feature-line segments of `family` in every regular triangle.
pub fn trace_regular_triangles(mesh: &TriMesh, family: &Family<'_>) -> FamilySegments {
    // One pass: each block of faces notes which are regular and keeps its segments; the
    // blocks' segments are then joined in order (two passes computed every face's signs twice).
    let faces = mesh.faces();
    let mut regular = vec![false; faces.len()];
    let blocks: Vec<(Vec<[Node; 2]>, Vec<u32>)> = regular
        .par_chunks_mut(FACE_BLOCK)
        .enumerate()
        .map(|(b, regular)| {
            let (mut segments, mut segment_faces) = (Vec::new(), Vec::new());
            for (i, is_regular) in regular.iter_mut().enumerate() {
                let f = (b * FACE_BLOCK + i) as u32;
                let t = faces[f as usize];
                let Some(signs) = consistent_signs(t.map(|v| family.dirs[v as usize])) else {
                    continue;
                };
                *is_regular = true;
                if let Some(segment) = feature_segment(mesh, family, f, signs) {
                    segments.push(segment);
                    segment_faces.push(f);
                }
            }
            (segments, segment_faces)
        })
        .collect();
    let count = blocks.iter().map(|(s, _)| s.len()).sum();
    let (mut segments, mut segment_faces) = (Vec::with_capacity(count), Vec::with_capacity(count));
    for (s, f) in blocks {
        segments.extend(s);
        segment_faces.extend(f);
    }
    FamilySegments {
        regular,
        segments,
        segment_faces,
    }
}

/// Faces per parallel work item of [`trace_regular_triangles`].
const FACE_BLOCK: usize = 4096;

/// The feature segment of a regular face, if its zero set is non-empty and eqs. 5–6 hold.
fn feature_segment(
    mesh: &TriMesh,
    family: &Family<'_>,
    f: u32,
    signs: [f64; 3],
) -> Option<[Node; 2]> {
    let t = mesh.faces()[f as usize];
    let e = [0, 1, 2].map(|i| signs[i] * family.e[t[i] as usize]);
    let positive = e.map(|x| x >= 0.0);
    if positive[0] == positive[1] && positive[1] == positive[2] {
        return None;
    }
    // Curvature condition (eq. 6 and its valley analogue).
    let sum = |k: &[f64]| t.iter().map(|&v| k[v as usize]).sum::<f64>();
    let (dominant, other) = (sum(family.k), sum(family.k_other));
    let curvature_ok = match family.kind {
        LineKind::Ridge => dominant.abs() > other.abs() && dominant > 0.0,
        LineKind::Valley => dominant.abs() > other.abs() && dominant < 0.0,
    };
    if !curvature_ok {
        return None;
    }
    // Extremum condition (eq. 5): the gradient of the linear e against the summed directions.
    let p = mesh.triangle(f as usize);
    let normal2 = (p[1] - p[0]).cross(&(p[2] - p[0]));
    let area2 = normal2.norm_squared();
    if area2 == 0.0 {
        return None;
    }
    // ∇e = Σ e_i (n × (p_{i+2} − p_{i+1})) / (2A), with n × v / (2A) = normal2 × v / |normal2|².
    let gradient = (0..3)
        .map(|i| normal2.cross(&(p[(i + 2) % 3] - p[(i + 1) % 3])) * e[i])
        .sum::<Vec3>()
        / area2;
    let dir_sum: Vec3 = (0..3).map(|i| family.dirs[t[i] as usize] * signs[i]).sum();
    let slope = gradient.dot(&dir_sum);
    let extremum_ok = match family.kind {
        LineKind::Ridge => slope < 0.0,
        LineKind::Valley => slope > 0.0,
    };
    if !extremum_ok {
        return None;
    }
    // The signs are not all equal, so exactly two of the three edges change sign. The edges
    // are looked up only here, for the few faces that carry a segment.
    let edges = mesh.topology().face_edges(f);
    let mut crossed = (0..3)
        .filter(|&s| positive[s] != positive[(s + 1) % 3])
        .map(|s| Node::Edge(edges[s]));
    match (crossed.next(), crossed.next()) {
        (Some(a), Some(b)) => Some([a, b]),
        _ => None,
    }
}

/// Position of a node on the mesh.
pub fn node_position(mesh: &TriMesh, family: &Family<'_>, node: Node) -> Vec3 {
    match node {
        Node::Edge(e) => {
            let [a, b] = mesh.topology().edge(e);
            let t = family.crossing(a, b).unwrap_or(0.5);
            mesh.position(a) * (1.0 - t) + mesh.position(b) * t
        }
        Node::Face(f) => mesh.triangle(f as usize).iter().sum::<Vec3>() / 3.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crossing_is_the_same_from_both_ends() {
        let dirs = vec![Vec3::x(), -Vec3::x()];
        let e = vec![1.0, 3.0]; // aligned: 1 and -3 → crossing at 1/4 from vertex 0.
        let zero = vec![0.0; 2];
        let fam = Family {
            kind: LineKind::Ridge,
            k: &zero,
            k_other: &zero,
            e: &e,
            e_other: &zero,
            dirs: &dirs,
            e_noise: 0.0,
            e_alternative: &[],
        };
        let t01 = fam.crossing(0, 1).unwrap();
        let t10 = fam.crossing(1, 0).unwrap();
        assert!((t01 - 0.25).abs() < 1e-12);
        assert!((t01 + t10 - 1.0).abs() < 1e-12);
    }
}
