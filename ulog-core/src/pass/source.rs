//! [`Source`]: where a pass takes a log's bytes from, and the loops that feed them to
//! framing: all at once (bytes in memory), in chunks read as framing goes, or in
//! chunks read ahead on a second thread.

use std::borrow::Cow;
use std::fs::File;
use std::io::Read;
use std::path::{Path, PathBuf};

use crate::error::ReadError;
use crate::log::file::LogFile;
use crate::log::ulog::ULog;
use crate::pass::driver::{Driver, Ran};
use crate::pass::keep::Keeper;
use crate::pass::keep::ScanSummary;
use crate::pass::visit::Visit;

/// Where a pass ([`scan`](crate::scan), [`scan_topics`](crate::scan_topics),
/// [`load_columns`](crate::load_columns)) reads a log from.
///
/// - bytes in memory (`&[u8]`, `&Vec<u8>`) or a [`LogFile`] (a memory map): framed in
///   place;
/// - a [`ULog`] already parsed: its index is used where it helps (timestamp order,
///   columns), its bytes framed otherwise;
/// - [`Source::reader`], any `Read` (a pipe, a socket, a decompressor), and
///   [`Source::file`], a file read with `read()` (no map: the memory held is a few
///   read buffers, and a file that changes while it is read cannot fault the
///   process): read in chunks as framing goes.
pub struct Source<'a> {
    pub(crate) inner: Inner<'a>,
    /// Sees each byte of a file as it is read ([`Source::file_observed`]).
    pub(crate) observer: Option<Observer<'a>>,
}

/// What [`Source::file_observed`] hands the bytes to.
pub(crate) type Observer<'a> = Box<dyn FnMut(&[u8]) + Send + 'a>;

/// A reader whose bytes `observer` sees as they are read.
struct Observed<'a, R> {
    reader: R,
    observer: Observer<'a>,
}

impl<R: Read> Read for Observed<'_, R> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let n = self.reader.read(buf)?;
        (self.observer)(&buf[..n]);
        Ok(n)
    }
}

pub(crate) enum Inner<'a> {
    Bytes(&'a [u8], Option<&'a Path>),
    Parsed(&'a ULog<'a>),
    Reader(Box<dyn Read + Send + 'a>),
    File(PathBuf),
}

impl<'a> Source<'a> {
    /// Any reader, read in chunks as the pass goes (it is not buffered further:
    /// a `File` needs no `BufReader`).
    pub fn reader(reader: impl Read + Send + 'a) -> Source<'a> {
        Source {
            inner: Inner::Reader(Box::new(reader)),
            observer: None,
        }
    }

    /// The file at `path`, opened by the pass and read in chunks (several threads
    /// of [`load_columns`](crate::load_columns) each read it).
    pub fn file(path: impl AsRef<Path>) -> Source<'static> {
        Source {
            inner: Inner::File(path.as_ref().to_owned()),
            observer: None,
        }
    }

    /// [`Source::file`], each byte handed to `observer` once, in order, as the pass
    /// reads it (on the thread that reads, which is not the pass's with read-ahead):
    /// a hash of the file at no second read. It sees the whole file when the pass
    /// frames it to its end.
    #[cfg_attr(not(feature = "parquet"), allow(dead_code))]
    pub(crate) fn file_observed(path: impl AsRef<Path>, observer: Observer<'a>) -> Source<'a> {
        Source {
            inner: Inner::File(path.as_ref().to_owned()),
            observer: Some(observer),
        }
    }
}

impl<'a> From<&'a [u8]> for Source<'a> {
    fn from(bytes: &'a [u8]) -> Source<'a> {
        Source {
            inner: Inner::Bytes(bytes, None),
            observer: None,
        }
    }
}

impl<'a> From<&'a Vec<u8>> for Source<'a> {
    fn from(bytes: &'a Vec<u8>) -> Source<'a> {
        Source::from(&bytes[..])
    }
}

impl<'a> From<&'a LogFile> for Source<'a> {
    fn from(file: &'a LogFile) -> Source<'a> {
        Source {
            inner: Inner::Bytes(file.bytes(), Some(file.path())),
            observer: None,
        }
    }
}

impl<'a, 'd: 'a> From<&'a ULog<'d>> for Source<'a> {
    fn from(log: &'a ULog<'d>) -> Source<'a> {
        Source {
            inner: Inner::Parsed(log),
            observer: None,
        }
    }
}

impl core::fmt::Debug for Source<'_> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match &self.inner {
            Inner::Bytes(b, path) => write!(f, "Source::Bytes({} bytes, {path:?})", b.len()),
            Inner::Parsed(_) => f.write_str("Source::Parsed"),
            Inner::Reader(_) => f.write_str("Source::Reader"),
            Inner::File(p) => write!(f, "Source::File({})", p.display()),
        }
    }
}

impl<'a> Inner<'a> {
    /// The file errors are said of, when there is one.
    pub fn path(&self) -> Option<&Path> {
        match self {
            Inner::Bytes(_, p) => *p,
            Inner::File(p) => Some(p),
            Inner::Parsed(_) | Inner::Reader(_) => None,
        }
    }

    /// The whole log in memory: borrowed where it already is, read otherwise.
    pub fn read_all(self) -> Result<Cow<'a, [u8]>, ReadError> {
        match self {
            Inner::Bytes(b, _) => Ok(Cow::Borrowed(b)),
            Inner::Parsed(log) => Ok(Cow::Borrowed(log.data())),
            Inner::Reader(mut r) => {
                let mut bytes = Vec::new();
                read_to_end(&mut r, &mut bytes)?;
                Ok(Cow::Owned(bytes))
            }
            Inner::File(path) => {
                let in_file = |e: ReadError| e.in_file(&path);
                let mut file = open(&path)?;
                let mut bytes = Vec::new();
                read_to_end(&mut file, &mut bytes).map_err(in_file)?;
                Ok(Cow::Owned(bytes))
            }
        }
    }
}

/// Opens `path` for a pass.
pub(crate) fn open(path: &Path) -> Result<File, ReadError> {
    File::open(path).map_err(|e| ReadError::io(e, None).in_file(path))
}

fn read_to_end(r: &mut dyn Read, bytes: &mut Vec<u8>) -> Result<(), ReadError> {
    loop {
        let len = bytes.len();
        bytes.resize(len + READ_CHUNK, 0);
        let n = read_some(r, &mut bytes[len..]).map_err(|e| ReadError::io(e, Some(len as u64)));
        let n = n.inspect_err(|_| bytes.truncate(len))?;
        bytes.truncate(len + n);
        if n == 0 {
            return Ok(());
        }
    }
}

/// One read into `buf`, retried while it is interrupted (`ErrorKind::Interrupted`
/// says to try again; nothing was read).
pub(crate) fn read_some(src: &mut (impl Read + ?Sized), buf: &mut [u8]) -> std::io::Result<usize> {
    loop {
        match src.read(buf) {
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
            other => return other,
        }
    }
}

/// Bytes read from a reader at a time.
const READ_CHUNK: usize = 256 * 1024;

/// Bytes read at a time when reading ahead: larger than [`READ_CHUNK`], the hand-over
/// from one thread to the other costing more than a read (bench/README.md has the
/// sizes tried).
const AHEAD_CHUNK: usize = 1 << 20;

/// Room kept before each chunk read ahead, for the bytes framing still needs from the
/// chunk before (a message, or the few that framing checks while it resynchronises;
/// more is moved the slow way).
const CARRY_ROOM: usize = 128 * 1024;

/// The memory page: each chunk read ahead is read to a page boundary of its buffer.
/// The kernel copies a cached file's pages about three times as fast to an address on
/// a page boundary as to one 16 bytes past it, where a buffer that `malloc` maps
/// starts (a 302 MB log's pass: 0.14 s → 0.07 s; bench/README.md).
const PAGE: usize = 4096;

/// Where the chunk of a buffer read ahead starts: the first page boundary of `buf`
/// at or after `room` (buffers have a page more than `room` and the chunk).
fn chunk_at(buf: &[u8], room: usize) -> usize {
    let addr = buf.as_ptr() as usize + room;
    room + (PAGE - addr % PAGE) % PAGE
}

/// Frames the whole log of `source` in file order, handing each data message to `f`;
/// `read_ahead` reads a reader's or file's next chunk on a second thread.
pub(crate) fn drive<F>(
    source: Source<'_>,
    read_ahead: bool,
    f: &mut F,
) -> Result<ScanSummary, ReadError>
where
    F: Visit + ?Sized,
{
    let mut driver = Driver::new();
    drive_with(source, read_ahead, &mut driver, f)?;
    Ok(driver.summary())
}

/// [`drive`], keeping the log's metadata as it goes by (see
/// [`LogMetadata`](crate::read::LogMetadata)) in the summary, and the data messages
/// of the topics named in `keep`.
pub(crate) fn drive_keeping<F>(
    source: Source<'_>,
    read_ahead: bool,
    keep: &[String],
    only: Option<&[String]>,
    f: &mut F,
) -> Result<ScanSummary, ReadError>
where
    F: Visit + ?Sized,
{
    let mut driver = Driver::new();
    let mut keeper = Keeper::new(f, keep, only);
    drive_with(source, read_ahead, &mut driver, &mut keeper)?;
    let mut summary = driver.summary();
    summary.metadata = Some(keeper.finish(&summary));
    Ok(summary)
}

fn drive_with<F>(
    source: Source<'_>,
    read_ahead: bool,
    driver: &mut Driver,
    f: &mut F,
) -> Result<(), ReadError>
where
    F: Visit + ?Sized,
{
    let path = source.inner.path().map(Path::to_owned);
    let in_file = |e: ReadError| match &path {
        Some(p) => e.in_file(p),
        None => e,
    };
    match source.inner {
        Inner::Bytes(bytes, _) => {
            // The whole file is given: framing ends, and the summary covers whatever
            // it framed.
            driver.run(bytes, 0, true, f).map_err(in_file)?;
        }
        Inner::Parsed(log) => {
            driver.run(log.data(), 0, true, f)?;
        }
        Inner::Reader(reader) if read_ahead => {
            read_ahead_chunks(reader, AHEAD_CHUNK, CARRY_ROOM, driver, f)?
        }
        Inner::Reader(mut reader) => read_chunks(&mut reader, driver, f)?,
        Inner::File(path) => {
            let file = open(&path)?;
            match source.observer {
                Some(observer) => read_file(
                    Observed {
                        reader: file,
                        observer,
                    },
                    read_ahead,
                    driver,
                    f,
                ),
                None => read_file(file, read_ahead, driver, f),
            }
            .map_err(in_file)?
        }
    }
    f.end(&driver.framer);
    Ok(())
}

/// Reads a file in chunks, read ahead on a second thread or not.
fn read_file<R, F>(
    mut file: R,
    read_ahead: bool,
    driver: &mut Driver,
    f: &mut F,
) -> Result<(), ReadError>
where
    R: Read + Send,
    F: Visit + ?Sized,
{
    if read_ahead {
        read_ahead_chunks(file, AHEAD_CHUNK, CARRY_ROOM, driver, f)
    } else {
        read_chunks(&mut file, driver, f)
    }
}

/// Reads `src` in chunks, keeping what framing still needs at the front of the
/// buffer and reading behind it, until the end, an error, or `f` stops.
fn read_chunks<F>(
    src: &mut (impl Read + ?Sized),
    driver: &mut Driver,
    f: &mut F,
) -> Result<(), ReadError>
where
    F: Visit + ?Sized,
{
    // The file from `base` is `buf[start..end]`.
    let mut buf = vec![0u8; READ_CHUNK * 2];
    let (mut start, mut end) = (0usize, 0usize);
    let mut base = 0u64;
    let mut eof = false;
    loop {
        if driver.run(&buf[start..end], base, eof, f)? != Ran::NeedMore {
            return Ok(());
        }
        let drop = driver.framer.done_with(base, end - start);
        start += drop;
        base += drop as u64;
        buf.copy_within(start..end, 0);
        end -= start;
        start = 0;
        if buf.len() - end < READ_CHUNK {
            buf.resize(end + READ_CHUNK, 0);
        }
        let n = read_some(src, &mut buf[end..])
            .map_err(|e| ReadError::io(e, Some(base + end as u64)))?;
        end += n;
        eof = n == 0;
    }
}

/// A chunk read ahead: the buffer (the bytes at `chunk_at(buf, room)`, `n` of them)
/// and `n` (0: the end of the source).
type Chunk = std::io::Result<(Vec<u8>, usize)>;

/// [`read_chunks`] with each chunk of `chunk` bytes read on a second thread while the
/// one before is framed, after `room` bytes kept for what framing still needs of it.
///
/// Returns once the reading thread has ended. After the end of
/// the source or a read error it reads no more; when the pass stops earlier (a log
/// refused at its start, `f` stopping or panicking), the read under way still has to
/// return: on a file at once, on a pipe or socket that stays open not until bytes
/// arrive or it closes. A thread that cannot be started is an I/O error.
pub(crate) fn read_ahead_chunks<R, F>(
    src: R,
    chunk: usize,
    room: usize,
    driver: &mut Driver,
    f: &mut F,
) -> Result<(), ReadError>
where
    R: Read + Send,
    F: Visit + ?Sized,
{
    use std::sync::mpsc::sync_channel;
    std::thread::scope(|s| {
        // Two buffers go round: one framed while the other is read (or waits). Both
        // channels go before the reader is joined (or as this closure unwinds): a
        // reader waiting on either one is let go.
        let (full_tx, full) = sync_channel::<Chunk>(1);
        let (free, free_rx) = sync_channel::<Vec<u8>>(2);
        for _ in 0..2 {
            let _ = free.send(vec![0u8; room + PAGE + chunk]);
        }
        let builder = std::thread::Builder::new().name("ulog read-ahead".to_owned());
        let reader = match builder
            .spawn_scoped(s, move || fill_chunks(src, room, chunk, full_tx, free_rx))
        {
            Ok(reader) => reader,
            Err(e) => return Err(ReadError::io(e, Some(0))),
        };
        let result = frame_ahead(chunk, room, driver, f, &full, &free);
        drop((full, free));
        crate::parallel::join_all(vec![reader]);
        result
    })
}

/// The framing side of [`read_ahead_chunks`]: frames each chunk `full` hands over,
/// carrying what framing still needs into the next, and gives buffers back to `free`.
fn frame_ahead<F>(
    chunk: usize,
    room: usize,
    driver: &mut Driver,
    f: &mut F,
    full: &std::sync::mpsc::Receiver<Chunk>,
    free: &std::sync::mpsc::SyncSender<Vec<u8>>,
) -> Result<(), ReadError>
where
    F: Visit + ?Sized,
{
    let mut cur = Vec::new();
    // The file from `base` is `cur[start..end]`, the bytes read so far.
    let (mut start, mut end, mut base) = (0usize, 0usize, 0u64);
    let mut eof = false;
    loop {
        if driver.run(&cur[start..end], base, eof, f)? != Ran::NeedMore {
            return Ok(());
        }
        // Carry what framing still needs into the next chunk.
        let read = base + (end - start) as u64;
        let drop = driver.framer.done_with(base, end - start);
        let carry = start + drop..end;
        let (mut next, n) = match full.recv() {
            Ok(Ok(chunk)) => chunk,
            Ok(Err(e)) => return Err(ReadError::io(e, Some(read))),
            // The reader sends until the end or an error: it hung up early only
            // if `src` panicked (passed on when it is joined).
            Err(_) => {
                let e = std::io::Error::other("the reading thread stopped");
                return Err(ReadError::io(e, Some(read)));
            }
        };
        let carried = carry.len();
        let at = chunk_at(&next, room);
        if carried <= at {
            next[at - carried..at].copy_from_slice(&cur[carry]);
            (start, end) = (at - carried, at + n);
        } else {
            let mut joined = Vec::with_capacity(carried + n);
            joined.extend_from_slice(&cur[carry]);
            joined.extend_from_slice(&next[at..at + n]);
            (start, end) = (0, joined.len());
            let _ = free.try_send(std::mem::replace(&mut next, joined));
        }
        base += drop as u64;
        eof = n == 0;
        let done = std::mem::replace(&mut cur, next);
        // Buffers of the reader's size go back to it (a joined one may happen to
        // be one); others go. (`try_send`: one the reader has no room for goes
        // too, rather than wait.)
        if done.len() == room + PAGE + chunk {
            let _ = free.try_send(done);
        }
    }
}

/// The reading thread of [`read_ahead_chunks`]: reads up to `chunk` bytes into the
/// buffers it is given, at the first page boundary after `room` bytes, once each (what
/// one read gives: a whole chunk from a file, what has arrived from a pipe), and sends
/// them on, until the end of `src` or an error.
fn fill_chunks<R: Read>(
    mut src: R,
    room: usize,
    chunk: usize,
    full: std::sync::mpsc::SyncSender<Chunk>,
    free: std::sync::mpsc::Receiver<Vec<u8>>,
) {
    while let Ok(mut buf) = free.recv() {
        let at = chunk_at(&buf, room);
        let read = read_some(&mut src, &mut buf[at..at + chunk]);
        let last = !matches!(read, Ok(n) if n > 0);
        let sent = full.send(read.map(|n| (buf, n)));
        if sent.is_err() || last {
            return;
        }
    }
}
#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::ReadErrorKind;
    use crate::pass::scan::{scan, ScanOptions};
    use crate::pass::visit::{DataRecord, Hand};
    use crate::testing::sample_log;

    /// Every data message of `bytes` through the driver, `f` saying whether to hand
    /// out more of the record's subscription.
    fn scan_filtered<F>(bytes: &[u8], mut f: F) -> Result<ScanSummary, ReadError>
    where
        F: FnMut(DataRecord<'_>) -> bool,
    {
        drive(Source::from(bytes), false, &mut |r: DataRecord<'_>| {
            if f(r) {
                Hand::Next
            } else {
                Hand::SkipTopic
            }
        })
    }

    /// The same from a reader, read in chunks.
    fn scan_chunks<R: Read + Send, F>(src: R, mut f: F) -> Result<ScanSummary, ReadError>
    where
        F: FnMut(DataRecord<'_>) -> bool,
    {
        drive(Source::reader(src), false, &mut |r: DataRecord<'_>| {
            if f(r) {
                Hand::Next
            } else {
                Hand::SkipTopic
            }
        })
    }

    /// The same read ahead, `chunk` bytes at a time after `room` bytes.
    fn read_ahead<R: Read + Send, F>(
        src: R,
        chunk: usize,
        room: usize,
        f: &mut F,
    ) -> Result<ScanSummary, ReadError>
    where
        F: FnMut(DataRecord<'_>) -> bool,
    {
        let mut driver = Driver::new();
        read_ahead_chunks(src, chunk, room, &mut driver, &mut |r: DataRecord<'_>| {
            if f(r) {
                Hand::Next
            } else {
                Hand::SkipTopic
            }
        })?;
        Ok(driver.summary())
    }

    fn plain_scan<F: FnMut(DataRecord<'_>)>(bytes: &[u8], f: F) -> Result<ScanSummary, ReadError> {
        scan(bytes, &ScanOptions::default(), f)
    }

    /// A subscription skipped after its `n`th record (`n` = its index mod 4) hands out
    /// exactly its first `n` records (at least one: the one that said so), in every
    /// scan (over the buffer, over reads of several sizes, read ahead), and the other
    /// subscriptions and the summary are unchanged: on the sample, and on the sample
    /// with junk in the middle of its data (records after it are framed while
    /// resynchronising, not on the plain path).
    #[test]
    fn a_skipped_subscription_hands_out_nothing_more() {
        let (sample, damaged, _) = sample_and_damaged();
        for (name, bytes) in [("sample", &sample[..]), ("damaged", &damaged)] {
            let mut all = Vec::new();
            let summary = plain_scan(bytes, |r| all.push((r.offset, r.topic.index()))).unwrap();
            if name == "damaged" {
                assert!(!summary.findings.is_empty());
            }
            let keep = |sub: usize| (sub % 4).max(1);
            let mut counts = vec![0usize; summary.topics.len()];
            let expected: Vec<(u64, usize)> = all
                .iter()
                .copied()
                .filter(|&(_, sub)| {
                    counts[sub] += 1;
                    counts[sub] <= keep(sub)
                })
                .collect();
            assert!(expected.len() < all.len());
            for chunk in [None, Some(1), Some(7), Some(4096), Some(0)] {
                let mut seen = vec![0usize; summary.topics.len()];
                let mut got = Vec::new();
                let mut f = |r: DataRecord<'_>| {
                    let sub = r.topic.index();
                    got.push((r.offset, sub));
                    seen[sub] += 1;
                    seen[sub] < keep(sub)
                };
                let filtered = match chunk {
                    None => scan_filtered(bytes, f).unwrap(),
                    // Read ahead, in chunks of 64 with 16 bytes of room.
                    Some(0) => read_ahead(Chunks(bytes, 50), 64, 16, &mut f).unwrap(),
                    Some(n) => scan_chunks(Chunks(bytes, n), &mut f).unwrap(),
                };
                assert_eq!(got, expected, "{name} {chunk:?}");
                assert_eq!(filtered, summary, "{name} {chunk:?}");
            }
        }
    }

    /// The sample, the sample with 37 junk bytes inserted before the data message in
    /// the middle of its data, and where they are.
    fn sample_and_damaged() -> (Vec<u8>, Vec<u8>, usize) {
        let sample = sample_log();
        let mut offsets = Vec::new();
        plain_scan(&sample, |r| offsets.push(r.offset)).unwrap();
        let mut damaged = sample.clone();
        let at = offsets[offsets.len() / 2] as usize;
        damaged.splice(at..at, [0xA5u8; 37]);
        (sample, damaged, at)
    }

    /// Reading ahead hands out the same records (offset, subscription, payload) and
    /// summary as one thread, on the sample, the sample with junk in its data, and
    /// the sample cut short: with chunks of several sizes down to one byte, and with
    /// no room or little room kept before a chunk (the bytes framing still needs then
    /// go the slow way).
    #[test]
    fn reading_ahead_hands_out_what_one_thread_does() {
        let (sample, damaged, at) = sample_and_damaged();
        let cut = &sample[..at + 5];
        for (name, bytes) in [("sample", &sample[..]), ("damaged", &damaged), ("cut", cut)] {
            let mut expected = Vec::new();
            let summary = plain_scan(bytes, |r| {
                expected.push((r.offset, r.topic.index(), r.payload.to_vec()))
            })
            .unwrap();
            for (chunk, room) in [(1, 0), (7, 3), (100, 64), (4096, 0), (4096, 1 << 17)] {
                let mut got = Vec::new();
                let ahead = read_ahead(bytes, chunk, room, &mut |r: DataRecord<'_>| {
                    got.push((r.offset, r.topic.index(), r.payload.to_vec()));
                    true
                })
                .unwrap();
                assert_eq!(ahead, summary, "{name} {chunk} {room}");
                assert!(got == expected, "{name} {chunk} {room}");
            }
        }
    }

    /// Framing can jump past the bytes read so far: a message cut by the start of
    /// appended data (its size runs past the appended offset) is left for the
    /// appended data. The next chunk must then be placed where the window ended, not
    /// where framing went: found by fuzzing.
    #[test]
    fn a_jump_to_appended_data_past_the_chunk_is_read_ahead_as_by_one_thread() {
        use crate::testing::LogBuilder;
        let build = |appended: u64| {
            let mut b = LogBuilder::new(1, 0);
            b.flag_bits([0; 8], [1, 0, 0, 0, 0, 0, 0, 0], [appended, 0, 0]);
            b.format("big:uint64_t timestamp;uint8_t[20000] blob");
            b.format("small:uint64_t timestamp;uint32_t x");
            b.subscribe(0, 0, "big").subscribe(0, 1, "small");
            let small = |b: &mut LogBuilder, t: u64| {
                let mut p = t.to_le_bytes().to_vec();
                p.extend_from_slice(&(t as u32).to_le_bytes());
                b.data(1, &p);
            };
            for t in 1..20 {
                small(&mut b, t);
            }
            let big_at = b.bytes().len() as u64;
            b.data(0, &[7u8; 20008]);
            let mut bytes = b.into_bytes();
            // The appended data overwrote the big message 300 bytes in.
            let at = big_at + 300;
            bytes.truncate(at as usize);
            let mut more = LogBuilder::new(1, 0);
            for t in 20..60 {
                small(&mut more, t);
            }
            bytes.extend_from_slice(&more.bytes()[16..]);
            (at, bytes)
        };
        let (at, _) = build(0);
        let (_, bytes) = build(at);
        let mut expected = Vec::new();
        let summary = plain_scan(&bytes, |r| expected.push(r.offset)).unwrap();
        assert_eq!(expected.len(), 59, "{:?}", summary.findings);
        assert!(summary
            .findings
            .iter()
            .any(|f| f.kind == crate::finding::FindingKind::PartialBeforeAppended));
        for (chunk, room) in [(64, 16), (100, 0), (299, 1024), (4096, 1024)] {
            let mut got = Vec::new();
            let ahead = read_ahead(Chunks(&bytes, 37), chunk, room, &mut |r: DataRecord<'_>| {
                got.push(r.offset);
                true
            })
            .unwrap();
            assert_eq!(got, expected, "{chunk} {room}");
            assert_eq!(ahead, summary, "{chunk} {room}");
        }
    }

    /// A read that fails is reported at the offset where it failed, as by one
    /// thread, after the records of the bytes read before it: in one chunk or after
    /// several.
    #[test]
    fn a_failed_read_ahead_is_the_error_one_thread_reports() {
        let sample = sample_log();
        for fail_at in [0, 10, sample.len() / 3, sample.len() - 1] {
            let mut plain = Vec::new();
            let one = ScanOptions::default();
            let e1 = scan(Source::reader(Failing(&sample, fail_at)), &one, |r| {
                plain.push(r.offset)
            })
            .unwrap_err();
            assert_eq!(e1.position(), Some(fail_at as u64));
            assert!(matches!(e1.kind(), ReadErrorKind::Io(_)), "{e1}");
            use std::error::Error as _;
            assert!(e1.source().is_some(), "the I/O error is kept");
            let mut ahead = Vec::new();
            let ahead_options = ScanOptions::default().read_ahead(true);
            let e2 = scan(
                Source::reader(Failing(&sample, fail_at)),
                &ahead_options,
                |r| ahead.push(r.offset),
            )
            .unwrap_err();
            let mut small = Vec::new();
            let e3 = read_ahead(Failing(&sample, fail_at), 64, 16, &mut |r: DataRecord<
                '_,
            >| {
                small.push(r.offset);
                true
            })
            .unwrap_err();
            for (e, got) in [(e2, ahead), (e3, small)] {
                assert_eq!(e, e1, "{fail_at}");
                assert_eq!(got, plain, "{fail_at}");
            }
        }
    }

    /// A scan that stops before the end of an endless source returns: a source that
    /// is not ULog, and a panic in `f` (passed on).
    #[test]
    fn a_pass_that_stops_early_lets_the_reading_thread_go() {
        let ahead = ScanOptions::default().read_ahead(true);
        let e = scan(Source::reader(std::io::repeat(0xA5)), &ahead, |_| {}).unwrap_err();
        assert!(matches!(e.kind(), ReadErrorKind::NotULog { .. }), "{e}");
        let sample = sample_log();
        let endless = (&sample[..]).chain(std::io::repeat(0));
        let panicked = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            scan(Source::reader(endless), &ahead, |_| -> () {
                panic!("stop here")
            })
        }));
        assert!(panicked.is_err());
        // A callback that stops: the summary says so, on every source.
        let endless = (&sample[..]).chain(std::io::repeat(0));
        for (source, options) in [
            (Source::from(&sample), ScanOptions::default()),
            (Source::reader(endless), ahead.clone()),
        ] {
            let mut seen = 0;
            let summary = scan(source, &options, |_| {
                seen += 1;
                if seen == 10 {
                    std::ops::ControlFlow::Break(())
                } else {
                    std::ops::ControlFlow::Continue(())
                }
            })
            .unwrap();
            assert_eq!(seen, 10);
            assert!(summary.stopped);
        }
    }

    /// Hands out its bytes up to `.1`, then fails.
    struct Failing<'a>(&'a [u8], usize);

    impl Read for Failing<'_> {
        fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
            if self.1 == 0 {
                return Err(std::io::Error::other("the disk is gone"));
            }
            let n = self.1.min(buf.len()).min(self.0.len()).min(1000);
            buf[..n].copy_from_slice(&self.0[..n]);
            self.0 = &self.0[n..];
            self.1 -= n;
            Ok(n)
        }
    }

    /// Hands out at most `.1` bytes a read.
    struct Chunks<'a>(&'a [u8], usize);

    impl Read for Chunks<'_> {
        fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
            let n = self.1.min(buf.len()).min(self.0.len());
            buf[..n].copy_from_slice(&self.0[..n]);
            self.0 = &self.0[n..];
            Ok(n)
        }
    }
}
