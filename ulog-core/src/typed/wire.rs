//! `WireField`: how one Rust field type maps to ULog bytes.
//!
//! Every field of a binding has a *wire* image: a type of alignment 1 whose bytes are
//! exactly the little-endian ULog bytes of the field (`zerocopy`'s
//! `little_endian::U32` for a `u32`, `u8` for a `bool`, a byte array of the binding's
//! size for a binding). A payload laid out as the binding is read field by field from
//! such an image at offsets fixed when the binding is compiled; one laid out
//! otherwise, field by field from the offsets its plan found (`from_payload`).

use ulog_format::BasicType;
use zerocopy::little_endian as le;
use zerocopy::{FromBytes, FromZeros, Immutable, IntoBytes, KnownLayout, Unaligned};

use super::chars::{ByteBool, CharArray};
use super::schema::FieldKind;
use crate::value::{LogText, Value};

/// Which optional fields (`Option<T>`, `#[ulog(default)]`) a log has, for one decode:
/// the plan finds them once per subscription. Slots are numbered in field order, a
/// nested binding's slots after the field that holds it.
#[derive(Debug, Clone, Copy)]
pub struct Present<'p>(Option<&'p [bool]>);

impl<'p> Present<'p> {
    /// Every optional field is in the log.
    pub const ALL: Present<'static> = Present(None);

    /// Slot `i` of `slots` is whether optional field `i` is in the log.
    pub fn new(slots: &'p [bool]) -> Present<'p> {
        Present(Some(slots))
    }

    /// Whether optional field `i` is in the log.
    #[inline(always)]
    pub fn get(self, i: usize) -> bool {
        match self.0 {
            None => true,
            Some(s) => s.get(i).copied().unwrap_or(true),
        }
    }

    /// The `len` slots from `start`: a nested binding's.
    #[inline(always)]
    pub fn sub(self, start: usize, len: usize) -> Present<'p> {
        match self.0 {
            Some(s) if len > 0 => Present(s.get(start..start + len)),
            _ => Present(None),
        }
    }
}

/// A Rust type that can be a field of a ULog binding.
///
/// Implemented for `u8`…`u64`, `i8`…`i64`, `f32`, `f64`, `bool`, [`CharArray<N>`]
/// (`char[N]`), `zerocopy`'s little-endian integer and float types (for borrowed
/// views), and every type that derives [`ULogMessage`](crate::ULogMessage). Arrays
/// `[T; N]` of these (except `CharArray`) are fields too; the derive handles them.
///
/// Derive it rather than implementing it.
#[diagnostic::on_unimplemented(
    message = "`{Self}` cannot be a field of a ULog message",
    note = "fields are u8..u64, i8..i64, f32, f64, bool, `CharArray<N>`, arrays of these, `Option`s of these, or types that derive `ULogMessage`"
)]
pub trait WireField: Sized {
    /// The field's bytes as stored in a payload: alignment 1, little endian.
    type Wire: FromBytes + IntoBytes + KnownLayout + Immutable + Unaligned;
    /// The ULog type of one value.
    const KIND: FieldKind;
    /// `Some(N)` for types that are ULog arrays by themselves (`CharArray<N>` is
    /// `char[N]`).
    const COUNT: Option<usize> = None;
    /// Whether `Self` in memory is its wire image: alignment 1, the size of
    /// `Self::Wire`, every bit pattern of those bytes a valid `Self` (no `bool`, no
    /// `Option`, no references, no padding), no interior mutability. The derive
    /// computes it from the fields; a binding that is also [`WireImage`](super::WireImage)
    /// can be borrowed from payloads.
    const IS_WIRE: bool = false;
    /// How many optional fields it has, nested bindings' included (the slots of a
    /// [`Present`]).
    const OPTIONAL: usize = 0;
    /// Whether its values can be written: [`Writable`], or [`HasOptionFields`] when it
    /// has an `Option` field, nested ones included (`None` has no bytes to write). The
    /// writer takes only `Writable` bindings, so that writing one with `Option` fields
    /// is a type error.
    type Writability: Writability;
    /// How many payload offsets [`from_payload`](Self::from_payload) takes: one for
    /// every type but bindings, whose fields each take their own (generated code).
    #[doc(hidden)]
    const SOURCES: usize = 1;
    /// Whether [`from_payload`](Self::from_payload) reads it from `SOURCES` offsets
    /// as the plan finds them: basic types (one value, whole), and derived bindings
    /// whose fields all do. A binding implemented by hand is decoded through its wire
    /// image instead (generated code).
    #[doc(hidden)]
    const DIRECT: bool = matches!(Self::KIND, FieldKind::Basic(_));
    /// The value of a wire image, its optional fields as `present` says.
    fn from_wire(wire: &Self::Wire, present: Present<'_>) -> Self;
    /// Whether a plan decodes it only through [`from_image`](Self::from_image): of
    /// the payload's prefix, or of an image the plan fills from the payload by the
    /// schema's table (the bindings of known formats). The type's code is then
    /// inlined once per decode, not once per way of decoding (generated code).
    #[doc(hidden)]
    const READS_IMAGE: bool = false;
    /// The value of a wire image held in `image`; `None` when `image` does not have
    /// the image's size (generated code).
    #[doc(hidden)]
    #[inline(always)]
    fn from_image(image: &[u8], present: Present<'_>) -> Option<Self> {
        match Self::Wire::ref_from_bytes(image) {
            Ok(wire) => Some(Self::from_wire(wire, present)),
            Err(_) => None,
        }
    }
    /// The value read straight from a log's payload, where `sources` says each part
    /// of it is: for a binding, one offset per field in declaration order (a nested
    /// binding's own offsets in its place; padding has none), [`NOWHERE`] for a
    /// field the log lacks; for other types, the offset of the whole value.
    ///
    /// A plan whose log lays fields out otherwise than the binding decodes through
    /// this, rather than copying the fields into a wire image first: loads right
    /// after the stores that built the image wait for them (generated code).
    #[doc(hidden)]
    #[inline(always)]
    fn from_payload(payload: &[u8], sources: &[u32], present: Present<'_>) -> Self {
        read_from::<Self>(
            payload,
            sources.first().copied().unwrap_or(NOWHERE),
            present,
        )
    }
    /// The value of one log value of another basic type that
    /// [widens](BasicType::widens_to) to `Self::KIND` (the plan allows no other),
    /// given as [`Widened`]; `None` for types that take no other (generated code).
    #[doc(hidden)]
    #[inline(always)]
    fn from_widened(value: Widened) -> Option<Self> {
        let _ = value;
        None
    }
    /// The wire image of a value (absent optional fields as zeros).
    fn to_wire(&self) -> Self::Wire;
    /// Calls `f` with `path` and the value of each leaf of `self`: the value itself
    /// for basic types and `char[N]`, each leaf field (its path after `path`) for
    /// bindings (generated code).
    #[doc(hidden)]
    fn visit(&self, path: &mut String, f: &mut dyn FnMut(&str, Value<'_>)) {
        if let FieldKind::Basic(b) = Self::KIND {
            let wire = self.to_wire();
            f(path, Value::decode(b, Self::COUNT, wire.as_bytes()));
        }
    }
}

/// Whether a binding can be written: [`Writable`] or [`HasOptionFields`], combined
/// over a binding's fields with [`Writability::And`].
pub trait Writability {
    /// `Writable` when both are.
    type And<B: Writability>: Writability;
}

/// Values of the binding can be written.
#[derive(Debug)]
pub enum Writable {}

/// The binding has `Option` fields (here or in a nested binding): values can be read,
/// not written (`None` has no bytes).
#[derive(Debug)]
pub enum HasOptionFields {}

impl Writability for Writable {
    type And<B: Writability> = B;
}

impl Writability for HasOptionFields {
    type And<B: Writability> = HasOptionFields;
}

/// Implemented by [`Writable`] alone: what the writer asks of a binding's
/// [`WireField::Writability`] (`T::Writability: IsWritable`), so that a binding with
/// `Option` fields is refused at compile time with a text that says so.
#[diagnostic::on_unimplemented(
    message = "a binding with `Option` fields cannot be written: `None` has no bytes",
    label = "this binding has `Option` fields (here or in a binding it nests)",
    note = "read with it, and write with a binding whose every field has a value: `#[ulog(default)]` instead of `Option<T>` reads a field the log lacks as its default, and can be written"
)]
pub trait IsWritable: Writability {}

impl IsWritable for Writable {}

/// A field type that can be the element of an array field (`[T; N]`): every
/// [`WireField`] except `CharArray<N>`, since ULog has no arrays of strings.
#[diagnostic::on_unimplemented(
    message = "`{Self}` cannot be an array element in a ULog message",
    note = "ULog has no arrays of arrays; `char[N]` strings cannot be put in arrays"
)]
pub trait ArrayElement: WireField {}

/// `from_image` of the basic types: the bytes taken as an array, not through
/// zerocopy's checked casts, whose generic layers a crate with many bindings would
/// otherwise compile once per type (bench/README.md).
macro_rules! from_image_bytes {
    ($t:ty, $from:expr) => {
        #[inline(always)]
        fn from_image(image: &[u8], _: Present<'_>) -> Option<$t> {
            match image.try_into() {
                Ok(bytes) => Some($from(bytes)),
                Err(_) => None,
            }
        }
    };
}

macro_rules! same_bytes {
    ($($t:ty => $basic:ident, $from:expr),*) => {$(
        impl WireField for $t {
            type Wire = $t;
            type Writability = Writable;
            const KIND: FieldKind = FieldKind::Basic(BasicType::$basic);
            const IS_WIRE: bool = true;
            #[inline(always)]
            fn from_wire(wire: &$t, _: Present<'_>) -> $t {
                *wire
            }
            from_image_bytes!($t, $from);
            #[inline(always)]
            fn from_widened(value: Widened) -> Option<$t> {
                widened!($basic, value).map(<$t>::from)
            }
            #[inline(always)]
            fn to_wire(&self) -> $t {
                *self
            }
        }
        impl ArrayElement for $t {}
    )*};
}

/// The value of a [`Widened`] as the native type of basic type `$basic`: exact, as
/// the plan lets only widenings through. `as` here converts values that fit.
macro_rules! widened {
    (UInt8, $v:expr) => {
        $v.unsigned().map(|v| v as u8)
    };
    (Int8, $v:expr) => {
        $v.signed().map(|v| v as i8)
    };
    (UInt16, $v:expr) => {
        $v.unsigned().map(|v| v as u16)
    };
    (Int16, $v:expr) => {
        $v.signed().map(|v| v as i16)
    };
    (UInt32, $v:expr) => {
        $v.unsigned().map(|v| v as u32)
    };
    (Int32, $v:expr) => {
        $v.signed().map(|v| v as i32)
    };
    (UInt64, $v:expr) => {
        $v.unsigned()
    };
    (Int64, $v:expr) => {
        $v.signed()
    };
    (Float, $v:expr) => {
        Some($v.float() as f32)
    };
    (Double, $v:expr) => {
        Some($v.float())
    };
}

same_bytes!(
    u8 => UInt8, u8::from_le_bytes, i8 => Int8, i8::from_le_bytes,
    le::U16 => UInt16, le::U16::from_bytes, le::I16 => Int16, le::I16::from_bytes,
    le::U32 => UInt32, le::U32::from_bytes, le::I32 => Int32, le::I32::from_bytes,
    le::U64 => UInt64, le::U64::from_bytes, le::I64 => Int64, le::I64::from_bytes,
    le::F32 => Float, le::F32::from_bytes, le::F64 => Double, le::F64::from_bytes
);

macro_rules! little_endian {
    ($($t:ty => $wire:ty, $basic:ident),*) => {$(
        impl WireField for $t {
            type Wire = $wire;
            type Writability = Writable;
            const KIND: FieldKind = FieldKind::Basic(BasicType::$basic);
            #[inline(always)]
            fn from_wire(wire: &$wire, _: Present<'_>) -> $t {
                wire.get()
            }
            from_image_bytes!($t, <$t>::from_le_bytes);
            #[inline(always)]
            fn from_widened(value: Widened) -> Option<$t> {
                widened!($basic, value)
            }
            #[inline(always)]
            fn to_wire(&self) -> $wire {
                <$wire>::new(*self)
            }
        }
        impl ArrayElement for $t {}
    )*};
}

little_endian!(
    u16 => le::U16, UInt16, i16 => le::I16, Int16, u32 => le::U32, UInt32,
    i32 => le::I32, Int32, u64 => le::U64, UInt64, i64 => le::I64, Int64,
    f32 => le::F32, Float, f64 => le::F64, Double
);

impl WireField for bool {
    type Wire = u8;
    type Writability = Writable;
    const KIND: FieldKind = FieldKind::Basic(BasicType::Bool);
    /// Any non-zero byte is true, as in PX4.
    #[inline(always)]
    fn from_wire(wire: &u8, _: Present<'_>) -> bool {
        *wire != 0
    }
    #[inline(always)]
    fn from_image(image: &[u8], _: Present<'_>) -> Option<bool> {
        match image {
            [b] => Some(*b != 0),
            _ => None,
        }
    }
    /// Only a `bool` (of a shorter array) becomes a `bool`.
    #[inline(always)]
    fn from_widened(value: Widened) -> Option<bool> {
        value.unsigned().map(|u| u != 0)
    }
    #[inline(always)]
    fn to_wire(&self) -> u8 {
        u8::from(*self)
    }
}
impl ArrayElement for bool {}

impl WireField for ByteBool {
    type Wire = ByteBool;
    type Writability = Writable;
    const KIND: FieldKind = FieldKind::Basic(BasicType::Bool);
    const IS_WIRE: bool = true;
    #[inline(always)]
    fn from_wire(wire: &ByteBool, _: Present<'_>) -> ByteBool {
        *wire
    }
    #[inline(always)]
    fn to_wire(&self) -> ByteBool {
        *self
    }
    fn visit(&self, path: &mut String, f: &mut dyn FnMut(&str, Value<'_>)) {
        f(path, Value::Bool(self.get()));
    }
}
impl ArrayElement for ByteBool {}

impl<const N: usize> WireField for CharArray<N> {
    type Wire = CharArray<N>;
    type Writability = Writable;
    const KIND: FieldKind = FieldKind::Basic(BasicType::Char);
    const COUNT: Option<usize> = Some(N);
    const IS_WIRE: bool = true;
    #[inline(always)]
    fn from_wire(wire: &CharArray<N>, _: Present<'_>) -> CharArray<N> {
        *wire
    }
    from_image_bytes!(CharArray<N>, CharArray);
    #[inline(always)]
    fn to_wire(&self) -> CharArray<N> {
        *self
    }
}

/// The size of `T`'s wire image.
pub const fn wire_size<T: WireField>() -> usize {
    core::mem::size_of::<T::Wire>()
}

/// The payload offset of a field the log lacks: read as zeros (only optional fields,
/// which are then not read, have it).
pub const NOWHERE: u32 = u32::MAX;

/// A payload offset whose value the log holds in another basic type, or as a
/// shorter array, than the binding ([`Converted`]): this bit set, the offset in the
/// low 16 bits (payloads are shorter than 64 KiB), the log's type's
/// [index](BasicType::index) in the next 4, its array length (0 for one value) in the
/// next 11.
const CONVERTED: u32 = 1 << 31;

/// Where a plan found a field that a binding reads in a type or length of its own
/// (a [widening](BasicType::widens_to), a shorter array, or a conversion the field
/// declares): the offset, the log's type and length, packed into a payload offset.
#[doc(hidden)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Converted {
    /// The byte offset in the payload.
    pub at: usize,
    /// The log's basic type.
    pub ty: BasicType,
    /// The log's array length (`None` for one value).
    pub len: Option<usize>,
}

/// The longest log array a conversion reads (the 11 bits of [`CONVERTED`]).
pub(crate) const CONVERTED_MAX_LEN: usize = (1 << 11) - 1;

impl Converted {
    /// The packed payload offset; `None` when it does not fit.
    pub(crate) fn pack(self) -> Option<u32> {
        let at = u32::try_from(self.at).ok().filter(|&a| a <= 0xffff)?;
        let len = self.len.unwrap_or(0);
        (len <= CONVERTED_MAX_LEN)
            .then(|| CONVERTED | at | ((self.ty.index() as u32) << 16) | ((len as u32) << 20))
    }

    /// The conversion a payload offset holds, if it is one.
    #[inline]
    pub fn unpack(source: u32) -> Option<Converted> {
        if source & CONVERTED == 0 || source == NOWHERE {
            return None;
        }
        let len = ((source >> 20) & 0x7ff) as usize;
        Some(Converted {
            at: (source & 0xffff) as usize,
            ty: BasicType::ALL[((source >> 16) & 0xf) as usize % 12],
            len: (len > 0).then_some(len),
        })
    }

    /// Element `i` of the log's value, as a [`Widened`]; `None` past the payload.
    #[inline]
    pub fn element(&self, payload: &[u8], i: usize) -> Option<Widened> {
        let size = self.ty.size();
        let at = self.at + i * size;
        let b = payload.get(at..at + size)?;
        let mut w = [0u8; 8];
        w[..size].copy_from_slice(b);
        let u = u64::from_le_bytes(w);
        Some(match self.ty {
            BasicType::UInt8 | BasicType::UInt16 | BasicType::UInt32 | BasicType::UInt64 => {
                Widened::Unsigned(u)
            }
            BasicType::Int8 => Widened::Signed(i64::from(b[0] as i8)),
            BasicType::Int16 => Widened::Signed(i64::from(u as u16 as i16)),
            BasicType::Int32 => Widened::Signed(i64::from(u as u32 as i32)),
            BasicType::Int64 => Widened::Signed(u as i64),
            BasicType::Float => Widened::Float(f64::from(f32::from_bits(u as u32))),
            BasicType::Double => Widened::Float(f64::from_bits(u)),
            BasicType::Bool => Widened::Unsigned(u64::from(b[0] != 0)),
            BasicType::Char => Widened::Unsigned(u64::from(b[0])),
        })
    }

    /// Element `i` of the log's value as the native type `N` of the log's type
    /// (a field's declared conversion, `#[ulog(convert(…))]`); zero when the
    /// payload does not hold it (generated code).
    #[inline]
    pub fn native<N: WireField>(&self, payload: &[u8], i: usize) -> N {
        let at = self.at + i * self.ty.size();
        read_from::<N>(payload, at as u32, Present::ALL)
    }
}

/// One log value on its way to a wider type: its exact value in the widest type of
/// its kind (generated code).
#[doc(hidden)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Widened {
    /// An unsigned integer, `bool` (0 or 1) or `char`.
    Unsigned(u64),
    /// A signed integer.
    Signed(i64),
    /// A `float` or `double`.
    Float(f64),
}

impl Widened {
    /// As an unsigned integer (`None` for signed and float values: the plan never
    /// widens them to one).
    #[inline]
    pub(crate) fn unsigned(self) -> Option<u64> {
        match self {
            Widened::Unsigned(u) => Some(u),
            _ => None,
        }
    }

    /// As a signed integer (`u64` values above `i64::MAX` never reach here: no
    /// unsigned type widens to a signed one of its size).
    #[inline]
    pub(crate) fn signed(self) -> Option<i64> {
        match self {
            Widened::Unsigned(u) => i64::try_from(u).ok(),
            Widened::Signed(i) => Some(i),
            Widened::Float(_) => None,
        }
    }

    /// As a float (exact for every widening to `float` or `double`).
    #[inline]
    pub(crate) fn float(self) -> f64 {
        match self {
            Widened::Unsigned(u) => u as f64,
            Widened::Signed(i) => i as f64,
            Widened::Float(f) => f,
        }
    }
}

/// The `T` at byte `at` of a payload; zeros where the payload does not hold it (see
/// [`NOWHERE`]), or, for a [`Converted`] offset, the log's value widened.
#[inline(always)]
fn read_from<T: WireField>(payload: &[u8], at: u32, present: Present<'_>) -> T {
    if at & CONVERTED != 0 && at != NOWHERE {
        return read_converted::<T>(payload, at, 0, present);
    }
    match payload
        .get(at as usize..)
        .and_then(|p| T::Wire::ref_from_prefix(p).ok())
    {
        Some((wire, _)) => T::from_wire(wire, present),
        None => T::from_wire(&T::Wire::new_zeroed(), present),
    }
}

/// Element `i` of a converted field: the log's value widened to `T`; zeros past the
/// log's array or payload.
#[cold]
fn read_converted<T: WireField>(payload: &[u8], at: u32, i: usize, present: Present<'_>) -> T {
    let value = Converted::unpack(at)
        .filter(|c| i < c.len.unwrap_or(1))
        .and_then(|c| c.element(payload, i))
        .and_then(T::from_widened);
    match value {
        Some(v) => v,
        None => T::from_wire(&T::Wire::new_zeroed(), present),
    }
}

/// How many payload offsets a `[T; N]` field takes: one for basic types, whose
/// elements follow each other in the log as in the binding, else one set per element
/// (generated code).
pub const fn array_sources<T: WireField>(n: usize) -> usize {
    match T::KIND {
        FieldKind::Basic(_) => 1,
        FieldKind::Nested(_) => n * T::SOURCES,
    }
}

/// Reads the `T` whose offsets start at `sources[k]` from a payload (generated code).
#[inline(always)]
pub fn read_source<T: WireField>(
    payload: &[u8],
    sources: &[u32],
    k: usize,
    present: Present<'_>,
) -> T {
    T::from_payload(payload, sources.get(k..).unwrap_or(&[]), present)
}

/// Reads the `[T; N]` whose offsets start at `sources[k]` from a payload (generated
/// code): basic elements at once from one offset, bindings each from their own.
#[inline(always)]
pub fn read_array_source<T: WireField, const N: usize>(
    payload: &[u8],
    sources: &[u32],
    k: usize,
    present: Present<'_>,
) -> [T; N] {
    match T::KIND {
        FieldKind::Basic(_) => {
            let at = sources.get(k).copied().unwrap_or(NOWHERE);
            if at & CONVERTED != 0 && at != NOWHERE {
                return core::array::from_fn(|i| read_converted::<T>(payload, at, i, present));
            }
            match payload
                .get(at as usize..)
                .and_then(|p| <[T::Wire; N]>::ref_from_prefix(p).ok())
            {
                Some((wire, _)) => core::array::from_fn(|i| T::from_wire(&wire[i], present)),
                None => core::array::from_fn(|_| T::from_wire(&T::Wire::new_zeroed(), present)),
            }
        }
        FieldKind::Nested(_) => core::array::from_fn(|i| {
            read_source::<T>(payload, sources, k + i * T::SOURCES, present)
        }),
    }
}

/// Reads the `T` whose offset is `sources[k]` through the conversion a field declares
/// (`#[ulog(convert(TYPE = function))]`): `convert` of the log's value of native type
/// `N` when the plan found the field of that type (`ty`), else as
/// [`read_source`] reads it (generated code).
#[inline(always)]
pub fn read_declared<N: WireField, T: WireField>(
    payload: &[u8],
    sources: &[u32],
    k: usize,
    ty: BasicType,
    convert: impl Fn(N) -> T,
    present: Present<'_>,
) -> T {
    let at = sources.get(k).copied().unwrap_or(NOWHERE);
    match Converted::unpack(at) {
        Some(c) if c.ty == ty => convert(c.native::<N>(payload, 0)),
        _ => read_source::<T>(payload, sources, k, present),
    }
}

/// [`read_declared`] of an array field: element by element, the binding's elements
/// beyond the log's array zeros (generated code).
#[inline(always)]
pub fn read_declared_array<N: WireField, T: WireField, const LEN: usize>(
    payload: &[u8],
    sources: &[u32],
    k: usize,
    ty: BasicType,
    convert: impl Fn(N) -> T,
    present: Present<'_>,
) -> [T; LEN] {
    let at = sources.get(k).copied().unwrap_or(NOWHERE);
    match Converted::unpack(at) {
        Some(c) if c.ty == ty => core::array::from_fn(|i| {
            if i < c.len.unwrap_or(1) {
                convert(c.native::<N>(payload, i))
            } else {
                T::from_wire(&T::Wire::new_zeroed(), present)
            }
        }),
        _ => read_array_source::<T, LEN>(payload, sources, k, present),
    }
}

/// Reads the `T` at `offset` of a binding's wire image (generated code).
#[inline(always)]
pub fn read<T: WireField>(wire: &[u8], offset: usize, present: Present<'_>) -> T {
    let value = match wire.get(offset..offset + wire_size::<T>()) {
        Some(bytes) => T::from_image(bytes, present),
        None => None,
    };
    match value {
        Some(value) => value,
        None => beyond_image(offset),
    }
}

/// A field read past its image's end: generated code never asks for one.
#[cold]
#[inline(never)]
fn beyond_image(offset: usize) -> ! {
    panic!("a field at byte {offset} is beyond its wire image")
}

/// Reads the `[T; N]` at `offset` of a binding's wire image (generated code).
#[inline(always)]
pub fn read_array<T: WireField, const N: usize>(
    wire: &[u8],
    offset: usize,
    present: Present<'_>,
) -> [T; N] {
    core::array::from_fn(|i| read::<T>(wire, offset + i * wire_size::<T>(), present))
}

/// Writes `value` at `offset` of a binding's wire image (generated code).
#[inline(always)]
pub fn write<T: WireField>(wire: &mut [u8], offset: usize, value: &T) {
    let image = value.to_wire();
    match wire.get_mut(offset..offset + wire_size::<T>()) {
        Some(out) => out.copy_from_slice(image.as_bytes()),
        None => beyond_image(offset),
    }
}

/// Writes `values` from `offset` of a binding's wire image (generated code).
#[inline(always)]
pub fn write_array<T: WireField>(wire: &mut [u8], offset: usize, values: &[T]) {
    for (i, v) in values.iter().enumerate() {
        write(wire, offset + i * wire_size::<T>(), v);
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
    value.visit(path, f);
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
        value.visit(path, f);
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
        _ => f(path, Value::Str(LogText(bytes))),
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
        assert!(bool::from_wire(&2, Present::ALL));
        assert_eq!(true.to_wire(), 1);
        let seven = le::U64::from_bytes(7u64.to_le_bytes());
        assert_eq!(u64::from_wire(&seven, Present::ALL), 7);
        let mut image = [0u8; 12];
        write(&mut image, 4, &-5i64);
        assert_eq!(read::<i64>(&image, 4, Present::ALL), -5);
        write_array(&mut image, 0, &[1u16, 2]);
        assert_eq!(read_array::<u16, 2>(&image, 0, Present::ALL), [1, 2]);
    }

    #[test]
    fn presence_slots_and_nested_ranges() {
        let slots = [true, false, true];
        let p = Present::new(&slots);
        assert!(p.get(0) && !p.get(1) && p.get(2));
        assert!(!p.sub(1, 2).get(0));
        assert!(p.sub(1, 0).get(0), "no slots: everything present");
        assert!(Present::ALL.get(7));
    }
}
