//! A log written by our writer, read by pyulog (the reference reader): every value
//! equal. Runs where `python3` could import `pyulog` when the tests were built (`.ci/run`
//! installs it); reported `ignored` otherwise.

use std::io::Cursor;

use serde_json::Value as J;
use ulog_core::read::LogLevel;
use ulog_core::typed::CharArray;
use ulog_core::write::Anonymise;
use ulog_core::write::{DefaultTypes, WriterOptions};
use ulog_core::{LogWriter, ULog, ULogMessage, Value};
use ulog_tests::{corpus_files, pyulog_dump, pyulog_dump_topics, stem};

#[derive(ULogMessage, Debug, Clone)]
struct EscReport {
    timestamp: u64,
    esc_rpm: i32,
    esc_voltage: f32,
    esc_state: u8,
    _padding0: [u8; 7],
}

#[derive(ULogMessage, Debug, Clone)]
struct EscStatus {
    timestamp: u64,
    counter: u16,
    esc_count: u8,
    armed: bool,
    _padding0: [u8; 4],
    esc: [EscReport; 2],
}

#[derive(ULogMessage, Debug, Clone)]
struct AllTypes {
    timestamp: u64,
    a: i8,
    b: u8,
    c: i16,
    d: u16,
    e: i32,
    f: u32,
    g: i64,
    h: u64,
    i: f32,
    j: f64,
    k: bool,
    name: CharArray<8>,
    v: [f32; 3],
    _padding0: [u8; 2],
}

/// Writes a log exercising every kind of message and field.
pub fn write_sample() -> Vec<u8> {
    let mut w = LogWriter::new(Vec::new(), 1_000).unwrap();
    w.info("sys_name", "PX4").unwrap();
    w.info("ver_sw_release", &0x010e_03ffu32).unwrap();
    w.info("time_ref_utc", &-3600i32).unwrap();
    w.multi_info("console", "first, ", false).unwrap();
    w.multi_info("console", "second", true).unwrap();
    w.param("MAV_TYPE", 2i32).unwrap();
    w.param("MPC_XY_VEL_MAX", 12.5f32).unwrap();
    w.default_param("MPC_XY_VEL_MAX", 10.0f32, DefaultTypes::BOTH)
        .unwrap();
    let esc = w.subscribe::<EscStatus>(0).unwrap();
    let all0 = w.subscribe::<AllTypes>(0).unwrap();
    let all1 = w.subscribe::<AllTypes>(1).unwrap();
    let mut data = w.start_data().unwrap();
    data.log(LogLevel::Info, 1_000, "[logger] started").unwrap();
    for n in 0..50u64 {
        let t = 1_000 + n * 10_000;
        let report = |k: u64| EscReport {
            timestamp: t + k,
            esc_rpm: 4000 + n as i32 * 3 - k as i32,
            esc_voltage: 16.0 - n as f32 * 0.01,
            esc_state: k as u8,
            _padding0: [0; 7],
        };
        data.write(
            &esc,
            &EscStatus {
                timestamp: t,
                counter: n as u16,
                esc_count: 2,
                armed: n > 3,
                _padding0: [0; 4],
                esc: [report(0), report(1)],
            },
        )
        .unwrap();
        let row = AllTypes {
            timestamp: t,
            a: -(n as i8),
            b: 200 + n as u8,
            c: -300 * n as i16,
            d: 60_000 + n as u16,
            e: -70_000 * n as i32,
            f: 4_000_000_000 + n as u32,
            g: -(1 << 40) * n as i64,
            h: u64::MAX - n,
            i: 0.1 * n as f32,
            j: 1e-7 * n as f64,
            k: n % 2 == 0,
            name: CharArray::from_str_truncated(&format!("row{n}")),
            v: [n as f32, 1.0 / (n as f32 + 1.0), -2.5],
            _padding0: [0; 2],
        };
        data.write(if n % 3 == 0 { &all1 } else { &all0 }, &row)
            .unwrap();
        if n == 25 {
            data.param("MPC_XY_VEL_MAX", 8.0f32).unwrap();
            data.tagged_log(LogLevel::Warning, 7, t, "tagged warning")
                .unwrap();
            data.dropout(15).unwrap();
        }
    }
    data.finish().unwrap()
}

fn json_eq(e: &J, ours: &Value) -> bool {
    match ours {
        Value::Str(s) => e.as_str() == Some(&*s.to_string_lossy()),
        // Not numbers: as the dump writes them (`nan`, `inf`, `-inf`).
        Value::F32(v) => {
            e.as_f64().is_some_and(|x| x == f64::from(*v))
                || (v.is_nan() && e == "nan")
                || (v.is_infinite() && e.as_str() == Some(&v.to_string()))
        }
        Value::F64(v) => {
            e.as_f64().is_some_and(|x| x == *v)
                || (v.is_nan() && e == "nan")
                || (v.is_infinite() && e.as_str() == Some(&v.to_string()))
        }
        // pyulog reads a `bool` as the byte logged (real logs hold other bytes than
        // 0 and 1); it is true where that byte is not 0.
        Value::Bool(b) => e.as_i64().map(|x| x != 0) == Some(*b) || e.as_bool() == Some(*b),
        v => match (v.as_i128(), e.as_i64(), e.as_u64()) {
            (Some(o), Some(x), _) => o == i128::from(x),
            (Some(o), None, Some(x)) => o == i128::from(x),
            _ => false,
        },
    }
}

/// Every value pyulog read equals ours: information, parameters, logged strings,
/// dropouts and every column of every topic.
fn assert_pyulog_reads_what_we_read(py: &J, bytes: &[u8]) {
    assert_pyulog_reads(py, bytes, None)
}

/// [`assert_pyulog_reads_what_we_read`], of the topics `only` when pyulog read those
/// alone.
fn assert_pyulog_reads(py: &J, bytes: &[u8], only: Option<&[&str]>) {
    let log = ULog::parse(bytes).unwrap();
    assert!(log.findings().is_empty(), "{:?}", log.findings());
    assert_eq!(py["corrupt"], J::Bool(false));
    for kv in log.info() {
        assert!(
            json_eq(&py["info"][&*kv.name()], &kv.value()),
            "info {}",
            kv.name()
        );
    }
    for kv in log.initial_params() {
        assert!(
            json_eq(&py["params"][&*kv.name()], &kv.value()),
            "param {}",
            kv.name()
        );
    }
    let changed = py["changed"].as_array().unwrap();
    assert_eq!(changed.len(), log.param_changes().len());
    // The time of a parameter change or a dropout is that of the data before it:
    // pyulog reading some topics alone has another.
    let all_data = only.is_none();
    for (e, c) in changed.iter().zip(log.param_changes()) {
        assert!(!all_data || e[0] == c.timestamp);
        assert_eq!(e[1], J::from(c.kv.name().into_owned()));
        assert!(json_eq(&e[2], &c.kv.value()));
    }
    let plain: Vec<_> = log
        .logged_messages()
        .iter()
        .filter(|l| l.tag.is_none())
        .collect();
    let logged = py["logged"].as_array().unwrap();
    assert_eq!(logged.len(), plain.len());
    for (e, l) in logged.iter().zip(plain) {
        assert_eq!(
            (e[0].as_u64(), e[1].as_u64()),
            (Some(u64::from(l.raw_level)), Some(l.timestamp))
        );
        assert_eq!(e[2].as_str(), l.text.as_str());
    }
    let drops: Vec<J> = log
        .dropouts()
        .iter()
        .map(|d| J::from(vec![d.timestamp, u64::from(d.duration_ms)]))
        .collect();
    if all_data {
        assert_eq!(py["dropouts"], J::from(drops));
    } else {
        let durations = |d: &J| {
            d.as_array()
                .unwrap()
                .iter()
                .map(|d| d[1].clone())
                .collect::<Vec<_>>()
        };
        assert_eq!(durations(&py["dropouts"]), durations(&J::from(drops)));
    }

    let topics = py["topics"].as_object().unwrap();
    let chosen = |t: &ulog_core::Topic<'_, '_>| only.is_none_or(|o| o.contains(&t.name()));
    let ours: Vec<_> = log
        .topics()
        .filter(|t| !t.is_empty() && chosen(t))
        .collect();
    assert_eq!(topics.len(), ours.len());
    for t in ours {
        let cols = &topics[&format!("{}/{}", t.name(), t.multi_id())];
        let mut compared = 0;
        for c in t.fields().unwrap() {
            match c.shape() {
                ulog_core::read::FieldShape::String(n) => {
                    // pyulog keeps a char[N] as N int8 columns.
                    for (row, p) in t.payloads().enumerate() {
                        let s = c.read(p).unwrap();
                        let bytes = s.as_str().unwrap().as_bytes();
                        for (i, &b) in bytes.iter().enumerate().take(n) {
                            let e = &cols[&format!("{}[{i}]", c.path())][row];
                            assert_eq!(e.as_i64(), Some(i64::from(b as i8)));
                        }
                    }
                }
                _ => {
                    let e = cols[c.path()]
                        .as_array()
                        .unwrap_or_else(|| panic!("pyulog lacks {}", c.path()));
                    assert_eq!(e.len(), t.len());
                    for (ev, p) in e.iter().zip(t.payloads()) {
                        let v = c.read(p).unwrap();
                        assert!(
                            json_eq(ev, &v),
                            "{}.{}: pyulog {ev}, ours {v:?}",
                            t.name(),
                            c.path()
                        );
                        compared += 1;
                    }
                }
            }
        }
        assert!(compared > 0);
    }
}

#[test]
#[cfg_attr(
    not(pyulog),
    ignore = "needs pyulog: pip install pyulog==1.3.0, then touch tests/build.rs"
)]
fn pyulog_reads_every_value_we_write() {
    let bytes = write_sample();
    let py = pyulog_dump("every_value", &bytes);
    assert_pyulog_reads_what_we_read(&py, &bytes);
    assert_eq!(
        py["info_multi"]["console"],
        serde_json::json!([["first, ", "second"]])
    );
    assert_eq!(py["tagged"]["7"][0][2], "tagged warning");
    assert_eq!(py["topics"].as_object().unwrap().len(), 3);
}

#[test]
#[cfg_attr(
    not(pyulog),
    ignore = "needs pyulog: pip install pyulog==1.3.0, then touch tests/build.rs"
)]
fn pyulog_reads_the_simulated_flight_example() {
    let bytes = ulog_examples::simulation::simulate_flight(Vec::new()).unwrap();
    let py = pyulog_dump("simulated_flight", &bytes);
    assert_pyulog_reads_what_we_read(&py, &bytes);
    assert_eq!(
        py["topics"]["vehicle_attitude/0"]["q[0]"]
            .as_array()
            .unwrap()
            .len(),
        3001
    );
}

/// Every corpus log the tests have, anonymised (positions moved, dates zeroed, keys
/// left out): pyulog reads each as not corrupt, with our values.
#[test]
#[cfg_attr(
    not(pyulog),
    ignore = "needs pyulog: pip install pyulog==1.3.0, then touch tests/build.rs"
)]
fn pyulog_reads_every_anonymised_corpus_log() {
    let (mut read, mut topics) = (0, 0);
    for path in corpus_files() {
        let name = stem(&path);
        let bytes = std::fs::read(&path).unwrap();
        let log = ULog::parse(&bytes).unwrap();
        let mut out = Vec::new();
        Anonymise::new()
            .to(-33.9, 151.2)
            .zero_utc(true)
            .zero_start(true)
            .edit(&log)
            .write(&log, &mut out)
            .unwrap();
        // The data pyulog reads: the topics whose rows changed (the rest are the
        // original's bytes, which the corpus tests compare with pyulog).
        let anon = ULog::parse(&out).unwrap();
        let mut changed: Vec<&str> = anon
            .topics()
            .filter(|t| {
                log.topics()
                    .find(|o| o.name() == t.name() && o.multi_id() == t.multi_id())
                    .is_none_or(|o| !o.payloads().eq(t.payloads()))
            })
            .map(|t| t.name())
            .collect();
        changed.sort_unstable();
        changed.dedup();
        let py = pyulog_dump_topics(&format!("anonymised-{name}"), &out, &changed);
        assert_pyulog_reads(&py, &out, Some(&changed));
        read += 1;
        topics += changed.len();
    }
    assert!(read >= 5 && topics > 0, "{read} logs, {topics} topics");
}

/// An `esc_status` row for time `t` (appended after the sample's 50).
fn crash_row(n: u64) -> EscStatus {
    let t = 600_000 + n * 1_000;
    let report = |k: u64| EscReport {
        timestamp: t + k,
        esc_rpm: -(n as i32) * 7 - k as i32,
        esc_voltage: 9.5 - n as f32 * 0.125,
        esc_state: 3 + k as u8,
        _padding0: [0; 7],
    };
    EscStatus {
        timestamp: t,
        counter: 1000 + n as u16,
        esc_count: 2,
        armed: true,
        _padding0: [0; 4],
        esc: [report(0), report(1)],
    }
}

/// Data appended with `Appender::subscribe` (a new subscription of a topic the log
/// has): pyulog reads the log as not corrupt, the appended rows as a second data set
/// of the same topic instance, with our values; we read them as the continuation of
/// that instance.
#[test]
#[cfg_attr(
    not(pyulog),
    ignore = "needs pyulog: pip install pyulog==1.3.0, then touch tests/build.rs"
)]
fn pyulog_reads_data_appended_under_a_new_subscription() {
    let mut file = Cursor::new(write_sample());
    let mut appender = ulog_core::append(&mut file, WriterOptions::default()).unwrap();
    let esc = appender.subscribe::<EscStatus>(0).unwrap();
    for n in 0..20 {
        appender.writer().write(&esc, &crash_row(n)).unwrap();
    }
    appender.finish().unwrap();
    let bytes = file.into_inner();

    let log = ULog::parse(&bytes).unwrap();
    assert_eq!(log.appended_sections().len(), 1);
    let ours: Vec<EscStatus> = log
        .read::<EscStatus>(0)
        .unwrap()
        .iter()
        .map(Result::unwrap)
        .collect();
    assert_eq!(
        ours.len(),
        70,
        "one instance: the log's 50 rows, then the 20 appended"
    );
    assert_eq!(
        format!("{:?}", &ours[50..]),
        format!("{:?}", (0..20).map(crash_row).collect::<Vec<_>>())
    );

    let py = pyulog_dump("appended", &bytes);
    assert_eq!(py["corrupt"], J::Bool(false));
    let sets: Vec<&J> = py["datasets"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|d| d[0] == "esc_status" && d[1] == 0)
        .collect();
    assert_eq!(sets.len(), 2, "the log's data set and the appended one");
    let rows = |d: &J| d[2]["timestamp"].as_array().unwrap().len();
    assert_eq!((rows(sets[0]), rows(sets[1])), (50, 20));
    let topic = log.topic("esc_status", 0).unwrap();
    let fields = topic.fields().unwrap();
    let mut compared = 0;
    for c in &fields {
        let column = sets[1][2][c.path()].as_array().unwrap();
        for (row, e) in column.iter().enumerate() {
            let v = c.read(topic.payload(50 + row).unwrap()).unwrap();
            assert!(
                json_eq(e, &v),
                "{}: row {row}: pyulog {e}, ours {v:?}",
                c.path()
            );
            compared += 1;
        }
    }
    assert!(compared >= 20 * 10);
}

/// `Appender::continue_topic` writes under the existing subscription's msg_id, as
/// the spec allows and we read; pyulog 1.3 forgets subscriptions at an appended
/// offset, drops those rows and calls the log corrupt, which is why the method's
/// documentation steers to `subscribe`. This holds pyulog to what we document.
#[test]
#[cfg_attr(
    not(pyulog),
    ignore = "needs pyulog: pip install pyulog==1.3.0, then touch tests/build.rs"
)]
fn pyulog_drops_data_continuing_an_old_subscription_as_documented() {
    let mut file = Cursor::new(write_sample());
    let mut appender = ulog_core::append(&mut file, WriterOptions::default()).unwrap();
    let esc = appender.continue_topic::<EscStatus>(0).unwrap();
    for n in 0..20 {
        appender.writer().write(&esc, &crash_row(n)).unwrap();
    }
    appender.finish().unwrap();
    let bytes = file.into_inner();
    let log = ULog::parse(&bytes).unwrap();
    assert_eq!(log.topic("esc_status", 0).unwrap().len(), 70);

    let py = pyulog_dump("continued", &bytes);
    assert_eq!(py["corrupt"], J::Bool(true));
    let rows = py["topics"]["esc_status/0"]["timestamp"]
        .as_array()
        .unwrap()
        .len();
    assert_eq!(
        rows, 50,
        "pyulog keeps only the rows before the appended offset"
    );
}
