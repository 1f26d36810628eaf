//! [`WriteError`]: what stops a log from being written, and where in the output.

use core::fmt;
use std::sync::Arc;

use ulog_format::{FormatError, LayoutError};

use crate::access::lookup::TopicNotFound;
use crate::error::ReadError;

/// Why a message could not be written. Matchable; new kinds may be added. Nothing
/// malformed is written: the message that fails is not written at all.
#[derive(Debug, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub enum WriteErrorKind {
    /// Writing to the output failed (the `std::io::Error` is the error's
    /// [`source`](std::error::Error::source)).
    Io(std::io::ErrorKind),
    /// A message would be larger than the 65,535 bytes a message can hold.
    MessageTooLarge {
        /// The message type.
        msg_type: u8,
        /// Its size.
        size: usize,
    },
    /// A format of this name was declared before with other fields.
    FormatConflict {
        /// The format.
        name: String,
    },
    /// A format (or one it nests) that the definitions section did not declare:
    /// formats cannot be written in the data section.
    FormatNotDeclared {
        /// The format.
        name: String,
    },
    /// A format given as text that does not parse.
    InvalidFormat(FormatError),
    /// A declared format that cannot be laid out.
    NoLayout {
        /// The format.
        name: String,
        /// Why.
        error: LayoutError,
    },
    /// All 65,536 msg_ids are in use.
    MsgIdsExhausted,
    /// An information or parameter name that is empty or holds a character outside
    /// `a-z A-Z 0-9 _ - /`.
    InvalidName(String),
    /// An information value of a type that has none (a nested binding, an array of
    /// strings).
    InvalidInfoValue {
        /// What was given.
        what: String,
    },
    /// A logged string holding a control character other than tab, line feed,
    /// carriage return and escape, at byte `at` of the text. Readers may take such a
    /// message for corruption (this one does when the byte is among the text's first
    /// 128), so it is refused wherever it is.
    ControlCharacter {
        /// Byte offset in the text.
        at: usize,
        /// The byte.
        byte: u8,
    },
    /// A payload given as bytes whose length fits neither the format's full size nor
    /// the size without trailing padding.
    PayloadSize {
        /// The topic.
        topic: String,
        /// Valid lengths: the full size and the size without trailing padding.
        expected: (usize, usize),
        /// The length given.
        found: usize,
    },
    /// Copying, appending, editing: the input log could not be read (not ULog, a
    /// header the spec says to refuse, an I/O error); the [`ReadError`] is the
    /// error's [`source`](std::error::Error::source).
    Unreadable,
    /// Appending: the log has no flag bits message (version 0 logs cannot take
    /// appended data).
    NoFlagBits,
    /// Appending: all three appended offsets of the log are in use.
    NoFreeAppendedOffset,
    /// Appending: the log has no such topic instance; editing: no topic of that name.
    TopicNotFound(TopicNotFound),
    /// Appending: the log's format of a topic is not exactly the binding's, so values
    /// of the binding cannot be written to its subscription.
    LayoutDiffers {
        /// The topic.
        topic: String,
        /// The binding's format.
        binding: String,
        /// The log's format.
        log: String,
    },
    /// Editing: a time window whose start is not before its end, so that it holds no
    /// time (refused before anything is read).
    EmptyWindow {
        /// The window's start (microseconds, as the log's timestamps).
        start: u64,
        /// The window's end.
        end: u64,
    },
}

/// A message that could not be written: what, and where in the output when there is
/// a place (the offset the message would have started at).
#[derive(Debug, Clone)]
pub struct WriteError(Box<Inner>);

#[derive(Debug, Clone)]
struct Inner {
    kind: WriteErrorKind,
    position: Option<u64>,
    source: Option<Source>,
}

#[derive(Debug, Clone)]
enum Source {
    Io(Arc<std::io::Error>),
    Read(ReadError),
}

impl WriteError {
    fn from_inner(inner: Inner) -> WriteError {
        WriteError(Box::new(inner))
    }

    pub(crate) fn new(kind: WriteErrorKind, position: Option<u64>) -> WriteError {
        WriteError::from_inner(Inner {
            kind,
            position,
            source: None,
        })
    }

    pub(crate) fn io(e: std::io::Error, position: Option<u64>) -> WriteError {
        WriteError::from_inner(Inner {
            kind: WriteErrorKind::Io(e.kind()),
            position,
            source: Some(Source::Io(Arc::new(e))),
        })
    }

    pub(crate) fn unreadable(e: ReadError) -> WriteError {
        WriteError::from_inner(Inner {
            kind: WriteErrorKind::Unreadable,
            position: e.position(),
            source: Some(Source::Read(e)),
        })
    }

    /// What went wrong.
    pub fn kind(&self) -> &WriteErrorKind {
        &self.0.kind
    }

    /// The byte offset in the output where it went wrong, where there is one.
    pub fn position(&self) -> Option<u64> {
        self.0.position
    }
}

impl PartialEq for WriteError {
    /// The same kind at the same place.
    fn eq(&self, other: &WriteError) -> bool {
        (&self.0.kind, self.0.position) == (&other.0.kind, other.0.position)
    }
}

impl Eq for WriteError {}

impl fmt::Display for WriteError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let e = &*self.0;
        match &e.kind {
            WriteErrorKind::Io(k) => match &e.source {
                Some(Source::Io(e)) => write!(f, "{e}"),
                _ => write!(f, "i/o error: {k}"),
            },
            WriteErrorKind::MessageTooLarge { msg_type, size } => write!(
                f,
                "a `{}` message of {size} bytes does not fit in a ULog message (65535 at most)",
                *msg_type as char
            ),
            WriteErrorKind::FormatConflict { name } => {
                write!(f, "format `{name}` is declared twice with different fields")
            }
            WriteErrorKind::FormatNotDeclared { name } => write!(
                f,
                "format `{name}` was not declared in the definitions section (formats cannot be written in the data section)"
            ),
            WriteErrorKind::InvalidFormat(e) => write!(f, "invalid format: {e}"),
            WriteErrorKind::NoLayout { name, error } => {
                write!(f, "format `{name}` cannot be laid out: {error}")
            }
            WriteErrorKind::MsgIdsExhausted => write!(f, "all 65,536 msg_ids are in use"),
            WriteErrorKind::InvalidName(n) => write!(
                f,
                "invalid name {n:?}: names are non-empty and use a-z A-Z 0-9 _ - /"
            ),
            WriteErrorKind::InvalidInfoValue { what } => {
                write!(f, "{what} cannot be an information value (basic types, arrays of them, and strings can)")
            }
            WriteErrorKind::ControlCharacter { at, byte } => write!(
                f,
                "logged text holds control character {byte:#04x} at byte {at}: readers may take the message for corruption (tab, line feed, carriage return and escape are allowed)"
            ),
            WriteErrorKind::PayloadSize {
                topic,
                expected,
                found,
            } => write!(
                f,
                "a payload of `{topic}` has {found} bytes, its format needs {} or {}",
                expected.0, expected.1
            ),
            WriteErrorKind::Unreadable => match &e.source {
                Some(Source::Read(e)) => unreadable_text(f, e),
                _ => write!(f, "the input log cannot be read"),
            },
            WriteErrorKind::NoFlagBits => write!(
                f,
                "the log has no flag bits message, so data cannot be appended to it"
            ),
            WriteErrorKind::NoFreeAppendedOffset => {
                write!(f, "all three appended offsets of the log are in use")
            }
            WriteErrorKind::TopicNotFound(t) => write!(f, "{t}"),
            WriteErrorKind::LayoutDiffers { topic, binding, log } => write!(
                f,
                "the log's format of `{topic}` is not the binding's: binding `{binding}`, log `{log}`"
            ),
            WriteErrorKind::EmptyWindow { start, end } => write!(
                f,
                "the time window is empty: its start ({start} us) is not before its end ({end} us)"
            ),
        }?;
        match e.position {
            Some(at) if !matches!(e.kind, WriteErrorKind::Unreadable) => {
                write!(f, " (at byte {at} of the output)")
            }
            _ => Ok(()),
        }
    }
}

/// The text of an input (to copy, append to or edit) that cannot be read: what is
/// wrong with it, and where; for bytes that are not ULog, what a ULog file starts with.
fn unreadable_text(f: &mut fmt::Formatter<'_>, e: &ReadError) -> fmt::Result {
    use crate::error::ReadErrorKind;
    match e.kind() {
        ReadErrorKind::NotULog { found } => write!(
            f,
            "the input is not a ULog file: no ULog magic (`ULog` 0x01 0x12 0x35) at byte 0, found {found}"
        ),
        ReadErrorKind::Empty | ReadErrorKind::TruncatedHeader { .. } => f.write_str(&e.what()),
        _ => match e.position() {
            Some(at) => write!(f, "the input log cannot be read at byte {at}: {}", e.what()),
            None => write!(f, "the input log cannot be read: {}", e.what()),
        },
    }
}

impl std::error::Error for WriteError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match (&self.0.source, &self.0.kind) {
            (Some(Source::Io(e)), _) => Some(&**e),
            (Some(Source::Read(e)), _) => Some(e),
            (None, WriteErrorKind::InvalidFormat(e)) => Some(e),
            (None, WriteErrorKind::NoLayout { error, .. }) => Some(error),
            _ => None,
        }
    }
}
