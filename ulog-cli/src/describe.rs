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
