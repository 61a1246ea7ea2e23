//! `crestline info`: counts and health figures of a mesh.

use std::path::PathBuf;

use anyhow::Result;

use crate::input::{FormatArg, load_mesh};

/// Arguments of `crestline info`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Mesh file (OBJ, PLY, OFF, STL). Without it, a built-in example is used.
    pub mesh: Option<PathBuf>,
    /// Read as this format instead of guessing from the extension.
    #[arg(long, value_enum)]
    pub format: Option<FormatArg>,
    /// Print one JSON object instead of text.
    #[arg(long)]
    pub json: bool,
}

/// Runs the subcommand.
pub fn run(args: Args) -> Result<()> {
    let (mesh, name) = load_mesh(args.mesh.as_ref(), args.format)?;
    let info = mesh.info();
    if args.json {
        println!("{}", serde_json::to_string_pretty(&info)?);
    } else {
        println!("{name}");
        println!("{info}");
    }
    Ok(())
}
