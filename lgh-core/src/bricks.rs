//! A sparse, bricked index over integer grid coordinates.
//!
//! Items (grid vertices of a level, or level-1 cells that hold level-0 lights) are identified by the
//! Morton code of their coordinates and stored densely in Morton order. Items are grouped in
//! bricks of 4×4×4; each brick keeps a 64-bit occupancy mask (bit = Morton index inside the brick)
//! and the dense index of its first item, so the dense index of any item is
//! `first + popcount(mask & below(bit))`. Bricks are found through a dense table when the level's
//! brick bounding box is small, and through an open-addressing hash table otherwise — so lights a
//! million units apart never make a dense grid.
//!
//! Nothing here allocates after construction.

use alloc::vec;
use alloc::vec::Vec;

use crate::morton;

/// One 4×4×4 brick of occupied items.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Brick {
    /// Bit `b` set ⇔ the item with in-brick Morton index `b` exists.
    pub mask: u64,
    /// Dense index of the brick's first item.
    pub first: u32,
    /// Brick coordinates (item coordinates divided by 4).
    pub coord: [u32; 3],
}

#[derive(Clone, Debug)]
enum Lookup {
    /// `table[(z·dy + y)·dx + x]` = brick index + 1, or 0 for none; coordinates relative to `min`.
    Dense {
        min: [u32; 3],
        dims: [u32; 3],
        table: Vec<u32>,
    },
    /// Linear probing; `keys[i] == EMPTY` marks a free slot.
    Hash {
        keys: Vec<u64>,
        values: Vec<u32>,
        bits: u32,
    },
}

const EMPTY: u64 = u64::MAX;

#[inline(always)]
fn hash(key: u64, bits: u32) -> usize {
    (key.wrapping_mul(0x9E37_79B9_7F4A_7C15) >> (64 - bits)) as usize
}

/// See the module documentation.
#[derive(Clone, Debug)]
pub(crate) struct BrickIndex {
    bricks: Vec<Brick>,
    lookup: Lookup,
    /// Bounding box of the item coordinates (inclusive); meaningless when empty.
    pub item_min: [u32; 3],
    pub item_max: [u32; 3],
}

impl BrickIndex {
    /// Builds the index of items given by strictly increasing Morton codes.
    pub fn from_sorted_codes(codes: &[u64]) -> Self {
        let mut bricks: Vec<Brick> = Vec::new();
        let mut item_min = [u32::MAX; 3];
        let mut item_max = [0u32; 3];
        for (i, &code) in codes.iter().enumerate() {
            debug_assert!(i == 0 || codes[i - 1] < code);
            let key = code >> 6;
            let bit = code & 63;
            match bricks.last_mut() {
                Some(b) if morton::encode(b.coord) == key => b.mask |= 1 << bit,
                _ => bricks.push(Brick {
                    mask: 1 << bit,
                    first: i as u32,
                    coord: morton::decode(key),
                }),
            }
            let c = morton::decode(code);
            for a in 0..3 {
                item_min[a] = item_min[a].min(c[a]);
                item_max[a] = item_max[a].max(c[a]);
            }
        }
        let lookup = Self::make_lookup(&bricks, item_min, item_max);
        BrickIndex {
            bricks,
            lookup,
            item_min,
            item_max,
        }
    }

    fn make_lookup(bricks: &[Brick], item_min: [u32; 3], item_max: [u32; 3]) -> Lookup {
        if bricks.is_empty() {
            return Lookup::Dense {
                min: [0; 3],
                dims: [0; 3],
                table: Vec::new(),
            };
        }
        let min = [item_min[0] >> 2, item_min[1] >> 2, item_min[2] >> 2];
        let dims = [
            (item_max[0] >> 2) - min[0] + 1,
            (item_max[1] >> 2) - min[1] + 1,
            (item_max[2] >> 2) - min[2] + 1,
        ];
        let cells = dims[0] as u64 * dims[1] as u64 * dims[2] as u64;
        let budget = (8 * bricks.len() as u64).clamp(4096, 1 << 26);
        if cells <= budget {
            let mut table = vec![0u32; cells as usize];
            for (i, b) in bricks.iter().enumerate() {
                let r = [
                    b.coord[0] - min[0],
                    b.coord[1] - min[1],
                    b.coord[2] - min[2],
                ];
                table[((r[2] * dims[1] + r[1]) * dims[0] + r[0]) as usize] = i as u32 + 1;
            }
            Lookup::Dense { min, dims, table }
        } else {
            let bits = (2 * bricks.len())
                .next_power_of_two()
                .trailing_zeros()
                .max(4);
            let size = 1usize << bits;
            let mut keys = vec![EMPTY; size];
            let mut values = vec![0u32; size];
            for (i, b) in bricks.iter().enumerate() {
                let key = morton::encode(b.coord);
                let mut slot = hash(key, bits);
                while keys[slot] != EMPTY {
                    slot = (slot + 1) & (size - 1);
                }
                keys[slot] = key;
                values[slot] = i as u32;
            }
            Lookup::Hash { keys, values, bits }
        }
    }

    /// True if the index holds no item.
    pub fn is_empty(&self) -> bool {
        self.bricks.is_empty()
    }

    /// The brick with brick coordinates `b`, if any item lies in it.
    #[inline]
    pub fn brick(&self, b: [u32; 3]) -> Option<&Brick> {
        match &self.lookup {
            Lookup::Dense { min, dims, table } => {
                let r = [
                    b[0].wrapping_sub(min[0]),
                    b[1].wrapping_sub(min[1]),
                    b[2].wrapping_sub(min[2]),
                ];
                if r[0] >= dims[0] || r[1] >= dims[1] || r[2] >= dims[2] {
                    return None;
                }
                let i = table[((r[2] * dims[1] + r[1]) * dims[0] + r[0]) as usize];
                if i == 0 {
                    None
                } else {
                    Some(&self.bricks[(i - 1) as usize])
                }
            }
            Lookup::Hash { keys, values, bits } => {
                if b.iter().any(|&c| c > morton::MAX_COORD) {
                    return None;
                }
                let key = morton::encode(b);
                let mask = (1usize << bits) - 1;
                let mut slot = hash(key, *bits);
                loop {
                    let k = keys[slot];
                    if k == key {
                        return Some(&self.bricks[values[slot] as usize]);
                    }
                    if k == EMPTY {
                        return None;
                    }
                    slot = (slot + 1) & mask;
                }
            }
        }
    }

    /// Dense index of the item at coordinates `c`, if it exists.
    #[inline]
    pub fn rank(&self, c: [u32; 3]) -> Option<u32> {
        let b = self.brick([c[0] >> 2, c[1] >> 2, c[2] >> 2])?;
        let bit = morton::encode([c[0] & 3, c[1] & 3, c[2] & 3]);
        if b.mask & (1 << bit) == 0 {
            return None;
        }
        Some(b.first + (b.mask & ((1u64 << bit) - 1)).count_ones())
    }

    /// Calls `f(first, count)` with the dense index range of the items of every brick that overlaps
    /// the box `lo..=hi` (inclusive item coordinates) and for which `keep_brick(brick coordinates)`
    /// is true. A brick's items are contiguous, so callers scan whole ranges; items of a reported
    /// brick may lie outside the box.
    ///
    /// When the box spans more bricks than the index holds, the brick list is scanned instead of
    /// the box, so the cost is bounded by the smaller of the two.
    #[inline]
    pub fn for_each_brick(
        &self,
        lo: [u32; 3],
        hi: [u32; 3],
        mut keep_brick: impl FnMut([u32; 3]) -> bool,
        mut f: impl FnMut(u32, u32),
    ) {
        let blo = [lo[0] >> 2, lo[1] >> 2, lo[2] >> 2];
        let bhi = [hi[0] >> 2, hi[1] >> 2, hi[2] >> 2];
        let span = (bhi[0] - blo[0] + 1) as u64
            * (bhi[1] - blo[1] + 1) as u64
            * (bhi[2] - blo[2] + 1) as u64;
        if span > self.bricks.len() as u64 {
            for b in &self.bricks {
                let inside = (0..3).all(|a| b.coord[a] >= blo[a] && b.coord[a] <= bhi[a]);
                if inside && keep_brick(b.coord) {
                    f(b.first, b.mask.count_ones());
                }
            }
        } else {
            for bz in blo[2]..=bhi[2] {
                for by in blo[1]..=bhi[1] {
                    for bx in blo[0]..=bhi[0] {
                        let c = [bx, by, bz];
                        if !keep_brick(c) {
                            continue;
                        }
                        if let Some(b) = self.brick(c) {
                            f(b.first, b.mask.count_ones());
                        }
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn build(coords: &[[u32; 3]]) -> (BrickIndex, Vec<u64>) {
        let mut codes: Vec<u64> = coords.iter().map(|&c| morton::encode(c)).collect();
        codes.sort_unstable();
        codes.dedup();
        (BrickIndex::from_sorted_codes(&codes), codes)
    }

    #[test]
    fn rank_matches_sorted_position_dense_and_hashed() {
        let mut coords = Vec::new();
        for i in 0..500u32 {
            coords.push([(i * 7) % 23, (i * 13) % 17, (i * 5) % 11]);
        }
        // Far-apart items force the hash lookup.
        let mut far = coords.clone();
        far.push([2_000_000, 3, 1_500_000]);
        for set in [coords, far] {
            let (idx, codes) = build(&set);
            for (i, &code) in codes.iter().enumerate() {
                assert_eq!(idx.rank(morton::decode(code)), Some(i as u32));
            }
            assert_eq!(idx.rank([100, 100, 100]), None);
        }
    }

    #[test]
    fn brick_ranges_cover_exactly_the_items_in_the_box() {
        let coords: Vec<[u32; 3]> = (0..2000u32)
            .map(|i| [(i * 31) % 40, (i * 17) % 37, (i * 7) % 29])
            .collect();
        let (idx, codes) = build(&coords);
        for (lo, hi) in [
            ([3, 5, 2], [17, 9, 28]),
            ([0, 0, 0], [100, 100, 100]),
            ([39, 36, 28], [39, 36, 28]),
        ] {
            let mut got = Vec::new();
            idx.for_each_brick(lo, hi, |_| true, |first, n| got.extend(first..first + n));
            got.sort_unstable();
            got.retain(|&i| {
                let c = morton::decode(codes[i as usize]);
                (0..3).all(|a| c[a] >= lo[a] && c[a] <= hi[a])
            });
            let want: Vec<u32> = codes
                .iter()
                .enumerate()
                .filter(|(_, &c)| {
                    let c = morton::decode(c);
                    (0..3).all(|a| c[a] >= lo[a] && c[a] <= hi[a])
                })
                .map(|(i, _)| i as u32)
                .collect();
            assert_eq!(got, want);
        }
    }
}
