//! The CAD solids of `cad_shapes.rs` (issue 20), built with their exact sharp edges and
//! corners: a box, a capped cylinder, a cone, a chamfered block, a block with one filleted
//! edge and a box-cylinder union, each tessellated as CAD exporters do and finely and
//! irregularly (see `cad_shapes.rs` for the tessellations and the scoring).

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::collections::HashMap;
use std::f64::consts::{FRAC_PI_2, TAU};

use crestline::{TriMesh, Vec3};

/// How faces are cut into triangles.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Tessellation {
    /// As CAD exporters: no vertex inside a face.
    Export,
    /// Fine and irregular.
    Fine,
}

/// Chordal tolerance of the exports, relative to the diagonal.
const CHORDAL: f64 = 0.0005;
/// Spacing of the fine meshes, relative to the diagonal.
const SPACING: f64 = 0.02;

/// A deterministic generator (splitmix64).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in [-1, 1].
    fn signed(&mut self) -> f64 {
        2.0 * self.next() - 1.0
    }
}

/// Triangles welded by position, each wound outward and labelled planar or not.
struct Builder {
    mode: Tessellation,
    /// Fine spacing (model units).
    h: f64,
    /// Chordal tolerance (model units).
    chordal: f64,
    rng: Rng,
    positions: Vec<Vec3>,
    index: HashMap<[i64; 3], u32>,
    faces: Vec<[u32; 3]>,
    planar: Vec<bool>,
}

impl Builder {
    fn new(mode: Tessellation, diagonal: f64) -> Self {
        Builder {
            mode,
            h: SPACING * diagonal,
            chordal: CHORDAL * diagonal,
            rng: Rng(20),
            positions: Vec::new(),
            index: HashMap::new(),
            faces: Vec::new(),
            planar: Vec::new(),
        }
    }

    fn vertex(&mut self, p: Vec3) -> u32 {
        let key = [p.x, p.y, p.z].map(|c| (c * 1e9).round() as i64);
        *self.index.entry(key).or_insert_with(|| {
            self.positions.push(p);
            (self.positions.len() - 1) as u32
        })
    }

    fn triangle(&mut self, [a, b, c]: [Vec3; 3], outward: Vec3, planar: bool) {
        let (ia, ib, ic) = (self.vertex(a), self.vertex(b), self.vertex(c));
        if ia == ib || ib == ic || ia == ic {
            return;
        }
        let flip = (b - a).cross(&(c - a)).dot(&outward) < 0.0;
        self.faces
            .push(if flip { [ia, ic, ib] } else { [ia, ib, ic] });
        self.planar.push(planar);
    }

    /// Segments of a circular arc of radius `r` and `angle` radians: by the chordal tolerance
    /// (exports) or the spacing (fine), at least `at_least`.
    fn arc_segments(&self, r: f64, angle: f64, at_least: usize) -> usize {
        let n = match self.mode {
            Tessellation::Export => {
                let step = 2.0 * (1.0 - self.chordal / r).clamp(-1.0, 1.0).acos();
                (angle / step).ceil()
            }
            Tessellation::Fine => (angle * r / self.h).ceil(),
        };
        (n as usize).max(at_least)
    }

    /// Pieces of a straight edge of length `length`.
    fn line_segments(&self, length: f64) -> usize {
        match self.mode {
            Tessellation::Export => 1,
            Tessellation::Fine => ((length / self.h).ceil() as usize).max(1),
        }
    }

    /// A planar convex face bounded by the closed loop `boundary`.
    fn planar(&mut self, boundary: &[Vec3], normal: Vec3) {
        match self.mode {
            Tessellation::Export => self.fan(boundary, normal),
            Tessellation::Fine => self.rings(boundary, normal),
        }
    }

    /// A fan from the loop vertex whose thinnest triangle is the widest; when every fan has a
    /// degenerate triangle (points along every side), ears are clipped instead, the largest
    /// first.
    fn fan(&mut self, boundary: &[Vec3], normal: Vec3) {
        let n = boundary.len();
        let area = |a: Vec3, b: Vec3, c: Vec3| (b - a).cross(&(c - a)).norm();
        let thinnest = |apex: usize| {
            (1..n - 1)
                .map(|k| {
                    area(
                        boundary[apex],
                        boundary[(apex + k) % n],
                        boundary[(apex + k + 1) % n],
                    )
                })
                .fold(f64::INFINITY, f64::min)
        };
        let apex = (0..n)
            .max_by(|&a, &b| thinnest(a).total_cmp(&thinnest(b)))
            .unwrap();
        let scale = perimeter(boundary);
        if thinnest(apex) <= 1e-9 * scale * scale {
            // Zip two chains between opposite corners: no triangle has three points on one
            // side.
            let corners: Vec<usize> = (0..n)
                .filter(|&k| {
                    area(
                        boundary[(k + n - 1) % n],
                        boundary[k],
                        boundary[(k + 1) % n],
                    ) > 1e-9 * scale * scale
                })
                .collect();
            let (i0, i1) = (corners[0], corners[corners.len() / 2]);
            let a: Vec<Vec3> = (i0..=i1).map(|k| boundary[k]).collect();
            let b: Vec<Vec3> = (i1..=i0 + n).rev().map(|k| boundary[k % n]).collect();
            let (mut i, mut j) = (0, 0);
            while i + 1 < a.len() || j + 1 < b.len() {
                let advance_a = j + 1 == b.len()
                    || (i + 1 < a.len()
                        && (i + 1) as f64 / (a.len() - 1) as f64
                            <= (j + 1) as f64 / (b.len() - 1) as f64);
                if advance_a {
                    self.triangle([a[i], a[i + 1], b[j]], normal, true);
                    i += 1;
                } else {
                    self.triangle([a[i], b[j + 1], b[j]], normal, true);
                    j += 1;
                }
            }
            return;
        }
        for k in 1..n - 1 {
            let tri = [
                boundary[apex],
                boundary[(apex + k) % n],
                boundary[(apex + k + 1) % n],
            ];
            self.triangle(tri, normal, true);
        }
    }

    /// Concentric loops shrunk towards the centre, resampled at the spacing and jittered,
    /// joined by strips; a fan at the centre.
    fn rings(&mut self, boundary: &[Vec3], normal: Vec3) {
        let n = boundary.len() as f64;
        let centre = boundary.iter().fold(Vec3::zeros(), |s, p| s + p) / n;
        let radius = boundary
            .iter()
            .map(|p| (p - centre).norm())
            .fold(0.0, f64::max);
        let count = ((radius / self.h).ceil() as usize).max(1);
        let (u, v) = plane_basis(normal);
        let mut outer = boundary.to_vec();
        for k in 1..count {
            let s = 1.0 - k as f64 / count as f64;
            let shrunk: Vec<Vec3> = boundary.iter().map(|p| centre + (p - centre) * s).collect();
            let samples = ((perimeter(&shrunk) / self.h).round() as usize).max(3);
            let mut ring = resample_loop(&shrunk, samples);
            for p in &mut ring {
                let (a, b) = (self.rng.signed(), self.rng.signed());
                *p += (u * a + v * b) * 0.15 * self.h;
            }
            self.strip_loops(&outer, &ring, normal);
            outer = ring;
        }
        for k in 0..outer.len() {
            let tri = [outer[k], outer[(k + 1) % outer.len()], centre];
            self.triangle(tri, normal, true);
        }
    }

    /// Triangles between two closed loops of any counts, planar with `normal`.
    fn strip_loops(&mut self, a: &[Vec3], b: &[Vec3], normal: Vec3) {
        let (n, m) = (a.len(), b.len());
        let start = (0..m)
            .min_by(|&i, &j| (b[i] - a[0]).norm().total_cmp(&(b[j] - a[0]).norm()))
            .unwrap();
        let (mut i, mut j) = (0, 0);
        while i < n || j < m {
            let advance_a =
                j == m || (i < n && (i + 1) as f64 / n as f64 <= (j + 1) as f64 / m as f64);
            let (pa, pb) = (a[i % n], b[(start + j) % m]);
            if advance_a {
                self.triangle([pa, a[(i + 1) % n], pb], normal, true);
                i += 1;
            } else {
                self.triangle([pa, b[(start + j + 1) % m], pb], normal, true);
                j += 1;
            }
        }
    }

    /// A ruled face between the polylines `a` and `b` (same counts; corresponding points on
    /// one ruling). Column k (between points k and k + 1) is planar when `planar[k]`.
    fn strip(
        &mut self,
        a: &[Vec3],
        b: &[Vec3],
        closed: bool,
        planar: &[bool],
        outward: &dyn Fn(Vec3) -> Vec3,
    ) {
        let n = a.len();
        let longest = a
            .iter()
            .zip(b)
            .map(|(p, q)| (q - p).norm())
            .fold(0.0, f64::max);
        let levels = self.line_segments(longest);
        // Rows of points, interior rows jittered along the rulings.
        let mut rows: Vec<Vec<Vec3>> = Vec::with_capacity(levels + 1);
        for l in 0..=levels {
            let row = (0..n)
                .map(|k| {
                    let mut t = l as f64 / levels as f64;
                    if l > 0 && l < levels {
                        t += 0.25 * self.rng.signed() / levels as f64;
                    }
                    a[k] + (b[k] - a[k]) * t
                })
                .collect();
            rows.push(row);
        }
        let columns = if closed { n } else { n - 1 };
        for l in 0..levels {
            for k in 0..columns {
                let k1 = (k + 1) % n;
                let (p, q, r, s) = (rows[l][k], rows[l][k1], rows[l + 1][k1], rows[l + 1][k]);
                let centre = (p + q + r + s) / 4.0;
                let out = outward(centre);
                let flip = self.mode == Tessellation::Fine && self.rng.next() < 0.5;
                let (t1, t2) = if flip {
                    ([p, q, s], [q, r, s])
                } else {
                    ([p, q, r], [p, r, s])
                };
                self.triangle(t1, out, planar[k]);
                self.triangle(t2, out, planar[k]);
            }
        }
    }

    fn mesh(&self) -> TriMesh {
        TriMesh::new(self.positions.clone(), self.faces.clone()).unwrap()
    }

    /// The solid built, with its exact sharp edges and corners.
    fn solid(&self, name: String, sharp: Vec<(Vec<Vec3>, bool)>, corners: Vec<Vec3>) -> Solid {
        Solid {
            name,
            mesh: self.mesh(),
            planar: self.planar.clone(),
            sharp,
            corners,
        }
    }
}

fn plane_basis(n: Vec3) -> (Vec3, Vec3) {
    let helper = if n.x.abs() < 0.9 {
        Vec3::x()
    } else {
        Vec3::y()
    };
    let u = n.cross(&helper).normalize();
    (u, n.cross(&u))
}

fn perimeter(loop_: &[Vec3]) -> f64 {
    (0..loop_.len())
        .map(|k| (loop_[(k + 1) % loop_.len()] - loop_[k]).norm())
        .sum()
}

/// `count` points evenly spaced along a closed polygon.
fn resample_loop(loop_: &[Vec3], count: usize) -> Vec<Vec3> {
    let total = perimeter(loop_);
    let n = loop_.len();
    let mut out = Vec::with_capacity(count);
    let (mut k, mut walked) = (0, 0.0);
    for s in 0..count {
        let target = total * s as f64 / count as f64;
        loop {
            let seg = (loop_[(k + 1) % n] - loop_[k]).norm();
            if walked + seg >= target || k + 1 >= n {
                let t = if seg > 0.0 {
                    (target - walked) / seg
                } else {
                    0.0
                };
                out.push(loop_[k] + (loop_[(k + 1) % n] - loop_[k]) * t.clamp(0.0, 1.0));
                break;
            }
            walked += seg;
            k += 1;
        }
    }
    out
}

/// A piece of a planar profile (in the xy plane).
#[derive(Clone, Copy)]
enum Piece {
    /// A straight segment from the point to the start of the next piece.
    Line([f64; 2]),
    /// An arc around `centre` of `radius` from angle `from` to `to` (counter-clockwise).
    Arc {
        centre: [f64; 2],
        radius: f64,
        from: f64,
        to: f64,
    },
}

impl Piece {
    fn start(&self) -> [f64; 2] {
        match *self {
            Piece::Line(p) => p,
            Piece::Arc {
                centre,
                radius,
                from,
                ..
            } => [
                centre[0] + radius * from.cos(),
                centre[1] + radius * from.sin(),
            ],
        }
    }
}

/// A closed counter-clockwise profile: its pieces and which piece starts have a sharp corner.
struct Profile {
    pieces: Vec<Piece>,
    sharp: Vec<bool>,
}

/// `m` points at equal angles along the arc around `centre` from `angles[0]` to `angles[1]`,
/// the last left out.
fn arc_points(
    centre: [f64; 2],
    radius: f64,
    [from, to]: [f64; 2],
    m: usize,
) -> impl Iterator<Item = [f64; 2]> {
    (0..m).map(move |s| {
        let a = from + (to - from) * s as f64 / m as f64;
        [centre[0] + radius * a.cos(), centre[1] + radius * a.sin()]
    })
}

impl Profile {
    fn polygon(corners: &[[f64; 2]]) -> Self {
        Profile {
            pieces: corners.iter().map(|&p| Piece::Line(p)).collect(),
            sharp: vec![true; corners.len()],
        }
    }

    fn circle(radius: f64) -> Self {
        Profile {
            pieces: vec![Piece::Arc {
                centre: [0.0, 0.0],
                radius,
                from: 0.0,
                to: TAU,
            }],
            sharp: vec![false],
        }
    }

    /// Points of the profile's tessellation, and per segment whether it is straight.
    fn tessellate(&self, b: &Builder) -> (Vec<[f64; 2]>, Vec<bool>) {
        let (mut points, mut straight) = (Vec::new(), Vec::new());
        for (k, piece) in self.pieces.iter().enumerate() {
            let end = self.pieces[(k + 1) % self.pieces.len()].start();
            match *piece {
                Piece::Line(p) => {
                    let d = ((end[0] - p[0]).powi(2) + (end[1] - p[1]).powi(2)).sqrt();
                    let m = b.line_segments(d);
                    for s in 0..m {
                        let t = s as f64 / m as f64;
                        points.push([p[0] + (end[0] - p[0]) * t, p[1] + (end[1] - p[1]) * t]);
                        straight.push(true);
                    }
                }
                Piece::Arc {
                    centre,
                    radius,
                    from,
                    to,
                } => {
                    let m = b.arc_segments(radius, to - from, 3);
                    points.extend(arc_points(centre, radius, [from, to], m));
                    straight.extend(std::iter::repeat_n(false, m));
                }
            }
        }
        (points, straight)
    }

    /// The exact outline at height z, densely sampled, as one closed polyline.
    fn outline(&self, z: f64) -> Vec<Vec3> {
        let mut out = Vec::new();
        for piece in &self.pieces {
            match *piece {
                Piece::Line(p) => out.push(Vec3::new(p[0], p[1], z)),
                Piece::Arc {
                    centre,
                    radius,
                    from,
                    to,
                } => out.extend(
                    arc_points(centre, radius, [from, to], 2000).map(|[x, y]| Vec3::new(x, y, z)),
                ),
            }
        }
        out
    }

    fn corners(&self) -> Vec<[f64; 2]> {
        self.pieces
            .iter()
            .zip(&self.sharp)
            .filter(|(_, s)| **s)
            .map(|(p, _)| p.start())
            .collect()
    }
}

/// A test solid: its mesh, planar labels, exact sharp edges (polylines with a closed flag) and
/// corners.
pub(super) struct Solid {
    pub(super) name: String,
    pub(super) mesh: TriMesh,
    pub(super) planar: Vec<bool>,
    pub(super) sharp: Vec<(Vec<Vec3>, bool)>,
    pub(super) corners: Vec<Vec3>,
}

fn lift(p: [f64; 2], z: f64) -> Vec3 {
    Vec3::new(p[0], p[1], z)
}

/// The vertical sharp edges from `z0` to `z1` at the profile corners `corners`, pushed onto
/// `sharp`; returns their ends, the solid's corners.
fn vertical_edges(
    corners: &[[f64; 2]],
    z0: f64,
    z1: f64,
    sharp: &mut Vec<(Vec<Vec3>, bool)>,
) -> Vec<Vec3> {
    let mut ends = Vec::new();
    for &c in corners {
        sharp.push((vec![lift(c, z0), lift(c, z1)], false));
        ends.push(lift(c, z0));
        ends.push(lift(c, z1));
    }
    ends
}

/// Radially outward from the z axis through `centre`.
fn radial(centre: [f64; 2]) -> impl Fn(Vec3) -> Vec3 {
    move |p: Vec3| Vec3::new(p.x - centre[0], p.y - centre[1], 0.0)
}

/// The profile extruded from z = 0 to `height`.
fn prism(name: &str, profile: &Profile, height: f64, mode: Tessellation) -> Solid {
    let corners_2d = profile.corners();
    let outline = profile.outline(0.0);
    let (lo, hi) = outline.iter().fold(
        (Vec3::repeat(f64::INFINITY), Vec3::repeat(f64::NEG_INFINITY)),
        |(lo, hi), p| (lo.inf(p), hi.sup(p)),
    );
    let diagonal = (hi - lo + Vec3::new(0.0, 0.0, height)).norm();
    let mut b = Builder::new(mode, diagonal);
    let (points, straight) = profile.tessellate(&b);
    let bottom: Vec<Vec3> = points.iter().map(|&p| lift(p, 0.0)).collect();
    let top: Vec<Vec3> = points.iter().map(|&p| lift(p, height)).collect();
    b.planar(&bottom, -Vec3::z());
    b.planar(&top, Vec3::z());
    let centre = [(lo.x + hi.x) / 2.0, (lo.y + hi.y) / 2.0];
    b.strip(&bottom, &top, true, &straight, &radial(centre));

    let mut sharp = vec![
        (profile.outline(0.0), true),
        (profile.outline(height), true),
    ];
    let corners = vertical_edges(&corners_2d, 0.0, height, &mut sharp);
    b.solid(format!("{name} ({mode:?})"), sharp, corners)
}

pub(super) fn block(mode: Tessellation) -> Solid {
    let profile = Profile::polygon(&[[-1.0, -0.6], [1.0, -0.6], [1.0, 0.6], [-1.0, 0.6]]);
    prism("box", &profile, 0.8, mode)
}

pub(super) fn chamfered_block(mode: Tessellation) -> Solid {
    let profile = Profile::polygon(&[
        [-1.0, -0.6],
        [1.0, -0.6],
        [1.0, 0.3],
        [0.7, 0.6],
        [-1.0, 0.6],
    ]);
    prism("chamfered block", &profile, 0.8, mode)
}

fn filleted_block(mode: Tessellation) -> Solid {
    let r = 0.35;
    let profile = Profile {
        pieces: vec![
            Piece::Line([-1.0, -0.6]),
            Piece::Line([1.0, -0.6]),
            Piece::Arc {
                centre: [1.0 - r, 0.6 - r],
                radius: r,
                from: 0.0,
                to: FRAC_PI_2,
            },
            Piece::Line([1.0 - r, 0.6]),
            Piece::Line([-1.0, 0.6]),
        ],
        // The fillet's tangent edges are not sharp.
        sharp: vec![true, true, false, false, true],
    };
    prism("filleted block", &profile, 0.8, mode)
}

fn capped_cylinder(mode: Tessellation) -> Solid {
    prism("capped cylinder", &Profile::circle(0.6), 1.5, mode)
}

fn cone(mode: Tessellation) -> Solid {
    let (r, height): (f64, f64) = (0.8, 1.2);
    let diagonal = (4.0 * r * r + 4.0 * r * r + height * height).sqrt();
    let mut b = Builder::new(mode, diagonal);
    let n = b.arc_segments(r, TAU, 8);
    let rim: Vec<Vec3> = (0..n)
        .map(|k| {
            let a = TAU * k as f64 / n as f64;
            Vec3::new(r * a.cos(), r * a.sin(), 0.0)
        })
        .collect();
    let apex = vec![Vec3::new(0.0, 0.0, height); n];
    b.planar(&rim, -Vec3::z());
    b.strip(&rim, &apex, true, &vec![false; n], &|p: Vec3| {
        Vec3::new(p.x, p.y, 0.0).normalize() * height + Vec3::z() * r
    });
    b.solid(
        format!("cone ({mode:?})"),
        vec![(Profile::circle(r).outline(0.0), true)],
        Vec::new(),
    )
}

/// A box [-1, 1]² × [0, 0.6] with a cylinder of radius 0.5 standing on it up to z = 1.5.
fn box_cylinder_union(mode: Tessellation) -> Solid {
    let (r, z_box, z_top): (f64, f64, f64) = (0.5, 0.6, 1.5);
    let diagonal = (8.0 + z_top * z_top).sqrt();
    let mut b = Builder::new(mode, diagonal);
    // Rays at multiples of 2π/n, n a multiple of 8 so that the square's corners are on rays.
    let n = b.arc_segments(r, TAU, 8).div_ceil(8) * 8;
    let dirs: Vec<[f64; 2]> = (0..n)
        .map(|k| {
            let a = TAU * k as f64 / n as f64;
            [a.cos(), a.sin()]
        })
        .collect();
    let square = |z: f64| -> Vec<Vec3> {
        dirs.iter()
            .map(|d| {
                let s = d[0].abs().max(d[1].abs());
                Vec3::new(d[0] / s, d[1] / s, z)
            })
            .collect()
    };
    let circle = |z: f64| -> Vec<Vec3> {
        dirs.iter()
            .map(|d| Vec3::new(r * d[0], r * d[1], z))
            .collect()
    };
    let (bottom, rim) = (square(0.0), square(z_box));
    b.planar(&bottom, -Vec3::z());
    b.strip(&bottom, &rim, true, &vec![true; n], &radial([0.0, 0.0]));
    b.strip(&rim, &circle(z_box), true, &vec![true; n], &|_| Vec3::z());
    b.strip(
        &circle(z_box),
        &circle(z_top),
        true,
        &vec![false; n],
        &radial([0.0, 0.0]),
    );
    b.planar(&circle(z_top), Vec3::z());

    let square_profile = Profile::polygon(&[[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]]);
    let mut sharp = vec![
        (square_profile.outline(0.0), true),
        (square_profile.outline(z_box), true),
        (Profile::circle(r).outline(z_box), true),
        (Profile::circle(r).outline(z_top), true),
    ];
    let corners = vertical_edges(&square_profile.corners(), 0.0, z_box, &mut sharp);
    b.solid(format!("box-cylinder union ({mode:?})"), sharp, corners)
}

pub(super) fn solids() -> Vec<Solid> {
    let builders: [fn(Tessellation) -> Solid; 6] = [
        block,
        capped_cylinder,
        cone,
        chamfered_block,
        filleted_block,
        box_cylinder_union,
    ];
    builders
        .iter()
        .flat_map(|f| [f(Tessellation::Export), f(Tessellation::Fine)])
        .collect()
}
