//! CAD solids with exact sharp edges (issue 20): a box, a capped cylinder, a cone, a chamfered
//! block, a block with one filleted edge and a box-cylinder union, each tessellated the way CAD
//! exporters do (no vertex inside a face: planar faces as fans of long thin triangles, ruled
//! faces as one row of quads, circles cut to a chordal tolerance of 0.0005 of the diagonal) and
//! finely and irregularly (spacing 2% of the diagonal, jittered points, random diagonals).
//!
//! The lines of `extract` (default settings, every method) are scored against the exact sharp
//! edges, sampled densely: precision (share of the line length within 0.5% of the diagonal of
//! a sharp edge) and recall (share of the sharp edges' length within that of a line). Also:
//! no line away from the sharp edges lies on a planar face, and every corner (where sharp
//! edges meet at an angle) is within the tolerance of the end of a line.
//! The solids themselves are built in `cad_solids.rs`.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use crestline::Vec3;
use crestline::extract::{ExtractOptions, Method, extract};
use crestline::lines::FeatureLines;
use crestline::spatial::{FaceGrid, PointGrid};

use super::cad_solids::{Solid, Tessellation, block, chamfered_block, solids};
use crate::common;

/// Scoring tolerance, relative to the diagonal.
const TOLERANCE: f64 = 0.005;

/// Points every `step` along polylines, each with the length it stands for.
fn sample(polylines: &[(Vec<Vec3>, bool)], step: f64) -> (Vec<Vec3>, Vec<f64>) {
    let segments = polylines.iter().flat_map(|(line, closed)| {
        let n = line.len();
        let count = if *closed { n } else { n.saturating_sub(1) };
        (0..count).map(move |k| [line[k], line[(k + 1) % n]])
    });
    common::weighted_samples(segments, step).into_iter().unzip()
}

/// What the lines of one solid score.
struct Score {
    precision: f64,
    recall: f64,
    /// Length of lines away from the sharp edges on planar faces.
    on_planes: f64,
    /// Corners with no line end within the tolerance.
    corners_missed: usize,
}

impl Score {
    fn f1(&self) -> f64 {
        let (p, r) = (self.precision, self.recall);
        if p + r > 0.0 {
            2.0 * p * r / (p + r)
        } else {
            0.0
        }
    }
}

fn score(solid: &Solid, lines: &FeatureLines) -> Score {
    let diagonal = solid.mesh.bounding_box().diagonal();
    let tol = TOLERANCE * diagonal;
    let (truth, truth_w) = sample(&solid.sharp, tol / 4.0);
    let detected: Vec<(Vec<Vec3>, bool)> = lines
        .lines
        .iter()
        .map(|l| (l.points.clone(), l.closed))
        .collect();
    let (found, found_w) = sample(&detected, tol / 4.0);
    let truth_grid = PointGrid::new(&truth, tol);
    let found_grid = PointGrid::new(&found, tol);
    let faces = FaceGrid::new(&solid.mesh);
    let (mut near, mut total, mut on_planes) = (0.0, 0.0, 0.0);
    for (&p, &w) in found.iter().zip(&found_w) {
        total += w;
        if truth_grid.nearest_within(p, tol).is_some() {
            near += w;
        } else if faces
            .closest_point(p)
            .is_some_and(|c| solid.planar[c.face as usize])
        {
            on_planes += w;
        }
    }
    let precision = if total > 0.0 { near / total } else { 0.0 };
    let covered: f64 = truth
        .iter()
        .zip(&truth_w)
        .filter(|(p, _)| found_grid.nearest_within(**p, tol).is_some())
        .map(|(_, w)| w)
        .sum();
    let recall = covered / truth_w.iter().sum::<f64>();
    let ends: Vec<Vec3> = lines
        .lines
        .iter()
        .filter(|l| !l.closed && !l.points.is_empty())
        .flat_map(|l| [l.points[0], l.points[l.points.len() - 1]])
        .collect();
    let corners_missed = solid
        .corners
        .iter()
        .filter(|c| !ends.iter().any(|e| (e - *c).norm() <= tol))
        .count();
    Score {
        precision,
        recall,
        on_planes,
        corners_missed,
    }
}

/// Checks every solid against issue 20's targets (F1 ≥ 0.98, nothing on planar faces, every
/// corner reached).
fn check_method(method: Method) {
    let mut failures = Vec::new();
    for solid in solids() {
        let topo = solid.mesh.topology();
        assert_eq!(
            topo.count_edges(crestline::mesh::EdgeKind::Boundary),
            0,
            "{}: not closed",
            solid.name
        );
        let result = extract(&solid.mesh, &ExtractOptions::for_method(method)).unwrap();
        let s = score(&solid, &result.lines);
        let diagonal = solid.mesh.bounding_box().diagonal();
        eprintln!(
            "{method:?} {:<36} {:>6} faces  P {:.3} R {:.3} F1 {:.4}  on planes {:.4} diag, \
             corners missed {}/{}, creases {}",
            solid.name,
            solid.mesh.num_faces(),
            s.precision,
            s.recall,
            s.f1(),
            s.on_planes / diagonal,
            s.corners_missed,
            solid.corners.len(),
            result.stats.creases,
        );
        if s.f1() < 0.98 || s.on_planes > 0.0 || s.corners_missed > 0 {
            // CAD_SHAPES_DUMP=folder keeps the mesh and the lines of a failure.
            if let Some(dir) = std::env::var_os("CAD_SHAPES_DUMP") {
                let stem = std::path::Path::new(&dir)
                    .join(format!("{method:?}-{}", solid.name).replace([' ', '(', ')'], "_"));
                let mesh_path = stem.with_extension("obj");
                crestline::io::write_mesh(
                    &mesh_path,
                    &solid.mesh,
                    crestline::io::Format::Obj,
                    &Default::default(),
                )
                .unwrap();
                let lines_path = stem.with_extension("json");
                crestline::io::lines::write_lines(
                    &lines_path,
                    &result.lines,
                    None,
                    crestline::io::PlyEncoding::Ascii,
                )
                .unwrap();
            }
            failures.push(solid.name.clone());
        }
    }
    assert!(failures.is_empty(), "{method:?} fails on {failures:?}");
}

// The fine cone used to be a known gap of HPW (F1 0.974) and of the saliency method (0.773):
// crest lines near the apex, out to 2.8 fitting radii from it (HPW) and 4.2 (saliency),
// where a cone's extremality is zero and the fits' e is their truncation error. The merge
// now cuts crest lines within three fitting radii of a cone point (`lines::merge`,
// `CONE_FIT_RADII`), where it cut within three rings: HPW 1.000, YBS 1.000, saliency 0.980
// (three short saliency lines at 3.1 to 4.2 radii, strengths below 0.001, are left).
#[test]
fn hpw_lines_are_the_sharp_edges_of_cad_solids() {
    check_method(Method::Hpw);
}

#[test]
fn ybs_lines_are_the_sharp_edges_of_cad_solids() {
    check_method(Method::Ybs);
}

#[test]
fn saliency_lines_are_the_sharp_edges_of_cad_solids() {
    check_method(Method::Saliency);
}

#[test]
fn creases_off_gives_no_crease_lines() {
    let solid = block(Tessellation::Fine);
    let mut options = ExtractOptions::default();
    options.creases.angle = crestline::lines::crease::CreaseAngle::Off;
    let result = extract(&solid.mesh, &options).unwrap();
    assert_eq!(result.stats.creases, 0);
    // +0, not the -0 of an empty float sum (`--stats` printed "length -0.000000").
    assert!(result.stats.crease_length == 0.0 && result.stats.crease_length.is_sign_positive());
    assert!(result.lines.lines.iter().all(|l| !l.crease));
}

#[test]
fn sharp_edges_are_where_the_builders_say() {
    // The exact sharp edges of the box: 12 edges, 8 corners, and the export has no vertex
    // inside a face.
    let solid = block(Tessellation::Export);
    assert_eq!(solid.sharp.len(), 2 + 4);
    assert_eq!(solid.corners.len(), 8);
    assert_eq!(solid.mesh.num_vertices(), 8);
}

#[test]
fn simplify_keeps_the_creases() {
    let solid = chamfered_block(Tessellation::Fine);
    let lines = extract(&solid.mesh, &ExtractOptions::default())
        .unwrap()
        .lines;
    let out = crestline::simplify::simplify(
        &solid.mesh,
        &lines,
        &crestline::simplify::SimplifyOptions::DEFAULT,
    )
    .unwrap();
    assert!(
        out.faces_after * 4 < solid.mesh.num_faces(),
        "{}",
        out.faces_after
    );
    let faces = out.mesh.num_faces();
    let simplified = Solid {
        name: "simplified chamfered block".into(),
        mesh: out.mesh,
        planar: vec![false; faces],
        sharp: solid.sharp,
        corners: solid.corners,
    };
    let result = extract(&simplified.mesh, &ExtractOptions::default()).unwrap();
    let s = score(&simplified, &result.lines);
    assert!(
        s.f1() >= 0.98 && s.corners_missed == 0,
        "F1 {:.3}, corners missed {}",
        s.f1(),
        s.corners_missed
    );
}
