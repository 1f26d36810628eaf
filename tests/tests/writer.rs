//! The writer: byte-exact pass-through of every corpus log, typed write → read round
//! trips (property tests), crash safety, appended crash data, section rules.

use proptest::prelude::*;
use ulog_core::read::{FindingKind, LogLevel};
use ulog_core::typed::{CharArray, TypedErrorKind};
use ulog_core::write::{DefaultTypes, WriteErrorKind, WriterOptions};
use ulog_core::{append, copy_log, LogWriter, ULog, ULogMessage, Value};
use ulog_tests::{corpus_files, stem};

#[test]
fn every_corpus_log_round_trips_byte_for_byte() {
    for path in corpus_files() {
        let bytes = std::fs::read(&path).unwrap();
        let mut out = Vec::new();
        let n = copy_log(&bytes, &mut out).unwrap();
        assert!(n > 0);
        assert!(out == bytes, "{}: output differs", stem(&path));
    }
}

#[derive(ULogMessage, Debug, Clone, PartialEq)]
struct Inner {
    a: i16,
    b: [u8; 3],
    _padding0: [u8; 1],
}

#[derive(ULogMessage, Debug, Clone, PartialEq)]
struct Everything {
    timestamp: u64,
    i8_: i8,
    u8_: u8,
    i16_: i16,
    u16_: u16,
    i32_: i32,
    u32_: u32,
    i64_: i64,
    u64_: u64,
    f32_: f32,
    f64_: f64,
    flag: bool,
    name: CharArray<6>,
    floats: [f32; 3],
    words: [u16; 2],
    flags: [bool; 2],
    inner: Inner,
    inners: [Inner; 2],
    _padding0: [u8; 5],
}

fn arb_inner() -> impl Strategy<Value = Inner> {
    (any::<i16>(), any::<[u8; 3]>()).prop_map(|(a, b)| Inner {
        a,
        b,
        _padding0: [0],
    })
}

fn arb_f32() -> impl Strategy<Value = f32> {
    any::<u32>().prop_map(f32::from_bits)
}

prop_compose! {
    fn arb_everything()(timestamp in any::<u64>(), ints in any::<(i8, u8, i16, u16, i32, u32, i64, u64)>(),
                        f32_ in arb_f32(), f64_ in any::<u64>().prop_map(f64::from_bits), flag in any::<bool>(),
                        name in any::<[u8; 6]>(), floats in [arb_f32(), arb_f32(), arb_f32()], words in any::<[u16; 2]>(),
                        flags in any::<[bool; 2]>(), inner in arb_inner(), inners in [arb_inner(), arb_inner()]) -> Everything {
        let (i8_, u8_, i16_, u16_, i32_, u32_, i64_, u64_) = ints;
        Everything { timestamp, i8_, u8_, i16_, u16_, i32_, u32_, i64_, u64_, f32_, f64_, flag,
                     name: CharArray::from_bytes(name), floats, words, flags, inner, inners, _padding0: [0; 5] }
    }
}

/// Equality that treats NaNs of the same bits as equal (a round trip keeps bits).
fn same(a: &Everything, b: &Everything) -> bool {
    a.f32_.to_bits() == b.f32_.to_bits()
        && a.f64_.to_bits() == b.f64_.to_bits()
        && a.floats
            .iter()
            .zip(&b.floats)
            .all(|(x, y)| x.to_bits() == y.to_bits())
        && Everything {
            f32_: 0.0,
            f64_: 0.0,
            floats: [0.0; 3],
            ..a.clone()
        } == Everything {
            f32_: 0.0,
            f64_: 0.0,
            floats: [0.0; 3],
            ..b.clone()
        }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    #[test]
    fn typed_values_round_trip(rows in proptest::collection::vec((arb_everything(), 0u8..3), 1..40)) {
        let mut w = LogWriter::with_options(Vec::new(), 7, WriterOptions { sync_interval: Some(300) }).unwrap();
        let handles = [w.subscribe::<Everything>(0).unwrap(), w.subscribe::<Everything>(1).unwrap(), w.subscribe::<Everything>(2).unwrap()];
        let mut data = w.start_data().unwrap();
        for (row, instance) in &rows {
            data.write(&handles[*instance as usize], row).unwrap();
        }
        let bytes = data.finish().unwrap();
        let log = ULog::parse(&bytes).unwrap();
        prop_assert!(log.findings().is_empty(), "{:?}", log.findings());
        for instance in 0..3u8 {
            let expect: Vec<&Everything> = rows.iter().filter(|(_, i)| *i == instance).map(|(r, _)| r).collect();
            let got: Vec<Everything> = log.read::<Everything>(instance).unwrap().iter().map(|r| r.unwrap()).collect();
            prop_assert_eq!(got.len(), expect.len());
            for (g, e) in got.iter().zip(expect) {
                prop_assert!(same(g, e), "{:?} != {:?}", g, e);
            }
            // Trailing padding is left out, as PX4 does.
            let t = log.topic("everything", instance).unwrap();
            for p in t.payloads() {
                prop_assert_eq!(p.len(), t.layout().unwrap().min_size());
            }
        }
    }
}

#[test]
fn definitions_messages_and_data_section_messages_read_back() {
    let mut w = LogWriter::new(Vec::new(), 1000).unwrap();
    w.info("sys_name", "PX4").unwrap();
    w.info("ver_sw_release", &0x010e_03ffu32).unwrap();
    w.info("xyz", &[1.5f32, 2.5, 3.5]).unwrap();
    w.multi_info("boot", "part one, ", false).unwrap();
    w.multi_info("boot", "part two", true).unwrap();
    w.param("MAV_TYPE", 2i32).unwrap();
    w.param("MPC_XY_VEL_MAX", 12.0f32).unwrap();
    w.default_param("MPC_XY_VEL_MAX", 10.0f32, DefaultTypes::SYSTEM)
        .unwrap();
    w.format("raw_topic:uint64_t timestamp;uint8_t v;uint8_t[7] _padding0;")
        .unwrap();
    // The same format again (spacing aside) is fine; other fields are an error.
    w.format("raw_topic:uint64_t  timestamp;uint8_t v;uint8_t[7] _padding0;")
        .unwrap();
    let e = w
        .format("raw_topic:uint64_t timestamp;uint16_t v;")
        .err()
        .unwrap();
    assert!(
        matches!(e.kind(), WriteErrorKind::FormatConflict { .. }),
        "{e}"
    );
    let raw = w.subscribe_raw("raw_topic", 0).unwrap();
    let mut data = w.start_data().unwrap();
    data.write_raw(&raw, &[&5000u64.to_le_bytes()[..], &[9]].concat())
        .unwrap();
    data.write_raw(&raw, &[&6000u64.to_le_bytes()[..], &[10], &[0; 7]].concat())
        .unwrap();
    let e = data.write_raw(&raw, &[1, 2, 3]).unwrap_err();
    assert!(matches!(e.kind(), WriteErrorKind::PayloadSize { .. }));
    data.param("MPC_XY_VEL_MAX", 8.0f32).unwrap();
    data.log(LogLevel::Warning, 6000, "low battery").unwrap();
    data.tagged_log(LogLevel::Info, 3, 6500, "tagged").unwrap();
    data.dropout(25).unwrap();
    data.sync().unwrap();
    let e = data.param("bad name", 1i32).unwrap_err();
    assert!(matches!(e.kind(), WriteErrorKind::InvalidName(_)));
    let e = data.subscribe_raw("never_declared", 0).unwrap_err();
    assert!(matches!(e.kind(), WriteErrorKind::FormatNotDeclared { .. }));
    let too_long = "x".repeat(70_000);
    let e = data.log(LogLevel::Info, 0, &too_long).unwrap_err();
    assert!(matches!(
        e.kind(),
        WriteErrorKind::MessageTooLarge { msg_type: b'L', .. }
    ));
    let bytes = data.finish().unwrap();

    let log = ULog::parse(&bytes).unwrap();
    assert!(log.findings().is_empty(), "{:?}", log.findings());
    assert!(log.flag_bits().unwrap().has_default_parameters());
    assert_eq!(log.info_value("sys_name").unwrap().to_string(), "PX4");
    assert_eq!(
        log.release_version("ver_sw_release").unwrap().to_string(),
        "v1.14.3"
    );
    assert_eq!(
        log.info_value("xyz").unwrap().to_string(),
        "[1.5, 2.5, 3.5]"
    );
    assert_eq!(log.multi_info()[0].entries[0].len(), 2);
    assert_eq!(log.initial_param("MAV_TYPE"), Some(Value::I32(2)));
    assert_eq!(log.param_changes()[0].kv.value(), Value::F32(8.0));
    assert_eq!(log.param_changes()[0].timestamp, 6000);
    assert_eq!(log.default_params()[0].default_types, 1);
    let t = log.topic("raw_topic", 0).unwrap();
    assert_eq!(t.len(), 2);
    let msgs = log.logged_messages();
    assert_eq!(
        (msgs[0].level(), msgs[0].text.as_str()),
        (Some(LogLevel::Warning), Some("low battery"))
    );
    assert_eq!(msgs[1].tag, Some(3));
    assert_eq!(log.dropouts()[0].duration_ms, 25);
    assert_eq!(log.sync_count(), 1);
}

#[derive(ULogMessage, Debug, Clone, Copy, PartialEq)]
struct VehicleLocalPosition {
    timestamp: u64,
    x: f32,
    y: f32,
    z: f32,
}

#[test]
fn a_crash_at_any_byte_leaves_the_complete_messages_readable() {
    let mut w = LogWriter::with_options(
        Vec::new(),
        0,
        WriterOptions {
            sync_interval: Some(200),
        },
    )
    .unwrap();
    let h = w.subscribe::<VehicleLocalPosition>(0).unwrap();
    let mut data = w.start_data().unwrap();
    let rows: Vec<VehicleLocalPosition> = (0..60u64)
        .map(|i| VehicleLocalPosition {
            timestamp: i * 1000,
            x: i as f32,
            y: -(i as f32),
            z: 0.5,
        })
        .collect();
    for r in &rows {
        data.write(&h, r).unwrap();
        data.flush().unwrap();
    }
    let bytes = data.finish().unwrap();
    let full = ULog::parse(&bytes).unwrap();
    assert!(full.sync_count() > 0);
    let t = full.topic("vehicle_local_position", 0).unwrap();
    let ends: Vec<u64> = t
        .message_offsets()
        .iter()
        .zip(t.payloads())
        .map(|(o, p)| o + 5 + p.len() as u64)
        .collect();
    for cut in 16..=bytes.len() {
        let log = ULog::parse(&bytes[..cut]).unwrap();
        let complete = ends.iter().filter(|&&e| e as usize <= cut).count();
        let got: Vec<_> = match log.read::<VehicleLocalPosition>(0) {
            Ok(rows) => rows.iter().map(|r| r.unwrap()).collect(),
            Err(e) => {
                assert!(matches!(e.kind(), TypedErrorKind::NotFound { .. }));
                Vec::new()
            }
        };
        assert_eq!(got[..], rows[..complete], "cut at {cut}");
        assert!(
            !log.findings()
                .iter()
                .any(|f| matches!(f.kind, FindingKind::Corrupt(_))),
            "cut at {cut}"
        );
    }
}

#[derive(ULogMessage, Debug, Clone, Copy, PartialEq)]
struct HardfaultInfo {
    timestamp: u64,
    code: u32,
}

#[test]
fn crash_data_is_appended_as_the_spec_describes() {
    let mut w = LogWriter::new(Vec::new(), 0).unwrap();
    w.subscribe::<HardfaultInfo>(0).unwrap(); // declares the format up front
    let pos = w.subscribe::<VehicleLocalPosition>(0).unwrap();
    let mut data = w.start_data().unwrap();
    for i in 0..5u64 {
        data.write(
            &pos,
            &VehicleLocalPosition {
                timestamp: i,
                x: 1.0,
                y: 2.0,
                z: 3.0,
            },
        )
        .unwrap();
    }
    let mut bytes = data.finish().unwrap();
    // The log was cut inside a message.
    bytes.extend_from_slice(&[30, 0, b'D', 1, 0, 9, 9]);
    for round in 0..3u64 {
        let len = bytes.len() as u64;
        let mut file = std::io::Cursor::new(std::mem::take(&mut bytes));
        let mut app = append(&mut file, WriterOptions::default()).unwrap();
        let h = app.continue_topic::<VehicleLocalPosition>(0).unwrap();
        app.writer()
            .write(
                &h,
                &VehicleLocalPosition {
                    timestamp: 100 + round,
                    x: 0.0,
                    y: 0.0,
                    z: 0.0,
                },
            )
            .unwrap();
        let crash = app.writer().subscribe::<HardfaultInfo>(0).unwrap();
        app.writer()
            .write(
                &crash,
                &HardfaultInfo {
                    timestamp: 200 + round,
                    code: 0xdead,
                },
            )
            .unwrap();
        app.finish().unwrap();
        bytes = file.into_inner();
        let log = ULog::parse(&bytes).unwrap();
        assert!(log.flag_bits().unwrap().has_data_appended());
        assert_eq!(
            log.flag_bits().unwrap().appended_offsets[round as usize],
            len
        );
        assert_eq!(log.appended_sections().len(), round as usize + 1);
        let ts: Vec<u64> = log
            .read::<VehicleLocalPosition>(0)
            .unwrap()
            .iter()
            .map(|r| r.unwrap().timestamp)
            .collect();
        let mut expect: Vec<u64> = (0..5).collect();
        expect.extend((0..=round).map(|r| 100 + r));
        assert_eq!(ts, expect, "round {round}");
        let crashes: usize = log
            .read_instances::<HardfaultInfo>()
            .unwrap()
            .map(|r| r.unwrap().len())
            .sum();
        assert_eq!(crashes, round as usize + 1);
    }
    let mut file = std::io::Cursor::new(bytes);
    let e = append(&mut file, WriterOptions::default()).err().unwrap();
    assert_eq!(*e.kind(), WriteErrorKind::NoFreeAppendedOffset);
    // A version 0 log has no flag bits to record the offset in.
    let mut v0 = ulog_core::testing::LogBuilder::new(0, 0);
    v0.format("t:uint64_t timestamp;");
    let e = append(
        std::io::Cursor::new(v0.into_bytes()),
        WriterOptions::default(),
    )
    .err()
    .unwrap();
    assert_eq!(*e.kind(), WriteErrorKind::NoFlagBits);
}

/// Found by the roundtrip fuzz target: text with a NUL was written, then read as
/// corruption and dropped. Text a reader would drop is refused when written, and
/// the text readers accept reads back.
#[test]
fn logged_text_readers_would_drop_is_refused_and_the_rest_reads_back() {
    let mut w = LogWriter::new(Vec::new(), 0).unwrap();
    w.subscribe::<Everything>(0).unwrap();
    let mut data = w.start_data().unwrap();
    let before = data.position();
    let e = data.log(LogLevel::Info, 1, "ok\0no").unwrap_err();
    assert_eq!(
        *e.kind(),
        WriteErrorKind::ControlCharacter { at: 2, byte: 0 }
    );
    assert_eq!(e.position(), Some(before));
    assert!(e.to_string().contains("0x00 at byte 2"), "{e}");
    let e = data
        .tagged_log(LogLevel::Info, 3, 1, "bell\x07")
        .unwrap_err();
    assert_eq!(
        *e.kind(),
        WriteErrorKind::ControlCharacter { at: 4, byte: 7 }
    );
    assert_eq!(data.position(), before, "nothing written");
    let kept = "tab\t, lines\r\n, \x1b[1mescape\x1b[0m, ünïcode";
    data.log(LogLevel::Warning, 2, kept).unwrap();
    data.tagged_log(LogLevel::Error, 4, 3, kept).unwrap();
    let bytes = data.finish().unwrap();
    let log = ULog::parse(&bytes).unwrap();
    assert!(log.findings().is_empty(), "{:?}", log.findings());
    let texts: Vec<&str> = log
        .logged_messages()
        .iter()
        .map(|l| l.text.as_str().unwrap())
        .collect();
    assert_eq!(texts, [kept, kept]);
}
