//! A file that cannot be read: non-zero exit and exactly one line on stderr.

mod common;

use std::path::Path;

fn refused(args: &[&std::ffi::OsStr], expect: &str, status: i32) {
    let out = common::ulog(args);
    assert_eq!(out.status.code(), Some(status), "{args:?}: exit status");
    assert!(out.stdout.is_empty());
    let err = String::from_utf8(out.stderr).unwrap();
    assert_eq!(err.lines().count(), 1, "one line expected: {err}");
    assert!(err.starts_with("ulog: "), "{err}");
    assert!(err.contains(expect), "`{expect}` expected in: {err}");
}

fn every_command(file: &Path, expect: &str, status: i32) {
    for cmd in ["info", "messages", "params", "csv"] {
        refused(&[cmd.as_ref(), file.as_os_str()], expect, status);
    }
}

#[test]
fn missing_file() {
    let dir = common::scratch("missing");
    let file = dir.join("nope.ulg");
    every_command(&file, "nope.ulg: no such file", 3);
}

#[test]
fn empty_file() {
    let file = common::scratch("empty").join("empty.ulg");
    std::fs::write(&file, b"").unwrap();
    every_command(&file, "the file is empty", 4);
}

#[test]
fn not_a_ulog_file() {
    let file = common::scratch("not_ulog").join("x.ulg");
    std::fs::write(&file, b"%PDF-1.4 this is not a flight log at all").unwrap();
    every_command(&file, "not a ULog file", 4);
}

#[test]
fn unknown_incompat_flag_is_refused() {
    let mut b = ulog_core::testing::LogBuilder::new(1, 0);
    b.flag_bits([0; 8], [0, 0, 4, 0, 0, 0, 0, 0], [0; 3]);
    b.format("t:uint64_t timestamp;");
    let file = common::scratch("incompat").join("x.ulg");
    std::fs::write(&file, b.bytes()).unwrap();
    every_command(&file, "unknown incompatible flag bits", 4);
}

#[test]
fn directory_is_refused() {
    let dir = common::scratch("a_dir");
    every_command(&dir, "is a directory", 3);
}

#[test]
fn defaults_of_a_log_without_them() {
    let file = common::sample_file("no_defaults");
    let mut b = ulog_core::testing::LogBuilder::new(1, 0);
    b.flag_bits([0; 8], [0; 8], [0; 3]);
    b.param("int32_t X", &1i32.to_le_bytes());
    std::fs::write(&file, b.bytes()).unwrap();
    refused(
        &[
            "params".as_ref(),
            file.as_os_str(),
            "--default".as_ref(),
            "system".as_ref(),
        ],
        "no default parameters",
        7,
    );
}

#[test]
fn unknown_topic_is_named_with_the_closest_one() {
    let mut b = ulog_core::testing::LogBuilder::new(1, 0);
    b.flag_bits([0; 8], [0; 8], [0; 3]);
    b.format("vehicle_status:uint64_t timestamp;uint8_t arming_state;");
    b.subscribe(0, 1, "vehicle_status");
    b.data(1, &[1, 0, 0, 0, 0, 0, 0, 0, 2]);
    let file = common::scratch("unknown_topic").join("x.ulg");
    std::fs::write(&file, b.bytes()).unwrap();
    refused(
        &[
            "csv".as_ref(),
            file.as_os_str(),
            "-m".as_ref(),
            "vehicle_stat".as_ref(),
        ],
        "vehicle_status",
        5,
    );
}
