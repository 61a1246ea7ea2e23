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
//! Polygons are triangulated (see [`super::triangulate`]): fanned in the pieces, and those
//! whose fan folds cut again once all vertices are read. `#` starts a comment; blank lines
//! are skipped.
//!
//! The body is cut at line breaks into pieces parsed on all cores. A first pass counts the
//! lines of each piece (a fast search for line breaks), which numbers the records when every
//! line holds one; the second parses the pieces, vertices straight into their place. Should a
//! piece meet a blank or comment line, the records are counted token by token and the pieces
//! parsed again. Lines of three finite numbers and triangle lines `3 a b c` are read in one
//! scan each; anything else (polygons, signs, comments, errors) goes through the tokens.
//! Errors still name the line, counted only when one occurs.
//!
//! Lines may end in LF, CR LF or a lone CR (see [`super::text`]). Pieces are cut after LFs
//! and pass 1 counts LFs only: a piece that turns out to hold more lines than that (lone
//! CRs) is, like one with blank lines, counted again token by token, and a file of lone CRs
//! only is one piece, parsed on one core.
//!
//! Limits: the body must put one vertex or face per line (as every writer does); 4D (`4OFF`),
//! n-dimensional (`nOFF`) and binary OFF (`OFF BINARY`) are refused with an error that says
//! so.
//!
//! Writing emits `OFF`, the counts, `x y z` per vertex (shortest round-trip numbers) and
//! `3 a b c` per triangle.

use std::io::Write;

use rayon::prelude::*;

use super::text::{
    Lines, Source, Tokens, is_integer_token, is_space, line_at, parse_count, parse_i64, show,
    vertex, vertex_line,
};
use super::triangulate::Triangulator;
use super::{MeshData, write_xyz};
use crate::error::Result;
use crate::mesh::TriMesh;

/// Parses an OFF file held in memory.
pub(super) fn parse(bytes: &[u8], source: Source<'_>) -> Result<MeshData> {
    parse_with_chunks(bytes, source, default_chunk_bytes(bytes.len()))
}

/// Size of the pieces the body is cut into for parsing on all cores: a few per thread (so
/// uneven pieces balance out), at least 64 KiB (so small files stay in one piece).
fn default_chunk_bytes(len: usize) -> usize {
    (len / (4 * rayon::current_num_threads())).max(1 << 16)
}

/// [`parse`] with the body cut into pieces of about `chunk_bytes` bytes.
fn parse_with_chunks(bytes: &[u8], source: Source<'_>, chunk_bytes: usize) -> Result<MeshData> {
    // Only lines with content matter: comments and blank lines are dropped here.
    let mut raw = Lines::new(bytes);
    let (vertex_count, face_count) = read_counts(bytes, &mut raw, source)?;
    // Counted only for an error message (a whole pass over the file).
    let last_line = || Lines::new(bytes).count().max(1);

    let body = Body {
        bytes,
        vertex_count,
        face_count,
    };
    let pieces = body.pieces(raw.offset(), chunk_bytes);
    // Pass 1 needs the number of the first record of every piece. Counting the lines (one
    // fast search for line breaks) gives it when every line holds a record, as in the files
    // writers produce; pass 2 checks that as it goes, and only when a piece meets a blank or
    // comment line are the records counted token by token and the pieces parsed again.
    let lines: Vec<usize> = pieces
        .par_iter()
        .map(|r| {
            let piece = &bytes[r.clone()];
            memchr::memchr_iter(b'\n', piece).count() + usize::from(piece.last() != Some(&b'\n'))
        })
        .collect();
    let parsed = match body.parse_pieces(&pieces, &lines, false) {
        Some(parsed) => parsed,
        None => {
            let records: Vec<usize> = pieces
                .par_iter()
                .map(|r| {
                    Lines::new(&bytes[r.clone()])
                        .filter(|(_, text)| Tokens::new(text).next().is_some())
                        .count()
                })
                .collect();
            body.parse_exact(&pieces, &records)
        }
    };
    let (positions, faces, total) = match parsed {
        Ok(parsed) => parsed,
        Err((offset, message)) => return Err(source.at_line(line_at(bytes, offset), message)),
    };
    if total < vertex_count {
        return Err(source.at_line(
            last_line(),
            format!("the file ends after {total} of {vertex_count} vertices"),
        ));
    }
    if total - vertex_count < face_count {
        return Err(source.at_line(
            last_line(),
            format!(
                "the file ends after {} of {face_count} faces",
                total - vertex_count
            ),
        ));
    }
    Ok(MeshData { positions, faces })
}

/// The vertex and face counts of the header, read from `raw` (which is left at the body).
fn read_counts(bytes: &[u8], raw: &mut Lines<'_>, source: Source<'_>) -> Result<(usize, usize)> {
    // Counted only for an error message (a whole pass over the file).
    let last_line = || Lines::new(bytes).count().max(1);

    let Some((line, first, mut rest)) = next_content(raw) else {
        return Err(source.whole("empty file"));
    };
    // The counts: after the header keyword on its line, on the next line, or (no header)
    // on the first line.
    let mut counts: Vec<(usize, &[u8])> = Vec::with_capacity(3);
    if first.ends_with(b"OFF") {
        let prefix = &first[..first.len() - 3];
        check_header_prefix(prefix).map_err(|m| source.at_line(line, m))?;
        counts.extend(rest.map(|t| (line, t)));
        // Geomview's binary OFF: the counts and records that follow are binary.
        if counts
            .first()
            .is_some_and(|&(_, t)| t.eq_ignore_ascii_case(b"BINARY"))
        {
            return Err(source.at_line(
                line,
                format!(
                    "binary OFF ('{} BINARY') is not supported: convert the file to ascii OFF, \
                     PLY or OBJ",
                    show(first)
                ),
            ));
        }
        if counts.is_empty() {
            let Some((line, first, rest)) = next_content(raw) else {
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
        parse_count(token, &format!("{what} count"))
            .map_err(|m| source.at_line(line, format!("malformed header: {m}")))
    };
    let vertex_count = count(0, "vertex")?;
    let face_count = count(1, "face")?;
    if vertex_count > u32::MAX as usize {
        return Err(source.at_line(
            counts[0].0,
            format!("{vertex_count} vertices is more than the 2^32-1 crestline indexes"),
        ));
    }
    Ok((vertex_count, face_count))
}

/// The next line with content: its number, first token and the rest of its tokens.
fn next_content<'a>(raw: &mut Lines<'a>) -> Option<(usize, &'a [u8], Tokens<'a>)> {
    raw.by_ref()
        .map(|(n, text)| (n, Tokens::new(text)))
        .find_map(|(n, mut tokens)| {
            let first = tokens.next()?;
            Some((n, first, tokens))
        })
}

/// The records after the header: `vertex_count` vertex lines, then `face_count` face lines;
/// anything after them is ignored.
struct Body<'a> {
    bytes: &'a [u8],
    vertex_count: usize,
    face_count: usize,
}

/// What [`Body::parse_piece`] found in one piece of the body.
#[derive(Default)]
struct Piece {
    /// Its triangles (its vertices went straight to their place in the positions).
    faces: Vec<[u32; 3]>,
    /// Its polygons, fanned until the positions they need are all read.
    polygons: Triangulator,
    /// Records read.
    records: usize,
    /// Lines without content met before the last record read (or lines beyond the count
    /// the piece was given).
    skipped: usize,
    /// The byte offset of the line that failed and what is wrong with it.
    error: Option<(usize, String)>,
}

/// The positions, the triangles and the number of records read, or the byte offset of the
/// first line (in file order) that failed and what is wrong with it.
type Parsed = std::result::Result<(Vec<[f64; 3]>, Vec<[u32; 3]>, usize), (usize, String)>;

impl Body<'_> {
    /// Cuts `bytes[start..]` into ranges of about `chunk_bytes` bytes that end at line ends.
    fn pieces(&self, start: usize, chunk_bytes: usize) -> Vec<std::ops::Range<usize>> {
        let len = self.bytes.len();
        let mut pieces = Vec::new();
        let mut begin = start;
        while begin < len {
            let cut = (begin + chunk_bytes.max(1)).min(len);
            let end = memchr::memchr(b'\n', &self.bytes[cut.saturating_sub(1)..])
                .map_or(len, |n| cut - 1 + n + 1)
                .max(begin + 1);
            pieces.push(begin..end);
            begin = end;
        }
        pieces
    }

    /// [`Body::parse_pieces`] with the exact number of records of every piece.
    fn parse_exact(&self, pieces: &[std::ops::Range<usize>], records: &[usize]) -> Parsed {
        // With exact counts nothing is rejected; an empty result would only come from a bug.
        self.parse_pieces(pieces, records, true)
            .unwrap_or_else(|| Ok((Vec::new(), Vec::new(), 0)))
    }

    /// Parses the pieces on all cores, taking piece `i` to hold `records[i]` records. When
    /// these counts are the pieces' numbers of lines (`exact` false), `None` says that a piece
    /// met a line without content, so that the counts were wrong.
    fn parse_pieces(
        &self,
        pieces: &[std::ops::Range<usize>],
        records: &[usize],
        exact: bool,
    ) -> Option<Parsed> {
        let mut first_record = Vec::with_capacity(pieces.len());
        let mut total = 0usize;
        for n in records {
            first_record.push(total);
            total += n;
        }
        // Every piece parses its vertices straight into their slots: no copies, and no
        // second array of positions.
        let len = self.vertex_count.min(total);
        let mut positions = vec![[0.0f64; 3]; len];
        let mut slots = Vec::with_capacity(pieces.len());
        let mut rest = &mut positions[..];
        for (&first, &n) in first_record.iter().zip(records) {
            let (mine, tail) = rest.split_at_mut((first + n).min(len) - first.min(len));
            slots.push(mine);
            rest = tail;
        }
        let mut parsed: Vec<Piece> = pieces
            .par_iter()
            .zip(first_record.par_iter().zip(records.par_iter()))
            .zip(slots.into_par_iter())
            .map(|((r, (&first, &n)), slots)| self.parse_piece(r.clone(), first, n, slots))
            .collect();
        let mut read = 0;
        let mut triangles = 0;
        for piece in &parsed {
            if !exact && piece.skipped > 0 {
                return None;
            }
            // The first failure in file order is the one reported.
            if let Some(error) = &piece.error {
                return Some(Err(error.clone()));
            }
            read += piece.records;
            triangles += piece.faces.len();
        }
        parsed
            .par_iter_mut()
            .for_each(|piece| piece.polygons.finish(&mut piece.faces, &positions));
        let mut faces = Vec::with_capacity(triangles);
        for piece in parsed {
            faces.extend_from_slice(&piece.faces);
        }
        Some(Ok((positions, faces, read)))
    }

    /// Parses the records in `bytes[range]`, which holds records `first..first + count`
    /// (fewer if it has lines without content): vertices into `slots` (those of vertices
    /// `first..`), triangles into the result.
    fn parse_piece(
        &self,
        range: std::ops::Range<usize>,
        first: usize,
        count: usize,
        slots: &mut [[f64; 3]],
    ) -> Piece {
        let records = self.vertex_count + self.face_count;
        let mut piece = Piece::default();
        if first >= records {
            return piece;
        }
        let face_records = (first + count)
            .min(records)
            .saturating_sub(first.max(self.vertex_count));
        piece.faces.reserve(face_records);
        let mut corners: Vec<u32> = Vec::with_capacity(8);
        let mut record = first;
        let mut lines = Lines::new(&self.bytes[range.clone()]);
        while record < records {
            let line_start = range.start + lines.offset();
            let Some((_, text)) = lines.next() else {
                break;
            };
            if record - first >= count {
                // Exact counts leave only lines without content here. Counts of LFs miss the
                // lines that end in a lone CR: the piece holds more lines than counted, and
                // must be counted again.
                piece.skipped += 1;
                break;
            }
            // Plain vertices and triangles first, without splitting the line into tokens.
            if record < self.vertex_count {
                if let Some(p) = vertex_line(text) {
                    slots[record - first] = p;
                    record += 1;
                    continue;
                }
            } else if let Some(t) = triangle_line(text, self.vertex_count) {
                piece.faces.push(t);
                record += 1;
                continue;
            }
            let mut tokens = Tokens::new(text);
            let Some(head) = tokens.next() else {
                piece.skipped += 1;
                continue;
            };
            let result = if record < self.vertex_count {
                // In range: a piece holds at most `count` records, and `slots` has room for
                // the vertices among them.
                vertex(&mut std::iter::once(head).chain(tokens), record)
                    .map(|p| slots[record - first] = p)
            } else {
                let f = record - self.vertex_count;
                face(head, tokens, f, self.vertex_count, &mut corners)
                    .map(|()| piece.polygons.push_later(&mut piece.faces, &corners))
            };
            if let Err(message) = result {
                piece.error = Some((line_start, message));
                return piece;
            }
            record += 1;
        }
        piece.records = record - first;
        piece
    }
}

/// The corners of a face line `3 a b c` with indices in range, read without splitting the
/// line into tokens; `None` sends the line to [`face`], which reads what this cannot
/// (polygons, signs) and words the errors.
#[inline]
fn triangle_line(line: &[u8], vertex_count: usize) -> Option<[u32; 3]> {
    let mut rest = line;
    if unsigned_prefix(&mut rest)? != 3 {
        return None;
    }
    let mut t = [0u32; 3];
    for corner in &mut t {
        let i = unsigned_prefix(&mut rest)?;
        if i >= vertex_count as u64 {
            return None;
        }
        *corner = i as u32;
    }
    Some(t)
}

/// An unsigned integer of at most 18 digits after leading whitespace, ending at whitespace or
/// the end of the line; `rest` moves past it.
#[inline]
fn unsigned_prefix(rest: &mut &[u8]) -> Option<u64> {
    let start = rest.iter().position(|&b| !is_space(b))?;
    let text = &rest[start..];
    let digits = text.iter().take_while(|b| b.is_ascii_digit()).count();
    if digits == 0 || digits > 18 || text.get(digits).is_some_and(|&b| !is_space(b)) {
        return None;
    }
    let value = text[..digits]
        .iter()
        .fold(0u64, |v, &d| v * 10 + u64::from(d - b'0'));
    *rest = &text[digits..];
    Some(value)
}

/// Reads face `f` (`n i0 ... i(n-1)`, `n` already split off as `head`) into `corners`.
fn face<'a>(
    head: &[u8],
    mut rest: impl Iterator<Item = &'a [u8]>,
    f: usize,
    vertex_count: usize,
    corners: &mut Vec<u32>,
) -> std::result::Result<(), String> {
    let n = parse_i64(head).ok_or_else(|| {
        if is_integer_token(head) {
            format!("face {f}: vertex count '{}' is out of range", show(head))
        } else {
            format!(
                "non-numeric token '{}' where the vertex count of face {f} was expected",
                show(head)
            )
        }
    })?;
    if n < 0 {
        return Err(format!(
            "face {f}: vertex count {n} is not a non-negative integer (a count cannot be \
             negative)"
        ));
    }
    if n < 3 {
        return Err(format!("face {f} has {n} vertices (at least 3 needed)"));
    }
    corners.clear();
    for k in 0..n {
        let Some(token) = rest.next() else {
            return Err(format!("face {f} lists {k} of its {n} vertex indices"));
        };
        let i = parse_i64(token).ok_or_else(|| {
            if is_integer_token(token) {
                format!(
                    "face {f}: vertex index {} out of range (the file has {vertex_count} \
                     vertices)",
                    show(token)
                )
            } else {
                format!(
                    "non-numeric token '{}' where a vertex index of face {f} was expected",
                    show(token)
                )
            }
        })?;
        if i < 0 || i as u64 >= vertex_count as u64 {
            return Err(format!(
                "face {f}: vertex index {i} out of range (the file has {vertex_count} vertices)"
            ));
        }
        corners.push(i as u32);
    }
    Ok(())
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
        write_xyz(&mut out, p)?;
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
        assert_eq!(error("# nothing\n\n"), "t.off: empty file");
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

    /// A file with a comment, a blank line and a quad somewhere in the middle of its body.
    fn grid_text(n: usize) -> String {
        let mut text = format!("OFF\n{} {} 0\n", n * n, 2 * (n - 1) * (n - 1) - 1);
        for i in 0..n * n {
            if i == n {
                text.push_str("# a comment\n\n");
            }
            text.push_str(&format!("{} {}.5 {}e-3\n", i % n, i / n, i));
        }
        for r in 0..n - 1 {
            for c in 0..n - 1 {
                let v = (r * n + c) as u32;
                let w = v + n as u32;
                if r == 1 && c == 1 {
                    text.push_str(&format!("4 {v} {} {} {w} 255 0 0\n\n", v + 1, w + 1));
                } else {
                    text.push_str(&format!("3 {v} {} {w}\n3 {} {} {w}\n", v + 1, v + 1, w + 1));
                }
            }
        }
        text.push_str("trailing junk after the last face is ignored\n");
        text
    }

    #[test]
    fn pieces_of_any_size_parse_alike() {
        let text = grid_text(12);
        let source = Source::new(Path::new("t.off"));
        let whole = parse_with_chunks(text.as_bytes(), source, usize::MAX / 2).unwrap();
        assert_eq!(whole.positions.len(), 144);
        assert_eq!(whole.faces.len(), 2 * 11 * 11);
        assert_eq!(whole.positions[13], [1.0, 1.5, 13e-3]);
        for chunk in [1, 2, 7, 30, 100, 1000] {
            let parts = parse_with_chunks(text.as_bytes(), source, chunk).unwrap();
            assert_eq!(parts.positions, whole.positions, "chunk {chunk}");
            assert_eq!(parts.faces, whole.faces, "chunk {chunk}");
        }
    }

    #[test]
    fn errors_in_late_pieces_name_their_line_and_the_first_one_wins() {
        let text = grid_text(12);
        let lines: Vec<&str> = text.lines().collect();
        // Header (2 lines), 12 vertices, comment + blank, 132 vertices, then the faces.
        let bad_vertex = 2 + 12 + 2 + 100;
        let bad_face = 2 + 144 + 2 + 50;
        let mut broken: Vec<String> = lines.iter().map(|l| l.to_string()).collect();
        broken[bad_vertex] = "1 2 x".into();
        broken[bad_face] = "3 0 1 999".into();
        let broken = broken.join("\n");
        let source = Source::new(Path::new("t.off"));
        for chunk in [1, 50, 100_000] {
            let e = parse_with_chunks(broken.as_bytes(), source, chunk)
                .unwrap_err()
                .to_string();
            assert_eq!(
                e,
                format!(
                    "t.off: line {}: non-numeric token 'x' where the z coordinate of vertex 112 \
                     was expected",
                    bad_vertex + 1
                ),
                "chunk {chunk}"
            );
        }
        let mut only_face: Vec<String> = lines.iter().map(|l| l.to_string()).collect();
        only_face[bad_face] = "3 0 1 999".into();
        let e = parse_with_chunks(only_face.join("\n").as_bytes(), source, 64)
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            format!(
                "t.off: line {}: face 49: vertex index 999 out of range (the file has 144 \
                 vertices)",
                bad_face + 1
            )
        );
    }

    #[test]
    fn triangle_lines_read_as_their_tokens_do() {
        let mut corners = Vec::new();
        for line in [
            "3 0 1 2",
            " 3\t2 1 0 255 0 0",
            "3 0 1 2#c",
            "3 0 1 9",
            "3 0 1",
            "4 0 1 2 3",
            "3 0 +1 2",
            "3 0 1 2x",
            "03 00 01 2",
        ] {
            // `None` leaves the line to the token path, always right.
            if let Some(t) = triangle_line(line.as_bytes(), 4) {
                let mut tokens = Tokens::new(line.as_bytes());
                let head = tokens.next().unwrap();
                face(head, tokens, 0, 4, &mut corners).unwrap();
                assert_eq!(corners, t, "{line}");
            }
        }
        assert_eq!(triangle_line(b" 3\t2 1 0 255 0 0", 4), Some([2, 1, 0]));
        assert_eq!(triangle_line(b"3 0 1 9", 4), None);
        assert_eq!(triangle_line(b"3 0 1 2#c", 4), None);
    }

    #[test]
    fn binary_off_is_named_as_unsupported() {
        assert_eq!(
            error("OFF BINARY\n\x00\x00\x00\x03"),
            "t.off: line 1: binary OFF ('OFF BINARY') is not supported: convert the file to \
             ascii OFF, PLY or OBJ"
        );
        assert_eq!(
            error("COFF binary\n"),
            "t.off: line 1: binary OFF ('COFF BINARY') is not supported: convert the file to \
             ascii OFF, PLY or OBJ"
        );
    }

    #[test]
    fn negative_and_huge_counts_say_so() {
        assert_eq!(
            error("OFF\n-4 1 0\n"),
            "t.off: line 2: malformed header: vertex count -4 is not a non-negative integer (a \
             count cannot be negative)"
        );
        assert_eq!(
            error("OFF\n3 -1 0\n"),
            "t.off: line 2: malformed header: face count -1 is not a non-negative integer (a \
             count cannot be negative)"
        );
        let digits = "9".repeat(300);
        assert_eq!(
            error(&format!("OFF\n{digits} 1 0\n")),
            format!(
                "t.off: line 2: malformed header: vertex count '{}…' is too large",
                &digits[..40]
            )
        );
        let head = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n";
        assert_eq!(
            error(&format!("{head}-3 0 1 2\n")),
            "t.off: line 6: face 0: vertex count -3 is not a non-negative integer (a count \
             cannot be negative)"
        );
        assert_eq!(
            error(&format!("{head}{digits} 0 1 2\n")),
            format!(
                "t.off: line 6: face 0: vertex count '{}…' is out of range",
                &digits[..40]
            )
        );
        assert_eq!(
            error(&format!("{head}3 0 1 {digits}\n")),
            format!(
                "t.off: line 6: face 0: vertex index {}… out of range (the file has 3 vertices)",
                &digits[..40]
            )
        );
    }

    #[test]
    fn lone_carriage_returns_end_lines_in_every_piece() {
        let text = grid_text(12).replace('\n', "\r");
        let source = Source::new(Path::new("t.off"));
        let lf = parse_with_chunks(grid_text(12).as_bytes(), source, usize::MAX / 2).unwrap();
        for chunk in [1, 7, 100, usize::MAX / 2] {
            let cr = parse_with_chunks(text.as_bytes(), source, chunk).unwrap();
            assert_eq!(cr, lf, "chunk {chunk}");
        }
        // Lone CRs among LFs (a piece then holds more lines than it has LFs).
        let mixed: String = grid_text(12)
            .split('\n')
            .enumerate()
            .map(|(i, l)| format!("{l}{}", if i % 3 == 0 { "\r" } else { "\n" }))
            .collect();
        for chunk in [1, 50, usize::MAX / 2] {
            let m = parse_with_chunks(mixed.as_bytes(), source, chunk).unwrap();
            assert_eq!(m, lf, "chunk {chunk}");
        }
        // Errors count the lines a lone CR ends.
        assert_eq!(
            error("OFF\r3 1 0\r0 0 0\r1 x 0\r0 1 0\r3 0 1 2\r"),
            "t.off: line 4: non-numeric token 'x' where the y coordinate of vertex 1 was \
             expected"
        );
        assert_eq!(
            error("OFF\r3 1 0\r0 0 0\r\n1 0 0\r0 1 0\r\r"),
            "t.off: line 6: the file ends after 0 of 1 faces"
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
