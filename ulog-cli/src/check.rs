//! `ulog check`: spec conformance and damage report for each file, with a summary line
//! per file and an exit status for scripts.

use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

use serde_json::{json, Value as Json};
use ulog_core::events::{EventFinding, EventOptions};
use ulog_core::read::{FindingKind, OutlierSide, Unwrapper};
use ulog_core::ULog;

use crate::describe::kind_name;
use crate::failure::{stdout_err, Failure, Status};
use crate::input;
use crate::progress::Progress;

const AFTER_HELP: &str = "\
Severities:
  error    data was lost or cannot be read as logged: truncation, corrupt byte ranges,
           data for unknown msg_ids, size mismatches, malformed messages, formats that
           do not parse or cannot be laid out
  warning  departures from the spec that lose nothing: unknown message types, no flag
           bits message in a version 1 log, redefined formats, subscriptions to unknown
           formats, timestamps that go backwards or jump (per topic instance), invalid
           log levels, unknown compatible flag bits, bad appended offsets, the
           DEFAULT_PARAMETERS flag with no default parameter logged
           PX4 event metadata that cannot be used, events it does not define
  note     facts worth knowing: dropouts, appended data, events without metadata in
           the log, events logged at error level or worse, rows stamped far outside
           the log's time span (stamped_before_start, stamped_after_end,
           timestamp_unset: `ulog info` says what the span is)
Exit status: 0 when every file is free of errors and warnings, 1 when one has any,
3 when a file cannot be read, 4 when one is not a ULog log (the highest applies).

JSON (--json): {\"files\": [{file, status (ok, warnings, damaged, refused, unreadable),
error (refused/unreadable only), messages, topics, duration_s (the log's span), errors, warnings, notes,
problems: [{severity, kind, offset, len, topic, multi_id, text}]}], \"exit_status\": N}";

/// Check each log against the ULog spec and report its damage: truncation, corruption
/// with byte ranges, unknown message types, size mismatches, formats that do not parse,
/// timestamps that go backwards or jump per topic, and more (see below). Prints a
/// summary line per file, then its problems.
#[derive(Debug, clap::Args)]
#[command(
    about = "Check logs against the ULog spec and report their damage",
    long_about,
    after_help = AFTER_HELP
)]
pub struct Args {
    /// ULog files, or directories: every `.ulg` and `.ulog` file (any case) in a
    /// directory and its subdirectories is checked.
    #[arg(required = true, value_name = "FILE_OR_DIR")]
    files: Vec<PathBuf>,
    /// Print one JSON document instead (keys below).
    #[arg(long)]
    json: bool,
    /// Only the summary line of each file.
    #[arg(short, long, conflicts_with = "json")]
    brief: bool,
    /// Every problem (text output shows at most 5 of each kind per file).
    #[arg(long, conflicts_with = "brief")]
    all: bool,
}

/// How bad a problem is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Severity {
    Error,
    Warning,
    Note,
}

impl Severity {
    fn name(self) -> &'static str {
        match self {
            Severity::Error => "error",
            Severity::Warning => "warning",
            Severity::Note => "note",
        }
    }
}

/// One thing found in a file.
#[derive(Debug, Clone)]
pub struct Problem {
    pub severity: Severity,
    pub kind: &'static str,
    pub offset: Option<u64>,
    pub len: Option<u64>,
    pub topic: Option<(String, u8)>,
    pub text: String,
}

impl Problem {
    fn new(severity: Severity, kind: &'static str, text: String) -> Problem {
        Problem {
            severity,
            kind,
            offset: None,
            len: None,
            topic: None,
            text,
        }
    }

    fn at(mut self, offset: u64) -> Problem {
        self.offset = Some(offset);
        self
    }
}

/// A timestamp gap counts as a jump to nonsense when longer than an hour and than
/// `JUMP_FACTOR` times the topic's median gap (a topic that is quiet for a minute is
/// normal; one that leaps by hours, or from 0 to a Unix time, is not).
const JUMP_MIN_US: u64 = 3_600_000_000;
const JUMP_FACTOR: u64 = 1000;

/// Lines of one kind shown per file in text output, unless `--all`.
const SHOWN_PER_KIND: usize = 5;

/// Everything `check` reports about a parsed log, most severe first, then by offset.
pub fn examine(log: &ULog<'_>) -> Vec<Problem> {
    let mut out = Vec::new();
    for f in log.findings() {
        let severity = match &f.kind {
            _ if f.is_damage() => Severity::Error,
            FindingKind::InvalidFormat(_) | FindingKind::Layout(_) => Severity::Error,
            FindingKind::AppendedData | FindingKind::LongFlagBits(_) => Severity::Note,
            _ => Severity::Warning,
        };
        let mut p = Problem::new(severity, kind_name(f), f.what()).at(f.offset);
        p.len = Some(f.len);
        out.push(p);
    }
    if log.version() >= 1 && log.flag_bits().is_none() {
        out.push(Problem::new(
            Severity::Warning,
            "no_flag_bits",
            "no flag bits message: the spec requires one first in a version 1 log".into(),
        ));
    }
    for m in log.logged_messages() {
        if m.level().is_none() {
            out.push(
                Problem::new(
                    Severity::Warning,
                    "invalid_log_level",
                    format!(
                        "logged message with level byte {:#04x}, not '0'..'7'",
                        m.raw_level
                    ),
                )
                .at(m.offset),
            );
        }
    }
    timestamp_problems(log, &mut out);
    span_problems(log, &mut out);
    let drops = log.dropouts();
    if !drops.is_empty() {
        let total: u64 = drops.iter().map(|d| u64::from(d.duration_ms)).sum();
        let max = drops.iter().map(|d| d.duration_ms).max().unwrap_or(0);
        out.push(
            Problem::new(
                Severity::Note,
                "dropouts",
                format!(
                    "{} dropouts, {total} ms of data lost in all (longest {max} ms)",
                    drops.len()
                ),
            )
            .at(drops[0].offset),
        );
    }
    defaults_problem(log, &mut out);
    events_problems(log, &mut out);
    out.sort_by_key(|p| (p.severity, p.offset.unwrap_or(0)));
    out
}

/// PX4 events: what could not be decoded (metadata missing is a note, bad metadata
/// and undefined events are warnings), and the events shown as messages
/// ([`Event::is_message`](ulog_core::events::Event::is_message)) logged at error level
/// or worse, as notes with their text.
fn events_problems(log: &ULog<'_>, out: &mut Vec<Problem>) {
    let events = log.events(&EventOptions::default());
    for f in &events.findings {
        let (severity, kind) = match f {
            EventFinding::NoMetadata => (Severity::Note, "no_event_metadata"),
            EventFinding::BadMetadata(_) => (Severity::Warning, "bad_event_metadata"),
            EventFinding::UnknownId { .. } => (Severity::Warning, "unknown_event"),
            _ => (Severity::Warning, "bad_event"),
        };
        out.push(Problem::new(severity, kind, f.to_string()));
    }
    let topic = log.topic("event", 0).ok();
    for e in events.iter().filter(|e| e.is_message() && e.level <= 3) {
        let mut p = Problem::new(
            Severity::Note,
            "event_error",
            format!(
                "{} at {:.3} s: {}",
                e.level_name(),
                seconds(log, e.timestamp),
                e.text
            ),
        );
        p.offset = topic.as_ref().and_then(|t| t.message_offsets().get(e.row));
        out.push(p);
    }
}

/// Seconds of `timestamp` since the log's start (its span's).
fn seconds(log: &ULog<'_>, timestamp: u64) -> f64 {
    timestamp.saturating_sub(log.span().start()) as f64 / 1e6
}

/// Rows far outside the log's span ([`ulog_core::read::TimeSpan`]): notes, as the
/// rows are data like any other (kept, and read by every reader); the note says why
/// time axes place them at the start or leave them out.
fn span_problems(log: &ULog<'_>, out: &mut Vec<Problem>) {
    let subscriptions = log.subscriptions();
    for o in log.span().outliers() {
        let Some(sub) = subscriptions.get(o.subscription) else {
            continue;
        };
        let id = format!("{}({})", sub.name(), sub.multi_id());
        let rows = match o.rows {
            1 => "1 row".to_owned(),
            n => format!("{n} rows"),
        };
        let stamped = match (o.earliest, o.latest) {
            (0, 0) => "stamped 0 (never set)".to_owned(),
            (a, b) if a == b => format!("stamped {a} us"),
            (a, b) => format!("stamped {a} to {b} us"),
        };
        let (kind, text) = match o.side {
            OutlierSide::BeforeStart if o.latest == 0 => (
                "timestamp_unset",
                format!("{id}: {rows} {stamped}; time axes leave them out"),
            ),
            OutlierSide::BeforeStart => (
                "stamped_before_start",
                format!(
                    "{id}: {rows} {stamped}, {:.1} s before the log's start at {} us \
                     (values made before logging began); time axes place them at the start",
                    o.earliest.abs_diff(log.span().start()) as f64 / 1e6,
                    log.span().start()
                ),
            ),
            _ => (
                "stamped_after_end",
                format!(
                    "{id}: {rows} {stamped}, beyond the log's span (which ends at {} us); \
                     time axes leave them out",
                    log.span().end()
                ),
            ),
        };
        let mut p = Problem::new(Severity::Note, kind, text).at(o.offset);
        p.topic = Some((sub.name().to_owned(), sub.multi_id()));
        out.push(p);
    }
}

/// The one departure about defaults: the `DEFAULT_PARAMETERS` flag set with no default
/// logged. A log with defaults for only some parameters, or none without the flag, is
/// what the spec allows (a parameter's default is then its value): not a finding.
fn defaults_problem(log: &ULog<'_>, out: &mut Vec<Problem>) {
    let flagged = log.flag_bits().is_some_and(|f| f.has_default_parameters());
    if flagged && log.default_params().is_empty() {
        out.push(Problem::new(
            Severity::Warning,
            "no_default_parameters",
            "the DEFAULT_PARAMETERS flag is set but no default parameter is logged".into(),
        ));
    }
}

/// Per topic instance: timestamps that go backwards, and jumps far beyond the topic's
/// usual interval.
fn timestamp_problems(log: &ULog<'_>, out: &mut Vec<Problem>) {
    for topic in log.topics() {
        let Some(field) = topic.timestamp_field() else {
            continue;
        };
        let mut u = Unwrapper::new(Some(field));
        let stamps: Vec<(u64, u64)> = topic
            .payloads()
            .zip(topic.message_offsets())
            .filter_map(|(p, o)| u.push(p).map(|t| (t, o)))
            .collect();
        if stamps.len() < 2 {
            continue;
        }
        let mut gaps: Vec<u64> = stamps
            .windows(2)
            .filter_map(|w| w[1].0.checked_sub(w[0].0))
            .collect();
        let median = if gaps.is_empty() {
            0
        } else {
            let mid = gaps.len() / 2;
            *gaps.select_nth_unstable(mid).1
        };
        let jump_limit = JUMP_MIN_US.max(median.saturating_mul(JUMP_FACTOR));
        let (mut back, mut first_back) = (0usize, None);
        let (mut jumps, mut first_jump) = (0usize, None);
        for w in stamps.windows(2) {
            let ((t0, _), (t1, o1)) = (w[0], w[1]);
            if t1 < t0 {
                back += 1;
                first_back.get_or_insert((o1, t0, t1));
            } else if t1 - t0 > jump_limit {
                jumps += 1;
                first_jump.get_or_insert((o1, t0, t1));
            }
        }
        let id = format!("{}({})", topic.name(), topic.multi_id());
        let mut warn = |kind, offset, text: String| {
            let mut p = Problem::new(Severity::Warning, kind, format!("{id}: {text}")).at(offset);
            p.topic = Some((topic.name().to_owned(), topic.multi_id()));
            out.push(p);
        };
        if let Some((o, t0, t1)) = first_back {
            warn(
                "timestamp_backwards",
                o,
                format!("timestamps go backwards {back} time(s), first from {t0} to {t1} us"),
            );
        }
        if let Some((o, t0, t1)) = first_jump {
            warn(
                "timestamp_jump",
                o,
                format!(
                    "timestamps jump forward {jumps} time(s), first by {:.1} s (from {t0} to {t1} us; usual interval {median} us)",
                    (t1 - t0) as f64 / 1e6
                ),
            );
        }
    }
}

/// The outcome for one file.
struct Report {
    file: String,
    status: Status,
    error: Option<String>,
    summary: Option<(u64, usize, f64)>,
    problems: Vec<Problem>,
}

impl Report {
    fn count(&self, s: Severity) -> usize {
        self.problems.iter().filter(|p| p.severity == s).count()
    }

    fn status_name(&self) -> &'static str {
        match self.status {
            Status::Io => "unreadable",
            Status::Refused => "refused",
            _ if self.count(Severity::Error) > 0 => "damaged",
            _ if self.count(Severity::Warning) > 0 => "warnings",
            _ => "ok",
        }
    }
}

/// The report of an input that could not be read or is not a log.
fn failed(file: String, f: Failure) -> Report {
    let (status, error) = match f {
        Failure::Message(s, m) => {
            let prefix = format!("{file}: ");
            (s, m.strip_prefix(&prefix).map_or(m.clone(), str::to_owned))
        }
        Failure::BrokenPipe => (Status::Other, "broken pipe".to_owned()),
    };
    Report {
        file,
        status,
        error: Some(error),
        summary: None,
        problems: Vec::new(),
    }
}

fn check_file(path: &Path) -> Report {
    let file = path.display().to_string();
    let failed = |f: Failure| failed(file.clone(), f);
    let mapped = match input::open(path) {
        Ok(m) => m,
        Err(f) => return failed(f),
    };
    let log = match input::parse(&file, mapped.bytes()) {
        Ok(l) => l,
        Err(f) => return failed(f),
    };
    let problems = examine(&log);
    let status = if problems.iter().any(|p| p.severity != Severity::Note) {
        Status::Findings
    } else {
        Status::Ok
    };
    let duration = log.span().duration_s();
    Report {
        file,
        status,
        error: None,
        summary: Some((log.message_count(), log.topics().count(), duration)),
        problems,
    }
}

fn plural(n: usize, word: &str) -> String {
    if n == 1 {
        format!("1 {word}")
    } else {
        format!("{n} {word}s")
    }
}

fn write_text(out: &mut impl Write, r: &Report, brief: bool, all: bool) -> io::Result<()> {
    if let Some(e) = &r.error {
        return writeln!(out, "{}: {} ({e})", r.file, r.status_name());
    }
    let (messages, topics, duration) = r.summary.unwrap_or_default();
    let counts = [
        (r.count(Severity::Error), "error"),
        (r.count(Severity::Warning), "warning"),
        (r.count(Severity::Note), "note"),
    ]
    .iter()
    .filter(|(n, _)| *n > 0)
    .map(|(n, w)| plural(*n, w))
    .collect::<Vec<_>>();
    let counts = if counts.is_empty() {
        String::new()
    } else {
        format!(", {}", counts.join(", "))
    };
    writeln!(
        out,
        "{}: {} ({messages} messages, {topics} topics, {duration:.1} s{counts})",
        r.file,
        r.status_name()
    )?;
    if brief {
        return Ok(());
    }
    let mut shown: std::collections::HashMap<&str, usize> = std::collections::HashMap::new();
    for p in &r.problems {
        let n = shown.entry(p.kind).or_default();
        *n += 1;
        if !all && *n > SHOWN_PER_KIND {
            continue;
        }
        match p.offset {
            Some(o) => writeln!(out, "  {:<7} at byte {o}: {}", p.severity.name(), p.text)?,
            None => writeln!(out, "  {:<7} {}", p.severity.name(), p.text)?,
        }
    }
    let mut hidden: Vec<(&str, usize)> = shown
        .into_iter()
        .filter(|&(_, n)| n > SHOWN_PER_KIND && !all)
        .map(|(k, n)| (k, n - SHOWN_PER_KIND))
        .collect();
    hidden.sort_unstable();
    for (kind, n) in hidden {
        writeln!(out, "  ... and {n} more {kind} (--all shows them)")?;
    }
    Ok(())
}

fn report_json(r: &Report) -> Json {
    let problems: Vec<Json> = r
        .problems
        .iter()
        .map(|p| {
            json!({
                "severity": p.severity.name(), "kind": p.kind, "offset": p.offset, "len": p.len,
                "topic": p.topic.as_ref().map(|t| t.0.clone()),
                "multi_id": p.topic.as_ref().map(|t| t.1),
                "text": p.text,
            })
        })
        .collect();
    let (messages, topics, duration) = r.summary.unwrap_or_default();
    let mut j = json!({
        "file": r.file,
        "status": r.status_name(),
        "messages": messages,
        "topics": topics,
        "duration_s": duration,
        "errors": r.count(Severity::Error),
        "warnings": r.count(Severity::Warning),
        "notes": r.count(Severity::Note),
        "problems": problems,
    });
    if let Some(e) = &r.error {
        j["error"] = Json::String(e.clone());
    }
    j
}

/// Runs the check; the exit status is the worst of all files (see `--help`).
pub fn run(args: &Args) -> Result<Status, Failure> {
    // Directories are searched as `ulog parquet` searches them; an input that is
    // missing, or a directory without logs, is a file that could not be read.
    let inputs: Vec<Result<PathBuf, Report>> = args
        .files
        .iter()
        .flat_map(|input| match input::logs_in(input) {
            Ok(logs) => logs.into_iter().map(|(path, _)| Ok(path)).collect(),
            Err(f) => vec![Err(failed(input.display().to_string(), f))],
        })
        .collect();
    let count = inputs.len();
    let progress = Progress::new(count as u64, "check files");
    let mut out = BufWriter::new(io::stdout().lock());
    let mut worst = Status::Ok;
    let mut all = Vec::new();
    for input in inputs {
        let r = match input {
            Ok(path) => {
                progress.message(path.display().to_string());
                check_file(&path)
            }
            Err(r) => r,
        };
        worst = worst.max(r.status);
        if args.json {
            all.push(report_json(&r));
        } else {
            write_text(&mut out, &r, args.brief, args.all).map_err(stdout_err)?;
        }
        progress.inc(1);
    }
    if args.json {
        let doc = json!({"files": all, "exit_status": worst as u8});
        serde_json::to_writer_pretty(&mut out, &doc)
            .map_err(|e| Failure::io("stdout", &e.into()))?;
        writeln!(out).map_err(stdout_err)?;
    } else if count > 1 {
        writeln!(out, "{count} files checked").map_err(stdout_err)?;
    }
    out.flush().map_err(stdout_err)?;
    Ok(worst)
}
