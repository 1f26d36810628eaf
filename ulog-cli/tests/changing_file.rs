//! A log that changes while a command reads it (a logger still writing it, a log being
//! rotated or synced): every command that reads ends with an exit status and at most
//! a message, never a signal or a panic, however the file is truncated, extended or
//! rewritten under it.

mod common;

use std::io::{Seek, SeekFrom, Write};
use std::os::unix::process::ExitStatusExt;
use std::path::Path;
use std::process::{Command, Stdio};
use std::sync::atomic::{AtomicBool, Ordering};

use ulog_core::testing::{LogBuilder, Rng};

/// A log of about 4 MB: a few topics, logged strings, parameter changes.
fn big_log() -> Vec<u8> {
    let mut b = LogBuilder::new(1, 0);
    b.flag_bits([0; 8], [0; 8], [0; 3]);
    b.info_str("sys_name", "PX4");
    b.format("fast:uint64_t timestamp;float[6] v;uint32_t n;");
    b.format("slow:uint64_t timestamp;int32_t a;char[12] label;");
    b.param("int32_t MAV_TYPE", &2i32.to_le_bytes());
    b.subscribe(0, 0, "fast");
    b.subscribe(0, 1, "slow");
    b.subscribe(1, 2, "fast");
    for i in 0..100_000u64 {
        let mut p = (i * 1000).to_le_bytes().to_vec();
        for k in 0..6 {
            p.extend_from_slice(&(i as f32 * 0.5 + k as f32).to_le_bytes());
        }
        p.extend_from_slice(&(i as u32).to_le_bytes());
        b.data((i % 2 * 2) as u16, &p);
        if i % 50 == 0 {
            let mut s = (i * 1000).to_le_bytes().to_vec();
            s.extend_from_slice(&(i as i32).to_le_bytes());
            s.extend_from_slice(b"slow-label\0\0");
            b.data(1, &s);
        }
        if i % 5000 == 0 {
            b.log(b'6', i * 1000, "a logged string");
        }
    }
    b.into_bytes()
}

/// Changes the file at `path` (of `len` bytes at first) until `stop`: truncations to
/// any length, extensions with garbage, rewrites of stretches in place. Returns how
/// many changes it made.
fn mutate(path: &Path, original: &[u8], stop: &AtomicBool, seed: u64) -> usize {
    let mut rng = Rng::new(seed | 1);
    let len = original.len() as u64;
    let mut changes = 0;
    while !stop.load(Ordering::Relaxed) {
        changes += 1;
        let Ok(mut f) = std::fs::OpenOptions::new().write(true).open(path) else {
            continue;
        };
        match rng.next_u64() % 4 {
            0 => {
                let _ = f.set_len(rng.next_u64() % len);
            }
            1 => {
                let at = rng.next_u64() % len;
                let garbage: Vec<u8> = (0..4096).map(|_| rng.next_u64() as u8).collect();
                let _ = f.seek(SeekFrom::Start(at));
                let _ = f.write_all(&garbage);
            }
            2 => {
                let _ = f.set_len(len + rng.next_u64() % 65_536);
            }
            _ => {
                // Back to the original, to be cut again while it is read.
                let _ = f.set_len(0);
                let _ = f.seek(SeekFrom::Start(0));
                let _ = f.write_all(original);
            }
        }
    }
    changes
}

#[test]
fn every_command_survives_a_file_changing_under_it() {
    let dir = common::scratch("changing_file");
    let original = big_log();
    // Each command that reads a log, with what it needs.
    let out = dir.join("out");
    let commands: Vec<Vec<String>> = vec![
        vec!["info".into()],
        vec!["check".into()],
        vec!["dump".into(), "--json".into()],
        vec!["messages".into()],
        vec!["params".into()],
        vec![
            "csv".into(),
            "-o".into(),
            out.display().to_string(),
            "-q".into(),
        ],
        vec![
            "parquet".into(),
            "--per-log".into(),
            "-o".into(),
            out.display().to_string(),
            "-q".into(),
        ],
        // A dataset of one: its id read before the pass, checked again by it.
        vec![
            "parquet".into(),
            "-o".into(),
            out.display().to_string(),
            "-q".into(),
        ],
        // Two passes over the file.
        vec![
            "report".into(),
            "-o".into(),
            dir.join("report.html").display().to_string(),
        ],
        vec!["codegen".into()],
        vec![
            "plot".into(),
            "fast.v[0]".into(),
            "-o".into(),
            dir.join("plot.svg").display().to_string(),
        ],
    ];
    const RUNS: usize = 40;
    let mut runs = 0;
    for (c, args) in commands.iter().enumerate() {
        let mut changes = 0;
        for run in 0..RUNS {
            let path = dir.join("changing.ulg");
            std::fs::write(&path, &original).unwrap();
            let _ = std::fs::remove_dir_all(&out);
            let stop = AtomicBool::new(false);
            let output = std::thread::scope(|s| {
                let mutator =
                    s.spawn(|| mutate(&path, &original, &stop, (c * RUNS + run) as u64 * 7919));
                let mut cmd = Command::new(env!("CARGO_BIN_EXE_ulog"));
                cmd.arg(&args[0]).arg(&path).args(&args[1..]);
                let output = cmd
                    .stdin(Stdio::null())
                    .stdout(Stdio::null())
                    .stderr(Stdio::piped())
                    .output()
                    .expect("run ulog");
                stop.store(true, Ordering::Relaxed);
                changes += mutator.join().unwrap();
                output
            });
            let stderr = String::from_utf8_lossy(&output.stderr);
            assert!(
                output.status.signal().is_none(),
                "`ulog {}` killed by signal {:?}: {stderr}",
                args[0],
                output.status.signal()
            );
            assert!(
                !stderr.contains("panicked"),
                "`ulog {}` panicked: {stderr}",
                args[0]
            );
            // 0 ok, 1 findings (check), 3 unreadable, 4 not ULog, 5 no such topic or
            // field (plot, once the cut removed it), 6 other (an output error).
            let code = output.status.code().unwrap();
            assert!(
                [0, 1, 3, 4, 5, 6].contains(&code),
                "`ulog {}` exit {code}: {stderr}",
                args[0]
            );
            runs += 1;
        }
        // The file did change under the command, at least once a run on average
        // (how often is printed: a whole rewrite takes longer than a short command).
        assert!(
            changes >= RUNS,
            "`ulog {}`: only {changes} changes in {RUNS} runs",
            args[0]
        );
        eprintln!("`ulog {}`: {RUNS} runs, {changes} changes", args[0]);
    }
    eprintln!(
        "{runs} runs of {} commands on a changing file",
        commands.len()
    );
}
