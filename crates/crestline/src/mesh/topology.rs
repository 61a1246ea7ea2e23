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
}

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
        let (vertex_face_offsets, vertex_faces) =
            parallel_compressed_rows(num_vertices, faces.len(), |f| {
                faces[f].map(|v| (v, f as u32))
            });

        // Edges are numbered vertex by vertex: the edges (v, w) with w > v, by increasing w.
        // Ids therefore follow the pair (smaller endpoint, larger endpoint), as a global sort
        // of the half-edges would give, but each vertex only looks at its own faces: parallel,
        // and nothing larger than the result is allocated.
        let n = num_vertices;
        let faces_of = |v: usize| {
            &vertex_faces[vertex_face_offsets[v] as usize..vertex_face_offsets[v + 1] as usize]
        };
        // The neighbours above `v`, sorted and deduplicated, into `scratch`.
        let upper_neighbours = |v: usize, scratch: &mut Vec<u32>| {
            scratch.clear();
            for &f in faces_of(v) {
                scratch.extend(faces[f as usize].iter().filter(|&&w| w as usize > v));
            }
            scratch.sort_unstable();
            scratch.dedup();
        };
        let upper_counts: Vec<u32> = (0..n)
            .into_par_iter()
            .map_init(Vec::new, |scratch, v| {
                upper_neighbours(v, scratch);
                scratch.len() as u32
            })
            .collect();
        let edge_start = prefix_sums(&upper_counts);
        drop(upper_counts);

        // The edges, and per edge its faces (the faces of v that contain w, by increasing
        // index): one or two in place; a non-manifold edge is marked `[NONE, count]` here and
        // gets its faces in a side table below.
        let m = edge_start[n] as usize;
        let mut edges = vec![[0u32; 2]; m];
        let mut edge_faces = vec![[NONE; 2]; m];
        split_rows(&mut edges, &edge_start, ROW_BLOCK)
            .into_par_iter()
            .zip(split_rows(&mut edge_faces, &edge_start, ROW_BLOCK))
            .for_each_init(Vec::new, |scratch, ((rows, edges), (_, pairs))| {
                let mut k = 0;
                for v in rows {
                    upper_neighbours(v, scratch);
                    for &w in scratch.iter() {
                        edges[k] = [v as u32, w];
                        let mut count = 0;
                        for &f in faces_of(v) {
                            if faces[f as usize].contains(&w) {
                                if count < 2 {
                                    pairs[k][count] = f;
                                }
                                count += 1;
                            }
                        }
                        if count > 2 {
                            pairs[k] = [NONE, count as u32];
                        }
                        k += 1;
                    }
                }
            });
        // Side table of the non-manifold edges: `[count, faces...]`, found at the index the
        // edge's pair holds after its `NONE`.
        let mut many_faces = Vec::new();
        for (pair, &[v, w]) in edge_faces.iter_mut().zip(&edges) {
            if pair[0] == NONE {
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

        let (vertex_edge_offsets, vertex_edges) =
            parallel_compressed_rows(num_vertices, edges.len(), |e| {
                let [a, b] = edges[e];
                [(a, e as u32), (b, e as u32)]
            });

        let mut topology = Topology {
            vertex_face_offsets,
            vertex_faces,
            vertex_edge_offsets,
            vertex_edges,
            edges,
            edge_faces,
            many_faces,
            faces: Vec::new(),
            vertex_kinds: Vec::new(),
        };
        topology.faces = face_list;
        topology.vertex_kinds = (0..num_vertices as u32)
            .into_par_iter()
            .map(|v| topology.classify_vertex(v, &topology.faces))
            .collect();
        topology
    }

    /// Winds the faces `f` with `flip[f]` the other way (swaps their corners 1 and 2). Nothing
    /// else changes: the connectivity does not depend on the winding.
    pub(crate) fn flip_faces(&mut self, flip: &[bool]) {
        self.faces
            .par_iter_mut()
            .zip(flip.par_iter())
            .for_each(|(t, &flip)| {
                if flip {
                    t.swap(1, 2);
                }
            });
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

    fn classify_vertex(&self, v: u32, faces: &[[u32; 3]]) -> VertexKind {
        let incident = self.vertex_faces(v);
        let Some(&f0) = incident.first() else {
            return VertexKind::Unreferenced;
        };
        if self
            .vertex_edges(v)
            .iter()
            .any(|&e| self.edge_faces(e).len() > 2)
        {
            return VertexKind::NonManifold;
        }
        // With every edge on at most two faces, walking across the edges at `v` is a simple
        // path or cycle: it either comes back to `f0` (closed fan) or stops at boundary edges
        // on both sides. One fan holds every incident face exactly when the vertex is manifold.
        let [e_ahead, e_behind] = self.edges_at(v, f0, faces);
        let (ahead, closed) = self.walk_count(v, f0, e_ahead, faces, incident.len());
        if closed {
            return if ahead == incident.len() {
                VertexKind::Interior
            } else {
                VertexKind::NonManifold
            };
        }
        let (behind, _) = self.walk_count(v, f0, e_behind, faces, incident.len());
        if ahead + behind - 1 == incident.len() {
            VertexKind::Boundary
        } else {
            VertexKind::NonManifold
        }
    }

    /// The two edges of face `f` that contain `v`.
    fn edges_at(&self, v: u32, f: u32, faces: &[[u32; 3]]) -> [u32; 2] {
        let t = faces[f as usize];
        let c = t.iter().position(|&x| x == v).unwrap_or(0);
        [
            self.edge_between(t[c], t[(c + 1) % 3]).unwrap_or(NONE),
            self.edge_between(t[(c + 2) % 3], t[c]).unwrap_or(NONE),
        ]
    }

    /// Walks from `f0` across `first` and on around `v` (manifold edges only); returns the
    /// number of faces seen (with `f0`) and whether the walk came back to `f0`.
    fn walk_count(
        &self,
        v: u32,
        f0: u32,
        first: u32,
        faces: &[[u32; 3]],
        limit: usize,
    ) -> (usize, bool) {
        let (mut f, mut e) = (f0, first);
        let mut count = 1;
        while count <= limit {
            let g = match *self.edge_faces(e) {
                [a, b] => {
                    if a == f {
                        b
                    } else {
                        a
                    }
                }
                _ => return (count, false),
            };
            if g == f0 {
                return (count, true);
            }
            count += 1;
            let [x, y] = self.edges_at(v, g, faces);
            e = if x == e { y } else { x };
            f = g;
        }
        (count, false)
    }

    /// Connected components over faces sharing a vertex: a component id per vertex
    /// (`NONE` for unreferenced vertices) and the number of components.
    pub fn vertex_components(&self, faces: &[[u32; 3]]) -> (Vec<u32>, usize) {
        let n = self.num_vertices();
        let mut parent: Vec<u32> = (0..n as u32).collect();
        fn find(parent: &mut [u32], mut x: u32) -> u32 {
            while parent[x as usize] != x {
                let p = parent[parent[x as usize] as usize];
                parent[x as usize] = p;
                x = p;
            }
            x
        }
        for t in faces {
            for s in 1..3 {
                let (a, b) = (find(&mut parent, t[0]), find(&mut parent, t[s]));
                if a != b {
                    parent[a.max(b) as usize] = a.min(b);
                }
            }
        }
        let mut id = vec![NONE; n];
        let mut count = 0usize;
        for v in 0..n as u32 {
            if self.vertex_kinds[v as usize] == VertexKind::Unreferenced {
                continue;
            }
            let r = find(&mut parent, v) as usize;
            if id[r] == NONE {
                id[r] = count as u32;
                count += 1;
            }
            id[v as usize] = id[r];
        }
        (id, count)
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
fn prefix_sums(counts: &[u32]) -> Vec<u32> {
    let mut offsets = Vec::with_capacity(counts.len() + 1);
    let mut total = 0u32;
    offsets.push(0);
    for &c in counts {
        total += c;
        offsets.push(total);
    }
    offsets
}

/// Cuts `values`, laid out in compressed rows with offsets `offsets`, into pieces of `block`
/// rows each: `(rows, entries of those rows)`, for filling the rows in parallel.
pub(crate) fn split_rows<'a, T>(
    values: &'a mut [T],
    offsets: &[u32],
    block: usize,
) -> Vec<(std::ops::Range<usize>, &'a mut [T])> {
    let rows = offsets.len().saturating_sub(1);
    let mut pieces = Vec::with_capacity(rows.div_ceil(block.max(1)));
    let mut rest = values;
    for first in (0..rows).step_by(block.max(1)) {
        let last = (first + block).min(rows);
        let (piece, tail) = rest.split_at_mut((offsets[last] - offsets[first]) as usize);
        pieces.push((first..last, piece));
        rest = tail;
    }
    pieces
}

/// [`compressed_rows`] of the pairs of items `0..items` (`K` pairs each, values increasing
/// with the item), built in parallel: rows are counted and filled through atomic cursors, then
/// each row is sorted, which restores the order the sequential build gives.
fn parallel_compressed_rows<const K: usize>(
    rows: usize,
    items: usize,
    pairs_of: impl Fn(usize) -> [(u32, u32); K] + Sync,
) -> (Vec<u32>, Vec<u32>) {
    use std::sync::atomic::{AtomicU32, Ordering::Relaxed};
    let cursors: Vec<AtomicU32> = (0..rows)
        .into_par_iter()
        .map(|_| AtomicU32::new(0))
        .collect();
    (0..items).into_par_iter().for_each(|i| {
        for (r, _) in pairs_of(i) {
            cursors[r as usize].fetch_add(1, Relaxed);
        }
    });
    let counts: Vec<u32> = cursors.par_iter().map(|c| c.load(Relaxed)).collect();
    let offsets = prefix_sums(&counts);
    drop(counts);
    cursors
        .par_iter()
        .zip(offsets.par_iter())
        .for_each(|(c, &o)| c.store(o, Relaxed));
    let slots: Vec<AtomicU32> = (0..offsets[rows] as usize)
        .into_par_iter()
        .map(|_| AtomicU32::new(0))
        .collect();
    (0..items).into_par_iter().for_each(|i| {
        for (r, x) in pairs_of(i) {
            let slot = cursors[r as usize].fetch_add(1, Relaxed);
            slots[slot as usize].store(x, Relaxed);
        }
    });
    drop(cursors);
    let mut values: Vec<u32> = slots.into_iter().map(AtomicU32::into_inner).collect();
    split_rows(&mut values, &offsets, ROW_BLOCK)
        .into_par_iter()
        .for_each(|(rows, piece)| {
            let base = offsets[rows.start];
            for r in rows {
                piece[(offsets[r] - base) as usize..(offsets[r + 1] - base) as usize]
                    .sort_unstable();
            }
        });
    (offsets, values)
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

    #[test]
    fn parallel_rows_match_the_sequential_ones() {
        // Pseudo-random rows, several items per row, some rows empty.
        let pairs_of = |i: usize| {
            let h = (i as u32).wrapping_mul(2_654_435_761);
            [(h % 997, i as u32), ((h >> 7) % 1000, i as u32)]
        };
        let items = 20_000;
        let (offsets, values) = parallel_compressed_rows(1000, items, pairs_of);
        let (o, v) = compressed_rows(1000, (0..items).flat_map(pairs_of));
        assert_eq!(offsets, o);
        assert_eq!(values, v);
    }

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
