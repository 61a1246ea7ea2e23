//! The weighted least-squares polynomial of a jet fit ([`super`], step 3) and the differential
//! quantities at its origin (step 4).

use nalgebra::{SMatrix, SVector};

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
fn monomials<const N: usize>(x: f64, y: f64) -> SVector<f64, N> {
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
    SVector::<f64, N>::from_fn(|i, _| all[i])
}

/// A fitted height polynomial (in units of the radius), its weighted RMS residual, and the
/// polynomial fitted to the samples' simulated noise instead of their heights.
pub(super) struct Fit {
    /// Coefficients in [`monomials`] order; at most 15 (unused ones are zero).
    pub(super) coef: [f64; 15],
    /// The same for the simulated noise.
    noise_coef: [f64; 15],
    pub(super) degree: usize,
    pub(super) residual: f64,
}

/// The weighted least-squares fit of `samples` by the first `N` monomials; the residual is
/// measured only when `residual` (NaN otherwise).
pub(super) fn solve<const N: usize>(
    samples: &[Sample],
    degree: usize,
    residual: bool,
) -> Option<Fit> {
    let mut ata = SMatrix::<f64, N, N>::zeros();
    let mut atb = SVector::<f64, N>::zeros();
    let mut atxi = SVector::<f64, N>::zeros();
    let mut weight = 0.0;
    for s in samples {
        let m = monomials::<N>(s.x, s.y);
        ata.syger(s.w, &m, &m, 1.0);
        atb.axpy(s.w * s.z, &m, 1.0);
        atxi.axpy(s.w * s.xi, &m, 1.0);
        weight += s.w;
    }
    if weight.is_nan() || weight <= 0.0 {
        return None;
    }
    // A whisper of ridge regularisation keeps nearly collinear discs solvable. It is the
    // identity in the rotation-orthogonal basis (`ROTATION_SCALE`), so that it does not
    // depend on how the tangent frame is turned.
    let ridge = 1e-12 * ata.trace() / N as f64;
    for k in 0..N {
        ata[(k, k)] += ridge / (ROTATION_SCALE[k] * ROTATION_SCALE[k]);
    }
    // `syger` wrote the lower triangle, which is the one the factorisation reads.
    let chol = ata.cholesky()?;
    let x = chol.solve(&atb);
    if !x.iter().all(|c| c.is_finite()) {
        return None;
    }
    let mut sq = f64::NAN;
    if residual {
        sq = 0.0;
        for s in samples {
            let r = monomials::<N>(s.x, s.y).dot(&x) - s.z;
            sq += s.w * r * r;
        }
    }
    let mut coef = [0.0; 15];
    coef[..N].copy_from_slice(x.as_slice());
    let mut noise_coef = [0.0; 15];
    noise_coef[..N].copy_from_slice(chol.solve(&atxi).as_slice());
    Some(Fit {
        coef,
        noise_coef,
        degree,
        residual: (sq / weight).sqrt(),
    })
}

impl Fit {
    /// Curvatures, directions and extremalities at the origin of a fit in the frame of
    /// `normal`, the coordinates having been divided by `r`.
    pub(super) fn estimate(&self, normal: Vec3, r: f64) -> (VertexEstimate, [f64; 2]) {
        let c = &self.coef;
        // Derivatives of h in model units: h_xx = H_XX / r, h_xxx = H_XXX / r².
        let (hxx, hxy, hyy) = (2.0 * c[3] / r, c[4] / r, 2.0 * c[5] / r);
        let (k_max, k_min, t) = symmetric_eigen_2x2(-hxx, -hxy, -hyy);
        // e = −D³h[t, t, t] for the coefficients c of a polynomial in units of r.
        let third = |c: &[f64; 15], a: f64, b: f64| -> f64 {
            if self.degree < 3 {
                return 0.0;
            }
            let (hxxx, hxxy, hxyy, hyyy) = (6.0 * c[6], 2.0 * c[7], 2.0 * c[8], 6.0 * c[9]);
            -(hxxx * a * a * a + 3.0 * hxxy * a * a * b + 3.0 * hxyy * a * b * b + hyyy * b * b * b)
                / (r * r)
        };
        let (u, w, n) = tangent_frame(normal);
        let tmin = [-t[1], t[0]];
        let estimate = VertexEstimate {
            k_max,
            k_min,
            dir_max: u * t[0] + w * t[1],
            dir_min: u * tmin[0] + w * tmin[1],
            e_max: third(c, t[0], t[1]),
            e_min: third(c, tmin[0], tmin[1]),
            normal: n,
            fallback: false,
        };
        let noise = [
            third(&self.noise_coef, t[0], t[1]),
            third(&self.noise_coef, tmin[0], tmin[1]),
        ];
        (estimate, noise)
    }
}
