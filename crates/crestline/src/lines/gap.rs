//! Gap jumping (YBS 2005, "Tracing and Thresholding Crest Lines", Fig. 4).
//!
//! Edge-based tracing leaves close, disconnected pieces of one crest line. In every vertex
//! star that contains end points of two lines of the same kind, the two ends are joined when
//! - `α ≤ π/3`: the angle between the first line's end segment (pointing out of the line) and
//!   the connecting segment,
//! - `β ≤ π/3`: the same at the second end, against the reversed connecting segment,
//! - `γ ≤ π/2`: the angle between the first end segment and the reversed second end segment
//!   (the two lines head towards each other).
//!
//! Candidate pairs are joined greedily, shortest gap first, each end at most once. A point on
//! an edge belongs to the stars of the vertices of the faces around that edge.
//!
//! Two cases the paper's figure does not show, decided here:
//! - **The two ends of one line** (of a chain of lines already joined) are a candidate pair like
//!   any other: joining them closes the line. A closed crest line broken once (the equator of
//!   an ellipsoid, the rim of a cap) would otherwise stay open.
//! - **Coincident ends** (a zero gap, e.g. two pieces ending at the same point of a
//!   triangle) have no connecting segment, so α and β are undefined; they are joined when
//!   `γ ≤ π/2` alone holds.

use std::collections::HashMap;

use crate::mesh::{TriMesh, Vec3};
use crate::slices::union_find_root;

use super::assemble::measure_line;
use super::trace::Family;
use super::{FeatureLine, SurfacePoint};

/// Angle limits of gap jumping; YBS's values are the default.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GapJumping {
    /// Largest α and β, radians. Default: π/3.
    pub max_end_angle: f64,
    /// Largest γ, radians. Default: π/2.
    pub max_turn_angle: f64,
}

impl Default for GapJumping {
    fn default() -> Self {
        GapJumping {
            max_end_angle: std::f64::consts::FRAC_PI_3,
            max_turn_angle: std::f64::consts::FRAC_PI_2,
        }
    }
}

/// One end of a line: the line, which end, the end point and the outward end direction.
#[derive(Debug, Clone, Copy)]
struct End {
    line: usize,
    point: Vec3,
    outward: Vec3,
}

/// Joins line pieces of `family`'s kind across small gaps; returns the number of joins.
/// `lines` must hold lines of one kind with surface locations.
pub fn jump_gaps(
    mesh: &TriMesh,
    family: &Family<'_>,
    lines: &mut Vec<FeatureLine>,
    options: &GapJumping,
) -> usize {
    let (ends, stars) = open_ends(mesh, lines);
    let candidates = rank_joins(lines, &ends, &stars, options);

    // Union of lines as chains: join greedily, keeping track of which line each original
    // line has been merged into and where its ends now are.
    let mut used_end = vec![false; ends.len()];
    let mut owner: Vec<usize> = (0..lines.len()).collect();
    let mut alive = vec![true; lines.len()];
    let mut joins = 0;
    for (_, _, i, j) in candidates {
        if used_end[i] || used_end[j] {
            continue;
        }
        let (a, b) = (ends[i], ends[j]);
        let (la, lb) = (
            union_find_root(&mut owner, a.line),
            union_find_root(&mut owner, b.line),
        );
        if la == lb {
            // Both ends are unused, so they are the two ends of this chain: close it.
            let line = &mut lines[la];
            if line.points.len() >= 3 {
                if line.points.first() == line.points.last() {
                    line.points.pop();
                    line.locations.pop();
                }
                line.closed = true;
                measure_line(mesh, family, line);
                used_end[i] = true;
                used_end[j] = true;
                joins += 1;
            }
            continue;
        }
        let placeholder = empty_like(&lines[la]);
        let first = std::mem::replace(&mut lines[la], placeholder.clone());
        let second = std::mem::replace(&mut lines[lb], placeholder);
        let mut joined = concatenate(first, second, &a, &b);
        measure_line(mesh, family, &mut joined);
        lines[la] = joined;
        alive[lb] = false;
        owner[lb] = la;
        used_end[i] = true;
        used_end[j] = true;
        joins += 1;
    }
    let mut k = 0;
    lines.retain(|_| {
        k += 1;
        alive[k - 1]
    });
    joins
}

/// The open ends of the lines (both ends of every open line with surface locations), and per
/// vertex the ends that lie on it or on an edge or face around it: ends near one another
/// share a vertex.
fn open_ends(mesh: &TriMesh, lines: &[FeatureLine]) -> (Vec<End>, HashMap<u32, Vec<usize>>) {
    let topo = mesh.topology();
    let faces = mesh.faces();
    let mut ends: Vec<End> = Vec::new();
    let mut stars: HashMap<u32, Vec<usize>> = HashMap::new();
    for (i, line) in lines.iter().enumerate() {
        let n = line.points.len();
        if line.closed || n < 2 || line.locations.len() != n {
            continue;
        }
        for at_start in [true, false] {
            let (end, inner) = if at_start { (0, 1) } else { (n - 1, n - 2) };
            let Some(outward) = (line.points[end] - line.points[inner]).try_normalize(0.0) else {
                continue;
            };
            let id = ends.len();
            ends.push(End {
                line: i,
                point: line.points[end],
                outward,
            });
            let mut vertices: Vec<u32> = match line.locations[end] {
                SurfacePoint::Edge { edge, .. } => topo
                    .edge_faces(edge)
                    .iter()
                    .flat_map(|&f| faces[f as usize])
                    .collect(),
                SurfacePoint::Face { face } => faces[face as usize].to_vec(),
                SurfacePoint::Vertex(v) => vec![v],
            };
            vertices.sort_unstable();
            vertices.dedup();
            for v in vertices {
                stars.entry(v).or_default().push(id);
            }
        }
    }
    (ends, stars)
}

/// The pairs of ends that pass the angle test, as (gap, γ, end, end): shortest gap first,
/// the straighter continuation on ties (several lines ending at one junction point).
fn rank_joins(
    lines: &[FeatureLine],
    ends: &[End],
    stars: &HashMap<u32, Vec<usize>>,
    options: &GapJumping,
) -> Vec<(f64, f64, usize, usize)> {
    let mut candidates: Vec<(f64, f64, usize, usize)> = Vec::new();
    let mut star_keys: Vec<&u32> = stars.keys().collect();
    star_keys.sort_unstable();
    for v in star_keys {
        let members = &stars[v];
        for (x, &i) in members.iter().enumerate() {
            for &j in &members[x + 1..] {
                let (a, b) = (ends[i], ends[j]);
                if a.line == b.line && lines[a.line].points.len() < 3 {
                    // Closing a single segment would give a degenerate loop.
                    continue;
                }
                if let Some(gamma) = join_angle(&a, &b, options) {
                    candidates.push(((b.point - a.point).norm(), gamma, i.min(j), i.max(j)));
                }
            }
        }
    }
    candidates.sort_by(|x, y| x.partial_cmp(y).unwrap_or(std::cmp::Ordering::Equal));
    candidates.dedup();
    candidates
}

/// `first` then `second`, oriented so that `first` ends at end `a` and `second` starts at
/// end `b`; not yet measured.
fn concatenate(mut first: FeatureLine, mut second: FeatureLine, a: &End, b: &End) -> FeatureLine {
    if first.points.first() == Some(&a.point) && first.points.last() != Some(&a.point) {
        first.points.reverse();
        first.locations.reverse();
    }
    if second.points.last() == Some(&b.point) && second.points.first() != Some(&b.point) {
        second.points.reverse();
        second.locations.reverse();
    }
    // Coincident ends: keep one copy of the shared point.
    let skip = usize::from(first.points.last() == second.points.first());
    first.points.extend(second.points.into_iter().skip(skip));
    first
        .locations
        .extend(second.locations.into_iter().skip(skip));
    first
}

/// YBS's angle test (Fig. 4) for joining end `a` to end `b`: `Some(γ)` when it passes.
/// Coincident ends only need the two lines to head towards each other (γ).
fn join_angle(a: &End, b: &End, options: &GapJumping) -> Option<f64> {
    let angle = |u: Vec3, w: Vec3| u.dot(&w).clamp(-1.0, 1.0).acos();
    let gamma = angle(a.outward, -b.outward);
    let ends_ok = match (b.point - a.point).try_normalize(0.0) {
        Some(c) => {
            angle(a.outward, c) <= options.max_end_angle
                && angle(b.outward, -c) <= options.max_end_angle
        }
        None => true,
    };
    (ends_ok && gamma <= options.max_turn_angle).then_some(gamma)
}

fn empty_like(line: &FeatureLine) -> FeatureLine {
    FeatureLine::new(line.kind, Vec::new(), false)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lines::LineKind;
    use crate::shapes;

    /// A flat 6 × 3 grid of unit cells with zero fields: only the line geometry matters.
    struct Grid {
        mesh: TriMesh,
        zero: Vec<f64>,
        dirs: Vec<Vec3>,
    }

    impl Grid {
        fn new() -> Self {
            let mesh = shapes::height_field(|_, _| 0.0, [0.0, 6.0], [0.0, 3.0], 6, 3);
            let n = mesh.num_vertices();
            Grid {
                mesh,
                zero: vec![0.0; n],
                dirs: vec![Vec3::x(); n],
            }
        }

        /// The face containing (x, y).
        fn locate(&self, x: f64, y: f64) -> SurfacePoint {
            let inside = |f: usize| {
                let [a, b, c] = self.mesh.triangle(f);
                let side = |p: Vec3, q: Vec3| (q.x - p.x) * (y - p.y) - (q.y - p.y) * (x - p.x);
                let s = [side(a, b), side(b, c), side(c, a)];
                s.iter().all(|&v| v >= 0.0) || s.iter().all(|&v| v <= 0.0)
            };
            let face = (0..self.mesh.num_faces()).find(|&f| inside(f)).unwrap() as u32;
            SurfacePoint::Face { face }
        }

        fn line(&self, pts: &[(f64, f64)]) -> FeatureLine {
            FeatureLine {
                locations: pts.iter().map(|&(x, y)| self.locate(x, y)).collect(),
                length: 0.0,
                ..FeatureLine::new(
                    LineKind::Ridge,
                    pts.iter().map(|&(x, y)| Vec3::new(x, y, 0.0)).collect(),
                    false,
                )
            }
        }

        fn jump(&self, lines: &mut Vec<FeatureLine>, options: &GapJumping) -> usize {
            let family = Family {
                kind: LineKind::Ridge,
                k: &self.zero,
                k_other: &self.zero,
                e: &self.zero,
                e_other: &self.zero,
                dirs: &self.dirs,
                e_noise: 0.0,
                e_alternative: &[],
            };
            jump_gaps(&self.mesh, &family, lines, options)
        }
    }

    const ANY_ANGLE: GapJumping = GapJumping {
        max_end_angle: std::f64::consts::PI,
        max_turn_angle: std::f64::consts::PI,
    };

    #[test]
    fn joins_broken_pieces_but_not_sharp_corners() {
        let g = Grid::new();
        let ybs = GapJumping::default();
        // Two collinear pieces with a gap inside one cell: joined into one line.
        let mut lines = vec![
            g.line(&[(0.3, 1.5), (1.3, 1.5), (2.2, 1.5)]),
            g.line(&[(4.8, 1.5), (3.8, 1.5), (2.8, 1.5)]),
        ];
        assert_eq!(g.jump(&mut lines, &ybs), 1);
        assert_eq!(lines.len(), 1);
        assert_eq!(lines[0].points.len(), 6);
        assert!((lines[0].length - 4.5).abs() < 1e-12);
        let xs: Vec<f64> = lines[0].points.iter().map(|p| p.x).collect();
        assert!(xs.windows(2).all(|w| w[1] > w[0]), "{xs:?}");

        // A piece meeting the first at a right angle: not joined.
        let mut lines = vec![
            g.line(&[(0.3, 1.5), (1.3, 1.5), (2.2, 1.5)]),
            g.line(&[(2.8, 2.8), (2.8, 2.2), (2.8, 1.6)]),
        ];
        assert_eq!(g.jump(&mut lines, &ybs), 0);
        assert_eq!(lines.len(), 2);

        // A piece coming back at a sharp angle (the lines turn by ~150°): not joined, although
        // the ends are close enough (any angle joins them; the far ends share a star too, so
        // the V is then also closed into a loop).
        let v_shape = || {
            vec![
                g.line(&[(0.3, 1.5), (1.3, 1.5), (2.2, 1.5)]),
                g.line(&[(0.5, 2.8), (1.6, 2.2), (2.7, 1.6)]),
            ]
        };
        let mut lines = v_shape();
        assert_eq!(g.jump(&mut lines, &ybs), 0);
        let mut lines = v_shape();
        assert!(g.jump(&mut lines, &ANY_ANGLE) >= 1);
        assert_eq!(lines.len(), 1);

        // A gentle bend (~30°) is one line continuing: joined.
        let mut lines = vec![
            g.line(&[(0.3, 1.5), (1.3, 1.5), (2.2, 1.5)]),
            g.line(&[(4.6, 2.5), (3.7, 2.0), (2.8, 1.5)]),
        ];
        assert_eq!(g.jump(&mut lines, &ybs), 1);

        // Collinear but too far apart (no common vertex star): not joined.
        let mut lines = vec![
            g.line(&[(0.3, 1.5), (1.3, 1.5)]),
            g.line(&[(3.5, 1.5), (4.5, 1.5)]),
        ];
        assert_eq!(g.jump(&mut lines, &ANY_ANGLE), 0);
    }

    #[test]
    fn closes_a_loop_broken_once() {
        let g = Grid::new();
        let pts = [
            (2.0, 0.5),
            (5.5, 0.5),
            (5.5, 2.5),
            (0.5, 2.5),
            (0.5, 0.5),
            (1.4, 0.5),
        ];
        let mut lines = vec![g.line(&pts)];
        assert_eq!(g.jump(&mut lines, &GapJumping::default()), 1);
        assert_eq!(lines.len(), 1);
        assert!(lines[0].closed);
        assert_eq!(lines[0].points.len(), pts.len());
        assert!(
            (lines[0].length - 14.0).abs() < 1e-12,
            "{}",
            lines[0].length
        );
        // A closed line has no ends left to join.
        assert_eq!(g.jump(&mut lines, &GapJumping::default()), 0);
    }

    #[test]
    fn at_a_junction_joins_the_straight_continuation() {
        let g = Grid::new();
        // Three lines ending at one point (a three-crest triangle's junction): the branch from
        // above turns by 90° against either of the other two, which continue each other.
        let mut lines = vec![
            g.line(&[(3.0, 2.8), (3.0, 1.5)]),
            g.line(&[(0.3, 1.5), (1.4, 1.5), (3.0, 1.5)]),
            g.line(&[(5.6, 1.5), (4.1, 1.5), (3.0, 1.5)]),
        ];
        assert_eq!(g.jump(&mut lines, &GapJumping::default()), 1);
        assert_eq!(lines.len(), 2);
        let straight = lines.iter().find(|l| l.points.len() == 5).unwrap();
        assert!(straight.points.iter().all(|p| p.y == 1.5));
        assert!((straight.length - 5.3).abs() < 1e-12, "{}", straight.length);
    }
}
