//! Uniform grids for spatial queries.
//!
//! - [`PointGrid`]: points bucketed into cubic cells of a chosen size (compressed rows over
//!   the cells; the points are stored in cell order, so a query reads them contiguously).
//!   A query with radius `r <= cell size` visits the 27 cells around the query point.
//!   Building is O(n) (a counting sort), a query O(points nearby). The cell count is capped
//!   so that a tiny cell size on a huge box cannot exhaust memory: cells then grow, queries
//!   stay correct, only slower. Per-point data permuted by [`PointGrid::order`] can be read
//!   in the same order ([`PointGrid::for_each_run_near`]).
//! - [`FaceGrid`]: a mesh's triangles, for the exact nearest point on the surface (used to
//!   put feature lines read from files onto a mesh, and to measure how far one surface is
//!   from another). Built in O(F), with the same cap on the cell count.

use crate::mesh::{TriMesh, Vec3, mean_edge_length};

/// Points bucketed into a uniform grid.
#[derive(Debug, Clone)]
pub struct PointGrid {
    origin: Vec3,
    cell: f64,
    dims: [usize; 3],
    cell_offsets: Vec<u32>,
    /// Slot → point index (cell order).
    order: Vec<u32>,
    /// The points in slot order.
    sorted: Vec<Vec3>,
}

impl PointGrid {
    /// Buckets `points` into cells of (at least) `cell_size`.
    pub fn new(points: &[Vec3], cell_size: f64) -> Self {
        let mut min = Vec3::repeat(f64::INFINITY);
        let mut max = Vec3::repeat(f64::NEG_INFINITY);
        for p in points {
            min = min.inf(p);
            max = max.sup(p);
        }
        if points.is_empty() {
            min = Vec3::zeros();
            max = Vec3::zeros();
        }
        let extent = max - min;
        let mut cell = if cell_size.is_finite() && cell_size > 0.0 {
            cell_size
        } else {
            extent.max().max(1.0)
        };
        // At most ~4 cells per point (and at least one cell).
        let budget = (4 * points.len()).max(1) as f64;
        loop {
            let cells: f64 = (0..3).map(|k| (extent[k] / cell).floor() + 1.0).product();
            if cells <= budget {
                break;
            }
            cell *= (cells / budget).cbrt().max(1.01);
        }
        let dims = [0, 1, 2].map(|k| (extent[k] / cell) as usize + 1);
        let cell_of = |p: &Vec3| -> usize {
            let c = [0, 1, 2].map(|k| (((p[k] - min[k]) / cell) as usize).min(dims[k] - 1));
            (c[2] * dims[1] + c[1]) * dims[0] + c[0]
        };
        let total = dims[0] * dims[1] * dims[2];
        let mut cell_offsets = vec![0u32; total + 1];
        let keys: Vec<usize> = points.iter().map(cell_of).collect();
        for &k in &keys {
            cell_offsets[k + 1] += 1;
        }
        for i in 0..total {
            cell_offsets[i + 1] += cell_offsets[i];
        }
        let mut cursor = cell_offsets.clone();
        let mut order = vec![0u32; points.len()];
        for (i, &k) in keys.iter().enumerate() {
            order[cursor[k] as usize] = i as u32;
            cursor[k] += 1;
        }
        let sorted = order.iter().map(|&i| points[i as usize]).collect();
        PointGrid {
            origin: min,
            cell,
            dims,
            cell_offsets,
            order,
            sorted,
        }
    }

    /// The point indices in cell order: slot `j` holds point `order()[j]`.
    pub fn order(&self) -> &[u32] {
        &self.order
    }

    /// The cell size actually used (>= the requested one).
    pub fn cell_size(&self) -> f64 {
        self.cell
    }

    /// The slots of each layer of cells along z (cells are stored z-major): layer `k` holds
    /// slots `offsets[k]..offsets[k + 1]`, so there is one entry more than layers. A point
    /// with `z` in layer `k` has `origin.z + k · cell_size() <= z` (up to rounding) and, below
    /// the top layer, `z < origin.z + (k + 1) · cell_size()`.
    pub fn layer_offsets(&self) -> Vec<usize> {
        let layer = self.dims[0] * self.dims[1];
        (0..=self.dims[2])
            .map(|k| self.cell_offsets[k * layer] as usize)
            .collect()
    }

    /// Calls `visit(index, squared distance)` for every point within `radius` of `p`.
    /// `radius` may exceed the cell size; more cells are then visited.
    pub fn for_each_within(&self, p: Vec3, radius: f64, mut visit: impl FnMut(u32, f64)) {
        let r2 = radius * radius;
        self.for_each_run_near(p, radius, |run| {
            for (slot, q) in run.clone().zip(&self.sorted[run]) {
                let d2 = (q - p).norm_squared();
                if d2 <= r2 {
                    visit(self.order[slot], d2);
                }
            }
        });
    }

    /// Calls `visit(slots)` with runs of consecutive slots (positions in
    /// [`PointGrid::order`]) that together hold every point within `radius` of `p`, and
    /// other points of the same cells: the caller tests the distances. Data stored in slot
    /// order is then read contiguously.
    pub fn for_each_run_near(
        &self,
        p: Vec3,
        radius: f64,
        visit: impl FnMut(std::ops::Range<usize>),
    ) {
        self.for_each_run_near_after(p, radius, 0, visit);
    }

    /// [`PointGrid::for_each_run_near`] limited to the slots from `first` on: the runs
    /// start at `first` or later (layers and rows of cells that end before it are not
    /// visited at all), so a caller that handles each pair of points once, from its
    /// earlier slot, skips the earlier half of the neighbourhood cheaply.
    pub fn for_each_run_near_after(
        &self,
        p: Vec3,
        radius: f64,
        first: usize,
        mut visit: impl FnMut(std::ops::Range<usize>),
    ) {
        // Cell coordinates of p (unclamped: p may lie outside the grid).
        let q = p - self.origin;
        // floor(x / cell) for x >= 0, and -1 ("before cell 0") for x < 0: all the clamped
        // ranges below need (and cheaper than `f64::floor`, a library call on baseline x86-64).
        let cell_of = |x: f64| {
            let t = x / self.cell;
            if t < 0.0 { -1 } else { t as isize }
        };
        let range = |k: usize, half: f64| {
            (
                cell_of(q[k] - half).max(0),
                cell_of(q[k] + half).min(self.dims[k] as isize - 1),
            )
        };
        // Distance from coordinate x to the slab of cells number i along one axis.
        let gap = |x: f64, i: isize| {
            let (a, b) = (i as f64 * self.cell, (i + 1) as f64 * self.cell);
            (a - x).max(x - b).max(0.0)
        };
        let r2 = radius * radius;
        let (z0, z1) = range(2, radius);
        let (y0, y1) = range(1, radius);
        let row_len = self.dims[0];
        let layer_len = self.dims[1] * row_len;
        for z in z0..=z1 {
            if (self.cell_offsets[(z as usize + 1) * layer_len] as usize) <= first {
                continue;
            }
            let dz = gap(q.z, z);
            for y in y0..=y1 {
                let row = (z as usize * self.dims[1] + y as usize) * row_len;
                if (self.cell_offsets[row + row_len] as usize) <= first {
                    continue;
                }
                // The ball meets this row of cells in a chord of half-length hx.
                let dy = gap(q.y, y);
                let h2 = r2 - dy * dy - dz * dz;
                if h2 < 0.0 {
                    continue;
                }
                let (x0, x1) = range(0, h2.sqrt());
                if x0 > x1 {
                    continue;
                }
                let start = (self.cell_offsets[row + x0 as usize] as usize).max(first);
                let end = self.cell_offsets[row + x1 as usize + 1] as usize;
                if start < end {
                    visit(start..end);
                }
            }
        }
    }

    /// Index of the point nearest to `p` within `radius`, if any.
    pub fn nearest_within(&self, p: Vec3, radius: f64) -> Option<u32> {
        let mut best: Option<(u32, f64)> = None;
        self.for_each_within(p, radius, |i, d2| {
            if best.is_none_or(|(_, b)| d2 < b) {
                best = Some((i, d2));
            }
        });
        best.map(|(i, _)| i)
    }
}

/// The point of segment `p q` nearest to `x`.
pub fn closest_point_on_segment(x: Vec3, p: Vec3, q: Vec3) -> Vec3 {
    p + (q - p) * segment_parameter(x, p, q)
}

/// The parameter `t` in [0, 1] of the point `p + t (q − p)` of segment `p q` nearest to `x`
/// (0 for a segment of zero length).
pub fn segment_parameter(x: Vec3, p: Vec3, q: Vec3) -> f64 {
    let pq = q - p;
    let len2 = pq.norm_squared();
    if len2 <= 0.0 {
        return 0.0;
    }
    ((x - p).dot(&pq) / len2).clamp(0.0, 1.0)
}

/// The point of triangle `[a, b, c]` (a closed set) nearest to `x`.
///
/// When the projection of `x` on the triangle's plane falls inside, that is the answer;
/// otherwise the nearest point lies on the boundary, on one of the three edges. A triangle of
/// (numerically) zero area is treated as its three edges.
pub fn closest_point_on_triangle(x: Vec3, [a, b, c]: [Vec3; 3]) -> Vec3 {
    let (ab, ac, ax) = (b - a, c - a, x - a);
    let (d11, d12, d22) = (ab.dot(&ab), ab.dot(&ac), ac.dot(&ac));
    let det = d11 * d22 - d12 * d12;
    if det > 1e-14 * d11 * d22 {
        // Barycentric coordinates (1 - s - t, s, t) of the projection.
        let (r1, r2) = (ax.dot(&ab), ax.dot(&ac));
        let s = (d22 * r1 - d12 * r2) / det;
        let t = (d11 * r2 - d12 * r1) / det;
        if s >= 0.0 && t >= 0.0 && s + t <= 1.0 {
            return a + ab * s + ac * t;
        }
    }
    [(a, b), (b, c), (c, a)]
        .iter()
        .map(|&(p, q)| closest_point_on_segment(x, p, q))
        .min_by(|p, q| (x - p).norm_squared().total_cmp(&(x - q).norm_squared()))
        .unwrap_or(a)
}

/// Result of a nearest-triangle query.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClosestPoint {
    /// The triangle.
    pub face: u32,
    /// The nearest point on it.
    pub point: Vec3,
    /// Distance from the query point.
    pub distance: f64,
}

/// A uniform grid of a mesh's triangles for nearest-triangle queries.
///
/// Each triangle is listed in every cell its bounding box overlaps; cells are about one mean
/// edge length wide (wider when that would make more than about four cells per triangle).
/// A query visits rings of cells around the point, skipping cells farther than the best
/// triangle found so far, until no unvisited cell can be nearer, so the answer is exact.
#[derive(Debug, Clone)]
pub struct FaceGrid<'a> {
    mesh: &'a TriMesh,
    origin: Vec3,
    cell: f64,
    dims: [usize; 3],
    offsets: Vec<u32>,
    faces: Vec<u32>,
}

impl<'a> FaceGrid<'a> {
    /// Builds the grid of `mesh`'s triangles.
    pub fn new(mesh: &'a TriMesh) -> Self {
        let bbox = mesh.bounding_box();
        let origin = Vec3::from(bbox.min);
        let extent = Vec3::from(bbox.max) - origin;
        let nf = mesh.num_faces().max(1);
        let mut cell = mean_edge_length(mesh);
        let largest = extent.max();
        if cell.is_nan() || cell <= 0.0 {
            cell = if largest > 0.0 { largest } else { 1.0 };
        }
        let dims_for = |cell: f64| extent.map(|e| (e / cell).floor() as usize + 1);
        let mut dims = dims_for(cell);
        // Cap the cell count near 4 per triangle so memory stays linear in the mesh size.
        while (dims.x as f64) * (dims.y as f64) * (dims.z as f64) > 4.0 * nf as f64 + 64.0 {
            cell *= 1.5;
            dims = dims_for(cell);
        }
        let dims = [dims.x, dims.y, dims.z];
        let mut grid = FaceGrid {
            mesh,
            origin,
            cell,
            dims,
            offsets: Vec::new(),
            faces: Vec::new(),
        };
        let cells = dims[0] * dims[1] * dims[2];
        let mut counts = vec![0u32; cells + 1];
        grid.for_each_cell_of_faces(|c, _| counts[c + 1] += 1);
        for i in 0..cells {
            counts[i + 1] += counts[i];
        }
        let mut cursor = counts.clone();
        let mut list = vec![0u32; counts[cells] as usize];
        grid.for_each_cell_of_faces(|c, f| {
            list[cursor[c] as usize] = f;
            cursor[c] += 1;
        });
        grid.offsets = counts;
        grid.faces = list;
        grid
    }

    fn for_each_cell_of_faces(&self, mut visit: impl FnMut(usize, u32)) {
        for f in 0..self.mesh.num_faces() {
            let [a, b, c] = self.mesh.triangle(f);
            let lo = self.cell_of(a.inf(&b).inf(&c));
            let hi = self.cell_of(a.sup(&b).sup(&c));
            for z in lo[2]..=hi[2] {
                for y in lo[1]..=hi[1] {
                    for x in lo[0]..=hi[0] {
                        visit(self.index([x, y, z]), f as u32);
                    }
                }
            }
        }
    }

    /// The cell containing `p`, clamped to the grid.
    fn cell_of(&self, p: Vec3) -> [usize; 3] {
        let mut c = [0usize; 3];
        for k in 0..3 {
            let i = ((p[k] - self.origin[k]) / self.cell).floor();
            c[k] = if i.is_finite() && i > 0.0 {
                (i as usize).min(self.dims[k] - 1)
            } else {
                0
            };
        }
        c
    }

    fn index(&self, [x, y, z]: [usize; 3]) -> usize {
        (z * self.dims[1] + y) * self.dims[0] + x
    }

    /// The triangle nearest to `p` and the nearest point on it; `None` for a mesh without
    /// triangles or a non-finite `p`.
    pub fn closest_point(&self, p: Vec3) -> Option<ClosestPoint> {
        if self.mesh.num_faces() == 0 || !p.iter().all(|c| c.is_finite()) {
            return None;
        }
        let center = self.cell_of(p);
        let mut best: Option<ClosestPoint> = None;
        let max_ring = self.dims.iter().copied().max().unwrap_or(1);
        for ring in 0..=max_ring {
            // Cells at Chebyshev distance `ring` from the centre cell are at least
            // `ring - 1` cells from `p`, whether `p` is inside the grid or was clamped onto it.
            if let Some(b) = best
                && b.distance <= ring.saturating_sub(1) as f64 * self.cell
            {
                break;
            }
            self.visit_ring(center, ring, |cell| {
                // Every point of a triangle listed here that lies in this cell is at least
                // this far; its parts in other cells are checked with those cells.
                let bound = best.map_or(f64::INFINITY, |b| b.distance);
                if self.cell_distance(cell, p) > bound {
                    return;
                }
                let i = self.index(cell);
                for &f in &self.faces[self.offsets[i] as usize..self.offsets[i + 1] as usize] {
                    let q = closest_point_on_triangle(p, self.mesh.triangle(f as usize));
                    let d = (p - q).norm();
                    if best.is_none_or(|b| d < b.distance) {
                        best = Some(ClosestPoint {
                            face: f,
                            point: q,
                            distance: d,
                        });
                    }
                }
            });
        }
        best
    }

    /// Distance from `p` to the box of `cell`.
    fn cell_distance(&self, cell: [usize; 3], p: Vec3) -> f64 {
        let mut d2 = 0.0;
        for k in 0..3 {
            let lo = self.origin[k] + cell[k] as f64 * self.cell;
            let hi = lo + self.cell;
            let gap = (lo - p[k]).max(p[k] - hi).max(0.0);
            d2 += gap * gap;
        }
        d2.sqrt()
    }

    /// Calls `visit` for each cell at Chebyshev distance `ring` from `center`.
    fn visit_ring(&self, center: [usize; 3], ring: usize, mut visit: impl FnMut([usize; 3])) {
        let r = ring as isize;
        let range = |k: usize| {
            let c = center[k] as isize;
            ((c - r).max(0), (c + r).min(self.dims[k] as isize - 1))
        };
        let (x0, x1) = range(0);
        let (y0, y1) = range(1);
        let (z0, z1) = range(2);
        for z in z0..=z1 {
            for y in y0..=y1 {
                for x in x0..=x1 {
                    let on_ring = (x - center[0] as isize).abs() == r
                        || (y - center[1] as isize).abs() == r
                        || (z - center[2] as isize).abs() == r;
                    if on_ring {
                        visit([x as usize, y as usize, z as usize]);
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes;

    #[test]
    fn finds_exactly_the_points_within_the_radius() {
        let pts: Vec<Vec3> = (0..500)
            .map(|i| {
                let f = i as f64;
                Vec3::new(
                    (f * 0.37).sin() * 3.0,
                    (f * 0.11).cos() * 2.0,
                    (f * 0.05).sin(),
                )
            })
            .collect();
        let grid = PointGrid::new(&pts, 0.4);
        for q in [
            Vec3::zeros(),
            Vec3::new(2.0, -1.0, 0.5),
            Vec3::new(9.0, 9.0, 9.0),
        ] {
            for r in [0.3, 0.4, 1.1] {
                let mut found = Vec::new();
                grid.for_each_within(q, r, |i, _| found.push(i));
                found.sort_unstable();
                let brute: Vec<u32> = (0..pts.len() as u32)
                    .filter(|&i| (pts[i as usize] - q).norm() <= r)
                    .collect();
                assert_eq!(found, brute, "q {q:?} r {r}");
            }
        }
        assert_eq!(
            grid.nearest_within(pts[7] + Vec3::repeat(1e-9), 0.1),
            Some(7)
        );
    }

    #[test]
    fn runs_after_a_slot_hold_exactly_the_later_points_nearby() {
        let pts: Vec<Vec3> = (0..800)
            .map(|i| {
                let f = i as f64;
                Vec3::new(
                    (f * 0.37).sin() * 3.0,
                    (f * 0.11).cos() * 2.0,
                    (f * 0.05).sin() * 4.0,
                )
            })
            .collect();
        let grid = PointGrid::new(&pts, 0.5);
        let order = grid.order();
        // The layers partition the slots, and each point lies in its layer's z range.
        let layers = grid.layer_offsets();
        assert_eq!(layers[0], 0);
        assert_eq!(*layers.last().unwrap(), pts.len());
        let z_min = pts.iter().map(|p| p.z).fold(f64::INFINITY, f64::min);
        for (k, w) in layers.windows(2).enumerate() {
            assert!(w[0] <= w[1]);
            for &i in &order[w[0]..w[1]] {
                let layer = (pts[i as usize].z - z_min) / grid.cell_size();
                assert!(layer >= k as f64 - 1e-9 && layer < (k + 1) as f64 + 1e-9);
            }
        }
        assert!(layers.len() > 10);
        for slot in [0, 1, 57, 400, 799] {
            let q = pts[order[slot] as usize];
            for r in [0.5, 1.0] {
                let mut found = Vec::new();
                let mut last_end = 0;
                grid.for_each_run_near_after(q, r, slot, |run| {
                    assert!(run.start >= slot.max(last_end) && run.start < run.end);
                    last_end = run.end;
                    found.extend(run.filter(|&t| (pts[order[t] as usize] - q).norm() <= r));
                });
                let brute: Vec<usize> = (slot..pts.len())
                    .filter(|&t| (pts[order[t] as usize] - q).norm() <= r)
                    .collect();
                assert_eq!(found, brute, "slot {slot} r {r}");
            }
        }
    }

    #[test]
    fn tiny_cells_on_a_huge_box_stay_bounded() {
        let pts = vec![Vec3::zeros(), Vec3::repeat(1e9)];
        let grid = PointGrid::new(&pts, 1e-9);
        assert!(grid.cell_size() > 1e7);
        let mut n = 0;
        grid.for_each_within(Vec3::zeros(), 1.0, |_, _| n += 1);
        assert_eq!(n, 1);
    }

    #[test]
    fn grid_finds_the_nearest_triangle() {
        let mesh = shapes::torus(2.0, 0.5, 24, 12);
        let grid = FaceGrid::new(&mesh);
        let mut state = 12345u64;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((state >> 11) as f64 / (1u64 << 53) as f64) * 8.0 - 4.0
        };
        for _ in 0..300 {
            let p = Vec3::new(next(), next(), next() * 0.5);
            let hit = grid.closest_point(p).unwrap();
            let brute = (0..mesh.num_faces())
                .map(|f| (p - closest_point_on_triangle(p, mesh.triangle(f))).norm())
                .fold(f64::INFINITY, f64::min);
            assert!((hit.distance - brute).abs() < 1e-12, "{p}");
        }
    }

    #[test]
    fn closest_point_on_triangle_regions() {
        let t = [Vec3::zeros(), Vec3::x(), Vec3::y()];
        let c = |x: f64, y: f64, z: f64| closest_point_on_triangle(Vec3::new(x, y, z), t);
        assert_eq!(c(0.2, 0.2, 3.0), Vec3::new(0.2, 0.2, 0.0));
        assert_eq!(c(-1.0, -1.0, 1.0), Vec3::zeros());
        assert_eq!(c(2.0, -1.0, 0.0), Vec3::x());
        assert_eq!(c(0.5, -2.0, 0.0), Vec3::new(0.5, 0.0, 0.0));
        assert!((c(1.0, 1.0, 0.0) - Vec3::new(0.5, 0.5, 0.0)).norm() < 1e-15);
    }
}
