//! `crestline`: feature lines on triangle meshes, from the command line.
//!
//! The CLI is thin: each subcommand (one file under `cmd/`) turns its arguments into the
//! library's options structs, calls the library and writes the results.

mod allocator;
mod cmd;
mod input;
mod interrupt;
mod output;
mod progress;
mod scene;

use clap::{Parser, Subcommand};

/// Ridges, valleys and crest lines on triangle meshes.
#[derive(Debug, Parser)]
#[command(name = "crestline", version, about, long_about = None)]
struct Cli {
    /// No progress and no notes on stderr (errors and warnings still go there).
    #[arg(short, long, global = true)]
    quiet: bool,
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Per-vertex curvature, directions and extremalities as PLY vertex properties or CSV.
    Curvature(cmd::curvature::Args),
    /// Find ridges, valleys and sharp creases and write them as polylines (OBJ, PLY or
    /// JSON); several meshes or folders at once in parallel.
    Extract(Box<cmd::extract::Args>),
    /// Print counts and health figures of a mesh.
    Info(cmd::info::Args),
    /// Draw a mesh, its feature lines and a field as a PNG or SVG picture.
    Render(cmd::render::Args),
    /// Write a self-contained HTML viewer (WebGL) of a mesh, its lines and a field.
    View(cmd::view::Args),
    /// Geodesic distance to the nearest feature line, as a PLY vertex property.
    Distance(cmd::distance::Args),
    /// Simplify a mesh, keeping detail near the feature lines (YBS 2005, eq. 7).
    Simplify(cmd::simplify::Args),
    /// Refine a mesh by Loop subdivision (each level turns every triangle into four).
    Subdivide(cmd::subdivide::Args),
}

fn main() -> std::process::ExitCode {
    allocator::return_large_blocks_when_freed();
    interrupt::remove_partial_outputs_on_signals();
    interrupt::end_quietly_when_output_fails();
    let cli = Cli::parse();
    progress::set_quiet(cli.quiet);
    let result = match cli.command {
        Command::Curvature(args) => cmd::curvature::run(args),
        Command::Extract(args) => cmd::extract::run(*args),
        Command::Info(args) => cmd::info::run(args),
        Command::Render(args) => cmd::render::run(args),
        Command::View(args) => cmd::view::run(args),
        Command::Distance(args) => cmd::distance::run(args),
        Command::Simplify(args) => cmd::simplify::run(args),
        Command::Subdivide(args) => cmd::subdivide::run(args),
    };
    match result {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {}", error_chain(&e));
            std::process::ExitCode::FAILURE
        }
    }
}

/// The error and its causes joined by `: `, leaving out a cause whose words the message
/// already holds (an I/O error that names its file and also carries the OS error as its
/// source would otherwise print the OS error twice).
pub(crate) fn error_chain(error: &anyhow::Error) -> String {
    let mut message = String::new();
    for cause in error.chain() {
        let text = cause.to_string();
        if message.contains(&text) {
            continue;
        }
        if !message.is_empty() {
            message.push_str(": ");
        }
        message.push_str(&text);
    }
    message
}
