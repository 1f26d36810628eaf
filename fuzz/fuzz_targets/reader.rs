//! The whole-file reader on arbitrary bytes: parse, then touch every topic's every
//! column of every row, and re-frame the messages.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(log) = ulog_core::ULog::parse(data) else {
        return;
    };
    for t in log.topics() {
        let _ = t.timestamps();
        if let Ok(cols) = t.columns() {
            for p in t.payloads().take(64) {
                for c in &cols {
                    let _ = c.read(p).map(|v| v.to_string());
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
