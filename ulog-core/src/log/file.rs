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
    /// A snapshot in anonymous memory, of which the first `.1` bytes were read.
    #[cfg(feature = "mmap")]
    Anonymous(memmap2::MmapMut, usize),
    Read(Vec<u8>),
}

impl LogFile {
    /// Reads the file at `path` into memory (a snapshot of it; see [`LogFile`]): as
    /// many bytes as it held when opened, or fewer if it shrinks meanwhile. A path
    /// that is not a regular file (a pipe, a device) is read to its end.
    pub fn open(path: impl AsRef<Path>) -> Result<LogFile, ReadError> {
        let path = path.as_ref();
        let io = |e: std::io::Error| ReadError::io(e, None).in_file(path);
        let file = std::fs::File::open(path).map_err(io)?;
        let meta = file.metadata().map_err(io)?;
        if !meta.is_file() {
            let mut bytes = Vec::new();
            std::io::Read::read_to_end(&mut &file, &mut bytes).map_err(io)?;
            return Ok(LogFile {
                bytes: Bytes::Read(bytes),
                path: path.to_owned(),
            });
        }
        let len = meta.len();
        #[cfg(feature = "mmap")]
        if len >= LARGE {
            if let Some(bytes) = read_large(&file, len).map_err(io)? {
                return Ok(LogFile {
                    bytes,
                    path: path.to_owned(),
                });
            }
        }
        let mut bytes = Vec::with_capacity(usize::try_from(len).unwrap_or(0));
        std::io::Read::read_to_end(&mut std::io::Read::take(&file, len), &mut bytes).map_err(io)?;
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
            #[cfg(feature = "mmap")]
            Bytes::Anonymous(m, len) => &m[..*len],
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

/// From this size on, [`LogFile::open`] reads into anonymous memory that may be
/// backed by huge pages: the copy of a large log then faults a page per 2 MiB instead
/// of per 4 KiB (bench/README.md has what it saves).
#[cfg(feature = "mmap")]
const LARGE: u64 = 8 << 20;

/// Reads up to `len` bytes of `file` into anonymous memory; `None` where it cannot be
/// allocated so (the caller then reads into a `Vec`).
#[cfg(feature = "mmap")]
fn read_large(mut file: &std::fs::File, len: u64) -> std::io::Result<Option<Bytes>> {
    let Ok(len) = usize::try_from(len) else {
        return Ok(None);
    };
    let Ok(mut memory) = memmap2::MmapOptions::new().len(len).map_anon() else {
        return Ok(None);
    };
    // Advice only: without huge pages the read is as fast as into a `Vec`.
    #[cfg(target_os = "linux")]
    let _ = memory.advise(memmap2::Advice::HugePage);
    let mut filled = 0;
    while filled < len {
        match std::io::Read::read(&mut file, &mut memory[filled..]) {
            // The file shrank since it was opened: the snapshot is what it held.
            Ok(0) => break,
            Ok(n) => filled += n,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
            Err(e) => return Err(e),
        }
    }
    Ok(Some(Bytes::Anonymous(memory, filled)))
}

impl core::fmt::Debug for LogFile {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("LogFile")
            .field("path", &self.path)
            .field("len", &self.bytes().len())
            .finish()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A file read whole, small or large (read into anonymous memory from `LARGE` on):
    /// the same bytes either way, and the same log.
    #[test]
    fn open_reads_small_and_large_files_whole() {
        let dir = std::env::temp_dir().join(format!("ulog-logfile-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let log = crate::testing::sample_log();
        let mut big = log.clone();
        // Padding after the log is read as more (damaged) data: enough to pass `LARGE`.
        big.resize(log.len() + (9 << 20), 0x55);
        for (name, bytes) in [("small.ulg", &log), ("big.ulg", &big)] {
            let path = dir.join(name);
            std::fs::write(&path, bytes).unwrap();
            let file = LogFile::open(&path).unwrap();
            assert_eq!(file.bytes(), &bytes[..], "{name}");
            assert_eq!(file.path(), path);
            let parsed = file.parse().unwrap();
            assert!(parsed.topic("vehicle_attitude", 0).is_ok(), "{name}");
        }
        std::fs::remove_dir_all(&dir).ok();
    }

    /// A pipe has no length: it is read to its end.
    #[cfg(unix)]
    #[test]
    fn open_reads_a_pipe_to_its_end() {
        let dir = std::env::temp_dir().join(format!("ulog-logfile-fifo-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let fifo = dir.join("log.fifo");
        let made = std::process::Command::new("mkfifo").arg(&fifo).status();
        assert!(made.is_ok_and(|s| s.success()), "mkfifo");
        let log = crate::testing::sample_log();
        let writer = {
            let (fifo, log) = (fifo.clone(), log.clone());
            std::thread::spawn(move || std::fs::write(fifo, log).unwrap())
        };
        let file = LogFile::open(&fifo).unwrap();
        writer.join().unwrap();
        assert_eq!(file.bytes(), &log[..]);
        std::fs::remove_dir_all(&dir).ok();
    }
}
