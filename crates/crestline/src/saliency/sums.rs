//! The multi-scale Gaussian sums behind `Var(p)` (Mao, Wang and Zhou, eqs. 6–8): every
//! scale of every vertex accumulated in one pass over a uniform grid, each pair of vertices
//! weighted once, in an order that does not depend on the number of threads.

use rayon::prelude::*;

use crate::mesh::{TriMesh, Vec3};
use crate::spatial::PointGrid;

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
pub(super) fn variation_with<const L: usize>(mesh: &TriMesh, curv: &[f64], sigma: f64) -> Vec<f64> {
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
    // Cells of r/2: the fastest of r, r/2 and r/3 on igea (`docs/benchmarks-history.md`).
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
pub(super) struct Gaussians<const L: usize>;

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
    pub(super) fn weights(a: f64) -> [f64; L] {
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
pub(super) fn exp_neg_small(t: f64) -> f64 {
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
