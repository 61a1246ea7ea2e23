//! The per-vertex fields of a surface as [`super::extract`] estimates them before tracing,
//! for callers that want the fields alone (`crestline curvature`, the pictures' `--field`,
//! Python's `curvature`): isolated outlier vertices put back first ([`crate::mesh::outliers`]),
//! then the jet fit split at the sharp creases ([`crate::lines::crease`]; the papers'
//! estimators read one star or ring and are not split).

use crate::curvature::{Curvature, CurvatureOptions, Estimator, estimate_split};
use crate::error::Result;
use crate::lines::crease::{CreaseAngle, CreaseOptions, find_creases};
use crate::mesh::{OutlierRepair, TriMesh, repair_outliers};

/// What [`surface_fields`] estimated, and on what.
#[derive(Debug, Clone)]
pub struct SurfaceFields {
    /// The fields, one per vertex of the mesh given.
    pub curvature: Curvature,
    /// The mesh with its outlier vertices put back, when any moved: the surface estimated.
    pub repaired: Option<TriMesh>,
    /// The outlier vertices moved (none when `repair_outliers` was off).
    pub outliers: OutlierRepair,
    /// The crease edges the fit was split at.
    pub crease_edges: usize,
    /// The crease curves they make.
    pub crease_curves: usize,
}

/// The fields of `mesh` with `options`: outlier vertices put back first when
/// `repair_outliers`, the jet fit split at the creases found with `creases` (module docs).
///
/// # Errors
/// Those of [`repair_outliers`], [`find_creases`] and [`estimate_split`].
pub fn surface_fields(
    mesh: &TriMesh,
    options: &CurvatureOptions,
    creases: CreaseAngle,
    repair_outliers_first: bool,
) -> Result<SurfaceFields> {
    let (repaired, outliers) = if repair_outliers_first {
        repair_outliers(mesh)?
    } else {
        (None, OutlierRepair::default())
    };
    let surface = repaired.as_ref().unwrap_or(mesh);
    let angle = match options.estimator {
        Estimator::JetFit => creases,
        _ => CreaseAngle::Off,
    };
    let found = find_creases(surface, &CreaseOptions::DEFAULT.with_angle(angle))?;
    let curvature = estimate_split(surface, options, found.barriers(surface).as_deref())?;
    Ok(SurfaceFields {
        curvature,
        crease_edges: found.edges.iter().filter(|&&c| c).count(),
        crease_curves: found.curves.len(),
        repaired,
        outliers,
    })
}
