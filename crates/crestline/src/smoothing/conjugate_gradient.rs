//! Preconditioned conjugate gradients for the implicit diffusion steps
//! `(M + t L_σ) u' = M u` — the default solver of [`super::DiffusionOperator`].
//!
//! **Why CG fits.** `A = M + t L_σ` is symmetric positive definite and, at the step sizes of
//! HPW (t of the order of h², h the mean edge length), well conditioned: with `D` its
//! diagonal (`d_p = m_p + t Σ_q w_pq`), Gershgorin's theorem puts the eigenvalues of the
//! scaled matrix `Â = D^{-½} A D^{-½} = I − W` in `[min m/d, 2 − min m/d]`, and m/d is
//! about 0.15 on the shared meshes at t = h². Conjugate gradients (Hestenes and Stiefel 1952;
//! Saad, *Iterative Methods for Sparse Linear Systems*, 2nd ed., Alg. 9.1) then converge in
//! a few dozen sweeps over the matrix, in memory linear in the number of edges, where a
//! Cholesky factorisation pays for fill-in and an ordering.
//!
//! **Scaling.** Jacobi: CG on `A` preconditioned by `D`, i.e. with `z = D⁻¹ r`; its
//! iterates are those of plain CG on the scaled system `Â ŷ = D^{-½} M u`, `ŷ = D^{½} u'`,
//! whose diagonal is 1, and `r·z = ‖D^{-½} r‖²` is that system's residual. Gauss–Seidel
//! works on `Â` directly, computing its entries from the stored ones.
//!
//! **Preconditioners** ([`Preconditioner`]):
//! - Jacobi (the default, the diagonal alone): every pass is parallel over the vertices, and
//!   all fields share each pass over the matrix.
//! - symmetric Gauss–Seidel: `P = (I − L)(I − Lᵀ)` with `L` the strictly lower part of `W` in
//!   vertex order, applied by Eisenstat's trick (S. C. Eisenstat, "Efficient implementation
//!   of a class of preconditioned conjugate gradient methods", SIAM J. Sci. Stat. Comput. 2,
//!   1981): CG runs on `(I − L)^{-1} Â (I − Lᵀ)^{-1}`, whose product with a vector costs one
//!   sweep down and one sweep up the mesh. It needs less than half the iterations of Jacobi
//!   (igea: 15 instead of 33 per step at tolerance 1e-6), but the sweeps are sequential (the
//!   fields run in parallel, one thread each) and each field reads the matrix on its own: on
//!   the 2-core test machine it took the same CPU time as Jacobi on igea and more wall time
//!   on a 1.5M-face mesh (`BENCHMARKS.md`). Splitting the sweeps into blocks for parallelism
//!   loses most of the gain (igea: 20 iterations with 2 blocks, whatever the vertex order),
//!   because a sweep carries information across the whole mesh only when it is not cut.
//!
//! **Storage.** Compressed rows laid out like the mesh's vertex → edge lists (ordered by
//! neighbour, so that the lower and upper parts of a row are its two ends), 8 bytes per
//! entry: the neighbour with the fields' sign bits below it in one `u32`, and the weight
//! `w_pq` as `f32`; per vertex only the diagonal `d_p` (the mass is recovered from it). About
//! 28 bytes per face. The products turn an entry's sign bits into the fields' factors ±1 with
//! one lookup in a 256-entry table rather than extracting each field's bit: on igea 8% fewer
//! instructions for the whole `extract` run, the smoothing stage 11–20% faster. The matrix
//! products read the rows front to back and gather only the neighbours' values: on a
//! 1.5M-face mesh this took about 20% less CPU time than reaching the neighbour and an `f64`
//! weight through the edge list (9 bytes per edge, about 22 per face with the mass and
//! diagonal), whose random reads cost more than the extra bytes. The weights are rounded to
//! single precision once ([`round_weights`]; a relative change below 6e-8, far below the
//! tolerance) and the diagonal is summed from the rounded values, so the system
//! is still exactly symmetric, conserves `Σ M u` and keeps constants fixed (σ = +1); the
//! other solvers are given the same rounded weights ([`super::DiffusionOperator`]).
//!
//! **Start and stopping.** Each step starts from the current values (the result of the
//! previous step), or from zero when that is closer (the residual of the previous values is
//! then larger than the right-hand side: a rough field that the step will mostly remove). It
//! stops when `‖r‖₂ ≤ tolerance · ‖b‖₂` for every field, with `r` and `b` the residual and
//! right-hand side of the system CG iterates on (scaled, and for Gauss–Seidel also
//! preconditioned); the relative error of the result is then about the tolerance.
//!
//! **Mixed precision (Jacobi).** The iterations are bound by memory traffic (on a 1.5M-face
//! mesh about 150 bytes per vertex per iteration against a few dozen flops), so the Jacobi
//! solver keeps its working vectors (residual, search direction, `A p`, correction) in single
//! precision and refines in double (iterative refinement; e.g. Higham, *Accuracy and
//! Stability of Numerical Algorithms*, 2nd ed., ch. 12): the right-hand side `b = M u` of the
//! step stays fixed in double precision; each round runs single-precision CG on the
//! correction equation `A e = r` from `e = 0`, then `x += e` and the true residual
//! `r = b − A x` is recomputed in double precision. A round aims a little below the
//! tolerance but asks for at most a 1e-5 reduction (what single precision reliably
//! delivers), so one round usually suffices (igea and horse-x16: one round per step, with
//! the iteration counts of the double-precision solver) and tight tolerances take several.
//! Through the first round the start values stay in place and `b` is computed from them
//! where it is needed; it is stored (8 bytes per vertex and field) only when a second round
//! follows: on igea that array was 8 bytes per face of the peak memory.
//! Dot products are summed in double precision. The stopping
//! test is the double-precision residual, so the accuracy contract is unchanged; a round
//! that fails to halve the residual ends with [`Error::Solver`] instead of looping. Measured
//! on horse-x16 (two steps, both families): the smoothing stage 0.75 s against 0.95 s
//! (minimum of five interleaved runs), the traced lines the same, points moved by at most
//! 4e-7 (fandisk; the tolerance is 1e-5).
//!
//! **Determinism.** The Gauss–Seidel sweeps are sequential; the parallel Jacobi passes work on
//! chunks of a fixed size whose partial sums are added in chunk order. Results therefore do
//! not depend on the number of threads. Flipping the sign of a field at a vertex together with
//! the σ of its edges flips every iterate at that vertex exactly (products only change sign),
//! which keeps the sign-independence of HPW's smoothing exact.

use rayon::prelude::*;

use crate::error::{Error, Result};
use crate::mesh::Topology;
use crate::slices::split_rows;

/// Rows per parallel work item (fixed so that sums do not depend on the thread count).
const CHUNK: usize = 2048;

/// At most this many fields are solved together (one sign bit each per edge).
pub const MAX_FIELDS: usize = 8;

/// The preconditioner of [`ConjugateGradientOptions`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Preconditioner {
    /// Jacobi (diagonal) scaling: passes parallel over vertices, fields share each pass.
    #[default]
    Jacobi,
    /// Symmetric Gauss–Seidel by Eisenstat's trick: less than half the iterations of Jacobi,
    /// but sequential sweeps (one thread per field), each reading the whole matrix.
    SymmetricGaussSeidel,
}

/// Options of the conjugate-gradient solver.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ConjugateGradientOptions {
    /// Stop when the residual's 2-norm is at most this fraction of the right-hand side's.
    ///
    /// Default: 1e-5. Measured on fandisk, bunny, horse and igea (three HPW steps): the
    /// traced lines are the same as with an exact solve, their total length within 1e-5
    /// relative; at 1e-4 lengths move by up to 1e-4, at 1e-3 a line can appear or vanish.
    pub tolerance: f64,
    /// Give up with [`Error::Solver`] after this many iterations in one step.
    ///
    /// Default: 1000 (the shared meshes need 20 to 45 per step).
    pub max_iterations: usize,
    /// The preconditioner. Default: [`Preconditioner::Jacobi`].
    pub preconditioner: Preconditioner,
}

impl ConjugateGradientOptions {
    /// The default options.
    pub const DEFAULT: Self = ConjugateGradientOptions {
        tolerance: 1e-5,
        max_iterations: 1000,
        preconditioner: Preconditioner::Jacobi,
    };

    /// Sets the relative residual tolerance.
    pub fn with_tolerance(mut self, tolerance: f64) -> Self {
        self.tolerance = tolerance;
        self
    }

    /// Sets the iteration limit.
    pub fn with_max_iterations(mut self, max_iterations: usize) -> Self {
        self.max_iterations = max_iterations;
        self
    }

    /// Sets the preconditioner.
    pub fn with_preconditioner(mut self, preconditioner: Preconditioner) -> Self {
        self.preconditioner = preconditioner;
        self
    }

    fn validate(&self) -> Result<()> {
        if !(self.tolerance.is_finite() && self.tolerance > 0.0) {
            return Err(Error::InvalidInput(format!(
                "conjugate-gradient tolerance must be a positive number, got {}",
                self.tolerance
            )));
        }
        if self.max_iterations == 0 {
            return Err(Error::InvalidInput(
                "conjugate gradients need at least one iteration".into(),
            ));
        }
        Ok(())
    }
}

impl Default for ConjugateGradientOptions {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// The system `A = D − t W_σ` (`D = M + t diag(Σ_q w_pq)`) for up to [`MAX_FIELDS`] fields
/// sharing the weights, in compressed rows (see the module docs).
#[derive(Debug, Clone)]
pub struct ConnectionSystem<'m> {
    topology: &'m Topology,
    /// Per entry of the rows (laid out as the topology's vertex → edge lists): the neighbour,
    /// shifted left by `flip_bits`, and below it bit `f` set when `σ_pq = −1` for field `f`.
    entries: Vec<u32>,
    /// Per entry: the weight `w_pq`, in single precision.
    weights: Vec<f32>,
    /// Sign bits per entry: the number of fields when any field has signs, else 0.
    flip_bits: u32,
    /// `d_p = m_p + t Σ_q w_pq` per vertex (the mass is not kept: see
    /// [`ConnectionSystem::mass`]).
    diagonal: Vec<f64>,
    time: f64,
    fields: usize,
    options: ConjugateGradientOptions,
}

/// The two precisions the solvers compute in.
trait Real: Copy + Default + std::ops::Add<Output = Self> + std::ops::Mul<Output = Self> {
    /// A stored weight in this precision.
    fn from_weight(w: f32) -> Self;
}

impl Real for f64 {
    #[inline(always)]
    fn from_weight(w: f32) -> Self {
        f64::from(w)
    }
}

impl Real for f32 {
    #[inline(always)]
    fn from_weight(w: f32) -> Self {
        w
    }
}

/// `w` with the sign of field `f` applied (an exact negation when bit `f` of `flips` is set),
/// for the row walks of the Gauss–Seidel solver; the Jacobi products use a [`SignTable`].
#[inline(always)]
fn signed(w: f64, flips: u32, f: usize) -> f64 {
    f64::from_bits(w.to_bits() ^ (u64::from((flips >> f) & 1) << 63))
}

/// Rounds diffusion weights to single precision, the precision [`ConnectionSystem`] stores
/// them in, so that every solver can be given the same system.
pub fn round_weights(weights: &mut [f64]) {
    weights
        .par_iter_mut()
        .for_each(|w| *w = f64::from(*w as f32));
}

impl<'m> ConnectionSystem<'m> {
    /// Builds the system from per-edge weights, the lumped mass, the time step and, per
    /// field, the edges where σ = −1 (`None`: σ = +1 everywhere). The weights are stored in
    /// single precision: the system solved is the one with the rounded weights (see
    /// [`round_weights`]).
    ///
    /// # Errors
    /// [`Error::InvalidInput`] for mismatched lengths, more than [`MAX_FIELDS`] fields,
    /// negative or non-finite weights, masses that are not positive, more vertices than the
    /// packed rows index (2^30 with two signed fields), or invalid options.
    pub fn new(
        topology: &'m Topology,
        weights: Vec<f64>,
        mass: Vec<f64>,
        time: f64,
        flips: &[Option<&[bool]>],
        options: ConjugateGradientOptions,
    ) -> Result<Self> {
        options.validate()?;
        let (n, m) = (topology.num_vertices(), topology.num_edges());
        if flips.is_empty() || flips.len() > MAX_FIELDS {
            return Err(Error::InvalidInput(format!(
                "conjugate gradients solve 1 to {MAX_FIELDS} fields together, got {}",
                flips.len()
            )));
        }
        if let Some(bad) = flips.iter().flatten().find(|f| f.len() != m) {
            return Err(Error::InvalidInput(format!(
                "{} edge signs for {m} edges",
                bad.len()
            )));
        }
        let fields = flips.len();
        let flip_bits = if flips.iter().any(Option::is_some) {
            fields as u32
        } else {
            0
        };
        if 2 * m > u32::MAX as usize || (n as u64) >= 1u64 << (32 - flip_bits) {
            return Err(Error::InvalidInput(format!(
                "{n} vertices and {m} edges are more than the solver indexes with \
                 {flip_bits} signed fields"
            )));
        }
        // Checked and in single precision before the rows are allocated: the double-precision
        // weights are freed first (the largest transient of the smoothing set-up).
        let weights = single_precision(topology, weights, &mass, time)?;
        let (offsets, lists) = topology.vertex_edge_rows();
        let edges = topology.edges();
        let mut entries = vec![0u32; lists.len()];
        split_rows(&mut entries, offsets, CHUNK)
            .into_par_iter()
            .for_each(|(rows, piece)| {
                let base = offsets[rows.start] as usize;
                for v in rows {
                    for k in offsets[v] as usize..offsets[v + 1] as usize {
                        let e = lists[k] as usize;
                        let [a, b] = edges[e];
                        let bits = flips.iter().enumerate().fold(0u32, |bits, (f, s)| {
                            bits | (u32::from(s.is_some_and(|s| s[e])) << f)
                        });
                        // The row's vertex is one end of the edge; a ^ b ^ v is the other.
                        piece[k - base] = ((a ^ b ^ v as u32) << flip_bits) | bits;
                    }
                }
            });
        let mut system = ConnectionSystem {
            topology,
            entries,
            weights: Vec::new(),
            flip_bits,
            diagonal: Vec::new(),
            time,
            fields,
            options,
        };
        system.fill(&weights, &mass, time);
        Ok(system)
    }

    /// Replaces weights and mass (same mesh, signs), as mean-curvature flow needs every step.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] for mismatched lengths, negative or non-finite weights or
    /// time, or masses that are not positive and finite.
    pub fn update(&mut self, weights: Vec<f64>, mass: Vec<f64>, time: f64) -> Result<()> {
        let weights = single_precision(self.topology, weights, &mass, time)?;
        self.fill(&weights, &mass, time);
        Ok(())
    }

    /// Fills the rows' weights and the diagonal from checked per-edge weights.
    fn fill(&mut self, weights: &[f32], mass: &[f64], time: f64) {
        let (offsets, lists) = self.topology.vertex_edge_rows();
        // Every entry is written below: a new array is a zeroed allocation (pages the system
        // zeroes on first touch, in parallel below) rather than filled on one thread.
        let mut stored = std::mem::take(&mut self.weights);
        if stored.len() != lists.len() {
            stored = vec![0.0; lists.len()];
        }
        let mut diagonal = vec![0.0; mass.len()];
        split_rows(&mut stored, offsets, CHUNK)
            .into_par_iter()
            .zip(diagonal.par_chunks_mut(CHUNK))
            .for_each(|((rows, piece), ds)| {
                let base = offsets[rows.start] as usize;
                for (v, d) in rows.zip(ds) {
                    let mut sum = 0.0;
                    for k in offsets[v] as usize..offsets[v + 1] as usize {
                        let w = weights[lists[k] as usize];
                        piece[k - base] = w;
                        sum += f64::from(w);
                    }
                    *d = mass[v] + time * sum;
                }
            });
        self.weights = stored;
        self.diagonal = diagonal;
        self.time = time;
    }

    /// The entries of row `v`: neighbours, weights `w_pq` and sign bits.
    #[inline(always)]
    fn row(&self, v: usize) -> impl DoubleEndedIterator<Item = (usize, f64, u32)> + '_ {
        let (offsets, _) = self.topology.vertex_edge_rows();
        let range = offsets[v] as usize..offsets[v + 1] as usize;
        let shift = self.flip_bits;
        let mask = (1u32 << shift) - 1;
        self.entries[range.clone()]
            .iter()
            .zip(&self.weights[range])
            .map(move |(&c, &w)| ((c >> shift) as usize, f64::from(w), c & mask))
    }

    /// The mass `m_v = d_v − t Σ_q w_vq` of vertex `v`, recovered from the diagonal (to
    /// rounding; the right-hand sides use this value, and `A·1 = m` holds for it exactly).
    #[inline]
    fn mass(&self, v: usize) -> f64 {
        let sum: f64 = self.row(v).map(|(_, w, _)| w).sum();
        self.diagonal[v] - self.time * sum
    }

    /// `√d_p` per vertex, for the symmetrically scaled system of the Gauss–Seidel solver.
    fn sqrt_diagonal(&self) -> Vec<f64> {
        self.diagonal.par_iter().map(|d| d.sqrt()).collect()
    }

    /// The entries of row `v` of the scaled system `Â = I − Ŵ`: neighbours,
    /// `Ŵ_vq = t w_vq / (√d_v √d_q)` and sign bits.
    #[inline(always)]
    fn scaled_row<'a>(
        &'a self,
        v: usize,
        sqrt_d: &'a [f64],
    ) -> impl DoubleEndedIterator<Item = (usize, f64, u32)> + 'a {
        let t = self.time / sqrt_d[v];
        self.row(v)
            .map(move |(q, w, flips)| (q, t * w / sqrt_d[q], flips))
    }

    /// `Σ_{q<v} Ŵ_vq u(q)` (`below`) or `Σ_{q>v} Ŵ_vq u(q)` for field `f`: the lower and upper
    /// parts of a row are its two ends, since rows are ordered by neighbour.
    #[inline(always)]
    fn half_row_sum(&self, v: usize, f: usize, below: bool, u: &[f64], sqrt_d: &[f64]) -> f64 {
        let mut sum = 0.0;
        if below {
            for (q, w, flips) in self.scaled_row(v, sqrt_d) {
                if q >= v {
                    break;
                }
                sum += signed(w, flips, f) * u[q];
            }
        } else {
            for (q, w, flips) in self.scaled_row(v, sqrt_d).rev() {
                if q <= v {
                    break;
                }
                sum += signed(w, flips, f) * u[q];
            }
        }
        sum
    }

    /// Number of fields the system solves together.
    pub fn fields(&self) -> usize {
        self.fields
    }

    /// One implicit step on every field, in place (`fields[f]` is field `f`, one value per
    /// vertex). Returns the number of iterations of the slowest field.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] for a wrong number or length of fields; [`Error::Solver`] when
    /// the iteration breaks down (non-finite values) or does not reach the tolerance within
    /// [`ConjugateGradientOptions::max_iterations`].
    pub fn step(&self, fields: &mut [&mut [f64]]) -> Result<usize> {
        self.steps(fields, 1)
    }

    /// `count` steps, each from the result of the last ([`ConnectionSystem::step`] repeated,
    /// sharing the solver's working memory). Returns the iterations of all steps (of the
    /// slowest field, per step, for Gauss–Seidel).
    ///
    /// # Errors
    /// As [`ConnectionSystem::step`].
    pub fn steps(&self, fields: &mut [&mut [f64]], count: usize) -> Result<usize> {
        let n = self.diagonal.len();
        if fields.len() != self.fields || fields.iter().any(|f| f.len() != n) {
            return Err(Error::InvalidInput(format!(
                "diffusion step: need {} fields of {n} values",
                self.fields
            )));
        }
        if n == 0 || count == 0 {
            return Ok(0);
        }
        match self.options.preconditioner {
            Preconditioner::SymmetricGaussSeidel => {
                let mut iterations = 0;
                for _ in 0..count {
                    iterations += fields
                        .par_iter_mut()
                        .enumerate()
                        .map(|(f, x)| self.solve_gauss_seidel(f, x))
                        .try_reduce(|| 0, |a, b| Ok(a.max(b)))?;
                }
                Ok(iterations)
            }
            Preconditioner::Jacobi => match fields.len() {
                1 => self.solve_jacobi::<1>(fields, count),
                2 => self.solve_jacobi::<2>(fields, count),
                3 => self.solve_jacobi::<3>(fields, count),
                4 => self.solve_jacobi::<4>(fields, count),
                5 => self.solve_jacobi::<5>(fields, count),
                6 => self.solve_jacobi::<6>(fields, count),
                7 => self.solve_jacobi::<7>(fields, count),
                _ => self.solve_jacobi::<8>(fields, count),
            },
        }
    }

    /// `Σ_q σ_vq w_vq u(q)` over the neighbours of `v` for every field, `u(q)` read
    /// through `value`, and `Σ_q w_vq` in double precision, added in row order as
    /// [`ConnectionSystem::mass`] adds it (the products that do not use it compile it away).
    #[inline(always)]
    fn neighbour_sum<T: Real, const K: usize>(
        &self,
        v: usize,
        value: impl Fn(usize) -> [T; K],
        signs: &SignTable<T, K>,
    ) -> ([T; K], f64) {
        // The entries hold no sign bits or one per field: with the shift a constant, decoding
        // an entry takes fewer instructions (the branch goes the same way for every row).
        if self.flip_bits == 0 {
            self.neighbour_sum_shifted::<T, K, 0>(v, value, signs)
        } else {
            self.neighbour_sum_shifted::<T, K, K>(v, value, signs)
        }
    }

    /// [`ConnectionSystem::neighbour_sum`] for entries with `SHIFT` sign bits.
    #[inline(always)]
    fn neighbour_sum_shifted<T: Real, const K: usize, const SHIFT: usize>(
        &self,
        v: usize,
        value: impl Fn(usize) -> [T; K],
        signs: &SignTable<T, K>,
    ) -> ([T; K], f64) {
        debug_assert_eq!(self.flip_bits as usize, SHIFT);
        // Two partial sums (even and odd entries) halve the chain of dependent additions,
        // which otherwise bounds the speed of the product.
        let (offsets, _) = self.topology.vertex_edge_rows();
        let range = offsets[v] as usize..offsets[v + 1] as usize;
        let (entries, weights) = (&self.entries[range.clone()], &self.weights[range]);
        let shift = SHIFT as u32;
        let mask = (1u32 << shift) - 1;
        let term = |sum: &mut [T; K], c: u32, w: f32| {
            let u = value((c >> shift) as usize);
            let sign = &signs[(c & mask & 0xff) as usize];
            let w = T::from_weight(w);
            for f in 0..K {
                sum[f] = sum[f] + w * sign[f] * u[f];
            }
        };
        let (mut even, mut odd) = ([T::default(); K], [T::default(); K]);
        let mut weight_sum = 0.0;
        let mut pairs = entries.chunks_exact(2).zip(weights.chunks_exact(2));
        for (c, w) in &mut pairs {
            term(&mut even, c[0], w[0]);
            term(&mut odd, c[1], w[1]);
            weight_sum = weight_sum + f64::from(w[0]) + f64::from(w[1]);
        }
        if entries.len() % 2 == 1 {
            let last = entries.len() - 1;
            term(&mut even, entries[last], weights[last]);
            weight_sum += f64::from(weights[last]);
        }
        (std::array::from_fn(|f| even[f] + odd[f]), weight_sum)
    }

    /// Right-hand side `b̂ = D^{-½} M x` of vertex `v` (`x` the unscaled value).
    #[inline(always)]
    fn scaled_rhs(&self, v: usize, x: f64, sqrt_d: &[f64]) -> f64 {
        self.mass(v) * x / sqrt_d[v]
    }

    /// Breakdown check of one CG step: `p·Âp` must be positive and α finite.
    fn step_length(rz: f64, pq: f64, iterations: usize) -> Result<f64> {
        let alpha = rz / pq;
        if alpha.is_finite() && pq > 0.0 {
            Ok(alpha)
        } else {
            Err(Error::Solver(format!(
                "conjugate gradients broke down after {iterations} iterations (p·Ap = {pq:e})"
            )))
        }
    }

    fn not_converged(&self, iterations: usize, relative: f64) -> Error {
        Error::Solver(format!(
            "conjugate gradients did not converge in {iterations} iterations (relative \
             residual {relative:.3e}, tolerance {:.1e})",
            self.options.tolerance
        ))
    }

    /// Field `f` by CG with symmetric Gauss–Seidel preconditioning (Eisenstat's trick).
    fn solve_gauss_seidel(&self, f: usize, x: &mut [f64]) -> Result<usize> {
        let n = x.len();
        let sqrt_d = &self.sqrt_diagonal();
        // r̂ = b̂ − Â ŷ with ŷ = D^{½} x; ‖b̂‖², ‖r̂‖².
        let mut r: Vec<f64> = (0..n)
            .into_par_iter()
            .with_min_len(CHUNK)
            .map(|v| {
                let near: f64 = self
                    .row(v)
                    .map(|(q, w, flips)| signed(w, flips, f) * sqrt_d[q] * x[q])
                    .sum();
                self.scaled_rhs(v, x[v], sqrt_d) - (sqrt_d[v] * x[v] - near)
            })
            .collect();
        let rhs_norm2: f64 = (0..n)
            .map(|v| self.scaled_rhs(v, x[v], sqrt_d).powi(2))
            .sum();
        let warm = r.iter().map(|r| r * r).sum::<f64>() <= rhs_norm2;
        // The iterate x̃ = (I − Lᵀ) ŷ, in place (rows ascending read only later rows).
        let mut b = vec![0.0; n];
        for v in 0..n {
            b[v] = self.scaled_rhs(v, x[v], sqrt_d);
            if warm {
                let later: f64 = self
                    .row(v)
                    .rev()
                    .map_while(|(q, w, flips)| {
                        (q > v).then(|| signed(w, flips, f) * sqrt_d[q] * x[q])
                    })
                    .sum();
                x[v] = sqrt_d[v] * x[v] - later;
            } else {
                x[v] = 0.0;
                r[v] = b[v];
            }
        }
        // b̃ = (I − L)^{-1} b̂ (for the stopping test) and r̃ = (I − L)^{-1} r̂.
        for v in 0..n {
            b[v] += self.half_row_sum(v, f, true, &b, sqrt_d);
            r[v] += self.half_row_sum(v, f, true, &r, sqrt_d);
        }
        let rhs_norm2: f64 = b.iter().map(|b| b * b).sum();
        let mut residual2: f64 = r.iter().map(|r| r * r).sum();
        if !(rhs_norm2.is_finite() && residual2.is_finite()) {
            return Err(not_finite());
        }
        let threshold = self.options.tolerance.powi(2) * rhs_norm2;
        // b's storage is reused: p, and t / q and s below.
        let mut p = b;
        p.fill(0.0);
        let mut t = vec![0.0; n];
        let mut s = vec![0.0; n];
        let mut beta = 0.0;
        let mut iterations = 0;
        while residual2 > threshold {
            if iterations == self.options.max_iterations {
                return Err(self.not_converged(iterations, (residual2 / rhs_norm2).sqrt()));
            }
            iterations += 1;
            // p = r̃ + β p and t = (I − Lᵀ)^{-1} p, sweeping up.
            for v in (0..n).rev() {
                p[v] = r[v] + beta * p[v];
                t[v] = p[v] + self.half_row_sum(v, f, false, &t, sqrt_d);
            }
            // s = (I − L)^{-1} (p − t), q = s + t (into t), sweeping down; p·q.
            let mut pq = 0.0;
            for v in 0..n {
                s[v] = p[v] - t[v] + self.half_row_sum(v, f, true, &s, sqrt_d);
                t[v] += s[v];
                pq += p[v] * t[v];
            }
            let alpha = Self::step_length(residual2, pq, iterations)?;
            let mut next = 0.0;
            for v in 0..n {
                x[v] += alpha * p[v];
                r[v] -= alpha * t[v];
                next += r[v] * r[v];
            }
            beta = next / residual2;
            residual2 = next;
        }
        // ŷ = (I − Lᵀ)^{-1} x̃ sweeping up, then x = D^{-½} ŷ.
        for v in (0..n).rev() {
            x[v] += self.half_row_sum(v, f, false, x, sqrt_d);
        }
        x.par_iter_mut()
            .zip(sqrt_d.par_iter())
            .for_each(|(x, s)| *x /= s);
        Ok(iterations)
    }

    /// All fields by Jacobi-preconditioned CG on `A = D − t W_σ`, parallel passes, in mixed
    /// precision (see the module docs): rounds of single-precision CG on the correction
    /// equation `A e = r`, each followed by `x += e` and the residual in double precision,
    /// until that residual meets the tolerance.
    ///
    /// With `z = D⁻¹ r`, `r·z = ‖D^{-½} r‖²`: the iterates are those of plain CG on the
    /// symmetrically scaled system, and so is the stopping test.
    ///
    /// Takes `steps` steps, each from the result of the last, with one set of working vectors
    /// (allocating them for every step maps and faults in 20 bytes per vertex again).
    fn solve_jacobi<const K: usize>(&self, x: &mut [&mut [f64]], steps: usize) -> Result<usize> {
        let n = self.diagonal.len();
        let mut work = Work::<K> {
            d: self.diagonal.par_iter().map(|&d| d as f32).collect(),
            r: vec![[0.0; K]; n],
            p: vec![[0.0; K]; n],
            q: vec![[0.0; K]; n],
            e: vec![[0.0; K]; n],
        };
        let mut iterations = 0;
        for _ in 0..steps {
            iterations += self.jacobi_step(x, &mut work)?;
        }
        Ok(iterations)
    }

    /// One step of [`ConnectionSystem::solve_jacobi`]; returns its iterations.
    fn jacobi_step<const K: usize>(
        &self,
        x: &mut [&mut [f64]],
        work: &mut Work<K>,
    ) -> Result<usize> {
        let n = self.diagonal.len();
        // The right-hand side b = M x₀ of the start values x₀ holds for the whole step (the
        // residuals of later rounds are taken against it, not against the moving x). The
        // first round reads it from x₀, which stays in `x` until the round is over; only a
        // second round stores it (see the module docs). r = b − A x₀; sums of b·D⁻¹b and r·D⁻¹r.
        let start = |j: usize| -> [f64; K] { std::array::from_fn(|f| x[f][j]) };
        let rhs_of_start =
            |v: usize, mass: f64| -> [f64; K] { std::array::from_fn(|f| mass * x[f][v]) };
        let [rhs_norm2, mut rz] = self.residual::<K>(start, rhs_of_start, &mut work.r);
        if !(0..K).all(|f| rhs_norm2[f].is_finite() && rz[f].is_finite()) {
            return Err(not_finite());
        }
        // A field whose start values are further from the solution than zero starts at zero
        // (then r = b); its iterate is e alone instead of x₀ + e.
        let cold: [bool; K] = std::array::from_fn(|f| rz[f] > rhs_norm2[f]);
        if cold.iter().any(|&c| c) {
            work.r
                .par_chunks_mut(CHUNK)
                .enumerate()
                .for_each(|(c, rs)| {
                    for (i, r) in rs.iter_mut().enumerate() {
                        let v = c * CHUNK + i;
                        let mass = self.mass(v);
                        for f in (0..K).filter(|&f| cold[f]) {
                            r[f] = (mass * x[f][v]) as f32;
                        }
                    }
                });
            for f in (0..K).filter(|&f| cold[f]) {
                rz[f] = rhs_norm2[f];
            }
        }
        let threshold: [f64; K] =
            std::array::from_fn(|f| self.options.tolerance.powi(2) * rhs_norm2[f]);
        let mut done: [bool; K] = std::array::from_fn(|f| rz[f] <= threshold[f]);
        let mut iterations = 0;
        let mut rhs: Vec<[f64; K]> = Vec::new();
        let mut first = true;
        while !done.iter().all(|&d| d) {
            // Each round aims a little below the tolerance (so that one round usually
            // suffices), but no lower than single precision reliably reaches.
            let target: [f64; K] = std::array::from_fn(|f| {
                (0.25 * threshold[f]).max(ROUND_REDUCTION * ROUND_REDUCTION * rz[f])
            });
            iterations += self.correction::<K>(work, target, done, iterations, &rhs_norm2)?;
            // The residual of the new iterate in double precision, then x = iterate.
            let next = if first {
                // x still holds x₀: the iterate is x₀ + e (e for a cold field).
                let e = &work.e;
                let iterate = |j: usize| -> [f64; K] {
                    std::array::from_fn(|f| {
                        let base = if cold[f] { 0.0 } else { x[f][j] };
                        base + f64::from(e[j][f])
                    })
                };
                let [_, next] = self.residual::<K>(
                    iterate,
                    |v, mass| std::array::from_fn(|f| mass * x[f][v]),
                    &mut work.r,
                );
                let converged = (0..K).all(|f| done[f] || next[f] <= threshold[f]);
                if !converged {
                    // A second round: b is kept from here on.
                    rhs = (0..n)
                        .into_par_iter()
                        .with_min_len(CHUNK)
                        .map(|v| {
                            let mass = self.mass(v);
                            std::array::from_fn(|f| mass * x[f][v])
                        })
                        .collect();
                }
                zero_cold_fields(x, &cold);
                add_correction(x, &work.e);
                first = false;
                next
            } else {
                add_correction(x, &work.e);
                let (x, rhs) = (&*x, &rhs);
                let iterate = |j: usize| -> [f64; K] { std::array::from_fn(|f| x[f][j]) };
                self.residual::<K>(iterate, |v, _| rhs[v], &mut work.r)[1]
            };
            for f in 0..K {
                if done[f] {
                    continue;
                }
                if !next[f].is_finite() {
                    return Err(not_finite());
                }
                // A round that does not halve the residual has hit the limit of single
                // precision (or the system is not positive definite): stop with an error
                // rather than loop.
                if next[f] > threshold[f] && next[f] > 0.25 * rz[f] {
                    return Err(Error::Solver(format!(
                        "conjugate gradients stalled after {iterations} iterations at relative \
                         residual {:.3e} (tolerance {:.1e})",
                        (next[f] / rhs_norm2[f]).sqrt(),
                        self.options.tolerance
                    )));
                }
                rz[f] = next[f];
                done[f] = rz[f] <= threshold[f];
            }
        }
        if first {
            // No round ran (every field met the tolerance at its start): a cold field's
            // start is zero.
            zero_cold_fields(x, &cold);
        }
        Ok(iterations)
    }

    /// `r = b − A x` in double precision for the iterate `x` (read through `iterate`) and the
    /// right-hand side `b` (`rhs(v, m_v)`, given the mass), stored in single precision;
    /// returns the sums of `b·D⁻¹b` and `r·D⁻¹r`.
    fn residual<const K: usize>(
        &self,
        iterate: impl Fn(usize) -> [f64; K] + Sync,
        rhs: impl Fn(usize, f64) -> [f64; K] + Sync,
        r: &mut [[f32; K]],
    ) -> [[f64; K]; 2] {
        let (d, t) = (&self.diagonal, self.time);
        let signs = sign_table::<f64, K>();
        let sums = r
            .par_chunks_mut(CHUNK)
            .enumerate()
            .map(|(c, rs)| {
                let mut sums = [[0.0; K]; 2];
                for (i, r) in rs.iter_mut().enumerate() {
                    let v = c * CHUNK + i;
                    let (near, weight_sum) = self.neighbour_sum::<f64, K>(v, &iterate, &signs);
                    let b = rhs(v, d[v] - t * weight_sum);
                    let x = iterate(v);
                    for f in 0..K {
                        sums[0][f] += b[f] * b[f] / d[v];
                        let rv = b[f] - (d[v] * x[f] - t * near[f]);
                        r[f] = rv as f32;
                        sums[1][f] += rv * rv / d[v];
                    }
                }
                sums
            })
            .collect::<Vec<_>>();
        add_up(&sums)
    }

    /// One round of single-precision CG on `A e = r` from `e = 0`, for the fields not `skip`ped,
    /// until `r·D⁻¹r ≤ target` for each (`r` is updated to the residual of the correction).
    /// `before` is the number of iterations of the earlier rounds and `rhs_norm2` the sums
    /// `b·D⁻¹b`, for the error messages. Returns the iterations used. Dot products are summed
    /// in double precision.
    ///
    /// # Errors
    /// [`Error::Solver`] when the iteration limit is reached or the iteration breaks down.
    fn correction<const K: usize>(
        &self,
        work: &mut Work<K>,
        target: [f64; K],
        skip: [bool; K],
        before: usize,
        rhs_norm2: &[f64; K],
    ) -> Result<usize> {
        let Work { d, r, p, q, e } = work;
        let t = self.time as f32;
        let signs = sign_table::<f32, K>();
        // p = D⁻¹ r, e = 0; r·D⁻¹r.
        let sums = p
            .par_chunks_mut(CHUNK)
            .zip(e.par_chunks_mut(CHUNK))
            .zip(r.par_chunks(CHUNK))
            .zip(d.par_chunks(CHUNK))
            .map(|(((ps, es), rs), ds)| {
                let mut rz = [0.0; K];
                for (((p, e), r), &d) in ps.iter_mut().zip(es).zip(rs).zip(ds) {
                    for f in 0..K {
                        p[f] = r[f] / d;
                        e[f] = 0.0;
                        rz[f] += f64::from(r[f] * p[f]);
                    }
                }
                [rz]
            })
            .collect::<Vec<_>>();
        let [mut rz] = add_up(&sums);
        let mut done: [bool; K] = std::array::from_fn(|f| skip[f] || rz[f] <= target[f]);
        let mut iterations = 0;
        while !done.iter().all(|&d| d) {
            if before + iterations == self.options.max_iterations {
                return Err(
                    self.not_converged(before + iterations, worst_relative(&rz, rhs_norm2, &done))
                );
            }
            iterations += 1;

            // q = A p; p·q.
            let sums = q
                .par_chunks_mut(CHUNK)
                .zip(d.par_chunks(CHUNK))
                .enumerate()
                .map(|(c, (qs, ds))| {
                    let mut pq = [0.0; K];
                    let ps = &p[c * CHUNK..c * CHUNK + qs.len()];
                    for (i, ((q, pv), &d)) in qs.iter_mut().zip(ps).zip(ds).enumerate() {
                        let (near, _) =
                            self.neighbour_sum::<f32, K>(c * CHUNK + i, |j| p[j], &signs);
                        for f in 0..K {
                            q[f] = d * pv[f] - t * near[f];
                            pq[f] += f64::from(pv[f] * q[f]);
                        }
                    }
                    [pq]
                })
                .collect::<Vec<_>>();
            let [pq] = add_up(&sums);
            let mut alpha = [0.0f32; K];
            for f in 0..K {
                if !done[f] {
                    alpha[f] = Self::step_length(rz[f], pq[f], before + iterations)? as f32;
                }
            }

            // e += α p, r −= α q; r·D⁻¹r.
            let sums = r
                .par_chunks_mut(CHUNK)
                .zip(e.par_chunks_mut(CHUNK))
                .zip(p.par_chunks(CHUNK))
                .zip(q.par_chunks(CHUNK))
                .zip(d.par_chunks(CHUNK))
                .map(|((((rs, es), ps), qs), ds)| {
                    let mut rz = [0.0; K];
                    for ((((r, e), p), q), &d) in rs.iter_mut().zip(es).zip(ps).zip(qs).zip(ds) {
                        for f in 0..K {
                            e[f] += alpha[f] * p[f];
                            r[f] -= alpha[f] * q[f];
                            rz[f] += f64::from(r[f] * r[f] / d);
                        }
                    }
                    [rz]
                })
                .collect::<Vec<_>>();
            let [next] = add_up(&sums);
            let mut beta = [0.0f32; K];
            for f in 0..K {
                if !done[f] {
                    beta[f] = (next[f] / rz[f]) as f32;
                    rz[f] = next[f];
                    done[f] = rz[f] <= target[f];
                }
            }
            if done.iter().all(|&d| d) {
                break;
            }

            // p = D⁻¹ r + β p (fields already done keep α = 0, so their p no longer matters).
            p.par_chunks_mut(CHUNK)
                .zip(r.par_chunks(CHUNK))
                .zip(d.par_chunks(CHUNK))
                .for_each(|((ps, rs), ds)| {
                    for ((p, r), &d) in ps.iter_mut().zip(rs).zip(ds) {
                        for f in 0..K {
                            p[f] = r[f] / d + beta[f] * p[f];
                        }
                    }
                });
        }
        Ok(iterations)
    }
}

/// Per combination of sign bits (the low bits of an entry), the factor ±1 of each field:
/// one table lookup per entry instead of extracting every field's bit.
type SignTable<T, const K: usize> = [[T; K]; 256];

/// The [`SignTable`] of `K` fields (multiplying by −1 is an exact negation).
fn sign_table<T: Real, const K: usize>() -> SignTable<T, K> {
    std::array::from_fn(|bits| {
        std::array::from_fn(|f| T::from_weight(if (bits >> f) & 1 == 1 { -1.0 } else { 1.0 }))
    })
}

/// Checks the inputs of [`ConnectionSystem::update`] and returns the weights in single
/// precision (the double-precision vector is consumed and freed).
fn single_precision(
    topology: &Topology,
    weights: Vec<f64>,
    mass: &[f64],
    time: f64,
) -> Result<Vec<f32>> {
    let (n, m) = (topology.num_vertices(), topology.num_edges());
    if weights.len() != m || mass.len() != n {
        return Err(Error::InvalidInput(format!(
            "diffusion system: {} weights and {} masses for {m} edges and {n} vertices",
            weights.len(),
            mass.len()
        )));
    }
    if !(time.is_finite() && time >= 0.0) {
        return Err(Error::InvalidInput(format!(
            "diffusion time must be a non-negative number, got {time}"
        )));
    }
    if weights
        .par_iter()
        .any(|&w| !((w as f32).is_finite() && w >= 0.0))
    {
        return Err(Error::InvalidInput(
            "diffusion weights must be non-negative numbers (below 3.4e38)".into(),
        ));
    }
    if mass.par_iter().any(|m| !(m.is_finite() && *m > 0.0)) {
        return Err(Error::InvalidInput(
            "diffusion masses must be positive numbers".into(),
        ));
    }
    Ok(weights.par_iter().map(|&w| w as f32).collect())
}

/// Each single-precision round of the Jacobi solver reduces the residual norm by this factor
/// at most (about 100 single-precision roundings: the true residual of the correction then
/// still follows the recursively updated one).
const ROUND_REDUCTION: f64 = 1e-5;

/// The single-precision vectors of the Jacobi solver: the diagonal, the residual `r`, the
/// search direction `p`, `q = A p` and the correction `e`, all fields of a vertex together.
struct Work<const K: usize> {
    d: Vec<f32>,
    r: Vec<[f32; K]>,
    p: Vec<[f32; K]>,
    q: Vec<[f32; K]>,
    e: Vec<[f32; K]>,
}

/// The largest relative residual `√(r·D⁻¹r / b·D⁻¹b)` among the fields not yet done.
fn worst_relative<const K: usize>(rz: &[f64; K], rhs_norm2: &[f64; K], done: &[bool; K]) -> f64 {
    (0..K)
        .filter(|&f| !done[f])
        .map(|f| (rz[f] / rhs_norm2[f]).sqrt())
        .fold(0.0, f64::max)
}

fn not_finite() -> Error {
    Error::Solver("conjugate gradients: the values to smooth are not finite".into())
}

/// Per-chunk partial sums added in chunk order (deterministic).
fn add_up<const K: usize, const S: usize>(partials: &[[[f64; K]; S]]) -> [[f64; K]; S] {
    let mut total = [[0.0; K]; S];
    for part in partials {
        for (t, p) in total.iter_mut().zip(part) {
            for (a, b) in t.iter_mut().zip(p) {
                *a += b;
            }
        }
    }
    total
}

/// The fields cut into [`CHUNK`]-row pieces, regrouped chunk by chunk (piece `f` of a group
/// belongs to field `f`).
/// Sets the fields that start cold (at zero instead of their values) to zero.
fn zero_cold_fields<const K: usize>(x: &mut [&mut [f64]], cold: &[bool; K]) {
    for (field, _) in x.iter_mut().zip(cold).filter(|(_, cold)| **cold) {
        field.fill(0.0);
    }
}

/// `x += e` for every field.
fn add_correction<const K: usize>(x: &mut [&mut [f64]], e: &[[f32; K]]) {
    field_chunks(x)
        .into_par_iter()
        .zip(e.par_chunks(CHUNK))
        .for_each(|(mut xs, es)| {
            for (i, e) in es.iter().enumerate() {
                for f in 0..K {
                    xs[f][i] += f64::from(e[f]);
                }
            }
        });
}

fn field_chunks<'a>(fields: &'a mut [&mut [f64]]) -> Vec<Vec<&'a mut [f64]>> {
    let mut groups: Vec<Vec<&'a mut [f64]>> = Vec::new();
    for field in fields.iter_mut() {
        for (c, piece) in field.chunks_mut(CHUNK).enumerate() {
            if c == groups.len() {
                groups.push(Vec::new());
            }
            groups[c].push(piece);
        }
    }
    groups
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::TriMesh;
    use crate::shapes;
    use crate::smoothing::{cotan_weights, lumped_mass};

    const BOTH: [Preconditioner; 2] =
        [Preconditioner::Jacobi, Preconditioner::SymmetricGaussSeidel];

    fn system<'m>(
        mesh: &'m TriMesh,
        time: f64,
        flips: &[Option<&[bool]>],
        options: ConjugateGradientOptions,
    ) -> ConnectionSystem<'m> {
        let w = cotan_weights(mesh, mesh.positions());
        let m = lumped_mass(mesh, mesh.positions());
        ConnectionSystem::new(mesh.topology(), w, m, time, flips, options).unwrap()
    }

    /// `(M + t L_σ) u` at every vertex, written out from the definition, with the weights
    /// in the single precision the system stores.
    fn apply(mesh: &TriMesh, time: f64, flips: Option<&[bool]>, u: &[f64]) -> Vec<f64> {
        let mut w = cotan_weights(mesh, mesh.positions());
        round_weights(&mut w);
        let m = lumped_mass(mesh, mesh.positions());
        let topo = mesh.topology();
        (0..mesh.num_vertices())
            .map(|v| {
                let mut out = m[v] * u[v];
                for &e in topo.vertex_edges(v as u32) {
                    let [a, b] = topo.edge(e);
                    let q = if a as usize == v { b } else { a } as usize;
                    let sigma = if flips.is_some_and(|f| f[e as usize]) {
                        -1.0
                    } else {
                        1.0
                    };
                    out += time * w[e as usize] * (u[v] - sigma * u[q]);
                }
                out
            })
            .collect()
    }

    #[test]
    fn solution_satisfies_the_system() {
        let mesh = shapes::torus(3.0, 1.0, 30, 12);
        let flips: Vec<bool> = (0..mesh.topology().num_edges())
            .map(|e| e % 3 == 0)
            .collect();
        let mass = lumped_mass(&mesh, mesh.positions());
        let u0: Vec<f64> = mesh.positions().iter().map(|p| p.x.sin() + p.z).collect();
        let rhs: Vec<f64> = u0.iter().zip(&mass).map(|(u, m)| u * m).collect();
        let scale = rhs.iter().fold(0.0f64, |s, x| s.max(x.abs()));
        for time in [0.01, 0.3] {
            for preconditioner in BOTH {
                let options = ConjugateGradientOptions::DEFAULT
                    .with_tolerance(1e-12)
                    .with_preconditioner(preconditioner);
                let sys = system(&mesh, time, &[None, Some(&flips)], options);
                let (mut a, mut b) = (u0.clone(), u0.clone());
                let iterations = sys.step(&mut [&mut a, &mut b]).unwrap();
                assert!(iterations > 0);
                for (u, f) in [(&a, None), (&b, Some(flips.as_slice()))] {
                    let lhs = apply(&mesh, time, f, u);
                    let worst = lhs
                        .iter()
                        .zip(&rhs)
                        .fold(0.0f64, |s, (l, r)| s.max((l - r).abs()));
                    assert!(
                        worst < 1e-9 * scale,
                        "{preconditioner:?}, t = {time}: residual {worst:e}"
                    );
                }
            }
        }
    }

    #[test]
    fn gauss_seidel_needs_fewer_iterations_than_jacobi() {
        let mesh = shapes::ellipsoid(1.0, 0.7, 0.4, 4);
        let h = crate::mesh::mean_edge_length(&mesh);
        let u0: Vec<f64> = mesh
            .positions()
            .iter()
            .enumerate()
            .map(|(i, p)| p.x * p.y + if i % 2 == 0 { 0.1 } else { -0.1 })
            .collect();
        let iterations =
            [Preconditioner::SymmetricGaussSeidel, Preconditioner::Jacobi].map(|preconditioner| {
                let options = ConjugateGradientOptions::DEFAULT.with_preconditioner(preconditioner);
                let sys = system(&mesh, h * h, &[None], options);
                let mut u = u0.clone();
                sys.step(&mut [&mut u]).unwrap()
            });
        assert!(
            2 * iterations[0] < 3 * iterations[1],
            "Gauss–Seidel {} vs Jacobi {}",
            iterations[0],
            iterations[1]
        );
    }

    #[test]
    fn results_do_not_depend_on_the_thread_count() {
        let mesh = shapes::torus(3.0, 1.0, 60, 24);
        let flips: Vec<bool> = (0..mesh.topology().num_edges())
            .map(|e| e % 7 == 0)
            .collect();
        let u0: Vec<f64> = mesh
            .positions()
            .iter()
            .map(|p| (3.0 * p.x).sin() * p.z)
            .collect();
        for preconditioner in BOTH {
            let run = |threads: usize| {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .unwrap();
                pool.install(|| {
                    let options =
                        ConjugateGradientOptions::DEFAULT.with_preconditioner(preconditioner);
                    let sys = system(&mesh, 0.05, &[Some(&flips), None], options);
                    let (mut a, mut b) = (u0.clone(), u0.clone());
                    sys.step(&mut [&mut a, &mut b]).unwrap();
                    (a, b)
                })
            };
            assert_eq!(run(1), run(3), "{preconditioner:?}");
        }
    }

    #[test]
    fn a_cold_field_starts_at_zero_even_when_no_round_runs() {
        // A rough field under a long step is further from the solution than zero, so it starts
        // at zero; with a tolerance that zero already meets, that is the result.
        let m = shapes::torus(3.0, 1.0, 24, 12);
        let rough: Vec<f64> = (0..m.num_vertices())
            .map(|v| if v % 2 == 0 { 1.0 } else { -1.0 })
            .collect();
        let h = crate::mesh::mean_edge_length(&m);
        for tolerance in [2.0, 1e-8] {
            let options = ConjugateGradientOptions::DEFAULT.with_tolerance(tolerance);
            let s = system(&m, 50.0 * h * h, &[None], options);
            let mut x = rough.clone();
            let iterations = s.step(&mut [&mut x]).unwrap();
            if tolerance > 1.0 {
                assert_eq!(iterations, 0);
                assert!(x.iter().all(|&v| v == 0.0));
            } else {
                assert!(iterations > 0);
                let exact = apply(&m, 50.0 * h * h, None, &x);
                let mass = lumped_mass(&m, m.positions());
                for v in 0..m.num_vertices() {
                    let b = mass[v] * rough[v];
                    assert!((exact[v] - b).abs() < 1e-6 * mass[v], "{v}");
                }
            }
        }
    }

    #[test]
    fn iteration_limit_is_an_error() {
        let mesh = shapes::torus(3.0, 1.0, 30, 12);
        for preconditioner in BOTH {
            let options = ConjugateGradientOptions::DEFAULT
                .with_tolerance(1e-14)
                .with_max_iterations(2)
                .with_preconditioner(preconditioner);
            let sys = system(&mesh, 0.3, &[None], options);
            let mut u: Vec<f64> = mesh.positions().iter().map(|p| p.x * p.y).collect();
            let err = sys.step(&mut [&mut u]).unwrap_err();
            assert!(matches!(err, Error::Solver(_)), "{err}");
            assert!(err.to_string().contains("did not converge"), "{err}");
        }
    }

    #[test]
    fn non_finite_values_are_an_error_not_a_panic() {
        let mesh = shapes::torus(3.0, 1.0, 10, 6);
        for preconditioner in BOTH {
            let options = ConjugateGradientOptions::DEFAULT.with_preconditioner(preconditioner);
            let sys = system(&mesh, 0.3, &[None], options);
            for bad in [f64::NAN, f64::INFINITY] {
                let mut u = vec![1.0; mesh.num_vertices()];
                u[3] = bad;
                let result = sys.step(&mut [&mut u]);
                assert!(matches!(result, Err(Error::Solver(_))), "{result:?}");
            }
        }
    }

    #[test]
    fn rejects_bad_input() {
        let mesh = shapes::torus(3.0, 1.0, 10, 6);
        let w = cotan_weights(&mesh, mesh.positions());
        let m = lumped_mass(&mesh, mesh.positions());
        let topo = mesh.topology();
        let ok = ConjugateGradientOptions::DEFAULT;
        let new = |w: &[f64], m: &[f64], fields: &[Option<&[bool]>], o| {
            ConnectionSystem::new(topo, w.to_vec(), m.to_vec(), 1.0, fields, o)
        };
        assert!(new(&w, &m, &[None], ok.with_tolerance(0.0)).is_err());
        assert!(new(&w, &m, &[None], ok.with_max_iterations(0)).is_err());
        assert!(new(&w, &m, &[], ok).is_err());
        assert!(new(&w, &m, &[None; MAX_FIELDS + 1], ok).is_err());
        assert!(new(&w[1..], &m, &[None], ok).is_err());
        assert!(new(&w, &m, &[Some(&[true; 3])], ok).is_err());
        let mut negative = w.clone();
        negative[0] = -1.0;
        assert!(new(&negative, &m, &[None], ok).is_err());
        let mut zero_mass = m.clone();
        zero_mass[0] = 0.0;
        assert!(new(&w, &zero_mass, &[None], ok).is_err());
        let sys = new(&w, &m, &[None, None], ok).unwrap();
        let mut u = vec![0.0; mesh.num_vertices()];
        assert!(sys.step(&mut [&mut u]).is_err());
        assert!(
            sys.step(&mut [&mut u[1..].to_vec(), &mut u.clone()])
                .is_err()
        );
    }
}
