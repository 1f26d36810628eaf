//! Examples of `ulog-core` live in `examples/examples/`; this library holds what they
//! share with their tests.

use std::collections::BTreeSet;

use ulog_core::format::TypeName;
use ulog_core::ULog;

pub mod firmware;
pub mod simulation;

/// The reference log that the `replay_check` example is compiled against
/// (`data/reference.ulg`): the format definitions and subscriptions of the bundled
/// sample log ([`ulog_core::testing::sample_log`]), and no data.
///
/// The committed file is checked against this function by the examples' tests
/// (`ULOG_BLESS=1` rewrites it).
///
/// ```
/// let bytes = ulog_examples::reference_log();
/// let log = ulog_core::ULog::parse(&bytes).unwrap();
/// assert!(log.format("esc_status").is_some());
/// assert!(log.topics().all(|t| t.is_empty()));
/// ```
pub fn reference_log() -> Vec<u8> {
    let sample = ulog_core::testing::sample_log();
    let log = ulog_core::ULog::parse(&sample).expect("the sample log parses");
    let mut b = ulog_core::testing::LogBuilder::new(log.version(), log.start_timestamp());
    b.flag_bits([0; 8], [0; 8], [0; 3]);
    let mut formats = log.formats();
    formats.sort_by(|a, b| a.name.cmp(&b.name));
    for f in formats {
        b.format(&f.to_string());
    }
    for t in log.topics() {
        b.subscribe(t.multi_id(), t.subscription().msg_id(), t.name());
    }
    b.into_bytes()
}

/// The repository's real log the `replay_attitude` example's reference is made of (a
/// PX4 v1.6 bench log: `sensor_combined` at 250 Hz, `vehicle_attitude` at 30 Hz), as a
/// path under the workspace root.
pub const ATTITUDE_SOURCE_LOG: &str = "tests/corpus/files/sample_appended_multiple.ulg";

/// The topics the `replay_attitude` example replays and checks.
pub const ATTITUDE_TOPICS: [&str; 2] = ["sensor_combined", "vehicle_attitude"];

/// A reference log of `topics` of `log`: their format definitions (and the formats
/// they nest) and subscriptions, and no data. The `replay_attitude` example is
/// compiled against `data/attitude_reference.ulg`, this of [`ATTITUDE_TOPICS`] of
/// [`ATTITUDE_SOURCE_LOG`]; its test keeps the committed file equal to it
/// (`ULOG_BLESS=1` rewrites it).
///
/// ```
/// let bytes = ulog_core::testing::sample_log();
/// let log = ulog_core::ULog::parse(&bytes).unwrap();
/// let reference = ulog_examples::reference_of(&log, &["esc_status"]);
/// let reference = ulog_core::ULog::parse(&reference).unwrap();
/// let formats: Vec<_> = reference.formats().iter().map(|f| f.name.clone()).collect();
/// assert_eq!(formats, ["esc_report", "esc_status"]); // the nested format too
/// assert_eq!(reference.topics().count(), log.topic_instances("esc_status").len());
/// assert!(reference.topics().all(|t| t.is_empty()));
/// ```
pub fn reference_of(log: &ULog<'_>, topics: &[&str]) -> Vec<u8> {
    let mut names = BTreeSet::new();
    let mut todo: Vec<&str> = topics.to_vec();
    while let Some(name) = todo.pop() {
        let Some(format) = log.format(name) else {
            continue;
        };
        if names.insert(format.name.as_str()) {
            for field in &format.fields {
                if let TypeName::Nested(nested) = &field.ty {
                    todo.push(nested);
                }
            }
        }
    }
    let mut b = ulog_core::testing::LogBuilder::new(log.version(), log.start_timestamp());
    b.flag_bits([0; 8], [0; 8], [0; 3]);
    for name in names {
        if let Some(format) = log.format(name) {
            b.format(&format.to_string());
        }
    }
    for t in log.topics().filter(|t| topics.contains(&t.name())) {
        b.subscribe(t.multi_id(), t.subscription().msg_id(), t.name());
    }
    b.into_bytes()
}
