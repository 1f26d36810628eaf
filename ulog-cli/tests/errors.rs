//! A file that cannot be read: non-zero exit and exactly one line on stderr.

mod common;

use std::path::Path;

fn refused(args: &[&std::ffi::OsStr], expect: &str) {
    let out = common::ulog(args);
    assert!(!out.status.success(), "{args:?} should fail");
    assert!(out.stdout.is_empty());
    let err = String::from_utf8(out.stderr).unwrap();
    assert_eq!(err.lines().count(), 1, "one line expected: {err}");
    assert!(err.starts_with("ulog: "), "{err}");
    assert!(err.contains(expect), "`{expect}` expected in: {err}");
}

fn every_command(file: &Path, expect: &str) {
    for cmd in ["info", "messages", "params", "csv"] {
        refused(&[cmd.as_ref(), file.as_os_str()], expect);
    }
}

#[test]
fn missing_file() {
    let dir = common::scratch("missing");
    let file = dir.join("nope.ulg");
    every_command(&file, "nope.ulg: no such file");
}

#[test]
fn empty_file() {
    let file = common::scratch("empty").join("empty.ulg");
    std::fs::write(&file, b"").unwrap();
    every_command(&file, "the file is empty");
}

#[test]
fn not_a_ulog_file() {
    let file = common::scratch("not_ulog").join("x.ulg");
    std::fs::write(&file, b"%PDF-1.4 this is not a flight log at all").unwrap();
    every_command(&file, "not a ULog file");
}

#[test]
fn unknown_incompat_flag_is_refused() {
    let mut b = ulog_core::testing::LogBuilder::new(1, 0);
    b.flag_bits([0; 8], [0, 0, 4, 0, 0, 0, 0, 0], [0; 3]);
    b.format("t:uint64_t timestamp;");
    let file = common::scratch("incompat").join("x.ulg");
    std::fs::write(&file, b.bytes()).unwrap();
    every_command(&file, "unknown incompatible flag bits");
}

#[test]
fn directory_is_refused() {
    let dir = common::scratch("a_dir");
    every_command(&dir, "is a directory");
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
    );
}
