//! Reading the real test meshes in `shared/data/meshes` (see its README): every one loads,
//! the counts their sources document come out, and writing then reading them is exact.

// Test code: stopping loudly on the first surprise is the point.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::path::{Path, PathBuf};

use crestline::MeshInfo;
use crestline::io::{Format, PlyEncoding, WriteOptions, read_mesh, read_mesh_bytes, write_mesh_to};

use crate::common::{load_shared, shared_meshes_dir};

fn info(name: &str) -> MeshInfo {
    load_shared(name).info()
}

#[test]
fn every_mesh_loads() {
    let mut paths: Vec<PathBuf> = std::fs::read_dir(shared_meshes_dir())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| Format::from_path(p).is_some())
        .collect();
    paths.sort();
    assert!(paths.len() >= 12, "only {} meshes found", paths.len());
    for path in paths {
        let mesh = read_mesh(&path, None).unwrap_or_else(|e| panic!("{e}"));
        assert!(mesh.num_faces() > 0, "{}", path.display());
        assert_eq!(mesh.degenerate_faces(), 0, "{}", path.display());
    }
}

#[test]
fn igea_tristrips() {
    let i = info("igea.ply");
    assert_eq!(i.vertices, 134_345);
    // A closed genus-0 scan: every strip triangle is kept, stitching triangles are not.
    assert_eq!(i.faces, 268_686);
    assert!(i.closed);
    assert_eq!(i.euler_characteristic, 2);
    assert_eq!(i.non_manifold_edges, 0);
}

#[test]
fn horse_binary_ply_with_normals() {
    let i = info("horse.ply");
    assert_eq!(i.vertices, 48_485);
    assert_eq!(i.faces, 96_966);
    assert!(i.closed);
    assert_eq!(i.euler_characteristic, 2);
}

#[test]
fn beetle_non_manifold_edges() {
    let i = info("beetle.obj");
    assert_eq!(i.faces, 2_053);
    assert_eq!(i.non_manifold_edges, 47);
    assert!(!i.closed);
}

#[test]
fn teapot_is_open() {
    let i = info("teapot.obj");
    assert_eq!(i.faces, 6_320);
    assert_eq!(i.boundary_edges, 1_036);
    assert!(!i.closed);
}

#[test]
fn stanford_bunny_has_holes_and_stray_vertices() {
    let i = info("stanford-bunny.obj");
    assert_eq!(i.vertices, 35_947);
    assert_eq!(i.faces, 69_451);
    assert_eq!(i.boundary_edges, 223);
    assert_eq!(i.boundary_loops, 5);
    // Checked independently: 1,113 vertices of the file are used by no face.
    assert_eq!(i.unreferenced_vertices, 1_113);
    // Genus 0 with 5 holes.
    assert_eq!(i.euler_characteristic, -3);
}

#[test]
fn suzanne_quads_with_normals() {
    let i = info("suzanne.obj");
    assert_eq!(i.vertices, 507);
    // 500 polygons, mostly quads, fan-triangulated.
    assert_eq!(i.faces, 968);
    assert_eq!(i.non_manifold_edges, 1);
}

#[test]
fn small_closed_models() {
    for (name, faces) in [
        ("fandisk.obj", 12_946),
        ("rocker-arm.obj", 20_088),
        ("spot.obj", 5_856),
        ("cow.obj", 5_804),
        ("homer.obj", 12_000),
    ] {
        let i = info(name);
        assert_eq!(i.faces, faces, "{name}");
        assert!(i.closed, "{name}");
    }
    assert_eq!(info("alligator.obj").faces, 5_981);
}

/// Writes `mesh` in every exact format and reads it back.
fn assert_round_trips(name: &str) {
    let mesh = load_shared(name);
    let variants = [
        (Format::Obj, PlyEncoding::BinaryLittleEndian),
        (Format::Off, PlyEncoding::BinaryLittleEndian),
        (Format::Ply, PlyEncoding::BinaryLittleEndian),
        (Format::Ply, PlyEncoding::BinaryBigEndian),
        (Format::Ply, PlyEncoding::Ascii),
    ];
    for (format, encoding) in variants {
        let options = WriteOptions::default().with_ply_encoding(encoding);
        let mut bytes = Vec::new();
        write_mesh_to(&mut bytes, &mesh, format, &options).unwrap();
        let back = read_mesh_bytes(&bytes, format, Path::new(name)).unwrap();
        let what = format!("{name} as {format} {encoding:?}");
        assert_eq!(back.faces(), mesh.faces(), "{what}");
        let same = back.positions().iter().zip(mesh.positions()).all(|(a, b)| {
            a.iter()
                .zip(b.iter())
                .all(|(x, y)| x.to_bits() == y.to_bits())
        });
        assert!(same && back.num_vertices() == mesh.num_vertices(), "{what}");
    }
}

#[test]
fn real_meshes_round_trip_exactly() {
    // The bunny keeps its unreferenced vertices; the horse comes from float PLY.
    assert_round_trips("stanford-bunny.obj");
    assert_round_trips("horse.ply");
}
