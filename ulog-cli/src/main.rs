//! `ulog`: the jobs of pyulog's scripts (`ulog_info`, `ulog_messages`, `ulog_params`,
//! `ulog2csv`) with output a pyulog user can diff against, plus what this reader finds
//! in damaged logs.

mod csv;
mod failure;
mod info;
mod input;
mod messages;
mod params;
mod parquet;
mod progress;
mod pyfmt;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

use crate::failure::{Failure, Status};

/// Read PX4 ULog flight logs: summary, logged messages, parameters, CSV and Parquet export.
#[derive(Debug, Parser)]
#[command(name = "ulog", version, about, long_about = None, after_help = failure::EXIT_STATUS_HELP)]
struct Cli {
    /// No progress bars (they are only drawn when stderr is a terminal).
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
    Parquet(parquet::Args),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    progress::set_quiet(cli.quiet);
    let result = match cli.command {
        Command::Info(a) => info::run(&a),
        Command::Messages(a) => messages::run(&a),
        Command::Params(a) => params::run(&a),
        Command::Csv(a) => csv::run(&a),
        Command::Parquet(a) => parquet::run(&a),
    };
    match result {
        Ok(()) => Status::Ok.code(),
        // The reader of our output went away (`ulog csv … | head`): not an error of ours.
        Err(Failure::BrokenPipe) => Status::Ok.code(),
        Err(Failure::Message(status, m)) => {
            use std::io::Write;
            let _ = writeln!(std::io::stderr(), "ulog: {m}");
            status.code()
        }
    }
}
