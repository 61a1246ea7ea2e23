//! `crestline distance`: the geodesic distance from every vertex to the nearest feature line,
//! written as a PLY vertex property `feature_distance`.

use std::path::PathBuf;

use anyhow::{Result, bail};
use crestline::distance::{DistanceOptions, feature_distance};
use crestline::io::{Format, PlyWriter, VertexProperty};

use crate::input::{LinesArg, OrientedMeshArgs, is_dash, load_lines};
use crate::output::{PlyEncodingArg, check_output, display, to_stdout};
use crate::progress::{self, note};

/// Arguments of `crestline distance`.
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(flatten)]
    pub input: OrientedMeshArgs,
    /// Output: the mesh as PLY with the vertex property `feature_distance`, or `-` for
    /// standard output. Vertices no line reaches (other components) get the largest distance
    /// found.
    #[arg(short, long)]
    pub output: PathBuf,
    #[command(flatten)]
    pub lines: LinesArg,
    /// Propagate along edges only (plain Dijkstra, which overestimates) instead of also
    /// across triangles.
    #[arg(long)]
    pub edges_only: bool,
    #[command(flatten)]
    pub ply: PlyEncodingArg,
}

/// Runs the subcommand.
pub fn run(args: Args) -> Result<()> {
    if !is_dash(&args.output) && Format::from_path(&args.output) != Some(Format::Ply) {
        bail!(
            "{}: the distance field is written as PLY: give an output ending in .ply",
            args.output.display()
        );
    }
    check_output(&args.output, &[args.input.path(), args.lines.path()])?;
    let (prepared, name) = args.input.load_prepared()?;
    let mesh = &prepared.mesh;
    let lines = progress::step("feature lines", || load_lines(args.lines.path(), mesh))?;
    let options = DistanceOptions::default().with_relax_across_triangles(!args.edges_only);
    let distance = progress::step("distance to the lines", || {
        feature_distance(mesh, &lines, &options)
    })?;
    // PLY readers handle infinities poorly; "as far as anything gets" is also how the
    // simplification weights read an unreached vertex.
    let values: Vec<f64> = distance
        .vertex
        .iter()
        .map(|&d| if d.is_finite() { d } else { distance.max })
        .collect();
    // One value per vertex of the file: each copy of a welded vertex gets its value.
    let values = prepared.per_given_vertex(values)?;
    let writer = PlyWriter::new(prepared.given_mesh())
        .encoding(args.ply.encoding())
        .comment(format!("feature_distance to {} lines", lines.lines.len()))
        .property(VertexProperty::new("feature_distance", values))?;
    if is_dash(&args.output) {
        to_stdout(|out| writer.write_to(out))?;
    } else {
        writer.write(&args.output)?;
    }
    note!(
        "{name}: {} lines, {} seeded vertices, largest distance {:.6}, {} vertices unreached; \
         written to {}",
        lines.lines.len(),
        distance.seeded_vertices,
        distance.max,
        distance.unreached_vertices,
        display(&args.output)
    );
    Ok(())
}
