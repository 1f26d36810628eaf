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
    /// The extensions of ULog files (`.ulg`, `.ulog`, compared without case).
    pub const EXTENSIONS: [&'static str; 2] = ["ulg", "ulog"];

    /// Whether `path` is named as a log file (one of [`LogFile::EXTENSIONS`]).
    pub fn is_log_name(path: &Path) -> bool {
        path.extension().is_some_and(|e| {
            LogFile::EXTENSIONS
                .iter()
                .any(|x| e.eq_ignore_ascii_case(x))
        })
    }

    /// The logs `input` names, each with its size: the file itself (whatever its
    /// name), or for a directory every log file ([`LogFile::is_log_name`]) in it and
    /// its subdirectories (not behind a symbolic link to a directory, which could
    /// loop), sorted; none when a directory holds none. What `ulog` commands and
    /// `ulog_rs.convert` take as their inputs.
    ///
    /// ```
    /// let dir = std::env::temp_dir().join(format!("ulog-find-{}", std::process::id()));
    /// std::fs::create_dir_all(dir.join("sub"))?;
    /// std::fs::write(dir.join("sub/b.ULG"), b"x")?;
    /// std::fs::write(dir.join("a.ulog"), b"xy")?;
    /// std::fs::write(dir.join("notes.txt"), b"")?;
    /// let found = ulog_core::LogFile::find(&dir)?;
    /// assert_eq!(found, [(dir.join("a.ulog"), 2), (dir.join("sub/b.ULG"), 1)]);
    /// # std::fs::remove_dir_all(&dir)?;
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn find(input: impl AsRef<Path>) -> Result<Vec<(PathBuf, u64)>, ReadError> {
        let input = input.as_ref();
        let meta = std::fs::metadata(input).map_err(|e| ReadError::io(e, None).in_file(input))?;
        if !meta.is_dir() {
            return Ok(vec![(input.to_owned(), meta.len())]);
        }
        let mut logs = Vec::new();
        find_logs(input, &mut logs)?;
        logs.sort();
        Ok(logs)
    }

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

    /// A log already in memory (fetched from object storage, received over a
    /// network), named `path` (a URL, or any name errors should give).
    ///
    /// ```
    /// let file = ulog_core::LogFile::from_bytes(ulog_core::testing::sample_log(), "sample.ulg");
    /// assert!(file.parse().is_ok());
    /// ```
    pub fn from_bytes(bytes: Vec<u8>, path: impl Into<PathBuf>) -> LogFile {
        LogFile {
            bytes: Bytes::Read(bytes),
            path: path.into(),
        }
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
fn read_large(file: &std::fs::File, len: u64) -> std::io::Result<Option<Bytes>> {
    let Ok(len) = usize::try_from(len) else {
        return Ok(None);
    };
    let Ok(mut memory) = memmap2::MmapOptions::new().len(len).map_anon() else {
        return Ok(None);
    };
    // Advice only: without huge pages the read is as fast as into a `Vec`.
    #[cfg(target_os = "linux")]
    let _ = memory.advise(memmap2::Advice::HugePage);
    let filled = read_parts(file, &mut memory, PART)?;
    Ok(Some(Bytes::Anonymous(memory, filled)))
}

/// The size of the parts a large file is read in on several threads: at least this,
/// so that a thread's start costs little beside its read.
#[cfg(feature = "mmap")]
const PART: usize = 32 << 20;

/// Reads `file` from its start into `memory`, in parts of at least `part` bytes on up
/// to one thread per core: the copy, and the kernel's zeroing of the fresh pages,
/// split between them (bench/README.md has what it saves). Returns the length of the
/// prefix read: all of `memory`, or less where the file shrank meanwhile.
#[cfg(feature = "mmap")]
fn read_parts(file: &std::fs::File, memory: &mut [u8], part: usize) -> std::io::Result<usize> {
    if memory.is_empty() {
        return Ok(0);
    }
    // Elsewhere reads go through the file's one cursor: one part.
    let threads = if cfg!(any(unix, windows)) {
        std::thread::available_parallelism().map_or(1, |n| n.get())
    } else {
        1
    };
    let count = (memory.len() / part.max(1)).clamp(1, threads);
    // Parts of whole huge pages (from the start of the memory, which the kernel
    // aligns to them where it backs it with them): no page faulted by two threads.
    let size = memory.len().div_ceil(count).next_multiple_of(2 << 20);
    let len = memory.len();
    let parts: Vec<std::sync::Mutex<Option<&mut [u8]>>> = memory
        .chunks_mut(size)
        .map(|c| std::sync::Mutex::new(Some(c)))
        .collect();
    let costs = vec![1u64; parts.len()];
    let read = crate::parallel::largest_first(&costs, count, |i| {
        let part = parts[i].lock().unwrap_or_else(|p| p.into_inner()).take();
        read_at(file, part.unwrap_or_default(), (i * size) as u64)
    });
    let (mut filled, mut ended) = (0, false);
    for (i, r) in read.into_iter().enumerate() {
        match r {
            Some(Err(e)) => return Err(e),
            Some(Ok(n)) if !ended => {
                filled += n;
                // A part the file no longer reaches: the snapshot ends there.
                ended = n < size.min(len - i * size);
            }
            // Parts after the end, or not read because another failed (its error is
            // the result).
            _ => {}
        }
    }
    Ok(filled)
}

/// Fills `buf` from byte `at` of `file`; returns how much was read (less at the end of
/// the file).
#[cfg(feature = "mmap")]
fn read_at(file: &std::fs::File, buf: &mut [u8], at: u64) -> std::io::Result<usize> {
    let mut filled = 0;
    while filled < buf.len() {
        match read_once(file, &mut buf[filled..], at + filled as u64) {
            Ok(0) => break,
            Ok(n) => filled += n,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
            Err(e) => return Err(e),
        }
    }
    Ok(filled)
}

#[cfg(all(feature = "mmap", unix))]
fn read_once(file: &std::fs::File, buf: &mut [u8], at: u64) -> std::io::Result<usize> {
    std::os::unix::fs::FileExt::read_at(file, buf, at)
}

#[cfg(all(feature = "mmap", windows))]
fn read_once(file: &std::fs::File, buf: &mut [u8], at: u64) -> std::io::Result<usize> {
    std::os::windows::fs::FileExt::seek_read(file, buf, at)
}

#[cfg(all(feature = "mmap", not(any(unix, windows))))]
fn read_once(mut file: &std::fs::File, buf: &mut [u8], at: u64) -> std::io::Result<usize> {
    use std::io::{Read, Seek, SeekFrom};
    file.seek(SeekFrom::Start(at))?;
    file.read(buf)
}

impl core::fmt::Debug for LogFile {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("LogFile")
            .field("path", &self.path)
            .field("len", &self.bytes().len())
            .finish()
    }
}

/// The read error of an I/O failure on `path`.
fn io(path: &Path) -> impl Fn(std::io::Error) -> ReadError + '_ {
    move |e| ReadError::io(e, None).in_file(path)
}

/// Adds the log files in `dir` and its subdirectories to `logs` (see [`LogFile::find`]).
fn find_logs(dir: &Path, logs: &mut Vec<(PathBuf, u64)>) -> Result<(), ReadError> {
    for entry in std::fs::read_dir(dir).map_err(io(dir))? {
        let entry = entry.map_err(io(dir))?;
        let path = entry.path();
        if entry.file_type().map_err(io(&path))?.is_dir() {
            find_logs(&path, logs)?;
            continue;
        }
        if !LogFile::is_log_name(&path) {
            continue;
        }
        let meta = std::fs::metadata(&path).map_err(io(&path))?;
        if meta.is_file() {
            logs.push((path, meta.len()));
        }
    }
    Ok(())
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

    /// A file read in parts on several threads: the same bytes, in order, as long as
    /// the file; a buffer longer than the file (it shrank after it was measured) holds
    /// the file and says how much of it.
    #[cfg(feature = "mmap")]
    #[test]
    fn parts_read_the_file_in_order() {
        let path = std::env::temp_dir().join(format!("ulog-parts-{}", std::process::id()));
        let bytes: Vec<u8> = (0..(5u32 << 20) + 12_345)
            .map(|i| (i % 251) as u8)
            .collect();
        std::fs::write(&path, &bytes).unwrap();
        let file = std::fs::File::open(&path).unwrap();
        let mut none: [u8; 0] = [];
        assert_eq!(read_parts(&file, &mut none, 1 << 20).unwrap(), 0);
        for extra in [0, 3 << 20] {
            let mut memory = vec![0u8; bytes.len() + extra];
            let n = read_parts(&file, &mut memory, 1 << 20).unwrap();
            assert_eq!(n, bytes.len(), "{extra} bytes more than the file");
            assert!(memory[..n] == bytes[..], "{extra} bytes more than the file");
        }
        std::fs::remove_file(&path).ok();
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
