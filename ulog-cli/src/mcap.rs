//! `ulog mcap`: logs as MCAP files for ROS 2 and Foxglove tools.

use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

use ulog_core::mcap::{write_mcap, McapEncoding, McapOptions, McapWriteError};

use crate::failure::{io_text, stdout_err, Failure, Status};
use crate::input;

/// Write each log as an MCAP file that Foxglove, Lichtblick and ROS 2's `ros2 bag`
/// tools read, without a ROS install or `px4_msgs`: each topic instance a channel
/// `/fmu/out/<topic>` (`_<N>` after it for instance N ≥ 1) of `ros2msg` schema
/// `px4_msgs/msg/<Format>` made from the log's own formats (nested formats as their
/// own types, `char[N]` as `uint8[N]`, padding left out), messages in CDR at their
/// `timestamp`; logged strings on `/rosout` (`rcl_interfaces/msg/Log`), parameters
/// on `/ulog/parameters`, information, multi-information, dropouts and damage found
/// as MCAP metadata. Chunks of 1 MiB, zstd-compressed; the log is read in chunks,
/// never held whole: a first pass finds its span (and with `--utc` its clock), the
/// second writes.
///
/// Times are since boot unless `--utc`; `--start`/`--end` are seconds since the
/// log's start (`90`, `1:30`, `1:30.5`). `--rosbag2` writes each log as a ROS 2 bag
/// instead: a folder with the MCAP file (`<stem>_0.mcap`) and the `metadata.yaml`
/// that `ros2 bag info` and `ros2 bag play` need.
#[derive(Debug, clap::Args)]
#[command(about = "Logs as MCAP files for ROS 2 and Foxglove tools", long_about)]
pub struct Args {
    /// ULog files.
    #[arg(required = true, value_name = "FILE")]
    files: Vec<PathBuf>,
    /// With one log, the file to write; with many, a directory for `<stem>.mcap`
    /// files (created if missing). Default: `<stem>.mcap` beside each log.
    #[arg(short = 'o', long = "output", value_name = "OUT")]
    output: Option<PathBuf>,
    /// Only these topics (comma-separated names).
    #[arg(short = 'm', long = "messages", value_name = "TOPICS")]
    messages: Option<String>,
    /// Only messages from this time on (seconds since the log's start).
    #[arg(long, value_name = "T", value_parser = input::seconds)]
    start: Option<f64>,
    /// Only messages up to this time (seconds since the log's start).
    #[arg(long, value_name = "T", value_parser = input::seconds)]
    end: Option<f64>,
    /// How messages are encoded: `ros2` (CDR with `ros2msg` schemas) or `json` (JSON
    /// with JSON Schemas, for tools without CDR; floats that are not finite are null).
    #[arg(long, value_enum, default_value = "ros2", value_name = "ENCODING")]
    encoding: Encoding,
    /// Compression of the chunks: `zstd` (level −1, zstd's fast side) or `none` (faster, larger).
    #[arg(long, value_enum, default_value = "zstd", value_name = "CODEC")]
    compression: Codec,
    /// Write a ROS 2 bag folder per log (the `-o` folder with one log; `<stem>/`
    /// beside each log or in the `-o` directory with many).
    #[arg(long)]
    rosbag2: bool,
    /// Times since the Unix epoch (UTC) from the log's GPS time or its
    /// `boot_time_utc_us` (`ulog info` says which) instead of since boot.
    #[arg(long)]
    utc: bool,
}

/// A chunk compression.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum Codec {
    /// Zstandard, level −1.
    Zstd,
    /// None.
    None,
}

/// A message encoding.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum Encoding {
    /// CDR, as ROS 2 writes it, with `ros2msg` schemas.
    Ros2,
    /// JSON with JSON Schemas.
    Json,
}

pub fn run(args: &Args) -> Result<(), Failure> {
    if args.rosbag2 && args.encoding == Encoding::Json {
        return Err(Failure::about(
            "--rosbag2",
            "a ROS 2 bag holds CDR messages: leave out --encoding json",
        ));
    }
    let many = args.files.len() > 1;
    if let (true, Some(dir)) = (many, &args.output) {
        std::fs::create_dir_all(dir)
            .map_err(|e| Failure::unreadable(dir.display(), io_text(&e)))?;
    }
    let mut first_failure = None;
    for file in &args.files {
        let stem = input::stem(file);
        let name = match args.rosbag2 {
            true => stem.to_string(),
            false => format!("{stem}.mcap"),
        };
        let out = match (&args.output, many) {
            (Some(o), false) => o.clone(),
            (Some(dir), true) => dir.join(name),
            (None, _) => file.with_file_name(name),
        };
        if let Err(f) = convert(args, file, &out) {
            if !many {
                return Err(f);
            }
            if let Failure::Message(_, m) = &f {
                let _ = writeln!(io::stderr(), "ulog: {m}");
            }
            first_failure.get_or_insert(f);
        }
    }
    match first_failure {
        Some(f) => Err(f),
        None => Ok(()),
    }
}

/// Writes the MCAP file (or, with `--rosbag2`, the bag folder) `out` of `file`.
fn convert(args: &Args, file: &Path, out: &Path) -> Result<(), Failure> {
    let name = file.display().to_string();
    let (bag, out) = match args.rosbag2 {
        true => {
            let stem = input::stem(file);
            std::fs::create_dir_all(out)
                .map_err(|e| Failure::unreadable(out.display(), io_text(&e)))?;
            (Some(out), out.join(format!("{stem}_0.mcap")))
        }
        false => (None, out.to_owned()),
    };
    let out = out.as_path();
    // A first pass over the file (framing, and the GPS rows that give the clock)
    // finds its span, which places each message's log time, and its UTC clock.
    let kept = input::keep(file, &[], input::Times::Every)?;
    let span = kept.metadata.span().clone();
    let utc = input::utc_of(&name, || kept.metadata.utc(), args.utc)?;
    drop(kept);
    let start = span.start();
    let at = |s: f64| start.saturating_add((s * 1e6).round() as u64);
    let options = McapOptions {
        topics: args.messages.as_ref().map(|list| {
            list.split(',')
                .filter(|s| !s.is_empty())
                .map(str::to_owned)
                .collect()
        }),
        encoding: match args.encoding {
            Encoding::Ros2 => McapEncoding::Ros2,
            Encoding::Json => McapEncoding::Json,
        },
        zstd: args.compression == Codec::Zstd,
        start_us: args.start.map(at),
        end_us: args.end.map(at),
        utc,
        span: Some(span),
        ..McapOptions::default()
    };
    let shown = out.display().to_string();
    if out.is_dir() {
        return Err(Failure::unreadable(
            &shown,
            "is a directory (with many logs, -o names a directory; with one, the file)",
        ));
    }
    let mut partial = out.as_os_str().to_owned();
    partial.push(".partial");
    let partial = PathBuf::from(partial);
    let sink =
        std::fs::File::create(&partial).map_err(|e| Failure::unreadable(&shown, io_text(&e)))?;
    let written = write_mcap(input::source(file)?, BufWriter::new(sink), &options);
    let summary = match written {
        Ok(s) => s,
        Err(e) => {
            let _ = std::fs::remove_file(&partial);
            return Err(match e {
                McapWriteError::Read(e) => {
                    Failure::new(Status::Refused, &name, input::error_text(&e))
                }
                e => Failure::unreadable(&shown, e),
            });
        }
    };
    if let (Some(names), false) = (&options.topics, summary.missing_topics.is_empty()) {
        if summary.missing_topics.len() == names.len() {
            let _ = std::fs::remove_file(&partial);
            return Err(Failure::unknown_name(
                &name,
                format!("no topic {} in the log", summary.missing_topics.join(", ")),
            ));
        }
        let _ = writeln!(
            io::stderr(),
            "ulog: {name}: not in the log: {}",
            summary.missing_topics.join(", ")
        );
    }
    if let Err(e) = std::fs::rename(&partial, out) {
        let _ = std::fs::remove_file(&partial);
        return Err(Failure::unreadable(&shown, io_text(&e)));
    }
    let shown = match bag {
        Some(dir) => {
            let file_name = out.file_name().unwrap_or_default().to_string_lossy();
            let yaml = dir.join("metadata.yaml");
            std::fs::write(&yaml, summary.rosbag2_metadata(&file_name))
                .map_err(|e| Failure::unreadable(yaml.display(), io_text(&e)))?;
            format!("the ROS 2 bag {}", dir.display())
        }
        None => shown,
    };
    input::note_damage(&name, &summary.findings);
    let mut stderr = io::stderr();
    for s in &summary.skipped {
        let _ = writeln!(
            stderr,
            "ulog: {name}: topic `{}` ({}) left out: {}",
            s.topic, s.multi_id, s.reason
        );
    }
    if summary.short_messages > 0 {
        let _ = writeln!(
            stderr,
            "ulog: {name}: {} data message(s) shorter than their format left out",
            summary.short_messages
        );
    }
    let messages: u64 = summary.channels.iter().map(|c| c.messages).sum();
    writeln!(
        io::stdout(),
        "Wrote {shown}: {} channel(s), {messages} message(s), {} logged string(s), {} parameter value(s)",
        summary.channels.len(),
        summary.logged,
        summary.parameters
    )
    .map_err(stdout_err)
}
