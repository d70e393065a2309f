//! A bounds-checked little-endian reader over a byte slice: every read of a malformed or truncated
//! file is an error, never a panic, and no count read from a file allocates before it is checked
//! against the bytes that remain.

use super::VdbError;

/// Reads little-endian values from a byte slice.
#[derive(Clone, Debug)]
pub(crate) struct Cursor<'a> {
    data: &'a [u8],
    pos: usize,
}

impl<'a> Cursor<'a> {
    pub fn new(data: &'a [u8]) -> Self {
        Cursor { data, pos: 0 }
    }

    pub fn pos(&self) -> usize {
        self.pos
    }

    pub fn remaining(&self) -> usize {
        self.data.len() - self.pos
    }

    /// Moves to absolute offset `pos` (must lie within the data).
    pub fn seek(&mut self, pos: u64) -> Result<(), VdbError> {
        if pos > self.data.len() as u64 {
            return Err(VdbError::Truncated { offset: pos });
        }
        self.pos = pos as usize;
        Ok(())
    }

    /// The next `n` bytes.
    pub fn bytes(&mut self, n: usize) -> Result<&'a [u8], VdbError> {
        if n > self.remaining() {
            return Err(VdbError::Truncated {
                offset: self.pos as u64,
            });
        }
        let s = &self.data[self.pos..self.pos + n];
        self.pos += n;
        Ok(s)
    }

    pub fn array<const N: usize>(&mut self) -> Result<[u8; N], VdbError> {
        let b = self.bytes(N)?;
        let mut a = [0u8; N];
        a.copy_from_slice(b);
        Ok(a)
    }

    pub fn u8(&mut self) -> Result<u8, VdbError> {
        Ok(self.array::<1>()?[0])
    }

    pub fn u32(&mut self) -> Result<u32, VdbError> {
        Ok(u32::from_le_bytes(self.array()?))
    }

    pub fn i32(&mut self) -> Result<i32, VdbError> {
        Ok(i32::from_le_bytes(self.array()?))
    }

    pub fn i64(&mut self) -> Result<i64, VdbError> {
        Ok(i64::from_le_bytes(self.array()?))
    }

    pub fn f64(&mut self) -> Result<f64, VdbError> {
        Ok(f64::from_le_bytes(self.array()?))
    }

    /// A count that must be backed by at least `min_bytes_each` bytes per item in what remains.
    pub fn count(&mut self, min_bytes_each: usize) -> Result<usize, VdbError> {
        let at = self.pos as u64;
        let n = self.u32()? as usize;
        if n.saturating_mul(min_bytes_each.max(1)) > self.remaining() {
            return Err(VdbError::Malformed {
                offset: at,
                what: "a count larger than the rest of the file",
            });
        }
        Ok(n)
    }

    /// A length-prefixed string (u32 length, then bytes).
    pub fn string(&mut self) -> Result<String, VdbError> {
        let n = self.count(1)?;
        Ok(String::from_utf8_lossy(self.bytes(n)?).into_owned())
    }
}
