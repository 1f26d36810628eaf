//! From the derive input to the intermediate form: ULog names decided, field types
//! sorted into shapes, unsupported types reported.

use proc_macro2::Span;
use syn::spanned::Spanned;
use syn::Type;
use ulog_format::BasicType;

use crate::errors::Errors;
use crate::input::{Input, InputField};
use crate::ir::{Absent, Message, MessageField, Paths, Shape};
use crate::names;

/// Lowers a parsed struct. Fields whose type cannot be bound are left out (their
/// error is recorded), so that the others are still checked.
pub(crate) fn lower(input: Input, errors: &mut Errors) -> (Message, Option<Span>) {
    let name_lit = input.attrs.name.get();
    let name_span = name_lit.as_ref().map(|l| l.span());
    let named_after_struct = name_lit.is_none();
    let name = name_lit
        .map(|l| l.value())
        .unwrap_or_else(|| names::snake_case(&input.ident.to_string()));
    let paths = Paths::new(input.attrs.krate.get());
    let view = input.attrs.view.get();
    let aliases = input
        .attrs
        .aliases
        .iter()
        .map(|a| (a.value(), a.span()))
        .collect();
    let fields = input
        .fields
        .into_iter()
        .filter_map(|f| lower_field(f, errors))
        .collect();
    (
        Message {
            ident: input.ident,
            name,
            named_after_struct,
            aliases,
            paths,
            fields,
            view,
        },
        name_span,
    )
}

fn lower_field(f: InputField, errors: &mut Errors) -> Option<MessageField> {
    let name_lit = f.attrs.name.get();
    let span = name_lit
        .as_ref()
        .map(|l| l.span())
        .unwrap_or_else(|| f.ident.span());
    let name = name_lit
        .map(|l| l.value())
        .unwrap_or_else(|| names::unraw(&f.ident));
    let aliases = f.attrs.aliases.iter().map(|a| a.value()).collect();
    let char_span = f.attrs.char_.get();
    let default = f.attrs.default.get();
    let padding = ulog_format::is_padding_name(&name);
    // `Option<T>`: the field's shape is `T`'s, and it may be absent.
    let (ty, option) = match option_inner(&f.ty) {
        Some(inner) if !padding => (inner, true),
        _ => (&f.ty, false),
    };
    let absent = match (option, default) {
        (true, Some((span, _))) => {
            errors.at(
                span,
                "an `Option` field is already optional: `None` when the log lacks it; `default` is for fields that are not `Option`s",
            );
            Absent::None
        }
        (true, None) => Absent::None,
        (false, Some((span, _))) if padding => {
            errors.at(span, "a padding field cannot have a default");
            Absent::Required
        }
        (false, Some((_, expr))) => Absent::Default(expr.map(Box::new)),
        (false, None) => Absent::Required,
    };
    let mut converts = Vec::new();
    for (ty, function) in f.attrs.converts {
        match ulog_format::BasicType::from_name(&ty.to_string()) {
            Some(BasicType::Char) | None => {
                let names: Vec<&str> = BasicType::ALL
                    .iter()
                    .filter(|t| **t != BasicType::Char)
                    .map(|t| t.name())
                    .collect();
                errors.at(
                    ty.span(),
                    format_args!(
                        "`{ty}` is not a ULog type a field can be converted from: one of {}",
                        names.join(", ")
                    ),
                );
            }
            Some(_) if padding || char_span.is_some() => {
                errors.at(ty.span(), "a padding or `char` field cannot be converted");
            }
            Some(b) if converts.iter().any(|(c, _)| *c == b) => {
                errors.at(
                    ty.span(),
                    format_args!("a conversion from `{ty}` is declared twice"),
                );
            }
            Some(b) => converts.push((b, function)),
        }
    }
    let shape = if padding {
        if option_inner(&f.ty).is_some() {
            errors.at(f.ty.span(), "a padding field cannot be an `Option`");
            return None;
        }
        padding_shape(ty, errors)
    } else if let Some(char_span) = char_span {
        char_shape(ty, char_span, errors)
    } else {
        value_shape(ty, errors)
    }?;
    Some(MessageField {
        ident: f.ident,
        name,
        span,
        aliases,
        shape,
        absent,
        basic: None,
        converts,
    })
}

/// `T` of a field type `Option<T>` (also `core::option::Option<T>`).
fn option_inner(ty: &Type) -> Option<&Type> {
    let Type::Path(p) = strip(ty) else {
        return None;
    };
    let last = p.path.segments.last()?;
    if p.qself.is_some() || last.ident != "Option" {
        return None;
    }
    match &last.arguments {
        syn::PathArguments::AngleBracketed(args) if args.args.len() == 1 => match &args.args[0] {
            syn::GenericArgument::Type(t) => Some(t),
            _ => None,
        },
        _ => None,
    }
}

fn strip(ty: &Type) -> &Type {
    match ty {
        Type::Group(g) => strip(&g.elem),
        Type::Paren(p) => strip(&p.elem),
        t => t,
    }
}

fn is_u8(ty: &Type) -> bool {
    matches!(strip(ty), Type::Path(p) if p.qself.is_none() && p.path.is_ident("u8"))
}

fn padding_shape(ty: &Type, errors: &mut Errors) -> Option<Shape> {
    match strip(ty) {
        t if is_u8(t) => Some(Shape::Padding {
            ty: BasicType::UInt8,
            count: None,
            bytes: syn::parse_quote!(1),
            array: false,
        }),
        Type::Array(a) if is_u8(&a.elem) => Some(Shape::Padding {
            ty: BasicType::UInt8,
            count: Some(a.len.clone()),
            bytes: a.len.clone(),
            array: true,
        }),
        t => {
            errors.at(
                t.span(),
                "a padding field (`_padding…`) must be `u8` or `[u8; N]`",
            );
            None
        }
    }
}

fn char_shape(ty: &Type, char_span: Span, errors: &mut Errors) -> Option<Shape> {
    match strip(ty) {
        t if is_u8(t) => Some(Shape::CharBytes { len: None }),
        Type::Array(a) if is_u8(&a.elem) => Some(Shape::CharBytes {
            len: Some(a.len.clone()),
        }),
        _ => {
            errors.at(char_span, "`char` needs a field of type `[u8; N]` or `u8`");
            None
        }
    }
}

const SUPPORTED: &str = "ULog fields are u8..u64, i8..i64, f32, f64, bool, `CharArray<N>`, fixed arrays of these, nested messages, or `Option`s of these";

/// Path types that are never fields, with a hint.
fn unsupported_path(ident: &str) -> Option<&'static str> {
    Some(match ident {
        "usize" | "isize" => "its size depends on the target; use a fixed-size integer",
        "u128" | "i128" => "ULog has no 128-bit integers",
        "char" => {
            "a ULog `char` is one byte: use `CharArray<N>`, or `u8`/`[u8; N]` with `#[ulog(char)]`"
        }
        "Option" => "an `Option` holds a whole field: it cannot be an array element or hold another `Option`",
        "String" | "str" | "Vec" | "Box" | "Cow" | "Rc" | "Arc" => "ULog fields have a fixed size",
        _ => return None,
    })
}

fn check_element(ty: &Type, errors: &mut Errors) -> bool {
    match strip(ty) {
        Type::Path(p) => {
            if let Some(last) = p.path.segments.last() {
                if let Some(hint) = unsupported_path(&last.ident.to_string()) {
                    errors.at(
                        ty.span(),
                        format_args!("unsupported field type `{}`: {hint}", last.ident),
                    );
                    return false;
                }
            }
            true
        }
        Type::Array(_) => {
            errors.at(
                ty.span(),
                "unsupported field type: ULog has no arrays of arrays",
            );
            false
        }
        _ => {
            errors.at(
                ty.span(),
                format_args!("unsupported field type: {SUPPORTED}"),
            );
            false
        }
    }
}

fn value_shape(ty: &Type, errors: &mut Errors) -> Option<Shape> {
    match strip(ty) {
        Type::Array(a) => check_element(&a.elem, errors).then(|| Shape::Array {
            elem: (*a.elem).clone(),
            len: a.len.clone(),
        }),
        t => check_element(t, errors).then(|| Shape::Scalar(t.clone())),
    }
}
