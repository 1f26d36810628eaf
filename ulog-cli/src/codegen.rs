//! `ulog codegen`: Rust bindings for every format of a log, as source to check in.

use std::io::{self, Write};
use std::path::PathBuf;

use crate::failure::{io_text, stdout_err, Failure};
use crate::input;

/// Write Rust bindings for every message format of a log: one struct per format with
/// its `ULogMessage` implementation (nested types, arrays and padding included), and
/// `visit_bindings`. This is the code `ulog_core::ulog_module!` generates at
/// compile time, for projects that want it checked in; use it as a module
/// (`mod bindings;`) of a crate that depends on `ulog-core`. The source is laid out by
/// prettyplease; put `#[rustfmt::skip]` on the `mod` to keep it identical to what this
/// command writes (so that a check can regenerate and compare).
///
/// Formats that cannot be bound (they do not parse, or name unknown nested types) are
/// left out and listed in the file's header comment and on stderr.
#[derive(Debug, clap::Args)]
#[command(about = "Rust bindings for every message format of a log", long_about)]
pub struct Args {
    /// The ULog file.
    file: PathBuf,
    /// Write to this file instead of stdout.
    #[arg(short, long, value_name = "FILE")]
    output: Option<PathBuf>,
    /// The path generated code uses for the runtime crate (when `ulog-core` is
    /// renamed or re-exported).
    #[arg(long = "crate", value_name = "PATH", default_value = "::ulog_core")]
    krate: String,
    /// Bindings that payloads can be borrowed as, without a copy (`TypedRows::views`):
    /// `#[repr(C)]` structs of little-endian fields, without the trailing padding that
    /// PX4 does not write (as `ulog_module!(views; …)`).
    #[arg(long)]
    views: bool,
}

pub fn run(args: &Args) -> Result<(), Failure> {
    let name = args.file.display().to_string();
    let file = input::open(&args.file)?;
    // Refuse what the reader refuses, with the same message.
    input::parse(&name, file.bytes())?;
    let shown = args
        .file
        .file_name()
        .map_or_else(|| name.clone(), |n| n.to_string_lossy().into_owned());
    let options = ulog_codegen::Options {
        krate: Some(&args.krate),
        views: args.views,
    };
    let generated = ulog_codegen::bindings_for_log(file.bytes(), &shown, &options)
        .map_err(|e| Failure::about(&name, e))?;
    if let Some(first) = generated.problems.first() {
        return Err(Failure::about(
            &name,
            format!(
                "{} format(s) cannot be bound, first: {}",
                generated.problems.len(),
                first.replace('\n', " ")
            ),
        ));
    }
    for s in &generated.skipped {
        let _ = writeln!(io::stderr(), "ulog: {name}: skipped {s}");
    }
    match &args.output {
        Some(path) => std::fs::write(path, generated.source.as_bytes())
            .map_err(|e| Failure::unreadable(path.display(), io_text(&e))),
        None => {
            let mut out = io::stdout().lock();
            out.write_all(generated.source.as_bytes())
                .and_then(|()| out.flush())
                .map_err(stdout_err)
        }
    }
}
