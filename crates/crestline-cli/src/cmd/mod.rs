//! One module per subcommand.

pub mod distance;
pub mod info;
pub mod simplify;
