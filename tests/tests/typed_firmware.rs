//! One binding across firmware versions: optional fields (`Option<T>`,
//! `#[ulog(default)]`), renamed fields (aliases), instances read each on its own, topic
//! names that are not in the log, and mismatch reports that list every difference.

use ulog_core::testing::LogBuilder;
use ulog_core::typed::{DifferenceKind, Plan, PlanKind, TypedErrorKind};
use ulog_core::{ULog, ULogMessage};
use ulog_format::{Format, Layout};

fn layout(texts: &[&str], name: &str) -> Layout {
    let formats: Vec<Format> = texts.iter().map(|t| Format::parse(t).unwrap()).collect();
    Layout::resolve(name, &formats).unwrap()
}

/// A GPS fix of every firmware: `int32_t` degrees·1e7 before 2023, `double` degrees
/// after; the satellite count under an older name; a noise figure that only some
/// firmware logs.
#[derive(ULogMessage, Debug, Clone, Copy, PartialEq)]
#[ulog(name = "vehicle_gps_position")]
struct GpsFix {
    timestamp: u64,
    lat: Option<i32>,
    latitude_deg: Option<f64>,
    #[ulog(alias = "satellites")]
    satellites_used: u8,
    #[ulog(default = -1.0)]
    noise_per_ms: f32,
    #[ulog(default)]
    jamming_indicator: u16,
}

const OLD_GPS: &str =
    "vehicle_gps_position:uint64_t timestamp;int32_t lat;uint8_t satellites;uint8_t[3] _padding0;";
const NEW_GPS: &str = "vehicle_gps_position:uint64_t timestamp;double latitude_deg;float noise_per_ms;uint16_t jamming_indicator;uint8_t satellites_used;uint8_t[1] _padding0;";

#[test]
fn one_struct_reads_an_old_and_a_new_format() {
    let old = Plan::<GpsFix>::new(&layout(&[OLD_GPS], "vehicle_gps_position")).unwrap();
    assert_eq!(old.kind(), PlanKind::Mapped);
    assert_eq!(old.present(), [true, false, false, false]);
    let mut p = 1u64.to_le_bytes().to_vec();
    p.extend_from_slice(&473_977_418i32.to_le_bytes());
    p.push(9);
    let fix = old.decode(&p).unwrap();
    assert_eq!(
        fix,
        GpsFix {
            timestamp: 1,
            lat: Some(473_977_418),
            latitude_deg: None,
            satellites_used: 9,
            noise_per_ms: -1.0,
            jamming_indicator: 0,
        }
    );
    assert!(old.why_mapped().unwrap().contains("not in the log"));

    let new = Plan::<GpsFix>::new(&layout(&[NEW_GPS], "vehicle_gps_position")).unwrap();
    assert_eq!(new.present(), [false, true, true, true]);
    let mut p = 2u64.to_le_bytes().to_vec();
    p.extend_from_slice(&47.3977418f64.to_le_bytes());
    p.extend_from_slice(&12.5f32.to_le_bytes());
    p.extend_from_slice(&40u16.to_le_bytes());
    p.push(11);
    let fix = new.decode(&p).unwrap();
    assert_eq!(
        (fix.lat, fix.latitude_deg, fix.satellites_used),
        (None, Some(47.3977418), 11)
    );
    assert_eq!((fix.noise_per_ms, fix.jamming_indicator), (12.5, 40));
}

#[test]
fn an_absent_required_field_is_still_a_difference() {
    let text = "vehicle_gps_position:uint64_t timestamp;int32_t lat;";
    let m = Plan::<GpsFix>::new(&layout(&[text], "vehicle_gps_position")).unwrap_err();
    let d: Vec<(&str, &DifferenceKind)> = m
        .differences
        .iter()
        .map(|d| (d.path.as_str(), &d.kind))
        .collect();
    assert_eq!(
        d,
        [(
            "satellites_used",
            &DifferenceKind::MissingField { closest: None }
        )],
        "only the required field: {m}"
    );
    assert_eq!(m.binding, "GpsFix");
}

/// A nested binding with an optional field, in an array.
#[derive(ULogMessage, Debug, Clone, Copy, PartialEq, Default)]
struct EscReport {
    timestamp: u64,
    esc_rpm: i32,
    esc_temperature: Option<f32>,
}

#[derive(ULogMessage, Debug, Clone, Copy, PartialEq)]
struct EscStatus {
    timestamp: u64,
    esc: [EscReport; 2],
    esc_online_flags: Option<u8>,
}

#[test]
fn nested_optional_fields_follow_the_nested_format() {
    let with = [
        "esc_report:uint64_t timestamp;int32_t esc_rpm;float esc_temperature;",
        "esc_status:uint64_t timestamp;esc_report[2] esc;uint8_t esc_online_flags;",
    ];
    let without = [
        "esc_report:uint64_t timestamp;int32_t esc_rpm;",
        "esc_status:uint64_t timestamp;esc_report[2] esc;",
    ];
    let plan = Plan::<EscStatus>::new(&layout(&with, "esc_status")).unwrap();
    assert_eq!(plan.kind(), PlanKind::Exact);
    let mut p = 7u64.to_le_bytes().to_vec();
    for k in 0..2u64 {
        p.extend_from_slice(&(100 + k).to_le_bytes());
        p.extend_from_slice(&(1000 + k as i32).to_le_bytes());
        p.extend_from_slice(&(20.5 + k as f32).to_le_bytes());
    }
    p.push(3);
    let v = plan.decode(&p).unwrap();
    assert_eq!(v.esc[1].esc_temperature, Some(21.5));
    assert_eq!(v.esc_online_flags, Some(3));

    let plan = Plan::<EscStatus>::new(&layout(&without, "esc_status")).unwrap();
    assert_eq!(plan.kind(), PlanKind::Mapped);
    // Slots: `esc`'s nested `esc_temperature`, then `esc_online_flags`.
    assert_eq!(plan.present(), [false, false]);
    let mut p = 7u64.to_le_bytes().to_vec();
    for k in 0..2u64 {
        p.extend_from_slice(&(100 + k).to_le_bytes());
        p.extend_from_slice(&(1000 + k as i32).to_le_bytes());
    }
    let v = plan.decode(&p).unwrap();
    assert_eq!(
        v.esc,
        [
            EscReport {
                timestamp: 100,
                esc_rpm: 1000,
                esc_temperature: None
            },
            EscReport {
                timestamp: 101,
                esc_rpm: 1001,
                esc_temperature: None
            }
        ]
    );
    assert_eq!(v.esc_online_flags, None);
}

#[test]
fn visiting_a_value_leaves_out_its_absent_fields() {
    let v = EscStatus {
        timestamp: 1,
        esc: [
            EscReport {
                timestamp: 2,
                esc_rpm: 3,
                esc_temperature: Some(4.5),
            },
            EscReport::default(),
        ],
        esc_online_flags: None,
    };
    let mut seen = Vec::new();
    v.visit_fields(&mut |path, value| seen.push(format!("{path}={value}")));
    assert_eq!(
        seen,
        [
            "timestamp=1",
            "esc[0].timestamp=2",
            "esc[0].esc_rpm=3",
            "esc[0].esc_temperature=4.5",
            "esc[1].timestamp=0",
            "esc[1].esc_rpm=0",
        ]
    );
}

/// A log with `battery_status` instances 0 and 2 subscribed before the format was
/// redefined, and instance 1 after: instance 1 has another layout.
fn battery_log() -> Vec<u8> {
    let mut b = LogBuilder::new(1, 0);
    b.format("battery_status:uint64_t timestamp;float voltage_v;float remaining;");
    b.subscribe(0, 0, "battery_status");
    b.subscribe(2, 2, "battery_status");
    b.format("battery_status:uint64_t timestamp;double voltage_v;");
    b.subscribe(1, 1, "battery_status");
    let row = |t: u64, v: f32| {
        [
            &t.to_le_bytes()[..],
            &v.to_le_bytes(),
            &0.5f32.to_le_bytes(),
        ]
        .concat()
    };
    b.data(0, &row(1, 16.0));
    b.data(2, &row(1, 15.0));
    b.data(
        1,
        &[&1u64.to_le_bytes()[..], &16.5f64.to_le_bytes()].concat(),
    );
    b.into_bytes()
}

#[derive(ULogMessage, Debug, Clone, Copy, PartialEq)]
struct BatteryStatus {
    timestamp: u64,
    voltage_v: f32,
}

#[test]
fn instances_are_read_each_on_its_own() {
    let bytes = battery_log();
    let log = ULog::parse(&bytes).unwrap();
    let instances: Vec<_> = log.read_instances::<BatteryStatus>().unwrap().collect();
    assert_eq!(instances.len(), 3);
    let v0 = instances[0]
        .as_ref()
        .unwrap()
        .iter()
        .next()
        .unwrap()
        .unwrap();
    assert_eq!(v0.voltage_v, 16.0);
    let e1 = instances[1].as_ref().map(|_| ()).unwrap_err();
    assert_eq!(e1.topic(), Some(("battery_status", 1)));
    assert!(matches!(e1.kind(), TypedErrorKind::Mismatch(_)), "{e1}");
    let v2 = instances[2]
        .as_ref()
        .unwrap()
        .iter()
        .next()
        .unwrap()
        .unwrap();
    assert_eq!(v2.voltage_v, 15.0);
    // The error says which subscription, on its first line.
    let first = e1.to_string().lines().next().unwrap().to_owned();
    assert!(
        first.starts_with(&format!(
            "topic `battery_status` instance 1 (subscribed at byte {}): the log's format",
            log.topic("battery_status", 1)
                .unwrap()
                .subscription()
                .offset()
        )),
        "{first}"
    );
}

/// A struct named otherwise than its topic, with no `name` attribute.
#[derive(ULogMessage, Debug)]
struct LocalPosition {
    timestamp: u64,
    x: f32,
}

#[test]
fn a_name_not_in_the_log_suggests_the_topics_and_says_where_it_came_from() {
    let mut b = LogBuilder::new(1, 0);
    b.format("vehicle_local_position:uint64_t timestamp;float x;");
    b.format("vehicle_local_position_setpoint:uint64_t timestamp;float x;");
    b.subscribe(0, 0, "vehicle_local_position");
    b.subscribe(0, 1, "vehicle_local_position_setpoint");
    let log = ULog::parse(b.bytes()).unwrap();
    let e = log.read::<LocalPosition>(0).map(|_| ()).unwrap_err();
    let TypedErrorKind::NotFound {
        missing,
        binding,
        named_after_struct,
    } = e.kind()
    else {
        panic!("{e}")
    };
    assert_eq!(missing.name, "local_position");
    assert_eq!(
        missing.closest,
        ["vehicle_local_position", "vehicle_local_position_setpoint"]
    );
    assert_eq!(binding.as_deref(), Some("LocalPosition"));
    assert!(named_after_struct);
    assert_eq!(e.position(), None, "no place in the file");
    let text = e.to_string();
    assert!(text.contains("#[ulog(name"), "{text}");
    assert!(!text.contains("at byte"), "{text}");

    // A wrong instance: the instances that exist, not a name.
    let e = log.read::<GpsFix>(0).map(|_| ()).unwrap_err();
    assert!(e.to_string().starts_with("no topic `vehicle_gps_position`"));
    let e = log.topic("vehicle_local_position", 3).unwrap_err();
    let ulog_core::LookupError::Topic(missing) = &e else {
        panic!("{e}")
    };
    assert_eq!(
        (
            missing.name.as_str(),
            missing.multi_id,
            &missing.instances[..]
        ),
        ("vehicle_local_position", Some(3), &[0u8][..])
    );
    assert_eq!(
        e.to_string(),
        "topic `vehicle_local_position` has no instance 3 (its instances: 0)"
    );
}

/// Every difference at every depth, once each, with paths (types the log's do not
/// widen to: a lossless widening is not a difference).
#[derive(ULogMessage, Debug)]
#[ulog(name = "esc_status")]
struct EscWrong {
    timestamp: u64,
    esc: [EscWrongReport; 4],
    count: i8,
}

#[derive(ULogMessage, Debug)]
#[ulog(name = "esc_report")]
struct EscWrongReport {
    esc_rpm: i8,
    esc_voltage: f32,
    esc_current: f32,
}

#[test]
fn a_mismatch_lists_every_difference_at_every_depth_once() {
    let l = layout(
        &[
            "esc_report:uint64_t timestamp;int16_t esc_rpm;float esc_voltage;",
            "esc_status:uint64_t timestamp;esc_report[8] esc;uint8_t count;",
        ],
        "esc_status",
    );
    let m = Plan::<EscWrong>::new(&l).unwrap_err();
    let d: Vec<String> = m.differences.iter().map(|d| d.to_string()).collect();
    assert_eq!(
        d,
        [
            "field `esc`: an array of 4 expected, the log has an array of 8",
            "field `esc[*].esc_rpm`: type `int8_t` expected, the log has `int16_t` (which does not widen to it without loss: declare a conversion, `#[ulog(convert(int16_t = path::to::function))]`)",
            "field `esc[*].esc_current`: missing in the log; if some firmware lacks it, make it `Option<_>` or give it #[ulog(default)]",
            "field `count`: type `int8_t` expected, the log has `uint8_t` (which does not widen to it without loss: declare a conversion, `#[ulog(convert(uint8_t = path::to::function))]`)",
        ]
    );
    let text = m.to_string();
    assert!(
        text.starts_with(
            "the log's format of `esc_status` does not fit binding `EscWrong` (4 differences)"
        ),
        "{text}"
    );
    assert!(text.ends_with("esc_status:uint64_t timestamp;esc_report[8] esc;uint8_t count;"));
}
