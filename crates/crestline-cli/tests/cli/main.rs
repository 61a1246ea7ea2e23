//! The command-line tool's integration tests, one module per area, linked into one test
//! binary; each runs the `crestline` binary Cargo built for the tests.

mod arguments;
mod bad_input_cli;
mod common;
mod compose;
mod curvature_cli;
mod extract_cli;
mod info;
mod orientation;
mod outputs;
mod render_cli;
mod simplify;
mod subdivide;
mod weld;
