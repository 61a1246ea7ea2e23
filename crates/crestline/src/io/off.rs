//! Object File Format (OFF) meshes.
//!
//! Reference: the Geomview manual, "OFF Files",
//! <http://www.geomview.org/docs/html/OFF.html>.
//!
//! Reading: an optional header keyword (`OFF`, or with the prefixes `ST`, `C`, `N` in any
//! combination: `COFF`, `NOFF`, `CNOFF`, `STOFF`, ...), then the counts `vertices faces
//! [edges]` (possibly on the header line itself), then one vertex per line (the first three
//! numbers; normals, colours and texture coordinates that follow are skipped), then one face
//! per line: `n i0 ... i(n-1)` with 0-based indices, optionally followed by a colour.
//! Polygons are fan-triangulated. `#` starts a comment; blank lines are skipped.
//!
//! Limits: the body must put one vertex or face per line (as every writer does); 4D (`4OFF`),
//! n-dimensional (`nOFF`) and binary OFF are refused with an error.
//!
//! Writing emits `OFF`, the counts, `x y z` per vertex (shortest round-trip numbers) and
//! `3 a b c` per triangle.

use std::io::Write;

use super::text::{Lines, Source, Tokens, parse_i64, show, vertex};
use super::{MeshData, push_fan, write_f64};
use crate::error::Result;
use crate::mesh::TriMesh;

/// Parses an OFF file held in memory.
pub(super) fn parse(bytes: &[u8], source: Source<'_>) -> Result<MeshData> {
    // Only lines with content matter: comments and blank lines are dropped here.
    let mut lines = Lines::new(bytes)
        .map(|(n, text)| (n, Tokens::new(text)))
        .filter_map(|(n, mut tokens)| {
            let first = tokens.next()?;
            Some((n, first, tokens))
        });
    // Counted only for an error message (a whole pass over the file).
    let last_line = || Lines::new(bytes).count().max(1);

    let Some((line, first, mut rest)) = lines.next() else {
        return Err(source.whole("empty file"));
    };
    // The counts: after the header keyword on its line, on the next line, or (no header)
    // on the first line.
    let mut counts: Vec<(usize, &[u8])> = Vec::with_capacity(3);
    if first.ends_with(b"OFF") {
        let prefix = &first[..first.len() - 3];
        check_header_prefix(prefix).map_err(|m| source.at_line(line, m))?;
        counts.extend(rest.map(|t| (line, t)));
        if counts.is_empty() {
            let Some((line, first, rest)) = lines.next() else {
                return Err(source.at_line(last_line(), "missing counts line after OFF header"));
            };
            counts.push((line, first));
            counts.extend(rest.map(|t| (line, t)));
        }
    } else if parse_i64(first).is_some() {
        counts.push((line, first));
        counts.extend(rest.by_ref().map(|t| (line, t)));
    } else {
        return Err(source.at_line(
            line,
            format!(
                "malformed header: '{}' is neither an OFF keyword nor a vertex count",
                show(first)
            ),
        ));
    }
    let count = |k: usize, what: &str| -> Result<usize> {
        let Some(&(line, token)) = counts.get(k) else {
            let line = counts.first().map_or(line, |c| c.0);
            return Err(source.at_line(line, format!("malformed header: missing {what} count")));
        };
        parse_i64(token)
            .and_then(|c| usize::try_from(c).ok())
            .ok_or_else(|| {
                source.at_line(
                    line,
                    format!(
                        "malformed header: {what} count '{}' is not a non-negative integer",
                        show(token)
                    ),
                )
            })
    };
    let vertex_count = count(0, "vertex")?;
    let face_count = count(1, "face")?;
    if vertex_count > u32::MAX as usize {
        return Err(source.at_line(
            counts[0].0,
            format!("{vertex_count} vertices is more than the 2^32-1 crestline indexes"),
        ));
    }

    // Every vertex line holds at least 6 bytes ("0 0 0\n"), which bounds the allocation.
    let mut positions = Vec::with_capacity(vertex_count.min(bytes.len() / 6));
    for v in 0..vertex_count {
        let Some((line, first, rest)) = lines.next() else {
            return Err(source.at_line(
                last_line(),
                format!("the file ends after {v} of {vertex_count} vertices"),
            ));
        };
        let p = vertex(&mut std::iter::once(first).chain(rest), v)
            .map_err(|m| source.at_line(line, m))?;
        positions.push(p);
    }

    let mut faces = Vec::with_capacity(face_count.min(bytes.len() / 8));
    let mut corners: Vec<u32> = Vec::with_capacity(8);
    for f in 0..face_count {
        let Some((line, first, mut rest)) = lines.next() else {
            return Err(source.at_line(
                last_line(),
                format!("the file ends after {f} of {face_count} faces"),
            ));
        };
        let at = |m: String| source.at_line(line, m);
        let n = parse_i64(first).ok_or_else(|| {
            at(format!(
                "non-numeric token '{}' where the vertex count of face {f} was expected",
                show(first)
            ))
        })?;
        if n < 3 {
            return Err(at(format!("face {f} has {n} vertices (at least 3 needed)")));
        }
        corners.clear();
        for k in 0..n {
            let Some(token) = rest.next() else {
                return Err(at(format!("face {f} lists {k} of its {n} vertex indices")));
            };
            let i = parse_i64(token).ok_or_else(|| {
                at(format!(
                    "non-numeric token '{}' where a vertex index of face {f} was expected",
                    show(token)
                ))
            })?;
            if i < 0 || i as u64 >= vertex_count as u64 {
                return Err(at(format!(
                    "face {f}: vertex index {i} out of range (the file has {vertex_count} \
                     vertices)"
                )));
            }
            corners.push(i as u32);
        }
        push_fan(&mut faces, &corners);
    }
    Ok(MeshData { positions, faces })
}

/// Accepts the optional prefixes of the header keyword: `ST` (texture coordinates), `C`
/// (colour), `N` (normal), in that order; refuses `4` and `n` (other dimensions).
fn check_header_prefix(prefix: &[u8]) -> Result<(), String> {
    let mut rest = prefix;
    for flag in [&b"ST"[..], b"C", b"N"] {
        if let Some(r) = rest.strip_prefix(flag) {
            rest = r;
        }
    }
    match rest {
        b"" => Ok(()),
        b"4" | b"n" | b"4n" => Err(format!("{}OFF (not 3D) is not supported", show(prefix))),
        _ => Err(format!(
            "malformed header: unknown header keyword '{}OFF'",
            show(prefix)
        )),
    }
}

/// Writes `mesh` as OFF: every vertex, then the kept triangles.
pub(super) fn write<W: Write>(mut out: W, mesh: &TriMesh) -> std::io::Result<()> {
    writeln!(out, "OFF\n{} {} 0", mesh.num_vertices(), mesh.num_faces())?;
    for p in mesh.positions() {
        write_f64(&mut out, p.x)?;
        out.write_all(b" ")?;
        write_f64(&mut out, p.y)?;
        out.write_all(b" ")?;
        write_f64(&mut out, p.z)?;
        out.write_all(b"\n")?;
    }
    for [a, b, c] in mesh.faces() {
        writeln!(out, "3 {a} {b} {c}")?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    fn parse_str(text: &str) -> Result<MeshData> {
        parse(text.as_bytes(), Source::new(Path::new("t.off")))
    }

    fn error(text: &str) -> String {
        parse_str(text).unwrap_err().to_string()
    }

    #[test]
    fn reads_polygons_comments_and_colours() {
        let m = parse_str(
            "OFF # a square\n# counts next\n\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n\
             4 0 1 2 3 255 0 0\n3 0 2 3\n",
        )
        .unwrap();
        assert_eq!(m.positions.len(), 4);
        assert_eq!(m.faces, vec![[0, 1, 2], [0, 2, 3], [0, 2, 3]]);
    }

    #[test]
    fn counts_on_the_header_line_and_extra_vertex_values() {
        let m = parse_str(
            "CNOFF 3 1 3\n0 0 0 0 0 1 1 0 0 1\n1 0 0 0 0 1 0 1 0 1\n0 1 0 0 0 1 0 0 1 1\n\
             3 0 1 2\n",
        )
        .unwrap();
        assert_eq!(m.positions[1], [1.0, 0.0, 0.0]);
        assert_eq!(m.faces, vec![[0, 1, 2]]);
        let m = parse_str("NOFF\n3 1\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n3 0 1 2\n").unwrap();
        assert_eq!(m.faces, vec![[0, 1, 2]]);
        let m = parse_str("COFF\n3 1 0\n0 0 0 1 1 1 1\n1 0 0 1 1 1 1\n0 1 0 1 1 1 1\n3 2 1 0\n")
            .unwrap();
        assert_eq!(m.faces, vec![[2, 1, 0]]);
    }

    #[test]
    fn header_keyword_is_optional() {
        let m = parse_str("3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n").unwrap();
        assert_eq!(m.faces, vec![[0, 1, 2]]);
    }

    #[test]
    fn comment_only_file_is_empty() {
        assert_eq!(error("# nothing\n\n"), "t.off: file: empty file");
    }

    #[test]
    fn malformed_headers() {
        assert_eq!(
            error("OFX\n3 1 0\n"),
            "t.off: line 1: malformed header: 'OFX' is neither an OFF keyword nor a vertex count"
        );
        assert_eq!(
            error("OFF\n3 x 0\n"),
            "t.off: line 2: malformed header: face count 'x' is not a non-negative integer"
        );
        assert_eq!(
            error("OFF\n3\n"),
            "t.off: line 2: malformed header: missing face count"
        );
        assert_eq!(
            error("4OFF\n3 1 0\n"),
            "t.off: line 1: 4OFF (not 3D) is not supported"
        );
        assert_eq!(
            error("XOFF\n3 1 0\n"),
            "t.off: line 1: malformed header: unknown header keyword 'XOFF'"
        );
        assert_eq!(
            error("OFF\n"),
            "t.off: line 1: missing counts line after OFF header"
        );
    }

    #[test]
    fn bad_vertices() {
        assert_eq!(
            error("OFF\n3 1 0\n0 0 0\n1 O 0\n0 1 0\n3 0 1 2\n"),
            "t.off: line 4: non-numeric token 'O' where the y coordinate of vertex 1 was \
             expected"
        );
        assert_eq!(
            error("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 NaN\n3 0 1 2\n"),
            "t.off: line 5: z coordinate of vertex 2 is NaN or infinite ('NaN')"
        );
        assert_eq!(
            error("OFF\n3 1 0\n0 0 0\n1 0\n0 1 0\n3 0 1 2\n"),
            "t.off: line 4: missing z coordinate of vertex 1"
        );
    }

    #[test]
    fn bad_faces() {
        let head = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n";
        let with = |face: &str| error(&format!("{head}{face}"));
        assert_eq!(
            with("3 0 1 3\n"),
            "t.off: line 6: face 0: vertex index 3 out of range (the file has 3 vertices)"
        );
        assert_eq!(
            with("3 0 -1 2\n"),
            "t.off: line 6: face 0: vertex index -1 out of range (the file has 3 vertices)"
        );
        assert_eq!(
            with("2 0 1\n"),
            "t.off: line 6: face 0 has 2 vertices (at least 3 needed)"
        );
        assert_eq!(
            with("3 0 1\n"),
            "t.off: line 6: face 0 lists 2 of its 3 vertex indices"
        );
        assert_eq!(
            with("3 0 one 2\n"),
            "t.off: line 6: non-numeric token 'one' where a vertex index of face 0 was expected"
        );
    }

    #[test]
    fn too_few_records() {
        assert_eq!(
            error("OFF\n3 1 0\n0 0 0\n1 0 0\n"),
            "t.off: line 4: the file ends after 2 of 3 vertices"
        );
        assert_eq!(
            error("OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2"),
            "t.off: line 6: the file ends after 1 of 2 faces"
        );
    }
}
