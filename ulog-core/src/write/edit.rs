//! [`Edit`]: a log re-written with a time window, a choice of topics and payloads
//! mapped by a closure, everything else as it was.

use std::collections::{HashMap, HashSet};
use std::io::Write;

use crate::access::lookup::TopicNotFound;
use crate::bytes::{u16_at, HEADER_SIZE, MESSAGE_HEADER_SIZE};
use crate::definitions::timestamp::Unwrapper;
use crate::definitions::Subscription;
use crate::finding::Finding;
use crate::log::message::Message;
use crate::log::messages::Messages;
use crate::log::ulog::ULog;
use crate::write::error::{WriteError, WriteErrorKind};
use crate::write::raw::RawWriter;

/// A payload mapper: the topic of the data message, and its payload (after the
/// msg_id) to change in place.
type Mapper<'f> = Box<dyn FnMut(&Subscription, &mut [u8]) + 'f>;

/// A log re-written message by message into a valid log: data messages of the chosen
/// topics inside a time window, payloads mapped by a closure, and every other message
/// kept byte for byte, by these rules:
///
/// - the header, information, multi-information and default parameters, logged
///   strings are kept (logged strings inside the window only, by their own timestamp);
/// - subscriptions of kept topics only, and with a topic filter the formats they use
///   only (nested ones included; without a filter, every format);
/// - parameters as they were at the window's start: changes before it become the
///   initial values (a name first set by a change is added after the initial ones),
///   changes inside it stay changes, later ones are left out;
/// - dropouts and sync markers inside the window; unsubscriptions of kept topics;
/// - data messages with `start ≤ timestamp < end`, each topic by its own timestamp
///   (narrow version 0 timestamps unwrapped); a topic without a timestamp field, and
///   the parameter changes, dropouts and syncs, by the log's time where they stand (the
///   highest data timestamp before them, as [`ULog`] gives it);
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
    map: Option<Mapper<'f>>,
}

impl core::fmt::Debug for Edit<'_> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Edit")
            .field("start", &self.start)
            .field("end", &self.end)
            .field("only", &self.only)
            .field("exclude", &self.exclude)
            .field("drop_info", &self.drop_info)
            .field("map", &self.map.is_some())
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
    /// What the reader stepped over in the input (not written).
    pub skipped: Vec<Finding>,
}

impl<'f> Edit<'f> {
    /// An edit that keeps everything.
    pub fn new() -> Edit<'f> {
        Edit::default()
    }

    /// Keeps data with `start ≤ timestamp < end` (microseconds, as the log's
    /// timestamps; `None`: no bound).
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

    /// Calls `map` on the payload of every data message written (after the msg_id),
    /// to change its bytes in place (its length stays).
    pub fn map_payloads(mut self, map: impl FnMut(&Subscription, &mut [u8]) + 'f) -> Edit<'f> {
        self.map = Some(Box::new(map));
        self
    }

    /// Writes the edited `log` to `out`.
    ///
    /// Errors: a topic of
    /// [`Edit::only`] or [`Edit::exclude`] that is not in the log
    /// ([`WriteErrorKind::TopicNotFound`], before anything is written), and failures to
    /// write.
    pub fn write<W: Write>(mut self, log: &ULog<'_>, out: W) -> Result<EditSummary, WriteError> {
        let data = log.data();
        for name in self.only.iter().flatten().chain(&self.exclude) {
            if log.topic_instances(name).is_empty() {
                let missing = TopicNotFound::in_log(log, name, None);
                return Err(WriteError::new(
                    WriteErrorKind::TopicNotFound(missing),
                    None,
                ));
            }
        }
        let kept = |name: &str| {
            self.only
                .as_ref()
                .map_or(true, |only| only.iter().any(|n| n == name))
                && !self.exclude.iter().any(|n| n == name)
        };
        // With a topic filter, only the formats the kept topics use, nested ones
        // included; without, all of them.
        let filtered = self.only.is_some() || !self.exclude.is_empty();
        let mut formats: HashSet<String> = HashSet::new();
        for sub in log.subscriptions().iter().filter(|s| kept(s.name())) {
            formats.insert(sub.name().to_owned());
            if let Ok(layout) = sub.layout() {
                formats.extend(layout.formats().iter().map(|f| f.name.clone()));
            }
        }
        let start = self.start.unwrap_or(0);
        let end = self.end.unwrap_or(u64::MAX);
        let inside = |t: u64| start <= t && t < end;
        // Parameters at the start: the last change before it of each name.
        let mut folded: HashMap<String, &[u8]> = HashMap::new();
        let mut added: Vec<String> = Vec::new();
        if self.start.is_some() {
            let initial: HashSet<String> = log
                .initial_params()
                .iter()
                .map(|kv| kv.name().into_owned())
                .collect();
            for change in log.param_changes().iter().filter(|c| c.timestamp < start) {
                let name = change.kv.name().into_owned();
                if !initial.contains(&name) && !folded.contains_key(&name) {
                    added.push(name.clone());
                }
                folded.insert(name, payload_at(data, change.offset));
            }
        }

        let mut w = RawWriter::new(out);
        let mut summary = EditSummary::default();
        let mut messages = Messages::new(data);
        let mut in_definitions = true;
        let mut last = log.start_timestamp();
        // Per subscription, met at its first data message: its timestamps, and whether
        // its topic is kept.
        let mut topics: Vec<Option<(Unwrapper, bool)>> = Vec::new();
        let mut buffer = Vec::new();
        let mut started = false;
        let mut kept_ids: HashSet<u16> = HashSet::new();
        while let Some(m) = messages.next() {
            let m = m.map_err(WriteError::unreadable)?;
            if !started {
                w.bytes(&data[..HEADER_SIZE])?;
                started = true;
            }
            let offset = m.offset as usize;
            let payload = payload_at(data, m.offset);
            let ends_definitions = matches!(m.message, Message::Subscribe { .. } | Message::Log(_));
            if in_definitions && ends_definitions {
                in_definitions = false;
                // Parameters first set by a change before the window.
                for name in &added {
                    w.message(b'P', &[folded[name]])?;
                    summary.messages += 1;
                }
            }
            let keep = match &m.message {
                Message::FlagBits(_) => {
                    if offset == HEADER_SIZE && payload.len() >= 40 {
                        // The result has no appended data: its offsets and flag go.
                        let mut bits = payload.to_vec();
                        bits[8] &= !1;
                        bits[16..40].fill(0);
                        w.message(b'B', &[&bits])?;
                        summary.messages += 1;
                    }
                    false
                }
                Message::Format(_) if filtered => {
                    let name = payload.split(|&b| b == b':').next().unwrap_or(&[]);
                    formats.contains(&*String::from_utf8_lossy(name))
                }
                Message::Param(kv) if in_definitions => {
                    let value = folded.get(&*kv.name()).copied().unwrap_or(payload);
                    w.message(b'P', &[value])?;
                    summary.messages += 1;
                    false
                }
                Message::Param(_) | Message::Dropout { .. } | Message::Sync(_) => inside(last),
                Message::Log(l) => inside(l.timestamp),
                Message::Subscribe { msg_id, .. } => {
                    let keep = messages
                        .subscription(*msg_id)
                        .is_some_and(|s| kept(s.name()));
                    if keep {
                        kept_ids.insert(*msg_id);
                    } else {
                        kept_ids.remove(msg_id);
                    }
                    keep
                }
                // Framing has let the subscription go already: whether it was kept is
                // remembered.
                Message::Unsubscribe { msg_id } => kept_ids.remove(msg_id),
                Message::Data { msg_id, payload } => {
                    let Some(sub) = messages.subscription(*msg_id) else {
                        continue;
                    };
                    let i = sub.index();
                    if topics.len() <= i {
                        topics.resize_with(i + 1, || None);
                    }
                    let (clock, chosen) = topics[i].get_or_insert_with(|| {
                        (Unwrapper::new(sub.timestamp_field()), kept(sub.name()))
                    });
                    let time = match clock.push(payload) {
                        Some(t) => {
                            last = last.max(t);
                            t
                        }
                        None => last,
                    };
                    if !*chosen || !inside(time) {
                        summary.rows_left_out += 1;
                        continue;
                    }
                    if let Some(map) = &mut self.map {
                        buffer.clear();
                        buffer.extend_from_slice(&msg_id.to_le_bytes());
                        buffer.extend_from_slice(payload);
                        map(sub, &mut buffer[2..]);
                        w.message(b'D', &[&buffer])?;
                        summary.messages += 1;
                        summary.rows += 1;
                        continue;
                    }
                    summary.rows += 1;
                    true
                }
                Message::Info(kv) | Message::MultiInfo { kv, .. } => {
                    !self.drop_info.iter().any(|k| *k == kv.name())
                }
                Message::Format(_) | Message::DefaultParam { .. } | Message::Unknown { .. } => true,
            };
            if keep {
                w.message(data[offset + 2], &[payload])?;
                summary.messages += 1;
            }
        }
        if !started {
            w.bytes(&data[..HEADER_SIZE.min(data.len())])?;
        }
        summary.skipped = messages.findings().to_vec();
        w.flush()?;
        Ok(summary)
    }
}

/// The payload of the message at `offset`.
fn payload_at(data: &[u8], offset: u64) -> &[u8] {
    let at = offset as usize;
    let size = usize::from(u16_at(data, at));
    &data[at + MESSAGE_HEADER_SIZE..at + MESSAGE_HEADER_SIZE + size]
}
