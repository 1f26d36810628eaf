//! [`ULog`]: a whole log parsed in one pass over borrowed bytes.

use std::collections::HashMap;
use std::sync::Arc;

use ulog_format::{Format, Layout, LayoutError};

use crate::error::{Error, ErrorKind, Result};
use crate::finding::{Finding, FindingKind};
use crate::read::framing::{FlagBits, Framer, Header, Record, Step, MSG_HEADER_LEN};
use crate::read::message::{KeyValue, LogMessage, Message};
use crate::read::offsets::OffsetIndex;
use crate::read::timestamp::{TimestampField, Unwrapper};
use crate::value::Value;

/// A subscription (`A`) with the data messages that belong to it.
#[derive(Debug, Clone)]
pub struct Subscription {
    pub(crate) msg_id: u16,
    pub(crate) multi_id: u8,
    pub(crate) name: String,
    pub(crate) offset: u64,
    pub(crate) layout: Result<Arc<Layout>, LayoutError>,
    /// Offsets of the `D` messages (their 3-byte headers), in file order.
    pub(crate) records: OffsetIndex,
    pub(crate) timestamp: Option<TimestampField>,
}

/// A multi-information key with its entries: each entry is the list of parts that
/// `is_continued` joined, in file order.
#[derive(Debug, Clone, PartialEq)]
pub struct MultiInfo<'a> {
    /// The key's name.
    pub name: String,
    /// The entries, each a list of continued parts.
    pub entries: Vec<Vec<KeyValue<'a>>>,
}

/// A parameter change in the data section.
#[derive(Debug, Clone, PartialEq)]
pub struct ParamChange<'a> {
    /// The latest data timestamp seen before the change (as pyulog reports it).
    pub timestamp: u64,
    /// Byte offset of the message.
    pub offset: u64,
    /// The parameter and its new value.
    pub kv: KeyValue<'a>,
}

/// A default parameter (`Q`).
#[derive(Debug, Clone, PartialEq)]
pub struct DefaultParam<'a> {
    /// Bit 0: system-wide default; bit 1: default of the current configuration.
    pub default_types: u8,
    /// Byte offset of the message.
    pub offset: u64,
    /// The parameter and its default value.
    pub kv: KeyValue<'a>,
}

/// A dropout (`O`): logging data lost for `duration_ms`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Dropout {
    /// Byte offset of the message.
    pub offset: u64,
    /// The latest data timestamp seen before the dropout.
    pub timestamp: u64,
    /// Duration in milliseconds.
    pub duration_ms: u16,
}

/// A message of a type this reader does not know, kept as it was.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct UnknownMessage<'a> {
    /// Byte offset of the message.
    pub offset: u64,
    /// The type byte.
    pub msg_type: u8,
    /// The payload.
    pub payload: &'a [u8],
}

/// Software or OS version decoded from `ver_sw_release` / `ver_os_release`
/// (`0xAABBCCTT`: major, minor, patch, type).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ReleaseVersion {
    /// Major version.
    pub major: u8,
    /// Minor version.
    pub minor: u8,
    /// Patch version.
    pub patch: u8,
    /// Type byte: < 64 development, < 128 alpha, < 192 beta, < 255 RC, 255 release.
    pub kind: u8,
}

impl ReleaseVersion {
    /// Decodes the packed `0xAABBCCTT` form.
    pub fn from_packed(v: u32) -> ReleaseVersion {
        let [major, minor, patch, kind] = v.to_be_bytes();
        ReleaseVersion {
            major,
            minor,
            patch,
            kind,
        }
    }

    /// `development`, `alpha`, `beta`, `rc` or `release`.
    pub fn kind_name(&self) -> &'static str {
        match self.kind {
            0..=63 => "development",
            64..=127 => "alpha",
            128..=191 => "beta",
            192..=254 => "rc",
            255 => "release",
        }
    }
}

impl core::fmt::Display for ReleaseVersion {
    /// As pyulog: `v1.4.2`, `v1.4.2 (RC)`; development versions too (`(dev)`).
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "v{}.{}.{}", self.major, self.minor, self.patch)?;
        match self.kind {
            0..=63 => write!(f, " (dev)"),
            64..=127 => write!(f, " (alpha)"),
            128..=191 => write!(f, " (beta)"),
            192..=254 => write!(f, " (RC)"),
            255 => Ok(()),
        }
    }
}

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
/// # Ok::<(), ulog_core::Error>(())
/// ```
#[derive(Debug)]
pub struct ULog<'a> {
    data: &'a [u8],
    header: Header,
    flag_bits: Option<FlagBits>,
    formats: HashMap<String, Format>,
    subscriptions: Vec<Subscription>,
    info: Vec<KeyValue<'a>>,
    multi_info: Vec<MultiInfo<'a>>,
    initial_params: Vec<KeyValue<'a>>,
    param_changes: Vec<ParamChange<'a>>,
    default_params: Vec<DefaultParam<'a>>,
    logged: Vec<LogMessage<'a>>,
    dropouts: Vec<Dropout>,
    sync_count: usize,
    unknown: Vec<UnknownMessage<'a>>,
    findings: Vec<Finding>,
    appended: Vec<u64>,
    last_timestamp: u64,
    message_count: u64,
}

struct Builder<'a> {
    log: ULog<'a>,
    /// Per subscription, what each data message updates: its offsets (moved into
    /// the subscription at the end) and its timestamp unwrapper.
    hot: Vec<(OffsetIndex, Unwrapper)>,
    multi_by_name: HashMap<String, usize>,
}

impl<'a> ULog<'a> {
    /// Parses a whole log from bytes (a buffer or a memory map).
    ///
    /// Damage does not fail the parse: it is reported in [`ULog::findings`] and the data
    /// around it is kept. Errors are for input that is not a ULog file at all, or a log
    /// the spec says to refuse (unknown incompatibility flags).
    pub fn parse(data: &'a [u8]) -> Result<ULog<'a>> {
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
                message_count: 0,
            },
            hot: Vec::new(),
            multi_by_name: HashMap::new(),
        };
        let mut started = false;
        loop {
            framer.plain_data_run(data, 0, |offset, sub, _, payload| {
                b.data(offset, sub, payload)
            });
            let step = framer.step(data, 0, true)?;
            if !started {
                if let Some(h) = framer.header {
                    b.log.header = h;
                    b.log.last_timestamp = h.timestamp;
                    started = true;
                }
            }
            match step {
                Step::Record(r) => b.record(&r, &mut framer),
                Step::End => break,
                Step::NeedMore => unreachable!("the whole file is given"),
            }
        }
        let mut log = b.log;
        for (sub, (records, _)) in log.subscriptions.iter_mut().zip(b.hot) {
            sub.records = records;
        }
        log.flag_bits = framer.flag_bits;
        log.formats = Arc::try_unwrap(std::mem::take(&mut framer.formats))
            .unwrap_or_else(|shared| (*shared).clone());
        log.findings = std::mem::take(&mut framer.findings);
        log.appended = log
            .findings
            .iter()
            .filter(|f| f.kind == FindingKind::AppendedData)
            .map(|f| f.offset)
            .collect();
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
    /// A data message of subscription `sub` (already mirrored: subscriptions only
    /// appear through [`Builder::record`]); `payload` starts with the msg_id.
    #[inline(always)]
    fn data(&mut self, offset: u64, sub: u32, payload: &[u8]) {
        self.log.message_count += 1;
        let (records, unwrap) = &mut self.hot[sub as usize];
        if records.is_full() {
            reserve_for_rest(records, offset, self.log.data.len());
        }
        records.push(offset);
        if let Some(ts) = unwrap.push(&payload[2..]) {
            self.log.last_timestamp = self.log.last_timestamp.max(ts);
        }
    }

    fn record(&mut self, r: &Record, framer: &mut Framer) {
        let data = self.log.data;
        let start = (r.offset as usize) + MSG_HEADER_LEN;
        let payload = &data[start..start + r.size as usize];
        // Subscriptions are created by framing; mirror new ones here.
        while self.log.subscriptions.len() < framer.subs.len() {
            let def = &framer.subs[self.log.subscriptions.len()];
            let timestamp = def.layout.as_ref().ok().and_then(|l| TimestampField::of(l));
            self.hot
                .push((OffsetIndex::default(), Unwrapper::new(timestamp)));
            self.log.subscriptions.push(Subscription {
                msg_id: def.msg_id,
                multi_id: def.multi_id,
                name: def.name.clone(),
                offset: def.offset,
                layout: def.layout.clone(),
                records: OffsetIndex::default(),
                timestamp,
            });
        }
        if r.msg_type == b'D' {
            match r.sub {
                Some(i) => self.data(r.offset, i, payload),
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
    /// larger), as pyulog's `last_timestamp`.
    pub fn last_timestamp(&self) -> u64 {
        self.last_timestamp
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
    pub fn logged_messages(&self) -> &[LogMessage<'a>] {
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

    /// Every subscription, in the order of their `A` messages.
    pub fn subscriptions(&self) -> &[Subscription] {
        &self.subscriptions
    }

    /// Every topic instance (one per subscription), in subscription order.
    pub fn topics(&self) -> impl Iterator<Item = crate::Topic<'_, 'a>> {
        self.subscriptions
            .iter()
            .map(move |sub| crate::Topic::new(self, sub))
    }

    /// The topic of subscription `index` (an index into [`ULog::subscriptions`]).
    ///
    /// # Panics
    /// If there is no such subscription.
    pub fn topic_at(&self, index: usize) -> crate::Topic<'_, 'a> {
        crate::Topic::new(self, &self.subscriptions[index])
    }

    /// The topic `name` with `multi_id`.
    pub fn topic(&self, name: &str, multi_id: u8) -> Result<crate::Topic<'_, 'a>> {
        self.subscriptions
            .iter()
            .find(|s| s.name == name && s.multi_id == multi_id)
            .map(|sub| crate::Topic::new(self, sub))
            .ok_or_else(|| {
                let names: Vec<&str> = self.subscriptions.iter().map(|s| s.name.as_str()).collect();
                let exists = names.contains(&name);
                Error::new(
                    ErrorKind::TopicNotFound {
                        name: if exists {
                            format!("{name}` with multi_id `{multi_id}")
                        } else {
                            name.to_owned()
                        },
                        suggestion: if exists {
                            None
                        } else {
                            crate::suggest::closest(name, names.iter().copied())
                        },
                    },
                    0,
                )
            })
    }

    /// Every instance of topic `name`, by multi_id.
    pub fn topic_instances(&self, name: &str) -> Vec<crate::Topic<'_, 'a>> {
        let mut v: Vec<_> = self.topics().filter(|t| t.name() == name).collect();
        v.sort_by_key(|t| t.multi_id());
        v
    }

    /// Every message in file order, framed again from the bytes (with the same
    /// damage handling as the parse).
    pub fn messages(&self) -> crate::read::iter::Messages<'a> {
        crate::read::iter::Messages::new(self.data)
    }
}
