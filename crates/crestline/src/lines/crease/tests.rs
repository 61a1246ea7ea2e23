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

/// A block 10 × 4 × 2 with a roof whose two planes meet at a ridge turning by `ridge`
/// degrees, every face split into triangles as an exporter does (10 vertices, 24 edges).
fn roofed_block(ridge: f64) -> TriMesh {
    let rise = 2.0 * (ridge.to_radians() / 2.0).tan();
    let p = vec![
        [0.0, 0.0, 0.0],
        [10.0, 0.0, 0.0],
        [10.0, 4.0, 0.0],
        [0.0, 4.0, 0.0],
        [0.0, 0.0, 2.0],
        [10.0, 0.0, 2.0],
        [10.0, 4.0, 2.0],
        [0.0, 4.0, 2.0],
        [0.0, 2.0, 2.0 + rise],
        [10.0, 2.0, 2.0 + rise],
    ];
    let faces = vec![
        [0, 2, 1],
        [0, 3, 2],
        [0, 1, 5],
        [0, 5, 4],
        [2, 3, 7],
        [2, 7, 6],
        [0, 4, 8],
        [0, 8, 7],
        [0, 7, 3],
        [1, 2, 6],
        [1, 6, 9],
        [1, 9, 5],
        [4, 5, 9],
        [4, 9, 8],
        [8, 9, 6],
        [8, 6, 7],
    ];
    TriMesh::from_arrays(p, faces).unwrap()
}

#[test]
fn a_shallow_crease_of_a_polyhedral_part_is_a_crease() {
    // One edge at 5° against fourteen at about 90° and nine flat ones: the gap search puts
    // the 5° edge with the flat ones (20.75° before), but no edge below the gap is a
    // tessellation edge, so the mesh has planar faces only and the ridge is a crease.
    let mesh = roofed_block(5.0);
    let angles = dihedral_angles(&mesh);
    let ridge = mesh.topology().edge_between(8, 9).unwrap();
    assert!((angles[ridge as usize].to_degrees() - 5.0).abs() < 1e-9);
    let creases = find_creases(&mesh, &CreaseOptions::DEFAULT).unwrap();
    assert!(
        creases.edges[ridge as usize],
        "threshold {:?}",
        creases.threshold
    );
    let turning = angles.iter().filter(|a| a.abs() > 1e-9).count();
    assert_eq!(turning, 15);
    assert_eq!(creases.edges.iter().filter(|&&e| e).count(), turning);
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
    // Also none between filtered normals (step 2b runs on all but the icosphere, rougher than
    // NOISE_ROUGHNESS): the torus's filtered angles have a gap of the filter's own below its
    // roughness; the capsules' pole fans, whole in one patch, once evened their first rings
    // into creases.
    let mut meshes = vec![shapes::icosphere(1.0, 3), shapes::torus(3.0, 1.0, 60, 20)];
    meshes.extend([24, 32, 40, 48].map(|n| shapes::capsule(1.0, 2.0, n)));
    for (k, mesh) in meshes.into_iter().enumerate() {
        // All but the icosphere are rough enough for step 2b to run.
        assert!(k == 0 || roughness(&mesh).to_degrees() >= NOISE_ROUGHNESS);
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

/// Step 2b: the noise of a scan leaves no gap in the angles of a folded sheet; between the
/// filtered normals its fold is a crease again, and nothing else is. Over several noises: a
/// curve may end one column aside at the mesh's edge or step aside for a vertex, and the
/// fold come out in a few pieces, but every crease vertex is within a column of the fold and
/// the convex curves cover it.
#[test]
fn a_noisy_fold_is_a_crease_between_filtered_normals() {
    for seed in 1..=6 {
        let mesh = normals::tests::noisy_roof(30, 40.0, 0.1, seed);
        let lengths = edge_lengths(&mesh);
        assert_eq!(
            gap_threshold(&dihedral_angles(&mesh), &lengths),
            None,
            "seed {seed}: the premise, the noise hides the gap"
        );
        let creases = find_creases(&mesh, &CreaseOptions::DEFAULT).unwrap();
        assert!(creases.filtered, "seed {seed}");
        assert!(
            (1..=8).contains(&creases.curves.len()),
            "seed {seed}: {} curves",
            creases.curves.len()
        );
        // The fold is the middle column (15) of the 31 × 31 vertices.
        assert!(
            creases
                .curves
                .iter()
                .flat_map(|c| &c.vertices)
                .all(|&v| (v % 31).abs_diff(15) <= 1),
            "seed {seed}: a crease off the fold"
        );
        let convex: f64 = creases
            .curves
            .iter()
            .filter(|c| c.convex)
            .map(|c| c.length)
            .sum();
        assert!(convex >= 28.0, "seed {seed}: convex length {convex}");
        let unfiltered = CreaseOptions {
            filter_noise: false,
            ..CreaseOptions::DEFAULT
        };
        assert!(find_creases(&mesh, &unfiltered).unwrap().is_empty());
    }
}
