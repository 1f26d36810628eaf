//! Several topics at once: a `ULogTopics` enum walks a log once, in file order or
//! merged by timestamp, decoding the topics it names and handing over the others raw.

use ulog_core::typed::{TopicRecord, ULogMessage, ULogTopics};
use ulog_core::{ErrorKind, Order, ULog};

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

/// `esc_status` with a field type the log does not have.
#[derive(ULogMessage, Debug, Clone, Copy)]
struct EscStatus {
    timestamp: u64,
    esc_count: u16,
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

fn timestamp(log: &ULog<'_>, r: &TopicRecord<'_, Topics>) -> u64 {
    match r {
        TopicRecord::Message {
            message: Topics::Attitude(a),
            ..
        } => a.timestamp,
        TopicRecord::Message {
            message: Topics::Battery(b),
            ..
        } => b.timestamp,
        TopicRecord::Raw { name, payload, .. } => {
            let t = log.topic(name, 0).unwrap();
            t.timestamp_field().unwrap().raw(payload).unwrap()
        }
    }
}

#[test]
fn walks_in_file_order_and_by_timestamp() {
    let bytes = ulog_core::testing::sample_log();
    let log = ULog::parse(&bytes).unwrap();
    let total: usize = log.topics().map(|t| t.len()).sum();
    for order in [Order::File, Order::Timestamp] {
        let records: Vec<_> = log.walk::<Topics>(order).map(|r| r.unwrap()).collect();
        assert_eq!(records.len(), total, "{order:?}");
        let (mut att, mut bat, mut raw) = (0, [0; 2], 0);
        for r in &records {
            match r {
                TopicRecord::Message {
                    message: Topics::Attitude(_),
                    ..
                } => att += 1,
                TopicRecord::Message {
                    message: Topics::Battery(_),
                    multi_id,
                } => bat[*multi_id as usize] += 1,
                TopicRecord::Raw { name, .. } => {
                    assert!(["vehicle_local_position", "esc_status"].contains(name));
                    raw += 1
                }
            }
        }
        assert_eq!((att, bat, raw), (200, [20, 20], 120), "{order:?}");
        let times: Vec<u64> = records.iter().map(|r| timestamp(&log, r)).collect();
        if order == Order::Timestamp {
            assert!(
                times.windows(2).all(|w| w[0] <= w[1]),
                "merged by timestamp"
            );
        }
    }
    // In file order, the walk follows the data messages' offsets.
    let file: Vec<u64> = log
        .walk::<Topics>(Order::File)
        .map(|r| match r.unwrap() {
            TopicRecord::Message {
                message: Topics::Attitude(a),
                ..
            } => a.timestamp,
            TopicRecord::Message {
                message: Topics::Battery(b),
                ..
            } => b.timestamp,
            TopicRecord::Raw { payload, .. } => {
                u64::from_le_bytes(payload[..8].try_into().unwrap())
            }
        })
        .collect();
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
    for r in log.walk::<WithMismatch>(Order::File) {
        match r {
            Err(e) => {
                assert!(matches!(e.kind, ErrorKind::Mismatch(_)), "{e}");
                assert!(e.to_string().contains("esc_count"), "{e}");
                errors += 1;
            }
            Ok(TopicRecord::Raw {
                name: "esc_status", ..
            }) => raw_esc += 1,
            Ok(TopicRecord::Raw { .. }) => {}
            Ok(TopicRecord::Message {
                message: WithMismatch::Esc(e),
                ..
            }) => {
                panic!("nothing fits, yet decoded {e:?}")
            }
        }
    }
    assert_eq!((errors, raw_esc), (1, 20));
    let _ = WithMismatch::NAMES;
}
