use super::*;

fn line(kind: LineKind, points: &[[f64; 3]], closed: bool) -> FeatureLine {
    let points: Vec<Vec3> = points.iter().map(|&p| Vec3::from(p)).collect();
    read_line(kind, false, points, closed, 2.0, 0.5)
}

fn sample() -> FeatureLines {
    FeatureLines {
        lines: vec![
            line(LineKind::Valley, &[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]], false),
            line(
                LineKind::Ridge,
                &[[0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [1.0, 1.0, 1.0]],
                true,
            ),
            line(LineKind::Ridge, &[[0.1, 0.2, 0.3], [0.4, 0.5, 0.6]], false),
        ],
    }
}

#[test]
fn obj_groups_by_kind_and_closes_with_the_first_index() {
    let mut out = Vec::new();
    write_lines_obj(&mut out, &sample()).unwrap();
    let text = String::from_utf8(out).unwrap();
    assert_eq!(
        text,
        "# crestline feature lines: 2 ridges, 1 valleys\n\
             o ridges\nv 0 0 1\nv 1 0 1\nv 1 1 1\n\
             # strength 2 curvature_integral 0.5\nl 1 2 3 1\n\
             v 0.1 0.2 0.3\nv 0.4 0.5 0.6\n\
             # strength 2 curvature_integral 0.5\nl 4 5\n\
             o valleys\nv 0 0 0\nv 1 0 0\n\
             # strength 2 curvature_integral 0.5\nl 6 7\n"
    );
}

#[test]
fn obj_reads_back_kinds_closure_and_length() {
    let mut out = Vec::new();
    write_lines_obj(&mut out, &sample()).unwrap();
    let back = parse_lines_obj(&out, Path::new("l.obj")).unwrap();
    assert_eq!(back.lines.len(), 3);
    let ridge = &back.lines[0];
    assert_eq!(ridge.kind, LineKind::Ridge);
    assert!(ridge.closed);
    assert_eq!(ridge.points.len(), 3);
    assert!((ridge.length - (2.0 + 2f64.sqrt())).abs() < 1e-15);
    assert!(ridge.locations.is_empty());
    assert_eq!(back.lines[2].kind, LineKind::Valley);
    assert!(!back.lines[2].closed);
    assert_eq!(back.lines[2].length, 1.0);
    assert_eq!(back.lines[1].points, sample().lines[2].points);
    assert!(back.lines.iter().all(|l| l.strength == 2.0));
    assert!(back.lines.iter().all(|l| l.curvature_integral == 0.5));
}

/// Lines of every class with distinct strengths, as `extract` gives them.
fn every_class() -> FeatureLines {
    let mut lines = sample();
    lines.lines[0].strength = 0.25;
    let mut crease = line(
        LineKind::Ridge,
        &[[2.0, 0.0, 0.0], [2.0, 1.0, 0.0], [2.0, 2.0, 0.5]],
        false,
    );
    crease.crease = true;
    crease.strength = 7.5;
    lines.lines.push(crease);
    let mut crease_valley = line(
        LineKind::Valley,
        &[
            [3.0, 0.0, 0.0],
            [3.0, 1.0, 0.0],
            [4.0, 1.0, 0.0],
            [4.0, 0.0, 0.0],
        ],
        true,
    );
    crease_valley.crease = true;
    crease_valley.curvature_integral = -1.25;
    lines.lines.push(crease_valley);
    lines
}

/// What survives a file: everything but the mesh locations.
/// Kind, crease, closed, points, length, strength, curvature integral.
type FileLine = (LineKind, bool, bool, Vec<Vec3>, f64, f64, f64);

fn file_view(lines: &FeatureLines) -> Vec<FileLine> {
    let mut v: Vec<_> = lines
        .lines
        .iter()
        .map(|l| {
            (
                l.kind,
                l.crease,
                l.closed,
                l.points.clone(),
                l.length,
                l.strength,
                l.curvature_integral,
            )
        })
        .collect();
    // OBJ groups by class; compare independently of order.
    v.sort_by(|a, b| {
        a.3[0]
            .x
            .total_cmp(&b.3[0].x)
            .then(a.3[0].z.total_cmp(&b.3[0].z))
    });
    v
}

#[test]
fn every_format_reads_back_kinds_closure_points_and_strengths() {
    let lines = every_class();
    for (format, encoding) in [
        (LinesFormat::Obj, PlyEncoding::Ascii),
        (LinesFormat::Json, PlyEncoding::Ascii),
        (LinesFormat::Ply, PlyEncoding::Ascii),
        (LinesFormat::Ply, PlyEncoding::BinaryLittleEndian),
        (LinesFormat::Ply, PlyEncoding::BinaryBigEndian),
    ] {
        let mut bytes = Vec::new();
        write_lines_to(&mut bytes, &lines, format, encoding).unwrap();
        let back = parse_lines(&bytes, format, Path::new("l")).unwrap();
        assert_eq!(
            file_view(&back),
            file_view(&lines),
            "{format:?} {encoding:?}"
        );
        if format != LinesFormat::Obj {
            // JSON and PLY keep the order too.
            assert_eq!(back.lines[0].kind, LineKind::Valley, "{format:?}");
            assert_eq!(back.lines[4].points.len(), 4, "{format:?}");
        }
    }
}

#[test]
fn ply_edges_chain_into_paths_and_loops_whatever_their_order() {
    // A square loop listed backwards and a path whose edges come out of order, no kind.
    let text = "ply\nformat ascii 1.0\nelement vertex 7\nproperty float x\n\
                    property float y\nproperty float z\nelement edge 6\nproperty int vertex1\n\
                    property int vertex2\nend_header\n\
                    0 0 0\n1 0 0\n1 1 0\n0 1 0\n5 0 0\n6 0 0\n7 0 0\n\
                    3 0\n2 3\n5 6\n1 2\n0 1\n4 5\n";
    let back = parse_lines_ply(text.as_bytes(), Path::new("e.ply")).unwrap();
    assert_eq!(back.lines.len(), 2);
    let square = &back.lines[0];
    assert!(square.closed && square.points.len() == 4 && square.length == 4.0);
    let path = &back.lines[1];
    assert!(!path.closed);
    assert_eq!(path.points.first().unwrap().x, 5.0);
    assert_eq!(path.points.len(), 3);
    assert!(
        back.lines
            .iter()
            .all(|l| l.kind == LineKind::Ridge && !l.crease)
    );
}

#[test]
fn anything_but_a_lines_file_is_an_error() {
    let e = |bytes: &[u8], format| {
        parse_lines(bytes, format, Path::new("x"))
            .unwrap_err()
            .to_string()
    };
    assert_eq!(
        e(b"hello\n", LinesFormat::Obj),
        "x: line 1: 'hello' is not an OBJ record: not a feature-line file"
    );
    assert!(
        e(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", LinesFormat::Obj)
            .contains("no polylines ('l' records) among 3 vertices and 1 faces"),
    );
    assert!(e(b"{\"ridges\": 1}", LinesFormat::Json).contains("missing field `lines`"));
    assert!(e(b"hello", LinesFormat::Json).starts_with("x: line 1: not a feature-line JSON"));
    assert_eq!(
        e(
            br#"{"lines": [{"kind": "bump", "points": []}]}"#,
            LinesFormat::Json
        ),
        "x: line 0 of \"lines\": unknown kind 'bump' (known: ridge, valley, \
             crease-ridge, crease-valley)"
    );
    let mesh = b"ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\n\
                     property float y\nproperty float z\nend_header\n";
    assert!(e(mesh, LinesFormat::Ply).contains("no 'edge' element"));
    let out_of_range = b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n\
                     property float y\nproperty float z\nelement edge 1\n\
                     property int vertex1\nproperty int vertex2\nend_header\n0 0 0\n0 1\n";
    assert_eq!(
        e(out_of_range, LinesFormat::Ply),
        "x: line 12: edge 0: vertex index 1 out of range (the file has 1 vertices)"
    );
    // What extract writes for no lines at all reads back as no lines.
    for format in [LinesFormat::Obj, LinesFormat::Json, LinesFormat::Ply] {
        let mut bytes = Vec::new();
        write_lines_to(
            &mut bytes,
            &FeatureLines::default(),
            format,
            PlyEncoding::Ascii,
        )
        .unwrap();
        let back = parse_lines(&bytes, format, Path::new("x")).unwrap();
        assert!(back.lines.is_empty(), "{format:?}");
    }
}

#[test]
fn obj_other_groups_are_ridges_and_indices_may_be_relative() {
    let text = b"g creases\nv 0 0 0\nv 3 4 0\nl -2 -1\ng Valleys\nv 0 0 0\nl 2 3\n";
    let back = parse_lines_obj(text, Path::new("l.obj")).unwrap();
    assert_eq!(back.lines[0].kind, LineKind::Ridge);
    assert_eq!(back.lines[0].length, 5.0);
    assert_eq!(back.lines[1].kind, LineKind::Valley);
}

#[test]
fn obj_errors_name_the_line() {
    let e = |t: &str| {
        parse_lines_obj(t.as_bytes(), Path::new("l.obj"))
            .unwrap_err()
            .to_string()
    };
    assert_eq!(e(""), "l.obj: empty file");
    assert_eq!(
        e("v 0 0 0\nl 1\n"),
        "l.obj: line 2: polyline with 1 vertices (at least 2 needed)"
    );
    assert_eq!(
        e("v 0 0 0\nl 1 2\n"),
        "l.obj: line 2: vertex index 2 out of range (the file has 1 vertices)"
    );
    assert_eq!(
        e("v 0 0 0\nl 1 -2\n"),
        "l.obj: line 2: relative vertex index -2 reaches before the first vertex (only 1 \
             read so far)"
    );
    assert_eq!(
        e("v 0 0 0\nl 1 x\n"),
        "l.obj: line 2: non-numeric token 'x' where a vertex index was expected"
    );
    assert_eq!(
        e("v 0 nan 0\n"),
        "l.obj: line 1: y coordinate of vertex 1 is NaN or infinite ('nan')"
    );
}

#[test]
fn json_has_every_attribute() {
    let mut out = Vec::new();
    write_lines_json(&mut out, &sample()).unwrap();
    let v: serde_json::Value = serde_json::from_slice(&out).unwrap();
    assert_eq!(v["ridges"], 2);
    assert_eq!(v["valleys"], 1);
    let first = &v["lines"][0];
    assert_eq!(first["kind"], "valley");
    assert_eq!(first["closed"], false);
    assert_eq!(first["points"][1][0], 1.0);
    assert_eq!(first["length"], 1.0);
    assert_eq!(first["curvature_integral"], 0.5);
    assert_eq!(first["strength"], 2.0);
    assert_eq!(v["lines"][1]["closed"], true);
}

#[test]
fn ply_edges_with_kind() {
    let mut out = Vec::new();
    write_lines_ply(&mut out, &sample(), PlyEncoding::Ascii).unwrap();
    let text = String::from_utf8(out).unwrap();
    assert!(text.contains("element vertex 7\n"), "{text}");
    assert!(text.contains("element edge 5\nproperty int vertex1\nproperty int vertex2\n"));
    assert!(
        text.ends_with("0 1 1 2 0.5\n2 3 0 2 0.5\n3 4 0 2 0.5\n4 2 0 2 0.5\n5 6 0 2 0.5\n"),
        "{text}"
    );
    // The binary file has the same header and 7 * 24 + 5 * 25 bytes of data.
    let mut binary = Vec::new();
    write_lines_ply(&mut binary, &sample(), PlyEncoding::BinaryLittleEndian).unwrap();
    let end = binary
        .windows(11)
        .position(|w| w == b"end_header\n")
        .unwrap()
        + 11;
    assert_eq!(binary.len() - end, 7 * 24 + 5 * 25);
    // Both read back as meshes with the line points as vertices.
    for bytes in [text.as_bytes(), &binary[..]] {
        let m =
            crate::io::parse_mesh_bytes(bytes, crate::io::Format::Ply, Path::new("l.ply")).unwrap();
        assert_eq!(m.positions.len(), 7);
        assert_eq!(m.positions[6], [0.4, 0.5, 0.6]);
    }
}

#[test]
fn lines_format_by_extension() {
    assert_eq!(
        LinesFormat::from_path(Path::new("a.JSON")),
        Some(LinesFormat::Json)
    );
    assert_eq!(
        LinesFormat::from_path(Path::new("a.obj")),
        Some(LinesFormat::Obj)
    );
    assert_eq!(
        LinesFormat::from_path(Path::new("a.ply")),
        Some(LinesFormat::Ply)
    );
    assert_eq!(LinesFormat::from_path(Path::new("a.txt")), None);
}
