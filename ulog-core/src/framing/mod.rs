//! Framing: the header, then `[u16 size][u8 type][payload]` records, each with its
//! file offset.
//!
//! [`Framer`] is a state machine over a window of the file (`&[u8]` starting at a known
//! absolute offset), told whether the window reaches the end of the file. The
//! whole-file reader hands it the whole file at once; the one-pass and incremental
//! readers hand it windows of what they have read. All of them therefore take the
//! same decisions.
//!
//! It keeps the log's [`Definitions`] (framing needs the subscriptions' sizes to judge
//! data messages), honours the flag bits (refusing unknown incompatibility bits,
//! jumping to appended offsets), and turns damage into findings: `check` judges one
//! message, `resync` finds real messages again after damage, `header` reads the file
//! header and says what a file that is not ULog looks like.

mod check;
mod header;
mod resync;

use std::sync::Arc;

use crate::audited::prefetch;
use crate::bytes::{u16_at, MESSAGE_HEADER_SIZE};
use crate::definitions::{Definitions, IdEntry, Subscription, NO_SUB};
use crate::error::ReadError;
use crate::finding::{Finding, FindingKind};

pub(crate) use check::is_text_byte;
use check::Check;
pub use header::{FlagBits, Header};
use resync::Resync;

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
    /// A message framed at `offset`, not (yet) tied to a subscription.
    pub fn framed(offset: u64, msg_type: u8, size: u16) -> Record {
        Record {
            offset,
            msg_type,
            size,
            sub: None,
            unknown: false,
        }
    }

    pub fn end(&self) -> u64 {
        self.offset + MESSAGE_HEADER_SIZE as u64 + self.size as u64
    }

    /// The payload of the record in `win`, the file's bytes from `base`.
    pub fn payload<'w>(&self, win: &'w [u8], base: u64) -> &'w [u8] {
        let start = (self.offset - base) as usize + MESSAGE_HEADER_SIZE;
        &win[start..start + self.size as usize]
    }
}

pub(crate) enum Step {
    Record(Record),
    NeedMore,
    End,
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Phase {
    Header,
    First,
    Messages,
    End,
}

/// The framing state machine (see the module docs).
///
/// Cloning is cheap: the definitions are shared until one of the copies changes them,
/// so a copy can be taken at every message (to see what a reader would make of the
/// file cut there).
#[derive(Clone)]
pub(crate) struct Framer {
    phase: Phase,
    pos: u64,
    /// Set while a damaged stretch is being skipped.
    resync: Option<Resync>,
    pub header: Option<Header>,
    pub flag_bits: Option<FlagBits>,
    /// Appended offsets not reached yet, in increasing order.
    appended: Vec<u64>,
    /// Where the flag bits message holds the appended offsets: the place of an
    /// offset that points past the end of the file.
    appended_field: u64,
    pub findings: Vec<Finding>,
    pub defs: Definitions,
    pub in_definitions: bool,
    /// The error that stopped the read: every later step returns it again.
    failed: Option<ReadError>,
    /// Keys of information and parameter messages found plausible before.
    known_keys: check::KnownKeys,
}

/// How far ahead of the message being framed [`Framer::plain_data_run`] asks for the
/// file's bytes.
const PREFETCH_AHEAD: usize = 2048;

/// The end (relative to `win`) and msg_id entry of the data message at `rel` when it
/// is plain: a data message ending by `limit`, of a subscribed msg_id and a size its
/// layout allows, that zero fill did not cut (it ends in a non-zero byte, or a message
/// header that is not zeros follows it).
#[inline(always)]
fn plain_at(win: &[u8], rel: usize, limit: usize, by_id: &[IdEntry]) -> Option<(usize, IdEntry)> {
    let head = win.get(rel..rel + 5)?;
    let size = u16::from_le_bytes([head[0], head[1]]) as usize;
    let end = rel + MESSAGE_HEADER_SIZE + size;
    if head[2] != b'D' || size < 2 || end > limit {
        return None;
    }
    let entry = by_id[u16::from_le_bytes([head[3], head[4]]) as usize];
    // A payload that ends in a zero byte, followed by a zero header or by the end of
    // the window, may have been cut by zero fill: `Framer::step` decides
    // (`Framer::cut_by_zero_fill`).
    if win[end - 1] == 0 && win.get(end..end + 3).map_or(true, |h| h == [0, 0, 0]) {
        return None;
    }
    (entry.sub != NO_SUB && entry.accepts(size - 2)).then_some((end, entry))
}

impl Framer {
    pub fn new() -> Framer {
        Framer {
            phase: Phase::Header,
            pos: 0,
            resync: None,
            header: None,
            flag_bits: None,
            appended: Vec::new(),
            appended_field: 0,
            findings: Vec::new(),
            defs: Definitions::new(),
            in_definitions: true,
            failed: None,
            known_keys: check::KnownKeys::default(),
        }
    }

    /// The first absolute offset whose bytes are still needed.
    pub fn keep_from(&self) -> u64 {
        match self.resync {
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

    /// Where plain data messages may be framed from: the current position and the end
    /// of what may be framed without a decision of [`Framer::step`] (the window's end
    /// or the next appended offset), both relative to `win`. `None` while not in the
    /// data messages, resynchronising or failed.
    #[inline]
    fn plain_window(&self, win: &[u8], base: u64) -> Option<(usize, usize)> {
        if self.phase != Phase::Messages || self.resync.is_some() || self.failed.is_some() {
            return None;
        }
        let rel = usize::try_from(self.pos.checked_sub(base)?).ok()?;
        let limit = match self.appended.first() {
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
        let (end, entry) = plain_at(win, rel, limit, self.defs.entries())?;
        let offset = self.pos;
        self.pos = base + end as u64;
        Some(Record {
            sub: Some(entry.sub),
            ..Record::framed(offset, b'D', (end - rel - MESSAGE_HEADER_SIZE) as u16)
        })
    }

    /// Frames the plain data messages (see [`Framer::plain_data`]) from the current
    /// position on, handing each to `f` with its offset, subscription and payload
    /// (after the message header), until `f` returns `false`, and stops at the first
    /// message that is anything else.
    #[inline]
    pub fn plain_data_run<'w>(
        &mut self,
        win: &'w [u8],
        base: u64,
        mut f: impl FnMut(u64, u32, &Arc<Subscription>, &'w [u8]) -> bool,
    ) {
        let Some((mut rel, limit)) = self.plain_window(win, base) else {
            return;
        };
        let (subs, entries) = (self.defs.subscriptions(), self.defs.entries());
        while let Some((end, entry)) = plain_at(win, rel, limit, entries) {
            prefetch(win, rel + PREFETCH_AHEAD);
            // The index comes from the msg_id table already loaded: callers that only
            // need it (the parse) do not reach into the subscription record.
            let go_on = f(
                base + rel as u64,
                entry.sub,
                &subs[entry.sub as usize],
                &win[rel + MESSAGE_HEADER_SIZE..end],
            );
            rel = end;
            if !go_on {
                break;
            }
        }
        self.pos = base + rel as u64;
    }

    fn finding(&mut self, kind: FindingKind, offset: u64, len: u64) {
        if let Some(last) = self.findings.last_mut() {
            if last.absorb(&kind, offset, len) {
                return;
            }
        }
        self.findings.push(Finding::new(kind, offset, len));
    }

    /// Frames the next record of `win` (bytes of the file from absolute offset
    /// `base`; `eof` when they reach the end of the file).
    pub fn step(&mut self, win: &[u8], base: u64, eof: bool) -> Result<Step, ReadError> {
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

    fn step_inner(&mut self, win: &[u8], base: u64, eof: bool) -> Result<Step, ReadError> {
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
            if self.resync.is_some() {
                match self.resync_step(win, base, eof) {
                    Some(step) => return Ok(step),
                    None => continue,
                }
            }
            let p = self.pos;
            let win_end = base + win.len() as u64;
            if let Some(&off) = self.appended.first() {
                if p >= off {
                    self.appended.remove(0);
                    if p == off {
                        self.in_definitions = false;
                        self.finding(FindingKind::AppendedData, off, 0);
                    } else {
                        self.finding(
                            FindingKind::InvalidAppendedOffset(off),
                            self.appended_field,
                            0,
                        );
                    }
                    continue;
                }
            }
            if p >= win_end {
                return Ok(if eof { self.end() } else { Step::NeedMore });
            }
            if win_end - p < MESSAGE_HEADER_SIZE as u64 && !eof {
                return Ok(Step::NeedMore);
            }
            if let Some(&off) = self.appended.first() {
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
                    if msg_type == b'D' {
                        match self.cut_by_zero_fill(win, base, p, size, eof) {
                            None => return Ok(Step::NeedMore),
                            Some(true) => {
                                self.phase = Phase::Messages;
                                self.resync = Some(Resync::cut(p, size));
                                continue;
                            }
                            Some(false) => {}
                        }
                    }
                    self.phase = Phase::Messages;
                    let record = Record::framed(p, msg_type, size);
                    self.pos = record.end();
                    let payload = &win[rel + 3..rel + 3 + size as usize];
                    if !self.in_definitions {
                        self.known_keys.accepted(msg_type, payload);
                    }
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
        // Offsets never reached point past the end of the file: the place to show
        // is where the flag bits message holds them.
        for off in std::mem::take(&mut self.appended) {
            self.finding(
                FindingKind::InvalidAppendedOffset(off),
                self.appended_field,
                0,
            );
        }
        Step::End
    }

    /// Applies what framing itself needs from an accepted message.
    fn accept(
        &mut self,
        mut record: Record,
        payload: &[u8],
        first: bool,
    ) -> Result<Record, ReadError> {
        match record.msg_type {
            b'B' if first => self.flag_bits(record, payload)?,
            b'B' => self.finding(FindingKind::MisplacedFlagBits, record.offset, 0),
            b'F' => {
                if let Some(kind) = self.defs.format(payload) {
                    // An invalid format is reported where its text starts.
                    let at = match kind {
                        FindingKind::InvalidFormat(_) => record.offset + 3,
                        _ => record.offset,
                    };
                    self.finding(kind, at, 0);
                }
            }
            b'A' => {
                self.in_definitions = false;
                if let Some(kind) = self.defs.subscribe(record.offset, payload) {
                    self.finding(kind, record.offset, 0);
                }
            }
            b'L' | b'C' => self.in_definitions = false,
            b'R' => self.defs.unsubscribe(u16_at(payload, 0)),
            b'D' => record.sub = self.defs.sub_index(u16_at(payload, 0)),
            _ => {}
        }
        Ok(record)
    }
}
