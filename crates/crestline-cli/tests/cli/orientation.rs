//! Meshes wound inward: `crestline extract` reverses closed components that face inward, so
//! that an ellipsoid's crest line comes out as a ridge whichever way its file is wound.

// Test code: stopping loudly on the first surprise is the point.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::ffi::OsStr;
use std::fmt::Write as _;
use std::path::Path;

use crate::common::{crestline_ok, stderr};

use crestline::shapes;

/// Writes the ellipsoid x²/9 + y²/4 + z² = 1 as an OFF file with every triangle reversed.
fn write_inward_ellipsoid(path: &Path) {
    let mesh = shapes::ellipsoid(3.0, 2.0, 1.0, 4);
    let mut off = format!("OFF\n{} {} 0\n", mesh.num_vertices(), mesh.num_faces());
    for p in mesh.positions() {
        writeln!(off, "{} {} {}", p.x, p.y, p.z).unwrap();
    }
    for [a, b, c] in mesh.faces() {
        writeln!(off, "3 {a} {c} {b}").unwrap();
    }
    std::fs::write(path, off).unwrap();
}

/// Runs `crestline extract` with `extra` arguments; returns (ridges, valleys, stderr).
fn extract(mesh: &Path, extra: &[&str]) -> (u64, u64, String) {
    let dir = mesh.parent().unwrap();
    let output = dir.join("lines.obj");
    let mut args: Vec<&OsStr> = vec!["extract".as_ref(), mesh.as_ref(), "-o".as_ref()];
    args.push(output.as_ref());
    args.push("--stats=json".as_ref());
    args.extend(extra.iter().map(OsStr::new));
    let out = crestline_ok(args);
    let stats: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    (
        stats["ridges"].as_u64().unwrap(),
        stats["valleys"].as_u64().unwrap(),
        stderr(&out),
    )
}

#[test]
fn an_ellipsoid_wound_inward_still_has_a_ridge_not_a_valley() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("inward.off");
    write_inward_ellipsoid(&path);
    let (ridges, valleys, stderr) = extract(&path, &[]);
    assert!(
        ridges >= 1 && valleys == 0,
        "{ridges} ridges, {valleys} valleys"
    );
    assert!(
        stderr.contains("faced inward"),
        "no note on stderr: {stderr}"
    );
    // Kept as wound, the normals point inward and the crest line is a valley.
    let (ridges, valleys, _) = extract(&path, &["--keep-orientation"]);
    assert!(
        ridges == 0 && valleys >= 1,
        "{ridges} ridges, {valleys} valleys"
    );
}

/// Writes a square of two triangles, a degenerate one (repeated corner) and two stray
/// vertices.
fn write_awkward(path: &Path) {
    std::fs::write(
        path,
        "OFF\n6 3 0\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n2 2 2\n5 5 5\n3 0 1 2\n3 1 3 2\n3 0 0 1\n",
    )
    .unwrap();
}

#[test]
fn quiet_hides_the_notes_about_the_mesh() {
    let dir = tempfile::tempdir().unwrap();
    let (inward, awkward, seam) = (
        dir.path().join("inward.off"),
        dir.path().join("awkward.off"),
        dir.path().join("seam.obj"),
    );
    write_inward_ellipsoid(&inward);
    write_awkward(&awkward);
    // Two triangles side by side, each with its own copy of the shared edge: welded.
    std::fs::write(
        &seam,
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 4 5 6\n",
    )
    .unwrap();
    for mesh in [&inward, &awkward, &seam] {
        let loud = stderr(&crestline_ok([
            "extract".as_ref(),
            mesh.as_os_str(),
            "-o".as_ref(),
            dir.path().join("l.obj").as_os_str(),
        ]));
        assert!(
            ["faced inward", "degenerate", "welded"]
                .iter()
                .any(|note| loud.contains(note)),
            "{loud}"
        );
        // `-q` before or after the subcommand.
        let output = dir.path().join("l.obj");
        let args: [&OsStr; 4] = [
            "extract".as_ref(),
            mesh.as_ref(),
            "-o".as_ref(),
            output.as_ref(),
        ];
        let before = std::iter::once("-q".as_ref()).chain(args);
        let after = args.into_iter().chain(std::iter::once("-q".as_ref()));
        assert_eq!(stderr(&crestline_ok(before)), "", "{}", mesh.display());
        assert_eq!(stderr(&crestline_ok(after)), "", "{}", mesh.display());
    }
}

#[test]
fn skipped_parts_of_a_mesh_are_named_on_stderr() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("awkward.off");
    write_awkward(&path);
    let (ridges, valleys, stderr) = extract(&path, &[]);
    assert_eq!((ridges, valleys), (0, 0));
    assert!(
        stderr.contains("1 degenerate triangle dropped")
            && stderr.contains("2 unreferenced vertices ignored"),
        "{stderr}"
    );
}
