//! An orthographic camera orbiting the model, fitted to what it looks at.
//!
//! The camera direction is set by an azimuth (turning around the up axis) and an elevation
//! (above the horizontal plane), both in degrees. At azimuth 0 and elevation 0 the camera
//! looks at the front of the model: along -Z when +Y is up, along +Y when +Z is up; a
//! positive azimuth moves the camera towards +X, a positive elevation raises it. Screen
//! right stays horizontal, so the up axis stays vertical on screen (a turntable camera);
//! this also holds at elevation ±90°, where the azimuth still orients the picture.
//!
//! Pixel coordinates have x to the right and y down, with pixel (i, j) covering
//! [i, i+1) × [j, j+1). Depth is the distance along the viewing direction, smaller nearer.
//!
//! The camera's centre is the middle of the fitted points' box in all three view directions,
//! depth included, and [`Camera::project`] subtracts it in `f64` before anything else: pixel
//! coordinates and depths are then small numbers relative to the model, whatever its
//! distance from the origin. The rasteriser keeps depths in `f32`; a depth measured from the
//! origin would, for georeferenced data (coordinates of 1e6–1e7), keep only about one unit
//! of resolution and the z-buffer would mix near and far surfaces.

use super::UpAxis;
use crate::mesh::Vec3;

/// A rectangle of the image, in pixels.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Viewport {
    /// Left edge.
    pub x: f64,
    /// Top edge.
    pub y: f64,
    /// Width.
    pub width: f64,
    /// Height.
    pub height: f64,
}

/// An orthographic camera: a screen basis, a centre and a scale in pixels per model unit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    right: Vec3,
    up: Vec3,
    toward: Vec3,
    center: Vec3,
    scale: f64,
    pixel_center: [f64; 2],
}

impl Camera {
    /// A camera looking from `azimuth`, `elevation` (degrees) at the origin, one pixel per
    /// model unit, the origin at pixel (0, 0). Use [`Camera::fit`] to frame a model.
    /// [`UpAxis::Auto`] needs a mesh to be resolved ([`UpAxis::resolve`]); here it is +Y.
    pub fn orbit(azimuth: f64, elevation: f64, up_axis: UpAxis) -> Camera {
        let (up, front) = match up_axis {
            UpAxis::Y | UpAxis::Auto => (Vec3::y(), Vec3::z()),
            UpAxis::Z => (Vec3::z(), -Vec3::y()),
        };
        let side = up.cross(&front);
        let (az, el) = (azimuth.to_radians(), elevation.to_radians());
        let horizontal = front * az.cos() + side * az.sin();
        let toward = horizontal * el.cos() + up * el.sin();
        let right = side * az.cos() - front * az.sin();
        let screen_up = toward.cross(&right);
        Camera {
            right,
            up: screen_up,
            toward,
            center: Vec3::zeros(),
            scale: 1.0,
            pixel_center: [0.0, 0.0],
        }
    }

    /// The same view, scaled and centred so that `points` fill `viewport` less a border of
    /// `margin` times its size on each side. With no points, or all at one place, the
    /// scale is left unchanged (or one pixel per unit along a flat direction). Depths are
    /// then measured from the middle of the points' depth range.
    pub fn fit(
        mut self,
        points: impl Iterator<Item = Vec3>,
        viewport: Viewport,
        margin: f64,
    ) -> Camera {
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for p in points {
            let uvw = [p.dot(&self.right), p.dot(&self.up), p.dot(&self.toward)];
            for k in 0..3 {
                lo[k] = lo[k].min(uvw[k]);
                hi[k] = hi[k].max(uvw[k]);
            }
        }
        self.pixel_center = [
            viewport.x + viewport.width / 2.0,
            viewport.y + viewport.height / 2.0,
        ];
        if lo[0] > hi[0] {
            return self;
        }
        let room = 1.0 - 2.0 * margin;
        let fits = [
            (hi[0] - lo[0], viewport.width * room),
            (hi[1] - lo[1], viewport.height * room),
        ]
        .into_iter()
        .filter(|&(extent, _)| extent > 0.0)
        .map(|(extent, pixels)| pixels / extent)
        .fold(f64::INFINITY, f64::min);
        if fits.is_finite() && fits > 0.0 {
            self.scale = fits;
        }
        let [u, v, w] = [0, 1, 2].map(|k| (lo[k] + hi[k]) / 2.0);
        self.center = self.right * u + self.up * v + self.toward * w;
        self
    }

    /// Pixel coordinates (x right, y down) and depth (smaller is nearer, 0 at the camera's
    /// centre) of `p`.
    #[inline]
    pub fn project(&self, p: &Vec3) -> [f64; 3] {
        let d = p - self.center;
        [
            self.pixel_center[0] + self.scale * d.dot(&self.right),
            self.pixel_center[1] - self.scale * d.dot(&self.up),
            -d.dot(&self.toward),
        ]
    }

    /// Unit vector from the model towards the camera.
    pub fn toward(&self) -> Vec3 {
        self.toward
    }

    /// Unit vector pointing right on screen.
    pub fn right(&self) -> Vec3 {
        self.right
    }

    /// Unit vector pointing up on screen.
    pub fn up(&self) -> Vec3 {
        self.up
    }

    /// Pixels per model unit.
    pub fn scale(&self) -> f64 {
        self.scale
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: Vec3, b: Vec3) -> bool {
        (a - b).norm() < 1e-12
    }

    #[test]
    fn front_view_looks_along_minus_z_with_y_up() {
        let c = Camera::orbit(0.0, 0.0, UpAxis::Y);
        assert!(close(c.toward(), Vec3::z()));
        assert!(close(c.right(), Vec3::x()));
        assert!(close(c.up(), Vec3::y()));
        let c = Camera::orbit(0.0, 0.0, UpAxis::Z);
        assert!(close(c.toward(), -Vec3::y()));
        assert!(close(c.right(), Vec3::x()));
        assert!(close(c.up(), Vec3::z()));
    }

    #[test]
    fn azimuth_moves_the_camera_towards_plus_x_and_elevation_raises_it() {
        let c = Camera::orbit(90.0, 0.0, UpAxis::Y);
        assert!(close(c.toward(), Vec3::x()));
        let c = Camera::orbit(0.0, 90.0, UpAxis::Y);
        assert!(close(c.toward(), Vec3::y()));
        // Straight from above the picture still has a right-handed basis.
        assert!(close(c.right().cross(&c.up()), c.toward()));
        let c = Camera::orbit(37.0, -25.0, UpAxis::Z);
        assert!(close(c.right().cross(&c.up()), c.toward()));
        assert!(c.right().z.abs() < 1e-12, "right stays horizontal");
    }

    #[test]
    fn fit_centres_and_fills_the_viewport() {
        let pts = [Vec3::new(-1.0, -0.5, 0.0), Vec3::new(3.0, 1.5, 2.0)];
        let vp = Viewport {
            x: 0.0,
            y: 0.0,
            width: 200.0,
            height: 100.0,
        };
        let c = Camera::orbit(0.0, 0.0, UpAxis::Y).fit(pts.into_iter(), vp, 0.1);
        // Width 4 into 160 px, height 2 into 80 px: both 40 px per unit.
        assert!((c.scale() - 40.0).abs() < 1e-12);
        let a = c.project(&pts[0]);
        let b = c.project(&pts[1]);
        assert!(
            (a[0] - 20.0).abs() < 1e-9 && (a[1] - 90.0).abs() < 1e-9,
            "{a:?}"
        );
        assert!(
            (b[0] - 180.0).abs() < 1e-9 && (b[1] - 10.0).abs() < 1e-9,
            "{b:?}"
        );
        // The nearer point (larger z, towards the camera) has the smaller depth.
        assert!(b[2] < a[2]);
    }

    #[test]
    fn a_model_far_from_the_origin_projects_as_at_the_origin() {
        // Georeferenced coordinates: the depth, like x and y, is measured from the middle
        // of the fitted points, so it stays small (the rasteriser keeps it in f32).
        let pts = [
            Vec3::new(-1.0, -0.5, 0.25),
            Vec3::new(3.0, 1.5, 2.0),
            Vec3::new(0.5, 2.0, -1.0),
        ];
        let far = Vec3::new(1e7, -2e7, 1e7);
        let vp = Viewport {
            x: 0.0,
            y: 0.0,
            width: 200.0,
            height: 100.0,
        };
        let near_camera = Camera::orbit(30.0, 20.0, UpAxis::Z).fit(pts.into_iter(), vp, 0.1);
        let far_camera =
            Camera::orbit(30.0, 20.0, UpAxis::Z).fit(pts.iter().map(|p| p + far), vp, 0.1);
        let depths = pts.map(|p| near_camera.project(&p)[2]);
        let (lo, hi) = (
            depths.iter().copied().fold(f64::INFINITY, f64::min),
            depths.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        );
        assert!((lo + hi).abs() < 1e-12, "depth 0 is the middle: {depths:?}");
        for p in pts {
            let (a, b) = (near_camera.project(&p), far_camera.project(&(p + far)));
            for k in 0..3 {
                assert!((a[k] - b[k]).abs() < 1e-6, "{a:?} {b:?}");
            }
        }
    }

    #[test]
    fn fit_of_nothing_keeps_a_finite_camera() {
        let vp = Viewport {
            x: 0.0,
            y: 0.0,
            width: 10.0,
            height: 10.0,
        };
        let c = Camera::orbit(0.0, 0.0, UpAxis::Y).fit(std::iter::empty(), vp, 0.0);
        assert_eq!(c.project(&Vec3::zeros())[..2], [5.0, 5.0]);
        let one = [Vec3::new(1.0, 1.0, 1.0)];
        let c = Camera::orbit(0.0, 0.0, UpAxis::Y).fit(one.into_iter(), vp, 0.0);
        assert_eq!(c.project(&one[0])[..2], [5.0, 5.0]);
    }
}
