//! `crestline subdivide` run as a user runs it: counts after Loop subdivision, format
//! conversion with `--levels 0`, clean refusals.

// Test code: stopping loudly on the first surprise is the point.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use crate::common::{crestline, stderr};
use crestline::io::{Format, WriteOptions, read_mesh, write_mesh};

#[test]
fn two_levels_of_a_closed_mesh() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("sphere.obj");
    let mesh = crestline::shapes::icosphere(1.0, 1);
    write_mesh(&input, &mesh, Format::Obj, &WriteOptions::default()).unwrap();
    let output = dir.path().join("fine.ply");
    let out = crestline(&[
        "subdivide",
        input.to_str().unwrap(),
        "-o",
        output.to_str().unwrap(),
        "--levels",
        "2",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let fine = read_mesh(&output, None).unwrap();
    // 80 faces, 42 vertices, 120 edges -> 320 faces, 162 vertices, 480 edges -> 1280, 642.
    assert_eq!(fine.num_faces(), 1280);
    assert_eq!(fine.num_vertices(), 642);
    let info = fine.info();
    assert!(info.closed && info.non_manifold_vertices == 0 && info.components == 1);
}

#[test]
fn zero_levels_converts_the_format() {
    let dir = tempfile::tempdir().unwrap();
    let output = dir.path().join("fandisk.off");
    // fandisk, the built-in example.
    let fandisk = concat!(env!("CARGO_MANIFEST_DIR"), "/data/fandisk.obj");
    let out = crestline(&[
        "subdivide",
        fandisk,
        "-o",
        output.to_str().unwrap(),
        "--levels",
        "0",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = std::fs::read_to_string(&output).unwrap();
    assert!(text.starts_with("OFF\n6475 12946 0\n"), "{}", &text[..40]);
}

#[test]
fn refuses_a_bad_corner_angle_and_an_oversized_result() {
    let dir = tempfile::tempdir().unwrap();
    let output = dir.path().join("x.obj");
    let o = output.to_str().unwrap();
    for (args, expected) in [
        (vec!["--corner-angle", "200"], "corner angle"),
        (vec!["--levels", "12"], "12 levels"),
    ] {
        let fandisk = concat!(env!("CARGO_MANIFEST_DIR"), "/data/fandisk.obj");
        let mut all = vec!["subdivide", fandisk, "-o", o];
        all.extend(args);
        let out = crestline(&all);
        let err = stderr(&out);
        assert!(!out.status.success(), "{all:?} should fail");
        assert!(!err.contains("panicked"), "{all:?} panicked: {err}");
        assert!(err.contains(expected), "{all:?}: {err}");
    }
    assert!(!output.exists());
}

#[test]
fn refuses_levels_beyond_the_face_bound_naming_the_largest_that_fits() {
    let dir = tempfile::tempdir().unwrap();
    let output = dir.path().join("fine.obj");
    let o = output.to_str().unwrap();
    // fandisk, the built-in example: 12946 faces.
    let fandisk = concat!(env!("CARGO_MANIFEST_DIR"), "/data/fandisk.obj");
    let run = |extra: &[&str]| {
        let mut all = vec!["subdivide", fandisk, "-o", o, "-q"];
        all.extend(extra);
        crestline(&all)
    };
    // A bound of the user's: 12946 · 4² = 207136 faces is too many, one level fits.
    let out = run(&["--levels", "2", "--max-faces", "100000"]);
    let err = stderr(&out);
    assert!(!out.status.success() && !err.contains("panicked"), "{err}");
    assert!(
        err.contains("207136 faces")
            && err.contains("at most 1 level stays under it (51784 faces)"),
        "{err}"
    );
    // The default bound: 8 levels would make 848 million faces (tens of GB), 5 fit.
    let out = run(&["--levels", "8"]);
    let err = stderr(&out);
    assert!(!out.status.success() && !err.contains("panicked"), "{err}");
    assert!(
        err.contains("8 levels") && err.contains("848429056 faces"),
        "{err}"
    );
    assert!(
        err.contains("at most 5 levels") && err.contains("--max-faces"),
        "{err}"
    );
    assert!(!output.exists());
    // The bound itself is allowed.
    let out = run(&["--levels", "1", "--max-faces", "51784"]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert_eq!(read_mesh(&output, None).unwrap().num_faces(), 51784);
}
