//! Outward orientation of closed components.
//!
//! Every curvature sign in the crate follows the winding of the triangles (see the module
//! docs of [`crate::mesh`]): on a closed mesh wound clockwise seen from outside the normals
//! point inward, every principal curvature changes sign and ridges come out as valleys.
//! Such files are common (the shared `horse.ply` is one). [`orientation`] finds the closed,
//! consistently oriented components whose signed volume is negative; [`orient_outward`]
//! reverses their triangles.
//!
//! A component is *closed* when every edge of it has exactly two faces, and *consistent* when
//! the two faces of every edge run through it in opposite directions. Only closed,
//! consistent components have an inside and an outside to decide by volume; open ones (a
//! height field, a scan with holes) and inconsistent ones are left as they are and counted.
//! Components are the connected parts over shared vertices, as in [`super::MeshInfo`].

use std::sync::atomic::{AtomicBool, Ordering::Relaxed};

use rayon::prelude::*;

use crate::error::Result;

use super::{TriMesh, Vec3};

/// What [`orientation`] found.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Orientation {
    /// Connected components (over shared vertices).
    pub components: usize,
    /// Closed, consistently oriented components.
    pub closed: usize,
    /// Of those, the ones with negative signed volume (facing inward).
    pub inward: usize,
    /// Triangles in the inward components.
    pub inward_faces: usize,
    /// Components that are closed but not consistently oriented (left as they are).
    pub inconsistent: usize,
}

/// Faces per block when summing volumes.
const VOLUME_BLOCK: usize = 1 << 14;

/// Classifies the components of `mesh`; returns the report and, per face, whether it lies in
/// an inward-facing closed component.
pub fn orientation(mesh: &TriMesh) -> (Orientation, Vec<bool>) {
    let (report, components) = classify(mesh);
    let faces = mesh.faces();
    let per_face = (0..faces.len())
        .into_par_iter()
        .map(|f| components.is_inward(&faces[f]))
        .collect();
    (report, per_face)
}

/// The component of every vertex and whether each faces inward, from which whether a face
/// lies in an inward component is read off its first corner (no array per face).
struct Components {
    of_vertex: Vec<u32>,
    inward: Vec<bool>,
}

impl Components {
    fn is_inward(&self, triangle: &[u32; 3]) -> bool {
        self.inward[self.of_vertex[triangle[0] as usize] as usize]
    }
}

/// The report of [`orientation`] and the components it found.
fn classify(mesh: &TriMesh) -> (Orientation, Components) {
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
    let inconsistent: Vec<bool> = inconsistent
        .into_iter()
        .map(AtomicBool::into_inner)
        .collect();
    // Signed volumes about the bounding-box centre (for fewer cancellations): summed in
    // parallel over fixed blocks of faces, run by run of faces in one component, then block
    // by block in order, so the sums do not depend on the number of threads. The runs also
    // count the faces of each component.
    let centre = mesh.bounding_box().center();
    let runs: Vec<Vec<(u32, f64, usize)>> = faces
        .par_chunks(VOLUME_BLOCK)
        .map(|block| {
            let mut runs: Vec<(u32, f64, usize)> = Vec::new();
            for t in block {
                let c = vertex_component[t[0] as usize];
                let v = tetrahedron_volume(mesh, centre, t);
                match runs.last_mut() {
                    Some((last, sum, faces)) if *last == c => {
                        *sum += v;
                        *faces += 1;
                    }
                    _ => runs.push((c, v, 1)),
                }
            }
            runs
        })
        .collect();
    let mut volume = vec![0.0f64; count];
    let mut face_count = vec![0usize; count];
    for (c, v, n) in runs.into_iter().flatten() {
        volume[c as usize] += v;
        face_count[c as usize] += n;
    }
    let mut report = Orientation {
        components: count,
        ..Default::default()
    };
    let mut flip = vec![false; count];
    for c in 0..count {
        if open[c] {
            continue;
        }
        if inconsistent[c] {
            report.inconsistent += 1;
            continue;
        }
        report.closed += 1;
        if volume[c] < 0.0 {
            report.inward += 1;
            report.inward_faces += face_count[c];
            flip[c] = true;
        }
    }
    let components = Components {
        of_vertex: vertex_component,
        inward: flip,
    };
    (report, components)
}

/// Signed volume of the tetrahedron of `triangle` and `centre` (positive when the triangle
/// faces away from `centre`).
fn tetrahedron_volume(mesh: &TriMesh, centre: Vec3, triangle: &[u32; 3]) -> f64 {
    let [a, b, c] = triangle.map(|v| mesh.position(v) - centre);
    a.dot(&b.cross(&c)) / 6.0
}

/// Reverses the triangles of the closed components that face inward (see the module docs),
/// so that normals point outward. Returns the mesh unchanged (not rebuilt) when nothing faces
/// inward, and the report either way.
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
    let (report, components) = classify(&mesh);
    if report.inward == 0 {
        return Ok((mesh, report));
    }
    Ok((
        mesh.with_components_flipped_where(|_, t| components.is_inward(t)),
        report,
    ))
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
    fn open_and_inconsistent_components_are_left_alone() {
        // An open height field wound downward: no inside, nothing to decide.
        let field =
            shapes::height_field(|x, y| 0.1 * (x * x + y * y), [-1.0, 1.0], [-1.0, 1.0], 8, 8);
        let down = flipped(&field);
        let (report, _) = orientation(&down);
        assert_eq!((report.components, report.closed, report.inward), (1, 0, 0));
        // A sphere with one triangle reversed: closed but inconsistent.
        let sphere = shapes::icosphere(1.0, 2);
        let mut faces = sphere.faces().to_vec();
        faces[0].swap(1, 2);
        let bad = TriMesh::new(sphere.positions().to_vec(), faces).unwrap();
        let (report, _) = orientation(&bad);
        assert_eq!(
            (report.closed, report.inconsistent, report.inward),
            (0, 1, 0)
        );
        // The same triangle reversed in place (the connectivity kept): the same verdict, and
        // reversing it back makes the sphere consistent again.
        let mut one = vec![false; sphere.num_faces()];
        one[0] = true;
        let reversed = sphere.clone().with_flipped_faces(&one);
        assert_eq!(orientation(&reversed).0, report);
        let back = reversed.with_flipped_faces(&one);
        let (report, _) = orientation(&back);
        assert_eq!(
            (report.closed, report.inconsistent, report.inward),
            (1, 0, 0)
        );
        // Only the corners of the reversed triangle have an inconsistent edge.
        let topo = bad.topology();
        for v in 0..bad.num_vertices() as u32 {
            assert_eq!(topo.has_inconsistent_edge(v), bad.faces()[0].contains(&v));
            assert!(!topo.has_open_edge(v));
        }
        let topo = down.topology();
        let open = (0..down.num_vertices() as u32).filter(|&v| topo.has_open_edge(v));
        assert_eq!(open.count(), 4 * 8);
    }
}
