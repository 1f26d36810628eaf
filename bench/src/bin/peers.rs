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

use yule_log::builder::ULogParserBuilder;
use yule_log::model::inst::{FieldValue, Format};
use yule_log::model::msg::UlogMessage;
use yule_log::{ULogData, ULogMessages};

#[path = "../px4.rs"]
mod px4;

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

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let a: Vec<&str> = args.iter().map(String::as_str).collect();
    let result = match a.as_slice() {
        ["yule-raw", f] => yule_raw(f),
        ["yule-derive", f] => yule_derive(f),
        ["px4-stream", f] => px4::stream(f),
        ["px4-full", f] => px4::full(f),
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
