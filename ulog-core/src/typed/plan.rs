//! `Plan`: a log's format checked against a binding once, then a decode per payload.
//!
//! Validation walks the binding's fields, finds each in the log's layout by name or
//! alias, and records one copy (log offset → binding offset, length) per field;
//! adjacent copies are merged. When every copy lands where it came from and the sizes
//! agree, the plan is [`PlanKind::Exact`] and a payload *is* the binding's wire image;
//! otherwise it is [`PlanKind::Mapped`] and decoding runs the short copy list. No name
//! is looked up after validation.

use core::fmt;
use core::marker::PhantomData;

use ulog_format::{Layout, LayoutType};
use zerocopy::{FromBytes, FromZeros, Immutable, IntoBytes, KnownLayout, Unaligned};

use super::error::{DecodeError, DecodeErrorKind, Difference, DifferenceKind, Mismatch};
use super::message::ULogMessage;
use super::schema::Schema;
use super::wire::{FieldKind, WireField};

/// How a plan decodes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PlanKind {
    /// The log's layout is the binding's: a payload is copied (or borrowed) whole.
    Exact,
    /// The fields lie elsewhere in the log's payload: each is copied from its offset.
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
    copies: Box<[CopyOp]>,
    size: usize,
    min_size: usize,
}

impl RawPlan {
    pub(crate) fn new<T: ULogMessage>(file: &Layout) -> Result<RawPlan, Mismatch> {
        let schema = T::schema();
        let mut copies = Vec::new();
        let mut differences = Vec::new();
        map_fields(schema, file, "", &mut copies, &mut differences);
        if !differences.is_empty() {
            return Err(Mismatch {
                message: schema.name().to_owned(),
                differences,
                expected_formats: schema.formats().iter().map(|f| f.to_string()).collect(),
                found_formats: file.formats().iter().map(|f| f.to_string()).collect(),
            });
        }
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
        let own = schema.layout();
        let exact = file.size() == own.size()
            && file.min_size() == own.min_size()
            && file.size() == core::mem::size_of::<T::Wire>()
            && merged.iter().all(|c| c.src == c.dst);
        Ok(RawPlan {
            kind: if exact {
                PlanKind::Exact
            } else {
                PlanKind::Mapped
            },
            copies: merged.into_boxed_slice(),
            size: file.size(),
            min_size: file.min_size(),
        })
    }

    fn length_error(&self, len: usize) -> DecodeError {
        DecodeError {
            kind: DecodeErrorKind::Length {
                size: self.size,
                min_size: self.min_size,
            },
            len,
        }
    }

    pub(crate) fn decode<T: WireField>(&self, payload: &[u8]) -> Result<T, DecodeError> {
        let len = payload.len();
        if len != self.size && len != self.min_size {
            return Err(self.length_error(len));
        }
        if self.kind == PlanKind::Exact && len == self.size {
            return match T::Wire::ref_from_bytes(payload) {
                Ok(wire) => Ok(T::from_wire(wire)),
                Err(_) => Err(self.length_error(len)),
            };
        }
        let mut wire = T::Wire::new_zeroed();
        let image = wire.as_mut_bytes();
        if self.kind == PlanKind::Exact {
            match image.get_mut(..len) {
                Some(prefix) => prefix.copy_from_slice(payload),
                None => return Err(self.length_error(len)),
            }
        } else {
            for c in self.copies.iter() {
                let src = payload.get(c.src..c.src + c.len);
                let dst = image.get_mut(c.dst..c.dst + c.len);
                match (src, dst) {
                    (Some(src), Some(dst)) => copy_field(dst, src),
                    _ => return Err(self.length_error(len)),
                }
            }
        }
        Ok(T::from_wire(&wire))
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

/// Finds every field of `schema` in `file`, pushing copies (relative to the starts of
/// both) and differences.
fn map_fields(
    schema: &Schema,
    file: &Layout,
    prefix: &str,
    copies: &mut Vec<CopyOp>,
    differences: &mut Vec<Difference>,
) {
    for (def, own) in schema.fields().iter().zip(schema.layout().fields()) {
        if own.is_padding() {
            continue;
        }
        let path = format!("{prefix}{}", def.name());
        let mut difference = |kind| {
            differences.push(Difference {
                path: path.clone(),
                kind,
            })
        };
        let found = core::iter::once(def.name())
            .chain(def.aliases().iter().copied())
            .find_map(|name| file.field(name).filter(|f| !f.is_padding()));
        let Some(theirs) = found else {
            difference(DifferenceKind::MissingField);
            continue;
        };
        if own.array_len != theirs.array_len {
            difference(DifferenceKind::ArrayLength {
                expected: own.array_len,
                found: theirs.array_len,
            });
            continue;
        }
        match (&own.ty, &theirs.ty, def.kind()) {
            (LayoutType::Basic(a), LayoutType::Basic(b), _) if a == b => copies.push(CopyOp {
                src: theirs.offset,
                dst: own.offset,
                len: own.size,
            }),
            (LayoutType::Nested(mine), LayoutType::Nested(other), FieldKind::Nested(nested)) => {
                let mut inner = Vec::new();
                let mut inner_differences = Vec::new();
                map_fields(
                    nested(),
                    other,
                    &format!("{path}."),
                    &mut inner,
                    &mut inner_differences,
                );
                if !inner_differences.is_empty() {
                    difference(DifferenceKind::NestedFormat {
                        expected: mine.format().to_string(),
                        found: other.format().to_string(),
                    });
                    differences.append(&mut inner_differences);
                    continue;
                }
                for i in 0..own.array_len.unwrap_or(1) {
                    for c in &inner {
                        copies.push(CopyOp {
                            src: theirs.offset + i * other.size() + c.src,
                            dst: own.offset + i * mine.size() + c.dst,
                            len: c.len,
                        });
                    }
                }
            }
            (a, b, _) => difference(DifferenceKind::Type {
                expected: a.name().to_owned(),
                found: b.name().to_owned(),
            }),
        }
    }
}

/// A log's format checked against binding `T`, once per subscription: decodes each
/// payload of that subscription into a `T`.
///
/// ```
/// # #[cfg(feature = "derive")] {
/// use ulog_core::typed::{Plan, PlanKind, ULogMessage};
/// use ulog_format::{Format, Layout};
///
/// #[derive(ULogMessage, Debug, PartialEq)]
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
    /// must be in it, by name or alias, with the same type and array length.
    /// Otherwise the error lists every difference.
    pub fn new(file_layout: &Layout) -> Result<Plan<T>, Mismatch> {
        RawPlan::new::<T>(file_layout).map(|raw| Plan {
            raw,
            binding: PhantomData,
        })
    }

    /// Exact or mapped.
    pub fn kind(&self) -> PlanKind {
        self.raw.kind
    }

    /// The number of byte ranges a mapped decode copies (1 or 0 for an exact plan of
    /// a message without internal padding).
    pub fn copy_count(&self) -> usize {
        self.raw.copies.len()
    }

    /// Decodes one payload (the data message after its `msg_id`). Its length must be
    /// the log format's size, with or without trailing padding.
    pub fn decode(&self, payload: &[u8]) -> Result<T, DecodeError> {
        self.raw.decode::<T>(payload)
    }

    /// Decodes every payload of an iterator.
    pub fn decode_all<'p, I>(
        &'p self,
        payloads: I,
    ) -> impl Iterator<Item = Result<T, DecodeError>> + 'p
    where
        I: IntoIterator<Item = &'p [u8]>,
        I::IntoIter: 'p,
    {
        payloads.into_iter().map(move |p| self.decode(p))
    }

    /// Borrows a payload as a `&T`, without copying. Needs an exact plan, the full
    /// payload (trailing padding included), and a `T` whose memory is its wire image:
    /// a `#[repr(C)]` struct of alignment-1 fields (`u8`, `i8`, `CharArray<N>`, the
    /// `zerocopy::little_endian` types, nested such structs, arrays of these) that
    /// also derives `zerocopy`'s `FromBytes`, `KnownLayout`, `Immutable`, `Unaligned`.
    pub fn view<'a>(&self, payload: &'a [u8]) -> Result<&'a T, DecodeError>
    where
        T: FromBytes + KnownLayout + Immutable + Unaligned,
    {
        const {
            assert!(
                <T as WireField>::IS_WIRE,
                "a view needs a binding whose memory is its wire image (repr(C), alignment-1 fields)"
            )
        };
        let len = payload.len();
        if self.raw.kind != PlanKind::Exact {
            return Err(DecodeError {
                kind: DecodeErrorKind::ViewNeedsExactLayout,
                len,
            });
        }
        if len != self.raw.size {
            if len == self.raw.min_size {
                return Err(DecodeError {
                    kind: DecodeErrorKind::ViewNeedsFullPayload,
                    len,
                });
            }
            return Err(self.raw.length_error(len));
        }
        T::ref_from_bytes(payload).map_err(|_| self.raw.length_error(len))
    }
}
