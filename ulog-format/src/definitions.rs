//! The file's fixed parts (magic, header and message header sizes, sync magic), and a
//! minimal walk of a log's definitions section for tools that only need the format
//! texts (the derive macros read a reference log at compile time). The reader in
//! `ulog-core` has its own full framing; this walk stops at the first subscription or
//! data message.

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

/// The payloads of the format (`F`) messages of a log's definitions section, with
/// their file offsets, in file order. The walk ends at the first subscription (`A`)
/// or data (`D`) message, or at a message cut off by the end of the file.
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
    while let Some(header) = bytes.get(pos..pos + MESSAGE_HEADER_SIZE) {
        let size = usize::from(u16::from_le_bytes([header[0], header[1]]));
        let kind = header[2];
        if kind == b'A' || kind == b'D' {
            break;
        }
        let start = pos + MESSAGE_HEADER_SIZE;
        let Some(payload) = bytes.get(start..start + size) else {
            break;
        };
        if kind == b'F' {
            out.push((start, payload));
        }
        pos = start + size;
    }
    Ok(out)
}

/// A format text of a log, parsed, with its file offset.
pub type ParsedFormat = (usize, Result<crate::Format, crate::FormatError>);

/// The formats of a log's definitions section, each parsed (see [`format_texts`]).
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
    fn stops_at_subscriptions_and_truncation() {
        let mut log = MAGIC.to_vec();
        log.extend_from_slice(&[1; 9]);
        log.extend(message(b'B', &[0; 40]));
        log.extend(message(b'F', b"a:uint8_t x;"));
        log.extend(message(b'I', b"\x0bchar[3] abcxyz"));
        log.extend(message(b'F', b"b:bad"));
        log.extend(message(b'A', b"\0\0\0a"));
        log.extend(message(b'F', b"c:uint8_t x;"));
        let found = formats_in(&log).unwrap();
        assert_eq!(found.len(), 2);
        assert_eq!(found[0].1.as_ref().unwrap().name, "a");
        assert!(found[1].1.is_err());
        let cut = &log[..log.len() - 40];
        assert_eq!(format_texts(cut).unwrap().len(), 1);
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
