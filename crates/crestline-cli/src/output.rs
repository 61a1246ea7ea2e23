//! Where results go: a file, or standard output for the path `-`.

use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use anyhow::{Result, bail};
use crestline::io::{Format, PlyEncoding, write_atomically};

use crate::input::{FormatArg, is_dash};

/// Writes to standard output through a buffer. A reader that stops early (`| head`) is not an
/// error: the rest of the output is simply not wanted.
pub fn to_stdout(write: impl FnOnce(&mut dyn Write) -> std::io::Result<()>) -> Result<()> {
    let stdout = std::io::stdout();
    let mut out = BufWriter::new(stdout.lock());
    match write(&mut out).and_then(|()| out.flush()) {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
        Err(e) => bail!("cannot write to standard output: {e}"),
    }
}

/// Writes `path` all or nothing ([`crestline::io::write_atomically`]), or standard output for
/// `-`.
pub fn to_path_or_stdout(
    path: &Path,
    write: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> Result<()> {
    if is_dash(path) {
        to_stdout(write)
    } else {
        Ok(write_atomically(path, |out| write(out))?)
    }
}

/// Checks an output before the work. Refuses an output in a folder that does not exist (on a
/// large mesh the error came after minutes of work), and one that is one of `inputs` (the
/// same file by any path or link): the command's result (feature lines, a picture, a table)
/// would replace the file it was made from. `subdivide` and `simplify`, whose output is a
/// mesh again, may write in place.
pub fn check_output(output: &Path, inputs: &[Option<&Path>]) -> Result<()> {
    if !is_dash(output) {
        crestline::io::check_output_folder(output)?;
    }
    for input in inputs.iter().flatten() {
        if !is_dash(output) && !is_dash(input) && same_file(output, input) {
            bail!(
                "{}: the output is the input {}: writing it would replace that file; choose \
                 another output",
                output.display(),
                input.display()
            );
        }
    }
    Ok(())
}

/// The extensions of the files crestline writes, with the format each names.
const EXTENSIONS: [(&str, &str); 10] = [
    ("obj", "OBJ"),
    ("ply", "PLY"),
    ("off", "OFF"),
    ("stl", "STL"),
    ("json", "JSON"),
    ("csv", "CSV"),
    ("png", "PNG"),
    ("svg", "SVG"),
    ("html", "HTML"),
    ("htm", "HTML"),
];

/// The extension of `path`, lower case, when it is one of the formats crestline writes.
pub fn known_extension(path: &Path) -> Option<String> {
    let extension = path.extension()?.to_str()?.to_ascii_lowercase();
    EXTENSIONS
        .iter()
        .any(|&(e, _)| e == extension)
        .then_some(extension)
}

/// Refuses an output whose extension names another format than the one written (`-o x.csv`
/// holding PLY, `view -o v.png` holding HTML): `written` says what would be written,
/// `expected` lists the extensions that fit it, `remedy` says what to do instead.
/// Standard output, unknown extensions and none are left alone (the format comes from an
/// option or the command's default there).
pub fn check_extension(path: &Path, written: &str, expected: &[&str], remedy: &str) -> Result<()> {
    if is_dash(path) {
        return Ok(());
    }
    let Some(extension) = known_extension(path) else {
        return Ok(());
    };
    if expected.contains(&extension.as_str()) {
        return Ok(());
    }
    let named = EXTENSIONS
        .iter()
        .find(|&&(e, _)| e == extension)
        .map_or("another format", |&(_, name)| name);
    bail!(
        "{}: a .{extension} file holds {named}, but {written} would be written into it: \
         {remedy}",
        path.display()
    );
}

/// True when both paths exist and are the same file.
fn same_file(a: &Path, b: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        match (std::fs::metadata(a), std::fs::metadata(b)) {
            (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
            _ => false,
        }
    }
    #[cfg(not(unix))]
    {
        matches!((a.canonicalize(), b.canonicalize()), (Ok(a), Ok(b)) if a == b)
    }
}

/// `--ascii` of the commands that write PLY vertex properties (`curvature`, `distance`).
#[derive(Debug, Clone, Copy, clap::Args)]
pub struct PlyEncodingArg {
    /// Write PLY as ascii instead of binary.
    #[arg(long)]
    pub ascii: bool,
}

impl PlyEncodingArg {
    /// The PLY encoding asked for (binary little-endian by default).
    pub fn encoding(self) -> PlyEncoding {
        if self.ascii {
            PlyEncoding::Ascii
        } else {
            PlyEncoding::BinaryLittleEndian
        }
    }
}

/// `-o` and `--format` of the commands that write a mesh (`simplify`, `subdivide`).
#[derive(Debug, Clone, clap::Args)]
pub struct MeshOutputArgs {
    /// Output mesh, or `-` for standard output; the format follows the extension (.obj,
    /// .ply, .off, .stl) unless --format is given, which then refuses another format's
    /// extension.
    #[arg(short, long)]
    pub output: PathBuf,
    /// Output format (needed for standard output).
    #[arg(long, value_enum)]
    pub format: Option<FormatArg>,
}

impl MeshOutputArgs {
    /// The format the mesh is written in ([`mesh_format`]).
    pub fn format(&self) -> Result<Format> {
        mesh_format(&self.output, self.format)
    }
}

/// The format of a mesh written to `path`: `format` when given (refusing an extension of
/// another format), else the extension's; for standard output `format` is needed.
pub fn mesh_format(path: &Path, format: Option<FormatArg>) -> Result<Format> {
    match format {
        Some(f) => {
            let format = Format::from(f);
            let extension = format.extension();
            check_extension(
                path,
                &format!("{format} (--format {extension})"),
                &[extension],
                &format!("give an output ending in .{extension}"),
            )?;
            Ok(format)
        }
        None if is_dash(path) => {
            bail!("writing the mesh to standard output (-o -): give its format with --format")
        }
        None => Ok(Format::resolve(path, None)?),
    }
}

/// What messages call the output.
pub fn display(path: &Path) -> String {
    if is_dash(path) {
        "standard output".into()
    } else {
        path.display().to_string()
    }
}
