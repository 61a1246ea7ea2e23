//! `crestline subdivide`: Loop subdivision (each level turns every triangle into four).

use anyhow::Result;
use crestline::io::{WriteOptions, write_mesh, write_mesh_to};
use crestline::mesh::{SubdivideOptions, loop_subdivide};

use crate::input::{MeshArgs, is_dash, weld_mesh};
use crate::output::{MeshOutputArgs, display, to_stdout};
use crate::progress::{self, note};

/// Arguments of `crestline subdivide`.
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(flatten)]
    pub input: MeshArgs,
    #[command(flatten)]
    pub out: MeshOutputArgs,
    /// Subdivision levels; each multiplies the number of faces by 4. With 0 the mesh is only
    /// converted (degenerate faces dropped). Default: 1.
    #[arg(long)]
    pub levels: Option<u32>,
    /// Boundary vertices where the boundary turns by more than this many degrees stay fixed.
    /// Default: 60.
    #[arg(long)]
    pub corner_angle: Option<f64>,
    /// Keep vertices that share a position apart. By default they are made one first
    /// (patches exported side by side): subdivided apart, every such seam would become a
    /// boundary, and the surface a crease along it. Keep them apart where a file split its
    /// hard edges on purpose (a cube of 24 vertices) and they should stay sharp.
    #[arg(long)]
    pub no_weld: bool,
}

/// Runs the subcommand.
pub fn run(args: Args) -> Result<()> {
    let output_format = args.out.format()?;
    let mut options = SubdivideOptions::default();
    if let Some(levels) = args.levels {
        options.levels = levels;
    }
    if let Some(angle) = args.corner_angle {
        options.corner_angle = angle;
    }
    let (mesh, name) = progress::step("reading", || args.input.load())?;
    let mesh = if args.no_weld {
        mesh
    } else {
        weld_mesh(&mesh, &name)?.map_or(mesh, |(welded, _)| welded)
    };
    let result = progress::step(
        format!("subdividing {} triangles", mesh.num_faces()),
        || loop_subdivide(&mesh, &options),
    )?;
    progress::step("writing", || -> Result<()> {
        if is_dash(&args.out.output) {
            to_stdout(|out| write_mesh_to(out, &result, output_format, &WriteOptions::default()))
        } else {
            Ok(write_mesh(
                &args.out.output,
                &result,
                output_format,
                &WriteOptions::default(),
            )?)
        }
    })?;
    note!(
        "{name}: {} faces, {} vertices -> {} faces, {} vertices ({} level{}), written to {}",
        mesh.num_faces(),
        mesh.num_vertices(),
        result.num_faces(),
        result.num_vertices(),
        options.levels,
        if options.levels == 1 { "" } else { "s" },
        display(&args.out.output)
    );
    Ok(())
}
