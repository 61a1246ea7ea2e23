//! The library's integration tests, one module per area, linked into one test binary (a
//! binary per file would link the library two dozen times). `common` holds the shared helpers.
//! The picture tests (`render`, `html_viewer`) need the `render` feature:
//! `cargo test -p crestline --features render` (the workspace's tests turn it on for the CLI).

mod auto_threshold;
mod bad_input;
mod bad_input_files;
mod cad_parts;
mod cad_shapes;
mod cad_solids;
mod common;
mod curvature;
mod curvature_robust;
mod extract;
mod extract_real_meshes;
mod extract_ybs;
mod files;
#[cfg(feature = "render")]
mod html_viewer;
mod invariance;
mod io_robustness;
mod io_round_trip;
mod non_manifold;
mod quality_cases;
mod real_meshes;
#[cfg(feature = "render")]
mod render;
mod simplify;
mod simplify_real_meshes;
mod simplify_strips;
