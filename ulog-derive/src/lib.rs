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
/// `#[ulog(crate = "…")]` (the runtime crate's path), `#[ulog(view)]` (payloads can
/// be borrowed as the struct: with `#[repr(C)]` and fields of `u8`, `i8`,
/// `CharArray<N>` and `ulog_core::typed::le` types). On fields: `#[ulog(name = "…")]`,
/// `#[ulog(alias = "…")]` (repeatable: the names of older firmware), `#[ulog(char)]`
/// (a `[u8; N]` that is a `char[N]`), `#[ulog(default)]` or `#[ulog(default = expr)]`
/// (the value when a log lacks the field). An `Option<T>` field is `None` when a log
/// lacks it. Fields named `_padding…` are padding.
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
/// the crate's `CARGO_MANIFEST_DIR`), optionally preceded by `crate = path;`. The
/// `ulog codegen` command writes the same bindings as a source file.
#[proc_macro]
pub fn ulog_module(input: TokenStream) -> TokenStream {
    ulog_codegen::ulog_module(input.into()).into()
}
