//! [`LogFile`]: a log file held in memory, read once or mapped.

use std::path::{Path, PathBuf};

use crate::error::ReadError;
use crate::log::ulog::ULog;

/// A log file in memory: [`LogFile::parse`] borrows from it, so no byte of the data
/// section is copied again, and a one-pass read of it ([`scan`](crate::scan),
/// [`scan_topics`](crate::scan_topics)) reads it where it is.
///
/// [`LogFile::open`] reads the whole file once: a snapshot of the file as it was
/// read. Another process truncating, extending or rewriting the file meanwhile (a
/// logger still writing, a log being rotated or synced) changes at most what the
/// snapshot holds, which the reader then treats as any log: a prefix, more messages,
/// or damage reported as findings. Nothing of it can fault or panic.
///
/// [`LogFile::map`] maps the file instead (feature `mmap`, on by default): no copy, and
/// pages read only where the log is read, but `unsafe`, because a file that changes
/// while it is mapped can kill the process (see its safety section).
///
/// ```no_run
/// let file = ulog_core::LogFile::open("flight.ulg")?;
/// let log = file.parse()?;
/// println!("{} topics", log.subscriptions().len());
/// # Ok::<(), ulog_core::ReadError>(())
/// ```
pub struct LogFile {
    bytes: Bytes,
    path: PathBuf,
}

enum Bytes {
    #[cfg(feature = "mmap")]
    Mapped(memmap2::Mmap),
    Read(Vec<u8>),
}

impl LogFile {
    /// Reads the file at `path` into memory (a snapshot of it; see [`LogFile`]).
    pub fn open(path: impl AsRef<Path>) -> Result<LogFile, ReadError> {
        let path = path.as_ref();
        let bytes = std::fs::read(path).map_err(|e| ReadError::io(e, None).in_file(path))?;
        Ok(LogFile {
            bytes: Bytes::Read(bytes),
            path: path.to_owned(),
        })
    }

    /// Maps the file at `path` read-only instead of reading it ([`LogFile::open`]): no
    /// copy of the file, and only the pages the reader touches are read, which saves
    /// the time and memory of the copy on large logs (bench/README.md).
    ///
    /// # Safety
    ///
    /// The file must not be truncated or written, by this process or another, while
    /// the returned `LogFile` (or anything borrowed from it) lives. A truncated file
    /// kills the process with `SIGBUS` when the reader touches a page past the new
    /// end, and bytes that change under a borrowed `&[u8]` break what Rust promises
    /// about it. Use it for files nothing else writes (a log copied off the vehicle,
    /// not one a logger or a sync tool may still change).
    #[cfg(feature = "mmap")]
    #[allow(unsafe_code)]
    pub unsafe fn map(path: impl AsRef<Path>) -> Result<LogFile, ReadError> {
        let path = path.as_ref();
        let io = |e: std::io::Error| ReadError::io(e, None).in_file(path);
        let file = std::fs::File::open(path).map_err(io)?;
        let bytes = if file.metadata().map_err(io)?.len() == 0 {
            // Mapping an empty file fails on some systems; an empty buffer is the same.
            Bytes::Read(Vec::new())
        } else {
            // SAFETY: the file does not change while mapped: this function's contract.
            Bytes::Mapped(unsafe { crate::audited::map(&file) }.map_err(io)?)
        };
        Ok(LogFile {
            bytes,
            path: path.to_owned(),
        })
    }

    /// The file's bytes.
    pub fn bytes(&self) -> &[u8] {
        match &self.bytes {
            #[cfg(feature = "mmap")]
            Bytes::Mapped(m) => m,
            Bytes::Read(v) => v,
        }
    }

    /// The path it was opened from.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Parses the file; an error names the file.
    pub fn parse(&self) -> Result<ULog<'_>, ReadError> {
        ULog::parse(self.bytes()).map_err(|e| e.in_file(&self.path))
    }
}

impl core::fmt::Debug for LogFile {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("LogFile")
            .field("path", &self.path)
            .field("len", &self.bytes().len())
            .finish()
    }
}
