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

/// Writes the report of a corpus log and returns its path and text. `test` names the
/// calling test: tests run in parallel and several report the same log, so each writes
/// into a folder of its own (one shared folder was emptied by one test while another's
/// browser opened the page in it).
fn report(test: &str, stem: &str) -> (PathBuf, String) {
    let dir = common::scratch(&format!("report-{test}-{stem}"));
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
        let (_, html) = report("kinds", stem);
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
    let (_, html) = report("kinds", DAMAGED.0);
    let damage = row(&html, "Damage");
    assert!(damage.contains("finding(s)"), "{damage}");
    let (_, html) = report("kinds", OLD_2016.0);
    let damage = row(&html, "Damage");
    assert!(damage.contains("ends inside a message"), "{damage}");
    let (_, html) = report("kinds", NEW_2024.0);
    assert_eq!(row(&html, "Damage"), "none found");
    // The flight analysis: spectra, step responses and spectrograms of an armed
    // flight, its vibration status (flight-review-rs says `warning` of this log too)
    // and no diagnostics.
    let data = page_data(&html);
    let ids = |key: &str| -> Vec<String> {
        data[key]
            .as_array()
            .unwrap()
            .iter()
            .map(|p| p["id"].as_str().unwrap().to_owned())
            .collect()
    };
    assert_eq!(
        ids("analysis"),
        ["psd_gyro", "psd_accel", "psd_torque", "step_response"]
    );
    assert_eq!(ids("heatmaps"), ["spectrogram_gyro", "spectrogram_accel"]);
    assert!(
        row(&html, "Vibration").starts_with("warning"),
        "{}",
        row(&html, "Vibration")
    );
    assert!(row(&html, "Diagnostics").starts_with("none"));
    assert!(html.contains("id=\"no-diagnostics\""));
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
        let (page, _) = report("browse", stem);
        let r = browse(&page, "battery", None);
        assert_eq!(r["errors"], serde_json::json!([]), "{stem}: console errors");
        assert_eq!(r["requests"], serde_json::json!([]), "{stem}: requests");
        for id in plots {
            let px = r["plots"][id]["linePixels"].as_u64().unwrap_or(0);
            assert!(px > 20, "{stem}: plot {id} is drawn ({px} line pixels)");
        }
        if stem == NEW_2024.0 {
            for id in ["psd_gyro", "psd_accel", "psd_torque", "step_response"] {
                let px = r["analysis"][id]["linePixels"].as_u64().unwrap_or(0);
                assert!(px > 20, "{stem}: {id} is drawn ({px} line pixels)");
            }
            for id in ["spectrogram_gyro", "spectrogram_accel"] {
                let m = &r["heatmaps"][id];
                let (coloured, all) = (m["colouredPixels"].as_u64(), m["pixels"].as_u64());
                assert!(
                    coloured.unwrap_or(0) * 2 > all.unwrap_or(u64::MAX),
                    "{stem}: {id} fills its canvas with colour: {m}"
                );
                assert!(m["columns"].as_u64().unwrap_or(0) > 50, "{stem}: {id}: {m}");
            }
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
        let (page, html) = report("every", &stem);
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

/// A log with what PX4 puts in its information: an xz-compressed blob in a `uint8_t`
/// array split over continued parts (`metadata_events`), perf counters one line per
/// part, the boot console in chunks cut anywhere, a list of entries, and a short
/// array value. Returns the log's path and the blob.
fn information_log(dir: &Path) -> (PathBuf, Vec<u8>) {
    let mut rng = ulog_core::testing::Rng::new(48);
    let mut blob = b"\xfd7zXZ\x00".to_vec();
    blob.extend((6..3000).map(|_| rng.below(256) as u8));
    let mut b = ulog_core::testing::LogBuilder::new(1, 1_000_000);
    b.info("char[3] sys_name", b"PX4");
    b.info("uint8_t[4] small", &[1, 2, 3, 0xfe]);
    for (i, part) in blob.chunks(1200).enumerate() {
        let key = format!("uint8_t[{}] metadata_events", part.len());
        b.multi_info(i > 0, &key, part);
    }
    for i in 0..40 {
        let line = format!("counter_{i}: {i} events");
        let key = format!("char[{}] perf_counter_preflight", line.len());
        b.multi_info(i > 0, &key, line.as_bytes());
    }
    let console: String = (0..30).map(|i| format!("line {i} <&>\n")).collect();
    for (i, chunk) in console.as_bytes().chunks(50).enumerate() {
        let key = format!("char[{}] boot_console_output", chunk.len());
        b.multi_info(i > 0, &key, chunk);
    }
    for topic in ["a", "b", "c"] {
        b.multi_info(false, "char[1] excluded_optional_topics", topic.as_bytes());
    }
    b.format("pos:uint64_t timestamp;float x;");
    b.subscribe(0, 0, "pos");
    for i in 0..200u64 {
        let t = 1_000_000 + i * 10_000;
        b.data(
            0,
            &[&t.to_le_bytes()[..], &(i as f32).sin().to_le_bytes()].concat(),
        );
    }
    let path = dir.join("information.ulg");
    std::fs::write(&path, b.bytes()).unwrap();
    (path, blob)
}

/// The value cell of the information or multi-information row of `key`.
fn info_cell<'h>(html: &'h str, key: &str) -> &'h str {
    let start = format!("<tr><td>{key}</td><td>");
    let at = html.find(&start).unwrap_or_else(|| panic!("row {key}")) + start.len();
    &html[at..at + html[at..].find("</td></tr>").unwrap()]
}

/// Binary values show as their size and kind with a link that downloads them, never
/// as Python's bytes; long texts are folded under their first line.
#[test]
fn information_shows_bytes_by_kind_and_folds_long_texts() {
    let dir = common::scratch("report-information");
    let (log, _) = information_log(&dir);
    let out = dir.join("information.html");
    common::ulog_ok([
        OsStr::new("report"),
        log.as_os_str(),
        OsStr::new("-o"),
        out.as_os_str(),
    ]);
    let html = std::fs::read_to_string(&out).unwrap();
    assert_self_contained("information", &html);
    assert!(!html.contains("b'\\xfd7zXZ"), "no Python bytes");

    let events = info_cell(&html, "metadata_events");
    assert!(
        events.starts_with("<span class=\"bytes\">3,000 bytes, xz-compressed data</span>"),
        "{events}"
    );
    let link = " <a class=\"download\" download=\"metadata_events.xz\" \
                href=\"data:application/x-xz;base64,";
    let at = events.find(link).expect("a download link") + link.len();
    let digits = &events[at..at + events[at..].find('"').unwrap()];
    assert_eq!(digits.len(), 4000, "3,000 bytes in base64");
    assert!(!events.contains("<code"), "no hex of a long value");

    let small = info_cell(&html, "small");
    assert!(
        small.starts_with(
            "<span class=\"bytes\">4 bytes, binary data</span> <code class=\"hex\">01 02 03 fe</code>"
        ),
        "{small}"
    );

    // One line per part; folded under the first.
    let perf = info_cell(&html, "perf_counter_preflight");
    let lines: Vec<String> = (0..40)
        .map(|i| format!("counter_{i}: {i} events"))
        .collect();
    let text = lines.join("\n");
    assert_eq!(
        perf,
        format!(
            "<details class=\"long\"><summary><code>counter_0: 0 events</code> (40 lines, {} \
             characters)</summary><pre>{text}</pre></details>",
            text.chars().count()
        )
    );
    // Chunks joined as they were cut, escaped.
    let console = info_cell(&html, "boot_console_output");
    let expected: String = (0..30)
        .map(|i| format!("line {i} &lt;&amp;&gt;\n"))
        .collect();
    assert!(
        console.starts_with(
            "<details class=\"long\"><summary><code>line 0 &lt;&amp;&gt;</code> (30 lines"
        ),
        "{console}"
    );
    assert!(
        console.ends_with(&format!("<pre>{expected}</pre></details>")),
        "{console}"
    );
    // Short: shown whole, the entries of a key as lines.
    assert_eq!(
        info_cell(&html, "excluded_optional_topics"),
        "<pre>a\nb\nc</pre>"
    );
    assert_eq!(info_cell(&html, "sys_name"), "<pre>PX4</pre>");

    // Nothing dumped: the page is the bare page (uPlot, script, one small plot) and the
    // blob in base64, not screens of bytes.
    let base = html.len() - digits.len();
    assert!(base < 200_000, "{base} bytes besides the blob");
}

/// The same page in Chromium: the download link gives the value's bytes, long texts
/// are closed folds whose visible text is their first line.
#[test]
#[cfg_attr(
    not(chromium),
    ignore = "needs /usr/bin/chromium with playwright-core in target/node (.ci/run installs \
              both)"
)]
fn information_downloads_give_the_bytes_and_folds_show_their_first_line() {
    let dir = common::scratch("report-information-browser");
    let (log, blob) = information_log(&dir);
    let out = dir.join("information.html");
    common::ulog_ok([
        OsStr::new("report"),
        log.as_os_str(),
        OsStr::new("-o"),
        out.as_os_str(),
    ]);
    let r = browse(&out, "", None);
    assert_eq!(r["errors"], serde_json::json!([]), "console errors");
    assert_eq!(r["requests"], serde_json::json!([]), "requests");
    let rows = r["information"].as_array().unwrap();
    let row = |key: &str| {
        rows.iter()
            .find(|r| r["key"] == key)
            .unwrap_or_else(|| panic!("row {key}: {rows:?}"))
    };
    let events = row("metadata_events");
    assert_eq!(events["download"], "metadata_events.xz");
    let got: Vec<u8> = events["bytes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|b| b.as_u64().unwrap() as u8)
        .collect();
    assert!(got == blob, "the link gives the value's bytes");
    assert_eq!(
        events["visible"].as_str().unwrap().trim(),
        "3,000 bytes, xz-compressed data download"
    );
    let small = row("small");
    let got: Vec<u64> = small["bytes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|b| b.as_u64().unwrap())
        .collect();
    assert_eq!(got, [1, 2, 3, 0xfe]);
    let perf = row("perf_counter_preflight");
    let fold = &perf["folds"][0];
    assert_eq!(fold["open"], false);
    assert!(fold["summary"]
        .as_str()
        .unwrap()
        .starts_with("counter_0: 0 events (40 lines"));
    assert_eq!(fold["text"].as_str().unwrap().lines().count(), 40);
    let visible = perf["visible"].as_str().unwrap();
    assert!(!visible.contains("counter_39"), "folded: {visible}");
    let console = row("boot_console_output");
    assert_eq!(
        console["folds"][0]["text"],
        (0..30)
            .map(|i| format!("line {i} <&>\n"))
            .collect::<String>()
    );
}

#[test]
fn a_brownout_is_listed_marked_and_counted_in_the_header() {
    let dir = common::scratch("report-brownout");
    let log = common::brownout_log(&dir);
    let out = dir.join("brownout.html");
    common::ulog_ok([
        OsStr::new("report"),
        log.as_os_str(),
        OsStr::new("-o"),
        out.as_os_str(),
    ]);
    let html = std::fs::read_to_string(&out).expect("the page");
    assert_eq!(
        row(&html, "Diagnostics"),
        "1 critical, 0 warning (table below)"
    );
    let table = &html[html.find("<table id=\"diagnostics\"").expect("the table")..];
    let table = &table[..table.find("</table>").unwrap()];
    assert_eq!(table.matches("<tr class=").count(), 1, "{table}");
    assert!(
        table.contains("battery_brownout") && table.contains("critical"),
        "{table}"
    );
    assert!(table.contains("critical_threshold_v=13.200"), "{table}");
    // The mark, at 30 s on the log's clock.
    let data = page_data(&html);
    let origin = data["origin_us"].as_f64().unwrap();
    let marks: Vec<&Json> = data["marks"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|m| m["kind"] == "diagnostic")
        .collect();
    assert_eq!(marks.len(), 1, "{marks:?}");
    assert_eq!(marks[0]["text"], "battery_brownout");
    let at = origin + marks[0]["t"].as_f64().unwrap() * 1e6;
    assert!((at - 30e6).abs() < 1.0, "the mark at {at} µs");
    // `ulog analyze` says the same: one source.
    let json: Json = serde_json::from_str(
        common::ulog_ok([OsStr::new("analyze"), OsStr::new("--json"), log.as_os_str()]).trim(),
    )
    .unwrap();
    let d = &json["diagnostics"][0];
    assert_eq!(
        (d["id"].as_str(), d["timestamp_us"].as_u64()),
        (Some("battery_brownout"), Some(30_000_000))
    );
    assert_eq!(d["end_timestamp_us"], 33_000_000);
    #[cfg(chromium)]
    {
        let r = browse(&out, "battery", None);
        assert_eq!(r["errors"], serde_json::json!([]), "console errors");
        let rows = r["diagnostics"].as_array().expect("the table's rows");
        assert_eq!(rows.len(), 1, "{rows:?}");
        assert_eq!(rows[0][3], "battery_brownout");
    }
}

/// The report of several logs compared, in the scratch folder of `test`.
fn compare_report(test: &str, stems: &[&str]) -> (PathBuf, String) {
    let dir = common::scratch(&format!("report-{test}"));
    let out = dir.join("compare.html");
    let mut args: Vec<std::ffi::OsString> = vec!["report".into()];
    args.extend(stems.iter().map(|s| log_path(s).into_os_string()));
    args.extend(["-o".into(), out.clone().into_os_string()]);
    let said = common::ulog_ok(&args);
    assert!(said.starts_with("Wrote "), "{said}");
    let text = std::fs::read_to_string(&out).expect("the page");
    (out, text)
}

/// Each log's lines on the compared page are its own page's, moved to time since its
/// takeoff (as `ulog analyze` says it) and coloured one colour per log; the plots of
/// every log are there; the parameters that differ are `ulog params --diff`'s.
fn assert_compared(test: &str, stems: &[&str]) -> (PathBuf, String) {
    let (page, html) = compare_report(test, stems);
    assert_self_contained(test, &html);
    let data = page_data(&html);
    assert_eq!(
        data["modes"],
        serde_json::json!([]),
        "no flight modes when comparing"
    );
    let compared: Vec<&Json> = data["plots"].as_array().unwrap().iter().collect();
    let mut colors = Vec::new();
    for (i, stem) in stems.iter().enumerate() {
        let (_, own) = report(test, stem);
        let own = page_data(&own);
        let analysis: Json = serde_json::from_str(
            common::ulog_ok([
                OsStr::new("analyze"),
                OsStr::new("--json"),
                log_path(stem).as_os_str(),
            ])
            .trim(),
        )
        .unwrap();
        let origin = own["origin_us"].as_f64().unwrap();
        let end = origin + own["duration"].as_f64().unwrap() * 1e6;
        let offset = match analysis["flight"]["takeoff_us"].as_f64() {
            Some(t) if (origin..=end).contains(&t) => (t - origin) / 1e6,
            _ => 0.0,
        };
        let prefix = format!("{stem}: ");
        for p in own["plots"].as_array().unwrap() {
            let id = &p["id"];
            let other = compared
                .iter()
                .find(|c| c["id"] == *id)
                .unwrap_or_else(|| panic!("{stem}: plot {id} on the compared page"));
            for t in p["tables"].as_array().unwrap() {
                let labels: Vec<String> = t["labels"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|l| format!("{prefix}{}", l.as_str().unwrap()))
                    .collect();
                let c = other["tables"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .find(|c| {
                        c["labels"]
                            .as_array()
                            .unwrap()
                            .iter()
                            .map(|l| l.as_str().unwrap())
                            .eq(labels.iter().map(String::as_str))
                    })
                    .unwrap_or_else(|| panic!("{stem}: {id}: lines {labels:?}"));
                assert_eq!(c["y"], t["y"], "{stem}: {id}: the same values");
                let (xs, xc) = (t["x"].as_array().unwrap(), c["x"].as_array().unwrap());
                assert_eq!(xs.len(), xc.len());
                for (a, b) in xs.iter().zip(xc) {
                    let (a, b) = (a.as_f64().unwrap(), b.as_f64().unwrap());
                    assert!(
                        (a - offset - b).abs() < 1e-9,
                        "{stem}: {id}: {a} − {offset} ≠ {b}"
                    );
                }
                colors.push((i, c["color"].as_str().unwrap().to_owned()));
            }
        }
    }
    // One colour per log, a different one for each.
    colors.sort();
    colors.dedup();
    assert_eq!(colors.len(), stems.len(), "{colors:?}");
    // The parameters that differ: those `ulog params --diff` lists across the logs.
    let mut args: Vec<std::ffi::OsString> = vec!["params".into(), log_path(stems[0]).into()];
    for s in &stems[1..] {
        args.extend(["--diff".into(), log_path(s).into_os_string()]);
    }
    args.extend(["-f".into(), "json".into()]);
    let diff: Json = serde_json::from_str(&common::ulog_ok(&args)).unwrap();
    let names: Vec<&str> = diff
        .as_array()
        .unwrap()
        .iter()
        .map(|d| d["name"].as_str().unwrap())
        .collect();
    let table = html.find("<table id=\"params-across\"");
    match table {
        Some(at) => {
            let body = &html[at..html[at..].find("</table>").unwrap() + at];
            assert_eq!(
                body.matches("<tr><td>").count(),
                names.len(),
                "one row per parameter"
            );
            for n in &names {
                assert!(body.contains(&format!("<tr><td>{n}</td>")), "{n}");
            }
        }
        None => assert!(names.is_empty(), "no table, and no parameter differs"),
    }
    (page, html)
}

#[test]
fn comparing_logs_of_the_repository_overlays_them() {
    assert_compared(
        "compare-own",
        &["esc_status_log", "sample_appended_multiple"],
    );
}

#[test]
#[cfg_attr(
    not(all(chromium, full_corpus)),
    ignore = "needs /usr/bin/chromium with playwright-core in target/node (.ci/run installs \
              both) and the full corpus"
)]
fn comparing_flights_overlays_them_on_time_since_takeoff_in_chromium() {
    let stems = [NEW_2024.0, "log_123_2024-3-1-14-47-02", OLD_2016.0];
    let (page, html) = assert_compared("compare-flights", &stems);
    // Both 2024 flights take off: time 0 is marked.
    let data = page_data(&html);
    assert_eq!(data["marks"][0]["kind"], "takeoff");
    let r = browse(&page, "battery", None);
    assert_eq!(r["errors"], serde_json::json!([]), "console errors");
    assert_eq!(r["requests"], serde_json::json!([]), "requests");
    for id in plot_ids(&data) {
        let px = r["plots"][&id]["linePixels"].as_u64().unwrap_or(0);
        assert!(px > 20, "plot {id} is drawn ({px} line pixels)");
    }
    assert!(
        r["paramsAcross"].as_array().unwrap().len() > 100,
        "the parameters that differ, as the browser shows them"
    );
}
