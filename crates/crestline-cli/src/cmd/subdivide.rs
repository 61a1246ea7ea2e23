//! `crestline subdivide`: Loop subdivision (each level turns every triangle into four).

use std::path::PathBuf;

use anyhow::Result;
use crestline::io::{Format, WriteOptions, write_mesh};
use crestline::mesh::{SubdivideOptions, loop_subdivide};

use crate::input::{FormatArg, load_mesh};

/// Arguments of `crestline subdivide`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Mesh file (OBJ, PLY, OFF, STL). Without it, a built-in example is used.
    pub mesh: Option<PathBuf>,
    /// Read the mesh as this format instead of guessing from the extension.
    #[arg(long, value_enum)]
    pub format: Option<FormatArg>,
    /// Output mesh; the format follows the extension (.obj, .ply, .off, .stl).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Subdivision levels; each multiplies the number of faces by 4. With 0 the mesh is only
    /// converted (degenerate faces dropped). Default: 1.
    #[arg(long)]
    pub levels: Option<u32>,
    /// Boundary vertices where the boundary turns by more than this many degrees stay fixed.
    /// Default: 60.
    #[arg(long)]
    pub corner_angle: Option<f64>,
}

/// Runs the subcommand.
pub fn run(args: Args) -> Result<()> {
    let output_format = Format::resolve(&args.output, None)?;
    let mut options = SubdivideOptions::default();
    if let Some(levels) = args.levels {
        options.levels = levels;
    }
    if let Some(angle) = args.corner_angle {
        options.corner_angle = angle;
    }
    let (mesh, name) = load_mesh(args.mesh.as_ref(), args.format)?;
    let result = loop_subdivide(&mesh, &options)?;
    write_mesh(
        &args.output,
        &result,
        output_format,
        &WriteOptions::default(),
    )?;
    println!(
        "{name}: {} faces, {} vertices -> {} faces, {} vertices ({} level{}), written to {}",
        mesh.num_faces(),
        mesh.num_vertices(),
        result.num_faces(),
        result.num_vertices(),
        options.levels,
        if options.levels == 1 { "" } else { "s" },
        args.output.display()
    );
    Ok(())
}
