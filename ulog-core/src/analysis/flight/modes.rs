//! What the vehicle was doing: flight modes, arming, takeoffs and landings.

use super::topics::{VehicleLandDetected, VehicleStatus};

/// The name of a PX4 flight mode (`vehicle_status.nav_state`).
///
/// ```
/// use ulog_core::analysis::mode_name;
/// assert_eq!(mode_name(2), "Position");
/// assert_eq!(mode_name(99), "mode 99");
/// ```
pub fn mode_name(nav_state: u8) -> String {
    let name = match nav_state {
        0 => "Manual",
        1 => "Altitude",
        2 => "Position",
        3 => "Mission",
        4 => "Hold",
        5 => "Return",
        6 => "Position slow",
        10 => "Acro",
        12 => "Descend",
        13 => "Termination",
        14 => "Offboard",
        15 => "Stabilized",
        17 => "Takeoff",
        18 => "Land",
        19 => "Follow target",
        20 => "Precision land",
        21 => "Orbit",
        22 => "VTOL takeoff",
        n => return format!("mode {n}"),
    };
    name.to_owned()
}

/// A flight mode from one time to another (µs on the log's clock).
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct ModeSegment {
    /// `nav_state`.
    pub mode: u8,
    /// Its name ([`mode_name`]).
    pub name: String,
    /// Start.
    pub start_us: u64,
    /// End: the next mode's start, or the log's last row.
    pub end_us: u64,
}

/// A moment the vehicle's state changed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EventKind {
    /// Armed.
    Arm,
    /// Disarmed.
    Disarm,
    /// Left the ground (`vehicle_land_detected.landed` became false).
    Takeoff,
    /// Landed.
    Landing,
}

impl EventKind {
    /// `arm`, `disarm`, `takeoff` or `landing`.
    pub fn as_str(self) -> &'static str {
        match self {
            EventKind::Arm => "arm",
            EventKind::Disarm => "disarm",
            EventKind::Takeoff => "takeoff",
            EventKind::Landing => "landing",
        }
    }
}

/// Flight modes, arming and takeoffs over a log: one source of what a flight was.
#[derive(Debug, Clone, Default, PartialEq)]
#[non_exhaustive]
pub struct Timeline {
    /// The flight modes, in time order.
    pub modes: Vec<ModeSegment>,
    /// Arming, disarming, takeoffs and landings, in time order (µs).
    pub events: Vec<(u64, EventKind)>,
    /// Time armed, s.
    pub armed_s: f64,
    /// Time in the air (from each takeoff to its landing or the log's end), s.
    pub airborne_s: f64,
}

impl Timeline {
    /// The first takeoff, µs.
    pub fn takeoff_us(&self) -> Option<u64> {
        self.events
            .iter()
            .find(|(_, k)| *k == EventKind::Takeoff)
            .map(|(t, _)| *t)
    }
}

/// The timeline as rows come.
#[derive(Default)]
pub(super) struct Modes {
    timeline: Timeline,
    armed_at: Option<u64>,
    landed: Option<bool>,
    airborne_at: Option<u64>,
}

impl Modes {
    /// A `vehicle_status` row (instance 0).
    pub(super) fn status(&mut self, s: &VehicleStatus, time: u64) {
        let modes = &mut self.timeline.modes;
        match modes.last_mut() {
            Some(m) if m.mode == s.nav_state => m.end_us = m.end_us.max(time),
            last => {
                if let Some(m) = last {
                    m.end_us = time;
                }
                modes.push(ModeSegment {
                    mode: s.nav_state,
                    name: mode_name(s.nav_state),
                    start_us: time,
                    end_us: time,
                });
            }
        }
        let armed = s.arming_state == 2;
        match (armed, self.armed_at) {
            (true, None) => {
                self.armed_at = Some(time);
                self.timeline.events.push((time, EventKind::Arm));
            }
            (false, Some(at)) => {
                self.timeline.armed_s += time.saturating_sub(at) as f64 * 1e-6;
                self.armed_at = None;
                self.timeline.events.push((time, EventKind::Disarm));
            }
            _ => {}
        }
    }

    /// A `vehicle_land_detected` row (instance 0).
    pub(super) fn land(&mut self, l: &VehicleLandDetected, time: u64) {
        if self.landed.is_some_and(|was| was != l.landed) {
            if l.landed {
                self.timeline.events.push((time, EventKind::Landing));
                if let Some(at) = self.airborne_at.take() {
                    self.timeline.airborne_s += time.saturating_sub(at) as f64 * 1e-6;
                }
            } else {
                self.timeline.events.push((time, EventKind::Takeoff));
                self.airborne_at = Some(time);
            }
        }
        self.landed = Some(l.landed);
    }

    /// The timeline, the last mode, arming and flight lasting to `end`.
    pub(super) fn finish(mut self, end: u64) -> Timeline {
        let t = &mut self.timeline;
        if let Some(at) = self.armed_at {
            t.armed_s += end.saturating_sub(at) as f64 * 1e-6;
        }
        if let Some(at) = self.airborne_at {
            t.airborne_s += end.saturating_sub(at) as f64 * 1e-6;
        }
        if let Some(m) = t.modes.last_mut() {
            m.end_us = m.end_us.max(end);
        }
        t.events.sort_by_key(|(time, _)| *time);
        self.timeline
    }
}
