//! Damage that used to lose data (issue: reliability), each on bytes that reproduce
//! it, against pyulog where it reads the same bytes: the rows we keep are a superset
//! of pyulog's.

use ulog_core::read::{Corruption, FindingKind, Messages, ReadErrorKind};
use ulog_core::testing::{LogBuilder, Rng};
use ulog_core::{ScanOptions, Source, ULog};
use ulog_tests::{cell_matches, pyulog_dump};

const FORMAT: &str = "t:uint64_t timestamp;uint32_t a;uint32_t b;";

fn row(i: u64) -> Vec<u8> {
    let mut p = (1_000 + i * 100).to_le_bytes().to_vec();
    p.extend_from_slice(&(i as u32).to_le_bytes());
    p.extend_from_slice(&(i as u32 * 3).to_le_bytes());
    p
}

/// A v1 log with one topic `t` (msg_id 0) and its flag bits.
fn start() -> LogBuilder {
    let mut b = LogBuilder::new(1, 0);
    b.flag_bits([0; 8], [0; 8], [0; 3]);
    b.format(FORMAT);
    b.subscribe(0, 0, "t");
    b
}

fn rows_of(log: &ULog<'_>) -> usize {
    log.topic("t", 0).map_or(0, |t| t.len())
}

/// pyulog's row count of `t/0`, and all it read.
fn pyulog_rows(test: &str, bytes: &[u8]) -> (usize, serde_json::Value) {
    let py = pyulog_dump(test, bytes);
    let rows = py["topics"]["t/0"]["timestamp"]
        .as_array()
        .map_or(0, |a| a.len());
    (rows, py)
}

#[test]
#[cfg_attr(
    not(pyulog),
    ignore = "needs pyulog: pip install pyulog==1.3.0, then touch tests/build.rs"
)]
fn a_log_level_outside_0_to_7_keeps_the_string_and_the_rows_after_it() {
    let mut b = start();
    for i in 0..1_000u64 {
        b.data(0, &row(i));
        if i % 2 == 0 {
            // Every second logged string with a level byte that is not '0'..'7'.
            let level = if i % 4 == 0 { b'x' } else { b'6' };
            b.log(level, 1_000 + i * 100, &format!("string {i}"));
        }
    }
    let bytes = b.into_bytes();
    let log = ULog::parse(&bytes).unwrap();
    assert!(log.findings().is_empty(), "{:?}", log.findings());
    assert_eq!(rows_of(&log), 1_000);
    assert_eq!(log.logged_messages().len(), 500);
    let odd = log
        .logged_messages()
        .iter()
        .filter(|m| m.raw_level == b'x')
        .count();
    assert_eq!(odd, 250);
    assert!(log.logged_messages()[0].level().is_none());
    let (rows, py) = pyulog_rows("bad_level", &bytes);
    assert_eq!(rows, 1_000);
    assert_eq!(py["logged"].as_array().unwrap().len(), 500);
}

#[test]
#[cfg_attr(
    not(pyulog),
    ignore = "needs pyulog: pip install pyulog==1.3.0, then touch tests/build.rs"
)]
fn a_key_that_is_not_type_name_does_not_swallow_what_follows_a_damaged_stretch() {
    let mut b = start();
    for i in 0..200u64 {
        b.data(0, &row(i));
    }
    let mut bytes = b.bytes().to_vec();
    let bounds = b.boundaries().to_vec();
    // Overwrite 64 bytes from the start of data message 50 (each is 21 bytes): at 5
    // bytes in, an information message whose key is binary with a space in it, sized
    // to end exactly where a real message starts 20 messages on (so that the messages
    // after it frame, as happened in a real log).
    let first_data = bounds.len() - 1 - 200;
    let p = bounds[first_data + 50];
    let target = bounds[first_data + 70];
    let mut garbage = vec![0xff; 64];
    let size = (target - (p + 5) - 3) as u16;
    garbage[5..7].copy_from_slice(&size.to_le_bytes());
    garbage[7] = b'I';
    garbage[8] = 8;
    garbage[9..17].copy_from_slice(b"\x01\x02 \x88\x99\xaa\xbb\xcc");
    bytes[p..p + 64].copy_from_slice(&garbage);

    let log = ULog::parse(&bytes).unwrap();
    // Every message that does not overlap the 64 bytes is kept.
    let damaged = (first_data + 50..bounds.len() - 1)
        .filter(|&k| bounds[k] < p + 64)
        .count();
    assert_eq!(rows_of(&log), 200 - damaged, "{:?}", log.findings());
    assert!(
        log.info().is_empty(),
        "no information message taken from the garbage"
    );
    let f = &log.findings()[0];
    assert_eq!(f.offset, p as u64);
    assert!(f.offset + f.len <= (p + 64) as u64 + 21, "{f:?}");
    {
        let (rows, _) = pyulog_rows("binary_key", &bytes);
        assert!(
            rows <= rows_of(&log),
            "pyulog {rows}, ours {}",
            rows_of(&log)
        );
    }
}

#[test]
fn an_appended_offset_past_the_end_is_reported_where_the_flag_bits_hold_it() {
    let mut b = LogBuilder::new(1, 0);
    b.flag_bits([0; 8], [1, 0, 0, 0, 0, 0, 0, 0], [u64::MAX, 0, 0]);
    b.format(FORMAT);
    b.subscribe(0, 0, "t");
    for i in 0..10 {
        b.data(0, &row(i));
    }
    let bytes = b.into_bytes();
    let log = ULog::parse(&bytes).unwrap();
    assert_eq!(rows_of(&log), 10);
    let f = log
        .findings()
        .iter()
        .find(|f| f.kind == FindingKind::InvalidAppendedOffset(u64::MAX))
        .expect("the offset is reported");
    // The header (16), the flag bits' message header (3), the compat and incompat
    // bytes (16): the first appended offset.
    assert_eq!(f.offset, 16 + 3 + 16);
    assert!(!f.to_string().contains("18446744073709551615 ("), "{f}");
}

#[test]
fn a_file_that_changes_between_the_passes_of_a_shared_load_is_an_error_not_a_panic() {
    let mut b = start();
    for i in 0..20_000u64 {
        b.data(0, &row(i));
    }
    let original = b.into_bytes();
    let dir = std::env::temp_dir().join(format!("ulog-changing-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("changing.ulg");
    std::fs::write(&path, &original).unwrap();
    let stop = std::sync::atomic::AtomicBool::new(false);
    let (mut ok, mut changed) = (0, 0);
    std::thread::scope(|s| {
        s.spawn(|| {
            let mut n = 0u64;
            while !stop.load(std::sync::atomic::Ordering::Relaxed) {
                n += 1;
                let cut = (n * 7919) % original.len() as u64;
                let _ = std::fs::OpenOptions::new()
                    .write(true)
                    .open(&path)
                    .and_then(|f| f.set_len(cut));
                let _ = std::fs::write(&path, &original);
            }
        });
        for _ in 0..200 {
            let options = ScanOptions::default().threads(2);
            match ulog_core::load_columns(Source::file(&path), &options) {
                Ok(_) => ok += 1,
                Err(e) => {
                    assert!(
                        matches!(
                            e.kind(),
                            ReadErrorKind::Changed
                                | ReadErrorKind::Empty
                                | ReadErrorKind::TruncatedHeader { .. }
                        ),
                        "{e}"
                    );
                    changed += 1;
                }
            }
        }
        stop.store(true, std::sync::atomic::Ordering::Relaxed);
    });
    std::fs::remove_dir_all(&dir).ok();
    assert_eq!(ok + changed, 200);
    eprintln!(
        "200 shared loads of a changing file: {ok} read, {changed} refused as changed or empty"
    );
}

/// Item 2: every data message of one topic 4 bytes longer than its format (a logger
/// that writes a newer struct than its format says), between the messages of another
/// topic. pyulog 1.3 keeps the other topic's rows and drops the long ones; we used to
/// drop everything after the first long message as one damaged stretch. Now each
/// long message is reported and kept (its format's bytes: the fields are where the
/// format says), and the other topic loses nothing.
#[test]
#[cfg_attr(
    not(pyulog),
    ignore = "needs pyulog: pip install pyulog==1.3.0, then touch tests/build.rs"
)]
fn every_message_of_a_topic_longer_than_its_format_keeps_its_rows() {
    let mut b = LogBuilder::new(1, 0);
    b.flag_bits([0; 8], [0; 8], [0; 3]);
    b.format(FORMAT);
    b.format("u:uint64_t timestamp;float x;");
    b.subscribe(0, 0, "t");
    b.subscribe(0, 1, "u");
    for i in 0..1_000u64 {
        let mut long = row(i);
        long.extend_from_slice(&[0xAB; 4]);
        b.data(0, &long);
        let mut u = (1_050 + i * 100).to_le_bytes().to_vec();
        u.extend_from_slice(&(i as f32).to_le_bytes());
        b.data(1, &u);
    }
    let bytes = b.into_bytes();
    let log = ULog::parse(&bytes).unwrap();
    let (pyulog_t, py) = pyulog_rows("longer_messages", &bytes);
    let pyulog_u = py["topics"]["u/0"]["timestamp"].as_array().unwrap().len();
    assert_eq!((pyulog_t, pyulog_u), (0, 1_000), "pyulog's rows");
    assert_eq!(rows_of(&log), 1_000, "{:?}", &log.findings()[..3]);
    assert_eq!(log.topic("u", 0).unwrap().len(), 1_000);
    // The values are the format's bytes of each payload.
    let t = log.topic("t", 0).unwrap();
    let b_field = t.field("b").unwrap();
    assert_eq!(
        b_field.read(t.payload(999).unwrap()),
        Some(ulog_core::Value::U32(999 * 3))
    );
    // Typed reading decodes them too.
    #[derive(ulog_core::ULogMessage)]
    #[ulog(name = "t")]
    struct T {
        timestamp: u64,
        a: u32,
        b: u32,
    }
    let typed: Vec<T> = log
        .read::<T>(0)
        .unwrap()
        .iter()
        .map(Result::unwrap)
        .collect();
    assert_eq!(typed.len(), 1_000);
    assert_eq!((typed[7].timestamp, typed[7].a, typed[7].b), (1_700, 7, 21));
    // All reported, as one size mismatch of msg_id 0 that happened 1,000 times, from
    // the first long message to the end of the last.
    let mismatches: Vec<_> = log
        .findings()
        .iter()
        .filter(|f| matches!(f.kind, FindingKind::SizeMismatch { msg_id: 0, .. }))
        .collect();
    assert_eq!(mismatches.len(), 1, "{:?}", log.findings());
    assert_eq!(mismatches[0].count, 1_000);
    let first = t.message_offsets().get(0).unwrap();
    assert_eq!(mismatches[0].offset, first);
    assert!(
        mismatches[0].to_string().contains("1000 times"),
        "{}",
        mismatches[0]
    );
    assert!(
        !log.findings()
            .iter()
            .any(|f| matches!(f.kind, FindingKind::Corrupt(_))),
        "{:?}",
        log.findings()
    );
}

/// Item 2: a format that no subscription uses refers to itself through another (a
/// cycle): it cannot be laid out, but nothing reads it, so every row of the other
/// topics is kept, as pyulog keeps them.
#[test]
#[cfg_attr(
    not(pyulog),
    ignore = "needs pyulog: pip install pyulog==1.3.0, then touch tests/build.rs"
)]
fn an_unused_cyclic_format_loses_no_row() {
    let mut b = LogBuilder::new(1, 0);
    b.flag_bits([0; 8], [0; 8], [0; 3]);
    b.format("cyc_a:uint64_t timestamp;cyc_b inner;");
    b.format("cyc_b:uint64_t timestamp;cyc_a inner;");
    b.format(FORMAT);
    b.subscribe(0, 0, "t");
    for i in 0..100u64 {
        b.data(0, &row(i));
        // And again in the data section, between the rows.
        if i % 10 == 0 {
            b.format("cyc_c:uint64_t timestamp;cyc_c inner;");
        }
    }
    let bytes = b.into_bytes();
    let log = ULog::parse(&bytes).unwrap();
    let (rows, _) = pyulog_rows("unused_cycle", &bytes);
    assert_eq!(rows, 100, "pyulog's rows");
    assert_eq!(rows_of(&log), 100, "{:?}", log.findings());
}

/// Item 8: a long run of sync markers (the magic bytes without message headers, as a
/// faulty writer repeats them) is one damaged stretch, not one finding per marker;
/// the rows after it are kept.
#[test]
fn a_run_of_repeated_sync_markers_is_one_finding() {
    const MAGIC: [u8; 8] = [0x2F, 0x73, 0x13, 0x20, 0x25, 0x0C, 0xBB, 0x12];
    let mut b = start();
    for i in 0..10u64 {
        b.data(0, &row(i));
    }
    let run = 100_000;
    b.garbage(&MAGIC.repeat(run));
    for i in 10..20u64 {
        b.data(0, &row(i));
    }
    let bytes = b.into_bytes();
    let log = ULog::parse(&bytes).unwrap();
    assert_eq!(rows_of(&log), 20, "{:?}", log.findings());
    assert!(log.findings().len() <= 2, "{:?}", &log.findings()[..3]);
    let damaged: u64 = log
        .findings()
        .iter()
        .filter(|f| f.is_damage())
        .map(|f| f.len)
        .sum();
    assert!(damaged >= (run as u64 - 1) * 8, "{damaged}");
}

/// A log as an SD card keeps it after a power loss (item 5: a real PX4 v1.14 log):
/// good messages interleaved with runs of zero bytes (blocks the card never wrote,
/// which read as message headers of size 0 and type 0), then megabytes of zeros (the
/// rest of the file, allocated but never written).
struct PowerLoss {
    bytes: Vec<u8>,
    /// The runs of zeros put between messages: (offset, length).
    zero_runs: Vec<(usize, usize)>,
    /// Where the zeros at the end start.
    tail: usize,
}

/// The zeros at the end of a power-loss log: 2 MiB, as in the real log.
const POWER_LOSS_TAIL: usize = 2 << 20;

/// A power-loss log made of the real log `real`: its messages unchanged up to
/// `damaged` messages before three quarters of it; those are dealt into islands of one
/// to four messages, each followed by a run of 200 bytes to 4 KiB of zeros, or (one
/// gap in four) with the bytes from the last 512-byte block boundary on zeroed
/// instead (a block the card never wrote, cutting the messages on it); then
/// `POWER_LOSS_TAIL` zeros.
fn power_loss(real: &[u8], damaged: usize, rng: &mut Rng) -> PowerLoss {
    let offsets: Vec<usize> = Messages::new(real)
        .map(|m| m.unwrap().offset as usize)
        .collect();
    let end = |o: usize| o + 3 + u16::from_le_bytes([real[o], real[o + 1]]) as usize;
    let last = offsets.len() * 3 / 4;
    let first = last - damaged;
    let mut out = real[..offsets[first]].to_vec();
    let mut zero_runs = Vec::new();
    let mut k = first;
    loop {
        let island = &offsets[k..(k + 1 + rng.below(4)).min(last)];
        for &o in island {
            out.extend_from_slice(&real[o..end(o)]);
        }
        k += island.len();
        if k == last {
            break;
        }
        let block = (out.len() - 1) / 512 * 512;
        if rng.below(4) == 0 && block > offsets[first] {
            out[block..].fill(0);
        } else {
            let len = 200 + rng.below(4096 - 200 + 1);
            zero_runs.push((out.len(), len));
            out.resize(out.len() + len, 0);
        }
    }
    let tail = out.len();
    out.resize(tail + POWER_LOSS_TAIL, 0);
    PowerLoss {
        bytes: out,
        zero_runs,
        tail,
    }
}

/// Every row pyulog keeps (`py`, from [`pyulog_dump`]) is one of ours, in the same
/// order within its topic instance, value for value (every column our field lookup
/// resolves: all but pyulog's one column per character of a `char[N]`). Returns the
/// row counts, ours and pyulog's. The one exception: a data message that zero fill
/// cuts (its payload ends in a run of zeros the resync skips) is damage that we
/// report (`Corruption::CutByZeroFill`), and pyulog hands out as a row; such a row of
/// pyulog's is passed over when a damage finding starts with a message of the topic
/// carrying its timestamp (the first field of PX4's formats): the cut message is
/// where the stretch it is reported in starts.
fn assert_rows_superset(
    log: &ULog<'_>,
    bytes: &[u8],
    py: &serde_json::Value,
    what: &str,
) -> (usize, usize) {
    let cut: Vec<(u16, u64)> = log
        .findings()
        .iter()
        .filter(|f| f.is_damage())
        .filter_map(|f| {
            let at = f.offset as usize;
            let h = bytes.get(at..at + 13)?;
            (h[2] == b'D').then(|| {
                (
                    u16::from_le_bytes([h[3], h[4]]),
                    u64::from_le_bytes(h[5..13].try_into().unwrap()),
                )
            })
        })
        .collect();
    let cell = |e: &serde_json::Value, v: &ulog_core::Value<'_>| {
        let text = e.as_str().map_or_else(|| e.to_string(), str::to_owned);
        cell_matches(&text, v)
    };
    let mut theirs = 0;
    for (key, cols) in py["topics"].as_object().unwrap() {
        let (name, multi_id) = key.rsplit_once('/').unwrap();
        let t = log
            .topic(name, multi_id.parse().unwrap())
            .unwrap_or_else(|e| panic!("{what}: {key}: pyulog has rows, we have none ({e})"));
        let cols: Vec<_> = cols
            .as_object()
            .unwrap()
            .iter()
            .filter_map(|(c, v)| Some((t.field(c).ok()?, v.as_array().unwrap())))
            .collect();
        let rows = cols[0].1.len();
        let mut ours = 0;
        let msg_id = t.subscription().msg_id();
        for row in 0..rows {
            let stamp = py["topics"][key]["timestamp"][row].as_u64();
            if stamp.is_some_and(|s| cut.contains(&(msg_id, s))) {
                continue;
            }
            loop {
                let p = t.payload(ours).unwrap_or_else(|| {
                    panic!(
                        "{what}: {key}: pyulog's row {row} of {rows} (timestamp {}) is not ours",
                        py["topics"][key]["timestamp"][row]
                    )
                });
                ours += 1;
                if cols.iter().all(|(f, v)| cell(&v[row], &f.read(p).unwrap())) {
                    break;
                }
            }
        }
        theirs += rows;
    }
    (log.topics().map(|t| t.len()).sum(), theirs)
}

/// Every run of zeros is reported as damage where it starts (the runs between messages
/// and the zeros at the end), never skipped silently.
fn assert_zeros_reported(log: &ULog<'_>, pl: &PowerLoss, what: &str) {
    let damage: Vec<_> = log.findings().iter().filter(|f| f.is_damage()).collect();
    for &(o, len) in &pl.zero_runs {
        assert!(
            damage
                .iter()
                .any(|f| f.offset <= o as u64 && (o as u64) < f.offset + f.len),
            "{what}: the zeros at {o} ({len} bytes) are not reported: {damage:?}"
        );
    }
    let last = damage.last().unwrap();
    assert_eq!(
        last.kind,
        FindingKind::Corrupt(Corruption::ZeroFill),
        "{what}"
    );
    assert_eq!(last.offset + last.len, pl.bytes.len() as u64, "{what}");
    assert!(last.offset <= pl.tail as u64, "{what}: {last:?}");
}

/// Item 5: a power-loss log (see [`power_loss`]) lost messages pyulog reads: a message
/// alone between two runs of zeros, or two, did not start the chain of three messages
/// that resynchronising asked for. Now the rows we keep are a superset of pyulog's
/// (which misses others, after the runs where it finds no header) and every run of
/// zeros is still reported.
#[test]
#[cfg_attr(
    not(pyulog),
    ignore = "needs pyulog: pip install pyulog==1.3.0, then touch tests/build.rs"
)]
fn a_power_loss_log_keeps_every_row_pyulog_keeps() {
    let real = std::fs::read(ulog_tests::own_log("esc_status_log.ulg")).unwrap();
    for seed in 1..=3 {
        let pl = power_loss(&real, 300, &mut Rng::new(0x5eed_0500 + seed));
        let what = format!("seed {seed}");
        let log = ULog::parse(&pl.bytes).unwrap();
        let py = pyulog_dump(&format!("power_loss_{seed}"), &pl.bytes);
        let (ours, theirs) = assert_rows_superset(&log, &pl.bytes, &py, &what);
        eprintln!("{what}: {ours} rows, pyulog {theirs}");
        assert_zeros_reported(&log, &pl, &what);
    }
}

/// The same on the PX4 v1.14 log of the corpus (the firmware of the real power-loss
/// log).
#[test]
#[cfg_attr(
    not(all(pyulog, full_corpus)),
    ignore = "needs pyulog (pip install pyulog==1.3.0, then touch tests/build.rs) and the \
              full corpus (../shared/corpus beside the workspace, or $ULOG_CORPUS)"
)]
fn a_power_loss_log_of_px4_1_14_keeps_every_row_pyulog_keeps() {
    let path = ulog_tests::corpus_dir().join("files/log_123_2024-3-1-14-47-02.ulg");
    let real = std::fs::read(path).unwrap();
    let pl = power_loss(&real, 400, &mut Rng::new(0x5eed_0514));
    let log = ULog::parse(&pl.bytes).unwrap();
    let py = pyulog_dump("power_loss_v1_14", &pl.bytes);
    let (ours, theirs) = assert_rows_superset(&log, &pl.bytes, &py, "v1.14");
    eprintln!("v1.14: {ours} rows, pyulog {theirs}");
    assert_zeros_reported(&log, &pl, "v1.14");
}

/// A header of a type no spec has, whose size happens to end on a message boundary
/// with messages after it (likely in a log of small messages: here it came of a
/// repeated stretch in a real log), was skipped as one message of an unknown type, and
/// with it the real messages its size spans (pyulog keeps them). The `messages` fuzz
/// target found the same of a known type whose size field was hit (an information
/// message 6 bytes short, whose last bytes then read as a malformed subscription).
/// A bad message that spans a chain of messages is now taken for damage, and
/// resynchronising keeps them.
#[test]
fn a_bad_header_does_not_swallow_the_messages_its_size_spans() {
    // 20 data messages of 3 + 2 + 16 bytes.
    let span = 20u16 * 21;
    let headers: [(&str, Vec<u8>); 5] = [
        ("a type no spec has", vec![b'7']),
        ("a subscription of no format", vec![b'A']),
        ("an information message whose key is no key", vec![b'I']),
        ("data of msg_id 18, not subscribed", vec![b'D']),
        ("data of msg_id 0, longer than its format", vec![b'D', 0, 0]),
    ];
    for (what, rest) in headers {
        let mut b = start();
        for i in 0..10u64 {
            b.data(0, &row(i));
        }
        let at = b.bytes().len() as u64;
        let mut header = (span + rest.len() as u16 - 1).to_le_bytes().to_vec();
        header.extend_from_slice(&rest);
        b.garbage(&header);
        for i in 10..40u64 {
            b.data(0, &row(i));
        }
        let bytes = b.into_bytes();
        let log = ULog::parse(&bytes).unwrap();
        assert_eq!(rows_of(&log), 40, "{what}: {:?}", log.findings());
        let damage: Vec<_> = log.findings().iter().filter(|f| f.is_damage()).collect();
        assert_eq!(damage.len(), 1, "{what}: {damage:?}");
        let found = (damage[0].offset, damage[0].len);
        assert_eq!(found, (at, header.len() as u64), "{what}: {damage:?}");
    }
}

/// A data message between damage and the end of the file was lost: resynchronising
/// asked for two messages before the end. Found by the `messages` fuzz target on
/// trig_stats.ulg (its last message, after a damaged one); a data message is now
/// enough there, as before zero fill. One alone between two damaged stretches is still
/// skipped with them: inside damage it is as likely damaged itself (the corpus log
/// `corrupt_unregistered_msg_id` has one with an intact header and a timestamp of
/// 4·10¹⁸ µs, which pyulog skips too).
#[test]
fn a_data_message_before_the_end_is_kept_but_not_one_alone_inside_damage() {
    let mut b = start();
    for i in 0..10u64 {
        b.data(0, &row(i));
    }
    let first = b.bytes().len() as u64;
    b.garbage(&[0xff; 7]);
    b.data(0, &row(10));
    let second = b.bytes().len() as u64;
    b.garbage(&[0xff; 7]);
    b.data(0, &row(11));
    let bytes = b.into_bytes();
    let log = ULog::parse(&bytes).unwrap();
    let kept: Vec<u64> = log.topic("t", 0).unwrap().timestamps();
    let expected: Vec<u64> = (0..10).chain([11]).map(|i| 1_000 + i * 100).collect();
    assert_eq!(kept, expected, "{:?}", log.findings());
    let damage: Vec<(u64, u64)> = log
        .findings()
        .iter()
        .filter(|f| f.is_damage())
        .map(|f| (f.offset, f.len))
        .collect();
    assert_eq!(damage, [(first, second + 7 - first)]);
}

/// The damage of the adversarial run, on the repository's real logs: a stretch
/// overwritten with random bytes, a 512-byte block zeroed (a card block never
/// written), a message's size field rewritten, a stretch cut out, random bytes put in,
/// a stretch repeated.
fn corrupt(real: &[u8], kind: usize, rng: &mut Rng) -> Vec<u8> {
    let offsets: Vec<usize> = Messages::new(real)
        .map(|m| m.unwrap().offset as usize)
        .collect();
    // The data section: after the first subscription.
    let first = offsets.iter().position(|&o| real[o + 2] == b'A').unwrap();
    let at = offsets[first + 1 + rng.below(offsets.len() - first - 2)];
    let at = at + rng.below(40);
    let mut out = real.to_vec();
    let mut random = |n: usize| -> Vec<u8> { (0..n).map(|_| rng.next_u64() as u8).collect() };
    match kind {
        0 => {
            let bytes = random(64);
            out[at..at + 64].copy_from_slice(&bytes);
        }
        1 => {
            let block = at / 512 * 512;
            out[block..block + 512].fill(0);
        }
        2 => {
            let o = offsets[first + 1 + (at % (offsets.len() - first - 2))];
            let size = random(2);
            out[o..o + 2].copy_from_slice(&size);
        }
        3 => {
            let n = 1 + (at * 7919) % 300;
            out.drain(at..at + n);
        }
        4 => {
            let n = 1 + (at * 7919) % 300;
            let bytes = random(n);
            out.splice(at..at, bytes);
        }
        _ => {
            let n = 1 + (at * 7919) % 300;
            let stretch = out[at..at + n].to_vec();
            out.splice(at..at, stretch);
        }
    }
    out
}

/// On every damaged real log of [`corrupt`] (three logs, six kinds of damage, four
/// seeds each) the rows we keep are a superset of pyulog's, value for value.
#[test]
#[cfg_attr(
    not(pyulog),
    ignore = "needs pyulog: pip install pyulog==1.3.0, then touch tests/build.rs"
)]
fn corruptions_of_real_logs_keep_every_row_pyulog_keeps() {
    let (mut compared, mut refused) = (0, Vec::new());
    let (mut ours_total, mut theirs_total) = (0, 0);
    for name in [
        "esc_status_log.ulg",
        "sample_appended_multiple.ulg",
        "trig_stats.ulg",
    ] {
        let real = std::fs::read(ulog_tests::own_log(name)).unwrap();
        for kind in 0..6 {
            for seed in 0..4u64 {
                let mut rng = Rng::new(0xdead_0000 + seed * 16 + kind as u64);
                let bytes = corrupt(&real, kind, &mut rng);
                let what = format!("{name}, damage {kind}, seed {seed}");
                let log = ULog::parse(&bytes).unwrap();
                match ulog_tests::pyulog_try_dump(&format!("corrupt_{kind}_{seed}"), &bytes) {
                    Ok(py) => {
                        let (ours, theirs) = assert_rows_superset(&log, &bytes, &py, &what);
                        ours_total += ours;
                        theirs_total += theirs;
                        compared += 1;
                    }
                    Err(e) => refused.push(format!("{what}: {}", e.lines().last().unwrap_or(""))),
                }
            }
        }
    }
    eprintln!(
        "{compared} damaged logs compared: {ours_total} rows, pyulog {theirs_total}; \
         pyulog refused {}: {refused:#?}",
        refused.len()
    );
    // pyulog raising on a damaged log is no comparison: most must be compared.
    assert!(compared >= 60, "only {compared} compared: {refused:#?}");
}

/// A reader that hands out one byte per read, so that framing sees every window size.
struct OneByte<'a>(&'a [u8]);

impl std::io::Read for OneByte<'_> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let n = buf.len().min(self.0.len()).min(1);
        buf[..n].copy_from_slice(&self.0[..n]);
        self.0 = &self.0[n..];
        Ok(n)
    }
}

/// A message too short for its type that ends exactly at the appended offset, read in
/// pieces: framing judges such a header before it has the message's bytes and knew its
/// end was a message boundary (the offset), and looking inside it for messages it
/// spans read past the bytes it had (a panic, found reviewing the change that added
/// that look). It now waits for the bytes, and reads what the whole-file parse reads.
#[test]
fn a_short_message_ending_at_the_appended_offset_reads_the_same_in_pieces() {
    let build = |appended: u64| {
        let mut b = LogBuilder::new(1, 0);
        b.flag_bits([0; 8], [1, 0, 0, 0, 0, 0, 0, 0], [appended, 0, 0]);
        b.format(FORMAT);
        b.subscribe(0, 0, "t");
        for i in 0..5u64 {
            b.data(0, &row(i));
        }
        // A logged string of 5 bytes: its level and timestamp alone take 9.
        b.garbage(&[5, 0, b'L', b'6', 1, 2, 3, 4]);
        let at = b.bytes().len() as u64;
        for i in 6..10u64 {
            b.data(0, &row(i));
        }
        (b.into_bytes(), at)
    };
    let (_, at) = build(0);
    let (bytes, again) = build(at);
    assert_eq!(at, again);
    let log = ULog::parse(&bytes).unwrap();
    let mut rows = 0;
    let summary = ulog_core::scan(
        ulog_core::Source::reader(OneByte(&bytes)),
        &ulog_core::ScanOptions::default(),
        |_| rows += 1,
    )
    .unwrap();
    assert_eq!(rows, rows_of(&log), "{:?}", log.findings());
    assert_eq!(summary.messages, log.message_count());
}
