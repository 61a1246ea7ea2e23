//! Generated meshes of analytic surfaces with known curvature, used by tests, benchmarks and
//! the built-in example.
//!
//! Every closed shape is wound counter-clockwise seen from outside, so face and vertex
//! normals point outward. Vertices lie exactly on the analytic surface.
//! [`pillow_box`] and [`tablet`] also return their exact crease lines, for the simplification
//! and crest-line tests.

pub mod exact;

use std::f64::consts::{PI, TAU};

use crate::lines::{FeatureLine, FeatureLines, LineKind, SurfacePoint};
use crate::mesh::{TriMesh, Vec3};

fn build(positions: Vec<Vec3>, faces: Vec<[u32; 3]>) -> TriMesh {
    match TriMesh::new(positions, faces) {
        Ok(m) => m,
        // Generators only emit finite positions and in-range indices.
        Err(e) => unreachable!("generated mesh is invalid: {e}"),
    }
}

/// A strip of `n` unit quads along x, between y = 0 and y = 1 (vertices `2i` at (i, 0) and
/// `2i + 1` at (i, 1)), each cut along its diagonal from (i, 0) to (i + 1, 1): the smallest
/// mesh on which the tracing and line-assembly tests lay a line across rungs.
#[cfg(test)]
pub(crate) fn quad_strip(n: u32) -> TriMesh {
    let positions = (0..=n)
        .flat_map(|i| {
            [
                Vec3::new(f64::from(i), 0.0, 0.0),
                Vec3::new(f64::from(i), 1.0, 0.0),
            ]
        })
        .collect();
    let faces = (0..n)
        .flat_map(|i| {
            let (a, b, c, d) = (2 * i, 2 * i + 2, 2 * i + 3, 2 * i + 1);
            [[a, b, c], [a, c, d]]
        })
        .collect();
    build(positions, faces)
}

/// The regular octahedron with vertices ±e_x, ±e_y, ±e_z (in that order), wound outward: the
/// smallest closed mesh whose shape operator is known exactly (1 in every direction at each
/// vertex).
pub fn octahedron() -> TriMesh {
    let positions = [
        [1.0, 0.0, 0.0],
        [-1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, -1.0, 0.0],
        [0.0, 0.0, 1.0],
        [0.0, 0.0, -1.0],
    ];
    let faces = vec![
        [0, 2, 4],
        [2, 1, 4],
        [1, 3, 4],
        [3, 0, 4],
        [2, 0, 5],
        [1, 2, 5],
        [3, 1, 5],
        [0, 3, 5],
    ];
    build(positions.into_iter().map(Vec3::from).collect(), faces)
}

/// The tetrahedron with corners at the origin, e_x, e_y and e_z (in that order), wound
/// outward: the smallest closed mesh.
pub fn tetrahedron() -> TriMesh {
    let positions = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
    ];
    let faces = vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]];
    build(positions.into_iter().map(Vec3::from).collect(), faces)
}

/// An icosahedron subdivided `subdivisions` times, projected on the sphere of `radius`
/// (20 · 4^s faces).
pub fn icosphere(radius: f64, subdivisions: u32) -> TriMesh {
    let (positions, faces) = unit_icosphere(subdivisions);
    build(positions.into_iter().map(|p| p * radius).collect(), faces)
}

fn unit_icosphere(subdivisions: u32) -> (Vec<Vec3>, Vec<[u32; 3]>) {
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let mut positions: Vec<Vec3> = [
        [-1.0, t, 0.0],
        [1.0, t, 0.0],
        [-1.0, -t, 0.0],
        [1.0, -t, 0.0],
        [0.0, -1.0, t],
        [0.0, 1.0, t],
        [0.0, -1.0, -t],
        [0.0, 1.0, -t],
        [t, 0.0, -1.0],
        [t, 0.0, 1.0],
        [-t, 0.0, -1.0],
        [-t, 0.0, 1.0],
    ]
    .iter()
    .map(|&p| Vec3::from(p).normalize())
    .collect();
    let mut faces: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..subdivisions {
        let mut midpoint = std::collections::HashMap::new();
        let mut mid = |a: u32, b: u32, positions: &mut Vec<Vec3>| -> u32 {
            let key = (a.min(b), a.max(b));
            *midpoint.entry(key).or_insert_with(|| {
                let p = (positions[a as usize] + positions[b as usize]).normalize();
                positions.push(p);
                (positions.len() - 1) as u32
            })
        };
        let mut next = Vec::with_capacity(faces.len() * 4);
        for [a, b, c] in faces {
            let ab = mid(a, b, &mut positions);
            let bc = mid(b, c, &mut positions);
            let ca = mid(c, a, &mut positions);
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        faces = next;
    }
    (positions, faces)
}

/// A triaxial ellipsoid x²/a² + y²/b² + z²/c² = 1: an icosphere scaled along the axes.
pub fn ellipsoid(a: f64, b: f64, c: f64, subdivisions: u32) -> TriMesh {
    let (positions, faces) = unit_icosphere(subdivisions);
    let positions = positions
        .into_iter()
        .map(|p| Vec3::new(a * p.x, b * p.y, c * p.z))
        .collect();
    build(positions, faces)
}

/// How the quads of a parametric grid are split into triangles.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum GridPattern {
    /// Alternating diagonals (a checkerboard): vertices of valence 4 and 8 alternate. The
    /// pattern of [`torus`], [`cylinder`], [`height_field`] and [`waving_surface`].
    #[default]
    Alternating,
    /// Every quad split along the same diagonal: every interior vertex has valence 6 and
    /// the mesh is translation-invariant (a regular lattice). Discrete operators that are
    /// only consistent on regular meshes (the HPW shape operator) are tested on this.
    Uniform,
}

/// A grid over the parameter rectangle [0, 1]² mapped through `f`, `nu` × `nv` cells, each
/// split into two triangles as `pattern` says. `wrap_u`/`wrap_v` join the last column/row
/// to the first (periodic directions).
fn parametric(
    nu: usize,
    nv: usize,
    wrap_u: bool,
    wrap_v: bool,
    pattern: GridPattern,
    f: impl Fn(f64, f64) -> Vec3,
) -> (Vec<Vec3>, Vec<[u32; 3]>) {
    let cols = if wrap_u { nu } else { nu + 1 };
    let rows = if wrap_v { nv } else { nv + 1 };
    let mut positions = Vec::with_capacity(cols * rows);
    for j in 0..rows {
        for i in 0..cols {
            positions.push(f(i as f64 / nu as f64, j as f64 / nv as f64));
        }
    }
    let id = |i: usize, j: usize| ((j % rows) * cols + (i % cols)) as u32;
    let mut faces = Vec::with_capacity(2 * nu * nv);
    for j in 0..nv {
        for i in 0..nu {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            if pattern == GridPattern::Uniform || (i + j) % 2 == 0 {
                faces.extend([[a, b, c], [a, c, d]]);
            } else {
                faces.extend([[a, b, d], [b, c, d]]);
            }
        }
    }
    (positions, faces)
}

/// A torus around the z axis with tube centre radius `major` and tube radius `minor`.
/// Principal curvatures: 1/minor across the tube and cos φ / (major + minor cos φ) along it.
pub fn torus(major: f64, minor: f64, n_major: usize, n_minor: usize) -> TriMesh {
    torus_with(major, minor, n_major, n_minor, GridPattern::Alternating)
}

/// [`torus`] with a choice of triangulation.
pub fn torus_with(
    major: f64,
    minor: f64,
    n_major: usize,
    n_minor: usize,
    pattern: GridPattern,
) -> TriMesh {
    let (p, f) = parametric(n_major, n_minor, true, true, pattern, |u, v| {
        let (theta, phi) = (TAU * u, TAU * v);
        let r = major + minor * phi.cos();
        Vec3::new(r * theta.cos(), r * theta.sin(), minor * phi.sin())
    });
    build(p, f)
}

/// An open cylinder of `radius` around the z axis from z = 0 to z = `height`
/// (k_max = 1/radius around, k_min = 0 along).
pub fn cylinder(radius: f64, height: f64, n_around: usize, n_along: usize) -> TriMesh {
    cylinder_with(radius, height, n_around, n_along, GridPattern::Alternating)
}

/// [`cylinder`] with a choice of triangulation.
pub fn cylinder_with(
    radius: f64,
    height: f64,
    n_around: usize,
    n_along: usize,
    pattern: GridPattern,
) -> TriMesh {
    let (p, f) = parametric(n_around, n_along, true, false, pattern, |u, v| {
        let theta = TAU * u;
        Vec3::new(radius * theta.cos(), radius * theta.sin(), height * v)
    });
    build(p, f)
}

/// The graph z = h(x, y) over [x0, x1] × [y0, y1] on an `nx` × `ny` grid, normal up (+z).
pub fn height_field(
    h: impl Fn(f64, f64) -> f64,
    x_range: [f64; 2],
    y_range: [f64; 2],
    nx: usize,
    ny: usize,
) -> TriMesh {
    height_field_with(h, x_range, y_range, nx, ny, GridPattern::Alternating)
}

/// [`height_field`] with a choice of triangulation.
pub fn height_field_with(
    h: impl Fn(f64, f64) -> f64,
    [x0, x1]: [f64; 2],
    [y0, y1]: [f64; 2],
    nx: usize,
    ny: usize,
    pattern: GridPattern,
) -> TriMesh {
    let (p, f) = parametric(nx, ny, false, false, pattern, |u, v| {
        let (x, y) = (x0 + (x1 - x0) * u, y0 + (y1 - y0) * v);
        Vec3::new(x, y, h(x, y))
    });
    build(p, f)
}

/// The waving surface of YBS 2005, z = cos(sqrt(x² + y²)), over the square [-r, r]² on an
/// `n` × `n` grid. Its exact crest lines are the circles sqrt(x² + y²) = kπ.
pub fn waving_surface(r: f64, n: usize) -> TriMesh {
    waving_surface_with(r, n, GridPattern::Alternating)
}

/// [`waving_surface`] with a choice of triangulation.
pub fn waving_surface_with(r: f64, n: usize, pattern: GridPattern) -> TriMesh {
    height_field_with(
        |x, y| (x * x + y * y).sqrt().cos(),
        [-r, r],
        [-r, r],
        n,
        n,
        pattern,
    )
}

/// A disk of `radius` around the z axis lifted to the graph z = h(x, y), meshed by `rings`
/// concentric rings of 6, 12, ..., 6·rings vertices around a centre vertex (nearly
/// equilateral triangles, 6·rings² of them), normal up (+z).
pub fn disk(h: impl Fn(f64, f64) -> f64, radius: f64, rings: usize) -> TriMesh {
    let mut positions = vec![Vec3::new(0.0, 0.0, h(0.0, 0.0))];
    let mut ring_start = vec![0usize];
    for j in 1..=rings {
        ring_start.push(positions.len());
        let r = radius * j as f64 / rings as f64;
        let n = 6 * j;
        // Stagger alternate rings by half a step so the strips do not line up.
        let offset = if j % 2 == 0 { 0.5 } else { 0.0 };
        for i in 0..n {
            let a = TAU * (i as f64 + offset) / n as f64;
            let (x, y) = (r * a.cos(), r * a.sin());
            positions.push(Vec3::new(x, y, h(x, y)));
        }
    }
    let mut faces = Vec::with_capacity(6 * rings * rings);
    if rings >= 1 {
        for b in 0..6 {
            faces.push([0, (1 + b) as u32, (1 + (b + 1) % 6) as u32]);
        }
    }
    // Between rings j − 1 and j, walk both by angle, always advancing the ring whose next
    // vertex comes first: each step emits one counter-clockwise triangle.
    let fraction = |k: usize, count: usize, ring: usize| {
        let offset = if ring % 2 == 0 { 0.5 } else { 0.0 };
        (k as f64 + offset) / count as f64
    };
    for j in 2..=rings {
        let (inner, m) = (ring_start[j - 1], 6 * (j - 1));
        let (outer, n) = (ring_start[j], 6 * j);
        let (mut a, mut b) = (0usize, 0usize);
        while a < m || b < n {
            let ia = (inner + a % m) as u32;
            let ob = (outer + b % n) as u32;
            let advance_inner =
                b == n || (a < m && fraction(a + 1, m, j - 1) < fraction(b + 1, n, j));
            if advance_inner {
                faces.push([ia, ob, (inner + (a + 1) % m) as u32]);
                a += 1;
            } else {
                faces.push([ia, ob, (outer + (b + 1) % n) as u32]);
                b += 1;
            }
        }
    }
    build(positions, faces)
}

/// The waving surface z = cos √(x² + y²) over the disk of `radius` (YBS's r(u, v) =
/// [u cos v, u sin v, cos u], u ≤ radius), meshed by [`disk`] with `rings` rings.
pub fn waving_disk(radius: f64, rings: usize) -> TriMesh {
    disk(|x, y| x.hypot(y).cos(), radius, rings)
}

/// A capsule: a cylinder of `radius` and length `length` along z capped by hemispheres.
/// `n` sets the resolution (segments around).
pub fn capsule(radius: f64, length: f64, n: usize) -> TriMesh {
    let n_cap = (n / 4).max(2);
    let n_side = ((length / (TAU * radius / n as f64)).round() as usize).max(1);
    let rows = 2 * n_cap + n_side;
    // Latitude profile: (ring radius, z) for rows 0..=rows, poles excluded by clamping.
    let profile = |j: usize| -> (f64, f64) {
        if j <= n_cap {
            let a = PI / 2.0 * (1.0 - j as f64 / n_cap as f64);
            (radius * a.cos(), -length / 2.0 - radius * a.sin())
        } else if j < n_cap + n_side {
            let t = (j - n_cap) as f64 / n_side as f64;
            (radius, -length / 2.0 + length * t)
        } else {
            let a = PI / 2.0 * ((j - n_cap - n_side) as f64 / n_cap as f64);
            (radius * a.cos(), length / 2.0 + radius * a.sin())
        }
    };
    revolve(rows, n, profile)
}

/// A tablet: a cylinder of `radius` and length `length` along z, closed at both ends by
/// spherical caps of radius `cap_radius` (≥ `radius`) that meet it at an angle, so the two rim
/// circles are sharp convex creases. Spherical and cylindrical parts are Dupin cyclides
/// (e = 0 everywhere); the rims are the only crest lines, returned (like [`pillow_box`]'s
/// creases) as closed ridges through the rim vertices. `n` is the number of segments around;
/// rows along the caps and the side are spaced about as far apart as the vertices of a rim.
pub fn tablet(radius: f64, length: f64, cap_radius: f64, n: usize) -> (TriMesh, FeatureLines) {
    let n = n.max(3);
    let cap_radius = cap_radius.max(radius);
    let spacing = TAU * radius / n as f64;
    // Polar angle of the rim seen from a cap's centre, and that centre's distance inside the rim.
    let rim_angle = (radius / cap_radius).asin();
    let inset = cap_radius * rim_angle.cos();
    let n_cap = ((cap_radius * rim_angle / spacing).round() as usize).max(2);
    let n_side = ((length / spacing).round() as usize).max(1);
    let rows = 2 * n_cap + n_side;
    let half = length / 2.0;
    let profile = |j: usize| -> (f64, f64) {
        if j <= n_cap {
            let a = rim_angle * j as f64 / n_cap as f64;
            (cap_radius * a.sin(), -half + inset - cap_radius * a.cos())
        } else if j < n_cap + n_side {
            (radius, -half + length * (j - n_cap) as f64 / n_side as f64)
        } else {
            let a = rim_angle * (rows - j) as f64 / n_cap as f64;
            (cap_radius * a.sin(), half - inset + cap_radius * a.cos())
        }
    };
    let mesh = revolve(rows, n, profile);
    let lines = [n_cap, n_cap + n_side]
        .into_iter()
        .map(|j| {
            let vertices: Vec<u32> = (0..n).map(|i| (1 + (j - 1) * n + i) as u32).collect();
            let points = vertices.iter().map(|&v| mesh.position(v)).collect();
            FeatureLine {
                locations: vertices.into_iter().map(SurfacePoint::Vertex).collect(),
                length: TAU * radius,
                ..FeatureLine::new(LineKind::Ridge, points, true)
            }
        })
        .collect();
    (mesh, FeatureLines { lines })
}

/// A surface of revolution about z from a profile `(ring radius, z)` sampled at rows 0..=rows,
/// where rows 0 and `rows` must be poles (radius 0).
fn revolve(rows: usize, n: usize, profile: impl Fn(usize) -> (f64, f64)) -> TriMesh {
    let mut positions = vec![Vec3::new(0.0, 0.0, profile(0).1)];
    for j in 1..rows {
        let (r, z) = profile(j);
        for i in 0..n {
            let a = TAU * i as f64 / n as f64;
            positions.push(Vec3::new(r * a.cos(), r * a.sin(), z));
        }
    }
    positions.push(Vec3::new(0.0, 0.0, profile(rows).1));
    let top = (positions.len() - 1) as u32;
    let ring = |j: usize, i: usize| (1 + (j - 1) * n + i % n) as u32;
    let mut faces = Vec::new();
    for i in 0..n {
        faces.push([0, ring(1, i + 1), ring(1, i)]);
    }
    for j in 1..rows - 1 {
        for i in 0..n {
            let (a, b, c, d) = (
                ring(j, i),
                ring(j, i + 1),
                ring(j + 1, i + 1),
                ring(j + 1, i),
            );
            faces.extend([[a, b, c], [a, c, d]]);
        }
    }
    for i in 0..n {
        faces.push([top, ring(rows - 1, i), ring(rows - 1, i + 1)]);
    }
    build(positions, faces)
}

/// A "pillow box": the cube [-half, half]³ whose six faces bulge outward by
/// `bulge · half · (1 - s²)(1 - t²)` (`s`, `t` in [-1, 1] across the face), on an `n` × `n`
/// grid per face (12 n² triangles).
///
/// The faces are curved and meet at the cube's 12 edges in sharp creases, which are returned
/// as exact polylines: ridges through the `n + 1` mesh vertices along each edge, with their
/// vertex locations. Vertices on the creases are shared by the two faces, so the mesh is
/// closed.
pub fn pillow_box(half: f64, bulge: f64, n: usize) -> (TriMesh, FeatureLines) {
    let n = n.max(1);
    // Vertices live on the integer lattice of the cube's surface, coordinates 0..=n.
    let mut ids: std::collections::HashMap<[usize; 3], u32> = std::collections::HashMap::new();
    let mut positions = Vec::new();
    let mut id = |l: [usize; 3], positions: &mut Vec<Vec3>| -> u32 {
        *ids.entry(l).or_insert_with(|| {
            let c = l.map(|i| 2.0 * i as f64 / n as f64 - 1.0);
            let on_face: Vec<usize> = (0..3).filter(|&k| l[k] == 0 || l[k] == n).collect();
            let mut p = Vec3::new(c[0], c[1], c[2]) * half;
            if let [k] = on_face[..] {
                let (s, t) = (c[(k + 1) % 3], c[(k + 2) % 3]);
                p[k] += c[k] * bulge * half * (1.0 - s * s) * (1.0 - t * t);
            }
            positions.push(p);
            (positions.len() - 1) as u32
        })
    };
    let mut faces = Vec::with_capacity(12 * n * n);
    for axis in 0..3 {
        for side in [0, n] {
            // (u, v) span the face so that u × v points outward.
            let (ua, va) = if side == n {
                ((axis + 1) % 3, (axis + 2) % 3)
            } else {
                ((axis + 2) % 3, (axis + 1) % 3)
            };
            let lattice = |i: usize, j: usize| {
                let mut l = [0; 3];
                l[axis] = side;
                l[ua] = i;
                l[va] = j;
                l
            };
            for j in 0..n {
                for i in 0..n {
                    let a = id(lattice(i, j), &mut positions);
                    let b = id(lattice(i + 1, j), &mut positions);
                    let c = id(lattice(i + 1, j + 1), &mut positions);
                    let d = id(lattice(i, j + 1), &mut positions);
                    if (i + j) % 2 == 0 {
                        faces.extend([[a, b, c], [a, c, d]]);
                    } else {
                        faces.extend([[a, b, d], [b, c, d]]);
                    }
                }
            }
        }
    }
    let mut lines = Vec::with_capacity(12);
    for axis in 0..3 {
        for (x, y) in [(0, 0), (n, 0), (0, n), (n, n)] {
            let vertices: Vec<u32> = (0..=n)
                .map(|i| {
                    let mut l = [0; 3];
                    l[axis] = i;
                    l[(axis + 1) % 3] = x;
                    l[(axis + 2) % 3] = y;
                    id(l, &mut positions)
                })
                .collect();
            let points: Vec<Vec3> = vertices.iter().map(|&v| positions[v as usize]).collect();
            lines.push(FeatureLine {
                locations: vertices.into_iter().map(SurfacePoint::Vertex).collect(),
                length: 2.0 * half,
                ..FeatureLine::new(LineKind::Ridge, points, false)
            });
        }
    }
    (build(positions, faces), FeatureLines { lines })
}

/// `mesh` as a scan would give it: every vertex moved along its (area-weighted) normal by a
/// normal number of standard deviation `fraction` of the mean edge length. The numbers come
/// from a hash of the vertex index and `seed` (the same arguments give the same mesh, up to
/// the last bits of the platform's `ln` and `cos`); the faces are kept as they are.
///
/// ```
/// # fn main() -> crestline::Result<()> {
/// let clean = crestline::shapes::icosphere(1.0, 3);
/// let noisy = crestline::shapes::with_normal_noise(&clean, 0.1, 7)?;
/// assert_eq!(noisy.faces(), clean.faces());
/// assert_ne!(noisy.positions(), clean.positions());
/// # Ok(())
/// # }
/// ```
///
/// # Errors
/// [`crate::Error::InvalidInput`] when `fraction` is negative or not finite.
pub fn with_normal_noise(mesh: &TriMesh, fraction: f64, seed: u64) -> crate::Result<TriMesh> {
    if !(fraction.is_finite() && fraction >= 0.0) {
        return Err(crate::Error::InvalidInput(format!(
            "noise must be a fraction of the mean edge >= 0, got {fraction}"
        )));
    }
    let sigma = fraction * crate::mesh::mean_edge_length(mesh);
    let normals = crate::mesh::vertex_normals_area(mesh);
    let positions = (mesh.positions().iter().zip(&normals).enumerate())
        .map(|(i, (p, n))| p + n * (sigma * standard_normal(i, seed)))
        .collect();
    mesh.with_positions(positions)
}

/// A standard normal number for `(i, seed)` (Box–Muller on two hashed uniforms).
fn standard_normal(i: usize, seed: u64) -> f64 {
    let uniform = |k: u64| {
        let mut z = (i as u64)
            .wrapping_mul(2)
            .wrapping_add(k)
            .wrapping_add(seed.wrapping_mul(0x1_0000_0001))
            .wrapping_mul(0x9E37_79B9_7F4A_7C15);
        z = (z ^ (z >> 31)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z ^= z >> 29;
        ((z >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    };
    (-2.0 * uniform(0).ln()).sqrt() * (TAU * uniform(1)).cos()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn outward(m: &TriMesh, center: Vec3) -> bool {
        let n = crate::mesh::face_normals(m);
        (0..m.num_faces()).all(|f| {
            let [a, b, c] = m.triangle(f);
            n[f].dot(&((a + b + c) / 3.0 - center)) > 0.0
        })
    }

    #[test]
    fn closed_shapes_are_closed_and_outward() {
        for (m, chi) in [
            (icosphere(2.0, 2), 2),
            (ellipsoid(3.0, 2.0, 1.0, 2), 2),
            (torus(3.0, 1.0, 24, 12), 0),
            (capsule(1.0, 2.0, 16), 2),
            (tablet(1.0, 2.0, 1.5, 16).0, 2),
        ] {
            let info = m.info();
            assert!(info.closed, "{info}");
            assert_eq!(info.euler_characteristic, chi);
            assert_eq!(info.non_manifold_vertices, 0);
        }
        assert!(outward(&icosphere(1.0, 1), Vec3::zeros()));
        assert!(outward(&ellipsoid(3.0, 2.0, 1.0, 1), Vec3::zeros()));
        assert!(outward(&capsule(1.0, 2.0, 12), Vec3::zeros()));
        assert!(outward(&tablet(1.0, 2.0, 1.5, 12).0, Vec3::zeros()));
    }

    #[test]
    fn pillow_box_is_closed_with_creases_on_its_vertices() {
        let (m, lines) = pillow_box(1.0, 0.2, 6);
        let info = m.info();
        assert!(info.closed, "{info}");
        assert_eq!(info.euler_characteristic, 2);
        assert_eq!(info.faces, 12 * 36);
        assert!(outward(&m, Vec3::zeros()));
        assert_eq!(lines.lines.len(), 12);
        for line in &lines.lines {
            assert_eq!(line.points.len(), 7);
            for (p, loc) in line.points.iter().zip(&line.locations) {
                let SurfacePoint::Vertex(v) = *loc else {
                    panic!("{loc:?}")
                };
                assert_eq!(m.position(v), *p);
                // On a cube edge: two coordinates at ±1.
                assert!(p.iter().filter(|c| c.abs() == 1.0).count() >= 2);
            }
        }
        // The middle of a face bulges out by `bulge`.
        let top = m.positions().iter().map(|p| p.z).fold(f64::MIN, f64::max);
        assert!((top - 1.2).abs() < 1e-12);
    }

    #[test]
    fn tablet_rims_are_its_vertices_on_both_surfaces() {
        let (r, len, cap) = (1.0, 2.0, 1.5);
        let (m, lines) = tablet(r, len, cap, 24);
        assert!(m.info().closed);
        assert_eq!(lines.lines.len(), 2);
        let sink = cap - (cap * cap - r * r).sqrt();
        for (line, z) in lines.lines.iter().zip([-1.0, 1.0]) {
            assert!(line.closed);
            assert_eq!(line.points.len(), 24);
            for (p, loc) in line.points.iter().zip(&line.locations) {
                let SurfacePoint::Vertex(v) = *loc else {
                    panic!("{loc:?}")
                };
                assert_eq!(m.position(v), *p);
                assert!((p.x.hypot(p.y) - r).abs() < 1e-12 && (p.z - z).abs() < 1e-12);
            }
        }
        // Every vertex lies on the cylinder or on one of the two cap spheres.
        let centre = len / 2.0 - (cap - sink);
        for p in m.positions() {
            let on_side = (p.x.hypot(p.y) - r).abs() < 1e-12 && p.z.abs() <= len / 2.0 + 1e-12;
            let on_cap = |c: f64| ((p - Vec3::new(0.0, 0.0, c)).norm() - cap).abs() < 1e-12;
            assert!(on_side || on_cap(centre) || on_cap(-centre), "{p:?}");
        }
        let top = m.positions().iter().map(|p| p.z).fold(f64::MIN, f64::max);
        assert!((top - (len / 2.0 + sink)).abs() < 1e-12);
    }

    #[test]
    fn open_shapes_have_boundaries() {
        let c = cylinder(1.0, 2.0, 16, 4).info();
        assert_eq!(c.boundary_loops, 2);
        assert_eq!(c.boundary_edges, 32);
        let w = waving_surface(5.0, 10).info();
        assert_eq!(w.boundary_loops, 1);
        assert_eq!(w.faces, 200);
        let d = waving_disk(5.0, 7);
        let info = d.info();
        assert_eq!(info.faces, 6 * 7 * 7);
        assert_eq!(info.vertices, 1 + 3 * 7 * 8);
        assert_eq!((info.boundary_loops, info.euler_characteristic), (1, 1));
        assert_eq!(info.non_manifold_vertices, 0);
        let up = crate::mesh::face_normals(&disk(|_, _| 0.0, 1.0, 5));
        assert!(up.iter().all(|n| (n - Vec3::z()).norm() < 1e-12));
    }
}
