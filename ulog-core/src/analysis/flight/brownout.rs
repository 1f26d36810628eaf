//! `battery_brownout`: the battery's voltage below 3.3 V per cell while armed.

use super::diagnostic::{secs, Diagnostic, Evidence, Severity};
use super::topics::BatteryStatus;
use super::Now;

/// The voltage per cell below which a LiPo/Li-ion cell is damaged or browns out the
/// vehicle (Flight Review v2's threshold).
const CRITICAL_PER_CELL: f32 = 3.3;
/// A full cell: the divisor that estimates the cell count from the first voltage
/// where the log has no `cell_count`.
const FULL_PER_CELL: f32 = 4.2;
/// Rows below the threshold this close (µs) belong to one episode (Flight Review v2
/// reports one every 30 s).
const MERGE_US: u64 = 30_000_000;

struct Episode {
    start: u64,
    last: u64,
    min_v: f32,
    current_at_min: Option<f32>,
}

/// One `battery_status` instance.
struct Battery {
    instance: u8,
    cells: Option<(u8, bool)>,
    episode: Option<Episode>,
}

/// The rule's state over a pass.
#[derive(Default)]
pub(super) struct Brownout {
    batteries: Vec<Battery>,
    found: Vec<Diagnostic>,
}

impl Brownout {
    pub(super) fn push(&mut self, instance: u8, b: &BatteryStatus, now: &Now) {
        let voltage = [Some(b.voltage_v), b.voltage_filtered_v]
            .into_iter()
            .flatten()
            .find(|v| v.is_finite() && *v > 0.0);
        let Some(voltage) = voltage else { return };
        let at = match self.batteries.iter().position(|x| x.instance == instance) {
            Some(i) => i,
            None => {
                self.batteries.push(Battery {
                    instance,
                    cells: None,
                    episode: None,
                });
                self.batteries.len() - 1
            }
        };
        let battery = &mut self.batteries[at];
        let (cells, _) = *battery.cells.get_or_insert_with(|| {
            match b
                .cell_count
                .and_then(|c| u8::try_from(c).ok())
                .filter(|c| (1..=24).contains(c))
            {
                Some(c) => (c, true),
                None => (
                    ((voltage / FULL_PER_CELL).round() as u8).clamp(1, 12),
                    false,
                ),
            }
        });
        let threshold = f32::from(cells) * CRITICAL_PER_CELL;
        if !now.armed || voltage >= threshold {
            return;
        }
        let current = Some(b.current_a).filter(|c| c.is_finite() && *c >= 0.0);
        if let Some(e) = &mut battery.episode {
            if now.time.saturating_sub(e.last) <= MERGE_US {
                e.last = e.last.max(now.time);
                if voltage < e.min_v {
                    e.min_v = voltage;
                    e.current_at_min = current;
                }
                return;
            }
        }
        if let Some(done) = battery.episode.take() {
            self.found.push(diagnostic(battery, done));
        }
        battery.episode = Some(Episode {
            start: now.time,
            last: now.time,
            min_v: voltage,
            current_at_min: current,
        });
    }

    pub(super) fn finish(mut self) -> Vec<Diagnostic> {
        for battery in &mut self.batteries {
            if let Some(done) = battery.episode.take() {
                self.found.push(diagnostic(battery, done));
            }
        }
        self.found
    }
}

fn diagnostic(battery: &Battery, e: Episode) -> Diagnostic {
    let (cells, logged) = battery.cells.unwrap_or((1, false));
    let threshold = f32::from(cells) * CRITICAL_PER_CELL;
    Diagnostic {
        id: "battery_brownout",
        severity: Severity::Critical,
        timestamp_us: e.start,
        end_timestamp_us: (e.last > e.start).then_some(e.last),
        summary: format!(
            "Battery voltage down to {:.2}V, below the critical threshold {:.1}V ({cells}S), \
             from {:.1}s to {:.1}s while armed",
            e.min_v,
            threshold,
            secs(e.start),
            secs(e.last)
        ),
        evidence: Evidence::BatteryBrownout {
            voltage_v: e.min_v,
            critical_threshold_v: threshold,
            cell_count: cells,
            cell_count_logged: logged,
            current_a: e.current_at_min,
            instance: battery.instance,
        },
    }
}
