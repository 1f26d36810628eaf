//! `ulog codegen`: Rust bindings for every format of a log, as source to check in.

use std::io::{self, Write};
use std::path::PathBuf;

use ulog_core::read::FindingKind;

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
/// Every format message of the log is bound or named: the formats that cannot be bound
/// (their text does not parse, they name an unknown nested type, two fields have one
/// Rust name, they nest such a format) are left out and listed, each with why, on
/// stderr and in the file's header comment.
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
    /// Only these formats, and the ones they nest (comma-separated names; as
    /// `ulog_module!(topics = […]; …)`).
    #[arg(short = 'm', long = "messages", value_name = "TOPICS")]
    messages: Option<String>,
}

pub fn run(args: &Args) -> Result<(), Failure> {
    let name = args.file.display().to_string();
    // The formats are metadata: one pass in chunks, the data not kept. The pass
    // refuses what the reader refuses, with the same message.
    let kept = input::keep(&args.file, &[], input::Times::Needed)?;
    let log = kept.log(&name)?;
    let shown = args
        .file
        .file_name()
        .map_or_else(|| name.clone(), |n| n.to_string_lossy().into_owned());
    let topics: Option<Vec<String>> = args.messages.as_ref().map(|list| {
        list.split(',')
            .filter(|s| !s.is_empty())
            .map(str::to_owned)
            .collect()
    });
    let options = ulog_codegen::Options {
        krate: Some(&args.krate),
        views: args.views,
        topics: topics.as_deref(),
    };
    // The kept log is the file without its data: the formats the reader found, at
    // other offsets. The format messages the reader could not read are not in it;
    // its findings name them, at their offsets in the file (as `ulog check` does).
    let generated = ulog_codegen::bindings_for_log(kept.metadata.bytes(), &shown, &options)
        .map_err(|e| {
            // The generator names a topic the log has no format for (with the nearest
            // name); the kept log is a log, so that is its only refusal here.
            let unknown = topics.iter().flatten().any(|t| log.format(t).is_none());
            if unknown {
                Failure::unknown_name(&name, e)
            } else {
                Failure::about(&name, e)
            }
        })?;
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
    let mut err = io::stderr().lock();
    // A text that does not parse has no name to pick it by.
    for f in log.findings().iter().filter(|_| topics.is_none()) {
        let unread = match &f.kind {
            FindingKind::InvalidFormat(_) => true,
            FindingKind::Malformed { msg_type, .. } => *msg_type == b'F',
            _ => false,
        };
        if unread {
            let _ = writeln!(
                err,
                "ulog: {name}: not bound: the format at byte {}: {}",
                f.offset,
                f.what()
            );
        }
    }
    // Texts with no name are those findings, said above at their place in the file.
    for u in generated.unbound.iter().filter(|u| u.name.is_some()) {
        let _ = writeln!(err, "ulog: {name}: not bound: {u}");
    }
    drop(err);
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
