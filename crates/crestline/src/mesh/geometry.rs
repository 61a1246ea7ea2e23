//! Per-face and per-vertex geometric quantities: normals, areas, edge lengths, bounds.
//!
//! Vertex normals come in two flavours: area-weighted (the sum of un-normalised face normals)
//! and Max's weights (N. Max, "Weights for computing vertex normals from facet normals",
//! JGT 1999), which are exact for vertices on a sphere and are what YBS 2005 uses before its
//! cubic fit. Both are unit length; an unreferenced vertex gets the zero vector.

use rayon::prelude::*;
use serde::Serialize;

use super::{TriMesh, Vec3};

/// An axis-aligned box.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct BoundingBox {
    /// Smallest corner.
    pub min: [f64; 3],
    /// Largest corner.
    pub max: [f64; 3],
}

impl BoundingBox {
    /// Length of the diagonal (0 for an empty box).
    pub fn diagonal(&self) -> f64 {
        let d = Vec3::from(self.max) - Vec3::from(self.min);
        if d.iter().all(|c| c.is_finite() && *c >= 0.0) {
            d.norm()
        } else {
            0.0
        }
    }

    /// Centre of the box.
    pub fn center(&self) -> Vec3 {
        (Vec3::from(self.max) + Vec3::from(self.min)) * 0.5
    }
}

pub(super) fn bounding_box(mesh: &TriMesh) -> BoundingBox {
    let topo = mesh.topology();
    let referenced = |v: usize| !topo.vertex_faces(v as u32).is_empty();
    let any_referenced = mesh.num_faces() > 0;
    let mut min = [f64::INFINITY; 3];
    let mut max = [f64::NEG_INFINITY; 3];
    for (v, p) in mesh.positions().iter().enumerate() {
        if any_referenced && !referenced(v) {
            continue;
        }
        for k in 0..3 {
            min[k] = min[k].min(p[k]);
            max[k] = max[k].max(p[k]);
        }
    }
    if min[0] > max[0] {
        return BoundingBox {
            min: [0.0; 3],
            max: [0.0; 3],
        };
    }
    BoundingBox { min, max }
}

/// [`TriMesh::model_size`]: per connected component its area and bounding box, in one pass
/// over the faces.
pub(super) fn model_size(mesh: &TriMesh) -> f64 {
    let faces = mesh.faces();
    let (component, count) = mesh.topology().vertex_components(faces);
    if count <= 1 {
        return bounding_box(mesh).diagonal();
    }
    let mut area = vec![0.0f64; count];
    let mut min = vec![[f64::INFINITY; 3]; count];
    let mut max = vec![[f64::NEG_INFINITY; 3]; count];
    for (f, t) in faces.iter().enumerate() {
        let c = component[t[0] as usize] as usize;
        area[c] += face_normal_and_area(mesh, f).1;
        for &v in t {
            let p = mesh.position(v);
            for k in 0..3 {
                min[c][k] = min[c][k].min(p[k]);
                max[c][k] = max[c][k].max(p[k]);
            }
        }
    }
    let diagonal = |c: usize| {
        BoundingBox {
            min: min[c],
            max: max[c],
        }
        .diagonal()
    };
    // The largest area; among equal areas (none: no component has area) the largest box.
    let largest = (0..count).max_by(|&a, &b| {
        area[a]
            .total_cmp(&area[b])
            .then(diagonal(a).total_cmp(&diagonal(b)))
    });
    match largest {
        Some(c) if area[c] > 0.0 => diagonal(c),
        _ => bounding_box(mesh).diagonal(),
    }
}

/// Unit face normals (right-hand rule on the winding).
pub fn face_normals(mesh: &TriMesh) -> Vec<Vec3> {
    (0..mesh.num_faces())
        .into_par_iter()
        .map(|f| {
            let [a, b, c] = mesh.triangle(f);
            (b - a)
                .cross(&(c - a))
                .try_normalize(0.0)
                .unwrap_or_else(Vec3::zeros)
        })
        .collect()
}

/// Unit normal and area of face `f` from one cross product (zero normal for a face made
/// degenerate by [`TriMesh::with_positions`]).
#[inline]
pub fn face_normal_and_area(mesh: &TriMesh, f: usize) -> (Vec3, f64) {
    let [a, b, c] = mesh.triangle(f);
    let cross = (b - a).cross(&(c - a));
    let norm = cross.norm();
    let normal = if norm > 0.0 {
        cross / norm
    } else {
        Vec3::zeros()
    };
    (normal, 0.5 * norm)
}

/// Face areas.
pub fn face_areas(mesh: &TriMesh) -> Vec<f64> {
    (0..mesh.num_faces())
        .into_par_iter()
        .map(|f| {
            let [a, b, c] = mesh.triangle(f);
            0.5 * (b - a).cross(&(c - a)).norm()
        })
        .collect()
}

/// Area of the star of each vertex: the sum of the areas of its faces (HPW's area(star(p))).
pub fn star_areas(mesh: &TriMesh, face_areas: &[f64]) -> Vec<f64> {
    let topo = mesh.topology();
    (0..mesh.num_vertices() as u32)
        .into_par_iter()
        .map(|v| {
            topo.vertex_faces(v)
                .iter()
                .map(|&f| face_areas[f as usize])
                .sum()
        })
        .collect()
}

/// Area-weighted unit vertex normals.
pub fn vertex_normals_area(mesh: &TriMesh) -> Vec<Vec3> {
    vertex_normals_with(mesh, |e1, e2| e1.cross(&e2))
}

/// Unit vertex normals with Max's weights: the sum over incident faces of
/// `(e1 × e2) / (|e1|² |e2|²)`, `e1`, `e2` the edges leaving the vertex in winding order.
pub fn vertex_normals_max(mesh: &TriMesh) -> Vec<Vec3> {
    vertex_normals_with(mesh, |e1, e2| {
        let d = e1.norm_squared() * e2.norm_squared();
        if d > 0.0 {
            e1.cross(&e2) / d
        } else {
            Vec3::zeros()
        }
    })
}

fn vertex_normals_with(mesh: &TriMesh, weight: impl Fn(Vec3, Vec3) -> Vec3 + Sync) -> Vec<Vec3> {
    let topo = mesh.topology();
    let faces = mesh.faces();
    let pos = mesh.positions();
    (0..mesh.num_vertices() as u32)
        .into_par_iter()
        .map(|v| {
            let p = pos[v as usize];
            let mut n = Vec3::zeros();
            for &f in topo.vertex_faces(v) {
                let t = faces[f as usize];
                let c = t.iter().position(|&x| x == v).unwrap_or(0);
                let a = pos[t[(c + 1) % 3] as usize];
                let b = pos[t[(c + 2) % 3] as usize];
                n += weight(a - p, b - p);
            }
            n.try_normalize(0.0).unwrap_or_else(Vec3::zeros)
        })
        .collect()
}

/// Mean length of the unique edges (0 for a mesh without faces).
pub fn mean_edge_length(mesh: &TriMesh) -> f64 {
    let edges = mesh.topology().edges();
    if edges.is_empty() {
        return 0.0;
    }
    let pos = mesh.positions();
    // Fixed chunks summed in order: a rayon `sum` adds in an order that depends on work
    // stealing, and the last bits of this length reach the smoothing time step, hence the
    // sign of extremalities that are zero up to rounding (lines on symmetric meshes).
    let partial: Vec<f64> = edges
        .par_chunks(4096)
        .map(|chunk| {
            chunk
                .iter()
                .map(|&[a, b]| (pos[a as usize] - pos[b as usize]).norm())
                .sum()
        })
        .collect();
    partial.iter().sum::<f64>() / edges.len() as f64
}

/// A right-handed orthonormal frame `(u, v, n)` around the unit normal `n`.
///
/// The tangent vectors depend only on `n`, so the (arbitrary) signs of the principal
/// directions built from them are fixed. A zero normal (unreferenced vertex) gives the
/// coordinate frame, so that nothing downstream sees a NaN.
pub fn tangent_frame(n: Vec3) -> (Vec3, Vec3, Vec3) {
    let Some(n) = n.try_normalize(1e-300) else {
        return (Vec3::x(), Vec3::y(), Vec3::z());
    };
    // Start from the coordinate axis least aligned with n: the projection is then at least
    // sqrt(2/3) long, far from cancellation.
    let axis = if n.x.abs() <= n.y.abs() && n.x.abs() <= n.z.abs() {
        Vec3::x()
    } else if n.y.abs() <= n.z.abs() {
        Vec3::y()
    } else {
        Vec3::z()
    };
    let u = (axis - n * n.dot(&axis)).normalize();
    let v = n.cross(&u);
    (u, v, n)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tetra_normals_point_outward() {
        let m = crate::shapes::tetrahedron();
        let c = Vec3::new(0.25, 0.25, 0.25);
        for (v, n) in vertex_normals_max(&m).iter().enumerate() {
            assert!((n.norm() - 1.0).abs() < 1e-12);
            assert!(n.dot(&(m.positions()[v] - c)) > 0.0);
        }
        let fnorm = face_normals(&m);
        assert!((fnorm[0] - Vec3::new(0.0, 0.0, -1.0)).norm() < 1e-12);
        let areas = face_areas(&m);
        assert!((areas[0] - 0.5).abs() < 1e-12);
        let star = star_areas(&m, &areas);
        assert!((star[0] - 1.5).abs() < 1e-12);
    }

    #[test]
    fn max_weights_are_exact_on_a_sphere() {
        // Vertex on the unit sphere with irregular neighbours also on the sphere.
        let p = |t: f64, f: f64| [t.sin() * f.cos(), t.sin() * f.sin(), t.cos()];
        let mut pos = vec![[0.0, 0.0, 1.0]];
        let angles = [0.0, 0.9, 2.1, 2.8, 4.0, 5.1];
        let thetas = [0.3, 0.5, 0.25, 0.45, 0.35, 0.6];
        for (a, t) in angles.iter().zip(thetas) {
            pos.push(p(t, *a));
        }
        let faces = (0..6)
            .map(|i| [0, 1 + i as u32, 1 + ((i + 1) % 6) as u32])
            .collect();
        let m = TriMesh::from_arrays(pos, faces).unwrap();
        let n = vertex_normals_max(&m)[0];
        assert!((n - Vec3::new(0.0, 0.0, 1.0)).norm() < 1e-12, "{n}");
        let n_area = vertex_normals_area(&m)[0];
        assert!((n_area - Vec3::new(0.0, 0.0, 1.0)).norm() > 1e-4);
    }

    #[test]
    fn bbox_and_edge_length() {
        let m = crate::shapes::tetrahedron();
        let b = m.bounding_box();
        assert_eq!(b.min, [0.0; 3]);
        assert_eq!(b.max, [1.0; 3]);
        assert!((b.diagonal() - 3f64.sqrt()).abs() < 1e-12);
        let expected = (3.0 + 3.0 * 2f64.sqrt()) / 6.0;
        assert!((mean_edge_length(&m) - expected).abs() < 1e-12);
    }
}
