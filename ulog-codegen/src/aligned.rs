//! `#[derive(Aligned)]`: a struct whose fields are bound topics (`Option<Binding>`),
//! read together at the steps of an alignment.
//!
//! Field attributes: `instance = N` (the topic instance, default 0) and
//! `method = "previous" | "nearest" | "linear"` (default `previous`). Every problem of
//! the struct is reported at once, each at its span.

use proc_macro2::{Span, TokenStream};
use quote::{format_ident, quote};
use syn::spanned::Spanned;
use syn::{Data, DeriveInput, Fields, GenericArgument, LitInt, LitStr, PathArguments, Type};

use crate::attr;
use crate::errors::Errors;
use crate::ir::Paths;

/// One field: its name, the binding it holds, its instance and method.
struct Member {
    ident: syn::Ident,
    binding: Type,
    instance: u8,
    method: &'static str,
}

/// Expands the struct derive; errors are reported together.
pub(crate) fn derive(input: &DeriveInput) -> TokenStream {
    let mut errors = Errors::default();
    let attrs = attr::container(&input.attrs, false, &mut errors);
    let paths = Paths::new(attrs.krate.get());
    if !input.generics.params.is_empty() {
        errors.at(
            input.generics.span(),
            "an aligned struct cannot be generic: its topics are fixed",
        );
    }
    let mut members = Vec::new();
    match &input.data {
        Data::Struct(s) => match &s.fields {
            Fields::Named(named) if !named.named.is_empty() => {
                for f in &named.named {
                    if let Some(m) = member(f, &mut errors) {
                        members.push(m);
                    }
                }
            }
            _ => errors.at(
                input.ident.span(),
                "an aligned struct needs named fields, each `Option<Binding>`",
            ),
        },
        _ => errors.at(
            input.ident.span(),
            "`Aligned` is derived for structs whose fields are `Option<Binding>`",
        ),
    }
    if !errors.is_empty() {
        return errors.to_compile_errors();
    }
    expand(&input.ident, &members, &paths)
}

/// The binding and attributes of field `f`, or `None` with the errors recorded.
fn member(f: &syn::Field, errors: &mut Errors) -> Option<Member> {
    let ident = f.ident.clone()?;
    let (instance, method) = field_attrs(f, errors);
    let Some(binding) = option_of(&f.ty) else {
        errors.at(
            f.ty.span(),
            "each field is `Option<Binding>`: a topic has no value before its first row",
        );
        return None;
    };
    Some(Member {
        ident,
        binding: binding.clone(),
        instance,
        method,
    })
}

/// `T` of a type written `Option<T>` (or `core::option::Option<T>`).
fn option_of(ty: &Type) -> Option<&Type> {
    let Type::Path(p) = ty else { return None };
    let last = p.path.segments.last()?;
    if last.ident != "Option" {
        return None;
    }
    let PathArguments::AngleBracketed(args) = &last.arguments else {
        return None;
    };
    match args.args.first() {
        Some(GenericArgument::Type(t)) if args.args.len() == 1 => Some(t),
        _ => None,
    }
}

/// `#[ulog(instance = N, method = "…")]` of a field.
fn field_attrs(f: &syn::Field, errors: &mut Errors) -> (u8, &'static str) {
    let mut instance: Option<(u8, Span)> = None;
    let mut method: Option<(&'static str, Span)> = None;
    for a in f.attrs.iter().filter(|a| a.path().is_ident("ulog")) {
        let result = a.parse_nested_meta(|meta| {
            let span = meta.path.span();
            if meta.path.is_ident("instance") {
                let lit: LitInt = meta.value()?.parse()?;
                match lit.base10_parse::<u8>() {
                    Ok(n) if instance.is_none() => instance = Some((n, span)),
                    Ok(_) => errors.at(span, "`instance` is set twice"),
                    Err(_) => errors.at(lit.span(), "an instance is a number from 0 to 255"),
                }
            } else if meta.path.is_ident("method") {
                let lit: LitStr = meta.value()?.parse()?;
                let known = match lit.value().as_str() {
                    "previous" => Some("Previous"),
                    "nearest" => Some("Nearest"),
                    "linear" => Some("Linear"),
                    _ => None,
                };
                match known {
                    Some(_) if method.is_some() => errors.at(span, "`method` is set twice"),
                    Some(m) => method = Some((m, span)),
                    None => errors.at(
                        lit.span(),
                        format_args!(
                            "unknown method `{}`: `previous`, `nearest` or `linear`",
                            lit.value()
                        ),
                    ),
                }
            } else {
                return Err(meta.error("unknown attribute, expected `instance` or `method`"));
            }
            Ok(())
        });
        if let Err(e) = result {
            errors.push(e);
        }
    }
    (
        instance.map_or(0, |i| i.0),
        method.map_or("Previous", |m| m.0),
    )
}

/// The `Aligned` implementation.
fn expand(ident: &syn::Ident, members: &[Member], paths: &Paths) -> TokenStream {
    let message_trait = paths.message_trait();
    let align = paths.align();
    let fields = members.iter().map(|m| {
        let (name, ty, instance) = (m.ident.to_string(), &m.binding, m.instance);
        let method = format_ident!("{}", m.method);
        quote!(#align::AlignedField {
            field: #name,
            topic: <#ty as #message_trait>::NAME,
            multi_id: #instance,
            method: #align::Method::#method,
        })
    });
    let vars: Vec<_> = (0..members.len())
        .map(|i| format_ident!("__f{}", i))
        .collect();
    let opens = members.iter().zip(&vars).enumerate().map(|(i, (m, v))| {
        let ty = &m.binding;
        quote!(let #v = __check.topic::<#ty>(#i);)
    });
    let names: Vec<_> = members.iter().map(|m| &m.ident).collect();
    let plans = members.iter().zip(&vars).enumerate().map(|(i, (m, v))| {
        let ty = &m.binding;
        quote!(let #v = __plans.plan::<#ty>(#i);)
    });
    let decodes = vars
        .iter()
        .enumerate()
        .map(|(i, v)| quote!(#align::__decode(&#v, __rows, #i)));
    quote! {
        const _: () = {
            #[automatically_derived]
            impl #align::Aligned for #ident {
                const FIELDS: &'static [#align::AlignedField] = &[#(#fields),*];
                fn open<'s>(
                    __steps: &'s #align::Alignment<'_, '_>,
                ) -> ::core::result::Result<#align::__Next<'s, Self>, #align::AlignedError> {
                    let mut __check = #align::__Check::new(__steps, Self::FIELDS);
                    #(#opens)*
                    match (#(#vars,)*) {
                        (#(::core::option::Option::Some(mut #vars),)*) => {
                            ::core::result::Result::Ok(::std::boxed::Box::new(
                                move |__to: ::core::option::Option<usize>| {
                                    if let ::core::option::Option::Some(__step) = __to {
                                        #(#vars.seek_step(__step);)*
                                        return ::core::option::Option::None;
                                    }
                                    ::core::option::Option::Some(Self {
                                        #(#names: ::core::iter::Iterator::next(&mut #vars)?,)*
                                    })
                                },
                            ))
                        }
                        _ => ::core::result::Result::Err(__check.error()),
                    }
                }
                fn __decoder(
                    __layouts: &#align::__Layouts,
                ) -> ::core::result::Result<#align::__Decode<Self>, #align::AlignedError> {
                    let mut __plans = #align::__Plans::new(__layouts, Self::FIELDS);
                    #(#plans)*
                    match (#(#vars,)*) {
                        (#(::core::option::Option::Some(#vars),)*) => {
                            ::core::result::Result::Ok(::std::boxed::Box::new(
                                move |__rows: &[::core::option::Option<#align::Row<'_>>]| Self {
                                    #(#names: #decodes,)*
                                },
                            ))
                        }
                        _ => ::core::result::Result::Err(__plans.error()),
                    }
                }
            }
        };
    }
}
