//! Pieces side by side: every command welds vertices that share a position before anything
//! else, so a surface exported as separate patches (here: every triangle with its own
//! corners, as STL stores it, written as OFF) gives the lines of the joined surface.

// Test code: stopping loudly on the first surprise is the point.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::ffi::OsStr;
use std::path::Path;

use crate::common::{crestline_ok, s, stderr};

use crestline::io::{Format, WriteOptions, write_mesh};
use crestline::{TriMesh, Vec3, shapes};

/// The ellipsoid x²/9 + y²/4 + z² = 1, whose crest lines are known.
fn ellipsoid() -> TriMesh {
    shapes::ellipsoid(3.0, 2.0, 1.0, 4)
}

/// Writes `positions` and `faces` as OFF (coordinates exactly, by the library's writer).
fn write_off(path: &Path, positions: Vec<Vec3>, faces: Vec<[u32; 3]>) {
    let mesh = TriMesh::new(positions, faces).unwrap();
    write_mesh(path, &mesh, Format::Off, &WriteOptions::default()).unwrap();
}

/// Every triangle of `mesh` with its own three corners, as STL stores it (wound the other
/// way when `reverse`).
fn soup(mesh: &TriMesh, reverse: bool) -> (Vec<Vec3>, Vec<[u32; 3]>) {
    let positions = mesh
        .faces()
        .iter()
        .flat_map(|t| t.map(|v| mesh.position(v)))
        .collect();
    let faces = (0..mesh.num_faces() as u32)
        .map(|f| {
            let [a, b, c] = [3 * f, 3 * f + 1, 3 * f + 2];
            if reverse { [a, c, b] } else { [a, b, c] }
        })
        .collect();
    (positions, faces)
}

/// Writes the ellipsoid as OFF, joined or as a soup of triangles.
fn write_ellipsoid(path: &Path, as_soup: bool) {
    let mesh = ellipsoid();
    let (positions, faces) = if as_soup {
        soup(&mesh, false)
    } else {
        (mesh.positions().to_vec(), mesh.faces().to_vec())
    };
    write_off(path, positions, faces);
}

/// Runs `crestline extract` with `extra` arguments; returns the stats and stderr.
fn extract(mesh: &Path, extra: &[&str]) -> (serde_json::Value, String) {
    let output = mesh.with_extension("lines.obj");
    let mut args: Vec<&OsStr> = vec!["extract".as_ref(), mesh.as_ref(), "-o".as_ref()];
    args.push(output.as_ref());
    args.push("--stats=json".as_ref());
    args.extend(extra.iter().map(OsStr::new));
    let out = crestline_ok(args);
    (serde_json::from_slice(&out.stdout).unwrap(), stderr(&out))
}

#[test]
fn a_triangle_soup_gives_the_lines_of_the_joined_surface() {
    let dir = tempfile::tempdir().unwrap();
    let (joined, soup) = (dir.path().join("joined.off"), dir.path().join("soup.off"));
    write_ellipsoid(&joined, false);
    write_ellipsoid(&soup, true);
    let (expected, _) = extract(&joined, &[]);
    assert!(expected["ridges"].as_u64().unwrap() >= 1, "{expected}");
    let (welded, note) = extract(&soup, &[]);
    assert!(
        note.contains("welded") && note.contains("--no-weld"),
        "no note on stderr: {note}"
    );
    assert_eq!(welded["ridges"], expected["ridges"]);
    assert_eq!(welded["valleys"], expected["valleys"]);
    let (a, b) = (
        welded["total_length"].as_f64().unwrap(),
        expected["total_length"].as_f64().unwrap(),
    );
    assert!((a - b).abs() <= 1e-3 * b, "{a} against {b}");
    // Kept apart, every triangle is a surface of its own: no disc to fit, no line.
    let (apart, note) = extract(&soup, &["--no-weld"]);
    assert_eq!(apart["lines"], 0, "{apart}");
    assert!(!note.contains("welded"), "{note}");
    // Not in silence: a warning says the triangles do not share corners, `-q` or not.
    let (_, warning) = extract(&soup, &["--no-weld", "-q"]);
    assert!(
        warning.contains("warning:") && warning.contains("triangle soup"),
        "{warning}"
    );
    let (_, welded_note) = extract(&soup, &[]);
    assert!(!welded_note.contains("triangle soup"), "{welded_note}");
}

#[test]
fn a_mask_has_one_factor_per_vertex_of_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let soup = dir.path().join("soup.off");
    write_ellipsoid(&soup, true);
    let text = std::fs::read_to_string(&soup).unwrap();
    let vertices: usize = text
        .lines()
        .nth(1)
        .unwrap()
        .split(' ')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    let mask = dir.path().join("mask.txt");
    std::fs::write(&mask, "1\n".repeat(vertices)).unwrap();
    let (stats, _) = extract(&soup, &["--mask", s(&mask)]);
    assert!(stats["ridges"].as_u64().unwrap() >= 1, "{stats}");
}

#[test]
fn info_counts_coincident_vertices() {
    let dir = tempfile::tempdir().unwrap();
    let soup = dir.path().join("soup.off");
    write_ellipsoid(&soup, true);
    let mesh = ellipsoid();
    let out = crestline_ok(["info", s(&soup)]);
    let text = String::from_utf8(out.stdout).unwrap();
    let expected = 3 * mesh.num_faces() - mesh.num_vertices();
    assert!(
        text.contains(&format!("coincident vertices    {expected}\n")),
        "{text}"
    );
}

#[test]
fn fields_keep_one_row_per_vertex_of_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let (joined, soup) = (dir.path().join("joined.off"), dir.path().join("soup.off"));
    write_ellipsoid(&joined, false);
    write_ellipsoid(&soup, true);
    let rows = |mesh: &Path| -> Vec<Vec<f64>> {
        let csv = mesh.with_extension("csv");
        crestline_ok(["curvature", s(mesh), "-o", s(&csv), "--csv", "-q"]);
        let text = std::fs::read_to_string(&csv).unwrap();
        text.lines()
            .skip(1)
            .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
            .collect()
    };
    let (soup_rows, joined_rows) = (rows(&soup), rows(&joined));
    let mesh = ellipsoid();
    assert_eq!(soup_rows.len(), 3 * mesh.num_faces());
    // Each corner's row is the row of the joined mesh's vertex at its place.
    for (corner, row) in soup_rows.iter().enumerate() {
        let v = mesh.faces()[corner / 3][corner % 3] as usize;
        let expected = &joined_rows[v];
        assert_eq!(row[..3], expected[..3]);
        for (a, b) in row.iter().zip(expected).skip(3) {
            assert!(
                (a - b).abs() <= 1e-9 * (1.0 + b.abs()),
                "{row:?} against {expected:?}"
            );
        }
    }
    // The picture draws the soup as read, its field per vertex of the file.
    let png = dir.path().join("soup.png");
    crestline_ok(["render", s(&soup), "--field", "k-max", "-o", s(&png), "-q"]);
    assert!(std::fs::metadata(&png).unwrap().len() > 1000);
}

#[test]
fn the_two_sides_of_a_double_sided_export_become_one_surface() {
    let dir = tempfile::tempdir().unwrap();
    let (joined, double) = (dir.path().join("joined.off"), dir.path().join("double.off"));
    write_ellipsoid(&joined, false);
    // Every triangle twice, the second copy wound the other way and with its own vertices.
    let mesh = ellipsoid();
    let n = mesh.num_vertices() as u32;
    let positions = [mesh.positions(), mesh.positions()].concat();
    let reversed = mesh.faces().iter().map(|&[a, b, c]| [a + n, c + n, b + n]);
    let faces = mesh.faces().iter().copied().chain(reversed).collect();
    write_off(&double, positions, faces);
    let (expected, _) = extract(&joined, &[]);
    let (welded, note) = extract(&double, &[]);
    assert!(
        note.contains(&format!("dropped {} triangles", mesh.num_faces())),
        "{note}"
    );
    assert_eq!(welded["ridges"], expected["ridges"]);
    assert_eq!(welded["valleys"], expected["valleys"]);
}

#[test]
fn a_soup_wound_inward_is_written_back_turned_outward() {
    // The curvature is estimated on the welded mesh, which is closed and turned outward; the
    // mesh written with it keeps the file's vertices, its triangles turned alike.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("soup.off");
    let (positions, faces) = soup(&ellipsoid(), true);
    write_off(&path, positions, faces);
    let ply = dir.path().join("fields.ply");
    let out = crestline_ok(["curvature", s(&path), "-o", s(&ply)]);
    assert!(stderr(&out).contains("faced inward"), "{}", stderr(&out));
    let written = crestline::io::read_mesh(&ply, None).unwrap();
    let mesh = ellipsoid();
    assert_eq!(written.num_vertices(), 3 * mesh.num_faces());
    assert!(crestline::mesh::signed_volume(&written) > 0.0);
}

#[test]
fn a_soup_with_triangles_wound_both_ways_is_written_back_wound_alike() {
    // Every fifth triangle of the soup wound the other way: once welded they are rewound to
    // agree with the rest, and the mesh written with the fields (the file's own vertices)
    // has them turned alike, so that every normal points outward.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("mixed.off");
    let (positions, mut faces) = soup(&ellipsoid(), false);
    for t in faces.iter_mut().skip(2).step_by(5) {
        t.swap(1, 2);
    }
    write_off(&path, positions, faces);
    let ply = dir.path().join("fields.ply");
    let out = crestline_ok(["curvature", s(&path), "-o", s(&ply)]);
    let note = stderr(&out);
    let count = (0..ellipsoid().num_faces()).filter(|f| f % 5 == 2).count();
    assert!(
        note.contains(&format!(
            "{count} triangles were wound against their neighbours"
        )),
        "{note}"
    );
    let written = crestline::io::read_mesh(&ply, None).unwrap();
    for &[a, b, c] in written.faces() {
        let [a, b, c] = [a, b, c].map(|v| written.position(v));
        // The ellipsoid is centred at the origin and convex.
        assert!((b - a).cross(&(c - a)).dot(&(a + b + c)) > 0.0);
    }
}
