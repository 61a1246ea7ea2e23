//! End-to-end properties of `extract` on analytic surfaces and real meshes (HPW; the YBS
//! counterparts are in `extract_ybs.rs`). The exact crest line of the test ellipsoid is
//! derived at [`common::ELLIPSOID`].

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use crate::common;

use common::{ELLIPSOID, check_deterministic_and_simple, check_ellipsoid, check_torus_is_empty};
use crestline::extract::{ExtractOptions, HpwOptions, Method, Pipeline};
use crestline::lines::LineKind;
use crestline::lines::filter::StrengthMeasure;
use crestline::shapes;
use crestline::threshold::Threshold;

const A: f64 = ELLIPSOID[0];
const B: f64 = ELLIPSOID[1];
const C: f64 = ELLIPSOID[2];

#[test]
fn hpw_finds_the_ellipsoid_crest_line_at_5k_and_20k_faces() {
    for subdivisions in [4, 5] {
        let mesh = shapes::ellipsoid(A, B, C, subdivisions);
        check_ellipsoid(&mesh, &ExtractOptions::for_method(Method::Hpw), "HPW");
    }
}

/// The capsule's seams, where k_min steps from 0 to 1, blur into the fits beside them; no
/// method may draw a line there. (YBS drew a ring of T = 2 on each cap, 1.2 fitting radii
/// from the seam, through faces next to the caps' umbilics; `lines::assemble::is_resolved`.)
#[test]
fn capsule_has_no_crest_lines() {
    let mesh = common::capsule();
    assert_eq!(
        mesh.topology()
            .count_edges(crestline::mesh::EdgeKind::Boundary),
        0
    );
    let diagonal = mesh.bounding_box().diagonal();
    for method in [Method::Hpw, Method::Ybs, Method::Saliency] {
        let result =
            crestline::extract::extract(&mesh, &ExtractOptions::for_method(method)).unwrap();
        assert!(
            result.lines.total_length() < 0.05 * diagonal,
            "{method:?}: {} lines, total length {:.3} (diagonal {diagonal:.3})",
            result.lines.lines.len(),
            result.lines.total_length()
        );
    }
}

#[test]
fn torus_has_no_crest_lines_by_default() {
    check_torus_is_empty(&ExtractOptions::for_method(Method::Hpw), "HPW");
}

#[test]
fn output_is_deterministic_and_polylines_are_simple() {
    let mesh = shapes::ellipsoid(A, B, C, 4);
    let options = ExtractOptions {
        pipeline: Pipeline::Hpw(HpwOptions {
            threshold: Threshold::Fixed(0.0),
            measure: StrengthMeasure::CurvatureIntegral,
        }),
        min_length: 0.0,
        ..ExtractOptions::default()
    };
    check_deterministic_and_simple(&mesh, &options, "HPW");
}

/// `mesh` with every seventh triangle wound the other way, as an exporter that lost their
/// winding leaves them, and how many.
fn some_wound_the_other_way(mesh: &crestline::TriMesh) -> (crestline::TriMesh, usize) {
    let wrong = |f: usize| f % 7 == 3;
    let faces = (mesh.faces().iter().enumerate())
        .map(|(f, &[a, b, c])| if wrong(f) { [a, c, b] } else { [a, b, c] })
        .collect();
    let count = (0..mesh.num_faces()).filter(|&f| wrong(f)).count();
    (
        crestline::TriMesh::new(mesh.positions().to_vec(), faces).unwrap(),
        count,
    )
}

#[test]
fn triangles_wound_against_their_neighbours_are_rewound_first() {
    let mesh = shapes::ellipsoid(A, B, C, 3);
    let (mixed, count) = some_wound_the_other_way(&mesh);
    let options = ExtractOptions::for_method(Method::Hpw);
    let found = crestline::extract::extract(&mixed, &options).unwrap();
    let orientation = found.stats.orientation;
    assert_eq!((orientation.rewound_faces, orientation.inward), (count, 0));
    let same = crestline::extract::extract(&mesh, &options).unwrap();
    assert_eq!((found.stats.ridges, found.stats.valleys), (1, 0));
    assert_eq!(found.lines.lines[0].points, same.lines.lines[0].points);
    // A box with rounded faces: taken as wound, the reversed triangles turn parts of its
    // convex creases into concave ones (crease valleys).
    let (pillow, _) = shapes::pillow_box(1.0, 0.1, 16);
    let (mixed, _) = some_wound_the_other_way(&pillow);
    let valleys = |found: &crestline::extract::Extraction| {
        (found.lines.creases(true))
            .filter(|l| l.kind == LineKind::Valley)
            .count()
    };
    let found = crestline::extract::extract(&mixed, &options).unwrap();
    let same = crestline::extract::extract(&pillow, &options).unwrap();
    assert_eq!(valleys(&found), 0);
    assert_eq!(found.lines.lines.len(), same.lines.lines.len());
    let as_wound = ExtractOptions {
        orient_outward: false,
        ..options
    };
    let found = crestline::extract::extract(&mixed, &as_wound).unwrap();
    assert!(valleys(&found) > 0, "{:?}", found.stats);
}

#[test]
fn a_scan_with_holes_wound_inward_is_oriented_first() {
    // The ellipsoid wound inward with holes around the ends of its two shorter axes, away
    // from its crest lines (a scan): still a ridge, not a valley.
    let outward = shapes::ellipsoid(A, B, C, 3);
    let holes = [[0.0, B, 0.0], [0.0, 0.0, C], [0.0, 0.0, -C]];
    let faces: Vec<[u32; 3]> = (outward.faces().iter())
        .filter(|t| {
            let c = t
                .iter()
                .map(|&v| outward.position(v))
                .sum::<crestline::Vec3>()
                / 3.0;
            holes
                .iter()
                .all(|h| (c - crestline::Vec3::from(*h)).norm() > 0.3 * C)
        })
        .map(|t| [t[0], t[2], t[1]])
        .collect();
    assert!(faces.len() + 10 < outward.num_faces());
    let scan = crestline::TriMesh::new(outward.positions().to_vec(), faces).unwrap();
    let options = ExtractOptions::for_method(Method::Hpw);
    let found = crestline::extract::extract(&scan, &options).unwrap();
    let o = found.stats.orientation;
    assert_eq!((o.closed, o.nearly_closed, o.inward), (0, 1, 1));
    assert_eq!((found.stats.ridges, found.stats.valleys), (1, 0));
}

#[test]
fn an_ellipsoid_wound_inward_is_oriented_first_unless_told_not_to() {
    let outward = shapes::ellipsoid(A, B, C, 3);
    let faces = outward.faces().iter().map(|t| [t[0], t[2], t[1]]).collect();
    let inward = crestline::TriMesh::new(outward.positions().to_vec(), faces).unwrap();
    let options = ExtractOptions::for_method(Method::Hpw);
    let found = crestline::extract::extract(&inward, &options).unwrap();
    assert_eq!((found.stats.ridges, found.stats.valleys), (1, 0));
    assert_eq!(found.stats.orientation.inward, 1);
    let same = crestline::extract::extract(&outward, &options).unwrap();
    assert_eq!(found.lines.lines[0].points, same.lines.lines[0].points);
    // Taken as wound, the normals point inward and the crest line is a valley.
    let as_wound = ExtractOptions {
        orient_outward: false,
        ..options
    };
    let found = crestline::extract::extract(&inward, &as_wound).unwrap();
    assert_eq!((found.stats.ridges, found.stats.valleys), (0, 1));
    assert_eq!(found.stats.orientation.inward, 0);
}

/// A crest through vertices on a plane of symmetry: marching cubes on a grid through the
/// ellipsoid's planes, its vertices projected onto the surface (`tests/data`). Its ridge, the
/// ellipse x² + (y/0.75)² = 1 in z = 0, runs through the vertices on that plane, where e
/// is zero to the fit's accuracy in both of the jet fit's models, of either sign
/// (`lines::assemble`, *Crossings at vertices*): its strength T was 1.1, at the threshold
/// (0.9 and no line with the file's coordinates to nine decimals), 54 now; regular meshes
/// of the surface give 30 and more.
#[test]
fn a_ridge_through_vertices_on_a_plane_of_symmetry_is_strong() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/marching_cubes_ellipsoid.obj");
    let mesh = crestline::io::read_mesh(&path, None).unwrap();
    let found = crestline::extract::extract(&mesh, &ExtractOptions::for_method(Method::Hpw))
        .unwrap()
        .lines;
    let ridges: Vec<_> = found.of_kind(LineKind::Ridge).collect();
    assert_eq!((ridges.len(), found.lines.len()), (1, 1), "{found:?}");
    let ridge = ridges[0];
    // The ellipse's perimeter, 5.526.
    assert!(
        (ridge.length - 5.526).abs() < 0.05,
        "length {}",
        ridge.length
    );
    assert!(ridge.strength > 5.0, "T = {}", ridge.strength);
    for p in &ridge.points {
        let off = (p.x * p.x + (p.y / 0.75).powi(2)).sqrt() - 1.0;
        assert!(p.z.abs() < 0.01 && off.abs() < 0.01, "{p:?}");
    }
}

/// A ridge along a column of a grid's vertices: the Gaussian ridge z = 0.3 exp(−(x/0.3)²)
/// extruded along y (e_min ≡ 0, so the crest's cyclideness is the interpolation's share of
/// e_max alone), on grids of 40 cells, with a column at x = 0, and 41, without
/// (`lines::assemble`, *Crossings at vertices*). Along the column T was 0.08, and no line,
/// where 39 cells, the crest between columns, give 93. Along it T is below a crossing
/// mid-edge's, which takes more of e than the mean over where a crossing may fall.
#[test]
fn a_ridge_along_a_column_of_vertices_is_kept() {
    let ridges = |cells| {
        let ridge = |x: f64, _: f64| 0.3 * (-(x / 0.3).powi(2)).exp();
        let mesh = shapes::height_field(ridge, [-1.0, 1.0], [-1.0, 1.0], cells, cells);
        let options = ExtractOptions::for_method(Method::Hpw);
        let found = crestline::extract::extract(&mesh, &options).unwrap().lines;
        let ridges: Vec<(f64, f64)> = found
            .of_kind(LineKind::Ridge)
            .map(|l| {
                assert!(l.points.iter().all(|p| p.x.abs() < 0.02), "{:?}", l.points);
                (l.length, l.strength)
            })
            .collect();
        assert_eq!(ridges.len(), 1, "{cells} cells: {ridges:?}");
        ridges[0]
    };
    let (along, between) = (ridges(40), ridges(41));
    for (length, _) in [along, between] {
        assert!((length - 2.0).abs() < 0.02, "length {length}");
    }
    assert!(
        along.1 > 0.4 * between.1 && along.1 < between.1,
        "T {} along a column, {} between",
        along.1,
        between.1
    );
}
