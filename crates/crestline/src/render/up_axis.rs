//! Which model axis points up: [`UpAxis`], and the guess from the mesh behind
//! [`UpAxis::Auto`].
//!
//! ## The rule ([`guess_up_axis`])
//! The choice is between +Y (the convention of scanned models and OBJ/PLY files: the bunny,
//! igea and the horse) and +Z (CAD parts and STL files). Neither convention shows in a
//! file's format, but CAD parts usually stand on a flat face, while scans rarely have one.
//! So, in order:
//! 1. **A flat sheet is seen face-on.** When the mesh is flat along Y or Z (thinner than
//!    [`FLAT_SHEET`] of the diagonal), that axis is never up: the turntable camera would see
//!    the sheet edge-on. Flat along Z gives Y, flat along Y gives Z.
//! 2. **A flat base marks the up axis.** The *support* of an axis is the area of the faces
//!    lying entirely within [`BASE_TOLERANCE`] of the diagonal above the mesh's lowest point
//!    along that axis whose normals are within [`BASE_ANGLE_DEGREES`] of it (either sign, so
//!    the orientation of the faces does not matter), as a fraction of the whole area. The
//!    axis with the larger support wins when that support is at least [`MIN_BASE_AREA`] and
//!    at least [`BASE_DOMINANCE`] times the other's: a plate, a nut or a box standing on its
//!    bottom face is recognised; a rounded bottom (an ellipsoid, the bunny's) is not a base.
//! 3. **Otherwise +Y**, the old default and the scans' convention.
//!
//! What a wrong guess costs is a picture turned by 90° (the model on its back or side); the
//! lines are still all drawn. The rule therefore needs clear evidence (a flat base) to leave
//! +Y, and with none it keeps the answer a Y-up scan needs. Only the lower side counts: up is
//! +Y or +Z, so a model upside-down is not turned over. Known limit: a Z-up scan without a
//! flat base is shown as Y-up; give the axis (`--up z`) then.

use rayon::prelude::*;

use crate::mesh::{TriMesh, Vec3};

/// A mesh thinner than this fraction of its bounding-box diagonal along an axis is a flat
/// sheet along that axis.
pub const FLAT_SHEET: f64 = 1e-3;
/// How far above the lowest point (fraction of the diagonal) a base face may lie.
pub const BASE_TOLERANCE: f64 = 2.5e-3;
/// Largest angle between a base face's normal and the axis, in degrees.
pub const BASE_ANGLE_DEGREES: f64 = 5.0;
/// Smallest base, as a fraction of the mesh's area.
pub const MIN_BASE_AREA: f64 = 0.01;
/// How many times larger than the other axis's the winning support must be.
pub const BASE_DOMINANCE: f64 = 2.0;

/// Which model axis points up on screen at elevation 0.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum UpAxis {
    /// Guessed from the mesh when drawing ([`guess_up_axis`]: a flat base along Z or a flat
    /// sheet in an XZ plane gives [`UpAxis::Z`], anything else [`UpAxis::Y`]).
    #[default]
    Auto,
    /// +Y up, the camera at azimuth 0 looks along -Z (the usual OBJ convention).
    Y,
    /// +Z up, the camera at azimuth 0 looks along +Y (the CAD and Blender convention).
    Z,
}

impl UpAxis {
    /// This axis, or the guess for `mesh` when it is [`UpAxis::Auto`].
    pub fn resolve(self, mesh: &TriMesh) -> UpAxis {
        match self {
            UpAxis::Auto => guess_up_axis(mesh).axis,
            given => given,
        }
    }

    /// `"auto"`, `"y"` or `"z"`.
    pub fn name(self) -> &'static str {
        match self {
            UpAxis::Auto => "auto",
            UpAxis::Y => "y",
            UpAxis::Z => "z",
        }
    }
}

/// Why [`guess_up_axis`] chose its axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum UpReason {
    /// The mesh is a flat sheet normal to the other axis.
    FlatSheet,
    /// The mesh stands on a flat base covering this fraction of its area.
    Base(f64),
    /// No flat base: the default.
    NoBase,
}

/// The guessed up axis of a mesh and the reason.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UpGuess {
    /// [`UpAxis::Y`] or [`UpAxis::Z`].
    pub axis: UpAxis,
    /// Why.
    pub reason: UpReason,
}

impl std::fmt::Display for UpGuess {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let axis = self.axis.name();
        match self.reason {
            UpReason::FlatSheet => write!(f, "{axis} (the mesh is flat, seen face-on)"),
            UpReason::Base(area) => write!(
                f,
                "{axis} (a flat base of {:.0}% of the area at the lowest {axis})",
                100.0 * area
            ),
            UpReason::NoBase => write!(f, "{axis} (no flat base: the scans' convention)"),
        }
    }
}

/// Guesses the up axis of `mesh` by the rule of the module documentation.
pub fn guess_up_axis(mesh: &TriMesh) -> UpGuess {
    let guess = |axis, reason| UpGuess { axis, reason };
    let bounds = mesh.bounding_box();
    let diagonal = bounds.diagonal();
    let extent = |k: usize| bounds.max[k] - bounds.min[k];
    if diagonal > 0.0 && extent(2) <= FLAT_SHEET * diagonal {
        return guess(UpAxis::Y, UpReason::FlatSheet);
    }
    if diagonal > 0.0 && extent(1) <= FLAT_SHEET * diagonal {
        return guess(UpAxis::Z, UpReason::FlatSheet);
    }
    let [y, z] = base_support(mesh, [bounds.min[1], bounds.min[2]], diagonal);
    let (axis, best, other) = if z > y {
        (UpAxis::Z, z, y)
    } else {
        (UpAxis::Y, y, z)
    };
    if best >= MIN_BASE_AREA && best >= BASE_DOMINANCE * other {
        guess(axis, UpReason::Base(best))
    } else {
        guess(UpAxis::Y, UpReason::NoBase)
    }
}

/// The supports of Y and Z (see the module documentation), given the lowest coordinates.
fn base_support(mesh: &TriMesh, lowest: [f64; 2], diagonal: f64) -> [f64; 2] {
    let tolerance = BASE_TOLERANCE * diagonal;
    let cos_angle = BASE_ANGLE_DEGREES.to_radians().cos();
    let (base, total) = mesh
        .faces()
        .par_iter()
        .map(|t| {
            let [a, b, c] = t.map(|v| mesh.position(v));
            let normal: Vec3 = (b - a).cross(&(c - a));
            let double_area = normal.norm();
            let mut base = [0.0; 2];
            for (k, axis) in [1, 2].into_iter().enumerate() {
                let highest = a[axis].max(b[axis]).max(c[axis]);
                if highest <= lowest[k] + tolerance && normal[axis].abs() >= cos_angle * double_area
                {
                    base[k] = double_area;
                }
            }
            (base, double_area)
        })
        .reduce(
            || ([0.0; 2], 0.0),
            |(b1, t1), (b2, t2)| ([b1[0] + b2[0], b1[1] + b2[1]], t1 + t2),
        );
    if total > 0.0 && total.is_finite() {
        base.map(|b| b / total)
    } else {
        [0.0; 2]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The box from `offset` to `offset + size` (two triangles per side).
    fn box_mesh(size: [f64; 3], offset: [f64; 3]) -> TriMesh {
        let (cube, _) = crate::shapes::pillow_box(0.5, 0.0, 1);
        let moved = cube
            .positions()
            .iter()
            .map(|p| Vec3::from([0, 1, 2].map(|k| offset[k] + size[k] * (p[k] + 0.5))));
        cube.with_positions(moved.collect()).unwrap()
    }

    /// Both meshes as one.
    fn union(a: &TriMesh, b: &TriMesh) -> TriMesh {
        let shift = a.num_vertices() as u32;
        let positions = [a.positions(), b.positions()].concat();
        let faces = a.faces().iter().copied();
        let faces = faces.chain(b.faces().iter().map(|t| t.map(|v| v + shift)));
        TriMesh::new(positions, faces.collect()).unwrap()
    }

    /// A sphere of radius 1 (smooth, no base) standing on a 2 × 2 slab 0.2 thick, along
    /// `up` (0, 1 or 2).
    fn standing_on_a_base(up: usize) -> TriMesh {
        let along_up = |on: f64, off: f64| [0, 1, 2].map(|k| if k == up { on } else { off });
        let sphere = crate::shapes::icosphere(1.0, 3);
        let lift = Vec3::from(along_up(1.0, 0.0));
        let sphere = sphere.with_positions(sphere.positions().iter().map(|p| p + lift).collect());
        let slab = box_mesh(along_up(0.2, 2.0), along_up(-0.2, -1.0));
        union(&sphere.unwrap(), &slab)
    }

    #[test]
    fn a_shape_standing_on_a_base_is_seen_upright() {
        assert_eq!(guess_up_axis(&standing_on_a_base(1)).axis, UpAxis::Y);
        let z = guess_up_axis(&standing_on_a_base(2));
        assert_eq!(z.axis, UpAxis::Z);
        assert!(matches!(z.reason, UpReason::Base(a) if a > 0.05), "{z:?}");
        // A base along X is not an up axis on offer: the default.
        assert_eq!(
            guess_up_axis(&standing_on_a_base(0)),
            UpGuess {
                axis: UpAxis::Y,
                reason: UpReason::NoBase
            }
        );
    }

    #[test]
    fn without_a_flat_base_y_is_up() {
        let ellipsoid = crate::shapes::ellipsoid(1.0, 0.75, 0.5, 3);
        assert_eq!(guess_up_axis(&ellipsoid).reason, UpReason::NoBase);
        assert_eq!(UpAxis::Auto.resolve(&ellipsoid), UpAxis::Y);
    }

    #[test]
    fn a_flat_base_must_dominate() {
        // A cube has a base along Y and along Z: no clear answer, so the default.
        let cube = box_mesh([1.0; 3], [0.0; 3]);
        assert_eq!(guess_up_axis(&cube).reason, UpReason::NoBase);
        // A slab thin along Z lies on its large face.
        let slab = box_mesh([1.0, 1.0, 0.1], [0.0; 3]);
        assert_eq!(guess_up_axis(&slab).axis, UpAxis::Z);
        let slab = box_mesh([1.0, 0.1, 1.0], [0.0; 3]);
        assert_eq!(guess_up_axis(&slab).axis, UpAxis::Y);
    }

    #[test]
    fn a_flat_sheet_is_seen_face_on() {
        // The unit square in the plane normal to axis `k`.
        let square = |k: usize| {
            let (i, j) = ((k + 1) % 3, (k + 2) % 3);
            let p = |u: f64, v: f64| {
                let mut p = [0.0; 3];
                p[i] = u;
                p[j] = v;
                p
            };
            let corners = vec![p(0.0, 0.0), p(1.0, 0.0), p(1.0, 1.0), p(0.0, 1.0)];
            TriMesh::from_arrays(corners, vec![[0, 1, 2], [0, 2, 3]]).unwrap()
        };
        // Flat along Z (in the XY plane): Y up, the camera looks along Z.
        assert_eq!(guess_up_axis(&square(2)).axis, UpAxis::Y);
        assert_eq!(guess_up_axis(&square(2)).reason, UpReason::FlatSheet);
        assert_eq!(guess_up_axis(&square(1)).axis, UpAxis::Z);
    }

    #[test]
    fn the_guess_does_not_depend_on_the_orientation_or_the_scale() {
        let mesh = standing_on_a_base(2);
        let flipped: Vec<[u32; 3]> = mesh.faces().iter().map(|t| [t[0], t[2], t[1]]).collect();
        let scaled: Vec<Vec3> = mesh.positions().iter().map(|p| p * 1e-6).collect();
        let other = TriMesh::new(scaled, flipped).unwrap();
        let (a, b) = (guess_up_axis(&other), guess_up_axis(&mesh));
        assert_eq!(a.axis, b.axis);
        let (UpReason::Base(x), UpReason::Base(y)) = (a.reason, b.reason) else {
            panic!("{a:?} {b:?}");
        };
        assert!((x - y).abs() < 1e-12);
        let empty = TriMesh::new(vec![], vec![]).unwrap();
        assert_eq!(guess_up_axis(&empty).axis, UpAxis::Y);
    }
}
