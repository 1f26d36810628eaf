//! `ekf_failure`: an EKF innovation test ratio above 1 for 2 s (warning) or 5 s
//! (critical).

use super::diagnostic::{secs, Diagnostic, Evidence, Severity};
use super::topics::EstimatorStatus;
use super::Now;

/// Above this a measurement fails the EKF's innovation consistency test.
const THRESHOLD: f32 = 1.0;
/// Exceedance this long (µs) is a warning.
const WARNING_US: u64 = 2_000_000;
/// And this long critical.
const CRITICAL_US: u64 = 5_000_000;

/// The innovations checked, with the field of each.
const INNOVATIONS: [&str; 3] = ["velocity", "position", "height"];

#[derive(Clone, Copy)]
struct Exceedance {
    since: u64,
    last: u64,
    max_ratio: f32,
}

/// The rule's state: per `estimator_status` instance, per innovation.
#[derive(Default)]
pub(super) struct Ekf {
    open: Vec<(u8, [Option<Exceedance>; 3])>,
    found: Vec<Diagnostic>,
}

impl Ekf {
    pub(super) fn push(&mut self, instance: u8, s: &EstimatorStatus, now: &Now) {
        let at = match self.open.iter().position(|(i, _)| *i == instance) {
            Some(at) => at,
            None => {
                self.open.push((instance, [None; 3]));
                self.open.len() - 1
            }
        };
        let ratios = [s.vel_test_ratio, s.pos_test_ratio, s.hgt_test_ratio];
        for (k, ratio) in ratios.into_iter().enumerate() {
            // Not logged, or NaN (the EKF not fusing that measurement): no verdict.
            let Some(ratio) = ratio.filter(|r| r.is_finite()) else {
                continue;
            };
            let slot = &mut self.open[at].1[k];
            if ratio > THRESHOLD {
                let e = slot.get_or_insert(Exceedance {
                    since: now.time,
                    last: now.time,
                    max_ratio: ratio,
                });
                e.last = e.last.max(now.time);
                e.max_ratio = e.max_ratio.max(ratio);
            } else if let Some(e) = slot.take() {
                self.found.extend(diagnostic(instance, k, e));
            }
        }
    }

    pub(super) fn finish(mut self) -> Vec<Diagnostic> {
        for (instance, slots) in &mut self.open {
            for (k, slot) in slots.iter_mut().enumerate() {
                if let Some(e) = slot.take() {
                    self.found.extend(diagnostic(*instance, k, e));
                }
            }
        }
        self.found.sort_by_key(|d| d.timestamp_us);
        self.found
    }
}

fn diagnostic(instance: u8, k: usize, e: Exceedance) -> Option<Diagnostic> {
    let duration = e.last - e.since;
    let severity = if duration >= CRITICAL_US {
        Severity::Critical
    } else if duration >= WARNING_US {
        Severity::Warning
    } else {
        return None;
    };
    let innovation = INNOVATIONS[k];
    Some(Diagnostic {
        id: "ekf_failure",
        severity,
        timestamp_us: e.since,
        end_timestamp_us: Some(e.last),
        summary: format!(
            "EKF {innovation} innovation exceeded threshold for {:.1}s starting at {:.1}s \
             (test ratio up to {:.2}, estimator {instance})",
            secs(duration),
            secs(e.since),
            e.max_ratio
        ),
        evidence: Evidence::EkfFailure {
            innovation,
            test_ratio: e.max_ratio,
            threshold: THRESHOLD,
            instance,
        },
    })
}
