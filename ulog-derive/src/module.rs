//! `ulog_module!`: a module of bindings for every format of a reference log.

use std::path::PathBuf;

use proc_macro2::{Span, TokenStream};
use quote::quote;
use syn::parse::{Parse, ParseStream};
use syn::{Ident, LitStr, Token, Visibility};
use ulog_format::definitions;

use crate::errors::Errors;
use crate::ir::Paths;
use crate::structs::{emit_structs, parse_crate, Source};

struct ModuleInput {
    krate: Option<syn::Path>,
    vis: Visibility,
    ident: Ident,
    path: LitStr,
}

impl Parse for ModuleInput {
    fn parse(input: ParseStream) -> syn::Result<Self> {
        let krate = parse_crate(input)?;
        let vis = input.parse()?;
        input.parse::<Token![mod]>()?;
        let ident = input.parse()?;
        input.parse::<Token![=]>()?;
        let path = input.parse()?;
        if input.peek(Token![;]) {
            input.parse::<Token![;]>()?;
        }
        Ok(ModuleInput {
            krate,
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
    let found = match definitions::formats_in(&bytes) {
        Ok(f) => f,
        Err(e) => {
            return syn::Error::new(input.path.span(), format!("`{}`: {e}", input.path.value()))
                .to_compile_error()
        }
    };
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
    let paths = Paths::new(input.krate);
    let mut errors = Errors::default();
    let mut bound = Vec::new();
    let structs = emit_structs(&sources, &paths, &mut errors, true, &mut bound);
    let typed = paths.typed();
    let visit_body = if bound.is_empty() {
        quote!(let _ = visitor;)
    } else {
        quote!(#(visitor.visit::<#bound>();)*)
    };
    let errors = errors.to_compile_errors();
    let vis = &input.vis;
    let ident = &input.ident;
    let file_text = file.display().to_string();
    let doc = format!(
        " Bindings for the {} formats of `{}`, generated at compile time.",
        sources.len(),
        input.path.value()
    );
    let skipped_doc = skipped.iter().map(|s| {
        let line = format!(" - skipped: {s}");
        quote!(#[doc = #line])
    });
    let _ = Span::call_site();
    quote! {
        #[doc = #doc]
        #[doc = ""]
        #(#skipped_doc)*
        #vis mod #ident {
            // Rebuild when the log changes.
            const _: &[u8] = ::core::include_bytes!(#file_text);
            #structs

            /// Calls `visitor` with each binding of the module, in the log's order.
            pub fn visit_bindings<V: #typed::BindingVisitor + ?::core::marker::Sized>(visitor: &mut V) {
                #visit_body
            }
        }
        #errors
    }
}
