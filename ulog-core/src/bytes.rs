//! Little-endian reads from the file's bytes, and the sizes of its fixed parts (from
//! `ulog-format`, which the derive macros read logs with too).

pub(crate) use ulog_format::definitions::{HEADER_SIZE, MAGIC, MESSAGE_HEADER_SIZE, SYNC_MAGIC};

/// The `u16` at `b[i..i + 2]`.
///
/// # Panics
/// If `b` is shorter: callers read what framing has checked to be there.
#[inline(always)]
pub(crate) fn u16_at(b: &[u8], i: usize) -> u16 {
    u16::from_le_bytes([b[i], b[i + 1]])
}

/// The `u64` at `b[i..i + 8]` (panics as [`u16_at`]).
#[inline(always)]
pub(crate) fn u64_at(b: &[u8], i: usize) -> u64 {
    let mut a = [0u8; 8];
    a.copy_from_slice(&b[i..i + 8]);
    u64::from_le_bytes(a)
}

/// The payload of the data message whose 3-byte header is at `offset` of `data`,
/// after its 2-byte msg_id (framing has checked that it is all there).
#[inline(always)]
pub(crate) fn data_payload_at(data: &[u8], offset: u64) -> &[u8] {
    let o = offset as usize;
    let size = usize::from(u16_at(data, o));
    &data[o + MESSAGE_HEADER_SIZE + 2..o + MESSAGE_HEADER_SIZE + size]
}
