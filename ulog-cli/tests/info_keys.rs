//! Information keys whose name holds a space (PX4 logs have `char[11] Build Date`):
//! their values are decoded by the key's type and shown as text (or numbers)
//! everywhere, as pyulog's `ulog_info` shows them.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

use ulog_core::testing::LogBuilder;

/// A small log with information and multi-information keys holding spaces.
fn spaced_keys_log(test: &str) -> PathBuf {
    let mut b = LogBuilder::new(1, 1_000_000);
    b.flag_bits([0; 8], [0; 8], [0; 3]);
    b.info_str("sys_name", "PX4");
    b.info_str("Build Date", "May 25 2022");
    b.info("int32_t Boot Count", &7i32.to_le_bytes());
    b.multi_info(false, "char[9] boot log", b"line one!");
    b.format("t:uint64_t timestamp;");
    b.subscribe(0, 0, "t");
    for i in 1..4u64 {
        b.data(0, &(1_000_000 * i).to_le_bytes());
    }
    let path = common::scratch(test).join("spaced.ulg");
    std::fs::write(&path, b.bytes()).unwrap();
    path
}

/// `key: value` pairs of the lines of section `title` (`Info Messages:`, …): the
/// indented lines after it.
fn section(text: &str, title: &str) -> Vec<(String, String)> {
    text.lines()
        .skip_while(|l| *l != title)
        .skip(1)
        .take_while(|l| l.starts_with(' '))
        .map(|l| {
            let (k, v) = l[1..].split_once(": ").expect("key: value");
            (k.to_owned(), v.to_owned())
        })
        .collect()
}

/// Ours against pyulog's: same values in the same order; pyulog keeps only the first
/// word of a key with spaces (its key ends at the second space), we keep the name.
fn assert_same_section(ours: &str, theirs: &str, title: &str) {
    let a = section(ours, title);
    let b = section(theirs, title);
    assert!(!b.is_empty(), "pyulog's {title}\n{theirs}");
    assert_eq!(
        a.len(),
        b.len(),
        "{title}\nours:\n{ours}\npyulog:\n{theirs}"
    );
    for ((ka, va), (kb, vb)) in a.iter().zip(&b) {
        assert_eq!(va, vb, "value of `{ka}`\nours:\n{ours}\npyulog:\n{theirs}");
        assert!(
            ka == kb || ka.starts_with(&format!("{kb} ")),
            "key `{ka}` vs pyulog's `{kb}`"
        );
    }
}

fn run(args: &[&str], file: &Path) -> String {
    let mut all: Vec<&std::ffi::OsStr> = args.iter().map(|a| a.as_ref()).collect();
    all.insert(1, file.as_os_str());
    common::ulog_ok(all)
}

#[test]
fn info_keys_with_spaces_show_their_values_as_text() {
    let file = spaced_keys_log("info_spaced_keys");

    let info = run(&["info"], &file);
    let items = section(&info, "Info Messages:");
    assert!(
        items.contains(&("Build Date".into(), "May 25 2022".into())),
        "{info}"
    );
    assert!(items.contains(&("Boot Count".into(), "7".into())), "{info}");
    assert!(!info.contains("b'"), "{info}");
    let verbose = run(&["info", "-v"], &file);
    assert!(
        verbose.contains(" boot log: [['line one!']]\n"),
        "{verbose}"
    );

    let json: serde_json::Value = serde_json::from_str(&run(&["info", "--json"], &file)).unwrap();
    assert_eq!(json["info"]["Build Date"], "May 25 2022", "{json}");
    assert_eq!(json["info"]["Boot Count"], 7, "{json}");
    assert_eq!(
        json["info_multiple"]["boot log"][0][0], "line one!",
        "{json}"
    );

    let dump = run(&["dump"], &file);
    let line = dump
        .lines()
        .find(|l| l.contains("Build Date"))
        .expect("dump shows the key");
    assert!(line.ends_with("= \"May 25 2022\""), "{line}");
    let line = dump.lines().find(|l| l.contains("Boot Count")).unwrap();
    assert!(line.ends_with("= 7"), "{line}");
    let dump_json = run(&["dump", "--json"], &file);
    let build: serde_json::Value = dump_json
        .lines()
        .map(|l| serde_json::from_str::<serde_json::Value>(l).unwrap())
        .find(|m| m["key"] == "char[11] Build Date")
        .expect("dump --json shows the key");
    assert_eq!(build["name"], "Build Date");
    assert_eq!(build["value"], "May 25 2022");

    let out = file.with_file_name("parquet");
    common::ulog_ok([
        "parquet".as_ref(),
        "--per-log".as_ref(),
        file.as_os_str(),
        "-o".as_ref(),
        out.as_os_str(),
    ]);
    let meta = std::fs::read_to_string(out.join("spaced/metadata.json")).unwrap();
    let meta: serde_json::Value = serde_json::from_str(&meta).unwrap();
    assert_eq!(meta["info"]["Build Date"], "May 25 2022", "{meta}");
    assert_eq!(meta["multi_info"]["boot log"][0][0], "line one!", "{meta}");
}

#[test]
#[cfg_attr(
    not(pyulog),
    ignore = "needs pyulog: pip install pyulog==1.3.0, then touch ulog-cli/build.rs"
)]
fn info_keys_with_spaces_equal_ulog_info() {
    let test = "info_keys_with_spaces_equal_ulog_info";
    let file = spaced_keys_log(test);
    for verbose in [false, true] {
        let mut py = Command::new("ulog_info");
        if verbose {
            py.arg("-v");
        }
        let py = py.arg(&file).output().expect("run ulog_info");
        assert!(
            py.status.success(),
            "{}",
            String::from_utf8_lossy(&py.stderr)
        );
        let theirs = String::from_utf8(py.stdout).unwrap();
        let ours = run(if verbose { &["info", "-v"] } else { &["info"] }, &file);
        assert_same_section(&ours, &theirs, "Info Messages:");
        if verbose {
            assert_same_section(&ours, &theirs, "Info Multiple Messages:");
        }
    }
}
