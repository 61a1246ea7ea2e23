//! The weighted least-squares polynomial of a jet fit ([`super`], step 3) and the differential
//! quantities at its origin (step 4).

use super::Sample;
use crate::curvature::{VertexEstimate, symmetric_eigen_2x2, tangent_frame};
use crate::mesh::Vec3;

/// `sqrt(binomial(k, a))` for the monomial `x^a y^(k−a)` of degree k, in the order of
/// [`monomials`]: in the basis of the monomials times these, a rotation of the tangent frame
/// acts on coefficients by an orthogonal matrix. The fit's regularisation is the identity in
/// that basis, so the fit does not depend on how the frame is turned (the frame follows the
/// coordinate axes): on discs that leave some terms almost undetermined (the rows of CAD
/// grids and fans, where the smallest eigenvalue of the normal equations falls to 1e-14 of
/// the largest), a regularisation that is the identity in the plain monomials made the
/// curvature of fandisk change by up to its whole size under a rotation of the model.
const ROTATION_SCALE: [f64; 15] = [
    1.0,
    1.0,
    1.0,
    1.0,
    std::f64::consts::SQRT_2,
    1.0,
    1.0,
    1.732_050_807_568_877_2,
    1.732_050_807_568_877_2,
    1.0,
    1.0,
    2.0,
    2.449_489_742_783_178,
    2.0,
    1.0,
];

/// The monomials `x^i y^j` of total degree up to 4, by degree, x's power decreasing: 1, x, y,
/// x², xy, y², x³, …, y⁴ (the first `N` of them).
#[inline(always)]
fn monomials<const N: usize>(x: f64, y: f64) -> [f64; N] {
    let (x2, y2) = (x * x, y * y);
    let all = [
        1.0,
        x,
        y,
        x2,
        x * y,
        y2,
        x2 * x,
        x2 * y,
        x * y2,
        y2 * y,
        x2 * x2,
        x2 * x * y,
        x2 * y2,
        x * y2 * y,
        y2 * y2,
    ];
    std::array::from_fn(|i| all[i])
}

/// A fitted height polynomial (in units of the radius), its weighted RMS residual, and the
/// polynomial fitted to the samples' simulated noise instead of their heights.
#[derive(Clone, Copy)]
pub(super) struct Fit {
    /// Coefficients in [`monomials`] order; at most 15 (unused ones are zero).
    pub(super) coef: [f64; 15],
    /// The same for the simulated noise (NaN in a fit of the heights alone: [`solve`]).
    noise_coef: [f64; 15],
    /// The same for the squared heights (`Σ w z² m` on the right): the fit of the curved
    /// heights `z + (c/2) z²` is `coef + (c/2) square_coef` ([`Fit::curved`]; NaN in a fit
    /// of the heights alone).
    square_coef: [f64; 15],
    pub(super) degree: usize,
    pub(super) residual: f64,
    /// The weighted RMS residual that white noise of unit variance in the heights leaves
    /// in expectation (less than 1: the fit takes up part of the noise); NaN unless the
    /// residual is measured.
    pub(super) noise_residual: f64,
    /// The smallest ratio of a Cholesky pivot to the diagonal entry of the normal equations
    /// it comes from: near 1 for samples spread over the disc, at the level of the
    /// regularisation (1e-12) where the samples cannot tell a monomial from the others, as
    /// on two or three rows of vertices.
    pub(super) conditioning: f64,
}

/// The weighted least-squares fit of `samples` by the first `N` monomials; the residual is
/// measured only when `residual` (NaN otherwise).
///
/// By the normal equations `(Σ w m mᵀ) c = Σ w z m` (m the monomials of a sample), solved by
/// Cholesky, with the simulated noise `Σ w ξ m` and the squared heights `Σ w z² m` as further
/// right-hand sides when `K` is 3; when `K` is 1 the heights alone (a fit read only for its
/// coefficients: the other columns are NaN). Each right-hand side's arithmetic is the same
/// either way. The arithmetic is that of nalgebra's `syger`, `cholesky` and `solve`,
/// operation for operation and in the same order, so the results are theirs to the bit
/// (test below); written out on fixed-size arrays, without the dynamically sized views
/// nalgebra's routines work on.
pub(super) fn solve<const N: usize, const K: usize>(
    samples: &[Sample],
    degree: usize,
    residual: bool,
) -> Option<Fit> {
    let (ata, rhs, weight) = normal_equations::<N, K>(samples);
    solve_system(ata, rhs, weight, samples, degree, residual).map(|(fit, _)| fit)
}

/// The cubic and the quartic fit of the same samples ([`solve_nested`]).
pub(super) struct Nested {
    pub(super) cubic: Fit,
    pub(super) quartic: Fit,
    /// The variance of the difference of the two fits' Hessians (squared Frobenius norm of
    /// `(2c₃, c₄; c₄, 2c₅)`, coefficient units) under white noise of unit variance in the
    /// heights: `Σ w² |m · (u₄ − u₃)|²` over the samples, with `u = M⁻¹ g` for each Hessian
    /// functional g and the normal matrix M of each fit.
    pub(super) extra_variance: f64,
}

/// The cubic and the quartic fit of `samples` (without residuals), from one set of normal
/// equations: the cubic's are the leading block of the quartic's, entry for entry, so the
/// cubic is [`solve`]'s to the bit. `None` unless both can be solved.
pub(super) fn solve_nested(samples: &[Sample]) -> Option<Nested> {
    let (ata, rhs, weight) = normal_equations::<15, 3>(samples);
    let ata3: [[f64; 10]; 10] = std::array::from_fn(|j| std::array::from_fn(|i| ata[j][i]));
    let rhs3: [[f64; 3]; 10] = std::array::from_fn(|i| rhs[i]);
    let (cubic, l3) = solve_system(ata3, rhs3, weight, samples, 3, false)?;
    let (quartic, l4) = solve_system(ata, rhs, weight, samples, 4, false)?;
    // The Hessian's entries as functionals of the coefficients, scaled for the Frobenius
    // norm: h_xx = 2 c₃, h_xy = c₄ (twice), h_yy = 2 c₅; one right-hand side each, solved
    // together (each column's arithmetic is that of a solve of its own).
    let functionals = [(3, 2.0), (4, std::f64::consts::SQRT_2), (5, 2.0)];
    let (mut g4, mut g3) = ([[0.0; 3]; 15], [[0.0; 3]; 10]);
    for (t, (k, scale)) in functionals.into_iter().enumerate() {
        g4[k][t] = scale;
        g3[k][t] = scale;
    }
    let (u4, u3) = (solve_factored(&l4, g4), solve_factored(&l3, g3));
    // `u₄ − u₃` by rows (`difference[i][t]`: coefficient i of functional t).
    let difference: [[f64; 3]; 15] = std::array::from_fn(|i| {
        std::array::from_fn(|t| u4[i][t] - if i < 10 { u3[i][t] } else { 0.0 })
    });
    let mut extra_variance = 0.0;
    for s in samples {
        let m = monomials::<15>(s.x, s.y);
        for d in dot_columns(&m, &difference) {
            let a = s.w * d;
            extra_variance += a * a;
        }
    }
    Some(Nested {
        cubic,
        quartic,
        extra_variance,
    })
}

/// [`solve`] from the normal equations ([`normal_equations`]); also returns the Cholesky
/// factor of the (regularised) normal matrix.
fn solve_system<const N: usize, const K: usize>(
    mut ata: [[f64; N]; N],
    rhs: [[f64; K]; N],
    weight: f64,
    samples: &[Sample],
    degree: usize,
    residual: bool,
) -> Option<(Fit, [[f64; N]; N])> {
    if weight.is_nan() || weight <= 0.0 {
        return None;
    }
    // A whisper of ridge regularisation keeps nearly collinear discs solvable. It is the
    // identity in the rotation-orthogonal basis (`ROTATION_SCALE`), so that it does not
    // depend on how the tangent frame is turned.
    let diagonal: [f64; N] = std::array::from_fn(|k| ata[k][k]);
    let trace = diagonal.iter().fold(0.0, |sum, d| sum + d);
    let ridge = 1e-12 * trace / N as f64;
    for (k, column) in ata.iter_mut().enumerate() {
        column[k] += ridge / (ROTATION_SCALE[k] * ROTATION_SCALE[k]);
    }
    if !cholesky(&mut ata) {
        return None;
    }
    let l = ata;
    let conditioning = (0..N).fold(f64::INFINITY, |least, k| {
        least.min(l[k][k] * l[k][k] / diagonal[k])
    });
    let solution = solve_factored(&l, rhs);
    let x: [f64; N] = std::array::from_fn(|i| solution[i][0]);
    if !x.iter().all(|c| c.is_finite()) {
        return None;
    }
    let mut coef = [0.0; 15];
    coef[..N].copy_from_slice(&x);
    let column = |k: usize| -> [f64; 15] {
        if k >= K {
            return [f64::NAN; 15];
        }
        let mut c = [0.0; 15];
        for (c, s) in c.iter_mut().zip(&solution) {
            *c = s[k];
        }
        c
    };
    let (noise_coef, square_coef) = (column(1), column(2));
    // With white noise of unit variance in the heights the expected weighted residual sum
    // is `Σ w − Σ w² mᵀ M⁻¹ m` (M the normal matrix; `mᵀ M⁻¹ m = |L⁻¹ m|²`): the fit takes
    // up part of the noise.
    let (mut sq, mut noise_sq) = (f64::NAN, f64::NAN);
    if residual {
        (sq, noise_sq) = (0.0, weight);
        let heights: [[f64; 1]; N] = x.map(|c| [c]);
        for s in samples {
            let m = monomials::<N>(s.x, s.y);
            let [fitted] = dot_columns(&m, &heights);
            let r = fitted - s.z;
            sq += s.w * r * r;
            noise_sq -= s.w * s.w * forward_squared(&l, m);
        }
    }
    let fit = Fit {
        coef,
        noise_coef,
        square_coef,
        degree,
        residual: (sq / weight).sqrt(),
        noise_residual: (noise_sq / weight).sqrt(),
        conditioning,
    };
    Some((fit, l))
}

/// The normal equations of the fit by the first `N` monomials: `Σ w m mᵀ` (`ata[j][i]` is
/// entry (i, j) for i ≥ j: the columns of its lower triangle, the one the factorisation
/// reads), the first `K` of the right-hand sides `Σ w z m`, `Σ w ξ m` and `Σ w z² m` side by
/// side (`rhs[i]`, solved together), and `Σ w`. A function of its own: inlined into [`solve`], its loop was
/// compiled with the accumulators spilled. (Its index loops compile to faster code than
/// `iter_mut().enumerate()` and `zip` did: 17% against 22% of igea's extract in perf.)
#[inline(never)]
#[allow(clippy::needless_range_loop)]
fn normal_equations<const N: usize, const K: usize>(
    samples: &[Sample],
) -> ([[f64; N]; N], [[f64; K]; N], f64) {
    const {
        assert!(
            K == 1 || K == 3,
            "the heights alone, or all three right-hand sides"
        )
    };
    let mut ata = [[0.0f64; N]; N];
    let mut rhs = [[0.0f64; K]; N];
    let mut weight = 0.0;
    for s in samples {
        let m = monomials::<N>(s.x, s.y);
        for j in 0..N {
            let wm = s.w * m[j];
            // From an even row, so that rows go in pairs (vectorised); the one entry above
            // the diagonal this adds in odd columns is never read.
            for i in (j & !1)..N {
                ata[j][i] += wm * m[i];
            }
        }
        let wv = [s.w * s.z, s.w * s.xi, s.w * s.z * s.z];
        for i in 0..N {
            // K is 1 or 3, written out: a loop over the columns compiled to slower code.
            rhs[i][0] += wv[0] * m[i];
            if K == 3 {
                rhs[i][1] += wv[1] * m[i];
                rhs[i][2] += wv[2] * m[i];
            }
        }
        weight += s.w;
    }
    (ata, rhs, weight)
}

/// Replaces the symmetric matrix whose lower triangle is given by columns (`a[j][i]`, i ≥ j)
/// by its Cholesky factor L (`a = L Lᵀ`), in the same layout; false unless it is positive
/// definite (a pivot zero, negative or NaN). Column by column, each updated by the columns
/// before it.
fn cholesky<const N: usize>(a: &mut [[f64; N]; N]) -> bool {
    for j in 0..N {
        let (done, rest) = a.split_at_mut(j);
        let column = &mut rest[0];
        for previous in done.iter() {
            let l_jk = previous[j];
            for i in j..N {
                column[i] -= l_jk * previous[i];
            }
        }
        let pivot = column[j];
        if pivot.is_nan() || pivot <= 0.0 {
            return false;
        }
        let pivot = pivot.sqrt();
        column[j] = pivot;
        for value in &mut column[j + 1..] {
            *value /= pivot;
        }
    }
    true
}

/// `|L⁻¹ m|²` for L from [`cholesky`] (`mᵀ (L Lᵀ)⁻¹ m`).
fn forward_squared<const N: usize>(l: &[[f64; N]; N], mut m: [f64; N]) -> f64 {
    let mut sum = 0.0;
    for i in 0..N {
        let y = m[i] / l[i][i];
        sum += y * y;
        for k in i + 1..N {
            m[k] -= y * l[i][k];
        }
    }
    sum
}

/// Solves `L Lᵀ x = b` for K right-hand sides (`b[i]` = row i of all), L from
/// [`cholesky`]: forward substitution, then back substitution with `Lᵀ`.
fn solve_factored<const N: usize, const K: usize>(
    l: &[[f64; N]; N],
    mut b: [[f64; K]; N],
) -> [[f64; K]; N] {
    for i in 0..N {
        let y = b[i].map(|v| v / l[i][i]);
        b[i] = y;
        for k in i + 1..N {
            for t in 0..K {
                b[k][t] -= y[t] * l[i][k];
            }
        }
    }
    for i in (0..N).rev() {
        let (row, below) = b[i..].split_at_mut(1);
        let done = dot_columns(&l[i][i + 1..], below);
        for t in 0..K {
            row[0][t] = (row[0][t] - done[t]) / l[i][i];
        }
    }
    b
}

/// `Σ a[k] b[k][t]` for each column t of `b`, each summed in the order of nalgebra's `dot`:
/// eight partial sums per block of eight, then the rest one by one (the order decides the
/// rounding). The columns side by side in one loop: with a closure per column the back
/// substitution was compiled to a call per column and row.
#[inline(always)]
fn dot_columns<const K: usize>(a: &[f64], b: &[[f64; K]]) -> [f64; K] {
    let mut sum = [0.0; K];
    let mut start = 0;
    while a.len() - start >= 8 {
        let mut p = [[0.0; K]; 8];
        for (k, p) in p.iter_mut().enumerate() {
            for t in 0..K {
                p[t] = 0.0 + a[start + k] * b[start + k][t];
            }
        }
        for t in 0..K {
            sum[t] += p[0][t] + p[4][t];
            sum[t] += p[1][t] + p[5][t];
            sum[t] += p[2][t] + p[6][t];
            sum[t] += p[3][t] + p[7][t];
        }
        start += 8;
    }
    for k in start..a.len() {
        for t in 0..K {
            sum[t] += a[k] * b[k][t];
        }
    }
    sum
}

/// The principal curvature of largest magnitude of the heights with Taylor coefficients
/// `c` (in units of the radius).
fn dominant_curvature(c: &[f64; 15]) -> f64 {
    let (k_max, k_min, _) = symmetric_eigen_2x2(-2.0 * c[3], -c[4], -2.0 * c[5]);
    if k_max.abs() >= k_min.abs() {
        k_max
    } else {
        k_min
    }
}

impl Fit {
    /// `cubic + λ (quartic − cubic)`, λ in [0, 1]: coefficients, noise coefficients; the
    /// quartic's residuals and conditioning. The cubic where the blend is not finite.
    pub(super) fn blend(cubic: Fit, quartic: Fit, lambda: f64) -> Fit {
        if lambda.is_nan() || lambda <= 0.0 {
            return cubic;
        }
        if lambda >= 1.0 {
            return quartic;
        }
        let mix = |a: &[f64; 15], b: &[f64; 15]| -> [f64; 15] {
            std::array::from_fn(|i| a[i] + lambda * (b[i] - a[i]))
        };
        let fit = Fit {
            coef: mix(&cubic.coef, &quartic.coef),
            noise_coef: mix(&cubic.noise_coef, &quartic.noise_coef),
            square_coef: mix(&cubic.square_coef, &quartic.square_coef),
            degree: 4,
            residual: quartic.residual,
            noise_residual: quartic.noise_residual,
            conditioning: quartic.conditioning,
        };
        if fit
            .coef
            .iter()
            .chain(&fit.noise_coef)
            .all(|c| c.is_finite())
        {
            fit
        } else {
            cubic
        }
    }

    /// The better of this fit and the fit of the *curved heights* `P = z + (c/2) z²` of the
    /// same samples, c the principal curvature of largest magnitude (in units of the radius)
    /// of that curved fit itself (iterated from this fit's): whichever leaves the smaller
    /// weighted residual in the heights, or the curved one wherever it is made when
    /// `keep_curved` is the noise's standard deviation (in units of the radius; on white
    /// noise, where the residuals' difference is the noise's: see the parent module's docs,
    /// step 3; the residual is then not measured); and the other one (`None` where the
    /// curved fit is not made: below the third degree, on flat discs, where it is not
    /// finite, or where the sphere of curvature c does not reach over the disc, to within
    /// twice that noise when it is given).
    ///
    /// The heights of a sphere or a circular cylinder of curvature c over its tangent plane,
    /// `z = −(1 − √(1 − c²ρ²))/c`, are a series that converges only within its radius of
    /// curvature, slowly near it; their curved heights are the quadratic `−(c/2)ρ²`. Where the
    /// disc is not much smaller than the radius of curvature (a torus's tube, coarse
    /// meshes, the wide discs of noisy ones), a polynomial of the heights leaves a
    /// truncation error that the extremalities take up as a bias; one of the curved heights
    /// leaves less. The curved heights are an implicit surface with a sphere's quadratic
    /// term in z, as in the algebraic spheres of Guennebaud and Gross (*Algebraic point set
    /// surfaces*, SIGGRAPH 2007). By linearity the fit of P is `coef + (c/2) square_coef`;
    /// the heights are `z = f(P) = 2P / (1 + √(1 + 2cP))`, whose Taylor coefficients at the
    /// origin up to the third order follow by the chain rule (the fourth-order ones are set
    /// to zero: nothing reads them). The simulated noise's coefficients are kept: `f′ ≈ 1`
    /// near the origin. Where the residual is measured, it becomes the kept fit's.
    pub(super) fn curved(self, samples: &[Sample], keep_curved: Option<f64>) -> (Fit, Option<Fit>) {
        if self.degree < 3 {
            return (self, None);
        }
        // c is the curved fit's own dominant curvature: from the heights' fit first, then
        // from the curved fit it gives, until it settles (each step takes c's error down by
        // the truncation error's share: 3% → 0.1% on a sphere as wide as the disc).
        let mut bend = dominant_curvature(&self.coef);
        for _ in 0..10 {
            let Some(coef) = self.curved_taylor(bend) else {
                return (self, None);
            };
            let next = dominant_curvature(&coef);
            let settled = (next - bend).abs() <= 1e-12 * bend.abs();
            bend = next;
            if settled {
                break;
            }
        }
        let Some(coef) = self.curved_taylor(bend) else {
            return (self, None);
        };
        let t = self.curved_coefficients(bend);
        // The curved surface z = f(P) must reach over the whole disc: 1 + 2cP ≥ 0 at every
        // sample (else the disc is wider than the sphere it describes; the model fails). On
        // white noise (`keep_curved`, the noise σ) to within 2σ in P: `1 + 2cP ≥ −4|c|σ`.
        let slack = keep_curved.map_or(0.0, |sigma| 4.0 * bend.abs() * sigma);
        let (mut plain, mut curved, mut weight) = (0.0, 0.0, 0.0);
        for s in samples {
            let m = monomials::<15>(s.x, s.y);
            let (mut p, mut q) = (0.0, 0.0);
            for i in 0..15 {
                p += m[i] * self.coef[i];
                q += m[i] * t[i];
            }
            let root = 1.0 + 2.0 * bend * q;
            if root.is_nan() || root < -slack {
                return (self, None);
            }
            if keep_curved.is_none() {
                let (a, b) = (p - s.z, 2.0 * q / (1.0 + root.sqrt()) - s.z);
                plain += s.w * a * a;
                curved += s.w * b * b;
                weight += s.w;
            }
        }
        if keep_curved.is_some() {
            // Kept whatever the residuals say, which are not measured.
            debug_assert!(
                self.residual.is_nan(),
                "no residual is read where keep_curved"
            );
            return (Fit { coef, ..self }, Some(self));
        }
        let residual = if self.residual.is_nan() {
            f64::NAN
        } else {
            (curved / weight).sqrt()
        };
        let fit = Fit {
            coef,
            residual,
            ..self
        };
        if curved < plain {
            (fit, Some(self))
        } else {
            (self, Some(fit))
        }
    }

    /// The coefficients of the fit of the curved heights `z + (c/2) z²` (`c` = `bend`): by
    /// linearity, the heights' plus c/2 times the squared heights'.
    fn curved_coefficients(&self, bend: f64) -> [f64; 15] {
        std::array::from_fn(|i| self.coef[i] + 0.5 * bend * self.square_coef[i])
    }

    /// The Taylor coefficients at the origin, to the third order, of the heights
    /// `z = f(P) = 2P / (1 + √(1 + 2cP))` of the fit of the curved heights `P = z + (c/2) z²`
    /// (`c` = `bend`), by the chain rule; `None` where f is not defined at the origin or the
    /// result is not finite.
    fn curved_taylor(&self, bend: f64) -> Option<[f64; 15]> {
        if !bend.is_finite() || bend == 0.0 {
            return None;
        }
        let t = self.curved_coefficients(bend);
        let q = 1.0 + 2.0 * bend * t[0];
        if q.is_nan() || q <= 0.0 {
            return None;
        }
        // Derivatives of f at P(0), and of P at the origin.
        let f1 = 1.0 / q.sqrt();
        let f2 = -bend * f1 / q;
        let f3 = 3.0 * bend * bend * f1 / (q * q);
        let g = [t[1], t[2]];
        let h = [[2.0 * t[3], t[4]], [t[4], 2.0 * t[5]]];
        // Third derivatives of P by the number of y's among the three indices.
        let d3 = [6.0 * t[6], 2.0 * t[7], 2.0 * t[8], 6.0 * t[9]];
        let second = |i: usize, j: usize| f1 * h[i][j] + f2 * g[i] * g[j];
        let third = |i: usize, j: usize, k: usize| {
            f1 * d3[i + j + k]
                + f2 * (h[i][j] * g[k] + h[i][k] * g[j] + h[j][k] * g[i])
                + f3 * g[i] * g[j] * g[k]
        };
        let mut coef = [0.0; 15];
        coef[0] = 2.0 * t[0] / (1.0 + q.sqrt());
        coef[1] = f1 * g[0];
        coef[2] = f1 * g[1];
        coef[3] = 0.5 * second(0, 0);
        coef[4] = second(0, 1);
        coef[5] = 0.5 * second(1, 1);
        coef[6] = third(0, 0, 0) / 6.0;
        coef[7] = 0.5 * third(0, 0, 1);
        coef[8] = 0.5 * third(0, 1, 1);
        coef[9] = third(1, 1, 1) / 6.0;
        coef.iter().all(|c| c.is_finite()).then_some(coef)
    }

    /// The Hessian of the height (model units) as (h_xx, h_xy, h_yy), the coordinates
    /// having been divided by `r`.
    pub(super) fn hessian(&self, r: f64) -> [f64; 3] {
        let c = &self.coef;
        [2.0 * c[3] / r, c[4] / r, 2.0 * c[5] / r]
    }

    /// Curvatures, directions and extremalities at the origin of a fit in the frame of
    /// `normal`, the coordinates having been divided by `r`; the extremalities of the fit to
    /// the simulated noise along the same directions; and those of `other` (the other model
    /// of the same samples, [`Fit::curved`]) along the same directions (the estimate's own
    /// without one).
    pub(super) fn estimate(
        &self,
        normal: Vec3,
        r: f64,
        other: Option<&Fit>,
    ) -> (VertexEstimate, [f64; 2], [f64; 2]) {
        let c = &self.coef;
        // Derivatives of h in model units: h_xx = H_XX / r, h_xxx = H_XXX / r².
        let (hxx, hxy, hyy) = (2.0 * c[3] / r, c[4] / r, 2.0 * c[5] / r);
        let (k_max, k_min, t) = symmetric_eigen_2x2(-hxx, -hxy, -hyy);
        let (u, w, n) = tangent_frame(normal);
        let tmin = [-t[1], t[0]];
        let [e_max, e_min] = self.extremalities(c, t, r);
        let estimate = VertexEstimate {
            k_max,
            k_min,
            dir_max: u * t[0] + w * t[1],
            dir_min: u * tmin[0] + w * tmin[1],
            e_max,
            e_min,
            normal: n,
            fallback: false,
        };
        let noise = self.extremalities(&self.noise_coef, t, r);
        let alternative = other
            .map(|other| other.extremalities(&other.coef, t, r))
            .filter(|e| e.iter().all(|x| x.is_finite()))
            .unwrap_or([e_max, e_min]);
        (estimate, noise, alternative)
    }

    /// `e = −D³h[t, t, t]` along the unit tangent `t` (frame coordinates) and along its
    /// perpendicular, for coefficients `c` of a polynomial in units of `r` (0 below the
    /// third degree).
    fn extremalities(&self, c: &[f64; 15], t: [f64; 2], r: f64) -> [f64; 2] {
        if self.degree < 3 {
            return [0.0; 2];
        }
        let (hxxx, hxxy, hxyy, hyyy) = (6.0 * c[6], 2.0 * c[7], 2.0 * c[8], 6.0 * c[9]);
        let third = |a: f64, b: f64| {
            -(hxxx * a * a * a + 3.0 * hxxy * a * a * b + 3.0 * hxyy * a * b * b + hyyy * b * b * b)
                / (r * r)
        };
        [third(t[0], t[1]), third(-t[1], t[0])]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{SMatrix, SVector};

    /// The fit as nalgebra computes it (`syger`, `cholesky`, `solve`, `dot`): coefficients,
    /// noise coefficients and residual.
    fn nalgebra_fit<const N: usize>(samples: &[Sample]) -> Option<([f64; N], [f64; N], f64)> {
        let mut ata = SMatrix::<f64, N, N>::zeros();
        let mut atb = SVector::<f64, N>::zeros();
        let mut atxi = SVector::<f64, N>::zeros();
        let mut weight = 0.0;
        for s in samples {
            let m = SVector::<f64, N>::from(monomials::<N>(s.x, s.y));
            ata.syger(s.w, &m, &m, 1.0);
            atb.axpy(s.w * s.z, &m, 1.0);
            atxi.axpy(s.w * s.xi, &m, 1.0);
            weight += s.w;
        }
        let ridge = 1e-12 * ata.trace() / N as f64;
        for k in 0..N {
            ata[(k, k)] += ridge / (ROTATION_SCALE[k] * ROTATION_SCALE[k]);
        }
        let chol = ata.cholesky()?;
        let x = chol.solve(&atb);
        let mut sq = 0.0;
        for s in samples {
            let r = SVector::<f64, N>::from(monomials::<N>(s.x, s.y)).dot(&x) - s.z;
            sq += s.w * r * r;
        }
        let noise = chol.solve(&atxi);
        Some((x.into(), noise.into(), (sq / weight).sqrt()))
    }

    /// Pseudo-random numbers in [0, 1) (xorshift) from `seed`.
    fn uniform(mut state: u64) -> impl FnMut() -> f64 {
        move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    /// `count` points drawn in [−1, 1]², those with x² + y² < `max_d2` kept as samples with
    /// the fit's kernel weight at `height(x, y, next)` (which may draw its noise from `next`)
    /// and simulated noise uniform in [−½, ½].
    fn kernel_disc(
        seed: u64,
        count: usize,
        max_d2: f64,
        mut height: impl FnMut(f64, f64, &mut dyn FnMut() -> f64) -> f64,
    ) -> Vec<Sample> {
        let mut next = uniform(seed);
        (0..count)
            .filter_map(|_| {
                let (x, y) = (2.0 * next() - 1.0, 2.0 * next() - 1.0);
                let d2 = x * x + y * y;
                if d2 >= max_d2 {
                    return None;
                }
                let z = height(x, y, &mut next);
                Some(Sample {
                    x,
                    y,
                    z,
                    w: (1.0 - d2).powi(2),
                    xi: next() - 0.5,
                })
            })
            .collect()
    }

    /// Discs of pseudo-random samples: full ones, and rows along a rim with a nearly
    /// singular system, as on CAD strips.
    fn discs() -> Vec<Vec<Sample>> {
        let mut next = uniform(0x9E37_79B9_7F4A_7C15);
        (0..200)
            .map(|d| {
                (0..20 + d % 70)
                    .map(|_| {
                        let (mut x, mut y) = (2.0 * next() - 1.0, 2.0 * next() - 1.0);
                        if d % 5 == 0 {
                            (x, y) = (0.5 * x, 0.9 + 1e-5 * y);
                        }
                        let w = (1.0 - (x * x + y * y)).max(0.0).powi(2) * (0.5 + next());
                        let z = 0.3 * x * x - 0.1 * x * y + 0.05 * y * y * y + 1e-3 * next();
                        Sample {
                            x,
                            y,
                            z,
                            w,
                            xi: next() - 0.5,
                        }
                    })
                    .collect()
            })
            .collect()
    }

    fn check<const N: usize>(degree: usize) {
        for samples in discs() {
            let fit = solve::<N, 3>(&samples, degree, true);
            let reference = nalgebra_fit::<N>(&samples);
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            // The heights alone: the same coefficients, residual and conditioning.
            let heights = solve::<N, 1>(&samples, degree, true);
            assert_eq!(heights.is_some(), fit.is_some());
            if let (Some(heights), Some(fit)) = (heights, fit) {
                assert_eq!(bits(&heights.coef), bits(&fit.coef));
                assert_eq!(heights.residual.to_bits(), fit.residual.to_bits());
                assert_eq!(heights.conditioning.to_bits(), fit.conditioning.to_bits());
                assert!(heights.noise_coef.iter().all(|c| c.is_nan()));
            }
            match (fit, reference) {
                (Some(fit), Some((coef, noise, residual))) => {
                    assert_eq!(bits(&fit.coef[..N]), bits(&coef));
                    assert_eq!(bits(&fit.noise_coef[..N]), bits(&noise));
                    assert_eq!(fit.residual.to_bits(), residual.to_bits());
                }
                (fit, reference) => assert!(fit.is_none() && reference.is_none()),
            }
        }
    }

    #[test]
    fn nested_fits_are_the_single_fits() {
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        for samples in discs() {
            let (Some(cubic), Some(quartic)) = (
                solve::<10, 3>(&samples, 3, false),
                solve::<15, 3>(&samples, 4, false),
            ) else {
                continue;
            };
            let Nested {
                cubic: nested_cubic,
                quartic: nested_quartic,
                extra_variance,
            } = solve_nested(&samples).unwrap();
            assert!(extra_variance >= 0.0);
            assert_eq!(bits(&nested_cubic.coef), bits(&cubic.coef));
            assert_eq!(bits(&nested_cubic.noise_coef), bits(&cubic.noise_coef));
            assert_eq!(bits(&nested_quartic.coef), bits(&quartic.coef));
            assert_eq!(bits(&nested_quartic.noise_coef), bits(&quartic.noise_coef));
        }
    }

    #[test]
    fn extra_variance_is_that_of_fits_to_white_noise() {
        // Heights of pure noise (uniform, unit variance), refitted many times on full discs
        // and on one-sided ones: the mean squared difference of the two Hessians.
        let mut uniform = uniform(0x2545_F491_4F6C_DD1D);
        for (d, mut samples) in discs().into_iter().enumerate().take(12) {
            if d % 5 == 0 {
                continue;
            }
            if d % 2 == 1 {
                samples.retain(|s| s.x > -0.2);
            }
            let Some(expected) = solve_nested(&samples).map(|n| n.extra_variance) else {
                continue;
            };
            let trials = 4000;
            let mut sum = 0.0;
            for _ in 0..trials {
                for s in samples.iter_mut() {
                    s.z = 3f64.sqrt() * (2.0 * uniform() - 1.0);
                }
                let c = solve::<10, 3>(&samples, 3, false).unwrap().coef;
                let q = solve::<15, 3>(&samples, 4, false).unwrap().coef;
                let h = [2.0 * (q[3] - c[3]), q[4] - c[4], 2.0 * (q[5] - c[5])];
                sum += h[0] * h[0] + 2.0 * h[1] * h[1] + h[2] * h[2];
            }
            let measured = sum / trials as f64;
            assert!(
                (measured / expected - 1.0).abs() < 0.1,
                "disc {d}: {measured} against {expected}"
            );
        }
    }

    #[test]
    fn curved_heights_fit_a_sphere_as_wide_as_the_disc() {
        // A sphere of radius 1 under a disc of radius 0.8: the quartic of its heights is
        // off by the series' truncation; its curved heights are a quadratic.
        let r = 0.8;
        let samples = kernel_disc(0x0DDB_1A5E_5BAD_5EED, 400, 1.0, |x, y, _| {
            -(1.0 - (1.0 - (x * x + y * y) * r * r).sqrt()) / r
        });
        let normal = Vec3::new(0.0, 0.0, 1.0);
        let plain = solve::<15, 3>(&samples, 4, false).unwrap();
        let (plain_estimate, _, _) = plain.estimate(normal, r, None);
        let (kept, other) = plain.curved(&samples, None);
        let (estimate, _, alternative) = kept.estimate(normal, r, other.as_ref());
        // Measured: the quartic k 1.0006 and 1.0006 (6e-4 off), the curved 1 to 1e-15.
        assert!((plain_estimate.k_max - 1.0).abs() > 1e-4);
        for k in [estimate.k_max, estimate.k_min] {
            assert!((k - 1.0).abs() < 1e-9, "k {k}");
        }
        assert!(estimate.e_max.abs() < 1e-9 && estimate.e_min.abs() < 1e-9);
        // The other model is the quartic: its extremalities along the kept directions.
        let (u, w, _) = tangent_frame(normal);
        let t = [estimate.dir_max.dot(&u), estimate.dir_max.dot(&w)];
        assert_eq!(alternative, plain.extremalities(&plain.coef, t, r));
        assert!(alternative[0].abs().max(alternative[1].abs()) > 1e-4);
    }

    #[test]
    fn curved_heights_kept_on_request_where_the_heights_fit_better() {
        // Heights that are a cubic, which the quartic fits exactly: the heights' fit leaves no
        // residual and the curved heights' does, so by residual the heights' fit is kept;
        // with `keep_curved` (white noise, where the residuals cannot tell the models apart)
        // the curved one, the heights' becoming the other model.
        let samples = kernel_disc(0x00C0_FFEE_0000_0042, 400, 1.0, |x, y, _| {
            -0.5 * x * x - 0.3 * y * y + 0.1 * x * x * x
        });
        let plain = solve::<15, 3>(&samples, 4, false).unwrap();
        let (by_residual, other) = plain.curved(&samples, None);
        assert_eq!(by_residual.coef, plain.coef);
        let curved = other.expect("the curved fit is made").coef;
        assert!((curved[6] - plain.coef[6]).abs() > 1e-3, "{curved:?}");
        let (kept, other) = plain.curved(&samples, Some(0.0));
        assert_eq!(kept.coef, curved);
        assert_eq!(other.map(|fit| fit.coef), Some(plain.coef));
    }

    #[test]
    fn curved_heights_kept_on_request_where_only_noise_takes_the_disc_past_their_sphere() {
        // A sphere of radius 1 under a disc as wide, with noise: the curved fit's surface
        // does not reach over the disc's rim (1 + 2cP < 0 at some sample), and by residual
        // the heights' fit is kept with no other model, as it is on request without noise;
        // on request with the noise's level (white noise, where the curved fit is read only
        // at the origin and the disc need reach over the samples only to within the noise)
        // the curved fit, close to the sphere.
        let sphere = |x: f64, y: f64| -(1.0 - (1.0 - x * x - y * y).sqrt());
        // Without the noise the sphere reaches over the disc and the curved fit is made.
        let clean = kernel_disc(0x5EED_0F70_1100_0001, 600, 0.999, |x, y, next| {
            let _ = next();
            sphere(x, y)
        });
        let heights = solve::<15, 3>(&clean, 4, false).unwrap();
        assert!(heights.curved(&clean, None).1.is_some());
        let samples = kernel_disc(0x5EED_0F70_1100_0001, 600, 0.999, |x, y, next| {
            sphere(x, y) + 0.01 * (next() - 0.5)
        });
        let plain = solve::<15, 3>(&samples, 4, false).unwrap();
        let (by_residual, other) = plain.curved(&samples, None);
        assert!(other.is_none());
        assert_eq!(by_residual.coef, plain.coef);
        let (without_noise, other) = plain.curved(&samples, Some(0.0));
        assert!(other.is_none());
        assert_eq!(without_noise.coef, plain.coef);
        let sigma = 0.01 / 12f64.sqrt();
        let (kept, other) = plain.curved(&samples, Some(sigma));
        assert_eq!(other.map(|fit| fit.coef), Some(plain.coef));
        let normal = Vec3::new(0.0, 0.0, 1.0);
        let k = |fit: &Fit| {
            let (estimate, _, _) = fit.estimate(normal, 1.0, None);
            [estimate.k_max, estimate.k_min]
        };
        eprintln!("heights k {:?}, curved k {:?}", k(&plain), k(&kept));
        for (curved, heights) in k(&kept).into_iter().zip(k(&plain)) {
            assert!(
                (curved - 1.0).abs() < (heights - 1.0).abs(),
                "{curved} {heights}"
            );
        }
    }

    #[test]
    fn curved_taylor_coefficients_are_those_of_the_heights() {
        // z = f(P(x, y)) for cubic P with a gradient and both signs of c: the Taylor
        // coefficients to the third order against central differences of z.
        let mut next = uniform(0x51AB_1E5E_ED00_0001);
        for bend in [0.7, -0.45, 1.3] {
            let mut coef = [0.0; 15];
            for c in coef.iter_mut().take(10) {
                *c = 0.6 * (next() - 0.5);
            }
            coef[0] = 0.05;
            let fit = Fit {
                coef,
                noise_coef: [0.0; 15],
                square_coef: [0.0; 15],
                degree: 4,
                residual: f64::NAN,
                noise_residual: f64::NAN,
                conditioning: 1.0,
            };
            let taylor = fit.curved_taylor(bend).unwrap();
            let z = |x: f64, y: f64| {
                let m = monomials::<15>(x, y);
                let p: f64 = m.iter().zip(&coef).map(|(a, b)| a * b).sum();
                2.0 * p / (1.0 + (1.0 + 2.0 * bend * p).sqrt())
            };
            let h = 1e-3;
            let dx = |f: &dyn Fn(f64, f64) -> f64, x: f64, y: f64| {
                (f(x + h, y) - f(x - h, y)) / (2.0 * h)
            };
            let dy = |f: &dyn Fn(f64, f64) -> f64, x: f64, y: f64| {
                (f(x, y + h) - f(x, y - h)) / (2.0 * h)
            };
            let zx = |x: f64, y: f64| dx(&z, x, y);
            let zy = |x: f64, y: f64| dy(&z, x, y);
            let zxx = |x: f64, y: f64| dx(&zx, x, y);
            let zxy = |x: f64, y: f64| dy(&zx, x, y);
            let zyy = |x: f64, y: f64| dy(&zy, x, y);
            let expected = [
                z(0.0, 0.0),
                zx(0.0, 0.0),
                zy(0.0, 0.0),
                zxx(0.0, 0.0) / 2.0,
                zxy(0.0, 0.0),
                zyy(0.0, 0.0) / 2.0,
                dx(&zxx, 0.0, 0.0) / 6.0,
                dy(&zxx, 0.0, 0.0) / 2.0,
                dx(&zyy, 0.0, 0.0) / 2.0,
                dy(&zyy, 0.0, 0.0) / 6.0,
            ];
            for (k, e) in expected.iter().enumerate() {
                assert!(
                    (taylor[k] - e).abs() < 1e-4 * (1.0 + e.abs()),
                    "c = {bend}, coefficient {k}: {} against {e}",
                    taylor[k]
                );
            }
        }
    }

    #[test]
    fn fits_are_nalgebras_to_the_bit() {
        check::<15>(4);
        check::<10>(3);
        check::<6>(2);
    }
}
