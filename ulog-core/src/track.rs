//! The GPS track of a log, as pyulog's `ulog2kml` draws it ([`Track::from_log`]),
//! and the raw receiver bytes of topic `gps_dump`, as its `extract_gps_dump` writes
//! them ([`gps_dump`]).
//!
//! A track is the positions of one GNSS topic (instance 0), split into one
//! [`Segment`] per flight mode (`vehicle_status.nav_state`), each point with its boot
//! timestamp and, where the receiver had one, its UTC time:
//!
//! ```
//! use ulog_core::testing::LogBuilder;
//! use ulog_core::track::{Track, TrackOptions};
//!
//! let mut b = LogBuilder::new(1, 0);
//! b.format("vehicle_gps_position:uint64_t timestamp;uint64_t time_utc_usec;int32_t lat;int32_t lon;int32_t alt;uint8_t fix_type;");
//! b.subscribe(0, 0, "vehicle_gps_position");
//! for i in 1..=5u64 {
//!     let mut p = Vec::new();
//!     p.extend_from_slice(&(i * 200_000).to_le_bytes()); // timestamp (µs since boot)
//!     p.extend_from_slice(&(1_700_000_000_000_000 + i * 200_000).to_le_bytes()); // UTC
//!     p.extend_from_slice(&473_977_420i32.to_le_bytes()); // lat, 1e-7 degrees
//!     p.extend_from_slice(&85_455_940i32.to_le_bytes()); // lon
//!     p.extend_from_slice(&488_000i32.to_le_bytes()); // alt, mm
//!     p.push(3); // fix_type: 3D
//!     b.data(0, &p);
//! }
//! let log = ulog_core::ULog::parse(b.bytes())?;
//! let track = Track::from_log(&log, &TrackOptions::default())?;
//! assert_eq!(track.topic, "vehicle_gps_position");
//! // No vehicle_status: one segment, of mode 0, as ulog2kml draws it.
//! assert_eq!(track.segments.len(), 1);
//! let segment = &track.segments[0];
//! assert_eq!((segment.name.as_str(), segment.color()), ("vehicle_gps_position:0", "ff0000ff"));
//! assert_eq!(segment.points.len(), 5);
//! let p = &segment.points[0];
//! assert_eq!((p.lat, p.lon, p.alt), (47.397742, 8.545594, 488.0));
//! assert_eq!((p.timestamp, p.time_utc_usec), (200_000, Some(1_700_000_000_200_000)));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use core::fmt;

use ulog_format::BasicType;

use crate::access::field::{FieldReader, FieldShape};
use crate::access::lookup::{LookupError, TopicNotFound};
use crate::access::topic::Topic;
use crate::log::ulog::ULog;
use crate::value::Value;

/// The GNSS topics tried when no topic is asked for, in order: the first with data
/// is used. `ulog2kml` tries the first two (`vehicle_gnss` replaced
/// `vehicle_gps_position` in PX4); `sensor_gps` (the raw receiver) is the fallback of
/// this reader for logs that have neither.
pub const GNSS_TOPICS: [&str; 3] = ["vehicle_gnss", "vehicle_gps_position", "sensor_gps"];

/// The topic of the raw bytes to and from the GPS receivers ([`gps_dump`]).
pub const GPS_DUMP_TOPIC: &str = "gps_dump";

/// The names a position field has across PX4 versions, tried in order: `lat`, `lon`
/// (`int32`, 1e-7 degrees) and `alt` (`int32`, millimetres) in older logs, or the
/// double-precision `latitude_deg`, `longitude_deg` and `altitude_msl_m`, or the
/// fields of `vehicle_gnss`'s nested `receiver`.
pub const POSITION_FIELDS: [(&str, &[&str]); 4] = [
    ("lat", &["lat", "latitude_deg", "receiver.latitude"]),
    ("lon", &["lon", "longitude_deg", "receiver.longitude"]),
    ("alt", &["alt", "altitude_msl_m", "receiver.altitude_msl"]),
    ("fix_type", &["fix_type", "receiver.fix_type"]),
];

/// The minimum time between two points of a track (seconds), as in `ulog2kml`.
pub const DEFAULT_MIN_INTERVAL_S: f64 = 0.1;

/// The colour of each flight mode's line, as `ulog2kml` picks it: KML colours
/// (`aabbggrr`: alpha, blue, green, red), indexed by `nav_state` modulo their number
/// (red, green, blue, violet, yellow, orange, burlywood, azure, light blue, lawn
/// green, indian red, hot pink, bisque, cyan, dark salmon, deep sky blue, lime,
/// orchid).
pub const MODE_COLORS: [&str; 18] = [
    "ff0000ff", "ff008000", "ffff0000", "ffee82ee", "ff00ffff", "ff00a5ff", "ff87b8de", "fffffff0",
    "ffe6d8ad", "ff00fc7c", "ff5c5ccd", "ffb469ff", "ffc4e4ff", "ffffff00", "ff7a96e9", "ffffbf00",
    "ff00ff00", "ffd670da",
];

/// The KML colour (`aabbggrr`) of flight mode `nav_state` ([`MODE_COLORS`]; a
/// negative mode has the colour of mode 0).
///
/// ```
/// assert_eq!(ulog_core::track::mode_color(4), "ff00ffff");
/// assert_eq!(ulog_core::track::mode_color(-1), "ff0000ff");
/// assert_eq!(ulog_core::track::mode_color(18), "ff0000ff");
/// ```
pub fn mode_color(nav_state: i32) -> &'static str {
    MODE_COLORS[nav_state.max(0) as usize % MODE_COLORS.len()]
}

/// What [`Track::from_log`] reads.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct TrackOptions {
    /// The position topic (instance 0); `None`: the first of [`GNSS_TOPICS`] with
    /// data.
    pub topic: Option<String>,
    /// A topic of camera trigger positions (`camera_capture`: `lat`, `lon`, `alt`,
    /// `seq`), instance 0; `None`: none.
    pub camera_trigger: Option<String>,
    /// The minimum time between two points (seconds): a point less than this after
    /// the last one kept is left out.
    pub min_interval_s: f64,
}

impl Default for TrackOptions {
    fn default() -> TrackOptions {
        TrackOptions {
            topic: None,
            camera_trigger: None,
            min_interval_s: DEFAULT_MIN_INTERVAL_S,
        }
    }
}

impl TrackOptions {
    /// The topics [`Track::from_log`] reads with these options: a log kept without
    /// its data but theirs ([`ScanOptions::keep_data`](crate::ScanOptions::keep_data))
    /// gives the same track as the whole log.
    ///
    /// ```
    /// let options = ulog_core::track::TrackOptions::default();
    /// assert!(options.topics().contains(&"vehicle_status"));
    /// ```
    pub fn topics(&self) -> Vec<&str> {
        let mut topics: Vec<&str> = match &self.topic {
            Some(t) => vec![t],
            None => GNSS_TOPICS.to_vec(),
        };
        topics.push("vehicle_status");
        topics.extend(self.camera_trigger.as_deref());
        topics
    }
}

/// One position of a track.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrackPoint {
    /// The row's timestamp (microseconds since boot).
    pub timestamp: u64,
    /// The receiver's UTC time of the row (`time_utc_usec`, microseconds since the
    /// Unix epoch), where the topic has it and it is not 0.
    pub time_utc_usec: Option<u64>,
    /// Latitude (degrees).
    pub lat: f64,
    /// Longitude (degrees).
    pub lon: f64,
    /// Altitude above mean sea level (metres).
    pub alt: f64,
}

/// The points of a track flown in one flight mode.
///
/// As in `ulog2kml`, the point where the mode changes ends one segment and starts
/// the next (it is in both).
#[derive(Debug, Clone, PartialEq)]
pub struct Segment {
    /// `<topic>:<nav_state>`, `ulog2kml`'s name of the line.
    pub name: String,
    /// The flight mode (`vehicle_status.nav_state`). As in `ulog2kml`: 0 when the
    /// log has no `vehicle_status`, and -1 for the points at or after the log's last
    /// timestamp.
    pub nav_state: i32,
    /// The points, in the topic's order.
    pub points: Vec<TrackPoint>,
}

impl Segment {
    /// The line's KML colour (`aabbggrr`): [`mode_color`] of its mode.
    pub fn color(&self) -> &'static str {
        mode_color(self.nav_state)
    }
}

/// A camera trigger position.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraTrigger {
    /// The trigger's sequence number (`seq`).
    pub seq: u64,
    /// The row's timestamp (microseconds since boot).
    pub timestamp: u64,
    /// Latitude (degrees).
    pub lat: f64,
    /// Longitude (degrees).
    pub lon: f64,
    /// Altitude (metres).
    pub alt: f64,
}

/// The GPS track of a log, split by flight mode, with the camera triggers asked for.
#[derive(Debug, Clone, PartialEq)]
pub struct Track {
    /// The position topic read (instance 0).
    pub topic: String,
    /// One segment per flight mode flown, in time order; there is always at least
    /// one, maybe empty (a receiver without a fix).
    pub segments: Vec<Segment>,
    /// The camera triggers, in the topic's order.
    pub camera_triggers: Vec<CameraTrigger>,
}

/// Why a track or a GPS dump could not be read.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum TrackError {
    /// None of [`GNSS_TOPICS`] has data in the log.
    NoGpsTopic,
    /// A topic asked for is not in the log, or cannot be decoded.
    Topic(LookupError),
    /// The topic (instance 0) has no data messages.
    NoData {
        /// The topic.
        topic: String,
    },
    /// A field the job needs is not in the topic under any of its names.
    MissingField {
        /// The topic.
        topic: String,
        /// The field's names tried, in order.
        tried: Vec<String>,
    },
}

impl fmt::Display for TrackError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            TrackError::NoGpsTopic => {
                write!(f, "no GPS position topic with data in the log (tried ")?;
                let names: Vec<String> = GNSS_TOPICS.iter().map(|n| format!("`{n}`")).collect();
                write!(f, "{})", names.join(", "))
            }
            TrackError::Topic(e) => e.fmt(f),
            TrackError::NoData { topic } => write!(f, "topic `{topic}` has no data"),
            TrackError::MissingField { topic, tried } => {
                let names: Vec<String> = tried.iter().map(|n| format!("`{n}`")).collect();
                write!(f, "topic `{topic}` has no field {}", names.join(" or "))
            }
        }
    }
}

impl std::error::Error for TrackError {}

impl From<LookupError> for TrackError {
    fn from(e: LookupError) -> TrackError {
        TrackError::Topic(e)
    }
}

/// The first of `names` that topic `t` has, as a scalar.
fn find_field(t: &Topic<'_, '_>, names: &[&str]) -> Result<Option<FieldReader>, TrackError> {
    t.layout()?;
    Ok(names
        .iter()
        .filter_map(|n| t.field(n).ok())
        .find(|f| f.shape() == FieldShape::Scalar))
}

/// The first of `names` that topic `t` has, or the error naming them.
fn need_field(t: &Topic<'_, '_>, names: &[&str]) -> Result<FieldReader, TrackError> {
    find_field(t, names)?.ok_or_else(|| TrackError::MissingField {
        topic: t.name().to_owned(),
        tried: names.iter().map(|n| (*n).to_owned()).collect(),
    })
}

/// The names of position field `what` (`lat`, `lon`, `alt`, `fix_type`).
fn names_of(what: &str) -> &'static [&'static str] {
    POSITION_FIELDS
        .iter()
        .find(|(w, _)| *w == what)
        .map_or(&[], |(_, names)| names)
}

/// A number as `f64` (a `float` widened exactly, as `ulog2kml` writes it:
/// `501.4285583496094`, not `501.42856`).
fn number(v: Value<'_>) -> Option<f64> {
    v.as_f64()
}

/// Reads the latitude, longitude and altitude of a topic's rows: in degrees and
/// metres (`int32` fields scaled from 1e-7 degrees and millimetres, as `ulog2kml`
/// does when `lon` is an `int32`).
struct Position {
    lat: FieldReader,
    lon: FieldReader,
    alt: FieldReader,
    scaled: bool,
}

impl Position {
    fn of(t: &Topic<'_, '_>) -> Result<Position, TrackError> {
        let lon = need_field(t, names_of("lon"))?;
        let lat = need_field(t, names_of("lat"))?;
        let alt = need_field(t, names_of("alt"))?;
        let scaled = lon.ty() == BasicType::Int32;
        Ok(Position {
            lat,
            lon,
            alt,
            scaled,
        })
    }

    /// (lat, lon, alt) of a payload; `None` for a payload too short to hold them.
    fn read(&self, p: &[u8]) -> Option<(f64, f64, f64)> {
        let lat = number(self.lat.read(p)?)?;
        let lon = number(self.lon.read(p)?)?;
        let alt = number(self.alt.read(p)?)?;
        Some(if self.scaled {
            (lat / 1e7, lon / 1e7, alt / 1e3)
        } else {
            (lat, lon, alt)
        })
    }
}

fn read_u64(f: &FieldReader, p: &[u8]) -> Option<u64> {
    f.read(p)?.as_u64()
}

impl Track {
    /// The track of `log`, as `ulog2kml` draws it.
    ///
    /// - The topic: `options.topic`, else the first of [`GNSS_TOPICS`] with data;
    ///   instance 0.
    /// - Points: the rows with `fix_type` > 2 (where the topic has `fix_type`), each
    ///   more than `options.min_interval_s` after the last point kept (the first: after
    ///   timestamp 0).
    /// - Segments: the flight modes of `vehicle_status.nav_state` (instance 0, rows
    ///   of timestamp 0 left out), with mode -1 from pyulog's last timestamp of the
    ///   topics it loads (the position topics, `vehicle_status`, the camera trigger
    ///   topic) on. A new segment starts at the first point at or after each change,
    ///   with that point.
    /// - Camera triggers: every row of `options.camera_trigger` (instance 0).
    ///
    /// `int32` positions are scaled from 1e-7 degrees and millimetres (as `f64`
    /// divisions, as numpy does them); `float` values are widened to `f64` exactly.
    pub fn from_log(log: &ULog<'_>, options: &TrackOptions) -> Result<Track, TrackError> {
        let has_data = |n: &str| log.topic_instances(n).iter().any(|t| !t.is_empty());
        // The topics ulog2kml loads: their data set its last timestamp.
        let mut loaded: Vec<&str> = Vec::new();
        let name: &str = match &options.topic {
            Some(t) => {
                loaded.push(t);
                t
            }
            None => {
                let name = GNSS_TOPICS
                    .iter()
                    .copied()
                    .find(|n| has_data(n))
                    .ok_or(TrackError::NoGpsTopic)?;
                loaded.extend_from_slice(&GNSS_TOPICS[..2]);
                loaded.push(name);
                name
            }
        };
        let topic = log.topic(name, 0)?;
        if topic.is_empty() {
            return Err(TrackError::NoData {
                topic: name.to_owned(),
            });
        }
        loaded.push("vehicle_status");
        let camera_trigger = match &options.camera_trigger {
            Some(c) => {
                loaded.push(c);
                Some(log.topic(c, 0)?)
            }
            None => None,
        };
        let position = Position::of(&topic)?;
        let timestamp = need_field(&topic, &["timestamp"])?;
        let fix_type = find_field(&topic, names_of("fix_type"))?;
        let utc = find_field(&topic, &["time_utc_usec"])?;

        let last_timestamp = log
            .topics()
            .filter(|t| loaded.contains(&t.name()))
            .flat_map(|t| t.timestamps())
            .fold(log.start_timestamp(), u64::max);
        let changes = mode_changes(log, last_timestamp);

        let segment = |nav_state: i32, points: Vec<TrackPoint>| Segment {
            name: format!("{name}:{nav_state}"),
            nav_state,
            points,
        };
        let mut change = 0usize;
        let mut segments = vec![segment(changes.first().map_or(0, |c| c.1), Vec::new())];
        let mut last_t = 0u64;
        for p in topic.payloads() {
            if let Some(f) = &fix_type {
                if f.read(p).and_then(|v| v.as_i128()).map_or(true, |x| x <= 2) {
                    continue;
                }
            }
            let (Some(t), Some((lat, lon, alt))) = (read_u64(&timestamp, p), position.read(p))
            else {
                continue;
            };
            // A position that is not a number (a receiver without a fix, where the
            // topic has no fix type) is no point of the track.
            if !(lat.is_finite() && lon.is_finite() && alt.is_finite()) {
                continue;
            }
            // As ulog2kml: unsigned microseconds (a step back wraps, and is kept).
            if t.wrapping_sub(last_t) as f64 / 1e6 <= options.min_interval_s {
                continue;
            }
            let point = TrackPoint {
                timestamp: t,
                time_utc_usec: utc.as_ref().and_then(|f| read_u64(f, p)).filter(|&u| u > 0),
                lat,
                lon,
                alt,
            };
            last_t = t;
            segments.last_mut().expect("a segment").points.push(point);
            while change + 1 < changes.len() && changes[change + 1].0 <= t {
                change += 1;
                segments.push(segment(changes[change].1, vec![point]));
            }
        }
        let camera_triggers = match camera_trigger {
            Some(c) => camera_triggers(&c)?,
            None => Vec::new(),
        };
        Ok(Track {
            topic: name.to_owned(),
            segments,
            camera_triggers,
        })
    }

    /// The number of points of all segments (a point where the mode changes counts
    /// twice, as it is in two segments).
    pub fn point_count(&self) -> usize {
        self.segments.iter().map(|s| s.points.len()).sum()
    }
}

/// pyulog's `list_value_changes('nav_state')` of `vehicle_status` (instance 0), with
/// `(last_timestamp, -1)` after them; empty without that topic or field.
fn mode_changes(log: &ULog<'_>, last_timestamp: u64) -> Vec<(u64, i32)> {
    let Ok(status) = log.topic("vehicle_status", 0) else {
        return Vec::new();
    };
    let (Ok(nav), Ok(ts)) = (status.field("nav_state"), status.field("timestamp")) else {
        return Vec::new();
    };
    if status.is_empty() {
        return Vec::new();
    }
    let mut changes: Vec<(u64, i32)> = Vec::new();
    for p in status.payloads() {
        let (Some(t), Some(mode)) = (read_u64(&ts, p), nav.read(p).and_then(|v| v.as_i128()))
        else {
            continue;
        };
        let mode = i32::try_from(mode).unwrap_or(i32::MAX);
        if t != 0 && changes.last().map_or(true, |c| c.1 != mode) {
            changes.push((t, mode));
        }
    }
    changes.push((last_timestamp, -1));
    changes
}

fn camera_triggers(t: &Topic<'_, '_>) -> Result<Vec<CameraTrigger>, TrackError> {
    if t.is_empty() {
        return Ok(Vec::new());
    }
    let position = Position::of(t)?;
    let seq = need_field(t, &["seq"])?;
    let timestamp = need_field(t, &["timestamp"])?;
    Ok(t.payloads()
        .filter_map(|p| {
            let (lat, lon, alt) = position.read(p)?;
            Some(CameraTrigger {
                seq: read_u64(&seq, p)?,
                timestamp: read_u64(&timestamp, p)?,
                lat,
                lon,
                alt,
            })
        })
        .collect())
}

/// One message of topic `gps_dump`: bytes sent to or received from a GPS receiver.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct GpsDumpChunk<'a> {
    /// The message's index among the `gps_dump` messages of all instances, in file
    /// order.
    pub row: usize,
    /// The topic instance it was logged under.
    pub multi_id: u8,
    /// Its timestamp (microseconds since boot).
    pub timestamp: u64,
    /// The receiver: field `instance` (0 the main receiver, 1 the secondary), or the
    /// topic instance in logs without that field.
    pub instance: u8,
    /// Bit 7 of `len`: bytes sent to the receiver (else received from it).
    pub to_device: bool,
    /// `len` as logged (bit 7 the direction, bits 0-6 the number of bytes).
    pub len: u8,
    /// The bytes: the first `len & 0x7f` of `data`, or all of `data` when `len` says
    /// more than it holds ([`GpsDumpChunk::is_clamped`]).
    pub data: &'a [u8],
}

impl GpsDumpChunk<'_> {
    /// Whether `len` says more bytes than the message's `data` holds (the data is then
    /// cut to what it holds).
    pub fn is_clamped(&self) -> bool {
        usize::from(self.len & 0x7f) > self.data.len()
    }
}

/// Every message of topic `gps_dump` ([`GPS_DUMP_TOPIC`]; all instances, in file
/// order), as `extract_gps_dump` reads them: `len` (bit 7: to the device) and `data`
/// (bytes), and `instance` where the format has it.
///
/// An error when the log has no `gps_dump` topic or its format has no `len` or
/// `data`; an empty list when the topic has no data.
///
/// ```
/// use ulog_core::testing::LogBuilder;
/// let mut b = LogBuilder::new(1, 0);
/// b.format("gps_dump:uint64_t timestamp;uint8_t instance;uint8_t len;uint8_t[79] data;");
/// b.subscribe(0, 0, "gps_dump");
/// let mut p = 1_000u64.to_le_bytes().to_vec();
/// p.extend_from_slice(&[1, 0x80 | 3]); // instance 1, 3 bytes to the device
/// p.extend_from_slice(&[0xb5, 0x62, 0x06]);
/// p.resize(8 + 2 + 79, 0);
/// b.data(0, &p);
/// let log = ulog_core::ULog::parse(b.bytes())?;
/// let chunks = ulog_core::track::gps_dump(&log)?;
/// assert_eq!(chunks.len(), 1);
/// assert_eq!((chunks[0].instance, chunks[0].to_device), (1, true));
/// assert_eq!(chunks[0].data, [0xb5, 0x62, 0x06]);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn gps_dump<'a>(log: &ULog<'a>) -> Result<Vec<GpsDumpChunk<'a>>, TrackError> {
    const TOPIC: &str = GPS_DUMP_TOPIC;
    let topics = log.topic_instances(TOPIC);
    if topics.is_empty() {
        return Err(LookupError::Topic(TopicNotFound::in_log(log, TOPIC, None)).into());
    }
    let mut rows: Vec<(u64, GpsDumpChunk<'a>)> = Vec::new();
    for t in &topics {
        if t.is_empty() {
            continue;
        }
        let len = need_field(t, &["len"])?;
        let data = t
            .field("data")
            .ok()
            .filter(|f| {
                matches!(f.shape(), FieldShape::Array(_))
                    && matches!(f.ty(), BasicType::UInt8 | BasicType::Int8)
            })
            .ok_or_else(|| TrackError::MissingField {
                topic: TOPIC.to_owned(),
                tried: vec!["data".to_owned()],
            })?;
        let FieldShape::Array(size) = data.shape() else {
            unreachable!("checked above")
        };
        let instance = find_field(t, &["instance"])?;
        let timestamp = find_field(t, &["timestamp"])?;
        for (offset, p) in t.message_offsets().iter().zip(t.payloads()) {
            let Some(n) = len.read(p).and_then(|v| v.as_u64()) else {
                continue;
            };
            let n = n as u8;
            let bytes = p.get(data.offset()..).unwrap_or_default();
            let bytes = &bytes[..bytes.len().min(size)];
            let count = usize::from(n & 0x7f).min(bytes.len());
            rows.push((
                offset,
                GpsDumpChunk {
                    row: 0,
                    multi_id: t.multi_id(),
                    timestamp: timestamp.as_ref().and_then(|f| read_u64(f, p)).unwrap_or(0),
                    instance: instance
                        .as_ref()
                        .and_then(|f| read_u64(f, p))
                        .map_or(t.multi_id(), |i| i as u8),
                    to_device: n & 0x80 != 0,
                    len: n,
                    data: &bytes[..count],
                },
            ));
        }
    }
    rows.sort_by_key(|r| r.0);
    Ok(rows
        .into_iter()
        .enumerate()
        .map(|(i, (_, c))| GpsDumpChunk { row: i, ..c })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::LogBuilder;

    /// A log of topic `name` with format `fields` and one row per payload.
    fn log_of(name: &str, fields: &str, rows: &[Vec<u8>]) -> Vec<u8> {
        let mut b = LogBuilder::new(1, 0);
        b.format(&format!("{name}:{fields}"));
        b.subscribe(0, 0, name);
        for r in rows {
            b.data(0, r);
        }
        b.into_bytes()
    }

    fn row(t: u64, lat: f64, lon: f64, alt: f32) -> Vec<u8> {
        [
            &t.to_le_bytes()[..],
            &lat.to_le_bytes(),
            &lon.to_le_bytes(),
            &alt.to_le_bytes(),
        ]
        .concat()
    }

    #[test]
    fn sensor_gps_is_the_fallback_and_doubles_are_read_as_they_are() {
        let rows: Vec<Vec<u8>> = (1..=4)
            .map(|i| row(i * 150_000, 47.5 + i as f64 * 1e-6, 8.5, 400.25))
            .collect();
        let bytes = log_of(
            "sensor_gps",
            "uint64_t timestamp;double latitude_deg;double longitude_deg;float altitude_msl_m;",
            &rows,
        );
        let log = ULog::parse(&bytes).unwrap();
        let track = Track::from_log(&log, &TrackOptions::default()).unwrap();
        assert_eq!(track.topic, "sensor_gps");
        let points = &track.segments[0].points;
        // No fix_type: every row; no time_utc_usec: no UTC time.
        assert_eq!(points.len(), 4);
        assert_eq!(
            (points[1].lat, points[1].lon, points[1].alt),
            (47.5 + 2e-6, 8.5, 400.25)
        );
        assert!(points.iter().all(|p| p.time_utc_usec.is_none()));
    }

    #[test]
    fn points_closer_than_the_interval_are_left_out_and_a_step_back_is_kept() {
        let ts = [50_000u64, 150_000, 200_000, 260_000, 100_000, 150_000];
        let rows: Vec<Vec<u8>> = ts.iter().map(|&t| row(t, 1.0, 2.0, 3.0)).collect();
        let bytes = log_of(
            "vehicle_gps_position",
            "uint64_t timestamp;double lat;double lon;float alt;",
            &rows,
        );
        let log = ULog::parse(&bytes).unwrap();
        let track = Track::from_log(&log, &TrackOptions::default()).unwrap();
        let kept: Vec<u64> = track.segments[0]
            .points
            .iter()
            .map(|p| p.timestamp)
            .collect();
        // 50 ms is not after 0.1 s; 200 ms is 50 ms after 150; back to 100 ms wraps
        // (unsigned, as in ulog2kml) and is kept; 150 ms is then too close.
        assert_eq!(kept, [150_000, 260_000, 100_000]);
    }

    #[test]
    fn errors_name_the_topic_and_the_fields() {
        let bytes = log_of(
            "vehicle_gps_position",
            "uint64_t timestamp;int32_t x;",
            &[[&1u64.to_le_bytes()[..], &[0; 4]].concat()],
        );
        let log = ULog::parse(&bytes).unwrap();
        let e = Track::from_log(&log, &TrackOptions::default()).unwrap_err();
        assert_eq!(
            e.to_string(),
            "topic `vehicle_gps_position` has no field `lon` or `longitude_deg` or `receiver.longitude`"
        );
        let options = TrackOptions {
            topic: Some("vehicle_gps_positio".into()),
            ..TrackOptions::default()
        };
        let e = Track::from_log(&log, &options).unwrap_err();
        assert!(
            matches!(e, TrackError::Topic(LookupError::Topic(_))),
            "{e:?}"
        );
        let sample = crate::testing::sample_log();
        let log = ULog::parse(&sample).unwrap();
        assert_eq!(
            Track::from_log(&log, &TrackOptions::default()),
            Err(TrackError::NoGpsTopic)
        );
        assert!(matches!(gps_dump(&log), Err(TrackError::Topic(_))));
    }
}
