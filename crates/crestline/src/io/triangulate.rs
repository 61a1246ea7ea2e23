//! Triangulating the polygons of mesh files: OBJ, OFF and PLY faces, and ascii STL loops, with
//! more than three corners.
//!
//! A polygon becomes the fan from its first corner, `(c0, ci, ci+1)`, when every triangle of
//! that fan faces the way the polygon winds: the triangles of such a fan cover the polygon
//! exactly once (when it does not cross itself). That holds for every convex polygon (nearly
//! every polygon real files hold): the check is O(n) and allocates nothing, and such polygons
//! keep the triangles the readers always made of them. The fan of a polygon that is not
//! convex (the L, U and notched outlines that CAD exporters and Blender write as n-gons) may
//! fold triangles back over the rest to fill a notch; such a polygon is cut by ear clipping
//! instead (G. H. Meisters, "Polygons have ears", Amer. Math. Monthly 82, 1975: a simple
//! polygon of four corners or more has a corner whose triangle with its neighbours lies inside
//! it, to be cut off until one triangle is left; the bookkeeping, where only the two
//! neighbours of a cut corner change and only corners that are not convex can lie in a
//! candidate triangle, is D. Eberly's, "Triangulation by Ear Clipping", Geometric Tools,
//! 2002), in O(n·r) for r corners that are not convex, O(n²) at most.
//!
//! Both steps use the polygon's Newell normal (M. E. Newell; F. Tampieri, "Newell's method for
//! computing the plane equation of a polygon", Graphics Gems III, 1992): the sum of the cross
//! products of consecutive corners, which is twice the polygon's area vector (and the sum of
//! its fan triangles' area vectors), so that it gives the polygon's plane and its winding. A
//! fan triangle is folded when its area vector points against it, by more than
//! [`FOLD_TOLERANCE`]. The ear clipper works in the plane normal to it, where a corner is
//! convex when it turns the way the polygon winds; ears are cut as `(previous, corner, next)`,
//! so every triangle keeps the polygon's winding.
//!
//! Degenerate corners: a repeated corner (the same index, or the same point, twice in a row) or
//! a spike is cut off as a flat triangle, which [`crate::TriMesh`] drops and counts, as it drops
//! the flat triangles a fan makes of them; a straight corner (three corners on a line) is never
//! cut off alone, as that would make a flat triangle and leave a crack, but becomes a corner of
//! the triangles beside it. Points that coincide (a polygon that touches itself, such as an
//! outline bridged to a hole) do not block each other's ears.
//!
//! Every polygon of n corners gives n − 2 triangles, so a polygon met before the positions of
//! its corners are all read is fanned at once and rewritten in place by
//! [`Triangulator::finish`] once they are: an OBJ face before its vertices, and every PLY and
//! OFF polygon (a PLY face element may come before the vertex element, and OFF's pieces are
//! parsed in parallel with the vertices they use).
//!
//! Limits: a polygon whose fan folds and that cannot be cut into ears (one that crosses itself,
//! or one so far from planar that its projection does) keeps its fan, as does one of more than
//! [`MAX_CLIPPED_CORNERS`] corners (the quadratic cost); polygons with holes do not exist in
//! these formats except as an outline bridged to its hole, which is cut like any other.

use nalgebra::Vector2;

use crate::mesh::Vec3;

/// A fan is kept unless one of its triangles faces against the polygon's winding by more than
/// this, as the sine of its angle at the first corner seen along the polygon's normal: a fan
/// triangle folded back less is a sliver no one could see, and files written in single
/// precision have straight corners off their line by about 1e-7 either way. Those keep the
/// triangles they always had.
const FOLD_TOLERANCE: f64 = 1e-6;

/// A corner that turns by less than this (as the sine of the angle between its two sides) is
/// straight to the ear clipper, which never cuts it off alone: it would make a triangle that
/// [`crate::TriMesh`] drops as flat (it drops those flatter than 1e-13), leaving a crack.
const FLAT_TURN: f64 = 1e-10;

/// Polygons of more corners than this keep their fan even when it folds: ear clipping costs up
/// to n²/2 point tests (a zigzag of this many corners takes a fifth of a second), and a file of
/// huge polygons must not take hours to read.
const MAX_CLIPPED_CORNERS: usize = 10_000;

/// Appends the fan of a polygon, `(c0, ci, ci+1)` for `i` in `1..n - 1`.
#[inline]
pub(super) fn push_fan(faces: &mut Vec<[u32; 3]>, corners: &[u32]) {
    match *corners {
        // Triangles and quads, nearly all polygons, without the iterator's overhead.
        [a, b, c] => faces.push([a, b, c]),
        [a, b, c, d] => faces.extend_from_slice(&[[a, b, c], [a, c, d]]),
        [first, ref rest @ ..] => faces.extend(rest.windows(2).map(|w| [first, w[0], w[1]])),
        [] => {}
    }
}

/// Triangulates the polygons of one file as a reader meets them, keeping its buffers from one
/// polygon to the next.
#[derive(Debug, Default)]
pub(super) struct Triangulator {
    /// Polygons met before the positions of all their corners were read, fanned for now: the
    /// index of their first triangle and their number of corners.
    pending: Vec<(usize, usize)>,
    /// The corners of a pending polygon, gathered back from its fan.
    corners: Vec<u32>,
    clipper: EarClipper,
}

impl Triangulator {
    /// Appends the `corners.len() - 2` triangles of the polygon `corners` to `faces`, whatever
    /// its shape. `positions` are the vertices read so far: a polygon with a corner beyond
    /// them is fanned for now and triangulated by [`Triangulator::finish`].
    #[inline]
    pub(super) fn push(
        &mut self,
        faces: &mut Vec<[u32; 3]>,
        corners: &[u32],
        positions: &[[f64; 3]],
    ) {
        if let &[a, b, c] = corners {
            faces.push([a, b, c]);
        } else {
            self.push_polygon(faces, corners, positions);
        }
    }

    /// [`Triangulator::push`] of a polygon that is not a triangle, out of line: the readers'
    /// loops stay as small as they were for files of triangles.
    #[inline(never)]
    fn push_polygon(&mut self, faces: &mut Vec<[u32; 3]>, corners: &[u32], positions: &[[f64; 3]]) {
        let first = faces.len();
        push_fan(faces, corners);
        if corners.len() < 4 {
            return;
        }
        if corners.iter().all(|&c| (c as usize) < positions.len()) {
            self.clipper
                .triangulate(positions, corners, &mut faces[first..]);
        } else {
            self.pending.push((first, corners.len()));
        }
    }

    /// As [`Triangulator::push`] for a polygon whose corners' positions may not all be read
    /// yet: fanned for now, and triangulated by [`Triangulator::finish`].
    #[inline]
    pub(super) fn push_later(&mut self, faces: &mut Vec<[u32; 3]>, corners: &[u32]) {
        if corners.len() > 3 {
            self.pending.push((faces.len(), corners.len()));
        }
        push_fan(faces, corners);
    }

    /// Triangulates the polygons left as fans by [`Triangulator::push`] and
    /// [`Triangulator::push_later`], now that `positions` holds every vertex; `faces` are the
    /// triangles they appended to. A corner still beyond `positions` (a file the reader
    /// refuses anyway) leaves its polygon a fan.
    pub(super) fn finish(&mut self, faces: &mut [[u32; 3]], positions: &[[f64; 3]]) {
        let Triangulator {
            pending,
            corners,
            clipper,
        } = self;
        for &(first, n) in pending.iter() {
            let Some(fan) = faces.get_mut(first..first + (n - 2)) else {
                continue;
            };
            // The corners, gathered back from the fan: a quad's without a buffer.
            let quad;
            let corners: &[u32] = if let [[a, b, c], [_, _, d]] = *fan {
                quad = [a, b, c, d];
                &quad
            } else {
                corners.clear();
                corners.extend_from_slice(&fan[0][..2]);
                corners.extend(fan.iter().map(|t| t[2]));
                corners
            };
            clipper.triangulate(positions, corners, fan);
        }
        pending.clear();
    }
}

/// Whether a polygon needs more than its fan: its Newell normal when a triangle of the fan
/// faces against it by more than [`FOLD_TOLERANCE`]; `None` when the fan is right (every
/// convex polygon, and one whose first corner sees all the others), for a polygon without
/// area, and for one with a corner beyond `positions`.
#[inline]
fn folded_fan_normal(positions: &[[f64; 3]], corners: &[u32]) -> Option<Vec3> {
    let point = |c: u32| positions.get(c as usize).map(|&p| Vec3::from(p));
    // Relative to the first corner: exact for a small polygon far from the origin, and the
    // cross products of consecutive corners are then the fan triangles' area vectors (the
    // first corner's terms vanish).
    let origin = point(*corners.first()?)?;
    let at = |k: usize| Some(point(corners[k])? - origin);
    // Whether the fan triangle of area vector `area` and sides `side` and `next` from the first
    // corner faces against `normal`.
    let folds = |area: Vec3, side: Vec3, next: Vec3, normal: Vec3| {
        let facing = area.dot(&normal);
        facing < 0.0
            && facing * facing
                > FOLD_TOLERANCE
                    * FOLD_TOLERANCE
                    * side.norm_squared()
                    * next.norm_squared()
                    * normal.norm_squared()
    };
    if let [_, b, c, d] = *corners {
        // Quads, the most common polygons, in one pass: two halves that face the same way (the
        // usual case) cannot face against their sum.
        let (b, c, d) = (point(b)? - origin, point(c)? - origin, point(d)? - origin);
        let (first, second) = (b.cross(&c), c.cross(&d));
        if first.dot(&second) >= 0.0 {
            return None;
        }
        let normal = first + second;
        return (folds(first, b, c, normal) || folds(second, c, d, normal)).then_some(normal);
    }
    let n = corners.len();
    if n < 4 {
        return None;
    }
    let mut normal = Vec3::zeros();
    let mut side = at(1)?;
    for k in 2..n {
        let next = at(k)?;
        normal += side.cross(&next);
        side = next;
    }
    let mut side = at(1)?;
    for k in 2..n {
        let next = at(k)?;
        if folds(side.cross(&next), side, next, normal) {
            return Some(normal);
        }
        side = next;
    }
    None
}

/// How a corner of the polygon being clipped turns, in its plane.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Turn {
    /// The way the polygon winds: an ear if its triangle holds no other corner.
    Convex,
    /// Against the winding.
    Reflex,
    /// Straight on, within [`FLAT_TURN`].
    Straight,
    /// Back the way it came (a spike), or not at all (a side of zero length).
    Back,
}

/// Ear clipping of one polygon at a time, with buffers kept from one to the next.
#[derive(Debug, Default)]
struct EarClipper {
    /// The corners, projected on the polygon's plane so that it winds counter-clockwise.
    points: Vec<Vector2<f64>>,
    /// The corners left, as a ring: the previous and next corner of each.
    prev: Vec<usize>,
    next: Vec<usize>,
    /// Whether each corner is an ear (kept up to date for the corners left).
    ear: Vec<bool>,
    /// Whether each corner is in `blockers`.
    blocks: Vec<bool>,
    /// The corners left that are not convex: the only ones that can lie in an ear's triangle.
    blockers: Vec<usize>,
    /// The triangles cut so far, as positions in the polygon.
    triangles: Vec<[u32; 3]>,
}

impl EarClipper {
    /// Replaces `fan`, the fan of the polygon `corners`, by the polygon's ears when the fan
    /// folds and clipping succeeds. A corner beyond `positions` leaves the fan.
    #[inline]
    fn triangulate(&mut self, positions: &[[f64; 3]], corners: &[u32], fan: &mut [[u32; 3]]) {
        if let Some(normal) = folded_fan_normal(positions, corners) {
            self.replace_fan(positions, corners, normal, fan);
        }
    }

    /// [`EarClipper::triangulate`] of a polygon whose fan folds, given its Newell normal
    /// (every corner indexes `positions`); out of line, to keep the readers' loops small.
    #[inline(never)]
    fn replace_fan(
        &mut self,
        positions: &[[f64; 3]],
        corners: &[u32],
        normal: Vec3,
        fan: &mut [[u32; 3]],
    ) {
        if corners.len() > MAX_CLIPPED_CORNERS {
            return;
        }
        if self.clip(positions, corners, normal) && self.triangles.len() == fan.len() {
            for (out, t) in fan.iter_mut().zip(&self.triangles) {
                *out = t.map(|k| corners[k as usize]);
            }
        }
    }

    /// Cuts the polygon into ears (in `triangles`); `false` when it cannot be.
    fn clip(&mut self, positions: &[[f64; 3]], corners: &[u32], normal: Vec3) -> bool {
        if !self.project(positions, corners, normal) {
            return false;
        }
        let n = corners.len();
        self.prev.clear();
        self.prev.extend((0..n).map(|k| (k + n - 1) % n));
        self.next.clear();
        self.next.extend((0..n).map(|k| (k + 1) % n));
        self.triangles.clear();
        self.classify_all(0, n);
        let mut left = n;
        let mut at = 0;
        let mut rescans = 0;
        while left > 3 {
            let cut = self
                .find(at, left, |clipper, k| clipper.ear[k])
                .or_else(|| self.find(at, left, |clipper, k| clipper.turn(k) == Turn::Back));
            let Some(k) = cut else {
                // Only the cut corner's neighbours are classified again, which is enough in
                // exact arithmetic; once or twice, rounding may call for a fresh look.
                if rescans == 2 {
                    return false;
                }
                rescans += 1;
                self.classify_all(at, left);
                continue;
            };
            let (p, q) = (self.prev[k], self.next[k]);
            self.triangles.push([p as u32, k as u32, q as u32]);
            self.next[p] = q;
            self.prev[q] = p;
            self.unblock(k);
            left -= 1;
            if left > 3 {
                self.classify(p);
                self.classify(q);
                self.ear[p] = self.is_ear(p);
                self.ear[q] = self.is_ear(q);
            }
            at = q;
        }
        // What is left is a triangle; one turned against the winding means a polygon that
        // crosses itself.
        if self.turn(at) == Turn::Reflex {
            return false;
        }
        self.triangles
            .push([self.prev[at] as u32, at as u32, self.next[at] as u32]);
        true
    }

    /// Projects the corners on the plane normal to `normal`, with axes that make the polygon
    /// wind counter-clockwise; `false` for a normal without a direction.
    fn project(&mut self, positions: &[[f64; 3]], corners: &[u32], normal: Vec3) -> bool {
        let length = normal.norm();
        if !(length > 0.0 && length.is_finite()) {
            return false;
        }
        let normal = normal / length;
        // The axis most nearly in the plane, made normal to `normal`: (u, v, normal) is
        // right-handed.
        let axis = normal.iamin();
        let u = Vec3::ith(axis, 1.0).cross(&normal).normalize();
        let v = normal.cross(&u);
        let origin = Vec3::from(positions[corners[0] as usize]);
        self.points.clear();
        self.points.extend(corners.iter().map(|&c| {
            let d = Vec3::from(positions[c as usize]) - origin;
            Vector2::new(d.dot(&u), d.dot(&v))
        }));
        self.points
            .iter()
            .all(|p| p.x.is_finite() && p.y.is_finite())
    }

    /// The first corner, walking the ring of the `left` corners from `start`, for which
    /// `wanted` holds.
    fn find(
        &self,
        start: usize,
        left: usize,
        wanted: impl Fn(&Self, usize) -> bool,
    ) -> Option<usize> {
        let mut k = start;
        for _ in 0..left {
            if wanted(self, k) {
                return Some(k);
            }
            k = self.next[k];
        }
        None
    }

    /// Classifies the `left` corners of the ring through `start` afresh: which block ears,
    /// and which are ears.
    fn classify_all(&mut self, start: usize, left: usize) {
        let n = self.points.len();
        self.ear.clear();
        self.ear.resize(n, false);
        self.blocks.clear();
        self.blocks.resize(n, false);
        self.blockers.clear();
        let mut k = start;
        for _ in 0..left {
            self.classify(k);
            k = self.next[k];
        }
        for _ in 0..left {
            self.ear[k] = self.is_ear(k);
            k = self.next[k];
        }
    }

    /// Puts corner `k` in or out of the blockers as it turns now.
    fn classify(&mut self, k: usize) {
        if self.turn(k) == Turn::Convex {
            self.unblock(k);
        } else if !self.blocks[k] {
            self.blocks[k] = true;
            self.blockers.push(k);
        }
    }

    /// Takes corner `k` out of the blockers.
    fn unblock(&mut self, k: usize) {
        if self.blocks[k] {
            self.blocks[k] = false;
            if let Some(i) = self.blockers.iter().position(|&b| b == k) {
                self.blockers.swap_remove(i);
            }
        }
    }

    /// How corner `k` turns, between its previous and next corner left.
    fn turn(&self, k: usize) -> Turn {
        let [a, b, c] = [self.prev[k], k, self.next[k]].map(|i| self.points[i]);
        let (side_in, side_out) = (b - a, c - b);
        let turn = side_in.perp(&side_out);
        let flat = FLAT_TURN * FLAT_TURN * side_in.norm_squared() * side_out.norm_squared();
        if turn * turn > flat {
            if turn > 0.0 {
                Turn::Convex
            } else {
                Turn::Reflex
            }
        } else if side_in.dot(&side_out) > 0.0 {
            Turn::Straight
        } else {
            Turn::Back
        }
    }

    /// Whether corner `k` is an ear: convex, with no corner that is not convex in or on its
    /// triangle (corners at the same point as one of the triangle's do not count).
    fn is_ear(&self, k: usize) -> bool {
        if self.turn(k) != Turn::Convex {
            return false;
        }
        let (p, q) = (self.prev[k], self.next[k]);
        let triangle = [self.points[p], self.points[k], self.points[q]];
        !self.blockers.iter().any(|&b| {
            let point = self.points[b];
            b != p && b != q && !triangle.contains(&point) && touches(&triangle, point)
        })
    }
}

/// Whether `point` lies in or on the counter-clockwise `triangle`, or within [`FLAT_TURN`] of
/// its sides.
fn touches(triangle: &[Vector2<f64>; 3], point: Vector2<f64>) -> bool {
    (0..3).all(|i| {
        let (a, b) = (triangle[i], triangle[(i + 1) % 3]);
        let (side, to_point) = (b - a, point - a);
        let turn = side.perp(&to_point);
        turn >= 0.0
            || turn * turn <= FLAT_TURN * FLAT_TURN * side.norm_squared() * to_point.norm_squared()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The triangles [`Triangulator::push`] makes of the polygon `points` (corners in order).
    fn triangulate(points: &[[f64; 3]]) -> Vec<[u32; 3]> {
        let corners: Vec<u32> = (0..points.len() as u32).collect();
        let mut faces = Vec::new();
        Triangulator::default().push(&mut faces, &corners, points);
        assert_eq!(faces.len(), points.len() - 2);
        faces
    }

    /// The fan of `n` corners.
    fn fan(n: u32) -> Vec<[u32; 3]> {
        (1..n - 1).map(|i| [0, i, i + 1]).collect()
    }

    /// Twice the signed area of the 2D triangle `(a, b, c)`.
    fn area2(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> f64 {
        (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
    }

    /// Twice the signed area of a polygon in the plane z = 0 (shoelace).
    fn polygon_area2(points: &[[f64; 3]]) -> f64 {
        (0..points.len())
            .map(|i| {
                let (a, b) = (points[i], points[(i + 1) % points.len()]);
                a[0] * b[1] - b[0] * a[1]
            })
            .sum()
    }

    /// Whether `p` is strictly inside the polygon `points` (plane z = 0, even-odd rule).
    fn inside(points: &[[f64; 3]], p: [f64; 3]) -> bool {
        let mut inside = false;
        for i in 0..points.len() {
            let (a, b) = (points[i], points[(i + 1) % points.len()]);
            if (a[1] > p[1]) != (b[1] > p[1]) {
                let x = a[0] + (p[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]);
                if p[0] < x {
                    inside = !inside;
                }
            }
        }
        inside
    }

    /// Checks the triangulation of a simple polygon in the plane z = 0: every triangle winds as
    /// the polygon does and lies inside it, and together they cover its area exactly once.
    #[track_caller]
    fn assert_cut_inside(points: &[[f64; 3]]) {
        let faces = triangulate(points);
        let total = polygon_area2(points);
        let mut sum = 0.0;
        for t in &faces {
            let [a, b, c] = t.map(|i| points[i as usize]);
            let area = area2(a, b, c);
            assert!(area * total.signum() > 0.0, "{t:?} winds the wrong way");
            let centre = [(a[0] + b[0] + c[0]) / 3.0, (a[1] + b[1] + c[1]) / 3.0, 0.0];
            assert!(inside(points, centre), "{t:?} outside the polygon");
            sum += area;
        }
        assert!(
            (sum - total).abs() <= 1e-12 * total.abs(),
            "{sum} != {total}"
        );
    }

    /// Corners given as (x, y) in the plane z = 0.
    fn flat(xy: &[[f64; 2]]) -> Vec<[f64; 3]> {
        xy.iter().map(|&[x, y]| [x, y, 0.0]).collect()
    }

    /// The L of the generator's `concave.obj`, counter-clockwise.
    const L: [[f64; 2]; 6] = [[0., 0.], [2., 0.], [2., 1.], [1., 1.], [1., 2.], [0., 2.]];

    /// The U of a notched prism's cap, counter-clockwise: the notch is (1..2) × (1..3).
    const U: [[f64; 2]; 8] = [
        [0., 0.],
        [3., 0.],
        [3., 3.],
        [2., 3.],
        [2., 1.],
        [1., 1.],
        [1., 3.],
        [0., 3.],
    ];

    /// Every rotation of the corners' order, in both windings.
    fn every_start_and_winding(points: &[[f64; 3]]) -> Vec<Vec<[f64; 3]>> {
        let mut out = Vec::new();
        for reversed in [false, true] {
            let mut p = points.to_vec();
            if reversed {
                p.reverse();
            }
            for _ in 0..p.len() {
                p.rotate_left(1);
                out.push(p.clone());
            }
        }
        out
    }

    #[test]
    fn concave_l_and_u_are_cut_inside_their_outline_from_any_start() {
        for polygon in [flat(&L), flat(&U)] {
            for p in every_start_and_winding(&polygon) {
                assert_cut_inside(&p);
            }
        }
    }

    #[test]
    fn a_comb_is_cut_between_its_teeth() {
        // Twelve teeth 5 high on a base 1 high, as a gear's or a connector's outline: most
        // corners are reflex or see only their own tooth.
        let mut comb = vec![[0., 0.], [24., 0.]];
        for k in (0..12).rev() {
            let x = f64::from(k) * 2.0;
            comb.extend([[x + 1.0, 1.0], [x + 1.0, 6.0], [x, 6.0], [x, 1.0]]);
        }
        comb.pop();
        comb.insert(2, [24., 1.]);
        let comb = flat(&comb);
        assert!(polygon_area2(&comb) > 0.0);
        for p in every_start_and_winding(&comb) {
            assert_cut_inside(&p);
        }
    }

    #[test]
    fn the_fan_of_the_u_folds_and_its_ears_do_not() {
        // The fan from (0, 0) crosses the notch: this is the case the clipper is for.
        let u = flat(&U);
        let folded = fan(8)
            .iter()
            .filter(|t| {
                let [a, b, c] = t.map(|i| u[i as usize]);
                area2(a, b, c) <= 0.0
            })
            .count();
        assert!(folded > 0);
        assert_ne!(triangulate(&u), fan(8));
    }

    #[test]
    fn a_concave_polygon_in_a_tilted_plane_keeps_its_winding() {
        // The U on a plane through the origin, tilted about two axes, far from the origin.
        let (s, c) = (0.6f64, 0.8f64);
        let place = |[x, y]: [f64; 2]| -> [f64; 3] {
            let (y, z) = (c * y, s * y);
            let (x, z) = (c * x + s * z, -s * x + c * z);
            [x + 1e4, y - 2e4, z + 3e4]
        };
        let points: Vec<[f64; 3]> = U.iter().map(|&p| place(p)).collect();
        let normal = {
            let a = Vec3::from(points[0]);
            let (b, c) = (Vec3::from(points[1]), Vec3::from(points[7]));
            (b - a).cross(&(c - a))
        };
        let faces = triangulate(&points);
        let mut area = 0.0;
        for t in &faces {
            let [a, b, c] = t.map(|i| Vec3::from(points[i as usize]));
            let n = (b - a).cross(&(c - a));
            assert!(n.dot(&normal) > 0.0, "{t:?} turned over");
            area += n.norm() / 2.0;
        }
        assert!((area - 7.0).abs() < 1e-9, "{area}");
    }

    #[test]
    fn convex_polygons_keep_their_fan() {
        let hexagon: Vec<[f64; 3]> = (0..6)
            .map(|k| {
                let a = f64::from(k) * std::f64::consts::TAU / 6.0;
                [a.cos(), a.sin(), 0.0]
            })
            .collect();
        assert_eq!(triangulate(&hexagon), fan(6));
        let mut clockwise = hexagon.clone();
        clockwise.reverse();
        assert_eq!(triangulate(&clockwise), fan(6));
        // A square with corners on its sides (straight corners), and one whose corners are
        // off by single-precision rounding.
        let sided = flat(&[[0., 0.], [1., 0.], [2., 0.], [2., 2.], [1., 2.], [0., 2.]]);
        assert_eq!(triangulate(&sided), fan(6));
        let rounded = flat(&[[0., 0.], [0.5, 1e-8], [1., 0.], [1., 1.], [0., 1.]]);
        assert_eq!(triangulate(&rounded), fan(5));
        // A quad that is not planar, bent along a diagonal.
        let bent = [[0., 0., 0.], [1., 0., 0.2], [1., 1., 0.], [0., 1., 0.2]];
        assert_eq!(triangulate(&bent), fan(4));
        // An L whose first corner sees every other: its fan is right too.
        assert_eq!(triangulate(&flat(&L)), fan(6));
        // A 200-gon.
        let circle: Vec<[f64; 3]> = (0..200)
            .map(|k| {
                let a = f64::from(k) * std::f64::consts::TAU / 200.0;
                [a.cos(), a.sin(), 0.5]
            })
            .collect();
        assert_eq!(triangulate(&circle), fan(200));
    }

    #[test]
    fn straight_corners_of_a_concave_polygon_are_corners_of_real_triangles() {
        // The U with corners in the middle of sides: ears with no flat triangle, which the
        // mesh would drop, leaving a crack. (A fan that does not fold keeps its flat triangles,
        // as convex polygons always have.)
        let u = flat(&[
            [0., 0.],
            [1.5, 0.],
            [3., 0.],
            [3., 3.],
            [2., 3.],
            [2., 2.],
            [2., 1.],
            [1.5, 1.],
            [1., 1.],
            [1., 3.],
            [0., 3.],
            [0., 1.5],
        ]);
        let mut clipped = 0;
        for p in every_start_and_winding(&u) {
            if triangulate(&p) != fan(12) {
                assert_cut_inside(&p);
                clipped += 1;
            }
        }
        assert!(clipped >= 12, "{clipped}");
    }

    #[test]
    fn repeated_corners_of_a_concave_polygon_become_flat_triangles() {
        // The U with its corners 2 and 5 given twice: the real triangles still cover it once,
        // and the extra ones are flat (the mesh drops them).
        let points = flat(&U);
        let corners = [0, 1, 2, 2, 3, 4, 5, 5, 6, 7];
        let mut faces = Vec::new();
        Triangulator::default().push(&mut faces, &corners, &points);
        assert_eq!(faces.len(), 8);
        let mut sum = 0.0;
        let mut flat_ones = 0;
        for t in &faces {
            let [a, b, c] = t.map(|i| points[i as usize]);
            let area = area2(a, b, c);
            assert!(area >= 0.0, "{t:?}");
            flat_ones += usize::from(area == 0.0);
            sum += area;
        }
        assert_eq!(flat_ones, 2);
        assert!((sum - polygon_area2(&points)).abs() < 1e-12);
    }

    #[test]
    fn a_polygon_bridged_to_its_hole_is_cut_around_the_hole() {
        // A 4 × 4 square with a 2 × 2 hole, joined by a bridge whose ends are given twice.
        let points = flat(&[
            [0., 0.],
            [4., 0.],
            [4., 4.],
            [0., 4.],
            [0., 0.],
            [1., 1.],
            [1., 3.],
            [3., 3.],
            [3., 1.],
            [1., 1.],
        ]);
        let faces = triangulate(&points);
        let mut sum = 0.0;
        for t in &faces {
            let [a, b, c] = t.map(|i| points[i as usize]);
            let area = area2(a, b, c);
            assert!(area >= 0.0, "{t:?}");
            sum += area;
        }
        assert!((sum - 2.0 * 12.0).abs() < 1e-12, "{sum}");
    }

    #[test]
    fn star_shaped_polygons_are_cut_inside_their_outline() {
        // Random simple polygons: corners at increasing angles less than half a turn apart,
        // at random distances from the centre.
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut random = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        for n in [4u32, 5, 7, 12, 40, 120] {
            for _ in 0..30 {
                let points: Vec<[f64; 3]> = (0..n)
                    .map(|k| {
                        let a =
                            (f64::from(k) + 0.9 * random()) * std::f64::consts::TAU / f64::from(n);
                        let r = 0.2 + random();
                        [r * a.cos(), r * a.sin(), 0.0]
                    })
                    .collect();
                assert_cut_inside(&points);
            }
        }
    }

    #[test]
    fn polygons_pushed_before_their_vertices_are_cut_by_finish() {
        let points = flat(&U);
        let corners: Vec<u32> = (0..8).collect();
        let mut triangulator = Triangulator::default();
        let mut faces = vec![[9, 9, 9]];
        triangulator.push(&mut faces, &corners, &points[..3]);
        triangulator.push(&mut faces, &[0, 1, 2, 3], &[]);
        assert_eq!(&faces[1..7], &fan(8)[..]);
        triangulator.finish(&mut faces, &points);
        assert_eq!(faces[0], [9, 9, 9]);
        assert_eq!(&faces[1..7], &triangulate(&points)[..]);
        assert_eq!(&faces[7..], &fan(4)[..]);
        // A corner still missing leaves the fan.
        let mut faces = Vec::new();
        triangulator.push(&mut faces, &corners, &[]);
        triangulator.finish(&mut faces, &points[..7]);
        assert_eq!(faces, fan(8));
    }

    #[test]
    fn degenerate_polygons_do_not_panic_and_give_n_minus_2_triangles() {
        let cases: Vec<Vec<[f64; 3]>> = vec![
            // All on a line, once and out and back.
            flat(&[[0., 0.], [1., 0.], [2., 0.], [3., 0.]]),
            flat(&[[0., 0.], [2., 0.], [1., 0.], [3., 0.], [0.5, 0.]]),
            // All at one point.
            vec![[1.0, 2.0, 3.0]; 6],
            // A spike out of a square, and a square whose side goes back over itself.
            flat(&[[0., 0.], [1., 0.], [2., 0.], [1., 0.], [1., 1.], [0., 1.]]),
            flat(&[[0., 0.], [2., 0.], [1., 0.], [2., 0.], [2., 2.], [0., 2.]]),
            // A bow tie of equal lobes (no area) and one of unequal lobes, crossing
            // themselves, and a pentagram.
            flat(&[[0., 0.], [1., 1.], [1., 0.], [0., 1.]]),
            flat(&[[0., 0.], [2., 2.], [2., 0.], [0., 1.]]),
            (0..5)
                .map(|k| {
                    let a = f64::from(k * 2) * std::f64::consts::TAU / 5.0;
                    [a.cos(), a.sin(), 0.0]
                })
                .collect(),
            // Far from planar: a U folded along its notch.
            U.iter()
                .map(|&[x, y]| [x, y, if x > 1.5 { 5.0 * y } else { -5.0 * y }])
                .collect(),
            // Huge and tiny coordinates.
            flat(&L).iter().map(|p| p.map(|c| c * 1e300)).collect(),
            flat(&L).iter().map(|p| p.map(|c| c * 1e-300)).collect(),
        ];
        for points in cases {
            let faces = triangulate(&points);
            assert!(faces.iter().flatten().all(|&i| (i as usize) < points.len()));
        }
        // Repeated indices of a zero-area polygon: the fan.
        let points = flat(&[[0., 0.], [1., 0.]]);
        let mut faces = Vec::new();
        Triangulator::default().push(&mut faces, &[0, 1, 0, 1, 1], &points);
        assert_eq!(faces, vec![[0, 1, 0], [0, 0, 1], [0, 1, 1]]);
    }

    #[test]
    fn push_fan_makes_the_fan_from_the_first_corner() {
        let mut faces = Vec::new();
        push_fan(&mut faces, &[0, 1, 2, 3, 4]);
        assert_eq!(faces, vec![[0, 1, 2], [0, 2, 3], [0, 3, 4]]);
    }
}
