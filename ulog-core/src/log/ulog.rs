//! [`ULog`]: a whole log parsed in one pass over borrowed bytes, with an index of
//! every topic's data messages.

use std::collections::HashMap;
use std::sync::Arc;

use ulog_format::Format;

use crate::definitions::timestamp::Unwrapper;
use crate::definitions::Subscription;
use crate::error::ReadError;
use crate::finding::{Finding, FindingKind};
use crate::framing::{FlagBits, Framer, Header, Record, Step};
use crate::log::message::{KeyValue, LoggedString, Message};
use crate::log::messages::Messages;
use crate::log::metadata::{
    DefaultParam, Dropout, MultiInfo, ParamChange, ReleaseVersion, UnknownMessage,
};
use crate::log::offsets::OffsetIndex;
use crate::log::span::{SpanTracker, TimeSpan};
use crate::value::Value;

/// A ULog file parsed in one pass: header, flag bits, definitions, every subscription
/// with the offsets of its data messages, and everything else the file holds.
/// Payloads are borrowed from the input (no copy of the data section).
///
/// ```
/// # let bytes = ulog_core::testing::sample_log();
/// let log = ulog_core::ULog::parse(&bytes)?;
/// let topic = log.topic("vehicle_attitude", 0)?;
/// let q0 = topic.field("q[0]")?;
/// for payload in topic.payloads() {
///     let value = q0.read(payload).and_then(|v| v.as_f64());
///     assert!(value.is_some());
/// }
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug)]
pub struct ULog<'a> {
    data: &'a [u8],
    header: Header,
    flag_bits: Option<FlagBits>,
    formats: HashMap<String, Format>,
    subscriptions: Vec<Arc<Subscription>>,
    /// Per subscription, its data messages.
    index: Vec<TopicIndex>,
    info: Vec<KeyValue<'a>>,
    multi_info: Vec<MultiInfo<'a>>,
    initial_params: Vec<KeyValue<'a>>,
    param_changes: Vec<ParamChange<'a>>,
    default_params: Vec<DefaultParam<'a>>,
    logged: Vec<LoggedString<'a>>,
    dropouts: Vec<Dropout>,
    sync_count: usize,
    unknown: Vec<UnknownMessage<'a>>,
    findings: Vec<Finding>,
    appended: Vec<u64>,
    last_timestamp: u64,
    span: TimeSpan,
    message_count: u64,
}

/// The data messages of one subscription.
#[derive(Debug, Clone, Default)]
pub(crate) struct TopicIndex {
    /// Offsets of the `D` messages (their 3-byte headers), in file order.
    pub offsets: OffsetIndex,
    /// For a topic without a timestamp field: per data message, the highest data
    /// timestamp of the log before it (where it stands in the log's time). Empty
    /// for topics with a timestamp.
    pub log_time: Vec<u64>,
    /// The timestamp of the last row.
    last_timestamp: u64,
    /// Whether a row's timestamp is below the one before it in file order, or a row is
    /// too short for its topic's timestamp (never for a topic without timestamps):
    /// otherwise the merge by time seeks in the topic by binary search and leaves it
    /// at the end of a window.
    pub goes_back: bool,
}

struct Builder<'a> {
    log: ULog<'a>,
    /// Per subscription, what each data message updates: its index and its
    /// timestamp unwrapper.
    hot: Vec<(TopicIndex, Unwrapper)>,
    multi_by_name: HashMap<String, usize>,
    span: SpanTracker,
}

impl<'a> ULog<'a> {
    /// Parses a whole log from bytes (a buffer or a [`LogFile`](crate::LogFile)).
    ///
    /// Damage does not fail the parse: it is reported in [`ULog::findings`] and the data
    /// around it is kept. Errors are for input that is not a ULog file at all, or a log
    /// the spec says to refuse (unknown incompatibility flags).
    pub fn parse(data: &'a [u8]) -> Result<ULog<'a>, ReadError> {
        let mut framer = Framer::new();
        let mut b = Builder {
            log: ULog {
                data,
                header: Header {
                    version: 0,
                    timestamp: 0,
                },
                flag_bits: None,
                formats: HashMap::new(),
                subscriptions: Vec::new(),
                index: Vec::new(),
                info: Vec::new(),
                multi_info: Vec::new(),
                initial_params: Vec::new(),
                param_changes: Vec::new(),
                default_params: Vec::new(),
                logged: Vec::new(),
                dropouts: Vec::new(),
                sync_count: 0,
                unknown: Vec::new(),
                findings: Vec::new(),
                appended: Vec::new(),
                last_timestamp: 0,
                span: TimeSpan::default(),
                message_count: 0,
            },
            hot: Vec::new(),
            multi_by_name: HashMap::new(),
            span: SpanTracker::new(0),
        };
        let mut started = false;
        loop {
            framer.plain_data_run(data, 0, |offset, sub, _, payload| {
                b.data(offset, sub as usize, payload);
                true
            });
            let step = framer.step(data, 0, true)?;
            if !started {
                if let Some(h) = framer.header {
                    b.log.header = h;
                    b.log.last_timestamp = h.timestamp;
                    b.span = SpanTracker::new(h.timestamp);
                    started = true;
                }
            }
            match step {
                Step::Record(r) => b.record(&r, &mut framer),
                // The whole file is given: framing never asks for more.
                Step::End | Step::NeedMore => break,
            }
        }
        let mut log = b.log;
        log.span = b.span.finish();
        log.index = b.hot.into_iter().map(|(index, _)| index).collect();
        log.subscriptions = framer.defs.take_subscriptions();
        // Subscriptions without data messages after the last record still get their
        // (empty) index.
        log.index
            .resize_with(log.subscriptions.len(), TopicIndex::default);
        log.formats = framer.defs.take_formats();
        log.flag_bits = framer.flag_bits;
        log.findings = std::mem::take(&mut framer.findings);
        log.appended = appended_of(&log.findings);
        Ok(log)
    }
}

/// Makes room in a full offset vector for the rows the rest of the file (`len`
/// bytes) will likely add, judged by the rate so far at `offset`.
#[cold]
fn reserve_for_rest(records: &mut OffsetIndex, offset: u64, len: usize) {
    let rows = records.len();
    let estimate = crate::estimate::rows_at_end(rows, offset, len as u64);
    // At least double, as `push` would.
    let target = estimate.max(rows * 2).max(16);
    records.reserve_exact(target - rows);
}

impl<'a> Builder<'a> {
    /// A data message of subscription `sub` (whose entry [`Builder::record`] has
    /// made); `payload` starts with the msg_id.
    #[inline(always)]
    fn data(&mut self, offset: u64, sub: usize, payload: &[u8]) {
        self.log.message_count += 1;
        let (index, unwrap) = &mut self.hot[sub];
        if index.offsets.is_full() {
            reserve_for_rest(&mut index.offsets, offset, self.log.data.len());
        }
        index.offsets.push(offset);
        match unwrap.push(&payload[2..]) {
            Some(ts) => {
                self.log.last_timestamp = self.log.last_timestamp.max(ts);
                self.span.push(sub, ts, offset);
                index.goes_back |= ts < index.last_timestamp;
                index.last_timestamp = ts;
            }
            None => {
                index.goes_back |= unwrap.field().is_some();
                index.log_time.push(self.log.last_timestamp);
            }
        }
    }

    fn record(&mut self, r: &Record, framer: &mut Framer) {
        let payload = r.payload(self.log.data, 0);
        // Subscriptions are made by framing: each gets its index as it appears.
        for sub in &framer.defs.subscriptions()[self.hot.len()..] {
            let unwrap = Unwrapper::new(sub.timestamp_field());
            self.hot.push((TopicIndex::default(), unwrap));
        }
        if r.msg_type == b'D' {
            match r.sub {
                Some(i) => self.data(r.offset, i as usize, payload),
                None => self.log.message_count += 1,
            }
            return;
        }
        self.log.message_count += 1;
        let in_definitions = framer.in_definitions;
        match Message::from_record(r, payload, None) {
            Message::Info(kv) => self.log.info.push(kv),
            Message::MultiInfo { continued, kv } => {
                let name = kv.name().into_owned();
                match self.multi_by_name.get(&name) {
                    Some(&i) => {
                        let entries = &mut self.log.multi_info[i].entries;
                        match entries.last_mut() {
                            Some(last) if continued => last.push(kv),
                            _ => entries.push(vec![kv]),
                        }
                    }
                    None => {
                        self.multi_by_name
                            .insert(name.clone(), self.log.multi_info.len());
                        self.log.multi_info.push(MultiInfo {
                            name,
                            entries: vec![vec![kv]],
                        });
                    }
                }
            }
            Message::Param(kv) if in_definitions => self.log.initial_params.push(kv),
            Message::Param(kv) => self.log.param_changes.push(ParamChange {
                timestamp: self.log.last_timestamp,
                offset: r.offset,
                kv,
            }),
            Message::DefaultParam { default_types, kv } => {
                self.log.default_params.push(DefaultParam {
                    default_types,
                    offset: r.offset,
                    kv,
                })
            }
            Message::Log(l) => self.log.logged.push(l),
            Message::Sync(_) => self.log.sync_count += 1,
            Message::Dropout { duration_ms } => self.log.dropouts.push(Dropout {
                offset: r.offset,
                timestamp: self.log.last_timestamp,
                duration_ms,
            }),
            Message::Unknown { msg_type, payload } => self.log.unknown.push(UnknownMessage {
                offset: r.offset,
                msg_type,
                payload,
            }),
            Message::FlagBits(_)
            | Message::Format(_)
            | Message::Subscribe { .. }
            | Message::Unsubscribe { .. }
            | Message::Data { .. } => {}
        }
    }
}

/// What a pass that kept a log without its data ([`LogMetadata`](crate::read::LogMetadata))
/// knows of the whole file, given back to the kept log's parse ([`ULog::restore`]).
pub(crate) struct WholeFile<'w> {
    /// Per parameter change and dropout: its offset in the kept bytes and the time
    /// of the data before it, sorted by offset.
    pub times: &'w [(u64, u64)],
    /// Per kept message: its offset in the kept bytes and in the file, sorted.
    pub places: &'w [(u64, u64)],
    pub last_timestamp: u64,
    pub flag_bits: Option<FlagBits>,
    pub subscriptions: &'w [Arc<Subscription>],
    pub findings: &'w [Finding],
    pub message_count: u64,
    /// The span the pass found ([`ULog::span`]).
    pub span: &'w TimeSpan,
}

impl ULog<'_> {
    /// Gives a log kept without its data what the pass that kept it saw of the whole
    /// file: each parameter change and dropout its time, each message its offset in
    /// the file, and the file's last timestamp, span, flag bits, subscriptions (when they
    /// are the kept log's: same names and instances), findings and message count.
    pub(crate) fn restore(&mut self, whole: &WholeFile<'_>) {
        self.last_timestamp = whole.last_timestamp;
        self.span = whole.span.clone();
        let time = |offset: u64| {
            let i = whole
                .times
                .binary_search_by_key(&offset, |&(o, _)| o)
                .ok()?;
            Some(whole.times[i].1)
        };
        for c in &mut self.param_changes {
            c.timestamp = time(c.offset).unwrap_or(c.timestamp);
        }
        for d in &mut self.dropouts {
            d.timestamp = time(d.offset).unwrap_or(d.timestamp);
        }
        let place = |offset: &mut u64| {
            if let Ok(i) = whole.places.binary_search_by_key(offset, |&(o, _)| o) {
                *offset = whole.places[i].1;
            }
        };
        self.param_changes
            .iter_mut()
            .for_each(|c| place(&mut c.offset));
        self.dropouts.iter_mut().for_each(|d| place(&mut d.offset));
        self.default_params
            .iter_mut()
            .for_each(|d| place(&mut d.offset));
        self.logged.iter_mut().for_each(|l| place(&mut l.offset));
        self.unknown.iter_mut().for_each(|u| place(&mut u.offset));
        let same = |a: &Arc<Subscription>, b: &Arc<Subscription>| {
            a.name() == b.name() && a.multi_id() == b.multi_id()
        };
        if whole.subscriptions.len() == self.subscriptions.len()
            && whole
                .subscriptions
                .iter()
                .zip(&self.subscriptions)
                .all(|(a, b)| same(a, b))
        {
            self.subscriptions = whole.subscriptions.to_vec();
        }
        self.flag_bits = whole.flag_bits;
        self.findings = whole.findings.to_vec();
        self.appended = appended_of(&self.findings);
        self.message_count = whole.message_count;
    }
}

/// The offsets where appended data sections start, as the findings say.
fn appended_of(findings: &[Finding]) -> Vec<u64> {
    findings
        .iter()
        .filter(|f| f.kind == FindingKind::AppendedData)
        .map(|f| f.offset)
        .collect()
}

impl<'a> ULog<'a> {
    /// The bytes the log was parsed from.
    pub fn data(&self) -> &'a [u8] {
        self.data
    }

    /// The file header.
    pub fn header(&self) -> Header {
        self.header
    }

    /// The file format version (0 or 1; higher versions are read and reported).
    pub fn version(&self) -> u8 {
        self.header.version
    }

    /// When logging started (header timestamp, microseconds).
    pub fn start_timestamp(&self) -> u64 {
        self.header.timestamp
    }

    /// The largest data timestamp in the log (the start timestamp when there is none
    /// larger), as pyulog's `last_timestamp`. A time axis takes [`ULog::span`]
    /// instead, which a stale or stray timestamp does not stretch.
    pub fn last_timestamp(&self) -> u64 {
        self.last_timestamp
    }

    /// The log's time span, by the one rule every output of this library draws and
    /// writes times with: its start, its end, and the rows far outside it
    /// ([`TimeSpan`](crate::read::TimeSpan) says how they are found).
    pub fn span(&self) -> &TimeSpan {
        &self.span
    }

    /// The flag bits message, when the log has one (version 1 logs).
    pub fn flag_bits(&self) -> Option<&FlagBits> {
        self.flag_bits.as_ref()
    }

    /// The format definitions, sorted by name.
    pub fn formats(&self) -> Vec<&Format> {
        let mut v: Vec<&Format> = self.formats.values().collect();
        v.sort_by(|a, b| a.name.cmp(&b.name));
        v
    }

    /// The format definition of `name`.
    pub fn format(&self, name: &str) -> Option<&Format> {
        self.formats.get(name)
    }

    /// Every information message, in file order.
    pub fn info(&self) -> &[KeyValue<'a>] {
        &self.info
    }

    /// The value of information key `name` (the last one wins, as in a dictionary).
    pub fn info_value(&self, name: &str) -> Option<Value<'a>> {
        self.info
            .iter()
            .rev()
            .find(|kv| kv.name() == name)
            .map(|kv| kv.value())
    }

    /// A release version from information key `ver_sw_release` or `ver_os_release`.
    pub fn release_version(&self, key: &str) -> Option<ReleaseVersion> {
        match self.info_value(key)? {
            Value::U32(v) => Some(ReleaseVersion::from_packed(v)),
            Value::I32(v) => Some(ReleaseVersion::from_packed(v as u32)),
            _ => None,
        }
    }

    /// Multi-information, one entry per key in order of first appearance.
    pub fn multi_info(&self) -> &[MultiInfo<'a>] {
        &self.multi_info
    }

    /// Parameters of the definitions section (their values when logging started).
    pub fn initial_params(&self) -> &[KeyValue<'a>] {
        &self.initial_params
    }

    /// The initial value of parameter `name`.
    pub fn initial_param(&self, name: &str) -> Option<Value<'a>> {
        self.initial_params
            .iter()
            .rev()
            .find(|kv| kv.name() == name)
            .map(|kv| kv.value())
    }

    /// Parameter changes in the data section, in file order.
    pub fn param_changes(&self) -> &[ParamChange<'a>] {
        &self.param_changes
    }

    /// Default parameters, in file order.
    pub fn default_params(&self) -> &[DefaultParam<'a>] {
        &self.default_params
    }

    /// Logged strings, plain and tagged, in file order.
    pub fn logged_messages(&self) -> &[LoggedString<'a>] {
        &self.logged
    }

    /// Dropouts, in file order.
    pub fn dropouts(&self) -> &[Dropout] {
        &self.dropouts
    }

    /// How many sync messages the log has.
    pub fn sync_count(&self) -> usize {
        self.sync_count
    }

    /// Messages of unknown types, kept as they were.
    pub fn unknown_messages(&self) -> &[UnknownMessage<'a>] {
        &self.unknown
    }

    /// What the reader found and stepped over, in file order.
    pub fn findings(&self) -> &[Finding] {
        &self.findings
    }

    /// Whether the log ends inside a message.
    pub fn is_truncated(&self) -> bool {
        self.findings
            .iter()
            .any(|f| f.kind == FindingKind::Truncated)
    }

    /// Whether any damage was found (corruption, skipped or dropped messages).
    pub fn has_damage(&self) -> bool {
        self.findings.iter().any(Finding::is_damage)
    }

    /// File offsets where appended data sections start (and were reached).
    pub fn appended_sections(&self) -> &[u64] {
        &self.appended
    }

    /// Number of messages framed.
    pub fn message_count(&self) -> u64 {
        self.message_count
    }

    /// Every subscription, in the order of their first `A` messages (the topic
    /// instances of the log; [`ULog::topics`] views them with their data).
    pub fn subscriptions(&self) -> &[Arc<Subscription>] {
        &self.subscriptions
    }

    /// The index of subscription `sub`'s data messages.
    pub(crate) fn index(&self, sub: usize) -> &TopicIndex {
        &self.index[sub]
    }

    /// Every message in file order, framed again from the bytes (with the same
    /// damage handling as the parse).
    pub fn messages(&self) -> Messages<'a> {
        Messages::new(self.data)
    }
}
