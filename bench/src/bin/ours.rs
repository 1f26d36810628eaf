//! Our workloads, each a whole process, through ulog-core's public API.
//!
//! ```text
//! ours framing FILE               ULog::parse on a memory map (indexes every message)
//! ours scan FILE                  scan over a memory map, counting the data messages
//!                                 (framing without the index)
//! ours decode-stream FILE         scan of Source::file (read in 256 KiB chunks);
//!                                 every field of every data message read as a typed
//!                                 value: numbers through a NumericBlock per subscription
//!                                 (64 payloads read column by column), `char[N]`
//!                                 strings through FieldReader
//! ours decode-ahead FILE          the same with ScanOptions::read_ahead (the next chunk
//!                                 read on a second thread while one is decoded)
//! ours decode-mmap FILE           the same with scan over a memory map
//! ours typed FILE                 sensor_combined and vehicle_attitude through derived
//!                                 structs, one pass over a memory map (scan_topics)
//! ours typed-indexed FILE         the same through ULog::parse + ULog::read::<T>
//! ours columns FILE [THREADS]     every topic into typed columns, read from the file in
//!                                 one pass per thread (load_columns of Source::file)
//! ours columns-indexed FILE THREADS  the same through ULog::parse + load_columns of the
//!                                 parsed log
//! ours write OUT MESSAGES         MESSAGES sensor_combined rows through LogWriter
//! ```
//!
//! Each prints `messages=N` (messages handled) and a `check=` sum of what it read, so
//! that nothing is optimised away (the decode workloads, like the px4-ulog peer, sum in
//! eight partial sums, so that the adds do not wait on each other); `write` also prints `bytes=` (bytes written).

use std::fs::File;
use std::io::BufWriter;
use std::process::ExitCode;

use ulog_core::columns::NumericBlock;
use ulog_core::read::FieldShape;
use ulog_core::write::WriterOptions;
use ulog_core::{
    DataRecord, FieldReader, LogFile, LogWriter, ScanOptions, Source, ULogMessage, ULogTopics,
    Value,
};

type Failure = Box<dyn std::error::Error>;

/// Adds a value read as a typed value to the checksum: numbers and booleans as `f64`,
/// strings byte by byte (as the px4-ulog peer reads `char[N]`: N `char` fields).
#[inline]
fn add(sum: &mut f64, v: Value<'_>) {
    match v {
        Value::Str(s) => *sum += s.as_bytes().iter().map(|b| f64::from(*b)).sum::<f64>(),
        v => *sum += v.as_f64().unwrap_or(0.0),
    }
}

fn framing(path: &str) -> Result<(), Failure> {
    let file = mapped(path)?;
    let log = file.parse()?;
    println!(
        "messages={} topics={} check={}",
        log.message_count(),
        log.subscriptions().len(),
        log.last_timestamp()
    );
    Ok(())
}

fn scan_only(path: &str) -> Result<(), Failure> {
    let file = mapped(path)?;
    let mut data = 0u64;
    let mut check = 0u64;
    let summary = ulog_core::scan(&file, &ScanOptions::default(), |r| {
        data += 1;
        check = check.wrapping_add(r.payload.len() as u64);
    })?;
    println!("messages={} data={data} check={check}", summary.messages);
    Ok(())
}

/// `scan` of `Source::file`, the next chunk read ahead, counting the data messages:
/// framing in chunks, for reference beside `floor --chunks`; with `keep`, the
/// metadata kept too (`ulog info`'s pass without the printing).
fn scan_file(path: &str, keep: bool) -> Result<(), Failure> {
    let options = ScanOptions::default().read_ahead(true).keep_metadata(keep);
    let mut data = 0u64;
    let summary = ulog_core::scan(ulog_core::Source::file(path), &options, |_| data += 1)?;
    let rows: u64 = summary
        .metadata
        .iter()
        .flat_map(|m| m.topics())
        .map(|t| t.rows)
        .sum();
    println!("messages={} data={data} check={rows}", summary.messages);
    Ok(())
}

/// What a subscription's data messages are read with: a block of its payloads whose
/// numeric columns are read at once, and readers for its `char[N]` strings.
struct Decoder {
    block: NumericBlock,
    strings: Vec<FieldReader>,
}

impl Decoder {
    /// Decodes the payloads gathered, and adds every field to the checksum.
    fn flush(&mut self, sum: &mut f64) {
        let rows = self.block.decode();
        // Eight partial sums, so that the adds do not wait on each other.
        let mut acc = [0.0f64; 8];
        let mut lanes = rows.values().chunks_exact(8);
        for q in &mut lanes {
            for k in 0..8 {
                acc[k] += q[k];
            }
        }
        for v in lanes.remainder() {
            acc[0] += *v;
        }
        let mut block =
            ((acc[0] + acc[1]) + (acc[2] + acc[3])) + ((acc[4] + acc[5]) + (acc[6] + acc[7]));
        if !self.strings.is_empty() {
            for i in 0..rows.len() {
                for c in &self.strings {
                    if let Some(v) = c.read(rows.payload(i)) {
                        add(&mut block, v);
                    }
                }
            }
        }
        *sum += block;
    }
}

/// Decoders per subscription index, made at the subscription's first record (`None`
/// inside: no layout).
struct Readers(Vec<Option<Option<Decoder>>>);

impl Readers {
    /// Gathers a data message; adds its block to the checksum when full.
    #[inline]
    fn add(&mut self, sum: &mut f64, r: &DataRecord<'_>) {
        let sub = r.topic.index();
        if sub >= self.0.len() {
            self.0.resize_with(sub + 1, || None);
        }
        let decoder = self.0[sub].get_or_insert_with(|| {
            r.topic.layout().ok().map(|l| Decoder {
                block: NumericBlock::new(l),
                strings: FieldReader::all(l)
                    .into_iter()
                    .filter(|c| c.shape() != FieldShape::Scalar)
                    .collect(),
            })
        });
        if let Some(d) = decoder {
            if d.block.push(r.payload) {
                d.flush(sum);
            }
        }
    }

    /// Adds the blocks not yet full.
    fn finish(&mut self, sum: &mut f64) {
        for d in self.0.iter_mut().flatten().flatten() {
            d.flush(sum);
        }
    }
}

fn decode_stream(path: &str, ahead: bool) -> Result<(), Failure> {
    let mut readers = Readers(Vec::new());
    let mut sum = 0.0f64;
    let options = ScanOptions::default().read_ahead(ahead);
    let summary = ulog_core::scan(Source::file(path), &options, |r| readers.add(&mut sum, &r))?;
    readers.finish(&mut sum);
    println!(
        "messages={} data={} check={sum}",
        summary.messages, summary.data_messages
    );
    Ok(())
}

fn decode_mmap(path: &str) -> Result<(), Failure> {
    let file = mapped(path)?;
    let mut readers = Readers(Vec::new());
    let mut sum = 0.0f64;
    let summary = ulog_core::scan(&file, &ScanOptions::default(), |r| {
        readers.add(&mut sum, &r)
    })?;
    readers.finish(&mut sum);
    println!(
        "messages={} data={} check={sum}",
        summary.messages, summary.data_messages
    );
    Ok(())
}

/// `sensor_combined`: the fields every PX4 version since 2017 logs (the derive maps
/// by name, so newer formats with more fields read too).
#[derive(ULogMessage, Clone, Copy)]
struct SensorCombined {
    timestamp: u64,
    gyro_rad: [f32; 3],
    accelerometer_m_s2: [f32; 3],
}

/// `vehicle_attitude`: timestamp and quaternion.
#[derive(ULogMessage, Clone, Copy)]
struct VehicleAttitude {
    timestamp: u64,
    q: [f32; 4],
}

impl SensorCombined {
    /// Adds the timestamp and every value to the checksum, grouped as the yule_log
    /// peer groups them (so that the two checksums are equal).
    #[inline]
    fn add_to(&self, sum: &mut f64) {
        *sum += self.timestamp as f64;
        *sum += self
            .gyro_rad
            .iter()
            .chain(&self.accelerometer_m_s2)
            .map(|v| f64::from(*v))
            .sum::<f64>();
    }
}

impl VehicleAttitude {
    /// Adds the timestamp and every value to the checksum, grouped as the yule_log
    /// peer groups them.
    #[inline]
    fn add_to(&self, sum: &mut f64) {
        *sum += self.timestamp as f64 + self.q.iter().map(|v| f64::from(*v)).sum::<f64>();
    }
}

/// The two topics of the typed workload.
#[derive(ULogTopics)]
enum Topics {
    Sensors(SensorCombined),
    Attitude(VehicleAttitude),
}

fn typed(path: &str) -> Result<(), Failure> {
    let file = mapped(path)?;
    let mut sum = 0.0f64;
    let mut rows = 0u64;
    let mut failed: Option<ulog_core::TypedError> = None;
    let options = ScanOptions::default();
    ulog_core::scan_topics::<Topics>(&file, &options, |record| match record {
        // Without `raw_others`, every record handed out is decoded.
        Ok(m) => {
            rows += 1;
            match m.message {
                Some(Topics::Sensors(r)) => r.add_to(&mut sum),
                Some(Topics::Attitude(r)) => r.add_to(&mut sum),
                None => unreachable!("a raw record without raw_others"),
            }
        }
        Err(e) => failed = failed.take().or(Some(e)),
    })?;
    if let Some(e) = failed {
        return Err(e.into());
    }
    println!("messages={rows} check={sum}");
    Ok(())
}

fn typed_indexed(path: &str) -> Result<(), Failure> {
    let file = mapped(path)?;
    let log = file.parse()?;
    let mut sum = 0.0f64;
    let mut rows = 0u64;
    // A log without one of the topics (a small test log) reads the other.
    let has = |name: &str| log.topic(name, 0).is_ok();
    let sensors = if has(SensorCombined::NAME) {
        Some(log.read::<SensorCombined>(0)?)
    } else {
        None
    };
    for row in sensors.iter().flat_map(|t| t.iter()) {
        rows += 1;
        row?.add_to(&mut sum);
    }
    let attitudes = if has(VehicleAttitude::NAME) {
        Some(log.read::<VehicleAttitude>(0)?)
    } else {
        None
    };
    for row in attitudes.iter().flat_map(|t| t.iter()) {
        rows += 1;
        row?.add_to(&mut sum);
    }
    println!("messages={rows} check={sum}");
    Ok(())
}

fn columns(path: &str, threads: usize) -> Result<(), Failure> {
    let options = ScanOptions::default().threads(threads);
    let loaded = ulog_core::load_columns(Source::file(path), &options)?;
    let tables = loaded.topics.iter().map(|t| t.columns.as_ref());
    print_columns(loaded.summary.messages, tables);
    Ok(())
}

fn columns_indexed(path: &str, threads: usize) -> Result<(), Failure> {
    let file = mapped(path)?;
    let log = file.parse()?;
    let options = ScanOptions::default().threads(threads);
    let loaded = ulog_core::load_columns(&log, &options)?;
    let tables = loaded.topics.iter().map(|t| t.columns.as_ref());
    print_columns(log.message_count(), tables);
    Ok(())
}

/// Prints the values loaded (so that nothing is optimised away) and the topics that
/// could not be loaded.
fn print_columns<'t, E: 't>(
    messages: u64,
    tables: impl Iterator<Item = Result<&'t Vec<ulog_core::columns::Column>, E>>,
) {
    let (mut values, mut topics, mut failed) = (0usize, 0usize, 0usize);
    for t in tables {
        topics += 1;
        match t {
            Ok(columns) => values += columns.iter().map(|c| c.data.len()).sum::<usize>(),
            Err(_) => failed += 1,
        }
    }
    println!("messages={messages} values={values} topics={topics} failed_topics={failed}");
}

/// `sensor_combined` as PX4 v1.14 logs it (48 bytes).
#[derive(ULogMessage, Clone, Copy)]
struct SensorCombinedFull {
    timestamp: u64,
    gyro_rad: [f32; 3],
    gyro_integral_dt: u32,
    accelerometer_timestamp_relative: i32,
    accelerometer_m_s2: [f32; 3],
    accelerometer_integral_dt: u32,
    accelerometer_clipping: u8,
    gyro_clipping: u8,
    accel_calibration_count: u8,
    gyro_calibration_count: u8,
}

fn write(out: &str, messages: u64) -> Result<(), Failure> {
    let file = BufWriter::with_capacity(1 << 16, File::create(out)?);
    let mut w = LogWriter::with_options(file, 0, WriterOptions::default())?;
    let h = w.subscribe::<SensorCombinedFull>(0)?;
    let mut data = w.start_data()?;
    for i in 0..messages {
        let f = i as f32 * 1e-3;
        data.write(
            &h,
            &SensorCombinedFull {
                timestamp: 1_000 + 1_000 * i,
                gyro_rad: [f, -f, 0.25],
                gyro_integral_dt: 5000,
                accelerometer_timestamp_relative: 0,
                accelerometer_m_s2: [0.1, -0.2, -9.81 + f],
                accelerometer_integral_dt: 5000,
                accelerometer_clipping: 0,
                gyro_clipping: 0,
                accel_calibration_count: 1,
                gyro_calibration_count: 1,
            },
        )?;
    }
    let mut file = data.finish()?;
    std::io::Write::flush(&mut file)?;
    let bytes = file.get_ref().metadata()?.len();
    println!("messages={messages} bytes={bytes}");
    Ok(())
}

const USAGE: &str = "usage: ours (framing|scan|scan-file|metadata|decode-stream|decode-ahead|decode-mmap|typed|typed-indexed) FILE | ours columns FILE [THREADS] | ours columns-indexed FILE THREADS | ours write OUT MESSAGES";

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let a: Vec<&str> = args.iter().map(String::as_str).collect();
    let result = match a.as_slice() {
        ["framing", f] => framing(f),
        ["scan", f] => scan_only(f),
        ["scan-file", f] => scan_file(f, false),
        ["metadata", f] => scan_file(f, true),
        ["decode-stream", f] => decode_stream(f, false),
        ["decode-ahead", f] => decode_stream(f, true),
        ["decode-mmap", f] => decode_mmap(f),
        ["typed", f] => typed(f),
        ["typed-indexed", f] => typed_indexed(f),
        ["columns", f] => columns(f, 1),
        ["columns-indexed", f, n] => match n.parse() {
            Ok(n) => columns_indexed(f, n),
            Err(e) => Err(format!("THREADS `{n}`: {e}").into()),
        },
        ["columns", f, n] => match n.parse() {
            Ok(n) => columns(f, n),
            Err(e) => Err(format!("THREADS `{n}`: {e}").into()),
        },
        ["write", out, n] => match n.parse() {
            Ok(n) => write(out, n),
            Err(e) => Err(format!("MESSAGES `{n}`: {e}").into()),
        },
        _ => {
            eprintln!("{USAGE}");
            return ExitCode::from(2);
        }
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("ours: {e}");
            ExitCode::FAILURE
        }
    }
}

/// The file mapped into memory, as the table says: nothing writes the benchmark's
/// logs while a program reads them, which is what `LogFile::map` asks of its caller.
fn mapped(path: &str) -> Result<LogFile, Failure> {
    // SAFETY: the benchmark's input files do not change while a program runs.
    Ok(unsafe { LogFile::map(path) }?)
}
