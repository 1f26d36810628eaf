//! Opening and parsing the log named on the command line, with one clear line when it
//! cannot be read.

use std::path::Path;

use ulog_core::read::{ReadErrorKind, UtcClock};
use ulog_core::{LogFile, ReadError, ULog};

use crate::failure::{io_text, Failure, Status};

/// Reads the file at `path` into memory ([`LogFile::open`]: a copy, so that a file
/// that changes meanwhile cannot kill the process); a missing, unreadable or directory
/// path is a failure.
pub fn open(path: &Path) -> Result<LogFile, Failure> {
    not_a_directory(path)?;
    LogFile::open(path).map_err(|e| Failure::unreadable(path.display(), error_text(&e)))
}

/// A missing or unreadable path, or a directory, is a failure about `path`.
pub fn not_a_directory(path: &Path) -> Result<(), Failure> {
    let shown = path.display();
    let meta = std::fs::metadata(path).map_err(|e| Failure::unreadable(&shown, io_text(&e)))?;
    if meta.is_dir() {
        return Err(Failure::unreadable(&shown, "is a directory"));
    }
    Ok(())
}

/// Parses `bytes`; a file that is not a ULog log, or one the spec says to refuse, is a
/// failure about `name`.
pub fn parse<'a>(name: &str, bytes: &'a [u8]) -> Result<ULog<'a>, Failure> {
    ULog::parse(bytes).map_err(|e| Failure::new(Status::Refused, name, error_text(&e)))
}

/// The UTC clock of `log` when `--utc` is `wanted` ([`ULog::utc`]); a log that does
/// not say its UTC time is then a failure about `name` (exit status 6), not boot times
/// printed as UTC.
pub fn utc_clock(name: &str, log: &ULog<'_>, wanted: bool) -> Result<Option<UtcClock>, Failure> {
    if !wanted {
        return Ok(None);
    }
    log.utc().map(Some).ok_or_else(|| {
        Failure::about(
            name,
            "--utc: the log does not say its UTC time (no GPS time_utc_usec in \
             vehicle_gps_position, sensor_gps or vehicle_gnss, and no boot_time_utc_us \
             information); leave out --utc for times since boot",
        )
    })
}

/// A read error as one line without the file (the caller names it): what, and the
/// byte offset where there is a place that the text does not already say.
pub fn error_text(e: &ReadError) -> String {
    match (e.kind(), e.position()) {
        (ReadErrorKind::Io(_) | ReadErrorKind::UnknownIncompatFlags { .. }, Some(at)) => {
            format!("{} (at byte {at})", e.what())
        }
        _ => e.what(),
    }
}

/// Seconds since a log's start (`--start`, `--end` of `plot` and `cut`) from `90`, `90.5`, `1:30`, `1:30.5` or `1:02:03.5` (minutes and seconds
/// after a `:` below 60).
pub fn seconds(s: &str) -> Result<f64, String> {
    let bad = || {
        format!(
            "`{s}` is not a time: expected the time since the log's start as seconds \
             (`90`, `90.5`), M:SS (`1:30`, `1:30.5`) or H:MM:SS (`1:02:03`)"
        )
    };
    let digits = |p: &str| !p.is_empty() && p.bytes().all(|b| b.is_ascii_digit());
    let parts: Vec<&str> = s.split(':').collect();
    let Some((last, units)) = parts.split_last() else {
        return Err(bad());
    };
    if units.len() > 2 {
        return Err(bad());
    }
    let seconds_ok = match last.split_once('.') {
        Some((whole, frac)) => digits(whole) && digits(frac),
        None => digits(last),
    };
    if !seconds_ok {
        return Err(bad());
    }
    let seconds: f64 = last.parse().map_err(|_| bad())?;
    if !units.is_empty() && seconds >= 60.0 {
        return Err(bad());
    }
    let mut total = 0.0f64;
    for (i, p) in units.iter().enumerate() {
        let v: f64 = p.parse().ok().filter(|_| digits(p)).ok_or_else(bad)?;
        if i > 0 && v >= 60.0 {
            return Err(bad());
        }
        total = total * 60.0 + v;
    }
    let t = total * 60.0 + seconds;
    if t.is_finite() {
        Ok(t)
    } else {
        Err(bad())
    }
}

/// The topic names of a `-m a,b,c` option, each checked to be in `log` (named `name`):
/// an unknown one is a failure that suggests the closest topic.
pub fn topic_list<'s>(name: &str, log: &ULog<'_>, list: &'s str) -> Result<Vec<&'s str>, Failure> {
    let wanted: Vec<&str> = list.split(',').filter(|s| !s.is_empty()).collect();
    for w in &wanted {
        if log.topic_instances(w).is_empty() {
            let text = match log.topic(w, 0) {
                Err(e) => e.to_string(),
                Ok(_) => format!("no topic `{w}` in the log"),
            };
            return Err(Failure::unknown_name(name, text));
        }
    }
    Ok(wanted)
}

/// The extensions of log files (any case): `.ulg`, and `.ulog` that some tools write.
pub const LOG_EXTENSIONS: [&str; 2] = ["ulg", "ulog"];

/// Whether `path` is named as a log file (`.ulg` or `.ulog`, any case).
pub fn is_log_name(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| LOG_EXTENSIONS.iter().any(|x| e.eq_ignore_ascii_case(x)))
}

/// `name` without its `.ulg` or `.ulog` extension (any case), or `None` when it has
/// neither.
pub fn strip_log_extension(name: &str) -> Option<&str> {
    LOG_EXTENSIONS.iter().find_map(|ext| {
        let cut = name.len().checked_sub(ext.len() + 1)?;
        let (stem, tail) = (name.get(..cut)?, name.get(cut..)?);
        (tail.starts_with('.') && tail[1..].eq_ignore_ascii_case(ext)).then_some(stem)
    })
}

/// Says on stderr, once, that the reader stepped over damage in the log `name`
/// (what the damaged stretches held is in no output), when `findings` has any.
pub fn note_damage(name: &str, findings: &[ulog_core::Finding]) {
    let damage = findings.iter().filter(|f| f.is_damage()).count();
    if damage > 0 {
        use std::io::Write as _;
        let _ = writeln!(
            std::io::stderr(),
            "ulog: {name}: {damage} damaged stretch(es) stepped over (`ulog check` lists \
             them); what they held is not written"
        );
    }
}

/// The name of the log at `path` without its folder and its `.ulg`/`.ulog`
/// extension (any case); the whole file name when it has neither.
pub fn stem(path: &Path) -> String {
    let name = path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    );
    match strip_log_extension(&name) {
        Some(stem) => stem.to_owned(),
        None => name,
    }
}

/// The threads a `-j/--jobs` option asks for: its value, else the number of CPUs.
pub fn threads(jobs: Option<std::num::NonZeroUsize>) -> usize {
    jobs.or_else(|| std::thread::available_parallelism().ok())
        .map_or(1, std::num::NonZeroUsize::get)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn times_are_seconds_or_minutes_and_seconds() {
        assert_eq!(seconds("90"), Ok(90.0));
        assert_eq!(seconds("90.25"), Ok(90.25));
        assert_eq!(seconds("1:30"), Ok(90.0));
        assert_eq!(seconds("1:30.5"), Ok(90.5));
        assert_eq!(seconds("01:02:03"), Ok(3723.0));
        assert_eq!(seconds("90:00"), Ok(5400.0));
        for bad in [
            "", "1:60", "1:75", "1:60:00", "a", "1:", ":30", "-5", "1e3", "1.", ".5", "1:2:3:4",
            "inf",
        ] {
            assert!(seconds(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn log_extensions_are_ulg_and_ulog_in_any_case() {
        assert_eq!(strip_log_extension("a/b.ulg"), Some("a/b"));
        assert_eq!(strip_log_extension("a/b.ULog"), Some("a/b"));
        assert_eq!(strip_log_extension("b.ulog.ulg"), Some("b.ulog"));
        assert_eq!(strip_log_extension("a/bulog"), None);
        assert_eq!(strip_log_extension("a/b.txt"), None);
        assert_eq!(strip_log_extension(".ulg"), Some(""));
        assert_eq!(strip_log_extension("é.ulg"), Some("é"));
        assert!(is_log_name(Path::new("x/y.ULOG")));
        assert!(is_log_name(Path::new("y.ulg")));
        assert!(!is_log_name(Path::new("y.ulg.txt")));
    }
}
