//! `crestline extract` over several meshes: files and folders given on the command line, in
//! parallel across files, one lines file per mesh in the `-o` folder, a summary at the end.
//! A file that fails is reported and skipped; the run then ends with an error (non-zero exit
//! code) once every other file is done.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result, bail};
use crestline::io::lines::write_lines;
use crestline::io::{Format, PlyEncoding};
use rayon::prelude::*;

use super::extract::{
    Args, IoTimes, StatsFormat, default_output, lines_format, mask_regions, options_from_args,
};
use crate::input::{Prepared, diffusion_factors, is_dash, load_mesh, prepare_mesh};
use crate::progress;

/// What became of one mesh: its figures (`--stats json`) and the warning to print, if any.
struct Outcome {
    input: PathBuf,
    output: PathBuf,
    result: Result<serde_json::Value>,
    warning: Option<String>,
    seconds: f64,
}

/// Runs the batch.
pub fn run(args: &Args) -> Result<()> {
    for (given, flag) in [
        (args.png.is_some(), "--png"),
        (args.svg.is_some(), "--svg"),
        (args.html.is_some(), "--html"),
        (args.mask.is_some(), "--mask"),
    ] {
        if given {
            bail!("{flag} is for one mesh; it cannot be used when extracting from several");
        }
    }
    // Values out of range are one error up front, not one per mesh.
    options_from_args(args)?.validate()?;
    let inputs = expand(&args.meshes)?;
    let folder = match &args.output {
        Some(o) if is_dash(o) => bail!("-o -: a batch writes one file per mesh; give a folder"),
        Some(o) if o.is_file() => bail!(
            "{}: a batch writes one file per mesh into a folder, and this is a file",
            o.display()
        ),
        Some(o) => o.clone(),
        None => PathBuf::from("."),
    };
    std::fs::create_dir_all(&folder)
        .with_context(|| format!("cannot create the folder {}", folder.display()))?;
    let outputs: Vec<PathBuf> = inputs
        .iter()
        .map(|input| folder.join(default_output(Some(input), args)))
        .collect();
    refuse_collisions(&inputs, &outputs)?;

    let bar = progress::counter(inputs.len(), "meshes");
    let outcomes: Vec<Outcome> = inputs
        .par_iter()
        .zip(&outputs)
        .map(|(input, output)| {
            let clock = Instant::now();
            let (result, warning) = match extract_one(input, output, args) {
                Ok((stats, warning)) => (Ok(stats), warning),
                Err(e) => (Err(e), None),
            };
            bar.inc(1);
            Outcome {
                input: input.clone(),
                output: output.clone(),
                result,
                warning,
                seconds: clock.elapsed().as_secs_f64(),
            }
        })
        .collect();
    bar.finish_and_clear();
    for warning in outcomes.iter().filter_map(|o| o.warning.as_deref()) {
        eprintln!("{warning}");
    }

    match args.stats {
        Some(StatsFormat::Json) => {
            println!(
                "{}",
                serde_json::to_string_pretty(&summary_json(&outcomes))?
            );
            // The JSON on standard output has the errors too; stderr names them so that the
            // last line below does not point at nothing.
            for o in &outcomes {
                if let Err(e) = &o.result {
                    eprintln!("{}: FAILED: {}", o.input.display(), crate::error_chain(e));
                }
            }
        }
        _ => eprint!("{}", summary_table(&outcomes)),
    }
    let failed = outcomes.iter().filter(|o| o.result.is_err()).count();
    if failed > 0 {
        bail!("{failed} of {} meshes failed (see above)", outcomes.len());
    }
    Ok(())
}

/// The mesh files named by `paths`: files as given, folders by their files with a mesh
/// extension (not recursing), sorted by name.
fn expand(paths: &[PathBuf]) -> Result<Vec<PathBuf>> {
    let mut files = Vec::new();
    for path in paths {
        if is_dash(path) {
            bail!("standard input (-) cannot be part of a batch of several meshes");
        }
        if !path.is_dir() {
            files.push(path.clone());
            continue;
        }
        let mut found: Vec<PathBuf> = std::fs::read_dir(path)
            .with_context(|| format!("cannot list the folder {}", path.display()))?
            .filter_map(|entry| entry.ok().map(|e| e.path()))
            .filter(|p| p.is_file() && Format::from_path(p).is_some())
            .collect();
        if found.is_empty() {
            bail!(
                "{}: no mesh files (.obj, .ply, .off, .stl) in this folder",
                path.display()
            );
        }
        found.sort();
        files.extend(found);
    }
    Ok(files)
}

/// Two meshes with the same name (`a.obj`, `a.ply`) would write the same file.
fn refuse_collisions(inputs: &[PathBuf], outputs: &[PathBuf]) -> Result<()> {
    let mut seen: std::collections::HashMap<&Path, &Path> = Default::default();
    for (input, output) in inputs.iter().zip(outputs) {
        if let Some(first) = seen.insert(output, input) {
            bail!(
                "{} and {} would both write {}: extract them in separate runs",
                first.display(),
                input.display(),
                output.display()
            );
        }
    }
    Ok(())
}

/// Extracts and writes the lines of one mesh into `output`; returns its figures, and the
/// warning for a raw marching-cubes mesh.
fn extract_one(
    input: &Path,
    output: &Path,
    args: &Args,
) -> Result<(serde_json::Value, Option<String>)> {
    let clock = Instant::now();
    let (mesh, name) = load_mesh(Some(input), args.input_format)?;
    let Prepared { mesh, weld, .. } = prepare_mesh(mesh, &name, args.prepare)?;
    let load = clock.elapsed();
    let mut options = options_from_args(args)?;
    options.smoothing.diffusion = diffusion_factors(None, mask_regions(args), &mesh, &weld)?;
    let extraction = crestline::extract::extract(&mesh, &options)?;
    let clock = Instant::now();
    write_lines(
        output,
        &extraction.lines,
        Some(lines_format(args, output)),
        PlyEncoding::BinaryLittleEndian,
    )?;
    let io = IoTimes {
        load,
        write: clock.elapsed(),
    };
    let warning = (extraction.stats.marching_cubes_grid)
        .map(|grid| super::extract::marching_cubes_warning(&name, grid.spacing));
    Ok((super::extract::stats_json(&extraction, &mesh, &io), warning))
}

fn summary_json(outcomes: &[Outcome]) -> serde_json::Value {
    let files: Vec<serde_json::Value> = outcomes
        .iter()
        .map(|o| match &o.result {
            Ok(stats) => serde_json::json!({
                "input": o.input.display().to_string(),
                "output": o.output.display().to_string(),
                "ok": true,
                "seconds": o.seconds,
                "stats": stats,
            }),
            Err(e) => serde_json::json!({
                "input": o.input.display().to_string(),
                "ok": false,
                "seconds": o.seconds,
                "error": crate::error_chain(e),
            }),
        })
        .collect();
    serde_json::json!({
        "meshes": outcomes.len(),
        "failed": outcomes.iter().filter(|o| o.result.is_err()).count(),
        "files": files,
    })
}

fn summary_table(outcomes: &[Outcome]) -> String {
    let width = outcomes
        .iter()
        .map(|o| o.input.display().to_string().len())
        .max()
        .unwrap_or(4)
        .max(4);
    let mut out = format!(
        "{:<width$}  {:>9}  {:>6}  {:>6}  {:>7}  {:>7}  {:>8}  output\n",
        "mesh", "triangles", "lines", "ridges", "valleys", "creases", "seconds"
    );
    for o in outcomes {
        let input = o.input.display().to_string();
        match &o.result {
            // Ridges and valleys are crest lines, as the JSON lines file counts them.
            Ok(s) => {
                out += &format!(
                    "{input:<width$}  {:>9}  {:>6}  {:>6}  {:>7}  {:>7}  {:>8.2}  {}\n",
                    s["triangles"].to_string(),
                    s["lines"].to_string(),
                    s["ridges"].to_string(),
                    s["valleys"].to_string(),
                    s["creases"].to_string(),
                    o.seconds,
                    o.output.display()
                )
            }
            Err(e) => out += &format!("{input:<width$}  FAILED: {}\n", crate::error_chain(e)),
        }
    }
    let failed = outcomes.iter().filter(|o| o.result.is_err()).count();
    out += &format!(
        "{} meshes, {} done, {failed} failed\n",
        outcomes.len(),
        outcomes.len() - failed
    );
    out
}
