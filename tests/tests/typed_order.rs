//! `scan_topics` by timestamp: never an invented time. A record whose topic has no
//! timestamp is handed out where it stands in the file, with no timestamp.

use std::ops::ControlFlow;

use ulog_core::read::ScanOrder;
use ulog_core::testing::LogBuilder;
use ulog_core::typed::TypedErrorKind;
use ulog_core::{scan, scan_topics, ScanOptions, Source, ULog, ULogMessage, ULogTopics};

#[derive(ULogMessage, Debug, Clone, Copy, PartialEq)]
struct Fast {
    timestamp: u64,
    v: u32,
}

#[derive(ULogMessage, Debug, Clone, Copy, PartialEq)]
struct Slow {
    timestamp: u64,
    v: u32,
}

/// No `timestamp` field.
#[derive(ULogMessage, Debug, Clone, Copy, PartialEq)]
struct Untimed {
    count: u32,
}

#[derive(ULogTopics, Debug)]
enum Topics {
    Fast(Fast),
    Slow(Slow),
    Untimed(Untimed),
}

/// `fast` at 10, 20, …; `slow` logged late (its times lag the file: 5, 15, …);
/// `untimed` between them; a `broken` topic whose format cannot be laid out.
fn log() -> Vec<u8> {
    let mut b = LogBuilder::new(1, 0);
    b.format("fast:uint64_t timestamp;uint32_t v;");
    b.format("slow:uint64_t timestamp;uint32_t v;");
    b.format("untimed:uint32_t count;");
    b.format("broken:uint64_t timestamp;missing m;");
    b.subscribe(0, 0, "fast");
    b.subscribe(0, 1, "slow");
    b.subscribe(0, 2, "untimed");
    b.subscribe(0, 3, "broken");
    let row = |t: u64, v: u32| [&t.to_le_bytes()[..], &v.to_le_bytes()].concat();
    for i in 1..=5u64 {
        b.data(0, &row(10 * i, i as u32));
        b.data(2, &(i as u32).to_le_bytes());
        b.data(1, &row(10 * i - 5, 100 + i as u32));
        b.data(3, &[0xAB; 12]);
    }
    b.into_bytes()
}

/// (topic, timestamp, value) of each record handed out.
fn order(bytes: &[u8], options: &ScanOptions) -> Vec<(String, Option<u64>, Option<u32>)> {
    let mut out = Vec::new();
    scan_topics::<Topics>(bytes, options, |r| {
        let r = r.unwrap();
        let v = match r.message {
            Some(Topics::Fast(f)) => Some(f.v),
            Some(Topics::Slow(s)) => Some(s.v),
            Some(Topics::Untimed(u)) => Some(u.count),
            None => None,
        };
        out.push((r.topic.name().to_owned(), r.timestamp, v));
    })
    .unwrap();
    out
}

#[test]
fn by_timestamp_untimed_records_stay_where_they_stand_in_the_file() {
    let bytes = log();
    let by_time = ScanOptions::default()
        .order(ScanOrder::Timestamp)
        .raw_others(true);
    let got = order(&bytes, &by_time);
    let timed: Vec<u64> = got.iter().filter_map(|r| r.1).collect();
    assert!(timed.windows(2).all(|w| w[0] <= w[1]), "{got:?}");
    assert_eq!(timed.len(), 10);
    // `untimed` row i was logged after `fast` at 10·i (and `slow` at 10·(i-1)-5):
    // it comes after every record at or below 10·i, before the next.
    for i in 1..=5u32 {
        let at = got
            .iter()
            .position(|r| r.0 == "untimed" && r.2 == Some(i))
            .unwrap();
        assert_eq!(got[at].1, None, "no timestamp is invented");
        let before = got[..at].iter().filter_map(|r| r.1).max().unwrap();
        assert_eq!(before, 10 * u64::from(i), "{got:?}");
        assert!(got[at + 1..].iter().filter_map(|r| r.1).all(|t| t > before));
    }
    // The topic that cannot be laid out: undecoded, no timestamp, in file order.
    let broken: Vec<usize> = (0..got.len()).filter(|&k| got[k].0 == "broken").collect();
    assert_eq!(broken.len(), 5);
    assert!(broken
        .iter()
        .all(|&k| got[k].1.is_none() && got[k].2.is_none()));
    assert!(broken.windows(2).all(|w| w[0] < w[1]));

    // The same through a parsed log and through a reader (read into memory first).
    let log = ULog::parse(&bytes).unwrap();
    let mut from_log = Vec::new();
    scan_topics::<Topics>(&log, &by_time, |r| {
        from_log.push(r.map(|r| (r.offset, r.timestamp)).ok())
    })
    .unwrap();
    let mut from_reader = Vec::new();
    scan_topics::<Topics>(Source::reader(&bytes[..]), &by_time, |r| {
        from_reader.push(r.map(|r| (r.offset, r.timestamp)).ok())
    })
    .unwrap();
    assert_eq!(from_log, from_reader);
    assert_eq!(from_log.len(), got.len());
    assert!(
        from_log.iter().all(Option::is_some),
        "an unnamed topic is no error"
    );
}

#[test]
fn in_file_order_records_carry_their_timestamps_and_unnamed_topics_are_left_out() {
    let bytes = log();
    let got = order(&bytes, &ScanOptions::default());
    // Without `raw_others`, only the enum's topics; `broken` is not named.
    assert_eq!(got.len(), 15);
    assert_eq!(got[0], ("fast".into(), Some(10), Some(1)));
    assert_eq!(got[1], ("untimed".into(), None, Some(1)));
    assert_eq!(got[2], ("slow".into(), Some(5), Some(101)));
}

#[derive(ULogMessage, Debug, Clone, Copy, PartialEq)]
#[ulog(name = "fast")]
struct FastWrong {
    timestamp: u64,
    v: f32,
}

/// Its `Fast` variant never fits the log: it is never read.
#[allow(dead_code)]
#[derive(ULogTopics, Debug)]
enum Wrong {
    Fast(FastWrong),
    Slow(Slow),
}

#[test]
fn a_topic_that_does_not_fit_is_reported_once_and_the_others_go_on() {
    let bytes = log();
    for options in [
        ScanOptions::default(),
        ScanOptions::default().order(ScanOrder::Timestamp),
    ] {
        let (mut errors, mut slow) = (Vec::new(), 0);
        scan_topics::<Wrong>(&bytes, &options, |r| match r {
            Ok(r) => {
                assert!(matches!(r.message, Some(Wrong::Slow(_))));
                slow += 1;
            }
            Err(e) => errors.push(e),
        })
        .unwrap();
        assert_eq!(slow, 5);
        assert_eq!(errors.len(), 1);
        assert!(matches!(errors[0].kind(), TypedErrorKind::Mismatch(_)));
        assert_eq!(errors[0].topic(), Some(("fast", 0)));
    }
}

#[test]
fn a_pass_stops_when_the_callback_says_so() {
    let bytes = log();
    let mut seen = 0;
    let summary = scan_topics::<Topics>(&bytes, &ScanOptions::default(), |_| {
        seen += 1;
        if seen == 3 {
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        }
    })
    .unwrap();
    assert_eq!(seen, 3);
    assert!(summary.stopped);
    let full = scan(&bytes, &ScanOptions::default(), |_| {}).unwrap();
    assert!(!full.stopped);
    assert_eq!(full.data_messages, 20);
}
