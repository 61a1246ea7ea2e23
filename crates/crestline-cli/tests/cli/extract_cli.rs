//! `crestline extract --stats=json` as the CGAL comparison (bench/compare) reads it.

// Test code: stopping loudly on the first surprise is the point.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use crate::common::crestline_ok;

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
