//! Unit tests of crease detection on generated shapes and tiny meshes.

use super::*;
use crate::shapes;

/// A unit cube, each face two triangles, wound outward.
fn cube() -> TriMesh {
    let p: Vec<[f64; 3]> = (0..8)
        .map(|i| [(i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64])
        .collect();
    let quads = [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ];
    let faces = quads
        .iter()
        .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
        .collect();
    TriMesh::from_arrays(p, faces).unwrap()
}

#[test]
fn cube_edges_are_twelve_convex_creases_between_corners() {
    let mesh = cube();
    let angles = dihedral_angles(&mesh);
    let right = angles
        .iter()
        .filter(|a| (**a - std::f64::consts::FRAC_PI_2).abs() < 1e-12)
        .count();
    assert_eq!(right, 12);
    assert_eq!(angles.iter().filter(|a| a.abs() < 1e-12).count(), 6);
    let creases = find_creases(&mesh, &CreaseOptions::DEFAULT).unwrap();
    assert_eq!(creases.curves.len(), 12);
    assert!(creases.curves.iter().all(|c| c.convex && !c.closed));
    assert!(creases.curves.iter().all(|c| c.vertices.len() == 2));
    let t = creases.threshold.unwrap();
    assert!(t > FLAT_ANGLE && t < 90.0, "threshold {t}");
}

#[test]
fn inward_cube_has_concave_creases() {
    let mesh = cube();
    let flipped: Vec<[u32; 3]> = mesh.faces().iter().map(|t| [t[0], t[2], t[1]]).collect();
    let mesh = TriMesh::new(mesh.positions().to_vec(), flipped).unwrap();
    let creases = find_creases(&mesh, &CreaseOptions::DEFAULT).unwrap();
    assert_eq!(creases.curves.len(), 12);
    assert!(creases.curves.iter().all(|c| !c.convex));
}

#[test]
fn smooth_meshes_have_no_gap() {
    for mesh in [shapes::icosphere(1.0, 3), shapes::torus(3.0, 1.0, 60, 20)] {
        let creases = find_creases(&mesh, &CreaseOptions::DEFAULT).unwrap();
        assert!(creases.is_empty(), "{:?}", creases.threshold);
    }
}

#[test]
fn off_and_fixed_angles() {
    let mesh = cube();
    let off = CreaseOptions::DEFAULT.with_angle(CreaseAngle::Off);
    assert!(find_creases(&mesh, &off).unwrap().is_empty());
    let steep = CreaseOptions::DEFAULT.with_angle(CreaseAngle::Degrees(95.0));
    assert!(find_creases(&mesh, &steep).unwrap().is_empty());
    let right = CreaseOptions::DEFAULT.with_angle(CreaseAngle::Degrees(80.0));
    assert_eq!(find_creases(&mesh, &right).unwrap().curves.len(), 12);
    for bad in [0.0, 180.0, f64::NAN, -3.0] {
        let o = CreaseOptions::DEFAULT.with_angle(CreaseAngle::Degrees(bad));
        assert!(find_creases(&mesh, &o).is_err());
    }
}

#[test]
fn boundary_edges_are_not_creases() {
    // Two triangles folded at 90 degrees: the fold is the only manifold edge.
    let mesh = TriMesh::from_arrays(
        vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ],
        vec![[0, 1, 2], [0, 3, 1]],
    )
    .unwrap();
    let angles = dihedral_angles(&mesh);
    assert_eq!(angles.iter().filter(|a| a.is_finite()).count(), 1);
    let fixed = CreaseOptions {
        min_length: 0.0,
        ..CreaseOptions::DEFAULT.with_angle(CreaseAngle::Degrees(45.0))
    };
    let creases = find_creases(&mesh, &fixed).unwrap();
    assert_eq!(creases.curves.len(), 1);
    assert_eq!(creases.edges.iter().filter(|e| **e).count(), 1);
}

#[test]
fn gap_needs_populations_on_both_sides() {
    let flat = vec![0.0; 100];
    let ones = vec![1.0; 100];
    assert_eq!(gap_threshold(&flat, &ones), None);
    let mut angles = flat.clone();
    angles.extend([1.5; 12]);
    let lengths = vec![1.0; angles.len()];
    let t = gap_threshold(&angles, &lengths).unwrap().to_degrees();
    assert!(t > FLAT_ANGLE && t < 85.9, "{t}");
    // A continuous spread has no gap.
    let spread: Vec<f64> = (0..2000).map(|i| (i as f64 * 0.05).to_radians()).collect();
    assert_eq!(gap_threshold(&spread, &vec![1.0; 2000]), None);
}

#[test]
fn stray_curves_are_dropped_by_length() {
    let mut curves = vec![
        CreaseCurve {
            vertices: vec![0, 1],
            closed: false,
            convex: true,
            length: 0.5,
            turning: 0.0,
        },
        CreaseCurve {
            vertices: vec![1, 2],
            closed: false,
            convex: true,
            length: 0.6,
            turning: 0.0,
        },
        CreaseCurve {
            vertices: vec![5, 6],
            closed: false,
            convex: true,
            length: 0.9,
            turning: 0.0,
        },
    ];
    assert_eq!(drop_stray_curves(&mut curves, 1.0), 1);
    assert_eq!(curves.len(), 2);
}
