//! Picks the schema the benchmark's bindings are generated from: the shared corpus's
//! `sample.ulg` when it is there (`cfg(has_corpus)`), else the examples' committed
//! reference log (the schema of `ulog_core::testing::sample_log`).

fn main() {
    println!("cargo::rustc-check-cfg=cfg(has_corpus)");
    println!("cargo::rerun-if-changed=build.rs");
    println!("cargo::rerun-if-changed=../../shared/corpus/files/sample.ulg");
    let manifest = std::env::var("CARGO_MANIFEST_DIR").expect("CARGO_MANIFEST_DIR");
    let sample = std::path::Path::new(&manifest).join("../../shared/corpus/files/sample.ulg");
    if sample.is_file() {
        println!("cargo::rustc-cfg=has_corpus");
    }
}
