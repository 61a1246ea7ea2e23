//! Exact principal curvatures, principal directions and extremalities of the analytic shapes
//! that [`crate::shapes`] generates, in the crate's conventions (outward normal, k > 0 where
//! the surface bends away from it, `e` the derivative of `k` along exactly the returned
//! direction). The known answers of the curvature tests, the accuracy example and the benches.
//!
//! Derivations (each checked against finite differences in the tests below):
//! - **Sphere** of radius r: k = 1/r, e = 0; every direction is principal (umbilic).
//! - **Cylinder** of radius r around z: k_max = 1/r around, k_min = 0 along z, e = 0.
//! - **Torus** (tube centre radius R, tube radius r, φ the angle around the tube, 0 on the
//!   outer equator): k = 1/r across the tube (meridian direction) and cos φ/(R + r cos φ)
//!   along it (parallel direction); the first is always the larger. Both are constant along
//!   their own lines of curvature, so e = 0 (a torus is a Dupin cyclide).
//! - **Implicit surfaces** F = 0 with n = ∇F/|∇F| outward: the shape operator is
//!   `P Hess F P / |∇F|` (P the tangent projector), and differentiating `tᵀ S t` along a
//!   principal direction t (with `D_t n = k t`, `D_t |∇F| = nᵀ Hess F t`) gives
//!   `e = (F_ijl t_i t_j t_l − 3k F_ij t_i n_j) / |∇F|`. For the **ellipsoid**
//!   F = x²/a² + y²/b² + z²/c² − 1 the third derivatives vanish.
//!   (YBS eq. 4 prints `+3k`; their curvature sign convention differs.)
//! - **Waving surface** z = f(ρ) = cos ρ, ρ = √(x² + y²), a surface of revolution with
//!   normal up. With W = √(1 + f'²) = √(1 + sin²ρ), the meridian (radial) curvature is
//!   `κ_r = −f''/W³ = cos ρ / (1 + sin²ρ)^{3/2}` and the parallel (circumferential) one is
//!   `κ_c = −f'/(ρ W) = sin ρ / (ρ √(1 + sin²ρ))` (signs flipped from the normal-up textbook
//!   formulas to our convention; both → 1 at the umbilic ρ = 0). By symmetry κ_c is constant
//!   along parallels, so its extremality is 0; along the unit radial direction
//!   t_r = (cos ψ, sin ψ, f') / W (pointing away from the axis), arc length is ds = W dρ and
//!   `e_r = κ_r'(ρ) / W = −2 sin ρ (2 − sin²ρ) / (1 + sin²ρ)³`
//!   (from `κ_r' = −sin ρ (4 − 2 sin²ρ) / (1 + sin²ρ)^{5/2}`).

use crate::curvature::symmetric_eigen_2x2;
use crate::mesh::Vec3;

/// Exact curvature at one point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ExactCurvature {
    /// Maximal principal curvature.
    pub k_max: f64,
    /// Minimal principal curvature.
    pub k_min: f64,
    /// Unit direction of `k_max` (arbitrary at umbilics).
    pub dir_max: Vec3,
    /// Unit direction of `k_min`.
    pub dir_min: Vec3,
    /// Derivative of `k_max` along `dir_max`.
    pub e_max: f64,
    /// Derivative of `k_min` along `dir_min`.
    pub e_min: f64,
    /// Outward unit normal.
    pub normal: Vec3,
}

/// Sphere of `radius` centred at the origin, at the surface point `p`.
pub fn sphere(radius: f64, p: Vec3) -> ExactCurvature {
    let normal = p.try_normalize(0.0).unwrap_or_else(Vec3::z);
    let (u, v, _) = crate::curvature::tangent_frame(normal);
    ExactCurvature {
        k_max: 1.0 / radius,
        k_min: 1.0 / radius,
        dir_max: u,
        dir_min: v,
        e_max: 0.0,
        e_min: 0.0,
        normal,
    }
}

/// Cylinder of `radius` around the z axis, at the surface point `p`.
pub fn cylinder(radius: f64, p: Vec3) -> ExactCurvature {
    let normal = Vec3::new(p.x, p.y, 0.0)
        .try_normalize(0.0)
        .unwrap_or_else(Vec3::x);
    ExactCurvature {
        k_max: 1.0 / radius,
        k_min: 0.0,
        dir_max: Vec3::new(-normal.y, normal.x, 0.0),
        dir_min: Vec3::z(),
        e_max: 0.0,
        e_min: 0.0,
        normal,
    }
}

/// Torus around z with tube centre radius `major` and tube radius `minor`, at `p`.
pub fn torus(major: f64, minor: f64, p: Vec3) -> ExactCurvature {
    let theta = p.y.atan2(p.x);
    let rho = p.x.hypot(p.y);
    let phi = p.z.atan2(rho - major);
    let (st, ct) = theta.sin_cos();
    let (sp, cp) = phi.sin_cos();
    ExactCurvature {
        k_max: 1.0 / minor,
        k_min: cp / (major + minor * cp),
        dir_max: Vec3::new(-sp * ct, -sp * st, cp),
        dir_min: Vec3::new(-st, ct, 0.0),
        e_max: 0.0,
        e_min: 0.0,
        normal: Vec3::new(cp * ct, cp * st, sp),
    }
}

/// Ellipsoid x²/a² + y²/b² + z²/c² = 1 at the surface point `p`.
pub fn ellipsoid(a: f64, b: f64, c: f64, p: Vec3) -> ExactCurvature {
    let hess = Vec3::new(2.0 / (a * a), 2.0 / (b * b), 2.0 / (c * c));
    let grad = hess.component_mul(&p);
    let g = grad.norm();
    let normal = grad / g;
    let (u, v, _) = crate::curvature::tangent_frame(normal);
    let form = |x: Vec3, y: Vec3| x.component_mul(&hess).dot(&y) / g;
    let (k_max, k_min, t) = symmetric_eigen_2x2(form(u, u), form(u, v), form(v, v));
    let dir_max = u * t[0] + v * t[1];
    let dir_min = v * t[0] - u * t[1];
    // e = (F_ijl t t t − 3k F_ij t_i n_j)/|∇F| with F_ijl = 0.
    let e = |k: f64, t: Vec3| -3.0 * k * t.component_mul(&hess).dot(&normal) / g;
    ExactCurvature {
        k_max,
        k_min,
        dir_max,
        dir_min,
        e_max: e(k_max, dir_max),
        e_min: e(k_min, dir_min),
        normal,
    }
}

/// Meridian curvature κ_r, parallel curvature κ_c and the radial extremality e_r of the
/// waving surface at distance `rho` from the axis (see the module docs).
pub fn waving_profile(rho: f64) -> (f64, f64, f64) {
    let (s, c) = rho.sin_cos();
    let w2 = 1.0 + s * s;
    let kappa_r = c / (w2 * w2.sqrt());
    // sin ρ / ρ → 1 at the axis; the series keeps full precision near it.
    let sinc = if rho.abs() < 1e-4 {
        1.0 - rho * rho / 6.0
    } else {
        s / rho
    };
    let kappa_c = sinc / w2.sqrt();
    let e_r = -2.0 * s * (2.0 - s * s) / (w2 * w2 * w2);
    (kappa_r, kappa_c, e_r)
}

/// The waving surface z = cos √(x² + y²) (normal up) at the surface point `p`.
pub fn waving(p: Vec3) -> ExactCurvature {
    let rho = p.x.hypot(p.y);
    let (kappa_r, kappa_c, e_r) = waving_profile(rho);
    let (cpsi, spsi) = if rho > 0.0 {
        (p.x / rho, p.y / rho)
    } else {
        (1.0, 0.0)
    };
    let slope = -rho.sin();
    let w = (1.0 + slope * slope).sqrt();
    let radial = Vec3::new(cpsi, spsi, slope) / w;
    let around = Vec3::new(-spsi, cpsi, 0.0);
    let normal = Vec3::new(-slope * cpsi, -slope * spsi, 1.0) / w;
    if kappa_r >= kappa_c {
        ExactCurvature {
            k_max: kappa_r,
            k_min: kappa_c,
            dir_max: radial,
            dir_min: around,
            e_max: e_r,
            e_min: 0.0,
            normal,
        }
    } else {
        ExactCurvature {
            k_max: kappa_c,
            k_min: kappa_r,
            dir_max: around,
            dir_min: radial,
            e_max: 0.0,
            e_min: e_r,
            normal,
        }
    }
}

/// Maximum and root-mean-square of a set of absolute errors.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ErrorStat {
    /// Largest absolute error (max-norm).
    pub max: f64,
    /// Root mean square error.
    pub rms: f64,
    /// Number of values.
    pub count: usize,
}

impl ErrorStat {
    fn of(values: impl Iterator<Item = f64>) -> Self {
        let (mut max, mut sum, mut count) = (0.0f64, 0.0, 0usize);
        for v in values {
            max = max.max(v.abs());
            sum += v * v;
            count += 1;
        }
        let rms = if count > 0 {
            (sum / count as f64).sqrt()
        } else {
            0.0
        };
        ErrorStat { max, rms, count }
    }
}

/// How far an estimated [`Curvature`](crate::curvature::Curvature) is from the exact values,
/// over selected vertices.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct CurvatureErrors {
    /// `|k_max − exact|`.
    pub k_max: ErrorStat,
    /// `|k_min − exact|`.
    pub k_min: ErrorStat,
    /// `|s·e_max − exact|` with `s = ±1` aligning the estimated `dir_max` with the exact one
    /// (e is odd in the direction).
    pub e_max: ErrorStat,
    /// The same for `e_min`.
    pub e_min: ErrorStat,
    /// Angle in degrees between the estimated and exact `dir_max` lines (only where the
    /// exact principal curvatures differ by more than `min_gap`).
    pub dir_max_deg: ErrorStat,
    /// The same for `dir_min`.
    pub dir_min_deg: ErrorStat,
}

/// Compares `curvature` with `exact` at the vertices `include` accepts. Directions are
/// compared where `exact.k_max − exact.k_min > min_gap` (elsewhere they are not defined).
pub fn compare(
    mesh: &crate::mesh::TriMesh,
    curvature: &crate::curvature::Curvature,
    exact: impl Fn(Vec3) -> ExactCurvature,
    include: impl Fn(usize) -> bool,
    min_gap: f64,
) -> CurvatureErrors {
    struct Row {
        k: [f64; 2],
        e: [f64; 2],
        dir: Option<[f64; 2]>,
    }
    let rows: Vec<Row> = (0..mesh.num_vertices())
        .filter(|&v| include(v))
        .map(|v| {
            let x = exact(mesh.positions()[v]);
            let align = |est: Vec3, ex: Vec3| if est.dot(&ex) < 0.0 { -1.0 } else { 1.0 };
            let angle = |est: Vec3, ex: Vec3| {
                let c = est.dot(&ex).abs() / (est.norm() * ex.norm()).max(1e-300);
                c.min(1.0).acos().to_degrees()
            };
            Row {
                k: [curvature.k_max[v] - x.k_max, curvature.k_min[v] - x.k_min],
                e: [
                    align(curvature.dir_max[v], x.dir_max) * curvature.e_max[v] - x.e_max,
                    align(curvature.dir_min[v], x.dir_min) * curvature.e_min[v] - x.e_min,
                ],
                dir: (x.k_max - x.k_min > min_gap).then(|| {
                    [
                        angle(curvature.dir_max[v], x.dir_max),
                        angle(curvature.dir_min[v], x.dir_min),
                    ]
                }),
            }
        })
        .collect();
    CurvatureErrors {
        k_max: ErrorStat::of(rows.iter().map(|r| r.k[0])),
        k_min: ErrorStat::of(rows.iter().map(|r| r.k[1])),
        e_max: ErrorStat::of(rows.iter().map(|r| r.e[0])),
        e_min: ErrorStat::of(rows.iter().map(|r| r.e[1])),
        dir_max_deg: ErrorStat::of(rows.iter().filter_map(|r| r.dir.map(|d| d[0]))),
        dir_min_deg: ErrorStat::of(rows.iter().filter_map(|r| r.dir.map(|d| d[1]))),
    }
}

/// Graph distance (in edges) from every vertex to the nearest boundary or non-manifold
/// vertex (`u32::MAX` when its component has none, e.g. closed shapes); used to exclude
/// boundary-adjacent vertices from comparisons.
pub fn rings_from_boundary(mesh: &crate::mesh::TriMesh) -> Vec<u32> {
    let topo = mesh.topology();
    let seeds: Vec<u32> = (0..mesh.num_vertices() as u32)
        .filter(|&v| {
            matches!(
                topo.vertex_kind(v),
                crate::mesh::VertexKind::Boundary | crate::mesh::VertexKind::NonManifold
            )
        })
        .collect();
    rings_from(mesh, &seeds)
}

/// Graph distance (in edges) from every vertex to the nearest of `seeds` (`u32::MAX` where
/// none is reached): the k-rings around them, breadth first.
pub fn rings_from(mesh: &crate::mesh::TriMesh, seeds: &[u32]) -> Vec<u32> {
    let topo = mesh.topology();
    let mut dist = vec![u32::MAX; mesh.num_vertices()];
    for &v in seeds {
        dist[v as usize] = 0;
    }
    let mut frontier = seeds.to_vec();
    let mut level = 0;
    while !frontier.is_empty() {
        level += 1;
        let mut next = Vec::new();
        for &v in &frontier {
            for w in topo.neighbors(v) {
                if dist[w as usize] == u32::MAX {
                    dist[w as usize] = level;
                    next.push(w);
                }
            }
        }
        frontier = next;
    }
    dist
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Central difference of `k(q(s))` along a surface curve through `p` with unit tangent `t`.
    fn fd(k: impl Fn(Vec3) -> f64, project: impl Fn(Vec3) -> Vec3, p: Vec3, t: Vec3) -> f64 {
        let h = 1e-5;
        let (a, b) = (project(p + t * h), project(p - t * h));
        (k(a) - k(b)) / (a - b).norm()
    }

    #[test]
    fn ellipsoid_extremality_matches_finite_differences() {
        let (a, b, c) = (3.0, 2.0, 1.0);
        // Newton projection along the gradient onto F = 0.
        let project = |mut q: Vec3| {
            for _ in 0..20 {
                let f = q.x * q.x / (a * a) + q.y * q.y / (b * b) + q.z * q.z / (c * c) - 1.0;
                let g = Vec3::new(
                    2.0 * q.x / (a * a),
                    2.0 * q.y / (b * b),
                    2.0 * q.z / (c * c),
                );
                q -= g * (f / g.norm_squared());
            }
            q
        };
        for dir in [
            Vec3::new(0.3, 0.5, 0.8),
            Vec3::new(-0.9, 0.1, 0.2),
            Vec3::new(0.2, -0.7, -0.4),
        ] {
            let p = project(dir.normalize());
            let ex = ellipsoid(a, b, c, p);
            assert!((ex.normal.norm() - 1.0).abs() < 1e-12);
            assert!(ex.k_max > ex.k_min && ex.k_min > 0.0);
            let k_max = |q: Vec3| ellipsoid(a, b, c, q).k_max;
            let k_min = |q: Vec3| ellipsoid(a, b, c, q).k_min;
            let fd_max = fd(k_max, project, p, ex.dir_max);
            let fd_min = fd(k_min, project, p, ex.dir_min);
            assert!((fd_max - ex.e_max).abs() < 1e-6, "{fd_max} vs {}", ex.e_max);
            assert!((fd_min - ex.e_min).abs() < 1e-6, "{fd_min} vs {}", ex.e_min);
        }
        // At the end of the long axis, x = a: k = a/b² and a/c² (c < b ⇒ max along z).
        let tip = ellipsoid(a, b, c, Vec3::new(a, 0.0, 0.0));
        assert!((tip.k_max - a / (c * c)).abs() < 1e-12);
        assert!((tip.k_min - a / (b * b)).abs() < 1e-12);
        assert!(tip.dir_max.z.abs() > 1.0 - 1e-12);
    }

    #[test]
    fn waving_formulas_match_finite_differences() {
        let f = |x: f64, y: f64| x.hypot(y).cos();
        let project = |q: Vec3| Vec3::new(q.x, q.y, f(q.x, q.y));
        for &(x, y) in &[
            (0.7, 0.2),
            (-1.9, 1.1),
            (2.5, -3.0),
            (0.05, 0.0),
            (5.0, 4.0),
        ] {
            let p = project(Vec3::new(x, y, 0.0));
            let ex = waving(p);
            // Curvatures against a generic graph formula: the shape operator of z = f(x, y)
            // with normal up is −(I + ∇f∇fᵀ)^{-1} Hess f / W in our convention; compare its
            // trace and determinant (2H and K) by finite differences of f.
            let h = 1e-4;
            let fx = (f(x + h, y) - f(x - h, y)) / (2.0 * h);
            let fy = (f(x, y + h) - f(x, y - h)) / (2.0 * h);
            let fxx = (f(x + h, y) - 2.0 * f(x, y) + f(x - h, y)) / (h * h);
            let fyy = (f(x, y + h) - 2.0 * f(x, y) + f(x, y - h)) / (h * h);
            let fxy = (f(x + h, y + h) - f(x + h, y - h) - f(x - h, y + h) + f(x - h, y - h))
                / (4.0 * h * h);
            let w2 = 1.0 + fx * fx + fy * fy;
            let gauss = (fxx * fyy - fxy * fxy) / (w2 * w2);
            let mean2 = -((1.0 + fy * fy) * fxx - 2.0 * fx * fy * fxy + (1.0 + fx * fx) * fyy)
                / (w2 * w2.sqrt());
            assert!(
                (ex.k_max * ex.k_min - gauss).abs() < 1e-5,
                "K at ({x}, {y})"
            );
            assert!(
                (ex.k_max + ex.k_min - mean2).abs() < 1e-5,
                "2H at ({x}, {y})"
            );
            let k_max = |q: Vec3| waving(q).k_max;
            let k_min = |q: Vec3| waving(q).k_min;
            let fd_max = fd(k_max, project, p, ex.dir_max);
            let fd_min = fd(k_min, project, p, ex.dir_min);
            assert!((fd_max - ex.e_max).abs() < 1e-5, "{fd_max} vs {}", ex.e_max);
            assert!((fd_min - ex.e_min).abs() < 1e-5, "{fd_min} vs {}", ex.e_min);
            assert!(ex.dir_max.dot(&ex.normal).abs() < 1e-12);
        }
    }

    #[test]
    fn torus_and_cylinder_frames() {
        let (big, small) = (3.0, 1.0);
        for &(theta, phi) in &[(0.3f64, 0.0f64), (2.0, 2.5), (-1.0, -1.2)] {
            let rr = big + small * phi.cos();
            let p = Vec3::new(rr * theta.cos(), rr * theta.sin(), small * phi.sin());
            let ex = torus(big, small, p);
            assert!((ex.k_min - phi.cos() / rr).abs() < 1e-12);
            assert!(ex.dir_max.dot(&ex.normal).abs() < 1e-12);
            assert!(ex.dir_min.dot(&ex.normal).abs() < 1e-12);
            assert!(ex.dir_min.dot(&ex.dir_max).abs() < 1e-12);
            // The normal is the direction from the tube centre.
            let centre = Vec3::new(big * theta.cos(), big * theta.sin(), 0.0);
            assert!((ex.normal - (p - centre) / small).norm() < 1e-12);
        }
        let c = cylinder(2.0, Vec3::new(0.0, 2.0, 1.0));
        assert!((c.normal - Vec3::y()).norm() < 1e-15 && (c.dir_max - -Vec3::x()).norm() < 1e-15);
    }
}
