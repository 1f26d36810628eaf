//! Typed values read from payload bytes: numbers, booleans, `char[N]` strings, arrays.

use core::fmt;

use ulog_format::BasicType;

/// Text as logged: a `char[N]` field, a logged string, a key. The bytes are kept as
/// they are (no terminating NUL is required; text after a NUL is kept): ULog does not
/// promise UTF-8, so they are shown lossily.
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
pub struct LogText<'a>(pub &'a [u8]);

impl<'a> LogText<'a> {
    /// The bytes as logged.
    pub fn as_bytes(&self) -> &'a [u8] {
        self.0
    }

    /// The text, if it is valid UTF-8.
    pub fn as_str(&self) -> Option<&'a str> {
        core::str::from_utf8(self.0).ok()
    }

    /// The text with invalid UTF-8 replaced by U+FFFD.
    pub fn to_string_lossy(&self) -> std::borrow::Cow<'a, str> {
        String::from_utf8_lossy(self.0)
    }

    /// The bytes up to the first NUL: how C code and pyulog's CSV export read a fixed
    /// `char[N]` field.
    pub fn until_nul(&self) -> LogText<'a> {
        LogText(self.0.split(|&b| b == 0).next().unwrap_or(&[]))
    }
}

impl fmt::Debug for LogText<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Debug::fmt(&self.to_string_lossy(), f)
    }
}

impl fmt::Display for LogText<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.to_string_lossy())
    }
}

/// An array of a basic type, borrowed from the payload.
#[derive(Clone, Copy, PartialEq)]
pub struct ValueArray<'a> {
    ty: BasicType,
    bytes: &'a [u8],
}

impl<'a> ValueArray<'a> {
    /// An array of `ty` over `bytes` (any bytes past the last whole element are ignored).
    pub fn new(ty: BasicType, bytes: &'a [u8]) -> ValueArray<'a> {
        let n = bytes.len() / ty.size();
        ValueArray {
            ty,
            bytes: &bytes[..n * ty.size()],
        }
    }

    /// The element type.
    pub fn element_type(&self) -> BasicType {
        self.ty
    }

    /// The number of elements.
    pub fn len(&self) -> usize {
        self.bytes.len() / self.ty.size()
    }

    /// Whether there are no elements.
    pub fn is_empty(&self) -> bool {
        self.bytes.is_empty()
    }

    /// Element `i`.
    pub fn get(&self, i: usize) -> Option<Value<'a>> {
        let s = self.ty.size();
        self.bytes
            .get(i * s..i * s + s)
            .map(|b| Value::read_scalar(self.ty, b))
    }

    /// The elements in order.
    pub fn iter(&self) -> impl Iterator<Item = Value<'a>> + 'a {
        let ty = self.ty;
        self.bytes
            .chunks_exact(ty.size())
            .map(move |b| Value::read_scalar(ty, b))
    }

    /// The raw little-endian bytes.
    pub fn as_bytes(&self) -> &'a [u8] {
        self.bytes
    }
}

impl fmt::Debug for ValueArray<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_list().entries(self.iter()).finish()
    }
}

/// A value of a field, an information message or a parameter.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub enum Value<'a> {
    /// `int8_t`
    I8(i8),
    /// `uint8_t`
    U8(u8),
    /// `int16_t`
    I16(i16),
    /// `uint16_t`
    U16(u16),
    /// `int32_t`
    I32(i32),
    /// `uint32_t`
    U32(u32),
    /// `int64_t`
    I64(i64),
    /// `uint64_t`
    U64(u64),
    /// `float`
    F32(f32),
    /// `double`
    F64(f64),
    /// `bool`
    Bool(bool),
    /// a single `char`
    Char(u8),
    /// `char[N]`
    Str(LogText<'a>),
    /// an array of a basic type other than `char`
    Array(ValueArray<'a>),
    /// bytes whose type this reader cannot decode (a nested type in an information
    /// key, or a value of the wrong length for its type)
    Bytes(&'a [u8]),
}

macro_rules! le {
    ($t:ty, $b:expr) => {{
        let mut a = [0u8; core::mem::size_of::<$t>()];
        a.copy_from_slice(&$b[..core::mem::size_of::<$t>()]);
        <$t>::from_le_bytes(a)
    }};
}

impl<'a> Value<'a> {
    /// Reads one value of `ty` from the first bytes of `b` (which must hold at least
    /// `ty.size()` bytes).
    #[inline]
    pub fn read_scalar(ty: BasicType, b: &'a [u8]) -> Value<'a> {
        match ty {
            BasicType::Int8 => Value::I8(b[0] as i8),
            BasicType::UInt8 => Value::U8(b[0]),
            BasicType::Int16 => Value::I16(le!(i16, b)),
            BasicType::UInt16 => Value::U16(le!(u16, b)),
            BasicType::Int32 => Value::I32(le!(i32, b)),
            BasicType::UInt32 => Value::U32(le!(u32, b)),
            BasicType::Int64 => Value::I64(le!(i64, b)),
            BasicType::UInt64 => Value::U64(le!(u64, b)),
            BasicType::Float => Value::F32(le!(f32, b)),
            BasicType::Double => Value::F64(le!(f64, b)),
            BasicType::Bool => Value::Bool(b[0] != 0),
            BasicType::Char => Value::Char(b[0]),
        }
    }

    /// Decodes `bytes` as a value of `ty` (an array when `array_len` is given):
    /// a `char` array is a string, other arrays are [`ValueArray`]s, and bytes of the wrong
    /// length for a scalar come back as [`Value::Bytes`].
    pub fn decode(ty: BasicType, array_len: Option<usize>, bytes: &'a [u8]) -> Value<'a> {
        match (ty, array_len) {
            (BasicType::Char, Some(_)) => Value::Str(LogText(bytes)),
            (_, Some(_)) => Value::Array(ValueArray::new(ty, bytes)),
            (_, None) if bytes.len() == ty.size() => Value::read_scalar(ty, bytes),
            (_, None) => Value::Bytes(bytes),
        }
    }

    /// The value as `f64` (numbers and booleans; `None` for strings and arrays).
    #[inline]
    pub fn as_f64(&self) -> Option<f64> {
        Some(match *self {
            Value::I8(v) => v as f64,
            Value::U8(v) => v as f64,
            Value::I16(v) => v as f64,
            Value::U16(v) => v as f64,
            Value::I32(v) => v as f64,
            Value::U32(v) => v as f64,
            Value::I64(v) => v as f64,
            Value::U64(v) => v as f64,
            Value::F32(v) => v as f64,
            Value::F64(v) => v,
            Value::Bool(v) => v as u8 as f64,
            Value::Char(v) => v as f64,
            _ => return None,
        })
    }

    /// The value as `i128` when it is an integer, bool or char.
    pub fn as_i128(&self) -> Option<i128> {
        Some(match *self {
            Value::I8(v) => v.into(),
            Value::U8(v) => v.into(),
            Value::I16(v) => v.into(),
            Value::U16(v) => v.into(),
            Value::I32(v) => v.into(),
            Value::U32(v) => v.into(),
            Value::I64(v) => v.into(),
            Value::U64(v) => v.into(),
            Value::Bool(v) => v.into(),
            Value::Char(v) => v.into(),
            _ => return None,
        })
    }

    /// The value as `u64` when it is a non-negative integer.
    pub fn as_u64(&self) -> Option<u64> {
        self.as_i128().and_then(|v| u64::try_from(v).ok())
    }

    /// The string, for `char[N]` values.
    pub fn as_str(&self) -> Option<LogText<'a>> {
        match self {
            Value::Str(s) => Some(*s),
            _ => None,
        }
    }
}

impl fmt::Display for Value<'_> {
    /// Numbers as Rust prints them (floats in their shortest form that reads back to
    /// the same value, `1.0`, `1e-7`, `NaN`), booleans as `true`/`false`, a `char` as
    /// its byte's character (`A`; its code in hex when it is not printable ASCII),
    /// strings as (lossy) text, arrays as `[a, b]`, bytes in hex. (The `ulog` command
    /// line prints values as pyulog does; that is its own formatting.)
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Value::I8(v) => write!(f, "{v}"),
            Value::U8(v) => write!(f, "{v}"),
            Value::I16(v) => write!(f, "{v}"),
            Value::U16(v) => write!(f, "{v}"),
            Value::I32(v) => write!(f, "{v}"),
            Value::U32(v) => write!(f, "{v}"),
            Value::I64(v) => write!(f, "{v}"),
            Value::U64(v) => write!(f, "{v}"),
            Value::F32(v) => write!(f, "{v:?}"),
            Value::F64(v) => write!(f, "{v:?}"),
            Value::Bool(v) => write!(f, "{v}"),
            Value::Char(v) if v.is_ascii_graphic() || *v == b' ' => write!(f, "{}", *v as char),
            Value::Char(v) => write!(f, "{v:#04x}"),
            Value::Str(s) => write!(f, "{s}"),
            Value::Array(a) => {
                f.write_str("[")?;
                for (i, v) in a.iter().enumerate() {
                    if i > 0 {
                        f.write_str(", ")?;
                    }
                    write!(f, "{v}")?;
                }
                f.write_str("]")
            }
            Value::Bytes(b) => {
                for x in *b {
                    write!(f, "{x:02x}")?;
                }
                Ok(())
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_display_as_rust_prints_them() {
        assert_eq!(Value::F32(4e6).to_string(), "4000000.0");
        assert_eq!(Value::F32(1e-7).to_string(), "1e-7");
        assert_eq!(
            Value::F64(f64::from(0.1f32)).to_string(),
            "0.10000000149011612"
        );
        assert_eq!(Value::I64(-3).to_string(), "-3");
        assert_eq!(Value::Char(b'A').to_string(), "A");
        assert_eq!(Value::Char(0).to_string(), "0x00");
        assert_eq!(Value::Bool(true).to_string(), "true");
    }

    #[test]
    fn decodes_scalars_arrays_and_strings() {
        let b = 0x0102_0304u32.to_le_bytes();
        assert_eq!(
            Value::decode(BasicType::UInt32, None, &b),
            Value::U32(0x0102_0304)
        );
        assert_eq!(
            Value::decode(BasicType::UInt32, None, &b[..3]),
            Value::Bytes(&b[..3])
        );
        let a = Value::decode(BasicType::UInt16, Some(2), &b);
        match a {
            Value::Array(a) => {
                assert_eq!(a.len(), 2);
                assert_eq!(a.get(1), Some(Value::U16(0x0102)));
                assert_eq!(a.get(2), None);
            }
            v => panic!("{v:?}"),
        }
        let s = Value::decode(BasicType::Char, Some(6), b"ab\0cd\xff");
        assert_eq!(s.as_str().unwrap().until_nul().as_bytes(), b"ab");
        assert_eq!(s.to_string(), "ab\0cd\u{fffd}");
    }
}
