//! Text put into XML and HTML documents (KML, GPX, SVG plots, the flight report): the
//! one place that decides what these formats can hold.
//!
//! Log text can hold any byte. XML 1.0 cannot hold the C0 control characters other
//! than tab, line feed and carriage return, not even as character references, nor
//! U+FFFE and U+FFFF; HTML takes every control character and noncharacter for a parse
//! error. Such characters become U+FFFD (as bytes that are not UTF-8 already are), so
//! that every document written parses, and the rest of the text stays.

use std::borrow::Cow;

/// `s` with `&`, `<`, `>`, `"` and `'` escaped and the characters XML or HTML cannot
/// hold replaced ([`plain`]): safe in element content and in attribute values of XML
/// and HTML.
pub fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            c if unfit(c) => out.push(char::REPLACEMENT_CHARACTER),
            c => out.push(c),
        }
    }
    out
}

/// `s` with the characters XML or HTML cannot hold replaced by U+FFFD, for a writer
/// that escapes markup itself (the SVG backend).
pub fn plain(s: &str) -> Cow<'_, str> {
    if !s.chars().any(unfit) {
        return Cow::Borrowed(s);
    }
    Cow::Owned(
        s.chars()
            .map(|c| match unfit(c) {
                true => char::REPLACEMENT_CHARACTER,
                false => c,
            })
            .collect(),
    )
}

/// Whether XML 1.0 or HTML cannot hold `c` as text: a control character other than
/// tab, line feed and carriage return (C0, DEL, C1), or a noncharacter.
pub fn unfit(c: char) -> bool {
    let n = c as u32;
    (c.is_control() && !matches!(c, '\t' | '\n' | '\r'))
        || (0xFDD0..=0xFDEF).contains(&n)
        || n & 0xFFFE == 0xFFFE
}

/// A `data:` URI of `bytes` with media type `mime`, in base64 (RFC 2397): a link
/// that downloads them from the page itself.
pub fn data_uri(mime: &str, bytes: &[u8]) -> String {
    const DIGITS: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::with_capacity(mime.len() + 13 + bytes.len().div_ceil(3) * 4);
    out.push_str("data:");
    out.push_str(mime);
    out.push_str(";base64,");
    for chunk in bytes.chunks(3) {
        let mut group = [0u8; 3];
        group[..chunk.len()].copy_from_slice(chunk);
        let n = u32::from_be_bytes([0, group[0], group[1], group[2]]);
        for i in 0..4 {
            // A chunk of k bytes gives k + 1 digits, then `=` to four.
            if i <= chunk.len() {
                out.push(char::from(DIGITS[(n >> (18 - 6 * i)) as usize & 63]));
            } else {
                out.push('=');
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn markup_is_escaped_and_what_cannot_be_held_replaced() {
        assert_eq!(escape("a<b>&\"'"), "a&lt;b&gt;&amp;&quot;&apos;");
        assert_eq!(escape("a\u{1}b\u{1f}c\u{7f}d\u{85}e"), "a�b�c�d�e");
        assert_eq!(escape("tab\tline\nret\r"), "tab\tline\nret\r");
        assert_eq!(escape("\u{fffe}\u{ffff}\u{fdd0}\u{1fffe}é😀"), "����é😀");
        assert!(matches!(
            plain("plain <text>"),
            Cow::Borrowed("plain <text>")
        ));
        assert_eq!(plain("x\u{0}y"), "x�y");
    }

    #[test]
    fn data_uris_are_base64() {
        // RFC 4648's test vectors.
        for (raw, b64) in [
            ("", ""),
            ("f", "Zg=="),
            ("fo", "Zm8="),
            ("foo", "Zm9v"),
            ("foob", "Zm9vYg=="),
            ("fooba", "Zm9vYmE="),
            ("foobar", "Zm9vYmFy"),
        ] {
            assert_eq!(
                data_uri("text/plain", raw.as_bytes()),
                format!("data:text/plain;base64,{b64}")
            );
        }
        assert_eq!(data_uri("x/y", &[0xff, 0xfe]), "data:x/y;base64,//4=");
    }
}
