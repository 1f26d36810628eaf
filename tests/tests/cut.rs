//! Cuts of every corpus log (`ulog_core::Edit`, what `ulog cut` runs): for several
//! windows of each log, the cut is a valid log; every kept row equals the original's
//! byte for byte and none outside the window is kept; parameters are the original's at
//! the window's start, changes, logged strings and dropouts those inside it; a cut of a
//! cut is the direct cut; a cut of everything is `copy_log`'s output. pyulog reads
//! every cut and agrees with our reader of it.

use std::collections::BTreeMap;

use ulog_core::read::FindingKind;
use ulog_core::{copy_log, Edit, ULog};
use ulog_tests::{corpus_files, stem};

/// The windows cut from a log: all of it, the middle third, from the middle on, the
/// first quarter.
fn windows(log: &ULog<'_>) -> Vec<(Option<u64>, Option<u64>)> {
    let s = log.start_timestamp();
    let span = log.last_timestamp().saturating_sub(s);
    vec![
        (None, None),
        (Some(s + span / 3), Some(s + 2 * span / 3)),
        (Some(s + span / 2), None),
        (None, Some(s + span / 4)),
    ]
}

fn cut(bytes: &[u8], window: (Option<u64>, Option<u64>)) -> Vec<u8> {
    let mut out = Vec::new();
    Edit::new()
        .window(window.0, window.1)
        .write(&ULog::parse(bytes).unwrap(), &mut out)
        .expect("cut");
    out
}

fn inside(window: (Option<u64>, Option<u64>), t: u64) -> bool {
    window.0.is_none_or(|s| s <= t) && window.1.is_none_or(|e| t < e)
}

/// Parameters as name → value text.
fn params(kvs: &[ulog_core::read::KeyValue<'_>]) -> BTreeMap<String, String> {
    kvs.iter()
        .map(|kv| (kv.name().into_owned(), kv.value().to_string()))
        .collect()
}

/// Checks the cut `out` of `log` for `window`; returns the number of rows kept.
fn check(what: &str, log: &ULog<'_>, out: &[u8], window: (Option<u64>, Option<u64>)) -> usize {
    let cut = ULog::parse(out).unwrap_or_else(|e| panic!("{what}: the cut does not parse: {e}"));
    for f in cut.findings() {
        assert!(
            !matches!(
                f.kind,
                FindingKind::Truncated
                    | FindingKind::Corrupt(_)
                    | FindingKind::UnknownMsgId(_)
                    | FindingKind::Malformed { .. }
                    | FindingKind::PartialBeforeAppended
                    | FindingKind::AppendedData
            ),
            "{what}: the cut has {f}"
        );
    }
    // Rows: each topic instance's, in order (two subscriptions of one name and
    // instance matched in order).
    let mut rows = 0;
    let mut theirs: BTreeMap<(String, u8), Vec<_>> = BTreeMap::new();
    for t in cut.topics() {
        theirs
            .entry((t.name().to_owned(), t.multi_id()))
            .or_default()
            .push(t);
    }
    let mut ours: BTreeMap<(String, u8), Vec<_>> = BTreeMap::new();
    for t in log.topics() {
        ours.entry((t.name().to_owned(), t.multi_id()))
            .or_default()
            .push(t);
    }
    for (key, originals) in &ours {
        let cuts = theirs.get(key).map(Vec::as_slice).unwrap_or(&[]);
        assert_eq!(cuts.len(), originals.len(), "{what}: {key:?} subscriptions");
        for (original, c) in originals.iter().zip(cuts) {
            if original.timestamp_field().is_none() {
                // By the log's time, which the public API does not give per row.
                assert!(c.len() <= original.len());
                continue;
            }
            let times = original.timestamps();
            let expected: Vec<&[u8]> = original
                .payloads()
                .zip(&times)
                .filter(|(_, &t)| inside(window, t))
                .map(|(p, _)| p)
                .collect();
            let got: Vec<&[u8]> = c.payloads().collect();
            assert!(
                got == expected,
                "{what}: {key:?}: {} rows against {} expected",
                got.len(),
                expected.len()
            );
            rows += got.len();
        }
    }
    // Parameters at the start, changes inside.
    let start = window.0.unwrap_or(0);
    let mut initial = params(log.initial_params());
    for c in log.param_changes().iter().filter(|c| c.timestamp < start) {
        initial.insert(c.kv.name().into_owned(), c.kv.value().to_string());
    }
    assert_eq!(params(cut.initial_params()), initial, "{what}: parameters");
    let changes = |l: &ULog<'_>, keep: &dyn Fn(u64) -> bool| -> Vec<(u64, String, String)> {
        l.param_changes()
            .iter()
            .filter(|c| keep(c.timestamp))
            .map(|c| {
                (
                    c.timestamp,
                    c.kv.name().into_owned(),
                    c.kv.value().to_string(),
                )
            })
            .collect()
    };
    assert_eq!(
        changes(&cut, &|_| true),
        changes(log, &|t| inside(window, t)),
        "{what}: parameter changes"
    );
    let logged = |l: &ULog<'_>, keep: &dyn Fn(u64) -> bool| -> Vec<(u64, u8, Vec<u8>)> {
        l.logged_messages()
            .iter()
            .filter(|m| keep(m.timestamp))
            .map(|m| (m.timestamp, m.raw_level, m.text.as_bytes().to_vec()))
            .collect()
    };
    assert_eq!(
        logged(&cut, &|_| true),
        logged(log, &|t| inside(window, t)),
        "{what}: logged strings"
    );
    let dropouts = |l: &ULog<'_>, keep: &dyn Fn(u64) -> bool| -> Vec<(u64, u16)> {
        l.dropouts()
            .iter()
            .filter(|d| keep(d.timestamp))
            .map(|d| (d.timestamp, d.duration_ms))
            .collect()
    };
    assert_eq!(
        dropouts(&cut, &|_| true),
        dropouts(log, &|t| inside(window, t)),
        "{what}: dropouts"
    );
    assert_eq!(cut.info().len(), log.info().len(), "{what}: information");
    rows
}

#[test]
fn cuts_of_every_corpus_log_keep_the_window_and_nothing_else() {
    let mut total = 0;
    for path in corpus_files() {
        let bytes = std::fs::read(&path).unwrap();
        let log = ULog::parse(&bytes).unwrap();
        let name = stem(&path);
        for window in windows(&log) {
            let what = format!("{name} {window:?}");
            let out = cut(&bytes, window);
            total += check(&what, &log, &out, window);
        }
    }
    // The repository's own five logs are small.
    let least = if ulog_tests::FULL_CORPUS {
        100_000
    } else {
        1_000
    };
    assert!(total > least, "{total} rows kept in all");
}

#[test]
fn a_cut_of_a_cut_is_the_direct_cut_and_a_cut_of_everything_is_a_copy() {
    let mut copies = 0;
    for path in corpus_files() {
        let bytes = std::fs::read(&path).unwrap();
        let log = ULog::parse(&bytes).unwrap();
        let name = stem(&path);
        let w = windows(&log);
        let (outer, inner) = (w[1], w[1]);
        let (a, b) = (outer.0.unwrap(), outer.1.unwrap());
        let narrower = (Some(a + (b - a) / 4), Some(b - (b - a) / 4));
        let once = cut(&bytes, narrower);
        let twice = cut(&cut(&bytes, inner), narrower);
        assert!(
            once == twice,
            "{name}: a cut of a cut differs from the direct cut"
        );

        let mut copy = Vec::new();
        copy_log(&bytes, &mut copy).unwrap();
        let whole = cut(&bytes, (None, None));
        if log.findings().is_empty() && log.appended_sections().is_empty() {
            assert!(whole == copy, "{name}: a cut of everything is not the copy");
            copies += 1;
        }
    }
    // The logs without damage or appended data (the others lose what the reader
    // steps over, and their appended offsets).
    assert!(copies >= 3, "{copies} logs compared with their copy");
}

#[test]
fn a_topic_filter_keeps_those_topics_and_the_formats_they_use() {
    let bytes = std::fs::read(ulog_tests::own_log("sample_log_small.ulg"))
        .or_else(|_| std::fs::read(corpus_files()[0].clone()))
        .unwrap();
    let log = ULog::parse(&bytes).unwrap();
    let mut names: Vec<&str> = log
        .topics()
        .filter(|t| !t.is_empty())
        .map(|t| t.name())
        .collect();
    names.sort_unstable();
    names.dedup();
    let (kept, dropped) = (names[0], names[1]);
    let mut out = Vec::new();
    Edit::new().only([kept]).write(&log, &mut out).unwrap();
    let cut = ULog::parse(&out).unwrap();
    let cut_names: Vec<&str> = cut.topics().map(|t| t.name()).collect();
    assert!(cut_names.iter().all(|n| *n == kept), "{cut_names:?}");
    let layout = log.topic(kept, 0).unwrap().layout().unwrap().clone();
    let mut formats: Vec<String> = cut.formats().iter().map(|f| f.name.clone()).collect();
    let mut used: Vec<String> = layout.formats().iter().map(|f| f.name.clone()).collect();
    formats.sort();
    used.sort();
    used.dedup();
    assert_eq!(formats, used);

    let mut out = Vec::new();
    Edit::new()
        .exclude([dropped])
        .write(&log, &mut out)
        .unwrap();
    let cut = ULog::parse(&out).unwrap();
    assert!(cut.topic_instances(dropped).is_empty());
    assert!(!cut.topic_instances(kept).is_empty());

    let err = Edit::new()
        .only(["no_such_topic"])
        .write(&log, Vec::new())
        .unwrap_err();
    assert!(
        matches!(
            err.kind(),
            ulog_core::write::WriteErrorKind::TopicNotFound(_)
        ),
        "{err}"
    );
}

#[test]
#[cfg_attr(
    not(pyulog),
    ignore = "needs pyulog: pip install pyulog==1.3.0, then touch tests/build.rs"
)]
fn pyulog_reads_every_cut_as_our_reader_does() {
    for path in corpus_files() {
        let bytes = std::fs::read(&path).unwrap();
        let log = ULog::parse(&bytes).unwrap();
        let name = stem(&path);
        let window = windows(&log)[1];
        let out = cut(&bytes, window);
        let ours = ULog::parse(&out).unwrap();
        let theirs = ulog_tests::pyulog_dump(&format!("cut-{name}"), &out);
        assert_eq!(theirs["corrupt"], false, "{name}: pyulog finds corruption");
        let params = theirs["params"].as_object().unwrap();
        assert_eq!(
            params.len(),
            ours.initial_params().len(),
            "{name}: parameters"
        );
        // Every topic instance pyulog reads, with our row count and timestamps.
        for set in theirs["datasets"].as_array().unwrap() {
            let topic = set[0].as_str().unwrap();
            let multi_id = set[1].as_u64().unwrap() as u8;
            let t = ours.topic(topic, multi_id).unwrap();
            let columns = set[2].as_object().unwrap();
            if let Some(ts) = columns.get("timestamp") {
                let ts: Vec<u64> = ts
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|v| v.as_u64().unwrap())
                    .collect();
                if t.timestamp_field().is_some_and(|f| f.unit_us() == 1) {
                    assert_eq!(ts, t.timestamps(), "{name}: {topic} {multi_id}");
                } else {
                    assert_eq!(ts.len(), t.len(), "{name}: {topic} {multi_id}");
                }
            }
        }
        let with_data = ours.topics().filter(|t| !t.is_empty()).count();
        assert_eq!(
            theirs["datasets"].as_array().unwrap().len(),
            with_data,
            "{name}: topics"
        );
    }
}

#[test]
fn topics_are_chosen_by_their_formats_and_a_window_past_the_end_keeps_the_definitions() {
    use ulog_core::testing::LogBuilder;
    let mut b = LogBuilder::new(1, 100);
    b.format("inner:uint8_t x;");
    b.format("outer:uint64_t timestamp;inner a;");
    b.format("other:uint64_t timestamp;");
    b.format("spare:uint64_t timestamp;");
    b.param("int32_t P_ONE", &1i32.to_le_bytes());
    b.subscribe(0, 0, "outer");
    b.subscribe(0, 1, "other");
    for t in [1_000u64, 2_000, 3_000] {
        b.data(0, &[&t.to_le_bytes()[..], &[7]].concat());
        b.data(1, &t.to_le_bytes());
    }
    b.param("int32_t P_ONE", &2i32.to_le_bytes());
    let bytes = b.bytes().to_vec();
    let formats = |out: &[u8]| {
        let mut f: Vec<String> = ULog::parse(out)
            .unwrap()
            .formats()
            .iter()
            .map(|f| f.name.clone())
            .collect();
        f.sort();
        f
    };

    // Leaving out `outer` drops its own format; `inner` is a format name like any
    // topic's, so it stays.
    let mut out = Vec::new();
    let s = Edit::new()
        .exclude(["outer"])
        .write(&bytes, &mut out)
        .unwrap();
    assert_eq!(formats(&out), ["inner", "other", "spare"]);
    assert_eq!((s.rows, s.rows_left_out), (3, 3));
    assert!(s.unlogged.is_empty());

    // A topic with a format and no subscription: no rows, and said so.
    let mut out = Vec::new();
    let s = Edit::new().only(["spare"]).write(&bytes, &mut out).unwrap();
    assert_eq!(formats(&out), ["spare"]);
    assert_eq!(
        (s.rows, s.unlogged.as_slice()),
        (0, &["spare".to_owned()][..])
    );

    // A name no format has: an error naming the closest, before anything is written.
    let mut out = Vec::new();
    let err = Edit::new()
        .only(["outr"])
        .write(&bytes, &mut out)
        .unwrap_err();
    match err.kind() {
        ulog_core::write::WriteErrorKind::TopicNotFound(t) => {
            assert_eq!(
                t.closest.first().map(String::as_str),
                Some("outer"),
                "{err}"
            )
        }
        other => panic!("{other:?}"),
    }
    assert!(out.is_empty());

    // A window after the last row: the definitions, with the parameter changed
    // before it as its initial value, and the subscriptions; no data.
    let mut out = Vec::new();
    let s = Edit::new()
        .window(Some(10_000), None)
        .write(&bytes, &mut out)
        .unwrap();
    assert_eq!(s.rows, 0);
    // Where the data was, for a caller to say so.
    assert_eq!(s.data_times, Some((1_000, 3_000)));
    let cut = ULog::parse(&out).unwrap();
    assert!(cut.findings().is_empty(), "{:?}", cut.findings());
    assert_eq!(cut.subscriptions().len(), 2);
    assert_eq!(cut.start_timestamp(), 100);
    let p = &cut.initial_params()[0];
    assert_eq!(
        (p.name().as_ref(), p.value().to_string()),
        ("P_ONE", "2".into())
    );
    assert!(cut.param_changes().is_empty());

    // A window that holds no time: refused before anything is read or written.
    for (start, end) in [(2_000, 1_000), (2_000, 2_000)] {
        let mut out = Vec::new();
        let err = Edit::new()
            .window(Some(start), Some(end))
            .write(&bytes, &mut out)
            .unwrap_err();
        assert_eq!(
            err.kind(),
            &ulog_core::write::WriteErrorKind::EmptyWindow { start, end },
            "{err}"
        );
        assert!(out.is_empty());
    }
    // One microsecond is a window.
    let mut out = Vec::new();
    let s = Edit::new()
        .window(Some(2_000), Some(2_001))
        .write(&bytes, &mut out)
        .unwrap();
    assert_eq!(s.rows, 2);

    // The header's timestamp replaced.
    let mut out = Vec::new();
    Edit::new()
        .header_timestamp(0)
        .write(&bytes, &mut out)
        .unwrap();
    assert_eq!(ULog::parse(&out).unwrap().start_timestamp(), 0);
    assert_eq!(out[16..], bytes[16..]);
}

#[test]
fn a_format_after_the_definitions_is_kept_with_its_topic() {
    // The spec puts formats in the definitions section; framing accepts one later,
    // and a cut must then still write it before its subscription.
    use ulog_core::testing::LogBuilder;
    let mut b = LogBuilder::new(1, 0);
    b.format("a:uint64_t timestamp;");
    b.subscribe(0, 0, "a");
    b.format("b:uint64_t timestamp;uint8_t x;");
    b.subscribe(0, 1, "b");
    for t in [1_000u64, 2_000, 3_000] {
        b.data(0, &t.to_le_bytes());
        b.data(1, &[&t.to_le_bytes()[..], &[1]].concat());
    }
    let bytes = b.into_bytes();
    for window in [None, Some(1_500)] {
        let mut out = Vec::new();
        Edit::new()
            .window(window, None)
            .exclude(["a"])
            .write(&bytes, &mut out)
            .unwrap();
        let cut = ULog::parse(&out).unwrap();
        assert!(
            cut.findings().is_empty(),
            "{window:?}: {:?}",
            cut.findings()
        );
        let rows = cut.topic("b", 0).unwrap().len();
        assert_eq!(rows, if window.is_some() { 2 } else { 3 }, "{window:?}");
        assert!(cut.topic_instances("a").is_empty());
    }
}
