//! Pictures of a mesh and its feature lines: PNG and SVG renders, colour maps and a
//! self-contained HTML viewer.
//!
//! ## What
//! [`render_image`] draws a shaded mesh, optionally coloured by a per-vertex field (with a
//! legend), and the feature lines on top with their hidden parts removed. [`render_png`],
//! [`render_svg`] and [`render_html`] produce the three file formats; [`write_png`],
//! [`write_svg`], [`write_html`] and [`write_picture`] write them to a file in one call.
//!
//! This module needs the `render` cargo feature (off by default, it adds the `tiny-skia`
//! dependency): `crestline = { version = "0.1", features = ["render"] }`.
//!
//! ## How
//! Everything runs on the CPU, one step per file:
//! 1. `camera.rs` — an orthographic camera turning around the model (azimuth, elevation in
//!    degrees) and fitted to the projected mesh; `up_axis.rs` — the model's up axis, guessed
//!    from a flat base when not given.
//! 2. `raster.rs` — a z-buffer rasteriser writing, per pixel, the depth and the index of the
//!    nearest face (a "visibility buffer"), parallel over horizontal bands of the image;
//!    then a shading pass: Lambert diffuse plus a Blinn specular highlight from a light
//!    attached to the camera, two-sided (back faces are lit like front faces).
//! 3. `colormap.rs` — viridis for one-signed fields, a diverging purple–white–green map
//!    centred at 0 for signed fields, a robust range from percentiles, and the legend.
//!    `wireframe.rs` — optionally, the edges of the visible faces, faded where they crowd.
//! 4. `hidden_lines.rs` — every line segment is cut into pieces about one pixel long and each
//!    piece's depth is tested against the z-buffer (with a small bias); consecutive visible
//!    pieces are joined into strokes, drawn antialiased with `tiny-skia`.
//! 5. `svg.rs` — the shaded mesh as an embedded PNG under the visible strokes as `<path>`s.
//! 6. `html.rs` — mesh and lines as base64 typed arrays in one HTML file with a hand-written
//!    WebGL viewer (orbit, zoom, toggles).
//!
//! Ridges are drawn red (`#d7191c`) and valleys blue (`#2c7bb6`), each with a thin dark halo
//! so that they stay readable over a colour map (see [`RenderOptions`]).
//!
//! ## Limits
//! One sample per pixel for the mesh: silhouettes are not antialiased (lines are). The depth
//! test of a line piece takes the farthest depth of the 3×3 pixels around it, so a line
//! behind a surface within one pixel of that surface's silhouette, or behind a sheet
//! thinner than the depth bias, is drawn. Perspective is not offered.

mod base64;
mod camera;
mod colormap;
mod font;
mod hidden_lines;
mod html;
mod raster;
mod svg;
mod up_axis;
mod wireframe;

use std::io::Write;
use std::path::Path;

use crate::error::{Error, Result};
use crate::lines::FeatureLines;
use crate::mesh::{TriMesh, Vec3};

pub use camera::{Camera, Viewport};
pub use colormap::{ColorMap, ColorMapChoice, ColorScale, FieldRange, percentile_range};
pub use hidden_lines::VisibleStroke;
pub use html::render_html;
pub use svg::render_svg;
pub use up_axis::{UpAxis, UpGuess, UpReason, guess_up_axis};

/// An sRGB colour, 8 bits per channel.
pub type Rgb = [u8; 3];

/// How a picture is made.
///
/// Build with [`RenderOptions::default`] (or [`RenderOptions::DEFAULT`]) and the `with_*`
/// methods.
#[derive(Debug, Clone, PartialEq)]
pub struct RenderOptions {
    /// Image width in pixels (1..=16384). Default: 1024.
    pub width: u32,
    /// Image height in pixels (1..=16384). Default: 1024.
    pub height: u32,
    /// Camera azimuth in degrees, turning around the up axis; positive moves the camera
    /// towards +X. Default: 30.
    pub azimuth: f64,
    /// Camera elevation in degrees above the horizontal plane, in [-90, 90]. Default: 20.
    pub elevation: f64,
    /// The model's up axis. Default: [`UpAxis::Auto`], guessed from the mesh by
    /// [`guess_up_axis`] (a flat base along Z gives Z, anything else Y).
    pub up: UpAxis,
    /// Free border around the mesh as a fraction of the image size, in [0, 0.45].
    /// Default: 0.05.
    pub margin: f64,
    /// Background colour. Default: white `[255, 255, 255]`.
    pub background: Rgb,
    /// Surface colour where no field is shown. Default: light grey `[200, 200, 200]`.
    pub surface: Rgb,
    /// Colour of ridges. Default: red `[215, 25, 28]` (`#d7191c`).
    pub ridge_color: Rgb,
    /// Colour of valleys. Default: blue `[44, 123, 182]` (`#2c7bb6`).
    pub valley_color: Rgb,
    /// Colour of the halo drawn under every line, one pixel wider on each side; `None` for
    /// no halo. Default: `Some([30, 30, 30])`.
    pub line_halo: Option<Rgb>,
    /// Draw ridges. Default: true.
    pub show_ridges: bool,
    /// Draw valleys. Default: true.
    pub show_valleys: bool,
    /// Show the field's colour map when a field is given. Default: true.
    pub show_field: bool,
    /// Line width in pixels. Default: 2.5.
    pub line_width: f64,
    /// How far (as a fraction of the bounding-box diagonal) a line point may lie behind the
    /// surface and still count as visible. Default: 0.004.
    pub depth_bias: f64,
    /// Interpolate normals across faces, but not across folds of more than 30 degrees (a
    /// corner there averages the faces within 30° of its own; false: one normal per face).
    /// Default: true.
    pub smooth_shading: bool,
    /// Light that reaches every surface, in [0, 1]; the diffuse part is `1 - ambient`.
    /// Default: 0.3.
    pub ambient: f64,
    /// Strength of the specular highlight, in [0, 1]. Default: 0.15.
    pub specular: f64,
    /// Blinn exponent of the highlight (larger: smaller, sharper). Default: 40.
    pub shininess: f64,
    /// Colour map for the field. Default: [`ColorMapChoice::Auto`] (diverging when the
    /// robust range has both signs, viridis otherwise).
    pub color_map: ColorMapChoice,
    /// Field values mapped to the ends of the colour map. Default:
    /// [`FieldRange::Percentile`]`(2.0)` (the 2nd and 98th percentiles).
    pub field_range: FieldRange,
    /// Draw a colour bar with its end values when a field is shown. Default: true.
    pub legend: bool,
    /// Title written above the colour bar (ASCII letters, digits, `_ . - +`). Default: empty.
    pub legend_title: String,
    /// Draw the mesh's edges over the surface, hidden edges hidden, in PNG and SVG pictures
    /// (the HTML viewer has no wireframe). Edges fade out where they come closer than a few
    /// pixels, so a dense mesh shows its surface rather than a dark smear. Default: false.
    pub wireframe: bool,
    /// Colour of the wireframe. Default: dark grey `[40, 40, 40]`.
    pub wireframe_color: Rgb,
}

impl RenderOptions {
    /// The default options, as a constant.
    pub const DEFAULT: RenderOptions = RenderOptions {
        width: 1024,
        height: 1024,
        azimuth: 30.0,
        elevation: 20.0,
        up: UpAxis::Auto,
        margin: 0.05,
        background: [255, 255, 255],
        surface: [200, 200, 200],
        ridge_color: [215, 25, 28],
        valley_color: [44, 123, 182],
        line_halo: Some([30, 30, 30]),
        show_ridges: true,
        show_valleys: true,
        show_field: true,
        line_width: 2.5,
        depth_bias: 0.004,
        smooth_shading: true,
        ambient: 0.3,
        specular: 0.15,
        shininess: 40.0,
        color_map: ColorMapChoice::Auto,
        field_range: FieldRange::Percentile(2.0),
        legend: true,
        legend_title: String::new(),
        wireframe: false,
        wireframe_color: [40, 40, 40],
    };

    /// Sets the image size in pixels.
    pub fn with_size(mut self, width: u32, height: u32) -> Self {
        self.width = width;
        self.height = height;
        self
    }

    /// Sets the camera azimuth and elevation in degrees.
    pub fn with_view(mut self, azimuth: f64, elevation: f64) -> Self {
        self.azimuth = azimuth;
        self.elevation = elevation;
        self
    }

    /// Sets the model's up axis.
    pub fn with_up(mut self, up: UpAxis) -> Self {
        self.up = up;
        self
    }

    /// Draws the mesh's edges (or not).
    pub fn with_wireframe(mut self, wireframe: bool) -> Self {
        self.wireframe = wireframe;
        self
    }

    /// Sets the title of the legend.
    pub fn with_legend_title(mut self, title: impl Into<String>) -> Self {
        self.legend_title = title.into();
        self
    }

    /// Checks every field's range.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] naming the first option out of range.
    pub fn validate(&self) -> Result<()> {
        const MAX_SIDE: u32 = 16384;
        let bad = |what: String| Err(Error::InvalidInput(what));
        if !(1..=MAX_SIDE).contains(&self.width) || !(1..=MAX_SIDE).contains(&self.height) {
            return bad(format!(
                "image size {}x{} is outside 1..={MAX_SIDE} pixels per side",
                self.width, self.height
            ));
        }
        if !self.azimuth.is_finite() || !(-90.0..=90.0).contains(&self.elevation) {
            return bad(format!(
                "view {},{}: the azimuth must be finite and the elevation within [-90, 90] degrees",
                self.azimuth, self.elevation
            ));
        }
        let unit_ranges = [
            ("margin", self.margin, 0.0, 0.45),
            ("ambient", self.ambient, 0.0, 1.0),
            ("specular", self.specular, 0.0, 1.0),
            ("depth_bias", self.depth_bias, 0.0, 1.0),
            ("line_width", self.line_width, 0.0, 1000.0),
            ("shininess", self.shininess, 0.0, 1e4),
        ];
        for (name, v, lo, hi) in unit_ranges {
            if !(lo..=hi).contains(&v) {
                return bad(format!("{name} = {v} is outside [{lo}, {hi}]"));
            }
        }
        self.field_range.validate()
    }
}

impl Default for RenderOptions {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// An RGBA picture, 8 bits per channel, rows from the top.
#[derive(Debug, Clone, PartialEq)]
pub struct Image {
    pixmap: tiny_skia::Pixmap,
}

impl Image {
    /// Width in pixels.
    pub fn width(&self) -> u32 {
        self.pixmap.width()
    }

    /// Height in pixels.
    pub fn height(&self) -> u32 {
        self.pixmap.height()
    }

    /// The colour of pixel (`x`, `y`) as RGBA, `None` outside the image.
    pub fn pixel(&self, x: u32, y: u32) -> Option<[u8; 4]> {
        self.pixmap.pixel(x, y).map(|p| {
            let c = p.demultiply();
            [c.red(), c.green(), c.blue(), c.alpha()]
        })
    }

    /// The picture encoded as PNG.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] if the encoder fails (it does not for valid images).
    pub fn to_png(&self) -> Result<Vec<u8>> {
        self.pixmap
            .encode_png()
            .map_err(|e| Error::InvalidInput(format!("PNG encoding failed: {e}")))
    }

    /// Writes the picture as a PNG file.
    ///
    /// # Errors
    /// [`Error::Io`] when the file cannot be written.
    pub fn write_png(&self, path: &Path) -> Result<()> {
        let bytes = self.to_png()?;
        crate::io::write_atomically(path, |out| out.write_all(&bytes))
    }
}

/// A rendered mesh (with its legend) before the lines are drawn, and the visible parts of
/// the lines as strokes in pixel coordinates. PNG draws the strokes into the image; SVG
/// writes them as paths.
#[derive(Debug, Clone)]
pub struct Frame {
    /// The shaded mesh, colour map and legend; no lines.
    pub image: Image,
    /// Visible parts of the lines, in drawing order (valleys first, then ridges).
    pub strokes: Vec<VisibleStroke>,
    /// The camera that made the picture.
    pub camera: Camera,
    /// The up axis the camera used ([`UpAxis::Auto`] resolved).
    pub up: UpAxis,
}

/// Renders the mesh and the visible parts of the lines, keeping the strokes apart from the
/// raster image (the first half of [`render_image`] and [`render_svg`]).
///
/// `field`, when given, holds one value per mesh vertex; non-finite values are drawn in the
/// surface colour.
///
/// # Errors
/// [`Error::InvalidInput`] for options out of range, a field whose length is not the number
/// of vertices, or a field without a single finite value.
pub fn render_frame(
    mesh: &TriMesh,
    lines: Option<&FeatureLines>,
    field: Option<&[f64]>,
    opts: &RenderOptions,
) -> Result<Frame> {
    opts.validate()?;
    if mesh.num_faces() >= raster::NO_FACE as usize {
        return Err(Error::InvalidInput(format!(
            "{} faces is more than the renderer indexes",
            mesh.num_faces()
        )));
    }
    let scale = field_scale(mesh, field, opts)?;
    let (width, height) = (opts.width as usize, opts.height as usize);
    let legend_width = match scale {
        Some(_) if opts.legend => colormap::legend_width(width, height),
        _ => 0,
    };
    let viewport = Viewport {
        x: 0.0,
        y: 0.0,
        width: (width - legend_width) as f64,
        height: height as f64,
    };
    let up = opts.up.resolve(mesh);
    let camera = Camera::orbit(opts.azimuth, opts.elevation, up).fit(
        fit_points(mesh, lines),
        viewport,
        opts.margin,
    );
    let screen = raster::project_vertices(mesh, &camera);
    let visibility = raster::rasterize(&screen, mesh.faces(), width, height);
    let mut rgba = vec![0u8; width * height * 4];
    let shading = raster::Shading::new(mesh, &camera, opts);
    let colors = scale.as_ref().zip(field);
    raster::shade(&visibility, mesh, &screen, &shading, colors, &mut rgba);
    if opts.wireframe {
        wireframe::draw(&visibility, mesh, &screen, opts.wireframe_color, &mut rgba);
    }
    if let (Some(scale), true) = (&scale, opts.legend) {
        colormap::draw_legend(&mut rgba, width, height, scale, &opts.legend_title);
    }
    let strokes = match lines {
        Some(lines) => {
            let bias = opts.depth_bias * mesh.bounding_box().diagonal();
            hidden_lines::visible_strokes(lines, &camera, &visibility, bias, opts)
        }
        None => Vec::new(),
    };
    let size = tiny_skia::IntSize::from_wh(opts.width, opts.height)
        .ok_or_else(|| Error::InvalidInput("empty image".into()))?;
    // Every pixel is opaque, so straight and premultiplied alpha coincide.
    let pixmap = tiny_skia::Pixmap::from_vec(rgba, size)
        .ok_or_else(|| Error::InvalidInput("image buffer has the wrong size".into()))?;
    Ok(Frame {
        image: Image { pixmap },
        strokes,
        camera,
        up,
    })
}

/// Renders the shaded mesh, the optional field with its legend and the visible parts of the
/// lines into an image.
///
/// # Errors
/// As [`render_frame`].
pub fn render_image(
    mesh: &TriMesh,
    lines: Option<&FeatureLines>,
    field: Option<&[f64]>,
    opts: &RenderOptions,
) -> Result<Image> {
    let mut frame = render_frame(mesh, lines, field, opts)?;
    hidden_lines::draw_strokes(&mut frame.image.pixmap, &frame.strokes, opts);
    Ok(frame.image)
}

/// Renders as [`render_image`] and encodes the picture as PNG.
///
/// ```
/// use crestline::render::{RenderOptions, render_png};
///
/// # fn main() -> crestline::Result<()> {
/// let (mesh, creases) = crestline::shapes::pillow_box(1.0, 0.25, 8);
/// let png = render_png(&mesh, Some(&creases), None, &RenderOptions::default().with_size(64, 48))?;
/// assert!(png.starts_with(b"\x89PNG"));
/// # Ok(())
/// # }
/// ```
///
/// # Errors
/// As [`render_frame`].
pub fn render_png(
    mesh: &TriMesh,
    lines: Option<&FeatureLines>,
    field: Option<&[f64]>,
    opts: &RenderOptions,
) -> Result<Vec<u8>> {
    render_image(mesh, lines, field, opts)?.to_png()
}

/// Renders a PNG picture into `path`.
///
/// # Errors
/// As [`render_frame`], and [`Error::Io`] when the file cannot be written.
pub fn write_png(
    path: &Path,
    mesh: &TriMesh,
    lines: Option<&FeatureLines>,
    field: Option<&[f64]>,
    opts: &RenderOptions,
) -> Result<()> {
    render_image(mesh, lines, field, opts)?.write_png(path)
}

/// Renders an SVG picture into `path`.
///
/// # Errors
/// As [`render_frame`], and [`Error::Io`] when the file cannot be written.
pub fn write_svg(
    path: &Path,
    mesh: &TriMesh,
    lines: Option<&FeatureLines>,
    field: Option<&[f64]>,
    opts: &RenderOptions,
) -> Result<()> {
    let svg = render_svg(mesh, lines, field, opts)?;
    crate::io::write_atomically(path, |out| out.write_all(svg.as_bytes()))
}

/// Writes the interactive HTML viewer into `path`.
///
/// # Errors
/// As [`render_html`], and [`Error::Io`] when the file cannot be written.
pub fn write_html(
    path: &Path,
    mesh: &TriMesh,
    lines: Option<&FeatureLines>,
    field: Option<&[f64]>,
    opts: &RenderOptions,
) -> Result<()> {
    let html = render_html(mesh, lines, field, opts)?;
    crate::io::write_atomically(path, |out| out.write_all(html.as_bytes()))
}

/// The picture formats, chosen from a file's extension by [`PictureFormat::from_path`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PictureFormat {
    /// A raster image.
    Png,
    /// A raster mesh under vector lines.
    Svg,
    /// The interactive WebGL viewer.
    Html,
}

impl PictureFormat {
    /// The format named by the extension of `path` (`png`, `svg`, `html`/`htm`, any case).
    ///
    /// # Errors
    /// [`Error::InvalidInput`] for any other extension.
    pub fn from_path(path: &Path) -> Result<Self> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match ext.as_deref() {
            Some("png") => Ok(PictureFormat::Png),
            Some("svg") => Ok(PictureFormat::Svg),
            Some("html" | "htm") => Ok(PictureFormat::Html),
            _ => Err(Error::InvalidInput(format!(
                "{}: cannot tell the picture format; use the extension .png, .svg or .html",
                path.display()
            ))),
        }
    }
}

/// Writes a PNG, SVG or HTML picture into `path`, the format chosen by its extension.
///
/// # Errors
/// As [`PictureFormat::from_path`], [`render_frame`] and [`render_html`]; [`Error::Io`]
/// when the file cannot be written.
pub fn write_picture(
    path: &Path,
    mesh: &TriMesh,
    lines: Option<&FeatureLines>,
    field: Option<&[f64]>,
    opts: &RenderOptions,
) -> Result<()> {
    match PictureFormat::from_path(path)? {
        PictureFormat::Png => write_png(path, mesh, lines, field, opts),
        PictureFormat::Svg => write_svg(path, mesh, lines, field, opts),
        PictureFormat::Html => write_html(path, mesh, lines, field, opts),
    }
}

/// The colour scale of `field` under `opts`, or `None` when no field is to be shown.
fn field_scale(
    mesh: &TriMesh,
    field: Option<&[f64]>,
    opts: &RenderOptions,
) -> Result<Option<ColorScale>> {
    let Some(values) = field.filter(|_| opts.show_field) else {
        return Ok(None);
    };
    check_field(mesh, values)?;
    ColorScale::for_field(values, opts.color_map, opts.field_range).map(Some)
}

/// Checks that `field` has one value per vertex.
fn check_field(mesh: &TriMesh, field: &[f64]) -> Result<()> {
    if field.len() != mesh.num_vertices() {
        return Err(Error::InvalidInput(format!(
            "the field has {} values for a mesh of {} vertices",
            field.len(),
            mesh.num_vertices()
        )));
    }
    Ok(())
}

/// The points the camera is fitted to: the referenced vertices, or the line points when
/// the mesh has no faces.
fn fit_points<'a>(
    mesh: &'a TriMesh,
    lines: Option<&'a FeatureLines>,
) -> Box<dyn Iterator<Item = Vec3> + 'a> {
    if mesh.num_faces() > 0 {
        let topo = mesh.topology();
        Box::new(
            (0..mesh.num_vertices() as u32)
                .filter(|&v| !topo.vertex_faces(v).is_empty())
                .map(|v| mesh.position(v)),
        )
    } else {
        Box::new(
            lines
                .into_iter()
                .flat_map(|l| l.lines.iter().flat_map(|line| line.points.iter().copied())),
        )
    }
}
