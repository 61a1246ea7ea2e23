//! Loading the inputs: the mesh (a file given by the user, or the built-in example) and the
//! feature lines that guide `distance` and `simplify`.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use clap::ValueEnum;
use crestline::TriMesh;
use crestline::extract::{ExtractOptions, extract};
use crestline::io::Format;
use crestline::lines::FeatureLines;
use crestline::mesh::{EdgeKind, VertexKind};

/// The built-in example: the fandisk CAD part (see `crates/crestline/fixtures/README.md`).
const BUILT_IN_EXAMPLE: &[u8] = include_bytes!("../../crestline/fixtures/fandisk.obj");

/// Formats a user can force with `--format`.
#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum FormatArg {
    /// Wavefront OBJ.
    Obj,
    /// Stanford PLY.
    Ply,
    /// Object File Format.
    Off,
    /// STL, ascii or binary.
    Stl,
}

impl From<FormatArg> for Format {
    fn from(f: FormatArg) -> Self {
        match f {
            FormatArg::Obj => Format::Obj,
            FormatArg::Ply => Format::Ply,
            FormatArg::Off => Format::Off,
            FormatArg::Stl => Format::Stl,
        }
    }
}

/// `--keep-orientation`, shared by the commands that estimate curvature.
#[derive(Debug, Clone, Copy, clap::Args)]
pub struct OrientArgs {
    /// Keep the winding of the triangles as it is. By default closed components whose
    /// triangles face inward (negative volume) are reversed first, since curvature signs
    /// follow the normals: facing inward, ridges and valleys swap.
    #[arg(long)]
    pub keep_orientation: bool,
}

/// Says on stderr what of `mesh` the algorithms skip or treat specially (degenerate
/// triangles dropped, unreferenced vertices, non-manifold edges), then reverses the closed
/// components that face inward (unless `args` says to keep them) and says so.
pub fn prepare_mesh(mesh: TriMesh, name: &str, args: OrientArgs) -> Result<TriMesh> {
    note_awkward_parts(&mesh, name);
    if args.keep_orientation {
        return Ok(mesh);
    }
    let (mesh, report) = crestline::mesh::orient_outward(mesh)?;
    if report.inward > 0 {
        eprintln!(
            "{name}: {} of {} closed components faced inward ({} triangles); reversed them so that \
             normals point outward (--keep-orientation to keep them)",
            report.inward, report.closed, report.inward_faces
        );
    }
    Ok(mesh)
}

/// One line on stderr listing the parts of `mesh` that are skipped or handled specially,
/// when there are any.
fn note_awkward_parts(mesh: &TriMesh, name: &str) {
    let topo = mesh.topology();
    let unreferenced = topo.count_vertices(VertexKind::Unreferenced);
    let non_manifold = topo.count_edges(EdgeKind::NonManifold);
    let plural =
        |n: usize, one: &str, many: &str| format!("{n} {}", if n == 1 { one } else { many });
    let mut parts = Vec::new();
    if mesh.degenerate_faces() > 0 {
        parts.push(plural(
            mesh.degenerate_faces(),
            "degenerate triangle dropped (repeated corner or zero area)",
            "degenerate triangles dropped (repeated corner or zero area)",
        ));
    }
    if unreferenced > 0 {
        parts.push(plural(
            unreferenced,
            "unreferenced vertex ignored",
            "unreferenced vertices ignored",
        ));
    }
    if non_manifold > 0 {
        parts.push(plural(
            non_manifold,
            "non-manifold edge (more than two triangles)",
            "non-manifold edges (more than two triangles)",
        ));
    }
    if !parts.is_empty() {
        eprintln!("{name}: {}", parts.join("; "));
    }
}

/// Reads `path`, or builds the built-in example when it is `None` (and says so on stderr).
pub fn load_mesh(path: Option<&PathBuf>, format: Option<FormatArg>) -> Result<(TriMesh, String)> {
    match path {
        Some(p) => {
            // Every reading error already names the file (and the position in it).
            let mesh = crestline::io::read_mesh(p, format.map(Into::into))
                .context("cannot load the mesh")?;
            Ok((mesh, p.display().to_string()))
        }
        None => {
            eprintln!(
                "no mesh given: using the built-in example (fandisk, a CAD part with sharp creases)"
            );
            let name = "fandisk.obj (built-in)";
            let mesh =
                crestline::io::read_mesh_bytes(BUILT_IN_EXAMPLE, Format::Obj, Path::new(name))?;
            Ok((mesh, name.into()))
        }
    }
}

/// The feature lines that guide `distance` and `simplify`: read from `path` (an OBJ with `l`
/// polylines, as `crestline extract` writes them) when given, otherwise extracted from `mesh`
/// with the default method (and said so on stderr).
pub fn load_lines(path: Option<&PathBuf>, mesh: &TriMesh) -> Result<FeatureLines> {
    match path {
        // Reading errors already name the file and line.
        Some(p) => Ok(crestline::io::lines::read_lines_obj(p).context("cannot load the lines")?),
        None => {
            let options = ExtractOptions::default();
            eprintln!(
                "no --lines given: extracting them with the default method ({:?})",
                options.method
            );
            Ok(extract(mesh, &options)
                .context("cannot extract the lines")?
                .lines)
        }
    }
}
