//! SVG pictures: the shaded mesh as an embedded PNG under the visible lines as vector paths.
//!
//! The image (mesh, colour map, legend) is the same raster [`super::render_image`] makes,
//! embedded as a `data:image/png;base64` URI, so the file is self-contained. Each visible
//! stroke becomes one `<path>`; ridges and valleys are grouped in `<g id="ridges">` and
//! `<g id="valleys">`, each with a group of halo strokes (when a halo is set) under a group of
//! coloured strokes, so they can be restyled or hidden in an editor.
//! Coordinates are in pixels with two decimals.

use std::fmt::Write;

use super::hidden_lines::VisibleStroke;
use super::{RenderOptions, Rgb, base64, render_frame};
use crate::error::Result;
use crate::lines::{FeatureLines, LineKind};
use crate::mesh::TriMesh;

/// Renders an SVG document: the mesh as an embedded PNG, visible line pieces as paths.
///
/// # Errors
/// As [`super::render_frame`].
pub fn render_svg(
    mesh: &TriMesh,
    lines: Option<&FeatureLines>,
    field: Option<&[f64]>,
    opts: &RenderOptions,
) -> Result<String> {
    let frame = render_frame(mesh, lines, field, opts)?;
    let png = frame.image.to_png()?;
    let (w, h) = (opts.width, opts.height);
    let mut svg = String::with_capacity(png.len() * 4 / 3 + 1024);
    svg.push_str(&format!(
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n\
         <svg xmlns=\"http://www.w3.org/2000/svg\" xmlns:xlink=\"http://www.w3.org/1999/xlink\" \
         width=\"{w}\" height=\"{h}\" viewBox=\"0 0 {w} {h}\">\n\
         <image id=\"mesh\" x=\"0\" y=\"0\" width=\"{w}\" height=\"{h}\" xlink:href=\"data:image/png;base64,"
    ));
    base64::encode_into(&png, &mut svg);
    svg.push_str("\"/>\n");
    for (kind, id, color) in [
        (LineKind::Valley, "valleys", opts.valley_color),
        (LineKind::Ridge, "ridges", opts.ridge_color),
    ] {
        write_group(&mut svg, &frame.strokes, kind, id, color, opts);
    }
    svg.push_str("</svg>\n");
    Ok(svg)
}

/// Writes the strokes of one kind as a group of paths (nothing when there are none).
fn write_group(
    svg: &mut String,
    strokes: &[VisibleStroke],
    kind: LineKind,
    id: &str,
    color: Rgb,
    opts: &RenderOptions,
) {
    let mine: Vec<&VisibleStroke> = strokes.iter().filter(|s| s.kind == kind).collect();
    if mine.is_empty() {
        return;
    }
    let hex = |c: Rgb| format!("#{:02x}{:02x}{:02x}", c[0], c[1], c[2]);
    let width = opts.line_width;
    // Writing into a String cannot fail.
    let _ = writeln!(
        svg,
        "<g id=\"{id}\" fill=\"none\" stroke-linecap=\"round\" stroke-linejoin=\"round\">"
    );
    let mut layers = Vec::new();
    if let Some(halo) = opts.line_halo {
        layers.push(("halo", halo, width + 2.0));
    }
    layers.push(("line", color, width));
    for (class, rgb, width) in layers {
        let _ = writeln!(
            svg,
            "<g class=\"{class}\" stroke=\"{}\" stroke-width=\"{width}\">",
            hex(rgb)
        );
        for s in &mine {
            write_path(svg, s);
        }
        svg.push_str("</g>\n");
    }
    svg.push_str("</g>\n");
}

/// One `<path>` for one stroke.
fn write_path(svg: &mut String, stroke: &VisibleStroke) {
    svg.push_str("<path d=\"");
    for (i, p) in stroke.points.iter().enumerate() {
        let _ = write!(
            svg,
            "{}{:.2} {:.2}",
            if i == 0 { 'M' } else { 'L' },
            p[0],
            p[1]
        );
    }
    svg.push_str("\"/>\n");
}
