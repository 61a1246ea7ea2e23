//! Enhanced adjacent-normal cubic fitting of Yoshizawa, Belyaev and Seidel, *Fast and Robust
//! Detection of Crest Lines on Meshes*, SPM 2005 (YBS), section "Estimating Surface
//! Derivatives", eqs. 2 and 3, after the adjacent-normal cubic approximation of Goldfeather
//! and Interrante (ACM TOG 2004).
//!
//! **Steps.**
//! 1. Pre-smoothing: each vertex p moves to p', the mean of the centroids of its triangles
//!    ([`presmoothed_positions`]). Boundary vertices stay where they are: their triangles lie
//!    on one side only, so p' would slide a third of an edge into the surface.
//! 2. Normals of the smoothed mesh M' by Max's weights (exact for vertices on a sphere).
//! 3. In the tangent frame (x, y, n) of p' (n its normal), the cubic of YBS eq. 2,
//!    `h(x, y) = ½(b₀x² + 2b₁xy + b₂y²) + ⅙(c₀x³ + 3c₁x²y + 3c₂xy² + c₃y³)`,
//!    is fitted by least squares to the k-ring neighbours q of p' whose normal makes an acute
//!    angle with n. Each neighbour gives three equations: its height `h(x_q, y_q) = z_q` and,
//!    from its normal `(a, b, c)` in the frame, `h_x = −a/c` and `h_y = −b/c` (the graph of h
//!    has normal ∝ (−h_x, −h_y, 1)), taken as `c h_x = −a` and `c h_y = −b` (*Slopes near
//!    the horizon*, below). Coordinates are divided by the RMS neighbour distance
//!    first, which balances the two kinds of equation and makes the fit exactly
//!    scale-invariant; the 7×7 normal equations are accumulated and solved by Cholesky on the stack.
//! 4. With n outward, a convex surface has h ≈ −x²/(2r); the crate's convention (k > 0 where
//!    the surface bends away from the normal) therefore takes the Weingarten matrix
//!    `W = −[[b₀, b₁], [b₁, b₂]]` (the metric is the identity to second order at the
//!    origin). Its eigen-pairs are the principal curvatures and directions (mapped back to
//!    3D by the frame).
//! 5. Extremality along a unit tangent t = (t₁, t₂): the shape operator of the graph is
//!    `Hess h + O(|x|²)` near the origin (the gradient of h vanishes there), so
//!    `d k/d t = tᵀ (∂_t Hess h) t = h_xxx t₁³ + 3h_xxy t₁²t₂ + 3h_xyy t₁t₂² + h_yyy t₂³
//!    = c₀t₁³ + 3c₁t₁²t₂ + 3c₂t₁t₂² + c₃t₂³`,
//!    negated for the crate's sign convention ([`LocalCubic::extremality`]).
//!    **YBS eq. 3 as printed**, `(t₁², t₂²) [[c₀, c₁], [c₂, c₃]] (t₁, t₂)ᵀ =
//!    c₀t₁³ + c₁t₁²t₂ + c₂t₁t₂² + c₃t₂³`, lacks the factors 3 on the mixed terms (both
//!    transcriptions agree). It equals the derivation above only when the frame's axes are
//!    the principal directions; in an arbitrary tangent frame it is not invariant under a
//!    rotation of the frame. We use the derived form.
//! 6. The values are assigned to the original vertex p (YBS do the same).
//!
//! **Boundaries.** A boundary neighbour's Max normal comes from half a fan and is tilted by
//! O(h); through the slope equations that tilt would reach the cubic coefficients as
//! δc ≈ δn/h², so boundary (and non-manifold) neighbours contribute their height equation
//! only. A boundary vertex's own fit is a one-sided extrapolation with a tilted frame, so by
//! default ([`CubicFitOptions::boundary_from_interior`]) it takes the mean curvature tensor
//! of its interior neighbours instead. Measured on a unit hemisphere (1-ring, no
//! pre-smoothing) this brings the boundary vertices' k error from 2.3 to 0.002 and that of
//! their neighbours from 0.2 to 0.003. With pre-smoothing on, the two rings next to a
//! boundary remain biased (k errors up to ≈ 0.4 on the unit hemisphere): interior vertices
//! shrink towards the centre of curvature while boundary vertices cannot follow without
//! sliding sideways (both choices were measured; keeping them fixed was the better one).
//!
//! **Slopes near the horizon.** YBS take neighbours whose normal makes an acute angle with
//! n, however close to 90°: across a sharp crease, rings of 4 and more reach faces whose
//! normal `(a, b, c)` has c near 0, and the slope `−a/c` of such a neighbour is huge, and
//! wrong by `δn/c²` for a normal error δn. As printed, the fit follows those equations:
//! fandisk with 4 rings had 258 vertices with |k| > 1000 (up to 9·10⁷), 6 rings 580. Each
//! slope equation is therefore multiplied by c, `c h_x = −a`: the same equation, whose
//! residual is now the error in the normal's components rather than in the slope, so a
//! neighbour weighs in as much as its normal says about the surface over the tangent
//! plane (nothing, at the horizon). Where the normals are close to n (c ≈ 1: smooth
//! surfaces, small rings) the fit is the paper's to within 1 − c. Measured: fandisk rings
//! 4 and 6, no vertex with |k| > 1000 (`tests/suite/curvature_robust.rs`).
//!
//! **Fallbacks** (all counted in [`Curvature::fallback_vertices`], never NaN, never a panic):
//! fewer than seven equations or an ill-conditioned system in the requested k-ring → the ring
//! grows one level at a time up to `max(rings, max_rings)`; still failing (tiny component) →
//! a quadratic fit (b only, e = 0) on what is there; nothing usable at all or an
//! unreferenced vertex → zero curvature and extremality in an arbitrary tangent frame.
//!
//! **Accuracy and limits** (measured, see `BENCHMARKS.md`). The extremality error is set by
//! the vertex normals: the slope equations carry a normal error δn into the cubic terms as
//! δc ≈ δn/h². With exact normals the fitted e converges like O(h²); with Max normals, which
//! are O(h²) accurate on regular meshes and O(h) on irregular or anisotropic ones, e has an
//! O(1) error floor on regular meshes and grows like O(1/h) on irregular ones (YBS report
//! max-norm errors of 0.48 and 0.56 on their waving surface). The pre-smoothing is an
//! umbrella-Laplacian step (p' = p + ⅔(q̄ − p) on a closed fan) whose normal displacement
//! depends on valence and edge lengths: it biases k by O(h²) on regular meshes but by O(1)
//! relative amounts where the valence alternates (e.g. 4/8 checkerboard grids), and it stops
//! e from converging. The per-vertex scratch is one reusable buffer per rayon job
//! (`map_init`); the normal equations live on the stack.

use rayon::prelude::*;

use super::{Curvature, VertexEstimate, collect_estimates, symmetric_eigen_2x2, tangent_frame};
use crate::error::{Error, Result};
use crate::mesh::{Topology, TriMesh, Vec3, VertexKind, vertex_normals_max};

/// Largest k-ring the options accept.
pub const MAX_RINGS: usize = 8;

/// Options of [`cubic_fit()`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CubicFitOptions {
    /// k of the k-ring neighbourhood the cubic is fitted to (YBS use 1 to 4; larger rings
    /// smooth more). Must be in `1..=MAX_RINGS`.
    ///
    /// Default: 1.
    pub rings: usize,
    /// The ring may grow up to `max(rings, max_rings)` levels when the requested one has
    /// fewer than three usable neighbours or an ill-conditioned fit (boundary corners, tiny
    /// components). At most [`MAX_RINGS`].
    ///
    /// Default: 4.
    pub max_rings: usize,
    /// Whether to run YBS's pre-smoothing p → p' (mean of the adjacent triangle centroids)
    /// before the fit. Turning it off fits the raw mesh (with Max normals of the raw mesh).
    ///
    /// Default: `true`.
    pub presmooth: bool,
    /// Whether a boundary vertex takes the mean curvature tensor of its interior neighbours
    /// (restricted to its own tangent plane) instead of its own one-sided fit, which is an
    /// extrapolation from half a ring with a tilted normal. Its extremalities are the
    /// neighbours' means, re-signed to the new directions. A boundary vertex without an
    /// interior neighbour keeps its own fit.
    ///
    /// Default: `true`.
    pub boundary_from_interior: bool,
}

impl CubicFitOptions {
    /// The default options (see each field).
    pub const DEFAULT: Self = CubicFitOptions {
        rings: 1,
        max_rings: 4,
        presmooth: true,
        boundary_from_interior: true,
    };

    /// Sets [`CubicFitOptions::rings`].
    pub fn with_rings(mut self, rings: usize) -> Self {
        self.rings = rings;
        self
    }

    /// Sets [`CubicFitOptions::max_rings`].
    pub fn with_max_rings(mut self, max_rings: usize) -> Self {
        self.max_rings = max_rings;
        self
    }

    /// Sets [`CubicFitOptions::presmooth`].
    pub fn with_presmooth(mut self, presmooth: bool) -> Self {
        self.presmooth = presmooth;
        self
    }

    /// Sets [`CubicFitOptions::boundary_from_interior`].
    pub fn with_boundary_from_interior(mut self, on: bool) -> Self {
        self.boundary_from_interior = on;
        self
    }

    fn validate(&self) -> Result<()> {
        if !(1..=MAX_RINGS).contains(&self.rings) || self.max_rings > MAX_RINGS {
            return Err(Error::InvalidInput(format!(
                "cubic fit rings = {}, max_rings = {}: rings must be in 1..={MAX_RINGS} and \
                 max_rings at most {MAX_RINGS}",
                self.rings, self.max_rings
            )));
        }
        Ok(())
    }
}

impl Default for CubicFitOptions {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// The local height function of YBS eq. 2,
/// `h(x, y) = ½(b₀x² + 2b₁xy + b₂y²) + ⅙(c₀x³ + 3c₁x²y + 3c₂xy² + c₃y³)`,
/// over the tangent plane of a vertex, height along its (outward) normal.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct LocalCubic {
    /// `[b₀, b₁, b₂]` = `[h_xx, h_xy, h_yy]` at the origin.
    pub b: [f64; 3],
    /// `[c₀, c₁, c₂, c₃]` = `[h_xxx, h_xxy, h_xyy, h_yyy]` at the origin.
    pub c: [f64; 4],
}

impl LocalCubic {
    /// `h(x, y)`.
    pub fn height(&self, x: f64, y: f64) -> f64 {
        let [b0, b1, b2] = self.b;
        let [c0, c1, c2, c3] = self.c;
        0.5 * (b0 * x * x + 2.0 * b1 * x * y + b2 * y * y)
            + (c0 * x * x * x + 3.0 * c1 * x * x * y + 3.0 * c2 * x * y * y + c3 * y * y * y) / 6.0
    }

    /// `(h_x, h_y)` at `(x, y)`.
    pub fn gradient(&self, x: f64, y: f64) -> [f64; 2] {
        let [b0, b1, b2] = self.b;
        let [c0, c1, c2, c3] = self.c;
        [
            b0 * x + b1 * y + 0.5 * c0 * x * x + c1 * x * y + 0.5 * c2 * y * y,
            b1 * x + b2 * y + 0.5 * c1 * x * x + c2 * x * y + 0.5 * c3 * y * y,
        ]
    }

    /// Principal curvatures at the origin in the crate's convention, with the unit principal
    /// direction of `k_max` in the (x, y) frame: `(k_max, k_min, t_max)`; the direction of
    /// `k_min` is `(−t_max[1], t_max[0])`.
    pub fn principal(&self) -> (f64, f64, [f64; 2]) {
        let [b0, b1, b2] = self.b;
        // Outward normal: a convex cap has h ≈ −x²/(2r), hence W = −Hess h.
        symmetric_eigen_2x2(-b0, -b1, -b2)
    }

    /// Derivative at the origin of the principal curvature whose unit direction is `t`,
    /// along `t` (crate convention, odd in `t`): `−(c₀t₁³ + 3c₁t₁²t₂ + 3c₂t₁t₂² + c₃t₂³)`.
    pub fn extremality(&self, t: [f64; 2]) -> f64 {
        let [c0, c1, c2, c3] = self.c;
        let [t1, t2] = t;
        -(c0 * t1 * t1 * t1 + 3.0 * c1 * t1 * t1 * t2 + 3.0 * c2 * t1 * t2 * t2 + c3 * t2 * t2 * t2)
    }
}

/// One fitting sample in the local frame: position and, when trusted, unit normal.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample {
    /// `(x, y, z)`: tangent coordinates and height.
    pub position: Vec3,
    /// Unit normal in the same frame with a positive `z` component; `None` when the
    /// sample's normal is not trusted (a boundary vertex's one-sided normal): the sample then
    /// gives its height equation only.
    pub normal: Option<Vec3>,
}

/// The slope equations `h_x = −a/c`, `h_y = −b/c` of a sample's normal `(a, b, c)`, as
/// `(c, −a, −b)`: each is taken multiplied by c, `c h_x = −a` (see the module docs, *Slopes
/// near the horizon*).
#[inline]
fn slopes(normal: Option<Vec3>) -> Option<(f64, f64, f64)> {
    // Of the unit normal: the weight `c` is a cosine whatever length the caller's normal has.
    let n = normal?.try_normalize(0.0)?;
    (n.z > 0.0).then_some((n.z, -n.x, -n.y))
}

/// Smallest acceptable ratio between the smallest and the largest diagonal entry of the
/// Cholesky factor of the (scaled) normal equations: below it the system's condition number
/// exceeds ~1e12 and the coefficients are dominated by rounding.
const MIN_PIVOT_RATIO: f64 = 1e-6;

/// Normal equations `AᵀA x = Aᵀb` of an `N`-unknown least-squares problem, accumulated row
/// by row on the stack (upper triangle only; the rows here have structural zeros that the
/// update skips).
struct NormalEquations<const N: usize> {
    ata: [[f64; N]; N],
    atb: [f64; N],
}

// Index loops mirror the textbook recurrences (rank-1 update, Cholesky, substitutions).
#[allow(clippy::needless_range_loop)]
impl<const N: usize> NormalEquations<N> {
    fn new() -> Self {
        NormalEquations {
            ata: [[0.0; N]; N],
            atb: [0.0; N],
        }
    }

    // Inlined so that the rows' constant zeros fold away and the loops unroll.
    #[inline(always)]
    fn add_row(&mut self, row: &[f64; N], value: f64) {
        for i in 0..N {
            let ri = row[i];
            if ri == 0.0 {
                continue;
            }
            for j in i..N {
                self.ata[i][j] += ri * row[j];
            }
            self.atb[i] += ri * value;
        }
    }

    /// Solves by Cholesky factorisation; `None` when the matrix is not positive definite or
    /// its factor's diagonal spans more than `1/MIN_PIVOT_RATIO` (ill-conditioned).
    fn solve(&self) -> Option<[f64; N]> {
        // Upper-triangular factor U with UᵀU = AᵀA, built in place of the upper triangle.
        let mut u = self.ata;
        let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
        for i in 0..N {
            let mut d = u[i][i];
            for k in 0..i {
                d -= u[k][i] * u[k][i];
            }
            if d.is_nan() || d <= 0.0 {
                return None;
            }
            let d = d.sqrt();
            u[i][i] = d;
            lo = lo.min(d);
            hi = hi.max(d);
            for j in i + 1..N {
                let mut x = u[i][j];
                for k in 0..i {
                    x -= u[k][i] * u[k][j];
                }
                u[i][j] = x / d;
            }
        }
        if lo.is_nan() || lo <= MIN_PIVOT_RATIO * hi {
            return None;
        }
        // Uᵀ y = b, then U x = y.
        let mut y = self.atb;
        for i in 0..N {
            for k in 0..i {
                y[i] -= u[k][i] * y[k];
            }
            y[i] /= u[i][i];
        }
        for i in (0..N).rev() {
            for k in i + 1..N {
                y[i] -= u[i][k] * y[k];
            }
            y[i] /= u[i][i];
        }
        y.iter().all(|v| v.is_finite()).then_some(y)
    }
}

/// RMS tangent distance of the samples (the fit's length unit), or `None` if zero.
fn sample_scale(samples: &[Sample]) -> Option<f64> {
    if samples.is_empty() {
        return None;
    }
    let mean_sq = samples
        .iter()
        .map(|s| s.position.x * s.position.x + s.position.y * s.position.y)
        .sum::<f64>()
        / samples.len() as f64;
    let scale = mean_sq.sqrt();
    (scale > 0.0 && scale.is_finite()).then_some(scale)
}

/// Least-squares fit of YBS eq. 2 to samples given in the local frame (positions relative to
/// the origin vertex): each sample contributes its height and, when it has one, its normal
/// (adjacent-normal method). Needs at least seven equations from samples in enough
/// directions (three samples with normals, not on a line); `None` when the system is
/// singular or ill-conditioned.
pub fn fit_cubic(samples: &[Sample]) -> Option<LocalCubic> {
    let equations: usize = samples
        .iter()
        .map(|q| if slopes(q.normal).is_some() { 3 } else { 1 })
        .sum();
    if equations < 7 {
        return None;
    }
    let s = sample_scale(samples)?;
    let mut eq = NormalEquations::<7>::new();
    for q in samples {
        let (x, y, z) = (q.position.x / s, q.position.y / s, q.position.z / s);
        let (xx, xy, yy) = (x * x, x * y, y * y);
        eq.add_row(
            &[
                0.5 * xx,
                xy,
                0.5 * yy,
                xx * x / 6.0,
                0.5 * xx * y,
                0.5 * x * yy,
                yy * y / 6.0,
            ],
            z,
        );
        if let Some((c, a, b)) = slopes(q.normal) {
            eq.add_row(&[x, y, 0.0, 0.5 * xx, xy, 0.5 * yy, 0.0].map(|t| c * t), a);
            eq.add_row(&[0.0, x, y, 0.0, 0.5 * xx, xy, 0.5 * yy].map(|t| c * t), b);
        }
    }
    let t = eq.solve()?;
    // Undo the scaling: b scales like 1/length, c like 1/length².
    let s2 = s * s;
    Some(LocalCubic {
        b: [t[0] / s, t[1] / s, t[2] / s],
        c: [t[3] / s2, t[4] / s2, t[5] / s2, t[6] / s2],
    })
}

/// Least-squares fit of the quadratic part of eq. 2 only (`c = 0`), the fallback when the
/// cubic is under-determined; needs two samples in different directions (one sample's
/// height equation is a combination of its two slope equations).
pub fn fit_quadratic(samples: &[Sample]) -> Option<LocalCubic> {
    let s = sample_scale(samples)?;
    let mut eq = NormalEquations::<3>::new();
    for q in samples {
        let (x, y, z) = (q.position.x / s, q.position.y / s, q.position.z / s);
        eq.add_row(&[0.5 * x * x, x * y, 0.5 * y * y], z);
        if let Some((c, a, b)) = slopes(q.normal) {
            eq.add_row(&[c * x, c * y, 0.0], a);
            eq.add_row(&[0.0, c * x, c * y], b);
        }
    }
    let t = eq.solve()?;
    Some(LocalCubic {
        b: [t[0] / s, t[1] / s, t[2] / s],
        c: [0.0; 4],
    })
}

/// YBS's pre-smoothing: each interior (or non-manifold) vertex moves to the mean of the
/// centroids of its triangles; boundary and unreferenced vertices stay.
pub fn presmoothed_positions(mesh: &TriMesh) -> Vec<Vec3> {
    let topo = mesh.topology();
    (0..mesh.num_vertices() as u32)
        .into_par_iter()
        .map(|v| {
            let faces = topo.vertex_faces(v);
            if faces.is_empty() || topo.vertex_kind(v) == VertexKind::Boundary {
                return mesh.position(v);
            }
            let sum: Vec3 = faces
                .iter()
                .map(|&f| {
                    let [a, b, c] = mesh.triangle(f as usize);
                    a + b + c
                })
                .sum();
            sum / (3.0 * faces.len() as f64)
        })
        .collect()
}

/// Reusable per-job scratch: the k-ring of the current vertex, level by level, and the
/// samples built from it.
#[derive(Default)]
struct Scratch {
    /// Ring vertices (the centre excluded), in BFS order.
    ring: Vec<u32>,
    /// `ring[level_ends[l - 1]..level_ends[l]]` is level l + 1 (`level_ends[0]` ends level 1).
    level_ends: Vec<usize>,
    samples: Vec<Sample>,
}

impl Scratch {
    fn start(&mut self) {
        self.ring.clear();
        self.level_ends.clear();
    }

    /// Adds the next BFS level around `centre`; false when nothing new was reached.
    fn grow(&mut self, topo: &Topology, centre: u32) -> bool {
        let levels = self.level_ends.len();
        let before = self.ring.len();
        // Level l is ring[level_start(l)..level_ends[l - 1]].
        let level_start = |l: usize| if l <= 1 { 0 } else { self.level_ends[l - 2] };
        if levels == 0 {
            self.ring.extend(topo.neighbors(centre));
        } else {
            // Neighbours of level L are the centre or lie in levels L − 1, L and L + 1, so
            // only that window needs searching.
            let window = level_start(levels - 1);
            for i in level_start(levels)..before {
                let u = self.ring[i];
                for w in topo.neighbors(u) {
                    if w != centre && !self.ring[window..].contains(&w) {
                        self.ring.push(w);
                    }
                }
            }
        }
        self.level_ends.push(self.ring.len());
        self.ring.len() > before
    }
}

/// Principal curvatures and extremalities of every vertex by the enhanced adjacent-normal
/// cubic fit (YBS eqs. 2, 3); see the module docs for the steps, conventions and fallbacks.
/// Runs in parallel.
///
/// # Errors
/// [`Error::InvalidInput`] when the options are out of range.
pub fn cubic_fit(mesh: &TriMesh, options: &CubicFitOptions) -> Result<Curvature> {
    options.validate()?;
    let smoothed;
    let fitted = if options.presmooth {
        smoothed = mesh.with_positions(presmoothed_positions(mesh))?;
        &smoothed
    } else {
        mesh
    };
    let normals = vertex_normals_max(fitted);
    let max_rings = options.rings.max(options.max_rings);
    let (mut curvature, mut fallback) =
        collect_estimates(mesh.num_vertices(), Scratch::default, |scratch, v| {
            fit_vertex(fitted, &normals, v, options.rings, max_rings, scratch).sanitized()
        });
    if options.boundary_from_interior {
        let topo = mesh.topology();
        let borrowed: Vec<(usize, VertexEstimate)> = (0..mesh.num_vertices() as u32)
            .into_par_iter()
            .filter(|&v| topo.vertex_kind(v) == VertexKind::Boundary)
            .filter_map(|v| {
                borrow_from_interior(topo, &curvature, &fallback, v).map(|e| (v as usize, e))
            })
            .collect();
        for (v, estimate) in borrowed {
            estimate.store(&mut curvature, v);
            fallback[v] = false;
        }
        curvature.fallback_vertices = fallback.iter().filter(|&&f| f).count();
    }
    Ok(curvature)
}

/// The mean curvature tensor `k_max d_max d_maxᵀ + k_min d_min d_minᵀ` of the interior
/// neighbours of `v` (that were estimated normally), restricted to the tangent plane of `v`,
/// with their extremalities averaged after re-signing them to the resulting directions.
fn borrow_from_interior(
    topo: &Topology,
    c: &Curvature,
    fallback: &[bool],
    v: u32,
) -> Option<VertexEstimate> {
    let interior = || {
        topo.neighbors(v)
            .map(|q| q as usize)
            .filter(|&q| topo.vertex_kind(q as u32) == VertexKind::Interior && !fallback[q])
    };
    let mut tensor = nalgebra::Matrix3::<f64>::zeros();
    let mut count = 0usize;
    for q in interior() {
        tensor += c.dir_max[q] * c.dir_max[q].transpose() * c.k_max[q]
            + c.dir_min[q] * c.dir_min[q].transpose() * c.k_min[q];
        count += 1;
    }
    if count == 0 {
        return None;
    }
    tensor /= count as f64;
    let (u, w, n) = tangent_frame(c.normals[v as usize]);
    let (tu, tw) = (tensor * u, tensor * w);
    let (k_max, k_min, t) = symmetric_eigen_2x2(u.dot(&tu), u.dot(&tw), w.dot(&tw));
    let dir_max = u * t[0] + w * t[1];
    let dir_min = w * t[0] - u * t[1];
    let (mut e_max, mut e_min) = (0.0, 0.0);
    for q in interior() {
        e_max += c.e_max[q] * c.dir_max[q].dot(&dir_max).signum();
        e_min += c.e_min[q] * c.dir_min[q].dot(&dir_min).signum();
    }
    Some(
        VertexEstimate {
            k_max,
            k_min,
            dir_max,
            dir_min,
            e_max: e_max / count as f64,
            e_min: e_min / count as f64,
            normal: n,
            // Borrowed values are estimates, not fallbacks (as for the shape operator).
            fallback: false,
        }
        .sanitized(),
    )
}

/// The estimate at vertex `v` of the (smoothed) mesh `mesh` with normals `normals`.
fn fit_vertex(
    mesh: &TriMesh,
    normals: &[Vec3],
    v: u32,
    rings: usize,
    max_rings: usize,
    scratch: &mut Scratch,
) -> VertexEstimate {
    let normal = normals[v as usize];
    if normal == Vec3::zeros() {
        return VertexEstimate::fallback(normal);
    }
    let frame = tangent_frame(normal);
    let topo = mesh.topology();
    let origin = mesh.position(v);
    scratch.start();
    for level in 1..=max_rings {
        if !scratch.grow(topo, v) {
            break;
        }
        if level < rings {
            continue;
        }
        collect_samples(mesh, normals, origin, frame, scratch);
        if let Some(cubic) = fit_cubic(&scratch.samples) {
            return estimate_from(&cubic, frame, level > rings);
        }
    }
    // Whatever ring we reached: the quadratic part only.
    collect_samples(mesh, normals, origin, frame, scratch);
    match fit_quadratic(&scratch.samples) {
        Some(quadratic) => estimate_from(&quadratic, frame, true),
        None => VertexEstimate::fallback(normal),
    }
}

/// Samples of the current ring in the frame: neighbours whose normal is at an acute angle
/// with the centre's (YBS: obtuse ones are dropped); boundary neighbours without their normal.
fn collect_samples(
    mesh: &TriMesh,
    normals: &[Vec3],
    origin: Vec3,
    (u, w, n): (Vec3, Vec3, Vec3),
    scratch: &mut Scratch,
) {
    scratch.samples.clear();
    for &q in &scratch.ring {
        let nq = normals[q as usize];
        let c = nq.dot(&n);
        if c.is_nan() || c <= 0.0 {
            continue;
        }
        let d = mesh.position(q) - origin;
        // A boundary vertex's normal comes from half a fan and is tilted by O(h); the slope
        // equations would pass that straight into the cubic coefficients (δc ≈ δn/h²), so
        // such a neighbour contributes its height only.
        let trusted = !mesh.topology().is_boundary_vertex(q);
        scratch.samples.push(Sample {
            position: Vec3::new(d.dot(&u), d.dot(&w), d.dot(&n)),
            normal: trusted.then(|| Vec3::new(nq.dot(&u), nq.dot(&w), c)),
        });
    }
}

fn estimate_from(
    cubic: &LocalCubic,
    (u, w, n): (Vec3, Vec3, Vec3),
    fallback: bool,
) -> VertexEstimate {
    let (k_max, k_min, t) = cubic.principal();
    let t_min = [-t[1], t[0]];
    VertexEstimate {
        k_max,
        k_min,
        dir_max: u * t[0] + w * t[1],
        dir_min: u * t_min[0] + w * t_min[1],
        e_max: cubic.extremality(t),
        e_min: cubic.extremality(t_min),
        normal: n,
        fallback,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ring_samples(cubic: &LocalCubic, radius: f64, n: usize) -> Vec<Sample> {
        (0..n)
            .map(|i| {
                let a = 0.3 + std::f64::consts::TAU * i as f64 / n as f64;
                let r = radius * (1.0 + 0.2 * (i % 3) as f64);
                let (x, y) = (r * a.cos(), r * a.sin());
                let [hx, hy] = cubic.gradient(x, y);
                Sample {
                    position: Vec3::new(x, y, cubic.height(x, y)),
                    normal: Some(Vec3::new(-hx, -hy, 1.0).normalize()),
                }
            })
            .collect()
    }

    #[test]
    fn fit_recovers_an_exact_cubic() {
        let exact = LocalCubic {
            b: [0.7, -0.2, -1.3],
            c: [0.4, -0.9, 0.25, 1.1],
        };
        for radius in [1e-3, 0.1, 10.0] {
            let fit = fit_cubic(&ring_samples(&exact, radius, 6)).unwrap();
            for i in 0..3 {
                assert!((fit.b[i] - exact.b[i]).abs() < 1e-8, "{radius}: {fit:?}");
            }
            for i in 0..4 {
                assert!((fit.c[i] - exact.c[i]).abs() < 1e-6, "{radius}: {fit:?}");
            }
        }
        // Three samples are enough (9 equations for 7 unknowns); two are not.
        assert!(fit_cubic(&ring_samples(&exact, 0.1, 3)).is_some());
        assert!(fit_cubic(&ring_samples(&exact, 0.1, 2)).is_none());
        // One sample constrains only the bending along its own direction (its height
        // equation is ½ of x·h_x + y·h_y): the quadratic needs two.
        let three = ring_samples(&exact, 0.1, 3);
        assert!(fit_quadratic(&three[..1]).is_none());
        assert!(fit_quadratic(&three[..2]).is_some());
        // Two samples on one line through the origin see one direction only.
        assert!(fit_quadratic(&ring_samples(&exact, 0.1, 2)).is_none());
    }

    #[test]
    fn sphere_cap_sign_convention() {
        // Sphere of radius r seen from its outward normal: h = −x²/(2r) − ... so b = −1/r and
        // the crate's k = +1/r.
        let r = 2.0;
        let cap = LocalCubic {
            b: [-1.0 / r, 0.0, -1.0 / r],
            c: [0.0; 4],
        };
        let (k_max, k_min, _) = cap.principal();
        assert!((k_max - 0.5).abs() < 1e-15 && (k_min - 0.5).abs() < 1e-15);
    }

    #[test]
    fn extremality_is_invariant_under_a_rotation_of_the_frame() {
        // The same surface in a frame turned by α: x = cos α x' − sin α y', ... The third
        // derivative tensor transforms as a symmetric 3-tensor, and D³h[t, t, t] is a scalar,
        // so e must not depend on α — with the factors 3 of our formula. YBS eq. 3 as
        // printed (no factors 3) fails this.
        let exact = LocalCubic {
            b: [0.7, -0.2, -1.3],
            c: [0.4, -0.9, 0.25, 1.1],
        };
        let alpha: f64 = 0.61;
        let (ca, sa) = (alpha.cos(), alpha.sin());
        // Sample the rotated surface h'(x', y') = h(R(x', y')) and fit it.
        let rotated: Vec<Sample> = ring_samples(&exact, 0.1, 8)
            .into_iter()
            .map(|s| {
                // Frame rotation by −α maps world (x, y) to (x', y').
                let p = s.position;
                let n = s.normal;
                let rot = |v: Vec3| Vec3::new(ca * v.x + sa * v.y, -sa * v.x + ca * v.y, v.z);
                Sample {
                    position: rot(p),
                    normal: n.map(rot),
                }
            })
            .collect();
        let fit = fit_cubic(&rotated).unwrap();
        let (k1, k2, t) = exact.principal();
        let (k1r, k2r, tr) = fit.principal();
        assert!((k1 - k1r).abs() < 1e-8 && (k2 - k2r).abs() < 1e-8);
        // Align the signs of the two frames' directions before comparing extremalities.
        let t_world = [ca * tr[0] - sa * tr[1], sa * tr[0] + ca * tr[1]];
        let sign = (t_world[0] * t[0] + t_world[1] * t[1]).signum();
        assert!((exact.extremality(t) - sign * fit.extremality(tr)).abs() < 1e-6);
        let printed = |c: &LocalCubic, t: [f64; 2]| {
            let [c0, c1, c2, c3] = c.c;
            -(c0 * t[0].powi(3)
                + c1 * t[0] * t[0] * t[1]
                + c2 * t[0] * t[1] * t[1]
                + c3 * t[1].powi(3))
        };
        assert!((printed(&exact, t) - sign * printed(&fit, tr)).abs() > 1e-3);
    }

    #[test]
    fn rejects_bad_rings() {
        let m = crate::shapes::icosphere(1.0, 1);
        assert!(cubic_fit(&m, &CubicFitOptions::DEFAULT.with_rings(0)).is_err());
        assert!(cubic_fit(&m, &CubicFitOptions::DEFAULT.with_rings(MAX_RINGS + 1)).is_err());
        assert!(cubic_fit(&m, &CubicFitOptions::DEFAULT.with_max_rings(MAX_RINGS + 1)).is_err());
    }

    #[test]
    fn ring_growth_matches_graph_distance() {
        let m = crate::shapes::height_field(|_, _| 0.0, [0.0, 1.0], [0.0, 1.0], 8, 8);
        let topo = m.topology();
        let centre = 4 * 9 + 4;
        let mut s = Scratch::default();
        s.start();
        let rings = crate::shapes::exact::rings_from(&m, &[centre]);
        for level in 1..=4 {
            assert!(s.grow(topo, centre));
            let mut expected: Vec<u32> = (0..m.num_vertices() as u32)
                .filter(|&w| (1..=level).contains(&rings[w as usize]))
                .collect();
            let mut got = s.ring.clone();
            expected.sort_unstable();
            got.sort_unstable();
            assert_eq!(got, expected, "level {level}");
        }
    }
}
