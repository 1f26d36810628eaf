//! The intermediate form between the inputs (a struct, format strings) and the
//! expansion: a message with its fields sorted into shapes, and the paths generated
//! code uses.

use proc_macro2::{Ident, Span, TokenStream};
use quote::quote;
use ulog_format::BasicType;

/// A binding to expand.
pub(crate) struct Message {
    /// The Rust type.
    pub ident: Ident,
    /// Its visibility (the wire struct gets the same).
    pub vis: syn::Visibility,
    /// The ULog message name.
    pub name: String,
    /// The runtime crate's path.
    pub paths: Paths,
    /// The fields, in order.
    pub fields: Vec<MessageField>,
}

/// One field of a binding.
pub(crate) struct MessageField {
    /// The Rust field.
    pub ident: Ident,
    /// The ULog field name.
    pub name: String,
    /// Where errors about it point.
    pub span: Span,
    /// Other ULog names to find it under.
    pub aliases: Vec<String>,
    /// How it maps to bytes.
    pub shape: Shape,
}

/// How a field maps to bytes.
pub(crate) enum Shape {
    /// One value of a type implementing `WireField` (basic, `CharArray<N>`, nested).
    Scalar(syn::Type),
    /// `[T; N]` of a type implementing `ArrayElement`.
    Array { elem: syn::Type, len: syn::Expr },
    /// `[u8; N]` holding a `char[N]` string (`len: Some(N)`), or `u8` holding one
    /// `char`.
    CharBytes { len: Option<syn::Expr> },
    /// `_padding…`: `bytes` bytes of zeros, `count` values of `ty` in the format
    /// (`None`: not an array).
    Padding {
        ty: BasicType,
        count: Option<syn::Expr>,
        bytes: syn::Expr,
        array: bool,
    },
}

/// The paths generated code uses, all below the runtime crate.
pub(crate) struct Paths {
    krate: syn::Path,
}

impl Paths {
    pub(crate) fn new(krate: Option<syn::Path>) -> Paths {
        Paths {
            krate: krate.unwrap_or_else(|| syn::parse_quote!(::ulog_core)),
        }
    }

    /// The runtime crate's path.
    pub(crate) fn krate(&self) -> &syn::Path {
        &self.krate
    }

    /// `ulog_core::typed`
    pub(crate) fn typed(&self) -> TokenStream {
        let k = &self.krate;
        quote!(#k::typed)
    }

    /// `ulog_core::typed::__private`
    pub(crate) fn private(&self) -> TokenStream {
        let k = &self.krate;
        quote!(#k::typed::__private)
    }

    /// The crate path as text, for `#[zerocopy(crate = "…")]`.
    pub(crate) fn zerocopy_text(&self) -> String {
        let k = &self.krate;
        quote!(#k::typed::__private::zerocopy)
            .to_string()
            .replace(' ', "")
    }
}

/// The Rust type of a basic ULog type (`char` is handled apart).
pub(crate) fn rust_basic(ty: BasicType) -> TokenStream {
    match ty {
        BasicType::Int8 => quote!(i8),
        BasicType::UInt8 | BasicType::Char => quote!(u8),
        BasicType::Int16 => quote!(i16),
        BasicType::UInt16 => quote!(u16),
        BasicType::Int32 => quote!(i32),
        BasicType::UInt32 => quote!(u32),
        BasicType::Int64 => quote!(i64),
        BasicType::UInt64 => quote!(u64),
        BasicType::Float => quote!(f32),
        BasicType::Double => quote!(f64),
        BasicType::Bool => quote!(bool),
    }
}

/// The `BasicType` variant name, for generated code.
pub(crate) fn basic_variant(ty: BasicType) -> Ident {
    Ident::new(&format!("{ty:?}"), Span::call_site())
}
