//! Properties both curvature estimators must have, on generated shapes with known answers
//! (`crestline::shapes::exact` holds the exact values and their derivations).
//!
//! Tolerances are set from measured errors (see `BENCHMARKS.md`, "Curvature") with a margin
//! of about 1.5–2×, tight enough that a sign error, a missing factor or a wrong direction
//! fails. Where a test excludes vertices (near boundaries, near umbilics) it says why.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::f64::consts::PI;

use crestline::curvature::{
    CubicFitOptions, Curvature, CurvatureOptions, Estimator, PrincipalSelection,
    ShapeOperatorOptions, cubic_fit, estimate, shape_operator,
};
use crestline::shapes::exact::{self, CurvatureErrors, ExactCurvature};
use crestline::shapes::{self, GridPattern};
use crestline::{TriMesh, Vec3};

fn so(m: &TriMesh) -> Curvature {
    estimate(
        m,
        &CurvatureOptions::DEFAULT.with_estimator(Estimator::ShapeOperator),
    )
    .unwrap()
}

fn cf(m: &TriMesh) -> Curvature {
    estimate(
        m,
        &CurvatureOptions::DEFAULT.with_estimator(Estimator::CubicFit),
    )
    .unwrap()
}

/// The cubic fit without YBS's pre-smoothing p → p' (which stops e from converging: it is a
/// valence-dependent umbrella step).
fn cf_raw(m: &TriMesh) -> Curvature {
    cubic_fit(m, &CubicFitOptions::DEFAULT.with_presmooth(false)).unwrap()
}

/// Errors at vertices at least `margin` rings from the boundary and, when `min_gap > 0`,
/// where the exact principal curvatures differ by more than `min_gap` (the principal
/// directions, and with them the labels of e_max/e_min, are undefined at umbilics).
fn errors(
    m: &TriMesh,
    c: &Curvature,
    ex: impl Fn(Vec3) -> ExactCurvature,
    margin: u32,
    min_gap: f64,
) -> CurvatureErrors {
    let dist = exact::rings_from_boundary(m);
    let keep = |v: usize| {
        dist[v] >= margin && {
            let x = ex(m.positions()[v]);
            min_gap <= 0.0 || x.k_max - x.k_min > min_gap
        }
    };
    exact::compare(m, c, &ex, keep, min_gap.max(0.0))
}

fn assert_all_finite(c: &Curvature, n: usize) {
    assert_eq!(c.len(), n);
    for v in 0..n {
        for x in [c.k_max[v], c.k_min[v], c.e_max[v], c.e_min[v]] {
            assert!(x.is_finite(), "vertex {v}: {x}");
        }
        assert!(c.k_max[v] >= c.k_min[v], "vertex {v}");
        for d in [c.dir_max[v], c.dir_min[v], c.normals[v]] {
            assert!((d.norm() - 1.0).abs() < 1e-9, "vertex {v}: {d}");
        }
    }
}

// ---------------------------------------------------------------------------------------
// Sphere: k = 1/r everywhere, e = 0.

#[test]
fn sphere_curvature_is_one_over_r() {
    let r = 2.0;
    let ex = |p| exact::sphere(r, p);
    // icosphere(4): shape operator 0.073 max (at the 12 valence-5 vertices, which keep a
    // ~15% error under refinement), 0.006 rms; cubic fit 0.018 max, 0.005 rms (0.002 without
    // p → p'). e: shape operator 0.18 max / 0.033 rms (growing at the valence-5 vertices),
    // cubic fit 0.15 / 0.06.
    let m = shapes::icosphere(r, 4);
    let e = errors(&m, &so(&m), ex, 0, 0.0);
    assert!(e.k_max.max < 0.1 && e.k_min.max < 0.1, "{e:?}");
    assert!(e.k_max.rms < 0.01 && e.k_min.rms < 0.01, "{e:?}");
    assert!(e.e_max.rms < 0.06 && e.e_min.rms < 0.06, "{e:?}");
    let e = errors(&m, &cf(&m), ex, 0, 0.0);
    assert!(e.k_max.max < 0.03 && e.k_min.max < 0.03, "{e:?}");
    assert!(e.e_max.max < 0.25 && e.e_min.max < 0.25, "{e:?}");
    let e = errors(&m, &cf_raw(&m), ex, 0, 0.0);
    assert!(e.k_max.max < 0.004 && e.k_min.max < 0.004, "{e:?}");
    assert!(e.e_max.max < 0.01 && e.e_min.max < 0.01, "{e:?}");
}

#[test]
fn sphere_error_shrinks_under_subdivision() {
    let ex = |p| exact::sphere(2.0, p);
    let (coarse, fine) = (shapes::icosphere(2.0, 3), shapes::icosphere(2.0, 4));
    // Shape operator: rms 0.012 → 0.006; the max stays at the valence-5 vertices (0.072).
    let (a, b) = (
        errors(&coarse, &so(&coarse), ex, 0, 0.0),
        errors(&fine, &so(&fine), ex, 0, 0.0),
    );
    assert!(b.k_max.rms < 0.7 * a.k_max.rms, "{a:?}\n{b:?}");
    // Cubic fit: max 0.026 → 0.018 (0.006 → 0.002 without p → p').
    let (a, b) = (
        errors(&coarse, &cf(&coarse), ex, 0, 0.0),
        errors(&fine, &cf(&fine), ex, 0, 0.0),
    );
    assert!(b.k_max.max < 0.8 * a.k_max.max, "{a:?}\n{b:?}");
    let (a, b) = (
        errors(&coarse, &cf_raw(&coarse), ex, 0, 0.0),
        errors(&fine, &cf_raw(&fine), ex, 0, 0.0),
    );
    assert!(b.k_max.max < 0.5 * a.k_max.max, "{a:?}\n{b:?}");
}

// ---------------------------------------------------------------------------------------
// Cylinder: k_max = 1/r around, k_min = 0 along the axis, e = 0.

#[test]
fn cylinder_shape_operator_on_a_regular_grid_is_exact() {
    // Uniform diagonals (valence 6): only the vertical edges bend, by β = 2π/n, each with
    // H_e = 2h sin(π/n) (h the row height) and w the horizontal tangent; the other edges lie
    // in one chord plane. A vertex has two vertical edges, so S(p) = 2h sin(π/n) w wᵀ, and
    // its six faces have area ½ · 2r sin(π/n) · h each: 3/area(star) · 2h sin(π/n) = 1/r
    // exactly, k_min = 0 exactly, dir_min = ±z.
    let r = 1.5;
    let m = shapes::cylinder_with(r, 4.0, 40, 20, GridPattern::Uniform);
    let c = so(&m);
    let topo = m.topology();
    for v in 0..m.num_vertices() {
        if topo.is_boundary_vertex(v as u32) {
            continue;
        }
        assert!((c.k_max[v] - 1.0 / r).abs() < 1e-12, "{v}: {}", c.k_max[v]);
        assert!(c.k_min[v].abs() < 1e-12, "{v}: {}", c.k_min[v]);
        assert!(c.dir_min[v].z.abs() > 1.0 - 1e-12);
        assert!(c.e_max[v].abs() < 1e-9 && c.e_min[v].abs() < 1e-9);
    }
    // Boundary vertices take their interior neighbours' operators (the two neighbours off to
    // the side are turned by 2π/n, hence the small deficit).
    let e = errors(&m, &c, |p| exact::cylinder(r, p), 0, 0.0);
    assert!(e.k_max.max < 0.02 / r && e.dir_min_deg.max < 1e-6, "{e:?}");
}

#[test]
fn cylinder_shape_operator_on_a_checkerboard_grid_is_off_by_the_star_areas() {
    // Alternating diagonals: vertices of valence 4 and 8 alternate. Only the two vertical
    // edges at a vertex bend (as above), but the star has 4 or 8 faces of area r sin(π/n) h:
    // 3 · 2h sin(π/n) / (4 r sin(π/n) h) = 1.5/r and 3 · 2h sin(π/n) / (8 r sin(π/n) h) =
    // 0.75/r. The HPW operator is consistent in the integrated sense (the area-weighted mean
    // is 1/r) but not pointwise on such meshes; this pins that documented limit down.
    let r = 1.0;
    let m = shapes::cylinder(r, 4.0, 32, 20);
    let c = so(&m);
    let topo = m.topology();
    for v in 0..m.num_vertices() as u32 {
        if topo.is_boundary_vertex(v) {
            continue;
        }
        let expected = match topo.vertex_faces(v).len() {
            4 => 1.5 / r,
            8 => 0.75 / r,
            d => panic!("valence {d}"),
        };
        assert!((c.k_max[v as usize] - expected).abs() < 1e-12);
        assert!(c.k_min[v as usize].abs() < 1e-12);
    }
}

#[test]
fn cylinder_cubic_fit() {
    let r = 1.0;
    let ex = |p| exact::cylinder(r, p);
    for pattern in [GridPattern::Alternating, GridPattern::Uniform] {
        let m = shapes::cylinder_with(r, 4.0, 64, 40, pattern);
        // Three rings from the boundary: with p → p' on, the boundary rows (which stay put)
        // bias the two rings next to them. Measured: k_max 0.04 / 0.01, k_min 0.05.
        let e = errors(&m, &cf(&m), ex, 3, 0.0);
        assert!(
            e.k_max.max < 0.06 && e.k_min.max < 0.08,
            "{pattern:?} {e:?}"
        );
        assert!(
            e.dir_max_deg.max < 0.5 && e.dir_min_deg.max < 0.5,
            "{pattern:?} {e:?}"
        );
        // Without p → p' (measured k 0.005, e 0.013 at the boundary rows, which take their
        // interior neighbours' values): all vertices, boundary included.
        let e = errors(&m, &cf_raw(&m), ex, 0, 0.0);
        assert!(
            e.k_max.max < 0.01 && e.k_min.max < 0.01,
            "{pattern:?} {e:?}"
        );
        assert!(
            e.e_max.max < 0.03 && e.e_min.max < 0.03,
            "{pattern:?} {e:?}"
        );
        assert!(e.dir_min_deg.max < 0.5, "{pattern:?} {e:?}");
    }
}

#[test]
fn largest_magnitude_rule_is_ambiguous_on_cylinders() {
    // HPW's literal rule (two eigenvalues of largest |λ| of the 3×3 operator) has to choose
    // between the axis and the normal, both with eigenvalue ≈ 0: it reports the normal as
    // dir_min at some vertices. The default tangent-plane restriction never does.
    let m = shapes::cylinder_with(1.0, 4.0, 32, 20, GridPattern::Uniform);
    let literal = shape_operator(
        &m,
        &ShapeOperatorOptions::DEFAULT.with_selection(PrincipalSelection::LargestMagnitude),
    );
    let default = shape_operator(&m, &ShapeOperatorOptions::DEFAULT);
    let off_axis = |c: &Curvature| {
        (0..m.num_vertices())
            .filter(|&v| c.dir_min[v].z.abs() < 0.99)
            .count()
    };
    assert!(off_axis(&literal) > 0);
    assert_eq!(off_axis(&default), 0);
    // Where it is not ambiguous, the two rules agree (ellipsoid: no principal curvature ≈ 0).
    let m = shapes::ellipsoid(2.0, 1.5, 1.0, 3);
    let literal = shape_operator(
        &m,
        &ShapeOperatorOptions::DEFAULT.with_selection(PrincipalSelection::LargestMagnitude),
    );
    let default = shape_operator(&m, &ShapeOperatorOptions::DEFAULT);
    for v in 0..m.num_vertices() {
        assert!((literal.k_max[v] - default.k_max[v]).abs() < 1e-3 * default.k_max[v]);
        assert!((literal.k_min[v] - default.k_min[v]).abs() < 1e-3 * default.k_max[v]);
    }
}

// ---------------------------------------------------------------------------------------
// Triaxial ellipsoid: exact values from the implicit form (shapes::exact::ellipsoid).

#[test]
fn ellipsoid_curvatures_and_directions() {
    let (a, b, c) = (2.0, 1.5, 1.0);
    let ex = |p| exact::ellipsoid(a, b, c, p);
    let (coarse, fine) = (shapes::ellipsoid(a, b, c, 4), shapes::ellipsoid(a, b, c, 5));
    // Directions only where k_max − k_min > 0.05 (the ellipsoid has four umbilics).
    // Measured (subdivision 4 → 5): shape operator k rms 0.013 → 0.006 (max 0.23 at the
    // valence-5 vertices, not shrinking), directions max 3.8° → 3.7°, rms 0.40° → 0.19°;
    // cubic fit k rms 0.015 → 0.009, max 0.068 → 0.064, directions max 2.3° → 1.8°.
    for (name, estimator) in [
        ("shape operator", so as fn(&TriMesh) -> Curvature),
        ("cubic fit", cf),
    ] {
        let ec = errors(&coarse, &estimator(&coarse), ex, 0, 0.05);
        let ef = errors(&fine, &estimator(&fine), ex, 0, 0.05);
        assert!(ef.k_max.rms < 0.02 && ef.k_min.rms < 0.02, "{name} {ef:?}");
        assert!(ef.k_max.max < 0.35 && ef.k_min.max < 0.15, "{name} {ef:?}");
        assert!(
            ef.dir_max_deg.max < 6.0 && ef.dir_min_deg.max < 6.0,
            "{name} {ef:?}"
        );
        assert!(ef.k_max.rms < 0.75 * ec.k_max.rms, "{name}\n{ec:?}\n{ef:?}");
        assert!(
            ef.dir_max_deg.rms < 0.75 * ec.dir_max_deg.rms,
            "{name}\n{ec:?}\n{ef:?}"
        );
    }
}

#[test]
fn ellipsoid_extremalities_correlate_with_the_exact_ones() {
    // The ellipsoid's e are O(1) (up to ≈ 3 at the ends of the long axis). On this
    // irregular, anisotropic mesh neither estimator's e converges pointwise (shape operator:
    // eq. 4 differentiates non-convergent point values; cubic fit: the O(h) error of the Max
    // normals enters e as O(1/h)), so check that e has the right sign and size on the whole:
    // relative rms error well below 1 (a sign error gives ≈ 2).
    let (a, b, c) = (2.0, 1.5, 1.0);
    let m = shapes::ellipsoid(a, b, c, 4);
    let exact: Vec<ExactCurvature> = m
        .positions()
        .iter()
        .map(|&p| exact::ellipsoid(a, b, c, p))
        .collect();
    for (name, curv, bound) in [("shape operator", so(&m), 0.3), ("cubic fit", cf(&m), 0.6)] {
        let (mut err, mut norm) = (0.0, 0.0);
        for (v, x) in exact.iter().enumerate() {
            if x.k_max - x.k_min < 0.05 {
                continue;
            }
            let s = curv.dir_max[v].dot(&x.dir_max).signum();
            err += (s * curv.e_max[v] - x.e_max).powi(2);
            norm += x.e_max.powi(2);
        }
        let relative = (err / norm).sqrt();
        assert!(
            relative < bound,
            "{name}: relative rms error of e_max {relative}"
        );
    }
}

// ---------------------------------------------------------------------------------------
// Torus: k = 1/r across the tube, cos φ/(R + r cos φ) along it, e = 0 (a Dupin cyclide).

#[test]
fn torus_curvatures_directions_and_zero_extremality() {
    let ex = |p| exact::torus(3.0, 1.0, p);
    let (coarse, fine) = (
        shapes::torus_with(3.0, 1.0, 48, 16, GridPattern::Uniform),
        shapes::torus_with(3.0, 1.0, 96, 32, GridPattern::Uniform),
    );
    // Measured (48×16 → 96×32): shape operator k 0.025 → 0.006 max (O(h²)), e 0.013 →
    // 0.004; cubic fit k_max 0.117 → 0.028 (the O(h²) shrinkage of p → p'), e 0.012 → 0.003.
    for (name, estimator) in [
        ("shape operator", so as fn(&TriMesh) -> Curvature),
        ("cubic fit", cf),
    ] {
        let ec = errors(&coarse, &estimator(&coarse), ex, 0, 0.0);
        let ef = errors(&fine, &estimator(&fine), ex, 0, 0.0);
        assert!(ef.k_max.max < 0.05 && ef.k_min.max < 0.02, "{name} {ef:?}");
        assert!(ef.e_max.max < 0.01 && ef.e_min.max < 0.01, "{name} {ef:?}");
        assert!(
            ef.dir_max_deg.max < 0.5 && ef.dir_min_deg.max < 0.5,
            "{name} {ef:?}"
        );
        assert!(ef.k_max.max < 0.5 * ec.k_max.max, "{name}\n{ec:?}\n{ef:?}");
        assert!(ef.e_max.max < 0.5 * ec.e_max.max, "{name}\n{ec:?}\n{ef:?}");
    }
}

// ---------------------------------------------------------------------------------------
// Waving surface z = cos ρ: κ_r = cos ρ/(1 + sin²ρ)^{3/2} (radial), κ_c = sin ρ/(ρ√(1 +
// sin²ρ)) (around), e_r = −2 sin ρ (2 − sin²ρ)/(1 + sin²ρ)³ along the outward radial
// direction, 0 around (derivation in shapes::exact).

#[test]
fn waving_surface_extremalities_converge_on_a_regular_grid() {
    // Valence-6 grid over [−6, 6]², three rings from the boundary; e and directions where
    // |κ_r − κ_c| > 0.05: on the circles where κ_r = κ_c the families swap and e_max, e_min
    // exchange labels (measured errors there ≈ 0.34 at every resolution, for both methods).
    let ex = exact::waving;
    let coarse = shapes::waving_surface_with(6.0, 60, GridPattern::Uniform);
    let fine = shapes::waving_surface_with(6.0, 120, GridPattern::Uniform);
    // Shape operator (60 → 120): k max 0.031 → 0.008, e max 0.16 → 0.047: O(h²).
    let (a, b) = (
        errors(&coarse, &so(&coarse), ex, 3, 0.05),
        errors(&fine, &so(&fine), ex, 3, 0.05),
    );
    assert!(
        b.k_max.max < 0.015 && b.e_max.max < 0.08 && b.e_min.max < 0.08,
        "{b:?}"
    );
    assert!(b.k_max.max < 0.5 * a.k_max.max, "{a:?}\n{b:?}");
    assert!(
        b.e_max.max < 0.5 * a.e_max.max && b.e_min.max < 0.5 * a.e_min.max,
        "{a:?}\n{b:?}"
    );
    assert!(b.dir_max_deg.max < 1.0, "{b:?}");
    // Cubic fit (60 → 120): k max 0.045 → 0.012, e max 0.18 → 0.11 (e has an O(1) floor
    // of ≈ 0.09 at finer grids: the O(h²) error of the Max normals, divided by h²).
    let (a, b) = (
        errors(&coarse, &cf(&coarse), ex, 3, 0.05),
        errors(&fine, &cf(&fine), ex, 3, 0.05),
    );
    assert!(
        b.k_max.max < 0.02 && b.e_max.max < 0.17 && b.e_min.max < 0.19,
        "{b:?}"
    );
    assert!(b.k_max.max < 0.5 * a.k_max.max, "{a:?}\n{b:?}");
    assert!(
        b.e_max.max < 0.8 * a.e_max.max && b.e_min.max < 0.8 * a.e_min.max,
        "{a:?}\n{b:?}"
    );
    assert!(b.dir_max_deg.max < 1.5, "{b:?}");
}

#[test]
fn waving_disk_as_in_ybs() {
    // YBS's r(u, v) = [u cos v, u sin v, cos u], u ≤ 3π, meshed by concentric rings (nearly
    // equilateral, valence 6 except along six seams); 28 rings = 4704 triangles (< 5K as in
    // YBS), 56 rings = 18816.
    let ex = exact::waving;
    let (coarse, fine) = (
        shapes::waving_disk(3.0 * PI, 28),
        shapes::waving_disk(3.0 * PI, 56),
    );
    // Shape operator: e rms 0.090 → 0.026, k rms 0.012 → 0.003 (maxima sit on the seams).
    let (a, b) = (
        errors(&coarse, &so(&coarse), ex, 3, 0.05),
        errors(&fine, &so(&fine), ex, 3, 0.05),
    );
    assert!(
        b.e_max.rms < 0.5 * a.e_max.rms && b.e_min.rms < 0.5 * a.e_min.rms,
        "{a:?}\n{b:?}"
    );
    assert!(b.k_max.rms < 0.5 * a.k_max.rms, "{a:?}\n{b:?}");
    // Cubic fit without p → p': e max 0.25 → 0.12, k max 0.064 → 0.019 (O(h)).
    let (a, b) = (
        errors(&coarse, &cf_raw(&coarse), ex, 3, 0.05),
        errors(&fine, &cf_raw(&fine), ex, 3, 0.05),
    );
    assert!(
        b.e_max.max < 0.65 * a.e_max.max && b.e_min.max < 0.8 * a.e_min.max,
        "{a:?}\n{b:?}"
    );
    assert!(b.k_max.max < 0.5 * a.k_max.max, "{a:?}\n{b:?}");
    // With p → p' (YBS as published): k converges (0.105 → 0.048) but e does not (0.40 →
    // 0.39 max, the seams' valence changes move p' differently); bound it at YBS's level.
    let (a, b) = (
        errors(&coarse, &cf(&coarse), ex, 3, 0.05),
        errors(&fine, &cf(&fine), ex, 3, 0.05),
    );
    assert!(b.k_max.max < 0.6 * a.k_max.max, "{a:?}\n{b:?}");
    assert!(a.e_max.max < 0.6 && a.e_min.max < 0.6, "{a:?}");
}

#[test]
fn extremality_is_the_derivative_along_the_stored_direction() {
    // Sign consistency: wherever the exact e is clearly non-zero and the directions are
    // well defined, sign(e) must equal the sign of the exact derivative of k along the
    // *stored* direction, ⟨∇k, dir⟩ = e_exact · ⟨dir_exact, dir⟩. A convention error (e
    // along a different orientation than dir) fails this at about half the vertices.
    let m = shapes::waving_surface_with(6.0, 100, GridPattern::Uniform);
    let dist = exact::rings_from_boundary(&m);
    for (name, c) in [("shape operator", so(&m)), ("cubic fit", cf(&m))] {
        let mut checked = 0;
        for (v, &rings) in dist.iter().enumerate() {
            let x = exact::waving(m.positions()[v]);
            if rings < 3 || x.k_max - x.k_min < 0.1 {
                continue;
            }
            for (e, e_exact, d, d_exact) in [
                (c.e_max[v], x.e_max, c.dir_max[v], x.dir_max),
                (c.e_min[v], x.e_min, c.dir_min[v], x.dir_min),
            ] {
                let along = e_exact * d_exact.dot(&d);
                if along.abs() > 0.25 {
                    assert_eq!(
                        e.signum(),
                        along.signum(),
                        "{name} vertex {v}: {e} vs {along}"
                    );
                    checked += 1;
                }
            }
        }
        assert!(checked > 1000, "{name}: {checked}");
    }
}

// ---------------------------------------------------------------------------------------
// Invariance.

/// A rotation (about an oblique axis) and translation.
fn rigid(p: Vec3) -> Vec3 {
    let axis = nalgebra::Unit::new_normalize(Vec3::new(0.3, -0.5, 0.8));
    let rot = nalgebra::Rotation3::from_axis_angle(&axis, 1.1);
    rot * p + Vec3::new(10.0, -3.0, 7.5)
}

fn rotate(d: Vec3) -> Vec3 {
    rigid(d) - rigid(Vec3::zeros())
}

fn test_meshes() -> Vec<TriMesh> {
    vec![
        shapes::ellipsoid(2.0, 1.5, 1.0, 3),
        shapes::waving_disk(3.0 * PI, 12),
        shapes::torus(3.0, 1.0, 24, 12),
    ]
}

type Estimate = fn(&TriMesh) -> Curvature;

fn estimators() -> Vec<(&'static str, Estimate)> {
    vec![
        ("shape operator", so),
        ("cubic fit", cf),
        ("cubic fit raw", cf_raw),
        ("cubic fit k=2", |m| {
            cubic_fit(m, &CubicFitOptions::DEFAULT.with_rings(2)).unwrap()
        }),
    ]
}

#[test]
fn invariant_under_rigid_motions() {
    for m in test_meshes() {
        let moved = m
            .with_positions(m.positions().iter().map(|&p| rigid(p)).collect())
            .unwrap();
        for (name, estimator) in estimators() {
            let (a, b) = (estimator(&m), estimator(&moved));
            let scale = a.k_max.iter().fold(0.0f64, |s, k| s.max(k.abs())).max(1.0);
            for v in 0..m.num_vertices() {
                assert!((a.k_max[v] - b.k_max[v]).abs() < 1e-8 * scale, "{name} {v}");
                assert!((a.k_min[v] - b.k_min[v]).abs() < 1e-8 * scale, "{name} {v}");
                assert!(
                    (rotate(a.normals[v]) - b.normals[v]).norm() < 1e-8,
                    "{name} {v}"
                );
                // Directions up to sign (the tangent frame is not equivariant), and e with
                // the same sign flip; skip near-umbilic vertices where directions are
                // arbitrary.
                if a.k_max[v] - a.k_min[v] < 1e-3 * scale {
                    continue;
                }
                for (da, db, ea, eb) in [
                    (a.dir_max[v], b.dir_max[v], a.e_max[v], b.e_max[v]),
                    (a.dir_min[v], b.dir_min[v], a.e_min[v], b.e_min[v]),
                ] {
                    let s = rotate(da).dot(&db);
                    assert!((s.abs() - 1.0).abs() < 1e-6, "{name} {v}: {s}");
                    assert!(
                        (ea * s.signum() - eb).abs() < 1e-6 * scale.powi(2),
                        "{name} {v}"
                    );
                }
            }
        }
    }
}

#[test]
fn uniform_scaling_scales_k_by_one_over_s_and_e_by_one_over_s_squared() {
    for s in [1e-6, 0.37, 1e6] {
        for m in test_meshes() {
            let scaled = m
                .with_positions(m.positions().iter().map(|&p| p * s).collect())
                .unwrap();
            for (name, estimator) in estimators() {
                let (a, b) = (estimator(&m), estimator(&scaled));
                let kscale = a.k_max.iter().fold(0.0f64, |x, k| x.max(k.abs())).max(1.0);
                let escale = a.e_max.iter().fold(0.0f64, |x, e| x.max(e.abs())).max(1.0);
                for v in 0..m.num_vertices() {
                    assert!(
                        (a.k_max[v] / s - b.k_max[v]).abs() < 1e-7 * kscale / s,
                        "{name} {s} {v}"
                    );
                    assert!(
                        (a.k_min[v] / s - b.k_min[v]).abs() < 1e-7 * kscale / s,
                        "{name} {s} {v}"
                    );
                    if a.k_max[v] - a.k_min[v] < 1e-3 * kscale {
                        continue;
                    }
                    let sign = a.dir_max[v].dot(&b.dir_max[v]).signum();
                    assert!(
                        (sign * a.e_max[v] / (s * s) - b.e_max[v]).abs() < 1e-6 * escale / (s * s),
                        "{name} {s} {v}"
                    );
                }
            }
        }
    }
}

// ---------------------------------------------------------------------------------------
// Awkward meshes: never NaN, never a panic.

fn awkward_meshes() -> Vec<(&'static str, TriMesh)> {
    let m = |p: Vec<[f64; 3]>, f: Vec<[u32; 3]>| TriMesh::from_arrays(p, f).unwrap();
    let square = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.2],
        [0.0, 1.0, 0.0],
    ];
    let mut with_isolated = square.clone();
    with_isolated.push([5.0, 5.0, 5.0]);
    // A tetrahedron plus a lone triangle far away plus an unreferenced vertex.
    let mut components = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [9.0, 9.0, 9.0],
        [10.0, 9.0, 9.0],
        [9.0, 10.0, 9.0],
        [-4.0, 2.0, 0.0],
    ];
    let components_faces = vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3], [4, 5, 6]];
    // An octahedron with one flipped face.
    let octa = vec![
        [1.0, 0.0, 0.0],
        [-1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, -1.0, 0.0],
        [0.0, 0.0, 1.0],
        [0.0, 0.0, -1.0],
    ];
    let octa_faces = vec![
        [0, 2, 4],
        [1, 2, 4],
        [1, 3, 4],
        [3, 0, 4],
        [2, 0, 5],
        [1, 2, 5],
        [3, 1, 5],
        [0, 3, 5],
    ];
    // A sliver next to a normal triangle, and a folded pair (normals opposite).
    let sliver = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.5, 1e-9, 0.0],
        [0.5, -1.0, 0.0],
    ];
    let folded = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.5, 1.0, 0.0],
        [0.5, 1.0, 1e-12],
    ];
    components.push([0.0; 3]); // a second unreferenced vertex
    let mut out = vec![
        ("single triangle", m(square[..3].to_vec(), vec![[0, 1, 2]])),
        (
            "two triangles",
            m(square.clone(), vec![[0, 1, 2], [0, 2, 3]]),
        ),
        (
            "isolated vertex",
            m(with_isolated, vec![[0, 1, 2], [0, 2, 3]]),
        ),
        ("no faces", m(square.clone(), vec![])),
        ("empty", m(vec![], vec![])),
        (
            "bowtie",
            m(
                vec![
                    [0.0, 0.0, 0.0],
                    [1.0, 0.0, 0.0],
                    [1.0, 1.0, 0.0],
                    [-1.0, 0.0, 0.3],
                    [-1.0, -1.0, 0.0],
                ],
                vec![[0, 1, 2], [0, 3, 4]],
            ),
        ),
        (
            "fin (non-manifold edge)",
            m(
                vec![
                    [0.0, 0.0, 0.0],
                    [1.0, 0.0, 0.0],
                    [0.5, 1.0, 0.0],
                    [0.5, -1.0, 0.0],
                    [0.5, 0.0, 1.0],
                ],
                vec![[0, 1, 2], [1, 0, 3], [0, 1, 4]],
            ),
        ),
        ("components", m(components, components_faces)),
        ("flipped face", m(octa, octa_faces)),
        ("sliver", m(sliver, vec![[0, 1, 2], [1, 0, 3]])),
        ("folded", m(folded, vec![[0, 1, 2], [1, 0, 3]])),
        ("open cylinder", shapes::cylinder(1.0, 1.0, 6, 1)),
        ("coarse waving grid", shapes::waving_surface(5.0, 3)),
    ];
    // Collapse a tetrahedron's positions onto a plane after construction: faces stay, areas
    // and normals may vanish.
    let tet = shapes::icosphere(1.0, 0);
    let flat = tet
        .with_positions(
            tet.positions()
                .iter()
                .map(|p| Vec3::new(p.x, p.y, 0.0))
                .collect(),
        )
        .unwrap();
    out.push(("flattened icosahedron", flat));
    let point = tet
        .with_positions(vec![Vec3::zeros(); tet.num_vertices()])
        .unwrap();
    out.push(("collapsed to a point", point));
    out
}

#[test]
fn no_nan_on_awkward_meshes() {
    for (name, m) in awkward_meshes() {
        for rings in 1..=4 {
            for presmooth in [true, false] {
                for boundary in [true, false] {
                    let c = cubic_fit(
                        &m,
                        &CubicFitOptions::DEFAULT
                            .with_rings(rings)
                            .with_presmooth(presmooth)
                            .with_boundary_from_interior(boundary),
                    )
                    .unwrap();
                    assert_all_finite(&c, m.num_vertices());
                }
            }
        }
        for selection in [
            PrincipalSelection::TangentPlane,
            PrincipalSelection::LargestMagnitude,
        ] {
            for boundary in [true, false] {
                let c = shape_operator(
                    &m,
                    &ShapeOperatorOptions::DEFAULT
                        .with_selection(selection)
                        .with_boundary_from_interior(boundary),
                );
                assert_all_finite(&c, m.num_vertices());
            }
        }
        let _ = name;
    }
}

#[test]
fn fallbacks_are_counted() {
    let meshes = awkward_meshes();
    let get = |n: &str| &meshes.iter().find(|(name, _)| *name == n).unwrap().1;
    // A lone triangle: no interior edge (shape operator), two neighbours per vertex (cubic
    // fit: quadratic fallback at best).
    let tri = get("single triangle");
    assert_eq!(so(tri).fallback_vertices, 3);
    assert_eq!(cf(tri).fallback_vertices, 3);
    // The unreferenced vertex is a fallback for both; the rest is estimated.
    let iso = get("isolated vertex");
    let c = so(iso);
    assert_eq!((c.k_max[4], c.e_max[4]), (0.0, 0.0));
    assert!(c.fallback_vertices >= 1);
    // Tetrahedron + lone triangle + two unreferenced vertices. Shape operator: the lone
    // triangle and the unreferenced vertices, 3 + 2. Cubic fit: on the tetrahedron the
    // normals of vertices 1, 2, 3 make obtuse angles with each other (cos = −1/3), so YBS's
    // rule leaves each of them one usable neighbour and no fit: 3 + 3 + 2.
    let comp = get("components");
    assert_eq!(so(comp).fallback_vertices, 3 + 2);
    assert_eq!(cf(comp).fallback_vertices, 3 + 3 + 2);
    // A boundary vertex with fewer than two interior neighbours cannot reach seven equations
    // in its 1-ring (boundary neighbours give heights only), so the ring grows and counts as
    // a fallback — unless the vertex takes its interior neighbours' tensor, an estimate.
    let g = get("coarse waving grid");
    let own = cubic_fit(
        g,
        &CubicFitOptions::DEFAULT.with_boundary_from_interior(false),
    )
    .unwrap();
    let boundary = (0..g.num_vertices() as u32)
        .filter(|&v| g.topology().is_boundary_vertex(v))
        .count();
    assert!(own.fallback_vertices > 0 && own.fallback_vertices <= boundary);
    // Only the two corners whose diagonal does not reach the interior (checkerboard) have no
    // interior neighbour to borrow from.
    assert_eq!(cf(g).fallback_vertices, 2);
}

#[test]
fn invalid_options_are_errors() {
    let m = shapes::icosphere(1.0, 1);
    let opts = CurvatureOptions::DEFAULT
        .with_estimator(Estimator::CubicFit)
        .with_rings(0);
    assert!(estimate(&m, &opts).is_err());
    let opts = CurvatureOptions::DEFAULT
        .with_estimator(Estimator::CubicFit)
        .with_rings(9);
    assert!(estimate(&m, &opts).is_err());
    // The other estimators ignore the cubic-fit options.
    let opts = CurvatureOptions::DEFAULT.with_rings(0);
    assert!(estimate(&m, &opts).is_ok());
}

#[test]
fn regular_triangles_on_analytic_shapes() {
    // Away from umbilics the directions vary slowly, so (almost) every triangle is regular;
    // on the torus (no umbilic) all of them.
    use crestline::extremality::triangle_regularity;
    let m = shapes::torus_with(3.0, 1.0, 48, 16, GridPattern::Uniform);
    for c in [so(&m), cf(&m)] {
        let r = triangle_regularity(&m, &c);
        assert_eq!((r.singular_max, r.singular_min), (0, 0));
    }
    // The sphere is all umbilic: directions are noise and many triangles are singular.
    let m = shapes::icosphere(1.0, 3);
    let r = triangle_regularity(&m, &so(&m));
    assert!(
        r.singular_max_fraction() > 0.05,
        "{}",
        r.singular_max_fraction()
    );
}

// ---------------------------------------------------------------------------------------
// The default estimator (jet fit) on irregular triangulations: issue 19's targets, k RMS
// ≤ 3% of max |k| and e RMS ≤ 0.25 of the 95th percentile of |e|, on meshes made here (not
// the public quality cases): every third triangle split at its centroid (valence 3 next to
// valence 8 to 12, slivers) and all vertices moved by up to 0.3 edge lengths, then put back
// on the surface.

/// A deterministic pseudo-random number in [−1, 1] for `(i, k)`.
fn jitter(i: usize, k: usize) -> f64 {
    let mut z = (i as u64 * 3 + k as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 31)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z ^= z >> 29;
    (z >> 11) as f64 / (1u64 << 52) as f64 - 1.0
}

fn irregular(mesh: &TriMesh, project: impl Fn(Vec3) -> Vec3) -> TriMesh {
    let step = 0.3 * crestline::mesh::mean_edge_length(mesh);
    let mut points: Vec<Vec3> = mesh.positions().to_vec();
    let mut faces = Vec::new();
    for (f, &[a, b, c]) in mesh.faces().iter().enumerate() {
        if f % 3 == 0 {
            let centre = points.len() as u32;
            let [pa, pb, pc] = [a, b, c].map(|v| mesh.positions()[v as usize]);
            points.push((pa + pb + pc) / 3.0);
            faces.extend([[a, b, centre], [b, c, centre], [c, a, centre]]);
        } else {
            faces.push([a, b, c]);
        }
    }
    let positions = points
        .iter()
        .enumerate()
        .map(|(i, &p)| {
            let offset = Vec3::new(jitter(i, 0), jitter(i, 1), jitter(i, 2)) * step;
            let q = project(p + offset);
            [q.x, q.y, q.z]
        })
        .collect();
    TriMesh::from_arrays(positions, faces).unwrap()
}

/// Relative errors of the default estimator: (k RMS / max |k|, e RMS / p95 |e|), e compared
/// where the exact principal curvatures differ by more than 5% of max |k|.
fn relative_errors(m: &TriMesh, ex: impl Fn(Vec3) -> ExactCurvature) -> (f64, f64) {
    let c = estimate(m, &CurvatureOptions::DEFAULT).unwrap();
    let exact: Vec<ExactCurvature> = m.positions().iter().map(|&p| ex(p)).collect();
    let k_scale = exact
        .iter()
        .map(|x| x.k_max.abs().max(x.k_min.abs()))
        .fold(0.0, f64::max);
    let mut e_abs: Vec<f64> = exact
        .iter()
        .flat_map(|x| [x.e_max.abs(), x.e_min.abs()])
        .collect();
    e_abs.sort_by(f64::total_cmp);
    let e_scale = e_abs[e_abs.len() * 95 / 100].max(1e-9);
    let all = exact::compare(m, &c, &ex, |_| true, 0.0);
    let gap = exact::compare(
        m,
        &c,
        &ex,
        |v| exact[v].k_max - exact[v].k_min > 0.05 * k_scale,
        0.0,
    );
    let k = all.k_max.rms.max(all.k_min.rms) / k_scale;
    let e = gap.e_max.rms.max(gap.e_min.rms) / e_scale;
    (k, e)
}

#[test]
fn jet_fit_on_an_irregular_ellipsoid() {
    let (a, b, c) = (1.0, 0.75, 0.5);
    let scale = Vec3::new(a, b, c);
    let sphere = shapes::icosphere(1.0, 5);
    let m = irregular(&sphere, |p| p.normalize().component_mul(&scale));
    // Measured: k 2.8e-5, e 7.0e-3 (issue 19's targets: 0.03 and 0.25).
    let (k, e) = relative_errors(&m, |p| exact::ellipsoid(a, b, c, p));
    eprintln!("irregular ellipsoid: k {k:.2e}, e {e:.2e}");
    assert!(k <= 1e-4, "k RMS {k:.2e} of max |k|");
    assert!(e <= 0.02, "e RMS {e:.2e} of the 95th percentile of |e|");
}

#[test]
fn jet_fit_on_an_irregular_torus() {
    // A Dupin cyclide: e = 0 everywhere, so compare e with the scale of k² instead.
    let (major, minor) = (1.0, 0.3);
    let onto = |p: Vec3| {
        let ring = Vec3::new(p.x, p.y, 0.0).normalize() * major;
        ring + (p - ring).normalize() * minor
    };
    let m = irregular(&shapes::torus(major, minor, 160, 48), onto);
    let c = estimate(&m, &CurvatureOptions::DEFAULT).unwrap();
    let errors = exact::compare(&m, &c, |p| exact::torus(major, minor, p), |_| true, 0.0);
    let k_scale = 1.0 / minor;
    let k = errors.k_max.rms.max(errors.k_min.rms) / k_scale;
    let e = errors.e_max.rms.max(errors.e_min.rms) / (k_scale * k_scale);
    // Measured: k 5.6e-4, e 3.8e-3.
    eprintln!("irregular torus: k {k:.2e}, e {e:.2e} of max k²");
    assert!(k <= 0.0015, "k RMS {k:.2e} of max |k|");
    assert!(e <= 0.01, "e RMS {e:.2e} of max k²");
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(64))]

    /// Random triangle soups (repeated indices, coincident and collinear points, any
    /// orientation): both estimators return finite values and unit vectors.
    #[test]
    fn random_soups_never_give_nan(
        points in proptest::collection::vec((-3i32..3, -3i32..3, -3i32..3), 1..14),
        faces in proptest::collection::vec((0u32..14, 0u32..14, 0u32..14), 0..24),
        rings in 1usize..4,
    ) {
        let positions: Vec<[f64; 3]> = points
            .iter()
            .map(|&(x, y, z)| [x as f64 * 0.5, y as f64 * 0.5, z as f64 * 0.5])
            .collect();
        let n = positions.len() as u32;
        let faces: Vec<[u32; 3]> = faces.iter().map(|&(a, b, c)| [a % n, b % n, c % n]).collect();
        let m = TriMesh::from_arrays(positions, faces).unwrap();
        assert_all_finite(&so(&m), m.num_vertices());
        let c = cubic_fit(&m, &CubicFitOptions::DEFAULT.with_rings(rings)).unwrap();
        assert_all_finite(&c, m.num_vertices());
    }
}
