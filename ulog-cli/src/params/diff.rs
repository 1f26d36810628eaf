//! `ulog params --diff B.ulg [C.ulg …]` and `--diff-defaults [KIND]`: the parameters
//! that differ across two or more logs, or from a log's defaults, as a table, csv or
//! JSON. The comparing
//! is the library's (`ulog_core::read::diff_params` and `diff_from_defaults`, over
//! `ULog::params_at_end`, or `params_at_start` with `--initial`); this prints.

use std::collections::BTreeMap;
use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::PathBuf;

use serde_json::Value as Json;
use ulog_core::read::{self, ParamDiff};
use ulog_core::{ULog, Value};

use super::{no_defaults, Args, DefaultKind, OutputFormat};
use crate::describe::value_json;
use crate::failure::{io_text, Failure};
use crate::input;
use crate::pyfmt::py_str;

/// Ends the process with a usage error (exit status 2) about the options of
/// `ulog params`, as clap reports its own.
pub(super) fn usage_error(message: &str) -> ! {
    use clap::Args as _;
    let mut cmd = Args::augment_args(clap::Command::new("params").bin_name("ulog params"));
    cmd.error(clap::error::ErrorKind::ArgumentConflict, message)
        .exit()
}

/// Runs `--diff` or `--diff-defaults` (one of them is set) in `format` (text, csv or
/// json: `super::run` checked it).
pub(super) fn run(args: &Args, format: OutputFormat) -> Result<(), Failure> {
    let name_a = args.file.display().to_string();
    // The parameters are metadata: one pass over each log in chunks.
    let files: Vec<&PathBuf> = std::iter::once(&args.file).chain(&args.diff).collect();
    let kept = files
        .iter()
        .map(|p| input::keep(p, &[], input::Times::Every))
        .collect::<Result<Vec<_>, _>>()?;
    let logs = kept
        .iter()
        .zip(&files)
        .map(|(k, p)| k.log(&p.display().to_string()))
        .collect::<Result<Vec<_>, _>>()?;
    fn values<'a>(log: &ULog<'a>, initial: bool) -> BTreeMap<String, Value<'a>> {
        match initial {
            true => log.params_at_start(),
            false => log.params_at_end(),
        }
    }
    let log_a = &logs[0];
    let (diffs, columns) = match args.diff_defaults {
        None => {
            let paths: Vec<&std::path::Path> = files.iter().map(|p| p.as_path()).collect();
            let columns = input::column_names(&paths);
            let sets: Vec<BTreeMap<String, Value<'_>>> =
                logs.iter().map(|l| values(l, args.initial)).collect();
            let sets: Vec<&BTreeMap<String, Value<'_>>> = sets.iter().collect();
            (read::diff_params(&sets), columns)
        }
        Some(kind) => {
            if !log_a
                .flag_bits()
                .is_some_and(|f| f.has_default_parameters())
            {
                return Err(Failure::lacking(&name_a, no_defaults("--diff-defaults")));
            }
            let (kind, title) = match kind {
                DefaultKind::System => (read::DefaultKind::System, "system_default"),
                DefaultKind::CurrentSetup => {
                    (read::DefaultKind::CurrentSetup, "current_setup_default")
                }
            };
            let diffs = read::diff_from_defaults(
                &values(log_a, args.initial),
                &log_a.param_defaults(),
                kind,
            );
            (diffs, vec![input::stem(&args.file), title.to_owned()])
        }
    };
    let text = match format {
        OutputFormat::Csv => csv(&diffs, &columns, &args.delimiter),
        OutputFormat::Json => json(&diffs),
        _ => table(&diffs, &columns),
    };
    let (out_name, sink): (String, Box<dyn Write>) = match args.output() {
        Some(p) => {
            let f = File::create(p).map_err(|e| Failure::unreadable(p.display(), io_text(&e)))?;
            (p.display().to_string(), Box::new(f))
        }
        None => ("stdout".to_owned(), Box::new(io::stdout().lock())),
    };
    let mut out = BufWriter::new(sink);
    out.write_all(text.as_bytes())
        .and_then(|()| out.flush())
        .map_err(|e| Failure::io(&out_name, &e))
}

/// A value as `ulog params` prints it (Python's `str()`), or `missing`.
fn text_of(v: Option<&Value<'_>>, missing: &str) -> String {
    v.map_or_else(|| missing.to_owned(), py_str)
}

/// The aligned table: a header of the columns' names, then `name  A  B …` per
/// parameter (`-` where a log does not have it), and a note where the types differ.
fn table(diffs: &[ParamDiff<'_>], columns: &[String]) -> String {
    let mut header = vec!["name".to_owned()];
    header.extend(columns.iter().cloned());
    header.push(String::new());
    let mut rows: Vec<Vec<String>> = vec![header];
    for d in diffs {
        let note = match d.type_change() {
            Some(types) => {
                let types: Vec<&str> = types.iter().map(|t| t.unwrap_or("-")).collect();
                format!("(types differ: {})", types.join(", "))
            }
            None => String::new(),
        };
        let mut row = vec![d.name.clone()];
        row.extend(d.values.iter().map(|v| text_of(v.as_ref(), "-")));
        row.push(note);
        rows.push(row);
    }
    let cells = columns.len() + 2;
    let widths: Vec<usize> = (0..cells)
        .map(|i| rows.iter().map(|r| r[i].chars().count()).max().unwrap_or(0))
        .collect();
    let mut s = String::new();
    for r in &rows {
        let mut line = String::new();
        for (i, cell) in r.iter().enumerate() {
            line.push_str(cell);
            if i + 1 < cells {
                let pad = widths[i] - cell.chars().count() + 2;
                line.extend(std::iter::repeat(' ').take(pad));
            }
        }
        s.push_str(line.trim_end());
        s.push('\n');
    }
    s
}

/// A csv field, quoted where it holds the delimiter, a quote or a line break.
fn csv_field(s: &str, delimiter: &str) -> String {
    if s.contains(delimiter) || s.contains(['"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_owned()
    }
}

/// `name,A,B,…` under a header of the columns' names; an empty field where a log does
/// not have the parameter.
fn csv(diffs: &[ParamDiff<'_>], columns: &[String], delimiter: &str) -> String {
    let mut s = String::new();
    let mut line = |cells: Vec<String>| {
        let cells: Vec<String> = cells.iter().map(|c| csv_field(c, delimiter)).collect();
        s.push_str(&cells.join(delimiter));
        s.push('\n');
    };
    let mut header = vec!["name".to_owned()];
    header.extend(columns.iter().cloned());
    line(header);
    for d in diffs {
        let mut row = vec![d.name.clone()];
        row.extend(d.values.iter().map(|v| text_of(v.as_ref(), "")));
        line(row);
    }
    s
}

/// A parameter value as JSON: a `float` as the double it widens to (the value pyulog
/// holds, as `ulog params` prints it), non-finite floats as Python's `str()` of them.
fn param_json(v: Option<&Value<'_>>) -> Json {
    let float = |f: f64| {
        serde_json::Number::from_f64(f)
            .map_or_else(|| Json::String(py_str(&Value::F64(f))), Json::Number)
    };
    match v {
        None => Json::Null,
        Some(Value::F32(f)) => float(f64::from(*f)),
        Some(Value::F64(f)) => float(*f),
        Some(other) => value_json(other),
    }
}

/// The JSON key of the `i`-th log: `a`, `b`, … `z`, then `log27`, `log28`, ….
fn column_key(i: usize) -> String {
    match u8::try_from(i).ok().filter(|i| *i < 26) {
        Some(i) => char::from(b'a' + i).to_string(),
        None => format!("log{}", i + 1),
    }
}

/// An array of `{"name", "a", "b", …}` (a key per log, in the order given), one object
/// per line.
fn json(diffs: &[ParamDiff<'_>]) -> String {
    if diffs.is_empty() {
        return "[]\n".to_owned();
    }
    let mut s = String::from("[\n");
    for (i, d) in diffs.iter().enumerate() {
        let mut o = serde_json::Map::new();
        o.insert("name".to_owned(), Json::String(d.name.clone()));
        for (k, v) in d.values.iter().enumerate() {
            o.insert(column_key(k), param_json(v.as_ref()));
        }
        s.push_str("  ");
        s.push_str(&Json::Object(o).to_string());
        s.push_str(if i + 1 < diffs.len() { ",\n" } else { "\n" });
    }
    s.push_str("]\n");
    s
}
