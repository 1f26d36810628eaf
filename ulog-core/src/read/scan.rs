//! One pass over the data messages of a log, in file order, keeping nothing: the
//! fastest way through a log when each message is needed once (a sum, a conversion,
//! a filter, columns built as the file goes by). [`scan`] reads a buffer or a memory
//! map; [`scan_reader`] reads any `Read` in bounded memory, so a log far larger than
//! memory is read with a few hundred KiB resident.
//!
//! Framing is the same as [`ULog::parse`](crate::ULog::parse)'s: definitions and
//! subscriptions are learnt, damage is stepped over and reported in the summary. Only
//! data messages of known subscriptions are handed out; the other messages are framed
//! and counted (use [`Messages`](crate::Messages) to see them).

use std::io::Read;
use std::sync::Arc;

use ulog_format::{Layout, LayoutError};

use crate::error::{Error, ErrorKind, Result};
use crate::finding::Finding;
use crate::read::framing::{FlagBits, Framer, Header, Step, SubDef, MSG_HEADER_LEN};
use crate::read::source::read_some;

/// A data message met by a scan.
#[derive(Debug, Clone, Copy)]
pub struct ScanRecord<'s, 'p> {
    /// Byte offset of the message's 3-byte header.
    pub offset: u64,
    /// The subscription's index, in the order of the `A` messages (the index into
    /// [`ULog::subscriptions`](crate::ULog::subscriptions) of the same file).
    pub subscription: usize,
    /// Byte offset of the subscription's `A` message.
    pub subscribed_at: u64,
    /// The topic (format) name.
    pub name: &'s str,
    /// The instance number.
    pub multi_id: u8,
    /// The layout of the topic's format (`None` when it could not be laid out; the
    /// finding says why).
    pub layout: Option<&'s Arc<Layout>>,
    /// The payload after the msg_id.
    pub payload: &'p [u8],
}

/// A subscription met by a scan.
#[derive(Debug, Clone, PartialEq)]
pub struct ScanTopic {
    /// The topic (format) name.
    pub name: String,
    /// The instance number.
    pub multi_id: u8,
    /// The msg_id of its (first) subscription.
    pub msg_id: u16,
    /// Byte offset of the subscription's `A` message.
    pub subscribed_at: u64,
    /// The layout of the topic's format, or why it could not be laid out.
    pub layout: std::result::Result<Arc<Layout>, LayoutError>,
}

/// What a scan saw besides the data messages it handed out.
#[derive(Debug, Clone, PartialEq)]
pub struct ScanSummary {
    /// The file header.
    pub header: Header,
    /// The flag bits message, when the log has one.
    pub flag_bits: Option<FlagBits>,
    /// Messages framed (of every type).
    pub messages: u64,
    /// Data messages of known subscriptions framed: every one is handed out by
    /// [`scan`] and [`scan_reader`]; scans that skip topics (such as
    /// [`scan_topics_only`](crate::scan_topics_only)) count the skipped ones too.
    pub data_messages: u64,
    /// Every subscription met, in the order of the `A` messages (the indexes of
    /// [`ScanRecord::subscription`]).
    pub topics: Vec<ScanTopic>,
    /// What the reader found and stepped over, in file order.
    pub findings: Vec<Finding>,
}

/// The framing state of a scan between windows of the file.
struct Driver {
    framer: Framer,
    messages: u64,
    data: u64,
    /// Subscriptions whose records are no longer handed out (see [`scan_filtered`]).
    skip: Vec<bool>,
}

#[inline(always)]
fn record<'s, 'p>(offset: u64, sub: u32, def: &'s SubDef, payload: &'p [u8]) -> ScanRecord<'s, 'p> {
    ScanRecord {
        offset,
        subscription: sub as usize,
        subscribed_at: def.offset,
        name: &def.name,
        multi_id: def.multi_id,
        layout: def.layout.as_ref().ok(),
        // Framing checked that a data message holds its msg_id.
        payload: &payload[2..],
    }
}

/// Hands the data message at `offset` (of subscription `sub`) to `f` unless the
/// subscription is skipped, and skips it from now on when `f` says so.
#[inline(always)]
fn hand_out<'w, F>(
    skip: &mut Vec<bool>,
    offset: u64,
    sub: u32,
    def: &SubDef,
    payload: &'w [u8],
    f: &mut F,
) where
    F: FnMut(ScanRecord<'_, 'w>) -> bool,
{
    if skip.get(sub as usize) == Some(&true) {
        return;
    }
    if !f(record(offset, sub, def, payload)) {
        skip_sub(skip, sub as usize);
    }
}

#[cold]
fn skip_sub(skip: &mut Vec<bool>, sub: usize) {
    if skip.len() <= sub {
        skip.resize(sub + 1, false);
    }
    skip[sub] = true;
}

impl Driver {
    fn new() -> Driver {
        Driver {
            framer: Framer::new(),
            messages: 0,
            data: 0,
            skip: Vec::new(),
        }
    }

    /// Frames what `win` (the file from `base`) holds, handing each data message of
    /// a subscription not yet skipped to `f`; `f` returning `false` skips the rest of
    /// that subscription's. `true`: the end of the file; `false`: more bytes are
    /// needed.
    #[inline]
    fn run<'w, F>(&mut self, win: &'w [u8], base: u64, eof: bool, f: &mut F) -> Result<bool>
    where
        F: FnMut(ScanRecord<'_, 'w>) -> bool,
    {
        loop {
            let mut n = 0u64;
            let skip = &mut self.skip;
            self.framer
                .plain_data_run(win, base, |offset, sub, def, payload| {
                    n += 1;
                    hand_out(skip, offset, sub, def, payload, f);
                });
            self.messages += n;
            self.data += n;
            match self.framer.step(win, base, eof)? {
                Step::Record(r) => {
                    self.messages += 1;
                    if let (b'D', Some(sub)) = (r.msg_type, r.sub) {
                        self.data += 1;
                        let start = (r.offset - base) as usize + MSG_HEADER_LEN;
                        let payload = &win[start..start + r.size as usize];
                        let def = &self.framer.subs[sub as usize];
                        hand_out(&mut self.skip, r.offset, sub, def, payload, f);
                    }
                }
                Step::NeedMore => return Ok(false),
                Step::End => return Ok(true),
            }
        }
    }

    fn summary(mut self) -> ScanSummary {
        ScanSummary {
            header: self.framer.header.unwrap_or(Header {
                version: 0,
                timestamp: 0,
            }),
            flag_bits: self.framer.flag_bits,
            messages: self.messages,
            data_messages: self.data,
            topics: self
                .framer
                .subs
                .iter()
                .map(|s| ScanTopic {
                    name: s.name.clone(),
                    multi_id: s.multi_id,
                    msg_id: s.msg_id,
                    subscribed_at: s.offset,
                    layout: s.layout.clone(),
                })
                .collect(),
            findings: std::mem::take(&mut self.framer.findings),
        }
    }
}

/// Hands every data message of `data` (a whole ULog file) to `f`, in file order.
///
/// Errors are those of [`ULog::parse`](crate::ULog::parse): input that is not ULog,
/// or a log the spec says to refuse; damage is reported in the summary.
///
/// ```
/// # let bytes = ulog_core::testing::sample_log();
/// let mut attitude_rows = 0;
/// let summary = ulog_core::scan(&bytes, |record| {
///     if record.name == "vehicle_attitude" {
///         attitude_rows += 1;
///     }
/// })?;
/// let log = ulog_core::ULog::parse(&bytes)?;
/// assert_eq!(attitude_rows, log.topic("vehicle_attitude", 0)?.len());
/// assert_eq!(summary.messages, log.message_count());
/// # Ok::<(), ulog_core::Error>(())
/// ```
pub fn scan<'a, F>(data: &'a [u8], mut f: F) -> Result<ScanSummary>
where
    F: FnMut(ScanRecord<'_, 'a>),
{
    scan_filtered(data, |r| {
        f(r);
        true
    })
}

/// [`scan`] where `f` returning `false` means "no more records of this
/// subscription": they are framed (and counted in the summary) but not handed out.
pub(crate) fn scan_filtered<'a, F>(data: &'a [u8], mut f: F) -> Result<ScanSummary>
where
    F: FnMut(ScanRecord<'_, 'a>) -> bool,
{
    let mut driver = Driver::new();
    // The whole file is given (end of input): framing ends, and the summary covers
    // whatever it framed.
    driver.run(data, 0, true, &mut f)?;
    Ok(driver.summary())
}

/// Bytes read from the source at a time by [`scan_reader`].
const READ_CHUNK: usize = 256 * 1024;

/// Hands every data message read from `src` to `f`, in file order, holding at most
/// the bytes framing still needs (see [`Incremental`](crate::Incremental)) plus
/// 256 KiB of read buffer. The same messages and findings as [`scan`] over the whole
/// file.
///
/// ```
/// # let bytes = ulog_core::testing::sample_log();
/// let mut from_reader = 0u64;
/// let summary = ulog_core::scan_reader(&bytes[..], |_| from_reader += 1)?;
/// assert_eq!(from_reader, summary.data_messages);
/// assert_eq!(summary, ulog_core::scan(&bytes, |_| {})?);
/// # Ok::<(), ulog_core::Error>(())
/// ```
pub fn scan_reader<R, F>(src: R, mut f: F) -> Result<ScanSummary>
where
    R: Read,
    F: FnMut(ScanRecord<'_, '_>),
{
    scan_range(src, u64::MAX, |r| {
        f(r);
        true
    })
}

/// Bytes read at a time by [`scan_reader_ahead`]: larger than [`READ_CHUNK`], the
/// hand-over from one thread to the other costing more than a read (1 MiB measured
/// 0.94× the wall time and 0.90× the CPU time of 256 KiB; 2 MiB no better).
const AHEAD_CHUNK: usize = 1 << 20;

/// Room kept before each chunk [`scan_reader_ahead`] reads, for the bytes framing
/// still needs from the chunk before (a message, or the few that framing checks
/// while it resynchronises; more is moved the slow way).
const CARRY_ROOM: usize = 128 * 1024;

/// A chunk read ahead: the buffer (the bytes at `room..room + n`) and
/// `n` (0: the end of the source).
type Chunk = std::io::Result<(Vec<u8>, usize)>;

/// [`scan_reader`] with the reads done on a second thread, ahead of framing: while the
/// messages of one 1 MiB chunk are handed out, the next chunk is read. On a file
/// this takes the kernel's copy of the bytes off the thread that frames them: a
/// decode of every value of the two large benchmark logs took 0.78–0.84× the wall
/// time of [`scan_reader`], for 1.15–1.19× its CPU time. The same messages, summary
/// and errors as [`scan_reader`], in about 2.3 MiB of buffers (3.5 MiB at most).
///
/// The scan returns once the reading thread has returned from its last read. After
/// the end of the source or a read error it reads no more; when the scan stops
/// earlier (a log refused at its start, a panic in `f`), the read under way still
/// has to return: on a file at once, on a pipe or socket that stays open not until
/// bytes arrive or it closes (where [`scan_reader`] would return at once). A thread
/// that cannot be started is an [`ErrorKind::Io`] error.
///
/// ```
/// # let bytes = ulog_core::testing::sample_log();
/// let mut ahead = Vec::new();
/// let summary = ulog_core::scan_reader_ahead(&bytes[..], |r| ahead.push(r.offset))?;
/// let mut plain = Vec::new();
/// assert_eq!(summary, ulog_core::scan_reader(&bytes[..], |r| plain.push(r.offset))?);
/// assert_eq!(ahead, plain);
/// # Ok::<(), ulog_core::Error>(())
/// ```
pub fn scan_reader_ahead<R, F>(src: R, mut f: F) -> Result<ScanSummary>
where
    R: Read + Send,
    F: FnMut(ScanRecord<'_, '_>),
{
    read_ahead(src, AHEAD_CHUNK, CARRY_ROOM, &mut |r| {
        f(r);
        true
    })
}

/// [`scan_reader_ahead`] reading `chunk` bytes at a time after `room` bytes kept for
/// what framing still needs of the chunk before; `f` as in [`scan_filtered`].
pub(crate) fn read_ahead<R, F>(src: R, chunk: usize, room: usize, f: &mut F) -> Result<ScanSummary>
where
    R: Read + Send,
    F: FnMut(ScanRecord<'_, '_>) -> bool,
{
    use std::sync::mpsc::sync_channel;
    std::thread::scope(|s| {
        // Two buffers go round: one framed while the other is read (or waits).
        // Both channels live in this closure: when it returns, a reader waiting on
        // either one is let go.
        let (full_tx, full) = sync_channel::<Chunk>(1);
        let (free, free_rx) = sync_channel::<Vec<u8>>(2);
        for _ in 0..2 {
            let _ = free.send(vec![0u8; room + chunk]);
        }
        let reader = std::thread::Builder::new().name("ulog read-ahead".to_owned());
        if let Err(e) = reader.spawn_scoped(s, move || fill_chunks(src, room, full_tx, free_rx)) {
            let e = format!("could not start the reading thread: {e}");
            return Err(Error::new(ErrorKind::Io(e), 0));
        }
        let mut driver = Driver::new();
        let mut cur = Vec::new();
        // The file from `base` is `cur[start..end]`, the bytes read so far.
        let (mut start, mut end, mut base) = (0usize, 0usize, 0u64);
        let mut eof = false;
        loop {
            if driver.run(&cur[start..end], base, eof, f)? {
                return Ok(driver.summary());
            }
            // Carry what framing still needs into the next chunk.
            let read = base + (end - start) as u64;
            let drop = driver.framer.done_with(base, end - start);
            let carry = start + drop..end;
            let (mut next, n) = match full.recv() {
                Ok(Ok(chunk)) => chunk,
                Ok(Err(e)) => return Err(Error::new(ErrorKind::Io(e.to_string()), read)),
                // The reader sends until the end or an error: it hung up early only
                // if `src` panicked (the scope then panics too).
                Err(_) => {
                    let e = ErrorKind::Io("the reading thread stopped".to_owned());
                    return Err(Error::new(e, read));
                }
            };
            let carried = carry.len();
            if carried <= room {
                next[room - carried..room].copy_from_slice(&cur[carry]);
                (start, end) = (room - carried, room + n);
            } else {
                let mut joined = Vec::with_capacity(carried + n);
                joined.extend_from_slice(&cur[carry]);
                joined.extend_from_slice(&next[room..room + n]);
                (start, end) = (0, joined.len());
                let _ = free.try_send(std::mem::replace(&mut next, joined));
            }
            base += drop as u64;
            eof = n == 0;
            let done = std::mem::replace(&mut cur, next);
            // Buffers of the reader's size go back to it (a joined one may happen to
            // be one); others go. (`try_send`: one the reader has no room for goes
            // too, rather than wait.)
            if done.len() == room + chunk {
                let _ = free.try_send(done);
            }
        }
    })
}

/// The reading thread of [`read_ahead`]: reads into the buffers it is given, after
/// `room` bytes, once each (what one read gives: a whole chunk from a file, what has
/// arrived from a pipe), and sends them on, until the end of `src` or an error.
fn fill_chunks<R: Read>(
    mut src: R,
    room: usize,
    full: std::sync::mpsc::SyncSender<Chunk>,
    free: std::sync::mpsc::Receiver<Vec<u8>>,
) {
    while let Ok(mut buf) = free.recv() {
        let read = read_some(&mut src, &mut buf[room..]);
        let last = !matches!(read, Ok(n) if n > 0);
        let sent = full.send(read.map(|n| (buf, n)));
        if sent.is_err() || last {
            return;
        }
    }
}

/// [`scan_reader`] that may stop once framing has passed offset `stop` (then the
/// summary covers only what was framed): every data message that starts before
/// `stop` has been handed out, and some after it may have been. `f` returning `false`
/// skips the rest of that subscription's records, as in [`scan_filtered`].
pub(crate) fn scan_range<R, F>(mut src: R, stop: u64, mut f: F) -> Result<ScanSummary>
where
    R: Read,
    F: FnMut(ScanRecord<'_, '_>) -> bool,
{
    let mut driver = Driver::new();
    // The file from `base` is `buf[start..end]`.
    let mut buf = vec![0u8; READ_CHUNK * 2];
    let (mut start, mut end) = (0usize, 0usize);
    let mut base = 0u64;
    let mut eof = false;
    loop {
        if driver.run(&buf[start..end], base, eof, &mut f)? || driver.framer.keep_from() >= stop {
            return Ok(driver.summary());
        }
        // Keep what framing still needs, at the front, then read behind it.
        let drop = driver.framer.done_with(base, end - start);
        start += drop;
        base += drop as u64;
        buf.copy_within(start..end, 0);
        end -= start;
        start = 0;
        if buf.len() - end < READ_CHUNK {
            buf.resize(end + READ_CHUNK, 0);
        }
        let n = read_some(&mut src, &mut buf[end..])
            .map_err(|e| Error::new(ErrorKind::Io(e.to_string()), base + end as u64))?;
        end += n;
        eof = n == 0;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::sample_log;

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
            let summary = scan(bytes, |r| all.push((r.offset, r.subscription))).unwrap();
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
                let mut f = |r: ScanRecord<'_, '_>| {
                    got.push((r.offset, r.subscription));
                    seen[r.subscription] += 1;
                    seen[r.subscription] < keep(r.subscription)
                };
                let filtered = match chunk {
                    None => scan_filtered(bytes, f).unwrap(),
                    // Read ahead, in chunks of 64 with 16 bytes of room.
                    Some(0) => read_ahead(Chunks(bytes, 50), 64, 16, &mut f).unwrap(),
                    Some(n) => scan_range(Chunks(bytes, n), u64::MAX, &mut f).unwrap(),
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
        scan(&sample, |r| offsets.push(r.offset)).unwrap();
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
            let summary = scan(bytes, |r| {
                expected.push((r.offset, r.subscription, r.payload.to_vec()))
            })
            .unwrap();
            for (chunk, room) in [(1, 0), (7, 3), (100, 64), (4096, 0), (4096, 1 << 17)] {
                let mut got = Vec::new();
                let ahead = read_ahead(bytes, chunk, room, &mut |r| {
                    got.push((r.offset, r.subscription, r.payload.to_vec()));
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
        let summary = scan(&bytes, |r| expected.push(r.offset)).unwrap();
        assert_eq!(expected.len(), 59, "{:?}", summary.findings);
        assert!(summary
            .findings
            .iter()
            .any(|f| f.kind == crate::FindingKind::PartialBeforeAppended));
        for (chunk, room) in [(64, 16), (100, 0), (299, 1024), (4096, 1024)] {
            let mut got = Vec::new();
            let ahead = read_ahead(Chunks(&bytes, 37), chunk, room, &mut |r| {
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
            let e1 = scan_reader(Failing(&sample, fail_at), |r| plain.push(r.offset)).unwrap_err();
            assert_eq!(e1.offset, fail_at as u64);
            assert!(matches!(e1.kind, ErrorKind::Io(_)), "{e1}");
            let mut ahead = Vec::new();
            let e2 =
                scan_reader_ahead(Failing(&sample, fail_at), |r| ahead.push(r.offset)).unwrap_err();
            let mut small = Vec::new();
            let e3 = read_ahead(Failing(&sample, fail_at), 64, 16, &mut |r| {
                small.push(r.offset);
                true
            })
            .unwrap_err();
            for (e, got) in [(e2, ahead), (e3, small)] {
                assert_eq!((e.offset, &e.kind), (e1.offset, &e1.kind), "{fail_at}");
                assert_eq!(got, plain, "{fail_at}");
            }
        }
    }

    /// A scan that stops before the end of an endless source returns: a source that
    /// is not ULog, and a panic in `f` (passed on).
    #[test]
    fn a_scan_that_stops_early_lets_the_reading_thread_go() {
        let e = scan_reader_ahead(std::io::repeat(0xA5), |_| {}).unwrap_err();
        assert!(matches!(e.kind, ErrorKind::NotULog { .. }), "{e}");
        let sample = sample_log();
        let endless = (&sample[..]).chain(std::io::repeat(0));
        let panicked = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            scan_reader_ahead(endless, |_| panic!("stop here"))
        }));
        assert!(panicked.is_err());
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
