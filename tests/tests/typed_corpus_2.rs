//! Typed decoding of the real logs, shard 2 of 4 (with `typed_corpus_1`, `typed_corpus_3`, `typed_corpus_4`): for each
//! corpus log dealt to this shard by `build.rs`, the bindings `ulog_module!`
//! generates from it at compile time decode every row of every topic to pyulog's
//! values (see `typed_corpus_common`). The logs are split over four test crates so
//! that they compile in parallel.

mod typed_corpus_common;

#[allow(dead_code, missing_docs)]
mod bindings {
    use crate::typed_corpus_common::Checker;
    include!(concat!(env!("OUT_DIR"), "/typed_corpus_2.rs"));
}

#[test]
fn generated_bindings_decode_every_row_like_pyulog() {
    typed_corpus_common::check_logs(bindings::STEMS, bindings::visit_log);
}
