//! `crestline curvature`: per-vertex principal curvatures, directions and extremalities,
//! written as a PLY with vertex properties (or CSV).

use std::io::Write;
use std::path::PathBuf;
use std::time::Duration;

use anyhow::{Context, Result};
use clap::ValueEnum;
use crestline::curvature::{Curvature, CurvatureOptions, Estimator, estimate};
use crestline::io::{PlyEncoding, PlyWriter, VertexProperty};
use crestline::saliency::{SaliencyOptions, mesh_saliency};
use indicatif::{ProgressBar, ProgressStyle};

use crate::input::{FormatArg, OrientArgs, load_mesh, prepare_mesh};

/// The estimator.
#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum EstimatorArg {
    /// Discrete shape operator and extremalities (HPW 2005).
    ShapeOperator,
    /// Enhanced adjacent-normal cubic fit (YBS 2005).
    CubicFit,
    /// Polynomial fit over a geodesic disc (Cazals and Pouget 2005; independent of the triangulation).
    JetFit,
}

impl From<EstimatorArg> for Estimator {
    fn from(e: EstimatorArg) -> Self {
        match e {
            EstimatorArg::ShapeOperator => Estimator::ShapeOperator,
            EstimatorArg::CubicFit => Estimator::CubicFit,
            EstimatorArg::JetFit => Estimator::JetFit,
        }
    }
}

/// Arguments of `crestline curvature`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Mesh file (OBJ, PLY, OFF, STL). Without it, a built-in example is used.
    pub mesh: Option<PathBuf>,
    #[command(flatten)]
    pub orient: OrientArgs,
    /// Output: a PLY with the mesh and the fields as vertex properties (CSV with `--csv`).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Read the mesh as this format instead of guessing from the extension.
    #[arg(long, value_enum)]
    pub format: Option<FormatArg>,
    /// The estimator.
    #[arg(long, value_enum, default_value = "jet-fit")]
    pub estimator: EstimatorArg,
    /// Rings of the cubic fit (1 to 4).
    #[arg(long, default_value_t = 1)]
    pub rings: usize,
    /// Radius of the jet fit's disc, in sample spacings.
    #[arg(long, default_value_t = crestline::curvature::JetFitOptions::DEFAULT.radius)]
    pub radius: f64,
    /// Degree of the jet fit (3 or 4).
    #[arg(long, default_value_t = crestline::curvature::JetFitOptions::DEFAULT.degree)]
    pub degree: usize,
    /// Do not grow the jet fit's radius with the measured noise level.
    #[arg(long)]
    pub no_noise_adaptation: bool,
    /// Write CSV (one row per vertex) instead of PLY.
    #[arg(long)]
    pub csv: bool,
    /// Also write the mesh saliency (`saliency`) and `curv` (Mao et al.).
    #[arg(long)]
    pub saliency: bool,
    /// Write PLY as ascii instead of binary.
    #[arg(long)]
    pub ascii: bool,
}

/// Column names, in output order, with their values.
fn columns(c: &Curvature) -> Vec<(&'static str, Vec<f64>)> {
    let comp = |d: &[crestline::Vec3], k: usize| d.iter().map(|v| v[k]).collect::<Vec<f64>>();
    vec![
        ("k_max", c.k_max.clone()),
        ("k_min", c.k_min.clone()),
        ("e_max", c.e_max.clone()),
        ("e_min", c.e_min.clone()),
        ("dir_max_x", comp(&c.dir_max, 0)),
        ("dir_max_y", comp(&c.dir_max, 1)),
        ("dir_max_z", comp(&c.dir_max, 2)),
        ("dir_min_x", comp(&c.dir_min, 0)),
        ("dir_min_y", comp(&c.dir_min, 1)),
        ("dir_min_z", comp(&c.dir_min, 2)),
    ]
}

/// Runs the subcommand.
pub fn run(args: Args) -> Result<()> {
    let (mesh, name) = load_mesh(args.mesh.as_ref(), args.format)?;
    let mesh = prepare_mesh(mesh, &name, args.orient)?;
    let options = CurvatureOptions::default()
        .with_estimator(args.estimator.into())
        .with_rings(args.rings);
    let options = CurvatureOptions {
        jet_fit: options
            .jet_fit
            .with_radius(args.radius)
            .with_degree(args.degree)
            .with_adapt_to_noise(!args.no_noise_adaptation),
        ..options
    };
    let spinner = ProgressBar::new_spinner().with_style(
        ProgressStyle::with_template("{spinner} {msg} {elapsed}")
            .unwrap_or_else(|_| ProgressStyle::default_spinner()),
    );
    spinner.set_message(format!("curvature of {} vertices", mesh.num_vertices()));
    spinner.enable_steady_tick(Duration::from_millis(100));
    let curvature = estimate(&mesh, &options)?;
    let mut cols = columns(&curvature);
    if args.saliency {
        let s = mesh_saliency(&mesh, &curvature, &SaliencyOptions::default())?;
        cols.push(("curv", s.curv));
        cols.push(("saliency", s.saliency));
    }
    spinner.finish_and_clear();

    if args.csv {
        let file = std::fs::File::create(&args.output)
            .with_context(|| format!("cannot create {}", args.output.display()))?;
        let mut out = std::io::BufWriter::new(file);
        let header: Vec<&str> = ["x", "y", "z"]
            .into_iter()
            .chain(cols.iter().map(|(n, _)| *n))
            .collect();
        writeln!(out, "{}", header.join(","))?;
        for (v, p) in mesh.positions().iter().enumerate() {
            write!(out, "{},{},{}", p.x, p.y, p.z)?;
            for (_, values) in &cols {
                write!(out, ",{}", values[v])?;
            }
            writeln!(out)?;
        }
        out.flush()?;
    } else {
        let mut writer = PlyWriter::new(&mesh)
            .encoding(if args.ascii {
                PlyEncoding::Ascii
            } else {
                PlyEncoding::BinaryLittleEndian
            })
            .comment(format!(
                "crestline curvature ({:?}) of {name}",
                args.estimator
            ));
        for (n, values) in &cols {
            let single: Vec<f32> = values.iter().map(|&x| x as f32).collect();
            writer = writer.property(VertexProperty::new(*n, single))?;
        }
        writer.write(&args.output)?;
    }
    eprintln!(
        "{name}: curvature of {} vertices ({} fallback) -> {}",
        mesh.num_vertices(),
        curvature.fallback_vertices,
        args.output.display()
    );
    Ok(())
}
