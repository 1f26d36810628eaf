//! The px4-ulog workloads, compiled twice: by `peers` against the crates.io release and
//! by `px4-master` (bench/px4-master) against the master snapshot in the peers folder,
//! so that both run the same code.

use px4_ulog::full_parser::SomeVec;
use px4_ulog::stream_parser::model::{FlattenedField, FlattenedFieldType};
// `file_reader::SimpleCallbackResult`: the master snapshot does not re-export it.
use px4_ulog::stream_parser::file_reader::SimpleCallbackResult;
use px4_ulog::stream_parser::{read_file_with_simple_callback, Message};

type Failure = Box<dyn std::error::Error>;

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

pub fn stream(path: &str) -> Result<(), Failure> {
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

pub fn full(path: &str) -> Result<(), Failure> {
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

/// Framing: `LogParser::consume_bytes` over the file in the 1 MiB reads its own
/// `read_file_with_simple_callback` makes, only the data-message callback set (it
/// counts), so that definitions are parsed and every message is framed, nothing decoded.
#[allow(dead_code)] // used by px4-master only
pub fn framing(path: &str) -> Result<(), Failure> {
    use std::io::Read;
    let mut data = 0u64;
    let mut count = |_: &px4_ulog::stream_parser::model::DataMessage| data += 1;
    let mut parser = px4_ulog::stream_parser::LogParser::default();
    parser.set_data_message_callback(&mut count);
    let mut file = std::fs::File::open(path)?;
    let mut buf = vec![0u8; 1024 * 1024];
    loop {
        let n = file.read(&mut buf)?;
        if n == 0 {
            break;
        }
        parser
            .consume_bytes(&buf[..n])
            .map_err(|e| format!("px4-ulog: {e:?}"))?;
    }
    drop(parser);
    println!("messages={data}");
    Ok(())
}
