//! Bindings across changed field types and lengths, and renamed topics: lossless
//! widenings bind (`uint8_t` into `i32`, `float` into `f64`, a shorter array into a
//! longer one), other changes only through a conversion the field declares, and a
//! binding finds its topic under its aliases. The cross-firmware structs of
//! `ulog_examples::firmware` read every PX4 log of the corpus, value by value as
//! pyulog reads them.

use std::collections::HashMap;

use ulog_core::testing::LogBuilder;
use ulog_core::typed::{DifferenceKind, Plan, PlanKind};
use ulog_core::{ULog, ULogMessage, ULogTopics, Value};
use ulog_examples::firmware::{
    micros_to_seconds, BatteryStatus, GpsFix, SensorCombined, VehicleStatus,
};
use ulog_format::{Format, Layout};
use ulog_tests::{corpus_files, stem};

fn layout(text: &str) -> Layout {
    let format = Format::parse(text).unwrap();
    let name = format.name.clone();
    Layout::resolve(&name, &[format][..]).unwrap()
}

/// Little-endian bytes of each value, concatenated.
macro_rules! payload {
    ($($v:expr),* $(,)?) => {{
        let mut p: Vec<u8> = Vec::new();
        $(p.extend_from_slice(&$v.to_le_bytes());)*
        p
    }};
}

#[test]
fn a_narrower_integer_and_a_shorter_array_widen_into_the_binding() {
    // PX4 v1.14: `cell_count` a `uint8_t`, ten cells.
    let plan = Plan::<BatteryStatus>::new(&layout(
        "battery_status:uint64_t timestamp;float voltage_v;float remaining;float[10] voltage_cell_v;uint8_t cell_count;",
    ))
    .unwrap();
    assert_eq!(plan.kind(), PlanKind::Mapped);
    assert!(
        plan.why_mapped().unwrap().contains("in the log"),
        "{:?}",
        plan.why_mapped()
    );
    let cells: Vec<f32> = (0..10).map(|i| 3.5 + i as f32 / 100.0).collect();
    let mut p = payload!(7u64, 16.2f32, 0.75f32);
    for c in &cells {
        p.extend_from_slice(&c.to_le_bytes());
    }
    p.push(200);
    let b = plan.decode(&p).unwrap();
    assert_eq!(
        b.cell_count, 200,
        "an unsigned byte stays unsigned in an i32"
    );
    let got = b.voltage_cell_v.unwrap();
    assert_eq!(&got[..10], &cells[..]);
    assert_eq!(&got[10..], &[0.0; 4], "cells beyond the log's are zeros");
    assert_eq!(b.discharged_mah, None);

    // PX4 v1.8: `int32_t`, no cells.
    let plan = Plan::<BatteryStatus>::new(&layout(
        "battery_status:uint64_t timestamp;float voltage_v;float remaining;int32_t cell_count;",
    ))
    .unwrap();
    let b = plan
        .decode(&payload!(1u64, 12.0f32, 0.5f32, -3i32))
        .unwrap();
    assert_eq!((b.cell_count, b.voltage_cell_v), (-3, None));
}

#[test]
fn every_lossless_widening_reads_the_exact_value() {
    #[derive(ULogMessage, Debug, PartialEq)]
    #[ulog(name = "wide")]
    struct Wide {
        a: i16,
        b: u64,
        c: f64,
        d: f32,
        e: i64,
        f: [f64; 2],
        g: u16,
    }
    let plan = Plan::<Wide>::new(&layout(
        "wide:int8_t a;uint32_t b;float c;int16_t d;int32_t e;float[2] f;bool g;",
    ))
    .unwrap();
    let third = 1.0f32 / 3.0;
    let mut p = payload!(
        -128i8,
        u32::MAX,
        third,
        i16::MIN,
        i32::MIN,
        0.1f32,
        f32::NAN
    );
    p.push(1);
    let w = plan.decode(&p).unwrap();
    assert_eq!(
        (w.a, w.b, w.c, w.d, w.e, w.g),
        (
            -128,
            u64::from(u32::MAX),
            f64::from(third),
            -32768.0,
            i64::from(i32::MIN),
            1
        )
    );
    assert_eq!(w.f[0], f64::from(0.1f32));
    assert!(w.f[1].is_nan());
}

#[test]
fn a_change_that_loses_values_is_refused_with_the_way_to_declare_it() {
    #[derive(ULogMessage, Debug)]
    #[ulog(name = "narrow")]
    struct Narrow {
        count: u8,
        dt: f32,
        signed: u32,
        cells: [f32; 4],
    }
    let m = Plan::<Narrow>::new(&layout(
        "narrow:int32_t count;uint32_t dt;int8_t signed;float[10] cells;",
    ))
    .unwrap_err();
    let found: Vec<(&str, &DifferenceKind)> = m
        .differences
        .iter()
        .map(|d| (d.path.as_str(), &d.kind))
        .collect();
    assert_eq!(found.len(), 4, "{found:?}");
    for (path, log) in [
        ("count", "int32_t"),
        ("dt", "uint32_t"),
        ("signed", "int8_t"),
    ] {
        let d = m.differences.iter().find(|d| d.path == path).unwrap();
        assert!(
            matches!(&d.kind, DifferenceKind::Type { found, .. } if found == log),
            "{d:?}"
        );
        let text = d.to_string();
        assert!(
            text.contains(&format!("convert({log} = ")),
            "the text names the fix: {text}"
        );
    }
    assert!(m.differences.iter().any(|d| d.path == "cells"
        && matches!(
            d.kind,
            DifferenceKind::ArrayLength {
                expected: Some(4),
                found: Some(10)
            }
        )));
}

#[test]
fn a_declared_conversion_reads_the_other_type() {
    // PX4 v1.11: microseconds in a `uint32_t`.
    let new = Plan::<SensorCombined>::new(&layout(
        "sensor_combined:uint64_t timestamp;float[3] gyro_rad;uint32_t gyro_integral_dt;int32_t accelerometer_timestamp_relative;float[3] accelerometer_m_s2;uint32_t accelerometer_integral_dt;",
    ))
    .unwrap();
    let p = payload!(9u64, 0.1f32, 0.2f32, 0.3f32, 4000u32, -2i32, 1.0f32, 2.0f32, 9.8f32, 4016u32);
    let s = new.decode(&p).unwrap();
    assert_eq!(s.gyro_integral_dt, micros_to_seconds(4000));
    assert_eq!(s.accelerometer_integral_dt, micros_to_seconds(4016));
    assert_eq!(s.accelerometer_m_s2, [1.0, 2.0, 9.8]);
    // PX4 v1.7: seconds in a `float`, read as they are.
    let old = Plan::<SensorCombined>::new(&layout(
        "sensor_combined:uint64_t timestamp;float[3] gyro_rad;float gyro_integral_dt;int32_t accelerometer_timestamp_relative;float[3] accelerometer_m_s2;float accelerometer_integral_dt;",
    ))
    .unwrap();
    let p =
        payload!(9u64, 0.1f32, 0.2f32, 0.3f32, 0.004f32, -2i32, 1.0f32, 2.0f32, 9.8f32, 0.005f32);
    let s = old.decode(&p).unwrap();
    assert_eq!(
        (s.gyro_integral_dt, s.accelerometer_integral_dt),
        (0.004, 0.005)
    );
    // A type the field neither widens from nor declares is still refused.
    let m = Plan::<SensorCombined>::new(&layout(
        "sensor_combined:uint64_t timestamp;float[3] gyro_rad;uint64_t gyro_integral_dt;float[3] accelerometer_m_s2;float accelerometer_integral_dt;",
    ))
    .unwrap_err();
    assert_eq!(m.differences.len(), 1, "{m}");
    assert_eq!(m.differences[0].path, "gyro_integral_dt");
}

#[test]
fn fields_of_nested_array_elements_widen_too() {
    #[derive(ULogMessage, Debug, Clone, Copy, PartialEq)]
    #[ulog(name = "esc_report")]
    struct EscReport {
        esc_rpm: i32,
        esc_voltage: f64,
    }
    #[derive(ULogMessage, Debug, PartialEq)]
    #[ulog(name = "esc_status")]
    struct EscStatus {
        timestamp: u64,
        esc: [EscReport; 2],
    }
    let formats = [
        Format::parse("esc_report:int16_t esc_rpm;float esc_voltage;").unwrap(),
        Format::parse("esc_status:uint64_t timestamp;uint8_t esc_count;esc_report[2] esc;")
            .unwrap(),
    ];
    let layout = Layout::resolve("esc_status", &formats[..]).unwrap();
    let plan = Plan::<EscStatus>::new(&layout).unwrap();
    let mut p = payload!(5u64);
    p.push(2);
    // Each element is 6 bytes (ULog packs fields): int16, float.
    for (rpm, v) in [(-1200i16, 15.5f32), (3000, 15.25)] {
        p.extend_from_slice(&rpm.to_le_bytes());
        p.extend_from_slice(&v.to_le_bytes());
    }
    let s = plan.decode(&p).unwrap();
    assert_eq!(
        s.esc,
        [
            EscReport {
                esc_rpm: -1200,
                esc_voltage: 15.5
            },
            EscReport {
                esc_rpm: 3000,
                esc_voltage: 15.25
            }
        ]
    );
}

/// A log with the GPS topics `names` says, three rows each.
fn gps_log(names: Names) -> Vec<u8> {
    let mut b = LogBuilder::new(1, 0);
    b.format("vehicle_gps_position:uint64_t timestamp;int32_t lat;int32_t lon;int32_t alt;uint8_t fix_type;uint8_t satellites_used;");
    b.format("sensor_gps:uint64_t timestamp;double latitude_deg;double longitude_deg;double altitude_msl_m;uint8_t fix_type;uint8_t satellites_used;");
    b.format("vehicle_status:uint64_t timestamp;uint8_t arming_state;uint8_t nav_state;uint8_t system_id;");
    b.subscribe(0, 0, "vehicle_status");
    if names == Names::Both {
        b.subscribe(0, 1, "vehicle_gps_position");
    }
    if names != Names::Neither {
        b.subscribe(0, 2, "sensor_gps");
        b.subscribe(1, 3, "sensor_gps");
    }
    for t in 1..=3u64 {
        let mut p = payload!(t * 1000);
        p.extend_from_slice(&[1, 0, 1]);
        b.data(0, &p);
        if names == Names::Both {
            let mut p = payload!(t * 1000, 473_977_418i32, 85_455_940i32, 488_000i32);
            p.extend_from_slice(&[3, 10]);
            b.data(1, &p);
        }
        if names != Names::Neither {
            let mut p = payload!(t * 1000, 47.3977418f64, 8.545594f64, 488.0f64);
            p.extend_from_slice(&[3, 12]);
            b.data(2, &p);
            let mut p = payload!(t * 1000, 0.0f64, 0.0f64, 0.0f64);
            p.extend_from_slice(&[1, 4]);
            b.data(3, &p);
        }
    }
    b.into_bytes()
}

#[test]
fn a_binding_finds_its_topic_under_an_alias() {
    assert_eq!(GpsFix::NAME, "vehicle_gps_position");
    assert_eq!(GpsFix::ALIASES, ["sensor_gps"]);
    // Only the alias: read, read_instances and scan_topics find it.
    let bytes = gps_log(Names::Alias);
    let log = ULog::parse(&bytes).unwrap();
    let rows = log.read::<GpsFix>(0).unwrap();
    assert_eq!(rows.topic().name(), "sensor_gps");
    let fixes: Vec<GpsFix> = rows.iter().map(Result::unwrap).collect();
    assert_eq!(fixes.len(), 3);
    assert_eq!(fixes[0].latitude_deg, Some(47.3977418));
    assert_eq!(fixes[0].lat, None);
    assert_eq!(fixes[0].satellites_used, 12);
    let instances: Vec<_> = log.read_instances::<GpsFix>().unwrap().collect();
    assert_eq!(instances.len(), 2);
    assert_eq!(instances[1].as_ref().unwrap().topic().multi_id(), 1);

    #[derive(ULogTopics, Debug)]
    enum Topics {
        Gps(GpsFix),
        #[allow(dead_code)]
        Status(VehicleStatus),
    }
    let mut seen = Vec::new();
    ulog_core::scan_topics::<Topics>(&bytes[..], &ulog_core::ScanOptions::default(), |record| {
        let record = record.unwrap();
        if let Some(Topics::Gps(g)) = record.message {
            seen.push((record.topic.multi_id(), g.satellites_used));
        }
    })
    .unwrap();
    assert_eq!(seen, [(0, 12), (1, 4), (0, 12), (1, 4), (0, 12), (1, 4)]);

    // Both names: the binding's own name first.
    let bytes = gps_log(Names::Both);
    let log = ULog::parse(&bytes).unwrap();
    let rows = log.read::<GpsFix>(0).unwrap();
    assert_eq!(rows.topic().name(), "vehicle_gps_position");
    let fix = rows.iter().next().unwrap().unwrap();
    assert_eq!((fix.lat, fix.satellites_used), (Some(473_977_418), 10));
    assert_eq!(log.read_instances::<GpsFix>().unwrap().len(), 1);
    // Instance 1 exists only under the alias.
    assert_eq!(log.read::<GpsFix>(1).unwrap().topic().name(), "sensor_gps");

    // Neither: the error says both names.
    let bytes = gps_log(Names::Neither);
    let log = ULog::parse(&bytes).unwrap();
    let Err(e) = log.read::<GpsFix>(0) else {
        panic!("no GPS topic to read")
    };
    let e = e.to_string();
    assert!(
        e.contains("no topic `vehicle_gps_position` or `sensor_gps` in the log"),
        "{e}"
    );
}

/// Which GPS topics [`gps_log`] has.
#[derive(Clone, Copy, PartialEq)]
enum Names {
    /// `sensor_gps` (instances 0 and 1).
    Alias,
    /// `vehicle_gps_position` (instance 0) and `sensor_gps` (0 and 1).
    Both,
    /// Neither.
    Neither,
}

/// pyulog's CSV of one topic instance: column names, then rows of cells.
fn pyulog_csv(stem: &str, topic: &str, multi_id: u8) -> Option<(Vec<String>, Vec<Vec<String>>)> {
    let path = ulog_tests::corpus_dir()
        .join("expected")
        .join(stem)
        .join("csv")
        .join(format!("{stem}_{topic}_{multi_id}.csv"));
    let text = std::fs::read_to_string(path).ok()?;
    let mut lines = text.lines();
    let header = lines.next()?.split(',').map(str::to_owned).collect();
    let rows = lines
        .map(|l| l.split(',').map(str::to_owned).collect())
        .collect();
    Some((header, rows))
}

/// The types of a topic's fields in pyulog's summary (`formats`).
fn log_types(summary: &serde_json::Value, topic: &str) -> HashMap<String, (String, u64)> {
    let fields = &summary["formats"][topic]["fields"];
    let fields = fields
        .as_array()
        .or_else(|| summary["formats"][topic].as_array())
        .cloned()
        .unwrap_or_default();
    fields
        .iter()
        .map(|f| {
            (
                f[2].as_str().unwrap().to_owned(),
                (f[0].as_str().unwrap().to_owned(), f[1].as_u64().unwrap()),
            )
        })
        .collect()
}

/// Whether our value (of the binding's type) is pyulog's cell of the log's type
/// `ty`: exactly, widened; for a field read through `micros_to_seconds`, that of
/// pyulog's microseconds.
fn same(ours: &Value<'_>, cell: &str, ty: &str, converted: bool) -> bool {
    let ours = ours.as_f64().unwrap();
    let theirs = match ty {
        "float" => cell.parse::<f32>().map(f64::from).ok(),
        "uint32_t" if converted => cell
            .parse::<u32>()
            .ok()
            .map(|us| f64::from(micros_to_seconds(us))),
        "uint64_t" => cell.parse::<u64>().ok().map(|v| v as f64),
        _ => cell.parse::<f64>().ok(),
    };
    match theirs {
        Some(t) if t.is_nan() => ours.is_nan(),
        Some(t) => t == ours,
        None => false,
    }
}

/// Reads every instance of `T` in a corpus log and compares each row with pyulog's
/// CSV; returns the values compared.
fn compare<T: ULogMessage>(stem: &str, log: &ULog<'_>, summary: &serde_json::Value) -> usize {
    let Ok(instances) = log.read_instances::<T>() else {
        assert!(
            T::names().all(|n| log.topic_instances(n).is_empty()),
            "{stem}: `{}` is in the log",
            T::NAME
        );
        return 0;
    };
    let mut values = 0;
    for rows in instances {
        let rows = rows.unwrap_or_else(|e| panic!("{stem}: `{}`: {e}", T::NAME));
        if rows.is_empty() {
            // pyulog writes no CSV of a topic without data.
            continue;
        }
        let topic = rows.topic();
        let types = log_types(summary, topic.name());
        let (header, csv) = pyulog_csv(stem, topic.name(), topic.multi_id())
            .unwrap_or_else(|| panic!("{stem}: no CSV of {}", topic.name()));
        let column: HashMap<&str, usize> = header
            .iter()
            .enumerate()
            .map(|(i, h)| (h.as_str(), i))
            .collect();
        let ours: Vec<T> = rows
            .iter()
            .map(|r| r.unwrap_or_else(|e| panic!("{stem}: {e}")))
            .collect();
        // pyulog skips the rows of damaged stretches we recover: match by timestamp.
        let ts = column["timestamp"];
        let mut k = 0;
        for cells in &csv {
            let t: u64 = cells[ts].parse().unwrap();
            while k < ours.len() && timestamp(&ours[k]) != t {
                k += 1;
            }
            let row = ours
                .get(k)
                .unwrap_or_else(|| panic!("{stem}: {}: no row at {t}", topic.name()));
            k += 1;
            row.visit_fields(&mut |path, value| {
                let base = path.split('[').next().unwrap();
                let Some((ty, _)) = types.get(base) else {
                    panic!("{stem}: `{path}` is not in the log's format")
                };
                match column.get(path) {
                    Some(&i) => {
                        let converted = ty == "uint32_t" && path.ends_with("integral_dt");
                        assert!(
                            same(&value, &cells[i], ty, converted),
                            "{stem}: {} at {t}: `{path}` is {value:?}, pyulog {} ({ty})",
                            topic.name(),
                            cells[i]
                        );
                        values += 1;
                    }
                    // An element beyond the log's shorter array.
                    None => assert_eq!(value.as_f64(), Some(0.0), "{stem}: `{path}`"),
                }
            });
        }
    }
    values
}

fn timestamp<T: ULogMessage>(row: &T) -> u64 {
    let mut t = 0;
    row.visit_fields(&mut |path, value| {
        if path == "timestamp" {
            t = value.as_u64().unwrap();
        }
    });
    t
}

/// The `flight_summary` example's structs, one per topic with no field left out for
/// firmware reasons, read every PX4 log of the corpus as pyulog reads it: every field
/// whose type changed (`cell_count`, `voltage_cell_v`, `*_integral_dt`, `system_id`),
/// and the GPS fix under either topic name.
#[test]
fn one_struct_per_topic_reads_every_firmware_like_pyulog() {
    let mut values = 0;
    let mut forms: HashMap<(&str, String), usize> = HashMap::new();
    for path in corpus_files() {
        let stem = stem(&path);
        let bytes = std::fs::read(&path).unwrap();
        let log = ULog::parse(&bytes).unwrap();
        let summary = ulog_tests::expected_summary(&path);
        values += compare::<BatteryStatus>(&stem, &log, &summary);
        values += compare::<SensorCombined>(&stem, &log, &summary);
        values += compare::<VehicleStatus>(&stem, &log, &summary);
        values += compare::<GpsFix>(&stem, &log, &summary);
        for (topic, field) in [
            ("battery_status", "cell_count"),
            ("battery_status", "voltage_cell_v"),
            ("sensor_combined", "gyro_integral_dt"),
            ("vehicle_status", "system_id"),
        ] {
            if let Some((ty, len)) = log_types(&summary, topic).get(field) {
                *forms.entry((field, format!("{ty}[{len}]"))).or_default() += 1;
            }
        }
        if !log.topic_instances("sensor_gps").is_empty() {
            *forms.entry(("gps", "sensor_gps".into())).or_default() += 1;
        } else if !log.topic_instances("vehicle_gps_position").is_empty() {
            *forms
                .entry(("gps", "vehicle_gps_position".into()))
                .or_default() += 1;
        }
    }
    eprintln!("{values} values; forms of the changed fields: {forms:?}");
    assert!(values > 0);
    if ulog_tests::FULL_CORPUS {
        // Every form the corpus has was read: both types of each changed field, all
        // three lengths of the cells, and the GPS under both names.
        for (field, form) in [
            ("cell_count", "int32_t[0]"),
            ("cell_count", "uint8_t[0]"),
            ("voltage_cell_v", "float[4]"),
            ("voltage_cell_v", "float[10]"),
            ("voltage_cell_v", "float[14]"),
            ("gyro_integral_dt", "float[0]"),
            ("gyro_integral_dt", "uint32_t[0]"),
            ("system_id", "uint32_t[0]"),
            ("system_id", "uint8_t[0]"),
            ("gps", "sensor_gps"),
            ("gps", "vehicle_gps_position"),
        ] {
            assert!(
                forms.contains_key(&(field, form.to_owned())),
                "{field} {form}: {forms:?}"
            );
        }
    }
}
