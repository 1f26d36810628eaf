//! The raw message writer: a header, then `[u16 size][u8 type][payload]` messages,
//! exactly as told. Buffered, with no allocation per message.

use std::io::Write;

use crate::bytes::{MAGIC, MESSAGE_HEADER_SIZE};
use crate::write::error::{WriteError, WriteErrorKind};

type Result<T, E = WriteError> = core::result::Result<T, E>;

const FLUSH_AT: usize = 64 * 1024;

/// Writes messages to any `Write`, buffering up to 64 KiB; knows the file offset of
/// everything it writes.
pub struct RawWriter<W: Write> {
    out: W,
    buf: Vec<u8>,
    written: u64,
}

impl<W: Write> RawWriter<W> {
    /// A writer at file offset 0 (write a header first, or use
    /// [`RawWriter::at_offset`] to continue an existing file).
    pub fn new(out: W) -> RawWriter<W> {
        RawWriter::at_offset(out, 0)
    }

    /// A writer whose first byte lands at file offset `offset`.
    pub fn at_offset(out: W, offset: u64) -> RawWriter<W> {
        RawWriter {
            out,
            buf: Vec::with_capacity(FLUSH_AT + 65_538),
            written: offset,
        }
    }

    /// The file offset of the next byte.
    pub fn position(&self) -> u64 {
        self.written + self.buf.len() as u64
    }

    /// The 16-byte file header.
    pub fn header(&mut self, version: u8, timestamp: u64) -> Result<()> {
        let mut h = [0u8; 16];
        h[..7].copy_from_slice(&MAGIC);
        h[7] = version;
        h[8..].copy_from_slice(&timestamp.to_le_bytes());
        self.bytes(&h)
    }

    /// One message whose payload is the concatenation of `parts`.
    pub fn message(&mut self, msg_type: u8, parts: &[&[u8]]) -> Result<()> {
        let size: usize = parts.iter().map(|p| p.len()).sum();
        let size16 = u16::try_from(size).map_err(|_| {
            WriteError::new(
                WriteErrorKind::MessageTooLarge { msg_type, size },
                Some(self.position()),
            )
        })?;
        self.buf.extend_from_slice(&size16.to_le_bytes());
        self.buf.push(msg_type);
        for p in parts {
            self.buf.extend_from_slice(p);
        }
        self.maybe_flush()
    }

    /// One message whose payload is written by `fill` into the buffer (no copy).
    pub fn message_with(&mut self, msg_type: u8, fill: impl FnOnce(&mut Vec<u8>)) -> Result<()> {
        let start = self.buf.len();
        self.buf.extend_from_slice(&[0, 0, msg_type]);
        fill(&mut self.buf);
        let size = self.buf.len() - start - MESSAGE_HEADER_SIZE;
        match u16::try_from(size) {
            Ok(s) => {
                self.buf[start..start + 2].copy_from_slice(&s.to_le_bytes());
                self.maybe_flush()
            }
            Err(_) => {
                self.buf.truncate(start);
                Err(WriteError::new(
                    WriteErrorKind::MessageTooLarge { msg_type, size },
                    Some(self.position()),
                ))
            }
        }
    }

    /// Bytes as they are (a damaged stretch copied verbatim, a header).
    pub fn bytes(&mut self, bytes: &[u8]) -> Result<()> {
        self.buf.extend_from_slice(bytes);
        self.maybe_flush()
    }

    fn maybe_flush(&mut self) -> Result<()> {
        if self.buf.len() >= FLUSH_AT {
            self.drain()?;
        }
        Ok(())
    }

    fn drain(&mut self) -> Result<()> {
        let at = self.written;
        self.out
            .write_all(&self.buf)
            .map_err(|e| WriteError::io(e, Some(at)))?;
        self.written += self.buf.len() as u64;
        self.buf.clear();
        Ok(())
    }

    /// Writes the buffer out and flushes the underlying writer: every message written
    /// so far is then in the file, complete.
    pub fn flush(&mut self) -> Result<()> {
        self.drain()?;
        let at = self.written;
        self.out.flush().map_err(|e| WriteError::io(e, Some(at)))
    }

    /// Flushes and gives the underlying writer back.
    pub fn into_inner(mut self) -> Result<W> {
        self.flush()?;
        Ok(self.out)
    }
}
