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
//! ## Quick start
//!
//! Read a mesh (OBJ, PLY, OFF, STL: [`io::read_mesh`], or from bytes), find its feature lines
//! with one of the three pipelines ([`extract::extract`]) and write them (OBJ, PLY or JSON:
//! [`io::lines`]); every step of the pipelines is also a public function with its own options
//! struct, and every options struct documents its defaults.
//!
//! ```
//! use crestline::extract::{ExtractOptions, Method, extract};
//! use crestline::io::lines::{LinesFormat, parse_lines, write_lines_to};
//! use crestline::io::{Format, PlyEncoding, read_mesh_bytes, write_mesh_to, WriteOptions};
//!
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! // A mesh from a file's bytes (here generated: an ellipsoid with one crest line).
//! let mut obj = Vec::new();
//! let ellipsoid = crestline::shapes::ellipsoid(3.0, 2.0, 1.0, 4);
//! write_mesh_to(&mut obj, &ellipsoid, Format::Obj, &WriteOptions::default())?;
//! let mesh = read_mesh_bytes(&obj, Format::Obj, "ellipsoid.obj".as_ref())?;
//!
//! // Ridges, valleys and sharp creases, by Hildebrandt, Polthier and Wardetzky's pipeline.
//! let found = extract(&mesh, &ExtractOptions::for_method(Method::Hpw))?;
//! assert_eq!((found.stats.ridges, found.stats.valleys), (1, 0));
//! let ridge = &found.lines.lines[0];
//! assert!(ridge.closed && ridge.strength > 1.0);
//!
//! // Written as JSON and read back with kinds and strengths.
//! let mut json = Vec::new();
//! write_lines_to(&mut json, &found.lines, LinesFormat::Json, PlyEncoding::Ascii)?;
//! let back = parse_lines(&json, LinesFormat::Json, "lines.json".as_ref())?;
//! assert_eq!(back.lines[0].strength, ridge.strength);
//! # Ok(())
//! # }
//! ```
//!
//! The command-line tool (`cargo install --path crates/crestline-cli`) runs the same
//! pipelines: `crestline extract mesh.obj -o lines.json`.
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
pub mod io;
pub mod lines;
pub mod mesh;
#[cfg(feature = "render")]
pub mod render;
pub mod saliency;
pub mod shapes;
pub mod simplify;
mod slices;
pub mod smoothing;
pub mod spatial;
pub mod threshold;

pub use error::{Error, Location, Result};
pub use mesh::{MeshInfo, TriMesh, Vec3};
