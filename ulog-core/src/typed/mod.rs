//! Typed bindings: Rust structs bound to ULog message formats.
//!
//! A binding is a struct that implements [`ULogMessage`], usually through
//! `#[derive(ULogMessage)]` (feature `derive`), or generated from format strings
//! (`ulog_structs!`) or from a reference log (`ulog_module!`). Its [`Schema`] holds the
//! exact ULog format it describes, with the nested formats it uses.
//!
//! Reading checks a subscription's format against the binding once, making a
//! [`Plan`]: [`PlanKind::Exact`] when the layouts are the same (a payload is copied in
//! one go, or borrowed with [`Plan::view`]), [`PlanKind::Mapped`] when the fields lie
//! elsewhere (a short copy list made at validation time), or a [`Mismatch`] listing
//! every difference. Writing uses [`ULogMessage::encode`] (trailing padding left out,
//! as PX4 does).
//!
//! Payload bytes are little endian on every host: each field's wire image
//! ([`WireField::Wire`]) is a `zerocopy` little-endian type of alignment 1.

mod chars;
mod error;
mod message;
mod plan;
mod schema;
mod topics;
mod wire;

pub use chars::CharArray;
pub use error::{DecodeError, DecodeErrorKind, Difference, DifferenceKind, Mismatch};
pub use message::{BindingVisitor, ULogMessage};
pub use plan::{Plan, PlanKind};
pub use schema::{FieldDef, Schema};
pub use topics::{
    walk, Subscription, TopicDispatcher, TopicError, TopicMessage, TopicPlan, TopicRecord,
    ULogTopics,
};
pub use wire::{ArrayElement, FieldKind, WireField};

/// `zerocopy`'s little-endian types: fields of bindings that can be borrowed as views.
pub use zerocopy::little_endian as le;

#[cfg(feature = "derive")]
pub use ulog_derive::{ulog_module, ulog_structs, ULogMessage, ULogTopics};

/// What generated code names; not a public API.
#[doc(hidden)]
pub mod __private {
    pub use super::wire::{visit_array, visit_chars, visit_field};
    pub use crate::value::Value;
    pub use std::sync::OnceLock;
    pub use ulog_format::{BasicType, Layout};
    pub use zerocopy;

    /// Compile-time check that an array element type can be one.
    pub const fn assert_array_element<T: super::ArrayElement>() {}
    /// Compile-time check that a field type is one.
    pub const fn assert_field<T: super::WireField>() {}
}
