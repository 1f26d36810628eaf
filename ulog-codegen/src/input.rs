//! The derive input: a struct with named fields and no generics.

use proc_macro2::Ident;
use syn::spanned::Spanned;
use syn::{Data, DeriveInput, Fields, Type};

use crate::attr::{self, ContainerAttrs, FieldAttrs};
use crate::errors::Errors;

/// A struct to bind.
pub(crate) struct Input {
    pub ident: Ident,
    pub attrs: ContainerAttrs,
    pub fields: Vec<InputField>,
}

/// A named field with its attributes.
pub(crate) struct InputField {
    pub ident: Ident,
    pub ty: Type,
    pub attrs: FieldAttrs,
}

/// Reads a derive input; what cannot be a binding is reported, and as much as
/// possible is still read so that later checks report their errors too.
pub(crate) fn parse(input: &DeriveInput, errors: &mut Errors) -> Input {
    let attrs = attr::container(&input.attrs, true, errors);
    if !input.generics.params.is_empty() {
        errors.at(
            input.generics.span(),
            "a ULog message cannot be generic: its format is fixed",
        );
    }
    let mut fields = Vec::new();
    match &input.data {
        Data::Struct(data) => match &data.fields {
            Fields::Named(named) => {
                for f in &named.named {
                    if let Some(ident) = &f.ident {
                        fields.push(InputField {
                            ident: ident.clone(),
                            ty: f.ty.clone(),
                            attrs: attr::field(&f.attrs, errors),
                        });
                    }
                }
                if named.named.is_empty() {
                    errors.at(
                        input.ident.span(),
                        "a ULog message needs at least one field",
                    );
                }
            }
            Fields::Unnamed(_) | Fields::Unit => errors.at(
                input.ident.span(),
                "a ULog message needs named fields: `struct Name { field: Type, … }`",
            ),
        },
        Data::Enum(e) => errors.at(
            e.enum_token.span,
            "`ULogMessage` binds a struct; for an enum of topics use `ULogTopics`",
        ),
        Data::Union(u) => errors.at(u.union_token.span, "`ULogMessage` cannot bind a union"),
    }
    Input {
        ident: input.ident.clone(),
        attrs,
        fields,
    }
}
