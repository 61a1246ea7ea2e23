//! Dropping weak and short lines (HPW 2005, Table 1 step 6; YBS 2005 eq. 5).
//!
//! Both strengths are scale independent: the integral of |k| along a line (Ohtake et al.
//! 2004, as HPW use) is dimensionless, and so is YBS's `T = ∫ds · ∫C ds`. The minimum length
//! is given relative to the model size (the bounding-box diagonal, of the largest part when
//! there are several: [`crate::TriMesh::model_size`]) for the same reason.

use super::{FeatureLine, FeatureLines};
use crate::threshold::{ChosenThreshold, NoKnee, Threshold, choose_threshold};

/// Default threshold of the HPW pipeline on T (dimensionless). Measured: spurious lines on a
/// torus have T ≈ 0.01, the ellipsoid's crest line T ≈ 40, fandisk's creases T ≈ 2 to 13.
pub const HPW_DEFAULT_THRESHOLD: f64 = 1.0;

/// Which strength a threshold applies to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum StrengthMeasure {
    /// `∫|k| ds` (Ohtake et al. 2004; the filter HPW use).
    #[default]
    CurvatureIntegral,
    /// YBS's `T = ∫ds · ∫C ds` (eq. 5).
    Cyclideness,
}

impl StrengthMeasure {
    /// The measure's value for a line.
    pub fn of(self, line: &FeatureLine) -> f64 {
        match self {
            StrengthMeasure::CurvatureIntegral => line.curvature_integral,
            StrengthMeasure::Cyclideness => line.strength,
        }
    }
}

/// Options of [`filter_lines`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LineFilter {
    /// The strength the threshold applies to. Default: [`StrengthMeasure::CurvatureIntegral`].
    pub measure: StrengthMeasure,
    /// Lines with a smaller strength are dropped. Default: 0 (keep all).
    pub threshold: f64,
    /// Lines shorter than this fraction of the model size are dropped.
    /// Default: 0.
    pub min_length: f64,
}

impl Default for LineFilter {
    fn default() -> Self {
        LineFilter {
            measure: StrengthMeasure::CurvatureIntegral,
            threshold: 0.0,
            min_length: 0.0,
        }
    }
}

/// Keeps the lines that pass `filter`; `diagonal` is the model size
/// ([`crate::TriMesh::model_size`]).
pub fn filter_lines(lines: FeatureLines, filter: &LineFilter, diagonal: f64) -> FeatureLines {
    let min_length = filter.min_length * diagonal;
    FeatureLines {
        lines: lines
            .lines
            .into_iter()
            .filter(|l| l.length >= min_length && filter.measure.of(l) >= filter.threshold)
            .collect(),
    }
}

/// The automatic threshold step for lines (HPW and YBS): `threshold` applied to the strengths
/// (`filter.measure`) of the lines at least `filter.min_length` diagonals long
/// ([`choose_threshold`]); when it is a knee search and the strengths have no knee, its
/// floor. `filter.threshold` is not read.
pub fn choose_line_threshold(
    lines: &FeatureLines,
    filter: &LineFilter,
    diagonal: f64,
    threshold: &Threshold,
) -> ChosenThreshold {
    let strengths: Vec<f64> = match threshold {
        Threshold::Fixed(_) => Vec::new(),
        Threshold::Knee { .. } => {
            let min_length = filter.min_length * diagonal;
            lines
                .lines
                .iter()
                .filter(|l| l.length >= min_length)
                .map(|l| filter.measure.of(l))
                .collect()
        }
    };
    choose_threshold(&strengths, threshold, NoKnee::Value(threshold.floor()))
}
