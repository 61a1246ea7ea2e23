//! `crestline curvature` writes the documented vertex properties (PLY) and columns (CSV).

use std::process::Command;

#[test]
fn curvature_writes_ply_properties_and_csv_columns() {
    let dir = tempfile::tempdir().unwrap();
    let ply = dir.path().join("fields.ply");
    let out = Command::new(env!("CARGO_BIN_EXE_crestline"))
        .args(["curvature", "--saliency", "-o"])
        .arg(&ply)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let bytes = std::fs::read(&ply).unwrap();
    let end = bytes.windows(10).position(|w| w == b"end_header").unwrap();
    let header = String::from_utf8_lossy(&bytes[..end]);
    for p in [
        "k_max",
        "k_min",
        "e_max",
        "e_min",
        "dir_max_x",
        "dir_max_y",
        "dir_max_z",
        "dir_min_x",
        "dir_min_y",
        "dir_min_z",
        "curv",
        "saliency",
    ] {
        assert!(
            header.contains(&format!("property float {p}\n")),
            "{p} missing in\n{header}"
        );
    }
    assert!(header.contains("element vertex 6475"));

    let csv = dir.path().join("fields.csv");
    let out = Command::new(env!("CARGO_BIN_EXE_crestline"))
        .args(["curvature", "--estimator", "cubic-fit", "--csv", "-o"])
        .arg(&csv)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut rows = text.lines();
    assert_eq!(
        rows.next().unwrap(),
        "x,y,z,k_max,k_min,e_max,e_min,dir_max_x,dir_max_y,dir_max_z,dir_min_x,dir_min_y,dir_min_z"
    );
    let first: Vec<f64> = rows
        .next()
        .unwrap()
        .split(',')
        .map(|t| t.parse().unwrap())
        .collect();
    assert_eq!(first.len(), 13);
    assert!(first.iter().all(|x| x.is_finite()));
    // k_max >= k_min, unit directions.
    assert!(first[3] >= first[4]);
    let norm = (first[7].powi(2) + first[8].powi(2) + first[9].powi(2)).sqrt();
    assert!((norm - 1.0).abs() < 1e-6);
    assert_eq!(text.lines().count(), 6476);
}

#[test]
fn extract_writes_lines_and_a_picture() {
    let dir = tempfile::tempdir().unwrap();
    let lines = dir.path().join("lines.obj");
    let png = dir.path().join("lines.png");
    let out = Command::new(env!("CARGO_BIN_EXE_crestline"))
        .args(["extract", "--method", "ybs", "-q", "-o"])
        .arg(&lines)
        .arg("--png")
        .arg(&png)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = std::fs::read_to_string(&lines).unwrap();
    assert!(text.contains("o ridges"));
    assert!(text.lines().filter(|l| l.starts_with("l ")).count() >= 10);
    assert!(std::fs::read(&png).unwrap().starts_with(b"\x89PNG"));
}
