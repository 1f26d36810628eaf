//! What a rule finds: a [`Diagnostic`], with its [`Severity`] and [`Evidence`].

use std::fmt;

/// How bad a diagnostic is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Severity {
    /// Notable, not a problem.
    Info,
    /// Worth a look.
    Warning,
    /// Likely a failure or a dangerous condition.
    Critical,
}

impl Severity {
    /// `info`, `warning` or `critical` (the names Flight Review v2 writes).
    pub fn as_str(self) -> &'static str {
        match self {
            Severity::Info => "info",
            Severity::Warning => "warning",
            Severity::Critical => "critical",
        }
    }
}

impl fmt::Display for Severity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// One anomaly a rule found in a log.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct Diagnostic {
    /// The rule's id: `battery_brownout`, `ekf_failure`, `gps_interference`,
    /// `motor_failure` or `rc_loss` (Flight Review v2's ids).
    pub id: &'static str,
    /// How bad it is.
    pub severity: Severity,
    /// When it started, µs on the log's clock.
    pub timestamp_us: u64,
    /// When it ended: the last row that showed it (for `rc_loss`, the first row with
    /// the signal back); `None` for an instant.
    pub end_timestamp_us: Option<u64>,
    /// One line for a person.
    pub summary: String,
    /// The figures behind it.
    pub evidence: Evidence,
}

/// The figures behind a [`Diagnostic`], one variant per rule.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum Evidence {
    /// `battery_brownout`.
    BatteryBrownout {
        /// The lowest voltage while below the threshold, V.
        voltage_v: f32,
        /// The threshold: 3.3 V per cell.
        critical_threshold_v: f32,
        /// The cell count the threshold is made of.
        cell_count: u8,
        /// Whether the count was logged (`battery_status.cell_count`) or estimated
        /// from the first voltage (4.2 V per cell, as Flight Review v2 does).
        cell_count_logged: bool,
        /// The current at the lowest voltage, A, when logged.
        current_a: Option<f32>,
        /// The `battery_status` instance.
        instance: u8,
    },
    /// `ekf_failure`.
    EkfFailure {
        /// `velocity`, `position` or `height`.
        innovation: &'static str,
        /// The highest test ratio in the episode.
        test_ratio: f32,
        /// The ratio above which the innovation fails its test (1.0).
        threshold: f32,
        /// The `estimator_status` instance (one per EKF instance since 2020).
        instance: u8,
    },
    /// `gps_interference`.
    GpsInterference {
        /// The worst horizontal position error in the episode, m.
        eph_m: f32,
        /// The worst vertical position error, m.
        epv_m: f32,
        /// The fewest satellites used.
        num_satellites: u16,
        /// The receiver's noise level (`noise_per_ms`) at the worst row, when logged.
        noise_level: Option<f32>,
        /// The receiver's jamming indicator at the worst row, when logged.
        jamming_indicator: Option<i32>,
        /// The baseline the episode is measured against: mean EPH, m.
        baseline_eph_m: f32,
        /// And mean satellites used.
        baseline_satellites: f32,
    },
    /// `motor_failure`.
    MotorFailure {
        /// The output's index in `actuator_outputs.output`.
        motor_index: u8,
        /// Its value when the rule fired.
        pwm_value: f32,
        /// `drop_to_zero` or `locked_at_max`.
        failure_mode: &'static str,
        /// The flight mode then ([`mode_name`](super::mode_name)).
        flight_mode: String,
        /// The `actuator_outputs` instance.
        instance: u8,
    },
    /// `rc_loss`.
    RcLoss {
        /// The last row with a signal before the loss, µs.
        last_signal_timestamp_us: u64,
        /// How long the signal was lost, ms.
        signal_lost_duration_ms: u64,
    },
}

/// One figure of [`Evidence`], for writers that do not know the variants.
#[derive(Debug, Clone, PartialEq)]
pub enum EvidenceValue {
    /// A measured value.
    Float(f64),
    /// A count, index or time.
    Int(i64),
    /// A name.
    Text(String),
    /// A yes/no.
    Bool(bool),
    /// Not logged.
    Missing,
}

impl Evidence {
    /// The variant's name (`BatteryBrownout`, …): the `type` Flight Review v2 writes.
    pub fn kind(&self) -> &'static str {
        match self {
            Evidence::BatteryBrownout { .. } => "BatteryBrownout",
            Evidence::EkfFailure { .. } => "EkfFailure",
            Evidence::GpsInterference { .. } => "GpsInterference",
            Evidence::MotorFailure { .. } => "MotorFailure",
            Evidence::RcLoss { .. } => "RcLoss",
        }
    }

    /// Its figures as a JSON object with its [`kind`](Self::kind) as `type` (Flight
    /// Review v2's form): floats that are not finite, and figures not logged, as `null`.
    ///
    /// ```
    /// use ulog_core::analysis::Evidence;
    /// let e = Evidence::RcLoss { last_signal_timestamp_us: 61_100_000, signal_lost_duration_ms: 2000 };
    /// assert_eq!(
    ///     e.json(),
    ///     r#"{"type":"RcLoss","last_signal_timestamp_us":61100000,"signal_lost_duration_ms":2000}"#
    /// );
    /// ```
    pub fn json(&self) -> String {
        let mut out = String::from("{\"type\":");
        crate::json_text::push_string(&mut out, self.kind().chars());
        for (k, v) in self.fields() {
            out.push(',');
            crate::json_text::push_string(&mut out, k.chars());
            out.push(':');
            match v {
                EvidenceValue::Float(f) if f.is_finite() => out.push_str(&f.to_string()),
                EvidenceValue::Int(i) => out.push_str(&i.to_string()),
                EvidenceValue::Text(t) => crate::json_text::push_string(&mut out, t.chars()),
                EvidenceValue::Bool(b) => out.push_str(if b { "true" } else { "false" }),
                EvidenceValue::Float(_) | EvidenceValue::Missing => out.push_str("null"),
            }
        }
        out.push('}');
        out
    }

    /// Its figures by name, in declaration order (for JSON, tables, Python).
    pub fn fields(&self) -> Vec<(&'static str, EvidenceValue)> {
        use EvidenceValue::{Bool, Float, Int, Missing, Text};
        let f = |v: f32| Float(f64::from(v));
        let opt = |v: Option<f32>| v.map_or(Missing, f);
        match self {
            Evidence::BatteryBrownout {
                voltage_v,
                critical_threshold_v,
                cell_count,
                cell_count_logged,
                current_a,
                instance,
            } => vec![
                ("voltage_v", f(*voltage_v)),
                ("critical_threshold_v", f(*critical_threshold_v)),
                ("cell_count", Int(i64::from(*cell_count))),
                ("cell_count_logged", Bool(*cell_count_logged)),
                ("current_a", opt(*current_a)),
                ("instance", Int(i64::from(*instance))),
            ],
            Evidence::EkfFailure {
                innovation,
                test_ratio,
                threshold,
                instance,
            } => vec![
                ("innovation", Text((*innovation).to_owned())),
                ("test_ratio", f(*test_ratio)),
                ("threshold", f(*threshold)),
                ("instance", Int(i64::from(*instance))),
            ],
            Evidence::GpsInterference {
                eph_m,
                epv_m,
                num_satellites,
                noise_level,
                jamming_indicator,
                baseline_eph_m,
                baseline_satellites,
            } => vec![
                ("eph_m", f(*eph_m)),
                ("epv_m", f(*epv_m)),
                ("num_satellites", Int(i64::from(*num_satellites))),
                ("noise_level", opt(*noise_level)),
                (
                    "jamming_indicator",
                    jamming_indicator.map_or(Missing, |j| Int(i64::from(j))),
                ),
                ("baseline_eph_m", f(*baseline_eph_m)),
                ("baseline_satellites", f(*baseline_satellites)),
            ],
            Evidence::MotorFailure {
                motor_index,
                pwm_value,
                failure_mode,
                flight_mode,
                instance,
            } => vec![
                ("motor_index", Int(i64::from(*motor_index))),
                ("pwm_value", f(*pwm_value)),
                ("failure_mode", Text((*failure_mode).to_owned())),
                ("flight_mode", Text(flight_mode.clone())),
                ("instance", Int(i64::from(*instance))),
            ],
            Evidence::RcLoss {
                last_signal_timestamp_us,
                signal_lost_duration_ms,
            } => vec![
                (
                    "last_signal_timestamp_us",
                    Int(i64::try_from(*last_signal_timestamp_us).unwrap_or(i64::MAX)),
                ),
                (
                    "signal_lost_duration_ms",
                    Int(i64::try_from(*signal_lost_duration_ms).unwrap_or(i64::MAX)),
                ),
            ],
        }
    }
}

/// Seconds on the log's clock, for summaries.
pub(super) fn secs(us: u64) -> f64 {
    us as f64 * 1e-6
}
