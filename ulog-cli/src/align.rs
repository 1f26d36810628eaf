//! `ulog align`: several topics on one time base, as one CSV or Parquet table.

mod one_pass;
mod parquet;

use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use ulog_core::align::{
    AlignError, AlignOptions, Grid, Method, Row, Rows, SelectedColumns, Selection, SelectionError,
};
use ulog_core::read::FieldShape;
use ulog_core::{FieldReader, LookupError, Value};

use crate::failure::{io_text, stdout_err, Failure};
use crate::input;
use crate::numfmt::{format_i64, format_numpy_f32, format_numpy_f64, format_u64, NUM_LEN};

/// Put fields of several topics on one time base and write them as one table: a
/// `timestamp` column (boot microseconds of each step), then one column per field.
///
/// The steps are the rows of one topic (`--on TOPIC`, its own fields are its rows) or
/// a fixed rate (`--rate HZ`: from the start of the log's span, as `ulog info` says
/// it, every 1/HZ seconds, rounded to the microsecond, up to and including its end).
/// At each step every other topic's value is found by `--method`: `previous` (the last
/// row at or before the step, the last written among equal timestamps: pandas'
/// `merge_asof(direction="backward")`), `nearest` (the earlier on a tie) or `linear`
/// (`float` and `double` fields interpolated between the rows around the step, as
/// `numpy.interp` within the topic's rows; quaternions `q[4]` by slerp; integers,
/// booleans and text from the earlier row). A topic with no value at a step (before
/// its first row, after its last for `linear`, further than `--tolerance`) leaves an
/// empty cell.
///
/// Columns are named `topic.field` as `ulog csv` names its columns
/// (`vehicle_attitude.q[0]`, `esc_status.esc[2].esc_rpm`), `topic:N.field` for
/// instance N ≥ 1. Floats are written with the fewest digits that read back as the
/// same value.
///
/// With `--one-pass` the log is read once in file order, holding only the rows the
/// methods still need (a few seconds of the log; a log larger than memory, or read
/// from a pipe): the same table, except where it says so on standard error (a row
/// written long after its time; a step decided before a topic's next row came, after
/// `--horizon` seconds of waiting). A topic named without an instance is instance 0,
/// `--start`/`--end` count from the start the header gives, and `--rate`'s steps end
/// at the last row of the topics read.
///
/// With `-o OUT.parquet` the table is a Parquet file (zstd, as `ulog parquet` writes
/// by default): `timestamp` a `uint64` with no nulls, every other column of its
/// field's type as `ulog parquet --flatten` types it (`float` a `float32`, `char[N]`
/// text, …), nullable, a null where the CSV cell is empty.
#[derive(Debug, clap::Args)]
#[command(
    about = "Several topics on one time base, as one CSV or Parquet table",
    long_about,
    group(clap::ArgGroup::new("grid").required(true).args(["on", "rate"]))
)]
pub struct Args {
    /// The ULog file.
    file: PathBuf,
    /// What to write: topics (`battery_status`: every field) or fields
    /// (`vehicle_attitude.q[0]`, `esc_status:1.esc[2].esc_rpm`), comma-separated or
    /// as separate arguments.
    #[arg(value_name = "TOPIC[.FIELD]", required = true, value_delimiter = ',')]
    selection: Vec<String>,
    /// Step on the rows of this topic (`TOPIC` or `TOPIC:N`).
    #[arg(long, value_name = "TOPIC")]
    on: Option<String>,
    /// Step at this many steps per second from the log's start.
    #[arg(long, value_name = "HZ")]
    rate: Option<f64>,
    /// How a value at a step is found: previous, nearest or linear.
    #[arg(long, default_value = "previous")]
    method: Method,
    /// Leave a value out when its row is further from the step than this (seconds).
    #[arg(long, value_name = "SECONDS")]
    tolerance: Option<f64>,
    /// Steps from this time since the log's start: seconds, `M:SS` or `H:MM:SS`.
    #[arg(long, value_name = "TIME", value_parser = input::seconds)]
    start: Option<f64>,
    /// Steps before this time since the log's start, written as for `--start`.
    #[arg(long, value_name = "TIME", value_parser = input::seconds)]
    end: Option<f64>,
    /// The table to write: CSV, or Parquet when the name ends in `.parquet`
    /// (default: CSV on standard output).
    #[arg(short = 'o', long = "output", value_name = "OUT.csv|OUT.parquet")]
    output: Option<PathBuf>,
    /// Threads formatting the CSV table (default: the number of CPUs).
    #[arg(short = 'j', long = "jobs", value_name = "N")]
    jobs: Option<std::num::NonZeroUsize>,
    /// Read the log once in file order, holding only the rows the methods still need.
    #[arg(long)]
    one_pass: bool,
    /// With `--one-pass`: how long (seconds of the log) a step waits for a topic's
    /// next row before it is decided without it.
    #[arg(
        long,
        value_name = "SECONDS",
        requires = "one_pass",
        default_value_t = 10.0
    )]
    horizon: f64,
}

pub fn run(args: &Args) -> Result<(), Failure> {
    let name = args.file.display().to_string();
    let about = |e: String| Failure::about(&name, e);
    let selected: Vec<Selection> = args
        .selection
        .iter()
        .map(|s| s.parse())
        .collect::<Result<_, SelectionError>>()
        .map_err(|e| about(e.to_string()))?;
    let grid_topic = args
        .on
        .as_deref()
        .map(str::parse::<Selection>)
        .transpose()
        .map_err(|e| about(e.to_string()))?;

    if args.one_pass {
        return one_pass::run(args, &selected, grid_topic.as_ref());
    }

    // One pass in chunks, keeping the rows of the topics named only.
    let mut names: Vec<&str> = selected.iter().map(|s| s.topic.as_str()).collect();
    names.extend(grid_topic.iter().map(|s| s.topic.as_str()));
    let kept = input::keep(&args.file, &names, input::Times::Every)?;
    let log = kept.log(&name)?;

    let tables = log
        .select_columns(&selected)
        .map_err(|e| lookup(&name, e))?;

    let align_err = |e: AlignError| match e {
        AlignError::Lookup(e) => lookup(&name, e),
        e => about(e.to_string()),
    };
    let options =
        AlignOptions::in_seconds(&log, args.tolerance, args.start, args.end).map_err(align_err)?;
    let grid = match (&grid_topic, args.rate) {
        (Some(g), _) => g.grid(&log).map_err(align_err)?,
        (None, Some(hz)) => Grid::Rate(hz),
        (None, None) => return Err(about("give `--on TOPIC` or `--rate HZ`".into())),
    };
    let steps = log
        .align(&grid, &options)
        .map_err(|e| about(e.to_string()))?;
    let rows: Vec<Rows<'_, '_>> = tables
        .iter()
        .map(|t| steps.rows(t.topic.name(), t.topic.multi_id(), args.method))
        .collect::<Result<_, _>>()
        .map_err(|e| lookup(&name, e))?;

    let tables: Vec<Table> = tables.iter().map(Table::of).collect();
    let threads = input::threads(args.jobs);
    match &args.output {
        Some(p) if is_parquet(p) => parquet::write(p, steps.times(), &tables, rows),
        Some(p) => {
            let f = std::fs::File::create(p)
                .map_err(|e| Failure::unreadable(p.display(), io_text(&e)))?;
            write_csv(f, steps.times(), &tables, &rows, threads)
                .map_err(|e| Failure::unreadable(p.display(), io_text(&e)))
        }
        None => write_csv(
            std::io::stdout().lock(),
            steps.times(),
            &tables,
            &rows,
            threads,
        )
        .map_err(stdout_err),
    }
}

/// Whether `-o` names a Parquet file (`.parquet`, in any case).
fn is_parquet(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("parquet"))
}

/// The columns of one topic instance in the table.
struct Table {
    name: String,
    multi_id: u8,
    columns: Vec<(String, FieldReader)>,
}

impl Table {
    fn of(selected: &SelectedColumns<'_, '_>) -> Table {
        Table {
            name: selected.topic.name().to_owned(),
            multi_id: selected.topic.multi_id(),
            columns: selected.columns.clone(),
        }
    }
}

/// The name of each column after `timestamp`: `topic.field`, `topic:N.field`.
fn column_names(tables: &[Table]) -> Vec<String> {
    let mut names = Vec::new();
    for t in tables {
        let prefix = match t.multi_id {
            0 => t.name.clone(),
            n => format!("{}:{n}", t.name),
        };
        names.extend(t.columns.iter().map(|(path, _)| format!("{prefix}.{path}")));
    }
    names
}

fn lookup(file: &str, e: LookupError) -> Failure {
    match e {
        LookupError::Topic(_) | LookupError::Field { .. } => Failure::unknown_name(file, &e),
        _ => Failure::about(file, &e),
    }
}

/// Bytes of CSV a part of the steps is formatted into, about: the parts are formatted
/// on several threads, a round of parts at a time, and written in order after each
/// round (what is held is one round's text, whatever the number of steps).
const PART_BYTES: usize = 1 << 20;

/// Bytes of CSV a round formats, about (at least a part per thread).
const ROUND_BYTES: usize = 16 << 20;

/// Writes the table as CSV: a header, then a line per step, the lines formatted on
/// `threads` threads.
fn write_csv(
    mut out: impl Write,
    times: &[u64],
    tables: &[Table],
    rows: &[Rows<'_, '_>],
    threads: usize,
) -> std::io::Result<()> {
    out.write_all(&csv_header(tables))?;
    // A step's line takes about 20 bytes a column (a float's shortest digits, often
    // fewer when cells are empty).
    let line = 20 * (1 + tables.iter().map(|t| t.columns.len()).sum::<usize>());
    let part = (PART_BYTES / line).max(64);
    let parts: Vec<core::ops::Range<usize>> = (0..times.len())
        .step_by(part)
        .map(|s| s..(s + part).min(times.len()))
        .collect();
    // The buffers of a round, used again by the next: fresh ones each round cost a
    // page fault for every 4 KiB of the table.
    let spare: Mutex<Vec<Vec<u8>>> = Mutex::new(Vec::new());
    for round in parts.chunks((ROUND_BYTES / PART_BYTES).max(threads)) {
        let done = ulog_core::parallel::largest_first(&vec![1; round.len()], threads, |i| {
            let mut text = spare.lock().map(|mut s| s.pop()).ok().flatten();
            let text = text.get_or_insert_with(|| Vec::with_capacity(PART_BYTES * 5 / 4));
            text.clear();
            csv_lines(text, times, tables, rows, round[i].clone());
            Ok::<_, core::convert::Infallible>(core::mem::take(text))
        });
        for text in done.into_iter().flatten().flatten() {
            out.write_all(&text)?;
            if let Ok(mut s) = spare.lock() {
                s.push(text);
            }
        }
    }
    out.flush()
}

/// The CSV table's first line.
fn csv_header(tables: &[Table]) -> Vec<u8> {
    let mut header: Vec<u8> = b"timestamp".to_vec();
    for name in column_names(tables) {
        header.push(b',');
        header.extend_from_slice(csv_text(&name).as_bytes());
    }
    header.push(b'\n');
    header
}

/// Appends the lines of the steps `range` to `text`.
fn csv_lines(
    text: &mut Vec<u8>,
    times: &[u64],
    tables: &[Table],
    rows: &[Rows<'_, '_>],
    range: core::ops::Range<usize>,
) {
    let mut cells: Vec<Cells<'_>> = tables.iter().map(Cells::new).collect();
    let mut rows: Vec<Rows<'_, '_>> = rows.iter().map(|r| r.from_step(range.start)).collect();
    let mut num = [0u8; NUM_LEN];
    for &t in &times[range] {
        let n = format_u64(t, &mut num);
        text.extend_from_slice(&num[..n]);
        for (cells, rows) in cells.iter_mut().zip(rows.iter_mut()) {
            cells.write(text, rows.next().flatten().as_ref());
        }
        text.push(b'\n');
    }
}

/// The cells of one topic's columns at a step (`,a,b,…`), kept while the step's row
/// holds the same bytes: a topic logged more slowly than the steps has the same row at
/// step after step (`previous`, `nearest`), whose cells are then copied, not formatted
/// again. (The bytes are compared, not the row's address: the one-pass alignment
/// reuses its buffers; cells depend on the bytes only.)
struct Cells<'t> {
    columns: &'t [(String, FieldReader)],
    /// The logged row `text` holds the cells of, when it is one.
    row: Option<Vec<u8>>,
    text: Vec<u8>,
}

impl<'t> Cells<'t> {
    fn new(table: &'t Table) -> Cells<'t> {
        Cells {
            columns: &table.columns,
            row: None,
            text: Vec::new(),
        }
    }

    /// Appends the cells of `row` (empty ones when there is none) to `line`.
    fn write(&mut self, line: &mut Vec<u8>, row: Option<&Row<'_>>) {
        match row {
            None => line.resize(line.len() + self.columns.len(), b','),
            Some(Row::Logged(p)) if self.row.as_deref() == Some(*p) => {
                line.extend_from_slice(&self.text);
            }
            Some(row) => {
                self.text.clear();
                row_cells(&mut self.text, self.columns, Some(row));
                match row {
                    Row::Logged(p) => {
                        let kept = self.row.get_or_insert_with(Vec::new);
                        kept.clear();
                        kept.extend_from_slice(p);
                    }
                    Row::Between { .. } => self.row = None,
                }
                line.extend_from_slice(&self.text);
            }
        }
    }
}

/// Appends the cells of `columns` in `row` (`,a,b,…`; empty ones when there is none)
/// to `line`.
fn row_cells(line: &mut Vec<u8>, columns: &[(String, FieldReader)], row: Option<&Row<'_>>) {
    match row {
        None => line.resize(line.len() + columns.len(), b','),
        Some(row) => {
            for (_, reader) in columns {
                line.push(b',');
                write_value(line, reader, row);
            }
        }
    }
}

/// The cell of `reader` in `row`: floats and doubles from the (interpolated) bytes,
/// the rest from the logged row; nothing when the row is too short for it.
fn write_value(line: &mut Vec<u8>, reader: &FieldReader, row: &Row<'_>) {
    let value = match reader.shape() {
        FieldShape::String(_) => reader.read(row.earlier()),
        _ => reader.read(row.bytes()),
    };
    let Some(value) = value else { return };
    let mut num = [0u8; NUM_LEN];
    let n = match value {
        Value::F32(v) => format_numpy_f32(v, &mut num),
        Value::F64(v) => format_numpy_f64(v, &mut num),
        Value::U8(v) => format_u64(v.into(), &mut num),
        Value::U16(v) => format_u64(v.into(), &mut num),
        Value::U32(v) => format_u64(v.into(), &mut num),
        Value::U64(v) => format_u64(v, &mut num),
        Value::I8(v) => format_i64(v.into(), &mut num),
        Value::I16(v) => format_i64(v.into(), &mut num),
        Value::I32(v) => format_i64(v.into(), &mut num),
        Value::I64(v) => format_i64(v, &mut num),
        Value::Bool(b) => {
            line.push(if b { b'1' } else { b'0' });
            return;
        }
        Value::Str(s) => {
            line.extend_from_slice(csv_text(&s.to_string()).as_bytes());
            return;
        }
        other => {
            line.extend_from_slice(other.to_string().as_bytes());
            return;
        }
    };
    line.extend_from_slice(&num[..n]);
}

/// `s` as a CSV field: quoted when it holds a comma, a quote or a line break.
fn csv_text(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_owned()
    }
}
