//! `ulog cut`: times as seconds since the start (`90`, `1:30`, `1:30.5`) or raw
//! microseconds, topic choices, the output checked with the reader, and the failures.

mod common;

use ulog_core::ULog;

#[test]
fn cut_keeps_the_window_and_the_topics_asked_for() {
    let log = common::sample_file("cut_window");
    let dir = log.parent().unwrap().to_owned();
    let bytes = std::fs::read(&log).unwrap();
    let original = ULog::parse(&bytes).unwrap();
    let start = original.start_timestamp();
    let topic = original
        .topics()
        .find(|t| t.len() > 2 && t.timestamp_field().is_some())
        .expect("a topic with rows");
    let times = topic.timestamps();
    let (from, to) = (times[1], times[times.len() - 1]);
    let name = topic.name().to_owned();

    // The same window given as seconds and as microseconds.
    let secs = |us: u64| format!("{}", (us - start) as f64 / 1e6);
    let a = dir.join("a.ulg");
    let out = common::ulog_ok([
        "cut",
        log.to_str().unwrap(),
        "-o",
        a.to_str().unwrap(),
        "--start",
        &secs(from),
        "--end",
        &secs(to),
        "-m",
        &name,
    ]);
    assert!(
        out.starts_with(&format!("Writing {}", a.display())),
        "{out}"
    );
    let b = dir.join("b.ulg");
    common::ulog_ok([
        "cut",
        log.to_str().unwrap(),
        "-o",
        b.to_str().unwrap(),
        "--start-us",
        &from.to_string(),
        "--end-us",
        &to.to_string(),
        "-m",
        &name,
    ]);
    let (a, b) = (std::fs::read(a).unwrap(), std::fs::read(b).unwrap());
    assert!(a == b, "seconds and microseconds give the same cut");
    let cut = ULog::parse(&a).unwrap();
    assert!(cut.topics().all(|t| t.name() == name));
    let kept = cut.topic(&name, topic.multi_id()).unwrap().timestamps();
    let expected: Vec<u64> = times
        .iter()
        .copied()
        .filter(|&t| from <= t && t < to)
        .collect();
    assert_eq!(kept, expected);

    // --exclude leaves the topic out, and keeps the others.
    let c = dir.join("c.ulg");
    common::ulog_ok([
        "cut",
        log.to_str().unwrap(),
        "-o",
        c.to_str().unwrap(),
        "--exclude",
        &name,
    ]);
    let c = std::fs::read(c).unwrap();
    let cut = ULog::parse(&c).unwrap();
    assert!(cut.topic_instances(&name).is_empty());
    assert_eq!(
        cut.topics().count(),
        original.topics().filter(|t| t.name() != name).count()
    );
}

#[test]
fn cut_failures_are_one_line_with_their_status() {
    let log = common::sample_file("cut_failures");
    let dir = log.parent().unwrap().to_owned();
    let out_path = dir.join("out.ulg");
    let run = |extra: &[&str]| {
        let mut args = vec![
            "cut",
            log.to_str().unwrap(),
            "-o",
            out_path.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        common::ulog(args)
    };
    let stderr = |o: &std::process::Output| String::from_utf8_lossy(&o.stderr).into_owned();

    let out = run(&["--start", "1:75"]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("`1:75` is not a time"),
        "{}",
        stderr(&out)
    );

    let out = run(&["-m", "esc_statsu"]);
    assert_eq!(out.status.code(), Some(5));
    assert!(
        stderr(&out).contains("did you mean `esc_status`?"),
        "{}",
        stderr(&out)
    );
    assert!(!out_path.exists(), "nothing written for an unknown topic");

    let out = common::ulog(["cut", log.to_str().unwrap(), "-o", log.to_str().unwrap()]);
    assert_ne!(out.status.code(), Some(0));
    assert!(
        stderr(&out).contains("would replace the input"),
        "{}",
        stderr(&out)
    );
    assert_eq!(
        std::fs::read(&log).unwrap(),
        ulog_core::testing::sample_log()
    );

    // Damage is not copied, and said.
    let mut damaged = ulog_core::testing::sample_log();
    let at = damaged.len() / 2;
    damaged[at..at + 40].fill(0xff);
    let bad = dir.join("damaged.ulg");
    std::fs::write(&bad, &damaged).unwrap();
    let out = common::ulog([
        "cut",
        bad.to_str().unwrap(),
        "-o",
        out_path.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(stderr(&out).contains("not copied"), "{}", stderr(&out));
    let cut = std::fs::read(&out_path).unwrap();
    assert!(ULog::parse(&cut)
        .unwrap()
        .findings()
        .iter()
        .all(|f| !f.is_damage()));
}

/// A window that holds no time (6), or none of the log's data (7), is an error with
/// one line saying why, and no output file, partial or whole, is left behind.
#[test]
fn empty_and_inverted_windows_are_refused_and_write_nothing() {
    let log = common::sample_file("cut_empty");
    let dir = log.parent().unwrap().to_owned();
    let bytes = std::fs::read(&log).unwrap();
    let original = ULog::parse(&bytes).unwrap();
    let start = original.start_timestamp();
    let end_s = (original.last_timestamp() - start) as f64 / 1e6;
    let out_path = dir.join("out.ulg");
    let partial = dir.join("out.ulg.partial");
    let run = |extra: &[&str], status: i32| {
        let mut args = vec![
            "cut",
            log.to_str().unwrap(),
            "-o",
            out_path.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        let out = common::ulog(args);
        let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
        assert_eq!(out.status.code(), Some(status), "{extra:?}: {stderr}");
        assert_eq!(stderr.lines().count(), 1, "{extra:?}: {stderr}");
        assert!(!out_path.exists(), "{extra:?}: an output was left");
        assert!(!partial.exists(), "{extra:?}: a partial output was left");
        stderr
    };
    let after = format!("{}", end_s + 10.0);
    let later = format!("{}", end_s + 20.0);
    let us = |t: u64| t.to_string();
    // 6: a window that cannot hold anything; 7: the log has no data in it.
    for (extra, says, status) in [
        (
            vec!["--start", "30", "--end", "20"],
            "--start 30 s is not before --end 20 s",
            6,
        ),
        (
            vec!["--start", "5", "--end", "5"],
            "--start 5 s is not before --end 5 s",
            6,
        ),
        (
            vec!["--start-us", &us(start + 2), "--end-us", &us(start + 1)],
            "is not before --end-us",
            6,
        ),
        (
            vec!["--start", "1", "--end-us", &us(start)],
            "the window is empty",
            6,
        ),
        (vec!["--start", &after], "no data in the window", 7),
        (
            vec!["--start", &after, "--end", &later],
            "no data in the window",
            7,
        ),
        (
            vec!["--end-us", &us(start.saturating_sub(1))],
            "no data in the window",
            7,
        ),
    ] {
        let stderr = run(&extra, status);
        assert!(stderr.contains(says), "{extra:?}: {stderr}");
    }
    // Where the data is, for a window past it.
    let stderr = run(&["--start", &after], 7);
    let first = original
        .topics()
        .flat_map(|t| t.timestamps())
        .min()
        .unwrap();
    let span = format!(
        "the log's data runs from {:.3} s to {:.3} s",
        (first as f64 - start as f64) / 1e6,
        end_s
    );
    assert!(stderr.contains(&span), "{stderr}");
    // A topic with data, but none of it in the window.
    let topic = original
        .topics()
        .filter(|t| t.len() > 1 && t.timestamp_field().is_some())
        .min_by_key(|t| t.timestamps().last().copied())
        .expect("a topic with rows");
    let its_last = *topic.timestamps().last().unwrap();
    assert!(
        its_last < original.last_timestamp(),
        "another topic runs on"
    );
    let from = format!("{}", (its_last + 1 - start) as f64 / 1e6 + 1e-6);
    let stderr = run(&["--start", &from, "-m", topic.name()], 7);
    assert!(stderr.contains("no data of the topics chosen"), "{stderr}");
    // The same window of every topic is a cut.
    common::ulog_ok([
        "cut",
        log.to_str().unwrap(),
        "-o",
        out_path.to_str().unwrap(),
        "--start",
        &from,
    ]);
    assert!(out_path.exists());
}

#[test]
fn anonymise_leaves_out_the_identity_and_moves_positions_as_asked() {
    use ulog_core::testing::LogBuilder;
    let dir = common::scratch("anonymise_cli");
    std::fs::create_dir_all(&dir).unwrap();
    let uuid = "0004004B3038511834303533";
    let mut b = LogBuilder::new(1, 900);
    b.info_str("sys_uuid", uuid);
    b.info_str("sys_name", "PX4");
    b.format("home_position:uint64_t timestamp;double lat;double lon;float alt;");
    b.subscribe(0, 0, "home_position");
    let row = |t: u64, lat: f64, lon: f64| {
        [
            &t.to_le_bytes()[..],
            &lat.to_le_bytes(),
            &lon.to_le_bytes(),
            &12.5f32.to_le_bytes(),
        ]
        .concat()
    };
    b.data(0, &row(1_000, 47.397742, 8.545594));
    b.data(0, &row(2_000, 47.397842, 8.545694));
    let input = dir.join("in.ulg");
    std::fs::write(&input, b.bytes()).unwrap();
    let output = dir.join("out.ulg");
    let (i, o) = (input.to_str().unwrap(), output.to_str().unwrap());

    common::ulog_ok(["anonymise", i, "-o", o, "--to", "-33.9,151.2"]);
    let out = std::fs::read(&output).unwrap();
    assert!(!out.windows(uuid.len()).any(|w| w == uuid.as_bytes()));
    let log = ULog::parse(&out).unwrap();
    assert_eq!(log.info_value("sys_name").unwrap().to_string(), "PX4");
    let home = log.topic("home_position", 0).unwrap();
    let lat = home.field("lat").unwrap();
    let lon = home.field("lon").unwrap();
    let first = home.payload(0).unwrap();
    let at = |f: &ulog_core::FieldReader| f.read(first).and_then(|v| v.as_f64()).unwrap();
    assert!((at(&lat) + 33.9).abs() < 1e-9 && (at(&lon) - 151.2).abs() < 1e-9);
    let alt = home.field("alt").unwrap();
    assert_eq!(alt.read(first).and_then(|v| v.as_f64()), Some(12.5));

    common::ulog_ok(["anonymise", i, "-o", o, "--keep", "sys_uuid"]);
    let out = std::fs::read(&output).unwrap();
    assert!(out.windows(uuid.len()).any(|w| w == uuid.as_bytes()));

    assert_eq!(ULog::parse(&out).unwrap().start_timestamp(), 900);

    common::ulog_ok(["anonymise", i, "-o", o, "--zero-start"]);
    let log_bytes = std::fs::read(&output).unwrap();
    let log = ULog::parse(&log_bytes).unwrap();
    assert_eq!(log.start_timestamp(), 0);
    let home = log.topic("home_position", 0).unwrap();
    assert_eq!(home.timestamps(), [1_000, 2_000], "data times stay");

    let bad = common::ulog(["anonymise", i, "-o", o, "--to", "91,0"]);
    assert_eq!(bad.status.code(), Some(2));
}
