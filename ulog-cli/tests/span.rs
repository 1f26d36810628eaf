//! One time span for every output: a log with a setpoint stamped 340 s before the
//! log's start, a transponder report stamped 0 and a mission row stamped 20 minutes
//! ahead of the rest (in the middle of the file) draws and writes the 45 s it lasts —
//! in the report, `plot`, MCAP (read by Foxglove's reader), `cut` and the dataset's
//! `duration_s` (read by DuckDB) — and names the stray rows.

mod common;

use std::ffi::OsStr;
use std::path::{Path, PathBuf};

use serde_json::Value as Json;
use ulog_core::testing::LogBuilder;

/// Seconds in microseconds.
const S: u64 = 1_000_000;
/// The header's timestamp: logging started 400 s after boot.
const START: u64 = 400 * S;

fn row(t: u64, x: f32) -> Vec<u8> {
    [&t.to_le_bytes()[..], &x.to_le_bytes()].concat()
}

/// IMU rows every second from the start to 45 s, with the stray rows among them.
fn log_with_stray_rows(header: u64, base: u64) -> Vec<u8> {
    let mut b = LogBuilder::new(1, header);
    b.info("char[3] sys_name", b"PX4");
    b.format("sensor_combined:uint64_t timestamp;float[3] gyro_rad;float[3] accelerometer_m_s2;");
    b.format("position_setpoint_triplet:uint64_t timestamp;float x;");
    b.format("transponder_report:uint64_t timestamp;float x;");
    b.format("mission:uint64_t timestamp;float x;");
    b.subscribe(0, 0, "sensor_combined");
    b.subscribe(0, 1, "position_setpoint_triplet");
    b.subscribe(0, 2, "transponder_report");
    b.subscribe(0, 3, "mission");
    // Made before logging began: 340 s before, and never stamped.
    b.data(1, &row(base - 340 * S, 1.0));
    b.data(2, &row(0, 2.0));
    for i in 0..=45u64 {
        let mut p = (base + i * S).to_le_bytes().to_vec();
        for k in 0..6 {
            p.extend_from_slice(&(i as f32 + k as f32).to_le_bytes());
        }
        b.data(0, &p);
        if i == 20 {
            // A timestamp of another clock, far ahead of every row around it.
            b.data(3, &row(base + 1200 * S, 3.0));
        }
        if i == 30 {
            b.data(1, &row(base + 30 * S, 4.0));
        }
    }
    b.into_bytes()
}

fn write_log(dir: &Path, name: &str, header: u64, base: u64) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, log_with_stray_rows(header, base)).unwrap();
    path
}

fn os<S: AsRef<OsStr> + ?Sized>(s: &S) -> &OsStr {
    s.as_ref()
}

#[test]
fn the_library_finds_the_span_and_names_the_stray_rows() {
    use ulog_core::read::OutlierSide;
    let bytes = log_with_stray_rows(START, START);
    let log = ulog_core::ULog::parse(&bytes).unwrap();
    let span = log.span();
    assert_eq!((span.start(), span.end()), (START, START + 45 * S));
    // pyulog's last timestamp is the stray row's.
    assert_eq!(log.last_timestamp(), START + 1200 * S);
    let named: Vec<(&str, OutlierSide, u64)> = span
        .outliers()
        .iter()
        .map(|o| (log.subscriptions()[o.subscription].name(), o.side, o.rows))
        .collect();
    assert_eq!(
        named,
        [
            ("position_setpoint_triplet", OutlierSide::BeforeStart, 1),
            ("transponder_report", OutlierSide::BeforeStart, 1),
            ("mission", OutlierSide::AfterEnd, 1),
        ]
    );
    // A pass that keeps the metadata finds the same span.
    let keep = ulog_core::ScanOptions::default().keep_metadata(true);
    let summary = ulog_core::scan(&bytes, &keep, |_| {}).unwrap();
    let kept = summary.metadata.unwrap();
    assert_eq!(kept.span(), span);
    assert_eq!(kept.log().unwrap().span(), span);
}

#[test]
fn the_report_draws_the_span_and_lists_the_stray_rows() {
    let dir = common::scratch("span-report");
    let log = write_log(&dir, "stray.ulg", START, START);
    let out = dir.join("stray.html");
    common::ulog_ok([os("report"), log.as_os_str(), os("-o"), out.as_os_str()]);
    let html = std::fs::read_to_string(&out).unwrap();
    let start = html
        .find("<script id=\"report-data\" type=\"application/json\">")
        .expect("data element");
    let rest = &html[start..];
    let body = &rest[rest.find('>').unwrap() + 1..rest.find("</script>").unwrap()];
    let data: Json = serde_json::from_str(body).unwrap();
    assert_eq!(data["origin_us"], START);
    assert_eq!(data["duration"], 45.0);
    let mut xs = Vec::new();
    for plot in data["plots"].as_array().unwrap() {
        for table in plot["tables"].as_array().unwrap() {
            xs.extend(
                table["x"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|x| x.as_f64().unwrap()),
            );
        }
    }
    assert!(!xs.is_empty());
    assert!(xs.iter().all(|&x| (0.0..=45.0).contains(&x)), "{xs:?}");
    assert!(
        html.contains("Timestamps off the time axis"),
        "the stray rows are named"
    );
    assert!(html.contains("stamped up to 340.0 s before the log"));
    assert!(html.contains("`mission` stamped 1200.0 s after the start"));
}

#[test]
fn plot_draws_the_span() {
    let dir = common::scratch("span-plot");
    let log = write_log(&dir, "stray.ulg", START, START);
    let svg = dir.join("stray.svg");
    let said = common::ulog_ok([
        os("plot"),
        log.as_os_str(),
        os("position_setpoint_triplet.x,transponder_report.x,mission.x,sensor_combined.gyro_rad"),
        os("-o"),
        svg.as_os_str(),
    ]);
    // The setpoint made before the start stands at 0, the stray mission row is left
    // out: the axis is the log's 45 s.
    assert!(said.contains("from 0.000 s to 45.000 s"), "{said}");
}

#[test]
#[cfg_attr(
    not(mcap_readers),
    ignore = "needs Foxglove's MCAP readers: pip install mcap mcap-ros2-support rosbags"
)]
fn mcap_records_stale_rows_at_the_start_and_publishes_them_at_their_time() {
    let dir = common::scratch("span-mcap");
    let log = write_log(&dir, "stray.ulg", START, START);
    let out = dir.join("stray.mcap");
    common::ulog_ok([os("mcap"), log.as_os_str(), os("-o"), out.as_os_str()]);
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/scripts/mcap_read.py");
    let read: Json =
        serde_json::from_slice(&common::python([script.as_os_str(), out.as_os_str()])).unwrap();
    let ns = |us: u64| us * 1000;
    assert_eq!(read["statistics"]["message_start_time"], ns(START));
    assert_eq!(read["statistics"]["message_end_time"], ns(START + 45 * S));
    let triplet = &read["channels"]["/fmu/out/position_setpoint_triplet"];
    assert_eq!(triplet["first_log_time"], ns(START));
    let file = &read["metadata"]["ulog_file"];
    assert_eq!(file["span_start_us"], START.to_string());
    assert_eq!(file["span_end_us"], (START + 45 * S).to_string());
}

#[test]
fn cut_counts_from_the_first_timestamp_of_a_header_without_time() {
    let dir = common::scratch("span-cut");
    // The header zeroed (as some uploaders do); the data starts 5228 s after boot.
    let base = 5228 * S;
    let log = write_log(&dir, "zeroed.ulg", 0, base);
    let out = dir.join("cut.ulg");
    common::ulog_ok([
        os("cut"),
        log.as_os_str(),
        os("-o"),
        out.as_os_str(),
        os("--start"),
        os("10"),
        os("--end"),
        os("20"),
        os("-m"),
        os("sensor_combined"),
    ]);
    let bytes = std::fs::read(&out).unwrap();
    let cut = ulog_core::ULog::parse(&bytes).unwrap();
    let topic = cut.topic("sensor_combined", 0).unwrap();
    let t = topic.field("timestamp").unwrap();
    let times: Vec<u64> = topic
        .payloads()
        .map(|p| t.read(p).unwrap().as_f64().unwrap() as u64)
        .collect();
    assert_eq!(times.first(), Some(&(base + 10 * S)));
    assert_eq!(times.last(), Some(&(base + 19 * S)));
}

#[test]
#[cfg_attr(
    not(query_engines),
    ignore = "needs DuckDB's Python package: pip install duckdb datafusion xxhash"
)]
fn the_dataset_gives_the_span_as_duration() {
    let dir = common::scratch("span-dataset");
    let log = write_log(&dir, "stray.ulg", START, START);
    let zeroed = write_log(&dir, "zeroed.ulg", 0, 5228 * S);
    let dataset = dir.join("dataset");
    common::ulog_ok([
        os("parquet"),
        log.as_os_str(),
        zeroed.as_os_str(),
        os("-o"),
        dataset.as_os_str(),
    ]);
    let query = format!(
        "import duckdb, json; print(json.dumps(duckdb.sql(\"SELECT path, start_timestamp, \
         duration_s FROM '{}' ORDER BY path\").fetchall()))",
        dataset.join("logs.parquet").display()
    );
    let rows: Json = serde_json::from_slice(&common::python([os("-c"), os(&query)])).unwrap();
    let rows = rows.as_array().unwrap();
    assert_eq!(rows.len(), 2);
    for r in rows {
        let path = r[0].as_str().unwrap();
        let start = if path.ends_with("stray.ulg") {
            START
        } else {
            5228 * S
        };
        assert_eq!(r[1], start, "{path}");
        assert_eq!(r[2], 45.0, "{path}");
    }
}

#[test]
fn info_and_check_say_the_span_and_name_the_stray_rows() {
    let dir = common::scratch("span-info");
    let log = write_log(&dir, "stray.ulg", START, START);
    let info: Json = serde_json::from_str(&common::ulog_ok([
        os("info"),
        log.as_os_str(),
        os("--json"),
    ]))
    .unwrap();
    // ulog_info's own keys stay pyulog's: the stray row sets the last timestamp.
    assert_eq!(info["start_timestamp"], START);
    assert_eq!(info["last_timestamp"], START + 1200 * S);
    let span = &info["span"];
    assert_eq!(span["start_us"], START);
    assert_eq!(span["end_us"], START + 45 * S);
    assert_eq!(span["duration_s"], 45.0);
    let mut named: Vec<(String, String, u64)> = span["outliers"]
        .as_array()
        .unwrap()
        .iter()
        .map(|o| {
            (
                o["topic"].as_str().unwrap().to_owned(),
                o["side"].as_str().unwrap().to_owned(),
                o["rows"].as_u64().unwrap(),
            )
        })
        .collect();
    named.sort();
    let expect = |t: &str, s: &str| (t.to_owned(), s.to_owned(), 1);
    assert_eq!(
        named,
        [
            expect("mission", "after_end"),
            expect("position_setpoint_triplet", "before_start"),
            expect("transponder_report", "before_start"),
        ]
    );
    let text = common::ulog_ok([os("info"), log.as_os_str()]);
    assert!(
        text.contains("Time span: 0:06:40 to 0:07:25 (45.000 s)"),
        "{text}"
    );
    assert!(text.contains("  mission(0): 1 row stamped up to 1155.0 s after the end"));

    // check: notes (the rows are data), not warnings; the status stays clean.
    let out = common::ulog([os("check"), log.as_os_str(), os("--json")]);
    let check: Json = serde_json::from_slice(&out.stdout).unwrap();
    let file = &check["files"][0];
    assert_eq!(file["duration_s"], 45.0);
    let mut kinds: Vec<(String, String, String)> = file["problems"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|p| {
            p["kind"].as_str().unwrap().starts_with("stamped") || p["kind"] == "timestamp_unset"
        })
        .map(|p| {
            (
                p["topic"].as_str().unwrap().to_owned(),
                p["kind"].as_str().unwrap().to_owned(),
                p["severity"].as_str().unwrap().to_owned(),
            )
        })
        .collect();
    kinds.sort();
    let note = |t: &str, k: &str| (t.to_owned(), k.to_owned(), "note".to_owned());
    assert_eq!(
        kinds,
        [
            note("mission", "stamped_after_end"),
            note("position_setpoint_triplet", "stamped_before_start"),
            note("transponder_report", "timestamp_unset"),
        ]
    );
}
