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
use crate::ir::{rust_basic, wire_basic, Absent, Message, MessageField, Paths, Shape};
use crate::{check, input, known, lower, names};

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

/// The options of the function-like macros, before their input: `crate = path;` (the
/// runtime crate's path) and `views;` (bindings borrowed from payloads), in any order.
#[derive(Default)]
pub(crate) struct MacroOptions {
    pub krate: Option<syn::Path>,
    pub views: bool,
}

pub(crate) fn parse_options(input: ParseStream) -> syn::Result<MacroOptions> {
    let mut options = MacroOptions::default();
    loop {
        if input.peek(Token![crate]) && input.peek2(Token![=]) {
            let at = input.parse::<Token![crate]>()?;
            if options.krate.is_some() {
                return Err(syn::Error::new(at.span, "`crate` is set twice"));
            }
            input.parse::<Token![=]>()?;
            options.krate = Some(syn::Path::parse_mod_style(input)?);
            input.parse::<Token![;]>()?;
        } else if input.peek(syn::Ident) && input.peek2(Token![;]) {
            let ident: Ident = input.fork().parse()?;
            if ident != "views" {
                return Err(syn::Error::new(
                    ident.span(),
                    "unknown option, expected `views;` or `crate = path;`",
                ));
            }
            input.parse::<Ident>()?;
            input.parse::<Token![;]>()?;
            options.views = true;
        } else {
            return Ok(options);
        }
    }
}

struct StructsInput {
    options: MacroOptions,
    texts: Vec<LitStr>,
}

impl Parse for StructsInput {
    fn parse(input: ParseStream) -> syn::Result<Self> {
        let options = parse_options(input)?;
        let texts = Punctuated::<LitStr, Token![,]>::parse_terminated(input)?;
        Ok(StructsInput {
            options,
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
    let paths = Paths::new(input.options.krate);
    let views = input.options.views;
    let mut out = emit_structs(&sources, &paths, views, &mut errors, None, &mut Vec::new());
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
/// (unknown or circular nested types, too large) are reported as errors, or, when
/// `skipped` is given (a whole log's formats), left out and listed there with why.
/// The structs that got real (not stand-in) implementations are pushed to `bound`.
///
/// With `views`, the structs are their payloads' images, to be borrowed from them:
/// `#[repr(C)]`, fields of `zerocopy`'s little-endian types (`ByteBool` for `bool`),
/// and no trailing padding (PX4 does not write it), except in formats nested in
/// others.
pub(crate) fn emit_structs(
    sources: &[Source],
    paths: &Paths,
    views: bool,
    errors: &mut Errors,
    mut skipped: Option<&mut Vec<String>>,
    bound: &mut Vec<Ident>,
) -> TokenStream {
    let formats: Vec<Format> = sources.iter().map(|s| s.format.clone()).collect();
    let idents = struct_idents(sources);
    let nested_in_others: std::collections::HashSet<&str> = formats
        .iter()
        .flat_map(|f| f.fields.iter())
        .filter_map(|fl| match &fl.ty {
            TypeName::Nested(n) => Some(n.as_str()),
            TypeName::Basic(_) => None,
        })
        .collect();
    let mut resolver = Resolver::new(Limits::default());
    let mut out = TokenStream::new();
    for s in sources {
        let f = &s.format;
        let mut ok = true;
        let laid_out = resolver.resolve(&f.name, &formats);
        if let Err(e) = laid_out.as_ref().map_err(Clone::clone) {
            ok = false;
            if let Some(skipped) = skipped.as_deref_mut() {
                skipped.push(format!("format `{}`: {e}", f.name));
            } else {
                let (target, message) = match &e.kind {
                    LayoutErrorKind::UnknownType { name } => {
                        (Some(name.clone()), unknown_nested(name, &formats))
                    }
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
        if skipped.is_some() && !ok {
            continue;
        }
        let mut fields = Vec::new();
        let mut seen_idents: HashMap<String, ()> = HashMap::new();
        // A view of a topic leaves out the trailing padding (the fields up to the last
        // value); a format nested in others keeps it, as it is inside their payloads.
        let trim = views && !nested_in_others.contains(f.name.as_str());
        let kept = match f.fields.iter().rposition(|fl| !fl.is_padding()) {
            Some(last) if trim => last + 1,
            None if trim => 0,
            _ => f.fields.len(),
        };
        for fl in &f.fields[..kept] {
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
                    let ty = if views {
                        wire_basic(*b, &paths.typed())
                    } else {
                        rust_basic(*b)
                    };
                    let ty: syn::Type = syn::parse2(ty).expect("basic types are types");
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
                absent: Absent::Required,
                basic: match &fl.ty {
                    TypeName::Basic(b) => Some((*b, fl.array_len)),
                    TypeName::Nested(_) => None,
                },
                converts: Vec::new(),
            });
        }
        let Some(ident) = idents.get(&f.name) else {
            continue;
        };
        let message = Message {
            ident: ident.clone(),
            name: f.name.clone(),
            named_after_struct: false,
            aliases: Vec::new(),
            paths: paths.clone(),
            fields,
            view: views.then(Span::call_site),
        };
        let canonical = f.to_string();
        match &laid_out {
            Ok(layout) if ok => {
                // The binding's own format: a view's without the trailing padding.
                let own = Format {
                    name: f.name.clone(),
                    fields: f.fields[..kept].to_vec(),
                };
                let format = own.to_string();
                let given = (s.text != canonical && !s.text.is_empty()).then_some(s.text.as_str());
                let known = known::Known {
                    format: &format,
                    canonical: &canonical,
                    given,
                    size: if trim {
                        layout.min_size()
                    } else {
                        layout.size()
                    },
                    sources: sources_of(&f.name, &formats),
                };
                bound.push(ident.clone());
                out.extend(known::expand(&message, &known));
            }
            _ => {
                out.extend(struct_definition(&message, &s.text, &canonical));
                out.extend(expand::stub(&message));
            }
        }
    }
    out
}

/// How many payload offsets the binding of format `name` takes (`WireField::SOURCES`):
/// one per basic field, padding none, a nested format's per element.
fn sources_of(name: &str, formats: &[Format]) -> usize {
    let Some(f) = formats.iter().find(|f| f.name == name) else {
        return 0;
    };
    f.fields
        .iter()
        .filter(|fl| !fl.is_padding())
        .map(|fl| match &fl.ty {
            TypeName::Basic(_) => 1,
            TypeName::Nested(n) => fl.array_len.unwrap_or(1) * sources_of(n, formats),
        })
        .sum()
}

fn struct_definition(m: &Message, given: &str, canonical: &str) -> TokenStream {
    let message_trait = m.paths.message_trait();
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
    let repr = m.view.map(|_| quote!(#[repr(C)]));
    quote! {
        #[doc = #doc_name]
        #[doc = ""]
        #[doc = "```text"]
        #[doc = #doc_format]
        #[doc = "```"]
        #given_note
        #[derive(::core::fmt::Debug, ::core::clone::Clone, ::core::marker::Copy, ::core::cmp::PartialEq)]
        #[allow(non_snake_case, non_camel_case_types)]
        #repr
        pub struct #ident {
            #(#fields,)*
        }

        #[automatically_derived]
        impl ::core::default::Default for #ident {
            /// Every field zero.
            fn #default_doc() -> Self {
                <Self as #message_trait>::zeroed()
            }
        }
    }
}

/// The error text of a field whose type is neither a basic type nor a format given:
/// the closest such name when it looks like a typo of one (`flaot`), else the fix.
fn unknown_nested(name: &str, formats: &[Format]) -> String {
    let basic = ulog_format::BasicType::ALL.iter().map(|b| b.name());
    let given = formats.iter().map(|f| f.name.as_str());
    match ulog_format::suggest::closest(name, basic.chain(given)) {
        Some(close) => format!(
            "unknown nested type `{name}`: did you mean `{close}`? (or give the format of `{name}` too)"
        ),
        None => format!("unknown nested type `{name}`: give its format too"),
    }
}
