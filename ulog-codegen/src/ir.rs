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
    /// The ULog message name.
    pub name: String,
    /// Whether the name was derived from the struct's name (no `name` attribute).
    pub named_after_struct: bool,
    /// `#[ulog(alias = "…")]`: the topic's other names, with their spans.
    pub aliases: Vec<(String, Span)>,
    /// The runtime crate's path.
    pub paths: Paths,
    /// The fields, in order.
    pub fields: Vec<MessageField>,
    /// `#[ulog(view)]`: the binding can be borrowed from payloads.
    pub view: Option<Span>,
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
    /// What it takes when a log lacks it.
    pub absent: Absent,
    /// Its ULog basic type and array length, when it is known to be one when the code
    /// is generated (bindings of formats and logs).
    pub basic: Option<(BasicType, Option<usize>)>,
    /// `#[ulog(convert(TYPE = function))]`: other ULog types it is read from, each
    /// through its function.
    pub converts: Vec<(BasicType, syn::Path)>,
}

/// What a field takes when a log's format lacks it.
pub(crate) enum Absent {
    /// Nothing: the format does not fit.
    Required,
    /// `None`: the field is `Option<shape>`.
    None,
    /// `Default::default()`, or the expression given (boxed: a `syn::Expr` is some
    /// hundreds of bytes, and most fields have none).
    Default(Option<Box<syn::Expr>>),
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
#[derive(Clone)]
pub(crate) struct Paths {
    krate: syn::Path,
    /// Whether the runtime's private module is named by the alias that
    /// [`Paths::private_alias`] declares (a module of bindings declares it once).
    aliased: bool,
}

impl Paths {
    pub(crate) fn new(krate: Option<syn::Path>) -> Paths {
        Paths {
            krate: krate.unwrap_or_else(|| syn::parse_quote!(::ulog_core)),
            aliased: false,
        }
    }

    /// The same paths, the private module named by its alias (`__p`).
    pub(crate) fn aliased(&self) -> Paths {
        Paths {
            krate: self.krate.clone(),
            aliased: true,
        }
    }

    /// The `use` that declares the private module's alias.
    pub(crate) fn private_alias(&self) -> TokenStream {
        let k = &self.krate;
        quote!(use #k::typed::__private as __p;)
    }

    /// `ulog_core::ULogMessage`
    pub(crate) fn message_trait(&self) -> TokenStream {
        let k = &self.krate;
        quote!(#k::ULogMessage)
    }

    /// `ulog_core::ULogTopics`
    pub(crate) fn topics_trait(&self) -> TokenStream {
        let k = &self.krate;
        quote!(#k::ULogTopics)
    }

    /// `ulog_core::align`
    pub(crate) fn align(&self) -> TokenStream {
        let k = &self.krate;
        quote!(#k::align)
    }

    /// `ulog_core::typed`
    pub(crate) fn typed(&self) -> TokenStream {
        let k = &self.krate;
        quote!(#k::typed)
    }

    /// `ulog_core::typed::__private`
    pub(crate) fn private(&self) -> TokenStream {
        if self.aliased {
            return quote!(__p);
        }
        let k = &self.krate;
        quote!(#k::typed::__private)
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

/// The type of a basic ULog type in a binding borrowed from payloads: alignment 1,
/// little endian (`char` is handled apart).
pub(crate) fn wire_basic(ty: BasicType, typed: &TokenStream) -> TokenStream {
    match ty {
        BasicType::Int8 => quote!(i8),
        BasicType::UInt8 | BasicType::Char => quote!(u8),
        BasicType::Int16 => quote!(#typed::le::I16),
        BasicType::UInt16 => quote!(#typed::le::U16),
        BasicType::Int32 => quote!(#typed::le::I32),
        BasicType::UInt32 => quote!(#typed::le::U32),
        BasicType::Int64 => quote!(#typed::le::I64),
        BasicType::UInt64 => quote!(#typed::le::U64),
        BasicType::Float => quote!(#typed::le::F32),
        BasicType::Double => quote!(#typed::le::F64),
        BasicType::Bool => quote!(#typed::ByteBool),
    }
}

/// The `BasicType` variant name, for generated code.
pub(crate) fn basic_variant(ty: BasicType) -> Ident {
    Ident::new(&format!("{ty:?}"), Span::call_site())
}
