//! `Debug` and `PartialEq` of the bindings of known formats, as `#[derive]` would
//! write them, by one walk of the binding's schema over its wire image: code compiled
//! once, where a derive compiles a body of every field for every binding (a crate
//! with `ulog_module!` on a 98-format log builds in about a tenth less time;
//! bench/README.md).
//!
//! The walk gives what the derives give: the struct's and nested structs' Rust names,
//! the fields' Rust names in order (`self_`, `f_2d` where the ULog name is no
//! identifier; a keyword without its `r#`, as `#[derive(Debug)]` prints it), each
//! value as its Rust type prints it (`char[N]` as the text of its `CharArray<N>`),
//! `{:#?}` laid out the same; floats compared as numbers (`NaN` differs from itself,
//! `-0.0` equals `0.0`), the rest by value. Two differences: a binding writes no
//! padding into its wire image, so padding fields print and compare as the zeros
//! that every value read from a log or made by `Default` holds; and the fields of a
//! view (zerocopy's little-endian types) print as numbers (`9`, not `U64(9)`) and
//! their floats compare as numbers, not as bytes. Since the implementations are not
//! derived, a binding's constants cannot be `match` patterns.

use core::fmt;

use ulog_format::BasicType;

use super::chars::text_bytes;
use super::schema::{FieldKind, Schema};

/// Formats the wire image `image` of a binding of `schema` as `#[derive(Debug)]`.
pub fn debug_image(schema: &Schema, image: &[u8], f: &mut fmt::Formatter<'_>) -> fmt::Result {
    let mut s = f.debug_struct(schema.rust_name());
    let mut at = 0;
    for field in schema.fields() {
        let (kind, count) = (field.kind(), field.array_len());
        let size = field_size(kind, count);
        let bytes = &image[at..at + size];
        let name = ulog_format::rust_field_name(field.name());
        if ulog_format::is_padding_name(field.name()) {
            // Padding is `[u8; bytes]`, or a `u8` when it is one byte not in an array,
            // whatever its ULog type.
            match (count, bytes) {
                (None, [b]) => s.field(&name, b),
                _ => s.field(&name, &bytes),
            };
        } else {
            s.field(&name, &Shown { kind, count, bytes });
        }
        at += size;
    }
    s.finish()
}

/// Whether two wire images of a binding of `schema` hold equal values, field by
/// field as `#[derive(PartialEq)]` compares them.
pub fn images_eq(schema: &Schema, a: &[u8], b: &[u8]) -> bool {
    let mut at = 0;
    for field in schema.fields() {
        let (kind, count) = (field.kind(), field.array_len());
        let size = field_size(kind, count);
        if !values_eq(kind, count, &a[at..at + size], &b[at..at + size]) {
            return false;
        }
        at += size;
    }
    true
}

/// The bytes of one element of `kind`.
fn elem_size(kind: FieldKind) -> usize {
    match kind {
        FieldKind::Basic(b) => b.size(),
        FieldKind::Nested(schema) => schema().layout().size(),
    }
}

/// The bytes of a field of `kind`, `count` elements of it when an array.
fn field_size(kind: FieldKind, count: Option<usize>) -> usize {
    elem_size(kind) * count.unwrap_or(1)
}

fn values_eq(kind: FieldKind, count: Option<usize>, a: &[u8], b: &[u8]) -> bool {
    let size = elem_size(kind);
    (0..count.unwrap_or(1)).all(|i| {
        let (x, y) = (&a[i * size..(i + 1) * size], &b[i * size..(i + 1) * size]);
        match kind {
            FieldKind::Basic(BasicType::Float) => {
                f32::from_le_bytes(word(x)) == f32::from_le_bytes(word(y))
            }
            FieldKind::Basic(BasicType::Double) => {
                f64::from_le_bytes(word(x)) == f64::from_le_bytes(word(y))
            }
            // A `bool` writes 0 or 1; a view's `ByteBool` writes its byte, and
            // compares by it.
            FieldKind::Basic(_) => x == y,
            FieldKind::Nested(schema) => images_eq(schema(), x, y),
        }
    })
}

/// The first `N` bytes of `bytes` (which has them: the walk slices by the types' sizes).
fn word<const N: usize>(bytes: &[u8]) -> [u8; N] {
    let mut out = [0; N];
    out.copy_from_slice(&bytes[..N]);
    out
}

/// One field's value (or an array's elements) in a wire image, shown as its Rust type.
struct Shown<'a> {
    kind: FieldKind,
    count: Option<usize>,
    bytes: &'a [u8],
}

impl fmt::Debug for Shown<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let (FieldKind::Basic(BasicType::Char), Some(_)) = (self.kind, self.count) {
            // `char[N]` is a `CharArray<N>`, which shows its text.
            return fmt::Debug::fmt(&String::from_utf8_lossy(text_bytes(self.bytes)), f);
        }
        if let Some(n) = self.count {
            let size = elem_size(self.kind);
            return f
                .debug_list()
                .entries((0..n).map(|i| Shown {
                    kind: self.kind,
                    count: None,
                    bytes: &self.bytes[i * size..(i + 1) * size],
                }))
                .finish();
        }
        let b = self.bytes;
        match self.kind {
            FieldKind::Nested(schema) => debug_image(schema(), b, f),
            FieldKind::Basic(t) => match t {
                BasicType::Int8 => fmt::Debug::fmt(&i8::from_le_bytes(word(b)), f),
                BasicType::UInt8 | BasicType::Char => fmt::Debug::fmt(&b[0], f),
                BasicType::Int16 => fmt::Debug::fmt(&i16::from_le_bytes(word(b)), f),
                BasicType::UInt16 => fmt::Debug::fmt(&u16::from_le_bytes(word(b)), f),
                BasicType::Int32 => fmt::Debug::fmt(&i32::from_le_bytes(word(b)), f),
                BasicType::UInt32 => fmt::Debug::fmt(&u32::from_le_bytes(word(b)), f),
                BasicType::Int64 => fmt::Debug::fmt(&i64::from_le_bytes(word(b)), f),
                BasicType::UInt64 => fmt::Debug::fmt(&u64::from_le_bytes(word(b)), f),
                BasicType::Float => fmt::Debug::fmt(&f32::from_le_bytes(word(b)), f),
                BasicType::Double => fmt::Debug::fmt(&f64::from_le_bytes(word(b)), f),
                BasicType::Bool => fmt::Debug::fmt(&(b[0] != 0), f),
            },
        }
    }
}
