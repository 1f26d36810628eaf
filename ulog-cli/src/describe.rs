//! How findings, message types and values are named in text and JSON output, shared by
//! the commands.

use serde_json::Value as Json;
use ulog_core::read::{Corruption, FindingKind};
use ulog_core::{Finding, Value};

/// A message type byte as text: `'D'`, or `0x07` when not printable.
pub fn type_name(t: u8) -> String {
    if t.is_ascii_graphic() {
        format!("'{}'", t as char)
    } else {
        format!("{t:#04x}")
    }
}

/// A stable name for each kind of finding (see the `--json` keys).
pub fn kind_name(f: &Finding) -> &'static str {
    match &f.kind {
        FindingKind::NewerVersion(_) => "newer_version",
        FindingKind::MisplacedFlagBits => "misplaced_flag_bits",
        FindingKind::LongFlagBits(_) => "long_flag_bits",
        FindingKind::UnknownCompatFlags { .. } => "unknown_compat_flags",
        FindingKind::InvalidAppendedOffset(_) => "invalid_appended_offset",
        FindingKind::AppendedFlagWithoutOffsets => "appended_flag_without_offsets",
        FindingKind::AppendedOffsetsWithoutFlag => "appended_offsets_without_flag",
        FindingKind::AppendedData => "appended_data",
        FindingKind::PartialBeforeAppended => "partial_before_appended",
        FindingKind::Truncated => "truncated",
        FindingKind::Corrupt(Corruption::ZeroSize) => "corrupt_zero_size",
        FindingKind::Corrupt(Corruption::BadHeader) => "corrupt_bad_header",
        FindingKind::Corrupt(Corruption::ZeroFill) => "corrupt_zero_fill",
        FindingKind::Corrupt(Corruption::Overrun) => "corrupt_overrun",
        FindingKind::Corrupt(Corruption::CutByZeroFill) => "corrupt_cut_by_zero_fill",
        FindingKind::UnknownMessageType(_) => "unknown_message_type",
        FindingKind::UnknownMsgId(_) => "unknown_msg_id",
        FindingKind::SizeMismatch { .. } => "size_mismatch",
        FindingKind::Malformed { .. } => "malformed",
        FindingKind::InvalidFormat(_) => "invalid_format",
        FindingKind::Layout(_) => "layout",
        FindingKind::RedefinedFormat(_) => "redefined_format",
        FindingKind::UnknownFormat(_) => "unknown_format",
        FindingKind::InvalidKey => "invalid_key",
        FindingKind::NoTimestamp(_) => "no_timestamp",
        _ => "other",
    }
}

/// A value as JSON: numbers as numbers (non-finite floats as null), text as strings,
/// arrays as arrays, undecodable bytes as an array of numbers.
pub fn value_json(v: &Value<'_>) -> Json {
    match v {
        Value::Str(s) => Json::String(s.to_string_lossy().into_owned()),
        Value::Array(a) => Json::Array(a.iter().map(|x| value_json(&x)).collect()),
        Value::Bytes(b) => Json::Array(b.iter().map(|&x| Json::from(x)).collect()),
        Value::Bool(b) => Json::Bool(*b),
        // The shortest decimal that reads back as the same f32 (0.1, not
        // 0.10000000149011612), as a JSON number.
        Value::F32(f) => f
            .to_string()
            .parse::<f64>()
            .ok()
            .and_then(serde_json::Number::from_f64)
            .map_or(Json::Null, Json::Number),
        Value::F64(f) => serde_json::Number::from_f64(*f).map_or(Json::Null, Json::Number),
        other => match (other.as_u64(), other.as_i128()) {
            (Some(u), _) => Json::from(u),
            (None, Some(i)) => i64::try_from(i).map_or(Json::Null, Json::from),
            _ => Json::Null,
        },
    }
}

/// What a run of bytes holds, told by the magic number it starts with.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BytesKind {
    /// What it is, in words (`xz-compressed data`).
    pub name: &'static str,
    /// Its media type.
    pub mime: &'static str,
    /// A file name extension for it.
    pub extension: &'static str,
}

/// Well-known magic numbers: the bytes a format starts with, and what it is.
const MAGIC_NUMBERS: &[(&[u8], BytesKind)] = &[
    (
        b"\xfd7zXZ\x00",
        kind("xz-compressed data", "application/x-xz", "xz"),
    ),
    (
        b"\x1f\x8b",
        kind("gzip-compressed data", "application/gzip", "gz"),
    ),
    (
        b"\x28\xb5\x2f\xfd",
        kind("zstd-compressed data", "application/zstd", "zst"),
    ),
    (
        b"BZh",
        kind("bzip2-compressed data", "application/x-bzip2", "bz2"),
    ),
    (
        b"\x04\x22\x4d\x18",
        kind("LZ4-compressed data", "application/x-lz4", "lz4"),
    ),
    (
        b"7z\xbc\xaf\x27\x1c",
        kind("7-Zip archive", "application/x-7z-compressed", "7z"),
    ),
    (b"PK\x03\x04", kind("ZIP archive", "application/zip", "zip")),
    (b"\x89PNG\r\n\x1a\n", kind("PNG image", "image/png", "png")),
    (b"\xff\xd8\xff", kind("JPEG image", "image/jpeg", "jpg")),
    (b"%PDF-", kind("PDF document", "application/pdf", "pdf")),
    (
        b"\x7fELF",
        kind("ELF executable", "application/octet-stream", "elf"),
    ),
    (
        b"ULog\x01\x12\x35",
        kind("ULog log", "application/octet-stream", "ulg"),
    ),
];

const fn kind(name: &'static str, mime: &'static str, extension: &'static str) -> BytesKind {
    BytesKind {
        name,
        mime,
        extension,
    }
}

/// Bytes of no kind [`bytes_kind`] knows.
pub const BINARY: BytesKind = kind("binary data", "application/octet-stream", "bin");

/// What `bytes` hold, by the magic number they start with; `None` for none known.
pub fn bytes_kind(bytes: &[u8]) -> Option<BytesKind> {
    MAGIC_NUMBERS
        .iter()
        .find(|(magic, _)| bytes.starts_with(magic))
        .map(|(_, k)| *k)
}

/// `n` with a comma between groups of three digits (`47,052`).
pub fn thousands(n: usize) -> String {
    let digits = n.to_string();
    let mut out = String::with_capacity(digits.len() + digits.len() / 3);
    for (i, d) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i) % 3 == 0 {
            out.push(',');
        }
        out.push(d);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bytes_are_told_by_their_magic_number() {
        let xz = bytes_kind(b"\xfd7zXZ\x00\x00\x04");
        assert_eq!(xz.map(|k| k.name), Some("xz-compressed data"));
        assert_eq!(bytes_kind(b"\x1f\x8b\x08").map(|k| k.extension), Some("gz"));
        assert_eq!(
            bytes_kind(b"ULog\x01\x12\x35\x01").map(|k| k.name),
            Some("ULog log")
        );
        assert_eq!(bytes_kind(b"\xfd7z"), None);
        assert_eq!(bytes_kind(b""), None);
    }

    #[test]
    fn thousands_are_grouped() {
        assert_eq!(thousands(0), "0");
        assert_eq!(thousands(999), "999");
        assert_eq!(thousands(1000), "1,000");
        assert_eq!(thousands(47_052), "47,052");
        assert_eq!(thousands(1_234_567), "1,234,567");
    }
}
