//! Max-heap entries for the error-bounded backends: the octree's error list, Lightcuts' cut and
//! Ward's potential contributions all take the entry with the largest key first.

use core::cmp::Ordering;

/// An entry ranked by `key`, largest first; equal keys by the lower `index`, so the order — and
/// with it every result — depends only on the input.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Ranked<T> {
    /// What the entry is ranked by (a bound or a potential contribution).
    pub key: f32,
    /// The node or light.
    pub index: u32,
    /// What travels with it.
    pub item: T,
}

impl<T> PartialEq for Ranked<T> {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}

impl<T> Eq for Ranked<T> {}

impl<T> PartialOrd for Ranked<T> {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl<T> Ord for Ranked<T> {
    fn cmp(&self, other: &Self) -> Ordering {
        self.key
            .total_cmp(&other.key)
            .then(other.index.cmp(&self.index))
    }
}
