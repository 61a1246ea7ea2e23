//! Stanford PLY meshes: ascii, binary little endian and binary big endian.
//!
//! Reference: G. Turk, "The PLY Polygon File Format" (1994),
//! <https://paulbourke.net/dataformats/ply/>.
//!
//! Reading: the header declares elements, each with a count and a list of scalar or list
//! properties. From the `vertex` element only `x`, `y`, `z` are kept (any scalar type; the
//! sized aliases `int8` ... `float64` are accepted too). From `face` the list named
//! `vertex_indices` (or `vertex_index`) is kept, with any integer count and index types;
//! polygons are fan-triangulated. A `tristrips` element holds triangle strips in one list
//! (`vertex_indices`, or its first list): `-1` restarts a strip, every second triangle has
//! its winding flipped to keep the orientation, and triangles with a repeated index (the
//! stitching between strips) are dropped. Every other element and property is skipped, in
//! all three encodings.
//!
//! Errors give a line for the header and the ascii body, and a byte offset in the file for
//! the binary body.
//!
//! Writing: [`PlyWriter`] writes `x y z` as `double` (exact), extra per-vertex scalar
//! properties as `float` or `double`, and one `face` element of triangles with a `uchar`
//! count and `int` indices.
//!
//! Limits: 64-bit integer types (not in the format's definition) are not accepted; list
//! properties other than the face indices must have integer counts.

pub(super) mod edges;

use std::borrow::Cow;
use std::io::Write;
use std::path::Path;

use super::text::{Lines, Source, Words, parse_f64, parse_i64, show};
use super::{MeshData, push_fan, write_f64};
use crate::error::{Error, Location, Result};
use crate::mesh::TriMesh;

/// How the body of a PLY file is encoded.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum PlyEncoding {
    /// Text, one element record per line.
    Ascii,
    /// Binary, least significant byte first (what nearly every tool writes).
    BinaryLittleEndian,
    /// Binary, most significant byte first.
    BinaryBigEndian,
}

impl PlyEncoding {
    pub(super) fn header_name(self) -> &'static str {
        match self {
            PlyEncoding::Ascii => "ascii",
            PlyEncoding::BinaryLittleEndian => "binary_little_endian",
            PlyEncoding::BinaryBigEndian => "binary_big_endian",
        }
    }
}

// ---------------------------------------------------------------------------------------
// Header
// ---------------------------------------------------------------------------------------

/// A scalar type of the format.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Scalar {
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
    fn from_name(name: &[u8]) -> Option<Scalar> {
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

    fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }

    fn is_integer(self) -> bool {
        !matches!(self, Scalar::F32 | Scalar::F64)
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    Scalar(Scalar),
    List { count: Scalar, item: Scalar },
}

/// What the reader does with a property.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Role {
    Skip,
    /// Vertex coordinate 0, 1 or 2.
    Coordinate(usize),
    /// Polygon corners (face element).
    Polygon,
    /// Triangle strips with -1 restarts (tristrips element).
    Strips,
}

#[derive(Debug, Clone)]
struct Property {
    name: String,
    kind: Kind,
    role: Role,
}

#[derive(Debug, Clone)]
struct Element {
    name: String,
    count: usize,
    properties: Vec<Property>,
}

impl Element {
    fn is_vertex(&self) -> bool {
        self.name == "vertex"
    }

    /// At most how many of its records `bytes` bytes of the body can hold: every value takes
    /// its size in binary, and at least a digit and a separator in ascii (bar the last). Bounds
    /// what is reserved ahead, whatever the header claims.
    fn records_in(&self, bytes: usize, encoding: PlyEncoding) -> usize {
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
    fn fixed_size(&self) -> Option<usize> {
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
struct Header {
    encoding: PlyEncoding,
    elements: Vec<Element>,
    vertex_count: usize,
    /// Byte offset and line number where the body starts.
    body_offset: usize,
    body_line: usize,
}

fn parse_header(bytes: &[u8], source: Source<'_>) -> Result<Header> {
    let malformed =
        |line: usize, message: String| source.at_line(line, format!("malformed header: {message}"));
    let mut lines = Lines::new(bytes);
    match lines.next() {
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
            .split(|&b| super::text::is_space(b))
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
                let (Some(name), Some(count)) = (tokens.next(), tokens.next()) else {
                    return Err(malformed(line, "element needs a name and a count".into()));
                };
                let count = parse_i64(count)
                    .and_then(|c| usize::try_from(c).ok())
                    .ok_or_else(|| {
                        malformed(
                            line,
                            format!(
                                "element count '{}' is not a non-negative integer",
                                show(count)
                            ),
                        )
                    })?;
                elements.push(Element {
                    name: String::from_utf8_lossy(name).into_owned(),
                    count,
                    properties: Vec::new(),
                });
            }
            b"property" => {
                let Some(element) = elements.last_mut() else {
                    return Err(malformed(line, "property before any element".into()));
                };
                let scalar = |token: Option<&[u8]>| {
                    let token = token.unwrap_or_default();
                    Scalar::from_name(token).ok_or_else(|| {
                        malformed(line, format!("unknown property type '{}'", show(token)))
                    })
                };
                let first = tokens.next();
                let kind = if first == Some(b"list") {
                    let count = scalar(tokens.next())?;
                    let item = scalar(tokens.next())?;
                    if !count.is_integer() {
                        return Err(malformed(
                            line,
                            "a list's count type must be an integer type".into(),
                        ));
                    }
                    Kind::List { count, item }
                } else {
                    Kind::Scalar(scalar(first)?)
                };
                let Some(name) = tokens.next() else {
                    return Err(malformed(line, "property without a name".into()));
                };
                element.properties.push(Property {
                    name: String::from_utf8_lossy(name).into_owned(),
                    kind,
                    role: Role::Skip,
                });
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
    Ok(Header {
        encoding,
        elements,
        vertex_count,
        body_offset: lines.offset(),
        // An empty body: errors point at the last line, end_header.
        body_line: if lines.offset() < bytes.len() {
            end_line + 1
        } else {
            end_line
        },
    })
}

/// Marks the properties the reader keeps; returns the number of vertices.
fn assign_roles(elements: &mut [Element]) -> Result<usize, String> {
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

// ---------------------------------------------------------------------------------------
// Body
// ---------------------------------------------------------------------------------------

/// Why a value could not be read.
enum Fault {
    /// The data ends before the value.
    End,
    /// Not a number (ascii).
    NotNumber(String),
    /// A number where an integer is needed (ascii).
    NotInteger(String),
}

/// A stream of values, ascii or binary, so one walker decodes both encodings.
trait Values {
    fn float(&mut self, ty: Scalar) -> Result<f64, Fault>;
    fn int(&mut self, ty: Scalar) -> Result<i64, Fault>;
    fn skip(&mut self, ty: Scalar, n: usize) -> Result<(), Fault>;
    /// Takes `records` records of `size` bytes at once, when the encoding allows it (binary):
    /// their bytes, the offset of the first one, and whether they are big-endian. The error
    /// is the index of the first record that is cut off.
    fn fixed_block(&mut self, records: usize, size: usize) -> Option<Result<Block<'_>, usize>>;
    /// Fails early when `n` values of `ty` cannot possibly follow (bounds list lengths
    /// before anything is allocated for them).
    fn room_for(&self, n: usize, ty: Scalar) -> Result<(), Fault>;
    /// Where the last value read (or the failed read) is.
    fn location(&self) -> Location;
}

/// Consecutive fixed-size binary records.
struct Block<'a> {
    bytes: &'a [u8],
    offset: usize,
    big_endian: bool,
}

/// Reads a `$t` from the start of `$bytes` in the given byte order, returning `None` from
/// the enclosing function when the bytes are too few.
macro_rules! scalar_from {
    ($bytes:ident, $big_endian:ident, $t:ty) => {{
        let b = *$bytes.first_chunk::<{ std::mem::size_of::<$t>() }>()?;
        if $big_endian {
            <$t>::from_be_bytes(b)
        } else {
            <$t>::from_le_bytes(b)
        }
    }};
}

/// Decodes one binary scalar from the start of `bytes` as `f64` (`None` if too short).
#[inline]
fn decode_f64(ty: Scalar, big_endian: bool, bytes: &[u8]) -> Option<f64> {
    Some(match ty {
        Scalar::I8 => f64::from(scalar_from!(bytes, big_endian, i8)),
        Scalar::U8 => f64::from(scalar_from!(bytes, big_endian, u8)),
        Scalar::I16 => f64::from(scalar_from!(bytes, big_endian, i16)),
        Scalar::U16 => f64::from(scalar_from!(bytes, big_endian, u16)),
        Scalar::I32 => f64::from(scalar_from!(bytes, big_endian, i32)),
        Scalar::U32 => f64::from(scalar_from!(bytes, big_endian, u32)),
        Scalar::F32 => f64::from(scalar_from!(bytes, big_endian, f32)),
        Scalar::F64 => scalar_from!(bytes, big_endian, f64),
    })
}

/// Decodes one binary integer scalar (the header keeps float types out of counts and
/// indices; should one get here it is truncated towards zero).
#[inline]
fn decode_i64(ty: Scalar, big_endian: bool, bytes: &[u8]) -> Option<i64> {
    Some(match ty {
        Scalar::I8 => i64::from(scalar_from!(bytes, big_endian, i8)),
        Scalar::U8 => i64::from(scalar_from!(bytes, big_endian, u8)),
        Scalar::I16 => i64::from(scalar_from!(bytes, big_endian, i16)),
        Scalar::U16 => i64::from(scalar_from!(bytes, big_endian, u16)),
        Scalar::I32 => i64::from(scalar_from!(bytes, big_endian, i32)),
        Scalar::U32 => i64::from(scalar_from!(bytes, big_endian, u32)),
        Scalar::F32 => scalar_from!(bytes, big_endian, f32) as i64,
        Scalar::F64 => scalar_from!(bytes, big_endian, f64) as i64,
    })
}

/// Binary values; `BIG` selects big-endian (a constant, so each byte order gets its own
/// compiled walker).
struct Binary<'a, const BIG: bool> {
    data: &'a [u8],
    position: usize,
    last: usize,
}

impl<const BIG: bool> Binary<'_, BIG> {
    #[inline]
    fn rest(&mut self) -> &[u8] {
        self.last = self.position;
        self.data.get(self.position..).unwrap_or_default()
    }
}

impl<const BIG: bool> Values for Binary<'_, BIG> {
    #[inline]
    fn float(&mut self, ty: Scalar) -> Result<f64, Fault> {
        let x = decode_f64(ty, BIG, self.rest()).ok_or(Fault::End)?;
        self.position += ty.size();
        Ok(x)
    }

    #[inline]
    fn int(&mut self, ty: Scalar) -> Result<i64, Fault> {
        let i = decode_i64(ty, BIG, self.rest()).ok_or(Fault::End)?;
        self.position += ty.size();
        Ok(i)
    }

    #[inline]
    fn skip(&mut self, ty: Scalar, n: usize) -> Result<(), Fault> {
        self.room_for(n, ty)?;
        self.last = self.position;
        self.position += n * ty.size();
        Ok(())
    }

    fn fixed_block(&mut self, records: usize, size: usize) -> Option<Result<Block<'_>, usize>> {
        let start = self.position.min(self.data.len());
        let remaining = self.data.len() - start;
        let total = records.checked_mul(size).filter(|&t| t <= remaining);
        Some(match total {
            Some(t) => {
                self.position = start + t;
                Ok(Block {
                    bytes: &self.data[start..start + t],
                    offset: start,
                    big_endian: BIG,
                })
            }
            None => {
                // Point at the first record that does not fit (size > 0 here: records of
                // zero bytes always fit).
                let complete = remaining / size.max(1);
                self.position = start + complete * size;
                self.last = self.position;
                Err(complete)
            }
        })
    }

    fn room_for(&self, n: usize, ty: Scalar) -> Result<(), Fault> {
        let remaining = self.data.len() - self.position.min(self.data.len());
        if n.checked_mul(ty.size()).is_some_and(|b| b <= remaining) {
            Ok(())
        } else {
            Err(Fault::End)
        }
    }

    fn location(&self) -> Location {
        Location::Byte(self.last as u64)
    }
}

/// Ascii values: whitespace-separated tokens across lines.
struct Ascii<'a> {
    words: Words<'a>,
    remaining_hint: usize,
}

impl Ascii<'_> {
    #[inline]
    fn word(&mut self) -> Result<&[u8], Fault> {
        self.words.next_word().ok_or(Fault::End)
    }
}

impl Values for Ascii<'_> {
    #[inline]
    fn float(&mut self, _ty: Scalar) -> Result<f64, Fault> {
        let w = self.word()?;
        parse_f64(w).ok_or_else(|| Fault::NotNumber(show(w)))
    }

    #[inline]
    fn int(&mut self, _ty: Scalar) -> Result<i64, Fault> {
        let w = self.word()?;
        parse_i64(w).ok_or_else(|| {
            if parse_f64(w).is_some() {
                Fault::NotInteger(show(w))
            } else {
                Fault::NotNumber(show(w))
            }
        })
    }

    fn skip(&mut self, _ty: Scalar, n: usize) -> Result<(), Fault> {
        for _ in 0..n {
            self.word()?;
        }
        Ok(())
    }

    fn fixed_block(&mut self, _records: usize, _size: usize) -> Option<Result<Block<'_>, usize>> {
        None
    }

    fn room_for(&self, n: usize, _ty: Scalar) -> Result<(), Fault> {
        // Every value takes at least two bytes (a digit and a separator), bar the last.
        if n <= self.remaining_hint / 2 + 1 {
            Ok(())
        } else {
            Err(Fault::End)
        }
    }

    fn location(&self) -> Location {
        Location::Line(self.words.line())
    }
}

/// Parses a PLY file held in memory.
pub(super) fn parse(bytes: &[u8], source: Source<'_>) -> Result<MeshData> {
    let header = parse_header(bytes, source)?;
    let body = &bytes[header.body_offset.min(bytes.len())..];
    match header.encoding {
        PlyEncoding::Ascii => {
            let mut values = Ascii {
                words: Words::new(bytes, header.body_offset, header.body_line),
                remaining_hint: body.len(),
            };
            decode(&header, &mut values, source, body.len())
        }
        PlyEncoding::BinaryLittleEndian => {
            let mut values = Binary::<false> {
                data: bytes,
                position: header.body_offset,
                last: header.body_offset,
            };
            decode(&header, &mut values, source, body.len())
        }
        PlyEncoding::BinaryBigEndian => {
            let mut values = Binary::<true> {
                data: bytes,
                position: header.body_offset,
                last: header.body_offset,
            };
            decode(&header, &mut values, source, body.len())
        }
    }
}

/// Walks every element of the body, keeping positions and faces.
fn decode<V: Values>(
    header: &Header,
    values: &mut V,
    source: Source<'_>,
    body_len: usize,
) -> Result<MeshData> {
    let vertex_count = header.vertex_count;
    // Never trust a header count for an allocation beyond what the file could hold.
    let room = |element: &Element| element.records_in(body_len, header.encoding);
    let mut positions = Vec::with_capacity(
        header
            .elements
            .iter()
            .find(|e| e.is_vertex())
            .map_or(0, room),
    );
    let mut faces = Vec::new();
    let mut corners: Vec<u32> = Vec::new();

    for element in &header.elements {
        let record_error = |values: &V, record: usize, fault: Fault| {
            let what = format!("{} {record}", element.name);
            let message = match fault {
                Fault::End => format!(
                    "truncated data: the file ends in {what} (of {} {} elements)",
                    element.count, element.name
                ),
                Fault::NotNumber(t) => format!("non-numeric token '{t}' in {what}"),
                Fault::NotInteger(t) => format!("'{t}' in {what} is not an integer"),
            };
            source.at(values.location(), message)
        };
        let keeps_nothing = element.properties.iter().all(|p| p.role == Role::Skip);
        // Binary elements of scalars only (vertices nearly always, and most elements that are
        // skipped) are taken as one block: one bounds check instead of one per value.
        if let Some(size) = element
            .fixed_size()
            .filter(|_| keeps_nothing || element.is_vertex())
        {
            match values.fixed_block(element.count, size) {
                Some(Ok(block)) => {
                    if !keeps_nothing {
                        read_vertex_block(&block, size, element, &mut positions)
                            .map_err(|(at, m)| source.at_byte(at, m))?;
                    }
                    continue;
                }
                Some(Err(record)) => return Err(record_error(values, record, Fault::End)),
                None => {}
            }
        }
        if element.name == "face" {
            faces.reserve(room(element));
        }
        for record in 0..element.count {
            let mut point = [0.0f64; 3];
            for property in &element.properties {
                read_property(
                    values,
                    property,
                    vertex_count,
                    &mut point,
                    &mut corners,
                    &mut faces,
                )
                .map_err(|e| match e {
                    ValueError::Fault(fault) => record_error(values, record, fault),
                    ValueError::Message(m) => {
                        source.at(values.location(), format!("{} {record}: {m}", element.name))
                    }
                })?;
            }
            if element.is_vertex() {
                if let Some(axis) = point.iter().position(|c| !c.is_finite()) {
                    return Err(source.at(
                        values.location(),
                        format!(
                            "vertex {record} has a NaN or infinite {} coordinate ({})",
                            ["x", "y", "z"][axis],
                            point[axis]
                        ),
                    ));
                }
                positions.push(point);
            }
        }
    }
    Ok(MeshData { positions, faces })
}

/// Decodes the positions of a block of fixed-size vertex records; the error is a byte
/// offset and a message.
fn read_vertex_block(
    block: &Block<'_>,
    size: usize,
    element: &Element,
    positions: &mut Vec<[f64; 3]>,
) -> Result<(), (usize, String)> {
    // Offset and type of x, y and z inside a record.
    let mut fields = [(0usize, Scalar::F32); 3];
    let mut offset = 0;
    for p in &element.properties {
        if let Kind::Scalar(ty) = p.kind {
            if let Role::Coordinate(axis) = p.role {
                fields[axis] = (offset, ty);
            }
            offset += ty.size();
        }
    }
    positions.reserve(element.count);
    for (record, bytes) in block.bytes.chunks_exact(size.max(1)).enumerate() {
        let mut point = [0.0f64; 3];
        for (axis, &(at, ty)) in fields.iter().enumerate() {
            let byte = block.offset + record * size + at;
            // The block holds whole records, so the field is always there.
            let x = bytes
                .get(at..)
                .and_then(|b| decode_f64(ty, block.big_endian, b))
                .ok_or_else(|| (byte, format!("truncated data in vertex {record}")))?;
            if !x.is_finite() {
                return Err((
                    byte,
                    format!(
                        "vertex {record} has a NaN or infinite {} coordinate ({x})",
                        ["x", "y", "z"][axis]
                    ),
                ));
            }
            point[axis] = x;
        }
        positions.push(point);
    }
    Ok(())
}

/// A failure while reading a property: a read fault or a message about the values.
enum ValueError {
    Fault(Fault),
    Message(String),
}

impl From<Fault> for ValueError {
    fn from(f: Fault) -> Self {
        ValueError::Fault(f)
    }
}

/// Reads one property of one record, keeping what its role asks for.
#[inline]
fn read_property<V: Values>(
    values: &mut V,
    property: &Property,
    vertex_count: usize,
    point: &mut [f64; 3],
    corners: &mut Vec<u32>,
    faces: &mut Vec<[u32; 3]>,
) -> Result<(), ValueError> {
    match (property.kind, property.role) {
        (Kind::Scalar(ty), Role::Coordinate(axis)) => point[axis] = values.float(ty)?,
        (Kind::Scalar(ty), _) => values.skip(ty, 1)?,
        (Kind::List { count, item }, role) => {
            let n = values.int(count)?;
            let Ok(n) = usize::try_from(n) else {
                return Err(ValueError::Message(format!("negative list length {n}")));
            };
            match role {
                Role::Polygon => read_polygon(values, n, item, vertex_count, corners, faces)?,
                Role::Strips => read_strips(values, n, item, vertex_count, faces)?,
                _ => values.skip(item, n)?,
            }
        }
    }
    Ok(())
}

#[inline]
fn checked_index(i: i64, vertex_count: usize) -> Result<u32, ValueError> {
    if i < 0 || i as u64 >= vertex_count as u64 {
        return Err(ValueError::Message(format!(
            "vertex index {i} out of range (the file has {vertex_count} vertices)"
        )));
    }
    // In range of a u32 because vertex_count <= u32::MAX (checked with the header).
    Ok(i as u32)
}

fn read_polygon<V: Values>(
    values: &mut V,
    n: usize,
    item: Scalar,
    vertex_count: usize,
    corners: &mut Vec<u32>,
    faces: &mut Vec<[u32; 3]>,
) -> Result<(), ValueError> {
    if n < 3 {
        return Err(ValueError::Message(format!(
            "face with {n} vertices (at least 3 needed)"
        )));
    }
    values.room_for(n, item)?;
    if n == 3 {
        // Most faces are triangles: no corner buffer.
        let a = checked_index(values.int(item)?, vertex_count)?;
        let b = checked_index(values.int(item)?, vertex_count)?;
        let c = checked_index(values.int(item)?, vertex_count)?;
        faces.push([a, b, c]);
        return Ok(());
    }
    corners.clear();
    for _ in 0..n {
        corners.push(checked_index(values.int(item)?, vertex_count)?);
    }
    push_fan(faces, corners);
    Ok(())
}

fn read_strips<V: Values>(
    values: &mut V,
    n: usize,
    item: Scalar,
    vertex_count: usize,
    faces: &mut Vec<[u32; 3]>,
) -> Result<(), ValueError> {
    values.room_for(n, item)?;
    faces.reserve(n);
    let mut strip = StripDecoder::default();
    for _ in 0..n {
        match values.int(item)? {
            -1 => strip.restart(),
            i => strip.push(checked_index(i, vertex_count)?, faces),
        }
    }
    Ok(())
}

/// Turns a triangle strip into triangles as its indices arrive: (s0 s1 s2), (s2 s1 s3),
/// (s2 s3 s4), ... — every odd triangle swaps its first two corners so that all keep the
/// strip's orientation. Triangles with a repeated index join strips and are dropped.
#[derive(Debug, Default)]
struct StripDecoder {
    previous: [u32; 2],
    length: usize,
}

impl StripDecoder {
    #[inline]
    fn push(&mut self, v: u32, faces: &mut Vec<[u32; 3]>) {
        let [a, b] = self.previous;
        if self.length >= 2 {
            let t = if self.length % 2 == 0 {
                [a, b, v]
            } else {
                [b, a, v]
            };
            if a != b && b != v && a != v {
                faces.push(t);
            }
        }
        self.previous = [b, v];
        self.length += 1;
    }

    fn restart(&mut self) {
        self.length = 0;
    }
}

// ---------------------------------------------------------------------------------------
// Writing
// ---------------------------------------------------------------------------------------

/// Values of one extra per-vertex property, stored as `double` or `float`.
#[derive(Debug, Clone, PartialEq)]
pub enum PropertyValues<'a> {
    /// Written as `double`.
    F64(Cow<'a, [f64]>),
    /// Written as `float`.
    F32(Cow<'a, [f32]>),
}

impl PropertyValues<'_> {
    fn len(&self) -> usize {
        match self {
            PropertyValues::F64(v) => v.len(),
            PropertyValues::F32(v) => v.len(),
        }
    }

    fn type_name(&self) -> &'static str {
        match self {
            PropertyValues::F64(_) => "double",
            PropertyValues::F32(_) => "float",
        }
    }

    fn borrowed(&self) -> PropertyValues<'_> {
        match self {
            PropertyValues::F64(v) => PropertyValues::F64(Cow::Borrowed(v)),
            PropertyValues::F32(v) => PropertyValues::F32(Cow::Borrowed(v)),
        }
    }
}

impl<'a> From<&'a [f64]> for PropertyValues<'a> {
    fn from(v: &'a [f64]) -> Self {
        PropertyValues::F64(Cow::Borrowed(v))
    }
}

impl<'a> From<&'a Vec<f64>> for PropertyValues<'a> {
    fn from(v: &'a Vec<f64>) -> Self {
        PropertyValues::F64(Cow::Borrowed(v))
    }
}

impl From<Vec<f64>> for PropertyValues<'_> {
    fn from(v: Vec<f64>) -> Self {
        PropertyValues::F64(Cow::Owned(v))
    }
}

impl<'a> From<&'a [f32]> for PropertyValues<'a> {
    fn from(v: &'a [f32]) -> Self {
        PropertyValues::F32(Cow::Borrowed(v))
    }
}

impl<'a> From<&'a Vec<f32>> for PropertyValues<'a> {
    fn from(v: &'a Vec<f32>) -> Self {
        PropertyValues::F32(Cow::Borrowed(v))
    }
}

impl From<Vec<f32>> for PropertyValues<'_> {
    fn from(v: Vec<f32>) -> Self {
        PropertyValues::F32(Cow::Owned(v))
    }
}

/// An extra scalar property of the vertex element, one value per vertex.
#[derive(Debug, Clone, PartialEq)]
pub struct VertexProperty<'a> {
    /// Property name as it appears in the header (`k_max`, `dir_max_x`, ...).
    pub name: Cow<'a, str>,
    /// One value per vertex, in vertex order.
    pub values: PropertyValues<'a>,
}

impl<'a> VertexProperty<'a> {
    /// A property from a name and values (`&[f64]`, `Vec<f64>`, `&[f32]`, `Vec<f32>`).
    pub fn new(name: impl Into<Cow<'a, str>>, values: impl Into<PropertyValues<'a>>) -> Self {
        VertexProperty {
            name: name.into(),
            values: values.into(),
        }
    }

    fn borrowed(&self) -> VertexProperty<'_> {
        VertexProperty {
            name: Cow::Borrowed(&self.name),
            values: self.values.borrowed(),
        }
    }
}

/// Writes a mesh as PLY, optionally with extra per-vertex properties.
///
/// ```
/// use crestline::io::{PlyEncoding, PlyWriter, VertexProperty};
/// let mesh = crestline::shapes::icosphere(1.0, 1);
/// let k: Vec<f32> = vec![1.0; mesh.num_vertices()];
/// let mut bytes = Vec::new();
/// PlyWriter::new(&mesh)
///     .encoding(PlyEncoding::Ascii)
///     .property(VertexProperty::new("k_max", k))?
///     .write_to(&mut bytes)?;
/// assert!(String::from_utf8_lossy(&bytes).contains("property float k_max\n"));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, Clone)]
pub struct PlyWriter<'a> {
    mesh: &'a TriMesh,
    encoding: PlyEncoding,
    comments: Vec<String>,
    properties: Vec<VertexProperty<'a>>,
}

impl<'a> PlyWriter<'a> {
    /// A writer for `mesh`, binary little endian, with no extra properties.
    pub fn new(mesh: &'a TriMesh) -> Self {
        PlyWriter {
            mesh,
            encoding: PlyEncoding::BinaryLittleEndian,
            comments: Vec::new(),
            properties: Vec::new(),
        }
    }

    /// Chooses the encoding. Default value: [`PlyEncoding::BinaryLittleEndian`].
    pub fn encoding(mut self, encoding: PlyEncoding) -> Self {
        self.encoding = encoding;
        self
    }

    /// Adds a `comment` line to the header (line breaks become spaces).
    pub fn comment(mut self, text: impl Into<String>) -> Self {
        self.comments.push(text.into().replace(['\n', '\r'], " "));
        self
    }

    /// Adds an extra vertex property, written after `x y z` in the order added.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] when the number of values differs from the number of
    /// vertices, or the name is empty, contains whitespace, is `x`/`y`/`z` or repeats one.
    pub fn property(mut self, property: VertexProperty<'a>) -> Result<Self> {
        let name = &property.name;
        if name.is_empty() || !name.bytes().all(|b| b.is_ascii_graphic()) {
            return Err(Error::InvalidInput(format!(
                "PLY property name '{name}' must be non-empty printable ascii without spaces"
            )));
        }
        if ["x", "y", "z"].contains(&name.as_ref())
            || self.properties.iter().any(|p| p.name == *name)
        {
            return Err(Error::InvalidInput(format!(
                "PLY vertex property '{name}' is given twice"
            )));
        }
        if property.values.len() != self.mesh.num_vertices() {
            return Err(Error::InvalidInput(format!(
                "PLY vertex property '{name}' has {} values for {} vertices",
                property.values.len(),
                self.mesh.num_vertices()
            )));
        }
        self.properties.push(property);
        Ok(self)
    }

    /// Writes the file to `out` (buffer it: values are written one by one).
    ///
    /// # Errors
    /// Whatever `out` returns.
    pub fn write_to<W: Write>(&self, out: W) -> std::io::Result<()> {
        let mesh = self.mesh;
        let mut out = RecordWriter::new(out, self.encoding);
        let mut header = format!(
            "ply\nformat {} 1.0\ncomment written by crestline\n",
            self.encoding.header_name()
        );
        for c in &self.comments {
            header.push_str(&format!("comment {c}\n"));
        }
        header.push_str(&format!(
            "element vertex {}\nproperty double x\nproperty double y\nproperty double z\n",
            mesh.num_vertices()
        ));
        for p in &self.properties {
            header.push_str(&format!("property {} {}\n", p.values.type_name(), p.name));
        }
        header.push_str(&format!(
            "element face {}\nproperty list uchar {} vertex_indices\nend_header\n",
            mesh.num_faces(),
            index_type(mesh.num_vertices())
        ));
        out.raw(header.as_bytes())?;
        for (v, p) in mesh.positions().iter().enumerate() {
            out.f64(p.x)?;
            out.f64(p.y)?;
            out.f64(p.z)?;
            for property in &self.properties {
                match &property.values {
                    PropertyValues::F64(values) => out.f64(values[v])?,
                    PropertyValues::F32(values) => out.f32(values[v])?,
                }
            }
            out.end()?;
        }
        for &[a, b, c] in mesh.faces() {
            out.u8(3)?;
            out.index(a)?;
            out.index(b)?;
            out.index(c)?;
            out.end()?;
        }
        out.finish()
    }

    /// Writes the file to `path`, all or nothing (see [`super::write_atomically`]).
    ///
    /// # Errors
    /// [`Error::Io`] naming the file.
    pub fn write(&self, path: &Path) -> Result<()> {
        super::write_atomically(path, |out| self.write_to(out))
    }
}

/// Writes `mesh` to `path` as PLY with extra per-vertex properties (see [`PlyWriter`]).
///
/// # Errors
/// [`Error::InvalidInput`] for a bad property (see [`PlyWriter::property`]), [`Error::Io`]
/// naming the file.
pub fn write_ply(
    path: &Path,
    mesh: &TriMesh,
    extra: &[VertexProperty<'_>],
    encoding: PlyEncoding,
) -> Result<()> {
    let mut writer = PlyWriter::new(mesh).encoding(encoding);
    for p in extra {
        writer = writer.property(p.borrowed())?;
    }
    writer.write(path)
}

/// The index type the face list uses: `int` as most readers expect, `uint` when needed.
pub(super) fn index_type(vertex_count: usize) -> &'static str {
    if vertex_count <= i32::MAX as usize {
        "int"
    } else {
        "uint"
    }
}

/// Writes records value by value in either encoding: ascii separates values with spaces and
/// ends records with a line break, binary concatenates bytes.
pub(super) struct RecordWriter<W: Write> {
    out: W,
    encoding: PlyEncoding,
    at_record_start: bool,
}

impl<W: Write> RecordWriter<W> {
    pub fn new(out: W, encoding: PlyEncoding) -> Self {
        RecordWriter {
            out,
            encoding,
            at_record_start: true,
        }
    }

    pub fn raw(&mut self, bytes: &[u8]) -> std::io::Result<()> {
        self.out.write_all(bytes)
    }

    fn separate(&mut self) -> std::io::Result<()> {
        if !self.at_record_start {
            self.out.write_all(b" ")?;
        }
        self.at_record_start = false;
        Ok(())
    }

    pub fn f64(&mut self, x: f64) -> std::io::Result<()> {
        super::check_finite(x)?;
        match self.encoding {
            PlyEncoding::Ascii => {
                self.separate()?;
                write_f64(&mut self.out, x)
            }
            PlyEncoding::BinaryLittleEndian => self.out.write_all(&x.to_le_bytes()),
            PlyEncoding::BinaryBigEndian => self.out.write_all(&x.to_be_bytes()),
        }
    }

    pub fn f32(&mut self, x: f32) -> std::io::Result<()> {
        super::check_finite(f64::from(x))?;
        match self.encoding {
            PlyEncoding::Ascii => {
                self.separate()?;
                // Widening to f64 would print the binary expansion's extra digits.
                let magnitude = x.abs();
                if magnitude == 0.0 || (1e-5..1e16).contains(&magnitude) {
                    write!(self.out, "{x}")
                } else {
                    write!(self.out, "{x:e}")
                }
            }
            PlyEncoding::BinaryLittleEndian => self.out.write_all(&x.to_le_bytes()),
            PlyEncoding::BinaryBigEndian => self.out.write_all(&x.to_be_bytes()),
        }
    }

    /// A vertex index, as `int` (or `uint` past 2^31, matching [`index_type`]).
    pub fn index(&mut self, i: u32) -> std::io::Result<()> {
        match self.encoding {
            PlyEncoding::Ascii => {
                self.separate()?;
                write!(self.out, "{i}")
            }
            PlyEncoding::BinaryLittleEndian => self.out.write_all(&i.to_le_bytes()),
            PlyEncoding::BinaryBigEndian => self.out.write_all(&i.to_be_bytes()),
        }
    }

    pub fn u8(&mut self, x: u8) -> std::io::Result<()> {
        match self.encoding {
            PlyEncoding::Ascii => {
                self.separate()?;
                write!(self.out, "{x}")
            }
            _ => self.out.write_all(&[x]),
        }
    }

    /// Ends a record.
    pub fn end(&mut self) -> std::io::Result<()> {
        self.at_record_start = true;
        match self.encoding {
            PlyEncoding::Ascii => self.out.write_all(b"\n"),
            _ => Ok(()),
        }
    }

    pub fn finish(mut self) -> std::io::Result<()> {
        self.out.flush()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::{Format, read_mesh_bytes};

    fn parse_bytes(bytes: &[u8]) -> Result<MeshData> {
        parse(bytes, Source::new(Path::new("t.ply")))
    }

    fn error(bytes: &[u8]) -> String {
        parse_bytes(bytes).unwrap_err().to_string()
    }

    /// A header then binary data built by `body`.
    fn binary(header: &str, body: impl FnOnce(&mut Vec<u8>)) -> Vec<u8> {
        let mut bytes = header.as_bytes().to_vec();
        body(&mut bytes);
        bytes
    }

    const SQUARE: [[f64; 3]; 4] = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
    ];

    #[test]
    fn ascii_with_extra_elements_and_properties() {
        let text = "ply\r\nformat ascii 1.0\r\ncomment anything # at all\r\n\
            element vertex 4\r\nproperty float x\r\nproperty float y\r\nproperty float z\r\n\
            property list uchar int junk\r\nproperty uchar red\r\n\
            element face 1\r\nproperty uchar flags\r\nproperty list uchar int vertex_indices\r\n\
            property float quality\r\n\
            element material 2\r\nproperty list int float values\r\n\
            end_header\r\n\
            0 0 0 2 7 7 255\r\n1 0 0 0 1\r\n1 1 0 1 9 0\r\n0 1 0 0 3\r\n\
            5 4 0 1 2 3 0.5\r\n\
            3 1.5 2 2.5\r\n0\r\n";
        let m = parse_bytes(text.as_bytes()).unwrap();
        assert_eq!(m.positions, SQUARE.to_vec());
        assert_eq!(m.faces, vec![[0, 1, 2], [0, 2, 3]]);
    }

    /// The same mesh as `ascii_with_extra_elements_and_properties`, binary, in both byte
    /// orders, with every scalar type somewhere and `vertex_index` as the list name.
    fn binary_square(big: bool) -> Vec<u8> {
        let header = format!(
            "ply\nformat binary_{}_endian 1.0\n\
             element vertex 4\nproperty int8 pad\nproperty double x\nproperty float32 y\n\
             property short z\nproperty list ushort uint16 junk\nproperty uint8 red\n\
             element face 1\nproperty uint flags\nproperty list uint8 int vertex_index\n\
             property float64 quality\n\
             element material 2\nproperty list int float values\nproperty char c\n\
             end_header\n",
            if big { "big" } else { "little" }
        );
        binary(&header, |b| {
            macro_rules! put {
                ($v:expr) => {
                    if big {
                        b.extend_from_slice(&$v.to_be_bytes())
                    } else {
                        b.extend_from_slice(&$v.to_le_bytes())
                    }
                };
            }
            for (i, p) in SQUARE.iter().enumerate() {
                put!(-1i8);
                put!(p[0]);
                put!(p[1] as f32);
                put!(p[2] as i16);
                put!(i as u16);
                for _ in 0..i {
                    put!(7u16);
                }
                put!(200u8);
            }
            put!(0xdead_beefu32);
            put!(4u8);
            for i in [0i32, 1, 2, 3] {
                put!(i);
            }
            put!(0.5f64);
            put!(2i32);
            put!(1.5f32);
            put!(2.5f32);
            put!(-3i8);
            put!(0i32);
            put!(4i8);
        })
    }

    #[test]
    fn binary_little_and_big_endian_with_extra_elements() {
        for big in [false, true] {
            let m = parse_bytes(&binary_square(big)).unwrap();
            assert_eq!(m.positions, SQUARE.to_vec(), "big endian: {big}");
            assert_eq!(m.faces, vec![[0, 1, 2], [0, 2, 3]], "big endian: {big}");
        }
    }

    #[test]
    fn integer_coordinates_are_accepted() {
        let bytes = binary(
            "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty uchar x\n\
             property int y\nproperty ushort z\nelement face 1\n\
             property list int uint vertex_indices\nend_header\n",
            |b| {
                for (x, y, z) in [(0u8, 0i32, 0u16), (250, -1, 1), (0, 1, 65535)] {
                    b.push(x);
                    b.extend_from_slice(&y.to_le_bytes());
                    b.extend_from_slice(&z.to_le_bytes());
                }
                b.extend_from_slice(&3i32.to_le_bytes());
                for i in 0u32..3 {
                    b.extend_from_slice(&i.to_le_bytes());
                }
            },
        );
        let m = parse_bytes(&bytes).unwrap();
        assert_eq!(m.positions[1], [250.0, -1.0, 1.0]);
        assert_eq!(m.positions[2], [0.0, 1.0, 65535.0]);
        assert_eq!(m.faces, vec![[0, 1, 2]]);
    }

    #[test]
    fn tristrips_restart_alternate_and_drop_stitches() {
        let text = "ply\nformat ascii 1.0\nelement vertex 6\n\
            property float x\nproperty float y\nproperty float z\n\
            element tristrips 1\nproperty list int int vertex_indices\nend_header\n\
            0 0 0\n1 0 0\n0 1 0\n1 1 0\n0 2 0\n1 2 0\n\
            11 0 1 2 3 3 4 -1 4 5 2 -1\n";
        let m = parse_bytes(text.as_bytes()).unwrap();
        // Strip 0 1 2 3 3 4: (0 1 2), (2 1 3), (2 3 3) dropped, (3 3 4) dropped.
        // Strip 4 5 2: (4 5 2).
        assert_eq!(m.faces, vec![[0, 1, 2], [2, 1, 3], [4, 5, 2]]);
    }

    #[test]
    fn strip_winding_alternates() {
        let mut faces = Vec::new();
        let mut strip = StripDecoder::default();
        for v in [0, 1, 2, 3, 4] {
            strip.push(v, &mut faces);
        }
        assert_eq!(faces, vec![[0, 1, 2], [2, 1, 3], [2, 3, 4]]);
        strip.restart();
        for v in [7, 8, 9] {
            strip.push(v, &mut faces);
        }
        assert_eq!(faces[3], [7, 8, 9]);
    }

    #[test]
    fn binary_tristrips() {
        let bytes = binary(
            "ply\nformat binary_big_endian 1.0\nelement vertex 4\n\
             property float x\nproperty float y\nproperty float z\n\
             element tristrips 1\nproperty list int int vertex_indices\nend_header\n",
            |b| {
                for p in SQUARE {
                    for c in p {
                        b.extend_from_slice(&(c as f32).to_be_bytes());
                    }
                }
                b.extend_from_slice(&5i32.to_be_bytes());
                for i in [1i32, 2, 0, 3, -1] {
                    b.extend_from_slice(&i.to_be_bytes());
                }
            },
        );
        let m = parse_bytes(&bytes).unwrap();
        assert_eq!(m.faces, vec![[1, 2, 0], [0, 2, 3]]);
    }

    #[test]
    fn point_cloud_without_faces() {
        let m = parse_bytes(
            b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n\
              property float z\nend_header\n1 2 3\n",
        )
        .unwrap();
        assert_eq!(m.positions, vec![[1.0, 2.0, 3.0]]);
        assert!(m.faces.is_empty());
    }

    const ASCII_HEADER: &str = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n\
        property float y\nproperty float z\nelement face 1\n\
        property list uchar int vertex_indices\nend_header\n";

    #[test]
    fn malformed_headers() {
        assert_eq!(
            error(b"plx\nformat ascii 1.0\n"),
            "t.ply: line 1: not a PLY file: the first line is 'plx', expected 'ply'"
        );
        assert_eq!(
            error(b"ply\nformat ascii 1.0\nelement vertex 3\nproperty flaot x\n"),
            "t.ply: line 4: malformed header: unknown property type 'flaot'"
        );
        assert_eq!(
            error(b"ply\nformat ascii 1.0\nelement vertex many\n"),
            "t.ply: line 3: malformed header: element count 'many' is not a non-negative integer"
        );
        assert_eq!(
            error(b"ply\nformat ascii 1.0\nproperty float x\n"),
            "t.ply: line 3: malformed header: property before any element"
        );
        assert_eq!(
            error(b"ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\n"),
            "t.ply: line 4: malformed header: no end_header line"
        );
        assert_eq!(
            error(b"ply\nformat binary_middle_endian 1.0\n"),
            "t.ply: line 2: malformed header: unknown format 'binary_middle_endian'"
        );
        assert_eq!(
            error(b"ply\nelement vertex 0\nproperty float x\nend_header\n"),
            "t.ply: line 4: malformed header: no format line"
        );
        assert_eq!(
            error(
                b"ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\n\
                  property float y\nend_header\n"
            ),
            "t.ply: line 6: malformed header: the vertex element has no 'z' property"
        );
        assert_eq!(
            error(
                b"ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\n\
                  property float z\nelement face 0\nproperty list uchar float vertex_indices\n\
                  end_header\n"
            ),
            "t.ply: line 9: malformed header: the face indices 'vertex_indices' must have an \
             integer type"
        );
        assert_eq!(
            error(b"ply\nformat ascii 1.0\nelement vertex 0\nproperty list float int x\n"),
            "t.ply: line 4: malformed header: a list's count type must be an integer type"
        );
        assert_eq!(
            error(b"ply\nformat ascii 1.0\nelemnt vertex 0\n"),
            "t.ply: line 3: malformed header: unknown keyword 'elemnt'"
        );
    }

    #[test]
    fn ascii_bad_values() {
        let with = |body: &str| error(format!("{ASCII_HEADER}{body}").as_bytes());
        assert_eq!(
            with("0 0 0\n1 0 0\n0 one 0\n3 0 1 2\n"),
            "t.ply: line 12: non-numeric token 'one' in vertex 2"
        );
        assert_eq!(
            with("0 0 0\n1 0 0\n0 1 nan\n3 0 1 2\n"),
            "t.ply: line 12: vertex 2 has a NaN or infinite z coordinate (NaN)"
        );
        assert_eq!(
            with("0 0 0\n1 0 inf\n0 1 0\n3 0 1 2\n"),
            "t.ply: line 11: vertex 1 has a NaN or infinite z coordinate (inf)"
        );
        assert_eq!(
            with("0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n"),
            "t.ply: line 13: face 0: vertex index 3 out of range (the file has 3 vertices)"
        );
        assert_eq!(
            with("0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n"),
            "t.ply: line 13: face 0: vertex index -1 out of range (the file has 3 vertices)"
        );
        assert_eq!(
            with("0 0 0\n1 0 0\n0 1 0\n2 0 1\n"),
            "t.ply: line 13: face 0: face with 2 vertices (at least 3 needed)"
        );
        assert_eq!(
            with("0 0 0\n1 0 0\n0 1 0\n3 0 1.5 2\n"),
            "t.ply: line 13: '1.5' in face 0 is not an integer"
        );
        assert_eq!(
            with("0 0 0\n1 0 0\n0 1 0\n3 0 1\n"),
            "t.ply: line 13: truncated data: the file ends in face 0 (of 1 face elements)"
        );
        assert_eq!(
            with("0 0 0\n1 0 0\n"),
            "t.ply: line 11: truncated data: the file ends in vertex 2 (of 3 vertex elements)"
        );
    }

    const BINARY_HEADER: &str = "ply\nformat binary_little_endian 1.0\nelement vertex 3\n\
        property float x\nproperty float y\nproperty float z\nelement face 1\n\
        property list uchar int vertex_indices\nend_header\n";

    fn binary_triangle(points: [[f32; 3]; 3], face: &[i32]) -> Vec<u8> {
        binary(BINARY_HEADER, |b| {
            for p in points {
                for c in p {
                    b.extend_from_slice(&c.to_le_bytes());
                }
            }
            b.push(face.len() as u8);
            for i in face {
                b.extend_from_slice(&i.to_le_bytes());
            }
        })
    }

    const TRIANGLE: [[f32; 3]; 3] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];

    #[test]
    fn binary_truncated_data_gives_the_byte_offset() {
        let header_len = BINARY_HEADER.len();
        let full = binary_triangle(TRIANGLE, &[0, 1, 2]);
        assert_eq!(full.len(), header_len + 36 + 1 + 12);
        // Cut inside the last index: the face's list is known not to fit from its count.
        let e = error(&full[..full.len() - 2]);
        assert_eq!(
            e,
            format!(
                "t.ply: byte {}: truncated data: the file ends in face 0 (of 1 face elements)",
                header_len + 36
            )
        );
        // Cut inside vertex 1.
        let e = error(&full[..header_len + 14]);
        assert_eq!(
            e,
            format!(
                "t.ply: byte {}: truncated data: the file ends in vertex 1 (of 3 vertex elements)",
                header_len + 12
            )
        );
        // A list count that runs past the end is caught before any allocation.
        let mut huge = binary_triangle(TRIANGLE, &[0, 1, 2]);
        huge[header_len + 36] = 255;
        assert!(error(&huge).contains("truncated data"), "{}", error(&huge));
    }

    #[test]
    fn binary_bad_values_give_the_byte_offset() {
        let h = BINARY_HEADER.len();
        let mut nan = TRIANGLE;
        nan[2][1] = f32::NAN;
        assert_eq!(
            error(&binary_triangle(nan, &[0, 1, 2])),
            format!(
                "t.ply: byte {}: vertex 2 has a NaN or infinite y coordinate (NaN)",
                h + 24 + 4
            )
        );
        let mut inf = TRIANGLE;
        inf[0][0] = f32::NEG_INFINITY;
        assert!(
            error(&binary_triangle(inf, &[0, 1, 2]))
                .contains("vertex 0 has a NaN or infinite x coordinate (-inf)")
        );
        assert_eq!(
            error(&binary_triangle(TRIANGLE, &[0, 7, 2])),
            format!(
                "t.ply: byte {}: face 0: vertex index 7 out of range (the file has 3 vertices)",
                h + 36 + 1 + 4
            )
        );
        assert_eq!(
            error(&binary_triangle(TRIANGLE, &[0, 1])),
            format!(
                "t.ply: byte {}: face 0: face with 2 vertices (at least 3 needed)",
                h + 36
            )
        );
    }

    #[test]
    fn binary_skipped_element_truncated() {
        let bytes = binary(
            "ply\nformat binary_little_endian 1.0\nelement vertex 0\nproperty float x\n\
             property float y\nproperty float z\nelement extra 10\nproperty double w\n\
             end_header\n",
            |b| b.extend_from_slice(&[0u8; 30]),
        );
        let h = bytes.len() - 30;
        assert_eq!(
            error(&bytes),
            format!(
                "t.ply: byte {}: truncated data: the file ends in extra 3 (of 10 extra elements)",
                h + 24
            )
        );
    }

    #[test]
    fn binary_skipped_element_after_others_truncated() {
        let bytes = binary(
            "ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float x\n\
             property float y\nproperty float z\nelement extra 10\nproperty double w\n\
             end_header\n",
            |b| b.extend_from_slice(&[0u8; 12 + 30]),
        );
        let h = bytes.len() - 42;
        assert_eq!(
            error(&bytes),
            format!(
                "t.ply: byte {}: truncated data: the file ends in extra 3 (of 10 extra elements)",
                h + 12 + 24
            )
        );
    }

    #[test]
    fn huge_counts_do_not_allocate() {
        let e = error(
            b"ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\n\
              property float y\nproperty float z\nend_header\n\0\0",
        );
        assert!(e.contains("truncated data"), "{e}");
    }

    fn sample_mesh() -> TriMesh {
        read_mesh_bytes(
            b"v 0 0 0\nv 1 0 1e-300\nv 0 1 0.1\nv 1 1 -7\nv 5 5 5\nf 1 2 3\nf 2 4 3\n",
            Format::Obj,
            Path::new("s.obj"),
        )
        .unwrap()
    }

    #[test]
    fn writes_and_reads_back_every_encoding_with_extra_properties() {
        let mesh = sample_mesh();
        let k: Vec<f64> = (0..5).map(|i| i as f64 / 3.0).collect();
        let q: Vec<f32> = vec![0.5, 1e-30, -2.0, 3.25, 1e30];
        for encoding in [
            PlyEncoding::Ascii,
            PlyEncoding::BinaryLittleEndian,
            PlyEncoding::BinaryBigEndian,
        ] {
            let mut bytes = Vec::new();
            PlyWriter::new(&mesh)
                .encoding(encoding)
                .comment("curvature\nof a test")
                .property(VertexProperty::new("k_max", &k))
                .unwrap()
                .property(VertexProperty::new("quality", q.clone()))
                .unwrap()
                .write_to(&mut bytes)
                .unwrap();
            let text = String::from_utf8_lossy(&bytes);
            assert!(text.contains("comment curvature of a test\n"));
            assert!(text.contains("property double k_max\nproperty float quality\n"));
            let back = parse_bytes(&bytes).unwrap();
            let positions: Vec<[f64; 3]> =
                mesh.positions().iter().map(|p| [p.x, p.y, p.z]).collect();
            assert_eq!(back.positions, positions, "{encoding:?}");
            assert_eq!(back.faces, mesh.faces().to_vec(), "{encoding:?}");
            if encoding == PlyEncoding::Ascii {
                assert!(
                    text.contains("\n1 0 1e-300 0.3333333333333333 1e-30\n"),
                    "{text}"
                );
            }
        }
    }

    #[test]
    fn bad_properties_are_refused() {
        let mesh = sample_mesh();
        let short = vec![1.0f64; 4];
        let e = PlyWriter::new(&mesh)
            .property(VertexProperty::new("k", &short))
            .unwrap_err();
        assert_eq!(
            e.to_string(),
            "invalid input: PLY vertex property 'k' has 4 values for 5 vertices"
        );
        let ok = vec![1.0f64; 5];
        assert!(
            PlyWriter::new(&mesh)
                .property(VertexProperty::new("x", &ok))
                .is_err()
        );
        assert!(
            PlyWriter::new(&mesh)
                .property(VertexProperty::new("a b", &ok))
                .is_err()
        );
        assert!(
            PlyWriter::new(&mesh)
                .property(VertexProperty::new("k", &ok))
                .unwrap()
                .property(VertexProperty::new("k", &ok))
                .is_err()
        );
    }
}
