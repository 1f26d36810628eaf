//! `Binding`: what the bindings of known formats implement (`ulog_module!`,
//! `ulog_structs!`, `ulog codegen`): their format's text, and their fields read from
//! and written to their wire image in order. `WireField`, `ULogMessage` and
//! `Default` follow from it through shared code (`__binding_impls!`), so that the code generated per binding is
//! little more than the struct and its field list: the schema is built from the text
//! at first use, and a log laid out otherwise is read through one walk of a table
//! ([`fill_image`]), not through code generated per field and per type.

use std::sync::OnceLock;

use ulog_format::{BasicType, Format, TypeName};
use zerocopy::{FromBytes, FromZeros, Immutable, IntoBytes, KnownLayout, Unaligned};

use super::message::visit_image;
use super::schema::{FieldDef, FieldKind, Schema};
use super::wire::{
    read, read_array, wire_size, write, write_array, Converted, Present, Widened, WireField,
    NOWHERE,
};
use crate::value::Value;

/// A binding whose format is known when its code is generated (generated code; not
/// a public API): its fields, read and written in order at the offsets of its wire
/// image, and its format's text, from which its schema is built.
#[doc(hidden)]
pub trait Binding: Sized + 'static {
    /// The wire image: `[u8; SIZE]`.
    type Wire: FromBytes + IntoBytes + KnownLayout + Immutable + Unaligned;
    /// The format's text (`name:type field;…`), the binding's fields exactly.
    const FORMAT: &'static str;
    /// The schemas of the formats its fields nest.
    const NESTED: &'static [fn() -> &'static Schema] = &[];
    /// [`WireField::SOURCES`]: one per basic field (padding none), and a nested
    /// binding's per element.
    const SOURCES: usize;
    /// [`WireField::IS_WIRE`] (bindings generated as views).
    const IS_WIRE: bool = false;
    /// The schema, from [`SchemaCell::get`].
    fn schema() -> &'static Schema;
    /// The value of a wire image, field by field.
    fn read(r: &mut Reader<'_>) -> Self;
    /// Writes the fields into a wire image (of zeros), in order.
    fn write(&self, w: &mut Writer<'_>);
}

/// The message name of a format text: the text before its `:`.
pub const fn format_name(format: &str) -> &str {
    let bytes = format.as_bytes();
    let mut i = 0;
    while i < bytes.len() && bytes[i] != b':' {
        i += 1;
    }
    match core::str::from_utf8(bytes.split_at(i).0) {
        Ok(name) => name,
        Err(_) => format,
    }
}

/// The implementations of `WireField`, `ArrayElement`, `ULogMessage` and `Default`
/// for a [`Binding`] (generated code: one line per binding). Not blanket
/// implementations: the compiler's errors about a type that is no field name
/// `WireField`, not `Binding`. Every method is `#[inline]`, so that only the ones a
/// program uses are compiled.
#[doc(hidden)]
#[macro_export]
macro_rules! __binding_impls {
    ($t:ty) => {
        impl $crate::typed::WireField for $t {
            type Wire = <$t as $crate::typed::__private::Binding>::Wire;
            type Writability = $crate::typed::Writable;
            const KIND: $crate::typed::FieldKind =
                $crate::typed::FieldKind::Nested(<$t as $crate::typed::__private::Binding>::schema);
            const IS_WIRE: bool = <$t as $crate::typed::__private::Binding>::IS_WIRE;
            const SOURCES: usize = <$t as $crate::typed::__private::Binding>::SOURCES;
            const DIRECT: bool = true;
            const READS_IMAGE: bool = true;
            #[inline]
            fn from_wire(wire: &Self::Wire, _: $crate::typed::Present<'_>) -> $t {
                $crate::typed::__private::binding::from_wire(wire)
            }
            #[inline]
            fn from_image(
                image: &[u8],
                _: $crate::typed::Present<'_>,
            ) -> ::core::option::Option<$t> {
                $crate::typed::__private::binding::from_image(image)
            }
            #[inline]
            fn from_payload(payload: &[u8], sources: &[u32], _: $crate::typed::Present<'_>) -> $t {
                $crate::typed::__private::binding::from_payload(payload, sources)
            }
            #[inline]
            fn to_wire(&self) -> Self::Wire {
                $crate::typed::__private::binding::to_wire(self)
            }
            #[inline]
            fn visit(
                &self,
                path: &mut ::std::string::String,
                f: &mut dyn ::core::ops::FnMut(&str, $crate::typed::__private::Value<'_>),
            ) {
                $crate::typed::__private::binding::visit(self, path, f)
            }
        }
        impl $crate::typed::ArrayElement for $t {}
        impl $crate::ULogMessage for $t {
            const NAME: &'static str = $crate::typed::__private::format_name(
                <$t as $crate::typed::__private::Binding>::FORMAT,
            );
            #[inline]
            fn schema() -> &'static $crate::typed::Schema {
                <$t as $crate::typed::__private::Binding>::schema()
            }
            #[inline]
            fn visit_fields(
                &self,
                f: &mut dyn ::core::ops::FnMut(&str, $crate::typed::__private::Value<'_>),
            ) {
                $crate::typed::__private::binding::visit(self, &mut ::std::string::String::new(), f)
            }
            #[inline]
            fn visit_fields_at(
                &self,
                path: &mut ::std::string::String,
                f: &mut dyn ::core::ops::FnMut(&str, $crate::typed::__private::Value<'_>),
            ) {
                $crate::typed::__private::binding::visit(self, path, f)
            }
        }
        impl ::core::default::Default for $t {
            /// Every field zero.
            #[inline]
            fn default() -> $t {
                <$t as $crate::ULogMessage>::zeroed()
            }
        }
    };
}

/// What [`__binding_impls!`] delegates to, the same for every binding.
pub mod impls {
    use super::*;

    /// `WireField::from_wire`.
    #[inline]
    pub fn from_wire<T: Binding>(wire: &T::Wire) -> T {
        T::read(&mut Reader::new(wire.as_bytes()))
    }

    /// `WireField::from_image`.
    #[inline]
    pub fn from_image<T: Binding>(image: &[u8]) -> Option<T> {
        match image.len() == core::mem::size_of::<T::Wire>() {
            true => Some(T::read(&mut Reader::new(image))),
            false => None,
        }
    }

    /// `WireField::from_payload`: through a wire image filled from the payload by
    /// the schema's table.
    pub fn from_payload<T: Binding>(payload: &[u8], sources: &[u32]) -> T {
        let mut wire = T::Wire::new_zeroed();
        fill_image(T::schema(), payload, sources, wire.as_mut_bytes());
        T::read(&mut Reader::new(wire.as_bytes()))
    }

    /// `WireField::to_wire`.
    pub fn to_wire<T: Binding>(value: &T) -> T::Wire {
        let mut wire = T::Wire::new_zeroed();
        value.write(&mut Writer::new(wire.as_mut_bytes()));
        wire
    }

    /// `WireField::visit` and `ULogMessage::visit_fields`: the wire image read as the
    /// reader reads a payload.
    pub fn visit<T: Binding>(value: &T, path: &mut String, f: &mut dyn FnMut(&str, Value<'_>)) {
        // `to_wire`'s two lines rather than a call: one function fewer compiled per
        // binding a program visits.
        let mut wire = T::Wire::new_zeroed();
        value.write(&mut Writer::new(wire.as_mut_bytes()));
        visit_image(T::schema().layout(), wire.as_bytes(), path, f);
    }
}

/// Reads the fields of a wire image in order (generated code).
#[doc(hidden)]
pub struct Reader<'w> {
    wire: &'w [u8],
    at: usize,
}

impl<'w> Reader<'w> {
    /// At the start of `wire`.
    #[inline]
    pub fn new(wire: &'w [u8]) -> Reader<'w> {
        Reader { wire, at: 0 }
    }

    /// The next field.
    #[inline]
    pub fn get<T: WireField>(&mut self) -> T {
        let value = read::<T>(self.wire, self.at, Present::ALL);
        self.at += wire_size::<T>();
        value
    }

    /// The next field, an array.
    #[inline]
    pub fn array<T: WireField, const N: usize>(&mut self) -> [T; N] {
        let value = read_array::<T, N>(self.wire, self.at, Present::ALL);
        self.at += N * wire_size::<T>();
        value
    }

    /// The next field, padding: zeros.
    #[inline]
    pub fn pad<const N: usize>(&mut self) -> [u8; N] {
        self.at += N;
        [0; N]
    }

    /// The next field, one byte of padding: zero.
    #[inline]
    pub fn pad_byte(&mut self) -> u8 {
        self.at += 1;
        0
    }
}

/// Writes the fields of a wire image in order (generated code).
#[doc(hidden)]
pub struct Writer<'w> {
    wire: &'w mut [u8],
    at: usize,
}

impl<'w> Writer<'w> {
    /// At the start of `wire`.
    #[inline]
    pub fn new(wire: &'w mut [u8]) -> Writer<'w> {
        Writer { wire, at: 0 }
    }

    /// The next field.
    #[inline]
    pub fn put<T: WireField>(&mut self, value: &T) {
        write(self.wire, self.at, value);
        self.at += wire_size::<T>();
    }

    /// The next field, an array.
    #[inline]
    pub fn array<T: WireField>(&mut self, values: &[T]) {
        write_array(self.wire, self.at, values);
        self.at += values.len() * wire_size::<T>();
    }

    /// Skips `n` bytes of padding (zeros, as the image starts).
    #[inline]
    pub fn skip(&mut self, n: usize) {
        self.at += n;
    }
}

/// The schema of a [`Binding`], built at its first use (generated code keeps one in
/// a `static` per binding).
#[doc(hidden)]
pub struct SchemaCell(OnceLock<Schema>);

impl SchemaCell {
    /// Not built yet.
    #[allow(clippy::new_without_default)]
    pub const fn new() -> SchemaCell {
        SchemaCell(OnceLock::new())
    }

    /// The schema of `T`, built from its format text on first use.
    #[inline]
    pub fn get<T: Binding>(&'static self) -> &'static Schema {
        self.get_or_build(T::FORMAT, T::NESTED, core::any::type_name::<T>())
    }

    /// [`get`](SchemaCell::get) past what depends on the binding's type.
    fn get_or_build(
        &'static self,
        format: &'static str,
        nested: &'static [fn() -> &'static Schema],
        type_name: &'static str,
    ) -> &'static Schema {
        self.0.get_or_init(|| {
            let rust_name = type_name.rsplit("::").next().unwrap_or(type_name);
            from_text(format, nested, rust_name)
        })
    }
}

/// The schema of the binding of format text `text`, whose nested formats' schemas are
/// `nested`.
///
/// # Panics
///
/// When the text is not a format, or names a nested format not in `nested`: the
/// generator writes both from one format.
fn from_text(
    text: &'static str,
    nested: &[fn() -> &'static Schema],
    rust_name: &'static str,
) -> Schema {
    let format = match Format::parse(text) {
        Ok(f) => f,
        Err(e) => panic!("invalid ULog binding `{text}`: {e}"),
    };
    let defs: Vec<FieldDef> = format
        .fields
        .iter()
        .map(|field| {
            // The name as a slice of the static text: the last word of the field's.
            let own = &text[field.span.start..field.span.end];
            let name = match own.rfind(field.name.as_str()) {
                Some(at) => &own[at..at + field.name.len()],
                None => panic!("field `{}` of `{text}` is not in its text", field.name),
            };
            let kind = match &field.ty {
                TypeName::Basic(b) => FieldKind::Basic(*b),
                TypeName::Nested(n) => match nested.iter().find(|s| s().name() == n) {
                    Some(schema) => FieldKind::Nested(*schema),
                    None => panic!("the nested format `{n}` of `{text}` is not given"),
                },
            };
            FieldDef::new(name, &[], kind, field.array_len)
        })
        .collect();
    // Built once per binding type and kept for the program's life, as the derive's
    // `static` field tables are.
    let defs: &'static [FieldDef] = Box::leak(defs.into_boxed_slice());
    Schema::build(format_name(text), defs).with_rust_name(rust_name, false)
}

/// Fills `image` (zeros) from `payload` at the plan's payload offsets `sources`, one
/// per leaf of `schema`: bytes copied, values the log holds in another type or a
/// shorter array widened (the plan lets only exact widenings through), fields the
/// log lacks left zero.
pub(crate) fn fill_image(schema: &Schema, payload: &[u8], sources: &[u32], image: &mut [u8]) {
    for (leaf, &source) in schema.image_leaves().iter().zip(sources) {
        let size = leaf.ty.size();
        let n = leaf.len.unwrap_or(1);
        let Some(dst) = image.get_mut(leaf.at..leaf.at + n * size) else {
            continue;
        };
        if source == NOWHERE {
            continue;
        }
        match Converted::unpack(source) {
            Some(c) => {
                for (i, out) in dst.chunks_exact_mut(size).enumerate() {
                    if i >= c.len.unwrap_or(1) {
                        break;
                    }
                    if let Some(value) = c.element(payload, i) {
                        put_widened(leaf.ty, value, out);
                    }
                }
            }
            None => {
                let at = source as usize;
                if let Some(src) = payload.get(at..at + dst.len()) {
                    dst.copy_from_slice(src);
                }
            }
        }
    }
}

/// Writes `value` as a little-endian `ty` into `out` (its size); nothing when the
/// value is not one of `ty` (the plan never widens so).
fn put_widened(ty: BasicType, value: Widened, out: &mut [u8]) {
    let bits = match ty {
        BasicType::UInt8 | BasicType::UInt16 | BasicType::UInt32 | BasicType::UInt64 => {
            value.unsigned()
        }
        BasicType::Int8 | BasicType::Int16 | BasicType::Int32 | BasicType::Int64 => {
            value.signed().map(|i| i as u64)
        }
        BasicType::Float => Some(u64::from((value.float() as f32).to_bits())),
        BasicType::Double => Some(value.float().to_bits()),
        BasicType::Bool => value.unsigned().map(|u| u64::from(u != 0)),
        BasicType::Char => None,
    };
    if let Some(bits) = bits {
        let n = out.len().min(8);
        out[..n].copy_from_slice(&bits.to_le_bytes()[..n]);
    }
}
