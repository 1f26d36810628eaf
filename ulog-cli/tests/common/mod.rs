//! Helpers shared by the integration tests: running the built `ulog`, finding the
//! corpus, scratch folders.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Runs the built `ulog` with `args`.
pub fn ulog<I, S>(args: I) -> Output
where
    I: IntoIterator<Item = S>,
    S: AsRef<std::ffi::OsStr>,
{
    Command::new(env!("CARGO_BIN_EXE_ulog"))
        .args(args)
        .output()
        .expect("run ulog")
}

/// Runs `ulog` and returns its stdout, failing the test on a non-zero exit.
pub fn ulog_ok<I, S>(args: I) -> String
where
    I: IntoIterator<Item = S>,
    S: AsRef<std::ffi::OsStr>,
{
    let out = ulog(args);
    assert!(
        out.status.success(),
        "ulog failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).expect("utf-8 output")
}

/// Runs `python3` with `args` and returns its stdout, failing the test (with its
/// stderr) when it fails.
pub fn python<I, S>(args: I) -> Vec<u8>
where
    I: IntoIterator<Item = S>,
    S: AsRef<std::ffi::OsStr>,
{
    let out = Command::new("python3")
        .args(args)
        .output()
        .expect("run python3");
    assert!(
        out.status.success(),
        "python3 failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    out.stdout
}

/// The corpus of real logs the tests check (`files/` and pyulog's `expected/`), as
/// `build.rs` found it: `$ULOG_CORPUS`, else the full shared corpus beside the
/// workspace (`../shared/corpus`), else the repository's own logs (`tests/corpus`).
pub fn corpus() -> PathBuf {
    PathBuf::from(env!("ULOG_TESTS_CORPUS"))
}

/// Every `.ulg` file of the corpus with its stem, sorted.
pub fn corpus_logs(dir: &Path) -> Vec<(String, PathBuf)> {
    let mut v: Vec<(String, PathBuf)> = std::fs::read_dir(dir.join("files"))
        .expect("corpus files")
        .map(|e| e.expect("dir entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "ulg"))
        .map(|p| (p.file_stem().unwrap().to_string_lossy().into_owned(), p))
        .collect();
    v.sort();
    v
}

/// pyulog's summary of a corpus log.
pub fn summary(dir: &Path, stem: &str) -> serde_json::Value {
    let text = std::fs::read_to_string(dir.join("expected").join(stem).join("summary.json"))
        .expect("summary.json");
    serde_json::from_str(&text).expect("summary json")
}

/// Every file below `dir`, by its path relative to `dir`, with its bytes.
pub fn files(dir: &Path) -> std::collections::BTreeMap<PathBuf, Vec<u8>> {
    let mut out = std::collections::BTreeMap::new();
    let mut stack = vec![dir.to_owned()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).expect("read dir") {
            let p = e.expect("entry").path();
            if p.is_dir() {
                stack.push(p);
            } else {
                let rel = p.strip_prefix(dir).expect("under dir").to_owned();
                out.insert(rel, std::fs::read(&p).expect("read"));
            }
        }
    }
    out
}

/// An empty scratch folder for one test.
pub fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("ulog-cli")
        .join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch dir");
    dir
}

/// The bundled sample log written to a file of the scratch folder `name`.
pub fn sample_file(name: &str) -> PathBuf {
    let path = scratch(name).join("sample.ulg");
    std::fs::write(&path, ulog_core::testing::sample_log()).expect("write sample");
    path
}

/// Logs where this reader recovers data messages after mid-stream corruption that
/// pyulog skips (pyulog only resynchronises at the next sync message, and drops what
/// lies between): our CSVs and row counts may hold extra rows there.
pub const RECOVERS_ROWS: &[&str] = &["corrupt_format_not_utf8", "corrupt_unregistered_msg_id"];

/// How pyulog's scripts print a logged string (`H:MM:SS.mmm LEVEL: text`).
pub fn message_line(level: u64, timestamp: u64, text: &str) -> String {
    let names = [
        "EMERGENCY",
        "ALERT",
        "CRITICAL",
        "ERROR",
        "WARNING",
        "NOTICE",
        "INFO",
        "DEBUG",
    ];
    let name = level
        .checked_sub(u64::from(b'0'))
        .and_then(|i| names.get(i as usize))
        .copied()
        .unwrap_or("UNKNOWN");
    let ms = timestamp / 1000;
    let s = ms / 1000;
    format!(
        "{}:{:02}:{:02}.{:03} {name}: {text}",
        s / 3600,
        s / 60 % 60,
        s % 60,
        ms % 1000
    )
}

/// A written flight of a 4S battery whose voltage dips below 3.3 V per cell (13.2 V)
/// from 30 s to 33 s while armed (armed from 2 s to 60 s).
pub fn brownout_log(dir: &Path) -> PathBuf {
    let mut b = ulog_core::testing::LogBuilder::new(1, 0);
    b.format("vehicle_status:uint64_t timestamp;uint8_t arming_state;uint8_t nav_state;");
    b.format(
        "battery_status:uint64_t timestamp;float voltage_v;float current_a;uint8_t cell_count;",
    );
    b.subscribe(0, 0, "vehicle_status");
    b.subscribe(0, 1, "battery_status");
    for i in 0..=620u64 {
        let t = 1_000_000 + i * 100_000;
        if i % 5 == 0 {
            let armed = (2_000_000..60_000_000).contains(&t);
            let mut p = t.to_le_bytes().to_vec();
            p.extend([if armed { 2u8 } else { 1 }, 2]);
            b.data(0, &p);
        }
        let volts: f32 = if (30_000_000..=33_000_000).contains(&t) {
            12.9
        } else {
            15.5
        };
        let mut p = t.to_le_bytes().to_vec();
        p.extend(volts.to_le_bytes());
        p.extend(8.0f32.to_le_bytes());
        p.push(4);
        b.data(1, &p);
    }
    let path = dir.join("brownout.ulg");
    std::fs::write(&path, b.into_bytes()).expect("write the log");
    path
}
