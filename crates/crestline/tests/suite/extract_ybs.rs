//! End-to-end checks of the YBS pipeline (`Method::Ybs`; Yoshizawa, Belyaev, Seidel 2005):
//! the analytic checks of the HPW pipeline (ellipsoid crest line, empty torus), the paper's
//! Fig. 5 (raising the strength T on a model with spherical and cylindrical parts), and gap
//! jumping on traced lines built from constructed curvature fields.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use crate::common;

use std::f64::consts::PI;

use common::{
    ELLIPSOID, check_deterministic_and_simple, check_ellipsoid, check_torus_is_empty, coverage,
    distance_to_lines,
};
use crestline::curvature::Curvature;
use crestline::extract::{ExtractOptions, Method, Pipeline, YbsOptions, extract};
use crestline::lines::gap::GapJumping;
use crestline::lines::{FeatureLines, LineKind, trace_crest_lines};
use crestline::threshold::{KneeSearch, Threshold};
use crestline::{TriMesh, Vec3, shapes};

fn ybs() -> ExtractOptions {
    ExtractOptions::for_method(Method::Ybs)
}

/// YBS as published: no extremality smoothing (the default smooths, see `extract`'s docs).
/// The automatic threshold stays on (`with_threshold(Threshold::Fixed(t))` for a fixed T).
fn ybs_as_published(rings: usize) -> ExtractOptions {
    let mut options = ybs();
    options.smoothing.steps = 0;
    options.curvature = options.curvature.with_rings(rings);
    options
}

// ---------------------------------------------------------------------------------------
// The analytic checks of the HPW pipeline.

#[test]
fn ybs_finds_the_ellipsoid_crest_line_as_one_closed_line_at_5k_and_20k_faces() {
    let [a, b, c] = ELLIPSOID;
    for subdivisions in [4, 5] {
        let mesh = shapes::ellipsoid(a, b, c, subdivisions);
        let name = format!("YBS, {} faces", mesh.num_faces());
        let lines = check_ellipsoid(&mesh, &ybs(), &name);
        // Not in pieces: the equator is one closed ridge.
        assert_eq!(lines.lines.len(), 1, "{name}: {} lines", lines.lines.len());
        assert!(lines.lines[0].closed, "{name}: the equator is not closed");
    }
}

#[test]
fn ybs_leaves_the_torus_empty() {
    check_torus_is_empty(&ybs(), "YBS");
    // The strength T alone, as the paper uses it, also removes every spurious line there.
    check_torus_is_empty(&ybs_as_published(1), "YBS as published");
}

#[test]
fn ybs_output_is_deterministic_and_polylines_are_simple() {
    let [a, b, c] = ELLIPSOID;
    let mesh = shapes::ellipsoid(a, b, c, 4);
    let mut options = ybs();
    options.pipeline = Pipeline::Ybs(YbsOptions {
        threshold: Threshold::Knee {
            floor: 0.0,
            search: KneeSearch::for_strengths(),
        },
        ..YbsOptions::default()
    });
    options.min_length = 0.0;
    check_deterministic_and_simple(&mesh, &options, "YBS");
}

// ---------------------------------------------------------------------------------------
// YBS Fig. 5: spherical and cylindrical parts (Dupin cyclides, e = 0) and the crest lines
// between them.

/// Total length of the lines that leave the `tol`-neighbourhood of `rims`.
fn length_off(lines: &FeatureLines, rims: &FeatureLines, tol: f64) -> f64 {
    lines
        .lines
        .iter()
        .filter(|l| l.points.iter().any(|&p| distance_to_lines(p, rims) > tol))
        .map(|l| l.length)
        .sum()
}

#[test]
fn raising_t_removes_the_lines_on_spherical_and_cylindrical_parts_but_keeps_the_rims() {
    // A cylinder (radius 1, length 2) closed by spherical caps of radius 1.5 meeting it at
    // sharp rims; 12,288 triangles.
    let (mesh, rims) = shapes::tablet(1.0, 2.0, 1.5, 96);
    let diagonal = mesh.bounding_box().diagonal();
    let tol = 0.01 * diagonal;
    let rim_samples: Vec<Vec3> = (0..2000)
        .map(|i| {
            let t = i as f64 * PI / 1000.0;
            let z = if i % 2 == 0 { -1.0 } else { 1.0 };
            Vec3::new(t.cos(), t.sin(), z)
        })
        .collect();
    let rims_found = |lines: &FeatureLines| coverage(&rim_samples, lines, tol);

    // As in the paper's figure: the 3-ring fit, no extremality smoothing.
    let with_threshold = |threshold: f64| {
        let options = ybs_as_published(3).with_threshold(Threshold::Fixed(threshold));
        extract(&mesh, &options).unwrap().lines
    };
    // Without a threshold, spurious lines cover the caps and the side (measured: 27 lines,
    // T ≤ 0.03), and the rims are there (T ≈ 300).
    let all = with_threshold(0.0);
    let spurious = length_off(&all, &rims, tol);
    assert!(
        spurious > 5.0 * diagonal,
        "only {spurious:.2} of spurious lines (diagonal {diagonal:.2})"
    );
    assert!(rims_found(&all) >= 0.95);
    // Raising T (the paper's figures use 1 to 3) removes them all; the rims stay.
    for threshold in [1.0, 3.0, 30.0] {
        let lines = with_threshold(threshold);
        assert_eq!(
            length_off(&lines, &rims, tol),
            0.0,
            "T = {threshold}: lines off the rims remain"
        );
        let found = rims_found(&lines);
        assert!(found >= 0.95, "T = {threshold}: rims {:.1}%", 100.0 * found);
        assert!(lines.lines.iter().all(|l| l.kind == LineKind::Ridge));
    }

    // The default pipeline finds the rims and nothing else.
    let lines = extract(&mesh, &ybs()).unwrap().lines;
    assert_eq!(length_off(&lines, &rims, tol), 0.0);
    assert!(rims_found(&lines) >= 0.95);
}

// ---------------------------------------------------------------------------------------
// Gap jumping on traced lines (YBS Fig. 4), from constructed fields on a flat grid. The angle
// rules (sharp corners, a V, a gentle bend, junctions, closing loops) are tested on
// polylines in `lines::gap`.

/// Ridge fields on the flat `mesh`: at each vertex `field(p)` gives the ridge direction
/// `dir_max` and `e_max`, or `None` to make the vertex fail the curvature condition
/// (`k_min = −10` against `k_max = 1`). `e_min = 0`, so nothing else is traced.
fn ridge_fields(mesh: &TriMesh, field: impl Fn(Vec3) -> Option<(Vec3, f64)>) -> Curvature {
    let n = mesh.num_vertices();
    // (dir_max, e_max, k_min) per vertex.
    let per_vertex: Vec<(Vec3, f64, f64)> = mesh
        .positions()
        .iter()
        .map(|&p| field(p).map_or((Vec3::y(), 0.0, -10.0), |(dir, e)| (dir, e, 0.0)))
        .collect();
    Curvature {
        k_max: vec![1.0; n],
        k_min: per_vertex.iter().map(|x| x.2).collect(),
        dir_max: per_vertex.iter().map(|x| x.0).collect(),
        dir_min: per_vertex.iter().map(|x| Vec3::z().cross(&x.0)).collect(),
        e_max: per_vertex.iter().map(|x| x.1).collect(),
        e_min: vec![0.0; n],
        normals: vec![Vec3::z(); n],
        ..Default::default()
    }
}

/// The ridge of `e = −⟨p − point, normal⟩` (falling along `normal`): the line through `point`
/// perpendicular to `normal`.
fn ridge_through(p: Vec3, point: Vec3, normal: Vec3) -> (Vec3, f64) {
    (normal, -(p - point).dot(&normal))
}

#[test]
fn gap_jumping_joins_the_two_pieces_of_a_broken_ridge() {
    let mesh = shapes::height_field(|_, _| 0.0, [0.0, 12.0], [0.0, 3.0], 12, 3);
    // The ridge y = 1.5, cut at x = 6 where the curvature condition fails.
    let fields = ridge_fields(&mesh, |p| {
        ((p.x - 6.0).abs() > 0.5).then(|| ridge_through(p, Vec3::new(0.0, 1.5, 0.0), Vec3::y()))
    });
    let (pieces, joins) = trace_crest_lines(&mesh, &fields, None);
    assert_eq!(joins, 0);
    assert_eq!(pieces.lines.len(), 2, "{pieces:?}");
    let gaps = GapJumping::default();
    let (joined, joins) = trace_crest_lines(&mesh, &fields, Some(&gaps));
    assert_eq!(joins, 1);
    assert_eq!(joined.lines.len(), 1);
    let line = &joined.lines[0];
    assert!(!line.closed);
    // One straight line across the strip, the jump included.
    assert!(line.points.iter().all(|p| (p.y - 1.5).abs() < 1e-12));
    assert!((line.length - 12.0).abs() < 1e-9, "{}", line.length);
    let xs: Vec<f64> = line.points.iter().map(|p| p.x).collect();
    assert!(
        xs.windows(2).all(|w| w[1] > w[0]) || xs.windows(2).all(|w| w[1] < w[0]),
        "{xs:?}"
    );
    // The jump spans the cut: from x = 5 to x = 7.
    assert!((line.length - pieces.total_length() - 2.0).abs() < 1e-9);
}
