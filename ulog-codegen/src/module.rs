//! `ulog_module!`: a module of bindings for every format of a reference log.

use std::path::PathBuf;

use proc_macro2::TokenStream;
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
    let bindings = match Bindings::new(&bytes, input.krate) {
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
        " Bindings for the {} formats of `{}`, generated at compile time.",
        bindings.count,
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
    /// Formats bound.
    pub count: usize,
    /// Formats left out, with why.
    pub skipped: Vec<String>,
}

impl Bindings {
    /// Reads the formats of the log `bytes` and emits their bindings, naming the
    /// runtime crate `krate` (default `::ulog_core`).
    pub fn new(bytes: &[u8], krate: Option<syn::Path>) -> Result<Bindings, String> {
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
        let structs = emit_structs(&sources, &paths, &mut errors, true, &mut bound);
        let typed = paths.typed();
        let visit_body = if bound.is_empty() {
            quote!(let _ = visitor;)
        } else {
            quote!(#(visitor.visit::<#bound>();)*)
        };
        let items = quote! {
            #structs

            /// Calls `visitor` with each binding of the module, in the log's order.
            pub fn visit_bindings<V: #typed::BindingVisitor + ?::core::marker::Sized>(visitor: &mut V) {
                #visit_body
            }
        };
        Ok(Bindings {
            items,
            errors,
            count: sources.len(),
            skipped,
        })
    }
}
