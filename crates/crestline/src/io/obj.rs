//! Wavefront OBJ meshes.
//!
//! Reference: the "Object Files (.obj)" appendix of the Wavefront Advanced Visualizer manual
//! (B1), as collected at <https://paulbourke.net/dataformats/obj/>.
//!
//! Reading keeps `v` (the first three numbers; a fourth `w` or the three colour components
//! some exporters append are ignored) and `f` (polygons, triangulated by
//! [`super::triangulate`]). A face corner may be `v`, `v/vt`, `v//vn` or `v/vt/vn`; only `v`
//! is used. Indices are 1-based, or negative
//! for "relative to the last vertex read"; a positive index may refer to a vertex defined
//! later in the file. Every other record (`vt`, `vn`, `l`, `o`, `g`, `s`, `usemtl`,
//! `mtllib`, ...) and `#` comments are ignored.
//!
//! Limits: line continuation with a trailing `\` is not supported (the `\` is reported as a
//! non-numeric token); free-form geometry (`curv`, `surf`) is ignored.
//!
//! Writing emits `v x y z` with shortest round-trip numbers and `f a b c` per triangle.

use std::io::Write;

use super::text::{
    Lines, Source, Tokens, is_blank, is_integer_token, is_space, parse_i64, short_decimal_prefix,
    show, vertex,
};
use super::triangulate::Triangulator;
use super::{MeshData, write_xyz};
use crate::error::Result;
use crate::mesh::TriMesh;

/// Parses an OBJ file held in memory.
pub(super) fn parse(bytes: &[u8], source: Source<'_>) -> Result<MeshData> {
    if is_blank(bytes) {
        return Err(source.whole("empty file"));
    }
    // A rough guess (a vertex line is ~30 bytes, there are ~2 faces per vertex) saves the
    // vectors a few reallocations on large files.
    let mut positions = Vec::with_capacity(bytes.len() / 100);
    let mut faces = Vec::with_capacity(bytes.len() / 50);
    let mut corners: Vec<u32> = Vec::with_capacity(8);
    let mut polygons = Triangulator::default();
    // Faces whose largest index pointed past the vertices read so far, checked at the end
    // once all vertices are known: (line, largest 0-based index).
    let mut forward_references: Vec<(usize, u64)> = Vec::new();

    // A record continued on the next lines (`\` at the end of a line), joined.
    let mut joined: Vec<u8> = Vec::new();
    let mut lines = Lines::new(bytes);
    while let Some((line, text)) = lines.next() {
        let text = match continued(text) {
            None => text,
            Some(head) => {
                joined.clear();
                joined.extend_from_slice(head);
                // Each following line joins the record, which it ends unless it continues.
                for (_, next) in lines.by_ref() {
                    joined.push(b' ');
                    match continued(next) {
                        Some(part) => joined.extend_from_slice(part),
                        None => {
                            joined.extend_from_slice(next);
                            break;
                        }
                    }
                }
                joined.as_slice()
            }
        };
        let mut tokens = Tokens::new(text);
        let Some(keyword) = tokens.next() else {
            continue;
        };
        match keyword {
            b"v" => {
                let p = match fast_vertex(tokens.remainder()) {
                    Some(p) => p,
                    None => vertex(&mut tokens, positions.len() + 1)
                        .map_err(|m| source.at_line(line, m))?,
                };
                positions.push(p);
            }
            b"f" => {
                corners.clear();
                if fast_corners(tokens.remainder(), positions.len(), &mut corners).is_none() {
                    corners.clear();
                    for token in tokens {
                        let index = vertex_index(token, positions.len())
                            .map_err(|m| source.at_line(line, m))?;
                        corners.push(index);
                    }
                }
                let largest = corners.iter().copied().max().map_or(0, u64::from);
                if corners.len() < 3 {
                    return Err(source.at_line(
                        line,
                        format!("face with {} vertices (at least 3 needed)", corners.len()),
                    ));
                }
                if largest >= positions.len() as u64 {
                    forward_references.push((line, largest));
                }
                polygons.push(&mut faces, &corners, &positions);
            }
            _ => {}
        }
    }

    let count = positions.len() as u64;
    if let Some(&(line, index)) = forward_references.iter().find(|&&(_, i)| i >= count) {
        return Err(source.at_line(
            line,
            format!(
                "vertex index {} out of range (the file has {count} vertices)",
                index + 1
            ),
        ));
    }
    if positions.len() > u32::MAX as usize {
        return Err(source.whole(format!(
            "{} vertices is more than the 2^32-1 crestline indexes",
            positions.len()
        )));
    }
    polygons.finish(&mut faces, &positions);
    Ok(MeshData { positions, faces })
}

/// The line without its final `\` (and the spaces after it) when it continues on the next
/// line; `None` for a line that does not, or whose `\` is inside a comment.
fn continued(line: &[u8]) -> Option<&[u8]> {
    let end = line.iter().rposition(|&b| !is_space(b))?;
    (line[end] == b'\\' && !line.contains(&b'#')).then(|| &line[..end])
}

/// The three coordinates of a `v` record in one pass over `rest` (the text after `v`), for
/// the usual plain decimals; `None` sends anything else to the token path, which handles
/// every form and words the errors. Numbers after the third (w, colours) are ignored, as
/// on the token path.
#[inline]
fn fast_vertex(rest: &[u8]) -> Option<[f64; 3]> {
    let mut p = [0.0; 3];
    let mut at = 0;
    for c in &mut p {
        at += rest.get(at..)?.iter().position(|&b| !is_space(b))?;
        let (x, used) = short_decimal_prefix(&rest[at..])?;
        at += used;
        // The number must end its token, as on the token path.
        if rest.get(at).is_some_and(|&b| !is_space(b)) {
            return None;
        }
        *c = x;
    }
    Some(p)
}

/// The 0-based corners of an `f` record in one pass over `rest` (the text after `f`);
/// `None` (with `corners` partly filled) sends anything unusual or wrong to the token path.
#[inline]
fn fast_corners(rest: &[u8], vertices_so_far: usize, corners: &mut Vec<u32>) -> Option<()> {
    let mut i = 0;
    loop {
        while rest.get(i).is_some_and(|&b| is_space(b)) {
            i += 1;
        }
        match rest.get(i) {
            None | Some(b'#') => return Some(()),
            _ => {}
        }
        let negative = rest[i] == b'-';
        i += usize::from(negative);
        let start = i;
        let mut value: u64 = 0;
        while let Some(d) = rest
            .get(i)
            .map(|b| b.wrapping_sub(b'0'))
            .filter(|&d| d < 10)
        {
            value = value * 10 + u64::from(d);
            i += 1;
            if i - start > 10 {
                return None;
            }
        }
        if i == start || value == 0 {
            return None;
        }
        // Texture and normal indices after a slash are not used.
        if rest.get(i) == Some(&b'/') {
            while rest.get(i).is_some_and(|&b| !is_space(b)) {
                i += 1;
            }
        } else if rest.get(i).is_some_and(|&b| !is_space(b)) {
            return None;
        }
        let index = if negative {
            (vertices_so_far as u64).checked_sub(value)?
        } else {
            value - 1
        };
        corners.push(u32::try_from(index).ok()?);
    }
}

/// The 0-based vertex index of a face corner `v`, `v/vt`, `v//vn` or `v/vt/vn`, given the
/// number of vertices read so far (for negative, relative indices).
#[inline]
fn vertex_index(token: &[u8], vertices_so_far: usize) -> Result<u32, String> {
    // Corners are short: a plain scan beats a vectorised search here.
    let digits = match token.iter().position(|&b| b == b'/') {
        Some(slash) => &token[..slash],
        None => token,
    };
    let Some(i) = parse_i64(digits) else {
        if is_integer_token(digits) {
            return Err(format!("vertex index {} out of range", show(digits)));
        }
        return Err(format!(
            "non-numeric token '{}' where a vertex index was expected",
            show(token)
        ));
    };
    let index = match i {
        0 => return Err("vertex index 0 (OBJ indices start at 1)".to_string()),
        i if i > 0 => i - 1,
        i => {
            let absolute = vertices_so_far as i64 + i;
            if absolute < 0 {
                return Err(format!(
                    "relative vertex index {i} reaches before the first vertex \
                     (only {vertices_so_far} read so far)"
                ));
            }
            absolute
        }
    };
    u32::try_from(index).map_err(|_| format!("vertex index {i} out of range"))
}

/// Writes `mesh` as OBJ: every vertex, then the kept triangles.
pub(super) fn write<W: Write>(mut out: W, mesh: &TriMesh) -> std::io::Result<()> {
    writeln!(
        out,
        "# crestline mesh: {} vertices, {} triangles",
        mesh.num_vertices(),
        mesh.num_faces()
    )?;
    for p in mesh.positions() {
        out.write_all(b"v ")?;
        write_xyz(&mut out, p)?;
    }
    for [a, b, c] in mesh.faces() {
        writeln!(out, "f {} {} {}", a + 1, b + 1, c + 1)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::{Format, read_mesh_bytes};
    use std::path::Path;

    fn parse_str(text: &str) -> Result<MeshData> {
        parse(text.as_bytes(), Source::new(Path::new("t.obj")))
    }

    fn error(text: &str) -> String {
        parse_str(text).unwrap_err().to_string()
    }

    #[test]
    fn reads_polygons_with_every_corner_form() {
        let m = parse_str(
            "# a square and a triangle\n\
             mtllib m.mtl\no thing\ng group\ns 1\nusemtl red\n\
             v 0 0 0\nv 1 0 0 0.5 0.5 0.5\nv 1 1 0\r\nv 0 1 0\n\
             vt 0 0\nvn 0 0 1\n\
             f 1/1/1 2/1/1 3/1/1 4/1/1\n\
             f 1//1 2//1 3//1\n\
             f 1/1 3/1 4/1\n\
             l 1 2\n",
        )
        .unwrap();
        assert_eq!(m.positions.len(), 4);
        assert_eq!(m.positions[1], [1.0, 0.0, 0.0]);
        assert_eq!(m.faces, vec![[0, 1, 2], [0, 2, 3], [0, 1, 2], [0, 2, 3]]);
    }

    #[test]
    fn negative_indices_are_relative_to_the_last_vertex() {
        let m = parse_str("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\nv 5 5 5\nf -4 -3 -1\n").unwrap();
        assert_eq!(m.faces, vec![[0, 1, 2], [0, 1, 3]]);
    }

    #[test]
    fn forward_references_are_allowed() {
        let m = parse_str("f 1 2 3\nv 0 0 0\nv 1 0 0\nv 0 1 0\n").unwrap();
        assert_eq!(m.faces, vec![[0, 1, 2]]);
    }

    #[test]
    fn trailing_comments_are_ignored() {
        let m = parse_str("v 0 0 0 # origin\nv 1 0 0\nv 0 1 0\nf 1 2 3 # one\n").unwrap();
        assert_eq!(m.faces.len(), 1);
    }

    #[test]
    fn repeated_index_faces_are_counted_by_the_mesh() {
        let bytes = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 1 2\n";
        let m = read_mesh_bytes(bytes, Format::Obj, Path::new("t.obj")).unwrap();
        assert_eq!(m.num_faces(), 1);
        assert_eq!(m.degenerate_faces(), 1);
    }

    #[test]
    fn fast_paths_agree_with_the_token_path() {
        for rest in [
            " 1 2 3",
            "\t-1.5 +2 3e2 0.5 0.5",
            " 1 2",
            " 1 2 x",
            " 1 2 3#c",
            " 1e400 0 0",
            " nan 0 0",
            " 0.1 0.2 0.30000000000000004",
            " 1. .5 -0",
        ] {
            let fast = fast_vertex(rest.as_bytes());
            let slow = vertex(&mut Tokens::new(rest.as_bytes()), 1).ok();
            if let Some(p) = fast {
                assert_eq!(Some(p), slow, "{rest}");
            }
        }
        for rest in [
            " 1 2 3",
            " 1/1/1 2//2 3/3",
            " -1 -2 -3",
            " -4 1 2",
            " 0 1 2",
            " 1 2x 3",
            " 1 2 3 # c",
            " 99999999999 1 2",
            " 1/x 2 3",
            "",
            " 4294967296 1 2",
        ] {
            let mut fast = Vec::new();
            let fast_ok = fast_corners(rest.as_bytes(), 3, &mut fast).is_some();
            let slow: Result<Vec<u32>, String> = Tokens::new(rest.as_bytes())
                .map(|t| vertex_index(t, 3))
                .collect();
            if fast_ok {
                assert_eq!(Ok(fast), slow, "{rest}");
            }
        }
        assert_eq!(fast_vertex(b" 1 -2.5 3e2 7"), Some([1.0, -2.5, 300.0]));
        let mut c = Vec::new();
        assert!(fast_corners(b" 1/2/3 -1//4 2", 3, &mut c).is_some());
        assert_eq!(c, vec![0, 2, 1]);
    }

    #[test]
    fn blank_file_is_empty() {
        assert_eq!(error("\n  \n"), "t.obj: empty file");
    }

    #[test]
    fn non_numeric_coordinate_names_line_and_token() {
        assert_eq!(
            error("v 0 0 0\nv 1 zero 0\n"),
            "t.obj: line 2: non-numeric token 'zero' where the y coordinate of vertex 2 \
             was expected"
        );
    }

    #[test]
    fn non_numeric_index_names_line_and_token() {
        assert_eq!(
            error("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x/1\n"),
            "t.obj: line 4: non-numeric token 'x/1' where a vertex index was expected"
        );
    }

    #[test]
    fn missing_coordinate() {
        assert_eq!(
            error("v 0 0\n"),
            "t.obj: line 1: missing z coordinate of vertex 1"
        );
    }

    #[test]
    fn nan_and_infinite_coordinates_are_rejected() {
        assert_eq!(
            error("v 0 0 0\n\nv nan 0 0\n"),
            "t.obj: line 3: x coordinate of vertex 2 is NaN or infinite ('nan')"
        );
        assert_eq!(
            error("v 0 0 -inf\n"),
            "t.obj: line 1: z coordinate of vertex 1 is NaN or infinite ('-inf')"
        );
        assert_eq!(
            error("v 0 1e400 0\n"),
            "t.obj: line 1: y coordinate of vertex 1 is NaN or infinite ('1e400')"
        );
    }

    #[test]
    fn index_out_of_range() {
        assert_eq!(
            error("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n"),
            "t.obj: line 4: vertex index 4 out of range (the file has 3 vertices)"
        );
        assert_eq!(
            error("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n"),
            "t.obj: line 4: vertex index 0 (OBJ indices start at 1)"
        );
    }

    #[test]
    fn negative_index_before_the_first_vertex() {
        assert_eq!(
            error("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n"),
            "t.obj: line 4: relative vertex index -4 reaches before the first vertex \
             (only 3 read so far)"
        );
    }

    #[test]
    fn face_with_fewer_than_three_vertices() {
        assert_eq!(
            error("v 0 0 0\nv 1 0 0\nf 1 2\n"),
            "t.obj: line 3: face with 2 vertices (at least 3 needed)"
        );
        assert_eq!(
            error("v 0 0 0\nf\n"),
            "t.obj: line 2: face with 0 vertices (at least 3 needed)"
        );
    }

    #[test]
    fn a_backslash_continues_a_record_on_the_next_line() {
        let text = "v 0 0 0\nv 1 0 \\\n 0\nv 0 1 0\nv 1 1 0 \\ \r\n\nf 1 2 \\\n3 \\\n\n# C:\\models\\\nf 2 4 3\n";
        let data = parse_str(text).unwrap();
        assert_eq!(data.positions.len(), 4);
        assert_eq!(data.positions[1], [1.0, 0.0, 0.0]);
        assert_eq!(data.positions[3], [1.0, 1.0, 0.0]);
        // `f 1 2 3` over three lines (the last one empty); the comment's backslash does not
        // swallow the face after it.
        assert_eq!(data.faces, vec![[0, 1, 2], [1, 3, 2]]);
    }

    #[test]
    fn lone_carriage_returns_end_lines() {
        // Classic Mac OS line ends: the whole file was one line, read as one vertex.
        let m = parse_str("v 0 0 0\rv 1 0 0\r\rv 0 1 0\rf 1 2 3\r").unwrap();
        assert_eq!(m.positions.len(), 3);
        assert_eq!(m.faces, vec![[0, 1, 2]]);
        // Errors count those lines, mixed with the other line ends.
        assert_eq!(
            error("v 0 0 0\r\nv 1 0 0\rv 0 1 0\nf 1 2 x\r"),
            "t.obj: line 4: non-numeric token 'x' where a vertex index was expected"
        );
    }

    #[test]
    fn huge_indices_are_out_of_range_not_words() {
        let digits = "9".repeat(300);
        assert_eq!(
            error(&format!("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 {digits}/1\n")),
            format!(
                "t.obj: line 4: vertex index {}… out of range",
                &digits[..40]
            )
        );
    }

    #[test]
    fn writes_what_it_reads() {
        let m = read_mesh_bytes(
            b"v 0.1 0 0\nv 1 0 1e-300\nv 0 1 0\nv 9 9 9\nf 1 2 3\n",
            Format::Obj,
            Path::new("t.obj"),
        )
        .unwrap();
        let mut out = Vec::new();
        write(&mut out, &m).unwrap();
        let text = String::from_utf8(out.clone()).unwrap();
        assert!(text.contains("v 0.1 0 0\nv 1 0 1e-300\n"), "{text}");
        assert!(text.ends_with("f 1 2 3\n"), "{text}");
        let back = parse(&out, Source::new(Path::new("t.obj"))).unwrap();
        assert_eq!(back.positions.len(), 4);
        assert_eq!(back.faces, vec![[0, 1, 2]]);
    }
}
