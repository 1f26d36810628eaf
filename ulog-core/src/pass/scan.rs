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
use crate::pass::keep::ScanSummary;
use crate::pass::order::time_ordered;
use crate::pass::source::{drive, drive_keeping, Source};
use crate::pass::visit::{DataRecord, Hand};

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
    pub(crate) keep_data: Vec<String>,
    pub(crate) topics: Option<Vec<String>>,
    pub(crate) window: Option<core::ops::Range<u64>>,
}

impl Default for ScanOptions {
    fn default() -> ScanOptions {
        ScanOptions {
            read_ahead: false,
            order: ScanOrder::File,
            raw_others: false,
            threads: 1,
            keep_metadata: false,
            keep_data: Vec::new(),
            topics: None,
            window: None,
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
    /// its timestamp, but with [`ScanOptions::topics`] (in [`scan`](crate::scan)) only
    /// those of the topics named (and of the GPS and event topics, for the UTC clock
    /// and the events). In timestamp order the log is parsed anyway: its metadata is
    /// then taken from the parsed log.
    pub fn keep_metadata(mut self, on: bool) -> ScanOptions {
        self.keep_metadata = on;
        self
    }

    /// With [`ScanOptions::keep_metadata`]: also keep the data messages of the topics
    /// named (every instance), so that the kept log
    /// ([`LogMetadata::log`](crate::read::LogMetadata::log)) reads them as a parsed
    /// log would, in the memory of those topics' rows alone: a command that needs one
    /// topic and the metadata reads a large file once, in chunks (default: none).
    ///
    /// ```
    /// # let bytes = ulog_core::testing::sample_log();
    /// use ulog_core::{ScanOptions, Source};
    ///
    /// let keep = ScanOptions::default().keep_metadata(true).keep_data(["esc_status"]);
    /// let summary = ulog_core::scan(Source::reader(&bytes[..]), &keep, |_| {})?;
    /// let metadata = summary.metadata.expect("kept when asked");
    /// let kept = metadata.log()?;
    /// let whole = ulog_core::ULog::parse(&bytes)?;
    /// let rows = |log: &ulog_core::ULog<'_>| -> Vec<Vec<u8>> {
    ///     let topic = log.topic("esc_status", 0).unwrap();
    ///     topic.payloads().map(<[u8]>::to_vec).collect()
    /// };
    /// assert_eq!(rows(&kept), rows(&whole));
    /// assert!(kept.topic("vehicle_attitude", 0)?.is_empty());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn keep_data<S: Into<String>>(
        mut self,
        topics: impl IntoIterator<Item = S>,
    ) -> ScanOptions {
        self.keep_data = topics.into_iter().map(Into::into).collect();
        self
    }

    /// [`scan`]: hand out only the records of the topics named (every instance;
    /// default: every topic). The others are still framed and their rows counted,
    /// but neither handed out nor, by a [keeping](ScanOptions::keep_metadata) pass,
    /// read for their times: the kept metadata is that of the log as the topics
    /// named see it, as pyulog's `message_name_filter_list` has it. Its [last
    /// timestamp](crate::read::LogMetadata::last_timestamp), the times of parameter
    /// changes and dropouts (the highest timestamp of those topics before them) and
    /// its [span](crate::read::LogMetadata::span) are theirs; its UTC clock and events
    /// are the whole log's. A topic of a 302 MB log and the metadata are read in
    /// about half the time of a pass that follows every topic (bench/README.md).
    ///
    /// ```
    /// # let bytes = ulog_core::testing::sample_log();
    /// let only = ulog_core::ScanOptions::default().topics(["esc_status"]);
    /// let mut names = std::collections::BTreeSet::new();
    /// let summary = ulog_core::scan(&bytes, &only, |r| {
    ///     names.insert(r.topic.name().to_owned());
    /// })?;
    /// assert_eq!(names.into_iter().collect::<Vec<_>>(), ["esc_status"]);
    /// assert!(summary.data_messages > summary.topics.len() as u64);
    /// # Ok::<(), ulog_core::ReadError>(())
    /// ```
    pub fn topics<S: Into<String>>(mut self, topics: impl IntoIterator<Item = S>) -> ScanOptions {
        self.topics = Some(topics.into_iter().map(Into::into).collect());
        self
    }

    /// [`scan_topics`](crate::scan_topics): only the records whose timestamp is in
    /// `[start, end)`, boot microseconds (either open; default: every record). A
    /// record without a timestamp (its topic's format has none) has no time and is in
    /// no window. In [`ScanOrder::Timestamp`] each topic starts at its first row at or
    /// after `start`, found by binary search over its rows in file order (the order
    /// the merge takes them in), and the pass ends at the first record at or after
    /// `end`: O(log n) per topic to start, nothing read after the end. In file order
    /// the pass still frames every message (a stream has no index to seek by) and
    /// leaves out, undecoded, the records outside. For seconds since the start of the
    /// log, [`TimeSpan::at`](crate::read::TimeSpan::at) gives the boot time.
    ///
    /// ```
    /// # #[cfg(feature = "derive")] {
    /// use ulog_core::read::ScanOrder;
    /// use ulog_core::{ScanOptions, ULogMessage, ULogTopics};
    ///
    /// #[derive(ULogMessage)]
    /// #[ulog(crate = "ulog_core")]
    /// struct VehicleAttitude { timestamp: u64 }
    /// #[derive(ULogTopics)]
    /// #[ulog(crate = "ulog_core")]
    /// enum Topics { Attitude(VehicleAttitude) }
    ///
    /// let bytes = ulog_core::testing::sample_log();
    /// let log = ulog_core::ULog::parse(&bytes).unwrap();
    /// // Seconds 2 to 3 of the log.
    /// let (start, end) = (log.span().at(2.0), log.span().at(3.0));
    /// let window = ScanOptions::default()
    ///     .order(ScanOrder::Timestamp)
    ///     .window_us(Some(start), Some(end));
    /// let mut times = Vec::new();
    /// ulog_core::scan_topics::<Topics>(&log, &window, |r| times.push(r.unwrap().timestamp.unwrap()))
    ///     .unwrap();
    /// assert_eq!(times.len(), 20); // 20 rows a second
    /// assert!(times.iter().all(|t| (start..end).contains(t)));
    /// # }
    /// ```
    pub fn window_us(mut self, start: Option<u64>, end: Option<u64>) -> ScanOptions {
        self.window = Some(start.unwrap_or(0)..end.unwrap_or(u64::MAX));
        self
    }

    /// The topics whose data a keeping pass keeps, and those whose times it follows
    /// (`None`: all); `None` when it keeps nothing.
    pub(crate) fn kept(&self) -> Option<(&[String], Option<&[String]>)> {
        self.keep_metadata
            .then_some((&self.keep_data[..], self.topics.as_deref()))
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
    // A topic left out is answered without a call to `f`, once: the pass skips it
    // from then on. (A keeping pass leaves it out itself, before its first record.)
    let wanted = |r: &DataRecord<'_>| match &options.topics {
        Some(names) => names.iter().any(|n| n == r.topic.name()),
        None => true,
    };
    // `f` called from each order's own closure (one closure shared by both kept it
    // out of line).
    match options.order {
        ScanOrder::File if options.keep_metadata => {
            // Through a trait object: `f` keeps one direct call site, the plain
            // file-order loop's.
            let f: &mut dyn FnMut(DataRecord<'_>) -> R = &mut f;
            drive_keeping(
                source.into(),
                options.read_ahead,
                &options.keep_data,
                options.topics.as_deref(),
                &mut |r: DataRecord<'_>| match wanted(&r) {
                    true => Hand::go_on(f(r).go_on()),
                    false => Hand::SkipTopic,
                },
            )
        }
        ScanOrder::File => drive(source.into(), options.read_ahead, &mut |r: DataRecord<
            '_,
        >| match wanted(&r)
        {
            true => Hand::go_on(f(r).go_on()),
            false => Hand::SkipTopic,
        }),
        ScanOrder::Timestamp => {
            time_ordered(
                source.into(),
                options.kept(),
                None,
                &mut |r, _| match wanted(&r) {
                    true => Hand::go_on(f(r).go_on()),
                    false => Hand::SkipTopic,
                },
            )
        }
    }
}
