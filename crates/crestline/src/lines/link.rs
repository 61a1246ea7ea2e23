//! Linking salient feature points into lines (Mao, Wang, Zhou, sec. 4.4).
//!
//! **Feature points** are the crest points of sec. 4.1, the points where eq. (1) or (2) holds
//! ("we can extract ridges and valleys by equation (1) and (2)"), that the saliency of sec. 4.2
//! then sorts into feature and non-feature points ("to reduce the false feature points"). A
//! crest point lies on a mesh edge ([`super::trace_edges::is_crest_edge`]: the extremality
//! changes sign, the crossing is a maximum of `k_max` or a minimum of `k_min`, and the
//! curvature condition holds); it is carried by the nearer end of its edge, which takes the
//! point's position and kind. Vertices with saliency above the threshold `T` of that kind
//! ([`crate::saliency::family`]: the paper's knee, or the family's own where it is lower) that
//! carry a crest point are feature points (`M1`), those with saliency in `(0.8 T, T]` weak
//! feature points (`M2`); only points of one kind are linked. (Reading every vertex above `T`
//! as a feature point instead turns the bands of high saliency around a crest into wandering
//! chains: mean F1 0.29 on the public quality cases against the crest lines.)
//!
//! For a feature point `p`, looking at its one-ring:
//! 1. exactly one feature neighbour `q`: link `p–q`;
//! 2. several: link the one whose step `pq` is best aligned with the line direction (the
//!    principal direction *along* the crest: `dir_min` on ridges, `dir_max` on valleys —
//!    our reading of "the smaller dihedral angle with the orientation of the principal
//!    curvature");
//! 3. none, but a weak neighbour `q` that itself touches a feature point `k` outside the
//!    one-ring of `p`: link `p–q` (best aligned as above) and promote `q` to a feature point.
//!
//! and repeat until nothing changes. One extension, documented here because it differs from
//! the paper's text: the rules are applied on *each side* of `p` (ahead of and behind it
//! along the line direction), linking the best-aligned feature neighbour on each side, or a
//! weak bridge on a side that has none. With a single link per point a chain breaks wherever
//! two neighbours both pick away from each other, and a gap of one weak point in the middle
//! of a crease is never bridged (the chain ends there have one feature neighbour each, so
//! rule 3 never applies); per side, both stay whole. The links are then split into
//! polylines at ends and junctions.
//!
//! **Whole lines** (our extension, [`LinkOptions::extend`], on by default). Saliency is high
//! where the curvature is large or changes, which along one crest line is only part of it:
//! the threshold keeps the salient stretch of a line, not the line. Before linking, the
//! feature points grow along their lines: a crest point of the same kind in the one-ring of a
//! feature point, in a direction within 60° of the line direction there, becomes a feature
//! point too, whatever its saliency. (60°: on a regular triangulation the neighbours are 60°
//! apart, so a line always has a continuation on each side; a branch across the line, at
//! 90°, never qualifies.) A line is thus kept whole when any part of it is salient, and
//! nothing grows from crest points that no salient line reaches. Measured on the public
//! quality cases (`bench/quality/run.sh`, jet-fit curvature): mean F1 0.68 with the paper's
//! rules alone, 0.90 with whole lines; the torus gets no line either way.
//!
//! A feature point stands at its crest point: the linking rules above measure directions
//! between crest points. The growth takes a crest point when the edge between the two
//! carrying vertices is within 60° of the line (as above) or, since 2026-11-28, when the two
//! crest points lie on edges of one triangle (the zero set of the extremality runs through it
//! from one to the other) and the step between them is: where a line crosses the triangles
//! at an angle (diagonally over a regular grid, over irregular triangles) the carriers lie on
//! either side of it and their edge can turn from it by more than 60°, and the lines were
//! kept in their salient stretches there. Measured (`score.py --method saliency`,
//! BENCHMARKS.md "Saliency lines grown between crest points"): public cases mean F1 0.930 →
//! 0.948, six height fields not in `../shared` 0.761 → 0.780, 48 noisy surfaces 0.834 →
//! 0.862; the CAD parts unchanged (0.999). Growing between any crest points gained twice as
//! much but grew rows of crest points along a cylinder from its tangent join with a dome
//! (`dome_cap-uniform` 1.000 → 0.934).
//!
//! **Strength** (our extension, [`LinkOptions::min_strength`]). Saliency does not tell a crest
//! line from the crest points that noise in the extremalities leaves on a surface whose
//! extremalities vanish (cylinders, spheres, planes: the cyclides), and where such a surface
//! is the salient part of a shape (the barrel of a shaft next to its flat ends) it fills with
//! short chains. The lines' strength T of YBS, with the floor the other methods use, removes
//! them. The length in it is that of the line's *stroke*, not of the polyline, since the
//! linking splits a line into polylines at every junction, and T, which grows with the
//! square of the length, would then fall below the floor on the pieces of a true line. A
//! stroke joins polylines that continue each other through a junction (within 60°, the
//! straightest pairs first) and the short polylines around a triangle of crest points; a
//! branch is a stroke of its own. The cyclideness is the polyline's own, so that weak pieces
//! joined to a strong line go. (Measured with `score_cad.py` on the public CAD parts and
//! `score.py` on the quality cases, mean F1: no floor 0.81 / 0.897; the floor with the
//! length of the whole network of joined lines 0.985 / 0.892, but noise crest points on a
//! cone link into one web of 27 diagonals, which then passes; with strokes 0.997 / 0.891.)

use super::filter::HPW_DEFAULT_THRESHOLD;
use crate::curvature::Curvature;
use crate::mesh::{TriMesh, Vec3};
use crate::slices::union_find_root;

use rayon::prelude::*;

use super::assemble::{chain_links, measure_line};
use super::trace::Family;
use super::trace_edges::is_crest_edge;
use super::{FeatureLine, FeatureLines, LineKind, SurfacePoint};

/// Options of [`link_feature_points`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinkOptions {
    /// Weak feature points have saliency in `(weak_fraction · T, T]`. Default: 0.8.
    pub weak_fraction: f64,
    /// Extend salient lines along the crest points that continue them, whatever their
    /// saliency (see the module docs, *Whole lines*). Default: true; false is the paper's
    /// rules alone.
    pub extend: bool,
    /// Lines are kept when the stroke they belong to has strength `T` (YBS eq. 5, over the
    /// whole stroke) of at least this (see the module docs, *Strength*). Default:
    /// [`HPW_DEFAULT_THRESHOLD`], the noise floor of the other methods.
    pub min_strength: f64,
}

impl Default for LinkOptions {
    fn default() -> Self {
        LinkOptions {
            weak_fraction: 0.8,
            extend: true,
            min_strength: HPW_DEFAULT_THRESHOLD,
        }
    }
}

/// A crest point carried by a vertex: its kind, where it lies and its distance from the vertex.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CrestPoint {
    /// Ridge (eq. 1) or valley (eq. 2).
    pub kind: LineKind,
    /// The zero crossing of the extremality on the edge.
    pub location: SurfacePoint,
    /// Its position.
    pub position: Vec3,
    /// Its distance from the vertex that carries it.
    pub distance: f64,
}

/// Per vertex, the nearest crest point on its edges that it is the nearer end of (`None`:
/// the vertex carries no crest point).
pub fn crest_points(mesh: &TriMesh, curvature: &Curvature) -> Vec<Option<CrestPoint>> {
    let topo = mesh.topology();
    let found: Vec<(u32, CrestPoint)> = (0..topo.num_edges() as u32)
        .into_par_iter()
        .flat_map_iter(|e| {
            [LineKind::Ridge, LineKind::Valley]
                .into_iter()
                .filter_map(move |kind| {
                    let family = Family::of(curvature, kind);
                    if !is_crest_edge(mesh, &family, e) {
                        return None;
                    }
                    let [a, b] = topo.edge(e);
                    let t = family.crossing(a, b)?;
                    let (pa, pb) = (mesh.position(a), mesh.position(b));
                    let (carrier, distance) = if t <= 0.5 {
                        (a, t * (pb - pa).norm())
                    } else {
                        (b, (1.0 - t) * (pb - pa).norm())
                    };
                    let point = CrestPoint {
                        kind,
                        location: SurfacePoint::Edge { edge: e, t },
                        position: pa + (pb - pa) * t,
                        distance,
                    };
                    Some((carrier, point))
                })
        })
        .collect();
    let mut nearest: Vec<Option<CrestPoint>> = vec![None; mesh.num_vertices()];
    for (v, point) in found {
        let slot = &mut nearest[v as usize];
        if slot.is_none_or(|old| point.distance < old.distance) {
            *slot = Some(point);
        }
    }
    nearest
}

/// Links the crest points ([`crest_points`]) whose vertices' `saliency` exceeds the threshold
/// of their kind (`threshold(kind)`) into feature lines.
pub fn link_feature_points(
    mesh: &TriMesh,
    curvature: &Curvature,
    saliency: &[f64],
    threshold: impl Fn(LineKind) -> f64,
    options: &LinkOptions,
) -> FeatureLines {
    let n = mesh.num_vertices();
    let crest = crest_points(mesh, curvature);
    let threshold = |v: usize| crest[v].map(|c| threshold(c.kind));
    let mut feature: Vec<bool> = (0..n)
        .map(|v| threshold(v).is_some_and(|t| saliency[v] > t))
        .collect();
    let weak: Vec<bool> = (0..n)
        .map(|v| {
            threshold(v)
                .is_some_and(|t| saliency[v] > options.weak_fraction * t && saliency[v] <= t)
        })
        .collect();
    // Only crest vertices are ever linked; the others' kind is never read.
    let kind: Vec<LineKind> = crest
        .iter()
        .map(|c| c.map_or(LineKind::Ridge, |c| c.kind))
        .collect();
    let graph = CrestGraph {
        mesh,
        curvature,
        crest: &crest,
        kind: &kind,
    };
    if options.extend {
        graph.extend_features(&mut feature);
    }
    let links = graph.link_neighbours(&mut feature, &weak);
    let paths: Vec<(Vec<usize>, bool)> = chain_links(n, &links)
        .into_iter()
        .filter(|(path, _)| path.len() >= 2)
        .collect();
    let lines: Vec<FeatureLine> = paths.iter().map(|path| graph.line_of(path)).collect();
    let keep = strong_strokes(&paths, &lines, options.min_strength);
    FeatureLines {
        lines: lines
            .into_iter()
            .zip(keep)
            .filter_map(|(line, keep)| keep.then_some(line))
            .collect(),
    }
}

/// The crest points of a mesh with their kinds, and the steps of [`link_feature_points`]
/// that walk between them.
struct CrestGraph<'a> {
    mesh: &'a TriMesh,
    curvature: &'a Curvature,
    crest: &'a [Option<CrestPoint>],
    kind: &'a [LineKind],
}

impl CrestGraph<'_> {
    /// The line direction at crest vertex `v`: the principal direction along a ridge or valley.
    fn along(&self, v: usize) -> Vec3 {
        match self.kind[v] {
            LineKind::Ridge => self.curvature.dir_min[v],
            LineKind::Valley => self.curvature.dir_max[v],
        }
    }

    /// Alignment with the line direction at p of the step from p's crest point to q's (the
    /// feature points stand at their crest points, module docs): signed cosine. A vertex of
    /// the ring that carries none (the linking filters such out) counts at its own position.
    fn alignment(&self, p: usize, q: usize) -> f64 {
        let at = |v: usize| self.crest[v].map_or(self.mesh.positions()[v], |c| c.position);
        self.step_alignment(p, at(p), at(q))
    }

    /// Alignment of edge p→q with the line direction at p: signed cosine.
    fn edge_alignment(&self, p: usize, q: usize) -> f64 {
        let positions = self.mesh.positions();
        self.step_alignment(p, positions[p], positions[q])
    }

    fn step_alignment(&self, p: usize, from: Vec3, to: Vec3) -> f64 {
        (to - from)
            .try_normalize(0.0)
            .map_or(0.0, |d| d.dot(&self.along(p)))
    }

    /// Whether the crest points of p and q lie on edges of one triangle: the zero set of the
    /// extremality runs through it from one to the other.
    fn in_one_triangle(&self, p: usize, q: usize) -> bool {
        let topo = self.mesh.topology();
        let edge = |v: usize| match self.crest[v].map(|c| c.location) {
            Some(SurfacePoint::Edge { edge, .. }) => Some(edge),
            _ => None,
        };
        let (Some(a), Some(b)) = (edge(p), edge(q)) else {
            return false;
        };
        a == b
            || topo
                .edge_faces(a)
                .iter()
                .any(|f| topo.edge_faces(b).contains(f))
    }

    /// The candidate best aligned with the line direction at `p`.
    fn best(&self, p: usize, candidates: &mut dyn Iterator<Item = usize>) -> Option<usize> {
        candidates.max_by(|&a, &b| {
            self.alignment(p, a)
                .abs()
                .total_cmp(&self.alignment(p, b).abs())
        })
    }

    /// Whole crest lines: a salient line goes on through crest points of its kind that
    /// continue it (within 60 degrees of its direction: along the edge between the carriers,
    /// or between crest points in one triangle), whatever their saliency.
    fn extend_features(&self, feature: &mut [bool]) {
        let topo = self.mesh.topology();
        let mut stack: Vec<usize> = (0..feature.len()).filter(|&v| feature[v]).collect();
        while let Some(p) = stack.pop() {
            for q in topo.neighbors(p as u32) {
                let q = q as usize;
                if !feature[q]
                    && self.crest[q].is_some_and(|c| c.kind == self.kind[p])
                    && (self.edge_alignment(p, q).abs() > 0.5
                        || (self.alignment(p, q).abs() > 0.5 && self.in_one_triangle(p, q)))
                {
                    feature[q] = true;
                    stack.push(q);
                }
            }
        }
    }

    /// Links every feature point to its best aligned feature neighbour ahead and behind;
    /// where none, a weak neighbour that bridges to a further feature point is promoted to
    /// a feature point, and the pass repeats until no point is promoted.
    fn link_neighbours(&self, feature: &mut [bool], weak: &[bool]) -> Vec<(usize, usize)> {
        let topo = self.mesh.topology();
        let kind = self.kind;
        let n = feature.len();
        let mut links: Vec<(usize, usize)> = Vec::new();
        let mut linked = vec![false; n];
        loop {
            let mut promoted = false;
            for p in 0..n {
                if !feature[p] || linked[p] {
                    continue;
                }
                let ring: Vec<usize> = topo.neighbors(p as u32).map(|q| q as usize).collect();
                for ahead in [true, false] {
                    let on_side = |q: &usize| (self.alignment(p, *q) >= 0.0) == ahead;
                    let strong = self.best(
                        p,
                        &mut ring
                            .iter()
                            .copied()
                            .filter(on_side)
                            .filter(|&q| feature[q] && kind[q] == kind[p]),
                    );
                    let chosen = strong.or_else(|| {
                        let bridge = self.best(
                            p,
                            &mut ring
                                .iter()
                                .copied()
                                .filter(on_side)
                                .filter(|&q| weak[q] && !feature[q] && kind[q] == kind[p])
                                .filter(|&q| {
                                    topo.neighbors(q as u32).any(|k| {
                                        let k = k as usize;
                                        k != p
                                            && feature[k]
                                            && kind[k] == kind[p]
                                            && !ring.contains(&k)
                                    })
                                }),
                        );
                        if let Some(q) = bridge {
                            feature[q] = true;
                            promoted = true;
                        }
                        bridge
                    });
                    if let Some(q) = chosen {
                        links.push((p, q));
                        linked[p] = true;
                    }
                }
            }
            if !promoted {
                break;
            }
        }
        links
    }

    /// The measured feature line through the crest points of a chained path.
    fn line_of(&self, (path, closed): &(Vec<usize>, bool)) -> FeatureLine {
        let line_kind = self.kind[path[0]];
        let family = Family::of(self.curvature, line_kind);
        let crests = || path.iter().filter_map(|&v| self.crest[v]);
        let mut line = FeatureLine {
            locations: crests().map(|c| c.location).collect(),
            ..FeatureLine::new(line_kind, crests().map(|c| c.position).collect(), *closed)
        };
        measure_line(self.mesh, &family, &mut line);
        line
    }
}

/// Per line: whether the stroke it belongs to, as strong per length as this line, has
/// strength `T = L · ∫C ds` of at least `min_strength`: `L_stroke² · (∫C ds / L)_line ≥
/// min_strength`. A stroke is a chain of lines that continue each other through junctions
/// (see [`strokes`]); a weak piece on a strong stroke does not pass for the stroke's sake.
fn strong_strokes(
    paths: &[(Vec<usize>, bool)],
    lines: &[FeatureLine],
    min_strength: f64,
) -> Vec<bool> {
    let stroke = strokes(paths, lines);
    let mut length = vec![0.0; lines.len()];
    for (line, &s) in lines.iter().zip(&stroke) {
        length[s] += line.length;
    }
    lines
        .iter()
        .zip(&stroke)
        .map(|(line, &s)| {
            // T / L² of the line: its ∫C ds per length.
            let density = if line.length > 0.0 {
                line.strength / (line.length * line.length)
            } else {
                0.0
            };
            length[s] * length[s] * density >= min_strength
        })
        .collect()
}

/// The stroke of each line, as the index of one line of it: lines meeting at a point are
/// joined when one continues the other (their directions there within 60 degrees), the
/// straightest pairs first, each line end at most once. A crest line split by a branch is
/// one stroke again, and the branch another; a web of short links that turn at every
/// junction (crest points of noise, where the extremalities vanish in theory) stays in
/// short strokes instead of one network as long as all of it.
fn strokes(paths: &[(Vec<usize>, bool)], lines: &[FeatureLine]) -> Vec<usize> {
    // Open line ends: (vertex, line, outward direction).
    let mut ends: Vec<(usize, usize, Vec3)> = Vec::new();
    for (i, ((path, closed), line)) in paths.iter().zip(lines).enumerate() {
        let p = &line.points;
        if *closed || p.len() < 2 || p.len() != path.len() {
            continue;
        }
        // A few points in, so that one zigzag of the crossings does not set the direction.
        let k = 3.min(p.len() - 1);
        let last = p.len() - 1;
        ends.push((path[0], i, p[0] - p[k]));
        ends.push((path[last], i, p[last] - p[last - k]));
    }
    ends.sort_by_key(|e| (e.0, e.1));
    let mut parent: Vec<usize> = (0..lines.len()).collect();
    // Small loops are one stroke: where three crest points form a triangle, the per-side
    // linking leaves two or three short lines around it (p–q beside p–m–q).
    for (a, b) in small_loops(paths) {
        let (ra, rb) = (
            union_find_root(&mut parent, a),
            union_find_root(&mut parent, b),
        );
        parent[ra.max(rb)] = ra.min(rb);
    }
    for group in ends.chunk_by(|a, b| a.0 == b.0) {
        // Pairs of ends at this point, straightest continuation first.
        let mut pairs: Vec<(f64, usize, usize)> = Vec::new();
        for a in 0..group.len() {
            for b in a + 1..group.len() {
                let (da, db) = (group[a].2.try_normalize(0.0), group[b].2.try_normalize(0.0));
                if let (Some(da), Some(db)) = (da, db) {
                    let cos = da.dot(&db);
                    // Outward directions: a continuation points the opposite way.
                    if cos < -0.5 && group[a].1 != group[b].1 {
                        pairs.push((cos, a, b));
                    }
                }
            }
        }
        pairs.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)).then(x.2.cmp(&y.2)));
        let mut used = vec![false; group.len()];
        for (_, a, b) in pairs {
            if used[a] || used[b] {
                continue;
            }
            used[a] = true;
            used[b] = true;
            let (ra, rb) = (
                union_find_root(&mut parent, group[a].1),
                union_find_root(&mut parent, group[b].1),
            );
            parent[ra.max(rb)] = ra.min(rb);
        }
    }
    (0..lines.len())
        .map(|i| union_find_root(&mut parent, i))
        .collect()
}

/// Pairs of lines on one small loop: two lines between the same two points, or three lines
/// of at most three points each around a triangle of line ends.
fn small_loops(paths: &[(Vec<usize>, bool)]) -> Vec<(usize, usize)> {
    // (end, other end, line) for both directions of every open line.
    let mut incident: Vec<(usize, usize, usize)> = Vec::new();
    for (i, (path, closed)) in paths.iter().enumerate() {
        if !closed && path.len() >= 2 {
            let (a, b) = (path[0], path[path.len() - 1]);
            if a != b {
                incident.push((a, b, i));
                incident.push((b, a, i));
            }
        }
    }
    incident.sort_unstable();
    let around = |v: usize| {
        let from = incident.partition_point(|e| e.0 < v);
        let to = incident.partition_point(|e| e.0 <= v);
        &incident[from..to]
    };
    let short = |i: usize| paths[i].0.len() <= 3;
    let mut pairs = Vec::new();
    for w in incident.windows(2) {
        if w[0].0 == w[1].0 && w[0].1 == w[1].1 {
            pairs.push((w[0].2, w[1].2));
        }
    }
    for &(u, v, l1) in &incident {
        if !short(l1) {
            continue;
        }
        for &(_, w, l2) in around(u) {
            if w == v || l2 == l1 || !short(l2) {
                continue;
            }
            if let Some(&(_, _, l3)) = around(v).iter().find(|e| e.1 == w && short(e.2)) {
                pairs.push((l1, l2));
                pairs.push((l1, l3));
            }
        }
    }
    pairs
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes;

    fn line(points: &[[f64; 2]]) -> FeatureLine {
        let points: Vec<Vec3> = points.iter().map(|p| Vec3::new(p[0], p[1], 0.0)).collect();
        let mut line = FeatureLine {
            locations: vec![SurfacePoint::Vertex(0); points.len()],
            ..FeatureLine::new(LineKind::Ridge, points, false)
        };
        line.strength = line.length * line.length;
        line
    }

    #[test]
    fn a_line_split_by_a_branch_is_one_stroke_and_the_branch_another() {
        // Vertices 0..=2 along y = 0, 3..=5 on from the junction 2, 6..=7 up from it.
        let paths = vec![
            (vec![0, 1, 2], false),
            (vec![2, 3, 4, 5], false),
            (vec![2, 6, 7], false),
        ];
        let lines = vec![
            line(&[[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]]),
            line(&[[2.0, 0.0], [3.0, 0.1], [4.0, 0.0], [5.0, 0.0]]),
            line(&[[2.0, 0.0], [2.1, 1.0], [2.0, 2.0]]),
        ];
        let stroke = strokes(&paths, &lines);
        assert_eq!(stroke[0], stroke[1]);
        assert_ne!(stroke[0], stroke[2]);
        // Density 1 per length²: the stroke of length 5 passes T >= 20, the branch (2) not.
        assert_eq!(strong_strokes(&paths, &lines, 20.0), [true, true, false]);
    }

    #[test]
    fn a_small_loop_does_not_break_a_stroke() {
        // 0–1–2, then 2–3 directly and 2–4–3 around a triangle (4 is also where a short spur
        // 4–9 ends, so 2–4 and 4–3 are lines of their own), then 3–5–6. Without the loop rule
        // the straightest pairs at 2 and 3 take 2–3 and leave the loop's lines apart; with
        // a spur at 4 the loop would also end the stroke there.
        let paths = vec![
            (vec![0, 1, 2], false),
            (vec![2, 3], false),
            (vec![2, 4], false),
            (vec![4, 3], false),
            (vec![4, 9], false),
            (vec![3, 5, 6], false),
        ];
        let lines = vec![
            line(&[[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]]),
            line(&[[2.0, 0.0], [3.0, 0.0]]),
            line(&[[2.0, 0.0], [2.5, 0.4]]),
            line(&[[2.5, 0.4], [3.0, 0.0]]),
            line(&[[2.5, 0.4], [2.5, 1.0]]),
            line(&[[3.0, 0.0], [4.0, 0.0], [5.0, 0.0]]),
        ];
        let stroke = strokes(&paths, &lines);
        for i in [1, 2, 3, 5] {
            assert_eq!(stroke[i], stroke[0], "line {i}");
        }
    }

    #[test]
    fn a_web_of_turning_links_is_many_short_strokes() {
        // A zigzag whose links turn by 90 degrees at every point, each link its own line.
        let pts: Vec<[f64; 2]> = (0..20)
            .map(|i| {
                let (a, b) = ((i / 2) as f64, (i % 2) as f64);
                if (i / 2) % 2 == 0 {
                    [a + b, a]
                } else {
                    [a, a + b]
                }
            })
            .collect();
        let paths: Vec<(Vec<usize>, bool)> = (0..19).map(|i| (vec![i, i + 1], false)).collect();
        let lines: Vec<FeatureLine> = (0..19).map(|i| line(&[pts[i], pts[i + 1]])).collect();
        let stroke = strokes(&paths, &lines);
        let mut sizes = std::collections::HashMap::new();
        for s in &stroke {
            *sizes.entry(s).or_insert(0) += 1;
        }
        assert!(sizes.values().all(|&k| k <= 2), "{sizes:?}");
    }

    /// A flat grid with a synthetic ridge of high saliency along y = 0.1 (k_max > 0, e_max
    /// falling through zero along dir_max = y, line direction dir_min along x).
    #[test]
    fn links_a_crease_into_one_line_across_a_weak_gap() {
        let mesh = shapes::height_field(|_, _| 0.0, [-5.0, 5.0], [-2.0, 2.0], 20, 8);
        let n = mesh.num_vertices();
        let mut c = Curvature {
            k_max: vec![0.0; n],
            k_min: vec![0.0; n],
            dir_max: vec![Vec3::y(); n],
            dir_min: vec![Vec3::x(); n],
            e_max: vec![0.0; n],
            e_min: vec![0.0; n],
            normals: vec![Vec3::z(); n],
            fallback_vertices: 0,
            extremality_noise: 0.0,
            simulated_noise: Default::default(),
            alternative_extremalities: Default::default(),
            one_sided: Vec::new(),
            smoothing_drift: Default::default(),
            smoothing_drift_noise: Default::default(),
            jet_fit: None,
        };
        let mut saliency = vec![0.1; n];
        for (v, p) in mesh.positions().iter().enumerate() {
            c.e_max[v] = 0.1 - p.y;
            if p.y.abs() < 1e-9 {
                c.k_max[v] = 2.0;
                // One weak point in the middle of the crease.
                saliency[v] = if (p.x - 0.5).abs() < 1e-9 { 0.9 } else { 1.5 };
            }
        }
        let lines = link_feature_points(&mesh, &c, &saliency, |_| 1.0, &LinkOptions::default());
        assert_eq!(
            lines.lines.len(),
            1,
            "{:?}",
            lines
                .lines
                .iter()
                .map(|l| l.points.len())
                .collect::<Vec<_>>()
        );
        let line = &lines.lines[0];
        assert_eq!(line.kind, LineKind::Ridge);
        assert_eq!(line.points.len(), 21);
        assert!((line.length - 10.0).abs() < 1e-9);
        assert!(line.points.iter().all(|p| (p.y - 0.1).abs() < 1e-9));
        // k_max interpolated at the crossings, a fifth of the way to the next row (k = 0).
        assert!((line.curvature_integral - 16.0).abs() < 1e-9);
    }
}
