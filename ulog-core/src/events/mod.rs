//! PX4 events (feature `events`): the `event` topic decoded with the event
//! definitions the log embeds, as PX4's events library and pyulog's `ulog_messages`
//! show them.
//!
//! Since v1.13, PX4 logs its important messages as events: an id, a log level and
//! up to 25 bytes of arguments, whose meaning (a name, a message template, argument
//! types) is in metadata that the log carries xz-compressed (multi-information
//! `metadata_events`, its SHA-256 in the information `metadata_events_sha256`).
//! [`ULog::events`] decodes them; [`Metadata::from_bytes`] reads metadata the user
//! has (PX4's `all_events.json.xz`) for logs without it. What cannot be decoded
//! (no metadata, bad metadata, an id it does not define, arguments shorter than its
//! template) is in [`Events::findings`], and such events keep their id and raw
//! arguments.
//!
//! ```
//! # #[cfg(feature = "events")] {
//! use ulog_core::events::EventOptions;
//! # let bytes = ulog_core::testing::sample_log();
//! let log = ulog_core::ULog::parse(&bytes)?;
//! let events = log.events(&EventOptions::default());
//! for e in events.iter().filter(|e| e.group.as_deref() == Some("default")) {
//!     println!("{} {}: {}", e.timestamp, e.level_name(), e.text);
//! }
//! # }
//! # Ok::<(), ulog_core::ReadError>(())
//! ```

mod metadata;
mod template;

use std::fmt;

pub use metadata::{Metadata, MetadataError};
pub use template::ArgValue;

use crate::access::field::FieldShape;
use crate::log::ulog::ULog;
use template::{basic_size, display, fill, read_basic};

/// How [`ULog::events`] decodes.
#[derive(Debug, Clone)]
pub struct EventOptions {
    profile: String,
    metadata: Option<Metadata>,
}

impl Default for EventOptions {
    fn default() -> EventOptions {
        EventOptions {
            profile: "normal".to_owned(),
            metadata: None,
        }
    }
}

impl EventOptions {
    /// The profile whose `<profile>` parts of messages are kept: `normal` (what a
    /// ground station shows a user; the default) or `dev` (what pyulog's
    /// `ulog_messages` shows).
    pub fn profile(mut self, profile: impl Into<String>) -> EventOptions {
        self.profile = profile.into();
        self
    }

    /// Metadata to use instead of what the log embeds (for logs without any, or
    /// with metadata that is bad).
    pub fn metadata(mut self, metadata: Metadata) -> EventOptions {
        self.metadata = Some(metadata);
        self
    }
}

/// An event of the log.
#[derive(Debug, Clone, PartialEq)]
pub struct Event {
    /// Its row in the `event` topic (instance 0).
    pub row: usize,
    /// Its `timestamp` (microseconds).
    pub timestamp: u64,
    /// The event id: component (top 8 bits) and sub-id.
    pub id: u32,
    /// Its sequence number.
    pub sequence: u16,
    /// The level for the log (the high 4 bits of `log_levels`): 0 emergency … 7
    /// debug, 8 protocol, 9 disabled.
    pub level: u8,
    /// The level for external display (the low 4 bits).
    pub external_level: u8,
    /// Its name, when the metadata defines it.
    pub name: Option<String>,
    /// Its group (`default`, `arming_check`, `health`, …), when defined; pyulog and
    /// ground stations show the `default` group as messages.
    pub group: Option<String>,
    /// The message, filled in; an undefined event reads
    /// `[Unknown event with ID N]` (with its raw arguments when there was no
    /// metadata at all).
    pub text: String,
    /// The description, filled in, when the definition has one.
    pub description: Option<String>,
    /// The arguments as the definition types them (empty when undefined).
    pub arguments: Vec<ArgValue>,
    /// The raw argument bytes as logged.
    pub raw_arguments: Vec<u8>,
}

impl Event {
    /// Whether PX4's tools show it as a message: an event of the `default` group (or
    /// one the metadata does not define) below the protocol level, as pyulog's
    /// `ulog_messages` and ground stations show them (arming checks and health
    /// reports are shown elsewhere, and repeat as the vehicle checks itself).
    pub fn is_message(&self) -> bool {
        self.level < 8 && self.group.as_deref().map_or(true, |g| g == "default")
    }

    /// The level's name as pyulog prints it (`INFO`, `WARNING`, …).
    pub fn level_name(&self) -> &'static str {
        level_name(self.level)
    }
}

/// The name of an event log level.
pub fn level_name(level: u8) -> &'static str {
    match level {
        0 => "EMERGENCY",
        1 => "ALERT",
        2 => "CRITICAL",
        3 => "ERROR",
        4 => "WARNING",
        5 => "NOTICE",
        6 => "INFO",
        7 => "DEBUG",
        8 => "PROTOCOL",
        9 => "DISABLED",
        _ => "UNKNOWN",
    }
}

/// What could not be decoded.
#[derive(Debug, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub enum EventFinding {
    /// The log has events but no metadata, and none was given.
    NoMetadata,
    /// The log's metadata cannot be used.
    BadMetadata(MetadataError),
    /// The `event` topic lacks a field events need (`id`, `arguments`,
    /// `log_levels`), or has it with another type.
    BadTopic(String),
    /// Events whose id the metadata does not define: the id and how many.
    UnknownId {
        /// The id.
        id: u32,
        /// How many events had it.
        count: usize,
    },
    /// An event whose arguments are shorter than its definition's, or of a type
    /// that is neither basic nor a defined enum.
    BadArguments {
        /// The event's name.
        name: String,
        /// When it was logged.
        timestamp: u64,
        /// What is wrong.
        what: String,
    },
}

impl fmt::Display for EventFinding {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            EventFinding::NoMetadata => f.write_str(
                "the log has no event metadata (metadata_events): events are shown by id \
                 and raw arguments (give PX4's all_events.json.xz with --events-json)",
            ),
            EventFinding::BadMetadata(e) => {
                write!(f, "{e}: events are shown by id and raw arguments")
            }
            EventFinding::BadTopic(what) => write!(f, "the event topic {what}"),
            EventFinding::UnknownId { id, count } => write!(
                f,
                "event id {id} ({count} event{}) is not in the metadata",
                if *count == 1 { "" } else { "s" }
            ),
            EventFinding::BadArguments {
                name,
                timestamp,
                what,
            } => write!(f, "event {name} at {timestamp} µs: {what}"),
        }
    }
}

/// The events of a log, in the order logged, and what could not be decoded.
#[derive(Debug, Clone, Default)]
pub struct Events {
    /// The events.
    pub events: Vec<Event>,
    /// What could not be decoded (the events concerned are still in `events`).
    pub findings: Vec<EventFinding>,
}

impl Events {
    /// The events, in the order logged.
    pub fn iter(&self) -> std::slice::Iter<'_, Event> {
        self.events.iter()
    }
}

impl ULog<'_> {
    /// The PX4 events of this log (its `event` topic, instance 0), decoded with the
    /// metadata the log embeds or that `options` gives (see [`events`](crate::events)).
    /// A log without an `event` topic has none; nothing here fails: what cannot be
    /// decoded is in [`Events::findings`].
    pub fn events(&self, options: &EventOptions) -> Events {
        let Ok(topic) = self.topic("event", 0) else {
            return Events::default();
        };
        let timestamps = topic.timestamps();
        let rows = topic
            .payloads()
            .enumerate()
            .map(|(i, p)| (timestamps.get(i).copied().unwrap_or(0), p));
        self.decode_events(&topic, options, rows)
    }

    /// The events of `rows` (timestamp and payload) of `topic`, an `event` topic of
    /// this log, with this log's metadata (or that of `options`).
    pub(crate) fn decode_events<'p>(
        &self,
        topic: &crate::Topic<'_, '_>,
        options: &EventOptions,
        rows: impl Iterator<Item = (u64, &'p [u8])>,
    ) -> Events {
        let mut out = Events::default();
        let field = |name: &str| topic.field(name).ok();
        let (Some(id), Some(args), Some(levels)) =
            (field("id"), field("arguments"), field("log_levels"))
        else {
            out.findings.push(EventFinding::BadTopic(
                "lacks one of the fields id, arguments, log_levels".into(),
            ));
            return out;
        };
        let args_len = match args.shape() {
            FieldShape::Array(n) if args.ty().size() == 1 => n,
            _ => {
                out.findings.push(EventFinding::BadTopic(
                    "has no byte array `arguments`".into(),
                ));
                return out;
            }
        };
        let sequence = field("event_sequence");
        let given = options.metadata.as_ref();
        let embedded = match given {
            Some(_) => None,
            None => match Metadata::from_log(self) {
                Some(Ok(m)) => Some(m),
                Some(Err(e)) => {
                    out.findings.push(EventFinding::BadMetadata(e));
                    None
                }
                None => None,
            },
        };
        let metadata = given.or(embedded.as_ref());
        let mut unknown: Vec<(u32, usize)> = Vec::new();
        for (row, (timestamp, payload)) in rows.enumerate() {
            if row == 0 && metadata.is_none() && out.findings.is_empty() {
                out.findings.push(EventFinding::NoMetadata);
            }
            let read_u = |f: &crate::FieldReader| f.read(payload).and_then(|v| v.as_u64());
            // Framing has checked every row's size: the fields are there.
            let event_id = read_u(&id).unwrap_or(0) as u32;
            let level_bits = read_u(&levels).unwrap_or(0);
            let raw: Vec<u8> = payload
                .get(args.offset()..args.offset() + args_len)
                .unwrap_or(&[])
                .to_vec();
            let mut event = Event {
                row,
                timestamp,
                id: event_id,
                sequence: sequence.as_ref().and_then(read_u).unwrap_or(0) as u16,
                level: ((level_bits >> 4) & 0xF) as u8,
                external_level: (level_bits & 0xF) as u8,
                name: None,
                group: None,
                text: String::new(),
                description: None,
                arguments: Vec::new(),
                raw_arguments: raw,
            };
            match metadata.map(|m| (m, m.find(event_id))) {
                Some((m, Some((component, group, def)))) => {
                    decode(&mut event, m, component, group, def, options, &mut out);
                }
                Some((_, None)) => {
                    match unknown.iter_mut().find(|(i, _)| *i == event_id) {
                        Some((_, n)) => *n += 1,
                        None => unknown.push((event_id, 1)),
                    }
                    event.text = format!("[Unknown event with ID {event_id}]");
                }
                None => {
                    let end = event
                        .raw_arguments
                        .iter()
                        .rposition(|&b| b != 0)
                        .map_or(0, |p| p + 1);
                    let hex: Vec<String> = event.raw_arguments[..end]
                        .iter()
                        .map(|b| format!("{b:02x}"))
                        .collect();
                    event.text = format!(
                        "[Unknown event with ID {event_id}, arguments: {}]",
                        if hex.is_empty() {
                            "none".to_owned()
                        } else {
                            hex.join(" ")
                        }
                    );
                }
            }
            out.events.push(event);
        }
        out.findings.extend(
            unknown
                .into_iter()
                .map(|(id, count)| EventFinding::UnknownId { id, count }),
        );
        out
    }
}

/// Fills in `event` from its definition.
fn decode(
    event: &mut Event,
    m: &Metadata,
    component: &metadata::Component,
    group: &str,
    def: &metadata::Definition,
    options: &EventOptions,
    out: &mut Events,
) {
    event.name = Some(def.name.clone());
    event.group = Some(group.to_owned());
    let mut shown = Vec::new();
    let mut at = 0;
    let mut problem = None;
    for ty in &def.arguments {
        // An enum's name is its component's unless it names another (`ns::name`).
        let en = if basic_size(ty).is_some() {
            None
        } else {
            let key = match ty.contains("::") {
                true => ty.clone(),
                false => format!("{}::{ty}", component.namespace),
            };
            let found = m.enums.get(&key);
            match found {
                Some(e) => Some(e),
                None => {
                    problem = Some(format!("argument type `{ty}` is not defined"));
                    break;
                }
            }
        };
        let basic = en.map_or(ty.as_str(), |e| e.ty.as_str());
        match read_basic(basic, event.raw_arguments.get(at..).unwrap_or(&[])) {
            Some((value, size)) => {
                event.arguments.push(value);
                shown.push(display(value, en));
                at += size;
            }
            None => {
                problem = Some(match basic_size(basic) {
                    Some(size) => format!(
                        "its arguments hold {} bytes, its definition needs more ({} at byte {at})",
                        event.raw_arguments.len(),
                        size
                    ),
                    None => format!("argument type `{basic}` is not a basic type"),
                });
                break;
            }
        }
    }
    if let Some(what) = problem {
        event.text = format!("[{}: {what}]", def.name);
        out.findings.push(EventFinding::BadArguments {
            name: def.name.clone(),
            timestamp: event.timestamp,
            what,
        });
        return;
    }
    event.text = fill(&def.message, &shown, &options.profile);
    event.description = def
        .description
        .as_deref()
        .map(|d| fill(d, &shown, &options.profile));
}
