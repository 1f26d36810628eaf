//! Errors of typed access: a log's format that does not fit a binding, and payloads
//! that cannot be decoded.

use core::fmt;

/// What differs between a binding and a log's format, at one field.
#[derive(Debug, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub enum DifferenceKind {
    /// The log's format has no field of this name (nor of any alias).
    MissingField,
    /// The field has another basic type, or is nested on one side only.
    Type {
        /// The type in the binding.
        expected: String,
        /// The type in the log.
        found: String,
    },
    /// The field is an array of another length, or an array on one side only.
    ArrayLength {
        /// The length in the binding (`None`: not an array).
        expected: Option<usize>,
        /// The length in the log.
        found: Option<usize>,
    },
    /// A nested format differs; the differences inside it follow, with longer paths.
    NestedFormat {
        /// The nested format in the binding.
        expected: String,
        /// The nested format in the log.
        found: String,
    },
}

/// One difference between a binding and a log's format.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Difference {
    /// The field's path in the binding: `timestamp`, `esc.esc_rpm` (for arrays of
    /// nested types, the difference holds for every element).
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
            DifferenceKind::MissingField => write!(f, "missing in the log"),
            DifferenceKind::Type { expected, found } => {
                write!(f, "type `{expected}` expected, the log has `{found}`")
            }
            DifferenceKind::ArrayLength { expected, found } => {
                write!(f, "{} expected, the log has {}", len(expected), len(found))
            }
            DifferenceKind::NestedFormat { expected, found } => {
                write!(
                    f,
                    "nested format `{expected}` differs from the log's `{found}`"
                )
            }
        }
    }
}

/// A log's format that a binding cannot read: every difference, with both formats.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Mismatch {
    /// The binding's message name.
    pub message: String,
    /// Every difference found, in the binding's field order.
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
            "the log's format of `{}` does not fit the binding ({n} difference{})",
            self.message,
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

/// Why a payload could not be decoded.
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
    /// A borrowed view needs the log's format to be the binding's exactly.
    ViewNeedsExactLayout,
    /// A borrowed view needs the trailing padding present in the payload.
    ViewNeedsFullPayload,
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
        match &self.kind {
            DecodeErrorKind::Length { size, min_size } if size == min_size => {
                write!(f, "payload of {} bytes, expected {size}", self.len)
            }
            DecodeErrorKind::Length { size, min_size } => write!(
                f,
                "payload of {} bytes, expected {size} (or {min_size} without trailing padding)",
                self.len
            ),
            DecodeErrorKind::ViewNeedsExactLayout => write!(
                f,
                "cannot borrow a payload of {} bytes: the log's layout differs from the binding's",
                self.len
            ),
            DecodeErrorKind::ViewNeedsFullPayload => write!(
                f,
                "cannot borrow a payload of {} bytes: its trailing padding is left out",
                self.len
            ),
            DecodeErrorKind::NoSuchVariant { variant } => {
                write!(
                    f,
                    "no topic variant {variant} for a payload of {} bytes",
                    self.len
                )
            }
        }
    }
}

impl std::error::Error for DecodeError {}
