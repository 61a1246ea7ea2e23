//! Where outputs go and in which format: `-` is standard output for every output (pictures
//! of `extract` too), one output at most on it, and an output whose extension names another
//! format than the one written is refused before any work.

// Test code: stopping loudly on the first surprise is the point.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::path::Path;
use std::process::{Command, Output};

use crate::common::{fails, listing, ok, s};

const FANDISK: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/data/fandisk.obj");

/// Runs `crestline` with `args` in the folder `dir` (a stray file named `-` would land there).
fn run_in(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_crestline"))
        .args(args)
        .current_dir(dir)
        .output()
        .unwrap()
}

#[test]
fn pictures_of_extract_go_to_standard_output_for_dash() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let lines = d.join("l.obj");
    for (flag, start) in [
        ("--png", &b"\x89PNG\r\n"[..]),
        ("--svg", b"<?xml"),
        ("--html", b"<!DOCTYPE html>"),
    ] {
        let out = ok(run_in(
            d,
            &["extract", FANDISK, "-o", s(&lines), flag, "-", "-q"],
        ));
        assert!(
            out.stdout.starts_with(start),
            "{flag}: {:?}",
            String::from_utf8_lossy(&out.stdout[..out.stdout.len().min(40)])
        );
        // The lines went to their file, and no file is named `-`.
        assert_eq!(listing(d), vec!["l.obj"], "{flag}");
    }
}

#[test]
fn two_outputs_on_standard_output_are_refused_before_the_work() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let lines = d.join("l.obj");
    for (args, named) in [
        (vec!["-o", "-", "--png", "-"], "-o - and --png -"),
        (
            vec!["-o", s(&lines), "--svg", "-", "--stats=json"],
            "--stats=json and --svg -",
        ),
        (
            vec!["-o", s(&lines), "--png", "-", "--html", "-"],
            "--png - and --html -",
        ),
    ] {
        let mut all = vec!["extract", FANDISK];
        all.extend(&args);
        let out = run_in(d, &all);
        let err = fails(out.clone());
        assert!(
            err.contains(named) && err.contains("standard output"),
            "{args:?}: {err}"
        );
        assert!(out.stdout.is_empty(), "{args:?}");
        assert!(listing(d).is_empty(), "{args:?}: {:?}", listing(d));
    }
}

#[test]
fn the_curvature_table_follows_the_extension() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("fields.csv");
    ok(run_in(
        dir.path(),
        &["curvature", FANDISK, "-o", s(&csv), "-q"],
    ));
    let text = std::fs::read_to_string(&csv).unwrap();
    assert!(text.starts_with("x,y,z,k_max,k_min,"), "{}", &text[..40]);
    // One row per vertex after the header.
    assert_eq!(text.lines().count(), 6475 + 1);
}

#[test]
fn an_extension_of_another_format_is_refused_before_the_work() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let o = |name: &str| d.join(name).to_str().unwrap().to_string();
    let cases: [(Vec<String>, &str, &str); 9] = [
        (
            vec!["curvature".into(), "-o".into(), o("x.ply"), "--csv".into()],
            "x.ply",
            ".csv",
        ),
        (
            vec!["curvature".into(), "-o".into(), o("x.obj")],
            "x.obj",
            ".ply",
        ),
        (
            vec!["view".into(), "-o".into(), o("v.png")],
            "v.png",
            "render",
        ),
        (
            vec![
                "render".into(),
                "-o".into(),
                o("r.png"),
                "--format".into(),
                "svg".into(),
            ],
            "r.png",
            ".svg",
        ),
        (
            vec!["extract".into(), "-o".into(), o("l.off")],
            "l.off",
            ".obj",
        ),
        (
            vec![
                "extract".into(),
                "-o".into(),
                o("l.obj"),
                "--format".into(),
                "json".into(),
            ],
            "l.obj",
            ".json",
        ),
        (
            vec![
                "extract".into(),
                "-o".into(),
                o("l.obj"),
                "--png".into(),
                o("p.svg"),
            ],
            "p.svg",
            ".png",
        ),
        (
            vec![
                "subdivide".into(),
                "-o".into(),
                o("s.obj"),
                "--format".into(),
                "off".into(),
            ],
            "s.obj",
            ".off",
        ),
        (
            vec![
                "simplify".into(),
                "-o".into(),
                o("s.ply"),
                "--format".into(),
                "obj".into(),
                "--eta".into(),
                "0".into(),
            ],
            "s.ply",
            ".obj",
        ),
    ];
    for (args, file, remedy) in cases {
        let mut all = vec![args[0].as_str(), FANDISK];
        all.extend(args[1..].iter().map(String::as_str));
        let err = fails(run_in(d, &all));
        assert!(
            err.contains(file) && err.contains("would be written") && err.contains(remedy),
            "{args:?}: {err}"
        );
        // Refused before anything was written.
        assert!(listing(d).is_empty(), "{args:?}: {:?}", listing(d));
    }
}
