//! px4-ulog master (the snapshot in the peers folder, not the crates.io release) on the
//! harness's workloads. bench/run writes a Cargo package for it under `target/` whose
//! `px4-ulog` dependency points at the snapshot by path, so this file is not part of
//! the bench workspace.
//!
//! ```text
//! px4-master framing FILE   LogParser::consume_bytes, data messages counted
//! px4-master stream FILE    the same code as `peers px4-stream`
//! px4-master full FILE      the same code as `peers px4-full`
//! ```

use std::process::ExitCode;

#[path = "../src/px4.rs"]
mod px4;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let a: Vec<&str> = args.iter().map(String::as_str).collect();
    let result = match a.as_slice() {
        ["framing", f] => px4::framing(f),
        ["stream", f] => px4::stream(f),
        ["full", f] => px4::full(f),
        _ => {
            eprintln!("usage: px4-master (framing|stream|full) FILE");
            return ExitCode::from(2);
        }
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("px4-master: {e}");
            ExitCode::FAILURE
        }
    }
}
