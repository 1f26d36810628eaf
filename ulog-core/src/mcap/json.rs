//! JSON messages and their JSON Schemas, for tools without CDR: a topic's message is
//! an object of its fields by their names in the log (padding and zero-length arrays
//! left out), arrays as arrays, nested formats as objects, `char[N]` as the text up
//! to its first NUL (one character per byte, ISO 8859-1), and floats in their shortest
//! round-trip form, `null` for NaN and infinities (JSON has no number for them). Text is
//! escaped as `crate::json_text` escapes it (control characters as `\uXXXX`), so that a
//! JSON reader gets it unchanged.

use std::fmt::Write as _;

use ulog_format::{BasicType, Layout, LayoutType};

use super::schema::members;

/// The JSON Schema (draft 2020-12) of a topic's messages, titled with its type name.
pub(crate) fn json_schema(layout: &Layout, title: &str) -> String {
    let mut s = String::new();
    s.push_str("{\"$schema\":\"https://json-schema.org/draft/2020-12/schema\",\"title\":");
    crate::json_text::push_string(&mut s, title.chars());
    s.push(',');
    object_schema_body(layout, &mut s);
    s.push('}');
    s
}

fn object_schema(layout: &Layout, s: &mut String) {
    s.push('{');
    object_schema_body(layout, s);
    s.push('}');
}

fn object_schema_body(layout: &Layout, s: &mut String) {
    s.push_str("\"type\":\"object\",\"properties\":{");
    let mut names = String::new();
    for (i, f) in members(layout).enumerate() {
        if i > 0 {
            s.push(',');
            names.push(',');
        }
        crate::json_text::push_string(s, f.name.chars());
        s.push(':');
        crate::json_text::push_string(&mut names, f.name.chars());
        match (&f.ty, f.array_len) {
            (LayoutType::Basic(BasicType::Char), Some(n)) => {
                let _ = write!(s, "{{\"type\":\"string\",\"maxLength\":{n}}}");
            }
            (ty, Some(n)) => {
                let _ = write!(
                    s,
                    "{{\"type\":\"array\",\"minItems\":{n},\"maxItems\":{n},\"items\":"
                );
                item_schema(ty, s);
                s.push('}');
            }
            (ty, None) => item_schema(ty, s),
        }
    }
    let _ = write!(
        s,
        "}},\"required\":[{names}],\"additionalProperties\":false"
    );
}

fn item_schema(ty: &LayoutType, s: &mut String) {
    match ty {
        LayoutType::Nested(inner) => object_schema(inner, s),
        LayoutType::Basic(b) => {
            let (min, max): (i128, i128) = match b {
                BasicType::Int8 => (i8::MIN.into(), i8::MAX.into()),
                BasicType::UInt8 | BasicType::Char => (0, u8::MAX.into()),
                BasicType::Int16 => (i16::MIN.into(), i16::MAX.into()),
                BasicType::UInt16 => (0, u16::MAX.into()),
                BasicType::Int32 => (i32::MIN.into(), i32::MAX.into()),
                BasicType::UInt32 => (0, u32::MAX.into()),
                BasicType::Int64 => (i64::MIN.into(), i64::MAX.into()),
                BasicType::UInt64 => (0, u64::MAX.into()),
                BasicType::Float | BasicType::Double => {
                    s.push_str("{\"type\":[\"number\",\"null\"]}");
                    return;
                }
                BasicType::Bool => {
                    s.push_str("{\"type\":\"boolean\"}");
                    return;
                }
            };
            let _ = write!(
                s,
                "{{\"type\":\"integer\",\"minimum\":{min},\"maximum\":{max}}}"
            );
        }
    }
}

/// Writes the JSON message of `payload` into `out` (cleared first); `None` when the
/// payload is shorter than its fields.
pub(crate) fn encode_json(layout: &Layout, payload: &[u8], out: &mut Vec<u8>) -> Option<()> {
    // The buffer's memory is reused from message to message: it holds UTF-8 (the
    // messages written) or nothing.
    let mut s = String::from_utf8(std::mem::take(out)).unwrap_or_default();
    s.clear();
    let done = object(layout, payload, 0, &mut s);
    *out = s.into_bytes();
    done
}

fn object(layout: &Layout, p: &[u8], base: usize, s: &mut String) -> Option<()> {
    s.push('{');
    for (i, f) in members(layout).enumerate() {
        if i > 0 {
            s.push(',');
        }
        // Written as they are, message after message: the format grammar gives field
        // names only ASCII letters, digits and `_`, which JSON strings hold unescaped
        // (the schema, written once, escapes them all the same).
        let _ = write!(s, "\"{}\":", f.name);
        let at = base + f.offset;
        match (&f.ty, f.array_len) {
            (LayoutType::Basic(BasicType::Char), Some(n)) => {
                let bytes = p.get(at..at + n)?;
                let end = bytes.iter().position(|&b| b == 0).unwrap_or(n);
                string(&bytes[..end], s);
            }
            (ty, Some(n)) => {
                s.push('[');
                for k in 0..n {
                    if k > 0 {
                        s.push(',');
                    }
                    value(ty, p, at + k * ty.size(), s)?;
                }
                s.push(']');
            }
            (ty, None) => value(ty, p, at, s)?,
        }
    }
    s.push('}');
    Some(())
}

fn value(ty: &LayoutType, p: &[u8], at: usize, s: &mut String) -> Option<()> {
    let b = match ty {
        LayoutType::Nested(inner) => return object(inner, p, at, s),
        LayoutType::Basic(b) => *b,
    };
    let bytes = p.get(at..at + b.size())?;
    let mut a = [0u8; 8];
    a[..bytes.len()].copy_from_slice(bytes);
    let u = u64::from_le_bytes(a);
    let _ = match b {
        BasicType::Int8 => write!(s, "{}", u as u8 as i8),
        BasicType::Int16 => write!(s, "{}", u as u16 as i16),
        BasicType::Int32 => write!(s, "{}", u as u32 as i32),
        BasicType::Int64 => write!(s, "{}", u as i64),
        BasicType::Bool => write!(s, "{}", u != 0),
        BasicType::Float => finite(f32::from_bits(u as u32), s),
        BasicType::Double => finite(f64::from_bits(u), s),
        _ => write!(s, "{u}"),
    };
    Some(())
}

/// A float in its shortest form (Rust's `Debug`: `0.1`, `1e-7`, `3.0`), `null` if not
/// finite.
fn finite<F: std::fmt::Debug + Into<f64> + Copy>(v: F, s: &mut String) -> std::fmt::Result {
    if v.into().is_finite() {
        write!(s, "{v:?}")
    } else {
        s.push_str("null");
        Ok(())
    }
}

/// A JSON string of bytes read one character per byte (ISO 8859-1).
fn string(bytes: &[u8], s: &mut String) {
    crate::json_text::push_string(s, bytes.iter().map(|&b| char::from(b)));
}

#[cfg(test)]
mod tests {
    use super::*;
    use ulog_format::Format;

    #[test]
    fn messages_are_objects_by_field_name() {
        let formats: Vec<Format> = [
            "inner:int16_t v;char[4] name;",
            "outer:uint64_t timestamp;float x;double[2] d;bool ok;uint8_t[1] _padding0;inner[2] items;",
        ]
        .iter()
        .map(|f| Format::parse(f).unwrap())
        .collect();
        let layout = Layout::resolve("outer", &formats[..]).unwrap();
        let mut p = 7u64.to_le_bytes().to_vec();
        p.extend_from_slice(&0.1f32.to_le_bytes());
        p.extend_from_slice(&f64::NAN.to_le_bytes());
        p.extend_from_slice(&(-2.5f64).to_le_bytes());
        p.extend_from_slice(&[1, 0]);
        p.extend_from_slice(&(-3i16).to_le_bytes());
        p.extend_from_slice(b"a\"\xe9\0");
        p.extend_from_slice(&4i16.to_le_bytes());
        p.extend_from_slice(b"xyzw");
        let mut out = Vec::new();
        encode_json(&layout, &p, &mut out).unwrap();
        assert_eq!(
            String::from_utf8(out).unwrap(),
            r#"{"timestamp":7,"x":0.1,"d":[null,-2.5],"ok":true,"items":[{"v":-3,"name":"a\"é"},{"v":4,"name":"xyzw"}]}"#
        );
        let schema = json_schema(&layout, "px4_msgs/msg/Outer");
        assert!(schema.contains(r#""d":{"type":"array","minItems":2,"maxItems":2,"items":{"type":["number","null"]}}"#), "{schema}");
        assert!(
            schema.contains(r#""name":{"type":"string","maxLength":4}"#),
            "{schema}"
        );
        assert!(!schema.contains("_padding0"), "{schema}");
    }
}
