//! Reading from a [`Read`] source.

use std::io::Read;

/// One read into `buf`, retried while it is interrupted (`ErrorKind::Interrupted`
/// says to try again; nothing was read).
pub(crate) fn read_some(src: &mut impl Read, buf: &mut [u8]) -> std::io::Result<usize> {
    loop {
        match src.read(buf) {
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
            other => return other,
        }
    }
}
