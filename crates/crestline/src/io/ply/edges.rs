//! The `edge` element of a PLY file, as feature-line files hold it (see [`crate::io::lines`]).
//!
//! Reads the vertex positions and, from the element named `edge`, the scalar properties
//! `vertex1` and `vertex2` (required, integer) and `kind`, `strength` and
//! `curvature_integral` (optional). Every other element and property is skipped, in all three
//! encodings, with the header parsed and checked as for meshes. Errors name the file and give
//! a line (header, ascii body) or a byte offset (binary body).

use super::{Ascii, Binary, Fault, Header, Kind, PlyEncoding, Role, Scalar, Values, parse_header};
use crate::error::Result;
use crate::io::text::{Source, Words};

/// One record of the `edge` element.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(in crate::io) struct EdgeRecord {
    /// `vertex1` and `vertex2`, checked against the vertex count.
    pub ends: [u32; 2],
    /// `kind`, when the element has it.
    pub kind: Option<i64>,
    /// `strength`, when the element has it.
    pub strength: Option<f64>,
    /// `curvature_integral`, when the element has it.
    pub curvature_integral: Option<f64>,
}

/// Vertex positions and edges of a PLY file.
#[derive(Debug, Clone, Default, PartialEq)]
pub(in crate::io) struct PlyEdges {
    pub positions: Vec<[f64; 3]>,
    pub edges: Vec<EdgeRecord>,
}

/// What an `edge` property is read into.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum EdgeField {
    End(usize),
    Kind,
    Strength,
    CurvatureIntegral,
    Skip,
}

fn edge_field(name: &str) -> EdgeField {
    match name {
        "vertex1" => EdgeField::End(0),
        "vertex2" => EdgeField::End(1),
        "kind" => EdgeField::Kind,
        "strength" => EdgeField::Strength,
        "curvature_integral" => EdgeField::CurvatureIntegral,
        _ => EdgeField::Skip,
    }
}

/// Parses the vertices and edges of a PLY file held in memory.
///
/// # Errors
/// A malformed header or body, a file without an `edge` element or whose edges lack
/// `vertex1`/`vertex2`, an index out of range, a NaN or infinite coordinate.
pub(in crate::io) fn parse_edges(bytes: &[u8], source: Source<'_>) -> Result<PlyEdges> {
    let header = parse_header(bytes, source)?;
    let edge = header.elements.iter().find(|e| e.name == "edge");
    let Some(edge) = edge else {
        return Err(source.whole(
            "no 'edge' element: not a feature-line file (crestline writes the lines as \
             vertices and edges)",
        ));
    };
    for end in ["vertex1", "vertex2"] {
        let property = edge.properties.iter().find(|p| p.name == end);
        if !matches!(property.map(|p| p.kind), Some(Kind::Scalar(s)) if s.is_integer()) {
            return Err(source.whole(format!("the edge element has no integer '{end}' property")));
        }
    }
    let offset = header.body_offset.min(bytes.len());
    match header.encoding {
        PlyEncoding::Ascii => {
            let mut values = Ascii {
                words: Words::new(bytes, header.body_offset, header.body_line),
                remaining_hint: bytes.len() - offset,
            };
            walk(&header, &mut values, source)
        }
        PlyEncoding::BinaryLittleEndian => walk(
            &header,
            &mut Binary::<false> {
                data: bytes,
                position: offset,
                last: offset,
            },
            source,
        ),
        PlyEncoding::BinaryBigEndian => walk(
            &header,
            &mut Binary::<true> {
                data: bytes,
                position: offset,
                last: offset,
            },
            source,
        ),
    }
}

/// Walks every record of every element, keeping positions and edges.
fn walk<V: Values>(header: &Header, values: &mut V, source: Source<'_>) -> Result<PlyEdges> {
    let vertex_count = header.vertex_count;
    let mut out = PlyEdges::default();
    for element in &header.elements {
        let is_edge = element.name == "edge";
        let fault = |values: &V, record: usize, fault: Fault| {
            source.at(values.location(), fault.message(element, record))
        };
        // A record without properties holds nothing (see the mesh reader).
        if element.properties.is_empty() {
            continue;
        }
        for record in 0..element.count {
            let mut point = [0.0f64; 3];
            let mut edge = EdgeRecord::default();
            for property in &element.properties {
                let read = match property.kind {
                    Kind::Scalar(ty) => read_scalar(
                        values,
                        ty,
                        property.role,
                        is_edge.then(|| edge_field(&property.name)),
                        &mut point,
                        &mut edge,
                        vertex_count,
                    ),
                    Kind::List { count, item } => match values.int(count) {
                        // Read as no values, a negative length would misplace every value
                        // after it (in binary, silently).
                        Ok(n) if n < 0 => Err(Read::NegativeLength(n)),
                        Ok(n) => values
                            .skip(item, usize::try_from(n).unwrap_or(usize::MAX))
                            .map_err(Read::Fault),
                        Err(f) => Err(Read::Fault(f)),
                    },
                };
                match read {
                    Ok(()) => {}
                    Err(Read::Fault(f)) => return Err(fault(values, record, f)),
                    Err(Read::NegativeLength(n)) => {
                        return Err(source.at(
                            values.location(),
                            format!("{} {record}: negative list length {n}", element.name),
                        ));
                    }
                    Err(Read::OutOfRange(i)) => {
                        return Err(source.at(
                            values.location(),
                            format!(
                                "edge {record}: vertex index {i} out of range (the file has \
                                 {vertex_count} vertices)"
                            ),
                        ));
                    }
                }
            }
            if element.is_vertex() {
                if let Some(axis) = point.iter().position(|c| !c.is_finite()) {
                    return Err(source.at(
                        values.location(),
                        format!(
                            "vertex {record} has a NaN or infinite {} coordinate",
                            ["x", "y", "z"][axis]
                        ),
                    ));
                }
                out.positions.push(point);
            } else if is_edge {
                out.edges.push(edge);
            }
        }
    }
    Ok(out)
}

/// Why one value could not be used.
enum Read {
    Fault(Fault),
    OutOfRange(i64),
    NegativeLength(i64),
}

impl From<Fault> for Read {
    fn from(f: Fault) -> Self {
        Read::Fault(f)
    }
}

/// Reads one scalar property into the vertex (`role`) or the edge (`field`), or skips it.
fn read_scalar<V: Values>(
    values: &mut V,
    ty: Scalar,
    role: Role,
    field: Option<EdgeField>,
    point: &mut [f64; 3],
    edge: &mut EdgeRecord,
    vertex_count: usize,
) -> std::result::Result<(), Read> {
    match (role, field) {
        (Role::Coordinate(axis), None) => point[axis] = values.float(ty)?,
        (_, Some(EdgeField::End(k))) => {
            let i = values.int(ty)?;
            match u32::try_from(i) {
                Ok(v) if (v as usize) < vertex_count => edge.ends[k] = v,
                _ => return Err(Read::OutOfRange(i)),
            }
        }
        (_, Some(EdgeField::Kind)) => edge.kind = Some(values.int(ty)?),
        (_, Some(EdgeField::Strength)) => edge.strength = Some(values.float(ty)?),
        (_, Some(EdgeField::CurvatureIntegral)) => {
            edge.curvature_integral = Some(values.float(ty)?)
        }
        _ => values.skip(ty, 1)?,
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    fn error(bytes: &[u8]) -> String {
        parse_edges(bytes, Source::new(Path::new("l.ply")))
            .unwrap_err()
            .to_string()
    }

    const HEADER: &str = "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\n\
        property float y\nproperty float z\nelement edge 1\nproperty int vertex1\n\
        property int vertex2\nproperty list int float extra\nend_header\n";

    #[test]
    fn negative_list_lengths_are_errors() {
        let body = "0 0 0\n1 0 0\n0 1 -2 7\n";
        assert_eq!(
            error(format!("{HEADER}{body}").as_bytes()),
            "l.ply: line 14: edge 0: negative list length -2"
        );
        // In binary the values after it would have been read from the wrong place.
        let mut bytes = HEADER.replace("ascii", "binary_little_endian").into_bytes();
        let header = bytes.len();
        for x in [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0] {
            bytes.extend_from_slice(&x.to_le_bytes());
        }
        for i in [0i32, 1, -2] {
            bytes.extend_from_slice(&i.to_le_bytes());
        }
        assert_eq!(
            error(&bytes),
            format!(
                "l.ply: byte {}: edge 0: negative list length -2",
                header + 24 + 8
            )
        );
        let ok = format!("{HEADER}0 0 0\n1 0 0\n0 1 2 7 8\n");
        let edges = parse_edges(ok.as_bytes(), Source::new(Path::new("l.ply"))).unwrap();
        assert_eq!(edges.edges[0].ends, [0, 1]);
    }
}
