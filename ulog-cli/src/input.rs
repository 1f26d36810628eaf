//! Opening and parsing the log named on the command line, with one clear line when it
//! cannot be read.

use std::path::Path;

use ulog_core::{Error, ErrorKind, MappedFile, ULog};

use crate::failure::{io_text, Failure, Status};

/// Maps the file at `path`; a missing, unreadable or directory path is a failure.
pub fn open(path: &Path) -> Result<MappedFile, Failure> {
    let shown = path.display();
    let meta = std::fs::metadata(path).map_err(|e| Failure::unreadable(&shown, io_text(&e)))?;
    if meta.is_dir() {
        return Err(Failure::unreadable(&shown, "is a directory"));
    }
    MappedFile::open(path).map_err(|e| Failure::unreadable(&shown, error_text(&e)))
}

/// Parses `bytes`; a file that is not a ULog log, or one the spec says to refuse, is a
/// failure about `name`.
pub fn parse<'a>(name: &str, bytes: &'a [u8]) -> Result<ULog<'a>, Failure> {
    ULog::parse(bytes).map_err(|e| Failure::new(Status::Refused, name, error_text(&e)))
}

/// A library error as one line: the kind, and the byte offset where one applies.
pub fn error_text(e: &Error) -> String {
    match &e.kind {
        // The library's I/O text already names the file; the caller names it too.
        ErrorKind::Io(s) => match s.rsplit_once(": ") {
            Some((_, tail)) => tail.to_owned(),
            None => s.clone(),
        },
        kind if e.offset == 0 => kind.to_string(),
        kind => format!("{kind} (at byte {})", e.offset),
    }
}

/// The topic names of a `-m a,b,c` option, each checked to be in `log` (named `name`):
/// an unknown one is a failure that suggests the closest topic.
pub fn topic_list<'s>(name: &str, log: &ULog<'_>, list: &'s str) -> Result<Vec<&'s str>, Failure> {
    let wanted: Vec<&str> = list.split(',').filter(|s| !s.is_empty()).collect();
    for w in &wanted {
        if log.topic_instances(w).is_empty() {
            let text = match log.topic(w, 0) {
                Err(e) => error_text(&e),
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
