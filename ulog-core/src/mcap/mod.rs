//! MCAP files of a log, for ROS 2 and Foxglove tools (feature `mcap`): one pass over
//! the log in file order, its data messages written as ROS 2 messages in CDR with
//! schemas made from the log's own formats, so that a bag needs no ROS install to
//! write and no `px4_msgs` to read.
//!
//! What goes where:
//!
//! - Each topic instance with data is a channel, named as PX4's ROS 2 bridge names
//!   topics: `/fmu/out/<topic>`, and `/fmu/out/<topic>_<N>` for instance N ≥ 1
//!   (characters a ROS 2 name cannot hold become `_`). Its schema is `ros2msg`, named
//!   `px4_msgs/msg/<Format>` as `px4_msgs` names PX4's messages (`vehicle_gps_position`
//!   → `VehicleGpsPosition`); nested formats are message types of their own in the
//!   schema text, arrays fixed arrays, `char[N]` `uint8[N]` (as PX4's ROS 2 messages
//!   declare them), padding left out. Field names keep the log's where ROS 2 allows
//!   them (see `field_name` in the source for the mapping of others). Channel
//!   metadata: `ulog.topic`, `ulog.multi_id`, `ulog.format` (the format text).
//! - Each message's log and publish time is its `timestamp` in nanoseconds: since
//!   boot, or, with [`McapOptions::utc`], since the Unix epoch.
//! - Logged and tagged strings are `rcl_interfaces/msg/Log` on `/rosout` (ROS levels:
//!   EMERG/ALERT/CRIT → FATAL, ERR → ERROR, WARNING → WARN, NOTICE/INFO → INFO, DEBUG
//!   → DEBUG; `name` is `ulog`, or `ulog/tag_<N>` for tagged ones).
//! - Parameters are `ulog_msgs/msg/Parameter` (`stamp`, `name`, `value` as float64,
//!   `initial`) on `/ulog/parameters`: the initial values at the log's start, each
//!   change at the time of the data before it (as [`ULog::param_changes`] times them).
//! - Information (`ulog_info`), multi-information (`ulog_multi_info`, the parts of a
//!   key joined, repeated keys numbered `key#2`…), and what the reader found
//!   (`ulog_findings`: byte offset → text; `ulog_dropouts`) are MCAP metadata records.
//!
//! Memory is that of a chunk (1 MiB by default) and the log's definitions, whatever
//! the size of the log.
//!
//! ```
//! use ulog_core::mcap::{write_mcap, McapOptions};
//! let bytes = ulog_core::testing::sample_log();
//! let mut out = std::io::Cursor::new(Vec::new());
//! let summary = write_mcap(&bytes, &mut out, &McapOptions::default())?;
//! let esc = summary.channels.iter().find(|c| c.topic == "esc_status").unwrap();
//! assert_eq!(esc.channel, "/fmu/out/esc_status");
//! assert_eq!(esc.schema, "px4_msgs/msg/EscStatus");
//! assert_eq!(esc.messages, 20);
//! assert!(out.get_ref().starts_with(b"\x89MCAP0\r\n"));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! [`ULog::param_changes`]: crate::ULog::param_changes

mod json;
mod schema;

use std::collections::BTreeMap;
use std::io::{Seek, Write};

use ::mcap::records::{MessageHeader, Metadata};
use ::mcap::{Compression, WriteOptions, Writer};

use crate::definitions::timestamp::Unwrapper;
use crate::error::ReadError;
use crate::finding::Finding;
use crate::framing::{Framer, Record};
use crate::log::message::Message;
use crate::log::utc::UtcClock;
use crate::pass::driver::{Hand, Visit};
use crate::pass::source::{drive, Source};
use crate::{DataRecord, Value};

pub use ::mcap::McapError;

/// How messages are encoded.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum McapEncoding {
    /// ROS 2: CDR messages, `ros2msg` schemas, profile `ros2` (the default).
    #[default]
    Ros2,
    /// JSON messages with `jsonschema` schemas, for tools without CDR: each message
    /// an object of its fields by their names in the log, arrays as arrays, nested
    /// formats as objects, `char[N]` as the text up to its first NUL (one character
    /// per byte, ISO 8859-1), floats in their shortest round-trip form and `null` for
    /// NaN and infinities. The schema names and channels are those of `Ros2`.
    Json,
}

/// What to write, and how.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct McapOptions {
    /// How messages are encoded.
    pub encoding: McapEncoding,
    /// Only these topics (every instance of each); `None`: every topic. Names the log
    /// does not have are listed in [`McapSummary::missing_topics`].
    pub topics: Option<Vec<String>>,
    /// Only messages at or after this timestamp (microseconds since boot).
    pub start_us: Option<u64>,
    /// Only messages at or before this timestamp (microseconds since boot).
    pub end_us: Option<u64>,
    /// Times in UTC by this clock ([`ULog::utc`](crate::ULog::utc)) instead of since
    /// boot.
    pub utc: Option<UtcClock>,
    /// Uncompressed bytes per chunk; at least 1.
    pub chunk_bytes: u64,
    /// Chunks compressed with zstd (level 1); `false` writes them as they are
    /// (faster, some 2.4 times larger).
    pub zstd: bool,
}

impl Default for McapOptions {
    fn default() -> McapOptions {
        McapOptions {
            encoding: McapEncoding::Ros2,
            topics: None,
            start_us: None,
            end_us: None,
            utc: None,
            chunk_bytes: WriteOptions::DEFAULT_CHUNK_SIZE,
            zstd: true,
        }
    }
}

/// One channel written.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ChannelSummary {
    /// The topic.
    pub topic: String,
    /// Its instance.
    pub multi_id: u8,
    /// The channel's (ROS 2 topic's) name.
    pub channel: String,
    /// The schema's (message type's) name.
    pub schema: String,
    /// Messages written.
    pub messages: u64,
}

/// A topic instance not written, and why.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct McapSkipped {
    /// The topic.
    pub topic: String,
    /// Its instance.
    pub multi_id: u8,
    /// Why.
    pub reason: String,
}

/// What [`write_mcap`] wrote.
#[derive(Debug, Clone, PartialEq)]
pub struct McapSummary {
    /// The data channels, in the order first met.
    pub channels: Vec<ChannelSummary>,
    /// Topic instances left out: their formats do not lay out.
    pub skipped: Vec<McapSkipped>,
    /// Names of [`McapOptions::topics`] that the log does not have.
    pub missing_topics: Vec<String>,
    /// Logged and tagged strings written to `/rosout`.
    pub logged: u64,
    /// Parameter values written (initial and changes).
    pub parameters: u64,
    /// Data messages shorter than their format, left out.
    pub short_messages: u64,
    /// The earliest and the latest log time written (nanoseconds), if any message was.
    pub time_range: Option<(u64, u64)>,
    /// What the reader found and stepped over (also in the file's metadata).
    pub findings: Vec<Finding>,
}

/// Why [`write_mcap`] failed.
#[derive(Debug)]
#[non_exhaustive]
pub enum McapWriteError {
    /// The log could not be read.
    Read(ReadError),
    /// The MCAP file could not be written.
    Write(McapError),
}

impl std::fmt::Display for McapWriteError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            McapWriteError::Read(e) => write!(f, "reading the log: {e}"),
            McapWriteError::Write(e) => write!(f, "writing MCAP: {e}"),
        }
    }
}

impl std::error::Error for McapWriteError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            McapWriteError::Read(e) => Some(e),
            McapWriteError::Write(e) => Some(e),
        }
    }
}

/// The `/rosout` message type, with the `Time` it uses.
const LOG_SCHEMA: &str = "uint8 DEBUG=10\nuint8 INFO=20\nuint8 WARN=30\nuint8 ERROR=40\n\
uint8 FATAL=50\nbuiltin_interfaces/Time stamp\nuint8 level\nstring name\nstring msg\n\
string file\nstring function\nuint32 line\n\
================================================================================\n\
MSG: builtin_interfaces/Time\nint32 sec\nuint32 nanosec\n";

/// The JSON Schema of `/rosout` messages in JSON.
const LOG_JSON_SCHEMA: &str = r#"{"$schema":"https://json-schema.org/draft/2020-12/schema","title":"rcl_interfaces/msg/Log","type":"object","properties":{"stamp":{"type":"object","properties":{"sec":{"type":"integer"},"nanosec":{"type":"integer"}},"required":["sec","nanosec"]},"level":{"type":"integer"},"name":{"type":"string"},"msg":{"type":"string"},"file":{"type":"string"},"function":{"type":"string"},"line":{"type":"integer"}},"required":["stamp","level","name","msg","file","function","line"],"additionalProperties":false}"#;

/// The JSON Schema of `/ulog/parameters` messages in JSON.
const PARAMETER_JSON_SCHEMA: &str = r#"{"$schema":"https://json-schema.org/draft/2020-12/schema","title":"ulog_msgs/msg/Parameter","type":"object","properties":{"stamp":{"type":"object","properties":{"sec":{"type":"integer"},"nanosec":{"type":"integer"}},"required":["sec","nanosec"]},"name":{"type":"string"},"value":{"type":["number","null"]},"initial":{"type":"boolean"}},"required":["stamp","name","value","initial"],"additionalProperties":false}"#;

/// The parameter message type of `/ulog/parameters`.
const PARAMETER_SCHEMA: &str = "builtin_interfaces/Time stamp\nstring name\nfloat64 value\n\
bool initial\n\
================================================================================\n\
MSG: builtin_interfaces/Time\nint32 sec\nuint32 nanosec\n";

/// Writes the log of `source` to `out` as an MCAP file (see the [module docs](self)).
pub fn write_mcap<'s, W: Write + Seek>(
    source: impl Into<Source<'s>>,
    out: W,
    options: &McapOptions,
) -> Result<McapSummary, McapWriteError> {
    let profile = match options.encoding {
        McapEncoding::Ros2 => "ros2",
        McapEncoding::Json => "",
    };
    let writer = WriteOptions::new()
        .profile(profile)
        .library(concat!("ulog-core ", env!("CARGO_PKG_VERSION")))
        .compression(options.zstd.then_some(Compression::Zstd))
        .chunk_size(Some(options.chunk_bytes.max(1)))
        // Level 1 on the writing thread: on a 295 MB log, 2.98 s (237 MB) against
        // 3.34 s (231 MB) at zstd's default level 3, and 3.53 s with zstd's two
        // worker threads, which lock for each of the small writes the crate makes
        // (one per record part).
        .compression_level(1)
        .compression_threads(0)
        .create(out)
        .map_err(McapWriteError::Write)?;
    let mut v = Visitor {
        writer,
        options,
        slots: Vec::new(),
        clocks: Vec::new(),
        held_params: Some(Vec::new()),
        channels: Vec::new(),
        skipped: Vec::new(),
        error: None,
        buf: Vec::with_capacity(1024),
        last: 0,
        start: None,
        rosout: None,
        params: None,
        logged: 0,
        parameters: 0,
        short_messages: 0,
        info: BTreeMap::new(),
        multi: BTreeMap::new(),
        dropouts: (0, 0),
        time_range: None,
        seen: std::collections::HashMap::new(),
    };
    let summary = drive(source.into(), true, &mut v);
    if v.error.is_none() {
        if let Err(e) = v.release_params() {
            v.error = Some(e);
        }
    }
    if let Some(e) = v.error.take() {
        return Err(McapWriteError::Write(e));
    }
    let summary = summary.map_err(McapWriteError::Read)?;
    let info = std::mem::take(&mut v.info);
    v.metadata("ulog_info", info)?;
    let multi = std::mem::take(&mut v.multi)
        .into_iter()
        .flat_map(|(key, parts)| {
            let n = parts.len();
            parts.into_iter().enumerate().map(move |(i, text)| {
                let key = if n > 1 {
                    format!("{key}#{}", i + 1)
                } else {
                    key.clone()
                };
                (key, text)
            })
        })
        .collect();
    v.metadata("ulog_multi_info", multi)?;
    let findings: BTreeMap<String, String> = summary
        .findings
        .iter()
        .map(|f| (format!("{:012}", f.offset), f.what()))
        .collect();
    v.metadata("ulog_findings", findings)?;
    let (count, total) = v.dropouts;
    v.metadata(
        "ulog_dropouts",
        BTreeMap::from([
            ("count".to_owned(), count.to_string()),
            ("total_ms".to_owned(), total.to_string()),
        ]),
    )?;
    let mut file = BTreeMap::from([
        ("version".to_owned(), summary.header.version.to_string()),
        (
            "start_timestamp_us".to_owned(),
            summary.header.timestamp.to_string(),
        ),
        ("time".to_owned(), "boot".to_owned()),
    ]);
    if let Some(clock) = &options.utc {
        file.insert("time".to_owned(), "utc".to_owned());
        file.insert("utc_source".to_owned(), clock.source().to_string());
    }
    v.metadata("ulog_file", file)?;
    v.writer.finish().map_err(McapWriteError::Write)?;
    let missing_topics = match &options.topics {
        Some(names) => names
            .iter()
            .filter(|n| summary.topics.iter().all(|t| t.name() != n.as_str()))
            .cloned()
            .collect(),
        None => Vec::new(),
    };
    let channels = v
        .channels
        .iter()
        .filter_map(|&i| match &v.slots[i] {
            Slot::Open(c) => Some(ChannelSummary {
                topic: c.topic.clone(),
                multi_id: c.multi_id,
                channel: c.channel.clone(),
                schema: c.schema.clone(),
                messages: c.messages,
            }),
            _ => None,
        })
        .collect();
    Ok(McapSummary {
        channels,
        skipped: v.skipped,
        missing_topics,
        logged: v.logged,
        parameters: v.parameters,
        short_messages: v.short_messages,
        time_range: v.time_range,
        findings: summary.findings,
    })
}

impl McapSummary {
    /// Messages written on every channel: data, `/rosout` and parameters.
    pub fn messages(&self) -> u64 {
        self.channels.iter().map(|c| c.messages).sum::<u64>() + self.logged + self.parameters
    }

    /// The `metadata.yaml` of a ROS 2 bag (rosbag2 format version 5, storage `mcap`)
    /// whose one file, `file_name` beside it, is the MCAP file this summary is of:
    /// with it, `ros2 bag info` and `ros2 bag play` take the folder. For a file of
    /// CDR messages ([`McapEncoding::Ros2`]): a bag's messages are CDR.
    pub fn rosbag2_metadata(&self, file_name: &str) -> String {
        let (start, end) = self.time_range.unwrap_or((0, 0));
        let duration = end - start;
        let mut topics: Vec<(String, &str, u64)> = self
            .channels
            .iter()
            .map(|c| (c.channel.clone(), c.schema.as_str(), c.messages))
            .collect();
        if self.logged > 0 {
            topics.push(("/rosout".into(), "rcl_interfaces/msg/Log", self.logged));
        }
        if self.parameters > 0 {
            topics.push((
                "/ulog/parameters".into(),
                "ulog_msgs/msg/Parameter",
                self.parameters,
            ));
        }
        // Strings as JSON strings, which YAML reads as they are.
        let quote = |s: &str| format!("{s:?}");
        let mut y = String::from(
            "rosbag2_bagfile_information:\n  version: 5\n  storage_identifier: mcap\n",
        );
        y.push_str(&format!("  duration:\n    nanoseconds: {duration}\n"));
        y.push_str(&format!(
            "  starting_time:\n    nanoseconds_since_epoch: {start}\n"
        ));
        y.push_str(&format!("  message_count: {}\n", self.messages()));
        y.push_str("  topics_with_message_count:\n");
        for (name, ty, count) in &topics {
            y.push_str(&format!(
                "    - topic_metadata:\n        name: {}\n        type: {}\n        \
                 serialization_format: cdr\n        offered_qos_profiles: \"\"\n      \
                 message_count: {count}\n",
                quote(name),
                quote(ty)
            ));
        }
        y.push_str("  compression_format: \"\"\n  compression_mode: \"\"\n");
        y.push_str(&format!(
            "  relative_file_paths:\n    - {}\n",
            quote(file_name)
        ));
        y.push_str(&format!(
            "  files:\n    - path: {}\n      starting_time:\n        nanoseconds_since_epoch: \
             {start}\n      duration:\n        nanoseconds: {duration}\n      message_count: {}\n",
            quote(file_name),
            self.messages()
        ));
        y
    }
}

/// A subscription as the pass meets it.
enum Slot {
    Unseen,
    /// Not among the topics asked for, or cannot be written.
    Left,
    Open(Box<Channel>),
    /// A second subscription of a topic instance: written to the first one's channel.
    Same(usize),
}

struct Channel {
    id: u16,
    topic: String,
    multi_id: u8,
    channel: String,
    schema: String,
    plan: Vec<schema::Step>,
    /// The layout, for JSON messages.
    layout: std::sync::Arc<ulog_format::Layout>,
    messages: u64,
}

struct Visitor<'o, W: Write + Seek> {
    writer: Writer<W>,
    options: &'o McapOptions,
    slots: Vec<Slot>,
    /// Each subscription's timestamps, unwrapped (version 0's narrow ones wrap).
    clocks: Vec<Option<Unwrapper>>,
    /// The parameters as they stand, until the window starts: the values written
    /// as the initial ones (changes before the window folded in).
    held_params: Option<Vec<(String, f64)>>,
    /// The subscriptions with a channel, in the order met.
    channels: Vec<usize>,
    skipped: Vec<McapSkipped>,
    error: Option<McapError>,
    buf: Vec<u8>,
    /// The latest timestamp met (microseconds since boot).
    last: u64,
    /// The header's timestamp, once framed.
    start: Option<u64>,
    rosout: Option<u16>,
    params: Option<u16>,
    logged: u64,
    parameters: u64,
    short_messages: u64,
    info: BTreeMap<String, String>,
    multi: BTreeMap<String, Vec<String>>,
    dropouts: (u64, u64),
    time_range: Option<(u64, u64)>,
    /// The first subscription of each topic instance met (a second subscription of
    /// one writes to the same channel).
    seen: std::collections::HashMap<(String, u8), usize>,
}

impl<W: Write + Seek> Visitor<'_, W> {
    /// Nanoseconds of the file's time for timestamp `t` (microseconds since boot).
    fn nanos(&self, t: u64) -> u64 {
        match &self.options.utc {
            Some(clock) => (clock.at(t).micros().max(0) as u64).saturating_mul(1000),
            None => t.saturating_mul(1000),
        }
    }

    fn inside(&self, t: u64) -> bool {
        inside(self.options, t)
    }

    fn metadata(
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
        let time = self.nanos(t);
        self.time_range = Some(match self.time_range {
            Some((a, b)) => (a.min(time), b.max(time)),
            None => (time, time),
        });
        self.writer.write_to_known_channel(
            &MessageHeader {
                channel_id: channel,
                sequence,
                log_time: time,
                publish_time: time,
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
        let (name, channel, ros2msg, jsonschema) = match which {
            Fixed::Rosout => (
                "rcl_interfaces/msg/Log",
                "/rosout",
                LOG_SCHEMA,
                LOG_JSON_SCHEMA,
            ),
            Fixed::Parameters => (
                "ulog_msgs/msg/Parameter",
                "/ulog/parameters",
                PARAMETER_SCHEMA,
                PARAMETER_JSON_SCHEMA,
            ),
        };
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
        if !self.inside(t) {
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
        if !self.inside(t) {
            return Ok(());
        }
        self.write_parameter(&name, value, t, false)
    }

    /// Writes the initial values (as they stand at the window's start), once.
    fn release_params(&mut self) -> Result<(), McapError> {
        let Some(held) = self.held_params.take() else {
            return Ok(());
        };
        let start = self
            .options
            .start_us
            .unwrap_or(0)
            .max(self.start.unwrap_or(0));
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
        let Slot::Open(c) = &mut self.slots[i] else {
            return Hand::Next;
        };
        if !inside(self.options, t) {
            return Hand::Next;
        }
        let encoded = match self.options.encoding {
            McapEncoding::Ros2 => schema::encode(&c.plan, r.payload, &mut self.buf),
            McapEncoding::Json => json::encode_json(&c.layout, r.payload, &mut self.buf),
        };
        if encoded.is_none() {
            self.short_messages += 1;
            return Hand::Next;
        }
        c.messages += 1;
        let (id, sequence) = (c.id, c.messages as u32);
        match self.write(id, sequence, t) {
            Ok(()) => Hand::Next,
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

/// Whether timestamp `t` is in the window of `options`.
fn inside(options: &McapOptions, t: u64) -> bool {
    options.start_us.map_or(true, |s| t >= s) && options.end_us.map_or(true, |e| t <= e)
}

/// A value as metadata text: strings as they are, numbers as Rust prints them.
fn value_text(v: &Value<'_>) -> String {
    match v {
        Value::Str(s) => s.to_string_lossy().into_owned(),
        other => other.to_string(),
    }
}

/// The channel of a topic instance: `/fmu/out/<topic>`, `_<N>` after it for instance
/// N ≥ 1; characters other than ASCII letters, digits and `_` become `_`.
pub fn channel_name(topic: &str, multi_id: u8) -> String {
    let mut name: String = topic
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect();
    if !name.starts_with(|c: char| c.is_ascii_alphabetic()) {
        name.insert(0, 't');
    }
    if multi_id > 0 {
        name.push_str(&format!("_{multi_id}"));
    }
    format!("/fmu/out/{name}")
}

/// The two channels that are not topics.
#[derive(Clone, Copy)]
enum Fixed {
    Rosout,
    Parameters,
}

/// A message of `/rosout` or `/ulog/parameters` being written: little-endian CDR
/// (aligned from after its header), or a JSON object.
struct Fields {
    json: bool,
    out: Vec<u8>,
}

impl Fields {
    fn new(encoding: McapEncoding, mut out: Vec<u8>) -> Fields {
        out.clear();
        let json = encoding == McapEncoding::Json;
        if json {
            out.push(b'{');
        } else {
            out.extend_from_slice(&[0, 1, 0, 0]);
        }
        Fields { json, out }
    }

    fn finish(mut self) -> Vec<u8> {
        if self.json {
            self.out.push(b'}');
        }
        self.out
    }

    /// Starts a JSON member; `true` for CDR, which writes the value itself.
    fn key(&mut self, name: &str) -> bool {
        if self.json {
            if self.out.len() > 1 {
                self.out.push(b',');
            }
            self.out
                .extend_from_slice(format!("\"{name}\":").as_bytes());
        }
        !self.json
    }

    fn align(&mut self, n: usize) {
        let pos = self.out.len() - 4;
        let pad = (n - pos % n) % n;
        self.out.resize(self.out.len() + pad, 0);
    }

    fn u8(&mut self, name: &str, v: u8) {
        if self.key(name) {
            self.out.push(v);
        } else {
            self.out.extend_from_slice(v.to_string().as_bytes());
        }
    }

    fn bool(&mut self, name: &str, v: bool) {
        if self.key(name) {
            self.out.push(u8::from(v));
        } else {
            self.out
                .extend_from_slice(if v { b"true" } else { b"false" });
        }
    }

    fn u32(&mut self, name: &str, v: u32) {
        if self.key(name) {
            self.align(4);
            self.out.extend_from_slice(&v.to_le_bytes());
        } else {
            self.out.extend_from_slice(v.to_string().as_bytes());
        }
    }

    fn f64(&mut self, name: &str, v: f64) {
        if self.key(name) {
            self.align(8);
            self.out.extend_from_slice(&v.to_le_bytes());
        } else if v.is_finite() {
            self.out.extend_from_slice(format!("{v:?}").as_bytes());
        } else {
            self.out.extend_from_slice(b"null");
        }
    }

    fn string(&mut self, name: &str, s: &str) {
        // A NUL would end the text for CDR readers: the text ends there.
        let s = s.split('\0').next().unwrap_or("");
        if self.key(name) {
            self.align(4);
            self.out
                .extend_from_slice(&(s.len() as u32 + 1).to_le_bytes());
            self.out.extend_from_slice(s.as_bytes());
            self.out.push(0);
        } else {
            let mut text = String::with_capacity(s.len() + 2);
            json::text(s.chars(), &mut text);
            self.out.extend_from_slice(text.as_bytes());
        }
    }

    /// A `builtin_interfaces/Time` of `nanos`.
    fn stamp(&mut self, name: &str, nanos: u64) {
        let secs = (nanos / 1_000_000_000).min(i32::MAX as u64) as u32;
        let rest = (nanos % 1_000_000_000) as u32;
        if self.key(name) {
            self.align(4);
            self.out.extend_from_slice(&secs.to_le_bytes());
            self.out.extend_from_slice(&rest.to_le_bytes());
        } else {
            self.out
                .extend_from_slice(format!("{{\"sec\":{secs},\"nanosec\":{rest}}}").as_bytes());
        }
    }
}
