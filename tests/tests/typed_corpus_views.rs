//! Zero-copy views on real firmware: view bindings generated from each corpus log
//! (`ulog_module!(views; …)`) borrow the rows of every topic in place, although PX4
//! never writes the trailing padding, and every value read through them equals
//! pyulog's (see `typed_corpus_common`). The only rows that cannot be borrowed are
//! those of a topic whose format is also nested in another format: its struct keeps
//! the trailing padding (the enclosing struct needs it), which the topic's own
//! payloads leave out; they are decoded by copy and checked the same way.

mod typed_corpus_common;

#[allow(dead_code, missing_docs)]
mod bindings {
    use crate::typed_corpus_common::Checker;
    include!(concat!(env!("OUT_DIR"), "/typed_corpus_views.rs"));
}

#[test]
fn view_bindings_borrow_every_row_of_real_logs() {
    use std::collections::BTreeSet;
    use ulog_core::LogFile;

    let totals = typed_corpus_common::check_logs_with(bindings::ALL_STEMS, |stem, c| {
        bindings::visit_log(stem, c);
        true
    });
    let (mut rows, mut borrowed) = (0, 0);
    for t in &totals {
        let file = ulog_tests::corpus_dir().join(format!("files/{}.ulg", t.stem));
        let file = LogFile::open(&file).unwrap();
        let log = file.parse().unwrap();
        // Formats that appear as a nested type in another format.
        let nested: BTreeSet<&str> = log
            .formats()
            .iter()
            .flat_map(|f| f.fields.iter())
            .filter_map(|f| match &f.ty {
                ulog_core::format::TypeName::Nested(n) => Some(n.as_str()),
                _ => None,
            })
            .collect();
        let mut copied = 0;
        for (topic, n, why) in &t.not_borrowed {
            assert!(
                nested.contains(topic.as_str()),
                "{}: `{topic}`: {n} rows not borrowed: {why}",
                t.stem
            );
            assert!(
                why.contains("trailing padding"),
                "{}: `{topic}`: {why}",
                t.stem
            );
            copied += n;
        }
        assert_eq!(t.borrowed + copied, t.rows, "{}", t.stem);
        eprintln!(
            "{}: {} of {} rows borrowed ({} of a topic nested in another, copied)",
            t.stem, t.borrowed, t.rows, copied
        );
        rows += t.rows;
        borrowed += t.borrowed;
    }
    assert_eq!(totals.len(), bindings::ALL_STEMS.len());
    assert!(borrowed > 0);
    eprintln!("views: {borrowed} of {rows} rows borrowed in place");
}
