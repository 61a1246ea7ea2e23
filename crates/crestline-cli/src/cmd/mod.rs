//! One module per subcommand.

pub mod curvature;
pub mod extract;
pub mod info;
pub mod render;
pub mod view;
