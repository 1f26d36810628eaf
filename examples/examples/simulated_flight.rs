//! Logs a simulated flight from Rust with derived types, then reads the log back.
//!
//! ```text
//! cargo run -p ulog-examples --example simulated_flight -- [OUT.ulg]
//! ```
//!
//! The flight (take-off, a circle at 10 m, landing) is written by
//! [`ulog_examples::simulation::simulate_flight`] through the typed writer: each topic
//! is a `#[derive(ULogMessage)]` struct, subscribed once, then written value by value.
//! The log (default `simulated_flight.ulg` in the current directory) opens in PX4's
//! tools and pyulog; `ulog info OUT.ulg` shows it, and the `flight_summary` example
//! analyses it.

use std::fs::File;
use std::io::BufWriter;
use std::process::ExitCode;

use ulog_core::{LogFile, Value, WriteError};
use ulog_examples::simulation::{simulate_flight, VehicleLocalPosition};

fn main() -> ExitCode {
    let path = std::env::args_os()
        .nth(1)
        .unwrap_or_else(|| "simulated_flight.ulg".into());
    let written = match File::create(&path) {
        Ok(f) => simulate_flight(BufWriter::new(f)).map_err(|e: WriteError| e.to_string()),
        Err(e) => Err(e.to_string()),
    };
    if let Err(e) = written {
        eprintln!("simulated_flight: {}: {e}", path.to_string_lossy());
        return ExitCode::FAILURE;
    }
    let file = match LogFile::open(&path) {
        Ok(f) => f,
        Err(e) => {
            eprintln!("simulated_flight: {e}");
            return ExitCode::FAILURE;
        }
    };
    let log = match file.parse() {
        Ok(l) => l,
        Err(e) => {
            eprintln!("simulated_flight: {e}");
            return ExitCode::FAILURE;
        }
    };
    println!(
        "wrote {} ({} bytes, {} messages, {} findings)",
        path.to_string_lossy(),
        file.bytes().len(),
        log.message_count(),
        log.findings().len()
    );
    for t in log.topics() {
        println!("  {:<24} {:>5} rows", t.name(), t.len());
    }
    // Read one topic back through the same binding that wrote it.
    let peak = log.read::<VehicleLocalPosition>(0).map(|rows| {
        rows.iter()
            .filter_map(Result::ok)
            .map(|p| -p.z)
            .fold(0.0f32, f32::max)
    });
    match peak {
        Ok(p) => println!("peak altitude: {p:.1} m"),
        Err(e) => println!("vehicle_local_position: {e}"),
    }
    if let Some(Value::F32(v)) = log.param_changes().first().map(|c| c.kv.value()) {
        println!("parameter change: MPC_XY_CRUISE -> {v}");
    }
    ExitCode::SUCCESS
}
