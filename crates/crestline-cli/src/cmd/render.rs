//! `crestline render`: a PNG or SVG picture (or the HTML viewer) of a mesh, its feature lines
//! and a field.

use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use clap::ValueEnum;
use crestline::render::{PictureFormat, render_html, render_png, render_svg, write_picture};

use crate::input::is_dash;
use crate::output::{check_extension, display, to_path_or_stdout};
use crate::progress::{self, note};
use crate::scene::{SceneArgs, WireframeArgs, parse_size, resolve_up};

/// Picture formats.
#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum PictureFormatArg {
    /// Raster image.
    Png,
    /// Raster mesh under vector lines.
    Svg,
    /// The interactive WebGL viewer.
    Html,
}

/// Arguments of `crestline render`.
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Output picture, or `-` for standard output; the extension chooses the format (.png,
    /// .svg, or .html for the viewer) unless --format is given (which then refuses the
    /// extension of another format).
    #[arg(short, long, value_name = "PICTURE")]
    pub output: PathBuf,
    /// Output format (needed for standard output).
    #[arg(long, value_enum)]
    pub format: Option<PictureFormatArg>,
    /// Image size in pixels, W or WxH [default: 1024x1024].
    #[arg(long, value_name = "W[xH]", value_parser = parse_size, allow_negative_numbers = true)]
    pub size: Option<(u32, u32)>,
    /// Do not draw the colour bar of --field.
    #[arg(long)]
    pub no_legend: bool,
    #[command(flatten)]
    pub wireframe: WireframeArgs,
}

/// Runs the subcommand.
pub fn run(args: Args) -> Result<()> {
    // Refuse bad arguments before the (possibly long) loading.
    let format = match (args.format, is_dash(&args.output)) {
        (Some(PictureFormatArg::Png), _) => PictureFormat::Png,
        (Some(PictureFormatArg::Svg), _) => PictureFormat::Svg,
        (Some(PictureFormatArg::Html), _) => PictureFormat::Html,
        (None, true) => {
            bail!("writing the picture to standard output (-o -): give its format with --format")
        }
        (None, false) => PictureFormat::from_path(&args.output)?,
    };
    if args.wireframe.wireframe && format == PictureFormat::Html {
        bail!("--wireframe: the HTML viewer draws no wireframe; write a .png or .svg picture");
    }
    let mut opts = args.scene.options();
    if let Some((w, h)) = args.size {
        opts = opts.with_size(w, h);
    }
    opts.legend = !args.no_legend;
    opts.wireframe = args.wireframe.wireframe;
    opts.validate()?;
    args.scene.check_output(&args.output)?;
    if let Some(given) = args.format {
        let extensions = match given {
            PictureFormatArg::Png => &["png"][..],
            PictureFormatArg::Svg => &["svg"],
            PictureFormatArg::Html => &["html", "htm"],
        };
        let name = format!("{given:?}").to_ascii_lowercase();
        check_extension(
            &args.output,
            &format!("{} (--format {name})", name.to_ascii_uppercase()),
            extensions,
            &format!("give an output ending in .{}", extensions[0]),
        )?;
    }
    let scene = args.scene.load()?;
    opts.up = resolve_up(opts.up, &scene.mesh);
    let (mesh, lines, field) = (&scene.mesh, scene.lines.as_ref(), scene.field.as_deref());
    let picture = || -> Result<Vec<u8>> {
        Ok(match format {
            PictureFormat::Png => render_png(mesh, lines, field, &opts)?,
            PictureFormat::Svg => render_svg(mesh, lines, field, &opts)?.into_bytes(),
            PictureFormat::Html => render_html(mesh, lines, field, &opts)?.into_bytes(),
        })
    };
    progress::step("drawing", || -> Result<()> {
        if is_dash(&args.output) || args.format.is_some() {
            // The format as given, whatever the extension.
            let bytes = picture()?;
            to_path_or_stdout(&args.output, |out| out.write_all(&bytes))
        } else {
            write_picture(&args.output, mesh, lines, field, &opts)
                .with_context(|| format!("cannot render {}", args.output.display()))
        }
    })?;
    note!("wrote {}", display(&args.output));
    Ok(())
}
