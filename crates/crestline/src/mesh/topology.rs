//! Connectivity of a triangle soup that may be anything but a clean manifold.
//!
//! Built once in O(F log d) (d the vertex degree) from the face list:
//! - vertex → incident faces and vertex → incident edges (compressed rows),
//! - unique undirected edges, edge → incident faces (a pair per edge, a side table for
//!   non-manifold edges),
//! - a [`VertexKind`] per vertex and an [`EdgeKind`] per edge;
//!
//! it keeps the faces, and looks a face's three edges up in the edge lists of its vertices
//! ([`Topology::face_edges`], a scan of a few entries) rather than storing them. About 65 bytes
//! per face in all (see `BENCHMARKS.md`, "Comparison with CGAL Ridges_3").
//!
//! Ordered one-rings are walked on demand across edges that have exactly two faces, so they
//! work whatever the orientation of the neighbouring faces; a vertex whose faces form more
//! than one fan (or that touches a non-manifold edge) is [`VertexKind::NonManifold`] and its
//! ring is returned fan by fan.
//!
//! The construction ([`Topology::from_faces`]) takes three passes: a counting sort of the
//! corners by vertex, which also copies each face's two other corners next to its entry; one
//! pass over the vertices' stars, each sorted once, by block of vertices; and a copy of the
//! blocks into place. On horse-x16 (1.55M faces, 2 threads) building the mesh took 0.21 s
//! (0.37 s of CPU) when each star was sorted twice and its faces looked up in the face list
//! (cache misses were most of a star's time), and takes 0.15 s (0.23 s of CPU). The copied
//! corners and the blocks' rooms cost about 26 bytes per face while it runs, given back
//! before the later, larger peaks; the result is unchanged.

use rayon::prelude::*;

/// A marker for "no element".
pub const NONE: u32 = u32::MAX;

/// How an edge is used by faces.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum EdgeKind {
    /// Exactly one incident face.
    Boundary,
    /// Exactly two incident faces.
    Manifold,
    /// Three or more incident faces.
    NonManifold,
}

/// How the faces around a vertex fit together.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum VertexKind {
    /// No face uses the vertex.
    Unreferenced,
    /// One closed fan of faces.
    Interior,
    /// One open fan whose two end edges are boundary edges.
    Boundary,
    /// Several fans, or an incident non-manifold edge.
    NonManifold,
}

/// One fan of faces around a vertex, in walking order.
///
/// `faces[i]` lies between `vertices[i]` and `vertices[i + 1]` (indices modulo
/// `vertices.len()` when the fan is closed). An open fan has one vertex more than faces.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Fan {
    /// Neighbouring vertices in order.
    pub vertices: Vec<u32>,
    /// Faces in order.
    pub faces: Vec<u32>,
    /// True when the walk came back to its first face.
    pub closed: bool,
}

/// Mesh connectivity. See the module docs.
#[derive(Debug, Clone, Default)]
pub struct Topology {
    vertex_face_offsets: Vec<u32>,
    vertex_faces: Vec<u32>,
    vertex_edge_offsets: Vec<u32>,
    vertex_edges: Vec<u32>,
    edges: Vec<[u32; 2]>,
    /// Per edge its one or two faces (`NONE` in the second slot of a boundary edge), or for a
    /// non-manifold edge `[NONE, i]` with `many_faces[i]` its number of faces and the faces
    /// after it: 8 bytes per edge where compressed rows took 12 (and 4 more per face).
    edge_faces: Vec<[u32; 2]>,
    many_faces: Vec<u32>,
    /// The triangles (the mesh's faces are these). Face → edge is looked up in the upper
    /// part of a vertex's edges rather than stored: 12 bytes per face less.
    faces: Vec<[u32; 3]>,
    vertex_kinds: Vec<VertexKind>,
    /// Per vertex, what its edges are: [`OPEN_EDGE`] and [`INCONSISTENT_EDGE`] bits, found
    /// while its star is sorted (orientation checks then read one byte per vertex instead of
    /// the faces of every edge).
    vertex_edge_flags: Vec<u8>,
}

/// A bit of [`Topology::vertex_edge_flags`]: an edge of the vertex has one face or more than
/// two.
const OPEN_EDGE: u8 = 1;
/// A bit of [`Topology::vertex_edge_flags`]: an edge of the vertex has two faces that run
/// through it in the same direction (their windings disagree).
const INCONSISTENT_EDGE: u8 = 2;

impl Topology {
    /// Builds the connectivity of `faces` over `num_vertices` vertices.
    ///
    /// Indices must be in range and faces must not repeat an index (as [`super::TriMesh::new`]
    /// guarantees).
    pub fn build(num_vertices: usize, faces: &[[u32; 3]]) -> Self {
        Self::from_faces(num_vertices, faces.to_vec())
    }

    /// [`Topology::build`] taking the faces over (the topology keeps them: see
    /// [`Topology::faces`]).
    pub fn from_faces(num_vertices: usize, face_list: Vec<[u32; 3]>) -> Self {
        let faces = &face_list[..];
        let n = num_vertices;
        let (vertex_face_offsets, vertex_faces, others) = vertex_face_rows(n, faces);
        let faces_of = |v: usize| {
            &vertex_faces[vertex_face_offsets[v] as usize..vertex_face_offsets[v + 1] as usize]
        };

        // Edges are numbered vertex by vertex: the edges (v, w) with w > v, by increasing w.
        // Ids therefore follow the pair (smaller endpoint, larger endpoint), as a global sort
        // of the half-edges would give, but each vertex only looks at its own faces: parallel.
        // Each star is gathered and sorted once, block by block of vertices, with the vertex's
        // kind, into the block's room in two arrays shared by the blocks: the vertices' rows
        // with neighbours in place of the edges, and the faces of the edges to the neighbours
        // above (a non-manifold edge marked `[NONE, count]`, and listed by the block, gets its
        // faces in a side table below). A vertex has at most two neighbours per face, which bounds
        // a block's room. The arrays are zeroed allocations: only the pages the blocks write
        // are touched, and all of them go back to the system when the arrays are dropped (with
        // a buffer per block, they stayed with the allocator and raised the peak of the later
        // steps by 20 MB on horse-x16). The numbers of neighbours below and above each vertex
        // then give the offsets, and the blocks are copied into place.
        let room: Vec<usize> = (0..=n.div_ceil(ROW_BLOCK))
            .map(|b| 2 * vertex_face_offsets[(b * ROW_BLOCK).min(n)] as usize)
            .collect();
        let mut neighbours = vec![0u32; room[room.len() - 1]];
        let mut above_faces = vec![[0u32; 2]; room[room.len() - 1]];
        let mut counts = vec![[0u32; 2]; n];
        let mut vertex_kinds = vec![VertexKind::Unreferenced; n];
        let mut vertex_edge_flags = vec![0u8; n];
        let many: Vec<Vec<u32>> = counts
            .par_chunks_mut(ROW_BLOCK)
            .zip(vertex_kinds.par_chunks_mut(ROW_BLOCK))
            .zip(vertex_edge_flags.par_chunks_mut(ROW_BLOCK))
            .zip(split_at(&mut neighbours, &room))
            .zip(split_at(&mut above_faces, &room))
            .enumerate()
            .map_init(
                Star::default,
                |star, (b, ((((counts, kinds), flags), neighbours), pairs))| {
                    let first = b * ROW_BLOCK;
                    // Entries written in the two rooms, and the non-manifold edges.
                    let (mut written, mut above, mut many) = (0, 0, Vec::new());
                    for (i, ((count, kind), flags)) in
                        counts.iter_mut().zip(kinds).zip(flags).enumerate()
                    {
                        let v = first + i;
                        let (start, end) = (vertex_face_offsets[v], vertex_face_offsets[v + 1]);
                        let incident = &vertex_faces[start as usize..end as usize];
                        let corners = &others[start as usize..end as usize];
                        star.gather(corners);
                        *kind = star.kind(incident.len());
                        *flags = star.edge_flags(corners);
                        let before = written;
                        for r in 0..star.runs.len() {
                            let (w, shared) = star.run(r);
                            neighbours[written] = w;
                            written += 1;
                            if w as usize > v {
                                let face = |c: u64| incident[position(c)];
                                pairs[above] = match *shared {
                                    [a] => [face(a), NONE],
                                    [a, b] => [face(a), face(b)],
                                    _ => {
                                        many.push(above as u32);
                                        [NONE, shared.len() as u32]
                                    }
                                };
                                above += 1;
                            }
                        }
                        let row = &neighbours[before..written];
                        let below = row.partition_point(|&w| (w as usize) < v);
                        *count = [below as u32, (row.len() - below) as u32];
                    }
                    many
                },
            )
            .collect();
        drop(others);
        let edge_start = prefix_sums(counts.iter().map(|c| c[1]));
        let vertex_edge_offsets = prefix_sums(counts.iter().map(|c| c[0] + c[1]));
        drop(counts);

        // The blocks in place. The edge to a neighbour `u` below `v` is found among the
        // neighbours above `u` in the block of `u`, which are sorted.
        let m = edge_start[n] as usize;
        // Every entry is written below: zeroed allocations, which the system provides without
        // touching the memory, cost less than filling with `NONE`.
        let mut edges = vec![[0u32; 2]; m];
        let mut edge_faces = vec![[0u32; 2]; m];
        let mut vertex_edges = vec![0u32; vertex_edge_offsets[n] as usize];
        // The row of `v` in the room of its block.
        let row_of = |v: usize| {
            let (b, base) = (
                v / ROW_BLOCK,
                vertex_edge_offsets[v / ROW_BLOCK * ROW_BLOCK],
            );
            let start = room[b] + (vertex_edge_offsets[v] - base) as usize;
            &neighbours[start..room[b] + (vertex_edge_offsets[v + 1] - base) as usize]
        };
        split_rows(&mut edges, &edge_start, ROW_BLOCK)
            .into_par_iter()
            .zip(split_rows(&mut edge_faces, &edge_start, ROW_BLOCK))
            .zip(split_rows(
                &mut vertex_edges,
                &vertex_edge_offsets,
                ROW_BLOCK,
            ))
            .for_each(|(((rows, edges), (b, pairs)), (_, row_edges))| {
                pairs.copy_from_slice(&above_faces[room[b.start / ROW_BLOCK]..][..pairs.len()]);
                let first_edge = edge_start[rows.start];
                let mut k = 0;
                let mut slot = 0;
                for v in rows {
                    let row = row_of(v);
                    for (&w, id) in row.iter().zip(&mut row_edges[slot..slot + row.len()]) {
                        if (w as usize) < v {
                            let u = w as usize;
                            let row = row_of(u);
                            let above =
                                &row[row.len() - (edge_start[u + 1] - edge_start[u]) as usize..];
                            *id =
                                edge_start[u] + above.partition_point(|&x| (x as usize) < v) as u32;
                        } else {
                            edges[k] = [v as u32, w];
                            *id = first_edge + k as u32;
                            k += 1;
                        }
                    }
                    slot += row.len();
                }
            });
        drop(neighbours);
        drop(above_faces);

        // Side table of the non-manifold edges: `[count, faces...]`, found at the index the
        // edge's pair holds after its `NONE`.
        let mut many_faces = Vec::new();
        for (b, many) in many.iter().enumerate() {
            for &k in many {
                let e = (edge_start[b * ROW_BLOCK] + k) as usize;
                let [v, w] = edges[e];
                let pair = &mut edge_faces[e];
                let start = many_faces.len() as u32;
                many_faces.push(pair[1]);
                many_faces.extend(
                    faces_of(v as usize)
                        .iter()
                        .filter(|&&f| faces[f as usize].contains(&w)),
                );
                pair[1] = start;
            }
        }
        drop(edge_start);

        Topology {
            vertex_face_offsets,
            vertex_faces,
            vertex_edge_offsets,
            vertex_edges,
            edges,
            edge_faces,
            many_faces,
            faces: face_list,
            vertex_kinds,
            vertex_edge_flags,
        }
    }

    /// Winds the faces for which `flip(index, corners)` holds the other way (swaps their
    /// corners 1 and 2). Nothing else changes: the connectivity does not depend on the winding.
    /// The consistency of the windings does; it is found again, unless `whole_components`
    /// says that `flip` takes all the faces of a connected component or none (which keeps it).
    pub(crate) fn flip_faces(
        &mut self,
        flip: impl Fn(usize, &[u32; 3]) -> bool + Sync,
        whole_components: bool,
    ) {
        self.faces.par_iter_mut().enumerate().for_each(|(f, t)| {
            if flip(f, t) {
                t.swap(1, 2);
            }
        });
        if whole_components {
            return;
        }
        let mut flags = std::mem::take(&mut self.vertex_edge_flags);
        flags.par_iter_mut().enumerate().for_each(|(v, flags)| {
            let inconsistent = self.vertex_edges(v as u32).iter().any(|&e| {
                let edge = self.edge(e);
                match *self.edge_faces(e) {
                    [f, g] => {
                        runs_through(&self.faces[f as usize], edge)
                            == runs_through(&self.faces[g as usize], edge)
                    }
                    _ => false,
                }
            });
            *flags =
                (*flags & !INCONSISTENT_EDGE) | if inconsistent { INCONSISTENT_EDGE } else { 0 };
        });
        self.vertex_edge_flags = flags;
    }

    /// True when an edge of `v` has one face or more than two (see [`Topology::edge_faces`]).
    #[inline]
    pub fn has_open_edge(&self, v: u32) -> bool {
        self.vertex_edge_flags[v as usize] & OPEN_EDGE != 0
    }

    /// True when an edge of `v` has two faces that run through it in the same direction:
    /// their windings disagree.
    #[inline]
    pub fn has_inconsistent_edge(&self, v: u32) -> bool {
        self.vertex_edge_flags[v as usize] & INCONSISTENT_EDGE != 0
    }

    /// Number of vertices (including unreferenced ones).
    pub fn num_vertices(&self) -> usize {
        self.vertex_kinds.len()
    }

    /// Number of unique undirected edges.
    pub fn num_edges(&self) -> usize {
        self.edges.len()
    }

    /// Endpoints of edge `e`, smaller index first.
    #[inline]
    pub fn edge(&self, e: u32) -> [u32; 2] {
        self.edges[e as usize]
    }

    /// All edges, smaller endpoint first.
    pub fn edges(&self) -> &[[u32; 2]] {
        &self.edges
    }

    /// Faces incident to edge `e`.
    #[inline]
    pub fn edge_faces(&self, e: u32) -> &[u32] {
        let pair = &self.edge_faces[e as usize];
        if pair[0] == NONE {
            let start = pair[1] as usize + 1;
            &self.many_faces[start..start + self.many_faces[start - 1] as usize]
        } else if pair[1] == NONE {
            &pair[..1]
        } else {
            pair
        }
    }

    /// Boundary, manifold or non-manifold.
    #[inline]
    pub fn edge_kind(&self, e: u32) -> EdgeKind {
        match self.edge_faces(e).len() {
            0 | 1 => EdgeKind::Boundary,
            2 => EdgeKind::Manifold,
            _ => EdgeKind::NonManifold,
        }
    }

    /// The edges of face `f`: slot `s` joins corner `s` to corner `s + 1`.
    #[inline]
    pub fn face_edges(&self, f: u32) -> [u32; 3] {
        let t = self.faces[f as usize];
        [0, 1, 2].map(|s| self.edge_between(t[s], t[(s + 1) % 3]).unwrap_or(NONE))
    }

    /// The edge joining `a` and `b`, if there is one: a scan of the edges from the smaller
    /// to its larger neighbours (the last entries of its edge list, consecutive ids).
    #[inline]
    pub fn edge_between(&self, a: u32, b: u32) -> Option<u32> {
        let (low, high) = (a.min(b), a.max(b));
        for &e in self.vertex_edges(low).iter().rev() {
            let [x, y] = self.edges[e as usize];
            if x != low || y < high {
                return None;
            }
            if y == high {
                return Some(e);
            }
        }
        None
    }

    /// The triangles the connectivity was built from.
    pub fn faces(&self) -> &[[u32; 3]] {
        &self.faces
    }

    /// The face across slot `s` of face `f`, when that edge has exactly two faces.
    #[inline]
    pub fn face_across(&self, f: u32, s: usize) -> Option<u32> {
        match *self.edge_faces(self.face_edges(f)[s]) {
            [a, b] => Some(if a == f { b } else { a }),
            _ => None,
        }
    }

    /// The faces across the three slots of face `f` (see [`Topology::face_across`]).
    #[inline]
    pub fn face_neighbors(&self, f: u32) -> [Option<u32>; 3] {
        [0, 1, 2].map(|s| self.face_across(f, s))
    }

    /// Faces incident to vertex `v`, unordered.
    #[inline]
    pub fn vertex_faces(&self, v: u32) -> &[u32] {
        let v = v as usize;
        &self.vertex_faces
            [self.vertex_face_offsets[v] as usize..self.vertex_face_offsets[v + 1] as usize]
    }

    /// Edges incident to vertex `v`, in increasing id order. Ids follow the pair (smaller
    /// endpoint, larger endpoint), so the edges to neighbours below `v` come first, then
    /// those to neighbours above it, each group by increasing neighbour.
    #[inline]
    pub fn vertex_edges(&self, v: u32) -> &[u32] {
        let v = v as usize;
        &self.vertex_edges
            [self.vertex_edge_offsets[v] as usize..self.vertex_edge_offsets[v + 1] as usize]
    }

    /// The vertex → edge lists of every vertex, one after the other, and their offsets
    /// (`vertex_edges(v)` is `lists[offsets[v]..offsets[v + 1]]`), for arrays laid out per
    /// entry of these lists.
    pub(crate) fn vertex_edge_rows(&self) -> (&[u32], &[u32]) {
        (&self.vertex_edge_offsets, &self.vertex_edges)
    }

    /// Neighbours of `v` (each once), in increasing order.
    pub fn neighbors(&self, v: u32) -> impl Iterator<Item = u32> + '_ {
        self.vertex_edges(v).iter().map(move |&e| {
            let [a, b] = self.edges[e as usize];
            if a == v { b } else { a }
        })
    }

    /// Number of edges at `v`.
    #[inline]
    pub fn degree(&self, v: u32) -> usize {
        let v = v as usize;
        (self.vertex_edge_offsets[v + 1] - self.vertex_edge_offsets[v]) as usize
    }

    /// Kind of vertex `v`.
    #[inline]
    pub fn vertex_kind(&self, v: u32) -> VertexKind {
        self.vertex_kinds[v as usize]
    }

    /// Kinds of all vertices.
    pub fn vertex_kinds(&self) -> &[VertexKind] {
        &self.vertex_kinds
    }

    /// Number of vertices of kind `kind`.
    pub fn count_vertices(&self, kind: VertexKind) -> usize {
        self.vertex_kinds.par_iter().filter(|&&k| k == kind).count()
    }

    /// Number of edges of kind `kind`.
    pub fn count_edges(&self, kind: EdgeKind) -> usize {
        if kind == EdgeKind::NonManifold {
            // Exactly the edges of the side table (usually none): walked from entry to entry.
            let mut count = 0;
            let mut at = 0;
            while at < self.many_faces.len() {
                count += 1;
                at += 1 + self.many_faces[at] as usize;
            }
            return count;
        }
        (0..self.num_edges() as u32)
            .into_par_iter()
            .filter(|&e| self.edge_kind(e) == kind)
            .count()
    }

    /// True when `v` is on the boundary or non-manifold (its ring is not one closed fan).
    #[inline]
    pub fn is_boundary_vertex(&self, v: u32) -> bool {
        !matches!(self.vertex_kinds[v as usize], VertexKind::Interior)
    }

    /// The ordered one-ring of `v`, fan by fan (one fan unless `v` is non-manifold).
    ///
    /// For a consistently oriented manifold mesh the order is counter-clockwise around the
    /// face normals. Open fans start at a boundary (or non-manifold) edge.
    pub fn fans(&self, v: u32, faces: &[[u32; 3]]) -> Vec<Fan> {
        let mut fans = Vec::new();
        self.walk_fans(v, faces, &mut fans);
        fans
    }

    /// [`Topology::fans`] into a reusable buffer (cleared first).
    pub fn walk_fans(&self, v: u32, faces: &[[u32; 3]], fans: &mut Vec<Fan>) {
        fans.clear();
        let incident = self.vertex_faces(v);
        let mut visited = vec![false; incident.len()];
        let slot_of = |f: u32| incident.iter().position(|&g| g == f);
        // The two neighbours of `v` in face `f`, in the face's winding order after `v`.
        let others = |f: u32| {
            let t = faces[f as usize];
            let c = t.iter().position(|&x| x == v).unwrap_or(0);
            (t[(c + 1) % 3], t[(c + 2) % 3])
        };
        let edge_to = |f: u32, u: u32| {
            let t = faces[f as usize];
            let fe = self.face_edges(f);
            (0..3)
                .find(|&s| {
                    let (a, b) = (t[s], t[(s + 1) % 3]);
                    (a == v && b == u) || (a == u && b == v)
                })
                .map(|s| fe[s])
                .unwrap_or(NONE)
        };
        let crossable = |e: u32| e != NONE && self.edge_faces(e).len() == 2;

        while let Some(first) = self.pick_fan_start(incident, &visited, &others, &edge_to) {
            let f0 = incident[first];
            let (a, b) = others(f0);
            // Enter through the edge that cannot be crossed, if there is one.
            let (entry, exit) = if !crossable(edge_to(f0, a)) || crossable(edge_to(f0, b)) {
                (a, b)
            } else {
                (b, a)
            };
            let mut fan = Fan {
                vertices: vec![entry, exit],
                faces: vec![f0],
                closed: false,
            };
            visited[first] = true;
            let (mut f, mut w) = (f0, exit);
            loop {
                let e = edge_to(f, w);
                if !crossable(e) {
                    break;
                }
                let [g0, g1] = [self.edge_faces(e)[0], self.edge_faces(e)[1]];
                let g = if g0 == f { g1 } else { g0 };
                let Some(k) = slot_of(g) else { break };
                if visited[k] {
                    fan.closed = g == f0;
                    break;
                }
                visited[k] = true;
                let (x, y) = others(g);
                let next = if x == w { y } else { x };
                fan.faces.push(g);
                f = g;
                w = next;
                fan.vertices.push(next);
            }
            if fan.closed {
                // The last vertex pushed is the entry vertex again.
                fan.vertices.pop();
            }
            fans.push(fan);
        }
    }

    fn pick_fan_start(
        &self,
        incident: &[u32],
        visited: &[bool],
        others: &impl Fn(u32) -> (u32, u32),
        edge_to: &impl Fn(u32, u32) -> u32,
    ) -> Option<usize> {
        let open_end = |f: u32| {
            let (a, b) = others(f);
            [a, b]
                .iter()
                .any(|&u| self.edge_faces(edge_to(f, u)).len() != 2)
        };
        let mut fallback = None;
        for (k, &f) in incident.iter().enumerate() {
            if visited[k] {
                continue;
            }
            if open_end(f) {
                return Some(k);
            }
            fallback.get_or_insert(k);
        }
        fallback
    }

    /// Connected components over faces sharing a vertex: a component id per vertex
    /// (`NONE` for unreferenced vertices) and the number of components, numbered by their
    /// smallest vertex.
    ///
    /// A union-find over the faces' corners, in parallel: links are made by compare-and-swap
    /// and always point from a root to a smaller vertex, so every set ends up rooted at its
    /// smallest vertex whatever the order the threads link in.
    pub fn vertex_components(&self, faces: &[[u32; 3]]) -> (Vec<u32>, usize) {
        use std::sync::atomic::{AtomicU32, Ordering::Relaxed};
        let n = self.num_vertices();
        let parent: Vec<AtomicU32> = (0..n as u32).into_par_iter().map(AtomicU32::new).collect();
        // Parents only ever move to smaller ancestors, so a stale read is still an ancestor.
        let find = |mut x: u32| loop {
            let p = parent[x as usize].load(Relaxed);
            if p == x {
                return x;
            }
            let g = parent[p as usize].load(Relaxed);
            if g != p {
                // Path halving; losing the race to another thread is harmless.
                let _ = parent[x as usize].compare_exchange_weak(p, g, Relaxed, Relaxed);
            }
            x = g;
        };
        faces.par_iter().for_each(|t| {
            for s in 1..3 {
                let (mut a, mut b) = (t[0], t[s]);
                loop {
                    (a, b) = (find(a), find(b));
                    if a == b {
                        break;
                    }
                    let (low, high) = (a.min(b), a.max(b));
                    if parent[high as usize]
                        .compare_exchange(high, low, Relaxed, Relaxed)
                        .is_ok()
                    {
                        break;
                    }
                }
            }
        });
        let roots: Vec<u32> = (0..n as u32)
            .into_par_iter()
            .map(|v| match self.vertex_kinds[v as usize] {
                VertexKind::Unreferenced => NONE,
                _ => find(v),
            })
            .collect();
        drop(parent);
        let mut number = vec![NONE; n];
        let mut count = 0u32;
        for (v, &r) in roots.iter().enumerate() {
            if r as usize == v {
                number[v] = count;
                count += 1;
            }
        }
        let id = roots
            .par_iter()
            .map(|&r| if r == NONE { NONE } else { number[r as usize] })
            .collect();
        (id, count as usize)
    }

    /// Number of boundary loops: closed walks along boundary edges, following the direction
    /// the faces give them where that is consistent.
    pub fn boundary_loops(&self, faces: &[[u32; 3]]) -> usize {
        // Directed boundary half-edges (as wound in their face), grouped by start vertex.
        let boundary: Vec<(u32, u32, u32)> = self
            .edges
            .iter()
            .enumerate()
            .filter(|&(e, _)| self.edge_faces(e as u32).len() == 1)
            .map(|(e, &[a, b])| {
                let f = self.edge_faces(e as u32)[0];
                let t = faces[f as usize];
                let forward = (0..3).any(|s| t[s] == a && t[(s + 1) % 3] == b);
                if forward {
                    (a, b, e as u32)
                } else {
                    (b, a, e as u32)
                }
            })
            .collect();
        if boundary.is_empty() {
            return 0;
        }
        let pairs = boundary
            .iter()
            .enumerate()
            .map(|(i, &(a, _, _))| (a, i as u32));
        let (out_off, out) = compressed_rows(self.num_vertices(), pairs);
        let pairs_in = boundary
            .iter()
            .enumerate()
            .map(|(i, &(_, b, _))| (b, i as u32));
        let (in_off, inc) = compressed_rows(self.num_vertices(), pairs_in);
        let row = |off: &[u32], data: &'_ [u32], v: u32| -> Vec<u32> {
            data[off[v as usize] as usize..off[v as usize + 1] as usize].to_vec()
        };
        let mut used = vec![false; boundary.len()];
        let mut loops = 0;
        for start in 0..boundary.len() {
            if used[start] {
                continue;
            }
            loops += 1;
            used[start] = true;
            let origin = boundary[start].0;
            let mut at = boundary[start].1;
            while at != origin {
                // Prefer continuing forward; fall back to a reversed edge (inconsistent winding).
                let next = row(&out_off, &out, at)
                    .into_iter()
                    .find(|&i| !used[i as usize])
                    .map(|i| (i, boundary[i as usize].1))
                    .or_else(|| {
                        row(&in_off, &inc, at)
                            .into_iter()
                            .find(|&i| !used[i as usize])
                            .map(|i| (i, boundary[i as usize].0))
                    });
                let Some((i, to)) = next else { break };
                used[i as usize] = true;
                at = to;
            }
        }
        loops
    }
}

/// Rows per parallel work item when filling compressed rows.
pub(crate) const ROW_BLOCK: usize = 2048;

/// Offsets from counts: `[0, c0, c0 + c1, ...]` (one more than the counts).
fn prefix_sums(counts: impl ExactSizeIterator<Item = u32>) -> Vec<u32> {
    let mut offsets = Vec::with_capacity(counts.len() + 1);
    let mut total = 0u32;
    offsets.push(0);
    for c in counts {
        total += c;
        offsets.push(total);
    }
    offsets
}

/// Cuts `values` at `bounds` (increasing, from 0 to at most `values.len()`): one piece per
/// pair of consecutive bounds.
pub(crate) fn split_at<'a, T>(mut values: &'a mut [T], bounds: &[usize]) -> Vec<&'a mut [T]> {
    let mut pieces = Vec::with_capacity(bounds.len().saturating_sub(1));
    for pair in bounds.windows(2) {
        let (piece, rest) = values.split_at_mut(pair[1] - pair[0]);
        pieces.push(piece);
        values = rest;
    }
    pieces
}

/// The vertex → face rows of `faces` over `n` vertices, each row by increasing face (offsets
/// and faces), and beside every entry the face's two other corners: the stars then read their
/// corners in order rather than looking them up face by face, mostly cache misses on large
/// meshes. A counting sort, with the vertices cut into one range per worker thread: each
/// worker reads all the faces and counts, then places, only the corners at its own vertices,
/// so every row is in face order whatever the number of workers and no write is shared.
/// (Threads sharing atomic counters were several times slower; a two-level parallel sort, by
/// block of vertices then by vertex, read the faces twice out of order and did twice the
/// work: no faster on 2 threads than one thread, measured on 1.5M faces.)
fn vertex_face_rows(n: usize, faces: &[[u32; 3]]) -> (Vec<u32>, Vec<u32>, Vec<[u32; 2]>) {
    let parts = rayon::current_num_threads().clamp(1, 16).min(n.max(1));
    let bounds: Vec<usize> = (0..=parts).map(|k| k * n / parts).collect();
    let mut offsets = vec![0u32; n + 1];
    split_at(&mut offsets[1..], &bounds)
        .into_par_iter()
        .zip(bounds.par_windows(2))
        .for_each(|(counts, range)| {
            let (first, len) = (range[0] as u32, counts.len() as u32);
            for t in faces {
                for &v in t {
                    let i = v.wrapping_sub(first);
                    if i < len {
                        counts[i as usize] += 1;
                    }
                }
            }
        });
    for i in 0..n {
        offsets[i + 1] += offsets[i];
    }
    let total = offsets[n] as usize;
    let mut values = vec![0u32; total];
    let mut others = vec![[0u32; 2]; total];
    let starts: Vec<usize> = bounds.iter().map(|&b| offsets[b] as usize).collect();
    split_at(&mut values, &starts)
        .into_par_iter()
        .zip(split_at(&mut others, &starts))
        .zip(bounds.par_windows(2))
        .for_each(|((values, others), range)| {
            let base = offsets[range[0]];
            let mut cursor: Vec<u32> = offsets[range[0]..range[1]]
                .iter()
                .map(|&o| o - base)
                .collect();
            let (first, len) = (range[0] as u32, cursor.len() as u32);
            for (f, t) in faces.iter().enumerate() {
                for s in 0..3 {
                    let i = t[s].wrapping_sub(first);
                    if i < len {
                        let c = &mut cursor[i as usize];
                        values[*c as usize] = f as u32;
                        others[*c as usize] = [t[(s + 1) % 3], t[(s + 2) % 3]];
                        *c += 1;
                    }
                }
            }
        });
    (offsets, values, others)
}

/// The neighbours of one vertex with the faces it shares with each (scratch space reused from
/// vertex to vertex).
#[derive(Default)]
struct Star {
    /// The corners of the vertex's faces other than the vertex, as `vertex << 32 | position`
    /// (of the face in the vertex's face list), sorted: by neighbour, then by face.
    corners: Vec<u64>,
    /// Per neighbour, in increasing order: its first corner and its number of corners (the
    /// faces it shares with the vertex).
    runs: Vec<(u32, u32)>,
    /// Per face (by position), the runs of its two other corners.
    face_runs: Vec<[u32; 2]>,
}

impl Star {
    /// Gathers and sorts the star of a vertex from the other corners of its faces, by
    /// increasing face (see [`vertex_face_rows`]).
    fn gather(&mut self, others: &[[u32; 2]]) {
        self.corners.clear();
        for (i, pair) in others.iter().enumerate() {
            self.corners
                .extend(pair.map(|w| u64::from(w) << 32 | i as u64));
        }
        self.corners.sort_unstable();
        self.runs.clear();
        let mut start = 0;
        for chunk in self.corners.chunk_by(|a, b| a >> 32 == b >> 32) {
            self.runs.push((start, chunk.len() as u32));
            start += chunk.len() as u32;
        }
    }

    /// The [`OPEN_EDGE`] and [`INCONSISTENT_EDGE`] bits of the vertex whose star was
    /// gathered from `others` (its faces' other corners, next then previous): an edge to a
    /// neighbour runs the same way through its two faces when the neighbour comes next in
    /// both or previous in both.
    fn edge_flags(&self, others: &[[u32; 2]]) -> u8 {
        let mut flags = 0;
        for r in 0..self.runs.len() {
            match self.run(r) {
                (w, &[a, b]) => {
                    if (others[position(a)][0] == w) == (others[position(b)][0] == w) {
                        flags |= INCONSISTENT_EDGE;
                    }
                }
                _ => flags |= OPEN_EDGE,
            }
        }
        flags
    }

    /// Neighbour `r` (in increasing order) and its corners: the faces it shares with the
    /// vertex, by increasing position (see [`position`]).
    fn run(&self, r: usize) -> (u32, &[u64]) {
        let (start, len) = self.runs[r];
        let corners = &self.corners[start as usize..(start + len) as usize];
        ((corners[0] >> 32) as u32, corners)
    }

    /// The kind of the vertex, which has `faces` faces.
    ///
    /// A neighbour shared by more than two faces is a non-manifold edge. Otherwise the faces
    /// linked across the edges with two faces form simple paths and cycles: the vertex is
    /// manifold exactly when the one through its first face holds every face (interior when
    /// it is a cycle, boundary when it is a path).
    fn kind(&mut self, faces: usize) -> VertexKind {
        if faces == 0 {
            return VertexKind::Unreferenced;
        }
        if self.runs.iter().any(|&(_, len)| len > 2) {
            return VertexKind::NonManifold;
        }
        self.face_runs.clear();
        self.face_runs.resize(faces, [NONE; 2]);
        for (r, &(start, len)) in self.runs.iter().enumerate() {
            for &c in &self.corners[start as usize..(start + len) as usize] {
                let slots = &mut self.face_runs[position(c)];
                slots[usize::from(slots[0] != NONE)] = r as u32;
            }
        }
        // From the first face across run `r`, on around the vertex: faces seen (with the
        // first) and whether the walk came back to the first face.
        let walk = |mut r: u32| {
            let (mut at, mut count) = (0u32, 1usize);
            while count <= faces {
                let (start, len) = self.runs[r as usize];
                if len != 2 {
                    return (count, false);
                }
                let pair = &self.corners[start as usize..start as usize + 2];
                let [i, j] = [0, 1].map(|k| position(pair[k]) as u32);
                let next = if i == at { j } else { i };
                if next == 0 {
                    return (count, true);
                }
                count += 1;
                let [a, b] = self.face_runs[next as usize];
                r = if a == r { b } else { a };
                at = next;
            }
            (count, false)
        };
        let [ahead_run, behind_run] = self.face_runs[0];
        let (ahead, closed) = walk(ahead_run);
        if closed {
            return if ahead == faces {
                VertexKind::Interior
            } else {
                VertexKind::NonManifold
            };
        }
        let (behind, _) = walk(behind_run);
        if ahead + behind - 1 == faces {
            VertexKind::Boundary
        } else {
            VertexKind::NonManifold
        }
    }
}

/// Whether `triangle` runs through `edge` from its first to its second vertex.
fn runs_through(triangle: &[u32; 3], [a, b]: [u32; 2]) -> bool {
    let i = triangle.iter().position(|&v| v == a).unwrap_or(0);
    triangle[(i + 1) % 3] == b
}

/// The position of the face of a corner of [`Star::corners`] in the vertex's face list.
#[inline]
fn position(corner: u64) -> usize {
    (corner & 0xffff_ffff) as usize
}

/// Cuts `values`, laid out in compressed rows with offsets `offsets`, into pieces of `block`
/// rows each: `(rows, entries of those rows)`, for filling the rows in parallel.
pub(crate) fn split_rows<'a, T>(
    values: &'a mut [T],
    offsets: &[u32],
    block: usize,
) -> Vec<(std::ops::Range<usize>, &'a mut [T])> {
    let rows = offsets.len().saturating_sub(1);
    let firsts: Vec<usize> = (0..rows).step_by(block.max(1)).chain([rows]).collect();
    let bounds: Vec<usize> = firsts
        .iter()
        .map(|&r| (offsets[r] - offsets[0]) as usize)
        .collect();
    firsts
        .windows(2)
        .map(|pair| pair[0]..pair[1])
        .zip(split_at(values, &bounds))
        .collect()
}

/// Compressed rows from (row, value) pairs: offsets of length `rows + 1` and values grouped by
/// row, in the order the pairs came.
fn compressed_rows(
    rows: usize,
    pairs: impl Iterator<Item = (u32, u32)> + Clone,
) -> (Vec<u32>, Vec<u32>) {
    let mut offsets = vec![0u32; rows + 1];
    for (r, _) in pairs.clone() {
        offsets[r as usize + 1] += 1;
    }
    for i in 0..rows {
        offsets[i + 1] += offsets[i];
    }
    let mut cursor = offsets.clone();
    let mut values = vec![0u32; offsets[rows] as usize];
    for (r, x) in pairs {
        let c = &mut cursor[r as usize];
        values[*c as usize] = x;
        *c += 1;
    }
    (offsets, values)
}

#[cfg(test)]
mod tests {
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
        vec![
            [0, 2, 4],
            [2, 1, 4],
            [1, 3, 4],
            [3, 0, 4],
            [2, 0, 5],
            [1, 2, 5],
            [3, 1, 5],
            [0, 3, 5],
        ]
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
}
