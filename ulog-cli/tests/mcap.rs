//! `ulog mcap`: the files it writes read back with readers we did not write —
//! Foxglove's `mcap` and `mcap-ros2-support` packages decode every message of every
//! corpus log with the schemas we wrote, and every value of every row equals this
//! reader's (nested types included), as do the logged strings on `/rosout` and the
//! parameters; the ROS 2 bag folder opens in `rosbags`.

mod common;

use std::collections::BTreeMap;
use std::path::Path;

use serde_json::Value as Json;
use sha2::{Digest, Sha256};
use ulog_core::format::{BasicType, Layout, LayoutType};
use ulog_core::read::Unwrapper;
use ulog_core::ULog;

/// What the Python readers make of an MCAP file (`scripts/mcap_read.py`), JSON
/// messages validated against their schemas: all of them, or the first `validate` of
/// each channel.
fn python_read(mcap: &Path, validate: Option<usize>) -> Json {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/scripts/mcap_read.py");
    let mut args = vec![script.into_os_string(), mcap.as_os_str().to_owned()];
    args.extend(validate.map(|n| n.to_string().into()));
    serde_json::from_slice(&common::python(args)).expect("JSON")
}

/// A float as the script prints it: the bits of its float64, `nan` for NaN; in
/// JSON, the float64 its shortest text parses to, and `null` if it is not finite.
fn float_text<F: std::fmt::Debug + Into<f64> + Copy>(v: F, json: bool) -> String {
    let wide: f64 = v.into();
    match (json, wide.is_finite()) {
        (true, false) => "null".to_owned(),
        (true, true) => {
            let parsed: f64 = format!("{v:?}").parse().unwrap();
            parsed.to_bits().to_string()
        }
        (false, _) if wide.is_nan() => "nan".to_owned(),
        (false, _) => wide.to_bits().to_string(),
    }
}

/// The values of a payload as ROS 2 messages hold them, depth first: the members
/// of the layout (no padding, no zero-length array), `char` as `uint8`; in JSON, a
/// `char[N]` is one text (up to its first NUL, a character per byte).
fn flatten(layout: &Layout, payload: &[u8], base: usize, json: bool, out: &mut Vec<String>) {
    for f in layout.fields() {
        if f.is_padding() || f.array_len == Some(0) {
            continue;
        }
        let count = f.array_len.unwrap_or(1);
        if let (true, LayoutType::Basic(BasicType::Char), Some(n)) = (json, &f.ty, f.array_len) {
            let bytes = &payload[base + f.offset..base + f.offset + n];
            let end = bytes.iter().position(|&b| b == 0).unwrap_or(n);
            out.push(bytes[..end].iter().map(|&b| char::from(b)).collect());
            continue;
        }
        match &f.ty {
            LayoutType::Basic(ty) => {
                for i in 0..count {
                    let at = base + f.offset + i * ty.size();
                    let b = &payload[at..at + ty.size()];
                    let mut a = [0u8; 8];
                    a[..b.len()].copy_from_slice(b);
                    let u = u64::from_le_bytes(a);
                    out.push(match ty {
                        BasicType::Float => float_text(f32::from_bits(u as u32), json),
                        BasicType::Double => float_text(f64::from_bits(u), json),
                        BasicType::Bool => u8::from(u != 0).to_string(),
                        BasicType::Int8 => (u as u8 as i8).to_string(),
                        BasicType::Int16 => (u as u16 as i16).to_string(),
                        BasicType::Int32 => (u as u32 as i32).to_string(),
                        BasicType::Int64 => (u as i64).to_string(),
                        _ => u.to_string(),
                    });
                }
            }
            LayoutType::Nested(inner) => {
                for i in 0..count {
                    flatten(
                        inner,
                        payload,
                        base + f.offset + i * inner.size(),
                        json,
                        out,
                    );
                }
            }
        }
    }
}

/// `builtin_interfaces/Time` values of a time in nanoseconds.
fn stamp(nanos: u64) -> [String; 2] {
    [
        (nanos / 1_000_000_000).to_string(),
        (nanos % 1_000_000_000).to_string(),
    ]
}

fn digest(lines: &[Vec<String>]) -> String {
    let mut h = Sha256::new();
    for l in lines {
        h.update(l.join(" ").as_bytes());
        h.update(b"\n");
    }
    format!("{:x}", h.finalize())
}

/// What the MCAP file of `log` holds per channel, as this reader sees the log: the
/// schema, and the lines the script hashes.
fn expected(log: &ULog<'_>, json: bool) -> BTreeMap<String, (String, Vec<Vec<String>>)> {
    let mut channels = BTreeMap::new();
    // Each message's log time and publish time: the time it was recorded, placed
    // in the log's span (before it: at the start; after it: at the end), and its
    // own timestamp.
    let span = log.span();
    let times = |t: u64| {
        let recorded = t.clamp(span.start(), span.end());
        [(recorded * 1000).to_string(), (t * 1000).to_string()]
    };
    for topic in log.topics() {
        let Ok(layout) = topic.layout() else { continue };
        if topic.is_empty() {
            continue;
        }
        // PX4's bridge's names, written out here rather than taken from the library.
        let schema = match topic.multi_id() {
            0 => format!("/fmu/out/{}", topic.name()),
            n => format!("/fmu/out/{}_{n}", topic.name()),
        };
        let mut clock = Unwrapper::new(topic.timestamp_field());
        let mut lines = Vec::new();
        for p in topic.payloads() {
            let t = clock.push(p).expect("a timestamp");
            let mut line = times(t).to_vec();
            flatten(layout, p, 0, json, &mut line);
            lines.push(line);
        }
        let type_name = format!("px4_msgs/msg/{}", camel(layout.name()));
        channels.insert(schema, (type_name, lines));
    }
    // Logged strings.
    let mut rosout = Vec::new();
    for m in log.logged_messages() {
        let level = match m.raw_level {
            b'0'..=b'2' => 50,
            b'3' => 40,
            b'4' => 30,
            b'7' => 10,
            _ => 20,
        };
        let name = match m.tag {
            Some(tag) => format!("ulog/tag_{tag}"),
            None => "ulog".to_owned(),
        };
        let text = m.text.to_string_lossy();
        let text = text.split('\0').next().unwrap_or("").to_owned();
        let mut line = times(m.timestamp).to_vec();
        line.extend(stamp(m.timestamp * 1000));
        line.extend([
            level.to_string(),
            name,
            text,
            String::new(),
            String::new(),
            "0".into(),
        ]);
        rosout.push(line);
    }
    if !rosout.is_empty() {
        channels.insert("/rosout".into(), ("rcl_interfaces/msg/Log".into(), rosout));
    }
    // Parameters: the initial values at the start, then each change.
    let param = |t: u64, kv: &ulog_core::read::KeyValue<'_>, initial: bool| {
        let mut line = times(t).to_vec();
        line.extend(stamp(t * 1000));
        line.push(kv.name().into_owned());
        line.push(float_text(kv.value().as_f64().unwrap_or(f64::NAN), json));
        line.push(u8::from(initial).to_string());
        line
    };
    let mut params: Vec<Vec<String>> = log
        .initial_params()
        .iter()
        .map(|kv| param(span.start(), kv, true))
        .collect();
    params.extend(
        log.param_changes()
            .iter()
            .map(|c| param(c.timestamp, &c.kv, false)),
    );
    if !params.is_empty() {
        channels.insert(
            "/ulog/parameters".into(),
            ("ulog_msgs/msg/Parameter".into(), params),
        );
    }
    channels
}

/// `vehicle_gps_position` → `VehicleGpsPosition`.
fn camel(name: &str) -> String {
    name.split('_')
        .filter(|w| !w.is_empty())
        .map(|w| {
            let mut c = w.chars();
            let first = c.next().unwrap().to_ascii_uppercase();
            std::iter::once(first).chain(c).collect::<String>()
        })
        .collect()
}

#[test]
#[cfg_attr(
    not(mcap_readers),
    ignore = "needs Foxglove's MCAP readers: pip install mcap mcap-ros2-support rosbags"
)]
fn every_message_of_every_corpus_log_reads_back_with_foxglove_readers() {
    every_message_reads_back("ros2");
}

#[test]
#[cfg_attr(
    not(mcap_readers),
    ignore = "needs Foxglove's MCAP readers and jsonschema: pip install mcap mcap-ros2-support rosbags jsonschema"
)]
fn every_json_message_of_every_corpus_log_validates_and_reads_back() {
    every_message_reads_back("json");
}

/// Writes every corpus log as MCAP in `encoding` and reads it back with the Python
/// readers: every channel, message and value as this reader reads the log.
fn every_message_reads_back(encoding: &str) {
    let json = encoding == "json";
    let corpus = common::corpus();
    let dir = common::scratch(&format!("mcap_corpus_{encoding}"));
    let mut logs = 0;
    let mut messages = 0u64;
    for (stem, path) in common::corpus_logs(&corpus) {
        let bytes = std::fs::read(&path).unwrap();
        let Ok(log) = ULog::parse(&bytes) else {
            continue;
        };
        let out = dir.join(format!("{stem}.mcap"));
        common::ulog_ok([
            "mcap".as_ref(),
            "--encoding".as_ref(),
            encoding.as_ref(),
            path.as_os_str(),
            "-o".as_ref(),
            out.as_os_str(),
        ]);
        // Every JSON message of three logs (old and new PX4, nested arrays of
        // structs) is validated against its schema, the first 200 of each channel of
        // the others (the validator takes some 12,000 messages a second); every
        // message's values are compared below.
        let all = [
            "sample_2016_old_rev",
            "log_61_2024-2-6-16-27-02",
            "esc_status_log",
        ];
        let validate = (!all.contains(&stem.as_str())).then_some(200);
        let theirs = python_read(&out, validate);
        assert_eq!(theirs["profile"], if json { "" } else { "ros2" }, "{stem}");
        let ours = expected(&log, json);
        let read: BTreeMap<String, Json> = theirs["channels"]
            .as_object()
            .unwrap()
            .iter()
            .map(|(k, v)| (k.clone(), v.clone()))
            .collect();
        let names = |m: &mut dyn Iterator<Item = &String>| m.cloned().collect::<Vec<_>>();
        assert_eq!(
            names(&mut read.keys()),
            names(&mut ours.keys()),
            "{stem}: the channels"
        );
        for (channel, (schema, lines)) in &ours {
            let t = &read[channel];
            assert_eq!(t["schema"], schema.as_str(), "{stem} {channel}");
            let (schema_encoding, message_encoding) = match json {
                true => ("jsonschema", "json"),
                false => ("ros2msg", "cdr"),
            };
            assert_eq!(t["encoding"], schema_encoding, "{stem} {channel}");
            assert_eq!(t["message_encoding"], message_encoding, "{stem} {channel}");
            assert_eq!(t["count"], lines.len(), "{stem} {channel}: messages");
            if json {
                let n = validate.map_or(lines.len(), |n| n.min(lines.len()));
                assert_eq!(t["validated"], n, "{stem} {channel}: validated");
            }
            assert_eq!(
                t["hash"],
                digest(lines),
                "{stem} {channel}: every value of every message, in order"
            );
            messages += lines.len() as u64;
        }
        let total: usize = ours.values().map(|(_, lines)| lines.len()).sum();
        assert_eq!(
            theirs["streamed"], total,
            "{stem}: messages read as a stream"
        );
        // Information as metadata.
        for kv in log.info() {
            let value = &theirs["metadata"]["ulog_info"][kv.name().as_ref()];
            assert!(value.is_string(), "{stem}: information {}", kv.name());
        }
        logs += 1;
    }
    assert!(logs >= 5, "logs read: {logs}");
    assert!(messages > 10_000, "messages compared: {messages}");
}

#[test]
#[cfg_attr(
    not(mcap_readers),
    ignore = "needs rosbags (pip install rosbags) and the corpus"
)]
fn ros2_bags_open_in_rosbags_with_every_topic_type_and_message() {
    let corpus = common::corpus();
    let dir = common::scratch("mcap_bags");
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/scripts/rosbag_read.py");
    let mut bags = 0;
    for (stem, path) in common::corpus_logs(&corpus) {
        let bytes = std::fs::read(&path).unwrap();
        let Ok(log) = ULog::parse(&bytes) else {
            continue;
        };
        let bag = dir.join(&stem);
        common::ulog_ok([
            "mcap".as_ref(),
            "--rosbag2".as_ref(),
            path.as_os_str(),
            "-o".as_ref(),
            bag.as_os_str(),
        ]);
        assert!(bag.join(format!("{stem}_0.mcap")).is_file());
        let out = common::python([script.as_os_str(), bag.as_os_str()]);
        let theirs: Json = serde_json::from_slice(&out).unwrap();
        let ours = expected(&log, false);
        let topics = theirs["topics"].as_object().unwrap();
        assert_eq!(topics.len(), ours.len(), "{stem}: topics");
        let mut total = 0;
        for (channel, (schema, lines)) in &ours {
            let t = &topics[channel.as_str()];
            assert_eq!(t["type"], schema.as_str(), "{stem} {channel}");
            assert_eq!(t["count"], lines.len(), "{stem} {channel}: metadata.yaml");
            assert_eq!(t["read"], lines.len(), "{stem} {channel}: deserialized");
            total += lines.len();
        }
        assert_eq!(theirs["message_count"], total, "{stem}");
        bags += 1;
    }
    assert!(bags >= 3, "bags read: {bags}");
}

#[test]
#[cfg_attr(
    not(mcap_readers),
    ignore = "needs Foxglove's MCAP readers: pip install mcap mcap-ros2-support rosbags"
)]
fn a_window_of_topics_in_utc() {
    use ulog_core::testing::LogBuilder;
    let boot = 1_707_207_944_000_000u64;
    let mut b = LogBuilder::new(1, 0);
    b.info("uint64_t boot_time_utc_us", &boot.to_le_bytes());
    b.format("vehicle_local_position:uint64_t timestamp;float z;");
    b.format("battery_status:uint64_t timestamp;float voltage_v;");
    b.param("float MPC_XY_P", &1.0f32.to_le_bytes());
    b.subscribe(0, 1, "vehicle_local_position");
    b.subscribe(0, 2, "battery_status");
    for s in 1..=10u64 {
        let mut p = (s * 1_000_000).to_le_bytes().to_vec();
        p.extend_from_slice(&(s as f32).to_le_bytes());
        b.data(1, &p);
        // The battery half a second later: a change after it is at its time.
        let mut q = (s * 1_000_000 + 500_000).to_le_bytes().to_vec();
        q.extend_from_slice(&(s as f32).to_le_bytes());
        b.data(2, &q);
        match s {
            2 => b.param("float MPC_XY_P", &2.0f32.to_le_bytes()),
            4 => b.param("float MPC_XY_P", &3.0f32.to_le_bytes()),
            _ => &mut b,
        };
    }
    let dir = common::scratch("mcap_window");
    let path = dir.join("w.ulg");
    std::fs::write(&path, b.bytes()).unwrap();
    let out = dir.join("w.mcap");
    let args = [
        "mcap",
        "--utc",
        "--start",
        "2",
        "--end",
        "5",
        "-m",
        "vehicle_local_position",
    ];
    let mut args: Vec<&std::ffi::OsStr> = args.iter().map(|a| a.as_ref()).collect();
    args.extend([path.as_os_str(), "-o".as_ref(), out.as_os_str()]);
    common::ulog_ok(&args);
    let read = python_read(&out, None);
    let channels = read["channels"].as_object().unwrap();
    assert_eq!(channels.len(), 2, "{channels:?}");
    let c = &channels["/fmu/out/vehicle_local_position"];
    // 2 s to 5 s since the start, both ends in: the header has no time, so the log
    // starts at its first timestamp, 1 s after boot (`TimeSpan`).
    assert_eq!(c["count"], 4);
    assert_eq!(c["first_log_time"], (boot + 3_000_000) * 1000);
    assert_eq!(c["last_log_time"], (boot + 6_000_000) * 1000);
    // The parameter as it stood at the window's start (the change at 2.5 s folded
    // in), then the change at 4.5 s: the time of the battery's row before it, though
    // the battery is not written.
    let p = &read["channels"]["/ulog/parameters"];
    assert_eq!(p["count"], 2);
    let ns = |us: u64| (boot + us) * 1000;
    let line = |us: u64, value: f32, initial: bool| {
        let n = ns(us);
        let bits = f64::from(value).to_bits();
        format!(
            "{n} {n} {} {} MPC_XY_P {bits} {}",
            n / 1_000_000_000,
            n % 1_000_000_000,
            u8::from(initial)
        )
    };
    let lines = vec![
        vec![line(3_000_000, 2.0, true)],
        vec![line(4_500_000, 3.0, false)],
    ];
    assert_eq!(p["hash"], digest(&lines), "{p}");
    assert_eq!(read["metadata"]["ulog_file"]["time"], "utc");
    assert_eq!(
        read["metadata"]["ulog_file"]["utc_source"],
        "information key boot_time_utc_us"
    );
    // A topic the log does not have.
    let bad = common::ulog([
        "mcap".as_ref(),
        path.as_os_str(),
        "-m".as_ref(),
        "nope".as_ref(),
        "-o".as_ref(),
        out.as_os_str(),
    ]);
    assert_eq!(
        bad.status.code(),
        Some(5),
        "{}",
        String::from_utf8_lossy(&bad.stderr)
    );
}
