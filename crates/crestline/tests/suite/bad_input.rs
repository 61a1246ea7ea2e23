//! The bad-input suite: broken, odd and hostile files in every format the library reads (OBJ,
//! PLY ascii / binary / tristrips, OFF, STL ascii / binary, feature-line OBJ, diffusion-mask
//! files), and awkward meshes run through the whole pipeline.
//!
//! Every case ends in one of two ways, and the test says which: an error that names the file,
//! a position in it (line, byte or "file") and what is wrong; or a correct result, with what
//! was skipped counted. Nothing panics, hangs or allocates from a header's word alone.
//! `io_robustness.rs` adds random damage; the CLI's side is in
//! `crates/crestline-cli/tests/bad_input_cli.rs`.

// Test code: stopping loudly on the first surprise is the point.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::path::Path;

use crestline::extract::{ExtractOptions, Method, extract};
use crestline::io::lines::parse_lines_obj;
use crestline::io::mask::parse_diffusion_factors;
use crestline::io::{
    Format, PlyEncoding, WriteOptions, read_mesh, read_mesh_bytes, write_mesh, write_mesh_to,
};
use crestline::mesh::{EdgeKind, VertexKind, orient_outward};
use crestline::{TriMesh, shapes};

// ---------------------------------------------------------------------------------------
// Helpers
// ---------------------------------------------------------------------------------------

/// Reads `bytes` as the format named by `name`'s extension.
fn read(name: &str, bytes: &[u8]) -> crestline::Result<TriMesh> {
    let format = Format::from_path(Path::new(name)).unwrap();
    read_mesh_bytes(bytes, format, Path::new(name))
}

/// The error of reading `bytes`; it must name the file and `location` ("line 3", "byte 84",
/// "file") and contain every one of `words`.
#[track_caller]
fn fails(name: &str, bytes: impl AsRef<[u8]>, location: &str, words: &[&str]) {
    let message = match read(name, bytes.as_ref()) {
        Ok(m) => panic!(
            "{name}: read as a mesh of {} vertices and {} triangles, expected an error at \
             {location}",
            m.num_vertices(),
            m.num_faces()
        ),
        Err(e) => e.to_string(),
    };
    // "byte" or "line" alone: any byte or line.
    let prefix = if location.ends_with(|c: char| c.is_ascii_digit()) || location == "file" {
        format!("{name}: {location}: ")
    } else {
        format!("{name}: {location} ")
    };
    assert!(message.starts_with(&prefix), "{message} (wanted {prefix})");
    for w in words {
        assert!(message.contains(w), "{message} (wanted '{w}')");
    }
}

/// The mesh read from `bytes`, which must have `vertices` vertices and `faces` triangles
/// kept, `degenerate` dropped.
#[track_caller]
fn reads(name: &str, bytes: impl AsRef<[u8]>, vertices: usize, faces: usize, degenerate: usize) {
    let m = read(name, bytes.as_ref()).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(
        (m.num_vertices(), m.num_faces(), m.degenerate_faces()),
        (vertices, faces, degenerate),
        "{name}: (vertices, triangles, degenerate)"
    );
}

/// Every prefix of `bytes` reads without a panic, and failures name the file and a position.
/// Returns how many prefixes failed.
fn every_prefix(name: &str, bytes: &[u8]) -> usize {
    let mut failures = 0;
    for end in 0..bytes.len() {
        if let Err(e) = read(name, &bytes[..end]) {
            let m = e.to_string();
            let rest = m
                .strip_prefix(&format!("{name}: "))
                .unwrap_or_else(|| panic!("prefix of {end} bytes: {m}"));
            assert!(
                rest.starts_with("line ") || rest.starts_with("byte ") || rest.starts_with("file"),
                "prefix of {end} bytes: {m}"
            );
            failures += 1;
        }
    }
    failures
}

fn with_bom(text: &str) -> Vec<u8> {
    let mut bytes = vec![0xef, 0xbb, 0xbf];
    bytes.extend_from_slice(text.as_bytes());
    bytes
}

fn crlf(text: &str) -> String {
    text.replace('\n', "\r\n")
}

/// A tetrahedron (closed, outward) as OBJ.
const TETRA_OBJ: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n\
                         f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";

fn icosphere_bytes(format: Format, encoding: PlyEncoding) -> Vec<u8> {
    let mesh = shapes::icosphere(1.0, 1);
    let mut bytes = Vec::new();
    let options = WriteOptions::default().with_ply_encoding(encoding);
    write_mesh_to(&mut bytes, &mesh, format, &options).unwrap();
    bytes
}

const PLY_HEAD: &str = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n\
                        property float y\nproperty float z\nelement face 1\n\
                        property list uchar int vertex_indices\nend_header\n";

const TRIANGLE_BODY: &str = "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";

/// A binary little-endian PLY with `vertices` (float xyz) and the faces `faces` (uchar
/// count, int indices), under a header declaring `declared` vertices and faces.
fn binary_ply(declared: (&str, &str), vertices: &[[f32; 3]], faces: &[&[i32]]) -> Vec<u8> {
    let mut bytes = format!(
        "ply\nformat binary_little_endian 1.0\nelement vertex {}\nproperty float x\n\
         property float y\nproperty float z\nelement face {}\n\
         property list uchar int vertex_indices\nend_header\n",
        declared.0, declared.1
    )
    .into_bytes();
    for p in vertices {
        for c in p {
            bytes.extend_from_slice(&c.to_le_bytes());
        }
    }
    for f in faces {
        bytes.push(f.len() as u8);
        for i in *f {
            bytes.extend_from_slice(&i.to_le_bytes());
        }
    }
    bytes
}

const TRIANGLE: [[f32; 3]; 3] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];

/// A binary STL of `triangles` whose header declares `declared` triangles.
fn binary_stl(declared: u32, triangles: &[[[f32; 3]; 3]]) -> Vec<u8> {
    let mut bytes = vec![b' '; 80];
    bytes.extend_from_slice(&declared.to_le_bytes());
    for t in triangles {
        bytes.extend_from_slice(&[0u8; 12]);
        for c in t.iter().flatten() {
            bytes.extend_from_slice(&c.to_le_bytes());
        }
        bytes.extend_from_slice(&[0u8; 2]);
    }
    bytes
}

const STL_ASCII: &str = "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n\
                         vertex 0 1 0\nendloop\nendfacet\nendsolid t\n";

// ---------------------------------------------------------------------------------------
// OBJ
// ---------------------------------------------------------------------------------------

#[test]
fn obj_empty_blank_and_comment_only_files_are_errors() {
    fails("a.obj", "", "file", &["empty file"]);
    fails("a.obj", " \n\t\n\r\n", "file", &["empty file"]);
    fails(
        "a.obj",
        "# only a comment\n# and another\n",
        "file",
        &["no vertices"],
    );
}

#[test]
fn obj_bad_numbers_are_errors_at_their_line() {
    fails(
        "a.obj",
        "v 0 0 0\nv nan 0 0\n",
        "line 2",
        &["NaN or infinite"],
    );
    fails(
        "a.obj",
        "v 0 0 0\nv 0 -inf 0\n",
        "line 2",
        &["NaN or infinite"],
    );
    fails(
        "a.obj",
        "v 0 0 1e309\n",
        "line 1",
        &["NaN or infinite", "1e309"],
    );
    fails("a.obj", "v 0 0\n", "line 1", &["missing z coordinate"]);
    fails(
        "a.obj",
        "v 0 0 0x1\n",
        "line 1",
        &["non-numeric token '0x1'"],
    );
}

#[test]
fn huge_but_finite_coordinates_read_and_are_refused_by_the_algorithms() {
    // Files store any finite number; a triangle of sides 1e308 is large, not degenerate.
    let text = "v 1e308 0 0\nv 0 1e308 0\nv 0 0 -1e308\nf 1 2 3\n";
    reads("a.obj", text, 3, 1, 0);
    reads(
        "a.obj",
        "v -1.7e308 0 0\nv 1.7e308 0 0\nv 0 1 0\nf 1 2 3\n",
        3,
        1,
        0,
    );
    // Squared lengths of 1e308 overflow: the algorithms refuse the mesh with a reason.
    let m = read("a.obj", text.as_bytes()).unwrap();
    let e = extract(&m, &ExtractOptions::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("vertex 0") && e.contains("too large"), "{e}");
    // At the limit, they run.
    let m = read("a.obj", b"v 1e75 0 0\nv 0 1e75 0\nv 0 0 -1e75\nf 1 2 3\n").unwrap();
    every_method("1e75", &m);
}

#[test]
fn obj_bad_indices_are_errors_at_their_line() {
    let v = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    fails(
        "a.obj",
        format!("{v}f 1 2 -4\n"),
        "line 4",
        &["reaches before the first"],
    );
    fails("a.obj", format!("{v}f 1 2 0\n"), "line 4", &["index 0"]);
    fails(
        "a.obj",
        format!("{v}f 1 2 4\n"),
        "line 4",
        &["4 out of range", "3 vertices"],
    );
    fails(
        "a.obj",
        format!("{v}f 1 2 99999999999999\n"),
        "line 4",
        &["out of range"],
    );
    fails(
        "a.obj",
        format!("{v}f 1 2 99999999999999999999999\n"),
        "line 4",
        &["99999999999999999999999"],
    );
    fails("a.obj", format!("{v}f 1 2 3.5\n"), "line 4", &["'3.5'"]);
}

#[test]
fn obj_faces_with_fewer_than_three_corners_are_errors() {
    let v = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    fails("a.obj", format!("{v}f\n"), "line 4", &["0 vertices"]);
    fails("a.obj", format!("{v}f 1\n"), "line 4", &["1 vertices"]);
    fails("a.obj", format!("{v}f 1 2\n"), "line 4", &["2 vertices"]);
}

#[test]
fn obj_polygons_with_many_corners_are_fan_triangulated() {
    let n = 200;
    let mut text = String::new();
    for k in 0..n {
        let a = k as f64 * std::f64::consts::TAU / n as f64;
        text += &format!("v {} {} 0\n", a.cos(), a.sin());
    }
    text += "f";
    for k in 1..=n {
        text += &format!(" {k}");
    }
    text += "\n";
    reads("a.obj", text, n, n - 2, 0);
}

#[test]
fn obj_degenerate_and_duplicate_faces_are_counted() {
    let v = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\n";
    // A repeated corner and three collinear corners are dropped; a duplicate is kept.
    reads("a.obj", format!("{v}f 1 2 3\nf 1 1 2\nf 1 2 4\n"), 4, 1, 2);
    reads("a.obj", format!("{v}f 1 2 3\nf 1 2 3\nf 3 2 1\n"), 4, 3, 0);
}

#[test]
fn obj_vertices_only_is_a_mesh_without_triangles() {
    reads("a.obj", "v 0 0 0\nv 1 0 0\nv 5 5 5\n", 3, 0, 0);
}

#[test]
fn obj_crlf_bom_and_comments_anywhere() {
    reads("a.obj", crlf(TETRA_OBJ), 4, 4, 0);
    reads("a.obj", with_bom(TETRA_OBJ), 4, 4, 0);
    reads("a.obj", with_bom(&crlf(TETRA_OBJ)), 4, 4, 0);
    let commented = "# head\n  # indented\nv 0 0 0 # origin\n#v 9 9 9\nv 1 0 0\t# x\nv 0 1 0\n\
                     v 0 0 1\n# faces\nf 1 3 2 # one\nf 1 2 4 #two\nf 1 4 3\n\nf 2 3 4\n# end";
    reads("a.obj", commented, 4, 4, 0);
    // A comment must start a token: glued to a number it makes that number unreadable.
    fails(
        "a.obj",
        "v 0 0 0#c\n",
        "line 1",
        &["non-numeric token '0#c'"],
    );
    // Bytes that are not UTF-8 in comments and names are ignored.
    reads(
        "a.obj",
        b"# \xff\xfe\no \xc3\x28\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
        3,
        1,
        0,
    );
}

#[test]
fn obj_line_continuations_are_named_in_the_error() {
    fails("a.obj", "v 0 0 \\\n 0\n", "line 1", &["'\\'"]);
}

#[test]
fn obj_cut_at_every_offset() {
    let bytes = icosphere_bytes(Format::Obj, PlyEncoding::Ascii);
    // OBJ has no counts, so a cut at a line break is a smaller valid file; cuts inside a
    // face line may be errors; none may panic.
    every_prefix("a.obj", &bytes);
}

// ---------------------------------------------------------------------------------------
// PLY
// ---------------------------------------------------------------------------------------

#[test]
fn ply_empty_and_header_only() {
    fails("a.ply", "", "file", &["empty file"]);
    fails("a.ply", "ply\n", "line 1", &["no end_header"]);
    fails(
        "a.ply",
        "ply\nformat ascii 1.0\n",
        "line 2",
        &["no end_header"],
    );
    fails("a.ply", PLY_HEAD, "line 9", &["truncated", "vertex 0"]);
    fails(
        "a.ply",
        "ply\nformat ascii 1.0\nend_header\n",
        "line 3",
        &["no vertex element"],
    );
    fails("a.ply", "solid x\n", "line 1", &["not a PLY file"]);
}

#[test]
fn ply_headers_claiming_a_trillion_elements_allocate_nothing() {
    // Each would need terabytes if the count were trusted; the file holds a few bytes.
    let t = "1000000000000";
    fails(
        "a.ply",
        PLY_HEAD.replace("vertex 3", &format!("vertex {t}")) + TRIANGLE_BODY,
        "line",
        &["2^32-1"],
    );
    fails(
        "a.ply",
        PLY_HEAD.replace("face 1", &format!("face {t}")) + TRIANGLE_BODY,
        "line 13",
        &["truncated", "face 1 (of 1000000000000 face elements)"],
    );
    fails(
        "a.ply",
        binary_ply(("3", t), &TRIANGLE, &[&[0, 1, 2]]),
        "byte",
        &["truncated", "face 1"],
    );
    fails(
        "a.ply",
        binary_ply(("4000000000", "1"), &TRIANGLE, &[&[0, 1, 2]]),
        "byte",
        &["truncated", "vertex 4 (of 4000000000"],
    );
    let skipped = PLY_HEAD.replace(
        "end_header",
        &format!("element material {t}\nproperty list int float rgb\nend_header"),
    );
    fails(
        "a.ply",
        skipped + TRIANGLE_BODY,
        "line 15",
        &["truncated", "material 0"],
    );
    let skipped = PLY_HEAD.replace(
        "end_header",
        &format!("element material {t}\nproperty float r\nend_header"),
    );
    fails(
        "a.ply",
        skipped + TRIANGLE_BODY,
        "line 15",
        &["truncated", "material 0"],
    );
}

#[test]
fn ply_list_lengths_beyond_the_file_allocate_nothing() {
    let mut bytes = binary_ply(("3", "1"), &TRIANGLE, &[&[0, 1, 2]]);
    let header = bytes.len() - 36 - 13;
    bytes[header + 36] = 250;
    fails("a.ply", &bytes, "byte", &["truncated", "face 0"]);
    // An int count of 2^31 - 1.
    let text = PLY_HEAD.replace("list uchar int", "list int int");
    let mut bytes = text.replace("ascii", "binary_little_endian").into_bytes();
    for p in TRIANGLE.iter().flatten() {
        bytes.extend_from_slice(&p.to_le_bytes());
    }
    bytes.extend_from_slice(&i32::MAX.to_le_bytes());
    bytes.extend_from_slice(&[0u8; 12]);
    fails("a.ply", &bytes, "byte", &["truncated", "face 0"]);
    fails(
        "a.ply",
        PLY_HEAD.replace("uchar", "int") + "0 0 0\n1 0 0\n0 1 0\n-3 0 1 2\n",
        "line 13",
        &["negative list length -3"],
    );
    let strips = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
                  property float z\nelement tristrips 1\nproperty list int int vertex_indices\n\
                  end_header\n0 0 0\n1 0 0\n0 1 0\n2000000000 0 1 2\n";
    fails("a.ply", strips, "line 13", &["truncated", "tristrips 0"]);
}

#[test]
fn ply_bad_values() {
    let body = |b: &str| PLY_HEAD.to_string() + b;
    fails(
        "a.ply",
        body("0 0 0\nnan 0 0\n0 1 0\n3 0 1 2\n"),
        "line 11",
        &["NaN"],
    );
    fails(
        "a.ply",
        body("0 0 0\n1 0 0\n0 inf 0\n3 0 1 2\n"),
        "line 12",
        &["infinite"],
    );
    fails(
        "a.ply",
        body("0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n"),
        "line 13",
        &["index -1"],
    );
    fails(
        "a.ply",
        body("0 0 0\n1 0 0\n0 1 0\n3 0 4294967296 2\n"),
        "line 13",
        &["4294967296 out of range"],
    );
    fails(
        "a.ply",
        body("0 0 0\n1 0 0\n0 1 0\n0\n"),
        "line 13",
        &["0 vertices"],
    );
    fails(
        "a.ply",
        body("0 0 0\n1 0 0\n0 1 0\n2 0 1\n"),
        "line 13",
        &["2 vertices"],
    );
    fails(
        "a.ply",
        body("0 0 0\n1 0 0\n0 1 0\n3 0 x 2\n"),
        "line 13",
        &["'x'"],
    );
    let mut nan = TRIANGLE;
    nan[1][0] = f32::NAN;
    fails(
        "a.ply",
        binary_ply(("3", "1"), &nan, &[&[0, 1, 2]]),
        "byte",
        &["NaN"],
    );
    fails(
        "a.ply",
        binary_ply(("3", "1"), &TRIANGLE, &[&[0, -7, 2]]),
        "byte",
        &["index -7 out of range"],
    );
    fails(
        "a.ply",
        binary_ply(("3", "1"), &TRIANGLE, &[&[0, 1]]),
        "byte",
        &["2 vertices"],
    );
}

#[test]
fn ply_wrong_counts() {
    // Fewer records than declared: truncated. More: the rest is ignored.
    fails(
        "a.ply",
        PLY_HEAD.to_string() + "0 0 0\n1 0 0\n",
        "line 11",
        &["truncated"],
    );
    reads(
        "a.ply",
        PLY_HEAD.to_string() + TRIANGLE_BODY + "3 0 1 2\n",
        3,
        1,
        0,
    );
    fails(
        "a.ply",
        binary_ply(("3", "2"), &TRIANGLE, &[&[0, 1, 2]]),
        "byte",
        &["truncated", "face 1"],
    );
    fails(
        "a.ply",
        "ply\nformat ascii 1.0\nelement vertex -1\n",
        "line 3",
        &["not a non-negative integer"],
    );
}

#[test]
fn ply_polygons_duplicates_and_point_clouds() {
    let head = PLY_HEAD
        .replace("vertex 3", "vertex 5")
        .replace("face 1", "face 3");
    let body = "0 0 0\n1 0 0\n1 1 0\n0 1 0\n9 9 9\n5 0 1 2 3 0\n3 0 1 2\n3 0 1 2\n";
    // A pentagon with a repeated corner: three fan triangles, one of them degenerate.
    reads("a.ply", head + body, 5, 4, 1);
    let cloud = "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n\
                 property float z\nend_header\n1 2 3\n4 5 6\n";
    reads("a.ply", cloud, 2, 0, 0);
}

#[test]
fn ply_tristrips() {
    let head = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n\
                property float z\nelement tristrips 1\nproperty list int int vertex_indices\n\
                end_header\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n";
    reads("a.ply", format!("{head}4 0 1 2 3\n"), 4, 2, 0);
    reads("a.ply", format!("{head}3 -1 -1 -1\n"), 4, 0, 0);
    reads("a.ply", format!("{head}0\n"), 4, 0, 0);
    fails(
        "a.ply",
        format!("{head}4 0 1 2 4\n"),
        "line 14",
        &["index 4 out of range"],
    );
    fails(
        "a.ply",
        format!("{head}4 0 1 -2 3\n"),
        "line 14",
        &["index -2 out of range"],
    );
}

#[test]
fn ply_crlf_bom_comments_and_skipped_elements() {
    let text = PLY_HEAD.to_string() + TRIANGLE_BODY;
    reads("a.ply", crlf(&text), 3, 1, 0);
    reads("a.ply", with_bom(&text), 3, 1, 0);
    let commented = text
        .replace("format", "comment made by hand\nformat")
        .replace(
            "element face",
            "comment between\nobj_info x\nelement edge 1\nproperty int a\n\
                  property int b\nelement face",
        )
        .replace("3 0 1 2", "0 1\n3 0 1 2");
    reads("a.ply", commented, 3, 1, 0);
    // A binary body after a CRLF header.
    let mut binary = binary_ply(("3", "1"), &TRIANGLE, &[&[0, 1, 2]]);
    let end = binary
        .windows(11)
        .position(|w| w == b"end_header\n")
        .unwrap()
        + 11;
    let head = crlf(std::str::from_utf8(&binary[..end]).unwrap());
    binary.splice(..end, head.into_bytes());
    reads("a.ply", &binary, 3, 1, 0);
    // A BOM before a binary file: errors in the body still give the byte in the file.
    let mut bytes = vec![0xef, 0xbb, 0xbf];
    bytes.extend(binary_ply(("3", "1"), &TRIANGLE, &[&[0, 9, 2]]));
    let at = bytes.len() - 8;
    fails("a.ply", &bytes, &format!("byte {at}"), &["index 9"]);
}

#[test]
fn ply_malformed_headers() {
    fails(
        "a.ply",
        "ply\nformat ascii 1.0\nelement vertex 1\nproperty list uchar float x\nproperty float y\n\
         property float z\nend_header\n",
        "line 7",
        &["'x' is a list"],
    );
    fails(
        "a.ply",
        "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\n\
         property float z\nelement vertex 0\nend_header\n",
        "line 8",
        &["two vertex elements"],
    );
    fails(
        "a.ply",
        "ply\nformat ascii 1.0\nelement vertex 0\nproperty int64 x\n",
        "line 4",
        &["unknown property type 'int64'"],
    );
}

#[test]
fn ply_cut_at_every_offset() {
    for encoding in [
        PlyEncoding::Ascii,
        PlyEncoding::BinaryLittleEndian,
        PlyEncoding::BinaryBigEndian,
    ] {
        let bytes = icosphere_bytes(Format::Ply, encoding);
        // PLY declares its counts: a cut before the last record is always an error.
        let failures = every_prefix("a.ply", &bytes);
        let last = match encoding {
            PlyEncoding::Ascii => bytes[..bytes.len() - 1]
                .iter()
                .rposition(|&b| b == b'\n')
                .unwrap(),
            _ => bytes.len() - 13,
        };
        assert!(
            failures > last,
            "{encoding:?}: {failures} of {} cuts fail",
            bytes.len()
        );
    }
}

// ---------------------------------------------------------------------------------------
// OFF
// ---------------------------------------------------------------------------------------

const TETRA_OFF: &str = "OFF\n4 4 6\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n\
                         3 1 2 3\n";

#[test]
fn off_empty_and_header_only() {
    fails("a.off", "", "file", &["empty file"]);
    fails("a.off", "OFF\n", "line 1", &["missing counts line"]);
    fails("a.off", "OFF\n4\n", "line 2", &["missing face count"]);
    fails("a.off", "OFF\n4 4 6\n", "line 2", &["0 of 4 vertices"]);
    fails("a.off", "COFF 4 x 6\n", "line 1", &["face count 'x'"]);
    fails("a.off", "4OFF\n", "line 1", &[]);
}

#[test]
fn off_counts_of_a_trillion_allocate_nothing() {
    fails(
        "a.off",
        "OFF\n1000000000000 1 0\n0 0 0\n",
        "line 2",
        &["2^32-1"],
    );
    fails(
        "a.off",
        "OFF\n3 1000000000000 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
        "line",
        &["1 of 1000000000000 faces"],
    );
}

#[test]
fn off_bad_records() {
    let v = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n";
    fails(
        "a.off",
        format!("{v}3 0 1 3\n"),
        "line 6",
        &["3 out of range"],
    );
    fails("a.off", format!("{v}3 0 -1 2\n"), "line 6", &["-1"]);
    fails(
        "a.off",
        format!("{v}3 0 1 99999999999999999999\n"),
        "line 6",
        &[],
    );
    fails("a.off", format!("{v}2 0 1\n"), "line 6", &["2"]);
    fails("a.off", format!("{v}0\n"), "line 6", &["0"]);
    fails("a.off", format!("{v}4 0 1 2\n"), "line 6", &[]);
    fails(
        "a.off",
        "OFF\n3 1 0\n0 0 0\nnan 0 0\n0 1 0\n3 0 1 2\n",
        "line 4",
        &["NaN"],
    );
    fails(
        "a.off",
        "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1e999 0\n3 0 1 2\n",
        "line 5",
        &["infinite"],
    );
}

#[test]
fn off_polygons_colours_crlf_bom_and_comments() {
    reads("a.off", TETRA_OFF, 4, 4, 0);
    reads("a.off", crlf(TETRA_OFF), 4, 4, 0);
    reads("a.off", with_bom(TETRA_OFF), 4, 4, 0);
    let commented = "# head\nOFF # keyword\n\n# counts next\n4 4 6\n0 0 0 # v0\n# between\n\
                     1 0 0\n0 1 0\n\n0 0 1\n3 0 2 1 # f0\n3 0 1 3\n# x\n3 0 3 2\n3 1 2 3\n";
    reads("a.off", commented, 4, 4, 0);
    reads(
        "a.off",
        "COFF\n4 1 0\n0 0 0 1 0 0 1\n1 0 0 1 0 0 1\n1 1 0 1 0 0 1\n0 1 0 1 0 0 1\n\
         4 0 1 2 3 255 0 0\n",
        4,
        2,
        0,
    );
}

#[test]
fn off_cut_at_every_offset() {
    let bytes = icosphere_bytes(Format::Off, PlyEncoding::Ascii);
    let failures = every_prefix("a.off", &bytes);
    let last = bytes[..bytes.len() - 1]
        .iter()
        .rposition(|&b| b == b'\n')
        .unwrap();
    assert!(failures > last, "{failures} of {} cuts fail", bytes.len());
}

// ---------------------------------------------------------------------------------------
// STL
// ---------------------------------------------------------------------------------------

#[test]
fn stl_empty_header_only_and_truncated() {
    fails("a.stl", "", "file", &["empty file"]);
    fails("a.stl", "solid x\n", "file", &["no vertices"]);
    fails("a.stl", "solid x\nendsolid x\n", "file", &["no vertices"]);
    fails("a.stl", binary_stl(0, &[]), "file", &["no vertices"]);
    let bytes = binary_stl(2, &[[[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]]);
    fails(
        "a.stl",
        &bytes,
        "byte 134",
        &["truncated", "declares 2 triangles"],
    );
    fails(
        "a.stl",
        "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n",
        "line 4",
        &["ends inside a facet"],
    );
}

#[test]
fn stl_binary_count_of_four_billion_allocates_nothing() {
    let bytes = binary_stl(u32::MAX, &[[[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]]);
    fails(
        "a.stl",
        &bytes,
        "byte 134",
        &["truncated", "4294967295 triangles"],
    );
}

#[test]
fn stl_bad_values() {
    let mut t = [[[0.0f32; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]];
    t[0][1][1] = f32::INFINITY;
    fails(
        "a.stl",
        binary_stl(1, &t),
        "byte 112",
        &["corner 1", "y coordinate", "infinite"],
    );
    fails(
        "a.stl",
        STL_ASCII.replace("vertex 1 0 0", "vertex 1 nan 0"),
        "line 5",
        &["NaN"],
    );
    fails(
        "a.stl",
        STL_ASCII.replace("vertex 1 0 0", "vertex 1 0"),
        "line 5",
        &["missing z"],
    );
    fails(
        "a.stl",
        STL_ASCII.replace("vertex 1 0 0\n", ""),
        "line 6",
        &["2 vertices"],
    );
    fails(
        "a.stl",
        STL_ASCII.replace("outer loop\n", ""),
        "line 3",
        &["outside an 'outer loop'"],
    );
}

#[test]
fn stl_polygons_crlf_bom_and_degenerate_facets() {
    reads("a.stl", STL_ASCII, 3, 1, 0);
    reads("a.stl", crlf(STL_ASCII), 3, 1, 0);
    reads("a.stl", with_bom(STL_ASCII), 3, 1, 0);
    let quad = STL_ASCII.replace("vertex 0 1 0\n", "vertex 1 1 0\nvertex 0 1 0\n");
    reads("a.stl", quad, 4, 2, 0);
    let sliver = STL_ASCII.replace("vertex 0 1 0", "vertex 2 0 0");
    reads("a.stl", sliver, 3, 0, 1);
    let mut twice = binary_stl(2, &[[[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]; 2]);
    reads("a.stl", &twice, 3, 2, 0);
    twice.extend_from_slice(b"trailing junk");
    reads("a.stl", &twice, 3, 2, 0);
}

#[test]
fn stl_cut_at_every_offset() {
    let mesh = shapes::icosphere(1.0, 0);
    let mut binary = Vec::new();
    write_mesh_to(&mut binary, &mesh, Format::Stl, &WriteOptions::default()).unwrap();
    let failures = every_prefix("a.stl", &binary);
    assert_eq!(failures, binary.len(), "every cut of a binary STL fails");
    every_prefix("a.stl", STL_ASCII.as_bytes());
}

// ---------------------------------------------------------------------------------------
// Feature-line OBJ and diffusion masks
// ---------------------------------------------------------------------------------------

#[test]
fn lines_files() {
    let lines = |t: &[u8]| parse_lines_obj(t, Path::new("l.obj")).map_err(|e| e.to_string());
    assert_eq!(lines(b"").unwrap_err(), "l.obj: file: empty file");
    assert!(
        lines(b"v 0 0 0\nl 1\n")
            .unwrap_err()
            .starts_with("l.obj: line 2: ")
    );
    assert!(
        lines(b"v 0 0 0\nv 1 1 1\nl 1 3\n")
            .unwrap_err()
            .contains("3 out of range")
    );
    assert!(
        lines(b"v 0 0 0\nv 1 1 1\nl 1 -3\n")
            .unwrap_err()
            .contains("before the first")
    );
    let huge = lines(b"v 0 0 0\nv 1 1 1\nl 1 99999999999999999999\n").unwrap_err();
    assert!(huge.starts_with("l.obj: line 3: "), "{huge}");
    assert!(
        lines(b"v 0 inf 0\n")
            .unwrap_err()
            .contains("NaN or infinite")
    );
    let text = "o ridges\nv 0 0 0\nv 1 0 0 # x\n# c\nl 1 2\n";
    for bytes in [
        text.as_bytes().to_vec(),
        crlf(text).into_bytes(),
        with_bom(text),
    ] {
        let l = lines(&bytes).unwrap();
        assert_eq!(l.lines.len(), 1);
        assert_eq!(l.lines[0].length, 1.0);
    }
    // No panic on any cut.
    for end in 0..text.len() {
        let _ = lines(&text.as_bytes()[..end]);
    }
}

#[test]
fn diffusion_mask_files() {
    let mask = |t: &[u8], n: usize| {
        parse_diffusion_factors(t, n, Path::new("m.txt")).map_err(|e| e.to_string())
    };
    assert_eq!(mask(b"1 0.5\n# c\n0\n", 3).unwrap(), vec![1.0, 0.5, 0.0]);
    assert_eq!(mask(&with_bom("1\r\n2\r\n"), 2).unwrap(), vec![1.0, 2.0]);
    assert_eq!(
        mask(b"", 2).unwrap_err(),
        "m.txt: file: 0 factors for a mesh of 2 vertices"
    );
    assert_eq!(
        mask(b"1\n2\n3\n", 2).unwrap_err(),
        "m.txt: line 3: more factors than the 2 vertices of the mesh"
    );
    assert_eq!(
        mask(b"1\nnan\n", 2).unwrap_err(),
        "m.txt: line 2: factor 'nan' must be a finite number >= 0"
    );
    assert_eq!(
        mask(b"1\n-2\n", 2).unwrap_err(),
        "m.txt: line 2: factor '-2' must be a finite number >= 0"
    );
    assert_eq!(
        mask(b"1\n\xff\n", 2).unwrap_err(),
        "m.txt: line 2: non-numeric token '\u{fffd}' where a factor was expected"
    );
}

// ---------------------------------------------------------------------------------------
// Files and paths
// ---------------------------------------------------------------------------------------

#[test]
fn missing_file_and_directory_as_input() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("missing.obj");
    let e = read_mesh(&missing, None).unwrap_err().to_string();
    assert_eq!(
        e,
        format!(
            "{}: No such file or directory (os error 2)",
            missing.display()
        )
    );
    // The cause is said once, in the message: it is not also the error's source (a chain of
    // causes, as anyhow prints it, would say it twice).
    let e = read_mesh(&missing, None).unwrap_err();
    assert!(std::error::Error::source(&e).is_none());
    let folder = dir.path().join("folder.obj");
    std::fs::create_dir(&folder).unwrap();
    let e = read_mesh(&folder, None).unwrap_err().to_string();
    assert!(e.starts_with(&format!("{}: ", folder.display())), "{e}");
    assert!(e.contains("directory"), "{e}");
}

/// Files in `dir`, sorted.
fn listing(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

#[test]
fn unwritable_outputs_leave_nothing_behind() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = shapes::icosphere(1.0, 1);
    let options = WriteOptions::default();
    // Into a folder that does not exist.
    let nowhere = dir.path().join("no/such/dir/out.obj");
    let e = write_mesh(&nowhere, &mesh, Format::Obj, &options).unwrap_err();
    assert!(
        e.to_string()
            .starts_with(&format!("{}: ", nowhere.display())),
        "{e}"
    );
    // Onto a folder.
    let folder = dir.path().join("out.ply");
    std::fs::create_dir(&folder).unwrap();
    let e = write_mesh(&folder, &mesh, Format::Ply, &options).unwrap_err();
    assert!(
        e.to_string()
            .starts_with(&format!("{}: ", folder.display())),
        "{e}"
    );
    assert!(folder.is_dir());
    assert_eq!(listing(dir.path()), vec!["out.ply"]);
    // Into a folder without write permission (unless running as root, who may write anyway).
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        let locked = dir.path().join("locked");
        std::fs::create_dir(&locked).unwrap();
        std::fs::set_permissions(&locked, std::fs::Permissions::from_mode(0o500)).unwrap();
        let target = locked.join("out.obj");
        if let Err(e) = write_mesh(&target, &mesh, Format::Obj, &options) {
            assert!(
                e.to_string()
                    .starts_with(&format!("{}: ", target.display())),
                "{e}"
            );
            assert!(listing(&locked).is_empty());
        }
        std::fs::set_permissions(&locked, std::fs::Permissions::from_mode(0o700)).unwrap();
    }
}

#[test]
fn output_over_its_own_input_is_replaced_whole() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("m.obj");
    std::fs::write(&path, TETRA_OBJ).unwrap();
    let mesh = read_mesh(&path, None).unwrap();
    let (mesh, _) = orient_outward(mesh).unwrap();
    write_mesh(&path, &mesh, Format::Obj, &WriteOptions::default()).unwrap();
    let back = read_mesh(&path, None).unwrap();
    assert_eq!(back.positions(), mesh.positions());
    assert_eq!(back.faces(), mesh.faces());
    assert_eq!(listing(dir.path()), vec!["m.obj"]);
}

#[test]
fn a_failed_write_keeps_the_old_file() {
    use crestline::io::lines::write_lines;
    use crestline::lines::{FeatureLine, FeatureLines, LineKind};
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("lines.json");
    std::fs::write(&path, "old").unwrap();
    // A line with a non-finite point cannot be written: the error comes before any byte
    // replaces the old file.
    let bad = FeatureLines {
        lines: vec![FeatureLine {
            kind: LineKind::Ridge,
            points: vec![
                crestline::Vec3::zeros(),
                crestline::Vec3::new(f64::NAN, 0.0, 0.0),
            ],
            locations: Vec::new(),
            closed: false,
            length: f64::NAN,
            curvature_integral: 0.0,
            strength: 0.0,
            crease: false,
        }],
    };
    for name in ["lines.json", "lines.obj", "lines.ply"] {
        let path = dir.path().join(name);
        std::fs::write(&path, "old").unwrap();
        let e = write_lines(&path, &bad, None, PlyEncoding::Ascii).unwrap_err();
        assert!(e.to_string().contains("must be finite"), "{name}: {e}");
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "old", "{name}");
    }
    assert_eq!(
        listing(dir.path()),
        vec!["lines.json", "lines.obj", "lines.ply"]
    );
}

// ---------------------------------------------------------------------------------------
// Awkward meshes through the whole pipeline
// ---------------------------------------------------------------------------------------

/// Runs every method on `mesh`: each gives lines with finite numbers or a clear error.
fn every_method(name: &str, mesh: &TriMesh) {
    for method in [Method::Hpw, Method::Ybs, Method::Saliency] {
        match extract(mesh, &ExtractOptions::for_method(method)) {
            Ok(x) => {
                for l in &x.lines.lines {
                    assert!(
                        l.points.iter().all(|p| p.iter().all(|c| c.is_finite()))
                            && l.length.is_finite()
                            && l.strength.is_finite(),
                        "{name} {method:?}: a line with a non-finite number"
                    );
                }
            }
            Err(e) => {
                let m = e.to_string();
                assert!(!m.is_empty(), "{name} {method:?}");
            }
        }
    }
}

fn mesh(positions: &[[f64; 3]], faces: &[[u32; 3]]) -> TriMesh {
    TriMesh::from_arrays(positions.to_vec(), faces.to_vec()).unwrap()
}

#[test]
fn isolated_vertices_only() {
    let m = mesh(&[[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 2.0]], &[]);
    assert_eq!(m.topology().count_vertices(VertexKind::Unreferenced), 3);
    every_method("isolated vertices", &m);
}

#[test]
fn one_triangle_and_a_single_degenerate_one() {
    every_method(
        "one triangle",
        &mesh(&TRIANGLE.map(|p| p.map(f64::from)), &[[0, 1, 2]]),
    );
    let m = mesh(&[[0.0; 3], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]], &[[0, 1, 2]]);
    assert_eq!((m.num_faces(), m.degenerate_faces()), (0, 1));
    every_method("degenerate only", &m);
}

#[test]
fn non_manifold_fan() {
    // Six triangles around one edge (0, 1), each a fin pointing another way.
    let mut positions = vec![[0.0, 0.0, -1.0], [0.0, 0.0, 1.0]];
    let mut faces = Vec::new();
    for k in 0..6 {
        let a = k as f64 * std::f64::consts::TAU / 6.0;
        positions.push([a.cos(), a.sin(), 0.0]);
        faces.push([0, 1, 2 + k]);
    }
    let m = mesh(&positions, &faces);
    assert_eq!(m.topology().count_edges(EdgeKind::NonManifold), 1);
    every_method("non-manifold fan", &m);
    // Two tetrahedra sharing one vertex (a non-manifold vertex) and the fan together.
    let (sphere, _) = orient_outward(shapes::icosphere(1.0, 2)).unwrap();
    let n = sphere.num_vertices() as u32;
    let mut positions: Vec<[f64; 3]> = sphere.positions().iter().map(|p| [p.x, p.y, p.z]).collect();
    let mut faces = sphere.faces().to_vec();
    positions.extend(sphere.positions().iter().map(|p| [p.x + 2.0, p.y, p.z]));
    faces.extend(sphere.faces().iter().map(|t| t.map(|v| v + n)));
    // Glue vertex 0 of the second sphere onto the first sphere's vertex 0... by index.
    for t in faces.iter_mut().skip(sphere.num_faces()) {
        for v in t.iter_mut() {
            if *v == n {
                *v = 0;
            }
        }
    }
    every_method("spheres sharing a vertex", &mesh(&positions, &faces));
}

/// A Moebius strip of `n` quads across its width.
fn moebius(n: usize) -> TriMesh {
    let mut positions = Vec::new();
    for i in 0..n {
        let t = i as f64 * std::f64::consts::TAU / n as f64;
        for s in [-0.3, 0.3] {
            let r = 1.0 + s * (t / 2.0).cos();
            positions.push([r * t.cos(), r * t.sin(), s * (t / 2.0).sin()]);
        }
    }
    let mut faces = Vec::new();
    for i in 0..n as u32 {
        let (a, b) = (2 * i, 2 * i + 1);
        // The last quad joins the strip to itself with a half twist.
        let (c, d) = if i + 1 == n as u32 {
            (1, 0)
        } else {
            (2 * i + 2, 2 * i + 3)
        };
        faces.push([a, c, b]);
        faces.push([b, c, d]);
    }
    TriMesh::from_arrays(positions, faces).unwrap()
}

#[test]
fn moebius_strip() {
    let m = moebius(120);
    assert_eq!(m.topology().count_edges(EdgeKind::NonManifold), 0);
    let (oriented, report) = orient_outward(m).unwrap();
    assert_eq!(report.closed, 0);
    every_method("moebius", &oriented);
}

#[test]
fn inconsistent_winding() {
    // A sphere with every third triangle flipped: still read, oriented where closed.
    let sphere = shapes::icosphere(1.0, 3);
    let faces: Vec<[u32; 3]> = sphere
        .faces()
        .iter()
        .enumerate()
        .map(|(f, &[a, b, c])| if f % 3 == 0 { [a, c, b] } else { [a, b, c] })
        .collect();
    let positions: Vec<[f64; 3]> = sphere.positions().iter().map(|p| [p.x, p.y, p.z]).collect();
    let m = mesh(&positions, &faces);
    let (m, _) = orient_outward(m).unwrap();
    every_method("inconsistent winding", &m);
}

#[test]
fn duplicate_faces_through_the_pipeline() {
    let sphere = shapes::icosphere(1.0, 2);
    let positions: Vec<[f64; 3]> = sphere.positions().iter().map(|p| [p.x, p.y, p.z]).collect();
    let mut faces = sphere.faces().to_vec();
    faces.extend_from_slice(&sphere.faces()[..20]);
    every_method("duplicate faces", &mesh(&positions, &faces));
}

#[test]
fn extreme_but_valid_scales_give_finite_lines() {
    for scale in [1e-60, 1e-30, 1e30, 1e60] {
        let m = shapes::ellipsoid(3.0 * scale, 2.0 * scale, scale, 2);
        every_method(&format!("ellipsoid at scale {scale:e}"), &m);
    }
}
