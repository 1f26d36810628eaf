//! Windows by time: a topic's time index, and `scan_topics` given a window, equal the
//! records of a whole pass whose timestamps fall in the window, on every corpus log.

use ulog_core::read::{ScanOrder, Unwrapper};
use ulog_core::{scan_topics, ScanOptions, ULog, ULogMessage, ULogTopics};

#[derive(ULogMessage, Debug, Clone, PartialEq)]
struct VehicleAttitude {
    timestamp: u64,
    q: [f32; 4],
}

#[derive(ULogTopics, Debug, Clone, PartialEq)]
enum Topics {
    Attitude(VehicleAttitude),
}

/// What a record is: where it stands, its timestamp, whether it was decoded.
type Seen = (u64, Option<u64>, bool);

fn pass(log: &ULog<'_>, options: &ScanOptions) -> Vec<Seen> {
    let mut seen = Vec::new();
    scan_topics::<Topics>(log, &options.clone().raw_others(true), |r| {
        if let Ok(r) = r {
            seen.push((r.offset, r.timestamp, r.message.is_some()));
        }
    })
    .unwrap();
    seen
}

/// Three windows of a log: its middle, one open at the start, one open at the end.
fn windows(log: &ULog<'_>) -> [(Option<u64>, Option<u64>); 3] {
    let span = log.span();
    let at = |f: f64| span.at(span.duration_s() * f);
    [
        (Some(at(0.3)), Some(at(0.6))),
        (None, Some(at(0.2))),
        (Some(at(0.9)), None),
    ]
}

#[test]
fn a_window_is_the_records_of_the_whole_pass_in_it() {
    let mut checked = 0;
    for path in ulog_tests::corpus_files() {
        let bytes = std::fs::read(&path).unwrap();
        let Ok(log) = ULog::parse(&bytes) else {
            continue;
        };
        for order in [ScanOrder::File, ScanOrder::Timestamp] {
            let by = ScanOptions::default().order(order);
            let whole = pass(&log, &by);
            for (start, end) in windows(&log) {
                let range = start.unwrap_or(0)..end.unwrap_or(u64::MAX);
                let want: Vec<Seen> = whole
                    .iter()
                    .filter(|s| s.1.is_some_and(|t| range.contains(&t)))
                    .copied()
                    .collect();
                let got = pass(&log, &by.clone().window_us(start, end));
                assert_eq!(
                    got,
                    want,
                    "{}: {order:?} window {start:?}..{end:?}",
                    path.display()
                );
            }
        }
        checked += 1;
    }
    // The repository's own corpus has five logs; the full one has many more.
    let least = if cfg!(full_corpus) { 10 } else { 1 };
    assert!(checked >= least, "{checked} logs");
}

#[test]
fn a_time_index_finds_what_a_scan_of_every_row_finds() {
    for path in ulog_tests::corpus_files() {
        let bytes = std::fs::read(&path).unwrap();
        let Ok(log) = ULog::parse(&bytes) else {
            continue;
        };
        for topic in log.topics() {
            if topic.timestamp_field().is_none() {
                continue;
            }
            let index = topic.time_index();
            // Every row's timestamp, unwrapped in file order; rows too short for one
            // have none and are not indexed.
            let mut unwrap = Unwrapper::new(topic.timestamp_field());
            let mut rows: Vec<(u64, u32)> = topic
                .payloads()
                .zip(0u32..)
                .filter_map(|(p, r)| Some((unwrap.push(p)?, r)))
                .collect();
            rows.sort_by_key(|r| r.0);
            assert_eq!(
                index.len(),
                rows.len(),
                "{}: {}",
                path.display(),
                topic.name()
            );
            for (start, end) in windows(&log) {
                let (start, end) = (start.unwrap_or(0), end.unwrap_or(u64::MAX));
                let want: Vec<u32> = rows
                    .iter()
                    .filter(|(t, _)| (start..end).contains(t))
                    .map(|r| r.1)
                    .collect();
                assert_eq!(index.rows_in(start, end), want, "{}", topic.name());
                let before = rows.iter().rev().find(|(t, _)| *t <= start).copied();
                assert_eq!(index.at_or_before(start), before, "{}", topic.name());
            }
        }
    }
}

#[test]
fn time_ordered_rows_are_the_decoded_records_by_time_and_seek_finds_a_suffix() {
    let mut checked = 0;
    for path in ulog_tests::corpus_files() {
        let bytes = std::fs::read(&path).unwrap();
        let Ok(log) = ULog::parse(&bytes) else {
            continue;
        };
        let Ok(rows) = log.time_ordered::<Topics>() else {
            continue;
        };
        let whole: Vec<(u64, u8, Topics)> = rows.collect();
        assert!(
            whole.windows(2).all(|w| w[0].0 <= w[1].0),
            "{}",
            path.display()
        );
        // The records scan_topics decodes, in any order: the same.
        let mut scanned = Vec::new();
        scan_topics::<Topics>(&log, &ScanOptions::default(), |r| {
            if let Ok(r) = r {
                if let (Some(t), Some(m)) = (r.timestamp, r.message) {
                    scanned.push((t, r.topic.multi_id(), m));
                }
            }
        })
        .unwrap();
        let key = |r: &(u64, u8, Topics)| {
            let Topics::Attitude(a) = &r.2;
            (r.0, r.1, a.q.map(f32::to_bits))
        };
        let mut a: Vec<_> = whole.iter().map(key).collect();
        let mut b: Vec<_> = scanned.iter().map(key).collect();
        a.sort();
        b.sort();
        assert_eq!(a, b, "{}", path.display());
        // Seeking, forwards then back: the rows from the first at or after the time.
        let mut rows = log.time_ordered::<Topics>().unwrap();
        for (start, _) in windows(&log) {
            let t = start.unwrap_or(0);
            rows.seek(t);
            let from = whole.partition_point(|r| r.0 < t);
            let got: Vec<_> = rows.by_ref().take(50).map(|r| key(&r)).collect();
            let want: Vec<_> = whole[from..].iter().take(50).map(key).collect();
            assert_eq!(got, want, "{}: seek {t}", path.display());
        }
        checked += usize::from(!whole.is_empty());
    }
    if cfg!(full_corpus) {
        assert!(checked >= 5, "{checked} logs with attitudes");
    }
}
