//! `ulog report`: the page of old (2016) and new (2024) PX4 logs, a non-PX4 log and
//! damaged logs.
//!
//! - Without a browser: each page is one file with nothing fetched from elsewhere, the
//!   plots each log should have, a note for the rest, and the damage the reader found.
//! - In headless Chromium (`scripts/report_check.js`, playwright-core with the
//!   system's browser): no console error and no request but the page; every plot the
//!   log should have is drawn (pixels in its lines' colours); dragging across one plot
//!   zooms every plot to the same range, a double-click zooms all out; the legend's
//!   value where the mouse hovers the battery plot equals this reader's
//!   `battery_status.voltage_v` at the shown time; the messages table has a row per
//!   line of `ulog messages`, and its level filter hides the lower levels.
//! - Every corpus log's page in Chromium: no console error or request, every plot on
//!   it drawn, every message listed.
//! - A 100 MB log built here: the page stays small and thinned (spikes kept), and the
//!   command runs within the file's size plus 64 MiB of data segment.

mod common;

use std::ffi::OsStr;
use std::path::{Path, PathBuf};
use std::process::Command;

use serde_json::Value as Json;
use ulog_core::read::Unwrapper;
use ulog_core::LogFile;

/// The plots a log of each kind should have, by id.
const NEW_2024: (&str, &[&str]) = (
    "log_61_2024-2-6-16-27-02",
    &[
        "altitude",
        "roll",
        "pitch",
        "yaw",
        "rates",
        "position",
        "velocity",
        "manual",
        "controls",
        "motors",
        "outputs",
        "accel",
        "gyro",
        "vibration",
        "clipping",
        "battery",
        "gps",
        "gps_noise",
        "test_ratios",
        "load",
        "mag",
    ],
);
const OLD_2016: (&str, &[&str]) = (
    "sample_2016_old_rev",
    &[
        "altitude",
        "roll",
        "pitch",
        "yaw",
        "rates",
        "position",
        "velocity",
        "controls",
        "outputs",
        "accel",
        "gyro",
        "vibration",
        "battery",
        "gps",
        "gps_noise",
        "test_ratios",
        "mag",
    ],
);
/// Not PX4's: one plot per topic.
const NOT_PX4: (&str, &[&str]) = ("powers", &["topic_powers_of_2_0", "topic_powers_of_10_0"]);
/// Two runs of zero bytes mid-stream.
const DAMAGED: (&str, &[&str]) = (
    "corrupt_format_not_utf8",
    &[
        "altitude",
        "roll",
        "pitch",
        "yaw",
        "rates",
        "position",
        "velocity",
        "manual",
        "controls",
        "motors",
        "outputs",
        "accel",
        "gyro",
        "vibration",
        "clipping",
        "battery",
        "test_ratios",
        "load",
        "mag",
    ],
);

fn log_path(stem: &str) -> PathBuf {
    common::corpus().join("files").join(format!("{stem}.ulg"))
}

/// Writes the report of a corpus log and returns its path and text.
fn report(stem: &str) -> (PathBuf, String) {
    let dir = common::scratch(&format!("report-{stem}"));
    let out = dir.join(format!("{stem}.html"));
    let log = log_path(stem);
    let said = common::ulog_ok([
        OsStr::new("report"),
        log.as_os_str(),
        OsStr::new("-o"),
        out.as_os_str(),
    ]);
    assert!(said.starts_with("Wrote "), "{said}");
    let text = std::fs::read_to_string(&out).expect("the report");
    (out, text)
}

/// The JSON the page draws from.
fn page_data(html: &str) -> Json {
    let start = html
        .find("<script id=\"report-data\" type=\"application/json\">")
        .expect("data element");
    let rest = &html[start..];
    let body = &rest[rest.find('>').unwrap() + 1..rest.find("</script>").unwrap()];
    serde_json::from_str(body).expect("the page's JSON")
}

fn plot_ids(data: &Json) -> Vec<String> {
    data["plots"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["id"].as_str().unwrap().to_owned())
        .collect()
}

/// Nothing is fetched: no element loads a URL, no script imports one.
fn assert_self_contained(stem: &str, html: &str) {
    for bad in [
        "src=\"http",
        "href=\"http",
        "src=\"//",
        "@import",
        "url(http",
    ] {
        assert!(!html.contains(bad), "{stem}: the page refers to `{bad}`");
    }
    assert!(html.contains("uPlot"), "{stem}: uPlot is inside");
}

#[test]
#[cfg_attr(
    not(full_corpus),
    ignore = "needs the full corpus's 2016, 2024 and damaged logs (../shared/corpus)"
)]
fn each_kind_of_log_gives_a_page_with_its_plots_and_notes() {
    for (stem, plots) in [NEW_2024, OLD_2016, NOT_PX4, DAMAGED] {
        let (_, html) = report(stem);
        assert_self_contained(stem, &html);
        let data = page_data(&html);
        assert_eq!(plot_ids(&data), *plots, "{stem}: the plots");
        for p in data["plots"].as_array().unwrap() {
            for t in p["tables"].as_array().unwrap() {
                let x = t["x"].as_array().unwrap();
                assert!(!x.is_empty(), "{stem}: {} has points", p["id"]);
                assert!(
                    x.windows(2).all(|w| w[0].as_f64() <= w[1].as_f64()),
                    "{stem}: {} in time order",
                    p["id"]
                );
            }
        }
        match stem {
            "powers" => {
                assert!(
                    html.contains("none of the topics of PX4"),
                    "{stem}: the note"
                );
                assert!(html.contains("No flight modes"), "{stem}: the note");
            }
            _ => assert!(
                !data["modes"].as_array().unwrap().is_empty(),
                "{stem}: flight modes"
            ),
        }
        if stem != "log_61_2024-2-6-16-27-02" {
            // The others lack some standard plots, and say which.
            assert!(
                html.contains("Plots this log has no data for"),
                "{stem}: the missing plots are named"
            );
        }
    }
    // Damage: the mid-stream runs of zeros, and the 2016 log's truncated end.
    let (_, html) = report(DAMAGED.0);
    let damage = row(&html, "Damage");
    assert!(damage.contains("finding(s)"), "{damage}");
    let (_, html) = report(OLD_2016.0);
    let damage = row(&html, "Damage");
    assert!(damage.contains("ends inside a message"), "{damage}");
    let (_, html) = report(NEW_2024.0);
    assert_eq!(row(&html, "Damage"), "none found");
    assert!(row(&html, "Start").starts_with("2024-02-06T08:25:44"));
    assert!(row(&html, "Software").starts_with("v1.14.0"));
}

/// The value of a header row.
fn row(html: &str, name: &str) -> String {
    let key = format!("<tr><th>{name}</th><td>");
    let at = html
        .find(&key)
        .unwrap_or_else(|| panic!("header row {name}"))
        + key.len();
    html[at..at + html[at..].find("</td>").unwrap()].to_owned()
}

/// Runs the browser script on a page; its JSON.
fn browse(page: &Path, hover: &str, screenshot: Option<&Path>) -> Json {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/scripts/report_check.js");
    let mut cmd = Command::new("node");
    cmd.arg(script).arg(page).arg(hover);
    if let Some(s) = screenshot {
        cmd.arg(s);
    }
    let out = cmd
        .env("NODE_PATH", env!("ULOG_TESTS_NODE_PATH"))
        .output()
        .expect("run node");
    assert!(
        out.status.success(),
        "report_check.js failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("the script's JSON")
}

/// `battery_status.voltage_v` of instance 0 at `timestamp`, as this reader reads it.
fn voltage_at(stem: &str, timestamp: u64) -> f32 {
    let file = LogFile::open(log_path(stem)).expect("open");
    let log = file.parse().expect("parse");
    let topic = log.topic("battery_status", 0).expect("battery_status");
    let v = topic.field("voltage_v").expect("voltage_v");
    let mut clock = Unwrapper::new(topic.timestamp_field());
    topic
        .payloads()
        .find(|p| clock.push(p) == Some(timestamp))
        .and_then(|p| v.read_f64(p))
        .unwrap_or_else(|| panic!("{stem}: no battery_status row at {timestamp} µs")) as f32
}

#[test]
#[cfg_attr(
    not(all(chromium, full_corpus)),
    ignore = "needs /usr/bin/chromium with playwright-core in target/node (.ci/run installs \
              both) and the full corpus"
)]
fn pages_draw_zoom_together_hover_reader_values_and_list_every_message() {
    for (stem, plots) in [NEW_2024, OLD_2016, NOT_PX4, DAMAGED] {
        let (page, _) = report(stem);
        let r = browse(&page, "battery", None);
        assert_eq!(r["errors"], serde_json::json!([]), "{stem}: console errors");
        assert_eq!(r["requests"], serde_json::json!([]), "{stem}: requests");
        for id in plots {
            let px = r["plots"][id]["linePixels"].as_u64().unwrap_or(0);
            assert!(px > 20, "{stem}: plot {id} is drawn ({px} line pixels)");
        }
        // Zoom: every plot shows the dragged plot's range, narrower than before.
        let zoomed = r["zoomed"].as_str().unwrap();
        let range = |which: &str, id: &str| -> (f64, f64) {
            let v = &r[which][id];
            (v[0].as_f64().unwrap(), v[1].as_f64().unwrap())
        };
        let (a, b) = range("after", zoomed);
        let (a0, b0) = range("before", zoomed);
        assert!(
            a > a0 && b < b0,
            "{stem}: zoomed in: {a}..{b} of {a0}..{b0}"
        );
        for id in plots.iter() {
            assert_eq!(range("after", id), (a, b), "{stem}: {id} follows the zoom");
            assert_eq!(range("reset", id), (a0, b0), "{stem}: {id} zoomed out");
        }
        // The hovered value is the reader's.
        if plots.contains(&"battery") {
            let hover = r["hover"].as_array().expect("legend values");
            let get = |label: &str| {
                hover
                    .iter()
                    .find(|e| e[0] == label)
                    .and_then(|e| e[1].as_str())
                    .unwrap_or_else(|| panic!("{stem}: legend {label}: {hover:?}"))
                    .to_owned()
            };
            let t: f64 = get("time").trim_end_matches(" s").parse().expect("time");
            // Times before the page's zero (data older than the first message) are
            // negative.
            let at = r["origin_us"].as_u64().unwrap() as i64 + (t * 1e6).round() as i64;
            let at = u64::try_from(at).expect("a time after boot");
            let shown: f32 = get("voltage [V]").parse().expect("a number");
            assert_eq!(shown, voltage_at(stem, at), "{stem}: voltage at {t} s");
        }
        // Every message, and the level filter.
        let lines = common::ulog_ok([OsStr::new("messages"), log_path(stem).as_os_str()]);
        let count = lines.lines().count() as u64;
        assert_eq!(r["messages"], count, "{stem}: rows of the messages table");
        let errors = lines
            .lines()
            .filter(|l| {
                let level = l.split_whitespace().nth(1).unwrap_or("");
                ["EMERGENCY:", "ALERT:", "CRITICAL:", "ERROR:"].contains(&level)
            })
            .count() as u64;
        assert_eq!(r["messagesShownAtError"], errors, "{stem}: ERROR and above");
    }
}

/// A long log of IMU rows (`sensor_combined`, 3 axes of gyro and accelerometer plus
/// padding to 80 bytes): `rows` rows, 4 ms apart.
fn long_imu_log(rows: u64) -> Vec<u8> {
    let mut b = ulog_core::testing::LogBuilder::new(1, 1_000_000);
    b.info("char[3] sys_name", b"PX4");
    b.format(
        "sensor_combined:uint64_t timestamp;float[3] gyro_rad;float[3] accelerometer_m_s2;\
         uint8_t[48] _padding0;",
    );
    b.subscribe(0, 0, "sensor_combined");
    for i in 0..rows {
        let mut p = (1_000_000 + i * 4000).to_le_bytes().to_vec();
        let phase = i as f32 * 0.01;
        for k in 0..6 {
            let spike = if i == rows / 3 && k == 4 { 80.0 } else { 0.0 };
            p.extend_from_slice(&((phase + k as f32).sin() + spike).to_le_bytes());
        }
        p.extend_from_slice(&[0; 48]);
        b.data(0, &p);
    }
    b.into_bytes()
}

/// Memory and size of the report of a 100 MB log: it runs with its data segment (heap
/// and private writable mappings) limited to the file's size plus 64 MiB, that is the
/// snapshot of the file every `ulog` command reads (`LogFile::open`) and a bounded rest:
/// no second copy and no row kept per message; its page keeps at most 2 + 2 × lines
/// rows per column of each table, spikes included.
#[test]
fn a_long_log_gives_a_small_page_in_bounded_memory() {
    let dir = common::scratch("report-long");
    let log = dir.join("long.ulg");
    let bytes = long_imu_log(1_200_000);
    std::fs::write(&log, &bytes).unwrap();
    let out = dir.join("long.html");
    let limit_kib = bytes.len() as u64 / 1024 + 64 * 1024;
    drop(bytes);
    let run = Command::new("sh")
        .arg("-c")
        .arg(format!("ulimit -d {limit_kib} && exec \"$0\" \"$@\""))
        .arg(env!("CARGO_BIN_EXE_ulog"))
        .args([
            OsStr::new("report"),
            log.as_os_str(),
            OsStr::new("-o"),
            out.as_os_str(),
        ])
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "ulog report within {} MiB: {:?}\n{}",
        limit_kib / 1024,
        run.status,
        String::from_utf8_lossy(&run.stderr)
    );
    let html = std::fs::read_to_string(&out).unwrap();
    assert!(html.len() < 3 << 20, "{} bytes", html.len());
    let data = page_data(&html);
    assert_eq!(plot_ids(&data), ["accel", "gyro"]);
    let accel = &data["plots"][0]["tables"][0];
    assert_eq!(accel["thinned"], true);
    let kept = accel["x"].as_array().unwrap().len();
    assert!(kept <= 2000 * (2 + 2 * 3), "{kept} rows kept");
    let z = accel["y"][1].as_array().unwrap();
    let top = z.iter().filter_map(Json::as_f64).fold(f64::MIN, f64::max);
    assert!(top > 79.0, "the spike survives: {top}");
}

#[test]
#[cfg_attr(
    not(chromium),
    ignore = "needs /usr/bin/chromium with playwright-core in target/node (.ci/run installs \
              both)"
)]
fn every_corpus_logs_page_opens_cleanly_and_draws_every_plot() {
    for (stem, _) in common::corpus_logs(&common::corpus()) {
        let (page, html) = report(&stem);
        let r = browse(&page, "battery", None);
        assert_eq!(r["errors"], serde_json::json!([]), "{stem}: console errors");
        assert_eq!(r["requests"], serde_json::json!([]), "{stem}: requests");
        for id in plot_ids(&page_data(&html)) {
            let px = r["plots"][&id]["linePixels"].as_u64().unwrap_or(0);
            assert!(px > 20, "{stem}: plot {id} is drawn ({px} line pixels)");
        }
        let lines = common::ulog_ok([OsStr::new("messages"), log_path(&stem).as_os_str()]);
        assert_eq!(
            r["messages"],
            lines.lines().count() as u64,
            "{stem}: rows of the messages table"
        );
    }
}
