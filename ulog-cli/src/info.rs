//! `ulog info`: what pyulog's `ulog_info` shows, then what this reader found.

use std::collections::BTreeMap;
use std::io::{self, BufWriter, Write};
use std::path::PathBuf;

use serde_json::{json, Map, Value as Json};
use ulog_core::read::{FindingKind, KeyValue};
use ulog_core::{ULog, Value};

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
  duration_s           (last - start) / 1e6
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
                       unknown_message_type, unknown_msg_id, size_mismatch,
                       malformed, invalid_format, layout, redefined_format,
                       unknown_format, invalid_key, no_timestamp, other";

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
}

pub fn run(args: &Args) -> Result<(), Failure> {
    let mapped;
    let owned;
    let (name, bytes): (String, &[u8]) = match &args.file {
        Some(p) => {
            mapped = input::open(p)?;
            (p.display().to_string(), mapped.bytes())
        }
        None => {
            let _ = writeln!(
                io::stderr(),
                "ulog: no FILE given: showing the bundled sample log"
            );
            owned = ulog_core::testing::sample_log();
            ("<bundled sample>".to_owned(), &owned)
        }
    };
    let log = input::parse(&name, bytes)?;
    let mut out = BufWriter::new(io::stdout().lock());
    if args.json {
        let j = to_json(&name, &log);
        serde_json::to_writer_pretty(&mut out, &j).map_err(|e| Failure::io("stdout", &e.into()))?;
        writeln!(out).map_err(stdout_err)?;
    } else {
        write_text(&mut out, &log, args.verbose).map_err(stdout_err)?;
    }
    out.flush().map_err(stdout_err)
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
fn topic_rows(log: &ULog<'_>) -> Vec<TopicRow> {
    let mut rows: Vec<TopicRow> = log
        .topics()
        .filter(|t| !t.is_empty())
        .map(|t| TopicRow {
            name: t.name().to_owned(),
            multi_id: t.multi_id(),
            size: t.layout().map_or(0, |l| l.min_size()),
            points: t.len(),
        })
        .collect();
    rows.sort_by(|a, b| (&a.name, a.multi_id).cmp(&(&b.name, b.multi_id)));
    rows.sort_by_cached_key(|r| format!("{}{}", r.name, r.multi_id));
    rows
}

fn write_text(out: &mut impl Write, log: &ULog<'_>, verbose: bool) -> io::Result<()> {
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
    for r in topic_rows(log) {
        let name_id = format!("{} ({}, {})", r.name, r.multi_id, r.size);
        writeln!(
            out,
            " {name_id:<40} {:7} {:10}",
            r.points,
            r.size * r.points
        )?;
    }
    write_findings(out, log)
}

/// Multi-information by key, sorted; the entries of each key in file order.
fn multi_dict<'l, 'a>(log: &'l ULog<'a>) -> BTreeMap<&'l str, &'l [Vec<KeyValue<'a>>]> {
    log.multi_info()
        .iter()
        .map(|m| (m.name.as_str(), m.entries.as_slice()))
        .collect()
}

/// What ulog_info does not show: the reader's view of the file.
fn write_findings(out: &mut impl Write, log: &ULog<'_>) -> io::Result<()> {
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
    match log.utc() {
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

fn to_json(name: &str, log: &ULog<'_>) -> Json {
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
    let topics: Vec<Json> = topic_rows(log)
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
    let utc = log.utc();
    json!({
        "file": name,
        "file_version": log.version(),
        "start_timestamp": log.start_timestamp(),
        "last_timestamp": log.last_timestamp(),
        "duration_s": log.last_timestamp().saturating_sub(log.start_timestamp()) as f64 / 1e6,
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
