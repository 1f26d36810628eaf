//! The metadata file of an export: everything in a log that is not topic data, as
//! one JSON document.

use std::fmt::Write as _;
use std::path::Path;

use super::error::ExportError;
use crate::finding::{Finding, FindingKind};
use crate::log::message::KeyValue;
use crate::log::ulog::ULog;
use crate::value::Value;

use super::latin1;

/// The name of the metadata file [`super::write_parquet`] writes beside the Parquet files.
pub const METADATA_FILE: &str = "metadata.json";

/// The log's metadata as a JSON object (what [`write_metadata`] writes):
///
/// - `version`, `start_timestamp`, `last_timestamp` (µs, as pyulog's), `span_start`,
///   `span_end` (µs, the log's [span](crate::ULog::span): what a time axis shows),
///   `truncated`, `damaged`;
/// - `info`: object, information key name → value (the last of a repeated key);
/// - `multi_info`: object, key name → list of entries, each the list of its parts'
///   values (continued messages are parts of one entry);
/// - `parameters`: object, name → value when logging started;
/// - `changed_parameters`: list of `{timestamp, name, value}`, in file order;
/// - `default_parameters`: list of `{name, value, default_types}`;
/// - `logged_messages`: list of `{timestamp, level, level_raw, tag, text}` (`level`
///   is `EMERGENCY`…`DEBUG` or null for an invalid level byte; `tag` is null for
///   untagged messages);
/// - `events` (feature `events`): the PX4 events, list of `{timestamp, id, name,
///   group, level, text}` (see [`ULog::events`]; `name` and `group` null for an
///   event the metadata does not define);
/// - `dropouts`: list of `{timestamp, duration_ms}`;
/// - `findings`: list of `{offset, len, damage, text}` (what the reader stepped over);
/// - `topics`: list of `{name, multi_id, rows}`, every subscription in file order.
///
/// Values: integers as JSON numbers (full `u64`/`i64` range), `float` and `double` as
/// the shortest decimal that reads back to the same value (`null` for NaN and
/// infinities), booleans, strings as in the Parquet files (trailing NULs removed, one
/// character per byte; `"` and `\` escaped, control characters as `\uXXXX`), arrays
/// as lists, and bytes of a type this reader cannot decode as a string of hex digits.
///
/// ```
/// let bytes = ulog_core::testing::sample_log();
/// let log = ulog_core::ULog::parse(&bytes)?;
/// let json = ulog_core::export::metadata_json(&log);
/// assert!(json.contains(r#""sys_name": "PX4""#));
/// assert!(json.contains(r#""MPC_XY_VEL_MAX": 12.0"#));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn metadata_json(log: &ULog<'_>) -> String {
    let rows: Vec<usize> = log.topics().map(|t| t.len()).collect();
    #[cfg(feature = "events")]
    let events = log.events(&crate::events::EventOptions::default());
    json(
        log,
        &Facts {
            last_timestamp: log.last_timestamp(),
            findings: log.findings(),
            rows: &rows,
            #[cfg(feature = "events")]
            events: Some(&events),
            flight: None,
        },
    )
}

/// What the metadata says that a log read without its data (the export's kept log)
/// does not know itself: the data's last timestamp, what framing found, and each
/// subscription's rows.
pub(super) struct Facts<'f> {
    pub last_timestamp: u64,
    pub findings: &'f [Finding],
    /// Rows per subscription, in the order of [`ULog::topics`].
    pub rows: &'f [usize],
    /// The PX4 events, decoded.
    #[cfg(feature = "events")]
    pub events: Option<&'f crate::events::Events>,
    /// The flight analysis of a dataset's log (made in the same pass).
    pub flight: Option<&'f crate::analysis::FlightAnalysis>,
}

/// [`metadata_json`] of `log` with `facts`.
pub(super) fn json(log: &ULog<'_>, facts: &Facts<'_>) -> String {
    let mut j = Json::default();
    j.open('{');
    j.key("version");
    j.raw(&log.version().to_string());
    j.key("start_timestamp");
    j.raw(&log.start_timestamp().to_string());
    j.key("last_timestamp");
    j.raw(&facts.last_timestamp.to_string());
    j.key("span_start");
    j.raw(&log.span().start().to_string());
    j.key("span_end");
    j.raw(&log.span().end().to_string());
    let truncated = facts
        .findings
        .iter()
        .any(|f| f.kind == FindingKind::Truncated);
    let damaged = facts.findings.iter().any(Finding::is_damage);
    j.key("truncated");
    j.raw(if truncated { "true" } else { "false" });
    j.key("damaged");
    j.raw(if damaged { "true" } else { "false" });

    j.key("info");
    key_values(&mut j, log.info());

    j.key("multi_info");
    j.open('{');
    for m in log.multi_info() {
        j.key(&m.name);
        j.open('[');
        for entry in &m.entries {
            j.item();
            j.open('[');
            for part in entry {
                j.item();
                j.value(part.value());
            }
            j.close(']');
        }
        j.close(']');
    }
    j.close('}');

    j.key("parameters");
    key_values(&mut j, log.initial_params());

    j.key("changed_parameters");
    j.open('[');
    for c in log.param_changes() {
        j.item();
        j.open('{');
        j.key("timestamp");
        j.raw(&c.timestamp.to_string());
        j.key("name");
        j.string(&c.kv.name());
        j.key("value");
        j.value(c.kv.value());
        j.close('}');
    }
    j.close(']');

    j.key("default_parameters");
    j.open('[');
    for d in log.default_params() {
        j.item();
        j.open('{');
        j.key("name");
        j.string(&d.kv.name());
        j.key("value");
        j.value(d.kv.value());
        j.key("default_types");
        j.raw(&d.default_types.to_string());
        j.close('}');
    }
    j.close(']');

    j.key("logged_messages");
    j.open('[');
    for m in log.logged_messages() {
        j.item();
        j.open('{');
        j.key("timestamp");
        j.raw(&m.timestamp.to_string());
        j.key("level");
        match m.level() {
            Some(l) => j.string(l.name()),
            None => j.raw("null"),
        }
        j.key("level_raw");
        j.raw(&m.raw_level.to_string());
        j.key("tag");
        match m.tag {
            Some(t) => j.raw(&t.to_string()),
            None => j.raw("null"),
        }
        j.key("text");
        j.text(m.text.as_bytes());
        j.close('}');
    }
    j.close(']');

    #[cfg(feature = "events")]
    {
        j.key("events");
        j.open('[');
        for e in facts.events.iter().flat_map(|e| e.iter()) {
            j.item();
            j.open('{');
            j.key("timestamp");
            j.raw(&e.timestamp.to_string());
            j.key("id");
            j.raw(&e.id.to_string());
            j.key("name");
            match &e.name {
                Some(n) => j.string(n),
                None => j.raw("null"),
            }
            j.key("group");
            match &e.group {
                Some(g) => j.string(g),
                None => j.raw("null"),
            }
            j.key("level");
            j.string(e.level_name());
            j.key("text");
            j.string(&e.text);
            j.close('}');
        }
        j.close(']');
    }

    j.key("dropouts");
    j.open('[');
    for d in log.dropouts() {
        j.item();
        j.open('{');
        j.key("timestamp");
        j.raw(&d.timestamp.to_string());
        j.key("duration_ms");
        j.raw(&d.duration_ms.to_string());
        j.close('}');
    }
    j.close(']');

    j.key("findings");
    j.open('[');
    for f in facts.findings {
        j.item();
        j.open('{');
        j.key("offset");
        j.raw(&f.offset.to_string());
        j.key("len");
        j.raw(&f.len.to_string());
        j.key("count");
        j.raw(&f.count.to_string());
        j.key("damage");
        j.raw(if f.is_damage() { "true" } else { "false" });
        j.key("text");
        j.string(&f.to_string());
        j.close('}');
    }
    j.close(']');

    j.key("topics");
    j.open('[');
    for (t, rows) in log.topics().zip(facts.rows) {
        j.item();
        j.open('{');
        j.key("name");
        j.string(t.name());
        j.key("multi_id");
        j.raw(&t.multi_id().to_string());
        j.key("rows");
        j.raw(&rows.to_string());
        j.close('}');
    }
    j.close(']');
    j.close('}');
    j.out.push('\n');
    j.out
}

/// Writes [`metadata_json`] to `path`.
pub fn write_metadata(log: &ULog<'_>, path: &Path) -> Result<(), ExportError> {
    std::fs::write(path, metadata_json(log)).map_err(|e| ExportError::io(e, path))
}

/// An object of key-value messages by name; a repeated name keeps its first place and
/// its last value.
fn key_values(j: &mut Json, kvs: &[KeyValue<'_>]) {
    let mut entries: Vec<(String, Value<'_>)> = Vec::with_capacity(kvs.len());
    // Where each name is in `entries`: a log may hold hundreds of thousands of keys.
    let mut place: std::collections::HashMap<String, usize> =
        std::collections::HashMap::with_capacity(kvs.len());
    for kv in kvs {
        let name = kv.name();
        match place.get(name.as_ref()) {
            Some(&i) => entries[i].1 = kv.value(),
            None => {
                place.insert(name.clone().into_owned(), entries.len());
                entries.push((name.into_owned(), kv.value()));
            }
        }
    }
    j.open('{');
    for (name, value) in entries {
        j.key(&name);
        j.value(value);
    }
    j.close('}');
}

/// A small JSON writer, indented two spaces per level.
#[derive(Default)]
struct Json {
    out: String,
    /// Whether the innermost open object or list has an element yet.
    first: Vec<bool>,
    scratch: String,
}

impl Json {
    fn newline(&mut self) {
        self.out.push('\n');
        for _ in 0..self.first.len() {
            self.out.push_str("  ");
        }
    }

    fn open(&mut self, c: char) {
        self.out.push(c);
        self.first.push(true);
    }

    fn close(&mut self, c: char) {
        let empty = self.first.pop().unwrap_or(true);
        if !empty {
            self.newline();
        }
        self.out.push(c);
    }

    /// Starts an element of the innermost list or object.
    fn item(&mut self) {
        if let Some(first) = self.first.last_mut() {
            if !*first {
                self.out.push(',');
            }
            *first = false;
        }
        self.newline();
    }

    fn key(&mut self, k: &str) {
        self.item();
        self.string(k);
        self.out.push_str(": ");
    }

    fn raw(&mut self, s: &str) {
        self.out.push_str(s);
    }

    fn string(&mut self, s: &str) {
        crate::json_text::push_string(&mut self.out, s.chars());
    }

    /// A `char[N]` value: trailing NULs removed, one character per byte.
    fn text(&mut self, bytes: &[u8]) {
        let mut s = std::mem::take(&mut self.scratch);
        latin1(bytes, &mut s);
        self.string(&s);
        self.scratch = s;
    }

    fn value(&mut self, v: Value<'_>) {
        match v {
            Value::F32(f) if f.is_finite() => {
                let _ = write!(self.out, "{f:?}");
            }
            Value::F64(f) if f.is_finite() => {
                let _ = write!(self.out, "{f:?}");
            }
            Value::F32(_) | Value::F64(_) => self.raw("null"),
            Value::Bool(b) => self.raw(if b { "true" } else { "false" }),
            Value::Str(s) => self.text(s.as_bytes()),
            Value::Array(a) => {
                self.out.push('[');
                for (i, e) in a.iter().enumerate() {
                    if i > 0 {
                        self.out.push_str(", ");
                    }
                    self.value(e);
                }
                self.out.push(']');
            }
            Value::Bytes(b) => {
                let mut hex = String::with_capacity(b.len() * 2);
                for x in b {
                    let _ = write!(hex, "{x:02x}");
                }
                self.string(&hex);
            }
            other => match other.as_i128() {
                Some(n) => {
                    let _ = write!(self.out, "{n}");
                }
                None => self.raw("null"),
            },
        }
    }
}
