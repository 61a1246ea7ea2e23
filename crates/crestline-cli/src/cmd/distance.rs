//! `crestline distance`: the geodesic distance from every vertex to the nearest feature line,
//! written as a PLY vertex property `feature_distance`.

use std::path::PathBuf;

use anyhow::{Result, bail};
use crestline::distance::{DistanceOptions, feature_distance};
use crestline::io::{Format, PlyEncoding, PlyWriter, VertexProperty};

use crate::input::{FormatArg, OrientArgs, load_lines, load_mesh, prepare_mesh};

/// Arguments of `crestline distance`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Mesh file (OBJ, PLY, OFF, STL). Without it, a built-in example is used.
    pub mesh: Option<PathBuf>,
    #[command(flatten)]
    pub orient: OrientArgs,
    /// Read the mesh as this format instead of guessing from the extension.
    #[arg(long, value_enum)]
    pub format: Option<FormatArg>,
    /// Output: the mesh as PLY with the vertex property `feature_distance`. Vertices no line
    /// reaches (other components) get the largest distance found.
    #[arg(short, long)]
    pub output: PathBuf,
    /// Feature lines as an OBJ file with `l` polylines. Without it they are extracted from
    /// the mesh with the default method (as `crestline extract` does).
    #[arg(long)]
    pub lines: Option<PathBuf>,
    /// Propagate along edges only (plain Dijkstra, which overestimates) instead of also
    /// across triangles.
    #[arg(long)]
    pub edges_only: bool,
    /// Write ascii PLY instead of binary.
    #[arg(long)]
    pub ascii: bool,
}

/// Runs the subcommand.
pub fn run(args: Args) -> Result<()> {
    if Format::from_path(&args.output) != Some(Format::Ply) {
        bail!(
            "{}: the distance field is written as PLY: give an output ending in .ply",
            args.output.display()
        );
    }
    let (mesh, name) = load_mesh(args.mesh.as_ref(), args.format)?;
    let mesh = prepare_mesh(mesh, &name, args.orient)?;
    let lines = load_lines(args.lines.as_ref(), &mesh)?;
    let options = DistanceOptions::default().with_relax_across_triangles(!args.edges_only);
    let distance = feature_distance(&mesh, &lines, &options)?;
    // PLY readers handle infinities poorly; "as far as anything gets" is also how the
    // simplification weights read an unreached vertex.
    let values: Vec<f64> = distance
        .vertex
        .iter()
        .map(|&d| if d.is_finite() { d } else { distance.max })
        .collect();
    let encoding = if args.ascii {
        PlyEncoding::Ascii
    } else {
        PlyEncoding::BinaryLittleEndian
    };
    PlyWriter::new(&mesh)
        .encoding(encoding)
        .comment(format!("feature_distance to {} lines", lines.lines.len()))
        .property(VertexProperty::new("feature_distance", values))?
        .write(&args.output)?;
    eprintln!(
        "{name}: {} lines, {} seeded vertices, largest distance {:.6}, {} vertices unreached; \
         written to {}",
        lines.lines.len(),
        distance.seeded_vertices,
        distance.max,
        distance.unreached_vertices,
        args.output.display()
    );
    Ok(())
}
