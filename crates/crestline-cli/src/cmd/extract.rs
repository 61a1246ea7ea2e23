//! `crestline extract`: feature lines of a mesh, written as OBJ, PLY or JSON; several meshes
//! (files or folders) are processed in parallel, one output each, with a summary (see
//! `batch.rs`).

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use anyhow::{Context, Result, bail};
use clap::ValueEnum;
use crestline::curvature::Estimator;
use crestline::curvature::cubic_fit::MAX_RINGS;
use crestline::extract::{
    ExtractOptions, ExtractStats, Extraction, Method, Pipeline, Stage, extract_with_progress,
};
use crestline::io::PlyEncoding;
use crestline::io::lines::{LinesFormat, write_lines, write_lines_to};
use crestline::lines::FeatureLines;
use crestline::lines::crease::CreaseAngle;
use crestline::mesh::OutlierRepair;
use crestline::render::{self, PictureFormat, RenderOptions};
use crestline::smoothing::extremality::MaskRegion;
use crestline::smoothing::surface::SurfaceSmoothing;
use crestline::threshold::Threshold;
use crestline::{TriMesh, Vec3};
use indicatif::ProgressBar;

use super::batch;
use super::curvature::EstimatorArgs;
use crate::input::{FormatArg, PrepareArgs, diffusion_factors, is_dash, load_mesh, prepare_mesh};
use crate::output::{check_extension, check_output, display, to_stdout};
use crate::progress::{self, counted, note};
use crate::scene::{UpArg, UpArgs, WireframeArgs, resolve_up};

/// Which pipeline runs.
#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum MethodArg {
    /// Hildebrandt–Polthier–Wardetzky 2005: shape operator, extremality smoothing.
    Hpw,
    /// Yoshizawa–Belyaev–Seidel 2005: cubic fitting, gap jumping, strength T.
    Ybs,
    /// Mao–Wang–Zhou: mesh saliency and automatic threshold.
    Saliency,
}

/// Output formats for lines.
#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum LinesFormatArg {
    /// OBJ with `o ridges` / `o valleys` / `o crease-ridges` / `o crease-valleys` groups of
    /// `l` records.
    Obj,
    /// PLY vertices and edges with a kind property.
    Ply,
    /// JSON: kind, points, length and strengths of every line.
    Json,
}

/// How `--stats` prints.
#[derive(Debug, Clone, Copy, ValueEnum, PartialEq, Eq)]
pub enum StatsFormat {
    /// Aligned text on stderr.
    Text,
    /// One JSON object on stdout.
    Json,
}

/// Arguments of `crestline extract`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Mesh files (OBJ, PLY, OFF, STL) or folders of them, or `-` for standard input.
    /// Several files or a folder run as a batch: in parallel, one output each in the `-o`
    /// folder, a summary at the end. Without any, standard input is read when it is not a
    /// terminal, and the built-in example is used when it is.
    pub meshes: Vec<PathBuf>,
    #[command(flatten)]
    pub prepare: PrepareArgs,
    /// Output: a file, `-` for standard output, or a folder (an existing one, or a path
    /// ending in `/`; a batch always writes to a folder, created if needed). Default:
    /// `<mesh name>-lines.<format>` in the current folder. An extension of another format
    /// than the one written (.off, .png, or .json with --format obj) is refused.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Read the meshes as this format instead of guessing from the extension (needed for
    /// standard input).
    #[arg(long, value_enum)]
    pub input_format: Option<FormatArg>,
    /// Output format (default: from the output's extension, else OBJ).
    #[arg(long, value_enum)]
    pub format: Option<LinesFormatArg>,
    /// The method.
    #[arg(long, value_enum, default_value = "hpw")]
    pub method: MethodArg,
    /// Extremality smoothing steps, every method (the saliency method links crest points).
    /// Default: automatic. With the jet-fit estimator 2 steps on meshes the fit finds noisy
    /// (`--stats` shows the noise it measured) and none on clean ones, where the fit has
    /// averaged enough; 2 with --estimator shape-operator or cubic-fit. Any other smoothing
    /// option (--smooth-time, --no-twicing, --crease-angle, --mask*) makes the 2 steps run on
    /// clean meshes too. 0 turns it off, which for YBS is the method as published. At most
    /// 1000 (more smoothing: a larger --smooth-time).
    #[arg(long, value_parser = whole_number::<usize>, allow_negative_numbers = true)]
    pub smooth_steps: Option<usize>,
    /// Extremality smoothing step size T, relative to the squared mean edge length, above 0
    /// and at most 1e6 (default 1). A step smooths over about sqrt(T) rings, so the largest
    /// already reaches across any mesh. Given, the smoothing runs on clean meshes too (see
    /// --smooth-steps).
    #[arg(long, value_parser = positive, allow_negative_numbers = true)]
    pub smooth_time: Option<f64>,
    /// Plain extremality smoothing, as HPW smooth. By default the smoothing is twiced: the
    /// residual it removes is smoothed and added back, which removes about the same noise
    /// without the drift it gives the zeros of the extremalities (twice the steps). Given,
    /// the smoothing runs on clean meshes too (see --smooth-steps).
    #[arg(long)]
    pub no_twicing: bool,
    /// On meshes whose noise the jet fit finds white (`--stats` says so), the extremality
    /// smoothing runs up to this many times faster along the lines than across them, which
    /// takes out more of the noise without moving the lines across (default 3; 1 is HPW's
    /// isotropic smoothing; above 0 and at most 1e6). Other meshes are smoothed isotropically.
    #[arg(long, value_name = "FACTOR", value_parser = positive, allow_negative_numbers = true)]
    pub smooth_along: Option<f64>,
    /// Crease-aware extremality smoothing: damp the smoothing across edges where the
    /// curvature jumps by about this dihedral angle, in degrees, 0 to 180 (default 0.3 rad,
    /// about 17.2; 0 with --no-twicing gives HPW's plain smoothing). Given, the smoothing
    /// runs on clean meshes too (see --smooth-steps).
    #[arg(long, value_name = "DEGREES", value_parser = degrees, allow_negative_numbers = true)]
    pub crease_angle: Option<f64>,
    /// Sharp creases: `auto` (default: edges above the gap in the histogram of dihedral
    /// angles; on a noisy mesh without one, the gap between face normals filtered within the
    /// faces, as on a scan of a machined part; none when there is no gap, as on scans of
    /// smooth shapes), `off`, or a dihedral angle in degrees.
    #[arg(
        long,
        value_name = "auto|off|DEGREES",
        value_parser = creases,
        allow_negative_numbers = true
    )]
    pub creases: Option<CreaseAngle>,
    /// Strength threshold, or `auto` to pick it from the knee of the sorted strengths.
    /// HPW: the strength T of YBS eq. 5, default 1. YBS: default auto (the knee of the
    /// strengths above T = 1; 1 when there is none). Saliency: the saliency, default auto
    /// (the knee over all vertices, or a lower one of the ridge or the valley points' own).
    #[arg(long, allow_negative_numbers = true)]
    pub threshold: Option<String>,
    /// Minimum line length as a fraction of the bounding-box diagonal (of the largest part when
    /// the mesh has several), >= 0 (default 0.01).
    #[arg(long, value_parser = non_negative, allow_negative_numbers = true)]
    pub min_length: Option<f64>,
    /// Spatial fairing: largest displacement as a fraction of the bounding-box diagonal,
    /// >= 0 (for example 0.002). Off by default.
    #[arg(long, value_parser = non_negative, allow_negative_numbers = true)]
    pub fair: Option<f64>,
    /// Leave the crest lines where the traced zeros of the extremalities are. By
    /// default, on meshes the curvature fit finds noisy (its disc is then wide), they are
    /// moved across by the displacement that disc is known to cause (a correction of second
    /// order in its radius) and, on white noise, by the drift of the extremality smoothing
    /// (measured by applying it once more; nothing moves on clean meshes)
    #[arg(long)]
    pub no_debias: bool,
    /// Accepted for scripts written when the correction was opt-in; it is the default now
    #[arg(long, hide = true, conflicts_with = "no_debias")]
    pub debias: bool,
    /// Keep the lines the noise moves about, and their ends. By default, on meshes the
    /// curvature fit finds white noise on (`--stats` says), HPW and YBS drop the lines whose
    /// extremality crosses zero less than twice as steeply as its estimation noise, and cut
    /// such ends off the lines they keep: they wander off the weak crests they follow
    /// (nothing is dropped on clean meshes, nor on scans whose residual is mostly surface)
    #[arg(long)]
    pub keep_unlocated: bool,
    /// Take every vertex as it is. By default isolated outlier vertices (spikes: single
    /// vertices far off the surface their neighbours describe, as scanners leave them) are
    /// put back on that surface first, so that they are not ringed with creases and crest
    /// lines; vertices on sharp features or under white noise are not outliers by the test
    /// (`--stats` says how many moved)
    #[arg(long)]
    pub keep_outliers: bool,
    /// Surface pre-smoothing steps (implicit mean-curvature flow), for very noisy scans. Off
    /// by default (the jet fit adapts to noise); not for CAD meshes, whose surface beside the
    /// creases it rounds into short spurious crest lines. At most 1000.
    #[arg(long, value_parser = whole_number::<usize>, allow_negative_numbers = true)]
    pub pre_smooth: Option<usize>,
    #[command(flatten)]
    pub estimator: EstimatorArgs,
    /// Per-vertex diffusion factors of the extremality smoothing (inhomogeneous smoothing):
    /// a text file with one number >= 0 per vertex (whitespace separated, `#` comments).
    /// Given, the smoothing runs on clean meshes too (see --smooth-steps).
    #[arg(long)]
    pub mask: Option<PathBuf>,
    /// A sphere `x,y,z,r,factor` (r and factor >= 0) scaling the extremality smoothing
    /// inside it (repeatable; the smoothing then runs on clean meshes too).
    #[arg(
        long = "mask-sphere",
        value_name = "X,Y,Z,R,F",
        value_parser = mask_sphere,
        allow_hyphen_values = true
    )]
    pub mask_spheres: Vec<MaskRegion>,
    /// A box `x0,y0,z0,x1,y1,z1,factor` (factor >= 0) scaling the extremality smoothing
    /// inside it (repeatable; the smoothing then runs on clean meshes too).
    #[arg(
        long = "mask-box",
        value_name = "X0,Y0,Z0,X1,Y1,Z1,F",
        value_parser = mask_box,
        allow_hyphen_values = true
    )]
    pub mask_boxes: Vec<MaskRegion>,
    /// Disable gap jumping (YBS only).
    #[arg(long)]
    pub no_gaps: bool,
    /// Print statistics: triangles, singular triangles, lines, length, time per stage (a
    /// batch: one row, or one JSON object, per file).
    #[arg(long, value_enum, num_args = 0..=1, default_missing_value = "text")]
    pub stats: Option<StatsFormat>,
    /// Also write a picture of the mesh and lines (PNG), or `-` for standard output (then
    /// the lines go to a file).
    #[arg(long, value_name = "PICTURE.png")]
    pub png: Option<PathBuf>,
    /// Also write a picture with the lines as vector paths (SVG), or `-` for standard output.
    #[arg(long, value_name = "PICTURE.svg")]
    pub svg: Option<PathBuf>,
    /// Also write a self-contained interactive viewer (HTML, WebGL), or `-` for standard
    /// output.
    #[arg(long, value_name = "VIEW.html")]
    pub html: Option<PathBuf>,
    #[command(flatten)]
    pub up: UpArgs,
    #[command(flatten)]
    pub wireframe: WireframeArgs,
}

/// Runs the subcommand.
pub fn run(args: Args) -> Result<()> {
    check_method_options(&args)?;
    check_picture_options(&args)?;
    let is_batch = args.meshes.len() > 1 || args.meshes.iter().any(|p| p.is_dir());
    if is_batch {
        return batch::run(&args);
    }
    let input = args.meshes.first().map(PathBuf::as_path);
    let output = output_path(&args, input)?;
    check_one_standard_output(&args, &output)?;
    let written = [
        Some(output.as_path()),
        args.png.as_deref(),
        args.svg.as_deref(),
    ];
    for written in written.into_iter().chain([args.html.as_deref()]).flatten() {
        check_output(written, &[input, args.mask.as_deref()])?;
    }
    check_extensions(&args, &output)?;
    let mut options = options_from_args(&args)?;
    options.validate()?;
    let clock = Instant::now();
    let (mesh, name) = progress::step("reading", || load_mesh(input, args.input_format))?;
    let prepared = prepare_mesh(mesh, &name, args.prepare)?;
    let mesh = &prepared.mesh;
    let load = clock.elapsed();
    options.smoothing.diffusion = diffusion_factors(
        args.mask.as_deref(),
        mask_regions(&args),
        mesh,
        &prepared.weld,
    )?;
    let extraction = run_with_progress(mesh, &options, progress::quiet())?;

    let format = lines_format(&args, &output);
    let clock = Instant::now();
    if is_dash(&output) {
        to_stdout(|out| {
            write_lines_to(
                out,
                &extraction.lines,
                format,
                PlyEncoding::BinaryLittleEndian,
            )
        })?;
    } else {
        write_lines(
            &output,
            &extraction.lines,
            Some(format),
            PlyEncoding::BinaryLittleEndian,
        )?;
    }
    let io = IoTimes {
        load,
        write: clock.elapsed(),
    };

    let mut picture_options = RenderOptions::default().with_wireframe(args.wireframe.wireframe);
    if args.png.is_some() || args.svg.is_some() || args.html.is_some() {
        picture_options.up = resolve_up(args.up.axis(), mesh);
    }
    for (path, format) in [
        (&args.png, PictureFormat::Png),
        (&args.svg, PictureFormat::Svg),
        (&args.html, PictureFormat::Html),
    ] {
        if let Some(path) = path {
            write_picture(path, format, mesh, &extraction.lines, &picture_options)?;
            note!("wrote {}", display(path));
        }
    }

    // A warning, not a note: the lines there are wrong, `-q` or not.
    if let Some(grid) = extraction.stats.marching_cubes_grid {
        eprintln!("{}", marching_cubes_warning(&name, grid.spacing));
    }
    if !progress::quiet() {
        print_summary(&name, &output, &extraction.stats, &options);
    }
    match args.stats {
        Some(StatsFormat::Text) => eprint!("{}", stats_text(&extraction, &io)),
        Some(StatsFormat::Json) => println!(
            "{}",
            serde_json::to_string_pretty(&stats_json(&extraction, mesh, &io))?
        ),
        None => {}
    }
    Ok(())
}

/// `2 ridges, 2 valleys, 34 convex and 4 concave creases`: the library's counts, crest lines
/// and creases apart as the JSON lines file counts them; the creases only when there are some.
pub fn describe_counts(s: &ExtractStats) -> String {
    let mut text = format!(
        "{}, {}",
        counted(s.ridges, "ridge", "ridges"),
        counted(s.valleys, "valley", "valleys")
    );
    let creases = s.crease_ridges + s.crease_valleys;
    if creases > 0 {
        text += &format!(
            ", {} convex and {} concave {}",
            s.crease_ridges,
            s.crease_valleys,
            if creases == 1 { "crease" } else { "creases" }
        );
    }
    text
}

/// The summary line of the outliers put back before the estimation (none when none moved);
/// `extract`, `curvature` and the fields of `render` and `view` alike.
pub fn outliers_note(name: &str, outliers: &OutlierRepair) -> Option<String> {
    (!outliers.vertices.is_empty()).then(|| {
        format!(
            "{name}: {} (spikes off the surface of their neighbours) put back on it first; \
             --keep-outliers keeps them",
            counted(
                outliers.vertices.len(),
                "outlier vertex",
                "outlier vertices"
            )
        )
    })
}

/// The warning for a mesh left as marching cubes made it, on a grid of `spacing`
/// ([`crestline::mesh::find_lattice`]); `extract` and its batches alike.
pub fn marching_cubes_warning(name: &str, spacing: [f64; 3]) -> String {
    let [x, y, z] = spacing.map(significant);
    format!(
        "{name}: warning: the vertices lie on the edges of a grid of spacing {x} x {y} x {z} \
         (marching cubes output, not moved onto the surface): the terraces of its interpolation \
         are crest lines of the mesh and may come out as rings of lines; move the vertices onto \
         the level set first (README, raw marching cubes)"
    )
}

/// `x` with six significant digits (`80.7701`, `0.000123457`; a length of a mesh modelled in
/// metres at the scale of microns is not `0.0000`), in scientific notation beyond 1e-4 and
/// 1e9.
pub fn significant(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let magnitude = x.abs().log10().floor();
    if (-4.0..9.0).contains(&magnitude) {
        let decimals = (5.0 - magnitude).max(0.0) as usize;
        format!("{x:.decimals$}")
    } else {
        format!("{x:.5e}")
    }
}

/// The one-paragraph summary on stderr: counts, creases, and what the automatic threshold
/// found.
fn print_summary(name: &str, output: &Path, s: &ExtractStats, options: &ExtractOptions) {
    eprintln!(
        "{name}: {} lines ({}), total length {} -> {}",
        s.lines,
        describe_counts(s),
        significant(s.total_length),
        display(output)
    );
    let smoothed = s
        .stage_times
        .iter()
        .any(|(stage, _)| *stage == crestline::extract::Stage::ExtremalitySmoothing);
    if let Some(j) = s.jet_fit
        && j.may_be_truncation_error()
        && smoothed
    {
        eprintln!(
            "{name}: the fit's residual ({:.4} spacings, not white) is as low as a coarse \
             clean mesh's truncation error, and the extremalities were smoothed as a scan's; if \
             the mesh is clean and its features only a few edges across, --smooth-steps 0 keeps \
             them",
            j.noise
        );
    }
    if let Some(line) = outliers_note(name, &s.outliers) {
        eprintln!("{line}");
    }
    if s.creases > 0 {
        eprintln!(
            "sharp creases: dihedral angle > {:.1} degrees{}, length {}",
            s.crease_threshold.unwrap_or(f64::NAN),
            if s.crease_normals_filtered {
                " between filtered normals (the mesh is noisy)"
            } else {
                ""
            },
            significant(s.crease_length)
        );
    }
    if s.threshold_is_split {
        eprintln!(
            "automatic threshold: {:.6} (the saliency rises without a knee: the split of its upper half){}",
            s.threshold,
            family_thresholds(s)
        );
    } else if s.threshold_is_auto {
        eprintln!(
            "automatic threshold: {:.6}{}",
            s.threshold,
            family_thresholds(s)
        );
    } else if options.pipeline.threshold().is_auto() {
        match options.method() {
            Method::Saliency => {
                eprintln!(
                    "automatic threshold: the saliency is flat (or too few values), no feature points"
                )
            }
            _ => eprintln!(
                "automatic threshold: the line strengths have no knee, kept T >= {}",
                s.threshold
            ),
        }
    }
}

/// The saliency method's thresholds of ridge and valley points where one is a family's own
/// knee (`crestline::saliency::family`), for the summary; empty otherwise.
fn family_thresholds(s: &ExtractStats) -> String {
    match s.family_thresholds {
        Some([ridge, valley]) if ridge != s.threshold || valley != s.threshold => {
            format!("; ridge points {ridge:.6}, valley points {valley:.6} (a family's own knee)")
        }
        _ => String::new(),
    }
}

/// Writes the picture of `--png`, `--svg` or `--html` into `path` (`-`: standard output) in
/// `format`, whatever the extension (a contradicting one was refused up front).
fn write_picture(
    path: &Path,
    format: PictureFormat,
    mesh: &TriMesh,
    lines: &FeatureLines,
    options: &RenderOptions,
) -> Result<()> {
    let lines = Some(lines);
    if is_dash(path) {
        let bytes = match format {
            PictureFormat::Png => render::render_png(mesh, lines, None, options)?,
            PictureFormat::Svg => render::render_svg(mesh, lines, None, options)?.into_bytes(),
            PictureFormat::Html => render::render_html(mesh, lines, None, options)?.into_bytes(),
        };
        return to_stdout(|out| out.write_all(&bytes));
    }
    match format {
        PictureFormat::Png => render::write_png(path, mesh, lines, None, options)?,
        PictureFormat::Svg => render::write_svg(path, mesh, lines, None, options)?,
        PictureFormat::Html => render::write_html(path, mesh, lines, None, options)?,
    }
    Ok(())
}

/// Refuses more than one output on standard output: the lines (`-o -`), `--stats=json` and
/// the pictures (`--png -`, `--svg -`, `--html -`) would be mixed into one stream.
fn check_one_standard_output(args: &Args, output: &Path) -> Result<()> {
    let dash = |path: &Option<PathBuf>| path.as_deref().is_some_and(is_dash);
    let claims: Vec<&str> = [
        (is_dash(output), "-o -"),
        (args.stats == Some(StatsFormat::Json), "--stats=json"),
        (dash(&args.png), "--png -"),
        (dash(&args.svg), "--svg -"),
        (dash(&args.html), "--html -"),
    ]
    .into_iter()
    .filter_map(|(claims, name)| claims.then_some(name))
    .collect();
    match claims.as_slice() {
        [] | [_] => Ok(()),
        [first @ .., last] => bail!(
            "{} and {last} {} write to standard output: choose one (give the others a file)",
            first.join(", "),
            if claims.len() == 2 { "both" } else { "all" }
        ),
    }
}

/// Refuses outputs whose extension names another format than the one written into them:
/// `-o` against the lines format (`--format`, else the extension's, else OBJ), and each
/// picture against its flag.
fn check_extensions(args: &Args, output: &Path) -> Result<()> {
    let format = lines_format(args, output);
    let extension = format.extension();
    let upper = extension.to_ascii_uppercase();
    if args.format.is_some() {
        check_extension(
            output,
            &format!("{upper} lines (--format {extension})"),
            &[extension],
            &format!("give an output ending in .{extension}"),
        )?;
    } else {
        check_extension(
            output,
            &format!("{upper} lines"),
            &["obj", "ply", "json"],
            "give an output ending in .obj, .ply or .json (or choose the format with --format)",
        )?;
    }
    for (path, flag, written, expected) in [
        (&args.png, "--png", "a PNG picture", &["png"][..]),
        (&args.svg, "--svg", "an SVG picture", &["svg"]),
        (&args.html, "--html", "an HTML viewer", &["html", "htm"]),
    ] {
        if let Some(path) = path {
            check_extension(
                path,
                &format!("{written} ({flag})"),
                expected,
                &format!(
                    "give {flag} a file ending in .{} (--png, --svg and --html each write their \
                     own format)",
                    expected[0]
                ),
            )?;
        }
    }
    Ok(())
}

/// The format the lines are written in: `--format`, else the output's extension, else OBJ.
pub fn lines_format(args: &Args, output: &Path) -> LinesFormat {
    let format = args.format.map(|f| match f {
        LinesFormatArg::Obj => LinesFormat::Obj,
        LinesFormatArg::Ply => LinesFormat::Ply,
        LinesFormatArg::Json => LinesFormat::Json,
    });
    format
        .or_else(|| LinesFormat::from_path(output))
        .unwrap_or(LinesFormat::Obj)
}

/// Where the lines of one mesh go: `-o` (a file, `-`, or a folder to put the default name
/// in), else the default name in the current folder.
fn output_path(args: &Args, input: Option<&Path>) -> Result<PathBuf> {
    match &args.output {
        Some(o) if o.is_dir() || o.as_os_str().to_string_lossy().ends_with('/') => {
            std::fs::create_dir_all(o).with_context(|| format!("cannot create {}", o.display()))?;
            Ok(o.join(default_output(input, args)))
        }
        Some(o) => Ok(o.clone()),
        None => Ok(default_output(input, args)),
    }
}

/// The method the arguments select.
fn method(args: &Args) -> Method {
    match args.method {
        MethodArg::Hpw => Method::Hpw,
        MethodArg::Ybs => Method::Ybs,
        MethodArg::Saliency => Method::Saliency,
    }
}

/// The method's command-line name (`hpw`, `ybs`, `saliency`).
pub fn method_name(method: Method) -> &'static str {
    match method {
        Method::Hpw => "hpw",
        Method::Ybs => "ybs",
        Method::Saliency => "saliency",
    }
}

/// Refuses options that the chosen method or estimator would not use, before any work.
fn check_method_options(args: &Args) -> Result<()> {
    let method = method(args);
    let defaults = ExtractOptions::for_method(method);
    let method_name = method_name(method);
    let mut unused: Vec<String> = Vec::new();
    if args.no_gaps && method != Method::Ybs {
        unused.push("--no-gaps (gap jumping is part of --method ybs only)".into());
    }
    unused.extend(args.estimator.unused(defaults.curvature.estimator));
    if args.no_debias && args.estimator.estimator(defaults.curvature.estimator) != Estimator::JetFit
    {
        unused.push(
            "--no-debias (the lines are moved back by the jet fit's bias only; the papers' \
             estimators read no disc)"
                .into(),
        );
    }
    if args.smooth_along.is_some()
        && args.estimator.estimator(defaults.curvature.estimator) != Estimator::JetFit
    {
        unused.push(
            "--smooth-along (only the jet fit tells white noise; the papers' estimators are \
             smoothed as HPW smooth)"
                .into(),
        );
    }
    if args.keep_unlocated && method == Method::Saliency {
        unused.push(
            "--keep-unlocated (HPW and YBS drop the lines the noise moves about; the saliency \
             method links feature points)"
                .into(),
        );
    } else if args.keep_unlocated
        && args.estimator.estimator(defaults.curvature.estimator) != Estimator::JetFit
    {
        unused.push(
            "--keep-unlocated (only the jet fit measures the noise; the papers' estimators \
             read no disc)"
                .into(),
        );
    }
    if !unused.is_empty() {
        bail!(
            "options that --method {method_name} would not use: {}",
            unused.join("; ")
        );
    }
    // `--smooth-along` does not make clean meshes smoothed, but it has nothing to shape at 0
    // steps either.
    let mut smoothing = smoothing_options_given(args);
    if args.smooth_along.is_some() {
        smoothing.push("--smooth-along");
    }
    if args.smooth_steps == Some(0) && !smoothing.is_empty() {
        bail!(
            "{}: the extremality smoothing they set does not run with --smooth-steps 0",
            smoothing.join(", ")
        );
    }
    Ok(())
}

/// Refuses the picture options without a picture to apply them to.
fn check_picture_options(args: &Args) -> Result<()> {
    let raster = args.png.is_some() || args.svg.is_some();
    if args.wireframe.wireframe && !raster {
        bail!("--wireframe draws on the picture of --png or --svg: give one of them");
    }
    if args.up.up != UpArg::Auto && !raster && args.html.is_none() {
        bail!("--up orients the picture of --png, --svg or --html: give one of them");
    }
    Ok(())
}

/// Parses a number > 0.
pub fn positive(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(x) if x.is_finite() && x > 0.0 => Ok(x),
        _ => Err(format!("expected a number > 0, got '{s}'")),
    }
}

/// Parses a whole number >= 0: a count of steps, levels or faces. Negative numbers get a
/// message that says so (clap's own parser says "invalid digit found in string").
pub fn whole_number<T: TryFrom<u128>>(s: &str) -> Result<T, String> {
    match s.trim().parse::<u128>() {
        Ok(n) => T::try_from(n).map_err(|_| format!("'{s}' is too large")),
        Err(_) => Err(format!(
            "expected a non-negative integer (0, 1, 2, ...), got '{s}'"
        )),
    }
}

/// Parses a number >= 0.
pub fn non_negative(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(x) if x.is_finite() && x >= 0.0 => Ok(x),
        _ => Err(format!("expected a number >= 0, got '{s}'")),
    }
}

/// Parses an angle in degrees, 0 to 180.
fn degrees(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(x) if (0.0..=180.0).contains(&x) => Ok(x),
        _ => Err(format!(
            "expected an angle in degrees from 0 to 180, got '{s}'"
        )),
    }
}

/// The largest `--radius` of the jet fit, in sample spacings: the library's
/// ([`crestline::curvature::jet_fit::MAX_RADIUS`], where the reason is).
pub const MAX_JET_FIT_RADIUS: f64 = crestline::curvature::jet_fit::MAX_RADIUS;

/// Parses the jet fit's radius in sample spacings, above 0 and at most
/// [`MAX_JET_FIT_RADIUS`].
pub fn jet_fit_radius(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(r) if r.is_finite() && r > 0.0 && r <= MAX_JET_FIT_RADIUS => Ok(r),
        _ => Err(format!(
            "expected a radius in sample spacings above 0 and at most {MAX_JET_FIT_RADIUS} \
             (larger discs blur every feature and take minutes), got '{s}'"
        )),
    }
}

/// Parses the rings of the cubic fit, 1 to [`MAX_RINGS`] (the library's limit).
pub fn rings(s: &str) -> Result<usize, String> {
    match s.parse::<usize>() {
        Ok(k) if (1..=MAX_RINGS).contains(&k) => Ok(k),
        _ => Err(format!(
            "expected a whole number of rings from 1 to {MAX_RINGS}, got '{s}'"
        )),
    }
}

/// Parses `--creases`: `auto`, `off` or a dihedral angle in degrees strictly between 0 and 180.
pub fn creases(s: &str) -> Result<CreaseAngle, String> {
    match s {
        "auto" => Ok(CreaseAngle::Auto),
        "off" => Ok(CreaseAngle::Off),
        _ => match s.parse::<f64>() {
            Ok(d) if d > 0.0 && d < 180.0 => Ok(CreaseAngle::Degrees(d)),
            _ => Err(format!(
                "expected `auto`, `off` or an angle in degrees between 0 and 180, got '{s}'"
            )),
        },
    }
}

/// Turns the arguments into the library's options.
pub fn options_from_args(args: &Args) -> Result<ExtractOptions> {
    let mut o = ExtractOptions::for_method(method(args));
    // Every mesh is oriented as it is loaded (`prepare_mesh`), as for the other commands.
    o.orient_outward = false;
    if let Some(n) = args.smooth_steps {
        o.smoothing.steps = n;
    }
    // The library smooths clean meshes only when told to: a smoothing option given is that
    // (otherwise `--smooth-time 50` would change nothing on fandisk, in silence).
    if args.smooth_steps.is_some() || !smoothing_options_given(args).is_empty() {
        o.smooth_only_noisy = false;
    }
    if let Some(t) = args.smooth_time {
        o.smoothing.time_step = t;
    }
    o.smoothing.twicing = !args.no_twicing;
    if let Some(factor) = args.smooth_along {
        o.white_noise_along_lines = factor;
    }
    if let Some(degrees) = args.crease_angle {
        o.smoothing.crease_angle = degrees.to_radians();
    }
    if let Some(angle) = args.creases {
        o.creases.angle = angle;
    }
    match args.threshold.as_deref() {
        Some("auto") => o.pipeline.set_threshold(o.pipeline.automatic_threshold()),
        Some(x) => {
            let t = x
                .parse::<f64>()
                .ok()
                .filter(|t| t.is_finite())
                .with_context(|| format!("--threshold takes a number or `auto`, got `{x}`"))?;
            o.pipeline.set_threshold(Threshold::Fixed(t));
        }
        None => {}
    }
    if let Some(l) = args.min_length {
        o.min_length = l;
    }
    if let Some(f) = args.fair {
        o.fairing.tolerance = f;
    }
    o.debias_lines = !args.no_debias;
    o.drop_unlocated_lines = !args.keep_unlocated;
    o.repair_outliers = !args.keep_outliers;
    if let Some(n) = args.pre_smooth {
        o.pre_smoothing = SurfaceSmoothing {
            steps: n,
            ..Default::default()
        };
    }
    o.curvature = args.estimator.apply(o.curvature);
    if let (true, Pipeline::Ybs(ybs)) = (args.no_gaps, &mut o.pipeline) {
        ybs.gaps = None;
    }
    Ok(o)
}

/// The options of the extremality smoothing given besides `--smooth-steps`, by flag.
fn smoothing_options_given(args: &Args) -> Vec<&'static str> {
    [
        (args.smooth_time.is_some(), "--smooth-time"),
        (args.no_twicing, "--no-twicing"),
        (args.crease_angle.is_some(), "--crease-angle"),
        (args.mask.is_some(), "--mask"),
        (!args.mask_spheres.is_empty(), "--mask-sphere"),
        (!args.mask_boxes.is_empty(), "--mask-box"),
    ]
    .into_iter()
    .filter_map(|(given, flag)| given.then_some(flag))
    .collect()
}

/// The `--mask-sphere` regions, then the `--mask-box` ones (the last containing a vertex
/// wins).
pub fn mask_regions(args: &Args) -> Vec<MaskRegion> {
    args.mask_spheres
        .iter()
        .chain(&args.mask_boxes)
        .cloned()
        .collect()
}

/// Parses `--mask-sphere x,y,z,r,factor`.
fn mask_sphere(s: &str) -> Result<MaskRegion, String> {
    let [x, y, z, radius, factor] = numbers(s)?;
    if radius < 0.0 {
        return Err(format!("radius '{radius}' must be a number >= 0"));
    }
    check_factor(factor)?;
    Ok(MaskRegion::Sphere {
        center: Vec3::new(x, y, z),
        radius,
        factor,
    })
}

/// Parses `--mask-box x0,y0,z0,x1,y1,z1,factor`.
fn mask_box(s: &str) -> Result<MaskRegion, String> {
    let [x0, y0, z0, x1, y1, z1, factor] = numbers(s)?;
    check_factor(factor)?;
    Ok(MaskRegion::Box {
        min: Vec3::new(x0, y0, z0),
        max: Vec3::new(x1, y1, z1),
        factor,
    })
}

/// Refuses a diffusion factor below 0, as `--mask` files do: diffusion cannot be negative.
fn check_factor(factor: f64) -> Result<(), String> {
    if factor >= 0.0 {
        Ok(())
    } else {
        Err(format!("factor '{factor}' must be a finite number >= 0"))
    }
}

/// `N` comma-separated finite numbers.
fn numbers<const N: usize>(text: &str) -> Result<[f64; N], String> {
    let expected = || format!("expected {N} comma-separated finite numbers, got '{text}'");
    let v: Vec<f64> = text
        .split(',')
        .map(|t| t.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| expected())?;
    match <[f64; N]>::try_from(v) {
        Ok(v) if v.iter().all(|x| x.is_finite()) => Ok(v),
        _ => Err(expected()),
    }
}

/// `<mesh name>-lines.<format>` (`example` for the built-in example, `stdin` for standard
/// input).
pub fn default_output(mesh: Option<&Path>, args: &Args) -> PathBuf {
    let stem = match mesh {
        Some(p) if is_dash(p) => "stdin".into(),
        Some(p) => p
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "mesh".into()),
        None => "example".into(),
    };
    let extension = lines_format(args, Path::new("")).extension();
    PathBuf::from(format!("{stem}-lines.{extension}"))
}

/// Runs the extraction with a spinner per stage on stderr (unless quiet).
pub fn run_with_progress(
    mesh: &TriMesh,
    options: &ExtractOptions,
    quiet: bool,
) -> Result<Extraction> {
    let mut spinner: Option<ProgressBar> = None;
    let mut progress = |stage: Stage, done: Option<Duration>| {
        if quiet {
            return;
        }
        match done {
            None => spinner = Some(progress::spinner(stage.name())),
            Some(t) => {
                if let Some(bar) = spinner.take() {
                    bar.finish_and_clear();
                }
                if t > Duration::from_millis(500) {
                    eprintln!("{} done in {:.2} s", stage.name(), t.as_secs_f64());
                }
            }
        }
    };
    Ok(extract_with_progress(mesh, options, &mut progress)?)
}

/// Wall times of reading the mesh and writing the lines (pictures excluded).
pub struct IoTimes {
    /// Reading the mesh.
    pub load: Duration,
    /// Writing the lines.
    pub write: Duration,
}

fn stats_text(x: &Extraction, io: &IoTimes) -> String {
    let s = &x.stats;
    let pct = |n: usize| 100.0 * n as f64 / s.triangles.max(1) as f64;
    let mut out = String::new();
    out += &format!("triangles              {}\n", s.triangles);
    if let Some(grid) = s.marching_cubes_grid {
        let [x, y, z] = grid.spacing.map(significant);
        out += &format!("marching cubes grid    spacing {x} x {y} x {z} (vertices on its edges)\n");
    }
    if let Some(largest) = s.outliers.distances.iter().copied().reduce(f64::max) {
        out += &format!(
            "outliers               {} moved onto their neighbours' surface (the farthest by {}; --keep-outliers keeps them)\n",
            counted(s.outliers.vertices.len(), "vertex", "vertices"),
            significant(largest)
        );
    }
    out += &format!(
        "singular (max/min)     {} ({:.2}%) / {} ({:.2}%)\n",
        s.trace.singular_max,
        pct(s.trace.singular_max),
        s.trace.singular_min,
        pct(s.trace.singular_min)
    );
    out += &format!("lines traced           {}\n", s.lines_traced);
    if s.lines_unlocated > 0 {
        out += &format!(
            "lines unlocated        {} (dropped: the noise moves them about)\n",
            s.lines_unlocated
        );
    }
    if s.lines_trimmed > 0 {
        out += &format!(
            "lines trimmed          {} (ends the noise moves about cut off, before the threshold)\n",
            s.lines_trimmed
        );
    }
    out += &format!(
        "lines kept             {} ({})\n",
        s.lines,
        describe_counts(s)
    );
    out += &format!(
        "total length           {} ({:.2} diagonals)\n",
        significant(s.total_length),
        s.total_length / s.scale.max(f64::MIN_POSITIVE)
    );
    out += &format!(
        "threshold              {:.6}{}\n",
        s.threshold,
        match (s.threshold_is_split, s.threshold_is_auto) {
            (true, _) => " (auto: split, no knee)",
            (false, true) => " (auto)",
            _ => "",
        }
    );
    if let Some([ridge, valley]) = s.family_thresholds {
        out += &format!("threshold by family    ridges {ridge:.6}, valleys {valley:.6}\n");
    }
    out += &match s.crease_threshold {
        Some(t) => format!(
            "creases                {} (dihedral angle > {:.2} degrees{}, length {})\n",
            s.creases,
            t,
            if s.crease_normals_filtered {
                " between filtered normals"
            } else {
                ""
            },
            significant(s.crease_length)
        ),
        None => "creases                none\n".to_string(),
    };
    if s.gaps_jumped > 0 {
        out += &format!("gaps jumped            {}\n", s.gaps_jumped);
    }
    if let Some(j) = s.jet_fit {
        out += &format!(
            "jet fit                radius {:.2} spacings ({:.4} model units), quartic weight {:.2}, noise {}\n",
            j.radius,
            j.radius * j.spacing,
            j.quartic_weight,
            if j.noise > crestline::curvature::jet_fit::REFERENCE_NOISE {
                format!(
                    "{:.4} spacings (standard deviation {:.4}; x{:.2} from 2.5 to 5 spacings: {})",
                    j.noise,
                    j.sigma,
                    j.noise_growth,
                    if j.white_noise() {
                        "white"
                    } else {
                        "not white"
                    }
                )
            } else {
                "none measured".to_string()
            }
        );
        if j.triangle_sampled > 0 {
            out += &format!(
                "fitted on triangles    {} vertices (discs along long thin triangles, as of CAD fans and strips: slower, no noise measured there)\n",
                j.triangle_sampled
            );
        }
    }
    let times = std::iter::once(("load", io.load))
        .chain(s.stage_times.iter().map(|(stage, t)| (stage.name(), *t)))
        .chain(std::iter::once(("write", io.write)));
    for (name, t) in times {
        out += &format!("time {:<22} {:.3} s\n", name, t.as_secs_f64());
    }
    out
}

/// The figures of `--stats=json`.
pub fn stats_json(x: &Extraction, mesh: &TriMesh, io: &IoTimes) -> serde_json::Value {
    let s = &x.stats;
    let mut seconds: serde_json::Map<String, serde_json::Value> = s
        .stage_times
        .iter()
        .map(|(st, t)| (st.name().to_string(), serde_json::json!(t.as_secs_f64())))
        .collect();
    seconds.insert("load".into(), serde_json::json!(io.load.as_secs_f64()));
    seconds.insert("write".into(), serde_json::json!(io.write.as_secs_f64()));
    serde_json::json!({
        "triangles": s.triangles,
        "outliers_moved": s.outliers.vertices.len(),
        "marching_cubes_grid": s.marching_cubes_grid.map(|grid| grid.spacing),
        "singular_max": s.trace.singular_max,
        "singular_min": s.trace.singular_min,
        "lines_traced": s.lines_traced,
        "lines_unlocated": s.lines_unlocated,
        "lines_trimmed": s.lines_trimmed,
        "lines": s.lines,
        // Crest lines and creases apart, as the JSON lines file counts them.
        "ridges": s.ridges,
        "valleys": s.valleys,
        "crease_ridges": s.crease_ridges,
        "crease_valleys": s.crease_valleys,
        "total_length": s.total_length,
        "creases": s.creases,
        "crease_length": s.crease_length,
        "crease_threshold_degrees": s.crease_threshold,
        "crease_normals_filtered": s.crease_normals_filtered,
        "diagonal": mesh.bounding_box().diagonal(),
        "scale": s.scale,
        "threshold": s.threshold,
        "threshold_auto": s.threshold_is_auto,
        "threshold_split": s.threshold_is_split,
        "threshold_ridges": s.family_thresholds.map(|t| t[0]),
        "threshold_valleys": s.family_thresholds.map(|t| t[1]),
        "gaps_jumped": s.gaps_jumped,
        "fallback_vertices": s.fallback_vertices,
        "jet_fit": s.jet_fit.map(|j| serde_json::json!({
            "spacing": j.spacing,
            "radius_spacings": j.radius,
            "noise_spacings": j.noise,
            "noise_sigma_spacings": j.sigma,
            "quartic_weight": j.quartic_weight,
            "noise_growth": j.noise_growth,
            "white_noise": j.white_noise(),
            "triangle_sampled_vertices": j.triangle_sampled,
        })),
        "load_seconds": io.load.as_secs_f64(),
        "write_seconds": io.write.as_secs_f64(),
        "stage_seconds": seconds,
    })
}
