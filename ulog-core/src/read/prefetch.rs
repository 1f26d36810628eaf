//! A hint to the processor that bytes a little further on in a window will be read
//! soon.
//!
//! The framing loop asks for the bytes 2 KiB ahead of each data message it frames.
//! Measured over a memory map of the ≈300 MB logs of `bench/` (the smallest of 48
//! in-process passes each), it took 0.91–0.92× the time of a scan that decodes every
//! value, 0.96–0.97× of `ULog::parse`, and 1.04–1.06× of a scan that only counts the
//! messages. Over a buffer in memory, `ULog::parse` took 1.11× (`cargo bench -p
//! ulog-benches --bench read`); a scan of a reader, whose window was just copied in,
//! was unchanged. Asking only when the line ahead changes cost more than it saved.

/// Asks for the cache line holding `bytes[at]` (nothing if `at` is past the end, or on
/// targets other than x86_64).
#[inline(always)]
pub(crate) fn prefetch(bytes: &[u8], at: usize) {
    #[cfg(target_arch = "x86_64")]
    if at < bytes.len() {
        // SAFETY: `_mm_prefetch` needs SSE, which every x86_64 processor has; the
        // address is inside `bytes`, and a prefetch reads nothing into the program
        // (it cannot fault or change memory).
        #[allow(unsafe_code)]
        unsafe {
            use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
            _mm_prefetch::<_MM_HINT_T0>(bytes.as_ptr().add(at).cast::<i8>());
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = (bytes, at);
}
