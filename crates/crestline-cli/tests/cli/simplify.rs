//! `crestline distance` and `crestline simplify` run as a user runs them, on the generated
//! pillow box with its exact crease lines written to files.

// Test code: stopping loudly on the first surprise is the point.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::path::{Path, PathBuf};

use crate::common::{crestline, crestline_ok, s, stderr};
use crestline::io::{Format, WriteOptions, read_mesh, write_mesh};

/// Writes the pillow box (12 · 16² triangles) and its creases; returns (mesh, lines) paths.
fn pillow_box_files(dir: &Path) -> (PathBuf, PathBuf) {
    let (mesh, lines) = crestline::shapes::pillow_box(1.0, 0.25, 16);
    let mesh_path = dir.join("box.obj");
    write_mesh(&mesh_path, &mesh, Format::Obj, &WriteOptions::default()).unwrap();
    let lines_path = dir.join("creases.obj");
    let file = std::fs::File::create(&lines_path).unwrap();
    crestline::io::lines::write_lines_obj(std::io::BufWriter::new(file), &lines).unwrap();
    (mesh_path, lines_path)
}

#[test]
fn simplify_with_lines_meets_the_face_count() {
    let dir = tempfile::tempdir().unwrap();
    let (mesh, lines) = pillow_box_files(dir.path());
    let out = dir.path().join("small.ply");
    let run = crestline_ok([
        "simplify",
        s(&mesh),
        "-o",
        s(&out),
        "--faces",
        "500",
        "--eta",
        "2",
        "--lines",
        s(&lines),
        "--json",
    ]);
    let report: serde_json::Value = serde_json::from_slice(&run.stdout).unwrap();
    assert_eq!(report["lines"], 12);
    assert_eq!(report["faces_before"], 3072);
    assert_eq!(report["target_reached"], true);
    let small = read_mesh(&out, None).unwrap();
    let faces = small.num_faces();
    assert!(faces == 500 || faces == 499, "{faces}");
    assert_eq!(report["faces_after"], faces);
    let info = small.info();
    assert!(info.closed && info.euler_characteristic == 2, "{info}");
}

#[test]
fn plain_qem_needs_no_lines() {
    let dir = tempfile::tempdir().unwrap();
    let (mesh, _) = pillow_box_files(dir.path());
    let out = dir.path().join("small.off");
    crestline_ok([
        "simplify",
        s(&mesh),
        "-o",
        s(&out),
        "--ratio",
        "0.25",
        "--eta",
        "0",
    ]);
    assert_eq!(read_mesh(&out, None).unwrap().num_faces(), 768);
}

#[test]
fn distance_writes_a_ply_vertex_property() {
    let dir = tempfile::tempdir().unwrap();
    let (mesh, lines) = pillow_box_files(dir.path());
    let out = dir.path().join("field.ply");
    crestline_ok([
        "distance",
        s(&mesh),
        "-o",
        s(&out),
        "--lines",
        s(&lines),
        "--ascii",
    ]);
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(text.contains("property double feature_distance\n"));
    let vertices = read_mesh(&mesh, None).unwrap().num_vertices();
    let body = text.split("end_header\n").nth(1).unwrap();
    let d: Vec<f64> = body
        .lines()
        .take(vertices)
        .map(|l| l.split_whitespace().nth(3).unwrap().parse().unwrap())
        .collect();
    assert!(d.iter().all(|x| x.is_finite() && *x >= 0.0));
    // The 12 edges of 17 vertices share the 8 corners: 12 · 15 + 8 vertices on creases.
    assert_eq!(d.iter().filter(|&&x| x == 0.0).count(), 12 * 15 + 8);
    // The farthest points are the face centres, a bulge above the middle of a face.
    let max = d.iter().copied().fold(0.0, f64::max);
    assert!(max > 1.0 && max < 1.2, "{max}");
}

#[test]
fn without_lines_they_are_extracted() {
    let dir = tempfile::tempdir().unwrap();
    let (mesh, _) = pillow_box_files(dir.path());
    let out = dir.path().join("small.obj");
    let run = crestline_ok(["simplify", s(&mesh), "-o", s(&out), "--json"]);
    assert!(stderr(&run).contains("extracting"), "{}", stderr(&run));
    let report: serde_json::Value = serde_json::from_slice(&run.stdout).unwrap();
    // Lines were found on the creases (how they split and join is extraction's business).
    assert!(report["lines"].as_u64().unwrap() > 0, "{report}");
    assert_eq!(report["target_reached"], true);
}

#[test]
fn bad_arguments_fail_cleanly() {
    let dir = tempfile::tempdir().unwrap();
    let (mesh, lines) = pillow_box_files(dir.path());
    let out = dir.path().join("x.obj");
    let run = crestline(&["distance", s(&mesh), "-o", s(&out), "--lines", s(&lines)]);
    assert!(!run.status.success());
    assert!(stderr(&run).contains(".ply"), "{}", stderr(&run));
    let run = crestline(&[
        "simplify",
        s(&mesh),
        "-o",
        s(&out),
        "--ratio",
        "0.5",
        "--faces",
        "10",
    ]);
    assert!(!run.status.success());
    let run = crestline(&[
        "simplify",
        s(&mesh),
        "-o",
        s(&out),
        "--ratio",
        "2",
        "--eta",
        "0",
    ]);
    assert!(!run.status.success());
    let err = stderr(&run);
    assert!(err.contains("ratio") && !err.contains("panicked"), "{err}");
}

#[test]
fn the_default_method_is_named_as_the_command_line_spells_it() {
    let dir = tempfile::tempdir().unwrap();
    let (mesh, _) = pillow_box_files(dir.path());
    for (command, output) in [("simplify", "small.obj"), ("distance", "field.ply")] {
        let out = crestline_ok([command, s(&mesh), "-o", s(&dir.path().join(output))]);
        let err = stderr(&out);
        assert!(
            err.contains("extracting them with the default method (hpw)"),
            "{command}: {err}"
        );
    }
}
