//! Linking salient feature points into lines (Mao, Wang, Zhou, sec. 4.4).
//!
//! **Feature points** are the crest points of sec. 4.1, the points where eq. (1) or (2) holds
//! ("we can extract ridges and valleys by equation (1) and (2)"), that the saliency of sec. 4.2
//! then sorts into feature and non-feature points ("to reduce the false feature points"). A
//! crest point lies on a mesh edge ([`super::trace_edges::is_crest_edge`]: the extremality
//! changes sign, the crossing is a maximum of `k_max` or a minimum of `k_min`, and the
//! curvature condition holds); it is carried by the nearer end of its edge, which takes the
//! point's position and kind. Vertices with saliency above the threshold `T` that carry a crest
//! point are feature points (`M1`), those with saliency in `(0.8 T, T]` weak feature points
//! (`M2`); only points of one kind are linked. (Reading every vertex above `T` as a feature
//! point instead turns the bands of high saliency around a crest into wandering chains: mean
//! F1 0.29 on the public quality cases against the crest lines.)
//!
//! For a feature point `p`, looking at its one-ring:
//! 1. exactly one feature neighbour `q`: link `p–q`;
//! 2. several: link the one whose edge `pq` is best aligned with the line direction (the
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
//! **Strength** (our extension, [`LinkOptions::min_strength`]). Saliency does not tell a crest
//! line from the crest points that noise in the extremalities leaves on a surface whose
//! extremalities vanish (cylinders, spheres, planes: the cyclides), and where such a surface
//! is the salient part of a shape (the barrel of a shaft next to its flat ends) it fills with
//! short chains. The lines' strength T of YBS, with the floor the other methods use, removes
//! them. The length in it is that of the network of joined lines, not of the polyline, since
//! the linking splits a line into polylines at every junction, and T, which grows with the
//! square of the length, would then fall below the floor on the pieces of a true line; the
//! cyclideness is the polyline's own, so that weak pieces joined to a strong line go
//! (measured on the public CAD parts, `score_cad.py`: mean F1 0.81 without, 0.98 with; on the
//! quality cases 0.897 without, 0.892 with).

use super::filter::HPW_DEFAULT_THRESHOLD;
use crate::curvature::Curvature;
use crate::mesh::{TriMesh, Vec3};

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
    /// Lines are kept when the network of lines they belong to has strength `T` (YBS eq. 5,
    /// over the whole network) of at least this (see the module docs, *Strength*). Default:
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

/// Links the crest points ([`crest_points`]) whose vertices' `saliency` exceeds `threshold`
/// into feature lines.
pub fn link_feature_points(
    mesh: &TriMesh,
    curvature: &Curvature,
    saliency: &[f64],
    threshold: f64,
    options: &LinkOptions,
) -> FeatureLines {
    let n = mesh.num_vertices();
    let crest = crest_points(mesh, curvature);
    let mut feature: Vec<bool> = (0..n)
        .map(|v| crest[v].is_some() && saliency[v] > threshold)
        .collect();
    let weak: Vec<bool> = (0..n)
        .map(|v| {
            crest[v].is_some()
                && saliency[v] > options.weak_fraction * threshold
                && saliency[v] <= threshold
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
    let keep = strong_networks(n, &paths, &lines, options.min_strength);
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

    /// Alignment of edge p→q with the line direction at p: signed cosine.
    fn alignment(&self, p: usize, q: usize) -> f64 {
        let d: Vec3 = self.mesh.positions()[q] - self.mesh.positions()[p];
        d.try_normalize(0.0).map_or(0.0, |d| d.dot(&self.along(p)))
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
    /// continue it (within 60 degrees of its direction), whatever their saliency.
    fn extend_features(&self, feature: &mut [bool]) {
        let topo = self.mesh.topology();
        let mut stack: Vec<usize> = (0..feature.len()).filter(|&v| feature[v]).collect();
        while let Some(p) = stack.pop() {
            for q in topo.neighbors(p as u32) {
                let q = q as usize;
                if !feature[q]
                    && self.crest[q].is_some_and(|c| c.kind == self.kind[p])
                    && self.alignment(p, q).abs() > 0.5
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
        let mut line = FeatureLine {
            kind: line_kind,
            points: path
                .iter()
                .filter_map(|&v| self.crest[v])
                .map(|c| c.position)
                .collect(),
            locations: path
                .iter()
                .filter_map(|&v| self.crest[v])
                .map(|c| c.location)
                .collect(),
            closed: *closed,
            length: 0.0,
            curvature_integral: 0.0,
            strength: 0.0,
            crease: false,
        };
        measure_line(self.mesh, &family, &mut line);
        line
    }
}

/// Per line: whether a network of lines as long as the one it belongs to (the lines joined
/// to it through shared points), all as strong per length as this line, would have strength
/// `T = L · ∫C ds` of at least `min_strength`: `L_network² · (∫C ds / L)_line ≥ min_strength`.
/// A network whose lines all pass has `T ≥ min_strength`; a weak piece hanging on a strong
/// network does not pass for the network's sake.
fn strong_networks(
    n: usize,
    paths: &[(Vec<usize>, bool)],
    lines: &[FeatureLine],
    min_strength: f64,
) -> Vec<bool> {
    // Union-find over vertices: lines meet only at their ends.
    let mut parent: Vec<usize> = (0..n).collect();
    fn root(parent: &mut [usize], mut v: usize) -> usize {
        while parent[v] != v {
            parent[v] = parent[parent[v]];
            v = parent[v];
        }
        v
    }
    for (path, _) in paths {
        let (a, b) = (
            root(&mut parent, path[0]),
            root(&mut parent, path[path.len() - 1]),
        );
        parent[a] = b;
    }
    let mut length = vec![0.0; n];
    let roots: Vec<usize> = paths
        .iter()
        .map(|(path, _)| root(&mut parent, path[0]))
        .collect();
    for (line, &r) in lines.iter().zip(&roots) {
        length[r] += line.length;
    }
    lines
        .iter()
        .zip(&roots)
        .map(|(line, &r)| {
            // T / L² of the line: its ∫C ds per length.
            let density = if line.length > 0.0 {
                line.strength / (line.length * line.length)
            } else {
                0.0
            };
            length[r] * length[r] * density >= min_strength
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes;

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
        let lines = link_feature_points(&mesh, &c, &saliency, 1.0, &LinkOptions::default());
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
