//! Properties of crest-line-guided simplification on generated shapes with known creases.

use crestline::distance::{DistanceOptions, feature_distance};
use crestline::lines::{FeatureLine, FeatureLines, LineKind};
use crestline::mesh::{VertexKind, face_normals};
use crestline::shapes;
use crestline::simplify::{SimplifyOptions, Target, simplify};
use crestline::spatial::FaceGrid;

use crate::common;
use common::{distance_to, samples};
use crestline::Vec3;

fn without_locations(lines: &FeatureLines) -> FeatureLines {
    let mut lines = lines.clone();
    for l in &mut lines.lines {
        l.locations.clear();
    }
    lines
}

#[test]
fn pillow_box_to_ten_percent_is_a_valid_closed_mesh_without_flips() {
    let (mesh, lines) = shapes::pillow_box(1.0, 0.25, 20);
    let r = simplify(&mesh, &lines, &SimplifyOptions::default()).unwrap();
    assert_eq!(r.target_faces, 480);
    assert!(r.target_reached);
    assert!(
        r.faces_after == 480 || r.faces_after == 479,
        "{}",
        r.faces_after
    );
    let info = r.mesh.info();
    assert!(info.closed, "{info}");
    assert_eq!(info.euler_characteristic, 2);
    assert_eq!(info.components, 1);
    assert_eq!(info.non_manifold_edges, 0);
    assert_eq!(info.non_manifold_vertices, 0);
    assert_eq!(info.degenerate_faces, 0);
    assert_eq!(info.faces, r.faces_after);
    // No flips: each new triangle faces the way the original surface faces where it lies.
    let grid = FaceGrid::new(&mesh);
    let original = face_normals(&mesh);
    for (f, n) in face_normals(&r.mesh).iter().enumerate() {
        let [a, b, c] = r.mesh.triangle(f);
        let hit = grid.closest_point((a + b + c) / 3.0).unwrap();
        assert!(n.dot(&original[hit.face as usize]) > 0.5, "face {f}");
    }
}

#[test]
fn open_surface_keeps_its_boundary() {
    let mesh = shapes::waving_surface(6.0, 40);
    // Its crest line r = π, as points only (located through the grid).
    let circle = (0..64)
        .map(|i| {
            let a = std::f64::consts::TAU * i as f64 / 64.0;
            let (x, y) = (
                std::f64::consts::PI * a.cos(),
                std::f64::consts::PI * a.sin(),
            );
            Vec3::new(x, y, -1.0)
        })
        .collect();
    let lines = FeatureLines {
        lines: vec![FeatureLine {
            length: std::f64::consts::TAU * std::f64::consts::PI,
            ..FeatureLine::new(LineKind::Valley, circle, true)
        }],
    };
    let options = SimplifyOptions::default().with_target(Target::Faces(400));
    let r = simplify(&mesh, &lines, &options).unwrap();
    assert!(r.faces_after == 400 || r.faces_after == 399);
    let info = r.mesh.info();
    assert_eq!(info.boundary_loops, 1, "{info}");
    assert_eq!(info.components, 1);
    assert_eq!(info.non_manifold_edges + info.non_manifold_vertices, 0);
    assert_eq!(info.degenerate_faces, 0);
    assert_eq!(info.euler_characteristic, 1);
    // Every boundary vertex of the result is one of the input's, unmoved; the corners stay.
    let topo = mesh.topology();
    let input_boundary: Vec<Vec3> = (0..mesh.num_vertices() as u32)
        .filter(|&v| topo.vertex_kind(v) == VertexKind::Boundary)
        .map(|v| mesh.position(v))
        .collect();
    let out = r.mesh.topology();
    let output_boundary: Vec<Vec3> = (0..r.mesh.num_vertices() as u32)
        .filter(|&v| out.vertex_kind(v) == VertexKind::Boundary)
        .map(|v| r.mesh.position(v))
        .collect();
    for p in &output_boundary {
        assert!(input_boundary.contains(p), "{p}");
    }
    for (x, y) in [(-6.0, -6.0), (6.0, -6.0), (-6.0, 6.0), (6.0, 6.0)] {
        assert!(
            output_boundary.iter().any(|p| p.x == x && p.y == y),
            "corner ({x}, {y}) lost"
        );
    }
}

#[test]
fn crest_lines_keep_detail_near_them() {
    // The key property of YBS eq. 7: at the same face count, eta > 0 approximates the
    // surface near the crest lines better than plain QEM (eta = 0).
    let (mesh, lines) = shapes::pillow_box(1.0, 0.25, 24);
    let d = feature_distance(&mesh, &lines, &DistanceOptions::default()).unwrap();
    // The band within 10 % of the largest distance from the creases, and the rest.
    let near = samples(&mesh, |f| d.face[f] <= 0.1 * d.max);
    let far = samples(&mesh, |f| d.face[f] > 0.1 * d.max);
    let mut errors = Vec::new();
    for eta in [0.0, 1.0, 2.0] {
        let r = common::simplify_to_tenth(&mesh, &lines, eta);
        assert!(r.target_reached);
        let (near_mean, near_max) = distance_to(&r.mesh, &near);
        let (far_mean, far_max) = distance_to(&r.mesh, &far);
        eprintln!(
            "eta {eta}: {} faces; near lines mean {near_mean:.3e} max {near_max:.3e}; \
             far mean {far_mean:.3e} max {far_max:.3e}",
            r.faces_after
        );
        errors.push((r.faces_after, near_mean, near_max));
    }
    // Measured (690 triangles each), near the creases: mean 1.09e-3 / max 8.3e-3 (eta 0),
    // 9.0e-4 / 5.1e-3 (eta 1), 6.6e-4 / 4.2e-3 (eta 2); far from them the mean grows from
    // 1.5e-3 to 2.0e-3 and 2.1e-3. The near mean falls steadily with eta; the near maximum
    // depends on tie-breaking at eta 1 (it was above eta 0's in an earlier variant), so it is
    // only checked at eta 2.
    let (faces0, mean0, max0) = errors[0];
    assert!(errors.iter().all(|e| e.0.abs_diff(faces0) <= 1));
    assert!(
        errors[1].1 < 0.9 * mean0,
        "eta 1: {:?} vs {:?}",
        errors[1],
        errors[0]
    );
    assert!(
        errors[2].1 < 0.75 * mean0,
        "eta 2: {:?} vs {:?}",
        errors[2],
        errors[0]
    );
    assert!(errors[2].1 < errors[1].1);
    assert!(
        errors[2].2 < max0,
        "eta 2: {:?} vs {:?}",
        errors[2],
        errors[0]
    );
}

#[test]
fn located_and_grid_located_lines_agree() {
    let (mesh, lines) = shapes::pillow_box(1.0, 0.25, 16);
    let opts = DistanceOptions::default();
    let a = feature_distance(&mesh, &lines, &opts).unwrap();
    let b = feature_distance(&mesh, &without_locations(&lines), &opts).unwrap();
    assert_eq!(a.unreached_vertices, 0);
    let worst = a
        .vertex
        .iter()
        .zip(&b.vertex)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max);
    // Both seed the creases with 0; they differ only in how wide a band gets Euclidean
    // seeds, which on the gently curved faces is a fraction of a percent of the size.
    assert!(worst < 5e-3, "{worst}");
    for line in &lines.lines {
        for p in &line.points {
            let v = mesh.positions().iter().position(|q| q == p).unwrap();
            assert_eq!(a.vertex[v], 0.0);
            assert_eq!(b.vertex[v], 0.0);
        }
    }
}

#[test]
fn result_does_not_depend_on_scale() {
    // Scaling by powers of two is exact in floating point, so every decision must repeat.
    let (mesh, lines) = shapes::pillow_box(1.0, 0.25, 12);
    let options = SimplifyOptions::default().with_target(Target::Ratio(0.2));
    let base = simplify(&mesh, &lines, &options).unwrap();
    for k in [-20, 20] {
        let s = 2f64.powi(k);
        let scaled = mesh
            .with_positions(mesh.positions().iter().map(|p| p * s).collect())
            .unwrap();
        let mut scaled_lines = lines.clone();
        for l in &mut scaled_lines.lines {
            l.points.iter_mut().for_each(|p| *p *= s);
        }
        let r = simplify(&scaled, &scaled_lines, &options).unwrap();
        assert_eq!(r.mesh.faces(), base.mesh.faces(), "scale 2^{k}");
        for (p, q) in r.mesh.positions().iter().zip(base.mesh.positions()) {
            assert_eq!(*p, q * s);
        }
    }
}
