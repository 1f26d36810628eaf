//! `Binding`: what the bindings of known formats implement (`ulog_module!`,
//! `ulog_structs!`, `ulog codegen`): their format's text, and their fields read from
//! and written to their wire image in order. `WireField`, `ArrayElement` and
//! `ULogMessage` follow from it by blanket implementations, `Clone`, `Debug`,
//! `PartialEq` and `Default` through shared code (`__binding_impls!`), so that the code generated per binding is
//! little more than the struct and its field list: the schema is built from the text
//! at first use, and a log laid out otherwise is read through one walk of a table
//! ([`fill_image`]), not through code generated per field and per type.

use std::sync::OnceLock;

use ulog_format::{BasicType, Format, TypeName};
use zerocopy::{FromBytes, FromZeros, Immutable, IntoBytes, KnownLayout, Unaligned};

use super::message::visit_image;
use super::schema::{FieldDef, FieldKind, Schema};
use super::wire::{
    read, wire_size, write, write_array, Converted, Present, Widened, WireField, NOWHERE,
};
use crate::value::Value;

/// A binding whose format is known when its code is generated (generated code; not
/// a public API): its fields, read and written in order at the offsets of its wire
/// image, and its format's text, from which its schema is built.
#[doc(hidden)]
#[diagnostic::on_unimplemented(
    message = "`{Self}` cannot be a field of a ULog message",
    note = "fields are u8..u64, i8..i64, f32, f64, bool, `CharArray<N>`, arrays of these, `Option`s of these, or types that derive `ULogMessage`"
)]
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

/// The implementations of the standard traits a [`Binding`] has (generated code: one
/// line per binding): `Clone` (bindings are `Copy`), `Debug` and `PartialEq` by one
/// walk of the schema (see `typed/derived.rs` for what they give), `Default` (every
/// field zero). Those of this crate's traits are blanket implementations below.
#[doc(hidden)]
#[macro_export]
macro_rules! __binding_impls {
    ($t:ty) => {
        impl ::core::clone::Clone for $t {
            #[inline]
            fn clone(&self) -> $t {
                *self
            }
        }
        impl ::core::fmt::Debug for $t {
            fn fmt(&self, f: &mut ::core::fmt::Formatter<'_>) -> ::core::fmt::Result {
                $crate::typed::__private::binding::debug(
                    <$t as $crate::typed::__private::Binding>::schema(),
                    &$crate::typed::__private::binding::to_wire(self),
                    f,
                )
            }
        }
        impl ::core::cmp::PartialEq for $t {
            #[inline]
            fn eq(&self, other: &$t) -> bool {
                $crate::typed::__private::binding::eq(
                    <$t as $crate::typed::__private::Binding>::schema(),
                    &$crate::typed::__private::binding::to_wire(self),
                    &$crate::typed::__private::binding::to_wire(other),
                )
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

/// Every binding is a field and a message. Blanket implementations, where one
/// implementation per binding had the compiler check each binding's again (a crate
/// with `ulog_module!` on a 98-format log: about a fifth of its build; bench/README.md).
/// A type that is no field is then said to lack `Binding`, whose diagnostic says what
/// `WireField`'s does.
impl<T: Binding> WireField for T {
    type Wire = <T as Binding>::Wire;
    type Writability = super::wire::Writable;
    const KIND: FieldKind = FieldKind::Nested(<T as Binding>::schema);
    const IS_WIRE: bool = <T as Binding>::IS_WIRE;
    const SOURCES: usize = <T as Binding>::SOURCES;
    const DIRECT: bool = true;
    const READS_IMAGE: bool = true;
    #[inline]
    fn from_wire(wire: &Self::Wire, _: Present<'_>) -> T {
        impls::from_wire(wire)
    }
    #[inline]
    fn from_image(image: &[u8], _: Present<'_>) -> Option<T> {
        impls::from_image(image)
    }
    #[inline]
    fn from_payload(payload: &[u8], sources: &[u32], _: Present<'_>) -> T {
        impls::from_payload(payload, sources)
    }
    #[inline]
    fn to_wire(&self) -> Self::Wire {
        impls::to_wire(self)
    }
    #[inline]
    fn visit(&self, path: &mut String, f: &mut dyn FnMut(&str, Value<'_>)) {
        impls::visit(self, path, f)
    }
}

impl<T: Binding> super::wire::ArrayElement for T {}

impl<T: Binding> crate::ULogMessage for T {
    const NAME: &'static str = format_name(<T as Binding>::FORMAT);
    #[inline]
    fn schema() -> &'static Schema {
        <T as Binding>::schema()
    }
    #[inline]
    fn visit_fields(&self, f: &mut dyn FnMut(&str, Value<'_>)) {
        impls::visit(self, &mut String::new(), f)
    }
    #[inline]
    fn visit_fields_at(&self, path: &mut String, f: &mut dyn FnMut(&str, Value<'_>)) {
        impls::visit(self, path, f)
    }
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
        // Through `to_wire`, which `Debug` and `PartialEq` call too: one function per
        // binding for the three.
        visit_image(T::schema().layout(), to_wire(value).as_bytes(), path, f);
    }

    /// `Debug::fmt` and `PartialEq::eq` of the wire images (of `to_wire`), as the
    /// derives show and compare the struct. Not generic: the binding's `fmt` and `eq`
    /// are one call each.
    pub use crate::typed::derived::{debug_image as debug, images_eq as eq};
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

    /// The next field, an array. Filled in a loop rather than by
    /// `core::array::from_fn`, whose generic layers a crate would compile for every
    /// element type and length its bindings have (bench/README.md).
    #[inline]
    pub fn array<T: WireField + Copy + Default, const N: usize>(&mut self) -> [T; N] {
        let mut value = [T::default(); N];
        for v in &mut value {
            *v = self.get();
        }
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
