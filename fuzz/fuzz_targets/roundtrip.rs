//! Writer → reader on arbitrary values: every value written reads back with the
//! same bits.
#![no_main]

use arbitrary::Arbitrary;
use libfuzzer_sys::fuzz_target;
use ulog_core::read::LogLevel;
use ulog_core::typed::CharArray;
use ulog_core::write::WriterOptions;
use ulog_core::{LogWriter, ULog, ULogMessage};

#[derive(ULogMessage, Debug, Clone, PartialEq)]
struct Nested {
    v: [i32; 2],
    _padding0: [u8; 4],
}

#[derive(ULogMessage, Debug, Clone, PartialEq)]
struct Row {
    timestamp: u64,
    a: i8,
    b: u16,
    c: i64,
    f: u32,
    d: u64,
    e: bool,
    name: CharArray<5>,
    nested: [Nested; 2],
    _padding0: [u8; 3],
}

/// The fields of one row of `Row`, as arbitrary values.
type RowValues = (u64, i8, u16, i64, u32, u64, bool, [u8; 5], [i32; 4], u8);

#[derive(Arbitrary, Debug)]
struct Input {
    rows: Vec<RowValues>,
    text: String,
    sync: Option<u16>,
}

fuzz_target!(|input: Input| {
    let options = WriterOptions {
        sync_interval: input.sync.map(u64::from),
    };
    let mut w = LogWriter::with_options(Vec::new(), 0, options).unwrap();
    let handles = [
        w.subscribe::<Row>(0).unwrap(),
        w.subscribe::<Row>(1).unwrap(),
    ];
    let mut data = w.start_data().unwrap();
    let rows: Vec<(Row, u8)> = input
        .rows
        .iter()
        .map(|&(timestamp, a, b, c, f, d, e, name, v, inst)| {
            (
                Row {
                    timestamp,
                    a,
                    b,
                    c,
                    f,
                    d,
                    e,
                    name: CharArray::from_bytes(name),
                    nested: [
                        Nested {
                            v: [v[0], v[1]],
                            _padding0: [0; 4],
                        },
                        Nested {
                            v: [v[2], v[3]],
                            _padding0: [0; 4],
                        },
                    ],
                    _padding0: [0; 3],
                },
                inst % 2,
            )
        })
        .collect();
    for (r, inst) in &rows {
        data.write(&handles[*inst as usize], r).unwrap();
    }
    let logged = data.log(LogLevel::Info, 0, &input.text).is_ok();
    let bytes = data.finish().unwrap();
    let log = ULog::parse(&bytes).unwrap();
    assert!(log.findings().is_empty());
    for inst in 0..2u8 {
        let expect: Vec<&Row> = rows
            .iter()
            .filter(|(_, i)| *i == inst)
            .map(|(r, _)| r)
            .collect();
        let got: Vec<Row> = log
            .read::<Row>(inst)
            .unwrap()
            .iter()
            .map(|r| r.unwrap())
            .collect();
        assert_eq!(got.len(), expect.len());
        for (g, e) in got.iter().zip(expect) {
            assert_eq!(g, e);
        }
    }
    if logged {
        assert_eq!(
            log.logged_messages()[0].text.as_bytes(),
            input.text.as_bytes()
        );
    }
});
