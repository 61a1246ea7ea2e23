//! `crestline view`: a self-contained HTML file to turn the mesh and its lines around in a
//! browser.

use std::path::PathBuf;

use anyhow::{Context, Result};

use crate::input::is_dash;
use crate::output::{check_extension, display, to_stdout};
use crate::progress::note;
use crate::scene::{SceneArgs, resolve_up};

/// Arguments of `crestline view`.
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Output HTML file (.html), or `-` for standard output. A picture's extension (.png,
    /// .svg) is refused: `crestline render` draws pictures.
    #[arg(short, long, value_name = "VIEW.html")]
    pub output: PathBuf,
}

/// Runs the subcommand.
pub fn run(args: Args) -> Result<()> {
    let mut opts = args.scene.options();
    opts.validate()?;
    args.scene.check_output(&args.output)?;
    check_extension(
        &args.output,
        "the HTML viewer",
        &["html", "htm"],
        "give an output ending in .html (`crestline render -o PICTURE.png` draws a picture)",
    )?;
    let scene = args.scene.load()?;
    opts.up = resolve_up(opts.up, &scene.mesh);
    let (mesh, lines, field) = (&scene.mesh, scene.lines.as_ref(), scene.field.as_deref());
    if is_dash(&args.output) {
        let html = crestline::render::render_html(mesh, lines, field, &opts)?;
        to_stdout(|out| out.write_all(html.as_bytes()))?;
    } else {
        crestline::render::write_html(&args.output, mesh, lines, field, &opts)
            .with_context(|| format!("cannot write {}", args.output.display()))?;
    }
    note!("wrote {}", display(&args.output));
    Ok(())
}
