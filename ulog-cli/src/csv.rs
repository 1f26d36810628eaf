//! `ulog csv`: one CSV file per topic instance, as pyulog's `ulog2csv` writes them.

use std::fs::File;
use std::io::{self, Write};
use std::path::{Path, PathBuf};

use ulog_core::format::BasicType;
use ulog_core::{FieldShape, Topic};

use crate::failure::{io_text, stdout_err, Failure};
use crate::input;
use crate::progress::Progress;
use crate::pyfmt::{write_i64, write_numpy_f32, write_numpy_f64, write_u64};

/// Write every topic instance with data to `<file stem>_<topic>_<multi_id>.csv`
/// (`/` in a topic name becomes `_`), exactly as pyulog's `ulog2csv` does: `timestamp`
/// first, then the fields in format order; arrays as `a[i]`, nested fields as `a.b` and
/// `a[i].b`; `char[N]` as one text column (bytes up to the first NUL, one character per
/// byte); padding left out, nested padding too; booleans as their raw byte (as a signed
/// int8, like pyulog); floats in numpy's shortest form.
///
/// Differences from ulog2csv: data messages that this reader recovers after corruption
/// (pyulog resynchronises later) are written; an unknown topic in `-m` is an error.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The ULog file.
    file: PathBuf,
    /// Only these topics (comma-separated names, e.g. `sensor_combined,vehicle_gps_position`).
    #[arg(short = 'm', long = "messages", value_name = "TOPICS")]
    messages: Option<String>,
    /// Output directory (created if missing; default: the directory of FILE).
    #[arg(short = 'o', long = "output", value_name = "DIR")]
    output: Option<PathBuf>,
    /// Field delimiter.
    #[arg(
        short = 'd',
        long = "delimiter",
        default_value = ",",
        value_name = "DELIM"
    )]
    delimiter: String,
    /// Start at the first row whose timestamp is at or after this many seconds (as
    /// ulog2csv: rows are a range from that row on, not a filter; 0 means from the start).
    #[arg(long = "time-start", visible_alias = "time_s", value_name = "S")]
    time_start: Option<f64>,
    /// Stop before the first row whose timestamp is at or after this many seconds (0 or
    /// absent: to the end).
    #[arg(long = "time-end", visible_alias = "time_e", value_name = "S")]
    time_end: Option<f64>,
}

pub fn run(args: &Args) -> Result<(), Failure> {
    let name = args.file.display().to_string();
    let file = input::open(&args.file)?;
    let log = input::parse(&name, file.bytes())?;

    let mut topics: Vec<Topic<'_, '_>> = log.topics().filter(|t| !t.is_empty()).collect();
    if let Some(list) = &args.messages {
        let wanted = input::topic_list(&name, &log, list)?;
        topics.retain(|t| wanted.contains(&t.name()));
    }
    topics.sort_by(|a, b| (a.name(), a.multi_id()).cmp(&(b.name(), b.multi_id())));

    let prefix = output_prefix(&name, args.output.as_deref())?;
    let stdout = io::stdout();
    let mut out = stdout.lock();
    let mut buf = Vec::with_capacity(1 << 17);
    let mut scratch = String::with_capacity(64);
    let range = TimeRange {
        start: args.time_start,
        end: args.time_end,
    };
    let rows: usize = topics.iter().map(|t| t.len()).sum();
    let progress = Progress::new(rows as u64, "csv rows");
    for topic in topics {
        progress.message(topic.name().to_owned());
        let path = format!(
            "{prefix}_{}_{}.csv",
            topic.name().replace('/', "_"),
            topic.multi_id()
        );
        let columns = match columns(&topic) {
            Ok(c) => c,
            Err(e) => {
                let _ = writeln!(
                    io::stderr(),
                    "ulog: {name}: topic `{}` ({}) cannot be decoded, skipped: {}",
                    topic.name(),
                    topic.multi_id(),
                    input::error_text(&e)
                );
                continue;
            }
        };
        writeln!(out, "Writing {path} ({} data points)", topic.len()).map_err(stdout_err)?;
        let mut file = File::create(&path).map_err(|e| Failure::unreadable(&path, io_text(&e)))?;
        write_topic(
            &mut file,
            &topic,
            &columns,
            args.delimiter.as_bytes(),
            range,
            &mut buf,
            &mut scratch,
        )
        .map_err(|e| Failure::unreadable(&path, io_text(&e)))?;
        progress.inc(topic.len() as u64);
    }
    out.flush().map_err(stdout_err)
}

/// The path prefix of the output files: FILE without `.ulg` (any case), in DIR when
/// given (DIR is created when missing).
fn output_prefix(name: &str, dir: Option<&Path>) -> Result<String, Failure> {
    let stem = if name.to_lowercase().ends_with(".ulg") && name.is_char_boundary(name.len() - 4) {
        &name[..name.len() - 4]
    } else {
        name
    };
    let Some(dir) = dir else {
        return Ok(stem.to_owned());
    };
    if !dir.is_dir() {
        writeln!(io::stdout(), "Creating output directory {}", dir.display())
            .map_err(stdout_err)?;
        std::fs::create_dir_all(dir)
            .map_err(|e| Failure::unreadable(dir.display(), io_text(&e)))?;
    }
    let base = Path::new(stem)
        .file_name()
        .map(|s| s.to_string_lossy().into_owned());
    Ok(dir.join(base.unwrap_or_default()).display().to_string())
}

/// How one column is printed.
#[derive(Debug, Clone, Copy)]
enum Cell {
    Unsigned(usize, BasicType),
    Signed(usize, BasicType),
    F32(usize),
    F64(usize),
    /// `bool` and a single `char`: pyulog keeps both as `int8`.
    Int8(usize),
    Text(usize, usize),
}

struct Column {
    name: String,
    cell: Cell,
}

fn columns(topic: &Topic<'_, '_>) -> ulog_core::Result<Vec<Column>> {
    let mut cols: Vec<Column> = topic
        .columns()?
        .into_iter()
        .map(|f| {
            let off = f.offset();
            let cell = match (f.shape(), f.ty()) {
                (FieldShape::String(n), _) => Cell::Text(off, n),
                (_, BasicType::Float) => Cell::F32(off),
                (_, BasicType::Double) => Cell::F64(off),
                (_, BasicType::Bool | BasicType::Char | BasicType::Int8) => Cell::Int8(off),
                (_, t @ (BasicType::Int16 | BasicType::Int32 | BasicType::Int64)) => {
                    Cell::Signed(off, t)
                }
                (_, t) => Cell::Unsigned(off, t),
            };
            Column {
                name: f.path().to_owned(),
                cell,
            }
        })
        .collect();
    // ulog2csv moves `timestamp` to the front, whatever its place in the format.
    if let Some(i) = cols.iter().position(|c| c.name == "timestamp") {
        let ts = cols.remove(i);
        cols.insert(0, ts);
    }
    Ok(cols)
}

#[derive(Debug, Clone, Copy)]
struct TimeRange {
    start: Option<f64>,
    end: Option<f64>,
}

impl TimeRange {
    /// The rows ulog2csv writes: from the first row whose timestamp is at or after the
    /// start, up to (not including) the first row at or after the end. A limit of 0 is
    /// no limit (ulog2csv tests it for truth). Where ulog2csv would fail because no row
    /// reaches a limit, we write no rows (start) or every row to the end (end).
    fn rows(&self, timestamps: &[u64]) -> core::ops::Range<usize> {
        let first_at = |s: f64| {
            let limit = s * 1e6;
            timestamps.iter().position(|&t| t as f64 >= limit)
        };
        let n = timestamps.len();
        let start = match self.start {
            Some(s) if s != 0.0 => first_at(s).unwrap_or(n),
            _ => 0,
        };
        let end = match self.end {
            Some(e) if e != 0.0 => first_at(e).unwrap_or(n),
            _ => n,
        };
        start..end.max(start)
    }
}

fn write_topic(
    file: &mut File,
    topic: &Topic<'_, '_>,
    columns: &[Column],
    delim: &[u8],
    range: TimeRange,
    buf: &mut Vec<u8>,
    scratch: &mut String,
) -> io::Result<()> {
    buf.clear();
    for (i, c) in columns.iter().enumerate() {
        if i > 0 {
            buf.extend_from_slice(delim);
        }
        buf.extend_from_slice(c.name.as_bytes());
    }
    buf.push(b'\n');

    let rows = if range.start.is_some() || range.end.is_some() {
        let ts: Vec<u64> = match columns.first().filter(|c| c.name == "timestamp") {
            Some(c) => topic.payloads().map(|p| raw_unsigned(c.cell, p)).collect(),
            None => vec![0; topic.len()],
        };
        range.rows(&ts)
    } else {
        0..topic.len()
    };
    for payload in topic.payloads().skip(rows.start).take(rows.len()) {
        for (i, c) in columns.iter().enumerate() {
            if i > 0 {
                buf.extend_from_slice(delim);
            }
            write_cell(buf, scratch, c.cell, payload);
        }
        buf.push(b'\n');
        if buf.len() >= 1 << 16 {
            file.write_all(buf)?;
            buf.clear();
        }
    }
    file.write_all(buf)?;
    buf.clear();
    Ok(())
}

fn bytes<const N: usize>(p: &[u8], off: usize) -> Option<[u8; N]> {
    p.get(off..off + N).map(|b| b.try_into().expect("N bytes"))
}

fn raw_unsigned(cell: Cell, p: &[u8]) -> u64 {
    match cell {
        Cell::Unsigned(off, t) => match t {
            BasicType::UInt8 => p.get(off).map_or(0, |&b| u64::from(b)),
            BasicType::UInt16 => bytes(p, off).map_or(0, |b| u64::from(u16::from_le_bytes(b))),
            BasicType::UInt32 => bytes(p, off).map_or(0, |b| u64::from(u32::from_le_bytes(b))),
            _ => bytes(p, off).map_or(0, u64::from_le_bytes),
        },
        _ => 0,
    }
}

/// Appends one value; nothing when the payload is too short for it (which the reader
/// does not let happen: such messages are skipped).
fn write_cell(out: &mut Vec<u8>, scratch: &mut String, cell: Cell, p: &[u8]) {
    match cell {
        Cell::Unsigned(off, t) => {
            if p.len() >= off + t.size() {
                write_u64(out, raw_unsigned(cell, p));
            }
        }
        Cell::Signed(off, t) => {
            let v = match t {
                BasicType::Int16 => bytes(p, off).map(|b| i64::from(i16::from_le_bytes(b))),
                BasicType::Int32 => bytes(p, off).map(|b| i64::from(i32::from_le_bytes(b))),
                _ => bytes(p, off).map(i64::from_le_bytes),
            };
            if let Some(v) = v {
                write_i64(out, v);
            }
        }
        Cell::Int8(off) => {
            if let Some(&b) = p.get(off) {
                write_i64(out, i64::from(b as i8));
            }
        }
        Cell::F32(off) => {
            if let Some(b) = bytes(p, off) {
                write_numpy_f32(out, scratch, f32::from_le_bytes(b));
            }
        }
        Cell::F64(off) => {
            if let Some(b) = bytes(p, off) {
                write_numpy_f64(out, scratch, f64::from_le_bytes(b));
            }
        }
        Cell::Text(off, n) => {
            if let Some(b) = p.get(off..off + n) {
                for &c in b.iter().take_while(|&&c| c != 0) {
                    // One character per byte (Latin-1), written as UTF-8.
                    if c < 0x80 {
                        out.push(c);
                    } else {
                        out.push(0xc0 | (c >> 6));
                        out.push(0x80 | (c & 0x3f));
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn time_range_is_an_index_range_like_ulog2csv() {
        let ts = [1_000_000, 2_000_000, 3_000_000, 1_500_000, 4_000_000];
        let r = |s, e| TimeRange { start: s, end: e }.rows(&ts);
        assert_eq!(r(None, None), 0..5);
        assert_eq!(r(Some(2.0), None), 1..5);
        assert_eq!(r(Some(0.0), Some(0.0)), 0..5);
        assert_eq!(r(None, Some(3.0)), 0..2);
        assert_eq!(r(Some(9.0), None), 5..5);
        assert_eq!(r(None, Some(9.0)), 0..5);
        assert_eq!(r(Some(3.0), Some(2.0)), 2..2);
    }

    #[test]
    fn prefix_strips_ulg_only() {
        assert_eq!(output_prefix("a/b.ULG", None).unwrap(), "a/b");
        assert_eq!(output_prefix("a/b.ulog", None).unwrap(), "a/b.ulog");
    }
}
