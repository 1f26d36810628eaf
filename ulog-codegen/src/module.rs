//! `ulog_module!`: a module of bindings for every format of a reference log, and the
//! formats it cannot bind, each named with why (a warning, an error or nothing, as
//! `unbound = warn | deny | allow;` says).

use std::collections::{HashMap, HashSet};
use std::path::PathBuf;

use proc_macro2::{Span, TokenStream};
use quote::quote;
use syn::parse::{Parse, ParseStream};
use syn::punctuated::Punctuated;
use syn::{Ident, LitStr, Token, Visibility};
use ulog_format::{
    definitions, BasicType, Format, LayoutError, LayoutErrorKind, Limits, Resolver, TypeName,
};

use crate::errors::Errors;
use crate::ir::Paths;
use crate::structs::{emit_structs, parse_options, MacroOptions, Source};
use crate::{names, Unbound};

/// What `ulog_module!` does with the formats it cannot bind (`unbound = …;`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
enum UnboundLevel {
    /// A compiler warning per format (the default).
    #[default]
    Warn,
    /// One `compile_error!` naming them all.
    Deny,
    /// Only the module's documentation names them.
    Allow,
}

struct ModuleInput {
    options: MacroOptions,
    unbound: UnboundLevel,
    topics: Option<Vec<LitStr>>,
    vis: Visibility,
    ident: Ident,
    path: LitStr,
}

impl Parse for ModuleInput {
    fn parse(input: ParseStream) -> syn::Result<Self> {
        let mut options = MacroOptions::default();
        let mut unbound = None;
        let mut topics = None;
        loop {
            if input.peek(syn::Ident) && input.peek2(Token![=]) {
                let key: Ident = input.parse()?;
                input.parse::<Token![=]>()?;
                if key == "unbound" {
                    let level: Ident = input.parse()?;
                    let parsed = match level.to_string().as_str() {
                        "warn" => UnboundLevel::Warn,
                        "deny" => UnboundLevel::Deny,
                        "allow" => UnboundLevel::Allow,
                        _ => {
                            return Err(syn::Error::new(
                                level.span(),
                                "expected `warn`, `deny` or `allow`",
                            ))
                        }
                    };
                    if unbound.replace(parsed).is_some() {
                        return Err(syn::Error::new(key.span(), "`unbound` is set twice"));
                    }
                } else if key == "topics" {
                    let content;
                    syn::bracketed!(content in input);
                    let list = Punctuated::<LitStr, Token![,]>::parse_terminated(&content)?;
                    if topics.replace(list.into_iter().collect()).is_some() {
                        return Err(syn::Error::new(key.span(), "`topics` is set twice"));
                    }
                } else {
                    return Err(syn::Error::new(
                        key.span(),
                        "unknown option, expected `views;`, `crate = path;`, \
                         `unbound = warn|deny|allow;` or `topics = [\"name\", …];`",
                    ));
                }
                input.parse::<Token![;]>()?;
            } else if input.peek(Token![crate])
                || (input.peek(syn::Ident) && input.peek2(Token![;]))
            {
                let more = parse_options(input)?;
                if more.krate.is_some() && options.krate.is_some() {
                    return Err(input.error("`crate` is set twice"));
                }
                options.krate = options.krate.or(more.krate);
                options.views |= more.views;
            } else {
                break;
            }
        }
        let vis = input.parse()?;
        input.parse::<Token![mod]>()?;
        let ident = input.parse()?;
        input.parse::<Token![=]>()?;
        let path = input.parse()?;
        if input.peek(Token![;]) {
            input.parse::<Token![;]>()?;
        }
        Ok(ModuleInput {
            options,
            unbound: unbound.unwrap_or_default(),
            topics,
            vis,
            ident,
            path,
        })
    }
}

/// `ulog_module!`.
pub(crate) fn from_log(tokens: TokenStream) -> TokenStream {
    let input: ModuleInput = match syn::parse2(tokens) {
        Ok(i) => i,
        Err(e) => return e.to_compile_error(),
    };
    let Ok(dir) = std::env::var("CARGO_MANIFEST_DIR") else {
        return syn::Error::new(input.path.span(), "CARGO_MANIFEST_DIR is not set")
            .to_compile_error();
    };
    let file = PathBuf::from(dir).join(input.path.value());
    let bytes = match std::fs::read(&file) {
        Ok(b) => b,
        Err(e) => {
            return syn::Error::new(
                input.path.span(),
                format!("cannot read `{}`: {e}", file.display()),
            )
            .to_compile_error()
        }
    };
    let topics: Option<Vec<String>> = input
        .topics
        .as_ref()
        .map(|t| t.iter().map(LitStr::value).collect());
    let bindings = match Bindings::new(
        &bytes,
        input.options.krate,
        input.options.views,
        topics.as_deref(),
    ) {
        Ok(b) => b,
        Err(Refused::Log(e)) => {
            return syn::Error::new(input.path.span(), format!("`{}`: {e}", input.path.value()))
                .to_compile_error()
        }
        Err(Refused::Topics(missing)) => {
            let lits = input.topics.as_deref().unwrap_or_default();
            return missing
                .iter()
                .map(|(i, message)| {
                    let span = lits.get(*i).map_or(input.path.span(), LitStr::span);
                    syn::Error::new(span, message).to_compile_error()
                })
                .collect();
        }
    };
    let vis = &input.vis;
    let ident = &input.ident;
    let file_text = file.display().to_string();
    let doc = format!(
        " Bindings for the {} format{} of `{}`, generated at compile time.",
        bindings.bound.len(),
        if bindings.bound.len() == 1 { "" } else { "s" },
        input.path.value()
    );
    let unbound_doc = bindings.unbound.iter().map(|u| {
        let line = format!(" - not bound: {u}");
        quote!(#[doc = #line])
    });
    let items = &bindings.items;
    let errors = bindings.errors.to_compile_errors();
    let diagnostics = unbound_diagnostics(&bindings.unbound, input.unbound, &input.path);
    quote! {
        #[doc = #doc]
        #[doc = ""]
        #(#unbound_doc)*
        #vis mod #ident {
            // Rebuild when the log changes.
            const _: &[u8] = ::core::include_bytes!(#file_text);
            #items
        }
        #errors
        #diagnostics
    }
}

/// The diagnostics naming the formats not bound: stable Rust has no warning for a
/// procedural macro to emit, so `warn` gives, per format, a use of a `#[deprecated]`
/// item whose note is the format and why (rustc prints it as a warning at the
/// macro's call); `deny` one `compile_error!` naming them all.
fn unbound_diagnostics(unbound: &[Unbound], level: UnboundLevel, path: &LitStr) -> TokenStream {
    if unbound.is_empty() {
        return TokenStream::new();
    }
    match level {
        UnboundLevel::Allow => TokenStream::new(),
        UnboundLevel::Warn => unbound
            .iter()
            .map(|u| {
                let note = format!(
                    "`ulog_module!` does not bind {u}; `unbound = allow;` silences this, \
                     `unbound = deny;` makes it an error"
                );
                quote! {
                    const _: () = {
                        #[deprecated(note = #note)]
                        struct UnboundFormat;
                        let _ = UnboundFormat;
                    };
                }
            })
            .collect(),
        UnboundLevel::Deny => {
            let mut message = format!(
                "{} format{} of `{}` cannot be bound (`unbound = deny;`):",
                unbound.len(),
                if unbound.len() == 1 { "" } else { "s" },
                path.value()
            );
            for u in unbound {
                message.push_str(&format!("\n  - {u}"));
            }
            syn::Error::new(path.span(), message).to_compile_error()
        }
    }
}

/// Why [`Bindings::new`] generates nothing.
pub(crate) enum Refused {
    /// The bytes are not a log (the reason).
    Log(String),
    /// Topics asked for that the log has no format for: their index in the list and
    /// the message.
    Topics(Vec<(usize, String)>),
}

impl Refused {
    /// The reason as one text.
    pub(crate) fn text(&self) -> String {
        match self {
            Refused::Log(e) => e.clone(),
            Refused::Topics(missing) => missing
                .iter()
                .map(|(_, m)| m.as_str())
                .collect::<Vec<_>>()
                .join("; "),
        }
    }
}

/// The bindings of every format of a log: the items of `ulog_module!`'s module.
pub(crate) struct Bindings {
    /// Structs, their implementations and `visit_bindings`.
    pub items: TokenStream,
    /// Errors in the generated code; empty when all went well (formats that cannot be
    /// bound are in `unbound`, not here).
    pub errors: Errors,
    /// The names of the formats bound (given a struct with its implementations), in
    /// the log's order.
    pub bound: Vec<String>,
    /// The formats not bound, with why, in the log's order.
    pub unbound: Vec<Unbound>,
}

impl Bindings {
    /// Reads the formats of the log `bytes` (every format message of the file, by
    /// `ulog_format::definitions`' walk: the ones the reader finds) and emits their
    /// bindings (borrowed from payloads, with `views`), naming the runtime crate
    /// `krate` (default `::ulog_core`). With `topics`, only those formats and the
    /// ones they nest are bound.
    pub fn new(
        bytes: &[u8],
        krate: Option<syn::Path>,
        views: bool,
        topics: Option<&[String]>,
    ) -> Result<Bindings, Refused> {
        let found = definitions::format_texts(bytes).map_err(|e| Refused::Log(e.to_string()))?;
        let mut sources: Vec<(usize, Source)> = Vec::new();
        let mut unbound: Vec<Unbound> = Vec::new();
        for (offset, text) in found {
            match Format::parse_bytes(text) {
                Ok(format) => {
                    // A later definition of a name replaces the earlier one, as in readers.
                    sources.retain(|(_, s)| s.format.name != format.name);
                    let text = format.to_string();
                    sources.push((
                        offset,
                        Source {
                            format,
                            lit: None,
                            text,
                        },
                    ));
                }
                Err(e) => unbound.push(Unbound {
                    name: name_of(text),
                    offset,
                    reason: e.to_string(),
                }),
            }
        }
        if let Some(topics) = topics {
            sources = pick(sources, topics)?;
            // Texts that do not parse are named only when they may be a topic picked.
            unbound.retain(|u| u.name.as_ref().map_or(true, |n| topics.contains(n)));
        }
        let sources = drop_unbindable(sources, &mut unbound);
        unbound.sort_by_key(|u| u.offset);
        // The module names the runtime's private module once, by an alias.
        let paths = Paths::new(krate).aliased();
        let mut errors = Errors::default();
        let mut bound_idents = Vec::new();
        let mut left_out = Vec::new();
        let structs = emit_structs(
            &sources,
            &paths,
            views,
            &mut errors,
            Some(&mut left_out),
            &mut bound_idents,
        );
        // `drop_unbindable` left only formats that lay out.
        debug_assert!(left_out.is_empty(), "{left_out:?}");
        let bound_names: HashSet<String> = bound_idents.iter().map(ToString::to_string).collect();
        let idents = crate::structs::struct_idents(&sources);
        let bound: Vec<String> = sources
            .iter()
            .filter(|s| {
                idents
                    .get(&s.format.name)
                    .is_some_and(|i| bound_names.contains(&i.to_string()))
            })
            .map(|s| s.format.name.clone())
            .collect();
        let typed = paths.typed();
        let visit_body = if bound_idents.is_empty() {
            quote!(let _ = visitor;)
        } else {
            quote!(#(visitor.visit::<#bound_idents>();)*)
        };
        let visit_views = views.then(|| {
            quote! {
                /// Calls `visitor` with each binding of the module, in the log's order:
                /// each one payloads can be borrowed as.
                pub fn visit_views<V: #typed::ViewVisitor + ?::core::marker::Sized>(visitor: &mut V) {
                    #visit_body
                }
            }
        });
        let alias = paths.private_alias();
        let items = quote! {
            #alias

            #structs

            /// Calls `visitor` with each binding of the module, in the log's order.
            pub fn visit_bindings<V: #typed::BindingVisitor + ?::core::marker::Sized>(visitor: &mut V) {
                #visit_body
            }

            #visit_views
        };
        Ok(Bindings {
            items,
            errors,
            bound,
            unbound,
        })
    }
}

/// The name of a format text that does not parse, when the text before its `:` is
/// one.
fn name_of(text: &[u8]) -> Option<String> {
    let name = &text[..text.iter().position(|&b| b == b':')?];
    let name = std::str::from_utf8(name).ok()?;
    let plain = !name.is_empty()
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '/');
    plain.then(|| name.to_owned())
}

/// The formats of `topics` and the ones they nest (transitively); an error naming
/// each topic the log has no format for.
fn pick(sources: Vec<(usize, Source)>, topics: &[String]) -> Result<Vec<(usize, Source)>, Refused> {
    let by_name: HashMap<&str, &Format> = sources
        .iter()
        .map(|(_, s)| (s.format.name.as_str(), &s.format))
        .collect();
    let mut missing = Vec::new();
    let mut wanted: HashSet<String> = HashSet::new();
    let mut todo: Vec<&str> = Vec::new();
    for (i, t) in topics.iter().enumerate() {
        if by_name.contains_key(t.as_str()) {
            todo.push(t);
        } else {
            let hint = ulog_format::suggest::closest(t, by_name.keys().copied())
                .map(|c| format!(" (did you mean `{c}`?)"))
                .unwrap_or_default();
            missing.push((i, format!("the log has no format `{t}`{hint}")));
        }
    }
    if !missing.is_empty() {
        return Err(Refused::Topics(missing));
    }
    while let Some(name) = todo.pop() {
        if !wanted.insert(name.to_owned()) {
            continue;
        }
        if let Some(f) = by_name.get(name) {
            for fl in &f.fields {
                if let TypeName::Nested(n) = &fl.ty {
                    todo.push(n);
                }
            }
        }
    }
    Ok(sources
        .into_iter()
        .filter(|(_, s)| wanted.contains(&s.format.name))
        .collect())
}

/// The sources that can be bound; the others go to `unbound` with why: a format that
/// cannot be laid out (an unknown or circular nested type, too large), one with two
/// fields of one Rust name or a padding field of a nested type, and one that nests
/// such a format.
fn drop_unbindable(sources: Vec<(usize, Source)>, unbound: &mut Vec<Unbound>) -> Vec<Source> {
    let formats: Vec<Format> = sources.iter().map(|(_, s)| s.format.clone()).collect();
    let mut resolver = Resolver::new(Limits::default());
    let mut why: HashMap<String, String> = HashMap::new();
    for f in &formats {
        if let Some(reason) = field_problem(f) {
            why.insert(f.name.clone(), reason);
        }
    }
    // A format nesting one that cannot be bound cannot be either.
    loop {
        let mut more = Vec::new();
        for f in &formats {
            if why.contains_key(&f.name) {
                continue;
            }
            let nested = f.fields.iter().find_map(|fl| match &fl.ty {
                TypeName::Nested(n) if why.contains_key(n) => Some(n),
                _ => None,
            });
            if let Some(n) = nested {
                more.push((
                    f.name.clone(),
                    format!("it nests `{n}`, which cannot be bound"),
                ));
            }
        }
        if more.is_empty() {
            break;
        }
        why.extend(more);
    }
    for f in &formats {
        if !why.contains_key(&f.name) {
            if let Err(e) = resolver.resolve(&f.name, &formats) {
                why.insert(f.name.clone(), layout_reason(f, &e, &formats));
            }
        }
    }
    let mut kept = Vec::new();
    for (offset, s) in sources {
        match why.remove(&s.format.name) {
            Some(reason) => unbound.push(Unbound {
                name: Some(s.format.name.clone()),
                offset,
                reason,
            }),
            None => kept.push(s),
        }
    }
    kept
}

/// Why `f` cannot be laid out, said of `f`: an unknown type with the nearest basic
/// type or format name (`float32`: did you mean `float`?).
fn layout_reason(f: &Format, e: &LayoutError, formats: &[Format]) -> String {
    let text = e.to_string();
    let own = format!("format `{}`: ", e.format);
    let what = text.strip_prefix(&own).unwrap_or(&text);
    let mut reason = if e.format == f.name {
        what.to_owned()
    } else {
        format!("its nested format `{}`: {what}", e.format)
    };
    if let LayoutErrorKind::UnknownType { name } = &e.kind {
        let basic = BasicType::ALL.iter().map(|b| b.name());
        let known = formats.iter().map(|f| f.name.as_str());
        match ulog_format::suggest::closest(name, basic.chain(known)) {
            Some(c) => reason.push_str(&format!(" (did you mean `{c}`?)")),
            None => reason.push_str(" (neither a basic type nor a format of the log)"),
        }
    }
    reason
}

/// Why the fields of `f` cannot be a struct's, if they cannot.
fn field_problem(f: &Format) -> Option<String> {
    let mut seen: HashMap<String, &str> = HashMap::new();
    for fl in &f.fields {
        if fl.is_padding() && matches!(fl.ty, TypeName::Nested(_)) {
            return Some(format!("its padding field `{}` has a nested type", fl.name));
        }
        let ident = names::field_ident(&fl.name, Span::call_site()).to_string();
        if let Some(other) = seen.insert(ident.clone(), &fl.name) {
            return Some(format!(
                "its fields `{other}` and `{}` have one Rust name, `{ident}`",
                fl.name
            ));
        }
    }
    None
}
#[cfg(test)]
mod tests {
    use super::{Bindings, Refused};

    /// A log of a header and these messages (type, payload).
    fn log_with(messages: &[(u8, &[u8])]) -> Vec<u8> {
        let mut log = ulog_format::definitions::MAGIC.to_vec();
        log.extend_from_slice(&[1, 0, 0, 0, 0, 0, 0, 0, 0]);
        for (kind, payload) in messages {
            log.extend_from_slice(&(payload.len() as u16).to_le_bytes());
            log.push(*kind);
            log.extend_from_slice(payload);
        }
        log
    }

    fn log_with_formats(formats: &[&str]) -> Vec<u8> {
        let messages: Vec<(u8, &[u8])> = formats.iter().map(|t| (b'F', t.as_bytes())).collect();
        log_with(&messages)
    }

    fn bind(log: &[u8], topics: Option<&[String]>) -> Bindings {
        match Bindings::new(log, None, false, topics) {
            Ok(b) => b,
            Err(e) => panic!("{}", e.text()),
        }
    }

    #[test]
    fn every_format_is_bound_or_named_with_why() {
        let log = log_with_formats(&[
            "ok:uint64_t timestamp;",
            "broken:uint64_t timestamp;missing m;",
            "uses_broken:broken[2] b;",
            "bad text",
            "odd:float32 x;",
            "clash:uint8_t self;uint8_t self_;",
            "nests_clash:clash c;uint64_t timestamp;",
            "padded:uint64_t timestamp;ok _padding0;",
        ]);
        let b = bind(&log, None);
        assert_eq!(b.bound, ["ok"]);
        let named: Vec<(Option<&str>, &str)> = b
            .unbound
            .iter()
            .map(|u| (u.name.as_deref(), u.reason.as_str()))
            .collect();
        let names: Vec<Option<&str>> = named.iter().map(|n| n.0).collect();
        assert_eq!(
            names,
            [
                Some("broken"),
                Some("uses_broken"),
                None,
                Some("odd"),
                Some("clash"),
                Some("nests_clash"),
                Some("padded")
            ],
            "{:?}",
            b.unbound
        );
        assert!(named[0].1.contains("missing"), "{named:?}");
        assert!(named[3].1.contains("float32"), "{named:?}");
        assert!(
            named[4].1.contains("`self`") && named[4].1.contains("`self_`"),
            "{named:?}"
        );
        assert!(named[5].1.contains("nests `clash`"), "{named:?}");
        assert!(named[6].1.contains("padding"), "{named:?}");
        // Offsets are those of the payloads, in file order.
        let offsets: Vec<usize> = b.unbound.iter().map(|u| u.offset).collect();
        assert!(offsets.windows(2).all(|w| w[0] < w[1]), "{offsets:?}");
        assert_eq!(b.unbound[0].offset, 16 + 3 + 22 + 3);
        assert!(b.errors.is_empty());
    }

    #[test]
    fn formats_after_data_are_bound() {
        let log = log_with(&[
            (b'F', b"first:uint64_t timestamp;"),
            (b'A', b"\0\0\0first"),
            (b'D', b"\0\0\x01\0\0\0\0\0\0\0"),
            (b'F', b"later:uint64_t timestamp;uint8_t x;"),
            (b'F', b"later_too:uint64_t timestamp;later l;"),
        ]);
        let b = bind(&log, None);
        assert_eq!(b.bound, ["first", "later", "later_too"]);
        assert!(b.unbound.is_empty());
    }

    #[test]
    fn topics_pick_formats_with_the_ones_they_nest_and_name_the_missing() {
        let log = log_with_formats(&[
            "inner:uint8_t x;",
            "outer:uint64_t timestamp;inner i;",
            "other:uint64_t timestamp;",
            "other_broken:uint64_t timestamp;missing m;",
        ]);
        let b = bind(&log, Some(&["outer".to_owned()]));
        assert_eq!(b.bound, ["inner", "outer"]);
        assert!(b.unbound.is_empty(), "formats not picked are not named");
        let Err(Refused::Topics(missing)) = Bindings::new(
            &log,
            None,
            false,
            Some(&["outer".to_owned(), "othr".to_owned(), "zzzzzz".to_owned()]),
        ) else {
            panic!("a topic the log does not have is refused");
        };
        assert_eq!(missing.len(), 2);
        assert_eq!(missing[0].0, 1);
        assert_eq!(
            missing[0].1,
            "the log has no format `othr` (did you mean `other`?)"
        );
        assert_eq!(missing[1].1, "the log has no format `zzzzzz`");
    }
}
