//! Every topic's columns, loaded four ways from arbitrary bytes, must agree: through
//! the index (`ULog::parse`, then `load_columns` of the parsed log on one thread and on
//! several), in one pass (`load_columns` of a `Source::reader`), and from a file on
//! several threads with the topics shared by a sample the input chose
//! (`testing::load_columns_in` of a `Source::file`). The loads that read the file
//! themselves (in one pass, and from the file) must count the parse's messages and
//! report its findings; a log the parse refuses, they refuse with the same error (the
//! file load's said of the file).
#![no_main]

use libfuzzer_sys::fuzz_target;
use ulog_core::columns::LoadedColumns;
use ulog_core::{ReadError, ScanOptions, Source, ULog};

/// Columns compared as text: NaN values are equal there.
fn text<T: std::fmt::Debug>(x: &T) -> String {
    format!("{x:?}")
}

/// The file load of `data` on `threads` threads, shared by a `sample` of its bytes, and
/// the path the file had.
fn load_file(
    data: &[u8],
    threads: usize,
    sample: u64,
) -> (Result<LoadedColumns, ReadError>, std::path::PathBuf) {
    let path = std::env::temp_dir().join(format!("ulog-fuzz-columns-{}.ulg", std::process::id()));
    std::fs::write(&path, data).unwrap();
    let loaded = ulog_core::testing::load_columns_in(Source::file(&path), threads, sample);
    std::fs::remove_file(&path).unwrap();
    (loaded, path)
}

fuzz_target!(|input: (u8, u16, &[u8])| {
    let (threads, sample, data) = input;
    let threads = 2 + usize::from(threads % 3);
    let one = ulog_core::load_columns(Source::reader(data), &ScanOptions::default());
    let (shared, path) = load_file(data, threads, u64::from(sample));
    let log = match ULog::parse(data) {
        Ok(log) => log,
        Err(e) => {
            assert_eq!(one.unwrap_err(), e);
            let shared = shared.unwrap_err();
            assert_eq!((shared.kind(), shared.position()), (e.kind(), e.position()));
            assert_eq!(shared.path(), Some(path.as_path()));
            return;
        }
    };
    let one = one.expect("the parse took the log");
    let indexed = ulog_core::load_columns(&log, &ScanOptions::default().threads(1))
        .expect("a parsed log loads");
    let several = ulog_core::load_columns(&log, &ScanOptions::default().threads(threads))
        .expect("a parsed log loads");
    assert_eq!(text(&several), text(&indexed));
    assert_eq!(one.topics.len(), indexed.topics.len());
    for ((t, loaded), expected) in log.topics().zip(&one.topics).zip(&indexed.topics) {
        assert_eq!(
            (
                loaded.topic.name(),
                loaded.topic.multi_id(),
                loaded.topic.msg_id()
            ),
            (t.name(), t.multi_id(), t.subscription().msg_id())
        );
        assert_eq!(
            text(&loaded.columns),
            text(&expected.columns),
            "{}",
            t.name()
        );
    }
    assert_eq!(one.summary.messages, log.message_count());
    assert_eq!(one.summary.findings, log.findings());

    let shared = shared.expect("the parse took the log");
    assert_eq!(shared.summary, one.summary);
    assert_eq!(shared.topics.len(), one.topics.len());
    for (a, b) in shared.topics.iter().zip(&one.topics) {
        assert_eq!(a.topic, b.topic);
        assert_eq!(text(&a.columns), text(&b.columns), "{}", a.topic.name());
    }
});
