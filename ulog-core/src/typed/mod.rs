//! Typed bindings: Rust structs bound to ULog message formats.
//!
//! A binding is a struct that implements [`ULogMessage`](crate::ULogMessage), usually through
//! `#[derive(ULogMessage)]` (feature `derive`), or generated from format strings
//! (`ulog_structs!`) or from a reference log (`ulog_module!`). Its [`Schema`] holds the
//! exact ULog format it describes, with the nested formats it uses.
//!
//! Reading checks a subscription's format against the binding once, making a
//! [`Plan`]: [`PlanKind::Exact`] when every field lies where the log has it (a
//! payload is decoded in place, or borrowed), [`PlanKind::Mapped`] when fields lie
//! elsewhere or optional ones are absent (a short copy list made at validation time),
//! or a [`Mismatch`] listing every difference. Writing uses
//! [`ULogMessage::encode`](crate::ULogMessage::encode)
//! (trailing padding left out, as PX4 does).
//!
//! # Fields that change across firmware
//!
//! - `Option<T>`: `None` when the log's format lacks the field (a field added in a
//!   newer firmware, or removed from an older one). Such a binding reads, but cannot be
//!   written.
//! - `#[ulog(default)]` (the type's `Default`) or `#[ulog(default = expr)]`: the value
//!   when the log's format lacks the field.
//! - `#[ulog(alias = "old_name")]` (repeatable): the field renamed across firmware.
//!
//! # The topic a binding reads
//!
//! A binding reads the topic of its ULog name: `#[ulog(name = "…")]`, or else the
//! struct's name in snake case (`VehicleLocalPosition` → `vehicle_local_position`).
//! Give the name whenever the struct is named otherwise (a struct holding a subset of
//! a topic's fields, `LocalPosition`): a name the log does not have is an error that
//! lists the closest topic names and says when the name came from the struct's name.
//!
//! Payload bytes are little endian on every host: each field's wire image
//! ([`WireField::Wire`]) is a `zerocopy` little-endian type of alignment 1.

mod binding;
mod chars;
mod derived;
pub(crate) mod error;
#[cfg(test)]
mod hand_binding;
pub(crate) mod message;
pub(crate) mod plan;
mod plans;
pub(crate) mod rows;
pub(crate) mod scan;
mod schema;
pub(crate) mod topics;
mod wire;

pub use crate::audited::WireImage;
pub use chars::{ByteBool, CharArray};
pub use error::{
    DecodeError, DecodeErrorKind, Difference, DifferenceKind, Mismatch, TypedErrorKind,
};
pub use message::{BindingVisitor, ViewVisitor};
pub use plan::{Plan, PlanKind};
pub use rows::{Instances, RowsIter};
pub use scan::TopicHandler;
pub use schema::{Absent, FieldDef, FieldKind, Schema};
pub use topics::TopicPlan;
pub use wire::{
    ArrayElement, HasOptionFields, IsWritable, Present, WireField, Writability, Writable,
};

/// `zerocopy`'s little-endian types: fields of bindings that can be borrowed as views.
pub use zerocopy::little_endian as le;

/// What generated code names; not a public API.
#[doc(hidden)]
pub mod __private {
    pub use super::binding::impls as binding;
    pub use super::binding::{format_name, Binding, Reader, SchemaCell, Writer};
    pub use super::message::ULogMessage;
    pub use super::schema::Schema;
    pub use super::wire::WireField;
    pub use super::wire::{
        array_sources, read, read_array, read_array_source, read_declared, read_declared_array,
        read_source, visit_array, visit_chars, visit_field, wire_size, write, write_array,
        Converted, Widened,
    };
    pub use crate::__binding_impls as binding_impls;
    pub use crate::audited::WireImage;
    pub use crate::value::Value;
    pub use std::sync::OnceLock;
    pub use ulog_format::{BasicType, Layout};
    pub use zerocopy;

    /// Compile-time check that an array element type can be one.
    pub const fn assert_array_element<T: super::ArrayElement>() {}
    /// Compile-time check that a field type is one.
    pub const fn assert_field<T: super::WireField>() {}
}
