//! Invariance and determinism of the lines on real meshes (fandisk, the Stanford bunny, igea).
//!
//! Feature lines are geometric: moving, turning or scaling the model, or listing its vertices
//! and faces in another order, must give the same lines moved, turned or scaled alike. After
//! transforming back, the test asks for the same number of lines, the same total length
//! within 0.1% of the bounding-box diagonal, and every point of either set within 1e-6 of
//! the diagonal of a point of the other. The output files must also be byte-identical from
//! run to run and with one or two worker threads.
//!
//! igea's extraction takes seconds, so the big meshes combine transforms (a rotation with a
//! translation by 1e4; a reordering with a scaling by 1e-3) and reuse one reference result.

// Test code: stopping loudly on the first surprise is the point.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use crate::common;

use std::collections::HashMap;

use crestline::extract::{ExtractOptions, extract};
use crestline::io::PlyEncoding;
use crestline::io::lines::{write_lines_json, write_lines_obj, write_lines_ply};
use crestline::lines::FeatureLines;
use crestline::{TriMesh, Vec3};

use common::load_shared;

/// A similarity transform p -> scale · R p + shift.
#[derive(Clone, Copy)]
struct Similarity {
    rotation: nalgebra::Rotation3<f64>,
    scale: f64,
    shift: Vec3,
}

impl Similarity {
    fn identity() -> Self {
        Similarity {
            rotation: nalgebra::Rotation3::identity(),
            scale: 1.0,
            shift: Vec3::zeros(),
        }
    }

    fn apply(&self, p: Vec3) -> Vec3 {
        self.rotation * p * self.scale + self.shift
    }

    fn invert(&self, p: Vec3) -> Vec3 {
        self.rotation.inverse() * ((p - self.shift) / self.scale)
    }
}

/// An arbitrary rotation (no axis-aligned symmetry left).
fn rotation() -> nalgebra::Rotation3<f64> {
    nalgebra::Rotation3::from_euler_angles(0.7, -1.1, 2.3)
}

/// A fixed pseudo-random permutation of `0..n`.
fn permutation(n: usize, seed: u64) -> Vec<usize> {
    let mut order: Vec<usize> = (0..n).collect();
    let mut state = seed;
    for i in (1..n).rev() {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        let j = (state >> 33) as usize % (i + 1);
        order.swap(i, j);
    }
    order
}

/// `mesh` transformed by `t` and, when `reorder`, with its vertices and faces listed in a
/// shuffled order (and each face's corners turned, keeping its winding).
fn transformed(mesh: &TriMesh, t: &Similarity, reorder: bool) -> TriMesh {
    let n = mesh.num_vertices();
    // new_of[old] = new index.
    let new_of: Vec<usize> = if reorder {
        permutation(n, 7)
    } else {
        (0..n).collect()
    };
    let mut positions = vec![[0.0; 3]; n];
    for (old, p) in mesh.positions().iter().enumerate() {
        let q = t.apply(*p);
        positions[new_of[old]] = [q.x, q.y, q.z];
    }
    let mut faces: Vec<[u32; 3]> = mesh
        .faces()
        .iter()
        .enumerate()
        .map(|(f, tri)| {
            let [a, b, c] = tri.map(|v| new_of[v as usize] as u32);
            match (f % 3, reorder) {
                (1, true) => [b, c, a],
                (2, true) => [c, a, b],
                _ => [a, b, c],
            }
        })
        .collect();
    if reorder {
        let order = permutation(faces.len(), 11);
        faces = order.iter().map(|&f| faces[f]).collect();
    }
    TriMesh::from_arrays(positions, faces).unwrap()
}

fn diagonal(mesh: &TriMesh) -> f64 {
    mesh.bounding_box().diagonal()
}

/// Points of `lines` mapped back by `t`.
fn points_back(lines: &FeatureLines, t: &Similarity) -> Vec<Vec3> {
    lines
        .lines
        .iter()
        .flat_map(|l| l.points.iter().map(|p| t.invert(*p)))
        .collect()
}

/// The largest distance from a point of `a` to the nearest point of `b`, looked up in a grid
/// of cells `cell` wide; `None` when some point has no point of `b` within a cell.
fn farthest_unmatched(a: &[Vec3], b: &[Vec3], cell: f64) -> Option<f64> {
    let key = |p: &Vec3| (p / cell).map(|c| c.floor() as i64);
    let mut grid: HashMap<[i64; 3], Vec<Vec3>> = HashMap::new();
    for p in b {
        let k = key(p);
        grid.entry([k.x, k.y, k.z]).or_default().push(*p);
    }
    let mut worst = 0.0f64;
    for p in a {
        let k = key(p);
        let mut best = f64::INFINITY;
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    if let Some(points) = grid.get(&[k.x + dx, k.y + dy, k.z + dz]) {
                        for q in points {
                            best = best.min((p - q).norm());
                        }
                    }
                }
            }
        }
        if best > cell {
            return None;
        }
        worst = worst.max(best);
    }
    Some(worst)
}

/// Checks the lines of the transformed mesh against the reference; returns a summary line.
fn check_same_lines(
    name: &str,
    what: &str,
    reference: &FeatureLines,
    reference_diagonal: f64,
    lines: &FeatureLines,
    t: &Similarity,
) -> (bool, String) {
    let length_back = lines.total_length() / t.scale;
    let length_error = (length_back - reference.total_length()).abs() / reference_diagonal;
    let tolerance = 1e-6 * reference_diagonal;
    let ours = points_back(lines, t);
    let theirs = points_back(reference, &Similarity::identity());
    let forward = farthest_unmatched(&ours, &theirs, tolerance);
    let backward = farthest_unmatched(&theirs, &ours, tolerance);
    let summary = format!(
        "{name} {what}: {} vs {} lines, length error {length_error:.2e} of the diagonal, \
         farthest point {:?} / {:?} (tolerance {tolerance:.2e})",
        lines.lines.len(),
        reference.lines.len(),
        forward,
        backward
    );
    let same = lines.lines.len() == reference.lines.len()
        && length_error <= 1e-3
        && forward.is_some()
        && backward.is_some();
    (same, summary)
}

/// The three line files as bytes.
fn files(lines: &FeatureLines) -> Vec<Vec<u8>> {
    let mut obj = Vec::new();
    write_lines_obj(&mut obj, lines).unwrap();
    let mut json = Vec::new();
    write_lines_json(&mut json, lines).unwrap();
    let mut ply = Vec::new();
    write_lines_ply(&mut ply, lines, PlyEncoding::BinaryLittleEndian).unwrap();
    vec![obj, json, ply]
}

fn extract_with_threads(mesh: &TriMesh, threads: usize) -> FeatureLines {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| extract(mesh, &ExtractOptions::default()).unwrap().lines)
}

/// Runs the checks on `file`: each entry of `transforms` is one extraction.
fn check_mesh(file: &str, transforms: &[(&str, Similarity, bool)]) {
    let mesh = load_shared(file);
    let d = diagonal(&mesh);
    // The reference with two threads, then once more with one: same bytes.
    let reference = extract_with_threads(&mesh, 2);
    assert!(!reference.lines.is_empty(), "{file}: no lines");
    let reference_files = files(&reference);
    let single = extract_with_threads(&mesh, 1);
    assert!(
        files(&single) == reference_files,
        "{file}: the line files differ between one and two threads"
    );
    // Every transform runs, so that a failure lists all that differ.
    let mut failures = Vec::new();
    for (what, t, reorder) in transforms {
        let moved = transformed(&mesh, t, *reorder);
        let lines = extract_with_threads(&moved, 2);
        let (same, summary) = check_same_lines(file, what, &reference, d, &lines, t);
        eprintln!("{summary}");
        if !same {
            failures.push(summary);
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

fn turned_and_shifted() -> Similarity {
    Similarity {
        rotation: rotation(),
        scale: 1.0,
        shift: Vec3::new(1e4, -1e4, 1e4),
    }
}

fn scaled(scale: f64) -> Similarity {
    Similarity {
        scale,
        ..Similarity::identity()
    }
}

fn rotated() -> Similarity {
    Similarity {
        rotation: rotation(),
        ..Similarity::identity()
    }
}

fn translated() -> Similarity {
    Similarity {
        shift: Vec3::new(1e4, 1e4, 1e4),
        ..Similarity::identity()
    }
}

#[test]
fn fandisk_lines_are_scale_invariant_and_deterministic() {
    check_mesh(
        "fandisk.obj",
        &[
            ("scaled by 1e-3", scaled(1e-3), false),
            ("scaled by 1e3", scaled(1e3), false),
        ],
    );
}

#[test]
fn bunny_lines_are_invariant_and_deterministic() {
    check_mesh(
        "stanford-bunny.obj",
        &[
            ("rotated and translated by 1e4", turned_and_shifted(), false),
            ("scaled by 1e3", scaled(1e3), false),
        ],
    );
}

#[test]
fn igea_lines_are_invariant_and_deterministic() {
    check_mesh(
        "igea.ply",
        &[
            ("rotated and translated by 1e4", turned_and_shifted(), false),
            ("scaled by 1e3", scaled(1e3), false),
        ],
    );
}

#[test]
fn fandisk_lines_are_invariant_under_translation_and_reordering() {
    check_mesh(
        "fandisk.obj",
        &[
            ("translated by 1e4", translated(), false),
            ("reordered", Similarity::identity(), true),
            ("reordered and translated by 1e4", translated(), true),
        ],
    );
}

// Measured gaps, now closed (issue 22). Translation and reordering on fandisk used to add one
// ridge of 3 points: a crease vertex between two flat sides has an angle of π on each, and
// `widest_side` chose between them by rounding; it now takes angles within 1e-9 as a tie
// (`SIDE_TIE`) and breaks it by area, face count and second moment (all invariant), and
// the merge joins lines to the nearest point of a crease curve rather than of its
// resampling; and the jet fit's regularisation is the identity in a basis that a turn of
// the tangent frame maps orthogonally (`ROTATION_SCALE`), where it was the identity in the
// plain monomials: on the rows of fandisk's grids some quartic fits are nearly singular
// (eigenvalues of the normal equations down to 1e-14 of the largest), and their curvature
// followed the frame, which follows the coordinate axes. A rotation then still joined one
// valley to a crease in one run and not in the other (1.66e-2 of the diagonal of length):
// the valley's tracing reached one more edge, beside a flat side whose extremality is at
// the level of rounding, in one run only; that point is cut (its fields are one-sided) and
// a cut end was joined only from the point cut, within the cut tolerance. Every end is
// now joined from the point kept: within the join distance, and a cut end also within its
// distance to the point cut plus the tolerance (`lines::merge`), so that point no longer
// matters: 45 lines against 45, the same length.
//
// Reordering the scans used to move their lines (bunny: points beyond 1e-6 of the diagonal;
// igea: 477 lines against 475): the jet fit's noise probe fitted every n/20000-th vertex in
// index order and the simulated noise was drawn by vertex index. Both now follow a key made
// from the vertex's distance to the centroid (`probe_keys`).

#[test]
fn fandisk_lines_are_invariant_under_rotation() {
    check_mesh("fandisk.obj", &[("rotated", rotated(), false)]);
}

#[test]
fn scan_lines_are_invariant_under_reordering() {
    for file in ["stanford-bunny.obj", "igea.ply"] {
        check_mesh(
            file,
            &[
                ("reordered", Similarity::identity(), true),
                ("scaled by 1e-3", scaled(1e-3), false),
            ],
        );
    }
}

/// `mesh` with copies of itself shifted by each of `shifts` in one mesh.
fn with_copies(mesh: &TriMesh, shifts: &[Vec3]) -> TriMesh {
    let n = mesh.num_vertices() as u32;
    let mut positions = mesh.positions().to_vec();
    let mut faces = mesh.faces().to_vec();
    for (k, shift) in shifts.iter().enumerate() {
        let offset = n * (k as u32 + 1);
        positions.extend(mesh.positions().iter().map(|p| p + shift));
        faces.extend(mesh.faces().iter().map(|t| t.map(|v| v + offset)));
    }
    TriMesh::new(positions, faces).unwrap()
}

#[test]
fn fandisk_lines_do_not_depend_on_what_else_the_file_holds() {
    // Relative lengths and strengths are fractions of the model size, the diagonal of the
    // largest part: a speck far away, or a second part beside the first, must not change
    // the lines (with the diagonal of the whole file, two copies 20 diagonals apart lost
    // every crest line).
    let mesh = load_shared("fandisk.obj");
    let d = diagonal(&mesh);
    let reference = extract(&mesh, &ExtractOptions::default()).unwrap().lines;
    let far = Vec3::new(20.0 * d, 0.0, 0.0);
    let mut failures = Vec::new();

    // A speck: one triangle 1e-3 of the diagonal wide, 20 diagonals away.
    let mut positions = mesh.positions().to_vec();
    let n = positions.len() as u32;
    let corner = Vec3::from(mesh.bounding_box().max) + far;
    positions.extend([
        corner,
        corner + Vec3::new(1e-3 * d, 0.0, 0.0),
        corner + Vec3::new(0.0, 1e-3 * d, 0.0),
    ]);
    let mut faces = mesh.faces().to_vec();
    faces.push([n, n + 1, n + 2]);
    let speck = TriMesh::new(positions, faces).unwrap();
    assert!(diagonal(&speck) > 20.0 * d);
    // The speck's three vertices are samples too: the jet fit's sample spacing (√(area per
    // vertex)) shrinks by 2e-4 of itself and the lines move by a little (measured: length
    // 3.9e-4 of the diagonal), so here the same lines are asked for within 1e-3 of the
    // diagonal, not at the level of rounding.
    let lines = extract(&speck, &ExtractOptions::default()).unwrap().lines;
    let length_error = (lines.total_length() - reference.total_length()).abs() / d;
    let points =
        |l: &FeatureLines| -> Vec<Vec3> { l.lines.iter().flat_map(|l| l.points.clone()).collect() };
    let (ours, theirs) = (points(&lines), points(&reference));
    let cell = 1e-3 * d;
    let summary = format!(
        "fandisk with a speck: {} vs {} lines, length error {length_error:.2e} of the \
         diagonal, farthest point {:?} / {:?} (tolerance {cell:.2e})",
        lines.lines.len(),
        reference.lines.len(),
        farthest_unmatched(&ours, &theirs, cell),
        farthest_unmatched(&theirs, &ours, cell),
    );
    eprintln!("{summary}");
    if lines.lines.len() != reference.lines.len()
        || length_error > 1e-3
        || farthest_unmatched(&ours, &theirs, cell).is_none()
        || farthest_unmatched(&theirs, &ours, cell).is_none()
    {
        failures.push(summary);
    }

    // Two copies: each gets the lines of one.
    let pair = with_copies(&mesh, &[far]);
    let lines = extract(&pair, &ExtractOptions::default()).unwrap().lines;
    let centre_x = mesh.bounding_box().center().x + 10.0 * d;
    let (second, first): (Vec<_>, Vec<_>) = lines
        .lines
        .into_iter()
        .partition(|l| l.points[0].x > centre_x);
    for (what, part, shift) in [
        ("first of two copies", first, Vec3::zeros()),
        ("second of two copies", second, far),
    ] {
        let t = Similarity {
            shift,
            ..Similarity::identity()
        };
        let part = FeatureLines { lines: part };
        let (same, summary) = check_same_lines("fandisk", what, &reference, d, &part, &t);
        eprintln!("{summary}");
        if !same {
            failures.push(summary);
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
