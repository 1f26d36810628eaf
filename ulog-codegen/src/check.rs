//! Checks across the fields of a binding, with the grammar of `ulog-format`: valid
//! message and field names, no duplicate names or aliases.

use std::collections::HashMap;

use proc_macro2::Span;
use ulog_format::{Format, FormatErrorKind};

use crate::errors::Errors;
use crate::ir::{Absent, Message};

fn describe(kind: &FormatErrorKind, what: &str) -> String {
    match kind {
        FormatErrorKind::InvalidNameChar(c) => {
            format!("character {c:?} is not allowed in a ULog {what} (allowed: a-z A-Z 0-9 _ - /)")
        }
        FormatErrorKind::InvalidFieldNameChar(c) => {
            format!("character {c:?} is not allowed in a ULog {what} (allowed: a-z A-Z 0-9 _)")
        }
        FormatErrorKind::EmptyName | FormatErrorKind::MissingFieldName => {
            format!("a ULog {what} cannot be empty")
        }
        FormatErrorKind::NameIsBasicType => format!("a ULog {what} cannot be a basic type"),
        FormatErrorKind::MissingColon => format!("a ULog {what} cannot contain `:`"),
        other => format!("invalid ULog {what} ({other:?})"),
    }
}

/// Checks a message name with the grammar.
pub(crate) fn message_name(name: &str, span: Span, errors: &mut Errors) {
    if name.contains(':') || name.contains(';') {
        errors.at(
            span,
            describe(&FormatErrorKind::MissingColon, "message name"),
        );
        return;
    }
    if let Err(all) = Format::parse_all(&format!("{name}:uint8_t x;")) {
        for e in all {
            errors.at(span, describe(&e.kind, "message name"));
        }
    }
}

/// Checks one field name with the grammar.
pub(crate) fn field_name(name: &str, span: Span, what: &str, errors: &mut Errors) {
    if name.is_empty() || name.contains([';', ' ']) {
        errors.at(span, format_args!("`{name}` is not a valid ULog {what}"));
        return;
    }
    if let Err(all) = Format::parse_all(&format!("m:uint8_t {name};")) {
        for e in all {
            errors.at(span, describe(&e.kind, what));
        }
    }
}

/// Every check of a lowered derive input.
pub(crate) fn check(message: &Message, name_span: Span, errors: &mut Errors) {
    message_name(&message.name, name_span, errors);
    for (i, (alias, span)) in message.aliases.iter().enumerate() {
        message_name(alias, *span, errors);
        let earlier = message.aliases[..i].iter().map(|(a, _)| a);
        if *alias == message.name || earlier.into_iter().any(|a| a == alias) {
            errors.at(
                *span,
                format_args!("the topic name `{alias}` is given twice"),
            );
        }
    }
    let mut seen: HashMap<&str, ()> = HashMap::new();
    for f in &message.fields {
        field_name(&f.name, f.span, "field name", errors);
        for a in &f.aliases {
            field_name(a, f.span, "alias", errors);
        }
        for n in core::iter::once(&f.name).chain(&f.aliases) {
            if seen.insert(n, ()).is_some() {
                errors.at(f.span, format_args!("duplicate ULog field name `{n}`"));
            }
        }
        if ulog_format::is_padding_name(&f.name) && !f.aliases.is_empty() {
            errors.at(f.span, "a padding field cannot have aliases");
        }
        if let (Some(view), Absent::None) = (message.view, &f.absent) {
            let _ = view;
            errors.at(
                f.span,
                "a binding borrowed from payloads (`view`) cannot have `Option` fields: an absent field has no bytes to borrow",
            );
        }
    }
}
