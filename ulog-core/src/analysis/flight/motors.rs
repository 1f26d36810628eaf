//! `motor_failure`: while armed, an output that was driving a motor drops to 0
//! (a disconnected motor or a failed ESC, critical), or stays at or above 1900 µs
//! for 50 rows in a row (a motor that cannot follow, or a locked rotor, warning).
//!
//! Unlike Flight Review v2, each `actuator_outputs` instance is read on its own (its
//! rule mixes the rows of every instance, so an auxiliary output at 0 reads as a
//! main motor dropping to 0); the rule applies while the vehicle is a multicopter
//! (`vehicle_status.vehicle_type` 1, or not logged): a fixed-wing's outputs are
//! mostly servos, which sit at full deflection, and a VTOL's hover motors stop in
//! forward flight; and the lock at the maximum is checked only on outputs on a PWM
//! scale (an instance with a value above 2500, such as UAVCAN ESC commands up to
//! 8191, is not).

use super::diagnostic::{secs, Diagnostic, Evidence, Severity};
use super::modes::mode_name;
use super::topics::ActuatorOutputs;
use super::Now;

/// At or above this (µs of PWM) an output is at its maximum.
const MAX_PWM: f32 = 1900.0;
/// Above this an instance's outputs are not on a PWM scale.
const PWM_SCALE_END: f32 = 2500.0;
/// `vehicle_status.vehicle_type` of a multicopter.
const ROTARY_WING: u8 = 1;
/// This many rows in a row at the maximum are a lock.
const LOCKED_ROWS: u32 = 50;

#[derive(Clone, Copy, Default)]
struct Output {
    /// Non-zero since the vehicle armed.
    active: bool,
    dropped: bool,
    locked: bool,
    /// The run of rows at the maximum: its first row's time and length.
    at_max: Option<(u64, u32)>,
    /// The last row of the run reported as a lock, to extend its end.
    lock_report: Option<usize>,
}

/// One `actuator_outputs` instance.
struct Instance {
    instance: u8,
    outputs: [Output; 16],
    /// A value above [`PWM_SCALE_END`] was seen.
    not_pwm: bool,
}

/// The rule's state over a pass.
#[derive(Default)]
pub(super) struct Motors {
    instances: Vec<Instance>,
    was_armed: bool,
    found: Vec<Diagnostic>,
}

impl Motors {
    pub(super) fn push(&mut self, instance: u8, a: &ActuatorOutputs, now: &Now) {
        if now.armed != self.was_armed {
            // A new arming: which outputs drive motors is learnt again.
            for i in &mut self.instances {
                for o in &mut i.outputs {
                    o.active = false;
                    o.at_max = None;
                    o.lock_report = None;
                }
            }
            self.was_armed = now.armed;
        }
        if !now.armed || now.vehicle_type.is_some_and(|t| t != ROTARY_WING) {
            return;
        }
        let at = match self.instances.iter().position(|i| i.instance == instance) {
            Some(at) => at,
            None => {
                self.instances.push(Instance {
                    instance,
                    outputs: [Output::default(); 16],
                    not_pwm: false,
                });
                self.instances.len() - 1
            }
        };
        // `noutputs` is how many outputs the driver has; 0 in some firmware.
        let count = match a.noutputs {
            1..=16 => a.noutputs as usize,
            _ => 16,
        };
        // Named only when a rule fires: no allocation per row.
        let mode = || {
            now.nav_state
                .map_or_else(|| "unknown".to_owned(), mode_name)
        };
        let outputs = &a.output[..count];
        if outputs.iter().any(|v| *v > PWM_SCALE_END) {
            let i = &mut self.instances[at];
            i.not_pwm = true;
            i.outputs.iter_mut().for_each(|o| o.at_max = None);
        }
        let pwm = !self.instances[at].not_pwm;
        for (m, &value) in outputs.iter().enumerate() {
            let o = &mut self.instances[at].outputs[m];
            if !value.is_finite() {
                o.at_max = None;
                continue;
            }
            if value != 0.0 {
                o.active = true;
            } else if o.active && !o.dropped {
                o.dropped = true;
                let mode = mode();
                self.found.push(Diagnostic {
                    id: "motor_failure",
                    severity: Severity::Critical,
                    timestamp_us: now.time,
                    end_timestamp_us: None,
                    summary: format!(
                        "Motor {m} output dropped to 0 at {:.1}s while armed in {mode} mode \
                         (actuator_outputs {instance})",
                        secs(now.time)
                    ),
                    evidence: Evidence::MotorFailure {
                        motor_index: m as u8,
                        pwm_value: value,
                        failure_mode: "drop_to_zero",
                        flight_mode: mode.clone(),
                        instance,
                    },
                });
            }
            if value < MAX_PWM || !pwm {
                o.at_max = None;
                o.lock_report = None;
                continue;
            }
            let (since, rows) = o.at_max.get_or_insert((now.time, 0));
            *rows += 1;
            if let Some(report) = o.lock_report {
                self.found[report].end_timestamp_us = Some(now.time);
            } else if *rows >= LOCKED_ROWS && !o.locked {
                o.locked = true;
                o.lock_report = Some(self.found.len());
                let mode = mode();
                self.found.push(Diagnostic {
                    id: "motor_failure",
                    severity: Severity::Warning,
                    timestamp_us: *since,
                    end_timestamp_us: Some(now.time),
                    summary: format!(
                        "Motor {m} locked at max output from {:.1}s while armed in {mode} mode \
                         (actuator_outputs {instance})",
                        secs(*since)
                    ),
                    evidence: Evidence::MotorFailure {
                        motor_index: m as u8,
                        pwm_value: value,
                        failure_mode: "locked_at_max",
                        flight_mode: mode.clone(),
                        instance,
                    },
                });
            }
        }
    }

    pub(super) fn finish(self) -> Vec<Diagnostic> {
        self.found
    }
}
