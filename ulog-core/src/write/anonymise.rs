//! [`Anonymise`]: what identifies a vehicle and where it flew, taken out of a log
//! through an [`Edit`].

use std::collections::HashMap;

use ulog_format::{BasicType, LeafKind};

use crate::definitions::Subscription;
use crate::write::edit::Edit;

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
/// 1e-7 degrees, `float` or `double` in degrees.
pub const POSITION_FIELDS: &[(&str, &str)] = &[
    ("lat", "lon"),
    ("latitude", "longitude"),
    ("latitude_deg", "longitude_deg"),
    ("ref_lat", "ref_lon"),
];

/// Positions held in arrays, by topic: (topic, latitude path, longitude path); taken
/// when both are `double` (degrees; older firmware logged the same topic's field in
/// metres, as `float`).
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
/// - every position ([`POSITION_FIELDS`], [`ARRAY_POSITIONS`], and `param5`/`param6` of the
///   `vehicle_command`s of [`POSITION_COMMANDS`]) is moved by one rotation of the Earth that
///   takes the log's first position to [`Anonymise::to`] (default 0° N 0° E): a
///   rotation keeps every distance between positions and the flight's shape (north
///   stays north near the flight), altitudes are not changed; a position of 0, 0 (no
///   fix) and values that are not numbers stay as they are;
/// - with [`Anonymise::zero_utc`], the `time_utc_usec` fields (GPS time) are zeroed;
/// - with [`Anonymise::zero_start`], the header's timestamp is 0;
/// - the topics of raw receiver data ([`RAW_GPS_TOPICS`]) are left out.
///
/// Everything else is kept byte for byte, as [`Edit`] keeps it.
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

    /// Also leaves out the wall-clock keys ([`UTC_KEYS`]) and zeroes the GPS time
    /// fields (`time_utc_usec`).
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
    /// edit).
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
        let mut positions = Positions {
            to: self.to,
            rotation: None,
            plans: HashMap::new(),
            zero_utc: self.zero_utc,
        };
        let mut edit = Edit::new();
        if self.zero_start {
            edit = edit.header_timestamp(0);
        }
        edit.exclude(raw)
            .drop_info(drop)
            .map_payloads(move |sub, payload| positions.map(sub, payload))
    }
}

/// Where a topic's positions and GPS times are.
#[derive(Debug, Clone, Default)]
struct Plan {
    /// Latitude and longitude leaves: offset and type of each.
    pairs: Vec<((usize, BasicType), (usize, BasicType))>,
    /// `time_utc_usec` leaves.
    times: Vec<(usize, BasicType)>,
    /// For `vehicle_command`: where its command id and position parameters are.
    command: Option<Command>,
}

/// Where a `vehicle_command`'s id (`command`) and position (`param5`, `param6`) are.
#[derive(Debug, Clone, Copy)]
struct Command {
    id: (usize, BasicType),
    lat: (usize, BasicType),
    lon: (usize, BasicType),
}

impl Plan {
    fn of(sub: &Subscription) -> Plan {
        let mut plan = Plan::default();
        let Ok(layout) = sub.layout() else {
            return plan;
        };
        let leaves: HashMap<&str, (usize, BasicType)> = layout
            .columns()
            .filter(|l| l.kind == LeafKind::Scalar)
            .map(|l| (l.path.as_str(), (l.offset, l.ty)))
            .collect();
        for (topic, lat, lon) in ARRAY_POSITIONS {
            if sub.name() == *topic {
                if let (Some(&a), Some(&b)) = (leaves.get(lat), leaves.get(lon)) {
                    if a.1 == BasicType::Double && b.1 == BasicType::Double {
                        plan.pairs.push((a, b));
                    }
                }
            }
        }
        if sub.name() == "vehicle_command" {
            if let (Some(&c), Some(&p5), Some(&p6)) = (
                leaves.get("command"),
                leaves.get("param5"),
                leaves.get("param6"),
            ) {
                if position_type(p5.1) && position_type(p6.1) {
                    plan.command = Some(Command {
                        id: c,
                        lat: p5,
                        lon: p6,
                    });
                }
            }
        }
        for leaf in layout.columns().filter(|l| l.kind == LeafKind::Scalar) {
            let (prefix, last) = match leaf.path.rsplit_once('.') {
                Some((p, l)) => (format!("{p}."), l),
                None => (String::new(), leaf.path.as_str()),
            };
            if last == "time_utc_usec" && matches!(leaf.ty, BasicType::UInt64 | BasicType::Int64) {
                plan.times.push((leaf.offset, leaf.ty));
            }
            for (lat, lon) in POSITION_FIELDS {
                if last == *lat {
                    if let Some(&other) = leaves.get(format!("{prefix}{lon}").as_str()) {
                        let pair = ((leaf.offset, leaf.ty), other);
                        if position_type(pair.0 .1) && position_type(other.1) {
                            plan.pairs.push(pair);
                        }
                    }
                }
            }
        }
        plan
    }
}

fn position_type(ty: BasicType) -> bool {
    matches!(ty, BasicType::Int32 | BasicType::Float | BasicType::Double)
}

/// The positions of a log as an edit goes: the rotation is fixed by the first.
struct Positions {
    to: (f64, f64),
    rotation: Option<Rotation>,
    plans: HashMap<usize, Plan>,
    zero_utc: bool,
}

impl Positions {
    fn map(&mut self, sub: &Subscription, payload: &mut [u8]) {
        let plan = self
            .plans
            .entry(sub.index())
            .or_insert_with(|| Plan::of(sub));
        // A command's parameters are a position only for some commands.
        let command = plan
            .command
            .filter(|c| read_uint(payload, c.id).is_some_and(|id| POSITION_COMMANDS.contains(&id)));
        let pairs = plan.pairs.iter().copied();
        for (lat, lon) in pairs.chain(command.map(|c| (c.lat, c.lon))) {
            let (Some(a), Some(b)) = (read(payload, lat), read(payload, lon)) else {
                continue;
            };
            if !a.is_finite() || !b.is_finite() || (a == 0.0 && b == 0.0) {
                continue;
            }
            let to = self.to;
            let rotation = self
                .rotation
                .get_or_insert_with(|| Rotation::taking((a, b), to));
            let (x, y) = rotation.apply(a, b);
            write(payload, lat, x);
            write(payload, lon, y);
        }
        if self.zero_utc {
            for &(offset, _) in &plan.times {
                if let Some(bytes) = payload.get_mut(offset..offset + 8) {
                    bytes.fill(0);
                }
            }
        }
    }
}

/// An unsigned integer field.
fn read_uint(payload: &[u8], (offset, ty): (usize, BasicType)) -> Option<u32> {
    let bytes = payload.get(offset..offset + ty.size())?;
    match ty {
        BasicType::UInt8 => Some(bytes[0] as u32),
        BasicType::UInt16 => Some(u16::from_le_bytes(bytes.try_into().ok()?) as u32),
        BasicType::UInt32 => Some(u32::from_le_bytes(bytes.try_into().ok()?)),
        _ => None,
    }
}

/// A value in degrees (`int32_t` in 1e-7 degrees).
fn read(payload: &[u8], (offset, ty): (usize, BasicType)) -> Option<f64> {
    let bytes = payload.get(offset..offset + ty.size())?;
    Some(match ty {
        BasicType::Int32 => i32::from_le_bytes(bytes.try_into().ok()?) as f64 * 1e-7,
        BasicType::Float => f32::from_le_bytes(bytes.try_into().ok()?) as f64,
        BasicType::Double => f64::from_le_bytes(bytes.try_into().ok()?),
        _ => return None,
    })
}

fn write(payload: &mut [u8], (offset, ty): (usize, BasicType), degrees: f64) {
    let Some(bytes) = payload.get_mut(offset..offset + ty.size()) else {
        return;
    };
    match ty {
        BasicType::Int32 => {
            let v = (degrees * 1e7)
                .round()
                .clamp(i32::MIN as f64, i32::MAX as f64) as i32;
            bytes.copy_from_slice(&v.to_le_bytes());
        }
        BasicType::Float => bytes.copy_from_slice(&(degrees as f32).to_le_bytes()),
        BasicType::Double => bytes.copy_from_slice(&degrees.to_le_bytes()),
        _ => {}
    }
}

/// A rotation of the sphere: turn about the polar axis to the target's meridian after
/// turning about the east-west axis of the first position's meridian by the change of
/// latitude (so that north stays north along that meridian).
#[derive(Debug, Clone, Copy)]
struct Rotation {
    /// Row-major 3×3 matrix on unit vectors (x to 0° N 0° E, z to the north pole).
    m: [[f64; 3]; 3],
}

impl Rotation {
    /// The rotation that takes `from` (latitude, longitude, degrees) to `to`.
    fn taking(from: (f64, f64), to: (f64, f64)) -> Rotation {
        let (lat0, lon0) = (from.0.to_radians(), from.1.to_radians());
        let (lat1, lon1) = (to.0.to_radians(), to.1.to_radians());
        // To the first position's meridian at 0° E, tilt by the change of latitude
        // (about the y axis), then to the target's meridian.
        let a = rot_z(-lon0);
        let b = rot_y(-(lat1 - lat0));
        let c = rot_z(lon1);
        Rotation {
            m: mul(&c, &mul(&b, &a)),
        }
    }

    fn apply(&self, lat: f64, lon: f64) -> (f64, f64) {
        let (la, lo) = (lat.to_radians(), lon.to_radians());
        let v = [la.cos() * lo.cos(), la.cos() * lo.sin(), la.sin()];
        let m = &self.m;
        let w: [f64; 3] =
            core::array::from_fn(|i| m[i][0] * v[0] + m[i][1] * v[1] + m[i][2] * v[2]);
        let lat = w[2].clamp(-1.0, 1.0).asin().to_degrees();
        let lon = w[1].atan2(w[0]).to_degrees();
        (lat, lon)
    }
}

fn rot_z(a: f64) -> [[f64; 3]; 3] {
    let (s, c) = a.sin_cos();
    [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]
}

/// A rotation about the y axis that raises a point on the x axis towards z by `-a`
/// (so `rot_y(-d)` adds `d` to the latitude of points on the 0° meridian).
fn rot_y(a: f64) -> [[f64; 3]; 3] {
    let (s, c) = a.sin_cos();
    [[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]]
}

fn mul(a: &[[f64; 3]; 3], b: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
    core::array::from_fn(|i| core::array::from_fn(|j| (0..3).map(|k| a[i][k] * b[k][j]).sum()))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Great-circle distance in metres.
    fn distance(a: (f64, f64), b: (f64, f64)) -> f64 {
        let (p1, p2) = (a.0.to_radians(), b.0.to_radians());
        let dp = p2 - p1;
        let dl = (b.1 - a.1).to_radians();
        let h = (dp / 2.0).sin().powi(2) + p1.cos() * p2.cos() * (dl / 2.0).sin().powi(2);
        2.0 * 6_371_000.0 * h.sqrt().asin()
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

    #[test]
    fn the_rotation_takes_the_first_point_to_the_target_and_keeps_distances() {
        let from = (47.397742, 8.545594);
        for to in [(0.0, 0.0), (-33.9, 151.2), (60.0, -120.0)] {
            let r = Rotation::taking(from, to);
            let (lat, lon) = r.apply(from.0, from.1);
            assert!(
                (lat - to.0).abs() < 1e-9 && (lon - to.1).abs() < 1e-9,
                "{lat} {lon}"
            );
            let points = [(47.3978, 8.5457), (47.41, 8.52), (47.2, 8.9), (46.0, 7.0)];
            for p in points {
                for q in points {
                    let (a, b) = (r.apply(p.0, p.1), r.apply(q.0, q.1));
                    assert!((distance(p, q) - distance(a, b)).abs() < 1e-3);
                }
            }
            // North stays north at the first position: a point due north of it is
            // due north of its image.
            let north = r.apply(from.0 + 0.001, from.1);
            assert!((north.1 - to.1).abs() < 1e-9 && north.0 > to.0);
        }
    }
}
