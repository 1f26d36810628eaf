//! `ulog report`: one self-contained HTML page with what Flight Review shows of a log.

mod analysis;
mod compare;
mod facts;
mod flight;
mod html;
mod pass;
mod plots;
mod spec;
mod table;
mod timeline;

use std::io::Write;
use std::path::{Path, PathBuf};

use ulog_core::analysis::{AnalyzeOptions, FlightAnalyzer};
use ulog_core::events::EventOptions;

use crate::failure::{io_text, stdout_err, Failure, Status};
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
/// Then what the flight analysis found (the library's `ulog_core::analysis`, as `ulog
/// analyze` reports it, read in the same pass): Flight Review v2's diagnostics
/// (battery brownout, EKF failure, GPS interference, motor failure, RC loss) as a
/// table and as marks on every plot, the vibration status in the header, the power
/// spectral densities of the raw gyro and accelerometer and of the controllers'
/// outputs while armed, the gyro's and accelerometer's spectrograms, and the rate
/// controllers' step responses.
///
/// Several files: one page comparing the flights. The standard plots of every log
/// overlaid, one colour per log (a log's own lines differ by dashes), each on time
/// since its first takeoff (or its start where it never takes off); every log's
/// diagnostics in one table; and the parameters that differ across the logs (as
/// `ulog params A --diff B --diff C` lists them).
///
/// Then the tables: logged messages and events (filterable by level), parameters
/// changed from their defaults and during the flight, information and
/// multi-information. Text is escaped; characters HTML cannot hold (control characters
/// but tab and line breaks, noncharacters) are shown as U+FFFD.
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
    /// The ULog file; several: one page comparing them.
    #[arg(required = true, value_name = "FILE")]
    files: Vec<PathBuf>,
    /// The page to write (default: `<FILE stem>_report.html` next to FILE; comparing
    /// logs, `<first stem>_compare.html` next to the first).
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

/// What the passes over one log give the page: its plots, the flight analysis, the
/// track.
struct Drawing {
    plots: Vec<plots::Plot>,
    missing: Vec<plots::Missing>,
    track: Option<flight::Track>,
    flight: ulog_core::analysis::FlightAnalysis,
    /// The standard plots came out empty: one plot per topic instead.
    every_topic: bool,
}

/// Reads a log's plots and its flight analysis in the second pass over `input` (a
/// third, every topic, only for a log whose standard plots turned out empty).
fn draw(
    input: &crate::input::Input,
    name: &str,
    survey: &pass::Survey,
    log: &ulog_core::ULog<'_>,
) -> Result<Drawing, Failure> {
    let rows = &survey.rows;
    let span = log.span();
    let mut analyzer = FlightAnalyzer::new(&AnalyzeOptions::default());
    let mut standard = plots::standard(log, rows, span);
    let mut attitude = flight::attitude(log, rows, span);
    let mut track = flight::track(log, rows, TRACK_POINTS);
    // A log with none of the standard topics has every topic plotted: read in the
    // same pass.
    let mut others = (plots::none_found(&standard) && attitude.is_none())
        .then(|| plots::every_topic(log, rows, span, FIELDS_PER_TOPIC));
    let mut routes = pass::Routes::new(log.subscriptions().len());
    plots::route(&mut standard, &mut routes);
    attitude.route(&mut routes);
    if let Some(t) = &mut track {
        t.route(&mut routes);
    }
    if let Some(o) = &mut others {
        plots::route_topics(o, &mut routes);
    }
    pass::read(input, name, survey, routes, Some(&mut analyzer))?;

    let flight = analyzer.finish();
    let (mut plots, missing) = plots::finish_standard(standard);
    // Attitude after altitude, as Flight Review orders them.
    let at = plots
        .iter()
        .position(|p| p.id == "altitude")
        .map_or(0, |i| i + 1);
    plots.splice(at..at, attitude.finish());
    let every_topic = plots.is_empty();
    if every_topic {
        let others = match others {
            Some(o) => o,
            // Standard topics whose values all turned out missing: one more pass.
            None => {
                let mut o = plots::every_topic(log, rows, span, FIELDS_PER_TOPIC);
                let mut routes = pass::Routes::new(log.subscriptions().len());
                plots::route_topics(&mut o, &mut routes);
                pass::read(input, name, survey, routes, None)?;
                o
            }
        };
        plots = plots::finish_topics(others);
    }
    Ok(Drawing {
        plots,
        missing,
        track,
        flight,
        every_topic,
    })
}

/// The report of a log read in passes over the file ([`pass`]): the first keeps the
/// metadata and counts the rows, the second reads the topics the page draws and runs
/// the flight analysis ([`draw`]). The memory is what the page holds, not the log.
/// Several files: the page comparing them ([`compare`]).
pub fn run(args: &Args) -> Result<(), Failure> {
    if args.files.len() > 1 {
        return compare::run(args);
    }
    let file = &args.files[0];
    let name = file.display().to_string();
    let input = crate::input::Input::open(file)?;
    let survey = pass::survey(&input, &name)?;
    let log = survey
        .metadata
        .log()
        .map_err(|e| Failure::new(Status::Refused, &name, input::error_text(&e)))?;
    // One time axis: the log's span (`TimeSpan`), which stale or stray timestamps
    // do not stretch; the rows far outside it are listed with the damage.
    let span = log.span().clone();
    let start = span.start();
    let Drawing {
        plots,
        missing,
        track,
        flight,
        every_topic,
    } = draw(&input, &name, &survey, &log)?;
    let (modes, mut marks, armed_s) = analysis::timeline(&flight, &span);
    let figures = flight::figures(&flight);
    let (diagnostics, diagnostic_marks) = analysis::diagnostics(&flight, &span);
    marks.extend(diagnostic_marks);
    let mut notes = Vec::new();
    if every_topic {
        notes.push(
            "The log has none of the topics of PX4's standard plots: below is one plot per \
             topic, with its first numeric fields."
                .to_owned(),
        );
    }
    if modes.is_empty() {
        notes.push("No flight modes: the log has no vehicle_status.".to_owned());
    }
    let track = track.and_then(flight::Track::finish);
    let metadata = &survey.metadata;
    let messages = facts::messages(&log, || metadata.events(&EventOptions::default()), start);
    for (t, level, text) in &messages {
        if html::severity(level) <= 3 {
            marks.push(timeline::Mark {
                t: *t,
                kind: "error",
                text: text.clone(),
            });
        }
    }
    marks.sort_by(|a, b| a.t.total_cmp(&b.t));
    let (info, multi) = facts::information(&log);
    let header = facts::header(
        &log,
        metadata.utc(),
        &survey.summary.findings,
        start,
        &figures,
        armed_s,
        &flight,
    );
    let page = html::Page {
        title: file
            .file_name()
            .map_or_else(|| name.clone(), |n| n.to_string_lossy().into_owned()),
        header,
        missing,
        notes,
        params_vs_defaults: facts::params_vs_defaults(&log),
        params_changed: facts::params_changed(&log, start),
        messages,
        info,
        multi,
        diagnostics,
        analysis_notes: flight.notes.clone(),
        params_across: None,
        drawn: html::Drawn {
            origin_us: start,
            duration: span.duration_s(),
            x_label: "seconds since the log's start",
            modes,
            marks,
            plots,
            track,
            analysis: analysis::xy_plots(&flight),
            heatmaps: analysis::heatmaps(&flight, &span),
        },
    };
    let out = args.output.clone().unwrap_or_else(|| default_output(file));
    write_page(args, &page, &name, &out)
}

/// Writes `page` to `out`, says so, and opens it when asked.
fn write_page(args: &Args, page: &html::Page, name: &str, out: &Path) -> Result<(), Failure> {
    let text = html::render(page).map_err(|e| Failure::about(name, e))?;
    let shown = out.display().to_string();
    std::fs::write(out, text.as_bytes()).map_err(|e| Failure::unreadable(&shown, io_text(&e)))?;
    writeln!(
        std::io::stdout(),
        "Wrote {shown}: {} plot(s), {} message(s), {} KB",
        page.drawn.plots.len(),
        page.messages.len(),
        text.len().div_ceil(1024)
    )
    .map_err(stdout_err)?;
    if args.open {
        open_in_browser(out).map_err(|e| Failure::about(&shown, e))?;
    }
    Ok(())
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
