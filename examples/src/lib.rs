//! Examples of `ulog-core` live in `examples/examples/`; this library holds what they
//! share with their tests.

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
