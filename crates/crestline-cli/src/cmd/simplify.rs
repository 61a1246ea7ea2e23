//! `crestline simplify`: crest-line-guided quadric-error decimation (YBS 2005, eq. 7).

use std::path::PathBuf;

use anyhow::Result;
use crestline::io::{Format, WriteOptions, write_mesh};
use crestline::lines::FeatureLines;
use crestline::simplify::{SimplifyOptions, Target, simplify};

use crate::input::{FormatArg, OrientArgs, load_lines, load_mesh, prepare_mesh};

/// Arguments of `crestline simplify`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Mesh file (OBJ, PLY, OFF, STL). Without it, a built-in example is used.
    pub mesh: Option<PathBuf>,
    #[command(flatten)]
    pub orient: OrientArgs,
    /// Read the mesh as this format instead of guessing from the extension.
    #[arg(long, value_enum)]
    pub format: Option<FormatArg>,
    /// Output mesh; the format follows the extension (.obj, .ply, .off, .stl).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Keep this fraction of the triangles, in (0, 1]. Default: 0.1.
    #[arg(long, conflicts_with = "faces")]
    pub ratio: Option<f64>,
    /// Keep this many triangles.
    #[arg(long)]
    pub faces: Option<usize>,
    /// Influence of the feature lines (eta of eq. 7); 0 is plain QEM and needs no lines.
    /// Default: 1.
    #[arg(long)]
    pub eta: Option<f64>,
    /// Regularisation epsilon of eq. 7. Default: 0.1.
    #[arg(long)]
    pub eps: Option<f64>,
    /// Feature lines as an OBJ file with `l` polylines. Without it they are extracted from
    /// the mesh with the default method (as `crestline extract` does).
    #[arg(long)]
    pub lines: Option<PathBuf>,
    /// Print the report as one JSON object on stdout.
    #[arg(long)]
    pub json: bool,
}

/// Runs the subcommand.
pub fn run(args: Args) -> Result<()> {
    let output_format = Format::resolve(&args.output, None)?;
    let mut options = SimplifyOptions::default();
    if let Some(r) = args.ratio {
        options.target = Target::Ratio(r);
    }
    if let Some(n) = args.faces {
        options.target = Target::Faces(n);
    }
    if let Some(eta) = args.eta {
        options.eta = eta;
    }
    if let Some(eps) = args.eps {
        options.eps = eps;
    }
    let (mesh, name) = load_mesh(args.mesh.as_ref(), args.format)?;
    let mesh = prepare_mesh(mesh, &name, args.orient)?;
    let lines = if options.eta == 0.0 && args.lines.is_none() {
        FeatureLines::default()
    } else {
        load_lines(args.lines.as_ref(), &mesh)?
    };
    let result = simplify(&mesh, &lines, &options)?;
    write_mesh(
        &args.output,
        &result.mesh,
        output_format,
        &WriteOptions::default(),
    )?;
    let r = &result.rejected;
    if args.json {
        let report = serde_json::json!({
            "input": name,
            "output": args.output.display().to_string(),
            "lines": lines.lines.len(),
            "faces_before": result.faces_before,
            "faces_after": result.faces_after,
            "target_faces": result.target_faces,
            "target_reached": result.target_reached,
            "collapses": result.collapses,
            "passes": result.passes,
            "rejected": {
                "non_manifold": r.non_manifold,
                "boundary": r.boundary,
                "link": r.link,
                "flip": r.flip,
                "degenerate": r.degenerate,
                "fixed": r.fixed,
            },
            "creases": lines.lines.iter().filter(|l| l.crease).count(),
        });
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        println!(
            "{name}: {} -> {} triangles (target {}{}), {} collapses, {} lines",
            result.faces_before,
            result.faces_after,
            result.target_faces,
            if result.target_reached {
                ""
            } else {
                ", not reached: every remaining collapse was refused"
            },
            result.collapses,
            lines.lines.len()
        );
        println!(
            "refused candidates: {} link condition, {} flip, {} degenerate, {} boundary, \
             {} non-manifold, {} on creases (kept as they are)",
            r.link, r.flip, r.degenerate, r.boundary, r.non_manifold, r.fixed
        );
        println!("written to {}", args.output.display());
    }
    Ok(())
}
