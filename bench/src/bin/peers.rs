//! Peer readers on the same workloads, each a whole process, through their published
//! APIs (crates.io: yule_log 0.4, px4-ulog 0.6).
//!
//! ```text
//! peers yule-raw FILE      yule_log's parser: every data message decoded, every field summed
//! peers yule-derive FILE   yule_log's derive: sensor_combined and vehicle_attitude
//! peers px4-stream FILE    px4-ulog's stream callback, every field of every data
//!                          message decoded from its flattened format and summed (in
//!                          eight partial sums, as `ours decode-*` sums)
//! peers px4-full FILE      px4-ulog's full_parser::read_file (every topic into columns)
//! ```
//!
//! Each prints `messages=N check=X` like `ours`.

use std::fs::File;
use std::io::BufReader;
use std::process::ExitCode;

use px4_ulog::full_parser::SomeVec;
use px4_ulog::stream_parser::model::{FlattenedField, FlattenedFieldType};
use px4_ulog::stream_parser::{read_file_with_simple_callback, Message, SimpleCallbackResult};
use yule_log::builder::ULogParserBuilder;
use yule_log::model::inst::{FieldValue, Format};
use yule_log::model::msg::UlogMessage;
use yule_log::{ULogData, ULogMessages};

type Failure = Box<dyn std::error::Error>;

fn sum_values(v: &FieldValue) -> f64 {
    use FieldValue::*;
    match v {
        ScalarU8(x) => f64::from(*x),
        ScalarU16(x) => f64::from(*x),
        ScalarU32(x) => f64::from(*x),
        ScalarU64(x) => *x as f64,
        ScalarI8(x) => f64::from(*x),
        ScalarI16(x) => f64::from(*x),
        ScalarI32(x) => f64::from(*x),
        ScalarI64(x) => *x as f64,
        ScalarF32(x) => f64::from(*x),
        ScalarF64(x) => *x,
        ScalarBool(x) => f64::from(u8::from(*x)),
        ScalarChar(c) => f64::from(c.as_u8()),
        ScalarOther(f) => sum_format(f),
        ArrayU8(v) => v.iter().map(|x| f64::from(*x)).sum(),
        ArrayU16(v) => v.iter().map(|x| f64::from(*x)).sum(),
        ArrayU32(v) => v.iter().map(|x| f64::from(*x)).sum(),
        ArrayU64(v) => v.iter().map(|x| *x as f64).sum(),
        ArrayI8(v) => v.iter().map(|x| f64::from(*x)).sum(),
        ArrayI16(v) => v.iter().map(|x| f64::from(*x)).sum(),
        ArrayI32(v) => v.iter().map(|x| f64::from(*x)).sum(),
        ArrayI64(v) => v.iter().map(|x| *x as f64).sum(),
        ArrayF32(v) => v.iter().map(|x| f64::from(*x)).sum(),
        ArrayF64(v) => v.iter().sum(),
        ArrayBool(v) => v.iter().map(|x| f64::from(u8::from(*x))).sum(),
        ArrayChar(v) => v.len() as f64,
        ArrayOther(v) => v.iter().map(sum_format).sum(),
    }
}

fn sum_format(f: &Format) -> f64 {
    f.fields.iter().map(|field| sum_values(&field.value)).sum()
}

fn yule_raw(path: &str) -> Result<(), Failure> {
    let reader = BufReader::new(File::open(path)?);
    let parser = ULogParserBuilder::new(reader).build()?;
    let mut messages = 0u64;
    let mut sum = 0.0;
    for m in parser {
        messages += 1;
        if let UlogMessage::LoggedData(d) = m? {
            sum += d.timestamp as f64 + sum_format(&d.data);
        }
    }
    println!("messages={messages} check={sum}");
    Ok(())
}

#[derive(ULogData)]
pub struct SensorCombined {
    pub timestamp: u64,
    pub gyro_rad: Vec<f32>,
    pub accelerometer_m_s2: Vec<f32>,
}

#[derive(ULogData)]
pub struct VehicleAttitude {
    pub timestamp: u64,
    pub q: Vec<f32>,
}

#[derive(ULogMessages)]
pub enum TwoTopics {
    SensorCombined(SensorCombined),
    VehicleAttitude(VehicleAttitude),
}

fn yule_derive(path: &str) -> Result<(), Failure> {
    let reader = BufReader::new(File::open(path)?);
    let mut rows = 0u64;
    let mut sum = 0.0;
    for m in TwoTopics::stream(reader)? {
        rows += 1;
        match m? {
            TwoTopics::SensorCombined(s) => {
                sum += s.timestamp as f64;
                sum += s
                    .gyro_rad
                    .iter()
                    .chain(&s.accelerometer_m_s2)
                    .map(|v| f64::from(*v))
                    .sum::<f64>();
            }
            TwoTopics::VehicleAttitude(a) => {
                sum += a.timestamp as f64 + a.q.iter().map(|v| f64::from(*v)).sum::<f64>();
            }
        }
    }
    println!("messages={rows} check={sum}");
    Ok(())
}

fn le<const N: usize>(b: &[u8]) -> [u8; N] {
    let mut a = [0u8; N];
    a.copy_from_slice(&b[..N]);
    a
}

/// A flattened field of a data message as `f64` (offsets count from the start of
/// `data`, the msg_id included).
#[inline]
fn px4_value(f: &FlattenedField, data: &[u8]) -> f64 {
    let b = &data[f.offset as usize..];
    match f.field_type {
        FlattenedFieldType::Int8 => f64::from(b[0] as i8),
        FlattenedFieldType::UInt8 => f64::from(b[0]),
        FlattenedFieldType::Int16 => f64::from(i16::from_le_bytes(le(b))),
        FlattenedFieldType::UInt16 => f64::from(u16::from_le_bytes(le(b))),
        FlattenedFieldType::Int32 => f64::from(i32::from_le_bytes(le(b))),
        FlattenedFieldType::UInt32 => f64::from(u32::from_le_bytes(le(b))),
        FlattenedFieldType::Int64 => i64::from_le_bytes(le(b)) as f64,
        FlattenedFieldType::UInt64 => u64::from_le_bytes(le(b)) as f64,
        FlattenedFieldType::Float => f64::from(f32::from_le_bytes(le(b))),
        FlattenedFieldType::Double => f64::from_le_bytes(le(b)),
        FlattenedFieldType::Bool => f64::from(u8::from(b[0] != 0)),
        FlattenedFieldType::Char => f64::from(b[0]),
    }
}

fn px4_stream(path: &str) -> Result<(), Failure> {
    let mut messages = 0u64;
    // Eight partial sums, a field to each in turn across messages, so that the adds
    // do not wait on each other (as `ours decode-*` sums). Of the loops tried (one
    // sum; four per message in fixed lanes; four or eight, a field to each in turn),
    // these are the fastest for px4-ulog; four and eight measure the same.
    let mut acc = [0.0f64; 8];
    let mut k = 0usize;
    read_file_with_simple_callback(path, &mut |m| {
        messages += 1;
        if let Message::Data(d) = m {
            for f in &d.flattened_format.fields {
                k += 1;
                acc[k & 7] += px4_value(f, d.data);
            }
        }
        SimpleCallbackResult::KeepReading
    })?;
    let sum = ((acc[0] + acc[1]) + (acc[2] + acc[3])) + ((acc[4] + acc[5]) + (acc[6] + acc[7]));
    println!("messages={messages} check={sum}");
    Ok(())
}

fn px4_full(path: &str) -> Result<(), Failure> {
    let parsed = px4_ulog::full_parser::read_file(path)?;
    let mut values = 0usize;
    for instances in parsed.messages.values() {
        for fields in instances.values() {
            for v in fields.values() {
                values += match v {
                    SomeVec::Int8(v) => v.len(),
                    SomeVec::UInt8(v) => v.len(),
                    SomeVec::Int16(v) => v.len(),
                    SomeVec::UInt16(v) => v.len(),
                    SomeVec::Int32(v) => v.len(),
                    SomeVec::UInt32(v) => v.len(),
                    SomeVec::Int64(v) => v.len(),
                    SomeVec::UInt64(v) => v.len(),
                    SomeVec::Float(v) => v.len(),
                    SomeVec::Double(v) => v.len(),
                    SomeVec::Bool(v) => v.len(),
                    SomeVec::Char(v) => v.len(),
                };
            }
        }
    }
    println!("values={values} topics={}", parsed.messages.len());
    Ok(())
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let a: Vec<&str> = args.iter().map(String::as_str).collect();
    let result = match a.as_slice() {
        ["yule-raw", f] => yule_raw(f),
        ["yule-derive", f] => yule_derive(f),
        ["px4-stream", f] => px4_stream(f),
        ["px4-full", f] => px4_full(f),
        _ => {
            eprintln!("usage: peers (yule-raw|yule-derive|px4-stream|px4-full) FILE");
            return ExitCode::from(2);
        }
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("peers: {e}");
            ExitCode::FAILURE
        }
    }
}
