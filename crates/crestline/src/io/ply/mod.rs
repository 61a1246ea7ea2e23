//! Stanford PLY meshes: ascii, binary little endian and binary big endian.
//!
//! Reference: G. Turk, "The PLY Polygon File Format" (1994),
//! <https://paulbourke.net/dataformats/ply/>.
//!
//! Reading: the header declares elements, each with a count and a list of scalar or list
//! properties. From the `vertex` element only `x`, `y`, `z` are kept (any scalar type; the
//! sized aliases `int8` ... `float64` are accepted too). From `face` the list named
//! `vertex_indices` (or `vertex_index`) is kept, with any integer count and index types;
//! polygons are triangulated (see [`super::triangulate`]). A `tristrips` element holds
//! triangle strips in one list (`vertex_indices`, or its first list): `-1` restarts a strip,
//! every second triangle has its winding flipped to keep the orientation, and triangles with
//! a repeated index (the stitching between strips) are dropped. Every other element and
//! property is skipped, in all three encodings.
//!
//! Errors give a line for the header and the ascii body, and a byte offset in the file for
//! the binary body. Counts must be non-negative integers, list lengths too. In ascii, a value
//! of a `float` property beyond single precision (`1e39`) is an error, as in binary, where it
//! could only be infinite; an integer beyond 64 bits is one as well. Header lines may end in
//! LF, CR LF or a lone CR; after a header of lone CRs an LF is the first byte of a binary
//! body, not part of the `end_header` line.
//!
//! Writing: [`PlyWriter`] writes `x y z` as `double` (exact), extra per-vertex scalar
//! properties as `float` or `double`, and one `face` element of triangles with a `uchar`
//! count and `int` indices.
//!
//! Limits: 64-bit integer types (not in the format's definition) are not accepted; list
//! properties other than the face indices must have integer counts.

mod ascii;
mod binary;
pub(super) mod edges;
mod header;
#[cfg(test)]
mod tests;
mod writer;

use super::MeshData;
use super::text::{Lines, Source, Words, parse_f64, parse_i64, show};
use super::triangulate::Triangulator;
use crate::error::{Location, Result};
use ascii::Ascii;
use binary::{Binary, Block, decode_f64};
use header::{Element, Header, Kind, Property, Role, Scalar, parse_header};
pub use writer::{PlyWriter, PropertyValues, VertexProperty, write_ply};
pub(crate) use writer::{RecordWriter, index_type};

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

/// Why a value could not be read.
enum Fault {
    /// The data ends before the value.
    End,
    /// Not a number (ascii).
    NotNumber(String),
    /// A number where an integer is needed (ascii).
    NotInteger(String),
    /// A number beyond what the property's type holds (ascii): an integer beyond 64 bits, or
    /// a `float` (single precision) value that would be infinite, as a binary file cannot
    /// hold. Type name and token.
    OutOfRange(&'static str, String),
}

impl Fault {
    /// The error message for this fault in record `record` of `element`.
    fn message(self, element: &Element, record: usize) -> String {
        let what = format!("{} {record}", element.name);
        match self {
            Fault::End => format!(
                "truncated data: the file ends in {what} (of {} {} elements)",
                element.count, element.name
            ),
            Fault::NotNumber(t) => format!("non-numeric token '{t}' in {what}"),
            Fault::NotInteger(t) => format!("'{t}' in {what} is not an integer"),
            Fault::OutOfRange(ty, t) => {
                format!("'{t}' in {what} is out of range for its type ({ty})")
            }
        }
    }
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
    let mut polygons = Triangulator::default();

    for element in &header.elements {
        let record_error = |values: &V, record: usize, fault: Fault| {
            source.at(values.location(), fault.message(element, record))
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
        // A record without properties holds nothing: skipped whatever the count claims
        // (a header's word alone must not cost time either).
        if element.properties.is_empty() {
            continue;
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
                    &mut polygons,
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
    polygons.finish(&mut faces, &positions);
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
    polygons: &mut Triangulator,
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
                Role::Polygon => {
                    read_polygon(values, n, item, vertex_count, corners, faces, polygons)?;
                }
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
    polygons: &mut Triangulator,
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
    // Triangulated once all vertices are read (a face element may come first).
    polygons.push_later(faces, corners);
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
