use super::build::vertex_face_rows;
use super::*;

#[test]
fn vertex_face_rows_do_not_depend_on_the_number_of_threads() {
    // A soup with unreferenced vertices, repeated triangles and vertices of high degree.
    let n = 1000usize;
    let faces: Vec<[u32; 3]> = (0..5000u64)
        .map(|i| {
            let h = |k: u64| ((i * 2654435761 + k * 40503) % 997) as u32;
            let a = if i % 7 == 0 { 3 } else { h(1) };
            [a, (a + 1 + h(2) % 500) % 997, (a + 501 + h(3) % 400) % 997]
        })
        .collect();
    // One row per vertex by increasing face, with the other two corners in order.
    let mut rows = vec![Vec::new(); n];
    for (f, t) in faces.iter().enumerate() {
        for s in 0..3 {
            rows[t[s] as usize].push((f as u32, [t[(s + 1) % 3], t[(s + 2) % 3]]));
        }
    }
    for threads in [1, 2, 3, 7] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let (offsets, values, others) = pool.install(|| vertex_face_rows(n, &faces));
        assert_eq!(offsets.len(), n + 1);
        for (v, row) in rows.iter().enumerate() {
            let range = offsets[v] as usize..offsets[v + 1] as usize;
            let got: Vec<(u32, [u32; 2])> = values[range.clone()]
                .iter()
                .copied()
                .zip(others[range].iter().copied())
                .collect();
            assert_eq!(&got, row, "vertex {v} with {threads} threads");
        }
    }
}

/// A square split into two triangles, both counter-clockwise from +z.
fn square() -> Vec<[u32; 3]> {
    vec![[0, 1, 2], [0, 2, 3]]
}

/// An octahedron, outward-wound.
fn octahedron() -> Vec<[u32; 3]> {
    crate::shapes::octahedron().faces().to_vec()
}

#[test]
fn square_edges_and_kinds() {
    let t = Topology::build(4, &square());
    assert_eq!(t.num_edges(), 5);
    let diagonal = t.face_edges(0)[2];
    assert_eq!(t.edge(diagonal), [0, 2]);
    assert_eq!(t.edge_kind(diagonal), EdgeKind::Manifold);
    assert_eq!(t.face_across(0, 2), Some(1));
    assert_eq!(t.face_across(0, 0), None);
    assert!(t.vertex_kinds().iter().all(|&k| k == VertexKind::Boundary));
    assert_eq!(t.boundary_loops(&square()), 1);
}

#[test]
fn boundary_fan_is_ordered_from_the_boundary() {
    let faces = square();
    let t = Topology::build(4, &faces);
    let fans = t.fans(0, &faces);
    assert_eq!(fans.len(), 1);
    assert!(!fans[0].closed);
    assert_eq!(fans[0].vertices, vec![1, 2, 3]);
    assert_eq!(fans[0].faces, vec![0, 1]);
}

#[test]
fn octahedron_rings_are_closed_and_counter_clockwise() {
    let faces = octahedron();
    let t = Topology::build(6, &faces);
    assert_eq!(t.num_edges(), 12);
    assert!(t.vertex_kinds().iter().all(|&k| k == VertexKind::Interior));
    let fans = t.fans(4, &faces);
    assert_eq!(fans.len(), 1);
    assert!(fans[0].closed);
    assert_eq!(fans[0].vertices.len(), 4);
    assert_eq!(fans[0].faces.len(), 4);
    // Around the apex 4 the ring is 0, 2, 1, 3 (up to a rotation).
    let ring = &fans[0].vertices;
    let k = ring.iter().position(|&x| x == 0).unwrap();
    let rotated: Vec<u32> = (0..4).map(|i| ring[(k + i) % 4]).collect();
    assert_eq!(rotated, vec![0, 2, 1, 3]);
    assert_eq!(t.boundary_loops(&faces), 0);
}

#[test]
fn ring_survives_a_flipped_face() {
    let mut faces = octahedron();
    faces[1] = [1, 2, 4];
    let t = Topology::build(6, &faces);
    assert_eq!(t.vertex_kind(4), VertexKind::Interior);
    assert_eq!(t.fans(4, &faces)[0].vertices.len(), 4);
}

#[test]
fn bowtie_and_fin_are_non_manifold() {
    // Two triangles sharing only vertex 0.
    let bowtie = vec![[0, 1, 2], [0, 3, 4]];
    let t = Topology::build(5, &bowtie);
    assert_eq!(t.vertex_kind(0), VertexKind::NonManifold);
    assert_eq!(t.fans(0, &bowtie).len(), 2);
    assert_eq!(t.vertex_kind(1), VertexKind::Boundary);
    assert_eq!(t.boundary_loops(&bowtie), 2);
    // Three triangles on one edge.
    let fin = vec![[0, 1, 2], [1, 0, 3], [0, 1, 4]];
    let t = Topology::build(5, &fin);
    let e = t.face_edges(0)[0];
    assert_eq!(t.edge_kind(e), EdgeKind::NonManifold);
    assert_eq!(t.vertex_kind(0), VertexKind::NonManifold);
    assert_eq!(t.vertex_kind(2), VertexKind::Boundary);
}

/// Edges, faces per edge and edges per face.
type Reference = (Vec<[u32; 2]>, Vec<Vec<u32>>, Vec<[u32; 3]>);

/// The connectivity built the slow, obvious way: all half-edges sorted by (smaller end,
/// larger end, face).
fn reference(n: usize, faces: &[[u32; 3]]) -> Reference {
    let mut half: Vec<(u32, u32, u32, usize)> = Vec::new();
    for (f, t) in faces.iter().enumerate() {
        for s in 0..3 {
            let (a, b) = (t[s], t[(s + 1) % 3]);
            half.push((a.min(b), a.max(b), f as u32, s));
        }
    }
    half.sort_unstable();
    let (mut edges, mut edge_faces) = (Vec::<[u32; 2]>::new(), Vec::<Vec<u32>>::new());
    let mut face_edges = vec![[NONE; 3]; faces.len()];
    for (a, b, f, s) in half {
        if edges.last() != Some(&[a, b]) {
            edges.push([a, b]);
            edge_faces.push(Vec::new());
        }
        edge_faces.last_mut().unwrap().push(f);
        face_edges[f as usize][s] = edges.len() as u32 - 1;
    }
    assert!(edges.iter().all(|e| (e[1] as usize) < n));
    (edges, edge_faces, face_edges)
}

#[test]
fn matches_the_obvious_construction() {
    let torus = crate::shapes::torus(3.0, 1.0, 12, 7);
    // A soup with a fin, a bowtie, isolated vertices and shuffled winding.
    let soup = vec![
        [0, 1, 2],
        [1, 0, 3],
        [0, 1, 4],
        [2, 5, 6],
        [9, 2, 5],
        [7, 8, 2],
        [8, 7, 11],
    ];
    for (n, faces) in [
        (6, octahedron()),
        (5, vec![[0, 1, 2], [0, 3, 4]]),
        (12, soup),
        (torus.num_vertices(), torus.faces().to_vec()),
    ] {
        let t = Topology::build(n, &faces);
        let (edges, edge_faces, face_edges) = reference(n, &faces);
        assert_eq!(t.edges(), &edges[..]);
        for (e, expected) in edge_faces.iter().enumerate() {
            assert_eq!(t.edge_faces(e as u32), &expected[..]);
        }
        for (f, expected) in face_edges.iter().enumerate() {
            assert_eq!(t.face_edges(f as u32), *expected);
        }
        for v in 0..n as u32 {
            let mut expected: Vec<u32> = (0..edges.len() as u32)
                .filter(|&e| edges[e as usize].contains(&v))
                .collect();
            expected.sort_unstable();
            assert_eq!(t.vertex_edges(v), &expected[..]);
        }
    }
}

/// A pseudo-random soup of `count` triangles over `n` vertices (no repeated index in a
/// triangle): fins, bowties, duplicates and isolated vertices turn up often.
fn random_soup(n: u32, count: usize, seed: u64) -> Vec<[u32; 3]> {
    let mut state = seed;
    let mut next = || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        ((state >> 33) % u64::from(n)) as u32
    };
    let mut faces = Vec::new();
    while faces.len() < count {
        let t = [next(), next(), next()];
        if t[0] != t[1] && t[1] != t[2] && t[0] != t[2] {
            faces.push(t);
        }
    }
    faces
}

/// The kind of `v` the obvious way: its faces (found by scanning all of them) joined
/// across the neighbours they share two by two; manifold when one group holds them all
/// (a cycle when no edge at `v` has a single face, otherwise a path).
fn reference_kind(v: u32, faces: &[[u32; 3]]) -> VertexKind {
    let incident: Vec<usize> = (0..faces.len())
        .filter(|&f| faces[f].contains(&v))
        .collect();
    if incident.is_empty() {
        return VertexKind::Unreferenced;
    }
    let mut neighbours: Vec<u32> = incident
        .iter()
        .flat_map(|&f| faces[f].into_iter().filter(|&w| w != v))
        .collect();
    neighbours.sort_unstable();
    neighbours.dedup();
    let mut group: Vec<usize> = (0..incident.len()).collect();
    let mut single = 0;
    for w in neighbours {
        let sharing: Vec<usize> = (0..incident.len())
            .filter(|&i| faces[incident[i]].contains(&w))
            .collect();
        match sharing[..] {
            [_] => single += 1,
            [i, j] => {
                let (gi, gj) = (group[i], group[j]);
                for g in &mut group {
                    if *g == gj {
                        *g = gi;
                    }
                }
            }
            _ => return VertexKind::NonManifold,
        }
    }
    if group.iter().any(|&g| g != group[0]) {
        VertexKind::NonManifold
    } else if single == 0 {
        VertexKind::Interior
    } else {
        VertexKind::Boundary
    }
}

/// Components the obvious way: a flood fill over the faces, numbered by smallest vertex.
fn reference_components(n: usize, faces: &[[u32; 3]]) -> (Vec<u32>, usize) {
    let mut label: Vec<Option<usize>> = vec![None; n];
    let mut referenced = vec![false; n];
    for t in faces {
        for &v in t {
            referenced[v as usize] = true;
        }
    }
    let mut count = 0;
    for start in 0..n {
        if !referenced[start] || label[start].is_some() {
            continue;
        }
        label[start] = Some(count);
        let mut changed = true;
        while changed {
            changed = false;
            for t in faces {
                if t.iter().any(|&v| label[v as usize] == Some(count)) {
                    for &v in t {
                        if label[v as usize].is_none() {
                            label[v as usize] = Some(count);
                            changed = true;
                        }
                    }
                }
            }
        }
        count += 1;
    }
    let ids = label.iter().map(|l| l.map_or(NONE, |c| c as u32)).collect();
    (ids, count)
}

#[test]
fn random_soups_match_the_obvious_construction() {
    let torus = crate::shapes::torus(3.0, 1.0, 9, 6);
    let mut cases: Vec<(usize, Vec<[u32; 3]>)> = Vec::new();
    for seed in 0..12 {
        let n = 6 + 5 * seed as u32;
        cases.push((n as usize + 3, random_soup(n, 4 + 6 * seed as usize, seed)));
    }
    // A torus with a duplicated face, a fin on one of its edges and a second torus
    // sharing one vertex with it.
    let mut faces = torus.faces().to_vec();
    let tn = torus.num_vertices() as u32;
    faces.push(faces[5]);
    let [a, b, _] = faces[0];
    faces.push([b, a, tn]);
    faces.extend(
        torus
            .faces()
            .iter()
            .map(|t| t.map(|v| if v == 0 { 0 } else { v + tn })),
    );
    cases.push((2 * tn as usize + 1, faces));
    for (n, faces) in cases {
        let t = Topology::build(n, &faces);
        let (edges, edge_faces, face_edges) = reference(n, &faces);
        assert_eq!(t.edges(), &edges[..]);
        for (e, expected) in edge_faces.iter().enumerate() {
            assert_eq!(t.edge_faces(e as u32), &expected[..], "edge {e}");
        }
        for (f, expected) in face_edges.iter().enumerate() {
            assert_eq!(t.face_edges(f as u32), *expected, "face {f}");
        }
        for v in 0..n as u32 {
            let expected: Vec<u32> = (0..edges.len() as u32)
                .filter(|&e| edges[e as usize].contains(&v))
                .collect();
            assert_eq!(t.vertex_edges(v), &expected[..], "vertex {v}");
            let expected: Vec<u32> = (0..faces.len() as u32)
                .filter(|&f| faces[f as usize].contains(&v))
                .collect();
            assert_eq!(t.vertex_faces(v), &expected[..], "vertex {v}");
            assert_eq!(t.vertex_kind(v), reference_kind(v, &faces), "vertex {v}");
        }
        assert_eq!(t.vertex_components(&faces), reference_components(n, &faces));
        let edge_count = |k: usize| edge_faces.iter().filter(|f| f.len() == k).count();
        assert_eq!(t.count_edges(EdgeKind::Boundary), edge_count(1));
        assert_eq!(t.count_edges(EdgeKind::Manifold), edge_count(2));
        assert_eq!(
            t.count_edges(EdgeKind::NonManifold),
            edge_faces.len() - edge_count(1) - edge_count(2)
        );
        for kind in [
            VertexKind::Unreferenced,
            VertexKind::Interior,
            VertexKind::Boundary,
            VertexKind::NonManifold,
        ] {
            let expected = (0..n as u32)
                .filter(|&v| reference_kind(v, &faces) == kind)
                .count();
            assert_eq!(t.count_vertices(kind), expected, "{kind:?}");
        }
    }
}

#[test]
fn components_do_not_depend_on_the_number_of_threads() {
    // Many components of many faces, numbered out of order: the parallel union-find races.
    let sphere = crate::shapes::icosphere(1.0, 3);
    let nv = sphere.num_vertices() as u32;
    let copies = 24u32;
    let mut faces = Vec::new();
    for k in 0..copies {
        // Interleave the copies' vertex ids: copy k uses ids k, k + copies, ...
        faces.extend(
            sphere
                .faces()
                .iter()
                .map(|t| t.map(|v| v * copies + (k * 7) % copies)),
        );
    }
    // Join copies 3 and 5 through a triangle.
    faces.push([3, 5, copies + 3]);
    let n = (nv * copies) as usize;
    let t = Topology::build(n, &faces);
    let expected = reference_components(n, &faces);
    assert_eq!(expected.1, copies as usize - 1);
    for threads in [1, 2, 4, 8] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let built = pool.install(|| Topology::build(n, &faces));
        assert_eq!(built.vertex_kinds(), t.vertex_kinds());
        assert_eq!(built.edges(), t.edges());
        assert_eq!(pool.install(|| t.vertex_components(&faces)), expected);
    }
}

#[test]
fn vertex_edges_are_ordered_by_neighbour() {
    let faces = octahedron();
    let t = Topology::build(6, &faces);
    for v in 0..6 {
        let neighbours: Vec<u32> = t.neighbors(v).collect();
        assert!(
            neighbours.windows(2).all(|w| w[0] < w[1]),
            "{v}: {neighbours:?}"
        );
        assert!(t.vertex_edges(v).windows(2).all(|w| w[0] < w[1]));
    }
}

#[test]
fn components_and_unreferenced() {
    let faces = vec![[0, 1, 2], [3, 4, 5]];
    let t = Topology::build(7, &faces);
    let (id, n) = t.vertex_components(&faces);
    assert_eq!(n, 2);
    assert_eq!(id[6], NONE);
    assert_eq!(t.vertex_kind(6), VertexKind::Unreferenced);
    assert_ne!(id[0], id[3]);
}
