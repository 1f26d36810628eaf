//! Every topic's columns, loaded four ways from arbitrary bytes, must agree: through
//! the index (`ULog::parse`, then `load_all_columns` on one thread and on several), in
//! one pass (`load_columns`), and from a file on several threads with the topics
//! shared by a sample the input chose (`testing::load_file_columns_in`). The loads
//! that read the file themselves (in one pass, and from the file) must count the
//! parse's messages and report its findings; a log the parse refuses, they refuse
//! with the same error.
#![no_main]

use libfuzzer_sys::fuzz_target;
use ulog_core::{LoadedColumns, ULog};

/// Columns compared as text: NaN values are equal there.
fn text<T: std::fmt::Debug>(x: &T) -> String {
    format!("{x:?}")
}

/// The file load of `data` on `threads` threads, shared by a `sample` of its bytes.
fn load_file(data: &[u8], threads: usize, sample: u64) -> ulog_core::Result<LoadedColumns> {
    let path = std::env::temp_dir().join(format!("ulog-fuzz-columns-{}.ulg", std::process::id()));
    std::fs::write(&path, data).unwrap();
    let loaded = ulog_core::testing::load_file_columns_in(&path, threads, sample);
    std::fs::remove_file(&path).unwrap();
    loaded
}

fuzz_target!(|input: (u8, u16, &[u8])| {
    let (threads, sample, data) = input;
    let threads = 2 + usize::from(threads % 3);
    let one = ulog_core::load_columns(data);
    let shared = load_file(data, threads, u64::from(sample));
    let log = match ULog::parse(data) {
        Ok(log) => log,
        Err(e) => {
            assert_eq!(one.unwrap_err(), e);
            assert_eq!(shared.unwrap_err(), e);
            return;
        }
    };
    let one = one.expect("the parse took the log");
    let indexed = log.load_all_columns(1);
    assert_eq!(text(&log.load_all_columns(threads)), text(&indexed));
    assert_eq!(one.topics.len(), indexed.len());
    for ((t, loaded), expected) in log.topics().zip(&one.topics).zip(&indexed) {
        assert_eq!(
            (loaded.topic.name.as_str(), loaded.topic.multi_id, loaded.topic.msg_id),
            (t.name(), t.multi_id(), t.msg_id())
        );
        assert_eq!(text(&loaded.columns), text(expected), "{}", t.name());
    }
    assert_eq!(one.summary.messages, log.message_count());
    assert_eq!(one.summary.findings, log.findings());

    let shared = shared.expect("the parse took the log");
    assert_eq!(shared.summary, one.summary);
    assert_eq!(shared.topics.len(), one.topics.len());
    for (a, b) in shared.topics.iter().zip(&one.topics) {
        assert_eq!(a.topic, b.topic);
        assert_eq!(text(&a.columns), text(&b.columns), "{}", a.topic.name);
    }
});
