//! Morton (Z-order) codes of non-negative integer grid coordinates, 21 bits per axis.
//!
//! Sorting lights by the Morton code of their level-1 cell makes every coarser cell a contiguous
//! run (a level-ℓ cell's code is the level-1 code shifted right by `3(ℓ−1)`), and makes every
//! 4×4×4 brick of vertices a contiguous run (the code shifted right by 6).

use alloc::vec::Vec;

/// Largest coordinate a Morton code can hold (21 bits).
pub const MAX_COORD: u32 = (1 << 21) - 1;

#[inline]
fn spread(v: u32) -> u64 {
    let mut x = (v & MAX_COORD) as u64;
    x = (x | (x << 32)) & 0x001f_0000_0000_ffff;
    x = (x | (x << 16)) & 0x001f_0000_ff00_00ff;
    x = (x | (x << 8)) & 0x100f_00f0_0f00_f00f;
    x = (x | (x << 4)) & 0x10c3_0c30_c30c_30c3;
    x = (x | (x << 2)) & 0x1249_2492_4924_9249;
    x
}

#[inline]
fn compact(v: u64) -> u32 {
    let mut x = v & 0x1249_2492_4924_9249;
    x = (x | (x >> 2)) & 0x10c3_0c30_c30c_30c3;
    x = (x | (x >> 4)) & 0x100f_00f0_0f00_f00f;
    x = (x | (x >> 8)) & 0x001f_0000_ff00_00ff;
    x = (x | (x >> 16)) & 0x001f_0000_0000_ffff;
    x = (x | (x >> 32)) & 0x0000_0000_001f_ffff;
    x as u32
}

/// Interleaves `[x, y, z]` (each ≤ [`MAX_COORD`]) into one code: x in bit 0, y in bit 1, z in bit 2.
#[inline]
#[must_use]
pub fn encode(c: [u32; 3]) -> u64 {
    spread(c[0]) | (spread(c[1]) << 1) | (spread(c[2]) << 2)
}

/// Inverse of [`encode`].
#[inline]
#[must_use]
pub fn decode(m: u64) -> [u32; 3] {
    [compact(m), compact(m >> 1), compact(m >> 2)]
}

/// Sorted, deduplicated Morton codes of the eight corners of every cell in `cells` (sorted codes).
pub(crate) fn corner_codes(cells: &[u64], out: &mut Vec<u64>) {
    out.clear();
    out.reserve(cells.len() * 8);
    for &code in cells {
        let c = decode(code);
        for k in 0..8u32 {
            out.push(encode([
                c[0] + (k & 1),
                c[1] + ((k >> 1) & 1),
                c[2] + (k >> 2),
            ]));
        }
    }
    crate::radix::sort_by_key(out, |&c| c);
    out.dedup();
}

#[cfg(test)]
mod tests {
    use super::*;
    use wasm_bindgen_test::wasm_bindgen_test;

    #[wasm_bindgen_test(unsupported = test)]
    fn round_trip_and_order() {
        for &c in &[
            [0, 0, 0],
            [1, 2, 3],
            [MAX_COORD, 0, 5],
            [12345, 678901, MAX_COORD],
        ] {
            assert_eq!(decode(encode(c)), c);
        }
        assert_eq!(encode([1, 0, 0]), 1);
        assert_eq!(encode([0, 1, 0]), 2);
        assert_eq!(encode([0, 0, 1]), 4);
        // A coarser cell (coordinates halved) is the code shifted by 3.
        let c = [13, 7, 22];
        assert_eq!(encode(c) >> 3, encode([c[0] >> 1, c[1] >> 1, c[2] >> 1]));
    }
}
