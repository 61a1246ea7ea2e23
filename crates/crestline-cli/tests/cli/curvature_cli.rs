//! `crestline curvature` writes the documented vertex properties (PLY) and columns (CSV).

// Test code: stopping loudly on the first surprise is the point.
#![allow(clippy::unwrap_used)]

use std::ffi::OsStr;

use crate::common::crestline_ok;

/// Runs `crestline` with `args` on fandisk (the mesh the command uses as its built-in example,
/// inserted after the subcommand) and checks that it succeeded.
fn crestline<I: IntoIterator<Item = S>, S: AsRef<OsStr>>(args: I) {
    let fandisk = concat!(env!("CARGO_MANIFEST_DIR"), "/data/fandisk.obj");
    let mut args: Vec<std::ffi::OsString> =
        args.into_iter().map(|a| a.as_ref().to_owned()).collect();
    args.insert(1, fandisk.into());
    crestline_ok(args);
}

#[test]
fn curvature_writes_ply_properties_and_csv_columns() {
    let dir = tempfile::tempdir().unwrap();
    let ply = dir.path().join("fields.ply");
    crestline([
        OsStr::new("curvature"),
        "--saliency".as_ref(),
        "-o".as_ref(),
        ply.as_os_str(),
    ]);
    let bytes = std::fs::read(&ply).unwrap();
    let end = bytes.windows(10).position(|w| w == b"end_header").unwrap();
    let header = String::from_utf8_lossy(&bytes[..end]);
    // The estimator as the command line spells it (it said `JetFit`).
    assert!(
        header.contains("crestline curvature (jet-fit) of "),
        "{header}"
    );
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
    let args = ["curvature", "--estimator", "cubic-fit", "--csv", "-o"];
    crestline(args.iter().map(OsStr::new).chain([csv.as_os_str()]));
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
    crestline([
        OsStr::new("extract"),
        "--method".as_ref(),
        "ybs".as_ref(),
        "-q".as_ref(),
        "-o".as_ref(),
        lines.as_os_str(),
        "--png".as_ref(),
        png.as_os_str(),
    ]);
    let text = std::fs::read_to_string(&lines).unwrap();
    assert!(text.contains("o ridges"));
    assert!(text.lines().filter(|l| l.starts_with("l ")).count() >= 10);
    assert!(std::fs::read(&png).unwrap().starts_with(b"\x89PNG"));
}

#[test]
fn curvature_saliency_writes_curv_and_saliency_values() {
    // Built-in example (fandisk), cubic fit as the saliency method uses it; CSV keeps full
    // precision, the ascii PLY holds the same values as f32 vertex properties.
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("fields.csv");
    let ply = dir.path().join("fields.ply");
    for (out, extra) in [(&csv, "--csv"), (&ply, "--ascii")] {
        let args = [
            "curvature",
            "--estimator",
            "cubic-fit",
            "--saliency",
            extra,
            "-o",
        ];
        crestline(args.iter().map(OsStr::new).chain([out.as_os_str()]));
    }
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut rows = text.lines();
    let header: Vec<&str> = rows.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let (k_max, k_min, curv, saliency) = (col("k_max"), col("k_min"), col("curv"), col("saliency"));
    assert_eq!(header.len(), 15);
    let values: Vec<Vec<f64>> = rows
        .map(|r| r.split(',').map(|t| t.parse().unwrap()).collect())
        .collect();
    assert_eq!(values.len(), 6475);
    let mut with_variation = 0;
    for row in &values {
        // Curv is the largest absolute principal curvature; S = 0.4 Curv + 0.6 Var, Var ≥ 0.
        assert_eq!(row[curv], row[k_max].abs().max(row[k_min].abs()));
        assert!(row[saliency].is_finite());
        assert!(row[saliency] >= 0.4 * row[curv] * (1.0 - 1e-12), "{row:?}");
        if row[saliency] > 0.4 * row[curv] * (1.0 + 1e-6) {
            with_variation += 1;
        }
    }
    assert!(with_variation > values.len() / 2, "{with_variation}");

    let text = std::fs::read_to_string(&ply).unwrap();
    let (head, body) = text.split_once("end_header\n").unwrap();
    // The vertex element's properties, in order (x, y, z are doubles, the fields floats).
    let properties: Vec<&str> = head
        .lines()
        .skip_while(|l| !l.starts_with("element vertex"))
        .skip(1)
        .take_while(|l| l.starts_with("property"))
        .map(|l| l.rsplit(' ').next().unwrap())
        .collect();
    let at = |name: &str| properties.iter().position(|p| *p == name).unwrap();
    let (ply_curv, ply_saliency) = (at("curv"), at("saliency"));
    assert_eq!(properties.len(), 15);
    for (line, row) in body.lines().zip(&values) {
        // Shortest round-trip f32 text: parsing it gives back the f32 written.
        let fields: Vec<f32> = line
            .split_whitespace()
            .map(|t| t.parse().unwrap())
            .collect();
        assert_eq!(fields[ply_curv], row[curv] as f32);
        assert_eq!(fields[ply_saliency], row[saliency] as f32);
    }
}

/// The CSV columns of `crestline curvature <args> --csv` on `mesh` (header, rows).
fn curvature_csv(mesh: &std::path::Path, args: &[&str]) -> (Vec<String>, Vec<Vec<f64>>) {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("fields.csv");
    let mut run: Vec<&OsStr> = vec!["curvature".as_ref(), mesh.as_ref()];
    run.extend(args.iter().map(OsStr::new));
    run.extend(["--csv", "-q", "-o"].map(OsStr::new));
    run.push(csv.as_ref());
    crestline_ok(run);
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut rows = text.lines();
    let header = rows.next().unwrap().split(',').map(str::to_owned).collect();
    let values = rows
        .map(|r| r.split(',').map(|t| t.parse().unwrap()).collect())
        .collect();
    (header, values)
}

#[test]
fn curvature_does_not_reach_across_creases() {
    // A box of side 2 whose top edges are rounded would do; a plain cylinder of radius 4 with
    // flat caps is simpler: on its rims the side has k = 1/4 around and 0 along, and the
    // caps are flat. Estimated across the rim crease, the fit sees a right angle.
    let dir = tempfile::tempdir().unwrap();
    let mesh = dir.path().join("can.obj");
    let (n, rows, radius, height) = (96usize, 24usize, 4.0f64, 6.0f64);
    let mut obj = String::new();
    for j in 0..=rows {
        for i in 0..n {
            let t = std::f64::consts::TAU * i as f64 / n as f64;
            let z = height * j as f64 / rows as f64;
            obj += &format!("v {} {} {z}\n", radius * t.cos(), radius * t.sin());
        }
    }
    obj += &format!("v 0 0 0\nv 0 0 {height}\n");
    let (bottom, top) = ((rows + 1) * n + 1, (rows + 1) * n + 2);
    let id = |j: usize, i: usize| j * n + (i % n) + 1;
    for j in 0..rows {
        for i in 0..n {
            let (a, b, c, d) = (id(j, i), id(j, i + 1), id(j + 1, i + 1), id(j + 1, i));
            obj += &format!("f {a} {b} {c}\nf {a} {c} {d}\n");
        }
    }
    for i in 0..n {
        obj += &format!("f {bottom} {} {}\n", id(0, i + 1), id(0, i));
        obj += &format!("f {top} {} {}\n", id(rows, i), id(rows, i + 1));
    }
    std::fs::write(&mesh, obj).unwrap();
    let (header, split) = curvature_csv(&mesh, &[]);
    let col = |name: &str| header.iter().position(|h| h == name).unwrap();
    let (z, k_max, k_min) = (col("z"), col("k_max"), col("k_min"));
    let rim: Vec<&Vec<f64>> = split[..(rows + 1) * n]
        .iter()
        .filter(|r| r[z] == 0.0 || r[z] == height)
        .collect();
    assert_eq!(rim.len(), 2 * n);
    for r in &rim {
        // The side's fit (the wider side at the rim): k_max = 1/4, k_min = 0.
        assert!(
            (r[k_max] - 0.25).abs() < 0.05,
            "k_max {} on the rim",
            r[k_max]
        );
        assert!(r[k_min].abs() < 0.12, "k_min {} on the rim", r[k_min]);
    }
    // Across the crease the same vertices see a right angle.
    let (_, merged) = curvature_csv(&mesh, &["--creases", "off"]);
    let worst = merged
        .iter()
        .filter(|r| r[z] == 0.0 || r[z] == height)
        .map(|r| r[k_max].abs().max(r[k_min].abs()))
        .fold(0.0, f64::max);
    assert!(
        worst > 1.0,
        "largest |k| on the rims without the split: {worst}"
    );
}

#[test]
fn curvature_puts_spikes_back_before_estimating() {
    // A unit sphere with two vertices three edges off it: as in `extract`, they are put back
    // before the fits (said on stderr), so every vertex gets the sphere's k = 1, the spikes
    // themselves included, at the file's positions. With --keep-outliers every fit whose
    // disc holds a spike is thrown off.
    let dir = tempfile::tempdir().unwrap();
    let spikes = [100, 1500];
    let mesh = dir.path().join("spiky.obj");
    let positions = crate::common::write_spiky_sphere(&mesh, 4, &spikes);
    let csv = dir.path().join("fields.csv");
    let said = crate::common::stderr(&crestline_ok([
        "curvature".as_ref(),
        mesh.as_os_str(),
        "-o".as_ref(),
        csv.as_os_str(),
    ]));
    assert!(said.contains("2 outlier vertices"), "{said}");
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    let header: Vec<String> = lines
        .next()
        .unwrap()
        .split(',')
        .map(str::to_owned)
        .collect();
    let repaired: Vec<Vec<f64>> = lines
        .map(|r| r.split(',').map(|t| t.parse().unwrap()).collect())
        .collect();
    let worst = |rows: &[Vec<f64>], header: &[String]| {
        let col = |name: &str| header.iter().position(|h| h == name).unwrap();
        let (k_max, k_min) = (col("k_max"), col("k_min"));
        rows.iter()
            .map(|r| (r[k_max] - 1.0).abs().max((r[k_min] - 1.0).abs()))
            .fold(0.0, f64::max)
    };
    assert!(
        worst(&repaired, &header) < 0.05,
        "{}",
        worst(&repaired, &header)
    );
    // The rows are the file's vertices, where they are.
    for v in spikes {
        let p = positions[v];
        for (k, x) in [p.x, p.y, p.z].into_iter().enumerate() {
            assert!(
                (repaired[v][k] - x).abs() < 1e-6,
                "{:?} against {p:?}",
                repaired[v]
            );
        }
    }
    let (header, kept) = curvature_csv(&mesh, &["--keep-outliers"]);
    assert!(worst(&kept, &header) > 0.5, "{}", worst(&kept, &header));
}
