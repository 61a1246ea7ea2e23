//! Reading and writing meshes: one front door over one file per format.
//!
//! | format | read | write | file |
//! | --- | --- | --- | --- |
//! | Wavefront OBJ | polygons, `v//vn`, `v/vt/vn`, negative indices | `v`, `f` | `obj.rs` |
//! | Stanford PLY | ascii, binary little/big endian; faces and `tristrips` | ascii, binary, extra vertex properties | `ply.rs` |
//! | OFF | `OFF`, `COFF`, `NOFF`, ... | `OFF` | `off.rs` |
//! | STL | ascii and binary, vertices welded | binary (single precision) | `stl.rs` |
//!
//! Feature lines have their own files (OBJ polylines, JSON, PLY edges) in [`lines`].
//!
//! Every reader takes the whole file as bytes and parses it in one pass with a hand-written
//! scanner, for speed and so that every error names the file and the line (text) or byte
//! offset (binary) where it was found. Polygons become triangles in `triangulate.rs`: the fan
//! from the first corner when none of its triangles folds back (every convex polygon), ears
//! cut along the outline otherwise. The readers produce
//! [`MeshData`] (see [`parse_mesh_bytes`]); [`read_mesh`] and [`read_mesh_bytes`] then build a
//! [`TriMesh`], which drops and counts triangles with a repeated index or zero area.
//!
//! Damaged files are errors, never a mesh read in silence with parts missing or made up:
//! a file cut short (anywhere in an ascii STL, too, up to its `endsolid`), a count that
//! disagrees with the data (a binary STL whose header counts fewer triangles than follow),
//! negative or oversized counts and indices, values a binary file of the declared type could
//! not hold (a PLY `float` of `1e39`), binary OFF (not supported). Things that are normal
//! keep working: degenerate faces (counted by the mesh), padding after the last binary STL
//! record, comments, a byte-order mark, and lines that end in LF, CR LF or a lone CR (classic
//! Mac OS) in every text format; line numbers count the lines as an editor shows them.
//!
//! Writers store `f64` exactly: text formats use Rust's shortest round-trip formatting and
//! binary PLY uses `double`, so writing then reading gives back the same bits. They write the
//! faces the mesh kept (degenerate input faces are not written back) and every vertex, in
//! order, including unreferenced ones.

pub mod lines;
pub mod mask;
mod obj;
mod off;
mod ply;
mod stl;
mod text;
mod triangulate;

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard, PoisonError};

use crate::error::{Error, Location, Result};
use crate::mesh::{TriMesh, Vec3};

pub use ply::{PlyEncoding, PlyWriter, PropertyValues, VertexProperty, write_ply};
use text::Source;

/// A mesh file format.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Format {
    /// Wavefront OBJ.
    Obj,
    /// Stanford PLY (ascii or binary).
    Ply,
    /// Object File Format.
    Off,
    /// STL (ascii or binary).
    Stl,
}

impl Format {
    /// Every format, in a fixed order.
    pub const ALL: [Format; 4] = [Format::Obj, Format::Ply, Format::Off, Format::Stl];

    /// The format a file extension names (case-insensitive, without the dot).
    pub fn from_extension(extension: &str) -> Option<Format> {
        Format::ALL
            .into_iter()
            .find(|f| f.extension().eq_ignore_ascii_case(extension))
    }

    /// The format a path's extension names.
    pub fn from_path(path: &Path) -> Option<Format> {
        Format::from_extension(path.extension()?.to_str()?)
    }

    /// The usual file extension, lower case without the dot.
    pub fn extension(self) -> &'static str {
        match self {
            Format::Obj => "obj",
            Format::Ply => "ply",
            Format::Off => "off",
            Format::Stl => "stl",
        }
    }

    /// `format` if given, otherwise the format named by `path`'s extension.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] naming the file when the extension is missing or unknown.
    pub fn resolve(path: &Path, format: Option<Format>) -> Result<Format> {
        if let Some(f) = format {
            return Ok(f);
        }
        Format::from_path(path).ok_or_else(|| {
            let extension = match path.extension() {
                Some(e)
                    if COMPRESSED_EXTENSIONS
                        .contains(&e.to_string_lossy().to_lowercase().as_str()) =>
                {
                    format!(
                        "a compressed file ('.{}'): decompress it first",
                        e.to_string_lossy()
                    )
                }
                Some(e) => format!("unknown extension '.{}'", e.to_string_lossy()),
                None => "no file extension".to_string(),
            };
            Error::InvalidInput(format!(
                "{}: {extension}: cannot tell the mesh format (known: .obj, .ply, .off, .stl; \
                 or force a format)",
                path.display()
            ))
        })
    }
}

impl std::fmt::Display for Format {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Format::Obj => "OBJ",
            Format::Ply => "PLY",
            Format::Off => "OFF",
            Format::Stl => "STL",
        })
    }
}

/// Positions and triangles as a reader produces them, before [`TriMesh`] checks them and
/// builds connectivity.
///
/// The readers guarantee finite coordinates and in-range indices; triangles may still repeat
/// an index (a polygon that does) or have zero area.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct MeshData {
    /// Vertex positions in file order.
    pub positions: Vec<[f64; 3]>,
    /// Triangles (polygons triangulated), indices into `positions`.
    pub faces: Vec<[u32; 3]>,
}

impl MeshData {
    /// Builds the [`TriMesh`] (dropping and counting degenerate triangles).
    ///
    /// # Errors
    /// As [`TriMesh::from_arrays`]; `name` labels the error.
    pub fn into_mesh(self, name: &Path) -> Result<TriMesh> {
        TriMesh::from_arrays(self.positions, self.faces).map_err(|e| match e {
            Error::InvalidInput(message) => Source::new(name).whole(message),
            other => other,
        })
    }
}

/// Reads a mesh, choosing the format by extension (case-insensitive) unless `format` is given.
///
/// ```
/// use crestline::io::{Format, WriteOptions, read_mesh, write_mesh};
///
/// # fn main() -> Result<(), Box<dyn std::error::Error>> {
/// let folder = tempfile::tempdir()?;
/// let path = folder.path().join("sphere.ply");
/// let sphere = crestline::shapes::icosphere(1.0, 2);
/// write_mesh(&path, &sphere, Format::Ply, &WriteOptions::default())?;
///
/// // The format from the extension (`Some(Format::Ply)` would say it whatever the name).
/// let mesh = read_mesh(&path, None)?;
/// assert_eq!((mesh.num_vertices(), mesh.num_faces()), (162, 320));
///
/// // A missing file is an error that names it.
/// let missing = folder.path().join("missing.obj");
/// let e = read_mesh(&missing, None).unwrap_err();
/// assert!(e.to_string().contains("missing.obj"));
/// # Ok(())
/// # }
/// ```
///
/// # Errors
/// [`Error::Io`] when the file cannot be read, [`Error::InvalidInput`] for an unknown
/// extension, [`Error::Parse`] naming the file and position for malformed contents.
pub fn read_mesh(path: &Path, format: Option<Format>) -> Result<TriMesh> {
    read_mesh_data(path, format)?.into_mesh(path)
}

/// Reads a mesh's positions and triangles as the file holds them (polygons triangulated),
/// without building connectivity: for callers that hand the arrays on (the Python bindings).
///
/// # Errors
/// As [`read_mesh`], except for the checks of [`MeshData::into_mesh`].
pub fn read_mesh_data(path: &Path, format: Option<Format>) -> Result<MeshData> {
    let format = Format::resolve(path, format)?;
    let bytes = read_file(path).map_err(|e| Error::io(path, e))?;
    // The file's bytes are freed on return, before any connectivity is built.
    parse_mesh_bytes(&bytes, format, path)
}

/// Files of at least twice this size are read in pieces of this size, in parallel.
const READ_PIECE: usize = 4 << 20;

/// Reads a whole file, as [`std::fs::read`] does. A large file is read in pieces of
/// [`READ_PIECE`] bytes by the worker threads, each piece into its place in one buffer: most of
/// the time of reading a file the system has cached goes into copying it and into the first
/// touch of the buffer's fresh pages, and both are then shared between the cores (an 84 MB
/// file: see `docs/benchmarks-history.md`, session 7). Bytes appended while the pieces are read are read
/// after them; a file that shrinks meanwhile gives an "unexpected end of file" error.
pub(crate) fn read_file(path: &Path) -> std::io::Result<Vec<u8>> {
    #[cfg(unix)]
    {
        use rayon::prelude::*;
        use std::io::{Read, Seek, SeekFrom};
        use std::os::unix::fs::FileExt;

        let mut file = File::open(path)?;
        let metadata = file.metadata()?;
        let len = usize::try_from(metadata.len()).unwrap_or(usize::MAX);
        if metadata.is_file() && len >= 2 * READ_PIECE && len < isize::MAX as usize {
            let mut bytes = vec![0u8; len];
            bytes
                .par_chunks_mut(READ_PIECE)
                .enumerate()
                .try_for_each(|(i, piece)| file.read_exact_at(piece, (i * READ_PIECE) as u64))?;
            file.seek(SeekFrom::Start(len as u64))?;
            file.read_to_end(&mut bytes)?;
            return Ok(bytes);
        }
    }
    std::fs::read(path)
}

/// Parses a whole file held in memory and builds the mesh; `name` labels errors.
///
/// # Errors
/// [`Error::Parse`] naming `name` and the position of the fault.
pub fn read_mesh_bytes(bytes: &[u8], format: Format, name: &Path) -> Result<TriMesh> {
    parse_mesh_bytes(bytes, format, name)?.into_mesh(name)
}

/// Parses a whole file held in memory into positions and triangles, without building
/// connectivity (the step benchmarks measure).
///
/// # Errors
/// [`Error::Parse`] naming `name` and the position of the fault.
pub fn parse_mesh_bytes(bytes: &[u8], format: Format, name: &Path) -> Result<MeshData> {
    let source = Source::new(name);
    if bytes.is_empty() {
        return Err(source.whole("empty file"));
    }
    // A UTF-8 byte-order mark before a text header is skipped (a binary STL's 80-byte header
    // may start with any bytes, so there only before `solid`); byte offsets in errors still
    // count it.
    let text = text::strip_bom(bytes);
    let (bytes, skipped) = match format {
        Format::Stl if !text.trim_ascii_start().starts_with(b"solid") => (bytes, 0),
        _ => (text, bytes.len() - text.len()),
    };
    let data = match format {
        Format::Obj => obj::parse(bytes, source),
        Format::Ply => ply::parse(bytes, source),
        Format::Off => off::parse(bytes, source),
        Format::Stl => stl::parse(bytes, source),
    }
    .map_err(|e| match e {
        Error::Parse {
            path,
            location: Location::Byte(at),
            message,
        } if skipped > 0 => Error::Parse {
            path,
            location: Location::Byte(at + skipped as u64),
            message,
        },
        e => e,
    });
    let data = match data {
        Ok(data) if data.positions.is_empty() => {
            Err(source.whole("no vertices: the file holds no mesh"))
        }
        other => other,
    };
    data.map_err(|e| with_format_hint(e, bytes, format))
}

/// Extensions of compressed files, which are not read: [`Format::resolve`] says to decompress
/// them first.
const COMPRESSED_EXTENSIONS: [&str; 7] = ["gz", "zip", "zst", "xz", "bz2", "7z", "z"];

/// The compression a file's first bytes announce (gzip, zip, zstd, xz, bzip2, 7z), if any.
pub fn sniff_compression(bytes: &[u8]) -> Option<&'static str> {
    const MAGIC: [(&[u8], &str); 6] = [
        (&[0x1f, 0x8b], "gzip"),
        (b"PK\x03\x04", "zip"),
        (&[0x28, 0xb5, 0x2f, 0xfd], "zstd"),
        (&[0xfd, b'7', b'z', b'X', b'Z', 0x00], "xz"),
        (b"BZh", "bzip2"),
        (&[b'7', b'z', 0xbc, 0xaf, 0x27, 0x1c], "7z"),
    ];
    MAGIC
        .iter()
        .find(|(magic, _)| bytes.starts_with(magic))
        .map(|&(_, name)| name)
}

/// A parse error of a file whose contents look like another format than the one it was read
/// as (a PLY file named `.obj`, the wrong `--input-format` on standard input), or like a
/// compressed file (a `.obj` that is gzipped), says so.
fn with_format_hint(error: Error, bytes: &[u8], format: Format) -> Error {
    if let (
        Error::Parse {
            path,
            location,
            message,
        },
        Some(compression),
    ) = (&error, sniff_compression(bytes))
    {
        return Error::Parse {
            path: path.clone(),
            location: *location,
            message: format!(
                "{message} (the file is {compression}-compressed: decompress it first)"
            ),
        };
    }
    match (error, sniff_format(bytes)) {
        (
            Error::Parse {
                path,
                location,
                message,
            },
            Some(looks),
        ) if looks != format => Error::Parse {
            path,
            location,
            message: format!("{message} (the contents look like {looks}, not {format})"),
        },
        (error, _) => error,
    }
}

/// The format a file's first bytes announce, when they announce one clearly: PLY's `ply`
/// line, OFF's keyword, an ascii STL's `solid` followed by a `facet`, a binary STL whose size
/// matches its triangle count, OBJ's vertex records before anything that is not OBJ.
pub fn sniff_format(bytes: &[u8]) -> Option<Format> {
    let text = text::strip_bom(bytes).trim_ascii_start();
    let head = &text[..text.len().min(4096)];
    let first_word = head
        .split(|b| b.is_ascii_whitespace())
        .next()
        .unwrap_or_default();
    if first_word == b"ply" {
        return Some(Format::Ply);
    }
    let off_keyword = first_word
        .strip_suffix(b"OFF")
        .is_some_and(|prefix| prefix.iter().all(|b| b"STCN4n".contains(b)));
    if off_keyword {
        return Some(Format::Off);
    }
    if first_word == b"solid" && head.windows(5).any(|w| w == b"facet") {
        return Some(Format::Stl);
    }
    if bytes.len() >= 84 {
        let count = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as u64;
        if count > 0 && 84 + 50 * count == bytes.len() as u64 {
            return Some(Format::Stl);
        }
    }
    // OBJ: the records before the first vertex are comments, blank lines or OBJ keywords.
    for line in head.split(|&b| b == b'\n') {
        let keyword = line
            .split(|b| b.is_ascii_whitespace())
            .find(|w| !w.is_empty());
        match keyword {
            None => continue,
            Some(w) if w.starts_with(b"#") => continue,
            Some(b"v") => return Some(Format::Obj),
            Some(b"mtllib" | b"o" | b"g" | b"s" | b"vn" | b"vt" | b"usemtl") => continue,
            Some(_) => return None,
        }
    }
    None
}

/// How meshes are written.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct WriteOptions {
    /// Encoding of PLY files.
    ///
    /// Default value: [`PlyEncoding::BinaryLittleEndian`] (compact, exact and fast).
    pub ply_encoding: PlyEncoding,
}

impl WriteOptions {
    /// The defaults, as a constant.
    pub const DEFAULT: WriteOptions = WriteOptions {
        ply_encoding: PlyEncoding::BinaryLittleEndian,
    };

    /// These options with another PLY encoding.
    pub fn with_ply_encoding(mut self, encoding: PlyEncoding) -> Self {
        self.ply_encoding = encoding;
        self
    }
}

impl Default for WriteOptions {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// Writes `mesh` to `path` in `format`, all or nothing (see [`write_atomically`]).
///
/// STL stores single precision and no shared vertices, so it is the one lossy format.
///
/// # Errors
/// [`Error::Io`] naming the file.
pub fn write_mesh(
    path: &Path,
    mesh: &TriMesh,
    format: Format,
    options: &WriteOptions,
) -> Result<()> {
    write_atomically(path, |out| write_mesh_to(out, mesh, format, options))
}

/// Writes the file `path` through `write`, all or nothing: the bytes go to a new temporary
/// file in the same folder, which replaces `path` (by a rename) only once `write` has
/// succeeded and everything is flushed. A failure midway (a full disk, a value that cannot be
/// written, an interrupted process) leaves any earlier file at `path` as it was and no
/// partial file behind; writing over the file a result was read from is safe. The new file
/// gets the usual permissions (read-write, less the umask).
///
/// # Errors
/// [`Error::Io`] naming `path` when the folder does not exist (`out/lines.obj: the folder
/// out does not exist`, as [`check_output_folder`] says) or cannot be written to, when
/// `path` is a folder, or when `write` fails.
pub fn write_atomically(
    path: &Path,
    write: impl FnOnce(&mut BufWriter<&File>) -> std::io::Result<()>,
) -> Result<()> {
    let fail = |e: std::io::Error| Error::io(path, e);
    let given = path;
    // A device, a pipe or a socket (`/dev/null`, `>(…)`, a FIFO) is written into: a rename
    // would replace it with a file. A symbolic link is followed: its target is replaced, the
    // link stays.
    if std::fs::metadata(path).is_ok_and(|m| !m.is_file() && !m.is_dir()) {
        let file = File::create(path).map_err(fail)?;
        let mut out = BufWriter::new(&file);
        return write(&mut out).and_then(|()| out.flush()).map_err(fail);
    }
    let resolved;
    let path = if std::fs::symlink_metadata(path).is_ok_and(|m| m.file_type().is_symlink()) {
        resolved = link_target(path).map_err(fail)?;
        resolved.as_path()
    } else {
        path
    };
    let folder = folder_of(path);
    // Otherwise the error would name the temporary file, not the folder.
    if !folder.is_dir() {
        return Err(missing_folder(given, folder));
    }
    let mut builder = tempfile::Builder::new();
    builder.prefix(".crestline-").suffix(".part");
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        builder.permissions(std::fs::Permissions::from_mode(0o666));
    }
    // Dropped on every early return, the temporary file removes itself.
    let temporary = builder.tempfile_in(folder).map_err(fail)?;
    let in_flight = InFlight::register(temporary.path());
    let mut out = BufWriter::new(temporary.as_file());
    write(&mut out).and_then(|()| out.flush()).map_err(fail)?;
    drop(out);
    // Under the lock, so that `abandon_writes` sees either the temporary file or the whole
    // file in its place, never a rename half-way.
    let writes = in_flight_writes();
    if !writes.contains(&in_flight.0) {
        return Err(fail(std::io::Error::new(
            std::io::ErrorKind::Interrupted,
            "interrupted: the write was abandoned",
        )));
    }
    temporary.persist(path).map_err(|e| fail(e.error))?;
    drop(writes);
    Ok(())
}

/// Refuses an output `path` in a folder that does not exist, with the message
/// [`write_atomically`] gives: for a front end to check before the work rather than after it.
///
/// # Errors
/// [`Error::Io`] of kind `NotFound`: `out/lines.obj: the folder out does not exist`.
pub fn check_output_folder(path: &Path) -> Result<()> {
    let folder = folder_of(path);
    if folder.is_dir() {
        Ok(())
    } else {
        Err(missing_folder(path, folder))
    }
}

/// The folder `path` is in (`.` for a bare file name).
fn folder_of(path: &Path) -> &Path {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    }
}

/// The error of an output `path` whose `folder` does not exist.
fn missing_folder(path: &Path, folder: &Path) -> Error {
    Error::io(
        path,
        std::io::Error::new(
            std::io::ErrorKind::NotFound,
            format!("the folder {} does not exist", folder.display()),
        ),
    )
}

/// The file a symbolic link leads to, through any chain of links (the last one may not exist
/// yet: a link made before its file).
fn link_target(link: &Path) -> std::io::Result<std::path::PathBuf> {
    let mut path = link.to_path_buf();
    for _ in 0..40 {
        if !std::fs::symlink_metadata(&path).is_ok_and(|m| m.file_type().is_symlink()) {
            return Ok(path);
        }
        let next = std::fs::read_link(&path)?;
        path = match path.parent() {
            Some(folder) if next.is_relative() => folder.join(next),
            _ => next,
        };
    }
    Err(std::io::Error::other("too many levels of symbolic links"))
}

/// Removes the temporary files of every write in progress (see [`write_atomically`]) and makes
/// any write that has not yet renamed its file fail instead: for a program stopped by a signal,
/// which ends without running destructors, so that it leaves no partial output behind. Safe to
/// call from any thread (not from a signal handler itself: it takes a lock). Writes finished
/// before the call keep their files; writes started after it are not affected.
pub fn abandon_writes() {
    let mut writes = in_flight_writes();
    for temporary in writes.drain(..) {
        // Already gone is fine: the write failed and removed it, or it never got that far.
        let _ = std::fs::remove_file(temporary);
    }
}

/// The temporary files of the writes in progress; a write whose file [`abandon_writes`] took
/// off the list must not rename it.
static IN_FLIGHT: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// The list of writes in progress, locked. A panic elsewhere while it was locked leaves it
/// usable: each change to it is a single push or removal.
fn in_flight_writes() -> MutexGuard<'static, Vec<PathBuf>> {
    IN_FLIGHT.lock().unwrap_or_else(PoisonError::into_inner)
}

/// One temporary file in [`IN_FLIGHT`], from its creation until it is renamed or dropped.
struct InFlight(PathBuf);

impl InFlight {
    fn register(temporary: &Path) -> InFlight {
        in_flight_writes().push(temporary.to_path_buf());
        InFlight(temporary.to_path_buf())
    }
}

impl Drop for InFlight {
    fn drop(&mut self) {
        let mut writes = in_flight_writes();
        if let Some(i) = writes.iter().position(|p| *p == self.0) {
            writes.swap_remove(i);
        }
    }
}

/// Writes `mesh` in `format` to any writer (buffer it: the writers issue many small writes).
///
/// # Errors
/// Whatever the writer returns.
pub fn write_mesh_to<W: Write>(
    writer: W,
    mesh: &TriMesh,
    format: Format,
    options: &WriteOptions,
) -> std::io::Result<()> {
    match format {
        Format::Obj => obj::write(writer, mesh),
        Format::Ply => PlyWriter::new(mesh)
            .encoding(options.ply_encoding)
            .write_to(writer),
        Format::Off => off::write(writer, mesh),
        Format::Stl => stl::write(writer, mesh),
    }
}

/// Writes a point as `x y z` and a newline, each coordinate as [`write_f64`] (the vertex lines
/// of the OBJ and OFF writers).
///
/// # Errors
/// As [`write_f64`].
fn write_xyz(out: &mut impl Write, p: &Vec3) -> std::io::Result<()> {
    write_f64(out, p.x)?;
    out.write_all(b" ")?;
    write_f64(out, p.y)?;
    out.write_all(b" ")?;
    write_f64(out, p.z)?;
    out.write_all(b"\n")
}

/// Writes an `f64` so that parsing it gives back the same bits, in the shortest form:
/// plain decimals for ordinary magnitudes, exponent notation for very small or large ones
/// (where plain decimals would run to hundreds of digits).
///
/// # Errors
/// As [`check_finite`], and whatever `out` returns.
#[inline]
fn write_f64(out: &mut impl Write, x: f64) -> std::io::Result<()> {
    check_finite(x)?;
    // zmij (already in the tree through serde_json) prints the same shortest round-trip
    // digits as `Display` for a third of the instructions (igea's lines: 30M against 103M),
    // and like the `{:e}` it replaced it switches to exponent form for very small and very
    // large magnitudes. Whole numbers keep `Display`'s form ("1", not "1.0").
    let mut buffer = zmij::Buffer::new();
    let text = buffer.format(x);
    out.write_all(text.strip_suffix(".0").unwrap_or(text).as_bytes())
}

/// `Ok` for a finite number. A NaN or an infinity in a result is a bug upstream: the writers
/// refuse it (and, writing all or nothing, leave no file) rather than write a number no
/// reader accepts (or, in JSON, a silent `null`).
///
/// # Errors
/// An [`std::io::ErrorKind::InvalidData`] error saying which value it was.
#[inline]
fn check_finite(x: f64) -> std::io::Result<()> {
    if x.is_finite() {
        Ok(())
    } else {
        Err(std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            format!(
                "cannot write the value {x}: every number written must be finite (a bug in \
                 crestline: please report it)"
            ),
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;

    #[test]
    fn an_output_in_a_missing_folder_names_the_folder_not_the_temporary_file() {
        let dir = tempfile::tempdir().unwrap();
        let folder = dir.path().join("no/such");
        let path = folder.join("lines.obj");
        let e = write_atomically(&path, |_| Ok(())).unwrap_err();
        let expected = format!(
            "{}: the folder {} does not exist",
            path.display(),
            folder.display()
        );
        assert_eq!(e.to_string(), expected);
        assert!(
            matches!(&e, Error::Io { cause, .. } if cause.kind() == std::io::ErrorKind::NotFound)
        );
        assert_eq!(
            check_output_folder(&path).unwrap_err().to_string(),
            expected
        );
        assert!(check_output_folder(&dir.path().join("here.obj")).is_ok());
        assert!(check_output_folder(Path::new("bare-name.obj")).is_ok());
        assert!(!folder.exists());
    }

    #[test]
    fn a_file_read_as_the_wrong_format_says_what_it_looks_like() {
        let ply = b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
                    property float z\nelement face 1\nproperty list uchar int vertex_indices\n\
                    end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
        let obj = b"# made by hand\nmtllib a.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
        let off = b"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
        let stl = b"solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n\
                    vertex 0 1 0\nendloop\nendfacet\nendsolid t\n";
        let mut binary = [0u8; 84 + 50];
        binary[80] = 1;
        let name = Path::new("m.x");
        for (bytes, looks) in [
            (&ply[..], Format::Ply),
            (&obj[..], Format::Obj),
            (&off[..], Format::Off),
            (&stl[..], Format::Stl),
            (&binary[..], Format::Stl),
        ] {
            assert_eq!(sniff_format(bytes), Some(looks));
            assert!(parse_mesh_bytes(bytes, looks, name).is_ok(), "{looks}");
            for format in Format::ALL.into_iter().filter(|&f| f != looks) {
                // Some readers make sense of another format's bytes (an OBJ reader skips what
                // it does not know); those that fail say what the contents look like.
                if let Err(e) = parse_mesh_bytes(bytes, format, name) {
                    let hint = format!("(the contents look like {looks}, not {format})");
                    assert!(e.to_string().ends_with(&hint), "{format}: {e}");
                }
            }
        }
        assert_eq!(sniff_format(b"3 0 1 2\n"), None);
        assert_eq!(sniff_format(b"hello\nv 0 0 0\n"), None);
        // A parse error of a file that looks like what it was read as has no hint.
        let e = parse_mesh_bytes(b"v 0 0 x\n", Format::Obj, name).unwrap_err();
        assert!(!e.to_string().contains("look like"), "{e}");
    }

    #[test]
    fn a_compressed_file_is_named_as_such() {
        // The start of `gzip < fandisk.obj`, of a zip archive and of a zstd frame.
        let gzip = b"\x1f\x8b\x08\x08\xa1\x4f\x27\x69\x00\x03fd.obj\x00\xad\x5b";
        let zip = b"PK\x03\x04\x14\x00\x00\x00\x08\x00fd.obj";
        let zstd = b"\x28\xb5\x2f\xfd\x24\x3c\x41\x01\x00";
        let name = Path::new("m.obj");
        for (bytes, kind) in [(&gzip[..], "gzip"), (&zip[..], "zip"), (&zstd[..], "zstd")] {
            assert_eq!(sniff_compression(bytes), Some(kind));
            for format in Format::ALL {
                let e = parse_mesh_bytes(bytes, format, name).unwrap_err();
                let hint = format!("(the file is {kind}-compressed: decompress it first)");
                assert!(e.to_string().ends_with(&hint), "{format}: {e}");
            }
        }
        assert_eq!(sniff_compression(b"v 0 0 0\n"), None);
        let e = Format::resolve(Path::new("scan.obj.gz"), None).unwrap_err();
        assert!(
            e.to_string()
                .contains("a compressed file ('.gz'): decompress it first"),
            "{e}"
        );
    }

    #[test]
    fn format_from_extension_ignores_case() {
        assert_eq!(Format::from_path(Path::new("a/B.OBJ")), Some(Format::Obj));
        assert_eq!(Format::from_path(Path::new("x.Ply")), Some(Format::Ply));
        assert_eq!(Format::from_path(Path::new("x.stl")), Some(Format::Stl));
        assert_eq!(Format::from_path(Path::new("x.off")), Some(Format::Off));
        assert_eq!(Format::from_path(Path::new("x.xyz")), None);
        assert_eq!(Format::from_path(Path::new("noext")), None);
    }

    #[test]
    fn unknown_extension_names_the_file() {
        let e = read_mesh(Path::new("scans/thing.xyz"), None).unwrap_err();
        let m = e.to_string();
        assert!(m.contains("scans/thing.xyz"), "{m}");
        assert!(m.contains("unknown extension '.xyz'"), "{m}");
        let e = read_mesh(Path::new("scans/thing"), None).unwrap_err();
        assert!(e.to_string().contains("no file extension"), "{e}");
    }

    #[test]
    fn forced_format_overrides_extension() {
        let bytes = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
        let m = read_mesh_bytes(bytes, Format::Obj, Path::new("a.txt")).unwrap();
        assert_eq!(m.num_faces(), 1);
    }

    #[test]
    fn empty_file_is_an_error_in_every_format() {
        for f in Format::ALL {
            let e = read_mesh_bytes(b"", f, Path::new("empty.x")).unwrap_err();
            assert_eq!(e.to_string(), "empty.x: empty file", "{f}");
        }
    }

    #[test]
    fn missing_file_is_an_io_error_naming_it() {
        let path = PathBuf::from("/nonexistent/dir/m.obj");
        let e = read_mesh(&path, None).unwrap_err();
        assert!(matches!(e, Error::Io { .. }));
        assert!(e.to_string().starts_with("/nonexistent/dir/m.obj: "), "{e}");
    }

    #[test]
    fn large_files_read_in_pieces_come_back_whole() {
        let dir = tempfile::tempdir().unwrap();
        // Pieces of every kind: whole ones and a short last one; and a file below the size
        // read in pieces.
        for len in [2 * READ_PIECE + 12_345, 3 * READ_PIECE, READ_PIECE + 1] {
            let bytes: Vec<u8> = (0..len).map(|i| (i * 7 + i / 4099) as u8).collect();
            let path = dir.path().join(format!("f{len}.bin"));
            std::fs::write(&path, &bytes).unwrap();
            assert!(read_file(&path).unwrap() == bytes, "{len} bytes");
        }
        let e = read_file(&dir.path().join("missing")).unwrap_err();
        assert_eq!(e.kind(), std::io::ErrorKind::NotFound);
    }

    #[cfg(unix)]
    #[test]
    fn writes_go_into_pipes_and_devices_and_through_links() {
        let dir = tempfile::tempdir().unwrap();
        let write = |path: &Path, text: &str| {
            let text = text.to_string();
            write_atomically(path, move |out| out.write_all(text.as_bytes()))
        };
        // A link to a file: the file gets the bytes, the link stays a link.
        let file = dir.path().join("file.obj");
        std::fs::write(&file, "old").unwrap();
        let link = dir.path().join("link.obj");
        std::os::unix::fs::symlink("file.obj", &link).unwrap();
        write(&link, "new").unwrap();
        assert!(
            std::fs::symlink_metadata(&link)
                .unwrap()
                .file_type()
                .is_symlink()
        );
        assert_eq!(std::fs::read_to_string(&file).unwrap(), "new");
        // A link made before its file: the file is made.
        let early = dir.path().join("early.obj");
        std::os::unix::fs::symlink("later.obj", &early).unwrap();
        write(&early, "made").unwrap();
        assert_eq!(
            std::fs::read_to_string(dir.path().join("later.obj")).unwrap(),
            "made"
        );
        // A named pipe is written into, not replaced.
        let fifo = dir.path().join("fifo");
        let made = std::process::Command::new("mkfifo").arg(&fifo).status();
        if made.is_ok_and(|s| s.success()) {
            let reader = {
                let fifo = fifo.clone();
                std::thread::spawn(move || std::fs::read_to_string(fifo).unwrap())
            };
            write(&fifo, "through").unwrap();
            assert_eq!(reader.join().unwrap(), "through");
            use std::os::unix::fs::FileTypeExt;
            assert!(std::fs::metadata(&fifo).unwrap().file_type().is_fifo());
        }
        // (Devices take the same path as pipes; not tried here: had the fix gone, the test
        // would replace /dev/null of the machine that runs it.)
    }

    #[test]
    fn floats_are_written_shortest_and_exact() {
        for x in [
            0.0,
            -0.0,
            0.1,
            1.0 / 3.0,
            -2.5e-7,
            1e300,
            f64::MIN_POSITIVE,
            5e-324,
            f64::MAX,
            123456.789,
        ] {
            let mut s = Vec::new();
            write_f64(&mut s, x).unwrap();
            let s = String::from_utf8(s).unwrap();
            let back: f64 = s.parse().unwrap();
            assert_eq!(back.to_bits(), x.to_bits(), "{s}");
            assert!(s.len() < 30, "{s}");
        }
    }
}
