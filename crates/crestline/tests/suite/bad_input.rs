//! The bad-input suite: broken, odd and hostile files in every format the library reads (OBJ,
//! PLY ascii / binary / tristrips, OFF, STL ascii / binary, feature-line OBJ, diffusion-mask
//! files), and awkward meshes run through the whole pipeline.
//!
//! Every case ends in one of two ways, and the test says which: an error that names the file,
//! a position in it (line or byte; none for the file as a whole) and what is wrong; or a correct result, with what
//! was skipped counted. Nothing panics, hangs or allocates from a header's word alone.
//! STL, feature-line and mask files, paths and whole-pipeline cases are in
//! `bad_input_files.rs`; `io_robustness.rs` adds random damage; the CLI's side is in
//! `crates/crestline-cli/tests/bad_input_cli.rs`.

// Test code: stopping loudly on the first surprise is the point.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::path::Path;

use crestline::extract::{ExtractOptions, extract};
use crestline::io::{Format, PlyEncoding, WriteOptions, read_mesh_bytes, write_mesh_to};
use crestline::{Error, Location, TriMesh, shapes};

use super::bad_input_files::every_method;

// ---------------------------------------------------------------------------------------
// Helpers
// ---------------------------------------------------------------------------------------

/// Reads `bytes` as the format named by `name`'s extension.
pub(super) fn read(name: &str, bytes: &[u8]) -> crestline::Result<TriMesh> {
    let format = Format::from_path(Path::new(name)).unwrap();
    read_mesh_bytes(bytes, format, Path::new(name))
}

/// The error of reading `bytes`; it must name the file and `location` ("line 3", "byte 84",
/// or "file": the file as a whole, named alone) and contain every one of `words`.
#[track_caller]
pub(super) fn fails(name: &str, bytes: impl AsRef<[u8]>, location: &str, words: &[&str]) {
    let message = match read(name, bytes.as_ref()) {
        Ok(m) => panic!(
            "{name}: read as a mesh of {} vertices and {} triangles, expected an error at \
             {location}",
            m.num_vertices(),
            m.num_faces()
        ),
        Err(e) => {
            let whole = matches!(
                e,
                Error::Parse {
                    location: Location::File,
                    ..
                }
            );
            assert_eq!(whole, location == "file", "{name}: {e} (wanted {location})");
            e.to_string()
        }
    };
    // "byte" or "line" alone: any byte or line.
    let prefix = if location == "file" {
        format!("{name}: ")
    } else if location.ends_with(|c: char| c.is_ascii_digit()) {
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
pub(super) fn reads(
    name: &str,
    bytes: impl AsRef<[u8]>,
    vertices: usize,
    faces: usize,
    degenerate: usize,
) {
    let m = read(name, bytes.as_ref()).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(
        (m.num_vertices(), m.num_faces(), m.degenerate_faces()),
        (vertices, faces, degenerate),
        "{name}: (vertices, triangles, degenerate)"
    );
}

/// Every prefix of `bytes` reads without a panic, and failures name the file and a position.
/// Returns how many prefixes failed.
pub(super) fn every_prefix(name: &str, bytes: &[u8]) -> usize {
    let mut failures = 0;
    for end in 0..bytes.len() {
        if let Err(e) = read(name, &bytes[..end]) {
            let m = e.to_string();
            let rest = m
                .strip_prefix(&format!("{name}: "))
                .unwrap_or_else(|| panic!("prefix of {end} bytes: {m}"));
            // A position, or none for the file as a whole.
            let positioned = rest.starts_with("line ") || rest.starts_with("byte ");
            let whole = matches!(
                e,
                Error::Parse {
                    location: Location::File,
                    ..
                }
            );
            assert!(
                matches!(e, Error::Parse { .. }) && positioned != whole,
                "prefix of {end} bytes: {m}"
            );
            failures += 1;
        }
    }
    failures
}

pub(super) fn with_bom(text: &str) -> Vec<u8> {
    let mut bytes = vec![0xef, 0xbb, 0xbf];
    bytes.extend_from_slice(text.as_bytes());
    bytes
}

pub(super) fn crlf(text: &str) -> String {
    text.replace('\n', "\r\n")
}

/// [`reads`] of `text` as it is, with CRLF line ends, after a byte order mark, and both.
pub(super) fn reads_with_crlf_and_bom(
    name: &str,
    text: &str,
    vertices: usize,
    faces: usize,
    degenerate: usize,
) {
    reads(name, text, vertices, faces, degenerate);
    reads(name, crlf(text), vertices, faces, degenerate);
    reads(name, with_bom(text), vertices, faces, degenerate);
    reads(name, with_bom(&crlf(text)), vertices, faces, degenerate);
}

/// A tetrahedron (closed, outward) as OBJ.
pub(super) const TETRA_OBJ: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n\
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

pub(super) const TRIANGLE: [[f32; 3]; 3] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];

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

/// A prism of height 1 over a U (a 3 × 3 square with a 1 × 2 notch cut from the middle of its
/// top side), its caps one 8-gon each, as CAD exporters and Blender write it: positions, then
/// polygons (0-based, wound to face out).
fn u_prism() -> (Vec<[f64; 3]>, Vec<Vec<usize>>) {
    let outline = [
        [0., 0.],
        [3., 0.],
        [3., 3.],
        [2., 3.],
        [2., 1.],
        [1., 1.],
        [1., 3.],
        [0., 3.],
    ];
    let positions: Vec<[f64; 3]> = [0.0, 1.0]
        .iter()
        .flat_map(|&z| outline.iter().map(move |&[x, y]| [x, y, z]))
        .collect();
    let mut polygons = vec![(0..8).rev().collect::<Vec<_>>(), (8..16).collect()];
    polygons.extend((0..8).map(|i| vec![i, (i + 1) % 8, (i + 1) % 8 + 8, i + 8]));
    (positions, polygons)
}

#[test]
fn non_convex_polygons_are_cut_inside_their_outline() {
    let (positions, polygons) = u_prism();
    let join = |p: &[usize], base: usize| {
        p.iter()
            .map(|i| (i + base).to_string())
            .collect::<Vec<_>>()
            .join(" ")
    };
    let coordinates = |p: &[f64; 3]| format!("{} {} {}", p[0], p[1], p[2]);
    let mut obj = String::new();
    let mut off = format!("OFF\n{} {} 0\n", positions.len(), polygons.len());
    let vertex_element = format!(
        "element vertex {}\nproperty double x\nproperty double y\nproperty double z\n",
        positions.len()
    );
    let face_element = format!(
        "element face {}\nproperty list uchar int vertex_indices\n",
        polygons.len()
    );
    let (mut ply_vertices, mut ply_faces) = (String::new(), String::new());
    for p in &positions {
        obj += &format!("v {}\n", coordinates(p));
        off += &format!("{}\n", coordinates(p));
        ply_vertices += &format!("{}\n", coordinates(p));
    }
    for p in &polygons {
        obj += &format!("f {}\n", join(p, 1));
        off += &format!("{} {}\n", p.len(), join(p, 0));
        ply_faces += &format!("{} {}\n", p.len(), join(p, 0));
    }
    let ply_head = "ply\nformat ascii 1.0\n";
    let ply =
        format!("{ply_head}{vertex_element}{face_element}end_header\n{ply_vertices}{ply_faces}");
    // The same prism with the faces before the vertices they use (both formats allow it).
    let ply_faces_first =
        format!("{ply_head}{face_element}{vertex_element}end_header\n{ply_faces}{ply_vertices}");
    let (vertices, faces) = obj.split_at(obj.find('f').unwrap());
    let obj_faces_first = format!("{faces}{vertices}");
    for (name, text) in [
        ("u.obj", &obj),
        ("faces-first.obj", &obj_faces_first),
        ("u.off", &off),
        ("u.ply", &ply),
        ("faces-first.ply", &ply_faces_first),
    ] {
        let mesh = read(name, text.as_bytes()).unwrap();
        let info = mesh.info();
        assert!(info.closed, "{name}: {info:?}");
        assert_eq!(info.inconsistent_components, 0, "{name}");
        // 6 triangles per cap, 2 per side, none flat.
        assert_eq!(
            (mesh.num_faces(), mesh.degenerate_faces()),
            (28, 0),
            "{name}"
        );
        let volume = crestline::mesh::signed_volume(&mesh);
        assert!((volume - 7.0).abs() < 1e-12, "{name}: volume {volume}");
        // The triangles of each cap face out as the cap does, and cover it once: a fan folds
        // some over the notch (inward, and adding to the area; the volume stays right).
        let mut area = 0.0;
        for f in 0..mesh.num_faces() {
            let [a, b, c] = mesh.triangle(f);
            let normal = (b - a).cross(&(c - a));
            area += normal.norm() / 2.0;
            if a.z == b.z && b.z == c.z {
                let outward = if a.z == 0.0 { -1.0 } else { 1.0 };
                assert!(normal.z * outward > 0.0, "{name}: triangle {f} faces in");
            }
        }
        // Caps 2 × 7, sides 16 (the perimeter) × 1.
        assert!((area - 30.0).abs() < 1e-12, "{name}: area {area}");
    }
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
    reads_with_crlf_and_bom("a.obj", TETRA_OBJ, 4, 4, 0);
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
fn obj_line_continuations_join_the_next_line() {
    // A backslash at the end of a line continues the record (the OBJ format); one inside a
    // comment does not, and one left inside a line is a token like any other.
    reads(
        "a.obj",
        "v 0 0 \\\n 0\nv 1 0 0\nv 0 1 0 # C:\\\nf 1 \\\n 2 \\\n 3\n",
        3,
        1,
        0,
    );
    fails("a.obj", "v 0 \\ 0 0\n", "line 1", &["'\\'"]);
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
fn ply_elements_without_properties_cost_nothing_whatever_their_count() {
    // Found by the `ply` fuzz target: an element of 10^18 records and no property made the
    // ascii reader loop over nothing for minutes. Such records hold no values: skipped.
    let head = "ply\nformat ascii 1.0\nelement stray 1000000000000000000\n";
    let ascii = PLY_HEAD.replace("ply\nformat ascii 1.0\n", head) + TRIANGLE_BODY;
    let mesh = read("a.ply", ascii.as_bytes()).unwrap();
    assert_eq!((mesh.num_vertices(), mesh.num_faces()), (3, 1));
    let mut binary = binary_ply(("3", "1"), &TRIANGLE, &[&[0, 1, 2]]);
    let at = binary.windows(7).position(|w| w == b"element").unwrap();
    binary.splice(
        at..at,
        b"element stray 1000000000000000000\n".iter().copied(),
    );
    let mesh = read("a.ply", &binary).unwrap();
    assert_eq!((mesh.num_vertices(), mesh.num_faces()), (3, 1));
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
    reads_with_crlf_and_bom("a.ply", &text, 3, 1, 0);
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
    reads_with_crlf_and_bom("a.off", TETRA_OFF, 4, 4, 0);
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
