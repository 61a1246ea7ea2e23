//! Feature lines as one JSON object: counts per kind and every line with its attributes.

use std::io::Write;
use std::path::Path;

use serde::{Deserialize, Serialize};

use super::{KIND_NAMES, class_counts, class_of, of_class, read_line};
use crate::error::Result;
use crate::io::text::Source;
use crate::lines::FeatureLines;
use crate::mesh::Vec3;

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
/// [`Error::Parse`](crate::error::Error::Parse) naming `name` and the line of the fault, or the line of the file whose
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
            crate::io::check_finite(*x)?;
        }
        for x in [l.length, l.curvature_integral, l.strength] {
            crate::io::check_finite(x)?;
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
