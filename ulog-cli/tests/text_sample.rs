//! `ulog info`, `messages` and `params` on the bundled sample log: the exact layout of
//! pyulog's scripts (these texts were checked against ulog_info, ulog_messages and
//! ulog_params 1.3.0 run on the same bytes), plus what pyulog does not show.

mod common;

const INFO: &str = "\
Logging start time: 0:00:01, duration: 0:00:09
Dropouts: count: 1, total duration: 0.0 s, max: 12 ms, mean: 12 ms
SW Version: v1.14.3
Info Messages:
 sys_name: PX4
 time_ref_utc: 0
 ver_hw: SIMULATED
 ver_sw_release: 17695743
Info Multiple Messages: [boot_console: 1]

Name (multi id, message size in bytes)    number of data points, total bytes
 battery_status (0, 17)                        20        340
 battery_status (1, 17)                        20        340
 esc_status (0, 48)                            20        960
 vehicle_attitude (0, 24)                     200       4800
 vehicle_local_position (0, 33)               100       3300

File version: 1
Flag bits: compat [1, 0, 0, 0, 0, 0, 0, 0], incompat [0, 0, 0, 0, 0, 0, 0, 0], appended offsets [0, 0, 0]
UTC start: unknown (no GPS time, no boot_time_utc_us information)
Time span: 0:00:01 to 0:00:10 (9.950 s)
Messages: 390 (2 logged, 1 tagged, 1 parameter changes, 4 sync)
Truncated: no
Findings: none
";

#[test]
fn info_without_file_shows_the_bundled_sample() {
    let out = common::ulog(["info"]);
    assert!(out.status.success());
    assert_eq!(String::from_utf8(out.stdout).unwrap(), INFO);
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(err.contains("bundled sample"), "{err}");
    assert_eq!(err.lines().count(), 1);
}

#[test]
fn info_of_a_file_equals_info_of_the_bundled_sample() {
    let file = common::sample_file("info_file");
    assert_eq!(common::ulog_ok(["info".as_ref(), file.as_os_str()]), INFO);
}

#[test]
fn verbose_info_shows_multi_information_as_python_lists() {
    let out = common::ulog_ok(["info", "-v"]);
    assert!(
        out.contains("Info Multiple Messages:\n boot_console: [['line 1', 'line 2']]\n"),
        "{out}"
    );
}

#[test]
fn info_json_has_the_documented_keys() {
    let out = common::ulog_ok(["info", "--json"]);
    let j: serde_json::Value = serde_json::from_str(&out).unwrap();
    for key in [
        "file",
        "file_version",
        "start_timestamp",
        "last_timestamp",
        "duration_s",
        "flag_bits",
        "appended_sections",
        "sw_version",
        "info",
        "info_multiple",
        "dropouts",
        "topics",
        "message_count",
        "logged_messages",
        "tagged_messages",
        "initial_parameters",
        "changed_parameters",
        "default_parameters",
        "sync_messages",
        "unknown_messages",
        "truncated",
        "corrupted",
        "findings",
    ] {
        assert!(j.get(key).is_some(), "missing key {key}");
    }
    assert_eq!(j["info"]["sys_name"], "PX4");
    assert_eq!(j["sw_version"], "v1.14.3");
    assert_eq!(j["topics"][3]["name"], "vehicle_attitude");
    assert_eq!(j["topics"][3]["data_points"], 200);
    assert_eq!(j["info_multiple"]["boot_console"][0][1], "line 2");
    assert_eq!(j["tagged_messages"], 1);
    assert_eq!(j["findings"].as_array().unwrap().len(), 0);
    let help = common::ulog_ok(["info", "--help"]);
    for key in j.as_object().unwrap().keys() {
        assert!(
            help.contains(&format!("  {key} ")),
            "--help does not document `{key}`"
        );
    }
}

#[test]
fn messages_in_time_order_with_tagged_ones() {
    let file = common::sample_file("messages");
    assert_eq!(
        common::ulog_ok(["messages".as_ref(), file.as_os_str()]),
        "0:00:01.000 INFO: [commander] Takeoff detected\n\
         0:00:06.000 WARNING: battery at 70%\n\
         0:00:11.000 INFO: [commander] Landing detected\n"
    );
    assert_eq!(
        common::ulog_ok([
            "messages".as_ref(),
            "--no-tagged".as_ref(),
            file.as_os_str()
        ]),
        "0:00:01.000 INFO: [commander] Takeoff detected\n\
         0:00:11.000 INFO: [commander] Landing detected\n"
    );
    assert!(common::ulog_ok(["messages", "--help"]).contains("events"));
}

#[test]
fn params_in_every_format() {
    let file = common::sample_file("params");
    let run = |opts: &[&str]| {
        let mut args = vec![std::ffi::OsStr::new("params"), file.as_os_str()];
        args.extend(opts.iter().map(std::ffi::OsStr::new));
        common::ulog_ok(args)
    };
    assert_eq!(run(&[]), "MAV_TYPE,2\nMPC_XY_VEL_MAX,12.0,8.0\n");
    assert_eq!(run(&["--initial"]), "MAV_TYPE,2\nMPC_XY_VEL_MAX,12.0\n");
    assert_eq!(run(&["-l", ";"]), "MAV_TYPE;2\nMPC_XY_VEL_MAX;12.0;8.0\n");
    assert_eq!(
        run(&["--timestamps"]),
        "MAV_TYPE,2\ntimestamp,0\nMPC_XY_VEL_MAX,12.0,8.0\ntimestamp,0,6000000\n"
    );
    // ulog_params reads no data with --initial: changes are stamped at the start time.
    assert_eq!(
        run(&["--initial", "--timestamps"]),
        "MAV_TYPE,2\ntimestamp,0\nMPC_XY_VEL_MAX,12.0,8.0\ntimestamp,0,1000000\n"
    );
    assert_eq!(
        run(&["--format", "octave"]),
        "# name MAV_TYPE\n# type: scalar\n2\n\
         # name MPC_XY_VEL_MAX\n# type: matrix\n# rows: 1\n# columns: 2\n12.0 8.0 \n"
    );
    assert_eq!(
        run(&["--format", "qgc"]),
        "1\t1\tMAV_TYPE\t2\t6\n1\t1\tMPC_XY_VEL_MAX\t12.0\t9\n"
    );
    assert_eq!(
        run(&["--default", "system"]),
        "MAV_TYPE,1\nMPC_XY_VEL_MAX,12.0\n"
    );
    assert_eq!(run(&["--default", "current_setup"]), "MAV_TYPE,1\n");
    let out_file = file.with_file_name("params.txt");
    run(&[out_file.to_str().unwrap()]);
    assert_eq!(
        std::fs::read_to_string(out_file).unwrap(),
        "MAV_TYPE,2\nMPC_XY_VEL_MAX,12.0,8.0\n"
    );
}

#[test]
fn a_closed_pipe_is_not_an_error() {
    use std::process::{Command, Stdio};
    let mut child = Command::new(env!("CARGO_BIN_EXE_ulog"))
        .args(["info", "-v"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!err.contains("panicked"), "{err}");
    assert!(out.status.success(), "{err}");
}
