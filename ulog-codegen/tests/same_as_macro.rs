//! `bindings_for_log` gives exactly the items `ulog_module!` puts in its module.

use quote::quote;

fn items_text(items: Vec<syn::Item>) -> String {
    prettyplease::unparse(&syn::File {
        shebang: None,
        attrs: Vec::new(),
        items,
    })
}

#[test]
fn codegen_source_equals_the_module_macro_expansion() {
    for views in [false, true] {
        same_as_macro(views);
    }
}

fn same_as_macro(views: bool) {
    let path =
        std::env::temp_dir().join(format!("ulog-codegen-{}-{views}.ulg", std::process::id()));
    std::fs::write(&path, ulog_core::testing::sample_log()).unwrap();
    let lit = path.display().to_string();
    let expanded = if views {
        ulog_codegen::ulog_module(quote!(views; pub mod sample = #lit;))
    } else {
        ulog_codegen::ulog_module(quote!(pub mod sample = #lit;))
    };
    let _ = std::fs::remove_file(&path);

    let file: syn::File = syn::parse2(expanded).expect("expansion parses");
    let module = file
        .items
        .into_iter()
        .find_map(|i| match i {
            syn::Item::Mod(m) => Some(m),
            _ => None,
        })
        .expect("a module");
    // Everything but the `include_bytes!` that makes the macro rebuild on change.
    let from_macro: Vec<syn::Item> = module
        .content
        .expect("inline module")
        .1
        .into_iter()
        .filter(|i| !matches!(i, syn::Item::Const(c) if quote!(#c).to_string().contains("include_bytes")))
        .collect();
    assert!(from_macro.len() > 4);

    let options = ulog_codegen::Options {
        views,
        ..Default::default()
    };
    let generated =
        ulog_codegen::bindings_for_log(&ulog_core::testing::sample_log(), "sample.ulg", &options)
            .unwrap();
    let parsed: syn::File = syn::parse_str(&generated.source).expect("source parses");
    assert_eq!(items_text(parsed.items), items_text(from_macro));
    assert_eq!(generated.source.contains("WireImage"), views);
    assert!(generated.unbound.is_empty());
    let sample = ulog_core::testing::sample_log();
    let log = ulog_core::ULog::parse(&sample).unwrap();
    let mut bound = generated.bound.clone();
    bound.sort();
    let read: Vec<&str> = log.formats().iter().map(|f| f.name.as_str()).collect();
    assert_eq!(bound, read);
    assert!(generated.problems.is_empty());
}

#[test]
fn a_file_that_is_not_a_log_is_an_error() {
    let default = ulog_codegen::Options::default();
    let e = ulog_codegen::bindings_for_log(b"hello", "x", &default).unwrap_err();
    assert!(!e.is_empty());
    let bad_path = ulog_codegen::Options {
        krate: Some("not a path"),
        ..Default::default()
    };
    let e = ulog_codegen::bindings_for_log(&ulog_core::testing::sample_log(), "x", &bad_path)
        .unwrap_err();
    assert!(e.contains("not a path"), "{e}");
}
