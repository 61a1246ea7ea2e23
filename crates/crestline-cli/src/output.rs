//! Where results go: a file, or standard output for the path `-`.

use std::io::{BufWriter, Write};
use std::path::Path;

use anyhow::{Result, bail};
use crestline::io::Format;

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

/// The format of a mesh written to `path`: `format` when given, else the extension's; for
/// standard output `format` is needed.
pub fn mesh_format(path: &Path, format: Option<FormatArg>) -> Result<Format> {
    match format {
        Some(f) => Ok(f.into()),
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
