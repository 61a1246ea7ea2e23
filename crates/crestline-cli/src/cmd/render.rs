//! `crestline render`: a PNG or SVG picture of a mesh, its feature lines and a field.

use std::path::PathBuf;

use anyhow::{Context, Result};

use crate::scene::{SceneArgs, parse_size};

/// Arguments of `crestline render`.
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Output picture; the extension chooses the format (.png, .svg, or .html for the viewer).
    #[arg(short, long, value_name = "PICTURE")]
    pub output: PathBuf,
    /// Image size in pixels, W or WxH [default: 1024x1024].
    #[arg(long, value_name = "W[xH]", value_parser = parse_size)]
    pub size: Option<(u32, u32)>,
    /// Do not draw the colour bar of --field.
    #[arg(long)]
    pub no_legend: bool,
}

/// Runs the subcommand.
pub fn run(args: Args) -> Result<()> {
    // Refuse bad arguments before the (possibly long) loading.
    crestline::render::PictureFormat::from_path(&args.output)?;
    let mut opts = args.scene.options();
    if let Some((w, h)) = args.size {
        opts = opts.with_size(w, h);
    }
    opts.legend = !args.no_legend;
    opts.validate()?;
    let scene = args.scene.load()?;
    crestline::render::write_picture(
        &args.output,
        &scene.mesh,
        scene.lines.as_ref(),
        scene.field.as_deref(),
        &opts,
    )
    .with_context(|| format!("cannot render {}", args.output.display()))?;
    eprintln!("wrote {}", args.output.display());
    Ok(())
}
