//! The library's one error type.
//!
//! Errors are grouped by kind, as in pmp-library: reading a file ([`Error::Io`],
//! [`Error::Parse`]), bad arguments or data ([`Error::InvalidInput`]), meshes the algorithm
//! cannot work on ([`Error::Topology`]) and numerical failures ([`Error::Solver`]). A parse
//! error always names the file and a position in it, so a user can go straight to the fault.

use std::fmt;
use std::path::PathBuf;

/// Convenient alias used throughout the crate.
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// Where in a file a parse error was found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Location {
    /// A 1-based line number in a text file.
    Line(usize),
    /// A 0-based byte offset in a binary file (or in a binary section of one).
    Byte(u64),
    /// The file as a whole (for example: it is empty); a message about it names the file
    /// alone (`empty.obj: empty file`).
    File,
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Location::Line(n) => write!(f, "line {n}"),
            Location::Byte(n) => write!(f, "byte {n}"),
            Location::File => write!(f, "file"),
        }
    }
}

/// Everything that can go wrong in crestline.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The operating system refused to read or write a file.
    ///
    /// The message says what the system said; the error has no [`source`]
    /// (`std::error::Error::source`), so that a chain of causes (as `anyhow` prints it) does not
    /// say it twice.
    ///
    /// [`source`]: std::error::Error::source
    #[error("{}: {cause}", path.display())]
    Io {
        /// The file concerned.
        path: PathBuf,
        /// What the operating system said.
        cause: std::io::Error,
    },
    /// A file's contents are malformed: `path: line 3: message`, `path: byte 84: message`,
    /// or `path: message` about the file as a whole ([`Location::File`]).
    #[error("{}: {}{message}", path.display(), position(location))]
    Parse {
        /// The file concerned (or a label such as `<memory>`).
        path: PathBuf,
        /// Where in the file.
        location: Location,
        /// What is wrong, in words a user understands.
        message: String,
    },
    /// Arguments or data that make no sense (NaN coordinates, index out of range, ...).
    #[error("invalid input: {0}")]
    InvalidInput(String),
    /// The mesh has a structure the requested algorithm cannot handle.
    #[error("topology: {0}")]
    Topology(String),
    /// A numerical method failed (for example a factorization that is not positive definite).
    #[error("solver: {0}")]
    Solver(String),
}

/// `line 3: ` or `byte 84: `; nothing for the file as a whole, which the path names already.
fn position(location: &Location) -> String {
    match location {
        Location::File => String::new(),
        _ => format!("{location}: "),
    }
}

impl Error {
    /// Builds a [`Error::Parse`].
    pub fn parse(path: impl Into<PathBuf>, location: Location, message: impl Into<String>) -> Self {
        Error::Parse {
            path: path.into(),
            location,
            message: message.into(),
        }
    }

    /// Builds an [`Error::Io`].
    pub fn io(path: impl Into<PathBuf>, cause: std::io::Error) -> Self {
        Error::Io {
            path: path.into(),
            cause,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parse_error_names_file_and_position() {
        let e = Error::parse("a/b.obj", Location::Line(12), "non-numeric token 'x'");
        assert_eq!(e.to_string(), "a/b.obj: line 12: non-numeric token 'x'");
        let e = Error::parse("m.ply", Location::Byte(1034), "truncated");
        assert_eq!(e.to_string(), "m.ply: byte 1034: truncated");
    }

    #[test]
    fn whole_file_parse_error_names_the_file_alone() {
        let e = Error::parse("empty.obj", Location::File, "empty file");
        assert_eq!(e.to_string(), "empty.obj: empty file");
    }
}
