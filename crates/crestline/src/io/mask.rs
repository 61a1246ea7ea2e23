//! Diffusion-mask files: one smoothing factor per vertex, for inhomogeneous extremality
//! smoothing ([`crate::smoothing::extremality::ExtremalitySmoothing::diffusion`]).
//!
//! The format is plain text: the factors of the vertices in order, as decimal numbers
//! separated by whitespace and line breaks (one per line is usual), each finite and >= 0
//! (0 keeps a vertex's values as they are, 1 smooths it as everywhere else). `#` starts a
//! comment; blank lines, CRLF line ends and a UTF-8 byte-order mark are accepted. The file
//! must hold exactly one factor per vertex of the mesh.

use std::path::Path;

use super::text::{Lines, Source, Tokens, parse_f64, show, strip_bom};
use crate::error::{Error, Result};

/// Reads the diffusion factors of a mesh of `vertices` vertices from `path`.
///
/// # Errors
/// [`Error::Io`] when the file cannot be read; [`Error::Parse`] naming the file and line of
/// a token that is not a finite number >= 0, or the file when the count is wrong.
pub fn read_diffusion_factors(path: &Path, vertices: usize) -> Result<Vec<f64>> {
    let bytes = super::read_file(path).map_err(|e| Error::io(path, e))?;
    parse_diffusion_factors(&bytes, vertices, path)
}

/// Parses diffusion factors held in memory; `name` labels errors.
///
/// # Errors
/// As [`read_diffusion_factors`].
pub fn parse_diffusion_factors(bytes: &[u8], vertices: usize, name: &Path) -> Result<Vec<f64>> {
    let source = Source::new(name);
    // Never more than the mesh needs, whatever the file's size.
    let mut factors = Vec::with_capacity(vertices.min(bytes.len() / 2 + 1));
    for (line, text) in Lines::new(strip_bom(bytes)) {
        for token in Tokens::new(text) {
            let x = parse_f64(token).ok_or_else(|| {
                source.at_line(
                    line,
                    format!(
                        "non-numeric token '{}' where a factor was expected",
                        show(token)
                    ),
                )
            })?;
            if !(x.is_finite() && x >= 0.0) {
                return Err(source.at_line(
                    line,
                    format!("factor '{}' must be a finite number >= 0", show(token)),
                ));
            }
            if factors.len() == vertices {
                return Err(source.at_line(
                    line,
                    format!("more factors than the {vertices} vertices of the mesh"),
                ));
            }
            factors.push(x);
        }
    }
    if factors.len() != vertices {
        return Err(source.whole(format!(
            "{} factors for a mesh of {vertices} vertices",
            factors.len()
        )));
    }
    Ok(factors)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_factor_per_vertex_across_lines() {
        let f = parse_diffusion_factors(b"1 0.5\n\n# c\n0 # end\n", 3, Path::new("m")).unwrap();
        assert_eq!(f, vec![1.0, 0.5, 0.0]);
    }

    #[test]
    fn missing_file_names_it() {
        let e = read_diffusion_factors(Path::new("/no/such/mask.txt"), 3).unwrap_err();
        assert!(e.to_string().starts_with("/no/such/mask.txt: "), "{e}");
    }
}
