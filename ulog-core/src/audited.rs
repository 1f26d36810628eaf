//! The crate's `unsafe` code, each block with the argument that makes it sound: a
//! memory map, a prefetch hint, and the cast behind typed views (with the unsafe
//! marker trait it rests on). The rest of the crate is `#![deny(unsafe_code)]`; the
//! one exception is `LogFile::map`, an `unsafe fn` whose call of [`map`] passes the
//! map's contract on to its caller.

/// Asks the processor for the cache line holding `bytes[at]`, which will be read soon
/// (nothing if `at` is past the end, or on targets other than x86_64). Framing asks
/// for the bytes a little ahead of each data message it frames; BENCHMARKS.md and
/// bench/README.md have what it saves.
#[inline(always)]
pub(crate) fn prefetch(bytes: &[u8], at: usize) {
    #[cfg(target_arch = "x86_64")]
    if at < bytes.len() {
        // SAFETY: `_mm_prefetch` needs SSE, which every x86_64 processor has; the
        // address is inside `bytes`, and a prefetch reads nothing into the program
        // (it cannot fault or change memory).
        unsafe {
            use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
            _mm_prefetch::<_MM_HINT_T0>(bytes.as_ptr().add(at).cast::<i8>());
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = (bytes, at);
}

/// Asks for the cache lines holding `bytes[at..at + len]` (what is inside `bytes`).
#[inline(always)]
pub(crate) fn prefetch_span(bytes: &[u8], at: usize, len: usize) {
    let end = at.saturating_add(len).min(bytes.len());
    let mut a = at;
    while a < end {
        prefetch(bytes, a);
        a += 64;
    }
    if end > at {
        prefetch(bytes, end - 1);
    }
}

/// Maps `file` read-only.
///
/// # Safety
///
/// The file must not be truncated or written while the map lives (see
/// [`LogFile::map`](crate::LogFile::map), whose contract this is).
#[cfg(feature = "mmap")]
pub(crate) unsafe fn map(file: &std::fs::File) -> std::io::Result<memmap2::Mmap> {
    // SAFETY: read-only; that the file does not change while it is mapped is the
    // caller's contract, passed on from `LogFile::map`.
    unsafe { memmap2::Mmap::map(file) }
}

/// A binding whose memory is its wire image, so that payload bytes can be borrowed as
/// it ([`TypedRows::views`](crate::TypedRows::views), [`Plan::view`](crate::typed::Plan::view)).
/// The readers also require its `WireField::IS_WIRE` to be true (a compile error
/// otherwise).
///
/// Implement it with `#[derive(ULogMessage)]`, `#[ulog(view)]` and `#[repr(C)]`: the
/// derive also checks, at compile time, that the struct is its wire image (fields of
/// `u8`, `i8`, [`CharArray<N>`](crate::typed::CharArray), the [`le`](crate::typed::le)
/// types, arrays of these and nested such bindings, in declaration order), and fails
/// to compile otherwise.
///
/// # Safety
///
/// Every value of `Self` must be exactly its wire image: alignment 1, the size of its
/// payload bytes, every bit pattern of those bytes a valid value, no interior
/// mutability.
pub unsafe trait WireImage {}

/// Borrows the first `size_of::<T>()` bytes of `bytes` as a `T`.
///
/// # Panics
/// If `bytes` is shorter: callers check it first and report it as an error.
pub(crate) fn view<T: WireImage>(bytes: &[u8]) -> &T {
    let size = core::mem::size_of::<T>();
    let bytes = &bytes[..size];
    // SAFETY: `T: WireImage`, whose implementer promises that every value of `T` is
    // exactly its wire image: `T` has alignment 1, its size is `size` bytes, every
    // bit pattern of those bytes is a valid `T`, and it has no interior mutability.
    // (The derive implements it only after checking, at compile time, each field's
    // own `IS_WIRE` and offset.) `bytes` has `size` bytes (the slice above panics
    // otherwise). So the pointer is aligned, the `size` bytes behind it
    // are initialised and valid for `T`, and the shared borrow of `bytes` keeps them
    // alive and unchanged for the returned lifetime.
    unsafe { &*bytes.as_ptr().cast::<T>() }
}
