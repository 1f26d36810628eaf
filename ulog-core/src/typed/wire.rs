//! `WireField`: how one Rust field type maps to ULog bytes.
//!
//! Every field of a binding has a *wire* image: a type of alignment 1 whose bytes are
//! exactly the little-endian ULog bytes of the field (`zerocopy`'s
//! `little_endian::U32` for a `u32`, `u8` for a `bool`, …). A binding's wire struct is
//! the `#[repr(C)]` sequence of its fields' wire images, so it has the layout of the
//! ULog payload on any host, and a payload is copied into it (or borrowed as it) in
//! one go.

use ulog_format::BasicType;
use zerocopy::little_endian as le;
use zerocopy::{FromBytes, Immutable, IntoBytes, KnownLayout, Unaligned};

use super::chars::CharArray;
use super::schema::Schema;
use crate::value::{Str, Value};

/// The ULog type of one value of a field: a basic type, or a nested message.
#[derive(Debug, Clone, Copy)]
pub enum FieldKind {
    /// One of the twelve basic types.
    Basic(BasicType),
    /// A nested message, by its schema.
    Nested(fn() -> &'static Schema),
}

/// A Rust type that can be a field of a ULog binding.
///
/// Implemented for `u8`…`u64`, `i8`…`i64`, `f32`, `f64`, `bool`, [`CharArray<N>`]
/// (`char[N]`), `zerocopy`'s little-endian integer and float types (for borrowed
/// views), and every type that derives [`ULogMessage`](super::ULogMessage). Arrays
/// `[T; N]` of these (except `CharArray`) are fields too; the derive handles them.
#[diagnostic::on_unimplemented(
    message = "`{Self}` cannot be a field of a ULog message",
    note = "fields are u8..u64, i8..i64, f32, f64, bool, `CharArray<N>`, arrays of these, or types that derive `ULogMessage`"
)]
pub trait WireField: Sized {
    /// The field's bytes as stored in a payload: alignment 1, little endian.
    type Wire: FromBytes + IntoBytes + KnownLayout + Immutable + Unaligned;
    /// The ULog type of one value.
    const KIND: FieldKind;
    /// `Some(N)` for types that are ULog arrays by themselves (`CharArray<N>` is
    /// `char[N]`).
    const COUNT: Option<usize> = None;
    /// Whether `Self` in memory is its wire image (alignment 1, same bytes), so that a
    /// payload can be borrowed as `&Self`.
    const IS_WIRE: bool = false;
    /// The value of a wire image.
    fn from_wire(wire: &Self::Wire) -> Self;
    /// The wire image of a value.
    fn to_wire(&self) -> Self::Wire;
    /// Calls `f` with `path` and the value of each leaf of `self`: the value itself
    /// for basic types and `char[N]`, each field (with `.name` appended to `path`)
    /// for bindings. See [`ULogMessage::visit_fields`](super::ULogMessage::visit_fields).
    fn visit_values(&self, path: &mut String, f: &mut dyn FnMut(&str, Value<'_>));
}

/// A field type that can be the element of an array field (`[T; N]`): every
/// [`WireField`] except `CharArray<N>`, since ULog has no arrays of strings.
#[diagnostic::on_unimplemented(
    message = "`{Self}` cannot be an array element in a ULog message",
    note = "ULog has no arrays of arrays; `char[N]` strings cannot be put in arrays"
)]
pub trait ArrayElement: WireField {}

macro_rules! same_bytes {
    ($($t:ty => $basic:ident, $value:ident, $native:ty),*) => {$(
        impl WireField for $t {
            type Wire = $t;
            const KIND: FieldKind = FieldKind::Basic(BasicType::$basic);
            const IS_WIRE: bool = true;
            fn from_wire(wire: &$t) -> $t {
                *wire
            }
            fn to_wire(&self) -> $t {
                *self
            }
            fn visit_values(&self, path: &mut String, f: &mut dyn FnMut(&str, Value<'_>)) {
                f(path, Value::$value(<$native as WireField>::from_wire(self)));
            }
        }
        impl ArrayElement for $t {}
    )*};
}

same_bytes!(
    u8 => UInt8, U8, u8, i8 => Int8, I8, i8,
    le::U16 => UInt16, U16, u16, le::I16 => Int16, I16, i16,
    le::U32 => UInt32, U32, u32, le::I32 => Int32, I32, i32,
    le::U64 => UInt64, U64, u64, le::I64 => Int64, I64, i64,
    le::F32 => Float, F32, f32, le::F64 => Double, F64, f64
);

macro_rules! little_endian {
    ($($t:ty => $wire:ty, $basic:ident, $value:ident),*) => {$(
        impl WireField for $t {
            type Wire = $wire;
            const KIND: FieldKind = FieldKind::Basic(BasicType::$basic);
            fn from_wire(wire: &$wire) -> $t {
                wire.get()
            }
            fn to_wire(&self) -> $wire {
                <$wire>::new(*self)
            }
            fn visit_values(&self, path: &mut String, f: &mut dyn FnMut(&str, Value<'_>)) {
                f(path, Value::$value(*self));
            }
        }
        impl ArrayElement for $t {}
    )*};
}

little_endian!(
    u16 => le::U16, UInt16, U16, i16 => le::I16, Int16, I16, u32 => le::U32, UInt32, U32,
    i32 => le::I32, Int32, I32, u64 => le::U64, UInt64, U64, i64 => le::I64, Int64, I64,
    f32 => le::F32, Float, F32, f64 => le::F64, Double, F64
);

impl WireField for bool {
    type Wire = u8;
    const KIND: FieldKind = FieldKind::Basic(BasicType::Bool);
    /// Any non-zero byte is true, as in PX4.
    fn from_wire(wire: &u8) -> bool {
        *wire != 0
    }
    fn to_wire(&self) -> u8 {
        u8::from(*self)
    }
    fn visit_values(&self, path: &mut String, f: &mut dyn FnMut(&str, Value<'_>)) {
        f(path, Value::Bool(*self));
    }
}
impl ArrayElement for bool {}

impl<const N: usize> WireField for CharArray<N> {
    type Wire = CharArray<N>;
    const KIND: FieldKind = FieldKind::Basic(BasicType::Char);
    const COUNT: Option<usize> = Some(N);
    const IS_WIRE: bool = true;
    fn from_wire(wire: &CharArray<N>) -> CharArray<N> {
        *wire
    }
    fn to_wire(&self) -> CharArray<N> {
        *self
    }
    /// The whole `N` bytes, as the reader gives a `char[N]` field.
    fn visit_values(&self, path: &mut String, f: &mut dyn FnMut(&str, Value<'_>)) {
        f(path, Value::Str(Str(self.as_bytes())));
    }
}

/// Visits field `name` of a binding whose path is `path[..base]` (generated code).
pub fn visit_field<T: WireField>(
    value: &T,
    path: &mut String,
    base: usize,
    name: &str,
    f: &mut dyn FnMut(&str, Value<'_>),
) {
    field_path(path, base, name);
    value.visit_values(path, f);
    path.truncate(base);
}

/// Visits array field `name` element by element, as `name[i]` (generated code).
pub fn visit_array<T: WireField>(
    values: &[T],
    path: &mut String,
    base: usize,
    name: &str,
    f: &mut dyn FnMut(&str, Value<'_>),
) {
    for (i, value) in values.iter().enumerate() {
        field_path(path, base, name);
        push_index(path, i);
        value.visit_values(path, f);
    }
    path.truncate(base);
}

/// Visits a `char[N]` held as `[u8; N]`, or one `char` (`single`) held as a `u8`
/// (generated code).
pub fn visit_chars(
    bytes: &[u8],
    single: bool,
    path: &mut String,
    base: usize,
    name: &str,
    f: &mut dyn FnMut(&str, Value<'_>),
) {
    field_path(path, base, name);
    match (single, bytes.first()) {
        (true, Some(&c)) => f(path, Value::Char(c)),
        _ => f(path, Value::Str(Str(bytes))),
    }
    path.truncate(base);
}

fn field_path(path: &mut String, base: usize, name: &str) {
    path.truncate(base);
    if base > 0 {
        path.push('.');
    }
    path.push_str(name);
}

fn push_index(path: &mut String, i: usize) {
    use core::fmt::Write;
    // Writing to a String cannot fail.
    let _ = write!(path, "[{i}]");
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wire_images_are_little_endian() {
        assert_eq!(0x0102_0304u32.to_wire().as_bytes(), [4, 3, 2, 1]);
        assert_eq!((-2i16).to_wire().as_bytes(), [0xfe, 0xff]);
        assert_eq!(1.0f32.to_wire().as_bytes(), 1.0f32.to_le_bytes());
        assert!(bool::from_wire(&2));
        assert_eq!(true.to_wire(), 1);
        assert_eq!(u64::from_wire(&le::U64::from_bytes(7u64.to_le_bytes())), 7);
    }
}
