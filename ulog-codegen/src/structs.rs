//! Bindings from format strings (`ulog_structs!`) and the derive's pipeline.
//!
//! Format strings are parsed and laid out with `ulog-format`, exactly as the reader
//! does at run time; each format becomes a struct and the same intermediate form the
//! derive lowers to, so both expand through [`expand`](crate::expand).

use std::collections::HashMap;

use proc_macro2::{Ident, Span, TokenStream};
use quote::{format_ident, quote};
use syn::parse::{Parse, ParseStream};
use syn::punctuated::Punctuated;
use syn::{DeriveInput, LitStr, Token};
use ulog_format::{Format, FormatError, LayoutErrorKind, Limits, Resolver, TypeName};

use crate::errors::Errors;
use crate::expand;
use crate::ir::{rust_basic, Message, MessageField, Paths, Shape};
use crate::{check, input, lower, names};

/// `#[derive(ULogMessage)]`: parse → lower → check → expand. With errors, the errors
/// and stand-in implementations.
pub(crate) fn derive_message(derive: &DeriveInput) -> TokenStream {
    let mut errors = Errors::default();
    let parsed = input::parse(derive, &mut errors);
    let (message, name_span) = lower::lower(parsed, &mut errors);
    check::check(
        &message,
        name_span.unwrap_or(derive.ident.span()),
        &mut errors,
    );
    if errors.is_empty() {
        expand::expand(&message)
    } else {
        let mut out = errors.to_compile_errors();
        // Stand-ins keep uses of the type quiet; a generic type cannot have them.
        if derive.generics.params.is_empty() {
            out.extend(expand::stub(&message));
        }
        out
    }
}

/// The options before the format strings: `crate = path;`.
pub(crate) fn parse_crate(input: ParseStream) -> syn::Result<Option<syn::Path>> {
    if input.peek(Token![crate]) && input.peek2(Token![=]) {
        input.parse::<Token![crate]>()?;
        input.parse::<Token![=]>()?;
        let path = syn::Path::parse_mod_style(input)?;
        input.parse::<Token![;]>()?;
        return Ok(Some(path));
    }
    Ok(None)
}

struct StructsInput {
    krate: Option<syn::Path>,
    texts: Vec<LitStr>,
}

impl Parse for StructsInput {
    fn parse(input: ParseStream) -> syn::Result<Self> {
        let krate = parse_crate(input)?;
        let texts = Punctuated::<LitStr, Token![,]>::parse_terminated(input)?;
        Ok(StructsInput {
            krate,
            texts: texts.into_iter().collect(),
        })
    }
}

/// An error at a column of a format-string literal: the span of those characters
/// where the compiler can give it, else the literal, with the column drawn in the
/// message.
pub(crate) fn error_in_literal(
    lit: &LitStr,
    text: &str,
    start: usize,
    end: usize,
    message: &str,
) -> syn::Error {
    let end = end.max(start + 1).min(text.len().max(start + 1));
    // Byte offsets map onto the literal's source only when it has no escapes.
    let plain = lit.token().to_string() == format!("{text:?}");
    let span = plain
        .then(|| lit.token().subspan(start + 1..end + 1))
        .flatten()
        .unwrap_or_else(|| lit.span());
    let caret = format!("{}{}", " ".repeat(start), "^".repeat(end - start));
    syn::Error::new(span, format!("{message}\n  {text}\n  {caret}"))
}

fn format_error(lit: &LitStr, text: &str, e: &FormatError) -> syn::Error {
    error_in_literal(lit, text, e.span.start, e.span.end, &e.to_string())
}

/// `ulog_structs!`.
pub(crate) fn from_format_strings(tokens: TokenStream) -> TokenStream {
    let input: StructsInput = match syn::parse2(tokens) {
        Ok(i) => i,
        Err(e) => return e.to_compile_error(),
    };
    let mut errors = Errors::default();
    if input.texts.is_empty() {
        errors.at(Span::call_site(), "no format strings given");
    }
    let mut sources: Vec<Source> = Vec::new();
    for lit in &input.texts {
        let text = lit.value();
        match Format::parse_all(&text) {
            Ok(format) => {
                if sources.iter().any(|s| s.format.name == format.name) {
                    errors.at(
                        lit.span(),
                        format_args!("format `{}` is given twice", format.name),
                    );
                    continue;
                }
                sources.push(Source {
                    format,
                    lit: Some(lit.clone()),
                    text,
                });
            }
            Err(all) => {
                for e in &all {
                    errors.push(format_error(lit, &text, e));
                }
            }
        }
    }
    let paths = Paths::new(input.krate);
    let mut out = emit_structs(&sources, &paths, &mut errors, false, &mut Vec::new());
    out.extend(errors.to_compile_errors());
    out
}

/// One format to bind, with the literal it came from (for errors).
pub(crate) struct Source {
    pub format: Format,
    pub lit: Option<LitStr>,
    pub text: String,
}

impl Source {
    fn error(&self, start: usize, end: usize, message: &str) -> syn::Error {
        match &self.lit {
            Some(lit) => error_in_literal(lit, &self.text, start, end, message),
            None => syn::Error::new(Span::call_site(), message),
        }
    }
}

/// Struct names for formats: CamelCase, unique (a suffix where two collide).
pub(crate) fn struct_idents(sources: &[Source]) -> HashMap<String, Ident> {
    let mut taken: HashMap<String, ()> = HashMap::new();
    let mut out = HashMap::new();
    for s in sources {
        let base = names::camel_case(&s.format.name);
        let mut ident = base.clone();
        let mut n = 2;
        while taken.contains_key(&ident) {
            ident = format!("{base}{n}");
            n += 1;
        }
        taken.insert(ident.clone(), ());
        out.insert(s.format.name.clone(), Ident::new(&ident, Span::call_site()));
    }
    out
}

/// Emits a struct and its implementations per source. Formats whose layout fails
/// (unknown or circular nested types, too large) are reported, or skipped silently
/// when `skip_bad` (a whole log's formats). The structs that got real (not stand-in)
/// implementations are pushed to `bound`.
pub(crate) fn emit_structs(
    sources: &[Source],
    paths: &Paths,
    errors: &mut Errors,
    skip_bad: bool,
    bound: &mut Vec<Ident>,
) -> TokenStream {
    let formats: Vec<Format> = sources.iter().map(|s| s.format.clone()).collect();
    let idents = struct_idents(sources);
    let mut resolver = Resolver::new(Limits::default());
    let mut out = TokenStream::new();
    for s in sources {
        let f = &s.format;
        let mut ok = true;
        let laid_out = resolver.resolve(&f.name, &formats).map(|_| ());
        if let Err(e) = laid_out.as_ref().map_err(Clone::clone) {
            ok = false;
            if !skip_bad {
                let (target, message) = match &e.kind {
                    LayoutErrorKind::UnknownType { name } => (
                        Some(name.clone()),
                        format!("unknown nested type `{name}`: give its format too"),
                    ),
                    LayoutErrorKind::Cycle { chain } => (
                        chain.get(1).cloned(),
                        format!("circular nested types: {}", chain.join(" -> ")),
                    ),
                    _ => (None, e.to_string()),
                };
                let field = target.and_then(|t| f.fields.iter().find(|fl| fl.ty.as_str() == t));
                match field {
                    Some(fl) => errors.push(s.error(fl.span.start, fl.span.end, &message)),
                    // The cause is in a format this one nests; it is reported there.
                    None if matches!(
                        e.kind,
                        LayoutErrorKind::UnknownType { .. } | LayoutErrorKind::Cycle { .. }
                    ) => {}
                    None => errors.push(s.error(0, s.text.len(), &message)),
                }
            }
        }
        if skip_bad && !ok {
            continue;
        }
        let mut fields = Vec::new();
        let mut seen_idents: HashMap<String, ()> = HashMap::new();
        for fl in &f.fields {
            let ident = names::field_ident(&fl.name, Span::call_site());
            if seen_idents.insert(ident.to_string(), ()).is_some() {
                errors.push(s.error(
                    fl.span.start,
                    fl.span.end,
                    &format!("field `{}` has the Rust name of another field", fl.name),
                ));
                ok = false;
                continue;
            }
            let len = fl.array_len.map(|n| -> syn::Expr { syn::parse_quote!(#n) });
            let shape = match (&fl.ty, fl.is_padding()) {
                (TypeName::Basic(b), true) => {
                    let bytes = b.size() * fl.array_len.unwrap_or(1);
                    Shape::Padding {
                        ty: *b,
                        count: len,
                        bytes: syn::parse_quote!(#bytes),
                        array: fl.array_len.is_some() || bytes > 1,
                    }
                }
                (TypeName::Nested(_), true) => {
                    errors.push(s.error(
                        fl.span.start,
                        fl.span.end,
                        "a padding field must have a basic type",
                    ));
                    ok = false;
                    continue;
                }
                (TypeName::Basic(ulog_format::BasicType::Char), false) => match &len {
                    Some(len) => {
                        let typed = paths.typed();
                        Shape::Scalar(syn::parse_quote!(#typed::CharArray<#len>))
                    }
                    None => Shape::CharBytes { len: None },
                },
                (TypeName::Basic(b), false) => {
                    let ty: syn::Type = syn::parse2(rust_basic(*b)).expect("basic types are types");
                    match len {
                        Some(len) => Shape::Array { elem: ty, len },
                        None => Shape::Scalar(ty),
                    }
                }
                (TypeName::Nested(n), false) => {
                    // A format that cannot be laid out keeps its basic fields only, so
                    // that an unknown or circular type causes no further errors.
                    let nested = idents.get(n).filter(|_| laid_out.is_ok());
                    let Some(nested) = nested else {
                        ok = false;
                        continue;
                    };
                    let ty: syn::Type = syn::parse_quote!(#nested);
                    match len {
                        Some(len) => Shape::Array { elem: ty, len },
                        None => Shape::Scalar(ty),
                    }
                }
            };
            fields.push(MessageField {
                ident,
                name: fl.name.clone(),
                span: Span::call_site(),
                aliases: Vec::new(),
                shape,
            });
        }
        let Some(ident) = idents.get(&f.name) else {
            continue;
        };
        let message = Message {
            ident: ident.clone(),
            vis: syn::parse_quote!(pub),
            name: f.name.clone(),
            paths: Paths::new(Some(paths.krate().clone())),
            fields,
        };
        out.extend(struct_definition(&message, &s.text, &f.to_string()));
        out.extend(if ok {
            bound.push(ident.clone());
            expand::expand(&message)
        } else {
            expand::stub(&message)
        });
    }
    out
}

fn struct_definition(m: &Message, given: &str, canonical: &str) -> TokenStream {
    let typed = m.paths.typed();
    let ident = &m.ident;
    let doc_name = format!(" The ULog message `{}`:", m.name);
    let doc_format = format!(" {canonical}");
    let given_note = (given != canonical && !given.is_empty()).then(|| {
        let g = format!(" (given as `{}`)", given.escape_debug());
        quote!(#[doc = #g])
    });
    let fields = m.fields.iter().map(|f| {
        let fi = &f.ident;
        let ty = match &f.shape {
            Shape::Scalar(t) => quote!(#t),
            Shape::Array { elem, len } => quote!([#elem; #len]),
            Shape::CharBytes { len: Some(len) } => quote!([u8; #len]),
            Shape::CharBytes { len: None } => quote!(u8),
            Shape::Padding {
                bytes, array: true, ..
            } => quote!([u8; #bytes]),
            Shape::Padding { array: false, .. } => quote!(u8),
        };
        let doc = format!(" `{}`", f.name);
        quote!(#[doc = #doc] pub #fi: #ty)
    });
    let default_doc = format_ident!("default");
    quote! {
        #[doc = #doc_name]
        #[doc = ""]
        #[doc = "```text"]
        #[doc = #doc_format]
        #[doc = "```"]
        #given_note
        #[derive(::core::fmt::Debug, ::core::clone::Clone, ::core::marker::Copy, ::core::cmp::PartialEq)]
        #[allow(non_snake_case, non_camel_case_types)]
        pub struct #ident {
            #(#fields,)*
        }

        #[automatically_derived]
        impl ::core::default::Default for #ident {
            /// Every field zero.
            fn #default_doc() -> Self {
                <Self as #typed::ULogMessage>::zeroed()
            }
        }
    }
}
