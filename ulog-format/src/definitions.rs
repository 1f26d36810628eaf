//! The file's fixed parts (magic, header and message header sizes, sync magic), and a
//! walk of a log's messages for tools that only need the format texts (the derive
//! macros read a reference log at compile time). The reader in `ulog-core` has its own
//! full framing; this walk finds the format messages it finds, anywhere in the file
//! (the spec allows formats after data; real loggers write them), stepping over
//! damage by searching for the next format message.

use core::fmt;

/// The first bytes of every ULog file: `ULog` then `0x01 0x12 0x35`.
pub const MAGIC: [u8; 7] = *b"ULog\x01\x12\x35";

/// The size of the file header (magic, version byte, start timestamp).
pub const HEADER_SIZE: usize = 16;

/// The size of a message header: `u16` payload size, then the `u8` message type.
pub const MESSAGE_HEADER_SIZE: usize = 3;

/// The payload of a sync (`S`) message, which readers search for to find messages
/// again after corruption.
pub const SYNC_MAGIC: [u8; 8] = [0x2F, 0x73, 0x13, 0x20, 0x25, 0x0C, 0xBB, 0x12];

/// Why the definitions of a log could not be walked.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum DefinitionsErrorKind {
    /// The file is shorter than the 16-byte header.
    TooShort,
    /// The file does not start with the ULog magic.
    BadMagic,
}

/// An error walking the definitions, with the byte offset it is about.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DefinitionsError {
    /// What is wrong.
    pub kind: DefinitionsErrorKind,
    /// Where in the file.
    pub offset: usize,
}

impl fmt::Display for DefinitionsError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.kind {
            DefinitionsErrorKind::TooShort => {
                write!(f, "file shorter than the 16-byte ULog header")
            }
            DefinitionsErrorKind::BadMagic => {
                write!(f, "not a ULog file (no magic at offset {})", self.offset)
            }
        }
    }
}

impl std::error::Error for DefinitionsError {}

/// The message types of the spec, in the order it lists them.
const KNOWN_TYPES: &[u8] = b"BFIMPQADRLCSO";

/// The payloads of the format (`F`) messages of a log, with their file offsets, in
/// file order: every message is walked, so formats defined after data are found too.
/// Where a message header frames nothing plausible (an unknown type whose size does not
/// lead to a known one, a size of 0: corruption, a zero-filled stretch), the walk
/// searches forward for the next format message (a header of type `F` whose text
/// parses as a format) and goes on from there; a message cut off by the end of the
/// file ends it.
///
/// ```
/// let mut log = ulog_format::definitions::MAGIC.to_vec();
/// log.extend_from_slice(&[1, 0, 0, 0, 0, 0, 0, 0, 0]);
/// let text = b"m:uint8_t x;";
/// log.extend_from_slice(&(text.len() as u16).to_le_bytes());
/// log.push(b'F');
/// log.extend_from_slice(text);
/// let formats = ulog_format::definitions::format_texts(&log).unwrap();
/// assert_eq!(formats, [(16 + 3, &text[..])]);
/// ```
pub fn format_texts(bytes: &[u8]) -> Result<Vec<(usize, &[u8])>, DefinitionsError> {
    if bytes.len() < HEADER_SIZE {
        return Err(DefinitionsError {
            kind: DefinitionsErrorKind::TooShort,
            offset: 0,
        });
    }
    if bytes[..MAGIC.len()] != MAGIC {
        return Err(DefinitionsError {
            kind: DefinitionsErrorKind::BadMagic,
            offset: 0,
        });
    }
    let mut out = Vec::new();
    let mut pos = HEADER_SIZE;
    while let Some((size, kind)) = message_header(bytes, pos) {
        let start = pos + MESSAGE_HEADER_SIZE;
        let end = start + size;
        let known = KNOWN_TYPES.contains(&kind);
        // An unknown type is skipped by its size (the spec's rule for new message
        // types) when a known message follows it.
        let frames = size > 0
            && end <= bytes.len()
            && (known || message_header(bytes, end).is_some_and(|(_, k)| KNOWN_TYPES.contains(&k)));
        if !frames {
            match next_format(bytes, pos + 1) {
                Some(p) => {
                    pos = p;
                    continue;
                }
                None => break,
            }
        }
        if kind == b'F' {
            out.push((start, &bytes[start..end]));
        }
        pos = end;
    }
    Ok(out)
}

/// The size and type of the message header at `pos`, if the file holds one there.
fn message_header(bytes: &[u8], pos: usize) -> Option<(usize, u8)> {
    let h = bytes.get(pos..pos + MESSAGE_HEADER_SIZE)?;
    Some((usize::from(u16::from_le_bytes([h[0], h[1]])), h[2]))
}

/// The offset of the first format message at or after `from` whose text parses.
fn next_format(bytes: &[u8], from: usize) -> Option<usize> {
    let mut at = from;
    loop {
        // The type byte is the third of a header.
        let f = at + 2 + bytes.get(at + 2..)?.iter().position(|&b| b == b'F')?;
        let pos = f - 2;
        if let Some((size, _)) = message_header(bytes, pos) {
            let start = pos + MESSAGE_HEADER_SIZE;
            if let Some(text) = bytes.get(start..start + size) {
                if size > 2 && crate::Format::parse_bytes(text).is_ok() {
                    return Some(pos);
                }
            }
        }
        at = pos + 1;
    }
}

/// A format text of a log, parsed, with its file offset.
pub type ParsedFormat = (usize, Result<crate::Format, crate::FormatError>);

/// The formats of a log, each parsed (see [`format_texts`]).
pub fn formats_in(bytes: &[u8]) -> Result<Vec<ParsedFormat>, DefinitionsError> {
    Ok(format_texts(bytes)?
        .into_iter()
        .map(|(offset, text)| (offset, crate::Format::parse_bytes(text)))
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn message(kind: u8, payload: &[u8]) -> Vec<u8> {
        let mut m = (payload.len() as u16).to_le_bytes().to_vec();
        m.push(kind);
        m.extend_from_slice(payload);
        m
    }

    #[test]
    fn finds_formats_after_data_and_damage_and_stops_at_truncation() {
        let mut log = MAGIC.to_vec();
        log.extend_from_slice(&[1; 9]);
        log.extend(message(b'B', &[0; 40]));
        log.extend(message(b'F', b"a:uint8_t x;"));
        log.extend(message(b'I', b"\x0bchar[3] abcxyz"));
        log.extend(message(b'F', b"b:bad"));
        log.extend(message(b'A', b"\0\0\0a"));
        log.extend(message(b'D', b"\0\0\x07"));
        // After data, as the spec allows.
        log.extend(message(b'F', b"c:uint8_t x;"));
        // A zero-filled stretch, then a message of a type this walk does not know.
        log.extend([0; 37]);
        log.extend(message(b'F', b"d:float32 x;"));
        log.extend(message(b'F', b"e:uint16_t y;"));
        log.extend(message(b'X', b"new"));
        log.extend(message(b'F', b"f:uint8_t z;"));
        let found = formats_in(&log).unwrap();
        let names: Vec<String> = found
            .iter()
            .map(|(_, f)| {
                f.as_ref()
                    .map_or_else(|_| "?".to_owned(), |f| f.name.clone())
            })
            .collect();
        // The search after the zeros looks for a format text that parses: `d` does
        // (`float32` is a nested type's name as far as the grammar goes; the log
        // defines no such type, which laying it out reports).
        assert_eq!(names, ["a", "?", "c", "d", "e", "f"]);
        let cut = &log[..log.len() - 4];
        assert_eq!(format_texts(cut).unwrap().len(), 5);
        assert_eq!(
            format_texts(b"ULog").unwrap_err().kind,
            DefinitionsErrorKind::TooShort
        );
        assert_eq!(
            format_texts(&[0; 20]).unwrap_err().kind,
            DefinitionsErrorKind::BadMagic
        );
    }
}
