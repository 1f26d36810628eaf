//! The `#[ulog(…)]` attributes, parsed into typed forms that keep their spans.
//!
//! Container: `name = "…"` (the ULog message name), `alias = "…"` (repeatable: the
//! topic's names in other firmware), `crate = "…"` (the runtime crate's path), `view`
//! (the binding can be borrowed from payloads). Field: `name = "…"` (the
//! ULog field name), `alias = "…"` (repeatable: names in older logs), `char` (a
//! `[u8; N]` that is a `char[N]` string), `default` or `default = expr` (the value when
//! a log lacks the field), `convert(TYPE = function, …)` (how to read the field from
//! logs that hold it in ULog type `TYPE`).

use proc_macro2::Span;
use syn::spanned::Spanned;
use syn::{Attribute, LitStr};

use crate::errors::Errors;

/// A value that may be set once.
pub(crate) struct Once<T> {
    what: &'static str,
    value: Option<T>,
}

impl<T> Once<T> {
    pub(crate) fn new(what: &'static str) -> Once<T> {
        Once { what, value: None }
    }

    fn set(&mut self, value: T, span: Span, errors: &mut Errors) {
        if self.value.is_some() {
            errors.at(span, format_args!("`{}` is set twice", self.what));
        } else {
            self.value = Some(value);
        }
    }

    pub(crate) fn get(self) -> Option<T> {
        self.value
    }
}

/// Attributes of the struct or enum.
pub(crate) struct ContainerAttrs {
    pub name: Once<LitStr>,
    pub aliases: Vec<LitStr>,
    pub krate: Once<syn::Path>,
    pub view: Once<Span>,
}

/// Attributes of a field.
pub(crate) struct FieldAttrs {
    pub name: Once<LitStr>,
    pub aliases: Vec<LitStr>,
    pub char_: Once<Span>,
    /// `default` (`None` inside: the type's `Default`) or `default = expr`.
    pub default: Once<(Span, Option<syn::Expr>)>,
    /// `convert(TYPE = function, …)`: the ULog type name and the function.
    pub converts: Vec<(syn::Ident, syn::Path)>,
}

fn ulog_attrs(attrs: &[Attribute]) -> impl Iterator<Item = &Attribute> {
    attrs.iter().filter(|a| a.path().is_ident("ulog"))
}

/// Parses the container attributes; `allow_name` is false for enums.
pub(crate) fn container(
    attrs: &[Attribute],
    allow_name: bool,
    errors: &mut Errors,
) -> ContainerAttrs {
    let mut out = ContainerAttrs {
        name: Once::new("name"),
        aliases: Vec::new(),
        krate: Once::new("crate"),
        view: Once::new("view"),
    };
    for attr in ulog_attrs(attrs) {
        let result = attr.parse_nested_meta(|meta| {
            if meta.path.is_ident("name") && allow_name {
                let lit: LitStr = meta.value()?.parse()?;
                out.name.set(lit, meta.path.span(), errors);
            } else if meta.path.is_ident("alias") && allow_name {
                out.aliases.push(meta.value()?.parse()?);
            } else if meta.path.is_ident("crate") {
                let lit: LitStr = meta.value()?.parse()?;
                match lit.parse_with(syn::Path::parse_mod_style) {
                    Ok(path) => out.krate.set(path, meta.path.span(), errors),
                    Err(_) => errors.at(lit.span(), "`crate` must be a path, like \"::ulog_core\""),
                }
            } else if meta.path.is_ident("view") && allow_name {
                out.view.set(meta.path.span(), meta.path.span(), errors);
            } else {
                let expected = if allow_name {
                    "`name`, `alias`, `crate` or `view`"
                } else {
                    "`crate`"
                };
                return Err(meta.error(format_args!("unknown attribute, expected {expected}")));
            }
            Ok(())
        });
        if let Err(e) = result {
            errors.push(e);
        }
    }
    out
}

/// Parses a field's attributes.
pub(crate) fn field(attrs: &[Attribute], errors: &mut Errors) -> FieldAttrs {
    let mut out = FieldAttrs {
        name: Once::new("name"),
        aliases: Vec::new(),
        char_: Once::new("char"),
        default: Once::new("default"),
        converts: Vec::new(),
    };
    for attr in ulog_attrs(attrs) {
        let result = attr.parse_nested_meta(|meta| {
            if meta.path.is_ident("convert") {
                meta.parse_nested_meta(|inner| {
                    let Some(ty) = inner.path.get_ident().cloned() else {
                        return Err(inner.error(
                            "expected a ULog type name, like `convert(uint32_t = my_function)`",
                        ));
                    };
                    out.converts.push((ty, inner.value()?.parse()?));
                    Ok(())
                })?;
            } else if meta.path.is_ident("name") {
                let lit: LitStr = meta.value()?.parse()?;
                out.name.set(lit, meta.path.span(), errors);
            } else if meta.path.is_ident("alias") {
                out.aliases.push(meta.value()?.parse()?);
            } else if meta.path.is_ident("char") {
                out.char_.set(meta.path.span(), meta.path.span(), errors);
            } else if meta.path.is_ident("default") {
                let value = if meta.input.peek(syn::Token![=]) {
                    Some(meta.value()?.parse::<syn::Expr>()?)
                } else {
                    None
                };
                out.default
                    .set((meta.path.span(), value), meta.path.span(), errors);
            } else {
                return Err(meta.error(
                    "unknown attribute, expected `name`, `alias`, `char`, `default` or `convert`",
                ));
            }
            Ok(())
        });
        if let Err(e) = result {
            errors.push(e);
        }
    }
    out
}

/// Rejects `#[ulog]` attributes where none belong (enum variants).
pub(crate) fn none(attrs: &[Attribute], errors: &mut Errors) {
    for attr in ulog_attrs(attrs) {
        errors.at(attr.span(), "no `ulog` attributes are allowed here");
    }
}
