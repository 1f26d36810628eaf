//! Code generation for a binding of a known format (`ulog_module!`, `ulog_structs!`,
//! `ulog codegen`): the struct, and an implementation of the runtime's `Binding`
//! that is mostly data (the format's text, the wire size, the nested bindings) with
//! the fields read and written in order, one call each. `WireField` and
//! `ULogMessage` follow from `Binding` in the runtime, whose shared code builds the
//! schema from the text and reads logs laid out otherwise through a table: nothing is
//! generated per field beyond those two calls, nor per type.

use proc_macro2::{Literal, TokenStream};
use quote::{format_ident, quote, quote_spanned};

use crate::ir::{Message, Shape};

/// What [`expand`] needs beside the message: the layout known when the code is
/// generated.
pub(crate) struct Known<'a> {
    /// The binding's format text: its fields exactly (a view's without the trailing
    /// padding).
    pub format: &'a str,
    /// The format as the log or the caller gives it, for the documentation.
    pub canonical: &'a str,
    /// The text as given, when it differs from the canonical one (format strings).
    pub given: Option<&'a str>,
    /// The wire size.
    pub size: usize,
    /// `WireField::SOURCES`: one per basic field, padding none, a nested binding's
    /// per element.
    pub sources: usize,
}

/// Whether rustc takes `name` for snake case (its `non_snake_case` rule).
fn is_snake_case(name: &str) -> bool {
    let name = name.strip_prefix("r#").unwrap_or(name).trim_matches('_');
    let mut underscore_ok = true;
    name.chars().all(|c| {
        if c == '_' {
            let ok = underscore_ok;
            underscore_ok = false;
            ok
        } else {
            underscore_ok = true;
            !c.is_uppercase()
        }
    })
}

/// The struct of `m` and its implementations, naming the runtime's private module
/// through `m.paths.private()`.
pub(crate) fn expand(m: &Message, k: &Known<'_>) -> TokenStream {
    let p = m.paths.private();
    let ident = &m.ident;
    let doc = format!(" The ULog message `{}`: `{}`", m.name, k.canonical);
    let given = k.given.map(|g| {
        let g = format!(" (given as `{}`)", g.escape_debug());
        quote!(#[doc = #g])
    });
    let odd_fields = m
        .fields
        .iter()
        .filter(|f| !is_snake_case(&f.ident.to_string()))
        .count();
    let allow = match (odd_fields > 0, ident.to_string().contains('_')) {
        (false, false) => TokenStream::new(),
        (true, false) => quote!(#[allow(non_snake_case)]),
        (false, true) => quote!(#[allow(non_camel_case_types)]),
        (true, true) => quote!(#[allow(non_snake_case, non_camel_case_types)]),
    };
    let mut decls = Vec::new();
    let mut reads = Vec::new();
    let mut writes = Vec::new();
    let mut nested = Vec::new();
    // Padding at the end is zeros already: nothing to skip.
    let last_value = m
        .fields
        .iter()
        .rposition(|f| !matches!(f.shape, Shape::Padding { .. }));
    for (i, f) in m.fields.iter().enumerate() {
        let fi = &f.ident;
        let (ty, read, write) = match &f.shape {
            Shape::Scalar(t) => (quote!(#t), quote!(r.get()), quote!(w.put(&self.#fi);)),
            Shape::Array { elem, len } => (
                quote!([#elem; #len]),
                quote!(r.array()),
                quote!(w.array(&self.#fi);),
            ),
            Shape::CharBytes { len: Some(len) } => (
                quote!([u8; #len]),
                quote!(r.array()),
                quote!(w.array(&self.#fi);),
            ),
            Shape::CharBytes { len: None } => {
                (quote!(u8), quote!(r.get()), quote!(w.put(&self.#fi);))
            }
            Shape::Padding {
                bytes, array: true, ..
            } => (
                quote!([u8; #bytes]),
                quote!(r.pad()),
                quote!(w.skip(#bytes);),
            ),
            Shape::Padding { array: false, .. } => {
                (quote!(u8), quote!(r.pad_byte()), quote!(w.skip(1);))
            }
        };
        // The ULog name, where the Rust one differs (`r#type`, `self_`).
        let doc = (crate::names::unraw(fi) != f.name).then(|| {
            let d = format!(" `{}`", f.name);
            quote!(#[doc = #d])
        });
        decls.push(quote!(#doc pub #fi: #ty));
        reads.push(quote!(#fi: #read));
        if last_value.is_some_and(|l| i <= l) {
            writes.push(write);
        }
        if let Shape::Scalar(t) | Shape::Array { elem: t, .. } = &f.shape {
            if f.basic.is_none() && !nested.contains(&t) {
                nested.push(t);
            }
        }
    }
    let size = Literal::usize_unsuffixed(k.size);
    let sources = Literal::usize_unsuffixed(k.sources);
    let format = k.format;
    let nested = (!nested.is_empty()).then(|| {
        quote! {
            const NESTED: &'static [fn() -> &'static #p::Schema] = &[#(<#nested as #p::Binding>::schema),*];
        }
    });
    let (r, w) = if m.fields.is_empty() {
        (format_ident!("_r"), format_ident!("_w"))
    } else if writes.is_empty() {
        (format_ident!("r"), format_ident!("_w"))
    } else {
        (format_ident!("r"), format_ident!("w"))
    };
    let (repr, is_wire, view) = match m.view {
        Some(span) => view_parts(m, k, span),
        None => (TokenStream::new(), TokenStream::new(), TokenStream::new()),
    };
    quote! {
        #[doc = #doc]
        #given
        #[derive(::core::marker::Copy)]
        #allow
        #repr
        pub struct #ident {
            #(#decls,)*
        }

        #p::binding_impls!(#ident);

        impl #p::Binding for #ident {
            type Wire = [u8; #size];
            const FORMAT: &'static str = #format;
            #nested
            const SOURCES: usize = #sources;
            #is_wire
            fn schema() -> &'static #p::Schema {
                static SCHEMA: #p::SchemaCell = #p::SchemaCell::new();
                SCHEMA.get::<Self>()
            }
            fn read(#r: &mut #p::Reader<'_>) -> Self {
                Self { #(#reads,)* }
            }
            fn write(&self, #w: &mut #p::Writer<'_>) {
                #(#writes)*
            }
        }

        #view
    }
}

/// A view's `#[repr(C)]`, its `IS_WIRE` (computed from its fields: their types and
/// offsets) and the assertion that makes it a compile error unless it holds, before
/// the `unsafe impl` of `WireImage`.
fn view_parts(
    m: &Message,
    k: &Known<'_>,
    span: proc_macro2::Span,
) -> (TokenStream, TokenStream, TokenStream) {
    let p = m.paths.private();
    let ident = &m.ident;
    let size = Literal::usize_unsuffixed(k.size);
    let mut offset = quote!(0usize);
    let mut checks = Vec::new();
    for f in &m.fields {
        let fi = &f.ident;
        let (wire, field_size) = match &f.shape {
            Shape::Scalar(t) => (
                quote!(<#t as #p::WireField>::IS_WIRE),
                quote!(#p::wire_size::<#t>()),
            ),
            Shape::Array { elem, len } => (
                quote!(<#elem as #p::WireField>::IS_WIRE),
                quote!((#p::wire_size::<#elem>() * (#len))),
            ),
            Shape::CharBytes { len: Some(len) } => (quote!(true), quote!((#len))),
            Shape::CharBytes { len: None } => (quote!(true), quote!(1usize)),
            Shape::Padding { bytes, .. } => (quote!(true), quote!((#bytes))),
        };
        checks.push(quote!(#wire && ::core::mem::offset_of!(Self, #fi) == #offset));
        offset = quote!(#offset + #field_size);
    }
    let message = format!(
        "`{ident}` is not its wire image, so it cannot be a view: its fields must be `u8`, `i8`, `CharArray<N>`, `ulog_core::typed::le` types, arrays of these or nested view bindings, laid out in declaration order (add `#[repr(C)]`)"
    );
    let is_wire = quote! {
        const IS_WIRE: bool = ::core::mem::size_of::<Self>() == #size
            && ::core::mem::align_of::<Self>() == 1
            #(&& #checks)*;
    };
    let view = quote_spanned! {span=>
        const _: () = ::core::assert!(<#ident as #p::WireField>::IS_WIRE, #message);
        // SAFETY: the assertion above makes it a compile error unless `IS_WIRE`,
        // computed from every field's own `IS_WIRE` and offset, holds.
        unsafe impl #p::WireImage for #ident {}
    };
    (quote!(#[repr(C)]), is_wire, view)
}
