//! `crestline info`: counts and health figures of a mesh.

use anyhow::Result;

use crate::input::MeshArgs;

/// Arguments of `crestline info`.
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(flatten)]
    pub input: MeshArgs,
    /// Print one JSON object instead of text.
    #[arg(long)]
    pub json: bool,
}

/// Runs the subcommand.
pub fn run(args: Args) -> Result<()> {
    let (mesh, name) = crate::progress::step("reading", || args.input.load())?;
    let info = mesh.info();
    if args.json {
        println!("{}", serde_json::to_string_pretty(&info)?);
    } else {
        println!("{name}");
        println!("{info}");
    }
    Ok(())
}
