//! The whole-file reader on arbitrary bytes: parse, then touch every topic's every
//! column of every row, read its numbers in blocks (equal, bit for bit, to the
//! one-field readers' values), and re-frame the messages. Also: `scan_topics` with the
//! default options hands out exactly the decoded records and errors of `scan_topics`
//! with `raw_others`, with the same summary (the other subscriptions skipped, not
//! lost).
#![no_main]

use libfuzzer_sys::fuzz_target;
use ulog_core::columns::{NumericBlock, NumericRow};
use ulog_core::{ScanOptions, ULogMessage, ULogTopics};

#[derive(ULogMessage, Debug)]
struct VehicleAttitude {
    timestamp: u64,
    q: [f32; 4],
}

/// Fits no PX4 `esc_status`: a mismatch, reported once.
#[derive(ULogMessage, Debug)]
struct EscStatus {
    timestamp: u64,
    esc_count: u64,
}

#[derive(ULogTopics, Debug)]
enum Topics {
    Attitude(VehicleAttitude),
    Esc(EscStatus),
}

impl Topics {
    /// What a record is compared by: its variant, timestamp and values.
    fn key(&self) -> String {
        match self {
            Topics::Attitude(a) => format!("attitude {} {:?}", a.timestamp, a.q.map(f32::to_bits)),
            Topics::Esc(e) => format!("esc {} {}", e.timestamp, e.esc_count),
        }
    }
}

/// `scan_topics` with `raw_others` and with the default options on `data`: the
/// decoded records and errors of the one are those of the other, and so are the
/// summaries.
fn only_is_scan_topics_without_raw(data: &[u8]) {
    let mut full = Vec::new();
    let raw_others = ScanOptions::default().raw_others(true);
    let a = ulog_core::scan_topics::<Topics>(data, &raw_others, |r| match r {
        Ok(r) => {
            if let Some(message) = r.message {
                full.push(format!("{} {}", r.topic.multi_id(), message.key()))
            }
        }
        Err(e) => full.push(format!("{e:?}")),
    });
    let mut only = Vec::new();
    let b = ulog_core::scan_topics::<Topics>(data, &ScanOptions::default(), |r| match r {
        Ok(m) => {
            let message = m
                .message
                .expect("decoded: no raw records without raw_others");
            only.push(format!("{} {}", m.topic.multi_id(), message.key()))
        }
        Err(e) => only.push(format!("{e:?}")),
    });
    assert_eq!(a.is_ok(), b.is_ok());
    if let (Ok(a), Ok(b)) = (a, b) {
        assert_eq!(a, b);
        assert_eq!(full, only);
    }
}

fuzz_target!(|data: &[u8]| {
    only_is_scan_topics_without_raw(data);
    let Ok(log) = ulog_core::ULog::parse(data) else {
        return;
    };
    for t in log.topics() {
        let _ = t.timestamps();
        if let Ok(cols) = t.fields() {
            for p in t.payloads().take(64) {
                for c in &cols {
                    let _ = c.read(p).map(|v| v.to_string());
                }
            }
            let layout = t.layout().expect("columns came from it");
            let numbers = NumericRow::of(layout);
            let payloads: Vec<&[u8]> = t.payloads().take(64).collect();
            let mut block = NumericBlock::with_capacity(layout, 5);
            let mut values = Vec::new();
            for chunk in payloads.chunks(5) {
                for p in chunk {
                    block.push(p);
                }
                let rows = block.decode();
                numbers.read_rows(chunk, &mut values);
                assert_eq!(rows.values().len(), values.len());
                for (i, p) in chunk.iter().enumerate() {
                    for (k, c) in numbers.columns().iter().enumerate() {
                        let want = c.read_f64(p).unwrap_or(f64::NAN).to_bits();
                        assert_eq!(rows.row(i)[k].to_bits(), want, "{}", c.path());
                        assert_eq!(values[i * numbers.width() + k].to_bits(), want);
                    }
                }
            }
        }
    }
    for kv in log.info().iter().chain(log.initial_params()) {
        let _ = kv.value().to_string();
    }
    for f in log.findings() {
        let _ = f.to_string();
    }
    assert_eq!(log.messages().count() as u64, log.message_count());
});
