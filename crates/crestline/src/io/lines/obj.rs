//! Feature lines as OBJ polylines: `o` groups per kind, a `# strength` comment per line.

use std::io::Write;
use std::path::Path;

use super::{GROUP_NAMES, class_counts, class_of, read_line};
use crate::error::{Error, Result};
use crate::io::text::{Lines, Source, Tokens, parse_i64, show, strip_bom, vertex};
use crate::io::{write_f64, write_xyz};
use crate::lines::{FeatureLine, FeatureLines, LineKind};
use crate::mesh::Vec3;

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
                write_xyz(&mut out, p)?;
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
                let indices = polyline_indices(tokens, positions.len())
                    .map_err(|m| source.at_line(line, m))?;
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

    let lines = resolve(polylines, &positions, source)?;
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
        .split(|&b| crate::io::text::is_space(b))
        .filter(|t| !t.is_empty());
    let strength = crate::io::text::parse_f64(tokens.next()?)?;
    if tokens.next()? != b"curvature_integral" {
        return None;
    }
    let integral = crate::io::text::parse_f64(tokens.next()?)?;
    Some([strength, integral])
}

/// The 0-based vertex indices of an `l` record's `tokens`, `read` vertices having been read
/// so far (relative indices count back from there).
fn polyline_indices(tokens: Tokens<'_>, read: usize) -> std::result::Result<Vec<usize>, String> {
    let mut indices = Vec::new();
    for token in tokens {
        let digits = token.split(|&b| b == b'/').next().unwrap_or_default();
        let i = parse_i64(digits).ok_or_else(|| {
            format!(
                "non-numeric token '{}' where a vertex index was expected",
                show(token)
            )
        })?;
        let index = match i {
            0 => Err("vertex index 0 (OBJ indices start at 1)".to_string()),
            i if i > 0 => Ok((i - 1) as usize),
            i => usize::try_from(read as i64 + i).map_err(|_| {
                format!(
                    "relative vertex index {i} reaches before the first vertex \
                     (only {read} read so far)"
                )
            }),
        }?;
        indices.push(index);
    }
    if indices.len() < 2 {
        return Err(format!(
            "polyline with {} vertices (at least 2 needed)",
            indices.len()
        ));
    }
    Ok(indices)
}

/// The polylines with their indices resolved to points, once every vertex is known.
fn resolve(
    polylines: Vec<ObjPolyline>,
    positions: &[[f64; 3]],
    source: Source<'_>,
) -> Result<Vec<FeatureLine>> {
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
    Ok(lines)
}
