//! `ulog cut`: a time window and a choice of topics of a log, as a valid log.

use std::io::{Read, Write};
use std::path::{Path, PathBuf};

use ulog_core::format::definitions::HEADER_SIZE;
use ulog_core::read::{Header, Messages, ReadErrorKind};
use ulog_core::write::{EditSummary, WriteErrorKind};
use ulog_core::{Edit, Source};

use crate::failure::{io_text, Failure, Status};
use crate::input;

/// Write a part of a log as a log of its own: the data messages with `--start ≤
/// timestamp < --end` (each topic by its own timestamp) of the topics chosen, with the
/// header, information, default parameters and the formats and subscriptions of the
/// kept topics; parameters as they were at `--start` (changes before it folded into the
/// initial values, changes inside the window kept as changes); logged messages,
/// dropouts and sync markers inside the window. Appended data is written as data.
/// Damaged stretches of the input are not copied (a line on stderr says how many). pyulog,
/// PlotJuggler and this reader read the result.
///
/// Times are seconds since the log's start (its header timestamp, or for a header
/// without one its first timestamp): `90`, `1:30` or `1:30.5` (also `1:02:03`);
/// `--start-us`/`--end-us` take the log's own timestamps (microseconds).
#[derive(Debug, clap::Args)]
#[command(
    about = "A time window and a choice of topics of a log, as a valid log",
    long_about
)]
pub struct Args {
    /// The ULog file.
    file: PathBuf,
    /// The log to write (replaced if it exists; never the input).
    #[arg(short = 'o', long = "output", value_name = "OUT.ulg")]
    output: PathBuf,
    /// Keep data from this time on (seconds since the log's start).
    #[arg(long, value_name = "T", value_parser = seconds, conflicts_with = "start_us")]
    start: Option<u64>,
    /// Keep data before this time (seconds since the log's start).
    #[arg(long, value_name = "T", value_parser = seconds, conflicts_with = "end_us")]
    end: Option<u64>,
    /// Keep data from this timestamp on (microseconds, as logged).
    #[arg(long, value_name = "US")]
    start_us: Option<u64>,
    /// Keep data before this timestamp (microseconds, as logged).
    #[arg(long, value_name = "US")]
    end_us: Option<u64>,
    /// Only these topics (comma-separated names).
    #[arg(
        short = 'm',
        long = "messages",
        value_name = "TOPICS",
        conflicts_with = "exclude"
    )]
    messages: Option<String>,
    /// Leave these topics out (comma-separated names).
    #[arg(long, value_name = "TOPICS")]
    exclude: Option<String>,
}

/// A time since the log's start ([`input::seconds`]) as microseconds.
fn seconds(text: &str) -> Result<u64, String> {
    input::seconds(text).map(|s| (s * 1e6).round() as u64)
}

pub fn run(args: &Args) -> Result<(), Failure> {
    let name = args.file.display().to_string();
    // The log is not parsed: the edit frames it once, as it reads it (BENCHMARKS.md,
    // "cut"). Times count from the log's start (`TimeSpan`): the header's timestamp,
    // or, in a log whose header has none, its first timestamp, which takes a pass.
    let mut start = header(&name, &args.file)?.timestamp;
    if start == 0 && (args.start.is_some() || args.end.is_some()) {
        start = input::keep(&args.file, &[], input::Times::Every)?
            .metadata
            .span()
            .start();
    }
    let from = args
        .start_us
        .or(args.start.map(|s| start.saturating_add(s)));
    let to = args.end_us.or(args.end.map(|s| start.saturating_add(s)));
    // A window that holds no time is refused before anything is read or written
    // (the library refuses it too; here it is said in the options' own terms).
    if let (Some(a), Some(b)) = (from, to) {
        if a >= b {
            return Err(Failure::about(
                &name,
                format!(
                    "the window is empty: {} is not before {}",
                    bound("--start", args.start, args.start_us),
                    bound("--end", args.end, args.end_us)
                ),
            ));
        }
    }
    let mut edit = Edit::new().window(from, to);
    let list = |text: &str| {
        text.split(',')
            .filter(|s| !s.is_empty())
            .map(str::to_owned)
            .collect::<Vec<_>>()
    };
    if let Some(text) = &args.messages {
        edit = edit.only(list(text));
    }
    if let Some(text) = &args.exclude {
        edit = edit.exclude(list(text));
    }
    // A cut that keeps none of the log's data (a window after its end or before its
    // start, topics without data there) is known once the pass has run: refused,
    // with where the data is, and nothing left behind.
    let since_start = |t: u64| (t as f64 - start as f64) / 1e6;
    let refuse = |summary: &EditSummary| {
        if summary.rows > 0 || summary.rows_left_out == 0 {
            return None;
        }
        let chosen = if args.messages.is_some() || args.exclude.is_some() {
            " of the topics chosen"
        } else {
            ""
        };
        let window = match (from, to) {
            (None, None) => String::new(),
            _ => format!(
                " in the window from {} to {}",
                from.map_or("the log's start".into(), |t| format!(
                    "{:.3} s",
                    since_start(t)
                )),
                to.map_or("the log's end".into(), |t| format!(
                    "{:.3} s",
                    since_start(t)
                ))
            ),
        };
        let span = summary
            .data_times
            .map(|(lo, hi)| {
                format!(
                    " (the log's data runs from {:.3} s to {:.3} s since its start)",
                    since_start(lo),
                    since_start(hi)
                )
            })
            .unwrap_or_default();
        Some(Failure::lacking(
            &name,
            format!("no data{chosen}{window}{span}: nothing written"),
        ))
    };
    write_edit(
        &name,
        &args.file,
        &args.output,
        input::source(&args.file)?,
        edit,
        refuse,
    )
}

/// A bound of the window as it was given: `--start 30 s` or `--start-us 1000`.
fn bound(flag: &str, seconds: Option<u64>, us: Option<u64>) -> String {
    match (seconds, us) {
        (Some(s), _) => format!("{flag} {} s", s as f64 / 1e6),
        (None, Some(us)) => format!("{flag}-us {us}"),
        (None, None) => flag.to_owned(),
    }
}

/// The header of the log at `path` (named `name`), from its first bytes.
pub fn header(name: &str, path: &Path) -> Result<Header, Failure> {
    let mut head = Vec::new();
    input::reader(name, path)?
        .take(HEADER_SIZE as u64)
        .read_to_end(&mut head)
        .map_err(|e| Failure::unreadable(name, io_text(&e)))?;
    let mut framing = Messages::new(&head);
    let first = framing.next();
    match (framing.header(), first) {
        (Some(header), _) => Ok(header),
        (None, Some(Err(e))) => Err(Failure::new(Status::Refused, name, input::error_text(&e))),
        (None, _) => Err(Failure::new(
            Status::Refused,
            name,
            "not a ULog file (no header)",
        )),
    }
}

/// Writes `edit` of `log` (the file `input`, named `name`) to `output`: under a
/// temporary name, renamed when done unless `refuse` fails what was written (then
/// removed); never over the input. Says what was written, and on stderr what damage
/// was not copied and which topics named have no data.
pub fn write_edit(
    name: &str,
    input: &Path,
    output: &Path,
    log: Source<'_>,
    edit: Edit<'_>,
    refuse: impl FnOnce(&EditSummary) -> Option<Failure>,
) -> Result<(), Failure> {
    if same_file(input, output) {
        return Err(Failure::about(name, "the output would replace the input"));
    }
    let shown = output.display().to_string();
    let mut tmp = output.as_os_str().to_owned();
    tmp.push(".partial");
    let tmp = PathBuf::from(tmp);
    let out = std::fs::File::create(&tmp).map_err(|e| Failure::unreadable(&shown, io_text(&e)))?;
    let result = edit.write(log, std::io::BufWriter::with_capacity(1 << 20, out));
    let summary = match result {
        Ok(s) => s,
        Err(e) => {
            let _ = std::fs::remove_file(&tmp);
            return Err(match e.kind() {
                WriteErrorKind::Io(_) => Failure::Message(Status::Io, format!("{shown}: {e}")),
                WriteErrorKind::TopicNotFound(_) => Failure::unknown_name(name, &e),
                // Not a log (refused), or a read that failed (unreadable).
                WriteErrorKind::Unreadable => {
                    let read = std::error::Error::source(&e)
                        .and_then(|s| s.downcast_ref::<ulog_core::ReadError>());
                    match read.map(|r| r.kind()) {
                        Some(ReadErrorKind::Io(_)) => Failure::unreadable(name, &e),
                        _ => Failure::new(Status::Refused, name, e.to_string()),
                    }
                }
                _ => Failure::about(name, &e),
            });
        }
    };
    if let Some(failure) = refuse(&summary) {
        let _ = std::fs::remove_file(&tmp);
        return Err(failure);
    }
    std::fs::rename(&tmp, output).map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        Failure::unreadable(&shown, io_text(&e))
    })?;
    // Findings that are not damage (appended data met) cost nothing.
    let damage: Vec<_> = summary.skipped.iter().filter(|f| f.is_damage()).collect();
    if !damage.is_empty() {
        let bytes: u64 = damage.iter().map(|f| f.len).sum();
        let _ = writeln!(
            std::io::stderr(),
            "ulog: {name}: {} damaged stretch{} ({bytes} bytes) not copied (`ulog check` lists them)",
            damage.len(),
            if damage.len() == 1 { "" } else { "es" },
        );
    }
    for topic in &summary.unlogged {
        let _ = writeln!(
            std::io::stderr(),
            "ulog: {name}: topic `{topic}` has a format but no data in the log"
        );
    }
    writeln!(
        std::io::stdout(),
        "Writing {shown} ({} data messages, {} left out)",
        summary.rows,
        summary.rows_left_out
    )
    .map_err(crate::failure::stdout_err)
}

/// Whether two paths name the same existing file.
fn same_file(a: &Path, b: &Path) -> bool {
    match (std::fs::canonicalize(a), std::fs::canonicalize(b)) {
        (Ok(a), Ok(b)) => a == b,
        _ => false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn times_are_seconds_minutes_and_hours() {
        assert_eq!(seconds("90"), Ok(90_000_000));
        assert_eq!(seconds("1:30"), Ok(90_000_000));
        assert_eq!(seconds("1:30.5"), Ok(90_500_000));
        assert_eq!(seconds("1:02:03"), Ok(3_723_000_000));
        assert_eq!(seconds("0.000001"), Ok(1));
        for bad in [
            "", "x", "-1", "1:60", "1:2:3:4", "1.5:30", "nan", "inf", "1:61:00",
        ] {
            assert!(seconds(bad).is_err(), "{bad}");
        }
    }
}
