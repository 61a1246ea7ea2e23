//! `crestline info` run as a user runs it: the JSON report on real meshes, and clean
//! failures (non-zero exit, file and position named, no panic) on bad files.

// Test code: stopping loudly on the first surprise is the point.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use crate::common::{crestline, crestline_ok, fails, s, shared_meshes_dir as meshes_dir};

/// Runs `info` on a file with `contents` and returns the failed run's stderr.
fn failing_info(name: &str, contents: &[u8]) -> String {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(name);
    std::fs::write(&path, contents).unwrap();
    let err = fails(crestline(&["info", s(&path)]));
    assert!(err.contains(name), "{name} not named: {err}");
    err
}

const KEYS: [&str; 17] = [
    "vertices",
    "faces",
    "unreferenced_vertices",
    "degenerate_faces",
    "boundary_edges",
    "boundary_loops",
    "non_manifold_edges",
    "non_manifold_vertices",
    "components",
    "euler_characteristic",
    "closed",
    "bbox_min",
    "bbox_max",
    "diagonal",
    "model_size",
    "mean_edge_length",
    "marching_cubes_grid",
];

#[test]
fn info_json_reports_every_key() {
    let path = meshes_dir().join("suzanne.obj");
    let out = crestline_ok(["info", s(&path), "--json"]);
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    for key in KEYS {
        assert!(report.get(key).is_some(), "missing key {key} in {report}");
    }
    assert_eq!(report["vertices"], 507);
    assert_eq!(report["non_manifold_edges"], 1);
    assert_eq!(report["closed"], false);
    assert_eq!(report["bbox_min"].as_array().unwrap().len(), 3);
    assert!(report["marching_cubes_grid"].is_null(), "{report}");
}

#[test]
fn info_reads_binary_ply_and_forced_formats() {
    let horse = meshes_dir().join("horse.ply");
    let out = crestline_ok(["info", s(&horse), "--json"]);
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(report["faces"], 96_966);

    // An OBJ under another name, read with --input-format.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("triangle.txt");
    std::fs::write(&path, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let out = crestline_ok(["info", s(&path), "--input-format", "obj"]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("faces                  1"), "{text}");
}

#[test]
fn bad_text_file_names_file_and_line() {
    let err = failing_info("bad-token.obj", b"v 0 0 0\nv 1 x 0\nv 0 1 0\nf 1 2 3\n");
    assert!(
        err.contains("bad-token.obj: line 2: non-numeric token 'x'"),
        "{err}"
    );
    let err = failing_info("far.off", b"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 9\n");
    assert!(
        err.contains("far.off: line 6: face 0: vertex index 9 out of range"),
        "{err}"
    );
}

#[test]
fn truncated_binary_file_names_file_and_byte() {
    let header = "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n\
                  property float y\nproperty float z\nend_header\n";
    let mut bytes = header.as_bytes().to_vec();
    bytes.extend_from_slice(&[0u8; 20]);
    // Vertex 0 is complete; vertex 1, cut off, starts at byte 12 of the body.
    let err = failing_info("cut.ply", &bytes);
    assert!(
        err.contains(&format!(
            "cut.ply: byte {}: truncated data: the file ends in vertex 1",
            header.len() + 12
        )),
        "{err}"
    );
    assert_eq!(err.matches("cut.ply").count(), 1, "file named once: {err}");
}

#[test]
fn empty_and_unknown_files_fail_cleanly() {
    let err = failing_info("empty.stl", b"");
    assert!(err.contains("empty.stl: empty file"), "{err}");
    let err = failing_info("mesh.xyz", b"whatever");
    assert!(err.contains("unknown extension '.xyz'"), "{err}");
    let err = fails(crestline(&["info", "/nonexistent/none.obj"]));
    assert!(err.contains("/nonexistent/none.obj"), "{err}");
}
