//! The bad-input suite, second part (the first, with the helpers, is `bad_input.rs`): STL
//! files, feature-line OBJ and diffusion-mask files, files and paths, and awkward meshes run
//! through the whole pipeline. Same rule: an error naming the file and a position, or a
//! correct result with what was skipped counted.

// Test code: stopping loudly on the first surprise is the point.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::path::Path;

use crestline::extract::{ExtractOptions, Method, extract};
use crestline::io::lines::parse_lines_obj;
use crestline::io::mask::parse_diffusion_factors;
use crestline::io::{Format, PlyEncoding, WriteOptions, read_mesh, write_mesh, write_mesh_to};
use crestline::mesh::{EdgeKind, VertexKind, orient_outward};
use crestline::{TriMesh, shapes};

use super::bad_input::{
    TETRA_OBJ, TRIANGLE, crlf, every_prefix, fails, reads, reads_with_crlf_and_bom, with_bom,
};
use crate::common::listing;

/// A binary STL of `triangles` whose header declares `declared` triangles.
fn binary_stl(declared: u32, triangles: &[[[f32; 3]; 3]]) -> Vec<u8> {
    let mut bytes = vec![b' '; 80];
    bytes.extend_from_slice(&declared.to_le_bytes());
    for t in triangles {
        bytes.extend_from_slice(&[0u8; 12]);
        for c in t.iter().flatten() {
            bytes.extend_from_slice(&c.to_le_bytes());
        }
        bytes.extend_from_slice(&[0u8; 2]);
    }
    bytes
}

const STL_ASCII: &str = "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n\
                         vertex 0 1 0\nendloop\nendfacet\nendsolid t\n";

// STL
// ---------------------------------------------------------------------------------------

#[test]
fn stl_empty_header_only_and_truncated() {
    fails("a.stl", "", "file", &["empty file"]);
    fails("a.stl", "solid x\n", "file", &["no vertices"]);
    fails("a.stl", "solid x\nendsolid x\n", "file", &["no vertices"]);
    fails("a.stl", binary_stl(0, &[]), "file", &["no vertices"]);
    let bytes = binary_stl(2, &[[[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]]);
    fails(
        "a.stl",
        &bytes,
        "byte 134",
        &["truncated", "declares 2 triangles"],
    );
    fails(
        "a.stl",
        "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n",
        "line 4",
        &["ends inside a facet"],
    );
}

#[test]
fn stl_binary_count_of_four_billion_allocates_nothing() {
    let bytes = binary_stl(u32::MAX, &[[[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]]);
    fails(
        "a.stl",
        &bytes,
        "byte 134",
        &["truncated", "4294967295 triangles"],
    );
}

#[test]
fn stl_bad_values() {
    let mut t = [[[0.0f32; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]];
    t[0][1][1] = f32::INFINITY;
    fails(
        "a.stl",
        binary_stl(1, &t),
        "byte 112",
        &["corner 1", "y coordinate", "infinite"],
    );
    fails(
        "a.stl",
        STL_ASCII.replace("vertex 1 0 0", "vertex 1 nan 0"),
        "line 5",
        &["NaN"],
    );
    fails(
        "a.stl",
        STL_ASCII.replace("vertex 1 0 0", "vertex 1 0"),
        "line 5",
        &["missing z"],
    );
    fails(
        "a.stl",
        STL_ASCII.replace("vertex 1 0 0\n", ""),
        "line 6",
        &["2 vertices"],
    );
    fails(
        "a.stl",
        STL_ASCII.replace("outer loop\n", ""),
        "line 3",
        &["outside an 'outer loop'"],
    );
}

#[test]
fn stl_polygons_crlf_bom_and_degenerate_facets() {
    reads_with_crlf_and_bom("a.stl", STL_ASCII, 3, 1, 0);
    let quad = STL_ASCII.replace("vertex 0 1 0\n", "vertex 1 1 0\nvertex 0 1 0\n");
    reads("a.stl", quad, 4, 2, 0);
    let sliver = STL_ASCII.replace("vertex 0 1 0", "vertex 2 0 0");
    reads("a.stl", sliver, 3, 0, 1);
    let mut twice = binary_stl(2, &[[[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]; 2]);
    reads("a.stl", &twice, 3, 2, 0);
    twice.extend_from_slice(b"trailing junk");
    reads("a.stl", &twice, 3, 2, 0);
}

#[test]
fn stl_cut_at_every_offset() {
    let mesh = shapes::icosphere(1.0, 0);
    let mut binary = Vec::new();
    write_mesh_to(&mut binary, &mesh, Format::Stl, &WriteOptions::default()).unwrap();
    let failures = every_prefix("a.stl", &binary);
    assert_eq!(failures, binary.len(), "every cut of a binary STL fails");
    every_prefix("a.stl", STL_ASCII.as_bytes());
}

// ---------------------------------------------------------------------------------------
// Feature-line OBJ and diffusion masks
// ---------------------------------------------------------------------------------------

#[test]
fn lines_files() {
    let lines = |t: &[u8]| parse_lines_obj(t, Path::new("l.obj")).map_err(|e| e.to_string());
    assert_eq!(lines(b"").unwrap_err(), "l.obj: empty file");
    assert!(
        lines(b"v 0 0 0\nl 1\n")
            .unwrap_err()
            .starts_with("l.obj: line 2: ")
    );
    assert!(
        lines(b"v 0 0 0\nv 1 1 1\nl 1 3\n")
            .unwrap_err()
            .contains("3 out of range")
    );
    assert!(
        lines(b"v 0 0 0\nv 1 1 1\nl 1 -3\n")
            .unwrap_err()
            .contains("before the first")
    );
    let huge = lines(b"v 0 0 0\nv 1 1 1\nl 1 99999999999999999999\n").unwrap_err();
    assert!(huge.starts_with("l.obj: line 3: "), "{huge}");
    assert!(
        lines(b"v 0 inf 0\n")
            .unwrap_err()
            .contains("NaN or infinite")
    );
    let text = "o ridges\nv 0 0 0\nv 1 0 0 # x\n# c\nl 1 2\n";
    for bytes in [
        text.as_bytes().to_vec(),
        crlf(text).into_bytes(),
        with_bom(text),
    ] {
        let l = lines(&bytes).unwrap();
        assert_eq!(l.lines.len(), 1);
        assert_eq!(l.lines[0].length, 1.0);
    }
    // No panic on any cut.
    for end in 0..text.len() {
        let _ = lines(&text.as_bytes()[..end]);
    }
}

#[test]
fn diffusion_mask_files() {
    let mask = |t: &[u8], n: usize| {
        parse_diffusion_factors(t, n, Path::new("m.txt")).map_err(|e| e.to_string())
    };
    assert_eq!(mask(b"1 0.5\n# c\n0\n", 3).unwrap(), vec![1.0, 0.5, 0.0]);
    assert_eq!(mask(&with_bom("1\r\n2\r\n"), 2).unwrap(), vec![1.0, 2.0]);
    let errors: [(&[u8], &str); 5] = [
        (b"", "m.txt: 0 factors for a mesh of 2 vertices"),
        (
            b"1\n2\n3\n",
            "m.txt: line 3: more factors than the 2 vertices of the mesh",
        ),
        (
            b"1\nnan\n",
            "m.txt: line 2: factor 'nan' must be a finite number >= 0",
        ),
        (
            b"1\n-2\n",
            "m.txt: line 2: factor '-2' must be a finite number >= 0",
        ),
        (
            b"1\n\xff\n",
            "m.txt: line 2: non-numeric token '\u{fffd}' where a factor was expected",
        ),
    ];
    for (text, expected) in errors {
        assert_eq!(mask(text, 2).unwrap_err(), expected);
    }
}

// ---------------------------------------------------------------------------------------
// Files and paths
// ---------------------------------------------------------------------------------------

#[test]
fn missing_file_and_directory_as_input() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("missing.obj");
    let e = read_mesh(&missing, None).unwrap_err().to_string();
    assert_eq!(
        e,
        format!(
            "{}: No such file or directory (os error 2)",
            missing.display()
        )
    );
    // The cause is said once, in the message: it is not also the error's source (a chain of
    // causes, as anyhow prints it, would say it twice).
    let e = read_mesh(&missing, None).unwrap_err();
    assert!(std::error::Error::source(&e).is_none());
    let folder = dir.path().join("folder.obj");
    std::fs::create_dir(&folder).unwrap();
    let e = read_mesh(&folder, None).unwrap_err().to_string();
    assert!(e.starts_with(&format!("{}: ", folder.display())), "{e}");
    assert!(e.contains("directory"), "{e}");
}

#[test]
fn unwritable_outputs_leave_nothing_behind() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = shapes::icosphere(1.0, 1);
    let options = WriteOptions::default();
    // Into a folder that does not exist.
    let nowhere = dir.path().join("no/such/dir/out.obj");
    let e = write_mesh(&nowhere, &mesh, Format::Obj, &options).unwrap_err();
    assert!(
        e.to_string()
            .starts_with(&format!("{}: ", nowhere.display())),
        "{e}"
    );
    // Onto a folder.
    let folder = dir.path().join("out.ply");
    std::fs::create_dir(&folder).unwrap();
    let e = write_mesh(&folder, &mesh, Format::Ply, &options).unwrap_err();
    assert!(
        e.to_string()
            .starts_with(&format!("{}: ", folder.display())),
        "{e}"
    );
    assert!(folder.is_dir());
    assert_eq!(listing(dir.path()), vec!["out.ply"]);
    // Into a folder without write permission (unless running as root, who may write anyway).
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        let locked = dir.path().join("locked");
        std::fs::create_dir(&locked).unwrap();
        std::fs::set_permissions(&locked, std::fs::Permissions::from_mode(0o500)).unwrap();
        let target = locked.join("out.obj");
        if let Err(e) = write_mesh(&target, &mesh, Format::Obj, &options) {
            assert!(
                e.to_string()
                    .starts_with(&format!("{}: ", target.display())),
                "{e}"
            );
            assert!(listing(&locked).is_empty());
        }
        std::fs::set_permissions(&locked, std::fs::Permissions::from_mode(0o700)).unwrap();
    }
}

#[test]
fn output_over_its_own_input_is_replaced_whole() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("m.obj");
    std::fs::write(&path, TETRA_OBJ).unwrap();
    let mesh = read_mesh(&path, None).unwrap();
    let (mesh, _) = orient_outward(mesh).unwrap();
    write_mesh(&path, &mesh, Format::Obj, &WriteOptions::default()).unwrap();
    let back = read_mesh(&path, None).unwrap();
    assert_eq!(back.positions(), mesh.positions());
    assert_eq!(back.faces(), mesh.faces());
    assert_eq!(listing(dir.path()), vec!["m.obj"]);
}

#[test]
fn a_failed_write_keeps_the_old_file() {
    use crestline::io::lines::write_lines;
    use crestline::lines::{FeatureLine, FeatureLines, LineKind};
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("lines.json");
    std::fs::write(&path, "old").unwrap();
    // A line with a non-finite point cannot be written: the error comes before any byte
    // replaces the old file.
    let bad = FeatureLines {
        lines: vec![FeatureLine {
            length: f64::NAN,
            ..FeatureLine::new(
                LineKind::Ridge,
                vec![
                    crestline::Vec3::zeros(),
                    crestline::Vec3::new(f64::NAN, 0.0, 0.0),
                ],
                false,
            )
        }],
    };
    for name in ["lines.json", "lines.obj", "lines.ply"] {
        let path = dir.path().join(name);
        std::fs::write(&path, "old").unwrap();
        let e = write_lines(&path, &bad, None, PlyEncoding::Ascii).unwrap_err();
        assert!(e.to_string().contains("must be finite"), "{name}: {e}");
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "old", "{name}");
    }
    assert_eq!(
        listing(dir.path()),
        vec!["lines.json", "lines.obj", "lines.ply"]
    );
}

// ---------------------------------------------------------------------------------------
// Awkward meshes through the whole pipeline
// ---------------------------------------------------------------------------------------

/// Runs every method on `mesh`: each gives lines with finite numbers or a clear error.
pub(super) fn every_method(name: &str, mesh: &TriMesh) {
    for method in [Method::Hpw, Method::Ybs, Method::Saliency] {
        match extract(mesh, &ExtractOptions::for_method(method)) {
            Ok(x) => {
                for l in &x.lines.lines {
                    assert!(
                        l.points.iter().all(|p| p.iter().all(|c| c.is_finite()))
                            && l.length.is_finite()
                            && l.strength.is_finite(),
                        "{name} {method:?}: a line with a non-finite number"
                    );
                }
            }
            Err(e) => {
                let m = e.to_string();
                assert!(!m.is_empty(), "{name} {method:?}");
            }
        }
    }
}

fn mesh(positions: &[[f64; 3]], faces: &[[u32; 3]]) -> TriMesh {
    TriMesh::from_arrays(positions.to_vec(), faces.to_vec()).unwrap()
}

#[test]
fn isolated_vertices_only() {
    let m = mesh(&[[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 2.0]], &[]);
    assert_eq!(m.topology().count_vertices(VertexKind::Unreferenced), 3);
    every_method("isolated vertices", &m);
}

#[test]
fn one_triangle_and_a_single_degenerate_one() {
    every_method(
        "one triangle",
        &mesh(&TRIANGLE.map(|p| p.map(f64::from)), &[[0, 1, 2]]),
    );
    let m = mesh(&[[0.0; 3], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]], &[[0, 1, 2]]);
    assert_eq!((m.num_faces(), m.degenerate_faces()), (0, 1));
    every_method("degenerate only", &m);
}

#[test]
fn non_manifold_fan() {
    // Six triangles around one edge (0, 1), each a fin pointing another way.
    let mut positions = vec![[0.0, 0.0, -1.0], [0.0, 0.0, 1.0]];
    let mut faces = Vec::new();
    for k in 0..6 {
        let a = k as f64 * std::f64::consts::TAU / 6.0;
        positions.push([a.cos(), a.sin(), 0.0]);
        faces.push([0, 1, 2 + k]);
    }
    let m = mesh(&positions, &faces);
    assert_eq!(m.topology().count_edges(EdgeKind::NonManifold), 1);
    every_method("non-manifold fan", &m);
    // Two tetrahedra sharing one vertex (a non-manifold vertex) and the fan together.
    let (sphere, _) = orient_outward(shapes::icosphere(1.0, 2)).unwrap();
    let n = sphere.num_vertices() as u32;
    let mut positions: Vec<[f64; 3]> = sphere.positions().iter().map(|p| [p.x, p.y, p.z]).collect();
    let mut faces = sphere.faces().to_vec();
    positions.extend(sphere.positions().iter().map(|p| [p.x + 2.0, p.y, p.z]));
    faces.extend(sphere.faces().iter().map(|t| t.map(|v| v + n)));
    // Glue vertex 0 of the second sphere onto the first sphere's vertex 0... by index.
    for t in faces.iter_mut().skip(sphere.num_faces()) {
        for v in t.iter_mut() {
            if *v == n {
                *v = 0;
            }
        }
    }
    every_method("spheres sharing a vertex", &mesh(&positions, &faces));
}

/// A Moebius strip of `n` quads across its width.
fn moebius(n: usize) -> TriMesh {
    let mut positions = Vec::new();
    for i in 0..n {
        let t = i as f64 * std::f64::consts::TAU / n as f64;
        for s in [-0.3, 0.3] {
            let r = 1.0 + s * (t / 2.0).cos();
            positions.push([r * t.cos(), r * t.sin(), s * (t / 2.0).sin()]);
        }
    }
    let mut faces = Vec::new();
    for i in 0..n as u32 {
        let (a, b) = (2 * i, 2 * i + 1);
        // The last quad joins the strip to itself with a half twist.
        let (c, d) = if i + 1 == n as u32 {
            (1, 0)
        } else {
            (2 * i + 2, 2 * i + 3)
        };
        faces.push([a, c, b]);
        faces.push([b, c, d]);
    }
    TriMesh::from_arrays(positions, faces).unwrap()
}

#[test]
fn moebius_strip() {
    let m = moebius(120);
    assert_eq!(m.topology().count_edges(EdgeKind::NonManifold), 0);
    let (oriented, report) = orient_outward(m).unwrap();
    assert_eq!(report.closed, 0);
    every_method("moebius", &oriented);
}

#[test]
fn inconsistent_winding() {
    // A sphere with every third triangle flipped: still read, oriented where closed.
    let sphere = shapes::icosphere(1.0, 3);
    let faces: Vec<[u32; 3]> = sphere
        .faces()
        .iter()
        .enumerate()
        .map(|(f, &[a, b, c])| if f % 3 == 0 { [a, c, b] } else { [a, b, c] })
        .collect();
    let positions: Vec<[f64; 3]> = sphere.positions().iter().map(|p| [p.x, p.y, p.z]).collect();
    let m = mesh(&positions, &faces);
    let (m, _) = orient_outward(m).unwrap();
    every_method("inconsistent winding", &m);
}

#[test]
fn duplicate_faces_through_the_pipeline() {
    let sphere = shapes::icosphere(1.0, 2);
    let positions: Vec<[f64; 3]> = sphere.positions().iter().map(|p| [p.x, p.y, p.z]).collect();
    let mut faces = sphere.faces().to_vec();
    faces.extend_from_slice(&sphere.faces()[..20]);
    every_method("duplicate faces", &mesh(&positions, &faces));
}

#[test]
fn extreme_but_valid_scales_give_finite_lines() {
    for scale in [1e-60, 1e-30, 1e30, 1e60] {
        let m = shapes::ellipsoid(3.0 * scale, 2.0 * scale, scale, 2);
        every_method(&format!("ellipsoid at scale {scale:e}"), &m);
    }
}
