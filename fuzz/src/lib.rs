//! What every fuzz target checks, shared so that each target is one line.
//!
//! A reader given any bytes returns a value or an error whose message starts with the file's
//! name and a position (`line n`, `byte n`; none for the file as a whole); it never panics
//! (libFuzzer reports a panic, an abort, a timeout or a runaway allocation as a crash).

use std::path::Path;

use crestline::extract::{ExtractOptions, Method, extract};
use crestline::io::{Format, read_mesh_bytes};

/// The name errors must start with.
const NAME: &str = "fuzzed";

/// Checks that an error names the file and a position in it (none when it is about the
/// file as a whole).
fn check_error(e: &crestline::Error) {
    let message = e.to_string();
    let rest = message
        .strip_prefix("fuzzed: ")
        .unwrap_or_else(|| panic!("error without the file name: {message}"));
    let whole = matches!(
        e,
        crestline::Error::Parse {
            location: crestline::Location::File,
            ..
        }
    );
    assert!(
        whole || rest.starts_with("line ") || rest.starts_with("byte "),
        "error without a position: {message}"
    );
}

/// Reads `data` as a mesh in `format` (positions, triangles and connectivity).
pub fn read_mesh(data: &[u8], format: Format) -> Option<crestline::TriMesh> {
    match read_mesh_bytes(data, format, Path::new(NAME)) {
        Ok(mesh) => Some(mesh),
        Err(e) => {
            check_error(&e);
            None
        }
    }
}

/// Reads `data` as a feature-line OBJ.
pub fn read_lines(data: &[u8]) {
    if let Err(e) = crestline::io::lines::parse_lines_obj(data, Path::new(NAME)) {
        check_error(&e);
    }
}

/// Reads `data` as a diffusion-mask file for a mesh of as many vertices as its first byte
/// says.
pub fn read_mask(data: &[u8]) {
    let Some((&n, rest)) = data.split_first() else {
        return;
    };
    if let Err(e) =
        crestline::io::mask::parse_diffusion_factors(rest, usize::from(n), Path::new(NAME))
    {
        check_error(&e);
    }
}

/// Largest input the pipeline target reads, and the largest mesh it runs: the pipeline's cost
/// grows with the mesh, and small meshes reach every branch.
const MAX_PIPELINE_BYTES: usize = 3000;
const MAX_PIPELINE_FACES: usize = 300;

/// The first byte picks the format; the mesh the rest gives (if a reader accepts it) goes
/// through every method of `extract`, oriented first as the command line does. Every number
/// of the result must be finite.
pub fn run_pipeline(data: &[u8]) {
    let Some((&selector, rest)) = data.split_first() else {
        return;
    };
    if rest.len() > MAX_PIPELINE_BYTES {
        return;
    }
    let format = Format::ALL[usize::from(selector) % Format::ALL.len()];
    let Some(mesh) = read_mesh(rest, format) else {
        return;
    };
    if mesh.num_faces() > MAX_PIPELINE_FACES {
        return;
    }
    let Ok((mesh, _)) = crestline::mesh::orient_outward(mesh) else {
        return;
    };
    for method in [Method::Hpw, Method::Ybs, Method::Saliency] {
        if let Ok(x) = extract(&mesh, &ExtractOptions::for_method(method)) {
            if let Err(e) = x.check_finite() {
                panic!("{method:?}: {e}");
            }
        }
    }
}
