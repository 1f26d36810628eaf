//! Run-time errors a user causes name the fix: a field the log lacks (the log's
//! closest name, `Option`/`#[ulog(default)]`), an input to copy that is not ULog (what
//! is wrong, where, the reader's error kept as the source). The compile-time ones are
//! the trybuild tests (`typed_ui`, `writer_ui`).

use std::error::Error as _;

use ulog_core::read::ReadErrorKind;
use ulog_core::testing::LogBuilder;
use ulog_core::typed::{DifferenceKind, TypedErrorKind};
use ulog_core::write::WriteErrorKind;
use ulog_core::{copy_log, ULog, ULogMessage};

/// A misspelt field, and one that no firmware of the log has.
#[derive(ULogMessage, Debug)]
#[ulog(name = "sensor_baro")]
struct Baro {
    timestamp: u64,
    temprature: f32,
    humidity: f32,
}

fn baro_log() -> Vec<u8> {
    let mut b = LogBuilder::new(1, 0);
    b.format("sensor_baro:uint64_t timestamp;float pressure;float temperature;");
    b.subscribe(0, 0, "sensor_baro");
    b.data(0, &[0; 16]);
    b.into_bytes()
}

#[test]
fn a_missing_field_gets_the_closest_name_and_the_optional_hint() {
    let bytes = baro_log();
    let log = ULog::parse(&bytes).unwrap();
    let e = log.read::<Baro>(0).err().expect("the binding does not fit");
    let TypedErrorKind::Mismatch(m) = e.kind() else {
        panic!("{e}")
    };
    let kinds: Vec<(&str, &DifferenceKind)> = m
        .differences
        .iter()
        .map(|d| (d.path.as_str(), &d.kind))
        .collect();
    assert_eq!(
        kinds,
        [
            (
                "temprature",
                &DifferenceKind::MissingField {
                    closest: Some("temperature".into())
                }
            ),
            ("humidity", &DifferenceKind::MissingField { closest: None }),
        ]
    );
    let text = e.to_string();
    assert!(
        text.contains(
            "field `temprature`: missing in the log; did you mean `temperature`? (rename the field, or add #[ulog(alias = \"temperature\")])"
        ),
        "{text}"
    );
    assert!(
        text.contains(
            "field `humidity`: missing in the log; if some firmware lacks it, make it `Option<_>` or give it #[ulog(default)]"
        ),
        "{text}"
    );
}

/// A name another field of the binding reads is not suggested for a missing one.
#[test]
fn a_name_the_binding_reads_is_not_suggested() {
    #[derive(ULogMessage, Debug)]
    #[ulog(name = "sensor_baro")]
    struct Twice {
        temperature: f32,
        temperatur: f32,
    }
    let bytes = baro_log();
    let log = ULog::parse(&bytes).unwrap();
    let e = log
        .read::<Twice>(0)
        .err()
        .expect("the binding does not fit");
    let TypedErrorKind::Mismatch(m) = e.kind() else {
        panic!("{e}")
    };
    assert_eq!(
        m.differences[0].kind,
        DifferenceKind::MissingField { closest: None },
        "{e}"
    );
}

#[test]
fn copying_bytes_that_are_not_ulog_says_what_is_there_and_where() {
    let gzip = b"\x1f\x8b\x08\x00 a gzip file, not a log";
    let e = copy_log(gzip, Vec::new()).unwrap_err();
    assert_eq!(e.kind(), &WriteErrorKind::Unreadable);
    assert_eq!(
        e.to_string(),
        "the input is not a ULog file: no ULog magic (`ULog` 0x01 0x12 0x35) at byte 0, found a gzip file"
    );
    // The reader's error is kept, for a program to match on.
    let read = e
        .source()
        .and_then(|s| s.downcast_ref::<ulog_core::ReadError>())
        .expect("the reader's error as the source");
    assert!(matches!(read.kind(), ReadErrorKind::NotULog { .. }));
    assert_eq!(read.position(), Some(0));

    let e = copy_log(b"", Vec::new()).unwrap_err();
    assert_eq!(e.to_string(), "not a ULog file: the file is empty");
}
