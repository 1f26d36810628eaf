//! `ulog info`: what pyulog's `ulog_info` shows, then what this reader found.

use std::collections::BTreeMap;
use std::io::{self, BufWriter, Write};
use std::path::PathBuf;

use serde_json::{json, Map, Value as Json};
use ulog_core::read::{
    FindingKind, KeyValue, MultiInfo, OutlierSide, SpanOutlier, TopicRows, UtcClock,
};
use ulog_core::{Source, ULog, Value};

use crate::describe::{kind_name, type_name, value_json};
use crate::failure::{stdout_err, Failure};
use crate::input;
use crate::pyfmt::{py_repr, py_str};

const JSON_KEYS: &str = "\
JSON keys (--json; stable, new keys may be added):
  file                 the file name (\"<bundled sample>\" without FILE)
  file_version         header version byte
  start_timestamp      header timestamp, microseconds
  last_timestamp       largest data timestamp, microseconds
  duration_s           (last - start) / 1e6, as ulog_info has it
  span                 the log's time span by the rule every output uses
                       (ulog_core's TimeSpan): {start_us, end_us, duration_s,
                       outliers: [{topic, multi_id, side (before_start, after_end),
                       rows, offset, earliest_us, latest_us}]}
  utc_start            UTC time of start_timestamp (RFC 3339, microseconds) or null
  utc_source           where it comes from (`ulog info` text) or null
  flag_bits            null (no flag bits message) or {compat_flags, incompat_flags,
                       appended_offsets} (arrays of 8, 8 and 3 numbers)
  appended_sections    file offsets where appended data starts
  sw_version           \"v1.14.0\" etc. as ulog_info shows it, or null
  info                 {key: value} (last value of each key; float as number)
  info_multiple        {key: [[part, ...], ...]}
  dropouts             {count, total_ms, max_ms}
  topics               [{name, multi_id, message_size, data_points, total_bytes}],
                       sorted as ulog_info sorts them
  message_count        messages framed
  logged_messages      number of L messages
  tagged_messages      number of C messages
  initial_parameters   number of parameters in the definitions
  changed_parameters   number of parameter changes in the data section
  default_parameters   number of default parameter messages
  sync_messages        number of sync messages
  unknown_messages     [{offset, type, size}]
  truncated            whether the file ends inside a message
  corrupted            whether pyulog would report data corruption
  findings             [{kind, offset, len, text}]; kind is one of newer_version,
                       misplaced_flag_bits, long_flag_bits, unknown_compat_flags,
                       invalid_appended_offset, appended_flag_without_offsets,
                       appended_offsets_without_flag, appended_data,
                       partial_before_appended, truncated, corrupt_zero_size,
                       corrupt_bad_header, corrupt_zero_fill, corrupt_overrun,
                       corrupt_cut_by_zero_fill, unknown_message_type,
                       unknown_msg_id, size_mismatch, malformed, invalid_format,
                       layout, redefined_format, unknown_format, invalid_key,
                       no_timestamp, other";

/// Show what a log holds, in pyulog's `ulog_info` layout (start time and duration,
/// dropouts, software version, information, multi-information, and the table of topics
/// with their message sizes and data points), then what this reader found: file
/// version, flag bits, appended sections, truncation, every corruption with its byte
/// range, unknown messages.
///
/// Without FILE, shows the small sample log bundled with the tool.
#[derive(Debug, clap::Args)]
#[command(
    about = "What a log holds, as pyulog's ulog_info shows it, and its damage",
    long_about,
    after_help = JSON_KEYS
)]
pub struct Args {
    /// The ULog file (default: the bundled sample log).
    file: Option<PathBuf>,
    /// Print one JSON object instead (keys below).
    #[arg(long)]
    json: bool,
    /// Also show `perf_*` information and the multi-information values.
    #[arg(short, long)]
    verbose: bool,
    /// Only the multi-information of this key, each entry under a `# KEY N:` line, as
    /// ulog_info's `-m` prints it (text as it is, other values as hex bytes).
    #[arg(
        short = 'm',
        long = "message",
        value_name = "KEY",
        conflicts_with_all = ["json", "verbose"]
    )]
    message: Option<String>,
    /// With `--message`: a line break between an entry's continued parts (ulog_info's
    /// `-n`).
    #[arg(short = 'n', long, requires = "message")]
    newline: bool,
    #[arg(short = 'i', long, help = crate::pyulog::IGNORE_HELP)]
    ignore: bool,
}

pub fn run(args: &Args) -> Result<(), Failure> {
    // One pass in chunks: the metadata, and each topic's rows counted.
    let (name, kept) = match &args.file {
        Some(p) => (
            p.display().to_string(),
            input::keep(p, &[], input::Times::Every)?,
        ),
        None => {
            let _ = writeln!(
                io::stderr(),
                "ulog: no FILE given: showing the bundled sample log"
            );
            let name = "<bundled sample>".to_owned();
            let bytes = ulog_core::testing::sample_log();
            let kept =
                input::keep_from(Source::from(&bytes), None, &name, &[], input::Times::Every)?;
            (name, kept)
        }
    };
    let log = kept.log(&name)?;
    let shown = Shown {
        log: &log,
        rows: kept.metadata.topics(),
        utc: kept.metadata.utc(),
    };
    let mut out = BufWriter::new(io::stdout().lock());
    if let Some(key) = &args.message {
        let Some(multi) = log.multi_info().iter().find(|m| m.name == *key) else {
            let mut keys: Vec<String> = log
                .multi_info()
                .iter()
                .map(|m| format!("`{}`", m.name))
                .collect();
            keys.sort();
            let have = match keys.is_empty() {
                true => "it has none".to_owned(),
                false => format!("its keys: {}", keys.join(", ")),
            };
            return Err(Failure::unknown_name(
                &name,
                format!("no multi-information `{key}` in the log ({have})"),
            ));
        };
        write_multi(&mut out, multi, args.newline).map_err(stdout_err)?;
        return out.flush().map_err(stdout_err);
    }
    if args.json {
        let j = to_json(&name, &shown);
        serde_json::to_writer_pretty(&mut out, &j).map_err(|e| Failure::io("stdout", &e.into()))?;
        writeln!(out).map_err(stdout_err)?;
    } else {
        write_text(&mut out, &shown, args.verbose).map_err(stdout_err)?;
    }
    out.flush().map_err(stdout_err)
}

/// What `info` shows: the log kept without its data, with what the pass counted of
/// the data.
struct Shown<'l, 'a> {
    log: &'l ULog<'a>,
    /// Per subscription, its rows.
    rows: &'l [TopicRows],
    utc: Option<UtcClock>,
}

/// Whether pyulog sets `file_corruption` for this log: damage other than the end of
/// the file (pyulog just stops there).
pub fn pyulog_corruption(log: &ULog<'_>) -> bool {
    log.findings().iter().any(|f| {
        f.is_damage()
            && !matches!(
                f.kind,
                FindingKind::Truncated | FindingKind::PartialBeforeAppended
            )
    })
}

/// `h:mm:ss` of whole seconds.
fn hms(us: u64) -> String {
    let s = us / 1_000_000;
    format!("{}:{:02}:{:02}", s / 3600, s / 60 % 60, s % 60)
}

/// The information dictionary: last value per key, sorted by key.
fn info_dict<'a>(log: &ULog<'a>) -> BTreeMap<String, Value<'a>> {
    log.info()
        .iter()
        .map(|kv| (kv.name().into_owned(), kv.value()))
        .collect()
}

/// `v1.14.0 (RC)` as ulog_info shows it; nothing for development versions.
fn sw_version(log: &ULog<'_>) -> Option<String> {
    let v = log.release_version("ver_sw_release")?;
    (v.kind >= 64).then(|| v.to_string())
}

struct TopicRow {
    name: String,
    multi_id: u8,
    size: usize,
    points: usize,
}

/// The topic table's rows, sorted as ulog_info sorts them (by name and multi_id
/// concatenated as text). Topics without data are left out, as pyulog does; the
/// message size is the format's without trailing padding.
fn topic_rows(shown: &Shown<'_, '_>) -> Vec<TopicRow> {
    let points = |i: usize| shown.rows.get(i).map_or(0, |r| r.rows as usize);
    let mut rows: Vec<TopicRow> = shown
        .log
        .topics()
        .filter(|t| points(t.subscription().index()) > 0)
        .map(|t| TopicRow {
            name: t.name().to_owned(),
            multi_id: t.multi_id(),
            size: t.layout().map_or(0, |l| l.min_size()),
            points: points(t.subscription().index()),
        })
        .collect();
    rows.sort_by(|a, b| (&a.name, a.multi_id).cmp(&(&b.name, b.multi_id)));
    rows.sort_by_cached_key(|r| format!("{}{}", r.name, r.multi_id));
    rows
}

fn write_text(out: &mut impl Write, shown: &Shown<'_, '_>, verbose: bool) -> io::Result<()> {
    let log = shown.log;
    if pyulog_corruption(log) {
        writeln!(out, "Warning: file has data corruption(s)")?;
    }
    let start = log.start_timestamp();
    writeln!(
        out,
        "Logging start time: {}, duration: {}",
        hms(start),
        hms(log.last_timestamp().saturating_sub(start))
    )?;
    let d: Vec<u64> = log
        .dropouts()
        .iter()
        .map(|d| u64::from(d.duration_ms))
        .collect();
    if d.is_empty() {
        writeln!(out, "No Dropouts")?;
    } else {
        let sum: u64 = d.iter().sum();
        writeln!(
            out,
            "Dropouts: count: {}, total duration: {:.1} s, max: {} ms, mean: {} ms",
            d.len(),
            sum as f64 / 1000.0,
            d.iter().max().unwrap_or(&0),
            sum / d.len() as u64
        )?;
    }
    if let Some(v) = sw_version(log) {
        writeln!(out, "SW Version: {v}")?;
    }
    writeln!(out, "Info Messages:")?;
    for (k, v) in info_dict(log) {
        if !k.starts_with("perf_") || verbose {
            writeln!(out, " {k}: {}", py_str(&v))?;
        }
    }
    let multi = multi_dict(log);
    if !multi.is_empty() {
        if verbose {
            writeln!(out, "Info Multiple Messages:")?;
            for (k, entries) in &multi {
                let lists: Vec<String> = entries
                    .iter()
                    .map(|parts| {
                        let items: Vec<String> =
                            parts.iter().map(|kv| py_repr(&kv.value())).collect();
                        format!("[{}]", items.join(", "))
                    })
                    .collect();
                writeln!(out, " {k}: [{}]", lists.join(", "))?;
            }
        } else {
            let items: Vec<String> = multi
                .iter()
                .map(|(k, e)| format!("[{k}: {}]", e.len()))
                .collect();
            writeln!(out, "Info Multiple Messages: {}", items.join(", "))?;
        }
    }
    writeln!(out)?;
    writeln!(
        out,
        "{:<41} {:7}, {:10}",
        "Name (multi id, message size in bytes)", "number of data points", "total bytes"
    )?;
    for r in topic_rows(shown) {
        let name_id = format!("{} ({}, {})", r.name, r.multi_id, r.size);
        writeln!(
            out,
            " {name_id:<40} {:7} {:10}",
            r.points,
            r.size * r.points
        )?;
    }
    write_findings(out, shown)
}

/// The entries of one multi-information key as ulog_info's `-m` prints them: per
/// entry a `# KEY N:` line, then its parts joined (by a line break with `newline`,
/// else by nothing): text as it is; values of other types as their bytes in hex
/// (`fd 37 7a`), the line saying how many bytes the entry has, as for pyulog's
/// `bytes` values (arrays, `char`, values it cannot decode). Numbers and booleans,
/// which ulog_info cannot join (it stops with a `TypeError`), print as Python shows them.
fn write_multi(out: &mut impl Write, multi: &MultiInfo<'_>, newline: bool) -> io::Result<()> {
    let separator = if newline { "\n" } else { "" };
    let key = &multi.name;
    for (i, parts) in multi.entries.iter().enumerate() {
        let is_bytes = |kv: &KeyValue<'_>| {
            matches!(
                kv.value(),
                Value::Array(_) | Value::Bytes(_) | Value::Char(_)
            )
        };
        // ulog_info looks at the first part to choose.
        if parts.first().is_some_and(is_bytes) {
            let len: usize = parts.iter().map(|kv| kv.raw.len()).sum();
            writeln!(out, "# {key} {i} (len: {len}):")?;
            let hex: Vec<String> = parts
                .iter()
                .map(|kv| {
                    let bytes: Vec<String> = kv.raw.iter().map(|b| format!("{b:02x}")).collect();
                    bytes.join(" ")
                })
                .collect();
            writeln!(out, "{}", hex.join(separator))?;
        } else {
            writeln!(out, "# {key} {i}:")?;
            let text: Vec<String> = parts.iter().map(|kv| py_str(&kv.value())).collect();
            writeln!(out, "{}", text.join(separator))?;
        }
    }
    Ok(())
}

/// The log's span and the rows far outside it, one line each: where the plots, the
/// MCAP file and the dataset put the log's start and end, and why a stale or stray
/// row does not stretch them.
fn write_span(out: &mut impl Write, log: &ULog<'_>) -> io::Result<()> {
    let span = log.span();
    writeln!(
        out,
        "Time span: {} to {} ({:.3} s){}",
        hms(span.start()),
        hms(span.end()),
        span.duration_s(),
        match span.outliers().len() {
            0 => String::new(),
            n => format!("; {n} topic instance(s) with rows far outside it:"),
        }
    )?;
    for o in span.outliers() {
        let topic = outlier_topic(log, o);
        let rows = if o.rows == 1 { "row" } else { "rows" };
        let what = match o.side {
            OutlierSide::BeforeStart if o.latest == 0 => "stamped 0 (never set)".to_owned(),
            OutlierSide::BeforeStart => format!(
                "stamped up to {:.1} s before the start",
                (span.start() - o.earliest) as f64 / 1e6
            ),
            _ => format!(
                "stamped up to {:.1} s after the end",
                o.latest.saturating_sub(span.end()) as f64 / 1e6
            ),
        };
        writeln!(
            out,
            "  {}({}): {} {rows} {what}, first at byte {}",
            topic.0, topic.1, o.rows, o.offset
        )?;
    }
    Ok(())
}

/// The topic name and multi id of an outlier's subscription.
fn outlier_topic(log: &ULog<'_>, o: &SpanOutlier) -> (String, u8) {
    log.subscriptions()
        .get(o.subscription)
        .map(|s| (s.name().to_owned(), s.multi_id()))
        .unwrap_or_else(|| (format!("subscription {}", o.subscription), 0))
}

/// `span` of `--json`.
fn span_json(log: &ULog<'_>) -> Json {
    let span = log.span();
    let outliers: Vec<Json> = span
        .outliers()
        .iter()
        .map(|o| {
            let (topic, multi_id) = outlier_topic(log, o);
            json!({
                "topic": topic,
                "multi_id": multi_id,
                "side": match o.side {
                    OutlierSide::BeforeStart => "before_start",
                    _ => "after_end",
                },
                "rows": o.rows,
                "offset": o.offset,
                "earliest_us": o.earliest,
                "latest_us": o.latest,
            })
        })
        .collect();
    json!({
        "start_us": span.start(),
        "end_us": span.end(),
        "duration_s": span.duration_s(),
        "outliers": outliers,
    })
}

/// Multi-information by key, sorted; the entries of each key in file order.
fn multi_dict<'l, 'a>(log: &'l ULog<'a>) -> BTreeMap<&'l str, &'l [Vec<KeyValue<'a>>]> {
    log.multi_info()
        .iter()
        .map(|m| (m.name.as_str(), m.entries.as_slice()))
        .collect()
}

/// What ulog_info does not show: the reader's view of the file.
fn write_findings(out: &mut impl Write, shown: &Shown<'_, '_>) -> io::Result<()> {
    let log = shown.log;
    writeln!(out)?;
    writeln!(out, "File version: {}", log.version())?;
    match log.flag_bits() {
        Some(f) => writeln!(
            out,
            "Flag bits: compat {:?}, incompat {:?}, appended offsets {:?}",
            f.compat_flags, f.incompat_flags, f.appended_offsets
        )?,
        None => writeln!(out, "Flag bits: none")?,
    }
    let appended = log.appended_sections();
    if !appended.is_empty() {
        let list: Vec<String> = appended.iter().map(u64::to_string).collect();
        writeln!(out, "Appended data at bytes: {}", list.join(", "))?;
    }
    match &shown.utc {
        Some(clock) => writeln!(
            out,
            "UTC start: {:.0} (from {})",
            clock.at(log.start_timestamp()),
            clock.source()
        )?,
        None => writeln!(
            out,
            "UTC start: unknown (no GPS time, no boot_time_utc_us information)"
        )?,
    }
    write_span(out, log)?;
    let tagged = log
        .logged_messages()
        .iter()
        .filter(|m| m.tag.is_some())
        .count();
    writeln!(
        out,
        "Messages: {} ({} logged, {} tagged, {} parameter changes, {} sync)",
        log.message_count(),
        log.logged_messages().len() - tagged,
        tagged,
        log.param_changes().len(),
        log.sync_count()
    )?;
    let unknown = log.unknown_messages();
    if !unknown.is_empty() {
        let mut types: Vec<u8> = unknown.iter().map(|u| u.msg_type).collect();
        types.sort_unstable();
        types.dedup();
        let names: Vec<String> = types.iter().map(|&t| type_name(t)).collect();
        writeln!(
            out,
            "Unknown messages: {} (types {})",
            unknown.len(),
            names.join(", ")
        )?;
    }
    writeln!(
        out,
        "Truncated: {}",
        if log.is_truncated() { "yes" } else { "no" }
    )?;
    let findings = log.findings();
    if findings.is_empty() {
        writeln!(out, "Findings: none")?;
    } else {
        writeln!(out, "Findings: {}", findings.len())?;
        for f in findings {
            writeln!(out, " {f}")?;
        }
    }
    Ok(())
}

fn to_json(name: &str, shown: &Shown<'_, '_>) -> Json {
    let log = shown.log;
    let info: Map<String, Json> = info_dict(log)
        .iter()
        .map(|(k, v)| (k.clone(), value_json(v)))
        .collect();
    let multi: Map<String, Json> = multi_dict(log)
        .iter()
        .map(|(k, entries)| {
            let e: Vec<Json> = entries
                .iter()
                .map(|parts| Json::Array(parts.iter().map(|kv| value_json(&kv.value())).collect()))
                .collect();
            ((*k).to_owned(), Json::Array(e))
        })
        .collect();
    let topics: Vec<Json> = topic_rows(shown)
        .iter()
        .map(|r| {
            json!({
                "name": r.name, "multi_id": r.multi_id, "message_size": r.size,
                "data_points": r.points, "total_bytes": r.size * r.points,
            })
        })
        .collect();
    let drop: Vec<u64> = log
        .dropouts()
        .iter()
        .map(|d| u64::from(d.duration_ms))
        .collect();
    let tagged = log
        .logged_messages()
        .iter()
        .filter(|m| m.tag.is_some())
        .count();
    let findings: Vec<Json> = log
        .findings()
        .iter()
        .map(|f| json!({"kind": kind_name(f), "offset": f.offset, "len": f.len, "count": f.count, "text": f.to_string()}))
        .collect();
    let unknown: Vec<Json> = log
        .unknown_messages()
        .iter()
        .map(|u| json!({"offset": u.offset, "type": u.msg_type, "size": u.payload.len()}))
        .collect();
    let utc = &shown.utc;
    json!({
        "file": name,
        "file_version": log.version(),
        "start_timestamp": log.start_timestamp(),
        "last_timestamp": log.last_timestamp(),
        "duration_s": log.last_timestamp().saturating_sub(log.start_timestamp()) as f64 / 1e6,
        "span": span_json(log),
        "utc_start": utc.as_ref().map(|c| c.at(log.start_timestamp()).to_string()),
        "utc_source": utc.as_ref().map(|c| c.source().to_string()),
        "flag_bits": log.flag_bits().map(|f| json!({
            "compat_flags": f.compat_flags,
            "incompat_flags": f.incompat_flags,
            "appended_offsets": f.appended_offsets,
        })),
        "appended_sections": log.appended_sections(),
        "sw_version": sw_version(log),
        "info": info,
        "info_multiple": multi,
        "dropouts": {
            "count": drop.len(),
            "total_ms": drop.iter().sum::<u64>(),
            "max_ms": drop.iter().max().copied().unwrap_or(0),
        },
        "topics": topics,
        "message_count": log.message_count(),
        "logged_messages": log.logged_messages().len() - tagged,
        "tagged_messages": tagged,
        "initial_parameters": log.initial_params().len(),
        "changed_parameters": log.param_changes().len(),
        "default_parameters": log.default_params().len(),
        "sync_messages": log.sync_count(),
        "unknown_messages": unknown,
        "truncated": log.is_truncated(),
        "corrupted": pyulog_corruption(log),
        "findings": findings,
    })
}
