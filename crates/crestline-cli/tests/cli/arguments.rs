//! Option values as users type them: counts that are negative get a message saying what is
//! expected, negative numbers reach the options that take them, and values too large to make
//! sense are refused before any work.

// Test code: stopping loudly on the first surprise is the point.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use crate::common::{crestline, fails, listing, ok, s};

const FANDISK: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/data/fandisk.obj");

#[test]
fn a_negative_count_is_said_to_need_a_non_negative_integer() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.obj");
    for args in [
        vec!["extract", "--pre-smooth", "-1"],
        vec!["extract", "--smooth-steps", "-2"],
        vec!["extract", "--smooth-steps=-2"],
        vec!["extract", "--pre-smooth", "1.5"],
        vec!["subdivide", "--levels", "-1"],
        vec!["subdivide", "--max-faces", "-1"],
        vec!["simplify", "--faces", "-1"],
    ] {
        let mut all = vec![args[0], FANDISK, "-o", s(&out)];
        all.extend(&args[1..]);
        let err = fails(crestline(&all));
        assert!(
            err.contains("expected a non-negative integer") && !err.contains("invalid digit"),
            "{args:?}: {err}"
        );
        // Not taken for a flag of its own ("unexpected argument '-1'").
        assert!(
            err.contains(&format!("for '{}", args[1].split('=').next().unwrap())),
            "{err}"
        );
    }
    // The rings keep their own range, stated the same way for -1.
    let err = fails(crestline(&[
        "extract",
        FANDISK,
        "-o",
        s(&out),
        "--rings",
        "-1",
    ]));
    assert!(err.contains("from 1 to 8, got '-1'"), "{err}");
    assert!(listing(dir.path()).is_empty());
}

#[test]
fn negative_coordinates_reach_the_mask_regions() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.obj");
    // fandisk's bounding box holds (-1, 0, 0); the sphere damps the smoothing there.
    ok(crestline(&[
        "extract",
        FANDISK,
        "-o",
        s(&out),
        "--mask-sphere",
        "-1,0,0,1,0.5",
        "--mask-box",
        "-2,-2,-2,-1,-1,-1,0.5",
        "-q",
    ]));
    assert!(out.exists());
}

#[test]
fn a_jet_fit_radius_or_smoothing_step_beyond_any_mesh_is_refused_before_the_work() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.obj");
    let csv = dir.path().join("out.csv");
    for (args, expected) in [
        (vec!["extract", "--radius", "1e6"], "at most 10"),
        (vec!["extract", "--radius", "10.5"], "at most 10"),
        (vec!["curvature", "--radius", "1e6"], "at most 10"),
        (vec!["extract", "--smooth-time", "1e9"], "at most 1e6"),
        (vec!["extract", "--smooth-time", "1e300"], "at most 1e6"),
    ] {
        let output = if args[0] == "curvature" { &csv } else { &out };
        let mut all = vec![args[0], FANDISK, "-o", s(output)];
        all.extend(&args[1..]);
        let err = fails(crestline(&all));
        assert!(err.contains(expected), "{args:?}: {err}");
        // Refused before the work: no summary of an extraction, no solver error.
        assert!(!err.contains("lines (") && !err.contains("solver"), "{err}");
        assert!(listing(dir.path()).is_empty(), "{args:?}");
    }
    // A batch refuses it once, not once per mesh.
    let (a, b) = (dir.path().join("a.obj"), dir.path().join("b.obj"));
    std::fs::copy(FANDISK, &a).unwrap();
    std::fs::copy(FANDISK, &b).unwrap();
    let batch = dir.path().join("batch");
    let err = fails(crestline(&[
        "extract",
        s(&a),
        s(&b),
        "-o",
        s(&batch),
        "--smooth-time",
        "1e9",
    ]));
    assert_eq!(err.matches("at most 1e6").count(), 1, "{err}");
    assert!(!batch.exists());
    // The help states the same bound as the error.
    let help = String::from_utf8(ok(crestline(&["curvature", "--help"])).stdout).unwrap();
    assert!(help.contains("at most 10"), "{help}");
    // The largest step allowed is a strong smoothing, not a solver failure.
    ok(crestline(&[
        "extract",
        FANDISK,
        "-o",
        s(&out),
        "--smooth-steps",
        "2",
        "--smooth-time",
        "1e6",
        "-q",
    ]));
    assert!(out.exists());
}

#[test]
fn simplify_weights_out_of_range_are_refused_before_the_mesh_is_read() {
    // The mesh does not exist: the error about eta comes first, before any extraction.
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("missing.obj");
    let out = dir.path().join("out.obj");
    for (flag, value, says) in [
        ("--eta", "-1", "eta must be"),
        ("--eps", "0", "eps must be"),
    ] {
        let err = fails(crestline(&[
            "simplify",
            s(&missing),
            "-o",
            s(&out),
            flag,
            value,
        ]));
        assert!(err.contains(says) && !err.contains("missing.obj"), "{err}");
    }
}

#[test]
fn negative_mask_factors_are_refused_as_they_are_parsed() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.obj");
    for (flag, value, says) in [
        (
            "--mask-box",
            "0,0,0,1,1,1,-1",
            "factor '-1' must be a finite number >= 0",
        ),
        (
            "--mask-sphere",
            "0,0,0,1,-0.5",
            "factor '-0.5' must be a finite number >= 0",
        ),
        (
            "--mask-sphere",
            "0,0,0,-1,1",
            "radius '-1' must be a number >= 0",
        ),
        ("--mask-box", "0,0,0,1,1,1,inf", "finite numbers"),
    ] {
        // Without --smooth-steps (the smoothing may not run) and with it (the error came
        // late, from the solver's input check, naming no flag).
        for steps in [None, Some("2")] {
            let mut all = vec!["extract", FANDISK, "-o", s(&out), flag, value];
            if let Some(n) = steps {
                all.extend(["--smooth-steps", n]);
            }
            let err = fails(crestline(&all));
            assert!(err.contains(says) && err.contains(flag), "{all:?}: {err}");
            assert!(!err.contains("diffusion factors"), "{err}");
        }
    }
    assert!(listing(dir.path()).is_empty());
}

#[test]
fn smoothing_along_the_lines_out_of_range_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.obj");
    for (extra, says) in [
        (
            vec!["--smooth-along", "0"],
            "expected a number > 0, got '0'",
        ),
        (
            vec!["--smooth-along", "-3"],
            "expected a number > 0, got '-3'",
        ),
        (vec!["--smooth-along", "1e7"], "at most 1e6"),
        (
            vec!["--smooth-along", "2", "--smooth-steps", "0"],
            "--smooth-along: the extremality smoothing they set does not run with --smooth-steps 0",
        ),
    ] {
        let mut all = vec!["extract", FANDISK, "-o", s(&out)];
        all.extend(&extra);
        let err = fails(crestline(&all));
        assert!(err.contains(says), "{all:?}: {err}");
    }
    assert!(listing(dir.path()).is_empty());
}
