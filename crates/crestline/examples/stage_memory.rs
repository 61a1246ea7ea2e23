//! Where time and memory go in `extract`: wall time, CPU time (all threads; steadier than wall
//! time on a shared machine), resident memory after every step, the
//! peak within the step and the peak so far (Linux `/proc/self/status`; the high-water mark is
//! reset at the start of each step through `/proc/self/clear_refs`), plus the bytes held by the
//! mesh itself. Used for the CGAL comparison (`docs/benchmarks-history.md`, session 3).
//!
//! ```sh
//! cargo run --release -p crestline --example stage_memory -- MESH [hpw|ybs|saliency|load]
//! ```
//!
//! `load` stops after the loading steps (read, parse, build, orient).

use std::path::PathBuf;
use std::time::{Duration, Instant};

use crestline::TriMesh;
use crestline::extract::{ExtractOptions, Method, Stage, extract_with_progress};
use crestline::io::Format;

/// `VmRSS` and `VmHWM` in bytes, when the system reports them.
fn memory() -> Option<(u64, u64)> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let field = |name: &str| -> Option<u64> {
        let line = status.lines().find(|l| l.starts_with(name))?;
        let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
        Some(kb * 1024)
    };
    Some((field("VmRSS:")?, field("VmHWM:")?))
}

/// CPU time of the process so far (user + system, all threads), in seconds, from
/// `/proc/self/stat` (clock ticks of 1/100 s). On a shared machine this moves less with
/// the load than wall time does.
fn cpu_seconds() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // Fields after the command name (which is in parentheses and may hold spaces).
    let rest = &stat[stat.rfind(')')? + 2..];
    let fields: Vec<&str> = rest.split_whitespace().collect();
    let ticks = |i: usize| fields.get(i)?.parse::<f64>().ok();
    // utime and stime are fields 14 and 15 of the line; `rest` starts at field 3.
    Some((ticks(11)? + ticks(12)?) / 100.0)
}

/// Resets the high-water mark to the current resident size (Linux 4.0 and later; ignored
/// where it is not supported, and the step peak is then the peak so far).
fn reset_peak() {
    let _ = std::fs::write("/proc/self/clear_refs", "5");
}

/// What the rows carry over: the peak over all steps so far and the CPU time at the end of
/// the last step.
struct Totals {
    peak: u64,
    cpu: f64,
}

/// Prints one row.
fn row(label: &str, seconds: f64, faces: usize, totals: &mut Totals) {
    let cpu = cpu_seconds().unwrap_or(f64::NAN);
    let step_cpu = cpu - totals.cpu;
    totals.cpu = cpu;
    let overall = &mut totals.peak;
    match memory() {
        Some((rss, hwm)) => {
            *overall = (*overall).max(hwm);
            // Not known yet while the file is read.
            let per_face = if faces > 0 {
                format!("{:.0}", *overall as f64 / faces as f64)
            } else {
                "–".into()
            };
            println!(
                "| {label} | {seconds:.3} | {step_cpu:.2} | {:.1} | {:.1} | {:.1} | {} |",
                rss as f64 / 1e6,
                hwm as f64 / 1e6,
                *overall as f64 / 1e6,
                per_face
            );
        }
        None => println!("| {label} | {seconds:.3} | {step_cpu:.2} | n/a | n/a | n/a | n/a |"),
    }
    reset_peak();
}

/// Bytes held by the mesh's own arrays: positions, faces and the connectivity, counted from
/// the element counts (see `mesh::Topology` for the layout).
fn mesh_bytes(mesh: &TriMesh) -> usize {
    let (v, f, e) = (
        mesh.num_vertices(),
        mesh.num_faces(),
        mesh.topology().num_edges(),
    );
    let positions = 24 * v;
    let faces = 12 * f;
    let vertex_faces = 4 * (v + 1) + 4 * 3 * f;
    let vertex_edges = 4 * (v + 1) + 4 * 2 * e;
    let edges = 8 * e;
    // One or two faces per edge in place (non-manifold edges' side table not counted).
    let edge_faces = 8 * e;
    let vertex_kinds = v;
    positions + faces + vertex_faces + vertex_edges + edges + edge_faces + vertex_kinds
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let path = PathBuf::from(
        args.next()
            .ok_or("usage: stage_memory MESH [hpw|ybs|saliency|load]")?,
    );
    let method = match args.next().as_deref() {
        None | Some("hpw") => Some(Method::Hpw),
        Some("ybs") => Some(Method::Ybs),
        Some("saliency") => Some(Method::Saliency),
        Some("load") => None,
        Some(other) => return Err(format!("unknown method {other}").into()),
    };

    println!(
        "| step | seconds | CPU seconds | RSS after, MB | peak in step, MB | peak so far, MB | peak bytes/face |"
    );
    println!("| --- | ---: | ---: | ---: | ---: | ---: | ---: |");
    let mut overall = Totals {
        peak: 0,
        cpu: cpu_seconds().unwrap_or(f64::NAN),
    };
    reset_peak();
    // Reading is split as `crestline::io::read_mesh` does it: file bytes, parse, TriMesh (the
    // degenerate-face check and the connectivity).
    let start = Instant::now();
    let bytes = std::fs::read(&path)?;
    let read_time = start.elapsed().as_secs_f64();
    row("read file", read_time, 0, &mut overall);
    let start = Instant::now();
    let data = crestline::io::parse_mesh_bytes(&bytes, Format::resolve(&path, None)?, &path)?;
    let faces = data.faces.len();
    let parse_time = start.elapsed().as_secs_f64();
    drop(bytes);
    row(
        "parse (file bytes then freed)",
        parse_time,
        faces,
        &mut overall,
    );
    let start = Instant::now();
    let mesh = data.into_mesh(&path)?;
    row(
        "build mesh (connectivity)",
        start.elapsed().as_secs_f64(),
        faces,
        &mut overall,
    );

    // As the CLI does before extracting: closed components facing inward are reversed.
    let start = Instant::now();
    let (mesh, _) = crestline::mesh::orient_outward(mesh)?;
    row(
        "orient outward",
        start.elapsed().as_secs_f64(),
        faces,
        &mut overall,
    );
    let Some(method) = method else {
        return Ok(());
    };

    let options = ExtractOptions::for_method(method);
    let mut progress = |stage: Stage, done: Option<Duration>| {
        if let Some(t) = done {
            row(stage.name(), t.as_secs_f64(), faces, &mut overall);
        }
    };
    let extraction = extract_with_progress(&mesh, &options, &mut progress)?;
    println!();
    println!(
        "{} faces, {} vertices; the mesh's arrays hold {:.1} MB ({:.0} bytes/face); {} lines",
        faces,
        mesh.num_vertices(),
        mesh_bytes(&mesh) as f64 / 1e6,
        mesh_bytes(&mesh) as f64 / faces as f64,
        extraction.lines.lines.len()
    );
    Ok(())
}
