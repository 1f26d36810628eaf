//! Hand-written bindings of nested PX4 topics (`esc_status` with `esc_report[8]` and
//! mid-struct padding, `telemetry_status`) decoding a real log to the values pyulog
//! gives, and agreeing with bindings generated from the same log.

use std::collections::HashMap;
use std::path::PathBuf;

use ulog_core::typed::{CharArray, Plan, PlanKind, ULogMessage};
use ulog_format::{Format, Layout};

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

/// Only the fields an analysis needs, in another order, named differently.
#[derive(ULogMessage, Debug, PartialEq)]
#[ulog(name = "telemetry_status")]
struct Heartbeat {
    #[ulog(name = "heartbeat_time")]
    heard_at: u64,
    #[ulog(alias = "rate_rx_old", alias = "rate_rx")]
    receive_rate: f32,
    timestamp: u64,
}

ulog_core::typed::ulog_module!(mod esc_log = "../../shared/corpus/files/esc_status_log.ulg");

/// A tiny walker of a log's records, enough to find the payloads of one topic (the
/// reader has the real one).
struct Records {
    formats: Vec<Format>,
    /// msg_id → (name, multi_id)
    subscriptions: HashMap<u16, (String, u8)>,
    data: Vec<(u16, Vec<u8>)>,
}

fn corpus() -> Option<PathBuf> {
    let dir = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../shared/corpus"));
    if dir.is_dir() {
        Some(dir)
    } else {
        eprintln!(
            "skipped: no corpus at {} (../shared/corpus beside the workspace)",
            dir.display()
        );
        None
    }
}

fn walk(bytes: &[u8]) -> Records {
    let mut r = Records {
        formats: Vec::new(),
        subscriptions: HashMap::new(),
        data: Vec::new(),
    };
    let mut pos = 16;
    while pos + 3 <= bytes.len() {
        let size = u16::from_le_bytes([bytes[pos], bytes[pos + 1]]) as usize;
        let kind = bytes[pos + 2];
        let Some(payload) = bytes.get(pos + 3..pos + 3 + size) else {
            break;
        };
        match kind {
            b'F' => {
                if let Ok(f) = Format::parse_bytes(payload) {
                    r.formats.push(f);
                }
            }
            b'A' => {
                let id = u16::from_le_bytes([payload[1], payload[2]]);
                let name = String::from_utf8_lossy(&payload[3..]).into_owned();
                r.subscriptions.insert(id, (name, payload[0]));
            }
            b'D' => r.data.push((
                u16::from_le_bytes([payload[0], payload[1]]),
                payload[2..].to_vec(),
            )),
            _ => {}
        }
        pos += 3 + size;
    }
    r
}

impl Records {
    fn topic(&self, name: &str, multi_id: u8) -> (Layout, Vec<&[u8]>) {
        let id = self
            .subscriptions
            .iter()
            .find(|(_, (n, m))| n == name && *m == multi_id)
            .map(|(id, _)| *id)
            .expect("topic in log");
        let layout = Layout::resolve(name, &self.formats).expect("layout");
        let payloads = self
            .data
            .iter()
            .filter(|(i, _)| *i == id)
            .map(|(_, p)| p.as_slice())
            .collect();
        (layout, payloads)
    }
}

fn expected_rows(
    corpus: &std::path::Path,
    stem: &str,
    topic: &str,
) -> (Vec<String>, Vec<Vec<String>>) {
    let path = corpus.join(format!("expected/{stem}/csv/{stem}_{topic}.csv"));
    let text = std::fs::read_to_string(path).expect("expected csv");
    let mut lines = text.lines();
    let header = lines
        .next()
        .unwrap()
        .split(',')
        .map(str::to_owned)
        .collect();
    let rows = lines
        .map(|l| l.split(',').map(str::to_owned).collect())
        .collect();
    (header, rows)
}

fn same(expected: &str, value: f64) -> bool {
    let e: f64 = expected.parse().unwrap_or(f64::NAN);
    e == value || (e.is_nan() && value.is_nan()) || ((e - value).abs() <= 1e-6 * e.abs().max(1.0))
}

#[test]
fn esc_status_decodes_like_pyulog() {
    let Some(corpus) = corpus() else { return };
    let bytes = std::fs::read(corpus.join("files/esc_status_log.ulg")).unwrap();
    let records = walk(&bytes);
    let (layout, payloads) = records.topic("esc_status", 0);
    let plan = Plan::<EscStatus>::new(&layout).unwrap();
    assert_eq!(plan.kind(), PlanKind::Exact);
    let (header, rows) = expected_rows(&corpus, "esc_status_log", "esc_status_0");
    assert_eq!(rows.len(), payloads.len());
    for (payload, row) in payloads.iter().zip(&rows) {
        let m = plan.decode(payload).unwrap();
        let col = |name: &str| &row[header.iter().position(|h| h == name).unwrap()];
        assert!(same(col("timestamp"), m.timestamp as f64));
        assert!(same(col("counter"), m.counter.into()));
        assert!(same(col("esc_count"), m.esc_count.into()));
        assert!(same(col("esc_connectiontype"), m.esc_connectiontype.into()));
        for (i, e) in m.esc.iter().enumerate() {
            let c = |f: &str| col(&format!("esc[{i}].{f}"));
            assert!(same(c("timestamp"), e.timestamp as f64));
            assert!(same(c("esc_errorcount"), e.esc_errorcount.into()));
            assert!(same(c("esc_rpm"), e.esc_rpm.into()));
            assert!(
                same(c("esc_voltage"), e.esc_voltage.into()),
                "{} {}",
                c("esc_voltage"),
                e.esc_voltage
            );
            assert!(same(c("esc_current"), e.esc_current.into()));
            assert!(same(c("esc_temperature"), e.esc_temperature.into()));
            assert!(same(c("esc_setpoint"), e.esc_setpoint.into()));
            assert!(same(c("esc_setpoint_raw"), e.esc_setpoint_raw.into()));
            assert!(same(c("esc_address"), e.esc_address.into()));
            assert!(same(c("esc_version"), e.esc_version.into()));
            assert!(same(c("esc_state"), e.esc_state.into()));
            assert!(same(c("esc_vendor"), e.esc_vendor.into()));
        }
        // The binding generated from the log decodes the same values.
        let generated = Plan::<esc_log::EscStatus>::new(&layout)
            .unwrap()
            .decode(payload)
            .unwrap();
        assert_eq!(generated.timestamp, m.timestamp);
        assert_eq!(generated.esc[3].esc_rpm, m.esc[3].esc_rpm);
        assert_eq!(generated.esc[1].esc_voltage, m.esc[1].esc_voltage);
        // Encoding gives back the payload (padding bytes aside: PX4 leaves them as
        // they were in memory, we write zeros).
        assert_eq!(m.encode().len(), payload.len());
        assert_eq!(plan.decode(&m.encode()).unwrap(), m);
    }
    // The derive produces the log's exact format strings, nested one first.
    for format in EscStatus::schema().formats() {
        assert!(records.formats.contains(format), "{format}");
    }
    assert_eq!(EscStatus::schema().formats()[0].name, "esc_report");
}

#[test]
fn telemetry_status_exact_and_mapped() {
    let Some(corpus) = corpus() else { return };
    let bytes = std::fs::read(corpus.join("files/esc_status_log.ulg")).unwrap();
    let records = walk(&bytes);
    let (layout, payloads) = records.topic("telemetry_status", 0);
    let full = Plan::<TelemetryStatus>::new(&layout).unwrap();
    assert_eq!(full.kind(), PlanKind::Exact);
    let heartbeat = Plan::<Heartbeat>::new(&layout).unwrap();
    assert_eq!(heartbeat.kind(), PlanKind::Mapped);
    let (header, rows) = expected_rows(&corpus, "esc_status_log", "telemetry_status_0");
    assert_eq!(rows.len(), payloads.len());
    for (payload, row) in payloads.iter().zip(&rows) {
        let col = |name: &str| &row[header.iter().position(|h| h == name).unwrap()];
        let t = full.decode(payload).unwrap();
        let h = heartbeat.decode(payload).unwrap();
        assert_eq!(
            (h.heard_at, h.receive_rate, h.timestamp),
            (t.heartbeat_time, t.rate_rx, t.timestamp)
        );
        assert!(same(col("heartbeat_time"), t.heartbeat_time as f64));
        assert!(same(col("rate_rx"), t.rate_rx.into()));
        assert!(same(col("type"), t.r#type.into()));
        assert!(same(col("mavlink_v2"), u8::from(t.mavlink_v2).into()));
        assert!(same(col("streams"), t.streams.into()));
        // Trailing padding present or left out.
        let short = &payload[..layout.min_size()];
        assert_eq!(full.decode(short).unwrap(), t);
        assert_eq!(heartbeat.decode(short).unwrap(), h);
        assert_eq!(t.encode(), short);
    }
}

#[test]
fn char_arrays_decode_as_text() {
    #[derive(ULogMessage, Debug)]
    struct Named {
        id: u8,
        name: CharArray<6>,
        #[ulog(char)]
        raw: [u8; 3],
    }
    let format = Format::parse("named:uint8_t id;char[6] name;char[3] raw;").unwrap();
    assert_eq!(Named::schema().format(), &format);
    let layout = Layout::resolve("named", &[format][..]).unwrap();
    let n = Plan::<Named>::new(&layout)
        .unwrap()
        .decode(b"\x07PX4\0\0\0abc")
        .unwrap();
    assert_eq!((n.id, n.name.as_str(), &n.raw), (7, Ok("PX4"), b"abc"));
}
