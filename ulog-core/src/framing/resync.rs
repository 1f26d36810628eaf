//! Damage: a message that is not plausible is skipped by its own size when the
//! messages after it frame cleanly; otherwise the reader looks forward for the next
//! sync magic or the first header that starts a chain of plausible messages (a short
//! one will do where it ends at the end of the file or at zero fill), and reports the
//! stretch it skipped. A data message that zero fill cut (its header written, the rest
//! in a block the SD card never wrote) is damage too, reported with the zeros after it
//! ([`Framer::cut_by_zero_fill`]).

use crate::bytes::{u16_at, SYNC_MAGIC};
use crate::finding::{Corruption, FindingKind};

use super::check::{Bad, Check};
use super::{Framer, Record, Step};

/// A damaged stretch being skipped.
#[derive(Clone, Copy)]
pub(super) struct Resync {
    /// Where the damage starts.
    start: u64,
    /// The next place to look at.
    pub next: u64,
    all_zero: bool,
    overrun: bool,
    zero_size: bool,
    /// Whether the stretch starts with a data message cut by zero fill.
    cut: bool,
}

impl Resync {
    /// The stretch of a data message at `p` (`size` bytes of payload) that zero fill
    /// cut, and of the zeros after it: looked through from the message's end.
    pub(super) fn cut(p: u64, size: u16) -> Resync {
        Resync {
            start: p,
            next: p + 3 + u64::from(size),
            all_zero: false,
            overrun: false,
            zero_size: false,
            cut: true,
        }
    }
}

/// Messages that must frame cleanly after a place for it to count as real messages.
const CHAIN_DEPTH: usize = 2;

/// Where a chain of plausible messages stops.
#[derive(Clone, Copy, PartialEq, Eq)]
enum ChainEnd {
    /// Not yet: `depth + 1` messages framed.
    Open,
    /// At a message that is not plausible.
    Broken,
    /// At the end of the file or at an appended offset.
    FileEnd,
    /// At zero fill: a header of size 0 and type 0, three zero bytes.
    ZeroFill,
}

/// Zero bytes that must follow a data message of the wrong size for it to be taken as
/// a whole message followed by zero fill (rather than a corrupt size field): zero
/// fill comes in sectors, while payloads hold shorter zero runs.
const ZEROS_AFTER_MISMATCH: usize = 512;

/// An SD card's sector: the unit it writes in, so that the blocks it never wrote
/// (after a power loss) are zeros from a multiple of it in the file (a file starts at
/// the start of a cluster), at least this long.
const SECTOR: u64 = 512;

/// The most non-zero bytes a data message's payload may start with and still be taken
/// for one cut by zero fill away from a sector boundary: two bytes of timestamp are
/// under 65,536 µs after boot, before any logger writes a row.
const CUT_HEAD: usize = 2;

impl Framer {
    /// Handles a message that is not plausible at `p`.
    pub(super) fn bad(
        &mut self,
        win: &[u8],
        base: u64,
        p: u64,
        eof: bool,
        bad: Bad,
    ) -> Option<Step> {
        let rel = (p - base) as usize;
        let (size, msg_type) = if win.len() - rel >= 3 {
            (u16_at(win, rel), win[rel + 2])
        } else {
            (0, 0)
        };
        let end = p + 3 + size as u64;
        let skippable = !matches!(bad, Bad::Overrun | Bad::ZeroSize);
        if skippable {
            // A message of a type this reader does not know has only its size to go
            // by: chance bytes (a run of sync magic, say) can make one that ends
            // exactly at the end of the file, so it needs a message after it too.
            let at_end = usize::from(matches!(bad, Bad::UnknownType(_)));
            match self.chain_valid(win, base, end, eof, CHAIN_DEPTH, at_end) {
                None => return Some(Step::NeedMore),
                Some(true) => match self.spans_a_chain(win, base, p, end, eof) {
                    None => return Some(Step::NeedMore),
                    // A bad message has nothing but the chain after it to vouch for its
                    // size, and landing on a message boundary by chance is likely enough in
                    // a log of small messages: one that spans messages of its own is a
                    // broken header (an unknown type of chance bytes, a key or size field
                    // hit by corruption), and resynchronising keeps what it would swallow.
                    Some(true) => {}
                    Some(false) => {
                        self.finding(self.bad_kind(bad, msg_type), p, end - p);
                        self.pos = end;
                        let record = Record::framed(p, msg_type, size);
                        return match bad {
                            Bad::UnknownType(_) => Some(Step::Record(Record {
                                unknown: true,
                                ..record
                            })),
                            // A data message longer than its format, framed by its own
                            // size: its first bytes are the format's, kept as a row (the
                            // readers read the format's size of it), reported above.
                            Bad::SizeMismatch(id, (full, _), found) if found > full => {
                                Some(Step::Record(Record {
                                    sub: self.defs.sub_index(id),
                                    ..record
                                }))
                            }
                            _ => None,
                        };
                    }
                },
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
                        match self.cut_by_zero_fill(win, base, p, size, eof) {
                            None => return Some(Step::NeedMore),
                            Some(true) => {
                                self.resync = Some(Resync::cut(p, size));
                                return None;
                            }
                            Some(false) => {}
                        }
                        let tail = win.get(after..).unwrap_or(&[]);
                        let seen = &tail[..tail.len().min(ZEROS_AFTER_MISMATCH)];
                        if seen.len() >= 3 && seen.iter().all(|&b| b == 0) {
                            if seen.len() < ZEROS_AFTER_MISMATCH && !eof {
                                return Some(Step::NeedMore);
                            }
                            self.finding(self.bad_kind(bad, msg_type), p, end - p);
                            self.pos = end;
                            return None;
                        }
                    }
                }
            }
        }
        self.resync = Some(Resync {
            start: p,
            next: p + 1,
            all_zero: win[rel] == 0,
            overrun: matches!(bad, Bad::Overrun),
            zero_size: matches!(bad, Bad::ZeroSize),
            cut: false,
        });
        None
    }

    /// Whether the data message at `p` (`size` bytes of payload, within `win`) was cut
    /// by zero fill: its payload ends in a run of zero bytes that goes on past its end
    /// (a zero header follows it, so the resync skips the rest of the run) for a
    /// sector's length at least ([`SECTOR`] bytes from where the run starts), and
    /// either the sector that holds the message's last byte is zeros from its start (an
    /// unwritten block that begins inside the message) or the run is all the payload
    /// but its msg_id and first [`CUT_HEAD`] bytes and the message does not end at a sector
    /// boundary (where an unwritten block would start right after a whole message).
    ///
    /// The second form is what a power-loss log shows where the blocks are not aligned
    /// with the file (timestamps 0, 34, 202 amid rows at 14 s): such a payload is a
    /// timestamp under 65,536 µs and nothing else, which no logger writes. A real row
    /// whose values are all zero keeps a real timestamp (a disarmed vehicle's
    /// `actuator_outputs`, zeros from byte 12 on, just before zero fill is a row; an
    /// earlier "most of the payload" rule dropped it). A payload that ends in a
    /// non-zero byte, or whose zeros the run does not continue for a sector, is a row;
    /// so is one whose trailing zeros happen to meet zero fill without either
    /// condition. `None`: more bytes needed (at most a sector and a header past the
    /// message's end).
    pub(super) fn cut_by_zero_fill(
        &self,
        win: &[u8],
        base: u64,
        p: u64,
        size: u16,
        eof: bool,
    ) -> Option<bool> {
        let rel = (p - base) as usize;
        let end = rel + 3 + usize::from(size);
        let payload = &win[rel + 3..end];
        let zeros = payload.iter().rev().take_while(|&&b| b == 0).count();
        if zeros == 0 {
            return Some(false);
        }
        let (run, abs_end) = (base + (end - zeros) as u64, base + end as u64);
        let sector = (abs_end - 1) / SECTOR * SECTOR;
        let unwritten_block = sector >= run;
        // `payload` starts with the two bytes of msg_id.
        let bare_stamp = abs_end % SECTOR != 0 && zeros + 2 + CUT_HEAD >= payload.len();
        if !unwritten_block && !bare_stamp {
            return Some(false);
        }
        // Zeros through the sector (or a sector's length of run), and a zero header.
        let through = if unwritten_block { sector } else { run } + SECTOR;
        let through = through.max(abs_end + 3);
        // Bytes after an appended offset are another section's.
        if self
            .appended
            .first()
            .is_some_and(|&off| off >= abs_end && off < through)
        {
            return Some(false);
        }
        let seen = &win[end..win.len().min((through - base) as usize)];
        if seen.iter().any(|&b| b != 0) {
            return Some(false);
        }
        if (seen.len() as u64) < through - abs_end {
            return if eof { Some(false) } else { None };
        }
        Some(true)
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

    /// Looks for the end of a corrupt stretch. `None`: resynchronised, go on.
    pub(super) fn resync_step(&mut self, win: &[u8], base: u64, eof: bool) -> Option<Step> {
        let mut s = self.resync.expect("resynchronising");
        let win_end = base + win.len() as u64;
        let limit = self.appended.first().copied().unwrap_or(u64::MAX);
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
                self.resync = Some(s);
                return Some(Step::NeedMore);
            }
            match self.chain_valid_resync(win, base, q, eof) {
                None => {
                    s.next = q;
                    self.resync = Some(s);
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
                self.resync = Some(s);
                return Some(Step::NeedMore);
            }
            None => win_end,
        };
        self.resync = None;
        let len = end_of_damage - s.start;
        let kind = if s.cut {
            FindingKind::Corrupt(Corruption::CutByZeroFill)
        } else if resume.is_none() && s.overrun && !s.all_zero {
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

    /// Whether a place found while resynchronising starts real messages: a chain of
    /// three; or, where the messages stop (the end of the file, an appended offset, zero
    /// fill), two, or a single data message.
    ///
    /// Zero fill is where a writer's bytes stop, as the end of the file is: after a
    /// power loss an SD card keeps good messages between blocks it never wrote, which
    /// read as headers of size 0 and type 0, so an island of one or two messages
    /// between two runs of zeros is common (pyulog, stepping through the zeros a byte
    /// at a time, reads it). A single data message is enough there and at the end of
    /// the file: its msg_id is subscribed, its size exactly its format's, and it ends
    /// exactly where the bytes stop (chance bytes almost never pass all three). Any
    /// other single message needs a second one: text that runs into zeros could pass
    /// for a logged string or a key. The zeros are still skipped and reported as a
    /// damaged stretch of their own.
    ///
    /// Before more damage (a broken header) two are needed even for data: damage comes
    /// in stretches, and a message framed alone inside one is as likely damaged itself
    /// (the corpus log `corrupt_unregistered_msg_id` has one whose header is intact and
    /// whose timestamp is 4·10¹⁸ µs; pyulog skips it too).
    fn chain_valid_resync(&self, win: &[u8], base: u64, q: u64, eof: bool) -> Option<bool> {
        let depth = CHAIN_DEPTH;
        let data = win.get((q - base) as usize + 2) == Some(&b'D');
        match self.chain_len(win, base, q, eof, depth, false)? {
            (n, _) if n > depth => Some(true),
            // A lone data message that zero fill cut is part of the stretch.
            (1, ChainEnd::ZeroFill) if data => {
                let size = u16_at(win, (q - base) as usize);
                Some(!self.cut_by_zero_fill(win, base, q, size, eof)?)
            }
            (n, ChainEnd::FileEnd | ChainEnd::ZeroFill) => Some(n >= 2 || (n == 1 && data)),
            (n, ChainEnd::Broken) => Some(n >= 2),
            (_, ChainEnd::Open) => Some(false),
        }
    }

    /// Whether a chain of plausible messages (as strict as resynchronising: three
    /// messages) lies wholly inside the bytes `p + 1..end`. `None`: those bytes are not
    /// all in `win` yet (a header too short for its type is judged before them, and its
    /// end can be known for a boundary, an appended offset, before it is read): the
    /// caller asks for more.
    fn spans_a_chain(&self, win: &[u8], base: u64, p: u64, end: u64, eof: bool) -> Option<bool> {
        let inside = match win.get(..(end - base) as usize) {
            Some(inside) => inside,
            // The file ends first: what there is is all there will be.
            None if eof => win,
            None => return None,
        };
        let inside_end = base + inside.len() as u64;
        Some((p + 1..inside_end).any(|q| {
            matches!(
                self.chain_len(inside, base, q, true, CHAIN_DEPTH, false),
                Some((n, _)) if n > CHAIN_DEPTH
            )
        }))
    }

    /// Whether the messages from `q` on frame cleanly for `depth` more messages (or
    /// reach the end of the file or an appended offset). `None`: more bytes needed.
    /// Data messages of a known subscription frame by their own size here even where
    /// it is not their format's: a logger that writes every message of a topic with
    /// the wrong size must not turn the rest of the log into one damaged stretch.
    /// (Looking for a place to resynchronise stays strict: there the exact size is
    /// much of what tells a real header from chance bytes.)
    /// Reaching the end counts after `at_end` messages or more; zero fill does not
    /// count here, as the size that led to it is the one in doubt (a size field hit
    /// by corruption can land on a few zero bytes inside a payload).
    fn chain_valid(
        &self,
        win: &[u8],
        base: u64,
        q: u64,
        eof: bool,
        depth: usize,
        at_end: usize,
    ) -> Option<bool> {
        match self.chain_len(win, base, q, eof, depth, true)? {
            (n, _) if n > depth => Some(true),
            (n, end) => Some(end == ChainEnd::FileEnd && n >= at_end),
        }
    }

    /// How many plausible messages follow from `q` (up to `depth + 1`), and where they
    /// stop; `any_size`: data messages of a known subscription count whatever their
    /// size. `None`: more bytes needed.
    fn chain_len(
        &self,
        win: &[u8],
        base: u64,
        q: u64,
        eof: bool,
        depth: usize,
        any_size: bool,
    ) -> Option<(usize, ChainEnd)> {
        let mut q = q;
        let mut new_ids: Vec<u16> = Vec::new();
        let win_end = base + win.len() as u64;
        for n in 0..=depth {
            if eof && q == win_end {
                return Some((n, ChainEnd::FileEnd));
            }
            if self.appended.first() == Some(&q) {
                return Some((n, ChainEnd::FileEnd));
            }
            let check = match self.check(win, base, q, eof, true, &new_ids) {
                Check::Bad(Bad::SizeMismatch(..)) if any_size => {
                    Check::Ok(u16_at(win, (q - base) as usize))
                }
                other => other,
            };
            match check {
                Check::NeedMore => return None,
                // A zero size is judged on the three header bytes, all in `win`.
                Check::Bad(Bad::ZeroSize) if win[(q - base) as usize + 2] == 0 => {
                    return Some((n, ChainEnd::ZeroFill))
                }
                Check::Bad(_) => return Some((n, ChainEnd::Broken)),
                Check::Ok(size) => {
                    let rel = (q - base) as usize;
                    if win[rel + 2] == b'A' {
                        new_ids.push(u16_at(win, rel + 4));
                    }
                    q += 3 + size as u64;
                }
            }
        }
        Some((depth + 1, ChainEnd::Open))
    }
}

#[cfg(test)]
mod tests {
    use crate::finding::{Corruption, FindingKind};
    use crate::read::Messages;
    use crate::stream::{Progress, PushReader};
    use crate::testing::LogBuilder;
    use crate::ULog;

    fn row(v: u32) -> Vec<u8> {
        [&(u64::from(v) * 100).to_le_bytes()[..], &v.to_le_bytes()].concat()
    }

    /// A power-loss log in small: data messages alone or in twos between runs of zeros
    /// (blocks the SD card never wrote), a logged string alone and one with a data
    /// message, then zeros to the end. Every data message is kept, the lone string is
    /// not (a single message that is not data needs a second one before zero fill),
    /// and every run of zeros is reported where it starts.
    #[test]
    fn messages_between_runs_of_zeros_are_kept_and_the_zeros_reported() {
        let mut b = LogBuilder::new(1, 0);
        b.flag_bits([0; 8], [0; 8], [0; 3]);
        b.format("t:uint64_t timestamp;uint32_t v;");
        b.subscribe(0, 0, "t");
        let mut runs = Vec::new();
        let mut zeros = |b: &mut LogBuilder, n: usize| {
            runs.push(b.bytes().len() as u64);
            b.garbage(&vec![0; n]);
        };
        for v in 0..4 {
            b.data(0, &row(v));
        }
        zeros(&mut b, 600);
        b.data(0, &row(4));
        zeros(&mut b, 300);
        b.data(0, &row(5)).data(0, &row(6));
        zeros(&mut b, 4096);
        b.log(b'6', 650, "alone");
        let alone_end = b.bytes().len() as u64;
        zeros(&mut b, 512);
        b.log(b'6', 680, "with a row").data(0, &row(7));
        zeros(&mut b, 64 * 1024);
        let bytes = b.into_bytes();

        let log = ULog::parse(&bytes).unwrap();
        let t = log.topic("t", 0).unwrap();
        let v = t.field("v").unwrap();
        let kept: Vec<u32> = t
            .payloads()
            .map(|p| v.read(p).unwrap().as_i128().unwrap() as u32)
            .collect();
        assert_eq!(kept, (0..8).collect::<Vec<_>>(), "{:?}", log.findings());
        let texts: Vec<String> = log
            .logged_messages()
            .iter()
            .map(|l| l.text.to_string())
            .collect();
        assert_eq!(texts, ["with a row"]);

        let found: Vec<_> = log
            .findings()
            .iter()
            .map(|f| (f.kind.clone(), f.offset, f.len))
            .collect();
        let zero_fill = FindingKind::Corrupt(Corruption::ZeroFill);
        let zero_size = FindingKind::Corrupt(Corruption::ZeroSize);
        assert_eq!(
            found,
            [
                (zero_fill.clone(), runs[0], 600),
                (zero_fill.clone(), runs[1], 300),
                // The zeros, the lone string and the zeros after it: one stretch.
                (zero_size, runs[2], alone_end + 512 - runs[2]),
                (zero_fill, runs[4], 64 * 1024),
            ]
        );

        // The incremental reader takes the same decisions, in any chunks.
        let mut whole = Messages::new(&bytes);
        let all: Vec<_> = whole.by_ref().map(Result::unwrap).collect();
        assert_eq!(whole.findings(), log.findings());
        for chunk in [1, 7, 300, 4096] {
            let mut inc = PushReader::new();
            let mut i = 0;
            let mut check = |inc: &mut PushReader| {
                while inc.advance().unwrap() == Progress::Ready {
                    assert_eq!(inc.current().unwrap(), all[i], "chunk {chunk}");
                    i += 1;
                }
            };
            for c in bytes.chunks(chunk) {
                inc.push(c);
                check(&mut inc);
            }
            inc.finish();
            check(&mut inc);
            assert_eq!(i, all.len(), "chunk {chunk}");
            assert_eq!(inc.findings(), log.findings(), "chunk {chunk}");
        }
    }

    /// A data message alone between two runs of zeros whose own payload is mostly the
    /// second run (a timestamp of 34, then zeros) is not an island to keep: the
    /// resynchronisation goes through it, and the two runs and the message are one
    /// stretch. A row alone between runs whose payload is its own (a few trailing
    /// zero bytes, or a real timestamp and every value zero, as a disarmed vehicle's
    /// `actuator_outputs`) stays an island.
    #[test]
    fn a_lone_message_cut_by_zero_fill_is_part_of_the_stretch() {
        let stamp_only = [&34u64.to_le_bytes()[..], &[0; 4]].concat();
        let zero_values = [&14_000_000u64.to_le_bytes()[..], &[0; 4]].concat();
        for (lone_row, cut) in [(stamp_only, true), (row(4), false), (zero_values, false)] {
            let mut b = LogBuilder::new(1, 0);
            b.format("t:uint64_t timestamp;uint32_t v;");
            b.subscribe(0, 0, "t");
            for v in 0..4 {
                b.data(0, &row(v));
            }
            let start = b.bytes().len() as u64;
            b.garbage(&[0; 600]);
            let lone = b.bytes().len() as u64;
            b.data(0, &lone_row);
            let zeros = b.bytes().len() as u64;
            b.garbage(&[0; 4096]);
            let resume = b.bytes().len() as u64;
            b.data(0, &row(5)).data(0, &row(6)).data(0, &row(7));
            let bytes = b.into_bytes();
            assert_ne!(zeros % 512, 0, "the lone message does not end a sector");

            let log = ULog::parse(&bytes).unwrap();
            let t = log.topic("t", 0).unwrap();
            let ts: Vec<u64> = t.timestamps();
            let found: Vec<_> = log
                .findings()
                .iter()
                .map(|f| (f.kind.clone(), f.offset, f.len))
                .collect();
            let zero_fill = FindingKind::Corrupt(Corruption::ZeroFill);
            if cut {
                assert_eq!(ts, [0, 100, 200, 300, 500, 600, 700]);
                assert_eq!(
                    found,
                    [(
                        FindingKind::Corrupt(Corruption::ZeroSize),
                        start,
                        resume - start
                    )]
                );
            } else {
                let lone_stamp = u64::from_le_bytes(lone_row[..8].try_into().unwrap());
                assert_eq!(ts, [0, 100, 200, 300, lone_stamp, 500, 600, 700]);
                assert_eq!(
                    found,
                    [
                        (zero_fill.clone(), start, lone - start),
                        (zero_fill, zeros, resume - zeros)
                    ]
                );
            }
            let mut inc = PushReader::new();
            for c in bytes.chunks(100) {
                inc.push(c);
                while inc.advance().unwrap() == Progress::Ready {}
            }
            inc.finish();
            while inc.advance().unwrap() == Progress::Ready {}
            assert_eq!(inc.findings(), log.findings(), "cut {cut}");
        }
    }
}
