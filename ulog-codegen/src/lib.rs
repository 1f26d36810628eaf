//! The code generation behind `ulog-derive`'s macros and the `ulog codegen` command:
//! Rust bindings for ULog message formats.
//!
//! Each entry point runs parse → lower → check → expand (`input`/`attr`, `lower`,
//! `check`, `expand`; `structs` for format strings and logs) and reports every error of
//! its input at once, with spans. The proc-macro crate `ulog-derive` is a thin shell
//! over [`derive_message`], [`derive_topics`], [`derive_aligned`], [`ulog_structs`] and [`ulog_module`];
//! [`bindings_for_log`] gives the same bindings as source text, for checking in.
//!
//! ```
//! let log = ulog_core::testing::sample_log();
//! let options = ulog_codegen::Options::default();
//! let generated = ulog_codegen::bindings_for_log(&log, "sample.ulg", &options).unwrap();
//! assert!(generated.source.contains("pub struct VehicleAttitude"));
//! assert!(generated.problems.is_empty());
//! ```

mod aligned;
mod attr;
mod check;
mod errors;
mod expand;
mod input;
mod ir;
mod known;
mod lower;
mod module;
mod names;
mod structs;
mod topics;

#[cfg(test)]
mod snapshots;

use proc_macro2::TokenStream;

/// `#[derive(ULogMessage)]`: the implementations for the struct in `input`, or
/// `compile_error!`s naming every problem (with stand-in implementations).
pub fn derive_message(input: TokenStream) -> TokenStream {
    match syn::parse2::<syn::DeriveInput>(input) {
        Ok(input) => structs::derive_message(&input),
        Err(e) => e.to_compile_error(),
    }
}

/// `#[derive(ULogTopics)]`: the implementation for the enum in `input`.
pub fn derive_topics(input: TokenStream) -> TokenStream {
    match syn::parse2::<syn::DeriveInput>(input) {
        Ok(input) => topics::derive(&input),
        Err(e) => e.to_compile_error(),
    }
}

/// `#[derive(Aligned)]`: the implementation for the struct of bound topics in
/// `input`, or `compile_error!`s naming every problem.
pub fn derive_aligned(input: TokenStream) -> TokenStream {
    match syn::parse2::<syn::DeriveInput>(input) {
        Ok(input) => aligned::derive(&input),
        Err(e) => e.to_compile_error(),
    }
}

/// `ulog_structs!(…)`: structs and implementations for the format strings in `input`.
pub fn ulog_structs(input: TokenStream) -> TokenStream {
    structs::from_format_strings(input)
}

/// `ulog_module!(options; vis mod name = "path.ulg")`: a module of bindings for every
/// format of the log at `path` (relative to `CARGO_MANIFEST_DIR`), wherever in the file
/// it is defined, and a warning or an error naming each format it cannot bind with why
/// (`unbound = warn | deny | allow;`); `topics = ["name", …];` picks the formats to
/// bind (with the ones they nest).
pub fn ulog_module(input: TokenStream) -> TokenStream {
    module::from_log(input)
}

/// Bindings for every format of a log as Rust source, from [`bindings_for_log`].
#[derive(Debug, Clone)]
pub struct Generated {
    /// The source: a header comment, then the items `ulog_module!` puts in its module
    /// (a struct with its implementations per format, and `visit_bindings`).
    pub source: String,
    /// The names of the formats that got a struct, in the log's order.
    pub bound: Vec<String>,
    /// The formats left out, with why, in the log's order: every format message of
    /// the log is either bound or here.
    pub unbound: Vec<Unbound>,
    /// Errors in the generated code, which the compiler will reject; empty unless
    /// the generator has a bug: the source holds a `compile_error!` for each, exactly
    /// as the macro would.
    pub problems: Vec<String>,
}

/// A format of a log that `ulog_module!` and `ulog codegen` do not bind, and why.
/// Shown as ``format `name`: reason``, or ``the format at offset N: reason`` when it
/// has no name.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Unbound {
    /// The format's name; `None` when its text does not parse far enough to give one.
    pub name: Option<String>,
    /// The file offset of its format message's payload.
    pub offset: usize,
    /// Why it is not bound: its text does not parse (the reader skips it too), it
    /// cannot be laid out (an unknown or circular nested type), two of its fields
    /// have one Rust name, or it nests a format that is not bound.
    pub reason: String,
}

impl core::fmt::Display for Unbound {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match &self.name {
            Some(name) => write!(f, "format `{name}`")?,
            None => write!(f, "the format at offset {}", self.offset)?,
        }
        write!(f, ": {}", self.reason)
    }
}

/// How [`bindings_for_log`] generates.
#[derive(Debug, Clone, Default)]
pub struct Options<'a> {
    /// The path generated code names the runtime by (default `::ulog_core`).
    pub krate: Option<&'a str>,
    /// Bindings borrowed from payloads (`ulog_module!(views; …)`): `#[repr(C)]`
    /// structs of little-endian fields, without the trailing padding.
    pub views: bool,
    /// Only these formats, and the ones they nest (`ulog_module!(topics = […]; …)`);
    /// `None`: every format of the log.
    pub topics: Option<&'a [String]>,
}

/// Bindings for every format of the log `bytes` (named `name` in the header comment)
/// as formatted Rust source: the same code `ulog_module!` generates for that log,
/// without the module around it. The formats it cannot bind are listed in
/// [`Generated::unbound`] and in the header comment.
///
/// Errors: the bytes are not a ULog log (the reason), `options.krate` is not a
/// path, or a name of `options.topics` is not a format of the log.
pub fn bindings_for_log(
    bytes: &[u8],
    name: &str,
    options: &Options<'_>,
) -> Result<Generated, String> {
    let krate = match options.krate {
        Some(k) => {
            Some(syn::parse_str::<syn::Path>(k).map_err(|e| format!("`{k}` is not a path: {e}"))?)
        }
        None => None,
    };
    let b =
        module::Bindings::new(bytes, krate, options.views, options.topics).map_err(|e| e.text())?;
    let mut tokens = b.items;
    tokens.extend(b.errors.to_compile_errors());
    let file: syn::File =
        syn::parse2(tokens).map_err(|e| format!("generated code does not parse: {e}"))?;
    let count = b.bound.len();
    let mut source = format!(
        "// Bindings for the {} format{} of `{}`, generated by `ulog codegen` ({} {}):\n\
         // the code `ulog_module!` generates for that log. Regenerate rather than edit.\n\
         // Use it as a module (`#[rustfmt::skip] mod bindings;`) of a crate that depends\n\
         // on `ulog-core`.\n",
        count,
        if count == 1 { "" } else { "s" },
        name.escape_debug(),
        env!("CARGO_PKG_NAME"),
        env!("CARGO_PKG_VERSION"),
    );
    for u in &b.unbound {
        // An offset says little in a file that is not the log (`ulog codegen` reads
        // the log without its data): a text with no name is named by its reason.
        let line = match &u.name {
            Some(_) => u.to_string(),
            None => format!("a format text that does not parse: {}", u.reason),
        };
        source.push_str(&format!("// Not bound: {}\n", line.replace('\n', " ")));
    }
    source.push('\n');
    source.push_str(&prettyplease::unparse(&file));
    Ok(Generated {
        source,
        bound: b.bound,
        unbound: b.unbound,
        problems: b.errors.messages(),
    })
}
