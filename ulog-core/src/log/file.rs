//! [`LogFile`]: a log file mapped into memory.

use std::fs::File;
use std::path::{Path, PathBuf};

use crate::error::ReadError;
use crate::log::ulog::ULog;

/// A log file mapped into memory (feature `mmap`, on by default): [`LogFile::parse`] borrows from it, so no byte of
/// the data section is copied, and a one-pass read of it
/// ([`scan`](crate::scan), [`scan_topics`](crate::scan_topics)) reads the map.
///
/// The map is of the file as it is when opened. Another process truncating or
/// rewriting it while it is mapped can make reads fault or see changed bytes; read a
/// file that may change (a log being written, one being rotated or synced) in one
/// pass from a reader instead ([`Source::file`](crate::Source::file)).
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
    /// Read into memory: an empty file, or a build without the `mmap` feature.
    Read(Vec<u8>),
}

impl LogFile {
    /// Maps the file at `path` read-only (without the `mmap` feature: reads it into
    /// memory).
    pub fn open(path: impl AsRef<Path>) -> Result<LogFile, ReadError> {
        let path = path.as_ref();
        let io = |e: std::io::Error| ReadError::io(e, None).in_file(path);
        let file = File::open(path).map_err(io)?;
        Ok(LogFile {
            bytes: Self::bytes_of(file).map_err(io)?,
            path: path.to_owned(),
        })
    }

    #[cfg(feature = "mmap")]
    fn bytes_of(file: File) -> std::io::Result<Bytes> {
        if file.metadata()?.len() == 0 {
            // Mapping an empty file fails on some systems; an empty slice is the same.
            return Ok(Bytes::Read(Vec::new()));
        }
        crate::audited::map(&file).map(Bytes::Mapped)
    }

    #[cfg(not(feature = "mmap"))]
    fn bytes_of(mut file: File) -> std::io::Result<Bytes> {
        let mut bytes = Vec::new();
        std::io::Read::read_to_end(&mut file, &mut bytes)?;
        Ok(Bytes::Read(bytes))
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

    /// Parses the mapped file; an error names the file.
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
