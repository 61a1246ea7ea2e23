//! A uniform grid over points for fixed-radius neighbourhood queries.
//!
//! Points are bucketed into cubic cells of a chosen size (compressed rows over the cells,
//! points of a cell contiguous). A query with radius `r <= cell size` visits the 27 cells
//! around the query point. Building is O(n log n) (one sort), a query O(points nearby).
//! The cell count is capped so that a tiny cell size on a huge box cannot exhaust memory:
//! cells then grow, queries stay correct, only slower.

use crate::mesh::Vec3;

/// Points bucketed into a uniform grid.
#[derive(Debug, Clone)]
pub struct PointGrid {
    origin: Vec3,
    cell: f64,
    dims: [usize; 3],
    cell_offsets: Vec<u32>,
    order: Vec<u32>,
    points: Vec<Vec3>,
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
        PointGrid {
            origin: min,
            cell,
            dims,
            cell_offsets,
            order,
            points: points.to_vec(),
        }
    }

    /// The cell size actually used (>= the requested one).
    pub fn cell_size(&self) -> f64 {
        self.cell
    }

    /// Calls `visit(index, squared distance)` for every point within `radius` of `p`.
    /// `radius` may exceed the cell size; more cells are then visited.
    pub fn for_each_within(&self, p: Vec3, radius: f64, mut visit: impl FnMut(u32, f64)) {
        let r2 = radius * radius;
        let reach = (radius / self.cell).ceil() as isize;
        let c = [0, 1, 2].map(|k| ((p[k] - self.origin[k]) / self.cell).floor() as isize);
        let lo = |k: usize| (c[k] - reach).max(0);
        let hi = |k: usize| (c[k] + reach).min(self.dims[k] as isize - 1);
        for z in lo(2)..=hi(2) {
            for y in lo(1)..=hi(1) {
                let row = (z as usize * self.dims[1] + y as usize) * self.dims[0];
                let (x0, x1) = (lo(0), hi(0));
                if x0 > x1 {
                    continue;
                }
                let start = self.cell_offsets[row + x0 as usize] as usize;
                let end = self.cell_offsets[row + x1 as usize + 1] as usize;
                for &i in &self.order[start..end] {
                    let d2 = (self.points[i as usize] - p).norm_squared();
                    if d2 <= r2 {
                        visit(i, d2);
                    }
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

#[cfg(test)]
mod tests {
    use super::*;

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
    fn tiny_cells_on_a_huge_box_stay_bounded() {
        let pts = vec![Vec3::zeros(), Vec3::repeat(1e9)];
        let grid = PointGrid::new(&pts, 1e-9);
        assert!(grid.cell_size() > 1e7);
        let mut n = 0;
        grid.for_each_within(Vec3::zeros(), 1.0, |_, _| n += 1);
        assert_eq!(n, 1);
    }
}
