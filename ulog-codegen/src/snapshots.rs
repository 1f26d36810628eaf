//! Expansion snapshots: the generated code of typical inputs, formatted, compared to
//! files in `tests/snapshots`. `ULOG_BLESS=1 cargo test -p ulog-derive` rewrites them,
//! so that a change in generated code shows in review.

use std::path::PathBuf;

use proc_macro2::TokenStream;
use quote::quote;

fn check(name: &str, tokens: TokenStream) {
    let file: syn::File = match syn::parse2(tokens.clone()) {
        Ok(f) => f,
        Err(e) => panic!("expansion of {name} does not parse: {e}\n{tokens}"),
    };
    let text = prettyplease::unparse(&file);
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/snapshots")
        .join(format!("{name}.expanded.rs"));
    if std::env::var_os("ULOG_BLESS").is_some() {
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(&path, &text).unwrap();
        return;
    }
    let expected = std::fs::read_to_string(&path)
        .unwrap_or_else(|_| panic!("no snapshot {}: run with ULOG_BLESS=1", path.display()));
    assert!(
        expected == text,
        "expansion of {name} changed; review and re-bless with ULOG_BLESS=1\n--- new ---\n{text}"
    );
}

#[test]
fn derive_with_nesting_padding_and_attributes() {
    let input: syn::DeriveInput = syn::parse_quote! {
        #[ulog(name = "esc_status", crate = "::my_ulog")]
        pub struct Esc {
            timestamp: u64,
            _padding0: [u8; 4],
            #[ulog(name = "esc", alias = "escs")]
            reports: [EscReport; 8],
            label: CharArray<4>,
            #[ulog(char)]
            code: [u8; 2],
        }
    };
    check("derive_message", crate::structs::derive_message(&input));
}

#[test]
fn derive_with_optional_fields_and_a_view() {
    let optional: syn::DeriveInput = syn::parse_quote! {
        struct GpsFix {
            timestamp: u64,
            #[ulog(alias = "lat")]
            latitude: Option<i32>,
            latitude_deg: Option<f64>,
            #[ulog(default)]
            satellites_used: u8,
            #[ulog(default = 99.0)]
            eph: f32,
            nested: Option<[Inner; 2]>,
        }
    };
    check("derive_optional", crate::structs::derive_message(&optional));
    let view: syn::DeriveInput = syn::parse_quote! {
        #[ulog(name = "vehicle_attitude", view)]
        #[repr(C)]
        struct Attitude { timestamp: le::U64, q: [le::F32; 4], reset: u8 }
    };
    check("derive_view", crate::structs::derive_message(&view));
}

#[test]
fn derive_topics() {
    let input: syn::DeriveInput = syn::parse_quote! {
        enum Topics { Attitude(VehicleAttitude), Esc(EscStatus) }
    };
    check("derive_topics", crate::topics::derive(&input));
}

#[test]
fn structs_from_format_strings() {
    let tokens = quote! {
        "vehicle_attitude:uint64_t timestamp;float[4] q;uint8_t type;char[3] name;uint8_t[4] _padding0;",
        "pair:vehicle_attitude[2] both;"
    };
    check("ulog_structs", crate::structs::from_format_strings(tokens));
}

#[test]
fn errors_come_all_at_once_with_stand_ins() {
    let input: syn::DeriveInput = syn::parse_quote! {
        #[ulog(name = "x", name = "y")]
        struct Bad { a: usize, _padding0: u16, #[ulog(name = "b")] c: u8, b: u8 }
    };
    let text = crate::structs::derive_message(&input).to_string();
    assert_eq!(text.matches("compile_error").count(), 4, "{text}");
    assert!(
        text.contains("impl :: ulog_core :: ULogMessage for Bad"),
        "{text}"
    );
}
