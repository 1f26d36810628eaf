//! Memory of `ulog parquet` and `ulog check` on the inputs that used to blow it up
//! (issue: reliability, items 6–8): each command runs in a child whose data segment is
//! limited (`ulimit -d`, which on Linux counts the heap and private writable mappings)
//! to twice the input plus a fixed allowance, and must succeed under it. And `ulog
//! report` of a long log, under a limit well below the log's size: it reads the file
//! in passes, never all of it at once; and the commands that need only the metadata
//! (`info`, `messages`, `params`, `codegen`, and `plot` of a slow topic) under a
//! limit of 32 MiB whatever the log's size: they read it once, in chunks.

mod common;

use std::path::Path;
use std::process::Command;

use ulog_core::testing::LogBuilder;

/// The fixed allowance above twice the input: the binary's own data, the thread
/// stacks of `-j 4`, the Parquet writer of one column and the output buffers.
const ALLOWANCE_MIB: u64 = 320;

fn flag_bits() -> LogBuilder {
    let mut b = LogBuilder::new(1, 0);
    b.flag_bits([0; 8], [0; 8], [0; 3]);
    b
}

/// Item 6: four topics of 65,000 one-byte fields each (flattened: 65,000 columns per
/// topic), `rows` rows each.
fn wide_topics(rows: u64) -> Vec<u8> {
    let mut b = flag_bits();
    for (id, name) in ["wa", "wb", "wc", "wd"].into_iter().enumerate() {
        b.format(&format!("{name}:uint64_t timestamp;uint8_t[65000] x;"));
        b.subscribe(0, id as u16, name);
    }
    for i in 0..rows {
        for id in 0..4u16 {
            let mut p = (i * 1000 + id as u64).to_le_bytes().to_vec();
            p.extend((0..65_000u32).map(|k| (k as u64 + i) as u8));
            b.data(id, &p);
        }
    }
    b.into_bytes()
}

/// Item 6: nested formats as a binary tree, `depth` levels of two children each
/// (2^depth leaves of one byte, at most 15 levels to fit a message, one struct column with that many leaves), `rows` rows.
fn binary_tree(depth: u32, rows: u64) -> Vec<u8> {
    let mut b = flag_bits();
    b.format("n0:uint8_t a;uint8_t b;");
    for level in 1..depth - 1 {
        let below = level - 1;
        b.format(&format!("n{level}:n{below} a;n{below} b;"));
    }
    let top = depth - 2;
    b.format(&format!("tree:uint64_t timestamp;n{top} l;n{top} r;"));
    b.subscribe(0, 0, "tree");
    for i in 0..rows {
        let mut p = (i * 1000).to_le_bytes().to_vec();
        p.extend((0..1u32 << depth).map(|k| (k as u64 * 7 + i) as u8));
        b.data(0, &p);
    }
    b.into_bytes()
}

/// Item 7: `n` information keys (and a topic, so that there is a file to write).
fn many_keys(n: u32) -> Vec<u8> {
    let mut b = flag_bits();
    for i in 0..n {
        b.info(&format!("uint32_t key_{i}"), &i.to_le_bytes());
    }
    b.format("t:uint64_t timestamp;uint32_t a;");
    b.subscribe(0, 0, "t");
    for i in 0..100u64 {
        let mut p = (i * 1000).to_le_bytes().to_vec();
        p.extend_from_slice(&(i as u32).to_le_bytes());
        b.data(0, &p);
    }
    b.into_bytes()
}

/// Item 8: `mib` MiB of repeated sync markers between two stretches of rows.
fn sync_markers(mib: usize) -> Vec<u8> {
    const MAGIC: [u8; 8] = [0x2F, 0x73, 0x13, 0x20, 0x25, 0x0C, 0xBB, 0x12];
    let mut b = flag_bits();
    b.format("t:uint64_t timestamp;uint32_t a;");
    b.subscribe(0, 0, "t");
    let row = |i: u64| {
        let mut p = (i * 1000).to_le_bytes().to_vec();
        p.extend_from_slice(&(i as u32).to_le_bytes());
        p
    };
    for i in 0..100 {
        b.data(0, &row(i));
    }
    b.garbage(&MAGIC.repeat((mib << 20) / 8));
    for i in 100..200 {
        b.data(0, &row(i));
    }
    b.into_bytes()
}

/// Runs `ulog ARGS` with its data segment limited to twice `input`'s size plus
/// [`ALLOWANCE_MIB`]; panics with its stderr unless it exits with one of `statuses`
/// (an allocation refused aborts it: a signal, no status).
fn run_limited(input: &Path, args: &[&str], statuses: &[i32]) {
    let size = std::fs::metadata(input).unwrap().len();
    let limit_kib = 2 * size / 1024 + ALLOWANCE_MIB * 1024;
    let out = Command::new("sh")
        .arg("-c")
        .arg(format!("ulimit -d {limit_kib} && exec \"$0\" \"$@\""))
        .arg(env!("CARGO_BIN_EXE_ulog"))
        .args(args)
        .output()
        .unwrap();
    assert!(
        out.status.code().is_some_and(|c| statuses.contains(&c)),
        "ulog {} on {} bytes, limit {} MiB: {:?}\n{}",
        args.join(" "),
        size,
        limit_kib / 1024,
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
}

/// Runs `ulog ARGS` with its data segment limited to `limit_mib`; panics with its
/// stderr unless it succeeds.
fn run_under(limit_mib: u64, args: &[&str]) {
    let out = Command::new("sh")
        .arg("-c")
        .arg(format!(
            "ulimit -d {} && exec \"$0\" \"$@\"",
            limit_mib * 1024
        ))
        .arg(env!("CARGO_BIN_EXE_ulog"))
        .args(args)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "ulog {} under {limit_mib} MiB: {:?}\n{}",
        args.join(" "),
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
}

/// A PX4-like log of about `mib` MiB: attitude at 250 Hz, the local position at
/// 50 Hz, status and battery at 5 Hz, with information, a parameter and messages.
fn long_flight(mib: usize) -> Vec<u8> {
    let mut b = flag_bits();
    b.info_str("sys_name", "PX4");
    b.param("int32_t MAV_TYPE", &2i32.to_le_bytes());
    b.format("vehicle_attitude:uint64_t timestamp;float[4] q;");
    b.format(
        "vehicle_local_position:uint64_t timestamp;float x;float y;float z;float vx;\
         float vy;float vz;bool xy_valid;uint8_t[3] _padding0;",
    );
    b.format("vehicle_status:uint64_t timestamp;uint8_t nav_state;uint8_t arming_state;");
    b.format("battery_status:uint64_t timestamp;float voltage_v;float remaining;");
    for (id, name) in [
        "vehicle_attitude",
        "vehicle_local_position",
        "vehicle_status",
        "battery_status",
    ]
    .into_iter()
    .enumerate()
    {
        b.subscribe(0, id as u16, name);
    }
    let f32s = |t: u64, values: &[f32]| -> Vec<u8> {
        let mut p = t.to_le_bytes().to_vec();
        values
            .iter()
            .for_each(|v| p.extend_from_slice(&v.to_le_bytes()));
        p
    };
    let mut t = 1_000_000u64;
    while b.bytes().len() < mib << 20 {
        t += 4000;
        let a = (t as f32 / 1e7).sin();
        b.data(0, &f32s(t, &[a.cos(), a.sin(), 0.0, 0.0]));
        if t % 20_000 == 0 {
            let mut p = f32s(t, &[a * 10.0, a * 5.0, -a, 0.1, 0.2, 0.3]);
            p.extend_from_slice(&[1, 0, 0, 0]);
            b.data(1, &p);
        }
        if t % 200_000 == 0 {
            let mut p = t.to_le_bytes().to_vec();
            p.extend_from_slice(&[(t / 60_000_000 % 4) as u8, 2]);
            b.data(2, &p);
            b.data(3, &f32s(t, &[16.0 - a, 0.5]));
        }
        if t % 100_000_000 == 0 {
            b.log(b'6', t, "still flying");
        }
    }
    b.into_bytes()
}

/// The report of a log of 160 MiB runs in half that: no copy of the log, only the
/// page and the read buffers.
#[test]
fn a_report_stays_far_below_the_logs_size() {
    let dir = common::scratch("memory_report");
    let log = dir.join("long.ulg");
    std::fs::write(&log, long_flight(160)).unwrap();
    let page = dir.join("long.html");
    run_under(
        80,
        &[
            "report",
            log.to_str().unwrap(),
            "-o",
            page.to_str().unwrap(),
        ],
    );
    let text = std::fs::read_to_string(&page).unwrap();
    assert!(text.contains("Roll angle"), "the attitude is drawn");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `info`, `messages`, `params`, `codegen` and `plot` of a slow topic, of a log of
/// 128 MiB, run under 32 MiB: one pass in chunks keeps only the metadata (and the
/// rows plotted).
#[test]
fn metadata_commands_stay_within_32_mib() {
    let dir = common::scratch("memory_metadata");
    let log = dir.join("long.ulg");
    std::fs::write(&log, long_flight(128)).unwrap();
    let log_arg = log.to_str().unwrap();
    let svg = dir.join("battery.svg");
    for args in [
        &["info", log_arg][..],
        &["info", "--json", log_arg],
        &["messages", log_arg],
        &["params", log_arg, "-t"],
        &["codegen", log_arg],
        // The rows of the topic plotted are kept, not the others'.
        &[
            "plot",
            log_arg,
            "battery_status.voltage_v",
            "-o",
            svg.to_str().unwrap(),
        ],
    ] {
        run_under(32, args);
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

fn check_and_parquet(test: &str, bytes: &[u8], parquet_args: &[&[&str]]) {
    let dir = common::scratch(test);
    let log = dir.join("in.ulg");
    std::fs::write(&log, bytes).unwrap();
    let log_arg = log.to_str().unwrap();
    // 1: the log has damage or warnings (the sync markers), which check reports.
    run_limited(&log, &["check", log_arg], &[0, 1]);
    for (i, extra) in parquet_args.iter().enumerate() {
        let out = dir.join(format!("out{i}"));
        let mut args = vec!["parquet", "--per-log", log_arg, "-o", out.to_str().unwrap()];
        args.extend_from_slice(extra);
        run_limited(&log, &args, &[0]);
    }
    // The default layout, a dataset, with the first options.
    let out = dir.join("dataset");
    let mut args = vec!["parquet", log_arg, "-o", out.to_str().unwrap()];
    args.extend_from_slice(parquet_args.first().copied().unwrap_or_default());
    run_limited(&log, &args, &[0]);
    // std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn wide_topics_flattened_stay_within_the_bound() {
    let bytes = wide_topics(1);
    check_and_parquet(
        "memory_wide",
        &bytes,
        &[&["--flatten", "-j", "1"], &["--flatten", "-j", "4"], &[]],
    );
}

#[test]
fn a_binary_tree_of_nested_formats_stays_within_the_bound() {
    let bytes = binary_tree(15, 200);
    check_and_parquet("memory_tree", &bytes, &[&[], &["--flatten"]]);
}

#[test]
fn many_information_keys_stay_within_the_bound() {
    let bytes = many_keys(200_000);
    check_and_parquet("memory_keys", &bytes, &[&[]]);
}

#[test]
fn a_run_of_sync_markers_stays_within_the_bound() {
    let bytes = sync_markers(64);
    check_and_parquet("memory_sync", &bytes, &[&[]]);
}
