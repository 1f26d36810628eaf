use std::path::PathBuf;

use arrow_array::cast::AsArray;
use arrow_array::types::{
    Float32Type, Float64Type, Int16Type, Int32Type, Int64Type, Int8Type, UInt16Type, UInt32Type,
    UInt64Type, UInt8Type,
};
use arrow_array::{Array, RecordBatch};
use arrow_schema::DataType;
use parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder;

use super::ExportErrorKind;
use super::*;
use crate::access::lookup::LookupError;
use crate::testing::LogBuilder;

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("ulog-export-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

/// A log with one topic of every basic type, two rows of extreme values.
fn all_types_log() -> Vec<u8> {
    let mut b = LogBuilder::new(1, 0);
    b.format(
        "all:uint64_t timestamp;int8_t a;uint8_t b;int16_t c;uint16_t d;int32_t e;\
         uint32_t f;int64_t g;uint64_t h;float i;double j;bool k;char l;char[5] s;\
         uint8_t[3] _padding0;",
    );
    b.subscribe(0, 0, "all");
    for row in 0..2u8 {
        let mut p = Vec::new();
        p.extend_from_slice(&(1000 + u64::from(row)).to_le_bytes());
        if row == 0 {
            p.push(i8::MIN as u8);
            p.push(u8::MAX);
            p.extend_from_slice(&i16::MIN.to_le_bytes());
            p.extend_from_slice(&u16::MAX.to_le_bytes());
            p.extend_from_slice(&i32::MIN.to_le_bytes());
            p.extend_from_slice(&u32::MAX.to_le_bytes());
            p.extend_from_slice(&i64::MIN.to_le_bytes());
            p.extend_from_slice(&u64::MAX.to_le_bytes());
            p.extend_from_slice(&f32::NAN.to_le_bytes());
            p.extend_from_slice(&f64::NEG_INFINITY.to_le_bytes());
            p.push(2); // any non-zero byte is true
            p.push(b'x');
            p.extend_from_slice(b"a\xff\0b\0");
        } else {
            p.push(i8::MAX as u8);
            p.push(0);
            p.extend_from_slice(&i16::MAX.to_le_bytes());
            p.extend_from_slice(&0u16.to_le_bytes());
            p.extend_from_slice(&i32::MAX.to_le_bytes());
            p.extend_from_slice(&7u32.to_le_bytes());
            p.extend_from_slice(&i64::MAX.to_le_bytes());
            p.extend_from_slice(&(1u64 << 63).to_le_bytes());
            p.extend_from_slice(&0.1f32.to_le_bytes());
            p.extend_from_slice(&1e300f64.to_le_bytes());
            p.push(0);
            p.push(0);
            p.extend_from_slice(b"hello");
        }
        b.data(0, &p); // trailing padding left out, as writers may
    }
    b.into_bytes()
}

/// A log with nested formats, arrays of them, arrays and nested padding.
fn nested_log() -> Vec<u8> {
    let mut b = LogBuilder::new(1, 0);
    b.format("inner:uint32_t v;char[4] name;float[2] xy;uint8_t[2] _padding0;");
    b.format("pad_only:uint8_t[4] _padding0;");
    b.format(
        "outer:uint64_t timestamp;inner[2] items;inner one;int16_t[3] arr;pad_only p;\
         float[0] none;bool[2] flags;",
    );
    b.subscribe(3, 0, "outer");
    for row in 0..3u32 {
        let mut p = Vec::new();
        p.extend_from_slice(&u64::from(row * 10).to_le_bytes());
        for k in 0..3u32 {
            p.extend_from_slice(&(row * 100 + k).to_le_bytes());
            p.extend_from_slice(if k == 1 { b"ab\0\0" } else { b"wxyz" });
            p.extend_from_slice(&(row as f32 + k as f32 / 2.0).to_le_bytes());
            p.extend_from_slice(&(-(row as f32)).to_le_bytes());
            p.extend_from_slice(&[0xee, 0xee]);
        }
        for k in 0..3i16 {
            p.extend_from_slice(&(k - row as i16).to_le_bytes());
        }
        p.extend_from_slice(&[0xdd; 4]);
        p.extend_from_slice(&[1, (row % 2) as u8]);
        b.data(0, &p);
    }
    b.into_bytes()
}

fn flat() -> Options {
    Options {
        flatten: true,
        ..Options::default()
    }
}

#[test]
fn every_basic_type_keeps_its_width_and_value() {
    let bytes = all_types_log();
    let log = ULog::parse(&bytes).unwrap();
    let topic = log.topic("all", 0).unwrap();
    for options in [Options::default(), flat()] {
        let batch = topic_record_batch(&topic, &options).unwrap();
        let schema = batch.schema();
        let types: Vec<(&str, &DataType)> = schema
            .fields()
            .iter()
            .map(|f| (f.name().as_str(), f.data_type()))
            .collect();
        assert_eq!(
            types,
            [
                ("timestamp", &DataType::UInt64),
                ("a", &DataType::Int8),
                ("b", &DataType::UInt8),
                ("c", &DataType::Int16),
                ("d", &DataType::UInt16),
                ("e", &DataType::Int32),
                ("f", &DataType::UInt32),
                ("g", &DataType::Int64),
                ("h", &DataType::UInt64),
                ("i", &DataType::Float32),
                ("j", &DataType::Float64),
                ("k", &DataType::Boolean),
                ("l", &DataType::UInt8),
                ("s", &DataType::Utf8),
            ]
        );
        assert!(schema.fields().iter().all(|f| !f.is_nullable()));
        let col = |n: &str| batch.column_by_name(n).unwrap().clone();
        assert_eq!(
            col("timestamp").as_primitive::<UInt64Type>().values(),
            &[1000, 1001]
        );
        assert_eq!(
            col("a").as_primitive::<Int8Type>().values(),
            &[i8::MIN, i8::MAX]
        );
        assert_eq!(col("b").as_primitive::<UInt8Type>().values(), &[u8::MAX, 0]);
        assert_eq!(
            col("c").as_primitive::<Int16Type>().values(),
            &[i16::MIN, i16::MAX]
        );
        assert_eq!(
            col("d").as_primitive::<UInt16Type>().values(),
            &[u16::MAX, 0]
        );
        assert_eq!(
            col("e").as_primitive::<Int32Type>().values(),
            &[i32::MIN, i32::MAX]
        );
        assert_eq!(
            col("f").as_primitive::<UInt32Type>().values(),
            &[u32::MAX, 7]
        );
        assert_eq!(
            col("g").as_primitive::<Int64Type>().values(),
            &[i64::MIN, i64::MAX]
        );
        assert_eq!(
            col("h").as_primitive::<UInt64Type>().values(),
            &[u64::MAX, 1 << 63]
        );
        let i = col("i");
        let i = i.as_primitive::<Float32Type>();
        assert!(i.value(0).is_nan());
        assert_eq!(i.value(1), 0.1f32);
        assert_eq!(
            col("j").as_primitive::<Float64Type>().values(),
            &[f64::NEG_INFINITY, 1e300]
        );
        let k = col("k");
        assert_eq!(
            (k.as_boolean().value(0), k.as_boolean().value(1)),
            (true, false)
        );
        assert_eq!(col("l").as_primitive::<UInt8Type>().values(), &[b'x', 0]);
        let s = col("s");
        let s = s.as_string::<i32>();
        // Trailing NULs go; an inner NUL and a non-UTF-8 byte stay, one char per byte.
        assert_eq!((s.value(0), s.value(1)), ("a\u{ff}\0b", "hello"));
        assert_eq!(
            schema.field_with_name("timestamp").unwrap().metadata()["unit"],
            "us"
        );
        assert_eq!(
            schema.field_with_name("s").unwrap().metadata()["ulog.type"],
            "char[5]"
        );
        assert_eq!(schema.metadata()["ulog.topic"], "all");
        assert_eq!(schema.metadata()["ulog.multi_id"], "0");
        assert!(schema.metadata()["ulog.format"].starts_with("all:uint64_t timestamp;"));
    }
}

#[test]
fn a_field_column_has_the_flattened_tables_type_and_values_and_nulls_where_rows_are_absent() {
    let bytes = all_types_log();
    let log = ULog::parse(&bytes).unwrap();
    let topic = log.topic("all", 0).unwrap();
    let table = topic_record_batch(&topic, &flat()).unwrap();
    let (first, second) = (topic.payload(0).unwrap(), topic.payload(1).unwrap());
    // Absent, a row, a row too short for most fields, the other row.
    let rows = [None, Some(first), Some(&first[..9]), Some(second)];
    for reader in topic.fields().unwrap() {
        let name = reader.path();
        let whole = table.column_by_name(name).unwrap();
        assert_eq!(&field_data_type(&reader), whole.data_type(), "{name}");
        let column = field_array(&reader, &rows).unwrap();
        assert_eq!(column.data_type(), whole.data_type(), "{name}");
        // The short row holds the timestamp and `a` only.
        let short_fits = matches!(name, "timestamp" | "a");
        let nulls: Vec<bool> = (0..4).map(|i| column.is_null(i)).collect();
        assert_eq!(nulls, [true, false, !short_fits, false], "{name}");
        assert_eq!(
            column.slice(1, 1).to_data(),
            whole.slice(0, 1).to_data(),
            "{name}"
        );
        assert_eq!(
            column.slice(3, 1).to_data(),
            whole.slice(1, 1).to_data(),
            "{name}"
        );
    }
    let q = topic.field("s").unwrap();
    assert_eq!(
        field_array(&q, &[Some(first)])
            .unwrap()
            .as_string::<i32>()
            .value(0),
        "a\u{ff}\0b"
    );
}

#[test]
fn nested_formats_are_structs_and_arrays_fixed_size_lists() {
    let bytes = nested_log();
    let log = ULog::parse(&bytes).unwrap();
    assert!(log.findings().is_empty(), "{:?}", log.findings());
    let topic = log.topic("outer", 3).unwrap();
    let batch = topic_record_batch(&topic, &Options::default()).unwrap();
    let schema = batch.schema();
    let names: Vec<&str> = schema.fields().iter().map(|f| f.name().as_str()).collect();
    // Padding, a struct of padding only and a zero-length array are left out.
    assert_eq!(names, ["timestamp", "items", "one", "arr", "flags"]);
    let DataType::FixedSizeList(item, 2) = schema.field(1).data_type() else {
        panic!("{:?}", schema.field(1))
    };
    let DataType::Struct(inner) = item.data_type() else {
        panic!("{item:?}")
    };
    let inner_names: Vec<&str> = inner.iter().map(|f| f.name().as_str()).collect();
    assert_eq!(inner_names, ["v", "name", "xy"]);
    assert!(
        matches!(inner[2].data_type(), DataType::FixedSizeList(f, 2) if f.data_type() == &DataType::Float32)
    );
    assert_eq!(schema.field(1).metadata()["ulog.type"], "inner[2]");
    assert!(schema.metadata()["ulog.format"].starts_with("inner:"));

    // Row 2, items[1]: v = 201, name "ab", xy = [2.5, -2.0].
    let items = batch.column(1).as_fixed_size_list();
    let row2 = items.value(2);
    let row2 = row2.as_struct();
    assert_eq!(
        row2.column(0).as_primitive::<UInt32Type>().values(),
        &[200, 201]
    );
    assert_eq!(row2.column(1).as_string::<i32>().value(1), "ab");
    let xy = row2.column(2).as_fixed_size_list().value(1);
    assert_eq!(xy.as_primitive::<Float32Type>().values(), &[2.5, -2.0]);
    let one = batch.column(2).as_struct();
    assert_eq!(one.column(0).as_primitive::<UInt32Type>().value(1), 102);
    let arr = batch.column(3).as_fixed_size_list().value(1);
    assert_eq!(arr.as_primitive::<Int16Type>().values(), &[-1, 0, 1]);
    let flags = batch.column(4).as_fixed_size_list().value(1);
    assert!(flags.as_boolean().value(0) && flags.as_boolean().value(1));

    // Flattened: pyulog's columns, in the reader's order, timestamp first.
    let batch = topic_record_batch(&topic, &flat()).unwrap();
    let names: Vec<String> = batch
        .schema()
        .fields()
        .iter()
        .map(|f| f.name().clone())
        .collect();
    let expected: Vec<String> = topic
        .fields()
        .unwrap()
        .iter()
        .map(|c| c.path().to_owned())
        .collect();
    assert_eq!(names, expected);
    assert!(names.contains(&"items[1].xy[0]".to_owned()));
    let v = batch.column_by_name("items[1].v").unwrap();
    assert_eq!(v.as_primitive::<UInt32Type>().values(), &[1, 101, 201]);
    let name = batch.column_by_name("items[1].name").unwrap();
    assert_eq!(name.as_string::<i32>().value(0), "ab");
}

/// The schema (with its metadata) and the one batch of a small Parquet file.
fn read_back(path: &std::path::Path) -> (arrow_schema::SchemaRef, RecordBatch) {
    let file = std::fs::File::open(path).unwrap();
    let builder = ParquetRecordBatchReaderBuilder::try_new(file).unwrap();
    let schema = builder.schema().clone();
    let mut batches: Vec<RecordBatch> = builder.build().unwrap().map(|b| b.unwrap()).collect();
    assert_eq!(batches.len(), 1, "one batch per small file");
    (schema, batches.remove(0))
}

#[test]
fn parquet_files_read_back_equal_to_the_record_batches() {
    for (name, bytes) in [("all", all_types_log()), ("nested", nested_log())] {
        let log = ULog::parse(&bytes).unwrap();
        for options in [Options::default(), flat()] {
            let dir = scratch(&format!("{name}-{}", options.flatten));
            let export = write_parquet(&log, &dir, &options).unwrap();
            assert_eq!(export.files.len(), 1);
            assert!(export.skipped.is_empty());
            let written = &export.files[0];
            let topic = log.topic(&written.topic, written.multi_id).unwrap();
            assert_eq!(written.path, dir.join(file_name(&topic)));
            assert_eq!(written.rows, topic.len());
            let ours = topic_record_batch(&topic, &options).unwrap();
            let (schema, back) = read_back(&written.path);
            // Types (u64 stays u64, lists stay fixed-size), values and metadata survive.
            assert_eq!(schema, ours.schema());
            assert_eq!(back.schema().fields(), ours.schema().fields());
            for (a, b) in back.columns().iter().zip(ours.columns()) {
                // NaN != NaN for `==`: compare the data bit for bit.
                assert_eq!(a.to_data(), b.to_data());
            }
            let meta = std::fs::read_to_string(&export.metadata).unwrap();
            assert!(meta.contains(&format!("\"name\": \"{}\"", written.topic)));
            std::fs::remove_dir_all(&dir).unwrap();
        }
    }
}

#[test]
fn units_of_fields_are_in_the_files_metadata_by_field_path() {
    let bytes = crate::testing::sample_log();
    let log = ULog::parse(&bytes).unwrap();
    for options in [Options::default(), flat()] {
        let dir = scratch(&format!("units-{}", options.flatten));
        let export = write_parquet(&log, &dir, &options).unwrap();
        let file = |topic: &str| {
            let w = export.files.iter().find(|w| w.topic == topic).unwrap();
            read_back(&w.path).0
        };
        let esc = file("esc_status");
        let units: Vec<(&str, &str)> = esc
            .metadata()
            .iter()
            .filter_map(|(k, v)| Some((k.strip_prefix("ulog.unit.")?, v.as_str())))
            .collect::<std::collections::BTreeMap<_, _>>()
            .into_iter()
            .collect();
        // Nested fields by their path without indices; fields whose name says no unit
        // (`esc_count`, `timestamp`, which has its own) have no key.
        assert_eq!(units, [("esc.esc_rpm", "rpm"), ("esc.esc_voltage", "V")]);
        let position = file("vehicle_local_position");
        assert_eq!(position.metadata()["ulog.unit.z"], "m");
        assert_eq!(position.metadata()["ulog.unit.vx"], "m/s");
        assert!(!position.metadata().contains_key("ulog.unit.xy_valid"));
        assert_eq!(
            file("battery_status").metadata()["ulog.unit.voltage_v"],
            "V"
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }
}

#[test]
fn a_utc_column_follows_the_timestamp_with_the_clocks_time() {
    use crate::read::UtcClock;
    let bytes = crate::testing::sample_log();
    let log = ULog::parse(&bytes).unwrap();
    let boot = 1_707_236_822_000_000i64;
    for flatten in [false, true] {
        let options = Options {
            flatten,
            utc: Some(UtcClock::from_boot(boot)),
            ..Options::default()
        };
        let dir = scratch(&format!("utc-{flatten}"));
        let export = write_parquet(&log, &dir, &options).unwrap();
        for written in &export.files {
            let topic = log.topic(&written.topic, written.multi_id).unwrap();
            let (schema, batch) = read_back(&written.path);
            let names: Vec<&str> = schema.fields().iter().map(|f| f.name().as_str()).collect();
            assert_eq!(
                names[..2],
                ["timestamp", "timestamp_utc"],
                "{}",
                written.topic
            );
            let field = schema.field(1);
            assert_eq!(
                field.data_type(),
                &DataType::Timestamp(arrow_schema::TimeUnit::Microsecond, Some("UTC".into()))
            );
            assert_eq!(
                field.metadata()["ulog.utc_source"],
                "information key boot_time_utc_us"
            );
            let utc = batch
                .column(1)
                .as_primitive::<arrow_array::types::TimestampMicrosecondType>();
            let expected: Vec<i64> = topic
                .timestamps()
                .iter()
                .map(|&t| boot + t as i64)
                .collect();
            assert_eq!(utc.values(), &expected[..], "{}", written.topic);
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }
}

#[test]
fn batches_split_rows_and_keep_them_all() {
    let bytes = crate::testing::sample_log();
    let log = ULog::parse(&bytes).unwrap();
    let topic = log.topic("vehicle_attitude", 0).unwrap();
    let options = Options {
        batch_rows: 7,
        row_group_rows: 7,
        ..Options::default()
    };
    let batches: Vec<RecordBatch> = topic_record_batches(&topic, &options)
        .unwrap()
        .map(|b| b.unwrap())
        .collect();
    assert_eq!(batches.len(), topic.len().div_ceil(7));
    assert!(batches.iter().all(|b| b.num_rows() <= 7));
    let whole = topic_record_batch(&topic, &options).unwrap();
    let mut row = 0;
    for b in &batches {
        assert_eq!(
            b.column(1).to_data(),
            whole.column(1).slice(row, b.num_rows()).to_data()
        );
        row += b.num_rows();
    }
    assert_eq!(row, topic.len());

    // Written in row groups of 7, read back whole.
    let dir = scratch("batches");
    let path = dir.join("att.parquet");
    std::fs::create_dir_all(&dir).unwrap();
    write_topic(&topic, &path, &options).unwrap();
    let (meta, _, back) = read_whole(&path);
    // One row group per batch.
    assert_eq!(meta.num_row_groups(), topic.len().div_ceil(7));
    assert_eq!(back.column(1).to_data(), whole.column(1).to_data());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn topic_filter_checks_names_and_skips_what_cannot_be_exported() {
    let bytes = crate::testing::sample_log();
    let log = ULog::parse(&bytes).unwrap();
    let options = Options {
        topics: Some(vec!["battery_status".into(), "esc_statsu".into()]),
        ..Options::default()
    };
    let dir = scratch("filter");
    let err = write_parquet(&log, &dir, &options).unwrap_err();
    match err.kind() {
        ExportErrorKind::Lookup(LookupError::Topic(missing)) => {
            assert_eq!(missing.name, "esc_statsu");
            assert_eq!(missing.closest, ["esc_status"]);
        }
        k => panic!("{k:?}"),
    }
    assert!(!dir.exists(), "nothing is left when a name is missing");

    // Unless asked to skip the missing names.
    let lenient = Options {
        skip_missing_topics: true,
        ..options.clone()
    };
    let export = write_parquet(&log, &dir, &lenient).unwrap();
    assert_eq!(export.files.len(), 2, "{:?}", export.files);
    match &export.missing_topics[..] {
        [LookupError::Topic(missing)] => assert_eq!(missing.closest, ["esc_status"]),
        other => panic!("{other:?}"),
    }
    std::fs::remove_dir_all(&dir).unwrap();
    // None of the names: still an error.
    let none = Options {
        topics: Some(vec!["esc_statsu".into()]),
        ..lenient
    };
    let err = write_parquet(&log, &dir, &none).unwrap_err();
    assert!(matches!(err.kind(), ExportErrorKind::Lookup(_)), "{err}");
    assert!(!dir.exists());

    let options = Options {
        topics: Some(vec!["battery_status".into()]),
        ..Options::default()
    };
    let export = write_parquet(&log, &dir, &options).unwrap();
    let names: Vec<(String, u8)> = export
        .files
        .iter()
        .map(|w| (w.topic.clone(), w.multi_id))
        .collect();
    assert_eq!(
        names,
        [("battery_status".into(), 0), ("battery_status".into(), 1)]
    );
    std::fs::remove_dir_all(&dir).unwrap();

    // A topic of padding only, and one whose nested type is undefined.
    let mut b = LogBuilder::new(1, 0);
    b.format("pad:uint8_t[4] _padding0;");
    b.format("broken:uint64_t timestamp;missing m;");
    b.format("ok:uint64_t timestamp;");
    b.subscribe(0, 0, "pad");
    b.subscribe(0, 1, "broken");
    b.subscribe(0, 2, "ok");
    b.data(0, &[0; 4]);
    b.data(1, &[0; 8]);
    b.data(2, &5u64.to_le_bytes());
    let log = ULog::parse(b.bytes()).unwrap();
    let dir = scratch("skipped");
    let export = write_parquet(&log, &dir, &Options::default()).unwrap();
    assert_eq!(export.files.len(), 1);
    assert_eq!(export.files[0].topic, "ok");
    let skipped: Vec<&str> = export.skipped.iter().map(|s| s.topic.as_str()).collect();
    assert_eq!(skipped, ["broken", "pad"]);
    assert!(matches!(
        export.skipped[0].error.kind(),
        ExportErrorKind::Lookup(LookupError::Layout { .. })
    ));
    assert_eq!(
        export.skipped[0].error.position(),
        Some(log.subscriptions()[1].offset())
    );
    assert!(matches!(
        export.skipped[1].error.kind(),
        ExportErrorKind::NoValues { .. }
    ));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn metadata_holds_what_the_log_holds() {
    let bytes = crate::testing::sample_log();
    let log = ULog::parse(&bytes).unwrap();
    let json: serde_json::Value = serde_json::from_str(&metadata_json(&log)).unwrap();
    assert_eq!(json["version"], 1);
    assert_eq!(json["start_timestamp"], log.start_timestamp());
    assert_eq!(json["last_timestamp"], log.last_timestamp());
    assert_eq!(json["damaged"], false);
    assert_eq!(json["info"]["sys_name"], "PX4");
    assert_eq!(json["info"]["ver_sw_release"], 0x010e_03ff);
    assert_eq!(json["info"]["time_ref_utc"], 0);
    assert_eq!(
        json["multi_info"]["boot_console"],
        serde_json::json!([["line 1", "line 2"]])
    );
    assert_eq!(json["parameters"]["MAV_TYPE"], 2);
    assert_eq!(json["parameters"]["MPC_XY_VEL_MAX"], 12.0);
    let changed = json["changed_parameters"].as_array().unwrap();
    assert_eq!(changed.len(), log.param_changes().len());
    assert_eq!(changed[0]["name"], "MPC_XY_VEL_MAX");
    assert_eq!(changed[0]["value"], 8.0);
    assert_eq!(changed[0]["timestamp"], log.param_changes()[0].timestamp);
    let defaults = json["default_parameters"].as_array().unwrap();
    assert_eq!(defaults[1]["name"], "MAV_TYPE");
    assert_eq!(defaults[1]["default_types"], 3);
    assert_eq!(defaults[1]["value"], 1);
    let messages = json["logged_messages"].as_array().unwrap();
    assert_eq!(messages.len(), 3);
    assert_eq!(messages[0]["text"], "[commander] Takeoff detected");
    assert_eq!(messages[0]["level"], "INFO");
    assert_eq!(messages[0]["tag"], serde_json::Value::Null);
    assert_eq!(messages[1]["level"], "WARNING");
    assert_eq!(messages[1]["tag"], 1);
    assert_eq!(json["dropouts"][0]["duration_ms"], 12);
    assert_eq!(json["findings"], serde_json::json!([]));
    let topics = json["topics"].as_array().unwrap();
    assert_eq!(topics.len(), 5);
    assert_eq!(topics[3]["name"], "battery_status");
    assert_eq!(topics[3]["multi_id"], 1);
    assert_eq!(topics[3]["rows"], 20);
}

#[test]
fn metadata_escapes_text_and_keeps_odd_values() {
    let mut b = LogBuilder::new(1, 0);
    b.info("char[6] quote", b"a\"b\\\n\0");
    b.info("float nan", &f32::NAN.to_le_bytes());
    b.info("uint64_t big", &u64::MAX.to_le_bytes());
    b.info("int16_t[2] pair", &[0xff, 0xff, 2, 0]);
    b.info("uint32_t short", &[1, 2]);
    b.info("char[2] quote", b"zz"); // the last value of a repeated key wins
    b.log(b'9', 5, "\u{e9}\x01");
    let log = ULog::parse(b.bytes()).unwrap();
    let text = metadata_json(&log);
    let json: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(json["info"]["quote"], "zz");
    assert_eq!(json["info"]["nan"], serde_json::Value::Null);
    assert_eq!(json["info"]["big"], u64::MAX);
    assert_eq!(json["info"]["pair"], serde_json::json!([-1, 2]));
    assert_eq!(json["info"]["short"], "0102");
    let m = &json["logged_messages"][0];
    assert_eq!(m["level"], serde_json::Value::Null);
    assert_eq!(m["level_raw"], u64::from(b'9'));
    // UTF-8 bytes c3 a9 are two characters, one per byte.
    assert_eq!(m["text"], "\u{c3}\u{a9}\u{1}");

    let mut b = LogBuilder::new(1, 0);
    b.info("char[6] quote", b"a\"b\\\n\0");
    let log = ULog::parse(b.bytes()).unwrap();
    let json: serde_json::Value = serde_json::from_str(&metadata_json(&log)).unwrap();
    assert_eq!(json["info"]["quote"], "a\"b\\\n");
}

/// A log with 100,000 information keys, each given twice: every key once, in the place
/// of its first message, with its last value (reliability issue, item 7: the names
/// were looked up one by one, so the time grew with the square of their number).
#[test]
fn metadata_of_many_keys_keeps_first_places_and_last_values() {
    let mut b = LogBuilder::new(1, 0);
    let n = 100_000u32;
    for round in 0..2u32 {
        for i in 0..n {
            b.info(&format!("uint32_t key_{i}"), &(i + round * n).to_le_bytes());
        }
    }
    let log = ULog::parse(b.bytes()).unwrap();
    let text = metadata_json(&log);
    let json: serde_json::Value = serde_json::from_str(&text).unwrap();
    let info = json["info"].as_object().unwrap();
    assert_eq!(info.len(), n as usize);
    assert_eq!(info["key_0"], n);
    assert_eq!(info["key_99999"], 2 * n - 1);
    // First places: the text names them in order.
    let (a, z) = (
        text.find("\"key_1\"").unwrap(),
        text.find("\"key_99998\"").unwrap(),
    );
    assert!(a < z);
}

#[test]
fn topics_written_on_several_threads_give_the_same_files_in_the_same_order() {
    let bytes = crate::testing::sample_log();
    let log = ULog::parse(&bytes).unwrap();
    let read_dir = |dir: &std::path::Path| {
        let mut files: Vec<(String, Vec<u8>)> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| {
                let p = e.unwrap().path();
                (p.display().to_string(), std::fs::read(&p).unwrap())
            })
            .collect();
        files.sort();
        files
    };
    let one = scratch("threads-1");
    let expected = write_parquet(&log, &one, &Options::default()).unwrap();
    assert!(expected.files.len() >= 3, "{:?}", expected.files);
    for threads in [2, 3, 64] {
        let dir = scratch(&format!("threads-{threads}"));
        let mut reported = Vec::new();
        let options = Options {
            threads,
            ..Options::default()
        };
        let export = write_parquet_with(&log, &dir, &options, |read| reported.push(read)).unwrap();
        let relative =
            |files: &[Written], root: &std::path::Path| -> Vec<(String, u8, PathBuf, usize)> {
                files
                    .iter()
                    .map(|w| {
                        (
                            w.topic.clone(),
                            w.multi_id,
                            w.path.strip_prefix(root).unwrap().to_owned(),
                            w.rows,
                        )
                    })
                    .collect()
            };
        assert_eq!(
            relative(&export.files, &dir),
            relative(&expected.files, &one)
        );
        // Progress only goes forward, within the log.
        assert!(reported.windows(2).all(|w| w[0] < w[1]), "{reported:?}");
        assert!(reported.iter().all(|&r| r < bytes.len() as u64));
        let (a, b) = (read_dir(&one), read_dir(&dir));
        assert_eq!(a.len(), b.len());
        for ((_, x), (_, y)) in a.iter().zip(&b) {
            assert!(x == y, "{threads} threads: a file differs");
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }
    // Read from a reader in chunks (a pipe, say), two bytes at a time: the same files.
    let dir = scratch("threads-reader");
    let trickle = Trickle(&bytes[..]);
    let options = Options {
        threads: 2,
        ..Options::default()
    };
    write_parquet(crate::Source::reader(trickle), &dir, &options).unwrap();
    assert!(read_dir(&one)
        .iter()
        .map(|(_, b)| b)
        .eq(read_dir(&dir).iter().map(|(_, b)| b)));
    std::fs::remove_dir_all(&dir).unwrap();
    std::fs::remove_dir_all(&one).unwrap();
}

/// A reader that gives at most two bytes a read.
struct Trickle<'a>(&'a [u8]);

impl std::io::Read for Trickle<'_> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let n = buf.len().min(2).min(self.0.len());
        buf[..n].copy_from_slice(&self.0[..n]);
        self.0 = &self.0[n..];
        Ok(n)
    }
}

#[test]
fn a_failed_export_leaves_no_partial_file_and_says_which_file() {
    let bytes = crate::testing::sample_log();
    let dir = scratch("failed");
    // A folder where a Parquet file should go: its rename fails.
    let blocker = dir.join("esc_status_0.parquet");
    std::fs::create_dir_all(blocker.join("inside")).unwrap();
    let options = Options {
        threads: 2,
        ..Options::default()
    };
    let err = write_parquet(&bytes, &dir, &options).unwrap_err();
    assert!(matches!(err.kind(), ExportErrorKind::Io(_)), "{err}");
    assert_eq!(err.path(), Some(blocker.as_path()), "{err}");
    let left: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(
        left,
        ["esc_status_0.parquet"],
        "only the folder that was there"
    );

    // Not a log at all: a read error, and the folder the export made is gone.
    let out = dir.join("new").join("deeper");
    let err = write_parquet(&b"not a log"[..], &out, &options).unwrap_err();
    assert_eq!(err.kind(), &ExportErrorKind::Read, "{err}");
    assert!(std::error::Error::source(&err).is_some());
    assert!(!dir.join("new").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A Parquet file's metadata and schema, and all its rows as one batch.
fn read_whole(
    path: &std::path::Path,
) -> (
    std::sync::Arc<parquet::file::metadata::ParquetMetaData>,
    arrow_schema::SchemaRef,
    RecordBatch,
) {
    let file = std::fs::File::open(path).unwrap();
    let builder = ParquetRecordBatchReaderBuilder::try_new(file).unwrap();
    let meta = builder.metadata().clone();
    let schema = builder.schema().clone();
    let mut back: Vec<RecordBatch> = builder
        .with_batch_size(1 << 20)
        .build()
        .unwrap()
        .map(|b| b.unwrap())
        .collect();
    assert_eq!(back.len(), 1);
    (meta, schema, back.pop().unwrap())
}

/// A log with a wide topic (flattened: 1,500 bytes, 60 structs of 4 fields and 3
/// structs of a nested array: more than `WIDE_LEAVES` columns) and the narrow
/// nested topic of [`nested_log`].
fn wide_log() -> Vec<u8> {
    let mut b = LogBuilder::new(1, 0);
    b.format("cell:uint16_t a;int8_t b;float c;char[3] d;");
    b.format("deep:cell[2] cells;uint32_t n;");
    b.format("wide:uint64_t timestamp;uint8_t[1500] raw;cell[60] cells;deep[3] deeps;");
    b.format("inner:uint32_t v;char[4] name;float[2] xy;uint8_t[2] _padding0;");
    b.format("outer:uint64_t timestamp;inner[2] items;int16_t[3] arr;");
    b.subscribe(0, 0, "wide");
    b.subscribe(0, 1, "outer");
    let cell = |p: &mut Vec<u8>, k: u32| {
        p.extend_from_slice(&(k as u16).to_le_bytes());
        p.push(k as u8 ^ 0x80);
        p.extend_from_slice(&(k as f32 / 3.0).to_le_bytes());
        p.extend_from_slice(&[b'a' + (k % 26) as u8, 0, b'z']);
    };
    for row in 0..5u32 {
        let mut p = (u64::from(row) * 1000).to_le_bytes().to_vec();
        p.extend((0..1500u32).map(|k| (k * 7 + row) as u8));
        for k in 0..60 {
            cell(&mut p, row * 60 + k);
        }
        for k in 0..3 {
            cell(&mut p, 1000 + k);
            cell(&mut p, 2000 + k);
            p.extend_from_slice(&(row + k).to_le_bytes());
        }
        b.data(0, &p);
        let mut q = (u64::from(row) * 1000 + 1).to_le_bytes().to_vec();
        for k in 0..2u32 {
            q.extend_from_slice(&(row * 10 + k).to_le_bytes());
            q.extend_from_slice(b"abcd");
            q.extend_from_slice(&(k as f32).to_le_bytes());
            q.extend_from_slice(&(row as f32).to_le_bytes());
            q.extend_from_slice(&[0, 0]);
        }
        for k in 0..3i16 {
            q.extend_from_slice(&(k * row as i16).to_le_bytes());
        }
        b.data(1, &q);
    }
    b.into_bytes()
}

#[test]
fn wide_and_narrow_topics_read_back_equal_on_any_thread_count() {
    use parquet::basic::Encoding;
    let bytes = wide_log();
    let log = ULog::parse(&bytes).unwrap();
    for flatten in [false, true] {
        let mut first: Option<Vec<Vec<u8>>> = None;
        for threads in [1, 3] {
            let options = Options {
                flatten,
                threads,
                row_group_rows: 2,
                ..Options::default()
            };
            let dir = scratch(&format!("wide-{flatten}-{threads}"));
            let export = write_parquet(&log, &dir, &options).unwrap();
            assert_eq!(export.files.len(), 2, "{:?}", export.skipped);
            let mut contents = Vec::new();
            for written in &export.files {
                let topic = log.topic(&written.topic, written.multi_id).unwrap();
                let ours = topic_record_batch(&topic, &options).unwrap();
                let (meta, schema, back) = read_whole(&written.path);
                assert_eq!(meta.num_row_groups(), 3, "5 rows in row groups of 2");
                assert_eq!(schema, ours.schema(), "{}", written.topic);
                for (a, b) in back.columns().iter().zip(ours.columns()) {
                    assert_eq!(a.to_data(), b.to_data(), "{}", written.topic);
                }
                // Wide tables: no dictionaries, no column index; narrow ones keep both.
                // (Nested, `wide` is 11 leaves: an array is one list column.)
                let wide = written.topic == "wide" && flatten;
                let leaves = meta.file_metadata().schema_descr().num_columns();
                assert_eq!(wide, leaves > 1024, "{} has {leaves} leaves", written.topic);
                let column = meta.row_group(0).column(1);
                assert_eq!(
                    column.encodings().contains(&Encoding::RLE_DICTIONARY),
                    !wide,
                    "{}: {:?}",
                    written.topic,
                    column.encodings()
                );
                assert_eq!(column.column_index_offset().is_some(), !wide);
                contents.push(std::fs::read(&written.path).unwrap());
            }
            match &first {
                None => first = Some(contents),
                Some(one) => assert!(one == &contents, "{threads} threads: a file differs"),
            }
            std::fs::remove_dir_all(&dir).unwrap();
        }
    }
}

#[test]
fn a_topic_whose_columns_read_no_byte_keeps_its_rows_on_any_thread_count() {
    let mut b = LogBuilder::new(1, 0);
    b.format("empty_text:char[0] s;");
    b.subscribe(0, 0, "empty_text");
    for _ in 0..5 {
        b.data(0, &[]);
    }
    let bytes = b.into_bytes();
    for threads in [1, 2] {
        let dir = scratch(&format!("char0-{threads}"));
        let options = Options {
            threads,
            buffer_bytes: 2,
            ..Options::default()
        };
        let export = write_parquet(&bytes, &dir, &options).unwrap();
        assert_eq!(export.files.len(), 1);
        assert_eq!(export.files[0].rows, 5);
        let (_, _, back) = read_whole(&export.files[0].path);
        assert_eq!(back.num_rows(), 5);
        assert!(back
            .column(0)
            .as_string::<i32>()
            .iter()
            .all(|s| s == Some("")));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}

#[test]
fn metadata_of_the_one_pass_export_is_the_parsed_logs_with_the_times_of_the_data() {
    let mut b = LogBuilder::new(1, 7);
    b.format("t:uint64_t timestamp;");
    // Misplaced flag bits (an unknown incompatible bit set): only a finding.
    b.flag_bits([0; 8], [0x80; 8], [0; 3]);
    b.param("int32_t P_A", &1i32.to_le_bytes());
    b.subscribe(0, 0, "t");
    b.data(0, &100u64.to_le_bytes());
    b.param("int32_t P_A", &2i32.to_le_bytes());
    b.data(0, &250u64.to_le_bytes());
    b.dropout(12);
    b.data(0, &200u64.to_le_bytes());
    b.param("int32_t P_A", &3i32.to_le_bytes());
    let bytes = b.into_bytes();
    let log = ULog::parse(&bytes).unwrap();
    assert!(!log.findings().is_empty());
    let dir = scratch("misplaced-flags");
    let export = write_parquet(&bytes, &dir, &Options::default()).unwrap();
    let text = std::fs::read_to_string(&export.metadata).unwrap();
    assert_eq!(text, metadata_json(&log));
    // The changes take the time of the data before them.
    let json: serde_json::Value = serde_json::from_str(&text).unwrap();
    let times: Vec<u64> = json["changed_parameters"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c["timestamp"].as_u64().unwrap())
        .collect();
    assert_eq!(times, [100, 250]);
    assert_eq!(json["dropouts"][0]["timestamp"], 250);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A log with topic `a` in two instances (rows interleaved), a GPS time, a parameter
/// change and a logged string.
fn two_instances_log() -> Vec<u8> {
    let mut b = LogBuilder::new(1, 0);
    b.info_str("sys_name", "Test");
    b.param("int32_t MAV_TYPE", &13i32.to_le_bytes());
    b.format("a:uint64_t timestamp;float x;");
    b.format("vehicle_gps_position:uint64_t timestamp;uint64_t time_utc_usec;");
    b.subscribe(0, 0, "a");
    b.subscribe(1, 1, "a");
    b.subscribe(0, 2, "vehicle_gps_position");
    for i in 0..10u64 {
        let mut p = (1000 + i).to_le_bytes().to_vec();
        p.extend_from_slice(&(i as f32).to_le_bytes());
        b.data((i % 2) as u16, &p);
    }
    let mut p = 2000u64.to_le_bytes().to_vec();
    p.extend_from_slice(&1_700_000_000_002_000u64.to_le_bytes());
    b.data(2, &p);
    b.param("int32_t MAV_TYPE", &2i32.to_le_bytes());
    b.log(3, 1500, "an error");
    b.into_bytes()
}

#[test]
fn a_dataset_file_holds_every_instance_of_a_topic_with_its_log_and_instance() {
    let dir = scratch("dataset_instances");
    let log = dir.with_extension("ulg");
    std::fs::write(&log, two_instances_log()).expect("write");
    let dataset = Dataset::open(&dir, &Options::default()).expect("open");
    let Added::Written { log_id, export } = dataset.add(&log, None, |_| {}).expect("add") else {
        panic!("a new dataset has no log")
    };
    assert_eq!(log_id.len(), 16);
    assert_eq!(
        export.files.len(),
        2,
        "a and vehicle_gps_position: one file each"
    );
    assert_eq!(export.files[0].rows, 10, "both instances");
    dataset.finish().expect("finish");

    let (schema, a) = read_back(&dir.join("a").join(format!("{log_id}.parquet")));
    let names: Vec<&str> = schema.fields().iter().map(|f| f.name().as_str()).collect();
    assert_eq!(names, ["log_id", "multi_id", "timestamp", "x"]);
    assert!(!schema.metadata().contains_key("ulog.multi_id"));
    assert_eq!(a.num_rows(), 10);
    let ids = a.column(0).as_string::<i32>();
    assert!(ids.iter().all(|id| id == Some(log_id.as_str())));
    let multi: Vec<u8> = a.column(1).as_primitive::<UInt8Type>().values().to_vec();
    let x: Vec<f32> = a.column(3).as_primitive::<Float32Type>().values().to_vec();
    // Each row keeps its instance: x is even in instance 0, odd in 1.
    for (m, x) in multi.iter().zip(&x) {
        assert_eq!(u32::from(*m), *x as u32 % 2);
    }
    assert_eq!(multi.iter().filter(|&&m| m == 1).count(), 5);

    let (_, logs) = read_back(&dir.join(LOGS_FILE));
    assert_eq!(logs.num_rows(), 1);
    let text = |name: &str| {
        logs.column_by_name(name)
            .unwrap()
            .as_string::<i32>()
            .value(0)
            .to_owned()
    };
    assert_eq!(text("sys_name"), "Test");
    assert_eq!(text("vehicle_type"), "hexarotor", "the initial MAV_TYPE");
    // The id and the hash, as other implementations give them (the fleet test checks
    // both against Python's xxhash and hashlib on the corpus).
    let bytes = two_instances_log();
    assert_eq!(
        log_id,
        format!("{:016x}", xxhash_rust::xxh3::xxh3_64(&bytes))
    );
    let sha: String = <sha2::Sha256 as sha2::Digest>::digest(&bytes)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect();
    assert_eq!(text("sha256"), sha);
    // The GPS time of the row at 2000 µs, taken during the pass, at the log's start:
    // its first timestamp (1000 µs), as the header has none (`ULog::span`).
    let utc = logs
        .column_by_name("start_utc")
        .unwrap()
        .as_primitive::<arrow_array::types::TimestampMicrosecondType>();
    assert_eq!(utc.value(0), 1_700_000_000_001_000);
    let (_, params) = read_back(&dir.join(PARAMETERS_FILE));
    let kinds: Vec<&str> = params
        .column_by_name("kind")
        .unwrap()
        .as_string::<i32>()
        .iter()
        .flatten()
        .collect();
    assert_eq!(kinds, ["initial", "changed"]);
    let (_, messages) = read_back(&dir.join(MESSAGES_FILE));
    assert_eq!(
        messages
            .column_by_name("text")
            .unwrap()
            .as_string::<i32>()
            .value(0),
        "an error"
    );
    assert_eq!(
        messages
            .column_by_name("level")
            .unwrap()
            .as_string::<i32>()
            .value(0),
        "ERROR"
    );
    let (_, formats) = read_back(&dir.join(FORMATS_FILE));
    assert_eq!(formats.num_rows(), 2);

    // Again: present, nothing written.
    let dataset = Dataset::open(&dir, &Options::default()).expect("open again");
    assert_eq!(dataset.len(), 1);
    assert!(dataset.contains(&log_id));
    assert!(matches!(
        dataset.add(&log, None, |_| {}),
        Ok(Added::Present { .. })
    ));
    let _ = std::fs::remove_dir_all(&dir);
    let _ = std::fs::remove_file(&log);
}

#[test]
fn a_log_that_fails_leaves_the_dataset_as_it_was() {
    let dir = scratch("dataset_failure");
    let bad = dir.with_extension("ulg");
    std::fs::write(&bad, b"this is not a log").expect("write");
    let dataset = Dataset::open(&dir, &Options::default()).expect("open");
    let e = dataset.add(&bad, None, |_| {}).expect_err("not a log");
    assert_eq!(e.kind(), &ExportErrorKind::Read);
    assert!(dataset.is_empty());
    dataset.finish().expect("finish");
    let mut left: Vec<String> = std::fs::read_dir(&dir)
        .expect("dir")
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    left.sort();
    assert_eq!(
        left,
        [
            ANALYSIS_FILE,
            FLIGHTS_FILE,
            FORMATS_FILE,
            LOGS_FILE,
            MESSAGES_FILE,
            PARAMETERS_FILE
        ],
        "the six tables, empty, and nothing else"
    );
    assert_eq!(read_back_rows(&dir.join(LOGS_FILE)), 0);

    // A table with other columns is an error that names it.
    std::fs::copy(dir.join(FORMATS_FILE), dir.join(LOGS_FILE)).expect("copy");
    let e = Dataset::open(&dir, &Options::default()).expect_err("other columns");
    assert!(matches!(e.kind(), ExportErrorKind::Dataset { .. }));
    assert_eq!(e.path(), Some(dir.join(LOGS_FILE).as_path()));

    // A table of the right columns whose ids were made by another rule (as the
    // SHA-256 of earlier versions, which recorded none) is refused: the same log
    // would come in twice.
    let formats = std::fs::File::open(dir.join(FORMATS_FILE)).expect("open");
    let schema = parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder::try_new(formats)
        .expect("read")
        .schema()
        .clone();
    let file = std::fs::File::create(dir.join(FORMATS_FILE)).expect("create");
    let writer = parquet::arrow::ArrowWriter::try_new(file, schema, None).expect("writer");
    writer.close().expect("close");
    std::fs::remove_file(dir.join(LOGS_FILE)).expect("remove");
    let e = Dataset::open(&dir, &Options::default()).expect_err("no rule");
    assert!(
        e.to_string().contains("log ids were made by another rule"),
        "{e}"
    );
    assert_eq!(e.path(), Some(dir.join(FORMATS_FILE).as_path()));
    let _ = std::fs::remove_dir_all(&dir);
    let _ = std::fs::remove_file(&bad);
}

fn read_back_rows(path: &std::path::Path) -> i64 {
    let file = std::fs::File::open(path).expect("open");
    ParquetRecordBatchReaderBuilder::try_new(file)
        .expect("reader")
        .metadata()
        .file_metadata()
        .num_rows()
}

#[test]
fn a_wide_topic_in_two_instances_keeps_both_in_its_dataset_file() {
    // 1,101 leaf columns flattened: a wide table, written after the pass.
    let mut b = LogBuilder::new(1, 0);
    b.format("w:uint64_t timestamp;uint8_t[1100] x;");
    b.subscribe(0, 0, "w");
    b.subscribe(1, 1, "w");
    for i in 0..6u64 {
        let mut p = (1000 + i).to_le_bytes().to_vec();
        p.extend(std::iter::repeat((i % 2) as u8).take(1100));
        b.data((i % 2) as u16, &p);
    }
    let dir = scratch("dataset_wide");
    let log = dir.with_extension("ulg");
    std::fs::write(&log, b.into_bytes()).expect("write");
    let options = Options {
        flatten: true,
        ..Options::default()
    };
    let dataset = Dataset::open(&dir, &options).expect("open");
    let Added::Written { log_id, export } = dataset.add(&log, None, |_| {}).expect("add") else {
        panic!("a new dataset has no log")
    };
    assert_eq!(export.files.len(), 1);
    assert_eq!(export.files[0].rows, 6);
    let (_, w) = read_back(&dir.join("w").join(format!("{log_id}.parquet")));
    assert_eq!(w.num_rows(), 6, "both instances' rows");
    let multi = w.column(1).as_primitive::<UInt8Type>();
    let first = w
        .column_by_name("x[0]")
        .unwrap()
        .as_primitive::<UInt8Type>();
    for i in 0..6 {
        assert_eq!(multi.value(i), first.value(i), "row {i} keeps its instance");
    }
    // The same options again are fine; the other flattening is refused, naming why.
    dataset.finish().expect("finish");
    Dataset::open(&dir, &options).expect("same options");
    let e = Dataset::open(&dir, &Options::default()).expect_err("other flattening");
    assert!(e.to_string().contains("flattened"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
    let _ = std::fs::remove_file(&log);
}

/// Checks the file of topic `names[id]` at `path`: its name valid on every common
/// file system, its rows those of the topic, its real name in its metadata.
fn check_topic_file(path: &std::path::Path, names: &[String], id: usize) {
    let (schema, batch) = read_back(path);
    for part in path.components().rev().take(2) {
        let part = part.as_os_str().to_string_lossy();
        assert!(part.len() <= 200 && part.is_ascii(), "{part}");
        assert!(
            !part.contains(['<', '>', ':', '"', '\\', '|', '?', '*']),
            "{part}"
        );
    }
    assert_eq!(
        schema.metadata()["ulog.topic"],
        names[id],
        "{}",
        path.display()
    );
    let n = batch
        .column_by_name("n")
        .unwrap()
        .as_primitive::<UInt32Type>();
    assert_eq!(n.len(), id + 1, "{}", names[id]);
    assert!(n.iter().all(|v| v == Some(id as u32)), "{}", names[id]);
}

#[test]
fn topic_names_a_file_system_refuses_or_folds_keep_every_row() {
    let (bytes, names) = crate::testing::awkward_names_log();
    let folded = |p: &std::path::Path| p.to_string_lossy().to_lowercase();

    // A log's folder: one file per topic, names distinct in any case.
    let dir = scratch("awkward_names");
    let written = write_parquet(&bytes, &dir, &Options::default()).unwrap();
    assert!(written.skipped.is_empty(), "{:?}", written.skipped);
    assert_eq!(written.files.len(), names.len());
    let mut seen = std::collections::HashSet::new();
    for f in &written.files {
        let id = names.iter().position(|n| *n == f.topic).unwrap();
        check_topic_file(&f.path, &names, id);
        assert!(seen.insert(folded(&f.path)), "{}", f.path.display());
    }
    let file_of = |topic: &str| {
        let f = written.files.iter().find(|f| f.topic == topic).unwrap();
        f.path.file_name().unwrap().to_string_lossy().into_owned()
    };
    // PX4's names and a lone case are kept; the others escaped.
    assert_eq!(file_of("vehicle_status"), "vehicle_status_0.parquet");
    assert_eq!(file_of("foo"), "foo_0.parquet");
    assert_eq!(file_of("a_b"), "a_b_0.parquet");
    assert!(file_of("a/b").starts_with("a_b~"), "{}", file_of("a/b"));
    assert!(file_of("CON").starts_with("CON~"), "{}", file_of("CON"));
    assert!(file_of("Foo").starts_with("Foo~"), "{}", file_of("Foo"));
    // The library's name of each file is the one written.
    let log = ULog::parse(&bytes).unwrap();
    for t in log.topics() {
        assert_eq!(file_name(&t), file_of(t.name()));
    }

    // A dataset: one folder per topic, distinct in any case, every row in.
    let ds = scratch("awkward_dataset");
    let path = ds.with_extension("ulg");
    std::fs::write(&path, &bytes).unwrap();
    let dataset = Dataset::open(&ds, &Options::default()).unwrap();
    let Added::Written { log_id, export } = dataset.add(&path, None, |_| {}).unwrap() else {
        panic!("a new dataset has no log")
    };
    dataset.finish().unwrap();
    assert!(export.skipped.is_empty(), "{:?}", export.skipped);
    assert_eq!(export.files.len(), names.len());
    let mut seen = std::collections::HashSet::new();
    for f in &export.files {
        let id = names.iter().position(|n| *n == f.topic).unwrap();
        assert_eq!(
            f.path.file_name().unwrap().to_string_lossy(),
            format!("{log_id}.parquet")
        );
        let folder = f.path.parent().unwrap();
        assert_eq!(
            folder.file_name().unwrap().to_string_lossy(),
            crate::naming::folder_name(&names[id])
        );
        assert!(seen.insert(folded(folder)), "{}", folder.display());
        check_topic_file(&f.path, &names, id);
    }
    assert!(ds.join("vehicle_status").is_dir());
    assert!(ds.join("foo").is_dir());
    assert!(!ds.join("FOO").exists() && !ds.join("CON").exists());
    let _ = std::fs::remove_dir_all(&dir);
    let _ = std::fs::remove_dir_all(&ds);
    let _ = std::fs::remove_file(&path);
}
