//! Text as a JSON string: the one escaper of the JSON this crate writes by hand (a
//! dataset's `metadata.json`, MCAP's JSON messages and their schemas).

use core::fmt::Write as _;

/// Appends `chars` to `out` as a JSON string, quotes included: `"` and `\` escaped,
/// line breaks and tabs as `\n`, `\r`, `\t`, every other control character (C0, DEL,
/// C1) as `\u00XX`, so that the text reads back the same and holds no control
/// character raw. (Text that was not UTF-8 reaches here as U+FFFD, or one character
/// per byte where the caller reads it so.)
pub(crate) fn push_string(out: &mut String, chars: impl IntoIterator<Item = char>) {
    out.push('"');
    for c in chars {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\r' => out.push_str("\\r"),
            '\t' => out.push_str("\\t"),
            c if c.is_control() => {
                let _ = write!(out, "\\u{:04x}", c as u32);
            }
            c => out.push(c),
        }
    }
    out.push('"');
}

#[cfg(test)]
mod tests {
    #[test]
    fn strings_escape_quotes_and_every_control_character() {
        let mut s = String::new();
        super::push_string(&mut s, "a\"b\\c\n\t\r\u{1}\u{1f}\u{7f}\u{85}é<".chars());
        assert_eq!(s, r#""a\"b\\c\n\t\r\u0001\u001f\u007f\u0085é<""#);
    }
}
