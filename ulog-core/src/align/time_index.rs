//! [`TimeIndex`]: one topic instance's rows in time order, and a cursor that walks
//! them with non-decreasing times.

use core::ops::Range;

use crate::access::topic::Topic;
use crate::read::Unwrapper;

/// The time index of a topic instance ([`Topic::time_index`]): its rows that have a
/// timestamp, in time order (file order among equal timestamps), the row and the
/// timestamp (boot microseconds, narrow version 0 ones unwrapped) of each, 12 bytes a
/// row; no values (they stay in the log's payloads). Built once in O(n), then a time
/// or a window is found in O(log n).
///
/// ```
/// let bytes = ulog_core::testing::sample_log();
/// let log = ulog_core::ULog::parse(&bytes)?;
/// let topic = log.topic("vehicle_attitude", 0)?;
/// let index = topic.time_index();
/// // Seconds 2 to 3 since the start of the log: the rows, by time.
/// let span = log.span();
/// let rows = index.rows_in(span.at(2.0), span.at(3.0));
/// assert_eq!(rows.len(), 20); // 20 a second
/// let q0 = topic.field("q[0]")?;
/// for &row in rows {
///     let payload = topic.payload(row as usize).unwrap();
///     assert!(q0.read(payload).is_some());
/// }
/// // The row as it was at a time, and where a time starts.
/// let (t, _row) = index.at_or_before(span.at(2.5)).unwrap();
/// assert!(t <= span.at(2.5) && span.at(2.5) - t < 50_000);
/// assert_eq!(index.times()[index.seek(t)], t);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, Clone, Default)]
pub struct TimeIndex {
    /// Timestamps, non-decreasing.
    pub(crate) times: Vec<u64>,
    /// The row of each, in the topic's file order.
    pub(crate) rows: Vec<u32>,
}

impl<'l, 'a> Topic<'l, 'a> {
    /// The topic's [`TimeIndex`]: its rows by time, to seek and take windows in.
    pub fn time_index(&self) -> TimeIndex {
        TimeIndex::of(self, |_| true)
    }
}

impl TimeIndex {
    /// The timestamps of the indexed rows, non-decreasing.
    pub fn times(&self) -> &[u64] {
        &self.times
    }

    /// The indexed rows (indices into the topic's rows, as
    /// [`Topic::payload`] and [`TypedRows::get`](crate::TypedRows::get) take them),
    /// in time order.
    pub fn rows(&self) -> &[u32] {
        &self.rows
    }

    /// How many rows are indexed (rows without a timestamp are not).
    pub fn len(&self) -> usize {
        self.times.len()
    }

    /// Whether no row is indexed.
    pub fn is_empty(&self) -> bool {
        self.times.is_empty()
    }

    /// The position (in [`times`](Self::times) and [`rows`](Self::rows)) of the
    /// first row at or after `t_us`; [`len`](Self::len) if none is.
    pub fn seek(&self, t_us: u64) -> usize {
        self.times.partition_point(|&t| t < t_us)
    }

    /// The positions of the rows in `[start_us, end_us)`.
    pub fn window(&self, start_us: u64, end_us: u64) -> Range<usize> {
        let start = self.seek(start_us);
        start..self.seek(end_us).max(start)
    }

    /// The rows in `[start_us, end_us)`, in time order.
    pub fn rows_in(&self, start_us: u64, end_us: u64) -> &[u32] {
        &self.rows[self.window(start_us, end_us)]
    }

    /// The last row at or before `t_us` (the last written among equal timestamps),
    /// with its timestamp.
    pub fn at_or_before(&self, t_us: u64) -> Option<(u64, u32)> {
        let i = self.times.partition_point(|&t| t <= t_us).checked_sub(1)?;
        Some((self.times[i], self.rows[i]))
    }

    /// The rows of `topic` that `keep` accepts (by payload), sorted by time.
    pub(crate) fn of(topic: &Topic<'_, '_>, keep: impl Fn(&[u8]) -> bool) -> TimeIndex {
        let mut u = Unwrapper::new(topic.timestamp_field());
        let mut pairs: Vec<(u64, u32)> = Vec::with_capacity(topic.len());
        for (i, payload) in topic.payloads().enumerate() {
            let Some(t) = u.push(payload) else { continue };
            if keep(payload) {
                pairs.push((t, i as u32));
            }
        }
        // Stable: equal timestamps stay in file order, so that "the last row at or
        // before t" is the last written.
        if !pairs.windows(2).all(|w| w[0].0 <= w[1].0) {
            pairs.sort_by_key(|p| p.0);
        }
        TimeIndex {
            times: pairs.iter().map(|p| p.0).collect(),
            rows: pairs.iter().map(|p| p.1).collect(),
        }
    }
}

/// A position in a [`TimeIndex`] for times that never decrease: how many rows lie at or
/// before the last time asked.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Cursor {
    at: usize,
}

impl Cursor {
    /// A cursor at the first row whose time is `t` or later (binary search: the
    /// start of a window).
    pub(crate) fn seek(series: &TimeIndex, t: u64) -> Cursor {
        Cursor {
            at: series.times.partition_point(|&x| x <= t),
        }
    }

    /// The neighbours of `t`: the last row at or before it and the first after it
    /// (positions in the series). `t` must not be less than the last time asked.
    pub(crate) fn around(&mut self, series: &TimeIndex, t: u64) -> (Option<usize>, Option<usize>) {
        let times = &series.times;
        while self.at < times.len() && times[self.at] <= t {
            self.at += 1;
        }
        let before = self.at.checked_sub(1);
        let after = (self.at < times.len()).then_some(self.at);
        (before, after)
    }
}
