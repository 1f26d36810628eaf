//! Several topics at once: a `ULogTopics` enum walks a log once, in file order or
//! merged by timestamp, decoding the topics it names and handing over the others raw.

use ulog_core::read::ScanOrder;
use ulog_core::typed::TypedErrorKind;
use ulog_core::{ScanOptions, TopicRecord, ULog, ULogMessage, ULogTopics};

#[derive(ULogMessage, Debug, Clone, Copy)]
struct VehicleAttitude {
    timestamp: u64,
    q: [f32; 4],
}

#[derive(ULogMessage, Debug, Clone, Copy)]
struct BatteryStatus {
    timestamp: u64,
    voltage_v: f32,
}

/// `esc_status` with a field type the log does not have and that its `uint8_t` does
/// not widen to.
#[derive(ULogMessage, Debug, Clone, Copy)]
struct EscStatus {
    timestamp: u64,
    esc_count: i8,
}

#[derive(ULogTopics, Debug)]
enum Topics {
    Attitude(VehicleAttitude),
    Battery(BatteryStatus),
}

#[derive(ULogTopics, Debug)]
enum WithMismatch {
    Esc(EscStatus),
}

/// What a record of the walk holds, kept past the callback.
struct Walked {
    name: String,
    multi_id: u8,
    payload: Vec<u8>,
    message: Option<Topics>,
}

/// Every record of the walk of `log` in `order`, the topics `E` does not name raw.
fn walk<E: ULogTopics>(
    log: &ULog<'_>,
    order: ScanOrder,
    mut f: impl FnMut(Result<TopicRecord<'_, E>, ulog_core::TypedError>),
) {
    let options = ScanOptions::default().order(order).raw_others(true);
    ulog_core::scan_topics::<E>(log, &options, |r| f(r)).unwrap();
}

fn timestamp(log: &ULog<'_>, r: &Walked) -> u64 {
    match &r.message {
        Some(Topics::Attitude(a)) => a.timestamp,
        Some(Topics::Battery(b)) => b.timestamp,
        None => {
            let t = log.topic(&r.name, 0).unwrap();
            t.timestamp_field().unwrap().raw(&r.payload).unwrap()
        }
    }
}

#[test]
fn walks_in_file_order_and_by_timestamp() {
    let bytes = ulog_core::testing::sample_log();
    let log = ULog::parse(&bytes).unwrap();
    let total: usize = log.topics().map(|t| t.len()).sum();
    for order in [ScanOrder::File, ScanOrder::Timestamp] {
        let mut records: Vec<Walked> = Vec::new();
        walk::<Topics>(&log, order, |r| {
            let r = r.unwrap();
            records.push(Walked {
                name: r.topic.name().to_owned(),
                multi_id: r.topic.multi_id(),
                payload: r.payload.to_vec(),
                message: r.message,
            })
        });
        assert_eq!(records.len(), total, "{order:?}");
        let (mut att, mut bat, mut raw) = (0, [0; 2], 0);
        for r in &records {
            match &r.message {
                Some(Topics::Attitude(_)) => att += 1,
                Some(Topics::Battery(_)) => bat[r.multi_id as usize] += 1,
                None => {
                    assert!(["vehicle_local_position", "esc_status"].contains(&r.name.as_str()));
                    raw += 1
                }
            }
        }
        assert_eq!((att, bat, raw), (200, [20, 20], 120), "{order:?}");
        let times: Vec<u64> = records.iter().map(|r| timestamp(&log, r)).collect();
        if order == ScanOrder::Timestamp {
            assert!(
                times.windows(2).all(|w| w[0] <= w[1]),
                "merged by timestamp"
            );
        }
    }
    // In file order, the walk follows the data messages' offsets.
    let mut file: Vec<u64> = Vec::new();
    walk::<Topics>(&log, ScanOrder::File, |r| {
        file.push(match r.unwrap() {
            TopicRecord {
                message: Some(Topics::Attitude(a)),
                ..
            } => a.timestamp,
            TopicRecord {
                message: Some(Topics::Battery(b)),
                ..
            } => b.timestamp,
            TopicRecord {
                message: None,
                payload,
                ..
            } => u64::from_le_bytes(payload[..8].try_into().unwrap()),
        })
    });
    let mut offsets: Vec<(u64, u64)> = Vec::new();
    for t in log.topics() {
        let ts = t.timestamps();
        offsets.extend(t.message_offsets().iter().zip(ts));
    }
    offsets.sort();
    assert_eq!(file, offsets.iter().map(|(_, t)| *t).collect::<Vec<_>>());
}

#[test]
fn a_topic_that_does_not_fit_is_reported_once_then_raw() {
    let bytes = ulog_core::testing::sample_log();
    let log = ULog::parse(&bytes).unwrap();
    let mut errors = 0;
    let mut raw_esc = 0;
    walk::<WithMismatch>(&log, ScanOrder::File, |r| match r {
        Err(e) => {
            assert!(matches!(e.kind(), TypedErrorKind::Mismatch(_)), "{e}");
            assert!(e.to_string().contains("esc_count"), "{e}");
            errors += 1;
        }
        Ok(TopicRecord {
            message: None,
            topic,
            ..
        }) if topic.name() == "esc_status" => raw_esc += 1,
        Ok(TopicRecord { message: None, .. }) => {}
        Ok(TopicRecord {
            message: Some(WithMismatch::Esc(e)),
            ..
        }) => {
            panic!("nothing fits, yet decoded {e:?}")
        }
    });
    assert_eq!((errors, raw_esc), (1, 20));
    let _ = WithMismatch::NAMES;
}
