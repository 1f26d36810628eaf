//! Names: Rust identifiers from ULog names and back.

use proc_macro2::{Ident, Span};

/// `VehicleAttitude` → `vehicle_attitude`, `GPSPosition` → `gps_position`.
pub(crate) fn snake_case(ident: &str) -> String {
    let chars: Vec<char> = ident.chars().collect();
    let mut out = String::with_capacity(ident.len() + 4);
    for (i, &c) in chars.iter().enumerate() {
        if c.is_ascii_uppercase() {
            let prev = i.checked_sub(1).map(|p| chars[p]);
            let next = chars.get(i + 1).copied();
            let boundary = match prev {
                Some(p) if p.is_ascii_lowercase() || p.is_ascii_digit() => true,
                Some(p) if p.is_ascii_uppercase() => next.is_some_and(|n| n.is_ascii_lowercase()),
                _ => false,
            };
            if boundary && !out.ends_with('_') {
                out.push('_');
            }
            out.push(c.to_ascii_lowercase());
        } else {
            out.push(c);
        }
    }
    out
}

/// `vehicle_attitude` → `VehicleAttitude`; `-`, `/` and `_` separate words; a name
/// starting with a digit gets a `T` in front.
pub(crate) fn camel_case(name: &str) -> String {
    let mut out = String::with_capacity(name.len());
    for word in name.split(['_', '-', '/']).filter(|w| !w.is_empty()) {
        let mut chars = word.chars();
        if let Some(first) = chars.next() {
            out.push(first.to_ascii_uppercase());
            out.extend(chars);
        }
    }
    if out.is_empty() || out.starts_with(|c: char| c.is_ascii_digit()) {
        out.insert(0, 'T');
    }
    out
}

/// A field identifier for a ULog field name: the name itself, raw (`r#type`) for
/// keywords, with a prefix when it cannot be an identifier at all.
pub(crate) fn field_ident(name: &str, span: Span) -> Ident {
    // The rule the bindings' `Debug` prints by too.
    let rust = ulog_format::rust_field_name(name);
    if rust != name {
        return Ident::new(&rust, span);
    }
    match syn::parse_str::<Ident>(name) {
        Ok(_) => Ident::new(name, span),
        Err(_) => Ident::new_raw(name, span),
    }
}

/// The ULog name of a field identifier (`r#type` → `type`).
pub(crate) fn unraw(ident: &Ident) -> String {
    let s = ident.to_string();
    s.strip_prefix("r#").map(str::to_owned).unwrap_or(s)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cases() {
        assert_eq!(snake_case("VehicleAttitude"), "vehicle_attitude");
        assert_eq!(snake_case("GPSPosition"), "gps_position");
        assert_eq!(snake_case("Esc2Status"), "esc2_status");
        assert_eq!(snake_case("cpuload"), "cpuload");
        assert_eq!(camel_case("vehicle_attitude"), "VehicleAttitude");
        assert_eq!(camel_case("a/b-c"), "ABC");
        assert_eq!(camel_case("3d"), "T3d");
        assert_eq!(field_ident("type", Span::call_site()).to_string(), "r#type");
        assert_eq!(field_ident("self", Span::call_site()).to_string(), "self_");
        assert_eq!(field_ident("0x", Span::call_site()).to_string(), "f_0x");
        assert_eq!(unraw(&field_ident("type", Span::call_site())), "type");
    }
}
