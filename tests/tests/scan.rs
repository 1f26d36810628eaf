//! One-pass scans (`scan` of bytes, of a reader, read ahead; `scan_topics` with and
//! without `raw_others`) hand out exactly the data messages the whole-file parse
//! indexes, in file order, with the same findings, on every corpus log (damaged ones
//! included) and however the bytes arrive.

use std::io::Read;

use ulog_core::typed::TypedErrorKind;
use ulog_core::{ScanOptions, Source, ULog, ULogMessage, ULogTopics};
use ulog_tests::{corpus_files, stem};

/// Every log to check: the sample and the corpus.
fn logs() -> Vec<(String, Vec<u8>)> {
    let mut logs = vec![("sample".to_owned(), ulog_core::testing::sample_log())];
    for p in corpus_files() {
        logs.push((stem(&p), std::fs::read(&p).unwrap()));
    }
    logs
}

/// (offset, subscription, payload) of every data message the parse indexed, in file
/// order.
fn indexed<'a>(log: &ULog<'a>) -> Vec<(u64, usize, &'a [u8])> {
    let mut all: Vec<(u64, usize, &'a [u8])> = Vec::new();
    for (i, topic) in log.topics().enumerate() {
        for (p, o) in topic.payloads().zip(topic.message_offsets()) {
            all.push((o, i, p));
        }
    }
    all.sort_by_key(|r| r.0);
    all
}

/// A reader that hands out the bytes in pieces of pseudo-random sizes (1 to 700
/// bytes), so that messages and damaged stretches straddle reads.
struct Drip<'a> {
    bytes: &'a [u8],
    state: u64,
}

impl Read for Drip<'_> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        self.state = self
            .state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        let n = ((self.state >> 33) % 700 + 1) as usize;
        let n = n.min(buf.len()).min(self.bytes.len());
        buf[..n].copy_from_slice(&self.bytes[..n]);
        self.bytes = &self.bytes[n..];
        Ok(n)
    }
}

#[test]
fn scans_hand_out_what_the_parse_indexes() {
    let mut checked = 0;
    for (name, bytes) in logs() {
        let Ok(log) = ULog::parse(&bytes) else {
            assert!(
                ulog_core::scan(&bytes, &ScanOptions::default(), |_| {}).is_err(),
                "{name}"
            );
            assert!(
                ulog_core::scan(Source::reader(&bytes[..]), &ScanOptions::default(), |_| {})
                    .is_err(),
                "{name}"
            );
            continue;
        };
        let expected = indexed(&log);
        let mut got = Vec::new();
        let summary = ulog_core::scan(&bytes, &ScanOptions::default(), |r| {
            let topic = log.topic_at(r.topic.index());
            assert_eq!(
                (r.topic.name(), r.topic.multi_id()),
                (topic.name(), topic.multi_id()),
                "{name}"
            );
            assert_eq!(r.topic.offset(), topic.subscription().offset(), "{name}");
            assert_eq!(
                r.topic.layout().ok().is_some(),
                log.topic_at(r.topic.index()).layout().is_ok()
            );
            got.push((r.offset, r.topic.index(), r.payload.to_vec()));
        })
        .unwrap();
        // The record's payload lives only as long as the callback: compared as copies.
        let expected_owned: Vec<(u64, usize, Vec<u8>)> = expected
            .iter()
            .map(|&(o, s, p)| (o, s, p.to_vec()))
            .collect();
        assert_eq!(got, expected_owned, "{name}");
        assert_eq!(summary.messages, log.message_count(), "{name}");
        assert_eq!(summary.data_messages as usize, expected.len(), "{name}");
        assert_eq!(summary.findings, log.findings(), "{name}");
        assert_eq!(summary.header, log.header(), "{name}");
        assert_eq!(summary.flag_bits.as_ref(), log.flag_bits(), "{name}");
        assert_eq!(summary.topics.len(), log.subscriptions().len(), "{name}");
        for (t, topic) in summary.topics.iter().zip(log.topics()) {
            assert_eq!((t.name(), t.multi_id()), (topic.name(), topic.multi_id()));
            assert_eq!(t.msg_id(), topic.subscription().msg_id(), "{name}");
        }

        // One thread, then reading ahead: with the library's chunks, and with small
        // chunks and room (carried bytes that do not fit it take the slow way).
        let sizes = [None, None, Some(None), Some(Some((997, 64)))];
        for (seed, ahead) in (1..).zip(sizes) {
            let mut streamed: Vec<(u64, usize, Vec<u8>)> = Vec::new();
            let drip = Drip {
                bytes: &bytes,
                state: seed,
            };
            let push = |r: ulog_core::DataRecord<'_>| {
                streamed.push((r.offset, r.topic.index(), r.payload.to_vec()))
            };
            let s = match ahead {
                None => ulog_core::scan(Source::reader(drip), &ScanOptions::default(), push),
                Some(None) => ulog_core::scan(
                    Source::reader(drip),
                    &ScanOptions::default().read_ahead(true),
                    push,
                ),
                Some(Some((chunk, room))) => {
                    ulog_core::testing::read_ahead_in(drip, chunk, room, push)
                }
            }
            .unwrap();
            assert_eq!(s, summary, "{name}: streamed summary ({ahead:?})");
            assert!(
                streamed
                    .iter()
                    .map(|(o, s, p)| (*o, *s, &p[..]))
                    .eq(expected.iter().copied()),
                "{name}: streamed records ({ahead:?})"
            );
        }
        checked += 1;
    }
    assert!(checked >= 1);
}

#[derive(ULogMessage, Debug, Clone, Copy)]
struct VehicleAttitude {
    timestamp: u64,
    q: [f32; 4],
}

#[derive(ULogMessage, Debug, Clone, Copy)]
struct SensorCombined {
    timestamp: u64,
    gyro_rad: [f32; 3],
    accelerometer_m_s2: [f32; 3],
}

/// `esc_status` with a field type no log has and none widens to (`esc_count` is a
/// `uint8_t`, which `i8` cannot hold every value of): a mismatch to report.
#[derive(ULogMessage, Debug, Clone, Copy)]
struct EscStatus {
    timestamp: u64,
    esc_count: i8,
}

#[derive(ULogTopics, Debug)]
enum Topics {
    Attitude(VehicleAttitude),
    Sensors(SensorCombined),
    Esc(EscStatus),
}

/// An error of a walk as text: the topic instance, where, and what.
fn error_text(topic: Option<(&str, u8)>, position: Option<u64>, what: &str) -> String {
    format!("error {topic:?} at {position:?}: {what}")
}

/// A record of `scan_topics` as text: where it is, its topic instance, timestamp and
/// payload, and the message decoded; an error as `error_text`.
fn walk_text(r: &Result<ulog_core::TopicRecord<'_, Topics>, ulog_core::TypedError>) -> String {
    match r {
        Ok(r) => format!(
            "{} {}/{} {:?} {:?} {:?}",
            r.offset,
            r.topic.name(),
            r.topic.multi_id(),
            r.timestamp,
            r.payload,
            r.message
        ),
        Err(e) => match e.kind() {
            TypedErrorKind::Mismatch(m) => error_text(e.topic(), e.position(), &format!("{m:?}")),
            TypedErrorKind::NoLayout(l) => error_text(e.topic(), e.position(), &format!("{l:?}")),
            _ => format!("{e:?}"),
        },
    }
}

/// The file-order walk built from the parse's index (what `ULog::walk` did): every
/// data message in file order, each subscription planned at its first record with
/// the enum's own `plan` (an error then if its format does not fit, its records
/// raw after it), the others raw.
fn index_walk(log: &ULog<'_>) -> Vec<String> {
    let n = log.subscriptions().len();
    let mut plans: Vec<Option<Option<ulog_core::typed::TopicPlan>>> = vec![None; n];
    let timestamps: Vec<Vec<u64>> = log.topics().map(|t| t.timestamps()).collect();
    let mut rows = vec![0usize; n];
    let mut out = Vec::new();
    for (offset, i, payload) in indexed(log) {
        let sub = log.topic_at(i).subscription();
        let instance = Some((sub.name(), sub.multi_id()));
        let plan = plans[i].get_or_insert_with(|| {
            let variant = Topics::variant_of(sub.name())?;
            match sub.layout() {
                Err(l) => {
                    out.push(error_text(instance, Some(sub.offset()), &format!("{l:?}")));
                    None
                }
                Ok(layout) => match Topics::plan(variant, layout)? {
                    Ok(plan) => Some(plan),
                    Err(m) => {
                        out.push(error_text(instance, Some(sub.offset()), &format!("{m:?}")));
                        None
                    }
                },
            }
        });
        let message = plan
            .as_ref()
            .map(|p| Topics::decode(p, payload).expect("framing checked the size"));
        let timestamp = sub
            .timestamp_field()
            .and_then(|_| timestamps[i].get(rows[i]).copied());
        rows[i] += 1;
        out.push(format!(
            "{offset} {}/{} {timestamp:?} {payload:?} {message:?}",
            sub.name(),
            sub.multi_id()
        ));
    }
    out
}

#[test]
fn scan_topics_is_the_file_order_walk() {
    let mut decoded = 0;
    let mut mismatches = 0;
    for (name, bytes) in logs() {
        let Ok(log) = ULog::parse(&bytes) else {
            continue;
        };
        // The walk of the parsed log's index, every record (the others raw), in file
        // order; and `scan_topics` of the parsed log, which must agree with it too.
        let walked = index_walk(&log);
        let all = ScanOptions::default().raw_others(true);
        let mut of_log: Vec<String> = Vec::new();
        ulog_core::scan_topics::<Topics>(&log, &all, |r| of_log.push(walk_text(&r))).unwrap();
        assert_eq!(of_log.len(), walked.len(), "{name}: of the parsed log");
        for (i, (s, w)) in of_log.iter().zip(&walked).enumerate() {
            assert_eq!(s, w, "{name}: record {i} of the parsed log");
        }
        let mut scanned = Vec::new();
        ulog_core::scan_topics::<Topics>(&bytes, &all, |r| {
            if let Ok(ulog_core::TopicRecord {
                message: Some(message),
                ..
            }) = &r
            {
                let timestamp = match message {
                    Topics::Attitude(a) => a.timestamp,
                    Topics::Sensors(s) => s.timestamp,
                    Topics::Esc(e) => e.timestamp,
                };
                assert!(timestamp > 0, "{name}");
                decoded += 1;
            }
            if let Err(e) = &r {
                assert!(
                    matches!(e.kind(), TypedErrorKind::Mismatch(_)),
                    "{name}: {e}"
                );
                mismatches += 1;
            }
            scanned.push(walk_text(&r));
        })
        .unwrap();
        assert_eq!(scanned.len(), walked.len(), "{name}");
        for (i, (s, w)) in scanned.iter().zip(&walked).enumerate() {
            assert_eq!(s, w, "{name}: record {i}");
        }
    }
    assert!(decoded > 0);
    // `esc_status` (in the sample and several corpus logs) does not fit `EscStatus`:
    // reported, then raw.
    assert!(mismatches > 0);
}

#[test]
fn scan_topics_only_is_scan_topics_without_the_raw_records() {
    let mut decoded = 0;
    let mut mismatches = 0;
    for (name, bytes) in logs() {
        // Offsets of the data messages, in file order, to place scan_topics' records.
        let mut offsets = Vec::new();
        let Ok(all) = ulog_core::scan(&bytes, &ScanOptions::default(), |r| offsets.push(r.offset))
        else {
            assert!(
                ulog_core::scan_topics::<Topics>(&bytes, &ScanOptions::default(), |_| {}).is_err()
            );
            continue;
        };
        let mut expected = Vec::new();
        let mut records = offsets.iter();
        let raw_others = ScanOptions::default().raw_others(true);
        let full = ulog_core::scan_topics::<Topics>(&bytes, &raw_others, |r| match r {
            Ok(r) => {
                let offset = records.next().unwrap();
                assert_eq!(r.offset, *offset, "{name}");
                if let Some(message) = r.message {
                    let multi_id = r.topic.multi_id();
                    expected.push(format!("{offset} {multi_id} {message:?}"));
                }
            }
            Err(e) => expected.push(format!("{e:?}")),
        })
        .unwrap();
        assert!(records.next().is_none(), "{name}");
        let mut only = Vec::new();
        let summary =
            ulog_core::scan_topics::<Topics>(&bytes, &ScanOptions::default(), |r| match r {
                Ok(m) => {
                    decoded += 1;
                    let message = m.message.expect("only named topics are handed out");
                    only.push(format!("{} {} {:?}", m.offset, m.topic.multi_id(), message));
                }
                Err(e) => {
                    assert!(
                        matches!(e.kind(), TypedErrorKind::Mismatch(_)),
                        "{name}: {e}"
                    );
                    mismatches += 1;
                    only.push(format!("{e:?}"));
                }
            })
            .unwrap();
        assert_eq!(only.len(), expected.len(), "{name}");
        for (i, (o, e)) in only.iter().zip(&expected).enumerate() {
            assert_eq!(o, e, "{name}: record {i}");
        }
        // The other topics are framed and counted all the same.
        assert_eq!(summary, full, "{name}");
        assert_eq!(summary, all, "{name}");
    }
    assert!(decoded > 0);
    // `esc_status` (in the sample and several corpus logs) does not fit `EscStatus`:
    // reported once.
    assert!(mismatches > 0);
}

/// One subscription's block, its column readers, and the payloads it holds.
struct Pending {
    block: ulog_core::columns::NumericBlock,
    columns: Vec<ulog_core::FieldReader>,
    min_size: usize,
    payloads: Vec<Vec<u8>>,
}

impl Pending {
    /// Decodes the block; every value must be what the column's own reader reads from
    /// the payload as handed out (NaN where it reads nothing), bit for bit.
    fn check(&mut self, name: &str, values: &mut usize) {
        let rows = self.block.decode();
        assert_eq!(rows.len(), self.payloads.len(), "{name}");
        assert_eq!(rows.width(), self.columns.len(), "{name}");
        for (i, p) in self.payloads.iter().enumerate() {
            assert_eq!(rows.payload(i), &p[..p.len().min(self.min_size)], "{name}");
            for (c, got) in self.columns.iter().zip(rows.row(i)) {
                let want = c.read_f64(p).unwrap_or(f64::NAN);
                assert_eq!(got.to_bits(), want.to_bits(), "{name} {}", c.path());
                *values += 1;
            }
        }
        self.payloads.clear();
    }
}

#[test]
fn numeric_blocks_read_every_number_as_field_readers_do() {
    let mut values = 0;
    for (name, bytes) in logs() {
        let mut pending: Vec<Option<Option<Pending>>> = Vec::new();
        let drip = Drip {
            bytes: &bytes,
            state: 7,
        };
        let scanned = ulog_core::scan(Source::reader(drip), &ScanOptions::default(), |r| {
            let i = r.topic.index();
            if i >= pending.len() {
                pending.resize_with(i + 1, || None);
            }
            let slot = pending[i].get_or_insert_with(|| {
                r.topic.layout().ok().map(|l| Pending {
                    // A small block, so that most logs fill it many times.
                    block: ulog_core::columns::NumericBlock::with_capacity(l, 7),
                    // The scalar columns, from the one-field readers.
                    columns: ulog_core::FieldReader::all(l)
                        .into_iter()
                        .filter(|c| c.shape() == ulog_core::read::FieldShape::Scalar)
                        .collect(),
                    min_size: l.min_size(),
                    payloads: Vec::new(),
                })
            });
            if let Some(p) = slot {
                p.payloads.push(r.payload.to_vec());
                if p.block.push(r.payload) {
                    p.check(&name, &mut values);
                }
            }
        });
        if scanned.is_err() {
            continue;
        }
        for p in pending.iter_mut().flatten().flatten() {
            p.check(&name, &mut values);
        }
    }
    // The repository's own logs hold over a hundred thousand values; the full corpus
    // over a million.
    let least = if ulog_tests::FULL_CORPUS {
        1_000_000
    } else {
        100_000
    };
    assert!(values > least, "{values} values compared");
}
