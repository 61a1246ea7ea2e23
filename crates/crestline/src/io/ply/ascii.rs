//! The ascii PLY body: whitespace-separated numbers, one element per line.

use super::{Block, Fault, Location, Scalar, Values, Words, parse_f64, parse_i64, show};
use crate::io::text::is_integer_token;

/// Ascii values: whitespace-separated tokens across lines.
pub(super) struct Ascii<'a> {
    pub(super) words: Words<'a>,
    pub(super) remaining_hint: usize,
}

impl Ascii<'_> {
    #[inline]
    pub(super) fn word(&mut self) -> Result<&[u8], Fault> {
        self.words.next_word().ok_or(Fault::End)
    }
}

impl Values for Ascii<'_> {
    #[inline]
    fn float(&mut self, ty: Scalar) -> Result<f64, Fault> {
        let w = self.word()?;
        let x = parse_f64(w).ok_or_else(|| Fault::NotNumber(show(w)))?;
        // A `float` that a binary file could not hold (it would be read as infinite). Written
        // `inf` or `nan` it is left to the caller, as in binary.
        if ty == Scalar::F32 && x.is_finite() && (x as f32).is_infinite() {
            return Err(Fault::OutOfRange("float", show(w)));
        }
        Ok(x)
    }

    #[inline]
    fn int(&mut self, ty: Scalar) -> Result<i64, Fault> {
        let w = self.word()?;
        parse_i64(w).ok_or_else(|| {
            if is_integer_token(w) {
                Fault::OutOfRange(ty.name(), show(w))
            } else if parse_f64(w).is_some() {
                Fault::NotInteger(show(w))
            } else {
                Fault::NotNumber(show(w))
            }
        })
    }

    fn skip(&mut self, _ty: Scalar, n: usize) -> Result<(), Fault> {
        for _ in 0..n {
            self.word()?;
        }
        Ok(())
    }

    fn fixed_block(&mut self, _records: usize, _size: usize) -> Option<Result<Block<'_>, usize>> {
        None
    }

    fn room_for(&self, n: usize, _ty: Scalar) -> Result<(), Fault> {
        // Every value takes at least two bytes (a digit and a separator), bar the last.
        if n <= self.remaining_hint / 2 + 1 {
            Ok(())
        } else {
            Err(Fault::End)
        }
    }

    fn location(&self) -> Location {
        Location::Line(self.words.line())
    }
}
