//! [`TimeSpan`]: the one rule for the time span of a log, and the rows that lie
//! outside it.
//!
//! Every output that draws or writes a time axis (the report, plots, MCAP files, cuts,
//! aligned tables, a dataset's `duration_s`) takes the span from here, so that one
//! stale timestamp cannot stretch any of them.

use core::fmt;

/// A row stamped this long before the log's start is named as an outlier; rows
/// closer to it are the usual first samples PX4's logger writes as it subscribes
/// (the topic's last value, published a moment before logging began).
pub const EARLY_OUTLIER_US: u64 = 60_000_000;

/// A row that jumps this far ahead of every row before it (and further than the log
/// has lasted so far) is out of the span unless the next row jumps as far.
pub const JUMP_US: u64 = 60_000_000;

/// In a log whose header has no time, the rows before a jump forward are stale
/// (made before logging began) when they are fewer than this.
pub const STALE_RUN_ROWS: usize = 10;

/// Which side of the span an outlier lies on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum OutlierSide {
    /// Stamped before the log's start: a value made before logging began (PX4 logs a
    /// topic's last sample when it subscribes, however old), whose value was current
    /// when logging began: time axes place it at the start. Or a timestamp never set
    /// (0, [`SpanOutlier::earliest`]), which time axes leave out.
    BeforeStart,
    /// Stamped far after every row around it in the file (a timestamp of another
    /// clock, or garbage): outputs leave it off the time axis.
    AfterEnd,
}

/// Rows of one topic instance outside a log's [`TimeSpan`], named because they lie
/// far from it (see [`TimeSpan`] for the rule).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SpanOutlier {
    /// The topic instance: its index in [`ULog::subscriptions`](crate::ULog::subscriptions).
    pub subscription: usize,
    /// Which side.
    pub side: OutlierSide,
    /// How many rows.
    pub rows: u64,
    /// The byte offset of the first such row's message.
    pub offset: u64,
    /// The smallest and largest timestamp among them.
    pub earliest: u64,
    /// See `earliest`.
    pub latest: u64,
}

/// The time span of a log: from its start to its end, in the log's microseconds.
///
/// The rule, one for every output of this library:
///
/// - **Start**: the header's timestamp, when logging started; for a log whose header
///   has none (0: written by another tool, or zeroed), its smallest non-zero data
///   timestamp (0 is PX4's "never set") after the rows it cannot tell from stale
///   ones: fewer than [`STALE_RUN_ROWS`] rows that the log then jumps ahead of, at
///   its first jump (see the end).
/// - **Before the start**: rows stamped before the start hold values made before
///   logging began (PX4's logger writes each topic's last sample as it subscribes).
///   They are data like any other, but on a time axis they stand at the start, when
///   they were recorded. Those more than [`EARLY_OUTLIER_US`] before it are named in
///   [`outliers`](TimeSpan::outliers) (a few rows a moment before the start are in
///   every PX4 log, and are not). Rows stamped 0 in a log whose header has a time
///   (or whose start lies further than that from 0) were never stamped (some PX4
///   topics never set their timestamp): they are named too, and left off time axes.
/// - **End**: the largest timestamp of the rows in the span. A row (in file order)
///   that jumps ahead of every row before it by more than [`JUMP_US`] and more than
///   the log has lasted so far is out of the span, unless the next row jumps as far
///   (the log really moved on: logging resumed after a gap); an outlier's rows are
///   named in [`outliers`](TimeSpan::outliers) and left off time axes.
///
/// [`ULog::last_timestamp`](crate::ULog::last_timestamp) stays pyulog's (the largest
/// timestamp of any row), which an outlier can set.
///
/// ```
/// use ulog_core::testing::LogBuilder;
/// use ulog_core::read::OutlierSide;
///
/// let mut b = LogBuilder::new(1, 400_000_000); // logging started 400 s after boot
/// b.format("position_setpoint_triplet:uint64_t timestamp;float x;");
/// b.format("sensor_combined:uint64_t timestamp;float x;");
/// b.subscribe(0, 0, "position_setpoint_triplet").subscribe(0, 1, "sensor_combined");
/// let row = |t: u64| [&t.to_le_bytes()[..], &1f32.to_le_bytes()].concat();
/// b.data(0, &row(60_000_000)); // a setpoint made 340 s before logging began
/// for t in 0..45 {
///     b.data(1, &row(400_000_000 + t * 1_000_000));
/// }
/// let bytes = b.into_bytes();
/// let log = ulog_core::ULog::parse(&bytes)?;
/// let span = log.span();
/// assert_eq!((span.start(), span.end()), (400_000_000, 444_000_000));
/// assert_eq!(span.duration_s(), 44.0);
/// assert_eq!(span.outliers()[0].side, OutlierSide::BeforeStart);
/// assert_eq!(span.axis_time(60_000_000), Some(400_000_000)); // drawn at the start
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct TimeSpan {
    start: u64,
    end: u64,
    /// Whether a timestamp of 0 means "never set" (the log has a start time).
    zero_unset: bool,
    outliers: Vec<SpanOutlier>,
}

impl TimeSpan {
    /// A span from `start` to `end` (microseconds; `end` below `start` is taken as
    /// `start`) with no outliers, in which 0 is a time like any other: for a window
    /// a program draws or writes over, as [`ULog::span`](crate::ULog::span) gives a
    /// log's.
    pub fn new(start: u64, end: u64) -> TimeSpan {
        TimeSpan {
            start,
            end: end.max(start),
            zero_unset: false,
            outliers: Vec::new(),
        }
    }

    /// The start, in the log's microseconds.
    pub fn start(&self) -> u64 {
        self.start
    }

    /// The end (the largest timestamp in the span; the start when there is none).
    pub fn end(&self) -> u64 {
        self.end
    }

    /// The length in microseconds.
    pub fn duration_us(&self) -> u64 {
        self.end - self.start
    }

    /// The length in seconds.
    pub fn duration_s(&self) -> f64 {
        self.duration_us() as f64 / 1e6
    }

    /// The rows far outside the span, per topic instance and side, in the order
    /// they were met.
    pub fn outliers(&self) -> &[SpanOutlier] {
        &self.outliers
    }

    /// Where a row stamped `timestamp` stands on the log's time axis: its own time
    /// inside the span, the start before it (a value current when logging began);
    /// `None` after the end (a stray row) and for a timestamp never set (0 in a log
    /// with a start time), which are left off the axis.
    pub fn axis_time(&self, timestamp: u64) -> Option<u64> {
        if timestamp > self.end || (timestamp == 0 && self.zero_unset) {
            return None;
        }
        Some(timestamp.max(self.start))
    }

    /// The time a row stamped `timestamp` was recorded at, for formats that need one
    /// for every row (MCAP's log time): [`axis_time`](TimeSpan::axis_time), the start
    /// for a timestamp never set, the end for a stray one.
    pub fn recorded_at(&self, timestamp: u64) -> u64 {
        timestamp.clamp(self.start, self.end)
    }

    /// Seconds from the start to `timestamp` (negative before it).
    pub fn seconds(&self, timestamp: u64) -> f64 {
        (timestamp as f64 - self.start as f64) / 1e6
    }

    /// The boot time (microseconds) of `seconds` since the start, rounded to the
    /// microsecond; the inverse of [`seconds`](Self::seconds) (0 for negative
    /// seconds before a start less than their magnitude).
    ///
    /// ```
    /// let span = ulog_core::read::TimeSpan::new(1_000_000, 9_000_000);
    /// assert_eq!(span.at(2.5), 3_500_000);
    /// assert_eq!(span.seconds(span.at(2.5)), 2.5);
    /// ```
    pub fn at(&self, seconds: f64) -> u64 {
        let us = (seconds * 1e6).round();
        if us >= 0.0 {
            self.start.saturating_add(us as u64)
        } else {
            self.start.saturating_sub((-us) as u64)
        }
    }

    /// Whether `timestamp` lies in the span, both ends included.
    pub fn contains(&self, timestamp: u64) -> bool {
        (self.start..=self.end).contains(&timestamp)
    }
}

impl SpanOutlier {
    /// What the rows are, for a topic named `topic` (its name and instance) in a log
    /// whose span is `span`: a line for findings.
    pub fn describe(&self, topic: &str, span: &TimeSpan) -> String {
        let rows = if self.rows == 1 {
            "1 row".to_owned()
        } else {
            format!("{} rows", self.rows)
        };
        match self.side {
            OutlierSide::BeforeStart if self.earliest == 0 => format!(
                "{rows} of `{topic}` stamped 0 (never set), from byte {}: left off the time axis",
                self.offset
            ),
            OutlierSide::BeforeStart => format!(
                "{rows} of `{topic}` stamped up to {:.1} s before the log's start (made before logging began), from byte {}: placed at the start",
                -span.seconds(self.earliest),
                self.offset
            ),
            OutlierSide::AfterEnd => format!(
                "{rows} of `{topic}` stamped {:.1} s after the start, far beyond the rows around {} in the file (the log ends at {:.1} s), from byte {}: left off the time axis",
                span.seconds(self.earliest),
                if self.rows == 1 { "it" } else { "them" },
                span.duration_s(),
                self.offset
            ),
        }
    }
}

impl fmt::Display for OutlierSide {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            OutlierSide::BeforeStart => "before the start",
            OutlierSide::AfterEnd => "after the end",
        })
    }
}

/// One row met, waiting for the next to say whether its jump was real.
#[derive(Debug, Clone, Copy)]
struct Row {
    sub: usize,
    timestamp: u64,
    offset: u64,
}

/// Follows the rows of a log in file order and finds its [`TimeSpan`]: the
/// whole-file parse and a pass that keeps the metadata feed one each, so both give
/// the same span.
#[derive(Debug, Clone, Default)]
pub(crate) struct SpanTracker {
    /// The header's timestamp (0: none).
    header: u64,
    /// The largest timestamp in the span so far.
    clock: Option<u64>,
    /// The smallest non-zero timestamp in the span so far (the start of a log whose
    /// header has none).
    low: Option<u64>,
    pending: Option<Row>,
    outliers: Vec<SpanOutlier>,
    /// Rows stamped 0 of a log whose header has no time: named if the start is
    /// far from 0.
    zeros: Vec<SpanOutlier>,
    /// In a log whose header has no time, the rows of the span so far while they
    /// are fewer than [`STALE_RUN_ROWS`]: stale if the log jumps ahead of them.
    first_rows: Vec<Row>,
    /// Whether the span so far has [`STALE_RUN_ROWS`] rows (or the header a time).
    settled: bool,
    /// The timestamps (inclusive) of the usual row, which only moves the clock or the
    /// low: settled, nothing pending, not 0, not before the header, no jump. Kept
    /// with the state it follows from ([`SpanTracker::refresh`]), so that the usual
    /// row costs two compares (the keeping pass of a 302 MB log in memory: 0.089 s →
    /// 0.086 s, the calls to `jumps` and `confirm` gone from its profile).
    usual: (u64, u64),
}

impl SpanTracker {
    /// Starts following a log whose header's timestamp is `header`.
    pub fn new(header: u64) -> SpanTracker {
        let mut tracker = SpanTracker {
            header,
            clock: (header > 0).then_some(header),
            settled: header > 0,
            ..SpanTracker::default()
        };
        tracker.refresh();
        tracker
    }

    /// The header's timestamp it follows.
    pub fn header(&self) -> u64 {
        self.header
    }

    /// A row of subscription `sub` stamped `timestamp`, its message at `offset`.
    #[inline(always)]
    pub fn push(&mut self, sub: usize, timestamp: u64, offset: u64) {
        let (low, high) = self.usual;
        if (low..=high).contains(&timestamp) {
            // Most rows move neither bound.
            let above = self.clock.map_or(true, |c| timestamp > c);
            let below = self.low.map_or(true, |l| timestamp < l);
            if above || below {
                self.confirm(timestamp);
                self.refresh();
            }
            return;
        }
        self.push_other(Row {
            sub,
            timestamp,
            offset,
        });
        self.refresh();
    }

    /// Where the usual row's timestamps lie, for the state as it stands.
    #[inline(always)]
    fn refresh(&mut self) {
        self.usual = match self.clock {
            Some(clock) if self.pending.is_none() && self.settled => {
                let start = if self.header > 0 {
                    self.header
                } else {
                    self.low.unwrap_or(clock)
                };
                let limit = JUMP_US.max(clock.saturating_sub(start));
                (self.header.max(1), clock.saturating_add(limit))
            }
            // None: every row takes the long way.
            _ => (1, 0),
        };
    }

    /// A row that is not the usual one (or may not be).
    fn push_other(&mut self, row: Row) {
        let timestamp = row.timestamp;
        if timestamp < self.header {
            if timestamp == 0 || self.header - timestamp > EARLY_OUTLIER_US {
                note(&mut self.outliers, OutlierSide::BeforeStart, row);
            }
            return;
        }
        if timestamp == 0 && self.header == 0 {
            note(&mut self.zeros, OutlierSide::BeforeStart, row);
            return;
        }
        // The usual row is no jump, with nothing pending.
        if self.pending.is_none() && self.settled && !self.jumps(timestamp) {
            self.confirm(timestamp);
            return;
        }
        self.decide(row);
    }

    #[cold]
    fn decide(&mut self, row: Row) {
        if let Some(p) = self.pending.take() {
            if self.jumps(row.timestamp) {
                // The log moved on: the pending row's jump was real. Before it, a
                // few rows of a log without a start time were stale.
                if !self.settled {
                    for stale in std::mem::take(&mut self.first_rows) {
                        note(&mut self.outliers, OutlierSide::BeforeStart, stale);
                    }
                    self.clock = None;
                    self.low = None;
                    // Only the first jump: the rows after it are the log's.
                    self.settled = true;
                }
                self.admit(p);
            } else {
                note(&mut self.outliers, OutlierSide::AfterEnd, p);
            }
        }
        if self.jumps(row.timestamp) {
            self.pending = Some(row);
        } else {
            self.admit(row);
        }
    }

    /// Takes `row` into the span.
    fn admit(&mut self, row: Row) {
        if !self.settled {
            self.first_rows.push(row);
            if self.first_rows.len() >= STALE_RUN_ROWS {
                self.settled = true;
                self.first_rows = Vec::new();
            }
        }
        self.confirm(row.timestamp);
    }

    /// Whether `timestamp` jumps ahead of the span so far.
    fn jumps(&self, timestamp: u64) -> bool {
        let Some(clock) = self.clock else {
            return false;
        };
        let start = if self.header > 0 {
            self.header
        } else {
            self.low.unwrap_or(clock)
        };
        let limit = JUMP_US.max(clock.saturating_sub(start));
        timestamp > clock.saturating_add(limit)
    }

    #[inline(always)]
    fn confirm(&mut self, timestamp: u64) {
        self.clock = Some(self.clock.map_or(timestamp, |c| c.max(timestamp)));
        if timestamp > 0 {
            self.low = Some(self.low.map_or(timestamp, |l| l.min(timestamp)));
        }
    }

    /// The span of the rows followed.
    pub fn finish(mut self) -> TimeSpan {
        if let Some(p) = self.pending.take() {
            note(&mut self.outliers, OutlierSide::AfterEnd, p);
        }
        let start = if self.header > 0 {
            self.header
        } else {
            self.low.unwrap_or(0)
        };
        // Zeros of another writer's log may be real times; far from the start they
        // are not.
        if start > EARLY_OUTLIER_US {
            self.outliers.append(&mut self.zeros);
        }
        TimeSpan {
            start,
            end: self.clock.unwrap_or(start).max(start),
            zero_unset: self.header > 0 || start > EARLY_OUTLIER_US,
            outliers: self.outliers,
        }
    }
}

/// Counts `row` among the outliers of its topic instance and side.
#[cold]
fn note(outliers: &mut Vec<SpanOutlier>, side: OutlierSide, row: Row) {
    match outliers
        .iter_mut()
        .find(|o| o.subscription == row.sub && o.side == side)
    {
        Some(o) => {
            o.rows += 1;
            o.earliest = o.earliest.min(row.timestamp);
            o.latest = o.latest.max(row.timestamp);
        }
        None => outliers.push(SpanOutlier {
            subscription: row.sub,
            side,
            rows: 1,
            offset: row.offset,
            earliest: row.timestamp,
            latest: row.timestamp,
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const S: u64 = 1_000_000;

    fn span(header: u64, rows: &[(usize, u64)]) -> TimeSpan {
        let mut t = SpanTracker::new(header);
        for (i, &(sub, ts)) in rows.iter().enumerate() {
            t.push(sub, ts, i as u64);
        }
        t.finish()
    }

    #[test]
    fn rows_a_moment_before_the_start_are_not_named() {
        let s = span(100 * S, &[(0, 99 * S), (1, 100 * S), (1, 130 * S)]);
        assert_eq!((s.start(), s.end()), (100 * S, 130 * S));
        assert!(s.outliers().is_empty());
        assert_eq!(s.axis_time(99 * S), Some(100 * S));
    }

    #[test]
    fn stale_and_unset_rows_are_named_before_the_start() {
        let s = span(400 * S, &[(0, 60 * S), (2, 0), (0, 59 * S), (1, 401 * S)]);
        assert_eq!((s.start(), s.end()), (400 * S, 401 * S));
        let o = s.outliers();
        assert_eq!(o.len(), 2);
        assert_eq!((o[0].subscription, o[0].rows), (0, 2));
        assert_eq!(
            (o[0].earliest, o[0].latest, o[0].offset),
            (59 * S, 60 * S, 0)
        );
        assert_eq!((o[1].subscription, o[1].earliest), (2, 0));
        assert!(o.iter().all(|o| o.side == OutlierSide::BeforeStart));
        assert_eq!(s.axis_time(59 * S), Some(400 * S));
        assert_eq!(s.axis_time(0), None);
        assert_eq!(s.recorded_at(0), 400 * S);
    }

    #[test]
    fn a_lone_jump_ahead_is_out_of_the_span() {
        let rows = [
            (0, 21 * S),
            (1, 22 * S),
            (2, 1194 * S),
            (0, 23 * S),
            (1, 26 * S),
        ];
        let s = span(20 * S, &rows);
        assert_eq!(s.end(), 26 * S);
        assert_eq!(s.outliers().len(), 1);
        assert_eq!(s.outliers()[0].side, OutlierSide::AfterEnd);
        assert_eq!(s.axis_time(1194 * S), None);
        // Last in the file, nothing follows to confirm it.
        let s = span(20 * S, &[(0, 21 * S), (2, 1194 * S)]);
        assert_eq!((s.end(), s.outliers().len()), (21 * S, 1));
    }

    #[test]
    fn a_gap_that_the_log_follows_is_kept() {
        // Logging resumed 300 s later: every topic jumps.
        let s = span(
            10 * S,
            &[(0, 11 * S), (1, 12 * S), (0, 312 * S), (1, 312 * S)],
        );
        assert_eq!(s.end(), 312 * S);
        assert!(s.outliers().is_empty());
        // Sparse rows, further apart than the jump limit but no further than the log
        // has lasted.
        let sparse: Vec<_> = (0..6).map(|i| (0, S + i * 500 * S)).collect();
        let s = span(S, &sparse);
        assert_eq!((s.start(), s.end()), (S, 2501 * S));
        assert!(s.outliers().is_empty(), "{:?}", s.outliers());
        // Without a start time, the first row cannot be told from a stale one.
        let s = span(0, &sparse);
        assert_eq!((s.start(), s.end()), (501 * S, 2501 * S));
        assert_eq!(s.outliers().len(), 1);
    }

    #[test]
    fn a_header_without_time_starts_after_a_few_stale_rows() {
        let mut rows = vec![(1, 4888 * S), (2, 0)];
        rows.extend((0..20).map(|i| (0, (5228 + i) * S)));
        let s = span(0, &rows);
        assert_eq!((s.start(), s.end()), (5228 * S, 5247 * S));
        let o = s.outliers();
        assert_eq!(o.len(), 2, "{o:?}");
        assert_eq!(
            (o[0].subscription, o[0].side),
            (1, OutlierSide::BeforeStart)
        );
        assert_eq!((o[1].subscription, o[1].earliest), (2, 0));
        // Many rows before the jump: logging resumed after a gap.
        let mut rows: Vec<_> = (0..20).map(|i| (0, (100 + i) * S)).collect();
        rows.extend((0..20).map(|i| (0, (500 + i) * S)));
        let s = span(0, &rows);
        assert_eq!((s.start(), s.end()), (100 * S, 519 * S));
        assert!(s.outliers().is_empty());
    }

    #[test]
    fn a_header_without_time_starts_at_the_first_set_timestamp() {
        let s = span(0, &[(0, 0), (1, 5228 * S), (1, 5229 * S), (0, 5250 * S)]);
        assert_eq!((s.start(), s.end()), (5228 * S, 5250 * S));
        assert_eq!(s.outliers().len(), 1);
        assert_eq!(s.outliers()[0].earliest, 0);
        // Times that start at 0 in a log of another writer: nothing is named.
        let s = span(0, &[(0, 0), (0, 1), (0, 2)]);
        assert_eq!((s.start(), s.end()), (1, 2));
        assert!(s.outliers().is_empty());
        assert_eq!(s.axis_time(0), Some(1));
        assert_eq!(s.recorded_at(7), 2);
        let s = span(0, &[(0, 0), (1, 0)]);
        assert_eq!((s.start(), s.end()), (0, 0));
        assert!(s.outliers().is_empty());
        assert_eq!(span(7, &[]).duration_us(), 0);
    }
}
