//! Welding: vertices at the same position made one.
//!
//! Many files hold a surface as pieces that share positions but not vertices: the patches of
//! a parametric model exported side by side (the Utah teapot of `../shared/data/meshes` has
//! 403 such vertices and 37 boundary loops, 6 once welded), seams split for texture
//! coordinates or for hard normals, STL's separate corners. Connectivity then stops at every
//! seam: a fitting disc ends there, so the fits along it see half a disc and the lines broken
//! off at it. [`weld_coincident`] joins the pieces again.
//!
//! Only bitwise-equal positions are merged (+0 and −0 count as equal): a tolerance would
//! merge features that are merely close (the two sides of a thin slot, a fold). Unreferenced
//! vertices are left as they are.

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

use rayon::prelude::*;

use crate::error::Result;

use super::{EdgeKind, TriMesh, Vec3};

/// What [`weld_coincident`] did.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Weld {
    /// Vertices (used by a triangle) merged into another one at the same position.
    pub merged: usize,
    /// Triangles dropped because, welded, they had the corners of an earlier triangle (either
    /// winding): the two sides of a double-sided export, a piece stored twice.
    pub duplicate_faces: usize,
    /// Per vertex of the mesh given, its index in the welded mesh (the identity when nothing
    /// was merged).
    pub map: Vec<u32>,
    /// Vertices of the welded mesh.
    pub vertices: usize,
}

impl Weld {
    /// Nothing merged, for a mesh of `vertices` vertices.
    pub fn identity(vertices: usize) -> Self {
        Weld {
            merged: 0,
            duplicate_faces: 0,
            map: (0..vertices as u32).collect(),
            vertices,
        }
    }

    /// Values per vertex of the mesh given, carried to the welded mesh: where vertices were
    /// merged, their values are folded together by `combine` in the order of the vertices.
    /// `None` unless there is one value per vertex given.
    pub fn to_welded<T: Copy>(&self, values: &[T], combine: impl Fn(T, T) -> T) -> Option<Vec<T>> {
        if values.len() != self.map.len() {
            return None;
        }
        let mut welded: Vec<Option<T>> = vec![None; self.vertices];
        for (&to, &value) in self.map.iter().zip(values) {
            let slot = &mut welded[to as usize];
            *slot = Some(slot.map_or(value, |sofar| combine(sofar, value)));
        }
        welded.into_iter().collect()
    }

    /// Values per vertex of the welded mesh, carried back to the mesh given: each vertex
    /// takes the value of the vertex it was merged into. `None` unless there is one value per
    /// welded vertex.
    pub fn to_given<T: Copy>(&self, values: &[T]) -> Option<Vec<T>> {
        (values.len() == self.vertices)
            .then(|| self.map.iter().map(|&m| values[m as usize]).collect())
    }
}

/// Merges the vertices used by triangles that lie at bitwise the same position into the first
/// of them; the others are dropped and the indices closed up, in order. Triangles keep their
/// order (none becomes degenerate: two corners at one position made it so already), except
/// that a triangle that now has the corners of an earlier one, in either winding, is dropped
/// ([`Weld::duplicate_faces`]): welded, the two sides of a double-sided export would make every
/// edge non-manifold. Triangles that repeat others without any welding (a piece stored twice
/// over the same vertices) are dropped alike. The mesh is returned as it is when no two used
/// vertices share a position and no triangle repeats another.
///
/// ```
/// use crestline::TriMesh;
/// use crestline::mesh::{EdgeKind, weld_coincident};
///
/// # fn main() -> crestline::Result<()> {
/// // Two triangles of a square, exported as separate pieces: vertices 3 and 4 repeat 0 and 2.
/// let square = TriMesh::from_arrays(
///     vec![[0., 0., 0.], [1., 0., 0.], [1., 1., 0.], [0., 0., 0.], [1., 1., 0.], [0., 1., 0.]],
///     vec![[0, 1, 2], [3, 4, 5]],
/// )?;
/// assert_eq!(square.topology().count_edges(EdgeKind::Boundary), 6);
/// let (welded, weld) = weld_coincident(square)?;
/// assert_eq!((welded.num_vertices(), weld.merged), (4, 2));
/// assert_eq!(weld.map, [0, 1, 2, 0, 2, 3]);
/// assert_eq!(welded.topology().count_edges(EdgeKind::Boundary), 4);
/// # Ok(())
/// # }
/// ```
///
/// # Errors
/// None in practice (the welded mesh is checked as every mesh is built).
pub fn weld_coincident(mesh: TriMesh) -> Result<(TriMesh, Weld)> {
    Ok(match welded(&mesh)? {
        Some(welded) => welded,
        None => {
            let weld = Weld::identity(mesh.num_vertices());
            (mesh, weld)
        }
    })
}

/// [`weld_coincident`] of a mesh that is kept: the welded mesh, or `None` when no two used
/// vertices share a position and no triangle repeats another (nothing to copy then).
///
/// # Errors
/// As [`weld_coincident`].
pub fn welded(mesh: &TriMesh) -> Result<Option<(TriMesh, Weld)>> {
    let n = mesh.num_vertices();
    let (into, merged) = first_at_each_position(mesh);
    if merged == 0 {
        return without_repeated_faces(mesh);
    }
    let mut map = vec![0u32; n];
    let mut positions = Vec::with_capacity(n - merged);
    for v in 0..n {
        if into[v] as usize == v {
            map[v] = positions.len() as u32;
            positions.push(mesh.position(v as u32));
        }
    }
    for v in 0..n {
        map[v] = map[into[v] as usize];
    }
    let remapped: Vec<[u32; 3]> = mesh
        .faces()
        .par_iter()
        .map(|t| t.map(|i| map[i as usize]))
        .collect();
    let (faces, duplicate_faces) = drop_repeated_faces(remapped);
    let vertices = positions.len();
    let mut welded = TriMesh::new(positions, faces)?;
    welded.degenerate_faces += mesh.degenerate_faces;
    let weld = Weld {
        merged,
        duplicate_faces,
        map,
        vertices,
    };
    Ok(Some((welded, weld)))
}

/// The mesh without the triangles that repeat the corners of an earlier one (either winding)
/// when nothing is welded, or `None` when there are none. Repeated triangles make their edges
/// non-manifold (a double-sided piece, a piece stored twice), so a mesh without non-manifold
/// edges is not searched.
fn without_repeated_faces(mesh: &TriMesh) -> Result<Option<(TriMesh, Weld)>> {
    if mesh.topology().count_edges(EdgeKind::NonManifold) == 0 {
        return Ok(None);
    }
    let (faces, duplicate_faces) = drop_repeated_faces(mesh.faces().to_vec());
    if duplicate_faces == 0 {
        return Ok(None);
    }
    let mut kept = TriMesh::new(mesh.positions().to_vec(), faces)?;
    kept.degenerate_faces += mesh.degenerate_faces;
    let weld = Weld {
        duplicate_faces,
        ..Weld::identity(mesh.num_vertices())
    };
    Ok(Some((kept, weld)))
}

/// The triangles without those that repeat the corners of an earlier one (either winding),
/// and how many were dropped.
fn drop_repeated_faces(faces: Vec<[u32; 3]>) -> (Vec<[u32; 3]>, usize) {
    let mut order: Vec<([u32; 3], u32)> = faces
        .par_iter()
        .enumerate()
        .map(|(f, t)| {
            let mut corners = *t;
            corners.sort_unstable();
            (corners, f as u32)
        })
        .collect();
    order.par_sort_unstable();
    let mut repeated = vec![false; faces.len()];
    let mut count = 0;
    for run in order.chunk_by(|a, b| a.0 == b.0) {
        for &(_, f) in &run[1..] {
            repeated[f as usize] = true;
            count += 1;
        }
    }
    if count == 0 {
        return (faces, 0);
    }
    let kept = faces
        .into_iter()
        .zip(repeated)
        .filter_map(|(t, repeated)| (!repeated).then_some(t))
        .collect();
    (kept, count)
}

/// The number of used vertices that share their position with another used vertex and
/// come after it: the vertices [`weld_coincident`] would merge.
pub fn coincident_vertices(mesh: &TriMesh) -> usize {
    first_at_each_position(mesh).1
}

/// Per vertex, the first used vertex at its position (itself when it is the first, or when
/// it is unused), and how many used vertices are not the first at theirs.
///
/// By sorting the used vertices by a hash of their position (in parallel; then equal
/// positions are neighbours, in the order of their indices) rather than by a hash map: on a
/// mesh of a million vertices the map's scattered reads took 0.19 s, more than the
/// connectivity.
fn first_at_each_position(mesh: &TriMesh) -> (Vec<u32>, usize) {
    let n = mesh.num_vertices();
    let topo = mesh.topology();
    let key = |v: u32| position_key(mesh.position(v));
    let mut order: Vec<(u64, u32)> = (0..n as u32)
        .into_par_iter()
        .filter(|&v| !topo.vertex_faces(v).is_empty())
        .map(|v| {
            let k = key(v);
            let mut hasher = WeldHasher::default();
            for c in k.iter() {
                hasher.write_u64(*c);
            }
            (hasher.finish(), v)
        })
        .collect();
    order.par_sort_unstable();
    let mut into: Vec<u32> = (0..n as u32).collect();
    let mut merged = 0;
    for run in order.chunk_by_mut(|a, b| a.0 == b.0) {
        if run.len() < 2 {
            continue;
        }
        // Equal hashes, nearly always equal positions; by position, then index, each goes to
        // the first at its position.
        run.sort_unstable_by_key(|&(_, v)| (key(v), v));
        for pair in run.windows(2) {
            let (first, v) = (pair[0].1, pair[1].1);
            if key(first) == key(v) {
                into[v as usize] = into[first as usize];
                merged += 1;
            }
        }
    }
    (into, merged)
}

/// The bits of a position's coordinates, +0 and −0 alike: equal keys, same place.
fn position_key(p: Vec3) -> [u64; 3] {
    // Adding +0 turns −0 into +0 and leaves every other value as it is.
    [p.x, p.y, p.z].map(|c| (c + 0.0).to_bits())
}

/// One index per distinct position (bitwise, +0 = −0): the first one given for it.
pub(crate) struct PositionMap {
    // Tuples, not arrays: an array's hash writes its length first.
    index_of: HashMap<(u64, u64, u64), u32, BuildHasherDefault<WeldHasher>>,
}

impl PositionMap {
    pub(crate) fn with_capacity(n: usize) -> Self {
        PositionMap {
            index_of: HashMap::with_capacity_and_hasher(n, Default::default()),
        }
    }

    /// The index of `p`: the one it was first given, or else `index`.
    #[inline]
    pub(crate) fn index_or(&mut self, p: Vec3, index: u32) -> u32 {
        let [x, y, z] = position_key(p);
        *self.index_of.entry((x, y, z)).or_insert(index)
    }
}

/// A fast multiplicative hasher for the position keys: std's default SipHash guards against
/// adversarial keys, which costs more than a whole STL parse and buys nothing here (a hostile
/// file can only slow its own loading down).
#[derive(Default)]
struct WeldHasher(u64);

impl Hasher for WeldHasher {
    #[inline]
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.write_u64(u64::from(b));
        }
    }

    #[inline]
    fn write_u64(&mut self, x: u64) {
        self.0 = (self.0.rotate_left(23) ^ x).wrapping_mul(0x9e37_79b9_7f4a_7c15);
    }

    #[inline]
    fn finish(&self) -> u64 {
        // Fold the well-mixed high bits down: hashbrown takes its bucket from the low bits.
        self.0 ^ (self.0 >> 29)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::EdgeKind;

    /// An octahedron cut into its eight faces, each with its own three corners (as STL
    /// stores it, and as patches are exported), +0 and −0 mixed.
    fn octahedron_in_pieces() -> TriMesh {
        let octahedron = crate::shapes::octahedron();
        let mut positions = Vec::new();
        let mut triangles = Vec::new();
        for (f, t) in octahedron.faces().iter().enumerate() {
            let base = positions.len() as u32;
            for &c in t {
                let p: [f64; 3] = octahedron.position(c).into();
                // Odd faces write their zeros as −0.
                positions.push(p.map(|x| if f % 2 == 1 && x == 0.0 { -0.0 } else { x }));
            }
            triangles.push([base, base + 1, base + 2]);
        }
        // An unused vertex at a corner's place stays as it is.
        positions.push([1.0, 0.0, 0.0]);
        TriMesh::from_arrays(positions, triangles).unwrap()
    }

    #[test]
    fn pieces_of_a_closed_surface_are_joined() {
        let pieces = octahedron_in_pieces();
        assert_eq!(pieces.topology().count_edges(EdgeKind::Boundary), 24);
        assert_eq!(coincident_vertices(&pieces), 24 - 6);
        let (welded, weld) = weld_coincident(pieces.clone()).unwrap();
        assert_eq!(weld.merged, 24 - 6);
        // The six corners and the unused vertex.
        assert_eq!(welded.num_vertices(), 7);
        assert_eq!(welded.num_faces(), 8);
        assert_eq!(welded.topology().count_edges(EdgeKind::Boundary), 0);
        assert_eq!(welded.topology().count_edges(EdgeKind::NonManifold), 0);
        // Every vertex keeps its place, and the triangles their corners' places and order.
        for (v, &w) in weld.map.iter().enumerate() {
            assert_eq!(pieces.position(v as u32), welded.position(w));
        }
        for (t, u) in pieces.faces().iter().zip(welded.faces()) {
            assert_eq!(t.map(|i| weld.map[i as usize]), *u);
        }
        // The unused vertex was not merged with the corner at its place.
        assert_ne!(weld.map[24], weld.map[0]);
        assert_eq!(coincident_vertices(&welded), 0);
        // Values per vertex go across and back: the first copy's value wins.
        let given: Vec<usize> = (0..25).collect();
        let there = weld.to_welded(&given, |first, _| first).unwrap();
        assert_eq!(there.len(), 7);
        let back = weld.to_given(&there).unwrap();
        for (v, &value) in back.iter().enumerate() {
            let first = weld.map.iter().position(|&m| m == weld.map[v]).unwrap();
            assert_eq!(value, first);
        }
        assert!(weld.to_welded(&given[1..], usize::min).is_none());
        assert!(weld.to_given(&given).is_none());
    }

    #[test]
    fn the_two_sides_of_a_double_sided_export_become_one() {
        // Every piece twice, the second time wound the other way (and once more the same
        // way): welded, the copies would give every edge four triangles.
        let pieces = octahedron_in_pieces();
        let mut positions: Vec<[f64; 3]> = pieces.positions().iter().map(|&p| p.into()).collect();
        let mut faces = pieces.faces().to_vec();
        for (k, t) in pieces.faces().iter().enumerate() {
            let base = positions.len() as u32;
            positions.extend(t.map(|v| <[f64; 3]>::from(pieces.position(v))));
            faces.push(if k % 2 == 0 {
                [base, base + 2, base + 1]
            } else {
                [base, base + 1, base + 2]
            });
        }
        let double = TriMesh::from_arrays(positions, faces).unwrap();
        let (welded, weld) = weld_coincident(double).unwrap();
        assert_eq!((weld.merged, weld.duplicate_faces), (48 - 6, 8));
        assert_eq!(
            welded.faces(),
            &pieces
                .faces()
                .iter()
                .map(|t| t.map(|i| weld.map[i as usize]))
                .collect::<Vec<_>>()[..]
        );
        assert_eq!(welded.topology().count_edges(EdgeKind::NonManifold), 0);
        assert_eq!(welded.topology().count_edges(EdgeKind::Boundary), 0);
        assert_eq!(weld.vertices, welded.num_vertices());
    }

    #[test]
    fn triangles_stored_twice_over_the_same_vertices_are_dropped() {
        // A closed sphere whose triangles all appear twice, the copies wound either way:
        // nothing to weld, but every edge has four triangles.
        let sphere = crate::shapes::icosphere(1.0, 2);
        let mut faces = sphere.faces().to_vec();
        for (k, &[a, b, c]) in sphere.faces().iter().enumerate() {
            faces.push(if k % 2 == 0 { [a, c, b] } else { [b, c, a] });
        }
        let twice = TriMesh::new(sphere.positions().to_vec(), faces).unwrap();
        assert!(twice.topology().count_edges(EdgeKind::NonManifold) > 0);
        let (kept, weld) = welded(&twice).unwrap().expect("repeated triangles dropped");
        assert_eq!((weld.merged, weld.duplicate_faces), (0, sphere.num_faces()));
        assert_eq!(kept.faces(), sphere.faces());
        assert_eq!(kept.positions(), sphere.positions());
        assert_eq!(
            weld.map,
            (0..sphere.num_vertices() as u32).collect::<Vec<_>>()
        );
        assert_eq!(kept.topology().count_edges(EdgeKind::NonManifold), 0);
    }

    #[test]
    fn a_mesh_without_shared_positions_is_returned_as_it_is() {
        let mesh = crate::shapes::icosphere(1.0, 2);
        let (welded, weld) = weld_coincident(mesh.clone()).unwrap();
        assert_eq!(weld.merged, 0);
        assert_eq!(welded.faces(), mesh.faces());
        assert_eq!(welded.positions(), mesh.positions());
        assert!(weld.map.iter().enumerate().all(|(v, &w)| v as u32 == w));
    }

    #[test]
    fn close_but_distinct_positions_stay_apart() {
        let mesh = TriMesh::from_arrays(
            vec![
                [0., 0., 0.],
                [1., 0., 0.],
                [0., 1., 0.],
                [1e-12, 0., 0.],
                [1., 0., 1.],
                [0., 1., 1.],
            ],
            vec![[0, 1, 2], [3, 4, 5]],
        )
        .unwrap();
        let (welded, weld) = weld_coincident(mesh).unwrap();
        assert_eq!((weld.merged, welded.num_vertices()), (0, 6));
    }
}
