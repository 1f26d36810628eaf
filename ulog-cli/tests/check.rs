//! `ulog check`: damage and spec departures per file, summary lines, exit statuses.

mod common;

use std::path::{Path, PathBuf};

use serde_json::Value as Json;
use ulog_core::testing::LogBuilder;
use ulog_core::ULog;

fn check_json(files: &[&Path]) -> (Json, Option<i32>) {
    let mut args: Vec<&std::ffi::OsStr> = vec!["check".as_ref(), "--json".as_ref()];
    args.extend(files.iter().map(|f| f.as_os_str()));
    let out = common::ulog(args);
    let j: Json = serde_json::from_slice(&out.stdout).expect("json");
    assert_eq!(
        j["exit_status"].as_i64().map(|n| n as i32),
        out.status.code()
    );
    (j, out.status.code())
}

fn write(dir: &Path, name: &str, b: &LogBuilder) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, b.bytes()).unwrap();
    p
}

fn base() -> LogBuilder {
    let mut b = LogBuilder::new(1, 1_000);
    b.flag_bits([0; 8], [0; 8], [0; 3]);
    b.format("pos:uint64_t timestamp;float x;");
    b.subscribe(0, 1, "pos");
    b
}

fn pos(b: &mut LogBuilder, t: u64, x: f32) {
    let mut p = t.to_le_bytes().to_vec();
    p.extend_from_slice(&x.to_le_bytes());
    b.data(1, &p);
}

fn kinds(file: &Json) -> Vec<(String, String)> {
    file["problems"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| {
            (
                p["severity"].as_str().unwrap().to_owned(),
                p["kind"].as_str().unwrap().to_owned(),
            )
        })
        .collect()
}

#[test]
fn clean_log_is_ok_with_exit_0() {
    let dir = common::scratch("check_clean");
    let mut b = base();
    for i in 0..20 {
        pos(&mut b, 1_000 + i * 10_000, i as f32);
    }
    let f = write(&dir, "clean.ulg", &b);
    let (j, code) = check_json(&[&f]);
    assert_eq!(code, Some(0));
    assert_eq!(j["files"][0]["status"], "ok");
    assert_eq!(j["files"][0]["messages"], 23);
    let text = common::ulog_ok(["check".as_ref(), f.as_os_str()]);
    assert_eq!(text.lines().count(), 1, "{text}");
    assert!(
        text.starts_with(&format!("{}: ok (23 messages, 1 topics", f.display())),
        "{text}"
    );
}

#[test]
fn timestamps_backwards_and_jumps_per_topic() {
    let dir = common::scratch("check_time");
    let mut b = base();
    for i in 0..10 {
        pos(&mut b, 1_000 + i * 10_000, 0.0);
    }
    let back_at = *b.boundaries().last().unwrap() as u64;
    pos(&mut b, 500, 0.0); // backwards
    pos(&mut b, 200_000, 0.0);
    let jump_at = *b.boundaries().last().unwrap() as u64;
    pos(&mut b, 1_710_773_360_254_000, 0.0); // a Unix time in a boot-time log
    let f = write(&dir, "time.ulg", &b);
    let (j, code) = check_json(&[&f]);
    assert_eq!(code, Some(1));
    let file = &j["files"][0];
    assert_eq!(file["status"], "warnings");
    let problems = file["problems"].as_array().unwrap();
    let back = problems
        .iter()
        .find(|p| p["kind"] == "timestamp_backwards")
        .unwrap();
    assert_eq!(back["offset"], back_at);
    assert_eq!(back["topic"], "pos");
    assert_eq!(back["multi_id"], 0);
    let jump = problems
        .iter()
        .find(|p| p["kind"] == "timestamp_jump")
        .unwrap();
    assert_eq!(jump["offset"], jump_at);
    assert_eq!(jump["severity"], "warning");
}

#[test]
fn spec_departures_and_damage() {
    let dir = common::scratch("check_spec");
    // Version 1 without flag bits, an unknown message type, a bad log level, some
    // parameters without defaults (which the spec allows: no finding), and a cut tail.
    let mut b = LogBuilder::new(1, 0);
    b.format("pos:uint64_t timestamp;float x;");
    b.param("int32_t A", &1i32.to_le_bytes());
    b.param("int32_t B", &1i32.to_le_bytes());
    b.default_param(1, "int32_t A", &0i32.to_le_bytes());
    // In the data section a logged string with a bad level is taken for corruption;
    // before it, the reader keeps it and `check` names the level.
    b.log(b'x', 20, "odd level");
    b.subscribe(0, 1, "pos");
    b.raw(b'X', &[1, 2, 3]);
    for i in 0..5 {
        pos(&mut b, 10 + i, 1.0);
    }
    pos(&mut b, 30, 1.0);
    let mut bytes = b.bytes().to_vec();
    bytes.extend_from_slice(&[14, 0, b'D', 1, 0, 9]); // a data message cut short
    let f = dir.join("spec.ulg");
    std::fs::write(&f, &bytes).unwrap();
    let (j, code) = check_json(&[&f]);
    assert_eq!(code, Some(1));
    let file = &j["files"][0];
    assert_eq!(file["status"], "damaged");
    let k = kinds(file);
    for expected in [
        ("error", "truncated"),
        ("warning", "no_flag_bits"),
        ("warning", "unknown_message_type"),
        ("warning", "invalid_log_level"),
    ] {
        assert!(
            k.contains(&(expected.0.to_owned(), expected.1.to_owned())),
            "{expected:?} in {k:?}"
        );
    }
    assert!(
        !k.iter().any(|(_, kind)| kind.contains("default")),
        "defaults for some parameters only are what the spec allows: {k:?}"
    );
    // Most severe first.
    let order: Vec<&str> = k.iter().map(|(s, _)| s.as_str()).collect();
    let mut sorted = order.clone();
    sorted.sort_by_key(|s| ["error", "warning", "note"].iter().position(|x| x == s));
    assert_eq!(order, sorted);
}

/// The spec lets a log hold defaults for some parameters or none: `check` says nothing
/// of it, except where the `DEFAULT_PARAMETERS` flag promises defaults and none follow.
#[test]
fn parameters_without_defaults_are_no_finding() {
    let dir = common::scratch("check_defaults");
    let with_params = |flag: u8, default: bool| {
        let mut b = LogBuilder::new(1, 1_000);
        b.flag_bits([flag, 0, 0, 0, 0, 0, 0, 0], [0; 8], [0; 3]);
        b.format("pos:uint64_t timestamp;float x;");
        b.param("int32_t A", &1i32.to_le_bytes());
        b.param("int32_t B", &2i32.to_le_bytes());
        if default {
            b.default_param(1, "int32_t A", &0i32.to_le_bytes());
        }
        b.subscribe(0, 1, "pos");
        for i in 0..5 {
            pos(&mut b, 1_000 + i * 10_000, 0.0);
        }
        b
    };
    let none = write(&dir, "none.ulg", &with_params(0, false));
    let some = write(&dir, "some.ulg", &with_params(1, true));
    let promised = write(&dir, "promised.ulg", &with_params(1, false));
    let (j, code) = check_json(&[&none, &some, &promised]);
    assert_eq!(code, Some(1));
    for file in &j["files"].as_array().unwrap()[..2] {
        assert_eq!(file["status"], "ok", "{file}");
        assert_eq!(file["problems"], Json::Array(vec![]), "{file}");
    }
    assert_eq!(
        kinds(&j["files"][2]),
        [("warning".to_owned(), "no_default_parameters".to_owned())]
    );
    // The corpus (PX4 logs with defaults for some parameters, or none): no word of them.
    let corpus = common::corpus();
    let logs = common::corpus_logs(&corpus);
    let paths: Vec<&Path> = logs.iter().map(|(_, p)| p.as_path()).collect();
    let (j, _) = check_json(&paths);
    for ((stem, _), file) in logs.iter().zip(j["files"].as_array().unwrap()) {
        let k = kinds(file);
        assert!(
            !k.iter().any(|(_, kind)| kind.contains("default")),
            "{stem}: {k:?}"
        );
    }
}

/// A directory is searched as `ulog parquet` searches one: every `.ulg` and `.ulog`
/// file in it and below, sorted; other files left alone; one without logs unreadable.
#[test]
fn directories_are_searched_for_logs() {
    let dir = common::scratch("check_dir");
    let mut b = base();
    pos(&mut b, 1_000, 0.0);
    std::fs::create_dir_all(dir.join("logs/sub")).unwrap();
    std::fs::create_dir_all(dir.join("empty")).unwrap();
    let a = write(&dir, "logs/b.ulg", &b);
    let c = write(&dir, "logs/sub/a.ULOG", &b);
    std::fs::write(dir.join("logs/notes.txt"), "not a log").unwrap();
    let (j, code) = check_json(&[&dir.join("logs")]);
    assert_eq!(code, Some(0));
    let files: Vec<&str> = j["files"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f["file"].as_str().unwrap())
        .collect();
    let expected = [a.display().to_string(), c.display().to_string()];
    assert_eq!(files, expected);
    let (j, code) = check_json(&[&dir.join("empty"), &a]);
    assert_eq!(code, Some(3));
    assert_eq!(j["files"][0]["status"], "unreadable");
    assert!(
        j["files"][0]["error"]
            .as_str()
            .unwrap()
            .contains("no .ulg or .ulog files"),
        "{j}"
    );
    assert_eq!(j["files"][1]["status"], "ok");
}

#[test]
fn unreadable_and_refused_files_do_not_stop_the_others() {
    let dir = common::scratch("check_mixed");
    let mut b = base();
    pos(&mut b, 1_000, 0.0);
    let good = write(&dir, "good.ulg", &b);
    let text = dir.join("notes.txt");
    std::fs::write(&text, "hello").unwrap();
    let missing = dir.join("missing.ulg");
    let (j, code) = check_json(&[&good, &text, &missing]);
    assert_eq!(code, Some(4), "refused (4) outranks unreadable (3)");
    let st: Vec<&str> = j["files"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f["status"].as_str().unwrap())
        .collect();
    assert_eq!(st, ["ok", "refused", "unreadable"]);
    assert!(j["files"][1]["error"]
        .as_str()
        .unwrap()
        .contains("not a ULog file"));

    let (_, code) = check_json(&[&good, &missing]);
    assert_eq!(code, Some(3));

    let out = common::ulog([
        "check".as_ref(),
        "--brief".as_ref(),
        good.as_os_str(),
        text.as_os_str(),
    ]);
    let stdout = String::from_utf8(out.stdout).unwrap();
    assert_eq!(
        stdout.lines().count(),
        3,
        "a line per file and the total: {stdout}"
    );
}

/// Every damage finding of the reader is an error of `check`, at its byte range; a
/// log is `damaged` exactly when the reader found damage, and pyulog's corrupt logs
/// are among them. Besides the corpus (whose own logs are all whole), a copy of one
/// with a stretch overwritten.
#[test]
fn corpus_damage_is_reported_with_byte_ranges() {
    let dir = common::corpus();
    let mut logs = common::corpus_logs(&dir);
    let (_, whole) = logs.iter().find(|(s, _)| s == "esc_status_log").unwrap();
    let mut bytes = std::fs::read(whole).unwrap();
    let at = bytes.len() * 2 / 5;
    bytes[at..at + 64].fill(0xA5);
    let damaged_copy = common::scratch("check_damaged_copy").join("overwritten.ulg");
    std::fs::write(&damaged_copy, bytes).unwrap();
    logs.push(("overwritten".to_owned(), damaged_copy));
    let paths: Vec<&Path> = logs.iter().map(|(_, p)| p.as_path()).collect();
    let (j, code) = check_json(&paths);
    assert_eq!(code, Some(1));
    let files = j["files"].as_array().unwrap();
    assert_eq!(files.len(), logs.len());
    let mut damaged = 0;
    for ((stem, path), file) in logs.iter().zip(files) {
        let bytes = std::fs::read(path).unwrap();
        let log = ULog::parse(&bytes).unwrap();
        let errors: Vec<&Json> = file["problems"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|p| p["severity"] == "error")
            .collect();
        for f in log.findings().iter().filter(|f| f.is_damage()) {
            assert!(
                errors
                    .iter()
                    .any(|e| e["offset"] == f.offset && e["len"] == f.len),
                "{stem}: {f} not reported"
            );
        }
        assert_eq!(
            file["status"] == "damaged",
            log.has_damage() || !errors.is_empty(),
            "{stem}"
        );
        assert_eq!(
            file["messages"].as_u64(),
            Some(log.message_count()),
            "{stem}"
        );
        if stem != "overwritten" && common::summary(&dir, stem)["file_corruption"] == true {
            assert_eq!(file["status"], "damaged", "{stem}: pyulog finds it corrupt");
        }
        damaged += usize::from(file["status"] == "damaged");
    }
    let least = if cfg!(full_corpus) { 5 } else { 1 };
    assert!(damaged >= least, "{damaged} damaged logs");
}
