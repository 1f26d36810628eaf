//! Typed writing throughput: values of a derived topic written through the writer into
//! memory, against a plain `Vec<u8>` copy of the very same bytes, measured in the same
//! run (the copy is the floor: the writer's cost is everything above it).
//!
//! ```text
//! cargo bench -p ulog-benches --bench write
//! cargo bench -p ulog-benches --bench write -- --test   # once (CI)
//! ```

use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::{Criterion, Throughput};
use ulog_core::write::WriterOptions;
use ulog_core::{LogWriter, ULogMessage};

/// `sensor_combined` as PX4 v1.14 logs it.
#[derive(ULogMessage, Clone, Copy)]
struct SensorCombined {
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

const ROWS: usize = 100_000;

fn rows() -> Vec<SensorCombined> {
    (0..ROWS)
        .map(|i| SensorCombined {
            timestamp: 1_000 * i as u64,
            gyro_rad: [i as f32 * 1e-3, -0.5, 0.25],
            gyro_integral_dt: 5000,
            accelerometer_timestamp_relative: 0,
            accelerometer_m_s2: [0.1, -0.2, -9.81],
            accelerometer_integral_dt: 5000,
            accelerometer_clipping: 0,
            gyro_clipping: 0,
            accel_calibration_count: 1,
            gyro_calibration_count: 1,
        })
        .collect()
}

fn write_all(rows: &[SensorCombined], out: Vec<u8>) -> Vec<u8> {
    let mut w = LogWriter::with_options(out, 0, WriterOptions::default()).unwrap();
    let h = w.subscribe::<SensorCombined>(0).unwrap();
    let mut data = w.start_data().unwrap();
    for r in rows {
        data.write(&h, r).unwrap();
    }
    data.finish().unwrap()
}

fn main() {
    let rows = rows();
    let written = write_all(&rows, Vec::new());
    let bytes = written.len();
    let mut c = Criterion::default().configure_from_args();
    let mut totals = [(Duration::ZERO, 0u64); 2];
    let mut group = c.benchmark_group("write");
    group.throughput(Throughput::Bytes(bytes as u64));
    let mut buf = Vec::with_capacity(bytes);
    group.bench_function("typed writer", |b| {
        b.iter_custom(|iters| {
            let start = Instant::now();
            for _ in 0..iters {
                buf.clear();
                buf = black_box(write_all(&rows, std::mem::take(&mut buf)));
            }
            let t = start.elapsed();
            totals[0].0 += t;
            totals[0].1 += iters;
            t
        })
    });
    let mut copy = Vec::with_capacity(bytes);
    group.bench_function("Vec<u8> copy", |b| {
        b.iter_custom(|iters| {
            let start = Instant::now();
            for _ in 0..iters {
                copy.clear();
                copy.extend_from_slice(black_box(&written));
                black_box(&copy);
            }
            let t = start.elapsed();
            totals[1].0 += t;
            totals[1].1 += iters;
            t
        })
    });
    group.finish();
    c.final_summary();
    let per = |(t, n): (Duration, u64)| t.as_secs_f64() / n.max(1) as f64;
    let (writer, floor) = (per(totals[0]), per(totals[1]));
    println!(
        "typed writer: {:.1} M messages/s, {:.0} MB/s; Vec<u8> copy of the same {} bytes: {:.0} MB/s; writer/copy time ratio {:.2}",
        ROWS as f64 / writer / 1e6,
        bytes as f64 / writer / 1e6,
        bytes,
        bytes as f64 / floor / 1e6,
        writer / floor
    );
}
