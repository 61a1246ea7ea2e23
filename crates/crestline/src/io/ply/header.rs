//! The PLY header: elements, their properties and the roles crestline reads them for.

use super::{Lines, PlyEncoding, Result, Source, show};
use crate::io::text::parse_count;

/// A scalar type of the format.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    pub(super) fn from_name(name: &[u8]) -> Option<Scalar> {
        Some(match name {
            b"char" | b"int8" => Scalar::I8,
            b"uchar" | b"uint8" => Scalar::U8,
            b"short" | b"int16" => Scalar::I16,
            b"ushort" | b"uint16" => Scalar::U16,
            b"int" | b"int32" => Scalar::I32,
            b"uint" | b"uint32" => Scalar::U32,
            b"float" | b"float32" => Scalar::F32,
            b"double" | b"float64" => Scalar::F64,
            _ => return None,
        })
    }

    /// The type's name in the format's definition.
    pub(super) fn name(self) -> &'static str {
        match self {
            Scalar::I8 => "char",
            Scalar::U8 => "uchar",
            Scalar::I16 => "short",
            Scalar::U16 => "ushort",
            Scalar::I32 => "int",
            Scalar::U32 => "uint",
            Scalar::F32 => "float",
            Scalar::F64 => "double",
        }
    }

    pub(super) fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }

    pub(super) fn is_integer(self) -> bool {
        !matches!(self, Scalar::F32 | Scalar::F64)
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Kind {
    Scalar(Scalar),
    List { count: Scalar, item: Scalar },
}

/// What the reader does with a property.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Role {
    Skip,
    /// Vertex coordinate 0, 1 or 2.
    Coordinate(usize),
    /// Polygon corners (face element).
    Polygon,
    /// Triangle strips with -1 restarts (tristrips element).
    Strips,
}

#[derive(Debug, Clone)]
pub(super) struct Property {
    pub(super) name: String,
    pub(super) kind: Kind,
    pub(super) role: Role,
}

#[derive(Debug, Clone)]
pub(super) struct Element {
    pub(super) name: String,
    pub(super) count: usize,
    pub(super) properties: Vec<Property>,
}

impl Element {
    pub(super) fn is_vertex(&self) -> bool {
        self.name == "vertex"
    }

    /// At most how many of its records `bytes` bytes of the body can hold: every value takes
    /// its size in binary, and at least a digit and a separator in ascii (bar the last). Bounds
    /// what is reserved ahead, whatever the header claims.
    pub(super) fn records_in(&self, bytes: usize, encoding: PlyEncoding) -> usize {
        let smallest: usize = self
            .properties
            .iter()
            .map(|p| match (encoding, p.kind) {
                (PlyEncoding::Ascii, _) => 2,
                (_, Kind::Scalar(s)) => s.size(),
                (_, Kind::List { count, .. }) => count.size(),
            })
            .sum();
        self.count.min(bytes / smallest.max(1) + 1)
    }

    /// Bytes per record when every property is a scalar.
    pub(super) fn fixed_size(&self) -> Option<usize> {
        self.properties
            .iter()
            .map(|p| match p.kind {
                Kind::Scalar(s) => Some(s.size()),
                Kind::List { .. } => None,
            })
            .sum()
    }
}

#[derive(Debug)]
pub(super) struct Header {
    pub(super) encoding: PlyEncoding,
    pub(super) elements: Vec<Element>,
    pub(super) vertex_count: usize,
    /// Byte offset and line number where the body starts.
    pub(super) body_offset: usize,
    pub(super) body_line: usize,
}

/// An `element` line after its keyword: a name and a count.
fn parse_element<'a>(mut tokens: impl Iterator<Item = &'a [u8]>) -> Result<Element, String> {
    let (Some(name), Some(count)) = (tokens.next(), tokens.next()) else {
        return Err("element needs a name and a count".into());
    };
    let count = parse_count(count, "element count")?;
    Ok(Element {
        name: String::from_utf8_lossy(name).into_owned(),
        count,
        properties: Vec::new(),
    })
}

/// A `property` line after its keyword: a scalar type or `list` with a count and an item
/// type, then a name.
fn parse_property<'a>(mut tokens: impl Iterator<Item = &'a [u8]>) -> Result<Property, String> {
    let scalar = |token: Option<&[u8]>| {
        let token = token.unwrap_or_default();
        Scalar::from_name(token).ok_or_else(|| format!("unknown property type '{}'", show(token)))
    };
    let first = tokens.next();
    let kind = if first == Some(b"list") {
        let count = scalar(tokens.next())?;
        let item = scalar(tokens.next())?;
        if !count.is_integer() {
            return Err("a list's count type must be an integer type".into());
        }
        Kind::List { count, item }
    } else {
        Kind::Scalar(scalar(first)?)
    };
    let Some(name) = tokens.next() else {
        return Err("property without a name".into());
    };
    Ok(Property {
        name: String::from_utf8_lossy(name).into_owned(),
        kind,
        role: Role::Skip,
    })
}

pub(super) fn parse_header(bytes: &[u8], source: Source<'_>) -> Result<Header> {
    let malformed =
        |line: usize, message: String| source.at_line(line, format!("malformed header: {message}"));
    let mut lines = Lines::new(bytes);
    let first = lines.next();
    // A header whose lines end in a lone CR (classic Mac OS): its `end_header` line ends
    // there too, and an LF after it is the first byte of a binary body.
    let lone_cr = lines.offset() > 0 && bytes[lines.offset() - 1] == b'\r';
    match first {
        Some((_, first)) if first.trim_ascii() == b"ply" => {}
        Some((_, first)) => {
            return Err(source.at_line(
                1,
                format!(
                    "not a PLY file: the first line is '{}', expected 'ply'",
                    show(first.trim_ascii())
                ),
            ));
        }
        None => return Err(source.whole("empty file")),
    }

    let mut encoding = None;
    let mut elements: Vec<Element> = Vec::new();
    let mut end = None;
    for (line, text) in lines.by_ref() {
        // Header lines are ascii; comments may hold anything, so `#` is not special here.
        let mut tokens = text
            .split(|&b| crate::io::text::is_space(b))
            .filter(|t| !t.is_empty());
        let Some(keyword) = tokens.next() else {
            continue;
        };
        match keyword {
            b"comment" | b"obj_info" => {}
            b"format" => {
                let name = tokens.next().unwrap_or_default();
                encoding = Some(match name {
                    b"ascii" => PlyEncoding::Ascii,
                    b"binary_little_endian" => PlyEncoding::BinaryLittleEndian,
                    b"binary_big_endian" => PlyEncoding::BinaryBigEndian,
                    _ => {
                        return Err(malformed(line, format!("unknown format '{}'", show(name))));
                    }
                });
            }
            b"element" => {
                elements.push(parse_element(tokens).map_err(|m| malformed(line, m))?);
            }
            b"property" => {
                let Some(element) = elements.last_mut() else {
                    return Err(malformed(line, "property before any element".into()));
                };
                let property = parse_property(tokens).map_err(|m| malformed(line, m))?;
                element.properties.push(property);
            }
            b"end_header" => {
                end = Some(line);
                break;
            }
            other => {
                return Err(malformed(
                    line,
                    format!("unknown keyword '{}'", show(other)),
                ));
            }
        }
    }
    let Some(end_line) = end else {
        return Err(malformed(
            lines.number().max(1),
            "no end_header line".into(),
        ));
    };
    let Some(encoding) = encoding else {
        return Err(malformed(end_line, "no format line".into()));
    };
    let vertex_count = assign_roles(&mut elements).map_err(|m| malformed(end_line, m))?;
    let mut body_offset = lines.offset();
    if lone_cr && encoding != PlyEncoding::Ascii && bytes[..body_offset].ends_with(b"\r\n") {
        body_offset -= 1;
    }
    Ok(Header {
        encoding,
        elements,
        vertex_count,
        body_offset,
        // An empty body: errors point at the last line, end_header.
        body_line: if lines.offset() < bytes.len() {
            end_line + 1
        } else {
            end_line
        },
    })
}

/// Marks the properties the reader keeps; returns the number of vertices.
pub(super) fn assign_roles(elements: &mut [Element]) -> Result<usize, String> {
    let mut vertex_count = None;
    for element in elements.iter_mut() {
        let is_index_list = |p: &Property| {
            matches!(p.kind, Kind::List { .. })
                && (p.name == "vertex_indices" || p.name == "vertex_index")
        };
        match element.name.as_str() {
            "vertex" => {
                if vertex_count.is_some() {
                    return Err("two vertex elements".into());
                }
                vertex_count = Some(element.count);
                for (axis, name) in ["x", "y", "z"].into_iter().enumerate() {
                    let Some(p) = element.properties.iter_mut().find(|p| p.name == name) else {
                        return Err(format!("the vertex element has no '{name}' property"));
                    };
                    if !matches!(p.kind, Kind::Scalar(_)) {
                        return Err(format!("vertex property '{name}' is a list"));
                    }
                    p.role = Role::Coordinate(axis);
                }
            }
            "face" => {
                let Some(p) = element.properties.iter_mut().find(|p| is_index_list(p)) else {
                    return Err("the face element has no 'vertex_indices' list".into());
                };
                p.role = Role::Polygon;
            }
            "tristrips" => {
                let position = element
                    .properties
                    .iter()
                    .position(is_index_list)
                    .or_else(|| {
                        element
                            .properties
                            .iter()
                            .position(|p| matches!(p.kind, Kind::List { .. }))
                    });
                let Some(i) = position else {
                    return Err("the tristrips element has no list property".into());
                };
                element.properties[i].role = Role::Strips;
            }
            _ => {}
        }
        for p in &element.properties {
            if let (Role::Polygon | Role::Strips, Kind::List { item, .. }) = (p.role, p.kind) {
                if !item.is_integer() {
                    return Err(format!(
                        "the {} indices '{}' must have an integer type",
                        element.name, p.name
                    ));
                }
            }
        }
    }
    let count = vertex_count.ok_or("no vertex element")?;
    if count > u32::MAX as usize {
        return Err(format!(
            "{count} vertices is more than the 2^32-1 crestline indexes"
        ));
    }
    Ok(count)
}
