//! Probes the corpus of real logs and pyulog for the tests (`probe.rs`: the one rule
//! of `ulog_tests::corpus_dir` and of `cfg(full_corpus)` and `cfg(pyulog)`), then
//! writes the `ulog_module!` invocations of the typed corpus tests: one module per
//! log, the logs dealt round-robin into shards so that the test crates
//! (`tests/typed_corpus_N.rs`) compile in parallel.

use std::fmt::Write as _;
use std::path::Path;

/// The number of `typed_corpus_N.rs` test crates the logs are dealt into.
const SHARDS: usize = 4;
/// The full shared corpus, relative to this package.
const SHARED: &str = "../../shared/corpus";
/// The repository's own logs, relative to this package.
const OWN: &str = "corpus";

include!("probe.rs");

fn main() {
    let out = std::env::var("OUT_DIR").expect("OUT_DIR");
    let corpus = probe(SHARED, OWN);
    let dir = corpus.join("files");
    let mut stems: Vec<String> = match std::fs::read_dir(&dir) {
        Ok(entries) => entries
            .filter_map(Result::ok)
            .map(|e| e.path())
            .filter(|p| p.extension().is_some_and(|e| e == "ulg"))
            .filter_map(|p| p.file_stem().map(|s| s.to_string_lossy().into_owned()))
            .collect(),
        Err(_) => Vec::new(),
    };
    stems.sort();
    for shard in 0..SHARDS {
        let mut code = String::new();
        let mut table = String::new();
        for (i, stem) in stems
            .iter()
            .enumerate()
            .filter(|(i, _)| i % SHARDS == shard)
        {
            writeln!(
                code,
                "ulog_core::ulog_module!(pub mod log{i} = {:?});",
                dir.join(format!("{stem}.ulg"))
            )
            .unwrap();
            writeln!(
                table,
                "        {stem:?} => log{i}::visit_bindings(checker),"
            )
            .unwrap();
        }
        let shard_stems: Vec<&String> = stems.iter().skip(shard).step_by(SHARDS).collect();
        writeln!(
            code,
            "/// The file stems of the logs of this shard.\n\
             pub static STEMS: &[&str] = &{shard_stems:?};\n\
             /// Every log of the corpus when this was built.\n\
             pub static ALL_STEMS: &[&str] = &{stems:?};\n\
             /// Visits the bindings generated from log `stem` of this shard.\n\
             pub fn visit_log(stem: &str, checker: &mut Checker<'_, '_>) {{\n\
             \x20   match stem {{\n{table}        other => panic!(\"{{other}} is not in this shard\"),\n    }}\n}}"
        )
        .unwrap();
        let file = Path::new(&out).join(format!("typed_corpus_{}.rs", shard + 1));
        std::fs::write(file, code).expect("write generated bindings");
    }
    // The same logs as view bindings (`ulog_module!(views; …)`), for
    // `typed_corpus_views.rs`: one crate, view modules compile quickly.
    let mut code = String::new();
    let mut table = String::new();
    for (i, stem) in stems.iter().enumerate() {
        writeln!(
            code,
            "ulog_core::ulog_module!(views; pub mod log{i} = {:?});",
            dir.join(format!("{stem}.ulg"))
        )
        .unwrap();
        writeln!(table, "        {stem:?} => log{i}::visit_views(checker),").unwrap();
    }
    writeln!(
        code,
        "/// Every log of the corpus when this was built.\n\
         pub static ALL_STEMS: &[&str] = &{stems:?};\n\
         /// Visits the view bindings generated from log `stem`.\n\
         pub fn visit_log(stem: &str, checker: &mut Checker<'_, '_>) {{\n\
         \x20   match stem {{\n{table}        other => panic!(\"{{other}} is not in the corpus\"),\n    }}\n}}"
    )
    .unwrap();
    std::fs::write(Path::new(&out).join("typed_corpus_views.rs"), code)
        .expect("write generated view bindings");
}
