//! Writing PLY: [`PlyWriter`] for meshes with extra vertex properties, and the record
//! writer the line files share.

use std::borrow::Cow;
use std::io::Write;
use std::path::Path;

use super::PlyEncoding;
use crate::error::{Error, Result};
use crate::io::write_f64;
use crate::mesh::TriMesh;

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

    /// Writes the file to `path`, all or nothing (see [`crate::io::write_atomically`]).
    ///
    /// # Errors
    /// [`Error::Io`] naming the file.
    pub fn write(&self, path: &Path) -> Result<()> {
        crate::io::write_atomically(path, |out| self.write_to(out))
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
pub(crate) fn index_type(vertex_count: usize) -> &'static str {
    if vertex_count <= i32::MAX as usize {
        "int"
    } else {
        "uint"
    }
}

/// Writes records value by value in either encoding: ascii separates values with spaces and
/// ends records with a line break, binary concatenates bytes.
pub(crate) struct RecordWriter<W: Write> {
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
        crate::io::check_finite(x)?;
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
        crate::io::check_finite(f64::from(x))?;
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
