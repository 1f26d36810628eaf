//! pyulog's flags: a pyulog user's command (`ulog_info -m KEY -n`, `ulog2csv -ts -te
//! -d -i`, `ulog_params -i -t -d -l --ignore OUT`) given to `ulog info`, `csv` and
//! `params` prints and writes what pyulog's script does, run beside it on the same
//! logs.

mod common;

use std::collections::BTreeMap;
use std::ffi::OsStr;
use std::path::{Path, PathBuf};
use std::process::Command;

use ulog_core::testing::LogBuilder;
use ulog_core::ULog;

/// Runs pyulog's script `script` with `args`; its stdout.
fn pyulog(script: &str, args: &[&OsStr]) -> Vec<u8> {
    let out = Command::new(script)
        .args(args)
        .output()
        .unwrap_or_else(|e| panic!("run {script}: {e}"));
    assert!(
        out.status.success(),
        "{script} {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    out.stdout
}

/// A log with multi-information of the kinds `ulog_info -m` prints apart: text whose
/// entries are continued, bytes (`uint8_t[N]`, as PX4's `metadata_events`), and a
/// single `char`; and parameters with defaults of both kinds, changed in flight.
fn written_log(dir: &Path) -> PathBuf {
    let mut b = LogBuilder::new(1, 1_000);
    b.flag_bits([1, 0, 0, 0, 0, 0, 0, 0], [0; 8], [0; 3]);
    b.info_str("sys_name", "PX4");
    b.multi_info(false, "char[6] boot_log", b"line 1");
    b.multi_info(true, "char[7] boot_log", b"\nline 2");
    b.multi_info(false, "char[5] boot_log", b"again");
    b.multi_info(false, "uint8_t[6] blob", &[0xfd, b'7', b'z', b'X', b'Z', 0]);
    b.multi_info(true, "uint8_t[3] blob", &[1, 2, 0xff]);
    b.multi_info(false, "char one", b"x");
    b.param("int32_t MAV_TYPE", &2i32.to_le_bytes());
    b.param("float MPC_XY_VEL_MAX", &12.0f32.to_le_bytes());
    b.param("int32_t SYS_AUTOSTART", &4001i32.to_le_bytes());
    b.default_param(1, "int32_t MAV_TYPE", &1i32.to_le_bytes());
    b.default_param(2, "int32_t MAV_TYPE", &2i32.to_le_bytes());
    b.default_param(3, "float MPC_XY_VEL_MAX", &10.0f32.to_le_bytes());
    b.format("pos:uint64_t timestamp;float x;");
    b.subscribe(0, 0, "pos");
    for i in 0..50u64 {
        let t = 1_000_000 + i * 100_000;
        b.data(
            0,
            &[&t.to_le_bytes()[..], &(i as f32).to_le_bytes()].concat(),
        );
        if i == 20 {
            b.param("float MPC_XY_VEL_MAX", &8.0f32.to_le_bytes());
        }
    }
    let path = dir.join("written.ulg");
    std::fs::write(&path, b.bytes()).unwrap();
    path
}

#[test]
#[cfg_attr(
    not(pyulog),
    ignore = "needs pyulog: pip install pyulog==1.3.0, then touch ulog-cli/build.rs"
)]
fn info_message_equals_ulog_info() {
    let dir = common::scratch("pyulog_info_m");
    let file = written_log(&dir);
    for key in ["boot_log", "blob", "one"] {
        for newline in [false, true] {
            let mut args: Vec<&OsStr> = vec!["-m".as_ref(), key.as_ref()];
            if newline {
                args.push("-n".as_ref());
            }
            args.push(file.as_os_str());
            let theirs = pyulog("ulog_info", &args);
            let mut ours: Vec<&OsStr> = vec!["info".as_ref()];
            ours.extend(&args);
            assert_eq!(
                common::ulog_ok(ours),
                String::from_utf8(theirs).unwrap(),
                "{key} -n {newline}"
            );
        }
    }
    // Where ulog_info says "message … not found" and exits 0: an unknown name (5),
    // with the keys the log has.
    let out = common::ulog([
        "info".as_ref(),
        "-m".as_ref(),
        "bolb".as_ref(),
        file.as_os_str(),
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(5), "{err}");
    assert!(
        err.contains(
            "no multi-information `bolb` in the log (its keys: `blob`, `boot_log`, `one`)"
        ),
        "{err}"
    );
}

/// Every multi-information key of every corpus log (perf counters, boot console,
/// `metadata_events`' xz bytes): `ulog info -m KEY [-n]` prints what ulog_info's own
/// code prints, run in one Python process per log over a log it parsed once.
#[test]
#[cfg_attr(
    not(pyulog),
    ignore = "needs pyulog: pip install pyulog==1.3.0, then touch ulog-cli/build.rs"
)]
fn info_message_of_every_corpus_key_equals_ulog_info() {
    const SCRIPT: &str = r#"
import contextlib, io, json, sys
import pyulog.info as info
from pyulog.core import ULog
path = sys.argv[1]
log = ULog(path, [])  # metadata only: -m reads nothing else
info.ULog = lambda *args, **kwargs: log
out = {}
for key in sorted(log.msg_info_multiple_dict):
    for newline in (False, True):
        sys.argv = ['ulog_info', '-m', key] + (['-n'] if newline else []) + [path]
        text = io.StringIO()
        try:
            with contextlib.redirect_stdout(text):
                info.main()
        except TypeError:
            continue  # numbers, which ulog_info cannot join
        out[json.dumps([key, newline])] = text.getvalue()
print()
print(json.dumps(out))
"#;
    let corpus = common::corpus();
    let mut compared = 0;
    for (stem, path) in common::corpus_logs(&corpus) {
        let bytes = std::fs::read(&path).unwrap();
        if ULog::parse(&bytes).unwrap().multi_info().is_empty() {
            continue;
        }
        let theirs = common::python(["-c".as_ref(), SCRIPT.as_ref(), path.as_os_str()]);
        // The last line: pyulog may print warnings of its own before it.
        let theirs = String::from_utf8(theirs).unwrap();
        let last = theirs.lines().last().unwrap_or_default();
        let theirs: BTreeMap<String, String> = serde_json::from_str(last).unwrap();
        assert!(!theirs.is_empty(), "{stem}");
        for (what, text) in theirs {
            let (key, newline): (String, bool) = serde_json::from_str(&what).unwrap();
            let mut args: Vec<&OsStr> = vec!["info".as_ref(), "-m".as_ref(), key.as_ref()];
            if newline {
                args.push("-n".as_ref());
            }
            args.push(path.as_os_str());
            assert!(
                common::ulog_ok(args) == text,
                "{stem}: -m {key} -n {newline}"
            );
            compared += 1;
        }
    }
    assert!(compared >= 4, "{compared} keys compared");
}

/// ulog2csv's `-ts`/`-te` (boot-time seconds: from the first row at or after the start
/// to the first at or after the end), `-d`, `-i`, `-m` and `-o`, as a pyulog user
/// types them.
#[test]
#[cfg_attr(
    not(pyulog),
    ignore = "needs pyulog: pip install pyulog==1.3.0, then touch ulog-cli/build.rs"
)]
fn csv_takes_ulog2csv_flags() {
    let corpus = common::corpus();
    let path = corpus.join("files").join("esc_status_log.ulg");
    let bytes = std::fs::read(&path).unwrap();
    let log = ULog::parse(&bytes).unwrap();
    // Whole seconds (ulog2csv takes integers) inside the log, and topics with rows on
    // both sides of each (ulog2csv fails on a topic without a row after a bound).
    let start_s = log.start_timestamp() / 1_000_000;
    let (ts, te) = (start_s + 10, start_s + 20);
    let topics: Vec<String> = log
        .topics()
        .filter(|t| t.name() != "esc_status")
        .filter(|t| {
            let times = t.timestamps();
            times.first().is_some_and(|&a| a < ts * 1_000_000)
                && times.last().is_some_and(|&b| b > te * 1_000_000)
        })
        .map(|t| t.name().to_owned())
        .take(4)
        .collect();
    assert!(topics.len() >= 2, "{topics:?}");
    let topics = topics.join(",");
    let root = common::scratch("pyulog_csv_flags");
    let (ts, te) = (ts.to_string(), te.to_string());
    let args = |out: &Path| -> Vec<std::ffi::OsString> {
        ["-m", &topics, "-ts", &ts, "-te", &te, "-d", ";", "-i", "-o"]
            .iter()
            .map(Into::into)
            .chain([out.into(), path.clone().into()])
            .collect()
    };
    let theirs = root.join("py");
    let py_args = args(&theirs);
    let py_args: Vec<&OsStr> = py_args.iter().map(|a| a.as_os_str()).collect();
    pyulog("ulog2csv", &py_args);
    let ours = root.join("ours");
    let mut our_args: Vec<std::ffi::OsString> = vec!["csv".into()];
    our_args.extend(args(&ours));
    common::ulog_ok(&our_args);
    let names = |dir: &Path| {
        let mut v: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    };
    assert_eq!(names(&ours), names(&theirs));
    for name in names(&theirs) {
        let (a, b) = (
            std::fs::read(ours.join(&name)).unwrap(),
            std::fs::read(theirs.join(&name)).unwrap(),
        );
        assert!(
            b.iter().filter(|&&c| c == b'\n').count() > 2,
            "{name}: rows"
        );
        assert!(a == b, "{name} differs from ulog2csv's");
    }
    // `-ts=N` is `-ts N`.
    let eq = root.join("eq");
    common::ulog_ok([
        "csv".as_ref(),
        path.as_os_str(),
        "-m".as_ref(),
        topics.as_ref(),
        format!("-ts={ts}").as_ref(),
        format!("-te={te}").as_ref(),
        "-d".as_ref(),
        ";".as_ref(),
        "-o".as_ref(),
        eq.as_os_str(),
    ]);
    for name in names(&theirs) {
        assert_eq!(
            std::fs::read(eq.join(&name)).unwrap(),
            std::fs::read(theirs.join(&name)).unwrap(),
            "{name}"
        );
    }
}

/// ulog_params' flags: `-i`, `-t`, `-d KIND`, `-l`, `-f`, `--ignore` and the output
/// file as its second argument (or `-o`, as other `ulog` commands take it).
#[test]
#[cfg_attr(
    not(pyulog),
    ignore = "needs pyulog: pip install pyulog==1.3.0, then touch ulog-cli/build.rs"
)]
fn params_takes_ulog_params_flags() {
    let dir = common::scratch("pyulog_params_flags");
    let file = written_log(&dir);
    let runs: [&[&str]; 10] = [
        &[],
        &["-i"],
        &["-t"],
        &["-i", "-t"],
        &["-d", "system"],
        &["-d", "current_setup", "-t"],
        &["-l", ";", "-t"],
        &["-f", "octave"],
        &["-f", "qgc", "-i"],
        &["--ignore"],
    ];
    for extra in runs {
        let mut args: Vec<&OsStr> = extra.iter().map(OsStr::new).collect();
        args.push(file.as_os_str());
        let theirs = pyulog("ulog_params", &args);
        let mut ours: Vec<&OsStr> = vec!["params".as_ref()];
        ours.extend(&args);
        assert_eq!(
            common::ulog_ok(&ours),
            String::from_utf8(theirs).unwrap(),
            "{extra:?}"
        );
    }
    // The output file: ulog_params' second argument, or -o.
    let (py, second, dash_o) = (dir.join("py.txt"), dir.join("b.txt"), dir.join("o.txt"));
    pyulog(
        "ulog_params",
        &["-t".as_ref(), file.as_os_str(), py.as_os_str()],
    );
    common::ulog_ok([
        "params".as_ref(),
        "-t".as_ref(),
        file.as_os_str(),
        second.as_os_str(),
    ]);
    common::ulog_ok([
        "params".as_ref(),
        file.as_os_str(),
        "-t".as_ref(),
        "-o".as_ref(),
        dash_o.as_os_str(),
    ]);
    let py = std::fs::read(&py).unwrap();
    assert!(!py.is_empty());
    assert_eq!(std::fs::read(&second).unwrap(), py);
    assert_eq!(std::fs::read(&dash_o).unwrap(), py);
    // Both at once is a usage error.
    let out = common::ulog([
        "params".as_ref(),
        file.as_os_str(),
        second.as_os_str(),
        "-o".as_ref(),
        dash_o.as_os_str(),
    ]);
    assert_eq!(out.status.code(), Some(2));
}

/// `-i`/`--ignore` of every pyulog script (`-x` of extract_gps_dump) is taken and
/// changes nothing: this reader never stops on text that is not UTF-8.
#[test]
fn ignore_flags_change_nothing() {
    let file = common::sample_file("pyulog_ignore");
    let dir = file.parent().unwrap().to_owned();
    let f = file.to_str().unwrap();
    for (with, without) in [
        (vec!["info", "-i", f], vec!["info", f]),
        (vec!["info", "--ignore", f], vec!["info", f]),
        (vec!["messages", "-i", f], vec!["messages", f]),
        (vec!["params", "--ignore", f], vec!["params", f]),
    ] {
        assert_eq!(
            common::ulog_ok(&with),
            common::ulog_ok(&without),
            "{with:?}"
        );
    }
    let d = dir.to_str().unwrap();
    common::ulog_ok(["csv", f, "-i", "-o", d]);
    let kml = dir.join("t.kml");
    let out = common::ulog(["kml", f, "-i", "-o", kml.to_str().unwrap()]);
    let gps = common::ulog(["gps-dump", f, "-x", "-o", d]);
    // The sample has no GPS topics: what matters is that the flags parse.
    for out in [out, gps] {
        assert_ne!(
            out.status.code(),
            Some(2),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
}
