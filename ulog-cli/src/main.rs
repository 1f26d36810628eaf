//! `ulog`: the jobs of pyulog's scripts (`ulog_info`, `ulog_messages`, `ulog_params`,
//! `ulog2csv`) with output a pyulog user can diff against, plus what this reader finds
//! in damaged logs (`check`, `dump`), Rust bindings (`codegen`) and time-series plots.

// The one exception, with its safety argument: Ryu writing into a buffer (numfmt.rs).
#![deny(unsafe_code)]

mod align;
mod analyze;
mod anonymise;
mod check;
mod codegen;
mod csv;
mod cut;
mod describe;
mod dump;
mod failure;
mod gps_dump;
mod info;
mod input;
mod kml;
mod markup;
mod mcap;
mod messages;
mod numfmt;
mod params;
mod parquet;
mod plot;
mod progress;
mod pyfmt;
mod pyulog;
mod report;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

use crate::failure::{Failure, Status};

/// PX4 ULog flight logs: info, check, dump, cut; CSV, Parquet, MCAP, KML; plots.
#[derive(Debug, Parser)]
#[command(name = "ulog", version, long_about = None, after_help = failure::EXIT_STATUS_HELP)]
struct Cli {
    /// No progress bars (drawn only when stderr is a terminal).
    #[arg(short, long, global = true)]
    quiet: bool,
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    Info(info::Args),
    Messages(messages::Args),
    Params(params::Args),
    Csv(csv::Args),
    Cut(cut::Args),
    Anonymise(anonymise::Args),
    Check(check::Args),
    Codegen(codegen::Args),
    Dump(dump::Args),
    Parquet(parquet::Args),
    Mcap(mcap::Args),
    Plot(plot::Args),
    Align(align::Args),
    Analyze(analyze::Args),
    Kml(kml::Args),
    Report(report::Args),
    GpsDump(gps_dump::Args),
}

fn main() -> ExitCode {
    let cli = Cli::parse_from(pyulog::rewrite_args(std::env::args_os()));
    progress::set_quiet(cli.quiet);
    let done = |r: Result<(), Failure>| r.map(|()| Status::Ok);
    let result = match cli.command {
        Command::Info(a) => done(info::run(&a)),
        Command::Messages(a) => done(messages::run(&a)),
        Command::Params(a) => done(params::run(&a)),
        Command::Csv(a) => done(csv::run(&a)),
        Command::Cut(a) => done(cut::run(&a)),
        Command::Anonymise(a) => done(anonymise::run(&a)),
        Command::Check(a) => check::run(&a),
        Command::Codegen(a) => done(codegen::run(&a)),
        Command::Dump(a) => done(dump::run(&a)),
        Command::Parquet(a) => done(parquet::run(&a)),
        Command::Mcap(a) => done(mcap::run(&a)),
        Command::Plot(a) => done(plot::run(&a)),
        Command::Align(a) => done(align::run(&a)),
        Command::Analyze(a) => done(analyze::run(&a)),
        Command::Kml(a) => done(kml::run(&a)),
        Command::Report(a) => done(report::run(&a)),
        Command::GpsDump(a) => done(gps_dump::run(&a)),
    };
    match result {
        Ok(status) => status.code(),
        // The reader of our output went away (`ulog csv … | head`): not an error of ours.
        Err(Failure::BrokenPipe) => Status::Ok.code(),
        Err(Failure::Message(status, m)) => {
            use std::io::Write;
            let _ = writeln!(std::io::stderr(), "ulog: {m}");
            status.code()
        }
    }
}
