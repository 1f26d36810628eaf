//! Hand-written bindings of nested PX4 topics — `esc_status` with `esc_report[8]` and
//! padding in the middle, `telemetry_status` heartbeats, and a mapped subset of it —
//! read through `ULog::read` on real logs: they decode every row identically to the
//! bindings generated from the log (`ulog_module!`), and to the reader's generic
//! field access, column by column.

use ulog_core::typed::PlanKind;
use ulog_core::{LogFile, Topic, ULog, ULogMessage};

#[derive(ULogMessage, Debug, Clone, Copy, PartialEq)]
struct EscReport {
    timestamp: u64,
    esc_errorcount: u32,
    esc_rpm: i32,
    esc_voltage: f32,
    esc_current: f32,
    esc_temperature: f32,
    esc_setpoint: f32,
    esc_setpoint_raw: u16,
    esc_address: u16,
    esc_version: u16,
    esc_state: u16,
    esc_vendor: u8,
    _padding0: [u8; 7],
}

#[derive(ULogMessage, Debug, Clone, Copy, PartialEq)]
struct EscStatus {
    timestamp: u64,
    counter: u16,
    esc_count: u8,
    esc_connectiontype: u8,
    _padding0: [u8; 4],
    esc: [EscReport; 8],
}

#[derive(ULogMessage, Debug, Clone, Copy, PartialEq)]
struct TelemetryStatus {
    timestamp: u64,
    heartbeat_time: u64,
    data_rate: f32,
    rate_multiplier: f32,
    rate_rx: f32,
    rate_tx: f32,
    rate_txerr: f32,
    remote_system_id: u8,
    remote_component_id: u8,
    remote_type: u8,
    remote_system_status: u8,
    r#type: u8,
    mode: u8,
    flow_control: bool,
    forwarding: bool,
    mavlink_v2: bool,
    ftp: bool,
    streams: u8,
    _padding0: [u8; 1],
}

/// Only the heartbeat fields, in another order, one renamed: a mapped plan on any
/// firmware that logs them.
#[derive(ULogMessage, Debug, PartialEq)]
#[ulog(name = "telemetry_status")]
struct Heartbeat {
    #[ulog(name = "heartbeat_time")]
    heard_at: u64,
    timestamp: u64,
}

ulog_core::ulog_module!(mod esc_log = "corpus/files/esc_status_log.ulg");

/// Every (path, value) of a decoded message, values as text (`NaN`s compare equal,
/// floats exactly: the text of a float is its shortest round-trip form).
fn fields<T: ULogMessage>(m: &T) -> Vec<(String, String)> {
    let mut out = Vec::new();
    m.visit_fields(&mut |path, v| out.push((path.to_owned(), format!("{v:?}"))));
    out
}

/// Every column of row `i` read with the reader's generic access.
fn generic(topic: &Topic<'_, '_>, i: usize) -> Vec<(String, String)> {
    let payload = topic.payload(i).unwrap();
    topic
        .fields()
        .unwrap()
        .iter()
        .map(|c| {
            (
                c.path().to_owned(),
                format!("{:?}", c.read(payload).unwrap()),
            )
        })
        .collect()
}

/// A binding decodes each row of `topic` to what the reader reads for the same paths.
fn agrees_with_reader<T: ULogMessage>(log: &ULog<'_>, name: &str, multi_id: u8) -> usize {
    let rows = log.read::<T>(multi_id).unwrap();
    let topic = rows.topic();
    for (i, row) in rows.iter().enumerate() {
        let ours = fields(&row.unwrap());
        let theirs = generic(&topic, i);
        for (path, value) in &ours {
            let found = theirs.iter().find(|(p, _)| p == path);
            assert_eq!(
                found.map(|(_, v)| v),
                Some(value),
                "{name}: {}/{multi_id} row {i} `{path}`",
                T::NAME
            );
        }
    }
    rows.len()
}

#[test]
fn esc_status_hand_written_equals_generated_and_reader() {
    let file = LogFile::open(ulog_tests::own_log("esc_status_log.ulg")).unwrap();
    let log = file.parse().unwrap();
    let hand = log.read::<EscStatus>(0).unwrap();
    assert_eq!(hand.plan().kind(), PlanKind::Exact);
    {
        let generated = log.read::<esc_log::EscStatus>(0).unwrap();
        assert_eq!(generated.plan().kind(), PlanKind::Exact);
        assert_eq!(hand.len(), generated.len());
        for (h, g) in hand.iter().zip(generated.iter()) {
            let (h, g) = (h.unwrap(), g.unwrap());
            assert_eq!(fields(&h), fields(&g));
            // Eight reports with the 7 padding bytes between them skipped.
            assert_eq!(fields(&h).len(), 4 + 8 * 12);
        }
        // The hand-written formats are the log's, nested one first.
        assert_eq!(
            EscStatus::schema().formats_text(),
            esc_log::EscStatus::schema().formats_text()
        );
    }
    let rows = agrees_with_reader::<EscStatus>(&log, "esc_status_log", 0);
    assert!(rows > 100, "{rows}");
    // Encoding gives back the payload but for padding (zeros here).
    let first = hand.get(0).unwrap().unwrap();
    assert_eq!(first.encode().len(), hand.topic().payload(0).unwrap().len());
    assert_eq!(hand.plan().decode(&first.encode()).unwrap(), first);
}

#[test]
fn telemetry_status_hand_written_equals_generated_and_reader() {
    let file = LogFile::open(ulog_tests::own_log("esc_status_log.ulg")).unwrap();
    let log = file.parse().unwrap();
    let full = log.read::<TelemetryStatus>(0).unwrap();
    assert_eq!(full.plan().kind(), PlanKind::Exact);
    let beats = log.read::<Heartbeat>(0).unwrap();
    assert_eq!(beats.plan().kind(), PlanKind::Mapped);
    {
        let generated = log.read::<esc_log::TelemetryStatus>(0).unwrap();
        for (t, g) in full.iter().zip(generated.iter()) {
            assert_eq!(fields(&t.unwrap()), fields(&g.unwrap()));
        }
    }
    for (t, h) in full.iter().zip(beats.iter()) {
        let (t, h) = (t.unwrap(), h.unwrap());
        assert_eq!((h.heard_at, h.timestamp), (t.heartbeat_time, t.timestamp));
    }
    agrees_with_reader::<TelemetryStatus>(&log, "esc_status_log", 0);
}

/// Heartbeats of every corpus log that has them, every instance, through the mapped
/// binding: the same values the reader reads, whatever the firmware's layout.
#[test]
fn heartbeats_of_every_corpus_log() {
    let mut checked = 0;
    for path in ulog_tests::corpus_files() {
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        let file = LogFile::open(&path).unwrap();
        let Ok(log) = file.parse() else { continue };
        for topic in log.topic_instances("telemetry_status") {
            if topic.field("heartbeat_time").is_err() {
                // Firmware before heartbeats were logged: the binding is refused.
                let Err(e) = topic.read::<Heartbeat>() else {
                    panic!("{name}: a binding without `heartbeat_time` is accepted");
                };
                assert!(e
                    .to_string()
                    .contains("field `heartbeat_time`: missing in the log"));
                continue;
            }
            checked += agrees_with_reader::<Heartbeat>(&log, &name, topic.multi_id());
        }
        for topic in log.topic_instances("esc_status") {
            if topic.read::<EscStatus>().is_ok() {
                checked += agrees_with_reader::<EscStatus>(&log, &name, topic.multi_id());
            }
        }
    }
    // esc_status_log alone, of the repository's own logs, has 238 rows of them.
    let least = if ulog_tests::FULL_CORPUS { 400 } else { 200 };
    assert!(checked > least, "{checked}");
}
