//! Typed decoding of the real logs, shard 1 of 4 (with `typed_corpus_2`, `typed_corpus_3`, `typed_corpus_4`): for each
//! corpus log dealt to this shard by `build.rs`, the bindings `ulog_module!`
//! generates from it at compile time decode every row of every topic to pyulog's
//! values (see `typed_corpus_common`). The logs are split over four test crates so
//! that they compile in parallel.

mod typed_corpus_common;

#[allow(dead_code, missing_docs)]
mod bindings {
    use crate::typed_corpus_common::Checker;
    include!(concat!(env!("OUT_DIR"), "/typed_corpus_1.rs"));
}

#[test]
fn generated_bindings_decode_every_row_like_pyulog() {
    typed_corpus_common::check_logs(bindings::STEMS, bindings::visit_log);
}

/// The logs were dealt into the shards from the corpus as it was at build time: all
/// of them, each once.
#[test]
fn every_corpus_log_has_generated_bindings() {
    let files: Vec<String> = ulog_tests::corpus_files()
        .iter()
        .map(|p| ulog_tests::stem(p))
        .collect();
    assert_eq!(bindings::ALL_STEMS, files, "rebuild: the corpus changed");
}
