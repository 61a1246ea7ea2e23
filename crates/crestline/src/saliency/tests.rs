//! Unit tests of the saliency field on small generated meshes.

use super::sums::{Gaussians, exp_neg_small};
use super::*;
use crate::curvature::{Curvature, CurvatureOptions, Estimator, estimate};
use crate::mesh::Vec3;
use crate::shapes;

/// The curvature of `mesh` by the HPW shape operator.
fn shape_operator(mesh: &TriMesh) -> Curvature {
    let options = CurvatureOptions::default().with_estimator(Estimator::ShapeOperator);
    estimate(mesh, &options).unwrap()
}

#[test]
fn crease_is_more_salient_than_a_flat_region() {
    // A roof: two planes meeting at a crease along x = 0.
    let mesh = shapes::height_field(|x, _| -x.abs() * 0.8, [-2.0, 2.0], [-2.0, 2.0], 40, 40);
    let c = shape_operator(&mesh);
    let s = mesh_saliency(&mesh, &c, &SaliencyOptions::default()).unwrap();
    let at = |x: f64, y: f64| {
        (0..mesh.num_vertices())
            .min_by(|&a, &b| {
                let d = |i: usize| {
                    (mesh.positions()[i].x - x).powi(2) + (mesh.positions()[i].y - y).powi(2)
                };
                d(a).total_cmp(&d(b))
            })
            .unwrap()
    };
    let crease = s.saliency[at(0.0, 0.0)];
    let flat = s.saliency[at(1.0, 0.0)];
    assert!(
        crease > 5.0 * flat.max(1e-12),
        "crease {crease} flat {flat}"
    );
}

#[test]
fn pillow_box_creases_are_more_salient_than_its_faces() {
    // The cube's edges are sharp creases; the faces bulge gently (largest curvature
    // ≈ 1 at their middles). With the cubic fit, as the saliency method runs it.
    let (mesh, _) = shapes::pillow_box(1.0, 0.25, 20);
    let options = CurvatureOptions::default().with_estimator(crate::curvature::Estimator::CubicFit);
    let c = estimate(&mesh, &options).unwrap();
    let s = mesh_saliency(&mesh, &c, &SaliencyOptions::default()).unwrap();
    let nearest = |q: Vec3| {
        (0..mesh.num_vertices())
            .min_by(|&a, &b| {
                (mesh.positions()[a] - q)
                    .norm()
                    .total_cmp(&(mesh.positions()[b] - q).norm())
            })
            .unwrap()
    };
    let edge_middle = s.saliency[nearest(Vec3::new(0.0, 1.0, 1.0))];
    let face_middle = s.saliency[nearest(Vec3::new(0.0, 0.0, 1.25))];
    assert!(
        edge_middle > 3.0 * face_middle,
        "edge {edge_middle}, face {face_middle}"
    );
    // Every crease vertex away from the corners beats every vertex in the middle half
    // of a face.
    let is_crease = |p: &Vec3| (0..3).filter(|&k| (p[k].abs() - 1.0).abs() < 1e-9).count() == 2;
    let crease_min = (0..mesh.num_vertices())
        .filter(|&v| {
            let p = mesh.positions()[v];
            is_crease(&p)
                && p.iter()
                    .all(|x| x.abs() < 0.99 || (x.abs() - 1.0).abs() < 1e-9)
        })
        .map(|v| s.saliency[v])
        .fold(f64::INFINITY, f64::min);
    let face_max = (0..mesh.num_vertices())
        .filter(|&v| {
            let p = mesh.positions()[v];
            (0..3).filter(|&k| p[k].abs() < 0.5).count() == 2
        })
        .map(|v| s.saliency[v])
        .fold(0.0, f64::max);
    assert!(
        crease_min > face_max,
        "crease min {crease_min}, face max {face_max}"
    );
}

#[test]
fn sphere_and_torus_saliency_have_no_knee() {
    // Curv is 1/r on a sphere and 1/r_minor on a torus (the tube curvature dominates), so
    // the sorted saliency has no steep part and the knee search finds no threshold.
    for mesh in [shapes::icosphere(2.0, 3), shapes::torus(3.0, 1.0, 90, 30)] {
        let c = shape_operator(&mesh);
        let s = mesh_saliency(&mesh, &c, &SaliencyOptions::default()).unwrap();
        let knee = crate::threshold::seek_threshold(&s.saliency, &Default::default());
        assert_eq!(
            knee,
            None,
            "{:?}",
            s.saliency.iter().take(5).collect::<Vec<_>>()
        );
    }
}

#[test]
fn sphere_saliency_is_uniform() {
    let mesh = shapes::icosphere(2.0, 3);
    let c = shape_operator(&mesh);
    let s = mesh_saliency(&mesh, &c, &SaliencyOptions::default()).unwrap();
    let max = s.saliency.iter().cloned().fold(f64::MIN, f64::max);
    let min = s.saliency.iter().cloned().fold(f64::MAX, f64::min);
    // The HPW shape operator keeps a ≈15% error at the icosphere's 12 valence-5 vertices
    // (measured saliency 0.200 .. 0.233; k = 0.428 at vertex 0, one of them), hence 20%
    // rather than 10% (see the curvature section of BENCHMARKS.md).
    assert!((max - min) < 0.2 * max, "{min} .. {max}");
    assert!((s.curv[0] - 0.5).abs() < 0.1, "{}", s.curv[0]);
}

/// Eqs. 6–8 term by term: every pair of vertices, `f64::exp`.
fn brute_force_variation(mesh: &TriMesh, curv: &[f64], sigma: f64, scales: usize) -> Vec<f64> {
    let p = mesh.positions();
    (0..p.len())
        .map(|i| {
            let g = |k: usize| {
                let s = sigma * k as f64;
                let (mut num, mut den) = (0.0, 0.0);
                for j in 0..p.len() {
                    let d2 = (p[j] - p[i]).norm_squared();
                    if d2 <= 4.0 * s * s {
                        let w = (-d2 / (2.0 * s * s)).exp();
                        num += w * curv[j];
                        den += w;
                    }
                }
                num / den
            };
            (1..=scales).map(|k| (g(k + 1) - g(k)).abs()).sum()
        })
        .collect()
}

#[test]
fn variation_matches_the_brute_force_sums() {
    // An irregular field on an ellipsoid, every number of scales.
    let mesh = shapes::ellipsoid(2.0, 1.5, 1.0, 3);
    let c = shape_operator(&mesh);
    let sigma = 0.7 * mean_edge_length(&mesh);
    let curv: Vec<f64> = (0..mesh.num_vertices())
        .map(|v| c.k_max[v].abs().max(c.k_min[v].abs()))
        .collect();
    for scales in 1..=MAX_SCALES {
        let fast = variation(&mesh, &curv, sigma, scales);
        let slow = brute_force_variation(&mesh, &curv, sigma, scales);
        for (v, (a, b)) in fast.iter().zip(&slow).enumerate() {
            assert!(
                (a - b).abs() <= 1e-12 * b.abs().max(1.0),
                "scales {scales}, vertex {v}: {a} vs {b}"
            );
        }
    }
}

#[test]
fn variation_does_not_depend_on_the_thread_count() {
    // Each pair is weighted once and its weights are added to both ends, by tasks that
    // run in parallel: the sums must still come out bit for bit the same.
    let mesh = shapes::ellipsoid(2.0, 1.5, 1.0, 4);
    let c = shape_operator(&mesh);
    let sigma = 0.5 * mean_edge_length(&mesh);
    // Cells of σ_4 = 4σ along the longest axis (x, 4 long): at least three layers per
    // phase, so several tasks write to the same sums.
    let layers = (4.0 / (4.0 * sigma)) as usize + 1;
    assert!(layers >= 12, "{layers} layers");
    let curv: Vec<f64> = (0..mesh.num_vertices())
        .map(|v| c.k_max[v].abs().max(c.k_min[v].abs()))
        .collect();
    let run = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| variation(&mesh, &curv, sigma, 3))
    };
    let one = run(1);
    for threads in [2, 3, 5] {
        let many = run(threads);
        assert!(
            one.iter()
                .zip(&many)
                .all(|(a, b)| a.to_bits() == b.to_bits()),
            "{threads} threads"
        );
    }
}

#[test]
fn gaussian_weights_are_exact_to_rounding() {
    fn check<const L: usize>() {
        for i in 0..=1000 {
            let a = 2.0 * (L * L) as f64 * i as f64 / 1000.0;
            let w = Gaussians::<L>::weights(a);
            for (k, w) in w.iter().enumerate() {
                let exact = (-a / ((k + 1) * (k + 1)) as f64).exp();
                assert!(
                    (w - exact).abs() <= 1e-12 * exact,
                    "L {L}, K {}, a {a}: {w} vs {exact}",
                    k + 1
                );
            }
        }
    }
    check::<2>();
    check::<3>();
    check::<4>();
    check::<5>();
    for i in 0..=100 {
        let t = 0.25 * i as f64 / 100.0;
        assert!((exp_neg_small(t) - (-t).exp()).abs() <= 4.0 * f64::EPSILON);
    }
}

#[test]
fn unreferenced_vertices_take_no_part() {
    // A stray vertex in the middle of a flat grid with a curved field: its saliency is
    // 0 and the others' are what they are without it.
    let mesh = shapes::height_field(
        |x, y| 0.1 * (x * x - y * y),
        [-1.0, 1.0],
        [-1.0, 1.0],
        12,
        12,
    );
    let mut positions = mesh.positions().to_vec();
    positions.push(Vec3::new(0.01, 0.02, 0.0));
    let with_stray = TriMesh::new(positions, mesh.faces().to_vec()).unwrap();
    let c = shape_operator(&mesh);
    let mut c2 = c.clone();
    for field in [&mut c2.k_max, &mut c2.k_min, &mut c2.e_max, &mut c2.e_min] {
        field.push(100.0);
    }
    c2.dir_max.push(Vec3::x());
    c2.dir_min.push(Vec3::y());
    c2.normals.push(Vec3::z());
    let a = mesh_saliency(&mesh, &c, &SaliencyOptions::default()).unwrap();
    let b = mesh_saliency(&with_stray, &c2, &SaliencyOptions::default()).unwrap();
    assert_eq!(b.saliency.len(), a.saliency.len() + 1);
    assert_eq!(*b.saliency.last().unwrap(), 0.0);
    // The mean edge length (σ) does not see the stray vertex either.
    for (x, y) in a.saliency.iter().zip(&b.saliency) {
        assert!((x - y).abs() <= 1e-12 * x.abs().max(1.0), "{x} vs {y}");
    }
}

#[test]
fn rejects_bad_options() {
    let mesh = shapes::icosphere(1.0, 1);
    let c = Curvature {
        k_max: vec![0.0; mesh.num_vertices()],
        k_min: vec![0.0; mesh.num_vertices()],
        ..Default::default()
    };
    let bad = SaliencyOptions {
        scales: 9,
        ..Default::default()
    };
    assert!(mesh_saliency(&mesh, &c, &bad).is_err());
    let bad = SaliencyOptions {
        lambda: f64::NAN,
        ..Default::default()
    };
    assert!(mesh_saliency(&mesh, &c, &bad).is_err());
    let short = Curvature {
        k_max: vec![0.0; 3],
        k_min: vec![0.0; 3],
        ..Default::default()
    };
    assert!(mesh_saliency(&mesh, &short, &SaliencyOptions::default()).is_err());
}
