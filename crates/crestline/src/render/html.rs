//! A self-contained interactive viewer: one HTML file with the mesh, the lines and a
//! hand-written WebGL renderer, no library and no network access.
//!
//! ## What is embedded
//! Binary arrays, little-endian, base64-encoded in `<script type="application/octet-stream">`
//! elements: positions (`Float32Array`, xyz, centred on the bounding box and scaled into the
//! unit sphere), triangles (`Uint32Array`), per-vertex colours of the field (`Uint8Array`,
//! RGB, already mapped with the same [`super::ColorScale`] as the PNG renderer, empty
//! without a field), and ridge and valley segments (`Float32Array`, two xyz points per
//! segment). Options (colours, view, lighting, legend) go in a small JSON object.
//!
//! ## What the page does
//! The shading normals are computed in the page, as for the PNG: not smoothed across folds of
//! more than 30° (a corner there gets a vertex of its own). The mesh is lit like the PNG (two-sided, light
//! from the camera, a little from the upper left); lines are screen-aligned quads of the
//! chosen width with a halo, depth-tested against the mesh, which is pushed back by its
//! slope (polygon offset) plus the depth bias of the options. Drag orbits (the same
//! turntable camera as `camera.rs`), the wheel zooms, double-click resets; the checkboxes or
//! the keys `r`, `v`, `c` toggle ridges, valleys and the colour map.
//!
//! The initial state can be set in the URL: `view.html#ridges=0&valleys=1&field=1&az=30&el=20&zoom=1.5`
//! (also as a query string); the page keeps the hash up to date, so a view can be shared.
//!
//! ## Limits
//! Needs WebGL (version 2, or 1 with 32-bit indices). Base64 adds a third to the size:
//! about 40 bytes per face, 40 MB for a million faces.

use std::fmt::Write;

use super::{ColorMap, ColorScale, RenderOptions, Rgb, UpAxis, base64, check_field};
use crate::error::{Error, Result};
use crate::lines::{FeatureLines, LineKind};
use crate::mesh::{TriMesh, Vec3};

const TEMPLATE: &str = include_str!("viewer.html");

/// Builds the viewer page for `mesh`, its `lines` and a per-vertex `field`.
///
/// The options give the initial view (`azimuth`, `elevation`, `up`), colours, lighting,
/// line width and halo, depth bias, which layers start visible, the colour map and legend
/// title, and the margin around the mesh in the initial view. The image size does not
/// apply: the page fills the browser window.
///
/// # Errors
/// [`Error::InvalidInput`] for invalid options, a field whose length is not the number of
/// vertices or without a finite value, or a mesh too large to index in 32 bits.
pub fn render_html(
    mesh: &TriMesh,
    lines: Option<&FeatureLines>,
    field: Option<&[f64]>,
    opts: &RenderOptions,
) -> Result<String> {
    opts.validate()?;
    let bbox = mesh.bounding_box();
    let center = bbox.center();
    let radius = bbox.diagonal() / 2.0;
    let scale = if radius > 0.0 { 1.0 / radius } else { 1.0 };
    let normalized = |p: &Vec3| ((p - center) * scale).map(|c| c as f32);

    let mut positions = Vec::with_capacity(mesh.num_vertices() * 12);
    for p in mesh.positions() {
        for c in normalized(p).iter() {
            positions.extend_from_slice(&c.to_le_bytes());
        }
    }
    let mut indices = Vec::with_capacity(mesh.num_faces() * 12);
    for t in mesh.faces() {
        for v in t {
            indices.extend_from_slice(&v.to_le_bytes());
        }
    }
    let color_scale = match field {
        Some(values) => {
            check_field(mesh, values)?;
            Some(ColorScale::for_field(
                values,
                opts.color_map,
                opts.field_range,
            )?)
        }
        None => None,
    };
    let mut colors = Vec::new();
    if let (Some(scale), Some(values)) = (&color_scale, field) {
        colors.reserve(values.len() * 3);
        for &v in values {
            colors.extend_from_slice(&scale.color(v).unwrap_or(opts.surface));
        }
    }
    let segments = |kind: LineKind| {
        let mut out = Vec::new();
        for line in lines
            .iter()
            .flat_map(|l| &l.lines)
            .filter(|l| l.kind == kind)
        {
            let n = line.points.len();
            let closing = usize::from(line.closed && n > 2);
            for i in 0..(n.saturating_sub(1) + closing) {
                for p in [&line.points[i], &line.points[(i + 1) % n]] {
                    for c in normalized(p).iter() {
                        out.extend_from_slice(&c.to_le_bytes());
                    }
                }
            }
        }
        out
    };
    let ridges = segments(LineKind::Ridge);
    let valleys = segments(LineKind::Valley);
    let config = config_json(opts, opts.up.resolve(mesh), color_scale.as_ref());
    let title = if opts.legend_title.is_empty() {
        "crestline viewer".to_string()
    } else {
        format!("crestline viewer: {}", opts.legend_title)
    };

    let data_len = positions.len() + indices.len() + colors.len() + ridges.len() + valleys.len();
    let mut html = String::with_capacity(TEMPLATE.len() + config.len() + data_len * 4 / 3 + 64);
    let mut rest = TEMPLATE;
    while let Some(start) = rest.find("@@") {
        html.push_str(&rest[..start]);
        let after = &rest[start + 2..];
        let end = after
            .find("@@")
            .ok_or_else(|| Error::InvalidInput("viewer template has an unclosed marker".into()))?;
        match &after[..end] {
            "TITLE" => html.push_str(&escape_html(&title)),
            "BACKGROUND" => html.push_str(&css_rgb(opts.background)),
            "CONFIG" => html.push_str(&config),
            "POSITIONS" => base64::encode_into(&positions, &mut html),
            "INDICES" => base64::encode_into(&indices, &mut html),
            "COLORS" => base64::encode_into(&colors, &mut html),
            "RIDGES" => base64::encode_into(&ridges, &mut html),
            "VALLEYS" => base64::encode_into(&valleys, &mut html),
            other => {
                return Err(Error::InvalidInput(format!(
                    "viewer template has an unknown marker {other}"
                )));
            }
        }
        rest = &after[end + 2..];
    }
    html.push_str(rest);
    Ok(html)
}

/// The options the page reads, as a JSON object literal.
fn config_json(opts: &RenderOptions, up: UpAxis, scale: Option<&ColorScale>) -> String {
    let rgb = |c: Rgb| format!("[{},{},{}]", c[0], c[1], c[2]);
    let num = |v: f64| {
        if v.is_finite() {
            format!("{v}")
        } else {
            "0".into()
        }
    };
    let mut s = String::from("{");
    let _ = write!(
        s,
        "\"azimuth\":{},\"elevation\":{},\"up\":\"{}\",",
        num(opts.azimuth),
        num(opts.elevation),
        up.name()
    );
    let _ = write!(
        s,
        "\"background\":{},\"surface\":{},\"ridgeColor\":{},\"valleyColor\":{},\"halo\":{},",
        rgb(opts.background),
        rgb(opts.surface),
        rgb(opts.ridge_color),
        rgb(opts.valley_color),
        opts.line_halo.map_or("null".into(), rgb)
    );
    let _ = write!(
        s,
        "\"margin\":{},\"lineWidth\":{},\"depthBias\":{},\"ambient\":{},\"specular\":{},\"shininess\":{},",
        num(opts.margin),
        num(opts.line_width),
        num(opts.depth_bias),
        num(opts.ambient),
        num(opts.specular),
        num(opts.shininess)
    );
    let _ = write!(
        s,
        "\"showRidges\":{},\"showValleys\":{},\"showField\":{},",
        opts.show_ridges, opts.show_valleys, opts.show_field
    );
    let (gradient, labels) = match scale {
        Some(scale) => {
            let stops: Vec<String> = (0..=10)
                .map(|i| {
                    let t = f64::from(i) / 10.0;
                    format!("{} {}%", css_rgb(scale.map.sample(t)), i * 10)
                })
                .collect();
            let mut labels = vec![super::colormap::format_value(scale.max)];
            if scale.map == ColorMap::Diverging {
                labels.push("0".into());
            }
            labels.push(super::colormap::format_value(scale.min));
            (
                format!("linear-gradient(to top, {})", stops.join(", ")),
                labels,
            )
        }
        None => (String::new(), Vec::new()),
    };
    let labels: Vec<String> = labels.iter().map(|l| json_string(l)).collect();
    let _ = write!(
        s,
        "\"legend\":{{\"gradient\":{},\"labels\":[{}],\"title\":{}}}}}",
        json_string(&gradient),
        labels.join(","),
        json_string(&opts.legend_title)
    );
    s
}

fn css_rgb(c: Rgb) -> String {
    format!("rgb({},{},{})", c[0], c[1], c[2])
}

/// A JSON string literal that is also safe inside an HTML `<script>` element.
fn json_string(text: &str) -> String {
    let mut s = String::with_capacity(text.len() + 2);
    s.push('"');
    for c in text.chars() {
        match c {
            '"' => s.push_str("\\\""),
            '\\' => s.push_str("\\\\"),
            c if c.is_control() || matches!(c, '<' | '>' | '&') => {
                let _ = write!(s, "\\u{:04x}", u32::from(c));
            }
            c => s.push(c),
        }
    }
    s.push('"');
    s
}

fn escape_html(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lines::FeatureLine;

    fn quad() -> TriMesh {
        TriMesh::from_arrays(
            vec![
                [0.0, 0.0, 0.0],
                [2.0, 0.0, 0.0],
                [2.0, 2.0, 0.0],
                [0.0, 2.0, 0.0],
            ],
            vec![[0, 1, 2], [0, 2, 3]],
        )
        .unwrap()
    }

    fn embedded<'a>(html: &'a str, id: &str) -> &'a str {
        let open = format!("id=\"{id}\">");
        let start = html.find(&open).unwrap() + open.len();
        let len = html[start..].find('<').unwrap();
        &html[start..start + len]
    }

    #[test]
    fn embeds_mesh_lines_and_colours_compactly() {
        let m = quad();
        let points = vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(2.0, 2.0, 0.0),
            Vec3::new(0.0, 2.0, 0.0),
        ];
        let line = FeatureLine::new(LineKind::Ridge, points, true);
        let lines = FeatureLines { lines: vec![line] };
        let field = [0.0, 1.0, 2.0, 3.0];
        let html = render_html(&m, Some(&lines), Some(&field), &RenderOptions::default()).unwrap();
        assert!(!html.contains("@@"));
        // 4 vertices x 12 bytes, 2 faces x 12 bytes, 4 colours x 3 bytes, 3 segments x 24.
        assert_eq!(embedded(&html, "data-positions").len(), 48 / 3 * 4);
        assert_eq!(embedded(&html, "data-indices").len(), 24 / 3 * 4);
        assert_eq!(embedded(&html, "data-colors").len(), 12 / 3 * 4);
        assert_eq!(embedded(&html, "data-ridges").len(), 72 / 3 * 4);
        assert_eq!(embedded(&html, "data-valleys"), "");
        // The first vertex (0,0,0) is the corner (-1,-1,0)/sqrt(2) of the unit sphere.
        let corner = (-(0.5f64.sqrt()) as f32).to_le_bytes();
        let expected = base64::encode(&[corner, corner].concat());
        assert_eq!(embedded(&html, "data-positions")[..8], expected[..8]);
        assert!(
            !html.contains("http://") && !html.contains("https://"),
            "no network"
        );
    }

    #[test]
    fn text_is_escaped_for_script_and_html() {
        assert_eq!(
            json_string("a\"</script>"),
            "\"a\\\"\\u003c/script\\u003e\""
        );
        let opts = RenderOptions::default().with_legend_title("</script><b>");
        let html = render_html(&quad(), None, None, &opts).unwrap();
        assert!(!html.contains("</script><b>"));
        assert!(html.contains("&lt;/script&gt;"));
    }

    #[test]
    fn a_field_of_the_wrong_length_is_refused() {
        let e = render_html(&quad(), None, Some(&[1.0]), &RenderOptions::default()).unwrap_err();
        assert!(e.to_string().contains("1 values for a mesh of 4"), "{e}");
    }
}
