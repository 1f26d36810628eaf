//! Flight modes, arming and takeoff/landing: the bands and marks behind every plot,
//! and the armed time, from `vehicle_status` and `vehicle_land_detected` as the second
//! pass ([`super::pass`]) hands their rows.

use serde::Serialize;
use ulog_core::read::TimeSpan;
use ulog_core::typed::Plan;
use ulog_core::ULog;

use super::flight::{typed, VehicleLandDetected, VehicleStatus};
use super::pass::{Routes, Rows};

/// The name of a PX4 flight mode (`vehicle_status.nav_state`).
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

/// A flight mode from one time to another (seconds since the log's start).
#[derive(Debug, Serialize)]
pub struct ModeBand {
    /// Start.
    pub t0: f64,
    /// End.
    pub t1: f64,
    /// `nav_state`.
    pub mode: u8,
    /// Its name.
    pub name: String,
}

/// A marked instant: arming, takeoff, a logged error.
#[derive(Debug, Serialize)]
pub struct Mark {
    /// Seconds since the log's start.
    pub t: f64,
    /// `arm`, `disarm`, `takeoff`, `landing`, `error`.
    pub kind: &'static str,
    /// What to show.
    pub text: String,
}

/// Flight modes, arming and takeoff/landing, and the armed time (seconds).
pub struct Timeline {
    /// The flight modes.
    pub modes: Vec<ModeBand>,
    /// Arming, disarming, takeoffs and landings.
    pub marks: Vec<Mark>,
    /// Time armed.
    pub armed_s: f64,
}

/// Flight modes and arming from `vehicle_status`, as its rows come.
struct Status {
    sub: usize,
    plan: Plan<VehicleStatus>,
    span: TimeSpan,
    modes: Vec<ModeBand>,
    marks: Vec<Mark>,
    armed_at: Option<f64>,
    armed_s: f64,
}

impl Rows for Status {
    fn push(&mut self, payload: &[u8]) {
        let Ok(s) = self.plan.decode(payload) else {
            return;
        };
        // Placed on the log's time axis as in the plots.
        let Some(at) = self.span.axis_time(s.timestamp) else {
            return;
        };
        let t = self.span.seconds(at);
        match self.modes.last_mut() {
            Some(m) if m.mode == s.nav_state => m.t1 = t,
            last => {
                if let Some(m) = last {
                    m.t1 = t;
                }
                self.modes.push(ModeBand {
                    t0: t,
                    t1: t,
                    mode: s.nav_state,
                    name: mode_name(s.nav_state),
                });
            }
        }
        let armed = s.arming_state == 2;
        match (armed, self.armed_at) {
            (true, None) => {
                self.armed_at = Some(t);
                self.marks.push(Mark {
                    t,
                    kind: "arm",
                    text: "armed".into(),
                });
            }
            (false, Some(at)) => {
                self.armed_s += t - at;
                self.armed_at = None;
                self.marks.push(Mark {
                    t,
                    kind: "disarm",
                    text: "disarmed".into(),
                });
            }
            _ => {}
        }
    }
}

/// Takeoffs and landings from `vehicle_land_detected`, as its rows come.
struct Landings {
    sub: usize,
    plan: Plan<VehicleLandDetected>,
    span: TimeSpan,
    landed: Option<bool>,
    marks: Vec<Mark>,
}

impl Rows for Landings {
    fn push(&mut self, payload: &[u8]) {
        let Ok(l) = self.plan.decode(payload) else {
            return;
        };
        let Some(at) = self.span.axis_time(l.timestamp) else {
            return;
        };
        if self.landed.is_some_and(|was| was != l.landed) {
            self.marks.push(Mark {
                t: self.span.seconds(at),
                kind: if l.landed { "landing" } else { "takeoff" },
                text: if l.landed { "landed" } else { "takeoff" }.into(),
            });
        }
        self.landed = Some(l.landed);
    }
}

/// The timeline being read.
pub struct TimelineRows {
    status: Option<Status>,
    landings: Option<Landings>,
}

/// The log's modes and marks, to be read from `vehicle_status` and
/// `vehicle_land_detected`; times in seconds since the start of `span`.
pub fn timeline(log: &ULog<'_>, span: &TimeSpan) -> TimelineRows {
    TimelineRows {
        status: typed::<VehicleStatus>(log).map(|(sub, plan)| Status {
            sub,
            plan,
            span: span.clone(),
            modes: Vec::new(),
            marks: Vec::new(),
            armed_at: None,
            armed_s: 0.0,
        }),
        landings: typed::<VehicleLandDetected>(log).map(|(sub, plan)| Landings {
            sub,
            plan,
            span: span.clone(),
            landed: None,
            marks: Vec::new(),
        }),
    }
}

impl TimelineRows {
    /// Has the second pass hand the rows of the topics here.
    pub fn route<'c>(&'c mut self, routes: &mut Routes<'c>) {
        if let Some(s) = &mut self.status {
            routes.add(s.sub, s);
        }
        if let Some(l) = &mut self.landings {
            routes.add(l.sub, l);
        }
    }

    /// The modes and marks, the last mode lasting to the span's end.
    pub fn finish(self) -> Timeline {
        let mut modes = Vec::new();
        let mut marks = Vec::new();
        let mut armed_s = 0.0;
        if let Some(mut s) = self.status {
            let end = s.span.seconds(s.span.end());
            armed_s = s.armed_s;
            if let Some(at) = s.armed_at {
                armed_s += end - at;
            }
            if let Some(m) = s.modes.last_mut() {
                m.t1 = m.t1.max(end);
            }
            modes = s.modes;
            marks = s.marks;
        }
        if let Some(l) = self.landings {
            marks.extend(l.marks);
        }
        Timeline {
            modes,
            marks,
            armed_s,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn modes_have_names() {
        assert_eq!(mode_name(2), "Position");
        assert_eq!(mode_name(99), "mode 99");
    }
}
