//! A pass that keeps the metadata (`ScanOptions::keep_metadata`) gives what the
//! whole-file parse gives of everything but the data: information, parameters and
//! their changes with their times, defaults, logged strings, dropouts, subscriptions,
//! formats, the last timestamp, the UTC time and the events, on every corpus log
//! (damaged ones included), read in chunks from the file, and in timestamp order.

use ulog_core::events::EventOptions;
use ulog_core::read::{LogMetadata, ScanOrder};
use ulog_core::{ScanOptions, Source, ULog};
use ulog_tests::{corpus_files, stem};

/// Checks `kept` against `whole`, the parse of the whole log `name`.
fn same(name: &str, kept: &LogMetadata, whole: &ULog<'_>) {
    let log = kept.log().unwrap();
    assert_eq!(log.header(), whole.header(), "{name}");
    assert_eq!(
        log.flag_bits().map(|b| b.compat_flags),
        whole.flag_bits().map(|b| b.compat_flags),
        "{name}"
    );
    assert_eq!(log.info(), whole.info(), "{name}");
    assert_eq!(log.multi_info(), whole.multi_info(), "{name}");
    assert_eq!(log.initial_params(), whole.initial_params(), "{name}");
    // Offsets are the kept log's own: what and when.
    let changes = |l: &ULog<'_>| -> Vec<_> {
        l.param_changes()
            .iter()
            .map(|c| (c.timestamp, format!("{:?}", c.kv)))
            .collect()
    };
    assert_eq!(changes(&log), changes(whole), "{name}");
    let defaults = |l: &ULog<'_>| -> Vec<_> {
        l.default_params()
            .iter()
            .map(|d| (d.default_types, format!("{:?}", d.kv)))
            .collect()
    };
    assert_eq!(defaults(&log), defaults(whole), "{name}");
    let logged = |l: &ULog<'_>| -> Vec<_> {
        l.logged_messages()
            .iter()
            .map(|m| (m.timestamp, m.raw_level, m.tag, m.text.to_string()))
            .collect()
    };
    assert_eq!(logged(&log), logged(whole), "{name}");
    let dropouts = |l: &ULog<'_>| -> Vec<_> {
        l.dropouts()
            .iter()
            .map(|d| (d.timestamp, d.duration_ms))
            .collect()
    };
    assert_eq!(dropouts(&log), dropouts(whole), "{name}");
    let subs = |l: &ULog<'_>| -> Vec<_> {
        l.subscriptions()
            .iter()
            .map(|s| (s.name().to_owned(), s.multi_id(), s.msg_id()))
            .collect()
    };
    assert_eq!(subs(&log), subs(whole), "{name}");
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
    for path in corpus_files() {
        let name = stem(&path);
        let bytes = std::fs::read(&path).unwrap();
        let Ok(whole) = ULog::parse(&bytes) else {
            assert!(ulog_core::scan(Source::file(&path), &keep, |_| {}).is_err());
            continue;
        };
        let mut rows = 0u64;
        let summary = ulog_core::scan(Source::file(&path), &keep, |_| rows += 1).unwrap();
        assert_eq!(rows, summary.data_messages, "{name}");
        assert_eq!(summary.findings, whole.findings(), "{name}");
        same(&name, summary.metadata.as_ref().unwrap(), &whole);
        // By timestamp, the metadata comes from the parsed log.
        let by_time = keep.clone().order(ScanOrder::Timestamp);
        let summary = ulog_core::scan(&bytes, &by_time, |_| {}).unwrap();
        same(&name, summary.metadata.as_ref().unwrap(), &whole);
        checked += 1;
        with_changes += usize::from(!whole.param_changes().is_empty());
        with_utc += usize::from(whole.utc().is_some());
        with_events += usize::from(!whole.events(&EventOptions::default()).events.is_empty());
    }
    // The corpus has logs of every kind checked.
    assert!(checked > 10, "{checked}");
    assert!(with_changes > 0 && with_utc > 0 && with_events > 0);
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
        let summary = ulog_core::scan_topics::<Topics, _, _>(&bytes, &keep, |r| {
            if let Ok(Some(Topics::Status(s))) = r.map(|r| r.message) {
                latest = latest.max(s.timestamp);
            }
        })
        .unwrap();
        assert!(latest <= whole.last_timestamp());
        same(&stem(&path), summary.metadata.as_ref().unwrap(), &whole);
    }
}
