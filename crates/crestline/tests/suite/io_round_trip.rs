//! Writing a mesh and reading it back gives the same bits: OBJ, OFF and PLY in all three
//! encodings, on random meshes whose coordinates span every finite magnitude.

// Test code: stopping loudly on the first surprise is the point.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::path::Path;

use crestline::TriMesh;
use crestline::io::{
    Format, PlyEncoding, WriteOptions, read_mesh, read_mesh_bytes, write_mesh, write_mesh_to,
};
use proptest::prelude::*;

/// Finite coordinates: ordinary, tiny, huge, subnormal, signed zeros and arbitrary bits.
fn coordinate() -> impl Strategy<Value = f64> {
    prop_oneof![
        -1e3..1e3f64,
        (-1.0..1.0f64).prop_map(|x| x * 1e-300),
        (-1.0..1.0f64).prop_map(|x| x * 1e300),
        Just(0.0),
        Just(-0.0),
        Just(f64::MAX),
        Just(f64::MIN_POSITIVE),
        Just(5e-324),
        prop::num::f64::NORMAL | prop::num::f64::SUBNORMAL | prop::num::f64::ZERO,
    ]
}

/// A random mesh: 3 to 40 vertices (some may be unreferenced) and faces with three
/// distinct indices.
fn mesh() -> impl Strategy<Value = TriMesh> {
    (3usize..40).prop_flat_map(|n| {
        let positions = prop::collection::vec([coordinate(), coordinate(), coordinate()], n);
        let faces = prop::collection::vec([0..n as u32, 0..n as u32, 0..n as u32], 0..60);
        (positions, faces).prop_map(|(positions, faces)| {
            let faces = faces
                .into_iter()
                .filter(|[a, b, c]| a != b && b != c && a != c)
                .collect();
            TriMesh::from_arrays(positions, faces).unwrap()
        })
    })
}

fn assert_same(a: &TriMesh, b: &TriMesh, what: &str) {
    assert_eq!(a.num_vertices(), b.num_vertices(), "{what}");
    for (p, q) in a.positions().iter().zip(b.positions()) {
        for k in 0..3 {
            assert_eq!(p[k].to_bits(), q[k].to_bits(), "{what}: {p:?} vs {q:?}");
        }
    }
    assert_eq!(a.faces(), b.faces(), "{what}");
}

const EXACT: [(Format, PlyEncoding); 5] = [
    (Format::Obj, PlyEncoding::BinaryLittleEndian),
    (Format::Off, PlyEncoding::BinaryLittleEndian),
    (Format::Ply, PlyEncoding::Ascii),
    (Format::Ply, PlyEncoding::BinaryLittleEndian),
    (Format::Ply, PlyEncoding::BinaryBigEndian),
];

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    #[test]
    fn write_then_read_is_exact(mesh in mesh()) {
        for (format, encoding) in EXACT {
            let options = WriteOptions::default().with_ply_encoding(encoding);
            let mut bytes = Vec::new();
            write_mesh_to(&mut bytes, &mesh, format, &options).unwrap();
            let back = read_mesh_bytes(&bytes, format, Path::new("random")).unwrap();
            assert_same(&mesh, &back, &format!("{format} {encoding:?}"));
            prop_assert_eq!(back.degenerate_faces(), 0);
        }
    }
}

#[test]
fn write_mesh_to_files_by_extension() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = crestline::shapes::torus(2.0, 0.5, 12, 8);
    for (format, encoding) in EXACT {
        let path = dir
            .path()
            .join(format!("torus-{encoding:?}.{}", format.extension()));
        let options = WriteOptions::default().with_ply_encoding(encoding);
        write_mesh(&path, &mesh, format, &options).unwrap();
        let back = read_mesh(&path, None).unwrap();
        assert_same(&mesh, &back, &path.display().to_string());
    }
    // STL rounds to f32 and renumbers vertices by first use, but welding gives the
    // connectivity back.
    let path = dir.path().join("torus.stl");
    write_mesh(&path, &mesh, Format::Stl, &WriteOptions::default()).unwrap();
    let back = read_mesh(&path, None).unwrap();
    assert_eq!(back.num_vertices(), mesh.num_vertices());
    assert_eq!(back.num_faces(), mesh.num_faces());
    let info = back.info();
    assert!(info.closed);
    assert_eq!(info.euler_characteristic, 0);
}

#[test]
fn write_errors_name_the_file() {
    let mesh = crestline::shapes::icosphere(1.0, 0);
    let e = write_mesh(
        Path::new("/nonexistent/dir/out.obj"),
        &mesh,
        Format::Obj,
        &WriteOptions::DEFAULT,
    )
    .unwrap_err();
    assert!(
        e.to_string().starts_with("/nonexistent/dir/out.obj: "),
        "{e}"
    );
}
