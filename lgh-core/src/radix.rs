//! A stable least-significant-digit radix sort on 64-bit keys.
//!
//! Sorting the lights by Morton code is the largest single step of a build; the keys use only
//! `3 × log2(cells per axis)` bits, so a radix sort over the bytes that vary beats comparison
//! sorts by several times. Stability keeps ties in input order, which callers then break by value.

use alloc::vec::Vec;

/// Sorts `items` by `key` (stable). Digits (bytes) on which all keys agree are skipped.
pub(crate) fn sort_by_key<T: Copy>(items: &mut Vec<T>, key: impl Fn(&T) -> u64) {
    let n = items.len();
    if n < 2 {
        return;
    }
    let (mut or, mut and) = (0u64, u64::MAX);
    for it in items.iter() {
        let k = key(it);
        or |= k;
        and &= k;
    }
    let varying = or ^ and;
    let mut scratch: Vec<T> = Vec::with_capacity(n);
    for digit in 0..8 {
        let shift = digit * 8;
        if (varying >> shift) & 0xff == 0 {
            continue;
        }
        let mut offsets = [0usize; 256];
        for it in items.iter() {
            offsets[((key(it) >> shift) & 0xff) as usize] += 1;
        }
        let mut sum = 0;
        for o in offsets.iter_mut() {
            let c = *o;
            *o = sum;
            sum += c;
        }
        // Scatter into `scratch` (every slot is written exactly once), then swap buffers.
        scratch.clear();
        scratch.resize(n, items[0]);
        for it in items.iter() {
            let d = ((key(it) >> shift) & 0xff) as usize;
            scratch[offsets[d]] = *it;
            offsets[d] += 1;
        }
        core::mem::swap(items, &mut scratch);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use alloc::vec;
    use proptest::prelude::*;
    use wasm_bindgen_test::wasm_bindgen_test;

    proptest! {
        #[wasm_bindgen_test(unsupported = test)]
        fn matches_a_stable_comparison_sort(v in prop::collection::vec((any::<u64>(), any::<u16>()), 0..500),
                                            mask in any::<u64>()) {
            let mut a: Vec<(u64, u16, usize)> = v.iter().enumerate().map(|(i, &(k, p))| (k & mask, p, i)).collect();
            let mut b = a.clone();
            sort_by_key(&mut a, |t| t.0);
            b.sort_by_key(|t| t.0);
            prop_assert_eq!(a, b);
        }
    }

    #[wasm_bindgen_test(unsupported = test)]
    fn small_inputs() {
        let mut v: Vec<u64> = vec![];
        sort_by_key(&mut v, |&k| k);
        let mut v = vec![3u64, 1, 2];
        sort_by_key(&mut v, |&k| k);
        assert_eq!(v, [1, 2, 3]);
    }
}
