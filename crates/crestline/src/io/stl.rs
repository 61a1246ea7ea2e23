//! STL (stereolithography) meshes, ascii and binary.
//!
//! Reference: 3D Systems, "StereoLithography Interface Specification" (1989); summarised at
//! <https://en.wikipedia.org/wiki/STL_(file_format)>.
//!
//! STL stores each triangle with its own three corners, so the reader welds corners whose
//! positions are bitwise equal (+0 = −0) into one vertex (no tolerance: a tolerance would
//! merge features that are merely close; see [`crate::mesh::weld_coincident`], which does the
//! same for the other formats). Stored facet normals are ignored.
//!
//! Telling the two encodings apart: a binary file is an 80-byte header, a little-endian u32
//! triangle count n and n 50-byte records, so its size is exactly 84 + 50·n. Many binary
//! exporters start the header with `solid`, so that word alone proves nothing: a file whose
//! size matches is binary; a file that starts with `solid` is ascii unless it holds zero
//! bytes and more than its count's records (ascii text in bytes 80 to 83 declares hundreds of
//! millions of triangles); a file that does not start with `solid` is binary, and a short one
//! is truncated.
//!
//! Bytes after the last record of a binary file (whatever its header starts with) are
//! tolerated when they are padding: a part of a record, zero bytes, text. When they start
//! instead with whole records that all look like triangles (twelve finite numbers, neither
//! all zero bytes nor all printable text), the header's count is wrong: exporters that write
//! the count before they know it leave 0 or a partial count there. That is an error naming
//! the offset of the first such record and both counts, rather than reading the triangles
//! anyway: either number could be the wrong one (a file cut short with junk after it looks
//! the same), the reader has no way to warn, and a mesh missing triangles or grown by
//! garbage would go on silently into the algorithms. The message says how to repair it.
//!
//! Ascii: `solid name`, then `facet normal nx ny nz`, `outer loop`, three `vertex x y z`,
//! `endloop`, `endfacet`, ..., `endsolid name`; keywords are matched case-insensitively and
//! several solids may follow each other. A loop with more than three vertices is
//! triangulated as a polygon (see [`super::triangulate`]). The nesting is checked, so that a
//! file cut inside a facet (after `facet normal ...`, inside a loop) or missing an `endloop`
//! or `endfacet` is an error naming the line, not a mesh short of triangles. A missing
//! `endsolid` after complete facets is tolerated, as other readers tolerate it (a file cut
//! exactly between two facets cannot be told from it). A `solid` line alone is left to the
//! "no vertices" error of every format.
//!
//! Writing emits binary STL; positions are rounded to `f32`, so it is the one lossy format.

use std::io::Write;

use super::MeshData;
use super::text::{Lines, Source, Tokens, coordinate, show};
use super::triangulate::Triangulator;
use crate::error::{Error, Result};
use crate::mesh::weld::PositionMap;
use crate::mesh::{TriMesh, Vec3};

const HEADER_BYTES: usize = 80;
const PREAMBLE_BYTES: usize = HEADER_BYTES + 4;
const RECORD_BYTES: usize = 50;

/// Parses an STL file held in memory, ascii or binary (see the module docs for how they are
/// told apart).
pub(super) fn parse(bytes: &[u8], source: Source<'_>) -> Result<MeshData> {
    let declared = bytes
        .get(HEADER_BYTES..)
        .and_then(|rest| rest.first_chunk::<4>())
        .map(|count| u32::from_le_bytes(*count) as usize);
    let expected_size = declared.map(|n| PREAMBLE_BYTES as u64 + RECORD_BYTES as u64 * n as u64);
    // Keywords are case-insensitive (`SOLID` from some exporters).
    let starts_with_solid = bytes
        .trim_ascii_start()
        .get(..5)
        .is_some_and(|word| word.eq_ignore_ascii_case(b"solid"));
    // Ascii STL is plain text; binary records nearly always hold zero bytes (attribute
    // counts, small coordinates). Used only to word an error message.
    let looks_binary = bytes.contains(&0);
    let size = bytes.len() as u64;
    match (declared, expected_size) {
        (Some(n), Some(expected)) if expected == size => parse_binary(bytes, n, source),
        (Some(n), Some(expected)) if !starts_with_solid => {
            if expected < size {
                check_trailing_records(bytes, n, source)?;
                parse_binary(bytes, n, source)
            } else {
                let complete = (bytes.len() - PREAMBLE_BYTES) / RECORD_BYTES;
                Err(source.at_byte(
                    PREAMBLE_BYTES + complete * RECORD_BYTES,
                    format!(
                        "truncated data: the binary STL header declares {n} triangles \
                         ({expected} bytes) but the file has {size} bytes; triangle \
                         {complete} is incomplete"
                    ),
                ))
            }
        }
        _ if starts_with_solid => {
            // A binary file whose header starts with "solid", followed by padding or by
            // records its count leaves out. (Ascii text in bytes 80 to 83 declares hundreds
            // of millions of triangles, far more than the file holds.)
            if let (Some(n), Some(expected)) = (declared, expected_size)
                && looks_binary
                && expected < size
            {
                check_trailing_records(bytes, n, source)?;
                return parse_binary(bytes, n, source);
            }
            // A binary file whose header starts with "solid" but whose size is wrong lands
            // here; say so, or the user only sees a baffling ascii error (or, with no line
            // break in its bytes, "no vertices").
            let hint = |message: String| match (declared, expected_size) {
                (Some(n), Some(expected)) if looks_binary => format!(
                    "{message} (if this is a binary STL, it is truncated or padded: its header \
                     declares {n} triangles, {expected} bytes, and the file has {size})"
                ),
                _ => message,
            };
            match parse_ascii(bytes, source) {
                Ok(data) if looks_binary && data.positions.is_empty() => {
                    Err(source.whole(hint("no facets in a file that starts with 'solid'".into())))
                }
                Ok(data) => Ok(data),
                Err(Error::Parse {
                    path,
                    location,
                    message,
                }) => Err(Error::Parse {
                    path,
                    location,
                    message: hint(message),
                }),
                Err(e) => Err(e),
            }
        }
        _ => Err(source.at_byte(
            bytes.len(),
            format!(
                "truncated data: {size} bytes is neither an ascii STL (it does not start with \
                 'solid') nor a binary one (shorter than the {PREAMBLE_BYTES}-byte header)"
            ),
        )),
    }
}

/// Refuses a binary file whose bytes after the `declared` triangles are whole records that
/// look like triangles (see the module docs).
fn check_trailing_records(bytes: &[u8], declared: usize, source: Source<'_>) -> Result<()> {
    let end = PREAMBLE_BYTES + declared * RECORD_BYTES;
    let trailing = &bytes[end.min(bytes.len())..];
    // Whole records only: a part of one after them (a stray line end) does not hide them.
    let extra = trailing.len() / RECORD_BYTES;
    if extra == 0
        || !trailing
            .chunks_exact(RECORD_BYTES)
            .all(looks_like_a_triangle)
    {
        return Ok(());
    }
    let total = declared + extra;
    Err(source.at_byte(
        end,
        format!(
            "the binary STL header declares {declared} triangles but the file holds {total} \
             whole 50-byte records that look like triangles ({} bytes): the {extra} from here \
             on are not padding, and the count in the header (bytes 80 to 83) is probably \
             wrong; set it to {total} to read them all, or cut the file at byte {end} to drop \
             them",
            bytes.len()
        ),
    ))
}

/// True for a 50-byte record whose twelve numbers (normal and corners) are finite and which is
/// neither all zero bytes nor all printable text (padding some exporters add).
fn looks_like_a_triangle(record: &[u8]) -> bool {
    let numbers = &record[..48.min(record.len())];
    let finite = numbers
        .chunks_exact(4)
        .all(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]).is_finite());
    let zeros = numbers.iter().all(|&b| b == 0);
    let text = record
        .iter()
        .all(|&b| b.is_ascii_graphic() || b.is_ascii_whitespace());
    finite && !zeros && !text
}

fn parse_binary(bytes: &[u8], triangles: usize, source: Source<'_>) -> Result<MeshData> {
    let body = &bytes[PREAMBLE_BYTES..];
    let mut welder = Welder::with_capacity(triangles / 2);
    let mut faces = Vec::with_capacity(triangles);
    for (t, record) in body.chunks_exact(RECORD_BYTES).take(triangles).enumerate() {
        let mut corners = [0u32; 3];
        for (k, corner) in corners.iter_mut().enumerate() {
            // Skip the 12-byte normal; each corner is three little-endian f32.
            let at = 12 + 12 * k;
            let mut p = [0.0f64; 3];
            for (axis, c) in p.iter_mut().enumerate() {
                let offset = at + 4 * axis;
                let raw = record
                    .get(offset..)
                    .and_then(|r| r.first_chunk::<4>())
                    .copied()
                    .unwrap_or_default();
                *c = f64::from(f32::from_le_bytes(raw));
                if !c.is_finite() {
                    return Err(source.at_byte(
                        PREAMBLE_BYTES + t * RECORD_BYTES + offset,
                        format!(
                            "triangle {t}, corner {k}: {} coordinate is NaN or infinite ({c})",
                            ["x", "y", "z"][axis]
                        ),
                    ));
                }
            }
            *corner = welder.index(p);
        }
        faces.push(corners);
    }
    Ok(MeshData {
        positions: welder.positions,
        faces,
    })
}

/// Where an ascii STL reader is in the nesting of `solid`, `facet` and `outer loop`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Nesting {
    /// Before the first `solid` or after an `endsolid`.
    Outside,
    /// Between `solid` and `endsolid`, outside a facet.
    Solid,
    /// Between `facet` and `endfacet`, outside its loop.
    Facet,
    /// Between `outer loop` and `endloop`.
    Loop,
}

fn parse_ascii(bytes: &[u8], source: Source<'_>) -> Result<MeshData> {
    let mut welder = Welder::with_capacity(bytes.len() / 500);
    let mut faces = Vec::with_capacity(bytes.len() / 250);
    let mut corners: Vec<u32> = Vec::with_capacity(3);
    let mut polygons = Triangulator::default();
    let mut nesting = Nesting::Outside;
    let mut last_line = 0;
    for (line, text) in Lines::new(bytes) {
        last_line = line;
        let mut tokens = Tokens::new(text);
        let Some(keyword) = tokens.next() else {
            continue;
        };
        let is = |k: &str| keyword.eq_ignore_ascii_case(k.as_bytes());
        // `(expected, next)`: the nesting the keyword needs and the one it leads to.
        let (expected, next) = if is("vertex") {
            if nesting != Nesting::Loop {
                return Err(source.at_line(line, "vertex outside an 'outer loop'"));
            }
            let mut p = [0.0f64; 3];
            for (axis, c) in p.iter_mut().enumerate() {
                let name = ["x", "y", "z"][axis];
                *c = coordinate(tokens.next(), || format!("{name} coordinate"))
                    .map_err(|m| source.at_line(line, m))?;
            }
            corners.push(welder.index(p));
            continue;
        } else if is("solid") {
            (Nesting::Outside, Nesting::Solid)
        } else if is("facet") {
            (Nesting::Solid, Nesting::Facet)
        } else if is("outer") {
            corners.clear();
            (Nesting::Facet, Nesting::Loop)
        } else if is("endloop") {
            if nesting == Nesting::Loop && corners.len() < 3 {
                return Err(source.at_line(
                    line,
                    format!("facet with {} vertices (at least 3 needed)", corners.len()),
                ));
            }
            (Nesting::Loop, Nesting::Facet)
        } else if is("endfacet") {
            (Nesting::Facet, Nesting::Solid)
        } else if is("endsolid") {
            (Nesting::Solid, Nesting::Outside)
        } else {
            return Err(source.at_line(
                line,
                format!(
                    "unexpected '{}' in ascii STL (expected solid, facet, outer loop, vertex, \
                     endloop, endfacet or endsolid)",
                    show(keyword)
                ),
            ));
        };
        if nesting != expected {
            return Err(source.at_line(
                line,
                format!("'{}' out of place {}", show(keyword), misplaced(nesting)),
            ));
        }
        if next == Nesting::Facet && nesting == Nesting::Loop {
            polygons.push(&mut faces, &corners, &welder.positions);
        }
        nesting = next;
    }
    let end = match nesting {
        // Between facets: a missing 'endsolid' line is tolerated, as other readers do (a
        // `solid` line alone is left to the "no vertices" error).
        Nesting::Outside | Nesting::Solid => None,
        Nesting::Facet | Nesting::Loop => {
            Some("truncated data: the file ends inside a facet".to_string())
        }
    };
    if let Some(message) = end {
        return Err(source.at_line(last_line.max(1), message));
    }
    Ok(MeshData {
        positions: welder.positions,
        faces,
    })
}

/// Where the reader is, and the keywords that may come there.
fn misplaced(nesting: Nesting) -> &'static str {
    match nesting {
        Nesting::Outside => "outside a solid: expected 'solid'",
        Nesting::Solid => "between facets: expected 'facet' or 'endsolid'",
        Nesting::Facet => "in a facet, outside its loop: expected 'outer loop' or 'endfacet'",
        Nesting::Loop => "in a loop: expected 'vertex' or 'endloop'",
    }
}

/// Gives one index to each distinct position (bitwise, +0 = −0), in order of first
/// appearance ([`PositionMap`]).
struct Welder {
    index_of: PositionMap,
    positions: Vec<[f64; 3]>,
}

impl Welder {
    fn with_capacity(n: usize) -> Self {
        Welder {
            index_of: PositionMap::with_capacity(n),
            positions: Vec::with_capacity(n),
        }
    }

    #[inline]
    fn index(&mut self, p: [f64; 3]) -> u32 {
        let next = self.positions.len() as u32;
        let index = self.index_of.index_or(Vec3::from(p), next);
        if index == next {
            self.positions.push(p);
        }
        index
    }
}

/// Writes `mesh` as binary STL (positions rounded to `f32`, unit facet normals).
pub(super) fn write<W: Write>(mut out: W, mesh: &TriMesh) -> std::io::Result<()> {
    let mut header = [b' '; HEADER_BYTES];
    let label = b"binary STL written by crestline";
    header[..label.len()].copy_from_slice(label);
    out.write_all(&header)?;
    let count = u32::try_from(mesh.num_faces()).unwrap_or(u32::MAX);
    out.write_all(&count.to_le_bytes())?;
    for f in 0..count as usize {
        let [a, b, c] = mesh.triangle(f);
        let normal = (b - a)
            .cross(&(c - a))
            .try_normalize(0.0)
            .unwrap_or_else(crate::mesh::Vec3::zeros);
        let mut record = [0u8; RECORD_BYTES];
        for (k, value) in normal
            .iter()
            .chain(a.iter())
            .chain(b.iter())
            .chain(c.iter())
            .enumerate()
        {
            let single = *value as f32;
            if !single.is_finite() {
                return Err(std::io::Error::new(
                    std::io::ErrorKind::InvalidData,
                    format!(
                        "triangle {f}: {value:e} does not fit the single precision of STL \
                         (use OBJ, PLY or OFF)"
                    ),
                ));
            }
            record[4 * k..4 * k + 4].copy_from_slice(&single.to_le_bytes());
        }
        out.write_all(&record)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    fn parse_bytes(bytes: &[u8]) -> Result<MeshData> {
        parse(bytes, Source::new(Path::new("t.stl")))
    }

    fn error(bytes: &[u8]) -> String {
        parse_bytes(bytes).unwrap_err().to_string()
    }

    const ASCII: &str = "solid square\n\
        facet normal 0 0 1\n outer loop\n  vertex 0 0 0\n  vertex 1 0 0\n  vertex 1 1 0\n\
        endloop\nendfacet\n\
        FACET NORMAL 0 0 1\n OUTER LOOP\n  VERTEX 0 0 0\n  VERTEX 1 1 0\n  VERTEX 0 1 0\n\
        ENDLOOP\nENDFACET\n\
        endsolid square\n";

    /// A binary STL of the same two triangles, with `header` as the first header bytes.
    fn binary(header: &[u8], triangles: &[[[f32; 3]; 3]]) -> Vec<u8> {
        let mut bytes = vec![0u8; HEADER_BYTES];
        bytes[..header.len()].copy_from_slice(header);
        bytes.extend_from_slice(&(triangles.len() as u32).to_le_bytes());
        for t in triangles {
            bytes.extend_from_slice(&[0u8; 12]);
            for c in t.iter().flatten() {
                bytes.extend_from_slice(&c.to_le_bytes());
            }
            bytes.extend_from_slice(&[0u8; 2]);
        }
        bytes
    }

    const SQUARE: [[[f32; 3]; 3]; 2] = [
        [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0]],
        [[0.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]],
    ];

    #[test]
    fn ascii_corners_are_welded() {
        let m = parse_bytes(ASCII.as_bytes()).unwrap();
        assert_eq!(m.positions.len(), 4);
        assert_eq!(m.faces, vec![[0, 1, 2], [0, 2, 3]]);
    }

    #[test]
    fn uppercase_ascii_is_ascii() {
        // `SOLID` was taken for a binary header ("declares 1347374924 triangles").
        let upper = ASCII.to_ascii_uppercase();
        let lower = parse_bytes(ASCII.as_bytes()).unwrap();
        let upper = parse_bytes(upper.as_bytes()).unwrap();
        assert_eq!(upper.positions, lower.positions);
        assert_eq!(upper.faces, lower.faces);
    }

    #[test]
    fn binary_corners_are_welded_even_when_the_header_says_solid() {
        for header in [&b"solid trap"[..], b"exported by something"] {
            let m = parse_bytes(&binary(header, &SQUARE)).unwrap();
            assert_eq!(m.positions.len(), 4);
            assert_eq!(m.positions[3], [0.0, 1.0, 0.0]);
            assert_eq!(m.faces, vec![[0, 1, 2], [0, 2, 3]]);
        }
    }

    #[test]
    fn welding_is_bitwise_but_for_the_sign_of_zero() {
        // −0 is the same place as +0 (mirrored halves write it on the mirror plane).
        let mut t = SQUARE;
        t[1][0] = [-0.0, 0.0, 0.0];
        let m = parse_bytes(&binary(b"", &t)).unwrap();
        assert_eq!(m.positions.len(), 4);
        // One unit in the last place of single precision apart is another place.
        t[1][0] = [f32::from_bits(1), 0.0, 0.0];
        let m = parse_bytes(&binary(b"", &t)).unwrap();
        assert_eq!(m.positions.len(), 5);
    }

    #[test]
    fn trailing_bytes_after_binary_records_are_tolerated() {
        let mut bytes = binary(b"x", &SQUARE);
        bytes.extend_from_slice(b"padding");
        assert_eq!(parse_bytes(&bytes).unwrap().faces.len(), 2);
    }

    #[test]
    fn truncated_binary() {
        let bytes = binary(b"x", &SQUARE);
        assert_eq!(
            error(&bytes[..bytes.len() - 10]),
            "t.stl: byte 134: truncated data: the binary STL header declares 2 triangles \
             (184 bytes) but the file has 174 bytes; triangle 1 is incomplete"
        );
        assert_eq!(
            error(b"\x00\x01binary junk"),
            "t.stl: byte 13: truncated data: 13 bytes is neither an ascii STL (it does not \
             start with 'solid') nor a binary one (shorter than the 84-byte header)"
        );
        // A truncated binary whose header starts with "solid" is read as ascii; the error
        // says what the binary reading would have been.
        let bytes = binary(b"solid", &SQUARE);
        let e = error(&bytes[..bytes.len() - 10]);
        assert!(e.starts_with("t.stl: line 1: unexpected"), "{e}");
        assert!(
            e.contains("declares 2 triangles, 184 bytes, and the file has 174"),
            "{e}"
        );
    }

    #[test]
    fn binary_nan_is_rejected_with_its_offset() {
        let mut t = SQUARE;
        t[1][2][2] = f32::NAN;
        assert_eq!(
            error(&binary(b"", &t)),
            "t.stl: byte 178: triangle 1, corner 2: z coordinate is NaN or infinite (NaN)"
        );
    }

    #[test]
    fn ascii_errors() {
        let bad = ASCII.replace("vertex 1 0 0", "vertex 1 zero 0");
        assert_eq!(
            error(bad.as_bytes()),
            "t.stl: line 5: non-numeric token 'zero' where the y coordinate was expected"
        );
        let bad = ASCII.replace("vertex 1 0 0", "vertex 1 0 inf");
        assert_eq!(
            error(bad.as_bytes()),
            "t.stl: line 5: z coordinate is NaN or infinite ('inf')"
        );
        let bad = ASCII.replace("  vertex 1 1 0\n", "");
        assert_eq!(
            error(bad.as_bytes()),
            "t.stl: line 6: facet with 2 vertices (at least 3 needed)"
        );
        assert_eq!(
            error(b"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n"),
            "t.stl: line 4: truncated data: the file ends inside a facet"
        );
        assert!(error(b"solid x\nfacett\n").starts_with("t.stl: line 2: unexpected 'facett'"));
    }

    #[test]
    fn binary_records_beyond_the_declared_count_are_an_error() {
        // Two triangles under a header that declares one (or none: exporters that never go
        // back to write the count).
        let mut bytes = binary(b"x", &SQUARE);
        bytes[80..84].copy_from_slice(&1u32.to_le_bytes());
        assert_eq!(
            error(&bytes),
            "t.stl: byte 134: the binary STL header declares 1 triangles but the file holds 2 \
             whole 50-byte records that look like triangles (184 bytes): the 1 from here on are \
             not padding, and the count in the header (bytes 80 to 83) is probably wrong; set \
             it to 2 to read them all, or cut the file at byte 134 to drop them"
        );
        bytes[80..84].copy_from_slice(&0u32.to_le_bytes());
        assert!(error(&bytes).starts_with("t.stl: byte 84: the binary STL header declares 0 "));
        // The same under a header that starts with "solid" (first read as ascii).
        let mut bytes = binary(b"solid x", &SQUARE);
        bytes[80..84].copy_from_slice(&1u32.to_le_bytes());
        assert!(error(&bytes).starts_with("t.stl: byte 134: the binary STL header declares 1 "));
        // A stray byte after the records does not hide them.
        bytes.push(b'\n');
        assert!(error(&bytes).starts_with("t.stl: byte 134: the binary STL header declares 1 "));
    }

    #[test]
    fn padding_after_binary_records_is_tolerated() {
        let square = binary(b"x", &SQUARE);
        let text = b"padded with a text of exactly fifty bytes, for fun";
        assert_eq!(text.len(), RECORD_BYTES);
        let mut not_finite = binary(b"", &[[[f32::NAN; 3]; 3]])[84..].to_vec();
        not_finite[0] = 1;
        for padding in [
            vec![0u8; RECORD_BYTES],
            vec![0u8; 3 * RECORD_BYTES],
            text.to_vec(),
            not_finite,
            // Less than a record.
            vec![7u8; 10],
        ] {
            for header in [&b"x"[..], b"solid x"] {
                let mut bytes = binary(header, &SQUARE);
                bytes.extend_from_slice(&padding);
                let m = parse_bytes(&bytes).unwrap_or_else(|e| panic!("{e}"));
                assert_eq!(m.faces.len(), 2);
            }
        }
        assert_eq!(square, binary(b"x", &SQUARE));
    }

    #[test]
    fn ascii_cut_anywhere_is_an_error_at_a_line() {
        let end = ASCII.find("endsolid").unwrap() + "endsolid".len();
        // Shorter than "solid": taken for binary, an error at a byte. Up to the first facet:
        // no vertices, which the front door refuses for every format.
        let first_facet = ASCII.find("facet").unwrap();
        for cut in 5..=first_facet {
            assert_eq!(
                parse_bytes(&ASCII.as_bytes()[..cut]).unwrap(),
                MeshData::default()
            );
        }
        for cut in first_facet + 1..end {
            // Cut after a whole facet: those facets (the 'endsolid' line is not needed).
            let head = &ASCII[..cut];
            let lower = head.to_ascii_lowercase();
            if lower.trim_end().ends_with("endfacet") {
                let facets = lower.matches("endfacet").count();
                assert_eq!(parse_bytes(head.as_bytes()).unwrap().faces.len(), facets);
                continue;
            }
            let e = error(head.as_bytes());
            assert!(e.starts_with("t.stl: line "), "cut at {cut}: {e}");
        }
        for cut in end..=ASCII.len() {
            assert_eq!(
                parse_bytes(&ASCII.as_bytes()[..cut]).unwrap().faces.len(),
                2
            );
        }
        assert_eq!(
            error(b"solid x\nfacet normal 0 0 1\n"),
            "t.stl: line 2: truncated data: the file ends inside a facet"
        );
        let without_endsolid = b"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n\
            vertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n";
        assert_eq!(parse_bytes(without_endsolid).unwrap().faces.len(), 1);
    }

    #[test]
    fn ascii_nesting_is_checked() {
        let without = |line: &str| error(ASCII.replacen(line, "", 1).as_bytes());
        assert_eq!(
            without("endloop\n"),
            "t.stl: line 7: 'endfacet' out of place in a loop: expected 'vertex' or 'endloop'"
        );
        assert_eq!(
            without("endfacet\n"),
            "t.stl: line 8: 'FACET' out of place in a facet, outside its loop: expected 'outer \
             loop' or 'endfacet'"
        );
        assert_eq!(
            without("facet normal 0 0 1\n"),
            "t.stl: line 2: 'outer' out of place between facets: expected 'facet' or 'endsolid'"
        );
        assert_eq!(
            error(format!("{ASCII}facet normal 0 0 1\n").as_bytes()),
            "t.stl: line 17: 'facet' out of place outside a solid: expected 'solid'"
        );
        // Several solids in a row are fine.
        let twice = parse_bytes(format!("{ASCII}{ASCII}").as_bytes()).unwrap();
        assert_eq!(twice.faces.len(), 4);
    }

    #[test]
    fn ascii_with_lone_carriage_returns() {
        let m = parse_bytes(ASCII.replace('\n', "\r").as_bytes()).unwrap();
        assert_eq!(m, parse_bytes(ASCII.as_bytes()).unwrap());
        let bad = ASCII
            .replace("vertex 1 0 0", "vertex 1 zero 0")
            .replace('\n', "\r");
        assert_eq!(
            error(bad.as_bytes()),
            "t.stl: line 5: non-numeric token 'zero' where the y coordinate was expected"
        );
    }

    #[test]
    fn huge_values_are_written_short_in_the_error() {
        let mesh = TriMesh::from_arrays(
            vec![[0.0, 0.0, 0.0], [1e100, 0.0, 0.0], [0.0, 1e100, 0.0]],
            vec![[0, 1, 2]],
        )
        .unwrap();
        let e = write(Vec::new(), &mesh).unwrap_err();
        assert_eq!(
            e.to_string(),
            "triangle 0: 1e100 does not fit the single precision of STL (use OBJ, PLY or OFF)"
        );
    }

    #[test]
    fn writes_binary_that_reads_back() {
        let data = parse_bytes(ASCII.as_bytes()).unwrap();
        let mesh = TriMesh::from_arrays(data.positions.clone(), data.faces.clone()).unwrap();
        let mut bytes = Vec::new();
        write(&mut bytes, &mesh).unwrap();
        assert_eq!(bytes.len(), 84 + 2 * 50);
        assert_eq!(parse_bytes(&bytes).unwrap(), data);
    }
}
