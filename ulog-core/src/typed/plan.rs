//! `Plan`: a log's format checked against a binding once, then a decode per payload.
//!
//! Validation walks the binding's fields, finds each in the log's layout by name or
//! alias, and records where each lies in the log's payload. When every field lies
//! where the log has it, the plan is [`PlanKind::Exact`] and a payload's first bytes
//! *are* the binding's wire image; otherwise it is [`PlanKind::Mapped`] and each field
//! is read from its own offset (`WireField::from_payload`). No name is looked up after
//! validation. This is the one rule every typed reader uses.

use core::fmt;
use core::marker::PhantomData;

use ulog_format::{BasicType, Layout, LayoutField, LayoutType};
use zerocopy::{FromZeros, IntoBytes};

use super::error::{DecodeError, DecodeErrorKind, Difference, DifferenceKind, Mismatch};
use super::message::ULogMessage;
use super::schema::{Absent, FieldDef, FieldKind, Schema};
use super::wire::{Converted, Present, WireField, NOWHERE};
use crate::audited::WireImage;

/// How a plan decodes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PlanKind {
    /// Every field of the binding lies where the log has it, and the binding ends
    /// within the log's format (it may leave out the trailing padding, or fields at
    /// the end): a payload is decoded in place, or borrowed
    /// ([`TypedRows::views`](crate::TypedRows::views)).
    Exact,
    /// Fields lie elsewhere in the log's payload, or the log lacks optional ones:
    /// each is read from its offset.
    Mapped,
}

/// One copy of a mapped plan.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct CopyOp {
    src: usize,
    dst: usize,
    len: usize,
}

/// A plan with its binding type erased (shared by [`Plan`] and the topic enums).
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct RawPlan {
    kind: PlanKind,
    /// Whether payloads are decoded by [`WireField::from_payload`] from `sources`
    /// (derived bindings), else through a wire image of the binding: the payload's
    /// prefix (exact plans) or `copies` (a hand-written `WireField`).
    direct: bool,
    /// Where each field of the binding is in the log's payload, in field order.
    sources: Box<[u32]>,
    copies: Box<[CopyOp]>,
    /// The log's full payload size, and its size without trailing padding.
    size: usize,
    min_size: usize,
    /// The binding's size.
    own: usize,
    /// Whether each optional field of the binding is in the log (empty: it has
    /// none).
    present: Box<[bool]>,
    /// Why the plan is not exact.
    why: Option<String>,
}

/// What a plan needs of a binding's type.
pub(crate) struct BindingOf {
    schema: &'static Schema,
    direct: bool,
    sources: usize,
    optional: usize,
    own: usize,
}

impl BindingOf {
    #[inline]
    pub(crate) fn of<T: ULogMessage>() -> BindingOf {
        BindingOf {
            schema: T::schema(),
            direct: T::DIRECT,
            sources: T::SOURCES,
            optional: T::OPTIONAL,
            own: core::mem::size_of::<T::Wire>(),
        }
    }

    /// The binding's schema.
    pub(crate) fn schema(&self) -> &'static Schema {
        self.schema
    }
}

/// What the walk over a binding's fields collects.
struct Walk {
    sources: Vec<u32>,
    copies: Vec<CopyOp>,
    differences: Vec<Difference>,
    present: Vec<bool>,
    why: Option<String>,
    /// The fields read in another type or length than the log's ([`Converted`]).
    converted: Vec<String>,
}

impl RawPlan {
    pub(crate) fn new<T: ULogMessage>(file: &Layout) -> Result<RawPlan, Mismatch> {
        RawPlan::build(&BindingOf::of::<T>(), file)
    }

    /// [`RawPlan::new`] past what depends on the binding's type: the one copy of it
    /// in a program, however many bindings it plans.
    pub(crate) fn build(binding: &BindingOf, file: &Layout) -> Result<RawPlan, Mismatch> {
        let schema = binding.schema;
        let mut walk = Walk {
            sources: Vec::new(),
            copies: Vec::new(),
            differences: Vec::new(),
            present: Vec::new(),
            why: None,
            converted: Vec::new(),
        };
        map_fields(schema, file, "", 0, 0, &mut walk);
        if !binding.direct {
            // A binding implemented by hand is decoded through its wire image, a copy
            // of the log's bytes: it reads no converted field.
            for path in walk.converted.drain(..) {
                walk.differences.push(Difference {
                    path,
                    kind: DifferenceKind::NotConvertible,
                });
            }
        }
        if !walk.differences.is_empty() {
            return Err(Mismatch {
                message: schema.name().to_owned(),
                binding: schema.rust_name().to_owned(),
                differences: walk.differences,
                expected_formats: schema.formats().iter().map(|f| f.to_string()).collect(),
                found_formats: file.formats().iter().map(|f| f.to_string()).collect(),
            });
        }
        debug_assert_eq!(walk.present.len(), binding.optional, "presence slots");
        let own = binding.own;
        if walk.why.is_none() && own > file.size() {
            walk.why = Some(format!(
                "the binding has {own} bytes, the log's format {}",
                file.size()
            ));
        }
        let mut copies = walk.copies;
        copies.sort_by_key(|c| c.dst);
        let mut merged: Vec<CopyOp> = Vec::with_capacity(copies.len());
        for c in copies {
            match merged.last_mut() {
                Some(last) if last.src + last.len == c.src && last.dst + last.len == c.dst => {
                    last.len += c.len;
                }
                _ => merged.push(c),
            }
        }
        let all_present = walk.present.iter().all(|&p| p);
        // A derived binding counts its offsets as the walk does; one implemented by
        // hand is decoded through its wire image.
        debug_assert!(
            !binding.direct || walk.sources.len() == binding.sources,
            "payload offsets of `{}`",
            schema.rust_name()
        );
        let direct = binding.direct && walk.sources.len() == binding.sources;
        Ok(RawPlan {
            direct,
            sources: walk.sources.into_boxed_slice(),
            kind: if walk.why.is_none() {
                PlanKind::Exact
            } else {
                PlanKind::Mapped
            },
            copies: merged.into_boxed_slice(),
            size: file.size(),
            min_size: file.min_size(),
            own,
            present: if all_present {
                Box::new([])
            } else {
                walk.present.into_boxed_slice()
            },
            why: walk.why,
        })
    }

    pub(crate) fn length_error(&self, len: usize) -> DecodeError {
        DecodeError {
            kind: DecodeErrorKind::Length {
                size: self.size,
                min_size: self.min_size,
            },
            len,
        }
    }

    pub(crate) fn present(&self) -> Present<'_> {
        if self.present.is_empty() {
            Present::ALL
        } else {
            Present::new(&self.present)
        }
    }

    #[inline(always)]
    pub(crate) fn decode<T: WireField>(&self, payload: &[u8]) -> Result<T, DecodeError> {
        if T::READS_IMAGE {
            return self.decode_image::<T>(payload);
        }
        let payload = self.checked(payload)?;
        if self.kind == PlanKind::Exact {
            if let Some(image) = payload.get(..self.own) {
                return match T::from_image(image, self.present()) {
                    Some(value) => Ok(value),
                    None => Err(self.length_error(payload.len())),
                };
            }
        }
        if self.direct {
            return Ok(T::from_payload(payload, &self.sources, self.present()));
        }
        let mut wire = T::Wire::new_zeroed();
        self.fill_wire(payload, wire.as_mut_bytes())?;
        Ok(T::from_wire(&wire, self.present()))
    }

    /// [`decode`](RawPlan::decode) of a binding read only through its wire image:
    /// one call of its code, on the image that [`image`](RawPlan::image) finds or
    /// fills. What depends on the binding is only that call and the image's size, so
    /// that each binding a program reads adds little code (bench/README.md, what
    /// `ulog_module!` costs a crate).
    #[inline]
    fn decode_image<T: WireField>(&self, payload: &[u8]) -> Result<T, DecodeError> {
        let mut wire = T::Wire::new_zeroed();
        let image = self.image(payload, wire.as_mut_bytes(), T::KIND)?;
        match T::from_image(image, self.present()) {
            Some(value) => Ok(value),
            None => Err(self.length_error(payload.len())),
        }
    }

    /// The binding's wire image of a payload: the payload's prefix (an exact plan), or
    /// `wire` (the binding's size) zeroed and filled from it.
    #[inline]
    pub(crate) fn image<'p>(
        &self,
        payload: &'p [u8],
        wire: &'p mut [u8],
        kind: FieldKind,
    ) -> Result<&'p [u8], DecodeError> {
        Ok(match self.exact_image(payload)? {
            Some(image) => image,
            None => {
                wire.fill(0);
                self.fill_image(payload, wire, kind)?;
                wire
            }
        })
    }

    /// The payload's prefix that is the binding's wire image (an exact plan); `None`
    /// when the image is to be filled ([`fill_image`](RawPlan::fill_image)).
    fn exact_image<'p>(&self, payload: &'p [u8]) -> Result<Option<&'p [u8]>, DecodeError> {
        let payload = self.checked(payload)?;
        Ok(match self.kind {
            PlanKind::Exact => payload.get(..self.own),
            PlanKind::Mapped => None,
        })
    }

    /// Fills a binding's wire image (zeros) from a payload: by the payload offsets
    /// and the table of the binding's schema (`kind`) when the plan reads offsets,
    /// else by its copies.
    fn fill_image(
        &self,
        payload: &[u8],
        image: &mut [u8],
        kind: FieldKind,
    ) -> Result<(), DecodeError> {
        let payload = self.checked(payload)?;
        match kind {
            FieldKind::Nested(schema) if self.direct => {
                super::binding::fill_image(schema(), payload, &self.sources, image);
                Ok(())
            }
            _ => self.fill_wire(payload, image),
        }
    }

    /// The bytes of `payload` that its format describes, when its length is the
    /// format's (with or without trailing padding).
    #[inline]
    fn checked<'p>(&self, payload: &'p [u8]) -> Result<&'p [u8], DecodeError> {
        let payload = self.format_bytes(payload);
        let len = payload.len();
        if len != self.size && len != self.min_size {
            return Err(self.length_error(len));
        }
        Ok(payload)
    }

    /// Fills a binding's wire image (zeros) from a payload of the right length, for a
    /// binding decoded through its image: the payload's prefix (an exact plan whose
    /// binding declares trailing padding the payload leaves out), else the copies.
    fn fill_wire(&self, payload: &[u8], image: &mut [u8]) -> Result<(), DecodeError> {
        let len = payload.len();
        if self.kind == PlanKind::Exact {
            let n = len.min(image.len());
            image[..n].copy_from_slice(&payload[..n]);
            return Ok(());
        }
        for c in self.copies.iter() {
            let src = payload.get(c.src..c.src + c.len);
            let dst = image.get_mut(c.dst..c.dst + c.len);
            match (src, dst) {
                (Some(src), Some(dst)) => copy_field(dst, src),
                _ => return Err(self.length_error(len)),
            }
        }
        Ok(())
    }

    /// The bytes of a payload that its format describes: all of them, but for a data
    /// message longer than its format (reported by the reader as a size mismatch and
    /// kept), whose fields are where the format puts them.
    #[inline(always)]
    fn format_bytes<'a>(&self, payload: &'a [u8]) -> &'a [u8] {
        payload.get(..self.size).unwrap_or(payload)
    }

    /// Borrows a payload as `T` (see [`Plan::view`]).
    pub(crate) fn view<'a, T: WireField + WireImage>(
        &self,
        payload: &'a [u8],
    ) -> Result<&'a T, DecodeError> {
        const {
            assert!(
                T::IS_WIRE,
                "a view needs a binding whose memory is its wire image: fields of `u8`, `i8`, `CharArray<N>`, `ulog_core::typed::le` types, arrays and nested such bindings (no `bool`, no `Option`)"
            )
        };
        let payload = self.checked(payload)?;
        self.viewable(payload.len(), core::mem::size_of::<T>())?;
        Ok(crate::audited::view::<T>(payload))
    }

    /// Whether a payload of `len` bytes can be borrowed as a binding of `needed`.
    fn viewable(&self, len: usize, needed: usize) -> Result<(), DecodeError> {
        if let Some(why) = &self.why {
            return Err(DecodeError {
                kind: DecodeErrorKind::ViewNeedsExactLayout { why: why.clone() },
                len,
            });
        }
        if len < needed {
            return Err(DecodeError {
                kind: DecodeErrorKind::ViewNeedsLongerPayload { needed },
                len,
            });
        }
        Ok(())
    }
}

/// Copies `src` into `dst` (of the same length). Fields are short: lengths up to 32
/// are copied as two overlapping fixed-size moves, without a call to `memcpy`.
#[inline(always)]
fn copy_field(dst: &mut [u8], src: &[u8]) {
    let n = src.len();
    if n != dst.len() {
        return dst.copy_from_slice(src);
    }
    macro_rules! pair {
        ($w:expr) => {{
            dst[..$w].copy_from_slice(&src[..$w]);
            dst[n - $w..].copy_from_slice(&src[n - $w..]);
        }};
    }
    match n {
        0 => {}
        1 => dst[0] = src[0],
        2..=3 => pair!(2),
        4..=7 => pair!(4),
        8..=15 => pair!(8),
        16..=32 => pair!(16),
        _ => dst.copy_from_slice(src),
    }
}

/// Finds every field of `schema` in `file` (whose fields lie from `src` in the log's
/// payload, the binding's from `dst`), pushing copies, differences and presence.
fn map_fields(
    schema: &Schema,
    file: &Layout,
    prefix: &str,
    src: usize,
    dst: usize,
    walk: &mut Walk,
) {
    for (def, own) in schema.fields().iter().zip(schema.layout().fields()) {
        if own.is_padding() {
            continue;
        }
        let path = format!("{prefix}{}", def.name());
        let nested_slots = match def.kind() {
            FieldKind::Nested(nested) => nested().optional_slots(),
            FieldKind::Basic(_) => 0,
        };
        let found = core::iter::once(def.name())
            .chain(def.aliases().iter().copied())
            .find_map(|name| file.field(name).filter(|f| !f.is_padding()));
        let optional = def.absent() != Absent::Required;
        let Some(theirs) = found else {
            walk.sources
                .extend(core::iter::repeat(NOWHERE).take(field_sources(def, own)));
            if optional {
                walk.present.push(false);
                walk.present
                    .extend(core::iter::repeat(false).take(nested_slots));
                walk.why
                    .get_or_insert_with(|| format!("field `{path}` is not in the log"));
            } else {
                walk.differences.push(Difference {
                    path,
                    kind: DifferenceKind::MissingField {
                        closest: closest_unbound(def.name(), schema, file),
                    },
                });
            }
            continue;
        };
        if optional {
            walk.present.push(true);
        }
        let (from, to) = (src + theirs.offset, dst + own.offset);
        if from != to {
            walk.why.get_or_insert_with(|| {
                format!(
                    "field `{path}` is at byte {from} of the log's payload, {to} of the binding"
                )
            });
        }
        let lengths_agree = own.array_len == theirs.array_len;
        if let (LayoutType::Basic(mine), LayoutType::Basic(log)) = (&own.ty, &theirs.ty) {
            if *mine == *log && lengths_agree {
                walk.sources.push(u32::try_from(from).unwrap_or(NOWHERE));
                walk.copies.push(CopyOp {
                    src: from,
                    dst: to,
                    len: own.size,
                });
            } else {
                convert_basic(def, own, theirs, *mine, *log, from, &path, walk);
            }
            continue;
        }
        if !lengths_agree {
            walk.differences.push(Difference {
                path: path.clone(),
                kind: DifferenceKind::ArrayLength {
                    expected: own.array_len,
                    found: theirs.array_len,
                },
            });
        }
        match (&own.ty, &theirs.ty, def.kind()) {
            (LayoutType::Nested(mine), LayoutType::Nested(other), FieldKind::Nested(nested)) => {
                // The elements are compared whatever the lengths, so that every
                // difference inside them is listed too.
                let inner_prefix = match own.array_len {
                    Some(_) => format!("{path}[*]."),
                    None => format!("{path}."),
                };
                let mut inner = Walk {
                    sources: Vec::new(),
                    copies: Vec::new(),
                    differences: Vec::new(),
                    present: Vec::new(),
                    why: None,
                    converted: Vec::new(),
                };
                map_fields(nested(), other, &inner_prefix, 0, 0, &mut inner);
                walk.differences.append(&mut inner.differences);
                walk.converted.append(&mut inner.converted);
                walk.present.append(&mut inner.present);
                if let Some(why) = inner.why {
                    walk.why.get_or_insert(why);
                }
                for i in 0..own.array_len.unwrap_or(1) {
                    let base = from + i * other.size();
                    walk.sources.extend(inner.sources.iter().map(|&s| {
                        match (s, Converted::unpack(s)) {
                            (NOWHERE, _) => s,
                            (_, Some(c)) => Converted {
                                at: base + c.at,
                                ..c
                            }
                            .pack()
                            .unwrap_or(NOWHERE),
                            _ => u32::try_from(base + s as usize).unwrap_or(NOWHERE),
                        }
                    }));
                }
                if lengths_agree {
                    for i in 0..own.array_len.unwrap_or(1) {
                        for c in &inner.copies {
                            walk.copies.push(CopyOp {
                                src: from + i * other.size() + c.src,
                                dst: to + i * mine.size() + c.dst,
                                len: c.len,
                            });
                        }
                    }
                    if other.size() != mine.size() && own.array_len.is_some() {
                        walk.why.get_or_insert_with(|| {
                            format!(
                                "the elements of `{path}` have {} bytes in the log, {} in the binding",
                                other.size(),
                                mine.size()
                            )
                        });
                    }
                }
            }
            (a, b, _) => walk.differences.push(Difference {
                path,
                kind: DifferenceKind::Type {
                    expected: a.name().to_owned(),
                    found: b.name().to_owned(),
                },
            }),
        }
    }
}

/// The field of the log's format `file` closest to `name` (a field of `schema` that
/// the log lacks), among those no field of `schema` reads by name or alias.
fn closest_unbound(name: &str, schema: &Schema, file: &Layout) -> Option<String> {
    let bound = |n: &str| {
        schema
            .fields()
            .iter()
            .any(|d| d.name() == n || d.aliases().contains(&n))
    };
    let unbound = file
        .fields()
        .iter()
        .filter(|f| !f.is_padding() && !bound(&f.name))
        .map(|f| f.name.as_str());
    crate::suggest::closest(name, unbound)
}

/// A basic field the log holds in another type or array length than the binding:
/// read through a [`Converted`] offset when every value of the log's converts
/// exactly (a [widening](ulog_format::BasicType::widens_to), or a conversion the
/// field declares, `#[ulog(convert(…))]`) and a log array is no longer than the
/// binding's (the binding's further elements are zeros); else a difference. `char`
/// strings and `bool`s take no other type.
#[allow(clippy::too_many_arguments)]
fn convert_basic(
    def: &FieldDef,
    own: &LayoutField,
    theirs: &LayoutField,
    mine: BasicType,
    log: BasicType,
    from: usize,
    path: &str,
    walk: &mut Walk,
) {
    let declared = def.converts().contains(&log);
    let type_ok = mine != BasicType::Char
        && (log == mine || (mine != BasicType::Bool && log.widens_to(mine)) || declared);
    let length_ok = match (own.array_len, theirs.array_len) {
        (a, b) if a == b => true,
        (Some(a), Some(b)) => b <= a && mine != BasicType::Char,
        _ => false,
    };
    let packed = Converted {
        at: from,
        ty: log,
        len: theirs.array_len,
    }
    .pack();
    match packed {
        Some(source) if type_ok && length_ok => {
            walk.sources.push(source);
            walk.converted.push(path.to_owned());
            walk.why
                .get_or_insert_with(|| match (log == mine, own.array_len, theirs.array_len) {
                    (true, Some(a), Some(b)) => {
                        format!("field `{path}` has {b} elements in the log, {a} in the binding")
                    }
                    _ => format!("field `{path}` is `{log}` in the log, `{mine}` in the binding"),
                });
        }
        _ => {
            walk.sources.push(NOWHERE);
            if !length_ok {
                walk.differences.push(Difference {
                    path: path.to_owned(),
                    kind: DifferenceKind::ArrayLength {
                        expected: own.array_len,
                        found: theirs.array_len,
                    },
                });
            }
            if !type_ok {
                walk.differences.push(Difference {
                    path: path.to_owned(),
                    kind: DifferenceKind::Type {
                        expected: mine.name().to_owned(),
                        found: log.name().to_owned(),
                    },
                });
            }
        }
    }
}

/// How many payload offsets field `def` (laid out as `own` in the binding) takes: as
/// `WireField::SOURCES` counts them.
fn field_sources(def: &FieldDef, own: &LayoutField) -> usize {
    match def.kind() {
        FieldKind::Basic(_) => 1,
        FieldKind::Nested(nested) => own.array_len.unwrap_or(1) * schema_sources(nested()),
    }
}

/// How many payload offsets a binding takes: its fields', padding none.
fn schema_sources(schema: &Schema) -> usize {
    schema
        .fields()
        .iter()
        .zip(schema.layout().fields())
        .filter(|(_, own)| !own.is_padding())
        .map(|(def, own)| field_sources(def, own))
        .sum()
}

/// A log's format checked against binding `T`, once per subscription: decodes each
/// payload of that subscription into a `T`.
///
/// ```
/// # #[cfg(feature = "derive")] {
/// use ulog_core::typed::{Plan, PlanKind};
/// use ulog_core::format::{Format, Layout};
///
/// #[derive(ulog_core::ULogMessage, Debug, PartialEq)]
/// #[ulog(crate = "ulog_core")]
/// struct VehicleAttitude {
///     timestamp: u64,
///     q: [f32; 4],
/// }
///
/// // A newer log: other fields around ours, in another order.
/// let format = Format::parse("vehicle_attitude:float[4] q;uint64_t timestamp;uint8_t yaw_reset;").unwrap();
/// let layout = Layout::resolve("vehicle_attitude", &[format][..]).unwrap();
/// let plan = Plan::<VehicleAttitude>::new(&layout).unwrap();
/// assert_eq!(plan.kind(), PlanKind::Mapped);
///
/// let mut payload = Vec::new();
/// for q in [1.0f32, 0.0, 0.0, 0.0] {
///     payload.extend_from_slice(&q.to_le_bytes());
/// }
/// payload.extend_from_slice(&42u64.to_le_bytes());
/// payload.push(0);
/// let att = plan.decode(&payload).unwrap();
/// assert_eq!(att, VehicleAttitude { timestamp: 42, q: [1.0, 0.0, 0.0, 0.0] });
/// assert!(plan.decode(&payload[1..]).is_err());
/// # }
/// ```
pub struct Plan<T> {
    raw: RawPlan,
    binding: PhantomData<fn() -> T>,
}

impl<T> Clone for Plan<T> {
    fn clone(&self) -> Plan<T> {
        Plan {
            raw: self.raw.clone(),
            binding: PhantomData,
        }
    }
}

impl<T> fmt::Debug for Plan<T> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Plan")
            .field("binding", &core::any::type_name::<T>())
            .field("kind", &self.raw.kind)
            .field("copies", &self.raw.copies.len())
            .finish()
    }
}

impl<T: ULogMessage> Plan<T> {
    /// Checks the log's layout of a subscription against `T`: every field of `T`
    /// must be in it, by name or alias, with the same type and array length, unless
    /// `T` says the field may be absent (`Option<F>`, `#[ulog(default)]`). Otherwise
    /// the error lists every difference.
    pub fn new(file_layout: &Layout) -> Result<Plan<T>, Mismatch> {
        RawPlan::new::<T>(file_layout).map(Plan::from_raw)
    }

    /// The plan past what depends on `T`.
    pub(crate) fn raw(&self) -> &RawPlan {
        &self.raw
    }

    /// The plan made by [`RawPlan::new`] for `T`.
    pub(crate) fn from_raw(raw: RawPlan) -> Plan<T> {
        Plan {
            raw,
            binding: PhantomData,
        }
    }

    /// Exact or mapped.
    pub fn kind(&self) -> PlanKind {
        self.raw.kind
    }

    /// Why the plan is not [`Exact`](PlanKind::Exact) (`None` when it is): the first
    /// field that lies elsewhere or is absent.
    pub fn why_mapped(&self) -> Option<&str> {
        self.raw.why.as_deref()
    }

    /// Whether each optional field of `T` (in field order, nested bindings' after the
    /// field that holds them) is in the log.
    pub fn present(&self) -> Vec<bool> {
        if self.raw.present.is_empty() {
            vec![true; T::OPTIONAL]
        } else {
            self.raw.present.to_vec()
        }
    }

    /// Decodes one payload (the data message after its `msg_id`). Its length must be
    /// the log format's size, with or without trailing padding.
    #[inline]
    pub fn decode(&self, payload: &[u8]) -> Result<T, DecodeError> {
        self.raw.decode::<T>(payload)
    }

    /// Borrows a payload as a `&T`, without copying. Needs an
    /// [`Exact`](PlanKind::Exact) plan, a payload that holds all of `T`, and a `T`
    /// whose memory is its wire image ([`WireImage`](super::WireImage)). For logs
    /// written by PX4, which leaves the trailing padding out, leave it out of `T` too.
    pub fn view<'a>(&self, payload: &'a [u8]) -> Result<&'a T, DecodeError>
    where
        T: WireImage,
    {
        self.raw.view::<T>(payload)
    }
}

#[cfg(test)]
mod tests {
    use std::sync::OnceLock;

    use ulog_format::{BasicType, Format};

    use super::*;
    use crate::typed::Writable;

    use crate::typed::hand_binding::Pair;

    /// A binding implemented by hand with one field and trailing padding: as many
    /// payload offsets (one) as its schema, by chance.
    #[derive(Debug, PartialEq)]
    struct Stamp {
        t: u64,
    }

    impl WireField for Stamp {
        type Wire = [u8; 16];
        type Writability = Writable;
        const KIND: FieldKind = FieldKind::Nested(<Stamp as ULogMessage>::schema);
        fn from_wire(w: &[u8; 16], _: Present<'_>) -> Stamp {
            let mut t = [0; 8];
            t.copy_from_slice(&w[..8]);
            Stamp {
                t: u64::from_le_bytes(t),
            }
        }
        fn to_wire(&self) -> [u8; 16] {
            let mut w = [0; 16];
            w[..8].copy_from_slice(&self.t.to_le_bytes());
            w
        }
    }

    impl ULogMessage for Stamp {
        const NAME: &'static str = "stamp";
        fn schema() -> &'static Schema {
            static FIELDS: [FieldDef; 2] = [
                FieldDef::new("t", &[], FieldKind::Basic(BasicType::UInt64), None),
                FieldDef::new(
                    "_padding0",
                    &[],
                    FieldKind::Basic(BasicType::UInt8),
                    Some(8),
                ),
            ];
            static SCHEMA: OnceLock<Schema> = OnceLock::new();
            SCHEMA.get_or_init(|| Schema::build("stamp", &FIELDS))
        }
    }

    /// A hand-written binding is never read from payload offsets, even where their
    /// count matches its own: its whole wire image would be read from its first
    /// field's offset. Here a payload that leaves the trailing padding out, and one
    /// with the field last.
    #[test]
    fn a_hand_written_binding_with_one_field_decodes_its_field() {
        for (format, payload) in [
            (
                "stamp:uint64_t t;uint8_t[8] _padding0;",
                &[5u8, 0, 0, 0, 0, 0, 0, 0][..],
            ),
            (
                "stamp:uint8_t x;uint64_t t;",
                &[9, 5, 0, 0, 0, 0, 0, 0, 0][..],
            ),
        ] {
            let format = Format::parse(format).unwrap();
            let layout = Layout::resolve("stamp", &[format][..]).unwrap();
            let plan = Plan::<Stamp>::new(&layout).unwrap();
            assert_eq!(plan.decode(payload).unwrap(), Stamp { t: 5 }, "{layout:?}");
        }
    }

    /// A hand-written binding whose offsets the plan cannot hand to `from_payload`
    /// still decodes a log that lays it out otherwise: through a wire image of it
    /// (derived bindings, which read from the payload, are decoded by every typed
    /// test).
    #[test]
    fn a_hand_written_binding_decodes_through_its_wire_image() {
        let format = Format::parse("pair:uint16_t b;uint8_t x;uint32_t a;").unwrap();
        let layout = Layout::resolve("pair", &[format][..]).unwrap();
        let plan = Plan::<Pair>::new(&layout).unwrap();
        assert_eq!(plan.kind(), PlanKind::Mapped);
        assert!(
            !plan.raw.direct,
            "a hand-written binding is not read from payload offsets"
        );
        let payload = [7, 0, 0xee, 1, 2, 0, 0];
        assert_eq!(plan.decode(&payload).unwrap(), Pair { a: 0x201, b: 7 });
    }
}
