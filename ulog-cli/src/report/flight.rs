//! What the report reads through typed bindings: attitude (Euler angles from the
//! quaternions) and the local track; the summary's distance, altitude, speed and
//! battery figures from the library's flight analysis ([`figures`]).
//!
//! One struct per topic, whatever the firmware: fields that only some firmware logs
//! are `Option`s, and the reader finds the rest by name. Each is read from the topic
//! `ULog::read` picks (instance 0), decoded with the plan it makes, as the second pass
//! ([`super::pass`]) hands the rows.

use ulog_core::analysis::FlightAnalysis;
use ulog_core::read::TimeSpan;
use ulog_core::typed::Plan;
use ulog_core::{ULog, ULogMessage};

use super::pass::{Routes, Rows};
use super::table::{Builder, Table};
use crate::report::plots::Plot;

#[derive(ULogMessage, Debug, Clone, Copy)]
struct VehicleAttitude {
    timestamp: u64,
    /// Since 2017.
    q: Option<[f32; 4]>,
    /// Before.
    roll: Option<f32>,
    pitch: Option<f32>,
    yaw: Option<f32>,
}

#[derive(ULogMessage, Debug, Clone, Copy)]
struct VehicleAttitudeSetpoint {
    timestamp: u64,
    /// Until 2024 (PX4 v1.15 logs only the quaternion).
    roll_body: Option<f32>,
    pitch_body: Option<f32>,
    yaw_body: Option<f32>,
    q_d: Option<[f32; 4]>,
}

#[derive(ULogMessage, Debug, Clone, Copy)]
struct VehicleLocalPosition {
    timestamp: u64,
    x: f32,
    y: f32,
    xy_valid: bool,
}

/// The subscription `ULog::read::<T>(0)` reads, and the plan it decodes its rows
/// with; `None` where the log has no such topic or its format does not fit `T`.
fn typed<T: ULogMessage>(log: &ULog<'_>) -> Option<(usize, Plan<T>)> {
    typed_instance(log, 0)
}

/// [`typed`] of instance `multi_id`.
fn typed_instance<T: ULogMessage>(log: &ULog<'_>, multi_id: u8) -> Option<(usize, Plan<T>)> {
    let rows = log.read::<T>(multi_id).ok()?;
    Some((rows.topic().subscription().index(), rows.plan().clone()))
}

/// The data messages of subscription `sub`, as the first pass counted them.
fn count(rows: &[usize], sub: usize) -> usize {
    rows.get(sub).copied().unwrap_or(0)
}

/// Roll, pitch and yaw (degrees) of a unit quaternion (w, x, y, z), as PX4's
/// `matrix::Eulerf` gives them.
fn euler(q: [f32; 4]) -> [f32; 3] {
    let [w, x, y, z] = q.map(f64::from);
    let roll = (2.0 * (w * x + y * z)).atan2(1.0 - 2.0 * (x * x + y * y));
    let pitch = (2.0 * (w * y - z * x)).clamp(-1.0, 1.0).asin();
    let yaw = (2.0 * (w * z + x * y)).atan2(1.0 - 2.0 * (y * y + z * z));
    [roll, pitch, yaw].map(|a| a.to_degrees() as f32)
}

/// Roll, pitch and yaw (degrees) of an attitude row, where it has them.
trait Angles {
    fn angles(&self) -> Option<(u64, [f32; 3])>;
}

impl Angles for VehicleAttitude {
    fn angles(&self) -> Option<(u64, [f32; 3])> {
        let angles = match (self.q, self.roll, self.pitch, self.yaw) {
            (Some(q), ..) => euler(q),
            (None, Some(r), Some(p), Some(y)) => [r, p, y].map(f32::to_degrees),
            _ => return None,
        };
        Some((self.timestamp, angles))
    }
}

impl Angles for VehicleAttitudeSetpoint {
    fn angles(&self) -> Option<(u64, [f32; 3])> {
        let angles = match (self.roll_body, self.pitch_body, self.yaw_body, self.q_d) {
            (Some(r), Some(p), Some(y), _) => [r, p, y].map(f32::to_degrees),
            (.., Some(q)) => euler(q),
            _ => return None,
        };
        Some((self.timestamp, angles))
    }
}

/// The angles of one attitude topic, thinned as they come.
struct AngleRows<T> {
    sub: usize,
    plan: Plan<T>,
    builder: Builder,
}

impl<T: ULogMessage + Angles> AngleRows<T> {
    fn new(
        log: &ULog<'_>,
        rows: &[usize],
        what: &str,
        span: &TimeSpan,
        multi_id: u8,
    ) -> Option<Self> {
        let (sub, plan) = typed_instance::<T>(log, multi_id)?;
        let builder = Builder::new(names(what), count(rows, sub), span);
        Some(AngleRows { sub, plan, builder })
    }
}

impl<T: ULogMessage + Angles> Rows for AngleRows<T> {
    fn push(&mut self, payload: &[u8]) {
        if let Some((t, angles)) = self.plan.decode(payload).ok().and_then(|a| a.angles()) {
            self.builder.push(t, &angles);
        }
    }
}

/// The roll, pitch and yaw plots (estimate and setpoint) being read.
pub struct Attitude {
    /// Each instance of the estimate: PX4 logs one; a replay or an estimator under
    /// test writes its own beside it (instance 1, …), drawn as `estimate 1`, ….
    estimates: Vec<(u8, AngleRows<VehicleAttitude>)>,
    setpoint: Option<AngleRows<VehicleAttitudeSetpoint>>,
}

/// The attitude plots, to be read where the log has attitude.
pub fn attitude(log: &ULog<'_>, rows: &[usize], span: &TimeSpan) -> Attitude {
    let estimates = log
        .topic_instances(VehicleAttitude::NAME)
        .iter()
        .filter_map(|t| {
            let id = t.multi_id();
            let what = match id {
                0 => "estimate".to_owned(),
                n => format!("estimate {n}"),
            };
            Some((id, AngleRows::new(log, rows, &what, span, id)?))
        })
        .collect();
    Attitude {
        estimates,
        setpoint: AngleRows::new(log, rows, "setpoint", span, 0),
    }
}

impl Attitude {
    /// Whether the log has neither topic.
    pub fn is_none(&self) -> bool {
        self.estimates.is_empty() && self.setpoint.is_none()
    }

    /// Has the second pass hand the attitude rows here.
    pub fn route<'c>(&'c mut self, routes: &mut Routes<'c>) {
        for (_, e) in &mut self.estimates {
            routes.add(e.sub, e);
        }
        if let Some(s) = &mut self.setpoint {
            routes.add(s.sub, s);
        }
    }

    /// The roll, pitch and yaw plots (estimate and setpoint), where the log has
    /// attitude.
    pub fn finish(self) -> Vec<Plot> {
        let mut tables: Vec<(Option<Table>, String)> = self
            .estimates
            .into_iter()
            .map(|(id, e)| {
                let topic = match id {
                    0 => VehicleAttitude::NAME.to_owned(),
                    n => format!("{}:{n}", VehicleAttitude::NAME),
                };
                (Some(e.builder.finish()), topic)
            })
            .collect();
        tables.push((
            self.setpoint.map(|s| s.builder.finish()),
            VehicleAttitudeSetpoint::NAME.to_owned(),
        ));
        let mut plots = Vec::new();
        for (axis, (id, title)) in [
            ("roll", "Roll angle"),
            ("pitch", "Pitch angle"),
            ("yaw", "Yaw angle"),
        ]
        .iter()
        .enumerate()
        {
            let mut plot = Plot {
                id: (*id).to_owned(),
                title: (*title).to_owned(),
                unit: "deg".into(),
                sources: Vec::new(),
                tables: Vec::new(),
            };
            for (table, topic) in &tables {
                if let Some(t) = table.as_ref().filter(|t| !t.x.is_empty()) {
                    plot.sources.push(topic.clone());
                    plot.tables.push(Table {
                        labels: vec![t.labels[axis].clone()],
                        x: t.x.clone(),
                        y: vec![t.y[axis].clone()],
                        thinned: t.thinned,
                        color: None,
                    });
                }
            }
            if !plot.tables.is_empty() {
                plots.push(plot);
            }
        }
        plots
    }
}

fn names(what: &str) -> Vec<String> {
    ["roll", "pitch", "yaw"]
        .iter()
        .map(|a| format!("{a} {what}"))
        .collect()
}

/// Figures of the header from the local position estimate and the battery.
#[derive(Debug, Default)]
pub struct Figures {
    /// Metres flown (horizontal and vertical steps between valid estimates).
    pub distance_m: Option<f64>,
    /// Highest point above the first estimate, metres.
    pub max_altitude_m: Option<f64>,
    /// Fastest horizontal speed, m/s.
    pub max_speed_m_s: Option<f64>,
    /// (first, last) voltage with a battery connected, remaining fraction and mAh drawn.
    pub battery: Option<Battery>,
}

/// The battery's use over the log.
#[derive(Debug)]
pub struct Battery {
    /// Volts at the first and last reading.
    pub voltage: (f32, f32),
    /// Remaining fraction at the first and last reading.
    pub remaining: (f32, f32),
    /// Charge drawn, where logged.
    pub discharged_mah: Option<f32>,
}

/// The header's figures, from the flight analysis (the figures `ulog analyze` gives).
pub fn figures(flight: &FlightAnalysis) -> Figures {
    let s = &flight.stats;
    let b = &flight.battery;
    let moved = s.position_rows > 0;
    Figures {
        distance_m: moved.then_some(s.flown_distance_m),
        max_altitude_m: moved.then_some(s.max_altitude_above_start_m),
        max_speed_m_s: moved.then_some(s.max_horizontal_speed_m_s),
        battery: b.voltage_first_last_v.map(|voltage| Battery {
            voltage,
            remaining: b.remaining_first_last.unwrap_or((f32::NAN, f32::NAN)),
            discharged_mah: b.discharged_mah.map(|m| m as f32),
        }),
    }
}

/// The track in local metres (east, north) from the local position estimate, every
/// n-th estimate, being read.
pub struct Track {
    sub: usize,
    plan: Plan<VehicleLocalPosition>,
    step: usize,
    row: usize,
    points: Vec<[f32; 2]>,
}

/// The track, to be read where the log has the local position: at most `points`
/// points (every n-th estimate).
pub fn track(log: &ULog<'_>, rows: &[usize], points: usize) -> Option<Track> {
    let (sub, plan) = typed::<VehicleLocalPosition>(log)?;
    Some(Track {
        sub,
        plan,
        step: count(rows, sub).div_ceil(points.max(1)).max(1),
        row: 0,
        points: Vec::new(),
    })
}

impl Rows for Track {
    fn push(&mut self, payload: &[u8]) {
        let row = self.row;
        self.row += 1;
        if row % self.step != 0 {
            return;
        }
        if let Ok(p) = self.plan.decode(payload) {
            if p.xy_valid && p.x.is_finite() && p.y.is_finite() {
                self.points.push([p.y, p.x]);
            }
        }
    }
}

impl Track {
    /// Has the second pass hand the local position rows here.
    pub fn route<'c>(&'c mut self, routes: &mut Routes<'c>) {
        routes.add(self.sub, self);
    }

    /// The track, when it has two points or more.
    pub fn finish(self) -> Option<Vec<[f32; 2]>> {
        (self.points.len() > 1).then_some(self.points)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn euler_angles_of_quaternions() {
        let close = |a: [f32; 3], b: [f32; 3]| a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-3);
        assert!(close(euler([1.0, 0.0, 0.0, 0.0]), [0.0, 0.0, 0.0]));
        let h = (0.5f32).sqrt();
        assert!(close(euler([h, h, 0.0, 0.0]), [90.0, 0.0, 0.0]));
        assert!(close(euler([h, 0.0, 0.0, h]), [0.0, 0.0, 90.0]));
        // Pitch away from ±90°, where roll and yaw are undefined.
        let (c, s) = (15f32.to_radians().cos(), 15f32.to_radians().sin());
        assert!(close(euler([c, 0.0, s, 0.0]), [0.0, 30.0, 0.0]));
    }

    #[test]
    fn every_instance_of_the_estimate_is_drawn() {
        // A replay's estimate (instance 1) beside the logged one, as the
        // `replay_attitude` example writes them.
        let mut b = ulog_core::testing::LogBuilder::new(1, 0);
        b.format("vehicle_attitude:uint64_t timestamp;float[4] q;");
        b.subscribe(0, 0, "vehicle_attitude");
        b.subscribe(1, 1, "vehicle_attitude");
        for t in [1_000u64, 2_000] {
            for msg_id in [0, 1] {
                let mut payload = t.to_le_bytes().to_vec();
                for v in [1.0f32, 0.0, 0.0, 0.0] {
                    payload.extend(v.to_le_bytes());
                }
                b.data(msg_id, &payload);
            }
        }
        let bytes = b.into_bytes();
        let log = ULog::parse(&bytes).unwrap();
        let mut rows = vec![0; 2];
        for t in log.topics() {
            rows[t.subscription().index()] = t.len();
        }
        let mut attitude = attitude(&log, &rows, log.span());
        for (id, e) in &mut attitude.estimates {
            for p in log.topic("vehicle_attitude", *id).unwrap().payloads() {
                e.push(p);
            }
        }
        let plots = attitude.finish();
        let ids: Vec<&str> = plots.iter().map(|p| p.id.as_str()).collect();
        assert_eq!(ids, ["roll", "pitch", "yaw"]);
        assert_eq!(plots[0].sources, ["vehicle_attitude", "vehicle_attitude:1"]);
        let labels: Vec<&str> = plots[0]
            .tables
            .iter()
            .map(|t| t.labels[0].as_str())
            .collect();
        assert_eq!(labels, ["roll estimate", "roll estimate 1"]);
    }
}
