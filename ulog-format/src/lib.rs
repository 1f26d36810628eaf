//! The grammar and layout model of ULog format strings.
//!
//! A ULog `F` message defines a message type as text:
//! `vehicle_attitude:uint64_t timestamp;float[4] q;uint8_t[4] _padding0;`.
//! This crate parses that text into a [`Format`] (the grammar) and resolves a format
//! with the nested formats it uses into a [`Layout`]: the offset, size and path of
//! every field, with nested types laid out with their own padding.
//!
//! It is the one model shared by the reader (`ulog-core`, at run time) and the derive
//! macros (`ulog-derive`, at compile time), so it has no dependencies.
//!
//! ```
//! use ulog_format::{BasicType, Format, Layout, LayoutType};
//!
//! let esc = Format::parse("esc_report:uint64_t timestamp;int32_t esc_rpm;uint8_t[4] _padding0;").unwrap();
//! let status = Format::parse("esc_status:uint64_t timestamp;esc_report[2] esc;").unwrap();
//! let formats = [esc, status];
//! let layout = Layout::resolve("esc_status", &formats[..]).unwrap();
//! assert_eq!(layout.size(), 8 + 2 * 16);
//! let rpm = layout.find("esc[1].esc_rpm").unwrap();
//! assert_eq!(rpm.offset, 8 + 16 + 8);
//! assert_eq!(rpm.ty, LayoutType::Basic(BasicType::Int32));
//! ```
#![forbid(unsafe_code)]
#![warn(missing_docs)]

mod basic;
pub mod definitions;
mod error;
mod layout;
mod parse;
mod span;
pub mod suggest;

pub use basic::BasicType;
pub use error::{FormatError, FormatErrorKind, LayoutError, LayoutErrorKind};
pub use layout::{
    FieldRef, FormatLookup, Layout, LayoutField, LayoutType, Leaf, LeafKind, Limits, Resolver,
};
pub use parse::{parse_field, parse_key, parse_key_as_written, Field, Format, TypeName};
pub use span::Span;

/// The Rust name of a ULog field, as generated bindings spell it and
/// `#[derive(Debug)]` prints it: the name itself (a keyword is written raw, `r#type`,
/// and printed `type`), with `_` after the names that cannot be identifiers even raw
/// (`self_`), `f_` before one that starts with a digit (`f_2d`). The one rule of the
/// generator and of the bindings' `Debug`.
///
/// ```
/// assert_eq!(ulog_format::rust_field_name("q"), "q");
/// assert_eq!(ulog_format::rust_field_name("self"), "self_");
/// assert_eq!(ulog_format::rust_field_name("2d"), "f_2d");
/// ```
pub fn rust_field_name(name: &str) -> std::borrow::Cow<'_, str> {
    if matches!(name, "self" | "Self" | "super" | "crate" | "_") {
        format!("{name}_").into()
    } else if name.starts_with(|c: char| c.is_ascii_digit()) {
        format!("f_{name}").into()
    } else {
        name.into()
    }
}

/// Whether a field name marks padding: names starting with `_padding` are never
/// shown as values and their bytes are ignored.
pub fn is_padding_name(name: &str) -> bool {
    name.starts_with("_padding")
}
