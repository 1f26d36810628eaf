//! Code generation for a derived binding (`#[derive(ULogMessage)]`): its `WireField`
//! and `ULogMessage` implementations, inside `const _: () = { … };`, with absolute
//! paths. (Bindings of known formats: `known.rs`.)
//!
//! A binding's wire image is a byte array of its size, read and written field by field
//! at offsets the compiler computes from the field types: no type is generated beside
//! the binding, and the table of fields (`FieldDef`s) is built once.

use proc_macro2::TokenStream;
use quote::{format_ident, quote, quote_spanned};

use crate::ir::{basic_variant, Absent, Message, MessageField, Shape};

/// What one field's type contributes to the implementations.
struct FieldCode {
    /// Its wire size.
    size: TokenStream,
    /// The presence slots of a nested binding inside it.
    nested_slots: TokenStream,
    /// How many payload offsets it takes, and whether it reads from them
    /// (`WireField::SOURCES`, `WireField::DIRECT`).
    sources: TokenStream,
    direct: TokenStream,
    /// Its `FieldKind` and array length.
    kind: TokenStream,
    count: TokenStream,
    /// Whether its type is its wire image, and whether its values can be written
    /// (`None`: a basic type, always).
    is_wire: TokenStream,
    writability: Option<TokenStream>,
    /// A compile-time check of its type, with its span.
    assert: Option<TokenStream>,
}

fn field_code(m: &Message, f: &MessageField) -> FieldCode {
    let typed = m.paths.typed();
    let private = m.paths.private();
    let wf = quote!(#typed::WireField);
    let none = quote!(::core::option::Option::None);
    match &f.shape {
        Shape::Scalar(ty) => FieldCode {
            size: quote!(#private::wire_size::<#ty>()),
            nested_slots: quote!(<#ty as #wf>::OPTIONAL),
            sources: quote!(<#ty as #wf>::SOURCES),
            direct: quote!(<#ty as #wf>::DIRECT),
            kind: quote!(<#ty as #wf>::KIND),
            count: quote!(<#ty as #wf>::COUNT),
            is_wire: quote!(<#ty as #wf>::IS_WIRE),
            writability: Some(quote!(<#ty as #wf>::Writability)),
            assert: Some(quote_spanned!(f.span=> #private::assert_field::<#ty>();)),
        },
        Shape::Array { elem, len } => FieldCode {
            size: quote!((#private::wire_size::<#elem>() * (#len))),
            nested_slots: quote!(<#elem as #wf>::OPTIONAL),
            sources: quote!(#private::array_sources::<#elem>(#len)),
            direct: quote!(<#elem as #wf>::DIRECT),
            kind: quote!(<#elem as #wf>::KIND),
            count: quote!(::core::option::Option::Some(#len)),
            is_wire: quote!(<#elem as #wf>::IS_WIRE),
            writability: Some(quote!(<#elem as #wf>::Writability)),
            assert: Some(quote_spanned!(f.span=> #private::assert_array_element::<#elem>();)),
        },
        Shape::CharBytes { len } => FieldCode {
            size: match len {
                Some(n) => quote!((#n)),
                None => quote!(1usize),
            },
            nested_slots: quote!(0usize),
            sources: quote!(1usize),
            direct: quote!(true),
            kind: quote!(#typed::FieldKind::Basic(#private::BasicType::Char)),
            count: match len {
                Some(n) => quote!(::core::option::Option::Some(#n)),
                None => none,
            },
            is_wire: quote!(true),
            writability: None,
            assert: None,
        },
        Shape::Padding {
            ty, count, bytes, ..
        } => {
            let variant = basic_variant(*ty);
            FieldCode {
                size: quote!((#bytes)),
                nested_slots: quote!(0usize),
                sources: quote!(0usize),
                direct: quote!(true),
                kind: quote!(#typed::FieldKind::Basic(#private::BasicType::#variant)),
                count: match count {
                    Some(c) => quote!(::core::option::Option::Some(#c)),
                    None => none,
                },
                is_wire: quote!(true),
                writability: None,
                assert: None,
            }
        }
    }
}

/// Where a field is read from: the binding's wire image at an offset, or a log's
/// payload at the offsets from `sources[k]` (`WireField::from_payload`).
enum ReadFrom<'t> {
    Image(&'t TokenStream),
    Payload(&'t TokenStream),
}

/// Reads field `f`, its nested slots from `present`.
fn read_expr(
    m: &Message,
    f: &MessageField,
    from: ReadFrom<'_>,
    present: &TokenStream,
) -> TokenStream {
    let private = m.paths.private();
    let typed = m.paths.typed();
    let (one, array, args) = match from {
        ReadFrom::Image(offset) => (quote!(read), quote!(read_array), quote!(wire, #offset)),
        ReadFrom::Payload(k) => (
            quote!(read_source),
            quote!(read_array_source),
            quote!(payload, sources, #k),
        ),
    };
    match &f.shape {
        Shape::Scalar(ty) => quote!(#private::#one::<#ty>(#args, #present)),
        // The length is the field's: the compiler infers it.
        Shape::Array { .. } => quote!(#private::#array(#args, #present)),
        Shape::CharBytes { len: Some(_) } => {
            quote!(#private::#array(#args, #typed::Present::ALL))
        }
        Shape::CharBytes { len: None } => {
            quote!(#private::#one::<u8>(#args, #typed::Present::ALL))
        }
        Shape::Padding {
            bytes, array: true, ..
        } => quote!([0u8; #bytes]),
        Shape::Padding { array: false, .. } => quote!(0u8),
    }
}

/// Field `f` read from a log's payload through the conversions it declares
/// (`#[ulog(convert(TYPE = function))]`): the function of the log's value where the
/// plan found the field in one of those types, else `otherwise`.
fn declared_conversions(
    m: &Message,
    f: &MessageField,
    k: &TokenStream,
    present: &TokenStream,
    otherwise: TokenStream,
) -> TokenStream {
    let private = m.paths.private();
    let (reader, inferred) = match &f.shape {
        Shape::Array { .. } => (quote!(read_declared_array), quote!(_, _)),
        _ => (quote!(read_declared), quote!(_)),
    };
    let arms = f.converts.iter().map(|(b, function)| {
        let v = basic_variant(*b);
        let native = crate::ir::rust_basic(*b);
        quote!(::core::option::Option::Some(c) if c.ty == #private::BasicType::#v => #private::#reader::<#native, #inferred>(
            payload, sources, #k, #private::BasicType::#v, #function, #present,
        ),)
    });
    quote!(match #private::Converted::unpack(sources.get(#k).copied().unwrap_or(u32::MAX)) {
        #(#arms)*
        _ => #otherwise,
    })
}

/// Writes `value` (an expression of a reference to the field's value) at `offset` of
/// `wire`.
fn write_stmt(
    m: &Message,
    f: &MessageField,
    offset: &TokenStream,
    value: &TokenStream,
) -> TokenStream {
    let private = m.paths.private();
    match &f.shape {
        Shape::Scalar(ty) => quote!(#private::write::<#ty>(&mut wire, #offset, #value);),
        Shape::Array { elem, .. } => {
            quote!(#private::write_array::<#elem>(&mut wire, #offset, #value);)
        }
        Shape::CharBytes { len: Some(_) } => {
            quote!(#private::write_array::<u8>(&mut wire, #offset, #value);)
        }
        Shape::CharBytes { len: None } => {
            quote!(#private::write::<u8>(&mut wire, #offset, #value);)
        }
        // Padding is zeros, as the image starts.
        Shape::Padding { .. } => TokenStream::new(),
    }
}

/// Visits `value` (a reference to the field's value) as field `f`.
fn visit_stmt(m: &Message, f: &MessageField, value: &TokenStream) -> TokenStream {
    let private = m.paths.private();
    let fname = &f.name;
    match &f.shape {
        Shape::Scalar(ty) => quote!(#private::visit_field::<#ty>(#value, path, base, #fname, f);),
        Shape::Array { elem, .. } => {
            quote!(#private::visit_array::<#elem>(#value, path, base, #fname, f);)
        }
        Shape::CharBytes { len: Some(_) } => {
            quote!(#private::visit_chars(#value, false, path, base, #fname, f);)
        }
        Shape::CharBytes { len: None } => quote!(
            #private::visit_chars(::core::slice::from_ref(#value), true, path, base, #fname, f);
        ),
        Shape::Padding { .. } => TokenStream::new(),
    }
}

/// The implementations of a checked binding.
pub(crate) fn expand(m: &Message) -> TokenStream {
    let typed = m.paths.typed();
    let private = m.paths.private();
    let message_trait = m.paths.message_trait();
    let wf = quote!(#typed::WireField);
    let ident = &m.ident;
    let name = &m.name;
    let rust_name = ident.to_string();
    let named_after_struct = m.named_after_struct;
    let topic_aliases: Vec<&String> = m.aliases.iter().map(|(a, _)| a).collect();

    let mut consts = Vec::new();
    let mut inits = Vec::new();
    let mut direct_inits = Vec::new();
    let mut writes = Vec::new();
    let mut defs = Vec::new();
    let mut is_wire = Vec::new();
    // Writable unless a field is an `Option`, here or in a nested binding.
    let has_options = m.fields.iter().any(|f| matches!(f.absent, Absent::None));
    let mut writability = if has_options {
        quote!(#typed::HasOptionFields)
    } else {
        quote!(#typed::Writable)
    };
    let mut asserts = Vec::new();
    let mut visits = Vec::new();
    // Offsets and presence slots: constants the compiler computes.
    let mut offset = quote!(0usize);
    let mut slot = quote!(0usize);
    let mut has_slots = false;
    // The index of each field's first payload offset (`from_payload`), and whether
    // every field reads from its offsets.
    let mut source = quote!(0usize);
    let mut direct = Vec::new();
    for (k, f) in m.fields.iter().enumerate() {
        let code = field_code(m, f);
        let fi = &f.ident;
        let fname = &f.name;
        let aliases = &f.aliases;
        let offset_id = format_ident!("__O{k}");
        let offset_k = quote!(#offset_id);
        let size = &code.size;
        consts.push(quote!(const #offset_k: usize = #offset;));
        offset = quote!(#offset_k + #size);
        let own_slot = !matches!(f.absent, Absent::Required);
        let nested = code.nested_slots.clone();
        let slot_k = format_ident!("__S{k}");
        consts.push(quote!(const #slot_k: usize = #slot;));
        let own = usize::from(own_slot);
        slot = quote!(#slot_k + #own + #nested);
        has_slots = true;
        let present = if own_slot {
            quote!(present.sub(#slot_k + 1, #nested))
        } else {
            quote!(present.sub(#slot_k, #nested))
        };
        let source_k = format_ident!("__R{k}");
        let field_sources = &code.sources;
        direct.push(code.direct.clone());
        consts.push(quote!(const #source_k: usize = #source;));
        source = quote!(#source_k + #field_sources);
        let init = |read: TokenStream| match &f.absent {
            Absent::Required => quote!(#fi: #read),
            Absent::None => quote!(#fi: if present.get(#slot_k) {
                ::core::option::Option::Some(#read)
            } else {
                ::core::option::Option::None
            }),
            Absent::Default(expr) => {
                let default = match expr {
                    Some(e) => quote!(#e),
                    None => quote!(::core::default::Default::default()),
                };
                quote!(#fi: if present.get(#slot_k) { #read } else { #default })
            }
        };
        inits.push(init(read_expr(m, f, ReadFrom::Image(&offset_k), &present)));
        let mut direct_read = read_expr(m, f, ReadFrom::Payload(&quote!(#source_k)), &present);
        if !f.converts.is_empty() {
            direct_read = declared_conversions(m, f, &quote!(#source_k), &present, direct_read);
        }
        direct_inits.push(init(direct_read));
        writes.push(match &f.absent {
            Absent::None => {
                let w = write_stmt(m, f, &offset_k, &quote!(value));
                quote!(if let ::core::option::Option::Some(value) = &self.#fi { #w })
            }
            _ => write_stmt(m, f, &offset_k, &quote!(&self.#fi)),
        });
        visits.push(match &f.absent {
            Absent::None => {
                let v = visit_stmt(m, f, &quote!(value));
                quote!(if let ::core::option::Option::Some(value) = &self.#fi { #v })
            }
            _ => visit_stmt(m, f, &quote!(&self.#fi)),
        });
        let (kind, count) = (&code.kind, &code.count);
        let mut def = quote!(#typed::FieldDef::new(#fname, &[#(#aliases),*], #kind, #count));
        if !f.converts.is_empty() {
            let types = f.converts.iter().map(|(b, _)| {
                let v = basic_variant(*b);
                quote!(#private::BasicType::#v)
            });
            def = quote!(#def.converting(&[#(#types),*]));
        }
        defs.push(match &f.absent {
            Absent::Required => def,
            Absent::None => quote!(#def.when_absent(#typed::Absent::None)),
            Absent::Default(_) => quote!(#def.when_absent(#typed::Absent::Default)),
        });
        let wire_ok = match f.absent {
            Absent::None => quote!(false),
            _ => code.is_wire.clone(),
        };
        is_wire.push(quote!(#wire_ok && ::core::mem::offset_of!(Self, #fi) == #offset_k));
        if let (false, Some(w)) = (has_options, &code.writability) {
            writability = quote!(<#writability as #typed::Writability>::And<#w>);
        }
        asserts.extend(code.assert);
    }
    let asserts = (!asserts.is_empty()).then(|| quote!(const _: () = { #(#asserts)* };));
    consts.push(quote!(const __SIZE: usize = #offset;));
    let size = quote!(__SIZE);
    let optional = if has_slots {
        quote!(#slot)
    } else {
        quote!(0usize)
    };
    let is_wire = quote!(
        ::core::mem::size_of::<Self>() == #size
            && ::core::mem::align_of::<Self>() == 1
            #(&& #is_wire)*
    );

    // A derived struct may hold optional fields, here or in a nested binding: its
    // visitor goes field by field.
    let visit_override = {
        let body = if visits.is_empty() {
            quote!(let _ = (path, f);)
        } else {
            quote!(let base = path.len(); #(#visits)*)
        };
        quote! {
            fn visit_fields_at(
                &self,
                path: &mut ::std::string::String,
                f: &mut dyn ::core::ops::FnMut(&str, #private::Value<'_>),
            ) {
                #body
            }
        }
    };
    let view = m.view.map(|span| {
        let message = format!(
            "`{rust_name}` is not its wire image, so it cannot be a view: its fields must be `u8`, `i8`, `CharArray<N>`, `ulog_core::typed::le` types, arrays of these or nested view bindings, laid out in declaration order (add `#[repr(C)]`)"
        );
        quote_spanned! {span=>
            const _: () = ::core::assert!(<#ident as #wf>::IS_WIRE, #message);
            // SAFETY: the assertion above makes it a compile error unless `IS_WIRE`,
            // computed from every field's own `IS_WIRE` and offset, holds.
            #[automatically_derived]
            unsafe impl #typed::WireImage for #ident {}
        }
    });
    let n = defs.len();
    let wire_mut = if writes.iter().all(TokenStream::is_empty) {
        quote!(wire)
    } else {
        quote!(mut wire)
    };
    quote! {
        #[allow(non_snake_case, clippy::all)]
        const _: () = {
            #(#consts)*

            #asserts

            #[automatically_derived]
            impl #wf for #ident {
                type Wire = [u8; #size];
                const KIND: #typed::FieldKind =
                    #typed::FieldKind::Nested(<Self as #message_trait>::schema);
                const IS_WIRE: bool = #is_wire;
                const OPTIONAL: usize = #optional;
                type Writability = #writability;
                const SOURCES: usize = #source;
                const DIRECT: bool = true #(&& #direct)*;
                #[inline]
                fn from_wire(wire: &[u8; #size], present: #typed::Present<'_>) -> Self {
                    let _ = present;
                    Self { #(#inits,)* }
                }
                #[inline]
                fn from_payload(
                    payload: &[u8],
                    sources: &[u32],
                    present: #typed::Present<'_>,
                ) -> Self {
                    let _ = (payload, sources, present);
                    Self { #(#direct_inits,)* }
                }
                #[inline]
                fn to_wire(&self) -> [u8; #size] {
                    let #wire_mut = [0u8; #size];
                    #(#writes)*
                    wire
                }
                fn visit(
                    &self,
                    path: &mut ::std::string::String,
                    f: &mut dyn ::core::ops::FnMut(&str, #private::Value<'_>),
                ) {
                    <Self as #message_trait>::visit_fields_at(self, path, f)
                }
            }

            #[automatically_derived]
            impl #typed::ArrayElement for #ident {}

            #[automatically_derived]
            impl #message_trait for #ident {
                const NAME: &'static str = #name;
                const ALIASES: &'static [&'static str] = &[#(#topic_aliases),*];
                fn schema() -> &'static #typed::Schema {
                    static FIELDS: [#typed::FieldDef; #n] = [#(#defs),*];
                    static SCHEMA: #private::OnceLock<#typed::Schema> = #private::OnceLock::new();
                    SCHEMA.get_or_init(|| {
                        #typed::Schema::build(#name, &FIELDS)
                            .with_rust_name(#rust_name, #named_after_struct)
                    })
                }
                #visit_override
            }

            #view
        };
    }
}

/// Implementations that stand in for a binding with errors, so that code using the
/// type reports no further errors.
pub(crate) fn stub(m: &Message) -> TokenStream {
    let typed = m.paths.typed();
    let message_trait = m.paths.message_trait();
    let ident = &m.ident;
    let name = &m.name;
    quote! {
        const _: () = {
            #[automatically_derived]
            impl #typed::WireField for #ident {
                type Wire = [u8; 0];
                type Writability = #typed::Writable;
                const KIND: #typed::FieldKind =
                    #typed::FieldKind::Nested(<Self as #message_trait>::schema);
                fn from_wire(_: &[u8; 0], _: #typed::Present<'_>) -> Self {
                    ::core::unreachable!()
                }
                fn to_wire(&self) -> [u8; 0] {
                    []
                }
            }
            #[automatically_derived]
            impl #typed::ArrayElement for #ident {}
            #[automatically_derived]
            impl #message_trait for #ident {
                const NAME: &'static str = #name;
                fn schema() -> &'static #typed::Schema {
                    ::core::unreachable!()
                }
            }
        };
    }
}
