//! Values printed the way pyulog's scripts print them: Python's `str()` and `repr()` of
//! what pyulog decodes, and numpy's shortest float form, written into reused buffers.

use core::fmt::Write as _;

pub use crate::numfmt::{
    format_i64, format_numpy_f32, format_numpy_f64, format_u64, write_numpy_f32, write_numpy_f64,
    NUM_LEN,
};
use ulog_core::Value;

/// Python's `str()` of the value pyulog decodes for an information or parameter key:
/// integers in decimal, `float` widened to a Python float (a double) and shown in
/// `repr` form, `bool` as `True`/`False`, `char[N]` as its text, anything else as
/// Python shows `bytes`.
pub fn py_str(v: &Value<'_>) -> String {
    match v {
        Value::Str(s) => s.to_string_lossy().into_owned(),
        _ => py_repr(v),
    }
}

/// Python's `repr()` of the same value (strings quoted and escaped).
pub fn py_repr(v: &Value<'_>) -> String {
    match v {
        Value::F32(f) => py_float(f64::from(*f)),
        Value::F64(f) => py_float(*f),
        Value::Bool(b) => if *b { "True" } else { "False" }.to_owned(),
        Value::Char(c) => py_bytes_repr(&[*c]),
        Value::Str(s) => py_str_repr(&s.to_string_lossy()),
        Value::Array(a) => py_bytes_repr(a.as_bytes()),
        Value::Bytes(b) => py_bytes_repr(b),
        other => other.to_string(),
    }
}

/// A value as pyulog's tables print it: integers in decimal, floats in numpy's
/// shortest form, booleans as `1`/`0` (pyulog keeps them as `int8`), a `char` as its
/// signed byte, strings as (lossy) text, arrays as `[a, b]`, undecodable bytes in hex.
pub fn value_text(v: &Value<'_>) -> String {
    let mut out = Vec::new();
    push_value(&mut out, v);
    String::from_utf8(out).unwrap_or_default()
}

fn push_value(out: &mut Vec<u8>, v: &Value<'_>) {
    match v {
        Value::F32(f) => write_numpy_f32(out, *f),
        Value::F64(f) => write_numpy_f64(out, *f),
        Value::Bool(b) => out.push(if *b { b'1' } else { b'0' }),
        Value::Char(c) => out.extend_from_slice((*c as i8).to_string().as_bytes()),
        Value::Str(s) => out.extend_from_slice(s.to_string_lossy().as_bytes()),
        Value::Array(a) => {
            out.push(b'[');
            for (i, x) in a.iter().enumerate() {
                if i > 0 {
                    out.extend_from_slice(b", ");
                }
                push_value(out, &x);
            }
            out.push(b']');
        }
        Value::Bytes(b) => {
            for x in *b {
                out.extend_from_slice(format!("{x:02x}").as_bytes());
            }
        }
        other => out.extend_from_slice(other.to_string().as_bytes()),
    }
}

/// Python's `repr()` of a float (the same rules as numpy's shortest form).
pub fn py_float(f: f64) -> String {
    let mut out = Vec::new();
    write_numpy_f64(&mut out, f);
    String::from_utf8(out).expect("ascii")
}

/// Python's `repr()` of a `str`.
pub fn py_str_repr(s: &str) -> String {
    let quote = if s.contains('\'') && !s.contains('"') {
        '"'
    } else {
        '\''
    };
    let mut out = String::with_capacity(s.len() + 2);
    out.push(quote);
    for c in s.chars() {
        match c {
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\r' => out.push_str("\\r"),
            '\t' => out.push_str("\\t"),
            c if c == quote => {
                out.push('\\');
                out.push(c);
            }
            c if (c as u32) < 0x20 || (0x7f..0xa0).contains(&(c as u32)) => {
                let _ = write!(out, "\\x{:02x}", c as u32);
            }
            c => out.push(c),
        }
    }
    out.push(quote);
    out
}

/// Python's `repr()` of `bytes`.
pub fn py_bytes_repr(b: &[u8]) -> String {
    let quote = if b.contains(&b'\'') && !b.contains(&b'"') {
        b'"'
    } else {
        b'\''
    };
    let mut out = String::from("b");
    out.push(quote as char);
    for &x in b {
        match x {
            b'\\' => out.push_str("\\\\"),
            b'\n' => out.push_str("\\n"),
            b'\r' => out.push_str("\\r"),
            b'\t' => out.push_str("\\t"),
            x if x == quote => {
                out.push('\\');
                out.push(x as char);
            }
            0x20..=0x7e => out.push(x as char),
            x => {
                let _ = write!(out, "\\x{x:02x}");
            }
        }
    }
    out.push(quote as char);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn python_reprs() {
        assert_eq!(py_str_repr("it's"), "\"it's\"");
        assert_eq!(py_str_repr("a\tb\\"), "'a\\tb\\\\'");
        assert_eq!(py_bytes_repr(b"a\x00'"), "b\"a\\x00'\"");
        assert_eq!(py_repr(&Value::Bool(true)), "True");
        assert_eq!(py_str(&Value::I32(-3)), "-3");
        assert_eq!(py_str(&Value::F32(12.0)), "12.0");
        assert_eq!(value_text(&Value::F32(4e6)), "4e+06");
        assert_eq!(value_text(&Value::Bool(true)), "1");
        assert_eq!(value_text(&Value::Char(b'A')), "65");
        assert_eq!(value_text(&Value::I64(-3)), "-3");
    }
}
