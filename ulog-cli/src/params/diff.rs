//! `ulog params --diff B.ulg` and `--diff-defaults [KIND]`: the parameters that differ
//! between two logs, or from a log's defaults, as a table, csv or JSON. The comparing
//! is the library's (`ulog_core::read::diff_params` and `diff_from_defaults`, over
//! `ULog::params_at_end`, or `params_at_start` with `--initial`); this prints.

use std::collections::BTreeMap;
use std::fs::File;
use std::io::{self, BufWriter, Write};

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
    let kept_a = input::keep(&args.file, &[])?;
    let log_a = kept_a.log(&name_a)?;
    let kept_b = match &args.diff {
        Some(path_b) => Some((path_b, input::keep(path_b, &[])?)),
        None => None,
    };
    let log_b = match &kept_b {
        Some((path_b, kept)) => Some((path_b, kept.log(&path_b.display().to_string())?)),
        None => None,
    };
    fn values<'a>(log: &ULog<'a>, initial: bool) -> BTreeMap<String, Value<'a>> {
        match initial {
            true => log.params_at_start(),
            false => log.params_at_end(),
        }
    }
    let (diffs, columns) = match (&log_b, args.diff_defaults) {
        (Some((path_b, log_b)), _) => {
            let (a, b) = (input::stem(&args.file), input::stem(path_b));
            let columns = match a == b {
                // Two logs of the same name in different folders: their paths.
                true => [name_a.clone(), path_b.display().to_string()],
                false => [a, b],
            };
            (
                read::diff_params(&values(&log_a, args.initial), &values(log_b, args.initial)),
                columns,
            )
        }
        (None, Some(kind)) => {
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
                &values(&log_a, args.initial),
                &log_a.param_defaults(),
                kind,
            );
            (diffs, [input::stem(&args.file), title.to_owned()])
        }
        (None, None) => unreachable!("run is called for --diff or --diff-defaults"),
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

/// The aligned table: a header of the two columns' names, then `name  A  B` per
/// parameter (`-` where a side does not have it), and a note where the types differ.
fn table(diffs: &[ParamDiff<'_>], columns: &[String; 2]) -> String {
    let mut rows: Vec<[String; 4]> = vec![[
        "name".to_owned(),
        columns[0].clone(),
        columns[1].clone(),
        String::new(),
    ]];
    for d in diffs {
        let note = match d.type_change() {
            Some((a, b)) => format!("(types differ: {a}, {b})"),
            None => String::new(),
        };
        rows.push([
            d.name.clone(),
            text_of(d.a.as_ref(), "-"),
            text_of(d.b.as_ref(), "-"),
            note,
        ]);
    }
    let width = |i: usize| rows.iter().map(|r| r[i].chars().count()).max().unwrap_or(0);
    let widths = [width(0), width(1), width(2)];
    let mut s = String::new();
    for r in &rows {
        let mut line = String::new();
        for (i, cell) in r.iter().enumerate() {
            line.push_str(cell);
            if i < 3 {
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

/// `name,A,B` under a header of the columns' names; an empty field where a side does
/// not have the parameter.
fn csv(diffs: &[ParamDiff<'_>], columns: &[String; 2], delimiter: &str) -> String {
    let mut s = String::new();
    let mut line = |cells: [&str; 3]| {
        let cells: Vec<String> = cells.iter().map(|c| csv_field(c, delimiter)).collect();
        s.push_str(&cells.join(delimiter));
        s.push('\n');
    };
    line(["name", &columns[0], &columns[1]]);
    for d in diffs {
        line([
            &d.name,
            &text_of(d.a.as_ref(), ""),
            &text_of(d.b.as_ref(), ""),
        ]);
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

/// An array of `{"name", "a", "b"}`, one object per line.
fn json(diffs: &[ParamDiff<'_>]) -> String {
    if diffs.is_empty() {
        return "[]\n".to_owned();
    }
    let mut s = String::from("[\n");
    for (i, d) in diffs.iter().enumerate() {
        let mut o = serde_json::Map::new();
        o.insert("name".to_owned(), Json::String(d.name.clone()));
        o.insert("a".to_owned(), param_json(d.a.as_ref()));
        o.insert("b".to_owned(), param_json(d.b.as_ref()));
        s.push_str("  ");
        s.push_str(&Json::Object(o).to_string());
        s.push_str(if i + 1 < diffs.len() { ",\n" } else { "\n" });
    }
    s.push_str("]\n");
    s
}
