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
//! per face in all (see `docs/benchmarks-history.md`, session 3, "Where time and memory go").
//!
//! Ordered one-rings are walked on demand across edges that have exactly two faces, so they
//! work whatever the orientation of the neighbouring faces; a vertex whose faces form more
//! than one fan (or that touches a non-manifold edge) is [`VertexKind::NonManifold`] and its
//! ring is returned fan by fan.
//!
//! The construction ([`Topology::from_faces`], in `build.rs`) takes three passes: a counting
//! sort of the corners by vertex, which also copies each face's two other corners next to its
//! entry; one pass over the vertices' stars, each sorted once, by block of vertices; and a copy
//! of the blocks into place.

mod build;
#[cfg(test)]
mod tests;

use rayon::prelude::*;

use crate::slices::compressed_rows;

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

    /// Per vertex, whether it is an end of an edge flagged in `flags` (one per edge of
    /// [`Topology::edges`]; missing flags count as false): the vertices of a set of edges,
    /// such as the creases.
    pub fn vertices_of_edges(&self, flags: &[bool]) -> Vec<bool> {
        let mut on = vec![false; self.num_vertices()];
        for (&[a, b], _) in self.edges.iter().zip(flags).filter(|(_, f)| **f) {
            on[a as usize] = true;
            on[b as usize] = true;
        }
        on
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

/// Whether `triangle` runs through `edge` from its first to its second vertex.
pub(crate) fn runs_through(triangle: &[u32; 3], [a, b]: [u32; 2]) -> bool {
    let i = triangle.iter().position(|&v| v == a).unwrap_or(0);
    triangle[(i + 1) % 3] == b
}
