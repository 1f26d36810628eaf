//! A timeline held in memory: items with their times, sought by binary search.

use super::Timeline;

/// Items with their times (boot microseconds), in memory, played from the first; a
/// [`Timeline`] that hands out clones of its items.
///
/// ```
/// use ulog_core::replay::{Recorded, Timeline};
/// // Sorted by time as it is built; items of equal times keep their order.
/// let mut items = Recorded::new(vec![(30, "c"), (10, "a"), (20, "b1"), (20, "b2")]);
/// assert_eq!(items.advance(), Some((10, "a")));
/// items.seek(15);
/// assert_eq!(items.advance(), Some((20, "b1")));
/// items.seek(31);
/// assert_eq!(items.advance(), None);
/// ```
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Recorded<T> {
    items: Vec<(u64, T)>,
    next: usize,
}

impl<T> Recorded<T> {
    /// The items in time order (a stable sort: items of equal times keep the order
    /// given), positioned at the first.
    pub fn new(mut items: Vec<(u64, T)>) -> Recorded<T> {
        // Already sorted is the common case (a log's rows): a check, not a sort.
        if !items.windows(2).all(|w| w[0].0 <= w[1].0) {
            items.sort_by_key(|(t, _)| *t);
        }
        Recorded { items, next: 0 }
    }

    /// The items and their times, in time order.
    pub fn items(&self) -> &[(u64, T)] {
        &self.items
    }

    /// How many items there are.
    pub fn len(&self) -> usize {
        self.items.len()
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.items.is_empty()
    }

    /// The position of the item [`Timeline::advance`] gives next (`len()` at the end).
    pub fn position(&self) -> usize {
        self.next
    }

    /// The items, given back.
    pub fn into_items(self) -> Vec<(u64, T)> {
        self.items
    }
}

impl<T: Clone> Timeline for Recorded<T> {
    type Item = T;

    fn advance(&mut self) -> Option<(u64, T)> {
        let item = self.items.get(self.next)?.clone();
        self.next += 1;
        Some(item)
    }

    fn seek(&mut self, t_us: u64) {
        self.next = self.items.partition_point(|(t, _)| *t < t_us);
    }
}

impl<T> FromIterator<(u64, T)> for Recorded<T> {
    fn from_iter<I: IntoIterator<Item = (u64, T)>>(iter: I) -> Recorded<T> {
        Recorded::new(iter.into_iter().collect())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn seek_finds_the_first_item_at_or_after() {
        let mut r: Recorded<u8> = [(5, 0), (10, 1), (10, 2), (20, 3)].into_iter().collect();
        r.seek(10);
        assert_eq!(r.advance(), Some((10, 1)));
        r.seek(0);
        assert_eq!(r.position(), 0);
        r.seek(11);
        assert_eq!(r.advance(), Some((20, 3)));
        assert_eq!(r.advance(), None);
        r.seek(u64::MAX);
        assert_eq!(r.advance(), None);
        // Backwards too.
        r.seek(6);
        assert_eq!(r.advance(), Some((10, 1)));
    }

    #[test]
    fn empty() {
        let mut r = Recorded::<()>::new(Vec::new());
        r.seek(3);
        assert!(r.is_empty());
        assert_eq!(r.advance(), None);
    }
}
