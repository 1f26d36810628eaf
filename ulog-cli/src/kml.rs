//! `ulog kml`: the GPS track, as pyulog's `ulog2kml` draws it, as KML, GPX or GeoJSON.

use std::fmt::Write as _;
use std::io::Write as _;
use std::path::PathBuf;

use serde_json::{json, Value as Json};
use ulog_core::track::{Segment, Track, TrackError, TrackOptions, TrackPoint};
use ulog_core::LookupError;

use crate::failure::{Failure, Status};
use crate::input;
use crate::markup::escape;

/// Write the GPS track of a log as KML (default), GPX or GeoJSON, as pyulog's
/// `ulog2kml` draws it: the first of `vehicle_gnss`, `vehicle_gps_position` (then
/// `sensor_gps`) with data, instance 0; only points with `fix_type` > 2, at least 0.1 s
/// apart; one line per flight mode (`vehicle_status.nav_state`), named `TOPIC:MODE`
/// and coloured by mode as `ulog2kml` colours it.
///
/// KML: one Placemark per line (a LineString, altitude absolute, width 3), and one per
/// camera trigger (`Camera Trigger SEQ`). GPX 1.1: one track of one segment per line,
/// each point with its elevation and, where the receiver had it, its UTC time
/// (`time_utc_usec`); camera triggers as waypoints. GeoJSON: one LineString feature
/// per line (properties: topic, nav_state, colour, first and last timestamps and UTC
/// times), camera triggers as Point features. As in `ulog2kml`, the point where the
/// mode changes is in both lines. Written to `<FILE stem>.kml` (`.gpx`, `.geojson`)
/// in the current directory unless `-o` says otherwise (`-o -`: stdout). Names are
/// escaped, and characters XML cannot hold (control characters but tab and line
/// breaks, noncharacters) written as U+FFFD, so that KML and GPX are well-formed XML.
#[derive(Debug, clap::Args)]
#[command(
    about = "The GPS track as KML, GPX or GeoJSON, as pyulog's ulog2kml",
    long_about
)]
pub struct Args {
    /// The ULog file.
    file: PathBuf,
    /// Output file (`-` for stdout; default: `<FILE stem>.kml`, `.gpx` or `.geojson`
    /// in the current directory).
    #[arg(short = 'o', long = "output", value_name = "OUT")]
    output: Option<PathBuf>,
    /// Write GPX 1.1 instead of KML.
    #[arg(long, conflicts_with = "geojson")]
    gpx: bool,
    /// Write GeoJSON instead of KML.
    #[arg(long)]
    geojson: bool,
    /// The position topic (instance 0; default: the first of `vehicle_gnss`,
    /// `vehicle_gps_position`, `sensor_gps` with data).
    #[arg(long, value_name = "NAME")]
    topic: Option<String>,
    /// A topic of camera trigger positions (e.g. `camera_capture`: `lat`, `lon`,
    /// `alt`, `seq`).
    #[arg(long = "camera-trigger", value_name = "NAME")]
    camera_trigger: Option<String>,
    #[arg(short = 'i', long, help = crate::pyulog::IGNORE_HELP)]
    ignore: bool,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Format {
    Kml,
    Gpx,
    GeoJson,
}

impl Format {
    fn extension(self) -> &'static str {
        match self {
            Format::Kml => "kml",
            Format::Gpx => "gpx",
            Format::GeoJson => "geojson",
        }
    }
}

pub fn run(args: &Args) -> Result<(), Failure> {
    let name = args.file.display().to_string();
    let mut options = TrackOptions::default();
    options.topic.clone_from(&args.topic);
    options.camera_trigger.clone_from(&args.camera_trigger);
    // One pass in chunks, keeping the metadata and the rows of the topics the track
    // reads.
    let kept = input::keep(&args.file, &options.topics(), input::Times::Every)?;
    let log = kept.log(&name)?;
    let track = Track::from_log(&log, &options).map_err(|e| track_failure(&name, e))?;
    input::note_damage(&name, log.findings());
    let format = if args.gpx {
        Format::Gpx
    } else if args.geojson {
        Format::GeoJson
    } else {
        Format::Kml
    };
    let stem = input::stem(&args.file);
    let text = match format {
        Format::Kml => kml(&track, &stem),
        Format::Gpx => gpx(&track, &stem),
        Format::GeoJson => geojson(&track),
    };
    let output = args
        .output
        .clone()
        .unwrap_or_else(|| PathBuf::from(format!("{stem}.{}", format.extension())));
    if output.as_os_str() == "-" {
        let mut out = std::io::stdout().lock();
        return out
            .write_all(text.as_bytes())
            .and_then(|()| out.flush())
            .map_err(crate::failure::stdout_err);
    }
    std::fs::write(&output, text).map_err(|e| Failure::io(output.display(), &e))?;
    writeln!(
        std::io::stdout(),
        "Writing {} ({} line{}, {} points, {} camera triggers)",
        output.display(),
        track.segments.len(),
        if track.segments.len() == 1 { "" } else { "s" },
        track.point_count(),
        track.camera_triggers.len()
    )
    .map_err(crate::failure::stdout_err)
}

/// A track error as a failure about the log `name`: a missing topic or field is an
/// unknown name.
pub fn track_failure(name: &str, e: TrackError) -> Failure {
    let status = match &e {
        TrackError::Topic(LookupError::Layout { .. }) => Status::Other,
        _ => Status::UnknownName,
    };
    Failure::new(status, name, e)
}

/// `lon,lat,alt`, each number in its shortest round-trip form.
fn kml_coordinates(lon: f64, lat: f64, alt: f64) -> String {
    format!("{lon},{lat},{alt}")
}

fn kml(track: &Track, stem: &str) -> String {
    let mut s = String::from(
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n\
         <kml xmlns=\"http://www.opengis.net/kml/2.2\">\n  <Document>\n",
    );
    let _ = writeln!(s, "    <name>{}</name>", escape(stem));
    for seg in &track.segments {
        let coordinates: Vec<String> = seg
            .points
            .iter()
            .map(|p| kml_coordinates(p.lon, p.lat, p.alt))
            .collect();
        let _ = write!(
            s,
            "    <Placemark>\n      <name>{}</name>\n      <Style>\n        <LineStyle>\n          \
             <color>{}</color>\n          <width>3</width>\n        </LineStyle>\n      </Style>\n      \
             <LineString>\n        <altitudeMode>absolute</altitudeMode>\n        \
             <coordinates>{}</coordinates>\n      </LineString>\n    </Placemark>\n",
            escape(&seg.name),
            seg.color(),
            coordinates.join(" ")
        );
    }
    for c in &track.camera_triggers {
        let _ = write!(
            s,
            "    <Placemark>\n      <name>Camera Trigger {}</name>\n      <Point>\n        \
             <coordinates>{}</coordinates>\n      </Point>\n    </Placemark>\n",
            c.seq,
            kml_coordinates(c.lon, c.lat, c.alt)
        );
    }
    s.push_str("  </Document>\n</kml>\n");
    s
}

/// A UTC time in microseconds since the Unix epoch as RFC 3339 (`…T…Z`, with the
/// microseconds); `None` past the year 9999.
fn rfc3339(us: u64) -> Option<String> {
    // Years after 9999 have no RFC 3339 form.
    (us < 253_402_300_800_000_000).then(|| ulog_core::read::UtcTime(us as i64).to_string())
}

fn gpx(track: &Track, stem: &str) -> String {
    let mut s = String::from(
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<gpx version=\"1.1\" creator=\"ulog\" \
         xmlns=\"http://www.topografix.com/GPX/1/1\">\n",
    );
    // GPX 1.1 lists waypoints before tracks.
    for c in &track.camera_triggers {
        let _ = writeln!(
            s,
            "  <wpt lat=\"{}\" lon=\"{}\"><ele>{}</ele><name>Camera Trigger {}</name></wpt>",
            c.lat, c.lon, c.alt, c.seq
        );
    }
    let _ = writeln!(
        s,
        "  <trk>\n    <name>{}</name>\n    <src>{}</src>",
        escape(stem),
        escape(&track.topic)
    );
    for seg in &track.segments {
        s.push_str("    <trkseg>\n");
        for p in &seg.points {
            let _ = write!(
                s,
                "      <trkpt lat=\"{}\" lon=\"{}\"><ele>{}</ele>",
                p.lat, p.lon, p.alt
            );
            if let Some(t) = p.time_utc_usec.and_then(rfc3339) {
                let _ = write!(s, "<time>{t}</time>");
            }
            s.push_str("</trkpt>\n");
        }
        s.push_str("    </trkseg>\n");
    }
    s.push_str("  </trk>\n</gpx>\n");
    s
}

/// A number for JSON: `null` when not finite.
fn number(x: f64) -> Json {
    serde_json::Number::from_f64(x).map_or(Json::Null, Json::Number)
}

fn geojson(track: &Track) -> String {
    let utc = |p: Option<&TrackPoint>| {
        p.and_then(|p| p.time_utc_usec)
            .and_then(rfc3339)
            .map_or(Json::Null, Json::String)
    };
    let line = |seg: &Segment| {
        let color = seg.color();
        let coordinates: Vec<Json> = seg
            .points
            .iter()
            .map(|p| json!([number(p.lon), number(p.lat), number(p.alt)]))
            .collect();
        let (first, last) = (seg.points.first(), seg.points.last());
        json!({
            "type": "Feature",
            "geometry": {"type": "LineString", "coordinates": coordinates},
            "properties": {
                "name": seg.name,
                "topic": track.topic,
                "nav_state": seg.nav_state,
                "color": color,
                "stroke": format!("#{}{}{}", &color[6..8], &color[4..6], &color[2..4]),
                "stroke-width": 3,
                "start_timestamp": first.map(|p| p.timestamp),
                "end_timestamp": last.map(|p| p.timestamp),
                "start_time_utc": utc(first),
                "end_time_utc": utc(last),
            }
        })
    };
    let mut features: Vec<Json> = track.segments.iter().map(line).collect();
    features.extend(track.camera_triggers.iter().map(|c| {
        json!({
            "type": "Feature",
            "geometry": {
                "type": "Point",
                "coordinates": [number(c.lon), number(c.lat), number(c.alt)],
            },
            "properties": {
                "name": format!("Camera Trigger {}", c.seq),
                "seq": c.seq,
                "timestamp": c.timestamp,
            }
        })
    }));
    let doc = json!({"type": "FeatureCollection", "features": features});
    let mut s = serde_json::to_string(&doc).expect("JSON of plain values");
    s.push('\n');
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn utc_times_are_rfc3339() {
        assert_eq!(rfc3339(0).as_deref(), Some("1970-01-01T00:00:00.000000Z"));
        assert_eq!(
            rfc3339(1_707_236_822_500_000).as_deref(),
            Some("2024-02-06T16:27:02.500000Z")
        );
        assert_eq!(
            rfc3339(951_782_400_000_001).as_deref(),
            Some("2000-02-29T00:00:00.000001Z")
        );
        assert_eq!(rfc3339(u64::MAX), None);
    }

    #[test]
    fn names_are_escaped_and_stems_lose_the_log_extension() {
        assert_eq!(escape("a<b>&\"'"), "a&lt;b&gt;&amp;&quot;&apos;");
        let stem = |p: &str| crate::input::stem(std::path::Path::new(p));
        assert_eq!(stem("dir/flight.ULG"), "flight");
        assert_eq!(stem("flight.bin"), "flight.bin");
    }
}
