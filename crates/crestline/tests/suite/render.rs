//! Pixel tests of the renderer on tiny generated scenes: a unit quad facing the camera and
//! hand-made lines in front of it, on it, behind it and through it.
//!
//! The quad spans [-1, 1]² in the plane z = 0 and is seen from +Z (azimuth 0, elevation 0,
//! +Y up) in a 200×200 image with a 10% margin: 80 pixels per unit, model (x, y) at pixel
//! (100 + 80x, 100 - 80y). Lighting is switched to ambient only so that surface pixels
//! have exactly the surface colour.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)] // test helpers may fail loudly

use crestline::lines::{FeatureLine, FeatureLines, LineKind};
use crestline::render::{
    ColorMap, ColorMapChoice, ColorScale, FieldRange, Image, RenderOptions, UpAxis, render_frame,
    render_html, render_image, render_png, render_svg, write_picture,
};
use crestline::{TriMesh, Vec3, shapes};

use crate::common;

const SURFACE: [u8; 3] = [200, 200, 200];

fn quad() -> TriMesh {
    TriMesh::from_arrays(
        vec![
            [-1.0, -1.0, 0.0],
            [1.0, -1.0, 0.0],
            [1.0, 1.0, 0.0],
            [-1.0, 1.0, 0.0],
        ],
        vec![[0, 1, 2], [0, 2, 3]],
    )
    .unwrap()
}

fn line(kind: LineKind, points: &[[f64; 3]]) -> FeatureLine {
    FeatureLine::new(kind, points.iter().map(|&p| Vec3::from(p)).collect(), false)
}

fn flat_options() -> RenderOptions {
    let mut o = RenderOptions::default()
        .with_size(200, 200)
        .with_view(0.0, 0.0);
    o.margin = 0.1;
    o.ambient = 1.0;
    o.specular = 0.0;
    o.line_halo = None;
    o.line_width = 5.0;
    o.surface = SURFACE;
    o
}

/// Pixel of model point (x, y) in the front view.
fn px(x: f64, y: f64) -> (u32, u32) {
    ((100.0 + 80.0 * x) as u32, (100.0 - 80.0 * y) as u32)
}

fn rgb(img: &Image, (x, y): (u32, u32)) -> [u8; 3] {
    let [r, g, b, a] = img.pixel(x, y).unwrap();
    assert_eq!(a, 255);
    [r, g, b]
}

fn close(a: [u8; 3], b: [u8; 3], tolerance: u8) -> bool {
    a.iter().zip(b).all(|(&x, y)| x.abs_diff(y) <= tolerance)
}

/// A ridge 0.5 in front of the quad at y = 0.5, a valley 0.5 behind it at y = -0.5.
fn front_and_back() -> FeatureLines {
    FeatureLines {
        lines: vec![
            line(LineKind::Ridge, &[[-0.8, 0.5, 0.5], [0.8, 0.5, 0.5]]),
            line(LineKind::Valley, &[[-0.8, -0.5, -0.5], [0.8, -0.5, -0.5]]),
        ],
    }
}

#[test]
fn line_in_front_is_drawn_and_line_behind_is_hidden() {
    let opts = flat_options();
    let lines = front_and_back();
    let img = render_image(&quad(), Some(&lines), None, &opts).unwrap();
    assert_eq!(rgb(&img, px(0.0, 0.5)), opts.ridge_color);
    assert_eq!(rgb(&img, px(0.0, -0.5)), SURFACE);
    assert_eq!(rgb(&img, px(0.0, 0.0)), SURFACE);
    // The background stays where the quad is not.
    assert_eq!(rgb(&img, (2, 2)), opts.background);

    // From behind the roles swap (x is mirrored, x = 0 stays in the middle).
    let back = flat_options().with_view(180.0, 0.0);
    let img = render_image(&quad(), Some(&lines), None, &back).unwrap();
    assert_eq!(rgb(&img, px(0.0, -0.5)), opts.valley_color);
    assert_eq!(rgb(&img, px(0.0, 0.5)), SURFACE);
}

#[test]
fn lines_on_the_surface_are_drawn_and_a_crossing_line_stops_where_it_goes_under() {
    let lines = FeatureLines {
        lines: vec![
            // On the surface, and a hair behind it (within the depth bias).
            line(LineKind::Ridge, &[[-0.8, 0.5, 0.0], [0.8, 0.5, 0.0]]),
            line(
                LineKind::Ridge,
                &[[-0.8, 0.25, -0.002], [0.8, 0.25, -0.002]],
            ),
            // From 0.3 in front at x = -0.8 to 0.3 behind at x = 0.8.
            line(LineKind::Valley, &[[-0.8, -0.5, 0.3], [0.8, -0.5, -0.3]]),
        ],
    };
    let opts = flat_options();
    let img = render_image(&quad(), Some(&lines), None, &opts).unwrap();
    assert_eq!(rgb(&img, px(0.0, 0.5)), opts.ridge_color);
    assert_eq!(rgb(&img, px(0.0, 0.25)), opts.ridge_color);
    assert_eq!(rgb(&img, px(-0.4, -0.5)), opts.valley_color);
    assert_eq!(rgb(&img, px(0.4, -0.5)), SURFACE);

    // The visible stroke of the crossing line ends near x = 0 (pixel 100), allowing for the
    // depth bias and the 3x3 neighbourhood of the test.
    let frame = render_frame(&quad(), Some(&lines), None, &opts).unwrap();
    let valleys: Vec<_> = frame
        .strokes
        .iter()
        .filter(|s| s.kind == LineKind::Valley)
        .collect();
    assert_eq!(valleys.len(), 1);
    let end = valleys[0].points.last().unwrap();
    assert!(
        (end[0] - 100.0).abs() < 4.0,
        "visible part ends at x = {}",
        end[0]
    );
    let start = valleys[0].points[0];
    assert!((start[0] - px(-0.8, 0.0).0 as f64).abs() < 1e-9);
}

#[test]
fn a_closed_mesh_hides_lines_on_its_far_side() {
    let sphere = shapes::icosphere(1.0, 4);
    // Two circles of latitude-like loops around the z axis, at z = +0.6 (near the camera)
    // and z = -0.6 (far side), both on the sphere.
    let ring = |kind, z: f64| common::circle(kind, (1.0f64 - z * z).sqrt(), z, 64);
    let lines = FeatureLines {
        lines: vec![ring(LineKind::Ridge, 0.6), ring(LineKind::Valley, -0.6)],
    };
    let mut opts = flat_options();
    opts.line_width = 3.0;
    let frame = render_frame(&sphere, Some(&lines), None, &opts).unwrap();
    assert!(frame.strokes.iter().any(|s| s.kind == LineKind::Ridge));
    assert!(frame.strokes.iter().all(|s| s.kind != LineKind::Valley));
    let img = render_image(&sphere, Some(&lines), None, &opts).unwrap();
    // The near ring passes through model point (0.8, 0) at radius 0.8.
    assert_eq!(rgb(&img, px(0.0, 0.8)), opts.ridge_color);
}

#[test]
fn ridges_and_valleys_have_their_documented_colours_and_can_be_hidden() {
    let lines = FeatureLines {
        lines: vec![
            line(LineKind::Ridge, &[[-0.8, 0.5, 0.0], [0.8, 0.5, 0.0]]),
            line(LineKind::Valley, &[[-0.8, -0.5, 0.0], [0.8, -0.5, 0.0]]),
        ],
    };
    let opts = flat_options();
    assert_eq!(opts.ridge_color, [215, 25, 28]);
    assert_eq!(opts.valley_color, [44, 123, 182]);
    let img = render_image(&quad(), Some(&lines), None, &opts).unwrap();
    assert_eq!(rgb(&img, px(0.0, 0.5)), [215, 25, 28]);
    assert_eq!(rgb(&img, px(0.0, -0.5)), [44, 123, 182]);

    let mut no_ridges = flat_options();
    no_ridges.show_ridges = false;
    let img = render_image(&quad(), Some(&lines), None, &no_ridges).unwrap();
    assert_eq!(rgb(&img, px(0.0, 0.5)), SURFACE);
    assert_eq!(rgb(&img, px(0.0, -0.5)), [44, 123, 182]);

    // With the default halo, the line's edge is dark, its middle keeps its colour.
    let mut halo = flat_options();
    halo.line_halo = Some([0, 0, 0]);
    // Width 6 around row boundary 60: the line covers rows 57..=62, the halo rows 56 and 63.
    halo.line_width = 6.0;
    let img = render_image(&quad(), Some(&lines), None, &halo).unwrap();
    let (x, y) = px(0.0, 0.5);
    assert_eq!(rgb(&img, (x, y)), [215, 25, 28]);
    let edge = rgb(&img, (x, y + 3));
    assert!(edge.iter().all(|&c| c < 10), "halo pixel {edge:?}");
}

#[test]
fn colour_map_colours_pixels_by_the_interpolated_field() {
    let mesh = quad();
    let mut opts = flat_options();
    opts.legend = false;
    opts.field_range = FieldRange::Percentile(0.0);

    // Signed field x: diverging, white in the middle.
    let field: Vec<f64> = mesh.positions().iter().map(|p| p.x).collect();
    let scale = ColorScale::for_field(&field, ColorMapChoice::Auto, opts.field_range).unwrap();
    assert_eq!(scale.map, ColorMap::Diverging);
    let img = render_image(&mesh, None, Some(&field), &opts).unwrap();
    for x in [-0.9, -0.45, 0.0, 0.45, 0.9] {
        let (i, j) = px(x, 0.1);
        let centre = (f64::from(i) + 0.5 - 100.0) / 80.0;
        let expected = scale.color(centre).unwrap();
        assert!(close(rgb(&img, (i, j)), expected, 2), "x = {x}");
    }
    assert!(close(rgb(&img, px(0.0, 0.1)), [0xf7; 3], 4));

    // One-signed field: viridis, dark on the left, yellow on the right.
    let field: Vec<f64> = mesh.positions().iter().map(|p| p.x + 2.0).collect();
    let img = render_image(&mesh, None, Some(&field), &opts).unwrap();
    let left = rgb(&img, px(-0.99, 0.0));
    let right = rgb(&img, px(0.99, 0.0));
    assert!(close(left, ColorMap::Viridis.sample(0.0), 6), "{left:?}");
    assert!(close(right, ColorMap::Viridis.sample(1.0), 6), "{right:?}");

    // Without the field, the same pixels are grey.
    let img = render_image(&mesh, None, None, &opts).unwrap();
    assert_eq!(rgb(&img, px(-0.99, 0.0)), SURFACE);
}

#[test]
fn legend_shows_both_ends_of_the_map_beside_the_mesh() {
    let mesh = quad();
    let field: Vec<f64> = mesh.positions().iter().map(|p| p.x + 2.0).collect();
    let with_legend = flat_options();
    let mut without = flat_options();
    without.legend = false;
    let count_in_strip = |img: &Image, color: [u8; 3]| {
        (150..200)
            .flat_map(|x| (0..200).map(move |y| (x, y)))
            .filter(|&p| rgb(img, p) == color)
            .count()
    };
    let top = ColorMap::Viridis.sample(1.0);
    let bottom = ColorMap::Viridis.sample(0.0);
    let img = render_image(&mesh, None, Some(&field), &with_legend).unwrap();
    assert!(count_in_strip(&img, top) > 0 && count_in_strip(&img, bottom) > 0);
    // Dark label pixels (the font's ink) are in the strip.
    assert!(count_in_strip(&img, [20, 20, 20]) > 10);
    // The mesh moved left to make room: the right margin is background.
    assert_eq!(rgb(&img, (175, 100)), with_legend.background);
    let img = render_image(&mesh, None, Some(&field), &without).unwrap();
    assert_eq!(count_in_strip(&img, [20, 20, 20]), 0);
}

#[test]
fn svg_has_paths_only_for_visible_pieces() {
    let opts = flat_options();
    let svg = render_svg(&quad(), Some(&front_and_back()), None, &opts).unwrap();
    assert!(svg.starts_with("<?xml"));
    assert!(
        svg.contains("data:image/png;base64,iVBORw0KGgo"),
        "embedded PNG"
    );
    assert!(svg.contains("<g id=\"ridges\""));
    assert!(
        !svg.contains("<g id=\"valleys\""),
        "the hidden valley has no path"
    );
    assert_eq!(svg.matches("<path").count(), 1);
    // The path runs along y = 0.5 (pixel row 60) from x = -0.8 to 0.8 (pixels 36..164).
    assert!(
        svg.contains("<path d=\"M36.00 60.00L164.00 60.00\"/>"),
        "{}",
        svg_tail(&svg)
    );

    // A halo doubles each path under the coloured one.
    let mut halo = flat_options();
    halo.line_halo = Some([0, 0, 0]);
    let svg = render_svg(&quad(), Some(&front_and_back()), None, &halo).unwrap();
    assert_eq!(svg.matches("<path").count(), 2);
    assert!(svg.contains("class=\"halo\" stroke=\"#000000\""));
}

fn svg_tail(svg: &str) -> &str {
    &svg[svg.find("<g").unwrap_or(0)..]
}

#[test]
fn png_encodes_the_rendered_image() {
    let opts = flat_options().with_size(120, 80);
    let png = render_png(&quad(), Some(&front_and_back()), None, &opts).unwrap();
    let decoded = tiny_skia::Pixmap::decode_png(&png).unwrap();
    assert_eq!((decoded.width(), decoded.height()), (120, 80));
    let img = render_image(&quad(), Some(&front_and_back()), None, &opts).unwrap();
    assert_eq!(img.to_png().unwrap(), png);
}

#[test]
fn odd_sizes_views_and_empty_meshes_render() {
    let lines = front_and_back();
    for (w, h) in [(1, 1), (3, 200), (301, 97)] {
        let img =
            render_image(&quad(), Some(&lines), None, &flat_options().with_size(w, h)).unwrap();
        assert_eq!((img.width(), img.height()), (w, h));
    }
    for (az, el) in [(0.0, 90.0), (0.0, -90.0), (123.0, 45.0), (-720.0, 0.0)] {
        let opts = flat_options().with_view(az, el).with_up(UpAxis::Z);
        render_image(&shapes::icosphere(1.0, 1), Some(&lines), None, &opts).unwrap();
    }
    // No faces: the lines alone are framed and drawn.
    let empty = TriMesh::from_arrays(vec![], vec![]).unwrap();
    let img = render_image(&empty, Some(&lines), None, &flat_options()).unwrap();
    let opts = flat_options();
    let coloured = (0..200)
        .flat_map(|x| (0..200).map(move |y| (x, y)))
        .filter(|&p| rgb(&img, p) == opts.ridge_color)
        .count();
    assert!(coloured > 100);
}

#[test]
fn bad_input_is_refused_with_a_message() {
    let opts = flat_options();
    let e = render_image(&quad(), None, Some(&[1.0, 2.0]), &opts).unwrap_err();
    assert!(
        e.to_string().contains("2 values for a mesh of 4 vertices"),
        "{e}"
    );
    let e = render_image(&quad(), None, Some(&[f64::NAN; 4]), &opts).unwrap_err();
    assert!(e.to_string().contains("no finite value"), "{e}");
    let e = render_image(&quad(), None, None, &flat_options().with_size(0, 10)).unwrap_err();
    assert!(e.to_string().contains("image size"), "{e}");
    let e = render_image(&quad(), None, None, &flat_options().with_view(0.0, 95.0)).unwrap_err();
    assert!(e.to_string().contains("elevation"), "{e}");
    let mut nan = flat_options();
    nan.line_width = f64::NAN;
    assert!(render_image(&quad(), None, None, &nan).is_err());
    let e = write_picture("out.jpg".as_ref(), &quad(), None, None, &opts).unwrap_err();
    assert!(e.to_string().contains(".png, .svg or .html"), "{e}");
    // A field that is hidden is not checked.
    let mut hidden = flat_options();
    hidden.show_field = false;
    assert!(render_image(&quad(), None, Some(&[1.0]), &hidden).is_ok());
}

#[test]
fn the_wireframe_draws_the_visible_edges_only() {
    // The front quad at z = 0.5; a smaller quad at z = -0.5 behind it, whose edges at
    // x = ±0.5 are hidden.
    let mut positions: Vec<[f64; 3]> = quad().positions().iter().map(|p| [p.x, p.y, 0.5]).collect();
    positions.extend(
        quad()
            .positions()
            .iter()
            .map(|p| [p.x / 2.0, p.y / 2.0, -0.5]),
    );
    let faces = vec![[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7]];
    let mesh = TriMesh::from_arrays(positions, faces).unwrap();
    // Seen from the front (the guess would take the back quad for a base along Z).
    let front = flat_options().with_up(UpAxis::Y);
    let plain = render_image(&mesh, None, None, &front).unwrap();
    let opts = front.with_wireframe(true);
    assert_eq!(opts.wireframe_color, [40, 40, 40]);
    let wired = render_image(&mesh, None, None, &opts).unwrap();
    // On the front quad's diagonal (pixel centre (124.5, 75.5) lies on x + y = 200): 75%
    // wire colour over the surface.
    assert!(
        close(rgb(&wired, (124, 75)), [80, 80, 80], 2),
        "{:?}",
        rgb(&wired, (124, 75))
    );
    assert_eq!(rgb(&plain, (124, 75)), SURFACE);
    // Where the hidden quad's edge x = 0.5 projects, and inside the faces, nothing changes.
    for p in [px(0.5, -0.2), px(0.5, 0.2), px(-0.5, 0.3), px(0.5, -0.8)] {
        assert_eq!(rgb(&wired, p), SURFACE, "{p:?}");
    }
}

#[test]
fn the_frame_tells_which_up_axis_was_used() {
    let up = |mesh: &TriMesh, up| {
        let opts = flat_options().with_up(up);
        render_frame(mesh, None, None, &opts).unwrap().up
    };
    // A cube stands on a base along Y and along Z alike: no clear answer, so +Y.
    let (cube, _) = shapes::pillow_box(1.0, 0.0, 4);
    assert_eq!(up(&cube, UpAxis::Auto), UpAxis::Y);
    assert_eq!(up(&cube, UpAxis::Z), UpAxis::Z);
    // Flattened along Z, it lies on its large face.
    let positions = cube
        .positions()
        .iter()
        .map(|p| Vec3::new(p.x, p.y, 0.1 * p.z));
    let slab = cube.with_positions(positions.collect()).unwrap();
    assert_eq!(up(&slab, UpAxis::Auto), UpAxis::Z);
    // The quad of the other tests is a flat sheet seen face-on.
    assert_eq!(up(&quad(), UpAxis::Auto), UpAxis::Y);
}

// Meshes far from the origin (georeferenced scans, survey data): an orthographic picture
// does not depend on where the model lies, so fandisk moved by `FAR` must render as it does
// where it is. Its sharp edges serve as lines, on the near side and the far side alike.

/// The translation of the far-from-origin tests, as large as survey coordinates get.
const FAR: [f64; 3] = [1e7, -2e7, 1e7];

/// Fandisk and its sharp edges (folds of more than 30°) as two-point ridges.
fn fandisk_and_its_creases() -> (TriMesh, FeatureLines) {
    let mesh = common::load_shared("fandisk.obj");
    let topo = mesh.topology();
    let lines = common::sharp_edges(&mesh, 30.0)
        .into_iter()
        .map(|e| {
            let points = topo.edge(e).map(|v| mesh.position(v)).to_vec();
            FeatureLine::new(LineKind::Ridge, points, false)
        })
        .collect();
    (mesh, FeatureLines { lines })
}

/// `mesh` and `lines` moved by `by`.
fn translated(mesh: &TriMesh, lines: &FeatureLines, by: Vec3) -> (TriMesh, FeatureLines) {
    let positions = mesh.positions().iter().map(|p| p + by).collect();
    let lines = lines
        .lines
        .iter()
        .map(|l| FeatureLine::new(l.kind, l.points.iter().map(|p| p + by).collect(), l.closed))
        .collect();
    (
        mesh.with_positions(positions).unwrap(),
        FeatureLines { lines },
    )
}

/// How many pixels of two pictures of one size differ at all.
fn differing_pixels(a: &Image, b: &Image) -> usize {
    assert_eq!((a.width(), a.height()), (b.width(), b.height()));
    (0..a.height())
        .flat_map(|y| (0..a.width()).map(move |x| (x, y)))
        .filter(|&(x, y)| a.pixel(x, y) != b.pixel(x, y))
        .count()
}

#[test]
fn a_mesh_far_from_the_origin_renders_as_at_the_origin() {
    let (mesh, lines) = fandisk_and_its_creases();
    assert!(lines.lines.len() > 100, "{}", lines.lines.len());
    let (far_mesh, far_lines) = translated(&mesh, &lines, Vec3::from(FAR));
    // The translated coordinates are rounded to f64 at 1e7 (steps of 2e-9), which moves a
    // vertex by about 1e-5 pixel here: only a pixel whose centre lies that close to an edge,
    // or whose colour that close to a rounding step, may change. Measured: none on fandisk,
    // at most 11 of 512² (0.004%) on the other shared meshes. A thousandth leaves room for
    // that while the defect (depths kept in f32 with the offset: about one unit of depth
    // resolution) changed 10% of the pixels, lines from the far side showing through.
    for (azimuth, elevation) in [(30.0, 20.0), (200.0, -40.0)] {
        for wireframe in [false, true] {
            let opts = RenderOptions::default()
                .with_size(512, 512)
                .with_view(azimuth, elevation)
                .with_wireframe(wireframe);
            let near = render_image(&mesh, Some(&lines), None, &opts).unwrap();
            let far = render_image(&far_mesh, Some(&far_lines), None, &opts).unwrap();
            let differing = differing_pixels(&near, &far);
            assert!(
                differing <= 512 * 512 / 1000,
                "view {azimuth},{elevation}, wireframe {wireframe}: {differing} pixels differ"
            );
        }
    }
}

/// Standard base64 decoded (the viewer's typed arrays).
fn base64_decode(text: &str) -> Vec<u8> {
    const ALPHABET: &[u8] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let (mut bytes, mut acc, mut bits) = (Vec::new(), 0u32, 0);
    for c in text.bytes().filter(|&c| c != b'=') {
        let digit = ALPHABET.iter().position(|&a| a == c).unwrap() as u32;
        acc = (acc << 6 | digit) & 0xffff;
        bits += 6;
        if bits >= 8 {
            bits -= 8;
            bytes.push((acc >> bits) as u8);
        }
    }
    bytes
}

/// The `Float32Array` embedded in the viewer page under `id`.
fn embedded_floats(html: &str, id: &str) -> Vec<f32> {
    let open = format!("id=\"{id}\">");
    let start = html.find(&open).unwrap() + open.len();
    let len = html[start..].find('<').unwrap();
    base64_decode(&html[start..start + len])
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect()
}

#[test]
fn the_viewer_writes_a_mesh_far_from_the_origin_as_at_the_origin() {
    // WebGL computes in f32: the page gets coordinates centred on the mesh and scaled into
    // the unit sphere, computed in f64, so the translation is gone before they are narrowed.
    let (mesh, lines) = fandisk_and_its_creases();
    let (far_mesh, far_lines) = translated(&mesh, &lines, Vec3::from(FAR));
    let opts = RenderOptions::default();
    let near = render_html(&mesh, Some(&lines), None, &opts).unwrap();
    let far = render_html(&far_mesh, Some(&far_lines), None, &opts).unwrap();
    for id in ["data-positions", "data-ridges"] {
        let (a, b) = (embedded_floats(&near, id), embedded_floats(&far, id));
        assert_eq!(a.len(), b.len(), "{id}");
        assert!(a.len() > 1000, "{id}: {}", a.len());
        // f32 steps are 6e-8 below 1; the f64 rounding at 1e7 is 5e-10 of fandisk's radius.
        let worst = a
            .iter()
            .zip(&b)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f32::max);
        assert!(worst <= 1e-6, "{id}: coordinates differ by {worst}");
    }
}
