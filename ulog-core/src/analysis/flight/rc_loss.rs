//! `rc_loss`: the RC receiver reports its signal lost while armed, for 0.5 s or more
//! (critical from 5 s). A loss ends at the first row with the signal back (so its
//! duration is how long there was none), at disarming, or at the log's last row.

use super::diagnostic::{secs, Diagnostic, Evidence, Severity};
use super::Now;

/// Shorter losses are not reported.
const MIN_US: u64 = 500_000;
/// Losses this long are critical.
const CRITICAL_US: u64 = 5_000_000;

/// The rule's state over a pass (`input_rc` instance 0).
#[derive(Default)]
pub(super) struct RcLoss {
    lost_since: Option<u64>,
    last_signal: u64,
    was_armed: bool,
    found: Vec<Diagnostic>,
}

impl RcLoss {
    /// A row of `input_rc`.
    pub(super) fn push(&mut self, instance: u8, lost: bool, now: &Now) {
        if instance != 0 {
            return;
        }
        if !lost {
            // Closed before `last_signal` moves: the evidence is the last row before
            // the loss.
            if let Some(since) = self.lost_since.take() {
                self.close(since, now.time);
            }
            self.last_signal = now.time;
        } else if now.armed && self.lost_since.is_none() {
            self.lost_since = Some(now.time);
        }
    }

    /// The arming state changed (or not): a disarm ends a loss.
    pub(super) fn status(&mut self, now: &Now) {
        if self.was_armed && !now.armed {
            if let Some(since) = self.lost_since.take() {
                self.close(since, now.time);
            }
        }
        self.was_armed = now.armed;
    }

    /// A loss open at the end of the log lasts to its last row.
    pub(super) fn finish(mut self, end: u64) -> Vec<Diagnostic> {
        if let Some(since) = self.lost_since.take() {
            self.close(since, end);
        }
        self.found
    }

    fn close(&mut self, since: u64, end: u64) {
        let duration = end.saturating_sub(since);
        if duration < MIN_US {
            return;
        }
        self.found.push(Diagnostic {
            id: "rc_loss",
            severity: if duration >= CRITICAL_US {
                Severity::Critical
            } else {
                Severity::Warning
            },
            timestamp_us: since,
            end_timestamp_us: Some(end),
            summary: format!(
                "RC signal lost for {:.1}s starting at {:.1}s while armed",
                secs(duration),
                secs(since)
            ),
            evidence: Evidence::RcLoss {
                last_signal_timestamp_us: self.last_signal,
                signal_lost_duration_ms: duration / 1000,
            },
        });
    }
}
