//! Hidden-line removal for feature lines drawn over the rendered mesh, and their drawing.
//!
//! Each segment of a line is cut into pieces at most [`PIECE_PIXELS`] long on screen. The
//! middle of each piece is projected and compared with the mesh's z-buffer: the piece is
//! visible when it is no farther than the *farthest* depth among the 3×3 pixels around it
//! plus a bias. Lines lie on the surface they were traced on, so the bias absorbs the
//! difference between the line and the rasterised triangles, and taking the farthest
//! neighbour keeps lines on creases and silhouettes (where depth jumps within a pixel)
//! visible. Pieces off the image are dropped. Consecutive visible pieces are joined into
//! one stroke, so strokes have proper joins and SVG paths stay short.
//!
//! Strokes are drawn antialiased with `tiny-skia`, round caps and joins, each kind as one
//! path: first every valley, then every ridge, each over its own halo when one is set.
//!
//! Limits: a line behind a surface but within one pixel of that surface's silhouette, or
//! behind a sheet thinner than the bias, counts as visible.

use rayon::prelude::*;

use super::RenderOptions;
use super::camera::Camera;
use super::raster::VisibilityBuffer;
use crate::lines::{FeatureLine, FeatureLines, LineKind};

/// Longest piece of a segment whose visibility is decided as a whole, in pixels.
pub const PIECE_PIXELS: f64 = 1.0;
/// Most pieces one segment is cut into (a guard against absurd coordinates).
const MAX_PIECES: f64 = 1.0e6;

/// A visible part of a feature line, in pixel coordinates (x right, y down).
#[derive(Debug, Clone, PartialEq)]
pub struct VisibleStroke {
    /// Ridge or valley.
    pub kind: LineKind,
    /// At least two points.
    pub points: Vec<[f64; 2]>,
}

/// The visible strokes of the lines whose kind `opts` shows: valleys first, then ridges,
/// each in the order of `lines`. `bias` is in model units.
pub fn visible_strokes(
    lines: &FeatureLines,
    camera: &Camera,
    buffer: &VisibilityBuffer,
    bias: f64,
    opts: &RenderOptions,
) -> Vec<VisibleStroke> {
    let mut strokes = Vec::new();
    for (kind, shown) in [
        (LineKind::Valley, opts.show_valleys),
        (LineKind::Ridge, opts.show_ridges),
    ] {
        if !shown {
            continue;
        }
        let of_kind: Vec<VisibleStroke> = lines
            .lines
            .par_iter()
            .filter(|l| l.kind == kind)
            .flat_map_iter(|l| strokes_of_line(l, camera, buffer, bias))
            .collect();
        strokes.extend(of_kind);
    }
    strokes
}

/// The visible runs of one line.
fn strokes_of_line(
    line: &FeatureLine,
    camera: &Camera,
    buffer: &VisibilityBuffer,
    bias: f64,
) -> Vec<VisibleStroke> {
    let n = line.points.len();
    let projected: Vec<[f64; 3]> = line.points.iter().map(|p| camera.project(p)).collect();
    let closing = line.closed && n > 2;
    let segments = (0..n.saturating_sub(1))
        .map(|i| (i, i + 1))
        .chain(closing.then_some((n - 1, 0)));
    let mut runs: Vec<Vec<[f64; 2]>> = Vec::new();
    let mut run: Option<Vec<[f64; 2]>> = None;
    for (i, j) in segments {
        let (p, q) = (projected[i], projected[j]);
        let at = |t: f64| [0, 1, 2].map(|k| p[k] + (q[k] - p[k]) * t);
        let length = (q[0] - p[0]).hypot(q[1] - p[1]);
        let pieces = (length / PIECE_PIXELS).ceil().clamp(1.0, MAX_PIECES) as usize;
        for k in 0..pieces {
            let start = k as f64 / pieces as f64;
            let mid = at((k as f64 + 0.5) / pieces as f64);
            if is_visible(mid, buffer, bias) {
                let points = run.get_or_insert_with(Vec::new);
                if points.is_empty() {
                    push_point(points, at(start));
                }
                if k + 1 == pieces {
                    push_point(points, [q[0], q[1], q[2]]);
                }
            } else if let Some(mut points) = run.take() {
                push_point(&mut points, at(start));
                runs.push(points);
            }
        }
    }
    runs.extend(run);
    runs.into_iter()
        .filter(|points| points.len() >= 2)
        .map(|points| VisibleStroke {
            kind: line.kind,
            points,
        })
        .collect()
}

/// Appends the screen position of `p` unless it repeats the last point.
fn push_point(points: &mut Vec<[f64; 2]>, p: [f64; 3]) {
    let xy = [p[0], p[1]];
    if points.last() != Some(&xy) {
        points.push(xy);
    }
}

/// Whether a point (pixel x, y, depth) lies on or in front of the mesh.
fn is_visible(p: [f64; 3], buffer: &VisibilityBuffer, bias: f64) -> bool {
    let (x, y) = (p[0].floor(), p[1].floor());
    if !(x >= 0.0 && y >= 0.0 && x < buffer.width as f64 && y < buffer.height as f64) {
        return false;
    }
    let (x, y) = (x as i64, y as i64);
    let mut farthest = f64::NEG_INFINITY;
    for dy in -1..=1 {
        for dx in -1..=1 {
            if let Some(d) = buffer.depth_at(x + dx, y + dy) {
                farthest = farthest.max(f64::from(d));
            }
        }
    }
    p[2] <= farthest + bias
}

/// Draws `strokes` into `pixmap`, each kind as one path over its halo.
pub fn draw_strokes(
    pixmap: &mut tiny_skia::Pixmap,
    strokes: &[VisibleStroke],
    opts: &RenderOptions,
) {
    for (kind, color) in [
        (LineKind::Valley, opts.valley_color),
        (LineKind::Ridge, opts.ridge_color),
    ] {
        let mut path = tiny_skia::PathBuilder::new();
        for s in strokes.iter().filter(|s| s.kind == kind) {
            let mut points = s.points.iter().map(|p| (p[0] as f32, p[1] as f32));
            if let Some((x, y)) = points.next() {
                path.move_to(x, y);
                for (x, y) in points {
                    path.line_to(x, y);
                }
            }
        }
        let Some(path) = path.finish() else {
            continue;
        };
        let width = opts.line_width as f32;
        let mut layers = Vec::new();
        if let Some(halo) = opts.line_halo {
            layers.push((halo, width + 2.0));
        }
        layers.push((color, width));
        for (rgb, width) in layers {
            let mut paint = tiny_skia::Paint::default();
            paint.set_color_rgba8(rgb[0], rgb[1], rgb[2], 255);
            paint.anti_alias = true;
            let stroke = tiny_skia::Stroke {
                width,
                line_cap: tiny_skia::LineCap::Round,
                line_join: tiny_skia::LineJoin::Round,
                ..tiny_skia::Stroke::default()
            };
            pixmap.stroke_path(
                &path,
                &paint,
                &stroke,
                tiny_skia::Transform::identity(),
                None,
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::Vec3;
    use crate::render::{UpAxis, Viewport};

    /// A camera mapping model (x, y, z) to pixel (x, 20 - y) at depth -z, and a 20×20 buffer
    /// at depth 0 left of x = 10 and -1 (nearer: an occluder) from x = 10 on.
    fn scene() -> (Camera, VisibilityBuffer) {
        let viewport = Viewport {
            x: 0.0,
            y: 0.0,
            width: 20.0,
            height: 20.0,
        };
        let corners = [Vec3::new(0.0, 0.0, 0.0), Vec3::new(20.0, 20.0, 0.0)];
        let camera = Camera::orbit(0.0, 0.0, UpAxis::Y).fit(corners.into_iter(), viewport, 0.0);
        let depth = (0..400)
            .map(|i| if i % 20 >= 10 { -1.0 } else { 0.0 })
            .collect();
        let buffer = VisibilityBuffer {
            width: 20,
            height: 20,
            depth,
            face: vec![0; 400],
        };
        (camera, buffer)
    }

    fn feature_line(points: &[[f64; 3]], closed: bool) -> FeatureLine {
        FeatureLine::new(
            LineKind::Ridge,
            points.iter().map(|&p| Vec3::from(p)).collect(),
            closed,
        )
    }

    #[test]
    fn a_line_going_behind_an_occluder_stops_there() {
        let (camera, buffer) = scene();
        let line = feature_line(&[[2.0, 10.0, 0.0], [18.0, 10.0, 0.0]], false);
        let strokes = strokes_of_line(&line, &camera, &buffer, 0.01);
        assert_eq!(strokes.len(), 1);
        let points = &strokes[0].points;
        assert_eq!(points[0], [2.0, 10.0]);
        // The last piece whose 3x3 neighbourhood still sees depth 0 is the one at x = 10.
        assert_eq!(points.len(), 2);
        assert!((10.0..=12.0).contains(&points[1][0]), "{points:?}");
        // In front of the occluder the whole line is one stroke of its two end points.
        let front = feature_line(&[[2.0, 10.0, 2.0], [18.0, 10.0, 2.0]], false);
        let strokes = strokes_of_line(&front, &camera, &buffer, 0.01);
        assert_eq!(strokes[0].points, vec![[2.0, 10.0], [18.0, 10.0]]);
    }

    #[test]
    fn a_visible_closed_line_is_one_stroke_back_to_its_start() {
        let (camera, buffer) = scene();
        let square = [
            [2.0, 2.0, 0.0],
            [8.0, 2.0, 0.0],
            [8.0, 8.0, 0.0],
            [2.0, 8.0, 0.0],
        ];
        let strokes = strokes_of_line(&feature_line(&square, true), &camera, &buffer, 0.01);
        assert_eq!(strokes.len(), 1);
        let p = &strokes[0].points;
        assert_eq!(p.len(), 5);
        assert_eq!(p[0], p[4]);
        // Off the image, nothing is drawn.
        let outside = feature_line(&[[30.0, 30.0, 0.0], [40.0, 30.0, 0.0]], false);
        assert!(strokes_of_line(&outside, &camera, &buffer, 0.01).is_empty());
    }
}
