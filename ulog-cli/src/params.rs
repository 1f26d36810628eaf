//! `ulog params`: the parameters, as pyulog's `ulog_params` writes them.

use std::collections::BTreeMap;
use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::PathBuf;

use ulog_core::read::UtcClock;
use ulog_core::{ULog, Value};

use crate::failure::{io_text, Failure};
use crate::input;
use crate::pyfmt::py_str;

mod diff;

/// Print the parameters sorted by name, exactly as pyulog's `ulog_params` does.
///
/// csv: `name,value[,changed value…]` (`--timestamps`: a second line
/// `timestamp,0[,time of change…]` per parameter). octave: `# name`, `# type: scalar`
/// or a `matrix` of the value and its changes. qgc: `1<TAB>1<TAB>name<TAB>value<TAB>type`
/// (9 float, 6 integer). Values print as Python prints them: `float` parameters as the
/// double they widen to (`0.10000000149011612`).
///
/// `--diff B.ulg` prints the parameters that differ between FILE (A) and B, and across
/// more logs with `--diff` repeated (`--diff B.ulg --diff C.ulg`: a parameter some log
/// lacks, or whose values are not all the same); `--diff-defaults[=system|current_setup]` those of FILE that differ from the log's
/// default values of that kind (system if not named; a parameter the log gives no
/// default for is taken to be at its default): each parameter's value at the end of
/// the log (the initial value with the changes applied; `--initial`: the initial
/// value), sorted by name, as an aligned table (a column per log; `-` where a log does
/// not have the parameter; a note where the values have different types, as an int32
/// 1 and a float 1.0, which differ), `--format csv` (`name,A,B,…` under a header of the
/// files' names without extension; an empty field where a log does not have it) or
/// `--format json` (an array of `{"name", "a", "b", …}`, a key per log in the order
/// given: numbers as JSON numbers, a `float` as the double it widens to, null where a
/// log does not have it, NaN and
/// infinities as the strings `nan`, `inf`, `-inf`). The exit status is 0 whether or not
/// parameters differ (there is no `--exit-code`; an empty table or `[]` says none do).
#[derive(Debug, clap::Args)]
#[command(
    about = "The parameters, as pyulog's ulog_params prints them",
    long_about
)]
pub struct Args {
    /// The ULog file (A of `--diff`).
    file: PathBuf,
    /// Output file (default: stdout), as ulog_params takes it.
    output: Option<PathBuf>,
    /// Output file, as the other `ulog` commands take it (instead of OUTPUT).
    #[arg(
        short = 'o',
        long = "output",
        value_name = "FILE",
        conflicts_with = "output"
    )]
    out: Option<PathBuf>,
    /// Only the initial values, no changes (csv, octave). As in ulog_params, with
    /// `--timestamps` the changes are still listed, all at the start time. With `--diff`
    /// or `--diff-defaults`: compare the initial values instead of those at the end.
    #[arg(short = 'i', long)]
    initial: bool,
    /// The default values of this kind instead of the configured ones (implies
    /// `--initial`).
    #[arg(short = 'd', long, value_name = "KIND")]
    default: Option<DefaultKind>,
    /// The parameters that differ across FILE and this log (repeat for more logs:
    /// `--diff B.ulg --diff C.ulg`).
    #[arg(
        long,
        value_name = "B.ulg",
        conflicts_with_all = ["default", "timestamps", "utc", "diff_defaults"]
    )]
    diff: Vec<PathBuf>,
    /// The parameters that differ from the log's defaults of this kind (system if not
    /// named; `--diff-defaults=current_setup`, so that a file after the option is not
    /// taken for a kind).
    #[arg(
        long,
        value_name = "KIND",
        num_args = 0..=1,
        require_equals = true,
        default_missing_value = "system",
        conflicts_with_all = ["default", "timestamps", "utc"]
    )]
    diff_defaults: Option<DefaultKind>,
    /// Output format (default: csv; text with `--diff` and `--diff-defaults`).
    #[arg(short = 'f', long, value_enum)]
    format: Option<OutputFormat>,
    /// csv: list the changes with their timestamps.
    #[arg(short = 't', long)]
    timestamps: bool,
    /// csv: list the changes with their times in UTC (RFC 3339; the initial values at
    /// the log's start) instead of microseconds since boot, from the log's GPS time or
    /// its `boot_time_utc_us` (`ulog info` says which). Implies `--timestamps`.
    #[arg(long)]
    utc: bool,
    /// csv delimiter.
    #[arg(short = 'l', long, default_value = ",", value_name = "DELIM")]
    delimiter: String,
    #[arg(long, help = crate::pyulog::IGNORE_HELP)]
    ignore: bool,
}

impl Args {
    /// The output file, given as OUTPUT or with `-o`.
    fn output(&self) -> Option<&PathBuf> {
        self.output.as_ref().or(self.out.as_ref())
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum DefaultKind {
    /// System-wide defaults (default_types bit 0).
    System,
    /// Defaults of the current configuration, e.g. the airframe (bit 1).
    #[value(name = "current_setup")]
    CurrentSetup,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum OutputFormat {
    Csv,
    Octave,
    Qgc,
    /// An aligned table (`--diff`, `--diff-defaults` only).
    Text,
    /// A JSON array (`--diff`, `--diff-defaults` only).
    Json,
}

pub fn run(args: &Args) -> Result<(), Failure> {
    let diffing = !args.diff.is_empty() || args.diff_defaults.is_some();
    let format = match (args.format, diffing) {
        (Some(f @ (OutputFormat::Octave | OutputFormat::Qgc)), true) => {
            diff::usage_error(&format!(
                "--format {}: --diff and --diff-defaults print text, csv or json",
                if f == OutputFormat::Octave {
                    "octave"
                } else {
                    "qgc"
                }
            ))
        }
        (Some(f @ (OutputFormat::Text | OutputFormat::Json)), false) => {
            diff::usage_error(&format!(
                "--format {}: only with --diff or --diff-defaults (the parameters \
                 themselves print as csv, octave or qgc)",
                if f == OutputFormat::Text {
                    "text"
                } else {
                    "json"
                }
            ))
        }
        (Some(f), _) => f,
        (None, true) => OutputFormat::Text,
        (None, false) => OutputFormat::Csv,
    };
    if diffing {
        return diff::run(args, format);
    }
    if args.utc && format != OutputFormat::Csv {
        diff::usage_error("--utc: only csv lists times (octave and qgc print values only)");
    }
    let name = args.file.display().to_string();
    // The parameters are metadata: one pass in chunks, the data not kept.
    let kept = input::keep(&args.file, &[], input::Times::Every)?;
    let log = kept.log(&name)?;
    let (out_name, sink): (String, Box<dyn Write>) = match args.output() {
        Some(p) => {
            let f = File::create(p).map_err(|e| Failure::unreadable(p.display(), io_text(&e)))?;
            (p.display().to_string(), Box::new(f))
        }
        None => ("stdout".to_owned(), Box::new(io::stdout().lock())),
    };
    let utc = input::utc_of(&name, || kept.metadata.utc(), args.utc)?;
    let mut out = BufWriter::new(sink);
    let text = render(&log, args, format, utc.as_ref())?;
    out.write_all(text.as_bytes())
        .and_then(|()| out.flush())
        .map_err(|e| Failure::io(&out_name, &e))
}

/// Why `option` (`--default`, `--diff-defaults`) fails on a log without defaults.
fn no_defaults(option: &str) -> String {
    format!(
        "{option}: the log has no default parameters to compare with (compat flag \
         DEFAULT_PARAMETERS is not set; `--diff B.ulg` compares with another log)"
    )
}

/// A parameter value: Python's `str()` of it, and whether Python holds it as a float.
struct Param {
    text: String,
    is_float: bool,
}

impl Param {
    fn of(v: Value<'_>) -> Param {
        Param {
            text: py_str(&v),
            is_float: matches!(v, Value::F32(_) | Value::F64(_)),
        }
    }
}

fn render(
    log: &ULog<'_>,
    args: &Args,
    format: OutputFormat,
    utc: Option<&UtcClock>,
) -> Result<String, Failure> {
    let mut params: BTreeMap<String, Param> = BTreeMap::new();
    let mut initial = args.initial;
    match args.default {
        None => {
            for kv in log.initial_params() {
                params.insert(kv.name().into_owned(), Param::of(kv.value()));
            }
        }
        Some(kind) => {
            let has_defaults = log.flag_bits().is_some_and(|f| f.has_default_parameters());
            if !has_defaults {
                let name = args.file.display();
                return Err(Failure::lacking(name, no_defaults("--default")));
            }
            let bit = if kind == DefaultKind::System { 1 } else { 2 };
            for d in log
                .default_params()
                .iter()
                .filter(|d| d.default_types & bit != 0)
            {
                params.insert(d.kv.name().into_owned(), Param::of(d.kv.value()));
            }
            initial = true;
        }
    }
    // ulog_params reads no data with --initial, so every change is stamped with the
    // start time.
    let changes: Vec<(String, u64, String)> = log
        .param_changes()
        .iter()
        .map(|c| {
            let t = if args.initial {
                log.start_timestamp()
            } else {
                c.timestamp
            };
            (c.kv.name().into_owned(), t, py_str(&c.kv.value()))
        })
        .collect();
    fn changes_of<'c>(
        changes: &'c [(String, u64, String)],
        key: &'c str,
    ) -> impl Iterator<Item = &'c (String, u64, String)> {
        changes.iter().filter(move |c| c.0 == key)
    }

    let d = &args.delimiter;
    let mut s = String::new();
    for (key, p) in &params {
        match format {
            OutputFormat::Csv if args.timestamps || utc.is_some() => {
                s.push_str(key);
                s.push_str(d);
                s.push_str(&p.text);
                for c in changes_of(&changes, key) {
                    s.push_str(d);
                    s.push_str(&c.2);
                }
                s.push_str("\ntimestamp");
                s.push_str(d);
                match utc {
                    Some(clock) => s.push_str(&clock.at(log.start_timestamp()).to_string()),
                    None => s.push('0'),
                }
                for c in changes_of(&changes, key) {
                    s.push_str(d);
                    match utc {
                        Some(clock) => s.push_str(&clock.at(c.1).to_string()),
                        None => s.push_str(&c.1.to_string()),
                    }
                }
                s.push('\n');
            }
            OutputFormat::Csv => {
                s.push_str(key);
                s.push_str(d);
                s.push_str(&p.text);
                if !initial {
                    for c in changes_of(&changes, key) {
                        s.push_str(d);
                        s.push_str(&c.2);
                    }
                }
                s.push('\n');
            }
            OutputFormat::Octave => {
                s.push_str("# name ");
                s.push_str(key);
                let mut values = vec![p.text.as_str()];
                if !initial {
                    values.extend(changes_of(&changes, key).map(|c| c.2.as_str()));
                }
                if values.len() > 1 {
                    s.push_str("\n# type: matrix\n# rows: 1\n# columns: ");
                    s.push_str(&values.len().to_string());
                    s.push('\n');
                    for v in values {
                        s.push_str(v);
                        s.push(' ');
                    }
                } else {
                    s.push_str("\n# type: scalar\n");
                    s.push_str(values[0]);
                }
                s.push('\n');
            }
            OutputFormat::Qgc => {
                let ty = if p.is_float { 9 } else { 6 };
                s.push_str(&format!("1\t1\t{key}\t{}\t{ty}\n", p.text));
            }
            OutputFormat::Text | OutputFormat::Json => unreachable!("checked in run"),
        }
    }
    Ok(s)
}
