//! `ulog dump`: every message of a log in file order, as text or JSON lines.

use std::collections::HashMap;
use std::io::{self, BufWriter, Write};
use std::path::PathBuf;

use serde_json::{json, Map, Value as Json};
use ulog_core::events::EventOptions;
use ulog_core::read::{KeyValue, MessageAt, Unwrapper, UtcClock, UtcTime};
use ulog_core::units::unit_of;
use ulog_core::{FieldReader, Finding, Message, ULog};

use crate::describe::{kind_name, type_name, value_json};
use crate::failure::{stdout_err, Failure};
use crate::input;
use crate::progress::Progress;
use crate::pyfmt::value_text;

const JSON_KEYS: &str = "\
JSON lines (--json): one object per message, in file order, each with
  offset   byte offset of the message header
  type     the message type letter (\"D\", \"F\", …; \"?\" for unknown types)
and by type:
  B  compat_flags, incompat_flags, appended_offsets
  F  format (the definition text)
  I  key, name, value            M  key, name, value, continued
  P  key, name, value            Q  key, name, value, default_types
  A  msg_id, multi_id, topic, units {column: unit} (the columns whose names say
     their unit, as ulog_core::units reads them)   R  msg_id
  D  msg_id, topic, multi_id, fields {column: value} (pyulog's column names, in
     order) or, when it cannot be decoded, size and error; rows of the PX4 event
     topic also event {id, name, group, level, level_name, text}; with --utc, utc
  L, C  level (0-7 as a number), level_name, tag (C only), timestamp, text; with
     --utc, utc
  S  (nothing else)              O  duration_ms
  ?  msg_type (the byte), size
Findings of the reader appear where they start, as objects with
  offset, finding (the kind, as in `ulog info --json`), len, text";

/// Print every message of a log in file order with its byte offset: flag bits,
/// formats, information, parameters, subscriptions, data (decoded, field by field),
/// logged strings, syncs, dropouts and unknown types, with what the reader found
/// (damage, skipped bytes) where it starts. Rows of the PX4 `event` topic are
/// followed by the event they hold, decoded (`=> event LEVEL: text`). Values whose
/// field name says their unit are followed by it (`vx=0.25 m/s`); with `--utc`, data
/// rows and logged strings also show their time in UTC.
#[derive(Debug, clap::Args)]
#[command(
    about = "Every message in file order, with its byte offset",
    long_about,
    after_help = JSON_KEYS
)]
pub struct Args {
    /// The ULog file.
    file: PathBuf,
    /// One JSON object per line instead of text (keys below).
    #[arg(long)]
    json: bool,
    /// Only data messages of these topics (comma-separated names); other messages are
    /// still shown.
    #[arg(short = 'm', long = "messages", value_name = "TOPICS")]
    messages: Option<String>,
    /// Leave out data messages (show the definitions and the other messages only).
    #[arg(long)]
    no_data: bool,
    /// Also show each data row's and logged string's time in UTC, from the log's GPS
    /// time or its `boot_time_utc_us` (`ulog info` says which).
    #[arg(long)]
    utc: bool,
}

/// Decoding state of one subscription: topic name, instance, column readers (or why
/// there are none) and the payload sizes that decode.
struct Decoder {
    name: String,
    multi_id: u8,
    columns: Result<Vec<FieldReader>, String>,
    /// The unit of each column, where its name says it.
    units: Vec<Option<&'static str>>,
    /// Reads the timestamps of the payloads, in order (`--utc`; version 0's narrow
    /// timestamps wrap).
    timestamps: Unwrapper,
    sizes: (usize, usize),
}

/// What every message's line needs besides the message.
struct Context<'l, 'a> {
    log: &'l ULog<'a>,
    current: HashMap<u16, usize>,
    decoders: Vec<Option<Decoder>>,
    utc: Option<UtcClock>,
}

pub fn run(args: &Args) -> Result<(), Failure> {
    let name = args.file.display().to_string();
    let file = input::open(&args.file)?;
    let bytes = file.bytes();
    let log = input::parse(&name, bytes)?;
    let wanted = match args.messages.as_deref() {
        Some(list) => Some(input::topic_list(&name, &log, list)?),
        None => None,
    };
    let utc = input::utc_clock(&name, &log, args.utc)?;
    // Subscriptions the reader kept, by the offset of their `A` message.
    let mut cx = Context {
        log: &log,
        current: HashMap::new(),
        decoders: (0..log.topics().count()).map(|_| None).collect(),
        utc,
    };

    let mut findings: Vec<&Finding> = log.findings().iter().collect();
    findings.sort_by_key(|f| f.offset);
    let mut next_finding = 0;

    // PX4 events, shown beside the rows of the event topic (instance 0).
    let events = log.events(&EventOptions::default());
    let event_topic = log.topic("event", 0).ok().map(|t| t.subscription().index());
    let mut event_row = 0usize;

    let progress = Progress::new(bytes.len() as u64, "dump bytes");
    let mut last_offset = 0u64;
    let mut out = BufWriter::with_capacity(1 << 16, io::stdout().lock());
    let mut line = String::with_capacity(256);
    let mut messages = log.messages();
    while let Some(item) = messages.next() {
        let Ok(m) = item else { break };
        while next_finding < findings.len() && findings[next_finding].offset <= m.offset {
            write_finding(&mut out, findings[next_finding], args.json).map_err(stdout_err)?;
            next_finding += 1;
        }
        progress.inc(m.offset - last_offset);
        last_offset = m.offset;
        // The reader's own rule for which topic instance a msg_id's data belongs to
        // (a topic instance subscribed twice is one instance), as `csv` and `check`
        // see it.
        match &m.message {
            Message::Subscribe { msg_id, .. } | Message::Unsubscribe { msg_id } => {
                match messages.subscription(*msg_id) {
                    Some(s) => cx.current.insert(*msg_id, s.index()),
                    None => cx.current.remove(msg_id),
                };
            }
            _ => {}
        }
        if let Message::Data { msg_id, .. } = &m.message {
            if args.no_data {
                continue;
            }
            if let Some(w) = &wanted {
                let Some(&i) = cx.current.get(msg_id) else {
                    continue;
                };
                if !w.contains(&log.topic_at(i).name()) {
                    continue;
                }
            }
        }
        // A row of the event topic: the event it is, decoded.
        let event = match &m.message {
            Message::Data { msg_id, .. }
                if event_topic.is_some() && cx.current.get(msg_id) == event_topic.as_ref() =>
            {
                event_row += 1;
                events.events.get(event_row - 1)
            }
            _ => None,
        };
        line.clear();
        if args.json {
            let mut j = message_json(&m, &mut cx);
            if let (Some(e), Json::Object(o)) = (event, &mut j) {
                o.insert(
                    "event".into(),
                    json!({"id": e.id, "name": e.name, "group": e.group,
                           "level": e.level, "level_name": e.level_name(), "text": e.text}),
                );
            }
            line.push_str(&j.to_string());
        } else {
            message_text(&mut line, &m, &mut cx);
            if let Some(e) = event {
                line.push_str(&format!(" => event {}: {}", e.level_name(), e.text));
            }
        }
        line.push('\n');
        out.write_all(line.as_bytes()).map_err(stdout_err)?;
    }
    for f in &findings[next_finding..] {
        write_finding(&mut out, f, args.json).map_err(stdout_err)?;
    }
    out.flush().map_err(stdout_err)
}

fn write_finding(out: &mut impl Write, f: &Finding, json: bool) -> io::Result<()> {
    if json {
        let j = json!({"offset": f.offset, "finding": kind_name(f), "len": f.len, "count": f.count, "text": f.what()});
        writeln!(out, "{j}")
    } else {
        writeln!(out, "{:>10}  !  {}", f.offset, f.what())
    }
}

impl Context<'_, '_> {
    /// The decoder of the topic instance `msg_id` is subscribed to now.
    fn decoder(&mut self, msg_id: u16) -> Option<&mut Decoder> {
        let &i = self.current.get(&msg_id)?;
        let log = self.log;
        Some(self.decoders[i].get_or_insert_with(|| {
            let t = log.topic_at(i);
            let sizes = t
                .layout()
                .map(|l| (l.size(), l.min_size()))
                .unwrap_or((0, 0));
            let columns = t.fields().map_err(|e| e.to_string());
            let units = match &columns {
                Ok(cols) => cols.iter().map(|c| unit_of(t.name(), c.path())).collect(),
                Err(_) => Vec::new(),
            };
            Decoder {
                name: t.name().to_owned(),
                multi_id: t.multi_id(),
                columns,
                units,
                timestamps: Unwrapper::new(t.timestamp_field()),
                sizes,
            }
        }))
    }

    /// The UTC time of the next data payload of `msg_id` (`--utc`), if it has a
    /// timestamp. Called for each data message of the topic, in file order.
    fn payload_utc(&mut self, msg_id: u16, payload: &[u8]) -> Option<UtcTime> {
        let clock = self.utc.clone()?;
        let t = self.decoder(msg_id)?.timestamps.push(payload)?;
        Some(clock.at(t))
    }
}

fn kv_text(line: &mut String, kv: &KeyValue<'_>) {
    use std::fmt::Write as _;
    let _ = write!(line, "{} = ", kv.key);
    match kv.value() {
        ulog_core::Value::Str(s) => {
            let _ = write!(line, "{:?}", s.to_string_lossy());
        }
        v => line.push_str(&value_text(&v)),
    }
}

fn message_text(line: &mut String, m: &MessageAt<'_>, cx: &mut Context<'_, '_>) {
    use std::fmt::Write as _;
    let letter = match &m.message {
        Message::Unknown { .. } => '?',
        other => other.msg_type() as char,
    };
    let _ = write!(line, "{:>10}  {letter}  ", m.offset);
    match &m.message {
        Message::FlagBits(f) => {
            let _ = write!(
                line,
                "flag bits: compat {:?}, incompat {:?}, appended offsets {:?}",
                f.compat_flags, f.incompat_flags, f.appended_offsets
            );
        }
        Message::Format(text) => {
            let _ = write!(line, "{text}");
        }
        Message::Info(kv) | Message::Param(kv) => kv_text(line, kv),
        Message::MultiInfo { continued, kv } => {
            kv_text(line, kv);
            if *continued {
                line.push_str(" (continued)");
            }
        }
        Message::DefaultParam { default_types, kv } => {
            kv_text(line, kv);
            let _ = write!(line, " (default types {default_types:#04b})");
        }
        Message::Subscribe {
            multi_id,
            msg_id,
            name,
        } => {
            let _ = write!(line, "msg_id {msg_id}: {name} instance {multi_id}");
        }
        Message::Unsubscribe { msg_id } => {
            let _ = write!(line, "msg_id {msg_id}");
        }
        Message::Data { msg_id, payload } => {
            match (cx.payload_utc(*msg_id, payload), cx.decoder(*msg_id)) {
                (_, None) => {
                    let _ = write!(
                        line,
                        "msg_id {msg_id}: no subscription, {} bytes",
                        payload.len()
                    );
                }
                (utc, Some(d)) => {
                    let _ = write!(line, "{}({}):", d.name, d.multi_id);
                    match (&d.columns, payload.len()) {
                        (Err(e), n) => {
                            let _ = write!(line, " {n} bytes, not decoded: {e}");
                        }
                        (Ok(_), n) if n != d.sizes.0 && n != d.sizes.1 => {
                            let _ = write!(line, " {n} bytes, not decoded: expected {}", d.sizes.0);
                        }
                        (Ok(cols), _) => {
                            for (c, unit) in cols.iter().zip(&d.units) {
                                match c.read(payload) {
                                    Some(v) => {
                                        let _ = write!(line, " {}={}", c.path(), value_text(&v));
                                        if let Some(u) = unit {
                                            let _ = write!(line, " {u}");
                                        }
                                    }
                                    None => {
                                        let _ = write!(line, " {}=?", c.path());
                                    }
                                }
                            }
                            if let Some(t) = utc {
                                let _ = write!(line, " utc={t}");
                            }
                        }
                    }
                }
            }
        }
        Message::Log(l) => {
            let level = l.level().map_or("UNKNOWN", |v| v.name());
            let _ = write!(line, "{level} ");
            if let Some(tag) = l.tag {
                let _ = write!(line, "tag {tag} ");
            }
            let _ = write!(line, "at {} us", l.timestamp);
            if let Some(clock) = &cx.utc {
                let _ = write!(line, " ({})", clock.at(l.timestamp));
            }
            let _ = write!(line, ": {}", l.text);
        }
        Message::Sync(_) => line.push_str("sync"),
        Message::Dropout { duration_ms } => {
            let _ = write!(line, "dropout of {duration_ms} ms");
        }
        Message::Unknown { msg_type, payload } => {
            let _ = write!(
                line,
                "unknown type {}, {} bytes",
                type_name(*msg_type),
                payload.len()
            );
        }
        _ => line.push_str("(a message type this tool does not show)"),
    }
}

fn kv_json(o: &mut Map<String, Json>, kv: &KeyValue<'_>) {
    o.insert(
        "key".into(),
        Json::String(kv.key.to_string_lossy().into_owned()),
    );
    o.insert("name".into(), Json::String(kv.name().into_owned()));
    o.insert("value".into(), value_json(&kv.value()));
}

fn message_json(m: &MessageAt<'_>, cx: &mut Context<'_, '_>) -> Json {
    let mut o = Map::new();
    o.insert("offset".into(), Json::from(m.offset));
    let letter = match &m.message {
        Message::Unknown { .. } => "?".to_owned(),
        other => (other.msg_type() as char).to_string(),
    };
    o.insert("type".into(), Json::String(letter));
    match &m.message {
        Message::FlagBits(f) => {
            o.insert("compat_flags".into(), json!(f.compat_flags));
            o.insert("incompat_flags".into(), json!(f.incompat_flags));
            o.insert("appended_offsets".into(), json!(f.appended_offsets));
        }
        Message::Format(text) => {
            o.insert(
                "format".into(),
                Json::String(text.to_string_lossy().into_owned()),
            );
        }
        Message::Info(kv) | Message::Param(kv) => kv_json(&mut o, kv),
        Message::MultiInfo { continued, kv } => {
            kv_json(&mut o, kv);
            o.insert("continued".into(), Json::Bool(*continued));
        }
        Message::DefaultParam { default_types, kv } => {
            kv_json(&mut o, kv);
            o.insert("default_types".into(), Json::from(*default_types));
        }
        Message::Subscribe {
            multi_id,
            msg_id,
            name,
        } => {
            o.insert("msg_id".into(), Json::from(*msg_id));
            o.insert("multi_id".into(), Json::from(*multi_id));
            o.insert(
                "topic".into(),
                Json::String(name.to_string_lossy().into_owned()),
            );
            if let Some(d) = cx.decoder(*msg_id) {
                let units: Map<String, Json> = match &d.columns {
                    Ok(cols) => cols
                        .iter()
                        .zip(&d.units)
                        .filter_map(|(c, u)| {
                            Some((c.path().to_owned(), Json::from(u.as_ref()?.to_string())))
                        })
                        .collect(),
                    Err(_) => Map::new(),
                };
                o.insert("units".into(), Json::Object(units));
            }
        }
        Message::Unsubscribe { msg_id } => {
            o.insert("msg_id".into(), Json::from(*msg_id));
        }
        Message::Data { msg_id, payload } => {
            o.insert("msg_id".into(), Json::from(*msg_id));
            let utc = cx.payload_utc(*msg_id, payload);
            match cx.decoder(*msg_id) {
                None => {
                    o.insert("size".into(), Json::from(payload.len()));
                    o.insert("error".into(), Json::String("no subscription".into()));
                }
                Some(d) => {
                    o.insert("topic".into(), Json::String(d.name.clone()));
                    o.insert("multi_id".into(), Json::from(d.multi_id));
                    let n = payload.len();
                    match &d.columns {
                        Err(e) => {
                            o.insert("size".into(), Json::from(n));
                            o.insert("error".into(), Json::String(e.clone()));
                        }
                        Ok(_) if n != d.sizes.0 && n != d.sizes.1 => {
                            o.insert("size".into(), Json::from(n));
                            o.insert(
                                "error".into(),
                                Json::String(format!("size {n}, expected {}", d.sizes.0)),
                            );
                        }
                        Ok(cols) => {
                            let fields: Map<String, Json> = cols
                                .iter()
                                .map(|c| {
                                    let v = c.read(payload).map_or(Json::Null, |v| value_json(&v));
                                    (c.path().to_owned(), v)
                                })
                                .collect();
                            o.insert("fields".into(), Json::Object(fields));
                            if let Some(t) = utc {
                                o.insert("utc".into(), Json::String(t.to_string()));
                            }
                        }
                    }
                }
            }
        }
        Message::Log(l) => {
            o.insert("level".into(), Json::from(l.raw_level.wrapping_sub(b'0')));
            o.insert(
                "level_name".into(),
                Json::String(l.level().map_or("UNKNOWN", |v| v.name()).to_owned()),
            );
            if let Some(tag) = l.tag {
                o.insert("tag".into(), Json::from(tag));
            }
            o.insert("timestamp".into(), Json::from(l.timestamp));
            if let Some(clock) = &cx.utc {
                o.insert(
                    "utc".into(),
                    Json::String(clock.at(l.timestamp).to_string()),
                );
            }
            o.insert(
                "text".into(),
                Json::String(l.text.to_string_lossy().into_owned()),
            );
        }
        Message::Sync(_) => {}
        Message::Dropout { duration_ms } => {
            o.insert("duration_ms".into(), Json::from(*duration_ms));
        }
        Message::Unknown { msg_type, payload } => {
            o.insert("msg_type".into(), Json::from(*msg_type));
            o.insert("size".into(), Json::from(payload.len()));
        }
        _ => {}
    }
    Json::Object(o)
}
