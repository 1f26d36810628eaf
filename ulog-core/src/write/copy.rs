//! Byte-exact pass-through: a log re-written message by message, unknown messages and
//! damaged stretches included, gives back the same file.

use std::io::Write;

use crate::error::Result;
use crate::read::framing::{HEADER_LEN, MSG_HEADER_LEN};
use crate::read::iter::Messages;
use crate::write::raw::RawWriter;

/// Copies a log through the reader and the raw writer: every framed message is
/// re-emitted from its parts (type and payload), and every byte between messages
/// (corruption, a partial message before appended data, a truncated tail) is copied
/// verbatim, so the output equals the input byte for byte.
///
/// Returns how many messages were re-emitted. Fails only where the reader refuses the
/// log (not ULog, unknown incompatibility flags) or writing fails.
///
/// ```
/// let bytes = ulog_core::testing::sample_log();
/// let mut out = Vec::new();
/// ulog_core::write::copy::copy_log(&bytes, &mut out)?;
/// assert_eq!(out, bytes);
/// # Ok::<(), ulog_core::Error>(())
/// ```
pub fn copy_log<W: Write>(data: &[u8], out: W) -> Result<u64> {
    let mut w = RawWriter::new(out);
    let mut messages = Messages::new(data);
    let mut at = 0usize;
    let mut count = 0u64;
    for m in messages.by_ref() {
        let m = m?;
        if at == 0 {
            w.bytes(&data[..HEADER_LEN])?;
            at = HEADER_LEN;
        }
        let start = m.offset as usize;
        if start > at {
            w.bytes(&data[at..start])?;
        }
        let size = u16::from_le_bytes([data[start], data[start + 1]]) as usize;
        let payload = &data[start + MSG_HEADER_LEN..start + MSG_HEADER_LEN + size];
        w.message(m.message.msg_type(), &[payload])?;
        at = start + MSG_HEADER_LEN + size;
        count += 1;
    }
    if at == 0 {
        // A log without messages: validate its header the same way, then copy it.
        crate::ULog::parse(data)?;
    }
    w.bytes(&data[at..])?;
    w.flush()?;
    Ok(count)
}
