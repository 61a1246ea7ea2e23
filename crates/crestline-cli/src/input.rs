//! Loading the inputs: the mesh (a file given by the user, or the built-in example) and the
//! feature lines that guide `distance` and `simplify`.

use std::io::{IsTerminal, Read};
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use clap::ValueEnum;
use crestline::TriMesh;
use crestline::extract::{ExtractOptions, extract};
use crestline::io::Format;
use crestline::io::mask::read_diffusion_factors;
use crestline::lines::FeatureLines;
use crestline::mesh::{EdgeKind, VertexKind, Weld};
use crestline::smoothing::extremality::{DiffusionMask, MaskRegion};

use crate::progress::{counted, note};

/// The built-in example: the fandisk CAD part (see `data/README.md`).
const BUILT_IN_EXAMPLE: &[u8] = include_bytes!("../data/fandisk.obj");

/// Mesh formats, for `--input-format` (and `--format` where a mesh is written).
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

/// `--keep-orientation` and `--no-weld`, shared by the commands that estimate curvature.
#[derive(Debug, Clone, Copy, clap::Args)]
pub struct PrepareArgs {
    /// Keep the winding of the triangles as it is. By default triangles wound against their
    /// neighbours are reversed first, then closed components whose triangles face inward
    /// (negative volume; also open ones whose holes are small enough that they have an
    /// inside, such as a scan with holes), since curvature signs follow the normals: facing
    /// inward, ridges and valleys swap, and a triangle wound the other way makes folds of its
    /// edges.
    #[arg(long)]
    pub keep_orientation: bool,
    /// Keep vertices that share a position apart. By default vertices at exactly the same
    /// position are made one first (patches exported side by side, seams split for texture
    /// or normals): otherwise the surface ends at every such seam, and so do the fits and
    /// the lines. Triangles that then repeat the corners of another (double-sided exports, a
    /// piece stored twice) are dropped too. Fields written per vertex keep one row per vertex
    /// of the file either way.
    #[arg(long)]
    pub no_weld: bool,
}

/// A mesh as the commands work on it ([`prepare_mesh`]).
pub struct Prepared {
    /// The mesh, welded and oriented: what the algorithms run on.
    pub mesh: TriMesh,
    /// How the vertices read were welded into `mesh`'s ([`crestline::mesh::Weld`]).
    pub weld: Weld,
    /// The mesh as read, oriented but not welded, when welding changed it.
    given: Option<TriMesh>,
}

impl Prepared {
    /// The mesh that fields written per vertex follow: as read (oriented, not welded), so
    /// that a row is a vertex of the file.
    pub fn given_mesh(&self) -> &TriMesh {
        self.given.as_ref().unwrap_or(&self.mesh)
    }

    /// Values per vertex of [`Prepared::mesh`] as values per vertex of
    /// [`Prepared::given_mesh`] (each copy of a welded vertex gets its value).
    pub fn per_given_vertex<T: Copy>(&self, values: Vec<T>) -> Result<Vec<T>> {
        if self.given.is_none() {
            return Ok(values);
        }
        self.weld
            .to_given(&values)
            .context("internal error: not one value per vertex of the welded mesh")
    }
}

/// Welds the vertices of `mesh` that share a position (unless `args.no_weld`) and says so,
/// says on stderr what of it the algorithms skip or treat specially (degenerate triangles
/// dropped, unreferenced vertices, non-manifold edges), then reverses the triangles wound
/// against their neighbours and the closed components that face inward (unless
/// `args.keep_orientation`) and says so. Every command that
/// estimates curvature or draws calls this (`info` reports the mesh as read; `subdivide`
/// welds it only, [`weld_mesh`]): welding and orientation are decided here for the whole CLI, by the
/// library's [`crestline::mesh::weld_coincident`] and [`crestline::mesh::orient_outward`]
/// (which `extract` also runs by default).
pub fn prepare_mesh(mesh: TriMesh, name: &str, args: PrepareArgs) -> Result<Prepared> {
    let welded = if args.no_weld {
        None
    } else {
        weld_mesh(&mesh, name)?
    };
    // The mesh as read is kept only when welding changed it.
    let (mesh, weld, given) = match welded {
        Some((welded, weld)) => (welded, weld, Some(mesh)),
        None => {
            let weld = Weld::identity(mesh.num_vertices());
            (mesh, weld, None)
        }
    };
    note_awkward_parts(&mesh, name);
    if args.keep_orientation {
        return Ok(Prepared { mesh, weld, given });
    }
    // Classified once, for the welded mesh and the mesh as read alike.
    let (report, reversed) = crestline::mesh::orientation(&mesh);
    let changed = report.inward > 0 || report.rewound_faces > 0;
    let given = match given {
        Some(given) if changed => Some(turned_like(given, &mesh, &weld, &reversed)?),
        given => given,
    };
    let mesh = crestline::mesh::reverse_faces(mesh, &reversed);
    if report.rewound_faces > 0 {
        note!(
            "{name}: {} wound against their neighbours; reversed so that normals agree \
             (--keep-orientation to keep them)",
            counted(report.rewound_faces, "triangle was", "triangles were")
        );
    }
    // A triangle soup (every triangle its own component: corners stored per triangle and
    // not exactly equal, so that the weld could not join them) has no surface to fit: no
    // lines, silently, without this.
    if mesh.num_faces() >= 100 && 2 * report.components > mesh.num_faces() {
        eprintln!(
            "{name}: warning: {} components for {} triangles: the triangles hardly share \
             corners (a triangle soup whose copies of a corner differ slightly?); curvature \
             and lines need a connected surface",
            report.components,
            mesh.num_faces()
        );
    }
    // A warning, not a note: the lines there are wrong, `-q` or not.
    if report.non_orientable > 0 {
        eprintln!(
            "{name}: warning: {} not be wound consistently (non-orientable, like a Möbius strip): \
             normals, and with them ridges and valleys, swap across a seam there",
            counted(report.non_orientable, "patch could", "patches could")
        );
    }
    if report.inward > 0 {
        let surfaces = match (report.closed, report.nearly_closed) {
            (_, 0) => "closed components",
            (0, _) => "open components with holes too small to change their inside",
            _ => "closed components (or open ones with small holes)",
        };
        note!(
            "{name}: {} of {} {surfaces} faced inward ({} triangles); reversed them so \
             that normals point outward (--keep-orientation to keep them)",
            report.inward,
            report.closed + report.nearly_closed,
            report.inward_faces
        );
    }
    Ok(Prepared { mesh, weld, given })
}

/// The mesh as read (`given`), turned where [`crestline::mesh::orient_outward`] turns the
/// mesh `welded` from it by `weld` (`reversed`: its flags per welded face, from
/// [`crestline::mesh::orientation`]): each triangle read is reversed when the welded triangle
/// over the same corners is (a triangle the weld dropped as a repeat follows the one it
/// repeats; one the weld made degenerate has none and stays as it is).
fn turned_like(
    given: TriMesh,
    welded: &TriMesh,
    weld: &Weld,
    reversed: &[bool],
) -> Result<TriMesh> {
    let corners = |t: [u32; 3]| {
        let mut key = t;
        key.sort_unstable();
        key
    };
    let turned: std::collections::HashMap<[u32; 3], bool> = welded
        .faces()
        .iter()
        .zip(reversed)
        .map(|(&t, &r)| (corners(t), r))
        .collect();
    let faces = given
        .faces()
        .iter()
        .map(|&[a, b, c]| {
            let key = corners([a, b, c].map(|v| weld.map[v as usize]));
            if turned.get(&key).copied().unwrap_or(false) {
                [a, c, b]
            } else {
                [a, b, c]
            }
        })
        .collect();
    Ok(TriMesh::new(given.positions().to_vec(), faces)?)
}

/// Welds the vertices of `mesh` that share a position ([`crestline::mesh::welded`]) and says
/// so on stderr; `None` when there were none.
pub fn weld_mesh(mesh: &TriMesh, name: &str) -> Result<Option<(TriMesh, Weld)>> {
    let Some((welded, weld)) = crestline::mesh::welded(mesh)? else {
        return Ok(None);
    };
    let (before, after) = (
        mesh.topology().count_edges(EdgeKind::Boundary),
        welded.topology().count_edges(EdgeKind::Boundary),
    );
    let mut also = String::new();
    if after != before {
        also += &format!("{before} -> {after} boundary edges; ");
    }
    if weld.merged == 0 {
        note!(
            "{name}: dropped {} triangles that repeated the corners of others (a piece stored \
             twice; --no-weld to keep them)",
            weld.duplicate_faces
        );
        return Ok(Some((welded, weld)));
    }
    if weld.duplicate_faces > 0 {
        also += &format!(
            "dropped {} triangles that then repeated others, as the two sides of a \
             double-sided export do; ",
            weld.duplicate_faces
        );
    }
    note!(
        "{name}: welded {} vertices that shared their position with another \
         ({also}--no-weld to keep them apart)",
        weld.merged
    );
    Ok(Some((welded, weld)))
}

/// One note on stderr (none with `-q`) listing the parts of `mesh` that are skipped or
/// handled specially, when there are any.
fn note_awkward_parts(mesh: &TriMesh, name: &str) {
    let topo = mesh.topology();
    let unreferenced = topo.count_vertices(VertexKind::Unreferenced);
    let non_manifold = topo.count_edges(EdgeKind::NonManifold);
    let mut parts = Vec::new();
    if mesh.degenerate_faces() > 0 {
        parts.push(counted(
            mesh.degenerate_faces(),
            "degenerate triangle dropped (repeated corner or zero area)",
            "degenerate triangles dropped (repeated corner or zero area)",
        ));
    }
    if unreferenced > 0 {
        parts.push(counted(
            unreferenced,
            "unreferenced vertex ignored",
            "unreferenced vertices ignored",
        ));
    }
    if non_manifold > 0 {
        parts.push(counted(
            non_manifold,
            "non-manifold edge (more than two triangles)",
            "non-manifold edges (more than two triangles)",
        ));
    }
    if !parts.is_empty() {
        note!("{name}: {}", parts.join("; "));
    }
}

/// The mesh a command reads: a file, `-` for standard input, or nothing (standard input
/// when it is not a terminal, the built-in example when it is).
#[derive(Debug, Clone, clap::Args)]
pub struct MeshArgs {
    /// Mesh file (OBJ, PLY, OFF, STL), or `-` for standard input. Without it, standard input
    /// is read when it is not a terminal, and the built-in example is used when it is.
    pub mesh: Option<PathBuf>,
    /// Read the mesh as this format instead of guessing from the extension (needed for
    /// standard input).
    #[arg(long, value_enum)]
    pub input_format: Option<FormatArg>,
}

impl MeshArgs {
    /// Reads the mesh; see [`load_mesh`].
    pub fn load(&self) -> Result<(TriMesh, String)> {
        load_mesh(self.mesh.as_deref(), self.input_format)
    }
}

/// The mesh of a command that estimates curvature (`curvature`, `distance`, `simplify`): the
/// file, and whether to keep its winding and its coincident vertices apart.
#[derive(Debug, Clone, clap::Args)]
pub struct OrientedMeshArgs {
    #[command(flatten)]
    pub mesh: MeshArgs,
    #[command(flatten)]
    pub prepare: PrepareArgs,
}

impl OrientedMeshArgs {
    /// The mesh file given, if any.
    pub fn path(&self) -> Option<&Path> {
        self.mesh.mesh.as_deref()
    }

    /// Reads the mesh (with a spinner) and prepares it ([`prepare_mesh`]): welded unless
    /// `--no-weld`, oriented outward unless `--keep-orientation`.
    pub fn load(&self) -> Result<(TriMesh, String)> {
        let (prepared, name) = self.load_prepared()?;
        Ok((prepared.mesh, name))
    }

    /// [`OrientedMeshArgs::load`], keeping the mesh as read for outputs per vertex.
    pub fn load_prepared(&self) -> Result<(Prepared, String)> {
        let (mesh, name) = crate::progress::step("reading", || self.mesh.load())?;
        Ok((prepare_mesh(mesh, &name, self.prepare)?, name))
    }
}

/// The name standard input goes by in messages.
pub const STDIN_NAME: &str = "<stdin>";

/// True for the path `-`, which stands for standard input or output.
pub fn is_dash(path: &Path) -> bool {
    path.as_os_str() == "-"
}

/// Reads `path` (`-`: standard input), or without a path standard input when it is not a
/// terminal, and the built-in example when it is a terminal or empty without
/// `--input-format` (said on stderr). A mesh without triangles
/// is an error.
pub fn load_mesh(path: Option<&Path>, format: Option<FormatArg>) -> Result<(TriMesh, String)> {
    let (mesh, name) = match path {
        Some(p) if is_dash(p) => read_stdin(format, "-")?,
        // `extract` runs a folder as a batch and never gets here with one.
        Some(p) if p.is_dir() => bail!(
            "{}: this is a folder, not a mesh file: give a mesh file (OBJ, PLY, OFF, STL; only \
             `crestline extract` takes folders, as a batch)",
            p.display()
        ),
        Some(p) => {
            // Every reading error already names the file (and the position in it).
            let mesh = crestline::io::read_mesh(p, format.map(Into::into))?;
            (mesh, p.display().to_string())
        }
        None if !std::io::stdin().is_terminal() && format.is_some() => read_stdin(
            format,
            "no mesh file given and standard input is not a terminal",
        )?,
        None if !std::io::stdin().is_terminal() => {
            let bytes = read_all_stdin()?;
            if bytes.is_empty() {
                // Run from a script or CI with nothing piped in: the example, as on a terminal.
                built_in_example("no mesh given and standard input is empty")?
            } else {
                parse_stdin(
                    &bytes,
                    format,
                    "no mesh file given and standard input is not a terminal",
                )?
            }
        }
        None => built_in_example("no mesh given")?,
    };
    if mesh.num_faces() == 0 {
        bail!(
            "{name}: no triangles ({} vertices, {} degenerate triangles dropped): nothing to \
             work on",
            mesh.num_vertices(),
            mesh.degenerate_faces()
        );
    }
    Ok((mesh, name))
}

/// The built-in example mesh, with a note on stderr that says `why`.
fn built_in_example(why: &str) -> Result<(TriMesh, String)> {
    eprintln!(
        "{why}: using the built-in example (fandisk, a CAD part with sharp creases); give a \
         file, or pipe one in with --input-format"
    );
    let name = "fandisk.obj (built-in)";
    let mesh = crestline::io::read_mesh_bytes(BUILT_IN_EXAMPLE, Format::Obj, Path::new(name))?;
    Ok((mesh, name.into()))
}

fn read_all_stdin() -> Result<Vec<u8>> {
    let mut bytes = Vec::new();
    std::io::stdin()
        .lock()
        .read_to_end(&mut bytes)
        .context("cannot read standard input")?;
    Ok(bytes)
}

/// Reads a whole mesh from standard input; `why` says why standard input is read.
fn read_stdin(format: Option<FormatArg>, why: &str) -> Result<(TriMesh, String)> {
    if format.is_none() {
        return parse_stdin(&[], format, why);
    }
    let bytes = read_all_stdin()?;
    if bytes.is_empty() {
        bail!("{STDIN_NAME}: standard input is empty ({why}); give a mesh file");
    }
    parse_stdin(&bytes, format, why)
}

/// Parses the bytes read from standard input as a mesh of `format`.
fn parse_stdin(bytes: &[u8], format: Option<FormatArg>, why: &str) -> Result<(TriMesh, String)> {
    let Some(format) = format else {
        bail!(
            "reading the mesh from standard input ({why}): give its format with \
             --input-format obj|ply|off|stl"
        );
    };
    let mesh = crestline::io::read_mesh_bytes(bytes, format.into(), Path::new(STDIN_NAME))?;
    Ok((mesh, STDIN_NAME.to_string()))
}

/// The per-vertex diffusion factors of the extremality smoothing: `--mask`'s file (one
/// number per vertex of the file, carried over to the prepared mesh by `weld`, see
/// [`Prepared::weld`]) scaled inside the `--mask-sphere` / `--mask-box` `regions`
/// ([`DiffusionMask::apply`]); `None` when neither is given.
pub fn diffusion_factors(
    file: Option<&Path>,
    regions: Vec<MaskRegion>,
    mesh: &TriMesh,
    weld: &Weld,
) -> Result<Option<Vec<f64>>> {
    // Vertices welded into one take the least of their factors (the most protective).
    let factors = match file {
        Some(path) => {
            let read = read_diffusion_factors(path, weld.map.len())?;
            let welded = weld.to_welded(&read, f64::min);
            Some(welded.with_context(|| format!("{}: not one factor per vertex", path.display()))?)
        }
        None => None,
    };
    Ok(DiffusionMask { regions }.apply(mesh, factors))
}

/// `--lines`: feature lines as `crestline extract` writes them (OBJ, PLY or JSON, by
/// extension), for the commands they guide.
#[derive(Debug, Clone, clap::Args)]
pub struct LinesArg {
    /// Feature lines as `crestline extract` writes them: OBJ, PLY or JSON, chosen by the
    /// extension; kinds and strengths are read back. Without it they are extracted from the
    /// mesh with the default method.
    #[arg(long, value_name = "LINES.{obj,ply,json}")]
    pub lines: Option<PathBuf>,
}

impl LinesArg {
    /// The file given, if any.
    pub fn path(&self) -> Option<&Path> {
        self.lines.as_deref()
    }
}

/// Reads feature lines written by `crestline extract` (OBJ, PLY or JSON, by extension).
pub fn read_lines(path: &Path) -> Result<FeatureLines> {
    if path.is_dir() {
        bail!(
            "{}: this is a folder, not a lines file: give the OBJ, PLY or JSON file `crestline \
             extract` wrote",
            path.display()
        );
    }
    // Reading errors already name the file and the position in it.
    Ok(crestline::io::lines::read_lines(path, None)?)
}

/// The feature lines that guide `distance` and `simplify`: read from `path` when given,
/// otherwise extracted from `mesh` with the default method (and said so on stderr).
pub fn load_lines(path: Option<&Path>, mesh: &TriMesh) -> Result<FeatureLines> {
    match path {
        Some(p) => read_lines(p),
        None => {
            let options = ExtractOptions {
                // The commands orient the mesh as they load it.
                orient_outward: false,
                ..ExtractOptions::default()
            };
            note!(
                "no --lines given: extracting them with the default method ({})",
                crate::cmd::extract::method_name(options.method())
            );
            Ok(extract(mesh, &options)
                .context("cannot extract the lines")?
                .lines)
        }
    }
}
