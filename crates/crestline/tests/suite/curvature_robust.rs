//! Curvature estimation on awkward meshes (never NaN, never a panic, fallbacks counted) and
//! the default estimator (jet fit) on irregular triangulations of shapes with known answers
//! (`crestline::shapes::exact`). The analytic-shape and invariance tests, and the helpers, are
//! in `curvature.rs`.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use crestline::curvature::{
    CubicFitOptions, CurvatureOptions, Estimator, PrincipalSelection, ShapeOperatorOptions,
    cubic_fit, estimate, shape_operator,
};
use crestline::shapes::exact::{self, ExactCurvature};
use crestline::shapes::{self, GridPattern};
use crestline::{TriMesh, Vec3};

use super::curvature::{assert_all_finite, cf, so};

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
    let octahedron = shapes::octahedron();
    let mut octa_faces = octahedron.faces().to_vec();
    octa_faces[1].swap(0, 1);
    let flipped = TriMesh::new(octahedron.positions().to_vec(), octa_faces).unwrap();
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
        ("flipped face", flipped),
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
    use crestline::curvature::extremality::triangle_regularity;
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

#[test]
fn jet_fit_on_a_coarse_torus() {
    // 30 and 20 samples around the tube, like `ring/reg5k` of the public cases and coarser.
    // The heights of a tube not much wider than the disc are a slowly converging series:
    // the quartic's truncation residual was taken for noise (radius grown to 3.2 and 5.6
    // spacings, the latter wider than the tube), and the fits were 1.4% and 35% off in k.
    // The curved heights leave a smaller residual and fit the tube itself. Measured: k
    // 6.7e-4 and 2.5e-3 of max |k|, e 5.2e-3 and 1.6e-2 of max k²; the first torus is taken
    // for clean (noise 1.1e-4 spacings), the second still not (1.5e-3, radius 3.3).
    let (major, minor) = (1.0, 0.3);
    for (around, along, max_k, max_e) in [(100, 30, 0.003, 0.02), (64, 20, 0.01, 0.05)] {
        let m = shapes::torus(major, minor, around, along);
        let c = estimate(&m, &CurvatureOptions::DEFAULT).unwrap();
        let report = c.jet_fit.unwrap();
        let errors = exact::compare(&m, &c, |p| exact::torus(major, minor, p), |_| true, 0.0);
        let k = errors.k_max.rms.max(errors.k_min.rms) * minor;
        let e = errors.e_max.rms.max(errors.e_min.rms) * minor * minor;
        eprintln!(
            "{around} x {along} torus: k {k:.2e} of max |k|, e {e:.2e} of max k², noise {:.2e} spacings, radius {:.2}",
            report.noise, report.radius
        );
        if along == 30 {
            assert!(report.noise <= crestline::curvature::jet_fit::REFERENCE_NOISE);
        }
        assert!(k <= max_k, "k RMS {k:.2e} of max |k|");
        assert!(e <= max_e, "e RMS {e:.2e} of max k²");
    }
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

#[test]
fn wide_cubic_fits_stay_finite_in_size_across_sharp_creases() {
    // Rings of 4 and more reach across fandisk's creases to faces whose normals are nearly
    // perpendicular to the fitting frame's: as slopes −a/c, c → 0, they gave curvatures up
    // to 9·10⁷ (258 vertices above 1000 with 4 rings). Taken as `c h_x = −a` (module docs of
    // `cubic_fit`, *Slopes near the horizon*) no curvature radius falls below a twentieth of
    // an edge; a crease of any angle sampled by edges of length h bends by at most about
    // 2π/h.
    let mesh = crate::common::load_shared("fandisk.obj");
    let h = crestline::mesh::mean_edge_length(&mesh);
    for rings in [4, 6] {
        let c = cubic_fit(&mesh, &CubicFitOptions::DEFAULT.with_rings(rings)).unwrap();
        let worst = c
            .k_max
            .iter()
            .chain(&c.k_min)
            .fold(0.0f64, |m, k| m.max(k.abs()));
        assert!(
            worst * h < 20.0,
            "rings {rings}: |k| up to {worst} (h = {h})"
        );
    }
}
