//! Derive and function-like macros that bind Rust structs to ULog message formats.
//!
//! Use them through `ulog-core` with its `derive` feature (`ulog_core::{ULogMessage,
//! ULogTopics, ulog_structs, ulog_module}`): the generated code names the runtime as
//! `::ulog_core` unless told otherwise with `#[ulog(crate = "…")]` (or `crate = path;`
//! in the function-like macros).
//!
//! ```
//! # extern crate renamed_ulog as ulog_core; // a dependency on `ulog-core`, feature `derive`
//! use ulog_core::{ULog, ULogMessage};
//!
//! /// The fields of `vehicle_attitude` this program reads: a subset, in any order.
//! #[derive(ULogMessage, Debug)]
//! #[ulog(name = "vehicle_attitude")]
//! struct Attitude {
//!     timestamp: u64,
//!     q: [f32; 4],
//! }
//!
//! let bytes = ulog_core::testing::sample_log();
//! let log = ULog::parse(&bytes)?;
//! // The binding is checked against the log's format once; then every row decodes.
//! for row in log.read::<Attitude>(0)?.iter() {
//!     let a = row?;
//!     let norm: f32 = a.q.iter().map(|v| v * v).sum();
//!     assert!((norm - 1.0).abs() < 1e-3, "{a:?}");
//! }
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! This crate is a shell: the pipeline (parse → lower → check → expand, every error of
//! an input at once, with spans) lives in `ulog-codegen`, which the `ulog codegen`
//! command shares.

use proc_macro::TokenStream;

/// Binds a struct to a ULog message: its format (with nested formats), layout, and
/// decoding and encoding. See `ulog_core::ULogMessage`.
///
/// Attributes on the struct: `#[ulog(name = "…")]` (the topic's name; default: the
/// struct name in snake_case: give it whenever the struct is named otherwise),
/// `#[ulog(alias = "…")]` (repeatable: the topic's names in other firmware, tried in
/// order after its name), `#[ulog(crate = "…")]` (the runtime crate's path),
/// `#[ulog(view)]` (payloads can be borrowed as the struct: with `#[repr(C)]` and
/// fields of `u8`, `i8`, `CharArray<N>` and `ulog_core::typed::le` types). On fields:
/// `#[ulog(name = "…")]`, `#[ulog(alias = "…")]` (repeatable: the names of older
/// firmware), `#[ulog(char)]` (a `[u8; N]` that is a `char[N]`), `#[ulog(default)]` or
/// `#[ulog(default = expr)]` (the value when a log lacks the field),
/// `#[ulog(convert(TYPE = function, …))]` (how to read the field from a log that
/// holds it in ULog type `TYPE`, which does not widen to the field's type without
/// loss: `function` takes the log's value, `fn(u32) -> f32` for `uint32_t` into an
/// `f32`; element by element for arrays). An `Option<T>` field is `None` when a log
/// lacks it. A log's type that widens exactly to the field's (Rust's `From`: `uint8_t`
/// into `i32`, `float` into `f64`) and a shorter log array (further elements zeros)
/// bind as they are. Fields named `_padding…` are padding.
#[proc_macro_derive(ULogMessage, attributes(ulog))]
pub fn derive_ulog_message(input: TokenStream) -> TokenStream {
    ulog_codegen::derive_message(input.into()).into()
}

/// Binds an enum with one tuple variant per binding, for reading several topics in
/// pass. See `ulog_core::ULogTopics` and `ulog_core::scan_topics`.
#[proc_macro_derive(ULogTopics, attributes(ulog))]
pub fn derive_ulog_topics(input: TokenStream) -> TokenStream {
    ulog_codegen::derive_topics(input.into()).into()
}

/// Binds a struct whose fields are bound topics (`Option<Binding>`), read together at
/// the steps of an alignment. See `ulog_core::align::Aligned`.
///
/// Attributes on fields: `#[ulog(instance = N)]` (the topic instance, default 0),
/// `#[ulog(method = "previous" | "nearest" | "linear")]` (how the value at a step is
/// found, default `previous`); on the struct, `#[ulog(crate = "…")]`.
#[proc_macro_derive(Aligned, attributes(ulog))]
pub fn derive_aligned(input: TokenStream) -> TokenStream {
    ulog_codegen::derive_aligned(input.into()).into()
}

/// Generates binding structs from ULog format strings:
/// `ulog_structs!("vehicle_attitude:uint64_t timestamp;float[4] q;")`, optionally
/// preceded by `crate = path;` and `pub`-style visibility `vis = pub(crate);`.
/// Nested types must be among the formats given.
#[proc_macro]
pub fn ulog_structs(input: TokenStream) -> TokenStream {
    ulog_codegen::ulog_structs(input.into()).into()
}

/// Generates a module of binding structs from every format in a `.ulg` log, read at
/// compile time: `ulog_module!(pub mod px4 = "logs/reference.ulg");` (path relative to
/// the crate's `CARGO_MANIFEST_DIR`). The `ulog codegen` command writes the same
/// bindings as a source file.
///
/// What is bound: every format message of the file, wherever it is (formats after
/// data messages too, as the spec allows; damage is stepped over), the last
/// definition of a name winning, as in the reader. Each format gets a struct with its
/// `ULogMessage` implementation (and `Clone`, `Copy`, `Default`: every field zero;
/// `Debug` and `PartialEq` as the derives give them, from shared code: padding prints
/// and compares as zeros, a view's fields print as numbers), and `visit_bindings`
/// visits them all.
///
/// What is named instead: a format that cannot be bound (its text does not parse, it
/// names a type that is neither basic nor a format of the log, such as `float32`, or
/// a circular one, two of its fields have one Rust name, it nests such a format) is
/// left out and named with why, in the module's documentation and as the
/// `unbound` option says.
///
/// Options, before the module, each ending with `;`, in any order:
/// - `crate = path;`: the runtime crate's path (default `::ulog_core`);
/// - `views;`: bindings borrowed from payloads (`#[repr(C)]`, little-endian fields);
/// - `unbound = warn;` (the default): a compiler warning per format not bound, with
///   its name and why. Stable Rust has no warning API for procedural macros: the
///   warning is the `deprecated` lint on a use of an item whose note is the text
///   (`use of deprecated unit struct `_::UnboundFormat`: `ulog_module!` does not bind
///   format `x`: …`), pointing at the macro; so `#![deny(warnings)]` makes it an error
///   and `#[allow(deprecated)]` silences it;
/// - `unbound = deny;`: one error naming every format not bound, with why (for a
///   crate that must bind the whole log);
/// - `unbound = allow;`: only the module's documentation names them;
/// - `topics = ["vehicle_attitude", "battery_status"];`: only these formats and the
///   ones they nest; a name the log has no format for is an error, with the nearest
///   name. Formats not picked are neither bound nor named.
///
/// ```text
/// ulog_core::ulog_module!(unbound = deny; topics = ["vehicle_attitude"]; pub mod px4 = "logs/reference.ulg");
/// ```
#[proc_macro]
pub fn ulog_module(input: TokenStream) -> TokenStream {
    ulog_codegen::ulog_module(input.into()).into()
}
