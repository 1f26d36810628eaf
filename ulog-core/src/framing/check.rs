//! Whether one message is plausible: its type, its size, and (in the data section
//! and while resynchronising) its content.

use crate::bytes::{u16_at, HEADER_SIZE, SYNC_MAGIC};
use crate::definitions::NO_SUB;
use ulog_format::TypeName;

use super::Framer;

/// The message types of both spec versions.
const KNOWN_TYPES: &[u8] = b"BFIMPQARDLCSO";

/// How many bytes of a message the content checks look at.
pub(super) const STRICT_PREFIX: usize = 128;

/// The verdict on one message.
pub(super) enum Check {
    /// Plausible, of this size.
    Ok(u16),
    /// The window ends inside it.
    NeedMore,
    /// Not plausible, and why.
    Bad(Bad),
}

/// Why a message is not plausible.
#[derive(Clone, Copy)]
pub(super) enum Bad {
    ZeroSize,
    UnknownType(u8),
    UnknownMsgId(u16),
    SizeMismatch(u16, (usize, usize), usize),
    Malformed(u8, &'static str),
    Overrun,
    Implausible,
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

/// Whether the key of an information or parameter message reads as `type name` with a
/// basic type. While resynchronising, the name must follow the format grammar
/// (`ulog_format::parse_key`) and the value must have the type's size, so that a
/// stretch of binary whose first bytes happen to hold a space does not pass for a key
/// and swallow the messages after it; elsewhere a key is read as written
/// (`parse_key_as_written`: real logs have `char[11] Build Date`), as the reader
/// reads it.
fn plausible_key(key: &[u8], value_len: usize, resync: bool, known: &KnownKeys) -> bool {
    // Outside resynchronisation only the key counts, and logs repeat a few keys
    // (parameter changes): one parse per key.
    (!resync && known.0.contains(key)) || parse_plausible_key(key, value_len, resync)
}

/// The keys of information and parameter messages framing accepted outside
/// resynchronisation, up to a bound (a hostile log of endless distinct keys is then
/// parsed key by key, as without it). A memo: a copy starts empty.
#[derive(Debug, Default)]
pub(crate) struct KnownKeys(std::collections::HashSet<Box<[u8]>>);

impl Clone for KnownKeys {
    fn clone(&self) -> KnownKeys {
        KnownKeys::default()
    }
}

impl KnownKeys {
    const MAX: usize = 4096;

    /// Remembers the key of `payload`, an accepted message of type `t` framed
    /// outside resynchronisation.
    pub(crate) fn accepted(&mut self, t: u8, payload: &[u8]) {
        let key = match t {
            b'I' | b'P' => payload.get(1..1 + usize::from(*payload.first().unwrap_or(&0))),
            b'M' | b'Q' => payload.get(2..2 + usize::from(*payload.get(1).unwrap_or(&0))),
            _ => None,
        };
        if let Some(key) = key {
            if self.0.len() < Self::MAX && !self.0.contains(key) {
                self.0.insert(key.into());
            }
        }
    }
}

fn parse_plausible_key(key: &[u8], value_len: usize, resync: bool) -> bool {
    let Ok(text) = std::str::from_utf8(key) else {
        return false;
    };
    let field = if resync {
        ulog_format::parse_key(text)
    } else {
        ulog_format::parse_key_as_written(text)
    };
    match field {
        Ok(field) => match field.ty {
            TypeName::Basic(b) => !resync || b.size() * field.array_len.unwrap_or(1) == value_len,
            TypeName::Nested(_) => false,
        },
        Err(_) => false,
    }
}

fn is_name_byte(b: u8) -> bool {
    b.is_ascii_alphanumeric() || b == b'_' || b == b'-' || b == b'/'
}

impl Framer {
    /// Whether one message at `q` is plausible. `resync`: looking for a place to
    /// resynchronise, where flag bits never fit. The content checks (a logged string
    /// looks like text, a key has its type, …) apply when resynchronising and in the
    /// data section: there, a stretch of garbage whose first bytes happen to form a
    /// header of a known type must not swallow the real messages after it (ULog has no
    /// checksums; content is all there is to judge by).
    pub(super) fn check(
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
                let entry = self.defs.entry(id);
                let n = p.len() - 2;
                if entry.sub == NO_SUB {
                    if !new_ids.contains(&id) {
                        return Check::Bad(Bad::UnknownMsgId(id));
                    }
                } else if !entry.accepts(n) {
                    return Check::Bad(Bad::SizeMismatch(id, entry.sizes(), n));
                }
            }
            b'I' | b'P' => {
                if 1 + p[0] as usize > p.len() || p[0] == 0 {
                    return bad("key longer than the message");
                }
                let (key, value) = p[1..].split_at(p[0] as usize);
                if content && !plausible_key(key, value.len(), resync, &self.known_keys) {
                    return Check::Bad(Bad::Implausible);
                }
            }
            b'M' | b'Q' => {
                if 2 + p[1] as usize > p.len() || p[1] == 0 {
                    return bad("key longer than the message");
                }
                let (key, value) = p[2..].split_at(p[1] as usize);
                if content
                    && (!plausible_key(key, value.len(), resync, &self.known_keys)
                        || (t == b'M' && p[0] > 1))
                {
                    return Check::Bad(Bad::Implausible);
                }
            }
            b'B' if resync || q != HEADER_SIZE as u64 => return Check::Bad(Bad::Implausible),
            // Content checks look at a bounded prefix, so that scanning a corrupt
            // stretch stays linear with a small constant.
            b'A' if content && !p[3..].iter().take(STRICT_PREFIX).all(|&b| is_name_byte(b)) => {
                return Check::Bad(Bad::Implausible)
            }
            // A level byte outside '0'..'7' is kept in the data section (pyulog keeps
            // such strings; `ulog check` warns), but does not start a resync.
            b'L' | b'C' if content && !((!resync || valid_level(p[0])) && plausible_text(p, t)) => {
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
}
