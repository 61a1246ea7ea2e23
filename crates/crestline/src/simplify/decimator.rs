//! The collapses themselves: a mutable copy of the mesh, the validity checks and the passes
//! over the candidate queue (see the module docs of [`crate::simplify`]).

use rayon::prelude::*;

use super::quadric::{Quadric, add_boundary_quadrics, face_quadrics};
use super::queue::{CandidateQueue, Entry};
use super::{MAX_VALENCE, Rejections, SimplifyOptions};
use crate::error::Result;
use crate::mesh::{TriMesh, Vec3, VertexKind};

/// Why a candidate collapse was refused.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Refusal {
    NonManifold,
    Boundary,
    Link,
    Flip,
    Degenerate,
    Fixed,
    Valence,
}

/// A planned collapse: `remove` merges into `keep`, which moves to `target`; `source` is the
/// input vertex whose position `target` is, or [`NEW_POSITION`].
#[derive(Debug, Clone, Copy)]
struct Plan {
    cost: f64,
    keep: u32,
    remove: u32,
    target: Vec3,
    source: u32,
}

/// The version of a vertex merged away.
const REMOVED: u32 = u32::MAX;

/// Marks a position computed by the decimation rather than taken from an input vertex.
const NEW_POSITION: u32 = u32::MAX;

/// The mutable mesh the collapses run on, in coordinates centred on the bounding box and
/// scaled to a unit diagonal (which keeps the quadrics well conditioned however the input is
/// placed and sized, and the costs in the range of `f32`).
pub(super) struct Decimator<'m> {
    input: &'m TriMesh,
    center: Vec3,
    scale: f64,
    positions: Vec<Vec3>,
    origin: Vec<u32>,
    faces: Vec<[u32; 3]>,
    face_alive: Vec<bool>,
    vertex_faces: Vec<Vec<u32>>,
    quadrics: Vec<Quadric>,
    boundary: Vec<bool>,
    locked: Vec<bool>,
    /// Crease corners, which no collapse may touch; empty without creases.
    fixed: Vec<bool>,
    /// Per vertex: its neighbours along creases (empty without creases).
    crease_neighbors: Vec<Vec<u32>>,
    /// Version stamp per vertex, bumped by every collapse that keeps the vertex;
    /// [`REMOVED`] once it is merged away (one array, so a liveness check reads two words).
    version: Vec<u32>,
    pub(super) live_faces: usize,
    min_cos: f64,
    pub(super) collapses: usize,
    pub(super) rejected: Rejections,
    /// Candidate collapses planned for the queue (see [`super::Simplified::candidates`]).
    pub(super) candidates: usize,
    ring_u: Vec<u32>,
    ring_v: Vec<u32>,
}

impl<'m> Decimator<'m> {
    pub(super) fn new(mesh: &'m TriMesh, face_weights: &[f64], options: &SimplifyOptions) -> Self {
        let topo = mesh.topology();
        let faces = mesh.faces().to_vec();
        let bbox = mesh.bounding_box();
        let center = bbox.center();
        let scale = match bbox.diagonal() {
            d if d > 0.0 && d.is_finite() => d,
            _ => 1.0,
        };
        let positions: Vec<Vec3> = mesh
            .positions()
            .iter()
            .map(|p| (p - center) / scale)
            .collect();
        let face_quadrics = face_quadrics(&positions, &faces, face_weights);
        let n = mesh.num_vertices();
        let mut quadrics: Vec<Quadric> = (0..n as u32)
            .into_par_iter()
            .map(|v| {
                let mut q = Quadric::default();
                for &f in topo.vertex_faces(v) {
                    q.add(&face_quadrics[f as usize]);
                }
                q
            })
            .collect();
        add_boundary_quadrics(
            mesh,
            &positions,
            face_weights,
            options.boundary_weight,
            &mut quadrics,
        );
        let kinds = topo.vertex_kinds();
        Decimator {
            input: mesh,
            center,
            scale,
            origin: (0..n as u32).collect(),
            positions,
            face_alive: vec![true; faces.len()],
            live_faces: faces.len(),
            faces,
            // Room for a few more triangles than now, which a vertex gains as it absorbs
            // its neighbours, saves most reallocations.
            vertex_faces: (0..n as u32)
                .map(|v| {
                    let faces = topo.vertex_faces(v);
                    let mut list = Vec::with_capacity(faces.len() + 4);
                    list.extend_from_slice(faces);
                    list
                })
                .collect(),
            quadrics,
            boundary: kinds.iter().map(|&k| k == VertexKind::Boundary).collect(),
            locked: kinds
                .iter()
                .map(|&k| k == VertexKind::NonManifold)
                .collect(),
            fixed: Vec::new(),
            crease_neighbors: Vec::new(),
            // Unreferenced vertices take part in nothing.
            version: kinds
                .iter()
                .map(|&k| {
                    if k == VertexKind::Unreferenced {
                        REMOVED
                    } else {
                        0
                    }
                })
                .collect(),
            min_cos: options.max_normal_rotation.to_radians().cos(),
            collapses: 0,
            rejected: Rejections::default(),
            candidates: 0,
            ring_u: Vec::new(),
            ring_v: Vec::new(),
        }
    }

    /// Sets the crease constraints: neighbours along `creases`, corners fixed.
    pub(super) fn constrain(&mut self, creases: &[[u32; 2]]) {
        if creases.is_empty() {
            return;
        }
        let n = self.positions.len();
        let mut neighbors = vec![Vec::new(); n];
        for &[a, b] in creases {
            if a != b && !neighbors[a as usize].contains(&b) {
                neighbors[a as usize].push(b);
                neighbors[b as usize].push(a);
            }
        }
        self.fixed = neighbors
            .iter()
            .map(|c| !c.is_empty() && c.len() != 2)
            .collect();
        self.crease_neighbors = neighbors;
    }

    /// Queues every current edge, then collapses the cheapest valid candidates until the
    /// target is met or the queue is empty. Returns the number of collapses made.
    pub(super) fn run_pass(&mut self, target_faces: usize) -> usize {
        let mut heap = self.rank_edge_collapses();
        let before = self.collapses;
        while self.live_faces > target_faces {
            let Some(Entry { u, v, stamp, .. }) = heap.pop(|e| self.is_live(e)) else {
                break;
            };
            if !self.is_live(&Entry {
                cost: 0,
                u,
                v,
                stamp,
            }) {
                continue;
            }
            let checked = self
                .plan_collapse(u, v)
                .and_then(|plan| self.check_link_condition(u, v).map(|()| plan))
                .and_then(|plan| self.check_valence(u, v).map(|()| plan))
                .and_then(|plan| self.check_moved_faces(&plan).map(|()| plan));
            match checked {
                Ok(plan) => {
                    self.perform_collapse(&plan);
                    self.queue_edges_of(plan.keep, &mut heap);
                }
                Err(r) => self.count(r),
            }
        }
        self.collapses - before
    }

    /// All current edges with their planned collapse, as a heap.
    fn rank_edge_collapses(&mut self) -> CandidateQueue {
        let this = &*self;
        let planned: Vec<Result<Entry, Refusal>> = (0..this.positions.len() as u32)
            .into_par_iter()
            .filter(|&u| this.version[u as usize] != REMOVED)
            .flat_map_iter(|u| {
                let mut ring = Vec::new();
                this.collect_ring(u, &mut ring);
                ring.retain(|&w| w > u);
                ring.into_iter().map(move |w| this.entry(u, w))
            })
            .collect();
        self.candidates += planned.len();
        let mut entries = Vec::with_capacity(planned.len());
        for p in planned {
            match p {
                Ok(e) => entries.push(e),
                Err(r) => self.count(r),
            }
        }
        CandidateQueue::from(entries)
    }

    fn entry(&self, u: u32, v: u32) -> Result<Entry, Refusal> {
        let plan = self.plan_collapse(u, v)?;
        Ok(Entry {
            cost: (plan.cost as f32).to_bits(),
            u,
            v,
            stamp: self.stamp(u, v),
        })
    }

    /// False for entries made stale by a collapse since they were queued.
    fn is_live(&self, e: &Entry) -> bool {
        let (vu, vv) = (self.version[e.u as usize], self.version[e.v as usize]);
        vu != REMOVED && vv != REMOVED && vu.wrapping_add(vv) == e.stamp
    }

    fn stamp(&self, u: u32, v: u32) -> u32 {
        self.version[u as usize].wrapping_add(self.version[v as usize])
    }

    fn queue_edges_of(&mut self, v: u32, heap: &mut CandidateQueue) {
        let mut ring = std::mem::take(&mut self.ring_u);
        self.collect_ring(v, &mut ring);
        self.candidates += ring.len();
        for &w in &ring {
            match self.entry(v, w) {
                Ok(e) => heap.push(e),
                Err(r) => self.count(r),
            }
        }
        self.ring_u = ring;
    }

    fn count(&mut self, refusal: Refusal) {
        let r = &mut self.rejected;
        match refusal {
            Refusal::NonManifold => r.non_manifold += 1,
            Refusal::Boundary => r.boundary += 1,
            Refusal::Link => r.link += 1,
            Refusal::Flip => r.flip += 1,
            Refusal::Degenerate => r.degenerate += 1,
            Refusal::Fixed => r.fixed += 1,
            Refusal::Valence => r.valence += 1,
        }
    }

    fn live_faces_of(&self, v: u32) -> impl Iterator<Item = u32> + '_ {
        self.vertex_faces[v as usize]
            .iter()
            .copied()
            .filter(|&f| self.face_alive[f as usize])
    }

    /// The neighbours of `v`, sorted, each once.
    fn collect_ring(&self, v: u32, ring: &mut Vec<u32>) {
        ring.clear();
        for f in self.live_faces_of(v) {
            ring.extend(self.faces[f as usize].iter().filter(|&&w| w != v));
        }
        ring.sort_unstable();
        ring.dedup();
    }

    /// Number of live triangles on edge `u v`, found among the triangles of the end point
    /// with fewer (a vertex at the tip of a fan may have many).
    fn edge_face_count(&self, u: u32, v: u32) -> usize {
        let (a, b) = if self.vertex_faces[u as usize].len() <= self.vertex_faces[v as usize].len() {
            (u, v)
        } else {
            (v, u)
        };
        self.live_faces_of(a)
            .filter(|&f| self.faces[f as usize].contains(&b))
            .count()
    }

    /// Where the merged vertex goes and at what cost (see the module docs on placement).
    fn plan_collapse(&self, u: u32, v: u32) -> Result<Plan, Refusal> {
        if self.locked[u as usize] || self.locked[v as usize] {
            return Err(Refusal::NonManifold);
        }
        let on_crease = |w: u32| {
            self.crease_neighbors
                .get(w as usize)
                .is_some_and(|c| !c.is_empty())
        };
        let q = self.quadrics[u as usize].sum(&self.quadrics[v as usize]);
        let (pu, pv) = (self.positions[u as usize], self.positions[v as usize]);
        let at = |keep: u32, remove: u32, target: Vec3, source: u32| Plan {
            cost: q.value(target).max(0.0),
            keep,
            remove,
            target,
            source,
        };
        let at_u = || at(u, v, pu, self.origin[u as usize]);
        let at_v = || at(v, u, pv, self.origin[v as usize]);
        let cheaper = |a: Plan, b: Plan| if b.cost < a.cost { b } else { a };
        if on_crease(u) || on_crease(v) {
            if self.boundary[u as usize] || self.boundary[v as usize] {
                return Err(Refusal::Fixed);
            }
            return match (on_crease(u), on_crease(v)) {
                (true, true) if self.crease_neighbors[u as usize].contains(&v) => {
                    // Corners are never removed.
                    match (self.fixed[v as usize], self.fixed[u as usize]) {
                        (false, false) => Ok(cheaper(at_u(), at_v())),
                        (false, true) => Ok(at_u()),
                        (true, false) => Ok(at_v()),
                        (true, true) => Err(Refusal::Fixed),
                    }
                }
                (true, true) => Err(Refusal::Fixed),
                (true, false) => Ok(at_u()),
                _ => Ok(at_v()),
            };
        }
        let plan = match (self.boundary[u as usize], self.boundary[v as usize]) {
            (true, true) => {
                if self.edge_face_count(u, v) != 1 {
                    return Err(Refusal::Boundary);
                }
                cheaper(at_u(), at_v())
            }
            (true, false) => at_u(),
            (false, true) => at_v(),
            (false, false) => {
                let mid = (pu + pv) * 0.5;
                let reach = 2.0 * (pu - pv).norm();
                match q.minimizer() {
                    Some(x) if (x - mid).norm() <= reach => at(v, u, x, NEW_POSITION),
                    _ => cheaper(cheaper(at_v(), at_u()), at(v, u, mid, NEW_POSITION)),
                }
            }
        };
        Ok(plan)
    }

    /// The link condition for collapsing edge `u v` on a surface with boundary (a boundary
    /// counts as joined to a virtual vertex): the common neighbours of `u` and `v` must be
    /// exactly the apexes of the triangles on `u v`, and no edge of both links may survive
    /// (which would fold a tetrahedron or a lone triangle flat).
    fn check_link_condition(&mut self, u: u32, v: u32) -> Result<(), Refusal> {
        let mut apexes = [0u32; 2];
        let mut count = 0;
        for f in self.live_faces_of(u) {
            let t = self.faces[f as usize];
            if t.contains(&v) {
                if count == 2 {
                    return Err(Refusal::Link);
                }
                apexes[count] = t.iter().copied().find(|&w| w != u && w != v).unwrap_or(u);
                count += 1;
            }
        }
        if count == 0 {
            return Err(Refusal::Link);
        }
        let (mut ring_u, mut ring_v) = (
            std::mem::take(&mut self.ring_u),
            std::mem::take(&mut self.ring_v),
        );
        self.collect_ring(u, &mut ring_u);
        self.collect_ring(v, &mut ring_v);
        let common = count_common(&ring_u, &ring_v);
        self.ring_u = ring_u;
        self.ring_v = ring_v;
        if common != count {
            return Err(Refusal::Link);
        }
        let has_face = |x: u32, a: u32, b: u32| {
            self.live_faces_of(x).any(|f| {
                let t = self.faces[f as usize];
                t.contains(&a) && t.contains(&b)
            })
        };
        match count {
            // Triangles u c d and v c d would both become x c d.
            2 => {
                let (c, d) = (apexes[0], apexes[1]);
                if has_face(u, c, d) && has_face(v, c, d) {
                    return Err(Refusal::Link);
                }
            }
            // u c and v c on the boundary too: the triangle hangs by c alone (or is alone).
            _ => {
                let c = apexes[0];
                if self.edge_face_count(u, c) == 1 && self.edge_face_count(v, c) == 1 {
                    return Err(Refusal::Link);
                }
            }
        }
        Ok(())
    }

    /// Refuses a collapse that would give the merged vertex more than [`MAX_VALENCE`]
    /// neighbours and more than either end point has now. Run after the link condition, which
    /// leaves the two rings in `ring_u` and `ring_v`.
    fn check_valence(&self, u: u32, v: u32) -> Result<(), Refusal> {
        let (ring_u, ring_v) = (&self.ring_u, &self.ring_v);
        debug_assert!(ring_u.binary_search(&v).is_ok() && ring_v.binary_search(&u).is_ok());
        // The union of the two rings, without u and v themselves.
        let merged = ring_u.len() + ring_v.len() - count_common(ring_u, ring_v) - 2;
        if merged > MAX_VALENCE && merged > ring_u.len().max(ring_v.len()) {
            return Err(Refusal::Valence);
        }
        Ok(())
    }

    /// Refuses a collapse that turns a moved triangle by more than the allowed angle or
    /// leaves it without area.
    fn check_moved_faces(&self, plan: &Plan) -> Result<(), Refusal> {
        let (u, v) = (plan.keep, plan.remove);
        for x in [u, v] {
            for f in self.live_faces_of(x) {
                let t = self.faces[f as usize];
                if t.contains(&u) && t.contains(&v) {
                    continue;
                }
                let old = t.map(|w| self.positions[w as usize]);
                let new = t.map(|w| {
                    if w == u || w == v {
                        plan.target
                    } else {
                        self.positions[w as usize]
                    }
                });
                let n_old = (old[1] - old[0]).cross(&(old[2] - old[0]));
                let n_new = (new[1] - new[0]).cross(&(new[2] - new[0]));
                let longest = (new[1] - new[0])
                    .norm_squared()
                    .max((new[2] - new[1]).norm_squared())
                    .max((new[0] - new[2]).norm_squared());
                // Far above the 1e-13 at which TriMesh drops a triangle as degenerate.
                if n_new.norm() <= 1e-8 * longest {
                    return Err(Refusal::Degenerate);
                }
                if n_old.dot(&n_new) < self.min_cos * n_old.norm() * n_new.norm() {
                    return Err(Refusal::Flip);
                }
            }
        }
        Ok(())
    }

    fn perform_collapse(&mut self, plan: &Plan) {
        let (k, r) = (plan.keep as usize, plan.remove as usize);
        self.positions[k] = plan.target;
        self.origin[k] = plan.source;
        let qr = self.quadrics[r];
        self.quadrics[k].add(&qr);
        self.boundary[k] |= self.boundary[r];
        if let Some(moved) = self.crease_neighbors.get_mut(r).map(std::mem::take) {
            // Along a crease: r's other crease neighbours become k's.
            let (keep, remove) = (plan.keep, plan.remove);
            for w in moved {
                if w == keep {
                    continue;
                }
                for x in &mut self.crease_neighbors[w as usize] {
                    if *x == remove {
                        *x = keep;
                    }
                }
                self.crease_neighbors[k].push(w);
            }
            self.crease_neighbors[k].retain(|&x| x != remove);
        }
        self.version[r] = REMOVED;
        // Skipping the sentinel keeps a live vertex from ever looking removed.
        self.version[k] = (self.version[k] + 1) % REMOVED;
        let moved = std::mem::take(&mut self.vertex_faces[r]);
        for f in moved {
            if !self.face_alive[f as usize] {
                continue;
            }
            let t = &mut self.faces[f as usize];
            if t.contains(&plan.keep) {
                self.face_alive[f as usize] = false;
                self.live_faces -= 1;
                if let Some(&c) = t.iter().find(|&&w| w != plan.keep && w != plan.remove) {
                    let alive = &self.face_alive;
                    self.vertex_faces[c as usize].retain(|&g| alive[g as usize]);
                }
            } else {
                for w in t.iter_mut() {
                    if *w == plan.remove {
                        *w = plan.keep;
                    }
                }
                self.vertex_faces[k].push(f);
            }
        }
        let alive = &self.face_alive;
        self.vertex_faces[k].retain(|&g| alive[g as usize]);
        self.collapses += 1;
    }

    /// The live triangles over the surviving vertices, renumbered, back in input coordinates
    /// (vertices that kept or took an input vertex's place get its position bit for bit).
    pub(super) fn into_mesh(self) -> Result<TriMesh> {
        let mut index = vec![u32::MAX; self.positions.len()];
        let mut positions = Vec::new();
        let mut faces = Vec::with_capacity(self.live_faces);
        for (f, t) in self.faces.iter().enumerate() {
            if !self.face_alive[f] {
                continue;
            }
            faces.push(t.map(|v| {
                let i = &mut index[v as usize];
                if *i == u32::MAX {
                    *i = positions.len() as u32;
                    positions.push(match self.origin[v as usize] {
                        NEW_POSITION => self.positions[v as usize] * self.scale + self.center,
                        o => self.input.position(o),
                    });
                }
                *i
            }));
        }
        TriMesh::new(positions, faces)
    }
}

/// Number of values in both sorted, deduplicated slices.
fn count_common(a: &[u32], b: &[u32]) -> usize {
    let (mut i, mut j, mut n) = (0, 0, 0);
    while i < a.len() && j < b.len() {
        match a[i].cmp(&b[j]) {
            std::cmp::Ordering::Less => i += 1,
            std::cmp::Ordering::Greater => j += 1,
            std::cmp::Ordering::Equal => {
                n += 1;
                i += 1;
                j += 1;
            }
        }
    }
    n
}
