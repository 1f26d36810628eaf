//! Opening and parsing the log named on the command line, with one clear line when it
//! cannot be read.

use std::path::{Path, PathBuf};

use ulog_core::read::{LogMetadata, ReadErrorKind, UtcClock};
use ulog_core::store::{Remote, StoreError};
use ulog_core::{LogFile, ReadError, ScanOptions, Source, ULog};

use crate::failure::{io_text, Failure, Status};

/// Reads the file at `path` into memory ([`LogFile::open`]: a copy, so that a file
/// that changes meanwhile cannot kill the process); a missing, unreadable or directory
/// path is a failure. An `s3://`, `https://` or `http://` URL is fetched whole.
pub fn open(path: &Path) -> Result<LogFile, Failure> {
    if let Some(remote) = remote(path)? {
        return remote.fetch().map_err(|e| store_failure(&e));
    }
    not_a_directory(path)?;
    LogFile::open(path).map_err(|e| Failure::unreadable(path.display(), error_text(&e)))
}

/// The object `path` names when it is an `s3://`, `https://` or `http://` URL
/// ([`ulog_core::store::Location`]); `None` for a local path.
pub fn remote(path: &Path) -> Result<Option<Remote>, Failure> {
    match path.to_str() {
        Some(text) if Remote::is_url(text) => {
            Remote::parse(text).map(Some).map_err(|e| store_failure(&e))
        }
        _ => Ok(None),
    }
}

/// A failed request to object storage, about its URL.
pub fn store_failure(e: &StoreError) -> Failure {
    Failure::unreadable(e.url(), e.what())
}

/// The log at `path` as a pass reads it: a file in chunks, or an object of a store
/// by ranged requests as the pass goes.
pub fn source(path: &Path) -> Result<Source<'static>, Failure> {
    match remote(path)? {
        Some(remote) => Ok(Source::reader(remote.reader())),
        None => Ok(Source::file(path)),
    }
}

/// The bytes of the log at `path` in order: the file, or the object by ranged
/// requests as they are read. A missing or unreadable path is a failure about `name`.
pub fn reader(name: &str, path: &Path) -> Result<Box<dyn std::io::Read + Send>, Failure> {
    if let Some(remote) = remote(path)? {
        return Ok(Box::new(remote.reader()));
    }
    not_a_directory(path)?;
    let file = std::fs::File::open(path).map_err(|e| Failure::unreadable(name, io_text(&e)))?;
    Ok(Box::new(file))
}

/// A missing or unreadable path, or a directory, is a failure about `path` (a URL is
/// checked when it is read).
pub fn not_a_directory(path: &Path) -> Result<(), Failure> {
    if remote(path)?.is_some() {
        return Ok(());
    }
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

/// A log read once in chunks, in bounded memory: everything but its data, and the
/// data of the topics asked for ([`keep`]).
pub struct Kept {
    /// Everything but the data (what framing saw of the whole file included), the
    /// rows of each topic counted.
    pub metadata: LogMetadata,
}

impl Kept {
    /// The kept log ([`LogMetadata::log`]); `name` is the log's, for the failure.
    pub fn log(&self, name: &str) -> Result<ULog<'_>, Failure> {
        self.metadata
            .log()
            .map_err(|e| Failure::new(Status::Refused, name, error_text(&e)))
    }
}

/// Which topics' times a pass that keeps the metadata follows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Times {
    /// Every topic's: the log's span, its last timestamp, the times of parameter
    /// changes and dropouts.
    Every,
    /// Only the GPS and event topics' (the UTC clock, the events): for a command
    /// that needs none of those (the pass then reads no other timestamp, about a
    /// third faster: bench/README.md).
    Needed,
}

/// Reads the log at `path` once, in chunks (the next read on a second thread), keeping
/// everything but the data and the data of `topics`, and the times of `times`: for
/// the commands that need no more, whatever the size of the file. A missing,
/// unreadable or directory path, or a read that fails, is a failure about `path`; a
/// file that is not ULog (or one to refuse) one about the log.
pub fn keep(path: &Path, topics: &[&str], times: Times) -> Result<Kept, Failure> {
    if let Some(remote) = remote(path)? {
        // A missing object is said as such, before any pass.
        remote.size().map_err(|e| store_failure(&e))?;
        let url = remote.url();
        return keep_from(Source::reader(remote.reader()), None, &url, topics, times);
    }
    not_a_directory(path)?;
    keep_from(
        Source::file(path),
        Some(path),
        &path.display().to_string(),
        topics,
        times,
    )
}

/// [`keep`] from any source; `path` is the file read errors are said of, `name` the
/// log's name.
pub fn keep_from(
    source: Source<'_>,
    path: Option<&Path>,
    name: &str,
    topics: &[&str],
    times: Times,
) -> Result<Kept, Failure> {
    let mut options = ScanOptions::default()
        .read_ahead(true)
        .keep_metadata(true)
        .keep_data(topics.iter().copied());
    if times == Times::Needed {
        // Hands out no topic, and follows none but those the UTC clock and the
        // events need.
        options = options.topics(std::iter::empty::<String>());
    }
    let mut summary =
        ulog_core::scan(source, &options, |_| {}).map_err(|e| pass_failure(path, name, &e))?;
    let Some(metadata) = summary.metadata.take() else {
        unreachable!("a pass asked to keep the metadata keeps it")
    };
    Ok(Kept { metadata })
}

/// Where a log is read from, once per pass (the report reads it twice).
pub enum Input {
    /// A regular file: read again for each pass.
    File(std::path::PathBuf),
    /// Anything else (a pipe): read once into memory, since it cannot be read twice.
    Read(LogFile),
    /// An object of a store: read again for each pass, by ranged requests.
    Remote(Remote),
}

impl Input {
    /// The log at `path` (or URL); a missing, unreadable or directory path is a
    /// failure.
    pub fn open(path: &Path) -> Result<Input, Failure> {
        if let Some(remote) = remote(path)? {
            remote.size().map_err(|e| store_failure(&e))?;
            return Ok(Input::Remote(remote));
        }
        not_a_directory(path)?;
        let regular = std::fs::metadata(path).is_ok_and(|m| m.is_file());
        if regular {
            Ok(Input::File(path.to_owned()))
        } else {
            open(path).map(Input::Read)
        }
    }

    /// The file's size and modification time as they are now (a file rewritten
    /// between the passes changes them even where its framing does not); `None` for
    /// a log read into memory.
    pub fn stamp(&self) -> Option<(u64, Option<std::time::SystemTime>)> {
        match self {
            Input::File(path) => std::fs::metadata(path)
                .ok()
                .map(|m| (m.len(), m.modified().ok())),
            Input::Read(_) | Input::Remote(_) => None,
        }
    }

    /// The log as a pass reads it: a file in chunks, the bytes in memory, or an
    /// object by ranged requests.
    pub fn source(&self) -> Source<'_> {
        match self {
            Input::File(path) => Source::file(path),
            Input::Read(file) => Source::from(file),
            Input::Remote(remote) => Source::reader(remote.reader()),
        }
    }

    /// The failure of a pass, as reading the whole file and parsing it gave it: a
    /// read that fails is about the file, a log that is not one (or is refused) about
    /// `name`.
    pub fn failure(&self, name: &str, e: &ReadError) -> Failure {
        let path = match self {
            Input::File(path) => Some(path.as_path()),
            Input::Read(_) | Input::Remote(_) => None,
        };
        pass_failure(path, name, e)
    }
}

/// The failure of a pass, as reading the whole file and parsing it gave it: a read
/// that fails is about the file `path`, a log that is not one (or is refused) about
/// `name`.
pub fn pass_failure(path: Option<&Path>, name: &str, e: &ReadError) -> Failure {
    match (path, e.kind()) {
        (Some(path), ReadErrorKind::Io(_)) => Failure::unreadable(path.display(), error_text(e)),
        _ => Failure::new(Status::Refused, name, error_text(e)),
    }
}

/// The UTC clock of `log` when `--utc` is `wanted` ([`ULog::utc`]); a log that does
/// not say its UTC time is then a failure about `name` (exit status 7), not boot times
/// printed as UTC.
pub fn utc_clock(name: &str, log: &ULog<'_>, wanted: bool) -> Result<Option<UtcClock>, Failure> {
    utc_of(name, || log.utc(), wanted)
}

/// [`utc_clock`] of the clock `clock` gives (a kept log's: [`LogMetadata::utc`]).
pub fn utc_of(
    name: &str,
    clock: impl FnOnce() -> Option<UtcClock>,
    wanted: bool,
) -> Result<Option<UtcClock>, Failure> {
    if !wanted {
        return Ok(None);
    }
    clock().map(Some).ok_or_else(|| {
        Failure::lacking(
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

/// `name` without its `.ulg` or `.ulog` extension (any case), or `None` when it has
/// neither.
pub fn strip_log_extension(name: &str) -> Option<&str> {
    LogFile::EXTENSIONS.iter().find_map(|ext| {
        let cut = name.len().checked_sub(ext.len() + 1)?;
        let (stem, tail) = (name.get(..cut)?, name.get(cut..)?);
        (tail.starts_with('.') && tail[1..].eq_ignore_ascii_case(ext)).then_some(stem)
    })
}

/// The logs an input of the command line names ([`LogFile::find`]): the file itself,
/// or the logs in a directory and its subdirectories, sorted, each with its size. A
/// missing input, or a directory without logs, is a failure about it.
/// An `s3://` URL names the object itself, or every log below it as a prefix; an
/// `http(s)://` URL one object.
pub fn logs_in(input: &Path) -> Result<Vec<(PathBuf, u64)>, Failure> {
    if let Some(remote) = remote(input)? {
        let logs = remote.find_logs().map_err(|e| match e.kind() {
            ulog_core::store::StoreErrorKind::NotFound => Failure::unreadable(
                e.url(),
                "no such object, and no .ulg or .ulog objects below it",
            ),
            _ => store_failure(&e),
        })?;
        return Ok(logs
            .into_iter()
            .map(|(r, size)| (PathBuf::from(r.url()), size))
            .collect());
    }
    let logs = LogFile::find(input).map_err(|e| {
        let text = std::error::Error::source(&e)
            .and_then(|s| s.downcast_ref::<std::io::Error>())
            .map_or_else(|| e.what(), io_text);
        Failure::unreadable(e.path().unwrap_or(input).display(), text)
    })?;
    if logs.is_empty() {
        return Err(Failure::unreadable(
            input.display(),
            "no .ulg or .ulog files in this directory or its subdirectories",
        ));
    }
    Ok(logs)
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

/// How a column names each of several logs: its [`stem`], or, where two logs share a
/// stem (logs of one name in different folders), every log's path.
pub fn column_names(files: &[&Path]) -> Vec<String> {
    let stems: Vec<String> = files.iter().map(|p| stem(p)).collect();
    let unique = stems
        .iter()
        .enumerate()
        .all(|(i, s)| !stems[..i].contains(s));
    match unique {
        true => stems,
        false => files.iter().map(|p| p.display().to_string()).collect(),
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
        assert!(LogFile::is_log_name(Path::new("x/y.ULOG")));
        assert!(LogFile::is_log_name(Path::new("y.ulg")));
        assert!(!LogFile::is_log_name(Path::new("y.ulg.txt")));
    }
}
