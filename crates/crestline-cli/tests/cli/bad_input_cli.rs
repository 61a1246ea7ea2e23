//! Bad input through the command line: every case ends with exit status 1 and one `error:`
//! line naming the file (or a result), never a panic, and leaves no partial output file. The
//! library's side of the bad-input suite is `crates/crestline/tests/bad_input.rs`.

// Test code: stopping loudly on the first surprise is the point.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use crate::common::{crestline, crestline_ok, listing, s, shared_meshes_dir, stderr};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The run failed cleanly: status 1, stderr's last line an `error:` containing `words`,
/// no panic.
#[track_caller]
fn failed_with(out: &Output, words: &[&str]) -> String {
    let stderr = stderr(out);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    let last = stderr.lines().last().unwrap_or_default().to_string();
    assert!(last.starts_with("error: "), "{stderr}");
    for w in words {
        assert!(last.contains(w), "{last} (wanted '{w}')");
    }
    last
}

const TETRA: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";

/// [`TETRA`] written as `tetra.obj` in `dir`.
fn tetra_in(dir: &Path) -> PathBuf {
    let mesh = dir.join("tetra.obj");
    std::fs::write(&mesh, TETRA).unwrap();
    mesh
}

#[test]
fn a_missing_file_is_named_once_with_its_cause_said_once() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("missing.obj");
    let out = dir.path().join("out.obj");
    let last = failed_with(
        &crestline(&["extract", s(&missing), "-o", s(&out), "-q"]),
        &[s(&missing), "No such file or directory"],
    );
    assert_eq!(
        last.matches("No such file or directory").count(),
        1,
        "{last}"
    );
    assert!(listing(dir.path()).is_empty());
}

#[test]
fn a_directory_as_input() {
    let dir = tempfile::tempdir().unwrap();
    let folder = dir.path().join("folder.obj");
    std::fs::create_dir(&folder).unwrap();
    failed_with(&crestline(&["info", s(&folder)]), &[s(&folder), "folder"]);
    // Without an extension it was "no file extension: cannot tell the mesh format".
    let plain = dir.path().join("somedir");
    std::fs::create_dir(&plain).unwrap();
    let png = dir.path().join("x.png");
    for args in [
        vec!["info", s(&plain)],
        vec!["render", s(&plain), "-o", s(&png)],
        vec!["curvature", s(&plain), "-o", s(&dir.path().join("c.ply"))],
        vec!["simplify", s(&plain), "-o", s(&dir.path().join("s.obj"))],
        vec!["subdivide", s(&plain), "-o", s(&dir.path().join("d.obj"))],
    ] {
        let last = failed_with(&crestline(&args), &[s(&plain), "is a folder"]);
        assert!(!last.contains("extension"), "{last}");
    }
    // extract takes a folder as a batch, as before.
    let last = failed_with(
        &crestline(&["extract", s(&plain), "-o", s(&dir.path().join("out"))]),
        &[s(&plain), "no mesh files"],
    );
    assert!(!last.contains("extension"), "{last}");
    // A folder as --lines.
    let mesh = tetra_in(dir.path());
    failed_with(
        &crestline(&["render", s(&mesh), "--lines", s(&plain), "-o", s(&png)]),
        &[s(&plain), "is a folder"],
    );
    assert!(!png.exists());
}

#[test]
fn a_mesh_output_in_a_missing_folder_is_refused_before_the_work() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = tetra_in(dir.path());
    let missing = dir.path().join("nonexistent");
    let output = missing.join("x.ply");
    for command in ["simplify", "subdivide"] {
        let out = crestline(&[command, s(&mesh), "-o", s(&output)]);
        let last = failed_with(
            &out,
            &[
                s(&output),
                &format!("the folder {} does not exist", s(&missing)),
            ],
        );
        // Not the temporary file's name, and before the lines were extracted.
        assert!(!last.contains(".part"), "{last}");
        assert!(
            !stderr(&out).contains("no --lines given"),
            "{}",
            stderr(&out)
        );
    }
    assert_eq!(listing(dir.path()), vec!["tetra.obj"]);
}

#[test]
fn malformed_files_in_every_format() {
    let dir = tempfile::tempdir().unwrap();
    for (name, bytes, words) in [
        (
            "a.obj",
            &b"v 0 0 0\nv 1 nan 0\n"[..],
            &["a.obj: line 2", "NaN"][..],
        ),
        (
            "b.ply",
            b"ply\nformat ascii 1.0\n",
            &["b.ply: line 2", "end_header"],
        ),
        (
            "c.off",
            b"OFF\n3 1 0\n0 0 0\n",
            &["c.off: line 3", "of 3 vertices"],
        ),
        ("d.stl", b"\x00\x01junk", &["d.stl: byte 6", "truncated"]),
        ("e.obj", b"", &["e.obj: empty file"]),
        ("f.obj", b"# nothing\n", &["f.obj: no vertices"]),
    ] {
        let path = dir.path().join(name);
        std::fs::write(&path, bytes).unwrap();
        let out = dir.path().join(format!("{name}-lines.obj"));
        failed_with(
            &crestline(&["extract", s(&path), "-o", s(&out), "-q"]),
            words,
        );
        assert!(!out.exists(), "{name}: an output was left behind");
    }
}

#[test]
fn an_unwritable_output_leaves_nothing_behind() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = tetra_in(dir.path());
    let nowhere = dir.path().join("no/such/folder/lines.obj");
    failed_with(
        &crestline(&["extract", s(&mesh), "-o", s(&nowhere), "-q"]),
        &[s(&nowhere)],
    );
    // The output is an existing folder.
    let folder = dir.path().join("out.obj");
    std::fs::create_dir(&folder).unwrap();
    failed_with(
        &crestline(&["subdivide", s(&mesh), "-o", s(&folder)]),
        &[s(&folder)],
    );
    assert!(folder.is_dir());
    assert_eq!(listing(dir.path()), vec!["out.obj", "tetra.obj"]);
}

#[test]
fn output_over_the_input_replaces_it_whole() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = tetra_in(dir.path());
    crestline_ok(["subdivide", s(&mesh), "-o", s(&mesh)]);
    let back = crestline::io::read_mesh(&mesh, None).unwrap();
    assert_eq!(back.num_faces(), 16);
    assert_eq!(listing(dir.path()), vec!["tetra.obj"]);
}

#[test]
fn a_bad_mask_file_names_its_line() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = tetra_in(dir.path());
    let mask = dir.path().join("mask.txt");
    std::fs::write(&mask, "1\n1\nx\n1\n").unwrap();
    let out = dir.path().join("lines.obj");
    failed_with(
        &crestline(&["extract", s(&mesh), "--mask", s(&mask), "-o", s(&out), "-q"]),
        &["mask.txt: line 3", "non-numeric token 'x'"],
    );
    std::fs::write(&mask, "\u{feff}1\r\n1\r\n0.5\r\n1\r\n").unwrap();
    crestline_ok(["extract", s(&mesh), "--mask", s(&mask), "-o", s(&out), "-q"]);
}

#[test]
fn awkward_meshes_run_through_extract() {
    let dir = tempfile::tempdir().unwrap();
    for (name, text) in [
        // Vertices only.
        ("points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n"),
        // One triangle and a degenerate one.
        (
            "one.obj",
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\nf 1 2 3\nf 1 2 4\n",
        ),
        // Three fins on one edge (a non-manifold edge).
        (
            "fins.obj",
            "v 0 0 -1\nv 0 0 1\nv 1 0 0\nv -1 1 0\nv -1 -1 0\nf 1 2 3\nf 1 2 4\nf 1 2 5\n",
        ),
    ] {
        let path = dir.path().join(name);
        std::fs::write(&path, text).unwrap();
        let out = dir.path().join(format!("{name}-lines.json"));
        let run = crestline(&["extract", s(&path), "-o", s(&out), "-q"]);
        let stderr = stderr(&run);
        assert!(!stderr.contains("panicked"), "{name}: {stderr}");
        if run.status.success() {
            let lines: serde_json::Value =
                serde_json::from_slice(&std::fs::read(&out).unwrap()).unwrap();
            assert!(lines["lines"].is_array(), "{name}");
        } else {
            failed_with(&run, &[]);
            assert!(!out.exists(), "{name}");
        }
    }
}

/// fandisk subdivided `levels` times (4^levels times its 12,946 triangles) as binary PLY in
/// `dir`: a mesh that takes the pipeline long enough to be stopped midway.
fn big_fandisk(dir: &Path, levels: &str) -> PathBuf {
    let fandisk = shared_meshes_dir().join("fandisk.obj");
    let big = dir.join(format!("fandisk-{levels}.ply"));
    crestline_ok([
        "subdivide",
        s(&fandisk),
        "-o",
        s(&big),
        "--levels",
        levels,
        "-q",
    ]);
    big
}

/// Sends `signal` (a name `kill` knows: INT, TERM, HUP) to `child`.
fn send(signal: &str, child: &std::process::Child) {
    let kill = Command::new("kill")
        .args([format!("-{signal}"), child.id().to_string()])
        .status()
        .unwrap();
    assert!(kill.success(), "kill -{signal}");
}

/// The files of `dir` apart from the ones in `keep`.
fn left_in(dir: &Path, keep: &[&Path]) -> Vec<String> {
    let keep: Vec<String> = keep
        .iter()
        .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    listing(dir)
        .into_iter()
        .filter(|name| !keep.contains(name))
        .collect()
}

#[test]
fn ctrl_c_during_the_work_leaves_no_output() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = big_fandisk(dir.path(), "3");
    for (signal, status) in [("INT", 130), ("HUP", 129)] {
        let out = dir.path().join("lines.obj");
        let child = Command::new(env!("CARGO_BIN_EXE_crestline"))
            .args(["extract", s(&mesh), "-o", s(&out), "-q"])
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        // 830k triangles keep the pipeline busy for far longer than this; a run that ended
        // before the signal would leave its output and fail the checks below.
        std::thread::sleep(std::time::Duration::from_millis(1500));
        send(signal, &child);
        let run = child.wait_with_output().unwrap();
        let stderr = stderr(&run);
        assert_eq!(run.status.code(), Some(status), "SIG{signal}: {stderr}");
        assert!(stderr.contains("interrupted"), "{stderr}");
        assert!(left_in(dir.path(), &[&mesh]).is_empty(), "SIG{signal}");
    }
}

#[test]
fn a_signal_while_writing_removes_the_temporary_file() {
    let dir = tempfile::tempdir().unwrap();
    let fandisk = shared_meshes_dir().join("fandisk.obj");
    let out_dir = dir.path().join("out");
    std::fs::create_dir(&out_dir).unwrap();
    let out = out_dir.join("fine.obj");
    // 830k triangles written as text: tens of megabytes, the write takes a while.
    let mut child = Command::new(env!("CARGO_BIN_EXE_crestline"))
        .args([
            "subdivide",
            s(&fandisk),
            "-o",
            s(&out),
            "--levels",
            "3",
            "-q",
        ])
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // The signal goes once the temporary file is there, that is while the mesh is written.
    let mut seen = false;
    while child.try_wait().unwrap().is_none() {
        if listing(&out_dir).iter().any(|n| n.ends_with(".part")) {
            seen = true;
            send("TERM", &child);
            break;
        }
    }
    let run = child.wait_with_output().unwrap();
    let stderr = stderr(&run);
    assert!(
        seen,
        "the run ended before its temporary file was seen: {stderr}"
    );
    assert_eq!(run.status.code(), Some(143), "{stderr}");
    assert!(listing(&out_dir).is_empty(), "{:?}", listing(&out_dir));
}

/// Every command that writes a file, with `OUT` standing for the output and `MESH` and
/// `LINES` for inputs.
const WRITERS: [&[&str]; 9] = [
    &["extract", "MESH", "-o", "OUT"],
    &[
        "extract", "MESH", "-o", "-", "--format", "json", "--png", "OUT",
    ],
    &["curvature", "MESH", "-o", "OUT", "--csv"],
    &["curvature", "MESH", "-o", "OUT"],
    &[
        "render", "MESH", "--lines", "LINES", "-o", "OUT", "--format", "png",
    ],
    &["render", "MESH", "-o", "OUT", "--format", "html"],
    &["view", "MESH", "--lines", "LINES", "-o", "OUT"],
    &["distance", "MESH", "--lines", "LINES", "-o", "OUT"],
    &["simplify", "MESH", "-o", "OUT"],
];

/// `command` with `MESH`, `LINES` and `OUT` put in.
fn with_paths(command: &[&str], mesh: &Path, lines: &Path, out: &Path) -> Vec<String> {
    command
        .iter()
        .map(|a| match *a {
            "MESH" => s(mesh).to_string(),
            "LINES" => s(lines).to_string(),
            "OUT" => s(out).to_string(),
            other => other.to_string(),
        })
        .chain(["-q".to_string()])
        .collect()
}

/// fandisk and its lines (JSON) in `dir`.
fn fandisk_and_lines(dir: &Path) -> (PathBuf, PathBuf) {
    let fandisk = shared_meshes_dir().join("fandisk.obj");
    let mesh = dir.join("fandisk.obj");
    std::fs::copy(fandisk, &mesh).unwrap();
    let lines = dir.join("lines.json");
    let run = crestline(&["extract", s(&mesh), "-o", s(&lines), "-q"]);
    assert!(run.status.success());
    (mesh, lines)
}

#[test]
fn every_writer_leaves_nothing_when_its_folder_is_missing() {
    let dir = tempfile::tempdir().unwrap();
    let (mesh, lines) = fandisk_and_lines(dir.path());
    let before = listing(dir.path());
    for command in WRITERS {
        let out = dir.path().join("no/such/folder/out.ply");
        let args = with_paths(command, &mesh, &lines, &out);
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let run = crestline(&args);
        failed_with(&run, &[s(&out)]);
        assert_eq!(listing(dir.path()), before, "{command:?}");
    }
}

#[test]
fn every_writer_refuses_or_replaces_whole_an_output_that_is_an_input() {
    let dir = tempfile::tempdir().unwrap();
    let (mesh, lines) = fandisk_and_lines(dir.path());
    let mesh_bytes = std::fs::read(&mesh).unwrap();
    let lines_bytes = std::fs::read(&lines).unwrap();
    for command in WRITERS {
        for input in [&mesh, &lines] {
            if input == &lines && !command.contains(&"LINES") {
                continue;
            }
            let args = with_paths(command, &mesh, &lines, input);
            let args: Vec<&str> = args.iter().map(String::as_str).collect();
            let run = crestline(&args);
            if command[0] == "simplify" {
                // A mesh again: written in place, whole.
                assert!(run.status.success(), "{command:?}");
                assert!(crestline::io::read_mesh(&mesh, None).unwrap().num_faces() > 0);
                std::fs::write(&mesh, &mesh_bytes).unwrap();
            } else if command[0] == "distance" {
                // Refused first for not ending in .ply.
                failed_with(&run, &[s(input)]);
            } else {
                failed_with(&run, &[s(input), "the output is the input"]);
            }
            assert_eq!(std::fs::read(&mesh).unwrap(), mesh_bytes, "{command:?}");
            assert_eq!(std::fs::read(&lines).unwrap(), lines_bytes, "{command:?}");
            assert_eq!(
                listing(dir.path()),
                vec!["fandisk.obj", "lines.json"],
                "{command:?}"
            );
        }
    }
}

#[test]
fn a_closed_standard_output_ends_the_run_quietly() {
    // `crestline info m.obj | head -0`: the pipe is closed before anything is written.
    let fandisk = shared_meshes_dir().join("fandisk.obj");
    let (reader, writer) = std::io::pipe().unwrap();
    drop(reader);
    let run = Command::new(env!("CARGO_BIN_EXE_crestline"))
        .args(["info", s(&fandisk)])
        .stdout(writer)
        .stderr(std::process::Stdio::piped())
        .output()
        .unwrap();
    let stderr = stderr(&run);
    assert_eq!(run.status.code(), Some(141), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
}

#[test]
fn an_output_folder_that_does_not_exist_is_refused_before_the_work() {
    let fandisk = shared_meshes_dir().join("fandisk.obj");
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("missing");
    for (command, option) in [("extract", "-o"), ("extract", "--png"), ("curvature", "-o")] {
        let out = missing.join("out.png");
        let mut args = vec![command, s(&fandisk)];
        if option != "-o" {
            args.extend(["-o", s(dir.path())]);
        }
        args.extend([option, s(&out)]);
        let run = crestline(&args);
        let stderr = stderr(&run);
        assert!(!run.status.success(), "{command} {option}");
        assert!(stderr.contains("does not exist"), "{stderr}");
        // Refused before the mesh was read: no summary of the work.
        assert!(!stderr.contains("lines ("), "{stderr}");
        assert!(!missing.exists());
    }
}
