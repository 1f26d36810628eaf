//! Byte-exact pass-through: a log re-written message by message, unknown messages and
//! damaged stretches included, gives back the same file.

use std::io::Write;

use crate::bytes::{u16_at, HEADER_SIZE, MESSAGE_HEADER_SIZE};
use crate::log::messages::Messages;
use crate::log::ulog::ULog;
use crate::write::error::WriteError;
use crate::write::raw::RawWriter;

/// Copies a log through the reader and the raw writer: every framed message is
/// re-emitted from its parts (type and payload), and every byte between messages
/// (corruption, a partial message before appended data, a truncated tail) is copied
/// verbatim, so the output equals the input byte for byte.
///
/// Returns how many messages were re-emitted. Fails only where the reader refuses the
/// log (not ULog, unknown incompatibility flags: [`WriteErrorKind::Unreadable`]) or
/// writing fails.
///
/// [`WriteErrorKind::Unreadable`]: crate::write::WriteErrorKind::Unreadable
///
/// ```
/// let bytes = ulog_core::testing::sample_log();
/// let mut out = Vec::new();
/// ulog_core::copy_log(&bytes, &mut out)?;
/// assert_eq!(out, bytes);
/// # Ok::<(), ulog_core::WriteError>(())
/// ```
pub fn copy_log<W: Write>(data: &[u8], out: W) -> Result<u64, WriteError> {
    let mut w = RawWriter::new(out);
    let mut messages = Messages::new(data);
    let mut at = 0usize;
    let mut count = 0u64;
    for m in messages.by_ref() {
        let m = m.map_err(WriteError::unreadable)?;
        if at == 0 {
            w.bytes(&data[..HEADER_SIZE])?;
            at = HEADER_SIZE;
        }
        let start = m.offset as usize;
        if start > at {
            w.bytes(&data[at..start])?;
        }
        let size = usize::from(u16_at(data, start));
        let payload = &data[start + MESSAGE_HEADER_SIZE..start + MESSAGE_HEADER_SIZE + size];
        w.message(m.message.msg_type(), &[payload])?;
        at = start + MESSAGE_HEADER_SIZE + size;
        count += 1;
    }
    if at == 0 {
        // A log without messages: validate its header the same way, then copy it.
        ULog::parse(data).map_err(WriteError::unreadable)?;
    }
    w.bytes(&data[at..])?;
    w.flush()?;
    Ok(count)
}
