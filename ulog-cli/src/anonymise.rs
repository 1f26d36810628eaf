//! `ulog anonymise`: a log without what identifies the vehicle and where it flew.

use std::path::PathBuf;

use ulog_core::write::Anonymise;

use crate::failure::Failure;
use crate::input;

/// Write a copy of a log to share: the information keys that identify the vehicle left
/// out (`sys_uuid`, `sys_mcu`, `ver_hw_subtype`, the boot console output), every
/// position moved by one rotation of the Earth that takes the first position to
/// `--to` (0° N 0° E by default), which keeps every distance and the flight's shape,
/// and the raw receiver topics (`gps_dump`, `gps_inject_data`) left out. Everything
/// else is kept byte for byte; damaged stretches are not copied.
///
/// A position is what a value holds: the fields named as one (`lat`/`lon`,
/// `latitude`/`longitude`, `ref_lat`/`ref_lon`… in any topic, nested ones too; the
/// position parameters of `vehicle_command`s that take one) and the parameters named
/// as a pair (`LPE_LAT`/`LPE_LON`) say where the log was; any two numbers of a row,
/// of the parameters or of the information that hold a latitude and a longitude
/// within 0.05° of those places (in degrees, radians or 1e-7 degrees) are moved too,
/// whatever their names, and so are such numbers in logged strings and other text.
/// Positions farther from every place named as one, in other units, or in raw bytes
/// are not found.
///
/// `--zero-utc` also leaves out the wall-clock keys (`time_ref_utc`,
/// `boot_time_utc_us`), zeroes the GPS time fields (`time_utc_usec`) and writes zeros
/// for every date and time of day in text and in PX4 events (the log file's name);
/// `--zero-start` writes 0 as the header's timestamp; `--keep` keeps keys of those
/// lists.
#[derive(Debug, clap::Args)]
#[command(
    about = "A log to share: the identity left out, positions moved",
    long_about
)]
pub struct Args {
    /// The ULog file.
    file: PathBuf,
    /// The log to write (replaced if it exists; never the input).
    #[arg(short = 'o', long = "output", value_name = "OUT.ulg")]
    output: PathBuf,
    /// Where the first position goes: `LAT,LON` in degrees.
    #[arg(long, value_name = "LAT,LON", value_parser = lat_lon, allow_hyphen_values = true)]
    to: Option<(f64, f64)>,
    /// Keep these keys (comma-separated) of those left out.
    #[arg(long, value_name = "KEYS")]
    keep: Option<String>,
    /// Also leave out the wall-clock keys, zero the GPS time fields and the dates and
    /// times written in text.
    #[arg(long)]
    zero_utc: bool,
    /// Write 0 as the log's start time (the header's timestamp, time since boot);
    /// times since the start then count from boot.
    #[arg(long)]
    zero_start: bool,
}

fn lat_lon(text: &str) -> Result<(f64, f64), String> {
    let bad = || format!("`{text}` is not LAT,LON in degrees (e.g. -33.9,151.2)");
    let (a, b) = text.split_once(',').ok_or_else(bad)?;
    let lat: f64 = a.trim().parse().map_err(|_| bad())?;
    let lon: f64 = b.trim().parse().map_err(|_| bad())?;
    if !(-90.0..=90.0).contains(&lat) || !(-180.0..=180.0).contains(&lon) {
        return Err(bad());
    }
    Ok((lat, lon))
}

pub fn run(args: &Args) -> Result<(), Failure> {
    let name = args.file.display().to_string();
    let file = input::open(&args.file)?;
    let log = input::parse(&name, file.bytes())?;
    let mut anonymise = Anonymise::new()
        .zero_utc(args.zero_utc)
        .zero_start(args.zero_start);
    if let Some((lat, lon)) = args.to {
        anonymise = anonymise.to(lat, lon);
    }
    if let Some(keys) = &args.keep {
        anonymise = anonymise.keep(keys.split(',').filter(|k| !k.is_empty()));
    }
    let edit = anonymise.edit(&log);
    crate::cut::write_edit(&name, &args.file, &args.output, (&log).into(), edit, |_| {
        None
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn positions_are_lat_comma_lon() {
        assert_eq!(lat_lon("-33.9,151.2"), Ok((-33.9, 151.2)));
        assert_eq!(lat_lon("0, 0"), Ok((0.0, 0.0)));
        for bad in ["", "1", "91,0", "0,181", "a,b", "nan,0"] {
            assert!(lat_lon(bad).is_err(), "{bad}");
        }
    }
}
