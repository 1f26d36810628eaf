//! `gps_interference` (a sudden loss of GPS quality: EPH or EPV spikes, satellites
//! lost) and the GPS quality figures, from the receiver's fix.

use super::diagnostic::{secs, Diagnostic, Evidence, Severity};
use super::topics::GpsPosition;
use super::Now;

/// Rows with a 3D fix that make the baseline.
const BASELINE_ROWS: u32 = 10;
/// An EPH above this (m) is a spike, when the baseline is below 2 m.
const EPH_SPIKE_M: f32 = 5.0;
/// An EPH above this makes an episode critical.
const EPH_CRITICAL_M: f32 = 10.0;
/// An EPV above this (m) is a spike.
const EPV_SPIKE_M: f32 = 10.0;
/// Fewer satellites than this makes an episode critical.
const SATELLITES_CRITICAL: u8 = 4;
/// Fewer than this fraction of the baseline's satellites is a drop.
const SATELLITE_DROP: f32 = 0.5;
/// Degraded rows this close (µs) belong to one episode.
const MERGE_US: u64 = 5_000_000;

/// The GPS quality over the log (the fix topic's instance 0).
#[derive(Debug, Clone, Default, PartialEq)]
#[non_exhaustive]
pub struct GpsQuality {
    /// The topic read: `vehicle_gps_position`, or `sensor_gps` where the log has no
    /// `vehicle_gps_position`.
    pub topic: String,
    /// Fewest satellites used.
    pub min_satellites: Option<u8>,
    /// Most satellites used.
    pub max_satellites: Option<u8>,
    /// Worst horizontal dilution of precision.
    pub max_hdop: Option<f32>,
    /// Worst horizontal position error, m.
    pub max_eph_m: Option<f32>,
    /// Worst vertical position error, m.
    pub max_epv_m: Option<f32>,
    /// The fix types seen (0–1 none, 2 2D, 3 3D, 4 DGPS, 5 RTK float, 6 RTK fixed).
    pub fix_types_seen: Vec<u8>,
    /// Rows read.
    pub rows: u64,
}

struct Episode {
    start: u64,
    last: u64,
    worst_eph: f32,
    worst_epv: f32,
    min_sats: u8,
    critical: bool,
    noise: Option<f32>,
    jamming: Option<i32>,
}

/// One fix topic's state.
#[derive(Default)]
struct Source {
    quality: GpsQuality,
    baseline_rows: u32,
    eph_sum: f64,
    sats_sum: f64,
    baseline: Option<(f32, f32)>,
    episode: Option<Episode>,
    found: Vec<Diagnostic>,
}

/// The rule and the figures, for each of the two fix topics.
#[derive(Default)]
pub(super) struct Gps {
    sources: [Source; 2],
}

impl Gps {
    pub(super) fn push(&mut self, topic: &str, instance: u8, g: &GpsPosition, now: &Now) {
        if instance != 0 {
            return;
        }
        let k = usize::from(topic != "vehicle_gps_position");
        let source = &mut self.sources[k];
        if source.quality.rows == 0 {
            source.quality.topic = topic.to_owned();
        }
        source.quality(g);
        source.detect(g, now.time);
    }

    /// The quality figures and the diagnostics of `vehicle_gps_position`, or of
    /// `sensor_gps` where the log has no rows of it.
    pub(super) fn finish(self) -> (Option<GpsQuality>, Vec<Diagnostic>) {
        let [primary, fallback] = self.sources;
        let mut chosen = if primary.quality.rows > 0 {
            primary
        } else {
            fallback
        };
        if chosen.quality.rows == 0 {
            return (None, Vec::new());
        }
        if let Some(e) = chosen.episode.take() {
            let d = chosen.diagnostic(e);
            chosen.found.push(d);
        }
        chosen.quality.fix_types_seen.sort_unstable();
        (Some(chosen.quality), chosen.found)
    }
}

fn max_of(slot: &mut Option<f32>, v: f32) {
    if v.is_finite() && v > 0.0 && slot.map_or(true, |m| v > m) {
        *slot = Some(v);
    }
}

impl Source {
    fn quality(&mut self, g: &GpsPosition) {
        let q = &mut self.quality;
        q.rows += 1;
        q.min_satellites = Some(
            q.min_satellites
                .map_or(g.satellites_used, |m| m.min(g.satellites_used)),
        );
        q.max_satellites = Some(
            q.max_satellites
                .map_or(g.satellites_used, |m| m.max(g.satellites_used)),
        );
        if let Some(h) = g.hdop {
            max_of(&mut q.max_hdop, h);
        }
        max_of(&mut q.max_eph_m, g.eph);
        max_of(&mut q.max_epv_m, g.epv);
        if !q.fix_types_seen.contains(&g.fix_type) {
            q.fix_types_seen.push(g.fix_type);
        }
    }

    fn detect(&mut self, g: &GpsPosition, time: u64) {
        let Some((base_eph, base_sats)) = self.baseline else {
            // The baseline is the receiver once it has a 3D fix: before that, EPH is
            // large and no satellites are used, which is not interference.
            if g.fix_type >= 3 && g.eph.is_finite() {
                self.baseline_rows += 1;
                self.eph_sum += f64::from(g.eph);
                self.sats_sum += f64::from(g.satellites_used);
                if self.baseline_rows == BASELINE_ROWS {
                    let n = f64::from(BASELINE_ROWS);
                    self.baseline = Some(((self.eph_sum / n) as f32, (self.sats_sum / n) as f32));
                }
            }
            return;
        };
        let eph_spike = base_eph < 2.0 && g.eph.is_finite() && g.eph > EPH_SPIKE_M;
        let epv_spike = g.epv.is_finite() && g.epv > EPV_SPIKE_M;
        let sats_drop =
            base_sats > 0.0 && f32::from(g.satellites_used) < base_sats * (1.0 - SATELLITE_DROP);
        if !(eph_spike || epv_spike || sats_drop) {
            return;
        }
        let critical = (g.eph.is_finite() && g.eph > EPH_CRITICAL_M)
            || g.satellites_used < SATELLITES_CRITICAL;
        let finite = |v: f32| if v.is_finite() { v } else { 0.0 };
        if let Some(e) = &mut self.episode {
            if time.saturating_sub(e.last) <= MERGE_US {
                e.last = e.last.max(time);
                if finite(g.eph) > e.worst_eph {
                    e.worst_eph = finite(g.eph);
                    e.noise = g.noise_per_ms.map(|n| n as f32);
                    e.jamming = g.jamming_indicator;
                }
                e.worst_epv = e.worst_epv.max(finite(g.epv));
                e.min_sats = e.min_sats.min(g.satellites_used);
                e.critical |= critical;
                return;
            }
        }
        if let Some(done) = self.episode.take() {
            let d = self.diagnostic(done);
            self.found.push(d);
        }
        self.episode = Some(Episode {
            start: time,
            last: time,
            worst_eph: finite(g.eph),
            worst_epv: finite(g.epv),
            min_sats: g.satellites_used,
            critical,
            noise: g.noise_per_ms.map(|n| n as f32),
            jamming: g.jamming_indicator,
        });
    }

    fn diagnostic(&self, e: Episode) -> Diagnostic {
        let (base_eph, base_sats) = self.baseline.unwrap_or((0.0, 0.0));
        Diagnostic {
            id: "gps_interference",
            severity: if e.critical {
                Severity::Critical
            } else {
                Severity::Warning
            },
            timestamp_us: e.start,
            end_timestamp_us: (e.last > e.start).then_some(e.last),
            summary: format!(
                "GPS quality degraded from {:.1}s to {:.1}s: EPH up to {:.1}m (baseline {:.1}m), \
                 EPV up to {:.1}m, satellites down to {} (baseline {:.0})",
                secs(e.start),
                secs(e.last),
                e.worst_eph,
                base_eph,
                e.worst_epv,
                e.min_sats,
                base_sats
            ),
            evidence: Evidence::GpsInterference {
                eph_m: e.worst_eph,
                epv_m: e.worst_epv,
                num_satellites: u16::from(e.min_sats),
                noise_level: e.noise,
                jamming_indicator: e.jamming,
                baseline_eph_m: base_eph,
                baseline_satellites: base_sats,
            },
        }
    }
}
