//! The command-line tool composes (issue 24): every lines file `extract` writes is read back by
//! every command taking `--lines`; standard input and output; batches; orientation decided in
//! one place; one meaning per flag with ranges checked up front; progress flags everywhere.

// Test code: stopping loudly on the first surprise is the point.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

use crate::common::{crestline as run, fails, ok, s, shared_meshes_dir, stderr};
use crestline::io::lines::read_lines;
use crestline::io::{Format, WriteOptions, write_mesh};
use crestline::lines::FeatureLines;

const FANDISK: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/data/fandisk.obj");

/// Runs with `input` on standard input.
fn run_with_stdin(args: &[&str], input: &[u8]) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_crestline"))
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    child.stdin.take().unwrap().write_all(input).unwrap();
    child.wait_with_output().unwrap()
}

/// The ellipsoid x²/9 + y²/4 + z² = 1 (1280 triangles), one closed ridge, as OBJ in `dir`;
/// with `inward`, every triangle reversed.
fn ellipsoid(dir: &Path, name: &str, inward: bool) -> PathBuf {
    let mesh = crestline::shapes::ellipsoid(3.0, 2.0, 1.0, 3);
    let mesh = if inward {
        let faces = mesh.faces().iter().map(|t| [t[0], t[2], t[1]]).collect();
        crestline::TriMesh::new(mesh.positions().to_vec(), faces).unwrap()
    } else {
        mesh
    };
    let path = dir.join(name);
    write_mesh(&path, &mesh, Format::Obj, &WriteOptions::default()).unwrap();
    path
}

/// (kind name, points, strength) of every line, in a fixed order.
fn summary(lines: &FeatureLines) -> Vec<(String, usize, u64)> {
    let mut v: Vec<_> = lines
        .lines
        .iter()
        .map(|l| {
            (
                l.kind_name().to_string(),
                l.points.len(),
                l.strength.to_bits(),
            )
        })
        .collect();
    v.sort();
    v
}

#[test]
fn lines_in_every_format_read_back_by_every_command_that_takes_them() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let mut pictures = Vec::new();
    let mut read = Vec::new();
    for ext in ["obj", "ply", "json"] {
        let lines = d.join(format!("lines.{ext}"));
        ok(run(&["extract", FANDISK, "-o", s(&lines), "-q"]));
        read.push(summary(&read_lines(&lines, None).unwrap()));
        let png = d.join(format!("{ext}.png"));
        ok(run(&[
            "render",
            FANDISK,
            "--lines",
            s(&lines),
            "-o",
            s(&png),
            "--size",
            "256",
            "-q",
        ]));
        pictures.push(std::fs::read(&png).unwrap());
        // distance and simplify read the same lines: none unreached, same count.
        let far = d.join(format!("{ext}-distance.ply"));
        let out = ok(run(&[
            "distance",
            FANDISK,
            "--lines",
            s(&lines),
            "-o",
            s(&far),
        ]));
        let err = stderr(&out);
        assert!(err.contains(" 0 vertices unreached"), "{ext}: {err}");
        assert!(!err.contains("no --lines given"), "{ext}: {err}");
        let small = d.join(format!("{ext}-small.obj"));
        let out = ok(run(&[
            "simplify",
            FANDISK,
            "--lines",
            s(&lines),
            "-o",
            s(&small),
            "--faces",
            "6000",
            "--json",
        ]));
        let report: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        assert_eq!(
            report["lines"].as_u64().unwrap() as usize,
            read[0].len(),
            "{ext}"
        );
        assert!(
            report["creases"].as_u64().unwrap() > 0,
            "{ext}: crease kinds kept"
        );
    }
    // Kinds (crease kinds included), point counts and strengths survive every format.
    assert!(
        read[0].iter().any(|l| l.0 == "crease-valley"),
        "{:?}",
        read[0]
    );
    assert!(read[0].iter().any(|l| l.2 != 0), "strengths kept");
    assert_eq!(read[0], read[1], "OBJ and PLY");
    assert_eq!(read[0], read[2], "OBJ and JSON");
    // The same lines are drawn, and lines are drawn at all.
    assert!(pictures[0] == pictures[1] && pictures[0] == pictures[2]);
    let bare = d.join("bare.png");
    ok(run(&[
        "render",
        FANDISK,
        "-o",
        s(&bare),
        "--size",
        "256",
        "-q",
    ]));
    assert!(std::fs::read(&bare).unwrap() != pictures[0]);
}

#[test]
fn a_file_that_holds_no_lines_is_an_error_not_no_lines() {
    let dir = tempfile::tempdir().unwrap();
    let hello = dir.path().join("hello.obj");
    std::fs::write(&hello, "hello\n").unwrap();
    let png = dir.path().join("x.png");
    let err = fails(run(&[
        "render",
        FANDISK,
        "--lines",
        s(&hello),
        "-o",
        s(&png),
    ]));
    assert!(
        err.contains("hello.obj: line 1: 'hello' is not an OBJ record"),
        "{err}"
    );
    // A mesh is not a lines file either, nor is an unknown extension.
    let html = dir.path().join("x.html");
    let err = fails(run(&["view", FANDISK, "--lines", FANDISK, "-o", s(&html)]));
    assert!(err.contains("no polylines"), "{err}");
    let txt = dir.path().join("lines.txt");
    std::fs::write(&txt, "l 1 2\n").unwrap();
    let out = dir.path().join("d.ply");
    let err = fails(run(&[
        "distance",
        FANDISK,
        "--lines",
        s(&txt),
        "-o",
        s(&out),
    ]));
    assert!(err.contains("cannot tell the feature-line format"), "{err}");
    // A mesh file holding just "hello" has no triangles: an error, not "0 lines".
    let err = fails(run(&[
        "extract",
        s(&hello),
        "-o",
        s(&dir.path().join("l.obj")),
    ]));
    // (The reader finds no vertex in it; a file with vertices but no triangle gets "no
    // triangles" from the CLI.)
    assert!(
        err.contains("hello.obj") && err.contains("no vertices"),
        "{err}"
    );
}

#[test]
fn standard_input_and_output() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = ellipsoid(dir.path(), "e.obj", false);
    let bytes = std::fs::read(&mesh).unwrap();
    // `-` reads standard input, `-o -` writes standard output, notes stay on stderr.
    let out = ok(run_with_stdin(
        &["extract", "-", "--input-format", "obj", "-o", "-"],
        &bytes,
    ));
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(
        text.starts_with("# crestline feature lines: 1 ridges"),
        "{text}"
    );
    assert!(!Path::new("-").exists());
    // Without a mesh, data on standard input is read (not the built-in example).
    let out = ok(run_with_stdin(
        &[
            "extract",
            "--input-format",
            "obj",
            "-o",
            "-",
            "--format",
            "json",
        ],
        &bytes,
    ));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["ridges"], 1);
    assert!(!stderr(&out).contains("built-in"), "{}", stderr(&out));
    // Other commands too.
    let out = ok(run_with_stdin(
        &["info", "--input-format", "obj", "--json"],
        &bytes,
    ));
    let info: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(info["faces"], 1280);
    let out = ok(run_with_stdin(
        &[
            "subdivide",
            "-",
            "--input-format",
            "obj",
            "-o",
            "-",
            "--format",
            "off",
        ],
        &bytes,
    ));
    assert!(out.stdout.starts_with(b"OFF\n"));
    // Standard input without its format, and empty standard input, are clear errors.
    let err = fails(run_with_stdin(&["extract", "-", "-o", "-"], &bytes));
    assert!(err.contains("--input-format"), "{err}");
    let err = fails(run_with_stdin(&["info", "--input-format", "obj"], b""));
    assert!(err.contains("standard input is empty"), "{err}");
    assert!(err.contains("not a terminal"), "{err}");
    // A mesh written to standard output needs its format.
    let err = fails(run(&["subdivide", s(&mesh), "-o", "-"]));
    assert!(err.contains("--format"), "{err}");
}

#[test]
fn the_built_in_example_only_when_standard_input_is_a_terminal() {
    // `script` runs the command on a pseudo-terminal (util-linux; skipped where missing).
    let command = format!("{} info", env!("CARGO_BIN_EXE_crestline"));
    let out = match Command::new("script")
        .args(["-qec", &command, "/dev/null"])
        .stdin(Stdio::null())
        .output()
    {
        Ok(out) if out.status.success() => out,
        other => {
            eprintln!("SKIPPED: no working `script` to give the command a terminal: {other:?}");
            return;
        }
    };
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("using the built-in example"), "{text}");
    assert!(text.contains("faces                  12946"), "{text}");
    // Not a terminal, with data: standard input is read (its format must be given), never
    // the example.
    let err = fails(run_with_stdin(&["info"], b"v 0 0 0\n"));
    assert!(
        err.contains("--input-format") && !err.contains("built-in example (fandisk"),
        "{err}"
    );
    // Not a terminal and empty (a script or CI with nothing piped in), no format given: the
    // example, said on stderr, as README's first command needs.
    let out = ok(run_with_stdin(&["info"], b""));
    assert!(
        stderr(&out).contains("standard input is empty: using the built-in example"),
        "{}",
        stderr(&out)
    );
    // With --input-format, an empty standard input is an error.
    let err = fails(run_with_stdin(&["info", "--input-format", "obj"], b""));
    assert!(err.contains("standard input is empty"), "{err}");
}

#[test]
fn every_command_orients_the_mesh_as_extract_does() {
    let dir = tempfile::tempdir().unwrap();
    let outward = ellipsoid(dir.path(), "out.obj", false);
    let inward = ellipsoid(dir.path(), "in.obj", true);
    // render and view colour the same field on both windings (k_max is positive on the
    // ellipsoid only with outward normals).
    let mut pictures = Vec::new();
    for mesh in [&outward, &inward] {
        let png = dir.path().join(format!("{}.png", pictures.len()));
        let out = ok(run(&[
            "render",
            s(mesh),
            "--field",
            "k_max",
            "-o",
            s(&png),
            "--size",
            "200",
        ]));
        if mesh == &inward {
            assert!(stderr(&out).contains("faced inward"), "{}", stderr(&out));
        }
        pictures.push(std::fs::read(&png).unwrap());
    }
    assert!(pictures[0] == pictures[1], "render does not orient");
    let keep = dir.path().join("keep.png");
    ok(run(&[
        "render",
        s(&inward),
        "--field",
        "k_max",
        "-o",
        s(&keep),
        "--size",
        "200",
        "--keep-orientation",
    ]));
    assert!(std::fs::read(&keep).unwrap() != pictures[0]);
}

#[test]
fn the_library_and_the_cli_find_the_same_ridges_and_valleys_on_the_inward_horse() {
    let horse = shared_meshes_dir().join("horse.ply");
    let dir = tempfile::tempdir().unwrap();
    let out = ok(run(&[
        "extract",
        s(&horse),
        "-o",
        s(&dir.path().join("l.obj")),
        "--stats=json",
        "-q",
    ]));
    let cli: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let mesh = crestline::io::read_mesh(&horse, None).unwrap();
    let library = crestline::extract::extract(&mesh, &Default::default()).unwrap();
    assert!(
        library.stats.orientation.inward > 0,
        "the horse faces inward"
    );
    assert_eq!(
        (library.stats.ridges, library.stats.valleys),
        (
            cli["ridges"].as_u64().unwrap() as usize,
            cli["valleys"].as_u64().unwrap() as usize
        )
    );
    assert!(
        library.stats.ridges > library.stats.valleys,
        "{:?}",
        library.stats
    );
}

#[test]
fn one_meaning_per_flag_and_ranges_checked_up_front() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = ellipsoid(dir.path(), "e.obj", false);
    let named_txt = dir.path().join("e.txt");
    std::fs::copy(&mesh, &named_txt).unwrap();
    let o = dir.path().join("o.ply");
    // --input-format is the input's format in every command that reads a mesh.
    for args in [
        vec!["info", s(&named_txt)],
        vec!["curvature", s(&named_txt), "-o", s(&o)],
        vec!["distance", s(&named_txt), "-o", s(&o)],
        vec!["subdivide", s(&named_txt), "-o", s(&o)],
        vec!["simplify", s(&named_txt), "-o", s(&o), "--eta", "0"],
        vec![
            "render",
            s(&named_txt),
            "-o",
            s(&dir.path().join("p.png")),
            "--size",
            "64",
        ],
    ] {
        let mut all = args.clone();
        all.extend(["--input-format", "obj", "-q"]);
        ok(run(&all));
        // --format is an output format: it is no longer taken as the input's.
        let mut all = args.clone();
        all.extend(["--format", "obj"]);
        if args[0] == "info" || args[0] == "curvature" || args[0] == "distance" {
            fails(run(&all));
        }
    }
    // --rings: the same range in the help and in the error, the library's.
    let max = crestline::curvature::cubic_fit::MAX_RINGS;
    let help = String::from_utf8(ok(run(&["extract", "--help"])).stdout).unwrap();
    assert!(help.contains(&format!("1 to {max}")), "{help}");
    let err = fails(run(&[
        "extract",
        s(&mesh),
        "--method",
        "ybs",
        "--rings",
        "9",
    ]));
    assert!(err.contains(&format!("from 1 to {max}")), "{err}");
    let err = fails(run(&[
        "curvature",
        s(&mesh),
        "-o",
        s(&o),
        "--estimator",
        "cubic-fit",
        "--rings",
        "0",
    ]));
    assert!(err.contains(&format!("from 1 to {max}")), "{err}");
    // Options the method does not use are refused.
    for (args, flag) in [
        (vec!["--method", "saliency", "--no-gaps"], "--no-gaps"),
        (vec!["--method", "hpw", "--no-gaps"], "--no-gaps"),
        (
            vec!["--estimator", "shape-operator", "--radius", "3"],
            "--radius",
        ),
        (vec!["--direction-support", "1"], "--direction-support"),
        (vec!["--rings", "2", "--no-debias"], "--no-debias"),
        (vec!["--rings", "2", "--keep-unlocated"], "--keep-unlocated"),
        (
            vec!["--estimator", "shape-operator", "--smooth-along", "2"],
            "--smooth-along",
        ),
        (
            vec!["--method", "saliency", "--keep-unlocated"],
            "--keep-unlocated",
        ),
    ] {
        let mut all = vec!["extract", s(&mesh), "-o", s(&o)];
        all.extend(&args);
        let err = fails(run(&all));
        assert!(
            err.contains(flag) && err.contains("would not use"),
            "{args:?}: {err}"
        );
    }
    // The correction is the default: the flag of when it was opt-in is accepted, not with
    // its opposite.
    assert!(
        run(&["extract", s(&mesh), "-o", s(&o), "-q", "--debias"])
            .status
            .success()
    );
    let err = fails(run(&[
        "extract",
        s(&mesh),
        "-o",
        s(&o),
        "--debias",
        "--no-debias",
    ]));
    assert!(err.contains("cannot be used with"), "{err}");
    // Smoothing steps have a ceiling: more ran for ever.
    for flag in ["--smooth-steps", "--pre-smooth"] {
        let err = fails(run(&["extract", s(&mesh), "-o", s(&o), flag, "1000000000"]));
        assert!(
            err.contains("steps must be at most 1000, got 1000000000"),
            "{flag}: {err}"
        );
    }
    // simplify refuses a bad ratio before extracting anything.
    let err = fails(run(&["simplify", s(&mesh), "-o", s(&o), "--ratio", "2"]));
    assert!(
        err.contains("(0, 1]") && !err.contains("extracting"),
        "{err}"
    );
    // A missing file: the OS error once.
    let err = fails(run(&["info", "/nonexistent/m.obj"]));
    assert_eq!(err.matches("os error 2").count(), 1, "{err}");
}

#[test]
fn a_batch_writes_one_file_per_mesh_and_reports_failures() {
    let dir = tempfile::tempdir().unwrap();
    let inputs = dir.path().join("meshes");
    std::fs::create_dir(&inputs).unwrap();
    ellipsoid(&inputs, "ellipsoid.obj", false);
    ellipsoid(&inputs, "inward.obj", true);
    std::fs::copy(
        shared_meshes_dir().join("suzanne.obj"),
        inputs.join("suzanne.obj"),
    )
    .unwrap();
    let out_dir = dir.path().join("out");
    let out = ok(run(&[
        "extract",
        s(&inputs),
        "-o",
        s(&out_dir),
        "--format",
        "json",
    ]));
    for name in ["ellipsoid", "inward", "suzanne"] {
        let lines = read_lines(&out_dir.join(format!("{name}-lines.json")), None).unwrap();
        if name != "suzanne" {
            assert_eq!(lines.lines.len(), 1, "{name}");
        }
    }
    let table = stderr(&out);
    assert!(table.contains("3 meshes, 3 done, 0 failed"), "{table}");

    // A broken file is reported and skipped; the exit code says something failed.
    std::fs::write(inputs.join("broken.obj"), "v 0 0 0\nf 1 2 3\n").unwrap();
    let extra = ellipsoid(dir.path(), "extra.obj", false);
    let out = run(&[
        "extract",
        s(&inputs),
        s(&extra),
        "-o",
        s(&dir.path().join("o2")),
        "--stats=json",
        "-q",
    ]);
    assert!(!out.status.success());
    let summary: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(summary["meshes"], 5);
    assert_eq!(summary["failed"], 1);
    let broken = &summary["files"][0];
    assert_eq!(broken["ok"], false);
    assert!(
        broken["error"].as_str().unwrap().contains("broken.obj"),
        "{broken}"
    );
    assert!(
        stderr(&out).contains("1 of 5 meshes failed"),
        "{}",
        stderr(&out)
    );
    // The failure is named on stderr as well ("see above"), `-q` or not.
    assert!(
        stderr(&out).contains("broken.obj: FAILED: "),
        "{}",
        stderr(&out)
    );
    // Two inputs that would write the same file are refused before any work.
    let err = fails(run(&[
        "extract",
        s(&inputs.join("suzanne.obj")),
        s(&shared_meshes_dir().join("suzanne.obj")),
    ]));
    assert!(err.contains("would both write"), "{err}");
}

#[test]
fn progress_is_hidden_with_q_and_when_stderr_is_not_a_terminal() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = ellipsoid(dir.path(), "e.obj", false);
    let o = |name: &str| dir.path().join(name).to_str().unwrap().to_string();
    for args in [
        vec![
            "simplify".to_string(),
            o("e.obj"),
            "-o".into(),
            o("s.obj"),
            "--eta".into(),
            "0".into(),
        ],
        vec![
            "render".into(),
            o("e.obj"),
            "-o".into(),
            o("r.png"),
            "--size".into(),
            "64".into(),
        ],
        vec!["view".into(), o("e.obj"), "-o".into(), o("v.html")],
        vec!["distance".into(), o("e.obj"), "-o".into(), o("d.ply")],
        vec!["curvature".into(), o("e.obj"), "-o".into(), o("c.ply")],
        vec!["subdivide".into(), o("e.obj"), "-o".into(), o("u.obj")],
        vec!["extract".into(), o("e.obj"), "-o".into(), o("l.obj")],
    ] {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let out = ok(run(&args));
        // Not a terminal: no spinner frames or cursor movements, only notes.
        assert!(
            !stderr(&out).contains('\u{1b}'),
            "{args:?}: {:?}",
            stderr(&out)
        );
        let mut quiet = args.clone();
        quiet.push("-q");
        let out = ok(run(&quiet));
        assert!(stderr(&out).is_empty(), "{quiet:?}: {}", stderr(&out));
    }
    drop(mesh);
}

#[test]
fn render_clips_the_colour_range_and_checks_it() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = ellipsoid(dir.path(), "e.obj", false);
    let picture = |extra: &[&str]| {
        let png = dir.path().join("p.png");
        let mut args = vec![
            "render",
            s(&mesh),
            "--field",
            "k_max",
            "-o",
            s(&png),
            "--size",
            "128",
        ];
        args.extend(extra);
        ok(run(&args));
        std::fs::read(&png).unwrap()
    };
    let default = picture(&[]);
    assert!(default == picture(&["--field-range", "2%"]));
    assert!(default != picture(&["--field-range", "full"]));
    assert!(default != picture(&["--field-range", "0,0.5"]));
    let err = fails(run(&[
        "render",
        s(&mesh),
        "-o",
        "x.png",
        "--field-range",
        "60%",
    ]));
    assert!(err.contains("below 50"), "{err}");
}

#[test]
fn stats_say_whether_the_noise_is_white_and_how_many_lines_it_moved_about() {
    // A sphere moved along its radius by uniform noise of 0.1 sample spacings: white noise,
    // whose zero crossings of the extremalities are lines the noise moves about.
    let dir = tempfile::tempdir().unwrap();
    let sphere = crestline::shapes::icosphere(1.0, 4);
    let spacing = crestline::curvature::jet_fit::sample_spacing(&sphere);
    let mut state = 12345u64;
    let positions = sphere
        .positions()
        .iter()
        .map(|p| {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let u = (state >> 11) as f64 / (1u64 << 53) as f64;
            let q = p * (1.0 + 0.1 * spacing * 3f64.sqrt() * (2.0 * u - 1.0));
            [q.x, q.y, q.z]
        })
        .collect();
    let noisy = crestline::TriMesh::from_arrays(positions, sphere.faces().to_vec()).unwrap();
    let path = dir.path().join("noisy.obj");
    write_mesh(&path, &noisy, Format::Obj, &WriteOptions::default()).unwrap();
    let out = dir.path().join("lines.obj");
    let text = |extra: &[&str]| {
        let mut args = vec!["extract", s(&path), "-o", s(&out), "--stats"];
        args.extend(extra);
        let output = ok(run(&args));
        // The table goes to standard error, `--stats=json` to standard output.
        let table = stderr(&output);
        String::from_utf8(output.stdout).unwrap() + &table
    };
    let default = text(&[]);
    assert!(
        default.contains("from 2.5 to 5 spacings: white"),
        "{default}"
    );
    assert!(default.contains("lines unlocated"), "{default}");
    let kept = text(&["--keep-unlocated"]);
    assert!(!kept.contains("lines unlocated"), "{kept}");
    let args = ["extract", s(&path), "-o", s(&out), "--stats=json", "-q"];
    let json = String::from_utf8(ok(run(&args)).stdout).unwrap();
    let stats: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert_eq!(stats["jet_fit"]["white_noise"], true, "{json}");
    let growth = stats["jet_fit"]["noise_growth"].as_f64().unwrap();
    assert!((growth - 1.0).abs() < 0.1, "{json}");
    assert!(stats["lines_unlocated"].as_u64().unwrap() > 0, "{json}");
}

#[test]
fn stats_count_the_vertices_fitted_on_the_triangles() {
    // An open cylinder as CAD exporters write it (one strip of triangles as long as it): every
    // disc is a row of vertices along a rim, and is sampled on the triangles; an icosphere's
    // never are.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("lines.obj");
    let strip = crestline::shapes::cylinder(1.0, 4.0, 128, 1);
    let sphere = crestline::shapes::icosphere(1.0, 3);
    for (name, mesh, expected) in [
        ("strip.obj", &strip, strip.num_vertices()),
        ("sphere.obj", &sphere, 0),
    ] {
        let path = dir.path().join(name);
        write_mesh(&path, mesh, Format::Obj, &WriteOptions::default()).unwrap();
        let table = stderr(&ok(run(&["extract", s(&path), "-o", s(&out), "--stats"])));
        assert_eq!(
            table.contains(&format!("fitted on triangles    {expected} vertices")),
            expected > 0,
            "{name}: {table}"
        );
        let args = ["extract", s(&path), "-o", s(&out), "--stats=json", "-q"];
        let json = String::from_utf8(ok(run(&args)).stdout).unwrap();
        let stats: serde_json::Value = serde_json::from_str(&json).unwrap();
        let count = stats["jet_fit"]["triangle_sampled_vertices"].as_u64();
        assert_eq!(count, Some(expected as u64), "{name}: {json}");
    }
}

#[test]
fn a_low_residual_that_is_not_white_gets_a_note_on_smoothing() {
    // A crater whose rim is four to five edges across: its truncation error passes for a
    // little noise that is not white, and it is smoothed as a scan would be, which blurs the
    // rim; the summary says so and how to keep it. White noise gets no such note.
    let dir = tempfile::tempdir().unwrap();
    let rim = |x: f64, y: f64| 0.25 * (-((x * x + 1.69 * y * y - 0.3) / 0.25).powi(2)).exp();
    let crater = crestline::shapes::height_field(rim, [-1.0, 1.0], [-1.0, 1.0], 50, 50);
    let path = dir.path().join("crater.obj");
    write_mesh(&path, &crater, Format::Obj, &WriteOptions::default()).unwrap();
    let out = dir.path().join("lines.obj");
    let note = "--smooth-steps 0 keeps them";
    let summary = stderr(&ok(run(&["extract", s(&path), "-o", s(&out)])));
    assert!(summary.contains(note), "{summary}");
    assert!(summary.contains("not white"), "{summary}");
    let unsmoothed = stderr(&ok(run(&[
        "extract",
        s(&path),
        "-o",
        s(&out),
        "--smooth-steps",
        "0",
    ])));
    assert!(!unsmoothed.contains(note), "{unsmoothed}");
    let quiet = stderr(&ok(run(&["extract", s(&path), "-o", s(&out), "-q"])));
    assert!(!quiet.contains(note), "{quiet}");

    let noisy = crestline::shapes::with_normal_noise(&crater, 0.1, 7).unwrap();
    let path = dir.path().join("noisy.obj");
    write_mesh(&path, &noisy, Format::Obj, &WriteOptions::default()).unwrap();
    let summary = stderr(&ok(run(&["extract", s(&path), "-o", s(&out)])));
    assert!(!summary.contains(note), "{summary}");
}

#[test]
fn spikes_are_put_back_and_the_summary_says_so() {
    // A sphere with two vertices three edges off it: put back before anything runs, said in
    // the summary, the text and the JSON stats; --keep-outliers leaves them, ringed by creases.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("spiky.obj");
    crate::common::write_spiky_sphere(&path, 4, &[100, 1500]);
    let out = dir.path().join("lines.obj");
    let summary = stderr(&ok(run(&["extract", s(&path), "-o", s(&out), "--stats"])));
    assert!(summary.contains("2 outlier vertices"), "{summary}");
    assert!(
        summary.contains("outliers               2 vertices moved"),
        "{summary}"
    );
    assert!(summary.contains(": 0 lines"), "{summary}");
    let json = ok(run(&[
        "extract",
        s(&path),
        "-o",
        s(&out),
        "--stats=json",
        "-q",
    ]));
    let stats: serde_json::Value = serde_json::from_slice(&json.stdout).unwrap();
    assert_eq!(stats["outliers_moved"], 2, "{stats}");
    let kept = stderr(&ok(run(&[
        "extract",
        s(&path),
        "-o",
        s(&out),
        "--keep-outliers",
    ])));
    assert!(!kept.contains("outlier"), "{kept}");
    assert!(kept.contains("sharp creases"), "{kept}");
}

#[test]
fn raw_marching_cubes_meshes_are_said_to_be() {
    // A torus as scikit-image's marching cubes leaves it: `info` and `extract` say that every
    // vertex lies on a grid edge (its terraces come out as lines); a mesh made otherwise is not.
    let torus = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../crestline/tests/data/raw_marching_cubes_torus.obj");
    let info = String::from_utf8(ok(run(&["info", s(&torus)])).stdout).unwrap();
    assert!(
        info.contains("marching cubes grid    spacing 0.082353 x 0.082353 x 0.082353"),
        "{info}"
    );
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("lines.obj");
    // A warning: said with -q too, and for each mesh of a batch.
    let warning = "warning: the vertices lie on the edges of a grid of spacing 0.0823529";
    let quiet = stderr(&ok(run(&["extract", s(&torus), "-o", s(&out), "-q"])));
    assert!(quiet.contains(warning), "{quiet}");
    let (a, b) = (dir.path().join("a.obj"), dir.path().join("b.obj"));
    std::fs::copy(&torus, &a).unwrap();
    std::fs::copy(&torus, &b).unwrap();
    let batch = dir.path().join("batch");
    let said = stderr(&ok(run(&["extract", s(&a), s(&b), "-o", s(&batch)])));
    assert_eq!(said.matches(warning).count(), 2, "{said}");
    let args = ["extract", s(&torus), "-o", s(&out), "--stats=json", "-q"];
    let stats: serde_json::Value = serde_json::from_slice(&ok(run(&args)).stdout).unwrap();
    let spacing = stats["marching_cubes_grid"][2].as_f64().unwrap();
    assert!((spacing - 0.0823529).abs() < 1e-6, "{stats}");
    let fandisk = shared_meshes_dir().join("fandisk.obj");
    let args = ["extract", s(&fandisk), "-o", s(&out), "--stats=json", "-q"];
    let stats: serde_json::Value = serde_json::from_slice(&ok(run(&args)).stdout).unwrap();
    assert!(stats["marching_cubes_grid"].is_null(), "{stats}");
}
