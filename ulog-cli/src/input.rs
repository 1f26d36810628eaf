//! Opening and parsing the log named on the command line, with one clear line when it
//! cannot be read.

use std::path::Path;

use ulog_core::read::ReadErrorKind;
use ulog_core::{LogFile, ReadError, ULog};

use crate::failure::{io_text, Failure, Status};

/// Maps the file at `path`; a missing, unreadable or directory path is a failure.
pub fn open(path: &Path) -> Result<LogFile, Failure> {
    let shown = path.display();
    let meta = std::fs::metadata(path).map_err(|e| Failure::unreadable(&shown, io_text(&e)))?;
    if meta.is_dir() {
        return Err(Failure::unreadable(&shown, "is a directory"));
    }
    LogFile::open(path).map_err(|e| Failure::unreadable(&shown, error_text(&e)))
}

/// Parses `bytes`; a file that is not a ULog log, or one the spec says to refuse, is a
/// failure about `name`.
pub fn parse<'a>(name: &str, bytes: &'a [u8]) -> Result<ULog<'a>, Failure> {
    ULog::parse(bytes).map_err(|e| Failure::new(Status::Refused, name, error_text(&e)))
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

/// The threads a `-j/--jobs` option asks for: its value, else the number of CPUs.
pub fn threads(jobs: Option<std::num::NonZeroUsize>) -> usize {
    jobs.or_else(|| std::thread::available_parallelism().ok())
        .map_or(1, std::num::NonZeroUsize::get)
}
