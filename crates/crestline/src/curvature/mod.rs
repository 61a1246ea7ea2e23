//! Per-vertex principal curvatures, principal directions and extremality coefficients.
//!
//! Two estimators fill the same [`Curvature`] result:
//! - [`Estimator::ShapeOperator`]: the discrete shape operator of HPW 2005 (sec. 3) with the
//!   discrete extremalities of its eq. 4 (`shape_operator.rs`);
//! - [`Estimator::CubicFit`]: the enhanced adjacent-normal cubic fit of YBS 2005 (eq. 2) with
//!   the extremality formula of its eq. 3 (`cubic_fit.rs`).
//!
//! ## Sign conventions
//! Normals point outward; curvature is positive where the surface bends away from the normal
//! (a sphere of radius r has k = 1/r everywhere); `k_max >= k_min`. `dir_max`/`dir_min` are
//! unit tangent vectors whose sign is arbitrary but fixed; `e_max`/`e_min` are the derivatives
//! of `k_max`/`k_min` along exactly the stored `dir_max`/`dir_min` (flip a direction and its
//! extremality flips sign with it).

use crate::mesh::Vec3;

/// Which estimator computes the curvature.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Estimator {
    /// Discrete shape operator and discrete extremalities (HPW 2005, sec. 3, eq. 4).
    #[default]
    ShapeOperator,
    /// Enhanced adjacent-normal cubic fitting (YBS 2005, eqs. 2, 3).
    CubicFit,
}

/// Per-vertex curvature fields, indexed like the mesh's vertices.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Curvature {
    /// Maximal principal curvature.
    pub k_max: Vec<f64>,
    /// Minimal principal curvature (`k_min <= k_max`).
    pub k_min: Vec<f64>,
    /// Unit principal direction of `k_max` (tangent; sign arbitrary but fixed).
    pub dir_max: Vec<Vec3>,
    /// Unit principal direction of `k_min`.
    pub dir_min: Vec<Vec3>,
    /// Extremality `e_max = d k_max / d dir_max`, consistent with the stored `dir_max`.
    pub e_max: Vec<f64>,
    /// Extremality `e_min = d k_min / d dir_min`, consistent with the stored `dir_min`.
    pub e_min: Vec<f64>,
    /// The unit normals the estimate used (outward).
    pub normals: Vec<Vec3>,
    /// Vertices that could not be estimated normally (too few neighbours, unreferenced,
    /// degenerate star) and got a fallback value; never NaN.
    pub fallback_vertices: usize,
}
