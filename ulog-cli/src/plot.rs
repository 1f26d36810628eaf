//! `ulog plot`: a time-series chart of chosen fields, as SVG or PNG.

mod backend;
mod decimate;
mod draw;
mod font;
mod markers;
mod series;
mod spec;

use std::io::Write;
use std::path::{Path, PathBuf};

use plotters::prelude::*;

use crate::failure::{io_text, stdout_err, Failure};
use crate::input;
use backend::WithFont;
use font::Glyphs;
use markers::Marker;
use series::Series;
use spec::FieldSpec;

/// Plot fields over time as SVG or PNG: seconds since log start on the x axis, one line
/// per field, a legend, units where the field's name tells them; parameter changes and
/// logged errors marked.
///
/// Markers are dashed vertical lines with their text: parameters set during the flight
/// (`NAME=value`) and logged messages of level ERROR or worse (EMERGENCY, ALERT,
/// CRITICAL, ERROR; tagged ones too), cut to 48 characters; markers of one kind within 8
/// pixels of each other share a line.
///
/// Fields are `TOPIC.FIELD`: `vehicle_local_position.z`, nested and array elements as in
/// the CSV columns (`esc_status.esc[2].esc_rpm`, `vehicle_attitude.q[0]`); a whole array
/// (`vehicle_attitude.q`) gives one line per element. `TOPIC:N.FIELD` picks instance
/// (multi_id) N; without it, the lowest instance the log has. Several fields are given
/// comma-separated or as separate arguments.
///
/// Units come from PX4 naming: whole names (`x`, `y`, `z` in position topics: m; `vx`:
/// m/s; `rollspeed`: rad/s; `temperature`: °C; …) and suffixes (`_m` m, `_m_s` m/s,
/// `_m_s2` m/s², `_rad` rad, `_rad_s` rad/s, `_deg` deg, `_v`/`voltage` V, `_a`/`current`
/// A, `_c` °C, `_hpa`, `_pa`, `_ga`, `_us`, `_hz`, `_mah`, `_rpm`, …); unknown units are
/// left out.
///
/// Long series are thinned to at most 4 points per pixel column (the first, last, lowest
/// and highest of each column), so spikes stay visible and files stay small. NaN and
/// infinite values are left out.
///
/// In SVG, characters XML cannot hold (control characters but tab and line breaks,
/// such as the ESC of a logged message's colours; noncharacters) are drawn as U+FFFD.
#[derive(Debug, clap::Args)]
#[command(about = "Plot fields over time as SVG or PNG", long_about)]
pub struct Args {
    /// The ULog file.
    file: PathBuf,
    /// The fields to plot: `TOPIC[:N].FIELD`, comma-separated or as separate arguments.
    #[arg(
        value_name = "TOPIC.FIELD",
        required = true,
        value_delimiter = ',',
        value_parser = parse_spec
    )]
    fields: Vec<FieldSpec>,
    /// The picture to write: `.svg` or `.png` picks the format (default: `<FILE stem>_plot.svg`
    /// next to FILE).
    #[arg(short = 'o', long = "output", value_name = "OUT", value_parser = parse_output)]
    output: Option<PathBuf>,
    /// The picture's size in pixels, `WIDTHxHEIGHT`.
    #[arg(long, value_name = "WxH", default_value = "1280x720", value_parser = parse_size)]
    size: (u32, u32),
    /// The caption (default: the file name).
    #[arg(long, value_name = "TEXT")]
    title: Option<String>,
    /// Start the time axis at this time since the log's start: seconds (`90`,
    /// `90.5`), `M:SS` or `H:MM:SS` (`1:30`, `1:30.5`) (default: the first point).
    #[arg(long, value_name = "TIME", value_parser = input::seconds)]
    start: Option<f64>,
    /// End the time axis at this time since the log's start, written as for `--start`
    /// (default: the last point).
    #[arg(long, value_name = "TIME", value_parser = input::seconds)]
    end: Option<f64>,
    /// Label the time axis with UTC times of day (`08:25:44`) instead of seconds since
    /// the log's start, from the log's GPS time or its `boot_time_utc_us` (`ulog info`
    /// says which); `--start` and `--end` are still times since the start.
    #[arg(long)]
    utc: bool,
    /// Not plot's: `csv`'s boot-time range. Refused with a pointer to `--start`.
    #[arg(long = "time-start", hide = true, value_name = "S", value_parser = not_plots)]
    _time_start: Option<String>,
    /// Not plot's: `csv`'s boot-time range. Refused with a pointer to `--end`.
    #[arg(long = "time-end", hide = true, value_name = "S", value_parser = not_plots)]
    _time_end: Option<String>,
    /// Do not mark parameter changes.
    #[arg(long = "no-params")]
    no_params: bool,
    /// Do not mark logged error messages.
    #[arg(long = "no-messages")]
    no_messages: bool,
    /// One panel per line, one above the other, sharing the time axis.
    #[arg(long)]
    separate: bool,
}

/// `--time-start`/`--time-end` given to `plot`: always an error that names plot's flags.
fn not_plots(_: &str) -> Result<String, String> {
    Err(
        "plot's time range is `--start`/`--end` (time since the log's start); \
         `--time-start`/`--time-end` are csv's (boot-time seconds)"
            .into(),
    )
}

fn parse_spec(s: &str) -> Result<FieldSpec, String> {
    FieldSpec::parse(s)
}

/// The output formats, by file extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Format {
    Svg,
    Png,
}

fn format_of(path: &Path) -> Option<Format> {
    let ext = path.extension()?.to_str()?.to_ascii_lowercase();
    match ext.as_str() {
        "svg" => Some(Format::Svg),
        "png" => Some(Format::Png),
        _ => None,
    }
}

fn parse_output(s: &str) -> Result<PathBuf, String> {
    let p = PathBuf::from(s);
    match format_of(&p) {
        Some(_) => Ok(p),
        None => Err("the file name must end in `.svg` or `.png` (that picks the format)".into()),
    }
}

fn parse_size(s: &str) -> Result<(u32, u32), String> {
    const LIMIT: u32 = 10_000;
    let bad = || format!("expected WIDTHxHEIGHT in pixels (e.g. `1280x720`), each 100 to {LIMIT}");
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(bad)?;
    let w: u32 = w.trim().parse().map_err(|_| bad())?;
    let h: u32 = h.trim().parse().map_err(|_| bad())?;
    if !(100..=LIMIT).contains(&w) || !(100..=LIMIT).contains(&h) {
        return Err(bad());
    }
    Ok((w, h))
}

pub fn run(args: &Args) -> Result<(), Failure> {
    let name = args.file.display().to_string();
    // One pass in chunks, keeping the metadata (parameter changes, messages) and the
    // rows of the topics plotted.
    let topics: Vec<&str> = args.fields.iter().map(|f| f.topic.as_str()).collect();
    let kept = input::keep(&args.file, &topics, input::Times::Every)?;
    let log = kept.log(&name)?;
    let span = log.span();
    let start_us = span.start();
    let utc_start = input::utc_of(&name, || kept.metadata.utc(), args.utc)?.map(|c| c.at(start_us));

    let mut all: Vec<Series> = Vec::new();
    for spec in &args.fields {
        all.extend(series::read(&log, &name, spec, span)?);
    }
    let (x0, x1) = time_axis(&all, args.start, args.end).map_err(|e| Failure::about(&name, e))?;
    let (width, height) = args.size;
    // About the plot's width in pixels (the picture less the axis labels and margins).
    let columns = (width as usize).saturating_sub(110).max(1);
    for s in &mut all {
        s.points.retain(|&(x, _)| x >= x0 && x <= x1);
        s.points = decimate::decimate(&s.points, x0, x1, columns);
    }

    let mut marks: Vec<Marker> = Vec::new();
    if !args.no_params {
        marks.extend(markers::param_changes(&log, start_us));
    }
    if !args.no_messages {
        marks.extend(markers::errors(&log, start_us));
    }
    marks.retain(|m| m.x >= x0 && m.x <= x1);
    let marks = markers::merge_close(marks, (x1 - x0) / columns as f64 * 8.0);

    let title = match &args.title {
        Some(t) => t.clone(),
        None => args
            .file
            .file_name()
            .map_or_else(|| name.clone(), |n| n.to_string_lossy().into_owned()),
    };
    let chart = draw::Chart {
        title: &title,
        series: &all,
        markers: &marks,
        x_range: (x0, x1),
        separate: args.separate,
        utc_start,
    };
    let out = match &args.output {
        Some(p) => p.clone(),
        None => default_output(&args.file),
    };
    let shown = out.display().to_string();
    let bytes = match format_of(&out) {
        Some(Format::Png) => png_bytes(&chart, width, height),
        _ => svg_bytes(&chart, width, height),
    }
    .map_err(|e| Failure::about(&shown, e))?;
    std::fs::write(&out, bytes).map_err(|e| Failure::unreadable(&shown, io_text(&e)))?;

    let points: usize = all.iter().map(|s| s.points.len()).sum();
    let count = |k| marks.iter().filter(|m| m.kind == k).count();
    writeln!(
        std::io::stdout(),
        "Wrote {shown}: {} line(s), {points} points drawn from {x0:.3} s to {x1:.3} s, {} parameter change marker(s), {} error message marker(s)",
        all.len(),
        count(markers::Kind::Param),
        count(markers::Kind::Error),
    )
    .map_err(stdout_err)
}

/// `<FILE without its extension (`.ulg`, `.ulog`)>_plot.svg`, next to FILE.
fn default_output(file: &Path) -> PathBuf {
    let stem = file
        .file_stem()
        .map_or_else(|| "plot".into(), |s| s.to_string_lossy().into_owned());
    file.with_file_name(format!("{stem}_plot.svg"))
}

/// The time axis: the options where given, else the extent of the data.
fn time_axis(
    series: &[Series],
    start: Option<f64>,
    end: Option<f64>,
) -> Result<(f64, f64), String> {
    let xs = series.iter().flat_map(|s| s.points.iter().map(|p| p.0));
    let (lo, hi) = xs.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| {
        (lo.min(x), hi.max(x))
    });
    if lo > hi && (start.is_none() || end.is_none()) {
        return Err("the chosen fields have no data to plot".into());
    }
    let x0 = start.unwrap_or(lo);
    let x1 = end.unwrap_or(hi);
    if !x0.is_finite() || !x1.is_finite() {
        return Err("the time range must be finite".into());
    }
    if x0 > x1 || (x0 == x1 && (start.is_some() || end.is_some())) {
        return Err(format!(
            "empty time range: {x0} s to {x1} s since log start (the data spans {lo:.3} s to {hi:.3} s)"
        ));
    }
    if x0 == x1 {
        // One instant of data: a second around it.
        return Ok((x0 - 0.5, x1 + 0.5));
    }
    Ok((x0, x1))
}

fn glyphs() -> Result<&'static Glyphs, String> {
    Glyphs::get().ok_or_else(|| "the built-in font cannot be loaded".to_owned())
}

fn svg_bytes(chart: &draw::Chart<'_>, width: u32, height: u32) -> Result<Vec<u8>, String> {
    let mut text = String::new();
    {
        let svg = SVGBackend::with_string(&mut text, (width, height));
        let root = WithFont::new(svg, glyphs()?, false).into_drawing_area();
        draw::draw(&root, chart).map_err(|e| e.to_string())?;
    }
    Ok(text.into_bytes())
}

fn png_bytes(chart: &draw::Chart<'_>, width: u32, height: u32) -> Result<Vec<u8>, String> {
    let mut rgb = vec![0u8; width as usize * height as usize * 3];
    {
        let bitmap = BitMapBackend::with_buffer(&mut rgb, (width, height));
        let root = WithFont::new(bitmap, glyphs()?, true).into_drawing_area();
        draw::draw(&root, chart).map_err(|e| e.to_string())?;
    }
    let mut out = Vec::new();
    let mut encoder = png::Encoder::new(&mut out, width, height);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    encoder.set_compression(png::Compression::High);
    let mut writer = encoder.write_header().map_err(|e| e.to_string())?;
    writer.write_image_data(&rgb).map_err(|e| e.to_string())?;
    writer.finish().map_err(|e| e.to_string())?;
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn output_format_follows_the_extension() {
        assert_eq!(format_of(Path::new("a/b.SVG")), Some(Format::Svg));
        assert_eq!(format_of(Path::new("b.png")), Some(Format::Png));
        assert_eq!(format_of(Path::new("b.jpg")), None);
        assert!(parse_output("x.pdf").is_err());
        assert_eq!(
            default_output(Path::new("logs/flight.ulg")),
            Path::new("logs/flight_plot.svg")
        );
        assert_eq!(
            default_output(Path::new("logs/flight.ulog")),
            Path::new("logs/flight_plot.svg")
        );
    }

    #[test]
    fn sizes_are_width_by_height_within_limits() {
        assert_eq!(parse_size("800x600"), Ok((800, 600)));
        assert_eq!(parse_size("1920X1080"), Ok((1920, 1080)));
        for bad in ["800", "0x600", "800x", "x600", "99999x10", "axb"] {
            assert!(parse_size(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn time_axis_from_data_or_options() {
        let s = vec![Series {
            label: "t.f".into(),
            unit: None,
            points: vec![(1.0, 0.0), (5.0, 1.0)],
        }];
        assert_eq!(time_axis(&s, None, None), Ok((1.0, 5.0)));
        assert_eq!(time_axis(&s, Some(2.0), None), Ok((2.0, 5.0)));
        assert_eq!(time_axis(&s, None, Some(3.0)), Ok((1.0, 3.0)));
        assert!(time_axis(&s, Some(4.0), Some(3.0)).is_err());
        assert!(time_axis(&[], None, None).is_err());
        assert_eq!(time_axis(&[], Some(0.0), Some(1.0)), Ok((0.0, 1.0)));
    }
}
