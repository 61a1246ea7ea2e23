//! Consistent winding, and outward orientation of closed surfaces.
//!
//! Every curvature sign in the crate follows the winding of the triangles (see the module
//! docs of [`crate::mesh`]): on a closed mesh wound clockwise seen from outside the normals
//! point inward, every principal curvature changes sign and ridges come out as valleys.
//! Such files are common (the shared `horse.ply` is one), and so are files in which some
//! triangles are wound against their neighbours (exporters that do not keep the winding,
//! pieces merged from several sources): there the normals flip from triangle to triangle,
//! and every edge between two such triangles looks like a fold of 180°.
//!
//! Two edges of faces *agree* when the two faces of the edge run through it in opposite
//! directions. [`orient_outward`] takes two steps:
//! 1. *Winding.* Within each patch of faces joined by edges with exactly two faces, it reverses
//!    the triangles that disagree with the others, keeping the winding that most of the
//!    patch's triangles have (a walk over the patch gives each face its winding relative to
//!    the first; the smaller of the two sets is reversed, at a tie the one without the
//!    patch's first face). A patch in which the walk meets itself with the other winding has
//!    none (a Möbius strip, a Klein bottle): it is left as it is and counted. Edges with more
//!    than two faces do not join patches: which two of their faces belong together is not
//!    known.
//! 2. *Outward.* Patches that are closed (every edge of their faces has exactly two faces)
//!    and consistently wound have an inside and an outside: those with negative signed
//!    volume are reversed. Where every vertex is manifold and every winding consistent, the
//!    patches are the connected components (over shared vertices, as in
//!    [`super::MeshInfo`]) and are found as those, without a walk over the faces; two shells
//!    touching at a vertex are one component but two patches, each decided by its own volume.
//! 3. *Nearly closed.* An open patch (a scan with holes, a part with a face missing) has an
//!    inside too when its holes are small: each hole (a loop of boundary edges) is closed by
//!    a fan to the mean of its corners, and the sign of the volume so enclosed decides, if no
//!    other way of closing the holes could change it. Any other cap over a hole of vector
//!    area S, within the patch's bounding box (diagonal D), encloses at most |S| D / 3 more
//!    or less (a cone of that base and height), so the sign counts when the volume exceeds
//!    Σ |S| D / 3. A scan of a closed object with a few holes, or a box without its lid,
//!    passes; a height field, a terrain, a hemisphere or a bowl does not (a hemisphere of
//!    radius r encloses 2.1 r³ with its flat cap, against 3.6 r³ that a cone could change),
//!    and keeps the winding of step 1: which side is out is then the file's to say.
//!
//! [`orientation`] reports what [`orient_outward`] would do without doing it; [`reverse_faces`]
//! then does it from that report's flags, without classifying the mesh again (for callers
//! that need the flags too, or keep the mesh as given when nothing changes).

use std::sync::atomic::{AtomicBool, Ordering::Relaxed};

use rayon::prelude::*;

use crate::error::Result;

use super::topology::runs_through;
use super::{TriMesh, Vec3, VertexKind};

/// What [`orientation`] found.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Orientation {
    /// Connected components (over shared vertices).
    pub components: usize,
    /// Closed surfaces (patches, step 2 of the module docs) that have a consistent winding
    /// (once rewound).
    pub closed: usize,
    /// Open surfaces (patches) whose holes are small enough that they have an inside (step 3
    /// of the module docs).
    pub nearly_closed: usize,
    /// Of the closed and nearly closed surfaces, the ones with negative signed volume
    /// (facing inward).
    pub inward: usize,
    /// Triangles in the inward surfaces.
    pub inward_faces: usize,
    /// Components (closed or open) in which some triangles are wound against their
    /// neighbours, as given.
    pub inconsistent: usize,
    /// Triangles reversed to agree with the rest of their patch (step 1 of the module docs).
    pub rewound_faces: usize,
    /// Patches that cannot be wound consistently (non-orientable: a Möbius strip), left as
    /// they are.
    pub non_orientable: usize,
}

/// Faces per block when summing volumes.
const VOLUME_BLOCK: usize = 1 << 14;

/// Classifies the components of `mesh`; returns the report and, per face, whether
/// [`orient_outward`] reverses it (to agree with its patch, or in an inward surface).
pub fn orientation(mesh: &TriMesh) -> (Orientation, Vec<bool>) {
    let (report, reversal) = classify(mesh);
    let faces = mesh.faces();
    let per_face = (0..faces.len())
        .into_par_iter()
        .map(|f| reversal.reverses(f, &faces[f]))
        .collect();
    (report, per_face)
}

/// The groups of faces whose volume decides their side: connected components (over shared
/// vertices, read off a face's first corner: no array per face) where every vertex is
/// manifold and every patch consistent, else patches (faces joined by edges with two
/// faces), so that two shells touching at a vertex, or a patch rewound, are decided alone.
enum Grouping {
    Components(Vec<u32>),
    Patches(Vec<u32>),
}

impl Grouping {
    fn of(&self, f: usize, triangle: &[u32; 3]) -> usize {
        match self {
            Grouping::Components(of_vertex) => of_vertex[triangle[0] as usize] as usize,
            Grouping::Patches(of_face) => of_face[f] as usize,
        }
    }
}

/// What [`orient_outward`] reverses: the groups that face inward and the faces to rewind
/// (empty when every patch is consistent).
struct Reversal {
    grouping: Grouping,
    inward: Vec<bool>,
    rewind: Vec<bool>,
}

impl Reversal {
    fn is_inward(&self, f: usize, triangle: &[u32; 3]) -> bool {
        self.inward[self.grouping.of(f, triangle)]
    }

    /// Whether face `f` with corners `triangle` is reversed: rewound or inward, not both.
    fn reverses(&self, f: usize, triangle: &[u32; 3]) -> bool {
        self.is_inward(f, triangle) != self.rewind.get(f).copied().unwrap_or(false)
    }
}

/// The patches of a mesh (step 1 of the module docs).
struct Patches {
    /// Per face, its patch.
    of_face: Vec<u32>,
    /// Per face, whether it is reversed to agree with its patch.
    rewind: Vec<bool>,
    /// Per patch: every edge of its faces has two faces (it bounds a volume, if orientable).
    closed: Vec<bool>,
    /// Per patch: it has a consistent winding.
    orientable: Vec<bool>,
    /// Faces to rewind.
    rewound: usize,
}

/// Walks the patches of `mesh` (depth first from their first face): per face its patch and
/// whether it disagrees with the winding most of its patch has.
fn patches(mesh: &TriMesh) -> Patches {
    const UNSEEN: u8 = u8::MAX;
    let topo = mesh.topology();
    let faces = mesh.faces();
    // Per face its winding relative to the first face of its patch: 0 the same, 1 reversed.
    let mut relative = vec![UNSEEN; faces.len()];
    let mut result = Patches {
        of_face: vec![0; faces.len()],
        rewind: vec![false; faces.len()],
        closed: Vec::new(),
        orientable: Vec::new(),
        rewound: 0,
    };
    let (mut patch, mut stack) = (Vec::new(), Vec::new());
    for first in 0..faces.len() {
        if relative[first] != UNSEEN {
            continue;
        }
        let id = result.closed.len() as u32;
        relative[first] = 0;
        stack.push(first as u32);
        patch.clear();
        let (mut orientable, mut closed) = (true, true);
        while let Some(f) = stack.pop() {
            patch.push(f);
            result.of_face[f as usize] = id;
            let here = relative[f as usize];
            for e in topo.face_edges(f) {
                let &[a, b] = topo.edge_faces(e) else {
                    closed = false;
                    continue;
                };
                let g = if a == f { b } else { a };
                let edge = topo.edge(e);
                let agree = runs_through(&faces[f as usize], edge)
                    != runs_through(&faces[g as usize], edge);
                let wanted = here ^ u8::from(!agree);
                let seen = &mut relative[g as usize];
                if *seen == UNSEEN {
                    *seen = wanted;
                    stack.push(g);
                } else if *seen != wanted {
                    orientable = false;
                }
            }
        }
        result.closed.push(closed);
        result.orientable.push(orientable);
        if !orientable {
            continue;
        }
        let reversed = patch.iter().filter(|&&f| relative[f as usize] == 1).count();
        // Reverse the smaller set; at a tie, the faces wound against the patch's first.
        let reverse = if 2 * reversed <= patch.len() { 1 } else { 0 };
        for &f in &patch {
            if relative[f as usize] == reverse {
                result.rewind[f as usize] = true;
                result.rewound += 1;
            }
        }
    }
    result
}

/// The report of [`orientation`] and what [`orient_outward`] reverses.
fn classify(mesh: &TriMesh) -> (Orientation, Reversal) {
    let topo = mesh.topology();
    let faces = mesh.faces();
    let (vertex_component, count) = topo.vertex_components(faces);
    // Per component: not closed, not consistent; read off the vertices' edge flags, which the
    // connectivity found while sorting the stars (an edge's component is its vertices').
    let open: Vec<AtomicBool> = (0..count).map(|_| AtomicBool::new(false)).collect();
    let inconsistent: Vec<AtomicBool> = (0..count).map(|_| AtomicBool::new(false)).collect();
    vertex_component.par_iter().enumerate().for_each(|(v, &c)| {
        // Unreferenced vertices have no component (and no edges).
        let (Some(component_open), Some(component_inconsistent)) =
            (open.get(c as usize), inconsistent.get(c as usize))
        else {
            return;
        };
        let v = v as u32;
        if topo.has_open_edge(v) {
            component_open.store(true, Relaxed);
        }
        if topo.has_inconsistent_edge(v) {
            component_inconsistent.store(true, Relaxed);
        }
    });
    let open: Vec<bool> = open.into_iter().map(AtomicBool::into_inner).collect();
    let mut report = Orientation {
        components: count,
        inconsistent: inconsistent.into_iter().filter(|x| x.load(Relaxed)).count(),
        ..Default::default()
    };
    // Step 1 (module docs), and the groups whose volume decides: components where that is
    // the same (the usual mesh, without a walk over its faces), else patches. The volumes
    // below are those of the rewound triangles.
    let (grouping, has_inside, orientable, rewind) =
        if report.inconsistent > 0 || topo.count_vertices(VertexKind::NonManifold) > 0 {
            let patches = patches(mesh);
            report.rewound_faces = patches.rewound;
            report.non_orientable = patches.orientable.iter().filter(|&&o| !o).count();
            let has_inside: Vec<bool> = (patches.closed.iter().zip(&patches.orientable))
                .map(|(&closed, &orientable)| closed && orientable)
                .collect();
            let rewind = if patches.rewound > 0 {
                patches.rewind
            } else {
                Vec::new()
            };
            (
                Grouping::Patches(patches.of_face),
                has_inside,
                patches.orientable,
                rewind,
            )
        } else {
            let has_inside: Vec<bool> = open.iter().map(|&open| !open).collect();
            (
                Grouping::Components(vertex_component),
                has_inside,
                vec![true; count],
                Vec::new(),
            )
        };
    let groups = has_inside.len();
    // Signed volumes about the bounding-box centre (for fewer cancellations): summed in
    // parallel over fixed blocks of faces, run by run of faces in one group, then block by
    // block in order, so the sums do not depend on the number of threads. The runs also
    // count the faces of each group.
    let centre = mesh.bounding_box().center();
    let runs: Vec<Vec<(usize, f64, usize)>> = faces
        .par_chunks(VOLUME_BLOCK)
        .enumerate()
        .map(|(block, triangles)| {
            let mut runs: Vec<(usize, f64, usize)> = Vec::new();
            for (i, t) in triangles.iter().enumerate() {
                let f = block * VOLUME_BLOCK + i;
                let g = grouping.of(f, t);
                let mut v = tetrahedron_volume(mesh, centre, t);
                if rewind.get(f) == Some(&true) {
                    v = -v;
                }
                match runs.last_mut() {
                    Some((last, sum, faces)) if *last == g => {
                        *sum += v;
                        *faces += 1;
                    }
                    _ => runs.push((g, v, 1)),
                }
            }
            runs
        })
        .collect();
    let mut volume = vec![0.0f64; groups];
    let mut face_count = vec![0usize; groups];
    for (g, v, n) in runs.into_iter().flatten() {
        volume[g] += v;
        face_count[g] += n;
    }
    // Step 3: open orientable groups with small holes.
    let open_candidates: Vec<bool> = (0..groups)
        .map(|g| !has_inside[g] && orientable[g])
        .collect();
    let capped = if open_candidates.contains(&true) {
        capped_volumes(mesh, &grouping, &rewind, &open_candidates, centre, &volume)
    } else {
        vec![None; groups]
    };
    let mut inward = vec![false; groups];
    for g in 0..groups {
        let enclosed = if has_inside[g] {
            report.closed += 1;
            volume[g]
        } else if let Some(v) = capped[g] {
            report.nearly_closed += 1;
            v
        } else {
            continue;
        };
        if enclosed < 0.0 {
            report.inward += 1;
            report.inward_faces += face_count[g];
            inward[g] = true;
        }
    }
    let reversal = Reversal {
        grouping,
        inward,
        rewind,
    };
    (report, reversal)
}

/// Per group, for the groups `candidate` marks: the signed volume (about `centre`) of the
/// group's surface with each hole closed by a fan to the mean of its corners, when that
/// volume's sign does not depend on how the holes are closed (step 3 of the module docs);
/// `volume` is the surface's own. `None` for the rest, and for a group whose boundary edges
/// do not form loops.
fn capped_volumes(
    mesh: &TriMesh,
    grouping: &Grouping,
    rewind: &[bool],
    candidate: &[bool],
    centre: Vec3,
    volume: &[f64],
) -> Vec<Option<f64>> {
    let topo = mesh.topology();
    let faces = mesh.faces();
    let groups = candidate.len();
    // The boundary edges as the (rewound) faces run through them: (group, from, to).
    let mut boundary: Vec<(u32, u32, u32)> = faces
        .par_iter()
        .enumerate()
        .flat_map_iter(|(f, t)| {
            let g = grouping.of(f, t);
            let rewound = rewind.get(f) == Some(&true);
            let edges = if candidate[g] {
                topo.face_edges(f as u32)
            } else {
                [u32::MAX; 3]
            };
            edges.into_iter().filter_map(move |e| {
                if e == u32::MAX || topo.edge_faces(e).len() == 2 {
                    return None;
                }
                let [a, b] = topo.edge(e);
                let forward = runs_through(t, [a, b]) != rewound;
                let (from, to) = if forward { (a, b) } else { (b, a) };
                Some((g as u32, from, to))
            })
        })
        .collect();
    boundary.par_sort_unstable();
    // Per group: the bounding box's diagonal.
    let mut low = vec![Vec3::repeat(f64::INFINITY); groups];
    let mut high = vec![Vec3::repeat(f64::NEG_INFINITY); groups];
    for (f, t) in faces.iter().enumerate() {
        let g = grouping.of(f, t);
        if candidate[g] {
            for &v in t {
                let p = mesh.position(v);
                low[g] = low[g].inf(&p);
                high[g] = high[g].sup(&p);
            }
        }
    }
    // Walk the loops: each boundary edge is followed by an unused one from its end.
    let mut loops_close = vec![true; groups];
    let mut caps = vec![0.0f64; groups];
    let mut hole_area = vec![0.0f64; groups];
    let mut used = vec![false; boundary.len()];
    let mut corners: Vec<Vec3> = Vec::new();
    for first in 0..boundary.len() {
        if used[first] {
            continue;
        }
        let (g, start, mut at) = boundary[first];
        used[first] = true;
        corners.clear();
        corners.push(mesh.position(start));
        while at != start {
            let from = boundary.partition_point(|&(h, v, _)| (h, v) < (g, at));
            let next = (from..boundary.len())
                .take_while(|&i| (boundary[i].0, boundary[i].1) == (g, at))
                .find(|&i| !used[i]);
            let Some(i) = next else {
                loops_close[g as usize] = false;
                break;
            };
            used[i] = true;
            corners.push(mesh.position(at));
            at = boundary[i].2;
        }
        if at != start {
            continue;
        }
        let m = corners.iter().sum::<Vec3>() / corners.len() as f64;
        let g = g as usize;
        let mut area = Vec3::zeros();
        for (i, &p) in corners.iter().enumerate() {
            let q = corners[(i + 1) % corners.len()];
            area += (p - m).cross(&(q - m)) * 0.5;
            // The cap runs through the edge the other way than the surface.
            caps[g] += tetrahedron_at(centre, [q, p, m]);
        }
        hole_area[g] += area.norm();
    }
    (0..groups)
        .map(|g| {
            let enclosed = volume[g] + caps[g];
            let diagonal = (high[g] - low[g]).norm();
            // A patch without volume (two triangles back to back between non-manifold
            // edges) has only rounding to tell its sides apart.
            let doubt = (hole_area[g] * diagonal / 3.0).max(1e-9 * diagonal.powi(3));
            (candidate[g] && loops_close[g] && enclosed.abs() > doubt).then_some(enclosed)
        })
        .collect()
}

/// Signed volume of the tetrahedron of the triangle `[a, b, c]` and `centre`.
fn tetrahedron_at(centre: Vec3, [a, b, c]: [Vec3; 3]) -> f64 {
    (a - centre).dot(&(b - centre).cross(&(c - centre))) / 6.0
}

/// Signed volume of the tetrahedron of `triangle` and `centre` (positive when the triangle
/// faces away from `centre`).
fn tetrahedron_volume(mesh: &TriMesh, centre: Vec3, triangle: &[u32; 3]) -> f64 {
    let [a, b, c] = triangle.map(|v| mesh.position(v) - centre);
    a.dot(&b.cross(&c)) / 6.0
}

/// Reverses the triangles wound against the rest of their patch, then those of the closed
/// components that face inward (see the module docs), so that normals agree and point
/// outward. Returns the mesh unchanged (not rebuilt) when nothing is reversed, and the report
/// either way.
///
/// ```
/// use crestline::mesh::{orient_outward, signed_volume};
///
/// # fn main() -> crestline::Result<()> {
/// let sphere = crestline::shapes::icosphere(1.0, 2);
/// let faces = sphere.faces().iter().map(|t| [t[0], t[2], t[1]]).collect();
/// let inward = crestline::TriMesh::new(sphere.positions().to_vec(), faces)?;
/// assert!(signed_volume(&inward) < 0.0);
/// let (outward, report) = orient_outward(inward)?;
/// assert_eq!((report.closed, report.inward), (1, 1));
/// assert!(signed_volume(&outward) > 0.0);
/// # Ok(())
/// # }
/// ```
///
/// # Errors
/// None at present (reversing triangles keeps the connectivity as it is); the `Result` leaves
/// room for meshes that cannot be oriented.
pub fn orient_outward(mesh: TriMesh) -> Result<(TriMesh, Orientation)> {
    let (report, reversal) = classify(&mesh);
    if report.rewound_faces > 0 {
        let faces = mesh.faces();
        let reverse: Vec<bool> = (0..faces.len())
            .into_par_iter()
            .map(|f| reversal.reverses(f, &faces[f]))
            .collect();
        return Ok((mesh.with_flipped_faces(&reverse), report));
    }
    if report.inward == 0 {
        return Ok((mesh, report));
    }
    Ok((
        mesh.with_components_flipped_where(|f, t| reversal.is_inward(f, t)),
        report,
    ))
}

/// The same mesh with the faces `f` where `reverse[f]` wound the other way: applies the flags
/// of [`orientation`], so that `reverse_faces(mesh, &orientation(&mesh).1)` is
/// [`orient_outward`]`(mesh)`'s mesh. Faces past the end of `reverse` stay as they are. The
/// connectivity does not depend on the winding: it is kept, not rebuilt.
///
/// ```
/// use crestline::mesh::{orientation, reverse_faces, signed_volume};
///
/// # fn main() -> crestline::Result<()> {
/// let sphere = crestline::shapes::icosphere(1.0, 2);
/// let faces = sphere.faces().iter().map(|t| [t[0], t[2], t[1]]).collect();
/// let inward = crestline::TriMesh::new(sphere.positions().to_vec(), faces)?;
/// let (report, reverse) = orientation(&inward);
/// assert_eq!(report.inward, 1);
/// assert!(signed_volume(&reverse_faces(inward, &reverse)) > 0.0);
/// # Ok(())
/// # }
/// ```
pub fn reverse_faces(mesh: TriMesh, reverse: &[bool]) -> TriMesh {
    if reverse.iter().any(|&r| r) {
        mesh.with_flipped_faces(reverse)
    } else {
        mesh
    }
}

/// Signed volume enclosed by `mesh` (positive when a closed mesh faces outward). Meaningful
/// for closed, consistently oriented meshes only.
pub fn signed_volume(mesh: &TriMesh) -> f64 {
    let centre = mesh.bounding_box().center();
    mesh.faces()
        .iter()
        .map(|t| tetrahedron_volume(mesh, centre, t))
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes;

    fn flipped(mesh: &TriMesh) -> TriMesh {
        let faces = mesh.faces().iter().map(|t| [t[0], t[2], t[1]]).collect();
        TriMesh::new(mesh.positions().to_vec(), faces).unwrap()
    }

    #[test]
    fn a_sphere_wound_inward_is_flipped_and_one_wound_outward_is_not() {
        let sphere = shapes::icosphere(2.0, 3);
        let exact = 4.0 / 3.0 * std::f64::consts::PI * 8.0;
        // The icosphere's volume is a little below the sphere's.
        let v = signed_volume(&sphere);
        assert!(v > 0.95 * exact && v < exact, "volume {v}");
        let (same, report) = orient_outward(sphere.clone()).unwrap();
        assert_eq!(report.inward, 0);
        assert_eq!(report.closed, 1);
        assert_eq!(same.faces(), sphere.faces());

        let inward = flipped(&sphere);
        assert!((signed_volume(&inward) + v).abs() < 1e-9 * v);
        let (fixed, report) = orient_outward(inward).unwrap();
        assert_eq!(report.inward, 1);
        assert_eq!(report.inward_faces, sphere.num_faces());
        assert!((signed_volume(&fixed) - v).abs() < 1e-9 * v);
    }

    #[test]
    fn flipping_keeps_the_connectivity_a_rebuild_gives() {
        // An inward sphere (flipped), and apart from it three fins on one edge: boundary and
        // non-manifold edges.
        let sphere = flipped(&shapes::icosphere(1.0, 2));
        let mut positions = sphere.positions().to_vec();
        let mut faces = sphere.faces().to_vec();
        let n = positions.len() as u32;
        positions.extend([
            Vec3::new(3.0, 0.0, 0.0),
            Vec3::new(3.0, 1.0, 0.0),
            Vec3::new(4.0, 0.0, 0.0),
            Vec3::new(3.0, 0.0, 1.0),
            Vec3::new(2.0, 0.0, 0.0),
        ]);
        faces.extend([[n, n + 1, n + 2], [n + 1, n, n + 3], [n, n + 1, n + 4]]);
        let mesh = TriMesh::new(positions, faces).unwrap();
        let (report, flip) = orientation(&mesh);
        assert_eq!(report.inward_faces, sphere.num_faces());
        let kept = mesh.clone().with_flipped_faces(&flip);
        let mut faces = mesh.faces().to_vec();
        for (t, &f) in faces.iter_mut().zip(&flip) {
            if f {
                t.swap(1, 2);
            }
        }
        let rebuilt = TriMesh::new(mesh.positions().to_vec(), faces).unwrap();
        let (k, r) = (kept.topology(), rebuilt.topology());
        assert_eq!(k.faces(), r.faces());
        assert_eq!(k.edges(), r.edges());
        assert_eq!(k.vertex_kinds(), r.vertex_kinds());
        for e in 0..r.num_edges() as u32 {
            assert_eq!(k.edge_faces(e), r.edge_faces(e));
            assert_eq!(k.edge_kind(e), r.edge_kind(e));
        }
        for v in 0..r.num_vertices() as u32 {
            assert_eq!(k.vertex_faces(v), r.vertex_faces(v));
            assert_eq!(k.vertex_edges(v), r.vertex_edges(v));
            assert_eq!(k.has_open_edge(v), r.has_open_edge(v));
            assert_eq!(k.has_inconsistent_edge(v), r.has_inconsistent_edge(v));
        }
        for f in 0..r.faces().len() as u32 {
            assert_eq!(k.face_edges(f), r.face_edges(f));
            assert_eq!(k.face_neighbors(f), r.face_neighbors(f));
        }
    }

    #[test]
    fn only_the_inward_component_is_flipped() {
        // Two disjoint spheres, the second wound inward.
        let a = shapes::icosphere(1.0, 2);
        let b = flipped(&shapes::icosphere(1.0, 2));
        let n = a.num_vertices() as u32;
        let mut positions = a.positions().to_vec();
        positions.extend(b.positions().iter().map(|p| p + Vec3::new(5.0, 0.0, 0.0)));
        let mut faces = a.faces().to_vec();
        faces.extend(b.faces().iter().map(|t| t.map(|v| v + n)));
        let two = TriMesh::new(positions, faces).unwrap();
        let (report, per_face) = orientation(&two);
        assert_eq!(report.components, 2);
        assert_eq!(report.closed, 2);
        assert_eq!(report.inward, 1);
        assert!(per_face[..a.num_faces()].iter().all(|&x| !x));
        assert!(per_face[a.num_faces()..].iter().all(|&x| x));
        let (fixed, _) = orient_outward(two).unwrap();
        let (after, _) = orientation(&fixed);
        assert_eq!(after.inward, 0);
    }

    #[test]
    fn open_components_keep_their_winding() {
        // An open height field wound downward: no inside, nothing to decide.
        let field =
            shapes::height_field(|x, y| 0.1 * (x * x + y * y), [-1.0, 1.0], [-1.0, 1.0], 8, 8);
        let down = flipped(&field);
        let (report, reversed) = orientation(&down);
        assert_eq!(
            (
                report.components,
                report.closed,
                report.inward,
                report.rewound_faces
            ),
            (1, 0, 0, 0)
        );
        assert!(reversed.iter().all(|&r| !r));
        let topo = down.topology();
        let open = (0..down.num_vertices() as u32).filter(|&v| topo.has_open_edge(v));
        assert_eq!(open.count(), 4 * 8);
    }

    /// The faces of `mesh` for which `keep` holds (all vertices kept).
    fn keep_faces(mesh: &TriMesh, keep: impl Fn(&[Vec3; 3]) -> bool) -> TriMesh {
        let faces = (mesh.faces().iter())
            .filter(|t| keep(&t.map(|v| mesh.position(v))))
            .copied()
            .collect();
        TriMesh::new(mesh.positions().to_vec(), faces).unwrap()
    }

    #[test]
    fn an_open_surface_with_small_holes_is_turned_outward_and_a_hemisphere_is_not() {
        // A sphere wound inward with three holes (a scan): nearly closed, turned outward.
        let sphere = flipped(&shapes::icosphere(1.0, 3));
        let holes = [Vec3::x(), -Vec3::y(), Vec3::new(0.0, 0.6, 0.8)];
        let scan = keep_faces(&sphere, |p| {
            let c = (p[0] + p[1] + p[2]) / 3.0;
            holes.iter().all(|h| (c.normalize() - h).norm() > 0.25)
        });
        assert!(scan.num_faces() < sphere.num_faces() - 20);
        let (report, reversed) = orientation(&scan);
        assert_eq!(
            (report.closed, report.nearly_closed, report.inward),
            (0, 1, 1)
        );
        assert!(reversed.iter().all(|&r| r));
        let (outward, _) = orient_outward(scan).unwrap();
        assert_eq!(orientation(&outward).0.inward, 0);
        // A unit box without its lid (z = 1), wound inward: no lid over the hole, flat or a
        // cone inside the box, could change the sign (volume 1 against √3 / 3).
        let corners = (0..8)
            .map(|i| Vec3::new(f64::from(i & 1), f64::from((i >> 1) & 1), f64::from(i >> 2)))
            .collect();
        let outward_sides = [
            [0, 2, 1],
            [1, 2, 3],
            [0, 1, 5],
            [0, 5, 4],
            [1, 3, 7],
            [1, 7, 5],
            [3, 2, 6],
            [3, 6, 7],
            [2, 0, 4],
            [2, 4, 6],
        ];
        let inward_sides = outward_sides.map(|[a, b, c]| [a, c, b]).to_vec();
        let open_box = TriMesh::new(corners, inward_sides).unwrap();
        let (report, reversed) = orientation(&open_box);
        assert_eq!((report.nearly_closed, report.inward), (1, 1));
        assert!(reversed.iter().all(|&r| r));
        let (fixed, _) = orient_outward(open_box).unwrap();
        assert_eq!(fixed.faces(), &outward_sides[..]);
        // A hemisphere wound either way keeps its winding: its hole is as large as it.
        for hemisphere in [
            keep_faces(&sphere, |p| p.iter().all(|q| q.z >= -1e-9)),
            keep_faces(&flipped(&sphere), |p| p.iter().all(|q| q.z >= -1e-9)),
        ] {
            let (report, reversed) = orientation(&hemisphere);
            assert_eq!((report.nearly_closed, report.inward), (0, 0));
            assert!(reversed.iter().all(|&r| !r));
        }
    }

    /// `mesh` with the faces `f` where `pick(f)` wound the other way.
    fn some_flipped(mesh: &TriMesh, pick: impl Fn(usize) -> bool) -> TriMesh {
        let faces = mesh
            .faces()
            .iter()
            .enumerate()
            .map(|(f, &[a, b, c])| if pick(f) { [a, c, b] } else { [a, b, c] })
            .collect();
        TriMesh::new(mesh.positions().to_vec(), faces).unwrap()
    }

    #[test]
    fn a_triangle_wound_against_its_neighbours_is_reversed() {
        let sphere = shapes::icosphere(1.0, 2);
        let bad = some_flipped(&sphere, |f| f == 0);
        let (report, reversed) = orientation(&bad);
        assert_eq!(
            (
                report.closed,
                report.inconsistent,
                report.rewound_faces,
                report.inward,
                report.non_orientable
            ),
            (1, 1, 1, 0, 0)
        );
        assert_eq!(reversed.iter().filter(|&&r| r).count(), 1);
        assert!(reversed[0]);
        // Only the corners of the reversed triangle have an inconsistent edge.
        let topo = bad.topology();
        for v in 0..bad.num_vertices() as u32 {
            assert_eq!(topo.has_inconsistent_edge(v), bad.faces()[0].contains(&v));
            assert!(!topo.has_open_edge(v));
        }
        let (fixed, _) = orient_outward(bad).unwrap();
        assert_eq!(fixed.faces(), sphere.faces());
        let (after, _) = orientation(&fixed);
        assert_eq!((after.inconsistent, after.rewound_faces), (0, 0));
        // The same triangle reversed in place (the connectivity kept): the same verdict, and
        // reversing it back makes the sphere consistent again.
        let mut one = vec![false; sphere.num_faces()];
        one[0] = true;
        let reversed = sphere.clone().with_flipped_faces(&one);
        assert_eq!(orientation(&reversed).0, report);
        let back = reversed.with_flipped_faces(&one);
        assert_eq!(orientation(&back).0.inconsistent, 0);
    }

    #[test]
    fn the_winding_most_triangles_have_wins_then_the_volume_decides() {
        // A sphere wound inward with a third of its triangles wound outward: the third is
        // rewound to agree with the rest, then the whole sphere is turned outward.
        let sphere = shapes::icosphere(1.0, 3);
        let inward = some_flipped(&sphere, |f| f % 3 != 0);
        let (report, _) = orientation(&inward);
        assert_eq!(report.rewound_faces, sphere.num_faces().div_ceil(3));
        assert_eq!((report.closed, report.inward), (1, 1));
        let (fixed, _) = orient_outward(inward).unwrap();
        assert_eq!(fixed.faces(), sphere.faces());
        // An open height field wound upward with every third triangle wound downward.
        let field =
            shapes::height_field(|x, y| 0.1 * (x * x + y * y), [-1.0, 1.0], [-1.0, 1.0], 8, 8);
        let mixed = some_flipped(&field, |f| f % 3 == 1);
        let (report, _) = orientation(&mixed);
        let wrong = (0..field.num_faces()).filter(|f| f % 3 == 1).count();
        assert_eq!((report.closed, report.rewound_faces), (0, wrong));
        assert_eq!(orient_outward(mixed).unwrap().0.faces(), field.faces());
    }

    /// A Möbius strip of `n` segments, each two triangles, wound consistently but for the
    /// last segment's, where the strip is glued to itself turned over.
    fn moebius(n: usize) -> TriMesh {
        let mut positions = Vec::new();
        for i in 0..n {
            let t = i as f64 / n as f64 * std::f64::consts::TAU;
            for w in [-0.3, 0.3] {
                let r = 1.0 + w * (t / 2.0).cos();
                positions.push(Vec3::new(r * t.cos(), r * t.sin(), w * (t / 2.0).sin()));
            }
        }
        let mut faces = Vec::new();
        for i in 0..n {
            let (a, b) = (2 * i as u32, 2 * i as u32 + 1);
            // The strip comes back turned over: the last segment joins a to the next b.
            let (c, d) = if i + 1 < n { (a + 2, b + 2) } else { (1, 0) };
            faces.extend([[a, c, b], [b, c, d]]);
        }
        TriMesh::new(positions, faces).unwrap()
    }

    #[test]
    fn a_moebius_strip_has_no_consistent_winding_and_is_left_alone() {
        let strip = moebius(24);
        let (report, reversed) = orientation(&strip);
        assert_eq!(
            (
                report.components,
                report.closed,
                report.inconsistent,
                report.non_orientable
            ),
            (1, 0, 1, 1)
        );
        assert_eq!(report.rewound_faces, 0);
        assert!(reversed.iter().all(|&r| !r));
        let (same, _) = orient_outward(strip.clone()).unwrap();
        assert_eq!(same.faces(), strip.faces());
    }

    /// Two octahedra touching at one vertex, (1, 0, 0) of the first, of radius 1, and
    /// (−2, 0, 0) of the second, of radius 2 (its centre at (3, 0, 0)): one component, two
    /// closed surfaces. The first's faces `f` where `reverse_first(f)` and all of the
    /// second's are wound the other way.
    fn touching_octahedra(reverse_first: impl Fn(usize) -> bool) -> TriMesh {
        let small = shapes::octahedron();
        let mut positions = small.positions().to_vec();
        let mut faces: Vec<[u32; 3]> = (small.faces().iter().enumerate())
            .map(|(f, &[a, b, c])| {
                if reverse_first(f) {
                    [a, c, b]
                } else {
                    [a, b, c]
                }
            })
            .collect();
        // The big one's vertex 1, (−1, 0, 0) scaled by 2 about (3, 0, 0), is the small
        // one's vertex 0.
        let map = |v: u32| if v == 1 { 0 } else { 6 + v };
        positions.extend(
            small
                .positions()
                .iter()
                .map(|p| p * 2.0 + Vec3::new(3.0, 0.0, 0.0)),
        );
        faces.extend(
            small
                .faces()
                .iter()
                .map(|&[a, b, c]| [map(a), map(c), map(b)]),
        );
        TriMesh::new(positions, faces).unwrap()
    }

    #[test]
    fn shells_touching_at_a_vertex_are_turned_each_by_its_own_volume() {
        let outward = |mesh: &TriMesh| {
            mesh.faces().iter().all(|&[a, b, c]| {
                let [a, b, c] = [a, b, c].map(|v| mesh.position(v));
                let centre = if a.x + b.x + c.x > 3.0 {
                    Vec3::new(3.0, 0.0, 0.0)
                } else {
                    Vec3::zeros()
                };
                (b - a).cross(&(c - a)).dot(&(a + b + c - 3.0 * centre)) > 0.0
            })
        };
        for reversed in [0, 1] {
            let mesh = touching_octahedra(|f| f < reversed);
            let (report, _) = orientation(&mesh);
            assert_eq!(
                (
                    report.components,
                    report.closed,
                    report.inward,
                    report.rewound_faces
                ),
                (1, 2, 1, reversed)
            );
            let (fixed, _) = orient_outward(mesh).unwrap();
            assert!(outward(&fixed), "{reversed} reversed: {:?}", fixed.faces());
        }
    }
}
