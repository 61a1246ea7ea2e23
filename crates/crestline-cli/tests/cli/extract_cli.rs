//! `crestline extract`: `--stats=json` as the CGAL comparison (bench/compare) reads it, the
//! counts of each kind of line, and smoothing options that take effect.

// Test code: stopping loudly on the first surprise is the point.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use crate::common::{crestline, crestline_ok, fails, stderr};

const FANDISK: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/data/fandisk.obj");

#[test]
fn json_stats_time_every_step_and_count_the_written_lines() {
    let dir = tempfile::tempdir().unwrap();
    let output = dir.path().join("lines.obj");
    // fandisk, the built-in example.
    let out = crestline_ok([
        "extract",
        concat!(env!("CARGO_MANIFEST_DIR"), "/data/fandisk.obj"),
        "-o",
        output.to_str().unwrap(),
        "--stats=json",
        "-q",
    ]);
    let stats: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    for key in ["load_seconds", "write_seconds"] {
        let t = stats[key].as_f64().unwrap_or(-1.0);
        assert!(t >= 0.0, "{key}: {}", stats[key]);
    }
    let stages = stats["stage_seconds"].as_object().unwrap();
    assert!(stages.contains_key("curvature"), "{stages:?}");
    let written = std::fs::read_to_string(&output).unwrap();
    let polylines = written.lines().filter(|l| l.starts_with("l ")).count();
    assert_eq!(stats["lines"].as_u64().unwrap() as usize, polylines);
    assert_eq!(stats["triangles"].as_u64().unwrap(), 12946);
}

/// Runs `crestline extract FANDISK` with `extra` arguments, the lines on standard output.
fn fandisk_lines(extra: &[&str]) -> Vec<u8> {
    let mut args = vec!["extract", FANDISK, "-o", "-", "-q"];
    args.extend(extra);
    crestline_ok(args).stdout
}

#[test]
fn a_smoothing_option_given_makes_the_smoothing_run_on_a_clean_mesh() {
    // fandisk is clean: by default its extremalities are not smoothed, so a smoothing option
    // that changed nothing would do so in silence.
    let default = fandisk_lines(&[]);
    let given = fandisk_lines(&["--smooth-time", "50"]);
    assert_ne!(default, given, "--smooth-time 50 changed nothing");
    // The steps that run are the default 2.
    assert_eq!(
        given,
        fandisk_lines(&["--smooth-time", "50", "--smooth-steps", "2"])
    );
    assert_ne!(
        default,
        fandisk_lines(&["--mask-box", "-9,-9,-9,9,9,9,0.5"])
    );
    assert_ne!(default, fandisk_lines(&["--no-twicing"]));
    // --smooth-steps 0 turns it off: the other smoothing options are refused with it.
    let err = fails(crestline(&[
        "extract",
        FANDISK,
        "-o",
        "-",
        "--smooth-steps",
        "0",
        "--smooth-time",
        "5",
    ]));
    assert!(
        err.contains("--smooth-time") && err.contains("--smooth-steps 0"),
        "{err}"
    );
    // The help states the real default, for every method (saliency links crest points).
    let help = String::from_utf8(crestline_ok(["extract", "--help"]).stdout).unwrap();
    assert!(!help.contains("default 2;"), "{help}");
    assert!(help.contains("Default: automatic"), "{help}");
    let steps = help
        .split("--smooth-steps <")
        .nth(1)
        .and_then(|rest| rest.split("\n\n").next())
        .unwrap_or_else(|| panic!("no --smooth-steps in {help}"));
    assert!(!steps.contains("HPW and YBS"), "{steps}");
}

#[test]
fn ridges_count_crest_lines_alike_in_the_summary_the_table_and_the_json_file() {
    let dir = tempfile::tempdir().unwrap();
    let output = dir.path().join("lines.json");
    let run = crestline_ok([
        "extract",
        FANDISK,
        "-o",
        output.to_str().unwrap(),
        "--stats=json",
    ]);
    let file: serde_json::Value = serde_json::from_slice(&std::fs::read(&output).unwrap()).unwrap();
    let stats: serde_json::Value = serde_json::from_slice(&run.stdout).unwrap();
    let count = |key: &str| file[key].as_u64().unwrap();
    // `--stats json` (the library's figures, as Python's `Lines.stats`) counts as the lines
    // file does, with the same keys (it once said 36 ridges and 6 valleys, creases included).
    for key in ["ridges", "valleys", "crease_ridges", "crease_valleys"] {
        assert_eq!(stats[key].as_u64().unwrap(), count(key), "{key}: {stats}");
    }
    // fandisk: a few crest lines, many creases (convex ones are crease ridges).
    assert!(count("crease_ridges") > count("ridges"), "{file}");
    assert_eq!(
        count("ridges") + count("valleys") + count("crease_ridges") + count("crease_valleys"),
        stats["lines"].as_u64().unwrap()
    );
    assert_eq!(
        count("crease_ridges") + count("crease_valleys"),
        stats["creases"].as_u64().unwrap()
    );
    // The summary on stderr counts as the lines file does (it said "36 ridges, 6 valleys").
    let summary = stderr(&run);
    let expected = format!(
        "({} ridges, {} valleys, {} convex and {} concave creases)",
        count("ridges"),
        count("valleys"),
        count("crease_ridges"),
        count("crease_valleys")
    );
    assert!(summary.contains(&expected), "{summary} (wanted {expected})");
    // The batch table's columns count the same way.
    let batch = dir.path().join("batch");
    let (a, b) = (dir.path().join("a.obj"), dir.path().join("b.obj"));
    std::fs::copy(FANDISK, &a).unwrap();
    std::fs::copy(FANDISK, &b).unwrap();
    let run = crestline_ok([
        "extract",
        a.to_str().unwrap(),
        b.to_str().unwrap(),
        "-o",
        batch.to_str().unwrap(),
    ]);
    let table = stderr(&run);
    let row = table.lines().find(|l| l.contains("a.obj")).unwrap();
    let cells: Vec<&str> = row.split_whitespace().collect();
    // mesh, triangles, lines, ridges, valleys, creases, ...
    assert_eq!(cells[3], count("ridges").to_string(), "{table}");
    assert_eq!(cells[4], count("valleys").to_string(), "{table}");
    assert_eq!(cells[5], stats["creases"].to_string(), "{table}");
}

#[test]
fn lengths_of_a_tiny_model_keep_their_significant_digits() {
    // An ellipsoid modelled at a scale of 1e-6: its crest line is about 1.3e-5 long.
    let dir = tempfile::tempdir().unwrap();
    let mesh = crestline::shapes::ellipsoid(3e-6, 2e-6, 1e-6, 4);
    let path = dir.path().join("tiny.obj");
    crestline::io::write_mesh(
        &path,
        &mesh,
        crestline::io::Format::Obj,
        &crestline::io::WriteOptions::default(),
    )
    .unwrap();
    let run = crestline_ok(["extract", path.to_str().unwrap(), "-o", "-", "--stats"]);
    let err = stderr(&run);
    assert!(!err.contains("total length 0.0000 "), "{err}");
    let length = err
        .lines()
        .find_map(|l| l.split("total length ").nth(1))
        .and_then(|rest| rest.split_whitespace().next())
        .unwrap();
    let value: f64 = length.parse().unwrap();
    assert!(value > 1e-6 && value < 1e-4, "{err}");
}
