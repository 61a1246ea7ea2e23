//! What `crestline render` and `crestline view` show: a mesh, optional feature lines and an
//! optional per-vertex field, and the view options they share.

use std::path::{Path, PathBuf};

use anyhow::{Result, bail};
use clap::ValueEnum;
use crestline::TriMesh;
use crestline::curvature::CurvatureOptions;
use crestline::distance::{DistanceOptions, feature_distance};
use crestline::extract::surface_fields;
use crestline::lines::FeatureLines;
use crestline::lines::crease::CreaseAngle;
use crestline::render::{ColorMapChoice, FieldRange, RenderOptions, UpAxis, guess_up_axis};
use crestline::saliency::{SaliencyOptions, mesh_saliency};

use crate::cmd::curvature::field_notes;
use crate::input::{MeshArgs, PrepareArgs, prepare_mesh, read_lines};
use crate::progress::{self, note};

/// Per-vertex fields that can colour the mesh.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum FieldArg {
    /// Maximal principal curvature.
    #[value(name = "k_max", alias = "k-max")]
    KMax,
    /// Minimal principal curvature.
    #[value(name = "k_min", alias = "k-min")]
    KMin,
    /// Extremality of k_max.
    #[value(name = "e_max", alias = "e-max")]
    EMax,
    /// Extremality of k_min.
    #[value(name = "e_min", alias = "e-min")]
    EMin,
    /// Mesh saliency (Mao et al.).
    Saliency,
    /// Distance along the surface to the nearest feature line (needs --lines).
    #[value(name = "feature_distance", alias = "feature-distance")]
    FeatureDistance,
}

impl FieldArg {
    /// The name shown on the legend.
    pub fn name(self) -> &'static str {
        match self {
            FieldArg::KMax => "k_max",
            FieldArg::KMin => "k_min",
            FieldArg::EMax => "e_max",
            FieldArg::EMin => "e_min",
            FieldArg::Saliency => "saliency",
            FieldArg::FeatureDistance => "feature_distance",
        }
    }
}

/// The model's up axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum UpArg {
    /// Guessed from the mesh: Z when it stands on a flat base along Z, else Y.
    Auto,
    /// +Y up (OBJ convention).
    Y,
    /// +Z up (CAD convention).
    Z,
}

/// `--up`, shared by every command that draws the mesh.
#[derive(Debug, Clone, Copy, clap::Args)]
pub struct UpArgs {
    /// The model's up axis; `auto` guesses it from the mesh (a flat base along Z, or a
    /// sheet in an XZ plane, means Z; anything else Y) and says which it chose.
    #[arg(long, value_enum, default_value = "auto")]
    pub up: UpArg,
}

impl UpArgs {
    /// The library's up axis.
    pub fn axis(self) -> UpAxis {
        match self.up {
            UpArg::Auto => UpAxis::Auto,
            UpArg::Y => UpAxis::Y,
            UpArg::Z => UpAxis::Z,
        }
    }
}

/// `--wireframe`, shared by every command that draws PNG or SVG pictures.
#[derive(Debug, Clone, Copy, clap::Args)]
pub struct WireframeArgs {
    /// Draw the mesh's edges over the surface (PNG and SVG; hidden edges hidden, edges
    /// closer together than a few pixels faded out).
    #[arg(long)]
    pub wireframe: bool,
}

/// The up axis to draw `mesh` with: `up` itself, or the guess when it is automatic, said
/// on stderr.
pub fn resolve_up(up: UpAxis, mesh: &TriMesh) -> UpAxis {
    if up != UpAxis::Auto {
        return up;
    }
    let guess = guess_up_axis(mesh);
    note!("up axis: {guess}; choose with --up y or --up z");
    guess.axis
}

/// Colour maps.
#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum ColorMapArg {
    /// Diverging for signed fields, viridis otherwise.
    Auto,
    /// Viridis.
    Viridis,
    /// Purple-white-green, centred at 0.
    Diverging,
}

/// Arguments shared by `render` and `view`.
#[derive(Debug, clap::Args)]
pub struct SceneArgs {
    #[command(flatten)]
    pub input: MeshArgs,
    #[command(flatten)]
    pub prepare: PrepareArgs,
    /// Feature lines to draw, as `crestline extract` writes them: OBJ, PLY or JSON, chosen
    /// by the extension.
    #[arg(long, value_name = "LINES.{obj,ply,json}")]
    pub lines: Option<PathBuf>,
    /// Colour the mesh by this per-vertex field. The curvature fields and the saliency are
    /// those `crestline curvature` writes with its defaults (outlier vertices put back first,
    /// the fit split at sharp creases).
    #[arg(long, value_enum)]
    pub field: Option<FieldArg>,
    /// For --field: take every vertex as it is (`crestline curvature --keep-outliers`).
    #[arg(long)]
    pub keep_outliers: bool,
    /// Camera azimuth and elevation in degrees [default: 30,20].
    #[arg(long, value_name = "AZ,EL", value_parser = parse_view, allow_hyphen_values = true)]
    pub view: Option<(f64, f64)>,
    #[command(flatten)]
    pub up: UpArgs,
    /// Colour map for --field.
    #[arg(long, value_enum, default_value = "auto")]
    pub colormap: ColorMapArg,
    /// Field values at the ends of the colour map: `P%` clips to the P-th and (100-P)-th
    /// percentiles (P from 0 to 49.9), `full` is the whole range (0%), `MIN,MAX` fixes them
    /// [default: 2%].
    #[arg(long, value_name = "P%|full|MIN,MAX", value_parser = parse_range, allow_hyphen_values = true)]
    pub field_range: Option<FieldRange>,
    /// Line width in pixels [default: 2.5].
    #[arg(long, allow_negative_numbers = true)]
    pub line_width: Option<f64>,
    /// Do not draw ridges (the viewer starts with them off).
    #[arg(long)]
    pub no_ridges: bool,
    /// Do not draw valleys (the viewer starts with them off).
    #[arg(long)]
    pub no_valleys: bool,
}

/// A loaded scene.
pub struct Scene {
    /// The mesh.
    pub mesh: TriMesh,
    /// Feature lines, when `--lines` was given.
    pub lines: Option<FeatureLines>,
    /// One value per vertex, when `--field` was given.
    pub field: Option<Vec<f64>>,
}

impl SceneArgs {
    /// [`crate::output::check_output`] of `output` against the mesh and the lines file read.
    pub fn check_output(&self, output: &Path) -> Result<()> {
        crate::output::check_output(output, &[self.input.mesh.as_deref(), self.lines.as_deref()])
    }

    /// Loads the mesh (welded and oriented as for every command) and the lines and computes
    /// the field.
    pub fn load(&self) -> Result<Scene> {
        let (mesh, name) = progress::step("reading", || self.input.load())?;
        let mesh = prepare_mesh(mesh, &name, self.prepare)?.mesh;
        let lines = match &self.lines {
            Some(path) => Some(read_lines(path)?),
            None => None,
        };
        let field = match self.field {
            Some(f) => {
                let (values, notes) = progress::step(format!("field {}", f.name()), || {
                    compute_field(&mesh, &name, lines.as_ref(), f, self.keep_outliers)
                })?;
                for line in notes {
                    note!("{line}");
                }
                Some(values)
            }
            None => None,
        };
        Ok(Scene { mesh, lines, field })
    }

    /// The render options these arguments set (over the library's defaults).
    pub fn options(&self) -> RenderOptions {
        let mut opts = RenderOptions::default();
        if let Some((azimuth, elevation)) = self.view {
            opts = opts.with_view(azimuth, elevation);
        }
        opts.up = self.up.axis();
        opts.color_map = match self.colormap {
            ColorMapArg::Auto => ColorMapChoice::Auto,
            ColorMapArg::Viridis => ColorMapChoice::Viridis,
            ColorMapArg::Diverging => ColorMapChoice::Diverging,
        };
        if let Some(range) = self.field_range {
            opts.field_range = range;
        }
        if let Some(w) = self.line_width {
            opts.line_width = w;
        }
        opts.show_ridges = !self.no_ridges;
        opts.show_valleys = !self.no_valleys;
        if let Some(f) = self.field {
            opts.legend_title = f.name().to_string();
        }
        opts
    }
}

/// Computes the per-vertex field `field` on `mesh` (named `name` in messages) as `crestline
/// curvature` does with its defaults ([`surface_fields`]); with the notes of that estimation.
fn compute_field(
    mesh: &TriMesh,
    name: &str,
    lines: Option<&FeatureLines>,
    field: FieldArg,
    keep_outliers: bool,
) -> Result<(Vec<f64>, Vec<String>)> {
    let mut notes = Vec::new();
    let mut fields = || {
        let options = CurvatureOptions::default();
        let fields = surface_fields(mesh, &options, CreaseAngle::default(), !keep_outliers)?;
        notes = field_notes(name, &fields);
        anyhow::Ok(fields)
    };
    let values = match field {
        FieldArg::KMax => fields()?.curvature.k_max,
        FieldArg::KMin => fields()?.curvature.k_min,
        FieldArg::EMax => fields()?.curvature.e_max,
        FieldArg::EMin => fields()?.curvature.e_min,
        FieldArg::Saliency => {
            let fields = fields()?;
            let surface = fields.repaired.as_ref().unwrap_or(mesh);
            mesh_saliency(surface, &fields.curvature, &SaliencyOptions::default())?.saliency
        }
        FieldArg::FeatureDistance => {
            let Some(lines) = lines else {
                bail!("--field feature_distance needs the lines: give them with --lines");
            };
            feature_distance(mesh, lines, &DistanceOptions::default())?.vertex
        }
    };
    Ok((values, notes))
}

/// Parses `P%`, `full` or `MIN,MAX` (see `--field-range`).
fn parse_range(s: &str) -> Result<FieldRange, String> {
    let number = |t: &str| {
        t.trim()
            .parse::<f64>()
            .ok()
            .filter(|x| x.is_finite())
            .ok_or_else(|| format!("'{t}' is not a number"))
    };
    if s == "full" {
        return Ok(FieldRange::Percentile(0.0));
    }
    if let Some(p) = s.strip_suffix('%') {
        let p = number(p)?;
        if !(0.0..50.0).contains(&p) {
            return Err(format!(
                "the percentile must be from 0 to below 50, got {p}"
            ));
        }
        return Ok(FieldRange::Percentile(p));
    }
    let Some((min, max)) = s.split_once(',') else {
        return Err(format!(
            "'{s}': expected P% (for example 2%), full, or MIN,MAX"
        ));
    };
    let (min, max) = (number(min)?, number(max)?);
    if min >= max {
        return Err(format!("MIN must be below MAX, got {min},{max}"));
    }
    Ok(FieldRange::Fixed { min, max })
}

/// Parses `AZ,EL` in degrees.
fn parse_view(s: &str) -> Result<(f64, f64), String> {
    let (a, e) = s
        .split_once(',')
        .ok_or_else(|| format!("'{s}': expected AZ,EL in degrees, for example 30,20"))?;
    let num = |t: &str| {
        t.trim()
            .parse::<f64>()
            .map_err(|_| format!("'{t}' is not a number of degrees"))
    };
    Ok((num(a)?, num(e)?))
}

/// Parses `W` or `WxH` in pixels.
pub fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let num = |t: &str| {
        t.trim()
            .parse::<u32>()
            .map_err(|_| format!("'{t}' is not a number of pixels"))
    };
    match s.split_once(['x', 'X']) {
        Some((w, h)) => Ok((num(w)?, num(h)?)),
        None => num(s).map(|w| (w, w)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn view_and_size_parse() {
        assert_eq!(parse_view("30,20"), Ok((30.0, 20.0)));
        assert_eq!(parse_view("-45, -10.5"), Ok((-45.0, -10.5)));
        assert!(parse_view("30").is_err());
        assert_eq!(parse_size("800"), Ok((800, 800)));
        assert_eq!(parse_size("800x600"), Ok((800, 600)));
        assert!(parse_size("800x").is_err());
        assert_eq!(parse_range("5%"), Ok(FieldRange::Percentile(5.0)));
        assert_eq!(parse_range("full"), Ok(FieldRange::Percentile(0.0)));
        assert_eq!(
            parse_range("-1,2.5"),
            Ok(FieldRange::Fixed {
                min: -1.0,
                max: 2.5
            })
        );
        assert!(parse_range("50%").is_err() && parse_range("2,1").is_err());
    }
}
