//! The default solver of [`super::DiffusionOperator`]: the system of [`super::system`],
//! `(M + t L_σ) u' = M u`, solved by Jacobi-preconditioned conjugate gradients in mixed
//! precision, all fields (up to [`MAX_FIELDS`]) in one pass over the matrix.
//!
//! It computes what [`super::system::jacobi_cg`] computes, with three changes for speed (the
//! iterations are bound by memory traffic; see `docs/benchmarks-history.md`, session 5):
//! - **Rows.** The matrix in compressed rows laid out like [`Topology::vertex_edges`], 8 bytes
//!   per entry: the neighbour with the fields' sign bits below it, and `w_pq` as `f32`; the
//!   signs become factors ±1 through a 256-entry table. The weights are rounded to single
//!   precision once ([`round_weights`]), and every solver is given the rounded weights.
//! - **Mixed precision.** Iterative refinement (Higham, *Accuracy and Stability of Numerical
//!   Algorithms*, 2nd ed., ch. 12): rounds of single-precision CG on `A e = r` from `e = 0`,
//!   then `x += e` and `r = b − A x` in double precision. The stopping test is the
//!   double-precision residual `‖r‖₂ ≤ tolerance · ‖b‖₂` of the scaled system, so the
//!   accuracy is that of the plain solver; a round that fails to halve it is an error.
//! - **Warm start.** Each step starts from the previous values, or from zero when that is
//!   closer (a rough field that the step will mostly remove).
//!
//! **Fallback.** On some systems single precision cannot finish: where triangles of almost
//! no area meet cotangent weights at their bound (a surface after a few steps of
//! mean-curvature flow: the cow with `--pre-smooth 3`), rounds of single-precision CG lose
//! their conjugacy and use up the iterations at a residual just above the tolerance. A step
//! that fails in mixed precision is taken again, from its best iterate, by the reference
//! solver of [`super::system`] (double precision, the matrices assembled from these rows;
//! `ConnectionSystem::double_precision_step`), which converges there, and so is every later
//! step of the same system (each attempt would use up the iterations first); an error is
//! returned only when that fails too.
//!
//! Chunks of fixed size are summed in order, so results do not depend on the thread count,
//! and flipping a field's sign at a vertex with the σ of its edges flips the iterates there
//! exactly (the sign-independence of HPW's smoothing).

use rayon::prelude::*;

use super::system::{DiffusionSystem, check_system, jacobi_cg};
use crate::error::{Error, Result};
use crate::mesh::Topology;
use crate::slices::{prefix_sums, split_rows};
use vectors::{Work, add_correction, add_up, not_finite, worst_relative, zero_cold_fields};

/// Rows per parallel work item (fixed so that sums do not depend on the thread count).
const CHUNK: usize = 2048;

/// At most this many fields are solved together (one sign bit each per edge).
pub const MAX_FIELDS: usize = 8;

/// Options of the conjugate-gradient solver.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ConjugateGradientOptions {
    /// Stop when the residual's 2-norm is at most this fraction of the right-hand side's.
    ///
    /// Default: 1e-5. Measured on fandisk, bunny, horse and igea (three HPW steps): the
    /// traced lines are the same as with an exact solve, their total length within 1e-5
    /// relative; at 1e-4 lengths move by up to 1e-4, at 1e-3 a line can appear or vanish.
    pub tolerance: f64,
    /// Give up with [`Error::Solver`] after this many iterations in one step (in mixed
    /// precision, then again per field in the double-precision fallback; module docs).
    ///
    /// Default: 1000 (the shared meshes need 20 to 45 per step).
    pub max_iterations: usize,
}

impl ConjugateGradientOptions {
    /// The default options.
    pub const DEFAULT: Self = ConjugateGradientOptions {
        tolerance: 1e-5,
        max_iterations: 1000,
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

    pub(super) fn validate(&self) -> Result<()> {
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
    /// Where each vertex's row starts in `entries` and `weights` (one more than vertices).
    offsets: Vec<u32>,
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
    /// Set when a step failed in mixed precision: the system for the reference solver, which
    /// takes every later step ([`ConnectionSystem::double_precision_step`]).
    reference: std::sync::OnceLock<DiffusionSystem>,
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

/// Where each vertex's row of [`Topology::vertex_edges`] starts, as compressed-row offsets.
fn row_offsets(topology: &Topology) -> Vec<u32> {
    prefix_sums((0..topology.num_vertices() as u32).map(|v| topology.vertex_edges(v).len() as u32))
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
        let offsets = row_offsets(topology);
        let edges = topology.edges();
        let mut entries = vec![0u32; offsets[n] as usize];
        split_rows(&mut entries, &offsets, CHUNK)
            .into_par_iter()
            .for_each(|(rows, piece)| {
                let base = offsets[rows.start] as usize;
                for v in rows {
                    let row = topology.vertex_edges(v as u32);
                    for (k, &e) in (offsets[v] as usize..).zip(row) {
                        let e = e as usize;
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
            offsets,
            entries,
            weights: Vec::new(),
            flip_bits,
            diagonal: Vec::new(),
            time,
            fields,
            options,
            reference: std::sync::OnceLock::new(),
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
        // A new system: single precision may do again.
        self.reference = std::sync::OnceLock::new();
        Ok(())
    }

    /// Fills the rows' weights and the diagonal from checked per-edge weights.
    fn fill(&mut self, weights: &[f32], mass: &[f64], time: f64) {
        let offsets = &self.offsets;
        // Every entry is written below: a new array is a zeroed allocation (pages the system
        // zeroes on first touch, in parallel below) rather than filled on one thread.
        let mut stored = std::mem::take(&mut self.weights);
        if stored.len() != self.entries.len() {
            stored = vec![0.0; self.entries.len()];
        }
        let mut diagonal = vec![0.0; mass.len()];
        split_rows(&mut stored, offsets, CHUNK)
            .into_par_iter()
            .zip(diagonal.par_chunks_mut(CHUNK))
            .for_each(|((rows, piece), ds)| {
                let base = offsets[rows.start] as usize;
                for (v, d) in rows.zip(ds) {
                    let mut sum = 0.0;
                    let row = self.topology.vertex_edges(v as u32);
                    for (k, &e) in (offsets[v] as usize..).zip(row) {
                        let w = weights[e as usize];
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
        let offsets = &self.offsets;
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
    /// slowest field, per step).
    ///
    /// # Errors
    /// As [`ConnectionSystem::step`].
    pub fn steps(&self, fields: &mut [&mut [f64]], count: usize) -> Result<usize> {
        self.steps_within(fields, count, self.options.tolerance)
    }

    /// [`ConnectionSystem::steps`], each step solved to the relative residual `tolerance`
    /// instead of [`ConjugateGradientOptions::tolerance`] (at least that: a larger of the two
    /// is kept).
    ///
    /// # Errors
    /// As [`ConnectionSystem::step`].
    pub fn steps_within(
        &self,
        fields: &mut [&mut [f64]],
        count: usize,
        tolerance: f64,
    ) -> Result<usize> {
        let tolerance = tolerance.max(self.options.tolerance);
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
        match fields.len() {
            1 => self.solve_jacobi::<1>(fields, count, tolerance),
            2 => self.solve_jacobi::<2>(fields, count, tolerance),
            3 => self.solve_jacobi::<3>(fields, count, tolerance),
            4 => self.solve_jacobi::<4>(fields, count, tolerance),
            5 => self.solve_jacobi::<5>(fields, count, tolerance),
            6 => self.solve_jacobi::<6>(fields, count, tolerance),
            7 => self.solve_jacobi::<7>(fields, count, tolerance),
            _ => self.solve_jacobi::<8>(fields, count, tolerance),
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
        let offsets = &self.offsets;
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

    fn not_converged(&self, iterations: usize, relative: f64, tolerance: f64) -> Error {
        Error::Solver(format!(
            "conjugate gradients did not converge in {iterations} iterations (relative \
             residual {relative:.3e}, tolerance {tolerance:.1e})"
        ))
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
    fn solve_jacobi<const K: usize>(
        &self,
        x: &mut [&mut [f64]],
        steps: usize,
        tolerance: f64,
    ) -> Result<usize> {
        let n = self.diagonal.len();
        let mut work = Work::<K> {
            d: self.diagonal.par_iter().map(|&d| d as f32).collect(),
            r: vec![[0.0; K]; n],
            p: vec![[0.0; K]; n],
            q: vec![[0.0; K]; n],
            e: vec![[0.0; K]; n],
            rhs: Vec::new(),
        };
        let mut iterations = 0;
        for _ in 0..steps {
            if self.reference.get().is_some() {
                iterations += self.double_precision_step(x, None, tolerance)?;
                continue;
            }
            work.rhs.clear();
            match self.jacobi_step(x, &mut work, tolerance) {
                Ok(taken) => iterations += taken,
                Err(single) => {
                    // Later steps and solves go straight to double precision (the reference
                    // system is kept): this system is beyond single precision, and each
                    // attempt would use up the iterations. `x` holds the start values x₀ (no round ended) or the best iterate,
                    // with b = M x₀ stored.
                    let rhs = std::mem::take(&mut work.rhs);
                    let b = |f: usize, v: usize| rhs[v][f];
                    let b: Option<&(dyn Fn(usize, usize) -> f64 + Sync)> =
                        if rhs.is_empty() { None } else { Some(&b) };
                    iterations += self.double_precision_step(x, b, tolerance).map_err(|e| {
                        Error::Solver(format!("{e} (after single precision failed: {single})"))
                    })?;
                }
            }
        }
        Ok(iterations)
    }

    /// One step by the reference solver ([`super::system`]: Jacobi CG in double precision on
    /// the assembled matrix of each field), solving `A x = b` from `x` with `b(f, v)` given,
    /// or `b = M x` for the start values in `x` (`None`): the fallback of a step that mixed
    /// precision cannot finish (see the module docs). The matrices are assembled from these
    /// rows once, at the first fallback. Returns the iterations of the slowest field.
    fn double_precision_step(
        &self,
        x: &mut [&mut [f64]],
        rhs: Option<&(dyn Fn(usize, usize) -> f64 + Sync)>,
        tolerance: f64,
    ) -> Result<usize> {
        let plain = self.reference_system()?;
        // `tolerance` is the step's, already no tighter than the solver's.
        let options = ConjugateGradientOptions {
            tolerance,
            ..self.options
        };
        let n = self.diagonal.len();
        let mut slowest = 0;
        for (f, u) in x.iter_mut().enumerate() {
            let b: Vec<f64> = match rhs {
                Some(rhs) => (0..n).map(|v| rhs(f, v)).collect(),
                None => (0..n).map(|v| self.mass(v) * u[v]).collect(),
            };
            if !b.iter().all(|b| b.is_finite()) {
                return Err(not_finite());
            }
            slowest = slowest.max(jacobi_cg(plain.matrix(f), &b, u, &options)?);
        }
        Ok(slowest)
    }

    /// The same system for the reference solver, assembled from the rows (weights, signs and
    /// the mass recovered from the diagonal) the first time it is asked for.
    fn reference_system(&self) -> Result<&DiffusionSystem> {
        if let Some(plain) = self.reference.get() {
            return Ok(plain);
        }
        let topology = self.topology;
        let m = topology.num_edges();
        let mut weights = vec![0.0; m];
        let mut flips = vec![vec![false; m]; if self.flip_bits > 0 { self.fields } else { 0 }];
        for v in 0..self.diagonal.len() {
            for (&e, (_, w, bits)) in topology.vertex_edges(v as u32).iter().zip(self.row(v)) {
                weights[e as usize] = w;
                for (f, flip) in flips.iter_mut().enumerate() {
                    flip[e as usize] = (bits >> f) & 1 == 1;
                }
            }
        }
        let mass = (0..self.diagonal.len()).map(|v| self.mass(v)).collect();
        let signs: Vec<Option<&[bool]>> = if flips.is_empty() {
            vec![None; self.fields]
        } else {
            flips.iter().map(|f| Some(f.as_slice())).collect()
        };
        let plain =
            DiffusionSystem::assemble(topology, &weights, mass, self.time, &signs, self.options)?;
        Ok(self.reference.get_or_init(|| plain))
    }

    /// One step of [`ConnectionSystem::solve_jacobi`]; returns its iterations.
    fn jacobi_step<const K: usize>(
        &self,
        x: &mut [&mut [f64]],
        work: &mut Work<K>,
        tolerance: f64,
    ) -> Result<usize> {
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
            self.start_cold(x, &mut work.r, &cold);
            for f in (0..K).filter(|&f| cold[f]) {
                rz[f] = rhs_norm2[f];
            }
        }
        let threshold: [f64; K] = std::array::from_fn(|f| tolerance.powi(2) * rhs_norm2[f]);
        let mut done: [bool; K] = std::array::from_fn(|f| rz[f] <= threshold[f]);
        let mut iterations = 0;
        let mut first = true;
        while !done.iter().all(|&d| d) {
            // Each round aims a little below the tolerance (so that one round usually
            // suffices), but no lower than single precision reliably reaches.
            let target: [f64; K] = std::array::from_fn(|f| {
                (0.25 * threshold[f]).max(ROUND_REDUCTION * ROUND_REDUCTION * rz[f])
            });
            iterations +=
                self.correction::<K>(work, target, done, iterations, &rhs_norm2, tolerance)?;
            // The residual of the new iterate in double precision, then x = iterate.
            let next = if first {
                first = false;
                let converged =
                    |next: &[f64; K]| (0..K).all(|f| done[f] || next[f] <= threshold[f]);
                let mut rhs = std::mem::take(&mut work.rhs);
                let next = self.end_first_round(x, work, &cold, converged, &mut rhs);
                work.rhs = rhs;
                next
            } else {
                add_correction(x, &work.e);
                let (x, rhs) = (&*x, &work.rhs);
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
                        tolerance
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

    /// The residual `r = b` of the fields that start `cold` (at zero), in single precision.
    fn start_cold<const K: usize>(&self, x: &[&mut [f64]], r: &mut [[f32; K]], cold: &[bool; K]) {
        r.par_chunks_mut(CHUNK).enumerate().for_each(|(c, rs)| {
            for (i, r) in rs.iter_mut().enumerate() {
                let v = c * CHUNK + i;
                let mass = self.mass(v);
                for f in (0..K).filter(|&f| cold[f]) {
                    r[f] = (mass * x[f][v]) as f32;
                }
            }
        });
    }

    /// After the first round, while `x` still holds the start values `x₀`: the residual of
    /// the iterate `x₀ + e` (`e` for a cold field), then `x` = that iterate. When the residual
    /// is not yet `converged`, `b = M x₀` is stored in `rhs` for the next rounds first.
    /// Returns the residual's `r·D⁻¹r` per field.
    fn end_first_round<const K: usize>(
        &self,
        x: &mut [&mut [f64]],
        work: &mut Work<K>,
        cold: &[bool; K],
        converged: impl Fn(&[f64; K]) -> bool,
        rhs: &mut Vec<[f64; K]>,
    ) -> [f64; K] {
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
        if !converged(&next) {
            *rhs = (0..self.diagonal.len())
                .into_par_iter()
                .with_min_len(CHUNK)
                .map(|v| {
                    let mass = self.mass(v);
                    std::array::from_fn(|f| mass * x[f][v])
                })
                .collect();
        }
        zero_cold_fields(x, cold);
        add_correction(x, &work.e);
        next
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
        tolerance: f64,
    ) -> Result<usize> {
        let signs = sign_table::<f32, K>();
        let mut rz = work.start_correction();
        let mut done: [bool; K] = std::array::from_fn(|f| skip[f] || rz[f] <= target[f]);
        let mut iterations = 0;
        while !done.iter().all(|&d| d) {
            if before + iterations == self.options.max_iterations {
                return Err(self.not_converged(
                    before + iterations,
                    worst_relative(&rz, rhs_norm2, &done),
                    tolerance,
                ));
            }
            iterations += 1;

            let pq = self.multiply_direction(work, &signs);
            let mut alpha = [0.0f32; K];
            for f in 0..K {
                if !done[f] {
                    alpha[f] = Self::step_length(rz[f], pq[f], before + iterations)? as f32;
                }
            }

            let next = work.advance(&alpha);
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

            // Fields already done keep α = 0, so their p no longer matters.
            work.next_direction(&beta);
        }
        Ok(iterations)
    }
    /// `q = A p` in single precision; returns `p·q` per field.
    fn multiply_direction<const K: usize>(
        &self,
        work: &mut Work<K>,
        signs: &SignTable<f32, K>,
    ) -> [f64; K] {
        let Work { d, p, q, .. } = work;
        let t = self.time as f32;
        let sums = q
            .par_chunks_mut(CHUNK)
            .zip(d.par_chunks(CHUNK))
            .enumerate()
            .map(|(c, (qs, ds))| {
                let mut pq = [0.0; K];
                let ps = &p[c * CHUNK..c * CHUNK + qs.len()];
                for (i, ((q, pv), &d)) in qs.iter_mut().zip(ps).zip(ds).enumerate() {
                    let (near, _) = self.neighbour_sum::<f32, K>(c * CHUNK + i, |j| p[j], signs);
                    for f in 0..K {
                        q[f] = d * pv[f] - t * near[f];
                        pq[f] += f64::from(pv[f] * q[f]);
                    }
                }
                [pq]
            })
            .collect::<Vec<_>>();
        let [pq] = add_up(&sums);
        pq
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
    check_system(topology, &weights, mass, time)?;
    Ok(weights.par_iter().map(|&w| w as f32).collect())
}

/// Each single-precision round of the Jacobi solver reduces the residual norm by this factor
/// at most (about 100 single-precision roundings: the true residual of the correction then
/// still follows the recursively updated one).
const ROUND_REDUCTION: f64 = 1e-5;

#[cfg(test)]
mod tests;
mod vectors;
