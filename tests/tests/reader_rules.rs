//! Each rule of the reader, on bytes built for it.

use ulog_core::read::{Corruption, FindingKind, LogLevel, ReadErrorKind};
use ulog_core::stream::{Progress, PushReader};
use ulog_core::testing::LogBuilder;
use ulog_core::{LookupError, Message, ULog, Value};

/// A version-1 log with one topic `t:uint64_t timestamp;uint32_t v;uint8_t[4] _padding0;`.
fn base() -> LogBuilder {
    let mut b = LogBuilder::new(1, 100);
    b.flag_bits([0; 8], [0; 8], [0; 3]);
    b.format("t:uint64_t timestamp;uint32_t v;uint8_t[4] _padding0;");
    b.subscribe(0, 0, "t");
    b
}

fn t_payload(ts: u64, v: u32) -> Vec<u8> {
    let mut p = ts.to_le_bytes().to_vec();
    p.extend_from_slice(&v.to_le_bytes());
    p
}

fn values(log: &ULog<'_>, topic: &str, multi_id: u8, path: &str) -> Vec<String> {
    let t = log.topic(topic, multi_id).unwrap();
    let f = t.field(path).unwrap();
    t.payloads()
        .map(|p| f.read(p).unwrap().to_string())
        .collect()
}

#[test]
fn header_errors_say_what_was_found() {
    let kind = |b: &[u8]| ULog::parse(b).unwrap_err().kind().clone();
    assert_eq!(kind(b""), ReadErrorKind::Empty);
    assert_eq!(
        kind(&[0u8; 4096]),
        ReadErrorKind::NotULog {
            found: "zero bytes where the header should be".into()
        }
    );
    assert_eq!(
        kind(b"\x1f\x8b\x08\0\0\0\0\0\0\0\0\0\0\0\0\0\0"),
        ReadErrorKind::NotULog {
            found: "a gzip file".into()
        }
    );
    assert!(
        matches!(kind(b"hello world, this is text"), ReadErrorKind::NotULog { found } if found.starts_with("text"))
    );
    assert_eq!(
        kind(&ulog_core::format::definitions::MAGIC[..5]),
        ReadErrorKind::TruncatedHeader { len: 5 }
    );
    let e = ULog::parse(b"").unwrap_err();
    assert!(e.to_string().contains("empty"), "{e}");
}

#[test]
fn versions_0_1_and_newer_are_read() {
    for version in [0u8, 1, 7] {
        let mut b = LogBuilder::new(version, 5);
        b.format("t:uint64_t timestamp;");
        b.subscribe(0, 0, "t");
        b.data(0, &9u64.to_le_bytes());
        let log = ULog::parse(b.bytes()).unwrap();
        assert_eq!(log.version(), version);
        assert_eq!(log.start_timestamp(), 5);
        assert_eq!(log.topic("t", 0).unwrap().len(), 1);
        let newer = log
            .findings()
            .iter()
            .any(|f| f.kind == FindingKind::NewerVersion(version));
        assert_eq!(newer, version > 1);
    }
}

#[test]
fn every_message_type_is_read_and_unknown_ones_are_kept() {
    let mut b = LogBuilder::new(1, 100);
    b.flag_bits([1, 0, 0, 0, 0, 0, 0, 0], [0; 8], [0; 3]);
    b.format("t:uint64_t timestamp;float x;");
    b.info_str("sys_name", "PX4");
    b.multi_info(false, "char[3] m", b"abc");
    b.param("int32_t P1", &7i32.to_le_bytes());
    b.default_param(2, "int32_t P1", &3i32.to_le_bytes());
    b.raw(b'X', b"future message");
    b.subscribe(0, 0, "t");
    b.data(
        0,
        &[&5u64.to_le_bytes()[..], &1.5f32.to_le_bytes()].concat(),
    );
    b.log(b'3', 6, "error text");
    b.tagged_log(b'4', 9, 7, "tagged");
    b.sync();
    b.dropout(20);
    b.unsubscribe(0);
    let bytes = b.into_bytes();
    let log = ULog::parse(&bytes).unwrap();
    let types: Vec<u8> = log
        .messages()
        .map(|m| m.unwrap().message.msg_type())
        .collect();
    assert_eq!(types, b"BFIMPQXADLCSOR");
    assert_eq!(log.unknown_messages().len(), 1);
    assert_eq!(log.unknown_messages()[0].msg_type, b'X');
    assert_eq!(log.unknown_messages()[0].payload, b"future message");
    assert!(log
        .findings()
        .iter()
        .any(|f| f.kind == FindingKind::UnknownMessageType(b'X')));
    assert!(log.flag_bits().unwrap().has_default_parameters());
    assert_eq!(log.info_value("sys_name").unwrap().to_string(), "PX4");
    assert_eq!(log.initial_param("P1"), Some(Value::I32(7)));
    assert_eq!(log.default_params()[0].default_types, 2);
    let logs = log.logged_messages();
    assert_eq!(
        (logs[0].level(), logs[0].tag, logs[0].timestamp),
        (Some(LogLevel::Error), None, 6)
    );
    assert_eq!(
        (logs[1].level(), logs[1].tag),
        (Some(LogLevel::Warning), Some(9))
    );
    assert_eq!(logs[1].text.as_str(), Some("tagged"));
    assert_eq!(log.sync_count(), 1);
    // A dropout's time is the largest data timestamp so far, the header's start time
    // if none is larger (as pyulog reports it).
    assert_eq!(
        (log.dropouts()[0].duration_ms, log.dropouts()[0].timestamp),
        (20, 100)
    );
    assert!(!log.has_damage());
}

#[test]
fn flag_bits_of_any_length_and_unknown_bits() {
    // A longer flag bits message (a future spec's): extra bytes ignored.
    let mut b = LogBuilder::new(1, 0);
    let mut p = vec![0u8; 48];
    p[0] = 1;
    b.raw(b'B', &p);
    b.format("t:uint64_t timestamp;");
    let log = ULog::parse(b.bytes()).unwrap();
    assert!(log.flag_bits().unwrap().has_default_parameters());
    assert!(log
        .findings()
        .iter()
        .any(|f| f.kind == FindingKind::LongFlagBits(48)));
    assert_eq!(log.formats().len(), 1);

    // Unknown incompat bits in any byte refuse the log, naming byte and bits.
    for byte in 0..8 {
        let mut incompat = [0u8; 8];
        incompat[byte] = if byte == 0 { 0b100 } else { 0x80 };
        let mut b = LogBuilder::new(1, 0);
        b.flag_bits([0; 8], incompat, [0; 3]);
        let e = ULog::parse(b.bytes()).unwrap_err();
        assert_eq!(
            *e.kind(),
            ReadErrorKind::UnknownIncompatFlags {
                byte,
                bits: incompat[byte]
            }
        );
        assert_eq!(e.position(), Some(16 + 3 + 8 + byte as u64));
        assert!(e.to_string().contains("refused"));
        // The incremental reader refuses it too.
        let mut inc = PushReader::new();
        inc.push(b.bytes());
        inc.finish();
        assert!(inc.advance().is_err());
    }
    // Unknown compat bits are only a finding.
    let mut b = LogBuilder::new(1, 0);
    b.flag_bits([0, 0, 4, 0, 0, 0, 0, 0], [0; 8], [0; 3]);
    let log = ULog::parse(b.bytes()).unwrap();
    assert!(log
        .findings()
        .iter()
        .any(|f| f.kind == FindingKind::UnknownCompatFlags { byte: 2, bits: 4 }));
}

#[test]
fn appended_data_at_three_offsets_keeps_earlier_subscriptions() {
    let mut b = LogBuilder::new(1, 0);
    b.flag_bits([0; 8], [1, 0, 0, 0, 0, 0, 0, 0], [0; 3]);
    let flag_at = 16 + 3;
    b.format("t:uint64_t timestamp;uint32_t v;uint8_t[4] _padding0;");
    b.format("crash:uint64_t timestamp;uint8_t code;");
    b.subscribe(0, 0, "t");
    b.data(0, &t_payload(1, 1));
    // The log was cut inside a message...
    let cut = t_payload(2, 2);
    b.garbage(&[14, 0, b'D', 0, 0]);
    b.garbage(&cut[..5]);
    let first = b.bytes().len() as u64;
    // ... then data was appended: a topic subscribed before, and a new one.
    b.data(0, &t_payload(3, 3));
    b.subscribe(0, 1, "crash");
    b.data(1, &[&4u64.to_le_bytes()[..], &[9]].concat());
    b.garbage(&[40, 0]); // cut again, inside a header
    let second = b.bytes().len() as u64;
    b.data(0, &t_payload(5, 5));
    let third = b.bytes().len() as u64;
    b.data(1, &[&6u64.to_le_bytes()[..], &[8]].concat());
    let mut bytes = b.into_bytes();
    for (i, o) in [first, second, third].iter().enumerate() {
        let at = flag_at + 16 + 8 * i;
        bytes[at..at + 8].copy_from_slice(&o.to_le_bytes());
    }
    let log = ULog::parse(&bytes).unwrap();
    assert_eq!(log.appended_sections(), &[first, second, third]);
    assert_eq!(values(&log, "t", 0, "v"), ["1", "3", "5"]);
    assert_eq!(values(&log, "crash", 0, "code"), ["9", "8"]);
    let partial: Vec<_> = log
        .findings()
        .iter()
        .filter(|f| f.kind == FindingKind::PartialBeforeAppended)
        .map(|f| (f.offset, f.len))
        .collect();
    assert_eq!(partial, [(first - 10, 10), (second - 2, 2)]);
    // Offsets that point past the end, or before the data, are findings.
    let mut bad = bytes.clone();
    let at = flag_at + 16 + 16;
    bad[at..at + 8].copy_from_slice(&(1u64 << 40).to_le_bytes());
    let log = ULog::parse(&bad).unwrap();
    assert!(log
        .findings()
        .iter()
        .any(|f| f.kind == FindingKind::InvalidAppendedOffset(1 << 40)));
    assert_eq!(values(&log, "t", 0, "v"), ["1", "3", "5"]);
}

#[test]
fn formats_nest_before_definition_and_bad_ones_fail_alone() {
    let mut b = LogBuilder::new(1, 0);
    b.format("outer/a-b:uint64_t timestamp;inner[2] in;");
    b.format("inner:uint16_t x;deeper d;");
    b.format("deeper:int8_t[3] y;uint8_t _padding0;");
    b.format("cyc_a:uint64_t timestamp;cyc_b b;");
    b.format("cyc_b:cyc_a a;");
    b.format("broken:uint64_t timestamp;float[x] q;");
    b.format("ok:uint64_t timestamp;");
    b.format("ok:uint64_t timestamp;"); // duplicate, identical: tolerated
    b.subscribe(0, 0, "outer/a-b");
    b.subscribe(0, 1, "cyc_a");
    b.subscribe(0, 2, "ok");
    let mut p = 1u64.to_le_bytes().to_vec();
    for i in 0..2u16 {
        p.extend_from_slice(&(100 + i).to_le_bytes());
        p.extend_from_slice(&[1, 2, 3, 0]);
    }
    b.data(0, &p);
    b.data(1, &[0; 8]);
    b.data(2, &[7, 0, 0, 0, 0, 0, 0, 0]);
    let bytes = b.into_bytes();
    let log = ULog::parse(&bytes).unwrap();
    let outer = log.topic("outer/a-b", 0).unwrap();
    assert_eq!(outer.layout().unwrap().size(), 8 + 2 * 6);
    let cols: Vec<_> = outer
        .fields()
        .unwrap()
        .iter()
        .map(|c| c.path().to_owned())
        .collect();
    assert_eq!(
        cols,
        [
            "timestamp",
            "in[0].x",
            "in[0].d.y[0]",
            "in[0].d.y[1]",
            "in[0].d.y[2]",
            "in[1].x",
            "in[1].d.y[0]",
            "in[1].d.y[1]",
            "in[1].d.y[2]"
        ]
    );
    assert_eq!(values(&log, "outer/a-b", 0, "in[1].d.y[2]"), ["3"]);
    assert_eq!(values(&log, "outer/a-b", 0, "in[1].x"), ["101"]);
    // The circular format is an error of that topic alone.
    let cyc = log.topic("cyc_a", 0).unwrap();
    assert!(matches!(
        cyc.layout().unwrap_err(),
        LookupError::Layout { .. }
    ));
    assert_eq!(cyc.len(), 1, "its data messages are still indexed");
    assert!(log
        .findings()
        .iter()
        .any(|f| matches!(f.kind, FindingKind::Layout(_))));
    assert!(log
        .findings()
        .iter()
        .any(|f| matches!(&f.kind, FindingKind::InvalidFormat(e) if e.span.start == 31)));
    assert_eq!(values(&log, "ok", 0, "timestamp"), ["7"]);
    assert!(!log
        .findings()
        .iter()
        .any(|f| matches!(f.kind, FindingKind::RedefinedFormat(_))));
}

#[test]
fn trailing_padding_may_be_omitted_or_present_other_sizes_are_skipped() {
    let mut b = base();
    b.data(0, &t_payload(1, 10)); // padding omitted
    b.data(0, &[t_payload(2, 20), vec![0; 4]].concat()); // padding present
    b.data(0, &[t_payload(3, 30), vec![0; 2]].concat()); // neither: skipped
    b.data(0, &t_payload(4, 40));
    let bytes = b.into_bytes();
    let log = ULog::parse(&bytes).unwrap();
    assert_eq!(values(&log, "t", 0, "v"), ["10", "20", "40"]);
    let f: Vec<_> = log.findings().iter().map(|f| f.kind.clone()).collect();
    assert_eq!(
        f,
        [FindingKind::SizeMismatch {
            msg_id: 0,
            expected: (16, 12),
            found: 14
        }]
    );
    let t = log.topic("t", 0).unwrap();
    assert!(t.field("_padding0").is_err(), "padding is never a value");
    assert_eq!(t.fields().unwrap().len(), 2);
}

#[test]
fn information_of_every_type_and_release_versions() {
    let mut b = LogBuilder::new(1, 0);
    b.info("int8_t a", &[0xfe]);
    b.info("uint8_t b", &[0xfe]);
    b.info("int16_t c", &(-2i16).to_le_bytes());
    b.info("uint16_t d", &65000u16.to_le_bytes());
    b.info("int32_t e", &(-3i32).to_le_bytes());
    b.info("uint32_t ver_sw_release", &0x010402c1u32.to_le_bytes());
    b.info("int64_t g", &(-4i64).to_le_bytes());
    b.info("uint64_t h", &u64::MAX.to_le_bytes());
    b.info("float i", &0.1f32.to_le_bytes());
    b.info("double j", &0.1f64.to_le_bytes());
    b.info("bool k", &[1]);
    b.info("char l", b"z");
    b.info(
        "float[2] arr",
        &[1.5f32.to_le_bytes(), 2.5f32.to_le_bytes()].concat(),
    );
    b.info("char[4] s", b"ab\xffc");
    b.info("uint32_t ver_os_release", &0x0c0300ffu32.to_le_bytes());
    let bytes = b.into_bytes();
    let log = ULog::parse(&bytes).unwrap();
    let v = |k| log.info_value(k).unwrap();
    assert_eq!(v("a"), Value::I8(-2));
    assert_eq!(v("b"), Value::U8(254));
    assert_eq!(v("c"), Value::I16(-2));
    assert_eq!(v("d"), Value::U16(65000));
    assert_eq!(v("e"), Value::I32(-3));
    assert_eq!(v("g"), Value::I64(-4));
    assert_eq!(v("h"), Value::U64(u64::MAX));
    assert_eq!(v("i"), Value::F32(0.1));
    assert_eq!(v("j"), Value::F64(0.1));
    assert_eq!(v("k"), Value::Bool(true));
    assert_eq!(v("l"), Value::Char(b'z'));
    assert_eq!(v("arr").to_string(), "[1.5, 2.5]");
    assert_eq!(v("s").as_str().unwrap().as_bytes(), b"ab\xffc");
    assert_eq!(v("s").to_string(), "ab\u{fffd}c", "non-UTF-8 shown lossily");
    let sw = log.release_version("ver_sw_release").unwrap();
    assert_eq!(
        (sw.major, sw.minor, sw.patch, sw.kind_name()),
        (1, 4, 2, "rc")
    );
    assert_eq!(sw.to_string(), "v1.4.2 (RC)");
    assert_eq!(
        log.release_version("ver_os_release").unwrap().to_string(),
        "v12.3.0"
    );
}

#[test]
fn multi_information_continues_and_parameters_change_in_time() {
    let mut b = LogBuilder::new(1, 100);
    b.format("t:uint64_t timestamp;uint32_t v;uint8_t[4] _padding0;");
    b.multi_info(false, "char[2] k", b"a1");
    b.multi_info(true, "char[2] k", b"a2");
    b.multi_info(false, "char[2] k", b"b1");
    b.multi_info(false, "char[2] other", b"o1");
    b.param("float P", &1.0f32.to_le_bytes());
    b.default_param(1, "float P", &0.5f32.to_le_bytes());
    b.default_param(3, "int32_t Q", &4i32.to_le_bytes());
    // The definitions section ends with the first subscription.
    b.subscribe(0, 0, "t");
    b.data(0, &t_payload(1000, 1));
    b.param("float P", &2.0f32.to_le_bytes());
    b.data(0, &t_payload(900, 2)); // not larger: the change time stays
    b.param("float P", &3.0f32.to_le_bytes());
    let bytes = b.into_bytes();
    let log = ULog::parse(&bytes).unwrap();
    let m = &log.multi_info()[0];
    assert_eq!(m.name, "k");
    let parts: Vec<Vec<String>> = m
        .entries
        .iter()
        .map(|e| e.iter().map(|kv| kv.value().to_string()).collect())
        .collect();
    assert_eq!(parts, [vec!["a1", "a2"], vec!["b1"]]);
    assert_eq!(log.multi_info()[1].name, "other");
    assert_eq!(log.initial_param("P"), Some(Value::F32(1.0)));
    let changes: Vec<_> = log
        .param_changes()
        .iter()
        .map(|c| (c.timestamp, c.kv.value()))
        .collect();
    assert_eq!(changes, [(1000, Value::F32(2.0)), (1000, Value::F32(3.0))]);
    let system: Vec<_> = log
        .default_params()
        .iter()
        .filter(|d| d.default_types & 1 != 0)
        .map(|d| d.kv.name().into_owned())
        .collect();
    let setup: Vec<_> = log
        .default_params()
        .iter()
        .filter(|d| d.default_types & 2 != 0)
        .map(|d| d.kv.name().into_owned())
        .collect();
    assert_eq!(
        (system, setup),
        (vec!["P".to_owned(), "Q".into()], vec!["Q".to_owned()])
    );
}

#[test]
fn subscriptions_anywhere_unsubscribe_unknown_ids_and_instances() {
    let mut b = base();
    b.format("u:uint64_t timestamp;int8_t w;");
    b.data(0, &t_payload(1, 1));
    b.subscribe(1, 1, "t"); // second instance, mid-data
    b.subscribe(0, 2, "u");
    b.data(1, &t_payload(2, 2));
    b.data(2, &[&3u64.to_le_bytes()[..], &[0xff]].concat());
    b.data(77, &t_payload(3, 3)); // no such subscription
    b.unsubscribe(2);
    b.data(2, &[&4u64.to_le_bytes()[..], &[1]].concat()); // after R
    b.data(0, &t_payload(5, 5));
    let bytes = b.into_bytes();
    let log = ULog::parse(&bytes).unwrap();
    assert_eq!(values(&log, "t", 0, "v"), ["1", "5"]);
    assert_eq!(values(&log, "t", 1, "v"), ["2"]);
    assert_eq!(values(&log, "u", 0, "w"), ["-1"]);
    let ids: Vec<_> = log
        .findings()
        .iter()
        .filter_map(|f| match f.kind {
            FindingKind::UnknownMsgId(id) => Some(id),
            _ => None,
        })
        .collect();
    assert_eq!(ids, [77, 2]);
    assert_eq!(log.topic_instances("t").len(), 2);
    let e = log.topic("vehicle_stuff", 0).unwrap_err();
    assert!(matches!(e, LookupError::Topic(_)));
    let e = log.topic("t", 0).unwrap().field("vv").unwrap_err();
    assert!(e.to_string().contains("did you mean `v`"), "{e}");
}

#[test]
fn version_0_narrow_timestamps_unwrap_per_series() {
    let mut b = LogBuilder::new(0, 0);
    b.format("a:uint16_t timestamp;uint8_t x;");
    b.format("m:uint8_t timestamp;uint8_t x;");
    b.format("w:uint32_t timestamp;");
    b.subscribe(0, 0, "a");
    b.subscribe(0, 1, "m");
    b.subscribe(0, 2, "w");
    for raw in [65000u16, 65535, 3, 200] {
        b.data(0, &[&raw.to_le_bytes()[..], &[1]].concat());
    }
    for raw in [250u8, 255, 1] {
        b.data(1, &[raw, 2]);
    }
    for raw in [u32::MAX, 5] {
        b.data(2, &raw.to_le_bytes());
    }
    let bytes = b.into_bytes();
    let log = ULog::parse(&bytes).unwrap();
    assert_eq!(
        log.topic("a", 0).unwrap().timestamps(),
        [65000, 65535, 65539, 65736]
    );
    assert_eq!(
        log.topic("m", 0).unwrap().timestamps(),
        [250_000, 255_000, 257_000]
    );
    assert_eq!(
        log.topic("w", 0).unwrap().timestamps(),
        [u32::MAX as u64, (1 << 32) + 5]
    );
    // The raw values stay readable as fields.
    assert_eq!(
        values(&log, "a", 0, "timestamp"),
        ["65000", "65535", "3", "200"]
    );
}

#[test]
fn corruption_is_skipped_reported_and_the_rest_kept() {
    // Zero-size headers, an impossible size, garbage, an unknown msg_id: each between
    // good messages, with and without sync messages to resynchronise on.
    for with_sync in [false, true] {
        let mut b = base();
        let mut expected = Vec::new();
        let mut damage = Vec::new();
        for i in 0..40u32 {
            b.data(0, &t_payload(u64::from(i), i));
            expected.push(i.to_string());
            if with_sync && i % 5 == 0 {
                b.sync();
            }
            let at = b.bytes().len() as u64;
            match i {
                5 => {
                    b.garbage(&[0; 37]);
                    damage.push((at, 37));
                }
                12 => {
                    b.garbage(&[0xff, 0xff, b'D', 1, 2, 3]);
                    damage.push((at, 6));
                }
                20 => {
                    let g = b"\x05\x00\x01garbage bytes in the middle";
                    b.garbage(g);
                    damage.push((at, g.len() as u64));
                }
                30 => {
                    b.data(500, &t_payload(0, 0));
                    damage.push((at, 17));
                }
                _ => {}
            }
        }
        let bytes = b.into_bytes();
        let log = ULog::parse(&bytes).unwrap();
        assert_eq!(values(&log, "t", 0, "v"), expected, "with_sync {with_sync}");
        let found: Vec<_> = log.findings().iter().map(|f| (f.offset, f.len)).collect();
        assert_eq!(found, damage, "with_sync {with_sync}: {:?}", log.findings());
        assert!(log.has_damage());
        assert!(matches!(
            log.findings()[0].kind,
            FindingKind::Corrupt(Corruption::ZeroFill)
        ));
        assert_eq!(log.findings()[3].kind, FindingKind::UnknownMsgId(500));
    }
}

#[test]
fn truncation_anywhere_keeps_a_prefix_and_is_reported() {
    let mut b = base();
    b.info_str("sys_name", "PX4");
    for i in 0..30u32 {
        b.data(0, &t_payload(u64::from(i), i));
        if i % 7 == 0 {
            b.log(b'6', u64::from(i), "text");
        }
    }
    let full = b.bytes().to_vec();
    let all: Vec<_> = ULog::parse(&full)
        .unwrap()
        .messages()
        .map(|m| m.unwrap())
        .collect();
    let boundaries = b.boundaries();
    for cut in 16..=full.len() {
        let bytes = &full[..cut];
        let log = ULog::parse(bytes).unwrap();
        let got: Vec<_> = log.messages().map(|m| m.unwrap()).collect();
        let n = all.iter().take_while(|m| (m.offset as usize) < cut).count();
        let complete = all.iter().filter(|m| {
            let size = u16::from_le_bytes([full[m.offset as usize], full[m.offset as usize + 1]]);
            m.offset as usize + 3 + size as usize <= cut
        });
        assert_eq!(got.len(), complete.count(), "cut at {cut}");
        assert_eq!(&got[..], &all[..got.len()], "cut at {cut}: a prefix");
        let truncated = log
            .findings()
            .iter()
            .any(|f| f.kind == FindingKind::Truncated);
        assert_eq!(
            truncated,
            !boundaries.contains(&cut),
            "cut at {cut}: {:?}",
            log.findings()
        );
        assert!(n >= got.len());
        if truncated {
            let f = &log.findings()[0];
            assert_eq!(f.offset + f.len, cut as u64);
        }
    }
}

#[test]
fn incremental_reader_matches_the_whole_file_reader_in_any_chunks() {
    let mut b = base();
    for i in 0..50u32 {
        b.data(0, &t_payload(u64::from(i), i));
        if i == 20 {
            b.garbage(&[0; 11]);
        }
        if i == 30 {
            b.garbage(&[9, 9, 9, 1, 2]);
        }
    }
    b.garbage(&[4, 0, b'D', 0]); // truncated at the end
    let bytes = b.into_bytes();
    let whole: Vec<_> = ULog::parse(&bytes)
        .unwrap()
        .messages()
        .map(|m| m.unwrap())
        .collect();
    let whole_findings = ULog::parse(&bytes).unwrap().findings().to_vec();
    for chunk in [1usize, 2, 3, 7, 64, 1000, bytes.len()] {
        let mut inc = PushReader::new();
        let mut got = Vec::new();
        for c in bytes.chunks(chunk) {
            inc.push(c);
            while inc.advance().unwrap() == Progress::Ready {
                got.push(inc.current().unwrap().offset);
            }
        }
        inc.finish();
        while inc.advance().unwrap() == Progress::Ready {
            got.push(inc.current().unwrap().offset);
        }
        let expect: Vec<u64> = whole.iter().map(|m| m.offset).collect();
        assert_eq!(got, expect, "chunk {chunk}");
        assert_eq!(inc.findings(), &whole_findings[..], "chunk {chunk}");
        assert!(inc.buffered() <= 3 * 65538 + chunk);
    }
}

#[test]
fn data_messages_carry_their_payload_and_subscription() {
    let mut b = base();
    b.data(0, &t_payload(5, 6));
    let bytes = b.into_bytes();
    let mut inc = PushReader::new();
    inc.push(&bytes);
    inc.finish();
    let mut seen = false;
    while inc.advance().unwrap() == Progress::Ready {
        if let Some(m) = inc.current() {
            if let Message::Data { msg_id, payload } = m.message {
                let sub = inc.subscription(msg_id).unwrap();
                assert_eq!((sub.name(), sub.multi_id()), ("t", 0));
                assert!(sub.layout().unwrap().accepts_len(payload.len()));
                seen = true;
            }
        }
    }
    assert!(seen);
}

#[test]
fn a_zero_filled_tail_is_reported_as_one_stretch() {
    let mut b = base();
    b.data(0, &t_payload(1, 1));
    b.data(0, &t_payload(2, 2));
    let end = b.bytes().len() as u64;
    b.garbage(&[0; 5000]);
    let bytes = b.into_bytes();
    let log = ULog::parse(&bytes).unwrap();
    assert_eq!(values(&log, "t", 0, "v"), ["1", "2"]);
    let f: Vec<_> = log
        .findings()
        .iter()
        .map(|f| (f.kind.clone(), f.offset, f.len))
        .collect();
    assert_eq!(f, [(FindingKind::Corrupt(Corruption::ZeroFill), end, 5000)]);
    assert!(!log.is_truncated());
    // A data message of the wrong size right before the zeros is reported as itself.
    let mut b = base();
    b.data(0, &t_payload(1, 1));
    let at = b.bytes().len() as u64;
    b.data(0, &[0; 28]);
    b.garbage(&[0; 100]);
    let bytes = b.into_bytes();
    let log = ULog::parse(&bytes).unwrap();
    let f: Vec<_> = log
        .findings()
        .iter()
        .map(|f| (f.kind.clone(), f.offset, f.len))
        .collect();
    assert_eq!(
        f,
        [
            (
                FindingKind::SizeMismatch {
                    msg_id: 0,
                    expected: (16, 12),
                    found: 28
                },
                at,
                33
            ),
            (FindingKind::Corrupt(Corruption::ZeroFill), at + 33, 100)
        ]
    );
}

/// Regression (fuzz target `chunked`): the whole-file and the incremental reader
/// described a non-ULog file differently when its first bytes were zero and later
/// ones were not.
#[test]
fn not_ulog_is_described_from_the_first_bytes_only() {
    let mut bytes = vec![0u8; 46];
    bytes.extend_from_slice(&[0xff; 10]);
    let whole = ULog::parse(&bytes).unwrap_err();
    let mut inc = PushReader::new();
    inc.push(&bytes[..20]);
    let chunked = inc.advance().unwrap_err();
    assert_eq!(whole, chunked);
}

/// Review findings, each held by a test: repeated subscriptions stay one (and cost
/// constant time), an error is final in the incremental reader, pushing drops the
/// current message, a cut tail never yields a message made of its own bytes, and a
/// format defined again with other spacing is the same format.
#[test]
fn repeated_subscriptions_of_an_undefined_format_stay_one() {
    let mut b = LogBuilder::new(1, 0);
    for _ in 0..50_000 {
        b.subscribe(0, 0, "nope");
    }
    let bytes = b.into_bytes();
    let log = ULog::parse(&bytes).unwrap();
    assert_eq!(log.subscriptions().len(), 1);
    assert_eq!(log.findings().len(), 1);
    assert_eq!(
        log.findings()[0].kind,
        FindingKind::UnknownFormat("nope".into())
    );
}

#[test]
fn a_refusal_is_final_in_the_incremental_reader() {
    let mut b = LogBuilder::new(1, 0);
    b.flag_bits([0; 8], [2, 0, 0, 0, 0, 0, 0, 0], [0; 3]);
    b.format("t:uint64_t timestamp;");
    let mut inc = PushReader::new();
    inc.push(b.bytes());
    inc.finish();
    let first = inc.advance().unwrap_err();
    assert_eq!(inc.advance().unwrap_err(), first);
}

#[test]
fn pushing_drops_the_current_message() {
    let mut b = base();
    b.data(0, &t_payload(1, 1));
    let bytes = b.into_bytes();
    let mut inc = PushReader::new();
    inc.push(&bytes);
    let mut ready = false;
    while let Ok(Progress::Ready) = inc.advance() {
        ready = true;
        inc.push(&[]);
        assert!(inc.current().is_none());
    }
    assert!(ready);
}

#[test]
fn a_cut_tail_never_yields_a_message_made_of_its_own_bytes() {
    // The cut message's last bytes look like a complete unsubscription ending at EOF.
    let mut b = base();
    b.data(0, &t_payload(1, 1));
    let mut bytes = b.into_bytes();
    bytes.extend_from_slice(&[40, 0, b'D', 0, 0, 1, 2, 3, 2, 0, b'R', 5, 0]);
    let log = ULog::parse(&bytes).unwrap();
    let types: Vec<u8> = log
        .messages()
        .map(|m| m.unwrap().message.msg_type())
        .collect();
    assert!(!types.contains(&b'R'), "{types:?}");
    assert!(log.is_truncated());
}

#[test]
fn formats_compare_by_content_not_by_spacing() {
    let mut b = LogBuilder::new(1, 0);
    b.format("t:uint64_t timestamp;uint32_t v;");
    b.format("t:uint64_t  timestamp;uint32_t v;");
    b.subscribe(0, 0, "t");
    b.subscribe(0, 1, "t");
    b.data(0, &t_payload(1, 1));
    b.data(1, &t_payload(2, 2));
    let bytes = b.into_bytes();
    let log = ULog::parse(&bytes).unwrap();
    assert!(log.findings().is_empty(), "{:?}", log.findings());
    assert_eq!(log.subscriptions().len(), 1);
    assert_eq!(values(&log, "t", 0, "v"), ["1", "2"]);
}

/// A power-loss log: a good log in which SD blocks (4 KiB, at multiples of 4 KiB in the
/// file) were never written and read as zeros. The data message whose header was
/// written before a block but whose payload runs into it (all of it, from its msg_id,
/// from its timestamp's third byte, from its last field) is damage, not a row: it is
/// reported with the zeros after it, from its header to the first message after the
/// block (`Corruption::CutByZeroFill`). Every message wholly outside the blocks is
/// kept, those in a written sector between two blocks included; a row whose own
/// trailing zero bytes meet a block that starts right after it is kept; and the
/// incremental reader takes the same decisions in any chunks.
#[test]
fn a_message_cut_by_an_unwritten_block_is_damage_and_every_whole_row_is_kept() {
    const BLOCK: usize = 4096;
    let mut b = base();
    let first = b.boundaries().len() - 1;
    // Rows of 17 bytes: their starts go through every residue modulo 4096. `v` is
    // small, so most payloads end in zero bytes of their own.
    for i in 0..5000u32 {
        b.data(0, &t_payload(1_000_000 + 1_000 * u64::from(i) + 34, i));
    }
    let starts = &b.boundaries()[first..b.boundaries().len() - 1];
    let ends = &b.boundaries()[first + 1..];
    let good = b.bytes().to_vec();
    // The row whose payload's `d`-th byte starts a block, after row `after`.
    let at = |d: usize, after: usize| -> usize {
        (after..starts.len())
            .find(|&i| (starts[i] + 3 + d).is_multiple_of(BLOCK))
            .unwrap()
    };
    struct Case {
        what: &'static str,
        blocks: Vec<(usize, usize)>,
        /// The first row of each damaged stretch (the cut row), when one is cut.
        cut: Vec<usize>,
    }
    let mut cases = Vec::new();
    for (d, what) in [
        (0, "payload all zeros"),
        (2, "from the timestamp on: timestamp 0"),
        (4, "from the timestamp's third byte: timestamp 34"),
        (13, "only the last byte of the payload"),
    ] {
        let i = at(d, 100);
        let block = starts[i] + 3 + d;
        cases.push(Case {
            what,
            blocks: vec![(block, block + BLOCK)],
            cut: vec![i],
        });
    }
    // Two blocks with one written sector between them: its whole rows are kept, the
    // one it cuts at its end is not.
    let i = at(6, 100);
    let first_block = starts[i] + 3 + 6;
    let island_end = first_block + BLOCK + 512;
    let j = (0..starts.len())
        .find(|&j| starts[j] < island_end && ends[j] > island_end)
        .unwrap();
    cases.push(Case {
        what: "an island of one written sector",
        blocks: vec![
            (first_block, first_block + BLOCK),
            (island_end, island_end + BLOCK),
        ],
        cut: vec![i, j],
    });
    // A block that starts right where a row ends: the row's own trailing zeros meet
    // it, but it was written whole.
    let k = (100..starts.len())
        .find(|&k| ends[k].is_multiple_of(BLOCK))
        .unwrap();
    assert!(
        good[ends[k] - 2..ends[k]] == [0, 0],
        "row {k} ends in zeros"
    );
    cases.push(Case {
        what: "a block right after a whole row",
        blocks: vec![(ends[k], ends[k] + BLOCK)],
        cut: vec![],
    });

    for case in cases {
        let what = case.what;
        let mut bytes = good.clone();
        for &(a, z) in &case.blocks {
            bytes[a..z].fill(0);
        }
        let log = ULog::parse(&bytes).unwrap();
        let whole = |r: usize| {
            case.blocks
                .iter()
                .all(|&(a, z)| ends[r] <= a || starts[r] >= z)
        };
        let expected: Vec<String> = (0..starts.len())
            .filter(|&r| whole(r))
            .map(|r| r.to_string())
            .collect();
        let got = values(&log, "t", 0, "v");
        assert!(
            got == expected,
            "{what}: rows read that are not whole: {:?}; whole rows lost: {:?}",
            got.iter()
                .filter(|v| !expected.contains(v))
                .collect::<Vec<_>>(),
            expected
                .iter()
                .filter(|v| !got.contains(v))
                .collect::<Vec<_>>()
        );
        assert!(
            expected.len() >= starts.len() - 2 * (BLOCK / 17 + 2),
            "{what}"
        );
        let found: Vec<_> = log
            .findings()
            .iter()
            .map(|f| (f.kind.clone(), f.offset, f.len))
            .collect();
        let stretches: Vec<_> = case
            .blocks
            .iter()
            .map(|&(a, z)| {
                let next = starts.iter().copied().find(|&s| s >= z).unwrap();
                match case.cut.iter().find(|&&r| starts[r] < a && ends[r] > a) {
                    Some(&r) => (
                        FindingKind::Corrupt(Corruption::CutByZeroFill),
                        starts[r] as u64,
                        (next - starts[r]) as u64,
                    ),
                    None => (
                        FindingKind::Corrupt(Corruption::ZeroFill),
                        a as u64,
                        (next - a) as u64,
                    ),
                }
            })
            .collect();
        assert_eq!(found, stretches, "{what}");
        assert_eq!(stretches.len(), case.blocks.len());

        // The incremental reader, in any chunks, and the one-pass scan agree.
        let whole_log: Vec<_> = log.messages().map(Result::unwrap).collect();
        for chunk in [1usize, 17, 512, 4096, 65536] {
            let mut inc = PushReader::new();
            let mut got = Vec::new();
            let mut take = |inc: &mut PushReader| {
                while inc.advance().unwrap() == Progress::Ready {
                    got.push(inc.current().unwrap().offset);
                }
            };
            for c in bytes.chunks(chunk) {
                inc.push(c);
                take(&mut inc);
            }
            inc.finish();
            take(&mut inc);
            let expect: Vec<u64> = whole_log.iter().map(|m| m.offset).collect();
            assert_eq!(got, expect, "{what}: chunk {chunk}");
            assert_eq!(inc.findings(), log.findings(), "{what}: chunk {chunk}");
        }
    }
}
