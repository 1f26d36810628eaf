//! The one error type of the library: what stopped a read, and where.

use core::fmt;

/// What went wrong. Matchable; new kinds may be added.
#[derive(Debug, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub enum ErrorKind {
    /// An I/O error (its text; `std::io::Error` is not `Clone`).
    Io(String),
    /// The file is empty.
    Empty,
    /// The file does not start with the ULog magic; says what it looks like instead.
    NotULog {
        /// A short description of what was found (e.g. `all zero bytes`, `a gzip file`).
        found: String,
    },
    /// The file ends inside the 16-byte header.
    TruncatedHeader {
        /// How many bytes there are.
        len: u64,
    },
    /// The flag bits set an incompatibility bit this reader does not know: the spec
    /// requires refusing the log.
    UnknownIncompatFlags {
        /// Index (0–7) of the first byte with an unknown bit.
        byte: usize,
        /// The unknown bits of that byte.
        bits: u8,
    },
    /// No topic of that name (and multi id) in the log.
    TopicNotFound {
        /// The topic asked for.
        name: String,
        /// The closest topic name the log has, if any is close.
        suggestion: Option<String>,
    },
    /// The topic has no field at that path.
    FieldNotFound {
        /// The topic.
        topic: String,
        /// The path asked for.
        path: String,
        /// The closest field path of the topic, if any is close.
        suggestion: Option<String>,
    },
    /// The topic's format could not be laid out (unknown nested type, cycle, limits).
    Layout(ulog_format::LayoutError),
    /// A data message's payload does not fit its format.
    PayloadSize {
        /// The topic.
        topic: String,
        /// Valid lengths: the full size and the size without trailing padding.
        expected: (usize, usize),
        /// The length found.
        found: usize,
    },
    /// The stream ended where more bytes were required (incremental reader).
    UnexpectedEof,
    /// A topic's format does not fit a binding: every difference, with both formats.
    Mismatch(Box<crate::typed::Mismatch>),
    /// A payload could not be decoded into a binding.
    Decode(crate::typed::DecodeError),
    /// Writing: a message would be larger than the 65,535 bytes a message can hold.
    MessageTooLarge {
        /// The message type.
        msg_type: u8,
        /// Its size.
        size: usize,
    },
    /// Writing: a format (or msg_id) that the definitions section did not declare.
    FormatUndefined(String),
    /// Writing: a format string that does not parse.
    InvalidFormat(ulog_format::FormatError),
    /// Writing: an information or parameter name that is empty or holds a character
    /// outside `a-z A-Z 0-9 _ - /`.
    InvalidName(String),
    /// Writing: a logged string holds a control character other than tab, line feed,
    /// carriage return and escape, at byte `at` of the text. This reader takes such a
    /// message in the data section for corruption when the byte is among the text's
    /// first 128; the writer refuses it anywhere, so that no reader drops the message.
    ControlCharacter {
        /// Byte offset in the text.
        at: usize,
        /// The byte.
        byte: u8,
    },
    /// Appending: the log has no flag bits message (version 0 logs cannot take
    /// appended data).
    NoFlagBits,
    /// Appending: all three appended offsets are in use.
    NoFreeAppendedOffset,
    /// An export to Arrow or Parquet failed (feature `parquet`), or a topic cannot be
    /// exported.
    Export(String),
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
}

/// An error with the byte offset in the file where it happened.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Error {
    /// What went wrong.
    pub kind: ErrorKind,
    /// Byte offset in the file (0 where no place applies).
    pub offset: u64,
}

impl Error {
    /// An error of `kind` at `offset`.
    pub fn new(kind: ErrorKind, offset: u64) -> Error {
        Error { kind, offset }
    }

    /// What went wrong.
    pub fn kind(&self) -> &ErrorKind {
        &self.kind
    }
}

impl From<std::io::Error> for Error {
    fn from(e: std::io::Error) -> Error {
        Error::new(ErrorKind::Io(e.to_string()), 0)
    }
}

impl fmt::Display for ErrorKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ErrorKind::Io(e) => write!(f, "i/o error: {e}"),
            ErrorKind::Empty => write!(f, "not a ULog file: the file is empty"),
            ErrorKind::NotULog { found } => {
                write!(
                    f,
                    "not a ULog file: no ULog magic at the start, found {found}"
                )
            }
            ErrorKind::TruncatedHeader { len } => write!(
                f,
                "truncated ULog header: the file has {len} bytes, the header needs 16"
            ),
            ErrorKind::UnknownIncompatFlags { byte, bits } => write!(
                f,
                "refused: unknown incompatible flag bits {bits:#04x} in incompat_flags[{byte}]"
            ),
            ErrorKind::TopicNotFound { name, suggestion } => {
                write!(f, "no topic `{name}` in the log")?;
                if let Some(s) = suggestion {
                    write!(f, " (did you mean `{s}`?)")?;
                }
                Ok(())
            }
            ErrorKind::FieldNotFound {
                topic,
                path,
                suggestion,
            } => {
                write!(f, "topic `{topic}` has no field `{path}`")?;
                if let Some(s) = suggestion {
                    write!(f, " (did you mean `{s}`?)")?;
                }
                Ok(())
            }
            ErrorKind::Layout(e) => write!(f, "{e}"),
            ErrorKind::PayloadSize {
                topic,
                expected,
                found,
            } => write!(
                f,
                "data message of `{topic}` has {found} bytes, its format needs {} or {}",
                expected.0, expected.1
            ),
            ErrorKind::UnexpectedEof => write!(f, "unexpected end of stream"),
            ErrorKind::Mismatch(m) => write!(f, "{m}"),
            ErrorKind::Decode(e) => write!(f, "{e}"),
            ErrorKind::MessageTooLarge { msg_type, size } => write!(
                f,
                "a `{}` message of {size} bytes does not fit in a ULog message (65535 at most)",
                *msg_type as char
            ),
            ErrorKind::FormatUndefined(name) => {
                write!(f, "format `{name}` was not declared in the definitions section")
            }
            ErrorKind::InvalidFormat(e) => write!(f, "invalid format: {e}"),
            ErrorKind::InvalidName(n) => write!(
                f,
                "invalid name {n:?}: names are non-empty and use a-z A-Z 0-9 _ - /"
            ),
            ErrorKind::ControlCharacter { at, byte } => write!(
                f,
                "logged text holds control character {byte:#04x} at byte {at}: readers may take the message for corruption (tab, line feed, carriage return and escape are allowed)"
            ),
            ErrorKind::NoFlagBits => write!(
                f,
                "the log has no flag bits message, so data cannot be appended to it"
            ),
            ErrorKind::NoFreeAppendedOffset => {
                write!(f, "all three appended offsets of the log are in use")
            }
            ErrorKind::Export(e) => write!(f, "export: {e}"),
            ErrorKind::LayoutDiffers { topic, binding, log } => write!(
                f,
                "the log's format of `{topic}` is not the binding's: binding `{binding}`, log `{log}`"
            ),
        }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} (at byte {})", self.kind, self.offset)
    }
}

impl std::error::Error for Error {}

/// The library's result type.
pub type Result<T, E = Error> = core::result::Result<T, E>;
