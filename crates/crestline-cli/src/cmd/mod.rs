//! One module per subcommand.

pub mod batch;
pub mod curvature;
pub mod distance;
pub mod extract;
pub mod info;
pub mod render;
pub mod simplify;
pub mod subdivide;
pub mod view;
