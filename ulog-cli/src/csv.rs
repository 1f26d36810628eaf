//! `ulog csv`: one CSV file per topic instance, as pyulog's `ulog2csv` writes them.

use std::fs::File;
use std::io::{self, Write};
use std::num::NonZeroUsize;
use std::path::{Path, PathBuf};

use ulog_core::format::{BasicType, LayoutField, LayoutType};
use ulog_core::read::UtcTime;
use ulog_core::{LookupError, Topic};

use crate::failure::{io_text, stdout_err, Failure};
use crate::input;
use crate::progress::Progress;
use crate::pyfmt::{format_i64, format_numpy_f32, format_numpy_f64, format_u64, NUM_LEN};

/// Write every topic instance with data to `<file stem>_<topic>_<multi_id>.csv`,
/// exactly as pyulog's `ulog2csv` does (a topic name that a file system refuses or
/// folds, such as `a/b`, `CON`, or `Foo` beside `foo`, is written as `a_b~` and a hash
/// of the name: `ulog_core::naming`): `timestamp`
/// first, then the fields in format order; arrays as `a[i]`, nested fields as `a.b` and
/// `a[i].b`; `char[N]` as one text column (bytes up to the first NUL, one character per
/// byte); the topic's own padding left out, that of nested types kept
/// (`esc[0]._padding0[3]`, as ulog2csv writes it); booleans as their raw byte (as a
/// signed int8, like pyulog); floats in numpy's shortest form.
///
/// Differences from ulog2csv: data messages that this reader recovers after corruption
/// (pyulog resynchronises later) are written; an unknown topic in `-m` is an error; the
/// file stem drops `.ulog` as it drops `.ulg` (ulog2csv keeps `.ulog`).
/// Several files are written at the same time (`-j`); the `Writing` lines all come
/// first, in name order.
#[derive(Debug, clap::Args)]
#[command(
    about = "One CSV file per topic instance, as pyulog's ulog2csv writes them",
    long_about
)]
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
    /// ulog2csv: rows are a range from that row on, not a filter; 0 means from the
    /// start). ulog2csv's `-ts` is taken too.
    #[arg(long = "time-start", visible_alias = "time_s", value_name = "S")]
    time_start: Option<f64>,
    /// Stop before the first row whose timestamp is at or after this many seconds (0 or
    /// absent: to the end). ulog2csv's `-te` is taken too.
    #[arg(long = "time-end", visible_alias = "time_e", value_name = "S")]
    time_end: Option<f64>,
    /// Add a column `timestamp_utc` after `timestamp`: the row's time in UTC (RFC 3339
    /// with microseconds), from the log's GPS time or its `boot_time_utc_us` (`ulog
    /// info` says which; a log with neither is an error).
    #[arg(long)]
    utc: bool,
    /// Files written at the same time (default: the number of CPUs).
    #[arg(short = 'j', long = "jobs", value_name = "N")]
    jobs: Option<NonZeroUsize>,
    #[arg(short = 'i', long, help = crate::pyulog::IGNORE_HELP)]
    ignore: bool,
}

pub fn run(args: &Args) -> Result<(), Failure> {
    let name = args.file.display().to_string();
    let file = input::open(&args.file)?;
    let threads = input::threads(args.jobs);
    let log = input::parse(&name, file.bytes())?;
    let utc = input::utc_clock(&name, &log, args.utc)?.map(|c| c.boot_us());

    let mut topics: Vec<Topic<'_, '_>> = log.topics().filter(|t| !t.is_empty()).collect();
    if let Some(list) = &args.messages {
        let wanted = input::topic_list(&name, &log, list)?;
        topics.retain(|t| wanted.contains(&t.name()));
    }
    topics.sort_by(|a, b| (a.name(), a.multi_id()).cmp(&(b.name(), b.multi_id())));

    // The files to write, announced in name order before any is written.
    let prefix = output_prefix(&name, args.output.as_deref())?;
    let stdout = io::stdout();
    let mut out = stdout.lock();
    let mut jobs = Vec::with_capacity(topics.len());
    // pyulog's names, but for topic names that a file system refuses or folds.
    let names = ulog_core::naming::LogNames::new(topics.iter().map(|t| t.name()));
    for topic in topics {
        let path = format!(
            "{prefix}_{}_{}.csv",
            names.file_part(topic.name()),
            topic.multi_id()
        );
        let columns = match columns(&topic, utc) {
            Ok(c) => c,
            Err(e) => {
                out.flush().map_err(stdout_err)?;
                let _ = writeln!(
                    io::stderr(),
                    "ulog: {name}: topic `{}` ({}) cannot be decoded, skipped: {}",
                    topic.name(),
                    topic.multi_id(),
                    e
                );
                continue;
            }
        };
        writeln!(out, "Writing {path} ({} data points)", topic.len()).map_err(stdout_err)?;
        jobs.push(Job {
            topic,
            columns,
            path,
        });
    }
    out.flush().map_err(stdout_err)?;
    drop(out);

    let range = TimeRange {
        start: args.time_start,
        end: args.time_end,
    };
    let rows: usize = jobs.iter().map(|j| j.topic.len()).sum();
    let progress = Progress::new(rows as u64, "csv rows");
    // The largest topics first, so that the threads end together.
    let costs: Vec<u64> = jobs.iter().map(|j| j.cost() as u64).collect();
    let written = ulog_core::parallel::largest_first(&costs, threads, |i| {
        thread_local!(static BUF: std::cell::RefCell<Vec<u8>> = const { std::cell::RefCell::new(Vec::new()) });
        let job = &jobs[i];
        progress.message(job.topic.name().to_owned());
        BUF.with_borrow_mut(|buf| {
            write_topic(job, args.delimiter.as_bytes(), range, buf, &progress)
                .map_err(|e| Failure::unreadable(&job.path, io_text(&e)))
        })
    });
    drop(progress);
    // The error of the first file in name order, as when they are written one by one.
    match written.into_iter().flatten().find_map(Result::err) {
        Some(failure) => Err(failure),
        None => Ok(()),
    }
}

/// One CSV file to write.
struct Job<'l, 'a> {
    topic: Topic<'l, 'a>,
    columns: Vec<Column>,
    path: String,
}

impl Job<'_, '_> {
    /// A measure of the work: the number of values to print.
    fn cost(&self) -> usize {
        self.topic.len() * (self.columns.len() + 1)
    }
}

/// The path prefix of the output files: FILE without `.ulg` or `.ulog` (any case), in
/// DIR when given (DIR is created when missing).
fn output_prefix(name: &str, dir: Option<&Path>) -> Result<String, Failure> {
    let stem = input::strip_log_extension(name).unwrap_or(name);
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

/// How one column is printed: the offset of its value in the payload and its type.
#[derive(Debug, Clone, Copy)]
enum Cell {
    U8(usize),
    U16(usize),
    U32(usize),
    U64(usize),
    /// `int8`, and `bool` and a single `char`: pyulog keeps both as `int8`.
    I8(usize),
    I16(usize),
    I32(usize),
    I64(usize),
    F32(usize),
    F64(usize),
    /// `char[n]`: the bytes up to the first NUL.
    Text(usize, usize),
    /// The UTC time of the `uint64_t` timestamp at the offset, with the UTC time at
    /// boot in microseconds.
    Utc(usize, i64),
}

impl Cell {
    /// The most bytes a value of this column takes in a row buffer: the window a
    /// number is formatted into, or a text of `n` bytes as UTF-8.
    fn room(self) -> usize {
        match self {
            Cell::Text(_, n) => NUM_LEN.max(2 * n),
            _ => NUM_LEN,
        }
    }
}

struct Column {
    name: String,
    cell: Cell,
}

/// The columns of `topic`, with `timestamp_utc` after `timestamp` when the UTC time at
/// boot is given (and the timestamp is a `uint64_t`: version 0's narrow ones wrap).
fn columns(topic: &Topic<'_, '_>, utc: Option<i64>) -> Result<Vec<Column>, LookupError> {
    let mut values = Vec::new();
    pyulog_fields(topic.layout()?.fields(), "", 0, &mut values);
    // ulog2csv's columns: `_padding` fields left out (only the topic's own can be
    // named so: nested ones are `a._padding0[0]`, and stay), a `char` array as one
    // text column named without the index, at the place of its first element.
    let mut cols: Vec<Column> = Vec::with_capacity(values.len());
    let mut strings: Vec<(String, usize)> = Vec::new();
    for (name, ty, off) in values {
        if name.starts_with("_padding") {
            continue;
        }
        if ty == BasicType::Char {
            if let Some((field, index)) = array_element(&name) {
                match strings.iter().position(|(f, _)| f == field) {
                    Some(i) => {
                        let col = strings[i].1;
                        if let Cell::Text(start, n) = &mut cols[col].cell {
                            *n = (*n).max(off + 1 - *start);
                        }
                    }
                    None => {
                        strings.push((field.to_owned(), cols.len()));
                        cols.push(Column {
                            name: field.to_owned(),
                            cell: Cell::Text(off, index + 1),
                        });
                    }
                }
                continue;
            }
        }
        let cell = match ty {
            BasicType::Float => Cell::F32(off),
            BasicType::Double => Cell::F64(off),
            BasicType::Bool | BasicType::Char | BasicType::Int8 => Cell::I8(off),
            BasicType::Int16 => Cell::I16(off),
            BasicType::Int32 => Cell::I32(off),
            BasicType::Int64 => Cell::I64(off),
            BasicType::UInt8 => Cell::U8(off),
            BasicType::UInt16 => Cell::U16(off),
            BasicType::UInt32 => Cell::U32(off),
            BasicType::UInt64 => Cell::U64(off),
        };
        cols.push(Column { name, cell });
    }
    // ulog2csv moves `timestamp` to the front, whatever its place in the format.
    if let Some(i) = cols.iter().position(|c| c.name == "timestamp") {
        let ts = cols.remove(i);
        cols.insert(0, ts);
    }
    if let (Some(boot), Some(Cell::U64(off))) = (utc, cols.first().map(|c| c.cell)) {
        if cols[0].name == "timestamp" {
            cols.insert(
                1,
                Column {
                    name: "timestamp_utc".to_owned(),
                    cell: Cell::Utc(off, boot),
                },
            );
        }
    }
    Ok(cols)
}

/// pyulog's flattened fields of a format (its `field_data`): every value with its path,
/// type and offset, array elements one by one (`a[2]`, `a[2].b`), nested types'
/// padding included (`esc[0]._padding0[3]`). The topic's own padding is not listed:
/// ulog2csv leaves it out.
fn pyulog_fields(
    fields: &[LayoutField],
    prefix: &str,
    base: usize,
    out: &mut Vec<(String, BasicType, usize)>,
) {
    for f in fields {
        if prefix.is_empty() && f.is_padding() {
            continue;
        }
        let path = format!("{prefix}{}", f.name);
        let off = base + f.offset;
        match (&f.ty, f.array_len) {
            (LayoutType::Basic(b), Some(n)) => {
                out.extend((0..n).map(|i| (format!("{path}[{i}]"), *b, off + i * b.size())));
            }
            (LayoutType::Basic(b), None) => out.push((path, *b, off)),
            (LayoutType::Nested(inner), Some(n)) => {
                for i in 0..n {
                    let p = format!("{path}[{i}].");
                    pyulog_fields(inner.fields(), &p, off + i * inner.size(), out);
                }
            }
            (LayoutType::Nested(inner), None) => {
                pyulog_fields(inner.fields(), &format!("{path}."), off, out);
            }
        }
    }
}

/// `(a[1].s, 3)` for `a[1].s[3]`: the name and index of an array element, as
/// ulog2csv's `(.*)\[(.*?)\]` reads them.
fn array_element(name: &str) -> Option<(&str, usize)> {
    let body = name.strip_suffix(']')?;
    let open = body.rfind('[')?;
    Some((&body[..open], body[open + 1..].parse().ok()?))
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

/// The size of a worker's row buffer (at least; a few rows of the widest topic).
const BUF_LEN: usize = 1 << 20;

/// How many rows ahead the payloads are prefetched.
const AHEAD: usize = 16;

/// Writes the CSV file of `job`, formatting the rows in place in `buf` (a worker's
/// buffer, reused from topic to topic).
fn write_topic(
    job: &Job<'_, '_>,
    delim: &[u8],
    range: TimeRange,
    buf: &mut Vec<u8>,
    progress: &Progress,
) -> io::Result<()> {
    let columns = &job.columns[..];
    let topic = &job.topic;
    let mut file = File::create(&job.path)?;
    let mut header = Vec::new();
    for (i, c) in columns.iter().enumerate() {
        if i > 0 {
            header.extend_from_slice(delim);
        }
        header.extend_from_slice(c.name.as_bytes());
    }
    header.push(b'\n');
    file.write_all(&header)?;

    let rows = if range.start.is_some() || range.end.is_some() {
        let ts: Vec<u64> = match columns.first().filter(|c| c.name == "timestamp") {
            Some(c) => topic.payloads().map(|p| unsigned(c.cell, p)).collect(),
            None => vec![0; topic.len()],
        };
        range.rows(&ts)
    } else {
        0..topic.len()
    };

    // Every column has its room in a row, so a row started at or below `limit` fits.
    let row_room: usize = columns
        .iter()
        .map(|c| c.cell.room() + delim.len())
        .sum::<usize>()
        + 1;
    if buf.len() < BUF_LEN.max(4 * row_room) {
        buf.resize(BUF_LEN.max(4 * row_room), 0);
    }
    let limit = buf.len() - row_room;
    let mut pos = 0;
    let mut last = vec![Last::NONE; columns.len()];
    let mut pending = 0;
    // The messages of a topic are scattered over the file: each row would wait for
    // memory (and an address translation) if it were not fetched early.
    for p in topic.payloads_in(rows.clone()).prefetch(AHEAD) {
        if pos > limit {
            file.write_all(&buf[..pos])?;
            pos = 0;
            last.fill(Last::NONE);
            progress.inc(pending);
            pending = 0;
        }
        pos = write_row(buf, pos, p, columns, &mut last, delim);
        pending += 1;
    }
    file.write_all(&buf[..pos])?;
    progress.inc(pending + (topic.len() - rows.len()) as u64);
    Ok(())
}

/// The float last printed in a column and where: when the next row holds the same bits
/// (sensor topics repeat many values: setpoints, covariances, unused fields), its text
/// is copied instead of formatted again.
#[derive(Debug, Clone, Copy)]
struct Last {
    bits: u64,
    /// Where the text starts in the row buffer, `usize::MAX` for none.
    at: usize,
    len: usize,
}

impl Last {
    const NONE: Last = Last {
        bits: 0,
        at: usize::MAX,
        len: 0,
    };
}

/// Formats one row at `buf[pos..]`, which has room for it; returns the end of the row.
#[inline]
fn write_row(
    buf: &mut [u8],
    mut pos: usize,
    p: &[u8],
    columns: &[Column],
    last: &mut [Last],
    delim: &[u8],
) -> usize {
    for (c, last) in columns.iter().zip(last) {
        pos = write_cell(buf, pos, c.cell, p, last);
        if let [d] = delim {
            buf[pos] = *d;
            pos += 1;
        } else {
            buf[pos..pos + delim.len()].copy_from_slice(delim);
            pos += delim.len();
        }
    }
    if !columns.is_empty() {
        // The last delimiter becomes the end of the line.
        pos -= delim.len();
    }
    buf[pos] = b'\n';
    pos + 1
}

/// The `N` bytes at `off` of a payload.
#[inline]
fn le<const N: usize>(p: &[u8], off: usize) -> Option<[u8; N]> {
    p.get(off..)?.first_chunk().copied()
}

/// The value of an unsigned column (the timestamp), 0 for other columns.
fn unsigned(cell: Cell, p: &[u8]) -> u64 {
    match cell {
        Cell::U8(off) => p.get(off).map_or(0, |&b| u64::from(b)),
        Cell::U16(off) => le(p, off).map_or(0, |b| u64::from(u16::from_le_bytes(b))),
        Cell::U32(off) => le(p, off).map_or(0, |b| u64::from(u32::from_le_bytes(b))),
        Cell::U64(off) => le(p, off).map_or(0, u64::from_le_bytes),
        _ => 0,
    }
}

/// The window of `buf` a number is formatted into.
#[inline]
fn window(buf: &mut [u8], pos: usize) -> &mut [u8; NUM_LEN] {
    buf[pos..]
        .first_chunk_mut()
        .expect("a row has room for a number in each column")
}

/// Formats a float (its `bits`) at `buf[pos..]` with `format`, or copies its text from
/// the previous row of the column when that held the same bits; returns its length.
#[inline]
fn write_float(
    buf: &mut [u8],
    pos: usize,
    bits: u64,
    last: &mut Last,
    format: impl FnOnce(&mut [u8; NUM_LEN]) -> usize,
) -> usize {
    let len = if last.bits == bits && last.at != usize::MAX {
        // A fixed-size copy (two vector moves), not a call to `memmove`: repeated
        // values are most of the cells of many topics.
        let text: [u8; NUM_LEN] = *window(buf, last.at);
        *window(buf, pos) = text;
        last.len
    } else {
        last.bits = bits;
        format(window(buf, pos))
    };
    last.at = pos;
    last.len = len;
    len
}

/// Formats one value at `buf[pos..]` (which has the column's room); returns its end.
/// Nothing is written when the payload is too short for the value (which the reader
/// does not let happen: such messages are skipped).
#[inline]
fn write_cell(buf: &mut [u8], pos: usize, cell: Cell, p: &[u8], last: &mut Last) -> usize {
    let n = match cell {
        Cell::F32(off) => le(p, off).map_or(0, |b| {
            let v = f32::from_le_bytes(b);
            write_float(buf, pos, v.to_bits().into(), last, |out| {
                format_numpy_f32(v, out)
            })
        }),
        Cell::F64(off) => le(p, off).map_or(0, |b| {
            let v = f64::from_le_bytes(b);
            write_float(buf, pos, v.to_bits(), last, |out| format_numpy_f64(v, out))
        }),
        Cell::U8(off) => p
            .get(off)
            .map_or(0, |&b| format_u64(b.into(), window(buf, pos))),
        Cell::U16(off) => le(p, off).map_or(0, |b| {
            format_u64(u16::from_le_bytes(b).into(), window(buf, pos))
        }),
        Cell::U32(off) => le(p, off).map_or(0, |b| {
            format_u64(u32::from_le_bytes(b).into(), window(buf, pos))
        }),
        Cell::U64(off) => {
            le(p, off).map_or(0, |b| format_u64(u64::from_le_bytes(b), window(buf, pos)))
        }
        Cell::I8(off) => p
            .get(off)
            .map_or(0, |&b| format_i64((b as i8).into(), window(buf, pos))),
        Cell::I16(off) => le(p, off).map_or(0, |b| {
            format_i64(i16::from_le_bytes(b).into(), window(buf, pos))
        }),
        Cell::I32(off) => le(p, off).map_or(0, |b| {
            format_i64(i32::from_le_bytes(b).into(), window(buf, pos))
        }),
        Cell::I64(off) => {
            le(p, off).map_or(0, |b| format_i64(i64::from_le_bytes(b), window(buf, pos)))
        }
        Cell::Text(off, n) => {
            let mut end = pos;
            if let Some(text) = p.get(off..off + n) {
                for &c in text.iter().take_while(|&&c| c != 0) {
                    // One character per byte (Latin-1), written as UTF-8.
                    if c < 0x80 {
                        buf[end] = c;
                        end += 1;
                    } else {
                        buf[end] = 0xc0 | (c >> 6);
                        buf[end + 1] = 0x80 | (c & 0x3f);
                        end += 2;
                    }
                }
            }
            return end;
        }
        Cell::Utc(off, boot) => le(p, off).map_or(0, |b| {
            let t = u64::from_le_bytes(b).min(i64::MAX as u64) as i64;
            let mut out: &mut [u8] = window(buf, pos);
            let room = out.len();
            // 27 bytes for years 0 to 9999, at most 30 for any i64: within the 32 of
            // the window.
            let _ = write!(out, "{}", UtcTime(boot.saturating_add(t)));
            room - out.len()
        }),
    };
    pos + n
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
    fn prefix_strips_the_log_extension() {
        assert_eq!(output_prefix("a/b.ULG", None).unwrap(), "a/b");
        assert_eq!(output_prefix("a/b.ulog", None).unwrap(), "a/b");
        assert_eq!(output_prefix("a/b.txt", None).unwrap(), "a/b.txt");
    }
}
