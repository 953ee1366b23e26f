//! Bounds-checked little-endian reading: every read either succeeds or returns a
//! [`LoadError`] naming the byte offset, so no input can make the loader index out of bounds.

use super::{LoadError, LoadErrorKind};

/// A cursor over a byte slice. Positions are offsets in the whole file (`base` is where the
/// slice starts), so errors point at the file's bytes.
pub(crate) struct Reader<'a> {
    bytes: &'a [u8],
    at: usize,
    base: usize,
}

impl<'a> Reader<'a> {
    /// Reads `bytes`, which start at file offset `base`.
    pub(crate) fn new(bytes: &'a [u8], base: usize) -> Reader<'a> {
        Reader { bytes, at: 0, base }
    }

    /// The file offset of the next byte.
    pub(crate) fn position(&self) -> usize {
        self.base + self.at
    }

    /// Bytes left.
    pub(crate) fn remaining(&self) -> usize {
        self.bytes.len() - self.at
    }

    /// True when every byte has been read.
    pub(crate) fn is_at_end(&self) -> bool {
        self.at == self.bytes.len()
    }

    /// The next `n` bytes.
    pub(crate) fn take(&mut self, n: usize) -> Result<&'a [u8], LoadError> {
        if n > self.remaining() {
            return Err(LoadError::new(
                self.position(),
                LoadErrorKind::Truncated { needed: n, available: self.remaining() },
            ));
        }
        let slice = &self.bytes[self.at..self.at + n];
        self.at += n;
        Ok(slice)
    }

    pub(crate) fn u8(&mut self) -> Result<u8, LoadError> {
        Ok(self.take(1)?[0])
    }

    pub(crate) fn u16(&mut self) -> Result<u16, LoadError> {
        let b = self.take(2)?;
        Ok(u16::from_le_bytes([b[0], b[1]]))
    }

    pub(crate) fn u32(&mut self) -> Result<u32, LoadError> {
        let b = self.take(4)?;
        Ok(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    }

    pub(crate) fn i64(&mut self) -> Result<i64, LoadError> {
        let b = self.take(8)?;
        let mut a = [0u8; 8];
        a.copy_from_slice(b);
        Ok(i64::from_le_bytes(a))
    }

    /// A count of items of at least `min_size` bytes each, refused if the items cannot fit in
    /// the bytes left: a hostile count never makes the loader allocate.
    pub(crate) fn count(&mut self, min_size: usize) -> Result<usize, LoadError> {
        let at = self.position();
        let n = self.u32()? as usize;
        if n.saturating_mul(min_size.max(1)) > self.remaining() {
            return Err(LoadError::new(at, LoadErrorKind::CountTooLarge { count: n, available: self.remaining() }));
        }
        Ok(n)
    }
}

/// Little-endian writing, the encoder's side.
#[cfg(feature = "encode")]
pub(crate) fn put_u16(out: &mut Vec<u8>, v: u16) {
    out.extend_from_slice(&v.to_le_bytes());
}

#[cfg(feature = "encode")]
pub(crate) fn put_u32(out: &mut Vec<u8>, v: u32) {
    out.extend_from_slice(&v.to_le_bytes());
}

#[cfg(feature = "encode")]
pub(crate) fn put_i64(out: &mut Vec<u8>, v: i64) {
    out.extend_from_slice(&v.to_le_bytes());
}
