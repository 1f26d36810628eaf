//! [`ExportError`]: what stops a topic or a log from being exported.

use core::fmt;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use crate::access::lookup::LookupError;

/// Why an export failed. Matchable; new kinds may be added.
#[derive(Debug, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub enum ExportErrorKind {
    /// Reading or writing a file failed (the `std::io::Error` is the error's
    /// [`source`](std::error::Error::source)).
    Io(std::io::ErrorKind),
    /// A topic of [`Options::topics`](super::Options::topics) is not in the log, or a
    /// topic's format cannot be laid out.
    Lookup(LookupError),
    /// The topic has no field with values (padding only, zero-length arrays).
    NoValues {
        /// The topic.
        topic: String,
    },
    /// A payload too short for the topic's columns (framing never hands these out).
    ShortPayload {
        /// The topic.
        topic: String,
        /// The bytes its columns need.
        needed: usize,
        /// The payload's length.
        found: usize,
    },
    /// The log could not be read: not a ULog file, refused, or a read failed (the
    /// [`ReadError`](crate::ReadError) is the [`source`](std::error::Error::source)).
    Read,
    /// Arrow or Parquet refused the data (its error is the
    /// [`source`](std::error::Error::source)).
    Encoding,
    /// A [`Dataset`](super::Dataset) cannot hold this: one of its tables cannot be read
    /// back (the error's [`path`](ExportError::path) names it), was written with other
    /// options, or two topic names would share a folder.
    Dataset {
        /// What is wrong with it.
        what: String,
    },
    /// Another conversion is writing the [`Dataset`](super::Dataset): one writes a
    /// dataset at a time (see [`LOCK_FILE`](super::LOCK_FILE)). Try again when it has
    /// ended.
    Busy {
        /// Who holds the lock, as its file says (`process 1234 on hostname`).
        owner: String,
        /// The lock file: to remove by hand only when no conversion runs (one that was
        /// killed on another machine, or on a system where a dead owner cannot be told).
        lock: PathBuf,
    },
}

/// An export that failed: what, the file it was writing when there is one, and where
/// in the log when there is a place.
#[derive(Debug, Clone)]
pub struct ExportError(Box<Inner>);

#[derive(Debug, Clone)]
struct Inner {
    kind: ExportErrorKind,
    path: Option<PathBuf>,
    position: Option<u64>,
    source: Option<Arc<dyn std::error::Error + Send + Sync>>,
}

impl ExportError {
    fn from_inner(inner: Inner) -> ExportError {
        ExportError(Box::new(inner))
    }

    pub(crate) fn new(kind: ExportErrorKind) -> ExportError {
        ExportError::from_inner(Inner {
            kind,
            path: None,
            position: None,
            source: None,
        })
    }

    pub(crate) fn io(e: std::io::Error, path: &Path) -> ExportError {
        ExportError::from_inner(Inner {
            kind: ExportErrorKind::Io(e.kind()),
            path: Some(path.to_owned()),
            position: None,
            source: Some(Arc::new(e)),
        })
    }

    pub(crate) fn encoding(e: impl std::error::Error + Send + Sync + 'static) -> ExportError {
        ExportError::from_inner(Inner {
            kind: ExportErrorKind::Encoding,
            path: None,
            position: None,
            source: Some(Arc::new(e)),
        })
    }

    pub(crate) fn read(e: crate::ReadError) -> ExportError {
        ExportError::from_inner(Inner {
            kind: ExportErrorKind::Read,
            path: None,
            position: e.position(),
            source: Some(Arc::new(e)),
        })
    }

    /// `e`, met by a compaction after the conversion's commit: the logs are in, the
    /// small files are not all merged (`e` is the source).
    pub(crate) fn compaction(e: ExportError) -> ExportError {
        ExportError::from_inner(Inner {
            kind: ExportErrorKind::Dataset {
                what: format!(
                    "the logs were added, but merging the small files stopped (run the \
                     compaction again): {e}"
                ),
            },
            path: None,
            position: None,
            source: Some(Arc::new(e)),
        })
    }

    pub(crate) fn at(mut self, position: u64) -> ExportError {
        self.0.position = Some(position);
        self
    }

    pub(crate) fn in_file(mut self, path: &Path) -> ExportError {
        self.0.path.get_or_insert_with(|| path.to_owned());
        self
    }

    /// What went wrong.
    pub fn kind(&self) -> &ExportErrorKind {
        &self.0.kind
    }

    /// The file being written, when there is one.
    pub fn path(&self) -> Option<&Path> {
        self.0.path.as_deref()
    }

    /// The byte offset in the log it is about, where there is one.
    pub fn position(&self) -> Option<u64> {
        self.0.position
    }
}

impl From<LookupError> for ExportError {
    fn from(e: LookupError) -> ExportError {
        let position = e.position();
        ExportError::from_inner(Inner {
            kind: ExportErrorKind::Lookup(e),
            path: None,
            position,
            source: None,
        })
    }
}

impl PartialEq for ExportError {
    /// The same kind about the same file and place.
    fn eq(&self, other: &ExportError) -> bool {
        let (a, b) = (&*self.0, &*other.0);
        (&a.kind, &a.path, a.position) == (&b.kind, &b.path, b.position)
    }
}

impl Eq for ExportError {}

impl fmt::Display for ExportError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let e = &*self.0;
        if let Some(p) = &e.path {
            write!(f, "{}: ", p.display())?;
        }
        match (&e.kind, &e.source) {
            (
                ExportErrorKind::Io(_) | ExportErrorKind::Encoding | ExportErrorKind::Read,
                Some(e),
            ) => {
                write!(f, "{e}")
            }
            (ExportErrorKind::Io(k), None) => write!(f, "i/o error: {k}"),
            (ExportErrorKind::Encoding, None) => write!(f, "Arrow or Parquet refused the data"),
            (ExportErrorKind::Read, None) => write!(f, "the log could not be read"),
            (ExportErrorKind::Lookup(e), _) => write!(f, "{e}"),
            (ExportErrorKind::Dataset { what }, _) => {
                write!(f, "{what}")
            }
            (ExportErrorKind::Busy { owner, lock }, _) => write!(
                f,
                "the dataset is being written by another conversion ({owner}); run again \
                 when it has ended (if none runs, remove {})",
                lock.display()
            ),
            (ExportErrorKind::NoValues { topic }, _) => {
                write!(f, "topic `{topic}` has no field with values")
            }
            (
                ExportErrorKind::ShortPayload {
                    topic,
                    needed,
                    found,
                },
                _,
            ) => write!(
                f,
                "a payload of `{topic}` has {found} bytes, its columns need {needed}"
            ),
        }?;
        match (e.position, &e.kind) {
            // A lookup error says where itself.
            (Some(at), ExportErrorKind::ShortPayload { .. }) => write!(f, " (at byte {at})"),
            _ => Ok(()),
        }
    }
}

impl std::error::Error for ExportError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match (&self.0.kind, &self.0.source) {
            (ExportErrorKind::Lookup(e), _) => Some(e),
            (_, Some(e)) => Some(&**e as &(dyn std::error::Error + 'static)),
            _ => None,
        }
    }
}
