//! `crestline simplify`: crest-line-guided quadric-error decimation (YBS 2005, eq. 7).

use anyhow::{Result, bail};
use crestline::io::{WriteOptions, write_mesh, write_mesh_to};
use crestline::lines::FeatureLines;
use crestline::simplify::{SimplifyOptions, Target, simplify};

use crate::input::{LinesArg, OrientedMeshArgs, is_dash, load_lines};
use crate::output::{MeshOutputArgs, check_output, display, to_stdout};
use crate::progress::{self, note};

/// Arguments of `crestline simplify`.
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(flatten)]
    pub input: OrientedMeshArgs,
    #[command(flatten)]
    pub out: MeshOutputArgs,
    /// Keep this fraction of the triangles, in (0, 1]. Default: 0.1.
    #[arg(long, conflicts_with = "faces", value_parser = ratio, allow_negative_numbers = true)]
    pub ratio: Option<f64>,
    /// Keep this many triangles.
    #[arg(
        long,
        value_parser = super::extract::whole_number::<usize>,
        allow_negative_numbers = true
    )]
    pub faces: Option<usize>,
    /// Influence of the feature lines (eta of eq. 7); 0 is plain QEM and needs no lines.
    /// Default: 1.
    #[arg(long, allow_negative_numbers = true)]
    pub eta: Option<f64>,
    /// Regularisation epsilon of eq. 7. Default: 0.1.
    #[arg(long, allow_negative_numbers = true)]
    pub eps: Option<f64>,
    #[command(flatten)]
    pub lines: LinesArg,
    /// Print the report as one JSON object on stdout.
    #[arg(long)]
    pub json: bool,
}

/// Runs the subcommand.
pub fn run(args: Args) -> Result<()> {
    if is_dash(&args.out.output) && args.json {
        bail!("--json and -o - both write to standard output: choose one");
    }
    let output_format = args.out.format()?;
    // Before the work: writing comes last, and a missing folder would only show then.
    check_output(&args.out.output, &[])?;
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
    // Before the mesh is read and the lines are extracted.
    options.check_weights()?;
    let (mesh, name) = args.input.load()?;
    let lines = if options.eta == 0.0 && args.lines.path().is_none() {
        FeatureLines::default()
    } else {
        progress::step("feature lines", || load_lines(args.lines.path(), &mesh))?
    };
    let result = progress::step(
        format!("simplifying {} triangles", mesh.num_faces()),
        || simplify(&mesh, &lines, &options),
    )?;
    progress::step("writing", || -> Result<()> {
        if is_dash(&args.out.output) {
            to_stdout(|out| {
                write_mesh_to(out, &result.mesh, output_format, &WriteOptions::default())
            })
        } else {
            Ok(write_mesh(
                &args.out.output,
                &result.mesh,
                output_format,
                &WriteOptions::default(),
            )?)
        }
    })?;
    let r = &result.rejected;
    if args.json {
        let report = serde_json::json!({
            "input": name,
            "output": display(&args.out.output),
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
                "valence": r.valence,
            },
            "candidates": result.candidates,
            "creases": lines.lines.iter().filter(|l| l.crease).count(),
        });
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else if !progress::quiet() {
        // On stderr: standard output may carry the mesh.
        eprintln!(
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
        eprintln!(
            "refused candidates: {} link condition, {} flip, {} degenerate, {} boundary, \
             {} non-manifold, {} on creases (kept as they are), {} above {} neighbours",
            r.link,
            r.flip,
            r.degenerate,
            r.boundary,
            r.non_manifold,
            r.fixed,
            r.valence,
            crestline::simplify::MAX_VALENCE
        );
        note!("written to {}", display(&args.out.output));
    }
    Ok(())
}

/// Parses the kept fraction of the triangles, in (0, 1] (as the library checks it).
fn ratio(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(r) if r > 0.0 && r <= 1.0 => Ok(r),
        _ => Err(format!("target ratio must be in (0, 1], got {s}")),
    }
}
