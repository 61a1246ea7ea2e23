//! Meshes made by marching cubes and left as it made them: every vertex on an edge of a grid.
//!
//! Marching cubes (Lorensen and Cline, SIGGRAPH 1987; scikit-image, VTK, Open3D and CGAL all
//! run it) puts each vertex where the linear interpolation of the function along a grid edge
//! crosses zero. Two of its coordinates are then those of grid planes and the third, along its
//! edge, is off the surface by the interpolation's error, about `−(f_aa / 2 f_a) t (1 − t) h²`
//! for grid spacing h and the vertex at a fraction t of its edge (measured against the exact
//! crossing: correlation 1.0000, `bench/quality/mc_raw.py --model`). Where the surface crosses
//! the grid's planes those errors form terraces, which are crest lines of the mesh: on the
//! public superquadric meshed so, rings of ridges on its flat faces (`BENCHMARKS.md`, "Open: raw
//! marching cubes"). Nothing here repairs them yet; [`find_lattice`] recognises such meshes so
//! that a caller can say so.
//!
//! **Test.** Along each axis the grid's planes hold most of the vertices, so their coordinates
//! repeat exactly: the values the most vertices share are planes, side by side, and the
//! grid spacing h is their smallest step, fitted again over every shared value on the planes
//! (`axis_planes`). A mesh is taken for a marching-cubes lattice when at least
//! [`ON_GRID_SHARE`] of its vertices have two coordinates on the grid planes (within
//! [`ON_GRID`] h), at least two axes are each the free one of [`FREE_AXIS_SHARE`] of them, and
//! no edge is longer than a cell's diagonal (√3 times the largest spacing: marching cubes joins
//! points on the edges of one cell). A height field sampled on a grid has x and y on a lattice
//! too, but z free everywhere and no interpolation error; a voxel mesh has all three on it; a
//! CAD part whose edges run along the axes, exported as fans, has its vertices on the planes of
//! its faces, but edges as long as its faces. A first look at the coordinates of 4,096 of the
//! vertices ends the test on meshes whose coordinates do not repeat (nearly all), without
//! copying or sorting them.
//! Measured in `BENCHMARKS.md`, "Open: raw marching cubes": every raw marching-cubes mesh made
//! there found, none of 199 others. Not found (a review's port of the test, not measured here):
//! shapes with large flat faces along the grid's planes (a box, a rounded box), whose faces'
//! free coordinates are shared by more vertices than the planes; shapes less than three cells
//! thick along an axis; coordinates rounded to more than a hundredth of the spacing.

use std::collections::HashMap;

use rayon::prelude::*;

use super::{TriMesh, Vec3};

/// The grid a marching-cubes mesh was made on ([`find_lattice`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lattice {
    /// The grid spacing along x, y and z.
    pub spacing: [f64; 3],
    /// A grid plane along each axis: the planes are `origin[a] + k spacing[a]`.
    pub origin: [f64; 3],
    /// Per axis, the share of the vertices whose free coordinate (off the grid's planes) is
    /// along it.
    pub free_share: [f64; 3],
}

/// Share of the vertices that must have two coordinates on the grid planes.
pub const ON_GRID_SHARE: f64 = 0.99;

/// Distance from a grid plane, in grid spacings, within which a coordinate is on it
/// (marching cubes writes `index × h` plus a corner: rounding alone, and a file's digits: six
/// significant digits at coordinates near 300 on a grid of spacing 0.066 are 8e-3 of it). A
/// mesh made otherwise would need 99% of its vertices within it of the planes on two axes.
pub const ON_GRID: f64 = 1e-2;

/// Share of the vertices that at least two axes must each be the free axis of.
pub const FREE_AXIS_SHARE: f64 = 0.05;

/// Vertices the first look takes.
const SAMPLE: usize = 4096;

/// The marching-cubes grid of `mesh` when its vertices lie on one (module docs), else `None`.
pub fn find_lattice(mesh: &TriMesh) -> Option<Lattice> {
    // First look, on the positions as they are: along every axis, a sample's coordinates
    // repeat on the grid's planes. Nearly every other mesh ends here, before any copy.
    let all = mesh.positions();
    if all.len() < 8 {
        return None;
    }
    let stride = all.len().div_ceil(SAMPLE);
    for a in 0..3 {
        let mut counts: HashMap<u64, usize> = HashMap::new();
        for p in all.iter().step_by(stride) {
            *counts.entry(p[a].to_bits()).or_default() += 1;
        }
        let sampled = all.len().div_ceil(stride);
        let repeated: usize = counts.values().filter(|&&c| c >= 2).sum();
        if (repeated as f64) < 0.3 * sampled as f64 {
            return None;
        }
    }
    let topology = mesh.topology();
    // The vertices of the triangles (stray unreferenced points are no part of the surface).
    let positions: Vec<Vec3> = (0..mesh.num_vertices() as u32)
        .filter(|&v| !topology.vertex_faces(v).is_empty())
        .map(|v| mesh.position(v))
        .collect();
    let n = positions.len();
    if n < 8 {
        return None;
    }
    let mut spacing = [0.0; 3];
    let mut origin = [0.0; 3];
    for a in 0..3 {
        (spacing[a], origin[a]) = axis_planes(positions.par_iter().map(|p| p[a]).collect())?;
    }
    let on_plane = |x: f64, a: usize| {
        let k = (x - origin[a]) / spacing[a];
        (k - k.round()).abs() < ON_GRID
    };
    // Vertices with two coordinates (or three) on the planes, and per axis those whose third
    // is off them along it.
    let [on_grid, x, y, z] = positions
        .par_iter()
        .map(|p| {
            let on = [0, 1, 2].map(|a| on_plane(p[a], a));
            let mut counts = [0usize; 4];
            let planes = on.iter().filter(|&&on| on).count();
            if planes >= 2 {
                counts[0] = 1;
            }
            if planes == 2 {
                counts[1 + on.iter().position(|&on| !on).unwrap_or(0)] = 1;
            }
            counts
        })
        .reduce(|| [0; 4], |a, b| [0, 1, 2, 3].map(|k| a[k] + b[k]));
    let free_share = [x, y, z].map(|count| count as f64 / n as f64);
    let free_axes = free_share.iter().filter(|&&s| s >= FREE_AXIS_SHARE).count();
    if on_grid < (ON_GRID_SHARE * n as f64).ceil() as usize || free_axes < 2 {
        return None;
    }
    let diagonal = 3f64.sqrt() * spacing.iter().fold(0.0f64, |m, &h| m.max(h));
    let within_cells = topology.edges().par_iter().all(|&[a, b]| {
        (mesh.position(a) - mesh.position(b)).norm() <= diagonal * (1.0 + 2.0 * ON_GRID)
    });
    within_cells.then_some(Lattice {
        spacing,
        origin,
        free_share,
    })
}

/// The spacing and one plane of the grid along one axis, from the vertices' coordinates
/// along it: the [`PLANES`] values that the most vertices share (three at least, and an
/// eighth as many as the most shared) are grid planes, the widest sections of the shape, side
/// by side; the spacing is their smallest step, of which every step must be a multiple.
/// (Values a few vertices share by the shape's symmetry, off the planes, are not among them:
/// a torus's free coordinates are shared by up to 16 vertices, its planes by hundreds.)
fn axis_planes(mut values: Vec<f64>) -> Option<(f64, f64)> {
    values.par_sort_unstable_by(f64::total_cmp);
    let mut shared: Vec<(usize, f64)> = Vec::new();
    let mut k = 0;
    while k < values.len() {
        let run = values[k..]
            .iter()
            .take_while(|&&x| x == values[k])
            .count()
            .max(1);
        if run >= 3 {
            shared.push((run, values[k]));
        }
        k += run;
    }
    shared.sort_unstable_by(|a, b| b.0.cmp(&a.0).then(a.1.total_cmp(&b.1)));
    let most = shared.first().map_or(0, |&(count, _)| count);
    let mut planes: Vec<f64> = shared
        .iter()
        .take_while(|&&(count, _)| 8 * count >= most)
        .take(PLANES)
        .map(|&(_, x)| x)
        .collect();
    if planes.len() < 3 {
        return None;
    }
    planes.sort_unstable_by(f64::total_cmp);
    let step = planes
        .windows(2)
        .map(|w| w[1] - w[0])
        .fold(f64::INFINITY, f64::min);
    if !(step.is_finite() && step > 0.0) {
        return None;
    }
    let (first, last) = (planes[0], planes[planes.len() - 1]);
    let off = |x: f64, h: f64| {
        let k = (x - first) / h;
        (k - k.round()).abs()
    };
    // The smallest step carries the file's rounding (a few 1e-5 of it with six decimals);
    // over the planes' span it is known to within their count, and then, fitted to every
    // shared value on those planes weighted by how many vertices share it (values shared by
    // symmetry, off the planes, are few and light), to within the grid's size.
    if !planes.iter().all(|&x| off(x, step) < 0.01) {
        return None;
    }
    let h = (last - first) / ((last - first) / step).round();
    let [mut sw, mut sk, mut skk, mut sx, mut skx] = [0.0; 5];
    // Within a tenth of the test's distance: values shared by symmetry, off the planes, that
    // the test's distance lets in would pull the fit.
    for &(count, x) in shared.iter().filter(|&&(_, x)| off(x, h) < 0.1 * ON_GRID) {
        let (w, k) = (count as f64, ((x - first) / h).round());
        sw += w;
        sk += w * k;
        skk += w * k * k;
        sx += w * x;
        skx += w * k * x;
    }
    let det = sw * skk - sk * sk;
    if det <= 0.0 {
        return Some((h, first));
    }
    let spacing = (sw * skx - sk * sx) / det;
    let origin = (sx - spacing * sk) / sw;
    (spacing > 0.0).then_some((spacing, origin))
}

/// How many of the most shared coordinate values along an axis are taken for grid planes.
const PLANES: usize = 16;

#[cfg(test)]
mod tests {
    use super::*;

    /// A sphere of radius 1 as marching cubes leaves it on a grid of spacing `h`: a vertex on
    /// each grid edge the surface crosses, where the linear interpolation of |p|² − 1 along the
    /// edge is zero, and in each cell a fan over the cell's vertices in their order around
    /// their centre (not marching cubes' own triangles: the test reads the vertices and that
    /// every edge stays within a cell).
    fn marching_sphere(h: [f64; 3], corner: Vec3) -> TriMesh {
        let f = |p: Vec3| p.norm_squared() - 1.0;
        let n = (1.3 / h.iter().fold(f64::INFINITY, |m, &x| m.min(x))).ceil() as i64;
        let node = |i: i64, j: i64, k: i64| {
            corner + Vec3::new(i as f64 * h[0], j as f64 * h[1], k as f64 * h[2])
        };
        let mut index: HashMap<[i64; 4], u32> = HashMap::new();
        let mut positions: Vec<[f64; 3]> = Vec::new();
        let mut cells = Vec::new();
        // The vertex on the edge from node c along `axis`, if the surface crosses it.
        let mut crossing = |c: [i64; 3], axis: usize| -> Option<u32> {
            let p = node(c[0], c[1], c[2]);
            let mut q = p;
            q[axis] += h[axis];
            let (a, b) = (f(p), f(q));
            if (a < 0.0) == (b < 0.0) {
                return None;
            }
            let key = [c[0], c[1], c[2], axis as i64];
            Some(*index.entry(key).or_insert_with(|| {
                let v = p + (q - p) * (a / (a - b));
                positions.push([v.x, v.y, v.z]);
                positions.len() as u32 - 1
            }))
        };
        for i in -n..n {
            for j in -n..n {
                for k in -n..n {
                    let mut cell = Vec::new();
                    for axis in 0..3 {
                        for (u, w) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                            let mut c = [i, j, k];
                            c[(axis + 1) % 3] += u;
                            c[(axis + 2) % 3] += w;
                            cell.extend(crossing(c, axis));
                        }
                    }
                    if cell.len() >= 3 {
                        cells.push(cell);
                    }
                }
            }
        }
        let at = |v: u32| Vec3::from(positions[v as usize]);
        let mut faces = Vec::new();
        for mut cell in cells {
            let centre = cell.iter().map(|&v| at(v)).sum::<Vec3>() / cell.len() as f64;
            let (x, y, _) = crate::mesh::tangent_frame(centre.normalize());
            let angle = |v: u32| (at(v) - centre).dot(&y).atan2((at(v) - centre).dot(&x));
            cell.sort_by(|&a, &b| angle(a).total_cmp(&angle(b)));
            for t in 1..cell.len() - 1 {
                faces.push([cell[0], cell[t], cell[t + 1]]);
            }
        }
        TriMesh::from_arrays(positions, faces).unwrap()
    }

    #[test]
    fn marching_cubes_vertices_are_found_on_their_grid() {
        let mesh = marching_sphere([0.1; 3], Vec3::zeros());
        let lattice = find_lattice(&mesh).expect("the grid");
        for a in 0..3 {
            assert!((lattice.spacing[a] - 0.1).abs() < 1e-9, "{lattice:?}");
            let k = lattice.origin[a] / 0.1;
            assert!((k - k.round()).abs() < 1e-6, "{lattice:?}");
            assert!(lattice.free_share[a] > 0.2, "{lattice:?}");
        }
        // Another spacing per axis, the grid's corner off the origin.
        let corner = Vec3::new(0.013, -0.027, 0.041);
        let mesh = marching_sphere([0.08, 0.1, 0.12], corner);
        let lattice = find_lattice(&mesh).expect("the grid");
        for (a, h) in [0.08, 0.1, 0.12].into_iter().enumerate() {
            assert!((lattice.spacing[a] - h).abs() < 1e-9, "{lattice:?}");
            let k = (lattice.origin[a] - corner[a]) / h;
            assert!((k - k.round()).abs() < 1e-6, "{lattice:?}");
        }
    }

    #[test]
    fn other_meshes_have_no_lattice() {
        // A sphere, a grid height field (x and y on a lattice, z free everywhere) and the same
        // marching-cubes sphere moved onto the surface (its coordinates off the grid).
        assert!(find_lattice(&crate::shapes::icosphere(1.0, 4)).is_none());
        let field = crate::shapes::height_field(|x, y| x * x - y, [0.0, 1.0], [0.0, 1.0], 40, 40);
        assert!(find_lattice(&field).is_none());
        let raw = marching_sphere([0.1; 3], Vec3::zeros());
        let projected: Vec<Vec3> = raw.positions().iter().map(|p| p.normalize()).collect();
        assert!(find_lattice(&raw.with_positions(projected).unwrap()).is_none());
        // Its vertices joined by edges longer than a cell (as a CAD part's fans would be).
        let positions = raw.positions().iter().map(|p| [p.x, p.y, p.z]).collect();
        let fan = (1..raw.num_vertices() as u32 - 1)
            .map(|v| [0, v, v + 1])
            .collect();
        assert!(find_lattice(&TriMesh::from_arrays(positions, fan).unwrap()).is_none());
    }
}
