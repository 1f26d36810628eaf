//! [`Edit`]: a log re-written with a time window, a choice of topics and payloads
//! mapped by a closure, everything else as it was.

use std::collections::{HashMap, HashSet};
use std::io::Write;

use crate::access::lookup::TopicNotFound;
use crate::bytes::{HEADER_SIZE, MAGIC};
use crate::definitions::timestamp::Unwrapper;
use crate::definitions::{Definitions, Subscription};
use crate::finding::Finding;
use crate::framing::{Framer, Header, Record};
use crate::log::message::{KeyValue, Message};
use crate::pass::source::{drive, Source};
use crate::pass::visit::{DataRecord, Hand, Visit};
use crate::write::error::{WriteError, WriteErrorKind};
use crate::write::raw::RawWriter;

/// A payload mapper: the topic of the data message, and its payload (after the
/// msg_id) to change in place.
type Mapper<'f> = Box<dyn FnMut(&Subscription, &mut [u8]) + 'f>;

/// A mapper of the messages that hold values besides data: the type byte and the
/// payload, to change (its length too).
type MessageMapper<'f> = Box<dyn FnMut(u8, &mut Vec<u8>) + 'f>;

/// The message types [`Edit::map_messages`] sees.
const MAPPED_TYPES: &[u8] = b"IMPQLC";

/// A log re-written message by message into a valid log: data messages of the chosen
/// topics inside a time window, payloads mapped by a closure, and every other message
/// kept byte for byte, by these rules:
///
/// - the header, information, multi-information and default parameters, logged
///   strings are kept (logged strings inside the window only, by their own timestamp);
/// - subscriptions of kept topics only; every format without a topic filter, with
///   [`Edit::only`] the formats of the named topics (nested ones included), with
///   [`Edit::exclude`] every format but the excluded topics' own (the formats
///   nested in them stay: formats are written before the subscriptions are met, so a
///   nested format cannot be told from a topic that is subscribed later);
/// - parameters as they were at the window's start: changes before it become the
///   initial values (a name first set by a change is added after the initial ones),
///   changes inside it stay changes, later ones are left out;
/// - dropouts and sync markers inside the window; unsubscriptions of kept topics;
/// - data messages with `start ≤ timestamp < end`, each topic by its own timestamp
///   (narrow version 0 timestamps unwrapped); a topic without a timestamp field, and
///   the parameter changes, dropouts and syncs, by the log's time where they stand (the
///   highest data timestamp before them, as [`ULog`](crate::ULog) gives it);
/// - appended data is data: it is written in place, and the flag bits say the result
///   has none (the appended offsets and the flag zeroed);
/// - what the reader steps over (corruption, a truncated tail, misplaced flag bits)
///   is not written: it is in [`EditSummary::skipped`]. Nothing malformed is written.
///
/// With no window, no topic filter and no mapper, an undamaged log without appended
/// data comes out byte for byte as it went in (as [`copy_log`](crate::copy_log)
/// gives it).
///
/// ```
/// use ulog_core::{Edit, ULog};
/// let bytes = ulog_core::testing::sample_log();
/// let log = ULog::parse(&bytes)?;
/// let start = log.start_timestamp();
/// let mut out = Vec::new();
/// let summary = Edit::new()
///     .window(Some(start + 1_000), None)
///     .exclude(["esc_status"])
///     .write(&log, &mut out)?;
/// let cut = ULog::parse(&out)?;
/// assert!(cut.topic_instances("esc_status").is_empty());
/// let attitude = cut.topic("vehicle_attitude", 0)?;
/// assert!(attitude.timestamps().iter().all(|&t| t >= start + 1_000));
/// assert_eq!(summary.rows, cut.topics().map(|t| t.len() as u64).sum::<u64>());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Default)]
pub struct Edit<'f> {
    start: Option<u64>,
    end: Option<u64>,
    only: Option<Vec<String>>,
    exclude: Vec<String>,
    drop_info: Vec<String>,
    header_timestamp: Option<u64>,
    map: Option<Mapper<'f>>,
    map_messages: Option<MessageMapper<'f>>,
}

impl core::fmt::Debug for Edit<'_> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Edit")
            .field("start", &self.start)
            .field("end", &self.end)
            .field("only", &self.only)
            .field("exclude", &self.exclude)
            .field("drop_info", &self.drop_info)
            .field("header_timestamp", &self.header_timestamp)
            .field("map", &self.map.is_some())
            .field("map_messages", &self.map_messages.is_some())
            .finish()
    }
}

/// What an [`Edit`] wrote, and what it did not copy.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct EditSummary {
    /// Messages written (after the header).
    pub messages: u64,
    /// Data messages written.
    pub rows: u64,
    /// Data messages left out (other topics, outside the window).
    pub rows_left_out: u64,
    /// The lowest and highest data timestamps of the input, of every topic (kept or
    /// not; by the clock the window uses): where a window that kept no row could
    /// have been. `None` for a log without data.
    pub data_times: Option<(u64, u64)>,
    /// Topics named by [`Edit::only`] or [`Edit::exclude`] that the log has a format
    /// for but never subscribes (so no data of them was kept or left out).
    pub unlogged: Vec<String>,
    /// What the reader stepped over in the input (not written).
    pub skipped: Vec<Finding>,
}

impl<'f> Edit<'f> {
    /// An edit that keeps everything.
    pub fn new() -> Edit<'f> {
        Edit::default()
    }

    /// Keeps data with `start ≤ timestamp < end` (microseconds, as the log's
    /// timestamps; `None`: no bound). A window whose start is not before its end is
    /// refused by [`Edit::write`] ([`WriteErrorKind::EmptyWindow`]).
    pub fn window(mut self, start: Option<u64>, end: Option<u64>) -> Edit<'f> {
        self.start = start;
        self.end = end;
        self
    }

    /// Keeps only these topics (every instance of each).
    pub fn only<S: Into<String>>(mut self, topics: impl IntoIterator<Item = S>) -> Edit<'f> {
        self.only = Some(topics.into_iter().map(Into::into).collect());
        self
    }

    /// Leaves these topics out (every instance of each; added to those left out
    /// before).
    pub fn exclude<S: Into<String>>(mut self, topics: impl IntoIterator<Item = S>) -> Edit<'f> {
        self.exclude.extend(topics.into_iter().map(Into::into));
        self
    }

    /// Leaves out the information and multi-information messages of these keys
    /// (added to those left out before).
    pub fn drop_info<S: Into<String>>(mut self, keys: impl IntoIterator<Item = S>) -> Edit<'f> {
        self.drop_info.extend(keys.into_iter().map(Into::into));
        self
    }

    /// Writes `timestamp` (microseconds) as the header's: when logging started. Data
    /// timestamps are not changed, so readers that count time from the header count
    /// from another origin.
    pub fn header_timestamp(mut self, timestamp: u64) -> Edit<'f> {
        self.header_timestamp = Some(timestamp);
        self
    }

    /// Calls `map` on the payload of every data message written (after the msg_id),
    /// to change its bytes in place (its length stays).
    pub fn map_payloads(mut self, map: impl FnMut(&Subscription, &mut [u8]) + 'f) -> Edit<'f> {
        self.map = Some(Box::new(map));
        self
    }

    /// Calls `map` on every information, multi-information, parameter, default
    /// parameter and logged string message written (`I`, `M`, `P`, `Q`, `L`, `C`), in
    /// the order they are written, with its type byte and its payload to change (its
    /// length may change; it must stay a message of its type). Parameters are seen as
    /// written: with a window, the initial values as they were at its start.
    pub fn map_messages(mut self, map: impl FnMut(u8, &mut Vec<u8>) + 'f) -> Edit<'f> {
        self.map_messages = Some(Box::new(map));
        self
    }

    /// Writes the edited log from `source` to `out`, in one pass over its messages in
    /// file order: no index is built, and a reader or [`Source::file`] is read in
    /// chunks on a second thread while the messages before are framed and written
    /// (the memory held is a few read buffers), so that a cut costs about a framing
    /// of the log and the writing of what is kept.
    ///
    /// Nothing is written before the definitions are read and, with a window, before
    /// the log reaches its start (the parameters written first are those at the
    /// start): until then what is kept is held.
    ///
    /// Errors: a topic of [`Edit::only`] or [`Edit::exclude`] that no format of the
    /// log's definitions section names ([`WriteErrorKind::TopicNotFound`], before
    /// anything is written; a topic with a format but no subscription is in
    /// [`EditSummary::unlogged`]; a format that comes after the definitions section,
    /// which framing accepts and the spec does not, is kept or left out with its topic
    /// but is not looked in for these names),
    /// input that is not a log ([`WriteErrorKind::Unreadable`], its error kept as the
    /// source), a window that holds no time ([`WriteErrorKind::EmptyWindow`], before
    /// anything is read), and failures to write. A window that holds time but none of
    /// the log's data is no error: the result has the definitions and no data
    /// ([`EditSummary::rows`] 0, [`EditSummary::data_times`] says where the data is).
    pub fn write<'s, W: Write>(
        self,
        source: impl Into<Source<'s>>,
        out: W,
    ) -> Result<EditSummary, WriteError> {
        if let (Some(start), Some(end)) = (self.start, self.end) {
            if start >= end {
                return Err(WriteError::new(
                    WriteErrorKind::EmptyWindow { start, end },
                    None,
                ));
            }
        }
        let mut editor = Editor {
            start: self.start.unwrap_or(0),
            end: self.end.unwrap_or(u64::MAX),
            edit: self,
            w: RawWriter::new(out),
            summary: EditSummary::default(),
            held: Some(Held::default()),
            last: 0,
            started: false,
            topics: Vec::new(),
            buffer: Vec::new(),
            kept_ids: HashSet::new(),
            error: None,
            header: Header {
                version: 1,
                timestamp: 0,
            },
        };
        let scan = drive(source.into(), true, &mut editor);
        if let Some(e) = editor.error.take() {
            return Err(e);
        }
        let scan = scan.map_err(WriteError::unreadable)?;
        if let Some(h) = editor.held.take() {
            editor.write_held(h, &scan.header)?;
        }
        let Editor {
            edit,
            mut w,
            mut summary,
            ..
        } = editor;
        let subscribed: HashSet<&str> = scan.topics.iter().map(|s| s.name()).collect();
        summary.unlogged = edit
            .only
            .iter()
            .flatten()
            .chain(&edit.exclude)
            .filter(|n| !subscribed.contains(n.as_str()))
            .cloned()
            .collect();
        summary.unlogged.sort();
        summary.unlogged.dedup();
        summary.skipped = scan.findings;
        w.flush()?;
        Ok(summary)
    }
}

/// An edit under way: what [`Edit::write`]'s pass hands the messages to.
struct Editor<'f, W: Write> {
    edit: Edit<'f>,
    start: u64,
    end: u64,
    w: RawWriter<W>,
    summary: EditSummary,
    /// What is kept before anything can be written; `None` once written.
    held: Option<Held>,
    /// The log's time: the highest data timestamp so far (the header's before any).
    last: u64,
    /// Whether a message has been met (and `last` set to the header's time).
    started: bool,
    /// Per subscription, met at its first data message: its timestamps, and whether
    /// its topic is kept.
    topics: Vec<Option<(Unwrapper, bool)>>,
    buffer: Vec<u8>,
    /// The msg_ids whose current subscription is kept.
    kept_ids: HashSet<u16>,
    /// What stopped the pass.
    error: Option<WriteError>,
    /// The input's header (once framed).
    header: Header,
}

/// What an edit keeps before it can write: the messages (type and payload), how many
/// of them are definitions (once known), the parameters changed before the start, and
/// the definitions framing had at their end.
#[derive(Default)]
struct Held {
    messages: Vec<(u8, Vec<u8>)>,
    definitions: Option<usize>,
    /// The last change before the start of each name: its payload.
    folded: HashMap<String, Vec<u8>>,
    /// Names first set by a change before the start, in the order they were.
    added: Vec<String>,
    defs: Option<Definitions>,
}

impl<'f, W: Write> Editor<'f, W> {
    #[inline(always)]
    fn inside(&self, t: u64) -> bool {
        self.start <= t && t < self.end
    }

    fn kept(&self, name: &str) -> bool {
        self.edit
            .only
            .as_ref()
            .map_or(true, |only| only.iter().any(|n| n == name))
            && !self.edit.exclude.iter().any(|n| n == name)
    }

    /// Writes what is held once it may be: after the definitions, once the log's
    /// time has reached the start.
    fn release(&mut self, in_definitions: bool) -> Result<(), WriteError> {
        if in_definitions || self.last < self.start {
            return Ok(());
        }
        if let Some(h) = self.held.take() {
            let header = self.header;
            self.write_held(h, &header)?;
        }
        Ok(())
    }

    /// Writes the header and what is held: the definitions (formats filtered, the
    /// initial parameters as at the start, flag bits without appended data), the
    /// parameters first set before the start, then the rest. First, the topics
    /// asked for are looked for among the formats of `defs`.
    fn write_held(&mut self, mut h: Held, header: &Header) -> Result<(), WriteError> {
        let edit = &self.edit;
        let defs = h.defs.take().unwrap_or_else(Definitions::new);
        for name in edit.only.iter().flatten().chain(&edit.exclude) {
            if defs.formats_of(name).is_empty() {
                // Sorted: suggestions as close as each other come in one order.
                let mut names: Vec<&str> = defs.format_names().collect();
                names.sort_unstable();
                let missing = TopicNotFound::among(name, names.into_iter());
                return Err(WriteError::new(
                    WriteErrorKind::TopicNotFound(missing),
                    None,
                ));
            }
        }
        let formats = kept_formats(edit, &defs);
        let timestamp = edit.header_timestamp.unwrap_or(header.timestamp);
        let mut bytes = MAGIC.to_vec();
        bytes.push(header.version);
        bytes.extend_from_slice(&timestamp.to_le_bytes());
        self.w.bytes(&bytes)?;
        let definitions = h.definitions.unwrap_or(h.messages.len());
        let mut added = std::mem::take(&mut h.added);
        // An initial value's change before the start replaces it; names first set by
        // a change are added after the definitions.
        let mut initial: HashSet<String> = HashSet::new();
        for (i, (msg_type, payload)) in h.messages.iter_mut().enumerate() {
            if i == definitions {
                self.write_added(&mut added, &h.folded, &initial)?;
            }
            match *msg_type {
                b'B' => {
                    payload[8] &= !1;
                    payload[16..40].fill(0);
                }
                b'F' if formats
                    .as_ref()
                    .is_some_and(|f| !f.contains(&format_name(payload))) =>
                {
                    continue;
                }
                b'P' if i < definitions => {
                    let name = param_name(payload);
                    if let Some(value) = h.folded.get(&name) {
                        payload.clone_from(value);
                    }
                    initial.insert(name);
                }
                _ => {}
            }
            self.write_other(*msg_type, payload)?;
        }
        self.write_added(&mut added, &h.folded, &initial)
    }

    /// Writes a message other than data, through [`Edit::map_messages`] if it maps
    /// its type.
    fn write_other(&mut self, msg_type: u8, payload: &[u8]) -> Result<(), WriteError> {
        match &mut self.edit.map_messages {
            Some(map) if MAPPED_TYPES.contains(&msg_type) => {
                let mut mapped = payload.to_vec();
                map(msg_type, &mut mapped);
                self.w.message(msg_type, &[&mapped])?;
            }
            _ => self.w.message(msg_type, &[payload])?,
        }
        self.summary.messages += 1;
        Ok(())
    }

    /// The parameters first set by a change before the start (not among `initial`),
    /// once.
    fn write_added(
        &mut self,
        added: &mut Vec<String>,
        folded: &HashMap<String, Vec<u8>>,
        initial: &HashSet<String>,
    ) -> Result<(), WriteError> {
        for name in std::mem::take(added) {
            if !initial.contains(&name) {
                self.write_other(b'P', &folded[&name])?;
            }
        }
        Ok(())
    }

    /// A message kept: written, or held until what comes before it is.
    fn keep(&mut self, msg_type: u8, payload: &[u8]) -> Result<(), WriteError> {
        match &mut self.held {
            Some(h) => h.messages.push((msg_type, payload.to_vec())),
            None => self.write_other(msg_type, payload)?,
        }
        Ok(())
    }

    fn other_message(
        &mut self,
        r: &Record,
        payload: &[u8],
        framer: &Framer,
    ) -> Result<(), WriteError> {
        let Some(header) = framer.header else {
            return Ok(());
        };
        self.header = header;
        if !self.started {
            self.last = header.timestamp;
            self.started = true;
        }
        let in_definitions = framer.in_definitions;
        if let Some(h) = &mut self.held {
            // The definitions as they stand where they end (one copy: a copy held
            // while framing adds formats would make it copy its table at each one),
            // and again at a format after them (framing accepts one).
            if !in_definitions && (h.definitions.is_none() || r.msg_type == b'F') {
                h.definitions.get_or_insert(h.messages.len());
                h.defs = Some(framer.defs.clone());
            }
        }
        self.release(in_definitions)?;
        let last = self.last;
        let message = Message::from_record(r, payload, framer.flag_bits);
        let keep = match &message {
            // Only the first message can be the flag bits (the result has no
            // appended data, which is seen to when they are written).
            Message::FlagBits(_) => r.offset as usize == HEADER_SIZE && payload.len() >= 40,
            Message::Param(_) if in_definitions => true,
            Message::Param(kv) => {
                if let (Some(h), true) = (&mut self.held, self.edit.start.is_some()) {
                    // A change before the start: folded into the initial values.
                    let name = kv.name().into_owned();
                    if !h.folded.contains_key(&name) {
                        h.added.push(name.clone());
                    }
                    h.folded.insert(name, payload.to_vec());
                    return Ok(());
                }
                self.inside(last)
            }
            Message::Dropout { .. } | Message::Sync(_) => self.inside(last),
            Message::Log(l) => self.inside(l.timestamp),
            Message::Subscribe { msg_id, .. } => {
                let sub = framer
                    .defs
                    .sub_index(*msg_id)
                    .and_then(|i| framer.defs.subscriptions().get(i as usize));
                let keep = sub.is_some_and(|s| self.kept(s.name()));
                if keep {
                    self.kept_ids.insert(*msg_id);
                } else {
                    self.kept_ids.remove(msg_id);
                }
                keep
            }
            // Framing has let the subscription go already: whether it was kept is
            // remembered.
            Message::Unsubscribe { msg_id } => self.kept_ids.remove(msg_id),
            Message::Info(kv) | Message::MultiInfo { kv, .. } => {
                !self.edit.drop_info.iter().any(|k| *k == kv.name())
            }
            // A format after the definitions, once what was held is written: kept by
            // the filter as it stands with it.
            Message::Format(_) if self.held.is_none() => kept_formats(&self.edit, &framer.defs)
                .map_or(true, |f| f.contains(&format_name(payload))),
            Message::Format(_) | Message::DefaultParam { .. } | Message::Unknown { .. } => true,
            Message::Data { .. } => false,
        };
        if keep {
            self.keep(r.msg_type, payload)?;
        }
        Ok(())
    }

    /// The first data message of a topic instance: whether its topic is kept, and
    /// its clock.
    #[cold]
    fn first_data(&mut self, r: &DataRecord<'_>) {
        let i = r.topic.index();
        if self.topics.len() <= i {
            self.topics.resize_with(i + 1, || None);
        }
        let chosen = self.kept(r.topic.name());
        self.topics[i] = Some((Unwrapper::new(r.topic.timestamp_field()), chosen));
    }

    /// A data message to write (inside the window, of a kept topic): what is held
    /// goes first (its time is inside the window, so the log's is too).
    #[inline(never)]
    fn write_data(&mut self, r: DataRecord<'_>) -> Result<(), WriteError> {
        if let Some(h) = self.held.take() {
            let header = self.header;
            self.write_held(h, &header)?;
        }
        self.summary.rows += 1;
        self.summary.messages += 1;
        let id = r.msg_id.to_le_bytes();
        match &mut self.edit.map {
            Some(map) => {
                self.buffer.clear();
                self.buffer.extend_from_slice(r.payload);
                map(r.topic, &mut self.buffer);
                self.w.message(b'D', &[&id, &self.buffer])
            }
            None => self.w.message(b'D', &[&id, r.payload]),
        }
    }
}

impl<W: Write> Visit for Editor<'_, W> {
    // The path of every data message: its time, and whether it is kept (most of a
    // cut's are not), inlined into framing's loop.
    #[inline(always)]
    fn data(&mut self, record: DataRecord<'_>) -> Hand {
        let i = record.topic.index();
        if !matches!(self.topics.get(i), Some(Some(_))) {
            self.first_data(&record);
        }
        let Some(Some((clock, chosen))) = self.topics.get_mut(i) else {
            return Hand::Next;
        };
        let time = match clock.push(record.payload) {
            Some(t) => {
                self.last = self.last.max(t);
                t
            }
            None => self.last,
        };
        self.summary.data_times = Some(match self.summary.data_times {
            Some((lo, hi)) => (lo.min(time), hi.max(time)),
            None => (time, time),
        });
        if !*chosen || !self.inside(time) {
            self.summary.rows_left_out += 1;
            return Hand::Next;
        }
        match self.write_data(record) {
            Ok(()) => Hand::Next,
            Err(e) => {
                self.error = Some(e);
                Hand::Stop
            }
        }
    }

    fn end(&mut self, framer: &Framer) {
        // A log that ends in its definitions (or still holding): the formats as they
        // stand at the end.
        if let Some(h) = &mut self.held {
            h.defs = Some(framer.defs.clone());
        }
    }

    fn other(&mut self, record: &Record, payload: &[u8], framer: &Framer) -> bool {
        match self.other_message(record, payload, framer) {
            Ok(()) => true,
            Err(e) => {
                self.error = Some(e);
                false
            }
        }
    }
}

/// With a topic filter, the formats the kept topics use, nested ones included: with
/// `only`, those of the named topics; with `exclude`, those of every other format (a
/// format nested in an excluded topic stays: formats come before the subscriptions
/// that would tell it from a topic's own). `None`: every format.
fn kept_formats(edit: &Edit<'_>, defs: &Definitions) -> Option<HashSet<String>> {
    match (&edit.only, edit.exclude.is_empty()) {
        (None, true) => None,
        (Some(only), _) => Some(
            only.iter()
                .filter(|n| !edit.exclude.contains(n))
                .flat_map(|n| defs.formats_of(n))
                .collect(),
        ),
        (None, false) => Some(
            defs.format_names()
                .filter(|n| !edit.exclude.iter().any(|x| x == n))
                .flat_map(|n| defs.formats_of(n))
                .collect(),
        ),
    }
}

/// The name a format message defines.
fn format_name(payload: &[u8]) -> String {
    let name = payload.split(|&b| b == b':').next().unwrap_or(&[]);
    String::from_utf8_lossy(name).into_owned()
}

/// The name of a parameter message's key (`type name`), as the reader gives it.
fn param_name(payload: &[u8]) -> String {
    let key_len = usize::from(payload.first().copied().unwrap_or(0));
    let key = payload.get(1..1 + key_len).unwrap_or(&[]);
    let raw = payload.get(1 + key_len..).unwrap_or(&[]);
    KeyValue::parse(key, raw).name().into_owned()
}
