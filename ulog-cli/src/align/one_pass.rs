//! `ulog align --one-pass`: the table from one pass over the log in file order
//! (`ulog_core::align::AlignStream`), holding only the rows the methods still need.

use std::io::{BufWriter, Write};

use ulog_core::align::{
    AlignError, AlignOptions, AlignStream, Grid, Selection, StreamError, StreamOptions,
    StreamSummary, Track,
};
use ulog_core::FieldReader;

use super::parquet::{self, Error};
use super::{csv_header, is_parquet, lookup, Args, Cells, Table};
use crate::failure::{io_text, stdout_err, Failure};
use crate::input;
use crate::numfmt::{format_u64, NUM_LEN};

pub(super) fn run(
    args: &Args,
    selected: &[Selection],
    grid_topic: Option<&Selection>,
) -> Result<(), Failure> {
    let name = args.file.display().to_string();
    let about = |e: String| Failure::about(&name, e);
    let failure = |e: StreamError| match e {
        StreamError::Read(e) => input::pass_failure(Some(&args.file), &name, &e),
        StreamError::Align(AlignError::Lookup(e)) => lookup(&name, e),
        StreamError::Align(e) => about(e.to_string()),
        e => about(e.to_string()),
    };

    // One track per topic instance, in the order first named, its selections with it.
    let mut groups: Vec<(Track, Vec<&Selection>)> = Vec::new();
    for s in selected {
        let track = s.track(args.method);
        match groups
            .iter_mut()
            .find(|(t, _)| t.topic == track.topic && t.multi_id == track.multi_id)
        {
            Some((_, g)) => g.push(s),
            None => groups.push((track, vec![s])),
        }
    }
    let grid = match (grid_topic, args.rate) {
        (Some(g), _) => {
            if let Some(field) = &g.field {
                let text = match g.instance {
                    Some(n) => format!("{}:{n}.{field}", g.topic),
                    None => format!("{}.{field}", g.topic),
                };
                return Err(about(AlignError::GridField(text).to_string()));
            }
            Grid::topic(&g.topic, g.instance.unwrap_or(0))
        }
        (None, Some(hz)) => Grid::Rate(hz),
        (None, None) => return Err(about("give `--on TOPIC` or `--rate HZ`".into())),
    };
    if !(args.horizon >= 0.0 && args.horizon.is_finite()) {
        return Err(about(format!(
            "horizon {}: seconds must be 0 or more",
            args.horizon
        )));
    }
    let options = StreamOptions {
        align: AlignOptions::since_start(args.tolerance, args.start, args.end)
            .map_err(|e| about(e.to_string()))?,
        horizon_us: (args.horizon * 1e6).round() as u64,
        window_from_start: true,
    };
    let file = crate::input::reader(&name, &args.file)?;
    let tracks = groups.iter().map(|(t, _)| t.clone()).collect();
    let mut stream =
        AlignStream::new(file, &grid, tracks, options).map_err(|e| about(e.to_string()))?;
    let layouts = stream.layouts().map_err(failure)?;
    let mut tables = Vec::with_capacity(groups.len());
    for ((track, sels), layout) in groups.iter().zip(&layouts) {
        let mut columns: Vec<(String, FieldReader)> = Vec::new();
        for s in sels {
            columns.extend(s.columns(layout).map_err(|e| lookup(&name, e))?);
        }
        tables.push(Table {
            name: track.topic.clone(),
            multi_id: track.multi_id,
            columns,
        });
    }

    match &args.output {
        Some(p) if is_parquet(p) => parquet::write_with(p, &tables, |out| {
            write_parquet(out, &mut stream, tables.len()).map_err(|e| match e {
                Stepped::Stream(e) => Error::Other(failure(e)),
                Stepped::Write(e) => e,
            })
        })?,
        Some(p) => {
            let f = std::fs::File::create(p)
                .map_err(|e| Failure::unreadable(p.display(), io_text(&e)))?;
            write_csv(f, &tables, &mut stream).map_err(|e| match e {
                Stepped::Stream(e) => failure(e),
                Stepped::Write(e) => Failure::unreadable(p.display(), io_text(&e)),
            })?
        }
        None => write_csv(std::io::stdout().lock(), &tables, &mut stream).map_err(|e| match e {
            Stepped::Stream(e) => failure(e),
            Stepped::Write(e) => stdout_err(e),
        })?,
    }
    report(&name, &tables, &stream.summary());
    Ok(())
}

/// What stopped the steps: the log, or the output.
enum Stepped<E> {
    Stream(StreamError),
    Write(E),
}

/// Writes the table as CSV, a line per step as the steps come.
fn write_csv<R: std::io::Read>(
    out: impl Write,
    tables: &[Table],
    stream: &mut AlignStream<R>,
) -> Result<(), Stepped<std::io::Error>> {
    let mut out = BufWriter::with_capacity(1 << 20, out);
    out.write_all(&csv_header(tables)).map_err(Stepped::Write)?;
    let mut line = Vec::new();
    let mut num = [0u8; NUM_LEN];
    let mut cells: Vec<Cells<'_>> = tables.iter().map(Cells::new).collect();
    while let Some(step) = stream.next_step().map_err(Stepped::Stream)? {
        line.clear();
        let n = format_u64(step.time, &mut num);
        line.extend_from_slice(&num[..n]);
        for (cells, row) in cells.iter_mut().zip(&step.rows) {
            cells.write(&mut line, row.as_ref());
        }
        line.push(b'\n');
        out.write_all(&line).map_err(Stepped::Write)?;
    }
    out.flush().map_err(Stepped::Write)
}

/// Writes the table's steps to Parquet, a batch at a time (the rows of a batch are
/// copied: the pass lets go of them as it moves on).
fn write_parquet<R: std::io::Read>(
    out: &mut parquet::TableWriter<'_>,
    stream: &mut AlignStream<R>,
    tables: usize,
) -> Result<(), Stepped<Error>> {
    let batch = out.batch;
    let mut times: Vec<u64> = Vec::with_capacity(batch);
    let mut rows: Vec<Vec<Option<Vec<u8>>>> = vec![Vec::with_capacity(batch); tables];
    let mut flush = |times: &mut Vec<u64>, rows: &mut Vec<Vec<Option<Vec<u8>>>>| {
        let payloads: Vec<Vec<Option<&[u8]>>> = rows
            .iter()
            .map(|c| c.iter().map(|r| r.as_deref()).collect())
            .collect();
        let written = out.write(times, &payloads).map_err(Stepped::Write);
        times.clear();
        rows.iter_mut().for_each(Vec::clear);
        written
    };
    while let Some(step) = stream.next_step().map_err(Stepped::Stream)? {
        times.push(step.time);
        for (column, row) in rows.iter_mut().zip(&step.rows) {
            column.push(row.as_ref().map(|r| r.bytes().to_vec()));
        }
        if times.len() == batch {
            flush(&mut times, &mut rows)?;
        }
    }
    if !times.is_empty() {
        flush(&mut times, &mut rows)?;
    }
    Ok(())
}

/// What the pass met that makes the table differ from the indexed one, on standard
/// error (the table itself is complete).
fn report(name: &str, tables: &[Table], summary: &StreamSummary) {
    let label = |t: &Table| match t.multi_id {
        0 => t.name.clone(),
        n => format!("{}:{n}", t.name),
    };
    for (t, r) in tables.iter().zip(&summary.tracks) {
        if r.late_rows > 0 {
            eprintln!(
                "{name}: note: {} row(s) of {} came after the steps at their time were written (the first at byte {}): those steps do not see them",
                r.late_rows,
                label(t),
                r.first_late_offset.unwrap_or_default()
            );
        }
        if r.early_steps > 0 {
            eprintln!(
                "{name}: note: {} step(s) were decided before {}'s next row came (--horizon): their value is the one after its last row",
                r.early_steps,
                label(t)
            );
        }
    }
    if summary.late_steps > 0 {
        eprintln!(
            "{name}: note: {} row(s) of the steps' topic came after later steps were written (the first at byte {}): left out",
            summary.late_steps,
            summary.first_late_step_offset.unwrap_or_default()
        );
    }
}
