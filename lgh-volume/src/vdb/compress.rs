//! The compressed arrays of an OpenVDB file: blosc frames (LZ4 or zlib inside, byte shuffle) and
//! zip (zlib) streams, each behind a signed 64-bit size; a negative size means stored raw.

use super::cursor::Cursor;
use super::VdbError;

/// `COMPRESS_ZIP`: zlib streams.
pub(crate) const COMPRESS_ZIP: u32 = 0x1;
/// `COMPRESS_ACTIVE_MASK`: only active values are stored (plus what restores the inactive ones).
pub(crate) const COMPRESS_ACTIVE_MASK: u32 = 0x2;
/// `COMPRESS_BLOSC`: blosc frames.
pub(crate) const COMPRESS_BLOSC: u32 = 0x4;

fn malformed(c: &Cursor<'_>, what: &'static str) -> VdbError {
    VdbError::Malformed {
        offset: c.pos() as u64,
        what,
    }
}

/// Reads an array of `n` bytes written with the grid's compression (OpenVDB's `readData`).
pub(crate) fn read_data(
    c: &mut Cursor<'_>,
    compression: u32,
    n: usize,
) -> Result<Vec<u8>, VdbError> {
    if compression & (COMPRESS_BLOSC | COMPRESS_ZIP) == 0 {
        return Ok(c.bytes(n)?.to_vec());
    }
    let size = c.i64()?;
    if size <= 0 {
        // Stored uncompressed (compression did not pay off).
        if size.unsigned_abs() != n as u64 {
            return Err(malformed(c, "an uncompressed array of the wrong size"));
        }
        return Ok(c.bytes(n)?.to_vec());
    }
    if size as u64 > c.remaining() as u64 {
        return Err(VdbError::Truncated {
            offset: c.pos() as u64,
        });
    }
    let at = c.pos();
    let frame = c.bytes(size as usize)?;
    let out = if compression & COMPRESS_BLOSC != 0 {
        blosc(frame, n)
    } else {
        inflate(frame, n)
    };
    out.ok_or(VdbError::Malformed {
        offset: at as u64,
        what: "a compressed array that does not decompress to its size",
    })
}

/// zlib-inflates `src` into exactly `n` bytes.
fn inflate(src: &[u8], n: usize) -> Option<Vec<u8>> {
    let out = miniz_oxide::inflate::decompress_to_vec_zlib_with_limit(src, n).ok()?;
    (out.len() == n).then_some(out)
}

/// Decodes one blosc (version 1 format) frame that must hold exactly `n` bytes.
///
/// Header: version, versionlz, flags, typesize, then u32 nbytes, blocksize and cbytes. Flags:
/// bit 0 byte shuffle, bit 1 stored raw, bit 2 bit shuffle (unsupported), bit 4 "blocks not
/// split", bits 5–7 the codec (1 = LZ4/LZ4HC, 3 = zlib supported). Each block starts at an offset
/// from the table after the header and is split into `typesize` streams when blosc splits it.
fn blosc(frame: &[u8], n: usize) -> Option<Vec<u8>> {
    let u32_at = |i: usize| -> Option<usize> {
        Some(u32::from_le_bytes(frame.get(i..i + 4)?.try_into().ok()?) as usize)
    };
    let flags = *frame.get(2)?;
    let typesize = *frame.get(3)? as usize;
    let nbytes = u32_at(4)?;
    let blocksize = u32_at(8)?;
    if nbytes != n {
        return None;
    }
    if n == 0 {
        return Some(Vec::new());
    }
    if flags & 0x2 != 0 {
        return frame.get(16..16 + n).map(<[u8]>::to_vec);
    }
    if flags & 0x4 != 0 || blocksize == 0 || typesize == 0 {
        return None; // bit shuffle is not written by OpenVDB
    }
    let codec = flags >> 5;
    let shuffle = flags & 0x1 != 0;
    let dont_split = flags & 0x10 != 0;
    let nblocks = n.div_ceil(blocksize);
    let leftover = n % blocksize;
    let mut out = vec![0u8; n];
    let mut tmp = vec![0u8; blocksize];
    for b in 0..nblocks {
        let last_partial = b == nblocks - 1 && leftover != 0;
        let bsize = if last_partial { leftover } else { blocksize };
        let nsplits = if !dont_split && typesize <= 16 && bsize / typesize >= 128 && !last_partial {
            typesize
        } else {
            1
        };
        if bsize % nsplits != 0 {
            return None;
        }
        let neblock = bsize / nsplits;
        let mut src = u32_at(16 + 4 * b)?;
        let block = &mut tmp[..bsize];
        for s in 0..nsplits {
            let cbytes = u32_at(src)?;
            src += 4;
            let input = frame.get(src..src.checked_add(cbytes)?)?;
            src += cbytes;
            let dst = &mut block[s * neblock..(s + 1) * neblock];
            if cbytes == neblock {
                dst.copy_from_slice(input);
            } else {
                match codec {
                    1 => {
                        if lz4_flex::block::decompress_into(input, dst).ok()? != neblock {
                            return None;
                        }
                    }
                    3 => dst.copy_from_slice(&inflate(input, neblock)?),
                    _ => return None,
                }
            }
        }
        let dest = &mut out[b * blocksize..b * blocksize + bsize];
        if shuffle && typesize > 1 {
            let count = bsize / typesize;
            for j in 0..typesize {
                for i in 0..count {
                    dest[i * typesize + j] = block[j * count + i];
                }
            }
            let tail = count * typesize;
            dest[tail..].copy_from_slice(&block[tail..]);
        } else {
            dest.copy_from_slice(block);
        }
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn raw_and_stored_arrays() {
        let data = [1u8, 2, 3, 4];
        let mut c = Cursor::new(&data);
        assert_eq!(read_data(&mut c, 0, 4).unwrap(), data);
        // Blosc flagged, but stored raw behind a negative size.
        let mut b = (-4i64).to_le_bytes().to_vec();
        b.extend(data);
        assert_eq!(
            read_data(&mut Cursor::new(&b), COMPRESS_BLOSC, 4).unwrap(),
            data
        );
        assert!(read_data(&mut Cursor::new(&b), COMPRESS_BLOSC, 5).is_err());
        // A size beyond the file.
        let huge = i64::MAX.to_le_bytes();
        assert!(read_data(&mut Cursor::new(&huge), COMPRESS_ZIP, 4).is_err());
    }

    #[test]
    fn zlib_round_trip() {
        let raw: Vec<u8> = (0..1000u32).map(|i| (i % 7) as u8).collect();
        let z = miniz_oxide::deflate::compress_to_vec_zlib(&raw, 6);
        let mut b = (z.len() as i64).to_le_bytes().to_vec();
        b.extend(&z);
        assert_eq!(
            read_data(&mut Cursor::new(&b), COMPRESS_ZIP, 1000).unwrap(),
            raw
        );
        assert!(read_data(&mut Cursor::new(&b), COMPRESS_ZIP, 999).is_err());
    }

    #[test]
    fn blosc_shuffled_lz4_split_frame() {
        // Build a frame by hand: 512 little-endian u32s, typesize 4, one block split in 4 streams.
        let values: Vec<u32> = (0..512).map(|i| i * 3 + 7).collect();
        let raw: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        let n = raw.len();
        let count = n / 4;
        let mut shuffled = vec![0u8; n];
        for i in 0..count {
            for j in 0..4 {
                shuffled[j * count + i] = raw[i * 4 + j];
            }
        }
        let mut body = Vec::new();
        for s in 0..4 {
            let part = lz4_flex::block::compress(&shuffled[s * count..(s + 1) * count]);
            body.extend((part.len() as u32).to_le_bytes());
            body.extend(part);
        }
        let mut frame = vec![2u8, 1, 0x21, 4];
        frame.extend((n as u32).to_le_bytes());
        frame.extend((n as u32).to_le_bytes());
        frame.extend(((16 + 4 + body.len()) as u32).to_le_bytes());
        frame.extend(20u32.to_le_bytes());
        frame.extend(body);
        assert_eq!(blosc(&frame, n).unwrap(), raw);
        assert!(blosc(&frame, n + 1).is_none());
        // Truncated frames fail cleanly.
        for cut in [3, 17, 25, frame.len() - 1] {
            assert!(blosc(&frame[..cut], n).is_none());
        }
    }
}
