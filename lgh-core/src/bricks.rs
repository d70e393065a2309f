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

    /// Calls `f(first, count)` with the dense index range of the items of every brick whose region
    /// (see [`Ball`]) meets `ball`. A brick's items are contiguous, so callers scan whole ranges;
    /// items of a reported brick may lie outside the ball.
    ///
    /// Bricks are enumerated row by row, each row's extent computed from the ball, so no brick
    /// outside it is looked up. When the ball's bounding box spans more bricks than the index holds,
    /// the brick list is scanned instead, so the cost is bounded by the smaller of the two.
    #[inline]
    pub fn for_each_brick_near(&self, ball: &Ball, mut f: impl FnMut(u32, u32)) {
        if self.bricks.is_empty() {
            return;
        }
        // Brick range of the ball's bounding box, clipped to the occupied bricks.
        let mut blo = [0u32; 3];
        let mut bhi = [0u32; 3];
        for a in 0..3 {
            let (lo, hi) = ball.brick_span(a);
            let lo = lo.max((self.item_min[a] >> 2) as f64);
            let hi = hi.min((self.item_max[a] >> 2) as f64);
            if lo > hi {
                return;
            }
            blo[a] = lo as u32;
            bhi[a] = hi as u32;
        }
        let span = (bhi[0] - blo[0] + 1) as u64
            * (bhi[1] - blo[1] + 1) as u64
            * (bhi[2] - blo[2] + 1) as u64;
        if span > self.bricks.len() as u64 {
            for b in &self.bricks {
                if ball.meets_brick(b.coord) {
                    f(b.first, b.mask.count_ones());
                }
            }
            return;
        }
        let r2 = ball.radius * ball.radius;
        for bz in blo[2]..=bhi[2] {
            let dz = ball.gap(2, bz);
            if dz * dz > r2 {
                continue;
            }
            for by in blo[1]..=bhi[1] {
                let dy = ball.gap(1, by);
                let rest = r2 - dz * dz - dy * dy;
                if rest < 0.0 {
                    continue;
                }
                let (from, to) = ball.row(crate::math::sqrt64(rest));
                let from = from.max(blo[0] as f64);
                let to = to.min(bhi[0] as f64);
                if from > to {
                    continue;
                }
                for bx in from as u32..=to as u32 {
                    if let Some(b) = self.brick([bx, by, bz]) {
                        f(b.first, b.mask.count_ones());
                    }
                }
            }
        }
    }
}

/// A query region in a level's integer coordinates: the ball of `radius` around `centre`, tested
/// against brick regions `[4b + lo_pad, 4b + hi_pad]` per axis. The pads say where a brick's items
/// can put their lights: level-0 cells `c` hold lights in `[c, c + 1]` (pads 0 and 4); a vertex `q`
/// has its illumination centre within one unit of `q` (pads −1 and 4).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Ball {
    pub centre: [f64; 3],
    pub radius: f64,
    pub lo_pad: f64,
    pub hi_pad: f64,
}

impl Ball {
    /// Distance along axis `a` from the centre to brick row `b`'s region (0 inside).
    #[inline]
    fn gap(&self, a: usize, b: u32) -> f64 {
        let lo = (b * 4) as f64 + self.lo_pad;
        let hi = (b * 4) as f64 + self.hi_pad;
        let t = self.centre[a];
        if t < lo {
            lo - t
        } else if t > hi {
            t - hi
        } else {
            0.0
        }
    }

    /// Brick coordinates (inclusive, possibly negative) whose regions meet the interval
    /// `centre[a] ± radius`.
    #[inline]
    fn brick_span(&self, a: usize) -> (f64, f64) {
        self.span(self.centre[a], self.radius)
    }

    #[inline]
    fn span(&self, t: f64, half: f64) -> (f64, f64) {
        // 4b + hi_pad ≥ t − half  and  4b + lo_pad ≤ t + half.
        let lo = crate::math::ceil64((t - half - self.hi_pad) * 0.25);
        let hi = crate::math::floor64((t + half - self.lo_pad) * 0.25);
        (lo.max(0.0), hi)
    }

    /// The x-range of bricks of a row whose remaining half-width is `half`.
    #[inline]
    fn row(&self, half: f64) -> (f64, f64) {
        self.span(self.centre[0], half)
    }

    /// True if brick `b`'s region meets the ball.
    #[inline]
    fn meets_brick(&self, b: [u32; 3]) -> bool {
        let d2: f64 = (0..3).map(|a| self.gap(a, b[a])).map(|g| g * g).sum();
        d2 <= self.radius * self.radius
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use wasm_bindgen_test::wasm_bindgen_test;

    fn build(coords: &[[u32; 3]]) -> (BrickIndex, Vec<u64>) {
        let mut codes: Vec<u64> = coords.iter().map(|&c| morton::encode(c)).collect();
        codes.sort_unstable();
        codes.dedup();
        (BrickIndex::from_sorted_codes(&codes), codes)
    }

    #[wasm_bindgen_test(unsupported = test)]
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

    #[wasm_bindgen_test(unsupported = test)]
    fn brick_ranges_cover_every_item_in_the_ball() {
        let mut coords: Vec<[u32; 3]> = (0..3000u32)
            .map(|i| [(i * 31) % 40, (i * 17) % 37, (i * 7) % 29])
            .collect();
        for far in [false, true] {
            if far {
                coords.push([1_500_000, 3, 9]); // forces the hash lookup
            }
            let (idx, codes) = build(&coords);
            for (centre, radius) in [
                ([10.3, 20.7, 5.5], 6.2),
                ([0.0, 0.0, 0.0], 3.0),
                ([39.0, 36.0, 28.0], 0.5),
                ([-5.0, 12.0, 50.0], 30.0),
                ([20.0, 20.0, 15.0], 1e7), // wider than the index: the brick list is scanned
            ] {
                let ball = Ball {
                    centre,
                    radius,
                    lo_pad: 0.0,
                    hi_pad: 3.0,
                };
                let mut got = Vec::new();
                idx.for_each_brick_near(&ball, |first, n| got.extend(first..first + n));
                let n = got.len();
                got.sort_unstable();
                got.dedup();
                assert_eq!(got.len(), n, "no brick reported twice");
                for (i, &code) in codes.iter().enumerate() {
                    let c = morton::decode(code);
                    let d2: f64 = (0..3).map(|a| (c[a] as f64 - centre[a]).powi(2)).sum();
                    if d2 <= radius * radius {
                        assert!(
                            got.binary_search(&(i as u32)).is_ok(),
                            "item {c:?} missed for {centre:?} r {radius}"
                        );
                    }
                }
            }
        }
    }
}
