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

mod json;
mod obj;
mod ply;
#[cfg(test)]
mod tests;

use std::io::Write;
use std::path::Path;

use super::ply::PlyEncoding;
use crate::error::{Error, Result};
use crate::lines::{FeatureLine, FeatureLines, LineKind};
use crate::mesh::Vec3;

pub use json::{parse_lines_json, write_lines_json};
pub use obj::{parse_lines_obj, read_lines_obj, write_lines_obj};
pub use ply::{parse_lines_ply, write_lines_ply};

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
pub(super) fn class_of(line: &FeatureLine) -> usize {
    match (line.kind, line.crease) {
        (LineKind::Ridge, false) => 0,
        (LineKind::Valley, false) => 1,
        (LineKind::Ridge, true) => 2,
        (LineKind::Valley, true) => 3,
    }
}

/// JSON `kind` of each class.
pub(super) const KIND_NAMES: [&str; 4] = ["ridge", "valley", "crease-ridge", "crease-valley"];
/// OBJ group of each class.
pub(super) const GROUP_NAMES: [&str; 4] = ["ridges", "valleys", "crease-ridges", "crease-valleys"];

/// Lines per class.
pub(super) fn class_counts(lines: &FeatureLines) -> [usize; 4] {
    let mut counts = [0; 4];
    for l in &lines.lines {
        counts[class_of(l)] += 1;
    }
    counts
}

/// A line read back from a file (no mesh locations; the length from its points).
pub(super) fn read_line(
    kind: LineKind,
    crease: bool,
    points: Vec<Vec3>,
    closed: bool,
    strength: f64,
    curvature_integral: f64,
) -> FeatureLine {
    FeatureLine {
        curvature_integral,
        strength,
        crease,
        ..FeatureLine::new(kind, points, closed)
    }
}

/// The kind and crease flag of a class (the PLY `kind`, the JSON `kind`).
pub(super) fn of_class(class: usize) -> (LineKind, bool) {
    match class {
        0 => (LineKind::Ridge, false),
        1 => (LineKind::Valley, false),
        2 => (LineKind::Ridge, true),
        _ => (LineKind::Valley, true),
    }
}
