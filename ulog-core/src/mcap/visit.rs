//! The pass that writes an MCAP file: what it does with each data message and each
//! other message of the log, as framing meets them.

use std::collections::BTreeMap;
use std::io::{Seek, Write};

use ::mcap::records::{MessageHeader, Metadata};
use ::mcap::McapError;

use super::fixed::{Fields, Fixed};
use super::writer::McapWriter;
use super::{channel_name, json, schema, McapEncoding, McapOptions, McapSkipped, McapWriteError};
use crate::definitions::timestamp::Unwrapper;
use crate::framing::{Framer, Record};
use crate::log::message::Message;
use crate::pass::visit::{Hand, Visit};
use crate::{DataRecord, Value};

/// A subscription as the pass meets it.
pub(super) enum Slot {
    Unseen,
    /// Not among the topics asked for, or cannot be written.
    Left,
    Open(Box<Channel>),
    /// A second subscription of a topic instance: written to the first one's channel.
    Same(usize),
}

pub(super) struct Channel {
    pub(super) id: u16,
    pub(super) topic: String,
    pub(super) multi_id: u8,
    pub(super) channel: String,
    pub(super) schema: String,
    pub(super) plan: Vec<schema::Step>,
    /// The layout, for JSON messages.
    pub(super) layout: std::sync::Arc<ulog_format::Layout>,
    pub(super) messages: u64,
}

pub(super) struct Visitor<'o, W: Write + Seek> {
    pub(super) writer: McapWriter<W>,
    pub(super) options: &'o McapOptions,
    pub(super) slots: Vec<Slot>,
    /// Each subscription's timestamps, unwrapped (version 0's narrow ones wrap).
    pub(super) clocks: Vec<Option<Unwrapper>>,
    /// The parameters as they stand, until the window starts: the values written
    /// as the initial ones (changes before the window folded in).
    pub(super) held_params: Option<Vec<(String, f64)>>,
    /// The subscriptions with a channel, in the order met.
    pub(super) channels: Vec<usize>,
    pub(super) skipped: Vec<McapSkipped>,
    pub(super) error: Option<McapError>,
    pub(super) buf: Vec<u8>,
    /// The latest timestamp met (microseconds since boot).
    pub(super) last: u64,
    /// The header's timestamp, once framed.
    pub(super) start: Option<u64>,
    pub(super) rosout: Option<u16>,
    pub(super) params: Option<u16>,
    pub(super) logged: u64,
    pub(super) parameters: u64,
    pub(super) short_messages: u64,
    pub(super) info: BTreeMap<String, String>,
    pub(super) multi: BTreeMap<String, Vec<String>>,
    pub(super) dropouts: (u64, u64),
    pub(super) time_range: Option<(u64, u64)>,
    /// The first subscription of each topic instance met (a second subscription of
    /// one writes to the same channel).
    pub(super) seen: std::collections::HashMap<(String, u8), usize>,
}

impl<W: Write + Seek> Visitor<'_, W> {
    /// Nanoseconds of the file's time for timestamp `t` (microseconds since boot).
    fn nanos(&self, t: u64) -> u64 {
        match &self.options.utc {
            Some(clock) => (clock.at(t).micros().max(0) as u64).saturating_mul(1000),
            None => t.saturating_mul(1000),
        }
    }

    /// The log time (when it was recorded) and the publish time (its own timestamp)
    /// of a message stamped `t`, in nanoseconds: with the log's span, a message made
    /// before logging began was recorded at the start, a stray one at the end.
    fn times(&self, t: u64) -> (u64, u64) {
        let recorded = match &self.options.span {
            Some(span) => span.recorded_at(t),
            None => t,
        };
        (self.nanos(recorded), self.nanos(t))
    }

    pub(super) fn metadata(
        &mut self,
        name: &str,
        metadata: BTreeMap<String, String>,
    ) -> Result<(), McapWriteError> {
        self.writer
            .write_metadata(&Metadata {
                name: name.to_owned(),
                metadata,
            })
            .map_err(McapWriteError::Write)
    }

    fn open(&mut self, sub: &crate::definitions::Subscription) -> Slot {
        if let Some(names) = &self.options.topics {
            if !names.iter().any(|n| n == sub.name()) {
                return Slot::Left;
            }
        }
        let layout = match sub.layout() {
            Ok(l) => l,
            Err(e) => {
                self.skipped.push(McapSkipped {
                    topic: sub.name().to_owned(),
                    multi_id: sub.multi_id(),
                    reason: e.to_string(),
                });
                return Slot::Left;
            }
        };
        let type_name = format!(
            "{}/msg/{}",
            schema::PACKAGE,
            schema::type_name(layout.name())
        );
        let (text, schema_encoding, message_encoding) = match self.options.encoding {
            McapEncoding::Ros2 => (schema::ros2msg(layout), "ros2msg", "cdr"),
            McapEncoding::Json => (json::json_schema(layout, &type_name), "jsonschema", "json"),
        };
        let channel = channel_name(sub.name(), sub.multi_id());
        let formats: Vec<String> = layout.formats().iter().map(|f| f.to_string()).collect();
        let metadata = BTreeMap::from([
            ("ulog.topic".to_owned(), sub.name().to_owned()),
            ("ulog.multi_id".to_owned(), sub.multi_id().to_string()),
            ("ulog.format".to_owned(), formats.join("\n")),
        ]);
        let id = self
            .writer
            .add_schema(&type_name, schema_encoding, text.as_bytes())
            .and_then(|schema| {
                self.writer
                    .add_channel(schema, &channel, message_encoding, &metadata)
            });
        match id {
            Ok(id) => Slot::Open(Box::new(Channel {
                id,
                topic: sub.name().to_owned(),
                multi_id: sub.multi_id(),
                channel,
                schema: type_name,
                plan: schema::cdr_plan(layout),
                layout: layout.clone(),

                messages: 0,
            })),
            Err(e) => {
                self.error.get_or_insert(e);
                Slot::Left
            }
        }
    }

    fn write(&mut self, channel: u16, sequence: u32, t: u64) -> Result<(), McapError> {
        let (log_time, publish_time) = self.times(t);
        self.time_range = widen(self.time_range, log_time);
        self.writer.write_to_known_channel(
            &MessageHeader {
                channel_id: channel,
                sequence,
                log_time,
                publish_time,
            },
            &self.buf,
        )
    }

    /// The channel of `/rosout` or `/ulog/parameters`, added when first needed.
    fn fixed_channel(&mut self, which: Fixed) -> Result<u16, McapError> {
        let slot = match which {
            Fixed::Rosout => &mut self.rosout,
            Fixed::Parameters => &mut self.params,
        };
        if let Some(id) = *slot {
            return Ok(id);
        }
        let (name, channel, ros2msg, jsonschema) = which.schemas();
        let (schema, encoding, message_encoding) = match self.options.encoding {
            McapEncoding::Ros2 => (ros2msg, "ros2msg", "cdr"),
            McapEncoding::Json => (jsonschema, "jsonschema", "json"),
        };
        let schema = self.writer.add_schema(name, encoding, schema.as_bytes())?;
        let id = self
            .writer
            .add_channel(schema, channel, message_encoding, &BTreeMap::new())?;
        match which {
            Fixed::Rosout => self.rosout = Some(id),
            Fixed::Parameters => self.params = Some(id),
        }
        Ok(id)
    }

    fn logged(&mut self, level: u8, tag: Option<u16>, t: u64, text: &str) -> Result<(), McapError> {
        if !self.options.contains(t) {
            return Ok(());
        }
        let id = self.fixed_channel(Fixed::Rosout)?;
        let ros_level = match level {
            b'0'..=b'2' => 50,
            b'3' => 40,
            b'4' => 30,
            b'7' => 10,
            _ => 20,
        };
        let name = match tag {
            Some(tag) => format!("ulog/tag_{tag}"),
            None => "ulog".to_owned(),
        };
        let time = self.nanos(t);
        let mut m = Fields::new(self.options.encoding, std::mem::take(&mut self.buf));
        m.stamp("stamp", time);
        m.u8("level", ros_level);
        m.string("name", &name);
        m.string("msg", text);
        m.string("file", "");
        m.string("function", "");
        m.u32("line", 0);
        self.buf = m.finish();
        self.logged += 1;
        self.write(id, self.logged as u32, t)
    }

    /// An initial value, held until the window starts, or a change at `t`: folded
    /// into the values held when before the window's start, else written as a change
    /// (after the initial values).
    fn parameter(
        &mut self,
        name: String,
        value: f64,
        t: u64,
        initial: bool,
    ) -> Result<(), McapError> {
        let before = self.options.start_us.is_some_and(|s| t < s);
        if let (Some(held), true) = (&mut self.held_params, initial || before) {
            match held.iter_mut().find(|(n, _)| *n == name) {
                Some(p) => p.1 = value,
                None => held.push((name, value)),
            }
            return Ok(());
        }
        self.release_params()?;
        if !self.options.contains(t) {
            return Ok(());
        }
        self.write_parameter(&name, value, t, false)
    }

    /// Writes the initial values (as they stand at the window's start), once.
    pub(super) fn release_params(&mut self) -> Result<(), McapError> {
        let Some(held) = self.held_params.take() else {
            return Ok(());
        };
        let log_start = match &self.options.span {
            Some(span) => span.start(),
            None => self.start.unwrap_or(0),
        };
        let start = self.options.start_us.unwrap_or(0).max(log_start);
        for (name, value) in held {
            self.write_parameter(&name, value, start, true)?;
        }
        Ok(())
    }

    fn write_parameter(
        &mut self,
        name: &str,
        value: f64,
        t: u64,
        initial: bool,
    ) -> Result<(), McapError> {
        let id = self.fixed_channel(Fixed::Parameters)?;
        let time = self.nanos(t);
        let mut m = Fields::new(self.options.encoding, std::mem::take(&mut self.buf));
        m.stamp("stamp", time);
        m.string("name", name);
        m.f64("value", value);
        m.bool("initial", initial);
        self.buf = m.finish();
        self.parameters += 1;
        self.write(id, self.parameters as u32, t)
    }

    fn other_message(
        &mut self,
        r: &Record,
        payload: &[u8],
        framer: &Framer,
    ) -> Result<(), McapError> {
        if self.start.is_none() {
            if let Some(h) = framer.header {
                self.start = Some(h.timestamp);
                self.last = h.timestamp;
            }
        }
        let start = self.start.unwrap_or(0);
        match Message::from_record(r, payload, framer.flag_bits) {
            Message::Info(kv) => {
                self.info
                    .insert(kv.name().into_owned(), value_text(&kv.value()));
            }
            Message::MultiInfo { continued, kv } => {
                let parts = self.multi.entry(kv.name().into_owned()).or_default();
                let text = value_text(&kv.value());
                match (continued, parts.last_mut()) {
                    (true, Some(last)) => last.push_str(&text),
                    _ => parts.push(text),
                }
            }
            Message::Param(kv) => {
                let value = kv.value().as_f64().unwrap_or(f64::NAN);
                let (t, initial) = match framer.in_definitions {
                    true => (start, true),
                    false => (self.last, false),
                };
                self.parameter(kv.name().into_owned(), value, t, initial)?;
            }
            Message::Log(l) => {
                let text = l.text.to_string_lossy();
                self.logged(l.raw_level, l.tag, l.timestamp, &text)?;
            }
            Message::Dropout { duration_ms } => {
                self.dropouts.0 += 1;
                self.dropouts.1 += u64::from(duration_ms);
            }
            _ => {}
        }
        Ok(())
    }
}

impl<W: Write + Seek> Visit for Visitor<'_, W> {
    fn data(&mut self, r: DataRecord<'_>) -> Hand {
        let i = r.topic.index();
        if self.slots.len() <= i {
            self.slots.resize_with(i + 1, || Slot::Unseen);
            self.clocks.resize_with(i + 1, || None);
        }
        // Every topic's time counts for the times of parameter changes (the latest
        // timestamp before them, as the parsed log gives them), written or not.
        let clock = self.clocks[i].get_or_insert_with(|| Unwrapper::new(r.topic.timestamp_field()));
        let time = clock.push(r.payload);
        let t = time.unwrap_or(self.last);
        self.last = self.last.max(t);
        if matches!(self.slots[i], Slot::Unseen) {
            let key = (r.topic.name().to_owned(), r.topic.multi_id());
            self.slots[i] = match self.seen.get(&key) {
                Some(&first) => Slot::Same(first),
                None => {
                    self.seen.insert(key, i);
                    let slot = self.open(r.topic);
                    if matches!(slot, Slot::Open(_)) {
                        self.channels.push(i);
                    }
                    slot
                }
            };
            if self.error.is_some() {
                return Hand::Stop;
            }
        }
        let i = match self.slots[i] {
            Slot::Same(first) => first,
            _ => i,
        };
        if !matches!(self.slots[i], Slot::Open(_)) || !self.options.contains(t) {
            return Hand::Next;
        }
        let (log_time, publish_time) = self.times(t);
        let Slot::Open(c) = &mut self.slots[i] else {
            return Hand::Next;
        };
        let header = MessageHeader {
            channel_id: c.id,
            sequence: (c.messages + 1) as u32,
            log_time,
            publish_time,
        };
        let written = match self.options.encoding {
            McapEncoding::Ros2 => {
                let plan = &c.plan;
                self.writer.write_with(&header, |out| {
                    schema::encode(plan, r.payload, out).is_some()
                })
            }
            McapEncoding::Json => match json::encode_json(&c.layout, r.payload, &mut self.buf) {
                Some(()) => self
                    .writer
                    .write_to_known_channel(&header, &self.buf)
                    .map(|()| true),
                None => Ok(false),
            },
        };
        match written {
            Ok(true) => {
                c.messages += 1;
                self.time_range = widen(self.time_range, log_time);
                Hand::Next
            }
            Ok(false) => {
                self.short_messages += 1;
                Hand::Next
            }
            Err(e) => {
                self.error = Some(e);
                Hand::Stop
            }
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

/// `range` grown to hold `time`.
fn widen(range: Option<(u64, u64)>, time: u64) -> Option<(u64, u64)> {
    Some(range.map_or((time, time), |(a, b)| (a.min(time), b.max(time))))
}

/// A value as metadata text: strings as they are, numbers as Rust prints them.
fn value_text(v: &Value<'_>) -> String {
    match v {
        Value::Str(s) => s.to_string_lossy().into_owned(),
        other => other.to_string(),
    }
}
