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
//! error, which is not noise.
//!
//! **How.** The triangles are found breadth-first from the centre's triangles across edges
//! that are not creases, keeping those that come within the radius of the centre. Each is
//! cut into m² congruent triangles (m = ⌈4 L / r⌉ for its longest edge L, at most 64), and
//! each piece is one sample at its centroid with its area as weight and the linear
//! interpolation of its corners' simulated noise. Only the pieces near the disc are looked
//! at ([`cut_triangle`]): the 4096 pieces of each of the thousands of slivers of a fan that
//! reach a disc were all tested before (a capped cylinder of 2048 segments took 47 s, 9 now).

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

/// Pieces per triangle side per radius.
const PIECES_PER_RADIUS: f64 = 4.0;

/// At most this many pieces along a triangle's side.
const MAX_PIECES: usize = 64;

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

    /// Samples the surface within `r` of vertex `v` on its triangles into `s.points`, and
    /// returns the samples' kernel-weighted area normal.
    pub(super) fn sample_triangles(&self, v: u32, r: f64, s: &mut Scratch) -> Vec3 {
        let topo = self.mesh.topology();
        let p = self.mesh.position(v);
        let r2 = r * r;
        let stamp = next_stamp(&mut s.face_marks, &mut s.face_stamp, self.mesh.num_faces());
        s.faces.clear();
        match self.split {
            Some(split) if split.vertices[v as usize] => {
                s.faces
                    .extend(crate::mesh::widest_side(self.mesh, v, split.edges))
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
/// The pieces are those of the regular subdivision into m² triangles, at their centroids
/// `a + u (b − a) + w (c − a)`: in row i (u = (i + o) / m, o = 1/3 for the upright pieces
/// and 2/3 for the inverted ones) the centroids lie on a line along `c − a`, and only the
/// stretch of it within the ball is visited. The pieces and their order are those of all
/// m² tested in turn, at a cost of about m plus the pieces kept: a disc on a fan of
/// thousands of slivers used to test millions.
fn cut_triangle(
    corners: [Vec3; 3],
    noise: [f64; 3],
    p: Vec3,
    r: f64,
    points: &mut Vec<SurfacePoint>,
) -> Vec3 {
    let r2 = r * r;
    let [a, b, c] = corners;
    let area_vector = (b - a).cross(&(c - a)) / 2.0;
    let longest = [(b - a), (c - b), (a - c)]
        .iter()
        .map(|d| d.norm())
        .fold(0.0, f64::max);
    let m = ((PIECES_PER_RADIUS * longest / r).ceil() as usize).clamp(1, MAX_PIECES);
    let piece = area_vector.norm() / (m * m) as f64;
    // Pieces without area weigh nothing in a fit (`SurfacePoint::sample`).
    if piece.is_nan() || piece <= 0.0 {
        return Vec3::zeros();
    }
    let unit = area_vector.try_normalize(0.0).unwrap_or_else(Vec3::zeros);
    let inv = 1.0 / m as f64;
    let along = c - a;
    let along2 = along.norm_squared();
    let mut normal = Vec3::zeros();
    for i in 0..m {
        // The pieces j of row i whose centroids can be within r: w = (j + o) / m within
        // `reach` of the foot of p on the row's line, for either offset.
        let rows = m - i;
        let mut columns = rows..0;
        for o in [1.0 / 3.0, 2.0 / 3.0] {
            let start = a + (b - a) * ((i as f64 + o) * inv);
            let to_p = p - start;
            // (The triangle has area: c − a is not zero.)
            let foot = to_p.dot(&along) / along2;
            let gap2 = (to_p - along * foot).norm_squared();
            if gap2.is_nan() || gap2 >= r2 || !foot.is_finite() {
                continue;
            }
            let reach = ((r2 - gap2) / along2).sqrt();
            // (j + o) / m in [foot − reach, foot + reach], with a margin of one piece.
            let low = ((foot - reach) * m as f64 - o).floor() - 1.0;
            let high = ((foot + reach) * m as f64 - o).ceil() + 1.0;
            let low = low.clamp(0.0, rows as f64) as usize;
            let high = (high.max(0.0) as usize).min(rows - 1) + 1;
            columns = columns.start.min(low)..columns.end.max(high);
        }
        for j in columns {
            let offsets: &[f64] = if i + j + 1 < m {
                &[1.0 / 3.0, 2.0 / 3.0]
            } else {
                &[1.0 / 3.0]
            };
            for &o in offsets {
                let (u, w) = ((i as f64 + o) * inv, (j as f64 + o) * inv);
                let x = a + (b - a) * u + along * w;
                let d2 = (x - p).norm_squared() / r2;
                if d2 >= 1.0 {
                    continue;
                }
                normal += unit * (piece * kernel(d2));
                points.push(SurfacePoint {
                    position: x,
                    area: piece,
                    noise: (1.0 - u - w) * noise[0] + u * noise[1] + w * noise[2],
                });
            }
        }
    }
    normal
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
    /// The sample this point makes in the frame (u, w, n) centred at `p`, scaled by `1 / r`.
    #[inline]
    pub(super) fn sample(&self, p: Vec3, [u, w, n]: [Vec3; 3], r: f64) -> Option<Sample> {
        let d = (self.position - p) / r;
        let weight = self.area * kernel(d.norm_squared());
        (weight > 0.0).then(|| Sample {
            x: d.dot(&u),
            y: d.dot(&w),
            z: d.dot(&n),
            w: weight,
            xi: self.noise / r,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// [`cut_triangle`] as it was written first: every one of the m² pieces tested.
    fn every_piece(corners: [Vec3; 3], p: Vec3, r: f64) -> Vec<[f64; 4]> {
        let [a, b, c] = corners;
        let longest = [(b - a), (c - b), (a - c)]
            .iter()
            .map(|d| d.norm())
            .fold(0.0, f64::max);
        let m = ((PIECES_PER_RADIUS * longest / r).ceil() as usize).clamp(1, MAX_PIECES);
        let inv = 1.0 / m as f64;
        let mut kept = Vec::new();
        for i in 0..m {
            for j in 0..m - i {
                let offsets: &[f64] = if i + j + 1 < m {
                    &[1.0 / 3.0, 2.0 / 3.0]
                } else {
                    &[1.0 / 3.0]
                };
                for &o in offsets {
                    let (u, w) = ((i as f64 + o) * inv, (j as f64 + o) * inv);
                    let x = a + (b - a) * u + (c - a) * w;
                    if (x - p).norm_squared() / (r * r) < 1.0 {
                        kept.push([x.x, x.y, x.z, u]);
                    }
                }
            }
        }
        kept
    }

    #[test]
    fn only_the_pieces_near_the_disc_are_visited_and_none_is_missed() {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut uniform = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
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
            let visited: Vec<[f64; 3]> = points.iter().map(|q| q.position.into()).collect();
            let all: Vec<[f64; 3]> = every_piece([a, b, c], p, r)
                .iter()
                .map(|x| [x[0], x[1], x[2]])
                .collect();
            assert_eq!(visited, all, "trial {trial}");
        }
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
