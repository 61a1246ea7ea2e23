//! The binary PLY body, little or big endian: fixed-size scalars read from bytes.

use super::{Fault, Location, Scalar, Values};

/// Consecutive fixed-size binary records.
pub(super) struct Block<'a> {
    pub(super) bytes: &'a [u8],
    pub(super) offset: usize,
    pub(super) big_endian: bool,
}

/// Reads a `$t` from the start of `$bytes` in the given byte order, returning `None` from
/// the enclosing function when the bytes are too few.
macro_rules! scalar_from {
    ($bytes:ident, $big_endian:ident, $t:ty) => {{
        let b = *$bytes.first_chunk::<{ std::mem::size_of::<$t>() }>()?;
        if $big_endian {
            <$t>::from_be_bytes(b)
        } else {
            <$t>::from_le_bytes(b)
        }
    }};
}

/// Decodes one binary scalar from the start of `bytes` as `f64` (`None` if too short).
#[inline]
pub(super) fn decode_f64(ty: Scalar, big_endian: bool, bytes: &[u8]) -> Option<f64> {
    Some(match ty {
        Scalar::I8 => f64::from(scalar_from!(bytes, big_endian, i8)),
        Scalar::U8 => f64::from(scalar_from!(bytes, big_endian, u8)),
        Scalar::I16 => f64::from(scalar_from!(bytes, big_endian, i16)),
        Scalar::U16 => f64::from(scalar_from!(bytes, big_endian, u16)),
        Scalar::I32 => f64::from(scalar_from!(bytes, big_endian, i32)),
        Scalar::U32 => f64::from(scalar_from!(bytes, big_endian, u32)),
        Scalar::F32 => f64::from(scalar_from!(bytes, big_endian, f32)),
        Scalar::F64 => scalar_from!(bytes, big_endian, f64),
    })
}

/// Decodes one binary integer scalar (the header keeps float types out of counts and
/// indices; should one get here it is truncated towards zero).
#[inline]
pub(super) fn decode_i64(ty: Scalar, big_endian: bool, bytes: &[u8]) -> Option<i64> {
    Some(match ty {
        Scalar::I8 => i64::from(scalar_from!(bytes, big_endian, i8)),
        Scalar::U8 => i64::from(scalar_from!(bytes, big_endian, u8)),
        Scalar::I16 => i64::from(scalar_from!(bytes, big_endian, i16)),
        Scalar::U16 => i64::from(scalar_from!(bytes, big_endian, u16)),
        Scalar::I32 => i64::from(scalar_from!(bytes, big_endian, i32)),
        Scalar::U32 => i64::from(scalar_from!(bytes, big_endian, u32)),
        Scalar::F32 => scalar_from!(bytes, big_endian, f32) as i64,
        Scalar::F64 => scalar_from!(bytes, big_endian, f64) as i64,
    })
}

/// Binary values; `BIG` selects big-endian (a constant, so each byte order gets its own
/// compiled walker).
pub(super) struct Binary<'a, const BIG: bool> {
    pub(super) data: &'a [u8],
    pub(super) position: usize,
    pub(super) last: usize,
}

impl<const BIG: bool> Binary<'_, BIG> {
    #[inline]
    pub(super) fn rest(&mut self) -> &[u8] {
        self.last = self.position;
        self.data.get(self.position..).unwrap_or_default()
    }
}

impl<const BIG: bool> Values for Binary<'_, BIG> {
    #[inline]
    fn float(&mut self, ty: Scalar) -> Result<f64, Fault> {
        let x = decode_f64(ty, BIG, self.rest()).ok_or(Fault::End)?;
        self.position += ty.size();
        Ok(x)
    }

    #[inline]
    fn int(&mut self, ty: Scalar) -> Result<i64, Fault> {
        let i = decode_i64(ty, BIG, self.rest()).ok_or(Fault::End)?;
        self.position += ty.size();
        Ok(i)
    }

    #[inline]
    fn skip(&mut self, ty: Scalar, n: usize) -> Result<(), Fault> {
        self.room_for(n, ty)?;
        self.last = self.position;
        self.position += n * ty.size();
        Ok(())
    }

    fn fixed_block(&mut self, records: usize, size: usize) -> Option<Result<Block<'_>, usize>> {
        let start = self.position.min(self.data.len());
        let remaining = self.data.len() - start;
        let total = records.checked_mul(size).filter(|&t| t <= remaining);
        Some(match total {
            Some(t) => {
                self.position = start + t;
                Ok(Block {
                    bytes: &self.data[start..start + t],
                    offset: start,
                    big_endian: BIG,
                })
            }
            None => {
                // Point at the first record that does not fit (size > 0 here: records of
                // zero bytes always fit).
                let complete = remaining / size.max(1);
                self.position = start + complete * size;
                self.last = self.position;
                Err(complete)
            }
        })
    }

    fn room_for(&self, n: usize, ty: Scalar) -> Result<(), Fault> {
        let remaining = self.data.len() - self.position.min(self.data.len());
        if n.checked_mul(ty.size()).is_some_and(|b| b <= remaining) {
            Ok(())
        } else {
            Err(Fault::End)
        }
    }

    fn location(&self) -> Location {
        Location::Byte(self.last as u64)
    }
}
