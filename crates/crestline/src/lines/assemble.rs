//! Joining segments into maximal polylines with their strengths (HPW 2005, Table 1 step 6;
//! strengths after Ohtake et al. 2004 and YBS 2005 eqs. 5–6).
//!
//! Segments form a graph on their end nodes (edge points and barycentres). A polyline runs
//! between nodes whose degree is not 2 (line ends and junctions such as trisector
//! barycentres); what is left after that are closed loops, which stay closed. The walk is
//! sequential over sorted nodes, so the output is deterministic.
//!
//! Each line carries its length, the integral of |k| of its family along it (trapezoid rule)
//! and YBS's scale-independent strength `T = ∫ds · ∫C ds` (over the part of the line that is
//! a crest, see [`measure_line`]), with the cyclideness
//! `C = sqrt(e_max² + e_min²)` interpolated at each line point as YBS prescribe (on an edge
//! that is the linear interpolation at the zero crossing, weights `|e(q)|`, `|e(p)|`).
//!
//! **Crossings at vertices.** On a crest the line's family has e = 0, so C there is the
//! other family's |e| (YBS); what the interpolation adds of this family's |e| is the chord
//! of |e| between the edge's ends, `2ab / (a + b)` for ends at |e| = a and b: the crest's
//! slope times a length that depends on where the vertices lie, zero when the crest runs
//! through them. There (a plane of symmetry through vertices, a ridge along a column of a
//! grid) the crossing is at a vertex through which e passes ([`is_resolved`]) or the line
//! runs along edges whose ends both are such zeros, and this family's part of C is taken
//! as the chord's mean over where the crossing may fall along the edge, a third of e's
//! change along it (for an edge along the crest, of the smaller of its ends' neighbours'
//! |e| beside it). A Gaussian ridge extruded along a grid (e_min ≡ 0) had T = 93 with its
//! crest between two columns and 0.08 along one, no line; now 56 along one (the suite's
//! `a_ridge_along_a_column_of_vertices_is_kept`; `BENCHMARKS.md`, *Crests through vertices*).

use rayon::prelude::*;

use crate::mesh::{TriMesh, Vec3};

use super::trace::{Family, FamilySegments, Node, node_position};
use super::{FeatureLine, SurfacePoint};

/// Joins the segments of one family into polylines.
pub fn assemble_lines(
    mesh: &TriMesh,
    family: &Family<'_>,
    segments: &FamilySegments,
) -> Vec<FeatureLine> {
    let mut nodes: Vec<Node> = segments.segments.iter().flatten().copied().collect();
    // Equal nodes are identical, so the unstable parallel sort gives one result.
    nodes.par_sort_unstable();
    nodes.dedup();
    let index = |n: Node| nodes.binary_search(&n).unwrap_or(0);

    let links: Vec<(usize, usize)> = segments
        .segments
        .par_iter()
        .map(|&[a, b]| (index(a), index(b)))
        .collect();
    let paths = chain_links(nodes.len(), &links);
    paths
        .into_par_iter()
        .map(|(path, closed)| {
            let path: Vec<Node> = path.into_iter().map(|i| nodes[i]).collect();
            build_line(mesh, family, &path, closed)
        })
        .collect()
}

/// Splits a graph into maximal paths: each path runs between nodes whose degree is not 2
/// (ends and junctions); what remains are cycles, returned with `true`. Duplicate links and
/// self-loops are ignored. Deterministic: nodes are visited in index order.
pub fn chain_links(num_nodes: usize, links: &[(usize, usize)]) -> Vec<(Vec<usize>, bool)> {
    let mut links: Vec<(usize, usize)> = links
        .iter()
        .filter(|(a, b)| a != b)
        .map(|&(a, b)| (a.min(b), a.max(b)))
        .collect();
    links.par_sort_unstable();
    links.dedup();

    let mut offsets = vec![0usize; num_nodes + 1];
    for &(a, b) in &links {
        offsets[a + 1] += 1;
        offsets[b + 1] += 1;
    }
    for i in 0..num_nodes {
        offsets[i + 1] += offsets[i];
    }
    let mut cursor = offsets.clone();
    let mut incident = vec![0usize; offsets[num_nodes]];
    for (l, &(a, b)) in links.iter().enumerate() {
        incident[cursor[a]] = l;
        cursor[a] += 1;
        incident[cursor[b]] = l;
        cursor[b] += 1;
    }
    let degree = |n: usize| offsets[n + 1] - offsets[n];
    let other = |l: usize, n: usize| {
        if links[l].0 == n {
            links[l].1
        } else {
            links[l].0
        }
    };

    let mut used = vec![false; links.len()];
    let walk = |start: usize, first: usize, used: &mut Vec<bool>| -> (Vec<usize>, bool) {
        let mut path = vec![start];
        let (mut at, mut via) = (start, first);
        loop {
            used[via] = true;
            at = other(via, at);
            if at == start {
                return (path, true);
            }
            path.push(at);
            if degree(at) != 2 {
                return (path, false);
            }
            let next = incident[offsets[at]..offsets[at + 1]]
                .iter()
                .copied()
                .find(|&l| !used[l]);
            match next {
                Some(l) => via = l,
                None => return (path, false),
            }
        }
    };
    let mut paths = Vec::new();
    // Paths between ends and junctions first; what remains are closed loops.
    for ends_only in [true, false] {
        for n in 0..num_nodes {
            if ends_only && degree(n) == 2 {
                continue;
            }
            for &l in &incident[offsets[n]..offsets[n + 1]] {
                if !used[l] {
                    paths.push(walk(n, l, &mut used));
                }
            }
        }
    }
    paths
}

/// A [`FeatureLine`] through `path`, with length and strengths.
fn build_line(mesh: &TriMesh, family: &Family<'_>, path: &[Node], closed: bool) -> FeatureLine {
    let topo = mesh.topology();
    let points = path
        .iter()
        .map(|&n| node_position(mesh, family, n))
        .collect();
    let mut line = FeatureLine {
        locations: path
            .iter()
            .map(|&node| match node {
                Node::Edge(e) => {
                    let [a, b] = topo.edge(e);
                    SurfacePoint::Edge {
                        edge: e,
                        t: family.crossing(a, b).unwrap_or(0.5),
                    }
                }
                Node::Face(f) => SurfacePoint::Face { face: f },
            })
            .collect(),
        ..FeatureLine::new(family.kind, points, closed)
    };
    measure_line(mesh, family, &mut line);
    line
}

/// Recomputes a line's length, `∫|k| ds` and `T = ∫ds · ∫C ds` from its points and surface
/// locations (values interpolated linearly from the vertices). Both integrals of T run only
/// where the crossing is a crest and not a degenerate zero of e ([`is_resolved`]): a line
/// that runs on along a cylinder or a cone, where e ≡ 0, is as strong as its crest part
/// (the dome of the public CAD parts on its cylinder, meshed uniformly, kept a line along the
/// cylinder whose few resolved points at the dome's seam, times the whole length, made
/// T > 1: HPW F1 0.883 → 1.000; the quality cases unchanged). On noisy meshes `∫C ds` counts
/// only the share of C above the extremalities' estimation noise ([`noise_free_share`]).
/// Lines without locations only get their length.
pub fn measure_line(mesh: &TriMesh, family: &Family<'_>, line: &mut FeatureLine) {
    let n = line.points.len();
    let mut k_abs = vec![0.0; n];
    let mut cyclideness = vec![0.0; n];
    let mut squared = vec![0.0; n];
    let mut resolved = vec![1.0; n];
    if line.locations.len() == n {
        for (i, location) in line.locations.iter().enumerate() {
            let (mut k, mut c, mut c2) = (0.0, 0.0, 0.0);
            let (mut other, mut other2) = (0.0, 0.0);
            for (v, w) in location_weights(mesh, *location) {
                let v = v as usize;
                let (e, e_other) = (family.e[v], family.e_other[v]);
                k += w * family.k[v];
                c += w * e.hypot(e_other);
                c2 += w * (e * e + e_other * e_other);
                other += w * e_other.abs();
                other2 += w * e_other * e_other;
            }
            if let SurfacePoint::Edge { edge, .. } = *location {
                // A crossing at a vertex through which e passes, or along an edge between
                // two: the interpolation at the zero takes none of this family's e, which a
                // crossing inside the edge has (module docs, *Crossings at vertices*).
                let [a, b] = mesh.topology().edge(edge);
                if let Some(across) = crest_at_vertices(mesh, family, a, b, k.abs()) {
                    let crest = across / 3.0;
                    (c, c2) = (other.hypot(crest), other2 + crest * crest);
                }
            }
            k_abs[i] = k.abs();
            if is_resolved(mesh, family, *location, k_abs[i]) {
                (cyclideness[i], squared[i]) = (c, c2);
            } else {
                resolved[i] = 0.0;
            }
        }
    }
    let (length, k_integral, c_integral) =
        integrate(&line.points, &k_abs, &cyclideness, line.closed);
    let (_, crest_length, square_integral) =
        integrate(&line.points, &resolved, &squared, line.closed);
    // A line with no crest part has T = 0 whatever the share.
    let share = if crest_length > 0.0 {
        noise_free_share(square_integral / crest_length, family.e_noise)
    } else {
        1.0
    };
    line.length = length;
    line.curvature_integral = k_integral;
    line.strength = crest_length * c_integral * share;
}

/// Whether the extremality changes across the line fast enough for the crossing to be a crest
/// rather than a degenerate zero: on cylinders, cones, spheres and tori (Dupin cyclides)
/// `e ≡ 0` and `de/dt = 0`, and the fit's rounding decides where a "line" runs. The test
/// compares the change of e along the crossed edge, `|Δe| / |edge|` (a lower bound of
/// |de/dt|), with the curvature's own scale `|k|³`, and asks both ends of the edge to be away
/// from umbilics ([`UMBILIC_GAP`]; flat points, where both curvatures are zero, pass: the
/// strength threshold handles them). A point inside a face or at a vertex has no edge to
/// measure e's change along; it counts unless a corner is near an umbilic. (On a capsule,
/// a cylinder with hemispherical caps, YBS's crest points alternated between edges next to
/// the caps' umbilics and faces beside them, and the faces carried a ring of T = 2 around
/// each cap, where no crest line is.) Nor is a crossing that the estimator's second model of
/// the surface does not have, the same way: e rising or falling alike
/// ([`Curvature::alternative_extremalities`](crate::curvature::Curvature::alternative_extremalities);
/// a value at the level of rounding counts as a zero, and so does an end where both models
/// are zero to the fit's accuracy, as on a plane of symmetry through vertices). (The bend
/// of the public pipe elbow, exported as a CAD program does, is a torus, e ≡ 0: e is a few
/// 1e-4 or less, of either sign, and the two models put it at −6e-4 and +1.6e-3 at the rows
/// of its strips, at ±7e-5 with opposite signs between them. Taking the better model at each
/// vertex traced ridges of T up to 11 along the bend; HPW F1 1.000 → 0.897.) An edge that
/// runs along the crest, both ends zeros of e that it passes through, is measured by their
/// neighbours' e across it instead (module docs, *Crossings at vertices*).
pub fn is_resolved(mesh: &TriMesh, family: &Family<'_>, location: SurfacePoint, k: f64) -> bool {
    let anisotropic = |v: u32| {
        let (Some(&k), Some(&other)) = (family.k.get(v as usize), family.k_other.get(v as usize))
        else {
            return true;
        };
        (k - other).abs() >= UMBILIC_GAP * k.abs().max(other.abs())
    };
    let edge = match location {
        SurfacePoint::Edge { edge, .. } => edge,
        SurfacePoint::Vertex(v) => return anisotropic(v),
        SurfacePoint::Face { face } => {
            return mesh
                .faces()
                .get(face as usize)
                .is_none_or(|corners| corners.iter().all(|&v| anisotropic(v)));
        }
    };
    let [a, b] = mesh.topology().edge(edge);
    if !(anisotropic(a) && anisotropic(b)) {
        return false;
    }
    let (change, bound) = change_and_bound(mesh, family, a, b, k);
    if change >= bound {
        alternative_crosses(mesh, family, a, b)
    } else {
        // An edge along the crest, both ends zeros of e that it passes through.
        along_crest(mesh, family, a, b).is_some_and(|beside| beside >= bound)
    }
}

/// e's change along the edge from `a` to `b`, and [`DEGENERATE_CREST`]'s bound on it for a
/// crest of curvature `k` (`DEGENERATE_CREST |k|³ |edge|`).
fn change_and_bound(mesh: &TriMesh, family: &Family<'_>, a: u32, b: u32, k: f64) -> (f64, f64) {
    let change = (family.e[b as usize] * family.relative_sign(a, b) - family.e[a as usize]).abs();
    let length = (mesh.position(b) - mesh.position(a)).norm();
    (change, DEGENERATE_CREST * k.abs().powi(3) * length)
}

/// This family's e across the crest where the line crosses the edge from `a` to `b` at a
/// vertex through which e passes ([`passes_through`]: e's change along the edge), or runs
/// along the edge between two such vertices ([`along_crest`], when above the degenerate
/// bound); `None` for a crossing inside the edge (module docs, *Crossings at vertices*).
fn crest_at_vertices(mesh: &TriMesh, family: &Family<'_>, a: u32, b: u32, k: f64) -> Option<f64> {
    let (change, bound) = change_and_bound(mesh, family, a, b, k);
    if change >= bound {
        (passes_through(mesh, family, a, change) || passes_through(mesh, family, b, change))
            .then_some(change)
    } else {
        along_crest(mesh, family, a, b).filter(|&beside| beside >= bound)
    }
}

/// For an edge whose ends are both zeros of e that it passes through ([`zero_through`]), the
/// edge runs along the crest: the smaller of its ends' neighbours' |e| beside it.
fn along_crest(mesh: &TriMesh, family: &Family<'_>, a: u32, b: u32) -> Option<f64> {
    let beside_a = zero_through(mesh, family, a, f64::INFINITY)?;
    Some(beside_a.min(zero_through(mesh, family, b, f64::INFINITY)?))
}

/// Whether the second model's extremality ([`Family::e_alternative`]) crosses zero along the
/// edge from `a` to `b` the way the estimate's does (rising or falling alike), an end at
/// zero to rounding (within `1e-9` of the estimate's larger end) counting as a crossing,
/// and so does an end through which e passes in both models ([`passes_through`]); true
/// without a second model.
fn alternative_crosses(mesh: &TriMesh, family: &Family<'_>, a: u32, b: u32) -> bool {
    let (Some(&ea), Some(&eb)) = (
        family.e_alternative.get(a as usize),
        family.e_alternative.get(b as usize),
    ) else {
        return true;
    };
    let sign = family.relative_sign(a, b);
    let (ka, kb) = (family.e[a as usize], family.e[b as usize] * sign);
    let eb = eb * sign;
    let rounding = 1e-9 * ka.abs().max(kb.abs());
    let same_way = (ea - eb) * (ka - kb) > 0.0;
    let change = (ka - kb).abs();
    same_way
        && (ea * eb <= 0.0
            || ea.abs() <= rounding
            || eb.abs() <= rounding
            || passes_through(mesh, family, a, change)
            || passes_through(mesh, family, b, change))
}

/// Whether e passes through zero at vertex `v` in both models: both are within
/// [`AT_VERTEX`] of `change` (e's change along the crossed edge) of zero there, and the
/// neighbours that lie clearly to either side of `v` along its principal direction (within
/// 60° of it), where the estimate's e is beyond `1 / AT_VERTEX` times `v`'s larger value,
/// have it of both signs and rising one way along that direction.
///
/// A crest through vertices on a plane of symmetry (marching cubes on a grid through that
/// plane, a mirrored model) has e zero at them to the fit's accuracy, of either sign in
/// either model, so that the two models' zeros fall just inside and just outside the edges
/// that end there. The public ovoid meshed so at 30 cells per unit, its vertices projected
/// onto the surface, kept 35 of its 474 crest points without this test (T 0.04 where the
/// public `mc` mesh gives 69: no line; the vertices on the plane had e at 1e-5 to 3e-3 of
/// its values beside them, coarser grids the more). The neighbours' signs and slope tell it
/// from a zero of e ≡ 0 next to a fit's bias: on the public pipe elbow, whose bend is a
/// torus, vertices of e at 2e-4 lie beside the seam's bias of 0.07 to 0.8, of both signs
/// but not rising one way (with the signs alone, YBS F1 1.000 → 0.996 there).
fn passes_through(mesh: &TriMesh, family: &Family<'_>, v: u32, change: f64) -> bool {
    zero_through(mesh, family, v, AT_VERTEX * change).is_some()
}

/// Whether e passes through zero at vertex `v`, by its neighbours alone: |e| there is at
/// most `at_most` in both of the jet fit's models, and the neighbours clearly to either side
/// of it along its principal direction (within 60°), where the estimate's e is beyond
/// `1 / AT_VERTEX` times `v`'s larger value, have it of both signs and rising one way along
/// that direction. Returns the smaller of the largest |e| of those neighbours on either side.
/// Never without a second model: the cubic fit's lines on fandisk's flat faces, where k ≈ 0
/// leaves every crossing above the degenerate bound, gained strength past the automatic
/// threshold's knee.
fn zero_through(mesh: &TriMesh, family: &Family<'_>, v: u32, at_most: f64) -> Option<f64> {
    let (e, alternative) = (
        family.e.get(v as usize)?,
        family.e_alternative.get(v as usize)?,
    );
    let value = e.abs().max(alternative.abs());
    if !value.is_finite() || at_most.is_nan() || value > at_most {
        return None;
    }
    let threshold = value / AT_VERTEX;
    let (p, dir) = (mesh.position(v), family.dirs[v as usize]);
    // Per side of v along its direction (ahead, behind), the neighbours there where e is
    // well away from zero, positive and negative, and the largest |e| there.
    let mut counts = [[0usize; 2]; 2];
    let mut largest = [0.0f64; 2];
    for w in mesh.topology().neighbors(v) {
        let e_w = family.e[w as usize] * family.relative_sign(v, w);
        let offset = mesh.position(w) - p;
        let along = offset.dot(&dir);
        if e_w.abs() > threshold && along.abs() >= 0.5 * offset.norm() && along != 0.0 {
            let side = usize::from(along < 0.0);
            counts[side][usize::from(e_w < 0.0)] += 1;
            largest[side] = largest[side].max(e_w.abs());
        }
    }
    let [[ahead_up, ahead_down], [behind_up, behind_down]] = counts;
    // e rises through v (negative behind, positive ahead) or falls, and not both.
    let rises = ahead_up > 0 && behind_down > 0 && ahead_down == 0 && behind_up == 0;
    let falls = ahead_down > 0 && behind_up > 0 && ahead_up == 0 && behind_down == 0;
    (rises || falls).then(|| largest[0].min(largest[1]))
}

/// [`is_resolved`]'s share for a crossing at a vertex: where both models' e at an end of the
/// crossed edge is within this share of its change along the edge of zero, and the
/// neighbours on either side of that vertex along its principal direction have e of both
/// signs beyond its value over this share, rising one way, the crossing is at that vertex.
/// An edge both of whose ends are such zeros (by their neighbours alone) runs along the
/// crest (module docs, *Crossings at vertices*).
pub const AT_VERTEX: f64 = 1e-2;

/// [`is_resolved`]'s bound: `|de/dt| < DEGENERATE_CREST |k|³` is a degenerate crossing.
pub const DEGENERATE_CREST: f64 = 0.01;

/// [`is_resolved`]'s umbilic bound: where `|k_max − k_min| < UMBILIC_GAP max(|k_max|, |k_min|)`
/// at an end of the crossed edge, the principal directions, and with them e (a derivative
/// along one of them), are not defined to the fit's accuracy (spheres, the seam where a dome
/// meets its cylinder). Measured (`score.py`, `score_cad.py`): every quality case unchanged,
/// CAD parts HPW 0.983 → 0.991, YBS 0.988 → 0.991; 0.25 costs YBS 0.04 on bumpy/irr20k.
pub const UMBILIC_GAP: f64 = 0.1;

/// The share of a line's cyclideness that is not the extremalities' estimation noise, from
/// the mean of C² along its crest part and the noise's standard deviation δ
/// ([`Curvature::extremality_noise`](crate::curvature::Curvature::extremality_noise)):
/// `sqrt(max(0, mean C² − δ²) / mean C²)`, 1 without noise (δ = 0) or without C.
///
/// **One δ², not two.** At a point of the line this family's e is zero. The noise the fit
/// and the smoothing leave is correlated over the fitting disc, many edges wide, so it is
/// nearly the same ν at both ends of the crossed edge: it moves the crossing and leaves the
/// value interpolated there as it was (ends `−h + ν` and `h + ν` interpolate to
/// `(h² − ν²) / h`, not more). Only the other family's e carries its noise into C:
/// `E[C²] ≈ C_true² + δ²`. (Noise that differs across one edge would add to it; the
/// smoothed fields have little of that.)
///
/// **Over the line, not point by point.** `sqrt(max(0, C² − δ²))` at each point is biased
/// by the clamp and the square root: for normal noise with C_true = δ it gives 0.73 δ on
/// average, and for a line of noise alone (C_true = 0) 0.34 δ, which a long line turns into
/// a large T (T grows with the square of the length). The mean of C² over the line is
/// unbiased; the share made of it is not quite (T about 7% low at C_true = δ, the unit
/// test), and on a line of noise alone it falls with the number of the noise's correlation
/// lengths along the line, not of points. It is not local: the noise of a weak tail of a
/// strong line is counted with the line's share.
///
/// Until 2026-11-27 each point's C was replaced by `sqrt(max(0, C² − 2δ²))` (both families'
/// noise); measurements before and after, and the cost on noisy tori, in `BENCHMARKS.md`
/// (*Quality on exact-answer cases*).
pub fn noise_free_share(mean_square: f64, noise: f64) -> f64 {
    if noise > 0.0 && mean_square > 0.0 {
        ((mean_square - noise * noise).max(0.0) / mean_square).sqrt()
    } else {
        1.0
    }
}

/// Linear interpolation weights of a surface point over mesh vertices (one to three).
pub fn location_weights(
    mesh: &TriMesh,
    location: SurfacePoint,
) -> impl Iterator<Item = (u32, f64)> {
    let (weights, count) = match location {
        SurfacePoint::Edge { edge, t } => {
            let [a, b] = mesh.topology().edge(edge);
            ([(a, 1.0 - t), (b, t), (b, 0.0)], 2)
        }
        SurfacePoint::Face { face } => (mesh.faces()[face as usize].map(|v| (v, 1.0 / 3.0)), 3),
        SurfacePoint::Vertex(v) => ([(v, 1.0); 3], 1),
    };
    weights.into_iter().take(count)
}

/// Length and trapezoid integrals of two per-point quantities along a polyline.
pub fn integrate(points: &[Vec3], f: &[f64], g: &[f64], closed: bool) -> (f64, f64, f64) {
    let n = points.len();
    let pairs = if closed && n > 2 {
        n
    } else {
        n.saturating_sub(1)
    };
    let (mut length, mut int_f, mut int_g) = (0.0, 0.0, 0.0);
    for i in 0..pairs {
        let j = (i + 1) % n;
        let ds = (points[j] - points[i]).norm();
        length += ds;
        int_f += 0.5 * (f[i] + f[j]) * ds;
        int_g += 0.5 * (g[i] + g[j]) * ds;
    }
    (length, int_f, int_g)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lines::LineKind;

    #[test]
    fn trapezoid_integrals() {
        let pts = vec![Vec3::zeros(), Vec3::x(), Vec3::new(1.0, 1.0, 0.0)];
        let (l, a, b) = integrate(&pts, &[1.0, 1.0, 1.0], &[0.0, 2.0, 0.0], false);
        assert!((l - 2.0).abs() < 1e-12);
        assert!((a - 2.0).abs() < 1e-12);
        assert!((b - 2.0).abs() < 1e-12);
        let (l, _, _) = integrate(&pts, &[0.0; 3], &[0.0; 3], true);
        assert!((l - (2.0 + 2f64.sqrt())).abs() < 1e-12);
    }

    /// The ridge family of `k` and `e` (the other family's fields `zero`), without noise.
    fn ridge_family<'a>(
        k: &'a [f64],
        e: &'a [f64],
        zero: &'a [f64],
        dirs: &'a [Vec3],
    ) -> Family<'a> {
        Family {
            kind: LineKind::Ridge,
            k,
            k_other: zero,
            e,
            e_other: zero,
            dirs,
            e_noise: 0.0,
            e_alternative: &[],
        }
    }

    /// A triangle, its first edge and that edge's ends.
    fn one_triangle() -> (TriMesh, u32, [u32; 2]) {
        let m = TriMesh::from_arrays(
            vec![[0.0, 0.0, 0.0], [0.5, 0.0, 0.0], [0.0, 1.0, 0.0]],
            vec![[0, 1, 2]],
        )
        .unwrap();
        let edge = m.topology().face_edges(0)[0];
        let ends = m.topology().edge(edge);
        (m, edge, ends)
    }

    /// A crossing counts when e changes along the crossed edge by at least
    /// `DEGENERATE_CREST |k|³` per unit length; rounding-level values, as on a cylinder, do not.
    #[test]
    fn degenerate_crossings_are_not_resolved() {
        let (m, edge, [a, b]) = one_triangle();
        let length = (m.position(b) - m.position(a)).norm();
        let k = vec![2.0; 3];
        let zero = vec![0.0; 3];
        let dirs = vec![Vec3::x(); 3];
        let resolved = |change: f64| {
            let mut e = vec![0.0; 3];
            e[a as usize] = -change / 2.0;
            e[b as usize] = change / 2.0;
            let fam = ridge_family(&k, &e, &zero, &dirs);
            is_resolved(&m, &fam, SurfacePoint::Edge { edge, t: 0.5 }, 2.0)
        };
        let bound = DEGENERATE_CREST * 8.0 * length;
        assert!(resolved(1.01 * bound));
        // The same change next to an umbilic (k_min close to k_max) does not count.
        let near_umbilic = vec![2.0 * (1.0 - 0.5 * UMBILIC_GAP); 3];
        let mut e = vec![0.0; 3];
        e[b as usize] = 1.0;
        let fam = ridge_family(&k, &e, &near_umbilic, &dirs);
        let point = SurfacePoint::Edge { edge, t: 0.5 };
        assert!(!is_resolved(&m, &fam, point, 2.0));
        assert!(!resolved(0.99 * bound));
        assert!(!resolved(1e-12));
        // Inside a face or at a vertex there is no edge to measure e's change along: the
        // point counts unless a corner is near an umbilic.
        let face = SurfacePoint::Face { face: 0 };
        assert!(!is_resolved(&m, &fam, face, 2.0));
        assert!(!is_resolved(&m, &fam, SurfacePoint::Vertex(a), 2.0));
        let fam = ridge_family(&k, &e, &zero, &dirs);
        assert!(is_resolved(&m, &fam, face, 2.0));
        assert!(is_resolved(&m, &fam, SurfacePoint::Vertex(a), 2.0));
        let empty = crate::curvature::Curvature::default();
        let fam = Family::of(&empty, LineKind::Ridge);
        assert!(is_resolved(&m, &fam, face, 2.0));
    }

    /// A crossing counts only when the second model of the surface has it too, the same way
    /// (or a zero to rounding at an end; a crossing at a vertex: the next test).
    #[test]
    fn crossings_the_second_model_does_not_have_are_not_resolved() {
        let (m, edge, [a, b]) = one_triangle();
        let (k, zero, dirs) = (vec![2.0; 3], vec![0.0; 3], vec![Vec3::x(); 3]);
        let mut e = vec![0.0; 3];
        e[a as usize] = -0.5;
        e[b as usize] = 0.5;
        let point = SurfacePoint::Edge { edge, t: 0.5 };
        let with_alternative = |ea: f64, eb: f64| {
            let mut alternative = vec![0.0; 3];
            alternative[a as usize] = ea;
            alternative[b as usize] = eb;
            let fam = Family {
                e_alternative: &alternative,
                ..ridge_family(&k, &e, &zero, &dirs)
            };
            is_resolved(&m, &fam, point, 2.0)
        };
        // The change of 1 is far above DEGENERATE_CREST |k|³ |edge| = 0.04.
        let fam = ridge_family(&k, &e, &zero, &dirs);
        assert!(is_resolved(&m, &fam, point, 2.0));
        assert!(with_alternative(-0.1, 2.0));
        assert!(with_alternative(1e-17, 2.0));
        assert!(!with_alternative(0.1, 2.0));
        assert!(!with_alternative(-0.1, -1e-3));
        // A crossing the other way (e falling where the estimate's rises) is not this one.
        assert!(!with_alternative(0.1, -2.0));
        // The same with the direction at b turned round: e and the second model's e at b
        // change sign with it.
        let mut turned = dirs.clone();
        turned[b as usize] = -Vec3::x();
        let mut e_turned = e.clone();
        e_turned[b as usize] = -e[b as usize];
        for (ea, eb, expected) in [(-0.1, 2.0, true), (0.1, 2.0, false), (0.1, -2.0, false)] {
            let mut alternative = vec![0.0; 3];
            alternative[a as usize] = ea;
            alternative[b as usize] = -eb;
            let fam = Family {
                e_alternative: &alternative,
                ..ridge_family(&k, &e_turned, &zero, &turned)
            };
            assert_eq!(is_resolved(&m, &fam, point, 2.0), expected, "{ea}, {eb}");
        }
    }

    /// A crest through a vertex (on a plane of symmetry): e is zero there to the fit's
    /// accuracy, of either sign in either model, so the second model's zero can fall just
    /// beyond the crossed edge. It counts when e passes through zero at that vertex: its
    /// neighbours on either side along the principal direction have e of both signs, far
    /// beyond its own, rising one way; not beside a zero of e ≡ 0 (the neighbour on the
    /// other side near zero too), nor where the signs do not rise one way (as beside a
    /// seam's fit bias).
    #[test]
    fn a_crest_through_a_vertex_counts_when_e_passes_through_zero_there() {
        // a at the origin, b and c on either side of it along x (the principal direction),
        // d beside it across the direction; the crossed edge is a–b.
        let fan = |c: [f64; 3]| {
            TriMesh::from_arrays(
                vec![[0.0, 0.0, 0.0], [0.5, 0.0, 0.0], c, [0.0, 1.0, 0.0]],
                vec![[0, 1, 3], [0, 3, 2]],
            )
            .unwrap()
        };
        // e at a in the estimate and the second model, e at c and d, c's direction.
        let resolved = |m: &TriMesh, [e_a, alternative_a, e_c, e_d]: [f64; 4], dir_c: Vec3| {
            let edge = m.topology().edge_between(0, 1).unwrap();
            let (k, zero) = (vec![2.0; 4], vec![0.0; 4]);
            let dirs = vec![Vec3::x(), Vec3::x(), dir_c, Vec3::x()];
            let e = vec![e_a, 0.5, e_c, e_d];
            let alternative = vec![alternative_a, 2.0, e_c, e_d];
            let fam = Family {
                e_alternative: &alternative,
                ..ridge_family(&k, &e, &zero, &dirs)
            };
            let point = SurfacePoint::Edge { edge, t: 0.0 };
            is_resolved(m, &fam, point, 2.0)
        };
        let across = fan([-0.5, 0.2, 0.0]);
        let x = Vec3::x();
        assert!(resolved(&across, [-1e-5, 1e-5, -0.5, 0.0], x));
        // c's direction turned round: its e turns with it, and it is the same field.
        assert!(resolved(&across, [-1e-5, 1e-5, 0.5, 0.0], -x));
        // d, across the direction, says nothing whatever its e.
        assert!(resolved(&across, [-1e-5, 1e-5, -0.5, 0.5], x));
        assert!(resolved(&across, [-1e-5, 1e-5, -0.5, -0.5], x));
        // Not at zero in one model, or not far enough below the neighbours' values.
        assert!(!resolved(&across, [-1e-5, 1e-2, -0.5, 0.0], x));
        assert!(!resolved(&across, [-1e-2, 1e-5, -0.5, 0.0], x));
        // The neighbour on the other side near zero too (e ≡ 0 beyond a), or of the same
        // sign as b.
        assert!(!resolved(&across, [-1e-5, 1e-5, -1e-4, 0.0], x));
        assert!(!resolved(&across, [-1e-5, 1e-5, 0.5, 0.0], x));
        // Both signs, but the negative one on b's side (c moved there, its triangle folded
        // over the first): e does not rise one way through a.
        assert!(!resolved(
            &fan([0.5, 0.8, 0.0]),
            [-1e-5, 1e-5, -0.5, 0.0],
            x
        ));
    }

    /// An edge along the crest, both ends zeros of e that it passes through: a crest point,
    /// though e hardly changes along it, when its ends' neighbours' e across it is above the
    /// degenerate bound; not below it, nor without the second model.
    #[test]
    fn an_edge_along_the_crest_is_resolved_by_its_neighbours() {
        // A 3 × 3 grid of unit squares' corners, x = −1, 0, 1 and y = 0, 1, 2, the crest on
        // x = 0 and the principal direction x.
        let positions: Vec<[f64; 3]> = (0..3)
            .flat_map(|j| (0..3).map(move |i| [f64::from(i) - 1.0, f64::from(j), 0.0]))
            .collect();
        let mut faces = Vec::new();
        for j in 0..2u32 {
            for i in 0..2u32 {
                let v = 3 * j + i;
                faces.push([v, v + 1, v + 4]);
                faces.push([v, v + 4, v + 3]);
            }
        }
        let m = TriMesh::from_arrays(positions, faces).unwrap();
        let edge = m.topology().edge_between(1, 4).unwrap();
        let resolved = |slope: f64, with_alternative: bool| {
            let (k, zero, dirs) = (vec![2.0; 9], vec![0.0; 9], vec![Vec3::x(); 9]);
            // e rises through the column, at 1e-6 of either sign on it.
            let e: Vec<f64> = (0..9)
                .map(|v| match v % 3 {
                    0 => -slope,
                    1 if v % 2 == 0 => 1e-6 * slope,
                    1 => -1e-6 * slope,
                    _ => slope,
                })
                .collect();
            let alternative: Vec<f64> = e
                .iter()
                .map(|&e| if e.abs() < slope { -e } else { e })
                .collect();
            let fam = Family {
                e_alternative: if with_alternative { &alternative } else { &[] },
                ..ridge_family(&k, &e, &zero, &dirs)
            };
            is_resolved(&m, &fam, SurfacePoint::Edge { edge, t: 0.5 }, 2.0)
        };
        // The degenerate bound is DEGENERATE_CREST |k|³ |edge| = 0.08.
        assert!(resolved(0.5, true));
        assert!(!resolved(0.05, true));
        assert!(!resolved(0.5, false));
    }

    /// The ridge through the midpoints of the rungs of `quad_strip(n)`, from x = 0 to n.
    fn along_the_rungs(strip: &TriMesh, n: u32) -> FeatureLine {
        FeatureLine {
            locations: (0..=n)
                .map(|i| SurfacePoint::Edge {
                    edge: strip.topology().edge_between(2 * i, 2 * i + 1).unwrap(),
                    t: 0.5,
                })
                .collect(),
            ..FeatureLine::new(
                LineKind::Ridge,
                (0..=n).map(|i| Vec3::new(f64::from(i), 0.5, 0.0)).collect(),
                false,
            )
        }
    }

    /// T counts only the part of a line that is a crest: along a strip of quads, e changes
    /// across the line on the left half and only at the level of rounding on the right half
    /// (as on a cylinder), so the right half adds to neither integral of T.
    #[test]
    fn strength_counts_only_the_crest_part_of_a_line() {
        let n = 6u32;
        let m = crate::shapes::quad_strip(n);
        let nv = m.num_vertices();
        let e: Vec<f64> = m
            .positions()
            .iter()
            .map(|p| (p.y - 0.5) * if p.x <= 3.0 { 1.0 } else { 1e-9 })
            .collect();
        let dirs = vec![Vec3::y(); nv];
        let k = vec![1.0; nv];
        let zero = vec![0.0; nv];
        let fam = ridge_family(&k, &e, &zero, &dirs);
        // The line through the rungs' midpoints, x = 0 to 6.
        let mut line = along_the_rungs(&m, n);
        measure_line(&m, &fam, &mut line);
        assert!((line.length - 6.0).abs() < 1e-12);
        // C = 0.5 at x = 0..3 and 0 from x = 4 on: ∫C ds = 1.5 + 0.25; the crest part is 3.5
        // long (half of the segment from 3 to 4 by the trapezoid rule), not 6.
        assert!(
            (line.strength - 3.5 * 1.75).abs() < 1e-9,
            "{}",
            line.strength
        );
    }

    /// On a noisy mesh T counts the cyclideness above the extremalities' estimation noise: a
    /// line whose other-family e is as large as that noise keeps about the T of its clean
    /// counterpart, a line of noise alone gets almost none ([`noise_free_share`]).
    #[test]
    fn strength_takes_out_the_noise_of_the_other_familys_extremality() {
        let n = 4000u32;
        let m = crate::shapes::quad_strip(n);
        let nv = m.num_vertices();
        let (k, zero, dirs) = (vec![1.0; nv], vec![0.0; nv], vec![Vec3::y(); nv]);
        // e changes by `change` across every rung, crossing zero in its middle; the other
        // family's e is `other` plus noise of standard deviation `noise`, one value per four
        // rungs (correlated over more than an edge, as the fit's and the smoothing's is).
        let strength = |change: f64, other: f64, noise: f64| {
            let e: Vec<f64> = m.positions().iter().map(|p| (p.y - 0.5) * change).collect();
            let e_other: Vec<f64> = (0..nv)
                .map(|v| other + noise * crate::curvature::jet_fit::simulated_noise(v as u64 / 8))
                .collect();
            let fam = Family {
                e_other: &e_other,
                e_noise: noise,
                ..ridge_family(&k, &e, &zero, &dirs)
            };
            let mut line = along_the_rungs(&m, n);
            measure_line(&m, &fam, &mut line);
            line.strength
        };
        let clean = strength(2.0, 1.0, 0.0);
        // C = hypot(1, 1) at every point.
        let length = f64::from(n);
        assert!((clean - length * length * 2f64.sqrt()).abs() < 1e-6 * clean);
        let noisy = strength(2.0, 1.0, 1.0);
        assert!((noisy / clean - 1.0).abs() < 0.1, "{noisy} against {clean}");
        let alone = strength(0.02, 0.0, 1.0);
        assert!(alone < 0.2 * clean, "{alone} against {clean}");
    }

    /// A strip of quads along x; segments cross the strip's rungs to form one line.
    #[test]
    fn segments_chain_into_one_line_and_loops_stay_closed() {
        let n = 6;
        let m = crate::shapes::quad_strip(n);
        let nv = m.num_vertices();
        // e = y - 0.5 with directions along y: zero line y = 0.5, crossing the rungs and diagonals.
        let e: Vec<f64> = m.positions().iter().map(|p| p.y - 0.5).collect();
        let dirs = vec![Vec3::y(); nv];
        let k = vec![1.0; nv];
        let zero = vec![0.0; nv];
        let fam = ridge_family(&k, &e, &zero, &dirs);
        let mut segs = FamilySegments {
            regular: vec![true; m.num_faces()],
            ..Default::default()
        };
        for f in 0..m.num_faces() as u32 {
            let fe = m.topology().face_edges(f);
            let t = m.faces()[f as usize];
            let crossed: Vec<Node> = (0..3)
                .filter(|&s| fam.crossing(t[s], t[(s + 1) % 3]).is_some())
                .map(|s| Node::Edge(fe[s]))
                .collect();
            segs.segments.push([crossed[0], crossed[1]]);
            segs.segment_faces.push(f);
        }
        let lines = assemble_lines(&m, &fam, &segs);
        assert_eq!(lines.len(), 1);
        let line = &lines[0];
        assert!(!line.closed);
        assert!((line.length - n as f64).abs() < 1e-9, "{}", line.length);
        assert!(line.points.iter().all(|p| (p.y - 0.5).abs() < 1e-9));
        assert!((line.curvature_integral - n as f64).abs() < 1e-9);
        // YBS interpolate C linearly between the edge's end vertices, where C = |e| = 0.5, so
        // C = 0.5 along the line and T = length · ∫C ds = 6 · 3.
        assert!((line.strength - 18.0).abs() < 1e-9, "{}", line.strength);
    }
}
