//! Opening a file by memory map.

use std::fs::File;
use std::path::Path;

use crate::error::{Error, ErrorKind, Result};
use crate::read::log::ULog;

/// A log file mapped into memory; [`MappedFile::parse`] borrows from it, so no byte of
/// the data section is copied.
///
/// ```no_run
/// let file = ulog_core::MappedFile::open("flight.ulg")?;
/// let log = file.parse()?;
/// println!("{} topics", log.subscriptions().len());
/// # Ok::<(), ulog_core::Error>(())
/// ```
pub struct MappedFile {
    map: Option<memmap2::Mmap>,
}

impl MappedFile {
    /// Maps the file at `path` (read-only).
    pub fn open(path: impl AsRef<Path>) -> Result<MappedFile> {
        let path = path.as_ref();
        let io =
            |e: std::io::Error| Error::new(ErrorKind::Io(format!("{}: {e}", path.display())), 0);
        let file = File::open(path).map_err(io)?;
        let len = file.metadata().map_err(io)?.len();
        if len == 0 {
            // Mapping an empty file fails on some systems; an empty slice is the same.
            return Ok(MappedFile { map: None });
        }
        // SAFETY: the map is read-only and lives as long as `MappedFile`, which every
        // borrow of its bytes is tied to. The one hazard is outside Rust's control:
        // another process truncating or rewriting the file while it is mapped (reads
        // may then fault or see changed bytes). A file that may still be growing is
        // read with the incremental reader instead (see `StreamReader`).
        let map = unsafe { memmap2::Mmap::map(&file) }.map_err(io)?;
        Ok(MappedFile { map: Some(map) })
    }

    /// The file's bytes.
    pub fn bytes(&self) -> &[u8] {
        self.map.as_deref().unwrap_or(&[])
    }

    /// Parses the mapped file.
    pub fn parse(&self) -> Result<ULog<'_>> {
        ULog::parse(self.bytes())
    }
}
