//! The whole-file reader on arbitrary bytes: parse, then touch every topic's every
//! column of every row, read its numbers in blocks (equal, bit for bit, to the
//! one-field readers' values), and re-frame the messages.
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
            let layout = t.layout().expect("columns came from it");
            let numbers = ulog_core::NumericRow::of(layout);
            let payloads: Vec<&[u8]> = t.payloads().take(64).collect();
            let mut block = ulog_core::NumericBlock::with_capacity(layout, 5);
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
