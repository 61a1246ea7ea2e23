//! One line set from crest lines and crease curves.
//!
//! A smooth-surface method sees a sharp crease as a band of extreme curvature one triangle
//! wide: its crest lines follow the crease approximately, double it (a ridge on each side),
//! wander off where the band is irregular and stop short of corners. The crease curves of
//! [`crate::lines::crease`] are exact there, so in the merged set:
//!
//! - the parts of crest lines within [`MergeOptions::tolerance`] of a crease curve are
//!   replaced by the crease curve (they are cut out of the crest lines);
//! - a crest line that ends near a crease (its own end, or where such a cut was made) is
//!   joined to the nearest point of the crease, when that point is within
//!   [`MergeOptions::join_distance`];
//! - crest lines are also cut where their position is interpolated from fields that do not
//!   describe the surface there: at a point on an edge or inside a triangle, every corner it is
//!   interpolated from that lies on a crease must have been estimated for that side of the
//!   crease ([`crate::mesh::widest_side`]), and one of them must be off the creases.
//!   In the fans of a CAD export, which have no vertex inside a face, crest lines through a
//!   face interpolate the one-sided estimates of its boundary and say nothing about the face;
//! - crest lines are cut within three rings (three times the mean length of its edges) of a
//!   cone point ([`crate::lines::crease::cone_points`]), or within [`CONE_FIT_RADII`] fitting
//!   radii of it if that is farther: the fits there straddle the tip or are biased by it;
//! - what is left of a cut crest line must still be [`MergeOptions::min_length`] long, not
//!   counting its joins to the crease;
//! - crest lines away from creases (fillets, blends, freeform parts) are kept as they are.
//!
//! Distances are measured to the crease curves themselves (exactly: resampled every half
//! tolerance to find the candidate segments, then the nearest point on those), so what is
//! near a crease and where a line joins it change continuously with the line: a motion of
//! the model that changes the rounding does not move a join point from one sample to the next. A cut line keeps its kind; its
//! strengths are scaled to the part kept (T = ∫ds·∫C ds by the square of the length ratio,
//! ∫|k|ds by the ratio).

use super::crease::Creases;
use super::{FeatureLine, FeatureLines, SurfacePoint, polyline_length};
use crate::error::{Error, Result};
use crate::mesh::widest_side;
use crate::mesh::{TriMesh, Vec3};
use crate::spatial::{PointGrid, segment_parameter};

/// Options of [`merge_creases`]; distances are fractions of the model size
/// ([`TriMesh::model_size`]: the bounding-box diagonal of the largest part).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MergeOptions {
    /// Crest-line points closer than this to a crease curve are replaced by the crease.
    ///
    /// Default: 0.005 (the tolerance at which sharp edges are scored).
    pub tolerance: f64,
    /// A crest line ending this close to a crease is extended to it.
    ///
    /// Default: 0.02.
    pub join_distance: f64,
    /// Pieces of cut crest lines shorter than this are dropped.
    ///
    /// Default: 0.01 (the minimum length of crest lines).
    pub min_length: f64,
}

impl MergeOptions {
    /// The default options (see each field).
    pub const DEFAULT: Self = MergeOptions {
        tolerance: 0.005,
        join_distance: 0.02,
        min_length: 0.01,
    };

    fn validate(&self) -> Result<()> {
        for (name, x) in [
            ("tolerance", self.tolerance),
            ("join distance", self.join_distance),
            ("minimum length", self.min_length),
        ] {
            if !(x.is_finite() && x >= 0.0) {
                return Err(Error::InvalidInput(format!(
                    "merge {name} must be a non-negative number, got {x}"
                )));
            }
        }
        Ok(())
    }
}

impl Default for MergeOptions {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// One straight piece of a crease curve.
struct CreaseSegment {
    p: Vec3,
    q: Vec3,
    /// The mesh edge it runs along, with its end vertices in the direction p → q.
    edge: Option<(u32, u32, u32)>,
    /// Where the piece lies when it is not along one edge.
    location: SurfacePoint,
}

/// The crease curves as segments, resampled for nearest-point queries: a query finds the
/// samples near a point, then the nearest point on their segments, so that what is "near"
/// and where a line is joined depend continuously on the line (not on the resampling).
struct CreaseSamples {
    segments: Vec<CreaseSegment>,
    /// The segment of each sample.
    segment_of: Vec<u32>,
    grid: PointGrid,
    spacing: f64,
}

impl CreaseSamples {
    /// Samples every crease segment at most `spacing` apart (both ends included).
    fn new(mesh: &TriMesh, creases: &FeatureLines, spacing: f64) -> Self {
        let topo = mesh.topology();
        let mut segments = Vec::new();
        let mut points = Vec::new();
        let mut segment_of = Vec::new();
        let fallback = |line: &FeatureLine, k: usize| {
            line.locations
                .get(k)
                .copied()
                .unwrap_or(SurfacePoint::Face { face: 0 })
        };
        for line in &creases.lines {
            let n = line.points.len();
            let count = if line.closed { n } else { n.saturating_sub(1) };
            let pieces: Vec<(usize, usize)> = if n == 1 {
                vec![(0, 0)]
            } else {
                (0..count).map(|k| (k, (k + 1) % n)).collect()
            };
            for (k, l) in pieces {
                let (p, q) = (line.points[k], line.points[l]);
                let edge = match (line.locations.get(k), line.locations.get(l)) {
                    (Some(SurfacePoint::Vertex(a)), Some(SurfacePoint::Vertex(b))) if k != l => {
                        topo.edge_between(*a, *b).map(|e| (e, *a, *b))
                    }
                    _ => None,
                };
                let steps = ((q - p).norm() / spacing).ceil().clamp(1.0, 1e6) as usize;
                for s in 0..=steps {
                    points.push(p + (q - p) * (s as f64 / steps as f64));
                    segment_of.push(segments.len() as u32);
                }
                segments.push(CreaseSegment {
                    p,
                    q,
                    edge,
                    location: fallback(line, k),
                });
            }
        }
        let grid = PointGrid::new(&points, spacing * 4.0);
        CreaseSamples {
            segments,
            segment_of,
            grid,
            spacing,
        }
    }

    /// The point of the crease curves nearest to `x`, if one is within `radius`, with where
    /// it lies on the mesh.
    fn nearest_point(&self, x: Vec3, radius: f64) -> Option<(Vec3, SurfacePoint)> {
        // Every segment within `radius` has a sample within `radius + spacing`.
        let mut candidates: Vec<u32> = Vec::new();
        self.grid.for_each_within(x, radius + self.spacing, |i, _| {
            candidates.push(self.segment_of[i as usize])
        });
        candidates.sort_unstable();
        candidates.dedup();
        let mut best: Option<(f64, u32, f64)> = None;
        for s in candidates {
            let seg = &self.segments[s as usize];
            let t = segment_parameter(x, seg.p, seg.q);
            let d2 = (seg.p + (seg.q - seg.p) * t - x).norm_squared();
            if d2 <= radius * radius && best.is_none_or(|(b, _, _)| d2 < b) {
                best = Some((d2, s, t));
            }
        }
        let (_, s, t) = best?;
        let seg = &self.segments[s as usize];
        let location = match seg.edge {
            Some((_, a, _)) if t <= 0.0 => SurfacePoint::Vertex(a),
            Some((_, _, b)) if t >= 1.0 => SurfacePoint::Vertex(b),
            Some((edge, a, b)) => SurfacePoint::Edge {
                edge,
                // Edge parameters run from the edge's first vertex.
                t: if a < b { t } else { 1.0 - t },
            },
            None => seg.location,
        };
        Some((seg.p + (seg.q - seg.p) * t, location))
    }
}

/// Merges `creases` (found by [`crate::lines::crease::find_creases`] on `mesh`) into `crest`
/// lines (see the module docs). The crest lines come first in the result, then the crease
/// curves. `fit_radius` is the radius (model units) of the discs the curvature estimate
/// read, 0 when it read stars or rings: crest lines are cut within
/// [`CONE_FIT_RADII`] of it around cone points.
///
/// # Errors
/// [`Error::InvalidInput`] for options out of range or creases of another mesh.
pub fn merge_creases(
    mesh: &TriMesh,
    crest: FeatureLines,
    creases: &Creases,
    options: &MergeOptions,
    fit_radius: f64,
) -> Result<FeatureLines> {
    options.validate()?;
    if creases.curves.is_empty() {
        return Ok(crest);
    }
    if creases
        .curves
        .iter()
        .flat_map(|c| &c.vertices)
        .any(|&v| v as usize >= mesh.num_vertices())
    {
        return Err(Error::InvalidInput(
            "crease curves refer to vertices the mesh does not have".into(),
        ));
    }
    let on_crease = creases.vertices(mesh);
    let sides: std::collections::HashMap<u32, Vec<u32>> = on_crease
        .iter()
        .enumerate()
        .filter(|(_, on)| **on)
        .map(|(v, _)| (v as u32, widest_side(mesh, v as u32, &creases.edges)))
        .collect();
    let crease_lines = creases.lines(mesh);
    let cone_radii: Vec<f64> = creases
        .cones
        .iter()
        .map(|&c| {
            let edges = mesh.topology().vertex_edges(c);
            let total: f64 = edges
                .iter()
                .map(|&e| {
                    let [a, b] = mesh.topology().edge(e);
                    (mesh.position(b) - mesh.position(a)).norm()
                })
                .sum();
            (3.0 * total / edges.len().max(1) as f64).max(CONE_FIT_RADII * fit_radius)
        })
        .collect();
    let cone_positions: Vec<Vec3> = creases.cones.iter().map(|&c| mesh.position(c)).collect();
    let largest = cone_radii.iter().copied().fold(0.0, f64::max);
    let supported = Support {
        mesh,
        on_crease: &on_crease,
        sides: &sides,
        cones: PointGrid::new(&cone_positions, largest),
        cone_radii: &cone_radii,
        largest,
    };
    let diagonal = mesh.model_size();
    let tolerance = options.tolerance * diagonal;
    // At most 5,000 samples per diagonal of crease, whatever the tolerance.
    let spacing = (tolerance / 2.0)
        .max(diagonal * 2e-4)
        .max(f64::MIN_POSITIVE);
    let samples = CreaseSamples::new(mesh, &crease_lines, spacing);
    let join = options.join_distance * diagonal;
    let min_length = options.min_length * diagonal;
    let mut lines = Vec::with_capacity(crest.lines.len() + crease_lines.lines.len());
    for line in crest.lines {
        cut_line(
            line, &samples, &supported, tolerance, join, min_length, &mut lines,
        );
    }
    lines.extend(crease_lines.lines);
    Ok(FeatureLines { lines })
}

/// Cuts the parts of `line` near a crease, joins the ends to the crease and pushes the
/// pieces long enough onto `out`.
fn cut_line(
    line: FeatureLine,
    samples: &CreaseSamples,
    support: &Support<'_>,
    tolerance: f64,
    join: f64,
    min_length: f64,
    out: &mut Vec<FeatureLine>,
) {
    let n = line.points.len();
    let has_locations = line.locations.len() == n;
    let near: Vec<bool> = (0..n)
        .map(|k| {
            (has_locations && !support.is_supported(line.locations[k]))
                || samples.nearest_point(line.points[k], tolerance).is_some()
                || support.near_cone(line.points[k])
        })
        .collect();
    if n == 0 {
        return;
    }
    if !near.iter().any(|&x| x) {
        let mut line = line;
        if !line.closed {
            let (first, last) = (line.points[0], line.points[n - 1]);
            join_end(&mut line, samples, first, join, true);
            join_end(&mut line, samples, last, join, false);
        }
        out.push(line);
        return;
    }
    // Runs of points away from creases, in order; a closed line is opened at a near point.
    let start = if line.closed {
        near.iter().position(|&x| x).unwrap_or(0)
    } else {
        0
    };
    let order: Vec<usize> = (0..n).map(|k| (start + k) % n).collect();
    let order: Vec<usize> = if line.closed {
        order.into_iter().chain([start]).collect()
    } else {
        order
    };
    let mut k = 0;
    while k < order.len() {
        if near[order[k]] {
            k += 1;
            continue;
        }
        let first = k;
        while k < order.len() && !near[order[k]] {
            k += 1;
        }
        let run = &order[first..k];
        let mut piece = FeatureLine {
            locations: if has_locations {
                run.iter().map(|&i| line.locations[i]).collect()
            } else {
                Vec::new()
            },
            ..FeatureLine::new(
                line.kind,
                run.iter().map(|&i| line.points[i]).collect(),
                false,
            )
        };
        // Every end goes to the crease point nearest to it, within the join distance; an
        // end where the line was cut also within its distance to the point cut next to it
        // plus the tolerance, so that it reaches the crease the line ran into. The anchor is
        // the end kept, never the point cut: whether the tracing reached one more point
        // there can follow rounding (a flat side's extremality), and the join must not.
        let reach = |end: Vec3, cut: Option<usize>| {
            cut.map_or(join, |i| {
                join.max((line.points[i] - end).norm() + tolerance)
            })
        };
        // What is left of the crest line must be long enough by itself: the joins to the
        // crease do not count (a single point beside a crease, joined to it, is not a line).
        let own_length = piece.length;
        if let Some(&start) = piece.points.first() {
            let radius = reach(start, (first > 0).then(|| order[first - 1]));
            join_end(&mut piece, samples, start, radius, true);
        }
        if let Some(&end) = piece.points.last() {
            let radius = reach(end, (k < order.len()).then(|| order[k]));
            join_end(&mut piece, samples, end, radius, false);
        }
        if own_length >= min_length && piece.points.len() >= 2 {
            let ratio = if line.length > 0.0 {
                (piece.length / line.length).min(1.0)
            } else {
                0.0
            };
            piece.curvature_integral = line.curvature_integral * ratio;
            piece.strength = line.strength * ratio * ratio;
            out.push(piece);
        }
    }
}

/// Which line points are interpolated from fields that describe the surface there (see the
/// module docs).
struct Support<'a> {
    mesh: &'a TriMesh,
    on_crease: &'a [bool],
    /// The faces each crease vertex's fields describe.
    sides: &'a std::collections::HashMap<u32, Vec<u32>>,
    /// Cone points, the radius around each where crest lines are cut, the largest radius.
    cones: PointGrid,
    cone_radii: &'a [f64],
    largest: f64,
}

impl Support<'_> {
    fn near_cone(&self, p: Vec3) -> bool {
        let mut near = false;
        if self.cone_radii.is_empty() {
            return false;
        }
        self.cones.for_each_within(p, self.largest, |c, d2| {
            let r = self.cone_radii[c as usize];
            near |= d2 <= r * r;
        });
        near
    }

    fn is_supported(&self, location: SurfacePoint) -> bool {
        let topo = self.mesh.topology();
        let off = |v: u32| !self.on_crease.get(v as usize).copied().unwrap_or(false);
        // Corners `corners` read in faces `faces`: each on a crease must describe one of them.
        let valid = |corners: &[u32], faces: &[u32]| {
            corners.iter().any(|&v| off(v))
                && corners.iter().all(|&v| {
                    off(v)
                        || self
                            .sides
                            .get(&v)
                            .is_some_and(|side| faces.iter().any(|f| side.contains(f)))
                })
        };
        match location {
            SurfacePoint::Vertex(v) => off(v),
            SurfacePoint::Edge { edge, .. } => {
                if edge as usize >= topo.num_edges() {
                    return true;
                }
                let [a, b] = topo.edge(edge);
                valid(&[a, b], topo.edge_faces(edge))
            }
            SurfacePoint::Face { face } => topo
                .faces()
                .get(face as usize)
                .is_none_or(|t| valid(t, &[face])),
        }
    }
}

/// Crest lines are cut within this many fitting radii of a cone point (and within three
/// rings of it, whichever is farther). A fit whose disc holds the tip straddles it; beyond,
/// the surface's Taylor series about a point at distance d from the tip converges only
/// within d, and the fit's truncation error in e, relative to the curvature's own scale,
/// falls off like (r / d)² for a disc of radius r: a ninth at three radii. A cone's
/// extremality is zero (k_max is constant around it), so what the fits find there is that
/// error: on the fine cone of the CAD solids (`tests/suite/cad_shapes.rs`) HPW's spurious
/// crest lines reach 2.8 fitting radii from the tip.
pub const CONE_FIT_RADII: f64 = 3.0;

/// Extends `line` at its start (or end) to the crease sample nearest to `anchor`, if there is
/// one within `radius` of it, and updates its length.
fn join_end(
    line: &mut FeatureLine,
    samples: &CreaseSamples,
    anchor: Vec3,
    radius: f64,
    at_start: bool,
) {
    let Some((p, loc)) = samples.nearest_point(anchor, radius) else {
        return;
    };
    let (end, other) = if at_start {
        (line.points.first(), line.points.last())
    } else {
        (line.points.last(), line.points.first())
    };
    // Already there; or the other end was joined to the same point, and the line would run
    // out and back (a piece of one point between two cuts).
    if end.is_none_or(|&e| e == p) || other == Some(&p) {
        return;
    }
    let with_locations = !line.locations.is_empty();
    if at_start {
        line.points.insert(0, p);
        if with_locations {
            line.locations.insert(0, loc);
        }
    } else {
        line.points.push(p);
        if with_locations {
            line.locations.push(loc);
        }
    }
    line.length = polyline_length(&line.points, line.closed);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lines::LineKind;

    fn grid_mesh() -> TriMesh {
        // A flat 11 x 11 grid on [0, 1]^2: the mesh only gives the diagonal and topology.
        let n = 11;
        let mut p = Vec::new();
        for j in 0..n {
            for i in 0..n {
                p.push([i as f64 / 10.0, j as f64 / 10.0, 0.0]);
            }
        }
        let mut f = Vec::new();
        for j in 0..n - 1 {
            for i in 0..n - 1 {
                let a = (j * n + i) as u32;
                f.push([a, a + 1, a + n as u32 + 1]);
                f.push([a, a + n as u32 + 1, a + n as u32]);
            }
        }
        TriMesh::from_arrays(p, f).unwrap()
    }

    fn line(points: &[[f64; 2]], crease: bool) -> FeatureLine {
        let points: Vec<Vec3> = points.iter().map(|p| Vec3::new(p[0], p[1], 0.0)).collect();
        FeatureLine {
            curvature_integral: 1.0,
            strength: 1.0,
            crease,
            ..FeatureLine::new(LineKind::Ridge, points, false)
        }
    }

    /// The grid's column x = 0.5 as a crease.
    fn middle_crease(mesh: &TriMesh) -> Creases {
        let vertices: Vec<u32> = (0..11).map(|j| j * 11 + 5).collect();
        let mut edges = vec![false; mesh.topology().num_edges()];
        for w in vertices.windows(2) {
            edges[mesh.topology().edge_between(w[0], w[1]).unwrap() as usize] = true;
        }
        Creases {
            threshold: Some(30.0),
            filtered: false,
            edges,
            curves: vec![crate::lines::crease::CreaseCurve {
                vertices,
                closed: false,
                convex: true,
                length: 1.0,
                turning: 0.5,
            }],
            dropped: 0,
            cones: Vec::new(),
        }
    }

    #[test]
    fn crest_line_along_a_crease_is_replaced_and_crossing_one_is_joined() {
        let mesh = grid_mesh();
        let crease = middle_crease(&mesh);
        // Runs along the crease 0.001 away, then turns off to the right.
        let along = line(
            &[
                [0.501, 0.1],
                [0.501, 0.3],
                [0.501, 0.5],
                [0.6, 0.5],
                [0.8, 0.5],
            ],
            false,
        );
        // Stops 0.01 short of the crease.
        let short = line(&[[0.1, 0.7], [0.3, 0.7], [0.49, 0.7]], false);
        let far = line(&[[0.1, 0.2], [0.2, 0.2]], false);
        let crest = FeatureLines {
            lines: vec![along, short, far.clone()],
        };
        let merged = merge_creases(&mesh, crest, &crease, &MergeOptions::DEFAULT, 0.0).unwrap();
        assert_eq!(merged.lines.len(), 4);
        let [a, b, c, d] = &merged.lines[..] else {
            unreachable!()
        };
        // The part along the crease is gone; the rest starts on the crease.
        assert!((a.points[0] - Vec3::new(0.5, 0.5, 0.0)).norm() < 0.003);
        assert!(a.points.iter().all(|p| p.x >= 0.5));
        assert!((b.points.last().unwrap() - Vec3::new(0.5, 0.7, 0.0)).norm() < 0.003);
        assert_eq!(c, &far);
        assert!(d.crease);
    }

    /// Around a cone point crest lines are cut within three rings, or within
    /// `CONE_FIT_RADII` fitting radii when that is farther.
    #[test]
    fn crest_lines_near_a_cone_point_are_cut_within_three_fitting_radii() {
        let mesh = grid_mesh();
        let mut creases = middle_crease(&mesh);
        // The vertex at (0.8, 0.5); three rings there are about 0.34.
        creases.cones = vec![5 * 11 + 8];
        // 0.41 to 0.43 from the cone point, 0.2 from the crease.
        let crest = FeatureLines {
            lines: vec![line(&[[0.7, 0.9], [0.8, 0.9], [0.95, 0.9]], false)],
        };
        let options = MergeOptions::DEFAULT;
        let kept = merge_creases(&mesh, crest.clone(), &creases, &options, 0.0).unwrap();
        assert_eq!(kept.lines.len(), 2);
        assert_eq!(kept.lines[0], crest.lines[0]);
        let cut = merge_creases(&mesh, crest, &creases, &options, 0.15).unwrap();
        assert_eq!(cut.lines.len(), 1);
        assert!(cut.lines[0].crease);
    }

    /// A piece of one point between two cuts is no line (its joins do not count towards the
    /// minimum length); without a minimum length it is joined to the crease once, not out
    /// and back.
    #[test]
    fn a_piece_of_one_point_between_two_cuts() {
        let mesh = grid_mesh();
        let creases = middle_crease(&mesh);
        // Near the crease, 0.05 off it, near it again.
        let crest = FeatureLines {
            lines: vec![line(&[[0.501, 0.1], [0.55, 0.2], [0.501, 0.3]], false)],
        };
        let merged =
            merge_creases(&mesh, crest.clone(), &creases, &MergeOptions::DEFAULT, 0.0).unwrap();
        assert_eq!(merged.lines.len(), 1);
        assert!(merged.lines[0].crease);
        let options = MergeOptions {
            min_length: 0.0,
            ..MergeOptions::DEFAULT
        };
        let merged = merge_creases(&mesh, crest, &creases, &options, 0.0).unwrap();
        assert_eq!(merged.lines.len(), 2);
        let piece = &merged.lines[0];
        assert_eq!(piece.points.len(), 2, "{:?}", piece.points);
        assert!((piece.points[0] - Vec3::new(0.5, 0.2, 0.0)).norm() < 1e-9);
        assert!((piece.length - 0.05).abs() < 1e-9);
    }

    #[test]
    fn no_creases_leaves_lines_alone() {
        let mesh = grid_mesh();
        let crest = FeatureLines {
            lines: vec![line(&[[0.1, 0.7], [0.3, 0.7]], false)],
        };
        let none = Creases::none(mesh.topology().num_edges());
        let merged =
            merge_creases(&mesh, crest.clone(), &none, &MergeOptions::DEFAULT, 0.0).unwrap();
        assert_eq!(merged, crest);
    }

    #[test]
    fn points_between_crease_vertices_only_are_cut() {
        let mesh = grid_mesh();
        let creases = middle_crease(&mesh);
        // A line along the grid row y = 0.5 with mesh locations at the vertices: x = 0.4 and
        // x = 0.6 are off the crease, x = 0.5 is on it.
        let row: Vec<u32> = (0..11).map(|i| 5 * 11 + i).collect();
        let mut crest = line(
            &row.iter()
                .map(|&v| [mesh.position(v).x, mesh.position(v).y])
                .collect::<Vec<_>>(),
            false,
        );
        crest.locations = row.iter().map(|&v| SurfacePoint::Vertex(v)).collect();
        let options = MergeOptions {
            tolerance: 0.0,
            ..MergeOptions::DEFAULT
        };
        let merged = merge_creases(
            &mesh,
            FeatureLines { lines: vec![crest] },
            &creases,
            &options,
            0.0,
        )
        .unwrap();
        // Two pieces joined to the crease, and the crease.
        assert_eq!(merged.lines.len(), 3);
        assert!(merged.lines[..2].iter().all(|l| l.points.len() == 6));
    }
}
