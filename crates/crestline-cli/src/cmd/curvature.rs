//! `crestline curvature`: per-vertex principal curvatures, directions and extremalities,
//! written as a PLY with vertex properties (or CSV).

use std::io::Write;
use std::path::PathBuf;

use anyhow::{Result, bail};
use clap::ValueEnum;
use crestline::curvature::{
    Curvature, CurvatureOptions, Estimator, EstimatorOption, EstimatorSelection, select_estimator,
};
use crestline::extract::{SurfaceFields, surface_fields};
use crestline::io::{PlyWriter, VertexProperty};
use crestline::lines::crease::CreaseAngle;
use crestline::saliency::{SaliencyOptions, mesh_saliency};

use super::extract::outliers_note;
use crate::input::{OrientedMeshArgs, is_dash};
use crate::output::{
    PlyEncodingArg, check_extension, check_output, display, known_extension, to_path_or_stdout,
    to_stdout,
};
use crate::progress::{self, note};

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

/// The curvature estimator and its options, shared by `extract` and `curvature`: each flag
/// means the same in both, and flags of an estimator that does not run are refused.
#[derive(Debug, Clone, clap::Args)]
pub struct EstimatorArgs {
    /// Curvature estimator (default: jet-fit; cubic-fit with --rings).
    #[arg(long, value_enum)]
    pub estimator: Option<EstimatorArg>,
    /// Rings of YBS's cubic fit, 1 to 8 (the paper uses 1 to 4); selects the cubic-fit
    /// estimator unless --estimator says otherwise.
    #[arg(long, value_parser = super::extract::rings, allow_negative_numbers = true)]
    pub rings: Option<usize>,
    /// Radius of the jet fit's disc, in sample spacings, above 0 and at most 10 (estimator
    /// jet-fit only; default 2.5; grown on noisy meshes unless --no-noise-adaptation).
    #[arg(long, value_parser = super::extract::jet_fit_radius, allow_negative_numbers = true)]
    pub radius: Option<f64>,
    /// Degree of the jet fit, 3 or 4 (estimator jet-fit only; default 4).
    #[arg(
        long,
        value_parser = clap::value_parser!(u8).range(3..=4),
        allow_negative_numbers = true
    )]
    pub degree: Option<u8>,
    /// Do not grow the jet fit's radius with the measured noise level (estimator jet-fit
    /// only).
    #[arg(long)]
    pub no_noise_adaptation: bool,
    /// Weight of the neighbourhood in the principal directions of the shape operator, >= 0
    /// (estimator shape-operator only; default 0.5; 0 gives the paper's operator, whose
    /// directions are arbitrary on flat faces).
    #[arg(
        long,
        value_name = "LAMBDA",
        value_parser = super::extract::non_negative,
        allow_negative_numbers = true
    )]
    pub direction_support: Option<f64>,
}

impl EstimatorArgs {
    /// The estimator flags given, as the library names them.
    fn given(&self) -> Vec<EstimatorOption> {
        [
            (self.radius.is_some(), EstimatorOption::Radius),
            (self.degree.is_some(), EstimatorOption::Degree),
            (self.no_noise_adaptation, EstimatorOption::NoNoiseAdaptation),
            (self.rings.is_some(), EstimatorOption::Rings),
            (
                self.direction_support.is_some(),
                EstimatorOption::DirectionSupport,
            ),
        ]
        .into_iter()
        .filter_map(|(given, option)| given.then_some(option))
        .collect()
    }

    /// The estimator that runs and the flags of another one
    /// ([`crestline::curvature::select_estimator`]).
    fn selection(&self, default: Estimator) -> EstimatorSelection {
        select_estimator(self.estimator.map(Into::into), &self.given(), default)
    }

    /// The estimator that runs: --estimator, else the cubic fit with --rings, else `default`.
    pub fn estimator(&self, default: Estimator) -> Estimator {
        self.selection(default).estimator
    }

    /// The flags given for another estimator than the one that runs, each with why.
    pub fn unused(&self, default: Estimator) -> Vec<String> {
        self.selection(default).reasons(flag)
    }

    /// `options` with the estimator and the flags given.
    pub fn apply(&self, options: CurvatureOptions) -> CurvatureOptions {
        let mut options = options.with_estimator(self.estimator(options.estimator));
        if let Some(k) = self.rings {
            options = options.with_rings(k);
        }
        if let Some(r) = self.radius {
            options.jet_fit = options.jet_fit.with_radius(r);
        }
        if let Some(d) = self.degree {
            options.jet_fit = options.jet_fit.with_degree(d.into());
        }
        if self.no_noise_adaptation {
            options.jet_fit = options.jet_fit.with_adapt_to_noise(false);
        }
        if let Some(support) = self.direction_support {
            options.shape_operator.direction_support = support;
        }
        options
    }
}

/// The flag of an estimator option.
fn flag(option: EstimatorOption) -> &'static str {
    match option {
        EstimatorOption::Radius => "--radius",
        EstimatorOption::Degree => "--degree",
        EstimatorOption::NoNoiseAdaptation => "--no-noise-adaptation",
        EstimatorOption::Rings => "--rings",
        EstimatorOption::DirectionSupport => "--direction-support",
    }
}

/// Arguments of `crestline curvature`.
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(flatten)]
    pub input: OrientedMeshArgs,
    /// Output: a PLY with the mesh and the fields as vertex properties, or a CSV table when
    /// it ends in .csv (or with --csv); `-` for standard output (PLY unless --csv). Another
    /// format's extension (.obj, .png, .ply with --csv) is refused.
    #[arg(short, long)]
    pub output: PathBuf,
    #[command(flatten)]
    pub estimator: EstimatorArgs,
    /// Sharp creases the estimation does not reach across (each side of a crease gets its
    /// own fit, as in `extract`; estimator jet-fit only): `auto` (default: edges above the gap in the histogram of
    /// dihedral angles, or between filtered normals on a noisy mesh without one; none on scans
    /// of smooth shapes), `off`, or a dihedral angle in degrees.
    #[arg(
        long,
        value_name = "auto|off|DEGREES",
        value_parser = super::extract::creases,
        allow_negative_numbers = true
    )]
    pub creases: Option<CreaseAngle>,
    /// Write CSV (one row per vertex) instead of PLY, whatever the extension (unless it
    /// names another format); an output ending in .csv is CSV without it.
    #[arg(long)]
    pub csv: bool,
    /// Also write the mesh saliency (`saliency`) and `curv` (Mao et al.).
    #[arg(long)]
    pub saliency: bool,
    /// Take every vertex as it is. By default isolated outlier vertices (spikes), which
    /// throw off every fit whose disc holds them, are put back on the surface of their
    /// neighbours before the estimation, as in `extract`; the file's positions are written
    /// as given, with the fields of the surface so repaired.
    #[arg(long)]
    pub keep_outliers: bool,
    #[command(flatten)]
    pub ply: PlyEncodingArg,
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

/// What was done to the mesh (named `name`) before the estimation of `fields`, a line each,
/// for stderr.
pub fn field_notes(name: &str, fields: &SurfaceFields) -> Vec<String> {
    let edges = fields.crease_edges;
    let creases = (edges > 0).then(|| {
        format!(
            "{name}: estimation split at {edges} crease edges ({} curves; --creases off to \
             estimate across them)",
            fields.crease_curves
        )
    });
    [outliers_note(name, &fields.outliers), creases]
        .into_iter()
        .flatten()
        .collect()
}

/// Runs the subcommand.
pub fn run(args: Args) -> Result<()> {
    let options = curvature_options(&args)?;
    let estimator = options.estimator;
    check_output(&args.output, &[args.input.path()])?;
    let csv = writes_csv(&args)?;
    let (prepared, name) = args.input.load_prepared()?;
    let spinner = progress::spinner(format!(
        "curvature of {} vertices",
        prepared.mesh.num_vertices()
    ));
    let fields = surface_fields(
        &prepared.mesh,
        &options,
        args.creases.unwrap_or_default(),
        !args.keep_outliers,
    )?;
    let mesh = fields.repaired.as_ref().unwrap_or(&prepared.mesh);
    let curvature = &fields.curvature;
    let mut cols = columns(curvature);
    if args.saliency {
        let s = mesh_saliency(mesh, curvature, &SaliencyOptions::default())?;
        cols.push(("curv", s.curv));
        cols.push(("saliency", s.saliency));
    }
    spinner.finish_and_clear();
    for line in field_notes(&name, &fields) {
        note!("{line}");
    }
    // One row per vertex of the file: each copy of a welded vertex gets its values.
    let cols = cols
        .into_iter()
        .map(|(n, values)| Ok((n, prepared.per_given_vertex(values)?)))
        .collect::<Result<Vec<_>>>()?;
    let mesh = prepared.given_mesh();

    if csv {
        let write_csv = |out: &mut dyn Write| -> std::io::Result<()> {
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
            Ok(())
        };
        to_path_or_stdout(&args.output, write_csv)?;
    } else {
        let mut writer = PlyWriter::new(mesh)
            .encoding(args.ply.encoding())
            .comment(format!(
                "crestline curvature ({}) of {name}",
                estimator.name()
            ));
        for (n, values) in &cols {
            let single: Vec<f32> = values.iter().map(|&x| x as f32).collect();
            writer = writer.property(VertexProperty::new(*n, single))?;
        }
        if is_dash(&args.output) {
            to_stdout(|out| writer.write_to(out))?;
        } else {
            writer.write(&args.output)?;
        }
    }
    note!(
        "{name}: curvature of {} vertices ({} fallback) -> {}",
        mesh.num_vertices(),
        curvature.fallback_vertices,
        display(&args.output)
    );
    Ok(())
}

/// True when the fields are written as CSV: with --csv, or to a file ending in .csv. Refuses
/// an output whose extension names another format than the one written.
fn writes_csv(args: &Args) -> Result<bool> {
    let csv = args.csv || known_extension(&args.output).as_deref() == Some("csv");
    if csv {
        check_extension(
            &args.output,
            "CSV (--csv)",
            &["csv"],
            "give an output ending in .csv (or leave out --csv and write .ply)",
        )?;
    } else {
        check_extension(
            &args.output,
            "PLY",
            &["ply"],
            "give an output ending in .ply, or in .csv for a CSV table",
        )?;
    }
    Ok(csv)
}

/// The estimator's options from the arguments; flags of another estimator are errors.
fn curvature_options(args: &Args) -> Result<CurvatureOptions> {
    let defaults = CurvatureOptions::default().with_estimator(Estimator::JetFit);
    let estimator = args.estimator.estimator(defaults.estimator);
    let mut unused = args.estimator.unused(defaults.estimator);
    if args.creases.is_some() && estimator != Estimator::JetFit {
        unused.push(format!(
            "--creases (the estimation splits at creases with the jet-fit estimator only; this \
             run uses {})",
            estimator.name()
        ));
    }
    if !unused.is_empty() {
        bail!(
            "options that --estimator {} would not use: {}",
            estimator.name(),
            unused.join("; ")
        );
    }
    Ok(args.estimator.apply(defaults))
}
