//! Why a command stopped: one line for stderr, or a closed output pipe (not an error).

use std::io;

/// What ended a command early.
#[derive(Debug)]
pub enum Failure {
    /// Writing to stdout failed because the reader closed the pipe.
    BrokenPipe,
    /// One line for stderr, after `ulog: ` (`<file>: <error>`).
    Message(String),
}

impl Failure {
    /// A failure about `subject` (a file name, `stdout`, …).
    pub fn about(subject: impl core::fmt::Display, what: impl core::fmt::Display) -> Failure {
        Failure::Message(format!("{subject}: {what}"))
    }

    /// An I/O error while writing or reading `subject`; a broken pipe is not reported.
    pub fn io(subject: impl core::fmt::Display, e: &io::Error) -> Failure {
        if e.kind() == io::ErrorKind::BrokenPipe {
            Failure::BrokenPipe
        } else {
            Failure::about(subject, io_text(e))
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
