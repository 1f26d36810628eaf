//! `ulog report`: one self-contained HTML page with what Flight Review shows of a log.

mod facts;
mod flight;
mod html;
mod plots;
mod spec;
mod table;

use std::io::Write;
use std::path::{Path, PathBuf};

use crate::failure::{io_text, stdout_err, Failure};
use crate::input;

/// Write a flight report: one HTML file that opens from disk in any browser, with no
/// network and no server, holding what Flight Review shows of a log.
///
/// The header: vehicle and airframe, hardware, software version and release, start
/// time (UTC where the log has GPS time or `boot_time_utc_us`), duration, time armed,
/// distance flown, highest altitude and fastest horizontal speed (from
/// `vehicle_local_position`), battery used, the damage the reader found (truncation,
/// corrupt ranges) and dropouts.
///
/// The plots, each drawn only where the log has its topics (old and new firmware
/// names): altitude, roll, pitch and yaw with their setpoints, angular rates, local
/// position and velocity with setpoints, the track in local metres, manual control
/// inputs, actuator controls, motors and outputs, raw IMU, vibration and clipping,
/// battery, GPS fix, satellites and noise, estimator test ratios, CPU and RAM load and
/// the magnetic field norm; a note names the plots the log has no data for. A log
/// without any of them (not PX4's) gets one plot per topic. Flight modes are coloured
/// bands behind every plot; arming, takeoff, landing and logged errors are marked.
/// Zooming one plot (drag; double-click to reset) zooms all; hovering shows every
/// line's value; legend entries hide lines.
///
/// Then the tables: logged messages and events (filterable by level), parameters
/// changed from their defaults and during the flight, information and
/// multi-information.
///
/// Long series are thinned so that the file stays small: the log's time span is cut
/// into 2000 columns; a topic with at most 16000 rows keeps every row (full detail on
/// zoom), a longer one keeps per column the first and last row and the rows with each
/// line's lowest and highest value.
#[derive(Debug, clap::Args)]
#[command(
    about = "A flight report: one HTML page of plots and tables",
    long_about
)]
pub struct Args {
    /// The ULog file.
    file: PathBuf,
    /// The page to write (default: `<FILE stem>_report.html` next to FILE).
    #[arg(short = 'o', long = "output", value_name = "OUT")]
    output: Option<PathBuf>,
    /// Open the page in the default browser when written.
    #[arg(long)]
    open: bool,
}

/// The most points of the track.
const TRACK_POINTS: usize = 5000;
/// The most fields per topic plotted for a log without PX4's topics.
const FIELDS_PER_TOPIC: usize = 8;

pub fn run(args: &Args) -> Result<(), Failure> {
    let name = args.file.display().to_string();
    let file = input::open(&args.file)?;
    let log = input::parse(&name, file.bytes())?;
    let start = time_origin(&log);
    let end = log.last_timestamp().max(start);

    let timeline = flight::timeline(&log, start, end);
    let figures = flight::figures(&log);
    let (mut plots, missing) = plots::standard(&log, start, end);
    // Attitude after altitude, as Flight Review orders them.
    let at = plots
        .iter()
        .position(|p| p.id == "altitude")
        .map_or(0, |i| i + 1);
    plots.splice(at..at, flight::attitude(&log, start, end));
    let mut notes = Vec::new();
    if plots.is_empty() {
        notes.push(
            "The log has none of the topics of PX4's standard plots: below is one plot per \
             topic, with its first numeric fields."
                .to_owned(),
        );
        plots = plots::every_topic(&log, start, end, FIELDS_PER_TOPIC);
    }
    if timeline.modes.is_empty() {
        notes.push("No flight modes: the log has no vehicle_status.".to_owned());
    }
    let track = flight::track(&log, TRACK_POINTS);
    let mut marks = timeline.marks;
    let messages = facts::messages(&log, start);
    for (t, level, text) in &messages {
        if html::severity(level) <= 3 {
            marks.push(flight::Mark {
                t: *t,
                kind: "error",
                text: text.clone(),
            });
        }
    }
    marks.sort_by(|a, b| a.t.total_cmp(&b.t));
    let (info, multi) = facts::information(&log);
    let page = html::Page {
        title: args
            .file
            .file_name()
            .map_or_else(|| name.clone(), |n| n.to_string_lossy().into_owned()),
        header: facts::header(&log, start, &figures, timeline.armed_s),
        missing,
        notes,
        params_vs_defaults: facts::params_vs_defaults(&log),
        params_changed: facts::params_changed(&log, start),
        messages,
        info,
        multi,
        drawn: html::Drawn {
            origin_us: start,
            duration: (end - start) as f64 / 1e6,
            modes: timeline.modes,
            marks,
            plots,
            track,
        },
    };
    let text = html::render(&page).map_err(|e| Failure::about(&name, e))?;
    let out = match &args.output {
        Some(p) => p.clone(),
        None => default_output(&args.file),
    };
    let shown = out.display().to_string();
    std::fs::write(&out, text.as_bytes()).map_err(|e| Failure::unreadable(&shown, io_text(&e)))?;
    writeln!(
        std::io::stdout(),
        "Wrote {shown}: {} plot(s), {} message(s), {} KB",
        page.drawn.plots.len(),
        page.messages.len(),
        text.len().div_ceil(1024)
    )
    .map_err(stdout_err)?;
    if args.open {
        open_in_browser(&out).map_err(|e| Failure::about(&shown, e))?;
    }
    Ok(())
}

/// Time zero of the page: the header's timestamp, or where that is zero (a writer
/// that does not set it, or a log whose uploader zeroed it) the first data timestamp.
fn time_origin(log: &ulog_core::ULog<'_>) -> u64 {
    let header = log.start_timestamp();
    if header != 0 {
        return header;
    }
    log.topics()
        .filter_map(|t| {
            let mut clock = ulog_core::read::Unwrapper::new(t.timestamp_field());
            t.payloads().next().and_then(|p| clock.push(p))
        })
        .min()
        .unwrap_or(0)
}

/// `<FILE without its extension>_report.html`, next to FILE.
fn default_output(file: &Path) -> PathBuf {
    let stem = file
        .file_stem()
        .map_or_else(|| "report".into(), |s| s.to_string_lossy().into_owned());
    file.with_file_name(format!("{stem}_report.html"))
}

/// Hands the page to the desktop's opener.
fn open_in_browser(path: &Path) -> Result<(), String> {
    let mut cmd = if cfg!(target_os = "macos") {
        std::process::Command::new("open")
    } else if cfg!(windows) {
        let mut c = std::process::Command::new("cmd");
        c.args(["/C", "start", ""]);
        c
    } else {
        std::process::Command::new("xdg-open")
    };
    cmd.arg(path)
        .spawn()
        .map(drop)
        .map_err(|e| format!("cannot open it in a browser: {}", io_text(&e)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_output_is_next_to_the_log() {
        assert_eq!(
            default_output(Path::new("logs/flight.ulg")),
            Path::new("logs/flight_report.html")
        );
    }
}
