//! `ulog messages`: the logged strings and PX4 events, as pyulog's `ulog_messages`
//! prints them.

use std::io::{self, BufWriter, Write};
use std::path::PathBuf;

use ulog_core::events::{EventFinding, EventOptions, Events, Metadata};
use ulog_core::read::LogLevel;
use ulog_core::{ULog, Value};

use crate::failure::{io_text, stdout_err, Failure};
use crate::input;

/// Print the logged strings (`L`), tagged logged strings (`C`) and PX4 events as
/// `H:MM:SS.mmm LEVEL: text`, like pyulog's `ulog_messages`.
///
/// For PX4 logs (`sys_name` is `PX4`), as ulog_messages does: the events of the
/// `event` topic are decoded with the metadata the log embeds (those of the
/// `default` group, below the protocol level, at their internal log level), the
/// logged strings that PX4 writes as copies of events (texts ending in a tab) are left
/// out, and everything is ordered by timestamp (events first where times are equal).
/// A log without event metadata has its events printed by id and raw arguments (a
/// line on stderr says so; `--events-json` takes PX4's `all_events.json.xz` or the
/// JSON), and keeps the copies, without their tab. Unlike ulog_messages, tagged
/// messages are printed too (`--no-tagged` leaves them out). Levels of logged
/// strings outside '0'..'7' print as UNKNOWN.
///
/// `--profile` chooses which `<profile>` parts of event messages show: `normal`
/// (what a ground station shows; the default) or `dev` (what ulog_messages shows).
#[derive(Debug, clap::Args)]
#[command(
    about = "Logged strings and events, as pyulog's ulog_messages prints them",
    long_about
)]
pub struct Args {
    /// The ULog file.
    file: PathBuf,
    /// Leave out tagged messages (`C`), as ulog_messages does.
    #[arg(long)]
    no_tagged: bool,
    /// Event metadata to decode events with (JSON, or xz-compressed JSON), instead of
    /// the log's.
    #[arg(long, value_name = "FILE")]
    events_json: Option<PathBuf>,
    /// The profile of event messages.
    #[arg(long, default_value = "normal", value_parser = ["normal", "dev"])]
    profile: String,
    /// Times as UTC (`2024-02-06T08:27:45.120Z`) instead of since boot, from the log's
    /// GPS time or its `boot_time_utc_us` (`ulog info` says which).
    #[arg(long)]
    utc: bool,
    #[arg(short = 'i', long, help = crate::pyulog::IGNORE_HELP)]
    ignore: bool,
}

pub fn run(args: &Args) -> Result<(), Failure> {
    let name = args.file.display().to_string();
    // One pass in chunks: the logged strings are metadata, the events' rows are kept
    // as it goes by (in the kept log, which is parsed once).
    let kept = input::keep(&args.file, &["event"], input::Times::Needed)?;
    let log = kept.log(&name)?;
    let mut options = EventOptions::default().profile(args.profile.clone());
    if let Some(path) = &args.events_json {
        let shown = path.display().to_string();
        let bytes = std::fs::read(path).map_err(|e| Failure::unreadable(&shown, io_text(&e)))?;
        let metadata = Metadata::from_bytes(&bytes).map_err(|e| Failure::about(&shown, e))?;
        options = options.metadata(metadata);
    }
    let (lines, findings) = lines(&log, || log.events(&options), args.no_tagged);
    let mut stderr = io::stderr();
    for f in &findings {
        let _ = writeln!(stderr, "ulog: {name}: {f}");
    }
    let utc = input::utc_of(&name, || kept.metadata.utc(), args.utc)?;
    let mut out = BufWriter::new(io::stdout().lock());
    for (t, level, text) in &lines {
        match &utc {
            Some(clock) => writeln!(out, "{:.3} {level}: {text}", clock.at(*t)),
            None => writeln!(out, "{}", line(*t, level, text)),
        }
        .map_err(stdout_err)?;
    }
    out.flush().map_err(stdout_err)
}

/// The messages `ulog messages` prints, as (timestamp, level name, text) in its order,
/// with what decoding the events found (printed by the caller). `events` gives the
/// log's events, decoded ([`ULog::events`], or those a pass kept), for a PX4 log.
pub fn lines(
    log: &ULog<'_>,
    events: impl FnOnce() -> Events,
    no_tagged: bool,
) -> (Vec<(u64, &'static str, String)>, Vec<EventFinding>) {
    // (timestamp, level, text), events first.
    let mut lines: Vec<(u64, &'static str, String)> = Vec::new();
    let mut findings = Vec::new();
    let px4 = matches!(log.info_value("sys_name"), Some(Value::Str(s)) if s.as_bytes() == b"PX4");
    let mut decoded = false;
    if px4 {
        let events = events();
        decoded = !events
            .findings
            .iter()
            .any(|f| matches!(f, EventFinding::NoMetadata | EventFinding::BadMetadata(_)));
        for e in events.iter().filter(|e| e.is_message()) {
            lines.push((e.timestamp, e.level_name(), e.text.clone()));
        }
        findings = events.findings;
    }
    for m in log.logged_messages() {
        if no_tagged && m.tag.is_some() {
            continue;
        }
        let text = m.text.to_string();
        let text = match (px4, text.strip_suffix('\t')) {
            // A copy of an event, which is printed decoded.
            (true, Some(_)) if decoded => continue,
            (true, Some(t)) => t.to_owned(),
            _ => text,
        };
        lines.push((m.timestamp, level_name(m.raw_level), text));
    }
    if px4 {
        lines.sort_by_key(|l| l.0); // stable, as Python's sort
    }
    (lines, findings)
}

/// `H:MM:SS.mmm LEVEL: text`.
fn line(timestamp: u64, level: &str, text: &str) -> String {
    let total_ms = timestamp / 1000;
    let s = total_ms / 1000;
    format!(
        "{}:{:02}:{:02}.{:03} {level}: {text}",
        s / 3600,
        s / 60 % 60,
        s % 60,
        total_ms % 1000,
    )
}

/// The level's name as pyulog prints it: PX4 writes ASCII digits; anything else is
/// `UNKNOWN` to pyulog.
pub fn level_name(raw: u8) -> &'static str {
    match raw {
        b'0'..=b'7' => LogLevel::from_raw(raw).map_or("UNKNOWN", LogLevel::name),
        _ => "UNKNOWN",
    }
}
