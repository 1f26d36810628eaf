//! [`ReadError`]: what stops a log from being read at all, and where.
//!
//! Damage inside a log never stops a read (it becomes a [`Finding`](crate::Finding));
//! what does is input that is not ULog, a log the spec says to refuse, or the bytes
//! not arriving (an I/O error).

use core::fmt;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Why a log could not be read. Matchable; new kinds may be added.
#[derive(Debug, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub enum ReadErrorKind {
    /// Reading the bytes failed (the `std::io::Error` is the error's
    /// [`source`](std::error::Error::source)).
    Io(std::io::ErrorKind),
    /// The file is empty.
    Empty,
    /// The file does not start with the ULog magic; says what it looks like instead.
    NotULog {
        /// A short description of what was found (e.g. `a gzip file`).
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
    /// The file changed while it was read: passes over it (the threads of
    /// [`load_columns`](crate::load_columns) each read the file) framed different
    /// logs, or the pass of a Parquet dataset's export read other bytes than those
    /// its `log_id` was taken of.
    Changed,
}

/// A log that could not be read: what, where in the file when there is a place, and
/// which file when it is known.
///
/// ```
/// let e = ulog_core::ULog::parse(b"\x1f\x8b\x08\0 a gzip file").unwrap_err();
/// assert!(matches!(e.kind(), ulog_core::read::ReadErrorKind::NotULog { .. }));
/// assert_eq!(e.position(), Some(0));
/// assert_eq!(e.to_string(), "not a ULog file: no ULog magic at the start, found a gzip file");
/// ```
#[derive(Debug, Clone)]
pub struct ReadError {
    kind: ReadErrorKind,
    position: Option<u64>,
    path: Option<PathBuf>,
    io: Option<Arc<std::io::Error>>,
}

impl ReadError {
    pub(crate) fn new(kind: ReadErrorKind, position: Option<u64>) -> ReadError {
        ReadError {
            kind,
            position,
            path: None,
            io: None,
        }
    }

    /// An I/O error while reading the bytes at `position` (`None`: before any byte,
    /// such as opening the file).
    pub(crate) fn io(e: std::io::Error, position: Option<u64>) -> ReadError {
        ReadError {
            kind: ReadErrorKind::Io(e.kind()),
            position,
            path: None,
            io: Some(Arc::new(e)),
        }
    }

    /// The error, said of the file at `path`.
    pub(crate) fn in_file(mut self, path: &Path) -> ReadError {
        self.path = Some(path.to_owned());
        self
    }

    /// What went wrong.
    pub fn kind(&self) -> &ReadErrorKind {
        &self.kind
    }

    /// The byte offset in the file where it went wrong, where there is one.
    pub fn position(&self) -> Option<u64> {
        self.position
    }

    /// The file, when the error came from reading a path.
    pub fn path(&self) -> Option<&Path> {
        self.path.as_deref()
    }

    /// What went wrong, without the file and the position: for output that shows
    /// those apart.
    pub fn what(&self) -> String {
        match (&self.kind, &self.io) {
            (ReadErrorKind::Io(_), Some(e)) => e.to_string(),
            (ReadErrorKind::Io(k), None) => format!("i/o error: {k}"),
            (ReadErrorKind::Empty, _) => "not a ULog file: the file is empty".to_owned(),
            (ReadErrorKind::NotULog { found }, _) => {
                format!("not a ULog file: no ULog magic at the start, found {found}")
            }
            (ReadErrorKind::TruncatedHeader { len }, _) => {
                format!("truncated ULog header: the file has {len} bytes, the header needs 16")
            }
            (ReadErrorKind::Changed, _) => {
                "the file changed while it was read (two reads of it differ): read it once it is \
                 complete"
                    .to_owned()
            }
            (ReadErrorKind::UnknownIncompatFlags { byte, bits }, _) => format!(
                "refused: unknown incompatible flag bits {bits:#04x} in incompat_flags[{byte}]"
            ),
        }
    }
}

impl PartialEq for ReadError {
    /// The same kind at the same place of the same file (two I/O errors of one kind
    /// are equal whatever their text).
    fn eq(&self, other: &ReadError) -> bool {
        (&self.kind, self.position, &self.path) == (&other.kind, other.position, &other.path)
    }
}

impl Eq for ReadError {}

impl fmt::Display for ReadError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(p) = &self.path {
            write!(f, "{}: ", p.display())?;
        }
        f.write_str(&self.what())?;
        // A position of 0 on a file that is not ULog says nothing the text does not.
        match (self.position, &self.kind) {
            (Some(at), ReadErrorKind::Io(_) | ReadErrorKind::UnknownIncompatFlags { .. }) => {
                write!(f, " (at byte {at})")
            }
            _ => Ok(()),
        }
    }
}

impl std::error::Error for ReadError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        self.io
            .as_deref()
            .map(|e| e as &(dyn std::error::Error + 'static))
    }
}
