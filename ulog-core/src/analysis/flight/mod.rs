//! What happened in a flight, read in one pass: Flight Review v2's five diagnostics
//! (`battery_brownout`, `ekf_failure`, `gps_interference`, `motor_failure`,
//! `rc_loss`), flight statistics, battery, GPS quality, vibration, the IMU's
//! spectra and the rate controllers' step responses ([`analyze`]).
//!
//! Every topic is read through one typed binding that spans PX4's firmware (v1.7 to
//! v1.16 in the corpus), so a field that changed type or a renamed topic
//! (`vehicle_gps_position` / `sensor_gps`) reads the same way everywhere. Each rule
//! follows Flight Review v2's thresholds; where ours differs (one diagnostic per
//! episode with its start and end rather than one per detection, each topic instance
//! on its own, a GPS baseline taken once the receiver has a fix, an RC loss open at
//! the end of the log reported) the rule's module says so, and
//! `docs/ANALYSIS.md` compares the two on every corpus log.

mod brownout;
mod diagnostic;
mod ekf;
mod gps;
mod json;
mod modes;
mod motors;
mod rc_loss;
mod spectra;
mod stats;
mod steps;
mod topics;

pub use diagnostic::{Diagnostic, Evidence, EvidenceValue, Severity};
pub use gps::GpsQuality;
pub use modes::{mode_name, EventKind, ModeSegment, Timeline};
pub use spectra::{AxisSpectrum, SignalSpectrogram};
pub use stats::{BatterySummary, FlightStats, VibrationSummary};
pub use steps::AxisStep;

use crate::definitions::Subscription;
use crate::error::ReadError;
use crate::pass::scan::ScanOptions;
use crate::pass::source::Source;
use crate::typed::TopicPlan;
use crate::{Finding, ULogTopics};

use topics::FlightTopic;

/// Below this logging rate of the controllers' rates, a step response is too coarse
/// to trust (a rate loop settles in tens of milliseconds).
const MIN_STEP_RATE_HZ: f64 = 100.0;

/// What [`analyze`] computes beyond the diagnostics and statistics.
#[derive(Debug, Clone, PartialEq)]
pub struct AnalyzeOptions {
    spectra: bool,
    step_response: bool,
}

impl Default for AnalyzeOptions {
    /// Everything: the spectra and the step responses too.
    fn default() -> AnalyzeOptions {
        AnalyzeOptions {
            spectra: true,
            step_response: true,
        }
    }
}

impl AnalyzeOptions {
    /// Whether to compute the IMU's spectra (on by default).
    pub fn spectra(mut self, on: bool) -> AnalyzeOptions {
        self.spectra = on;
        self
    }

    /// Whether to compute the rate controllers' step responses (on by default; holds
    /// up to 2^18 rows of each of two topics).
    pub fn step_response(mut self, on: bool) -> AnalyzeOptions {
        self.step_response = on;
        self
    }
}

/// What [`analyze`] found in a log.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct FlightAnalysis {
    /// The anomalies, in time order.
    pub diagnostics: Vec<Diagnostic>,
    /// Flight modes, arming, takeoffs and landings.
    pub timeline: Timeline,
    /// Distance, altitude, speeds, tilt, rotation.
    pub stats: FlightStats,
    /// The battery.
    pub battery: BatterySummary,
    /// The GPS fix's quality; `None` without a GPS topic.
    pub gps: Option<GpsQuality>,
    /// The accelerometer's vibration metric.
    pub vibration: VibrationSummary,
    /// The spectra of `sensor_combined`'s gyro and accelerometer axes while armed,
    /// with their dominant frequencies, and of the rate controllers' outputs
    /// (`actuator_controls_0` or `vehicle_torque_setpoint`: roll, pitch, yaw).
    pub spectra: Vec<AxisSpectrum>,
    /// The gyro's and the accelerometer's power over time while armed.
    pub spectrograms: Vec<SignalSpectrogram>,
    /// The rate controllers' step responses over the longest armed stretch.
    pub step_responses: Vec<AxisStep>,
    /// The first and last time of a row the analysis read, µs.
    pub span_us: Option<(u64, u64)>,
    /// What could not be analysed and why: a topic whose format the bindings do not
    /// fit, step responses without enough data.
    pub notes: Vec<String>,
    /// What framing found (damage, with byte offsets): the analysis covers the rest.
    pub findings: Vec<Finding>,
}

impl FlightAnalysis {
    /// The diagnostics with id `id`.
    pub fn diagnostics_of<'a>(&'a self, id: &'a str) -> impl Iterator<Item = &'a Diagnostic> {
        self.diagnostics.iter().filter(move |d| d.id == id)
    }
}

/// The state of a pass that the rules share.
pub(super) struct Now {
    /// The row's time, µs.
    time: u64,
    /// `vehicle_status.arming_state == 2` at the last row before.
    armed: bool,
    /// The flight mode then.
    nav_state: Option<u8>,
    /// `vehicle_status.vehicle_type` then (1 multicopter, 2 fixed-wing), where logged.
    vehicle_type: Option<u8>,
}

/// Analyses a log in one pass in file order, from any [`Source`] (a file is read in
/// chunks: memory is the analysis's state, a few MiB, not the log). A
/// [`FlightAnalyzer`] fed by the pass.
///
/// A damaged log is analysed up to and around its damage (the damage is in
/// [`FlightAnalysis::findings`]); only a log that cannot be read at all is an error.
///
/// ```
/// use ulog_core::analysis::{analyze, AnalyzeOptions};
///
/// let bytes = ulog_core::testing::sample_log();
/// let flight = analyze(&bytes, &AnalyzeOptions::default())?;
/// assert!(flight.span_us.is_some() && flight.diagnostics.is_empty());
/// for d in &flight.diagnostics {
///     println!("{} {} at {} µs: {}", d.severity, d.id, d.timestamp_us, d.summary);
/// }
/// # Ok::<(), ulog_core::ReadError>(())
/// ```
pub fn analyze<'s>(
    source: impl Into<Source<'s>>,
    options: &AnalyzeOptions,
) -> Result<FlightAnalysis, ReadError> {
    let mut analyzer = FlightAnalyzer::new(options);
    let scan = ScanOptions::default().read_ahead(true);
    let summary = crate::scan(source, &scan, |r| analyzer.push(r.topic, r.payload))?;
    let mut flight = analyzer.finish();
    flight.findings = summary.findings;
    Ok(flight)
}

/// The analysis fed one data message at a time, for a pass that does other work too
/// (the flight report reads the log once for its plots and this). [`analyze`] is a
/// pass that feeds only this.
///
/// Each subscription is planned at its first message: a topic the analysis reads whose
/// format its binding does not fit is named in [`FlightAnalysis::notes`] and left out.
///
/// ```
/// use ulog_core::analysis::{AnalyzeOptions, FlightAnalyzer};
/// use ulog_core::ScanOptions;
///
/// let bytes = ulog_core::testing::sample_log();
/// let mut analyzer = FlightAnalyzer::new(&AnalyzeOptions::default());
/// let mut rows = 0;
/// ulog_core::scan(&bytes, &ScanOptions::default(), |r| {
///     rows += 1;
///     analyzer.push(r.topic, r.payload);
/// })?;
/// let flight = analyzer.finish();
/// assert!(rows > 0 && flight.span_us.is_some());
/// # Ok::<(), ulog_core::ReadError>(())
/// ```
pub struct FlightAnalyzer {
    pass: Pass,
    /// Per subscription (its index), how its messages decode.
    plans: Vec<Planned>,
    /// Per subscription, its messages that did not decode.
    undecoded: Vec<u64>,
}

enum Planned {
    /// Not met yet.
    Unknown,
    /// Not a topic the analysis reads, or its format does not fit.
    Skip,
    /// Decoded with this plan.
    Read(TopicPlan),
}

impl FlightAnalyzer {
    /// An analysis with nothing read yet.
    pub fn new(options: &AnalyzeOptions) -> FlightAnalyzer {
        FlightAnalyzer {
            pass: Pass::new(options),
            plans: Vec::new(),
            undecoded: Vec::new(),
        }
    }

    /// A data message of subscription `topic` (its payload after the msg_id), in file
    /// order.
    pub fn push(&mut self, topic: &Subscription, payload: &[u8]) {
        let i = topic.index();
        if self.plans.len() <= i {
            self.plans.resize_with(i + 1, || Planned::Unknown);
        }
        if matches!(self.plans[i], Planned::Unknown) {
            self.plans[i] = self.plan(topic);
        }
        let Planned::Read(plan) = &self.plans[i] else {
            return;
        };
        match FlightTopic::decode(plan, payload) {
            Ok(m) => self.pass.row(topic.name(), topic.multi_id(), &m),
            Err(e) => {
                // Said once per subscription; its other messages are still read.
                if self.undecoded.len() <= i {
                    self.undecoded.resize(i + 1, 0);
                }
                self.undecoded[i] += 1;
                if self.undecoded[i] == 1 {
                    self.pass.notes.push(format!(
                        "{} instance {}: messages that do not decode are left out ({e})",
                        topic.name(),
                        topic.multi_id()
                    ));
                }
            }
        }
    }

    fn plan(&mut self, topic: &Subscription) -> Planned {
        let Some(variant) = FlightTopic::variant_of(topic.name()) else {
            return Planned::Skip;
        };
        let layout = match topic.layout() {
            Ok(layout) => layout,
            Err(e) => {
                self.pass.notes.push(format!(
                    "{} instance {} is left out: {e}",
                    topic.name(),
                    topic.multi_id()
                ));
                return Planned::Skip;
            }
        };
        match FlightTopic::plan(variant, layout) {
            Some(Ok(plan)) => Planned::Read(plan),
            Some(Err(mismatch)) => {
                self.pass.notes.push(format!(
                    "{} instance {} is left out: {mismatch}",
                    topic.name(),
                    topic.multi_id()
                ));
                Planned::Skip
            }
            None => Planned::Skip,
        }
    }

    /// What the messages pushed showed ([`FlightAnalysis::findings`] is empty: the
    /// pass that fed this has them).
    pub fn finish(self) -> FlightAnalysis {
        self.pass.finish()
    }
}

/// The rules and figures being gathered.
struct Pass {
    options: AnalyzeOptions,
    now: Now,
    span: Option<(u64, u64)>,
    modes: modes::Modes,
    stats: stats::Stats,
    brownout: brownout::Brownout,
    ekf: ekf::Ekf,
    gps: gps::Gps,
    motors: motors::Motors,
    rc: rc_loss::RcLoss,
    gyro: spectra::Welch,
    accel: spectra::Welch,
    controls: spectra::Welch,
    torque: spectra::Welch,
    steps: steps::Steps,
    notes: Vec<String>,
}

impl Pass {
    fn new(options: &AnalyzeOptions) -> Pass {
        Pass {
            options: options.clone(),
            now: Now {
                time: 0,
                armed: false,
                nav_state: None,
                vehicle_type: None,
            },
            span: None,
            modes: modes::Modes::default(),
            stats: stats::Stats::default(),
            brownout: brownout::Brownout::default(),
            ekf: ekf::Ekf::default(),
            gps: gps::Gps::default(),
            motors: motors::Motors::default(),
            rc: rc_loss::RcLoss::default(),
            gyro: spectra::Welch::new("sensor_combined", "gyro_rad"),
            accel: spectra::Welch::new("sensor_combined", "accelerometer_m_s2"),
            controls: spectra::Welch::new("actuator_controls_0", "control"),
            torque: spectra::Welch::new("vehicle_torque_setpoint", "xyz"),
            steps: steps::Steps::default(),
            notes: Vec::new(),
        }
    }

    fn row(&mut self, topic: &str, instance: u8, m: &FlightTopic) {
        let time = m.timestamp();
        self.now.time = time;
        self.span = Some(match self.span {
            Some((a, b)) => (a.min(time), b.max(time)),
            None => (time, time),
        });
        let first = instance == 0;
        match m {
            FlightTopic::Status(s) if first => {
                self.modes.status(s, time);
                let armed = s.arming_state == 2;
                if self.now.armed && !armed {
                    self.steps.disarmed();
                    for w in [
                        &mut self.gyro,
                        &mut self.accel,
                        &mut self.controls,
                        &mut self.torque,
                    ] {
                        w.gap();
                    }
                }
                self.now.armed = armed;
                self.now.nav_state = Some(s.nav_state);
                self.now.vehicle_type = s.vehicle_type;
                self.rc.status(&self.now);
            }
            FlightTopic::Land(l) if first => self.modes.land(l, time),
            FlightTopic::Battery(b) => {
                if first {
                    self.stats.battery(b);
                }
                self.brownout.push(instance, b, &self.now);
            }
            FlightTopic::Estimator(e) => self.ekf.push(instance, e, &self.now),
            FlightTopic::Gps(g) => self.gps.push(topic, instance, g, &self.now),
            FlightTopic::Outputs(a) => self.motors.push(instance, a, &self.now),
            FlightTopic::Rc(r) => self.rc.push(instance, r.rc_lost, &self.now),
            FlightTopic::Position(p) if first => self.stats.position(p),
            FlightTopic::Attitude(a) if first => self.stats.attitude(a),
            FlightTopic::Rates(r) if first => {
                self.stats.rates(r);
                if self.now.armed && self.options.step_response {
                    self.steps.rates(time, r.xyz);
                }
            }
            FlightTopic::RatesSetpoint(s)
                if first && self.now.armed && self.options.step_response =>
            {
                self.steps.setpoint(time, [s.roll, s.pitch, s.yaw]);
            }
            FlightTopic::Imu(i) => self.stats.imu(i),
            FlightTopic::Sensors(s) if first && self.now.armed && self.options.spectra => {
                self.gyro.push(time, s.gyro_rad);
                self.accel.push(time, s.accelerometer_m_s2);
            }
            FlightTopic::Controls(c) if first && self.now.armed && self.options.spectra => {
                self.controls
                    .push(time, [c.control[0], c.control[1], c.control[2]]);
            }
            FlightTopic::Torque(t) if first && self.now.armed && self.options.spectra => {
                self.torque.push(time, t.xyz);
            }
            _ => {}
        }
    }

    fn finish(mut self) -> FlightAnalysis {
        let end = self.span.map_or(0, |(_, b)| b);
        let mut diagnostics = Vec::new();
        diagnostics.extend(self.brownout.finish());
        diagnostics.extend(self.ekf.finish());
        let (gps, gps_found) = self.gps.finish();
        diagnostics.extend(gps_found);
        diagnostics.extend(self.motors.finish());
        diagnostics.extend(self.rc.finish(end));
        diagnostics.sort_by_key(|d| (d.timestamp_us, d.id));
        let (stats, battery, vibration) = self.stats.finish();
        let mut spectra = Vec::new();
        let mut spectrograms = Vec::new();
        if self.options.spectra {
            for (i, w) in [self.gyro, self.accel, self.controls, self.torque]
                .into_iter()
                .enumerate()
            {
                let (axes, spectrogram) = w.finish();
                spectra.extend(axes);
                // The IMU's: Flight Review draws those two over time.
                if i < 2 {
                    spectrograms.extend(spectrogram);
                }
            }
        }
        let mut step_responses = Vec::new();
        if self.options.step_response {
            match self.steps.finish() {
                Ok(axes) => {
                    for axis in axes {
                        match axis {
                            Ok(step) => step_responses.push(step),
                            Err(why) => self.notes.push(format!("no step response of {why}")),
                        }
                    }
                    if let Some(slow) = step_responses
                        .first()
                        .filter(|s| s.rate_hz < MIN_STEP_RATE_HZ)
                    {
                        self.notes.push(format!(
                            "the step responses are from rates logged at {:.0} Hz: below \
                             {MIN_STEP_RATE_HZ:.0} Hz the response's first tens of \
                             milliseconds are not resolved (PX4's high-rate logging profile \
                             logs them faster)",
                            slow.rate_hz
                        ));
                    }
                }
                Err(why) => self.notes.push(format!(
                    "no step response (vehicle_rates_setpoint and vehicle_angular_velocity \
                     while armed): {why}"
                )),
            }
        }
        FlightAnalysis {
            diagnostics,
            timeline: self.modes.finish(end),
            stats,
            battery,
            gps,
            vibration,
            spectra,
            spectrograms,
            step_responses,
            span_us: self.span,
            notes: self.notes,
            findings: Vec::new(),
        }
    }
}
