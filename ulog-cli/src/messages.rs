//! `ulog messages`: the logged strings, as pyulog's `ulog_messages` prints them.

use std::io::{self, BufWriter, Write};
use std::path::PathBuf;

use ulog_core::read::{LogLevel, LoggedString};
use ulog_core::Value;

use crate::failure::{stdout_err, Failure};
use crate::input;

/// Print the logged strings (`L`) and tagged logged strings (`C`) as
/// `H:MM:SS.mmm LEVEL: text`, like pyulog's `ulog_messages`.
///
/// As ulog_messages does for PX4 logs (`sys_name` is `PX4`), messages are ordered by
/// timestamp. Unlike it, PX4 "events" (the `event` topic) are not decoded, so their
/// string copies (texts ending in a tab) are kept rather than replaced by the decoded
/// event; and tagged messages are printed too (ulog_messages leaves them out; use
/// `--no-tagged` for its output). Levels outside '0'..'7' print as UNKNOWN.
#[derive(Debug, clap::Args)]
#[command(
    about = "The logged strings, as pyulog's ulog_messages prints them",
    long_about
)]
pub struct Args {
    /// The ULog file.
    file: PathBuf,
    /// Leave out tagged messages (`C`), as ulog_messages does.
    #[arg(long)]
    no_tagged: bool,
}

pub fn run(args: &Args) -> Result<(), Failure> {
    let name = args.file.display().to_string();
    let file = input::open(&args.file)?;
    let log = input::parse(&name, file.bytes())?;
    let mut msgs: Vec<&LoggedString<'_>> = log
        .logged_messages()
        .iter()
        .filter(|m| !(args.no_tagged && m.tag.is_some()))
        .collect();
    let px4 = matches!(log.info_value("sys_name"), Some(Value::Str(s)) if s.as_bytes() == b"PX4");
    if px4 {
        msgs.sort_by_key(|m| m.timestamp); // stable, as Python's sort
    }
    let mut out = BufWriter::new(io::stdout().lock());
    for m in msgs {
        writeln!(out, "{}", line(m)).map_err(stdout_err)?;
    }
    out.flush().map_err(stdout_err)
}

/// `H:MM:SS.mmm LEVEL: text`.
pub fn line(m: &LoggedString<'_>) -> String {
    let total_ms = m.timestamp / 1000;
    let s = total_ms / 1000;
    format!(
        "{}:{:02}:{:02}.{:03} {}: {}",
        s / 3600,
        s / 60 % 60,
        s % 60,
        total_ms % 1000,
        level_name(m.raw_level),
        m.text
    )
}

/// The level's name as pyulog prints it: PX4 writes ASCII digits; anything else is
/// `UNKNOWN` to pyulog.
pub fn level_name(raw: u8) -> &'static str {
    match raw {
        b'0'..=b'7' => LogLevel::from_raw(raw).map_or("UNKNOWN", LogLevel::name),
        _ => "UNKNOWN",
    }
}
