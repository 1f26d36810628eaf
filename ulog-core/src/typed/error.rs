//! Errors of typed reading: a log's format that does not fit a binding (every
//! difference), a topic the log does not have, a payload that cannot be decoded.

use core::fmt;

use ulog_format::LayoutError;

use crate::access::lookup::TopicNotFound;
use crate::definitions::Subscription;

/// What differs between a binding and a log's format, at one field.
#[derive(Debug, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub enum DifferenceKind {
    /// The log's format has no field of this name (nor of any alias), and the binding
    /// does not say it may be absent (`Option<T>` or `#[ulog(default)]`).
    MissingField {
        /// The log's field closest to the name, when one looks like a typo of it or
        /// contains it (and no other field of the binding has that name).
        closest: Option<String>,
    },
    /// The field has another basic type, or is nested on one side only.
    Type {
        /// The type in the binding.
        expected: String,
        /// The type in the log.
        found: String,
    },
    /// The field has another type or length in the log that a derived binding would
    /// read (a widening), in a binding implemented by hand.
    NotConvertible,
    /// The field is an array of another length, or an array on one side only.
    ArrayLength {
        /// The length in the binding (`None`: not an array).
        expected: Option<usize>,
        /// The length in the log.
        found: Option<usize>,
    },
}

/// One difference between a binding and a log's format.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Difference {
    /// The field's path in the binding, as the reader names columns: `timestamp`,
    /// `esc[*].esc_rpm` (`[*]`: in every element of an array of a nested type; the
    /// formats are the same for every element).
    pub path: String,
    /// What differs.
    pub kind: DifferenceKind,
}

impl fmt::Display for Difference {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let len = |n: &Option<usize>| match n {
            Some(n) => format!("an array of {n}"),
            None => "not an array".to_owned(),
        };
        write!(f, "field `{}`: ", self.path)?;
        match &self.kind {
            DifferenceKind::MissingField { closest } => {
                f.write_str("missing in the log")?;
                if let Some(c) = closest {
                    write!(
                        f,
                        "; did you mean `{c}`? (rename the field, or add #[ulog(alias = \"{c}\")])"
                    )?;
                }
                write!(
                    f,
                    "; if some firmware lacks it, make it `Option<_>` or give it #[ulog(default)]"
                )
            }
            DifferenceKind::Type { expected, found } => {
                write!(f, "type `{expected}` expected, the log has `{found}`")?;
                if ulog_format::BasicType::from_name(found).is_some()
                    && ulog_format::BasicType::from_name(expected).is_some()
                {
                    write!(
                        f,
                        " (which does not widen to it without loss: declare a conversion, \
                         `#[ulog(convert({found} = path::to::function))]`)"
                    )?;
                }
                Ok(())
            }
            DifferenceKind::NotConvertible => write!(
                f,
                "another type or length in the log, which a binding implemented by hand \
                 cannot read (derive it)"
            ),
            DifferenceKind::ArrayLength { expected, found } => {
                write!(f, "{} expected, the log has {}", len(expected), len(found))
            }
        }
    }
}

/// A log's format that a binding cannot read: every difference, at every depth, once
/// each, with both formats.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Mismatch {
    /// The binding's ULog message name.
    pub message: String,
    /// The binding's Rust type name.
    pub binding: String,
    /// Every difference, in the binding's field order (nested fields after the field
    /// that holds them).
    pub differences: Vec<Difference>,
    /// The binding's format strings, nested first.
    pub expected_formats: Vec<String>,
    /// The log's format strings, nested first.
    pub found_formats: Vec<String>,
}

impl fmt::Display for Mismatch {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let n = self.differences.len();
        write!(
            f,
            "the log's format of `{}` does not fit binding `{}` ({n} difference{})",
            self.message,
            self.binding,
            if n == 1 { "" } else { "s" }
        )?;
        for d in &self.differences {
            write!(f, "\n  {d}")?;
        }
        f.write_str("\nbinding's format:")?;
        for text in &self.expected_formats {
            write!(f, "\n  {text}")?;
        }
        f.write_str("\nlog's format:")?;
        for text in &self.found_formats {
            write!(f, "\n  {text}")?;
        }
        Ok(())
    }
}

impl std::error::Error for Mismatch {}

/// Why a payload could not be decoded, or borrowed.
#[derive(Debug, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub enum DecodeErrorKind {
    /// The payload is neither the full size of the log's format nor that size without
    /// its trailing padding.
    Length {
        /// The full size.
        size: usize,
        /// The size without trailing padding.
        min_size: usize,
    },
    /// A borrowed view needs every field of the binding where the log has it (an
    /// [`Exact`](super::PlanKind::Exact) plan).
    ViewNeedsExactLayout {
        /// The first field that is elsewhere, or another reason.
        why: String,
    },
    /// A borrowed view needs the payload to hold the whole binding: the binding
    /// declares trailing padding that the log's writer left out.
    ViewNeedsLongerPayload {
        /// The binding's size.
        needed: usize,
    },
    /// A topic plan names a variant that its enum does not have.
    NoSuchVariant {
        /// The variant index.
        variant: usize,
    },
}

/// A payload that could not be decoded into a binding.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DecodeError {
    /// What went wrong.
    pub kind: DecodeErrorKind,
    /// The payload's length.
    pub len: usize,
}

impl fmt::Display for DecodeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let len = self.len;
        match &self.kind {
            DecodeErrorKind::Length { size, min_size } if size == min_size => {
                write!(f, "payload of {len} bytes, expected {size}")
            }
            DecodeErrorKind::Length { size, min_size } => write!(
                f,
                "payload of {len} bytes, expected {size} (or {min_size} without trailing padding)"
            ),
            DecodeErrorKind::ViewNeedsExactLayout { why } => write!(
                f,
                "cannot borrow a payload of {len} bytes: {why}, so the binding is not the payload's layout"
            ),
            DecodeErrorKind::ViewNeedsLongerPayload { needed } => write!(
                f,
                "cannot borrow a payload of {len} bytes as a binding of {needed}: leave the trailing padding (that the log's writer left out) out of the binding"
            ),
            DecodeErrorKind::NoSuchVariant { variant } => {
                write!(f, "no topic variant {variant} for a payload of {len} bytes")
            }
        }
    }
}

impl std::error::Error for DecodeError {}

/// What went wrong reading a topic into a binding. Matchable; new kinds may be added.
#[derive(Debug, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub enum TypedErrorKind {
    /// The log has no such topic, or no such instance of it.
    NotFound {
        /// What the log has instead.
        missing: TopicNotFound,
        /// The binding's Rust type name, when the name came from a binding.
        binding: Option<String>,
        /// Whether that name was derived from the struct's name (no
        /// `#[ulog(name = …)]`).
        named_after_struct: bool,
    },
    /// The topic's format could not be laid out, so it cannot be decoded.
    NoLayout(LayoutError),
    /// The log's format does not fit the binding: every difference.
    Mismatch(Box<Mismatch>),
    /// A payload could not be decoded (or borrowed).
    Decode(DecodeError),
    /// The rows cannot be borrowed as the binding
    /// ([`TypedRows::views`](crate::TypedRows::views), refused once for all rows);
    /// they can be decoded by copy.
    NoView {
        /// The binding's Rust type name.
        binding: String,
        /// Why: the first field that is not where the log has it, or the rows that
        /// are shorter than the binding.
        why: String,
    },
}

/// An error of typed reading: what ([`kind`](TypedError::kind), a
/// [`typed::TypedErrorKind`](crate::typed::TypedErrorKind) to match on), the topic
/// instance it is about, and where in the file when there is a place (a subscription
/// for a format that does not fit, a data message for a payload).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TypedError(Box<Inner>);

#[derive(Debug, Clone, PartialEq, Eq)]
struct Inner {
    kind: TypedErrorKind,
    topic: Option<(String, u8)>,
    position: Option<u64>,
}

impl TypedError {
    pub(crate) fn new(
        kind: TypedErrorKind,
        topic: Option<&Subscription>,
        position: Option<u64>,
    ) -> TypedError {
        TypedError(Box::new(Inner {
            kind,
            topic: topic.map(|t| (t.name().to_owned(), t.multi_id())),
            position,
        }))
    }

    /// A topic's format that does not fit its binding.
    pub(crate) fn mismatch(topic: &Subscription, m: Mismatch) -> TypedError {
        let kind = TypedErrorKind::Mismatch(Box::new(m));
        TypedError::new(kind, Some(topic), Some(topic.offset()))
    }

    /// A topic's format without a layout.
    pub(crate) fn no_layout(topic: &Subscription, e: &LayoutError) -> TypedError {
        let kind = TypedErrorKind::NoLayout(e.clone());
        TypedError::new(kind, Some(topic), Some(topic.offset()))
    }

    /// A topic that is not in the log, asked for by binding `schema`.
    pub(crate) fn not_found(missing: TopicNotFound, schema: &super::Schema) -> TypedError {
        let kind = TypedErrorKind::NotFound {
            missing,
            binding: Some(schema.rust_name().to_owned()),
            named_after_struct: schema.named_after_struct(),
        };
        TypedError::new(kind, None, None)
    }

    /// Rows of `topic` that cannot be borrowed as binding `schema`, and why.
    pub(crate) fn no_view(topic: &Subscription, schema: &super::Schema, why: String) -> TypedError {
        let kind = TypedErrorKind::NoView {
            binding: schema.rust_name().to_owned(),
            why,
        };
        TypedError::new(kind, Some(topic), Some(topic.offset()))
    }

    /// A payload of `topic`'s data message at `offset` that could not be decoded.
    #[cold]
    #[inline(never)]
    pub(crate) fn decode(topic: &Subscription, offset: u64, e: DecodeError) -> TypedError {
        TypedError::new(TypedErrorKind::Decode(e), Some(topic), Some(offset))
    }

    /// What went wrong: match on
    /// [`ulog_core::typed::TypedErrorKind`](crate::typed::TypedErrorKind).
    ///
    /// ```
    /// # #[cfg(feature = "derive")] {
    /// use ulog_core::typed::TypedErrorKind;
    ///
    /// #[derive(ulog_core::ULogMessage)]
    /// #[ulog(crate = "ulog_core")]
    /// struct VehicleAtitude { timestamp: u64 }
    ///
    /// let bytes = ulog_core::testing::sample_log();
    /// let log = ulog_core::ULog::parse(&bytes).unwrap();
    /// let Err(e) = log.read::<VehicleAtitude>(0) else { panic!("a topic of that name") };
    /// assert!(matches!(e.kind(), TypedErrorKind::NotFound { .. }));
    /// # }
    /// ```
    pub fn kind(&self) -> &TypedErrorKind {
        &self.0.kind
    }

    /// The topic (name, instance) it is about, when one was found.
    pub fn topic(&self) -> Option<(&str, u8)> {
        self.0.topic.as_ref().map(|(n, m)| (n.as_str(), *m))
    }

    /// The byte offset in the file it is about, where there is one.
    pub fn position(&self) -> Option<u64> {
        self.0.position
    }
}

impl fmt::Display for TypedError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        // The topic and the place first, on the first line: a mismatch goes on over
        // several lines after it.
        if let Some((name, multi_id)) = &self.0.topic {
            write!(f, "topic `{name}` instance {multi_id}")?;
            match (&self.0.kind, self.0.position) {
                (TypedErrorKind::Decode(_), Some(at)) => write!(f, ", data message at byte {at}")?,
                (_, Some(at)) => write!(f, " (subscribed at byte {at})")?,
                (_, None) => {}
            }
            f.write_str(": ")?;
        }
        match &self.0.kind {
            TypedErrorKind::NotFound {
                missing,
                binding,
                named_after_struct,
            } => {
                write!(f, "{missing}")?;
                // A close name in the log and a name made from the struct's: the
                // struct may be named otherwise than its topic.
                match binding {
                    Some(b) if *named_after_struct && !missing.closest.is_empty() => write!(
                        f,
                        "; binding `{b}` takes the name `{}` from its struct name: give the topic's name with #[ulog(name = \"…\")]",
                        missing.name
                    ),
                    _ => Ok(()),
                }
            }
            TypedErrorKind::NoLayout(e) => write!(f, "cannot be decoded: {e}"),
            TypedErrorKind::Mismatch(m) => write!(f, "{m}"),
            TypedErrorKind::Decode(e) => write!(f, "{e}"),
            TypedErrorKind::NoView { binding, why } => write!(
                f,
                "its rows cannot be borrowed as `{binding}`: {why}; `iter()` decodes them by copy, and `ulog codegen --views` writes views of a log's own layouts"
            ),
        }
    }
}

impl std::error::Error for TypedError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match &self.0.kind {
            TypedErrorKind::NoLayout(e) => Some(e),
            TypedErrorKind::Mismatch(m) => Some(&**m),
            TypedErrorKind::Decode(e) => Some(e),
            TypedErrorKind::NotFound { .. } | TypedErrorKind::NoView { .. } => None,
        }
    }
}
