//! The index of a topic's data messages: their file offsets in four bytes each (the
//! low 32 bits), with the rows where the high 32 bits change kept aside (a file
//! under 4 GiB has none). Half the memory of `u64` offsets, and half the writes
//! while a log is parsed.

/// The offsets of one subscription's data messages as [`ULog::parse`] builds them.
///
/// [`ULog::parse`]: crate::ULog::parse
#[derive(Debug, Clone, Default)]
pub(crate) struct OffsetIndex {
    low: Vec<u32>,
    /// `(row, high)`: from `row` on, the offsets' high 32 bits are `high`. Rows in
    /// increasing order; before the first entry the high bits are 0.
    high: Vec<(usize, u32)>,
}

impl OffsetIndex {
    /// Appends the offset of the next message (offsets come in file order).
    #[inline(always)]
    pub(crate) fn push(&mut self, offset: u64) {
        let high = (offset >> 32) as u32;
        if high != high_at(&self.high, usize::MAX).1 {
            self.new_high(high);
        }
        self.low.push(offset as u32);
    }

    #[cold]
    fn new_high(&mut self, high: u32) {
        self.high.push((self.low.len(), high));
    }

    /// Messages indexed.
    #[inline]
    pub(crate) fn len(&self) -> usize {
        self.low.len()
    }

    /// Whether the vector of low halves is full (the next push reallocates).
    #[inline(always)]
    pub(crate) fn is_full(&self) -> bool {
        self.low.len() == self.low.capacity()
    }

    /// Makes room for `additional` more messages at once.
    pub(crate) fn reserve_exact(&mut self, additional: usize) {
        self.low.reserve_exact(additional);
    }

    /// The view handed out by [`Topic::message_offsets`](crate::Topic::message_offsets).
    pub(crate) fn view(&self) -> MessageOffsets<'_> {
        MessageOffsets {
            low: &self.low,
            high: &self.high,
            first_row: 0,
        }
    }
}

/// The file offsets of a topic's data messages (of their 3-byte headers), in file
/// order: [`Topic::message_offsets`](crate::Topic::message_offsets). Stored in four
/// bytes a message; read as `u64`.
///
/// ```
/// # let bytes = ulog_core::testing::sample_log();
/// let log = ulog_core::ULog::parse(&bytes)?;
/// let topic = log.topic("vehicle_attitude", 0)?;
/// let offsets = topic.message_offsets();
/// assert_eq!(offsets.len(), topic.len());
/// let first = offsets.get(0).unwrap();
/// assert_eq!(bytes[first as usize + 2], b'D');
/// assert!(offsets.iter().zip(offsets.iter().skip(1)).all(|(a, b)| a < b));
/// assert_eq!(offsets.slice(1..3).to_vec(), offsets.to_vec()[1..3]);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, Clone, Copy)]
pub struct MessageOffsets<'l> {
    low: &'l [u32],
    /// As [`OffsetIndex::high`], rows counted from the whole index's first.
    high: &'l [(usize, u32)],
    /// The whole index's row of `low[0]`.
    first_row: usize,
}

impl<'l> MessageOffsets<'l> {
    /// Number of messages.
    pub fn len(&self) -> usize {
        self.low.len()
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.low.is_empty()
    }

    /// The offset of message `i`.
    pub fn get(&self, i: usize) -> Option<u64> {
        let low = *self.low.get(i)?;
        let (_, high) = high_at(self.high, self.first_row + i);
        Some(u64::from(high) << 32 | u64::from(low))
    }

    /// Messages `range` of these.
    ///
    /// # Panics
    /// If the range is out of bounds, as slicing is.
    pub fn slice(&self, range: core::ops::Range<usize>) -> MessageOffsets<'l> {
        MessageOffsets {
            low: &self.low[range.clone()],
            high: self.high,
            first_row: self.first_row + range.start,
        }
    }

    /// Every offset, in file order.
    pub fn iter(&self) -> OffsetsIter<'l> {
        let (from, high) = high_at(self.high, self.first_row);
        OffsetsIter {
            low: self.low.iter(),
            row: self.first_row,
            high,
            next: &self.high[from..],
        }
    }

    /// The offsets as a vector.
    pub fn to_vec(&self) -> Vec<u64> {
        self.iter().collect()
    }
}

/// The high 32 bits of the offset of `row`, and where in `high` the changes after
/// that row start.
#[inline]
fn high_at(high: &[(usize, u32)], row: usize) -> (usize, u32) {
    match high.last() {
        // No search when nothing changes (a file under 4 GiB) or `row` is past the
        // last change (every push).
        None => (0, 0),
        Some(&(last, h)) if last <= row => (high.len(), h),
        Some(_) => {
            let from = high.partition_point(|&(r, _)| r <= row);
            (from, from.checked_sub(1).map_or(0, |k| high[k].1))
        }
    }
}

impl<'l> IntoIterator for MessageOffsets<'l> {
    type Item = u64;
    type IntoIter = OffsetsIter<'l>;

    fn into_iter(self) -> OffsetsIter<'l> {
        self.iter()
    }
}

/// Iterator over [`MessageOffsets`].
#[derive(Debug, Clone)]
pub struct OffsetsIter<'l> {
    low: core::slice::Iter<'l, u32>,
    /// The row of the next offset.
    row: usize,
    high: u32,
    /// Where the high bits change next.
    next: &'l [(usize, u32)],
}

impl Iterator for OffsetsIter<'_> {
    type Item = u64;

    #[inline]
    fn next(&mut self) -> Option<u64> {
        let low = *self.low.next()?;
        if let Some(&(row, high)) = self.next.first() {
            if row == self.row {
                self.high = high;
                self.next = &self.next[1..];
            }
        }
        self.row += 1;
        Some(u64::from(self.high) << 32 | u64::from(low))
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        self.low.size_hint()
    }
}

impl ExactSizeIterator for OffsetsIter<'_> {}

#[cfg(test)]
mod tests {
    use super::OffsetIndex;

    #[test]
    fn offsets_past_4_gib_read_back_whole_by_index_slice_and_iterator() {
        let offsets: Vec<u64> = [16, 1 << 20, (1 << 32) - 3, 1 << 32, (1 << 32) + 9]
            .into_iter()
            .chain((0..5).map(|k| (5 << 32) + k * 1000))
            .chain([(7 << 32) + 1])
            .collect();
        let mut index = OffsetIndex::default();
        for &o in &offsets {
            index.push(o);
        }
        let view = index.view();
        assert_eq!(view.len(), offsets.len());
        assert_eq!(view.to_vec(), offsets);
        for (i, &o) in offsets.iter().enumerate() {
            assert_eq!(view.get(i), Some(o), "row {i}");
        }
        assert_eq!(view.get(offsets.len()), None);
        for start in 0..=offsets.len() {
            for end in start..=offsets.len() {
                let part = view.slice(start..end);
                assert_eq!(part.to_vec(), offsets[start..end], "{start}..{end}");
                assert_eq!(part.iter().len(), end - start);
                for i in 0..end - start {
                    assert_eq!(part.get(i), Some(offsets[start + i]), "{start}..{end} {i}");
                }
            }
        }
    }

    #[test]
    fn an_empty_index_has_no_offsets() {
        let index = OffsetIndex::default();
        assert!(index.view().is_empty());
        assert_eq!(index.view().iter().next(), None);
        assert_eq!(index.view().get(0), None);
    }
}
