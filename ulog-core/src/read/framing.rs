//! Framing: the header, then `[u16 size][u8 type][payload]` records, each with its
//! file offset.
//!
//! [`Framer`] is a state machine over a window of the file (`&[u8]` starting at a known
//! absolute offset), told whether the window reaches the end of the file. The
//! whole-file reader hands it the whole file at once; the incremental reader hands it
//! a buffer that grows as chunks arrive. Both therefore take the same decisions.
//!
//! It keeps the little schema that framing needs to judge data messages (formats,
//! subscriptions and their sizes), honours the flag bits (refusing unknown
//! incompatibility bits, jumping to appended offsets), and turns damage into findings:
//! a message that is not plausible is skipped by its size when the messages after it
//! frame cleanly, otherwise the reader scans forward to the next sync magic or to a
//! header that starts a chain of plausible messages.

use std::collections::HashMap;
use std::sync::Arc;

use ulog_format::{Format, Layout, LayoutError, Limits, Resolver};

use crate::error::{Error, ErrorKind, Result};
use crate::finding::{Corruption, Finding, FindingKind};
use crate::read::prefetch::prefetch;
use crate::read::timestamp::TimestampField;

/// The 7 magic bytes that start every ULog file (`ULog` then 0x01 0x12 0x35).
pub const MAGIC: [u8; 7] = [0x55, 0x4c, 0x6f, 0x67, 0x01, 0x12, 0x35];
/// The payload of a sync message, which readers search for to recover from corruption.
pub const SYNC_MAGIC: [u8; 8] = [0x2F, 0x73, 0x13, 0x20, 0x25, 0x0C, 0xBB, 0x12];
/// Size of the file header.
pub const HEADER_LEN: usize = 16;
/// Size of a message header.
pub const MSG_HEADER_LEN: usize = 3;

/// The message types of both spec versions.
pub const KNOWN_TYPES: &[u8] = b"BFIMPQARDLCSO";

/// The file header.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Header {
    /// File format version (0 or 1 today).
    pub version: u8,
    /// When logging started, in microseconds.
    pub timestamp: u64,
}

/// The flag bits message (`B`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FlagBits {
    /// Compatible flags; bit 0 of byte 0 is DEFAULT_PARAMETERS.
    pub compat_flags: [u8; 8],
    /// Incompatible flags; bit 0 of byte 0 is DATA_APPENDED.
    pub incompat_flags: [u8; 8],
    /// File offsets of appended data (0 where unused).
    pub appended_offsets: [u64; 3],
}

impl FlagBits {
    /// Whether the DEFAULT_PARAMETERS compatible flag is set.
    pub fn has_default_parameters(&self) -> bool {
        self.compat_flags[0] & 1 != 0
    }

    /// Whether the DATA_APPENDED incompatible flag is set.
    pub fn has_data_appended(&self) -> bool {
        self.incompat_flags[0] & 1 != 0
    }
}

/// A subscription as framing knows it.
#[derive(Debug, Clone)]
pub(crate) struct SubDef {
    pub msg_id: u16,
    pub multi_id: u8,
    pub name: String,
    pub offset: u64,
    pub layout: Result<Arc<Layout>, LayoutError>,
}

/// One framed message: where it is and what it is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Record {
    pub offset: u64,
    pub msg_type: u8,
    pub size: u16,
    /// For accepted data messages: the index of their subscription.
    pub sub: Option<u32>,
    /// Whether the record is a message this reader does not know (kept raw).
    pub unknown: bool,
}

impl Record {
    pub fn end(&self) -> u64 {
        self.offset + MSG_HEADER_LEN as u64 + self.size as u64
    }
}

pub(crate) enum Step {
    Record(Record),
    NeedMore,
    End,
}

enum Check {
    Ok(u16),
    NeedMore,
    Bad(Bad),
}

#[derive(Clone, Copy)]
enum Bad {
    ZeroSize,
    UnknownType(u8),
    UnknownMsgId(u16),
    SizeMismatch(u16, (usize, usize), usize),
    Malformed(u8, &'static str),
    Overrun,
    Implausible,
}

#[derive(Clone, Copy)]
struct Scan {
    start: u64,
    next: u64,
    all_zero: bool,
    overrun: bool,
    zero_size: bool,
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Phase {
    Header,
    First,
    Messages,
    End,
}

const NO_SUB: u32 = u32::MAX;
/// Payload size (after the msg_id) standing for "any": a subscription whose format
/// has no layout cannot have its data messages' sizes checked.
const ANY_SIZE: u32 = u32::MAX;

/// A msg_id's current subscription (`NO_SUB` when there is none) and the payload
/// sizes (after the msg_id) its data messages may have: the full layout size, or the
/// size without trailing padding.
#[derive(Clone, Copy)]
struct IdEntry {
    sub: u32,
    full: u32,
    min: u32,
}

impl IdEntry {
    const NONE: IdEntry = IdEntry {
        sub: NO_SUB,
        full: ANY_SIZE,
        min: ANY_SIZE,
    };

    #[inline]
    fn accepts(&self, n: usize) -> bool {
        self.full == ANY_SIZE || n == self.full as usize || n == self.min as usize
    }
}
/// Zero bytes that must follow a data message of the wrong size for it to be taken as
/// a whole message followed by zero fill (rather than a corrupt size field): zero
/// fill comes in sectors, while payloads hold shorter zero runs.
const ZEROS_AFTER_MISMATCH: usize = 512;
/// How many bytes of a message the content checks of a resynchronisation look at.
const STRICT_PREFIX: usize = 128;

/// The framing state machine (see the module docs).
///
/// Cloning is cheap: what changes only with definitions and subscriptions is shared
/// until one of the copies changes it, so a copy can be taken at every message (to
/// see what a reader would make of the file cut there).
#[derive(Clone)]
pub(crate) struct Framer {
    phase: Phase,
    pos: u64,
    scan: Option<Scan>,
    pub header: Option<Header>,
    pub flag_bits: Option<FlagBits>,
    pending_appended: Vec<u64>,
    pub findings: Vec<Finding>,
    pub formats: Arc<HashMap<String, Format>>,
    resolver: Arc<Resolver>,
    pub subs: Arc<Vec<SubDef>>,
    /// What a data message of each msg_id belongs to, with the sizes it may have.
    by_id: Arc<Vec<IdEntry>>,
    pub in_definitions: bool,
    max_records_checked_ahead: usize,
    /// Subscriptions by (name, multi_id), so that a repeated `A` finds its own in
    /// constant time.
    sub_by_key: Arc<HashMap<(String, u8), Vec<u32>>>,
    /// The error that stopped the read: every later step returns it again.
    failed: Option<Error>,
}

fn u16_at(b: &[u8], i: usize) -> u16 {
    u16::from_le_bytes([b[i], b[i + 1]])
}

fn u64_at(b: &[u8], i: usize) -> u64 {
    let mut a = [0u8; 8];
    a.copy_from_slice(&b[i..i + 8]);
    u64::from_le_bytes(a)
}

fn min_size(t: u8) -> usize {
    match t {
        b'B' => 40,
        b'F' => 2,
        b'I' | b'P' => 2,
        b'M' | b'Q' => 3,
        b'A' => 4,
        b'R' | b'O' => 2,
        b'D' => 2,
        b'L' => 9,
        b'C' => 11,
        _ => 1,
    }
}

/// How far ahead of the message being framed [`Framer::plain_data_run`] asks for the
/// file's bytes.
const PREFETCH_AHEAD: usize = 2048;

/// The end (relative to `win`) and msg_id entry of the data message at `rel` when it
/// is plain: a data message ending by `limit`, of a subscribed msg_id and a size its
/// layout allows.
#[inline(always)]
fn plain_at(win: &[u8], rel: usize, limit: usize, by_id: &[IdEntry]) -> Option<(usize, IdEntry)> {
    let head = win.get(rel..rel + 5)?;
    let size = u16::from_le_bytes([head[0], head[1]]) as usize;
    let end = rel + MSG_HEADER_LEN + size;
    if head[2] != b'D' || size < 2 || end > limit {
        return None;
    }
    let entry = by_id[u16::from_le_bytes([head[3], head[4]]) as usize];
    (entry.sub != NO_SUB && entry.accepts(size - 2)).then_some((end, entry))
}

fn valid_level(l: u8) -> bool {
    l <= 7 || (b'0'..=b'7').contains(&l)
}

/// Whether the text of a logged string (`L`/`C`) looks like text: no control bytes
/// but tab, line breaks and escape (terminal colours) in its first bytes, so that a
/// stretch of binary data does not pass for a long logged string.
fn plausible_text(p: &[u8], t: u8) -> bool {
    let start = if t == b'C' { 11 } else { 9 };
    p.get(start..)
        .unwrap_or(&[])
        .iter()
        .take(STRICT_PREFIX)
        .all(|&b| is_text_byte(b))
}

/// A byte logged text may hold: anything but control bytes, except tab, line breaks
/// and escape (terminal colours). Framing checks a text's first bytes with it; the
/// writer refuses text with other bytes anywhere.
pub(crate) fn is_text_byte(b: u8) -> bool {
    b >= 0x20 || matches!(b, b'\t' | b'\n' | b'\r' | 0x1b)
}

fn is_name_byte(b: u8) -> bool {
    b.is_ascii_alphanumeric() || b == b'_' || b == b'-' || b == b'/'
}

/// What a file that is not ULog looks like, for the error message.
pub(crate) fn describe_non_ulog(bytes: &[u8]) -> String {
    let head = &bytes[..bytes.len().min(16)];
    let known: &[(&[u8], &str)] = &[
        (b"\x1f\x8b", "a gzip file"),
        (b"PK\x03\x04", "a zip file"),
        (b"BZh", "a bzip2 file"),
        (b"\xfd7zXZ", "an xz file"),
        (b"\x28\xb5\x2f\xfd", "a zstd file"),
        (b"\x89PNG", "a PNG image"),
        (b"%PDF", "a PDF document"),
        (b"#ROSBAG", "a ROS bag"),
        (b"SQLite format", "an SQLite database"),
        (b"\xa3\x95\x80\x80", "a PX4 sdlog2 (.px4log) file"),
        (b"\xa3\x95", "an APM/PX4 DataFlash log"),
        (b"ULog", "a ULog magic with wrong trailing bytes"),
    ];
    // Only the first 16 bytes are looked at, so that the whole-file and the
    // incremental reader describe a file the same way.
    if head.iter().all(|&b| b == 0) {
        return "zero bytes where the header should be".to_owned();
    }
    for (magic, what) in known {
        if head.starts_with(magic) {
            return (*what).to_owned();
        }
    }
    let text = head
        .iter()
        .all(|b| b.is_ascii_graphic() || b.is_ascii_whitespace());
    let hex: Vec<String> = head.iter().take(8).map(|b| format!("{b:02x}")).collect();
    if text {
        format!(
            "text ({:?}…)",
            String::from_utf8_lossy(&head[..head.len().min(12)])
        )
    } else {
        format!("bytes {}", hex.join(" "))
    }
}

impl Framer {
    pub fn new() -> Framer {
        Framer {
            phase: Phase::Header,
            pos: 0,
            scan: None,
            header: None,
            flag_bits: None,
            pending_appended: Vec::new(),
            findings: Vec::new(),
            formats: Arc::default(),
            resolver: Arc::new(Resolver::new(Limits::default())),
            subs: Arc::default(),
            by_id: Arc::new(vec![IdEntry::NONE; 1 << 16]),
            in_definitions: true,
            max_records_checked_ahead: 2,
            sub_by_key: Arc::default(),
            failed: None,
        }
    }

    /// The first absolute offset whose bytes are still needed.
    pub fn keep_from(&self) -> u64 {
        match self.scan {
            Some(s) => s.next,
            None => self.pos,
        }
    }

    /// How many bytes at the front of a window of `len` bytes from offset `base`
    /// framing no longer needs. At most `len`: framing may be past the window (a jump
    /// to appended data), and then the window's end is still where the bytes that
    /// follow it start.
    pub fn done_with(&self, base: u64, len: usize) -> usize {
        let keep = self.keep_from().max(base);
        usize::try_from(keep - base).map_or(len, |d| d.min(len))
    }

    pub fn sub_index(&self, msg_id: u16) -> Option<u32> {
        let i = self.by_id[msg_id as usize].sub;
        (i != NO_SUB).then_some(i)
    }

    /// Where plain data messages may be framed from: the current position and the end
    /// of what may be framed without a decision of [`Framer::step`] (the window's end
    /// or the next appended offset), both relative to `win`. `None` while not in the
    /// data messages, resynchronising or failed.
    #[inline]
    fn plain_window(&self, win: &[u8], base: u64) -> Option<(usize, usize)> {
        if self.phase != Phase::Messages || self.scan.is_some() || self.failed.is_some() {
            return None;
        }
        let rel = usize::try_from(self.pos.checked_sub(base)?).ok()?;
        let limit = match self.pending_appended.first() {
            Some(&off) => win.len().min(usize::try_from(off.checked_sub(base)?).ok()?),
            None => win.len(),
        };
        Some((rel, limit))
    }

    /// Frames the data message at the current position when it is the plain case: in
    /// the data messages, not resynchronising, wholly inside `win` and before the next
    /// appended offset, of a subscribed msg_id and a size its layout allows. `None`
    /// leaves every other case, with the same outcome, to [`Framer::step`].
    #[inline]
    fn plain_data(&mut self, win: &[u8], base: u64) -> Option<Record> {
        let (rel, limit) = self.plain_window(win, base)?;
        let (end, entry) = plain_at(win, rel, limit, &self.by_id)?;
        let offset = self.pos;
        self.pos = base + end as u64;
        Some(Record {
            offset,
            msg_type: b'D',
            size: (end - rel - MSG_HEADER_LEN) as u16,
            sub: Some(entry.sub),
            unknown: false,
        })
    }

    /// Frames the plain data messages (see [`Framer::plain_data`]) from the current
    /// position on, handing each to `f` with its offset, subscription index,
    /// subscription and payload (after the message header), and stops at the first
    /// message that is anything else.
    #[inline]
    pub fn plain_data_run<'w>(
        &mut self,
        win: &'w [u8],
        base: u64,
        mut f: impl FnMut(u64, u32, &SubDef, &'w [u8]),
    ) {
        let Some((mut rel, limit)) = self.plain_window(win, base) else {
            return;
        };
        let subs = &self.subs[..];
        while let Some((end, entry)) = plain_at(win, rel, limit, &self.by_id) {
            prefetch(win, rel + PREFETCH_AHEAD);
            f(
                base + rel as u64,
                entry.sub,
                &subs[entry.sub as usize],
                &win[rel + MSG_HEADER_LEN..end],
            );
            rel = end;
        }
        self.pos = base + rel as u64;
    }

    fn finding(&mut self, kind: FindingKind, offset: u64, len: u64) {
        self.findings.push(Finding::new(kind, offset, len));
    }

    /// Frames the next record of `win` (bytes of the file from absolute offset
    /// `base`; `eof` when they reach the end of the file).
    pub fn step(&mut self, win: &[u8], base: u64, eof: bool) -> Result<Step> {
        if let Some(r) = self.plain_data(win, base) {
            return Ok(Step::Record(r));
        }
        if let Some(e) = &self.failed {
            return Err(e.clone());
        }
        let step = self.step_inner(win, base, eof);
        if let Err(e) = &step {
            self.failed = Some(e.clone());
            self.phase = Phase::End;
        }
        step
    }

    fn step_inner(&mut self, win: &[u8], base: u64, eof: bool) -> Result<Step> {
        loop {
            match self.phase {
                Phase::End => return Ok(Step::End),
                Phase::Header => {
                    if let Some(step) = self.read_header(win, eof)? {
                        return Ok(step);
                    }
                    continue;
                }
                Phase::First | Phase::Messages => {}
            }
            if self.scan.is_some() {
                match self.scan_step(win, base, eof) {
                    Some(step) => return Ok(step),
                    None => continue,
                }
            }
            let p = self.pos;
            let win_end = base + win.len() as u64;
            if let Some(&off) = self.pending_appended.first() {
                if p >= off {
                    self.pending_appended.remove(0);
                    if p == off {
                        self.in_definitions = false;
                        self.finding(FindingKind::AppendedData, off, 0);
                    } else {
                        self.finding(FindingKind::InvalidAppendedOffset(off), off, 0);
                    }
                    continue;
                }
            }
            if p >= win_end {
                return Ok(if eof { self.end() } else { Step::NeedMore });
            }
            if win_end - p < MSG_HEADER_LEN as u64 && !eof {
                return Ok(Step::NeedMore);
            }
            if let Some(&off) = self.pending_appended.first() {
                let rel = (p - base) as usize;
                let end = if win.len() - rel >= 3 {
                    p + 3 + u16_at(win, rel) as u64
                } else {
                    p + 3
                };
                if off < end {
                    self.finding(FindingKind::PartialBeforeAppended, p, off - p);
                    self.pos = off;
                    continue;
                }
            }
            let first = self.phase == Phase::First;
            match self.check(win, base, p, eof, false, &[]) {
                Check::NeedMore => return Ok(Step::NeedMore),
                Check::Ok(size) => {
                    let rel = (p - base) as usize;
                    let msg_type = win[rel + 2];
                    self.phase = Phase::Messages;
                    let record = Record {
                        offset: p,
                        msg_type,
                        size,
                        sub: None,
                        unknown: false,
                    };
                    self.pos = record.end();
                    let payload = &win[rel + 3..rel + 3 + size as usize];
                    return self.accept(record, payload, first).map(Step::Record);
                }
                Check::Bad(bad) => {
                    self.phase = Phase::Messages;
                    if let Some(step) = self.bad(win, base, p, eof, bad) {
                        return Ok(step);
                    }
                }
            }
        }
    }

    fn end(&mut self) -> Step {
        self.phase = Phase::End;
        for off in std::mem::take(&mut self.pending_appended) {
            self.finding(FindingKind::InvalidAppendedOffset(off), off, 0);
        }
        Step::End
    }

    fn read_header(&mut self, win: &[u8], eof: bool) -> Result<Option<Step>> {
        if win.len() < HEADER_LEN {
            if !eof {
                return Ok(Some(Step::NeedMore));
            }
            if win.is_empty() {
                return Err(Error::new(ErrorKind::Empty, 0));
            }
            if MAGIC.starts_with(&win[..win.len().min(7)]) {
                return Err(Error::new(
                    ErrorKind::TruncatedHeader {
                        len: win.len() as u64,
                    },
                    0,
                ));
            }
            return Err(Error::new(
                ErrorKind::NotULog {
                    found: describe_non_ulog(win),
                },
                0,
            ));
        }
        if win[..7] != MAGIC {
            return Err(Error::new(
                ErrorKind::NotULog {
                    found: describe_non_ulog(win),
                },
                0,
            ));
        }
        let header = Header {
            version: win[7],
            timestamp: u64_at(win, 8),
        };
        if header.version > 1 {
            self.finding(FindingKind::NewerVersion(header.version), 7, 0);
        }
        self.header = Some(header);
        self.pos = HEADER_LEN as u64;
        self.phase = Phase::First;
        Ok(None)
    }

    /// Handles a message that is not plausible at `p`.
    fn bad(&mut self, win: &[u8], base: u64, p: u64, eof: bool, bad: Bad) -> Option<Step> {
        let rel = (p - base) as usize;
        let (size, msg_type) = if win.len() - rel >= 3 {
            (u16_at(win, rel), win[rel + 2])
        } else {
            (0, 0)
        };
        let end = p + 3 + size as u64;
        let skippable = !matches!(bad, Bad::Overrun | Bad::ZeroSize);
        if skippable {
            match self.chain_valid(win, base, end, eof, self.max_records_checked_ahead) {
                None => return Some(Step::NeedMore),
                Some(true) => {
                    let len = 3 + size as u64;
                    self.finding(self.bad_kind(bad, msg_type), p, len);
                    self.pos = end;
                    let unknown = matches!(bad, Bad::UnknownType(_));
                    return unknown.then_some(Step::Record(Record {
                        offset: p,
                        msg_type,
                        size,
                        sub: None,
                        unknown: true,
                    }));
                }
                Some(false) => {
                    // A data message of a known subscription, framed by its own size and
                    // followed by zero bytes (a zero-filled stretch or tail): the message
                    // is reported for what it is, the zeros as their own stretch. The
                    // decision needs only the next `ZEROS_AFTER_MISMATCH` bytes (or the
                    // end of the file), so the incremental reader takes it too without
                    // buffering the zeros. Fewer zeros prove nothing: a size field hit
                    // by corruption can land on a few zero bytes inside a payload.
                    let after = (end - base) as usize;
                    if matches!(bad, Bad::SizeMismatch(..)) {
                        let tail = win.get(after..).unwrap_or(&[]);
                        let seen = &tail[..tail.len().min(ZEROS_AFTER_MISMATCH)];
                        if seen.len() >= 3 && seen.iter().all(|&b| b == 0) {
                            if seen.len() < ZEROS_AFTER_MISMATCH && !eof {
                                return Some(Step::NeedMore);
                            }
                            self.finding(self.bad_kind(bad, msg_type), p, 3 + size as u64);
                            self.pos = end;
                            return None;
                        }
                    }
                }
            }
        }
        self.scan = Some(Scan {
            start: p,
            next: p + 1,
            all_zero: win[rel] == 0,
            overrun: matches!(bad, Bad::Overrun),
            zero_size: matches!(bad, Bad::ZeroSize),
        });
        None
    }

    fn bad_kind(&self, bad: Bad, msg_type: u8) -> FindingKind {
        match bad {
            Bad::UnknownType(t) => FindingKind::UnknownMessageType(t),
            Bad::UnknownMsgId(id) => FindingKind::UnknownMsgId(id),
            Bad::SizeMismatch(id, expected, found) => FindingKind::SizeMismatch {
                msg_id: id,
                expected,
                found,
            },
            Bad::Malformed(t, what) => FindingKind::Malformed { msg_type: t, what },
            Bad::Implausible | Bad::ZeroSize | Bad::Overrun => FindingKind::Malformed {
                msg_type,
                what: "implausible content",
            },
        }
    }

    /// Scans for the end of a corrupt stretch. `None`: resynchronised, go on.
    fn scan_step(&mut self, win: &[u8], base: u64, eof: bool) -> Option<Step> {
        let mut s = self.scan.expect("scanning");
        let win_end = base + win.len() as u64;
        let limit = self.pending_appended.first().copied().unwrap_or(u64::MAX);
        let mut q = s.next;
        let resume = loop {
            if q >= limit {
                break Some(limit);
            }
            if q >= win_end {
                break None;
            }
            let rel = (q - base) as usize;
            if win[rel..].starts_with(&SYNC_MAGIC) {
                let header_at = q.checked_sub(3).filter(|&h| h > s.start && h >= base);
                match header_at {
                    Some(h) if win[(h - base) as usize..rel] == [8, 0, b'S'] => break Some(h),
                    _ => break Some((q + SYNC_MAGIC.len() as u64).min(limit)),
                }
            }
            if !eof && win_end - q < SYNC_MAGIC.len() as u64 {
                s.next = q;
                self.scan = Some(s);
                return Some(Step::NeedMore);
            }
            match self.chain_valid_scan(win, base, q, eof) {
                None => {
                    s.next = q;
                    self.scan = Some(s);
                    return Some(Step::NeedMore);
                }
                Some(true) if q < win_end => break Some(q),
                _ => {}
            }
            s.all_zero &= win[rel] == 0;
            q += 1;
        };
        let end_of_damage = match resume {
            Some(r) => r,
            None if !eof => {
                s.next = q;
                self.scan = Some(s);
                return Some(Step::NeedMore);
            }
            None => win_end,
        };
        self.scan = None;
        let len = end_of_damage - s.start;
        let kind = if resume.is_none() && s.overrun && !s.all_zero {
            FindingKind::Truncated
        } else if s.all_zero {
            FindingKind::Corrupt(Corruption::ZeroFill)
        } else if s.zero_size {
            FindingKind::Corrupt(Corruption::ZeroSize)
        } else if s.overrun {
            FindingKind::Corrupt(Corruption::Overrun)
        } else {
            FindingKind::Corrupt(Corruption::BadHeader)
        };
        self.finding(kind, s.start, len);
        match resume {
            Some(r) => {
                self.pos = r;
                None
            }
            None => {
                self.pos = win_end;
                Some(self.end())
            }
        }
    }

    /// Whether a place found while scanning starts real messages: a chain of three,
    /// or of two that end exactly at an appended offset or the end of the file (one
    /// message that happens to end there could be the tail of the cut message itself).
    fn chain_valid_scan(&self, win: &[u8], base: u64, q: u64, eof: bool) -> Option<bool> {
        let depth = self.max_records_checked_ahead;
        match self.chain_len(win, base, q, eof, depth)? {
            (n, _) if n > depth => Some(true),
            (n, true) => Some(n >= 2),
            _ => Some(false),
        }
    }

    /// Whether the messages from `q` on frame cleanly for `depth` more messages (or
    /// reach the end of the file or an appended offset). `None`: more bytes needed.
    fn chain_valid(&self, win: &[u8], base: u64, q: u64, eof: bool, depth: usize) -> Option<bool> {
        match self.chain_len(win, base, q, eof, depth)? {
            (n, _) if n > depth => Some(true),
            (_, reached_end) => Some(reached_end),
        }
    }

    /// How many plausible messages follow from `q` (up to `depth + 1`), and whether
    /// they end at the end of the file or an appended offset. `None`: more bytes
    /// needed.
    fn chain_len(
        &self,
        win: &[u8],
        base: u64,
        q: u64,
        eof: bool,
        depth: usize,
    ) -> Option<(usize, bool)> {
        let mut q = q;
        let mut new_ids: Vec<u16> = Vec::new();
        let win_end = base + win.len() as u64;
        for n in 0..=depth {
            if eof && q == win_end {
                return Some((n, true));
            }
            if self.pending_appended.first() == Some(&q) {
                return Some((n, true));
            }
            match self.check(win, base, q, eof, true, &new_ids) {
                Check::NeedMore => return None,
                Check::Bad(_) => return Some((n, false)),
                Check::Ok(size) => {
                    let rel = (q - base) as usize;
                    if win[rel + 2] == b'A' {
                        new_ids.push(u16_at(win, rel + 4));
                    }
                    q += 3 + size as u64;
                }
            }
        }
        Some((depth + 1, false))
    }

    /// Whether one message at `q` is plausible. `resync`: looking for a place to
    /// resynchronise, where flag bits never fit. The content checks (a logged string
    /// looks like text, a key has its type, …) apply when resynchronising and in the
    /// data section: there, a stretch of garbage whose first bytes happen to form a
    /// header of a known type must not swallow the real messages after it (ULog has no
    /// checksums; content is all there is to judge by).
    fn check(
        &self,
        win: &[u8],
        base: u64,
        q: u64,
        eof: bool,
        resync: bool,
        new_ids: &[u16],
    ) -> Check {
        if q < base {
            return Check::Bad(Bad::Implausible);
        }
        let rel = (q - base) as usize;
        let avail = win.len().saturating_sub(rel);
        if avail < 3 {
            return if eof {
                Check::Bad(Bad::Overrun)
            } else {
                Check::NeedMore
            };
        }
        let size = u16_at(win, rel);
        let t = win[rel + 2];
        if size == 0 {
            return Check::Bad(Bad::ZeroSize);
        }
        if !KNOWN_TYPES.contains(&t) {
            return Check::Bad(Bad::UnknownType(t));
        }
        if (size as usize) < min_size(t) {
            return Check::Bad(Bad::Malformed(t, "shorter than its type allows"));
        }
        if avail < 3 + size as usize {
            return if eof {
                Check::Bad(Bad::Overrun)
            } else {
                Check::NeedMore
            };
        }
        let p = &win[rel + 3..rel + 3 + size as usize];
        let bad = |what| Check::Bad(Bad::Malformed(t, what));
        let content = resync || !self.in_definitions;
        match t {
            b'D' => {
                let id = u16_at(p, 0);
                let entry = self.by_id[id as usize];
                let n = p.len() - 2;
                if entry.sub == NO_SUB {
                    if !new_ids.contains(&id) {
                        return Check::Bad(Bad::UnknownMsgId(id));
                    }
                } else if !entry.accepts(n) {
                    let sizes = (entry.full as usize, entry.min as usize);
                    return Check::Bad(Bad::SizeMismatch(id, sizes, n));
                }
            }
            b'I' | b'P' => {
                if 1 + p[0] as usize > p.len() || p[0] == 0 {
                    return bad("key longer than the message");
                }
                if content && !p[1..1 + p[0] as usize].contains(&b' ') {
                    return Check::Bad(Bad::Implausible);
                }
            }
            b'M' | b'Q' => {
                if 2 + p[1] as usize > p.len() || p[1] == 0 {
                    return bad("key longer than the message");
                }
                if content && (!p[2..2 + p[1] as usize].contains(&b' ') || (t == b'M' && p[0] > 1))
                {
                    return Check::Bad(Bad::Implausible);
                }
            }
            b'B' if resync || q != HEADER_LEN as u64 => return Check::Bad(Bad::Implausible),
            // Content checks look at a bounded prefix, so that scanning a corrupt
            // stretch stays linear with a small constant.
            b'A' if content && !p[3..].iter().take(STRICT_PREFIX).all(|&b| is_name_byte(b)) => {
                return Check::Bad(Bad::Implausible)
            }
            b'L' | b'C' if content && !(valid_level(p[0]) && plausible_text(p, t)) => {
                return Check::Bad(Bad::Implausible)
            }
            b'F' if content
                && !(is_name_byte(p[0]) && p[..p.len().min(STRICT_PREFIX)].contains(&b':')) =>
            {
                return Check::Bad(Bad::Implausible)
            }
            b'R' | b'O' if content && size != 2 => return Check::Bad(Bad::Implausible),
            b'S' if content && self.header.is_some_and(|h| h.version >= 1) && p != SYNC_MAGIC => {
                return Check::Bad(Bad::Implausible)
            }
            _ => {}
        }
        Check::Ok(size)
    }

    /// Applies what framing itself needs from an accepted message.
    fn accept(&mut self, mut record: Record, payload: &[u8], first: bool) -> Result<Record> {
        match record.msg_type {
            b'B' if first => self.flag_bits(record, payload)?,
            b'B' => self.finding(FindingKind::MisplacedFlagBits, record.offset, 0),
            b'F' => self.format(record, payload),
            b'A' => {
                self.in_definitions = false;
                self.subscribe(record, payload);
            }
            b'L' | b'C' => self.in_definitions = false,
            b'R' => {
                let id = u16_at(payload, 0);
                if self.by_id[id as usize].sub != NO_SUB {
                    Arc::make_mut(&mut self.by_id)[id as usize] = IdEntry::NONE;
                }
            }
            b'D' => record.sub = self.sub_index(u16_at(payload, 0)),
            _ => {}
        }
        Ok(record)
    }

    fn flag_bits(&mut self, record: Record, p: &[u8]) -> Result<()> {
        let mut fb = FlagBits {
            compat_flags: [0; 8],
            incompat_flags: [0; 8],
            appended_offsets: [0; 3],
        };
        fb.compat_flags.copy_from_slice(&p[0..8]);
        fb.incompat_flags.copy_from_slice(&p[8..16]);
        for (i, o) in fb.appended_offsets.iter_mut().enumerate() {
            *o = u64_at(p, 16 + 8 * i);
        }
        let at = record.offset + 3;
        for (byte, &bits) in fb.incompat_flags.iter().enumerate() {
            let unknown = if byte == 0 { bits & !1 } else { bits };
            if unknown != 0 {
                return Err(Error::new(
                    ErrorKind::UnknownIncompatFlags {
                        byte,
                        bits: unknown,
                    },
                    at + 8 + byte as u64,
                ));
            }
        }
        for (byte, &bits) in fb.compat_flags.iter().enumerate() {
            let unknown = if byte == 0 { bits & !1 } else { bits };
            if unknown != 0 {
                self.finding(
                    FindingKind::UnknownCompatFlags {
                        byte,
                        bits: unknown,
                    },
                    at + byte as u64,
                    0,
                );
            }
        }
        if record.size > 40 {
            self.finding(FindingKind::LongFlagBits(record.size), record.offset, 0);
        }
        let offsets: Vec<u64> = fb
            .appended_offsets
            .iter()
            .copied()
            .filter(|&o| o != 0)
            .collect();
        if fb.has_data_appended() {
            if offsets.is_empty() {
                self.finding(FindingKind::AppendedFlagWithoutOffsets, at + 8, 0);
            }
            let mut valid: Vec<u64> = Vec::new();
            for o in offsets {
                if o < record.end() {
                    self.finding(FindingKind::InvalidAppendedOffset(o), at + 16, 0);
                } else if !valid.contains(&o) {
                    valid.push(o);
                }
            }
            valid.sort_unstable();
            self.pending_appended = valid;
        } else if !offsets.is_empty() {
            self.finding(FindingKind::AppendedOffsetsWithoutFlag, at + 16, 0);
        }
        self.flag_bits = Some(fb);
        Ok(())
    }

    fn format(&mut self, record: Record, p: &[u8]) {
        match Format::parse_bytes(p) {
            Ok(format) => {
                if let Some(old) = self.formats.get(&format.name) {
                    if old.fields != format.fields {
                        self.finding(
                            FindingKind::RedefinedFormat(format.name.clone()),
                            record.offset,
                            0,
                        );
                        Arc::make_mut(&mut self.resolver).clear();
                    } else {
                        return;
                    }
                }
                Arc::make_mut(&mut self.formats).insert(format.name.clone(), format);
                // A new format may complete one that could not be laid out before.
                Arc::make_mut(&mut self.resolver).clear();
            }
            Err(e) => self.finding(FindingKind::InvalidFormat(e), record.offset + 3, 0),
        }
    }

    fn subscribe(&mut self, record: Record, p: &[u8]) {
        let multi_id = p[0];
        let msg_id = u16_at(p, 1);
        let name = String::from_utf8_lossy(&p[3..]).into_owned();
        let layout = Arc::make_mut(&mut self.resolver).resolve(&name, &*self.formats);
        // The same topic subscribed again (under another msg_id, or in appended data)
        // with the same layout continues the same subscription.
        let key = (name, multi_id);
        let existing = self.sub_by_key.get(&key).and_then(|ids| {
            ids.iter()
                .copied()
                .find(|&i| match (&self.subs[i as usize].layout, &layout) {
                    (Ok(a), Ok(b)) => Arc::ptr_eq(a, b) || a == b,
                    (Err(a), Err(b)) => a == b,
                    _ => false,
                })
        });
        let index = match existing {
            Some(i) => i,
            None => {
                let (name, multi_id) = key.clone();
                match &layout {
                    Err(_) if !self.formats.contains_key(&name) => {
                        self.finding(FindingKind::UnknownFormat(name.clone()), record.offset, 0)
                    }
                    Err(e) => self.finding(FindingKind::Layout(e.clone()), record.offset, 0),
                    Ok(l) if TimestampField::of(l).is_none() => {
                        self.finding(FindingKind::NoTimestamp(name.clone()), record.offset, 0)
                    }
                    Ok(_) => {}
                }
                Arc::make_mut(&mut self.subs).push(SubDef {
                    msg_id,
                    multi_id,
                    name,
                    offset: record.offset,
                    layout,
                });
                let i = (self.subs.len() - 1) as u32;
                Arc::make_mut(&mut self.sub_by_key)
                    .entry(key)
                    .or_default()
                    .push(i);
                i
            }
        };
        if self.by_id[msg_id as usize].sub != index {
            let (full, min) = match &self.subs[index as usize].layout {
                Ok(l) => (l.size() as u32, l.min_size() as u32),
                Err(_) => (ANY_SIZE, ANY_SIZE),
            };
            Arc::make_mut(&mut self.by_id)[msg_id as usize] = IdEntry {
                sub: index,
                full,
                min,
            };
        }
    }
}
