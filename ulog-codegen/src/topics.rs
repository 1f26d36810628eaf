//! `#[derive(ULogTopics)]`: an enum with one tuple variant per binding.

use proc_macro2::TokenStream;
use quote::quote;
use syn::spanned::Spanned;
use syn::{Data, DeriveInput, Fields};

use crate::attr;
use crate::errors::Errors;
use crate::ir::Paths;

/// Expands the enum derive; errors are reported together.
pub(crate) fn derive(input: &DeriveInput) -> TokenStream {
    let mut errors = Errors::default();
    let attrs = attr::container(&input.attrs, false, &mut errors);
    let paths = Paths::new(attrs.krate.get());
    if !input.generics.params.is_empty() {
        errors.at(input.generics.span(), "a topic enum cannot be generic");
    }
    let mut variants = Vec::new();
    match &input.data {
        Data::Enum(e) => {
            for v in &e.variants {
                attr::none(&v.attrs, &mut errors);
                match &v.fields {
                    Fields::Unnamed(f) if f.unnamed.len() == 1 => {
                        let ty = &f.unnamed[0].ty;
                        let key = quote!(#ty).to_string();
                        if variants.iter().any(|(_, _, k): &(_, _, String)| *k == key) {
                            errors.at(ty.span(), format_args!("`{key}` has a variant already"));
                        }
                        variants.push((v.ident.clone(), ty.clone(), key));
                    }
                    _ => errors.at(
                        v.span(),
                        "each variant holds one binding: `Variant(Message)`",
                    ),
                }
            }
            if e.variants.is_empty() {
                errors.at(
                    input.ident.span(),
                    "a topic enum needs at least one variant",
                );
            }
        }
        _ => errors.at(input.ident.span(), "`ULogTopics` is derived for enums"),
    }
    if !errors.is_empty() {
        return errors.to_compile_errors();
    }
    let typed = paths.typed();
    let private = paths.private();
    let message_trait = paths.message_trait();
    let topics_trait = paths.topics_trait();
    let ident = &input.ident;
    let idx: Vec<usize> = (0..variants.len()).collect();
    let names = variants
        .iter()
        .map(|(_, ty, _)| quote!(<#ty as #message_trait>::NAME));
    let aliases = variants
        .iter()
        .map(|(_, ty, _)| quote!(<#ty as #message_trait>::ALIASES));
    let plans = variants.iter().zip(&idx).map(|((_, ty, _), i)| {
        quote!(#i => ::core::option::Option::Some(#typed::TopicPlan::new::<#ty>(#i, layout)))
    });
    let decodes = variants.iter().zip(&idx).map(|((v, ty, _), i)| {
        quote!(#i => ::core::result::Result::map(plan.decode_as::<#ty>(payload), Self::#v))
    });
    quote! {
        const _: () = {
            #[automatically_derived]
            impl #topics_trait for #ident {
                const NAMES: &'static [&'static str] = &[#(#names),*];
                const ALIASES: &'static [&'static [&'static str]] = &[#(#aliases),*];
                fn plan(
                    variant: usize,
                    layout: &#private::Layout,
                ) -> ::core::option::Option<::core::result::Result<#typed::TopicPlan, #typed::Mismatch>> {
                    match variant {
                        #(#plans,)*
                        _ => ::core::option::Option::None,
                    }
                }
                fn decode(
                    plan: &#typed::TopicPlan,
                    payload: &[u8],
                ) -> ::core::result::Result<Self, #typed::DecodeError> {
                    match plan.variant() {
                        #(#decodes,)*
                        variant => ::core::result::Result::Err(#typed::DecodeError {
                            kind: #typed::DecodeErrorKind::NoSuchVariant { variant },
                            len: payload.len(),
                        }),
                    }
                }
            }
        };
    }
}
