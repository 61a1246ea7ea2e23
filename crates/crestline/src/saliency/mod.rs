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

use crate::curvature::Curvature;
use crate::error::{Error, Result};
use crate::mesh::{TriMesh, mean_edge_length};

pub mod family;
mod sums;
#[cfg(test)]
mod tests;

pub use family::{FamilyThresholds, family_thresholds};
use sums::variation_with;

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
