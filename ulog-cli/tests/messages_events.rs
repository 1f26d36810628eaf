//! `ulog messages` with PX4 events: on every corpus log that embeds event metadata, its
//! output equals pyulog 1.3's `ulog_messages` line for line (with `--no-tagged`, as
//! ulog_messages prints no tagged strings, and `--profile dev`, the profile pyulog
//! decodes with; pyulog's parse warnings, which it prints on stdout, left out); a log
//! without metadata prints its events by id and says why once.

mod common;

use std::process::Command;

/// Whether a corpus log embeds event metadata (its bytes hold the key's name).
fn has_event_metadata(bytes: &[u8]) -> bool {
    let key = b"metadata_events";
    bytes.windows(key.len()).any(|w| w == key)
}

#[test]
#[cfg_attr(
    not(all(pyulog, full_corpus)),
    ignore = "needs pyulog (pip install pyulog==1.3.0) and the full corpus (../shared/corpus): its logs with event metadata"
)]
fn messages_equal_ulog_messages_on_logs_with_events() {
    let corpus = common::corpus();
    let mut compared = 0;
    for (stem, path) in common::corpus_logs(&corpus) {
        if !has_event_metadata(&std::fs::read(&path).unwrap()) {
            continue;
        }
        let script = "import sys\nfrom pyulog.messages import main\nsys.argv = ['ulog_messages', sys.argv[1]]\nmain()\n";
        let py = Command::new("python3")
            .args(["-c", script])
            .arg(&path)
            .output()
            .expect("run python3");
        assert!(
            py.status.success(),
            "{stem}: {}",
            String::from_utf8_lossy(&py.stderr)
        );
        // pyulog prints its parse warnings on stdout (`Warning: no subscription
        // found …`); they are not messages.
        let theirs: String = String::from_utf8(py.stdout)
            .unwrap()
            .lines()
            .filter(|l| !l.starts_with("Warning: "))
            .map(|l| format!("{l}\n"))
            .collect();
        let ours = common::ulog_ok([
            "messages".as_ref(),
            "--no-tagged".as_ref(),
            "--profile".as_ref(),
            "dev".as_ref(),
            path.as_os_str(),
        ]);
        assert!(!theirs.is_empty(), "{stem}: ulog_messages printed nothing");
        let (t, o): (Vec<&str>, Vec<&str>) = (theirs.lines().collect(), ours.lines().collect());
        for (i, (a, b)) in t.iter().zip(&o).enumerate() {
            assert_eq!(a, b, "{stem}: line {}", i + 1);
        }
        assert_eq!(t.len(), o.len(), "{stem}: lines");
        compared += 1;
    }
    assert!(
        compared >= 3,
        "{compared} logs with event metadata compared"
    );
}

#[test]
fn a_log_without_event_metadata_prints_events_by_id_and_says_why_once() {
    use ulog_core::testing::LogBuilder;
    let mut b = LogBuilder::new(1, 0);
    b.info_str("sys_name", "PX4");
    b.format(
        "event:uint64_t timestamp;uint32_t id;uint16_t event_sequence;\
         uint8_t[25] arguments;uint8_t log_levels;",
    );
    b.subscribe(0, 0, "event");
    for (i, t) in [2_000_000u64, 3_000_000].iter().enumerate() {
        let mut p = t.to_le_bytes().to_vec();
        p.extend_from_slice(&0x0100_0010u32.to_le_bytes());
        p.extend_from_slice(&(i as u16).to_le_bytes());
        let mut args = vec![0u8; 25];
        args[0] = 5;
        p.extend_from_slice(&args);
        p.push(0x46);
        b.data(0, &p);
    }
    b.log(b'4', 2_500_000, "Low battery\t");
    let dir = common::scratch("messages_no_metadata");
    let path = dir.join("events.ulg");
    std::fs::write(&path, b.bytes()).unwrap();
    let out = common::ulog(["messages".as_ref(), path.as_os_str()]);
    assert!(out.status.success());
    let stdout = String::from_utf8(out.stdout).unwrap();
    assert_eq!(
        stdout,
        "0:00:02.000 WARNING: [Unknown event with ID 16777232, arguments: 05]\n\
         0:00:02.500 WARNING: Low battery\n\
         0:00:03.000 WARNING: [Unknown event with ID 16777232, arguments: 05]\n"
    );
    let stderr = String::from_utf8(out.stderr).unwrap();
    assert_eq!(stderr.matches("no event metadata").count(), 1, "{stderr}");

    // Metadata given by the user decodes them; the string copy then goes.
    let json = dir.join("events.json");
    std::fs::write(
        &json,
        r#"{"version": 2, "components": {"1": {"namespace": "px4", "event_groups": {
            "default": {"events": {"16": {"name": "low", "message": "Battery at {1}%",
            "arguments": [{"type": "uint8_t", "name": "p"}]}}}}}}}"#,
    )
    .unwrap();
    let out = common::ulog_ok([
        "messages".as_ref(),
        "--events-json".as_ref(),
        json.as_os_str(),
        path.as_os_str(),
    ]);
    assert_eq!(
        out,
        "0:00:02.000 WARNING: Battery at 5%\n0:00:03.000 WARNING: Battery at 5%\n"
    );
    let bad = dir.join("bad.json");
    std::fs::write(&bad, "{").unwrap();
    let out = common::ulog([
        "messages".as_ref(),
        "--events-json".as_ref(),
        bad.as_os_str(),
        path.as_os_str(),
    ]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("not JSON"));
}

#[test]
#[cfg_attr(
    not(full_corpus),
    ignore = "needs the full corpus (../shared/corpus): its logs with event metadata"
)]
fn dump_check_and_the_parquet_metadata_show_the_events() {
    let corpus = common::corpus();
    let mut seen = 0;
    for (stem, path) in common::corpus_logs(&corpus) {
        if !has_event_metadata(&std::fs::read(&path).unwrap()) {
            continue;
        }
        let log_bytes = std::fs::read(&path).unwrap();
        let log = ulog_core::ULog::parse(&log_bytes).unwrap();
        let events = log.events(&ulog_core::events::EventOptions::default());
        let texts: Vec<&str> = events.iter().map(|e| e.text.as_str()).collect();

        // dump: each row of the event topic carries its event.
        let dump = common::ulog_ok(["dump".as_ref(), "--json".as_ref(), path.as_os_str()]);
        let dumped: Vec<String> = dump
            .lines()
            .filter_map(|l| serde_json::from_str::<serde_json::Value>(l).ok())
            .filter_map(|j| {
                j.get("event")
                    .map(|e| e["text"].as_str().unwrap().to_owned())
            })
            .collect();
        assert_eq!(dumped, texts, "{stem}: dump");

        // messages: the default group's events below the protocol level (sorted by
        // time there, where rows are in file order).
        let messages = common::ulog_ok(["messages".as_ref(), path.as_os_str()]);
        for e in events
            .iter()
            .filter(|e| e.level < 8 && e.group.as_deref() == Some("default"))
        {
            let want = format!("{}: {}", e.level_name(), e.text);
            assert!(
                messages.lines().any(|l| l.ends_with(&want)),
                "{stem}: `{want}`"
            );
        }

        // check: nothing wrong with the events.
        let check = common::ulog(["check".as_ref(), "--json".as_ref(), path.as_os_str()]);
        let report: serde_json::Value = serde_json::from_slice(&check.stdout).unwrap();
        let kinds: Vec<&str> = report["files"][0]["problems"]
            .as_array()
            .unwrap()
            .iter()
            .map(|p| p["kind"].as_str().unwrap())
            .collect();
        assert!(
            !kinds
                .iter()
                .any(|k| k.contains("event") && *k != "event_error"),
            "{stem}: {kinds:?}"
        );

        // The Parquet export's metadata.json lists them.
        let dir = common::scratch(&format!("events_parquet_{stem}"));
        common::ulog_ok([
            "parquet".as_ref(),
            "--per-log".as_ref(),
            path.as_os_str(),
            "-o".as_ref(),
            dir.as_os_str(),
            "-m".as_ref(),
            "event".as_ref(),
        ]);
        let meta = dir.join(&stem).join("metadata.json");
        let meta: serde_json::Value =
            serde_json::from_slice(&std::fs::read(&meta).unwrap()).unwrap();
        let listed: Vec<&str> = meta["events"]
            .as_array()
            .unwrap()
            .iter()
            .map(|e| e["text"].as_str().unwrap())
            .collect();
        assert_eq!(listed, texts, "{stem}: metadata.json");
        seen += 1;
    }
    assert!(seen >= 3, "{seen} logs with event metadata");
}

#[test]
fn check_and_dump_say_what_events_could_not_be_decoded() {
    use ulog_core::testing::LogBuilder;
    let mut b = LogBuilder::new(1, 0);
    b.info_str("sys_name", "PX4");
    b.format(
        "event:uint64_t timestamp;uint32_t id;uint16_t event_sequence;\
         uint8_t[25] arguments;uint8_t log_levels;",
    );
    b.subscribe(0, 0, "event");
    let mut p = 1_000u64.to_le_bytes().to_vec();
    p.extend_from_slice(&0x0100_0010u32.to_le_bytes());
    p.extend_from_slice(&0u16.to_le_bytes());
    p.extend_from_slice(&[3; 25]);
    p.push(0x33);
    b.data(0, &p);
    let dir = common::scratch("events_check_dump");
    let path = dir.join("events.ulg");
    std::fs::write(&path, b.bytes()).unwrap();
    let dump = common::ulog_ok(["dump".as_ref(), path.as_os_str()]);
    assert!(
        dump.contains("=> event ERROR: [Unknown event with ID 16777232, arguments: 03 03"),
        "{dump}"
    );
    // (It warns of the missing flag bits too: exit status 1.)
    let check = common::ulog(["check".as_ref(), path.as_os_str()]);
    let text = String::from_utf8(check.stdout).unwrap();
    assert!(text.contains("no event metadata"), "{text}");
}
