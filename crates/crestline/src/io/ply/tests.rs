use super::*;
use std::path::Path;

use crate::io::{Format, read_mesh_bytes};
use crate::mesh::TriMesh;

fn parse_bytes(bytes: &[u8]) -> Result<MeshData> {
    parse(bytes, Source::new(Path::new("t.ply")))
}

fn error(bytes: &[u8]) -> String {
    parse_bytes(bytes).unwrap_err().to_string()
}

/// A header then binary data built by `body`.
fn binary(header: &str, body: impl FnOnce(&mut Vec<u8>)) -> Vec<u8> {
    let mut bytes = header.as_bytes().to_vec();
    body(&mut bytes);
    bytes
}

const SQUARE: [[f64; 3]; 4] = [
    [0.0, 0.0, 0.0],
    [1.0, 0.0, 0.0],
    [1.0, 1.0, 0.0],
    [0.0, 1.0, 0.0],
];

#[test]
fn ascii_with_extra_elements_and_properties() {
    let text = "ply\r\nformat ascii 1.0\r\ncomment anything # at all\r\n\
            element vertex 4\r\nproperty float x\r\nproperty float y\r\nproperty float z\r\n\
            property list uchar int junk\r\nproperty uchar red\r\n\
            element face 1\r\nproperty uchar flags\r\nproperty list uchar int vertex_indices\r\n\
            property float quality\r\n\
            element material 2\r\nproperty list int float values\r\n\
            end_header\r\n\
            0 0 0 2 7 7 255\r\n1 0 0 0 1\r\n1 1 0 1 9 0\r\n0 1 0 0 3\r\n\
            5 4 0 1 2 3 0.5\r\n\
            3 1.5 2 2.5\r\n0\r\n";
    let m = parse_bytes(text.as_bytes()).unwrap();
    assert_eq!(m.positions, SQUARE.to_vec());
    assert_eq!(m.faces, vec![[0, 1, 2], [0, 2, 3]]);
}

/// The same mesh as `ascii_with_extra_elements_and_properties`, binary, in both byte
/// orders, with every scalar type somewhere and `vertex_index` as the list name.
fn binary_square(big: bool) -> Vec<u8> {
    let header = format!(
        "ply\nformat binary_{}_endian 1.0\n\
             element vertex 4\nproperty int8 pad\nproperty double x\nproperty float32 y\n\
             property short z\nproperty list ushort uint16 junk\nproperty uint8 red\n\
             element face 1\nproperty uint flags\nproperty list uint8 int vertex_index\n\
             property float64 quality\n\
             element material 2\nproperty list int float values\nproperty char c\n\
             end_header\n",
        if big { "big" } else { "little" }
    );
    binary(&header, |b| {
        macro_rules! put {
            ($v:expr) => {
                if big {
                    b.extend_from_slice(&$v.to_be_bytes())
                } else {
                    b.extend_from_slice(&$v.to_le_bytes())
                }
            };
        }
        for (i, p) in SQUARE.iter().enumerate() {
            put!(-1i8);
            put!(p[0]);
            put!(p[1] as f32);
            put!(p[2] as i16);
            put!(i as u16);
            for _ in 0..i {
                put!(7u16);
            }
            put!(200u8);
        }
        put!(0xdead_beefu32);
        put!(4u8);
        for i in [0i32, 1, 2, 3] {
            put!(i);
        }
        put!(0.5f64);
        put!(2i32);
        put!(1.5f32);
        put!(2.5f32);
        put!(-3i8);
        put!(0i32);
        put!(4i8);
    })
}

#[test]
fn binary_little_and_big_endian_with_extra_elements() {
    for big in [false, true] {
        let m = parse_bytes(&binary_square(big)).unwrap();
        assert_eq!(m.positions, SQUARE.to_vec(), "big endian: {big}");
        assert_eq!(m.faces, vec![[0, 1, 2], [0, 2, 3]], "big endian: {big}");
    }
}

#[test]
fn integer_coordinates_are_accepted() {
    let bytes = binary(
        "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty uchar x\n\
             property int y\nproperty ushort z\nelement face 1\n\
             property list int uint vertex_indices\nend_header\n",
        |b| {
            for (x, y, z) in [(0u8, 0i32, 0u16), (250, -1, 1), (0, 1, 65535)] {
                b.push(x);
                b.extend_from_slice(&y.to_le_bytes());
                b.extend_from_slice(&z.to_le_bytes());
            }
            b.extend_from_slice(&3i32.to_le_bytes());
            for i in 0u32..3 {
                b.extend_from_slice(&i.to_le_bytes());
            }
        },
    );
    let m = parse_bytes(&bytes).unwrap();
    assert_eq!(m.positions[1], [250.0, -1.0, 1.0]);
    assert_eq!(m.positions[2], [0.0, 1.0, 65535.0]);
    assert_eq!(m.faces, vec![[0, 1, 2]]);
}

#[test]
fn tristrips_restart_alternate_and_drop_stitches() {
    let text = "ply\nformat ascii 1.0\nelement vertex 6\n\
            property float x\nproperty float y\nproperty float z\n\
            element tristrips 1\nproperty list int int vertex_indices\nend_header\n\
            0 0 0\n1 0 0\n0 1 0\n1 1 0\n0 2 0\n1 2 0\n\
            11 0 1 2 3 3 4 -1 4 5 2 -1\n";
    let m = parse_bytes(text.as_bytes()).unwrap();
    // Strip 0 1 2 3 3 4: (0 1 2), (2 1 3), (2 3 3) dropped, (3 3 4) dropped.
    // Strip 4 5 2: (4 5 2).
    assert_eq!(m.faces, vec![[0, 1, 2], [2, 1, 3], [4, 5, 2]]);
}

#[test]
fn strip_winding_alternates() {
    let mut faces = Vec::new();
    let mut strip = StripDecoder::default();
    for v in [0, 1, 2, 3, 4] {
        strip.push(v, &mut faces);
    }
    assert_eq!(faces, vec![[0, 1, 2], [2, 1, 3], [2, 3, 4]]);
    strip.restart();
    for v in [7, 8, 9] {
        strip.push(v, &mut faces);
    }
    assert_eq!(faces[3], [7, 8, 9]);
}

#[test]
fn binary_tristrips() {
    let bytes = binary(
        "ply\nformat binary_big_endian 1.0\nelement vertex 4\n\
             property float x\nproperty float y\nproperty float z\n\
             element tristrips 1\nproperty list int int vertex_indices\nend_header\n",
        |b| {
            for p in SQUARE {
                for c in p {
                    b.extend_from_slice(&(c as f32).to_be_bytes());
                }
            }
            b.extend_from_slice(&5i32.to_be_bytes());
            for i in [1i32, 2, 0, 3, -1] {
                b.extend_from_slice(&i.to_be_bytes());
            }
        },
    );
    let m = parse_bytes(&bytes).unwrap();
    assert_eq!(m.faces, vec![[1, 2, 0], [0, 2, 3]]);
}

#[test]
fn point_cloud_without_faces() {
    let m = parse_bytes(
        b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n\
              property float z\nend_header\n1 2 3\n",
    )
    .unwrap();
    assert_eq!(m.positions, vec![[1.0, 2.0, 3.0]]);
    assert!(m.faces.is_empty());
}

const ASCII_HEADER: &str = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n\
        property float y\nproperty float z\nelement face 1\n\
        property list uchar int vertex_indices\nend_header\n";

#[test]
fn malformed_headers() {
    assert_eq!(
        error(b"plx\nformat ascii 1.0\n"),
        "t.ply: line 1: not a PLY file: the first line is 'plx', expected 'ply'"
    );
    assert_eq!(
        error(b"ply\nformat ascii 1.0\nelement vertex 3\nproperty flaot x\n"),
        "t.ply: line 4: malformed header: unknown property type 'flaot'"
    );
    assert_eq!(
        error(b"ply\nformat ascii 1.0\nelement vertex many\n"),
        "t.ply: line 3: malformed header: element count 'many' is not a non-negative integer"
    );
    assert_eq!(
        error(b"ply\nformat ascii 1.0\nproperty float x\n"),
        "t.ply: line 3: malformed header: property before any element"
    );
    assert_eq!(
        error(b"ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\n"),
        "t.ply: line 4: malformed header: no end_header line"
    );
    assert_eq!(
        error(b"ply\nformat binary_middle_endian 1.0\n"),
        "t.ply: line 2: malformed header: unknown format 'binary_middle_endian'"
    );
    assert_eq!(
        error(b"ply\nelement vertex 0\nproperty float x\nend_header\n"),
        "t.ply: line 4: malformed header: no format line"
    );
    assert_eq!(
        error(
            b"ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\n\
                  property float y\nend_header\n"
        ),
        "t.ply: line 6: malformed header: the vertex element has no 'z' property"
    );
    assert_eq!(
        error(
            b"ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\n\
                  property float z\nelement face 0\nproperty list uchar float vertex_indices\n\
                  end_header\n"
        ),
        "t.ply: line 9: malformed header: the face indices 'vertex_indices' must have an \
             integer type"
    );
    assert_eq!(
        error(b"ply\nformat ascii 1.0\nelement vertex 0\nproperty list float int x\n"),
        "t.ply: line 4: malformed header: a list's count type must be an integer type"
    );
    assert_eq!(
        error(b"ply\nformat ascii 1.0\nelemnt vertex 0\n"),
        "t.ply: line 3: malformed header: unknown keyword 'elemnt'"
    );
}

#[test]
fn ascii_bad_values() {
    let with = |body: &str| error(format!("{ASCII_HEADER}{body}").as_bytes());
    assert_eq!(
        with("0 0 0\n1 0 0\n0 one 0\n3 0 1 2\n"),
        "t.ply: line 12: non-numeric token 'one' in vertex 2"
    );
    assert_eq!(
        with("0 0 0\n1 0 0\n0 1 nan\n3 0 1 2\n"),
        "t.ply: line 12: vertex 2 has a NaN or infinite z coordinate (NaN)"
    );
    assert_eq!(
        with("0 0 0\n1 0 inf\n0 1 0\n3 0 1 2\n"),
        "t.ply: line 11: vertex 1 has a NaN or infinite z coordinate (inf)"
    );
    assert_eq!(
        with("0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n"),
        "t.ply: line 13: face 0: vertex index 3 out of range (the file has 3 vertices)"
    );
    assert_eq!(
        with("0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n"),
        "t.ply: line 13: face 0: vertex index -1 out of range (the file has 3 vertices)"
    );
    assert_eq!(
        with("0 0 0\n1 0 0\n0 1 0\n2 0 1\n"),
        "t.ply: line 13: face 0: face with 2 vertices (at least 3 needed)"
    );
    assert_eq!(
        with("0 0 0\n1 0 0\n0 1 0\n3 0 1.5 2\n"),
        "t.ply: line 13: '1.5' in face 0 is not an integer"
    );
    assert_eq!(
        with("0 0 0\n1 0 0\n0 1 0\n3 0 1\n"),
        "t.ply: line 13: truncated data: the file ends in face 0 (of 1 face elements)"
    );
    assert_eq!(
        with("0 0 0\n1 0 0\n"),
        "t.ply: line 11: truncated data: the file ends in vertex 2 (of 3 vertex elements)"
    );
}

const BINARY_HEADER: &str = "ply\nformat binary_little_endian 1.0\nelement vertex 3\n\
        property float x\nproperty float y\nproperty float z\nelement face 1\n\
        property list uchar int vertex_indices\nend_header\n";

fn binary_triangle(points: [[f32; 3]; 3], face: &[i32]) -> Vec<u8> {
    binary(BINARY_HEADER, |b| {
        for p in points {
            for c in p {
                b.extend_from_slice(&c.to_le_bytes());
            }
        }
        b.push(face.len() as u8);
        for i in face {
            b.extend_from_slice(&i.to_le_bytes());
        }
    })
}

const TRIANGLE: [[f32; 3]; 3] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];

#[test]
fn binary_truncated_data_gives_the_byte_offset() {
    let header_len = BINARY_HEADER.len();
    let full = binary_triangle(TRIANGLE, &[0, 1, 2]);
    assert_eq!(full.len(), header_len + 36 + 1 + 12);
    // Cut inside the last index: the face's list is known not to fit from its count.
    let e = error(&full[..full.len() - 2]);
    assert_eq!(
        e,
        format!(
            "t.ply: byte {}: truncated data: the file ends in face 0 (of 1 face elements)",
            header_len + 36
        )
    );
    // Cut inside vertex 1.
    let e = error(&full[..header_len + 14]);
    assert_eq!(
        e,
        format!(
            "t.ply: byte {}: truncated data: the file ends in vertex 1 (of 3 vertex elements)",
            header_len + 12
        )
    );
    // A list count that runs past the end is caught before any allocation.
    let mut huge = binary_triangle(TRIANGLE, &[0, 1, 2]);
    huge[header_len + 36] = 255;
    assert!(error(&huge).contains("truncated data"), "{}", error(&huge));
}

#[test]
fn binary_bad_values_give_the_byte_offset() {
    let h = BINARY_HEADER.len();
    let mut nan = TRIANGLE;
    nan[2][1] = f32::NAN;
    assert_eq!(
        error(&binary_triangle(nan, &[0, 1, 2])),
        format!(
            "t.ply: byte {}: vertex 2 has a NaN or infinite y coordinate (NaN)",
            h + 24 + 4
        )
    );
    let mut inf = TRIANGLE;
    inf[0][0] = f32::NEG_INFINITY;
    assert!(
        error(&binary_triangle(inf, &[0, 1, 2]))
            .contains("vertex 0 has a NaN or infinite x coordinate (-inf)")
    );
    assert_eq!(
        error(&binary_triangle(TRIANGLE, &[0, 7, 2])),
        format!(
            "t.ply: byte {}: face 0: vertex index 7 out of range (the file has 3 vertices)",
            h + 36 + 1 + 4
        )
    );
    assert_eq!(
        error(&binary_triangle(TRIANGLE, &[0, 1])),
        format!(
            "t.ply: byte {}: face 0: face with 2 vertices (at least 3 needed)",
            h + 36
        )
    );
}

/// A binary file of `vertices` vertices and an element `extra` of 10 doubles cut short in
/// its fourth: the error names extra 3 and the byte where it ends.
fn skipped_element_truncated_after(vertices: usize) {
    let header = format!(
        "ply\nformat binary_little_endian 1.0\nelement vertex {vertices}\nproperty float x\n\
         property float y\nproperty float z\nelement extra 10\nproperty double w\n\
         end_header\n"
    );
    let data = 12 * vertices + 30;
    let bytes = binary(&header, |b| b.resize(b.len() + data, 0));
    let h = bytes.len() - data;
    assert_eq!(
        error(&bytes),
        format!(
            "t.ply: byte {}: truncated data: the file ends in extra 3 (of 10 extra elements)",
            h + 12 * vertices + 24
        )
    );
}

#[test]
fn binary_skipped_element_truncated() {
    skipped_element_truncated_after(0);
}

#[test]
fn binary_skipped_element_after_others_truncated() {
    skipped_element_truncated_after(1);
}

#[test]
fn huge_counts_do_not_allocate() {
    let e = error(
        b"ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\n\
              property float y\nproperty float z\nend_header\n\0\0",
    );
    assert!(e.contains("truncated data"), "{e}");
}

fn sample_mesh() -> TriMesh {
    read_mesh_bytes(
        b"v 0 0 0\nv 1 0 1e-300\nv 0 1 0.1\nv 1 1 -7\nv 5 5 5\nf 1 2 3\nf 2 4 3\n",
        Format::Obj,
        Path::new("s.obj"),
    )
    .unwrap()
}

#[test]
fn writes_and_reads_back_every_encoding_with_extra_properties() {
    let mesh = sample_mesh();
    let k: Vec<f64> = (0..5).map(|i| i as f64 / 3.0).collect();
    let q: Vec<f32> = vec![0.5, 1e-30, -2.0, 3.25, 1e30];
    for encoding in [
        PlyEncoding::Ascii,
        PlyEncoding::BinaryLittleEndian,
        PlyEncoding::BinaryBigEndian,
    ] {
        let mut bytes = Vec::new();
        PlyWriter::new(&mesh)
            .encoding(encoding)
            .comment("curvature\nof a test")
            .property(VertexProperty::new("k_max", &k))
            .unwrap()
            .property(VertexProperty::new("quality", q.clone()))
            .unwrap()
            .write_to(&mut bytes)
            .unwrap();
        let text = String::from_utf8_lossy(&bytes);
        assert!(text.contains("comment curvature of a test\n"));
        assert!(text.contains("property double k_max\nproperty float quality\n"));
        let back = parse_bytes(&bytes).unwrap();
        let positions: Vec<[f64; 3]> = mesh.positions().iter().map(|p| [p.x, p.y, p.z]).collect();
        assert_eq!(back.positions, positions, "{encoding:?}");
        assert_eq!(back.faces, mesh.faces().to_vec(), "{encoding:?}");
        if encoding == PlyEncoding::Ascii {
            assert!(
                text.contains("\n1 0 1e-300 0.3333333333333333 1e-30\n"),
                "{text}"
            );
        }
    }
}

#[test]
fn bad_properties_are_refused() {
    let mesh = sample_mesh();
    let short = vec![1.0f64; 4];
    let e = PlyWriter::new(&mesh)
        .property(VertexProperty::new("k", &short))
        .unwrap_err();
    assert_eq!(
        e.to_string(),
        "invalid input: PLY vertex property 'k' has 4 values for 5 vertices"
    );
    let ok = vec![1.0f64; 5];
    assert!(
        PlyWriter::new(&mesh)
            .property(VertexProperty::new("x", &ok))
            .is_err()
    );
    assert!(
        PlyWriter::new(&mesh)
            .property(VertexProperty::new("a b", &ok))
            .is_err()
    );
    assert!(
        PlyWriter::new(&mesh)
            .property(VertexProperty::new("k", &ok))
            .unwrap()
            .property(VertexProperty::new("k", &ok))
            .is_err()
    );
}

#[test]
fn ascii_float_values_beyond_single_precision_are_errors() {
    let with = |body: &str| error(format!("{ASCII_HEADER}{body}").as_bytes());
    // Read as `float`, 1e39 is infinite: as in binary, where it can only be inf.
    assert_eq!(
        with("0 0 0\n1e39 0 0\n0 1 0\n3 0 1 2\n"),
        "t.ply: line 11: '1e39' in vertex 1 is out of range for its type (float)"
    );
    assert_eq!(
        with("0 0 0\n1 0 0\n0 1 -3.5e38\n3 0 1 2\n"),
        "t.ply: line 12: '-3.5e38' in vertex 2 is out of range for its type (float)"
    );
    // Up to the largest float, and beyond it as `double`.
    let m =
        parse_bytes(format!("{ASCII_HEADER}0 0 0\n3.4028235e38 0 0\n0 1 0\n3 0 1 2\n").as_bytes())
            .unwrap();
    assert_eq!(m.positions[1][0], 3.4028235e38);
    let double = ASCII_HEADER.replace("float x", "double x");
    let m = parse_bytes(format!("{double}0 0 0\n1e39 0 0\n0 1 0\n3 0 1 2\n").as_bytes()).unwrap();
    assert_eq!(m.positions[1][0], 1e39);
}

#[test]
fn negative_and_huge_numbers_say_so() {
    assert_eq!(
        error(b"ply\nformat ascii 1.0\nelement vertex -3\n"),
        "t.ply: line 3: malformed header: element count -3 is not a non-negative integer (a \
         count cannot be negative)"
    );
    let digits = "9".repeat(300);
    assert_eq!(
        error(format!("ply\nformat ascii 1.0\nelement vertex {digits}\n").as_bytes()),
        format!(
            "t.ply: line 3: malformed header: element count '{}…' is too large",
            &digits[..40]
        )
    );
    assert_eq!(
        error(format!("{ASCII_HEADER}0 0 0\n1 0 0\n0 1 0\n3 0 1 {digits}\n").as_bytes()),
        format!(
            "t.ply: line 13: '{}…' in face 0 is out of range for its type (int)",
            &digits[..40]
        )
    );
}

#[test]
fn lone_carriage_returns_end_lines() {
    let text = format!("{ASCII_HEADER}0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n").replace('\n', "\r");
    let m = parse_bytes(text.as_bytes()).unwrap();
    assert_eq!(m.positions.len(), 3);
    assert_eq!(m.faces, vec![[0, 1, 2]]);
    let bad = format!("{ASCII_HEADER}0 0 0\n1 0 0\n0 one 0\n3 0 1 2\n").replace('\n', "\r");
    assert_eq!(
        error(bad.as_bytes()),
        "t.ply: line 12: non-numeric token 'one' in vertex 2"
    );
    // A binary body after a header of lone CRs, starting with an LF byte (10 as the first
    // byte of x): the LF is data, not the end of "end_header\r".
    let mut points = TRIANGLE;
    points[0][0] = f32::from_le_bytes([10, 0, 0, 0]);
    let lf = binary_triangle(points, &[0, 1, 2]);
    let mut cr = lf.clone();
    let header = BINARY_HEADER.len();
    for b in &mut cr[..header] {
        if *b == b'\n' {
            *b = b'\r';
        }
    }
    assert_eq!(cr[header], b'\n');
    assert_eq!(parse_bytes(&cr).unwrap(), parse_bytes(&lf).unwrap());
    assert_eq!(
        parse_bytes(&cr).unwrap().positions[0][0],
        f64::from(points[0][0])
    );
}
