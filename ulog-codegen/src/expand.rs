//! Code generation for a binding: its wire struct and its `WireField` and
//! `ULogMessage` implementations, inside `const _: () = { … };`, with absolute paths.

use proc_macro2::{Ident, Span, TokenStream};
use quote::{quote, quote_spanned};

use crate::ir::{basic_variant, Message, Shape};

/// The name of the wire struct, private to the `const _` block.
fn wire_ident() -> Ident {
    Ident::new("__UlogWire", Span::call_site())
}

/// The implementations of a checked binding.
pub(crate) fn expand(m: &Message) -> TokenStream {
    let typed = m.paths.typed();
    let private = m.paths.private();
    let zerocopy = quote!(#private::zerocopy);
    let zerocopy_text = m.paths.zerocopy_text();
    let ident = &m.ident;
    let wire = wire_ident();
    let name = &m.name;
    let wf = quote!(#typed::WireField);
    let vis = &m.vis;

    let mut wire_fields = Vec::new();
    let mut from_wire = Vec::new();
    let mut to_wire = Vec::new();
    let mut defs = Vec::new();
    let mut is_wire = Vec::new();
    let mut asserts = Vec::new();
    let mut visits = Vec::new();
    for f in &m.fields {
        let fi = &f.ident;
        let fname = &f.name;
        let aliases = &f.aliases;
        let (wire_ty, from, to, kind, len, wire_ok) = match &f.shape {
            Shape::Scalar(ty) => {
                visits.push(quote!(#private::visit_field(&self.#fi, path, base, #fname, f);));
                asserts.push(quote_spanned!(f.span=> #private::assert_field::<#ty>();));
                (
                    quote!(<#ty as #wf>::Wire),
                    quote!(<#ty as #wf>::from_wire(&wire.#fi)),
                    quote!(<#ty as #wf>::to_wire(&self.#fi)),
                    quote!(<#ty as #wf>::KIND),
                    quote!(<#ty as #wf>::COUNT),
                    quote!(<#ty as #wf>::IS_WIRE),
                )
            }
            Shape::Array { elem, len } => {
                visits.push(quote!(#private::visit_array(&self.#fi, path, base, #fname, f);));
                asserts.push(quote_spanned!(f.span=> #private::assert_array_element::<#elem>();));
                (
                    quote!([<#elem as #wf>::Wire; #len]),
                    quote!(::core::array::from_fn(|i| <#elem as #wf>::from_wire(&wire.#fi[i]))),
                    quote!(::core::array::from_fn(|i| <#elem as #wf>::to_wire(&self.#fi[i]))),
                    quote!(<#elem as #wf>::KIND),
                    quote!(::core::option::Option::Some(#len)),
                    quote!(<#elem as #wf>::IS_WIRE),
                )
            }
            Shape::CharBytes { len } => {
                visits.push(match len {
                    Some(_) => {
                        quote!(#private::visit_chars(&self.#fi, false, path, base, #fname, f);)
                    }
                    None => quote!(
                        #private::visit_chars(&[self.#fi], true, path, base, #fname, f);
                    ),
                });
                let (ty, count) = match len {
                    Some(len) => (
                        quote!([u8; #len]),
                        quote!(::core::option::Option::Some(#len)),
                    ),
                    None => (quote!(u8), quote!(::core::option::Option::None)),
                };
                (
                    ty,
                    quote!(wire.#fi),
                    quote!(self.#fi),
                    quote!(#typed::FieldKind::Basic(#private::BasicType::Char)),
                    count,
                    quote!(true),
                )
            }
            Shape::Padding {
                ty,
                count,
                bytes,
                array,
            } => {
                let variant = basic_variant(*ty);
                let count = match count {
                    Some(c) => quote!(::core::option::Option::Some(#c)),
                    None => quote!(::core::option::Option::None),
                };
                let (wire_ty, zero) = if *array {
                    (quote!([u8; #bytes]), quote!([0u8; #bytes]))
                } else {
                    (quote!(u8), quote!(0u8))
                };
                (
                    wire_ty,
                    zero.clone(),
                    zero,
                    quote!(#typed::FieldKind::Basic(#private::BasicType::#variant)),
                    count,
                    quote!(true),
                )
            }
        };
        wire_fields.push(quote!(#fi: #wire_ty));
        from_wire.push(quote!(#fi: #from));
        to_wire.push(quote!(#fi: #to));
        defs.push(quote!(#typed::FieldDef::new(#fname, &[#(#aliases),*], #kind, #len)));
        is_wire.push(quote!(
            #wire_ok && ::core::mem::offset_of!(Self, #fi) == ::core::mem::offset_of!(#wire, #fi)
        ));
    }
    let n = defs.len();
    let visit_body = if visits.is_empty() {
        quote!(let _ = (path, f);)
    } else {
        quote!(let base = path.len(); #(#visits)*)
    };
    quote! {
        #[allow(non_snake_case, clippy::all)]
        const _: () = {
            #[repr(C)]
            #[derive(
                #zerocopy::FromBytes,
                #zerocopy::IntoBytes,
                #zerocopy::KnownLayout,
                #zerocopy::Immutable,
                #zerocopy::Unaligned
            )]
            #[zerocopy(crate = #zerocopy_text)]
            #[doc(hidden)]
            #vis struct #wire {
                #(#wire_fields,)*
            }

            const _: () = {
                #(#asserts)*
            };

            #[automatically_derived]
            impl #wf for #ident {
                type Wire = #wire;
                const KIND: #typed::FieldKind =
                    #typed::FieldKind::Nested(<Self as #typed::ULogMessage>::schema);
                const IS_WIRE: bool = ::core::mem::size_of::<Self>() == ::core::mem::size_of::<#wire>()
                    && ::core::mem::align_of::<Self>() == 1
                    #(&& #is_wire)*;
                #[inline]
                fn from_wire(wire: &#wire) -> Self {
                    Self { #(#from_wire,)* }
                }
                #[inline]
                fn to_wire(&self) -> #wire {
                    #wire { #(#to_wire,)* }
                }
                fn visit_values(
                    &self,
                    path: &mut ::std::string::String,
                    f: &mut dyn ::core::ops::FnMut(&str, #private::Value<'_>),
                ) {
                    #visit_body
                }
            }

            #[automatically_derived]
            impl #typed::ArrayElement for #ident {}

            #[automatically_derived]
            impl #typed::ULogMessage for #ident {
                const NAME: &'static str = #name;
                fn schema() -> &'static #typed::Schema {
                    static FIELDS: [#typed::FieldDef; #n] = [#(#defs),*];
                    static SCHEMA: #private::OnceLock<#typed::Schema> = #private::OnceLock::new();
                    SCHEMA.get_or_init(|| #typed::Schema::build(#name, &FIELDS))
                }
            }
        };
    }
}

/// Implementations that stand in for a binding with errors, so that code using the
/// type reports no further errors.
pub(crate) fn stub(m: &Message) -> TokenStream {
    let typed = m.paths.typed();
    let ident = &m.ident;
    let name = &m.name;
    quote! {
        const _: () = {
            #[automatically_derived]
            impl #typed::WireField for #ident {
                type Wire = ();
                const KIND: #typed::FieldKind =
                    #typed::FieldKind::Nested(<Self as #typed::ULogMessage>::schema);
                fn from_wire(_: &()) -> Self {
                    ::core::unreachable!()
                }
                fn to_wire(&self) {}
                fn visit_values(
                    &self,
                    _: &mut ::std::string::String,
                    _: &mut dyn ::core::ops::FnMut(&str, #typed::__private::Value<'_>),
                ) {
                }
            }
            #[automatically_derived]
            impl #typed::ArrayElement for #ident {}
            #[automatically_derived]
            impl #typed::ULogMessage for #ident {
                const NAME: &'static str = #name;
                fn schema() -> &'static #typed::Schema {
                    ::core::unreachable!()
                }
            }
        };
    }
}
