//! `crestline view`: a self-contained HTML file to turn the mesh and its lines around in a
//! browser.

use std::path::PathBuf;

use anyhow::{Context, Result};

use crate::scene::SceneArgs;

/// Arguments of `crestline view`.
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Output HTML file.
    #[arg(short, long, value_name = "VIEW.html")]
    pub output: PathBuf,
}

/// Runs the subcommand.
pub fn run(args: Args) -> Result<()> {
    let opts = args.scene.options();
    opts.validate()?;
    let scene = args.scene.load()?;
    crestline::render::write_html(
        &args.output,
        &scene.mesh,
        scene.lines.as_ref(),
        scene.field.as_deref(),
        &opts,
    )
    .with_context(|| format!("cannot write {}", args.output.display()))?;
    eprintln!("wrote {}", args.output.display());
    Ok(())
}
