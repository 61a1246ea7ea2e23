//! Mesh saliency of Mao, Wang and Zhou (sec. 4.2, eqs. 5–8), after Lee et al. 2005.
//!
//! `Curv(p)` is the largest absolute principal curvature. `G(p, K)` is its Gaussian-weighted
//! average (eq. 6) over the vertices within `2σ_K` of `p`, at scale `σ_K = K λ ē` (`ē` the mean
//! edge length). The difference between neighbouring scales `φ_K = |G(p, K+1) − G(p, K)|`
//! (eq. 7) summed over `K = 1..n` gives `Var(p)` (eq. 8), and the saliency is
//! `S = 0.4 Curv + 0.6 Var` (eq. 5).
//!
//! Neighbourhoods come from a uniform grid ([`crate::spatial::PointGrid`]) queried once per
//! vertex at the largest radius; all scales are accumulated in that one pass, and each pair
//! of vertices is weighted once (the Gaussian weight is symmetric) for both its ends, in an
//! order that does not depend on the number of threads. Unreferenced vertices take no part
//! (their saliency is 0).
//!
//! Distances are Euclidean, as in Lee et al.; across thin parts (a finger, the ear of a
//! bunny) neighbourhoods may include the other side.

use rayon::prelude::*;

use crate::curvature::Curvature;
use crate::error::{Error, Result};
use crate::mesh::{TriMesh, Vec3, mean_edge_length};
use crate::spatial::PointGrid;

/// Options of [`mesh_saliency`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SaliencyOptions {
    /// `λ` in `σ = λ ē`. Default: 1.0.
    pub lambda: f64,
    /// Number of scale differences `n` in eq. 8 (the paper uses 3 or 4). Default: 3.
    pub scales: usize,
    /// Weight of `Curv` in eq. 5. Default: 0.4.
    pub curvature_weight: f64,
    /// Weight of `Var` in eq. 5. Default: 0.6.
    pub variation_weight: f64,
}

impl Default for SaliencyOptions {
    fn default() -> Self {
        SaliencyOptions {
            lambda: 1.0,
            scales: 3,
            curvature_weight: 0.4,
            variation_weight: 0.6,
        }
    }
}

/// Per-vertex saliency and its two terms.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Saliency {
    /// `Curv(p)`: the largest absolute principal curvature.
    pub curv: Vec<f64>,
    /// `Var(p)`: the multi-scale variation (eq. 8).
    pub var: Vec<f64>,
    /// `S(p) = 0.4 Curv + 0.6 Var` (eq. 5).
    pub saliency: Vec<f64>,
}

/// Largest `n` supported (scales up to `n + 1 = 5` share one exponential).
pub const MAX_SCALES: usize = 4;

/// Computes the saliency of every vertex. Unreferenced vertices get 0.
///
/// ```
/// use crestline::curvature::{CurvatureOptions, estimate};
/// use crestline::saliency::{SaliencyOptions, mesh_saliency};
///
/// # fn main() -> crestline::Result<()> {
/// let mesh = crestline::shapes::ellipsoid(3.0, 2.0, 1.0, 3);
/// let curvature = estimate(&mesh, &CurvatureOptions::default())?;
/// let s = mesh_saliency(&mesh, &curvature, &SaliencyOptions::default())?;
/// assert_eq!(s.saliency.len(), mesh.num_vertices());
/// assert!(s.saliency.iter().all(|x| x.is_finite() && *x >= 0.0));
/// # Ok(())
/// # }
/// ```
///
/// # Errors
/// [`Error::InvalidInput`] when `scales` is not in `1..=4` or `lambda` is not positive.
pub fn mesh_saliency(
    mesh: &TriMesh,
    curvature: &Curvature,
    options: &SaliencyOptions,
) -> Result<Saliency> {
    if !(1..=MAX_SCALES).contains(&options.scales) {
        return Err(Error::InvalidInput(format!(
            "saliency scales must be 1 to {MAX_SCALES}, got {}",
            options.scales
        )));
    }
    if !(options.lambda.is_finite() && options.lambda > 0.0) {
        return Err(Error::InvalidInput(format!(
            "saliency lambda must be positive, got {}",
            options.lambda
        )));
    }
    let n = mesh.num_vertices();
    if curvature.k_max.len() != n || curvature.k_min.len() != n {
        return Err(Error::InvalidInput(format!(
            "curvature of {} vertices for a mesh of {n}",
            curvature.k_max.len().min(curvature.k_min.len())
        )));
    }
    let topo = mesh.topology();
    let curv: Vec<f64> = (0..n)
        .map(|v| {
            if topo.vertex_faces(v as u32).is_empty() {
                0.0
            } else {
                curvature.k_max[v].abs().max(curvature.k_min[v].abs())
            }
        })
        .collect();
    let sigma = options.lambda * mean_edge_length(mesh);
    if !(sigma > 0.0 && sigma.is_finite()) {
        return Ok(Saliency {
            saliency: curv.iter().map(|c| options.curvature_weight * c).collect(),
            var: vec![0.0; n],
            curv,
        });
    }
    let var = variation(mesh, &curv, sigma, options.scales);
    let saliency = curv
        .iter()
        .zip(&var)
        .map(|(c, v)| options.curvature_weight * c + options.variation_weight * v)
        .collect();
    Ok(Saliency {
        curv,
        var,
        saliency,
    })
}

/// `Var(p)` (eq. 8) of every vertex, with `G` at scales `σ_K = K σ`, `K = 1..=scales + 1`.
fn variation(mesh: &TriMesh, curv: &[f64], sigma: f64, scales: usize) -> Vec<f64> {
    match scales + 1 {
        2 => variation_with::<2>(mesh, curv, sigma),
        3 => variation_with::<3>(mesh, curv, sigma),
        4 => variation_with::<4>(mesh, curv, sigma),
        _ => variation_with::<5>(mesh, curv, sigma),
    }
}

/// Layers of cells a task may write to: its own and the next three (see [`variation_with`]).
const WINDOW_LAYERS: usize = 4;

/// `Var(p)` with `L` scales.
///
/// The referenced vertices are bucketed into a grid of cells of half the largest radius
/// (`r = 2 σ_L`), with the longest axis of the bounding box as the grid's z, and their
/// coordinates and `Curv` are copied into the grid's slot order (one array each), so each
/// query reads its neighbours from contiguous memory.
///
/// Each pair of vertices is weighted once: the vertex in slot `s` takes the neighbours in
/// slots `t > s`; its own sums stay in registers and the same weights are added to the
/// sums of `t` in memory. A neighbour within `r` of a vertex in layer `k` of cells lies in
/// layers `k − 2 ..= k + 2` (`k + 3` at worst by rounding; cells are at least `r/2` wide), so
/// layer `k` writes only to layers `k ..= k + 3` (the runs are clipped there, which drops
/// only points more than `1.5 r` away). The layers are processed in
/// [`WINDOW_LAYERS`] phases, `k mod 4` at a time: within a phase the tasks write to disjoint
/// windows and run in parallel, and every sum receives its terms in the same order whatever
/// the number of threads. The result does not depend on it.
fn variation_with<const L: usize>(mesh: &TriMesh, curv: &[f64], sigma: f64) -> Vec<f64> {
    let topo = mesh.topology();
    let positions = mesh.positions();
    let referenced: Vec<u32> = (0..mesh.num_vertices() as u32)
        .filter(|&v| !topo.vertex_faces(v).is_empty())
        .collect();
    // The longest axis last: the most layers of cells, so the most tasks per phase.
    let bbox = mesh.bounding_box();
    let extent = |k: usize| bbox.max[k] - bbox.min[k];
    let longest = (0..3)
        .max_by(|&a, &b| extent(a).total_cmp(&extent(b)))
        .unwrap_or(2);
    let axes = match longest {
        0 => [1, 2, 0],
        1 => [2, 0, 1],
        _ => [0, 1, 2],
    };
    // Scaled by 1/(√2 σ), so that a squared distance is `a = d²/(2σ²)` directly.
    let scale = 1.0 / (std::f64::consts::SQRT_2 * sigma);
    let points: Vec<Vec3> = referenced
        .iter()
        .map(|&v| {
            let p = positions[v as usize];
            Vec3::new(p[axes[0]], p[axes[1]], p[axes[2]]) * scale
        })
        .collect();
    // 2 σ_L, scaled.
    let radius = std::f64::consts::SQRT_2 * L as f64;
    // Cells of r/2: on igea a query scans 1.8 times the points within r, in 17 runs of
    // cells (cells of r: 2.8 times, in 7 runs; r/3: 1.5 times, in 30 runs) — the fastest
    // of the three, measured.
    let grid = PointGrid::new(&points, radius / 2.0);
    let order = grid.order();
    let column =
        |f: &dyn Fn(usize) -> f64| -> Vec<f64> { order.iter().map(|&i| f(i as usize)).collect() };
    let neighbourhood = Neighbourhood {
        grid: &grid,
        x: column(&|i| points[i].x),
        y: column(&|i| points[i].y),
        z: column(&|i| points[i].z),
        curv: column(&|i| curv[referenced[i] as usize]),
        radius,
    };
    let layers = grid.layer_offsets();
    let num_layers = layers.len() - 1;
    let mut sums = vec![Totals::<L>::default(); order.len()];
    for phase in 0..WINDOW_LAYERS.min(num_layers) {
        // Split the sums into the windows of layers phase, phase + 4, ...
        let mut tasks = Vec::new();
        let (_, mut rest) = sums.split_at_mut(layers[phase]);
        for k in (phase..num_layers).step_by(WINDOW_LAYERS) {
            let end = layers[(k + WINDOW_LAYERS).min(num_layers)];
            let (window, tail) = rest.split_at_mut(end - layers[k]);
            tasks.push((k, window));
            rest = tail;
        }
        tasks.into_par_iter().for_each(|(k, window)| {
            let mut batch = Batch::default();
            for s in layers[k]..layers[k + 1] {
                neighbourhood.accumulate(s, layers[k], window, &mut batch);
            }
        });
    }
    let mut var = vec![0.0; mesh.num_vertices()];
    let var_sorted: Vec<f64> = sums.par_iter().map(Totals::variation).collect();
    for (&i, x) in order.iter().zip(var_sorted) {
        var[referenced[i as usize] as usize] = x;
    }
    var
}

/// Independent partial sums per scale in the inner loop of [`Neighbourhood::accumulate`].
const LANES: usize = 4;

/// What a vertex's multi-scale averages read: the grid and, in its slot order, the
/// coordinates (scaled by `1/(√2 σ)`) and `Curv` of the referenced vertices.
struct Neighbourhood<'a> {
    grid: &'a PointGrid,
    x: Vec<f64>,
    y: Vec<f64>,
    z: Vec<f64>,
    curv: Vec<f64>,
    /// `2 σ_L`, scaled.
    radius: f64,
}

/// Neighbours within reach collected before their weights are computed, [`LANES`] at a
/// time (a power of two, a multiple of [`LANES`]).
const BATCH: usize = 64;

/// Neighbours within reach, compacted: `a = d²/(2σ²)`, `Curv`, and the slot relative to the
/// window. Room for a full batch plus one more chunk of candidates. One per task, reused by
/// its vertices.
struct Batch {
    a: [f64; 2 * BATCH],
    c: [f64; 2 * BATCH],
    t: [u32; 2 * BATCH],
    n: usize,
}

impl Default for Batch {
    fn default() -> Self {
        Batch {
            a: [0.0; 2 * BATCH],
            c: [0.0; 2 * BATCH],
            t: [0; 2 * BATCH],
            n: 0,
        }
    }
}

impl Neighbourhood<'_> {
    /// Adds the pairs of slot `s` with the slots `t > s` within reach to both ends' sums,
    /// and the pair `(s, s)`. `window` holds the sums of slots `base..`, `s` among them.
    fn accumulate<const L: usize>(
        &self,
        s: usize,
        base: usize,
        window: &mut [Totals<L>],
        batch: &mut Batch,
    ) {
        let reach = Gaussians::<L>::REACH[L - 1];
        let p = Vec3::new(self.x[s], self.y[s], self.z[s]);
        let cs = self.curv[s];
        let window_end = base + window.len();
        let mut lanes = Sums::<L>::default();
        batch.n = 0;
        self.grid
            .for_each_run_near_after(p, self.radius, s + 1, |run| {
                // The window holds all the later slots within reach.
                let mut start = run.start;
                let run_end = run.end.min(window_end);
                while start < run_end {
                    let end = (start + BATCH).min(run_end);
                    self.within_reach(p, reach, start..end, base, batch);
                    if batch.n >= BATCH {
                        lanes.add_batch(
                            &batch.a[..BATCH],
                            &batch.c[..BATCH],
                            &batch.t[..BATCH],
                            cs,
                            window,
                        );
                        batch.a.copy_within(BATCH..batch.n, 0);
                        batch.c.copy_within(BATCH..batch.n, 0);
                        batch.t.copy_within(BATCH..batch.n, 0);
                        batch.n -= BATCH;
                    }
                    start = end;
                }
            });
        // The last partial batch: lanes past the last neighbour get weight 0 and add it to
        // `s` (whose sums are its own even if `Curv` is not finite).
        let n = batch.n;
        let full = n.next_multiple_of(LANES);
        batch.a[n..full].fill(f64::INFINITY);
        batch.c[n..full].fill(0.0);
        batch.t[n..full].fill((s - base) as u32);
        lanes.add_batch(
            &batch.a[..full],
            &batch.c[..full],
            &batch.t[..full],
            cs,
            window,
        );
        // The pair (s, s) has weight 1 at every scale.
        let own = &mut window[s - base];
        for k in 0..L {
            own.num[k] += lanes.num[k].iter().sum::<f64>() + cs;
            own.den[k] += lanes.den[k].iter().sum::<f64>() + 1.0;
        }
    }

    /// Appends to `batch` (from `batch.n < BATCH` on) the candidates in `slots` (at most
    /// [`BATCH`]) with `a = d²/(2σ²) ≤ reach`, without branches.
    /// Not inlined: as a small function of its own its loop keeps everything in registers.
    #[inline(never)]
    fn within_reach(
        &self,
        p: Vec3,
        reach: f64,
        slots: std::ops::Range<usize>,
        base: usize,
        batch: &mut Batch,
    ) {
        let first = (slots.start - base) as u32;
        let (x, y, z, c) = (
            &self.x[slots.clone()],
            &self.y[slots.clone()],
            &self.z[slots.clone()],
            &self.curv[slots],
        );
        let mut n = batch.n;
        for i in 0..x.len().min(y.len()).min(z.len()).min(c.len()) {
            let (dx, dy, dz) = (x[i] - p.x, y[i] - p.y, z[i] - p.z);
            let a = dx * dx + dy * dy + dz * dz;
            // n < 2 BATCH (n starts below BATCH, grows by at most BATCH), so the mask
            // changes nothing but the bounds check.
            batch.a[n & (2 * BATCH - 1)] = a;
            batch.c[n & (2 * BATCH - 1)] = c[i];
            batch.t[n & (2 * BATCH - 1)] = first + i as u32;
            n += usize::from(a <= reach);
        }
        batch.n = n;
    }
}

/// A vertex's sums of `w · Curv` and of `w` per scale (eq. 6), over all its pairs.
#[derive(Debug, Clone, Copy)]
#[repr(align(64))]
struct Totals<const L: usize> {
    num: [f64; L],
    den: [f64; L],
}

impl<const L: usize> Default for Totals<L> {
    fn default() -> Self {
        Totals {
            num: [0.0; L],
            den: [0.0; L],
        }
    }
}

impl<const L: usize> Totals<L> {
    /// `Var = Σ_{K=1}^{L-1} |G(K+1) − G(K)|`. Every vertex is within reach of itself at
    /// every scale, so `den > 0`.
    fn variation(&self) -> f64 {
        let g = |k: usize| self.num[k] / self.den[k];
        (0..L - 1).map(|k| (g(k + 1) - g(k)).abs()).sum()
    }
}

/// Per scale, [`LANES`] partial sums of `w · Curv` and of `w` (independent, so the loop
/// pipelines and vectorises).
struct Sums<const L: usize> {
    num: [[f64; LANES]; L],
    den: [[f64; LANES]; L],
}

impl<const L: usize> Default for Sums<L> {
    fn default() -> Self {
        Sums {
            num: [[0.0; LANES]; L],
            den: [[0.0; LANES]; L],
        }
    }
}

impl<const L: usize> Sums<L> {
    /// Adds the pairs `(s, t[i])` with `a[i], c[i]` (`a.len()` a multiple of [`LANES`]) to
    /// these sums of `s` and to the sums of `t[i]` in `window`, `cs` being `Curv` at `s`.
    #[inline(always)]
    fn add_batch(&mut self, a: &[f64], c: &[f64], t: &[u32], cs: f64, window: &mut [Totals<L>]) {
        for ((a, c), t) in a
            .chunks_exact(LANES)
            .zip(c.chunks_exact(LANES))
            .zip(t.chunks_exact(LANES))
        {
            let a: [f64; LANES] = std::array::from_fn(|l| a[l]);
            let c: [f64; LANES] = std::array::from_fn(|l| c[l]);
            let w = self.add(&a, &c);
            for (&t, w) in t.iter().zip(&w) {
                let sums = &mut window[t as usize];
                for ((num, den), &w) in sums.num.iter_mut().zip(&mut sums.den).zip(w) {
                    *num += w * cs;
                    *den += w;
                }
            }
        }
    }

    /// Adds [`LANES`] neighbours with `a = d²/(2σ²)` and curvature `c`; returns their
    /// weights. Scale `K` reaches a neighbour when `d ≤ 2σ_K`, i.e. `a ≤ 2K²`; lanes with
    /// `a > 2L²` get weight 0.
    #[inline(always)]
    fn add(&mut self, a: &[f64; LANES], c: &[f64; LANES]) -> [[f64; L]; LANES] {
        let mut out = [[0.0; L]; LANES];
        for l in 0..LANES {
            // Clamped so that empty lanes stay finite (their weights are 0).
            let w = Gaussians::<L>::weights(a[l].min(Gaussians::<L>::REACH[L - 1]));
            for k in 0..L {
                let w = if a[l] <= Gaussians::<L>::REACH[k] {
                    w[k]
                } else {
                    0.0
                };
                self.num[k][l] += w * c[l];
                self.den[k][l] += w;
                out[l][k] = w;
            }
        }
        out
    }
}

/// The Gaussian weights `exp(−a/K²)`, `K = 1..=L`, from one exponential: with `M` a common
/// multiple of the `K²` and `u = exp(−a/M)`, `exp(−a/K²) = u^(M/K²)`. `M ≥ 8 L²` keeps
/// `a/M ≤ 1/4` for every `a` within reach (`a ≤ 2 L²`), where a Taylor polynomial of degree
/// 11 is exact to rounding; the powers are products, so the weights keep a relative error
/// below `M/K² · 2⁻⁵²` (3·10⁻¹⁴ for the default `L = 4`, `M = 144`). The constants are
/// computed at compile time, so the powers unroll into a few multiplications.
struct Gaussians<const L: usize>;

impl<const L: usize> Gaussians<L> {
    const M: u64 = {
        let mut lcm = 1u64;
        let mut k = 1;
        while k <= L as u64 {
            lcm = lcm / gcd(lcm, k * k) * (k * k);
            k += 1;
        }
        let min = 8 * (L * L) as u64;
        lcm * min.div_ceil(lcm)
    };
    const INV_M: f64 = 1.0 / Self::M as f64;
    /// `M / K²` for `K = k + 1`.
    const POWERS: [u32; L] = {
        let mut p = [0u32; L];
        let mut k = 0;
        while k < L {
            p[k] = (Self::M / ((k + 1) * (k + 1)) as u64) as u32;
            k += 1;
        }
        p
    };
    /// Binary digits of the largest power, `M`.
    const BITS: usize = (u64::BITS - Self::M.leading_zeros()) as usize;

    /// `exp(−a/K²)` for `K = 1..=L`, for `0 ≤ a ≤ 2 L²`: the squares `u^(2^i)` are shared
    /// by all scales; the loops have constant bounds and digits, so they unroll into a
    /// fixed chain of products.
    #[inline(always)]
    fn weights(a: f64) -> [f64; L] {
        let mut squares = [0.0f64; 16];
        squares[0] = exp_neg_small(a * Self::INV_M);
        for i in 1..Self::BITS {
            squares[i] = squares[i - 1] * squares[i - 1];
        }
        let mut w = [1.0f64; L];
        for (k, w) in w.iter_mut().enumerate() {
            for (i, square) in squares.iter().enumerate().take(Self::BITS) {
                if Self::POWERS[k] >> i & 1 == 1 {
                    *w *= square;
                }
            }
        }
        w
    }

    /// `2 K²`: the largest `a` that scale `K` reaches.
    const REACH: [f64; L] = {
        let mut r = [0.0f64; L];
        let mut k = 0;
        while k < L {
            r[k] = 2.0 * ((k + 1) * (k + 1)) as f64;
            k += 1;
        }
        r
    };
}

const fn gcd(a: u64, b: u64) -> u64 {
    if b == 0 { a } else { gcd(b, a % b) }
}

/// `exp(−t)` for `0 ≤ t ≤ 1/4` by its Taylor polynomial of degree 11 (truncation error
/// below `(1/4)¹²/12! ≈ 1.2·10⁻¹⁶`), evaluated by Estrin's scheme (short dependency chains).
#[inline(always)]
fn exp_neg_small(t: f64) -> f64 {
    // 1/k! for k = 0..=11.
    const C: [f64; 12] = [
        1.0,
        1.0,
        1.0 / 2.0,
        1.0 / 6.0,
        1.0 / 24.0,
        1.0 / 120.0,
        1.0 / 720.0,
        1.0 / 5040.0,
        1.0 / 40320.0,
        1.0 / 362880.0,
        1.0 / 3628800.0,
        1.0 / 39916800.0,
    ];
    // Not mul_add: without a target FMA that is a library call.
    let x = -t;
    let x2 = x * x;
    let x4 = x2 * x2;
    let x8 = x4 * x4;
    let pair = |k: usize| C[k] + C[k + 1] * x;
    let q0 = pair(0) + pair(2) * x2;
    let q1 = pair(4) + pair(6) * x2;
    let q2 = pair(8) + pair(10) * x2;
    q0 + q1 * x4 + q2 * x8
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::curvature::{CurvatureOptions, estimate};
    use crate::shapes;

    #[test]
    fn crease_is_more_salient_than_a_flat_region() {
        // A roof: two planes meeting at a crease along x = 0.
        let mesh = shapes::height_field(|x, _| -x.abs() * 0.8, [-2.0, 2.0], [-2.0, 2.0], 40, 40);
        let c = estimate(
            &mesh,
            &CurvatureOptions::default().with_estimator(crate::curvature::Estimator::ShapeOperator),
        )
        .unwrap();
        let s = mesh_saliency(&mesh, &c, &SaliencyOptions::default()).unwrap();
        let at = |x: f64, y: f64| {
            (0..mesh.num_vertices())
                .min_by(|&a, &b| {
                    let d = |i: usize| {
                        (mesh.positions()[i].x - x).powi(2) + (mesh.positions()[i].y - y).powi(2)
                    };
                    d(a).total_cmp(&d(b))
                })
                .unwrap()
        };
        let crease = s.saliency[at(0.0, 0.0)];
        let flat = s.saliency[at(1.0, 0.0)];
        assert!(
            crease > 5.0 * flat.max(1e-12),
            "crease {crease} flat {flat}"
        );
    }

    #[test]
    fn pillow_box_creases_are_more_salient_than_its_faces() {
        // The cube's edges are sharp creases; the faces bulge gently (largest curvature
        // ≈ 1 at their middles). With the cubic fit, as the saliency method runs it.
        let (mesh, _) = shapes::pillow_box(1.0, 0.25, 20);
        let options =
            CurvatureOptions::default().with_estimator(crate::curvature::Estimator::CubicFit);
        let c = estimate(&mesh, &options).unwrap();
        let s = mesh_saliency(&mesh, &c, &SaliencyOptions::default()).unwrap();
        let nearest = |q: Vec3| {
            (0..mesh.num_vertices())
                .min_by(|&a, &b| {
                    (mesh.positions()[a] - q)
                        .norm()
                        .total_cmp(&(mesh.positions()[b] - q).norm())
                })
                .unwrap()
        };
        let edge_middle = s.saliency[nearest(Vec3::new(0.0, 1.0, 1.0))];
        let face_middle = s.saliency[nearest(Vec3::new(0.0, 0.0, 1.25))];
        assert!(
            edge_middle > 3.0 * face_middle,
            "edge {edge_middle}, face {face_middle}"
        );
        // Every crease vertex away from the corners beats every vertex in the middle half
        // of a face.
        let is_crease = |p: &Vec3| (0..3).filter(|&k| (p[k].abs() - 1.0).abs() < 1e-9).count() == 2;
        let crease_min = (0..mesh.num_vertices())
            .filter(|&v| {
                let p = mesh.positions()[v];
                is_crease(&p)
                    && p.iter()
                        .all(|x| x.abs() < 0.99 || (x.abs() - 1.0).abs() < 1e-9)
            })
            .map(|v| s.saliency[v])
            .fold(f64::INFINITY, f64::min);
        let face_max = (0..mesh.num_vertices())
            .filter(|&v| {
                let p = mesh.positions()[v];
                (0..3).filter(|&k| p[k].abs() < 0.5).count() == 2
            })
            .map(|v| s.saliency[v])
            .fold(0.0, f64::max);
        assert!(
            crease_min > face_max,
            "crease min {crease_min}, face max {face_max}"
        );
    }

    #[test]
    fn sphere_and_torus_saliency_have_no_knee() {
        // Curv is 1/r on a sphere and 1/r_minor on a torus (the tube curvature dominates), so
        // the sorted saliency has no steep part and the knee search finds no threshold.
        for mesh in [shapes::icosphere(2.0, 3), shapes::torus(3.0, 1.0, 90, 30)] {
            let c = estimate(
                &mesh,
                &CurvatureOptions::default()
                    .with_estimator(crate::curvature::Estimator::ShapeOperator),
            )
            .unwrap();
            let s = mesh_saliency(&mesh, &c, &SaliencyOptions::default()).unwrap();
            let knee = crate::threshold::seek_threshold(&s.saliency, &Default::default());
            assert_eq!(
                knee,
                None,
                "{:?}",
                s.saliency.iter().take(5).collect::<Vec<_>>()
            );
        }
    }

    #[test]
    fn sphere_saliency_is_uniform() {
        let mesh = shapes::icosphere(2.0, 3);
        let c = estimate(
            &mesh,
            &CurvatureOptions::default().with_estimator(crate::curvature::Estimator::ShapeOperator),
        )
        .unwrap();
        let s = mesh_saliency(&mesh, &c, &SaliencyOptions::default()).unwrap();
        let max = s.saliency.iter().cloned().fold(f64::MIN, f64::max);
        let min = s.saliency.iter().cloned().fold(f64::MAX, f64::min);
        // The HPW shape operator keeps a ≈15% error at the icosphere's 12 valence-5 vertices
        // (measured saliency 0.200 .. 0.233; k = 0.428 at vertex 0, one of them), hence 20%
        // rather than 10% (see the curvature section of BENCHMARKS.md).
        assert!((max - min) < 0.2 * max, "{min} .. {max}");
        assert!((s.curv[0] - 0.5).abs() < 0.1, "{}", s.curv[0]);
    }

    /// Eqs. 6–8 term by term: every pair of vertices, `f64::exp`.
    fn brute_force_variation(mesh: &TriMesh, curv: &[f64], sigma: f64, scales: usize) -> Vec<f64> {
        let p = mesh.positions();
        (0..p.len())
            .map(|i| {
                let g = |k: usize| {
                    let s = sigma * k as f64;
                    let (mut num, mut den) = (0.0, 0.0);
                    for j in 0..p.len() {
                        let d2 = (p[j] - p[i]).norm_squared();
                        if d2 <= 4.0 * s * s {
                            let w = (-d2 / (2.0 * s * s)).exp();
                            num += w * curv[j];
                            den += w;
                        }
                    }
                    num / den
                };
                (1..=scales).map(|k| (g(k + 1) - g(k)).abs()).sum()
            })
            .collect()
    }

    #[test]
    fn variation_matches_the_brute_force_sums() {
        // An irregular field on an ellipsoid, every number of scales.
        let mesh = shapes::ellipsoid(2.0, 1.5, 1.0, 3);
        let c = estimate(
            &mesh,
            &CurvatureOptions::default().with_estimator(crate::curvature::Estimator::ShapeOperator),
        )
        .unwrap();
        let sigma = 0.7 * mean_edge_length(&mesh);
        let curv: Vec<f64> = (0..mesh.num_vertices())
            .map(|v| c.k_max[v].abs().max(c.k_min[v].abs()))
            .collect();
        for scales in 1..=MAX_SCALES {
            let fast = variation(&mesh, &curv, sigma, scales);
            let slow = brute_force_variation(&mesh, &curv, sigma, scales);
            for (v, (a, b)) in fast.iter().zip(&slow).enumerate() {
                assert!(
                    (a - b).abs() <= 1e-12 * b.abs().max(1.0),
                    "scales {scales}, vertex {v}: {a} vs {b}"
                );
            }
        }
    }

    #[test]
    fn variation_does_not_depend_on_the_thread_count() {
        // Each pair is weighted once and its weights are added to both ends, by tasks that
        // run in parallel: the sums must still come out bit for bit the same.
        let mesh = shapes::ellipsoid(2.0, 1.5, 1.0, 4);
        let c = estimate(
            &mesh,
            &CurvatureOptions::default().with_estimator(crate::curvature::Estimator::ShapeOperator),
        )
        .unwrap();
        let sigma = 0.5 * mean_edge_length(&mesh);
        // Cells of σ_4 = 4σ along the longest axis (x, 4 long): at least three layers per
        // phase, so several tasks write to the same sums.
        let layers = (4.0 / (4.0 * sigma)) as usize + 1;
        assert!(layers >= 12, "{layers} layers");
        let curv: Vec<f64> = (0..mesh.num_vertices())
            .map(|v| c.k_max[v].abs().max(c.k_min[v].abs()))
            .collect();
        let run = |threads: usize| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| variation(&mesh, &curv, sigma, 3))
        };
        let one = run(1);
        for threads in [2, 3, 5] {
            let many = run(threads);
            assert!(
                one.iter()
                    .zip(&many)
                    .all(|(a, b)| a.to_bits() == b.to_bits()),
                "{threads} threads"
            );
        }
    }

    #[test]
    fn gaussian_weights_are_exact_to_rounding() {
        fn check<const L: usize>() {
            for i in 0..=1000 {
                let a = 2.0 * (L * L) as f64 * i as f64 / 1000.0;
                let w = Gaussians::<L>::weights(a);
                for (k, w) in w.iter().enumerate() {
                    let exact = (-a / ((k + 1) * (k + 1)) as f64).exp();
                    assert!(
                        (w - exact).abs() <= 1e-12 * exact,
                        "L {L}, K {}, a {a}: {w} vs {exact}",
                        k + 1
                    );
                }
            }
        }
        check::<2>();
        check::<3>();
        check::<4>();
        check::<5>();
        for i in 0..=100 {
            let t = 0.25 * i as f64 / 100.0;
            assert!((exp_neg_small(t) - (-t).exp()).abs() <= 4.0 * f64::EPSILON);
        }
    }

    #[test]
    fn unreferenced_vertices_take_no_part() {
        // A stray vertex in the middle of a flat grid with a curved field: its saliency is
        // 0 and the others' are what they are without it.
        let mesh = shapes::height_field(
            |x, y| 0.1 * (x * x - y * y),
            [-1.0, 1.0],
            [-1.0, 1.0],
            12,
            12,
        );
        let mut positions = mesh.positions().to_vec();
        positions.push(Vec3::new(0.01, 0.02, 0.0));
        let with_stray = TriMesh::new(positions, mesh.faces().to_vec()).unwrap();
        let c = estimate(
            &mesh,
            &CurvatureOptions::default().with_estimator(crate::curvature::Estimator::ShapeOperator),
        )
        .unwrap();
        let mut c2 = c.clone();
        for field in [&mut c2.k_max, &mut c2.k_min, &mut c2.e_max, &mut c2.e_min] {
            field.push(100.0);
        }
        c2.dir_max.push(Vec3::x());
        c2.dir_min.push(Vec3::y());
        c2.normals.push(Vec3::z());
        let a = mesh_saliency(&mesh, &c, &SaliencyOptions::default()).unwrap();
        let b = mesh_saliency(&with_stray, &c2, &SaliencyOptions::default()).unwrap();
        assert_eq!(b.saliency.len(), a.saliency.len() + 1);
        assert_eq!(*b.saliency.last().unwrap(), 0.0);
        // The mean edge length (σ) does not see the stray vertex either.
        for (x, y) in a.saliency.iter().zip(&b.saliency) {
            assert!((x - y).abs() <= 1e-12 * x.abs().max(1.0), "{x} vs {y}");
        }
    }

    #[test]
    fn rejects_bad_options() {
        let mesh = shapes::icosphere(1.0, 1);
        let c = Curvature {
            k_max: vec![0.0; mesh.num_vertices()],
            k_min: vec![0.0; mesh.num_vertices()],
            ..Default::default()
        };
        let bad = SaliencyOptions {
            scales: 9,
            ..Default::default()
        };
        assert!(mesh_saliency(&mesh, &c, &bad).is_err());
        let bad = SaliencyOptions {
            lambda: f64::NAN,
            ..Default::default()
        };
        assert!(mesh_saliency(&mesh, &c, &bad).is_err());
        let short = Curvature {
            k_max: vec![0.0; 3],
            k_min: vec![0.0; 3],
            ..Default::default()
        };
        assert!(mesh_saliency(&mesh, &short, &SaliencyOptions::default()).is_err());
    }
}
