//! Triangle meshes: geometry, connectivity and a health report.
//!
//! A [`TriMesh`] holds `f64` positions and `u32` triangles plus the connectivity
//! ([`Topology`]) built once when the mesh is made. Real meshes contain boundaries,
//! non-manifold edges and vertices, unreferenced vertices, degenerate triangles and several
//! components; none of these is an error here. Triangles with a repeated index or zero area
//! are kept out of the geometry and counted ([`TriMesh::degenerate_faces`]); everything else is
//! reported by [`MeshInfo`] and handled by the algorithms.
//!
//! Sign convention (used by every algorithm in the crate): face normals follow the winding
//! of the triangle by the right-hand rule; on a closed, consistently oriented mesh wound
//! counter-clockwise seen from outside, normals point outward.

mod geometry;
mod info;
pub mod lattice;
mod orient;
pub mod outliers;
mod sides;
mod subdivide;
mod topology;
pub(crate) mod weld;

pub use geometry::{
    BoundingBox, face_areas, face_normal_and_area, face_normals, mean_edge_length, star_areas,
    tangent_frame, vertex_normals_area, vertex_normals_max,
};
pub use info::MeshInfo;
pub use lattice::{Lattice, find_lattice};
pub use orient::{Orientation, orient_outward, orientation, reverse_faces, signed_volume};
pub use outliers::{OutlierRepair, find_outliers, repair_outliers};
pub(crate) use sides::corner_angle;
pub use sides::{SIDE_TIE, widest_side};
pub use subdivide::{SubdivideOptions, loop_subdivide};
pub use topology::{EdgeKind, Topology, VertexKind};
pub use weld::{Weld, coincident_vertices, weld_coincident, welded};

use std::sync::{Arc, OnceLock};

use rayon::prelude::*;

use crate::error::{Error, Result};

/// A 3-vector of `f64`, used for positions, normals and directions.
pub type Vec3 = nalgebra::Vector3<f64>;

/// A triangle mesh with its connectivity.
///
/// Construct with [`TriMesh::new`]; positions can be replaced later with
/// [`TriMesh::with_positions`] (for example after smoothing) without rebuilding connectivity.
///
/// Faces and connectivity (the faces live in the [`Topology`]) are shared, reference-counted,
/// between a mesh and the meshes made from it by [`TriMesh::with_positions`] or `clone`: they
/// take 65 of the 77 bytes per face of a mesh, and smoothed copies (YBS's pre-smoothing,
/// surface smoothing) only need new positions.
#[derive(Debug, Clone)]
pub struct TriMesh {
    positions: Vec<Vec3>,
    topology: Arc<Topology>,
    degenerate_faces: usize,
    /// [`TriMesh::model_size`], computed once (a union-find over the faces; an extraction
    /// reads it in four places). The winding does not change it; new positions get a new one.
    model_size: OnceLock<f64>,
}

impl TriMesh {
    /// Builds a mesh from positions and triangles.
    ///
    /// Triangles with a repeated vertex index or (numerically) zero area are dropped and
    /// counted in [`TriMesh::degenerate_faces`].
    ///
    /// # Errors
    /// [`Error::InvalidInput`] when a coordinate is NaN or infinite, or an index is out of range.
    pub fn new(positions: Vec<Vec3>, faces: Vec<[u32; 3]>) -> Result<Self> {
        if let Some(i) = positions
            .par_iter()
            .position_first(|p| !(p.x.is_finite() && p.y.is_finite() && p.z.is_finite()))
        {
            return Err(Error::InvalidInput(format!(
                "vertex {i} has a non-finite coordinate ({}, {}, {})",
                positions[i].x, positions[i].y, positions[i].z
            )));
        }
        let n = positions.len();
        if n > u32::MAX as usize {
            return Err(Error::InvalidInput(format!(
                "{n} vertices is more than the 2^32-1 this crate indexes"
            )));
        }
        // One pass over the faces counts the degenerate ones and notes whether an index is out
        // of range; only then is the first such face looked for (to name it).
        let (out_of_range, degenerate_faces) = faces
            .par_iter()
            .map(|t| {
                if t.iter().any(|&i| i as usize >= n) {
                    (true, 0)
                } else {
                    (false, usize::from(is_degenerate(&positions, t)))
                }
            })
            .reduce(|| (false, 0), |a, b| (a.0 || b.0, a.1 + b.1));
        if out_of_range
            && let Some(f) = faces
                .par_iter()
                .position_first(|t| t.iter().any(|&i| i as usize >= n))
        {
            let t = faces[f];
            return Err(Error::InvalidInput(format!(
                "face {f} ({} {} {}) refers to a vertex beyond the {n} there are",
                t[0], t[1], t[2]
            )));
        }
        // Usually there are none, and the faces are kept as they are.
        let faces: Vec<[u32; 3]> = if degenerate_faces == 0 {
            faces
        } else {
            faces
                .into_par_iter()
                .filter(|t| !is_degenerate(&positions, t))
                .collect()
        };
        let topology = Topology::from_faces(n, faces);
        Ok(TriMesh {
            positions,
            topology: Arc::new(topology),
            degenerate_faces,
            model_size: OnceLock::new(),
        })
    }

    /// Builds a mesh from `[f64; 3]` positions (as the readers produce them).
    ///
    /// # Errors
    /// As [`TriMesh::new`].
    pub fn from_arrays(positions: Vec<[f64; 3]>, faces: Vec<[u32; 3]>) -> Result<Self> {
        Self::new(positions.into_iter().map(Vec3::from).collect(), faces)
    }

    /// The same connectivity with new positions (one per vertex).
    ///
    /// Faces that were kept stay kept even if the new positions make them thin: connectivity
    /// does not change.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] when the count differs or a coordinate is not finite.
    pub fn with_positions(&self, positions: Vec<Vec3>) -> Result<Self> {
        if positions.len() != self.positions.len() {
            return Err(Error::InvalidInput(format!(
                "{} positions given for a mesh of {} vertices",
                positions.len(),
                self.positions.len()
            )));
        }
        if positions.iter().any(|p| !p.iter().all(|c| c.is_finite())) {
            return Err(Error::InvalidInput("non-finite coordinate".into()));
        }
        Ok(TriMesh {
            positions,
            topology: Arc::clone(&self.topology),
            degenerate_faces: self.degenerate_faces,
            model_size: OnceLock::new(),
        })
    }

    /// The same mesh with the faces `f` where `flip[f]` wound the other way (corners 1 and 2
    /// swapped). The connectivity does not depend on the winding: it is kept, not rebuilt.
    pub(crate) fn with_flipped_faces(mut self, flip: &[bool]) -> TriMesh {
        Arc::make_mut(&mut self.topology)
            .flip_faces(|f, _| flip.get(f).copied().unwrap_or(false), false);
        self
    }

    /// The same mesh with the faces of the connected components for which
    /// `flip(index, corners)` holds wound the other way (corners 1 and 2 swapped); `flip` must
    /// hold for all the faces of a component or none. The connectivity is kept, not rebuilt.
    pub(crate) fn with_components_flipped_where(
        mut self,
        flip: impl Fn(usize, &[u32; 3]) -> bool + Sync,
    ) -> TriMesh {
        Arc::make_mut(&mut self.topology).flip_faces(flip, true);
        self
    }

    /// The largest magnitude of a coordinate the algorithms accept: they form products of up
    /// to four lengths (squared areas, the units of squared extremalities), which must stay
    /// finite. Meshes hold and files store any finite coordinate exactly; no real model comes
    /// near this bound (the observable universe is 1e27 metres across).
    pub const MAX_COORDINATE: f64 = 1e75;

    /// `Ok` when every coordinate is at most [`TriMesh::MAX_COORDINATE`] in magnitude: the
    /// check the algorithms ([`crate::curvature::estimate`], [`crate::extract::extract`]) make
    /// before they start.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] naming the first vertex beyond the bound.
    pub fn check_coordinate_range(&self) -> Result<()> {
        let within = |p: &Vec3| p.iter().all(|c| c.abs() <= Self::MAX_COORDINATE);
        match self.positions.par_iter().position_first(|p| !within(p)) {
            None => Ok(()),
            Some(i) => {
                let p = self.positions[i];
                Err(Error::InvalidInput(format!(
                    "vertex {i} has a coordinate too large to compute with: ({:e}, {:e}, {:e}); \
                     |x| must be at most {:e} (scale the model down)",
                    p.x,
                    p.y,
                    p.z,
                    Self::MAX_COORDINATE
                )))
            }
        }
    }

    /// Vertex positions, one per vertex (including unreferenced ones).
    pub fn positions(&self) -> &[Vec3] {
        &self.positions
    }

    /// Position of vertex `v`.
    #[inline]
    pub fn position(&self, v: u32) -> Vec3 {
        self.positions[v as usize]
    }

    /// The triangles kept (degenerate ones dropped), with their input winding.
    pub fn faces(&self) -> &[[u32; 3]] {
        self.topology.faces()
    }

    /// Number of vertices, including unreferenced ones.
    pub fn num_vertices(&self) -> usize {
        self.positions.len()
    }

    /// Number of triangles kept.
    pub fn num_faces(&self) -> usize {
        self.topology.faces().len()
    }

    /// Connectivity: edges, adjacency, one-rings.
    pub fn topology(&self) -> &Topology {
        &self.topology
    }

    /// Triangles dropped because of a repeated index or zero area.
    pub fn degenerate_faces(&self) -> usize {
        self.degenerate_faces
    }

    /// The three corner positions of face `f`.
    #[inline]
    pub fn triangle(&self, f: usize) -> [Vec3; 3] {
        let [a, b, c] = self.topology.faces()[f];
        [
            self.positions[a as usize],
            self.positions[b as usize],
            self.positions[c as usize],
        ]
    }

    /// Axis-aligned bounding box of the referenced vertices (all vertices if none is referenced).
    pub fn bounding_box(&self) -> BoundingBox {
        geometry::bounding_box(self)
    }

    /// The size the feature-line pipeline measures relative lengths and strengths against:
    /// the bounding-box diagonal of the connected component (over shared vertices) with the
    /// largest area, or of the whole mesh when no component has area.
    ///
    /// The diagonal of the whole file would make the lines depend on what else the file holds:
    /// a stray triangle far from a scan, or a second part beside the first, stretches the box,
    /// and every minimum length, strength and tolerance with it (two copies of fandisk 200
    /// units apart lost every crest line). The largest part is what a user sees as the
    /// model; on a mesh of one component this is its bounding-box diagonal.
    ///
    /// ```
    /// use crestline::{TriMesh, Vec3};
    ///
    /// # fn main() -> crestline::Result<()> {
    /// let sphere = crestline::shapes::icosphere(1.0, 3);
    /// let size = sphere.model_size();
    /// assert!((size - sphere.bounding_box().diagonal()).abs() < 1e-12);
    /// // A speck 100 units away stretches the box, not the model size.
    /// let mut positions = sphere.positions().to_vec();
    /// let n = positions.len() as u32;
    /// positions.extend([
    ///     Vec3::new(100.0, 100.0, 100.0),
    ///     Vec3::new(100.01, 100.0, 100.0),
    ///     Vec3::new(100.0, 100.01, 100.0),
    /// ]);
    /// let mut faces = sphere.faces().to_vec();
    /// faces.push([n, n + 1, n + 2]);
    /// let with_speck = TriMesh::new(positions, faces)?;
    /// assert!(with_speck.bounding_box().diagonal() > 100.0);
    /// assert_eq!(with_speck.model_size(), size);
    /// # Ok(())
    /// # }
    /// ```
    pub fn model_size(&self) -> f64 {
        *self.model_size.get_or_init(|| geometry::model_size(self))
    }

    /// Counts and health figures for reports (`crestline info`).
    pub fn info(&self) -> MeshInfo {
        MeshInfo::of(self)
    }
}

/// True when a triangle has a repeated index or an area that is zero up to rounding.
fn is_degenerate(positions: &[Vec3], t: &[u32; 3]) -> bool {
    if t[0] == t[1] || t[1] == t[2] || t[0] == t[2] {
        return true;
    }
    let [a, b, c] = t.map(|i| positions[i as usize]);
    let (e1, e2, e3) = (b - a, c - a, c - b);
    // In units of the largest edge component, so that huge coordinates do not overflow the
    // products below (a triangle of sides 1e200 is large, not flat).
    let unit = e1.amax().max(e2.amax()).max(e3.amax());
    if unit == 0.0 {
        return true;
    }
    if !unit.is_finite() {
        return false;
    }
    let (e1, e2, e3) = (e1 / unit, e2 / unit, e3 / unit);
    let cross = e1.cross(&e2).norm();
    let scale = e1
        .norm_squared()
        .max(e2.norm_squared())
        .max(e3.norm_squared());
    // Relative test: a triangle whose height is ~1e-13 of its longest edge is flat to rounding.
    cross <= 1e-13 * scale
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn drops_and_counts_degenerate_faces() {
        let p = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [2.0, 0.0, 0.0],
        ];
        // Second face repeats an index, third is collinear.
        let m = TriMesh::from_arrays(p, vec![[0, 1, 2], [0, 0, 1], [0, 1, 3]]).unwrap();
        assert_eq!(m.num_faces(), 1);
        assert_eq!(m.degenerate_faces(), 2);
    }

    #[test]
    fn rejects_out_of_range_and_nan() {
        let e = TriMesh::from_arrays(vec![[0.0; 3]; 3], vec![[0, 1, 3]]).unwrap_err();
        assert!(e.to_string().contains("face 0"), "{e}");
        let e = TriMesh::from_arrays(vec![[0.0, f64::NAN, 0.0]], vec![]).unwrap_err();
        assert!(e.to_string().contains("non-finite"), "{e}");
    }
}
