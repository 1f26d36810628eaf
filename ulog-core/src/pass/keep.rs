//! [`ScanSummary`]: what a pass saw besides the data it handed out; and
//! [`LogMetadata`]: what a pass ([`ScanOptions::keep_metadata`]) keeps of a log
//! besides the data it hands out, so that one pass over a large file gives what
//! [`ULog::parse`] gives of it but the data messages, with memory for the metadata
//! only.
//!
//! [`ScanOptions::keep_metadata`]: crate::ScanOptions::keep_metadata

use std::sync::Arc;

use crate::bytes::{HEADER_SIZE, MAGIC};
use crate::definitions::timestamp::Unwrapper;
use crate::definitions::Subscription;
use crate::error::ReadError;
use crate::finding::Finding;
use crate::framing::{FlagBits, Framer, Header, Record};
use crate::log::span::{SpanTracker, TimeSpan};
use crate::log::ulog::{ULog, WholeFile};
use crate::log::utc::{GpsTime, UtcClock, UtcSamples};
use crate::pass::visit::{DataRecord, Hand, Visit};

/// What a pass saw besides the data messages it handed out.
#[derive(Debug, Clone, PartialEq)]
pub struct ScanSummary {
    /// The file header.
    pub header: Header,
    /// The flag bits message, when the log has one.
    pub flag_bits: Option<FlagBits>,
    /// Messages framed (of every type).
    pub messages: u64,
    /// Data messages of known subscriptions framed, handed out or not (a pass that
    /// leaves topics out still frames and counts their messages).
    pub data_messages: u64,
    /// Every subscription met, in the order of their first `A` messages.
    pub topics: Vec<Arc<Subscription>>,
    /// What the reader found and stepped over, in file order.
    pub findings: Vec<Finding>,
    /// Whether the callback stopped the pass before the end of the log: the summary
    /// then covers what was framed until then.
    pub stopped: bool,
    /// Everything but the data messages, with what the data says of it, when the
    /// pass was asked to keep it ([`ScanOptions::keep_metadata`](crate::ScanOptions::keep_metadata)).
    pub metadata: Option<LogMetadata>,
}

impl ScanSummary {
    /// The summary of a log already parsed.
    pub(crate) fn of(log: &ULog<'_>) -> ScanSummary {
        ScanSummary {
            header: log.header(),
            flag_bits: log.flag_bits().copied(),
            messages: log.message_count(),
            data_messages: (0..log.subscriptions().len())
                .map(|i| log.index(i).offsets.len() as u64)
                .sum(),
            topics: log.subscriptions().to_vec(),
            findings: log.findings().to_vec(),
            stopped: false,
            metadata: None,
        }
    }
}

/// Everything a log holds but its data messages, kept by a pass with
/// [`ScanOptions::keep_metadata`](crate::ScanOptions::keep_metadata) (in
/// [`ScanSummary::metadata`](crate::ScanSummary::metadata)): the header, flag bits,
/// formats, subscriptions, information, parameters and their changes, default
/// parameters, logged strings and dropouts, as a small log of their own that
/// [`LogMetadata::log`] parses; and what [`ULog`] takes from the data for them, taken
/// as the data went by: the time of each parameter change and dropout (the highest
/// data timestamp before it), the [`last timestamp`](ULog::last_timestamp), the GPS
/// times of [`ULog::utc`] and the rows of the `event` topic; and each topic
/// instance's row count and first and last timestamps ([`LogMetadata::topics`]).
/// With [`ScanOptions::keep_data`](crate::ScanOptions::keep_data), the data messages
/// of the topics it names are kept too, so that the kept log reads them as a parsed
/// log would.
///
/// ```
/// # let bytes = ulog_core::testing::sample_log();
/// use ulog_core::{ScanOptions, Source};
///
/// // One pass: the data as it goes by, the rest kept (here from a reader, read in
/// // chunks, as `Source::file` reads a file).
/// let keep = ScanOptions::default().keep_metadata(true);
/// let mut rows = 0;
/// let summary = ulog_core::scan(Source::reader(&bytes[..]), &keep, |_| rows += 1)?;
/// let metadata = summary.metadata.expect("kept when asked");
/// let kept = metadata.log()?;
///
/// let whole = ulog_core::ULog::parse(&bytes)?;
/// assert_eq!(kept.info(), whole.info());
/// assert_eq!(kept.initial_params(), whole.initial_params());
/// assert_eq!(kept.last_timestamp(), whole.last_timestamp());
/// assert_eq!(metadata.utc(), whole.utc());
/// assert_eq!(rows, summary.data_messages);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LogMetadata {
    /// The kept log: the file header, then each message but data messages as it was,
    /// in file order (the flag bits' appended offsets zeroed, the data being gone).
    bytes: Vec<u8>,
    /// For each parameter change and dropout: its offset in `bytes` and the highest
    /// data timestamp before it (not below the header's).
    times: Vec<(u64, u64)>,
    /// For each message kept but data messages: its offset in `bytes` and in the file.
    places: Vec<(u64, u64)>,
    last_timestamp: u64,
    span: TimeSpan,
    /// Per subscription, its rows and their times.
    topics: Vec<TopicRows>,
    /// What framing saw of the whole file.
    flag_bits: Option<FlagBits>,
    subscriptions: Vec<Arc<Subscription>>,
    findings: Vec<Finding>,
    messages: u64,
    utc: UtcSamples,
    /// The rows of the `event` topic (instance 0): timestamp and payload.
    #[cfg(feature = "events")]
    events: Vec<(u64, Vec<u8>)>,
}

impl LogMetadata {
    /// The log without its data messages, as [`ULog::parse`] reads it, but as the
    /// whole file has it: parameter changes and dropouts have their times in the whole
    /// log, messages their offsets in the file, and the [last
    /// timestamp](ULog::last_timestamp), [flag bits](ULog::flag_bits),
    /// [subscriptions](ULog::subscriptions), [findings](ULog::findings),
    /// [appended sections](ULog::appended_sections) and [message
    /// count](ULog::message_count) are the whole file's. Its topics have no rows (their
    /// counts are in [`LogMetadata::topics`]), but those of
    /// [`ScanOptions::keep_data`](crate::ScanOptions::keep_data), whose data messages
    /// are read from the kept bytes ([`Topic::message_offsets`](crate::Topic::message_offsets)
    /// are offsets in those). [`ULog::utc`] of it sees only those rows:
    /// [`LogMetadata::utc`] is the whole log's.
    ///
    /// Errors: none for metadata a pass kept (the pass refused what parsing would);
    /// a `Result` all the same, as parsing's.
    pub fn log(&self) -> Result<ULog<'_>, ReadError> {
        let mut log = ULog::parse(&self.bytes)?;
        log.restore(&WholeFile {
            times: &self.times,
            places: &self.places,
            last_timestamp: self.last_timestamp,
            flag_bits: self.flag_bits,
            subscriptions: &self.subscriptions,
            findings: &self.findings,
            message_count: self.messages,
            span: &self.span,
        });
        Ok(log)
    }

    /// The kept log's bytes: a valid ULog file of the header and every message but
    /// the data messages (those of [`ScanOptions::keep_data`](crate::ScanOptions::keep_data)'s
    /// topics kept), which [`LogMetadata::log`] parses.
    pub fn bytes(&self) -> &[u8] {
        &self.bytes
    }

    /// Per subscription (by [`Subscription::index`]), its data messages and their
    /// first and last timestamps, counted as the pass went by: what [`Topic::len`]
    /// gives of a parsed log. A topic whose times the pass did not follow
    /// ([`ScanOptions::topics`](crate::ScanOptions::topics)) has its rows counted and
    /// no timestamps.
    ///
    /// [`Topic::len`]: crate::Topic::len
    pub fn topics(&self) -> &[TopicRows] {
        &self.topics
    }

    /// [`ULog::span`] of the whole log, found as the data went by.
    pub fn span(&self) -> &TimeSpan {
        &self.span
    }

    /// The largest data timestamp of the log (the header's when none is larger):
    /// [`ULog::last_timestamp`] of the whole log.
    pub fn last_timestamp(&self) -> u64 {
        self.last_timestamp
    }

    /// [`ULog::utc`] of the whole log: from the GPS times kept as the data went by,
    /// else from information key `boot_time_utc_us`.
    pub fn utc(&self) -> Option<UtcClock> {
        self.utc
            .clock(|| self.log().ok().and_then(|log| log.boot_clock()))
    }

    /// [`ULog::events`] of the whole log: the rows of its `event` topic (instance 0),
    /// kept as they went by, decoded.
    #[cfg(feature = "events")]
    pub fn events(&self, options: &crate::events::EventOptions) -> crate::events::Events {
        let Ok(log) = self.log() else {
            return crate::events::Events::default();
        };
        let Ok(topic) = log.topic("event", 0) else {
            return crate::events::Events::default();
        };
        let rows = self.events.iter().map(|(t, p)| (*t, &p[..]));
        log.decode_events(&topic, options, rows)
    }
}

/// The data messages of one topic instance (subscription), counted by a pass that
/// keeps the metadata ([`LogMetadata::topics`]).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
#[non_exhaustive]
pub struct TopicRows {
    /// Its data messages.
    pub rows: u64,
    /// The timestamp of its first data message (in file order), when it has one (a
    /// topic whose format has no timestamp has none; narrow version 0 timestamps are
    /// unwrapped).
    pub first_timestamp: Option<u64>,
    /// The timestamp of its last data message, in file order.
    pub last_timestamp: Option<u64>,
}

/// What the keeping pass follows of one subscription.
struct Sub {
    clock: Unwrapper,
    rows: TopicRows,
    /// Whether its times count among the log's ([`ScanOptions::topics`]).
    ///
    /// [`ScanOptions::topics`]: crate::ScanOptions::topics
    follow: bool,
    /// Whether its timestamps are read at all: followed, or needed for the UTC
    /// clock, the events or the kept data.
    timed: bool,
    /// Whether its data messages are kept too.
    keep: bool,
    gps: Option<GpsTime>,
    #[cfg(feature = "events")]
    event: bool,
}

/// A visitor that keeps a log's metadata ([`LogMetadata`]) as the pass goes, and
/// hands every data record on to `inner`.
pub(crate) struct Keeper<'v, V: ?Sized> {
    inner: &'v mut V,
    /// The topics whose data messages are kept.
    keep: &'v [String],
    /// The topics whose times are followed; `None`: all.
    only: Option<&'v [String]>,
    bytes: Vec<u8>,
    times: Vec<(u64, u64)>,
    places: Vec<(u64, u64)>,
    /// The highest data timestamp so far: the time of a parameter change or dropout
    /// met now, by [`ULog::parse`]'s rule.
    clock: u64,
    subs: Vec<Sub>,
    /// Subscriptions whose records `inner` wants no more: still read here (their
    /// timestamps count), not handed on.
    skip: Vec<bool>,
    /// The span, as [`ULog::parse`] finds it (made when the header is known).
    span: Option<SpanTracker>,
    utc: UtcSamples,
    #[cfg(feature = "events")]
    events: Vec<(u64, Vec<u8>)>,
}

impl<'v, V: Visit + ?Sized> Keeper<'v, V> {
    pub fn new(inner: &'v mut V, keep: &'v [String], only: Option<&'v [String]>) -> Keeper<'v, V> {
        Keeper {
            inner,
            keep,
            only,
            // The header, filled in at the end.
            bytes: vec![0; HEADER_SIZE],
            times: Vec::new(),
            places: Vec::new(),
            clock: 0,
            subs: Vec::new(),
            skip: Vec::new(),
            span: None,
            utc: UtcSamples::default(),
            #[cfg(feature = "events")]
            events: Vec::new(),
        }
    }

    /// The metadata of the log whose pass saw `summary`.
    pub fn finish(self, summary: &ScanSummary) -> LogMetadata {
        let header = summary.header;
        let mut bytes = self.bytes;
        bytes[..MAGIC.len()].copy_from_slice(&MAGIC);
        bytes[MAGIC.len()] = header.version;
        bytes[MAGIC.len() + 1..HEADER_SIZE].copy_from_slice(&header.timestamp.to_le_bytes());
        let start = header.timestamp;
        let mut topics: Vec<TopicRows> = self.subs.iter().map(|s| s.rows).collect();
        topics.resize(summary.topics.len(), TopicRows::default());
        LogMetadata {
            bytes,
            times: self
                .times
                .into_iter()
                .map(|(at, t)| (at, t.max(start)))
                .collect(),
            places: self.places,
            last_timestamp: self.clock.max(start),
            span: self
                .span
                .filter(|s| s.header() == start)
                .unwrap_or_else(|| SpanTracker::new(start))
                .finish(),
            topics,
            flag_bits: summary.flag_bits,
            subscriptions: summary.topics.clone(),
            findings: summary.findings.clone(),
            messages: summary.messages,
            utc: self.utc,
            #[cfg(feature = "events")]
            events: self.events,
        }
    }

    /// Follows the subscriptions framing has made since the last call, in their
    /// order: the first of a GPS topic's or of `event` at instance 0 is the one
    /// [`ULog::topic`] finds.
    #[cold]
    fn subscribed(&mut self, framer: &Framer) {
        for sub in &framer.defs.subscriptions()[self.subs.len()..] {
            let first = sub.multi_id() == 0
                && !framer.defs.subscriptions()[..sub.index()]
                    .iter()
                    .any(|s| s.multi_id() == 0 && s.name() == sub.name());
            let follow = match self.only {
                Some(only) => only.iter().any(|n| n == sub.name()),
                None => true,
            };
            let keep = self.keep.iter().any(|k| k == sub.name());
            let gps = if first { self.utc.gps_time(sub) } else { None };
            #[cfg(feature = "events")]
            let event = first && sub.name() == "event";
            #[cfg(not(feature = "events"))]
            let event = false;
            self.subs.push(Sub {
                clock: Unwrapper::new(sub.timestamp_field()),
                rows: TopicRows::default(),
                follow,
                timed: follow || keep || gps.is_some() || event,
                keep,
                gps,
                #[cfg(feature = "events")]
                event,
            });
            // A topic left out is not handed on (`scan` would skip it at its first
            // record; here it costs no call at all).
            if !follow {
                if self.skip.len() <= sub.index() {
                    self.skip.resize(sub.index() + 1, false);
                }
                self.skip[sub.index()] = true;
            }
        }
    }

    /// Keeps the message `r` (not a data message), its payload `payload`.
    #[cold]
    fn keep(&mut self, r: &Record, payload: &[u8]) {
        // Flag bits anywhere but first are only a finding of the whole file's: were
        // the messages before them not kept, they would be read as the kept log's
        // own (framing accepts no data message before the definitions, so this does
        // not happen today; the check keeps it so).
        if r.msg_type == b'B' && r.offset != HEADER_SIZE as u64 {
            return;
        }
        if matches!(r.msg_type, b'P' | b'O') {
            self.times.push((self.bytes.len() as u64, self.clock));
        }
        self.places.push((self.bytes.len() as u64, r.offset));
        let start = self.bytes.len();
        self.bytes
            .extend_from_slice(&(payload.len() as u16).to_le_bytes());
        self.bytes.push(r.msg_type);
        self.bytes.extend_from_slice(payload);
        // The appended offsets (after the two 8-byte flag fields) point into the
        // whole file: the kept log has no appended data.
        if r.msg_type == b'B' && payload.len() >= 40 {
            self.bytes[start + 3 + 16..start + 3 + 40].fill(0);
        }
    }
}

/// Appends data message `record` to the kept bytes.
#[cold]
fn keep_data(bytes: &mut Vec<u8>, record: &DataRecord<'_>) {
    // Framing handed it out: its payload and msg_id fit its u16 size.
    let size = (record.payload.len() + 2) as u16;
    bytes.extend_from_slice(&size.to_le_bytes());
    bytes.push(b'D');
    bytes.extend_from_slice(&record.msg_id.to_le_bytes());
    bytes.extend_from_slice(record.payload);
}

impl<V: Visit + ?Sized> Visit for Keeper<'_, V> {
    #[inline(always)]
    fn data(&mut self, record: DataRecord<'_>) -> Hand {
        let i = record.sub as usize;
        // Framing makes a subscription at its `A` message, which `other` saw.
        if let Some(sub) = self.subs.get_mut(i) {
            sub.rows.rows += 1;
            let time = match sub.timed {
                true => sub.clock.push(record.payload),
                false => None,
            };
            if let Some(t) = time {
                if sub.follow {
                    self.clock = self.clock.max(t);
                    if let Some(span) = &mut self.span {
                        span.push(i, t, record.offset);
                    }
                    if sub.rows.first_timestamp.is_none() {
                        sub.rows.first_timestamp = time;
                    }
                    sub.rows.last_timestamp = time;
                }
                if let Some(at) = sub.gps {
                    self.utc.push(at, record.payload, t);
                }
            }
            if sub.keep {
                keep_data(&mut self.bytes, &record);
            }
            // PX4 events: a few hundred small rows (time 0 where the topic has no
            // timestamp, as `ULog::events` gives it).
            #[cfg(feature = "events")]
            if sub.event {
                let t = time.unwrap_or(0);
                self.events.push((t, record.payload.to_vec()));
            }
        }
        if self.skip.get(i) == Some(&true) {
            return Hand::Next;
        }
        match self.inner.data(record) {
            Hand::SkipTopic => {
                if self.skip.len() <= i {
                    self.skip.resize(i + 1, false);
                }
                self.skip[i] = true;
                Hand::Next
            }
            hand => hand,
        }
    }

    #[inline(always)]
    fn other(&mut self, record: &Record, payload: &[u8], framer: &Framer) -> bool {
        self.keep(record, payload);
        if self.span.is_none() {
            self.span = framer.header.map(|h| SpanTracker::new(h.timestamp));
        }
        if self.subs.len() < framer.defs.subscriptions().len() {
            self.subscribed(framer);
        }
        self.inner.other(record, payload, framer)
    }

    fn end(&mut self, framer: &Framer) {
        self.inner.end(framer);
    }
}

#[cfg(test)]
mod tests {
    use crate::pass::scan::{scan, ScanOptions};
    use crate::testing::LogBuilder;
    use crate::ULog;

    /// Parameter changes and dropouts take the highest data timestamp before them
    /// (not the last one: rows may go back in time), and never one below the
    /// header's, as in the whole-file parse; a narrow (v0) timestamp that wraps is
    /// unwrapped.
    #[test]
    fn times_are_the_whole_parses() {
        let mut b = LogBuilder::new(1, 7_000);
        b.info_str("sys_name", "PX4");
        b.param("int32_t A", &1i32.to_le_bytes());
        b.format("t:uint64_t timestamp;uint8_t x;");
        b.format("n:uint16_t timestamp;uint8_t x;");
        b.subscribe(0, 0, "t").subscribe(0, 1, "n");
        b.param("int32_t A", &2i32.to_le_bytes());
        let wide = |t: u64| [&t.to_le_bytes()[..], &[1]].concat();
        let narrow = |t: u16| [&t.to_le_bytes()[..], &[1]].concat();
        b.data(0, &wide(5_000));
        b.dropout(30);
        b.data(0, &wide(9_000)).data(0, &wide(8_000));
        b.param("int32_t A", &3i32.to_le_bytes());
        b.data(1, &narrow(65_000)).data(1, &narrow(10));
        b.dropout(40).log(b'3', 9_500, "late");
        b.param("int32_t A", &4i32.to_le_bytes());
        let bytes = b.into_bytes();
        let whole = ULog::parse(&bytes).unwrap();
        let keep = ScanOptions::default().keep_metadata(true);
        let summary = scan(&bytes, &keep, |_| {}).unwrap();
        let kept = summary.metadata.unwrap();
        let log = kept.log().unwrap();
        let changes = |l: &ULog<'_>| -> Vec<(u64, String)> {
            l.param_changes()
                .iter()
                .map(|c| (c.timestamp, format!("{:?}", c.kv.value())))
                .collect()
        };
        assert_eq!(changes(&log), changes(&whole));
        assert_eq!(
            changes(&log).iter().map(|c| c.0).collect::<Vec<_>>(),
            [7_000, 9_000, 65_546]
        );
        let dropouts = |l: &ULog<'_>| -> Vec<(u64, u16)> {
            l.dropouts()
                .iter()
                .map(|d| (d.timestamp, d.duration_ms))
                .collect()
        };
        assert_eq!(dropouts(&log), [(7_000, 30), (65_546, 40)]);
        assert_eq!(dropouts(&log), dropouts(&whole));
        assert_eq!(log.logged_messages().len(), 1);
        assert_eq!(kept.last_timestamp(), whole.last_timestamp());
        assert_eq!(log.last_timestamp(), 65_546);
    }

    /// With `ScanOptions::topics`, the kept metadata is that of the log as the
    /// topics named see it: the same as the whole-file parse of the log written
    /// without the other topics' rows (pyulog's `message_name_filter_list`), but
    /// for the UTC clock, which is the whole log's, and the row counts, which are
    /// every topic's.
    #[test]
    fn topics_named_keep_their_own_times() {
        let boot = 1_707_236_822_000_000u64;
        let write = |others: bool| {
            let mut b = LogBuilder::new(1, 1_000);
            b.param("int32_t A", &1i32.to_le_bytes());
            b.format("t:uint64_t timestamp;uint8_t x;");
            b.format("u:uint64_t timestamp;uint8_t x;");
            b.format("vehicle_gps_position:uint64_t timestamp;uint64_t time_utc_usec;uint8_t fix_type;uint8_t[7] _padding0;");
            b.subscribe(0, 0, "t").subscribe(0, 1, "u");
            b.subscribe(0, 2, "vehicle_gps_position");
            let row = |t: u64| [&t.to_le_bytes()[..], &[1]].concat();
            let gps = |t: u64| {
                let mut p = t.to_le_bytes().to_vec();
                p.extend_from_slice(&(boot + t).to_le_bytes());
                p.extend_from_slice(&[3, 0, 0, 0, 0, 0, 0, 0]);
                p
            };
            for k in 0..6u64 {
                b.data(0, &row(2_000 + k * 1_000));
                if others {
                    // Ahead of `t`, and far ahead once.
                    b.data(1, &row(if k == 3 { 90_000 } else { 2_500 + k * 1_000 }));
                    b.data(2, &gps(2_600 + k * 1_000));
                }
                if k % 2 == 1 {
                    b.param("int32_t A", &(k as i32).to_le_bytes());
                    b.dropout(10 + k as u16);
                }
            }
            b.into_bytes()
        };
        let (bytes, alone) = (write(true), write(false));
        let only = ScanOptions::default().keep_metadata(true).topics(["t"]);
        let mut handed = std::collections::BTreeSet::new();
        let summary = scan(&bytes, &only, |r| {
            handed.insert(r.topic.name().to_owned());
        })
        .unwrap();
        assert_eq!(handed.into_iter().collect::<Vec<_>>(), ["t"]);
        let kept = summary.metadata.unwrap();
        let log = kept.log().unwrap();
        let expected = ULog::parse(&alone).unwrap();
        let times = |l: &ULog<'_>| -> Vec<u64> {
            let changes = l.param_changes().iter().map(|c| c.timestamp);
            changes
                .chain(l.dropouts().iter().map(|d| d.timestamp))
                .collect()
        };
        assert_eq!(times(&log), times(&expected));
        assert_eq!(times(&log), [3_000, 5_000, 7_000, 3_000, 5_000, 7_000]);
        assert_ne!(times(&log), times(&ULog::parse(&bytes).unwrap()));
        assert_eq!(kept.last_timestamp(), expected.last_timestamp());
        assert_eq!(kept.last_timestamp(), 7_000);
        assert_eq!(kept.span(), expected.span());
        // Every topic's rows counted; times only for the one followed.
        let rows: Vec<_> = kept
            .topics()
            .iter()
            .map(|t| (t.rows, t.last_timestamp))
            .collect();
        assert_eq!(rows, [(6, Some(7_000)), (6, None), (6, None)]);
        // The whole log's UTC clock, from the GPS rows the filter leaves out.
        let whole = ULog::parse(&bytes).unwrap().utc().unwrap();
        assert_eq!(kept.utc().unwrap().boot_us(), whole.boot_us());
    }
}
