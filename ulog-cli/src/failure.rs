//! Why a command stopped: one line for stderr with an exit status that says what kind
//! of failure it was, or a closed output pipe (not an error).

use std::io;
use std::process::ExitCode;

/// The exit status of `ulog`, one per kind of failure, so scripts can tell them apart.
///
/// Usage errors (an unknown option, a missing argument) exit with 2, from `clap`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Status {
    /// 0: the command did its job (for `check`: every file conforms).
    Ok = 0,
    /// 1: `check` found damage or departures from the spec in a file it could read.
    Findings = 1,
    /// 3: a file could not be read or written (missing, a directory, no permission).
    Io = 3,
    /// 4: a file is not a ULog log, or the spec says to refuse it.
    Refused = 4,
    /// 5: a topic or field name on the command line is not in the log.
    UnknownName = 5,
    /// 6: anything else (an option value that cannot work, an internal limit).
    Other = 6,
    /// 7: the log does not hold what an option needs: default parameters (`params -d`,
    /// `--diff-defaults`), a UTC time (`--utc`), data in a cut's window.
    Lacking = 7,
}

impl Status {
    /// The process exit code.
    pub fn code(self) -> ExitCode {
        ExitCode::from(self as u8)
    }
}

/// The `Exit status` section of `ulog --help`.
pub const EXIT_STATUS_HELP: &str = "\
Exit status: 0 ok, 1 `check` found damage, 2 bad usage, 3 file not readable or
  writable, 4 not ULog, 5 name not in log, 6 other, 7 log lacks what is asked";

/// What ended a command early.
#[derive(Debug)]
pub enum Failure {
    /// Writing to stdout failed because the reader closed the pipe.
    BrokenPipe,
    /// One line for stderr, after `ulog: ` (`<file>: <error>`), and the exit status.
    Message(Status, String),
}

impl Failure {
    /// A failure of kind `status` about `subject` (a file name, `stdout`, …).
    pub fn new(
        status: Status,
        subject: impl core::fmt::Display,
        what: impl core::fmt::Display,
    ) -> Failure {
        Failure::Message(status, format!("{subject}: {what}"))
    }

    /// A failure about `subject` that fits no more precise status.
    pub fn about(subject: impl core::fmt::Display, what: impl core::fmt::Display) -> Failure {
        Failure::new(Status::Other, subject, what)
    }

    /// A file that could not be read or written.
    pub fn unreadable(subject: impl core::fmt::Display, what: impl core::fmt::Display) -> Failure {
        Failure::new(Status::Io, subject, what)
    }

    /// What an option needs that the log does not hold (`what` says which option).
    pub fn lacking(subject: impl core::fmt::Display, what: impl core::fmt::Display) -> Failure {
        Failure::new(Status::Lacking, subject, what)
    }

    /// A topic or field name that is not in the log.
    pub fn unknown_name(
        subject: impl core::fmt::Display,
        what: impl core::fmt::Display,
    ) -> Failure {
        Failure::new(Status::UnknownName, subject, what)
    }

    /// An I/O error while writing or reading `subject`; a broken pipe is not reported.
    pub fn io(subject: impl core::fmt::Display, e: &io::Error) -> Failure {
        if e.kind() == io::ErrorKind::BrokenPipe {
            Failure::BrokenPipe
        } else {
            Failure::unreadable(subject, io_text(e))
        }
    }
}

/// An I/O error's text without the `(os error N)` suffix, lower-case first letter.
pub fn io_text(e: &io::Error) -> String {
    let s = e.to_string();
    let s = match s.rfind(" (os error ") {
        Some(i) => s[..i].to_owned(),
        None => s,
    };
    let mut c = s.chars();
    match c.next() {
        Some(first) => first.to_lowercase().chain(c).collect(),
        None => s,
    }
}

/// Maps write errors on stdout.
pub fn stdout_err(e: io::Error) -> Failure {
    Failure::io("stdout", &e)
}
