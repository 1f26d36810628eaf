//! [`scan`]: one pass over the data messages of a log, keeping nothing. The fastest
//! way through a log when each message is needed once (a sum, a conversion, a
//! filter, columns built as the file goes by).
//!
//! Framing is the same as [`ULog::parse`]'s: definitions and subscriptions are learnt,
//! damage is stepped over and reported in the summary. Only data messages of known
//! subscriptions are handed out; the other messages are framed and counted (use
//! [`Messages`](crate::read::Messages) to see them).

use std::ops::ControlFlow;

use crate::error::ReadError;
use crate::pass::driver::{DataRecord, Hand, ScanSummary};
use crate::pass::order::time_ordered;
use crate::pass::source::{drive, drive_keeping, Source};

/// The order a pass hands records out in.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[non_exhaustive]
pub enum ScanOrder {
    /// As the messages stand in the file (one pass, nothing kept).
    #[default]
    File,
    /// By timestamp (microseconds, narrow version 0 timestamps unwrapped), ties and
    /// each topic's own rows in file order. This needs every topic's index: a source
    /// that is not a parsed [`ULog`](crate::ULog) is parsed first (a reader is read into memory).
    ///
    /// A record whose topic has no timestamp (its format has no `timestamp` field of
    /// a timestamp type, or could not be laid out) is never given one: it comes where
    /// it stands in the file, after the records whose timestamps are at or below the
    /// highest timestamp logged before it, and its
    /// [`TopicRecord::timestamp`](crate::TopicRecord::timestamp) is `None`.
    Timestamp,
}

/// How a pass reads, and what it hands out. Options that do not apply to a pass or a
/// source are ignored (each says where it applies).
///
/// ```
/// use ulog_core::read::ScanOrder;
/// let options = ulog_core::ScanOptions::default()
///     .order(ScanOrder::Timestamp)
///     .raw_others(true);
/// # let _ = options;
/// ```
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ScanOptions {
    pub(crate) read_ahead: bool,
    pub(crate) order: ScanOrder,
    pub(crate) raw_others: bool,
    pub(crate) threads: usize,
    pub(crate) keep_metadata: bool,
}

impl Default for ScanOptions {
    fn default() -> ScanOptions {
        ScanOptions {
            read_ahead: false,
            order: ScanOrder::File,
            raw_others: false,
            threads: 1,
            keep_metadata: false,
        }
    }
}

impl ScanOptions {
    /// Reads the next chunk of a reader or file on a second thread while one is
    /// framed (readers and files only; in file order). It takes the kernel's copy of
    /// the bytes off the framing thread, for about twice the buffer memory (a few
    /// MiB); BENCHMARKS.md has what it gains.
    pub fn read_ahead(mut self, on: bool) -> ScanOptions {
        self.read_ahead = on;
        self
    }

    /// The order records are handed out in (default: file order).
    pub fn order(mut self, order: ScanOrder) -> ScanOptions {
        self.order = order;
        self
    }

    /// [`scan_topics`](crate::scan_topics): also hand out, undecoded, the records of
    /// topics the enum does not name and of those whose format does not fit
    /// (default: leave them out, which is faster: they are framed, not handed out).
    pub fn raw_others(mut self, on: bool) -> ScanOptions {
        self.raw_others = on;
        self
    }

    /// [`scan`](crate::scan), [`scan_topics`](crate::scan_topics): also keep
    /// everything but the data messages, with what the data says of it (parameter
    /// changes' times, the last timestamp, the UTC time, the events), in
    /// [`ScanSummary::metadata`](crate::ScanSummary::metadata) (default: keep
    /// nothing). The memory is that of the metadata (the log's messages other than
    /// data, its GPS times and events), whatever the size of the log; see
    /// [`LogMetadata`](crate::read::LogMetadata). Every data message is then read for
    /// its timestamp, those of topics a pass leaves out too. In timestamp order the
    /// log is parsed anyway: its metadata is then taken from the parsed log.
    pub fn keep_metadata(mut self, on: bool) -> ScanOptions {
        self.keep_metadata = on;
        self
    }

    /// [`load_columns`](crate::load_columns): fill the columns on up to this many
    /// threads (at least 1, the default).
    pub fn threads(mut self, threads: usize) -> ScanOptions {
        self.threads = threads.max(1);
        self
    }
}

/// What a pass's callback returns: `()` to go on, or a [`ControlFlow`] whose `Break`
/// stops the pass (the summary then says
/// [`stopped`](ScanSummary::stopped)).
pub trait ScanFlow {
    /// Whether the pass goes on.
    fn go_on(self) -> bool;
}

impl ScanFlow for () {
    #[inline(always)]
    fn go_on(self) -> bool {
        true
    }
}

impl<B> ScanFlow for ControlFlow<B> {
    #[inline(always)]
    fn go_on(self) -> bool {
        self.is_continue()
    }
}

/// Hands every data message of a log to `f`, in file order or by timestamp
/// ([`ScanOptions::order`]), and returns what else the pass saw.
///
/// The source is the log's bytes (a buffer, a [`LogFile`](crate::LogFile)), a parsed
/// [`ULog`](crate::ULog), or a reader or file ([`Source::reader`], [`Source::file`]) read in
/// chunks of a few hundred KiB (so a log far larger than memory is read with a few
/// hundred KiB resident; [`ScanOptions::read_ahead`] reads the next chunk on a second
/// thread). `f` returns `()`, or a [`ControlFlow`] to stop early.
///
/// Errors are those of [`ULog::parse`](crate::ULog::parse): input that is not ULog, a log the spec says
/// to refuse, or a read that fails; damage is reported in the summary.
///
/// ```
/// # let bytes = ulog_core::testing::sample_log();
/// use ulog_core::{ScanOptions, Source};
///
/// let mut attitude_rows = 0;
/// let summary = ulog_core::scan(&bytes, &ScanOptions::default(), |record| {
///     if record.topic.name() == "vehicle_attitude" {
///         attitude_rows += 1;
///     }
/// })?;
/// let log = ulog_core::ULog::parse(&bytes)?;
/// assert_eq!(attitude_rows, log.topic("vehicle_attitude", 0)?.len());
/// assert_eq!(summary.messages, log.message_count());
///
/// // The same from any `Read`, the next chunk read on a second thread.
/// let ahead = ScanOptions::default().read_ahead(true);
/// let from_reader = ulog_core::scan(Source::reader(&bytes[..]), &ahead, |_| {})?;
/// assert_eq!(from_reader, summary);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn scan<'s, F, R>(
    source: impl Into<Source<'s>>,
    options: &ScanOptions,
    mut f: F,
) -> Result<ScanSummary, ReadError>
where
    F: FnMut(DataRecord<'_>) -> R,
    R: ScanFlow,
{
    // `f` called from each order's own closure (one closure shared by both kept it
    // out of line).
    match options.order {
        ScanOrder::File if options.keep_metadata => {
            // Through a trait object: `f` keeps one direct call site, the plain
            // file-order loop's.
            let f: &mut dyn FnMut(DataRecord<'_>) -> R = &mut f;
            drive_keeping(source.into(), options.read_ahead, &mut |r: DataRecord<
                '_,
            >| {
                Hand::go_on(f(r).go_on())
            })
        }
        ScanOrder::File => drive(source.into(), options.read_ahead, &mut |r: DataRecord<
            '_,
        >| {
            Hand::go_on(f(r).go_on())
        }),
        ScanOrder::Timestamp => time_ordered(source.into(), options.keep_metadata, &mut |r, _| {
            Hand::go_on(f(r).go_on())
        }),
    }
}
