//! A pass that keeps the metadata (`ScanOptions::keep_metadata`) gives what the
//! whole-file parse gives of everything but the data: information, parameters and
//! their changes with their times, defaults, logged strings, dropouts, subscriptions,
//! formats, every offset, the findings, flag bits and message count, the last
//! timestamp, the UTC time, the events, and each topic's row count and first and last
//! timestamps, on every corpus log (damaged ones included), read in chunks from the
//! file, and in timestamp order; with `keep_data`, the rows of the topics it names.

use ulog_core::events::EventOptions;
use ulog_core::read::{LogMetadata, ScanOrder};
use ulog_core::{ScanOptions, Source, ULog};
use ulog_tests::{corpus_files, stem};

/// Checks `kept` against `whole`, the parse of the whole log `name`.
fn same(name: &str, kept: &LogMetadata, whole: &ULog<'_>) {
    let log = kept.log().unwrap();
    assert_eq!(log.header(), whole.header(), "{name}");
    assert_eq!(log.flag_bits(), whole.flag_bits(), "{name}");
    assert_eq!(log.findings(), whole.findings(), "{name}");
    assert_eq!(log.is_truncated(), whole.is_truncated(), "{name}");
    assert_eq!(log.appended_sections(), whole.appended_sections(), "{name}");
    assert_eq!(log.message_count(), whole.message_count(), "{name}");
    assert_eq!(log.sync_count(), whole.sync_count(), "{name}");
    assert_eq!(log.unknown_messages(), whole.unknown_messages(), "{name}");
    assert_eq!(log.info(), whole.info(), "{name}");
    assert_eq!(log.multi_info(), whole.multi_info(), "{name}");
    assert_eq!(log.initial_params(), whole.initial_params(), "{name}");
    // What, when, and where in the file.
    assert_eq!(log.param_changes(), whole.param_changes(), "{name}");
    assert_eq!(log.default_params(), whole.default_params(), "{name}");
    assert_eq!(log.logged_messages(), whole.logged_messages(), "{name}");
    assert_eq!(log.dropouts(), whole.dropouts(), "{name}");
    assert_eq!(log.subscriptions(), whole.subscriptions(), "{name}");
    // Each topic's rows, counted as the pass went by.
    let rows = |t: ulog_core::Topic<'_, '_>| {
        let times = t.timestamps();
        (
            t.len() as u64,
            times.first().copied(),
            times.last().copied(),
        )
    };
    let counted: Vec<_> = kept
        .topics()
        .iter()
        .map(|r| (r.rows, r.first_timestamp, r.last_timestamp))
        .collect();
    assert_eq!(
        counted,
        whole.topics().map(rows).collect::<Vec<_>>(),
        "{name}"
    );
    assert_eq!(log.formats(), whole.formats(), "{name}");
    assert_eq!(log.last_timestamp(), whole.last_timestamp(), "{name}");
    assert_eq!(kept.last_timestamp(), whole.last_timestamp(), "{name}");
    assert_eq!(kept.utc(), whole.utc(), "{name}");
    let options = EventOptions::default();
    let events = kept.events(&options);
    let expected = whole.events(&options);
    assert_eq!(events.events, expected.events, "{name}");
    assert_eq!(events.findings.len(), expected.findings.len(), "{name}");
}

#[test]
fn kept_metadata_is_the_parse_of_the_whole_log() {
    let keep = ScanOptions::default().keep_metadata(true);
    let (mut checked, mut with_changes, mut with_utc, mut with_events) = (0, 0, 0, 0);
    let files = corpus_files();
    let mut unreadable = 0;
    for path in &files {
        let path = path.as_path();
        let name = stem(path);
        let bytes = std::fs::read(path).unwrap();
        let Ok(whole) = ULog::parse(&bytes) else {
            assert!(ulog_core::scan(Source::file(path), &keep, |_| {}).is_err());
            unreadable += 1;
            continue;
        };
        let mut rows = 0u64;
        let summary = ulog_core::scan(Source::file(path), &keep, |_| rows += 1).unwrap();
        assert_eq!(rows, summary.data_messages, "{name}");
        assert_eq!(summary.findings, whole.findings(), "{name}");
        same(&name, summary.metadata.as_ref().unwrap(), &whole);
        // The rows of the topics `keep_data` names are kept, every instance, as the
        // whole parse reads them; the others are not.
        let names: Vec<&str> = whole
            .topics()
            .filter(|t| !t.is_empty())
            .map(|t| t.name())
            .take(2)
            .collect();
        let some = keep.clone().keep_data(names.iter().copied());
        let summary = ulog_core::scan(Source::file(path), &some, |_| {}).unwrap();
        let kept = summary.metadata.as_ref().unwrap();
        same(&name, kept, &whole);
        let log = kept.log().unwrap();
        for (t, w) in log.topics().zip(whole.topics()) {
            let payloads = |t: &ulog_core::Topic<'_, '_>| -> Vec<Vec<u8>> {
                t.payloads().map(<[u8]>::to_vec).collect()
            };
            if names.contains(&w.name()) {
                assert_eq!(payloads(&t), payloads(&w), "{name}: {}", w.name());
            } else {
                assert!(t.is_empty(), "{name}: {}", w.name());
            }
        }
        // By timestamp, the metadata comes from the parsed log.
        let by_time = keep.clone().order(ScanOrder::Timestamp);
        let summary = ulog_core::scan(&bytes, &by_time, |_| {}).unwrap();
        same(&name, summary.metadata.as_ref().unwrap(), &whole);
        checked += 1;
        with_changes += usize::from(!whole.param_changes().is_empty());
        with_utc += usize::from(whole.utc().is_some());
        with_events += usize::from(!whole.events(&EventOptions::default()).events.is_empty());
    }
    // Every log that parses was checked, whichever corpus the tests have (the
    // repository's own five logs on a fresh clone, or the full one).
    assert_eq!(checked + unreadable, files.len());
    assert!(checked > 0, "no corpus log parses");
    assert!(with_utc > 0, "no log with a UTC clock");
    // Only the full corpus has logs with parameter changes and PX4 events (the
    // repository's own five have neither).
    if cfg!(full_corpus) {
        assert!(
            checked > 10 && with_events > 0 && with_changes > 0,
            "{checked} {with_events} {with_changes}"
        );
    }
    // Without the option, nothing is kept.
    let sample = ulog_core::testing::sample_log();
    let summary = ulog_core::scan(&sample, &ScanOptions::default(), |_| {}).unwrap();
    assert!(summary.metadata.is_none());
}

/// A pass that leaves topics out (`scan_topics` without `raw_others`) still takes
/// their timestamps for the metadata.
#[test]
fn topics_left_out_still_give_their_times() {
    #[derive(ulog_core::ULogMessage)]
    #[ulog(crate = "ulog_core")]
    struct VehicleStatus {
        timestamp: u64,
    }
    #[derive(ulog_core::ULogTopics)]
    #[ulog(crate = "ulog_core")]
    enum Topics {
        Status(VehicleStatus),
    }
    let keep = ScanOptions::default().keep_metadata(true);
    for path in corpus_files().into_iter().take(8) {
        let bytes = std::fs::read(&path).unwrap();
        let Ok(whole) = ULog::parse(&bytes) else {
            continue;
        };
        let mut latest = 0;
        let summary = ulog_core::scan_topics::<Topics>(&bytes, &keep, |r| {
            if let Ok(Some(Topics::Status(s))) = r.map(|r| r.message) {
                latest = latest.max(s.timestamp);
            }
        })
        .unwrap();
        assert!(latest <= whole.last_timestamp());
        same(&stem(&path), summary.metadata.as_ref().unwrap(), &whole);
    }
}
