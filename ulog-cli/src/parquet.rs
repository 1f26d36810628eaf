//! `ulog parquet`: logs to a Parquet dataset (one file per topic and log, and four
//! tables of what the logs are), or one folder per log; many logs at once, in parallel.

use std::collections::BTreeSet;
use std::io::{self, Write};
use std::num::NonZeroUsize;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use ulog_core::export::{self, Added, Compression, Dataset, ExportErrorKind, LogPath, Options};
use ulog_core::read::{ReadErrorKind, UtcClock};
use ulog_core::store::{Downloaded, RemoteDataset, StoreErrorKind};
use ulog_core::{LookupError, ReadError};

use crate::failure::{stdout_err, Failure, Status};
use crate::input;
use crate::progress::Progress;

/// Convert logs to Parquet, as one dataset that query engines (DuckDB, DataFusion,
/// Polars, Spark) read across logs in one statement: `DATASET/<topic>/<log_id>.parquet`
/// holds a topic's rows in one log (all its instances, with columns `log_id` and
/// `multi_id` first); `DATASET/logs.parquet` one row per log (source, size, sha256,
/// start in boot time and UTC, duration, system, versions, vehicle type, counts, damage
/// found); `parameters.parquet` the initial, changed and default parameters;
/// `messages.parquet` the logged strings and PX4 events; `formats.parquet` the message
/// formats of each log; `analysis.parquet` the diagnostics of the flight analysis
/// (`ulog analyze`, made in the same pass) and `flights.parquet` its flight statistics,
/// one row per log.
///
/// `_schemas/<topic>.parquet` holds each topic's union schema over the firmware
/// versions of the dataset (no rows), for engines that take one schema per folder.
/// Logs may be `s3://` or `https://` URLs (an `s3://` prefix: every log below it), and
/// the dataset an `s3://` prefix, with the standard AWS environment's credentials and
/// endpoint; `logs.parquet` is uploaded last, so a reader never sees half a log.
///
/// `log_id` is the log's XXH3 64-bit hash in 16 hex digits: a log already in the
/// dataset is skipped, so converting into an existing dataset adds only the new logs.
/// The files are the same byte for byte from run to run.
///
/// Columns keep the log's types (a `uint64_t` stays UInt64; `bool` is Boolean);
/// arrays are fixed-size lists and nested types structs, unless `--flatten`; `char[N]`
/// is a string without its trailing NULs, one character per byte (ISO 8859-1, so no
/// byte is lost); padding is left out; `timestamp` stays as logged (microseconds).
///
/// With `--layout fleet`, for thousands of logs, a topic's rows of many logs share a
/// file instead: `DATASET/<topic>/month=YYYY-MM/<log_id>.parquet` (the month of the
/// log's `start_utc`; `--partition-by` chooses the folders), row groups of whole logs,
/// logs in `log_id` order, each one's rows in `timestamp` order, files of about
/// `--file-size` MB, each file's format hash, firmware versions and logs in its
/// key-value metadata. Logs added later go into new files; no file is rewritten. A
/// dataset keeps the layout it was made with.
///
/// With `--per-log`, each log goes to a folder of its own instead: `<log stem>/`
/// holding `<topic>_<multi_id>.parquet` per topic instance and `metadata.json`
/// (information, parameters, logged messages, dropouts, damage found, topics). A topic
/// name that a file system refuses or folds (`a/b`, `CON`, a name of 300 bytes, `Foo`
/// beside `foo`) is escaped in file and folder names (`a_b~` and a hash of the name;
/// in a dataset every name with an upper-case letter, since its folders hold every
/// log's topics): the real name is in each file's metadata (`ulog.topic`).
///
/// Several logs are converted in parallel, each by one thread; a single log is hashed,
/// then read once, in chunks (never held whole), its row groups encoded in parallel as
/// it goes.
/// A log that cannot be read or converted is reported (one line) and the others go
/// on; the exit status is then that of the first failure, in the order given.
///
/// One conversion writes a dataset at a time: another `ulog parquet` into the same
/// folder meanwhile waits until it is done (it says so on stderr), then adds the logs
/// the first did not (a lock file, `.ulog-dataset.lock`, names the process holding
/// it; a lock left by a conversion that was killed is taken over on Linux).
#[derive(Debug, clap::Args)]
#[command(
    about = "Logs to one Parquet dataset of topic files and tables, for SQL",
    long_about
)]
pub struct Args {
    /// ULog files, or directories: every `.ulg` and `.ulog` file (any case) in a
    /// directory and its subdirectories is converted. `s3://BUCKET/KEY` is a log, or
    /// every log below it as a prefix; `https://…` a log.
    #[arg(required_unless_present = "compact", value_name = "FILE_OR_DIR")]
    inputs: Vec<PathBuf>,
    /// The dataset (a folder, made if missing; the logs it has are skipped), or an
    /// `s3://BUCKET/PREFIX` (written through a local staging folder, `logs.parquet`
    /// last: a reader never sees half a log). Default with one log: `<log stem>/`
    /// beside it. With `--per-log`: each log goes to
    /// `DIR/<log stem>/` (default: `<log stem>/` beside each log).
    #[arg(short = 'o', long = "output", value_name = "DATASET")]
    output: Option<PathBuf>,
    /// One folder per log (`<topic>_<multi_id>.parquet` and `metadata.json`) instead
    /// of a dataset.
    #[arg(long)]
    per_log: bool,
    /// pyulog's columns instead of struct and list columns: one per value, named by
    /// path (`q[0]`, `esc[3].esc_rpm`), `timestamp` first, as `ulog csv` names them
    /// (without the nested padding columns that `ulog csv` keeps).
    #[arg(long)]
    flatten: bool,
    /// Only these topics (comma-separated names, e.g. `vehicle_local_position,sensor_combined`).
    /// With one log, a name it lacks is an error and nothing is left written; with many,
    /// each log gets the topics it has, a log with none of them is skipped, and a name
    /// in none of the logs is an error at the end.
    #[arg(short = 'm', long = "messages", value_name = "TOPICS")]
    messages: Option<String>,
    /// Compression of the Parquet files (zstd: the smallest files, for keeping).
    #[arg(long, value_enum, default_value = "zstd", value_name = "CODEC")]
    compression: Codec,
    /// Add a column `timestamp_utc` after `timestamp` (Arrow/Parquet timestamp, UTC,
    /// microseconds) from the log's GPS time or its `boot_time_utc_us` (`ulog info`
    /// says which). A log with neither is an error; with many logs, it is written
    /// without the column and a line says so.
    #[arg(long)]
    utc: bool,
    /// Threads (default: the number of CPUs): logs converted at the same time, or,
    /// for a single log, row groups encoded at the same time.
    #[arg(short = 'j', long = "jobs", value_name = "N")]
    jobs: Option<NonZeroUsize>,
    /// How a new dataset lays out its topic files: `file-per-log` (`<topic>/<log_id>.parquet`,
    /// the default) or `fleet` (many logs per file, in partition folders). An existing
    /// dataset keeps its own; asking for another is an error.
    #[arg(long, value_enum, value_name = "LAYOUT")]
    layout: Option<LayoutArg>,
    /// The fleet layout's partition folders, outermost first (comma-separated):
    /// `month` (of the log's `start_utc`), `vehicle` (its `sys_uuid`), or `none`
    /// [default: month].
    #[arg(
        long = "partition-by",
        value_enum,
        value_name = "KEYS",
        value_delimiter = ','
    )]
    partition_by: Option<Vec<PartitionArg>>,
    /// The fleet layout's file size in MB: a file is closed once it holds this much
    /// (a log's rows are never split over files) [default: 128].
    #[arg(
        long = "file-size",
        value_name = "MB",
        value_parser = clap::value_parser!(u64).range(1..)
    )]
    file_size: Option<u64>,
    /// Fleet layout: also merge each partition's files smaller than half the file size
    /// (left by conversions of a few logs at a time) into files of about that size;
    /// with no logs given, only that. Without it, no file is rewritten.
    #[arg(long)]
    compact: bool,
}

/// A partition folder of the fleet layout (`--partition-by`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum PartitionArg {
    /// `month=YYYY-MM`, of the log's `start_utc`.
    Month,
    /// `vehicle=<sys_uuid>`.
    Vehicle,
    /// No partition folders.
    None,
}

/// A dataset's layout (`--layout`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum LayoutArg {
    /// A file per topic and log.
    FilePerLog,
    /// A topic's rows of many logs per file, in partition folders.
    Fleet,
}

/// A compression codec.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum Codec {
    /// Snappy: fast, read by every engine.
    Snappy,
    /// Zstandard (level 1): smaller files, for keeping; read by every current engine.
    Zstd,
    /// No compression.
    None,
}

/// One log to convert.
struct Job {
    input: PathBuf,
    /// Its folder (`--per-log`).
    out: PathBuf,
    size: u64,
}

/// What converting one log gave.
struct Done {
    /// Topic names of `-m` that the log has.
    found: Vec<String>,
    /// The first suggestion for a name it lacks.
    suggestion: Option<String>,
}

pub fn run(args: &Args) -> Result<(), Failure> {
    let jobs = plan(args)?;
    if args.compact {
        if args.per_log {
            return Err(Failure::about(
                "--compact",
                "merges the files of a dataset: leave out --per-log",
            ));
        }
        match (&args.output, jobs.is_empty()) {
            (None, true) => {
                return Err(Failure::about(
                    "--compact",
                    "name the dataset to compact with -o DATASET",
                ))
            }
            (Some(dir), true)
                if input::remote(dir)?.is_none() && !dir.join(export::LOGS_FILE).exists() =>
            {
                return Err(Failure::about(
                    dir.display(),
                    format!("no dataset to compact here (no {})", export::LOGS_FILE),
                ))
            }
            _ => {}
        }
    }
    let names: Option<Vec<String>> = args.messages.as_ref().map(|list| {
        list.split(',')
            .filter(|s| !s.is_empty())
            .map(str::to_owned)
            .collect()
    });
    let available = input::threads(args.jobs);
    let options = Options {
        flatten: args.flatten,
        topics: names.clone(),
        compression: match args.compression {
            Codec::Snappy => Compression::Snappy,
            Codec::Zstd => Compression::Zstd,
            Codec::None => Compression::Uncompressed,
        },
        threads: if jobs.len() == 1 { available } else { 1 },
        layout: layout(args)?,
        compact: args.compact,
        ..Options::default()
    };
    // With one log, names it lacks are an error and nothing is left written; with
    // many, each log exports the names it has.
    let strict = jobs.len() == 1;
    // Where the logs go: one dataset, or (`--per-log`) each to its folder.
    let mut made = false;
    let target = if args.per_log {
        if let Some(out) = args
            .output
            .as_deref()
            .filter(|o| input::remote(o).is_ok_and(|r| r.is_some()))
        {
            return Err(Failure::about(
                out.display(),
                "--per-log writes local folders: name a local folder, or leave out --per-log \
                 to write a dataset to object storage",
            ));
        }
        None
    } else {
        let dir = dataset_dir(args, &jobs)?;
        match input::remote(&dir)? {
            Some(remote) => Some(Target::Remote(open_remote(remote, &options)?)),
            None => {
                made = !dir.exists();
                Some(Target::Local(open_dataset(&dir, &options)?))
            }
        }
    };
    let dataset = target.as_ref().map(Target::dataset);

    let total: u64 = jobs.iter().map(|j| j.size).sum();
    let progress = Progress::bytes(total, "parquet");
    let stdout = Mutex::new(io::stdout());
    // Largest logs first, so that the threads end together; a log that fails does not
    // stop the others (its failure is its result).
    let sizes: Vec<u64> = jobs.iter().map(|j| j.size).collect();
    let results = ulog_core::parallel::largest_first(&sizes, available, |i| {
        let result = convert(
            &jobs[i], dataset, &options, args.utc, strict, &progress, &stdout,
        );
        if let Err(Failure::Message(_, m)) = &result {
            if !strict {
                progress.suspend(|| {
                    let _ = writeln!(io::stderr(), "ulog: {m}");
                });
            }
        }
        Ok::<_, core::convert::Infallible>(result)
    });
    drop(progress);
    let results: Vec<Option<Result<Done, Failure>>> = results
        .into_iter()
        .map(|r| r.map(|r| r.unwrap_or_else(|e| match e {})))
        .collect();
    let failed = results.iter().flatten().any(Result::is_err);
    if strict && failed && (made || matches!(target, Some(Target::Remote(_)))) {
        // One log that failed leaves nothing written, as with --per-log (a dataset in
        // a store is not written to until the end).
        if let Some(Target::Local(dataset)) = &target {
            let _ = std::fs::remove_dir_all(dataset.dir());
        }
    } else if let Some(target) = target {
        let logs = target.dataset().len();
        let shown = match target {
            Target::Local(dataset) => {
                let dir = dataset.dir().to_owned();
                let finished = dataset
                    .finish()
                    .map_err(|e| failure(&dir.display().to_string(), &e))?;
                if let Some(c) = finished.compacted {
                    writeln!(
                        io::stdout(),
                        "Compacted {}: {} small files merged into {} ({} topic files now)",
                        dir.display(),
                        c.merged,
                        c.written,
                        c.files
                    )
                    .map_err(stdout_err)?;
                }
                dir.display().to_string()
            }
            Target::Remote(remote) => {
                let url = remote.url();
                remote.finish().map_err(|e| input::store_failure(&e))?;
                url
            }
        };
        let mut out = io::stdout().lock();
        writeln!(
            out,
            "Writing {} ({}, {}, {}, {}, {}, {}: {logs} log{})",
            shown,
            export::LOGS_FILE,
            export::PARAMETERS_FILE,
            export::MESSAGES_FILE,
            export::FORMATS_FILE,
            export::ANALYSIS_FILE,
            export::FLIGHTS_FILE,
            if logs == 1 { "" } else { "s" }
        )
        .map_err(stdout_err)?;
    }
    io::stdout().flush().map_err(stdout_err)?;
    let mut found = BTreeSet::new();
    let mut suggestion = None;
    let mut failures = Vec::new();
    for r in results.into_iter().flatten() {
        match r {
            Ok(done) => {
                found.extend(done.found);
                suggestion = suggestion.or(done.suggestion);
            }
            Err(f) => failures.push(f),
        }
    }
    if strict {
        if let Some(f) = failures.into_iter().next() {
            return Err(f);
        }
    } else if let Some(Failure::Message(status, _)) = failures.first() {
        return Err(Failure::new(
            *status,
            "parquet",
            format!(
                "{} of {} logs failed (see above)",
                failures.len(),
                jobs.len()
            ),
        ));
    }
    if let Some(names) = &names {
        if let Some(missing) = names.iter().find(|n| !found.contains(*n)) {
            let mut text = format!("no topic `{missing}` in any of the {} logs", jobs.len());
            if let Some(s) = suggestion {
                text.push_str(&format!(" (did you mean `{s}`?)"));
            }
            return Err(Failure::unknown_name("parquet", text));
        }
    }
    Ok(())
}

/// The layout `--layout`, `--partition-by` and `--file-size` ask for
/// (`DatasetLayout::from_names`, as Python's `ulog_rs.convert` reads its arguments).
fn layout(args: &Args) -> Result<Option<export::DatasetLayout>, Failure> {
    let name = args.layout.map(|l| match l {
        LayoutArg::FilePerLog => "file-per-log",
        LayoutArg::Fleet => "fleet",
    });
    let keys: Option<Vec<&str>> = args.partition_by.as_ref().map(|keys| {
        keys.iter()
            .map(|k| match k {
                PartitionArg::Month => "month",
                PartitionArg::Vehicle => "vehicle",
                PartitionArg::None => "none",
            })
            .collect()
    });
    export::DatasetLayout::from_names(name, keys.as_deref(), args.file_size).map_err(|e| {
        // Which flag: a key or size without the fleet layout, else a key given twice
        // (clap has checked the names and the size's range).
        let fleet = args.layout == Some(LayoutArg::Fleet);
        let flag = if !fleet && args.partition_by.is_none() {
            "--file-size"
        } else {
            "--partition-by"
        };
        Failure::about(flag, e)
    })
}

/// The dataset in `dir`, once no other conversion writes it: while one does (another
/// `ulog parquet` into the same folder), says so once on stderr and waits for it.
fn open_dataset(dir: &Path, options: &Options) -> Result<Dataset, Failure> {
    let mut said = false;
    loop {
        match Dataset::open(dir, options) {
            Err(e) if matches!(e.kind(), ExportErrorKind::Busy { .. }) => {
                if !said {
                    if let ExportErrorKind::Busy { owner, lock } = e.kind() {
                        let _ = writeln!(
                            io::stderr(),
                            "ulog: {}: another conversion ({owner}) is writing the dataset: \
                             waiting for it to end (if none runs, remove {})",
                            dir.display(),
                            lock.display()
                        );
                    }
                    said = true;
                }
                std::thread::sleep(std::time::Duration::from_millis(100));
            }
            other => return other.map_err(|e| failure(&dir.display().to_string(), &e)),
        }
    }
}

/// Where the dataset is written.
enum Target {
    /// A folder.
    Local(Dataset),
    /// An `s3://` prefix, through a local staging folder.
    Remote(RemoteDataset),
}

impl Target {
    fn dataset(&self) -> &Dataset {
        match self {
            Target::Local(dataset) => dataset,
            Target::Remote(remote) => remote.dataset(),
        }
    }
}

/// The dataset under the `s3://` prefix `remote`, once no other conversion writes it
/// (as [`open_dataset`]: says so once and waits); says how many files a conversion
/// that died had left.
fn open_remote(
    remote: ulog_core::store::Remote,
    options: &Options,
) -> Result<RemoteDataset, Failure> {
    let mut said = false;
    loop {
        match RemoteDataset::open(remote.clone(), options) {
            Err(e) if matches!(e.kind(), StoreErrorKind::Busy { .. }) => {
                if !said {
                    let _ = writeln!(
                        io::stderr(),
                        "ulog: {e}: waiting for it to end (if none runs, remove that object)"
                    );
                    said = true;
                }
                std::thread::sleep(std::time::Duration::from_millis(500));
            }
            Err(e) => return Err(input::store_failure(&e)),
            Ok(dataset) => {
                if dataset.removed_leftovers() > 0 {
                    let _ = writeln!(
                        io::stderr(),
                        "ulog: {}: removed {} topic file(s) of logs that logs.parquet does \
                         not list (left by a conversion that did not end)",
                        dataset.url(),
                        dataset.removed_leftovers()
                    );
                }
                return Ok(dataset);
            }
        }
    }
}

/// The dataset's folder: `-o`, or with one log `<stem>/` beside it.
fn dataset_dir(args: &Args, jobs: &[Job]) -> Result<PathBuf, Failure> {
    match (&args.output, jobs) {
        (Some(dir), _) => Ok(dir.clone()),
        (None, [job]) => Ok(job.out.clone()),
        (None, _) => Err(Failure::about(
            "parquet",
            format!(
                "{} logs make one dataset: name its folder with -o DATASET \
                 (or use --per-log for a folder per log)",
                jobs.len()
            ),
        )),
    }
}

/// The logs named on the command line (directories searched, subdirectories too),
/// each with its `--per-log` folder. Missing inputs, and with `--per-log` two logs
/// writing to one folder, are errors before any work.
fn plan(args: &Args) -> Result<Vec<Job>, Failure> {
    let mut files = Vec::new();
    for input in &args.inputs {
        files.extend(input::logs_in(input)?);
    }
    let mut jobs: Vec<Job> = Vec::with_capacity(files.len());
    let mut outs = std::collections::HashMap::new();
    for (input, size) in files {
        let out = output_dir(&input, args.output.as_deref().filter(|_| args.per_log));
        if args.per_log {
            if let Some(other) = outs.insert(out.clone(), input.clone()) {
                return Err(Failure::about(
                    out.display(),
                    format!(
                        "both {} and {} would be written here",
                        other.display(),
                        input.display()
                    ),
                ));
            }
        }
        jobs.push(Job { input, out, size });
    }
    Ok(jobs)
}

/// `DIR/<stem>` or, without `-o`, `<stem>` beside the log; the stem is the file name
/// without `.ulg` or `.ulog` (any case), or with `_parquet` added when it has no such
/// extension.
fn output_dir(input: &Path, dir: Option<&Path>) -> PathBuf {
    let name = input
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let stem = match input::strip_log_extension(&name) {
        Some(stem) if !stem.is_empty() => stem.to_owned(),
        _ => format!("{name}_parquet"),
    };
    match dir {
        Some(d) => d.join(stem),
        // Beside a log of a store: in the current folder.
        None if input::remote(input).is_ok_and(|r| r.is_some()) => PathBuf::from(stem),
        None => input.with_file_name(stem),
    }
}

/// Converts one log, advancing `progress` by its size, and prints what was written.
fn convert(
    job: &Job,
    dataset: Option<&Dataset>,
    options: &Options,
    utc: bool,
    strict: bool,
    progress: &Progress,
    stdout: &Mutex<io::Stdout>,
) -> Result<Done, Failure> {
    let name = job.input.display().to_string();
    let mut advanced = 0u64;
    let result = (|| {
        progress.message(name.clone());
        let mut options = options.clone();
        options.skip_missing_topics = !strict;
        if utc {
            options.utc = utc_clock(&job.input, &name, strict, progress)?;
        }
        let mut done = Done {
            found: Vec::new(),
            suggestion: None,
        };
        let advance = |read: u64| {
            let read = read.min(job.size);
            if read > advanced {
                progress.inc(read - advanced);
                advanced = read;
            }
        };
        let export = match dataset {
            None => {
                let source = input::source(&job.input)?;
                export::write_parquet_with(source, &job.out, &options, advance)
                    .map(|e| (Some(e), None))
            }
            Some(dataset) => {
                // A log of a store is copied to a temporary file first: it is hashed
                // (its id), then read again by the pass.
                let downloaded = match input::remote(&job.input)? {
                    Some(remote) => {
                        Some(Downloaded::new(&remote).map_err(|e| input::store_failure(&e))?)
                    }
                    None => None,
                };
                let log = match &downloaded {
                    Some(d) => LogPath::named(d.path(), d.url()),
                    None => LogPath::from(&job.input),
                };
                dataset
                    .add(log, options.utc.clone(), advance)
                    .map(|added| match added {
                        Added::Written { log_id, export } => (Some(export), Some(log_id)),
                        Added::Present { log_id } => (None, Some(log_id)),
                        _ => (None, None),
                    })
            }
        };
        let (export, log_id) = match export {
            Ok((Some(export), log_id)) => (export, log_id),
            Ok((None, log_id)) => {
                // Its topics are those it was added with: not said again.
                done.found = options.topics.clone().unwrap_or_default();
                let id = log_id.unwrap_or_default();
                progress.suspend(|| {
                    let mut out = stdout.lock().expect("no thread panicked holding it");
                    writeln!(out, "Skipping {name}: the dataset has it already ({id})")
                        .map_err(stdout_err)
                })?;
                return Ok(done);
            }
            Err(e) => {
                if let ExportErrorKind::Lookup(LookupError::Topic(t)) = e.kind() {
                    done.suggestion = t.closest.first().cloned();
                    if !strict {
                        // The log has none of the names.
                        progress.suspend(|| {
                            let mut out = stdout.lock().expect("no thread panicked holding it");
                            writeln!(out, "Skipping {name}: it has none of the topics")
                                .map_err(stdout_err)
                        })?;
                        return Ok(done);
                    }
                }
                return Err(failure(&name, &e));
            }
        };
        if let Some(names) = &options.topics {
            for missing in &export.missing_topics {
                if let LookupError::Topic(t) = missing {
                    done.suggestion = done.suggestion.take().or(t.closest.first().cloned());
                }
            }
            done.found = names
                .iter()
                .filter(|n| {
                    !export
                        .missing_topics
                        .iter()
                        .any(|m| matches!(m, LookupError::Topic(t) if &t.name == *n))
                })
                .cloned()
                .collect();
        }
        let rows: usize = export.files.iter().map(|w| w.rows).sum();
        let files = export.files.len();
        let plural = if files == 1 { "" } else { "s" };
        progress.suspend(|| -> Result<(), Failure> {
            let mut err = io::stderr();
            for s in &export.skipped {
                let _ = writeln!(
                    err,
                    "ulog: {name}: topic `{}` ({}) cannot be exported, skipped: {}",
                    s.topic, s.multi_id, s.error
                );
            }
            let mut out = stdout.lock().expect("no thread panicked holding it");
            match log_id {
                Some(id) => writeln!(
                    out,
                    "Adding {name} as {id} ({files} Parquet file{plural}, {rows} rows)"
                ),
                _ => writeln!(
                    out,
                    "Writing {} ({files} Parquet file{plural}, {rows} rows, {})",
                    job.out.display(),
                    export::METADATA_FILE
                ),
            }
            .map_err(stdout_err)
        })?;
        Ok(done)
    })();
    progress.inc(job.size - advanced);
    result
}

/// The failure of an export of the log `name`.
fn failure(name: &str, e: &export::ExportError) -> Failure {
    match e.kind() {
        ExportErrorKind::Lookup(LookupError::Topic(_)) => Failure::unknown_name(name, e),
        // The text names the file that could not be written.
        ExportErrorKind::Io(_) => Failure::Message(Status::Io, e.to_string()),
        ExportErrorKind::Read => {
            let read = std::error::Error::source(e).and_then(|s| s.downcast_ref::<ReadError>());
            match read {
                Some(r) if matches!(r.kind(), ReadErrorKind::Io(_)) => {
                    Failure::unreadable(name, input::error_text(r))
                }
                Some(r) => Failure::new(Status::Refused, name, input::error_text(r)),
                None => Failure::about(name, e),
            }
        }
        _ => Failure::about(name, e),
    }
}

/// The UTC clock of the log at `path` (`--utc`): read before the export, which is
/// one pass in file order and meets the GPS time only as it goes (so `--utc` reads a
/// log twice, and holds it whole in memory for the first read). With many logs
/// (`strict` false), a log without one is written without the column.
fn utc_clock(
    path: &Path,
    name: &str,
    strict: bool,
    progress: &Progress,
) -> Result<Option<UtcClock>, Failure> {
    // Read whole (as other commands do), then dropped before the export starts.
    let file = input::open(path)?;
    let log = input::parse(name, file.bytes())?;
    match input::utc_clock(name, &log, true) {
        Ok(clock) => Ok(clock),
        Err(f) if strict => Err(f),
        Err(_) => {
            progress.suspend(|| {
                let _ = writeln!(
                    io::stderr(),
                    "ulog: {name}: no UTC time in the log: written without timestamp_utc"
                );
            });
            Ok(None)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn output_folder_is_the_stem() {
        assert_eq!(output_dir(Path::new("a/b.ULG"), None), PathBuf::from("a/b"));
        assert_eq!(
            output_dir(Path::new("a/b.ulog"), None),
            PathBuf::from("a/b")
        );
        assert_eq!(
            output_dir(Path::new("a/b.ulg"), Some(Path::new("out"))),
            PathBuf::from("out/b")
        );
        // Never the log itself.
        assert_eq!(
            output_dir(Path::new("a/b"), None),
            PathBuf::from("a/b_parquet")
        );
    }
}
