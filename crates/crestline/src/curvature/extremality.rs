//! Discrete extremalities and regular/singular triangles (Hildebrandt, Polthier, Wardetzky,
//! *Smooth Feature Lines on Surface Meshes*, SGP 2005 (HPW), sec. 3, eq. 4 and Definition 1).
//!
//! **Extremality (eq. 4).** κ_i (i = max, min) is the piecewise-linear interpolation of the
//! vertex values; its gradient ∇κ_i(T) is constant on each triangle T. Then
//!
//! `e_i(p) = 1/area(star(p)) · Σ_{T∋p} area(T) ⟨∇κ_i(T), dir_i(p)⟩`.
//!
//! κ_i is a scalar field, so the signs of the principal directions at the other vertices of
//! T do not enter: the gradient is the same whatever they are. Only `dir_i(p)` matters, and
//! exactly as stored: we compute the area-weighted mean gradient
//! `G_i(p) = Σ_{T∋p} area(T) ∇κ_i(T) / area(star(p))` and return `⟨G_i(p), dir_i(p)⟩`. Flip
//! `dir_i(p)` and `e_i(p)` flips; this is the derivative of k_i along the stored direction,
//! the crate's convention. (HPW's consistent orientation of the directions over a triangle
//! or a regularized star matters later, when the zero set of e_i inside a triangle is traced
//! — that needs the three e_i re-signed with consistently oriented directions; see
//! [`consistent_signs`], which [`crate::lines::trace`] uses.) ∇κ_i(T) lies in the plane of T and `dir_i(p)` in the tangent plane
//! of p; we take the plain 3D inner product, as the paper does.
//!
//! **Regularity (Definition 1).** A triangle is regular for family i when the signs of the
//! three directions can be chosen so that their inner products are all positive. Fixing the
//! first direction and choosing the others to agree with it, the remaining product is
//! positive exactly when `⟨d₀,d₁⟩⟨d₁,d₂⟩⟨d₂,d₀⟩ > 0` ([`consistent_signs`], [`is_regular`];
//! the signs are compared rather than the product formed, which could underflow); a zero
//! product is singular.
//!
//! **Limits.** At an umbilic the principal directions are arbitrary, so triangles near
//! umbilics (and in noisy, nearly umbilic regions) come out singular: that is the point of
//! the definition. Eq. 4 differentiates the shape operator's point values once more, so on
//! irregular meshes the extremalities are noisy (HPW answer this with extremality smoothing,
//! sec. 5.1). A vertex whose star has zero area gets e = 0.

use rayon::prelude::*;

use super::Curvature;
use crate::mesh::{TriMesh, Vec3, face_normal_and_area};

/// Area times the gradient of the piecewise-linear interpolation of `(f₀, f₁, f₂)` over a
/// triangle with unit normal `n` and corners `p`: `A ∇f = ½ n × Σ_j f_j (p_{j+2} − p_{j+1})`
/// (each opposite edge turned by 90° in the plane; zero for a zero normal).
#[inline]
fn area_gradient(n: Vec3, p: &[Vec3; 3], f: [f64; 3]) -> Vec3 {
    let rotated_sum = (p[2] - p[1]) * f[0] + (p[0] - p[2]) * f[1] + (p[1] - p[0]) * f[2];
    0.5 * n.cross(&rotated_sum)
}

/// Fills `curvature.e_max` and `curvature.e_min` by HPW eq. 4 from its curvatures and
/// directions (the two families share one pass over the faces), vertex by vertex in
/// parallel. Vertices with a zero-area star get 0.
///
/// Each face's normal, area and gradients are recomputed at each of its three corners rather
/// than stored (a per-face table would be the largest transient of the curvature stage); the
/// arithmetic is the same, so are the results.
pub fn compute_extremalities(mesh: &TriMesh, curvature: &mut Curvature) {
    let n = mesh.num_vertices();
    let faces = mesh.faces();
    let topo = mesh.topology();
    let Curvature {
        k_max,
        k_min,
        dir_max,
        dir_min,
        e_max,
        e_min,
        ..
    } = curvature;
    e_max.resize(n, 0.0);
    e_min.resize(n, 0.0);
    let (k_max, k_min, dir_max, dir_min) = (&*k_max, &*k_min, &*dir_max, &*dir_min);
    e_max
        .par_iter_mut()
        .zip(e_min.par_iter_mut())
        .enumerate()
        .for_each(|(v, (e_max, e_min))| {
            let (mut g_max, mut g_min, mut star) = (Vec3::zeros(), Vec3::zeros(), 0.0);
            for &f in topo.vertex_faces(v as u32) {
                let f = f as usize;
                let (normal, area) = face_normal_and_area(mesh, f);
                let t = faces[f].map(|v| v as usize);
                let p = mesh.triangle(f);
                g_max += area_gradient(normal, &p, t.map(|v| k_max[v]));
                g_min += area_gradient(normal, &p, t.map(|v| k_min[v]));
                star += area;
            }
            (*e_max, *e_min) = if star.is_nan() || star <= 0.0 {
                (0.0, 0.0)
            } else {
                (
                    finite_or_zero(g_max.dot(&dir_max[v]) / star),
                    finite_or_zero(g_min.dot(&dir_min[v]) / star),
                )
            };
        });
}

#[inline]
fn finite_or_zero(x: f64) -> f64 {
    if x.is_finite() { x } else { 0.0 }
}

/// HPW Definition 1: signs making the three line directions mutually positive (their
/// pairwise inner products all > 0), or `None` when the triangle is singular. The first sign
/// is always `+1`; the directions re-signed are consistently oriented over the triangle.
#[inline]
pub fn consistent_signs(d: [Vec3; 3]) -> Option<[f64; 3]> {
    let d01 = d[0].dot(&d[1]);
    let d02 = d[0].dot(&d[2]);
    let s1 = if d01 < 0.0 { -1.0 } else { 1.0 };
    let s2 = if d02 < 0.0 { -1.0 } else { 1.0 };
    (d01 != 0.0 && d02 != 0.0 && s1 * s2 * d[1].dot(&d[2]) > 0.0).then_some([1.0, s1, s2])
}

/// HPW Definition 1: true when the three line directions can be oriented consistently
/// ([`consistent_signs`] finds signs).
#[inline]
pub fn is_regular(d: [Vec3; 3]) -> bool {
    consistent_signs(d).is_some()
}

/// Per-face regularity of the two principal direction fields (HPW Definition 1).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct TriangleRegularity {
    /// `regular_max[f]`: the `dir_max` directions at the corners of face `f` can be oriented
    /// consistently.
    pub regular_max: Vec<bool>,
    /// The same for `dir_min`.
    pub regular_min: Vec<bool>,
    /// Faces singular for `dir_max`.
    pub singular_max: usize,
    /// Faces singular for `dir_min`.
    pub singular_min: usize,
    /// Faces singular for either family.
    pub singular_either: usize,
}

impl TriangleRegularity {
    /// Fraction of faces singular for `dir_max` (0 for a mesh without faces).
    pub fn singular_max_fraction(&self) -> f64 {
        fraction(self.singular_max, self.regular_max.len())
    }

    /// Fraction of faces singular for `dir_min`.
    pub fn singular_min_fraction(&self) -> f64 {
        fraction(self.singular_min, self.regular_min.len())
    }

    /// Fraction of faces singular for either family.
    pub fn singular_either_fraction(&self) -> f64 {
        fraction(self.singular_either, self.regular_max.len())
    }
}

fn fraction(count: usize, total: usize) -> f64 {
    if total == 0 {
        0.0
    } else {
        count as f64 / total as f64
    }
}

/// Classifies every face as regular or singular for both direction families.
///
/// In exact arithmetic the max and min families give the same answer at interior vertices
/// whose two directions are orthogonal in a common plane; with directions in different
/// tangent planes they can differ slightly, so both are reported.
pub fn triangle_regularity(mesh: &TriMesh, curvature: &Curvature) -> TriangleRegularity {
    let (regular_max, regular_min): (Vec<bool>, Vec<bool>) = mesh
        .faces()
        .par_iter()
        .map(|t| {
            (
                is_regular(t.map(|v| curvature.dir_max[v as usize])),
                is_regular(t.map(|v| curvature.dir_min[v as usize])),
            )
        })
        .unzip();
    let singular_max = regular_max.iter().filter(|&&r| !r).count();
    let singular_min = regular_min.iter().filter(|&&r| !r).count();
    let singular_either = regular_max
        .iter()
        .zip(&regular_min)
        .filter(|&(&a, &b)| !(a && b))
        .count();
    TriangleRegularity {
        regular_max,
        regular_min,
        singular_max,
        singular_min,
        singular_either,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes;

    /// A flat grid over [-1, 1]² in the plane z = 0 with a linear field, whose gradient is
    /// exact on every triangle.
    fn flat_grid() -> TriMesh {
        shapes::height_field(|_, _| 0.0, [-1.0, 1.0], [-1.0, 1.0], 6, 5)
    }

    /// HPW eq. 4 for one family: `k` and `dir` as both families' fields.
    fn extremality(mesh: &TriMesh, k: &[f64], dir: &[Vec3]) -> Vec<f64> {
        let mut curvature = Curvature {
            k_max: k.to_vec(),
            k_min: k.to_vec(),
            dir_max: dir.to_vec(),
            dir_min: dir.to_vec(),
            ..Default::default()
        };
        compute_extremalities(mesh, &mut curvature);
        curvature.e_max
    }

    #[test]
    fn linear_field_has_exact_extremality_and_flips_with_the_direction() {
        let m = flat_grid();
        // k(x, y) = 2x − 3y: ∇k = (2, −3, 0) everywhere, so e = ⟨(2, −3, 0), dir⟩ exactly,
        // boundary vertices included (the mean of equal gradients).
        let k: Vec<f64> = m
            .positions()
            .iter()
            .map(|p| 2.0 * p.x - 3.0 * p.y)
            .collect();
        let dir: Vec<Vec3> = (0..m.num_vertices())
            .map(|i| {
                let a = i as f64 * 0.7;
                Vec3::new(a.cos(), a.sin(), 0.0)
            })
            .collect();
        let e = extremality(&m, &k, &dir);
        for (i, d) in dir.iter().enumerate() {
            let expected = 2.0 * d.x - 3.0 * d.y;
            assert!(
                (e[i] - expected).abs() < 1e-12,
                "{i}: {} vs {expected}",
                e[i]
            );
        }
        let flipped: Vec<Vec3> = dir.iter().map(|d| -d).collect();
        let e_flipped = extremality(&m, &k, &flipped);
        for i in 0..e.len() {
            assert_eq!(e_flipped[i], -e[i]);
        }
    }

    #[test]
    fn regularity_of_three_directions() {
        let x = Vec3::x();
        let at = |deg: f64| {
            let a = deg.to_radians();
            Vec3::new(a.cos(), a.sin(), 0.0)
        };
        assert!(is_regular([x, at(10.0), at(-20.0)]));
        // Signs do not matter.
        assert!(is_regular([-x, at(10.0), -at(-20.0)]));
        assert!(is_regular([x, at(170.0), at(200.0)]));
        // Three lines 60° apart (a trisector pattern): no consistent orientation.
        assert!(!is_regular([x, at(60.0), at(120.0)]));
        assert!(!is_regular([x, -at(60.0), at(120.0)]));
        // An orthogonal pair is singular (zero product).
        assert!(!is_regular([x, Vec3::y(), x]));
        assert_eq!(consistent_signs([x, x, x]), Some([1.0, 1.0, 1.0]));
        assert_eq!(consistent_signs([x, -x, x]), Some([1.0, -1.0, 1.0]));
        assert_eq!(
            consistent_signs([x, at(170.0), at(200.0)]),
            Some([1.0, -1.0, -1.0])
        );
        // Three directions 120° apart: singular.
        assert_eq!(consistent_signs([x, at(120.0), at(240.0)]), None);
        assert!(consistent_signs([at(0.0), at(17.0), at(34.0)]).is_some());
    }

    #[test]
    fn regularity_counts() {
        let m = flat_grid();
        let n = m.num_vertices();
        let mut c = Curvature {
            dir_max: vec![Vec3::x(); n],
            dir_min: vec![Vec3::y(); n],
            ..Default::default()
        };
        let r = triangle_regularity(&m, &c);
        assert_eq!(
            (r.singular_max, r.singular_min, r.singular_either),
            (0, 0, 0)
        );
        // Rotate the directions at one interior vertex by 90°: each of its faces now has
        // two parallel and one orthogonal direction, a zero product, so it is singular.
        let v = 8; // (i, j) = (2, 1) on the 7 × 6 vertex grid: interior.
        assert!(!m.topology().is_boundary_vertex(v));
        c.dir_max[v as usize] = Vec3::y();
        c.dir_min[v as usize] = Vec3::x();
        let r = triangle_regularity(&m, &c);
        let star = m.topology().vertex_faces(v).len();
        assert_eq!(
            (r.singular_max, r.singular_min, r.singular_either),
            (star, star, star)
        );
        assert!((r.singular_max_fraction() - star as f64 / m.num_faces() as f64).abs() < 1e-15);
    }
}
