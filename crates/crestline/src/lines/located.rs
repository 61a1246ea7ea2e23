//! Dropping the crest lines that noise moves about, and their ends: on a surface with white
//! noise, a line is kept only where its extremality crosses zero more steeply than the
//! estimation noise does.
//! Not a step of the papers (HPW and YBS filter by strength alone); crestline's own, for
//! noisy meshes.
//!
//! A traced line is a zero of the estimated extremality `e = e_true + ε`. Where `e` crosses
//! steeply the noise ε moves the zero little (by `ε / |∂e/∂t|`); where the true slope is not
//! above the noise's own, the zero goes where the noise takes it, and so does the line. The
//! public noisy bumps (`../shared/quality`, `bumpy/noisy20k`) have weak crests between the
//! bumps whose slope `|∂e/∂t|` on the clean mesh is 2 to 3 (the bumps' ridges 20 to 40):
//! under noise of 0.1 spacings the lines traced along them (T up to 5.5, above the strength
//! threshold) wander off them by two to four tolerances of the scorer (1% of the diagonal).
//! The strength T does not see it: its cyclideness C = |(e_max, e_min)| is as large on a
//! wandering line as on a located one.
//!
//! The noise's slope is known. The simulated noise ([`Curvature::simulated_noise`]) is what
//! the estimator makes of white noise of the measured level, smoothed as the extremalities
//! are; its root mean square change per unit length across the edges that run along the
//! principal direction is the noise's slope σ_s ([`slope_noise`]). At the zero crossings of
//! a stationary Gaussian process the slope is Rayleigh distributed (S. O. Rice, *Mathematical
//! analysis of random noise*, Bell System Technical Journal 23–24, 1944–45), with mean
//! `σ_s √(π/2) ≈ 1.25 σ_s`: a line of noise alone measures about 1.25 σ_s. A line is kept
//! when the mean slope at its crossings ([`line_slope`]) is at least [`LOCATED_SLOPE`] = 2
//! times σ_s: a noise of one standard deviation δ then moves its zeros by δ / (2 σ_s) or less
//! on average, half the noise's own length scale δ / σ_s (zeros of the noise alone are about
//! π δ / σ_s apart).
//!
//! Both slopes are measured the same way, as the change of the field along an edge within 60°
//! of the principal direction divided by the edge's length along it ([`edge_slope`]). On an
//! edge at an angle θ to the direction this adds `tan θ` times the change across the
//! direction: the noise's σ_s is read about 1.3 times its slope along the direction alone
//! (isotropic noise, edges up to 60°), and so are the crossings of a line of noise, while a
//! crest, along which e hardly changes, is read at its slope. The bound 2 is in this measure,
//! about 2.6 in slopes along the direction.
//!
//! A line kept can still wander at its ends, where the crest it follows weakens: its ends
//! are cut while the mean slope of the crossings within half a fit radius along it is below
//! the same bound ([`trim_unlocated_ends`]), before the strength threshold measures it.
//!
//! The simulated noise describes the estimation noise only when the surface's noise is
//! white: on scans and coarse models, whose fit residual is mostly the surface the
//! polynomial cannot follow, it overstates the noise of e many times (the cow's twelve ridges
//! measure 0.04 to 1.7 times σ_s, the horse's lines from 0.27). The step runs only when the jet fit
//! finds white noise ([`crate::curvature::jet_fit::JetFitReport::white_noise`]); of the
//! shared meshes only the teapot's faceting passes for it (its lines along the base and the
//! handle stay).
//! Measured in BENCHMARKS.md, "Lines the noise moves about".

use rayon::prelude::*;

use super::trace::Family;
use super::{FeatureLine, FeatureLines, LineKind, SurfacePoint, arc_lengths};
use crate::curvature::{Curvature, MIN_NOISE_SAMPLES};
use crate::mesh::{TriMesh, Vec3};

/// A line is located when the mean slope of its extremality at its edge crossings is at
/// least this many times the noise's root mean square slope ([`slope_noise`]); noise alone
/// averages 1.25 (see the module docs).
pub const LOCATED_SLOPE: f64 = 2.0;

/// The noise's slope σ_s of the ridge and the valley family ([`slope_noise`]), as
/// [`drop_unlocated_lines`] and [`trim_unlocated_ends`] read it. `creases` flags the crease
/// edges (per edge of [`crate::mesh::Topology::edges`]) the extremalities were smoothed
/// apart at, if any.
pub fn slope_noises(
    mesh: &TriMesh,
    curvature: &Curvature,
    creases: Option<&[bool]>,
) -> [Option<f64>; 2] {
    [LineKind::Ridge, LineKind::Valley].map(|kind| slope_noise(mesh, curvature, creases, kind))
}

/// Drops the lines of `lines` whose extremality does not cross zero at least
/// [`LOCATED_SLOPE`] times as steeply as its simulated estimation noise (`noise`, the
/// ridges' and the valleys' [`slope_noises`]), and returns how many it dropped. Lines
/// without edge crossings along their principal direction are kept, and so is every line
/// of a family without simulated noise.
pub fn drop_unlocated_lines(
    mesh: &TriMesh,
    curvature: &Curvature,
    noise: [Option<f64>; 2],
    lines: &mut FeatureLines,
) -> usize {
    let before = lines.lines.len();
    lines.lines.retain(|line| {
        let index = usize::from(line.kind == LineKind::Valley);
        let Some(noise) = noise[index] else {
            return true;
        };
        let family = Family::of(curvature, line.kind);
        line_slope(mesh, &family, line).is_none_or(|slope| slope >= LOCATED_SLOPE * noise)
    });
    before - lines.lines.len()
}

/// Cuts off the ends of the lines of `lines` where the noise moves them about, and returns
/// how many lines it shortened. From each end of an open line, points are dropped while the
/// mean slope of the extremality at the edge crossings within `window / 2` along the line
/// (arc length) is below [`LOCATED_SLOPE`] times the noise's slope ([`slope_noise`]); the
/// line is measured again ([`super::assemble::measure_line`]) for the strength threshold.
/// `noise` as for [`drop_unlocated_lines`].
/// A line with no located point, or only one, is left whole (the whole-line test,
/// [`drop_unlocated_lines`], has judged it).
/// Crossings on edges with a [`Curvature::one_sided`] end are not judged: the noise and the
/// bias of the fits there are not the interior's that σ_s measures (noisy ridges made like
/// the public one, whose valleys run to the boundary, lost them when they were).
pub fn trim_unlocated_ends(
    mesh: &TriMesh,
    curvature: &Curvature,
    noise: [Option<f64>; 2],
    window: f64,
    lines: &mut FeatureLines,
) -> usize {
    let one_sided = |v: u32| {
        curvature
            .one_sided
            .get(v as usize)
            .copied()
            .unwrap_or(false)
    };
    let mut trimmed = 0;
    for line in &mut lines.lines {
        let n = line.points.len();
        let index = usize::from(line.kind == LineKind::Valley);
        let Some(noise) = noise[index] else {
            continue;
        };
        if line.closed || line.locations.len() != n || n < 3 {
            continue;
        }
        let family = Family::of(curvature, line.kind);
        let slopes: Vec<Option<f64>> = line
            .locations
            .iter()
            .map(|&location| crossing_slope(mesh, &family, location, one_sided))
            .collect();
        let located = windowed_means(&line.points, &slopes, 0.5 * window)
            .into_iter()
            .map(|mean| mean.is_none_or(|m| m >= LOCATED_SLOPE * noise))
            .collect::<Vec<bool>>();
        let (Some(first), Some(last)) = (
            located.iter().position(|&l| l),
            located.iter().rposition(|&l| l),
        ) else {
            continue;
        };
        if (first, last) == (0, n - 1) || last <= first {
            continue;
        }
        line.points = line.points[first..=last].to_vec();
        line.locations = line.locations[first..=last].to_vec();
        super::assemble::measure_line(mesh, &family, line);
        trimmed += 1;
    }
    trimmed
}

/// Per point of the polyline `points`, the mean of the `values` given within `half` of it
/// along the line (arc length), `None` where none is: two pointers over the arc lengths.
fn windowed_means(points: &[Vec3], values: &[Option<f64>], half: f64) -> Vec<Option<f64>> {
    let half = half.max(0.0);
    let n = points.len();
    if n == 0 {
        return Vec::new();
    }
    let arc = arc_lengths(points, false);
    let (mut lo, mut hi) = (0, 0);
    let (mut sum, mut count) = (0.0, 0usize);
    let mut means = Vec::with_capacity(n);
    for i in 0..n {
        while hi < n && arc[hi] <= arc[i] + half {
            if let Some(v) = values[hi] {
                sum += v;
                count += 1;
            }
            hi += 1;
        }
        while arc[lo] < arc[i] - half {
            if let Some(v) = values[lo] {
                sum -= v;
                count -= 1;
                if count == 0 {
                    sum = 0.0;
                }
            }
            lo += 1;
        }
        means.push((count > 0).then(|| sum / count as f64));
    }
    means
}

/// The root mean square slope of the simulated noise of one family's extremality
/// ([`Curvature::simulated_noise`]), over the edges within 60° of the family's principal
/// direction ([`edge_slope`]) whose ends are neither [`Curvature::one_sided`] nor on one of
/// the `creases` (unless fewer than [`MIN_NOISE_SAMPLES`] edges are left); `None` without
/// simulated noise. The smoothing does not reach across a crease and leaves the noise of
/// crease vertices as it is: their edges would count it unsmoothed.
pub fn slope_noise(
    mesh: &TriMesh,
    curvature: &Curvature,
    creases: Option<&[bool]>,
    kind: LineKind,
) -> Option<f64> {
    let index = usize::from(kind == LineKind::Valley);
    let noise = &curvature.simulated_noise[index];
    if noise.len() != curvature.len() || noise.is_empty() {
        return None;
    }
    let family = Family::of(curvature, kind);
    let topology = mesh.topology();
    let on_crease = creases.map_or_else(Vec::new, |c| topology.vertices_of_edges(c));
    let apart = |v: u32| {
        let one_sided = curvature.one_sided.get(v as usize).copied();
        one_sided.unwrap_or(false) || on_crease.get(v as usize).copied().unwrap_or(false)
    };
    let sum = |interior_only: bool| {
        topology
            .edges()
            .par_iter()
            .filter(|[a, b]| !interior_only || !(apart(*a) || apart(*b)))
            .filter_map(|&[a, b]| edge_slope(mesh, &family, noise, a, b))
            .map(|slope| (slope * slope, 1usize))
            .reduce(|| (0.0, 0), |x, y| (x.0 + y.0, x.1 + y.1))
    };
    let (mut squares, mut count) = sum(true);
    if count < MIN_NOISE_SAMPLES {
        (squares, count) = sum(false);
    }
    (count > 0).then(|| (squares / count as f64).sqrt())
}

/// The mean slope `|∂e/∂t|` of the family's extremality at the line's edge crossings
/// ([`edge_slope`]); `None` when no crossing is on an edge within 60° of the principal
/// direction.
pub fn line_slope(mesh: &TriMesh, family: &Family<'_>, line: &FeatureLine) -> Option<f64> {
    let (sum, count) = line
        .locations
        .iter()
        .filter_map(|&location| crossing_slope(mesh, family, location, |_| false))
        .fold((0.0, 0usize), |(sum, count), slope| {
            (sum + slope, count + 1)
        });
    (count > 0).then(|| sum / count as f64)
}

/// The slope of the family's extremality at a line point on an edge ([`edge_slope`]);
/// `None` for a point in a face or at a vertex, and on an edge with an end `skip` names.
fn crossing_slope(
    mesh: &TriMesh,
    family: &Family<'_>,
    location: SurfacePoint,
    skip: impl Fn(u32) -> bool,
) -> Option<f64> {
    let SurfacePoint::Edge { edge, .. } = location else {
        return None;
    };
    let [a, b] = mesh.topology().edge(edge);
    if skip(a) || skip(b) {
        return None;
    }
    edge_slope(mesh, family, family.e, a, b)
}

/// The change of `field` (a per-vertex value along the family's principal directions, as
/// the extremality) from `a` to `b` per unit length along the principal direction, the
/// directions of the two ends averaged with a common sign; `None` when the edge makes more
/// than 60° with that direction (it then measures the change mostly along the line).
pub fn edge_slope(
    mesh: &TriMesh,
    family: &Family<'_>,
    field: &[f64],
    a: u32,
    b: u32,
) -> Option<f64> {
    let sign = family.relative_sign(a, b);
    let direction = family.dirs[a as usize] + family.dirs[b as usize] * sign;
    let edge = mesh.position(b) - mesh.position(a);
    let norm = direction.norm();
    if norm == 0.0 {
        return None;
    }
    let along = edge.dot(&direction).abs() / norm;
    (along > 0.5 * edge.norm())
        .then(|| (field[b as usize] * sign - field[a as usize]).abs() / along)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The plane over [0, 10]² on a 10 × 10 grid (unit spacing), with the max family's
    /// direction along x, the min family's along y, and `e_max` and the simulated noise of
    /// both families given as functions of x.
    fn plane(e_max: impl Fn(f64) -> f64, noise: impl Fn(f64) -> f64) -> (TriMesh, Curvature) {
        let mesh = crate::shapes::height_field(|_, _| 0.0, [0.0, 10.0], [0.0, 10.0], 10, 10);
        let n = mesh.num_vertices();
        let x: Vec<f64> = mesh.positions().iter().map(|p| p.x).collect();
        let simulated: Vec<f64> = x.iter().map(|&x| noise(x)).collect();
        let curvature = Curvature {
            k_max: vec![1.0; n],
            k_min: vec![0.0; n],
            dir_max: vec![Vec3::new(1.0, 0.0, 0.0); n],
            dir_min: vec![Vec3::new(0.0, 1.0, 0.0); n],
            e_max: x.iter().map(|&x| e_max(x)).collect(),
            e_min: vec![0.0; n],
            simulated_noise: [simulated.clone(), simulated],
            ..Curvature::default()
        };
        (mesh, curvature)
    }

    /// A ridge across the plane at x = 5.5: the crossings of the edges from x = 5 to x = 6.
    fn ridge_at_5_5(mesh: &TriMesh) -> FeatureLine {
        let topo = mesh.topology();
        let locations: Vec<SurfacePoint> = (0..topo.num_edges() as u32)
            .filter(|&e| {
                let [a, b] = topo.edge(e);
                let (pa, pb) = (mesh.position(a), mesh.position(b));
                pa.y == pb.y && pa.x.min(pb.x) == 5.0 && pa.x.max(pb.x) == 6.0
            })
            .map(|edge| SurfacePoint::Edge { edge, t: 0.5 })
            .collect();
        assert_eq!(locations.len(), 11);
        let points = locations.iter().map(|_| Vec3::zeros()).collect();
        FeatureLine {
            locations,
            ..FeatureLine::new(LineKind::Ridge, points, false)
        }
    }

    #[test]
    fn crease_vertices_and_one_sided_discs_are_left_out_of_the_slope_noise() {
        // Noise of slope 1 everywhere but between x = 4 and x = 6, where it is 10.
        let ramp = |x: f64| {
            if x <= 4.0 {
                x
            } else if x <= 6.0 {
                4.0 + 10.0 * (x - 4.0)
            } else {
                18.0 + x
            }
        };
        let (mesh, mut curvature) = plane(|_| 0.0, ramp);
        let all = slope_noise(&mesh, &curvature, None, LineKind::Ridge).unwrap();
        assert!(all > 2.0, "{all}");
        // The column x = 5 a crease: every edge with an end on it is left out.
        let creases: Vec<bool> = mesh
            .topology()
            .edges()
            .iter()
            .map(|&[a, b]| mesh.position(a).x == 5.0 && mesh.position(b).x == 5.0)
            .collect();
        let apart = slope_noise(&mesh, &curvature, Some(&creases), LineKind::Ridge).unwrap();
        assert!((apart - 1.0).abs() < 1e-12, "{apart}");
        // The same with the column's vertices one-sided.
        curvature.one_sided = mesh.positions().iter().map(|p| p.x == 5.0).collect();
        let one_sided = slope_noise(&mesh, &curvature, None, LineKind::Ridge).unwrap();
        assert!((one_sided - 1.0).abs() < 1e-12, "{one_sided}");
    }

    #[test]
    fn windowed_means_average_the_values_within_reach_along_the_line() {
        let points: Vec<Vec3> = (0..6).map(|i| Vec3::new(i as f64, 0.0, 0.0)).collect();
        let values = [Some(1.0), None, Some(3.0), Some(5.0), None, None];
        let means = windowed_means(&points, &values, 1.0);
        assert_eq!(
            means,
            vec![Some(1.0), Some(2.0), Some(4.0), Some(4.0), Some(5.0), None]
        );
    }

    #[test]
    fn wandering_ends_are_cut_off_and_the_located_middle_kept() {
        // A ridge along the column x = 5.5 of the plane (noise slope 1, so a bound of 2),
        // whose extremality crosses with these slopes on the rows y = 0 to 10. Over a window
        // of 2 (the crossings within 1 along the line) the means are below 2 up to y = 2 and
        // from y = 9: those rows are cut. Judged one by one, y = 2 (slope 3) would stay.
        let slopes = [0.5, 0.5, 3.0, 0.5, 4.0, 4.0, 4.0, 4.0, 4.0, 0.5, 0.5];
        let noise = |x: f64| if (x as i64) % 2 == 0 { 0.5 } else { -0.5 };
        let (mesh, mut curvature) = plane(|_| 0.0, noise);
        for (v, p) in mesh.positions().iter().enumerate() {
            curvature.e_max[v] = slopes[p.y as usize] * (5.5 - p.x);
        }
        let mut line = ridge_at_5_5(&mesh);
        let family = Family::of(&curvature, LineKind::Ridge);
        // Ordered along the line (by y), with its points where they are.
        let mut order: Vec<(f64, SurfacePoint)> = line
            .locations
            .iter()
            .map(|&location| match location {
                SurfacePoint::Edge { edge, .. } => {
                    let [a, _] = mesh.topology().edge(edge);
                    (mesh.position(a).y, location)
                }
                _ => unreachable!(),
            })
            .collect();
        order.sort_by(|a, b| a.0.total_cmp(&b.0));
        line.locations = order.iter().map(|&(_, l)| l).collect();
        line.points = order.iter().map(|&(y, _)| Vec3::new(5.5, y, 0.0)).collect();
        super::super::assemble::measure_line(&mesh, &family, &mut line);
        // The cut over a window of 2 with the noise's slope of `curvature`.
        let trim = |curvature: &Curvature, lines: &mut FeatureLines| {
            let noise = slope_noises(&mesh, curvature, None);
            trim_unlocated_ends(&mesh, curvature, noise, 2.0, lines)
        };
        let mut lines = FeatureLines {
            lines: vec![line.clone()],
        };
        let trimmed = trim(&curvature, &mut lines);
        assert_eq!(trimmed, 1);
        let cut = &lines.lines[0];
        let ys: Vec<f64> = cut.points.iter().map(|p| p.y).collect();
        assert_eq!(ys, vec![3.0, 4.0, 5.0, 6.0, 7.0, 8.0]);
        assert_eq!(cut.locations, line.locations[3..=8].to_vec());
        // Measured again: as the same piece measured from scratch.
        let mut piece = FeatureLine {
            points: line.points[3..=8].to_vec(),
            locations: line.locations[3..=8].to_vec(),
            ..line.clone()
        };
        super::super::assemble::measure_line(&mesh, &family, &mut piece);
        assert!((cut.length - 5.0).abs() < 1e-12, "{}", cut.length);
        assert_eq!(
            (cut.strength, cut.curvature_integral),
            (piece.strength, piece.curvature_integral)
        );
        assert!(cut.strength < line.strength);
        // A closed line, or one without simulated noise, is left as it is.
        let mut closed = FeatureLines {
            lines: vec![FeatureLine {
                closed: true,
                ..line.clone()
            }],
        };
        assert_eq!(trim(&curvature, &mut closed), 0);
        let clean = Curvature {
            simulated_noise: Default::default(),
            ..curvature.clone()
        };
        let mut lines = FeatureLines {
            lines: vec![line.clone()],
        };
        assert_eq!(trim(&clean, &mut lines), 0);
        // Nor are ends whose crossings are all one-sided judged.
        curvature.one_sided = mesh
            .positions()
            .iter()
            .map(|p| !(3.0..=8.0).contains(&p.y))
            .collect();
        let mut lines = FeatureLines { lines: vec![line] };
        assert_eq!(trim(&curvature, &mut lines), 0);
        assert_eq!(lines.lines[0].points.len(), 11);
    }

    #[test]
    fn the_slope_noise_is_the_rms_change_along_the_direction() {
        // Noise rising by 0.7 per unit of x: every edge within 60° of x (the grid's rows and
        // diagonals) measures 0.7, the columns are left out.
        let (mesh, curvature) = plane(|_| 0.0, |x| 0.7 * x);
        let ridges = slope_noise(&mesh, &curvature, None, LineKind::Ridge).unwrap();
        assert!((ridges - 0.7).abs() < 1e-12, "{ridges}");
        // Along y the same noise does not change on the columns and changes by 0.7 per unit of
        // y's projection on the diagonals.
        let valleys = slope_noise(&mesh, &curvature, None, LineKind::Valley).unwrap();
        assert!(valleys > 0.0 && valleys < 0.7, "{valleys}");
        let clean = Curvature {
            simulated_noise: Default::default(),
            ..curvature
        };
        assert_eq!(slope_noise(&mesh, &clean, None, LineKind::Ridge), None);
    }

    #[test]
    fn lines_are_kept_where_e_crosses_more_steeply_than_the_noise() {
        let noise = |x: f64| if (x as i64) % 2 == 0 { 0.5 } else { -0.5 };
        for (slope, kept) in [(2.5, true), (1.5, false)] {
            let (mesh, curvature) = plane(|x| slope * (5.5 - x), noise);
            // The noise alternates by ±0.5 from column to column: a slope of 1 along x on
            // the rows and the diagonals.
            let sigma = slope_noise(&mesh, &curvature, None, LineKind::Ridge).unwrap();
            assert!((sigma - 1.0).abs() < 1e-12, "{sigma}");
            let line = ridge_at_5_5(&mesh);
            let family = Family::of(&curvature, LineKind::Ridge);
            let measured = line_slope(&mesh, &family, &line).unwrap();
            assert!((measured - slope).abs() < 1e-12, "{measured}");
            let mut lines = FeatureLines { lines: vec![line] };
            let dropped = drop_unlocated_lines(
                &mesh,
                &curvature,
                slope_noises(&mesh, &curvature, None),
                &mut lines,
            );
            assert_eq!(
                (dropped, lines.lines.len()),
                (usize::from(!kept), usize::from(kept))
            );
        }
        // The directions of every other vertex reversed, their extremalities and noise with
        // them: the same field, the same slopes (the ends are compared with a common sign).
        let (mesh, mut curvature) = plane(|x| 2.5 * (5.5 - x), noise);
        for v in (1..curvature.len()).step_by(2) {
            curvature.dir_max[v] = -curvature.dir_max[v];
            curvature.e_max[v] = -curvature.e_max[v];
            curvature.simulated_noise[0][v] = -curvature.simulated_noise[0][v];
        }
        let sigma = slope_noise(&mesh, &curvature, None, LineKind::Ridge).unwrap();
        assert!((sigma - 1.0).abs() < 1e-12, "{sigma}");
        let line = ridge_at_5_5(&mesh);
        let family = Family::of(&curvature, LineKind::Ridge);
        let measured = line_slope(&mesh, &family, &line).unwrap();
        assert!((measured - 2.5).abs() < 1e-12, "{measured}");
        // Without simulated noise nothing is dropped.
        let (mesh, mut curvature) = plane(|x| 0.1 * (5.5 - x), noise);
        curvature.simulated_noise = Default::default();
        let mut lines = FeatureLines {
            lines: vec![ridge_at_5_5(&mesh)],
        };
        assert_eq!(
            drop_unlocated_lines(
                &mesh,
                &curvature,
                slope_noises(&mesh, &curvature, None),
                &mut lines
            ),
            0
        );
    }
}
