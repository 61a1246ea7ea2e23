//! Loading the input mesh: a file given by the user, or the built-in example.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use clap::ValueEnum;
use crestline::TriMesh;
use crestline::io::Format;

/// The built-in example: the fandisk CAD part (see `crates/crestline/fixtures/README.md`).
const BUILT_IN_EXAMPLE: &[u8] = include_bytes!("../../crestline/fixtures/fandisk.obj");

/// Formats a user can force with `--format`.
#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum FormatArg {
    /// Wavefront OBJ.
    Obj,
    /// Stanford PLY.
    Ply,
    /// Object File Format.
    Off,
    /// STL, ascii or binary.
    Stl,
}

impl From<FormatArg> for Format {
    fn from(f: FormatArg) -> Self {
        match f {
            FormatArg::Obj => Format::Obj,
            FormatArg::Ply => Format::Ply,
            FormatArg::Off => Format::Off,
            FormatArg::Stl => Format::Stl,
        }
    }
}

/// Reads `path`, or builds the built-in example when it is `None` (and says so on stderr).
pub fn load_mesh(path: Option<&PathBuf>, format: Option<FormatArg>) -> Result<(TriMesh, String)> {
    match path {
        Some(p) => {
            // Every reading error already names the file (and the position in it).
            let mesh = crestline::io::read_mesh(p, format.map(Into::into))
                .context("cannot load the mesh")?;
            Ok((mesh, p.display().to_string()))
        }
        None => {
            eprintln!(
                "no mesh given: using the built-in example (fandisk, a CAD part with sharp creases)"
            );
            let name = "fandisk.obj (built-in)";
            let mesh =
                crestline::io::read_mesh_bytes(BUILT_IN_EXAMPLE, Format::Obj, Path::new(name))?;
            Ok((mesh, name.into()))
        }
    }
}
