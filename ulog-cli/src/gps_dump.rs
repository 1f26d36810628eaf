//! `ulog gps-dump`: the raw bytes between the autopilot and its GPS receivers (topic
//! `gps_dump`), as pyulog's `extract_gps_dump` writes them.

use std::io::Write as _;
use std::path::PathBuf;

use ulog_core::track::{gps_dump, GpsDumpChunk, GPS_DUMP_TOPIC};

use crate::failure::{io_text, Failure};
use crate::input;

/// Extract the raw communication with the GPS receivers (topic `gps_dump`, all
/// instances, in file order), as pyulog's `extract_gps_dump` writes it: per receiver
/// instance N, `<FILE stem>_N_to_device.dat` (messages with bit 7 of `len` set) and
/// `<FILE stem>_N_from_device.dat`, each the first `len & 0x7f` bytes of `data` of its
/// messages. Without `-i`, one pair of files for every instance in the log; with `-i
/// N`, that instance's pair only (both written, even if empty). The receiver is field
/// `instance` (the topic instance in logs without it). A `len` beyond the `data` array
/// is a warning and the bytes there are written.
#[derive(Debug, clap::Args)]
#[command(
    about = "Raw GPS receiver bytes, as pyulog's extract_gps_dump",
    long_about
)]
pub struct Args {
    /// The ULog file.
    file: PathBuf,
    /// Output directory (created if missing; default: the current directory).
    #[arg(short = 'o', long = "output", value_name = "DIR")]
    output: Option<PathBuf>,
    /// Only this receiver instance (0 the main receiver, 1 the secondary).
    #[arg(short = 'i', long = "instance", value_name = "N")]
    instance: Option<u8>,
    #[arg(short = 'x', long, help = crate::pyulog::IGNORE_HELP)]
    ignore: bool,
}

pub fn run(args: &Args) -> Result<(), Failure> {
    let name = args.file.display().to_string();
    // One pass in chunks, keeping the metadata and the rows of `gps_dump`.
    let kept = input::keep(&args.file, &[GPS_DUMP_TOPIC], input::Times::Every)?;
    let log = kept.log(&name)?;
    let chunks = gps_dump(&log).map_err(|e| crate::kml::track_failure(&name, e))?;
    input::note_damage(&name, log.findings());
    if chunks.is_empty() {
        return Err(Failure::unknown_name(&name, "topic `gps_dump` has no data"));
    }
    let mut stderr = std::io::stderr().lock();
    for c in chunks.iter().filter(|c| c.is_clamped()) {
        let _ = writeln!(
            stderr,
            "ulog: {name}: warning: gps_dump message {} (instance {}): len {} is more than \
             its data's {} bytes; writing those",
            c.row,
            c.instance,
            c.len & 0x7f,
            c.data.len()
        );
    }
    if !log.dropouts().is_empty() {
        let _ = writeln!(
            stderr,
            "ulog: {name}: warning: the log has {} dropouts: bytes may be missing",
            log.dropouts().len()
        );
    }
    let instances: Vec<u8> = match args.instance {
        Some(i) => vec![i],
        None => {
            let mut v: Vec<u8> = chunks.iter().map(|c| c.instance).collect();
            v.sort_unstable();
            v.dedup();
            v
        }
    };
    let dir = args.output.clone().unwrap_or_default();
    if !dir.as_os_str().is_empty() {
        std::fs::create_dir_all(&dir)
            .map_err(|e| Failure::unreadable(dir.display(), io_text(&e)))?;
    }
    let stem = input::stem(&args.file);
    for instance in instances {
        for to_device in [true, false] {
            let which = if to_device { "to" } else { "from" };
            let path = dir.join(format!("{stem}_{instance}_{which}_device.dat"));
            let bytes = bytes_of(&chunks, instance, to_device);
            std::fs::write(&path, &bytes).map_err(|e| Failure::io(path.display(), &e))?;
            writeln!(
                std::io::stdout(),
                "Writing {} ({} bytes)",
                path.display(),
                bytes.len()
            )
            .map_err(crate::failure::stdout_err)?;
        }
    }
    Ok(())
}

/// The bytes of the messages of receiver `instance` in one direction, in file order.
fn bytes_of(chunks: &[GpsDumpChunk<'_>], instance: u8, to_device: bool) -> Vec<u8> {
    chunks
        .iter()
        .filter(|c| c.instance == instance && c.to_device == to_device)
        .flat_map(|c| c.data.iter().copied())
        .collect()
}
