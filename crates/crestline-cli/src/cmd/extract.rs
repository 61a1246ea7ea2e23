//! `crestline extract`: feature lines of a mesh, written as OBJ, PLY or JSON.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use anyhow::{Context, Result, bail};
use clap::ValueEnum;
use crestline::curvature::Estimator;
use crestline::extract::{ExtractOptions, Extraction, Method, Stage, extract_with_progress};
use crestline::io::PlyEncoding;
use crestline::io::lines::{LinesFormat, write_lines};
use crestline::io::mask::read_diffusion_factors;
use crestline::lines::crease::CreaseAngle;
use crestline::smoothing::extremality::{DiffusionMask, MaskRegion};
use crestline::smoothing::surface::SurfaceSmoothing;
use crestline::{TriMesh, Vec3};
use indicatif::{ProgressBar, ProgressStyle};

use super::curvature::EstimatorArg;
use crate::input::{FormatArg, OrientArgs, load_mesh, prepare_mesh};

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
    /// Mesh file (OBJ, PLY, OFF, STL). Without it, a built-in example is used.
    pub mesh: Option<PathBuf>,
    #[command(flatten)]
    pub orient: OrientArgs,
    /// Output file for the lines. Default: `<mesh name>-lines.obj` in the current folder.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Read the mesh as this format instead of guessing from the extension.
    #[arg(long, value_enum)]
    pub input_format: Option<FormatArg>,
    /// Output format (default: from the output's extension, else OBJ).
    #[arg(long, value_enum)]
    pub format: Option<LinesFormatArg>,
    /// The method.
    #[arg(long, value_enum, default_value = "hpw")]
    pub method: MethodArg,
    /// Extremality smoothing steps (default 2 for HPW and YBS; 0 turns it off, which for
    /// YBS is the method as published).
    #[arg(long)]
    pub smooth_steps: Option<usize>,
    /// Extremality smoothing step size, relative to the squared mean edge length (default 1).
    #[arg(long)]
    pub smooth_time: Option<f64>,
    /// Crease-aware smoothing: damp the smoothing across edges where the curvature jumps by
    /// about this dihedral angle, in degrees (default 17; 0 gives HPW's plain smoothing).
    #[arg(long, value_name = "DEGREES")]
    pub crease_angle: Option<f64>,
    /// Sharp creases: `auto` (default: edges above the gap in the histogram of dihedral
    /// angles; none when there is no gap, as on scans), `off`, or a dihedral angle in degrees.
    #[arg(long, value_name = "auto|off|DEGREES")]
    pub creases: Option<String>,
    /// Weight of the neighbourhood in the principal directions of the shape operator (HPW;
    /// default 0.5; 0 gives the paper's operator, whose directions are arbitrary on flat faces).
    #[arg(long, value_name = "LAMBDA")]
    pub direction_support: Option<f64>,
    /// Strength threshold, or `auto` to pick it from the knee of the sorted strengths.
    /// HPW: the strength T of YBS eq. 5, default 1. YBS: default auto (the knee of the
    /// strengths above T = 1; 1 when there is none). Saliency: the saliency, default auto.
    #[arg(long)]
    pub threshold: Option<String>,
    /// Minimum line length as a fraction of the bounding-box diagonal (default 0.01).
    #[arg(long)]
    pub min_length: Option<f64>,
    /// Spatial fairing: largest displacement as a fraction of the bounding-box diagonal
    /// (for example 0.002). Off by default.
    #[arg(long)]
    pub fair: Option<f64>,
    /// Surface pre-smoothing steps (implicit mean-curvature flow). Off by default.
    #[arg(long)]
    pub pre_smooth: Option<usize>,
    /// Curvature estimator (default: jet-fit for hpw and ybs, cubic-fit for saliency).
    #[arg(long, value_enum)]
    pub estimator: Option<EstimatorArg>,
    /// Radius of the jet fit's disc, in sample spacings (default 2.5).
    #[arg(long)]
    pub radius: Option<f64>,
    /// Rings of YBS's cubic fit (1 to 4); selects the cubic-fit estimator unless
    /// `--estimator` says otherwise.
    #[arg(long)]
    pub rings: Option<usize>,
    /// Per-vertex diffusion factors for inhomogeneous smoothing: a text file with one number
    /// per vertex (whitespace separated, `#` comments).
    #[arg(long)]
    pub mask: Option<PathBuf>,
    /// A sphere `x,y,z,r,factor` scaling the smoothing inside it (repeatable).
    #[arg(long = "mask-sphere", value_name = "X,Y,Z,R,F")]
    pub mask_spheres: Vec<String>,
    /// A box `x0,y0,z0,x1,y1,z1,factor` scaling the smoothing inside it (repeatable).
    #[arg(long = "mask-box", value_name = "X0,Y0,Z0,X1,Y1,Z1,F")]
    pub mask_boxes: Vec<String>,
    /// Disable YBS gap jumping.
    #[arg(long)]
    pub no_gaps: bool,
    /// Print statistics: triangles, singular triangles, lines, length, time per stage.
    #[arg(long, value_enum, num_args = 0..=1, default_missing_value = "text")]
    pub stats: Option<StatsFormat>,
    /// Also write a picture of the mesh and lines (PNG).
    #[arg(long, value_name = "PICTURE.png")]
    pub png: Option<PathBuf>,
    /// Also write a picture with the lines as vector paths (SVG).
    #[arg(long, value_name = "PICTURE.svg")]
    pub svg: Option<PathBuf>,
    /// Also write a self-contained interactive viewer (HTML, WebGL).
    #[arg(long, value_name = "VIEW.html")]
    pub html: Option<PathBuf>,
    /// Do not show progress.
    #[arg(short, long)]
    pub quiet: bool,
}

/// Runs the subcommand.
pub fn run(args: Args) -> Result<()> {
    let clock = Instant::now();
    let (mesh, name) = load_mesh(args.mesh.as_ref(), args.input_format)?;
    let mesh = prepare_mesh(mesh, &name, args.orient)?;
    let load = clock.elapsed();
    let options = options_from_args(&args, &mesh)?;
    let extraction = run_with_progress(&mesh, &options, args.quiet)?;

    let output = args
        .output
        .clone()
        .unwrap_or_else(|| default_output(args.mesh.as_deref()));
    let format = args.format.map(|f| match f {
        LinesFormatArg::Obj => LinesFormat::Obj,
        LinesFormatArg::Ply => LinesFormat::Ply,
        LinesFormatArg::Json => LinesFormat::Json,
    });
    let format = format
        .or_else(|| LinesFormat::from_path(&output))
        .unwrap_or(LinesFormat::Obj);
    let clock = Instant::now();
    write_lines(
        &output,
        &extraction.lines,
        Some(format),
        PlyEncoding::BinaryLittleEndian,
    )?;
    let io = IoTimes {
        load,
        write: clock.elapsed(),
    };

    let picture_options = crestline::render::RenderOptions::default();
    for (path, write) in [
        (&args.png, crestline::render::write_png as PictureWriter),
        (&args.svg, crestline::render::write_svg),
        (&args.html, crestline::render::write_html),
    ] {
        if let Some(path) = path {
            write(path, &mesh, Some(&extraction.lines), None, &picture_options)?;
            if !args.quiet {
                eprintln!("wrote {}", path.display());
            }
        }
    }

    let s = &extraction.stats;
    if !args.quiet {
        eprintln!(
            "{name}: {} lines ({} ridges, {} valleys), total length {:.4} -> {}",
            s.lines,
            s.ridges,
            s.valleys,
            s.total_length,
            output.display()
        );
        if s.creases > 0 {
            eprintln!(
                "{} sharp creases (dihedral angle > {:.1} degrees), length {:.4}",
                s.creases,
                s.crease_threshold.unwrap_or(f64::NAN),
                s.crease_length
            );
        }
        if s.threshold_is_auto {
            eprintln!("automatic threshold: {:.6}", s.threshold);
        } else if options.auto_threshold {
            match options.method {
                Method::Saliency => {
                    eprintln!("automatic threshold: the saliency has no knee, no feature points")
                }
                _ => eprintln!(
                    "automatic threshold: the line strengths have no knee, kept T >= {}",
                    s.threshold
                ),
            }
        }
    }
    match args.stats {
        Some(StatsFormat::Text) => eprint!("{}", stats_text(&extraction, &mesh, &io)),
        Some(StatsFormat::Json) => println!(
            "{}",
            serde_json::to_string_pretty(&stats_json(&extraction, &mesh, &io))?
        ),
        None => {}
    }
    Ok(())
}

type PictureWriter = fn(
    &Path,
    &TriMesh,
    Option<&crestline::lines::FeatureLines>,
    Option<&[f64]>,
    &crestline::render::RenderOptions,
) -> crestline::Result<()>;

/// Turns the arguments into the library's options.
pub fn options_from_args(args: &Args, mesh: &TriMesh) -> Result<ExtractOptions> {
    let method = match args.method {
        MethodArg::Hpw => Method::Hpw,
        MethodArg::Ybs => Method::Ybs,
        MethodArg::Saliency => Method::Saliency,
    };
    let mut o = ExtractOptions::for_method(method);
    if let Some(n) = args.smooth_steps {
        o.smoothing.steps = n;
        o.smooth_only_noisy = false;
    }
    if let Some(t) = args.smooth_time {
        o.smoothing.time_step = t;
    }
    if let Some(degrees) = args.crease_angle {
        o.smoothing.crease_angle = degrees.to_radians();
    }
    match args.creases.as_deref() {
        Some("auto") => o.creases.angle = CreaseAngle::Auto,
        Some("off") => o.creases.angle = CreaseAngle::Off,
        Some(x) => {
            let degrees: f64 = x.parse().with_context(|| {
                format!("--creases takes `auto`, `off` or an angle in degrees, got `{x}`")
            })?;
            o.creases.angle = CreaseAngle::Degrees(degrees);
        }
        None => {}
    }
    if let Some(support) = args.direction_support {
        o.curvature.shape_operator.direction_support = support;
    }
    match args.threshold.as_deref() {
        Some("auto") => o.auto_threshold = true,
        Some(x) => {
            o.filter.threshold = x
                .parse()
                .with_context(|| format!("--threshold takes a number or `auto`, got `{x}`"))?;
            o.auto_threshold = false;
        }
        None => {}
    }
    if let Some(l) = args.min_length {
        o.filter.min_length = l;
    }
    let diagonal = mesh.bounding_box().diagonal();
    if let Some(f) = args.fair {
        o.fairing.tolerance = f * diagonal;
    }
    if let Some(n) = args.pre_smooth {
        o.pre_smoothing = SurfaceSmoothing {
            steps: n,
            ..Default::default()
        };
    }
    if let Some(k) = args.rings {
        o.curvature = o
            .curvature
            .with_rings(k)
            .with_estimator(Estimator::CubicFit);
    }
    if let Some(e) = args.estimator {
        o.curvature.estimator = e.into();
    }
    if let Some(r) = args.radius {
        o.curvature.jet_fit.radius = r;
    }
    if args.no_gaps {
        o.gaps = None;
    }
    o.smoothing.diffusion = diffusion_factors(args, mesh)?;
    Ok(o)
}

fn diffusion_factors(args: &Args, mesh: &TriMesh) -> Result<Option<Vec<f64>>> {
    let mut factors = match &args.mask {
        Some(path) => Some(read_diffusion_factors(path, mesh.num_vertices())?),
        None => None,
    };
    let mut mask = DiffusionMask::default();
    for s in &args.mask_spheres {
        let v = numbers(s, 5, "--mask-sphere")?;
        mask.regions.push(MaskRegion::Sphere {
            center: Vec3::new(v[0], v[1], v[2]),
            radius: v[3],
            factor: v[4],
        });
    }
    for s in &args.mask_boxes {
        let v = numbers(s, 7, "--mask-box")?;
        mask.regions.push(MaskRegion::Box {
            min: Vec3::new(v[0], v[1], v[2]),
            max: Vec3::new(v[3], v[4], v[5]),
            factor: v[6],
        });
    }
    if !mask.regions.is_empty() {
        let regions = mask.factors(mesh);
        // Regions apply on top of the file's factors, where they contain the vertex.
        factors = Some(match factors {
            Some(f) => f.iter().zip(&regions).map(|(a, b)| a * b).collect(),
            None => regions,
        });
    }
    Ok(factors)
}

fn numbers(text: &str, count: usize, flag: &str) -> Result<Vec<f64>> {
    let v: Vec<f64> = text
        .split(',')
        .map(|t| t.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .with_context(|| format!("{flag} takes {count} comma-separated numbers, got `{text}`"))?;
    if v.len() != count || v.iter().any(|x| !x.is_finite()) {
        bail!("{flag} takes {count} comma-separated finite numbers, got `{text}`");
    }
    Ok(v)
}

fn default_output(mesh: Option<&Path>) -> PathBuf {
    let stem = mesh
        .and_then(|p| p.file_stem())
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "example".into());
    PathBuf::from(format!("{stem}-lines.obj"))
}

/// Runs the extraction with a spinner per stage on stderr (unless quiet).
pub fn run_with_progress(
    mesh: &TriMesh,
    options: &ExtractOptions,
    quiet: bool,
) -> Result<Extraction> {
    let mut spinner: Option<ProgressBar> = None;
    let style = ProgressStyle::with_template("{spinner} {msg} {elapsed}")
        .unwrap_or_else(|_| ProgressStyle::default_spinner());
    let mut progress = |stage: Stage, done: Option<Duration>| {
        if quiet {
            return;
        }
        match done {
            None => {
                let bar = ProgressBar::new_spinner().with_style(style.clone());
                bar.set_message(stage.name());
                bar.enable_steady_tick(Duration::from_millis(100));
                spinner = Some(bar);
            }
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
struct IoTimes {
    load: Duration,
    write: Duration,
}

fn stats_text(x: &Extraction, mesh: &TriMesh, io: &IoTimes) -> String {
    let s = &x.stats;
    let pct = |n: usize| 100.0 * n as f64 / s.triangles.max(1) as f64;
    let mut out = String::new();
    out += &format!("triangles              {}\n", s.triangles);
    out += &format!(
        "singular (max/min)     {} ({:.2}%) / {} ({:.2}%)\n",
        s.trace.singular_max,
        pct(s.trace.singular_max),
        s.trace.singular_min,
        pct(s.trace.singular_min)
    );
    out += &format!("lines traced           {}\n", s.lines_traced);
    out += &format!(
        "lines kept             {} ({} ridges, {} valleys)\n",
        s.lines, s.ridges, s.valleys
    );
    out += &format!(
        "total length           {:.6} ({:.2} diagonals)\n",
        s.total_length,
        s.total_length / mesh.bounding_box().diagonal().max(f64::MIN_POSITIVE)
    );
    out += &format!(
        "threshold              {:.6}{}\n",
        s.threshold,
        if s.threshold_is_auto { " (auto)" } else { "" }
    );
    out += &match s.crease_threshold {
        Some(t) => format!(
            "creases                {} (dihedral angle > {:.2} degrees, length {:.6})\n",
            s.creases, t, s.crease_length
        ),
        None => "creases                none\n".to_string(),
    };
    if s.gaps_jumped > 0 {
        out += &format!("gaps jumped            {}\n", s.gaps_jumped);
    }
    if let Some(j) = s.jet_fit {
        out += &format!(
            "jet fit                radius {:.2} spacings ({:.4} model units), noise {}\n",
            j.radius,
            j.radius * j.spacing,
            if j.noise > crestline::curvature::jet_fit::REFERENCE_NOISE {
                format!("{:.4} spacings", j.noise)
            } else {
                "none measured".to_string()
            }
        );
    }
    let times = std::iter::once(("load", io.load))
        .chain(s.stage_times.iter().map(|(stage, t)| (stage.name(), *t)))
        .chain(std::iter::once(("write", io.write)));
    for (name, t) in times {
        out += &format!("time {:<22} {:.3} s\n", name, t.as_secs_f64());
    }
    out
}

fn stats_json(x: &Extraction, mesh: &TriMesh, io: &IoTimes) -> serde_json::Value {
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
        "singular_max": s.trace.singular_max,
        "singular_min": s.trace.singular_min,
        "lines_traced": s.lines_traced,
        "lines": s.lines,
        "ridges": s.ridges,
        "valleys": s.valleys,
        "total_length": s.total_length,
        "creases": s.creases,
        "crease_length": s.crease_length,
        "crease_threshold_degrees": s.crease_threshold,
        "diagonal": mesh.bounding_box().diagonal(),
        "threshold": s.threshold,
        "threshold_auto": s.threshold_is_auto,
        "gaps_jumped": s.gaps_jumped,
        "fallback_vertices": s.fallback_vertices,
        "jet_fit": s.jet_fit.map(|j| serde_json::json!({
            "spacing": j.spacing,
            "radius_spacings": j.radius,
            "noise_spacings": j.noise,
        })),
        "load_seconds": io.load.as_secs_f64(),
        "write_seconds": io.write.as_secs_f64(),
        "stage_seconds": seconds,
    })
}
