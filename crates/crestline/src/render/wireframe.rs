//! The mesh's edges drawn over the shaded surface, hidden edges hidden.
//!
//! Each covered pixel already knows the face seen there (the visibility buffer), so a pixel
//! is darkened by its distance to the nearest edge *of that face*: an edge is drawn only
//! where a face it bounds is visible, which hides the hidden edges as the z-buffer hides the
//! hidden surface, and costs one pass over the pixels whatever the number of faces. The
//! distance (in pixels, from the snapped edge functions of the rasteriser) gives an
//! antialiased line about one pixel wide on each side of the edge.
//!
//! On a dense mesh, or at grazing angles, the edges of a face come closer together than a
//! few pixels and would paint the surface dark: a face's edges fade with its smallest
//! height on screen, invisible below [`FADE_START`] pixels and fully drawn from [`FADE_END`].

use super::Rgb;
use super::raster::{SUB, ScreenVertex, VisibilityBuffer, corners, edge, for_each_pixel};
use crate::mesh::TriMesh;

/// Smallest on-screen height of a face (pixels) whose edges are drawn at all.
pub const FADE_START: f64 = 1.0;
/// Smallest on-screen height of a face (pixels) whose edges are drawn at full strength.
pub const FADE_END: f64 = 8.0;
/// Opacity of a fully drawn edge: the shading stays readable under the wires.
const OPACITY: f64 = 0.75;

/// Blends the wireframe of the visible faces into `rgba` (row-major RGBA, the buffer's size).
pub fn draw(
    buffer: &VisibilityBuffer,
    mesh: &TriMesh,
    screen: &[ScreenVertex],
    color: Rgb,
    rgba: &mut [u8],
) {
    let faces = mesh.faces();
    for_each_pixel(buffer, rgba, |face, p, px| {
        let Some(f) = face else {
            return;
        };
        let alpha = edge_coverage(corners(screen, &faces[f as usize]), p);
        if alpha > 0.0 {
            for (c, wire) in px.iter_mut().zip(color) {
                let blended = f64::from(*c) * (1.0 - alpha) + f64::from(wire) * alpha;
                *c = blended.round().clamp(0.0, 255.0) as u8;
            }
        }
    });
}

/// How much of the wire colour the pixel centre `p` (snapped units) takes, inside the
/// triangle `v`: the coverage of the nearest edge's line, times the face's fade.
fn edge_coverage(v: [ScreenVertex; 3], p: (i64, i64)) -> f64 {
    let corner = v.map(|c| (c.x, c.y));
    let double_area = edge(corner[0], corner[1], corner[2]).unsigned_abs() as f64;
    if double_area == 0.0 {
        return 0.0;
    }
    let mut longest: f64 = 0.0;
    let mut nearest = f64::INFINITY;
    for k in 0..3 {
        let (a, b) = (corner[k], corner[(k + 1) % 3]);
        let length = ((b.0 - a.0) as f64).hypot((b.1 - a.1) as f64);
        longest = longest.max(length);
        // |edge function| / edge length is the distance to the edge's line, in snapped units.
        nearest = nearest.min(edge(a, b, p).unsigned_abs() as f64 / length);
    }
    let sub = SUB as f64;
    let height = double_area / longest / sub;
    let fade = ((height - FADE_START) / (FADE_END - FADE_START)).clamp(0.0, 1.0);
    let coverage = (1.0 - nearest / sub).clamp(0.0, 1.0);
    OPACITY * fade * coverage
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sv(x: f64, y: f64) -> ScreenVertex {
        let mut v = ScreenVertex::default();
        v.x = (x * SUB as f64) as i64;
        v.y = (y * SUB as f64) as i64;
        v
    }

    fn at(x: f64, y: f64) -> (i64, i64) {
        ((x * SUB as f64) as i64, (y * SUB as f64) as i64)
    }

    #[test]
    fn pixels_on_an_edge_are_drawn_and_inside_not() {
        let big = [sv(0.0, 0.0), sv(40.0, 0.0), sv(0.0, 40.0)];
        assert!((edge_coverage(big, at(10.0, 0.0)) - OPACITY).abs() < 1e-12);
        assert!(edge_coverage(big, at(10.0, 0.5)) > 0.0);
        assert_eq!(edge_coverage(big, at(10.0, 10.0)), 0.0);
        // The hypotenuse, x + y = 40.
        assert!(edge_coverage(big, at(20.0, 19.9)) > 0.5);
    }

    #[test]
    fn faces_a_few_pixels_small_fade_out() {
        let tiny = [sv(0.0, 0.0), sv(1.0, 0.0), sv(0.0, 1.0)];
        assert_eq!(edge_coverage(tiny, at(0.5, 0.0)), 0.0);
        let sliver = [sv(0.0, 0.0), sv(100.0, 0.0), sv(50.0, 1.0)];
        assert_eq!(edge_coverage(sliver, at(50.0, 0.0)), 0.0);
        let degenerate = [sv(0.0, 0.0), sv(10.0, 0.0), sv(20.0, 0.0)];
        assert_eq!(edge_coverage(degenerate, at(5.0, 0.0)), 0.0);
    }
}
