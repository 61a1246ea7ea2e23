//! The construction of [`Topology`]: corners sorted by vertex, each vertex's star sorted once
//! into edges and a vertex kind, block by block of vertices in parallel, then the blocks copied
//! into place.

use rayon::prelude::*;

use super::{INCONSISTENT_EDGE, NONE, OPEN_EDGE, Topology, VertexKind};
use crate::slices::{prefix_sums, split_at, split_rows};

impl Topology {
    /// [`Topology::build`] taking the faces over (the topology keeps them: see
    /// [`Topology::faces`]).
    ///
    /// Edges are numbered vertex by vertex: the edges (v, w) with w > v, by increasing w. Ids
    /// therefore follow the pair (smaller endpoint, larger endpoint), as a global sort of the
    /// half-edges would give, but each vertex only looks at its own faces, in parallel.
    pub fn from_faces(num_vertices: usize, face_list: Vec<[u32; 3]>) -> Self {
        let faces = &face_list[..];
        let n = num_vertices;
        let (vertex_face_offsets, vertex_faces, others) = vertex_face_rows(n, faces);
        let stars = sort_stars(n, &vertex_face_offsets, &vertex_faces, &others);
        drop(others);
        let edge_start = prefix_sums(stars.counts.iter().map(|c| c[1]));
        let vertex_edge_offsets = prefix_sums(stars.counts.iter().map(|c| c[0] + c[1]));
        let (edges, mut edge_faces, vertex_edges) =
            place_edges(&stars, &edge_start, &vertex_edge_offsets);
        // The rooms go back to the system before the side table is built.
        let Stars {
            vertex_kinds,
            vertex_edge_flags,
            many,
            ..
        } = stars;
        let faces_on = |v: u32, w: u32| {
            let (start, end) = (
                vertex_face_offsets[v as usize],
                vertex_face_offsets[v as usize + 1],
            );
            vertex_faces[start as usize..end as usize]
                .iter()
                .filter(|&&f| faces[f as usize].contains(&w))
                .copied()
                .collect()
        };
        let many_faces = non_manifold_faces(&many, &edge_start, &edges, &mut edge_faces, faces_on);
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
}

/// The sorted stars of all vertices, block by block of [`ROW_BLOCK`] vertices, each block in
/// its own room of the two shared arrays.
struct Stars {
    /// Where each block's room starts in `neighbours` and `above_faces` (a vertex has at most
    /// two neighbours per face, which bounds a room).
    room: Vec<usize>,
    /// Per vertex, its neighbours in increasing order (the row of edges, with neighbours in
    /// place of the edge ids).
    neighbours: Vec<u32>,
    /// The faces of the edges to the neighbours above each vertex; a non-manifold edge is
    /// `[NONE, count]` and listed in `many`.
    above_faces: Vec<[u32; 2]>,
    /// Per vertex, its numbers of neighbours below and above it.
    counts: Vec<[u32; 2]>,
    vertex_kinds: Vec<VertexKind>,
    vertex_edge_flags: Vec<u8>,
    /// Per block, the non-manifold edges, as indices among its edges to neighbours above.
    many: Vec<Vec<u32>>,
}

/// Gathers and sorts each vertex's star once, with its kind and edge flags (see [`Stars`]).
fn sort_stars(
    n: usize,
    vertex_face_offsets: &[u32],
    vertex_faces: &[u32],
    others: &[[u32; 2]],
) -> Stars {
    let room: Vec<usize> = (0..=n.div_ceil(ROW_BLOCK))
        .map(|b| 2 * vertex_face_offsets[(b * ROW_BLOCK).min(n)] as usize)
        .collect();
    // Zeroed allocations: only the pages the blocks write are touched.
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
    Stars {
        room,
        neighbours,
        above_faces,
        counts,
        vertex_kinds,
        vertex_edge_flags,
        many,
    }
}

/// Copies the blocks into place: the edges with their faces, and each vertex's row of edge
/// ids. The edge to a neighbour `u` below `v` is found among the sorted neighbours above `u`.
fn place_edges(
    stars: &Stars,
    edge_start: &[u32],
    vertex_edge_offsets: &[u32],
) -> (Vec<[u32; 2]>, Vec<[u32; 2]>, Vec<u32>) {
    let n = stars.counts.len();
    let (room, neighbours, above_faces) = (&stars.room, &stars.neighbours, &stars.above_faces);
    let m = edge_start[n] as usize;
    // Every entry is written below: zeroed allocations cost less than filling with `NONE`.
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
    split_rows(&mut edges, edge_start, ROW_BLOCK)
        .into_par_iter()
        .zip(split_rows(&mut edge_faces, edge_start, ROW_BLOCK))
        .zip(split_rows(
            &mut vertex_edges,
            vertex_edge_offsets,
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
                        *id = edge_start[u] + above.partition_point(|&x| (x as usize) < v) as u32;
                    } else {
                        edges[k] = [v as u32, w];
                        *id = first_edge + k as u32;
                        k += 1;
                    }
                }
                slot += row.len();
            }
        });
    (edges, edge_faces, vertex_edges)
}

/// The side table of the non-manifold edges, `[count, faces...]` per edge, found at the index
/// the edge's pair holds after its `NONE`; `faces_on(v, w)` lists the faces on edge `v w`.
fn non_manifold_faces(
    many: &[Vec<u32>],
    edge_start: &[u32],
    edges: &[[u32; 2]],
    edge_faces: &mut [[u32; 2]],
    faces_on: impl Fn(u32, u32) -> Vec<u32>,
) -> Vec<u32> {
    let mut many_faces = Vec::new();
    for (b, many) in many.iter().enumerate() {
        for &k in many {
            let e = (edge_start[b * ROW_BLOCK] + k) as usize;
            let [v, w] = edges[e];
            let pair = &mut edge_faces[e];
            let start = many_faces.len() as u32;
            many_faces.push(pair[1]);
            many_faces.extend(faces_on(v, w));
            pair[1] = start;
        }
    }
    many_faces
}

/// Rows per parallel work item when filling compressed rows.
const ROW_BLOCK: usize = 2048;

/// The vertex → face rows of `faces` over `n` vertices, each row by increasing face (offsets
/// and faces), and beside every entry the face's two other corners: the stars then read their
/// corners in order rather than looking them up face by face, mostly cache misses on large
/// meshes. A counting sort, with the vertices cut into one range per worker thread: each
/// worker reads all the faces and counts, then places, only the corners at its own vertices,
/// so every row is in face order whatever the number of workers and no write is shared
/// (shared atomic counters were slower, see `docs/benchmarks-history.md`, sessions 4 and 7).
pub(super) fn vertex_face_rows(
    n: usize,
    faces: &[[u32; 3]],
) -> (Vec<u32>, Vec<u32>, Vec<[u32; 2]>) {
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

/// The position of the face of a corner of [`Star::corners`] in the vertex's face list.
#[inline]
fn position(corner: u64) -> usize {
    (corner & 0xffff_ffff) as usize
}
