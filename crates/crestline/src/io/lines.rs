//! Feature-line files: OBJ polylines (written and read back), JSON and PLY edges.
//!
//! - **OBJ** (reference as in `obj.rs`): groups `o ridges`, `o valleys`, `o crease-ridges`
//!   and `o crease-valleys` (crest lines, then sharp creases; empty groups are left out), each
//!   a run of `v` records followed by one `l` record per polyline; a closed line repeats its
//!   first index at the end of its `l`. Any OBJ with `l` records reads back: a group (`o` or
//!   `g`) whose name contains `valley` (any case) gives valleys, every other group ridges; a
//!   name containing `crease` gives creases. Lines read back have no mesh locations and zero
//!   `curvature_integral` and `strength` (OBJ does not store them); their `length` is
//!   recomputed.
//! - **JSON**: `{"ridges": n, "valleys": m, "crease_ridges": p, "crease_valleys": q,
//!   "lines": [{"kind": "ridge" | "valley" | "crease-ridge" | "crease-valley", "closed",
//!   "points": [[x, y, z], ...], "length", "curvature_integral", "strength"}]}` (`ridges` and
//!   `valleys` count crest lines).
//! - **PLY** (reference as in `ply.rs`): every line point as a vertex (`double x, y, z`) and
//!   an `edge` element with `int vertex1, vertex2` and `uchar kind` (0 ridge, 1 valley,
//!   2 crease ridge, 3 crease valley); a closed line has an edge back to its first point.
//!
//! Limits: a line with fewer than two points cannot be written as an OBJ `l` and is left out
//! of OBJ files (JSON and PLY keep it).

use std::io::Write;
use std::path::Path;

use serde::Serialize;

use super::ply::{PlyEncoding, RecordWriter, index_type};
use super::text::{Lines, Source, Tokens, parse_i64, show, strip_bom, vertex};
use super::write_f64;
use crate::error::{Error, Result};
use crate::lines::{FeatureLine, FeatureLines, LineKind};
use crate::mesh::Vec3;

/// A feature-line file format.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum LinesFormat {
    /// OBJ polylines, one group per kind (readable back).
    Obj,
    /// JSON with every attribute of every line.
    Json,
    /// PLY vertices and edges with a kind.
    Ply,
}

impl LinesFormat {
    /// The format a path's extension names (case-insensitive).
    pub fn from_path(path: &Path) -> Option<LinesFormat> {
        let extension = path.extension()?.to_str()?.to_ascii_lowercase();
        match extension.as_str() {
            "obj" => Some(LinesFormat::Obj),
            "json" => Some(LinesFormat::Json),
            "ply" => Some(LinesFormat::Ply),
            _ => None,
        }
    }
}

/// Writes feature lines to `path` (all or nothing, see [`super::write_atomically`]), in
/// `format` or else the one its extension names; PLY
/// uses the encoding in `ply_encoding`.
///
/// # Errors
/// [`Error::InvalidInput`] for an unknown extension, [`Error::Io`] naming the file.
pub fn write_lines(
    path: &Path,
    lines: &FeatureLines,
    format: Option<LinesFormat>,
    ply_encoding: PlyEncoding,
) -> Result<()> {
    let format = format
        .or_else(|| LinesFormat::from_path(path))
        .ok_or_else(|| {
            Error::InvalidInput(format!(
                "{}: cannot tell the feature-line format from the extension (known: .obj, \
                 .json, .ply)",
                path.display()
            ))
        })?;
    super::write_atomically(path, |out| match format {
        LinesFormat::Obj => write_lines_obj(out, lines),
        LinesFormat::Json => write_lines_json(out, lines),
        LinesFormat::Ply => write_lines_ply(out, lines, ply_encoding),
    })
}

/// The class of a line in files (the PLY `kind`): 0 ridge, 1 valley, 2 crease ridge, 3 crease
/// valley.
fn class_of(line: &FeatureLine) -> usize {
    match (line.kind, line.crease) {
        (LineKind::Ridge, false) => 0,
        (LineKind::Valley, false) => 1,
        (LineKind::Ridge, true) => 2,
        (LineKind::Valley, true) => 3,
    }
}

/// JSON `kind` of each class.
const KIND_NAMES: [&str; 4] = ["ridge", "valley", "crease-ridge", "crease-valley"];
/// OBJ group of each class.
const GROUP_NAMES: [&str; 4] = ["ridges", "valleys", "crease-ridges", "crease-valleys"];

/// Lines per class.
fn class_counts(lines: &FeatureLines) -> [usize; 4] {
    let mut counts = [0; 4];
    for l in &lines.lines {
        counts[class_of(l)] += 1;
    }
    counts
}

/// Writes OBJ polylines: `o ridges`, `o valleys`, `o crease-ridges`, then `o crease-valleys`,
/// each line as its `v` records and one `l` record.
///
/// # Errors
/// Whatever `out` returns.
pub fn write_lines_obj<W: Write>(mut out: W, lines: &FeatureLines) -> std::io::Result<()> {
    let counts = class_counts(lines);
    write!(
        out,
        "# crestline feature lines: {} ridges, {} valleys",
        counts[0], counts[1]
    )?;
    if counts[2] + counts[3] > 0 {
        write!(
            out,
            ", {} crease ridges, {} crease valleys",
            counts[2], counts[3]
        )?;
    }
    writeln!(out)?;
    let mut next_index = 1usize;
    for (class, group) in GROUP_NAMES.iter().enumerate() {
        let mut group_started = false;
        for line in lines.lines.iter().filter(|l| class_of(l) == class) {
            if line.points.len() < 2 {
                continue;
            }
            if !group_started {
                writeln!(out, "o {group}")?;
                group_started = true;
            }
            for p in &line.points {
                out.write_all(b"v ")?;
                write_f64(&mut out, p.x)?;
                out.write_all(b" ")?;
                write_f64(&mut out, p.y)?;
                out.write_all(b" ")?;
                write_f64(&mut out, p.z)?;
                out.write_all(b"\n")?;
            }
            out.write_all(b"l")?;
            let first = next_index;
            for _ in &line.points {
                write!(out, " {next_index}")?;
                next_index += 1;
            }
            if line.closed {
                write!(out, " {first}")?;
            }
            out.write_all(b"\n")?;
        }
    }
    Ok(())
}

/// Reads feature lines from an OBJ file with `l` records.
///
/// # Errors
/// [`Error::Io`], or [`Error::Parse`] naming the file and line.
pub fn read_lines_obj(path: &Path) -> Result<FeatureLines> {
    let bytes = std::fs::read(path).map_err(|e| Error::io(path, e))?;
    parse_lines_obj(&bytes, path)
}

/// Parses feature lines from OBJ text held in memory; `name` labels errors.
///
/// # Errors
/// [`Error::Parse`] naming `name` and the line of the fault.
pub fn parse_lines_obj(bytes: &[u8], name: &Path) -> Result<FeatureLines> {
    let source = Source::new(name);
    if bytes.is_empty() {
        return Err(source.whole("empty file"));
    }
    let bytes = strip_bom(bytes);
    let mut positions: Vec<[f64; 3]> = Vec::new();
    // (line number, kind, 0-based indices); resolved once every vertex is known, since an
    // `l` may refer to vertices that come later.
    let mut polylines: Vec<(usize, LineKind, bool, Vec<usize>)> = Vec::new();
    let mut kind = LineKind::Ridge;
    let mut crease = false;
    for (line, text) in Lines::new(bytes) {
        let mut tokens = Tokens::new(text);
        match tokens.next() {
            Some(b"v") => {
                let p = vertex(&mut tokens, positions.len() + 1)
                    .map_err(|m| source.at_line(line, m))?;
                positions.push(p);
            }
            Some(b"o" | b"g") => {
                let name = tokens.next().unwrap_or_default().to_ascii_lowercase();
                let has = |word: &[u8]| name.windows(word.len()).any(|w| w == word);
                kind = if has(b"valley") {
                    LineKind::Valley
                } else {
                    LineKind::Ridge
                };
                crease = has(b"crease");
            }
            Some(b"l") => {
                let mut indices = Vec::new();
                for token in tokens {
                    let digits = token.split(|&b| b == b'/').next().unwrap_or_default();
                    let i = parse_i64(digits).ok_or_else(|| {
                        source.at_line(
                            line,
                            format!(
                                "non-numeric token '{}' where a vertex index was expected",
                                show(token)
                            ),
                        )
                    })?;
                    let index = match i {
                        0 => Err("vertex index 0 (OBJ indices start at 1)".to_string()),
                        i if i > 0 => Ok((i - 1) as usize),
                        i => usize::try_from(positions.len() as i64 + i).map_err(|_| {
                            format!(
                                "relative vertex index {i} reaches before the first vertex \
                                 (only {} read so far)",
                                positions.len()
                            )
                        }),
                    }
                    .map_err(|m| source.at_line(line, m))?;
                    indices.push(index);
                }
                if indices.len() < 2 {
                    return Err(source.at_line(
                        line,
                        format!(
                            "polyline with {} vertices (at least 2 needed)",
                            indices.len()
                        ),
                    ));
                }
                polylines.push((line, kind, crease, indices));
            }
            _ => {}
        }
    }

    let mut lines = Vec::with_capacity(polylines.len());
    for (line, kind, crease, mut indices) in polylines {
        if let Some(&bad) = indices.iter().find(|&&i| i >= positions.len()) {
            return Err(source.at_line(
                line,
                format!(
                    "vertex index {} out of range (the file has {} vertices)",
                    bad + 1,
                    positions.len()
                ),
            ));
        }
        let closed = indices.len() >= 3 && indices.first() == indices.last();
        if closed {
            indices.pop();
        }
        let points: Vec<Vec3> = indices.iter().map(|&i| Vec3::from(positions[i])).collect();
        lines.push(FeatureLine {
            kind,
            length: polyline_length(&points, closed),
            points,
            locations: Vec::new(),
            closed,
            curvature_integral: 0.0,
            strength: 0.0,
            crease,
        });
    }
    Ok(FeatureLines { lines })
}

/// Length of a polyline, with the closing segment when `closed`.
fn polyline_length(points: &[Vec3], closed: bool) -> f64 {
    let open: f64 = points.windows(2).map(|w| (w[1] - w[0]).norm()).sum();
    match (closed, points.first(), points.last()) {
        (true, Some(first), Some(last)) => open + (*first - *last).norm(),
        _ => open,
    }
}

#[derive(Serialize)]
struct JsonFile {
    ridges: usize,
    valleys: usize,
    crease_ridges: usize,
    crease_valleys: usize,
    lines: Vec<JsonLine>,
}

#[derive(Serialize)]
struct JsonLine {
    kind: &'static str,
    closed: bool,
    points: Vec<[f64; 3]>,
    length: f64,
    curvature_integral: f64,
    strength: f64,
}

/// Writes every line with all its attributes as one JSON object.
///
/// # Errors
/// Whatever `out` returns.
pub fn write_lines_json<W: Write>(out: W, lines: &FeatureLines) -> std::io::Result<()> {
    // serde_json would write a non-finite number as `null`.
    for l in &lines.lines {
        for x in l.points.iter().flat_map(|p| p.iter()) {
            super::check_finite(*x)?;
        }
        for x in [l.length, l.curvature_integral, l.strength] {
            super::check_finite(x)?;
        }
    }
    let [ridges, valleys, crease_ridges, crease_valleys] = class_counts(lines);
    let file = JsonFile {
        ridges,
        valleys,
        crease_ridges,
        crease_valleys,
        lines: lines
            .lines
            .iter()
            .map(|l| JsonLine {
                kind: KIND_NAMES[class_of(l)],
                closed: l.closed,
                points: l.points.iter().map(|p| [p.x, p.y, p.z]).collect(),
                length: l.length,
                curvature_integral: l.curvature_integral,
                strength: l.strength,
            })
            .collect(),
    };
    serde_json::to_writer(out, &file).map_err(std::io::Error::other)
}

/// Writes the lines as PLY vertices and `edge`s with a `kind` (0 ridge, 1 valley, 2 crease
/// ridge, 3 crease valley).
///
/// # Errors
/// Whatever `out` returns.
pub fn write_lines_ply<W: Write>(
    out: W,
    lines: &FeatureLines,
    encoding: PlyEncoding,
) -> std::io::Result<()> {
    let vertices: usize = lines.lines.iter().map(|l| l.points.len()).sum();
    let edges: usize = lines
        .lines
        .iter()
        .map(|l| match l.points.len() {
            0 | 1 => 0,
            n if l.closed && n >= 3 => n,
            n => n - 1,
        })
        .sum();
    let index = index_type(vertices);
    let header = format!(
        "ply\nformat {} 1.0\ncomment crestline feature lines; edge kind: 0 = ridge, 1 = valley, 2 = crease ridge, \
         3 = crease valley\n\
         element vertex {vertices}\nproperty double x\nproperty double y\nproperty double z\n\
         element edge {edges}\nproperty {index} vertex1\nproperty {index} vertex2\n\
         property uchar kind\nend_header\n",
        encoding.header_name()
    );
    let mut out = RecordWriter::new(out, encoding);
    out.raw(header.as_bytes())?;
    for p in lines.lines.iter().flat_map(|l| &l.points) {
        out.f64(p.x)?;
        out.f64(p.y)?;
        out.f64(p.z)?;
        out.end()?;
    }
    let mut first = 0u32;
    for line in &lines.lines {
        let n = line.points.len() as u32;
        let kind = class_of(line) as u8;
        let closing = line.closed && n >= 3;
        for k in 0..n.saturating_sub(1) + u32::from(closing) {
            out.index(first + k)?;
            out.index(first + (k + 1) % n)?;
            out.u8(kind)?;
            out.end()?;
        }
        first += n;
    }
    out.finish()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn line(kind: LineKind, points: &[[f64; 3]], closed: bool) -> FeatureLine {
        let points: Vec<Vec3> = points.iter().map(|&p| Vec3::from(p)).collect();
        FeatureLine {
            kind,
            length: polyline_length(&points, closed),
            points,
            locations: Vec::new(),
            closed,
            curvature_integral: 0.5,
            strength: 2.0,
            crease: false,
        }
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
             o ridges\nv 0 0 1\nv 1 0 1\nv 1 1 1\nl 1 2 3 1\n\
             v 0.1 0.2 0.3\nv 0.4 0.5 0.6\nl 4 5\n\
             o valleys\nv 0 0 0\nv 1 0 0\nl 6 7\n"
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
        assert_eq!(e(""), "l.obj: file: empty file");
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
            text.ends_with("0 1 1\n2 3 0\n3 4 0\n4 2 0\n5 6 0\n"),
            "{text}"
        );
        // The binary file has the same header and 7 * 24 + 5 * 9 bytes of data.
        let mut binary = Vec::new();
        write_lines_ply(&mut binary, &sample(), PlyEncoding::BinaryLittleEndian).unwrap();
        let end = binary
            .windows(11)
            .position(|w| w == b"end_header\n")
            .unwrap()
            + 11;
        assert_eq!(binary.len() - end, 7 * 24 + 5 * 9);
        // Both read back as meshes with the line points as vertices.
        for bytes in [text.as_bytes(), &binary[..]] {
            let m = crate::io::parse_mesh_bytes(bytes, crate::io::Format::Ply, Path::new("l.ply"))
                .unwrap();
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
}
