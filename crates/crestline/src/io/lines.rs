//! Feature-line files: OBJ polylines, JSON and PLY edges, each written and read back.
//!
//! [`write_lines`] and [`write_lines_to`] write, [`read_lines`] and [`parse_lines`] read
//! every format back with the kind (ridge, valley, crease ridge, crease valley), closedness,
//! strength and curvature integral of every line; the length is recomputed from the points.
//! Lines read back have no mesh locations.
//!
//! - **OBJ** (reference as in `obj.rs`): groups `o ridges`, `o valleys`, `o crease-ridges`
//!   and `o crease-valleys` (crest lines, then sharp creases; empty groups are left out), each
//!   a run of `v` records followed, per polyline, by a comment
//!   `# strength <T> curvature_integral <I>` and one `l` record; a closed line repeats its
//!   first index at the end of its `l`. Any OBJ with `l` records reads back: a group (`o` or
//!   `g`) whose name contains `valley` (any case) gives valleys, every other group ridges; a
//!   name containing `crease` gives creases; a line without the strength comment has
//!   strength and curvature integral 0. A record that is not OBJ (`hello`), or a mesh without
//!   `l` records, is an error.
//! - **JSON**: `{"ridges": n, "valleys": m, "crease_ridges": p, "crease_valleys": q,
//!   "lines": [{"kind": "ridge" | "valley" | "crease-ridge" | "crease-valley", "closed",
//!   "points": [[x, y, z], ...], "length", "curvature_integral", "strength"}]}` (`ridges` and
//!   `valleys` count crest lines). Reading needs `lines`, and `kind` and `points` in each.
//! - **PLY** (reference as in `ply.rs`): every line point as a vertex (`double x, y, z`) and
//!   an `edge` element with `int vertex1, vertex2`, `uchar kind` (0 ridge, 1 valley,
//!   2 crease ridge, 3 crease valley) and the line's `double strength, curvature_integral`;
//!   a closed line has an edge back to its first point. Reading chains the edges of each kind
//!   into polylines (split where more than two meet; a chain that comes back to its start is
//!   closed), in the order of their first edges; `kind` and the strengths are optional.
//!
//! Limits: a line with fewer than two points cannot be written as an OBJ `l` or a PLY edge
//! and is left out of OBJ files and reads back from PLY as nothing (JSON keeps it).

use std::io::Write;
use std::path::Path;

use serde::{Deserialize, Serialize};

use super::ply::edges::{EdgeRecord, parse_edges};
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

    /// The usual file extension, lower case without the dot.
    pub fn extension(self) -> &'static str {
        match self {
            LinesFormat::Obj => "obj",
            LinesFormat::Json => "json",
            LinesFormat::Ply => "ply",
        }
    }

    /// `format` if given, otherwise the format named by `path`'s extension.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] naming the file when the extension is missing or unknown.
    pub fn resolve(path: &Path, format: Option<LinesFormat>) -> Result<LinesFormat> {
        format
            .or_else(|| LinesFormat::from_path(path))
            .ok_or_else(|| {
                Error::InvalidInput(format!(
                    "{}: cannot tell the feature-line format from the extension (known: \
                     .obj, .json, .ply)",
                    path.display()
                ))
            })
    }
}

/// Reads feature lines from `path`, in `format` or else the one its extension names.
///
/// ```
/// use crestline::io::lines::{LinesFormat, read_lines, write_lines_to};
/// use crestline::io::PlyEncoding;
/// # fn main() -> Result<(), Box<dyn std::error::Error>> {
/// let mesh = crestline::shapes::ellipsoid(3.0, 2.0, 1.0, 3);
/// let lines = crestline::extract::extract(&mesh, &Default::default())?.lines;
/// let dir = std::env::temp_dir().join("crestline-doc-read-lines");
/// std::fs::create_dir_all(&dir)?;
/// let path = dir.join("lines.ply");
/// let mut file = std::fs::File::create(&path)?;
/// write_lines_to(&mut file, &lines, LinesFormat::Ply, PlyEncoding::BinaryLittleEndian)?;
/// let back = read_lines(&path, None)?;
/// assert_eq!(back.lines.len(), lines.lines.len());
/// # Ok(())
/// # }
/// ```
///
/// # Errors
/// [`Error::InvalidInput`] for an unknown extension, [`Error::Io`] naming the file,
/// [`Error::Parse`] naming the file and the position of a fault.
pub fn read_lines(path: &Path, format: Option<LinesFormat>) -> Result<FeatureLines> {
    let format = LinesFormat::resolve(path, format)?;
    let bytes = std::fs::read(path).map_err(|e| Error::io(path, e))?;
    parse_lines(&bytes, format, path)
}

/// Parses feature lines in `format` from bytes held in memory; `name` labels errors.
///
/// # Errors
/// [`Error::Parse`] naming `name` and the position of the fault.
pub fn parse_lines(bytes: &[u8], format: LinesFormat, name: &Path) -> Result<FeatureLines> {
    match format {
        LinesFormat::Obj => parse_lines_obj(bytes, name),
        LinesFormat::Json => parse_lines_json(bytes, name),
        LinesFormat::Ply => parse_lines_ply(bytes, name),
    }
}

/// Writes feature lines in `format` to any writer (buffer it: the writers issue many small
/// writes); PLY uses `ply_encoding`.
///
/// # Errors
/// Whatever the writer returns.
pub fn write_lines_to<W: Write>(
    out: W,
    lines: &FeatureLines,
    format: LinesFormat,
    ply_encoding: PlyEncoding,
) -> std::io::Result<()> {
    match format {
        LinesFormat::Obj => write_lines_obj(out, lines),
        LinesFormat::Json => write_lines_json(out, lines),
        LinesFormat::Ply => write_lines_ply(out, lines, ply_encoding),
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
            out.write_all(b"# strength ")?;
            write_f64(&mut out, line.strength)?;
            out.write_all(b" curvature_integral ")?;
            write_f64(&mut out, line.curvature_integral)?;
            out.write_all(b"\nl")?;
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
    let mut polylines: Vec<ObjPolyline> = Vec::new();
    let mut kind = LineKind::Ridge;
    let mut crease = false;
    let mut strengths: Option<[f64; 2]> = None;
    let mut faces = 0usize;
    for (line, text) in Lines::new(bytes) {
        if let Some(comment) = text.trim_ascii_start().strip_prefix(b"# strength ") {
            strengths = strength_comment(comment);
            continue;
        }
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
                polylines.push(ObjPolyline {
                    line,
                    kind,
                    crease,
                    strengths: strengths.take().unwrap_or_default(),
                    indices,
                });
            }
            Some(b"f") => faces += 1,
            Some(keyword) if !OBJ_KEYWORDS.contains(&keyword) => {
                return Err(source.at_line(
                    line,
                    format!(
                        "'{}' is not an OBJ record: not a feature-line file",
                        show(keyword)
                    ),
                ));
            }
            _ => {}
        }
    }
    if polylines.is_empty() && (faces > 0 || !positions.is_empty()) {
        return Err(source.whole(format!(
            "no polylines ('l' records) among {} vertices and {faces} faces: a mesh, not \
             feature lines",
            positions.len()
        )));
    }

    let mut lines = Vec::with_capacity(polylines.len());
    for ObjPolyline {
        line,
        kind,
        crease,
        strengths: [strength, curvature_integral],
        mut indices,
    } in polylines
    {
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
        lines.push(read_line(
            kind,
            crease,
            points,
            closed,
            strength,
            curvature_integral,
        ));
    }
    Ok(FeatureLines { lines })
}

/// An OBJ `l` record before its indices are resolved.
struct ObjPolyline {
    line: usize,
    kind: LineKind,
    crease: bool,
    /// Strength and curvature integral, from the comment before the record.
    strengths: [f64; 2],
    indices: Vec<usize>,
}

/// The records of the OBJ format (geometry, grouping, display and free-form ones): anything
/// else in a lines file means it is not OBJ at all.
const OBJ_KEYWORDS: [&[u8]; 34] = [
    b"v",
    b"vt",
    b"vn",
    b"vp",
    b"f",
    b"l",
    b"p",
    b"o",
    b"g",
    b"s",
    b"mg",
    b"usemtl",
    b"mtllib",
    b"cstype",
    b"deg",
    b"bmat",
    b"step",
    b"curv",
    b"curv2",
    b"surf",
    b"parm",
    b"trim",
    b"hole",
    b"scrv",
    b"sp",
    b"end",
    b"con",
    b"lod",
    b"bevel",
    b"c_interp",
    b"d_interp",
    b"shadow_obj",
    b"trace_obj",
    b"ctech",
];

/// The numbers of a `# strength <T> curvature_integral <I>` comment (`None` when it does not
/// have that form: it is then an ordinary comment).
fn strength_comment(rest: &[u8]) -> Option<[f64; 2]> {
    let mut tokens = rest
        .split(|&b| super::text::is_space(b))
        .filter(|t| !t.is_empty());
    let strength = super::text::parse_f64(tokens.next()?)?;
    if tokens.next()? != b"curvature_integral" {
        return None;
    }
    let integral = super::text::parse_f64(tokens.next()?)?;
    Some([strength, integral])
}

/// A line read back from a file (no mesh locations; the length from its points).
fn read_line(
    kind: LineKind,
    crease: bool,
    points: Vec<Vec3>,
    closed: bool,
    strength: f64,
    curvature_integral: f64,
) -> FeatureLine {
    FeatureLine {
        kind,
        length: polyline_length(&points, closed),
        points,
        locations: Vec::new(),
        closed,
        curvature_integral,
        strength,
        crease,
    }
}

/// The kind and crease flag of a class (the PLY `kind`, the JSON `kind`).
fn of_class(class: usize) -> (LineKind, bool) {
    match class {
        0 => (LineKind::Ridge, false),
        1 => (LineKind::Valley, false),
        2 => (LineKind::Ridge, true),
        _ => (LineKind::Valley, true),
    }
}

#[derive(Deserialize)]
struct JsonFileIn {
    lines: Vec<JsonLineIn>,
}

#[derive(Deserialize)]
struct JsonLineIn {
    kind: String,
    #[serde(default)]
    closed: bool,
    points: Vec<[f64; 3]>,
    #[serde(default)]
    curvature_integral: f64,
    #[serde(default)]
    strength: f64,
}

/// Parses feature lines from JSON (as [`write_lines_json`] writes them); `name` labels
/// errors.
///
/// # Errors
/// [`Error::Parse`] naming `name` and the line of the fault, or the line of the file whose
/// `kind` is unknown.
pub fn parse_lines_json(bytes: &[u8], name: &Path) -> Result<FeatureLines> {
    let source = Source::new(name);
    if bytes.is_empty() {
        return Err(source.whole("empty file"));
    }
    let file: JsonFileIn = serde_json::from_slice(bytes).map_err(|e| {
        // serde_json's message ends with the position, which the error gives already.
        let message = e.to_string();
        let message = match message.rfind(" at line ") {
            Some(at) => format!("{} (column {})", &message[..at], e.column()),
            None => message,
        };
        source.at_line(e.line(), format!("not a feature-line JSON file: {message}"))
    })?;
    let mut lines = Vec::with_capacity(file.lines.len());
    for (i, line) in file.lines.into_iter().enumerate() {
        let Some(class) = KIND_NAMES.iter().position(|&k| k == line.kind) else {
            return Err(source.whole(format!(
                "line {i} of \"lines\": unknown kind '{}' (known: {})",
                line.kind,
                KIND_NAMES.join(", ")
            )));
        };
        let (kind, crease) = of_class(class);
        let points = line.points.into_iter().map(Vec3::from).collect();
        lines.push(read_line(
            kind,
            crease,
            points,
            line.closed,
            line.strength,
            line.curvature_integral,
        ));
    }
    Ok(FeatureLines { lines })
}

/// Parses feature lines from a PLY file of vertices and edges (as [`write_lines_ply`] writes
/// them, in any encoding); `name` labels errors.
///
/// # Errors
/// [`Error::Parse`] naming `name` and the position of the fault.
pub fn parse_lines_ply(bytes: &[u8], name: &Path) -> Result<FeatureLines> {
    let source = Source::new(name);
    if bytes.is_empty() {
        return Err(source.whole("empty file"));
    }
    let ply = parse_edges(bytes, source)?;
    if let Some((i, e)) = ply
        .edges
        .iter()
        .enumerate()
        .find(|(_, e)| e.kind.is_some_and(|k| !(0..4).contains(&k)))
    {
        return Err(source.whole(format!(
            "edge {i} has kind {} (known: 0 ridge, 1 valley, 2 crease ridge, 3 crease valley)",
            e.kind.unwrap_or_default()
        )));
    }
    let mut chains: Vec<(usize, FeatureLine)> = Vec::new();
    for class in 0..4 {
        let edges: Vec<(usize, &EdgeRecord)> = ply
            .edges
            .iter()
            .enumerate()
            .filter(|(_, e)| e.kind.unwrap_or(0) as usize == class)
            .collect();
        let (kind, crease) = of_class(class);
        for (first_edge, indices, closed) in chain_edges(&edges, ply.positions.len()) {
            let record = ply.edges[first_edge];
            let points = indices
                .iter()
                .map(|&v| Vec3::from(ply.positions[v as usize]))
                .collect();
            let line = read_line(
                kind,
                crease,
                points,
                closed,
                record.strength.unwrap_or(0.0),
                record.curvature_integral.unwrap_or(0.0),
            );
            chains.push((first_edge, line));
        }
    }
    chains.sort_by_key(|&(first_edge, _)| first_edge);
    Ok(FeatureLines {
        lines: chains.into_iter().map(|(_, l)| l).collect(),
    })
}

/// Chains `edges` (file index, record) into polylines: paths between vertices where other
/// than two edges meet, then loops. Returns, per polyline, the file index of its first edge,
/// its vertices and whether it is closed. A path runs from its lowest-numbered end; a loop
/// starts at the first vertex of its first edge and follows that edge.
fn chain_edges(
    edges: &[(usize, &EdgeRecord)],
    vertex_count: usize,
) -> Vec<(usize, Vec<u32>, bool)> {
    // Edges at each vertex, compressed (offsets, then edge numbers into `edges`).
    let mut start = vec![0usize; vertex_count + 1];
    for (_, e) in edges {
        for v in e.ends {
            start[v as usize + 1] += 1;
        }
    }
    for v in 0..vertex_count {
        start[v + 1] += start[v];
    }
    let mut fill = start.clone();
    let mut at = vec![0usize; 2 * edges.len()];
    for (k, (_, e)) in edges.iter().enumerate() {
        for v in e.ends {
            at[fill[v as usize]] = k;
            fill[v as usize] += 1;
        }
    }
    let degree = |v: u32| start[v as usize + 1] - start[v as usize];
    let mut used = vec![false; edges.len()];
    let other = |k: usize, v: u32| {
        let [a, b] = edges[k].1.ends;
        if a == v { b } else { a }
    };
    // Follows unused edges from `v` over `k` while the path goes through vertices of degree 2.
    let follow = |mut v: u32, mut k: usize, used: &mut Vec<bool>| {
        let mut path = vec![v];
        let mut lowest_edge = edges[k].0;
        loop {
            used[k] = true;
            lowest_edge = lowest_edge.min(edges[k].0);
            v = other(k, v);
            path.push(v);
            if degree(v) != 2 {
                break;
            }
            match at[start[v as usize]..start[v as usize + 1]]
                .iter()
                .find(|&&next| !used[next])
            {
                Some(&next) => k = next,
                None => break,
            }
        }
        (lowest_edge, path)
    };
    let mut polylines = Vec::new();
    for v in 0..vertex_count as u32 {
        if degree(v) == 2 || degree(v) == 0 {
            continue;
        }
        for &k in &at[start[v as usize]..start[v as usize + 1]] {
            if !used[k] {
                let (first, path) = follow(v, k, &mut used);
                polylines.push((first, path, false));
            }
        }
    }
    for k in 0..edges.len() {
        if !used[k] {
            let (first, mut path) = follow(edges[k].1.ends[0], k, &mut used);
            // Around a loop the walk ends where it began.
            let closed = path.len() >= 4 && path.first() == path.last();
            if closed {
                path.pop();
            }
            polylines.push((first, path, closed));
        }
    }
    polylines
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
         property uchar kind\nproperty double strength\nproperty double curvature_integral\n\
         end_header\n",
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
            out.f64(line.strength)?;
            out.f64(line.curvature_integral)?;
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
            "x: file: line 0 of \"lines\": unknown kind 'bump' (known: ridge, valley, \
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
