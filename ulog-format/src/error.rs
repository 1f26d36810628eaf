//! Errors of the grammar and of layout resolution.

use core::fmt;

use crate::span::Span;

/// What is wrong with a format string.
#[derive(Debug, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub enum FormatErrorKind {
    /// The text is not UTF-8.
    NotUtf8,
    /// There is no `:` between the message name and the fields.
    MissingColon,
    /// The message name is empty.
    EmptyName,
    /// A message or type name holds a character outside `a-z A-Z 0-9 _ - /`.
    InvalidNameChar(char),
    /// The message name is one of the basic types.
    NameIsBasicType,
    /// The format has no field.
    NoFields,
    /// A field has a type but no name (`type name` expected).
    MissingFieldName,
    /// A field has an empty type.
    EmptyType,
    /// A field name holds a character outside `a-z A-Z 0-9 _`.
    InvalidFieldNameChar(char),
    /// An array length is not a positive decimal number in `[…]`, or is too large.
    BadArrayLength,
    /// Two fields of one format have the same name.
    DuplicateField(String),
}

/// An error in a format string, with the byte range of the text it is about.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FormatError {
    /// What is wrong.
    pub kind: FormatErrorKind,
    /// Where in the format text (byte offsets; `start` is the column).
    pub span: Span,
}

impl fmt::Display for FormatError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.kind {
            FormatErrorKind::NotUtf8 => write!(f, "format text is not UTF-8")?,
            FormatErrorKind::MissingColon => {
                write!(f, "no `:` between the message name and its fields")?
            }
            FormatErrorKind::EmptyName => write!(f, "empty message name")?,
            FormatErrorKind::InvalidNameChar(c) => write!(
                f,
                "character {c:?} is not allowed in a name (allowed: a-z A-Z 0-9 _ - /)"
            )?,
            FormatErrorKind::NameIsBasicType => write!(f, "a message name cannot be a basic type")?,
            FormatErrorKind::NoFields => write!(f, "format has no fields")?,
            FormatErrorKind::MissingFieldName => {
                write!(f, "field has no name (expected `type name`)")?
            }
            FormatErrorKind::EmptyType => write!(f, "field has no type")?,
            FormatErrorKind::InvalidFieldNameChar(c) => write!(
                f,
                "character {c:?} is not allowed in a field name (allowed: a-z A-Z 0-9 _)"
            )?,
            FormatErrorKind::BadArrayLength => {
                write!(f, "array length must be a whole number from 0 to 65535")?
            }
            FormatErrorKind::DuplicateField(name) => write!(f, "duplicate field `{name}`")?,
        }
        write!(f, " at column {}", self.span.start)
    }
}

impl std::error::Error for FormatError {}

/// Why a format could not be laid out.
#[derive(Debug, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub enum LayoutErrorKind {
    /// A type name used in a field is neither a basic type nor a known format.
    UnknownType {
        /// The unknown type name.
        name: String,
    },
    /// The format uses itself, directly or through other formats.
    Cycle {
        /// The chain of format names, from the first to the one that closes the circle.
        chain: Vec<String>,
    },
    /// Nesting deeper than [`Limits::max_depth`](crate::Limits::max_depth).
    TooDeep {
        /// The limit that was passed.
        limit: usize,
    },
    /// The laid-out size, or the number of leaf fields, passes the limits.
    TooLarge {
        /// What passed its limit (`size` or `leaves`).
        what: &'static str,
        /// The limit.
        limit: usize,
    },
}

/// An error resolving a format into a [`Layout`](crate::Layout).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LayoutError {
    /// The format that could not be laid out.
    pub format: String,
    /// Why.
    pub kind: LayoutErrorKind,
}

impl fmt::Display for LayoutError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "format `{}`: ", self.format)?;
        match &self.kind {
            LayoutErrorKind::UnknownType { name } => write!(f, "unknown type `{name}`"),
            LayoutErrorKind::Cycle { chain } => {
                write!(f, "circular definition {}", chain.join(" -> "))
            }
            LayoutErrorKind::TooDeep { limit } => {
                write!(f, "nesting deeper than {limit} levels")
            }
            LayoutErrorKind::TooLarge { what, limit } => {
                write!(f, "{what} larger than the limit of {limit}")
            }
        }
    }
}

impl std::error::Error for LayoutError {}
