//! `CharArray<N>`: a ULog `char[N]` string held in place; `ByteBool`: a ULog `bool` held
//! as its byte.

use core::fmt;

use zerocopy::{FromBytes, Immutable, IntoBytes, KnownLayout, Unaligned};

/// A ULog `char[N]` field: `N` bytes of text, not NUL-terminated, padded with NULs
/// when shorter (PX4 writes the text up to its length and zeroes the rest).
///
/// ```
/// use ulog_core::typed::CharArray;
///
/// let name = CharArray::<8>::from_str_truncated("PX4");
/// assert_eq!(name.as_str(), Ok("PX4"));
/// assert_eq!(name.as_bytes(), b"PX4\0\0\0\0\0");
/// let bad = CharArray::from_bytes([b'o', b'k', 0xff, 0]);
/// assert_eq!(bad.to_string_lossy(), "ok\u{fffd}");
/// ```
#[derive(
    Clone,
    Copy,
    PartialEq,
    Eq,
    Hash,
    PartialOrd,
    Ord,
    FromBytes,
    IntoBytes,
    KnownLayout,
    Immutable,
    Unaligned,
)]
#[repr(transparent)]
pub struct CharArray<const N: usize>(pub [u8; N]);

impl<const N: usize> CharArray<N> {
    /// The bytes as stored, all `N` of them.
    pub const fn from_bytes(bytes: [u8; N]) -> CharArray<N> {
        CharArray(bytes)
    }

    /// Text cut to at most `N` bytes (at a character boundary) and NUL-padded.
    pub fn from_str_truncated(text: &str) -> CharArray<N> {
        let mut end = text.len().min(N);
        while !text.is_char_boundary(end) {
            end -= 1;
        }
        let mut bytes = [0u8; N];
        bytes[..end].copy_from_slice(&text.as_bytes()[..end]);
        CharArray(bytes)
    }

    /// All `N` bytes, NUL padding included.
    pub const fn as_bytes(&self) -> &[u8; N] {
        &self.0
    }

    /// The text bytes: everything before the first NUL (or all `N` bytes).
    pub fn text_bytes(&self) -> &[u8] {
        text_bytes(&self.0)
    }

    /// The text, if it is UTF-8.
    pub fn as_str(&self) -> Result<&str, core::str::Utf8Error> {
        core::str::from_utf8(self.text_bytes())
    }

    /// The text, with invalid UTF-8 replaced by U+FFFD.
    pub fn to_string_lossy(&self) -> std::borrow::Cow<'_, str> {
        String::from_utf8_lossy(self.text_bytes())
    }
}

/// The text of a `char[N]`'s bytes: everything before the first NUL (or all of them).
pub(crate) fn text_bytes(bytes: &[u8]) -> &[u8] {
    let end = bytes.iter().position(|&b| b == 0).unwrap_or(bytes.len());
    &bytes[..end]
}

impl<const N: usize> Default for CharArray<N> {
    fn default() -> CharArray<N> {
        CharArray([0; N])
    }
}

impl<const N: usize> fmt::Debug for CharArray<N> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Debug::fmt(&self.to_string_lossy(), f)
    }
}

impl<const N: usize> fmt::Display for CharArray<N> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.to_string_lossy())
    }
}

impl<const N: usize> From<[u8; N]> for CharArray<N> {
    fn from(bytes: [u8; N]) -> CharArray<N> {
        CharArray(bytes)
    }
}

/// A ULog `bool` held as its byte, for bindings borrowed from payloads (a Rust `bool`
/// cannot hold every byte a log may have): any byte but 0 is true, as in PX4.
///
/// ```
/// use ulog_core::typed::ByteBool;
/// assert!(ByteBool(2).get());
/// assert_eq!(ByteBool::from(false), ByteBool(0));
/// ```
#[derive(
    Clone,
    Copy,
    PartialEq,
    Eq,
    Hash,
    Default,
    FromBytes,
    IntoBytes,
    KnownLayout,
    Immutable,
    Unaligned,
)]
#[repr(transparent)]
pub struct ByteBool(pub u8);

impl ByteBool {
    /// The value: any byte but 0 is true.
    pub const fn get(self) -> bool {
        self.0 != 0
    }
}

impl From<bool> for ByteBool {
    fn from(v: bool) -> ByteBool {
        ByteBool(u8::from(v))
    }
}

impl fmt::Debug for ByteBool {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Debug::fmt(&self.get(), f)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn truncates_at_char_boundaries_and_stops_at_nul() {
        let c = CharArray::<4>::from_str_truncated("aé€");
        assert_eq!(c.as_str(), Ok("aé"));
        assert_eq!(CharArray::<3>::from_bytes(*b"abc").as_str(), Ok("abc"));
        assert_eq!(CharArray::<3>::default().as_str(), Ok(""));
        assert_eq!(
            format!("{:?}", CharArray::<3>::from_bytes(*b"a\0c")),
            "\"a\""
        );
    }
}
