//! The Garland–Heckbert quadrics of the decimation: a plane quadric per triangle, scaled by
//! its area and YBS eq. 7 weight, and one per boundary edge (see the module docs of
//! [`crate::simplify`]).

use rayon::prelude::*;

use crate::mesh::{TriMesh, Vec3};

/// A symmetric 4 × 4 quadric `[A b; bᵀ c]`, stored as its upper triangle, whose value at `x`
/// is `xᵀAx + 2bᵀx + c`: a weighted sum of squared distances to planes.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(super) struct Quadric([f64; 10]);

impl Quadric {
    /// `weight` times the squared distance to the plane `n·x + d = 0` (`n` unit).
    pub(super) fn plane(n: Vec3, d: f64, weight: f64) -> Self {
        let (a, b, c) = (n.x, n.y, n.z);
        Quadric(
            [
                a * a,
                a * b,
                a * c,
                a * d,
                b * b,
                b * c,
                b * d,
                c * c,
                c * d,
                d * d,
            ]
            .map(|x| x * weight),
        )
    }

    pub(super) fn add(&mut self, other: &Quadric) {
        for (x, y) in self.0.iter_mut().zip(other.0) {
            *x += y;
        }
    }

    pub(super) fn sum(&self, other: &Quadric) -> Quadric {
        let mut q = *self;
        q.add(other);
        q
    }

    pub(super) fn value(&self, p: Vec3) -> f64 {
        let [a11, a12, a13, b1, a22, a23, b2, a33, b3, c] = self.0;
        let (x, y, z) = (p.x, p.y, p.z);
        x * (a11 * x + 2.0 * (a12 * y + a13 * z + b1))
            + y * (a22 * y + 2.0 * (a23 * z + b2))
            + z * (a33 * z + 2.0 * b3)
            + c
    }

    /// The point where the quadric is smallest, when `A` is well conditioned.
    pub(super) fn minimizer(&self) -> Option<Vec3> {
        let [a11, a12, a13, b1, a22, a23, b2, a33, b3, _] = self.0;
        // Cofactors of the symmetric A (Cramer's rule).
        let c11 = a22 * a33 - a23 * a23;
        let c12 = a13 * a23 - a12 * a33;
        let c13 = a12 * a23 - a13 * a22;
        let c22 = a11 * a33 - a13 * a13;
        let c23 = a12 * a13 - a11 * a23;
        let c33 = a11 * a22 - a12 * a12;
        let det = a11 * c11 + a12 * c12 + a13 * c13;
        // For a positive semi-definite A, det / (trace/3)³ is the ratio of the geometric to
        // the arithmetic mean of the eigenvalues, cubed: near zero when one eigenvalue is
        // negligible against the others, i.e. the minimiser is not a point.
        let mean = (a11 + a22 + a33) / 3.0;
        if mean.is_nan() || mean <= 0.0 || det <= 1e-10 * mean * mean * mean {
            return None;
        }
        let x = -(c11 * b1 + c12 * b2 + c13 * b3) / det;
        let y = -(c12 * b1 + c22 * b2 + c23 * b3) / det;
        let z = -(c13 * b1 + c23 * b2 + c33 * b3) / det;
        let p = Vec3::new(x, y, z);
        p.iter().all(|c| c.is_finite()).then_some(p)
    }
}

/// Each triangle's `w · area · plane quadric`.
pub(super) fn face_quadrics(
    positions: &[Vec3],
    faces: &[[u32; 3]],
    face_weights: &[f64],
) -> Vec<Quadric> {
    faces
        .par_iter()
        .enumerate()
        .map(|(f, t)| {
            let [a, b, c] = t.map(|v| positions[v as usize]);
            let cross = (b - a).cross(&(c - a));
            let area = 0.5 * cross.norm();
            match cross.try_normalize(0.0) {
                Some(n) => Quadric::plane(n, -n.dot(&a), face_weights[f] * area),
                None => Quadric::default(),
            }
        })
        .collect()
}

/// Adds, for each boundary edge, the plane through it perpendicular to its triangle to both
/// end points, weighted by `boundary_weight · w · length²`.
pub(super) fn add_boundary_quadrics(
    mesh: &TriMesh,
    positions: &[Vec3],
    face_weights: &[f64],
    boundary_weight: f64,
    quadrics: &mut [Quadric],
) {
    if boundary_weight == 0.0 {
        return;
    }
    let topo = mesh.topology();
    for e in 0..topo.num_edges() as u32 {
        let &[f] = topo.edge_faces(e) else {
            continue;
        };
        let [a, b] = topo.edge(e);
        let [p, q, r] = mesh.faces()[f as usize].map(|v| positions[v as usize]);
        let normal = (q - p).cross(&(r - p));
        let (pa, pb) = (positions[a as usize], positions[b as usize]);
        let edge = pb - pa;
        let Some(m) = edge.cross(&normal).try_normalize(0.0) else {
            continue;
        };
        let weight = boundary_weight * face_weights[f as usize] * edge.norm_squared();
        let plane = Quadric::plane(m, -m.dot(&pa), weight);
        quadrics[a as usize].add(&plane);
        quadrics[b as usize].add(&plane);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn minimizer_is_the_corner_of_three_planes() {
        let mut q = Quadric::default();
        for (n, d) in [(Vec3::x(), -1.0), (Vec3::y(), -2.0), (Vec3::z(), 3.0)] {
            q.add(&Quadric::plane(n, d, 1.5));
        }
        let x = q.minimizer().unwrap();
        assert!((x - Vec3::new(1.0, 2.0, -3.0)).norm() < 1e-12);
        assert!(q.value(x).abs() < 1e-12);
        assert!((q.value(Vec3::new(1.0, 2.0, -1.0)) - 1.5 * 4.0).abs() < 1e-12);
        // Two planes meet in a line: no unique minimiser.
        let mut crease = Quadric::plane(Vec3::x(), 0.0, 1.0);
        crease.add(&Quadric::plane(Vec3::y(), 0.0, 1.0));
        assert_eq!(crease.minimizer(), None);
    }
}
