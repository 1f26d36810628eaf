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
//! - Each message's publish time is its `timestamp` in nanoseconds: since boot, or,
//!   with [`McapOptions::utc`], since the Unix epoch. Its log time (when it was
//!   recorded) is the same, but that with [`McapOptions::span`] (the log's
//!   [`TimeSpan`]) a message made before logging began (or never stamped) counts as
//!   recorded at the log's start, and a stray one (far beyond the rows around it) at
//!   its end ([`TimeSpan::recorded_at`]), so that the file's time range is the
//!   flight's.
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
//! Memory is that of a few chunks (1 MiB by default; the one being filled and up to
//! two per compression thread) and the log's definitions, whatever the size of the
//! log.
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

mod fixed;
mod json;
mod schema;
mod visit;
mod writer;

use std::collections::BTreeMap;
use std::io::{Seek, Write};

use ::mcap::WriteOptions;

use self::visit::{Slot, Visitor};
use self::writer::McapWriter;
use crate::error::ReadError;
use crate::finding::Finding;
use crate::log::span::TimeSpan;
use crate::log::utc::UtcClock;
use crate::pass::source::{drive, Source};

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
    /// per byte, ISO 8859-1; control characters as `\uXXXX`), floats in their shortest
    /// round-trip form and `null` for NaN and infinities. The schema names and
    /// channels are those of `Ros2`.
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
    /// The log's span ([`ULog::span`](crate::ULog::span), or
    /// [`LogMetadata::span`](crate::read::LogMetadata::span) of a pass): messages'
    /// log times are placed on it (see the [module docs](self)). `None`: every log
    /// time is the message's timestamp.
    pub span: Option<TimeSpan>,
    /// Uncompressed bytes per chunk; at least 1.
    pub chunk_bytes: u64,
    /// Chunks compressed with zstd (level −1); `false` writes them as they are
    /// (faster, about twice as large).
    pub zstd: bool,
}

impl McapOptions {
    /// Whether timestamp `t` is in the window.
    pub(super) fn contains(&self, t: u64) -> bool {
        self.start_us.map_or(true, |s| t >= s) && self.end_us.map_or(true, |e| t <= e)
    }
}

impl Default for McapOptions {
    fn default() -> McapOptions {
        McapOptions {
            encoding: McapEncoding::Ros2,
            topics: None,
            start_us: None,
            end_us: None,
            utc: None,
            span: None,
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
    // Level −1 (the first of zstd's fast levels): compression is the larger half of
    // the work. On the ≈300 MB logs it takes 9% less CPU than level 1 for files 3% larger
    // (log61 ×90: 297 MB against 287 MB; events ×200: 243 MB against 237 MB; level 3
    // gives 231 MB on events): what keeps the export as fast as CSV's (BENCHMARKS.md).
    let writer = McapWriter::create(
        out,
        profile,
        concat!("ulog-core ", env!("CARGO_PKG_VERSION")),
        options.chunk_bytes.max(1),
        options.zstd.then_some(-1),
    )
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
    if let Some(span) = &options.span {
        file.insert("span_start_us".to_owned(), span.start().to_string());
        file.insert("span_end_us".to_owned(), span.end().to_string());
    }
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
