//! Helpers shared by the integration tests: where the shared corpus of real logs is,
//! and how pyulog's expected outputs compare with ours.

use std::path::{Path, PathBuf};

use ulog_core::Value;

pub mod module_logs;

/// The corpus of real logs the tests check (`files/` and pyulog's `expected/`), as
/// `build.rs` picked it: `$ULOG_CORPUS`, else the full shared corpus beside the
/// workspace (`../shared/corpus`), else the repository's own logs (`tests/corpus`).
pub fn corpus_dir() -> PathBuf {
    PathBuf::from(env!("ULOG_TESTS_CORPUS"))
}

/// Whether [`corpus_dir`] is the full corpus (tests that need one of its logs are
/// `ignore`d otherwise, by `cfg(full_corpus)`).
pub const FULL_CORPUS: bool = cfg!(full_corpus);

/// A log of the repository's own corpus (`tests/corpus/files`), there on every clone.
pub fn own_log(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("corpus/files")
        .join(name)
}

/// Every `.ulg` file of the corpus, sorted by name.
pub fn corpus_files() -> Vec<PathBuf> {
    let dir = corpus_dir();
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir.join("files"))
        .expect("corpus files dir")
        .map(|e| e.expect("dir entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "ulg"))
        .collect();
    files.sort();
    files
}

/// The file stem (`sample` for `sample.ulg`).
pub fn stem(path: &Path) -> String {
    path.file_stem()
        .expect("file name")
        .to_string_lossy()
        .into_owned()
}

/// pyulog's `summary.json` for a corpus file.
pub fn expected_summary(path: &Path) -> serde_json::Value {
    let dir = corpus_dir();
    let p = dir.join("expected").join(stem(path)).join("summary.json");
    let text = std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
    serde_json::from_str(&text).expect("summary.json parses")
}

/// Whether a value printed by pyulog (CSV cell) equals ours. Floats compare by value
/// (pyulog prints a float32 in its shortest form), `nan` equals `nan`; strings as
/// pyulog's `ulog2csv` reads them: up to the first NUL, one character per byte.
pub fn cell_matches(expected: &str, ours: &Value) -> bool {
    match ours {
        Value::F32(v) => match expected.parse::<f32>() {
            Ok(e) => (e.is_nan() && v.is_nan()) || e == *v,
            Err(_) => false,
        },
        Value::F64(v) => match expected.parse::<f64>() {
            Ok(e) => (e.is_nan() && v.is_nan()) || e == *v,
            Err(_) => false,
        },
        // pyulog stores bool as int8, so its CSV prints the byte (0, 1, or whatever
        // else was logged); we read any non-zero byte as true.
        Value::Bool(b) => expected.parse::<i8>().is_ok_and(|e| (e != 0) == *b),
        Value::Str(s) => {
            let latin1: String = s
                .until_nul()
                .as_bytes()
                .iter()
                .map(|&b| b as char)
                .collect();
            latin1 == expected
        }
        v => match (v.as_i128(), expected.parse::<i128>()) {
            (Some(a), Ok(b)) => a == b,
            _ => false,
        },
    }
}

/// Whether a JSON value of `summary.json` equals one of our values.
pub fn json_matches(expected: &serde_json::Value, ours: &Value) -> bool {
    use serde_json::Value as J;
    match (expected, ours) {
        // The expected outputs decode text as UTF-8 with U+FFFD for invalid bytes,
        // as we show it.
        (J::String(e), Value::Str(s)) => *e == s.to_string_lossy(),
        // pyulog keeps array values as raw bytes; the expected outputs show them as
        // text too.
        (J::String(e), Value::Array(a)) => *e == String::from_utf8_lossy(a.as_bytes()),
        (J::String(e), Value::Bytes(b)) => *e == String::from_utf8_lossy(b),
        (J::Number(n), Value::F32(v)) => n.as_f64().is_some_and(|e| e == f64::from(*v)),
        (J::Number(n), Value::F64(v)) => n.as_f64().is_some_and(|e| e == *v),
        (J::Number(n), v) => match (n.as_i64(), n.as_u64(), v.as_i128()) {
            (Some(e), _, Some(o)) => i128::from(e) == o,
            (None, Some(e), Some(o)) => i128::from(e) == o,
            _ => false,
        },
        (J::Bool(e), Value::Bool(o)) => e == o,
        _ => false,
    }
}

/// Stretches where we keep data that pyulog skips: from the end of each corrupt stretch
/// to the next sync message (pyulog resynchronises only on sync messages; we also on
/// the first header that starts a chain of valid messages).
pub fn recovered_stretches(log: &ulog_core::ULog<'_>) -> Vec<(u64, u64)> {
    let syncs: Vec<u64> = log
        .messages()
        .filter_map(Result::ok)
        .filter(|m| m.message.msg_type() == b'S')
        .map(|m| m.offset)
        .collect();
    log.findings()
        .iter()
        .filter(|f| matches!(f.kind, ulog_core::read::FindingKind::Corrupt(_)))
        .map(|f| {
            let end = f.offset + f.len;
            (
                end,
                syncs
                    .iter()
                    .copied()
                    .find(|&s| s >= end)
                    .unwrap_or(u64::MAX),
            )
        })
        .collect()
}

/// pyulog's reading of `bytes` (written to a scratch file) as JSON
/// (`scripts/pyulog_dump.py`: information, parameters, logged strings, dropouts, each
/// data set's columns). Tests that call it are `ignore`d where `python3` could not
/// import pyulog when they were built (`cfg(pyulog)`, see `build.rs`):
/// `#[cfg_attr(not(pyulog), ignore = "needs pyulog")]`.
pub fn pyulog_dump(test: &str, bytes: &[u8]) -> serde_json::Value {
    pyulog_try_dump(test, bytes).unwrap_or_else(|e| panic!("pyulog failed: {e}"))
}

/// [`pyulog_dump`], or pyulog's error output when it refuses the bytes (an exception
/// on damaged input).
pub fn pyulog_try_dump(test: &str, bytes: &[u8]) -> Result<serde_json::Value, String> {
    pyulog_dump_run(test, bytes, None)
}

/// [`pyulog_dump`] with the data of these topics only (pyulog's
/// `message_name_filter_list`): the rest of the log as in the full dump.
pub fn pyulog_dump_topics(test: &str, bytes: &[u8], topics: &[&str]) -> serde_json::Value {
    pyulog_dump_run(test, bytes, Some(topics)).unwrap_or_else(|e| panic!("pyulog failed: {e}"))
}

fn pyulog_dump_run(
    test: &str,
    bytes: &[u8],
    topics: Option<&[&str]>,
) -> Result<serde_json::Value, String> {
    use std::process::Command;
    let dir = std::env::temp_dir().join(format!("ulog-pyulog-{test}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("written.ulg");
    std::fs::write(&path, bytes).unwrap();
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/scripts/pyulog_dump.py");
    let out = Command::new("python3")
        .arg(script)
        .arg(&path)
        .args(
            topics
                .map(|t| [&["--only"], t].concat())
                .unwrap_or_default(),
        )
        .output()
        .unwrap();
    std::fs::remove_dir_all(&dir).ok();
    if !out.status.success() {
        return Err(String::from_utf8_lossy(&out.stderr).into_owned());
    }
    Ok(serde_json::from_slice(&out.stdout).unwrap())
}
