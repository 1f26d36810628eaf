//! What `ulog_rs.ULog` is made of, read by ulog-core and held as owned Rust values
//! until it becomes Python objects: the log's metadata as pyulog keeps it, and each
//! topic's rows packed as pyulog packs them (fields flattened in format order, the
//! trailing padding fields left out, no alignment), so that one numpy structured view
//! gives pyulog's `data` dict.

use std::collections::HashSet;
use std::ops::ControlFlow;
use std::path::Path;

use ulog_core::events::EventOptions;
use ulog_core::format::{BasicType, LayoutField, LayoutType};
use ulog_core::parallel::Shares;
use ulog_core::read::{FindingKind, KeyValue, LogMetadata, Messages, Subscription, UtcSource};
use ulog_core::{DataRecord, Message, ReadError, ScanOptions, ScanSummary, Source, ULog};

/// A `type name` key and its value bytes, decoded on the Python side as pyulog does.
pub type KeyRaw = (Vec<u8>, Vec<u8>);

/// A format: its name and fields `(type, array_size, name)` (0: not an array).
pub type FormatFields = (String, Vec<(String, usize, String)>);

/// Everything `ulog_rs.ULog` shows of a log.
#[derive(Debug, Default)]
pub struct Loaded {
    pub version: u8,
    pub start_timestamp: u64,
    pub last_timestamp: u64,
    pub compat_flags: [u8; 8],
    pub incompat_flags: [u8; 8],
    pub appended_offsets: Vec<u64>,
    /// The formats, in file order.
    pub formats: Vec<FormatFields>,
    pub info: Vec<KeyRaw>,
    /// Per multi-information key: its entries, each the list of its continued parts.
    pub info_multiple: Vec<Vec<Vec<KeyRaw>>>,
    pub initial_parameters: Vec<KeyRaw>,
    /// `(timestamp, key, value)`: the latest timestamp of the loaded topics before it.
    pub changed_parameters: Vec<(u64, Vec<u8>, Vec<u8>)>,
    /// `(default_types bits, key, value)`.
    pub default_parameters: Vec<(u8, Vec<u8>, Vec<u8>)>,
    /// `(level byte, tag, timestamp, text)`.
    pub logged_messages: Vec<(u8, Option<u16>, u64, Vec<u8>)>,
    /// `(timestamp, duration_ms)`.
    pub dropouts: Vec<(u64, u16)>,
    /// Whether the reader reported damage other than the end of the file cut short.
    pub corrupt: bool,
    /// Findings: `(what, byte offset, length, whether it is damage)`.
    pub findings: Vec<(String, u64, u64, bool)>,
    pub topics: Vec<TopicRows>,
    /// The log's UTC clock: microseconds since the Unix epoch at boot, and where it
    /// comes from.
    pub utc: Option<(i64, String)>,
    /// The PX4 events, decoded when first asked for.
    pub events: Events,
}

/// A log's PX4 events, decoded with the metadata the log embeds when first asked
/// for: decoding takes about 0.02 s of a 302 MB log whose one topic loads in about
/// 0.09 s, and most loads never look at them.
#[derive(Debug, Default)]
pub struct Events(Option<LogMetadata>);

impl Events {
    /// The events, decoded.
    pub fn decode(&self) -> Vec<EventRow> {
        let Some(metadata) = &self.0 else {
            return Vec::new();
        };
        metadata
            .events(&EventOptions::default())
            .events
            .into_iter()
            .map(|e| {
                let message = e.is_message();
                (
                    e.timestamp,
                    e.id,
                    e.sequence,
                    e.level,
                    e.external_level,
                    e.name,
                    e.group,
                    e.text,
                    e.description,
                    message,
                )
            })
            .collect()
    }
}

/// A decoded PX4 event: `(timestamp, id, sequence, level, external level, name,
/// group, text, description, is_message)`.
pub type EventRow = (
    u64,
    u32,
    u16,
    u8,
    u8,
    Option<String>,
    Option<String>,
    String,
    Option<String>,
    bool,
);

/// The rows of one topic instance, packed as pyulog packs them.
#[derive(Debug)]
pub struct TopicRows {
    pub name: String,
    pub multi_id: u8,
    pub msg_id: u16,
    /// `(field name, type name)` flattened as pyulog does: arrays of basic types
    /// element by element (`q[0]`, `name[3]` of a `char[N]`), nested types with their
    /// path (`esc[3].esc_rpm`), trailing `_padding` fields left out.
    pub fields: Vec<(String, &'static str)>,
    /// Index of `timestamp` in `fields`, or -1.
    pub timestamp_idx: i64,
    /// Bytes per packed row: the sum of the fields' sizes.
    pub itemsize: usize,
    /// The rows, `itemsize` bytes each.
    pub rows: Vec<u8>,
}

/// What to load.
#[derive(Debug, Clone)]
pub struct Request {
    /// Only these topics (pyulog's `message_name_filter_list`); `None`: all.
    pub names: Option<Vec<String>>,
    /// Keep the topics whose name is part of one of `names` (pyulog's `in` on a
    /// string filter) rather than equal to one.
    pub within: bool,
    /// Only the definitions section (pyulog's `parse_header_only`).
    pub header_only: bool,
    /// Logs of this many bytes or more are shared between two passes
    /// ([`SHARE_FROM`] unless a test asks for less).
    pub share_from: u64,
}

/// pyulog's name of a basic type.
fn type_name(b: BasicType) -> &'static str {
    b.name()
}

/// Appends the fields of `fields` (at `prefix`) flattened as pyulog flattens them.
/// Not [`Layout::leaves`](ulog_core::format::Layout::leaves): pyulog names every
/// element of a `char[N]` and of a padding array (`_padding0[3]`) as a field of its
/// own, where the layout's leaves keep each as one string or one run of padding bytes.
fn flatten(fields: &[LayoutField], prefix: &str, out: &mut Vec<(String, &'static str)>) {
    for f in fields {
        let path = format!("{prefix}{}", f.name);
        match (&f.ty, f.array_len) {
            (LayoutType::Basic(b), None) => out.push((path, type_name(*b))),
            (LayoutType::Basic(b), Some(n)) => {
                out.extend((0..n).map(|i| (format!("{path}[{i}]"), type_name(*b))))
            }
            (LayoutType::Nested(inner), None) => flatten(inner.fields(), &format!("{path}."), out),
            (LayoutType::Nested(inner), Some(n)) => {
                for i in 0..n {
                    flatten(inner.fields(), &format!("{path}[{i}]."), out);
                }
            }
        }
    }
}

/// The size of a basic type by its name.
fn size_of(name: &str) -> usize {
    BasicType::from_name(name).map_or(0, |b| b.size())
}

/// One topic's rows as the pass fills them.
struct Table {
    fields: Vec<(String, &'static str)>,
    timestamp_idx: i64,
    itemsize: usize,
    rows: Vec<u8>,
    /// Per row, the byte offset of its message and its timestamp as pyulog reads it
    /// (kept only when a filter makes the loaded topics' times differ from the
    /// whole log's).
    times: Vec<(u64, u64)>,
    /// Where the timestamp is in a packed row (pyulog reads 8 bytes there whatever
    /// the field's type).
    timestamp_at: Option<usize>,
}

impl Table {
    /// Makes room for the rows the rest of the log will likely bring, judged by the
    /// rate so far at `offset` (a topic's rows are about evenly spread over a log):
    /// one allocation of about the right size instead of a doubling's copies.
    #[cold]
    fn grow(&mut self, offset: u64, len: u64) {
        let have = self.rows.len() as u128;
        let expected = (have * u128::from(len) / u128::from(offset.max(1))) as usize;
        let target = (expected + expected / 8)
            .max(self.rows.len() + 64 * self.itemsize)
            .max(self.rows.len() * 5 / 4);
        self.rows.reserve_exact(target - self.rows.len());
    }

    /// A table for `topic`, or `None` when its format cannot be laid out (pyulog
    /// cannot read such a topic either).
    fn new(topic: &Subscription) -> Option<Table> {
        let layout = topic.layout().ok()?;
        let mut fields = Vec::new();
        flatten(layout.fields(), "", &mut fields);
        while fields
            .last()
            .is_some_and(|(n, _)| n.starts_with("_padding"))
        {
            fields.pop();
        }
        let itemsize: usize = fields.iter().map(|(_, t)| size_of(t)).sum();
        let timestamp_idx = fields.iter().position(|(n, _)| n == "timestamp");
        let timestamp_at = timestamp_idx
            .map(|i| fields[..i].iter().map(|(_, t)| size_of(t)).sum::<usize>())
            .filter(|at| at + 8 <= itemsize);
        Some(Table {
            fields,
            timestamp_idx: timestamp_idx.map_or(-1, |i| i as i64),
            itemsize,
            rows: Vec::new(),
            times: Vec::new(),
            timestamp_at,
        })
    }

    /// Adds the row of a data message at `offset` of a log of `len` bytes.
    #[inline]
    fn push(&mut self, payload: &[u8], offset: u64, len: u64, keep_times: bool) {
        // Every row the reader hands out holds the format's fields (a longer one has
        // its trailing padding or more).
        let Some(row) = payload.get(..self.itemsize) else {
            return;
        };
        if self.rows.capacity() - self.rows.len() < row.len() {
            self.grow(offset, len);
        }
        self.rows.extend_from_slice(row);
        if keep_times {
            if let Some(at) = self.timestamp_at {
                let t = u64::from_le_bytes(row[at..at + 8].try_into().expect("8 bytes"));
                self.times.push((offset, t));
            }
        }
    }
}

/// The end of the definitions section as pyulog sees it (the first subscription or
/// logged string) and the format names in file order.
fn definitions(bytes: &[u8]) -> (u64, Vec<String>) {
    let mut order = Vec::new();
    let mut seen = HashSet::new();
    for m in Messages::new(bytes) {
        let Ok(m) = m else { break };
        match m.message {
            Message::Subscribe { .. } | Message::Log(_) => return (m.offset, order),
            Message::Format(text) => {
                let text = text.to_string_lossy();
                let name = text.split(':').next().unwrap_or_default().to_owned();
                if seen.insert(name.clone()) {
                    order.push(name);
                }
            }
            _ => {}
        }
    }
    (bytes.len() as u64, order)
}

fn key_raw(kv: &KeyValue<'_>) -> KeyRaw {
    (kv.key.0.to_vec(), kv.raw.to_vec())
}

/// Where the log's bytes come from: each pass reads them anew.
#[derive(Debug, Clone, Copy)]
pub enum Input<'a> {
    /// A file, read in chunks.
    Path(&'a Path),
    /// The log's bytes.
    Bytes(&'a [u8]),
}

impl<'a> Input<'a> {
    fn source(self) -> Source<'a> {
        match self {
            Input::Path(p) => Source::file(p),
            Input::Bytes(b) => Source::from(b),
        }
    }

    fn len(self) -> u64 {
        match self {
            Input::Path(p) => std::fs::metadata(p).map_or(0, |m| m.len()),
            Input::Bytes(b) => b.len() as u64,
        }
    }
}

/// Why a log could not be loaded.
#[derive(Debug)]
pub enum LoadError {
    /// The reader's error.
    Read(ReadError),
    /// The passes that share the topics saw different logs: the file changed while
    /// it was read (a logger still writing it).
    Changed,
}

impl From<ReadError> for LoadError {
    fn from(e: ReadError) -> LoadError {
        LoadError::Read(e)
    }
}

/// Logs smaller than this are read on one thread: a second pass is not worth it.
pub const SHARE_FROM: u64 = 16 << 20;

/// Which of two passes packs each topic, balanced on the work of each in the first
/// fiftieth of the log (ulog-core's [`Shares`]).
fn shares(input: Input<'_>, len: u64) -> Result<Shares, ReadError> {
    let sample = (len / 50).max(1 << 20);
    let mut work: Vec<u64> = Vec::new();
    ulog_core::scan(
        input.source(),
        &ScanOptions::default(),
        |r: DataRecord<'_>| {
            if r.offset >= sample {
                return ControlFlow::Break(());
            }
            let i = r.topic.index();
            if i >= work.len() {
                work.resize(i + 1, 0);
            }
            // A row's cost: about fifty bytes' worth of framing and hand-out, then its bytes.
            work[i] += 48 + r.payload.len() as u64;
            ControlFlow::Continue(())
        },
    )?;
    Ok(Shares::new(&work, 2))
}

/// One pass: the tables of the topics `mine` gives it, and what the pass saw.
fn pass(
    input: Input<'_>,
    request: &Request,
    keep_metadata: bool,
    read_ahead: bool,
    mut mine: impl FnMut(usize) -> bool,
) -> Result<(ScanSummary, Vec<Option<Table>>), ReadError> {
    let wanted = |name: &str| {
        request.names.as_ref().is_none_or(|names| {
            names.iter().any(|n| match request.within {
                true => n.contains(name),
                false => n == name,
            })
        })
    };
    // With a filter, the time of a parameter change or dropout is the latest
    // timestamp of the loaded topics' rows before it (pyulog's running maximum),
    // not the whole log's. Topics named exactly: the pass keeps those times itself
    // (`ScanOptions::topics`). Named by a string that holds their names: here.
    let keep_times = request.names.is_some() && request.within;
    let len = input.len();
    // Per subscription index: its table, `None` when not loaded here.
    let mut tables: Vec<Option<Table>> = Vec::new();
    let mut seen: Vec<bool> = Vec::new();
    let mut options = ScanOptions::default()
        .keep_metadata(keep_metadata)
        .read_ahead(read_ahead);
    // Topics named exactly: the pass neither hands the others out nor reads their
    // times (one topic of a 302 MB log: 0.22 s → 0.12 s with the events decoded
    // when asked for; bench/README.md).
    if let (Some(names), false) = (&request.names, request.within) {
        options = options.topics(names.iter().cloned());
    }
    let summary = ulog_core::scan(input.source(), &options, |r: DataRecord<'_>| {
        if request.header_only {
            return ControlFlow::Break(());
        }
        let i = r.topic.index();
        if i >= seen.len() {
            seen.resize(i + 1, false);
            tables.resize_with(i + 1, || None);
        }
        if !seen[i] {
            seen[i] = true;
            if mine(i) && wanted(r.topic.name()) {
                tables[i] = Table::new(r.topic);
            }
        }
        if let Some(t) = &mut tables[i] {
            t.push(r.payload, r.offset, len, keep_times);
        }
        ControlFlow::Continue(())
    })?;
    Ok((summary, tables))
}

/// Reads the log of `input` as `request` asks: one pass that keeps the metadata and
/// packs the rows, or (every topic of a log of 16 MiB or more, `threads` 2 or more)
/// two passes on two threads, each packing its share of the topics: 0.37 s instead
/// of 0.8 s for every topic of a 302 MB log on two cores (the copy of 276 MB of rows
/// into fresh memory is most of the work, and each thread does half).
pub fn load(input: Input<'_>, request: &Request, threads: usize) -> Result<Loaded, LoadError> {
    let len = input.len();
    // A filter loads a few topics: a second pass would frame the log again for few
    // or none of them.
    let one_pass = request.header_only || request.names.is_some();
    let (mut summary, tables) = if one_pass || threads < 2 || len < request.share_from {
        // Reading ahead on a second thread: the one pass's chunks come sooner.
        pass(input, request, true, true, |_| true)?
    } else {
        let shares = shares(input, len)?;
        // Each pass its own copy: they take the same decisions.
        let mine = |k: usize| {
            let mut shares = shares.clone();
            move |i: usize| shares.owner(i) == k
        };
        let (first, second) = std::thread::scope(|s| {
            let other = s.spawn(|| pass(input, request, false, false, mine(1)));
            let first = pass(input, request, true, false, mine(0));
            // A panic of the other pass is a bug here: passed on.
            (
                first,
                other
                    .join()
                    .unwrap_or_else(|p| std::panic::resume_unwind(p)),
            )
        });
        let (summary, mut tables) = first?;
        let (other, theirs) = second?;
        if other.data_messages != summary.data_messages
            || other.topics.len() != summary.topics.len()
        {
            return Err(LoadError::Changed);
        }
        if tables.len() < theirs.len() {
            tables.resize_with(theirs.len(), || None);
        }
        for (mine, theirs) in tables.iter_mut().zip(theirs) {
            if mine.is_none() {
                *mine = theirs;
            }
        }
        (summary, tables)
    };
    let metadata = summary
        .metadata
        .take()
        .expect("kept: the pass was asked to keep the metadata");
    let (defs_end, format_order) = definitions(metadata.bytes());
    let log = if request.header_only {
        // The definitions alone, as a log of their own (they end on a message
        // boundary).
        ULog::parse(&metadata.bytes()[..defs_end as usize])?
    } else {
        metadata.log()?
    };
    let mut out = Loaded {
        version: summary.header.version,
        start_timestamp: summary.header.timestamp,
        // As pyulog: a file that ends inside a message (a log cut short) is not
        // corruption; `findings` still says so.
        corrupt: summary
            .findings
            .iter()
            .any(|f| f.is_damage() && f.kind != FindingKind::Truncated),
        findings: summary
            .findings
            .iter()
            .map(|f| (f.what(), f.offset, f.len, f.is_damage()))
            .collect(),
        ..Loaded::default()
    };
    if let Some(fb) = &summary.flag_bits {
        out.compat_flags = fb.compat_flags;
        out.incompat_flags = fb.incompat_flags;
        let mut offsets = fb.appended_offsets.to_vec();
        while offsets.last() == Some(&0) {
            offsets.pop();
        }
        out.appended_offsets = offsets;
    }
    // Formats in file order; any that come after data (allowed by the spec) after
    // them, by name.
    let mut formats: Vec<_> = format_order.iter().filter_map(|n| log.format(n)).collect();
    for f in log.formats() {
        if !format_order.contains(&f.name) {
            formats.push(f);
        }
    }
    out.formats = formats
        .into_iter()
        .map(|f| {
            let fields = f
                .fields
                .iter()
                .map(|fd| {
                    let ty = fd.ty.as_str().to_owned();
                    (ty, fd.array_len.unwrap_or(0), fd.name.clone())
                })
                .collect();
            (f.name.clone(), fields)
        })
        .collect();
    out.info = log.info().iter().map(key_raw).collect();
    out.info_multiple = log
        .multi_info()
        .iter()
        .map(|m| {
            m.entries
                .iter()
                .map(|e| e.iter().map(key_raw).collect())
                .collect()
        })
        .collect();
    out.initial_parameters = log.initial_params().iter().map(key_raw).collect();
    out.default_parameters = log
        .default_params()
        .iter()
        .map(|d| (d.default_types, d.kv.key.0.to_vec(), d.kv.raw.to_vec()))
        .collect();
    out.logged_messages = log
        .logged_messages()
        .iter()
        .map(|l| (l.raw_level, l.tag, l.timestamp, l.text.0.to_vec()))
        .collect();
    if request.header_only {
        out.last_timestamp = out.start_timestamp;
        return Ok(out);
    }
    out.utc = metadata.utc().map(|c| {
        let source = match c.source() {
            UtcSource::Gps { topic, samples } => format!("gps: {topic} ({samples} rows)"),
            UtcSource::BootTime => "boot_time_utc_us".to_owned(),
            other => format!("{other:?}"),
        };
        (c.boot_us(), source)
    });

    let mut running: Vec<(u64, u64)> = Vec::new();
    for (sub, table) in summary.topics.iter().zip(tables) {
        let Some(mut t) = table else { continue };
        running.append(&mut t.times);
        if t.rows.is_empty() {
            continue;
        }
        out.topics.push(TopicRows {
            name: sub.name().to_owned(),
            multi_id: sub.multi_id(),
            msg_id: sub.msg_id(),
            fields: t.fields,
            timestamp_idx: t.timestamp_idx,
            itemsize: t.itemsize,
            rows: t.rows,
        });
    }
    // Filtered by a string: the running maximum of the loaded topics' timestamps
    // (each row's offset with the latest so far); else as the pass kept them (the
    // whole log's, or the topics named's).
    let filtered = (request.names.is_some() && request.within).then(|| {
        running.sort_unstable_by_key(|&(offset, _)| offset);
        let mut latest = out.start_timestamp;
        for r in &mut running {
            latest = latest.max(r.1);
            r.1 = latest;
        }
        running
    });
    let time_at = |offset: u64, whole: u64| match &filtered {
        Some(running) => {
            let before = running.partition_point(|&(o, _)| o < offset);
            before
                .checked_sub(1)
                .map_or(out.start_timestamp, |i| running[i].1)
        }
        None => whole,
    };
    out.last_timestamp = time_at(u64::MAX, log.last_timestamp());
    out.changed_parameters = log
        .param_changes()
        .iter()
        .map(|c| {
            let t = time_at(c.offset, c.timestamp);
            (t, c.kv.key.0.to_vec(), c.kv.raw.to_vec())
        })
        .collect();
    out.dropouts = log
        .dropouts()
        .iter()
        .map(|d| (time_at(d.offset, d.timestamp), d.duration_ms))
        .collect();
    drop(log);
    out.events = Events(Some(metadata));
    Ok(out)
}
