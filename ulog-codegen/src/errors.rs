//! Collecting every error of one macro input, each with its span.

use proc_macro2::{Span, TokenStream};

/// The errors of one macro invocation, reported together.
#[derive(Default)]
pub(crate) struct Errors {
    list: Vec<syn::Error>,
}

impl Errors {
    /// Records an error at `span`.
    pub(crate) fn at(&mut self, span: Span, message: impl core::fmt::Display) {
        self.list.push(syn::Error::new(span, message));
    }

    /// Records an error (from syn, or made elsewhere).
    pub(crate) fn push(&mut self, error: syn::Error) {
        self.list.push(error);
    }

    pub(crate) fn is_empty(&self) -> bool {
        self.list.is_empty()
    }

    /// The messages, in order.
    pub(crate) fn messages(&self) -> Vec<String> {
        self.list.iter().map(|e| e.to_string()).collect()
    }

    /// A `compile_error!` per error.
    pub(crate) fn to_compile_errors(&self) -> TokenStream {
        self.list.iter().map(syn::Error::to_compile_error).collect()
    }
}
