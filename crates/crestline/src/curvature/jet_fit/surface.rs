//! Sampling a fitting disc on the mesh's triangles instead of at its vertices, for the discs
//! that long thin triangles cross.
//!
//! **Why.** A CAD exporter tessellates a cylinder as strips of triangles as long as the
//! cylinder, and a planar or ruled face as a fan: within a fitting radius of a vertex on such
//! a strip, the only vertices are a row along one rim. Their heights say nothing about the
//! surface across the row, the fit is singular in that direction, and its curvature and
//! extremalities are arbitrary (a cylinder's k_min 0.15 instead of 0, |e| ~ 1e5). The surface
//! the mesh stands for is its triangles, so such a disc is sampled where the surface is: the
//! weighted sum over samples stays a quadrature of `∫ K f dA` (see the parent module), now
//! with the triangles' area elements instead of the vertices' barycentric areas.
//!
//! **When.** Only where vertex sampling fails: the disc's vertices, with their weights and
//! projected on the tangent plane, lie along a strip (the smaller eigenvalue of their weighted
//! second moment is below 2% of the larger), tested once the disc has grown to its minimal
//! number of vertices: a row of vertices along the rim of a CAD strip or fan; or the fit of
//! the vertices is ill-posed (a pivot of its normal equations below 1e-8 of its diagonal
//! entry, `ILL_POSED`): vertices on two or three rows, too few for the polynomial across
//! them, as where triangles several times longer than wide meet a boundary or run along a
//! bend. On the public quality cases and the shared scans this never happens. A disc of a
//! mesh that samples the surface in both directions never takes this path: its results are
//! those of vertex sampling. The fit's residual does not count towards the noise level
//! there: pieces of flat triangles are off a curved surface by the tessellation's chord
//! error, which is not noise (the probe of the noise level does not fit such discs at all).
//!
//! **How.** The triangles are found breadth-first from the centre's triangles across edges
//! that are not creases, keeping those that come within the radius of the centre. Each is
//! cut by a grid of square cells at most r/8 wide ([`PIECES_PER_RADIUS`]), laid along its
//! longest side and fitted to its length and height; each cell's part of the triangle is one
//! sample at its centroid, with its area as weight and the linear interpolation of the
//! corners' simulated noise there. Only the cells that can reach the disc are cut
//! ([`cut_triangle`]). A sliver of a fan, narrower than a cell, is cut across only: a disc
//! takes about 16 pieces of it whatever its length, where the regular subdivision into m²
//! congruent triangles (m = ⌈4 L / r⌉, used before) left 16 L / r pieces of it in the disc,
//! and as many slivers cross a disc on a fan as its rim has segments near it: the
//! triangles' number squared in all (a capped cylinder of 2048 segments took 9 s). A sliver's
//! pieces are integrated in closed form ([`slab_piece`]) rather than clipped. A disc on a fan
//! still takes about 16 pieces of every sliver that crosses it, so the time there grows
//! faster than the triangles (`bench/quality/slivers.py`: a capped cylinder of 8192 segments,
//! 32,768 triangles, 6.8 s in all; BENCHMARKS.md, *Fans and strips of slivers*).

#[cfg(doc)]
use super::JetFitOptions;
use super::{Context, Sample, Scratch, kernel, next_stamp, simulated_noise};
use crate::curvature::{symmetric_eigen_2x2, tangent_frame};
use crate::mesh::Vec3;
use crate::spatial::closest_point_on_triangle;

/// Ratio of the smaller to the larger eigenvalue of the disc's weighted second moment (on the
/// tangent plane) below
/// which its vertices are taken to lie along a strip. A full disc has 1, a half disc at a
/// boundary 0.3, a quarter disc at a corner 0.2; a row of vertices along the rim of a CAD
/// strip 0.0001, a cylinder cut into triangles 7 times longer than wide 0.005.
const STRIP_RATIO: f64 = 0.02;

/// Cells per radius: the cells that cut a triangle are at most `r / PIECES_PER_RADIUS` wide.
const PIECES_PER_RADIUS: f64 = 8.0;

/// Whether the weighted `points` (tangent-plane coordinates, weight) lie along a strip: the
/// smaller eigenvalue of their weighted second moment is below [`STRIP_RATIO`] times the
/// larger. Fewer than three points are not: such a disc grows (see
/// [`JetFitOptions::min_points`]).
fn is_strip(points: impl Iterator<Item = ([f64; 2], f64)>) -> bool {
    // Weighted sums of 1, x, y, x², xy, y² in one pass.
    let mut m = [0.0f64; 6];
    let mut count = 0usize;
    for ([x, y], w) in points {
        for (sum, term) in m.iter_mut().zip([1.0, x, y, x * x, x * y, y * y]) {
            *sum += w * term;
        }
        count += 1;
    }
    let total = m[0];
    if count < 3 || total <= 0.0 {
        return false;
    }
    let (mx, my) = (m[1] / total, m[2] / total);
    let (a, b, c) = (
        m[3] / total - mx * mx,
        m[4] / total - mx * my,
        m[5] / total - my * my,
    );
    let (large, small, _) = symmetric_eigen_2x2(a, b, c);
    small < STRIP_RATIO * large
}

impl Context<'_> {
    /// Whether the disc of vertex `v` in `s` (radius `r`) is to be sampled on its triangles
    /// (module docs, *When*).
    pub(super) fn needs_triangle_samples(&self, v: u32, r: f64, s: &Scratch) -> bool {
        let p = self.mesh.position(v);
        // The vertices as the fit sees them: on the tangent plane (a row along a curved rim
        // is a strip there, though not in space).
        let normal = match self.split {
            Some(split) if split.vertices[v as usize] => s.side_normal,
            _ => self.normals[v as usize],
        };
        let (u, w, _) = tangent_frame(normal);
        is_strip(s.disc.iter().map(|&q| {
            let d = self.mesh.position(q) - p;
            let weight = self.areas[q as usize] * kernel(d.norm_squared() / (r * r));
            ([d.dot(&u), d.dot(&w)], weight)
        }))
    }

    /// Samples the disc of radius `radius` on the triangles ([`Self::sample_triangles`]),
    /// grown by half, up to the radius `grown` its vertex disc grew to, while the area of its
    /// samples is below that of [`JetFitOptions::min_points`] vertices of a regular
    /// triangulation at the mesh's sample spacing h (`√3/2 h²` each). A disc at a boundary
    /// grows as its vertex disc did; a disc on a fan, whose vertices are all on its rim, no
    /// longer grows for want of vertices where its triangles cover enough (a rim vertex of
    /// a capped cylinder grew to its largest radius, over the whole cap). Returns the
    /// samples' kernel-weighted area normal and the radius sampled.
    pub(super) fn sample_triangle_disc(
        &self,
        v: u32,
        radius: f64,
        grown: f64,
        s: &mut Scratch,
    ) -> (Vec3, f64) {
        let wanted =
            self.options.min_points as f64 * 3f64.sqrt() / 2.0 * self.spacing * self.spacing;
        let mut r = radius;
        loop {
            let normal = self.sample_triangles(v, r, s);
            let area: f64 = s.points.iter().map(|q| q.area).sum();
            // (The vertex disc's radii are `radius` times powers of 1.5, as these.)
            if area >= wanted || r * 1.25 > grown || r.is_nan() {
                return (normal, r);
            }
            r = (r * 1.5).min(grown);
        }
    }

    /// Samples the surface within `r` of vertex `v` on its triangles into `s.points`, and
    /// returns the samples' kernel-weighted area normal.
    fn sample_triangles(&self, v: u32, r: f64, s: &mut Scratch) -> Vec3 {
        let topo = self.mesh.topology();
        let p = self.mesh.position(v);
        let r2 = r * r;
        let stamp = next_stamp(&mut s.face_marks, &mut s.face_stamp, self.mesh.num_faces());
        s.faces.clear();
        match self.split {
            Some(split) if split.vertices[v as usize] => {
                s.faces.extend_from_slice(split.widest_side(v))
            }
            _ => s.faces.extend_from_slice(topo.vertex_faces(v)),
        }
        for &f in &s.faces {
            s.face_marks[f as usize] = stamp;
        }
        let mut head = 0;
        while head < s.faces.len() {
            let f = s.faces[head];
            head += 1;
            for e in topo.face_edges(f) {
                if self.split.is_some_and(|split| split.edges[e as usize]) {
                    continue;
                }
                for &g in topo.edge_faces(e) {
                    if s.face_marks[g as usize] == stamp {
                        continue;
                    }
                    s.face_marks[g as usize] = stamp;
                    let corners = self.mesh.triangle(g as usize);
                    if (closest_point_on_triangle(p, corners) - p).norm_squared() < r2 {
                        s.faces.push(g);
                    }
                }
            }
        }
        s.points.clear();
        let mut normal = Vec3::zeros();
        for k in 0..s.faces.len() {
            let f = s.faces[k] as usize;
            let noise = self.mesh.faces()[f].map(|q| simulated_noise(self.keys[q as usize]));
            normal += cut_triangle(self.mesh.triangle(f), noise, p, r, &mut s.points);
        }
        normal
    }
}

/// Pushes onto `points` the pieces of the triangle `corners` (simulated noise `noise` at its
/// corners) whose centroids lie within `r` of `p` (module docs, *How*), and returns their
/// kernel-weighted area normal.
///
/// In the triangle's plane, with its longest side from (0, 0) to (L, 0) and its third corner
/// at (cx, cy), cy > 0 (0 ≤ cx ≤ L: the angles at the longest side are acute), the cells are
/// `[i hx, (i + 1) hx] × [j hy, (j + 1) hy]`, hx = L / ⌈L / h⌉ and hy = cy / ⌈cy / h⌉ for
/// h = r / 8; a cell's piece is the cell clipped by the two other sides. Only the rows and
/// columns within reach of the disc are visited.
fn cut_triangle(
    corners: [Vec3; 3],
    noise: [f64; 3],
    p: Vec3,
    r: f64,
    points: &mut Vec<SurfacePoint>,
) -> Vec3 {
    let sides = [
        corners[1] - corners[0],
        corners[2] - corners[1],
        corners[0] - corners[2],
    ];
    let lengths = sides.map(|side| side.norm());
    let k = (0..3).fold(0, |k, i| if lengths[i] > lengths[k] { i } else { k });
    // The longest side from a to b.
    let (a, b, c) = (corners[k], corners[(k + 1) % 3], corners[(k + 2) % 3]);
    let noise = [noise[k], noise[(k + 1) % 3], noise[(k + 2) % 3]];
    let length = lengths[k];
    let along = (b - a) / length;
    let across = (c - a) - along * (c - a).dot(&along);
    let height = across.norm();
    let area = length * height / 2.0;
    // Pieces without area weigh nothing in a fit (`SurfacePoint::sample`).
    if area.is_nan() || area <= 0.0 || area.is_infinite() {
        return Vec3::zeros();
    }
    let across = across / height;
    let unit = along.cross(&across);
    let (cx, cy) = ((c - a).dot(&along), height);
    // The disc in the plane: centre (px, py), radius `reach`.
    let to_p = p - a;
    let (px, py, pz) = (to_p.dot(&along), to_p.dot(&across), to_p.dot(&unit));
    let reach2 = r * r - pz * pz;
    if reach2.is_nan() || reach2 <= 0.0 {
        return Vec3::zeros();
    }
    let reach = reach2.sqrt();
    let h = r / PIECES_PER_RADIUS;
    let (columns, rows) = ((length / h).ceil().max(1.0), (cy / h).ceil().max(1.0));
    let (hx, hy) = (length / columns, cy / rows);
    // Cells that can hold a point within `reach` of (px, py), from `low` to `high` (not
    // included) of `count`: those overlapping [centre − reach, centre + reach].
    let span = |centre: f64, step: f64, count: f64| {
        let low = ((centre - reach) / step).floor().clamp(0.0, count);
        let high = ((centre + reach) / step).floor().clamp(-1.0, count - 1.0) + 1.0;
        low as usize..high.max(low) as usize
    };
    let mut weight = Vec3::zeros();
    for j in span(py, hy, rows) {
        let (y0, y1) = (j as f64 * hy, (j + 1) as f64 * hy);
        // The triangle between y0 and y1 lies within x from cx y0 / cy to
        // L − (L − cx) y0 / cy.
        let (left, right) = (cx * y0 / cy, length - (length - cx) * y0 / cy);
        let near = span(px, hx, columns);
        let first = near.start.max((left / hx).floor() as usize);
        let last = near.end.min(((right / hx).ceil() as usize).max(1));
        for i in first..last {
            let (x0, x1) = (i as f64 * hx, (i + 1) as f64 * hx);
            // A triangle of one row (a sliver narrower than a cell) in closed form.
            let cut = if rows == 1.0 {
                slab_piece([x0, x1], length, [cx, cy])
            } else {
                clip_cell([x0, x1], [y0, y1], length, [cx, cy])
            };
            let Some((piece, [x, y])) = cut else {
                continue;
            };
            let (dx, dy) = (x - px, y - py);
            let d2 = (dx * dx + dy * dy + pz * pz) / (r * r);
            if d2 >= 1.0 {
                continue;
            }
            weight += unit * (piece * kernel(d2));
            // Barycentric coordinates of (x, y): (x, y) = u (L, 0) + w (cx, cy).
            let w = y / cy;
            let u = (x - w * cx) / length;
            points.push(SurfacePoint {
                position: a + along * x + across * y,
                area: piece,
                noise: (1.0 - u - w) * noise[0] + u * noise[1] + w * noise[2],
            });
        }
    }
    weight
}

/// The area and centroid of the part of the triangle (0, 0), (L, 0), (cx, cy) between x = x0
/// and x = x1 (`None` if it has no area; x1 may pass L by rounding): what [`clip_cell`] gives
/// for a cell as high as the triangle, integrated in closed form over the two linear pieces of
/// its upper boundary (the slivers of a CAD fan and strip, narrower than a cell, are all of
/// one row: clipping their cells was most of the time spent on them).
fn slab_piece([x0, x1]: [f64; 2], length: f64, [cx, cy]: [f64; 2]) -> Option<(f64, [f64; 2])> {
    let (mut area, mut mx, mut my) = (0.0, 0.0, 0.0);
    // Over [s, t], where the boundary goes linearly from height h0 to h1: the area under it
    // and its moments about x = 0 and y = 0.
    let mut add = |s: f64, t: f64, [h0, h1]: [f64; 2]| {
        let w = t - s;
        let a = w * (h0 + h1) / 2.0;
        area += a;
        mx += s * a + w * w * (h0 + 2.0 * h1) / 6.0;
        my += w * (h0 * h0 + h0 * h1 + h1 * h1) / 6.0;
    };
    // Left of the third corner the boundary rises, right of it it falls (each part has
    // length only where its side has: cx > 0, cx < L); heights from ratios within [0, 1].
    let (s, t) = (x0, x1.min(cx));
    if t > s {
        add(s, t, [s, t].map(|x| cy * (x / cx)));
    }
    let (s, t) = (x0.max(cx), x1.min(length));
    if t > s {
        add(s, t, [s, t].map(|x| cy * ((length - x) / (length - cx))));
    }
    (area > 0.0).then(|| (area, [mx / area, my / area]))
}

/// The area and centroid of the cell `[x0, x1] × [y0, y1]` (y0 ≥ 0) clipped by the triangle
/// (0, 0), (L, 0), (cx, cy); `None` if nothing of it is left.
fn clip_cell(
    [x0, x1]: [f64; 2],
    [y0, y1]: [f64; 2],
    length: f64,
    [cx, cy]: [f64; 2],
) -> Option<(f64, [f64; 2])> {
    let mut polygon = [[0.0f64; 2]; 8];
    polygon[..4].copy_from_slice(&[[x0, y0], [x1, y0], [x1, y1], [x0, y1]]);
    let mut count = 4;
    // The sides (L, 0) → (cx, cy) and (cx, cy) → (0, 0), counter-clockwise: inside is to
    // their left (the side (0, 0) → (L, 0) is y ≥ 0, which every cell keeps).
    for (start, end) in [([length, 0.0], [cx, cy]), ([cx, cy], [0.0, 0.0])] {
        let side = |q: [f64; 2]| {
            (end[0] - start[0]) * (q[1] - start[1]) - (end[1] - start[1]) * (q[0] - start[0])
        };
        let mut clipped = [[0.0f64; 2]; 8];
        let mut kept = 0;
        for k in 0..count {
            let (q, next) = (polygon[k], polygon[(k + 1) % count]);
            let (sq, sn) = (side(q), side(next));
            if sq >= 0.0 {
                clipped[kept] = q;
                kept += 1;
            }
            if (sq >= 0.0) != (sn >= 0.0) {
                let t = sq / (sq - sn);
                clipped[kept] = [q[0] + t * (next[0] - q[0]), q[1] + t * (next[1] - q[1])];
                kept += 1;
            }
        }
        polygon = clipped;
        count = kept;
        if count < 3 {
            return None;
        }
    }
    // The shoelace formula, about the first corner (for rounding).
    let origin = polygon[0];
    let (mut area2, mut mx, mut my) = (0.0, 0.0, 0.0);
    for k in 1..count - 1 {
        let (q, next) = (polygon[k], polygon[k + 1]);
        let (qx, qy) = (q[0] - origin[0], q[1] - origin[1]);
        let (nx, ny) = (next[0] - origin[0], next[1] - origin[1]);
        let cross = qx * ny - nx * qy;
        area2 += cross;
        mx += cross * (qx + nx);
        my += cross * (qy + ny);
    }
    (area2 > 0.0).then(|| {
        let centroid = [
            origin[0] + mx / (3.0 * area2),
            origin[1] + my / (3.0 * area2),
        ];
        (area2 / 2.0, centroid)
    })
}

/// A point the fit samples: a vertex with its barycentric area, or a piece of a triangle.
#[derive(Debug, Clone, Copy)]
pub(super) struct SurfacePoint {
    pub position: Vec3,
    pub area: f64,
    /// Simulated unit noise of the height there ([`simulated_noise`]).
    pub noise: f64,
}

impl SurfacePoint {
    /// This point relative to the centre `p`, scaled by `1 / r`, with its weight; `None`
    /// where the weight is not positive (outside the disc, or no area).
    #[inline]
    pub(super) fn scaled(&self, p: Vec3, r: f64) -> Option<Scaled> {
        let d = (self.position - p) / r;
        let weight = self.area * kernel(d.norm_squared());
        (weight > 0.0).then(|| Scaled {
            d,
            w: weight,
            xi: self.noise / r,
        })
    }
}

/// A [`SurfacePoint`] relative to the disc's centre, scaled by the inverse radius, with its
/// weight and scaled simulated noise: a [`Sample`] before the frame is chosen.
#[derive(Debug, Clone, Copy)]
pub(super) struct Scaled {
    d: Vec3,
    w: f64,
    xi: f64,
}

impl Scaled {
    /// The sample this point makes in the frame (u, w, n).
    #[inline]
    pub(super) fn sample(&self, [u, w, n]: [Vec3; 3]) -> Sample {
        Sample {
            x: self.d.dot(&u),
            y: self.d.dot(&w),
            z: self.d.dot(&n),
            w: self.w,
            xi: self.xi,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every piece of [`cut_triangle`]'s grid with none skipped (as positions and areas),
    /// those far from the disc included.
    fn every_piece(corners: [Vec3; 3], r: f64) -> Vec<(Vec3, f64)> {
        let lengths = [0, 1, 2].map(|k| (corners[(k + 1) % 3] - corners[k]).norm());
        let k = (0..3).fold(0, |k, i| if lengths[i] > lengths[k] { i } else { k });
        let (a, b, c) = (corners[k], corners[(k + 1) % 3], corners[(k + 2) % 3]);
        let length = lengths[k];
        let along = (b - a) / length;
        let across = (c - a) - along * (c - a).dot(&along);
        let (cx, cy) = ((c - a).dot(&along), across.norm());
        let across = across / cy;
        let h = r / PIECES_PER_RADIUS;
        let (columns, rows) = ((length / h).ceil().max(1.0), (cy / h).ceil().max(1.0));
        let (hx, hy) = (length / columns, cy / rows);
        let mut pieces = Vec::new();
        for j in 0..rows as usize {
            for i in 0..columns as usize {
                let x = [i as f64 * hx, (i + 1) as f64 * hx];
                let y = [j as f64 * hy, (j + 1) as f64 * hy];
                if let Some((area, [x, y])) = clip_cell(x, y, length, [cx, cy]) {
                    pieces.push((a + along * x + across * y, area));
                }
            }
        }
        pieces
    }

    fn random_numbers() -> impl FnMut() -> f64 {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    #[test]
    fn only_the_pieces_near_the_disc_are_visited_and_none_is_missed() {
        let mut uniform = random_numbers();
        for trial in 0..400 {
            let mut numbers = [0.0; 16];
            numbers.iter_mut().for_each(|x| *x = uniform());
            let point = |k: usize, scale: f64| {
                Vec3::new(numbers[k] - 0.5, numbers[k + 1] - 0.5, numbers[k + 2] - 0.5) * scale
            };
            // Well-shaped triangles, slivers of fans (two corners close) and needles, with
            // discs from much smaller than the triangle to larger than it.
            let a = point(0, 2.0);
            let b = a + point(3, 2.0);
            let c = match trial % 3 {
                0 => a + point(6, 2.0),
                1 => b + point(6, 0.01),
                _ => a + (b - a) * numbers[9] + point(6, 1e-4),
            };
            let r = 0.02 + 1.5 * numbers[10];
            let p = a + (b - a) * numbers[11] + (c - a) * (0.5 * numbers[12]) + point(13, r);
            let mut points = Vec::new();
            cut_triangle([a, b, c], [0.0; 3], p, r, &mut points);
            let visited: Vec<(Vec3, f64)> = points.iter().map(|q| (q.position, q.area)).collect();
            let mut all = every_piece([a, b, c], r);
            // The pieces cover the triangle: their areas and first moments add up to its.
            let area = (b - a).cross(&(c - a)).norm() / 2.0;
            let total: f64 = all.iter().map(|(_, area)| area).sum();
            let moment: Vec3 = all.iter().map(|(x, area)| x * *area).sum();
            assert!((total - area).abs() <= 1e-9 * area, "trial {trial}");
            let centroid = (a + b + c) / 3.0;
            let size = (b - a).norm() + (c - a).norm();
            assert!(
                (moment / total - centroid).norm() <= 1e-9 * size,
                "trial {trial}"
            );
            all.retain(|(x, _)| (x - p).norm_squared() < r * r);
            // The same pieces in the same order; those of one row are integrated in closed
            // form rather than clipped (`slab_piece`): equal up to rounding.
            assert_eq!(visited.len(), all.len(), "trial {trial}");
            for ((x, area), (y, expected)) in visited.iter().zip(&all) {
                assert!((x - y).norm() <= 1e-12 * size, "trial {trial}");
                assert!((area - expected).abs() <= 1e-12 * expected, "trial {trial}");
            }
        }
    }

    #[test]
    fn a_slab_of_a_triangle_in_closed_form_is_the_clipped_cell() {
        let mut uniform = random_numbers();
        for trial in 0..1000 {
            let length = 0.01 + 10.0 * uniform();
            // The third corner anywhere above the longest side, at either end too.
            let cx = match trial % 7 {
                0 => 0.0,
                1 => length,
                // A corner all but above an end of the longest side.
                2 => length * 1e-300,
                3 => length * (1.0 - f64::EPSILON),
                _ => length * uniform(),
            };
            let cy = length * (1e-4 + uniform());
            let (mut x0, mut x1) = (length * uniform(), length * uniform());
            if x0 > x1 {
                (x0, x1) = (x1, x0);
            }
            if trial % 5 == 0 {
                (x0, x1) = (0.0, length);
            }
            if trial % 11 == 0 {
                // The last column of `cut_triangle` can end an ulp past the triangle.
                x1 = length * (1.0 + f64::EPSILON);
            }
            let slab = slab_piece([x0, x1], length, [cx, cy]);
            let clipped = clip_cell([x0, x1], [0.0, cy], length, [cx, cy]);
            match (slab, clipped) {
                (Some((a, [x, y])), Some((b, [u, v]))) => {
                    assert!((a - b).abs() <= 1e-12 * b, "trial {trial}: {a} {b}");
                    assert!((x - u).abs() <= 1e-12 * length, "trial {trial}");
                    assert!((y - v).abs() <= 1e-12 * length, "trial {trial}");
                    if x0 == 0.0 && x1 >= length {
                        // The whole triangle: its area and centroid.
                        assert!((a - length * cy / 2.0).abs() <= 1e-12 * a, "trial {trial}");
                        assert!((x - (length + cx) / 3.0).abs() <= 1e-12 * length);
                        assert!((y - cy / 3.0).abs() <= 1e-12 * length);
                    }
                }
                (None, None) => assert!(x1 - x0 <= 1e-12 * length, "trial {trial}"),
                other => panic!("trial {trial}: {other:?}"),
            }
        }
    }

    #[test]
    fn pieces_are_small_and_carry_the_noise_of_their_place() {
        let (a, b, c) = (
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(3.0, 0.2, 0.0),
            Vec3::new(0.5, 2.0, 0.1),
        );
        let noise = [1.0, -2.0, 4.0];
        let (p, r) = (Vec3::new(1.0, 0.7, 0.0), 1.2);
        let mut points = Vec::new();
        let weight = cut_triangle([a, b, c], noise, p, r, &mut points);
        assert!(points.len() > 20);
        let mut expected = Vec3::zeros();
        let n = (b - a).cross(&(c - a));
        let unit = n.normalize();
        for q in &points {
            // Barycentric coordinates of the centroid: the noise is their interpolation.
            let (v0, v1, v2) = (b - a, c - a, q.position - a);
            let (d00, d01, d11) = (v0.dot(&v0), v0.dot(&v1), v1.dot(&v1));
            let (d20, d21) = (v2.dot(&v0), v2.dot(&v1));
            let det = d00 * d11 - d01 * d01;
            let u = (d11 * d20 - d01 * d21) / det;
            let w = (d00 * d21 - d01 * d20) / det;
            let interpolated = (1.0 - u - w) * noise[0] + u * noise[1] + w * noise[2];
            assert!((q.noise - interpolated).abs() < 1e-12);
            let d2 = (q.position - p).norm_squared() / (r * r);
            assert!(d2 < 1.0);
            expected += unit * (q.area * kernel(d2));
        }
        assert!((weight - expected).norm() < 1e-12 * expected.norm());
        // Every piece lies in a cell at most r/8 wide.
        let side = r / PIECES_PER_RADIUS;
        for q in &points {
            assert!(q.area <= side * side * (1.0 + 1e-12));
        }
    }

    #[test]
    fn a_sliver_of_any_length_gives_a_disc_a_few_pieces() {
        // A sliver of a fan, 0.001 wide, crossing a disc of radius 1 at its middle: the
        // pieces in the disc do not grow with its length (the regular subdivision into m²
        // triangles gave 16 L / r of them): one row of cells r/8 long across the disc.
        let mut counts = Vec::new();
        for length in [10.0, 100.0, 1000.0, 10000.0] {
            let (a, b, c) = (
                Vec3::new(-length / 2.0, 0.0, 0.0),
                Vec3::new(length / 2.0, 0.0, 0.0),
                Vec3::new(length / 2.0, 0.001, 0.0),
            );
            let mut points = Vec::new();
            cut_triangle([a, b, c], [0.0; 3], Vec3::zeros(), 1.0, &mut points);
            counts.push(points.len());
        }
        assert!(counts.iter().all(|&n| (15..=17).contains(&n)), "{counts:?}");
    }

    #[test]
    fn rows_of_points_are_strips_and_discs_are_not() {
        let row = (0..10).map(|i| ([i as f64, 0.01 * (i as f64).powi(2)], 1.0));
        assert!(is_strip(row.clone()));
        let disc = (0..10).map(|i| {
            let (t, s) = (i as f64 * 0.7, 1.0 + 0.1 * i as f64);
            ([s * t.cos(), s * t.sin()], 1.0)
        });
        assert!(!is_strip(disc));
        // Points off the row with next to no weight leave it a strip.
        let faint = (0..4).map(|i| ([i as f64, 3.0], 1e-4));
        assert!(is_strip(row.chain(faint)));
        assert!(!is_strip(
            [([0.0, 0.0], 1.0), ([1.0, 0.0], 1.0)].into_iter()
        ));
    }
}
