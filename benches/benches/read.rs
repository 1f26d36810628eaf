//! Reading: framing (`ULog::parse`, which indexes every message) and generic decoding
//! of every field of every data message: message by message (`StreamReader`), in
//! one pass (`scan` of a `Source::reader`, with field readers; the numbers only, with a
//! `NumericRow` per message or a `NumericBlock` per topic, the blocks also through
//! `scan` over the buffer) and from the parsed index; and the columnar load in one
//! pass (`load_columns` of a `Source::reader`) and from the index on one and two
//! threads; and two topics (`sensor_combined`, `vehicle_attitude`) through derived
//! structs in one pass (`scan_topics`), with the other topics handed out raw
//! (`raw_others(true)`) or not at all (the default).
//! The whole-process versions of these, beside the peers, are in `bench/run`.
//!
//! ```text
//! cargo bench -p ulog-benches --bench read                  # the corpus's sample.ulg
//! ULOG_BENCH_FILE=big.ulg cargo bench -p ulog-benches --bench read
//! cargo bench -p ulog-benches --bench read -- --test        # each once (CI)
//! ```

use std::hint::black_box;

use criterion::{Criterion, Throughput};
use ulog_core::columns::{NumericBlock, NumericRow};
use ulog_core::stream::StreamReader;
use ulog_core::{
    DataRecord, FieldReader, Message, ScanOptions, Source, ULog, ULogMessage, ULogTopics, Value,
};

/// `sensor_combined`: timestamp, gyro and accelerometer.
#[derive(ULogMessage)]
struct SensorCombined {
    timestamp: u64,
    gyro_rad: [f32; 3],
    accelerometer_m_s2: [f32; 3],
}

/// `vehicle_attitude`: timestamp and quaternion.
#[derive(ULogMessage)]
struct VehicleAttitude {
    timestamp: u64,
    q: [f32; 4],
}

/// The two topics of the typed rows.
#[derive(ULogTopics)]
enum Two {
    Sensors(SensorCombined),
    Attitude(VehicleAttitude),
}

impl Two {
    /// The timestamp and every value, summed.
    fn sum(&self) -> f64 {
        let sum = |v: &[f32]| v.iter().map(|&x| f64::from(x)).sum::<f64>();
        match self {
            Two::Sensors(s) => s.timestamp as f64 + sum(&s.gyro_rad) + sum(&s.accelerometer_m_s2),
            Two::Attitude(a) => a.timestamp as f64 + sum(&a.q),
        }
    }
}

/// The two topics through `scan_topics` with `raw_others` (the other topics come raw).
fn typed_scan(bytes: &[u8]) -> f64 {
    let mut sum = 0.0;
    let options = ScanOptions::default().raw_others(true);
    ulog_core::scan_topics::<Two>(bytes, &options, |r| {
        if let Ok(ulog_core::TopicRecord {
            message: Some(message),
            ..
        }) = r
        {
            sum += message.sum();
        }
    })
    .expect("scans");
    sum
}

/// The two topics through `scan_topics` with the default options (the other topics
/// are not handed out).
fn typed_scan_only(bytes: &[u8]) -> f64 {
    let mut sum = 0.0;
    ulog_core::scan_topics::<Two>(bytes, &ScanOptions::default(), |r| {
        if let Ok(ulog_core::TopicRecord {
            message: Some(message),
            ..
        }) = r
        {
            sum += message.sum();
        }
    })
    .expect("scans");
    sum
}

fn load() -> (String, Vec<u8>) {
    if let Some(path) = std::env::var_os("ULOG_BENCH_FILE") {
        let bytes = std::fs::read(&path)
            .unwrap_or_else(|e| panic!("ULOG_BENCH_FILE {}: {e}", path.to_string_lossy()));
        return (path.to_string_lossy().into_owned(), bytes);
    }
    let corpus = std::env::var_os("ULOG_CORPUS")
        .map(std::path::PathBuf::from)
        .unwrap_or_else(|| {
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/corpus")
        });
    if let Ok(bytes) = std::fs::read(corpus.join("files/sample.ulg")) {
        return ("corpus sample.ulg".to_owned(), bytes);
    }
    (
        "ulog_core::testing::sample_log()".to_owned(),
        ulog_core::testing::sample_log(),
    )
}

fn add(sum: &mut f64, v: Value<'_>) {
    match v {
        Value::Str(s) => *sum += s.as_bytes().len() as f64,
        v => *sum += v.as_f64().unwrap_or(0.0),
    }
}

/// The sum of `values` in eight partial sums, so that the adds do not wait on each
/// other (as `bench/`'s whole-process decode sums); one running sum would take longer
/// than the decoding.
fn sum8(values: &[f64]) -> f64 {
    let mut acc = [0.0f64; 8];
    let mut lanes = values.chunks_exact(8);
    for q in &mut lanes {
        for k in 0..8 {
            acc[k] += q[k];
        }
    }
    for v in lanes.remainder() {
        acc[0] += *v;
    }
    ((acc[0] + acc[1]) + (acc[2] + acc[3])) + ((acc[4] + acc[5]) + (acc[6] + acc[7]))
}

/// Every field of every data message through the stream reader, leaves resolved once
/// per subscription.
fn decode_stream(bytes: &[u8]) -> f64 {
    let mut reader = StreamReader::new(bytes);
    let mut by_id: Vec<Option<Vec<FieldReader>>> = Vec::new();
    let mut sum = 0.0;
    loop {
        let mut subscribed = None;
        {
            let Some(m) = reader.next_message().expect("reads") else {
                break;
            };
            match m.message {
                Message::Data { msg_id, payload } => {
                    if let Some(Some(columns)) = by_id.get(msg_id as usize) {
                        for c in columns {
                            if let Some(v) = c.read(payload) {
                                add(&mut sum, v);
                            }
                        }
                    }
                }
                Message::Subscribe { msg_id, .. } => subscribed = Some(msg_id),
                _ => {}
            }
        }
        if let Some(id) = subscribed {
            let columns = reader
                .state()
                .subscription(id)
                .and_then(|s| s.layout().ok().map(|l| FieldReader::all(l)));
            if by_id.len() <= id as usize {
                by_id.resize(id as usize + 1, None);
            }
            by_id[id as usize] = columns;
        }
    }
    sum
}

/// Every field of every data message in one pass (`scan` of a `Source::reader`),
/// leaves resolved at each subscription's first record.
fn decode_scan(bytes: &[u8]) -> f64 {
    let mut readers: Vec<Option<Option<Vec<FieldReader>>>> = Vec::new();
    let mut sum = 0.0;
    ulog_core::scan(Source::reader(bytes), &ScanOptions::default(), |r| {
        let sub = r.topic.index();
        if sub >= readers.len() {
            readers.resize(sub + 1, None);
        }
        let columns =
            readers[sub].get_or_insert_with(|| r.topic.layout().ok().map(|l| FieldReader::all(l)));
        for c in columns.iter().flatten() {
            if let Some(v) = c.read(r.payload) {
                add(&mut sum, v);
            }
        }
    })
    .expect("reads");
    sum
}

/// Every number of every data message in one pass (`scan` of a `Source::reader`),
/// through a `NumericRow` per subscription, message by message (`char[N]` strings left
/// out).
fn decode_rows(bytes: &[u8]) -> f64 {
    let mut rows: Vec<Option<Option<NumericRow>>> = Vec::new();
    let mut values = Vec::new();
    let mut sum = 0.0;
    ulog_core::scan(Source::reader(bytes), &ScanOptions::default(), |r| {
        let sub = r.topic.index();
        if sub >= rows.len() {
            rows.resize_with(sub + 1, || None);
        }
        let row = rows[sub].get_or_insert_with(|| r.topic.layout().ok().map(|l| NumericRow::of(l)));
        if let Some(row) = row {
            values.resize(row.width(), 0.0);
            row.read(r.payload, &mut values);
            sum += sum8(&values);
        }
    })
    .expect("reads");
    sum
}

/// Every number of every data message in one pass, through a `NumericBlock` per
/// subscription (`char[N]` strings left out): with `scan` over the buffer when
/// `in_place` (as over a memory map), else with `scan` of a `Source::reader` (a copy
/// into its window).
fn decode_blocks(bytes: &[u8], in_place: bool) -> f64 {
    type Blocks = Vec<Option<Option<NumericBlock>>>;
    fn add_rows(sum: &mut f64, block: &mut NumericBlock) {
        *sum += sum8(block.decode().values());
    }
    fn push(blocks: &mut Blocks, sum: &mut f64, r: &DataRecord<'_>) {
        let sub = r.topic.index();
        if sub >= blocks.len() {
            blocks.resize_with(sub + 1, || None);
        }
        let block =
            blocks[sub].get_or_insert_with(|| r.topic.layout().ok().map(|l| NumericBlock::new(l)));
        if let Some(block) = block {
            if block.push(r.payload) {
                add_rows(sum, block);
            }
        }
    }
    let mut blocks: Blocks = Vec::new();
    let mut sum = 0.0;
    let options = ScanOptions::default();
    if in_place {
        ulog_core::scan(bytes, &options, |r| push(&mut blocks, &mut sum, &r))
    } else {
        ulog_core::scan(Source::reader(bytes), &options, |r| {
            push(&mut blocks, &mut sum, &r)
        })
    }
    .expect("reads");
    for block in blocks.iter_mut().flatten().flatten() {
        add_rows(&mut sum, block);
    }
    sum
}

/// Every field of every data message through the parsed index and field readers.
fn decode_index(log: &ULog<'_>) -> f64 {
    let mut sum = 0.0;
    for topic in log.topics() {
        let Ok(columns) = topic.fields() else {
            continue;
        };
        for payload in topic.payloads() {
            for c in &columns {
                if let Some(v) = c.read(payload) {
                    add(&mut sum, v);
                }
            }
        }
    }
    sum
}

fn main() {
    let (name, bytes) = load();
    let log = ULog::parse(&bytes).expect("the input parses");
    println!(
        "input: {name} ({} bytes, {} messages)",
        bytes.len(),
        log.message_count()
    );
    let mut c = Criterion::default().configure_from_args();
    let mut group = c.benchmark_group("read");
    group.throughput(Throughput::Bytes(bytes.len() as u64));
    group.bench_function("framing (ULog::parse)", |b| {
        b.iter(|| {
            ULog::parse(black_box(&bytes))
                .expect("parses")
                .message_count()
        })
    });
    group.bench_function("generic decode (StreamReader)", |b| {
        b.iter(|| decode_stream(black_box(&bytes)))
    });
    group.bench_function("generic decode (scan, Source::reader)", |b| {
        b.iter(|| decode_scan(black_box(&bytes)))
    });
    group.bench_function("numbers only (scan, Source::reader, NumericRow)", |b| {
        b.iter(|| decode_rows(black_box(&bytes)))
    });
    group.bench_function("numbers only (scan, Source::reader, NumericBlock)", |b| {
        b.iter(|| decode_blocks(black_box(&bytes), false))
    });
    group.bench_function("numbers only (scan, NumericBlock)", |b| {
        b.iter(|| decode_blocks(black_box(&bytes), true))
    });
    group.bench_function("generic decode (parsed index)", |b| {
        b.iter(|| decode_index(black_box(&log)))
    });
    group.bench_function("typed decode (scan_topics raw_others, 2 topics)", |b| {
        b.iter(|| typed_scan(black_box(&bytes)))
    });
    group.bench_function("typed decode (scan_topics named only, 2 topics)", |b| {
        b.iter(|| typed_scan_only(black_box(&bytes)))
    });
    group.bench_function("columnar load (one pass, load_columns)", |b| {
        b.iter(|| {
            ulog_core::load_columns(
                Source::reader(black_box(&bytes[..])),
                &ScanOptions::default(),
            )
            .expect("loads")
            .topics
            .len()
        })
    });
    for threads in [1, 2] {
        group.bench_function(format!("columnar load (index, {threads} thread)"), |b| {
            let options = ScanOptions::default().threads(threads);
            b.iter(|| {
                ulog_core::load_columns(black_box(&log), &options)
                    .expect("loads")
                    .topics
                    .len()
            })
        });
    }
    group.finish();
    c.final_summary();
}
