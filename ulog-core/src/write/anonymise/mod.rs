//! [`Anonymise`]: what identifies a vehicle and where it flew, taken out of a log
//! through an [`Edit`].

mod detect;
#[cfg(feature = "events")]
mod events;
mod mapping;
mod places;
mod rotation;
mod text;

use std::sync::Arc;

use crate::write::edit::Edit;
use detect::Survey;
use rotation::Rotation;
use text::Texts;

/// Information and multi-information keys that identify a vehicle, left out by
/// [`Anonymise`] (unless kept with [`Anonymise::keep`]): `sys_uuid` (the board's
/// unique id), `sys_mcu` (the MCU and its revision), `ver_hw_subtype` (a hardware
/// variant, often with a serial), and the console output captured at boot
/// (`boot_console_output`, which prints serial numbers and ids).
pub const IDENTIFYING_KEYS: &[&str] = &[
    "sys_uuid",
    "sys_mcu",
    "ver_hw_subtype",
    "boot_console_output",
];

/// Keys of wall-clock time, left out with [`Anonymise::zero_utc`]: `time_ref_utc` (the
/// time zone) and `boot_time_utc_us`.
pub const UTC_KEYS: &[&str] = &["time_ref_utc", "boot_time_utc_us"];

/// Topics of raw receiver data (positions in the receiver's own protocol), left out.
pub const RAW_GPS_TOPICS: &[&str] = &["gps_dump", "gps_inject_data"];

/// The pairs of field names that hold a position (latitude, longitude), in any topic
/// and at any depth (`current.lat` of `position_setpoint_triplet`): `int32_t` in
/// 1e-7 degrees, `float` or `double` in degrees. Their values are where the log was:
/// the references by which what holds a position under another name is found (see
/// [`Anonymise`]).
pub const POSITION_FIELDS: &[(&str, &str)] = &[
    ("lat", "lon"),
    ("latitude", "longitude"),
    ("latitude_deg", "longitude_deg"),
    ("ref_lat", "ref_lon"),
];

/// Positions held in arrays, by topic: (topic, latitude path, longitude path); taken
/// when both are `double` (degrees; older firmware logged the same topic's field in
/// metres, as `float`). Other arrays are found by their values.
pub const ARRAY_POSITIONS: &[(&str, &str, &str)] = &[(
    "estimator_aid_src_gnss_pos",
    "observation[0]",
    "observation[1]",
)];

/// MAVLink commands whose `param5`, `param6` are a latitude and longitude in
/// `vehicle_command` (waypoint, loiters, land, takeoff, VTOL takeoff and land, orbit,
/// reposition, set home, region of interest, land start, payload place).
pub const POSITION_COMMANDS: &[u32] = &[
    16, 17, 18, 19, 21, 22, 31, 34, 84, 85, 94, 179, 189, 192, 195, 201,
];

/// What [`Anonymise::edit`] changes in a log:
///
/// - the information keys of [`IDENTIFYING_KEYS`] are left out (and those of
///   [`UTC_KEYS`] with [`Anonymise::zero_utc`]); [`Anonymise::keep`] keeps some;
/// - every position (below) is moved by one rotation of the Earth that takes the
///   log's first position to [`Anonymise::to`] (default 0° N 0° E): a rotation keeps
///   every distance between positions and the flight's shape (north stays north near
///   the flight); altitudes are not changed; a position of 0, 0 (no fix) and values
///   that are not numbers stay as they are;
/// - with [`Anonymise::zero_utc`], the `time_utc_usec` fields (GPS time) are zeroed and
///   every date and time of day written in text becomes zeros (below);
/// - with [`Anonymise::zero_start`], the header's timestamp is 0;
/// - the topics of raw receiver data ([`RAW_GPS_TOPICS`]) are left out.
///
/// Everything else is kept byte for byte, as [`Edit`] keeps it.
///
/// # What is a position
///
/// The log is read once for what it holds before the edit writes it:
///
/// 1. **By name**, the references: the fields of [`POSITION_FIELDS`] (any topic, any
///    depth) and [`ARRAY_POSITIONS`], `param5`/`param6` of the `vehicle_command`s of
///    [`POSITION_COMMANDS`], and the parameters and information keys named as a pair
///    (`LPE_LAT` with `LPE_LON`, `home_lat` with `home_lon`, `latitude` with
///    `longitude`; `float`/`double` in degrees, `int32_t` in 1e-7 degrees). The rotation
///    starts from the first of these in the file: a row of the vehicle's own (of
///    other aircraft, `transponder_report`, when none is), a key when no row holds
///    one.
/// 2. **By value**, whatever holds a position near a reference, under any name: in
///    every topic, two numeric fields of one row (`float`/`double` read as degrees
///    and as radians, `int32_t`/`int64_t` as 1e-7 degrees; array elements too) that
///    hold, in one unit, a latitude and a longitude within 0.05° (5.5 km) of a
///    reference together, in at least half of the rows where they are a position
///    (`follow_target_estimator.lat_est`/`lon_est`, the `observation` of
///    `estimator_aid_src_fake_pos`, a custom topic in radians); likewise two
///    parameters or two information keys whose values are near a reference together.
///    A single value near a reference's latitude (a voltage of 47.4) is not a
///    position, nor is a pair near one in only a few of its rows.
/// 3. **In text** (logged strings, information and multi-information strings,
///    `char[N]` fields): two numbers near a reference together (decimal degrees, or
///    integers of 7 to 10 digits in 1e-7 degrees) move, and so does a lone decimal
///    number of 5 decimals or more near a reference's latitude or longitude; a moved
///    number keeps its decimals (and its length where the text's is fixed:
///    multi-information split over messages, `char[N]`). With
///    [`Anonymise::zero_utc`], dates (`2021-05-22`, `2026-8-20`; years 1970 to 2100)
///    with the time after them (`2021-05-22/19_41_57.ulg`, `2024-03-01T06:46:06`), a
///    time of day (`06:46:06`) and a log file's name (`6_5_17.ulg`) become zeros of
///    the same shape (`0000-00-00/00_00_00.ulg`); so do the arguments of a PX4 event
///    whose message shows one (`logging: opening log file 2026-8-20/6_5_17.ulg`
///    becomes `0-0-0/0_0_0.ulg`), found by decoding the events with the metadata the
///    log embeds (feature `events`).
///
/// What cannot be found that way stays as it is:
///
/// - anything, when the log holds no reference (no field, parameter or key named as a
///   position, or none with a fix): nothing is near;
/// - a position farther than 0.05° from every reference (a target or a waypoint far
///   from the flight);
/// - a latitude without its longitude in the same row or message, or the two in
///   different units or types;
/// - positions in other units (1e-5 degrees, minutes, fixed point, text in degrees,
///   minutes and seconds, a lone number of fewer than 5 decimals) or encoded in bytes
///   (`uint8_t[]` buffers, MAVLink or receiver messages carried raw);
/// - which element goes with which, in a custom topic that carries several positions
///   in arrays: elements are paired by their values, then by their index (`lat[2]`
///   with `lon[2]`), then by their nearness in the row (`pos[2]` with `pos[3]`), so a
///   single array of all the latitudes then all the longitudes still moves every
///   value far from where it was, but a latitude may move with another entry's
///   longitude, and the shape between those entries is then not kept exactly;
/// - positions in the arguments of PX4 events, and dates in those of events the log
///   has no metadata for;
/// - local positions (metres from the estimator's origin: they tell the flight's
///   shape, not where it was), altitudes, and a time zone written in text.
///
/// ```
/// use ulog_core::{testing::LogBuilder, write::Anonymise, ULog, Value};
/// let mut b = LogBuilder::new(1, 0);
/// b.info_str("sys_uuid", "0004004B3038511834303533");
/// b.format("vehicle_gps_position:uint64_t timestamp;int32_t lat;int32_t lon;");
/// b.subscribe(0, 0, "vehicle_gps_position");
/// let fix = |t: u64, lat: i32, lon: i32| {
///     [&t.to_le_bytes()[..], &lat.to_le_bytes(), &lon.to_le_bytes()].concat()
/// };
/// b.data(0, &fix(1_000, 473_977_420, 85_455_940));
/// b.data(0, &fix(2_000, 473_978_420, 85_455_940));
/// let log = ULog::parse(b.bytes())?;
///
/// let mut out = Vec::new();
/// Anonymise::new().edit(&log).write(&log, &mut out)?;
/// let anonymised = ULog::parse(&out)?;
/// assert!(anonymised.info_value("sys_uuid").is_none());
/// let gps = anonymised.topic("vehicle_gps_position", 0)?;
/// let lat = gps.field("lat")?;
/// // The first fix is at 0° N 0° E; the second still 1e-4 degrees (11 m) north of it.
/// assert_eq!(lat.read(gps.payload(0).unwrap()), Some(Value::I32(0)));
/// assert_eq!(lat.read(gps.payload(1).unwrap()), Some(Value::I32(1_000)));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Anonymise {
    to: (f64, f64),
    keep: Vec<String>,
    zero_utc: bool,
    zero_start: bool,
}

impl Default for Anonymise {
    fn default() -> Anonymise {
        Anonymise::new()
    }
}

impl Anonymise {
    /// Positions moved to 0° N 0° E, the identifying keys left out.
    pub fn new() -> Anonymise {
        Anonymise {
            to: (0.0, 0.0),
            keep: Vec::new(),
            zero_utc: false,
            zero_start: false,
        }
    }

    /// Where the log's first position goes (latitude, longitude in degrees).
    pub fn to(mut self, latitude: f64, longitude: f64) -> Anonymise {
        self.to = (latitude, longitude);
        self
    }

    /// Keeps these keys of [`IDENTIFYING_KEYS`] and [`UTC_KEYS`].
    pub fn keep<S: Into<String>>(mut self, keys: impl IntoIterator<Item = S>) -> Anonymise {
        self.keep = keys.into_iter().map(Into::into).collect();
        self
    }

    /// Also leaves out the wall-clock keys ([`UTC_KEYS`]), zeroes the GPS time fields
    /// (`time_utc_usec`) and writes zeros for the dates and times of day in text and
    /// in events (see [`Anonymise`]).
    pub fn zero_utc(mut self, on: bool) -> Anonymise {
        self.zero_utc = on;
        self
    }

    /// Writes 0 as the header's timestamp (when logging started, in microseconds
    /// since boot): how long the vehicle had been on before logging is then not told.
    /// Data timestamps stay, so times counted from the start (as `ulog cut --start`
    /// and most viewers count them) count from boot instead.
    pub fn zero_start(mut self, on: bool) -> Anonymise {
        self.zero_start = on;
        self
    }

    /// The [`Edit`] that anonymises `log` (add a window or topics to it as to any
    /// edit). `log` is surveyed first, for what holds a position (see
    /// [`Anonymise`]); the edit then applies to the same log.
    pub fn edit<'f>(&self, log: &crate::ULog<'_>) -> Edit<'f> {
        let mut drop: Vec<String> = IDENTIFYING_KEYS.iter().map(|k| k.to_string()).collect();
        if self.zero_utc {
            drop.extend(UTC_KEYS.iter().map(|k| k.to_string()));
        }
        drop.retain(|k| !self.keep.contains(k));
        let raw: Vec<&str> = RAW_GPS_TOPICS
            .iter()
            .copied()
            .filter(|t| !log.topic_instances(t).is_empty())
            .collect();
        let survey = Survey::of(log);
        let texts = Arc::new(Texts {
            places: survey.places.clone(),
            rotation: survey.anchor.map(|a| Rotation::taking(a, self.to)),
            anchor: survey.anchor,
            zero_utc: self.zero_utc,
        });
        let survey = Arc::new(survey);
        let mut messages = mapping::Messages::new(log, survey.clone(), texts.clone());
        #[cfg(feature = "events")]
        let dated_events = match self.zero_utc {
            true => events::dated_events(log),
            false => Default::default(),
        };
        #[cfg(not(feature = "events"))]
        let dated_events = Default::default();
        let mut payloads = mapping::Payloads::new(survey, texts, dated_events);
        let mut edit = Edit::new();
        if self.zero_start {
            edit = edit.header_timestamp(0);
        }
        edit.exclude(raw)
            .drop_info(drop)
            .map_payloads(move |sub, payload| payloads.map(sub, payload))
            .map_messages(move |msg_type, payload| messages.map(msg_type, payload))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Great-circle distance in metres.
    fn distance(a: (f64, f64), b: (f64, f64)) -> f64 {
        let (p1, p2) = (a.0.to_radians(), b.0.to_radians());
        let h = ((p2 - p1) / 2.0).sin().powi(2)
            + p1.cos() * p2.cos() * ((b.1 - a.1).to_radians() / 2.0).sin().powi(2);
        2.0 * 6_371_000.0 * h.sqrt().asin()
    }

    #[test]
    fn positions_in_arrays_under_no_name_move_entry_by_entry() {
        use crate::testing::LogBuilder;
        use crate::ULog;
        let (lat, lon) = (47.397742f64, 8.545594f64);
        let mut b = LogBuilder::new(1, 0);
        b.format("vehicle_gps_position:uint64_t timestamp;int32_t lat;int32_t lon;");
        // Three waypoints: their latitudes, then their longitudes (the closest
        // longitude to `lat[2]` in the row is `lon[0]`).
        b.format("custom_plan:uint64_t timestamp;double[3] lat_wp;double[3] lon_wp;");
        b.subscribe(0, 0, "vehicle_gps_position");
        b.subscribe(0, 1, "custom_plan");
        let waypoints = [(0.004, -0.003), (0.01, 0.02), (-0.02, 0.01)];
        for n in 0..10u64 {
            let t = (1 + n * 1_000).to_le_bytes();
            let fix = [(lat * 1e7) as i32, (lon * 1e7) as i32 + n as i32 * 100];
            b.data(
                0,
                &[&t[..], &fix[0].to_le_bytes(), &fix[1].to_le_bytes()].concat(),
            );
            let mut row = t.to_vec();
            for (d, _) in waypoints {
                row.extend_from_slice(&(lat + d).to_le_bytes());
            }
            for (_, d) in waypoints {
                row.extend_from_slice(&(lon + d).to_le_bytes());
            }
            b.data(1, &row);
        }
        let log = ULog::parse(b.bytes()).unwrap();
        let mut out = Vec::new();
        Anonymise::new()
            .to(-33.9, 151.2)
            .edit(&log)
            .write(&log, &mut out)
            .unwrap();
        let anon = ULog::parse(&out).unwrap();
        let plan = anon.topic("custom_plan", 0).unwrap();
        let at = |path: &str| {
            let f = plan.field(path).unwrap();
            f.read(plan.payload(0).unwrap())
                .and_then(|v| v.as_f64())
                .unwrap()
        };
        // The first fix went to the target; each waypoint is as far from it as it
        // was from the fix, and from every other waypoint.
        let moved: Vec<(f64, f64)> = (0..3)
            .map(|i| (at(&format!("lat_wp[{i}]")), at(&format!("lon_wp[{i}]"))))
            .collect();
        let before: Vec<(f64, f64)> = waypoints.iter().map(|(a, b)| (lat + a, lon + b)).collect();
        for i in 0..3 {
            let (d0, d1) = (
                distance((lat, lon), before[i]),
                distance((-33.9, 151.2), moved[i]),
            );
            assert!((d0 - d1).abs() < 0.01, "waypoint {i}: {d0} m became {d1} m");
            for j in 0..3 {
                let (d0, d1) = (distance(before[i], before[j]), distance(moved[i], moved[j]));
                assert!((d0 - d1).abs() < 0.01, "{i} to {j}: {d0} m became {d1} m");
            }
        }
    }

    #[test]
    fn command_positions_move_and_other_commands_stay() {
        use crate::testing::LogBuilder;
        use crate::ULog;
        let mut b = LogBuilder::new(1, 0);
        b.format(
            "vehicle_command:uint64_t timestamp;double param5;double param6;uint32_t command;",
        );
        b.subscribe(0, 0, "vehicle_command");
        let row = |t: u64, p5: f64, p6: f64, command: u32| {
            [
                &t.to_le_bytes()[..],
                &p5.to_le_bytes(),
                &p6.to_le_bytes(),
                &command.to_le_bytes(),
            ]
            .concat()
        };
        // Reposition (192) to a place; arm (400) with values in param5/6 that are
        // not a position.
        b.data(0, &row(1, 47.397742, 8.545594, 192));
        b.data(0, &row(2, 47.5, 8.5, 400));
        let log = ULog::parse(b.bytes()).unwrap();
        let mut out = Vec::new();
        Anonymise::new()
            .to(10.0, 20.0)
            .edit(&log)
            .write(&log, &mut out)
            .unwrap();
        let cut = ULog::parse(&out).unwrap();
        let topic = cut.topic("vehicle_command", 0).unwrap();
        let p5 = topic.field("param5").unwrap();
        let p6 = topic.field("param6").unwrap();
        let at = |f: &crate::FieldReader, i: usize| {
            f.read(topic.payload(i).unwrap())
                .and_then(|v| v.as_f64())
                .unwrap()
        };
        assert!((at(&p5, 0) - 10.0).abs() < 1e-9 && (at(&p6, 0) - 20.0).abs() < 1e-9);
        assert_eq!((at(&p5, 1), at(&p6, 1)), (47.5, 8.5));
    }
}
