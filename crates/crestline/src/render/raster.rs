//! A software z-buffer rasteriser and the shading of the pixels it covers.
//!
//! ## Rasterising
//! Vertices are projected once and snapped to 1/256 pixel, so the edge functions are exact
//! integer arithmetic: two triangles sharing an edge never leave a crack nor both claim a
//! pixel centre on it (a pixel centre exactly on an edge belongs to the triangle for which
//! that edge runs downwards, or rightwards when horizontal — the usual "top-left" rule, in
//! a form independent of the winding). Faces are drawn from both sides. The result is a
//! visibility buffer: per pixel, the depth and the index of the nearest face.
//!
//! Work is split into horizontal bands of [`BAND_ROWS`] rows. Faces are first sorted into
//! the bands their pixels touch (in face order, so the result does not depend on the
//! number of threads), then the bands are rasterised in parallel, each owning its rows of
//! the buffer.
//!
//! ## Shading
//! A second pass computes, for each covered pixel, the barycentric coordinates of its
//! centre in its face, interpolates the normals of its corners (or takes the face normal), turns
//! the normal towards the camera (two-sided lighting) and applies Lambert diffuse plus a
//! Blinn highlight. The light is attached to the camera: it shines from the viewer, a little
//! from the upper left, so relief reads the same from every direction.
//!
//! A corner's normal is its vertex's (area-weighted) normal, except where the surface folds
//! at the vertex (a face of its star more than [`FOLD_DEGREES`] off the corner's face): there
//! it averages only the faces within that angle of the corner's face (per face, unlike
//! modelling tools' "auto smooth", which splits the fan at sharp edges: at a fan that turns
//! by more than the angle in small steps, neighbouring faces can then disagree a little). A cube's faces stay flat and a CAD part's creases crisp, also when its
//! file stored the sides of each crease with separate vertices and they were welded.

use rayon::prelude::*;

use super::camera::Camera;
use super::colormap::ColorScale;
use super::{RenderOptions, Rgb};
use crate::mesh::{TriMesh, Vec3};

/// The angle between two faces at a vertex beyond which the shading does not smooth across
/// them (degrees).
pub const FOLD_DEGREES: f64 = 30.0;

/// Rows per band of parallel work.
pub const BAND_ROWS: usize = 16;
/// Sub-pixel steps per pixel of the snapped coordinates.
pub(super) const SUB: i64 = 256;
/// Faces per unit of parallel work when sorting faces into bands.
const BIN_CHUNK: usize = 1 << 15;
/// Marks a pixel no face covers.
pub const NO_FACE: u32 = u32::MAX;
/// Pixel coordinates are clamped to this magnitude so that edge functions fit in `i64`.
const MAX_PIXEL: f64 = 1.0e6;

/// A projected vertex: position in 1/256 pixel and depth (smaller is nearer).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ScreenVertex {
    pub(super) x: i64,
    pub(super) y: i64,
    z: f32,
}

/// Per pixel, the depth and the face seen there.
#[derive(Debug, Clone)]
pub struct VisibilityBuffer {
    /// Width in pixels.
    pub width: usize,
    /// Height in pixels.
    pub height: usize,
    /// Depth of the nearest face, `+inf` where no face is.
    pub depth: Vec<f32>,
    /// Index of the nearest face, [`NO_FACE`] where no face is.
    pub face: Vec<u32>,
}

impl VisibilityBuffer {
    /// Depth at pixel (`x`, `y`), `None` outside the image.
    pub fn depth_at(&self, x: i64, y: i64) -> Option<f32> {
        if x < 0 || y < 0 || x >= self.width as i64 || y >= self.height as i64 {
            return None;
        }
        Some(self.depth[y as usize * self.width + x as usize])
    }
}

/// Projects every vertex with `camera`.
///
/// The depth is narrowed to `f32` only after the projection, which measures it from the
/// camera's centre (see `camera.rs`): it is then of the order of the model's size, and
/// `f32` resolves it to about 1e-7 of that wherever the model lies.
pub fn project_vertices(mesh: &TriMesh, camera: &Camera) -> Vec<ScreenVertex> {
    mesh.positions()
        .par_iter()
        .map(|p| {
            let [x, y, z] = camera.project(p);
            let snap = |c: f64| (c.clamp(-MAX_PIXEL, MAX_PIXEL) * SUB as f64).round() as i64;
            ScreenVertex {
                x: snap(x),
                y: snap(y),
                z: z as f32,
            }
        })
        .collect()
}

/// Twice the signed area of (a, b, p) in snapped units; positive when p is to the left of
/// a→b in a y-down frame seen as y-up (the orientation does not matter to callers).
#[inline]
pub(super) fn edge(a: (i64, i64), b: (i64, i64), p: (i64, i64)) -> i64 {
    (b.0 - a.0) * (p.1 - a.1) - (b.1 - a.1) * (p.0 - a.0)
}

/// Whether pixel centres exactly on the edge a→b belong to the triangle on its positive
/// side. Exactly one of a→b and b→a owns the edge.
#[inline]
fn owns_edge(a: (i64, i64), b: (i64, i64)) -> bool {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    dy > 0 || (dy == 0 && dx > 0)
}

/// The inclusive range of pixel indices whose centres lie in [lo, hi] (snapped units),
/// clipped to 0..n; `None` when empty.
#[inline]
fn pixel_span(lo: i64, hi: i64, n: usize) -> Option<(usize, usize)> {
    let first = (lo - SUB / 2).div_euclid(SUB) + i64::from((lo - SUB / 2).rem_euclid(SUB) != 0);
    let last = (hi - SUB / 2).div_euclid(SUB);
    let (first, last) = (first.max(0), last.min(n as i64 - 1));
    (first <= last).then_some((first as usize, last as usize))
}

/// The pixel rows and columns whose centres a face's bounding box contains.
#[inline]
fn pixel_box(
    v: [ScreenVertex; 3],
    width: usize,
    height: usize,
) -> Option<((usize, usize), (usize, usize))> {
    let xs = [v[0].x, v[1].x, v[2].x];
    let ys = [v[0].y, v[1].y, v[2].y];
    let cols = pixel_span(min3(xs), max3(xs), width)?;
    let rows = pixel_span(min3(ys), max3(ys), height)?;
    Some((cols, rows))
}

#[inline]
fn min3(a: [i64; 3]) -> i64 {
    a[0].min(a[1]).min(a[2])
}

#[inline]
fn max3(a: [i64; 3]) -> i64 {
    a[0].max(a[1]).max(a[2])
}

#[inline]
pub(super) fn corners(screen: &[ScreenVertex], t: &[u32; 3]) -> [ScreenVertex; 3] {
    [
        screen[t[0] as usize],
        screen[t[1] as usize],
        screen[t[2] as usize],
    ]
}

/// Sorts face indices into the bands of rows their pixels touch, in face order.
fn bin_faces(
    screen: &[ScreenVertex],
    faces: &[[u32; 3]],
    width: usize,
    height: usize,
) -> Vec<Vec<u32>> {
    let bands = height.div_ceil(BAND_ROWS);
    let per_chunk: Vec<Vec<Vec<u32>>> = faces
        .par_chunks(BIN_CHUNK)
        .enumerate()
        .map(|(c, chunk)| {
            let mut bins = vec![Vec::new(); bands];
            for (k, t) in chunk.iter().enumerate() {
                if let Some((_, (r0, r1))) = pixel_box(corners(screen, t), width, height) {
                    let id = (c * BIN_CHUNK + k) as u32;
                    for bin in &mut bins[r0 / BAND_ROWS..=r1 / BAND_ROWS] {
                        bin.push(id);
                    }
                }
            }
            bins
        })
        .collect();
    (0..bands)
        .into_par_iter()
        .map(|b| {
            let n = per_chunk.iter().map(|bins| bins[b].len()).sum();
            let mut all = Vec::with_capacity(n);
            for bins in &per_chunk {
                all.extend_from_slice(&bins[b]);
            }
            all
        })
        .collect()
}

/// Rasterises `faces` (indices into `screen`, fewer than `u32::MAX`) into a
/// `width` × `height` visibility buffer.
pub fn rasterize(
    screen: &[ScreenVertex],
    faces: &[[u32; 3]],
    width: usize,
    height: usize,
) -> VisibilityBuffer {
    let bins = bin_faces(screen, faces, width, height);
    let mut depth = vec![f32::INFINITY; width * height];
    let mut face = vec![NO_FACE; width * height];
    depth
        .par_chunks_mut(width * BAND_ROWS)
        .zip(face.par_chunks_mut(width * BAND_ROWS))
        .zip(bins.par_iter())
        .enumerate()
        .for_each(|(b, ((depth, face), bin))| {
            let mut band = Band {
                first_row: b * BAND_ROWS,
                rows: depth.len() / width,
                width,
                depth,
                face,
            };
            for &f in bin {
                band.draw_triangle(corners(screen, &faces[f as usize]), f);
            }
        });
    VisibilityBuffer {
        width,
        height,
        depth,
        face,
    }
}

/// The rows of the visibility buffer one thread owns.
struct Band<'a> {
    first_row: usize,
    rows: usize,
    width: usize,
    depth: &'a mut [f32],
    face: &'a mut [u32],
}

impl Band<'_> {
    /// Writes face `id` where it is nearer than what the band holds.
    fn draw_triangle(&mut self, v: [ScreenVertex; 3], id: u32) {
        let [a, mut b, mut c] = v;
        let mut area = edge((a.x, a.y), (b.x, b.y), (c.x, c.y));
        if area == 0 {
            return;
        }
        if area < 0 {
            std::mem::swap(&mut b, &mut c);
            area = -area;
        }
        let Some(((c0, c1), (r0, r1))) = pixel_box([a, b, c], self.width, self.height_limit())
        else {
            return;
        };
        let r0 = r0.max(self.first_row);
        if r0 > r1 {
            return;
        }
        let (pa, pb, pc) = ((a.x, a.y), (b.x, b.y), (c.x, c.y));
        // Weight of each vertex = edge function of the opposite edge; a centre exactly on an
        // edge the triangle does not own is pushed out by one unit.
        let opposite = [(pb, pc), (pc, pa), (pa, pb)];
        let bias = opposite.map(|(p, q)| if owns_edge(p, q) { 0 } else { -1 });
        let steps = opposite.map(|(p, q)| -(q.1 - p.1) * SUB);
        let x0 = c0 as i64 * SUB + SUB / 2;
        let inv_area = 1.0 / area as f32;
        let (za, zb, zc) = (a.z, b.z, c.z);
        for row in r0..=r1 {
            let y = row as i64 * SUB + SUB / 2;
            let mut w = [0i64; 3];
            for k in 0..3 {
                w[k] = edge(opposite[k].0, opposite[k].1, (x0, y)) + bias[k];
            }
            let base = (row - self.first_row) * self.width;
            for col in c0..=c1 {
                if (w[0] | w[1] | w[2]) >= 0 {
                    let z = (w[0] as f32 * za + w[1] as f32 * zb + w[2] as f32 * zc) * inv_area;
                    let i = base + col;
                    if z < self.depth[i] {
                        self.depth[i] = z;
                        self.face[i] = id;
                    }
                }
                w[0] += steps[0];
                w[1] += steps[1];
                w[2] += steps[2];
            }
        }
    }

    /// One past the last image row this band owns.
    fn height_limit(&self) -> usize {
        self.first_row + self.rows
    }
}

/// The normals of the faces' corners: per vertex, and per corner where the surface folds
/// (see the module docs).
struct CornerNormals {
    vertex: Vec<Vec3>,
    /// Per face, an index into `folded`, or `u32::MAX` when its corners take their vertices'
    /// normals.
    face: Vec<u32>,
    folded: Vec<[Vec3; 3]>,
}

impl CornerNormals {
    fn new(mesh: &TriMesh) -> Self {
        let faces = mesh.faces();
        let topo = mesh.topology();
        // Face normals weighted by area (cross products) and their lengths, once.
        let (weighted, lengths): (Vec<Vec3>, Vec<f64>) = (0..faces.len())
            .into_par_iter()
            .map(|f| {
                let [a, b, c] = mesh.triangle(f);
                let n = (b - a).cross(&(c - a));
                (n, n.norm())
            })
            .unzip();
        // The normal of the faces `star` keeps (unit; `fallback` when they cancel).
        let sum = |star: &[u32], keep: &dyn Fn(u32) -> bool, fallback: Vec3| {
            star.iter()
                .filter(|&&g| keep(g))
                .map(|&g| weighted[g as usize])
                .sum::<Vec3>()
                .try_normalize(0.0)
                .unwrap_or(fallback)
        };
        // The area-weighted vertex normals (those of `crate::mesh::vertex_normals_area`).
        let vertex: Vec<Vec3> = (0..mesh.num_vertices() as u32)
            .into_par_iter()
            .map(|v| sum(topo.vertex_faces(v), &|_| true, Vec3::zeros()))
            .collect();
        let cos_fold = FOLD_DEGREES.to_radians().cos();
        let within = |f: usize, g: u32| {
            let g = g as usize;
            weighted[f].dot(&weighted[g]) >= cos_fold * lengths[f] * lengths[g]
        };
        let folded: Vec<(u32, [Vec3; 3])> = (0..faces.len())
            .into_par_iter()
            .filter_map(|f| {
                let star = |k: usize| topo.vertex_faces(faces[f][k]);
                let folds = (0..3).any(|k| star(k).iter().any(|&g| !within(f, g)));
                folds.then(|| {
                    let own = weighted[f].try_normalize(0.0).unwrap_or_else(Vec3::zeros);
                    let corners = std::array::from_fn(|k| sum(star(k), &|g| within(f, g), own));
                    (f as u32, corners)
                })
            })
            .collect();
        let mut face = vec![u32::MAX; faces.len()];
        for (i, (f, _)) in folded.iter().enumerate() {
            face[*f as usize] = i as u32;
        }
        CornerNormals {
            vertex,
            face,
            folded: folded.into_iter().map(|(_, corners)| corners).collect(),
        }
    }

    /// The normal of corner `k` of face `f`, whose vertices are `t`.
    fn corner(&self, f: u32, t: &[u32; 3], k: usize) -> Vec3 {
        match self.face[f as usize] {
            u32::MAX => self.vertex[t[k] as usize],
            i => self.folded[i as usize][k],
        }
    }
}

/// Everything the shading pass needs besides the buffer.
pub struct Shading {
    normals: Option<CornerNormals>,
    toward: Vec3,
    light: Vec3,
    half: Vec3,
    ambient: f64,
    specular: f64,
    shininess: f64,
    surface: Rgb,
    background: Rgb,
}

impl Shading {
    /// Lighting set up for `camera` under `opts`.
    pub fn new(mesh: &TriMesh, camera: &Camera, opts: &RenderOptions) -> Self {
        let toward = camera.toward();
        let light = (toward + camera.up() * 0.35 - camera.right() * 0.25).normalize();
        Shading {
            normals: opts.smooth_shading.then(|| CornerNormals::new(mesh)),
            toward,
            light,
            half: (light + toward).normalize(),
            ambient: opts.ambient,
            specular: opts.specular,
            shininess: opts.shininess,
            surface: opts.surface,
            background: opts.background,
        }
    }

    /// The lit colour of a surface with base colour `base` and unit normal `n` (facing the
    /// camera).
    fn lit(&self, base: Rgb, n: Vec3) -> [u8; 3] {
        let diffuse = n.dot(&self.light).max(0.0);
        let highlight = 255.0 * self.specular * n.dot(&self.half).max(0.0).powf(self.shininess);
        let light = self.ambient + (1.0 - self.ambient) * diffuse;
        base.map(|c| (f64::from(c) * light + highlight).round().clamp(0.0, 255.0) as u8)
    }
}

/// Colours every pixel of `rgba` (row-major RGBA, the buffer's size): the background where
/// no face is, the lit surface (or field colour) elsewhere.
pub fn shade(
    buffer: &VisibilityBuffer,
    mesh: &TriMesh,
    screen: &[ScreenVertex],
    shading: &Shading,
    field: Option<(&ColorScale, &[f64])>,
    rgba: &mut [u8],
) {
    for_each_pixel(buffer, rgba, |face, p, px| {
        let rgb = match face {
            None => shading.background,
            Some(f) => shade_pixel(mesh, f, screen, shading, field, p),
        };
        px.copy_from_slice(&[rgb[0], rgb[1], rgb[2], 255]);
    });
}

/// Calls `paint` on every pixel of `rgba` (row-major RGBA, the buffer's size), in parallel
/// over rows, with the face seen there (`None` where no face is) and the pixel's centre in
/// snapped units.
pub fn for_each_pixel(
    buffer: &VisibilityBuffer,
    rgba: &mut [u8],
    paint: impl Fn(Option<u32>, (i64, i64), &mut [u8]) + Sync,
) {
    let width = buffer.width;
    rgba.par_chunks_mut(width * 4)
        .enumerate()
        .for_each(|(row, out)| {
            let y = row as i64 * SUB + SUB / 2;
            for (col, px) in out.chunks_exact_mut(4).enumerate() {
                let face = buffer.face[row * width + col];
                let x = col as i64 * SUB + SUB / 2;
                paint((face != NO_FACE).then_some(face), (x, y), px);
            }
        });
}

/// The colour of face `f` at the pixel centre `p` (snapped units).
fn shade_pixel(
    mesh: &TriMesh,
    f: u32,
    screen: &[ScreenVertex],
    shading: &Shading,
    field: Option<(&ColorScale, &[f64])>,
    p: (i64, i64),
) -> Rgb {
    let t = mesh.faces()[f as usize];
    let [a, b, c] = corners(screen, &t).map(|v| (v.x, v.y));
    let area = edge(a, b, c);
    // Projected winding is clockwise in the y-down frame when the face's normal points to
    // the camera.
    let side = if area < 0 { 1.0 } else { -1.0 };
    let inv = 1.0 / area as f64;
    let weights = [
        edge(b, c, p) as f64 * inv,
        edge(c, a, p) as f64 * inv,
        edge(a, b, p) as f64 * inv,
    ]
    .map(|w| w.clamp(0.0, 1.0));
    let sum: f64 = weights.iter().sum();
    let weights = if sum > 0.0 {
        weights.map(|w| w / sum)
    } else {
        [1.0 / 3.0; 3]
    };
    let normal = match &shading.normals {
        Some(normals) => {
            let n: Vec3 = (0..3).map(|k| normals.corner(f, &t, k) * weights[k]).sum();
            n * side
        }
        None => {
            let [pa, pb, pc] = t.map(|v| mesh.position(v));
            (pb - pa).cross(&(pc - pa))
        }
    };
    let mut normal = normal.try_normalize(0.0).unwrap_or(shading.toward);
    if shading.normals.is_none() && normal.dot(&shading.toward) < 0.0 {
        normal = -normal;
    }
    let base = field
        .and_then(|(scale, values)| {
            let v: f64 = (0..3).map(|k| values[t[k] as usize] * weights[k]).sum();
            scale.color(v)
        })
        .unwrap_or(shading.surface);
    shading.lit(base, normal)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sv(x: f64, y: f64, z: f32) -> ScreenVertex {
        ScreenVertex {
            x: (x * SUB as f64) as i64,
            y: (y * SUB as f64) as i64,
            z,
        }
    }

    #[test]
    fn corners_at_a_fold_take_the_normals_of_their_own_side() {
        // The octahedron folds by 109° at every edge: each face is shaded flat.
        let octahedron = crate::shapes::octahedron();
        let normals = CornerNormals::new(&octahedron);
        for (f, t) in octahedron.faces().iter().enumerate() {
            let [a, b, c] = octahedron.triangle(f);
            let n = (b - a).cross(&(c - a)).normalize();
            for k in 0..3 {
                assert!((normals.corner(f as u32, t, k) - n).norm() < 1e-12);
            }
        }
        // A fine sphere does not fold anywhere: every corner takes its vertex's normal.
        let sphere = crate::shapes::icosphere(1.0, 3);
        let normals = CornerNormals::new(&sphere);
        assert!(normals.folded.is_empty());
        assert!(normals.face.iter().all(|&i| i == u32::MAX));
    }

    fn covered(buf: &VisibilityBuffer) -> usize {
        buf.face.iter().filter(|&&f| f != NO_FACE).count()
    }

    #[test]
    fn two_triangles_of_a_square_cover_it_exactly_once() {
        // A 6x6 px square split along its diagonal, both windings: 36 pixels, no gap, and
        // each pixel written by exactly one triangle.
        let screen = [
            sv(1.0, 1.0, 0.0),
            sv(7.0, 1.0, 0.0),
            sv(7.0, 7.0, 0.0),
            sv(1.0, 7.0, 0.0),
        ];
        for faces in [[[0, 1, 2], [0, 2, 3]], [[0, 2, 1], [0, 3, 2]]] {
            let buf = rasterize(&screen, &faces, 10, 10);
            assert_eq!(covered(&buf), 36);
            let on_first = buf.face.iter().filter(|&&f| f == 0).count();
            // The diagonal's 6 centres go to one side only.
            assert!(on_first == 15 || on_first == 21, "{on_first}");
        }
    }

    #[test]
    fn nearer_face_wins_regardless_of_order() {
        let screen = [
            sv(0.0, 0.0, 2.0),
            sv(8.0, 0.0, 2.0),
            sv(0.0, 8.0, 2.0),
            sv(0.0, 0.0, 1.0),
            sv(8.0, 0.0, 1.0),
            sv(0.0, 8.0, 1.0),
        ];
        for faces in [[[0, 1, 2], [3, 4, 5]], [[3, 4, 5], [0, 1, 2]]] {
            let buf = rasterize(&screen, &faces, 8, 8);
            let near = faces.iter().position(|t| t[0] == 3).unwrap() as u32;
            assert!(buf.face.iter().all(|&f| f == NO_FACE || f == near));
            assert!((buf.depth_at(1, 1).unwrap() - 1.0).abs() < 1e-5);
        }
    }

    #[test]
    fn triangles_spanning_bands_and_leaving_the_image_are_clipped() {
        let screen = [
            sv(-5.0, -5.0, 0.0),
            sv(50.0, -5.0, 0.0),
            sv(-5.0, 50.0, 0.0),
        ];
        let buf = rasterize(&screen, &[[0, 1, 2]], 20, 40);
        // Every pixel centre with x + y + 1 <= 45 is covered: those exactly on the
        // hypotenuse too, since it runs downwards (b to c) and so belongs to the triangle.
        let expected = (0..20)
            .flat_map(|x| (0..40).map(move |y| (x, y)))
            .filter(|&(x, y)| (x as f64 + 0.5) + (y as f64 + 0.5) <= 45.0)
            .count();
        assert_eq!(covered(&buf), expected);
    }

    #[test]
    fn depth_is_interpolated() {
        let screen = [sv(0.0, 0.0, 0.0), sv(16.0, 0.0, 16.0), sv(0.0, 16.0, 0.0)];
        let buf = rasterize(&screen, &[[0, 1, 2]], 16, 16);
        let z = buf.depth_at(4, 2).unwrap();
        assert!((z - 4.5).abs() < 1e-5, "{z}");
    }
}
