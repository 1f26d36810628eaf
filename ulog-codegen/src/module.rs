//! `ulog_module!`: a module of bindings for every format of a reference log.

use std::path::PathBuf;

use proc_macro2::TokenStream;
use quote::quote;
use syn::parse::{Parse, ParseStream};
use syn::{Ident, LitStr, Token, Visibility};
use ulog_format::definitions;

use crate::errors::Errors;
use crate::ir::Paths;
use crate::structs::{emit_structs, parse_options, MacroOptions, Source};

struct ModuleInput {
    options: MacroOptions,
    vis: Visibility,
    ident: Ident,
    path: LitStr,
}

impl Parse for ModuleInput {
    fn parse(input: ParseStream) -> syn::Result<Self> {
        let options = parse_options(input)?;
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
    let bindings = match Bindings::new(&bytes, input.options.krate, input.options.views) {
        Ok(b) => b,
        Err(e) => {
            return syn::Error::new(input.path.span(), format!("`{}`: {e}", input.path.value()))
                .to_compile_error()
        }
    };
    let vis = &input.vis;
    let ident = &input.ident;
    let file_text = file.display().to_string();
    let doc = format!(
        " Bindings for the {} format{} of `{}`, generated at compile time.",
        bindings.count,
        if bindings.count == 1 { "" } else { "s" },
        input.path.value()
    );
    let skipped_doc = bindings.skipped.iter().map(|s| {
        let line = format!(" - skipped: {s}");
        quote!(#[doc = #line])
    });
    let items = &bindings.items;
    let errors = bindings.errors.to_compile_errors();
    quote! {
        #[doc = #doc]
        #[doc = ""]
        #(#skipped_doc)*
        #vis mod #ident {
            // Rebuild when the log changes.
            const _: &[u8] = ::core::include_bytes!(#file_text);
            #items
        }
        #errors
    }
}

/// The bindings of every format of a log: the items of `ulog_module!`'s module.
pub(crate) struct Bindings {
    /// Structs, their implementations and `visit_bindings`.
    pub items: TokenStream,
    /// Formats the macros cannot bind (two fields with one Rust name); empty when all
    /// went well.
    pub errors: Errors,
    /// Formats bound (given a struct with its implementations).
    pub count: usize,
    /// Formats left out, with why.
    pub skipped: Vec<String>,
}

impl Bindings {
    /// Reads the formats of the log `bytes` and emits their bindings (borrowed from
    /// payloads, with `views`), naming the runtime crate `krate` (default `::ulog_core`).
    pub fn new(bytes: &[u8], krate: Option<syn::Path>, views: bool) -> Result<Bindings, String> {
        let found = definitions::formats_in(bytes).map_err(|e| e.to_string())?;
        let mut sources: Vec<Source> = Vec::new();
        let mut skipped: Vec<String> = Vec::new();
        for (offset, parsed) in found {
            match parsed {
                Ok(format) => {
                    // A later definition of a name replaces the earlier one, as in readers.
                    sources.retain(|s| s.format.name != format.name);
                    let text = format.to_string();
                    sources.push(Source {
                        format,
                        lit: None,
                        text,
                    });
                }
                Err(e) => skipped.push(format!("format at offset {offset}: {e}")),
            }
        }
        let paths = Paths::new(krate);
        let mut errors = Errors::default();
        let mut bound = Vec::new();
        let structs = emit_structs(
            &sources,
            &paths,
            views,
            &mut errors,
            Some(&mut skipped),
            &mut bound,
        );
        let typed = paths.typed();
        let visit_body = if bound.is_empty() {
            quote!(let _ = visitor;)
        } else {
            quote!(#(visitor.visit::<#bound>();)*)
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
        let items = quote! {
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
            count: bound.len(),
            skipped,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::Bindings;

    /// A log of a header and these format texts.
    fn log_with_formats(formats: &[&str]) -> Vec<u8> {
        let mut log = ulog_format::definitions::MAGIC.to_vec();
        log.extend_from_slice(&[1, 0, 0, 0, 0, 0, 0, 0, 0]);
        for text in formats {
            log.extend_from_slice(&(text.len() as u16).to_le_bytes());
            log.push(b'F');
            log.extend_from_slice(text.as_bytes());
        }
        log
    }

    #[test]
    fn formats_that_cannot_be_laid_out_are_listed_as_skipped_not_counted() {
        let log = log_with_formats(&[
            "ok:uint64_t timestamp;",
            "broken:uint64_t timestamp;missing m;",
            "uses_broken:broken[2] b;",
            "bad text",
        ]);
        let b = Bindings::new(&log, None, false).unwrap();
        assert_eq!(b.count, 1, "only `ok` is bound");
        assert_eq!(b.skipped.len(), 3, "{:?}", b.skipped);
        assert!(
            b.skipped[0].starts_with("format at offset"),
            "{:?}",
            b.skipped
        );
        assert!(b.skipped[1].contains("`broken`") && b.skipped[1].contains("missing"));
        assert!(b.skipped[2].contains("`uses_broken`"));
        assert!(b.errors.is_empty());
    }
}
