//! Linking salient feature points into lines (Mao, Wang, Zhou, sec. 4.4).
//!
//! Vertices with saliency above the threshold `T` are feature points (`M1`), those in
//! `(0.8 T, T]` weak feature points (`M2`); each is a ridge or a valley point by the sign of
//! its dominant (largest absolute) principal curvature, and only points of one kind are
//! linked. For a feature point `p`, looking at its one-ring:
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

use crate::curvature::Curvature;
use crate::mesh::{TriMesh, Vec3};

use super::assemble::{chain_links, measure_line};
use super::trace::Family;
use super::{FeatureLine, FeatureLines, LineKind, SurfacePoint};

/// Options of [`link_feature_points`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinkOptions {
    /// Weak feature points have saliency in `(weak_fraction · T, T]`. Default: 0.8.
    pub weak_fraction: f64,
}

impl Default for LinkOptions {
    fn default() -> Self {
        LinkOptions { weak_fraction: 0.8 }
    }
}

/// Ridge or valley by the sign of the dominant principal curvature.
fn point_kind(c: &Curvature, v: usize) -> LineKind {
    if c.k_max[v].abs() >= c.k_min[v].abs() {
        LineKind::Ridge
    } else {
        LineKind::Valley
    }
}

/// Links the vertices whose `saliency` exceeds `threshold` into feature lines.
pub fn link_feature_points(
    mesh: &TriMesh,
    curvature: &Curvature,
    saliency: &[f64],
    threshold: f64,
    options: &LinkOptions,
) -> FeatureLines {
    let topo = mesh.topology();
    let n = mesh.num_vertices();
    let referenced = |v: usize| !topo.vertex_faces(v as u32).is_empty();
    let mut feature: Vec<bool> = (0..n)
        .map(|v| referenced(v) && saliency[v] > threshold)
        .collect();
    let weak: Vec<bool> = (0..n)
        .map(|v| {
            referenced(v)
                && saliency[v] > options.weak_fraction * threshold
                && saliency[v] <= threshold
        })
        .collect();
    let kind: Vec<LineKind> = (0..n).map(|v| point_kind(curvature, v)).collect();
    let along = |v: usize| match kind[v] {
        LineKind::Ridge => curvature.dir_min[v],
        LineKind::Valley => curvature.dir_max[v],
    };
    // Alignment of edge p→q with the line direction at p: signed cosine.
    let alignment = |p: usize, q: usize| -> f64 {
        let d: Vec3 = mesh.positions()[q] - mesh.positions()[p];
        d.try_normalize(0.0).map_or(0.0, |d| d.dot(&along(p)))
    };
    let best = |p: usize, candidates: &mut dyn Iterator<Item = usize>| -> Option<usize> {
        candidates.max_by(|&a, &b| alignment(p, a).abs().total_cmp(&alignment(p, b).abs()))
    };

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
                let on_side = |q: &usize| (alignment(p, *q) >= 0.0) == ahead;
                let strong = best(
                    p,
                    &mut ring
                        .iter()
                        .copied()
                        .filter(on_side)
                        .filter(|&q| feature[q] && kind[q] == kind[p]),
                );
                let chosen = strong.or_else(|| {
                    let bridge = best(
                        p,
                        &mut ring
                            .iter()
                            .copied()
                            .filter(on_side)
                            .filter(|&q| weak[q] && !feature[q] && kind[q] == kind[p])
                            .filter(|&q| {
                                topo.neighbors(q as u32).any(|k| {
                                    let k = k as usize;
                                    k != p && feature[k] && kind[k] == kind[p] && !ring.contains(&k)
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

    let lines = chain_links(n, &links)
        .into_iter()
        .filter(|(path, _)| path.len() >= 2)
        .map(|(path, closed)| {
            let line_kind = kind[path[0]];
            let family = Family::of(curvature, line_kind);
            let mut line = FeatureLine {
                kind: line_kind,
                points: path.iter().map(|&v| mesh.positions()[v]).collect(),
                locations: path
                    .iter()
                    .map(|&v| SurfacePoint::Vertex(v as u32))
                    .collect(),
                closed,
                length: 0.0,
                curvature_integral: 0.0,
                strength: 0.0,
                crease: false,
            };
            measure_line(mesh, &family, &mut line);
            line
        })
        .collect();
    FeatureLines { lines }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes;

    /// A flat grid with a synthetic crease of high saliency along y = 0 (ridge: k_max > 0,
    /// line direction dir_min along x).
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
        assert!((line.curvature_integral - 20.0).abs() < 1e-9);
    }
}
