//! `crestline subdivide`: Loop subdivision (each level turns every triangle into four).

use anyhow::{Result, bail};
use crestline::io::{WriteOptions, write_mesh, write_mesh_to};
use crestline::mesh::{SubdivideOptions, loop_subdivide};

use crate::input::{MeshArgs, is_dash, weld_mesh};
use crate::output::{MeshOutputArgs, check_output, display, to_stdout};
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
    #[arg(
        long,
        value_parser = super::extract::whole_number::<u32>,
        allow_negative_numbers = true
    )]
    pub levels: Option<u32>,
    /// Refuse, before any work, levels that would make more faces than this (subdividing
    /// takes about 130 bytes of memory per face made). Default: 50000000 (about 6.5 GB).
    #[arg(
        long,
        value_name = "FACES",
        value_parser = super::extract::whole_number::<u64>,
        allow_negative_numbers = true
    )]
    pub max_faces: Option<u64>,
    /// Boundary vertices where the boundary turns by more than this many degrees stay fixed.
    /// Default: 60.
    #[arg(long, allow_negative_numbers = true)]
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
    // Before the work: writing comes last, and a missing folder would only show then.
    check_output(&args.out.output, &[])?;
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
    check_result_size(
        &name,
        mesh.num_faces(),
        options.levels,
        args.max_faces.unwrap_or(DEFAULT_MAX_FACES),
    )?;
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

/// The default of `--max-faces`. Subdividing fandisk 4 levels (3.3 million faces) peaked at
/// 424 MB, about 130 bytes per face made: 50 million faces take about 6.5 GB.
const DEFAULT_MAX_FACES: u64 = 50_000_000;

/// Refuses `levels` levels of subdivision of `faces` faces when the result, `faces · 4^levels`
/// faces, would exceed `max_faces`, naming the largest number of levels that stays under it
/// (`--levels 8` on fandisk would have tried to allocate tens of gigabytes). Converting (0 levels)
/// is never refused.
fn check_result_size(name: &str, faces: usize, levels: u32, max_faces: u64) -> Result<()> {
    let made = |levels: u32| (faces as u128).saturating_mul(4u128.saturating_pow(levels));
    if levels == 0 || made(levels) <= u128::from(max_faces) {
        return Ok(());
    }
    let fitting = (0..levels)
        .rev()
        .find(|&l| made(l) <= u128::from(max_faces));
    let advice = match fitting {
        Some(0) | None => "not even 1 level stays under it".to_string(),
        Some(1) => format!("at most 1 level stays under it ({} faces)", made(1)),
        Some(l) => format!("at most {l} levels stay under it ({} faces)", made(l)),
    };
    let total = made(levels);
    let total = if total == u128::MAX {
        "more than 10^38".to_string()
    } else {
        total.to_string()
    };
    bail!(
        "{name}: {levels} level{} of subdivision would make {total} faces ({faces} × 4^{levels}), \
         more than the bound of {max_faces} (--max-faces; about 130 bytes of memory per face): \
         {advice}",
        if levels == 1 { "" } else { "s" }
    );
}
