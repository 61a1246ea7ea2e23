//! # crestline
//!
//! Feature lines — ridges, valleys and crest lines — on triangle meshes.
//!
//! The crate implements three papers:
//! - K. Hildebrandt, K. Polthier, M. Wardetzky, *Smooth Feature Lines on Surface Meshes*,
//!   SGP 2005 (HPW): discrete shape operator, discrete extremalities, extremality smoothing,
//!   tracing in regular and singular triangles, spatial fairing.
//! - S. Yoshizawa, A. Belyaev, H.-P. Seidel, *Fast and Robust Detection of Crest Lines on
//!   Meshes*, SPM 2005 (YBS): enhanced adjacent-normal cubic fitting, gap jumping, the
//!   cyclideness strength T, crest-line-guided simplification.
//! - Z. Mao, R. Wang, Y. Zhou, *Automatic Extraction of Feature Lines on 3D Surface*: mesh
//!   saliency and automatic thresholds.
//!
//! ## Sign conventions
//! Unit normals point outward (right-hand rule on a counter-clockwise winding seen from
//! outside). Curvature is positive where the surface bends away from the normal: a sphere of
//! radius r has k = 1/r. Principal curvatures satisfy `k_max >= k_min`.
//! Ridges: `e_max = 0`, `de_max/dt_max < 0`, `k_max > |k_min|`.
//! Valleys: `e_min = 0`, `de_min/dt_min > 0`, `k_min < -|k_max|`.

#![forbid(unsafe_code)]

pub mod curvature;
pub mod distance;
pub mod error;
pub mod extract;
pub mod extremality;
pub mod io;
pub mod lines;
pub mod mesh;
pub mod render;
pub mod saliency;
pub mod shapes;
pub mod simplify;
pub mod smoothing;
pub mod spatial;
pub mod threshold;

pub use error::{Error, Location, Result};
pub use mesh::{MeshInfo, TriMesh, Vec3};
